/*
 * Private API of the 7DOF two-particle neck model (docs/7dof.md, "the spec" below;
 * seed 001 = Ivannikov et al. 2022, sec. 2.2, eqs. 1-9, table 1).
 *
 * State Y = [y1 .. y7] in "parametrisation 2" (spec §2.1), all lengths in m:
 *   y1 = x    neck (grain-boundary disc) radius
 *   y2 = R_A  radius of sphere A        y5 = R_B
 *   y3 = d_A  centre A -> plane of the cone-A/cap-A junction circle (towards B)   y6 = d_B
 *   y4 = L_A  centre A -> grain-boundary plane                                     y7 = L_B
 *
 * Layers, one idea per file:
 *   geometry.c      V(Y), A_s(Y), A_gb(Y) and their analytic partial derivatives (spec §2.2-2.3),
 *                   the validity guards (spec §2.5)
 *   rhs.c           Arrhenius coefficients with the phase switch (seed 001 eq. 5, spec §3, §6.1),
 *                   chemical potentials (seed 001 eq. 9, spec §2.4), fluxes (seed 001 eq. 4,
 *                   table 1, spec §3), volume balances (seed 001 eq. 3) and the chain rule (eq. 2)
 *   jacobian.c      dense 7x7 finite-difference Jacobian of the right-hand side
 *   initial.c       initial condition of two touching spheres (spec §4)
 *   schedule.c      piecewise-linear temperature schedule, its breakpoints and phase switches
 *   cvode_driver.c  CVODE BDF + Newton + SUNDIALS dense 7x7 solver across a schedule
 *   rk4.c           fixed-step classical Runge-Kutta of the same RHS (the seed's integrator)
 *   batch.c         many pairs in one CVODE system with a block-diagonal Jacobian (strategy 3)
 *   blockdiag.c     the block-diagonal SUNMatrix and direct SUNLinearSolver batch.c uses
 *   model.c         the public handle (options by key) and sinter_neck_two_particles
 *   gb_law.c        the classic grain-boundary diffusion contact law (Bouvard & McMeeking),
 *                   a free two-particle law for comparison with the 7DOF model
 *
 * Threads: nothing here has global state; a solver or batch object is used by one thread at a
 * time. Pure functions (geometry, rhs, jacobian) may be called concurrently.
 */
#ifndef SINTER_NECK_H
#define SINTER_NECK_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

#define SINTER_NECK_DOF 7

/* Indices into Y (spec §2.1). Side P (0 = A, 1 = B) has R, d, L at 1 + 3P, 2 + 3P, 3 + 3P. */
enum {
    SINTER_NECK_X = 0,
    SINTER_NECK_RA = 1,
    SINTER_NECK_DA = 2,
    SINTER_NECK_LA = 3,
    SINTER_NECK_RB = 4,
    SINTER_NECK_DB = 5,
    SINTER_NECK_LB = 6
};

/* Boltzmann and gas constants (spec §3) [J/K], [J/(mol K)]. */
#define SINTER_NECK_KB 1.380649e-23
#define SINTER_NECK_GAS_CONSTANT 8.314462618

/* ---------------------------------------------------------------------------------------- */
/* Material data                                                                              */
/* ---------------------------------------------------------------------------------------- */

/* The diffusion data of one phase (seed 001 tables 2 and 4), SI. */
typedef struct sinter_neck_phase {
    double atomic_volume;            /* Omega [m^3] */
    double surface_energy;           /* gamma_s [J/m^2] */
    double grain_boundary_energy;    /* gamma_gb [J/m^2] */
    double surface_thickness;        /* delta_s [m] */
    double grain_boundary_thickness; /* delta_gb [m] */
    double lattice_d0, lattice_q;    /* D_v0 [m^2/s], Q_v [J/mol] */
    double surface_d0, surface_q;    /* D_s0, Q_s */
    double boundary_d0, boundary_q;  /* D_gb0, Q_gb */
    double surface_fraction;         /* n_s = n Omega of the surface (spec §3) [-] */
    double boundary_fraction;        /* n_gb [-] */
} sinter_neck_phase;

