/*
 * The 7DOF reconstruction's path constants as material parameters (issue 42, docs/7dof.md §3):
 * neck_boundary_path, neck_cone_path, neck_cap_path and lattice_mobile_fraction. Each enters the
 * right-hand side only through a flux's D / Delta s, so halving a path is doubling that
 * mechanism's prefactor: with the other mechanisms that share the path switched off the two
 * runs are the same to the bit (scalings by powers of two are exact), which is what the tests
 * check, through the public two-particle model.
 */
#include <math.h>
#include <string.h>

#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

static const double TIMES[1] = {0.0}, TEMPS[1] = {1293.0};
static const double OUT[2] = {100.0, 1000.0};

/* neck radius and shrinkage of two 25 um spheres of m at 1293 K, at OUT */
static void run(sinter_ctx *ctx, const sinter_material *m, double neck[2], double shrink[2])
{
    sinter_neck_model *nm = NULL;
    OK(sinter_neck_model_create(&nm, ctx));
    OK(sinter_neck_two_particles(nm, m, 25e-6, 25e-6, 1, TIMES, TEMPS, 2, OUT, neck, shrink, NULL));
    sinter_neck_model_destroy(nm);
}

static void test_defaults_and_ranges(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *m = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_material_create(&m, ctx, "copper"));
    const sinter_material_param p[4] = {SINTER_MAT_NECK_BOUNDARY_PATH, SINTER_MAT_NECK_CONE_PATH,
                                        SINTER_MAT_NECK_CAP_PATH,
                                        SINTER_MAT_LATTICE_MOBILE_FRACTION};
    const double expected[4] = {0.25, 0.5, 1.0, 1.0}; /* docs/7dof.md §3: x/4, s/2, s, n_v = 1 */
    for (int k = 0; k < 4; ++k) {
        double v = -1.0;
        OK(sinter_material_get(m, p[k], &v));
        assert_true(v == expected[k]);
    }
    assert_int_equal(sinter_material_set(m, SINTER_MAT_NECK_BOUNDARY_PATH, 0.0),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_NECK_CAP_PATH, 101.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_LATTICE_MOBILE_FRACTION, 1.5),
                     SINTER_ERR_INVALID);
    OK(sinter_material_set(m, SINTER_MAT_LATTICE_MOBILE_FRACTION, 0.0));
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
}

/* Grain boundary only (D_s0 = D_v0 = 0): Delta s = x/8 is D_gb0 twice as large. */
static void test_boundary_path_is_a_prefactor(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *a = NULL, *b = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_material_create(&a, ctx, "gb"));
    OK(sinter_material_set(a, SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR, 0.0));
    OK(sinter_material_set(a, SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 0.0));
    OK(sinter_material_clone(&b, a));
    OK(sinter_material_set(a, SINTER_MAT_NECK_BOUNDARY_PATH, 0.125));
    OK(sinter_material_set(b, SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, 2 * 2.7e11));
    double na[2], sa[2], nb[2], sb[2], n0[2], s0[2];
    run(ctx, a, na, sa);
    run(ctx, b, nb, sb);
    for (int k = 0; k < 2; ++k)
        assert_true(na[k] == nb[k] && sa[k] == sb[k]);
    /* and the path matters: with every mechanism on, the boundary path x/8 shrinks the copper
     * pair more (docs/7dof.md §3: shrinkage roughly as 1 / Delta s_gb) */
    sinter_material *c = NULL, *d = NULL;
    OK(sinter_material_create(&c, ctx, "copper"));
    OK(sinter_material_clone(&d, c));
    OK(sinter_material_set(d, SINTER_MAT_NECK_BOUNDARY_PATH, 0.125));
    run(ctx, c, n0, s0);
    run(ctx, d, na, sa);
    for (int k = 0; k < 2; ++k) {
        print_message("copper, t = %g s: shrinkage %.6e with x/8, %.6e with x/4\n", OUT[k], sa[k],
                      s0[k]);
        assert_true(sa[k] > 1.3 * s0[k]);
    }
    sinter_material_destroy(c);
    sinter_material_destroy(d);
    sinter_material_destroy(a);
    sinter_material_destroy(b);
    sinter_ctx_destroy(ctx);
}

/* Surface only (D_gb0 = D_v0 = 0): cone and cap paths halved are D_s0 twice as large. */
static void test_surface_paths_are_a_prefactor(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *a = NULL, *b = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_material_create(&a, ctx, "surface"));
    OK(sinter_material_set(a, SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, 0.0));
    OK(sinter_material_set(a, SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 0.0));
    OK(sinter_material_clone(&b, a));
    OK(sinter_material_set(a, SINTER_MAT_NECK_CONE_PATH, 0.25));
    OK(sinter_material_set(a, SINTER_MAT_NECK_CAP_PATH, 0.5));
    OK(sinter_material_set(b, SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR, 2 * 7.0e6));
    double na[2], sa[2], nb[2], sb[2];
    run(ctx, a, na, sa);
    run(ctx, b, nb, sb);
    for (int k = 0; k < 2; ++k)
        assert_true(na[k] == nb[k] && sa[k] == sb[k]);
    sinter_material_destroy(a);
    sinter_material_destroy(b);
    sinter_ctx_destroy(ctx);
}

/* n_v = 1/2 is D_v0 halved, with every mechanism on. */
static void test_lattice_fraction_is_a_prefactor(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *a = NULL, *b = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_material_create(&a, ctx, "copper"));
    OK(sinter_material_clone(&b, a));
    OK(sinter_material_set(a, SINTER_MAT_LATTICE_MOBILE_FRACTION, 0.5));
    OK(sinter_material_set(b, SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR, 0.5 * 6.2e-5));
    double na[2], sa[2], nb[2], sb[2];
    run(ctx, a, na, sa);
    run(ctx, b, nb, sb);
    for (int k = 0; k < 2; ++k)
        assert_true(na[k] == nb[k] && sa[k] == sb[k]);
    sinter_material_destroy(a);
    sinter_material_destroy(b);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_and_ranges),
        cmocka_unit_test(test_boundary_path_is_a_prefactor),
        cmocka_unit_test(test_surface_paths_are_a_prefactor),
        cmocka_unit_test(test_lattice_fraction_is_a_prefactor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
