/* Decompositions of libsinter_mpi (src/mpi/, issue 44), tested without MPI: the brick's grid and
 * tiling, recursive coordinate bisection balancing points and weights, the imbalance metric and
 * rebalancing above a threshold. A pour's particles in the bottom third of the box: a brick of
 * z slabs leaves every particle to the lowest slab (imbalance exactly 2 on two parts, at least 2
 * on three and four), bisection balances them to 1.1 or better. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#include "sinter_mpi_decomp.h"

static double uniform(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) * 0x1p-53;
}

/* n points uniform in [lo, hi). */
static double *points(size_t n, const double lo[3], const double hi[3], uint64_t seed)
{
    double *x = malloc(3 * n * sizeof *x);
    assert_non_null(x);
    for (size_t i = 0; i < 3 * n; ++i)
        x[i] = lo[i % 3] + (hi[i % 3] - lo[i % 3]) * uniform(&seed);
    return x;
}

static const double box_lo[3] = {0.0, 0.0, 0.0};
static const double box_hi[3] = {1.0, 1.0, 1.0};
static const double third_hi[3] = {1.0, 1.0, 1.0 / 3.0}; /* the pour: the bottom third */

static double imbalance_of(const sinter_mpi_decomp *d, const double *x, const double *w, size_t n)
{
    int parts = 0;
    assert_int_equal(sinter_mpi_decomp_info(d, NULL, &parts), SINTER_OK);
    double loads[64], imb = 0.0;
    assert_true(parts <= 64);
    assert_int_equal(sinter_mpi_decomp_loads(d, x, w, n, NULL, NULL, loads), SINTER_OK);
    assert_int_equal(sinter_mpi_imbalance(loads, parts, &imb), SINTER_OK);
    return imb;
}

