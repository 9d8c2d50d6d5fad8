/*
 * The quasi-static sintering stepper (seed 001 = Ivannikov et al. 2022, sec. 2-3, fig. 6-7):
 * every contact is a bonded link carrying a 7DOF neck (src/neck) and a beam (src/bonded). One
 * global step of length dt:
 *   1. advance every neck with the seed's RK4 and step-doubling error control,
 *        strategy 1 (sec. 3.3, eq. 45-47): one step for all pairs, the whole step rejected and
 *          dt / alpha when any pair misses the tolerance, dt alpha when all are within 0.1 of it;
 *        strategy 2: dt is kept and each pair sub-steps on its own; the next dt grows by alpha
 *          when fewer than 5 % of the pairs needed sub-steps and shrinks when more than 15 % did;
 *        strategy 3 (not in the seed; the default): the necks in CVODE; with young_pairs = 0
 *          all pairs in one CVODE system (neck/batch.c, shared adaptive steps, every pair
 *          within the tolerance), with young_pairs = 1 (the default) each young neck (x/R <
 *          0.05) on its own CVODE steps (neck/cvode_driver.c); the global dt then only limits the
 *          mechanical increment: it grows by alpha while the largest link approach of a step
 *          stays below max_strain L0 and shrinks by alpha above it (the small-increment
 *          assumption of sec. 2.4); with strain_fraction > 0 it grows while at most that
 *          fraction of the links reached max_strain L0 (a few links the network compresses
 *          faster than their neck no longer hold the step back; 0.01 gives strategy 2's
 *          shrinkage error and cost over a whole copper run, with twice its neck error at the
 *          99th percentile, tests/bench/RESULTS.md); with
 *          grown_rk4 = 1 (the default) only the young necks stay in CVODE and the grown ones
 *          take strategy 2's per-pair RK4 sub-steps, which cost less than restarting CVODE
 *          every global step once the global step is shorter than a neck's own step (about
 *          half over a whole run, RESULTS.md, issue 45); the defaults (strain_fraction 0.01,
 *          grown_rk4 1, young_pairs 1) are the whole-run setting of RESULTS.md, issue 45;
 *   2. turn the approach of each neck into a sintering force (eq. 13, 17);
 *   3. solve K u = f (eq. 40) with PCG under the principal-plane conditions of sec. 3.3;
 *   4. move and turn the particles, and share the axial compression of each link between y4 and
 *      y7 (eq. 41-44);
 *   5. turn new touching pairs into links with a fresh neck (docs/7dof.md §4).
 * The core (sinter_qs_*) works on borrowed particle arrays; sinter_quasistatic_* adapt it to a
 * sinter_stepper. Links are keyed by the ids of their particles and every order of the step
 * (links, sums, the solve) is an order of ids (qs_ids.c, issue 43), so a reordering of the
 * particles in memory does not change a bit of the results.
 */
#ifndef SINTER_STEPPER_QUASISTATIC_H
#define SINTER_STEPPER_QUASISTATIC_H

#include "bonded/beam.h"
#include "neck/neck.h"
#include "sinter_submodel.h"

