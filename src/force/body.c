/* Body forces: gravity m g and a constant force on every particle (seed 003 eq. 1). */
#include "force_model.h"

static inline void add_weight(double m, const double g[3], double *f)
{
    f[0] += m * g[0];
    f[1] += m * g[1];
    f[2] += m * g[2];
}

static sinter_status gravity_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const double g[3] = {fm->param[0], fm->param[1], fm->param[2]};
    const double *m = e->ps->mass;
    double *f = e->force;
    const long n = (long)e->ps->count;
    const int threads = n < 4096 ? 1 : sinter_threads(e->ctx);
    if (threads > 1) { /* (a region of one thread costs a team's allocation: ranges_run.h) */
#pragma omp parallel for num_threads(threads) schedule(static)
        for (long i = 0; i < n; ++i)
            add_weight(m[i], g, f + 3 * i);
    } else {
        for (long i = 0; i < n; ++i)
            add_weight(m[i], g, f + 3 * i);
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
