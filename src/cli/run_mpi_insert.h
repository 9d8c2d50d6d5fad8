/*
 * Continuous insertion ([insert]) in `mpiexec sinter run` (issues 43/44): the series columns
 * "inserted mass" and "insertion target" as the serial series has them (after the stepper's
 * columns, before the solid fraction), and the insertion region in the decomposition's box
 * (a scene that starts empty has no particles to size it).
 */
#ifndef SINTER_CLI_RUN_MPI_INSERT_H
#define SINTER_CLI_RUN_MPI_INSERT_H

#include <stdio.h>

#include <sinter.h>

enum { RUN_MPI_INSERT_COLUMNS = 2 };

/* Their names, each after a comma. */
void run_mpi_insert_header(FILE *csv);

/* Their values into row[0..RUN_MPI_INSERT_COLUMNS): the same on every rank (the library agrees
 * the inserted mass, and every rank keeps the same target). 0 on failure. */
int run_mpi_insert_observe(const sinter_stepper *st, double *row);

/* lo and hi grown to hold the [insert] section's box_min and box_max of the scene file at
 * `path` (unchanged without them). */
void run_mpi_insert_box(const char *path, double lo[3], double hi[3]);

#endif