typedef struct sinter_qs_options {
    int strategy;             /* 1 or 2 (sec. 3.3, fig. 7), or 3: CVODE batch (below) */
    double dt_initial;        /* first global step [s] */
    double dt_min, dt_max;    /* [s]; below dt_min a step fails */
    double alpha;             /* step factor of eq. 45, 47 */
    double error_limit;       /* eps_lim of eq. 46: weighted RK4 local error per step */
    double grow_fraction;     /* strategy 2: grow when fewer pairs than this sub-stepped (0.05) */
    double shrink_fraction;   /* strategy 2: shrink when more than this did (0.15) */
    double contact_tolerance; /* new contact if distance < (r_a + r_b)(1 + this) */
    double plane_tolerance;   /* on a principal plane if x_d - r < this r */
    double solve_rtol;        /* K u = f: true residual |f - K u| relative to |f| (1e-7) */
    double rtol;              /* relative accuracy of the necks (error weights, neck.h) */
    double epsilon, h0_ratio; /* fresh neck, docs/7dof.md §4 */
    double max_strain;        /* strategy 3: largest approach per step / L0 before dt shrinks */
    double strain_fraction;   /* strategy 3: fraction of the links allowed to reach max_strain
                                 while dt grows (0: none) */
    double grown_rk4;         /* strategy 3: 1 advances the grown necks by strategy 2's RK4 */
    double young_pairs;       /* strategy 3: 1 advances each young neck in CVODE on its own
                                 steps instead of one batch with shared steps */
    double new_contacts;      /* 1: contacts made during the run become links (sec. 3.3); 0:
                                 only the contacts of the first step (a diagnostic: the
                                 titanium packing's shrinkage, RESULTS.md, session 3) */
    double neck_stiffness;    /* 0: the links' section is the full pi R_m^2 (eq. 36, constant);
                                 1: the neck's own, pi x^2 (the seed's stated extension, sec.
                                 2.4): axial and shear stiffness and the sintering force scale
                                 by (x/R_m)^2, bending and torsion by (x/R_m)^4 */
    double validity;          /* the validity guard (docs/7dof.md §2.6, qs_validity.c): 0 off,
                                 1 a warning (default), 2 SINTER_ERR_DOMAIN */
    double neck_law;          /* the pair law of step 1 (qs_law.c): 0 the 7DOF model (default,
                                 by the strategy), 1 the classic grain-boundary diffusion law
                                 (neck/gb_law.c), 2 the host law below */
    double cell_strain;       /* periodic axes (qs_periodic.c): 1 (default) the cell follows the
                                 links' mean approach (free sintering of a representative
                                 volume), 0 the cell keeps its size (constrained sintering) */
    sinter_neck_law_callbacks host_law; /* neck_law 2 (sinter_stepper_set_neck_law) */
    void *host_law_user;
} sinter_qs_options;

/* strategy 3, dt 1e-6 s, dt_min 1e-12 s, dt_max 10 s (docs/7dof.md §5), alpha 1.5, eps_lim 1,
 * 5 % / 15 %, contact 1e-9, plane 1e-6, solve 1e-7, rtol 1e-6, epsilon 0.01, h0 1.5 x0,
 * max_strain 7e-5, strain_fraction 0.01, grown_rk4 1, young_pairs 1. */
void sinter_qs_options_default(sinter_qs_options *opt);

/*
 * Option keys (for sinter_stepper_set_option on the quasi-static kind): "qs_strategy",
 * "qs_dt_min", "qs_dt_max", "qs_alpha", "qs_error_limit", "qs_grow_fraction",
 * "qs_shrink_fraction", "qs_contact_tolerance", "qs_plane_tolerance", "qs_solve_rtol",
 * "qs_rtol", "qs_epsilon", "qs_h0_ratio", "qs_max_strain", "qs_strain_fraction" (in [0, 1]),
 * "qs_grown_rk4" and "qs_young_pairs" (0 or 1; any value above 0 means 1), "qs_new_contacts" (1,
 * the default: links for contacts made during the run; 0: none after the first step; any value
 * above 0 means 1), "qs_neck_stiffness" (0, the default: constant full-section links; 1: the
 * section of the neck, pi x^2; any value above 0 means 1), "qs_validity" (0, 1 or 2: the validity
 * guard off, a warning (the default) or an error, docs/7dof.md §2.6), "qs_neck_law" (0, the
 * default: the 7DOF model; 1: the classic grain-boundary diffusion law; 2: the host law of
 * sinter_stepper_set_neck_law; the strategies apply to the 7DOF model only, the other laws
 * advance every pair over the global step, which follows strategy 3's strain rule),
 * "qs_cell_strain" (1, the default: a periodic cell follows the links' mean approach; 0: it keeps
 * its size; any value above 0 means 1; qs_periodic.c). Set checks the value (the
 * whole set is validated again when the stepper is created). Errors: SINTER_ERR_NOT_FOUND (unknown
 * key; the message lists the keys), SINTER_ERR_INVALID (value out of range or not finite, or
 * qs_dt_min above qs_dt_max).
 */