/* Both phases and the switch temperature (0: single phase, phase[1] unused). */
typedef struct sinter_neck_material {
    sinter_neck_phase phase[2];    /* [0] below the transition (Ti alpha), [1] at/above (Ti beta) */
    double transition_temperature; /* [K] */
    /* The reconstruction's path constants (docs/7dof.md §3), both phases: Delta s of fluxes
     * I-II = boundary_path x, III-IV = cone_path s, V-VI = cap_path s; n_v of the lattice. */
    double boundary_path, cone_path, cap_path, lattice_fraction;
} sinter_neck_material;

/* Read the neck parameters of a public material. */
void sinter_neck_material_from(const sinter_material *m, sinter_neck_material *out);

/* Phase (0 or 1) at temperature T: 1 iff a transition is set and T >= it (spec §6.1). */
int sinter_neck_phase_at(const sinter_neck_material *m, double temperature);

/* The constants of the right-hand side at one temperature and phase. */
typedef struct sinter_neck_coeffs {
    double temperature; /* [K] */
    int phase;
    double atomic_volume;      /* Omega [m^3] */
    double surface_energy;     /* gamma_s [J/m^2] */
    double boundary_energy;    /* gamma_gb [J/m^2] */
    double surface_thickness;  /* delta_s [m] */
    double boundary_thickness; /* delta_gb [m] */
    /* D n_frac / (k_B T) of each mechanism (seed 001 eq. 4-5, spec §3: n Omega = n_frac,
     * n_v = 1) [m^2/(J s)]. */
    double mobility_lattice;
    double mobility_surface;
    double mobility_boundary;
    /* 1 / Delta s = boundary_factor / x (fluxes I, II), cap_factor / s (V, VI) and
     * cone_factor cap_factor / s (III, IV): 4, 1 and 2 with the default path constants. */
    double boundary_factor, cap_factor, cone_factor;
} sinter_neck_coeffs;

/* Fill the coefficients of `phase` at temperature T (> 0). */
void sinter_neck_coeffs_eval(const sinter_neck_material *m, int phase, double temperature,
                             sinter_neck_coeffs *c);

/* ---------------------------------------------------------------------------------------- */
/* Geometry (spec §2)                                                                         */
/* ---------------------------------------------------------------------------------------- */

/* Derived quantities of one side (spec §2.1). */
typedef struct sinter_neck_side {
    double cone_height;     /* H = L - d [m] */
    double junction_radius; /* h = sqrt(R^2 - d^2) [m] */
    double slant;           /* s = sqrt(H^2 + (h - x)^2) [m], also the lattice depth l */
} sinter_neck_side;

/* V, A_s, A_gb and their partial derivatives with respect to y1..y7 (spec §2.2-2.3). */
typedef struct sinter_neck_geometry {
    sinter_neck_side side[2];
    double volume;                     /* V(Y) [m^3] */
    double surface_area;               /* A_s(Y) [m^2] */
    double boundary_area;              /* A_gb(Y) = pi y1^2 [m^2] */
    double dvolume[SINTER_NECK_DOF];   /* dV/dy_i [m^2] */
    double dsurface[SINTER_NECK_DOF];  /* dA_s/dy_i [m] */
    double dboundary[SINTER_NECK_DOF]; /* dA_gb/dy_i [m] */
} sinter_neck_geometry;

/*
 * Evaluate the geometry. Returns 0, or -1 if the formulas cannot be evaluated (a value not
 * finite, R <= 0, |d| >= R, or a zero slant); the domain guards are separate (below).
 */
int sinter_neck_geometry_eval(const double y[SINTER_NECK_DOF], sinter_neck_geometry *g);

