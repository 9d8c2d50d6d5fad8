/*
 * Forward sensitivities of the two-particle model (sinter_neck_sensitivities,
 * docs/calibration.md §3):
 *  - against central finite differences of sinter_neck_two_particles, for the titanium E14B
 *    schedule of seed 001's Table 3 (both phases, four pieces) and for copper at 1293 K;
 *  - exact relations: at a constant temperature D depends on D0 exp(-Q / (R T)) only, so
 *    dy/dQ = -dy/d ln D0 / (R T); the data of a phase the schedule never reaches have zero
 *    sensitivity; the values themselves are those of sinter_neck_two_particles;
 *  - the path constants of docs/7dof.md §3 (ln of each) against differences, and the exact
 *    identities that make a path and its mechanism's D0 inseparable (issue 42);
 *  - argument errors.
 */
#include <string.h>

#include "test_support.h"

#define GAS 8.314462618

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_neck_model *nm;
    sinter_material *m;
} fixture;

static void setup(fixture *f, int titanium)
{
    assert_int_equal(sinter_ctx_create(&f->ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_neck_model_create(&f->nm, f->ctx), SINTER_OK);
    assert_int_equal(sinter_neck_model_set(f->nm, "rtol", 1e-10), SINTER_OK);
    assert_int_equal(sinter_material_create(&f->m, f->ctx, "m"), SINTER_OK);
    if (!titanium)
        return; /* the library's defaults are seed 001's copper (docs/7dof.md §6.1) */
    /* Seed 001 table 4 (docs/7dof.md §6.1): alpha as the base set, beta as the _HOT set. */
    static const struct {
        sinter_material_param key;
        double value;
    } TI[] = {
        {SINTER_MAT_ATOMIC_VOLUME, 1.76e-29},
        {SINTER_MAT_SURFACE_ENERGY, 2.05},
        {SINTER_MAT_GRAIN_BOUNDARY_ENERGY, 0.3},
        {SINTER_MAT_SURFACE_THICKNESS, 0.26e-9},
        {SINTER_MAT_GRAIN_BOUNDARY_THICKNESS, 0.78e-9},
        {SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 17e-9},
        {SINTER_MAT_LATTICE_ACTIVATION_ENERGY, 192.8e3},
        {SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR, 213.14},
        {SINTER_MAT_SURFACE_ACTIVATION_ENERGY, 161.2e3},
        {SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, 2.12e-10},
        {SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY, 20.5e3},
        {SINTER_MAT_ATOMIC_VOLUME_HOT, 1.81e-29},
        {SINTER_MAT_SURFACE_ENERGY_HOT, 2.05},
        {SINTER_MAT_GRAIN_BOUNDARY_ENERGY_HOT, 0.184},
        {SINTER_MAT_SURFACE_THICKNESS_HOT, 0.26e-9},
        {SINTER_MAT_GRAIN_BOUNDARY_THICKNESS_HOT, 0.78e-9},
        {SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT, 19e-8},
        {SINTER_MAT_LATTICE_ACTIVATION_ENERGY_HOT, 152.8e3},
        {SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT, 3.9e-2},
        {SINTER_MAT_SURFACE_ACTIVATION_ENERGY_HOT, 205.2e3},
        {SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT, 50.98},
        {SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY_HOT, 221.0e3},
        {SINTER_MAT_PHASE_TRANSITION_TEMPERATURE, 1156.0},
    };
    for (size_t k = 0; k < sizeof(TI) / sizeof(TI[0]); ++k)
        assert_int_equal(sinter_material_set(f->m, TI[k].key, TI[k].value), SINTER_OK);
}

static void teardown(fixture *f)
{
    sinter_material_destroy(f->m);
    sinter_neck_model_destroy(f->nm);
    sinter_ctx_destroy(f->ctx);
}

#define N_OUT 3

static double value_of(const sinter_material *m, sinter_material_param key)
{
    double value = NAN;
    assert_int_equal(sinter_material_get(m, key, &value), SINTER_OK);
    return value;
}

/* Neck ratio and shrinkage of sinter_neck_two_particles with parameter `key` set to `value`. */
static void run_plain(fixture *f, double radius, size_t n, const double *times, const double *temps,
                      const double *out, sinter_material_param key, double value, double *ratio,
                      double *shrinkage)
{
    sinter_material *m = NULL;
    assert_int_equal(sinter_material_clone(&m, f->m), SINTER_OK);
    assert_int_equal(sinter_material_set(m, key, value), SINTER_OK);
    double x[N_OUT];
    assert_int_equal(sinter_neck_two_particles(f->nm, m, radius, radius, n, times, temps, N_OUT,
                                               out, x, shrinkage, NULL),
                     SINTER_OK);
    for (int k = 0; k < N_OUT; ++k)
        ratio[k] = x[k] / radius;
    sinter_material_destroy(m);
}

/*
 * Each sensitivity against a central difference of 1e-2 in ln D0, or of 1e-2 R (1000 K) in Q
 * (ln D moves by about 1e-2 either way). The difference's truncation error is of order
 * h^2 = 1e-4 of the derivative; the runs' own error at rtol 1e-12, divided by 2h, stays below
 * 1e-6 of it even for the smallest effect here (the alpha boundary data, whose outputs move by
 * 2e-7 in x/R). Agreement to 5e-4 of the largest derivative over the outputs, plus 1e-12.
 */
static void check_against_differences(fixture *f, double radius, size_t n, const double *times,
                                      const double *temps, const double *out,
                                      const sinter_material_param *params, size_t n_params)
{
    double ratio[N_OUT], shrink[N_OUT], d_ratio[N_OUT * 16], d_shrink[N_OUT * 16];
    assert_int_equal(sinter_neck_sensitivities(f->ctx, f->nm, f->m, radius, radius, n, times, temps,
                                               n_params, params, N_OUT, out, ratio, shrink, d_ratio,
                                               d_shrink),
                     SINTER_OK);
    /* the values are the model's (the sensitivities share its error control: 1e-7 relative) */
    double r0[N_OUT], s0[N_OUT];
    run_plain(f, radius, n, times, temps, out, params[0], value_of(f->m, params[0]), r0, s0);
    for (int k = 0; k < N_OUT; ++k) {
        assert_close(ratio[k], r0[k], 1e-7 * fabs(r0[k]));
        assert_close(shrink[k], s0[k], 1e-7 * fabs(s0[k]) + 1e-14);
    }
    const double h = 1e-2;
    /* the differences of much smaller effects need tighter runs than the sensitivities */
    assert_int_equal(sinter_neck_model_set(f->nm, "rtol", 1e-12), SINTER_OK);
    for (size_t j = 0; j < n_params; ++j) {
        const double value = value_of(f->m, params[j]);
        const int prefactor = params[j] == SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR ||
                              params[j] == SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR ||
                              params[j] == SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR ||
                              params[j] == SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT ||
                              params[j] == SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT ||
                              params[j] == SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT ||
                              params[j] == SINTER_MAT_NECK_BOUNDARY_PATH ||
                              params[j] == SINTER_MAT_NECK_CONE_PATH ||
                              params[j] == SINTER_MAT_NECK_CAP_PATH ||
                              params[j] == SINTER_MAT_LATTICE_MOBILE_FRACTION; /* ln of it */
        /* Q moves by h R (1000 K): ln D changes by about h, as for a prefactor (a relative
         * step in Q would change ln D by h Q / (R T), 0.5 for copper's boundary, far too much) */
        const double dq = h * GAS * 1000.0;
        const double up = prefactor ? value * exp(h) : value + dq;
        const double down = prefactor ? value * exp(-h) : value - dq;
        const double span = prefactor ? 2.0 * h : 2.0 * dq;
        double ru[N_OUT], su[N_OUT], rd[N_OUT], sd[N_OUT];
        run_plain(f, radius, n, times, temps, out, params[j], up, ru, su);
        run_plain(f, radius, n, times, temps, out, params[j], down, rd, sd);
        double largest_r = 0.0, largest_s = 0.0;
        for (int k = 0; k < N_OUT; ++k) {
            largest_r = fmax(largest_r, fabs(d_ratio[k * n_params + j]));
            largest_s = fmax(largest_s, fabs(d_shrink[k * n_params + j]));
        }
        assert_true(largest_r > 0.0 && largest_s > 0.0); /* each parameter acts */
        for (int k = 0; k < N_OUT; ++k) {
            assert_close(d_ratio[k * n_params + j], (ru[k] - rd[k]) / span,
                         5e-4 * largest_r + 1e-12);
            assert_close(d_shrink[k * n_params + j], (su[k] - sd[k]) / span,
                         5e-4 * largest_s + 1e-12);
        }
    }
}

static void test_titanium_schedule_against_differences(void **state)
{
    (void)state;
    fixture f;
    setup(&f, 1);
    /* E14B (seed 001 table 3): 793 K, 20 K/min to 1373 K, 90 min hold, back to 793 K; 66.6 um */
    const double times[] = {0.0, 1740.0, 7140.0, 8880.0}, temps[] = {793.0, 1373.0, 1373.0, 793.0};
    const double out[N_OUT] = {1000.0, 4000.0, 8880.0};
    const sinter_material_param params[] = {
        SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT,
        SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY_HOT,
        SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT,
        SINTER_MAT_SURFACE_ACTIVATION_ENERGY_HOT,
        SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, /* alpha: acts while heating and cooling */
        SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT,
    };
    check_against_differences(&f, 33.3e-6, 4, times, temps, out, params,
                              sizeof(params) / sizeof(params[0]));
    teardown(&f);
}

static void test_copper_isothermal_against_differences(void **state)
{
    (void)state;
    fixture f;
    setup(&f, 0);
    const double times[] = {0.0}, temps[] = {1293.0}; /* docs/7dof.md §6.2 */
    const double out[N_OUT] = {10.0, 300.0, 5000.0};
    const sinter_material_param params[] = {
        SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR,
        SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR,
        SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR,
        SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY,
    };
    check_against_differences(&f, 25e-6, 1, times, temps, out, params,
                              sizeof(params) / sizeof(params[0]));
    teardown(&f);
}

/* At constant T: dy/dQ = -(1 / (R T)) dy/d ln D0 for each mechanism, since D depends on
 * D0 exp(-Q / (R T)) only; the two integrate proportional equations under one error control
 * (1e-6 relative). The _HOT data of a single-phase material never act: exactly zero. */
static void test_exact_relations(void **state)
{
    (void)state;
    fixture f;
    setup(&f, 0);
    const double T = 1293.0, times[] = {0.0}, temps[] = {T};
    const double out[N_OUT] = {1.0, 100.0, 5000.0};
    const sinter_material_param params[] = {
        SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR,
        SINTER_MAT_SURFACE_ACTIVATION_ENERGY,
        SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT,
    };
    double ratio[N_OUT], shrink[N_OUT], d_ratio[N_OUT * 3], d_shrink[N_OUT * 3];
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 3,
                                               params, N_OUT, out, ratio, shrink, d_ratio,
                                               d_shrink),
                     SINTER_OK);
    for (int k = 0; k < N_OUT; ++k) {
        assert_close(d_ratio[3 * k + 1], -d_ratio[3 * k] / (GAS * T),
                     1e-6 * fabs(d_ratio[3 * k]) / (GAS * T));
        assert_close(d_shrink[3 * k + 1], -d_shrink[3 * k] / (GAS * T),
                     1e-6 * fabs(d_shrink[3 * k]) / (GAS * T) + 1e-20);
        assert_true(d_ratio[3 * k + 2] == 0.0 && d_shrink[3 * k + 2] == 0.0);
        assert_true(d_ratio[3 * k] > 0.0); /* faster surface diffusion, larger neck */
    }
    teardown(&f);
}

