/*
 * The series columns of `mpiexec sinter run` after the solid fraction that come from the heat
 * stage (issues 41/43/44), as the serial series has them (src/io/scene_run.c): the frozen heat
 * stage's five ("frozen", "frozen time", "heat steps", "wake-ups", "heat step") with the option
 * frozen_heat on, then the beams' two ("lit particles", "lit mean temperature") with a laser,
 * nozzle or beam heat model. Absent otherwise.
 */
#ifndef SINTER_CLI_RUN_MPI_HEAT_H
#define SINTER_CLI_RUN_MPI_HEAT_H

#include <stdio.h>

#include <sinter.h>
#include <sinter_mpi.h>

/* How many such columns the stepper's series has; `beam`: the scene has a [heat laser],
 * [heat nozzle] or [heat beam] section. */
size_t run_mpi_heat_columns(const sinter_stepper *st, int beam);

/* Their names, each after a comma. */
void run_mpi_heat_header(FILE *csv, const sinter_stepper *st, int beam);

/* Their values into row[0..run_mpi_heat_columns) (collective: the lit particles' count and
 * temperatures summed exactly over the ranks, so one rank gives the serial bits; the frozen
 * stage's figures are decided together, the same on every rank). 0 on a failed view or
 * reduction. */
int run_mpi_heat_observe(const sinter_stepper *st, int beam, sinter_particles *ps,
                         sinter_mpi_domain *domain, double *row);

/* sinter_mpi_checkpoint_write of the stepper's state into `path`, or nothing (SINTER_OK, *skipped
 * = 1) while the frozen heat stage holds the mechanics: its per-particle rates do not travel in
 * the portable records yet (the stepper refuses to save them). Collective; the stage's state is
 * the same on every rank (decided from reductions). */
sinter_status run_mpi_heat_checkpoint(sinter_stepper *st, sinter_particles *ps, MPI_Comm comm,
                                      const char *path, int *skipped);

#endif