/* The validity guards of spec §2.5. */
typedef enum sinter_neck_violation {
    SINTER_NECK_VALID = 0,
    SINTER_NECK_NOT_FINITE = 1,    /* a state value is NaN or infinite */
    SINTER_NECK_NECK_RADIUS = 2,   /* y1 <= 0 */
    SINTER_NECK_SPHERE_RADIUS = 3, /* R_P <= 0 */
    SINTER_NECK_JUNCTION = 4,      /* |d_P| >= R_P (h_P would exceed R_P or be undefined) */
    SINTER_NECK_CONE_HEIGHT = 5,   /* H_P = L_P - d_P <= 0 */
    SINTER_NECK_TANGENT = 6        /* |dV/dd_P| < 1e-3 pi h_P^2: cone P tangent to sphere P */
} sinter_neck_violation;

/* What a guard found: which guard, on which side, with the offending value and its limit. */
typedef struct sinter_neck_domain_error {
    sinter_neck_violation what;
    int side;     /* 0 = A, 1 = B, -1 = not side-specific */
    double value; /* the offending quantity [m or m^2] */
    double limit; /* the bound it violated */
    double time;  /* when [s] (NaN when not known) */
} sinter_neck_domain_error;

/*
 * Check the guards of spec §2.5 on y (and g when non-NULL and already evaluated for y, else it
 * is evaluated here). Returns SINTER_NECK_VALID or the first violation (filled into *err when
 * err is non-NULL; err->time is left NaN).
 */
sinter_neck_violation sinter_neck_check_domain(const double y[SINTER_NECK_DOF],
                                               const sinter_neck_geometry *g,
                                               sinter_neck_domain_error *err);

/* "cone height H_A = L_A - d_A = -1.2e-09 m must be > 0" (no time, no trailing period). */
void sinter_neck_describe_violation(const sinter_neck_domain_error *err, char *text, size_t size);

/* G = gamma_s A_s + gamma_gb A_gb (seed 001 eq. 8) [J]. */
double sinter_neck_free_energy(const sinter_neck_geometry *g, const sinter_neck_coeffs *c);

/* ---------------------------------------------------------------------------------------- */
/* Right-hand side (seed 001 eqs. 2-9, spec §2.4, §3)                                          */
/* ---------------------------------------------------------------------------------------- */

/* Volume flows of one side [m^3/s], positive in the direction of seed 001 table 1. */
enum {
    SINTER_NECK_FLUX_I = 0,   /* GB diffusion, GB (4) -> ring (1) */
    SINTER_NECK_FLUX_II = 1,  /* lattice, GB (4) -> ring (1) */
    SINTER_NECK_FLUX_III = 2, /* surface, cone (3) -> ring (1) */
    SINTER_NECK_FLUX_IV = 3,  /* lattice, cone (3) -> ring (1) */
    SINTER_NECK_FLUX_V = 4,   /* surface, cap (2) -> cone (3) */
    SINTER_NECK_FLUX_VI = 5,  /* lattice, cap (2) -> cone (3) */
    SINTER_NECK_FLUXES = 6
};

/* Everything the RHS computes on the way, for tests and diagnostics. */
typedef struct sinter_neck_rhs_detail {
    sinter_neck_geometry geometry;
    double potential[SINTER_NECK_DOF];   /* mu_i [J per atom] (seed 001 eq. 9) */
    double flux[2][SINTER_NECK_FLUXES];  /* [side][I..VI] [m^3/s] */
    double region_rate[SINTER_NECK_DOF]; /* dV_i/dt [m^3/s] (seed 001 eq. 3) */
} sinter_neck_rhs_detail;

/*
 * ydot = f(y) at fixed coefficients. Returns SINTER_NECK_VALID, or the guard that y violates
 * (then ydot is untouched and *err, when non-NULL, says which). `detail` may be NULL.
 */
sinter_neck_violation sinter_neck_rhs(const double y[SINTER_NECK_DOF], const sinter_neck_coeffs *c,
                                      double ydot[SINTER_NECK_DOF], sinter_neck_domain_error *err,
                                      sinter_neck_rhs_detail *detail);

