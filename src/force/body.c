/* Body forces: gravity m g and a constant force on every particle (seed 003 eq. 1). */
#include "force_model.h"

static sinter_status gravity_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const double g[3] = {fm->param[0], fm->param[1], fm->param[2]};
    const double *m = e->ps->mass;
    double *f = e->force;
    const long n = (long)e->ps->count;
#pragma omp parallel for num_threads(n < 4096 ? 1 : sinter_threads(e->ctx)) schedule(static)
    for (long i = 0; i < n; ++i) {
        f[3 * i] += m[i] * g[0];
        f[3 * i + 1] += m[i] * g[1];
        f[3 * i + 2] += m[i] * g[2];
    }
    return SINTER_OK;
}

static sinter_status body_force_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    double *f = e->force;
    for (size_t i = 0; i < e->ps->count; ++i) {
        f[3 * i] += fm->param[0];
        f[3 * i + 1] += fm->param[1];
        f[3 * i + 2] += fm->param[2];
    }
    return SINTER_OK;
}

const sinter_force_ops sinter_force_gravity = {.name = "gravity",
                                               .keys = {"gx", "gy", "gz", NULL},
                                               .defaults = {0.0, 0.0, -9.81},
                                               .eval = gravity_eval};

const sinter_force_ops sinter_force_body_force = {.name = "body_force",
                                                  .keys = {"fx", "fy", "fz", NULL},
                                                  .defaults = {0.0, 0.0, 0.0},
                                                  .eval = body_force_eval};
