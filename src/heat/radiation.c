/*
 * Radiation exchange with the environment at theta_E, Stefan-Boltzmann (seed 003 eq. 41):
 * Q = epsilon sigma A_s (theta_E^4 - theta^4), A_s = 4 pi r^2, epsilon = the particle
 * material's emissivity, sigma = 5.670374419e-8 W/(m^2 K^4) (CODATA 2018; the seed prints
 * 5.670367e-8). One-way: "temperature" theta_E (may follow a schedule) does not respond to the
 * particles; no view factors, no exchange between particles or with walls.
 */
#include "contact/particle_pass.h"
#include "heat_model.h"
#include "particles/particles.h"

static const double PI = 3.14159265358979323846;
static const double SIGMA = 5.670374419e-8;

typedef struct radiation_job {
    const sinter_particles *ps;
    double *heat;
    double te4, c;
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
        job->heat[i] += eps * job->c * r[i] * r[i] * (job->te4 - t2 * t2); /* eq. 41 */
    }
}

static sinter_status radiation_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double te = sinter_heat_param(hm, 0, e->time);
    radiation_job job = {e->ps, e->heat, te * te * te * te, 4.0 * PI * SIGMA};
    sinter_particle_pass(e->ctx, e->pp, e->ps->count, radiation_range, &job);
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_radiation = {"radiation",    0,   {"temperature", NULL}, {293.15},
                                               radiation_eval, NULL};
