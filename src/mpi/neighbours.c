/*
 * The neighbourhood of a rank (libsinter_mpi, issue 44): the parts of the decomposition whose
 * boxes lie within the ghost cut-off of this rank's box, as a symmetric graph communicator
 * (MPI_Dist_graph_create_adjacent) for MPI's neighbourhood collectives. Every particle a rank
 * owns at a redistribution lies in its part, and every ghost it needs lies within the cut-off
 * of one of them, so the neighbours are all it exchanges with between two redistributions.
 * A part's faces on the global box are pushed to infinity: a point outside the box belongs to
 * the nearest part (sinter_mpi_decomp_owners).
 */
#include <math.h>
#include <stdlib.h>

#include "mpi/attach.h"
#include "mpi/domain.h"

void sinter_mpi_open_box(const sinter_mpi_domain *d, int p, double lo[3], double hi[3])
{
    sinter_mpi_decomp_box(d->decomp, p, lo, hi);
    for (int a = 0; a < 3; ++a) {
        if (lo[a] <= d->options.lo[a])
            lo[a] = -INFINITY;
        if (hi[a] >= d->options.hi[a])
            hi[a] = INFINITY;
    }
}

/* The squared distance between two boxes (0 when they touch or overlap). */
static double box_gap2(const double alo[3], const double ahi[3], const double blo[3],
                       const double bhi[3])
{
    double s = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double g = fmax(0.0, fmax(alo[a] - bhi[a], blo[a] - ahi[a]));
        s += g * g;
    }
    return s;
}

int sinter_mpi_grow_counts(sinter_mpi_attachment *a, int n)
{
    for (int k = 0; k < 4; ++k) {
        int *g = realloc(a->counts[k], (size_t)(n + 1) * sizeof(int));
        if (g == NULL)
            return -1;
        a->counts[k] = g;
    }
    int *s = realloc(a->send_count, (size_t)(n + 1) * sizeof(int));
    if (s != NULL)
        a->send_count = s;
    int *r = realloc(a->recv_count, (size_t)(n + 1) * sizeof(int));
    if (r != NULL)
        a->recv_count = r;
    return s != NULL && r != NULL ? 0 : -1;
}

sinter_status sinter_mpi_neighbours(sinter_mpi_attachment *a, double cutoff)
{
    sinter_mpi_domain *d = a->d;
    if (a->graph != MPI_COMM_NULL && cutoff == a->graph_cutoff &&
        d->stats.rebalances == a->graph_rebalances)
        return SINTER_OK;
    /* every rank holds the same decomposition and cut-off: the same graph everywhere */
    double mlo[3], mhi[3], plo[3], phi[3];
    sinter_mpi_open_box(d, d->rank, mlo, mhi);
    int *nbr = malloc((size_t)d->size * sizeof(int)), n = 0;
    /* equal weights (MPI_UNWEIGHTED, a sentinel of no size, trips GCC's access checks) */
    int *weight = malloc((size_t)d->size * sizeof(int));
    int bad = nbr == NULL || weight == NULL;
    for (int p = 0; p < d->size && !bad; ++p) {
        sinter_mpi_open_box(d, p, plo, phi);
        if (p != d->rank && box_gap2(mlo, mhi, plo, phi) <= cutoff * cutoff)
            weight[n] = 1, nbr[n++] = p;
    }
    bad |= !bad && sinter_mpi_grow_counts(a, n) != 0;
    double *box = bad ? NULL : realloc(a->nbr_box, (6 * (size_t)n + 6) * sizeof(double));
    if (box != NULL)
        a->nbr_box = box;
    bad |= box == NULL;
    if (sinter_mpi_agree(a, bad)) {
        free(nbr);
        free(weight);
        return SINTER_ERR_NOMEM;
    }
    if (a->graph != MPI_COMM_NULL)
        MPI_Comm_free(&a->graph);
    const double t0 = MPI_Wtime();
    const int rc = MPI_Dist_graph_create_adjacent(d->comm, n, nbr, weight, n, nbr, weight,
                                                  MPI_INFO_NULL, 0, &a->graph);
    free(weight);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    free(a->nbr);
    a->nbr = nbr;
    a->nbr_count = n;
    a->graph_cutoff = cutoff;
    a->graph_rebalances = d->stats.rebalances;
    a->stats.graph_builds++;
    a->stats.neighbours = n;
    if (rc != MPI_SUCCESS) {
        a->graph = MPI_COMM_NULL;
        return SINTER_ERR_IO;
    }
    MPI_Comm_set_errhandler(a->graph, MPI_ERRORS_RETURN);
    return SINTER_OK;
}
