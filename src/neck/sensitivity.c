/*
 * Forward sensitivities of the two-particle 7DOF model with respect to its Arrhenius data and
 * the reconstruction's path constants (sinter_neck_sensitivities, include/sinter.h;
 * docs/calibration.md §3).
 *
 * For a parameter p the sensitivity s = dy/dp obeys the forward sensitivity equation
 *     ds/dt = J(y) s + df/dp,   s(t0) = 0
 * (the seeded neck of docs/7dof.md §4 does not depend on the diffusion data). The right-hand
 * side of docs/7dof.md §3 is linear in each mechanism's mobility D n_frac / (k_B T) with
 * D = D0 exp(-Q / (R T)) (seed 001 eq. 4-5), so exactly
 *     df/d ln D0_m = f_m(y)          (f with only mechanism m's mobility kept)
 *     df/dQ_m      = -f_m(y) / (R T)
 * and only the parameters of the phase active on a piece contribute there. The path constants
 * (docs/7dof.md §3) act on both phases and enter each flux as 1 / ds, so exactly
 *     df/d ln(boundary path) = -f_{I,II},  df/d ln(cone path) = -f_{III,IV},
 *     df/d ln(cap path) = -f_{V,VI},       df/d ln n_v = f_lattice
 * (f with only those fluxes kept). J(y) s is a central
 * difference of f along s. The state and its sensitivities form one system of 7 (1 + P)
 * equations, integrated by CVODE (BDF, Newton with the block-diagonal matrix of 7x7 blocks
 * I - gamma J, the simultaneous-corrector approximation CVODES makes) piece by piece between the
 * schedule points and phase switches, as cvode_driver.c does for the state alone; y and s are
 * continuous across a piece boundary, whose time does not depend on the parameters.
 *
 * Why not CVODES itself: CVODE and CVODES export the same symbol names, so the library cannot
 * link both, and moving every neck integration to CVODES is a change of the state path's
 * library that this file need not make. The equations integrated are CVODES's.
 *
 * An activation energy is integrated as q = Q / (R T_s), T_s = 1000 K, so that every
 * sensitivity is a length of the state's order and weights made from the state fit them all.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "neck/neck.h"

#define DOF SINTER_NECK_DOF
#define MAX_PARAMS 16
#define Q_SCALE_TEMPERATURE 1000.0 /* T_s [K] of q = Q / (R T_s) */

enum { MECH_LATTICE = 0, MECH_SURFACE = 1, MECH_BOUNDARY = 2 };
enum { PATH_NONE = 0, PATH_BOUNDARY = 1, PATH_CONE = 2, PATH_CAP = 3 };

typedef struct parameter {
    int mechanism; /* MECH_* (for PATH_NONE) */
    int phase;     /* 0 base set, 1 the _HOT set, -1 both (path constants, n_v) */
    int energy;    /* 0: ln D0 (ln of the value), 1: q = Q / (R T_s) */
    int path;      /* PATH_*: ln of that path constant */
} parameter;

typedef struct problem {
    sinter_ctx *ctx;
    const sinter_neck_material *material;
    size_t count; /* parameters */
    parameter param[MAX_PARAMS];
    int phase;
    double segment_start, segment_end, temperature_start, temperature_end;
    double rtol, atol;
    int error_scale;
    int domain_hit;
    sinter_neck_domain_error domain;
    char message[256];
} problem;

