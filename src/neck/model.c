/*
 * Public face of the 7DOF neck model: the option-carrying handle and the two-particle driver
 * sinter_neck_two_particles (include/sinter.h, section "Neck (7DOF) submodel").
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "neck/neck.h"
#include "stepper/stepper.h" /* sinter_clock */

enum {
    OPTION_EPSILON,
    OPTION_H0_RATIO,
    OPTION_RTOL,
    OPTION_ATOL,
    OPTION_INITIAL_STEP,
    OPTION_MAX_STEPS,
    OPTION_INTEGRATOR,
    OPTION_RK4_STEPS,
    OPTION_RK4_TIME_SCALE,
    OPTION_ERROR_SCALE,
    OPTION_VALIDITY,
    OPTION_VALIDITY_COORDINATION,
    OPTION_VALIDITY_GREEN_DENSITY,
    OPTION_COUNT
};

enum { OPEN_NONE = 0, OPEN_MIN = 1, OPEN_MAX = 2, WHOLE = 4 };

typedef struct option_spec {
    const char *key;
    double default_value;
    double min_value;
    double max_value;
    int flags;
} option_spec;

/* Indexed by the OPTION_ enum; documented in include/sinter.h. */
static const option_spec OPTIONS[OPTION_COUNT] = {
    {"epsilon", 0.01, 0.0, 0.1, OPEN_MIN},            /* docs/7dof.md §4 */
    {"h0_ratio", 1.5, 1.0, 2.0, OPEN_MIN | OPEN_MAX}, /* docs/7dof.md §4: h0 in (x0, 2 x0) */
    {"rtol", 1e-8, 1e-14, 1e-2, OPEN_NONE},
    {"atol", 0.0, 0.0, 1.0, OPEN_NONE},           /* 0: 1e-14 min(R_A, R_B), docs/7dof.md §4 */
    {"initial_step", 1e-12, 0.0, 1e6, OPEN_NONE}, /* docs/7dof.md §4 */
    {"max_steps", 1e6, 1.0, 1e12, WHOLE},
    {"integrator", 0.0, 0.0, 1.0, WHOLE},
    {"rk4_steps", 20000.0, 1.0, 1e10, WHOLE},
    {"rk4_time_scale", 1e-6, 0.0, 1e6, OPEN_MIN},
    {"error_scale", 1.0, 0.0, 1.0, WHOLE}, /* neck.h: sinter_neck_error_scale */
    {"validity", 1.0, 0.0, 2.0, WHOLE},    /* 0 off, 1 warn, 2 error (docs/7dof.md §2.6) */
    {"validity_coordination", 6.0, 0.0, 100.0, OPEN_NONE},
    {"validity_green_density", 0.6, 0.0, 1.0, OPEN_NONE},
};

struct sinter_neck_model {
    sinter_ctx *ctx;
    double option[OPTION_COUNT];
    sinter_neck_solver *solver;    /* created at the first CVODE run */
    sinter_neck_counters counters; /* of the last run */
    double seconds;
};

sinter_status sinter_neck_model_create(sinter_neck_model **out, sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    sinter_neck_model *nm = sinter_calloc(ctx, 1, sizeof(*nm));
    if (nm == NULL)
        return SINTER_ERR_NOMEM;
    nm->ctx = ctx;
    for (int k = 0; k < OPTION_COUNT; ++k)
        nm->option[k] = OPTIONS[k].default_value;
    *out = nm;
    return SINTER_OK;
}

void sinter_neck_model_destroy(sinter_neck_model *nm)
{
    if (nm == NULL)
        return;
    sinter_neck_solver_destroy(nm->solver);
    sinter_free(nm->ctx, nm);
}

static int find_option(const char *key)
{
    for (int k = 0; k < OPTION_COUNT; ++k)
        if (strcmp(OPTIONS[k].key, key) == 0)
            return k;
    return -1;
}