/*
 * The same from the geometry of y, already evaluated (sinter_neck_geometry_eval) and inside the
 * domain (sinter_neck_check_domain): an integrator that checks each new state reuses its
 * geometry for the next step's first stage. Same bits as sinter_neck_rhs.
 */
void sinter_neck_rhs_at(const double y[SINTER_NECK_DOF], const sinter_neck_geometry *g,
                        const sinter_neck_coeffs *c, double ydot[SINTER_NECK_DOF],
                        sinter_neck_rhs_detail *detail);

/*
 * Dense Jacobian J[i + 7 j] = d f_i / d y_j by forward differences around (y, f = f(y)), one
 * RHS evaluation per column, increments sqrt(machine epsilon) * |y_j| (floored at 1e-8 y1).
 * Returns SINTER_NECK_VALID or the guard a perturbed state violated.
 */
sinter_neck_violation sinter_neck_jacobian(const double y[SINTER_NECK_DOF],
                                           const double f[SINTER_NECK_DOF],
                                           const sinter_neck_coeffs *c,
                                           double jac[SINTER_NECK_DOF * SINTER_NECK_DOF]);

/* ---------------------------------------------------------------------------------------- */
/* Initial condition (spec §4)                                                                */
/* ---------------------------------------------------------------------------------------- */

/*
 * Two touching spheres: x0 = epsilon min(R_A, R_B), h0 = h0_ratio x0, y2 = y4 = R_A,
 * y3 = sqrt(R_A^2 - h0^2), and the same for B. Returns 0, or -1 for invalid arguments
 * (radii <= 0, epsilon outside (0, 0.5), h0_ratio outside (1, 2), h0 >= min radius).
 */
int sinter_neck_initial_state(double radius_a, double radius_b, double epsilon, double h0_ratio,
                              double y[SINTER_NECK_DOF]);

/* ---------------------------------------------------------------------------------------- */
/* Temperature schedule                                                                       */
/* ---------------------------------------------------------------------------------------- */

/* Piecewise-linear T(t) through n >= 1 points (times strictly increasing), constant outside. */
typedef struct sinter_neck_schedule {
    size_t count;
    const double *times;        /* [s] (borrowed) */
    const double *temperatures; /* [K] (borrowed), each > 0 */
} sinter_neck_schedule;

/* T(t) [K]. */
double sinter_neck_schedule_temperature(const sinter_neck_schedule *s, double t);

/*
 * The first time strictly after t (and <= t_end) at which the RHS stops being smooth: a
 * schedule point or a crossing of the material's transition temperature. t_end if none.
 */
double sinter_neck_schedule_next_break(const sinter_neck_schedule *s, const sinter_neck_material *m,
                                       double t, double t_end);

/* Phase on the open segment (t0, t1) between two consecutive breaks (T at its midpoint). */
int sinter_neck_schedule_phase(const sinter_neck_schedule *s, const sinter_neck_material *m,
                               double t0, double t1);

/* 1 if T is the same at every time in [t0, t1] (no schedule point with a change inside). */
int sinter_neck_schedule_constant(const sinter_neck_schedule *s, double t0, double t1);

/* ---------------------------------------------------------------------------------------- */
/* One pair: the state the DEM coupling keeps per contact, and its advance                    */
/* ---------------------------------------------------------------------------------------- */

typedef struct sinter_neck_state {
    double y[SINTER_NECK_DOF];
    double time;             /* time of y [s] */
    double center_distance0; /* L0 = y4(0) + y7(0) (seed 001 eq. 11) [m] */
    double last_dy4;         /* y4 decrement of the last advance (seed 001 eq. 43a) [m] */
    double last_dy7;         /* y7 decrement of the last advance (seed 001 eq. 43b) [m] */
    double step_hint;        /* last integrator step, used to start the next advance (0: none) */
} sinter_neck_state;

/* Seed a pair at time t0 from spec §4 (fails like sinter_neck_initial_state). */
int sinter_neck_state_init(sinter_neck_state *state, double radius_a, double radius_b,
                           double epsilon, double h0_ratio, double t0);

