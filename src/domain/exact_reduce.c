/* Order- and split-independent sums over every subdomain: see exact_reduce.h. */
#include "domain/exact_reduce.h"

#include <math.h>
#include <string.h>

enum { CHUNK = 64 }; /* products formed on the stack, this many at a time */

void sinter_exact_begin(sinter_exact *x, size_t count)
{
    memset(x, 0, sizeof(*x));
    x->count = count < SINTER_EXACT_MAX ? count : SINTER_EXACT_MAX;
    for (size_t c = 0; c < x->count; ++c)
        x->e[c] = INT32_MIN; /* (every term zero so far) */
}

/* Terms [k0, k0 + m) of a sum into p: a[k] or a[k] b[k] (each product rounded once, the same
 * bits wherever it is formed). */
static const double *terms(const double *a, const double *b, size_t k0, size_t m, double *p)
{
    if (b == NULL)
        return a + k0;
    for (size_t k = 0; k < m; ++k)
        p[k] = a[k0 + k] * b[k0 + k];
    return p;
}

void sinter_exact_scan(sinter_exact *x, size_t c, const double *a, const double *b, size_t n)
{
    double p[CHUNK];
    for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
        const size_t m = n - k0 < CHUNK ? n - k0 : CHUNK;
        int finite = 1;
        const int e = sinter_repro_exponent(terms(a, b, k0, m, p), m, 1, &finite);
        if (e > x->e[c])
            x->e[c] = e;
        if (!finite)
            x->e[x->count + c] = 1;
    }
}

sinter_status sinter_exact_agree(sinter_ctx *ctx, sinter_domain *d, sinter_exact *x)
{
    if (d == NULL || !d->on)
        return SINTER_OK;
    return sinter_domain_reduce(ctx, d, x->e, 2 * x->count, SINTER_REDUCE_I64, SINTER_REDUCE_MAX);
}

void sinter_exact_add(sinter_exact *x, size_t c, const double *a, const double *b, size_t n)
{
    double p[CHUNK];
    for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
        const size_t m = n - k0 < CHUNK ? n - k0 : CHUNK;
        sinter_repro_add(&x->s[c], (int)x->e[c], terms(a, b, k0, m, p), m, 1);
    }
}

sinter_status sinter_exact_finish(sinter_ctx *ctx, sinter_domain *d, sinter_exact *x, double *out)
{
    /* each part's limbs carried (no limb near overflow), then summed as integers: exact */
    int64_t limbs[SINTER_REPRO_LIMBS * SINTER_EXACT_MAX];
    const sinter_repro_sum zero = {{0}, 0};
    for (size_t c = 0; c < x->count; ++c) {
        sinter_repro_sum part = zero;
        sinter_repro_merge(&part, &x->s[c]);
        memcpy(limbs + SINTER_REPRO_LIMBS * c, part.limb, sizeof(part.limb));
    }
    if (d != NULL && d->on) {
        const sinter_status s = sinter_domain_reduce(ctx, d, limbs, SINTER_REPRO_LIMBS * x->count,
                                                     SINTER_REDUCE_I64, SINTER_REDUCE_SUM);
        if (s != SINTER_OK)
            return s;
    }
    for (size_t c = 0; c < x->count; ++c) {
        sinter_repro_sum all = zero;
        memcpy(all.limb, limbs + SINTER_REPRO_LIMBS * c, sizeof(all.limb));
        out[c] = x->e[x->count + c] ? NAN : sinter_repro_value(&all, (int)x->e[c]);
    }
    return SINTER_OK;
}
