/*
 * The 6x6 block storage of the bonded stiffness and Eisenstat's SSOR sweeps (src/bonded/
 * block_ssor.h) against dense matrices built from the same blocks, and the bonded solve
 * (src/bonded/solve.c, which runs PCG on the transformed system) against its promise: the
 * residual of the ORIGINAL system, computed here link by link with sinter_beam_apply and not
 * from the assembled blocks, is at most rtol |f|.
 */
#include "test_support.h"

#include <string.h>

#include "bonded/beam.h"
#include "bonded/block_ssor.h"
#include "bonded/domain_order.h"

enum { N = 7, DOFS = 6 * N, LINKS = 9 };

/* A small deterministic pseudo-random generator (the tests must not depend on libc's). */
static double next_uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0 * 2.0 - 1.0;
}

/* Links (lower, upper) of a connected graph on N particles, in an order that is not sorted. */
static const uint32_t LOWER_OF[LINKS] = {3, 0, 1, 0, 2, 4, 1, 5, 3};
static const uint32_t UPPER_OF[LINKS] = {6, 1, 2, 3, 5, 6, 4, 6, 4};

/* The same graph in an order with two domains, A = {0, 1}, B = {2, 3, 4}, and the separator
 * S = {5, 6}: no link between A and B. */
static const uint32_t split_lower_of[LINKS] = {0, 0, 1, 2, 3, 1, 2, 4, 5};
static const uint32_t split_upper_of[LINKS] = {1, 5, 6, 3, 4, 5, 6, 6, 6};

/* Random symmetric positive-definite diagonal blocks (sum of the coupling blocks' magnitude
 * plus a margin on the diagonal) and random coupling blocks; dense K, E = D + L alongside.
 * split: the graph with two domains. */
static void build(sinter_block_ssor *m, double k[DOFS][DOFS], double e[DOFS][DOFS], int split)
{
    uint64_t seed = 12345;
    const uint32_t *lower_of = split ? split_lower_of : LOWER_OF,
                   *upper_of = split ? split_upper_of : UPPER_OF;
    assert_int_equal(
        sinter_block_ssor_layout(m, N, lower_of, upper_of, LINKS, split ? 2 : 0, split ? 5 : 0),
        SINTER_OK);
    memset(k, 0, sizeof(double) * DOFS * DOFS);
    const size_t blocks = m->row_start[N];
    assert_int_equal(blocks, LINKS);
    for (size_t b = 0; b < blocks; ++b) {
        const size_t link = m->link_of[b];
        assert_int_equal(m->column[b], upper_of[link]);
        const size_t p = lower_of[link], q = upper_of[link];
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c) {
                const double v = next_uniform(&seed);
                m->upper_rows[36 * b + (size_t)(6 * r + c)] = v;
                k[6 * p + (size_t)r][6 * q + (size_t)c] = v;
                k[6 * q + (size_t)c][6 * p + (size_t)r] = v;
            }
    }
    for (size_t p = 0; p < N; ++p) {
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c <= r; ++c) {
                const double v = next_uniform(&seed);
                k[6 * p + (size_t)r][6 * p + (size_t)c] = k[6 * p + (size_t)c][6 * p + (size_t)r] =
                    v;
            }
        for (int r = 0; r < 6; ++r) { /* diagonal dominance: SPD */
            double row = 0.0;
            for (size_t c = 0; c < DOFS; ++c)
                row += c == 6 * p + (size_t)r ? 0.0 : fabs(k[6 * p + (size_t)r][c]);
            k[6 * p + (size_t)r][6 * p + (size_t)r] = row + 1.0;
        }
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                m->diag[36 * p + (size_t)(6 * r + c)] = k[6 * p + (size_t)r][6 * p + (size_t)c];
    }
    for (size_t i = 0; i < DOFS; ++i)
        for (size_t j = 0; j < DOFS; ++j)
            e[i][j] = j / 6 <= i / 6 ? k[i][j] : 0.0; /* block lower triangle with D */
    size_t singular = 99;
    assert_int_equal(sinter_block_ssor_finish(m, &singular), 0);
}

