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
    /* the moments only where a wall wants them (else every term is zero) */
    int moments = 0;
    for (size_t k = 0; k < nw; ++k)
        moments |= st->walls->wall[k].moment_wanted;
    const int per = moments ? 6 : 3;
    /* scratch: the exponents (v int64), the limb sums (v), their limbs for a reduction, the
     * slots' starts (v + 1) and the terms gathered by slot (per m) */
    const size_t bytes = v * (sizeof(int64_t) + sizeof(sinter_repro_sum) +
                              SINTER_REPRO_LIMBS * sizeof(int64_t) + sizeof(size_t)) +
                         sizeof(size_t) + (size_t)per * m * sizeof(double);
    sinter_status s =
        sinter_grow(st->ctx, &st->wall_sums_scratch, &st->wall_sums_scratch_capacity, bytes, 1);
    if (s != SINTER_OK)
        return s;
    int64_t *ex = st->wall_sums_scratch;
    sinter_repro_sum *sum = (sinter_repro_sum *)(ex + v);
    int64_t *limbs = (int64_t *)(sum + v);
    size_t *start = (size_t *)(limbs + SINTER_REPRO_LIMBS * v);
    double *terms = (double *)(start + v + 1);
    const uint32_t *wall = st->pw.j;
    const double *r = st->pw_reaction;
    /* the terms of each sum together (a counting sort by wall: each sum then is one pass of
     * the limb sum over its terms, in any order) */
    memset(start, 0, (v + 1) * sizeof(size_t));
    for (size_t c = 0; c < m; ++c)
        for (int d = 0; d < per; ++d)
            start[slot_of(nw, wall[c], d) + 1]++;
    for (size_t q = 0; q < v; ++q)
        start[q + 1] += start[q];
    for (size_t c = 0; c < m; ++c)
        for (int d = 0; d < per; ++d)
            terms[start[slot_of(nw, wall[c], d)]++] = r[6 * c + (size_t)d];
    for (size_t q = v; q > 0; --q) /* (the cursors ran to the ends: back to the starts) */
        start[q] = start[q - 1];
    start[0] = 0;
    for (size_t q = 0; q < v; ++q)
        ex[q] = sinter_repro_exponent(terms + start[q], start[q + 1] - start[q], 1, NULL);
    const int domain = st->domain.on && total != NULL;
    if (domain && (s = sinter_domain_reduce(st->ctx, &st->domain, ex, v, SINTER_REDUCE_I64,
                                            SINTER_REDUCE_MAX)) != SINTER_OK)
        return s;
    memset(sum, 0, v * sizeof(sinter_repro_sum));
    for (size_t q = 0; q < v; ++q)
        sinter_repro_add(&sum[q], (int)ex[q], terms + start[q], start[q + 1] - start[q], 1);
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
    s = sinter_domain_reduce(st->ctx, &st->domain, limbs, SINTER_REPRO_LIMBS * v,
                             SINTER_REDUCE_I64, SINTER_REDUCE_SUM);
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
