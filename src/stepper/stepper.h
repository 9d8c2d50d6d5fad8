/* Private layout of a stepper and the evaluation pipeline shared by all steppers. */
#ifndef SINTER_STEPPER_H
#define SINTER_STEPPER_H

#include "contact/history.h"
#include "domain/domain.h"
#include "ghosts/ghosts.h"
#include "stepper/anderson.h"
#include "stepper/step_control.h"
#include "force/force_model.h"
#include "stepper/frozen_heat.h"
#include "stepper/heat_interval.h"
#include "stepper/thermal.h"
#include "stepper/quasistatic.h"
#include "stepper/thread_choice.h"
#include "stepper/verlet_blocks.h"

typedef struct sinter_force_slot {
    sinter_force_model *model;
    sinter_history pp;
    sinter_history pw;
    uint64_t bonds_broken; /* bonds its last evaluation broke, counted at the next commit */
} sinter_force_slot;

/* Options and work arrays of the implicit staggered stepper (staggered.c, seed 000 sec. 3, 6). */
typedef struct sinter_staggered {
    double phi;                   /* trapezoidal parameter, eq. 24-25, 36 */
    int target_iterations;        /* K_d, eq. 49 */
    double tolerance;             /* TOL_r = TOL_theta, eq. 48 */
    double exponent;              /* p, eq. 49 */
    double dt_max;                /* dt_lim */
    double dt_min;                /* floor: below it a step fails */
    int adaptive;                 /* 0: keep dt */
    double position_tolerance;    /* absolute floor of eq. 47-48 for positions [m] */
    double temperature_tolerance; /* and for temperatures [K] */
    int scheme;                   /* 0: seed's Algorithm 1, 1: Anderson + WRMS + PI (staggered.c) */
    int anderson_depth;           /* m of Anderson(m), scheme 1 (anderson.h) */
    /* scheme 1: the controller's and the predictor's history (checkpointed) */
    sinter_step_control control;
    double h_prev;        /* the last accepted step [s] */
    double contraction;   /* contraction estimate of the last accepted step (0: none measured) */
    int history_valid;    /* hist holds F, torques, Q at the start of the last accepted step */
    size_t history_count; /* particles the history was made with */
    double *hist;         /* 7 doubles per particle: F^(L-1), torque^(L-1), Q^(L-1) */
    size_t hist_capacity;
    double *work; /* scheme 1: iterate, image and weights, 10 doubles per particle each */
    size_t work_capacity;
    sinter_anderson aa;
    /* state at t (restored on a rejection), 28 doubles per particle; see staggered.c */
    double *saved;
    size_t saved_capacity;
    uint32_t *flags; /* particle flags at t (the electric solve sets ELECTRIFIED) */
    size_t flags_capacity;
    double *power; /* per heat slot: power at t, then of the last iterate (2 per slot) */
    size_t power_capacity;
    /* periodic boundaries: the positions at t of every row, images included, for the sanity
     * check (3 per row; staggered.c) */
    double *x_rows;
    size_t x_rows_capacity;
    /* the reproducible mode: the terms of the exact sums (staggered_exact.h) */
    double *terms;
    size_t terms_capacity;
} sinter_staggered;

/*
 * Streaming stores for the explicit step's new x, v and w (explicit.c): they pay when the
 * particles' arrays do not fit in the caches (a 512k bed: the integrator's passes 13 %
 * faster) and cost where they do (64k: 60 % slower); where that lies depends on the machine,
 * so the stepper times steps of both kinds and keeps the faster. Both write the same values:
 * the results do not depend on the choice.
 */
typedef struct sinter_store_choice {
    int option;      /* option "stream_stores": -1 measure (the default), 0 never, 1 always */
    int stream_now;  /* the kind of the step being taken */
    int decided;     /* the kind chosen (0 or 1), or -1 while measuring, for: */
    uint64_t layout; /* the particles' layout_generation */
    int threads;
    int trials;     /* steps timed so far */
    double best[2]; /* the shortest step of each kind [s] */
} sinter_store_choice;

