/*
 * The relative density of laminae (seed 001 eq. 48, Fig. 10): the volume of the spheres'
 * slices between a lamina's two planes over the lamina's volume (sinter_lamina_profile).
 */
#include <math.h>

#include <sinter_domain.h>

#include "core/core.h"
#include "particles/particles.h"

static const double PI = 3.14159265358979323846;

/* The volume of a sphere of radius r centred at 0 between the planes u = a and u = b (a <= b):
 * pi [r^2 u - u^3 / 3] over the part of [a, b] inside [-r, r]. */
static double slice_volume(double r, double a, double b)
{
    a = fmax(a, -r);
    b = fmin(b, r);
    if (!(b > a))
        return 0.0;
    return PI * (r * r * (b - a) - (b * b * b - a * a * a) / 3.0);
}

/* Check the arguments of sinter_lamina_profile and _sums. */
static sinter_status lamina_check(sinter_ctx *ctx, const char *fn, int axis, const double lo[3],
                                  const double hi[3], size_t count)
{
    SINTER_CHECK_NULL(ctx, lo);
    SINTER_CHECK_NULL(ctx, hi);
    if (axis < 0 || axis > 2)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: axis is %d, expected 0, 1 or 2", fn, axis);
    if (count == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: need count >= 1 laminae", fn);
    for (int d = 0; d < 3; ++d)
        if (!(lo[d] < hi[d]) || !isfinite(lo[d]) || !isfinite(hi[d]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: need finite lo < hi along axis %d of the box", fn, d);
    return SINTER_OK;
}

/* Add the slice volumes of the first n particles to volume[] and times their temperature to
 * heat[]. */
static void lamina_add(const sinter_particles *ps, size_t n, int axis, const double lo[3],
                       const double hi[3], size_t count, double *volume, double *heat)
{
    const double q = (hi[axis] - lo[axis]) / (double)count;
    for (size_t i = 0; i < n; ++i) {
        const double r = ps->radius[i], c = ps->x[3 * i + (size_t)axis];
        /* the laminae the sphere reaches */
        const double first = floor((c - r - lo[axis]) / q), last = floor((c + r - lo[axis]) / q);
        if (last < 0 || first >= (double)count)
            continue;
        const size_t s0 = first < 0 ? 0 : (size_t)first;
        const size_t s1 = last >= (double)count ? count - 1 : (size_t)last;
        for (size_t s = s0; s <= s1; ++s) {
            const double a = lo[axis] + (double)s * q - c, b = a + q;
            const double v = slice_volume(r, a, b);
            volume[s] += v;
            heat[s] += v * ps->temperature[i];
        }
    }
}

sinter_status sinter_lamina_sums(const sinter_particles *ps, int axis, const double lo[3],
                                 const double hi[3], size_t count, double *sums)
{
    static const char *const fn = "sinter_lamina_sums";
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_status st = lamina_check(ps->ctx, fn, axis, lo, hi, count);
    if (st != SINTER_OK)
        return st;
    SINTER_CHECK_NULL(ps->ctx, sums);
    lamina_add(ps, ps->count - ps->ghost_count, axis, lo, hi, count, sums, sums + count);
    return SINTER_OK;
}

sinter_status sinter_lamina_profile(const sinter_particles *ps, int axis, const double lo[3],
                                    const double hi[3], size_t count, double *fraction,
                                    double *temperature)
{
    static const char *const fn = "sinter_lamina_profile";
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    sinter_status st = lamina_check(ctx, fn, axis, lo, hi, count);
    if (st != SINTER_OK)
        return st;
    double *volume = sinter_calloc(ctx, 2 * count, sizeof(double));
    if (volume == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory", fn);
    double *heat = volume + count; /* slice volume times temperature */
    const double q = (hi[axis] - lo[axis]) / (double)count;
    lamina_add(ps, ps->count, axis, lo, hi, count, volume, heat);
    double section = 1.0;
    for (int d = 0; d < 3; ++d)
        if (d != axis)
            section *= hi[d] - lo[d];
    for (size_t s = 0; s < count; ++s) {
        if (fraction != NULL)
            fraction[s] = volume[s] / (section * q); /* eq. 48 */
        if (temperature != NULL)
            temperature[s] = volume[s] > 0 ? heat[s] / volume[s] : NAN;
    }
    sinter_free(ctx, volume);
    return SINTER_OK;
}
