/*
 * Ghost particles (issues 38 and 43): copies of owned particles stored after them in the set
 * (owned rows [0, count - ghost_count), ghosts after). A ghost is never integrated for its own
 * sake: every step its owner's state is copied over it (the forward halo), and it only serves
 * as the far end of the pairs of owned particles. There are no ghost-ghost pairs and no ghost
 * wall contacts (contact/neighbors.c).
 *
 * The one transport built in is the periodic one: along each periodic axis a particle within
 * the ghost cut-off of a face has an image, shifted by the period, beyond the opposite face
 * (LAMMPS does periodic images the same way, as ghost atoms refreshed by its forward
 * communication). Because both ends of a pair across a periodic face are owned by the same
 * set, the pair is evaluated once, from its smaller-id end (which is owned), and the ghost's
 * force, moment and heat power are added back to its owner (the reverse halo): one history per
 * pair, keyed by the two particles' ids as for any other pair, so a contact keeps its history
 * when one of its particles wraps across the face.
 */
#ifndef SINTER_GHOSTS_H
#define SINTER_GHOSTS_H

#include "core/core.h"
#include "particles/particles.h"

typedef struct sinter_ghosts {
    int periodic[3]; /* 1 for a periodic axis */
    double lo[3];    /* the periodic cell along each periodic axis [m] */
    double hi[3];
    size_t count; /* image rows made by the last rebuild */
    /* with domain operations (sinter_ghosts_append): the host's ghost rows that come before
     * the images in the set's ghost block; 0 without them */
    size_t host;
    size_t capacity;
    uint32_t *owner; /* the owned particle each ghost copies */
    double *shift;   /* 3 per ghost: ghost position - owner position [m] */
    double *saved;   /* 6 per ghost: force and moment kept across a body force's evaluation */
    size_t saved_capacity;
    uint64_t layout; /* the set's layout_generation right after that rebuild */
    int built;
    /* 1 while a step iterates on positions measured from its start (the staggered stepper):
     * a rebuild then makes the images without wrapping the owned particles, which
     * sinter_ghosts_wrap does between steps (a particle a step's motion outside the cell still
     * gets the images it needs: the test below is by distance to the faces) */
    int hold;
} sinter_ghosts;

void sinter_ghosts_free(sinter_ctx *ctx, sinter_ghosts *g);

/* Room for `count` ghosts in the table (a checkpoint's restore grows it before it applies). */
sinter_status sinter_ghosts_reserve(sinter_ctx *ctx, sinter_ghosts *g, size_t count);

/* 1 when some axis is periodic. */
int sinter_ghosts_on(const sinter_ghosts *g);

/* Axis 0..2 periodic on [lo, hi) (hi > lo, finite); lo = hi = 0 makes it non-periodic. */
sinter_status sinter_ghosts_set_periodic(sinter_ctx *ctx, sinter_ghosts *g, int axis, double lo,
                                         double hi);

/* 1 while the ghost rows of ps are the ones the last rebuild made (no particle was added,
 * removed or reordered since). */
int sinter_ghosts_current(const sinter_ghosts *g, const sinter_particles *ps);

/* At a neighbour-list rebuild: the old ghost rows dropped, owned particles wrapped into the
 * periodic cell, and a ghost made for every image within `cutoff` [m] of the cell (the distance
 * within which a particle can meet one across the face before the next rebuild: 2 r_max +
 * skin). Refused when a period is under twice the cut-off (a particle could then meet two
 * images of one other). `x_old` (3 per particle, or NULL): positions of an earlier state,
 * shifted with their particle's wrap, so that x - x_old stays the displacement. */
sinter_status sinter_ghosts_rebuild(sinter_ghosts *g, sinter_particles *ps, double cutoff,
                                    double *x_old);

/* The periodic transport beside the host's ghosts (domain operations, a decomposition that
 * does not cut a periodic axis): the owned particles were wrapped before the host's
 * redistribution (sinter_ghosts_wrap_with), so the host's ghosts are inside the cell too; the
 * images of every row, owned or the host's ghost, within `cutoff` of a face are appended after
 * the host's ghost rows (g->host of them). An image of an owned particle is the periodic kind
 * (its pairs evaluated once, its force added back to its owner by sinter_ghosts_reverse); an
 * image of a host's ghost is a ghost of another subdomain (newton off, its force discarded). */
sinter_status sinter_ghosts_append(sinter_ghosts *g, sinter_particles *ps, double cutoff);

/* The number of image rows at the end of ps's ghost block: g->count while they are the rows
 * the last rebuild or append made (the layout did not change since), else 0. */
size_t sinter_ghosts_images(const sinter_ghosts *g, const sinter_particles *ps);

/* Owned particles wrapped into the cell with `x_old` (3 per particle, or NULL) shifted alike,
 * as sinter_ghosts_rebuild does; returns the number of particles moved. */
size_t sinter_ghosts_wrap_with(sinter_ghosts *g, sinter_particles *ps, double *x_old);

/* Owned particles outside the periodic cell wrapped into it, as a rebuild does; returns the
 * number of particles moved (then the ghost rows are out of date: g->built is cleared). */
size_t sinter_ghosts_wrap(sinter_ghosts *g, sinter_particles *ps);

/* Ghost rows of another per-particle array of 3 doubles (the stepper's copy of an earlier
 * state) made as the rebuild made them in the set: the owner's row, plus the shift when
 * `shifted` (positions). */
void sinter_ghosts_copy_rows(const sinter_ghosts *g, const sinter_particles *ps, double *a,
                             int shifted);

/* The forward halo: every ghost takes its owner's position (plus the shift), velocity, spin,
 * rotation, temperature and current. */
void sinter_ghosts_forward(const sinter_ghosts *g, sinter_particles *ps);

/* The reverse halo: every ghost's force, moment and heat power added to its owner's, in ghost
 * order (the same order every run), then zeroed. */
void sinter_ghosts_reverse(const sinter_ghosts *g, sinter_particles *ps);

/* A body force model (one that does not use contacts) acts on the owners only: the ghost rows'
 * force and moment are saved before its evaluation and put back after it, so that they keep
 * what the pairs put there (sinter_ghosts_reverse). */
sinter_status sinter_ghosts_save_rows(sinter_ctx *ctx, sinter_ghosts *g,
                                      const sinter_particles *ps);
void sinter_ghosts_restore_rows(const sinter_ghosts *g, sinter_particles *ps);

/* The distance within which ghosts are needed: 2 r_max (over the owned particles) + skin. */
double sinter_ghosts_cutoff(const sinter_particles *ps, double skin);

#endif
