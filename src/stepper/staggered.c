/*
 * Implicit staggered stepper, two schemes (option "scheme"): 0 is the seed's Algorithm 1,
 * described here; 1 (the default) solves the same trapezoidal rule with Anderson acceleration,
 * a weighted RMS test, a PI step controller and a predictor, described above
 * attempt_anderson below (anderson.c, step_control.c).
 *
 * Scheme 0: seed 000 sec. 3.1 (trapezoidal rule with phi solved by fixed-point
 * iterations, eq. 24-30), sec. 4.2 (the same rule for temperatures, eq. 36-37) and sec. 6
 * (multiphysical staggering, eq. 45-49, Algorithm 1).
 *
 * One step from t to t + h, state s = (x, v, w, rotation), temperatures theta:
 *
 *   s^1 from the forces at t alone (predictor; s^0 = s^L, theta^0 = theta^L)
 *   for K = 1 .. K_d:
 *     evaluate the pipeline at (s^K, theta^(K-1)) with the walls at t + h: neighbours,
 *       contacts, currents (eq. 43), forces F^K, heat Q^K; history increments over h are
 *       written as trial history only (the commit/rollback contract of include/sinter_submodel.h)
 *     theta^K = theta^L + h/(m C) (phi Q^K + (1 - phi) Q^L)                      eq. 36, 46
 *     normalised errors (eq. 47), violation ratio Z_K (eq. 48), step scale Lambda_K (eq. 49)
 *     Z_K <= 1: accept (s^K, theta^K)
 *     s^(K+1): v = v^L + h/m (phi F^K + (1 - phi) F^L),
 *              x = x^L + h (phi v + (1 - phi) v^L)                            eq. 24-26, 45
 *   no convergence by K = K_d: restore the state at t exactly, h <- Lambda_K h, restart from t
 *
 * Eq. 25-26 eliminate v: x^(L+1) = x^L + v^L h + phi h^2/m (phi F^(L+1) + (1 - phi) F^L);
 * the two-line form above is the same rule and also gives the velocity. Spins and the total
 * rotation vector (seed 003 eq. 45) follow the same rule with the torques.
 *
 * Staggering (eq. 45-46): positions are computed with the temperatures frozen, temperatures
 * with the positions frozen. One pipeline evaluation per iteration serves both: the one at
 * (s^K, theta^(K-1)) gives Q^K for theta^K exactly as eq. 46 asks (positions s^K frozen), and
 * its forces F^K for s^(K+1); eq. 45 would use F(s^K, theta^K), so the mechanics sees the
 * temperatures one iteration late. Temperature enters the forces only through softening, and
 * both versions have the same fixed point; the lag halves the evaluations per iteration.
 *
 * Errors (eq. 47, Algorithm 1 step 4a): eps_r^K = sum_i |x_i^K - x_i^(K-1)| /
 * sum_i |x_i^K - x_i^L| and the same for theta (particles with a fixed position or
 * temperature are not unknowns and are left out). With the start s^0 = s^L, eps^1 = 1: the
 * first iterate measures nothing, and eps_0 of eq. 49 (the normalised initial error) is 1.
 * When the iterates agree to the round-off of the field itself (|change| <= 8 eps_mach
 * sum |value|), eps is 0: a body at rest or a field that does not change converges instead of
 * comparing round-off with round-off. Options "position_tolerance" [m] and
 * "temperature_tolerance" [K] (default 0, the seed's test) add an absolute floor: the
 * denominator is at least n atol / TOL, so a mean change per particle <= atol also passes.
 * The seed's relative test alone cannot be met by a resting pile with Coulomb friction
 * (eq. 5-6): the friction of a resting contact flips direction between iterates, the iterates
 * stop contracting at a change ~ h^2 mu g while the step's motion goes to zero, and the step
 * collapses (press scene: below 4e-5 s at t = 1.6 s and still falling).
 *
 * Step scaling (eq. 49): the iteration error is modelled as eps_K = (S h^p)^K eps_0; it should
 * reach TOL in exactly K_d iterations, (S h_tol^p)^K_d eps_0 = TOL, hence
 *   Lambda_K = (TOL/eps_0)^(1/(p K_d)) / (eps_K/eps_0)^(1/(p K)),  Lambda = min over fields.
 * An accepted step (eps_K <= TOL at K <= K_d) has Lambda >= 1 and the next step is
 * min(dt_max, Lambda h) (Algorithm 1 step 6b-c); a step that fails has Lambda < 1 and is
 * retried from t with Lambda h (step 7). Safeguards beyond the seed, each needed by the press
 * scene or an impact:
 *  - Lambda is at most 2 (eq. 49 gives infinity when an iteration reproduces its
 *    predecessor, e.g. free flight), at most 0.9 and at least 0.1 after a failure, and 1 on
 *    the step that follows a restart (the usual step-controller rule);
 *  - stagnation: from K = 3 the last contraction rho = eps_K / eps_(K-1) is known. When
 *    rho > 1/2 the model eps_K = eta^K no longer describes the iteration (it levels off at a
 *    floor, as with friction above, that more iterations do not lower but a smaller step
 *    does, as S h^p): Lambda is then at most (TOL/eps_K)^(1/p). When eps_K rho^(K_d - K) > TOL
 *    the attempt cannot succeed by K_d and is restarted at once instead of iterating on;
 *  - a non-finite iterate (or a temperature <= 0) counts as a failure with Lambda = 0.1.
 *
 * Currents (Algorithm 1 steps 6d, 7b; sec. 6 remark 2): the electric model is solved inside
 * every pipeline evaluation, i.e. at every iterate and again on the accepted configuration,
 * which is more than "re-solved after each accepted step" asks. After acceptance the pipeline
 * is evaluated once more at (s^(L+1), theta^(L+1)) when there are heat models (without them
 * the last iterate's evaluation already is that state): this evaluation re-solves the currents
 * on the accepted configuration, gives F^(L+1) and Q^(L+1) for the next step's trapezoid and
 * the trial history that is then committed. A rejected attempt commits nothing: the
 * committed history is as it was at t, and positions, velocities, spins, rotations,
 * temperatures, forces, torques, heat powers, currents and flags are restored bit for bit.
 *
 * Periodic boundaries (issue 38; ghosts/ghosts.h): the unknowns are the owned particles, the
 * rows before the images. Every evaluation first gives the images their owners' iterate (the
 * forward halo; a neighbour build within the step makes them from the owners), and the
 * evaluation adds what the pairs put on an image to its owner. Positions are iterated from the
 * step's start, so a build within the step makes images without wrapping (sinter_ghosts.hold):
 * the owned particles are wrapped into the cell between steps, before the state at t is saved,
 * and a rejected attempt restores the owners and their images.
 *
 * Subdomains (issue 43, domain/domain.h, docs/scaleout.md): the unknowns are the owned
 * particles; every evaluation first gives the ghosts of other subdomains their owners' iterate
 * (a forward halo) and its status is agreed; the sums behind every norm, a bad state anywhere
 * and Anderson's inner products are reduced, so that every subdomain takes the same branches
 * and steps. Inside an attempt the host may make new ghosts but not migrate (the state at t
 * and the histories are per index); a refused migration is made at the next accepted state
 * (sinter_stepper_domain_accepted_stage).
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sanity.h"
#include "staggered_exact.h"
#include "stepper.h"

/* The owned particles: the unknowns (the rows after them are periodic images). */
static inline size_t owned_rows(const sinter_particles *ps)
{
    return ps->count - ps->ghost_count;
}