/* Which parameter a material key is, or -1. */
static int classify(sinter_material_param key, parameter *out)
{
    static const struct {
        sinter_material_param key;
        parameter p;
    } TABLE[MAX_PARAMS] = {
        {SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, {MECH_LATTICE, 0, 0, PATH_NONE}},
        {SINTER_MAT_LATTICE_ACTIVATION_ENERGY, {MECH_LATTICE, 0, 1, PATH_NONE}},
        {SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR, {MECH_SURFACE, 0, 0, PATH_NONE}},
        {SINTER_MAT_SURFACE_ACTIVATION_ENERGY, {MECH_SURFACE, 0, 1, PATH_NONE}},
        {SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, {MECH_BOUNDARY, 0, 0, PATH_NONE}},
        {SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY, {MECH_BOUNDARY, 0, 1, PATH_NONE}},
        {SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT, {MECH_LATTICE, 1, 0, PATH_NONE}},
        {SINTER_MAT_LATTICE_ACTIVATION_ENERGY_HOT, {MECH_LATTICE, 1, 1, PATH_NONE}},
        {SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT, {MECH_SURFACE, 1, 0, PATH_NONE}},
        {SINTER_MAT_SURFACE_ACTIVATION_ENERGY_HOT, {MECH_SURFACE, 1, 1, PATH_NONE}},
        {SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT, {MECH_BOUNDARY, 1, 0, PATH_NONE}},
        {SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY_HOT, {MECH_BOUNDARY, 1, 1, PATH_NONE}},
        /* n_v scales the lattice mobility of both phases: exactly like ln D0_v of each */
        {SINTER_MAT_LATTICE_MOBILE_FRACTION, {MECH_LATTICE, -1, 0, PATH_NONE}},
        {SINTER_MAT_NECK_BOUNDARY_PATH, {MECH_LATTICE, -1, 0, PATH_BOUNDARY}},
        {SINTER_MAT_NECK_CONE_PATH, {MECH_LATTICE, -1, 0, PATH_CONE}},
        {SINTER_MAT_NECK_CAP_PATH, {MECH_LATTICE, -1, 0, PATH_CAP}},
    };
    for (int k = 0; k < MAX_PARAMS; ++k)
        if (TABLE[k].key == key) {
            *out = TABLE[k].p;
            return k;
        }
    return -1;
}

static double temperature_at(const problem *pb, double t)
{
    if (pb->temperature_end == pb->temperature_start)
        return pb->temperature_start;
    const double w = (t - pb->segment_start) / (pb->segment_end - pb->segment_start);
    return pb->temperature_start + w * (pb->temperature_end - pb->temperature_start);
}

/* The coefficients with only one mechanism's mobility kept. */
static sinter_neck_coeffs only(const sinter_neck_coeffs *c, int mechanism)
{
    sinter_neck_coeffs m = *c;
    m.mobility_lattice = mechanism == MECH_LATTICE ? c->mobility_lattice : 0.0;
    m.mobility_surface = mechanism == MECH_SURFACE ? c->mobility_surface : 0.0;
    m.mobility_boundary = mechanism == MECH_BOUNDARY ? c->mobility_boundary : 0.0;
    return m;
}

/* df/d ln(path) = -(f with only the fluxes on that path kept), docs/7dof.md §3: the factors are
 * 1 / ds of I-II (boundary_factor), of V-VI (cap_factor) and of III-IV (cone_factor cap_factor),
 * so zeroing cone_factor and cap_factor keeps I-II, zeroing boundary_factor and cone_factor keeps
 * V-VI, and III-IV is the rest of f without I-II. */
static void path_derivative(const double *y, const sinter_neck_geometry *g,
                            const sinter_neck_coeffs *c, int path, double *out)
{
    sinter_neck_coeffs kept = *c;
    double rest[DOF];
    kept.boundary_factor = path == PATH_BOUNDARY ? c->boundary_factor : 0.0;
    kept.cone_factor = path == PATH_CONE ? c->cone_factor : 0.0;
    kept.cap_factor = path == PATH_BOUNDARY ? 0.0 : c->cap_factor;
    sinter_neck_rhs_at(y, g, &kept, out, NULL);
    if (path == PATH_CONE) { /* out = III-VI; take V-VI away */
        kept.cone_factor = 0.0;
        sinter_neck_rhs_at(y, g, &kept, rest, NULL);
        for (int i = 0; i < DOF; ++i)
            out[i] -= rest[i];
    }
    for (int i = 0; i < DOF; ++i)
        out[i] = -out[i];
}

/* f at y + e with e = sigma * direction; returns 0, or 1 outside the domain. */
static int rhs_shifted(const double *y, const double *direction, double sigma,
                       const sinter_neck_coeffs *c, double *out, sinter_neck_domain_error *err)
{
    double shifted[DOF];
    for (int i = 0; i < DOF; ++i)
        shifted[i] = y[i] + sigma * direction[i];
    return sinter_neck_rhs(shifted, c, out, err, NULL) != SINTER_NECK_VALID;
}

