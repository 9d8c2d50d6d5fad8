/* The quasi-static stepper's state (private to quasistatic.c and qs_state.c). */
#ifndef SINTER_STEPPER_QS_STRUCT_H
#define SINTER_STEPPER_QS_STRUCT_H

#include "stepper/quasistatic.h"

/* A link's key: the ids of its two particles, the smaller first (issue 43). */
typedef struct sinter_qs_pair {
    uint64_t lo, hi;
} sinter_qs_pair;

/* Where a particle started (the reference of the shrinkage), by particle id. */
typedef struct sinter_qs_origin {
    uint64_t id;
    double x[3]; /* [m] */
} sinter_qs_origin;

struct sinter_qs {
    sinter_ctx *ctx;
    sinter_qs_options opt;
    sinter_qs_link *links;
    size_t count, capacity;
    sinter_qs_pair *keys; /* the id pairs of every link, sorted */
    size_t keys_capacity;
    /* The id order (qs_ids.c, issue 43): the stepper numbers the particles by ascending id
     * ("slots"), so that every order it makes (links, sums, the solve's) follows the ids and not
     * the caller's indices; the arrays marked "per slot" below are in that order. */
    uint64_t *slot_id;       /* per slot: its particle's id, ascending */
    uint32_t *index_of_slot; /* per slot: the caller's index of its particle */
    uint32_t *slot_of;       /* per caller index: its slot */
    size_t slots;            /* particles of the map */
    int slots_valid;         /* the map was made (for `slots` particles) */
    int slots_identity;      /* slot = index for every particle (ids ascending) */
    double *slot_x, *slot_r; /* positions and radii per slot, for the contact search */
    size_t slot_id_capacity, index_of_slot_capacity, slot_of_capacity, slot_x_capacity,
        slot_r_capacity;
    uint64_t *candidates; /* touching pairs found by the cell grid (qs_pairs.c), slot keys */
    size_t candidates_capacity;
    sinter_qs_near near; /* the pairs within a skin, kept between searches (qs_pairs.c), by slot */
    sinter_bonded_solver *solver;
    unsigned char *fixed; /* 6 per slot: principal-plane conditions (sec. 3.3) */
    double *f, *u;        /* 6 per slot: loads and displacements of the solve */
    size_t fixed_capacity, f_capacity, u_capacity;
    double (*saved)[SINTER_NECK_DOF]; /* strategy 1: the necks at t, and new states */
    double (*trial)[SINTER_NECK_DOF];
    size_t saved_capacity, trial_capacity;
    double *saved_hint; /* strategy 2: the necks' step hints at t */
    size_t saved_hint_capacity;
    sinter_beam *beams; /* the links' beams, contiguous for the solver, a and b their slots */
    size_t beams_capacity;
    uint32_t *component;           /* qs_floating.c: the link graph's components */
    unsigned char *component_held; /* and the axes planes hold them on */
    double *component_sums;        /* their centroids, mean rotations and displacements */
    size_t component_capacity, component_held_capacity, component_sums_capacity;
    sinter_neck_batch *batch;        /* strategy 3: grown necks */
    sinter_neck_batch *batch_young;  /* strategy 3: young necks (quasistatic.c) */
    sinter_neck_solver *pair_solver; /* strategy 3 with young_pairs: one neck at a time */
    size_t *batch_order;             /* young link indices first, then the grown ones */
    size_t batch_order_capacity;
    sinter_neck_state *batch_states;
    const sinter_neck_material **batch_materials;
    size_t batch_states_capacity, batch_materials_capacity;
    uint64_t layout_generation;     /* of the stepper's particles the links' indices are for */
    uint64_t population_generation; /* of the particles of the last step (adapter) */
    int population_known;           /* 0 for a new or restored stepper */
    size_t particles;               /* count the conditions were detected for (0: not yet) */
    double extent0[3];              /* initial extent of the centres */
    sinter_qs_origin *origins;      /* every particle of the first set-up, sorted by id */
    size_t origin_count, origin_capacity;
    double density0; /* sphere volume / bounding box of the spheres at the first set-up */
    double dt_next;
    int warned_coverage, warned_density; /* the validity guard warned (qs_validity.c) */
    double u_step; /* step of the displacements in u (0: none to start the next solve from) */
    uint64_t steps, rejected, pcg_iterations, substepped;
    sinter_neck_counters batch_counters[2]; /* strategy 3: CVODE work, young [0] and grown [1] */
};

/* ---- the id order (qs_ids.c) ---- */

/* qsort/bsearch order of sinter_qs_pair (lo, then hi). */
int sinter_qs_pair_compare(const void *a, const void *b);

/* The key of a link between particles of ids a and b. */
static inline sinter_qs_pair sinter_qs_pair_of(uint64_t a, uint64_t b)
{
    const sinter_qs_pair k = {a < b ? a : b, a < b ? b : a};
    return k;
}

/* The slot of id (the map must be made), or SIZE_MAX. */
size_t sinter_qs_slot_of_id(const sinter_qs *qs, uint64_t id);

/* Make the id order of n particles with ids (NULL: the index is the id) into qs's map (the
 * links are not touched). Errors: SINTER_ERR_NOMEM, SINTER_ERR_INVALID (a repeated id, or
 * more than 2^32 - 2 particles); the map is then left unmade. */
sinter_status sinter_qs_slots_make(sinter_qs *qs, size_t n, const uint64_t *ids);

/* Make the id order current for p: nothing when it is (an O(n) check), else sinter_qs_remap. */
sinter_status sinter_qs_follow_ids(sinter_qs *qs, const sinter_qs_particles *p);

/* Positions and radii per slot (qs->slot_x, slot_r; p's own arrays when slot = index). */
sinter_status sinter_qs_slot_geometry(sinter_qs *qs, const sinter_qs_particles *p, const double **x,
                                      const double **radius);

#endif /* SINTER_STEPPER_QS_STRUCT_H */