/* Every point lies in its owner's box, and the boxes' volumes add up to the whole box's. */
static void assert_tiles(const sinter_mpi_decomp *d, const double *x, size_t n)
{
    int parts = 0;
    assert_int_equal(sinter_mpi_decomp_info(d, NULL, &parts), SINTER_OK);
    double volume = 0.0;
    for (int p = 0; p < parts; ++p) {
        double lo[3], hi[3];
        assert_int_equal(sinter_mpi_decomp_box(d, p, lo, hi), SINTER_OK);
        volume += (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    }
    assert_close(volume, 1.0, 1e-12); /* the unit box; rounding of the cut coordinates only */
    int *owner = malloc(n * sizeof *owner);
    assert_non_null(owner);
    assert_int_equal(sinter_mpi_decomp_owners(d, x, n, owner), SINTER_OK);
    for (size_t i = 0; i < n; ++i) {
        double lo[3], hi[3];
        assert_int_equal(sinter_mpi_decomp_box(d, owner[i], lo, hi), SINTER_OK);
        for (int a = 0; a < 3; ++a)
            assert_true(lo[a] <= x[3 * i + a] && x[3 * i + a] < hi[a]);
    }
    free(owner);
}

static void brick_grid_is_the_least_cut_area(void **state)
{
    (void)state;
    sinter_mpi_decomp *d = NULL;
    int grid[3];
    /* a cube: ties go to the earlier axis, as MPI_Dims_create's order */
    assert_int_equal(sinter_mpi_decomp_brick(&d, 2, NULL, box_lo, box_hi), SINTER_OK);
    assert_int_equal(sinter_mpi_decomp_grid(d, grid), SINTER_OK);
    assert_true(grid[0] == 2 && grid[1] == 1 && grid[2] == 1);
    sinter_mpi_decomp_destroy(d);
    assert_int_equal(sinter_mpi_decomp_brick(&d, 12, NULL, box_lo, box_hi), SINTER_OK);
    assert_int_equal(sinter_mpi_decomp_grid(d, grid), SINTER_OK);
    assert_true(grid[0] == 3 && grid[1] == 2 && grid[2] == 2); /* area 2 + 1 + 1 */
    sinter_mpi_decomp_destroy(d);
    /* a column three times taller than wide: two parts cut across z (area 1 against 3) */
    const double tall[3] = {1.0, 1.0, 3.0};
    assert_int_equal(sinter_mpi_decomp_brick(&d, 2, NULL, box_lo, tall), SINTER_OK);
    assert_int_equal(sinter_mpi_decomp_grid(d, grid), SINTER_OK);
    assert_true(grid[0] == 1 && grid[1] == 1 && grid[2] == 2);
    sinter_mpi_decomp_destroy(d);
    /* an axis given is kept; a grid that does not multiply to the parts is refused */
    const int given[3] = {0, 0, 3};
    assert_int_equal(sinter_mpi_decomp_brick(&d, 6, given, box_lo, box_hi), SINTER_OK);
    assert_int_equal(sinter_mpi_decomp_grid(d, grid), SINTER_OK);
    assert_true(grid[0] == 2 && grid[1] == 1 && grid[2] == 3);
    sinter_mpi_decomp_destroy(d);
    const int wrong[3] = {2, 2, 2};
    assert_int_equal(sinter_mpi_decomp_brick(&d, 6, wrong, box_lo, box_hi), SINTER_ERR_INVALID);
    assert_null(d);
}

static void brick_tiles_the_box_in_cartesian_order(void **state)
{
    (void)state;
    const size_t n = 2000;
    double *x = points(n, box_lo, box_hi, 7);
    sinter_mpi_decomp *d = NULL;
    const int grid[3] = {2, 3, 2};
    assert_int_equal(sinter_mpi_decomp_brick(&d, 12, grid, box_lo, box_hi), SINTER_OK);
    assert_tiles(d, x, n);
    /* MPI_Cart_create's numbering: (i0 g1 + i1) g2 + i2 */
    const double p[3] = {0.75, 0.5, 0.25}; /* i = (1, 1, 0) */
    int owner = -1;
    assert_int_equal(sinter_mpi_decomp_owners(d, p, 1, &owner), SINTER_OK);
    assert_int_equal(owner, (1 * 3 + 1) * 2 + 0);
    /* outside the box: the nearest part */
    const double out[3] = {-5.0, 9.0, 0.9};
    assert_int_equal(sinter_mpi_decomp_owners(d, out, 1, &owner), SINTER_OK);
    assert_int_equal(owner, (0 * 3 + 2) * 2 + 1);
    sinter_mpi_decomp_destroy(d);
    free(x);
}

/* The pour: every particle in the bottom third. */
static void bottom_third_brick_against_rcb(void **state)
{
    (void)state;
    const size_t n = 6000;
    double *x = points(n, box_lo, third_hi, 11);
    for (int parts = 2; parts <= 4; ++parts) {
        sinter_mpi_decomp *brick = NULL, *rcb = NULL;
        const int slabs[3] = {1, 1, parts};
        assert_int_equal(sinter_mpi_decomp_brick(&brick, parts, slabs, box_lo, box_hi), SINTER_OK);
        const double b = imbalance_of(brick, x, NULL, n);
        if (parts == 2)
            assert_close(b, 2.0, 0.0); /* every particle below z = 1/2: exactly 2 */
        else
            assert_true(b >= 2.0); /* 3 (all in [0, 1/3)) and 3 (3/4 of them in [0, 1/4)) */
        assert_int_equal(sinter_mpi_decomp_rcb(&rcb, parts, box_lo, box_hi, x, NULL, n, NULL, NULL),
                         SINTER_OK);
        const double r = imbalance_of(rcb, x, NULL, n);
        print_message("bottom third, %d parts: brick %.4f, RCB %.4f\n", parts, b, r);
        /* one particle is 1/1500 of a part's share at 4 parts; the cut search stops at 1e-4 */
        assert_true(r <= 1.1);
        assert_true(r <= 1.0 + 2.0 * parts / (double)n);
        assert_tiles(rcb, x, n);
        sinter_mpi_decomp_destroy(brick);
        sinter_mpi_decomp_destroy(rcb);
    }
    /* parts that are not powers of two, and more of them */
    for (int parts = 5; parts <= 8; ++parts) {
        sinter_mpi_decomp *rcb = NULL;
        assert_int_equal(sinter_mpi_decomp_rcb(&rcb, parts, box_lo, box_hi, x, NULL, n, NULL, NULL),
                         SINTER_OK);
        assert_true(imbalance_of(rcb, x, NULL, n) <= 1.0 + 2.0 * parts / (double)n);
        assert_tiles(rcb, x, n);
        sinter_mpi_decomp_destroy(rcb);
    }
    free(x);
}

/* Weights: points uniform in [0, 2] x [0, 1]^2 weighing 3 below x = 1 and 1 above: half the
 * weight lies below x = 2/3, where two parts must be cut (a third of the points). */
static void rcb_balances_weights_not_counts(void **state)
{
    (void)state;
    const size_t n = 40000;
    const double hi[3] = {2.0, 1.0, 1.0};
    double *x = points(n, box_lo, hi, 5);
    double *w = malloc(n * sizeof *w);
    assert_non_null(w);
    for (size_t i = 0; i < n; ++i)
        w[i] = x[3 * i] < 1.0 ? 3.0 : 1.0;
    sinter_mpi_decomp *d = NULL;
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 2, box_lo, hi, x, w, n, NULL, NULL), SINTER_OK);
    double lo0[3], hi0[3];
    assert_int_equal(sinter_mpi_decomp_box(d, 0, lo0, hi0), SINTER_OK);
    /* the cut normal to x at 2/3: sampling error of the weight below it about 3/sqrt(n) */
    assert_close(hi0[0], 2.0 / 3.0, 0.02);
    assert_close(hi0[1], 1.0, 0.0);
    /* the search stops within 1e-4 of the weight: 2e-4 on the imbalance of two parts */
    assert_true(imbalance_of(d, x, w, n) <= 1.0 + 2.5e-4);
    /* by count the parts hold about 1/3 and 2/3 of the points: 4/3 */
    assert_close(imbalance_of(d, x, NULL, n), 4.0 / 3.0, 0.03);
    sinter_mpi_decomp_destroy(d);
    free(w);
    free(x);
}

