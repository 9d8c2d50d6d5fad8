/*
 * Heat at its own pace over a frozen bed (issue 41, stepper/frozen_heat.c): the heat step
 * control's convergence on two spheres with a closed-form solution, the frozen run against the
 * fully coupled one on seed 003 sec. 5.1 (a particle settling on a 700 K floor, with thermal
 * softening: the mechanics wake up), a restart through a frozen phase, bit for bit, and the
 * same restart with the stage off (the mechanics wake).
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

static double option(const sinter_stepper *st, const char *key)
{
    double v = NAN;
    OK(sinter_stepper_get_option(st, key, &v));
    return v;
}

/* Two overlapping spheres held in place (no force model: at rest from the first step), the
 * frozen heat stage at rtol; the error of the temperature gap at t = 3 / rate against the
 * closed form 100 K exp(-3) [K], the heat steps and sum m C theta's relative drift. */
typedef struct two_result {
    double error, drift;
    double steps;
} two_result;

static two_result two_spheres(double rtol)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 3000, 0.0, 0.0);
    const double k = 50.0, c = 500.0;
    OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, k));
    OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, c));
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_walls_create(&s.walls, s.ctx));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_EXPLICIT, s.ps, s.walls));
    const double r1 = 1e-3, r2 = 0.6e-3, d = 1.5e-3;
    const double x[2][3] = {{0, 0, 0}, {d, 0, 0}}, rad[2] = {r1, r2};
    OK(sinter_particles_add(s.ps, 2, x[0], rad, 0, 300.0, NULL));
    set_temperature(&s, 0, 400.0);
    sinter_heat_model *cond = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_stepper_add_heat(s.st, cond));
    /* closed form (seed 003 eq. 33-34): G = k A / d, the gap decays as exp(-rate t) */
    const double li = 0.5 * (d - (r2 * r2 - r1 * r1) / d), area = PI * (r1 * r1 - li * li);
    const double g = k * area / d;
    const double m1 = get1(&s, SINTER_FIELD_MASS, 0), m2 = get1(&s, SINTER_FIELD_MASS, 1);
    const double rate = g * (1.0 / (m1 * c) + 1.0 / (m2 * c));
    OK(sinter_stepper_set_dt(s.st, 1e-4 / rate));
    OK(sinter_stepper_set_option(s.st, "frozen_heat", 1));
    OK(sinter_stepper_set_option(s.st, "frozen_settle", 1));
    OK(sinter_stepper_set_option(s.st, "frozen_rtol", rtol));
    OK(sinter_stepper_set_option(s.st, "frozen_atol", 1e-12));
    const double e0 = m1 * c * 400.0 + m2 * c * 300.0;
    OK(sinter_stepper_advance(s.st, 3.0 / rate));
    const double t0 = get1(&s, SINTER_FIELD_TEMPERATURE, 0),
                 t1 = get1(&s, SINTER_FIELD_TEMPERATURE, 1);
    two_result out;
    out.error = fabs((t0 - t1) - 100.0 * exp(-3.0)); /* [K] */
    out.drift = fabs(m1 * c * t0 + m2 * c * t1 - e0) / e0;
    out.steps = option(s.st, "frozen_steps");
    assert_true(option(s.st, "frozen_active") == 1.0);
    assert_true(option(s.st, "frozen_freezes") == 1.0);
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    return out;
}

