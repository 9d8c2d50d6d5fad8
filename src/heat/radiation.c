/*
 * Radiation exchange with the environment at theta_E, Stefan-Boltzmann (seed 003 eq. 41):
 * Q = epsilon sigma A_s (theta_E^4 - theta^4), A_s = 4 pi r^2, epsilon = the particle
 * material's emissivity, sigma = 5.670374419e-8 W/(m^2 K^4) (CODATA 2018; the seed prints
 * 5.670367e-8). One-way: "temperature" theta_E (may follow a schedule) does not respond to the
 * particles; no exchange between particles or with walls. "exposed" = 1 scales A_s by the
 * fraction of the surface that sees the surroundings (heat/exposure.h: one minus the view
 * factors to touching particles and walls), for particles buried in a bed (issue 40); 0 (the
 * default) keeps the seed's whole surface.
 */
#include "contact/particle_pass.h"
#include "heat/exposure.h"
#include "heat_model.h"
#include "particles/particles.h"

static const double PI = 3.14159265358979323846;
static const double SIGMA = 5.670374419e-8;

typedef struct radiation_job {
    const sinter_particles *ps;
    double *heat;
    double te4, c;
    const double *exposed; /* per particle, or NULL: the whole surface */
} radiation_job;

static void radiation_range(void *data, int range, size_t lo, size_t hi)
{
    (void)range;
    const radiation_job *job = data;
    const sinter_particles *ps = job->ps;
    const double *r = ps->radius, *theta = ps->temperature;
    for (size_t i = lo; i < hi; ++i) {
        const double t2 = theta[i] * theta[i];
        const double eps = sinter_particle_param(ps, i, SINTER_MAT_EMISSIVITY);
        const double q = eps * job->c * r[i] * r[i] * (job->te4 - t2 * t2); /* eq. 41 */
        job->heat[i] += job->exposed != NULL ? job->exposed[i] * q : q;
    }
}

static sinter_status radiation_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double te = sinter_heat_param(hm, 0, e->time);
    const double exposed = sinter_heat_param(hm, 1, e->time);
    sinter_status st = sinter_heat_exposed_check(hm, exposed, e->ctx);
    double *fraction = NULL;
    if (st == SINTER_OK && exposed == 1.0)
        st = sinter_heat_exposed_fraction(e, &fraction);
    if (st != SINTER_OK)
        return st;
    radiation_job job = {e->ps, e->heat, te * te * te * te, 4.0 * PI * SIGMA, fraction};
    sinter_particle_pass(e->ctx, e->pp, sinter_heat_owned(e), radiation_range, &job);
    sinter_free(e->ctx, fraction);
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_radiation = {
    "radiation", 0, {"temperature", "exposed", NULL}, {293.15, 0.0}, radiation_eval, NULL};
