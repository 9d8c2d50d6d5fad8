/*
 * Velocity Verlet's two passes over a range of plain particles (neither fixed nor without
 * rotation), in blocks that the compiler vectorises (issue 9): the per-particle factors are
 * spread over the block's x, y, z first, so that the updates run over flat arrays. The same
 * operations on the same values as one particle at a time, so the same bits.
 */
#ifndef SINTER_VERLET_BLOCKS_H
#define SINTER_VERLET_BLOCKS_H

#include <stddef.h>

/* The arrays of one pass (3 per particle but m, j). */
typedef struct sinter_verlet_arrays {
    const double *x, *v, *w, *rot; /* state at t */
    double *f, *tq;                /* read, then f = 0 + m g and tq = 0 */
    const double *m, *j;           /* mass, moment of inertia */
    const double *x0;              /* positions at the neighbour build (exact only) */
    double *nx, *nv, *nw, *nrot;   /* state at t + h, velocities at t + h/2 */
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

/* Second half kick of particles [lo, hi), in place: v += h/(2m) f, w += h/(2J) tq. Returns
 * the first particle whose velocity or spin is not finite, or hi. */
size_t sinter_verlet_kick(double *v, double *w, const double *f, const double *tq, const double *m,
                          const double *j, double h, size_t lo, size_t hi);

#endif
