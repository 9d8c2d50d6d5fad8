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

#include "heat_model.h"
#include "particles/particles.h"

enum { P_TEMP = 0, P_H, P_K, P_MU, P_C, P_RHO, P_SPEED };

static const double PI = 3.14159265358979323846;

static sinter_status convection_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    double p[P_SPEED + 1];
    for (int k = 0; k <= P_SPEED; ++k)
        p[k] = sinter_heat_param(hm, k, e->time);
    const double theta_e = p[P_TEMP], k_e = p[P_K], mu_e = p[P_MU];
    const sinter_particles *ps = e->ps;
    const double *r = ps->radius, *theta = ps->temperature;
    double *heat = e->heat;
    const size_t n = ps->count;
    if (p[P_H] > 0.0) {
        const double h4pi = 4.0 * PI * p[P_H];
        for (size_t i = 0; i < n; ++i)
            heat[i] += h4pi * r[i] * r[i] * (theta_e - theta[i]); /* eq. 37 */
        return SINTER_OK;
    }
    if (!(k_e > 0.0 && mu_e > 0.0 && p[P_C] >= 0.0 && p[P_RHO] >= 0.0 && p[P_SPEED] >= 0.0))
        return sinter_fail(
            e->ctx, SINTER_ERR_INVALID,
            "heat model '%s': the Whitaker correlation needs fluid_conductivity > 0, "
            "fluid_viscosity > 0 and fluid_heat_capacity, fluid_density, "
            "fluid_speed >= 0 (or set 'h' > 0)",
            hm->name);
    if (p[P_SPEED] == 0.0) {
        /* Stagnant: Nu = 2, h = Nu k_E / (2 r) (eq. 38-39), so h A_s = 4 pi k_E r. */
        const double c = 4.0 * PI * k_e;
        for (size_t i = 0; i < n; ++i)
            heat[i] += c * r[i] * (theta_e - theta[i]);
        return SINTER_OK;
    }
    const double pr04 = pow(p[P_C] * mu_e / k_e, 0.4);    /* eq. 40 */
    const double re_per_d = p[P_RHO] * p[P_SPEED] / mu_e; /* Re / (2 r) */
    for (size_t i = 0; i < n; ++i) {
        const double re = re_per_d * 2.0 * r[i];
        const double nu = 2.0 + (0.4 * sqrt(re) + 0.06 * cbrt(re * re)) * pr04; /* eq. 39 */
        const double h = nu * k_e / (2.0 * r[i]);                               /* eq. 38 */
        heat[i] += h * 4.0 * PI * r[i] * r[i] * (theta_e - theta[i]);           /* eq. 37 */
    }
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_convection = {"convection",
                                                0,
                                                {"temperature", "h", "fluid_conductivity",
                                                 "fluid_viscosity", "fluid_heat_capacity",
                                                 "fluid_density", "fluid_speed", NULL},
                                                {293.15, 0.0, 0.026, 1.8e-5, 1005.0, 1.2, 0.0},
                                                convection_eval, NULL};