/* The images take their owners' state (ghosts/ghosts.h), unless a build is due anyway. */
static void forward_images(sinter_stepper *st)
{
    if (st->ps->ghost_count > 0 && sinter_ghosts_current(&st->ghosts, st->ps))
        sinter_ghosts_forward(&st->ghosts, st->ps);
}

/* The pipeline at the iterate in the particles: images first (see the top of the file); with
 * domain operations the ghosts of other subdomains first take their owners' iterate (the
 * forward halo), and the status is agreed (collective, domain/domain.h). */
static sinter_status evaluate(sinter_stepper *st, double h)
{
    forward_images(st);
    sinter_status s = SINTER_OK;
    if (st->domain.on)
        s = sinter_domain_forward(st->ctx, &st->domain, st->ps);
    if (s == SINTER_OK)
        s = sinter_stepper_eval_forces(st, h);
    return sinter_domain_agree(st->ctx, &st->domain, s);
}

/* ---- the global quantities of a decomposed run (domain/domain.h) --------------------------- */

/* Sums of doubles over every subdomain, in place (nothing without domain operations). */
static sinter_status global_sum(sinter_stepper *st, double *values, size_t count)
{
    return sinter_domain_sum(st->ctx, &st->domain, values, count);
}

/* Whether any subdomain has a particle with a bad state (`bad` < n here); a failed reduction
 * into *s, and 1 (the caller returns *s then). Without domain operations bad < n. */
static int any_bad(sinter_stepper *st, size_t bad, size_t n, sinter_status *s)
{
    if (!st->domain.on)
        return bad < n;
    int64_t v = bad < n;
    const sinter_status r =
        sinter_domain_reduce(st->ctx, &st->domain, &v, 1, SINTER_REDUCE_I64, SINTER_REDUCE_MAX);
    if (r != SINTER_OK) {
        *s = r;
        return 1;
    }
    return v != 0;
}

/* Anderson's inner products over every subdomain (anderson.h). */
static int anderson_sum(double *values, size_t count, void *user)
{
    sinter_stepper *st = user;
    return global_sum(st, values, count) == SINTER_OK ? 0 : -1;
}

/* ---- options ------------------------------------------------------------------------- */

enum {
    OPT_PHI,
    OPT_KD,
    OPT_TOL,
    OPT_EXPONENT,
    OPT_DT_MAX,
    OPT_DT_MIN,
    OPT_ADAPTIVE,
    OPT_POSITION_TOL,
    OPT_TEMPERATURE_TOL,
    OPT_SCHEME,
    OPT_ANDERSON_DEPTH,
    OPT_COUNT
};

static const char *const OPTION_KEYS[OPT_COUNT] = {"phi",
                                                   "target_iterations",
                                                   "tolerance",
                                                   "exponent",
                                                   "dt_max",
                                                   "dt_min",
                                                   "adaptive",
                                                   "position_tolerance",
                                                   "temperature_tolerance",
                                                   "scheme",
                                                   "anderson_depth"};

#define OPTION_LIST                                                                                \
    "phi, target_iterations, tolerance, exponent, dt_max, dt_min, adaptive, position_tolerance, "  \
    "temperature_tolerance, scheme, anderson_depth"

void sinter_staggered_init(sinter_staggered *sg)
{
    memset(sg, 0, sizeof(*sg));
    sg->phi = 0.5;              /* seed 000 sec. 7 */
    sg->target_iterations = 10; /* K_d, sec. 7 */
    sg->tolerance = 5e-4;       /* sec. 7 */
    sg->exponent = 2.0;         /* sec. 3.1: p = 2 for second-order problems */
    sg->dt_max = HUGE_VAL;
    sg->dt_min = 1e-12;
    sg->adaptive = 1;
    sg->scheme = 1; /* by measurement: tests/bench/RESULTS.md, press work-precision */
    sg->anderson_depth = 3;
    sinter_anderson_init(&sg->aa);
}

void sinter_staggered_free(sinter_ctx *ctx, sinter_staggered *sg)
{
    sinter_free(ctx, sg->saved);
    sinter_free(ctx, sg->flags);
    sinter_free(ctx, sg->power);
    sinter_free(ctx, sg->x_rows);
    sg->x_rows = NULL;
    sg->x_rows_capacity = 0;
    sinter_free(ctx, sg->terms);
    sg->terms = NULL;
    sg->terms_capacity = 0;
    sg->saved = NULL;
    sg->flags = NULL;
    sg->power = NULL;
    sg->saved_capacity = sg->flags_capacity = sg->power_capacity = 0;
    sinter_free(ctx, sg->hist);
    sinter_free(ctx, sg->work);
    sg->hist = sg->work = NULL;
    sg->hist_capacity = sg->work_capacity = 0;
    sg->history_valid = 0;
    sinter_anderson_free(ctx, &sg->aa);
}

static int find_option(const char *key)
{
    for (int k = 0; k < OPT_COUNT; ++k)
        if (strcmp(key, OPTION_KEYS[k]) == 0)
            return k;
    return -1;
}

int sinter_staggered_is_option(const char *key)
{
    return find_option(key) >= 0;
}

static sinter_status option_target(const sinter_stepper *st, const char *func, const char *key,
                                   int *which)
{
    *which = find_option(key);
    if (*which < 0)
        return sinter_fail(
            st->ctx, SINTER_ERR_NOT_FOUND,
            "%s: unknown option '%s'; the explicit and staggered steppers take sort_interval "
            "and rotation, the explicit stepper stream_stores, thread_choice, dt_check and "
            "energy_check, the staggered "
            "stepper also " OPTION_LIST,
            func, key);
    if (st->kind != SINTER_STEPPER_STAGGERED)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "%s: '%s' is an option of the implicit staggered stepper "
                           "(SINTER_STEPPER_STAGGERED, scene files: kind = staggered); this "
                           "stepper is %s",
                           func, key,
                           st->kind == SINTER_STEPPER_QUASISTATIC ? "quasi-static" : "explicit");
    return SINTER_OK;
}

