/*
 * Joule heating. With the "network" electric model (by default): the power its solution
 * dissipates in the contacts (joule_from_network below), energy-consistent. Otherwise, and
 * with "source" = 1, seed 000 eq. 35 (sec. 5 remark 1): H_i = a_i J_i^2 / sigma_i V_i.
 *
 *  - J_i: the particle's current field (ps->current), written by the stepper's electric model
 *    (src/electric/) or set by the host. The formula is used as printed: with J a current
 *    density [A/m^2] H is a power [W]; the library's field is documented in A, and seed 000
 *    sec. 7 mixes both readings (see docs/validation.md's note on 000 sec. 7's units).
 *  - a_i: the absorptance of the particle's material (SINTER_MAT_ABSORPTANCE, 0 <= a <= 1).
 *  - sigma_i: the electric conductivity of its material (SINTER_MAT_ELECTRIC_CONDUCTIVITY),
 *    or, with "sigmoid" = 1, the thermo-electric saturation law of seed 000 eq. 50:
 *
 *      sigma(theta, E) = sigma_0 (1 + K1 / (1 + exp(-gamma1 (theta - theta_R)))
 *                                   + K2 / (1 + exp(-gamma2 |E - E_R|)))
 *
 *    where sigma_0 is the material's conductivity. Reading eq. 50 carefully:
 *      * the seed names the prefactor sigma(theta_R, E_R), but each sigmoid equals 1/2 at its
 *        reference, so the law evaluated at (theta_R, E_R) gives sigma_0 (1 + K1/2 + K2/2), not
 *        sigma_0. We implement the formula as written, with sigma_0 the prefactor;
 *      * the field term depends on |E - E_R| >= 0, so its sigmoid lies in [1/2, 1): it can
 *        only raise (K2 > 0) or lower (K2 < 0) the conductivity by up to |K2| sigma_0;
 *      * "for many materials sigma decreases with theta until saturation": K1 < 0 with
 *        gamma1 > 0 (or K1 > 0 with gamma1 < 0) gives that;
 *      * the field is a scalar here: E_i = |J_i| / sigma_0 (Ohm's law J = sigma E with the
 *        prefactor conductivity, in the units of J / sigma; evaluating Ohm's law with
 *        sigma(theta, E) itself would make eq. 50 implicit in E). E_R is a scalar in the same
 *        units and |E - E_R| is |E_i - E_R|.
 *    Parameters: "sigmoid" (0 off, 1 on; default 0), "theta_ref" theta_R [K] (default
 *    293.15), "k1" K1 [-], "gamma1" gamma1 [1/K], "k2" K2 [-], "gamma2" gamma2 [1 / units of
 *    E], "field_ref" E_R [units of E] (all default 0). A conductivity <= 0 from eq. 50 (e.g.
 *    K1 <= -1) is SINTER_ERR_DOMAIN.
 *  - V_i = 4/3 pi r_i^3.
 * A particle without current gets no heat (whatever its conductivity); a particle with a
 * current and zero conductivity (the material default) is SINTER_ERR_INVALID: eq. 35 would
 * give infinite power.
 */
#include <math.h>

#include "heat_model.h"
#include "particles/particles.h"

enum {
    PARAM_SOURCE = 7, /* after the eq. 50 parameters, so that their indices stay */
    PARAM_SIGMOID = 0,
    PARAM_THETA_REF = 1,
    PARAM_K1 = 2,
    PARAM_GAMMA1 = 3,
    PARAM_K2 = 4,
    PARAM_GAMMA2 = 5,
    PARAM_FIELD_REF = 6
};

static const double PI = 3.14159265358979323846;

/* 1 / (1 + e^-x); saturates to 0 or 1 without producing NaN. */
static double logistic(double x)
{
    return 1.0 / (1.0 + exp(-x));
}

/*
 * "source" = 0 (automatic, the default) or 2: each particle's share of the power the network
 * electric model dissipates in the contacts, G (phi_a - phi_b)^2 per contact, half to each
 * particle of a pair and all to the particle at an electrode (electric/network.c): the heat
 * put into the particles is the electrical work of the walls, exactly (energy-consistent; the
 * absorptance does not enter: all of the work is heat in the bodies). With "source" = 0 and a
 * model that has no potentials ("averaged", or none), and with "source" = 1: eq. 35 below.
 */
