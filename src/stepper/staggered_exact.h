/*
 * The staggered stepper's global sums in the reproducible mode (issue 43, stepper option
 * "reproducible"): eq. 47's error sums (scheme 0), the weighted RMS norms and Anderson's inner
 * products (scheme 1) as exact sums of their per-particle terms (domain/exact_reduce.h), so
 * that every decision of the fixed point and the step control is the same bits for any
 * decomposition into subdomains, any number of threads and any order of the particles in
 * memory. Collective with domain operations (two integer reductions per batch of sums).
 */
#ifndef SINTER_STAGGERED_EXACT_H
#define SINTER_STAGGERED_EXACT_H

#include "stepper/stepper.h"

/* Eq. 47's sums over the owned particles whose flags do not contain `skip`, for a field of
 * `comps` (1 or 3) components per particle: out = {sum |now - prev|, sum |now - start|,
 * sum |now|, the particles counted}, each term as staggered.c's normalised_error forms it. */
sinter_status sinter_staggered_exact_errors(sinter_stepper *st, const double *now,
                                            const double *prev, const double *start, int comps,
                                            uint32_t skip, double out[4]);

/* The WRMS sums of squares of w (g - u) over the positions (rows [0, 3n)) and the
 * temperatures (rows [9n, 10n)) of scheme 1's vectors of n particles: out = {x, theta}. */
sinter_status sinter_staggered_exact_norms(sinter_stepper *st, size_t n, const double *u,
                                           const double *g, const double *w, double out[2]);

/* Anderson's inner products (anderson.h, sinter_anderson_sum.dots); user: the stepper. */
int sinter_staggered_exact_dots(const double *const *a, const double *const *b, size_t n,
                                size_t count, double *out, void *user);

#endif