/* The cuts depend on the set of points and weights only: the same bits for the points in
 * another order (their weights summed exactly, in integer limbs). */
static void rcb_cuts_are_deterministic(void **state)
{
    (void)state;
    const size_t n = 5000;
    double *x = points(n, box_lo, third_hi, 3);
    double *w = malloc(n * sizeof *w);
    double *xr = malloc(3 * n * sizeof *xr);
    double *wr = malloc(n * sizeof *wr);
    assert_true(w != NULL && xr != NULL && wr != NULL);
    uint64_t seed = 99;
    for (size_t i = 0; i < n; ++i)
        w[i] = 0.1 + uniform(&seed) * 1e3; /* sums of these round differently in each order */
    for (size_t i = 0; i < n; ++i) {
        memcpy(xr + 3 * i, x + 3 * (n - 1 - i), 3 * sizeof *x);
        wr[i] = w[n - 1 - i];
    }
    for (int parts = 2; parts <= 7; ++parts) {
        sinter_mpi_decomp *a = NULL, *b = NULL;
        assert_int_equal(sinter_mpi_decomp_rcb(&a, parts, box_lo, box_hi, x, w, n, NULL, NULL),
                         SINTER_OK);
        assert_int_equal(sinter_mpi_decomp_rcb(&b, parts, box_lo, box_hi, xr, wr, n, NULL, NULL),
                         SINTER_OK);
        for (int p = 0; p < parts; ++p) {
            double la[3], ha[3], lb[3], hb[3];
            assert_int_equal(sinter_mpi_decomp_box(a, p, la, ha), SINTER_OK);
            assert_int_equal(sinter_mpi_decomp_box(b, p, lb, hb), SINTER_OK);
            assert_memory_equal(la, lb, sizeof la);
            assert_memory_equal(ha, hb, sizeof ha);
        }
        double loads_a[8], loads_b[8];
        assert_int_equal(sinter_mpi_decomp_loads(a, x, w, n, NULL, NULL, loads_a), SINTER_OK);
        assert_int_equal(sinter_mpi_decomp_loads(a, xr, wr, n, NULL, NULL, loads_b), SINTER_OK);
        assert_memory_equal(loads_a, loads_b, parts * sizeof *loads_a);
        sinter_mpi_decomp_destroy(a);
        sinter_mpi_decomp_destroy(b);
    }
    free(x);
    free(w);
    free(xr);
    free(wr);
}

