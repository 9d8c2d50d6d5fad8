/* Collective agreement on a status (libsinter_mpi, issue 44): every rank learns the most
 * negative status of any rank, so that no rank goes on while another failed. */
#ifndef SINTER_MPI_AGREE_H
#define SINTER_MPI_AGREE_H

#include <mpi.h>

#include "sinter.h"

/* The most negative of every rank's `status` (SINTER_OK when none failed); SINTER_ERR_IO when
 * the reduction itself fails. Collective over comm. */
static inline int sinter_mpi_agree(MPI_Comm comm, int status)
{
    int worst = status;
    if (MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS)
        return SINTER_ERR_IO;
    return worst;
}

#endif
