/*
 * Periodic boundaries with the implicit staggered stepper (issue 38): a cluster straddling a
 * periodic face iterates to the same steps as the same cluster away from it (both schemes,
 * rejected attempts included), and a checkpoint restarts it bit for bit.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sinter_submodel.h>

#include "periodic_cluster.h"

/*
 * A compressed 3x3x3 cluster with random velocities, spins and temperatures (300-400 K),
 * Hertz-Mindlin with friction and conduction, on the staggered stepper (`scheme` 0 or 1,
 * first step dt), its first corner at x = x0; periodic along x on [0, L) or not.
 */
static void cluster(scene *s, sinter_heat_model **cond, double x0, int periodic, int scheme,
                    double dt)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.5);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 400.0));
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_walls_create(&s->walls, s->ctx));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_STAGGERED, s->ps, s->walls));
    OK(sinter_stepper_set_option(s->st, "scheme", scheme));
    OK(sinter_force_model_create(&s->contact, s->ctx, "hertz_mindlin"));
    OK(sinter_stepper_add_force(s->st, s->contact));
    OK(sinter_heat_model_create(cond, s->ctx, "conduction"));
    OK(sinter_stepper_add_heat(s->st, *cond));
    periodic_cluster_fill(s, x0, periodic, dt);
}

static void cluster_close(scene *s, sinter_heat_model *cond)
{
    sinter_stepper_destroy(s->st);
    s->st = NULL;
    sinter_heat_model_destroy(cond);
    scene_close(s);
}

/* The owned particles' positions, velocities and temperatures. */
static void cluster_state(scene *s, double *x, double *v, double *temp)
{
    for (size_t i = 0; i < N; ++i) {
        get3(s, SINTER_FIELD_POSITION, i, x + 3 * i);
        get3(s, SINTER_FIELD_VELOCITY, i, v + 3 * i);
        temp[i] = get1(s, SINTER_FIELD_TEMPERATURE, i);
    }
}

/* Run to t_end; the state, the time reached and the stepper's statistics out. */
static void run(double x0, int periodic, int scheme, double dt, double t_end, double *x, double *v,
                double *temp, sinter_stepper_stats *stats)
{
    scene s;
    sinter_heat_model *cond = NULL;
    cluster(&s, &cond, x0, periodic, scheme, dt);
    if (sinter_stepper_advance(s.st, t_end) != SINTER_OK)
        fail_msg("%s", sinter_last_error(s.ctx));
    size_t owned = 0, count = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    OK(sinter_particles_count(s.ps, &count));
    assert_int_equal(owned, N);
    if (periodic)
        assert_true(count > owned); /* images were made: the cluster straddles the face */
    cluster_state(&s, x, v, temp);
    stats->struct_size = sizeof(*stats);
    OK(sinter_stepper_get_stats(s.st, stats));
    cluster_close(&s, cond);
}

/* The difference of two x coordinates modulo L, in [-L/2, L/2). */
static double periodic_diff(double a, double b)
{
    double d = fmod(a - b, L);
    if (d >= 0.5 * L)
        d -= L;
    if (d < -0.5 * L)
        d += L;
    return d;
}

/*
 * The test on the staggered stepper: the cluster straddling x = 0 (x0 = -A) against
 * the same cluster at x0 = 4 mm, over 0.2 ms. The first step (below) is too long for the
 * iteration to converge on these contacts (Hertz's collision time of these spheres at
 * 0.05 m/s is ~24 us), so attempts are rejected and restored before the controller finds its
 * step: the restore of the owners and their images is in the comparison. Both runs must take the
 * same steps (the same counts of steps, rejections and iterations) and agree to round-off:
 * positions to 1e-13 m, velocities to `vtol` and temperatures to 1e-9 K (the positions
 * differ by ~ulp(1e-2 m) = 2e-18 m a step as in test_periodic.c; each implicit step solves to
 * the iteration's tolerance, but the same iterations from states a round-off apart give
 * iterates a round-off apart). vtol: 1e-10 m/s for the seed's plain iteration (measured
 * 1.4e-12); 1e-7 m/s with Anderson acceleration, whose least-squares fit over differences of
 * residuals that are themselves near the tolerance amplifies round-off (measured 4.4e-9 m/s
 * on speeds ~0.25 m/s; with anderson_depth 0 the 1e-10 bound holds). Images left with a
 * stale state (no forward halo before an evaluation) change the step counts themselves.
 * First steps: 20 us for the seed's scheme, 100 us for Anderson's, so that both reject.
 */
static void straddle(int scheme, double dt, double vtol)
{
    double xa[3 * N], va[3 * N], ta[N], xb[3 * N], vb[3 * N], tb[N];
    sinter_stepper_stats sa, sb;
    run(-A, 1, scheme, dt, 2e-4, xa, va, ta, &sa);
    run(4e-3, 0, scheme, dt, 2e-4, xb, vb, tb, &sb);
    assert_true(sb.rejected > 0); /* the restore was exercised */
    assert_int_equal(sa.steps, sb.steps);
    assert_int_equal(sa.rejected, sb.rejected);
    assert_int_equal(sa.iterations, sb.iterations);
    for (int i = 0; i < N; ++i) {
        assert_true(xa[3 * i] >= -0.5 * R && xa[3 * i] < L + 0.5 * R); /* in the cell */
        assert_close(periodic_diff(xa[3 * i], xb[3 * i] - (4e-3 + A)), 0.0, 1e-13);
        for (int d = 1; d < 3; ++d)
            assert_close(xa[3 * i + d], xb[3 * i + d], 1e-13);
        for (int d = 0; d < 3; ++d)
            assert_close(va[3 * i + d], vb[3 * i + d], vtol);
        assert_close(ta[i], tb[i], 1e-9);
    }
}

static void test_staggered_straddling_seed_scheme(void **state)
{
    (void)state;
    straddle(0, 2e-5, 1e-10);
}

static void test_staggered_straddling_anderson(void **state)
{
    (void)state;
    straddle(1, 1e-4, 1e-7);
}

/* A checkpoint of the straddling cluster after 0.1 ms (the predictor's history, kept for the
 * owned particles, and the images with it), read into a stepper set up without the periodic
 * axis: 0.1 ms more continue bit for bit. */
static void test_staggered_periodic_restart(void **state)
{
    (void)state;
    const char *path = "test_periodic_staggered.ckpt";
    double xa[3 * N], va[3 * N], ta[N], xb[3 * N], vb[3 * N], tb[N];
    scene s;
    sinter_heat_model *cond = NULL;
    cluster(&s, &cond, -A, 1, 1, 2e-6);
    OK(sinter_stepper_advance(s.st, 1e-4));
    OK(sinter_checkpoint_write(s.st, path));
    OK(sinter_stepper_advance(s.st, 2e-4));
    cluster_state(&s, xa, va, ta);
    cluster_close(&s, cond);
    cluster(&s, &cond, -A, 0, 1, 2e-6);
    OK(sinter_checkpoint_read(s.st, path));
    int on = 0;
    OK(sinter_stepper_get_periodic(s.st, 0, &on, NULL, NULL));
    assert_int_equal(on, 1);
    OK(sinter_stepper_advance(s.st, 2e-4));
    cluster_state(&s, xb, vb, tb);
    cluster_close(&s, cond);
    remove(path);
    assert_memory_equal(xa, xb, sizeof(xa));
    assert_memory_equal(va, vb, sizeof(va));
    assert_memory_equal(ta, tb, sizeof(ta));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_staggered_straddling_seed_scheme),
        cmocka_unit_test(test_staggered_straddling_anderson),
        cmocka_unit_test(test_staggered_periodic_restart),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
