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

void sinter_coarse_fields_free(sinter_ctx *ctx, sinter_coarse_fields *f);

#endif
