/*
 * Coarse-grained fields and lamina profiles (sinter_coarse_grain, sinter_lamina_profile; issue
 * 37). Each check fails when its quantity is wrong:
 *  - on a simple cubic lattice of touching spheres the solid fraction at interior grid points
 *    is the lattice's pi / 6 and the temperature the particles' one;
 *  - for a cloud of spheres, the density summed over a grid finer than the kernel (times the
 *    cell volume) is the particles' mass and the momentum their momentum;
 *  - a sphere squeezed between two walls: the stress integrated over space is -F L along the
 *    axis (F the wall force, L the distance between the contact points) and 0 across it;
 *  - the laminae (seed 001 eq. 48) hold the spheres' whole volume and a single sphere's slice
 *    is the closed form;
 *  - bad arguments are refused.
 *
 * Tolerance of a grid sum. The sum over grid points of spacing h of the kernel (a Gaussian of
 * width w cut at C w, normalised over its ball) differs from its integral, 1, by (i) the
 * aliasing of the smooth Gaussian, 6 exp(-2 pi^2 w^2 / h^2) to first order (Poisson
 * summation), and (ii) the cut: at most the points of a shell of thickness h at the cut,
 * 4 pi (C w)^2 h / h^3, times h^3 W(C w), i.e. (h / w) 4 pi C^2 exp(-C^2 / 2) / ((2 pi)^(3/2)
 * N_C), N_C the normalisation's fraction of the Gaussian. The tests use C = 5 and h <= w.
 */
#include <math.h>
#include <stdlib.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;

/* The bound above for cutoff c and h / w = ratio. */
static double grid_sum_bound(double c, double ratio)
{
    const double norm = erf(c / sqrt(2.0)) - sqrt(2.0 / PI) * c * exp(-0.5 * c * c);
    return 6.0 * exp(-2.0 * PI * PI / (ratio * ratio)) +
           ratio * 4.0 * PI * c * c * exp(-0.5 * c * c) / (pow(2.0 * PI, 1.5) * norm);
}

static sinter_particles *lattice(sinter_ctx *ctx, sinter_material *m, int n, double r)
{
    sinter_particles *ps = NULL;
    OK(sinter_particles_create(&ps, ctx));
    OK(sinter_particles_set_material(ps, 0, m));
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double p[3] = {2 * r * i, 2 * r * j, 2 * r * k};
                OK(sinter_particles_add(ps, 1, p, &r, 0, 500.0, NULL));
            }
    return ps;
}

static void test_lattice_solid_fraction(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e9, 0.3, 8900, 0.0, 0.0);
    const double r = 1e-3, a = 2 * r;
    sinter_particles *ps = lattice(s.ctx, s.mat, 14, r);
    sinter_coarse_options o;
    OK(sinter_coarse_options_init(&o, sizeof(o)));
    o.width = a;
    o.cutoff = 5.0;
    /* grid points in the lattice's middle, at least 5 w from its outer spheres: 13 a - 10 a */
    for (int d = 0; d < 3; ++d) {
        o.origin[d] = 5.2 * a;
        o.spacing[d] = 0.37 * a;
        o.points[d] = 8;
    }
    const size_t n = 8 * 8 * 8;
    double *phi = malloc(n * sizeof(double)), *temp = malloc(n * sizeof(double));
    OK(sinter_coarse_grain(ps, NULL, &o, SINTER_COARSE_SOLID_FRACTION, phi, n));
    OK(sinter_coarse_grain(ps, NULL, &o, SINTER_COARSE_TEMPERATURE, temp, n));
    /* the lattice sum of a^3 W at spacing a = w */
    const double tol = grid_sum_bound(o.cutoff, 1.0);
    for (size_t p = 0; p < n; ++p) {
        assert_true(fabs(phi[p] / (PI / 6.0) - 1.0) < tol);
        assert_true(fabs(temp[p] - 500.0) < 1e-12 * 500.0);
    }
    free(phi);
    free(temp);
    sinter_particles_destroy(ps);
    scene_close(&s);
}

