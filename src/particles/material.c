/* Materials: named parameter sets with units, defaults and valid ranges. */
#include <math.h>
#include <string.h>

#include "material.h"

enum { RANGE_CLOSED = 0, RANGE_OPEN_MIN = 1, RANGE_INTEGER = 2 };

typedef struct param_spec {
    const char *key;
    const char *unit;
    const char *meaning;
    double default_value;
    double min_value;
    double max_value;
    int range;
} param_spec;

/* Indexed by sinter_material_param; order must follow the enum in sinter.h. */
static const param_spec PARAMS[SINTER_MAT_PARAM_COUNT_] = {
    {"density", "kg/m^3", "mass density", 2500.0, 0.0, 1e6, RANGE_OPEN_MIN},
    {"youngs_modulus", "Pa", "elasticity modulus at the reference temperature", 1e7, 0.0, 1e13,
     RANGE_OPEN_MIN},
    {"poisson_ratio", "1", "Poisson coefficient", 0.3, -0.999, 0.4999, RANGE_CLOSED},
    {"damping_ratio", "1", "normal contact damping rate xi_con (seed 003 eq. 6)", 0.0, 0.0, 10.0,
     RANGE_CLOSED},
    {"friction_static", "1", "static friction coefficient mu_s (seed 003 eq. 8)", 0.3, 0.0, 100.0,
     RANGE_CLOSED},
    {"friction_dynamic", "1", "dynamic friction coefficient mu_d (seed 003 eq. 8, seed 000 eq. 5)",
     0.3, 0.0, 100.0, RANGE_CLOSED},
    {"friction_damping_ratio", "1", "tangential damping rate xi_fric (seed 003 eq. 11)", 0.0, 0.0,
     10.0, RANGE_CLOSED},
    {"rolling_friction", "1", "rolling resistance coefficient mu_r (seed 003 eq. 16)", 0.0, 0.0,
     100.0, RANGE_CLOSED},
    {"rolling_damping_ratio", "1", "rolling damping rate xi_rol (seed 003 eq. 18)", 0.0, 0.0, 10.0,
     RANGE_CLOSED},
    {"contact_stiffness", "Pa", "particle contact constant K_p (seed 000 eq. 2)", 1e7, 0.0, 1e15,
     RANGE_CLOSED},
    {"contact_exponent", "1", "particle contact exponent p_p (seed 000 eq. 2)", 1.0, 0.0, 20.0,
     RANGE_OPEN_MIN},
    {"wall_stiffness", "Pa", "wall contact constant K_w (seed 000 eq. 13)", 1e7, 0.0, 1e15,
     RANGE_CLOSED},
    {"wall_exponent", "1", "wall contact exponent p_w (seed 000 eq. 13)", 1.0, 0.0, 20.0,
     RANGE_OPEN_MIN},
    {"bond_stiffness", "Pa", "adhesive bond constant K_b (seed 000 eq. 19)", 0.0, 0.0, 1e15,
     RANGE_CLOSED},
    {"bond_exponent", "1", "adhesive bond exponent p_b (seed 000 eq. 19)", 1.0, 0.0, 20.0,
     RANGE_OPEN_MIN},
    {"bond_critical_strain", "1",
     "normalised interpenetration |E*| that activates a bond (seed 000 eq. 19)", 0.1, 0.0, 1.0,
     RANGE_OPEN_MIN},
    {"drag_coefficient", "kg/s", "interstitial drag c_env (seed 000 eq. 20)", 0.0, 0.0, 1e12,
     RANGE_CLOSED},
    {"thermal_conductivity", "W/(m K)", "thermal conductivity k (seed 003 eq. 35)", 1.0, 0.0, 1e5,
     RANGE_CLOSED},
    {"heat_capacity", "J/(kg K)", "specific heat C (seed 003 eq. 24)", 1000.0, 0.0, 1e7,
     RANGE_OPEN_MIN},
    {"emissivity", "1", "surface emissivity (seed 003 eq. 41)", 0.0, 0.0, 1.0, RANGE_CLOSED},
    {"absorptance", "1", "absorptance a of external heat (seed 003 eq. 29, seed 000 eq. 35)", 1.0,
     0.0, 1.0, RANGE_CLOSED},
    {"softening_law", "1",
     "thermal softening: 0 none, 1 linear with floor (seed 000), 2 exponential (seed 003 eq. 42), "
     "3 tabulated curve, 4 host callback",
     0.0, 0.0, 4.0, RANGE_INTEGER},
    {"softening_temperature", "K", "temperature theta* where softening starts", 400.0, 0.0, 1e5,
     RANGE_OPEN_MIN},
    {"softening_rate", "1/K or 1",
     "linear law: relative stiffness loss per kelvin; exponential law: rate c in exp(c(1 - "
     "theta/theta*))",
     1.0, 0.0, 1e6, RANGE_CLOSED},
    {"softening_floor", "1", "lowest stiffness as a fraction of the reference value", 0.0, 0.0, 1.0,
     RANGE_CLOSED},
    {"electric_conductivity", "S/m", "electrical conductivity sigma (seed 000 eq. 35)", 0.0, 0.0,
     1e12, RANGE_CLOSED},
    {"atomic_volume", "m^3", "atomic volume Omega (seed 001 table 2/4)", 1.18e-29, 0.0, 1e-26,
     RANGE_OPEN_MIN},
    {"surface_energy", "J/m^2", "surface free energy gamma_s (seed 001 eq. 8, table 2/4)", 1.78,
     0.0, 100.0, RANGE_CLOSED},
    {"grain_boundary_energy", "J/m^2",
     "grain-boundary free energy gamma_gb (seed 001 eq. 8, table 2/4)", 0.55, 0.0, 100.0,
     RANGE_CLOSED},
    {"surface_thickness", "m", "surface diffusion layer thickness delta_s (seed 001 table 1, 2/4)",
     0.23e-9, 0.0, 1e-6, RANGE_CLOSED},
    {"grain_boundary_thickness", "m", "grain-boundary thickness delta_gb (seed 001 table 1, 2/4)",
     0.69e-9, 0.0, 1e-6, RANGE_CLOSED},
    {"lattice_diffusion_prefactor", "m^2/s",
     "lattice diffusion prefactor D_v0 (seed 001 eq. 5, table 2/4)", 6.2e-5, 0.0, 1e30,
     RANGE_CLOSED},
    {"lattice_activation_energy", "J/mol",
     "lattice diffusion activation energy Q_v (seed 001 eq. 5, table 2/4)", 207e3, 0.0, 1e7,
     RANGE_CLOSED},
    {"surface_diffusion_prefactor", "m^2/s",
     "surface diffusion prefactor D_s0 (seed 001 eq. 5, table 2/4)", 7.0e6, 0.0, 1e30,
     RANGE_CLOSED},
    {"surface_activation_energy", "J/mol",
     "surface diffusion activation energy Q_s (seed 001 eq. 5, table 2/4)", 370e3, 0.0, 1e7,
     RANGE_CLOSED},
    {"grain_boundary_diffusion_prefactor", "m^2/s",
     "grain-boundary diffusion prefactor D_gb0 (seed 001 eq. 5, table 2/4)", 2.7e11, 0.0, 1e30,
     RANGE_CLOSED},
    {"grain_boundary_activation_energy", "J/mol",
     "grain-boundary diffusion activation energy Q_gb (seed 001 eq. 5, table 2/4)", 500e3, 0.0, 1e7,
     RANGE_CLOSED},
    {"surface_mobile_fraction", "1",
     "concentration of mobile surface atoms n_s (seed 001 eq. 4, table 2/4)", 0.2, 0.0, 1.0,
     RANGE_CLOSED},
    {"grain_boundary_mobile_fraction", "1",
     "concentration of mobile grain-boundary atoms n_gb (seed 001 eq. 4, table 2/4)", 0.1, 0.0, 1.0,
     RANGE_CLOSED},
    {"atomic_volume_hot", "m^3", "atomic volume Omega of the hot phase (seed 001 table 4)",
     1.18e-29, 0.0, 1e-26, RANGE_OPEN_MIN},
    {"surface_energy_hot", "J/m^2",
     "surface free energy gamma_s of the hot phase (seed 001 eq. 8, table 4)", 1.78, 0.0, 100.0,
     RANGE_CLOSED},
    {"grain_boundary_energy_hot", "J/m^2",
     "grain-boundary free energy gamma_gb of the hot phase (seed 001 eq. 8, table 4)", 0.55, 0.0,
     100.0, RANGE_CLOSED},
    {"surface_thickness_hot", "m",
     "surface diffusion layer thickness delta_s of the hot phase (seed 001 table 1, 2/4)", 0.23e-9,
     0.0, 1e-6, RANGE_CLOSED},
    {"grain_boundary_thickness_hot", "m",
     "grain-boundary thickness delta_gb of the hot phase (seed 001 table 1, 2/4)", 0.69e-9, 0.0,
     1e-6, RANGE_CLOSED},
    {"lattice_diffusion_prefactor_hot", "m^2/s",
     "lattice diffusion prefactor D_v0 of the hot phase (seed 001 eq. 5, table 4)", 6.2e-5, 0.0,
     1e30, RANGE_CLOSED},
    {"lattice_activation_energy_hot", "J/mol",
     "lattice diffusion activation energy Q_v of the hot phase (seed 001 eq. 5, table 4)", 207e3,
     0.0, 1e7, RANGE_CLOSED},
    {"surface_diffusion_prefactor_hot", "m^2/s",
     "surface diffusion prefactor D_s0 of the hot phase (seed 001 eq. 5, table 4)", 7.0e6, 0.0,
     1e30, RANGE_CLOSED},
    {"surface_activation_energy_hot", "J/mol",
     "surface diffusion activation energy Q_s of the hot phase (seed 001 eq. 5, table 4)", 370e3,
     0.0, 1e7, RANGE_CLOSED},
    {"grain_boundary_diffusion_prefactor_hot", "m^2/s",
     "grain-boundary diffusion prefactor D_gb0 of the hot phase (seed 001 eq. 5, table 4)", 2.7e11,
     0.0, 1e30, RANGE_CLOSED},
    {"grain_boundary_activation_energy_hot", "J/mol",
     "grain-boundary diffusion activation energy Q_gb of the hot phase (seed 001 eq. 5, table 4)",
     500e3, 0.0, 1e7, RANGE_CLOSED},
    {"surface_mobile_fraction_hot", "1",
     "concentration of mobile surface atoms n_s of the hot phase (seed 001 eq. 4, table 4)", 0.2,
     0.0, 1.0, RANGE_CLOSED},
    {"grain_boundary_mobile_fraction_hot", "1",
     "concentration of mobile grain-boundary atoms n_gb of the hot phase (seed 001 eq. 4, table 4)",
     0.1, 0.0, 1.0, RANGE_CLOSED},
    {"phase_transition_temperature", "K",
     "neck model uses the _hot set at T >= this, 0 = single phase (seed 001 sec. 4.2: Ti 1156 K)",
     0.0, 0.0, 1e5, RANGE_CLOSED},
    {"melting_temperature", "K",
     "melting point theta_m, 0 = none; without latent heat and with melting_stop = 1 a step "
     "taking a particle above it is refused",
     0.0, 0.0, 1e5, RANGE_CLOSED},
    {"latent_heat", "J/kg",
     "latent heat of melting L, absorbed over [theta_m, theta_m + melting_range] (apparent heat "
     "capacity), 0 = none",
     0.0, 0.0, 1e8, RANGE_CLOSED},
    {"melting_range", "K", "width of the melting interval that absorbs latent_heat", 1.0, 0.0, 1e4,
     RANGE_OPEN_MIN},
    {"melting_stop", "1",
     "1: refuse a step taking a particle above melting_temperature when latent_heat = 0; 0: heat "
     "on",
     1.0, 0.0, 1.0, RANGE_INTEGER},
    {"neck_boundary_path", "1",
     "grain-boundary diffusion path of the 7DOF neck as a fraction of the neck radius "
     "(docs/7dof.md sec. 3: x/4)",
     0.25, 0.0, 100.0, RANGE_OPEN_MIN},
    {"neck_cone_path", "1",
     "cone-to-neck diffusion path of the 7DOF neck as a fraction of the cone slant "
     "(docs/7dof.md sec. 3: s/2)",
     0.5, 0.0, 100.0, RANGE_OPEN_MIN},
    {"neck_cap_path", "1",
     "cap-to-cone diffusion path of the 7DOF neck as a fraction of the cone slant "
     "(docs/7dof.md sec. 3: s)",
     1.0, 0.0, 100.0, RANGE_OPEN_MIN},
    {"lattice_mobile_fraction", "1",
     "concentration of mobile atoms of lattice diffusion n_v (seed 001 eq. 4; both phases)",
     1.0, 0.0, 1.0, RANGE_CLOSED},
};

