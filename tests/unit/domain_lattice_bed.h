/*
 * The lattice bed of test_domain.c and tests/mpi/test_mpi_attach.c: 8 x 6 x 6 spheres of
 * radius R on a lattice of spacing A (1.5 % overlap) in the box [0, LX] x [0, LY], jiggled,
 * with random velocities, spins and temperatures from one seed (43), the same for every
 * decomposition; ids in another order than the lattice's (a multiplicative permutation) so
 * that nothing leans on ids ascending. The slabs along x: [X0, X1) cut into 1-4 equal ones
 * puts every border on a column of the lattice (X1 - X0 = 12 A), so that the particles of that
 * column, jiggling about it, cross it back and forth and migrate. And a host body force that
 * poisons one particle's force with a NaN.
 */
#ifndef SINTER_TEST_DOMAIN_LATTICE_BED_H
#define SINTER_TEST_DOMAIN_LATTICE_BED_H

#include <math.h>
#include <stdint.h>

#include <sinter.h>
#include <sinter_submodel.h>

enum { NX = 8, NY = 6, NZ = 6, N = NX * NY * NZ };
static const double R = 1e-3, A = 1.97e-3; /* radius and lattice spacing [m]: 1.5 % overlap */
static const double LX = R + A * (NX - 1) + 0.99 * R; /* the box [m] */
static const double LY = R + A * (NY - 1) + 0.99 * R;
static const double X0 = R - 2 * A, X1 = R + 10 * A; /* the slabs' range [m] */

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

typedef struct bed_spec {
    double x[3 * N], v[3 * N], w[3 * N], temp[N];
    uint64_t id[N];
} bed_spec;

static bed_spec BED;

static void make_bed(void)
{
    uint64_t seed = 43;
    for (int k = 0; k < N; ++k) {
        const int i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
        BED.x[3 * k] = R + A * i + 0.01 * R * (lcg(&seed) - 0.5);
        BED.x[3 * k + 1] = R + A * j + 0.01 * R * (lcg(&seed) - 0.5);
        BED.x[3 * k + 2] = 0.99 * R + A * l + 0.01 * R * (lcg(&seed) - 0.5);
        for (int d = 0; d < 3; ++d) {
            BED.v[3 * k + d] = 0.04 * (lcg(&seed) - 0.5);
            BED.w[3 * k + d] = 20.0 * (lcg(&seed) - 0.5);
        }
        BED.temp[k] = 300.0 + 100.0 * lcg(&seed);
        BED.id[k] = 1 + (uint64_t)((k * 37) % N);
    }
}

/* A host body force that makes the force of the particle with id `id` NaN from time `after`
 * on, on the subdomain that owns it then (it may have migrated). */
typedef struct poison {
    const sinter_particles *ps;
    uint64_t id; /* (0: none) */
    double after;
} poison;

static int poison_force(const sinter_state_view *s, double *force, double *torque, void *user)
{
    (void)torque;
    const poison *p = user;
    size_t i = SIZE_MAX, owned = 0;
    if (p->id == 0 || !(s->time > p->after) ||
        sinter_particles_owned_count(p->ps, &owned) != SINTER_OK ||
        sinter_particles_find_id(p->ps, p->id, &i) != SINTER_OK || i >= owned)
        return 0;
    force[3 * i] = NAN;
    return 0;
}

#endif