static void test_mass_and_momentum(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e9, 0.3, 8900, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    srand(7);
    const double r0 = 1e-3;
    for (int i = 0; i < 40; ++i) {
        const double p[3] = {4e-3 * rand() / RAND_MAX, 4e-3 * rand() / RAND_MAX,
                             4e-3 * rand() / RAND_MAX};
        const double r = r0 * (0.5 + (double)rand() / RAND_MAX);
        OK(sinter_particles_add(s.ps, 1, p, &r, 0, 300.0 + i, NULL));
    }
    double *v = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    for (int i = 0; i < 120; ++i)
        v[i] = sin(1.0 + i);
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    const double *m = NULL, *vv = NULL;
    double mass = 0, mom[3] = {0, 0, 0}, size[3] = {0, 0, 0};
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_MASS, (const void **)&m, NULL, NULL));
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_VELOCITY, (const void **)&vv, NULL, NULL));
    for (int i = 0; i < 40; ++i) {
        mass += m[i];
        for (int d = 0; d < 3; ++d) {
            mom[d] += m[i] * vv[3 * i + d];
            size[d] += m[i] * fabs(vv[3 * i + d]);
        }
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_MASS));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    sinter_coarse_options o;
    OK(sinter_coarse_options_init(&o, sizeof(o)));
    o.width = 0.8e-3;
    o.cutoff = 5.0;
    const double h = 0.8e-3; /* h = w */
    /* every sphere's kernel (reach 4 mm) inside the grid: from -4.5 mm to 8.5 mm */
    for (int d = 0; d < 3; ++d) {
        o.origin[d] = -4.5e-3;
        o.spacing[d] = h;
        o.points[d] = 17;
    }
    const size_t n = 17 * 17 * 17;
    double *rho = malloc(n * sizeof(double)), *vel = malloc(3 * n * sizeof(double));
    OK(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, rho, n));
    OK(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_VELOCITY, vel, 3 * n));
    double sum = 0, p[3] = {0, 0, 0};
    for (size_t k = 0; k < n; ++k) {
        sum += rho[k] * h * h * h;
        for (int d = 0; d < 3; ++d)
            p[d] += rho[k] * vel[3 * k + (size_t)d] * h * h * h;
    }
    const double tol = grid_sum_bound(o.cutoff, 1.0);
    assert_true(fabs(sum / mass - 1.0) < tol);
    /* each particle's momentum is conserved the same way: |error| <= tol sum m |v| */
    for (int d = 0; d < 3; ++d)
        assert_true(fabs(p[d] - mom[d]) < tol * size[d]);
    free(rho);
    free(vel);
    scene_close(&s);
}

static void test_squeezed_sphere_stress(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e8, 0.3, 2500, 0.0, 0.0);
    scene_open(&s, "hertz_mindlin", 0);
    const double r = 1e-3, delta = 2e-5;
    scene_add(&s, 0, 0, r - delta, r);
    scene_floor(&s, 0.0);
    const double top[3] = {0, 0, 2 * r - 2 * delta}, down[3] = {0, 0, -1};
    OK(sinter_walls_add_plane(s.walls, top, down, s.wall_mat, NULL));
    OK(sinter_stepper_set_dt(s.st, 1e-7));
    OK(sinter_stepper_step(s.st, 0));
    double f0[3], f1[3];
    OK(sinter_walls_get_force(s.walls, 0, f0));
    OK(sinter_walls_get_force(s.walls, 1, f1));
    assert_true(fabs(f0[2]) > 0);
    assert_true(fabs(f0[2] + f1[2]) < 1e-9 * fabs(f0[2])); /* symmetric: balanced */
    sinter_snapshot *snap = NULL;
    OK(sinter_snapshot_create(&snap, s.st));
    sinter_coarse_options o;
    OK(sinter_coarse_options_init(&o, sizeof(o)));
    o.width = 0.5 * r;
    o.cutoff = 5.0;
    const double h = 0.25 * r;
    for (int d = 0; d < 3; ++d) {
        o.origin[d] = -4 * r;
        o.spacing[d] = h;
        o.points[d] = 33;
    }
    const size_t n = 33 * 33 * 33;
    double *sigma = malloc(9 * n * sizeof(double));
    OK(sinter_coarse_grain(s.ps, snap, &o, SINTER_COARSE_STRESS, sigma, 9 * n));
    double integral[9] = {0};
    for (size_t k = 0; k < n; ++k)
        for (int c = 0; c < 9; ++c)
            integral[c] += sigma[9 * k + (size_t)c] * h * h * h;
    /* compressive: -F L with L = 2 r - 2 delta between the wall contacts */
    const double expected = -fabs(f0[2]) * (2 * r - 2 * delta);
    const double tol = grid_sum_bound(o.cutoff, 0.5);
    assert_true(fabs(integral[8] / expected - 1.0) < tol);
    for (int c = 0; c < 8; ++c)
        assert_true(fabs(integral[c]) < tol * fabs(expected));
    /* without the snapshot: no contact stress, and a particle at rest has no kinetic one */
    OK(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_STRESS, sigma, 9 * n));
    for (size_t k = 0; k < 9 * n; ++k)
        assert_true(sigma[k] == 0.0);
    free(sigma);
    sinter_snapshot_destroy(snap);
    scene_close(&s);
}

