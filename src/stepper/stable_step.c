/*
 * The explicit stepper's stable step (issue 35): an estimate of the critical step from the
 * stiffest contact the particles can meet, the refusal of a fixed step beyond it, and the
 * elastic energy of a contact for the energy check of sanity.c (criterion 4).
 *
 * The estimate. Velocity Verlet on one contact, linearised about an overlap, is the
 * oscillator m* x'' = -k x - c x' with c = 2 xi sqrt(k m*); it is stable for
 *
 *     dt <= dt_crit = (2 / omega) (sqrt(1 + xi^2) - xi),   omega = sqrt(k / m*)
 *
 * (2 / omega undamped: the central-difference limit, Belytschko, Liu & Moran, "Nonlinear
 * Finite Elements for Continua and Structures", 2000, sec. 6.3; the damped factor is the
 * same book's eq. 6.3.34, and it holds for this stepper's scheme, in which the damping reads
 * the half-kicked velocity: checked by iterating the scheme's linear map, xi = 0 .. 2).
 * The critical step of the set is the smallest over every pair of materials the particles
 * hold (and every particle material against every wall's material), for every built-in
 * contact model of the stepper, with:
 *
 *  - the smallest particle of each material (Hertz and the power law: omega^2 = k / m* grows
 *    as 1 / R^2 at a fixed relative overlap), R* = R_a R_b / (R_a + R_b), m* likewise (a wall:
 *    R* = R_a, m* = m_a);
 *  - Hertz (seed 003 eq. 2-6): the tangent stiffness k = d f / d delta = 2 E* sqrt(R* delta)
 *    at the reference overlap delta = SINTER_STABLE_HERTZ_OVERLAP R* (1 %), and the damping
 *    ratio xi of the pair (eq. 6 is exactly xi relative to that stiffness: d = 2 xi sqrt(k m*)).
 *    Hertz's stiffness grows only as delta^(1/2), so dt_crit as delta^(-1/4): a real overlap
 *    16 times smaller than the reference makes dt_crit twice as long, one 16 times larger half
 *    as long. 1 % is beyond the overlaps of stiff grains (steel spheres falling 10 mm reach
 *    0.2 %) and below those of the soft ones of seed 003 (E = 1 MPa at 1 m/s: 16 %).
 *    (LIGGGHTS and EDEM compare the step with the Rayleigh time, T_R = pi R sqrt(rho / G) /
 *    (0.1631 nu + 0.8766), and the Hertz collision time at the largest speed; those are
 *    accuracy criteria, not the stability bound, and would refuse the peer benchmark mech.scene
 *    at 0.23 T_R.)
 *  - the power law of seed 000 (eq. 2, 13): f = K E^p A with A = pi a^2 ~ 2 pi R* delta for a
 *    small overlap, E = delta / L (L = R_a + R_b, or R_a at a wall), so k = 2 pi (p + 1) K R*
 *    E^p at the reference strain SINTER_STABLE_POWER_STRAIN (0.1, the seed's bond strain E*),
 *    undamped (its damping is friction and the drag, which only lengthen dt_crit);
 *  - the linear spring: k = kn, xi = cn / (2 sqrt(kn m*));
 *  - thermal softening only lowers E or K (laws 1 and 2; the bound keeps the unsoftened value;
 *    a tabulated curve counts with its largest factor if above 1; a host callback is assumed
 *    not to stiffen); host force models and the tangential and rolling springs (capped by
 *    Coulomb's limit) are not in the estimate.
 *
 * The refusal: a fixed step above SINTER_STABLE_STEP_FACTOR (2) times dt_crit is refused
 * before the first step with SINTER_ERR_INVALID giving both numbers and the option "dt_check"
 * that allows it. The factor covers the estimate's reference overlap (16 times the real one
 * for stiff grains); a step between dt_crit and twice it is accepted but is unstable for any
 * contact that does reach the reference overlap. A grain in several contacts has a higher
 * frequency than one contact (a chain: up to sqrt(2) times): recommended steps are a fifth
 * to a tenth of dt_crit.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sanity.h"
#include "stepper.h"

static const double PI = 3.14159265358979323846;

/* The smallest particle of each material: radius and mass. */
typedef struct smallest {
    double r[SINTER_MAX_MATERIALS];
    double m[SINTER_MAX_MATERIALS];
    double scale[SINTER_MAX_MATERIALS]; /* largest softening factor (>= 1) */
} smallest;

