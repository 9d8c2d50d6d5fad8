/* The quasi-static stepper's state (private to quasistatic.c and qs_state.c). */
#ifndef SINTER_STEPPER_QS_STRUCT_H
#define SINTER_STEPPER_QS_STRUCT_H

#include "domain/domain.h"
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

/* A touching pair of the periodic search: slots sa < sb, B seen from A at x_B + image L. */
typedef struct sinter_qs_image_pair {
    uint32_t sa, sb;
    int32_t image[3];
} sinter_qs_image_pair;

/* A decomposed run (qs_domain.c, issue 43): the particles of a step are this subdomain's owned
 * ones, then ghosts of the other subdomains; this subdomain keeps the links whose smaller id it
 * owns. Bound by the adapter before each step (qs_domain_bind); `on` is 0 without domain
 * operations. */
typedef struct sinter_qs_domain {
    int on;
    sinter_domain *d;   /* the stepper's collective operations */
    size_t owned;       /* owned rows, first */
    size_t ghosts;      /* ghost rows, after them */
    const uint64_t *id; /* the set's ids (for the halos) */
    uint64_t size;      /* subdomains (exscan of 1; 0: not asked yet) */
    int split;          /* more than one subdomain: the split solve, the guard skipped */
    int started;        /* the global extents and green density taken (first step) */
    int repro;          /* the reproducible mode (qs_repro.h): exact sums, with or without `on` */
    int restored;       /* loaded from a portable global part (qs_portable.c): its links come
                         * with the records, so domain operations may step it */
    double *rows;       /* halo rows, (owned + ghosts) * width */
    size_t rows_capacity;
} sinter_qs_domain;

struct sinter_qs {
    sinter_ctx *ctx;
    sinter_qs_domain dom;
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
    /* Periodic axes (qs_periodic.c) */
    int periodic[3];     /* 1 for a periodic axis */
    double cell_lo[3];   /* the cell's lower corner [m] (fixed: the cell shrinks towards it) */
    double cell_len[3];  /* its lengths now [m] */
    double cell_len0[3]; /* at the first step [m] (the reference of the cell's strain) */
    int cell_started;    /* cell_len0 taken */
    double eps[3];       /* the step's cell strain increment (qs_cell_strain) */
    double *xi_affine;   /* per link: the approach the cell's strain gives it [m] */
    size_t xi_affine_capacity;
    sinter_qs_image_pair *image_pairs; /* the periodic contact search's pairs */
    size_t image_pairs_capacity;
    double *ext_x, *ext_r; /* the search's spheres: the slots, then their images */
    uint32_t *ext_owner;   /* per sphere of the search (from n on, the images): its slot */
    int32_t *ext_image;    /* and 3 cell offsets */
    size_t ext_x_capacity, ext_r_capacity, ext_owner_capacity, ext_image_capacity;
    /* Per-particle state imported with the records (qs_portable.c), until the next remap */
    uint64_t *carried_id;
    struct sinter_qs_carried *carried;
    size_t carried_count, carried_id_capacity, carried_capacity;
};

/* The imported per-particle state given to the slots of the map just made (qs_portable.c):
 * when it covers every slot and the stepper was set up, the plane conditions (and the last
 * displacements when all came) are taken and 1 is returned; 0 otherwise. Then dropped. */
int sinter_qs_carried_apply(sinter_qs *qs);

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

/* ---- periodic axes (qs_periodic.c) ---- */

/* 1 when some axis is periodic. */
static inline int sinter_qs_periodic_on(const sinter_qs *qs)
{
    return qs->periodic[0] || qs->periodic[1] || qs->periodic[2];
}

/* Where B is as A's neighbour: x_B + image L (x_B itself without periodic axes). */
static inline void sinter_qs_image_of(const sinter_qs *qs, const int32_t image[3],
                                      const double xb[3], double out[3])
{
    for (int d = 0; d < 3; ++d)
        out[d] = image[d] != 0 ? xb[d] + (double)image[d] * qs->cell_len[d] : xb[d];
}

/* The touching pairs of the n slots (positions x, radii r per slot) across the periodic faces
 * as well: qs->image_pairs[0..*count), sorted by (sa, sb). Errors: SINTER_ERR_NOMEM,
 * SINTER_ERR_INVALID (a non-finite position), SINTER_ERR_UNSUPPORTED (a period under twice the
 * touching distance: a pair could touch through two images). */
sinter_status sinter_qs_periodic_pairs(sinter_qs *qs, size_t n, const double *x, const double *r,
                                       size_t *count);

/* The step's cell strain increment qs->eps from the links' free approaches over the step
 * (their necks at t in qs->saved; 0 along the axes that are not periodic, and without
 * qs_cell_strain), and each link's approach from it in qs->xi_affine; the loads that strain
 * puts on the links taken off f (6 per slot). */
sinter_status sinter_qs_cell_strain(sinter_qs *qs, const sinter_qs_particles *p, double *f);

/* The centre distance of link k after the step (u: the solve's displacements per slot, the
 * cell's strain qs->eps on top), squared; positions at t. */
double sinter_qs_cell_distance2(const sinter_qs *qs, const sinter_qs_particles *p, size_t k,
                                const double *u);

/* The cell's strain applied to positions at t: every particle moved by -eps (x - lo) along
 * each periodic axis, and the cell's lengths by (1 - eps). */
void sinter_qs_cell_move(sinter_qs *qs, const sinter_qs_particles *p);

/* Particles outside the cell along a periodic axis moved in by a period, the images of their
 * links following (the links' vectors unchanged). */
void sinter_qs_cell_wrap(sinter_qs *qs, const sinter_qs_particles *p);

#endif /* SINTER_STEPPER_QS_STRUCT_H */
