/* Order- and split-independent sums over every subdomain: see exact_reduce.h. */
#include "domain/exact_reduce.h"

static int reduce_i64(int64_t *values, size_t count, int op, void *user)
{
    sinter_domain_reducer *r = user;
    const sinter_status s =
        sinter_domain_reduce(r->ctx, r->d, values, count, SINTER_REDUCE_I64,
                             op == SINTER_REPRO_MAX ? SINTER_REDUCE_MAX : SINTER_REDUCE_SUM);
    if (r->status == SINTER_OK)
        r->status = s;
    return s != SINTER_OK;
}

sinter_repro_reduce_fn sinter_domain_reducer_init(sinter_domain_reducer *r, sinter_ctx *ctx,
                                                  sinter_domain *d)
{
    *r = (sinter_domain_reducer){.ctx = ctx, .d = d, .status = SINTER_OK};
    return d != NULL && d->on ? reduce_i64 : NULL;
}

sinter_status sinter_domain_exact_sums(sinter_ctx *ctx, sinter_domain *d, size_t count,
                                       const double *const *a, const double *const *b,
                                       const size_t *n, double *out)
{
    sinter_domain_reducer r;
    const sinter_repro_reduce_fn reduce = sinter_domain_reducer_init(&r, ctx, d);
    sinter_repro_batch x;
    sinter_repro_begin(&x, count);
    for (size_t c = 0; c < x.count; ++c)
        sinter_repro_scan(&x, c, a[c], b != NULL ? b[c] : NULL, n[c]);
    if (sinter_repro_agree(&x, reduce, &r) != 0)
        return r.status;
    for (size_t c = 0; c < x.count; ++c)
        sinter_repro_accumulate(&x, c, a[c], b != NULL ? b[c] : NULL, n[c]);
    (void)sinter_repro_finish(&x, reduce, &r, out);
    return r.status;
}