sinter_status sinter_staggered_set(sinter_stepper *st, const char *key, double value)
{
    static const char *func = "sinter_stepper_set_option";
    int which;
    sinter_status s = option_target(st, func, key, &which);
    if (s != SINTER_OK)
        return s;
    sinter_staggered *sg = &st->staggered;
    sinter_ctx *ctx = st->ctx;
    switch (which) {
    case OPT_PHI:
        if (!(value > 0.0 && value <= 1.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: phi = %g must be in (0, 1] (0.5: trapezoidal rule, second "
                               "order; 1: backward Euler, first order)",
                               func, value);
        sg->phi = value;
        break;
    case OPT_KD:
        if (!(value >= 2.0 && value <= 1000.0 && value == floor(value)))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: target_iterations = %g must be a whole number in [2, 1000] "
                               "(the first iterate's normalised error is 1 by eq. 47, so no step "
                               "converges in fewer than 2)",
                               func, value);
        sg->target_iterations = (int)value;
        break;
    case OPT_TOL:
        if (!(value > 0.0 && value < 1.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: tolerance = %g must be in (0, 1): it bounds the normalised "
                               "iteration errors of eq. 47",
                               func, value);
        sg->tolerance = value;
        break;
    case OPT_EXPONENT:
        if (!(value > 0.0 && value <= 10.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: exponent = %g must be in (0, 10] (p of eq. 49: the "
                               "contraction constant scales as dt^p; 2 for particle dynamics)",
                               func, value);
        sg->exponent = value;
        break;
    case OPT_DT_MAX:
        if (!(value > 0.0) || isnan(value))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: dt_max = %g s must be > 0 (HUGE_VAL: no bound)", func, value);
        if (value < sg->dt_min)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: dt_max = %g s is below dt_min = %g s",
                               func, value, sg->dt_min);
        sg->dt_max = value;
        break;
    case OPT_DT_MIN:
        if (!(value > 0.0 && isfinite(value)))
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: dt_min = %g s must be > 0 and finite",
                               func, value);
        if (value > sg->dt_max)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: dt_min = %g s is above dt_max = %g s",
                               func, value, sg->dt_max);
        sg->dt_min = value;
        break;
    case OPT_ADAPTIVE:
        if (value != 0.0 && value != 1.0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: adaptive = %g must be 0 (keep the step) or 1 (eq. 49)", func,
                               value);
        sg->adaptive = value == 1.0;
        break;
    case OPT_SCHEME:
        if (value != 0.0 && value != 1.0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: scheme = %g must be 0 (the seed's Algorithm 1) or 1 (Anderson "
                               "acceleration, WRMS test, PI step control, predictor)",
                               func, value);
        sg->scheme = (int)value;
        sg->history_valid = 0;
        sg->control.x_prev = 0.0;
        sg->control.after_reject = 0;
        break;
    case OPT_ANDERSON_DEPTH:
        if (!(value >= 0.0 && value <= 10.0 && value == floor(value)))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: anderson_depth = %g must be a whole number in [0, 10] (0: "
                               "plain fixed-point iteration)",
                               func, value);
        sg->anderson_depth = (int)value;
        break;
    default: /* OPT_POSITION_TOL, OPT_TEMPERATURE_TOL */
        if (!(value >= 0.0 && isfinite(value)))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: %s = %g %s must be >= 0 and finite (0: the relative test of "
                               "eq. 47-48 alone)",
                               func, key, value, which == OPT_POSITION_TOL ? "m" : "K");
        if (which == OPT_POSITION_TOL)
            sg->position_tolerance = value;
        else
            sg->temperature_tolerance = value;
        break;
    }
    return SINTER_OK;
}

sinter_status sinter_staggered_get(const sinter_stepper *st, const char *key, double *value)
{
    int which;
    sinter_status s = option_target(st, "sinter_stepper_get_option", key, &which);
    if (s != SINTER_OK)
        return s;
    const sinter_staggered *sg = &st->staggered;
    const double values[OPT_COUNT] = {sg->phi,
                                      (double)sg->target_iterations,
                                      sg->tolerance,
                                      sg->exponent,
                                      sg->dt_max,
                                      sg->dt_min,
                                      (double)sg->adaptive,
                                      sg->position_tolerance,
                                      sg->temperature_tolerance,
                                      (double)sg->scheme,
                                      (double)sg->anderson_depth};
    *value = values[which];
    return SINTER_OK;
}

/* ---- the state at t ------------------------------------------------------------------- */

/* Pointers into sg->saved: 25 doubles per particle. */
typedef struct saved_state {
    double *x, *v, *w, *rot; /* s^L */
    double *f, *tq, *q;      /* F^L, torques, Q^L */
    double *theta, *current; /* theta^L, currents at t */
    double *x_prev;          /* x^(K-1) */
    double *theta_prev;      /* theta^(K-1) */
} saved_state;

enum { SAVED_PER_PARTICLE = 25 };

static saved_state saved_layout(const sinter_staggered *sg, size_t n)
{
    double *p = sg->saved;
    saved_state a;
    a.x = p;
    a.v = p + 3 * n;
    a.w = p + 6 * n;
    a.rot = p + 9 * n;
    a.f = p + 12 * n;
    a.tq = p + 15 * n;
    a.x_prev = p + 18 * n;
    a.q = p + 21 * n;
    a.theta = p + 22 * n;
    a.current = p + 23 * n;
    a.theta_prev = p + 24 * n;
    return a;
}

static sinter_status reserve(sinter_stepper *st)
{
    sinter_staggered *sg = &st->staggered;
    const size_t n = owned_rows(st->ps), slots = st->thermal.count;
    if (SAVED_PER_PARTICLE * n + 1 > sg->saved_capacity) {
        double *p =
            sinter_realloc_array(st->ctx, sg->saved, SAVED_PER_PARTICLE * n + 1, sizeof(double));
        if (p == NULL)
            return sinter_last_status(st->ctx);
        sg->saved = p;
        sg->saved_capacity = SAVED_PER_PARTICLE * n + 1;
    }
    if (n + 1 > sg->flags_capacity) {
        uint32_t *p = sinter_realloc_array(st->ctx, sg->flags, n + 1, sizeof(uint32_t));
        if (p == NULL)
            return sinter_last_status(st->ctx);
        sg->flags = p;
        sg->flags_capacity = n + 1;
    }
    if (2 * slots + 1 > sg->power_capacity) {
        double *p = sinter_realloc_array(st->ctx, sg->power, 2 * slots + 1, sizeof(double));
        if (p == NULL)
            return sinter_last_status(st->ctx);
        sg->power = p;
        sg->power_capacity = 2 * slots + 1;
    }
    if (st->reproducible) /* the exact sums' terms (staggered_exact.c), before any reduction */
        return sinter_grow(st->ctx, (void **)&sg->terms, &sg->terms_capacity, 4 * n + 1,
                           sizeof(double));
    return SINTER_OK;
}

static void save_state(sinter_stepper *st, const saved_state *a)
{
    const sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps), n3 = 3 * n * sizeof(double), n1 = n * sizeof(double);
    memcpy(a->x, ps->x, n3);
    memcpy(a->v, ps->v, n3);
    memcpy(a->w, ps->w, n3);
    memcpy(a->rot, ps->rot, n3);
    memcpy(a->f, ps->force, n3);
    memcpy(a->tq, ps->torque, n3);
    memcpy(a->q, ps->heat, n1);
    memcpy(a->theta, ps->temperature, n1);
    memcpy(a->current, ps->current, n1);
    memcpy(st->staggered.flags, ps->flags, n * sizeof(uint32_t));
    for (size_t k = 0; k < st->thermal.count; ++k)
        st->staggered.power[k] = st->thermal.slots[k].power;
}

/* Back to the state at t, bit for bit; the committed history was never touched. */
static void restore_state(sinter_stepper *st, const saved_state *a, double t)
{
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps), n3 = 3 * n * sizeof(double), n1 = n * sizeof(double);
    memcpy(ps->x, a->x, n3);
    memcpy(ps->v, a->v, n3);
    memcpy(ps->w, a->w, n3);
    memcpy(ps->rot, a->rot, n3);
    memcpy(ps->force, a->f, n3);
    memcpy(ps->torque, a->tq, n3);
    memcpy(ps->heat, a->q, n1);
    memcpy(ps->temperature, a->theta, n1);
    memcpy(ps->current, a->current, n1);
    memcpy(ps->flags, st->staggered.flags, n * sizeof(uint32_t));
    for (size_t k = 0; k < st->thermal.count; ++k)
        st->thermal.slots[k].power = st->staggered.power[k];
    forward_images(st);
    if (st->domain.on) { /* the ghosts of other subdomains: their owners' state at t */
        const sinter_status r = sinter_domain_forward(st->ctx, &st->domain, ps);
        (void)r; /* (the error reported is the step's; a failed halo fails the next one too) */
    }
    st->time = t;
    if (st->walls != NULL)
        sinter_walls_move(st->walls, t);
}