/* The path constants and n_v (derivatives with respect to ln of each) against differences:
 * titanium E14B, where they act in both phases, and copper at 1293 K with every mechanism on.
 * n_v is at most 1 (a fraction): at 0.5 here, so that the difference can step up. */
static void test_paths_against_differences(void **state)
{
    (void)state;
    const sinter_material_param params[] = {
        SINTER_MAT_NECK_BOUNDARY_PATH,
        SINTER_MAT_NECK_CONE_PATH,
        SINTER_MAT_NECK_CAP_PATH,
        SINTER_MAT_LATTICE_MOBILE_FRACTION,
    };
    const size_t n_params = sizeof(params) / sizeof(params[0]);
    fixture f;
    setup(&f, 1);
    assert_int_equal(sinter_material_set(f.m, SINTER_MAT_LATTICE_MOBILE_FRACTION, 0.5), SINTER_OK);
    const double times[] = {0.0, 1740.0, 7140.0, 8880.0}, temps[] = {793.0, 1373.0, 1373.0, 793.0};
    const double out[N_OUT] = {1000.0, 4000.0, 8880.0};
    check_against_differences(&f, 33.3e-6, 4, times, temps, out, params, n_params);
    teardown(&f);
    setup(&f, 0);
    assert_int_equal(sinter_material_set(f.m, SINTER_MAT_LATTICE_MOBILE_FRACTION, 0.5), SINTER_OK);
    const double t_cu[] = {0.0}, temp_cu[] = {1293.0};
    const double out_cu[N_OUT] = {10.0, 300.0, 5000.0};
    check_against_differences(&f, 25e-6, 1, t_cu, temp_cu, out_cu, params, n_params);
    teardown(&f);
}

