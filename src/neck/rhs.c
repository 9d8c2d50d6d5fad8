/*
 * Right-hand side of the 7DOF neck model: Arrhenius mobilities with the phase switch, chemical
 * potentials, the twelve volume fluxes, the regional volume balances and the chain rule
 * (seed 001 eqs. 2-9 and table 1; docs/7dof.md §2.4 and §3).
 */
#include <math.h>

#include "neck/neck.h"
#include "particles/material.h"

_Static_assert(SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION_HOT - SINTER_MAT_ATOMIC_VOLUME_HOT ==
                   SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION - SINTER_MAT_ATOMIC_VOLUME,
               "the *_HOT material parameters must mirror the base set");

static void read_phase(const sinter_material *m, int hot, sinter_neck_phase *p)
{
    /* The *_HOT parameters follow the base set in the same order (include/sinter.h). */
    const int offset = hot ? SINTER_MAT_ATOMIC_VOLUME_HOT - SINTER_MAT_ATOMIC_VOLUME : 0;
    const double *v = m->value + offset;
    p->atomic_volume = v[SINTER_MAT_ATOMIC_VOLUME];
    p->surface_energy = v[SINTER_MAT_SURFACE_ENERGY];
    p->grain_boundary_energy = v[SINTER_MAT_GRAIN_BOUNDARY_ENERGY];
    p->surface_thickness = v[SINTER_MAT_SURFACE_THICKNESS];
    p->grain_boundary_thickness = v[SINTER_MAT_GRAIN_BOUNDARY_THICKNESS];
    p->lattice_d0 = v[SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR];
    p->lattice_q = v[SINTER_MAT_LATTICE_ACTIVATION_ENERGY];
    p->surface_d0 = v[SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR];
    p->surface_q = v[SINTER_MAT_SURFACE_ACTIVATION_ENERGY];
    p->boundary_d0 = v[SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR];
    p->boundary_q = v[SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY];
    p->surface_fraction = v[SINTER_MAT_SURFACE_MOBILE_FRACTION];
    p->boundary_fraction = v[SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION];
}

void sinter_neck_material_from(const sinter_material *m, sinter_neck_material *out)
{
    read_phase(m, 0, &out->phase[0]);
    read_phase(m, 1, &out->phase[1]);
    out->transition_temperature = m->value[SINTER_MAT_PHASE_TRANSITION_TEMPERATURE];
    out->boundary_path = m->value[SINTER_MAT_NECK_BOUNDARY_PATH];
    out->cone_path = m->value[SINTER_MAT_NECK_CONE_PATH];
    out->cap_path = m->value[SINTER_MAT_NECK_CAP_PATH];
    out->lattice_fraction = m->value[SINTER_MAT_LATTICE_MOBILE_FRACTION];
}

int sinter_neck_phase_at(const sinter_neck_material *m, double temperature)
{
    /* docs/7dof.md §6.1: alpha -> beta at the transition on heating, beta -> alpha on cooling, no
     * hysteresis; 0 means a single-phase material. */
    return m->transition_temperature > 0.0 && temperature >= m->transition_temperature;
}

/* Seed 001 eq. 5: D = D0 exp(-Q / (R T)). */
static double arrhenius(double d0, double q, double temperature)
{
    if (d0 == 0.0)
        return 0.0;
    return d0 * exp(-q / (SINTER_NECK_GAS_CONSTANT * temperature));
}

void sinter_neck_coeffs_eval(const sinter_neck_material *m, int phase, double temperature,
                             sinter_neck_coeffs *c)
{
    const sinter_neck_phase *p = &m->phase[phase ? 1 : 0];
    const double kt = SINTER_NECK_KB * temperature;
    c->temperature = temperature;
    c->phase = phase ? 1 : 0;
    c->atomic_volume = p->atomic_volume;
    c->surface_energy = p->surface_energy;
    c->boundary_energy = p->grain_boundary_energy;
    c->surface_thickness = p->surface_thickness;
    c->boundary_thickness = p->grain_boundary_thickness;
    /* Seed 001 eq. 4 with docs/7dof.md §3: V = C (D n_frac / (k_B T)) (mu_a - mu_b) / ds, n Omega =
     * n_frac for surface and grain boundary, n_v (1 by default) for the lattice. */
    c->mobility_lattice =
        arrhenius(p->lattice_d0, p->lattice_q, temperature) * m->lattice_fraction / kt;
    c->mobility_surface =
        arrhenius(p->surface_d0, p->surface_q, temperature) * p->surface_fraction / kt;
    c->mobility_boundary =
        arrhenius(p->boundary_d0, p->boundary_q, temperature) * p->boundary_fraction / kt;
    /* docs/7dof.md §3's path lengths as factors (exact for the defaults 1/4, 1/2, 1: the same
     * bits as the constants 4, 2, 1 they replace) */
    c->boundary_factor = 1.0 / m->boundary_path;
    c->cap_factor = 1.0 / m->cap_path;
    c->cone_factor = m->cap_path / m->cone_path;
}

#define PI 3.14159265358979323846

sinter_neck_violation sinter_neck_rhs(const double y[SINTER_NECK_DOF], const sinter_neck_coeffs *c,
                                      double ydot[SINTER_NECK_DOF], sinter_neck_domain_error *err,
                                      sinter_neck_rhs_detail *detail)
{
    sinter_neck_rhs_detail local;
    sinter_neck_rhs_detail *w = detail != NULL ? detail : &local;
    sinter_neck_geometry *g = &w->geometry;
    if (sinter_neck_geometry_eval(y, g) != 0)
        return sinter_neck_check_domain(y, NULL, err); /* never VALID when eval failed */
    const sinter_neck_violation bad = sinter_neck_check_domain(y, g, err);
    if (bad != SINTER_NECK_VALID)
        return bad;
    sinter_neck_rhs_at(y, g, c, ydot, w);
    return SINTER_NECK_VALID;
}