/* ---- the two field updates ------------------------------------------------------------ */

/* Rotation vector of particle i from its spin by the trapezoidal rule (seed 003 eq. 45). */
static void rotate(sinter_stepper *st, const saved_state *a, double h, size_t i)
{
    const double phi = st->staggered.phi, psi = 1.0 - phi;
    const double *w = st->ps->w + 3 * i, *w0 = a->w + 3 * i;
    double *alpha = st->ps->rot + 3 * i;
    memcpy(alpha, a->rot + 3 * i, 3 * sizeof(double));
    const double da[3] = {h * (phi * w[0] + psi * w0[0]), h * (phi * w[1] + psi * w0[1]),
                          h * (phi * w[2] + psi * w0[2])};
    if (st->rotation)
        sinter_compose_rotation(alpha, da); /* seed 003 eq. 45 */
}

/*
 * s = s^L + trapezoid with the forces f, torques tq of the current iterate (eq. 24-26).
 * Returns the first particle whose new state is not finite, or n.
 */
static size_t update_mechanics(sinter_stepper *st, const saved_state *a, double h, const double *f,
                               const double *tq)
{
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps);
    const double phi = st->staggered.phi, psi = 1.0 - phi;
    size_t bad = n;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t fl = ps->flags[i];
        double *x = ps->x + 3 * i, *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        const double *x0 = a->x + 3 * i, *v0 = a->v + 3 * i, *w0 = a->w + 3 * i;
        if (!(fl & SINTER_PARTICLE_FIXED)) {
            const double b = h / ps->mass[i];
            for (int d = 0; d < 3; ++d) {
                v[d] = v0[d] + b * (phi * f[3 * i + d] + psi * a->f[3 * i + d]);
                x[d] = x0[d] + h * (phi * v[d] + psi * v0[d]);
            }
        } else { /* prescribed: moves with its velocity, as in the explicit stepper */
            for (int d = 0; d < 3; ++d) {
                v[d] = v0[d];
                x[d] = x0[d] + h * v0[d];
            }
        }
        if (!(fl & (SINTER_PARTICLE_NO_ROTATION | SINTER_PARTICLE_FIXED))) {
            const double b = h / ps->inertia[i];
            for (int d = 0; d < 3; ++d)
                w[d] = w0[d] + b * (phi * tq[3 * i + d] + psi * a->tq[3 * i + d]);
        } else {
            memcpy(w, w0, 3 * sizeof(double));
        }
        rotate(st, a, h, i);
        const double check = x[0] + x[1] + x[2] + v[0] + v[1] + v[2] + w[0] + w[1] + w[2];
        if (!isfinite(check) && bad == n)
            bad = i;
    }
    return bad;
}

/* theta = theta^L + h/(m C) (phi Q + (1 - phi) Q^L), eq. 36. Returns the first bad particle or n.
 */
static size_t update_temperatures(sinter_stepper *st, const saved_state *a, double h,
                                  const double *q)
{
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps);
    const double phi = st->staggered.phi, psi = 1.0 - phi;
    size_t bad = n;
    for (size_t i = 0; i < n; ++i) {
        if (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE)
            continue;
        const sinter_enthalpy *H = sinter_particle_enthalpy(ps, i);
        double theta;
        if (H == NULL) {
            const double mc = ps->mass[i] * sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY);
            theta = a->theta[i] + h / mc * (phi * q[i] + psi * a->q[i]);
        } else { /* eq. 36 for the enthalpy: C(theta) or latent heat */
            theta = sinter_enthalpy_inverse(H, sinter_enthalpy_at(H, a->theta[i]) +
                                                   h / ps->mass[i] * (phi * q[i] + psi * a->q[i]));
        }
        ps->temperature[i] = theta;
        if (!(theta > 0.0 && theta < INFINITY) && bad == n)
            bad = i;
    }
    return bad;
}

/*
 * Eq. 47 for a field of `comps` components per particle: sum_i |now_i - prev_i| /
 * sum_i |now_i - start_i| over the particles whose flags do not contain `skip`. Two floors:
 * the change is 0 when it is at the round-off of the field, and the denominator is at least
 * n atol / TOL, so that a mean change per particle <= atol passes eq. 48 (atol = 0: the seed's
 * relative test alone).
 */