static int augmented_rhs(realtype t, N_Vector v, N_Vector vdot, void *user)
{
    problem *pb = user;
    const double *y = N_VGetArrayPointer(v);
    double *ydot = N_VGetArrayPointer(vdot);
    const double temperature = temperature_at(pb, t);
    sinter_neck_coeffs c;
    sinter_neck_coeffs_eval(pb->material, pb->phase, temperature, &c);
    sinter_neck_geometry g;
    sinter_neck_domain_error err;
    if (sinter_neck_geometry_eval(y, &g) != 0 ||
        sinter_neck_check_domain(y, &g, &err) != SINTER_NECK_VALID) {
        sinter_neck_check_domain(y, NULL, &err);
        err.time = t;
        pb->domain = err;
        pb->domain_hit = 1;
        return 1; /* recoverable: CVODE retries with a smaller step */
    }
    sinter_neck_rhs_at(y, &g, &c, ydot, NULL);

    /* Lengths against which a shift along s is measured: x, and min(|y_i|, H_P) per side. */
    double scale[DOF];
    scale[SINTER_NECK_X] = fabs(y[SINTER_NECK_X]);
    for (int p = 0; p < 2; ++p)
        for (int k = 1; k <= 3; ++k)
            scale[k + 3 * p] = fmin(fabs(y[k + 3 * p]), g.side[p].cone_height);

    for (size_t j = 0; j < pb->count; ++j) {
        const double *s = y + DOF * (j + 1);
        double *sdot = ydot + DOF * (j + 1);
        /* J s by a central difference along s, each component shifted by at most 1e-6 of its
         * length scale (the error is then of order 1e-12 relative, the rounding 1e-10). */
        double largest = 0.0;
        for (int i = 0; i < DOF; ++i)
            largest = fmax(largest, fabs(s[i]) / scale[i]);
        if (largest > 0.0) {
            const double sigma = 1e-6 / largest;
            double up[DOF], down[DOF];
            if (rhs_shifted(y, s, sigma, &c, up, &err) ||
                rhs_shifted(y, s, -sigma, &c, down, &err)) {
                err.time = t; /* the shift left the domain: CVODE retries with a smaller step */
                pb->domain = err;
                pb->domain_hit = 1;
                return 1;
            }
            for (int i = 0; i < DOF; ++i)
                sdot[i] = (up[i] - down[i]) / (2.0 * sigma);
        } else {
            for (int i = 0; i < DOF; ++i)
                sdot[i] = 0.0;
        }
        const parameter *p = &pb->param[j];
        if (p->phase >= 0 && p->phase != pb->phase)
            continue; /* the other phase's data do not act on this piece */
        double fm[DOF];
        if (p->path != PATH_NONE) {
            path_derivative(y, &g, &c, p->path, fm);
        } else {
            const sinter_neck_coeffs cm = only(&c, p->mechanism);
            sinter_neck_rhs_at(y, &g, &cm, fm, NULL);
        }
        /* df/dq = -(T_s / T) f_m with q = Q / (R T_s); df/d ln D0 = f_m. */
        const double factor = p->energy ? -Q_SCALE_TEMPERATURE / temperature : 1.0;
        for (int i = 0; i < DOF; ++i)
            sdot[i] += factor * fm[i];
    }
    return 0;
}

/* The state's weights (sinter_neck_error_weights, its error scale) for y; for every sensitivity
 * the per-component weights 1 / (rtol |y_i| + atol) of the same state. The geometry scale's
 * min(|y_i|, H_P) on the sensitivities too made the titanium alpha-surface case 3.7 times dearer
 * (0.23 s against 0.06 s CPU for E14B at rtol 1e-9) for results that agree with differences
 * equally well (1e-5). */
static int augmented_weights(N_Vector v, N_Vector w, void *user)
{
    const problem *pb = user;
    const double *y = N_VGetArrayPointer(v);
    double *out = N_VGetArrayPointer(w);
    sinter_neck_error_weights(y, pb->rtol, pb->atol, pb->error_scale, out);
    double component[DOF];
    sinter_neck_error_weights(y, pb->rtol, pb->atol, SINTER_NECK_SCALE_COMPONENT, component);
    for (size_t j = 1; j <= pb->count; ++j)
        memcpy(out + DOF * j, component, DOF * sizeof(double));
    return 0;
}

