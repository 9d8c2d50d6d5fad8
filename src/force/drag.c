/*
 * Interstitial drag of seed 000 eq. 20: f_i = -c_env (v_i - v_env), with c_env the particle's
 * material SINTER_MAT_DRAG_COEFFICIENT [kg/s] and v_env the medium's velocity from the model
 * parameters "vx", "vy", "vz" [m/s] (default 0, the seed's v_env ~ 0).
 *
 * Each particle on its own, on the pair partition's particle ranges (contact/particle_pass.h):
 * the same operations on any thread count.
 */
#include "contact/particle_pass.h"
#include "force_model.h"

typedef struct drag_job {
    const sinter_force_model *fm;
    const sinter_force_eval *e;
    double coefficient[SINTER_MAX_MATERIALS];
} drag_job;

static void drag_range(void *data, int range, size_t lo, size_t hi)
{
    (void)range;
    const drag_job *job = data;
    const sinter_particles *ps = job->e->ps;
    const double *v = ps->v, *env = job->fm->param;
    const int32_t *material = ps->material;
    double *force = job->e->force;
    for (size_t i = lo; i < hi; ++i) {
        const double c = job->coefficient[material[i]];
        for (int d = 0; d < 3; ++d)
            force[3 * i + d] -= c * (v[3 * i + d] - env[d]); /* eq. 20 */
    }
}

static sinter_status drag_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    drag_job job = {fm, e, {0.0}};
    for (int m = 0; m < ps->material_top; ++m) /* the others are 0 (job's initialiser) */
        job.coefficient[m] = ps->materials[m].value[SINTER_MAT_DRAG_COEFFICIENT];
    sinter_particle_pass(e->ctx, e->pp, ps->count, drag_range, &job);
    return SINTER_OK;
}

const sinter_force_ops sinter_force_drag = {
    "drag", 0,    0,    0,   {"vx", "vy", "vz", NULL}, {0.0, 0.0, 0.0}, drag_eval, NULL,
    NULL,   NULL, NULL, NULL};