/* A new context and an empty block matrix of it. */
static void empty_matrix(sinter_ctx **ctx, sinter_block_ssor *m)
{
    assert_int_equal(sinter_ctx_create(ctx, NULL), SINTER_OK);
    memset(m, 0, sizeof(*m));
    m->ctx = *ctx;
}

static void dense_times(double a[DOFS][DOFS], const double *x, double *y, int transpose)
{
    for (size_t i = 0; i < DOFS; ++i) {
        double sum = 0.0;
        for (size_t j = 0; j < DOFS; ++j)
            sum += (transpose ? a[j][i] : a[i][j]) * x[j];
        y[i] = sum;
    }
}

/* |a - b| <= tol max|b| over a vector */
static void assert_vectors_close(const double *a, const double *b, size_t n, double tol)
{
    double scale = 0.0;
    for (size_t i = 0; i < n; ++i)
        scale = fmax(scale, fabs(b[i]));
    for (size_t i = 0; i < n; ++i)
        assert_close(a[i], b[i], tol * scale);
}

static void sweeps_against_dense(int split)
{
    sinter_ctx *ctx = NULL;
    sinter_block_ssor m;
    empty_matrix(&ctx, &m);
    static double k[DOFS][DOFS], e[DOFS][DOFS];
    build(&m, k, e, split);
    uint64_t seed = 777;
    double x[DOFS], y[DOFS], ref[DOFS], t[DOFS];
    for (size_t i = 0; i < DOFS; ++i)
        x[i] = next_uniform(&seed);
    /* products: K x, D x, E^T x = (D + U) x */
    sinter_block_ssor_multiply(&m, x, y);
    dense_times(k, x, ref, 0);
    assert_vectors_close(y, ref, DOFS, 1e-14);
    sinter_block_ssor_upper_multiply(&m, x, y);
    dense_times(e, x, ref, 1);
    assert_vectors_close(y, ref, DOFS, 1e-14);
    sinter_block_ssor_diag_multiply(&m, x, y);
    for (size_t i = 0; i < DOFS; ++i) {
        ref[i] = 0.0;
        for (size_t j = 6 * (i / 6); j < 6 * (i / 6) + 6; ++j)
            ref[i] += k[i][j] * x[j];
    }
    assert_vectors_close(y, ref, DOFS, 1e-14);
    /* sweeps: E^-T (E^T x) = x and E^-1 (E x) = x; diagonally dominant blocks keep the
     * sweeps' rounding within a few units of 1e-16 times the condition number (< 100) */
    dense_times(e, x, y, 1);
    sinter_block_ssor_upper_solve(&m, y);
    assert_vectors_close(y, x, DOFS, 1e-13);
    dense_times(e, x, y, 0);
    sinter_block_ssor_lower_solve(&m, y);
    assert_vectors_close(y, x, DOFS, 1e-13);
    /* Eisenstat's product equals E^-1 K E^-T v: E (K^ v) = K (E^-T v) */
    sinter_block_ssor_transformed(&m, x, y);
    dense_times(e, y, ref, 0);
    memcpy(t, x, sizeof(t));
    sinter_block_ssor_upper_solve(&m, t);
    dense_times(k, t, y, 0);
    assert_vectors_close(ref, y, DOFS, 1e-13);
    sinter_block_ssor_release(&m);
    sinter_ctx_destroy(ctx);
}

static void test_sweeps_against_dense(void **state)
{
    (void)state;
    sweeps_against_dense(0);
    /* two domains: the sweeps take A and B apart and S last (first, backward), the forward
     * sweep's pushes from A and B into S in a pass of their own */
    sweeps_against_dense(1);
}

/* A singular diagonal block is reported, the first in particle order, whichever domain or the
 * separator holds it. */
