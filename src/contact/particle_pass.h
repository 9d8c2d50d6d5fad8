/*
 * A pass over the particles, each on its own (a drag, a heat source, a softening factor), on
 * the pair partition's particle ranges (contact/chunks.h): each thread takes the particles
 * whose contact forces and heat it sums, so their cache lines stay on its core. Without a
 * partition (one thread, or a list too small to be split) one call covers every particle.
 * The ranges depend on the contact list only: any thread count gives the same calls, and a
 * pass whose particles are independent gives the same bits.
 */
#ifndef SINTER_CONTACT_PARTICLE_PASS_H
#define SINTER_CONTACT_PARTICLE_PASS_H

#include <stddef.h>

#include "contact/chunks.h"
#include "core/core.h"

/* Work on particles [lo, hi), range `range` of the pass (0 without a partition). */
typedef void (*sinter_particle_range_fn)(void *data, int range, size_t lo, size_t hi);

/* Calls fn over n particles: on the step's threads (sinter_threads) over the ranges of the
 * pair list pp's partition (pp NULL: none) when it has one, else once. Returns the number of
 * ranges (1 without a partition; at most SINTER_CHUNKS_MAX). */
int sinter_particle_pass(const sinter_ctx *ctx, const sinter_contact_list *pp, size_t n,
                         sinter_particle_range_fn fn, void *data);

#endif