static void find_smallest(const sinter_particles *ps, smallest *s)
{
    for (int k = 0; k < SINTER_MAX_MATERIALS; ++k) {
        s->r[k] = s->m[k] = INFINITY;
        s->scale[k] = 1.0;
    }
    for (size_t i = 0; i < ps->count; ++i) {
        const int32_t k = ps->material[i];
        s->r[k] = ps->radius[i] < s->r[k] ? ps->radius[i] : s->r[k];
        s->m[k] = ps->mass[i] < s->m[k] ? ps->mass[i] : s->m[k];
    }
    for (int k = 0; k < ps->material_top; ++k) {
        const struct sinter_softening_curve *c = &ps->softening[k];
        if (ps->materials[k].value[SINTER_MAT_SOFTENING_LAW] == 3.0)
            for (size_t p = 0; p < c->count; ++p)
                s->scale[k] = fmax(s->scale[k], c->factor[p]);
    }
}

/* dt_crit of one contact of stiffness k, effective mass m and damping ratio xi. */
static double critical(double k, double m, double xi)
{
    if (!(k > 0.0))
        return INFINITY;
    return 2.0 * sqrt(m / k) * (sqrt(1.0 + xi * xi) - xi);
}

static double hertz_compliance(const sinter_material *a, double scale)
{
    const double nu = a->value[SINTER_MAT_POISSON_RATIO];
    return (1.0 - nu * nu) / (a->value[SINTER_MAT_YOUNGS_MODULUS] * scale);
}

/* One side of a contact: a particle material (its smallest particle) or a wall. */
typedef struct contact_side {
    const sinter_material *mat;
    double r, m, scale; /* r = m = INFINITY for a wall */
} contact_side;

/* R* and m* of two sides (a wall is the second). */
static void reduced(const contact_side *a, const contact_side *b, double *rstar, double *mstar)
{
    *rstar = isinf(b->r) ? a->r : a->r * b->r / (a->r + b->r);
    *mstar = isinf(b->m) ? a->m : a->m * b->m / (a->m + b->m);
}

/* dt_crit of model fm for a contact between sides a and b; *what names the law. */
static double model_critical(const sinter_force_model *fm, const contact_side *a,
                             const contact_side *b, const char **what)
{
    double rstar, mstar;
    reduced(a, b, &rstar, &mstar);
    const int wall = isinf(b->r);
    const double *va = a->mat->value, *vb = b->mat->value;
    if (fm->ops == &sinter_force_hertz_mindlin) {
        *what = "Hertz";
        const double estar =
            1.0 / (hertz_compliance(a->mat, a->scale) + hertz_compliance(b->mat, b->scale));
        const double k = 2.0 * estar * sqrt(rstar * SINTER_STABLE_HERTZ_OVERLAP * rstar);
        const double xi = 0.5 * (va[SINTER_MAT_DAMPING_RATIO] + vb[SINTER_MAT_DAMPING_RATIO]);
        return critical(k, mstar, xi);
    }
    if (fm->ops == &sinter_force_power_law) {
        *what = "power law";
        const sinter_material_param kp =
            wall ? SINTER_MAT_WALL_STIFFNESS : SINTER_MAT_CONTACT_STIFFNESS;
        const sinter_material_param pp =
            wall ? SINTER_MAT_WALL_EXPONENT : SINTER_MAT_CONTACT_EXPONENT;
        const double K = 0.5 * (va[kp] + vb[kp]) * fmax(a->scale, wall ? 1.0 : b->scale);
        const double p = 0.5 * (va[pp] + vb[pp]);
        const double k = 2.0 * PI * (p + 1.0) * K * rstar * pow(SINTER_STABLE_POWER_STRAIN, p);
        return critical(k, mstar, 0.0);
    }
    if (fm->ops == &sinter_force_linear_spring) {
        *what = "linear spring";
        const double k = fm->param[0], c = fm->param[1];
        return critical(k, mstar, k > 0.0 ? c / (2.0 * sqrt(k * mstar)) : 0.0);
    }
    return INFINITY;
}