static double normalised_error(sinter_stepper *st, const double *now, const double *prev,
                               const double *start, int comps, uint32_t skip, double atol,
                               double tol, sinter_status *status)
{
    const sinter_particles *ps = st->ps;
    double num = 0.0, den = 0.0, scale = 0.0;
    size_t free_count = 0;
    if (st->reproducible) { /* exact sums: the same bits for any decomposition */
        double v[4];
        const sinter_status r = sinter_staggered_exact_errors(st, now, prev, start, comps, skip, v);
        if (r != SINTER_OK && *status == SINTER_OK)
            *status = r;
        num = v[0];
        den = v[1];
        scale = v[2];
        free_count = (size_t)v[3];
    }
    for (size_t i = 0; i < owned_rows(ps) && !st->reproducible; ++i) {
        if (ps->flags[i] & skip)
            continue;
        free_count++;
        const double *a = now + (size_t)comps * i, *b = prev + (size_t)comps * i,
                     *c = start + (size_t)comps * i;
        if (comps == 1) {
            num += fabs(a[0] - b[0]);
            den += fabs(a[0] - c[0]);
            scale += fabs(a[0]);
        } else {
            const double d1[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
            const double d2[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
            num += sqrt(d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
            den += sqrt(d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]);
            scale += sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        }
    }
    /* (default mode) sums over every subdomain: the count is exact as a double */
    if (st->domain.on && !st->reproducible) {
        double v[4] = {num, den, scale, (double)free_count};
        const sinter_status r = global_sum(st, v, 4);
        if (r != SINTER_OK && *status == SINTER_OK)
            *status = r;
        num = v[0];
        den = v[1];
        scale = v[2];
        free_count = (size_t)v[3];
    }
    if (num <= 8.0 * DBL_EPSILON * scale)
        return 0.0;
    den = fmax(den, (double)free_count * atol / tol);
    return den > 0.0 ? num / den : INFINITY;
}

/*
 * Step scale of one field after iteration k with normalised errors eps (now) and eps_prev
 * (iteration k - 1): Lambda_K of eq. 49 with eps_0 = 1 (see the top of the file). From k = 3 on
 * the last contraction rho = eps / eps_prev is known. When the iteration stagnates
 * (rho > 1/2: eq. 49's model eps_K = eta^K has stopped describing it, as when Coulomb friction
 * of a resting contact flips direction between iterates) the error is taken as a floor S h^p
 * that more iterations do not lower, and Lambda is at most (TOL/eps)^(1/p). *hopeless is set
 * when the last rate extrapolated to K_d misses the tolerance: eps rho^(K_d - k) > TOL.
 */
static double field_scale(const sinter_staggered *sg, double eps, double eps_prev, int k,
                          int *hopeless)
{
    if (eps <= 0.0)
        return INFINITY;
    const double p = sg->exponent, tol = sg->tolerance;
    double lambda = pow(tol, 1.0 / (p * sg->target_iterations)) / pow(eps, 1.0 / (p * k));
    if (k >= 3 && eps > tol) {
        const double rho = eps_prev > 0.0 ? eps / eps_prev : INFINITY;
        if (rho > 0.5)
            lambda = fmin(lambda, pow(tol / eps, 1.0 / p));
        if (!(eps * pow(fmin(rho, 1.0), sg->target_iterations - k) <= tol))
            *hopeless = 1;
    } else if (k >= 3 && eps > 0.5 * eps_prev) {
        lambda = fmin(lambda, pow(tol / eps, 1.0 / p));
    }
    return lambda;
}

/* ---- one attempt ------------------------------------------------------------------------ */

typedef struct attempt_result {
    int converged;
    int iterations;
    double eps_r, eps_theta; /* eq. 47 at the last iteration */
    double lambda;           /* eq. 49; scheme 1: the controller's ratio x (step_control.h) */
    double rho;              /* scheme 1: measured contraction (E_K / E_0)^(1/K), 0 if K = 0 */
    size_t bad;              /* particle with a non-finite state, or the count */
    const char *bad_field;
} attempt_result;

static sinter_status attempt(sinter_stepper *st, const saved_state *a, double t, double h,
                             attempt_result *res)
{
    sinter_staggered *sg = &st->staggered;
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps);
    const int thermal = st->thermal.count > 0;
    memset(res, 0, sizeof(*res));
    res->bad = n;
    double prev_r = 1.0, prev_t = 1.0; /* eq. 47 of the previous iteration */
    st->time = t + h;
    sinter_status s = st->walls != NULL ? sinter_walls_move(st->walls, t + h) : SINTER_OK;
    if (s != SINTER_OK)
        return s;
    memcpy(a->x_prev, a->x, 3 * n * sizeof(double));     /* x^0 = x^L */
    memcpy(a->theta_prev, a->theta, n * sizeof(double)); /* theta^0 = theta^L */
    double t0 = sinter_clock();
    size_t bad = update_mechanics(st, a, h, a->f, a->tq); /* s^1 from F^L */
    st->stats.seconds_integrate += sinter_clock() - t0;
    for (int k = 1; k <= sg->target_iterations; ++k) {
        res->iterations = k;
        st->stats.iterations++;
        if (any_bad(st, bad, n, &s)) {
            if (s != SINTER_OK)
                return s;
            res->bad = bad;
            res->bad_field = "position, velocity or spin not finite";
            res->lambda = 0.1;
            return SINTER_OK;
        }
        /* Evaluate at (s^K, theta^(K-1)); ps->temperature holds theta^(K-1). */
        s = evaluate(st, h);
        if (s != SINTER_OK)
            return s;
        t0 = sinter_clock();
        if (thermal) {
            for (size_t j = 0; j < st->thermal.count; ++j)
                sg->power[st->thermal.count + j] = st->thermal.slots[j].power;
            bad = update_temperatures(st, a, h, ps->heat);
            if (any_bad(st, bad, n, &s)) {
                if (s != SINTER_OK)
                    return s;
                st->stats.seconds_integrate += sinter_clock() - t0;
                res->bad = bad;
                res->bad_field = "temperature not positive and finite";
                res->lambda = 0.1;
                return SINTER_OK;
            }
        }
        /* Eq. 47-49. The first iterate's errors are 1 by definition (x^0 = x^L). */
        const double eps_r =
            k == 1 ? 1.0
                   : normalised_error(st, ps->x, a->x_prev, a->x, 3, SINTER_PARTICLE_FIXED,
                                      sg->position_tolerance, sg->tolerance, &s);
        const double eps_t = !thermal ? 0.0
                             : k == 1
                                 ? 1.0
                                 : normalised_error(st, ps->temperature, a->theta_prev, a->theta, 1,
                                                    SINTER_PARTICLE_FIXED_TEMPERATURE,
                                                    sg->temperature_tolerance, sg->tolerance, &s);
        if (s != SINTER_OK)
            return s;
        res->eps_r = eps_r;
        res->eps_theta = eps_t;
        const double z = fmax(eps_r, eps_t) / sg->tolerance; /* eq. 48 */
        int hopeless = 0;
        res->lambda = fmin(field_scale(sg, eps_r, prev_r, k, &hopeless),
                           field_scale(sg, eps_t, prev_t, k, &hopeless)); /* eq. 49 */
        prev_r = eps_r;
        prev_t = eps_t;
        if (z <= 1.0) {
            st->stats.seconds_integrate += sinter_clock() - t0;
            res->converged = 1;
            return SINTER_OK;
        }
        if (k == sg->target_iterations || hopeless) {
            st->stats.seconds_integrate += sinter_clock() - t0;
            break;
        }
        memcpy(a->x_prev, ps->x, 3 * n * sizeof(double));
        if (thermal)
            memcpy(a->theta_prev, ps->temperature, n * sizeof(double));
        bad = update_mechanics(st, a, h, ps->force, ps->torque); /* s^(K+1) from F^K */
        st->stats.seconds_integrate += sinter_clock() - t0;
    }
    return SINTER_OK;
}

/* ---- scheme 1: Anderson acceleration, WRMS test, PI step control, predictor -------------- */

/*
 * Scheme 1 ("scheme" = 1) keeps the trapezoidal rule and its fixed point, and changes how the
 * fixed point is found and how the step is chosen:
 *
 *  - The unknowns u = (x, v, w, theta) (10 per particle) and the map u -> G(u): evaluate the
 *    pipeline at u (positions and temperatures of the same iterate: no staggering lag, so the
 *    evaluation at the accepted iterate gives F^(L+1) and Q^(L+1) and no extra evaluation is
 *    needed) and apply the trapezoid (eq. 24-26, 36) with its forces and heat. G is the
 *    staggered iteration of Algorithm 1 made a Jacobi sweep; its fixed point is the same.
 *  - Anderson(m) acceleration of u_(k+1) = G(u_k) (anderson.h; option anderson_depth, 3;
 *    0 is the plain iteration). Anderson combinations are affine (weights summing to 1), so
 *    every iterate keeps x = x^L + h (phi v + (1 - phi) v^L); rotations follow the spins.
 *  - Convergence: the correction G(u_k) - u_k in a weighted RMS norm per quantity, as SUNDIALS'
 *    integrators weigh errors: weight 1/(rtol |d_i| + atol) with rtol = "tolerance" and
 *    - positions: d_i the predicted displacement of the particle over the step (the seed's
 *      eq. 47 relates the change to the step's motion, not to the coordinate, whose size
 *      depends on the origin); atol = position_tolerance, or 1e-6 rtol R_i where that is 0
 *      (a contact's overlap can be ~1e-6 R: a steel sphere resting on a steel floor,
 *      test_hard_cases.c; 1e-3 rtol R left it 12 % off Hertz's overlap);
 *    - temperatures: d_i = theta^L_i; atol = temperature_tolerance;
 *    - velocities and spins carry weight 0: the trapezoid ties a velocity correction dv to
 *      the position correction phi h dv, so the position test bounds them.
 *    u_k is accepted when both norms are <= 1 (u_k itself, whose evaluation is at hand).
 *  - Predictor: u_0 is the trapezoid with the forces, torques and heat powers extrapolated
 *    linearly from the two previous steps, F^L + (h / h_prev) (F^L - F^(L-1)); the first step
 *    (and the first after a change of particle order or count) uses F^L. Temperatures start
 *    from forward Euler instead of theta^L. The start only costs iterations when it is poor:
 *    the fixed point does not depend on it.
 *  - Step control: step_control.h, a PI controller on the measured contraction; an attempt is
 *    rejected when it diverges (E_k > E_0 from k = 3), when the measured rate cannot reach the
 *    tolerance within 2 K_d iterations, or at 2 K_d iterations.
 */

typedef struct aa_vectors {
    double *u, *g, *w; /* 10 n each: x, v, w (3n each), theta (n) */
} aa_vectors;

static sinter_status aa_reserve(sinter_stepper *st, aa_vectors *vec)
{
    sinter_staggered *sg = &st->staggered;
    const size_t n = owned_rows(st->ps);
    if (30 * n + 1 > sg->work_capacity) {
        double *p = sinter_realloc_array(st->ctx, sg->work, 30 * n + 1, sizeof(double));
        if (p == NULL)
            return sinter_last_status(st->ctx);
        sg->work = p;
        sg->work_capacity = 30 * n + 1;
    }
    if (7 * n + 1 > sg->hist_capacity) {
        double *p = sinter_realloc_array(st->ctx, sg->hist, 7 * n + 1, sizeof(double));
        if (p == NULL)
            return sinter_last_status(st->ctx);
        sg->hist = p;
        sg->hist_capacity = 7 * n + 1;
    }
    vec->u = sg->work;
    vec->g = sg->work + 10 * n;
    vec->w = sg->work + 20 * n;
    return sinter_anderson_reset(st->ctx, &sg->aa, 10 * n, sg->anderson_depth);
}

static void aa_pack(const sinter_particles *ps, double *u)
{
    const size_t n = owned_rows(ps);
    memcpy(u, ps->x, 3 * n * sizeof(double));
    memcpy(u + 3 * n, ps->v, 3 * n * sizeof(double));
    memcpy(u + 6 * n, ps->w, 3 * n * sizeof(double));
    memcpy(u + 9 * n, ps->temperature, n * sizeof(double));
}

/* ps <- u, rotations from the spins; returns the first particle with a bad state, or n. */
static size_t aa_unpack(sinter_stepper *st, const saved_state *a, double h, const double *u,
                        int thermal)
{
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps);
    memcpy(ps->x, u, 3 * n * sizeof(double));
    memcpy(ps->v, u + 3 * n, 3 * n * sizeof(double));
    memcpy(ps->w, u + 6 * n, 3 * n * sizeof(double));
    if (thermal)
        memcpy(ps->temperature, u + 9 * n, n * sizeof(double));
    size_t bad = n;
    for (size_t i = 0; i < n; ++i) {
        rotate(st, a, h, i);
        const double *x = ps->x + 3 * i, *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        const double check = x[0] + x[1] + x[2] + v[0] + v[1] + v[2] + w[0] + w[1] + w[2];
        const double theta = ps->temperature[i]; /* checked only where it is an unknown */
        const int bad_theta = thermal && !(ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE) &&
                              !(theta > 0.0 && theta < INFINITY);
        if ((!isfinite(check) || bad_theta) && bad == n)
            bad = i;
    }
    return bad;
}