/*
 * The energy check (sanity.c, criterion 4) runs on every step by default: a damped contact can
 * create energy in the few steps of one collision and the run then goes on looking sound, so a
 * check of every N-th step ("energy_check" N, for large runs: its pass costs about 12 % of a
 * step of the 64k packed bed, tests/bench/RESULTS.md, session 24) may miss it.
 */
#define SINTER_ENERGY_CHECK_INTERVAL 1

struct sinter_stepper {
    sinter_ctx *ctx;
    int kind;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_force_slot *forces;
    size_t force_count;
    size_t force_capacity;
    sinter_neighbors nb;
    int skin_set;
    sinter_contact_list pp;
    sinter_contact_list pw;
    double time;
    double dt;
    sinter_observer_fn observer;
    void *observer_user;
    sinter_stepper_stats stats;
    int forces_current;  /* forces of the current state are evaluated and committed */
    int forces_zeroed;   /* the integrator zeroed force and torque after its last read */
    int gravity_seeded;  /* ... and wrote the first force model's m g into the force
                            (that model, gravity, is not evaluated again) */
    int plain_particles; /* the integrator found no fixed or non-rotating particle */
    /* the explicit step's second half kick by ranges, handed to the last force model's law
     * during its evaluation (sinter_force_eval.range_final; NULL otherwise), and whether that
     * law called it for every range (ranges_final) */
    void (*range_final)(void *user, int range, size_t lo, size_t hi);
    void *range_final_user;
    int ranges_final;
    /* the explicit step asks for its conduction in the same region (thermal.h,
     * sinter_thermal_law_begin) */
    int heat_in_law;
    /* option "heat_interval" (heat_interval.h): the explicit step advances the temperatures
     * every heat_interval-th step (1: every step); heat_skip: this evaluation leaves the heat
     * models out (their powers are not read before the next evaluation) */
    uint64_t heat_interval;
    int heat_skip;
    /* evaluations whose contacts the force law confirmed (sinter_contacts_find_pp_deferred),
     * and those of them in which it dropped ended contacts */
    uint64_t law_confirmed, law_dropped;
    uint64_t sort_interval; /* option "sort_interval": steps between spatial sorts, 0 off */
    uint64_t steps_since_sort;
    int rotation;                   /* option "rotation": integrate the total rotation vector */
    uint64_t write_generation;      /* particle write_generation when forces were evaluated */
    uint64_t population_generation; /* particle population_generation then */
    double *wall_force;             /* 3 per wall, then 3 per wall of moments [N m], from the
                                       last evaluation (capacity: walls) */
    size_t wall_force_capacity;
    /* the reproducible mode (stepper/wall_sums.h): 6 doubles per wall contact of the last
     * evaluation (pw_reaction_count of them), and the sums' scratch */
    double *pw_reaction;
    size_t pw_reaction_capacity, pw_reaction_count;
    int pw_reaction_valid; /* 1 after an evaluation in the mode (cleared when it is set) */
    void *wall_sums_scratch;
    size_t wall_sums_scratch_capacity;
    /* the power the contacts dissipated at the last evaluation, 2 doubles per particle (normal
     * damping, sliding), for a "dissipation" heat model (heat/dissipation.c); valid while
     * dissipation_valid */
    double *dissipation;
    size_t dissipation_capacity;
    int dissipation_valid;
    /* The other copy of x, v, w and rot (3 doubles per particle each, for ps->capacity
     * particles): the explicit step writes the new state into it and swaps it with the set's
     * arrays, so that after a step it holds the last accepted state (rollback, sanity check)
     * without a copy. */
    double *spare[4];
    size_t spare_capacity; /* particles */
    sinter_store_choice stores;
    sinter_thread_choice threads_choice; /* explicit stepper, option "thread_choice" */
    /* whether a particle is fixed or does not rotate, and the smallest radius (explicit.c,
     * any_special), for these particle generations */
    int any_special;
    double rmin;
    int particles_known;
    uint64_t known_layout, known_write;
    sinter_state_view view;
    double *wall_arrays; /* point, normal, velocity: 9 per wall, for host views */
    /* walls proven out of reach since the explicit drifts of the last steps: their candidate
     * pairs are not tested (contact/wall_skip.h; the same contacts) */
    sinter_wall_skip wall_skip;
    /* the explicit passes' per-particle factors, kept between steps (verlet_blocks.h) */
    sinter_verlet_factors verlet_factors;
    size_t wall_arrays_capacity;
    sinter_thermal thermal;            /* heat submodels and the temperature update */
    double thermal_last_h;             /* step of the last temperature update [s] */
    uint64_t stats_thermal_iterations; /* PCG iterations of implicit conduction */
    double stats_seconds_heat;         /* wall-clock time in heat evaluation [s] (conduction summed
                                          in the law's region counts in stats.seconds_force) */
    sinter_ghosts ghosts; /* periodic axes and their images (ghosts/ghosts.h); explicit only */
    sinter_domain domain; /* the host's collective operations (domain/domain.h); explicit only */
    int has_domain;
    double domain_lo[3];
    double domain_hi[3];
    /* the explicit step's domain test skipped while provably passed (sanity.c,
     * sinter_sanity_domain_moved): the smallest distance of a centre to the domain's faces at
     * the last full test [m], the steps' largest displacements summed since [m], valid while
     * domain_known and the particles' generations match */
    double domain_margin;
    double domain_moved;
    int domain_known;
    uint64_t domain_layout, domain_write;
    struct sinter_electric_model *electric; /* borrowed, NULL: no current solve */
    uint64_t electric_iterations;           /* sweeps / PCG iterations of its solves, total */
    sinter_staggered staggered;             /* SINTER_STEPPER_STAGGERED only */
    struct sinter_qs *quasistatic;          /* SINTER_STEPPER_QUASISTATIC: links and necks */
    sinter_qs_options quasistatic_options;  /* copied into it on the first step */
    /* how far the velocities the last evaluation saw lag behind the set's: h / 2 after an
     * explicit step (its force read the half-step velocities), 0 after any other evaluation
     * (read by sinter_snapshot_create only) [s] */
    double eval_lag;
    double *furnace;      /* sinter_stepper_set_furnace: times, then temperatures */
    size_t furnace_count; /* points (0: no furnace) */
    /* issue 35 (stable_step.c, sanity.c criterion 4), explicit stepper only */
    int reproducible;     /* option "reproducible": 1 sorts the pairs by ids at every build
                             (contact/canonical_order.h); 0, the default, keeps the build's order */
    int dt_check;         /* option "dt_check": 1 (the default) refuses a step beyond the limit */
    int energy_check;     /* option "energy_check": check every N-th step for energy
                             creation (default SINTER_ENERGY_CHECK_INTERVAL), 0 never */
    double stable_logged; /* the last estimate logged at info level (0: none) */
    double energy_floor;  /* the energy check's resolution [J]: SINTER_SANITY_ENERGY_FLOOR of the
                             least elastic energy of a contact at the reference overlap */
    unsigned char *energy_flag; /* per particle: examined by the energy check */
    size_t energy_flag_capacity;
    double *energy_store; /* per particle: elastic energy of its contacts at t and at t + h */
    size_t energy_store_capacity;
    size_t *energy_start; /* per particle: its contact partners' list in energy_adj */
    size_t energy_start_capacity;
    uint32_t *energy_adj;
    size_t energy_adj_capacity;
    double *energy_force; /* beside energy_adj: a bound of that contact's force in the step */
    size_t energy_force_capacity;
    sinter_frozen frozen; /* heat at its own pace over a frozen bed (frozen_heat.h, issue 41) */
    struct sinter_insertion *insertion; /* continuous insertion (insertion.h), NULL: none */
    /* pair histories of imported particles waiting for the next neighbour build (migrate.h),
     * NULL: none */
    struct sinter_migrate_stage *migrate;
};

