/*
 * Advance one neck with CVODE: BDF with Newton iteration and the SUNDIALS dense 7x7 linear
 * solver, the Jacobian from jacobian.c. The temperature schedule is integrated piecewise:
 * CVODE stops (CVodeSetStopTime) at every schedule point and phase switch and is
 * re-initialised there, so that the RHS is smooth inside each piece (docs/7dof.md §6.5).
 * Accepted steps are taken one at a time (CV_ONE_STEP) so that each can be checked against the
 * guards of docs/7dof.md §2.5 and shown to an observer; outputs are interpolated (CVodeGetDky).
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

struct sinter_neck_solver {
    sinter_ctx *ctx;
    SUNContext sunctx;
    void *cvode;
    N_Vector y;
    N_Vector interpolated;
    SUNMatrix matrix;
    SUNLinearSolver linear_solver;
    sinter_neck_step_fn observer;
    void *observer_user;

    /* The current smooth piece [segment_start, segment_end]: T is linear on it. */
    const sinter_neck_material *material;
    int phase;
    double segment_start, segment_end;
    double temperature_start, temperature_end;
    sinter_neck_coeffs coeffs; /* cached at coeffs.temperature */

    double rtol, atol; /* of the current advance */
    int error_scale;

    uint64_t rhs_calls;
    uint64_t jacobian_calls;
    int domain_hit; /* a trial state of the current CVode call violated a guard */
    sinter_neck_domain_error domain;
    char cvode_message[256];
};

void sinter_neck_tolerances_default(sinter_neck_tolerances *tol)
{
    tol->rtol = 1e-8;
    tol->atol = 0.0;
    tol->initial_step = 1e-12; /* docs/7dof.md §4: "start the adaptive step near 1e-12 s" */
    tol->max_steps = 1000000;
    tol->error_scale = SINTER_NECK_SCALE_GEOMETRY;
}

void sinter_neck_error_weights(const double y[SINTER_NECK_DOF], double rtol, double atol,
                               int error_scale, double w[SINTER_NECK_DOF])
{
    /* neck.h, sinter_neck_error_scale: y1 by |x|; the lengths of side P by |y_i| or, for
     * GEOMETRY, by min(|y_i|, H_P) with H_P = L_P - d_P (docs/7dof.md §2.1) the cone height. */
    w[SINTER_NECK_X] = 1.0 / (rtol * fabs(y[SINTER_NECK_X]) + atol);
    for (int p = 0; p < 2; ++p) {
        const double height = fabs(y[3 + 3 * p] - y[2 + 3 * p]);
        for (int k = 1; k <= 3; ++k) {
            double scale = fabs(y[k + 3 * p]);
            if (error_scale == SINTER_NECK_SCALE_GEOMETRY)
                scale = fmin(scale, height);
            w[k + 3 * p] = 1.0 / (rtol * scale + atol);
        }
    }
}

/* Coefficients at time t of the current piece, on which T(t) is linear. */
static const sinter_neck_coeffs *coeffs_at(sinter_neck_solver *s, double t)
{
    double temperature = s->temperature_start;
    if (s->temperature_end != s->temperature_start) {
        const double w = (t - s->segment_start) / (s->segment_end - s->segment_start);
        temperature += w * (s->temperature_end - s->temperature_start);
    }
    if (temperature != s->coeffs.temperature)
        sinter_neck_coeffs_eval(s->material, s->phase, temperature, &s->coeffs);
    return &s->coeffs;
}

static int cvode_rhs(realtype t, N_Vector y, N_Vector ydot, void *user)
{
    sinter_neck_solver *s = user;
    s->rhs_calls++;
    sinter_neck_domain_error err;
    if (sinter_neck_rhs(N_VGetArrayPointer(y), coeffs_at(s, t), N_VGetArrayPointer(ydot), &err,
                        NULL) != SINTER_NECK_VALID) {
        err.time = t;
        s->domain = err;
        s->domain_hit = 1;
        return 1; /* recoverable: CVODE retries with a smaller step */
    }
    return 0;
}

static int cvode_weights(N_Vector y, N_Vector w, void *user)
{
    const sinter_neck_solver *s = user;
    sinter_neck_error_weights(N_VGetArrayPointer(y), s->rtol, s->atol, s->error_scale,
                              N_VGetArrayPointer(w));
    return 0;
}

