/*
 * Candidate pairs within a Verlet skin, found with a uniform cell grid
 * (docs/models.md, "Contact geometry"). A pair list is valid until some particle moved more
 * than half the skin, or a wall moved so far that particle and wall together
 * could have closed the skin.
 */
#ifndef SINTER_NEIGHBORS_H
#define SINTER_NEIGHBORS_H

#include "core/core.h"
#include "particles/particles.h"
#include "walls/walls.h"

#define SINTER_NO_PAIR UINT32_MAX

/* Candidate pairs: particle i with particle j (i < j) or with wall j. */
typedef struct sinter_pair_list {
    size_t count;
    size_t capacity;
    uint32_t *i;
    uint32_t *j;
    uint64_t *key_i; /* persistent particle id of i */
    uint64_t *key_j; /* persistent id of j, or the wall index */
    uint32_t
        *from; /* after a build: index of the same pair in the previous list, or SINTER_NO_PAIR */
    /* particle-particle lists only, made on demand (sinter_pairs_adjacency): for each
     * particle its pairs in ascending pair index (both roles), adj_pair[adj_start[p] ..
     * adj_start[p + 1]); lets threads sum forces per particle in exactly the serial order.
     * Valid while adj_build is build_id */
    uint32_t *adj_start;
    size_t adj_start_capacity;
    uint32_t *adj_pair;
    size_t adj_pair_capacity;
    uint64_t adj_build;
    /* this content's identity (sinter_unique_id), set by each completed build or restore; 0
     * while a build is under way. A contact list found among these pairs can tell by it that
     * its pairs did not change since (sinter_contacts_find_pp_lean) */
    uint64_t build_id;
    /* 1 when the build sorted the pairs by their keys (the reproducible mode:
     * contact/canonical_order.h); such a list is never partitioned (contact/chunks.h), so that
     * every particle receives its terms in that order on any number of threads */
    int canonical;
} sinter_pair_list;

typedef struct sinter_neighbors {
    sinter_ctx *ctx;
    double skin;
    /* [m] particle pairs closer than skin + reach (gap) at a build are listed, so that every
     * pair apart by less than `reach` is a candidate until the list is stale (the staleness
     * test reads the skin alone); 0 (the default): the contact search's pairs only. A heat law
     * between pairs apart sets it (heat/gas_gap.h) */
    double reach;
    /* the reproducible mode (stepper option "reproducible"): each build sorts its pairs by
     * their keys (contact/canonical_order.h), in order_scratch */
    int canonical;
    void *order_scratch;
    size_t order_scratch_capacity;
    int both_sides; /* ghosts of other subdomains: a pair is kept when either end is owned
                       (newton off; domain/domain.h), not only its smaller-id end */
    /* periodic images in a decomposed run (stepper/domain_periodic.c): rows [image_first,
     * image_first + image_count) are images, image_owner[k] the row each copies; a pair whose
     * smaller-id end is an image of an owned particle goes (its twin from that owned
     * particle is kept), even with both_sides */
    size_t image_first, image_count;
    const uint32_t *image_owner;
    int built;
    sinter_pair_list pp;     /* particle-particle */
    sinter_pair_list pw;     /* particle-wall */
    sinter_pair_list old_pp; /* previous lists, kept to carry history over */
    sinter_pair_list old_pw;
    double *x_ref; /* positions at the last build, 3 per particle */
    size_t ref_capacity;
    double *wall_ref; /* n . p of each wall at the last build */
    size_t wall_ref_capacity;
    uint64_t layout_generation;
    size_t wall_count;
    /* a build with a wall that is not a plane: per particle and wall (i nw + k) whether it is
     * a candidate (the counting pass's verdict, which the writing pass reads), and for a mesh
     * the triangle its last search ended on (sinter_wall_contact_hinted), kept across builds */
    uint8_t *wall_near;
    size_t wall_near_capacity;
    uint32_t *wall_hint;
    size_t wall_hint_capacity;
    /* scratch of the cell grid */
    uint32_t *cell_start;
    size_t cell_capacity;
    uint32_t *cell_items;
    size_t items_capacity;
    uint32_t *cell_counts; /* per range of particles, per cell: the threaded counting sort */
    size_t cell_counts_capacity;
    uint32_t *hash; /* open-addressing table of old pair indices */
    size_t hash_capacity;
    uint32_t *scan; /* per-thread segments of the threaded build */
    size_t scan_capacity;
    /* largest squared displacement since the build, measured by the integrator, for the
     * next staleness test only; valid while moved_valid and the particles' generations match */
    double moved2;
    int moved_valid;
    uint64_t moved_layout, moved_write;
    /* an upper bound on the largest displacement since the build [m]: the last exact measure
     * (sinter_neighbors_set_moved) plus each later step's largest displacement
     * (sinter_neighbors_add_step); valid while bound_valid and the particles' generations
     * match */
    double moved_bound;
    int bound_valid;
    uint64_t bound_layout, bound_write;
    /* pairs the next build keeps at any distance (bonds that hold in tension), by smaller
     * particle index a: the larger ones keep_j[keep_start[a] .. keep_start[a + 1]); none while
     * keep_count is 0 (sinter_neighbors_keep) */
    uint32_t *keep_start;
    size_t keep_start_capacity;
    uint32_t *keep_j;
    size_t keep_j_capacity;
    size_t keep_count;
} sinter_neighbors;

