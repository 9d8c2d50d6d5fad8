/*
 * The solid fraction of a packing without counting overlaps twice (issue 37): the series'
 * "volume fraction" divides the spheres' summed volumes by the box, so overlapping spheres (a
 * pressed bed) count their lenses twice and parts beyond the walls count too (the press reads
 * 1.004 at its hold). Here the union's volume inside the box: sum of the sphere volumes, less
 * each overlapping pair's lens, less each sphere's caps beyond the box's faces.
 *
 * Lens of spheres of radii a, b at distance d < a + b (the intersection of two balls):
 *   V = pi (a + b - d)^2 (d^2 + 2 d (a + b) - 3 (a - b)^2) / (12 d),
 * and the smaller ball when d <= |a - b|. Cap of height c beyond a plane: V = pi c^2 (3 r - c) / 3.
 */
#include <math.h>

#include "core/sphere_volume.h"
#include "io/solid_fraction.h"

static const double PI = 3.14159265358979323846;

double sinter_lens_volume(double a, double b, double d)
{
    return sinter_sphere_lens_volume(a, b, d);
}

double sinter_solid_volume_in_box(const sinter_particles *ps, const sinter_pair_list *pairs,
                                  const double lo[3], const double hi[3])
{
    double volume = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i], *x = ps->x + 3 * i;
        volume += 4.0 / 3.0 * PI * r * r * r;
        for (int d = 0; d < 3; ++d)
            volume -= sinter_sphere_cap_volume(r, x[d] - lo[d]) +
                      sinter_sphere_cap_volume(r, hi[d] - x[d]);
    }
    for (size_t k = 0; pairs != NULL && k < pairs->count; ++k) {
        const uint32_t i = pairs->i[k], j = pairs->j[k];
        if (i >= ps->count || j >= ps->count)
            continue;
        const double *a = ps->x + 3 * i, *b = ps->x + 3 * j;
        const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        volume -=
            sinter_lens_volume(ps->radius[i], ps->radius[j], sqrt(dx * dx + dy * dy + dz * dz));
    }
    return volume;
}

double sinter_solid_fraction_sampled(sinter_ctx *ctx, const sinter_particles *ps,
                                     const double lo[3], const double hi[3], double max_points)
{
    double rmin = INFINITY;
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i], *x = ps->x + 3 * i;
        int in = 1;
        for (int d = 0; d < 3; ++d)
            in &= x[d] + r > lo[d] && x[d] - r < hi[d];
        if (in)
            rmin = fmin(rmin, r);
    }
    if (rmin == INFINITY)
        return 0.0;
    const double volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    double h = 0.25 * rmin;
    if (volume / (h * h * h) > max_points)
        h = cbrt(volume / max_points);
    size_t n[3];
    for (int d = 0; d < 3; ++d)
        n[d] = (size_t)fmax(1.0, ceil((hi[d] - lo[d]) / h));
    const double w[3] = {(hi[0] - lo[0]) / (double)n[0], (hi[1] - lo[1]) / (double)n[1],
                         (hi[2] - lo[2]) / (double)n[2]};
    const size_t total = n[0] * n[1] * n[2];
    unsigned char *mark = sinter_calloc(ctx, total, 1);
    if (mark == NULL)
        return NAN;
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i], *x = ps->x + 3 * i;
        size_t a[3], b[3];
        int in = 1;
        for (int d = 0; d < 3 && in; ++d) {
            /* the cells whose midpoint lo + (k + 1/2) w can lie within r of x */
            const double k0 = ceil((x[d] - r - lo[d]) / w[d] - 0.5),
                         k1 = floor((x[d] + r - lo[d]) / w[d] - 0.5);
            in = k1 >= 0 && k0 < (double)n[d] && k0 <= k1;
            a[d] = k0 < 0 ? 0 : (size_t)k0;
            b[d] = k1 >= (double)n[d] ? n[d] - 1 : (size_t)k1;
        }
        if (!in)
            continue;
        for (size_t p = a[0]; p <= b[0]; ++p) {
            const double dx = lo[0] + ((double)p + 0.5) * w[0] - x[0];
            for (size_t q = a[1]; q <= b[1]; ++q) {
                const double dy = lo[1] + ((double)q + 0.5) * w[1] - x[1];
                for (size_t s = a[2]; s <= b[2]; ++s) {
                    const double dz = lo[2] + ((double)s + 0.5) * w[2] - x[2];
                    if (dx * dx + dy * dy + dz * dz <= r * r)
                        mark[(p * n[1] + q) * n[2] + s] = 1;
                }
            }
        }
    }
    size_t inside = 0;
    for (size_t k = 0; k < total; ++k)
        inside += mark[k];
    sinter_free(ctx, mark);
    return (double)inside / (double)total;
}
