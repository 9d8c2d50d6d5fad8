/*
 * Mixtures of materials by mass fraction (issue 38), in random packing and in continuous
 * insertion, with one size distribution for all materials or one of each's own.
 *
 * The rule (src/particles/mixture.c) gives each new particle the material furthest below its
 * mass share. Its bound is deterministic: after every particle, each material's mass M_k lies
 * within one particle's mass m_max of its share f_k M (for two materials on both sides; for
 * more, never more than m_max above). An independent draw by number would scatter as a
 * binomial, |M_k / M - f_k| of order sqrt(f_k (1 - f_k) / N) (times the spread of the particle
 * masses); the bound m_max / M is tighter by a factor of order sqrt(N) (with N ~ 1000 particles:
 * some 30 times), and is what these tests assert, so the fractions converge to the requested
 * ones as 1 / M. Where a statistic is random (a material's own size distribution sampled),
 * the tolerance is binomial: the fraction of a material's radii below its median is binomial
 * (n, 1/2), within 4 standard deviations 2 / sqrt(n) of 1/2 (a false failure about once in
 * 16 000 runs, and the seed is fixed).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene_support.h"

#define PI 3.14159265358979323846
#define RHO_A 8960.0 /* copper */
#define RHO_B 3950.0 /* alumina */

static const int32_t IDS[2] = {0, 1};
static const double SHARES[2] = {0.6, 0.4};

/* A closed box [-half, half]^2 x [0, 2 half] of two materials: 0 copper-like, 1 alumina-like. */
static void open_box(scene *s, int gravity, double half)
{
    scene_init(s);
    scene_material(s, 1e6, 0.3, RHO_A, 0.5, 0.3); /* soft: dt 1e-6 s is stable */
    scene_open(s, "hertz_mindlin", gravity);
    sinter_material *b = NULL;
    OK(sinter_material_clone(&b, s->mat));
    OK(sinter_material_set(b, SINTER_MAT_DENSITY, RHO_B));
    OK(sinter_particles_set_material(s->ps, 1, b));
    sinter_material_destroy(b);
    for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
            double p[3] = {0, 0, half}, n[3] = {0, 0, 0};
            p[d] += side ? half : -half;
            n[d] = side ? -1.0 : 1.0;
            OK(sinter_walls_add_plane(s->walls, p, n, s->wall_mat, NULL));
        }
    OK(sinter_stepper_set_dt(s->st, 1e-6));
}

/* Own sizes: material 0 log-normal (median radius 20 um, gsd 1.3, cut at 3 gsd), material 1
 * uniform 60 +- 10 um. */
static void own_sizes(sinter_packing_options sizes[2])
{
    for (int k = 0; k < 2; ++k)
        OK(sinter_packing_options_init(&sizes[k], sizeof(sizes[k])));
    sizes[0].distribution = SINTER_RADII_LOGNORMAL;
    sizes[0].radius_median = 20e-6;
    sizes[0].radius_gsd = 1.3;
    sizes[1].distribution = SINTER_RADII_UNIFORM;
    sizes[1].radius_mean = 60e-6;
    sizes[1].radius_spread = 10e-6;
}

/* A mixture powder in the box [-half, half]^2 x [lo_z, hi_z]; shared sizes: log-normal, median
 * radius 30 um, gsd 1.4; `sizes` non-NULL: each material's own. */
static sinter_packing_options powder(double half, double lo_z, double hi_z,
                                     const sinter_packing_options *sizes)
{
    sinter_packing_options p;
    OK(sinter_packing_options_init(&p, sizeof(p)));
    p.distribution = SINTER_RADII_LOGNORMAL;
    p.radius_median = 30e-6;
    p.radius_gsd = 1.4;
    p.seed = 38;
    p.max_attempts = 500;
    for (int d = 0; d < 2; ++d) {
        p.box_min[d] = -half;
        p.box_max[d] = half;
    }
    p.box_min[2] = lo_z;
    p.box_max[2] = hi_z;
    p.mixture_count = 2;
    p.mixture_materials = IDS;
    p.mixture_mass_fractions = SHARES;
    p.mixture_sizes = sizes;
    return p;
}