static void test_finish_reports_first_singular(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_block_ssor m;
    empty_matrix(&ctx, &m);
    static double k[DOFS][DOFS], e[DOFS][DOFS];
    const size_t cases[3][2] = {{3, 6}, {6, 6}, {1, 3}}; /* zeroed blocks -> first: A {0, 1},
                                                            B {2, 3, 4}, S {5, 6} */
    for (int c = 0; c < 3; ++c) {
        build(&m, k, e, 1);
        for (int z = 0; z < 2; ++z)
            memset(m.diag + 36 * cases[c][z], 0, 36 * sizeof(double));
        size_t singular = 99;
        assert_int_equal(sinter_block_ssor_finish(&m, &singular), -1);
        assert_int_equal(singular, cases[c][0]);
    }
    sinter_block_ssor_release(&m);
    sinter_ctx_destroy(ctx);
}

/* A link between the two domains is refused, and so are domains beyond the particles. */
static void test_layout_refuses_linked_domains(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_block_ssor m;
    empty_matrix(&ctx, &m);
    /* B = [2, 6) would hold particle 5, which particles 0 and 1 link to */
    assert_int_equal(sinter_block_ssor_layout(&m, N, split_lower_of, split_upper_of, LINKS, 2, 6),
                     SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "joins particle 0 of the first domain"));
    assert_int_equal(sinter_block_ssor_layout(&m, N, split_lower_of, split_upper_of, LINKS, 3, 2),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_block_ssor_layout(&m, N, split_lower_of, split_upper_of, LINKS, 2, 5),
                     SINTER_OK);
    sinter_block_ssor_release(&m);
    sinter_ctx_destroy(ctx);
}

/* A 4 x 4 x 3 simple cubic lattice of spheres, bonded to its neighbours by necks of random radii
 * rm in (centre +- spread) R and held on the principal planes as the quasi-static stepper holds
 * a packing. */
enum { LX = 4, LY = 4, LZ = 3, NP = LX * LY * LZ };

