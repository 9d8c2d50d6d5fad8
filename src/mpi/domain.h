/* The MPI domain's state shared by domain.c and reduce.c (libsinter_mpi, issue 44). */
#ifndef SINTER_MPI_DOMAIN_H
#define SINTER_MPI_DOMAIN_H

#include "sinter_mpi.h"

struct sinter_mpi_domain {
    MPI_Comm comm; /* a duplicate, MPI_ERRORS_RETURN */
    int rank, size;
    sinter_mpi_options options;
    sinter_mpi_decomp *decomp;
    sinter_mpi_stats stats;
    struct sinter_mpi_attachment *attached; /* the stepper installed on it (attach.c), or NULL */
};

#endif