/* Block-diagonal Newton matrix: J(y) on every 7x7 diagonal block. */
static int augmented_jacobian(realtype t, N_Vector v, N_Vector fv, SUNMatrix jac, void *user,
                              N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    (void)tmp1;
    (void)tmp2;
    (void)tmp3;
    problem *pb = user;
    sinter_neck_coeffs c;
    sinter_neck_coeffs_eval(pb->material, pb->phase, temperature_at(pb, t), &c);
    double dense[DOF * DOF];
    if (sinter_neck_jacobian(N_VGetArrayPointer(v), N_VGetArrayPointer(fv), &c, dense) !=
        SINTER_NECK_VALID)
        return 1;
    SUNMatZero(jac);
    for (size_t b = 0; b <= pb->count; ++b)
        for (int j = 0; j < DOF; ++j) {
            realtype *column = SM_COLUMN_D(jac, DOF * b + (size_t)j);
            for (int i = 0; i < DOF; ++i)
                column[DOF * b + (size_t)i] = dense[i + DOF * j];
        }
    return 0;
}

static void error_handler(int code, const char *module, const char *function, char *msg, void *user)
{
    (void)module;
    problem *pb = user;
    if (code == CV_WARNING)
        return;
    snprintf(pb->message, sizeof(pb->message), "%s: %s", function, msg);
}

/* Outputs of one state (x/R, shrinkage) and their derivatives (ln D0, ln of a path constant or
 * n_v, or Q [J/mol]). */
static void write_output(const problem *pb, const double *v, double radius, double l0, size_t k,
                         double *neck_ratio, double *shrinkage, double *d_neck_ratio,
                         double *d_shrinkage)
{
    neck_ratio[k] = v[SINTER_NECK_X] / radius;
    shrinkage[k] = (l0 - (v[SINTER_NECK_LA] + v[SINTER_NECK_LB])) / l0;
    for (size_t j = 0; j < pb->count; ++j) {
        const double *s = v + DOF * (j + 1);
        const double unit =
            pb->param[j].energy ? 1.0 / (SINTER_NECK_GAS_CONSTANT * Q_SCALE_TEMPERATURE) : 1.0;
        d_neck_ratio[k * pb->count + j] = s[SINTER_NECK_X] / radius * unit;
        d_shrinkage[k * pb->count + j] = -(s[SINTER_NECK_LA] + s[SINTER_NECK_LB]) / l0 * unit;
    }
}

static double option(const sinter_neck_model *nm, const char *key)
{
    double value = NAN;
    sinter_neck_model_get(nm, key, &value);
    return value;
}

