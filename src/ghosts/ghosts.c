/* Ghost particles and the periodic transport (ghosts.h). */
#include "ghosts/ghosts.h"

#include <math.h>
#include <string.h>

void sinter_ghosts_free(sinter_ctx *ctx, sinter_ghosts *g)
{
    sinter_free(ctx, g->owner);
    sinter_free(ctx, g->shift);
    sinter_free(ctx, g->saved);
    g->owner = NULL;
    g->shift = NULL;
    g->saved = NULL;
    g->saved_capacity = 0;
    g->count = g->capacity = 0;
    g->built = 0;
}

int sinter_ghosts_on(const sinter_ghosts *g)
{
    return g->periodic[0] | g->periodic[1] | g->periodic[2];
}

sinter_status sinter_ghosts_set_periodic(sinter_ctx *ctx, sinter_ghosts *g, int axis, double lo,
                                         double hi)
{
    if (axis < 0 || axis > 2)
        return sinter_fail(ctx, SINTER_ERR_RANGE, "periodic axis %d is not 0 (x), 1 (y) or 2 (z)",
                           axis);
    if (lo == 0.0 && hi == 0.0) {
        g->periodic[axis] = 0;
        g->built = 0;
        return SINTER_OK;
    }
    if (!isfinite(lo) || !isfinite(hi) || !(hi > lo) || !isfinite(hi - lo))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "periodic %c: the cell %g m to %g m needs finite bounds with hi > lo",
                           "xyz"[axis], lo, hi);
    g->periodic[axis] = 1;
    g->lo[axis] = lo;
    g->hi[axis] = hi;
    g->built = 0;
    return SINTER_OK;
}

int sinter_ghosts_current(const sinter_ghosts *g, const sinter_particles *ps)
{
    return g->built && g->layout == ps->layout_generation && ps->ghost_count == g->count;
}

double sinter_ghosts_cutoff(const sinter_particles *ps, double skin)
{
    double rmax = 0.0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i)
        rmax = ps->radius[i] > rmax ? ps->radius[i] : rmax;
    return 2.0 * rmax + skin;
}

/* x wrapped into [lo, hi): a whole number of periods L taken off (one, after a neighbour
 * period, in all but pathological cases). */
static double wrap(double x, double lo, double hi)
{
    const double L = hi - lo;
    if (x >= lo && x < hi)
        return x;
    x -= L * floor((x - lo) / L);
    if (x >= hi) /* (round-off of the line above) */
        x -= L;
    if (x < lo)
        x += L;
    return x;
}

sinter_status sinter_ghosts_reserve(sinter_ctx *ctx, sinter_ghosts *g, size_t need)
{
    if (need <= g->capacity)
        return SINTER_OK;
    const size_t cap = need + need / 2 + 16;
    uint32_t *owner = sinter_realloc_array(ctx, g->owner, cap, sizeof(uint32_t));
    if (owner == NULL)
        return sinter_last_status(ctx);
    g->owner = owner;
    double *shift = sinter_realloc_array(ctx, g->shift, 3 * cap, sizeof(double));
    if (shift == NULL)
        return sinter_last_status(ctx);
    g->shift = shift;
    g->capacity = cap;
    return SINTER_OK;
}

/* Refused when a period is under twice the cut-off. */
static sinter_status check_periods(const sinter_ghosts *g, sinter_ctx *ctx, double cutoff)
{
    for (int d = 0; d < 3; ++d)
        if (g->periodic[d] && !(g->hi[d] - g->lo[d] >= 2.0 * cutoff))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "periodic %c: the period %g m is under twice the ghost cut-off "
                               "%g m (2 r_max + skin), so a particle could meet two images of "
                               "another; make the cell larger",
                               "xyz"[d], g -> hi[d] - g -> lo[d], cutoff);
    return SINTER_OK;
}

static sinter_status make_images(sinter_ghosts *g, sinter_particles *ps, double cutoff, size_t n);

sinter_status sinter_ghosts_rebuild(sinter_ghosts *g, sinter_particles *ps, double cutoff,
                                    double *x_old)
{
    sinter_ctx *ctx = ps->ctx;
    sinter_particles_drop_ghosts(ps);
    g->built = 0;
    g->count = 0;
    g->host = 0;
    const sinter_status s = check_periods(g, ctx, cutoff);
    if (s != SINTER_OK)
        return s;
    if (!g->hold)
        (void)sinter_ghosts_wrap_with(g, ps, x_old);
    return make_images(g, ps, cutoff, ps->count);
}

sinter_status sinter_ghosts_append(sinter_ghosts *g, sinter_particles *ps, double cutoff)
{
    g->built = 0;
    g->count = 0;
    const sinter_status s = check_periods(g, ps->ctx, cutoff);
    if (s != SINTER_OK)
        return s;
    g->host = ps->ghost_count;
    return make_images(g, ps, cutoff, ps->count);
}

size_t sinter_ghosts_images(const sinter_ghosts *g, const sinter_particles *ps)
{
    return g->count > 0 && g->layout == ps->layout_generation &&
                   g->host + g->count == ps->ghost_count
               ? g->count
               : 0;
}

