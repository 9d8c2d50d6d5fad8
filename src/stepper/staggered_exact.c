/* The staggered stepper's exact sums in the reproducible mode: see staggered_exact.h. */
#include "stepper/staggered_exact.h"

#include <math.h>
#include <string.h>

#include "domain/exact_reduce.h"

/* The subdomains' operations, or NULL without them. */
static sinter_domain *domain_of(sinter_stepper *st)
{
    return st->domain.on ? &st->domain : NULL;
}

/* Room for `count` terms in the stepper's scratch. */
static sinter_status terms_room(sinter_stepper *st, size_t count, double **terms)
{
    sinter_staggered *sg = &st->staggered;
    const sinter_status s =
        sinter_grow(st->ctx, (void **)&sg->terms, &sg->terms_capacity, count + 1, sizeof(double));
    *terms = sg->terms;
    return s;
}

sinter_status sinter_staggered_exact_errors(sinter_stepper *st, const double *now,
                                            const double *prev, const double *start, int comps,
                                            uint32_t skip, double out[4])
{
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count - ps->ghost_count;
    double *t = NULL;
    sinter_status s = terms_room(st, 3 * n, &t);
    /* (without memory every subdomain still takes part in the reductions, with no terms) */
    const size_t m = s == SINTER_OK ? n : 0;
    size_t free_count = 0;
    for (size_t i = 0; i < m; ++i) {
        t[i] = t[n + i] = t[2 * n + i] = 0.0;
        if (ps->flags[i] & skip)
            continue;
        free_count++;
        const double *a = now + (size_t)comps * i, *b = prev + (size_t)comps * i,
                     *c = start + (size_t)comps * i;
        if (comps == 1) {
            t[i] = fabs(a[0] - b[0]);
            t[n + i] = fabs(a[0] - c[0]);
            t[2 * n + i] = fabs(a[0]);
        } else {
            const double d1[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
            const double d2[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
            t[i] = sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
            t[n + i] = sqrt(d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]);
            t[2 * n + i] = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        }
    }
    const double *a[3] = {t, t + n, t + 2 * n};
    const size_t len[3] = {m, m, m};
    const sinter_status r = sinter_domain_exact_sums(st->ctx, domain_of(st), 3, a, NULL, len, out);
    out[3] = (double)free_count; /* (a count: exact as a double in any order) */
    const sinter_status q = sinter_domain_sum(st->ctx, &st->domain, out + 3, 1);
    return s != SINTER_OK ? s : r != SINTER_OK ? r : q;
}

sinter_status sinter_staggered_exact_norms(sinter_stepper *st, size_t n, const double *u,
                                           const double *g, const double *w, double out[2])
{
    double *t = NULL;
    const sinter_status s = terms_room(st, 4 * n, &t);
    const size_t m = s == SINTER_OK ? n : 0;
    for (size_t i = 0; i < 3 * m; ++i)
        t[i] = w[i] * (g[i] - u[i]);
    for (size_t i = 0; i < m; ++i)
        t[3 * m + i] = w[9 * m + i] * (g[9 * m + i] - u[9 * m + i]);
    const double *a[2] = {t, t + 3 * m};
    const size_t len[2] = {3 * m, m};
    const sinter_status r =
        sinter_domain_exact_sums(st->ctx, domain_of(st), 2, a, a, len, out); /* the squares */
    return s != SINTER_OK ? s : r;
}

/* Anderson's vectors hold x, v, w (3 m rows each), theta (m rows); the rows of v and w carry
 * weight 0 (staggered.c, aa_weights), so every product there is W dF or W f times something,
 * zero: only the rows of x and theta are summed (0.4 of the terms). */
int sinter_staggered_exact_dots(const double *const *a, const double *const *b, size_t n,
                                size_t count, double *out, void *user)
{
    sinter_stepper *st = user;
    if (count > SINTER_REPRO_BATCH)
        return -1;
    const size_t m = n / 10;
    sinter_domain_reducer r;
    const sinter_repro_reduce_fn reduce = sinter_domain_reducer_init(&r, st->ctx, domain_of(st));
    sinter_repro_batch x;
    sinter_repro_begin(&x, count);
    for (size_t c = 0; c < count; ++c) {
        sinter_repro_scan(&x, c, a[c], b[c], 3 * m);
        sinter_repro_scan(&x, c, a[c] + 9 * m, b[c] + 9 * m, m);
    }
    if (sinter_repro_agree(&x, reduce, &r) != 0)
        return -1;
    for (size_t c = 0; c < count; ++c) {
        sinter_repro_accumulate(&x, c, a[c], b[c], 3 * m);
        sinter_repro_accumulate(&x, c, a[c] + 9 * m, b[c] + 9 * m, m);
    }
    return sinter_repro_finish(&x, reduce, &r, out);
}