static sinter_status joule_from_network(const sinter_heat_model *hm, sinter_heat_eval *e,
                                        int source)
{
    if (e->joule_dissipation == NULL) {
        if (source == 2)
            return sinter_fail(e->ctx, SINTER_ERR_STATE,
                               "heat model '%s': 'source' = 2 takes the power the network "
                               "electric model dissipates, and the stepper has no network model "
                               "solved over these particles",
                               hm->name);
        return SINTER_ERR_NOT_FOUND; /* automatic: eq. 35 */
    }
    /* (the network puts a pair's power across a periodic face on the owners: electric.h) */
    for (size_t i = 0; i < sinter_heat_owned(e); ++i)
        e->heat[i] += e->joule_dissipation[i];
    return SINTER_OK;
}

static sinter_status joule_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double t = e->time;
    const double source = sinter_heat_param(hm, PARAM_SOURCE, t);
    if (source != 0.0 && source != 1.0 && source != 2.0)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'source' = %g must be 0 (automatic), 1 (eq. 35) or "
                           "2 (the network's dissipation)",
                           hm->name, source);
    if (source != 1.0) {
        const sinter_status st = joule_from_network(hm, e, (int)source);
        if (st != SINTER_ERR_NOT_FOUND)
            return st;
    }
    const double sigmoid = sinter_heat_param(hm, PARAM_SIGMOID, t);
    if (sigmoid != 0.0 && sigmoid != 1.0)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'sigmoid' = %g must be 0 (constant conductivity) or "
                           "1 (seed 000 eq. 50)",
                           hm->name, sigmoid);
    const double theta_ref = sinter_heat_param(hm, PARAM_THETA_REF, t);
    const double k1 = sinter_heat_param(hm, PARAM_K1, t);
    const double gamma1 = sinter_heat_param(hm, PARAM_GAMMA1, t);
    const double k2 = sinter_heat_param(hm, PARAM_K2, t);
    const double gamma2 = sinter_heat_param(hm, PARAM_GAMMA2, t);
    const double field_ref = sinter_heat_param(hm, PARAM_FIELD_REF, t);
    const sinter_particles *ps = e->ps;
    for (size_t i = 0; i < sinter_heat_owned(e); ++i) { /* a source: owned rows only */
        const double current = ps->current[i];
        if (current == 0.0)
            continue;
        /* sigma(theta) from the material's table when it has one (its sigma_0 otherwise) */
        const double sigma0 = sinter_particle_property(ps, i, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY,
                                                       SINTER_MAT_ELECTRIC_CONDUCTIVITY);
        if (!(sigma0 > 0.0))
            return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                               "heat model '%s': particle %zu (id %llu) carries a current of %g "
                               "A but its material %d has electric conductivity %g S/m; eq. 35 "
                               "needs sigma > 0",
                               hm->name, i, (unsigned long long)ps->id[i], current,
                               (int)ps->material[i], sigma0);
        double sigma = sigma0;
        if (sigmoid == 1.0) {
            const double field = fabs(current) / sigma0; /* Ohm's law with sigma_0 */
            sigma = sigma0 * (1.0 + k1 * logistic(gamma1 * (ps->temperature[i] - theta_ref)) +
                              k2 * logistic(gamma2 * fabs(field - field_ref))); /* eq. 50 */
            if (!(sigma > 0.0) || !isfinite(sigma))
                return sinter_fail(e->ctx, SINTER_ERR_DOMAIN,
                                   "heat model '%s': seed 000 eq. 50 gives conductivity %g S/m "
                                   "for particle %zu (id %llu) at %g K (k1 = %g, k2 = %g); it "
                                   "must stay positive",
                                   hm->name, sigma, i, (unsigned long long)ps->id[i],
                                   ps->temperature[i], k1, k2);
        }
        const double r = ps->radius[i];
        const double volume = 4.0 / 3.0 * PI * r * r * r;
        const double a = sinter_particle_param(ps, i, SINTER_MAT_ABSORPTANCE);
        e->heat[i] += a * current * current / sigma * volume; /* eq. 35 */
    }
    return SINTER_OK;
}

const sinter_heat_ops sinter_heat_joule = {
    "joule",
    0,
    {"sigmoid", "theta_ref", "k1", "gamma1", "k2", "gamma2", "field_ref", "source", NULL},
    {0.0, 293.15, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
    joule_eval,
    NULL};