/* Mass of each material over particles [first, count), and the largest particle's mass. */
static void masses(scene *s, size_t first, double m[2], double *largest)
{
    size_t count = 0;
    OK(sinter_particles_count(s->ps, &count));
    m[0] = m[1] = 0.0;
    *largest = 0.0;
    for (size_t i = first; i < count; ++i) {
        const double mi = get1(s, SINTER_FIELD_MASS, i);
        const int32_t *mat = NULL;
        OK(sinter_particles_view_read(s->ps, SINTER_FIELD_MATERIAL, (const void **)&mat, NULL,
                                      NULL));
        const int32_t k = mat[i];
        OK(sinter_particles_release(s->ps, SINTER_FIELD_MATERIAL));
        assert_true(k == 0 || k == 1);
        m[k] += mi;
        *largest = fmax(*largest, mi);
    }
}

static int32_t material_of(scene *s, size_t i)
{
    const int32_t *mat = NULL;
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_MATERIAL, (const void **)&mat, NULL, NULL));
    const int32_t k = mat[i];
    OK(sinter_particles_release(s->ps, SINTER_FIELD_MATERIAL));
    return k;
}

/*
 * Packing with sizes per material: 1500 spheres; each material's mass within one particle's
 * mass of its share; each material's radii from its own distribution (the uniform one within
 * its bounds, the log-normal one within its cut and half below its median within the binomial
 * tolerance); the same seed, the same packing bit for bit; the layout before mixture_sizes
 * still served.
 */
static void test_packing_own_sizes(void **state)
{
    (void)state;
    sinter_packing_options sizes[2];
    own_sizes(sizes);
    double first_x[2] = {0, 0};
    for (int run = 0; run < 2; ++run) {
        scene s;
        open_box(&s, 0, 0.6e-3);
        sinter_packing_options p = powder(0.6e-3, 0, 1.2e-3, sizes);
        size_t placed = 0;
        OK(sinter_pack_random(s.ps, &p, 1500, &placed));
        assert_int_equal(placed, 1500);
        double m[2], largest;
        masses(&s, 0, m, &largest);
        const double total = m[0] + m[1];
        size_t n0 = 0, below = 0;
        for (size_t i = 0; i < placed; ++i) {
            const double r = get1(&s, SINTER_FIELD_RADIUS, i);
            if (material_of(&s, i) == 1) {
                assert_true(r >= 50e-6 && r <= 70e-6);
            } else {
                const double cut = pow(1.3, 3.0);
                assert_true(r >= 20e-6 / cut * (1 - 1e-12) && r <= 20e-6 * cut * (1 + 1e-12));
                n0++;
                below += r < 20e-6;
            }
        }
        const double half_below = (double)below / (double)n0;
        if (run == 0)
            print_message("packing: copper %.5f (share 0.6), alumina %.5f; bound %.5f; %zu copper "
                          "spheres, %.4f below their median (binomial tolerance %.4f)\n",
                          m[0] / total, m[1] / total, largest / total, n0, half_below,
                          2.0 / sqrt((double)n0));
        for (int k = 0; k < 2; ++k)
            assert_true(fabs(m[k] - SHARES[k] * total) <= largest);
        assert_true(fabs(half_below - 0.5) <= 2.0 / sqrt((double)n0));
        double x[3];
        get3(&s, SINTER_FIELD_POSITION, 1499, x);
        first_x[run] = x[0] + get1(&s, SINTER_FIELD_RADIUS, 1499) + material_of(&s, 1499);
        scene_close(&s);
    }
    assert_true(first_x[0] == first_x[1]);
    /* the layout that ended at mixture_mass_fractions: mixture_sizes not read (shared sizes) */
    double r_old = 0, r_new = 0;
    for (int layout = 0; layout < 2; ++layout) {
        scene s;
        open_box(&s, 0, 0.6e-3);
        sinter_packing_options p = powder(0.6e-3, 0, 1.2e-3, NULL);
        if (layout == 1) {
            p.struct_size = offsetof(sinter_packing_options, mixture_sizes);
            p.mixture_sizes = (const sinter_packing_options *)&p; /* past the layout: ignored */
        }
        OK(sinter_pack_random(s.ps, &p, 50, NULL));
        *(layout ? &r_old : &r_new) = get1(&s, SINTER_FIELD_RADIUS, 49) + material_of(&s, 49);
        scene_close(&s);
    }
    assert_true(r_old == r_new);
}