static void test_heat_step_control_converges(void **state)
{
    (void)state;
    /* Backward Euler is of order 1: its local error h^2 / 2 theta'' held to the tolerance
     * (error per step) gives steps h ~ rtol^(1/2) and a global error ~ h ~ rtol^(1/2). Held:
     * the observed order in the step, log(e1 / e2) / log(N2 / N1), within 0.8-1.2 on each
     * decade of rtol, and the error within a factor 2 of sqrt(10) smaller per decade. */
    const double tols[3] = {1e-3, 1e-4, 1e-5};
    two_result r[3];
    for (int k = 0; k < 3; ++k) {
        r[k] = two_spheres(tols[k]);
        print_message("rtol %.0e: error %.3e K, %g heat steps, energy drift %.1e\n", tols[k],
                      r[k].error, r[k].steps, r[k].drift);
        /* conduction between two particles conserves sum m C theta (to the PCG's solve) */
        assert_true(r[k].drift < 1e-12);
    }
    for (int k = 0; k < 2; ++k) {
        const double gain = r[k].error / r[k + 1].error;
        const double order = log(gain) / log(r[k + 1].steps / r[k].steps);
        print_message("decade %d: error / %.2f, order %.3f in the step\n", k, gain, order);
        assert_true(order > 0.8 && order < 1.2);
        assert_true(gain > sqrt(10.0) / 2.0 && gain < 2.0 * sqrt(10.0));
    }
}

/* Seed 003 sec. 5.1 (test_heat.c's hot floor): r = 1 mm settling on a 700 K floor, softening
 * theta* = 400 K; the temperature every 0.1 s to 16 s; frozen heat at rtol (0: coupled). The
 * stepper is left open for the caller when keep != NULL. */
typedef struct floor_run {
    double theta[161];
    double force;
    double wakeups, heat_steps, frozen_time;
} floor_run;

static void open_floor(scene *s, double rtol)
{
    scene_init(s);
    scene_material(s, 1e6, 0.3, 3000, 1.0, 0.0);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 60.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 100.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_SOFTENING_LAW, 2));
    OK(sinter_material_set(s->mat, SINTER_MAT_SOFTENING_TEMPERATURE, 400.0));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_YOUNGS_MODULUS, 1e13));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 60.0));
    scene_open(s, "hertz_mindlin", 1);
    scene_floor(s, 0.0);
    OK(sinter_walls_set_temperature(s->walls, 0, 700.0));
    scene_add(s, 0, 0, 1e-3, 1e-3);
    set_temperature(s, 0, 300.0);
    OK(sinter_stepper_set_dt(s->st, 2e-5));
    if (rtol > 0.0) {
        OK(sinter_stepper_set_option(s->st, "frozen_heat", 1));
        OK(sinter_stepper_set_option(s->st, "frozen_ke", 1e-15));
        OK(sinter_stepper_set_option(s->st, "frozen_rtol", rtol));
        OK(sinter_stepper_set_option(s->st, "frozen_atol", 1e-9));
        OK(sinter_stepper_set_option(s->st, "frozen_wake", 1e-3));
    }
}

static floor_run run_floor(double rtol)
{
    scene s;
    open_floor(&s, rtol);
    sinter_heat_model *cond = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_stepper_add_heat(s.st, cond));
    floor_run out;
    memset(&out, 0, sizeof(out));
    out.theta[0] = 300.0;
    for (int k = 1; k <= 160; ++k) {
        OK(sinter_stepper_advance(s.st, 0.1 * k));
        out.theta[k] = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
    }
    double f[3];
    OK(sinter_walls_get_force(s.walls, 0, f));
    out.force = -f[2];
    out.wakeups = option(s.st, "frozen_wakeups");
    out.heat_steps = option(s.st, "frozen_steps");
    out.frozen_time = option(s.st, "frozen_time");
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    return out;
}

