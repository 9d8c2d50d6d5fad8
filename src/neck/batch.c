/*
 * Many necks in one CVODE system (strategy 3 of the issue): n pairs are n independent 7-DOF
 * systems stacked into one vector of 7n unknowns and integrated with a shared step.
 *
 *  - Newton matrix: I - gamma J is block diagonal with 7x7 blocks, held in a block-diagonal
 *    SUNMatrix with its own direct solver (blockdiag.c), so CVODE's Jacobian-reuse heuristics
 *    apply unchanged while factorisation and solves cost O(n). Each block is the pair's own
 *    finite-difference Jacobian (sinter_neck_jacobian: 7 pair-RHS calls per pair, not 7n
 *    full RHS calls). A SUNDIALS band matrix of half-bandwidth 6 would also hold the blocks,
 *    but its LU and solves took over half of the batch's time (perf, 240 necks).
 *  - Error test: the vector's WRMS-norm operation is replaced by the largest per-pair WRMS
 *    norm, so every pair meets the tolerance a single-pair advance would, however many pairs
 *    there are (the plain WRMS over 7n components would dilute one pair's error by sqrt(n)).
 *  - CVODE needs a fixed vector length, so the system is rebuilt when n changes.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include "neck/blockdiag.h"

struct sinter_neck_batch {
    sinter_ctx *ctx;
    SUNContext sunctx;
    size_t pairs; /* size of the current system (0: none) */
    void *cvode;
    N_Vector y;
    SUNMatrix matrix;
    SUNLinearSolver linear_solver;

    /* The current advance and piece. */
    const sinter_neck_material *const *materials;
    int *phase;                 /* per pair */
    sinter_neck_coeffs *coeffs; /* per pair, cached at coeffs[k].temperature */
    double segment_start, segment_end, temperature_start, temperature_end;
    double rtol, atol;
    int error_scale;
    uint64_t rhs_calls, jacobian_calls;
    int domain_hit;
    size_t domain_pair;
    sinter_neck_domain_error domain;
    char cvode_message[256];
};

/* The largest per-pair WRMS norm: CVODE's error and convergence tests then hold pair by
 * pair (see the file comment). */
static realtype pairwise_max_wrms(N_Vector x, N_Vector w)
{
    const realtype *xd = N_VGetArrayPointer(x), *wd = N_VGetArrayPointer(w);
    const sunindextype length = N_VGetLength(x);
    realtype worst = 0.0;
    for (sunindextype start = 0; start + SINTER_NECK_DOF <= length; start += SINTER_NECK_DOF) {
        realtype sum = 0.0;
        for (int i = 0; i < SINTER_NECK_DOF; ++i) {
            const realtype v = xd[start + i] * wd[start + i];
            sum += v * v;
        }
        if (sum > worst)
            worst = sum;
    }
    return sqrt(worst / SINTER_NECK_DOF);
}

static int batch_weights(N_Vector y, N_Vector w, void *user)
{
    const sinter_neck_batch *b = user;
    const double *yd = N_VGetArrayPointer(y);
    double *wd = N_VGetArrayPointer(w);
    for (size_t k = 0; k < b->pairs; ++k)
        sinter_neck_error_weights(yd + SINTER_NECK_DOF * k, b->rtol, b->atol, b->error_scale,
                                  wd + SINTER_NECK_DOF * k);
    return 0;
}

static const sinter_neck_coeffs *pair_coeffs(sinter_neck_batch *b, size_t k, double t)
{
    double temperature = b->temperature_start;
    if (b->temperature_end != b->temperature_start)
        temperature += (t - b->segment_start) / (b->segment_end - b->segment_start) *
                       (b->temperature_end - b->temperature_start);
    sinter_neck_coeffs *c = &b->coeffs[k];
    if (temperature != c->temperature) {
        if (k > 0 && b->materials[k] == b->materials[k - 1] && b->phase[k] == b->phase[k - 1] &&
            b->coeffs[k - 1].temperature == temperature)
            *c = b->coeffs[k - 1]; /* same material as the previous pair: no exp() */
        else
            sinter_neck_coeffs_eval(b->materials[k], b->phase[k], temperature, c);
    }
    return c;
}