/* Why a path and its mechanism's D0 cannot both be fitted (docs/calibration.md §2): with the
 * lattice off the boundary path scales flux I exactly as 1 / D_gb0 does, and the cone and cap
 * paths together scale III and V as 1 / D_s0; n_v scales the lattice mobility as D_v0 does. The
 * sensitivity equations are then proportional, integrated under one error control: 1e-6. */
static void test_path_identities(void **state)
{
    (void)state;
    fixture f;
    setup(&f, 0);
    const double times[] = {0.0}, temps[] = {1293.0};
    const double out[N_OUT] = {1.0, 100.0, 5000.0};
    const sinter_material_param params[] = {
        SINTER_MAT_NECK_BOUNDARY_PATH,
        SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR,
        SINTER_MAT_NECK_CONE_PATH,
        SINTER_MAT_NECK_CAP_PATH,
        SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR,
    };
    enum { P = 5 };
    double ratio[N_OUT], shrink[N_OUT], d_ratio[N_OUT * P], d_shrink[N_OUT * P];
    assert_int_equal(sinter_material_set(f.m, SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 0.0),
                     SINTER_OK);
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, P,
                                               params, N_OUT, out, ratio, shrink, d_ratio,
                                               d_shrink),
                     SINTER_OK);
    for (int k = 0; k < N_OUT; ++k) {
        const double *r = d_ratio + P * k, *s = d_shrink + P * k;
        assert_true(s[1] > 0.0); /* faster boundary diffusion, more shrinkage */
        assert_close(r[0], -r[1], 1e-6 * fabs(r[1]) + 1e-15);
        assert_close(s[0], -s[1], 1e-6 * fabs(s[1]) + 1e-15);
        assert_close(r[2] + r[3], -r[4], 1e-6 * fabs(r[4]) + 1e-15);
        assert_close(s[2] + s[3], -s[4], 1e-6 * fabs(s[4]) + 1e-15);
        assert_true(r[2] != 0.0 && r[3] != 0.0); /* the two paths differ, each acts */
    }
    /* lattice on again: n_v and ln D_v0 are one parameter */
    assert_int_equal(sinter_material_set(f.m, SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 6.2e-5),
                     SINTER_OK);
    const sinter_material_param lattice[] = {SINTER_MAT_LATTICE_MOBILE_FRACTION,
                                             SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR};
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 2,
                                               lattice, N_OUT, out, ratio, shrink, d_ratio,
                                               d_shrink),
                     SINTER_OK);
    for (int k = 0; k < N_OUT; ++k) {
        assert_true(d_shrink[2 * k] != 0.0);
        assert_close(d_ratio[2 * k], d_ratio[2 * k + 1], 1e-6 * fabs(d_ratio[2 * k + 1]));
        assert_close(d_shrink[2 * k], d_shrink[2 * k + 1], 1e-6 * fabs(d_shrink[2 * k + 1]));
    }
    teardown(&f);
}

