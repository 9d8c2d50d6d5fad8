/*
 * Periodic boundaries and their ghost images (issues 38 and 43): a cluster straddling a
 * periodic face moves as the same cluster away from it, a contact sliding across the face
 * keeps its tangential spring, and a periodic box conserves momentum.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sinter_submodel.h>

#include "periodic_cluster.h"

/* A compressed 3x3x3 cluster with random velocities, spins and temperatures, Hertz-Mindlin
 * with friction and rolling resistance and conduction, its first corner at x = x0; periodic
 * along x on [0, L) or not. */
static void cluster_scene(scene *s, sinter_heat_model **cond, double x0, int periodic)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.5);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 400.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_ROLLING_FRICTION, 0.1));
    scene_open(s, "hertz_mindlin", 0);
    OK(sinter_heat_model_create(cond, s->ctx, "conduction"));
    OK(sinter_stepper_add_heat(s->st, *cond));
    periodic_cluster_fill(s, x0, periodic, 2e-6);
}

/* The owned particles' positions, forces and temperatures. */
static void cluster_state(scene *s, double *x, double *f, double *temp)
{
    for (size_t i = 0; i < N; ++i) {
        get3(s, SINTER_FIELD_POSITION, i, x + 3 * i);
        get3(s, SINTER_FIELD_FORCE, i, f + 3 * i);
        temp[i] = get1(s, SINTER_FIELD_TEMPERATURE, i);
    }
}

/* The cluster after 100 steps (0.2 ms, while it is still compressed). */
static void run_cluster(double x0, int periodic, double *x, double *f, double *temp)
{
    scene s;
    sinter_heat_model *cond = NULL;
    cluster_scene(&s, &cond, x0, periodic);
    OK(sinter_stepper_step(s.st, 100));
    size_t owned = 0, count = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    OK(sinter_particles_count(s.ps, &count));
    assert_int_equal(owned, N);
    if (periodic)
        assert_true(count > owned); /* images were made: the cluster straddles the face */
    cluster_state(&s, x, f, temp);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
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
 * The test: the cluster straddling x = 0 of the periodic cell (x0 = -A: its first
 * layer of particles beyond the face, the rest inside) against the same cluster in open space
 * at x0 = 4 mm. Not bit for bit: the two runs hold the positions as different doubles (shifted
 * by 4 mm + A, or by L after the wrap), so each difference x_j - x_i rounds differently, by
 * about ulp(1e-2 m) = 2e-18 m a step. Over 100 steps such round-off grows to well under
 * 1e-15 m in positions; the tolerances (1e-13 m, 1e-9 relative in forces, 1e-9 K) leave room
 * for that and would catch any missing or doubled contact, whose force is ~0.1 N.
 */
static void test_straddling_cluster(void **state)
{
    (void)state;
    double xa[3 * N], fa[3 * N], ta[N], xb[3 * N], fb[3 * N], tb[N];
    run_cluster(-A, 1, xa, fa, ta);
    run_cluster(4e-3, 0, xb, fb, tb);
    double fmax = 0.0;
    for (int k = 0; k < 3 * N; ++k)
        fmax = fmax > fabs(fb[k]) ? fmax : fabs(fb[k]);
    assert_true(fmax > 1e-3); /* the cluster is in contact */
    for (int i = 0; i < N; ++i) {
        assert_true(xa[3 * i] >= 0.0 - 0.5 * R && xa[3 * i] < L + 0.5 * R); /* wrapped */
        assert_close(periodic_diff(xa[3 * i], xb[3 * i] - (4e-3 + A)), 0.0, 1e-13);
        for (int d = 1; d < 3; ++d)
            assert_close(xa[3 * i + d], xb[3 * i + d], 1e-13);
        for (int d = 0; d < 3; ++d)
            assert_close(fa[3 * i + d], fb[3 * i + d], 1e-9 * fmax);
        assert_close(ta[i], tb[i], 1e-9);
    }
}

/*
 * Two particles pressed together (2 % overlap), one held, the other driven along x at 0.5 m/s
 * across the face x = L of the periodic cell; friction high enough that the contact sticks,
 * so the tangential spring grows linearly with the slip. Its force must follow the same run
 * far from the face step by step (to round-off, as above): a spring lost at the wrap would
 * drop to zero.
 */
static double slide(int periodic, double x0, double *fx_out, int steps)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.0, 100.0);
    scene_open(&s, "hertz_mindlin", 0);
    if (periodic)
        OK(sinter_stepper_set_periodic(s.st, 0, 0.0, L));
    const double pi[3] = {x0, 0.0, 0.0}, pj[3] = {x0, 2 * R * 0.98, 0.0};
    OK(sinter_particles_add(s.ps, 1, pi, &R, 0, 300.0, NULL));
    OK(sinter_particles_add(s.ps, 1, pj, &R, 0, 300.0, NULL));
    uint32_t *flags = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_FLAGS, (void **)&flags, NULL, NULL));
    flags[0] = flags[1] = SINTER_PARTICLE_FIXED;
    OK(sinter_particles_release(s.ps, SINTER_FIELD_FLAGS));
    const double u[3] = {0.5, 0.0, 0.0};
    set3(&s, SINTER_FIELD_VELOCITY, 1, u);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    for (int k = 0; k < steps; ++k) {
        OK(sinter_stepper_step(s.st, 1));
        double f[3];
        get3(&s, SINTER_FIELD_FORCE, 0, f);
        fx_out[k] = f[0];
    }
    /* one evaluation a step and the first: the images made at a build do not count as new
     * particles (which would make each call evaluate the forces again) */
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    assert_int_equal(stats.evaluations, (uint64_t)steps + 1);
    double xj[3];
    get3(&s, SINTER_FIELD_POSITION, 1, xj);
    scene_close(&s);
    return xj[0];
}

