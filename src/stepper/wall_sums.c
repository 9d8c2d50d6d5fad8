/* The wall reactions of the reproducible mode: see wall_sums.h. */
#include <string.h>

#include "core/repro_sum.h"
#include "domain/domain.h"
#include "stepper/wall_sums.h"

sinter_status sinter_wall_sums_prepare(sinter_stepper *st, double **reaction)
{
    *reaction = NULL;
    st->pw_reaction_count = 0;
    if (!st->reproducible || st->walls == NULL || st->walls->count == 0)
        return SINTER_OK;
    const size_t m = st->pw.count;
    const sinter_status s = sinter_grow(st->ctx, (void **)&st->pw_reaction,
                                        &st->pw_reaction_capacity, 6 * m + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    memset(st->pw_reaction, 0, 6 * m * sizeof(double));
    st->pw_reaction_count = m;
    st->pw_reaction_valid = 1;
    *reaction = st->pw_reaction;
    return SINTER_OK;
}

/* Values (k, d) of the 6 nw sums: force d of wall k at 3 k + d, its moment at 3 (nw + k) + d. */
static size_t slot_of(size_t nw, size_t wall, int d)
{
    return d < 3 ? 3 * wall + (size_t)d : 3 * (nw + wall) + (size_t)(d - 3);
}

sinter_status sinter_wall_sums(sinter_stepper *st, double *local, double *total)
{
    const size_t nw = st->walls != NULL ? st->walls->count : 0, m = st->pw_reaction_count;
    if (nw == 0)
        return SINTER_OK;
    const size_t v = 6 * nw; /* values */
    /* scratch: the exponents (v int64), the limb sums (v), their limbs for a reduction */
    const size_t bytes =
        v * (sizeof(int64_t) + sizeof(sinter_repro_sum) + SINTER_REPRO_LIMBS * sizeof(int64_t));
    sinter_status s =
        sinter_grow(st->ctx, &st->wall_sums_scratch, &st->wall_sums_scratch_capacity, bytes, 1);
    if (s != SINTER_OK)
        return s;
    int64_t *ex = st->wall_sums_scratch;
    sinter_repro_sum *sum = (sinter_repro_sum *)(ex + v);
    int64_t *limbs = (int64_t *)(sum + v);
    const uint32_t *wall = st->pw.j;
    const double *r = st->pw_reaction;
    /* the exponent of each sum over its terms (its wall's contacts), the same for any order */
    for (size_t q = 0; q < v; ++q)
        ex[q] = INT32_MIN;
    for (size_t c = 0; c < m; ++c)
        for (int d = 0; d < 6; ++d) {
            const int e = sinter_repro_exponent(r + 6 * c + d, 1, 1, NULL);
            int64_t *to = &ex[slot_of(nw, wall[c], d)];
            *to = e > *to ? e : *to;
        }
    const int domain = st->domain.on && total != NULL;
    if (domain && (s = sinter_domain_reduce(st->ctx, &st->domain, ex, v, SINTER_REDUCE_I64,
                                            SINTER_REDUCE_MAX)) != SINTER_OK)
        return s;
    memset(sum, 0, v * sizeof(sinter_repro_sum));
    for (size_t c = 0; c < m; ++c)
        for (int d = 0; d < 6; ++d) {
            const size_t q = slot_of(nw, wall[c], d);
            sinter_repro_add(&sum[q], (int)ex[q], r + 6 * c + d, 1, 1);
        }
    if (!domain) { /* the share is the total (at its own exponents) */
        for (size_t q = 0; q < v; ++q) {
            const double x = sinter_repro_value(&sum[q], (int)ex[q]);
            if (local != NULL)
                local[q] = x;
            if (total != NULL)
                total[q] = x;
        }
        return SINTER_OK;
    }
    /* the share at the common exponents, then the limbs summed over the subdomains (integer
     * sums: exact and order-free; each part carried first, so no limb overflows) */
    const sinter_repro_sum zero = {{0}, 0};
    for (size_t q = 0; q < v; ++q) {
        sinter_repro_sum part = zero;
        sinter_repro_merge(&part, &sum[q]); /* (carries) */
        if (local != NULL)
            local[q] = sinter_repro_value(&part, (int)ex[q]);
        for (int k = 0; k < SINTER_REPRO_LIMBS; ++k)
            limbs[SINTER_REPRO_LIMBS * q + (size_t)k] = part.limb[k];
    }
    s = sinter_domain_reduce(st->ctx, &st->domain, limbs, SINTER_REPRO_LIMBS * v, SINTER_REDUCE_I64,
                             SINTER_REDUCE_SUM);
    if (s != SINTER_OK)
        return s;
    for (size_t q = 0; q < v; ++q) {
        sinter_repro_sum all = zero;
        for (int k = 0; k < SINTER_REPRO_LIMBS; ++k)
            all.limb[k] = limbs[SINTER_REPRO_LIMBS * q + (size_t)k];
        total[q] = sinter_repro_value(&all, (int)ex[q]);
    }
    return SINTER_OK;
}