static int cvode_jacobian(realtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void *user,
                          N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    sinter_neck_solver *s = user;
    double dense[SINTER_NECK_DOF * SINTER_NECK_DOF];
    s->jacobian_calls++;
    s->rhs_calls += SINTER_NECK_DOF;
    if (sinter_neck_jacobian(N_VGetArrayPointer(y), N_VGetArrayPointer(fy), coeffs_at(s, t),
                             dense) != SINTER_NECK_VALID)
        return 1;
    for (int j = 0; j < SINTER_NECK_DOF; ++j) {
        realtype *column = SM_COLUMN_D(jac, j);
        for (int i = 0; i < SINTER_NECK_DOF; ++i)
            column[i] = dense[i + SINTER_NECK_DOF * j];
    }
    return 0;
}

/* CVODE's messages go to the solver, never to stderr (the library does not print). */
static void cvode_error_handler(int code, const char *module, const char *function, char *msg,
                                void *user)
{
    sinter_neck_solver *s = user;
    if (code == CV_WARNING)
        return;
    snprintf(s->cvode_message, sizeof(s->cvode_message), "%s: %s", function, msg);
}

sinter_status sinter_neck_solver_create(sinter_neck_solver **out, sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    sinter_neck_solver *s = sinter_calloc(ctx, 1, sizeof(*s));
    if (s == NULL)
        return SINTER_ERR_NOMEM;
    s->ctx = ctx;
    int ok = SUNContext_Create(NULL, &s->sunctx) == 0;
    if (ok) {
        s->y = N_VNew_Serial(SINTER_NECK_DOF, s->sunctx);
        s->interpolated = N_VNew_Serial(SINTER_NECK_DOF, s->sunctx);
        s->matrix = SUNDenseMatrix(SINTER_NECK_DOF, SINTER_NECK_DOF, s->sunctx);
        s->cvode = CVodeCreate(CV_BDF, s->sunctx);
        ok = s->y != NULL && s->interpolated != NULL && s->matrix != NULL && s->cvode != NULL;
    }
    if (ok) {
        s->linear_solver = SUNLinSol_Dense(s->y, s->matrix, s->sunctx);
        ok = s->linear_solver != NULL;
    }
    if (ok) {
        /* CVodeInit needs a vector only for its size; every advance re-initialises. */
        N_VConst(1.0, s->y);
        ok = CVodeSetErrHandlerFn(s->cvode, cvode_error_handler, s) == CV_SUCCESS &&
             CVodeInit(s->cvode, cvode_rhs, 0.0, s->y) == CV_SUCCESS &&
             CVodeSetUserData(s->cvode, s) == CV_SUCCESS &&
             CVodeSStolerances(s->cvode, 1e-8, 1e-20) == CV_SUCCESS &&
             CVodeSetLinearSolver(s->cvode, s->linear_solver, s->matrix) == CV_SUCCESS &&
             CVodeSetJacFn(s->cvode, cvode_jacobian) == CV_SUCCESS &&
             CVodeSetMaxHnilWarns(s->cvode, -1) == CV_SUCCESS;
    }
    if (!ok) {
        sinter_neck_solver_destroy(s);
        return sinter_fail(ctx, SINTER_ERR_NOMEM,
                           "sinter_neck_solver_create: SUNDIALS could "
                           "not allocate the CVODE solver");
    }
    *out = s;
    return SINTER_OK;
}

void sinter_neck_solver_destroy(sinter_neck_solver *s)
{
    if (s == NULL)
        return;
    if (s->cvode != NULL)
        CVodeFree(&s->cvode);
    if (s->linear_solver != NULL)
        SUNLinSolFree(s->linear_solver);
    if (s->matrix != NULL)
        SUNMatDestroy(s->matrix);
    if (s->y != NULL)
        N_VDestroy(s->y);
    if (s->interpolated != NULL)
        N_VDestroy(s->interpolated);
    if (s->sunctx != NULL)
        SUNContext_Free(&s->sunctx);
    sinter_free(s->ctx, s);
}

void sinter_neck_solver_set_observer(sinter_neck_solver *s, sinter_neck_step_fn fn, void *user)
{
    s->observer = fn;
    s->observer_user = user;
}

/* Add the counters of the piece just integrated: CVODE's restart at every CVodeReInit. */
static void close_piece(sinter_neck_solver *s, sinter_neck_counters *counters)
{
    long steps = 0, error_fails = 0, newton_iterations = 0, newton_fails = 0;
    CVodeGetNumSteps(s->cvode, &steps);
    CVodeGetNumErrTestFails(s->cvode, &error_fails);
    CVodeGetNumNonlinSolvIters(s->cvode, &newton_iterations);
    CVodeGetNumNonlinSolvConvFails(s->cvode, &newton_fails);
    counters->steps += (uint64_t)steps;
    counters->error_test_failures += (uint64_t)error_fails;
    counters->nonlinear_iterations += (uint64_t)newton_iterations;
    counters->nonlinear_failures += (uint64_t)newton_fails;
    counters->segments += 1;
    counters->rhs_evaluations += s->rhs_calls;
    counters->jacobian_evaluations += s->jacobian_calls;
    s->rhs_calls = 0;
    s->jacobian_calls = 0;
}