static void test_frozen_equals_coupled_hot_floor(void **state)
{
    (void)state;
    const floor_run coupled = run_floor(0.0), frozen = run_floor(1e-6);
    double worst = 0.0;
    for (int k = 0; k <= 160; ++k)
        worst = fmax(worst, fabs(frozen.theta[k] - coupled.theta[k]));
    print_message("hot floor, 16 s: frozen %.2f s of it in %g heat steps, %g wake-ups; largest "
                  "temperature difference %.3f K; static force %.5e / %.5e N\n",
                  frozen.frozen_time, frozen.heat_steps, frozen.wakeups, worst, frozen.force,
                  coupled.force);
    /* Most of the run frozen, the softening waking the mechanics on the way (E falls to
     * 0.47 E_0 over the heating, a 0.1 % change wakes them). */
    assert_true(frozen.frozen_time > 10.0);
    assert_true(frozen.wakeups > 10.0);
    /* The stated error (RESULTS.md, issue 41): within 0.2 K of the coupled run over the 400 K
     * rise (0.05 %), the same static force to 0.1 %. */
    assert_true(worst < 0.2);
    assert_close(frozen.force, coupled.force, 1e-3 * coupled.force);
}

/* Run to t1 (frozen by then), checkpoint, run to t2; a second stepper reads the checkpoint and
 * runs to t2: the same bits (temperature, position, velocity and the frozen statistics). */
static void test_restart_through_frozen_phase(void **state)
{
    (void)state;
    const char *path = "test_frozen_heat.ck";
    const double t1 = 3.0, t2 = 9.0; /* from t1: a frozen phase; t2 after wake-ups */
    double a[7], b[7];
    for (int pass = 0; pass < 2; ++pass) {
        scene s;
        open_floor(&s, 1e-5);
        sinter_heat_model *cond = NULL;
        OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
        OK(sinter_stepper_add_heat(s.st, cond));
        if (pass == 0) {
            /* on to the first sample from t1 on, every 0.05 s, that finds the bed frozen */
            double t = t1;
            OK(sinter_stepper_advance(s.st, t));
            while (option(s.st, "frozen_active") != 1.0 && t < 6.0)
                OK(sinter_stepper_advance(s.st, t += 0.05));
            assert_true(option(s.st, "frozen_active") == 1.0);
            const sinter_status w = sinter_checkpoint_write(s.st, path);
            if (w != SINTER_OK)
                print_message("%s\n", sinter_last_error(s.ctx));
            OK(w);
        } else {
            OK(sinter_checkpoint_read(s.st, path));
            assert_true(option(s.st, "frozen_active") == 1.0);
        }
        OK(sinter_stepper_advance(s.st, t2));
        double *out = pass == 0 ? a : b, x[3], v[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x);
        get3(&s, SINTER_FIELD_VELOCITY, 0, v);
        out[0] = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
        out[1] = x[2];
        out[2] = v[2];
        out[3] = option(s.st, "frozen_steps");
        out[4] = option(s.st, "frozen_wakeups");
        out[5] = option(s.st, "frozen_time");
        out[6] = option(s.st, "frozen_dt");
        assert_true(out[4] > 0.0); /* the continued run woke the mechanics */
        sinter_stepper_destroy(s.st);
        s.st = NULL;
        sinter_heat_model_destroy(cond);
        scene_close(&s);
    }
    remove(path);
    assert_memory_equal(a, b, sizeof(a));
}

/*
 * The same checkpoint of a frozen bed read by a stepper with frozen_heat off (issue 41): the
 * freeze is restored, then the option decides, so the mechanics wake at the first step and
 * the particle, resting on the floor under gravity, moves again: its position and velocity
 * leave the checkpoint's bits within 20 mechanical steps (all of them explicit steps), where
 * the frozen stage would keep them. Run on to t2 coupled, its temperature stays within 0.5 K
 * (0.13 % of the 390 K rise; measured 0.19 K) of the run that continued frozen at rtol 1e-5,
 * ten times the rtol of the 0.2 K stated in test_frozen_equals_coupled_hot_floor.
 */