sinter_status sinter_qs_option_set(sinter_qs_options *opt, sinter_ctx *ctx, const char *key,
                                   double value);
sinter_status sinter_qs_option_get(const sinter_qs_options *opt, sinter_ctx *ctx, const char *key,
                                   double *value);

/* Per material: the neck data and the elastic constants of the links. */
typedef struct sinter_qs_material {
    sinter_neck_material neck;
    double youngs;  /* E [Pa] */
    double poisson; /* nu [-] */
} sinter_qs_material;

/* Borrowed particle arrays (particle-major, 3 per particle for x and rot). */
typedef struct sinter_qs_particles {
    size_t count;
    double *x;               /* centres [m], moved by a step */
    double *rot;             /* total rotation vectors, composed by a step (may be NULL) */
    const double *radius;    /* [m] */
    const int32_t *material; /* index into materials (NULL: all 0) */
    const uint64_t *id;      /* stable particle ids (NULL: the index is the id) */
    const sinter_qs_material *materials;
} sinter_qs_particles;

typedef struct sinter_qs_link {
    sinter_beam beam;
    sinter_neck_state neck;
    double rm;                     /* R_m (eq. 16) [m] */
    double youngs;                 /* E of the link [Pa] */
    sinter_neck_material material; /* the neck data (of particle A), copied */
    int substepped;                /* strategy 2: the last advance needed sub-steps */
    uint64_t id_a, id_b;           /* particle ids of a and b (id_a < id_b for the links made
                                      since issue 43: A is the particle of the smaller id); the
                                      beam's a and b are the caller's indices, set from these
                                      after a reordering (sinter_qs_remap) */
    double born;                   /* time the link was made [s] (its age: neck.time - born) */
    int32_t image[3]; /* periodic axes (qs_periodic.c): B as A's neighbour is the image of B at
                         x_B + image * L, L the cell's lengths; 0 without periodic axes */
} sinter_qs_link;

/* Outputs (seed 001 sec. 4; docs/7dof.md §5). */
typedef struct sinter_qs_stats {
    double time;    /* [s] */
    double dt_next; /* proposal for the next global step [s] */
    size_t particles, links;
    double neck_mean, neck_min, neck_max; /* y1 [m] */
    double neck_ratio_mean;               /* mean y1 / min(R_A, R_B) */
    double shrinkage[3];     /* homogeneous strain of the linked centres along x, y, z (see
                                quasistatic.c: shrinkage()) */
    double relative_density; /* initial sphere volume / box of the spheres, over the box's
                                shrinkage (1 - s_x)(1 - s_y)(1 - s_z) */
    double coordination;     /* 2 links / particles */
    uint64_t steps, rejected, pcg_iterations, substepped_pairs;
} sinter_qs_stats;

typedef struct sinter_qs sinter_qs;

sinter_status sinter_qs_create(sinter_qs **out, sinter_ctx *ctx, const sinter_qs_options *opt);
void sinter_qs_destroy(sinter_qs *qs);

/*
 * One accepted global step from time t of at most h (strategy 1 may take less after rejections;
 * *taken gets it) at the temperatures of `schedule`. The first call detects the initial links
 * and the principal-plane conditions. Errors: SINTER_ERR_NOMEM, SINTER_ERR_NOT_CONVERGED (PCG,
 * or no step above dt_min met the tolerance), SINTER_ERR_DOMAIN, SINTER_ERR_INVALID.
 */
sinter_status sinter_qs_step(sinter_qs *qs, const sinter_qs_particles *p,
                             const sinter_neck_schedule *schedule, double t, double h,
                             double *taken);