static void test_laminae(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e9, 0.3, 8900, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    srand(3);
    double volume = 0;
    for (int i = 0; i < 30; ++i) {
        const double r = 1e-3 * (0.5 + (double)rand() / RAND_MAX);
        const double p[3] = {r + (6e-3 - 2 * r) * rand() / RAND_MAX,
                             r + (6e-3 - 2 * r) * rand() / RAND_MAX,
                             r + (6e-3 - 2 * r) * rand() / RAND_MAX};
        OK(sinter_particles_add(s.ps, 1, p, &r, 0, i < 15 ? 300.0 : 600.0, NULL));
        volume += 4.0 / 3.0 * PI * r * r * r;
    }
    const double lo[3] = {0, 0, 0}, hi[3] = {6e-3, 6e-3, 6e-3};
    double fraction[24], temperature[24];
    for (int axis = 0; axis < 3; ++axis) {
        OK(sinter_lamina_profile(s.ps, axis, lo, hi, 24, fraction, temperature));
        double sum = 0;
        for (int k = 0; k < 24; ++k) {
            sum += fraction[k] * 36e-6 * 0.25e-3;
            assert_true(isnan(temperature[k]) ||
                        (temperature[k] >= 300.0 - 1e-9 && temperature[k] <= 600.0 + 1e-9));
        }
        assert_true(fabs(sum / volume - 1.0) < 1e-12);
    }
    scene_close(&s);
    /* one sphere: the lamina from its centre to r above holds half of it, the cap beyond
     * r / 2 is pi h^2 (3 r - h) / 3 with h = r / 2 */
    scene_init(&s);
    scene_material(&s, 1e9, 0.3, 8900, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    scene_add(&s, 0, 0, 0, 1.0);
    const double l2[3] = {-1, -1, 0}, h2[3] = {1, 1, 1};
    OK(sinter_lamina_profile(s.ps, 2, l2, h2, 2, fraction, NULL));
    const double cap = PI * 0.25 * (3.0 - 0.5) / 3.0, half = 2.0 * PI / 3.0;
    assert_true(fabs(fraction[1] * 4 * 0.5 - cap) < 1e-14);
    assert_true(fabs(fraction[0] * 4 * 0.5 - (half - cap)) < 1e-14);
    scene_close(&s);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e9, 0.3, 8900, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    sinter_coarse_options o;
    assert_int_equal(sinter_coarse_options_init(NULL, sizeof(o)), SINTER_ERR_NULL);
    assert_int_equal(sinter_coarse_options_init(&o, 3), SINTER_ERR_STRUCT_SIZE);
    OK(sinter_coarse_options_init(&o, sizeof(o)));
    double out[9];
    assert_int_equal(sinter_coarse_grain(NULL, NULL, &o, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, NULL, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, NULL, 1),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_COUNT_, out, 1),
                     SINTER_ERR_RANGE);
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_STRESS, out, 1),
                     SINTER_ERR_INVALID);
    OK(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_STRESS, out, 9));
    o.width = 0;
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_INVALID);
    o.width = 1e-3;
    o.cutoff = 0.5;
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_INVALID);
    o.cutoff = 3;
    o.points[1] = 0;
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_INVALID);
    o.points[1] = 1;
    o.spacing[2] = NAN;
    assert_int_equal(sinter_coarse_grain(s.ps, NULL, &o, SINTER_COARSE_DENSITY, out, 1),
                     SINTER_ERR_INVALID);
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    assert_int_equal(sinter_lamina_profile(s.ps, 3, lo, hi, 2, out, NULL), SINTER_ERR_INVALID);
    assert_int_equal(sinter_lamina_profile(s.ps, 0, lo, hi, 0, out, NULL), SINTER_ERR_INVALID);
    assert_int_equal(sinter_lamina_profile(s.ps, 0, hi, lo, 2, out, NULL), SINTER_ERR_INVALID);
    assert_int_equal(sinter_lamina_profile(s.ps, 0, NULL, hi, 2, out, NULL), SINTER_ERR_NULL);
    const char *name = NULL;
    size_t comp = 0;
    OK(sinter_coarse_quantity_info(SINTER_COARSE_STRESS, &name, NULL, &comp));
    assert_string_equal(name, "stress");
    assert_int_equal(comp, 9);
    assert_int_equal(sinter_coarse_quantity_info(SINTER_COARSE_COUNT_, NULL, NULL, NULL),
                     SINTER_ERR_RANGE);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lattice_solid_fraction), cmocka_unit_test(test_mass_and_momentum),
        cmocka_unit_test(test_squeezed_sphere_stress), cmocka_unit_test(test_laminae),
        cmocka_unit_test(test_bad_arguments)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
