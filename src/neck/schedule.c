/*
 * Piecewise-linear temperature schedule T(t) and the times where the neck RHS stops being
 * smooth: the schedule's points (dT/dt jumps) and crossings of the phase-transition temperature
 * (the diffusion data jump, docs/7dof.md §6.1 and §6.5: "integrate piecewise, with breakpoints at
 * the switch times and at the start and end of the hold").
 */
#include <math.h>

#include "neck/neck.h"

double sinter_neck_schedule_temperature(const sinter_neck_schedule *s, double t)
{
    return sinter_interpolate(s->count, s->times, s->temperatures, t);
}

double sinter_neck_schedule_next_break(const sinter_neck_schedule *s, const sinter_neck_material *m,
                                       double t, double t_end)
{
    double next = t_end;
    const double tt = m->transition_temperature;
    for (size_t k = 0; k < s->count; ++k) {
        const double tk = s->times[k];
        if (tk > t && tk < next)
            next = tk;
        /* A crossing of the transition inside (times[k], times[k+1]) on the linear piece. */
        if (tt > 0.0 && k + 1 < s->count) {
            const double t0 = s->times[k], t1 = s->times[k + 1];
            const double T0 = s->temperatures[k], T1 = s->temperatures[k + 1];
            if ((T0 - tt) * (T1 - tt) < 0.0) {
                const double cross = t0 + (tt - T0) / (T1 - T0) * (t1 - t0);
                if (cross > t && cross < next)
                    next = cross;
            }
        }
    }
    return next;
}

int sinter_neck_schedule_phase(const sinter_neck_schedule *s, const sinter_neck_material *m,
                               double t0, double t1)
{
    return sinter_neck_phase_at(m, sinter_neck_schedule_temperature(s, 0.5 * (t0 + t1)));
}

int sinter_neck_schedule_constant(const sinter_neck_schedule *s, double t0, double t1)
{
    const double T0 = sinter_neck_schedule_temperature(s, t0);
    if (sinter_neck_schedule_temperature(s, t1) != T0)
        return 0;
    for (size_t k = 0; k < s->count; ++k)
        if (s->times[k] > t0 && s->times[k] < t1 && s->temperatures[k] != T0)
            return 0;
    return 1;
}
