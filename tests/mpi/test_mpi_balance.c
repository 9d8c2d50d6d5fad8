/* libsinter_mpi's load balance under mpiexec (issue 44): a pour's particles in the bottom third
 * of the box, spread over the ranks in two ways. A brick of z slabs leaves them to the lowest
 * rank (imbalance 2 on two ranks, 3 on three and four); sinter_mpi_balance bisects them to at
 * most 1.1, and the parts are the same bits as one process's bisection of all the points: the
 * cuts do not depend on how many ranks there are or which rank holds which point. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

#include "sinter_mpi.h"

static int rank, size;

static double uniform(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) * 0x1p-53;
}

/* The parts of a and b are the same bits. */
static int same_parts(const sinter_mpi_decomp *a, const sinter_mpi_decomp *b)
{
    int pa = 0, pb = 0, same = 1;
    sinter_mpi_decomp_info(a, NULL, &pa);
    sinter_mpi_decomp_info(b, NULL, &pb);
    if (pa != pb)
        return 0;
    for (int p = 0; p < pa; ++p) {
        double la[3], ha[3], lb[3], hb[3];
        sinter_mpi_decomp_box(a, p, la, ha);
        sinter_mpi_decomp_box(b, p, lb, hb);
        same &= memcmp(la, lb, sizeof la) == 0 && memcmp(ha, hb, sizeof ha) == 0;
    }
    return same;
}

/* One spread of the points: round-robin (blocks = 0) or contiguous blocks in reverse. */
static void balance_case(const double *x, const double *w, size_t n, int blocks)
{
    double *mx = malloc(3 * n * sizeof *mx), *mw = malloc(n * sizeof *mw);
    CHECK(mx != NULL && mw != NULL);
    if (mx == NULL || mw == NULL)
        return;
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
        const int holder =
            blocks ? size - 1 - (int)(i * (size_t)size / n) : (int)(i % (size_t)size);
        if (holder != rank)
            continue;
        memcpy(mx + 3 * m, x + 3 * i, 3 * sizeof *x);
        mw[m++] = w != NULL ? w[i] : 1.0;
    }
    sinter_mpi_options o;
    CHECK(sinter_mpi_options_init(&o, sizeof o) == SINTER_OK);
    o.grid[0] = o.grid[1] = 1;
    o.grid[2] = size; /* z slabs */
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK);
    if (d == NULL)
        return;
    double before = 0.0;
    int changed = -1;
    CHECK(sinter_mpi_balance(d, mx, w != NULL ? mw : NULL, m, &before, &changed) == SINTER_OK);
    const sinter_mpi_decomp *decomp = NULL;
    CHECK(sinter_mpi_domain_decomp(d, &decomp) == SINTER_OK);
    double loads[64], after = 0.0;
    CHECK(size <= 64);
    CHECK(sinter_mpi_decomp_loads(decomp, mx, w != NULL ? mw : NULL, m, sinter_mpi_reduce, d,
                                  loads) == SINTER_OK);
    CHECK(sinter_mpi_imbalance(loads, size, &after) == SINTER_OK);
    if (rank == 0)
        printf("%s, %s: brick of z slabs %.4f, after balancing %.4f (%s)\n",
               w != NULL ? "weighted" : "unweighted", blocks ? "blocks" : "round-robin", before,
               after, changed ? "rebalanced" : "kept");
    if (size == 1) {
        CHECK(before == 1.0 && changed == 0);
    } else {
        CHECK(w != NULL || (size == 2 ? before == 2.0 : before >= 2.0));
        CHECK(changed == 1);
        CHECK(after <= 1.1);
        /* the bisection of one process holding every point: the same bits */
        sinter_mpi_decomp *serial = NULL;
        CHECK(sinter_mpi_decomp_rcb(&serial, size, o.lo, o.hi, x, w, n, NULL, NULL) == SINTER_OK);
        CHECK(serial != NULL && same_parts(serial, decomp));
        sinter_mpi_decomp_destroy(serial);
        /* balanced now: the next check keeps it */
        CHECK(sinter_mpi_balance(d, mx, w != NULL ? mw : NULL, m, &before, &changed) == SINTER_OK);
        CHECK(changed == 0 && before <= 1.1);
    }
    /* every rank holds the same decomposition */
    double boxes[6 * 64];
    for (int p = 0; p < size && p < 64; ++p)
        sinter_mpi_decomp_box(decomp, p, boxes + 6 * p, boxes + 6 * p + 3);
    CHECK(same_on_every_rank(boxes, (int)(6 * (size_t)(size < 64 ? size : 64) * sizeof *boxes)));
    sinter_mpi_domain_destroy(d);
    free(mx);
    free(mw);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const size_t n = 6000;
    double *x = malloc(3 * n * sizeof *x), *w = malloc(n * sizeof *w);
    CHECK(x != NULL && w != NULL);
    if (x != NULL && w != NULL) {
        uint64_t seed = 2026;
        for (size_t i = 0; i < n; ++i) { /* the same points on every rank: the bottom third */
            x[3 * i] = uniform(&seed);
            x[3 * i + 1] = uniform(&seed);
            x[3 * i + 2] = uniform(&seed) / 3.0;
            w[i] = 0.5 + 10.0 * uniform(&seed); /* contacts or measured time, say */
        }
        balance_case(x, NULL, n, 0);
        balance_case(x, NULL, n, 1);
        balance_case(x, w, n, 0);
        balance_case(x, w, n, 1);
    }
    free(x);
    free(w);
    const int rc = mpi_check_finish("test_mpi_balance");
    MPI_Finalize();
    return rc;
}
