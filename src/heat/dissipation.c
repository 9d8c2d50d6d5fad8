/*
 * Heat from friction and inelastic impacts (issue 40; seed 003 remark 3 names it as future
 * work). The stepper has its force models report the power each contact dissipates in the
 * state of the evaluation (sinter_force_ops.dissipation; Hertz-Mindlin: the normal damper's
 * (f_n - f_elastic) delta_dot and, where the contact slides, |f_t . u_t|), half to each
 * particle of a pair and all of it to the particle at a wall, and this model puts it into the
 * particles: Q_i = "impact" P_normal,i + "friction" P_sliding,i (each 1 or 0, default 1).
 * The kinetic plus elastic energy the contacts lose becomes heat, to the integrator's order.
 * Without such a report (no force model that gives one, or a stepper that does not ask:
 * only the explicit stepper does) the model adds nothing.
 */
#include "heat_model.h"

enum { PARAM_IMPACT = 0, PARAM_FRICTION = 1 };

static sinter_status dissipation_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double impact = sinter_heat_param(hm, PARAM_IMPACT, e->time);
    const double friction = sinter_heat_param(hm, PARAM_FRICTION, e->time);
    if ((impact != 0.0 && impact != 1.0) || (friction != 0.0 && friction != 1.0))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'impact' = %g and 'friction' = %g must be 0 or 1",
                           hm->name, impact, friction);
    const double *p = e->dissipation;
    if (p == NULL)
        return SINTER_OK;
    const size_t n = e->ps->count;
    for (size_t i = 0; i < n; ++i) {
        if (impact != 0.0)
            e->heat[i] += p[2 * i];
        if (friction != 0.0)
            e->heat[i] += p[2 * i + 1];
    }
    return SINTER_OK;
}

/* The force models' report reads the pair contacts' geometry: the stepper finds them with it. */
static int dissipation_reads_geometry(const sinter_heat_model *hm, double t)
{
    (void)hm;
    (void)t;
    return 1;
}

const sinter_heat_ops sinter_heat_dissipation = {"dissipation",
                                                 0,
                                                 {"impact", "friction", NULL},
                                                 {1.0, 1.0},
                                                 dissipation_eval,
                                                 dissipation_reads_geometry};
