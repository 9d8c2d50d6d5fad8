/* The quasi-static stepper's state (private to quasistatic.c and qs_state.c). */
#ifndef SINTER_STEPPER_QS_STRUCT_H
#define SINTER_STEPPER_QS_STRUCT_H

#include "stepper/quasistatic.h"

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
    uint64_t *keys; /* sorted a * n + b (a < b) of every link */
    size_t keys_capacity;
    uint64_t *candidates; /* touching pairs found by the cell grid (qs_pairs.c) */
    size_t candidates_capacity;
    sinter_qs_near near; /* the pairs within a skin, kept between searches (qs_pairs.c) */
    sinter_bonded_solver *solver;
    unsigned char *fixed; /* 6 per particle: principal-plane conditions (sec. 3.3) */
    double *f, *u;
    size_t fixed_capacity, f_capacity, u_capacity;
    double (*saved)[SINTER_NECK_DOF]; /* strategy 1: the necks at t, and new states */
    double (*trial)[SINTER_NECK_DOF];
    size_t saved_capacity, trial_capacity;
    double *saved_hint; /* strategy 2: the necks' step hints at t */
    size_t saved_hint_capacity;
    sinter_beam *beams; /* the links' beams, contiguous for the solver */
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
    uint64_t layout_generation; /* of the stepper's particles (adapter) */
    int layout_known;
    size_t particles;          /* count the conditions were detected for (0: not yet) */
    double extent0[3];         /* initial extent of the centres */
    sinter_qs_origin *origins; /* every particle of the first set-up, sorted by id */
    size_t origin_count, origin_capacity;
    double density0; /* sphere volume / bounding box of the spheres at the first set-up */
    double dt_next;
    int warned_coverage, warned_density; /* the validity guard warned (qs_validity.c) */
    double u_step; /* step of the displacements in u (0: none to start the next solve from) */
    uint64_t steps, rejected, pcg_iterations, substepped;
    sinter_neck_counters batch_counters[2]; /* strategy 3: CVODE work, young [0] and grown [1] */
};

#endif /* SINTER_STEPPER_QS_STRUCT_H */