static void test_sliding_across_face(void **state)
{
    (void)state;
    enum { STEPS = 600 }; /* (the contact opens at a slip of 0.39 mm) */
    static double fa[STEPS], fb[STEPS];
    const double start = L - 0.1 * R;              /* 0.1 mm before the face */
    const double end = slide(1, start, fa, STEPS); /* moves 0.3 mm: crosses at step 200 */
    (void)slide(0, 5e-3, fb, STEPS);
    assert_true(end < 0.5 * L); /* particle 1 crossed the face and was wrapped */
    double fmax = 0.0;
    for (int k = 0; k < STEPS; ++k)
        fmax = fmax > fabs(fb[k]) ? fmax : fabs(fb[k]);
    assert_true(fmax > 1e-4);                      /* the spring did grow */
    assert_true(fabs(fb[STEPS - 1]) > 0.9 * fmax); /* and holds after the wrap */
    for (int k = 0; k < STEPS; ++k)
        assert_close(fa[k], fb[k], 1e-9 * fmax);
}

/*
 * A gas of 60 frictional, damped spheres in a box periodic along x, y and z (no walls, no
 * gravity): every contact, across a face or not, acts on both particles with equal and
 * opposite forces, so the total momentum stays at its start to round-off (the pair forces,
 * ~0.1 N at most, against m v ~ 1e-6 kg m/s; 1e-12 of sum m |v| allows for the summation).
 */
static void test_momentum_periodic_box(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.5);
    scene_open(&s, "hertz_mindlin", 0);
    const double box = 10e-3;
    for (int d = 0; d < 3; ++d)
        OK(sinter_stepper_set_periodic(s.st, d, 0.0, box));
    uint64_t seed = 3;
    enum { M = 60 };
    for (int k = 0; k < M; ++k) {
        const double p[3] = {box * (k % 4) / 4.0 + 0.3e-3 * lcg(&seed),
                             box * ((k / 4) % 4) / 4.0 + 0.3e-3 * lcg(&seed),
                             box * (k / 16) / 4.0 + 0.3e-3 * lcg(&seed)};
        OK(sinter_particles_add(s.ps, 1, p, &R, 0, 300.0, NULL));
    }
    double *v = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    for (int k = 0; k < 3 * M; ++k)
        v[k] = 0.5 * (lcg(&seed) - 0.5);
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    double p0[3] = {0}, scale = 0.0, p1[3] = {0}, v0[3 * M];
    const double m = get1(&s, SINTER_FIELD_MASS, 0);
    for (int k = 0; k < M; ++k) {
        double *vk = v0 + 3 * k;
        get3(&s, SINTER_FIELD_VELOCITY, (size_t)k, vk);
        for (int d = 0; d < 3; ++d) {
            p0[d] += m * vk[d];
            scale += m * fabs(vk[d]);
        }
    }
    OK(sinter_stepper_set_dt(s.st, 2e-6));
    if (sinter_stepper_step(s.st, 5000) != SINTER_OK)
        fail_msg("%s", sinter_last_error(s.ctx));
    size_t owned = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    assert_int_equal(owned, M);
    double changed = 0.0; /* collisions changed the velocities: the test is not empty */
    for (int k = 0; k < M; ++k) {
        double vk[3], xk[3];
        get3(&s, SINTER_FIELD_VELOCITY, (size_t)k, vk);
        get3(&s, SINTER_FIELD_POSITION, (size_t)k, xk);
        for (int d = 0; d < 3; ++d) {
            changed = fmax(changed, fabs(vk[d] - v0[3 * k + d]));
            p1[d] += m * vk[d];
            assert_true(xk[d] > -R && xk[d] < box + R); /* kept in the cell */
        }
    }
    assert_true(changed > 0.05);
    for (int d = 0; d < 3; ++d)
        assert_close(p1[d], p0[d], 1e-12 * scale);
    scene_close(&s);
}