/*
 * How the local error of each component is weighed: CVODE keeps the WRMS norm of
 * error_i / (rtol scale_i + atol) below 1.
 *  - COMPONENT: scale_i = |y_i|, as docs/7dof.md §4 writes it. In parametrisation 2 the lengths
 *    R, d, L are ~R while the cone height H = L - d they define is ~x^2/(2R) for a young neck
 *    (1e-4 R), so a loose rtol leaves H unresolved early on and the error at the end depends
 *    erratically on the neck: over the benchmark's 2400 copper necks (22.5-27.5 um, 5000 s)
 *    the worst error was 2.3e-2 in x and 1.1e-1 in Delta L / L0 at rtol 1e-4, and at rtol 1e-3
 *    140 necks were driven out of the domain (H < 0).
 *  - GEOMETRY (default): y1 by |x|; R_P, d_P, L_P by min(|y_i|, H_P), so rtol is a relative
 *    accuracy of the smallest length of the geometry. Same necks: 7.4e-3 and 6.6e-3 at
 *    rtol 1e-4 (17 failures at 1e-3), and from rtol 1e-5 on the worst error stays within
 *    10-30 rtol; for the same CPU time both scales reach about the same error
 *    (tests/bench/RESULTS.md), so the gain is an rtol that means what it says, not speed.
 */
typedef enum sinter_neck_error_scale {
    SINTER_NECK_SCALE_COMPONENT = 0,
    SINTER_NECK_SCALE_GEOMETRY = 1
} sinter_neck_error_scale;

/* Integrator settings. */
typedef struct sinter_neck_tolerances {
    double rtol;         /* relative tolerance */
    double atol;         /* absolute tolerance [m] (0: 1e-14 min(R_A, R_B), spec §4) */
    double initial_step; /* first step of a fresh pair [s] (0: let CVODE estimate) */
    long max_steps;      /* most steps of one advance */
    int error_scale;     /* a sinter_neck_error_scale */
} sinter_neck_tolerances;

/* rtol 1e-8, atol 0 (auto), initial step 1e-12 s (spec §4), 1e6 steps, GEOMETRY scale. */
void sinter_neck_tolerances_default(sinter_neck_tolerances *tol);

/* CVODE's error weights w_i = 1 / (rtol scale_i + atol) of one pair (atol already resolved). */
void sinter_neck_error_weights(const double y[SINTER_NECK_DOF], double rtol, double atol,
                               int error_scale, double w[SINTER_NECK_DOF]);

/* Work counters, accumulated (never reset) by every advance. */
typedef struct sinter_neck_counters {
    uint64_t steps;           /* accepted steps */
    uint64_t rhs_evaluations; /* every f(y), including those of Jacobians */
    uint64_t jacobian_evaluations;
    uint64_t error_test_failures;
    uint64_t nonlinear_iterations;
    uint64_t nonlinear_failures; /* nonlinear convergence failures */
    uint64_t segments;           /* smooth pieces integrated (one CVODE (re)initialisation each) */
} sinter_neck_counters;

/* Requested outputs of an advance: states at `count` nondecreasing times (7 doubles each). */
typedef struct sinter_neck_outputs {
    size_t count;
    const double *times; /* [s], each in [state->time, t_end] */
    double *states;      /* 7 * count doubles, written */
} sinter_neck_outputs;

/* Observer of every accepted step (time, state, phase); non-zero return stops with
 * SINTER_ERR_CALLBACK. */
typedef int (*sinter_neck_step_fn)(double t, const double y[SINTER_NECK_DOF], int phase,
                                   void *user);

/* CVODE memory for one 7-DOF system, reused across pairs and advances. */
typedef struct sinter_neck_solver sinter_neck_solver;

sinter_status sinter_neck_solver_create(sinter_neck_solver **out, sinter_ctx *ctx);
void sinter_neck_solver_destroy(sinter_neck_solver *solver);

