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

#endif
