/*
 * The seed's integrator for comparison: classical 4th-order Runge-Kutta (seed 001 sec. 2.2,
 * "the forth-order Runge-Kutta integration was chosen") on a fixed grid.
 *
 * A grid uniform in t would need the initial transient's step (about 1e-5 s for copper) all
 * the way to 5000 s. The neck's fastest relaxation rate falls roughly like 1/t (max |lambda| t
 * is 20-200 after the first millisecond for copper at 1293 K), so the grid is uniform in
 * u = ln(1 + (t - t0)/tau): node k is t0 + tau (exp(k du) - 1). The fixed step count is then
 * spent evenly over the decades of time, and the explicit stability limit |lambda dt| < 2.78
 * holds at every step once du is small enough. Steps are cut at schedule breaks (so each step
 * sees a smooth RHS) and at output times.
 */
#include <math.h>
#include <string.h>

#include "neck/neck.h"

/* T(t) on the piece [t0, t1], linear between its end values. */
typedef struct piece {
    const sinter_neck_material *material;
    int phase;
    double t0, t1, temperature0, temperature1;
    sinter_neck_coeffs coeffs;
} piece;

static const sinter_neck_coeffs *piece_coeffs(piece *p, double t)
{
    double temperature = p->temperature0;
    if (p->temperature1 != p->temperature0)
        temperature += (t - p->t0) / (p->t1 - p->t0) * (p->temperature1 - p->temperature0);
    if (temperature != p->coeffs.temperature)
        sinter_neck_coeffs_eval(p->material, p->phase, temperature, &p->coeffs);
    return &p->coeffs;
}

/* One classical RK4 step of length dt from (t, y); fills y_new. */
static sinter_neck_violation rk4_step(piece *p, double t, double dt,
                                      const double y[SINTER_NECK_DOF],
                                      double y_new[SINTER_NECK_DOF], sinter_neck_domain_error *err,
                                      uint64_t *rhs_calls)
{
    double k1[SINTER_NECK_DOF], k2[SINTER_NECK_DOF], k3[SINTER_NECK_DOF], k4[SINTER_NECK_DOF];
    double stage[SINTER_NECK_DOF];
    sinter_neck_violation bad;
    /* k1 = f(t, y), k2 = f(t + dt/2, y + dt/2 k1), k3 = f(t + dt/2, y + dt/2 k2),
     * k4 = f(t + dt, y + dt k3), y_new = y + dt/6 (k1 + 2 k2 + 2 k3 + k4). */
    *rhs_calls += 4;
    if ((bad = sinter_neck_rhs(y, piece_coeffs(p, t), k1, err, NULL)) != SINTER_NECK_VALID)
        return bad;
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        stage[i] = y[i] + 0.5 * dt * k1[i];
    if ((bad = sinter_neck_rhs(stage, piece_coeffs(p, t + 0.5 * dt), k2, err, NULL)) !=
        SINTER_NECK_VALID)
        return bad;
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        stage[i] = y[i] + 0.5 * dt * k2[i];
    if ((bad = sinter_neck_rhs(stage, piece_coeffs(p, t + 0.5 * dt), k3, err, NULL)) !=
        SINTER_NECK_VALID)
        return bad;
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        stage[i] = y[i] + dt * k3[i];
    if ((bad = sinter_neck_rhs(stage, piece_coeffs(p, t + dt), k4, err, NULL)) != SINTER_NECK_VALID)
        return bad;
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        y_new[i] = y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    return sinter_neck_check_domain(y_new, NULL, err);
}

sinter_status sinter_neck_rk4_advance(sinter_ctx *ctx, sinter_neck_state *state,
                                      const sinter_neck_material *m,
                                      const sinter_neck_schedule *schedule, double t_end,
                                      uint64_t steps, double time_scale,
                                      const sinter_neck_outputs *outputs,
                                      sinter_neck_counters *counters)
{
    static const char *const WHO = "sinter_neck_rk4_advance";
    SINTER_CHECK_NULL(ctx, state);
    SINTER_CHECK_NULL(ctx, m);
    if (steps < 1 || !(time_scale > 0.0) || !isfinite(time_scale))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: %llu steps with time scale %g s; need >= 1 step and a "
                           "positive time scale",
                           WHO, (unsigned long long)steps, time_scale);
    sinter_status status = sinter_neck_check_advance(ctx, state, schedule, t_end, outputs, WHO);
    if (status != SINTER_OK)
        return status;
    sinter_neck_counters local = {0};
    if (counters == NULL)
        counters = &local;

    const double start = state->time;
    const double y4_start = state->y[SINTER_NECK_LA], y7_start = state->y[SINTER_NECK_LB];
    const double du = log1p((t_end - start) / time_scale) / (double)steps;
    uint64_t node = 0; /* index of the last grid node at or before state->time */
    size_t next_output = 0;
    while (outputs != NULL && next_output < outputs->count &&
           outputs->times[next_output] <= state->time) {
        memcpy(outputs->states + SINTER_NECK_DOF * next_output, state->y, sizeof(state->y));
        ++next_output;
    }
    piece p = {.material = m};
    p.coeffs.temperature = NAN;
    while (state->time < t_end) {
        p.t0 = state->time;
        p.t1 = sinter_neck_schedule_next_break(schedule, m, p.t0, t_end);
        p.temperature0 = sinter_neck_schedule_temperature(schedule, p.t0);
        p.temperature1 = sinter_neck_schedule_temperature(schedule, p.t1);
        p.phase = sinter_neck_schedule_phase(schedule, m, p.t0, p.t1);
        p.coeffs.temperature = NAN;
        counters->segments += 1;
        while (state->time < p.t1) {
            /* Next grid node strictly after the current time, then cut at events. */
            double target = start + time_scale * expm1((double)(node + 1) * du);
            if (node + 1 >= steps)
                target = t_end;
            double t_next = fmin(target, p.t1);
            if (outputs != NULL && next_output < outputs->count)
                t_next = fmin(t_next, outputs->times[next_output]);
            if (!(t_next > state->time)) { /* node at or behind us after a cut */
                ++node;
                continue;
            }
            double y_new[SINTER_NECK_DOF];
            sinter_neck_domain_error err;
            if (rk4_step(&p, state->time, t_next - state->time, state->y, y_new, &err,
                         &counters->rhs_evaluations) != SINTER_NECK_VALID) {
                char what[200];
                sinter_neck_describe_violation(&err, what, sizeof(what));
                return sinter_fail(ctx, SINTER_ERR_UNSTABLE,
                                   "%s: step from t = %.9g s to %.9g s left the domain: %s "
                                   "(7dof.md section 2.5); with a fixed step this usually means "
                                   "the step exceeds the explicit stability limit, use more "
                                   "steps",
                                   WHO, state->time, t_next, what);
            }
            memcpy(state->y, y_new, sizeof(y_new));
            state->time = t_next;
            counters->steps += 1;
            if (t_next >= target)
                ++node;
            while (outputs != NULL && next_output < outputs->count &&
                   outputs->times[next_output] <= state->time) {
                memcpy(outputs->states + SINTER_NECK_DOF * next_output, state->y, sizeof(state->y));
                ++next_output;
            }
        }
    }
    /* Seed 001 eq. 43: decrements of y4 and y7 over this advance. */
    state->last_dy4 = y4_start - state->y[SINTER_NECK_LA];
    state->last_dy7 = y7_start - state->y[SINTER_NECK_LB];
    return SINTER_OK;
}