/* Observer for the next advances of this solver (NULL to remove). */
void sinter_neck_solver_set_observer(sinter_neck_solver *solver, sinter_neck_step_fn fn,
                                     void *user);

/*
 * Advance one pair from state->time to t_end with CVODE (BDF, Newton, dense 7x7), stopping
 * and re-initialising at every schedule point and phase switch so that each piece is smooth.
 * Fills `outputs` (may be NULL), updates state (y, time, last_dy4/7, step_hint) and adds to
 * `counters` (may be NULL). Errors: SINTER_ERR_DOMAIN (a guard of spec §2.5, naming the
 * quantity and the time), SINTER_ERR_NOT_CONVERGED (CVODE failure, with its flag),
 * SINTER_ERR_INVALID, SINTER_ERR_CALLBACK, SINTER_ERR_NOMEM. On error state keeps the last
 * accepted step.
 */
sinter_status sinter_neck_advance_pair(sinter_neck_solver *solver, sinter_neck_state *state,
                                       const sinter_neck_material *m,
                                       const sinter_neck_schedule *schedule, double t_end,
                                       const sinter_neck_tolerances *tol,
                                       const sinter_neck_outputs *outputs,
                                       sinter_neck_counters *counters);

/* Shared by the advances: argument checks (schedule, end time, the state's guards, output
 * times) and the SINTER_ERR_DOMAIN message naming the quantity and the time. */
sinter_status sinter_neck_check_advance(sinter_ctx *ctx, const sinter_neck_state *state,
                                        const sinter_neck_schedule *schedule, double t_end,
                                        const sinter_neck_outputs *outputs, const char *who);
sinter_status sinter_neck_report_domain(sinter_ctx *ctx, const sinter_neck_domain_error *err,
                                        const char *who);

/*
 * The seed's integrator (seed 001 sec. 2.2: classical 4th-order Runge-Kutta) with a fixed
 * number of steps: the grid is uniform in u = ln(1 + (t - t0)/time_scale) over [t0, t_end]
 * (rk4.c explains why), and steps are cut at schedule breaks and output times. Same errors as
 * sinter_neck_advance_pair (ctx for the messages), except that a state outside the domain is
 * SINTER_ERR_UNSTABLE: with a fixed step it almost always is explicit instability.
 */
sinter_status sinter_neck_rk4_advance(sinter_ctx *ctx, sinter_neck_state *state,
                                      const sinter_neck_material *m,
                                      const sinter_neck_schedule *schedule, double t_end,
                                      uint64_t steps, double time_scale,
                                      const sinter_neck_outputs *outputs,
                                      sinter_neck_counters *counters);

/* ---------------------------------------------------------------------------------------- */
/* Many pairs in one CVODE system (strategy 3 of the issue)                                    */
/* ---------------------------------------------------------------------------------------- */

/*
 * A batch integrates n pairs as one system of 7n ODEs with one CVODE instance and a shared
 * step. The Newton matrix I - gamma J is block diagonal (pairs do not interact inside the
 * neck model): it is held in a block-diagonal SUNMatrix with its own direct solver
 * (blockdiag.c), each 7x7 block from sinter_neck_jacobian (7 pair-RHS calls per pair, not 7n
 * full RHS calls), factorised in O(n).
 * CVODE's error test uses the largest per-pair WRMS norm (the vector's norm operation is
 * replaced), so every pair meets the tolerance of a single-pair advance whatever n is.
 * All pairs share one schedule and one time: a batch is meant for the DEM coupling's global
 * step, where every contact advances over the same interval. Materials may differ per pair.
 */
typedef struct sinter_neck_batch sinter_neck_batch;

sinter_status sinter_neck_batch_create(sinter_neck_batch **out, sinter_ctx *ctx);
void sinter_neck_batch_destroy(sinter_neck_batch *batch);

/*
 * Advance pairs[0..n) (all at the same time) to t_end; materials[k] belongs to pair k.
 * Errors as sinter_neck_advance_pair; a domain error names the pair index.
 */
