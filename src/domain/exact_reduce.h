/*
 * Sums over every subdomain whose bits depend neither on the order of their terms nor on how
 * the terms are split into subdomains (issue 43, the reproducible mode): the batches of
 * core/repro_sum.h with their two integer reductions (the exponents' MAX, the limbs' SUM)
 * through sinter_domain_reduce. Without domain operations (d NULL or off) the sums are this
 * part's alone, the same bits.
 */
#ifndef SINTER_DOMAIN_EXACT_REDUCE_H
#define SINTER_DOMAIN_EXACT_REDUCE_H

#include "core/repro_sum.h"
#include "domain/domain.h"

/* The subdomains' reductions as a sinter_repro_reduce_fn's user data; status: the first
 * failure's (the reduction's own message is in ctx). */
typedef struct sinter_domain_reducer {
    sinter_ctx *ctx;
    sinter_domain *d;
    sinter_status status;
} sinter_domain_reducer;

/* r set up for d; returns the reduce callback for r, NULL without domain operations. */
sinter_repro_reduce_fn sinter_domain_reducer_init(sinter_domain_reducer *r, sinter_ctx *ctx,
                                                  sinter_domain *d);

/* The exact sums out[c] = sum_k a[c][k] b[c][k] (b or b[c] NULL: the a[c][k]), k < n[c],
 * c < count (count <= SINTER_REPRO_BATCH), over every subdomain (d NULL or off: this part's).
 * Collective: two integer reductions. */
sinter_status sinter_domain_exact_sums(sinter_ctx *ctx, sinter_domain *d, size_t count,
                                       const double *const *a, const double *const *b,
                                       const size_t *n, double *out);

#endif
