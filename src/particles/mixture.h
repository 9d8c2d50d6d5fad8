/* The apportionment of a mixture by mass fraction (issue 38): which material the next particle
 * of a packing or an insertion takes (mixture.c). */
#ifndef SINTER_MIXTURE_H
#define SINTER_MIXTURE_H

#include "core/core.h"

typedef struct sinter_mixture {
    size_t count;      /* materials; 0: no mixture */
    int32_t *material; /* ids */
    double *fraction;  /* mass fractions as given (positive, summing to `sum`) */
    double *density;   /* of each material [kg/m^3] */
    double *mass;      /* placed so far, per material [kg] */
    double sum, total; /* the fractions' sum; the mass placed so far [kg] */
} sinter_mixture;

/* The mixture of validated options (mixture_count > 0; nothing to do for 0), fractions and ids
 * copied, densities read from the set, no mass placed yet. Errors: SINTER_ERR_NOMEM. */
sinter_status sinter_mixture_init(sinter_mixture *mx, const sinter_particles *ps,
                                  const sinter_packing_options *o);
void sinter_mixture_free(sinter_ctx *ctx, sinter_mixture *mx);

/* The index of the material furthest below its share, f_k / sum M - M_k largest (the lowest
 * index on a tie). */
size_t sinter_mixture_next(const sinter_mixture *mx);

/* The mass of a sphere of radius r [m] of material k [kg]. */
double sinter_mixture_particle_mass(const sinter_mixture *mx, size_t k, double r);

/* Count a sphere of radius r [m] of material k as placed. */
void sinter_mixture_add(sinter_mixture *mx, size_t k, double r);

#endif
