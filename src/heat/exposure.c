/* Exposed surface fractions of particles in a bed: see exposure.h. */
#include "heat/exposure.h"

#include <math.h>

#include "contact/contacts.h"
#include "particles/particles.h"

sinter_status sinter_heat_exposed_check(const sinter_heat_model *hm, double exposed,
                                        sinter_ctx *ctx)
{
    if (exposed == 0.0 || exposed == 1.0)
        return SINTER_OK;
    return sinter_fail(ctx, SINTER_ERR_INVALID,
                       "heat model '%s': exposed = %g must be 0 (the whole surface) or 1 (the "
                       "surface not facing touching particles and walls)",
                       hm->name, exposed);
}

sinter_status sinter_heat_exposed_fraction(const sinter_heat_eval *e, double **out)
{
    const sinter_particles *ps = e->ps;
    const size_t n = ps->count;
    double *f = sinter_alloc(e->ctx, (n + 1) * sizeof(double));
    if (f == NULL)
        return sinter_last_status(e->ctx);
    for (size_t i = 0; i < n; ++i)
        f[i] = 1.0;
    const double *x = ps->x, *r = ps->radius;
    if (e->pp != NULL)
        for (size_t c = 0; c < e->pp->count; ++c) { /* in list order: the same bits always */
            const size_t i = e->pp->i[c], j = e->pp->j[c];
            const double d[3] = {x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                                 x[3 * j + 2] - x[3 * i + 2]};
            const double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (!(dist > 0.0))
                continue;
            const double si = fmin(r[j] / dist, 1.0), sj = fmin(r[i] / dist, 1.0);
            f[i] -= 0.5 * (1.0 - sqrt(1.0 - si * si)); /* the view factor from i to j */
            f[j] -= 0.5 * (1.0 - sqrt(1.0 - sj * sj));
        }
    if (e->pw != NULL)
        for (size_t c = 0; c < e->pw->count; ++c)
            f[e->pw->i[c]] -= 0.5; /* a sphere to a plane */
    /* a contact across a periodic face shades the owner of its image (heat_model.h) */
    for (size_t k = 0; e->ghost_owner != NULL && k < n - e->owned; ++k)
        f[e->ghost_owner[k]] -= 1.0 - f[e->owned + k];
    for (size_t i = 0; i < n; ++i)
        f[i] = f[i] < 0.0 ? 0.0 : f[i];
    *out = f;
    return SINTER_OK;
}
