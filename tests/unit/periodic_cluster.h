/*
 * The cluster of the periodic-boundary tests (test_periodic.c, test_periodic_staggered.c,
 * test_periodic_models.c): a compressed 3x3x3 lattice of spheres straddling a periodic face or
 * away from it, with random temperatures, velocities and spins drawn from one seed, so that
 * the two runs of a test start from the same state shifted by the period.
 */
#ifndef SINTER_TEST_PERIODIC_CLUSTER_H
#define SINTER_TEST_PERIODIC_CLUSTER_H

#include <stdint.h>

#include "scene_support.h"

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

enum { SIDE = 3, N = SIDE * SIDE * SIDE };
static const double R = 1e-3, A = 1.96e-3; /* radius and lattice spacing [m]: 2 % overlap */
static const double L = 12e-3;             /* the period along x [m] */

/* The spheres of the cluster (first corner at x = x0, temperatures 300-400 K, velocities within
 * ±0.025 m/s and spins within ±10 rad/s, seed 11) added to s's set, periodic along x on [0, L)
 * when `periodic`, the stepper's step dt [s]. The stepper and its models are the caller's. */
static void periodic_cluster_fill(scene *s, double x0, int periodic, double dt)
{
    if (periodic)
        OK(sinter_stepper_set_periodic(s->st, 0, 0.0, L));
    uint64_t seed = 11;
    for (int k = 0; k < N; ++k) {
        const double p[3] = {x0 + A * (k % SIDE), A * ((k / SIDE) % SIDE), A * (k / (SIDE * SIDE))};
        OK(sinter_particles_add(s->ps, 1, p, &R, 0, 300.0 + 100.0 * lcg(&seed), NULL));
    }
    double *v = NULL, *w = NULL;
    OK(sinter_particles_view(s->ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    OK(sinter_particles_view(s->ps, SINTER_FIELD_SPIN, (void **)&w, NULL, NULL));
    for (int k = 0; k < 3 * N; ++k) {
        v[k] = 0.05 * (lcg(&seed) - 0.5);
        w[k] = 20.0 * (lcg(&seed) - 0.5);
    }
    OK(sinter_particles_release(s->ps, SINTER_FIELD_VELOCITY));
    OK(sinter_particles_release(s->ps, SINTER_FIELD_SPIN));
    OK(sinter_stepper_set_dt(s->st, dt));
}

#endif