sinter_status sinter_neck_report_domain(sinter_ctx *ctx, const sinter_neck_domain_error *err,
                                        const char *who)
{
    char what[200];
    sinter_neck_describe_violation(err, what, sizeof(what));
    return sinter_fail(ctx, SINTER_ERR_DOMAIN,
                       "%s: the 7DOF neck left its domain of validity at t = %.9g s: %s "
                       "(7dof.md section 2.5)",
                       who, err->time, what);
}

static sinter_status check_outputs(sinter_ctx *ctx, const sinter_neck_outputs *outputs, double t0,
                                   double t_end, const char *who)
{
    if (outputs == NULL || outputs->count == 0)
        return SINTER_OK;
    if (outputs->times == NULL || outputs->states == NULL)
        return sinter_fail(ctx, SINTER_ERR_NULL, "%s: output times or states are NULL", who);
    for (size_t k = 0; k < outputs->count; ++k) {
        const double tk = outputs->times[k];
        if (!(tk >= t0 && tk <= t_end) || (k > 0 && tk < outputs->times[k - 1]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: output time %zu is %g s; output times must be "
                               "nondecreasing and in [%g, %g] s",
                               who, k, tk, t0, t_end);
    }
    return SINTER_OK;
}

/* Argument checks shared by the CVODE and RK4 advances. */
sinter_status sinter_neck_check_advance(sinter_ctx *ctx, const sinter_neck_state *state,
                                        const sinter_neck_schedule *schedule, double t_end,
                                        const sinter_neck_outputs *outputs, const char *who)
{
    if (schedule == NULL || schedule->count == 0 || schedule->times == NULL ||
        schedule->temperatures == NULL)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: the temperature schedule is empty", who);
    if (!isfinite(t_end) || !(t_end >= state->time))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: end time %g s must be finite and >= the pair's time %g s", who,
                           t_end, state->time);
    sinter_neck_domain_error err;
    if (sinter_neck_check_domain(state->y, NULL, &err) != SINTER_NECK_VALID) {
        err.time = state->time;
        return sinter_neck_report_domain(ctx, &err, who);
    }
    return check_outputs(ctx, outputs, state->time, t_end, who);
}

/* Copy y into outputs whose times are <= t (and not yet filled). */
static void copy_outputs(const sinter_neck_outputs *outputs, size_t *next, double t,
                         const double *y)
{
    if (outputs == NULL)
        return;
    while (*next < outputs->count && outputs->times[*next] <= t) {
        memcpy(outputs->states + SINTER_NECK_DOF * *next, y, SINTER_NECK_DOF * sizeof(double));
        ++*next;
    }
}