/* The images of rows [0, n) near the faces appended to the set's ghost rows. */
static sinter_status make_images(sinter_ghosts *g, sinter_particles *ps, double cutoff, size_t n)
{
    sinter_ctx *ctx = ps->ctx;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        /* per axis the images the particle needs: none, +1 period (near lo) or -1 (near hi) */
        int s[3];
        int any = 0;
        for (int d = 0; d < 3; ++d) {
            s[d] = 0;
            if (!g->periodic[d])
                continue;
            const double x = ps->x[3 * i + d];
            s[d] = x - g->lo[d] < cutoff ? 1 : g->hi[d] - x <= cutoff ? -1 : 0;
            any |= s[d] != 0;
        }
        if (!any)
            continue;
        /* every non-empty combination of the axes that need one: up to 7 images (a corner) */
        for (int mask = 1; mask < 8; ++mask) {
            int ok = 1;
            for (int d = 0; d < 3; ++d)
                ok &= !(mask & (1 << d)) || s[d] != 0;
            if (!ok)
                continue;
            sinter_status st = sinter_ghosts_reserve(ctx, g, count + 1);
            if (st != SINTER_OK)
                return st;
            g->owner[count] = (uint32_t)i;
            for (int d = 0; d < 3; ++d)
                g->shift[3 * count + d] =
                    (mask & (1 << d)) ? (double)s[d] * (g->hi[d] - g->lo[d]) : 0.0;
            ++count;
        }
    }
    const sinter_status st = sinter_particles_append_ghost_rows(ps, count, g->owner, g->shift);
    if (st != SINTER_OK)
        return st;
    g->count = count;
    g->layout = ps->layout_generation;
    g->built = 1;
    return SINTER_OK;
}

size_t sinter_ghosts_wrap_with(sinter_ghosts *g, sinter_particles *ps, double *x_old)
{
    size_t moved = 0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i) {
        int out = 0;
        for (int d = 0; d < 3; ++d)
            if (g->periodic[d]) {
                const double x = ps->x[3 * i + d], y = wrap(x, g->lo[d], g->hi[d]);
                if (y != x && x_old != NULL) /* shifted by the same whole periods */
                    x_old[3 * i + d] += y - x;
                out |= y != x;
                ps->x[3 * i + d] = y;
            }
        moved += (size_t)out;
    }
    if (moved > 0)
        g->built = 0;
    return moved;
}

size_t sinter_ghosts_wrap(sinter_ghosts *g, sinter_particles *ps)
{
    return sinter_ghosts_wrap_with(g, ps, NULL);
}

void sinter_ghosts_copy_rows(const sinter_ghosts *g, const sinter_particles *ps, double *a,
                             int shifted)
{
    const size_t first = ps->count - ps->ghost_count + g->host;
    for (size_t k = 0; k < ps->ghost_count - g->host; ++k) {
        const size_t o = g->owner[k], q = first + k;
        for (int d = 0; d < 3; ++d)
            a[3 * q + d] = a[3 * o + d] + (shifted ? g->shift[3 * k + d] : 0.0);
    }
}

void sinter_ghosts_forward(const sinter_ghosts *g, sinter_particles *ps)
{
    const size_t first = ps->count - ps->ghost_count + g->host;
    for (size_t k = 0; k < ps->ghost_count - g->host; ++k) {
        const size_t o = g->owner[k], q = first + k;
        for (int d = 0; d < 3; ++d) {
            ps->x[3 * q + d] = ps->x[3 * o + d] + g->shift[3 * k + d];
            ps->v[3 * q + d] = ps->v[3 * o + d];
            ps->w[3 * q + d] = ps->w[3 * o + d];
            ps->rot[3 * q + d] = ps->rot[3 * o + d];
        }
        ps->temperature[q] = ps->temperature[o];
        ps->current[q] = ps->current[o];
    }
}

void sinter_ghosts_reverse(const sinter_ghosts *g, sinter_particles *ps)
{
    const size_t owned = ps->count - ps->ghost_count, first = owned + g->host;
    for (size_t k = 0; k < ps->ghost_count - g->host; ++k) {
        const size_t o = g->owner[k], q = first + k;
        if (o < owned) /* (an image of a host's ghost: discarded, newton off) */
            for (int d = 0; d < 3; ++d) {
                ps->force[3 * o + d] += ps->force[3 * q + d];
                ps->torque[3 * o + d] += ps->torque[3 * q + d];
            }
        if (o < owned)
            ps->heat[o] += ps->heat[q];
        for (int d = 0; d < 3; ++d)
            ps->force[3 * q + d] = ps->torque[3 * q + d] = 0.0;
        ps->heat[q] = 0.0;
    }
}

sinter_status sinter_ghosts_save_rows(sinter_ctx *ctx, sinter_ghosts *g, const sinter_particles *ps)
{
    const size_t n = ps->ghost_count - g->host, first = ps->count - n;
    if (6 * n + 1 > g->saved_capacity) {
        double *grown = sinter_realloc_array(ctx, g->saved, 6 * n + 1, sizeof(double));
        if (grown == NULL)
            return sinter_last_status(ctx);
        g->saved = grown;
        g->saved_capacity = 6 * n + 1;
    }
    memcpy(g->saved, ps->force + 3 * first, 3 * n * sizeof(double));
    memcpy(g->saved + 3 * n, ps->torque + 3 * first, 3 * n * sizeof(double));
    return SINTER_OK;
}

void sinter_ghosts_restore_rows(const sinter_ghosts *g, sinter_particles *ps)
{
    const size_t n = ps->ghost_count - g->host, first = ps->count - n;
    memcpy(ps->force + 3 * first, g->saved, 3 * n * sizeof(double));
    memcpy(ps->torque + 3 * first, g->saved + 3 * n, 3 * n * sizeof(double));
}