static int batch_rhs(realtype t, N_Vector y, N_Vector ydot, void *user)
{
    sinter_neck_batch *b = user;
    const double *yd = N_VGetArrayPointer(y);
    double *fd = N_VGetArrayPointer(ydot);
    b->rhs_calls++;
    for (size_t k = 0; k < b->pairs; ++k) {
        sinter_neck_domain_error err;
        if (sinter_neck_rhs(yd + SINTER_NECK_DOF * k, pair_coeffs(b, k, t),
                            fd + SINTER_NECK_DOF * k, &err, NULL) != SINTER_NECK_VALID) {
            err.time = t;
            b->domain = err;
            b->domain_pair = k;
            b->domain_hit = 1;
            return 1; /* recoverable: CVODE retries with a smaller step */
        }
    }
    return 0;
}

static int batch_jacobian(realtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void *user,
                          N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    sinter_neck_batch *b = user;
    const double *yd = N_VGetArrayPointer(y), *fd = N_VGetArrayPointer(fy);
    b->jacobian_calls++;
    for (size_t k = 0; k < b->pairs; ++k)
        if (sinter_neck_jacobian(yd + SINTER_NECK_DOF * k, fd + SINTER_NECK_DOF * k,
                                 pair_coeffs(b, k, t),
                                 sinter_neck_blockdiag_block(jac, k)) != SINTER_NECK_VALID)
            return 1;
    return 0;
}

static void batch_error_handler(int code, const char *module, const char *function, char *msg,
                                void *user)
{
    sinter_neck_batch *b = user;
    if (code != CV_WARNING)
        snprintf(b->cvode_message, sizeof(b->cvode_message), "%s: %s", function, msg);
}

static void free_system(sinter_neck_batch *b)
{
    if (b->cvode != NULL)
        CVodeFree(&b->cvode);
    if (b->linear_solver != NULL)
        SUNLinSolFree(b->linear_solver);
    if (b->matrix != NULL)
        SUNMatDestroy(b->matrix);
    if (b->y != NULL)
        N_VDestroy(b->y);
    b->cvode = NULL;
    b->linear_solver = NULL;
    b->matrix = NULL;
    b->y = NULL;
    sinter_free(b->ctx, b->phase);
    sinter_free(b->ctx, b->coeffs);
    b->phase = NULL;
    b->coeffs = NULL;
    b->pairs = 0;
}

/* (Re)build CVODE for n pairs. */
static sinter_status build_system(sinter_neck_batch *b, size_t n)
{
    if (b->pairs == n)
        return SINTER_OK;
    free_system(b);
    if (sinter_mul_overflows(n, SINTER_NECK_DOF * sizeof(sinter_neck_coeffs)))
        return sinter_fail(b->ctx, SINTER_ERR_OVERFLOW, "sinter_neck_batch_advance: %zu pairs", n);
    b->phase = sinter_calloc(b->ctx, n, sizeof(int));
    b->coeffs = sinter_calloc(b->ctx, n, sizeof(sinter_neck_coeffs));
    if (b->phase == NULL || b->coeffs == NULL) {
        free_system(b);
        return SINTER_ERR_NOMEM;
    }
    const sunindextype length = (sunindextype)(SINTER_NECK_DOF * n);
    b->y = N_VNew_Serial(length, b->sunctx);
    b->matrix = sinter_neck_blockdiag_matrix(b->ctx, b->sunctx, n);
    b->linear_solver = sinter_neck_blockdiag_solver(b->ctx, b->sunctx, n);
    b->cvode = CVodeCreate(CV_BDF, b->sunctx);
    int ok = b->y != NULL && b->matrix != NULL && b->linear_solver != NULL && b->cvode != NULL;
    if (ok) {
        b->y->ops->nvwrmsnorm = pairwise_max_wrms; /* inherited by CVODE's clones */
        N_VConst(1.0, b->y);
        ok = CVodeSetErrHandlerFn(b->cvode, batch_error_handler, b) == CV_SUCCESS &&
             CVodeInit(b->cvode, batch_rhs, 0.0, b->y) == CV_SUCCESS &&
             CVodeSetUserData(b->cvode, b) == CV_SUCCESS &&
             CVodeSStolerances(b->cvode, 1e-8, 1e-20) == CV_SUCCESS &&
             CVodeSetLinearSolver(b->cvode, b->linear_solver, b->matrix) == CV_SUCCESS &&
             CVodeSetJacFn(b->cvode, batch_jacobian) == CV_SUCCESS &&
             CVodeSetMaxHnilWarns(b->cvode, -1) == CV_SUCCESS;
    }
    if (!ok) {
        free_system(b);
        return sinter_fail(b->ctx, SINTER_ERR_NOMEM,
                           "sinter_neck_batch_advance: SUNDIALS could not allocate the CVODE "
                           "system for %zu pairs",
                           n);
    }
    b->pairs = n;
    return SINTER_OK;
}

