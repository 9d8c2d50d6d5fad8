/*
 * Radiation exchange with the environment at theta_E, Stefan-Boltzmann (seed 003 eq. 41):
 * Q = epsilon sigma A_s (theta_E^4 - theta^4), A_s = 4 pi r^2, epsilon = the particle
 * material's emissivity, sigma = 5.670374419e-8 W/(m^2 K^4) (CODATA 2018; the seed prints
 * 5.670367e-8). One-way: "temperature" theta_E (may follow a schedule) does not respond to the
 * particles; no view factors, no exchange between particles or with walls.
 */
#include "heat_model.h"
#include "particles/particles.h"

static const double PI = 3.14159265358979323846;
static const double SIGMA = 5.670374419e-8;

static sinter_status radiation_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double te = sinter_heat_param(hm, 0, e->time);
    const double te4 = te * te * te * te;
    const sinter_particles *ps = e->ps;
    const double *r = ps->radius, *theta = ps->temperature;
    const double c = 4.0 * PI * SIGMA;
    for (size_t i = 0; i < ps->count; ++i) {
        const double t2 = theta[i] * theta[i];
        const double eps = sinter_particle_param(ps, i, SINTER_MAT_EMISSIVITY);
        e->heat[i] += eps * c * r[i] * r[i] * (te4 - t2 * t2); /* eq. 41 */
    }
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_radiation = {
    "radiation", 0, {"temperature", NULL}, {293.15}, radiation_eval, NULL};