/* Set every particle's temperature to the furnace's T(st->time) (no-op without a furnace). */
void sinter_stepper_apply_furnace(sinter_stepper *st);

/* Delay the furnace's schedule by `delay` [s] (the scene runner times it from a pour's end). */
void sinter_stepper_shift_furnace(sinter_stepper *st, double delay);

/* alpha <- alpha (+) d_alpha: composition of total rotation vectors, seed 003 eq. 45. */
static inline void sinter_compose_rotation(double *alpha, const double da[3])
{
    const double dot = alpha[0] * da[0] + alpha[1] * da[1] + alpha[2] * da[2];
    const double c[3] = {alpha[1] * da[2] - alpha[2] * da[1], alpha[2] * da[0] - alpha[0] * da[2],
                         alpha[0] * da[1] - alpha[1] * da[0]};
    const double s = 4.0 / (4.0 - dot);
    for (int d = 0; d < 3; ++d)
        alpha[d] = s * (alpha[d] + da[d] - 0.5 * c[d]);
}

/* Seconds of a monotonic clock. */
double sinter_clock(void);

/* Evaluate every force model on the current state; spring increments use dt_hist. */
sinter_status sinter_stepper_eval_forces(sinter_stepper *st, double dt_hist);
/* The staggered stepper's redistribution at an accepted state, with domain operations
 * (collective; stepper.c): a migration the host was refused during the last step's attempts is
 * made now, and the predictor's history restarts on every subdomain if on any. */