size_t sinter_neck_batch_failed_pair(const sinter_neck_batch *batch)
{
    return batch != NULL && batch->domain_hit ? batch->domain_pair : SIZE_MAX;
}

sinter_status sinter_neck_batch_create(sinter_neck_batch **out, sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    sinter_neck_batch *b = sinter_calloc(ctx, 1, sizeof(*b));
    if (b == NULL)
        return SINTER_ERR_NOMEM;
    b->ctx = ctx;
    if (SUNContext_Create(NULL, &b->sunctx) != 0) {
        sinter_free(ctx, b);
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_neck_batch_create: no SUNContext");
    }
    *out = b;
    return SINTER_OK;
}

void sinter_neck_batch_destroy(sinter_neck_batch *b)
{
    if (b == NULL)
        return;
    free_system(b);
    SUNContext_Free(&b->sunctx);
    sinter_free(b->ctx, b);
}

static void add_counters(sinter_neck_batch *b, sinter_neck_counters *counters)
{
    long steps = 0, error_fails = 0, newton_iterations = 0, newton_fails = 0;
    CVodeGetNumSteps(b->cvode, &steps);
    CVodeGetNumErrTestFails(b->cvode, &error_fails);
    CVodeGetNumNonlinSolvIters(b->cvode, &newton_iterations);
    CVodeGetNumNonlinSolvConvFails(b->cvode, &newton_fails);
    counters->steps += (uint64_t)steps;
    counters->error_test_failures += (uint64_t)error_fails;
    counters->nonlinear_iterations += (uint64_t)newton_iterations;
    counters->nonlinear_failures += (uint64_t)newton_fails;
    counters->segments += 1;
    /* In pair-RHS units: one batch RHS is n pair RHS; a Jacobian is 7 per pair. */
    counters->rhs_evaluations += (b->rhs_calls + SINTER_NECK_DOF * b->jacobian_calls) * b->pairs;
    counters->jacobian_evaluations += b->jacobian_calls * b->pairs;
    b->rhs_calls = 0;
    b->jacobian_calls = 0;
}

