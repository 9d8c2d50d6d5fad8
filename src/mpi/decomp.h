/* The decomposition object shared by brick.c, rcb.c and decomp.c (libsinter_mpi, issue 44). */
#ifndef SINTER_MPI_DECOMP_INTERNAL_H
#define SINTER_MPI_DECOMP_INTERNAL_H

#include "sinter_mpi_decomp.h"

struct sinter_mpi_decomp {
    int kind; /* a sinter_mpi_decomp_kind */
    int parts;
    double lo[3], hi[3];
    double *box; /* parts x {lo[3], hi[3]} */
    /* brick */
    int grid[3];
    double *planes[3]; /* grid[a] + 1 planes per axis, planes[a][0] = lo[a], [grid[a]] = hi[a] */
    double *plane_store;
    /* RCB: parts - 1 cuts, node 0 the root; a child >= 0 is a node, < 0 the part -(child + 1) */
    int *axis;
    double *cut;
    int *child; /* 2 per node: below the cut, at or above it */
};

/* An empty decomposition of `parts` parts over [lo, hi] (arguments checked by the caller). */
sinter_status sinter_mpi_decomp_alloc(sinter_mpi_decomp **out, int kind, int parts,
                                      const double lo[3], const double hi[3]);

/* The part owning one point. */
int sinter_mpi_decomp_owner(const sinter_mpi_decomp *d, const double x[3]);

/* 1 when lo < hi on every axis and all are finite. */
int sinter_mpi_box_valid(const double lo[3], const double hi[3]);

#endif