/* A checkpoint carries the periodic cell and the ghosts: the straddling cluster restarted
 * after 60 steps in a stepper set up without the periodic axis continues bit for bit. */
static void test_periodic_restart(void **state)
{
    (void)state;
    const char *path = "test_periodic.ckpt";
    double xa[3 * N], fa[3 * N], ta[N], xb[3 * N], fb[3 * N], tb[N];
    scene s;
    sinter_heat_model *cond = NULL;
    cluster_scene(&s, &cond, -A, 1);
    OK(sinter_stepper_step(s.st, 60));
    OK(sinter_checkpoint_write(s.st, path));
    OK(sinter_stepper_step(s.st, 40));
    cluster_state(&s, xa, fa, ta);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    cluster_scene(&s, &cond, -A, 0);
    OK(sinter_checkpoint_read(s.st, path));
    int on = 0;
    OK(sinter_stepper_get_periodic(s.st, 0, &on, NULL, NULL));
    assert_int_equal(on, 1);
    OK(sinter_stepper_step(s.st, 40));
    cluster_state(&s, xb, fb, tb);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
    remove(path);
    assert_memory_equal(xa, xb, sizeof(xa));
    assert_memory_equal(fa, fb, sizeof(fa));
    assert_memory_equal(ta, tb, sizeof(ta));
}

/* A host body force (none) that fails while *user is set: the step is rejected. */
static int poisoned(const sinter_state_view *state, double *force, double *torque, void *user)
{
    (void)state;
    (void)force;
    (void)torque;
    return *(const int *)user ? -1 : 0;
}

/* The straddling cluster (x0 = -A, periodic) or the open one, 60 steps with a host body force
 * (after the contact law: it must not touch what the pairs put on the images), then a step in
 * which that model fails (rejected: the last accepted state kept), then 40 more steps. */
static void run_rollback(double x0, int periodic, double *x, double *f, double *temp)
{
    scene s;
    sinter_heat_model *cond = NULL;
    cluster_scene(&s, &cond, x0, periodic);
    int poison = 0;
    sinter_force_callbacks cb;
    memset(&cb, 0, sizeof(cb));
    cb.struct_size = sizeof(cb);
    cb.particles = poisoned;
    sinter_force_model *host = NULL;
    OK(sinter_force_model_create_host(&host, s.ctx, "poisoned", &cb, &poison));
    OK(sinter_stepper_add_force(s.st, host));
    OK(sinter_stepper_step(s.st, 60));
    poison = 1;
    assert_int_not_equal(sinter_stepper_step(s.st, 1), SINTER_OK);
    poison = 0;
    OK(sinter_stepper_step(s.st, 40));
    cluster_state(&s, x, f, temp);
    sinter_stepper_destroy(s.st); /* (it holds the model) */
    s.st = NULL;
    sinter_force_model_destroy(host);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
}

/* A rejected step across a periodic face is undone as one in open space: the two runs of
 * run_rollback agree to round-off (the tolerances of the straddling test). */
static void test_periodic_rollback(void **state)
{
    (void)state;
    double xa[3 * N], fa[3 * N], ta[N], xb[3 * N], fb[3 * N], tb[N];
    run_rollback(-A, 1, xa, fa, ta);
    run_rollback(4e-3, 0, xb, fb, tb);
    double fmax = 0.0;
    for (int k = 0; k < 3 * N; ++k)
        fmax = fmax > fabs(fb[k]) ? fmax : fabs(fb[k]);
    for (int i = 0; i < N; ++i) {
        assert_close(periodic_diff(xa[3 * i], xb[3 * i] - (4e-3 + A)), 0.0, 1e-13);
        for (int d = 1; d < 3; ++d)
            assert_close(xa[3 * i + d], xb[3 * i + d], 1e-13);
        for (int d = 0; d < 3; ++d)
            assert_close(fa[3 * i + d], fb[3 * i + d], 1e-9 * fmax);
        assert_close(ta[i], tb[i], 1e-9);
    }
}

