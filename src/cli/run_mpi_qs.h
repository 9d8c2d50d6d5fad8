/* The quasi-static stepper's share of `mpiexec -n N sinter run` (run_mpi_qs.c, issue 44). */
#ifndef SINTER_CLI_RUN_MPI_QS_H
#define SINTER_CLI_RUN_MPI_QS_H

#include <stdio.h>

#include <sinter.h>

#include "core/id_row.h"

/* The serial series' sintering columns after the wall forces (seed 001 sec. 4). */
enum { CLI_MPI_QS_COLUMNS = 9 };

/* Their header names, each after a comma. */
void cli_mpi_qs_header(FILE *csv);

/*
 * The sintering columns into q (collective: the statistics are reduced over the ranks by the
 * library). Before the stepper's first step, as the serial runner: no links, no shrinkage, and
 * the relative density of the spheres' summed volume `solid` [m^3] over their bounding box
 * lo..hi [m] (both already reduced over the ranks). 0 on a failed call.
 */
int cli_mpi_qs_sintering(sinter_stepper *st, double solid, const double lo[3], const double hi[3],
                         double q[CLI_MPI_QS_COLUMNS]);

/*
 * This rank's links (each held once, by the rank that owns its smaller id), into *links, and
 * their lens volumes [m^3] subtracted from *volume in link order: the spheres' overlaps that
 * the solid fraction does not count twice. x, radius: the set's rows (`owned` first, then
 * ghosts); table: its ids sorted (rows entries). Before the stepper's first step (no links
 * yet) its overlapping pairs instead, each counted by the owner of its smaller id: the pairs
 * that the first step links (a compacted green body's overlaps). 0 when a link's end is
 * neither owned nor a ghost here, or out of memory.
 */
int cli_mpi_qs_lenses(const sinter_stepper *st, const sinter_id_row *table, size_t rows,
                      size_t owned, const double *x, const double *radius, double *volume,
                      double *links);

#endif
