/* A minimal checker for the tests run under mpiexec (issue 44): every rank checks, failures are
 * printed with the rank and line, and the exit status is the same on every rank (a MAX over the
 * ranks' failure counts), so that mpiexec reports one result. */
#ifndef SINTER_TEST_MPI_CHECK_H
#define SINTER_TEST_MPI_CHECK_H

#include <mpi.h>
#include <stdio.h>

static int mpi_check_failures = 0;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            int rank_;                                                                             \
            MPI_Comm_rank(MPI_COMM_WORLD, &rank_);                                                 \
            fprintf(stderr, "rank %d: %s:%d: check failed: %s\n", rank_, __FILE__, __LINE__,       \
                    #cond);                                                                        \
            ++mpi_check_failures;                                                                  \
        }                                                                                          \
    } while (0)

/* 0 when no rank failed, else 1 (on every rank). */
static int mpi_check_finish(const char *name)
{
    int worst = 0, rank = 0, size = 0;
    MPI_Allreduce(&mpi_check_failures, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (rank == 0)
        printf("%s on %d ranks: %s\n", name, size, worst ? "FAILED" : "passed");
    return worst ? 1 : 0;
}

/* The same bytes on every rank (compared with rank 0's). */
static int same_on_every_rank(const void *bytes, int n)
{
    unsigned char buf[4096];
    if (n > (int)sizeof buf)
        return 0;
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    const unsigned char *b = bytes;
    for (int k = 0; k < n; ++k)
        buf[k] = b[k];
    MPI_Bcast(buf, n, MPI_UNSIGNED_CHAR, 0, MPI_COMM_WORLD);
    int same = 1;
    for (int k = 0; k < n; ++k)
        same &= buf[k] == b[k];
    int all = 0;
    MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all;
}

#endif