/* A lattice of 12^3 spheres in a box periodic along x, y and z with random velocities, 40
 * steps on `threads` threads: positions and forces of the owned particles out. */
static void run_box_threads(int threads, double *x, double *f)
{
    enum { M = 12 };
    scene s;
    sinter_heat_model *cond = NULL;
    scene_init(&s);
    OK(sinter_ctx_set_threads(s.ctx, threads));
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.5);
    OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, 400.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.1));
    scene_open(&s, "hertz_mindlin", 0);
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_stepper_add_heat(s.st, cond));
    for (int d = 0; d < 3; ++d)
        OK(sinter_stepper_set_periodic(s.st, d, 0.0, M * A));
    uint64_t seed = 7;
    for (int k = 0; k < M * M * M; ++k) {
        const double p[3] = {A * (0.5 + k % M), A * (0.5 + (k / M) % M), A * (0.5 + k / (M * M))};
        OK(sinter_particles_add(s.ps, 1, p, &R, 0, 300.0 + 100.0 * lcg(&seed), NULL));
    }
    double *v = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    for (int k = 0; k < 3 * M * M * M; ++k)
        v[k] = 0.2 * (lcg(&seed) - 0.5);
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    OK(sinter_stepper_set_dt(s.st, 2e-6));
    OK(sinter_stepper_step(s.st, 40));
    const double *xs = NULL, *fs = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&xs, NULL, NULL));
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_FORCE, (const void **)&fs, NULL, NULL));
    memcpy(x, xs, 3 * M * M * M * sizeof(double));
    memcpy(f, fs, 3 * M * M * M * sizeof(double));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_FORCE));
    sinter_heat_model_destroy(cond);
    scene_close(&s);
}

/* The library's promise holds across periodic faces too: the same bits on 1 and 2 threads
 * (the ghost stages run serially in ghost order; the laws sum as without ghosts). */
static void test_periodic_threads(void **state)
{
    (void)state;
    enum { B = 3 * 12 * 12 * 12 };
    static double x1[B], f1[B], x2[B], f2[B];
    run_box_threads(1, x1, f1);
    run_box_threads(2, x2, f2);
    assert_memory_equal(x1, x2, sizeof(x1));
    assert_memory_equal(f1, f2, sizeof(f1));
}

/* Misuse: periodic on a stepper that does not support it, a bad axis or cell, a period
 * shorter than twice the ghost cut-off. */
static void test_periodic_refusals(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.5);
    scene_open(&s, "hertz_mindlin", 0);
    assert_int_equal(sinter_stepper_set_periodic(s.st, 3, 0.0, 1.0), SINTER_ERR_RANGE);
    assert_int_equal(sinter_stepper_set_periodic(s.st, 0, 1.0, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_periodic(s.st, 0, 0.0, NAN), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_periodic(s.st, 0, 0.0, 3e-3)); /* < 2 (2 R + skin) */
    int on = 0;
    double lo = 1, hi = 0;
    OK(sinter_stepper_get_periodic(s.st, 0, &on, &lo, &hi));
    assert_int_equal(on, 1);
    assert_true(lo == 0.0 && hi == 3e-3);
    scene_add(&s, 1e-3, 0, 0, R);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    assert_int_equal(sinter_stepper_step(s.st, 1), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_periodic(s.st, 0, 0.0, 0.0)); /* off again */
    OK(sinter_stepper_get_periodic(s.st, 0, &on, NULL, NULL));
    assert_int_equal(on, 0);
    OK(sinter_stepper_step(s.st, 1));
    sinter_stepper *quasistatic = NULL;
    OK(sinter_stepper_create(&quasistatic, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, s.walls));
    OK(sinter_stepper_set_periodic(quasistatic, 1, 0.0, 1.0)); /* its own cell (test_qs_periodic) */
    sinter_stepper_destroy(quasistatic);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straddling_cluster),    cmocka_unit_test(test_sliding_across_face),
        cmocka_unit_test(test_momentum_periodic_box), cmocka_unit_test(test_periodic_restart),
        cmocka_unit_test(test_periodic_threads),      cmocka_unit_test(test_periodic_rollback),
        cmocka_unit_test(test_periodic_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