void sinter_material_defaults(double values[SINTER_MAT_PARAM_COUNT_])
{
    for (int p = 0; p < SINTER_MAT_PARAM_COUNT_; ++p)
        values[p] = PARAMS[p].default_value;
}

static int param_valid(int param)
{
    return param >= 0 && param < SINTER_MAT_PARAM_COUNT_;
}

int sinter_material_value_valid(sinter_material_param param, double value)
{
    const param_spec *s = &PARAMS[param];
    if (!isfinite(value) || value < s->min_value || value > s->max_value)
        return 0;
    if (s->range == RANGE_OPEN_MIN && value == s->min_value)
        return 0;
    if (s->range == RANGE_INTEGER && value != floor(value))
        return 0;
    return 1;
}

static void copy_name(char dst[SINTER_MATERIAL_NAME_SIZE], const char *name)
{
    dst[0] = '\0';
    if (name != NULL) {
        strncpy(dst, name, SINTER_MATERIAL_NAME_SIZE - 1);
        dst[SINTER_MATERIAL_NAME_SIZE - 1] = '\0';
    }
}

sinter_status sinter_material_create(sinter_material **out, sinter_ctx *ctx, const char *name)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    if (name != NULL && strlen(name) >= SINTER_MATERIAL_NAME_SIZE)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_material_create: name '%.40s...' is longer than %d characters",
                           name, SINTER_MATERIAL_NAME_SIZE - 1);
    sinter_material *m = sinter_alloc(ctx, sizeof(*m));
    if (m == NULL)
        return SINTER_ERR_NOMEM;
    m->ctx = ctx;
    copy_name(m->name, name);
    sinter_material_defaults(m->value);
    *out = m;
    return SINTER_OK;
}