/* Elastic energy of model fm's contact between sides a and b at the reference overlap (Hertz,
 * linear spring: 1 % of R*) or strain (power law: 0.1), unsoftened; 0 for other models. */
static double model_energy(const sinter_force_model *fm, const contact_side *a,
                           const contact_side *b)
{
    double rstar, mstar;
    reduced(a, b, &rstar, &mstar);
    const int wall = isinf(b->r);
    const double *va = a->mat->value, *vb = b->mat->value;
    const double delta = SINTER_STABLE_HERTZ_OVERLAP * rstar;
    if (fm->ops == &sinter_force_hertz_mindlin) {
        const double estar = 1.0 / (hertz_compliance(a->mat, 1.0) + hertz_compliance(b->mat, 1.0));
        return 8.0 / 15.0 * estar * sqrt(rstar * delta) * delta * delta;
    }
    if (fm->ops == &sinter_force_power_law) {
        const sinter_material_param kp =
            wall ? SINTER_MAT_WALL_STIFFNESS : SINTER_MAT_CONTACT_STIFFNESS;
        const sinter_material_param pp =
            wall ? SINTER_MAT_WALL_EXPONENT : SINTER_MAT_CONTACT_EXPONENT;
        const double length = wall ? a->r : a->r + b->r;
        const double p = 0.5 * (va[pp] + vb[pp]), d = SINTER_STABLE_POWER_STRAIN * length;
        return 2.0 * PI * rstar * 0.5 * (va[kp] + vb[kp]) * d * d *
               pow(SINTER_STABLE_POWER_STRAIN, p) / (p + 2.0);
    }
    if (fm->ops == &sinter_force_linear_spring)
        return 0.5 * fm->param[0] * delta * delta;
    return 0.0;
}

/* The estimate and a description of the contact that sets it (into text, if not NULL); into
 * *energy (if not NULL) the least elastic energy of a contact at the reference overlap. */
static double estimate(const sinter_stepper *st, char *text, size_t size, double *energy)
{
    const sinter_particles *ps = st->ps;
    smallest s;
    find_smallest(ps, &s);
    double best = INFINITY, least = INFINITY;
    if (text != NULL && size > 0)
        text[0] = '\0';
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    for (size_t f = 0; f < st->force_count; ++f) {
        const sinter_force_model *fm = st->forces[f].model;
        if (!fm->ops->uses_contacts)
            continue;
        for (int a = 0; a < ps->material_top; ++a) {
            if (isinf(s.r[a]))
                continue; /* no particle of this material */
            const contact_side sa = {&ps->materials[a], s.r[a], s.m[a], s.scale[a]};
            for (int b = a; b < ps->material_top; ++b) {
                if (isinf(s.r[b]))
                    continue;
                const contact_side sb = {&ps->materials[b], s.r[b], s.m[b], s.scale[b]};
                const char *what = "";
                const double dt = model_critical(fm, &sa, &sb, &what);
                const double u = model_energy(fm, &sa, &sb);
                least = u > 0.0 && u < least ? u : least;
                if (dt < best) {
                    best = dt;
                    if (text != NULL)
                        snprintf(text, size,
                                 "%s contact of materials %d and %d (radii %g and %g m, masses "
                                 "%g and %g kg)",
                                 what, a, b, s.r[a], s.r[b], s.m[a], s.m[b]);
                }
            }
            for (size_t k = 0; k < nw; ++k) {
                const contact_side sw = {&st->walls->wall[k].material, INFINITY, INFINITY, 1.0};
                const char *what = "";
                const double dt = model_critical(fm, &sa, &sw, &what);
                const double u = model_energy(fm, &sa, &sw);
                least = u > 0.0 && u < least ? u : least;
                if (dt < best) {
                    best = dt;
                    if (text != NULL)
                        snprintf(text, size,
                                 "%s contact of material %d (radius %g m, mass %g kg) with wall "
                                 "%zu",
                                 what, a, s.r[a], s.m[a], k);
                }
            }
        }
    }
    if (energy != NULL)
        *energy = isfinite(least) ? least : 0.0;
    return best;
}