/*
 * Continuous insertion of a mixture (shared sizes, then each material's own) into a falling
 * stream: after each of 25 insertions the masses by material reported equal the inserted
 * particles' (to round-off), add up to the mass inserted, and each is within one particle's
 * mass of its share: the fractions converge to the requested ones as m_max / M.
 */
static void test_insertion_fractions(void **state)
{
    (void)state;
    sinter_packing_options sizes[2];
    own_sizes(sizes);
    for (int own = 0; own < 2; ++own) {
        scene s;
        open_box(&s, 1, 0.6e-3);
        sinter_packing_options p = powder(0.6e-3, 0.9e-3, 1.2e-3, own ? sizes : NULL);
        sinter_insertion_options o;
        OK(sinter_insertion_options_init(&o, sizeof(o)));
        o.mass_rate = 4e-5; /* kg/s: about two of the largest spheres a millisecond */
        o.interval = 1e-3;
        o.velocity[2] = -0.05;
        OK(sinter_stepper_set_insertion(s.st, &p, &o));
        double m[2], largest = 0.0, reported[3] = {0, 0, 0};
        for (int k = 0; k < 25; ++k) {
            if (sinter_stepper_advance(s.st, (k + 0.5) * o.interval) != SINTER_OK) {
                print_error("%s\n", sinter_last_error(s.ctx));
                fail();
            }
            double done = 0;
            size_t count = 0;
            OK(sinter_stepper_get_insertion(s.st, &done, NULL, NULL, NULL));
            OK(sinter_stepper_get_insertion_mixture(s.st, reported, 3, &count));
            assert_int_equal(count, 2);
            assert_true(reported[2] == 0.0); /* capacity 3, 2 written */
            masses(&s, 0, m, &largest);
            const double total = m[0] + m[1];
            assert_true(fabs(reported[0] + reported[1] - done) <= 1e-12 * done);
            for (int j = 0; j < 2; ++j) {
                assert_true(fabs(reported[j] - m[j]) <= 1e-12 * total);
                assert_true(fabs(m[j] - SHARES[j] * total) <= largest);
            }
        }
        const double total = m[0] + m[1];
        print_message("insertion (%s sizes): %.0f particles' worth, copper %.5f (share 0.6), "
                      "alumina %.5f, bound %.5f\n",
                      own ? "own" : "shared", total / largest, m[0] / total, m[1] / total,
                      largest / total);
        assert_true(largest / total < 0.05); /* the bound is tight: many particles inserted */
        scene_close(&s);
    }
}

/* A run stopped mid-way, checkpointed and read into a fresh stepper with the same mixture,
 * continues as the straight run (positions, radii, materials, the masses by material, bit for
 * bit); a stepper whose insertion mixes other materials is refused the checkpoint. */
static void test_checkpoint_restart(void **state)
{
    (void)state;
    char path[64];
    snprintf(path, sizeof(path), "/tmp/test_mixture_%ld.ck", (long)getpid());
    sinter_packing_options sizes[2];
    own_sizes(sizes);
    size_t counts[2] = {0, 0};
    double *final[2] = {NULL, NULL}, mass[2][2];
    for (int run = 0; run < 2; ++run) {
        scene s;
        open_box(&s, 1, 0.6e-3);
        sinter_packing_options p = powder(0.6e-3, 0.9e-3, 1.2e-3, sizes);
        sinter_insertion_options o;
        OK(sinter_insertion_options_init(&o, sizeof(o)));
        o.mass_rate = 2e-6;
        o.velocity[2] = -0.05;
        OK(sinter_stepper_set_insertion(s.st, &p, &o));
        OK(sinter_stepper_advance(s.st, 4.5e-3));
        if (run == 1) {
            OK(sinter_checkpoint_write(s.st, path));
            scene_close(&s);
            /* one material only: refused, nothing changed */
            open_box(&s, 1, 0.6e-3);
            sinter_packing_options one = powder(0.6e-3, 0.9e-3, 1.2e-3, NULL);
            one.mixture_count = 0;
            OK(sinter_stepper_set_insertion(s.st, &one, &o));
            assert_int_equal(sinter_checkpoint_read(s.st, path), SINTER_ERR_INVALID);
            assert_non_null(strstr(sinter_last_error(s.ctx), "mixture"));
            scene_close(&s);
            open_box(&s, 1, 0.6e-3);
            OK(sinter_stepper_set_insertion(s.st, &p, &o));
            OK(sinter_checkpoint_read(s.st, path));
            remove(path);
        }
        OK(sinter_stepper_advance(s.st, 9.5e-3));
        OK(sinter_particles_count(s.ps, &counts[run]));
        OK(sinter_stepper_get_insertion_mixture(s.st, mass[run], 2, NULL));
        final[run] = malloc(5 * counts[run] * sizeof(double));
        assert_non_null(final[run]);
        for (size_t i = 0; i < counts[run]; ++i) {
            get3(&s, SINTER_FIELD_POSITION, i, final[run] + 5 * i);
            final[run][5 * i + 3] = get1(&s, SINTER_FIELD_RADIUS, i);
            final[run][5 * i + 4] = material_of(&s, i);
        }
        scene_close(&s);
    }
    assert_true(counts[0] > 20);
    assert_int_equal(counts[0], counts[1]);
    assert_memory_equal(final[0], final[1], 5 * counts[0] * sizeof(double));
    assert_memory_equal(mass[0], mass[1], sizeof(mass[0]));
    free(final[0]);
    free(final[1]);
}