/* A simple cubic lattice of 10 x 10 x 10 points: whole layers only. Three parts: the best
 * plane leaves 3 of the 10 x-layers to part 0 (300 points for a share of 333), the other 700
 * are cut across y, the longer side, into 5 + 5 layers of 70: loads 300, 350, 350, imbalance
 * 350 / (1000 / 3) = 1.05 exactly; the search ends (the bracket cannot narrow) although no
 * plane meets the share. */
static void rcb_on_a_lattice(void **state)
{
    (void)state;
    double x[3000];
    for (int i = 0; i < 1000; ++i) {
        x[3 * i] = 0.05 + 0.1 * (i % 10);
        x[3 * i + 1] = 0.05 + 0.1 * (i / 10 % 10);
        x[3 * i + 2] = 0.05 + 0.1 * (i / 100);
    }
    sinter_mpi_decomp *d = NULL;
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 3, box_lo, box_hi, x, NULL, 1000, NULL, NULL),
                     SINTER_OK);
    double loads[3];
    assert_int_equal(sinter_mpi_decomp_loads(d, x, NULL, 1000, NULL, NULL, loads), SINTER_OK);
    assert_close(loads[0], 300.0, 0.0);
    assert_close(loads[1], 350.0, 0.0);
    assert_close(loads[2], 350.0, 0.0);
    assert_close(imbalance_of(d, x, NULL, 1000), 1.05, 1e-15);
    assert_tiles(d, x, 1000);
    sinter_mpi_decomp_destroy(d);
}

static void imbalance_metric(void **state)
{
    (void)state;
    double imb = 0.0;
    const double even[4] = {2.0, 2.0, 2.0, 2.0}, one[4] = {8.0, 0.0, 0.0, 0.0},
                 none[3] = {0.0, 0.0, 0.0}, bad[2] = {1.0, -1.0};
    assert_int_equal(sinter_mpi_imbalance(even, 4, &imb), SINTER_OK);
    assert_close(imb, 1.0, 0.0);
    assert_int_equal(sinter_mpi_imbalance(one, 4, &imb), SINTER_OK);
    assert_close(imb, 4.0, 0.0);
    assert_int_equal(sinter_mpi_imbalance(none, 3, &imb), SINTER_OK);
    assert_close(imb, 1.0, 0.0);
    assert_int_equal(sinter_mpi_imbalance(bad, 2, &imb), SINTER_ERR_INVALID);
    assert_int_equal(sinter_mpi_imbalance(even, 0, &imb), SINTER_ERR_INVALID);
    assert_int_equal(sinter_mpi_imbalance(NULL, 4, &imb), SINTER_ERR_NULL);
}

