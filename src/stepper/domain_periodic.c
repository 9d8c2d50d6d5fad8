/*
 * Periodic axes in a decomposed run (issues 38 and 43), for a decomposition that does not cut
 * a periodic axis (every subdomain spans the whole cell along it: slabs along a non-periodic
 * axis, or one subdomain). The host owns the ghosts of other subdomains and knows nothing of
 * the periodic cell; the library keeps its own images, as without domain operations:
 *   1. before the host's redistribution, the owned particles wrap into the cell (with the
 *      spare positions of the step under way), so that the host decides ownership and makes
 *      its ghosts from positions inside the cell;
 *   2. after it, the images of every row near a face, owned or the host's ghost, are
 *      appended after the host's ghosts (ghosts/ghosts.h, sinter_ghosts_append).
 * An image of an owned particle keeps the periodic rules (its pair with an owned particle
 * evaluated once, from the smaller id; its force added back to its owner); an image of a
 * host's ghost is a ghost of another subdomain (its pair evaluated on both sides, newton off,
 * its force discarded). The two sides of such a pair see positions that differ by a period
 * in different places (owner + L on one side, the other owner - L on the other), so they agree
 * to round-off, not bit for bit.
 */
#include <math.h>

#include "domain/domain.h"
#include "stepper.h"

sinter_status sinter_domain_periodic_wrap(sinter_stepper *st)
{
    st->domain.periodic = &st->ghosts;
    if (!sinter_ghosts_on(&st->ghosts))
        return SINTER_OK;
    sinter_particles *ps = st->ps;
    sinter_particles_drop_ghosts(ps); /* (the host makes its ghosts again) */
    double *x_old = st->spare[0] != NULL && st->spare_capacity >= ps->count ? st->spare[0] : NULL;
    (void)sinter_ghosts_wrap_with(&st->ghosts, ps, x_old);
    return SINTER_OK;
}

/* 1 when this subdomain owns particles and, along some periodic axis, none within `cutoff`
 * of one of the faces: the sign of a decomposition that cuts that axis. */
static int cuts_axis(const sinter_ghosts *g, const sinter_particles *ps, double cutoff)
{
    const size_t owned = ps->count - ps->ghost_count;
    if (owned == 0)
        return 0;
    for (int d = 0; d < 3; ++d) {
        if (!g->periodic[d])
            continue;
        int near_lo = 0, near_hi = 0;
        for (size_t i = 0; i < owned && !(near_lo && near_hi); ++i) {
            near_lo |= ps->x[3 * i + d] - g->lo[d] < cutoff;
            near_hi |= g->hi[d] - ps->x[3 * i + d] <= cutoff;
        }
        if (!near_lo || !near_hi)
            return 1;
    }
    return 0;
}

sinter_status sinter_domain_periodic_images(sinter_stepper *st, double cutoff)
{
    sinter_neighbors *nb = &st->nb;
    nb->image_count = 0;
    if (!sinter_ghosts_on(&st->ghosts))
        return SINTER_OK;
    sinter_particles *ps = st->ps;
    /* collective: the number of subdomains and of those that seem to cut an axis */
    double v[2] = {1.0, cuts_axis(&st->ghosts, ps, cutoff) ? 1.0 : 0.0};
    sinter_status s =
        sinter_domain_reduce(st->ctx, &st->domain, v, 2, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (s != SINTER_OK)
        return s;
    if (v[0] > 1.0 && v[1] > 0.0)
        return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                           "periodic axes across subdomains: %.0f of %.0f subdomains own no "
                           "particle within the ghost cut-off %g m of a face of a periodic "
                           "axis, so the decomposition seems to cut that axis; only "
                           "decompositions that leave every periodic axis whole (slabs along a "
                           "non-periodic axis) are supported yet",
                           v[1], v[0], cutoff);
    const size_t host = ps->ghost_count;
    if ((s = sinter_ghosts_append(&st->ghosts, ps, cutoff)) != SINTER_OK)
        return s;
    if ((s = sinter_explicit_keep_spare(st)) != SINTER_OK)
        return s;
    /* the spare rows (the state at t) of the images: their owners' (shifted for positions),
     * as without domain operations (the host's ghost rows were copied before) */
    for (int k = 0; k < 4 && st->spare[k] != NULL; ++k)
        sinter_ghosts_copy_rows(&st->ghosts, ps, st->spare[k], k == 0);
    nb->image_first = ps->count - ps->ghost_count + host;
    nb->image_count = st->ghosts.count;
    nb->image_owner = st->ghosts.owner;
    return SINTER_OK;
}