/* Refused, by the packer and by the insertion alike, naming the cause: fractions not summing to
 * 1, a negative or zero fraction, an unknown material, sizes without a mixture, a bad size of
 * one material; nothing is set by a refusal. */
static void test_bad_input(void **state)
{
    (void)state;
    scene s;
    open_box(&s, 0, 0.6e-3);
    sinter_insertion_options o;
    OK(sinter_insertion_options_init(&o, sizeof(o)));
    sinter_packing_options sizes[2];
    own_sizes(sizes);
    const double sum_09[2] = {0.5, 0.4}, negative[2] = {1.2, -0.2}, zero[2] = {1.0, 0.0};
    const int32_t unknown[2] = {0, 9};
    sinter_packing_options bad_size[2];
    own_sizes(bad_size);
    bad_size[1].radius_mean = -1e-6;
    struct {
        const double *fractions;
        const int32_t *ids;
        size_t count;
        const sinter_packing_options *sizes;
        sinter_status status;
        const char *fragment;
    } bad[] = {
        {sum_09, IDS, 2, NULL, SINTER_ERR_INVALID, "sum to 0.9"},
        {negative, IDS, 2, NULL, SINTER_ERR_INVALID, "mixture_mass_fractions[1] = -0.2"},
        {zero, IDS, 2, NULL, SINTER_ERR_INVALID, "mixture_mass_fractions[1] = 0"},
        {SHARES, unknown, 2, NULL, SINTER_ERR_NOT_FOUND, "material 9 is not registered"},
        {SHARES, IDS, 0, sizes, SINTER_ERR_INVALID, "mixture_sizes is set but mixture_count is 0"},
        {SHARES, IDS, 2, bad_size, SINTER_ERR_INVALID, "mixture_sizes[1] (material 1)"},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        sinter_packing_options p = powder(0.6e-3, 0, 1.2e-3, bad[k].sizes);
        p.mixture_mass_fractions = bad[k].fractions;
        p.mixture_materials = bad[k].ids;
        p.mixture_count = bad[k].count;
        for (int insert = 0; insert < 2; ++insert) {
            const sinter_status st = insert ? sinter_stepper_set_insertion(s.st, &p, &o)
                                            : sinter_pack_random(s.ps, &p, 10, NULL);
            assert_int_equal(st, bad[k].status);
            if (strstr(sinter_last_error(s.ctx), bad[k].fragment) == NULL) {
                print_error("message '%s' lacks '%s'\n", sinter_last_error(s.ctx), bad[k].fragment);
                fail();
            }
        }
    }
    size_t count = 1;
    OK(sinter_particles_count(s.ps, &count));
    assert_int_equal(count, 0);
    OK(sinter_stepper_get_insertion_mixture(s.st, NULL, 0, &count));
    assert_int_equal(count, 0);
    assert_int_equal(sinter_stepper_get_insertion_mixture(NULL, NULL, 0, NULL), SINTER_ERR_NULL);
    double m[2];
    assert_int_equal(sinter_stepper_get_insertion_mixture(s.st, NULL, 2, NULL), SINTER_ERR_NULL);
    (void)m;
    scene_close(&s);
}