sinter_status sinter_stepper_stable_step(sinter_stepper *st, double *dt)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, dt);
    /* material ids written through a view index the table: checked first */
    const sinter_status valid = sinter_particles_validate(st->ps, NULL);
    if (valid != SINTER_OK)
        return valid;
    *dt = estimate(st, NULL, 0, NULL);
    return SINTER_OK;
}

sinter_status sinter_stable_step_check(sinter_stepper *st)
{
    char what[256];
    double least = 0.0;
    const double crit = estimate(st, what, sizeof(what), &least);
    st->energy_floor = SINTER_SANITY_ENERGY_FLOOR * least; /* (sanity.c, criterion 4) */
    if (crit != st->stable_logged && isfinite(crit)) {
        sinter_log(st->ctx, SINTER_LOG_INFO,
                   "explicit stepper: stable step estimate %g s (time step %g s, %.3g of it), "
                   "set by the %s",
                   crit, st->dt, st->dt / crit, what);
        st->stable_logged = crit;
    }
    if (!st->dt_check || !(st->dt > SINTER_STABLE_STEP_FACTOR * crit))
        return SINTER_OK;
    return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                       "the explicit stepper's time step %g s is %.3g times its stable step "
                       "estimate %g s (refused above %g times it; see "
                       "sinter_stepper_stable_step). Take a smaller step, or set the stepper "
                       "option \"dt_check\" to 0 ([stepper] dt_check = 0 in a scene) to run "
                       "it knowingly. The estimate is set by the %s",
                       st->dt, st->dt / crit, crit, SINTER_STABLE_STEP_FACTOR, what);
}

/* Elastic energy stored by the contact models of the stepper in one contact of overlap
 * delta > 0 between particle i and particle j (or wall `wall` when j == SIZE_MAX), with the
 * unsoftened stiffness (an upper bound); bonds of the power law count as stored energy too
 * (they pull the pair together). */
double sinter_contact_energy(const sinter_stepper *st, size_t i, size_t j, size_t wall,
                             double delta)
{
    const sinter_particles *ps = st->ps;
    const sinter_material *a = &ps->materials[ps->material[i]];
    const int is_wall = j == SIZE_MAX;
    const sinter_material *b =
        is_wall ? &st->walls->wall[wall].material : &ps->materials[ps->material[j]];
    const double ri = ps->radius[i], rj = is_wall ? INFINITY : ps->radius[j];
    const double rstar = is_wall ? ri : ri * rj / (ri + rj);
    const double length = is_wall ? ri : ri + rj;
    double u = 0.0;
    for (size_t f = 0; f < st->force_count; ++f) {
        const sinter_force_model *fm = st->forces[f].model;
        if (fm->ops == &sinter_force_hertz_mindlin) {
            /* (8/15) E* sqrt(R*) delta^(5/2), the integral of seed 003 eq. 2 */
            const double estar = 1.0 / (hertz_compliance(a, 1.0) + hertz_compliance(b, 1.0));
            u += 8.0 / 15.0 * estar * sqrt(rstar * delta) * delta * delta;
        } else if (fm->ops == &sinter_force_power_law) {
            /* integral of K (delta / L)^p 2 pi R* delta: 2 pi R* K delta^2 E^p / (p + 2) */
            const double *va = a->value, *vb = b->value;
            const double strain = delta / length;
            const sinter_material_param kp =
                is_wall ? SINTER_MAT_WALL_STIFFNESS : SINTER_MAT_CONTACT_STIFFNESS;
            const sinter_material_param pp =
                is_wall ? SINTER_MAT_WALL_EXPONENT : SINTER_MAT_CONTACT_EXPONENT;
            const double p = 0.5 * (va[pp] + vb[pp]);
            u += 2.0 * PI * rstar * 0.5 * (va[kp] + vb[kp]) * delta * delta * pow(strain, p) /
                 (p + 2.0);
            if (!is_wall) {
                const double pb =
                    0.5 * (va[SINTER_MAT_BOND_EXPONENT] + vb[SINTER_MAT_BOND_EXPONENT]);
                const double kb =
                    0.5 * (va[SINTER_MAT_BOND_STIFFNESS] + vb[SINTER_MAT_BOND_STIFFNESS]);
                u += 2.0 * PI * rstar * kb * delta * delta * pow(strain, pb) / (pb + 2.0);
            }
        } else if (fm->ops == &sinter_force_linear_spring) {
            u += 0.5 * fm->param[0] * delta * delta;
        }
    }
    return u;
}

