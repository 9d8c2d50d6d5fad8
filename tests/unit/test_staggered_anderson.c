/*
 * Scheme 1 of the implicit staggered stepper (seed 000 sec. 3, 6 with Anderson acceleration, a
 * weighted RMS test, a PI controller on the contraction and an extrapolating predictor;
 * src/stepper/staggered.c, anderson.c, step_control.c), public API only: second order on a
 * smooth two-particle thermo-mechanical problem; Anderson converges in fewer iterations than
 * the plain iteration; no cycling of the step on a pile at rest; restart bit for bit.
 * Each tolerance is derived where it is asserted (docs/validation.md).
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include <sinter_submodel.h>

#include "scene_support.h"

static sinter_stepper_stats stats_of(sinter_stepper *st)
{
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(st, &stats));
    return stats;
}

/* ---- a smooth two-particle thermo-mechanical problem ------------------------------------- */

/*
 * Two spheres (radius r, mass m) pressed together by opposite host body forces +-F along x and
 * held apart by a linear spring contact (kn, cn = 0): the overlap oscillates as
 * F/kn + (delta_0 - F/kn) cos(omega t), omega = sqrt(2 kn / m), and never opens (amplitude half
 * the static overlap). The spheres start at 400 K and 300 K and exchange heat by conduction
 * through the contact, whose conductance follows the overlap (seed 003 eq. 34): temperatures
 * depend on the motion. Everything is smooth, so the trapezoidal rule is second order in both.
 */
static int push_together(const sinter_state_view *state, double *force, double *torque, void *user)
{
    (void)state;
    (void)torque;
    const double f = *(const double *)user;
    force[0] = f;
    force[3] = -f;
    return 0;
}

typedef struct pair_result {
    double delta, theta; /* overlap [m] and temperature of sphere 0 [K] at the end */
    double delta_error;  /* overlap against the closed form at the end [m] */
    sinter_stepper_stats stats;
} pair_result;

/* Five radians of the oscillation with fixed step omega h = wh (adaptive = 0). */
static pair_result pair_run(double wh, double tolerance, int depth, int kd)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.0);
    OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 50.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, 5.0));
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_walls_create(&s.walls, s.ctx));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_STAGGERED, s.ps, s.walls));
    const double r = 1e-3, kn = 100.0, delta0 = 1.5e-5;
    double f = 1e-3;
    OK(sinter_force_model_create(&s.contact, s.ctx, "linear_spring"));
    OK(sinter_force_model_set(s.contact, "kn", kn));
    OK(sinter_force_model_set(s.contact, "cn", 0.0));
    OK(sinter_stepper_add_force(s.st, s.contact));
    sinter_force_callbacks cb;
    memset(&cb, 0, sizeof(cb));
    cb.struct_size = sizeof(cb);
    cb.particles = push_together;
    OK(sinter_force_model_create_host(&s.gravity, s.ctx, "push_together", &cb, &f));
    OK(sinter_stepper_add_force(s.st, s.gravity));
    sinter_heat_model *cond = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_stepper_add_heat(s.st, cond));
    scene_add(&s, 0.0, 0.0, 0.0, r);
    scene_add(&s, 2.0 * r - delta0, 0.0, 0.0, r);
    double *theta = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&theta, NULL, NULL));
    theta[0] = 400.0;
    theta[1] = 300.0;
    OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE));
    const double m = get1(&s, SINTER_FIELD_MASS, 0);
    const double omega = sqrt(2.0 * kn / m), h = wh / omega;
    /* The same end time for every step, omega t = 5 (50 steps of omega h = 0.1), where the
     * phase error shows fully in the overlap (|sin 5| = 0.96; near a whole period it would
     * vanish to first order and leave higher orders). */
    const int steps = (int)lround(5.0 / wh);
    OK(sinter_stepper_set_option(s.st, "scheme", 1));
    OK(sinter_stepper_set_option(s.st, "anderson_depth", depth));
    OK(sinter_stepper_set_option(s.st, "adaptive", 0));
    OK(sinter_stepper_set_option(s.st, "tolerance", tolerance));
    OK(sinter_stepper_set_option(s.st, "target_iterations", kd));
    OK(sinter_stepper_set_dt(s.st, h));
    OK(sinter_stepper_advance(s.st, steps * h));
    pair_result res;
    double x0[3], x1[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x0);
    get3(&s, SINTER_FIELD_POSITION, 1, x1);
    res.delta = 2.0 * r - (x1[0] - x0[0]);
    res.theta = get1(&s, SINTER_FIELD_TEMPERATURE, 0);
    const double ds = f / kn;
    res.delta_error = res.delta - (ds + (delta0 - ds) * cos(omega * steps * h));
    res.stats = stats_of(s.st);
    assert_int_equal(res.stats.steps, (uint64_t)steps);
    assert_int_equal(res.stats.rejected, 0);
    print_message("omega h %.4f, tolerance %g, Anderson(%d): %.2f evaluations/step, delta %.9e m, "
                  "theta %.9f K\n",
                  wh, tolerance, depth, (double)res.stats.iterations / steps, res.delta, res.theta);
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    return res;
}