static void test_restart_frozen_with_stage_off(void **state)
{
    (void)state;
    const char *path = "test_frozen_heat_off.ck";
    const double t2 = 9.0;
    double x0[3], v0[3], t_ck = 3.0, frozen_theta = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
        scene s;
        open_floor(&s, pass == 0 ? 1e-5 : 0.0); /* pass 1: the option off */
        sinter_heat_model *cond = NULL;
        OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
        OK(sinter_stepper_add_heat(s.st, cond));
        if (pass == 0) {
            OK(sinter_stepper_advance(s.st, t_ck));
            while (option(s.st, "frozen_active") != 1.0 && t_ck < 6.0)
                OK(sinter_stepper_advance(s.st, t_ck += 0.05));
            assert_true(option(s.st, "frozen_active") == 1.0);
            get3(&s, SINTER_FIELD_POSITION, 0, x0);
            get3(&s, SINTER_FIELD_VELOCITY, 0, v0);
            OK(sinter_checkpoint_write(s.st, path));
            OK(sinter_stepper_advance(s.st, t2));
            frozen_theta = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
        } else {
            OK(sinter_checkpoint_read(s.st, path));
            assert_true(option(s.st, "frozen_active") == 1.0); /* the state as written */
            const double wakeups = option(s.st, "frozen_wakeups");
            const double heat_steps = option(s.st, "frozen_steps");
            sinter_stepper_stats before = {.struct_size = sizeof(sinter_stepper_stats)},
                                 after = {.struct_size = sizeof(sinter_stepper_stats)};
            OK(sinter_stepper_get_stats(s.st, &before));
            OK(sinter_stepper_step(s.st, 20));
            OK(sinter_stepper_get_stats(s.st, &after));
            assert_true(option(s.st, "frozen_active") == 0.0);
            assert_true(option(s.st, "frozen_wakeups") == wakeups + 1.0);
            assert_true(option(s.st, "frozen_steps") == heat_steps); /* no heat step alone */
            assert_int_equal(after.steps - before.steps, 20);
            double x[3], v[3];
            get3(&s, SINTER_FIELD_POSITION, 0, x);
            get3(&s, SINTER_FIELD_VELOCITY, 0, v);
            print_message("frozen checkpoint at %.2f s read with frozen_heat 0: after 20 steps "
                          "z %.17g -> %.17g m, v_z %.6g -> %.6g m/s\n",
                          t_ck, x0[2], x[2], v0[2], v[2]);
            assert_true(memcmp(x, x0, sizeof(x)) != 0);
            assert_true(memcmp(v, v0, sizeof(v)) != 0);
            OK(sinter_stepper_advance(s.st, t2));
            const double theta = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
            print_message("at %g s: %.4f K coupled from the checkpoint, %.4f K frozen\n", t2, theta,
                          frozen_theta);
            assert_true(option(s.st, "frozen_active") == 0.0);
            assert_true(fabs(theta - frozen_theta) < 0.5);
        }
        sinter_stepper_destroy(s.st);
        s.st = NULL;
        sinter_heat_model_destroy(cond);
        scene_close(&s);
    }
    remove(path);
}

/* A laser crossing a row of ten spheres held apart (no contacts: the beam alone heats them), the
 * frozen stage at `travel` (< 0: the stage off, the explicit scheme at every mechanical step, the
 * reference). Each sphere's temperature rise is the beam's power on it times the time it is lit;
 * a heat step takes the power at its start, so a lit time is off by at most a step at each of its
 * two ends. The largest error over the spheres, relative to the largest rise, is returned. */