static sinter_status unknown_option(sinter_ctx *ctx, const char *who, const char *key)
{
    return sinter_fail(
        ctx, SINTER_ERR_NOT_FOUND,
        "%s: unknown neck model option '%s'; known: epsilon, h0_ratio, rtol, atol, "
        "initial_step, max_steps, integrator, rk4_steps, rk4_time_scale, error_scale, "
        "validity, validity_coordination, validity_green_density",
        who, key);
}

sinter_status sinter_neck_model_set(sinter_neck_model *nm, const char *key, double value)
{
    if (nm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(nm->ctx, key);
    const int k = find_option(key);
    if (k < 0)
        return unknown_option(nm->ctx, "sinter_neck_model_set", key);
    const option_spec *o = &OPTIONS[k];
    const int below = (o->flags & OPEN_MIN) ? !(value > o->min_value) : !(value >= o->min_value);
    const int above = (o->flags & OPEN_MAX) ? !(value < o->max_value) : !(value <= o->max_value);
    if (!isfinite(value) || below || above || ((o->flags & WHOLE) && value != floor(value)))
        return sinter_fail(nm->ctx, SINTER_ERR_INVALID,
                           "sinter_neck_model_set: %s = %g is invalid; it must be %s in %s%g, "
                           "%g%s",
                           key, value, (o->flags & WHOLE) ? "a whole number" : "finite and",
                           (o->flags & OPEN_MIN) ? "(" : "[", o->min_value, o->max_value,
                           (o->flags & OPEN_MAX) ? ")" : "]");
    nm->option[k] = value;
    return SINTER_OK;
}

sinter_status sinter_neck_model_get(const sinter_neck_model *nm, const char *key, double *value)
{
    if (nm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(nm->ctx, key);
    SINTER_CHECK_NULL(nm->ctx, value);
    const int k = find_option(key);
    if (k < 0)
        return unknown_option(nm->ctx, "sinter_neck_model_get", key);
    *value = nm->option[k];
    return SINTER_OK;
}

static sinter_status check_arguments(sinter_ctx *ctx, double radius_a, double radius_b,
                                     size_t n_times, const double *times,
                                     const double *temperatures, size_t n_out,
                                     const double *out_times, const double *neck_radius,
                                     const double *shrinkage)
{
    static const char *const WHO = "sinter_neck_two_particles";
    if (!(radius_a > 0.0) || !(radius_b > 0.0) || !isfinite(radius_a) || !isfinite(radius_b))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: radii %g m and %g m must be positive and finite", WHO, radius_a,
                           radius_b);
    if (n_times == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the temperature schedule needs at least one point", WHO);
    SINTER_CHECK_NULL(ctx, times);
    SINTER_CHECK_NULL(ctx, temperatures);
    for (size_t k = 0; k < n_times; ++k) {
        if (!isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: schedule time %zu is %g s; times must be finite and "
                               "strictly increasing",
                               WHO, k, times[k]);
        if (!(temperatures[k] > 0.0) || !isfinite(temperatures[k]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: schedule temperature %zu is %g K; it must be positive and "
                               "finite",
                               WHO, k, temperatures[k]);
    }
    if (n_out == 0)
        return SINTER_OK;
    SINTER_CHECK_NULL(ctx, out_times);
    SINTER_CHECK_NULL(ctx, neck_radius);
    SINTER_CHECK_NULL(ctx, shrinkage);
    for (size_t k = 0; k < n_out; ++k)
        if (!isfinite(out_times[k]) || !(out_times[k] >= times[0]) ||
            (k > 0 && out_times[k] < out_times[k - 1]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: output time %zu is %g s; output times must be finite, "
                               "nondecreasing and >= the schedule's start %g s",
                               WHO, k, out_times[k], times[0]);
    return SINTER_OK;
}

/*
 * The validity guard (docs/7dof.md §2.6) at the output times, in order: the neck ratio against
 * the impingement limit of validity_coordination equal necks, and the relative density a packing
 * of validity_green_density would reach shrinking as the pair does, against 0.8 (seed 001 sec.
 * 4.2). A warning for the first output past each limit; with validity = 2 an error
 * (SINTER_ERR_DOMAIN) there, the later outputs set to NaN.
 */
static sinter_status check_validity(const sinter_neck_model *nm, double radius, size_t n_out,
                                    const double *out_times, double *neck_radius, double *shrinkage,
                                    double *states)
{
    static const char *const WHO = "sinter_neck_two_particles";
    const int mode = (int)nm->option[OPTION_VALIDITY];
    const double coordination = nm->option[OPTION_VALIDITY_COORDINATION];
    const double green = nm->option[OPTION_VALIDITY_GREEN_DENSITY];
    const double ratio_limit = sinter_neck_impingement_ratio(coordination);
    int warned_ratio = 0, warned_density = 0;
    char what[256];
    for (size_t k = 0; k < n_out && mode > 0; ++k) {
        const double ratio = neck_radius[k] / radius;
        const double density = sinter_neck_pair_density(green, shrinkage[k]);
        what[0] = '\0';
        if (!warned_ratio && ratio > ratio_limit) {
            warned_ratio = 1;
            snprintf(what, sizeof(what),
                     "the neck ratio x/R = %.4g passed %.4g, where the necks of a particle "
                     "with %g neighbours impinge (docs/7dof.md section 2.6), at t = %.6g s",
                     ratio, ratio_limit, coordination, out_times[k]);
        } else if (!warned_density && green > 0.0 && density > SINTER_NECK_DENSITY_LIMIT) {
            warned_density = 1;
            snprintf(what, sizeof(what),
                     "the relative density %.4g of a packing of green density %g shrinking as "
                     "the pair (shrinkage %.4g) passed the model's limit %g (seed 001 sec. 4.2), "
                     "at t = %.6g s",
                     density, green, shrinkage[k], SINTER_NECK_DENSITY_LIMIT, out_times[k]);
        }
        if (what[0] == '\0')
            continue;
        if (mode == 1) {
            sinter_log(nm->ctx, SINTER_LOG_WARNING, "%s: %s", WHO, what);
            --k; /* the same output may pass the other limit too */
            continue;
        }
        for (size_t j = k + 1; j < n_out; ++j) {
            neck_radius[j] = NAN;
            shrinkage[j] = NAN;
            if (states != NULL)
                for (size_t d = 0; d < SINTER_NECK_DOF; ++d)
                    states[SINTER_NECK_DOF * j + d] = NAN;
        }
        return sinter_fail(nm->ctx, SINTER_ERR_DOMAIN, "%s: %s", WHO, what);
    }
    return SINTER_OK;
}

sinter_status sinter_neck_two_particles(sinter_neck_model *nm, const sinter_material *m,
                                        double radius_a, double radius_b, size_t n_times,
                                        const double *times, const double *temperatures,
                                        size_t n_out, const double *out_times, double *neck_radius,
                                        double *shrinkage, double *state)
{
    static const char *const WHO = "sinter_neck_two_particles";
    if (nm == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = nm->ctx;
    SINTER_CHECK_NULL(ctx, m);
    sinter_status status = check_arguments(ctx, radius_a, radius_b, n_times, times, temperatures,
                                           n_out, out_times, neck_radius, shrinkage);
    if (status != SINTER_OK)
        return status;
    const double started = sinter_clock();
    memset(&nm->counters, 0, sizeof(nm->counters));
    nm->seconds = 0.0;
    if (n_out == 0)
        return SINTER_OK;
    for (size_t k = 0; k < n_out; ++k) {
        neck_radius[k] = NAN;
        shrinkage[k] = NAN;
    }

    sinter_neck_material material;
    sinter_neck_material_from(m, &material);
    sinter_neck_state pair;
    if (sinter_neck_state_init(&pair, radius_a, radius_b, nm->option[OPTION_EPSILON],
                               nm->option[OPTION_H0_RATIO], times[0]) != 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: cannot seed a neck with epsilon = %g and h0_ratio = %g between "
                           "radii %g m and %g m (7dof.md section 4)",
                           WHO, nm->option[OPTION_EPSILON], nm->option[OPTION_H0_RATIO], radius_a,
                           radius_b);

    /* States go to the caller's array when given, else to a scratch array. */
    double *states = state;
    if (states == NULL) {
        if (sinter_mul_overflows(n_out, SINTER_NECK_DOF * sizeof(double)))
            return sinter_fail(ctx, SINTER_ERR_OVERFLOW, "%s: %zu outputs overflow", WHO, n_out);
        states = sinter_alloc(ctx, n_out * SINTER_NECK_DOF * sizeof(double));
        if (states == NULL)
            return SINTER_ERR_NOMEM;
    }
    for (size_t k = 0; k < n_out * SINTER_NECK_DOF; ++k)
        states[k] = NAN;

    const sinter_neck_schedule schedule = {n_times, times, temperatures};
    const sinter_neck_outputs outputs = {n_out, out_times, states};
    const double t_end = out_times[n_out - 1];
    if (nm->option[OPTION_INTEGRATOR] == 1.0) {
        status = sinter_neck_rk4_advance(
            ctx, &pair, &material, &schedule, t_end, (uint64_t)nm->option[OPTION_RK4_STEPS],
            nm->option[OPTION_RK4_TIME_SCALE], &outputs, &nm->counters);
    } else {
        if (nm->solver == NULL)
            status = sinter_neck_solver_create(&nm->solver, ctx);
        if (status == SINTER_OK) {
            sinter_neck_tolerances tol;
            sinter_neck_tolerances_default(&tol);
            tol.rtol = nm->option[OPTION_RTOL];
            tol.atol = nm->option[OPTION_ATOL];
            tol.initial_step = nm->option[OPTION_INITIAL_STEP];
            tol.max_steps = (long)nm->option[OPTION_MAX_STEPS];
            tol.error_scale = (int)nm->option[OPTION_ERROR_SCALE];
            status = sinter_neck_advance_pair(nm->solver, &pair, &material, &schedule, t_end, &tol,
                                              &outputs, &nm->counters);
        }
    }

    /* docs/7dof.md §5 outputs: x = y1; Delta L / L0 = (L0 - (y4 + y7)) / L0 (seed 001 eq. 13).
     * NaN states (not reached) stay NaN. */
    const double l0 = pair.center_distance0;
    for (size_t k = 0; k < n_out; ++k) {
        const double *y = states + SINTER_NECK_DOF * k;
        neck_radius[k] = y[SINTER_NECK_X];
        shrinkage[k] = (l0 - (y[SINTER_NECK_LA] + y[SINTER_NECK_LB])) / l0;
    }
    if (status == SINTER_OK)
        status = check_validity(nm, fmin(radius_a, radius_b), n_out, out_times, neck_radius,
                                shrinkage, state);
    if (states != state)
        sinter_free(ctx, states);
    nm->seconds = sinter_clock() - started;
    return status;
}

sinter_status sinter_neck_get_stats(const sinter_neck_model *nm, sinter_neck_stats *stats)
{
    if (nm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(nm->ctx, stats);
    if (stats->struct_size != sizeof(sinter_neck_stats))
        return sinter_fail(nm->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_neck_get_stats: struct_size is %zu, expected %zu",
                           stats->struct_size, sizeof(sinter_neck_stats));
    stats->steps = nm->counters.steps;
    stats->rhs_evaluations = nm->counters.rhs_evaluations;
    stats->jacobian_evaluations = nm->counters.jacobian_evaluations;
    stats->error_test_failures = nm->counters.error_test_failures;
    stats->nonlinear_iterations = nm->counters.nonlinear_iterations;
    stats->nonlinear_failures = nm->counters.nonlinear_failures;
    stats->segments = nm->counters.segments;
    stats->seconds = nm->seconds;
    return SINTER_OK;
}
