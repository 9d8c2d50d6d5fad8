/*
 * Particle pairs proven out of contact: a certificate per candidate pair that lets the
 * particle-particle search skip a pair's distance test while the pair provably cannot touch
 * (issue 41: in the vibrated beds every candidate pair was tested every step, 38 % of a step's
 * instructions, though a few dozen of some thousand pairs touch).
 *
 * The bound. When the search tests pair (i, j) and finds it apart (centre distance d >= the
 * sum of radii R), it keeps the key
 *     k = T + (d - R) - 1e-9 (d + R + T),
 * with T the travel at that moment: twice the sum, over the explicit drifts since the keys'
 * origin, of the largest step any particle made (the drift reports it). Since then each of
 * the two particles has moved by at most half of T_now - T_then, so the distance has shrunk
 * by at most that much and the pair cannot touch while T_now < k: its verdict "no contact" is
 * known without reading its positions (one comparison). The 1e-9 term is far above
 * the rounding of d, of the sums of steps and of the search's own test (relative 1e-16 each over at
 * most millions of steps), so a skipped pair is exactly one the test would find apart: the
 * contacts, and every result, keep their bits.
 *
 * The keys hold while the candidate pairs (their build), the particles (layout, writes,
 * count) are those they were made for and every position change since was a drift that
 * reported its step (sinter_pair_skip_moved); anything else sets all keys to 0 (T >= 0, so
 * every pair is tested and keyed again). Only for lists without held pairs (bonds in tension
 * touch at any distance).
 */
#ifndef SINTER_PAIR_SKIP_H
#define SINTER_PAIR_SKIP_H

#include <math.h>

#include "contact/neighbors.h"
#include "core/core.h"
#include "particles/particles.h"

typedef struct sinter_pair_skip {
    int valid;              /* the keys hold for build_id, ..., particles */
    int moved;              /* positions changed since the last search only by reported drifts */
    uint64_t build_id;      /* the candidate pairs' build */
    size_t pair_count;      /* ... and their number */
    uint64_t layout, write; /* the particles' layout_generation and write_generation */
    size_t particles;       /* their count */
    double travel;          /* T [m] */
    double *key;            /* k per candidate pair [m] */
    size_t capacity;
} sinter_pair_skip;

void sinter_pair_skip_free(sinter_ctx *ctx, sinter_pair_skip *s);

/* A drift moved every particle by at most sqrt(step2) [m^2]. */
void sinter_pair_skip_moved(sinter_pair_skip *s, double step2);

/* The keys dropped (a state restored, or positions changed otherwise than by a drift). */
void sinter_pair_skip_drop(sinter_pair_skip *s);

/*
 * Start of a search over `pairs` at the particles' current positions: returns the keys to
 * test against (and *travel, the T to compare), made valid for these pairs and particles
 * (all 0 when they did not hold), or NULL when none can be kept (no memory).
 */
double *sinter_pair_skip_begin(sinter_ctx *ctx, sinter_pair_skip *s, const sinter_pair_list *pairs,
                               const sinter_particles *ps, double *travel);

/* The key of a pair found apart at squared distance d2 >= R^2 (R = rs) with travel T. */
static inline double sinter_pair_skip_key(double d2, double rs, double travel)
{
    const double d = sqrt(d2);
    return travel + (d - rs) - 1e-9 * (d + rs + travel);
}

#endif
