/*
 * Continuous insertion (issue 38): the mass rate met within one particle's mass per interval,
 * no overlap at insertion (nothing moves in a box without gravity: a sphere inserted into an
 * overlap would be pushed), the cylinder region, a region too crowded to take the target,
 * the same spheres for the same seed, a checkpoint restart continuing the insertion bit for
 * bit, and bad input refused.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "scene_support.h"

#define RHO 2500.0
#define PI 3.14159265358979323846

static void open_box(scene *s, int gravity, double half)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, RHO, 0.5, 0.3);
    scene_open(s, "hertz_mindlin", gravity);
    /* a closed box [-half, half]^2 x [0, 2 half] */
    for (int d = 0; d < 3; ++d)
        for (int side = 0; side < 2; ++side) {
            double p[3] = {0, 0, half}, n[3] = {0, 0, 0};
            p[d] += side ? half : -half;
            n[d] = side ? -1.0 : 1.0;
            OK(sinter_walls_add_plane(s->walls, p, n, s->wall_mat, NULL));
        }
    OK(sinter_stepper_set_dt(s->st, 1e-6));
}

/* log-normal powder (median radius 0.1 mm, gsd 1.3, cut at 3 gsd) filling a box */
static sinter_packing_options powder(double lo_z, double hi_z, double half)
{
    sinter_packing_options p;
    assert_int_equal(sinter_packing_options_init(&p, sizeof(p)), SINTER_OK);
    p.distribution = SINTER_RADII_LOGNORMAL;
    p.radius_median = 1e-4;
    p.radius_gsd = 1.3;
    p.seed = 38;
    p.max_attempts = 200;
    for (int d = 0; d < 2; ++d) {
        p.box_min[d] = -half;
        p.box_max[d] = half;
    }
    p.box_min[2] = lo_z;
    p.box_max[2] = hi_z;
    return p;
}

static double largest_mass(void)
{
    const double r = 1e-4 * pow(1.3, 3.0);
    return RHO * 4.0 / 3.0 * PI * r * r * r;
}

/*
 * Inserted mass against mass_rate (k + 1) interval after each of 20 insertions into a falling
 * stream (gravity, the region high above the floor): the target minus the inserted mass lies in
 * [0, m_max), m_max the largest sphere's mass; the inserted mass is the particles' total mass.
 */
static void test_mass_rate(void **state)
{
    (void)state;
    scene s;
    open_box(&s, 1, 2e-3);
    sinter_packing_options p = powder(3e-3, 4e-3, 2e-3);
    sinter_insertion_options o;
    OK(sinter_insertion_options_init(&o, sizeof(o)));
    o.mass_rate = 2e-5; /* kg/s: about 2.4 spheres of the median size a millisecond */
    o.interval = 1e-3;
    o.velocity[2] = -0.1;
    OK(sinter_stepper_set_insertion(s.st, &p, &o));
    const double m_max = largest_mass();
    for (int k = 0; k < 20; ++k) {
        OK(sinter_stepper_advance(s.st, (k + 0.5) * o.interval));
        double done = 0, target = 0;
        uint64_t n = 0, crowded = 0;
        OK(sinter_stepper_get_insertion(s.st, &done, &target, &n, &crowded));
        assert_true(fabs(target - o.mass_rate * (k + 1) * o.interval) <= 1e-15 * target);
        assert_true(done <= target * (1 + 1e-12));
        assert_true(target - done < m_max);
        assert_int_equal(crowded, 0);
        size_t count = 0;
        OK(sinter_particles_count(s.ps, &count));
        assert_int_equal(count, n);
        double total = 0;
        for (size_t i = 0; i < count; ++i)
            total += get1(&s, SINTER_FIELD_MASS, i);
        assert_true(fabs(total - done) <= 1e-12 * done);
    }
    scene_close(&s);
}

/*
 * No overlaps at insertion: without gravity and at rest, a sphere only moves if a contact
 * pushes it. Spheres are inserted every millisecond into a box that already holds a random
 * packing, until the box is crowded; every velocity stays exactly 0 and every pair and wall
 * keeps its gap. The region is the upper part of the box, so the walls bound it.
 */