/* WRMS weights (see above), scaled by 1/sqrt(count) per field so that ||W f||_2 is the
 * field's WRMS norm. Made once per attempt, at the predictor. */
static sinter_status aa_weights(sinter_stepper *st, const saved_state *a, double *w, int thermal)
{
    const sinter_particles *ps = st->ps;
    const sinter_staggered *sg = &st->staggered;
    const size_t n = owned_rows(ps);
    size_t nx = 0, nt = 0;
    for (size_t i = 0; i < n; ++i) {
        nx += !(ps->flags[i] & SINTER_PARTICLE_FIXED);
        nt += thermal && !(ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE);
    }
    if (st->domain.on) { /* the counts over every subdomain (exact as doubles) */
        double c[2] = {(double)nx, (double)nt};
        const sinter_status r = global_sum(st, c, 2);
        if (r != SINTER_OK)
            return r;
        nx = (size_t)c[0];
        nt = (size_t)c[1];
    }
    const double rtol = sg->tolerance;
    const double sx = nx > 0 ? 1.0 / sqrt(3.0 * (double)nx) : 0.0;
    const double st_ = nt > 0 ? 1.0 / sqrt((double)nt) : 0.0;
    memset(w, 0, 10 * n * sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        if (!(ps->flags[i] & SINTER_PARTICLE_FIXED)) {
            const double *x = ps->x + 3 * i, *x0 = a->x + 3 * i;
            const double d[3] = {x[0] - x0[0], x[1] - x0[1], x[2] - x0[2]};
            const double atol =
                sg->position_tolerance > 0.0 ? sg->position_tolerance : 1e-6 * rtol * ps->radius[i];
            const double wi = sx / (rtol * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + atol);
            for (int c = 0; c < 3; ++c)
                w[3 * i + c] = wi;
        }
        if (thermal && !(ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE))
            w[9 * n + i] = st_ / (rtol * fabs(a->theta[i]) + sg->temperature_tolerance);
    }
    return SINTER_OK;
}

/* WRMS norms of g - u for positions and temperatures (W already holds 1/sqrt(count)); with
 * domain operations the sums of squares over every subdomain. */
static sinter_status aa_norms(sinter_stepper *st, size_t n, const double *u, const double *g,
                              const double *w, double *ex, double *et)
{
    double sx = 0.0, st_ = 0.0;
    if (st->reproducible) { /* exact sums: the same bits for any decomposition */
        double sums[2] = {0.0, 0.0};
        const sinter_status s = sinter_staggered_exact_norms(st, n, u, g, w, sums);
        *ex = sqrt(sums[0]);
        *et = sqrt(sums[1]);
        return s;
    }
    for (size_t i = 0; i < 3 * n; ++i) {
        const double e = w[i] * (g[i] - u[i]);
        sx += e * e;
    }
    for (size_t i = 9 * n; i < 10 * n; ++i) {
        const double e = w[i] * (g[i] - u[i]);
        st_ += e * e;
    }
    double sums[2] = {sx, st_};
    const sinter_status s = global_sum(st, sums, 2);
    *ex = sqrt(sums[0]);
    *et = sqrt(sums[1]);
    return s;
}

/* The predictor's forces, torques and heat into f (3n), tq (3n), q (n). */
static void aa_predict(const sinter_stepper *st, const saved_state *a, double h, double *f,
                       double *tq, double *q)
{
    const sinter_staggered *sg = &st->staggered;
    const size_t n = owned_rows(st->ps);
    const int history = sg->history_valid && sg->history_count == n && sg->h_prev > 0.0;
    const double r = history ? h / sg->h_prev : 0.0;
    const double *fp = sg->hist, *tp = sg->hist + 3 * n, *qp = sg->hist + 6 * n;
    for (size_t i = 0; i < 3 * n; ++i) {
        f[i] = history ? a->f[i] + r * (a->f[i] - fp[i]) : a->f[i];
        tq[i] = history ? a->tq[i] + r * (a->tq[i] - tp[i]) : a->tq[i];
    }
    for (size_t i = 0; i < n; ++i)
        q[i] = history ? a->q[i] + r * (a->q[i] - qp[i]) : a->q[i];
}

