/*
 * The cost of libsinter_mpi's reproducible reductions against MPI's own (issue 44), in the same
 * run: blocks of calls alternate between MPI_Allreduce(MPI_DOUBLE, MPI_SUM) and
 * sinter_mpi_reduce(F64, SUM) (two reductions: exponents and limbs), and the ratio of each pair
 * of blocks is kept; the median ratio and its range are printed. Then the time of one recursive
 * coordinate bisection of points spread over the ranks. Built with -DSINTER_MPI=ON, not run by
 * ctest:   mpiexec -n 2 --oversubscribe build/bin/mpi_reduce_bench [count] [points]
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "sinter_mpi.h"

static int compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    const size_t count = argc > 1 ? (size_t)atol(argv[1]) : 1;
    const size_t points = argc > 2 ? (size_t)atol(argv[2]) : 100000;
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    sinter_mpi_options o;
    sinter_mpi_domain *d = NULL;
    if (count < 1 || count > 4096 || sinter_mpi_options_init(&o, sizeof o) != SINTER_OK ||
        sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) != SINTER_OK) {
        MPI_Finalize();
        return 1;
    }
    double v[4096];
    enum { BLOCKS = 21, CALLS = 200 };
    double ratio[BLOCKS], t_mpi[BLOCKS], t_ours[BLOCKS];
    for (int b = 0; b < BLOCKS; ++b) {
        for (int pass = 0; pass < 2; ++pass) {
            MPI_Barrier(MPI_COMM_WORLD);
            const double t0 = MPI_Wtime();
            for (int c = 0; c < CALLS; ++c) {
                for (size_t k = 0; k < count; ++k)
                    v[k] = 1.0 / (double)(rank + k + c + 1);
                if (pass == 0)
                    MPI_Allreduce(MPI_IN_PLACE, v, (int)count, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
                else
                    sinter_mpi_reduce(v, count, SINTER_MPI_F64, SINTER_MPI_SUM, d);
            }
            double t = (MPI_Wtime() - t0) / CALLS;
            MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
            (pass == 0 ? t_mpi : t_ours)[b] = t;
        }
        ratio[b] = t_ours[b] / t_mpi[b];
    }
    qsort(ratio, BLOCKS, sizeof *ratio, compare);
    qsort(t_mpi, BLOCKS, sizeof *t_mpi, compare);
    qsort(t_ours, BLOCKS, sizeof *t_ours, compare);
    /* points uniform in the bottom third of the unit box, spread round-robin */
    const size_t mine = points / (size_t)size + ((size_t)rank < points % (size_t)size);
    double *x = malloc(3 * (mine > 0 ? mine : 1) * sizeof *x);
    uint64_t s = 12345 + (uint64_t)rank;
    for (size_t i = 0; x != NULL && i < 3 * mine; ++i) {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        x[i] = (double)(s >> 11) * 0x1p-53 / (i % 3 == 2 ? 3.0 : 1.0);
    }
    double t_rcb = 0.0;
    sinter_mpi_decomp *rcb = NULL;
    MPI_Barrier(MPI_COMM_WORLD);
    const double t0 = MPI_Wtime();
    const sinter_status st =
        sinter_mpi_decomp_rcb(&rcb, size, o.lo, o.hi, x, NULL, mine, sinter_mpi_reduce, d);
    t_rcb = MPI_Wtime() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &t_rcb, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    sinter_mpi_stats stats;
    stats.struct_size = sizeof stats;
    sinter_mpi_get_stats(d, &stats);
    if (rank == 0) {
        printf("np %d, %zu doubles per reduction: MPI_Allreduce %.2f us, sinter_mpi_reduce %.2f "
               "us (medians of %d blocks of %d calls); ratio median %.2f (%.2f-%.2f)\n",
               size, count, 1e6 * t_mpi[BLOCKS / 2], 1e6 * t_ours[BLOCKS / 2], BLOCKS, CALLS,
               ratio[BLOCKS / 2], ratio[0], ratio[BLOCKS - 1]);
        printf("np %d: RCB of %zu points into %d parts %.2f ms (%s)\n", size, points, size,
               1e3 * t_rcb, sinter_status_name(st));
    }
    sinter_mpi_decomp_destroy(rcb);
    free(x);
    sinter_mpi_domain_destroy(d);
    MPI_Finalize();
    return 0;
}
