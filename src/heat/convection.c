/*
 * Convection to a surrounding fluid at theta_E (seed 003 eq. 37-40): Newton's law
 * Q = h (theta_E - theta) A_s with A_s = 4 pi r^2 (eq. 37). The film coefficient is "h" when
 * it is > 0, otherwise h = Nu k_E / (2 r) (eq. 38) with Whitaker's correlation (eq. 39)
 * Nu = 2 + (0.4 Re^1/2 + 0.06 Re^2/3) Pr^0.4, Re = rho_E v 2 r / mu_E, Pr = C_E mu_E / k_E
 * (eq. 40) and mu_E / mu_E,s = 1 (as the seed assumes). A stagnant fluid ("fluid_speed" = 0)
 * gives Nu = 2 exactly, h = k_E / r. The fluid is one-way: its temperature is a parameter (it
 * may follow a schedule) and does not respond to the particles; v is the fluid's speed, not
 * relative to each particle.
 *
 * Options beyond the seed (issue 40), both off by default:
 * - "exposed" = 1 scales A_s by the fraction of the surface that faces the surroundings
 *   (heat/exposure.h), for particles buried in a bed.
 * - "fluid_law" = 1: the fluid's properties depend on the film temperature
 *   theta_f = (theta + theta_E) / 2 of each particle, the given ones holding at
 *   "fluid_reference_temperature" T0: viscosity and conductivity by Sutherland's law,
 *   p(T) = p(T0) (T / T0)^(3/2) (T0 + S) / (T + S), with S = "sutherland_viscosity" and
 *   "sutherland_conductivity" (air's 111 K and 194 K: White, Viscous Fluid Flow, 3rd ed.,
 *   McGraw-Hill 2006, tables 1-2 and 1-3), the density of an ideal gas at constant pressure,
 *   rho(T) = rho(T0) T0 / T, the heat capacity constant.
 */
#include <math.h>

#include "contact/particle_pass.h"
#include "heat/exposure.h"
#include "heat_model.h"
#include "particles/particles.h"

enum {
    P_TEMP = 0,
    P_H,
    P_K,
    P_MU,
    P_C,
    P_RHO,
    P_SPEED,
    P_EXPOSED,
    P_LAW,
    P_T0,
    P_S_MU,
    P_S_K,
    P_COUNT
};

static const double PI = 3.14159265358979323846;

/* The film law of one evaluation: h given, a stagnant fluid, or Whitaker's correlation. */
enum film { FILM_GIVEN, FILM_STAGNANT, FILM_WHITAKER };

typedef struct convection_job {
    const sinter_particles *ps;
    double *heat;
    enum film film;
    double theta_e, k_e, h4pi, c, pr04, re_per_d;
    /* the general path (exposed fractions or a fluid law): per particle */
    const double *exposed; /* or NULL */
    int law;
    double mu_e, c_e, rho_e, speed, t0, s_mu, s_k;
} convection_job;

/* Sutherland's law: the ratio p(t) / p(t0) for the constant s [K]. */
static double sutherland(double t, double t0, double s)
{
    return pow(t / t0, 1.5) * (t0 + s) / (t + s);
}

/* h A_s (theta_E - theta_i) of particle i by the general path (the same formulas). */
static double convection_general(const convection_job *job, size_t i, double r, double theta)
{
    double h = job->h4pi / (4.0 * PI); /* FILM_GIVEN: no fluid property is read */
    if (job->film != FILM_GIVEN) {
        double k = job->k_e, mu = job->mu_e, rho = job->rho_e, pr04 = job->pr04;
        if (job->law) { /* the properties at the film temperature */
            const double tf = 0.5 * (theta + job->theta_e);
            k *= sutherland(tf, job->t0, job->s_k);
            mu *= sutherland(tf, job->t0, job->s_mu);
            rho *= job->t0 / tf;
            if (job->film == FILM_WHITAKER)
                pr04 = pow(job->c_e * mu / k, 0.4); /* eq. 40 */
        }
        if (job->film == FILM_STAGNANT) {
            h = k / r; /* Nu = 2 */
        } else {
            const double re = rho * job->speed * 2.0 * r / mu;
            const double nu = 2.0 + (0.4 * sqrt(re) + 0.06 * cbrt(re * re)) * pr04; /* eq. 39 */
            h = nu * k / (2.0 * r);                                                 /* eq. 38 */
        }
    }
    const double q = h * 4.0 * PI * r * r * (job->theta_e - theta); /* eq. 37 */
    return job->exposed != NULL ? job->exposed[i] * q : q;
}

static void convection_range(void *data, int range, size_t lo, size_t hi)
{
    (void)range;
    const convection_job *job = data;
    const double *r = job->ps->radius, *theta = job->ps->temperature;
    const double theta_e = job->theta_e, k_e = job->k_e;
    double *heat = job->heat;
    if (job->exposed != NULL || job->law) {
        for (size_t i = lo; i < hi; ++i)
            heat[i] += convection_general(job, i, r[i], theta[i]);
    } else if (job->film == FILM_GIVEN) {
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
    double p[P_COUNT];
    for (int k = 0; k < P_COUNT; ++k)
        p[k] = sinter_heat_param(hm, k, e->time);
    const double k_e = p[P_K], mu_e = p[P_MU];
    convection_job job = {
        .ps = e->ps, .heat = e->heat, .film = FILM_GIVEN, .theta_e = p[P_TEMP], .k_e = k_e};
    sinter_status st = sinter_heat_exposed_check(hm, p[P_EXPOSED], e->ctx);
    if (st != SINTER_OK)
        return st;
    if (p[P_LAW] != 0.0 && p[P_LAW] != 1.0)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': fluid_law = %g must be 0 (constant properties) or 1 "
                           "(Sutherland's law and an ideal gas)",
                           hm->name, p[P_LAW]);
    if (p[P_LAW] == 1.0 && !(p[P_T0] > 0.0 && p[P_S_MU] >= 0.0 && p[P_S_K] >= 0.0))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': fluid_law = 1 needs fluid_reference_temperature > 0 "
                           "and Sutherland constants >= 0 (got %g, %g, %g K)",
                           hm->name, p[P_T0], p[P_S_MU], p[P_S_K]);
    job.law = p[P_LAW] == 1.0;
    job.mu_e = mu_e;
    job.c_e = p[P_C];
    job.rho_e = p[P_RHO];
    job.speed = p[P_SPEED];
    job.t0 = p[P_T0];
    job.s_mu = p[P_S_MU];
    job.s_k = p[P_S_K];
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
    double *fraction = NULL;
    if (p[P_EXPOSED] == 1.0 && (st = sinter_heat_exposed_fraction(e, &fraction)) != SINTER_OK)
        return st;
    job.exposed = fraction;
    sinter_particle_pass(e->ctx, e->pp, sinter_heat_owned(e), convection_range, &job);
    sinter_free(e->ctx, fraction);
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_convection = {
    "convection",
    0,
    {"temperature", "h", "fluid_conductivity", "fluid_viscosity", "fluid_heat_capacity",
     "fluid_density", "fluid_speed", "exposed", "fluid_law", "fluid_reference_temperature",
     "sutherland_viscosity", "sutherland_conductivity", NULL},
    {293.15, 0.0, 0.026, 1.8e-5, 1005.0, 1.2, 0.0, 0.0, 0.0, 293.15, 111.0, 194.0},
    convection_eval,
    NULL};
