/* Internals of the packing helpers that the tests reach. */
#ifndef SINTER_PACKING_H
#define SINTER_PACKING_H

#include "core/core.h"

/*
 * Draw n radii [m] from the distribution of `options` (validated as sinter_pack_random does,
 * the box included) with its seed, without placing them: the sampler of sinter_pack_random
 * alone, so that a test can check a distribution on many radii. (The stream differs from the
 * packer's, which draws positions between the radii.)
 */
sinter_status sinter_packing_sample_radii(sinter_particles *particles,
                                          const sinter_packing_options *options, size_t n,
                                          double *radii);

/*
 * A sampler of one particle set's size distribution that outlives the call that made it (the
 * continuous insertion, stepper/insertion.c): the options validated as sinter_pack_random does,
 * the tables and a mixture copied, and a random stream seeded with options->seed that gives
 * radii and uniform numbers in the order they are asked for, the same on every machine. In a
 * mixture each radius drawn is of the material the apportionment (mixture.h) picks from the
 * spheres counted as placed so far, from that material's sizes if it has its own.
 */
typedef struct sinter_radius_sampler sinter_radius_sampler;

sinter_status sinter_radius_sampler_create(sinter_radius_sampler **out, sinter_particles *particles,
                                           const sinter_packing_options *options, const char *func);
/* The next radius [m] of the distribution. */
double sinter_radius_sampler_radius(sinter_radius_sampler *s);
/* The material id of the last radius drawn (options->material without a mixture). */
int32_t sinter_radius_sampler_material(const sinter_radius_sampler *s);
/* Count the last radius drawn, r [m], as placed (the mixture's masses; nothing without one). */
void sinter_radius_sampler_placed(sinter_radius_sampler *s, double r);
/* The mixture's number of materials (0: none) and its masses placed so far [kg] (*mass may be
 * NULL: not set). */
size_t sinter_radius_sampler_mixture(const sinter_radius_sampler *s, const double **mass);
/* A checkpoint's mixture state: the pending material's index, and count + 1 masses (each
 * material's, then the total) [kg]; set returns 0 (and changes nothing) for values that cannot
 * be the mixture's. */
void sinter_radius_sampler_get_mixture(const sinter_radius_sampler *s, uint64_t *pending,
                                       double *mass);
int sinter_radius_sampler_set_mixture(sinter_radius_sampler *s, uint64_t pending,
                                      const double *mass);
/* The next uniform number in [0, 1). */
double sinter_radius_sampler_uniform(sinter_radius_sampler *s);
/* The largest radius the distribution draws [m]. */
double sinter_radius_sampler_max(const sinter_radius_sampler *s);
/* The options as validated (the table pointing to the sampler's copy). */
const sinter_packing_options *sinter_radius_sampler_options(const sinter_radius_sampler *s);
/* The random stream's state (a checkpoint's), and its restoration. */
void sinter_radius_sampler_get_stream(const sinter_radius_sampler *s, uint64_t state[4]);
void sinter_radius_sampler_set_stream(sinter_radius_sampler *s, const uint64_t state[4]);
void sinter_radius_sampler_destroy(sinter_ctx *ctx, sinter_radius_sampler *s);

#endif
