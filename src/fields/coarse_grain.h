/*
 * Coarse-grained fields on a regular grid (src/fields/coarse_grain.c, issue 37): every
 * quantity of sinter_coarse_grain from one pass over the particles and the contacts, for the
 * scene's .vti frames (io/vti.h).
 */
#ifndef SINTER_FIELDS_COARSE_GRAIN_H
#define SINTER_FIELDS_COARSE_GRAIN_H

#include "core/core.h"

/* The grid's arrays, points = nx ny nz (owned; sinter_coarse_fields_free). */
typedef struct sinter_coarse_fields {
    size_t points;
    double *solid;       /* [1] */
    double *density;     /* [kg/m^3] */
    double *temperature; /* [K] */
    double *velocity;    /* 3 per point [m/s] */
    double *stress;      /* 9 per point [Pa] */
} sinter_coarse_fields;

/* Check the options (SINTER_ERR_INVALID with a message naming `fn`). */
sinter_status sinter_coarse_check(sinter_ctx *ctx, const char *fn, const sinter_coarse_options *o);

/* Every quantity on the grid; `snap` NULL: no contact stress. */
sinter_status sinter_coarse_fields_compute(const sinter_particles *ps, const sinter_snapshot *snap,
                                           const sinter_coarse_options *o,
                                           sinter_coarse_fields *out);

/* Per grid point: volume, mass, m T, momentum (3), m v v (9) of the particles. The sums of a
 * grid of `points` lie in two blocks: these 15 per point, then the 9 of the contact stress. */
#define SINTER_COARSE_PARTICLE_SUMS 15

/* Add the kernel-weighted sums of the first `owned` particles and of the snapshot's contacts
 * (NULL: none) whose smaller id (a wall contact: whose particle) is among them to `sums`
 * (points * SINTER_COARSE_SUMS doubles, the two blocks above). */
sinter_status sinter_coarse_accumulate(const sinter_particles *ps, const sinter_snapshot *snap,
                                       const sinter_coarse_options *o, size_t owned, double *sums);

/* The fields from (summed) sums; `out` owned as sinter_coarse_fields_compute's. */
sinter_status sinter_coarse_fields_from_sums(sinter_ctx *ctx, size_t points, const double *sums,
                                             sinter_coarse_fields *out);

void sinter_coarse_fields_free(sinter_ctx *ctx, sinter_coarse_fields *f);

#endif
