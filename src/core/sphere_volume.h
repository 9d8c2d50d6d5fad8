/*
 * Volumes of the pieces of spheres that the solid-fraction measures subtract: the lens two
 * overlapping spheres share and the cap of a sphere beyond a plane. Header-only so that the
 * library (io/solid_fraction.c) and the MPI command-line runner (cli/run_mpi.c, which sees only
 * the public API of the shared library) compute them with the very same expressions.
 */
#ifndef SINTER_CORE_SPHERE_VOLUME_H
#define SINTER_CORE_SPHERE_VOLUME_H

#include <math.h>

#define SINTER_SPHERE_PI 3.14159265358979323846

/* The lens [m^3] two balls of radii a, b [m] at centre distance d [m] share (the smaller ball
 * when d <= |a - b|, 0 when apart): pi (a + b - d)^2 (d^2 + 2 d (a + b) - 3 (a - b)^2) / (12 d). */
static inline double sinter_sphere_lens_volume(double a, double b, double d)
{
    if (!(d < a + b))
        return 0.0;
    const double small = fmin(a, b);
    if (d <= fabs(a - b))
        return 4.0 / 3.0 * SINTER_SPHERE_PI * small * small * small;
    const double gap = a + b - d, diff = a - b;
    return SINTER_SPHERE_PI * gap * gap * (d * d + 2.0 * d * (a + b) - 3.0 * diff * diff) /
           (12.0 * d);
}

/* The cap [m^3] of a sphere of radius r [m] beyond a plane at distance s [m] from its centre
 * (s < 0: the centre is beyond it): V = pi c^2 (3 r - c) / 3 with c = min(r - s, 2 r). */
static inline double sinter_sphere_cap_volume(double r, double s)
{
    if (s >= r)
        return 0.0;
    const double c = fmin(r - s, 2.0 * r);
    return SINTER_SPHERE_PI * c * c * (3.0 * r - c) / 3.0;
}

#endif