static sinter_status attempt_anderson(sinter_stepper *st, const saved_state *a, double t, double h,
                                      attempt_result *res)
{
    sinter_staggered *sg = &st->staggered;
    sinter_particles *ps = st->ps;
    const size_t n = owned_rows(ps);
    const int thermal = st->thermal.count > 0;
    const int k_max = 2 * sg->target_iterations;
    memset(res, 0, sizeof(*res));
    res->bad = n;
    aa_vectors vec = {NULL, NULL, NULL};
    sinter_status s = aa_reserve(st, &vec);
    st->time = t + h;
    if (s == SINTER_OK)
        s = st->walls != NULL ? sinter_walls_move(st->walls, t + h) : SINTER_OK;
    if ((s = sinter_domain_agree(st->ctx, &st->domain, s)) != SINTER_OK)
        return s;
    /* Predictor u_0 (the image buffer is scratch until the first evaluation). */
    double t0 = sinter_clock();
    aa_predict(st, a, h, vec.g, vec.g + 3 * n, vec.g + 6 * n);
    size_t bad = update_mechanics(st, a, h, vec.g, vec.g + 3 * n);
    if (thermal && bad == n)
        bad = update_temperatures(st, a, h, vec.g + 6 * n);
    if ((s = aa_weights(st, a, vec.w, thermal)) != SINTER_OK)
        return s;
    aa_pack(ps, vec.u);
    st->stats.seconds_integrate += sinter_clock() - t0;
    double e0 = 0.0;
    for (int k = 0; k <= k_max; ++k) {
        res->iterations = k;
        if (any_bad(st, bad, n, &s)) {
            if (s != SINTER_OK)
                return s;
            res->bad = bad;
            res->bad_field = "position, velocity, spin or temperature not finite (or <= 0 K)";
            res->lambda = INFINITY;
            return SINTER_OK;
        }
        st->stats.iterations++;
        s = evaluate(st, h); /* at u_k */
        if (s != SINTER_OK)
            return s;
        t0 = sinter_clock();
        for (size_t j = 0; j < st->thermal.count; ++j)
            sg->power[st->thermal.count + j] = st->thermal.slots[j].power;
        /* G(u_k) */
        bad = update_mechanics(st, a, h, ps->force, ps->torque);
        if (thermal && bad == n)
            bad = update_temperatures(st, a, h, ps->heat);
        aa_pack(ps, vec.g);
        double ex, et;
        if ((s = aa_norms(st, n, vec.u, vec.g, vec.w, &ex, &et)) != SINTER_OK)
            return s;
        const double e = fmax(ex, et);
        res->eps_r = ex;
        res->eps_theta = et;
        if (k == 0)
            e0 = e;
        if (e <= 1.0) { /* accept u_k: back into the particles */
            bad = aa_unpack(st, a, h, vec.u, thermal);
            st->stats.seconds_integrate += sinter_clock() - t0;
            res->converged = 1;
            res->lambda = sinter_step_control_ratio(e0, e, k, sg->target_iterations);
            res->rho = k > 0 ? pow(e / e0, 1.0 / k) : 0.0;
            return SINTER_OK;
        }
        /* Rejection tests from k = 3: the first plain iteration may grow the error (beyond
         * the plain iteration's contraction limit, phi omega h > 1) before Anderson's first
         * two extrapolations bring it down. */
        const double x = sinter_step_control_ratio(e0, e, k, sg->target_iterations);
        res->lambda = isfinite(e) ? x : INFINITY;
        if (!isfinite(e) || k == k_max) {
            st->stats.seconds_integrate += sinter_clock() - t0;
            return SINTER_OK;
        }
        if (k >= 3) {
            const double rho = pow(e / e0, 1.0 / k);
            if (e > e0 || e * pow(rho, k_max - k) > 1.0) {
                st->stats.seconds_integrate += sinter_clock() - t0;
                return SINTER_OK;
            }
        }
        /* the inner products over every subdomain, exact in the reproducible mode */
        const sinter_anderson_sum sum = {anderson_sum, st,
                                         st->reproducible ? sinter_staggered_exact_dots : NULL};
        if (sinter_anderson_update(&sg->aa, vec.u, vec.g, vec.w, /* u_(k+1) */
                                   st->domain.on || st->reproducible ? &sum : NULL) < 0)
            return sinter_last_status(st->ctx);
        bad = aa_unpack(st, a, h, vec.u, thermal);
        st->stats.seconds_integrate += sinter_clock() - t0;
    }
    return SINTER_OK;
}

/* ---- the step ---------------------------------------------------------------------------- */

/* What did not converge, for the error message. */
static const char *limiting_field(const attempt_result *r)
{
    if (r->bad_field != NULL)
        return r->bad_field;
    return r->eps_theta > r->eps_r ? "temperature field" : "position field";
}

static sinter_status give_up_status(sinter_stepper *st, double t, double h, double h_next,
                                    const attempt_result *r);

static sinter_status give_up(sinter_stepper *st, const saved_state *a, double t, double h,
                             double h_next, const attempt_result *r)
{
    restore_state(st, a, t);
    st->forces_current = 0;
    return sinter_domain_agree(st->ctx, &st->domain, give_up_status(st, t, h, h_next, r));
}

/* give_up's status and message (for a decomposed run: the same code everywhere; the particle
 * with a bad state is named by the subdomain that holds it, the others report nothing). */
static sinter_status give_up_status(sinter_stepper *st, double t, double h, double h_next,
                                    const attempt_result *r)
{
    const sinter_staggered *sg = &st->staggered;
    if (st->domain.on && r->bad_field != NULL && r->bad >= owned_rows(st->ps))
        return SINTER_OK; /* (another subdomain's particle: its message is the one agreed) */
    char errors[96];
    if (st->thermal.count > 0)
        snprintf(errors, sizeof(errors), "positions %.3g, temperatures %.3g", r->eps_r,
                 r->eps_theta);
    else
        snprintf(errors, sizeof(errors), "positions %.3g", r->eps_r);
    if (r->bad < owned_rows(st->ps))
        return sinter_fail(st->ctx, SINTER_ERR_NOT_CONVERGED,
                           "staggered step at t = %.9g s: the fixed-point iteration diverged "
                           "with step %g s (particle %zu, id %llu: %s) and %s %g s; the last "
                           "accepted state is kept",
                           t, h, r->bad, (unsigned long long)st->ps->id[r->bad], r->bad_field,
                           sg->adaptive ? "the next step would fall below dt_min ="
                                        : "the step is fixed (adaptive = 0) at",
                           sg->adaptive ? sg->dt_min : h);
    if (!sg->adaptive)
        return sinter_fail(st->ctx, SINTER_ERR_NOT_CONVERGED,
                           "staggered step at t = %.9g s: the fixed-point iteration did not "
                           "converge in %d iterations with the fixed step %g s (adaptive = 0): "
                           "the %s did not meet the tolerance (normalised errors of eq. 47: %s; "
                           "tolerance %g); the last accepted state is kept",
                           t, r->iterations, h, limiting_field(r), errors, sg->tolerance);
    return sinter_fail(st->ctx, SINTER_ERR_NOT_CONVERGED,
                       "staggered step at t = %.9g s: the fixed-point iteration did not converge "
                       "in %d iterations with step %g s: the %s did not meet the tolerance "
                       "(normalised errors of eq. 47: %s; tolerance %g), and the next step %g s "
                       "would fall below dt_min = %g s; the last accepted state is kept",
                       t, r->iterations, h, limiting_field(r), errors, sg->tolerance, h_next,
                       sg->dt_min);
}

