/*
 * Step 1 of the quasi-static stepper with a pair law other than the 7DOF model: every link's
 * pair advanced freely over the global step by the classic grain-boundary diffusion law
 * (neck/gb_law.c) or by a host law (sinter_stepper_set_neck_law, include/sinter_submodel.h).
 * The rest of the step is the 7DOF model's: the decrease of L_A + L_B is the pair's free
 * approach, turned into a sintering force (seed 001 eq. 13, 17).
 */
#include <math.h>
#include <string.h>

#include "contact/neighbors.h" /* sinter_threads */
#include "stepper/qs_struct.h"
#include "stepper/quasistatic.h"

/* The grain-boundary law on one link: the neck grows by the law, L_A and L_B shrink by the free
 * approach (a1^2 - a0^2) / (4 R*) (Coble's a^2 = 4 R* delta), shared as the caps' heights
 * a^2 / (2 R_P) are: R* / R_A to A and R* / R_B to B. */
static int gb_link(const sinter_qs_link *l, const sinter_neck_schedule *s, double t, double h,
                   double y[SINTER_NECK_DOF])
{
    memcpy(y, l->neck.y, SINTER_NECK_DOF * sizeof(double));
    const double ra = y[SINTER_NECK_RA], rb = y[SINTER_NECK_RB];
    const double a0 = y[SINTER_NECK_X];
    double a1 = a0;
    if (sinter_gb_law_advance(&l->material, s, ra, rb, t, t + h, &a1) != 0) {
        y[SINTER_NECK_X] = NAN; /* reported by the caller's check */
        return -1;
    }
    const double rstar = ra * rb / (ra + rb);
    const double approach = (a1 - a0) * (a1 + a0) / (4.0 * rstar);
    y[SINTER_NECK_X] = a1;
    y[SINTER_NECK_LA] -= approach * (rstar / ra);
    y[SINTER_NECK_LB] -= approach * (rstar / rb);
    return 0;
}

/* The host law over every link: the batch of include/sinter_submodel.h. */
static sinter_status host_links(sinter_qs *qs, const sinter_qs_particles *p,
                                const sinter_neck_schedule *s, double t, double h, double *out)
{
    const size_t m = qs->count;
    sinter_ctx *ctx = qs->ctx;
    uint32_t *ab = sinter_calloc(ctx, 2 * m + 1, sizeof(uint32_t));
    int32_t *material = sinter_calloc(ctx, m + 1, sizeof(int32_t));
    double *radii = sinter_calloc(ctx, 2 * m + 1, sizeof(double));
    sinter_status st = SINTER_OK;
    if (ab == NULL || material == NULL || radii == NULL) {
        st = SINTER_ERR_NOMEM;
    } else {
        for (size_t k = 0; k < m; ++k) {
            const sinter_qs_link *l = &qs->links[k];
            ab[k] = l->beam.a;
            ab[m + k] = l->beam.b;
            material[k] = p->material != NULL ? p->material[l->beam.a] : 0;
            radii[k] = p->radius[l->beam.a];
            radii[m + k] = p->radius[l->beam.b];
            memcpy(out + SINTER_NECK_DOF * k, l->neck.y, sizeof(l->neck.y));
        }
        sinter_neck_law_batch batch = {m,  t,      h,        s->count, s->times,  s->temperatures,
                                       ab, ab + m, material, radii,    radii + m, out};
        const int rc = qs->opt.host_law.advance(&batch, qs->opt.host_law_user);
        if (rc != 0)
            st = sinter_fail(ctx, SINTER_ERR_CALLBACK,
                             "quasi-static stepper: the host neck law returned %d for %zu links "
                             "from t = %.9g s; the state at t is kept",
                             rc, m, t);
    }
    sinter_free(ctx, ab);
    sinter_free(ctx, material);
    sinter_free(ctx, radii);
    return st;
}

void sinter_qs_set_host_law(sinter_qs *qs, const sinter_qs_options *opt)
{
    qs->opt.neck_law = opt->neck_law;
    qs->opt.host_law = opt->host_law;
    qs->opt.host_law_user = opt->host_law_user;
}

sinter_status sinter_qs_advance_law(sinter_qs *qs, const sinter_qs_particles *p,
                                    const sinter_neck_schedule *schedule, double t, double h)
{
    const size_t m = qs->count;
    const int host = qs->opt.neck_law == 2.0;
    if (host && qs->opt.host_law.advance == NULL)
        return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                           "quasi-static stepper: qs_neck_law = 2 but no host neck law is set "
                           "(sinter_stepper_set_neck_law)");
    double *out = sinter_calloc(qs->ctx, SINTER_NECK_DOF * m + 1, sizeof(double));
    if (out == NULL)
        return SINTER_ERR_NOMEM;
    sinter_status st = SINTER_OK;
    size_t bad = m;
    if (host) {
        st = host_links(qs, p, schedule, t, h, out);
    } else {
        /* pairs are independent: the same bits on any thread count */
        const int threads = m < 64 ? 1 : sinter_threads(qs->ctx);
        if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
            for (size_t k = 0; k < m; ++k)
                (void)gb_link(&qs->links[k], schedule, t, h, out + SINTER_NECK_DOF * k);
        } else { /* a region of one thread costs a team (core/ranges_run.h) */
            for (size_t k = 0; k < m; ++k)
                (void)gb_link(&qs->links[k], schedule, t, h, out + SINTER_NECK_DOF * k);
        }
    }
    for (size_t k = 0; k < m && st == SINTER_OK && bad == m; ++k)
        for (int i = 0; i < SINTER_NECK_DOF; ++i)
            if (!isfinite(out[SINTER_NECK_DOF * k + (size_t)i]) ||
                !(out[SINTER_NECK_DOF * k + (size_t)i] > 0.0))
                bad = k;
    if (st == SINTER_OK && bad < m) {
        const sinter_qs_link *l = &qs->links[bad];
        st = sinter_fail(qs->ctx, SINTER_ERR_DOMAIN,
                         "quasi-static stepper: the %s neck law left the pair of particles id "
                         "%llu and id %llu with a value not finite or <= 0 (neck radius %g m) "
                         "from t = %.9g s; the state at t is kept",
                         host ? "host" : "grain-boundary diffusion", (unsigned long long)l->id_a,
                         (unsigned long long)l->id_b, out[SINTER_NECK_DOF * bad], t);
    }
    if (st == SINTER_OK)
        for (size_t k = 0; k < m; ++k)
            memcpy(qs->links[k].neck.y, out + SINTER_NECK_DOF * k, sizeof(qs->links[k].neck.y));
    sinter_free(qs->ctx, out);
    return st;
}