static void test_second_order_on_a_smooth_problem(void **state)
{
    (void)state;
    /*
     * Halving h divides the error by 4 (the trapezoidal rule, phi = 0.5): the overlap's
     * against its closed form (a phase error omega t (omega h)^2 / 12, as in
     * test_staggered.c), the temperature's measured by the differences of successive halvings
     * (Richardson: e(h) - e(h/2) = 3/4 e(h) for a second-order error). The next order in
     * (omega h)^2 is below 0.2 %, and the iteration is converged far below the errors
     * (tolerance 1e-10 of a step's displacement and of the temperature; the accepted states'
     * residuals add up to < 1e-4 of the finest error; at omega h = 0.005 they no longer
     * would, and the ratio there reads 4.7): [3.6, 4.4].
     */
    const double wh[4] = {0.1, 0.05, 0.025, 0.0125};
    double ed[4], theta[4];
    for (int k = 0; k < 4; ++k) {
        const pair_result r = pair_run(wh[k], 1e-10, 3, 10);
        ed[k] = fabs(r.delta_error);
        theta[k] = r.theta;
    }
    const double dt[3] = {theta[0] - theta[1], theta[1] - theta[2], theta[2] - theta[3]};
    print_message("overlap error ratios %.4f, %.4f, %.4f; temperature difference ratios %.4f, "
                  "%.4f\n",
                  ed[0] / ed[1], ed[1] / ed[2], ed[2] / ed[3], dt[0] / dt[1], dt[1] / dt[2]);
    for (int k = 0; k < 3; ++k)
        assert_true(ed[k] / ed[k + 1] > 3.6 && ed[k] / ed[k + 1] < 4.4);
    for (int k = 0; k < 2; ++k)
        assert_true(dt[k] / dt[k + 1] > 3.6 && dt[k] / dt[k + 1] < 4.4);
}

static void test_anderson_needs_fewer_iterations(void **state)
{
    (void)state;
    /*
     * At omega h = 1 the plain iteration contracts the overlap's error by (phi omega h)^2 =
     * 1/4 per iteration (seed 000 sec. 3.1), and the temperatures by a small factor; from the
     * predictor's error (~ (omega h)^3 of the amplitude, 10^4-10^5 times the tolerance
     * 1e-8 of the displacement) to the tolerance it needs log(1e5)/log(4) ~ 8 iterations. The
     * map is affine in the one relative coordinate that moves (linear spring) plus the
     * temperatures, so Anderson(3), which on an affine map is GMRES on the residual (Walker
     * and Ni 2011, Theorem 2.2), reaches the tolerance in at most about 3 iterations
     * beyond the predictor: at most 4 evaluations per step, against at least 6 for the plain
     * iteration (one for the predictor plus > 5).
     */
    const pair_result plain = pair_run(1.0, 1e-8, 0, 50);
    const pair_result aa = pair_run(1.0, 1e-8, 3, 50);
    const double steps = (double)plain.stats.steps;
    const double per_plain = (double)plain.stats.iterations / steps;
    const double per_aa = (double)aa.stats.iterations / steps;
    print_message("evaluations per step: plain %.2f, Anderson(3) %.2f\n", per_plain, per_aa);
    assert_true(per_aa <= 4.0);
    assert_true(per_plain >= 6.0);
    /* Both solve the same implicit equation to 1e-8 of a step's motion. */
    assert_true(fabs(plain.delta - aa.delta) < 1e-6 * 1.5e-5);
    /* Temperatures: each accepted step is within the tolerance, 1e-8 x 400 K, of the fixed
     * point; over the 5 steps that is below 2e-5 K with margin for the
     * propagation: 5e-5 K. */
    assert_true(fabs(plain.theta - aa.theta) < 5e-5);
}

/* ---- a pile at rest, and restart ---------------------------------------------------------- */

static const char *PILE_SCENE =
    "[scene]\nname = pile\nunits = SI\n"
    "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\ndamping_ratio = 0.2\n"
    "friction_dynamic = 0.3\n"
    "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = 0 0 0.0005\n"
    "box_max = 0.004 0.004 0.003\nradius = 0.0005\nspacing = 0.00105\n"
    "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
    "[force hertz_mindlin]\n[force gravity]\n"
    "[output]\ninterval = 0.01\nvtu = no\ncsv = no\nplot = no\ncheckpoint_interval = 0\n"
    "[stepper]\nkind = staggered\ndt = 1e-4\nend_time = 1\ndt_max = 1e-3\n"
    "position_tolerance = 5e-9\n";