/* The positions at t of every row, for the sanity check: a->x itself without images, else
 * the owners' with the images' rows made from them (ghosts/ghosts.h), or with the ghosts of
 * other subdomains as they are now; NULL when out of memory. */
static const double *positions_at_start(sinter_stepper *st, const saved_state *a)
{
    const sinter_particles *ps = st->ps;
    if (ps->ghost_count == 0)
        return a->x;
    sinter_staggered *sg = &st->staggered;
    if (sinter_grow(st->ctx, (void **)&sg->x_rows, &sg->x_rows_capacity, 3 * ps->count + 1,
                    sizeof(double)) != SINTER_OK)
        return NULL;
    memcpy(sg->x_rows, a->x, 3 * owned_rows(ps) * sizeof(double));
    if (st->domain.on) /* ghosts of other subdomains: their owners check them (no motion here) */
        memcpy(sg->x_rows + 3 * owned_rows(ps), ps->x + 3 * owned_rows(ps),
               3 * ps->ghost_count * sizeof(double));
    else
        sinter_ghosts_copy_rows(&st->ghosts, ps, sg->x_rows, 1);
    return sg->x_rows;
}

/* The attempts of one step from the state at t (saved in a) until one is accepted, then the
 * commit and the next step's size; see staggered_step. */
static sinter_status staggered_attempts(sinter_stepper *st, const saved_state *saved, double t,
                                        double h, double *taken)
{
    sinter_staggered *sg = &st->staggered;
    const saved_state a = *saved;
    attempt_result r;
    int restarted = 0;
    sinter_status s = SINTER_OK;
    for (;;) {
        s = sg->scheme == 1 ? attempt_anderson(st, &a, t, h, &r) : attempt(st, &a, t, h, &r);
        if (s != SINTER_OK) {
            restore_state(st, &a, t);
            st->forces_current = 0;
            st->stats.rejected++;
            return s;
        }
        if (r.converged)
            break;
        /* Algorithm 1 step 7: restart at t with Lambda_K h. */
        st->stats.rejected++;
        const double h_next =
            sg->scheme == 1 ? sinter_step_control_reject(&sg->control, r.lambda, sg->exponent) * h
                            : fmin(fmax(r.lambda, 0.1), 0.9) * h;
        if (!sg->adaptive || h_next < sg->dt_min)
            return give_up(st, &a, t, h, h_next, &r);
        restore_state(st, &a, t);
        h = h_next;
        restarted = 1;
    }
    /* Accepted: (s^K, theta^K) at t + h. */
    s = sinter_sanity_domain(st, "staggered step", t, h);
    const double *x_start = s == SINTER_OK ? positions_at_start(st, &a) : a.x;
    if (s == SINTER_OK && x_start == NULL)
        s = sinter_last_status(st->ctx);
    if (s == SINTER_OK)
        s = sinter_sanity_step(st, x_start, t, h, NULL);
    s = sinter_domain_agree(st->ctx, &st->domain, s); /* (checks of this subdomain's particles) */
    if (s == SINTER_OK && st->thermal.count > 0) {
        /* Copy the iterate's slot powers before the evaluation overwrites them. */
        for (size_t j = 0; j < st->thermal.count; ++j)
            st->thermal.slots[j].applied =
                h * (sg->phi * sg->power[st->thermal.count + j] + (1.0 - sg->phi) * sg->power[j]);
        if (sg->scheme == 0)     /* scheme 1 evaluated the accepted state itself */
            s = evaluate(st, h); /* currents, F, Q of the accepted state */
    }
    if (s == SINTER_OK)
        s = sinter_stepper_commit(st);
    if (s != SINTER_OK) {
        restore_state(st, &a, t);
        st->forces_current = 0;
        st->stats.rejected++;
        return s;
    }
    for (size_t j = 0; j < st->thermal.count; ++j)
        st->thermal.slots[j].energy += st->thermal.slots[j].applied;
    st->thermal_last_h = h;
    if (sg->scheme == 1) {
        /* The predictor's history: F, torques and Q at t become F^(L-1) for the next step. */
        const size_t n = owned_rows(st->ps);
        memcpy(sg->hist, a.f, 3 * n * sizeof(double));
        memcpy(sg->hist + 3 * n, a.tq, 3 * n * sizeof(double));
        memcpy(sg->hist + 6 * n, a.q, n * sizeof(double));
        sg->history_valid = 1;
        sg->history_count = n;
        sg->h_prev = h;
        sg->contraction = r.rho;
        if (sg->adaptive)
            st->dt = fmin(sg->dt_max,
                          sinter_step_control_accept(&sg->control, r.lambda, sg->exponent) * h);
        st->stats.dt = st->dt;
        *taken = h;
        return SINTER_OK;
    }
    /* Eq. 49, Algorithm 1 step 6b-c; after a restart the step does not grow at once (the
     * usual safeguard of step controllers, e.g. Hairer, Norsett and Wanner, sec. II.4). */
    if (sg->adaptive)
        st->dt = fmin(sg->dt_max, fmin(fmax(r.lambda, 0.1), restarted ? 1.0 : 2.0) * h);
    st->stats.dt = st->dt;
    *taken = h;
    return SINTER_OK;
}

static sinter_status staggered_step(sinter_stepper *st, double h, double *taken)
{
    sinter_staggered *sg = &st->staggered;
    sinter_status s = SINTER_OK;
    sinter_stepper_adopt_history(st); /* (a portable restart's predictor history, by id) */
    if (st->domain.on)                /* (settings not yet supported across subdomains) */
        s = sinter_domain_agree(st->ctx, &st->domain, sinter_domain_check(st));
    if (s == SINTER_OK && st->domain.on) /* a migration refused during the last step, now */
        s = sinter_stepper_domain_accepted_stage(st);
    if (s == SINTER_OK)
        s = reserve(st);
    if ((s = sinter_domain_agree(st->ctx, &st->domain, s)) != SINTER_OK)
        return s;
    const double t = st->time;
    const saved_state a = saved_layout(sg, owned_rows(st->ps));
    save_state(st, &a);
    st->domain.in_attempt = st->domain.on; /* migration waits for the accepted state */
    s = staggered_attempts(st, &a, t, h, taken);
    st->domain.in_attempt = 0;
    return s;
}

sinter_status sinter_staggered_step(sinter_stepper *st, double h, double *taken)
{
    if (!sinter_ghosts_on(&st->ghosts))
        return staggered_step(st, h, taken);
    /* periodic: the owned particles into the cell between steps, none during (see the top) */
    sinter_status s = sinter_periodic_check(st);
    if (s != SINTER_OK)
        return s;
    (void)sinter_ghosts_wrap(&st->ghosts, st->ps);
    st->ghosts.hold = 1;
    s = staggered_step(st, h, taken);
    st->ghosts.hold = 0;
    forward_images(st); /* the images of the accepted (or the kept) state */
    return s;
}