/* The scene keys: [insert] materials, mass_fractions and sizes naming [size NAME] sections;
 * the fractions met; bad keys refused with the file and line. */
static const char *SCENE_HEAD = "[scene]\nname = mixture\nunits = SI\n"
                                "[material glass]\ndensity = 2500\nyoungs_modulus = 1e6\n"
                                "[material steel]\ndensity = 7800\nyoungs_modulus = 1e6\n"
                                "[size fine]\ndistribution = uniform\nradius = 3e-5\n"
                                "spread = 5e-6\n"
                                "[size coarse]\ndistribution = lognormal\nradius = 5e-5\n"
                                "gsd = 1.2\n"
                                "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
                                "[force hertz_mindlin]\n[force gravity]\n"
                                "[stepper]\ndt = 1e-6\nend_time = 0.005\n";

static const char *INSERT = "[insert]\nbox_min = -6e-4 -6e-4 9e-4\nbox_max = 6e-4 6e-4 1.2e-3\n"
                            "mass_rate = 4e-5\nvelocity = 0 0 -0.05\n";

static sinter_status load_scene(const char *body, sinter_ctx *ctx, sinter_scene **sc)
{
    char path[64], text[4096];
    snprintf(path, sizeof(path), "/tmp/test_mixture_%ld.sc", (long)getpid());
    snprintf(text, sizeof(text), "%s%s%s", SCENE_HEAD, INSERT, body);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    const sinter_status st = sinter_scene_load(sc, ctx, path);
    remove(path);
    return st;
}

static void test_scene_keys(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *sc = NULL;
    OK(load_scene("materials = glass steel\nmass_fractions = 0.25 0.75\nsizes = fine coarse\n", ctx,
                  &sc));
    sinter_stepper *st = NULL;
    OK(sinter_scene_get_stepper(sc, &st));
    OK(sinter_stepper_advance(st, 10.5e-3));
    double m[2], done = 0;
    size_t count = 0;
    OK(sinter_stepper_get_insertion(st, &done, NULL, NULL, NULL));
    OK(sinter_stepper_get_insertion_mixture(st, m, 2, &count));
    assert_int_equal(count, 2);
    const double r = 5e-5 * pow(1.2, 3.0), largest = 7800 * 4.0 / 3.0 * PI * r * r * r;
    assert_true(fabs(m[0] - 0.25 * done) <= largest && fabs(m[1] - 0.75 * done) <= largest);
    assert_true(done > 10 * largest);
    sinter_scene_destroy(sc);
    struct {
        const char *body, *fragment;
    } bad[] = {
        {"materials = glass steel\nmass_fractions = 0.25 0.7\nradius = 3e-5\n", "sum to 0.95"},
        {"materials = glass steel\nmass_fractions = 0.25\nradius = 3e-5\n",
         "one fraction for each of the 2"},
        {"materials = glass copper\nmass_fractions = 0.25 0.75\nradius = 3e-5\n",
         "'copper' is not the name"},
        {"materials = glass steel\nmass_fractions = 0.25 0.75\nsizes = fine\n",
         "one [size] name for each of the 2 materials, got 1"},
        {"materials = glass steel\nmass_fractions = 0.25 0.75\nsizes = fine medium\n",
         "'medium' is not the name of a [size NAME]"},
        {"material = glass\nradius = 1e-4\nsizes = fine\n", "sizes per material need materials"},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        sc = NULL;
        const sinter_status st2 = load_scene(bad[k].body, ctx, &sc);
        assert_true(st2 == SINTER_ERR_PARSE || st2 == SINTER_ERR_INVALID ||
                    st2 == SINTER_ERR_NOT_FOUND);
        assert_null(sc);
        if (strstr(sinter_last_error(ctx), bad[k].fragment) == NULL ||
            strstr(sinter_last_error(ctx), "test_mixture_") == NULL) {
            print_error("message '%s' lacks '%s' or the file\n", sinter_last_error(ctx),
                        bad[k].fragment);
            fail();
        }
    }
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_packing_own_sizes),  cmocka_unit_test(test_insertion_fractions),
        cmocka_unit_test(test_checkpoint_restart), cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_scene_keys),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
