/*
 * Heat every k-th step (issue 41, option "heat_interval", stepper/heat_interval.h): forward
 * Euler over k h from the powers of the evaluation before (seed 003 eq. 46 with the step
 * k h). Two spheres held in place against the closed form of their temperature gap (first
 * order in k h, sum m C theta conserved); the same spheres with conduction and convection
 * against heat every step at the step k h (the same operations: the same bits); a bed
 * bouncing on a hot floor on one and two threads and through a restart between two updates
 * (the same bits); the combinations the option refuses.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;

static void set_temperature(scene *s, size_t i, double t)
{
    double *a = NULL;
    OK(sinter_particles_view(s->ps, SINTER_FIELD_TEMPERATURE, (void **)&a, NULL, NULL));
    a[i] = t;
    OK(sinter_particles_release(s->ps, SINTER_FIELD_TEMPERATURE));
}

/* Two overlapping spheres (r 1 and 0.6 mm, 1.5 mm apart, 400 K and 300 K) with no force
 * model (at rest), conduction (and convection to 250 K air when `convection`); dt the step.
 * Returns the conduction's decay rate g (1 / (m1 C) + 1 / (m2 C)) [1/s]. */
typedef struct two {
    scene s;
    sinter_heat_model *cond, *conv;
    double rate, m1, m2, c;
} two;

static void open_two(two *w, double dt_rate, int convection)
{
    memset(w, 0, sizeof(*w));
    scene *s = &w->s;
    scene_init(s);
    scene_material(s, 1e7, 0.3, 3000, 0.0, 0.0);
    const double k = 50.0, c = 500.0;
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, k));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, c));
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_walls_create(&s->walls, s->ctx));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_EXPLICIT, s->ps, s->walls));
    const double r1 = 1e-3, r2 = 0.6e-3, d = 1.5e-3;
    const double x[2][3] = {{0, 0, 0}, {d, 0, 0}}, rad[2] = {r1, r2};
    OK(sinter_particles_add(s->ps, 2, x[0], rad, 0, 300.0, NULL));
    set_temperature(s, 0, 400.0);
    OK(sinter_heat_model_create(&w->cond, s->ctx, "conduction"));
    OK(sinter_stepper_add_heat(s->st, w->cond));
    if (convection) {
        OK(sinter_heat_model_create(&w->conv, s->ctx, "convection"));
        OK(sinter_heat_model_set(w->conv, "temperature", 250.0));
        OK(sinter_heat_model_set(w->conv, "h", 2000.0));
        OK(sinter_stepper_add_heat(s->st, w->conv));
    }
    /* closed form (seed 003 eq. 33-34): G = k A / d, the gap decays as exp(-rate t) */
    const double li = 0.5 * (d - (r2 * r2 - r1 * r1) / d), area = PI * (r1 * r1 - li * li);
    w->m1 = get1(s, SINTER_FIELD_MASS, 0);
    w->m2 = get1(s, SINTER_FIELD_MASS, 1);
    w->c = c;
    w->rate = k * area / d * (1.0 / (w->m1 * c) + 1.0 / (w->m2 * c));
    OK(sinter_stepper_set_dt(s->st, dt_rate / w->rate));
}

static void close_two(two *w)
{
    sinter_stepper_destroy(w->s.st);
    w->s.st = NULL;
    sinter_heat_model_destroy(w->cond);
    sinter_heat_model_destroy(w->conv);
    scene_close(&w->s);
}

