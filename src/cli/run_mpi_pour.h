/*
 * The pour of `mpiexec -n N sinter run` (run_mpi_pour.c): a scene's [pour] section on the ranks,
 * as the serial runner's programme has it (io/scene_run.c).
 */
#ifndef SINTER_CLI_RUN_MPI_POUR_H
#define SINTER_CLI_RUN_MPI_POUR_H

#include <sinter.h>
#include <sinter_mpi.h>

typedef struct mpi_pour {
    int on;        /* the scene has a [pour] section */
    int furnace;   /* its [stepper] has a temperature_schedule (refused with a pour) */
    double ke;     /* ke_per_particle: the kinetic energy per particle at rest [J] */
    double t_min;  /* the least time of the pour [s] */
    double t_max;  /* the longest [s] */
    int pouring;   /* the pour is under way */
    double start;  /* its start [s] */
    double origin; /* its end: the walls' motions and the end time count from it [s] */
    double energy; /* the last sample's kinetic energy per particle [J] */
} mpi_pour;

/* The [pour] section's keys and whether [stepper] has a furnace, from the scene file (every
 * rank reads it). 0 when the file cannot be read. Not collective. */
int mpi_pour_read(const char *scene_path, mpi_pour *p);

/* A fresh run's pour after its first sample at time t [s]: every wall held (its motion starts
 * at the pour's end). Not collective. */
sinter_status mpi_pour_begin(mpi_pour *p, sinter_walls *walls, double t);

/* The end of the current phase [s]: the pour's start + t_max, else the origin + end_time. */
double mpi_pour_phase_end(const mpi_pour *p, double end_time);

/* After a sample at time t [s] with the kinetic energy ke [J] summed over the ranks (the
 * same on every rank): the pour ends when it has lasted t_min and the energy per owned
 * particle of all ranks is below the threshold; then every wall's motion starts at t, which
 * becomes the origin, and *ended is 1. Collective while pouring (the particles' count). */
sinter_status mpi_pour_sample(mpi_pour *p, sinter_walls *walls, sinter_particles *ps,
                              sinter_mpi_domain *domain, double t, double ke, int *ended);

/* Rank 0: the pour's state beside the checkpoint (CHECKPOINT.pour), written to a temporary
 * file and renamed. 0 on an I/O error. */
int mpi_pour_save(const mpi_pour *p, const char *checkpoint_path);

/* At a restart: the pour's state from CHECKPOINT.pour. 0 when it is missing or unreadable. */
int mpi_pour_load(mpi_pour *p, const char *checkpoint_path);

#endif
