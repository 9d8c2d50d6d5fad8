/* An MPI domain: a duplicated communicator and its decomposition (libsinter_mpi, issue 44). */
#include "mpi/domain.h"

#include "mpi/attach.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sinter_status sinter_mpi_options_init(sinter_mpi_options *options, size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (struct_size != sizeof *options)
        return SINTER_ERR_STRUCT_SIZE;
    memset(options, 0, sizeof *options);
    options->struct_size = sizeof *options;
    options->decomposition = SINTER_MPI_DECOMP_BRICK;
    for (int a = 0; a < 3; ++a)
        options->hi[a] = 1.0;
    options->balance_threshold = 1.1;
    return SINTER_OK;
}

sinter_status sinter_mpi_domain_create(sinter_mpi_domain **out, MPI_Comm comm,
                                       const sinter_mpi_options *options)
{
    if (out == NULL || options == NULL)
        return SINTER_ERR_NULL;
    *out = NULL;
    if (options->struct_size != sizeof *options)
        return SINTER_ERR_STRUCT_SIZE;
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized || comm == MPI_COMM_NULL)
        return SINTER_ERR_INVALID;
    if ((options->decomposition != SINTER_MPI_DECOMP_BRICK &&
         options->decomposition != SINTER_MPI_DECOMP_RCB) ||
        !(options->balance_threshold >= 1.0) || !isfinite(options->balance_threshold))
        return SINTER_ERR_INVALID;
    sinter_mpi_domain *d = calloc(1, sizeof *d);
    /* every rank learns of a failure on any rank before going on */
    int ok = d != NULL, all_ok = 0;
    if (MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS || !all_ok) {
        free(d);
        return all_ok ? SINTER_ERR_IO : SINTER_ERR_NOMEM;
    }
    if (MPI_Comm_dup(comm, &d->comm) != MPI_SUCCESS) {
        free(d);
        return SINTER_ERR_IO;
    }
    MPI_Comm_set_errhandler(d->comm, MPI_ERRORS_RETURN);
    MPI_Comm_rank(d->comm, &d->rank);
    MPI_Comm_size(d->comm, &d->size);
    d->options = *options;
    d->stats.struct_size = sizeof d->stats;
    /* an RCB needs points: a brick until the first balance */
    sinter_status st =
        sinter_mpi_decomp_brick(&d->decomp, d->size, options->grid, options->lo, options->hi);
    ok = st == SINTER_OK;
    if (MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, d->comm) != MPI_SUCCESS)
        st = SINTER_ERR_IO;
    else if (!all_ok && st == SINTER_OK)
        st = SINTER_ERR_NOMEM; /* argument errors are the same on every rank */
    if (st != SINTER_OK) {
        sinter_mpi_domain_destroy(d);
        return st;
    }
    *out = d;
    return SINTER_OK;
}

void sinter_mpi_domain_destroy(sinter_mpi_domain *d)
{
    if (d == NULL)
        return;
    if (d->attached != NULL) /* its stepper outlives it: its callbacks fail from now on */
        d->attached->d = NULL;
    sinter_mpi_decomp_destroy(d->decomp);
    MPI_Comm_free(&d->comm);
    free(d);
}

sinter_status sinter_mpi_domain_rank(const sinter_mpi_domain *d, int *rank, int *size)
{
    if (d == NULL || (rank == NULL && size == NULL))
        return SINTER_ERR_NULL;
    if (rank != NULL)
        *rank = d->rank;
    if (size != NULL)
        *size = d->size;
    return SINTER_OK;
}

sinter_status sinter_mpi_domain_comm(const sinter_mpi_domain *d, MPI_Comm *comm)
{
    if (d == NULL || comm == NULL)
        return SINTER_ERR_NULL;
    *comm = d->comm;
    return SINTER_OK;
}

sinter_status sinter_mpi_domain_decomp(const sinter_mpi_domain *d, const sinter_mpi_decomp **decomp)
{
    if (d == NULL || decomp == NULL)
        return SINTER_ERR_NULL;
    *decomp = d->decomp;
    return SINTER_OK;
}

sinter_status sinter_mpi_balance(sinter_mpi_domain *d, const double *positions,
                                 const double *weights, size_t n, double *imbalance,
                                 int *rebalanced)
{
    if (d == NULL || (positions == NULL && n > 0))
        return SINTER_ERR_NULL;
    int changed = 0, kind = SINTER_MPI_DECOMP_BRICK;
    sinter_mpi_decomp_info(d->decomp, &kind, NULL);
    /* an RCB domain's first balance bisects unless the brick it started as is perfect */
    const double threshold =
        d->options.decomposition == SINTER_MPI_DECOMP_RCB && kind == SINTER_MPI_DECOMP_BRICK
            ? 1.0
            : d->options.balance_threshold;
    const sinter_status st = sinter_mpi_decomp_rebalance(
        d->decomp, positions, weights, n, threshold, sinter_mpi_reduce, d, imbalance, &changed);
    if (st == SINTER_OK && changed)
        ++d->stats.rebalances;
    if (rebalanced != NULL)
        *rebalanced = st == SINTER_OK ? changed : 0;
    return st;
}

sinter_status sinter_mpi_get_stats(const sinter_mpi_domain *d, sinter_mpi_stats *stats)
{
    if (d == NULL || stats == NULL)
        return SINTER_ERR_NULL;
    if (stats->struct_size != sizeof *stats)
        return SINTER_ERR_STRUCT_SIZE;
    *stats = d->stats;
    return SINTER_OK;
}
