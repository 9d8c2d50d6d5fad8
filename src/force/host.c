/* Host force submodels: batched callbacks over contacts and particles. */
#include <string.h>

#include "force_model.h"

/* Scratch for one batch, allocated per call (host models are not the fast path). */
static sinter_status run_batch(const sinter_force_model *fm, sinter_force_eval *e,
                               const sinter_contact_list *c, sinter_history *h, int kind)
{
    sinter_ctx *ctx = e->ctx;
    const size_t n = c->count, w = fm->host.history_size;
    if (n == 0)
        return SINTER_OK;
    double *out = sinter_calloc(ctx, 10 * n, sizeof(double));
    double *hist = w ? sinter_calloc(ctx, w * n, sizeof(double)) : NULL;
    if (out == NULL || (w && hist == NULL)) {
        sinter_free(ctx, out);
        sinter_free(ctx, hist);
        return SINTER_ERR_NOMEM;
    }
    for (size_t k = 0; k < n && w; ++k)
        memcpy(hist + k * w, h->committed + (size_t)c->pair[k] * w, w * sizeof(double));
    double *radius = out + 9 * n;
    sinter_contact_radii(c, radius);
    sinter_contact_batch b = {n,          kind,       c->i,      c->j,  c->n,
                              c->delta,   c->dist,    radius,    c->area, c->branch,
                              w,          hist,       w ? h->trial : NULL,
                              out,        out + 3 * n, out + 6 * n};
    const int rc = fm->host.contacts(e->view, &b, fm->user);
    sinter_status st = SINTER_OK;
    if (rc != 0) {
        st = sinter_fail(ctx, SINTER_ERR_CALLBACK,
                         "host force model '%s' returned %d for a batch of %zu %s contacts at "
                         "t = %g s",
                         fm->name, rc, n, kind == SINTER_CONTACT_WALL ? "wall" : "particle",
                         e->time);
    } else {
        for (size_t k = 0; k < n; ++k) {
            const uint32_t i = c->i[k], j = c->j[k];
            for (int d = 0; d < 3; ++d) {
                e->force[3 * i + d] += out[3 * k + d];
                e->torque[3 * i + d] += out[3 * n + 3 * k + d];
                if (kind == SINTER_CONTACT_PARTICLE) {
                    e->force[3 * j + d] -= out[3 * k + d];
                    e->torque[3 * j + d] += out[6 * n + 3 * k + d];
                } else {
                    e->wall_force[3 * j + d] -= out[3 * k + d];
                    if (e->pw_reaction != NULL) /* (the reproducible mode) */
                        e->pw_reaction[6 * k + (size_t)d] -= out[3 * k + d];
                }
            }
            if (kind == SINTER_CONTACT_WALL && e->wall_moment != NULL &&
                e->walls->wall[j].moment_wanted) {
                /* the torque the host gave the particle about its centre, less the force's
                 * moment, is its contact moment (its rolling moment) */
                const double *nrm = c->n + 3 * k, li = c->branch[k], *f = out + 3 * k;
                const double *x = e->ps->x + 3 * i;
                const double arm[3] = {li * nrm[0], li * nrm[1], li * nrm[2]};
                const double at[3] = {x[0] + arm[0], x[1] + arm[1], x[2] + arm[2]};
                double mr[3];
                mr[0] = out[3 * n + 3 * k] - (arm[1] * f[2] - arm[2] * f[1]);
                mr[1] = out[3 * n + 3 * k + 1] - (arm[2] * f[0] - arm[0] * f[2]);
                mr[2] = out[3 * n + 3 * k + 2] - (arm[0] * f[1] - arm[1] * f[0]);
                sinter_wall_add_moment(&e->walls->wall[j], at, f, mr, e->wall_moment + 3 * j);
                if (e->pw_reaction != NULL)
                    sinter_wall_add_moment(&e->walls->wall[j], at, f, mr,
                                           e->pw_reaction + 6 * k + 3);
            }
        }
    }
    sinter_free(ctx, out);
    sinter_free(ctx, hist);
    return st;
}

sinter_status sinter_force_host_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    sinter_status st = SINTER_OK;
    if (fm->host.contacts != NULL) {
        st = run_batch(fm, e, e->pp, e->hist_pp, SINTER_CONTACT_PARTICLE);
        if (st == SINTER_OK && e->walls != NULL)
            st = run_batch(fm, e, e->pw, e->hist_pw, SINTER_CONTACT_WALL);
    }
    if (st == SINTER_OK && fm->host.particles != NULL) {
        const size_t n = e->ps->count;
        double *out = sinter_calloc(e->ctx, 6 * n + 1, sizeof(double));
        if (out == NULL)
            return SINTER_ERR_NOMEM;
        const int rc = fm->host.particles(e->view, out, out + 3 * n, fm->user);
        if (rc != 0) {
            st = sinter_fail(e->ctx, SINTER_ERR_CALLBACK,
                             "host force model '%s' returned %d for the particle batch at t = "
                             "%g s",
                             fm->name, rc, e->time);
        } else {
            for (size_t k = 0; k < 3 * n; ++k) {
                e->force[k] += out[k];
                e->torque[k] += out[3 * n + k];
            }
        }
        sinter_free(e->ctx, out);
    }
    return st;
}