static void test_arguments(void **state)
{
    (void)state;
    fixture f;
    setup(&f, 0);
    const double times[] = {0.0}, temps[] = {1293.0}, out[] = {10.0};
    double r, s, dr[2], ds[2];
    sinter_material_param params[] = {SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR,
                                      SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR};
    /* a repeated parameter, one that is not Arrhenius data, none, too many */
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 2,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f.ctx), "twice"));
    params[1] = SINTER_MAT_DENSITY;
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 2,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 0,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    /* bad radius, output before the start, NULLs, the RK4 integrator */
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, -1.0, 25e-6, 1, times, temps, 1,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    const double early[] = {-1.0};
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 1,
                                               params, 1, early, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_neck_sensitivities(NULL, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 1,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 1,
                                               params, 1, out, &r, &s, NULL, ds),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_neck_model_set(f.nm, "integrator", 1.0), SINTER_OK);
    assert_int_equal(sinter_neck_sensitivities(f.ctx, f.nm, f.m, 25e-6, 25e-6, 1, times, temps, 1,
                                               params, 1, out, &r, &s, dr, ds),
                     SINTER_ERR_INVALID);
    teardown(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_titanium_schedule_against_differences),
        cmocka_unit_test(test_copper_isothermal_against_differences),
        cmocka_unit_test(test_exact_relations),
        cmocka_unit_test(test_paths_against_differences),
        cmocka_unit_test(test_path_identities),
        cmocka_unit_test(test_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
