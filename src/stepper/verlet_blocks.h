/*
 * Velocity Verlet's two passes over a range of plain particles (neither fixed nor without
 * rotation), in blocks that the compiler vectorises (issue 9): the per-particle factors are
 * spread over the block's x, y, z first, so that the updates run over flat arrays. The same
 * operations on the same values as one particle at a time, so the same bits.
 */
#ifndef SINTER_VERLET_BLOCKS_H
#define SINTER_VERLET_BLOCKS_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

/*
 * The passes' per-particle factors kept between steps, spread over x, y, z (3 per particle
 * each): h/(2m), h/(2J) and gravity's force 0 + m g, the values the passes form, so the same
 * bits. They change only with the masses, h or g, yet forming them took two divisions a
 * particle in each pass (issue 41: the vibrated beds' 12 million steps of 1796 spheres).
 */
typedef struct sinter_verlet_factors {
    double *fa, *fb, *mg;
    size_t capacity;        /* particles */
    size_t count;           /* particles of the factors held (0: none) */
    uint64_t layout, write; /* the particles' generations they were made for */
    const double *m, *j;    /* ... their arrays */
    double h, g[3];
    /* every particle's factors the same bits (one powder, one size): the passes read the
     * first block's lanes for every block, from L1, instead of three more arrays of the set's
     * size (issue 41: the passes ran at the speed of L2) */
    int uniform;
} sinter_verlet_factors;

/* The arrays of one pass (3 per particle but m, j). */
typedef struct sinter_verlet_arrays {
    const double *x, *v, *w, *rot;        /* state at t */
    double *f, *tq;                       /* read, then f = 0 + m g and tq = 0 */
    const double *m, *j;                  /* mass, moment of inertia */
    const double *x0;                     /* positions at the neighbour build (exact only) */
    double *nx, *nv, *nw, *nrot;          /* state at t + h, velocities at t + h/2 */
    const sinter_verlet_factors *factors; /* kept factors of these particles, h and g, or NULL */
} sinter_verlet_arrays;

/* What a range's first pass found: the first particle with a non-finite position or rotation
 * (hi: none), the largest squared displacement since the neighbour build (with `exact`) and
 * in this step, and this step's largest squared displacement along each axis (the walls'
 * certificate, contact/wall_skip.h). */
typedef struct sinter_drift_scan {
    size_t bad;
    double moved2, step2;
    double axis2[3];
} sinter_drift_scan;

/*
 * First half kick and drift of particles [lo, hi): nv = v + h/(2m) f, nx = x + h nv,
 * nw = w + h/(2J) tq, nrot = rot composed with h nw (seed 003 eq. 45) when `rotation`;
 * f = 0 + m g, tq = 0. `exact`: measure |nx - x0|^2. `stream`: streaming stores for nx, nv,
 * nw (core/stream_store.h; the caller fences).
 */
sinter_drift_scan sinter_verlet_kick_drift(const sinter_verlet_arrays *a, double h,
                                           const double g[3], int rotation, int exact, int stream,
                                           size_t lo, size_t hi);

/* Second half kick of particles [lo, hi), in place: v += h/(2m) f, w += h/(2J) tq (factors:
 * kept for these particles and h, or NULL). Returns the first particle whose velocity or spin
 * is not finite, or hi. */
size_t sinter_verlet_kick(double *v, double *w, const double *f, const double *tq, const double *m,
                          const double *j, const sinter_verlet_factors *factors, double h,
                          size_t lo, size_t hi);

/* The factors of n particles with masses m, moments j (generations layout and write), step h
 * and gravity g made or kept; returns NULL when they cannot be held (no memory: the passes
 * form them). */
const sinter_verlet_factors *sinter_verlet_factors_for(sinter_ctx *ctx, sinter_verlet_factors *c,
                                                       size_t n, const double *m, const double *j,
                                                       uint64_t layout, uint64_t write, double h,
                                                       const double g[3]);
void sinter_verlet_factors_free(sinter_ctx *ctx, sinter_verlet_factors *c);

#endif