sinter_status sinter_neck_advance_pair(sinter_neck_solver *s, sinter_neck_state *state,
                                       const sinter_neck_material *m,
                                       const sinter_neck_schedule *schedule, double t_end,
                                       const sinter_neck_tolerances *tol,
                                       const sinter_neck_outputs *outputs,
                                       sinter_neck_counters *counters)
{
    static const char *const WHO = "sinter_neck_advance_pair";
    if (s == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = s->ctx;
    SINTER_CHECK_NULL(ctx, state);
    SINTER_CHECK_NULL(ctx, m);
    SINTER_CHECK_NULL(ctx, tol);
    if (!(tol->rtol > 0.0) || !(tol->atol >= 0.0) || !(tol->initial_step >= 0.0) ||
        tol->max_steps < 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: tolerances rtol = %g, atol = %g m, initial step %g s, "
                           "max_steps %ld are invalid",
                           WHO, tol->rtol, tol->atol, tol->initial_step, tol->max_steps);
    sinter_status status = sinter_neck_check_advance(ctx, state, schedule, t_end, outputs, WHO);
    if (status != SINTER_OK)
        return status;

    sinter_neck_counters local = {0};
    if (counters == NULL)
        counters = &local;
    const double y4_start = state->y[SINTER_NECK_LA], y7_start = state->y[SINTER_NECK_LB];
    /* docs/7dof.md §4: absolute tolerance about 1e-14 R on lengths. */
    const double atol = tol->atol > 0.0
                            ? tol->atol
                            : 1e-14 * fmin(state->y[SINTER_NECK_RA], state->y[SINTER_NECK_RB]);
    double step_hint = state->step_hint > 0.0 ? state->step_hint : tol->initial_step;
    size_t next_output = 0;
    copy_outputs(outputs, &next_output, state->time, state->y);
    s->material = m;
    s->rtol = tol->rtol;
    s->atol = atol;
    s->error_scale = tol->error_scale;
    long steps_taken = 0;
    double *y = N_VGetArrayPointer(s->y);

    while (state->time < t_end) {
        /* One smooth piece: up to the next schedule point or phase switch. */
        const double t0 = state->time;
        const double t1 = sinter_neck_schedule_next_break(schedule, m, t0, t_end);
        s->segment_start = t0;
        s->segment_end = t1;
        s->temperature_start = sinter_neck_schedule_temperature(schedule, t0);
        s->temperature_end = sinter_neck_schedule_temperature(schedule, t1);
        s->phase = sinter_neck_schedule_phase(schedule, m, t0, t1);
        sinter_neck_coeffs_eval(m, s->phase, s->temperature_start, &s->coeffs);

        memcpy(y, state->y, sizeof(state->y));
        int flag = CVodeReInit(s->cvode, t0, s->y);
        if (flag == CV_SUCCESS)
            flag = CVodeWFtolerances(s->cvode, cvode_weights);
        if (flag == CV_SUCCESS)
            flag = CVodeSetStopTime(s->cvode, t1);
        if (flag == CV_SUCCESS)
            flag = CVodeSetInitStep(s->cvode, fmin(step_hint, t1 - t0));
        if (flag != CV_SUCCESS)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: CVODE set-up failed with %s: %s", WHO,
                               CVodeGetReturnFlagName(flag), s->cvode_message);

        for (;;) {
            double t_reached = t0;
            s->domain_hit = 0;
            s->cvode_message[0] = '\0';
            flag = CVode(s->cvode, t1, s->y, &t_reached, CV_ONE_STEP);
            if (flag < 0) {
                close_piece(s, counters);
                if (s->domain_hit)
                    return sinter_neck_report_domain(ctx, &s->domain, WHO);
                return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                   "%s: CVODE failed at t = %.9g s (T = %.6g K) with %s: %s", WHO,
                                   state->time, s->coeffs.temperature, CVodeGetReturnFlagName(flag),
                                   s->cvode_message);
            }
            /* The accepted state itself must satisfy the guards (docs/7dof.md §2.5). */
            sinter_neck_domain_error err;
            if (sinter_neck_check_domain(y, NULL, &err) != SINTER_NECK_VALID) {
                close_piece(s, counters);
                err.time = t_reached;
                return sinter_neck_report_domain(ctx, &err, WHO);
            }
            /* Outputs inside the step just taken, by CVODE's interpolant. */
            while (outputs != NULL && next_output < outputs->count &&
                   outputs->times[next_output] <= t_reached) {
                if (outputs->times[next_output] == t_reached) {
                    copy_outputs(outputs, &next_output, t_reached, y);
                    continue;
                }
                CVodeGetDky(s->cvode, outputs->times[next_output], 0, s->interpolated);
                memcpy(outputs->states + SINTER_NECK_DOF * next_output,
                       N_VGetArrayPointer(s->interpolated), SINTER_NECK_DOF * sizeof(double));
                ++next_output;
            }
            memcpy(state->y, y, sizeof(state->y));
            state->time = t_reached;
            if (s->observer != NULL && s->observer(t_reached, y, s->phase, s->observer_user)) {
                close_piece(s, counters);
                return sinter_fail(ctx, SINTER_ERR_CALLBACK,
                                   "%s: the step observer stopped the run at t = %.9g s", WHO,
                                   t_reached);
            }
            if (++steps_taken > tol->max_steps) {
                close_piece(s, counters);
                return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                   "%s: more than %ld steps before t = %.9g s (at t = %.9g s)", WHO,
                                   tol->max_steps, t_end, t_reached);
            }
            if (flag == CV_TSTOP_RETURN || t_reached >= t1)
                break;
        }
        close_piece(s, counters);
        double next_step = 0.0; /* the step CVODE would try next (not the cut last one) */
        CVodeGetCurrentStep(s->cvode, &next_step);
        if (next_step > 0.0)
            step_hint = next_step;
        state->time = t1;
    }
    copy_outputs(outputs, &next_output, state->time, state->y);
    /* Seed 001 eq. 43: decrements of y4 and y7 over this advance, for the DEM correction. */
    state->last_dy4 = y4_start - state->y[SINTER_NECK_LA];
    state->last_dy7 = y7_start - state->y[SINTER_NECK_LB];
    state->step_hint = step_hint;
    return SINTER_OK;
}