void sinter_neck_rhs_at(const double y[SINTER_NECK_DOF], const sinter_neck_geometry *g,
                        const sinter_neck_coeffs *c, double ydot[SINTER_NECK_DOF],
                        sinter_neck_rhs_detail *detail)
{
    sinter_neck_rhs_detail local;
    sinter_neck_rhs_detail *w = detail != NULL ? detail : &local;
    if (detail != NULL && &detail->geometry != g)
        detail->geometry = *g;

    /* Seed 001 eq. 9 with docs/7dof.md §2.4: mu_i = Omega (gamma_s dA_s/dy_i + gamma_gb dA_gb/dy_i)
     * / (dV/dy_i), the "specific volume" V_i of eq. 2 being the total volume's change. */
    double *mu = w->potential, inv_dv[SINTER_NECK_DOF]; /* divisions once (eq. 2 and 9) */
    for (int i = 0; i < SINTER_NECK_DOF; ++i) {
        inv_dv[i] = 1.0 / g->dvolume[i];
        mu[i] = c->atomic_volume *
                (c->surface_energy * g->dsurface[i] + c->boundary_energy * g->dboundary[i]) *
                inv_dv[i];
    }

    /* Seed 001 table 1 cross-sections C and docs/7dof.md §3 path lengths ds (the defaults of the
     * material's neck_*_path options), per side P with
     * regions ring = 1, cap = 2 + 3P, cone = 3 + 3P, GB = 4 + 3P (1-based as in the seed):
     *   I   GB -> ring,    C = pi x delta_gb,       ds = x/4, D_gb n_gb
     *   II  GB -> ring,    C = (2/3) pi x^2,        ds = x/4, D_v
     *   III cone -> ring,  C = pi (x + h) delta_s,  ds = s/2, D_s n_s
     *   IV  cone -> ring,  C = pi (x + h) l, l = s, ds = s/2, D_v
     *   V   cap -> cone,   C = 2 pi h delta_s,      ds = s,   D_s n_s
     *   VI  cap -> cone,   C = 2 pi h l, l = s,     ds = s,   D_v
     * each V = C (D n_frac / (k_B T)) (mu_from - mu_to) / ds (seed 001 eq. 4). */
    const double x = y[SINTER_NECK_X];
    const double ring_mu = mu[SINTER_NECK_X];
    double *rate = w->region_rate;
    rate[SINTER_NECK_X] = 0.0;
    const double per_gb_path = c->boundary_factor / x; /* 1 / ds, ds = x/4 by default */
    for (int p = 0; p < 2; ++p) {
        const double h = g->side[p].junction_radius, s = g->side[p].slant;
        const double cap_mu = mu[1 + 3 * p], cone_mu = mu[2 + 3 * p], gb_mu = mu[3 + 3 * p];
        /* ds = s and s/2 by default */
        const double per_cap_path = c->cap_factor / s,
                     per_cone_path = c->cone_factor * per_cap_path;
        double *f = w->flux[p];
        f[SINTER_NECK_FLUX_I] =
            PI * x * c->boundary_thickness * c->mobility_boundary * (gb_mu - ring_mu) * per_gb_path;
        f[SINTER_NECK_FLUX_II] =
            2.0 / 3.0 * PI * x * x * c->mobility_lattice * (gb_mu - ring_mu) * per_gb_path;
        f[SINTER_NECK_FLUX_III] = PI * (x + h) * c->surface_thickness * c->mobility_surface *
                                  (cone_mu - ring_mu) * per_cone_path;
        f[SINTER_NECK_FLUX_IV] =
            PI * (x + h) * s * c->mobility_lattice * (cone_mu - ring_mu) * per_cone_path;
        f[SINTER_NECK_FLUX_V] = 2.0 * PI * h * c->surface_thickness * c->mobility_surface *
                                (cap_mu - cone_mu) * per_cap_path;
        f[SINTER_NECK_FLUX_VI] =
            2.0 * PI * h * s * c->mobility_lattice * (cap_mu - cone_mu) * per_cap_path;

        /* Seed 001 eq. 3 (with docs/7dof.md §1's correction of eq. 3c):
         * dV1/dt += I + II + III + IV;  dV_cap/dt = -(V + VI);
         * dV_cone/dt = V + VI - (III + IV);  dV_gb/dt = -(I + II). */
        rate[SINTER_NECK_X] += f[SINTER_NECK_FLUX_I] + f[SINTER_NECK_FLUX_II] +
                               f[SINTER_NECK_FLUX_III] + f[SINTER_NECK_FLUX_IV];
        rate[1 + 3 * p] = -(f[SINTER_NECK_FLUX_V] + f[SINTER_NECK_FLUX_VI]);
        rate[2 + 3 * p] = f[SINTER_NECK_FLUX_V] + f[SINTER_NECK_FLUX_VI] -
                          (f[SINTER_NECK_FLUX_III] + f[SINTER_NECK_FLUX_IV]);
        rate[3 + 3 * p] = -(f[SINTER_NECK_FLUX_I] + f[SINTER_NECK_FLUX_II]);
    }

    /* Seed 001 eq. 2: dy_i/dt = (dV_i/dy_i)^-1 dV_i/dt. */
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        ydot[i] = rate[i] * inv_dv[i];
}