static double laser_row(double travel, const double *reference, double *rise, double *steps)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 3000, 0.0, 0.0);
    OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 50.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, 500.0));
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_walls_create(&s.walls, s.ctx));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_EXPLICIT, s.ps, s.walls));
    const double r = 0.5e-3;
    for (int i = 0; i < 10; ++i) {
        const double x[3] = {1.2e-3 * i, 0.0, r};
        OK(sinter_particles_add(s.ps, 1, x, &r, 0, 300.0, NULL));
    }
    sinter_heat_model *cond = NULL, *laser = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_stepper_add_heat(s.st, cond));
    OK(sinter_heat_model_create(&laser, s.ctx, "laser"));
    OK(sinter_heat_model_set(laser, "radius", 2e-3));
    OK(sinter_heat_model_set(laser, "intensity", 2e6));
    const double times[2] = {0.0, 0.18}, xs[2] = {-3e-3, 15e-3}; /* 0.1 m/s */
    OK(sinter_heat_model_set_schedule(laser, "x", 2, times, xs));
    OK(sinter_stepper_add_heat(s.st, laser));
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    if (travel >= 0.0) {
        OK(sinter_stepper_set_option(s.st, "frozen_heat", 1));
        OK(sinter_stepper_set_option(s.st, "frozen_settle", 1));
        OK(sinter_stepper_set_option(s.st, "frozen_travel", travel));
    }
    OK(sinter_stepper_advance(s.st, 0.18));
    double worst = 0.0, top = 0.0;
    for (size_t i = 0; i < 10; ++i) {
        const double d = get1(&s, SINTER_FIELD_TEMPERATURE, i) - 300.0;
        if (reference == NULL)
            rise[i] = d;
        else
            worst = fmax(worst, fabs(d - reference[i]));
        top = fmax(top, fabs(reference != NULL ? reference[i] : d));
    }
    *steps = travel >= 0.0 ? option(s.st, "frozen_steps") : 0.0;
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    sinter_heat_model_destroy(laser);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    return worst / top;
}

static void test_moving_source_limits_the_heat_step(void **state)
{
    (void)state;
    double rise[10], steps = 0.0;
    laser_row(-1.0, NULL, rise, &steps);
    for (int i = 0; i < 10; ++i)
        assert_true(rise[i] > 1.0); /* every sphere is crossed by the beam */
    /* 0.05 radii a step: h <= 0.05 r / v = 2.5e-4 s, a lit time of 2 R / v = 0.04 s off by at
     * most 2 h: 1.25 %; held to 2 % (the reference's own steps, 1e-5 s, are 0.05 %) */
    const double limited = laser_row(0.05, rise, rise, &steps);
    print_message("frozen_travel 0.05: %g heat steps, largest error %.3e of the largest rise\n",
                  steps, limited);
    assert_true(steps >= 0.18 * 0.1 / (0.05 * 0.5e-3) * 0.9);
    assert_true(limited < 0.02);
    /* without the limit the steps grow past the lit times (the error estimate sees no change
     * of the rates within a step): the comparison can fail */
    const double free_steps = laser_row(0.0, rise, rise, &steps);
    print_message("frozen_travel 0: %g heat steps, largest error %.3e of the largest rise\n",
                  steps, free_steps);
    assert_true(free_steps > 0.1);
}

static void test_options_checked(void **state)
{
    (void)state;
    scene s;
    open_floor(&s, 0.0);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_heat", 2), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_rtol", 0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_atol", NAN), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_settle", 1.5), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_steps", 1), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_travel", -1), SINTER_ERR_INVALID);
    assert_true(option(s.st, "frozen_travel") == 0.05);
    OK(sinter_stepper_set_option(s.st, "frozen_dt_max", 0.5));
    assert_true(option(s.st, "frozen_dt_max") == 0.5);
    assert_true(option(s.st, "frozen_heat") == 0.0);
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    scene_close(&s);
    scene_init(&s);
    scene_material(&s, 1e6, 0.3, 3000, 1.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_STAGGERED, s.ps, NULL));
    assert_int_equal(sinter_stepper_set_option(s.st, "frozen_heat", 1), SINTER_ERR_UNSUPPORTED);
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_heat_step_control_converges),
        cmocka_unit_test(test_frozen_equals_coupled_hot_floor),
        cmocka_unit_test(test_restart_through_frozen_phase),
        cmocka_unit_test(test_restart_frozen_with_stage_off),
        cmocka_unit_test(test_moving_source_limits_the_heat_step),
        cmocka_unit_test(test_options_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