/* An LX x LY x LZ lattice's links (at most 3 per particle) and positions (3 per particle). */
static size_t lattice_links_of(int lx, int ly, int lz, sinter_beam *links, double *x, double centre,
                               double spread)
{
    const double r = 25e-6;
    uint64_t seed = 4242;
    for (int i = 0; i < lx; ++i)
        for (int j = 0; j < ly; ++j)
            for (int l = 0; l < lz; ++l) {
                double *xp = x + 3 * (size_t)((i * ly + j) * lz + l);
                xp[0] = (2 * i + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
                xp[1] = (2 * j + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
                xp[2] = (2 * l + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
            }
    size_t count = 0;
    for (int i = 0; i < lx; ++i)
        for (int j = 0; j < ly; ++j)
            for (int l = 0; l < lz; ++l) {
                const uint32_t a = (uint32_t)((i * ly + j) * lz + l);
                const int next[3][3] = {{i + 1, j, l}, {i, j + 1, l}, {i, j, l + 1}};
                for (int d = 0; d < 3; ++d) {
                    if (next[d][0] >= lx || next[d][1] >= ly || next[d][2] >= lz)
                        continue;
                    const uint32_t b = (uint32_t)((next[d][0] * ly + next[d][1]) * lz + next[d][2]);
                    const double rm = (centre + spread * next_uniform(&seed)) * r;
                    /* alternate the link's direction so that both orientations are assembled */
                    const uint32_t first = count % 2 ? b : a, second = count % 2 ? a : b;
                    assert_int_equal(sinter_beam_init(&links[count], first, second, x + 3 * first,
                                                      x + 3 * second, 0.97 * r, 0.99 * r, rm, 2 * r,
                                                      72e9, 0.3),
                                     0);
                    ++count;
                }
            }
    return count;
}

static size_t lattice_links(sinter_beam *links, double *x, double centre, double spread)
{
    return lattice_links_of(LX, LY, LZ, links, x, centre, spread);
}

static void solve_lattice(double centre, double spread)
{
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_bonded_solver *sv = NULL;
    assert_int_equal(sinter_bonded_solver_create(&sv, ctx), SINTER_OK);
    static sinter_beam links[3 * NP];
    static double x[3 * NP], f[6 * NP], u[6 * NP], ku[6 * NP];
    static unsigned char fixed[6 * NP];
    memset(f, 0, sizeof(f));
    const size_t count = lattice_links(links, x, centre, spread);
    const double r = 25e-6;
    for (size_t p = 0; p < NP; ++p) /* the principal planes x, y, z = 0 */
        for (int d = 0; d < 3; ++d)
            fixed[6 * p + (size_t)d] = x[3 * p + (size_t)d] < 1.5 * r;
    uint64_t seed = 99;
    for (size_t k = 0; k < count; ++k) { /* sintering-like loads along each link */
        const double fn = 1e-3 * (1.0 + 0.5 * next_uniform(&seed));
        for (int d = 0; d < 3; ++d) {
            f[6 * links[k].a + (size_t)d] += fn * links[k].axis[d];
            f[6 * links[k].b + (size_t)d] -= fn * links[k].axis[d];
        }
    }
    const double rtols[3] = {1e-4, 1e-7, 1e-10};
    for (int t = 0; t < 3; ++t) {
        int it = 0;
        assert_int_equal(sinter_bonded_solve(sv, NP, links, count, fixed, f, u, rtols[t], &it),
                         SINTER_OK);
        memset(ku, 0, sizeof(ku));
        for (size_t k = 0; k < count; ++k)
            sinter_beam_apply(&links[k], u + 6 * links[k].a, u + 6 * links[k].b,
                              ku + 6 * links[k].a, ku + 6 * links[k].b);
        double res = 0.0, norm = 0.0;
        for (size_t i = 0; i < 6 * NP; ++i) {
            if (fixed[i]) {
                assert_true(u[i] == 0.0);
                continue;
            }
            res += (f[i] - ku[i]) * (f[i] - ku[i]);
            norm += f[i] * f[i];
        }
        print_message("lattice of %d, %zu links, necks %.2f-%.2f R, rtol %.0e: %d PCG iterations, "
                      "residual %.3e |f|\n",
                      NP, count, centre - spread, centre + spread, rtols[t], it, sqrt(res / norm));
        /* the promise, with 1 % for the difference in rounding between the link-by-link
         * product here and the assembled blocks the solve tests */
        assert_true(sqrt(res) <= 1.01 * rtols[t] * sqrt(norm));
        /* and not a solve that stopped at 0: the loads do work */
        assert_true(it > 0);
    }
    sinter_bonded_solver_destroy(sv);
    sinter_ctx_destroy(ctx);
}

static void test_solve_meets_true_residual(void **state)
{
    (void)state;
    solve_lattice(0.2, 0.1);
    /* necks from 0.01 to 0.5 R, young beside grown: bending stiffness (rm^4) spread over 6e6 */
    solve_lattice(0.255, 0.245);
}

/* A link to a particle that is not there, or from a particle to itself, is refused with a
 * message naming it, and the solver stays usable. */
static void test_solve_refuses_bad_links(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_bonded_solver *sv = NULL;
    assert_int_equal(sinter_bonded_solver_create(&sv, ctx), SINTER_OK);
    const double xa[3] = {0, 0, 0}, xb[3] = {50e-6, 0, 0};
    sinter_beam l;
    assert_int_equal(sinter_beam_init(&l, 0, 1, xa, xb, 25e-6, 25e-6, 5e-6, 50e-6, 72e9, 0.3), 0);
    double f[12] = {0}, u[12];
    f[6] = 1e-3;
    unsigned char fixed[12] = {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0};
    int it = -1;
    sinter_beam bad = l;
    bad.b = 2; /* of 2 particles */
    assert_int_equal(sinter_bonded_solve(sv, 2, &bad, 1, fixed, f, u, 1e-7, &it),
                     SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "link 0 joins particles 0 and 2 of 2"));
    bad.b = 0;
    assert_int_equal(sinter_bonded_solve(sv, 2, &bad, 1, fixed, f, u, 1e-7, &it),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_bonded_solve(sv, 2, &l, 1, fixed, f, u, 1e-7, &it), SINTER_OK);
    assert_true(u[6] > 0.0 && it > 0);
    sinter_bonded_solver_destroy(sv);
    sinter_ctx_destroy(ctx);
}

/* The domains' order (bonded/domain_order.h) of `count` links: a permutation and its inverse,
 * no link between the two domains, and (balanced) each domain at least min_domain of the n
 * particles and the separator at most max_separator. */
static void check_order(const sinter_domain_order *o, size_t n, const uint32_t *a,
                        const uint32_t *b, size_t count, double min_domain, double max_separator)
{
    for (size_t p = 0; p < n; ++p) {
        assert_true(o->new_of_old[p] < n);
        assert_int_equal(o->old_of_new[o->new_of_old[p]], p);
    }
    assert_true(o->split_a <= o->split_b && o->split_b <= n);
    for (size_t k = 0; k < count; ++k) {
        const uint32_t pa = o->new_of_old[a[k]], pb = o->new_of_old[b[k]];
        const int da = pa < o->split_a   ? 0
                       : pa < o->split_b ? 1
                                         : 2,
                  db = pb < o->split_a   ? 0
                       : pb < o->split_b ? 1
                                         : 2;
        assert_false((da == 0 && db == 1) || (da == 1 && db == 0));
    }
    const size_t in_b = o->split_b - o->split_a;
    print_message("%zu particles, %zu links: domains of %zu and %zu, separator of %zu\n", n, count,
                  o->split_a, in_b, n - o->split_b);
    assert_true((double)o->split_a >= min_domain * (double)n);
    assert_true((double)in_b >= min_domain * (double)n);
    assert_true((double)(n - o->split_b) <= max_separator * (double)n);
}

/* The breadth-first levels of a 10 x 10 x 8 lattice, numbered in lattice order and then at
 * random, and of two lattices beside isolated particles: two domains of over 40 % each and a
 * separator of at most 12 % (a corner's level structure: the diagonal planes, the middle one
 * of 64-70 particles of 800). */
static void test_domain_order_separates(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    enum { BX = 10, BY = 10, BZ = 8, BN = BX * BY * BZ };
    static sinter_beam links[3 * BN];
    static double x[3 * BN];
    static uint32_t a[6 * BN], b[6 * BN], label[2 * BN + 50];
    const size_t count = lattice_links_of(BX, BY, BZ, links, x, 0.2, 0.1);
    sinter_domain_order o;
    memset(&o, 0, sizeof(o));
    o.ctx = ctx;
    for (int relabel = 0; relabel < 2; ++relabel) {
        for (size_t p = 0; p < BN; ++p)
            label[p] = (uint32_t)p;
        uint64_t seed = 31;
        for (size_t p = BN; relabel && p-- > 1;) { /* Fisher-Yates */
            const size_t q =
                (size_t)((next_uniform(&seed) + 1.0) * 0.5 * (double)(p + 1)) % (p + 1);
            const uint32_t t = label[p];
            label[p] = label[q];
            label[q] = t;
        }
        for (size_t k = 0; k < count; ++k) {
            a[k] = label[links[k].a];
            b[k] = label[links[k].b];
        }
        assert_int_equal(sinter_domain_order_make(&o, BN, a, b, count), SINTER_OK);
        check_order(&o, BN, a, b, count, 0.4, 0.12);
    }
    /* two lattices (the second one's particles after 50 isolated ones) */
    for (size_t k = 0; k < count; ++k) {
        a[k] = links[k].a;
        b[k] = links[k].b;
        a[count + k] = links[k].a + BN + 50;
        b[count + k] = links[k].b + BN + 50;
    }
    assert_int_equal(sinter_domain_order_make(&o, 2 * BN + 50, a, b, 2 * count), SINTER_OK);
    check_order(&o, 2 * BN + 50, a, b, 2 * count, 0.4, 0.12);
    /* no links: one level, none of it with a deeper neighbour, all of it in A */
    assert_int_equal(sinter_domain_order_make(&o, 5, a, b, 0), SINTER_OK);
    check_order(&o, 5, a, b, 0, 0.0, 0.0);
    assert_int_equal(o.split_a, 5);
    /* a comb: a chain of 7 particles c_k (0-6), each with a pendant p_k (7-13). From the
     * pendant p_0, level l holds c_(l-1) and p_(l-2); the pendant has no deeper neighbour and
     * joins A, so the separator is one particle of the chain */
    size_t comb = 0;
    for (uint32_t k = 0; k < 7; ++k) {
        if (k > 0) {
            a[comb] = k - 1;
            b[comb++] = k;
        }
        a[comb] = k;
        b[comb++] = 7 + k;
    }
    assert_int_equal(sinter_domain_order_make(&o, 14, a, b, comb), SINTER_OK);
    check_order(&o, 14, a, b, comb, 0.25, 1.0 / 14.0);
    assert_int_equal(14 - o.split_b, 1);
    sinter_domain_order_release(&o);
    sinter_ctx_destroy(ctx);
}

/* The bonded solve of an 8 x 8 x 6 lattice (384 particles: two domains, swept side by side on
 * two threads) gives the same bits on one thread and on two. */
static void test_solve_same_on_threads(void **state)
{
    (void)state;
    enum { TX = 8, TY = 8, TZ = 6, TN = TX * TY * TZ };
    static sinter_beam links[3 * TN];
    static double x[3 * TN], f[6 * TN], u[2][6 * TN];
    static unsigned char fixed[6 * TN];
    static uint32_t a[3 * TN], b[3 * TN];
    const size_t count = lattice_links_of(TX, TY, TZ, links, x, 0.2, 0.1);
    const double r = 25e-6;
    for (size_t p = 0; p < TN; ++p)
        for (int d = 0; d < 3; ++d)
            fixed[6 * p + (size_t)d] = x[3 * p + (size_t)d] < 1.5 * r;
    uint64_t seed = 5;
    for (size_t i = 0; i < 6 * TN; ++i)
        f[i] = 1e-3 * next_uniform(&seed);
    int iterations[2] = {0, 0};
    for (int threads = 1; threads <= 2; ++threads) {
        sinter_ctx *ctx = NULL;
        assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
        assert_int_equal(sinter_ctx_set_threads(ctx, threads), SINTER_OK);
        sinter_bonded_solver *sv = NULL;
        assert_int_equal(sinter_bonded_solver_create(&sv, ctx), SINTER_OK);
        assert_int_equal(sinter_bonded_solve(sv, TN, links, count, fixed, f, u[threads - 1], 1e-9,
                                             &iterations[threads - 1]),
                         SINTER_OK);
        if (threads == 1) { /* the order has two domains, so two threads do sweep */
            sinter_domain_order o;
            memset(&o, 0, sizeof(o));
            o.ctx = ctx;
            for (size_t k = 0; k < count; ++k) {
                a[k] = links[k].a;
                b[k] = links[k].b;
            }
            assert_int_equal(sinter_domain_order_make(&o, TN, a, b, count), SINTER_OK);
            assert_true(o.split_a > 100 && o.split_b - o.split_a > 100);
            sinter_domain_order_release(&o);
        }
        sinter_bonded_solver_destroy(sv);
        sinter_ctx_destroy(ctx);
    }
    assert_true(iterations[0] > 0);
    assert_int_equal(iterations[0], iterations[1]);
    assert_memory_equal(u[0], u[1], sizeof(u[0]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sweeps_against_dense),
        cmocka_unit_test(test_layout_refuses_linked_domains),
        cmocka_unit_test(test_finish_reports_first_singular),
        cmocka_unit_test(test_domain_order_separates),
        cmocka_unit_test(test_solve_same_on_threads),
        cmocka_unit_test(test_solve_meets_true_residual),
        cmocka_unit_test(test_solve_refuses_bad_links),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
