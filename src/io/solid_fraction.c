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

#include "io/solid_fraction.h"

static const double PI = 3.14159265358979323846;

double sinter_lens_volume(double a, double b, double d)
{
    if (!(d < a + b))
        return 0.0;
    const double small = fmin(a, b);
    if (d <= fabs(a - b))
        return 4.0 / 3.0 * PI * small * small * small;
    const double gap = a + b - d, diff = a - b;
    return PI * gap * gap * (d * d + 2.0 * d * (a + b) - 3.0 * diff * diff) / (12.0 * d);
}

/* The cap of a sphere of radius r beyond a plane at distance s from its centre (s < 0: the
 * centre is beyond it). */
static double cap_volume(double r, double s)
{
    if (s >= r)
        return 0.0;
    const double c = fmin(r - s, 2.0 * r);
    return PI * c * c * (3.0 * r - c) / 3.0;
}

double sinter_solid_volume_in_box(const sinter_particles *ps, const sinter_pair_list *pairs,
                                  const double lo[3], const double hi[3])
{
    double volume = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i], *x = ps->x + 3 * i;
        volume += 4.0 / 3.0 * PI * r * r * r;
        for (int d = 0; d < 3; ++d)
            volume -= cap_volume(r, x[d] - lo[d]) + cap_volume(r, hi[d] - x[d]);
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