sinter_status sinter_stepper_domain_accepted_stage(sinter_stepper *st);

/* The staggered stepper's predictor history brought by records imported between two steps
 * (a portable restart: record bit 2, migrate.c), taken by id at the start of the next step
 * when every owned particle brought its own (local; stepper.c). */
void sinter_stepper_adopt_history(sinter_stepper *st);

/* Accept the last evaluation: commit history and wall reactions (with domain operations the
 * status and the reactions agreed in one reduction). */
sinter_status sinter_stepper_commit(sinter_stepper *st);

/* The same in two stages, for the explicit step's stage C (explicit.c): the memory the commit
 * needs taken before the status is agreed (_reserve, local), the status agreed together with
 * the wall reactions (_agree_reactions: collective, one reduction for up to 10 walls; the
 * walls written only when SINTER_OK), then the commit itself, which cannot fail after the
 * reserve (_agreed, local). */
sinter_status sinter_stepper_commit_reserve(sinter_stepper *st);
/* The explicit step's stage A with domain operations: the status after the drift agreed
 * together with the rebuild decision (one MAX of three doubles: the stale flag, the largest
 * radius, a failure flag; the full agreement follows only when a subdomain failed). The
 * decision waits in the domain (decided) for the evaluation's rebuild stage, which then makes
 * no reduction of its own. */
sinter_status sinter_stepper_agree_drift(sinter_stepper *st, sinter_status s);
sinter_status sinter_stepper_agree_reactions(sinter_stepper *st, sinter_status s);
sinter_status sinter_stepper_commit_agreed(sinter_stepper *st);

/* Bring forces, wall positions and history in line with the current state when the particles
 * changed (as sinter_stepper_advance does before its first step): the insertion stage's new
 * particles get their forces (stepper.c). */
sinter_status sinter_stepper_prepare(sinter_stepper *st);

/* Explicit velocity-Verlet step of size h (explicit.c). */
sinter_status sinter_explicit_step(sinter_stepper *st, double h);

/* 1 while the explicit stepper times its streaming stores (the thread choice waits). */
int sinter_explicit_stores_measuring(const sinter_stepper *st);

/* The explicit step's spare arrays at the set's capacity, their pages touched: done when the
 * forces are set up, so that the first step does not fault them in (explicit.c). */