/* Above the threshold the brick becomes an RCB (same address, same parts); below it, nothing. */
static void rebalance_above_threshold(void **state)
{
    (void)state;
    const size_t n = 3000;
    double *x = points(n, box_lo, third_hi, 17);
    const int slabs[3] = {1, 1, 2};
    sinter_mpi_decomp *d = NULL;
    assert_int_equal(sinter_mpi_decomp_brick(&d, 2, slabs, box_lo, box_hi), SINTER_OK);
    double before = 0.0;
    int changed = -1, kind = -1, parts = 0;
    /* 2 is below a threshold of 2.5: kept */
    assert_int_equal(sinter_mpi_decomp_rebalance(d, x, NULL, n, 2.5, NULL, NULL, &before, &changed),
                     SINTER_OK);
    assert_int_equal(changed, 0);
    assert_close(before, 2.0, 0.0);
    assert_int_equal(sinter_mpi_decomp_info(d, &kind, &parts), SINTER_OK);
    assert_int_equal(kind, SINTER_MPI_DECOMP_BRICK);
    /* above 1.1: bisected */
    assert_int_equal(sinter_mpi_decomp_rebalance(d, x, NULL, n, 1.1, NULL, NULL, &before, &changed),
                     SINTER_OK);
    assert_int_equal(changed, 1);
    assert_close(before, 2.0, 0.0);
    assert_int_equal(sinter_mpi_decomp_info(d, &kind, &parts), SINTER_OK);
    assert_int_equal(kind, SINTER_MPI_DECOMP_RCB);
    assert_int_equal(parts, 2);
    int grid[3];
    assert_int_equal(sinter_mpi_decomp_grid(d, grid), SINTER_ERR_STATE);
    /* balanced now: the next check keeps it */
    assert_int_equal(sinter_mpi_decomp_rebalance(d, x, NULL, n, 1.1, NULL, NULL, &before, &changed),
                     SINTER_OK);
    assert_int_equal(changed, 0);
    assert_true(before <= 1.0 + 2.0 / n);
    assert_int_equal(sinter_mpi_decomp_rebalance(d, x, NULL, n, 0.9, NULL, NULL, &before, &changed),
                     SINTER_ERR_INVALID);
    sinter_mpi_decomp_destroy(d);
    free(x);
}

static void refuses_bad_input(void **state)
{
    (void)state;
    sinter_mpi_decomp *d = NULL;
    const double flat[3] = {1.0, 0.0, 1.0};
    double x[6] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
    const double negative[2] = {1.0, -1.0};
    assert_int_equal(sinter_mpi_decomp_brick(NULL, 2, NULL, box_lo, box_hi), SINTER_ERR_NULL);
    assert_int_equal(sinter_mpi_decomp_brick(&d, 0, NULL, box_lo, box_hi), SINTER_ERR_INVALID);
    assert_int_equal(sinter_mpi_decomp_brick(&d, 2, NULL, box_lo, flat), SINTER_ERR_INVALID);
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 2, box_lo, box_hi, NULL, NULL, 2, NULL, NULL),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 2, box_lo, box_hi, x, negative, 2, NULL, NULL),
                     SINTER_ERR_INVALID);
    x[4] = NAN;
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 2, box_lo, box_hi, x, NULL, 2, NULL, NULL),
                     SINTER_ERR_INVALID);
    assert_null(d);
    /* no points at all: cut at the middle of the box */
    assert_int_equal(sinter_mpi_decomp_rcb(&d, 4, box_lo, box_hi, NULL, NULL, 0, NULL, NULL),
                     SINTER_OK);
    double lo[3], hi[3];
    assert_int_equal(sinter_mpi_decomp_box(d, 0, lo, hi), SINTER_OK);
    assert_close(hi[0], 0.5, 0.0);
    assert_int_equal(sinter_mpi_decomp_box(d, 4, lo, hi), SINTER_ERR_RANGE);
    sinter_mpi_decomp_destroy(d);
    sinter_mpi_decomp_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(brick_grid_is_the_least_cut_area),
        cmocka_unit_test(brick_tiles_the_box_in_cartesian_order),
        cmocka_unit_test(bottom_third_brick_against_rcb),
        cmocka_unit_test(rcb_balances_weights_not_counts),
        cmocka_unit_test(rcb_cuts_are_deterministic),
        cmocka_unit_test(rcb_on_a_lattice),
        cmocka_unit_test(imbalance_metric),
        cmocka_unit_test(rebalance_above_threshold),
        cmocka_unit_test(refuses_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