/*
 * Step 1 with a pair law other than the 7DOF model (qs_law.c): every link's pair advanced
 * freely over [t, t + h] by the grain-boundary diffusion law (neck_law 1) or the host law
 * (neck_law 2). On error every link keeps its state at t. Errors: SINTER_ERR_NOMEM,
 * SINTER_ERR_CALLBACK, SINTER_ERR_DOMAIN, SINTER_ERR_INVALID (neck_law 2 without a host law).
 */
sinter_status sinter_qs_advance_law(sinter_qs *qs, const sinter_qs_particles *p,
                                    const sinter_neck_schedule *schedule, double t, double h);
/* Copy opt's neck_law and host law into a stepper already made (sinter_stepper_set_neck_law). */
void sinter_qs_set_host_law(sinter_qs *qs, const sinter_qs_options *opt);

/*
 * The validity guard after a step to time t (qs_validity.c, docs/7dof.md §2.6): the necks of a
 * particle cover more than SINTER_NECK_COVERAGE_LIMIT of its surface (they impinge), or the
 * relative density passes SINTER_NECK_DENSITY_LIMIT. Once per quantity a warning (validity 1)
 * or SINTER_ERR_DOMAIN naming the quantity and the time (validity 2).
 */
sinter_status sinter_qs_check_validity(sinter_qs *qs, const sinter_qs_particles *p, double t);

/* Scale of a link's section area against the full pi R_m^2 (eq. 36a): 1, or (x/R_m)^2 with
 * qs_neck_stiffness. */
double sinter_qs_section_scale(const sinter_qs_options *opt, const sinter_qs_link *l);

/* Why a link's numbers (neck state, lengths, stiffnesses, times: a checkpoint's or an imported
 * record's) cannot be used, or NULL when they can (qs_state.c). */
const char *sinter_qs_link_numbers_wrong(const sinter_qs_link *l);

/* March from t0 to t1 with the adaptive global step (convenience for tests and drivers). */
sinter_status sinter_qs_run(sinter_qs *qs, const sinter_qs_particles *p,
                            const sinter_neck_schedule *schedule, double t0, double t1);

/*
 * Follow a reordering, addition or removal of particles (qs_ids.c): ids[0..n) are the ids now at
 * each index (the links remember ids). A reordering of the same particles changes nothing but
 * the indices the links name: the stepper keeps everything else per particle in id order, and
 * continues with the same bits. With other particles, links to a removed particle are dropped
 * and the plane conditions are detected again at the next step (the initial extents are kept);
 * the links of an id removed and given again stay (links follow ids: a particle that leaves and
 * comes back keeps them).
 * sinter_qs_step does this itself when p's ids are not those of the last step. Errors:
 * SINTER_ERR_NOMEM, SINTER_ERR_INVALID (a repeated id; the links are unchanged).
 */
sinter_status sinter_qs_remap(sinter_qs *qs, size_t n, const uint64_t *ids);

/* qsort/bsearch order of uint64_t keys (and of structs that start with one). */
int sinter_qs_key_compare(const void *a, const void *b);

/*
 * The touching pairs of n spheres (centre distance < (r_a + r_b)(1 + tolerance)) as sorted keys
 * a n + b with a < b, found with a cell grid (qs_pairs.c); with margin > 0 [m] the pairs closer
 * than (r_a + r_b)(1 + tolerance) + margin. *keys grows with sinter_grow.
 * Errors: SINTER_ERR_NOMEM, SINTER_ERR_INVALID (a non-finite position).
 */
sinter_status sinter_qs_touching_pairs(sinter_ctx *ctx, size_t n, const double *x,
                                       const double *radius, double tolerance, double margin,
                                       uint64_t **keys, size_t *capacity, size_t *count);

/*
 * The pairs within a margin (a skin) of touching, kept from one search to the next while no
 * sphere has moved by more than 0.45 of the skin since it and no radius and no count changed:
 * a pair that touches now was then closer than touching plus the skin. The quasi-static
 * stepper's spheres move a small fraction of a radius a step, so the grid search runs once in
 * many steps. valid 0: search at the next call.
 */
