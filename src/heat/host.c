/* Host heat submodels: one batched callback per evaluation. */
#include <string.h>

#include "contact/host_views.h"
#include "heat_model.h"

sinter_status sinter_heat_host_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const size_t n = e->ps->count;
    double *q = sinter_calloc(e->ctx, n + e->pp->count + e->pw->count + 1, sizeof(double));
    if (q == NULL)
        return SINTER_ERR_NOMEM;
    double *radius_pp = q + n, *radius_pw = q + n + e->pp->count;
    sinter_contact_radii(e->pp, radius_pp);
    sinter_contact_radii(e->pw, radius_pw);
    sinter_contact_batch pp, pw;
    sinter_host_contact_batch(e->pp, SINTER_CONTACT_PARTICLE, radius_pp, &pp);
    sinter_host_contact_batch(e->pw, SINTER_CONTACT_WALL, radius_pw, &pw);
    const int rc = hm->host.power(e->view, &pp, &pw, q, hm->user);
    sinter_status st = SINTER_OK;
    if (rc != 0)
        st = sinter_fail(e->ctx, SINTER_ERR_CALLBACK,
                         "host heat model '%s' returned %d at t = %g s", hm->name, rc, e->time);
    else
        for (size_t i = 0; i < n; ++i)
            e->heat[i] += q[i];
    sinter_free(e->ctx, q);
    return st;
}

int sinter_heat_host_reads_geometry(const sinter_heat_model *hm, double t)
{
    (void)hm;
    (void)t;
    return 1; /* the batches carry the contact radii */
}