void sinter_material_destroy(sinter_material *m)
{
    if (m != NULL)
        sinter_free(m->ctx, m);
}

sinter_status sinter_material_clone(sinter_material **out, const sinter_material *m)
{
    if (m == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(m->ctx, out);
    sinter_material *copy = sinter_alloc(m->ctx, sizeof(*copy));
    if (copy == NULL)
        return SINTER_ERR_NOMEM;
    *copy = *m;
    *out = copy;
    return SINTER_OK;
}

sinter_status sinter_material_set(sinter_material *m, sinter_material_param param, double value)
{
    if (m == NULL)
        return SINTER_ERR_NULL;
    if (!param_valid((int)param))
        return sinter_fail(m->ctx, SINTER_ERR_RANGE,
                           "sinter_material_set: parameter %d is not a material parameter "
                           "(0..%d)",
                           (int)param, SINTER_MAT_PARAM_COUNT_ - 1);
    if (!sinter_material_value_valid(param, value)) {
        const param_spec *s = &PARAMS[param];
        return sinter_fail(m->ctx, SINTER_ERR_INVALID,
                           "material '%s': %s = %g %s is invalid; it must be %s in %s%g, %g]",
                           m->name, s->key, value, s->unit,
                           s->range == RANGE_INTEGER ? "a whole number" : "finite and",
                           s->range == RANGE_OPEN_MIN ? "(" : "[", s->min_value, s->max_value);
    }
    m->value[param] = value;
    return SINTER_OK;
}

sinter_status sinter_material_get(const sinter_material *m, sinter_material_param param,
                                  double *value)
{
    if (m == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(m->ctx, value);
    if (!param_valid((int)param))
        return sinter_fail(m->ctx, SINTER_ERR_RANGE,
                           "sinter_material_get: parameter %d is not a material parameter "
                           "(0..%d)",
                           (int)param, SINTER_MAT_PARAM_COUNT_ - 1);
    *value = m->value[param];
    return SINTER_OK;
}

const char *sinter_material_name(const sinter_material *m)
{
    return m == NULL ? "" : m->name;
}

sinter_status sinter_material_param_info(sinter_material_param param, const char **key,
                                         const char **unit, const char **meaning,
                                         double *default_value, double *min_value,
                                         double *max_value)
{
    if (!param_valid((int)param))
        return SINTER_ERR_RANGE;
    const param_spec *s = &PARAMS[param];
    if (key)
        *key = s->key;
    if (unit)
        *unit = s->unit;
    if (meaning)
        *meaning = s->meaning;
    if (default_value)
        *default_value = s->default_value;
    if (min_value)
        *min_value = s->min_value;
    if (max_value)
        *max_value = s->max_value;
    return SINTER_OK;
}

sinter_status sinter_material_param_find(const char *key, sinter_material_param *param)
{
    if (key == NULL || param == NULL)
        return SINTER_ERR_NULL;
    for (int p = 0; p < SINTER_MAT_PARAM_COUNT_; ++p) {
        if (strcmp(PARAMS[p].key, key) == 0) {
            *param = (sinter_material_param)p;
            return SINTER_OK;
        }
    }
    return SINTER_ERR_NOT_FOUND;
}