double sinter_contact_force_bound(const sinter_stepper *st, size_t i, size_t j, size_t wall,
                                  double delta, double speed)
{
    const sinter_particles *ps = st->ps;
    const sinter_material *a = &ps->materials[ps->material[i]];
    const int is_wall = j == SIZE_MAX;
    const sinter_material *b =
        is_wall ? &st->walls->wall[wall].material : &ps->materials[ps->material[j]];
    const double *va = a->value, *vb = b->value;
    const double ri = ps->radius[i], rj = is_wall ? INFINITY : ps->radius[j];
    const double rstar = is_wall ? ri : ri * rj / (ri + rj);
    const double mstar =
        is_wall ? ps->mass[i] : ps->mass[i] * ps->mass[j] / (ps->mass[i] + ps->mass[j]);
    const double length = is_wall ? ri : ri + rj;
    const double mu = fmax(sqrt(va[SINTER_MAT_FRICTION_STATIC] * vb[SINTER_MAT_FRICTION_STATIC]),
                           sqrt(va[SINTER_MAT_FRICTION_DYNAMIC] * vb[SINTER_MAT_FRICTION_DYNAMIC]));
    double f = 0.0;
    for (size_t k = 0; k < st->force_count; ++k) {
        const sinter_force_model *fm = st->forces[k].model;
        if (fm->ops == &sinter_force_hertz_mindlin) {
            /* seed 003 eq. 2 and 6 */
            const double estar = 1.0 / (hertz_compliance(a, 1.0) + hertz_compliance(b, 1.0));
            const double xi = 0.5 * (va[SINTER_MAT_DAMPING_RATIO] + vb[SINTER_MAT_DAMPING_RATIO]);
            const double srd = sqrt(rstar * delta);
            f += (4.0 / 3.0 * estar * srd * delta +
                  2.0 * xi * sqrt(2.0 * estar * mstar * srd) * speed) *
                 (1.0 + mu);
        } else if (fm->ops == &sinter_force_power_law) {
            /* seed 000 eq. 2, 13, 19 with A <= 2 pi R* delta */
            const sinter_material_param kp =
                is_wall ? SINTER_MAT_WALL_STIFFNESS : SINTER_MAT_CONTACT_STIFFNESS;
            const sinter_material_param pp =
                is_wall ? SINTER_MAT_WALL_EXPONENT : SINTER_MAT_CONTACT_EXPONENT;
            const double area = 2.0 * PI * rstar * delta, strain = delta / length;
            double g = 0.5 * (va[kp] + vb[kp]) * pow(strain, 0.5 * (va[pp] + vb[pp])) * area;
            if (!is_wall)
                g += 0.5 * (va[SINTER_MAT_BOND_STIFFNESS] + vb[SINTER_MAT_BOND_STIFFNESS]) *
                     pow(strain,
                         0.5 * (va[SINTER_MAT_BOND_EXPONENT] + vb[SINTER_MAT_BOND_EXPONENT])) *
                     area;
            f += g * (1.0 + mu);
        } else if (fm->ops == &sinter_force_linear_spring) {
            f += fm->param[0] * delta + fm->param[1] * speed;
        }
    }
    return f;
}
