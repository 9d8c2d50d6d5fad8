/*
 * Interstitial drag of seed 000 eq. 20: f_i = -c_env (v_i - v_env), with c_env the particle's
 * material SINTER_MAT_DRAG_COEFFICIENT [kg/s] and v_env the medium's velocity from the model
 * parameters "vx", "vy", "vz" [m/s] (default 0, the seed's v_env ~ 0).
 */
#include "force_model.h"

static sinter_status drag_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    const double *v = ps->v;
    for (size_t i = 0; i < ps->count; ++i) {
        const double c = ps->materials[ps->material[i]].value[SINTER_MAT_DRAG_COEFFICIENT];
        for (int d = 0; d < 3; ++d)
            e->force[3 * i + d] -= c * (v[3 * i + d] - fm->param[d]); /* eq. 20 */
    }
    return SINTER_OK;
}

const sinter_force_ops sinter_force_drag = {
    "drag", 0, 0, 0, {"vx", "vy", "vz", NULL}, {0.0, 0.0, 0.0}, drag_eval, NULL, NULL, NULL};
