/* Particles sent to the ranks whose parts hold them (libsinter_mpi, issue 44). */
#ifndef SINTER_MPI_SEND_TO_OWNERS_H
#define SINTER_MPI_SEND_TO_OWNERS_H

#include <mpi.h>

#include "sinter.h"
#include "sinter_mpi_decomp.h"

/*
 * Move every owned particle of (stepper, particles) whose centre lies in another rank's part of
 * `decomp` (part r belongs to rank r of comm) to that rank, with everything its stepper keeps
 * for it: the records of sinter_stepper_export (with removal, one stream per destination in
 * ascending rank order), their sizes through MPI_Alltoall and the streams through
 * MPI_Alltoallv, imported in ascending rank order of their senders. Collective over comm (its
 * error handler MPI_ERRORS_RETURN); returns the same status on every rank. On an error the
 * particles may be spread between the ranks: the caller undoes what it needs to.
 */
int sinter_mpi_send_to_owners(sinter_stepper *stepper, sinter_particles *particles, MPI_Comm comm,
                              const sinter_mpi_decomp *decomp);

#endif