sinter_status sinter_neck_batch_advance(sinter_neck_batch *batch, size_t n,
                                        sinter_neck_state *pairs,
                                        const sinter_neck_material *const *materials,
                                        const sinter_neck_schedule *schedule, double t_end,
                                        const sinter_neck_tolerances *tol,
                                        sinter_neck_counters *counters);

/* The index of the pair whose domain error stopped the last advance (SIZE_MAX: none). */
size_t sinter_neck_batch_failed_pair(const sinter_neck_batch *batch);

/* ---------------------------------------------------------------------------------------- */
/* Validity guard: neck impingement and the density domain (docs/7dof.md §2.6, validity.c)   */
/* ---------------------------------------------------------------------------------------- */

/* Share of a particle's surface the necks may cover before neighbouring necks are taken to
 * meet: Z equal necks on regular lattices meet at a covered share of 0.73 (bcc, Z = 8), 0.80
 * (fcc, Z = 12) and 0.88 (simple cubic, Z = 6) (docs/7dof.md §2.6). */
#define SINTER_NECK_COVERAGE_LIMIT 0.8
/* Relative density past which the model's initial/intermediate-stage geometry no longer holds
 * (seed 001 sec. 4.2: "hardly possible to advance significantly further than ... 0.8"). */
#define SINTER_NECK_DENSITY_LIMIT 0.8

/* Share of a sphere's surface cut off by a neck plane of radius x = ratio R: the cap
 * (1 - cos theta) / 2 with sin theta = ratio (ratio clamped to [0, 1]). */
double sinter_neck_cap_share(double ratio);
/* x/R at which `coordination` equal necks cover SINTER_NECK_COVERAGE_LIMIT of the surface;
 * INFINITY when they never do (coordination <= 2 * 0.8 / 2, or 0 = not checked). */
double sinter_neck_impingement_ratio(double coordination);
/* Relative density of a packing of green density `green` that shrinks isotropically as the
 * pair does: green / (1 - shrinkage)^3. */
double sinter_neck_pair_density(double green, double shrinkage);

/* ---------------------------------------------------------------------------------------- */
/* The classic grain-boundary diffusion contact law (gb_law.c, docs/7dof.md §7)               */
/* ---------------------------------------------------------------------------------------- */

/* Delta_b = Omega delta_gb D_gb(T) / (k_B T) of a phase [m^6/(J s)] (no mobile fraction n_gb:
 * the law's own definition). */
double sinter_gb_law_diffusion(const sinter_neck_phase *p, double temperature);
/* F_s = pi gamma_s [4 R* (1 - cos(psi/2)) + a sin(psi/2)], cos(psi/2) = gamma_gb / (2 gamma_s)
 * [N] (0 when gamma_s <= 0 or gamma_gb >= 2 gamma_s). */
double sinter_gb_law_sintering_force(const sinter_neck_phase *p, double rstar, double a);
/* The free pair's approach rate 8 Delta_b F_s / (pi a^4) [m/s]. */
double sinter_gb_law_approach_rate(const sinter_neck_phase *p, double temperature, double rstar,
                                   double a);
/* The neck a1 with integral_{a0}^{a1} a^5 / (b + s a) da = target (b > 0, s >= 0) [m]. */
double sinter_gb_law_grow(double b, double s, double a0, double target);
/* Advance the neck radius *a of a free pair of radii radius_a, radius_b over [t0, t1] on the
 * schedule (split at its points and the phase switches). Returns 0, or -1 (bad arguments or a
 * neck that is not finite; *a untouched). The approach over the step is
 * (a1^2 - a0^2) / (4 R*), by the law's neck relation a^2 = 4 R* delta. */
int sinter_gb_law_advance(const sinter_neck_material *m, const sinter_neck_schedule *s,
                          double radius_a, double radius_b, double t0, double t1, double *a);

#endif /* SINTER_NECK_H */