sinter_status sinter_neck_batch_advance(sinter_neck_batch *b, size_t n, sinter_neck_state *pairs,
                                        const sinter_neck_material *const *materials,
                                        const sinter_neck_schedule *schedule, double t_end,
                                        const sinter_neck_tolerances *tol,
                                        sinter_neck_counters *counters)
{
    static const char *const WHO = "sinter_neck_batch_advance";
    if (b == NULL)
        return SINTER_ERR_NULL;
    b->domain_hit = 0; /* sinter_neck_batch_failed_pair reports this call only */
    sinter_ctx *ctx = b->ctx;
    SINTER_CHECK_NULL(ctx, pairs);
    SINTER_CHECK_NULL(ctx, materials);
    SINTER_CHECK_NULL(ctx, tol);
    if (n == 0)
        return SINTER_OK;
    if (!(tol->rtol > 0.0) || !(tol->atol >= 0.0) || !(tol->initial_step >= 0.0) ||
        tol->max_steps < 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: invalid tolerances", WHO);
    double atol = tol->atol, step_hint = INFINITY;
    for (size_t k = 0; k < n; ++k) {
        if (materials[k] == NULL)
            return sinter_fail(ctx, SINTER_ERR_NULL, "%s: material of pair %zu is NULL", WHO, k);
        if (pairs[k].time != pairs[0].time)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: pair %zu is at t = %g s, pair 0 at %g s; a batch advances "
                               "pairs that share their time",
                               WHO, k, pairs[k].time, pairs[0].time);
        sinter_status status =
            sinter_neck_check_advance(ctx, &pairs[k], schedule, t_end, NULL, WHO);
        if (status != SINTER_OK)
            return status;
        /* docs/7dof.md §4: atol ~ 1e-14 R, over the smallest sphere of the batch. */
        if (tol->atol == 0.0) {
            const double r = fmin(pairs[k].y[SINTER_NECK_RA], pairs[k].y[SINTER_NECK_RB]);
            atol = (k == 0) ? 1e-14 * r : fmin(atol, 1e-14 * r);
        }
        step_hint =
            fmin(step_hint, pairs[k].step_hint > 0.0 ? pairs[k].step_hint : tol->initial_step);
    }
    sinter_status status = build_system(b, n);
    if (status != SINTER_OK)
        return status;
    sinter_neck_counters local = {0};
    if (counters == NULL)
        counters = &local;

    b->materials = materials;
    b->rtol = tol->rtol;
    b->atol = atol;
    b->error_scale = tol->error_scale;
    double *y = N_VGetArrayPointer(b->y);
    for (size_t k = 0; k < n; ++k)
        memcpy(y + SINTER_NECK_DOF * k, pairs[k].y, sizeof(pairs[k].y));
    double t = pairs[0].time;
    long steps_taken = 0;
    while (t < t_end) {
        /* The next break of any pair's material (they share the schedule). */
        double t1 = t_end;
        for (size_t k = 0; k < n; ++k)
            if (k == 0 || materials[k] != materials[k - 1])
                t1 = fmin(t1, sinter_neck_schedule_next_break(schedule, materials[k], t, t_end));
        b->segment_start = t;
        b->segment_end = t1;
        b->temperature_start = sinter_neck_schedule_temperature(schedule, t);
        b->temperature_end = sinter_neck_schedule_temperature(schedule, t1);
        for (size_t k = 0; k < n; ++k) {
            b->phase[k] = sinter_neck_schedule_phase(schedule, materials[k], t, t1);
            b->coeffs[k].temperature = NAN;
        }
        int flag = CVodeReInit(b->cvode, t, b->y);
        if (flag == CV_SUCCESS)
            flag = CVodeWFtolerances(b->cvode, batch_weights);
        if (flag == CV_SUCCESS)
            flag = CVodeSetStopTime(b->cvode, t1);
        if (flag == CV_SUCCESS)
            flag = CVodeSetInitStep(b->cvode, fmin(step_hint, t1 - t));
        if (flag == CV_SUCCESS)
            flag = CVodeSetMaxNumSteps(b->cvode, tol->max_steps - steps_taken);
        if (flag != CV_SUCCESS)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: CVODE set-up failed with %s: %s", WHO,
                               CVodeGetReturnFlagName(flag), b->cvode_message);
        double t_reached = t;
        b->domain_hit = 0;
        b->cvode_message[0] = '\0';
        flag = CVode(b->cvode, t1, b->y, &t_reached, CV_NORMAL);
        long steps = 0;
        CVodeGetNumSteps(b->cvode, &steps);
        steps_taken += steps;
        add_counters(b, counters);
        if (flag < 0) {
            if (b->domain_hit) {
                char who[96];
                snprintf(who, sizeof(who), "%s (pair %zu)", WHO, b->domain_pair);
                return sinter_neck_report_domain(ctx, &b->domain, who);
            }
            return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                               "%s: CVODE failed near t = %.9g s with %s: %s", WHO, t_reached,
                               CVodeGetReturnFlagName(flag), b->cvode_message);
        }
        for (size_t k = 0; k < n; ++k) {
            sinter_neck_domain_error err;
            if (sinter_neck_check_domain(y + SINTER_NECK_DOF * k, NULL, &err) !=
                SINTER_NECK_VALID) {
                b->domain_hit = 1;
                b->domain_pair = k;
                char who[96];
                snprintf(who, sizeof(who), "%s (pair %zu)", WHO, k);
                err.time = t1;
                return sinter_neck_report_domain(ctx, &err, who);
            }
        }
        double next_step = 0.0;
        CVodeGetCurrentStep(b->cvode, &next_step);
        if (next_step > 0.0)
            step_hint = next_step;
        t = t1;
    }
    for (size_t k = 0; k < n; ++k) {
        const double *yk = y + SINTER_NECK_DOF * k;
        /* Seed 001 eq. 43: decrements of y4 and y7 over this advance. */
        pairs[k].last_dy4 = pairs[k].y[SINTER_NECK_LA] - yk[SINTER_NECK_LA];
        pairs[k].last_dy7 = pairs[k].y[SINTER_NECK_LB] - yk[SINTER_NECK_LB];
        memcpy(pairs[k].y, yk, sizeof(pairs[k].y));
        pairs[k].time = t_end;
        pairs[k].step_hint = step_hint;
    }
    return SINTER_OK;
}
