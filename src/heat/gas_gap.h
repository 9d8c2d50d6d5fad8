/*
 * Conduction through the interstitial gas between two spheres, touching or near (issue 40).
 *
 * The solid-fluid-solid path of Cheng, Yu & Zulli 1999 (also Zhou, Yu & Zulli 2009 for DEM
 * beds): heat crosses the gas along lines parallel to the line of centres, each annulus
 * 2 pi rho d rho with the local gap g(rho) as its length, the gap cut off below at a smallest
 * gap g_min of the order of the gas's mean free path. With the small-gap (paraboloid) surfaces
 * of Batchelor & O'Brien 1977, g(rho) = h + rho^2 / (2 r*), h = d - r_i - r_j the gap on the
 * line of centres (< 0 when the spheres overlap), r* = r_i r_j / (r_i + r_j), the integral from
 * the solid contact radius a (0 apart) to rho_out has a closed form for any radii and gaps:
 *   G_gas = int 2 pi k_g rho / max(g(rho), g_min) d rho
 *         = pi k_g (rho_m^2 - a^2) / g_min + 2 pi k_g r* ln(g(rho_out) / g(rho_lo)),
 * rho_m^2 = 2 r* (g_min - h) the radius inside which the cut-off holds (clamped to
 * [a^2, rho_out^2]), rho_lo = max(a, rho_m). It is continuous through touching (h = 0, a = 0),
 * so one law serves the contacts and the pairs apart.
 */
#ifndef SINTER_GAS_GAP_H
#define SINTER_GAS_GAP_H

#include <math.h>

#include "heat_model.h"

/* G_gas [W/K] of a lens of outer radius rout [m] (gas conductivity kg [W/(m K)], smallest gap
 * gmin [m], r* [m], gap h [m] on the line of centres, solid contact radius squared a2 [m^2]). */
static inline double sinter_gas_lens(double kg, double gmin, double rout, double rstar, double h,
                                     double a2)
{
    const double pi = 3.14159265358979323846;
    const double c = 0.5 / rstar, out2 = rout * rout;
    if (!(out2 > a2))
        return 0.0;
    double m2 = (gmin - h) / c; /* rho_m^2 */
    m2 = m2 < a2 ? a2 : m2 > out2 ? out2 : m2;
    double g = pi * kg * (m2 - a2) / gmin;
    if (out2 > m2)
        g += pi * kg / c * log((h + c * out2) / (h + c * m2));
    return g;
}

/* The gas law's parameters (the "conduction" model's gas_* keys). */
typedef struct sinter_gas_law {
    double k;      /* gas conductivity [W/(m K)]; 0: none */
    double gap;    /* smallest gap g_min [m] */
    double radius; /* outer radius of the lens / min(r_i, r_j) */
    double reach;  /* pairs apart conduct while h < reach min(r_i, r_j); 0: touching pairs only */
} sinter_gas_law;

/*
 * The pairs apart (e->pairs: the candidate pairs that do not touch by the contact search's own
 * test, d^2 >= (r_i + r_j)^2) with a gap h < reach min(r_i, r_j): Q = G_gas (theta_j - theta_i)
 * added to particle i and subtracted from j, exactly antisymmetric, so sum m C theta is kept to
 * round-off. Explicit in both schemes (the implicit solve couples the contacts only: the pairs
 * apart enter its right-hand side). Nothing without a candidate list (e->pairs NULL).
 */
void sinter_gas_near_pairs(const sinter_heat_eval *e, const sinter_gas_law *law);

/* The reach of model hm at time t as a fraction of the smaller radius: "gas_reach" of a
 * "conduction" model with gas (gas_conductivity > 0), else 0 (conduction.c). A stepper widens
 * its neighbour search by it times the largest radius. */
double sinter_heat_gas_reach(const sinter_heat_model *hm, double t);

#endif