/* Threads a context allows (its setting; 0 means all available); contacts.c. */
int sinter_threads_allowed(const sinter_ctx *ctx);

/* Threads to use now: those the explicit stepper chose for the step being taken
 * (stepper/thread_choice.h), else the context's allowed count; contacts.c. */
int sinter_threads(const sinter_ctx *ctx);

void sinter_neighbors_init(sinter_neighbors *nb, sinter_ctx *ctx, double skin);
void sinter_neighbors_free(sinter_neighbors *nb);

/* The integrator measured the largest squared displacement since the build while it moved
 * the particles: the next staleness test uses it instead of a pass of its own. */
void sinter_neighbors_set_moved(sinter_neighbors *nb, const sinter_particles *ps, double moved2);
void sinter_neighbors_clear_moved(sinter_neighbors *nb);

/* 1 when the displacement bound holds for ps and is under a quarter of the skin: then the
 * integrator may report just the step's largest displacement (sinter_neighbors_add_step)
 * instead of measuring against x_ref (issue 9: 24 bytes a particle less to read). */
int sinter_neighbors_bound_holds(const sinter_neighbors *nb, const sinter_particles *ps);
/* A step in which no particle moved more than `step` [m]: the bound grows by it and, while
 * it stays under a quarter of the skin, answers the next staleness test (no particle can have
 * moved half the skin); beyond, the test measures. */
void sinter_neighbors_add_step(sinter_neighbors *nb, const sinter_particles *ps, double step);
/* The particles were put back at positions of an earlier state (a rejected step's rollback):
 * what was measured or bounded of the undone positions says nothing of these, so the next
 * staleness test and the next step measure against x_ref again. */
void sinter_neighbors_positions_restored(sinter_neighbors *nb);

/* 1 when the lists must be rebuilt before the next evaluation. */
int sinter_neighbors_stale(const sinter_neighbors *nb, const sinter_particles *ps,
                           const sinter_walls *walls);

/* The per-particle adjacency of particle-particle list l over n particles, made unless it
 * is current (adj_build): only the laws that sum per particle on threads read it (rolling
 * resistance), so a build does not make it (issue 9: 20 % of a build). */
sinter_status sinter_pairs_adjacency(sinter_ctx *ctx, sinter_pair_list *l, size_t n);

/* Pairs (ki[k], kj[k]), k < count, of particles of ps's current layout that the next build
 * lists as candidates whatever their distance (count 0: none); a pair the cell search finds
 * anyway is listed once. */
sinter_status sinter_neighbors_keep(sinter_neighbors *nb, const sinter_particles *ps,
                                    const uint32_t *ki, const uint32_t *kj, size_t count);

/* Rebuild both lists; pp.from and pw.from map each new pair to its old index. */
sinter_status sinter_neighbors_build(sinter_neighbors *nb, const sinter_particles *ps,
                                     const sinter_walls *walls);

#endif
