/*
 * A few sums over every subdomain whose bits depend neither on the order of their terms nor on
 * how the terms are split into subdomains (issue 43, the reproducible mode): the limb sums of
 * core/repro_sum.h with two integer reductions, the exponents' maximum (with a flag for a
 * term that is not finite) and the limbs' sum, as the wall reactions of stepper/wall_sums.c.
 * Without domain operations (d NULL or off) the sums are this part's alone, the same bits.
 *
 * Use: sinter_exact_begin, then for each sum its terms through sinter_exact_scan (the
 * exponents), sinter_exact_agree (collective), the same terms through sinter_exact_add, then
 * sinter_exact_finish (collective). A sum of terms that holds one that is not finite anywhere
 * is NaN everywhere.
 */
#ifndef SINTER_DOMAIN_EXACT_REDUCE_H
#define SINTER_DOMAIN_EXACT_REDUCE_H

#include "core/repro_sum.h"
#include "domain/domain.h"

#define SINTER_EXACT_MAX 16 /* sums in one batch */

typedef struct sinter_exact {
    size_t count;                    /* sums in the batch */
    int64_t e[2 * SINTER_EXACT_MAX]; /* exponents, then the flags of non-finite terms */
    sinter_repro_sum s[SINTER_EXACT_MAX];
} sinter_exact;

/* A batch of `count` sums (count <= SINTER_EXACT_MAX), all zero. */
void sinter_exact_begin(sinter_exact *x, size_t count);

/* The exponents of sum c's terms: a[k] (b NULL) or the products a[k] b[k], k < n. */
void sinter_exact_scan(sinter_exact *x, size_t c, const double *a, const double *b, size_t n);

/* The exponents' maximum over every subdomain (collective: one reduction of integers). */
sinter_status sinter_exact_agree(sinter_ctx *ctx, sinter_domain *d, sinter_exact *x);

/* The same terms as scanned, added to sum c at the agreed exponent. */
void sinter_exact_add(sinter_exact *x, size_t c, const double *a, const double *b, size_t n);

/* The sums over every subdomain into out[0 .. count) (collective: one reduction of integers). */
sinter_status sinter_exact_finish(sinter_ctx *ctx, sinter_domain *d, sinter_exact *x, double *out);

#endif