static sinter_status check_arguments(sinter_ctx *ctx, const sinter_neck_model *nm, double radius_a,
                                     double radius_b, size_t n_times, const double *times,
                                     const double *temperatures, size_t n_params,
                                     const sinter_material_param *params, parameter *parsed,
                                     size_t n_out, const double *out_times)
{
    static const char *const WHO = "sinter_neck_sensitivities";
    if (option(nm, "integrator") != 0.0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the sensitivities need the CVODE integrator (integrator = 0)", WHO);
    if (!(isfinite(radius_a) && radius_a > 0.0 && isfinite(radius_b) && radius_b > 0.0))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: radii %g m and %g m must be positive and finite", WHO, radius_a,
                           radius_b);
    if (n_times == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: the schedule is empty", WHO);
    for (size_t k = 0; k < n_times; ++k) {
        if (!isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: schedule time %zu is %g s; times must be finite and "
                               "strictly increasing",
                               WHO, k, times[k]);
        if (!(isfinite(temperatures[k]) && temperatures[k] > 0.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: schedule temperature %zu is %g K; it must be positive", WHO, k,
                               temperatures[k]);
    }
    if (n_params == 0 || n_params > MAX_PARAMS)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: %zu parameters; 1 to %d are allowed", WHO,
                           n_params, MAX_PARAMS);
    int seen[MAX_PARAMS] = {0};
    for (size_t j = 0; j < n_params; ++j) {
        const int k = classify(params[j], &parsed[j]);
        if (k < 0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: parameter %zu (material parameter %d) is not a diffusion "
                               "prefactor, activation energy, neck path or lattice mobile "
                               "fraction",
                               WHO, j, (int)params[j]);
        if (seen[k]++)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: parameter %zu is given twice", WHO, j);
    }
    for (size_t k = 0; k < n_out; ++k)
        if (!(out_times[k] >= times[0] && isfinite(out_times[k])) ||
            (k > 0 && out_times[k] < out_times[k - 1]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: output time %zu is %g s; output times must be finite, "
                               "nondecreasing and >= %g s",
                               WHO, k, out_times[k], times[0]);
    return SINTER_OK;
}

typedef struct cvode_set {
    SUNContext sunctx;
    N_Vector v, interpolated;
    SUNMatrix matrix;
    SUNLinearSolver solver;
    void *cvode;
} cvode_set;

static void cvode_set_free(cvode_set *cs)
{
    if (cs->cvode != NULL)
        CVodeFree(&cs->cvode);
    if (cs->solver != NULL)
        SUNLinSolFree(cs->solver);
    if (cs->matrix != NULL)
        SUNMatDestroy(cs->matrix);
    if (cs->v != NULL)
        N_VDestroy(cs->v);
    if (cs->interpolated != NULL)
        N_VDestroy(cs->interpolated);
    if (cs->sunctx != NULL)
        SUNContext_Free(&cs->sunctx);
}

static int cvode_set_create(cvode_set *cs, sunindextype n, problem *pb)
{
    if (SUNContext_Create(NULL, &cs->sunctx) != 0)
        return 0;
    cs->v = N_VNew_Serial(n, cs->sunctx);
    cs->interpolated = N_VNew_Serial(n, cs->sunctx);
    cs->matrix = SUNDenseMatrix(n, n, cs->sunctx);
    cs->cvode = CVodeCreate(CV_BDF, cs->sunctx);
    if (cs->v == NULL || cs->interpolated == NULL || cs->matrix == NULL || cs->cvode == NULL)
        return 0;
    cs->solver = SUNLinSol_Dense(cs->v, cs->matrix, cs->sunctx);
    if (cs->solver == NULL)
        return 0;
    N_VConst(1.0, cs->v);
    return CVodeSetErrHandlerFn(cs->cvode, error_handler, pb) == CV_SUCCESS &&
           CVodeInit(cs->cvode, augmented_rhs, 0.0, cs->v) == CV_SUCCESS &&
           CVodeSetUserData(cs->cvode, pb) == CV_SUCCESS &&
           CVodeSStolerances(cs->cvode, 1e-8, 1e-20) == CV_SUCCESS &&
           CVodeSetLinearSolver(cs->cvode, cs->solver, cs->matrix) == CV_SUCCESS &&
           CVodeSetJacFn(cs->cvode, augmented_jacobian) == CV_SUCCESS &&
           CVodeSetMaxHnilWarns(cs->cvode, -1) == CV_SUCCESS;
}

sinter_status sinter_neck_sensitivities(
    sinter_ctx *ctx, const sinter_neck_model *nm, const sinter_material *m, double radius_a,
    double radius_b, size_t n_times, const double *times, const double *temperatures,
    size_t n_params, const sinter_material_param *params, size_t n_out, const double *out_times,
    double *neck_ratio, double *shrinkage, double *d_neck_ratio, double *d_shrinkage)
{
    static const char *const WHO = "sinter_neck_sensitivities";
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, nm);
    SINTER_CHECK_NULL(ctx, m);
    SINTER_CHECK_NULL(ctx, times);
    SINTER_CHECK_NULL(ctx, temperatures);
    SINTER_CHECK_NULL(ctx, params);
    if (n_out > 0) {
        SINTER_CHECK_NULL(ctx, out_times);
        SINTER_CHECK_NULL(ctx, neck_ratio);
        SINTER_CHECK_NULL(ctx, shrinkage);
        SINTER_CHECK_NULL(ctx, d_neck_ratio);
        SINTER_CHECK_NULL(ctx, d_shrinkage);
    }
    problem pb;
    memset(&pb, 0, sizeof(pb));
    sinter_status status =
        check_arguments(ctx, nm, radius_a, radius_b, n_times, times, temperatures, n_params, params,
                        pb.param, n_out, out_times);
    if (status != SINTER_OK || n_out == 0)
        return status;
    for (size_t k = 0; k < n_out; ++k) {
        neck_ratio[k] = shrinkage[k] = NAN;
        for (size_t j = 0; j < n_params; ++j)
            d_neck_ratio[k * n_params + j] = d_shrinkage[k * n_params + j] = NAN;
    }

    sinter_neck_material material;
    sinter_neck_material_from(m, &material);
    sinter_neck_state pair;
    if (sinter_neck_state_init(&pair, radius_a, radius_b, option(nm, "epsilon"),
                               option(nm, "h0_ratio"), times[0]) != 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: cannot seed a neck between radii %g m and %g m (7dof.md "
                           "section 4)",
                           WHO, radius_a, radius_b);
    pb.ctx = ctx;
    pb.material = &material;
    pb.count = n_params;
    pb.rtol = option(nm, "rtol");
    pb.atol = option(nm, "atol") > 0.0 ? option(nm, "atol") : 1e-14 * fmin(radius_a, radius_b);
    pb.error_scale = (int)option(nm, "error_scale");
    const long max_steps = (long)option(nm, "max_steps");
    double step_hint = option(nm, "initial_step");

    const sunindextype n = (sunindextype)(DOF * (n_params + 1));
    cvode_set cs;
    memset(&cs, 0, sizeof(cs));
    if (!cvode_set_create(&cs, n, &pb)) {
        cvode_set_free(&cs);
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: SUNDIALS could not allocate CVODE", WHO);
    }
    double *v = N_VGetArrayPointer(cs.v);
    memset(v, 0, (size_t)n * sizeof(double)); /* s(t0) = 0 */
    memcpy(v, pair.y, sizeof(pair.y));
    const double radius = fmin(radius_a, radius_b), l0 = pair.center_distance0;
    const sinter_neck_schedule schedule = {n_times, times, temperatures};
    const double t_end = out_times[n_out - 1];
    double time = times[0];
    size_t next = 0;
    long steps = 0;
    while (next < n_out && out_times[next] <= time)
        write_output(&pb, v, radius, l0, next++, neck_ratio, shrinkage, d_neck_ratio, d_shrinkage);

    while (status == SINTER_OK && time < t_end) {
        const double t1 = sinter_neck_schedule_next_break(&schedule, &material, time, t_end);
        pb.segment_start = time;
        pb.segment_end = t1;
        pb.temperature_start = sinter_neck_schedule_temperature(&schedule, time);
        pb.temperature_end = sinter_neck_schedule_temperature(&schedule, t1);
        pb.phase = sinter_neck_schedule_phase(&schedule, &material, time, t1);
        int flag = CVodeReInit(cs.cvode, time, cs.v);
        if (flag == CV_SUCCESS)
            flag = CVodeWFtolerances(cs.cvode, augmented_weights);
        if (flag == CV_SUCCESS)
            flag = CVodeSetStopTime(cs.cvode, t1);
        if (flag == CV_SUCCESS && step_hint > 0.0)
            flag = CVodeSetInitStep(cs.cvode, fmin(step_hint, t1 - time));
        if (flag != CV_SUCCESS) {
            status = sinter_fail(ctx, SINTER_ERR_INVALID, "%s: CVODE set-up failed with %s: %s",
                                 WHO, CVodeGetReturnFlagName(flag), pb.message);
            break;
        }
        for (;;) {
            double reached = time;
            pb.domain_hit = 0;
            pb.message[0] = '\0';
            flag = CVode(cs.cvode, t1, cs.v, &reached, CV_ONE_STEP);
            if (flag < 0) {
                status = pb.domain_hit
                             ? sinter_neck_report_domain(ctx, &pb.domain, WHO)
                             : sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                           "%s: CVODE failed at t = %.9g s with %s: %s", WHO, time,
                                           CVodeGetReturnFlagName(flag), pb.message);
                break;
            }
            sinter_neck_domain_error err;
            if (sinter_neck_check_domain(v, NULL, &err) != SINTER_NECK_VALID) {
                err.time = reached;
                status = sinter_neck_report_domain(ctx, &err, WHO);
                break;
            }
            while (next < n_out && out_times[next] <= reached) {
                const double *at = v;
                if (out_times[next] < reached) {
                    CVodeGetDky(cs.cvode, out_times[next], 0, cs.interpolated);
                    at = N_VGetArrayPointer(cs.interpolated);
                }
                write_output(&pb, at, radius, l0, next++, neck_ratio, shrinkage, d_neck_ratio,
                             d_shrinkage);
            }
            time = reached;
            if (++steps > max_steps) {
                status =
                    sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                "%s: more than %ld steps before t = %.9g s", WHO, max_steps, t_end);
                break;
            }
            if (flag == CV_TSTOP_RETURN || reached >= t1)
                break;
        }
        double next_step = 0.0;
        CVodeGetCurrentStep(cs.cvode, &next_step);
        if (next_step > 0.0)
            step_hint = next_step;
        time = t1;
    }
    if (status == SINTER_OK)
        while (next < n_out)
            write_output(&pb, v, radius, l0, next++, neck_ratio, shrinkage, d_neck_ratio,
                         d_shrinkage);
    cvode_set_free(&cs);
    return status;
}