sinter_status sinter_explicit_reserve(sinter_stepper *st);
/* The spare arrays grown, their content kept, after the set grew within a step (ghost rows
 * made at a neighbour build: ghosts/ghosts.h); nothing to do when the capacity is unchanged. */
sinter_status sinter_explicit_keep_spare(sinter_stepper *st);
/* Periodic axes with domain operations (domain_periodic.c): the owned particles wrapped into
 * the cell before the host's redistribution, then the images of the owned particles and of
 * the host's ghosts appended after its ghosts, with the spare rows (cutoff [m]). The second
 * is collective and refuses (SINTER_ERR_UNSUPPORTED) a decomposition that seems to cut a
 * periodic axis. */
sinter_status sinter_domain_periodic_wrap(sinter_stepper *st);
sinter_status sinter_domain_periodic_images(sinter_stepper *st, double cutoff);
/* SINTER_OK when the stepper's submodels work across periodic faces (periodic.c), else
 * SINTER_ERR_UNSUPPORTED naming the one that does not. */
sinter_status sinter_periodic_check(sinter_stepper *st);

/* Change the kind of a stepper that has not stepped yet (the scene reader creates its stepper
 * before it reads [stepper] kind). Errors: SINTER_ERR_UNSUPPORTED, SINTER_ERR_STATE. */
sinter_status sinter_stepper_set_kind(sinter_stepper *st, int kind);

/* Defaults of the staggered options; free its arrays (staggered.c). */
void sinter_staggered_init(sinter_staggered *sg);
void sinter_staggered_free(sinter_ctx *ctx, sinter_staggered *sg);

/* Option keys of the staggered stepper (sinter_stepper_set_option). */
/* 1 if `key` is an option of the staggered stepper (phi, tolerance, ...), else 0. */
int sinter_staggered_is_option(const char *key);
sinter_status sinter_staggered_set(sinter_stepper *st, const char *key, double value);
sinter_status sinter_staggered_get(const sinter_stepper *st, const char *key, double *value);

/* One accepted implicit staggered step of at most h (staggered.c, seed 000 Algorithm 1): the
 * step actually taken (smaller after rejections) is returned in *taken, and the proposal for
 * the next step is left in st->dt. */
sinter_status sinter_staggered_step(sinter_stepper *st, double h, double *taken);

/*
 * The explicit stepper's stable step (stable_step.c, where the formula is justified): the
 * reference overlap of Hertz contacts as a fraction of R*, the reference strain of the power
 * law, and the factor above the estimate from which a fixed step is refused.
 */
#define SINTER_STABLE_HERTZ_OVERLAP 0.01
#define SINTER_STABLE_POWER_STRAIN 0.1
#define SINTER_STABLE_STEP_FACTOR 2.0

/* Refuse the explicit stepper's dt beyond SINTER_STABLE_STEP_FACTOR times the estimate (unless
 * option "dt_check" is 0) with SINTER_ERR_INVALID; logs a new estimate at info level. */
sinter_status sinter_stable_step_check(sinter_stepper *st);

/* Elastic energy [J] stored by the stepper's built-in contact models in one contact of overlap
 * delta > 0 of particle i with particle j, or with wall `wall` when j is SIZE_MAX (unsoftened:
 * an upper bound; stable_step.c). */
double sinter_contact_energy(const sinter_stepper *st, size_t i, size_t j, size_t wall,
                             double delta);

/* A bound [N] of the force of the stepper's built-in contact models in one contact of overlap
 * delta > 0 between particles i and j (wall contacts: j is SIZE_MAX) closing or opening at
 * normal speed at most `speed` [m/s]: the unsoftened normal force with its damping, times
 * 1 + the friction coefficient (Coulomb's limit of the tangential force). */
double sinter_contact_force_bound(const sinter_stepper *st, size_t i, size_t j, size_t wall,
                                  double delta, double speed);

#endif
