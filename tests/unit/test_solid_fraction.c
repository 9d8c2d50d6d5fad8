/*
 * The solid fraction without overlaps counted twice (io/solid_fraction.c, issue 37): the lens of
 * two equal spheres against its own closed form, V = pi (4 r + d) (2 r - d)^2 / 12, and of a ball
 * inside another; a sphere cut by a face of the box against its cap; a cluster of overlapping
 * spheres in a box against a Monte Carlo estimate of the union's volume (200 000 points: the
 * tolerance is four standard errors of the estimate).
 */
#include "test_support.h"

#include "contact/neighbors.h"
#include "io/solid_fraction.h"
#include "particles/particles.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

static const double PI = 3.14159265358979323846;

static void test_lens_and_cap(void **state)
{
    (void)state;
    const double r = 1.0;
    for (double d = 0.1; d < 2.0; d += 0.3) {
        const double equal = PI * (4.0 * r + d) * (2.0 * r - d) * (2.0 * r - d) / 12.0;
        assert_true(fabs(sinter_lens_volume(r, r, d) - equal) <= 1e-12 * equal);
    }
    assert_true(sinter_lens_volume(1.0, 1.0, 2.0) == 0.0);
    assert_true(fabs(sinter_lens_volume(1.0, 0.3, 0.5) - 4.0 / 3.0 * PI * 0.027) < 1e-15);

    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_particles_create(&ps, ctx));
    sinter_material *m = NULL;
    OK(sinter_material_create(&m, ctx, NULL));
    OK(sinter_particles_set_material(ps, 0, m));
    const double x[3] = {0.0, 0.0, 0.7}, radius = 1.0;
    OK(sinter_particles_add(ps, 1, x, &radius, 0, 300.0, NULL));
    /* the box's top face 0.3 below the sphere's top: a cap of height 0.3 is outside */
    const double lo[3] = {-5, -5, -5}, hi[3] = {5, 5, 1.4};
    const double c = 0.3, cap = PI * c * c * (3.0 - c) / 3.0;
    const double inside = sinter_solid_volume_in_box(ps, NULL, lo, hi);
    assert_true(fabs(inside - (4.0 / 3.0 * PI - cap)) < 1e-12);
    sinter_particles_destroy(ps);
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
}

static double uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static void test_cluster_against_monte_carlo(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_particles_create(&ps, ctx));
    sinter_material *m = NULL;
    OK(sinter_material_create(&m, ctx, NULL));
    OK(sinter_particles_set_material(ps, 0, m));
    /* a chain and a branch of overlapping spheres, no point in three of them; the first
     * sphere crosses the box's floor */
    const double x[5][3] = {
        {0, 0, 0.15}, {1.8, 0, 0.9}, {3.5, 0.2, 0.9}, {1.9, 1.7, 1.0}, {5.1, 0.4, 1.2}};
    const double r[5] = {1.0, 1.0, 0.9, 0.9, 0.8};
    for (int k = 0; k < 5; ++k)
        OK(sinter_particles_add(ps, 1, x[k], &r[k], 0, 300.0, NULL));
    sinter_neighbors nb;
    sinter_neighbors_init(&nb, ctx, 0.1);
    OK(sinter_neighbors_build(&nb, ps, NULL));
    const double lo[3] = {-1.2, -1.2, 0.0}, hi[3] = {6.2, 3.0, 3.0};
    const double solid = sinter_solid_volume_in_box(ps, &nb.pp, lo, hi);
    uint64_t seed = 12345;
    const long n = 200000;
    long hits = 0;
    for (long k = 0; k < n; ++k) {
        double p[3];
        for (int d = 0; d < 3; ++d)
            p[d] = lo[d] + (hi[d] - lo[d]) * uniform(&seed);
        for (int s = 0; s < 5; ++s) {
            const double dx = p[0] - x[s][0], dy = p[1] - x[s][1], dz = p[2] - x[s][2];
            if (dx * dx + dy * dy + dz * dz < r[s] * r[s]) {
                ++hits;
                break;
            }
        }
    }
    const double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    const double f = (double)hits / (double)n, error = sqrt(f * (1.0 - f) / (double)n);
    const double summed = 4.0 / 3.0 * PI * (1.0 + 1.0 + 0.729 + 0.729 + 0.512) / box;
    print_message("solid fraction %.5f, Monte Carlo %.5f +- %.5f, summed volumes %.5f\n",
                  solid / box, f, error, summed);
    assert_true(fabs(solid / box - f) <= 4.0 * error);
    assert_true(summed - solid / box > 10.0 * error); /* the overlaps and the cap matter here */
    sinter_neighbors_free(&nb);
    sinter_particles_destroy(ps);
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
}

