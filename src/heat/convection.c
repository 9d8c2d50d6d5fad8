/*
 * Convection to a surrounding fluid at theta_E (seed 003 eq. 37-40): Newton's law
 * Q = h (theta_E - theta) A_s with A_s = 4 pi r^2 (eq. 37). The film coefficient is "h" when
 * it is > 0, otherwise h = Nu k_E / (2 r) (eq. 38) with Whitaker's correlation (eq. 39)
 * Nu = 2 + (0.4 Re^1/2 + 0.06 Re^2/3) Pr^0.4, Re = rho_E v 2 r / mu_E, Pr = C_E mu_E / k_E
 * (eq. 40) and mu_E / mu_E,s = 1 (as the seed assumes). A stagnant fluid ("fluid_speed" = 0)
 * gives Nu = 2 exactly, h = k_E / r. The fluid is one-way: its temperature is a parameter (it
 * may follow a schedule) and does not respond to the particles; v is the fluid's speed, not
 * relative to each particle.
 */
#include <math.h>

#include "contact/particle_pass.h"
#include "heat_model.h"
#include "particles/particles.h"

enum { P_TEMP = 0, P_H, P_K, P_MU, P_C, P_RHO, P_SPEED };

static const double PI = 3.14159265358979323846;

/* The film law of one evaluation: h given, a stagnant fluid, or Whitaker's correlation. */
enum film { FILM_GIVEN, FILM_STAGNANT, FILM_WHITAKER };

typedef struct convection_job {
    const sinter_particles *ps;
    double *heat;
    enum film film;
    double theta_e, k_e, h4pi, c, pr04, re_per_d;
} convection_job;

static void convection_range(void *data, int range, size_t lo, size_t hi)
{
    (void)range;
    const convection_job *job = data;
    const double *r = job->ps->radius, *theta = job->ps->temperature;
    const double theta_e = job->theta_e, k_e = job->k_e;
    double *heat = job->heat;
    if (job->film == FILM_GIVEN) {
        for (size_t i = lo; i < hi; ++i)
            heat[i] += job->h4pi * r[i] * r[i] * (theta_e - theta[i]); /* eq. 37 */
    } else if (job->film == FILM_STAGNANT) {
        for (size_t i = lo; i < hi; ++i)
            heat[i] += job->c * r[i] * (theta_e - theta[i]);
    } else {
        for (size_t i = lo; i < hi; ++i) {
            const double re = job->re_per_d * 2.0 * r[i];
            const double nu =
                2.0 + (0.4 * sqrt(re) + 0.06 * cbrt(re * re)) * job->pr04; /* eq. 39 */
            const double h = nu * k_e / (2.0 * r[i]);                      /* eq. 38 */
            heat[i] += h * 4.0 * PI * r[i] * r[i] * (theta_e - theta[i]);  /* eq. 37 */
        }
    }
}

static sinter_status convection_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    double p[P_SPEED + 1];
    for (int k = 0; k <= P_SPEED; ++k)
        p[k] = sinter_heat_param(hm, k, e->time);
    const double k_e = p[P_K], mu_e = p[P_MU];
    convection_job job = {e->ps, e->heat, FILM_GIVEN, p[P_TEMP], k_e, 0.0, 0.0, 0.0, 0.0};
    if (p[P_H] > 0.0) {
        job.h4pi = 4.0 * PI * p[P_H];
    } else if (!(k_e > 0.0 && mu_e > 0.0 && p[P_C] >= 0.0 && p[P_RHO] >= 0.0 &&
                 p[P_SPEED] >= 0.0)) {
        return sinter_fail(
            e->ctx, SINTER_ERR_INVALID,
            "heat model '%s': the Whitaker correlation needs fluid_conductivity > 0, "
            "fluid_viscosity > 0 and fluid_heat_capacity, fluid_density, "
            "fluid_speed >= 0 (or set 'h' > 0)",
            hm->name);
    } else if (p[P_SPEED] == 0.0) {
        /* Stagnant: Nu = 2, h = Nu k_E / (2 r) (eq. 38-39), so h A_s = 4 pi k_E r. */
        job.film = FILM_STAGNANT;
        job.c = 4.0 * PI * k_e;
    } else {
        job.film = FILM_WHITAKER;
        job.pr04 = pow(p[P_C] * mu_e / k_e, 0.4);    /* eq. 40 */
        job.re_per_d = p[P_RHO] * p[P_SPEED] / mu_e; /* Re / (2 r) */
    }
    sinter_particle_pass(e->ctx, e->pp, e->ps->count, convection_range, &job);
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_convection = {"convection",
                                                0,
                                                {"temperature", "h", "fluid_conductivity",
                                                 "fluid_viscosity", "fluid_heat_capacity",
                                                 "fluid_density", "fluid_speed", NULL},
                                                {293.15, 0.0, 0.026, 1.8e-5, 1005.0, 1.2, 0.0},
                                                convection_eval,
                                                NULL};
