/* A domain installed as a stepper's collective operations (libsinter_mpi, issue 44): the state
 * shared by attach.c (the callback table), neighbours.c (the graph), migrate.c (particles moving
 * between ranks) and halo.c (ghosts and their exchange). */
#ifndef SINTER_MPI_ATTACH_H
#define SINTER_MPI_ATTACH_H

#include "sinter_domain.h"
#include "sinter_mpi.h"

/* One ghost as it travels: id, x, v, spin, rotation (3 each), radius, mass, inertia,
 * temperature, material, flags. */
#define SINTER_MPI_GHOST_RECORD (8 + 16 * 8 + 4 + 4)

typedef struct sinter_mpi_attachment {
    sinter_mpi_domain *d; /* NULL once the domain is destroyed */
    sinter_stepper *st;
    sinter_particles *ps;
    int flags;
    sinter_domain_ops ops; /* the table installed (the tests call its halo directly) */
    /* the neighbourhood: ranks whose parts lie within `graph_cutoff` of this one's */
    MPI_Comm graph;      /* MPI_COMM_NULL: none yet */
    int nbr_count;       /* neighbours, in ascending rank order */
    int *nbr;            /* their ranks */
    double *nbr_box;     /* 6 per neighbour: the bounding box of its owned particles (lo, hi) */
    double graph_cutoff; /* [m] */
    uint64_t graph_rebalances; /* the domain's rebalance count when the graph was made */
    /* the ghosts of the last redistribution */
    size_t *send_index; /* owned rows sent, neighbour after neighbour */
    size_t send_capacity;
    int *send_count, *recv_count; /* per neighbour: ghost rows sent and received */
    size_t ghosts;                /* sum of recv_count */
    double *buffer;               /* halo packing */
    size_t buffer_capacity;       /* doubles */
    /* MPI_Neighbor_alltoallv's counts and displacements (per neighbour) */
    int *counts[4];
    sinter_mpi_exchange_stats stats;
} sinter_mpi_attachment;

/* Every rank's flag, the largest (MPI_Allreduce on the domain's communicator, counted); a
 * failure of MPI itself counts as 1. */
int sinter_mpi_agree(sinter_mpi_attachment *a, int flag);

/* Part p's box with its faces on the global box pushed to infinity. */
void sinter_mpi_open_box(const sinter_mpi_domain *d, int p, double lo[3], double hi[3]);

/* Make the neighbourhood graph when the cut-off or the decomposition changed. Collective. */
sinter_status sinter_mpi_neighbours(sinter_mpi_attachment *a, double cutoff);

/* Move the owned particles to the ranks whose parts hold them; `everywhere`: through every
 * rank (MPI_Alltoallv) rather than the neighbours. Collective; 0 or -1 on every rank. */
int sinter_mpi_migrate(sinter_mpi_attachment *a, int everywhere);

/* The ghosts of this rank: the other ranks' owned particles within `cutoff` of its part.
 * Collective; 0 or -1 (an error before the exchange is agreed; set_ghosts' is local). */
int sinter_mpi_make_ghosts(sinter_mpi_attachment *a, double cutoff);

/* The halo callback (sinter_domain_ops.halo) on the graph of the last redistribution. */
int sinter_mpi_halo(const sinter_halo *h, void *user);

/* Grow a per-neighbour int array set for `n` neighbours; 0 or -1. */
int sinter_mpi_grow_counts(sinter_mpi_attachment *a, int n);

#endif