/*
 * The sampled solid fraction of a box that spheres cross and lie outside of
 * (sinter_solid_fraction_sampled, issue 38: the packing density inside a powder layer): the
 * cluster above in a box that cuts four of its five spheres and leaves one outside, against a
 * Monte Carlo estimate of the union's volume in that box (200 000 points). The grid's own error
 * at cells of a quarter of the smallest radius is a fraction of a percent of the solid here (the
 * errors of the cells across a sphere's surface cancel in the main); the tolerance is four
 * standard errors of the estimate plus 1 % of the fraction. A coarser grid (max_points) still
 * lands within 5 %, and a box no sphere reaches reads 0.
 */
static void test_sampled_fraction_in_a_sub_box(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_particles_create(&ps, ctx));
    sinter_material *m = NULL;
    OK(sinter_material_create(&m, ctx, NULL));
    OK(sinter_particles_set_material(ps, 0, m));
    const double x[5][3] = {
        {0, 0, 0.15}, {1.8, 0, 0.9}, {3.5, 0.2, 0.9}, {1.9, 1.7, 1.0}, {5.1, 0.4, 1.2}};
    const double r[5] = {1.0, 1.0, 0.9, 0.9, 0.8};
    for (int k = 0; k < 5; ++k)
        OK(sinter_particles_add(ps, 1, x[k], &r[k], 0, 300.0, NULL));
    const double lo[3] = {0.5, -0.5, 0.3}, hi[3] = {3.8, 1.5, 1.6};
    const double sampled = sinter_solid_fraction_sampled(ctx, ps, lo, hi, 2e7);
    uint64_t seed = 4321;
    const long n = 200000;
    long hits = 0;
    for (long k = 0; k < n; ++k) {
        double p[3];
        for (int d = 0; d < 3; ++d)
            p[d] = lo[d] + (hi[d] - lo[d]) * uniform(&seed);
        for (int s = 0; s < 5; ++s) {
            const double dx = p[0] - x[s][0], dy = p[1] - x[s][1], dz = p[2] - x[s][2];
            if (dx * dx + dy * dy + dz * dz < r[s] * r[s]) {
                ++hits;
                break;
            }
        }
    }
    const double f = (double)hits / (double)n, error = sqrt(f * (1.0 - f) / (double)n);
    const double coarse = sinter_solid_fraction_sampled(ctx, ps, lo, hi, 200);
    print_message("sampled %.5f, coarse %.5f, Monte Carlo %.5f +- %.5f\n", sampled, coarse, f,
                  error);
    assert_true(fabs(sampled - f) <= 4.0 * error + 0.01 * f);
    assert_true(fabs(coarse - f) <= 4.0 * error + 0.05 * f);
    const double far_lo[3] = {10, 10, 10}, far_hi[3] = {11, 11, 11};
    assert_true(sinter_solid_fraction_sampled(ctx, ps, far_lo, far_hi, 2e7) == 0.0);
    sinter_particles_destroy(ps);
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lens_and_cap),
        cmocka_unit_test(test_cluster_against_monte_carlo),
        cmocka_unit_test(test_sampled_fraction_in_a_sub_box),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
