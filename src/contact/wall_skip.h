/*
 * Plane walls proven out of reach: a certificate that lets the particle-wall search skip
 * every candidate pair of an axis-aligned plane wall that no particle can have reached since
 * the certificate was taken (issue 41: in a one-sphere-thick slab every sphere is a
 * candidate of the front and back walls, which none ever touches, and their tests were 30 %
 * of the step).
 *
 * The bound. For a plane wall whose unit normal is +-e_d (exactly: its other two components
 * are 0), the centre-plane distance of particle i is s = +-(x_d - p_d) (sinter_plane_distance,
 * the zero terms add nothing). At the certificate the search measured, per wall, the smallest
 * gap g = s - r over its candidate pairs. Later, s has changed by at most the particles'
 * travel along d since then (T_d: the explicit drift's largest step along d, summed over the
 * steps) plus the wall's own displacement along d (|p_d - p_d at the certificate|), so while
 *     g - T_d - |dp_d| > 1e-9 (S + T_d + |dp_d|)   (S: the largest |s| + r of its pairs)
 * none of its pairs touches (s >= r: the search's verdict "no contact"). The right side is
 * far above the rounding of these sums and differences (relative 1e-16 each, over at most
 * millions of steps), so the skipped verdicts are exactly those the test would give: the
 * contacts, and every result, keep their bits.
 *
 * The certificate holds while the candidate pairs (their build), the particles (layout,
 * writes, count) and the walls (count, kinds, normals' bits) are those it was taken with, and
 * while every position change since was a drift that reported its steps
 * (sinter_wall_skip_moved); any evaluation without such a drift first drops it, and the search
 * takes it again after a full test.
 */
#ifndef SINTER_WALL_SKIP_H
#define SINTER_WALL_SKIP_H

#include "contact/neighbors.h"
#include "core/core.h"
#include "particles/particles.h"
#include "walls/walls.h"

enum { SINTER_WALL_SKIP_MAX = 64 }; /* walls a certificate covers (more: none skipped) */

typedef struct sinter_wall_skip {
    int valid;              /* a certificate is held */
    int moved;              /* positions changed since the last search only by reported drifts */
    uint64_t build_id;      /* the candidate pairs' build */
    size_t pair_count;      /* ... and their number */
    uint64_t layout, write; /* the particles' layout_generation and write_generation */
    size_t particles;       /* their count */
    size_t wall_count;
    const sinter_walls *walls;
    double travel[3];               /* T_d: bound on any particle's travel along d since [m] */
    uint64_t mask;                  /* walls certified out of reach at the certificate */
    int axis[SINTER_WALL_SKIP_MAX]; /* d of a normal +-e_d, or -1 */
    double gap[SINTER_WALL_SKIP_MAX], scale[SINTER_WALL_SKIP_MAX]; /* g and S [m] */
    double p[SINTER_WALL_SKIP_MAX][3], n[SINTER_WALL_SKIP_MAX][3]; /* the wall then */
    uint32_t *active; /* the candidate pairs of the other walls, ascending */
    size_t active_count, active_capacity;
    int ascending; /* the pairs' particle indices ascend (as the search finds it) */
} sinter_wall_skip;

void sinter_wall_skip_free(sinter_ctx *ctx, sinter_wall_skip *s);

/* A drift moved every particle by at most sqrt(axis2[d]) along each axis d [m^2]. */
void sinter_wall_skip_moved(sinter_wall_skip *s, const double axis2[3]);

/* Start of an evaluation: the certificate is dropped unless only reported drifts moved the
 * particles since the last search. */
void sinter_wall_skip_begin(sinter_wall_skip *s);

/* The candidate pairs still to test (s->active, s->active_count) when the certificate holds
 * for these pairs, particles and walls now and every wall it certified is still out of reach:
 * returns 1; else 0 (test them all, then sinter_wall_skip_take). */
int sinter_wall_skip_holds(sinter_wall_skip *s, const sinter_pair_list *pairs,
                           const sinter_particles *ps, const sinter_walls *walls);

/* Take the certificate after a full test of `pairs` at the current positions (ascending: the
 * pairs' particle indices ascend). */
sinter_status sinter_wall_skip_take(sinter_ctx *ctx, sinter_wall_skip *s,
                                    const sinter_pair_list *pairs, const sinter_particles *ps,
                                    const sinter_walls *walls, int ascending);

#endif
