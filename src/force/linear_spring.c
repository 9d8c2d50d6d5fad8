/*
 * Linear spring-dashpot normal contact: f_i = -(k_n delta + c_n delta_dot) n.
 * The textbook reference law (no friction); used to check host submodels
 * against a built-in one and as a cheap law for tests.
 * Parameters: "kn" [N/m], "cn" [kg/s].
 */
#include "force_model.h"
#include "vec3.h"

static void spring(const sinter_force_model *fm, const double n[3], double delta, const double u[3],
                   double f[3])
{
    const double fn = fm->param[0] * delta + fm->param[1] * v3_dot(u, n);
    for (int d = 0; d < 3; ++d)
        f[d] = -fn * n[d];
}

static sinter_status linear_spring_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const double *v = e->ps->v;
    const sinter_contact_list *c = e->pp;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        const double u[3] = {v[3 * i] - v[3 * j], v[3 * i + 1] - v[3 * j + 1],
                             v[3 * i + 2] - v[3 * j + 2]};
        double f[3];
        spring(fm, c->n + 3 * k, c->delta[k], u, f);
        for (int d = 0; d < 3; ++d) {
            e->force[3 * i + d] += f[d];
            e->force[3 * j + d] -= f[d];
        }
    }
    if (e->walls == NULL)
        return SINTER_OK;
    c = e->pw;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], wk = c->j[k];
        const sinter_wall *wall = &e->walls->wall[wk];
        const double *n = c->n + 3 * k, li = c->branch[k];
        const double at[3] = {e->ps->x[3 * i] + li * n[0], e->ps->x[3 * i + 1] + li * n[1],
                              e->ps->x[3 * i + 2] + li * n[2]};
        double uw[3];
        sinter_wall_velocity_at(wall, at, uw); /* the surface's velocity at the contact */
        const double u[3] = {v[3 * i] - uw[0], v[3 * i + 1] - uw[1], v[3 * i + 2] - uw[2]};
        double f[3];
        spring(fm, n, c->delta[k], u, f);
        for (int d = 0; d < 3; ++d) {
            e->force[3 * i + d] += f[d];
            e->wall_force[3 * wk + d] -= f[d];
        }
        if (e->pw_reaction != NULL) /* (the reproducible mode: each contact's own) */
            for (int d = 0; d < 3; ++d)
                e->pw_reaction[6 * k + (size_t)d] -= f[d];
        if (e->wall_moment != NULL && wall->moment_wanted)
            sinter_wall_add_moment(wall, at, f, NULL, e->wall_moment + 3 * wk);
        if (e->pw_reaction != NULL && e->wall_moment != NULL && wall->moment_wanted)
            sinter_wall_add_moment(wall, at, f, NULL, e->pw_reaction + 6 * k + 3);
    }
    return SINTER_OK;
}

const sinter_force_ops sinter_force_linear_spring = {"linear_spring",
                                                     0,
                                                     0,
                                                     1,
                                                     {"kn", "cn", NULL},
                                                     {1e3, 0.0},
                                                     linear_spring_eval,
                                                     NULL,
                                                     NULL,
                                                     NULL,
                                                     NULL,
                                                     NULL};
