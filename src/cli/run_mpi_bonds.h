/*
 * Bonds that hold in tension ([force power_law] bond_strength > 0, force/power_law.c) in
 * `mpiexec sinter run` (issue 44): the serial series' column "broken bonds" (after the
 * stepper's columns, before the insertion's). A bond's flag and area live in its pair's
 * contact history, which travels with migration and is equal on both sides of a border, and
 * a broken bond is counted by the rank that owns its pair's smaller id only, so the sum over
 * the ranks (sinter_stepper_get_stats_global) counts each bond once.
 */
#ifndef SINTER_CLI_RUN_MPI_BONDS_H
#define SINTER_CLI_RUN_MPI_BONDS_H

#include <stdint.h>
#include <stdio.h>

#include <sinter.h>
#include <sinter_domain.h>
#include <sinter_mpi.h>

/* 1 for a scene file's key line `bond_strength = VALUE` in [force power_law] with a value
 * above 0 [Pa] (the bonds on). */
int run_mpi_bonds_key(const char *section, const char *line);

/* The column's name, after a comma. */
void run_mpi_bonds_header(FILE *csv);

/* At a restart (collective): the count to add to sinter_stepper_get_stats_global's
 * bonds_broken from now on, into *offset. checkpoint.mpi's global part is rank 0's, so every
 * reader starts from rank 0's share of the count; the count over the ranks at the checkpoint's
 * time is the last row of series.csv (`series`, read by rank 0; its rows end at that time).
 * 0 on every rank when it has no such column or a rank fails. */
int run_mpi_bonds_resume(const sinter_stepper *st, MPI_Comm comm, const char *series,
                         int64_t *offset);

#endif
