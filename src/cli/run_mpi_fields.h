/*
 * A scene's [fields] section through `mpiexec sinter run` (issue 44): with every frame, the
 * coarse-grained grid frames/fields_NNNNN.vti and the lamina profiles
 * frames/profile_<axis>_NNNNN.csv that the serial runner writes (src/io/scene_frames.c). Each
 * rank adds its owned particles' and its contacts' kernel-weighted sums per grid point and per
 * lamina (sinter_coarse_sums, sinter_lamina_sums: a pair by the rank that owns its smaller
 * id), the sums are summed exactly over the ranks (sinter_mpi_reduce), and rank 0 forms the
 * ratios (temperature, velocity, the kinetic stress, the fraction) and writes the files. One
 * rank writes the serial runner's bytes; more ranks differ by the rounding of the per-rank
 * partial sums (tests/mpi/cli_mpi_fields.py).
 */
#ifndef SINTER_CLI_RUN_MPI_FIELDS_H
#define SINTER_CLI_RUN_MPI_FIELDS_H

#include <sinter.h>
#include <sinter_mpi.h>

typedef struct run_mpi_fields {
    int on;                                 /* a [fields] section */
    int grid;                               /* write the .vti (key grid, default yes) */
    unsigned profiles;                      /* bit d: a profile along axis d */
    double width, spacing, cutoff, laminae; /* [m], [m], [1], [1] */
    int box;                                /* box_min and box_max given */
    double lo[3], hi[3];                    /* [m] */
    int domain;                             /* [stepper] domain_min and domain_max */
    double domain_lo[3], domain_hi[3];      /* [m] */
    int frames;                             /* [output] vtu (default yes) */
    int flags;                              /* 1 base64 arrays, 2 single precision */
    int appended;                           /* [output] vtu_format = appended (refused) */
} run_mpi_fields;

/* The scene file's [fields] section and the [output] and [stepper] keys it depends on (the
 * scene parser has checked them). */
void run_mpi_fields_read(const char *path, run_mpi_fields *f);

/* Collective: frame `frame`'s fields files, written by rank 0 into out_dir/frames (nothing
 * without a [fields] section or with vtu = no). 0 on every rank if any failed. */
int run_mpi_fields_write(const run_mpi_fields *f, sinter_ctx *ctx, sinter_stepper *st,
                         sinter_particles *ps, sinter_mpi_domain *domain, int rank,
                         const char *out_dir, unsigned long long frame);

#endif