static void test_closed_form_first_order(void **state)
{
    (void)state;
    /* 3000 steps of h = 1e-3 / rate to t = 3 / rate. Forward Euler over k h gives the gap
     * 100 K (1 - k h rate)^(3000 / k) exactly (to round-off: held to 1e-9 relative, so the
     * step k h is the one applied, every k-th step); its error against 100 K exp(-3) is about
     * 100 K exp(-3) 3 k h rate / 2, first order in k h: held within 5 % of k times k = 1's. */
    const int ks[3] = {1, 4, 20};
    double err[3];
    for (int q = 0; q < 3; ++q) {
        two w;
        open_two(&w, 1e-3, 0);
        OK(sinter_stepper_set_option(w.s.st, "heat_interval", ks[q]));
        const double e0 = w.m1 * w.c * 400.0 + w.m2 * w.c * 300.0;
        OK(sinter_stepper_step(w.s.st, 3000));
        const double t0 = get1(&w.s, SINTER_FIELD_TEMPERATURE, 0),
                     t1 = get1(&w.s, SINTER_FIELD_TEMPERATURE, 1);
        const double euler = 100.0 * pow(1.0 - ks[q] * 1e-3, 3000.0 / ks[q]);
        err[q] = fabs((t0 - t1) - 100.0 * exp(-3.0));
        const double drift = fabs(w.m1 * w.c * t0 + w.m2 * w.c * t1 - e0) / e0;
        print_message("k = %d: gap %.9f K, forward Euler over k h %.9f K, error %.4e K, energy "
                      "drift %.1e\n",
                      ks[q], t0 - t1, euler, err[q], drift);
        assert_true(fabs((t0 - t1) - euler) < 1e-9 * euler);
        assert_true(drift < 1e-13); /* conduction between two particles conserves it */
        close_two(&w);
    }
    for (int q = 1; q < 3; ++q)
        assert_true(fabs(err[q] / (ks[q] * err[0]) - 1.0) < 0.05);
}

static void test_same_bits_as_the_longer_step(void **state)
{
    (void)state;
    /* Conduction and convection, the spheres at rest: heat_interval 5 at h advances the
     * temperatures by the same operations as heat every step at 5 h, from the same states. */
    double a[2], b[2];
    for (int pass = 0; pass < 2; ++pass) {
        two w;
        open_two(&w, 1e-3, 1);
        if (pass == 0) {
            OK(sinter_stepper_set_option(w.s.st, "heat_interval", 5));
            OK(sinter_stepper_step(w.s.st, 2000));
        } else {
            OK(sinter_stepper_set_dt(w.s.st, 5.0 * (1e-3 / w.rate)));
            OK(sinter_stepper_step(w.s.st, 400));
        }
        double *out = pass == 0 ? a : b;
        out[0] = get1(&w.s, SINTER_FIELD_TEMPERATURE, 0);
        out[1] = get1(&w.s, SINTER_FIELD_TEMPERATURE, 1);
        close_two(&w);
    }
    print_message("k = 5 at h: %.12f / %.12f K; every step at 5 h: %.12f / %.12f K\n", a[0], a[1],
                  b[0], b[1]);
    assert_true(a[1] < 300.0); /* the convection to 250 K air acted */
    assert_memory_equal(a, b, sizeof(a));
}

/* 600 spheres (r 1 mm, a 30 x 20 layer above a second, shifted, two layers: more than
 * SINTER_THREADED_PARTICLES, so that two threads share the passes) dropped onto a 700 K floor,
 * conduction and convection, heat_interval 4, on `threads` threads; to step 1001 (between two
 * updates), optionally a checkpoint there read by a second stepper, then to step 2000
 * (0.04 s: the spheres bounce). Out: the mean temperature and the first sphere's temperature
 * and height, and the sum of the heights. */
enum { BED = 600 };