typedef struct sinter_qs_near {
    uint64_t *keys; /* the pairs within the skin, sorted */
    size_t count, keys_capacity;
    double *x0, *r0; /* centres and radii at the search */
    size_t x0_capacity, r0_capacity;
    size_t n;
    double tolerance, skin;
    int valid;
} sinter_qs_near;

void sinter_qs_near_free(sinter_ctx *ctx, sinter_qs_near *near);

/* What sinter_qs_touching_pairs gives (the same keys), from near's pairs when they are valid
 * for the spheres; *searched (may be NULL) is 1 if the grid search ran. */
sinter_status sinter_qs_touching_pairs_near(sinter_ctx *ctx, sinter_qs_near *near, size_t n,
                                            const double *x, const double *radius, double tolerance,
                                            uint64_t **keys, size_t *capacity, size_t *count,
                                            int *searched);

/*
 * Checkpoint state (qs_state.c): the bytes sinter_qs_state_save writes (links, plane
 * conditions, extents, next step, counters; per-particle records in order of ascending id).
 * sinter_qs_state_restore builds a new stepper state from such bytes for n particles with ids
 * (8 bytes each, may be unaligned; NULL: the index is the id), in any order: the links find
 * their particles by id. by_index: the bytes come from a checkpoint of version 3 to 10, whose
 * per-particle records follow the particles' indices. Options opt; on SINTER_ERR_CORRUPT *why
 * says what is wrong, and nothing is made.
 */
size_t sinter_qs_state_size(const sinter_qs *qs);
void sinter_qs_state_save(const sinter_qs *qs, unsigned char *out);
sinter_status sinter_qs_state_restore(sinter_qs **out, sinter_ctx *ctx,
                                      const sinter_qs_options *opt, const unsigned char *data,
                                      size_t bytes, size_t n, const void *ids, int by_index,
                                      int with_cell, const char **why);

/*
 * Periodic axes (qs_periodic.c): axis d periodic on [lo[d], hi[d]) when periodic[d] is 1. Links
 * across a face join a particle to the image of another; with qs_cell_strain the cell shrinks
 * with the links' mean approach. Set before the first step, or between steps (the links keep
 * their images, which scale with the cell). Errors: SINTER_ERR_INVALID (hi <= lo or not
 * finite).
 */
sinter_status sinter_qs_set_cell(sinter_qs *qs, const int periodic[3], const double lo[3],
                                 const double hi[3]);
/* The periodic axes and the cell now (hi = lo + the current lengths); 0 when no axis is
 * periodic. */
int sinter_qs_get_cell(const sinter_qs *qs, int periodic[3], double lo[3], double hi[3]);

/* The links (count in *n). */
const sinter_qs_link *sinter_qs_links(const sinter_qs *qs, size_t *n);

/* Statistics of the current state. */
void sinter_qs_stats_get(const sinter_qs *qs, const sinter_qs_particles *p, sinter_qs_stats *out);

/* ---------------------------------------------------------------------------------------- */
/* Adapter to a sinter_stepper (stepper.c dispatches a new kind here)                          */
/* ---------------------------------------------------------------------------------------- */

struct sinter_stepper;

/*
 * One quasi-static step of at most h on st->ps from st->time, like sinter_staggered_step: the
 * step taken goes to *taken, st->time advances by it, st->dt and st->stats.dt get the proposal
 * for the next step, and st->forces_current is cleared (positions moved). *qs is created on
 * first use with `opt` (NULL: defaults); free it with sinter_qs_destroy. The temperature is
 * the furnace's T(t) (sinter_stepper_set_furnace), or without one the mean particle
 * temperature held over the step; walls and force models are not used.
 * A reordering of st->ps (layout_generation) is followed through the particle ids.
 */
sinter_status sinter_quasistatic_step(struct sinter_stepper *st, sinter_qs **qs,
                                      const sinter_qs_options *opt, double h, double *taken);

#endif /* SINTER_STEPPER_QUASISTATIC_H */
