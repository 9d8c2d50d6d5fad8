/*
 * The compaction of `mpiexec -n N sinter run` (run_mpi_compact.c): a scene's [compact] section
 * before the run, as the serial runner's programme has it (io/scene_run.c).
 */
#ifndef SINTER_CLI_RUN_MPI_COMPACT_H
#define SINTER_CLI_RUN_MPI_COMPACT_H

#include <sinter.h>

typedef struct mpi_compact {
    int on;                            /* the scene has a [compact] section */
    sinter_compaction_options options; /* its keys, as the scene reads them */
} mpi_compact;

/* The [compact] section's keys from the scene file (every rank reads it; the scene's load
 * has checked them). 0 when the file cannot be read. Not collective. */
int mpi_compact_read(const char *scene_path, mpi_compact *c);

/* Compact `particles` (every particle of the scene, before rank 0 spreads them) with
 * sinter_pack_compact, as the serial runner does before its first step; `message` receives
 * the serial runner's info line about it ("" without [compact]). Not collective (rank 0). */
sinter_status mpi_compact_run(const mpi_compact *c, sinter_particles *particles, char *message,
                              size_t size);

#endif