static void floor_bed(int threads, int restart, double out[4])
{
    const char *path = "test_heat_interval.ck";
    for (int pass = 0; pass < (restart ? 2 : 1); ++pass) {
        scene s;
        scene_init(&s);
        OK(sinter_ctx_set_threads(s.ctx, threads));
        scene_material(&s, 1e7, 0.3, 3000, 0.3, 0.5);
        OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 60.0));
        OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, 100.0));
        OK(sinter_material_set(s.wall_mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 60.0));
        scene_open(&s, "hertz_mindlin", 2);
        scene_floor(&s, 0.0);
        OK(sinter_walls_set_temperature(s.walls, 0, 700.0));
        for (int i = 0; i < BED; ++i) {
            const int layer = i / 300, row = (i % 300) / 30, col = i % 30;
            scene_add(&s, 2.1e-3 * col + 1.05e-3 * layer, 2.1e-3 * row + 1.05e-3 * layer,
                      1.05e-3 + 1.8e-3 * layer, 1e-3);
        }
        sinter_heat_model *cond = NULL, *conv = NULL;
        OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
        OK(sinter_stepper_add_heat(s.st, cond));
        OK(sinter_heat_model_create(&conv, s.ctx, "convection"));
        OK(sinter_heat_model_set(conv, "temperature", 300.0));
        OK(sinter_heat_model_set(conv, "h", 50.0));
        OK(sinter_stepper_add_heat(s.st, conv));
        OK(sinter_stepper_set_dt(s.st, 2e-5));
        OK(sinter_stepper_set_option(s.st, "heat_interval", 4));
        if (pass == 0) {
            OK(sinter_stepper_step(s.st, 1001));
            if (restart)
                OK(sinter_checkpoint_write(s.st, path));
        } else {
            OK(sinter_checkpoint_read(s.st, path));
        }
        if (pass + 1 == (restart ? 2 : 1)) {
            OK(sinter_stepper_step(s.st, 2000 - 1001));
            double x[3];
            get3(&s, SINTER_FIELD_POSITION, 0, x);
            out[0] = 0.0;
            out[1] = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
            out[2] = x[2];
            out[3] = 0.0;
            for (size_t i = 0; i < BED; ++i) {
                get3(&s, SINTER_FIELD_POSITION, i, x);
                out[0] += get1(&s, SINTER_FIELD_TEMPERATURE, i) / BED;
                out[3] += x[2];
            }
        }
        sinter_stepper_destroy(s.st);
        s.st = NULL;
        sinter_heat_model_destroy(cond);
        sinter_heat_model_destroy(conv);
        scene_close(&s);
    }
    remove(path);
}

static void test_threads_and_restart_same_bits(void **state)
{
    (void)state;
    double one[4], two_threads[4], restarted[4];
    floor_bed(1, 0, one);
    floor_bed(2, 0, two_threads);
    floor_bed(1, 1, restarted);
    print_message("at 0.04 s: mean %.6f K, sphere 0 %.6f K at z %.6e m\n", one[0], one[1], one[2]);
    assert_true(one[1] > 301.0); /* the floor heated a sphere of the lower layer */
    assert_memory_equal(one, two_threads, sizeof(one));
    assert_memory_equal(one, restarted, sizeof(one));
}

static void test_refused(void **state)
{
    (void)state;
    two w;
    open_two(&w, 1e-3, 0);
    sinter_stepper *st = w.s.st;
    assert_int_equal(sinter_stepper_set_option(st, "heat_interval", 0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(st, "heat_interval", 2.5), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(st, "heat_interval", 1e6), SINTER_ERR_INVALID);
    double v = 0.0;
    OK(sinter_stepper_get_option(st, "heat_interval", &v));
    assert_true(v == 1.0);
    OK(sinter_stepper_set_option(st, "heat_interval", 3));
    OK(sinter_stepper_get_option(st, "heat_interval", &v));
    assert_true(v == 3.0);
    /* the implicit scheme, frozen_heat: refused at the step, nothing advanced */
    OK(sinter_stepper_set_thermal_scheme(st, SINTER_THERMAL_IMPLICIT));
    assert_int_equal(sinter_stepper_step(st, 1), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_thermal_scheme(st, SINTER_THERMAL_EXPLICIT));
    OK(sinter_stepper_set_option(st, "frozen_heat", 1));
    assert_int_equal(sinter_stepper_step(st, 1), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_option(st, "frozen_heat", 0));
    /* a model whose power belongs to every step (the contacts' dissipation) */
    OK(sinter_heat_model_create(&w.conv, w.s.ctx, "dissipation")); /* destroyed by close_two */
    OK(sinter_stepper_add_heat(st, w.conv));
    assert_int_equal(sinter_stepper_step(st, 1), SINTER_ERR_INVALID);
    assert_true(get1(&w.s, SINTER_FIELD_TEMPERATURE, 0) == 400.0);
    double t = -1.0;
    OK(sinter_stepper_time(st, &t));
    assert_true(t == 0.0);
    close_two(&w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_form_first_order),
        cmocka_unit_test(test_same_bits_as_the_longer_step),
        cmocka_unit_test(test_threads_and_restart_same_bits),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
