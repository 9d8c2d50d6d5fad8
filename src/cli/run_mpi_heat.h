/*
 * The series columns of `mpiexec sinter run` after the solid fraction that come from the heat
 * stage (issues 41/43/44), as the serial series has them (src/io/scene_run.c): the frozen heat
 * stage's five ("frozen", "frozen time", "heat steps", "wake-ups", "heat step") with the option
 * frozen_heat on, the temperature histogram's n + 2 with [output] temperature_bins, then the
 * beams' two ("lit particles", "lit mean temperature") with a laser, nozzle or beam heat model.
 * Absent otherwise.
 */
#ifndef SINTER_CLI_RUN_MPI_HEAT_H
#define SINTER_CLI_RUN_MPI_HEAT_H

#include <stdio.h>

#include <sinter.h>
#include <sinter_mpi.h>

/* The most such columns: 5 of the frozen stage, 100 bins + 2, 2 lit (the scene parser's limit
 * on the bins is 100, SCENE_MAX_TEMPERATURE_BINS). */
enum { RUN_MPI_HEAT_MAX_BINS = 100, RUN_MPI_HEAT_MAX_COLUMNS = 5 + RUN_MPI_HEAT_MAX_BINS + 2 + 2 };

/* What the scene asks of them beyond the stepper's options. */
typedef struct run_mpi_heat_spec {
    int beam;      /* a [heat laser], [heat nozzle] or [heat beam] section: the lit columns */
    size_t bins;   /* [output] temperature_bins' count n (0: no histogram) */
    double lo, hi; /* its range [K] */
} run_mpi_heat_spec;

/* The histogram's `low high n` from the scene file's [output] temperature_bins into spec (bins
 * 0 without it; the scene parser has checked it). */
void run_mpi_heat_read(const char *path, run_mpi_heat_spec *spec);

/* How many such columns the stepper's series has. */
size_t run_mpi_heat_columns(const sinter_stepper *st, const run_mpi_heat_spec *spec);

/* Their names, each after a comma. */
void run_mpi_heat_header(FILE *csv, const sinter_stepper *st, const run_mpi_heat_spec *spec);

/* Their values into row[0..run_mpi_heat_columns) (collective: the histogram's counts and the lit
 * particles' count and temperatures summed exactly over the ranks, so one rank gives the serial
 * bits; the frozen stage's figures are decided together, the same on every rank). 0 on a failed
 * view or reduction. */
int run_mpi_heat_observe(const sinter_stepper *st, const run_mpi_heat_spec *spec,
                         sinter_particles *ps, sinter_mpi_domain *domain, double *row);

/* sinter_mpi_checkpoint_write of the stepper's state into `path`, or nothing (SINTER_OK, *skipped
 * = 1) while the frozen heat stage holds the mechanics: its per-particle rates do not travel in
 * the portable records yet (the stepper refuses to save them). Collective; the stage's state is
 * the same on every rank (decided from reductions). */
sinter_status run_mpi_heat_checkpoint(sinter_stepper *st, sinter_particles *ps, MPI_Comm comm,
                                      const char *path, int *skipped);

#endif