static sinter_scene *load_pile(sinter_ctx *ctx, const char *dir, int scheme)
{
    char path[512];
    snprintf(path, sizeof(path), "%s/pile.scene", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(PILE_SCENE, f);
    fprintf(f, "scheme = %d\n", scheme);
    fclose(f);
    sinter_scene *sc = NULL;
    OK(sinter_scene_load(&sc, ctx, path));
    remove(path);
    return sc;
}

static void test_no_cycling_on_a_pile_at_rest(void **state)
{
    (void)state;
    char dir[64];
    snprintf(dir, sizeof(dir), "/tmp/sinter_anderson_XXXXXX");
    assert_non_null(mkdtemp(dir));
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    double ratio[2] = {0, 0};
    for (int scheme = 0; scheme <= 1; ++scheme) {
        sinter_scene *sc = load_pile(ctx, dir, scheme);
        sinter_stepper *st = NULL;
        OK(sinter_scene_get_stepper(sc, &st));
        /* 48 spheres fall 0.5 mm onto the floor and onto each other and come to rest; then
         * 0.4 s at rest, counted. */
        OK(sinter_stepper_advance(st, 0.2));
        const sinter_stepper_stats a = stats_of(st);
        OK(sinter_stepper_advance(st, 0.6));
        const sinter_stepper_stats b = stats_of(st);
        const double steps = (double)(b.steps - a.steps),
                     rejected = (double)(b.rejected - a.rejected);
        ratio[scheme] = rejected / steps;
        print_message("scheme %d at rest: %.0f steps, %.0f rejected, %.2f evaluations per step, "
                      "last step %.3g s\n",
                      scheme, steps, rejected, (double)(b.evaluations - a.evaluations) / steps,
                      b.dt);
        sinter_scene_destroy(sc);
    }
    /*
     * The PI controller with its growth limits (step_control.h) does not cycle: a rejection
     * is followed by steps that do not grow, and the step settles where the iteration
     * converges. At most one attempt in ten is rejected (a cycling controller, as eq. 49 alone,
     * rejects about one in two or three: grow twofold, fail, cut).
     */
    assert_true(ratio[1] <= 0.1);
    sinter_ctx_destroy(ctx);
    rmdir(dir);
}

/* Positions, velocities and spins of a stepper's particles, for a bitwise comparison. */
static double *copy_state(sinter_scene *sc, size_t *n)
{
    sinter_particles *ps = NULL;
    OK(sinter_scene_get_particles(sc, &ps));
    OK(sinter_particles_count(ps, n));
    double *out = malloc(9 * *n * sizeof(double));
    assert_non_null(out);
    const sinter_field fields[3] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY,
                                    SINTER_FIELD_SPIN};
    for (int f = 0; f < 3; ++f) {
        const double *p = NULL;
        OK(sinter_particles_view_read(ps, fields[f], (const void **)&p, NULL, NULL));
        memcpy(out + 3 * (size_t)f * *n, p, 3 * *n * sizeof(double));
        OK(sinter_particles_release(ps, fields[f]));
    }
    return out;
}

static void test_restart_bit_for_bit(void **state)
{
    (void)state;
    char dir[64];
    snprintf(dir, sizeof(dir), "/tmp/sinter_anderson_XXXXXX");
    assert_non_null(mkdtemp(dir));
    char ckpt[512];
    snprintf(ckpt, sizeof(ckpt), "%s/c.bin", dir);
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    /* Straight: to 0.03 s (falling, impacts: the controller and predictor are busy), write a
     * checkpoint, on to 0.06 s. Restarted: a fresh scene reads the checkpoint and goes on to
     * 0.06 s. Everything must agree to the bit, step size and counts included. */
    sinter_scene *sc = load_pile(ctx, dir, 1);
    sinter_stepper *st = NULL;
    OK(sinter_scene_get_stepper(sc, &st));
    OK(sinter_stepper_advance(st, 0.03));
    OK(sinter_checkpoint_write(st, ckpt));
    OK(sinter_stepper_advance(st, 0.06));
    size_t n = 0, n2 = 0;
    double *straight = copy_state(sc, &n);
    const sinter_stepper_stats s1 = stats_of(st);
    sinter_scene_destroy(sc);
    sc = load_pile(ctx, dir, 1);
    OK(sinter_scene_get_stepper(sc, &st));
    OK(sinter_checkpoint_read(st, ckpt));
    OK(sinter_stepper_advance(st, 0.06));
    double *restarted = copy_state(sc, &n2);
    const sinter_stepper_stats s2 = stats_of(st);
    print_message("restart: %llu steps, %llu rejected, %llu iterations, dt %.6g s\n",
                  (unsigned long long)s1.steps, (unsigned long long)s1.rejected,
                  (unsigned long long)s1.iterations, s1.dt);
    assert_int_equal(n, n2);
    assert_memory_equal(straight, restarted, 9 * n * sizeof(double));
    assert_int_equal(s1.steps, s2.steps);
    assert_int_equal(s1.rejected, s2.rejected);
    assert_int_equal(s1.iterations, s2.iterations);
    assert_true(memcmp(&s1.dt, &s2.dt, sizeof(double)) == 0);
    free(straight);
    free(restarted);
    sinter_scene_destroy(sc);
    sinter_ctx_destroy(ctx);
    remove(ckpt);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_second_order_on_a_smooth_problem),
        cmocka_unit_test(test_anderson_needs_fewer_iterations),
        cmocka_unit_test(test_no_cycling_on_a_pile_at_rest),
        cmocka_unit_test(test_restart_bit_for_bit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