static void test_no_overlap(void **state)
{
    (void)state;
    for (int region = 0; region < 2; ++region) {
        scene s;
        const double half = 1e-3;
        open_box(&s, 0, half);
        sinter_packing_options p = powder(0, 2 * half, half);
        p.seed = 7;
        size_t placed = 0;
        OK(sinter_pack_random(s.ps, &p, 40, &placed));
        assert_int_equal(placed, 40);
        p.seed = 8;
        p.box_min[2] = 0.5 * half; /* the walls cut into the region: the wall check matters */
        sinter_insertion_options o;
        OK(sinter_insertion_options_init(&o, sizeof(o)));
        o.region = region;
        o.mass_rate = 1e-3; /* far more than fits: the box crowds */
        o.interval = 1e-4;
        o.end = 3e-3;
        OK(sinter_stepper_set_insertion(s.st, &p, &o));
        OK(sinter_stepper_advance(s.st, 3e-3));
        uint64_t n = 0, crowded = 0;
        double done = 0, target = 0;
        OK(sinter_stepper_get_insertion(s.st, &done, &target, &n, &crowded));
        assert_true(n > 50);
        assert_true(crowded > 0);
        assert_true(done < target);
        size_t count = 0;
        OK(sinter_particles_count(s.ps, &count));
        assert_int_equal(count, 40 + n);
        const double *x = NULL, *v = NULL, *r = NULL;
        OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
        OK(sinter_particles_view_read(s.ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL));
        OK(sinter_particles_view_read(s.ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
        for (size_t i = 0; i < count; ++i) {
            for (int d = 0; d < 3; ++d)
                assert_true(v[3 * i + d] == 0.0);
            for (size_t j = 0; j < i; ++j) {
                const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1],
                             dz = x[3 * i + 2] - x[3 * j + 2];
                assert_true(sqrt(dx * dx + dy * dy + dz * dz) >= r[i] + r[j]);
            }
            assert_true(x[3 * i + 2] - r[i] >= 0 && x[3 * i + 2] + r[i] <= 2 * half);
            for (int d = 0; d < 2; ++d)
                assert_true(fabs(x[3 * i + d]) + r[i] <= half);
            if (region == SINTER_INSERT_CYLINDER && i >= 40)
                assert_true(hypot(x[3 * i], x[3 * i + 1]) + r[i] <= half * (1 + 1e-12));
            if (i >= 40)
                assert_true(x[3 * i + 2] - r[i] >= 0.5 * half);
        }
        OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
        OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
        OK(sinter_particles_release(s.ps, SINTER_FIELD_RADIUS));
        scene_close(&s);
    }
}

/* The same seed inserts the same spheres, bit for bit; another seed others. */
static void test_reproducible(void **state)
{
    (void)state;
    double first[3][2];
    for (int run = 0; run < 3; ++run) {
        scene s;
        open_box(&s, 1, 2e-3);
        sinter_packing_options p = powder(3e-3, 4e-3, 2e-3);
        p.seed = run == 2 ? 39 : 38;
        sinter_insertion_options o;
        OK(sinter_insertion_options_init(&o, sizeof(o)));
        o.mass_rate = 2e-5;
        OK(sinter_stepper_set_insertion(s.st, &p, &o));
        OK(sinter_stepper_advance(s.st, 5e-3));
        double x[3];
        get3(&s, SINTER_FIELD_POSITION, 3, x);
        first[run][0] = x[0];
        first[run][1] = get1(&s, SINTER_FIELD_RADIUS, 3);
        scene_close(&s);
    }
    assert_true(first[0][0] == first[1][0] && first[0][1] == first[1][1]);
    assert_true(first[0][0] != first[2][0]);
}

/* A run stopped mid-way, written to a checkpoint and read into a fresh stepper with the same
 * insertion, continues exactly as the straight run: the same spheres, the same bits. */
static void test_checkpoint_restart(void **state)
{
    (void)state;
    char path[64];
    snprintf(path, sizeof(path), "/tmp/test_insertion_%ld.ck", (long)getpid());
    size_t counts[2] = {0, 0};
    double *final[2] = {NULL, NULL};
    for (int run = 0; run < 2; ++run) {
        scene s;
        open_box(&s, 1, 2e-3);
        sinter_packing_options p = powder(3e-3, 4e-3, 2e-3);
        sinter_insertion_options o;
        OK(sinter_insertion_options_init(&o, sizeof(o)));
        o.mass_rate = 2e-5;
        OK(sinter_stepper_set_insertion(s.st, &p, &o));
        OK(sinter_stepper_advance(s.st, 4.5e-3)); /* both stop here (the last step lands on it) */
        if (run == 1) {
            OK(sinter_checkpoint_write(s.st, path));
            scene_close(&s);
            open_box(&s, 1, 2e-3);
            OK(sinter_stepper_set_insertion(s.st, &p, &o));
            OK(sinter_checkpoint_read(s.st, path));
            remove(path);
        }
        OK(sinter_stepper_advance(s.st, 9.5e-3));
        OK(sinter_particles_count(s.ps, &counts[run]));
        final[run] = malloc(4 * counts[run] * sizeof(double));
        assert_non_null(final[run]);
        for (size_t i = 0; i < counts[run]; ++i) {
            get3(&s, SINTER_FIELD_POSITION, i, final[run] + 4 * i);
            final[run][4 * i + 3] = get1(&s, SINTER_FIELD_RADIUS, i);
        }
        scene_close(&s);
    }
    assert_true(counts[0] > 10);
    assert_int_equal(counts[0], counts[1]);
    assert_memory_equal(final[0], final[1], 4 * counts[0] * sizeof(double));
    free(final[0]);
    free(final[1]);
}

/* The scene's [insert] section: a scene without [particles] fills from its region at the rate
 * given; bad keys are refused with the file and line; a scene with neither is refused. */
static const char *SCENE_HEAD = "[scene]\nname = insert\nunits = SI\n"
                                "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\n"
                                "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
                                "[force hertz_mindlin]\n[force gravity]\n"
                                "[stepper]\ndt = 1e-6\nend_time = 0.005\n";

static sinter_status load_scene(const char *body, sinter_ctx *ctx, sinter_scene **sc)
{
    char path[64], text[2048];
    snprintf(path, sizeof(path), "/tmp/test_insertion_%ld.sc", (long)getpid());
    snprintf(text, sizeof(text), "%s%s", SCENE_HEAD, body);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    const sinter_status st = sinter_scene_load(sc, ctx, path);
    remove(path);
    return st;
}

static void test_scene_section(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *sc = NULL;
    OK(load_scene("[insert]\nmaterial = glass\ndistribution = uniform\nradius = 1e-4\n"
                  "spread = 2e-5\nbox_min = -1e-3 -1e-3 2e-3\nbox_max = 1e-3 1e-3 3e-3\n"
                  "region = cylinder\nmass_rate = 2e-5\ninterval = 1e-3\nseed = 9\n"
                  "velocity = 0 0 -0.1\n",
                  ctx, &sc));
    sinter_stepper *st = NULL;
    OK(sinter_scene_get_stepper(sc, &st));
    OK(sinter_stepper_advance(st, 2.5e-3));
    double done = 0, target = 0;
    uint64_t n = 0;
    OK(sinter_stepper_get_insertion(st, &done, &target, &n, NULL));
    const double r = 1.2e-4, m_max = RHO * 4.0 / 3.0 * PI * r * r * r;
    assert_true(fabs(target - 3 * 2e-5 * 1e-3) <= 1e-15);
    assert_true(done <= target && target - done < m_max);
    assert_true(n > 0);
    sinter_scene_destroy(sc);
    struct {
        const char *body, *fragment;
    } bad[] = {
        {"[insert]\nmaterial = glass\nradius = 1e-4\nbox_min = 0 0 0\nbox_max = 1e-3 1e-3 "
         "1e-3\nmass_rate = 1e-5\nregion = sphere\n",
         "region: expected box or cylinder"},
        {"[insert]\nmaterial = glass\nradius = 1e-4\nbox_min = 0 0 0\nbox_max = 1e-3 1e-3 "
         "1e-3\n",
         "needs 'mass_rate"},
        {"[insert]\nmaterial = glass\nradius = 1e-4\nbox_min = 0 0 0\nbox_max = 1e-3 1e-3 "
         "1e-3\nmass_rate = -1\n",
         "mass_rate = -1 kg/s"},
        {"", "has no particles"},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        sc = NULL;
        const sinter_status st2 = load_scene(bad[k].body, ctx, &sc);
        assert_true(st2 == SINTER_ERR_PARSE || st2 == SINTER_ERR_INVALID);
        assert_null(sc);
        if (strstr(sinter_last_error(ctx), bad[k].fragment) == NULL) {
            print_error("message '%s' lacks '%s'\n", sinter_last_error(ctx), bad[k].fragment);
            fail();
        }
    }
    sinter_ctx_destroy(ctx);
}

static void test_bad_input(void **state)
{
    (void)state;
    scene s;
    open_box(&s, 0, 1e-3);
    sinter_packing_options p = powder(0, 2e-3, 1e-3);
    sinter_insertion_options o;
    OK(sinter_insertion_options_init(&o, sizeof(o)));
    assert_int_equal(sinter_insertion_options_init(&o, 3), SINTER_ERR_STRUCT_SIZE);
    assert_int_equal(sinter_stepper_set_insertion(NULL, &p, &o), SINTER_ERR_NULL);
    assert_int_equal(sinter_stepper_set_insertion(s.st, &p, NULL), SINTER_ERR_NULL);
    struct {
        double *field, value;
    } bad[] = {{&o.mass_rate, 0.0}, {&o.mass_rate, -1.0}, {&o.mass_rate, NAN},  {&o.interval, 0.0},
               {&o.end, 0.0},       {&o.start, INFINITY}, {&o.velocity[1], NAN}};
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        sinter_insertion_options b = o;
        *(double *)((char *)&b + ((char *)bad[k].field - (char *)&o)) = bad[k].value;
        assert_int_equal(sinter_stepper_set_insertion(s.st, &p, &b), SINTER_ERR_INVALID);
    }
    sinter_insertion_options b = o;
    b.region = 2;
    assert_int_equal(sinter_stepper_set_insertion(s.st, &p, &b), SINTER_ERR_INVALID);
    b = o;
    b.struct_size = 8;
    assert_int_equal(sinter_stepper_set_insertion(s.st, &p, &b), SINTER_ERR_STRUCT_SIZE);
    sinter_packing_options q = p;
    q.box_max[2] = q.box_min[2] + 1e-4; /* narrower than the largest sphere */
    assert_int_equal(sinter_stepper_set_insertion(s.st, &q, &o), SINTER_ERR_INVALID);
    q = p;
    q.material = 5;
    assert_int_equal(sinter_stepper_set_insertion(s.st, &q, &o), SINTER_ERR_NOT_FOUND);
    q = p;
    const int32_t mats[1] = {0};
    const double fractions[1] = {0.9}; /* a mixture's fractions must sum to 1 (test_mixture.c) */
    q.mixture_count = 1;
    q.mixture_materials = mats;
    q.mixture_mass_fractions = fractions;
    assert_int_equal(sinter_stepper_set_insertion(s.st, &q, &o), SINTER_ERR_INVALID);
    /* nothing was set by the refusals */
    double target = 1;
    OK(sinter_stepper_get_insertion(s.st, NULL, &target, NULL, NULL));
    assert_true(target == 0.0);
    OK(sinter_stepper_set_insertion(s.st, &p, &o));
    OK(sinter_stepper_set_insertion(s.st, NULL, NULL)); /* removed */
    scene_close(&s);
    /* another stepper kind does not insert */
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, RHO, 0.5, 0.3);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_STAGGERED, s.ps, NULL));
    assert_int_equal(sinter_stepper_set_insertion(s.st, &p, &o), SINTER_ERR_STATE);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mass_rate),     cmocka_unit_test(test_no_overlap),
        cmocka_unit_test(test_reproducible),  cmocka_unit_test(test_checkpoint_restart),
        cmocka_unit_test(test_scene_section), cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
