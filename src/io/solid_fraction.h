/* The solid volume of overlapping spheres inside a box (io/solid_fraction.c). */
#ifndef SINTER_IO_SOLID_FRACTION_H
#define SINTER_IO_SOLID_FRACTION_H

#include "contact/neighbors.h"
#include "particles/particles.h"

/*
 * The volume [m^3] of the union of the spheres inside the box [lo, hi]: the spheres' volumes,
 * less the lens of every overlapping pair of `pairs` (a neighbour list over the particles; NULL:
 * none) and the cap of every sphere beyond each face of the box. Exact while no point lies in
 * three spheres, nor a lens or a cap in two caps (a sphere across an edge of the box).
 */
double sinter_solid_volume_in_box(const sinter_particles *ps, const sinter_pair_list *pairs,
                                  const double lo[3], const double hi[3]);

/* The volume [m^3] of the lens two spheres of radii a and b share at centre distance d (0 when
 * they do not overlap; the smaller sphere when it lies inside the other). */
double sinter_lens_volume(double a, double b, double d);

/*
 * The solid fraction of a box [lo, hi] that spheres may cross or lie outside (a region inside a
 * bed, such as a powder layer's middle): the fraction of the midpoints of a regular grid of
 * cells over the box that lie in at least one sphere (the union: overlaps count once). The
 * cells are about a quarter of the smallest radius reaching the box wide, at most `max_points`
 * in all (coarser when more would be needed); the midpoint count of a sphere of radius r on
 * cells of width h errs by O(h / r) of its surface layer, a fraction of a percent of the
 * volume at h = r / 4 for a bed of many spheres (tests/unit/test_solid_fraction.c). Returns NAN
 * when out of memory; 0 when no sphere reaches the box.
 */
double sinter_solid_fraction_sampled(sinter_ctx *ctx, const sinter_particles *ps,
                                     const double lo[3], const double hi[3], double max_points);

#endif
