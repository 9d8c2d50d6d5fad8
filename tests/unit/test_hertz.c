/*
 * Hertz-Mindlin contact and the explicit stepper against closed forms
 * (docs/validation.md: contact, friction, dynamics).
 */
#include <math.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;
static const double R = 1e-3, E = 1e7, NU = 0.3, RHO = 2500.0;

/* Observer that tracks the overlap of particles 0 and 1 and the contact's start and end. */
typedef struct collision {
    scene *s;
    double t_start, t_end;
    int in_contact;
} collision;

static int watch_collision(const sinter_stepper *st, double t, void *user)
{
    (void)st;
    collision *c = user;
    double a[3], b[3];
    get3(c->s, SINTER_FIELD_POSITION, 0, a);
    get3(c->s, SINTER_FIELD_POSITION, 1, b);
    const double d = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                          (a[2] - b[2]) * (a[2] - b[2]));
    const int touching = d < 2.0 * R;
    if (touching && !c->in_contact && c->t_start < 0)
        c->t_start = t;
    if (!touching && c->in_contact)
        c->t_end = t;
    c->in_contact = touching;
    return 0;
}

/* Head-on collision of two equal spheres at relative speed v; returns contact time and e. */
static void head_on(double xi, double v, double *duration, double *restitution, double *t_closed)
{
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, xi, 0.0);
    scene_open(&s, "hertz_mindlin", 0);
    scene_add(&s, -R - 1e-6, 0, 0, R);
    scene_add(&s, R + 1e-6, 0, 0, R);
    const double v0[3] = {0.5 * v, 0, 0}, v1[3] = {-0.5 * v, 0, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v0);
    set3(&s, SINTER_FIELD_VELOCITY, 1, v1);
    const double m = RHO * 4.0 / 3.0 * PI * R * R * R;
    const double mstar = 0.5 * m, rstar = 0.5 * R, estar = E / (2.0 * (1.0 - NU * NU));
    *t_closed = 2.87 * pow(mstar * mstar / (rstar * estar * estar * v), 0.2); /* seed 003 eq. 47 */
    OK(sinter_stepper_set_dt(s.st, *t_closed / 2000.0));
    collision c = {&s, -1.0, -1.0, 0};
    OK(sinter_stepper_set_observer(s.st, watch_collision, &c));
    OK(sinter_stepper_advance(s.st, 3.0 * *t_closed));
    double a[3], b[3];
    get3(&s, SINTER_FIELD_VELOCITY, 0, a);
    get3(&s, SINTER_FIELD_VELOCITY, 1, b);
    *duration = c.t_end - c.t_start;
    *restitution = (a[0] - b[0]) / -v;
    scene_close(&s);
}

static void test_head_on_contact_duration(void **state)
{
    (void)state;
    double duration, e, t_closed;
    head_on(0.0, 0.1, &duration, &e, &t_closed);
    /* The bound is 2 %; 2.87 is the closed form's constant to 3 digits (exactly
     * 2.868), and dt = t_c / 2000 resolves the start and end to 0.1 %. */
    print_message("contact time %.6e s, closed form %.6e s (ratio %.5f), e = %.6f\n", duration,
                  t_closed, duration / t_closed, e);
    assert_close(duration, t_closed, 0.02 * t_closed);
    assert_close(e, 1.0, 1e-3); /* undamped: elastic */
    /* The duration scales as v^(-1/5). */
    double duration2, e2, t_closed2;
    head_on(0.0, 3.2, &duration2, &e2, &t_closed2);
    assert_close(duration / duration2, pow(32.0, 0.2), 0.01 * pow(32.0, 0.2));
}

static void test_restitution_from_damping_ratio(void **state)
{
    (void)state;
    const double targets[3] = {0.9, 0.5, 0.2};
    for (int k = 0; k < 3; ++k) {
        double xi = 0.0;
        OK(sinter_damping_ratio_from_restitution(targets[k], &xi));
        double duration, e, t_closed;
        head_on(xi, 0.1, &duration, &e, &t_closed);
        /* Exact relation for this law (Antypov & Elliott 2011); the velocity-Verlet
         * half-step velocity in the damping term costs O(dt / t_c) = 5e-4. */
        print_message("xi = %.5f: e = %.5f (target %.2f)\n", xi, e, targets[k]);
        assert_close(e, targets[k], 5e-3);
        /* and the same e at another impact speed (velocity independence) */
        double e_fast;
        head_on(xi, 1.0, &duration, &e_fast, &t_closed);
        assert_close(e_fast, targets[k], 5e-3);
    }
    double xi;
    assert_int_equal(sinter_damping_ratio_from_restitution(0.0, &xi), SINTER_ERR_INVALID);
    assert_int_equal(sinter_damping_ratio_from_restitution(1.5, &xi), SINTER_ERR_INVALID);
}

static void test_sphere_at_rest_on_plane(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 1.0, 0.3);
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_YOUNGS_MODULUS, 1e13)); /* rigid floor */
    scene_open(&s, "hertz_mindlin", 1);
    scene_floor(&s, 0.0);
    scene_add(&s, 0, 0, R + 1e-6, R);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    OK(sinter_stepper_advance(s.st, 0.03));
    const double m = get1(&s, SINTER_FIELD_MASS, 0), w = m * 9.81;
    double f[3], x[3];
    OK(sinter_walls_get_force(s.walls, 0, f));
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    /* Critically damped: after 30 periods the residual motion is e^-100 of the start. */
    print_message("wall force %.10e N, weight %.10e N\n", -f[2], w);
    assert_close(-f[2], w, 1e-6 * w);
    assert_close(f[0], 0.0, 1e-12 * w);
    const double estar = 1.0 / ((1 - NU * NU) / E + (1 - NU * NU) / 1e13);
    const double delta = pow(3.0 * w / (4.0 * estar * sqrt(R)), 2.0 / 3.0);
    assert_close(R - x[2], delta, 1e-6 * delta);
    scene_close(&s);
}

static void test_sliding_sphere_starts_rolling_at_five_sevenths(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double mu = 0.3, v0 = 0.5;
    scene_material(&s, E, NU, RHO, 0.5, mu);
    OK(sinter_material_set(s.mat, SINTER_MAT_FRICTION_DAMPING_RATIO, 0.5));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_FRICTION_DAMPING_RATIO, 0.5));
    scene_open(&s, "hertz_mindlin", 1);
    scene_floor(&s, 0.0);
    scene_add(&s, 0, 0, R - 3.6e-7, R); /* near the static overlap */
    OK(sinter_stepper_set_dt(s.st, 2e-6));
    OK(sinter_stepper_advance(s.st, 2e-3)); /* settle */
    const double v[3] = {v0, 0, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v);
    const double t_roll = 2.0 * v0 / (7.0 * mu * 9.81);
    OK(sinter_stepper_advance(s.st, 2e-3 + 1.5 * t_roll));
    double vel[3], w[3];
    get3(&s, SINTER_FIELD_VELOCITY, 0, vel);
    get3(&s, SINTER_FIELD_SPIN, 0, w);
    /* 1 % as the issue asks; the contact point sits at L = r - delta, 4e-4 r lower. */
    print_message("rolling speed %.6f m/s, 5/7 v0 = %.6f m/s, w r = %.6f m/s\n", vel[0],
                  5.0 / 7.0 * v0, w[1] * R);
    assert_close(vel[0], 5.0 / 7.0 * v0, 0.01 * 5.0 / 7.0 * v0);
    assert_close(w[1] * R, vel[0], 0.01 * vel[0]); /* rolling without slip: v = w r */
    scene_close(&s);
}

/* Bouncing, undamped, frictionless: largest energy error over several bounces. */
static double bounce_energy_error(double dt)
{
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 0.0, 0.0);
    scene_open(&s, "hertz_mindlin", 1);
    scene_floor(&s, 0.0);
    scene_add(&s, 0, 0, 2 * R, R);
    OK(sinter_stepper_set_dt(s.st, dt));
    const double m = get1(&s, SINTER_FIELD_MASS, 0);
    const double estar = E / (2.0 * (1.0 - NU * NU)), k = 4.0 / 3.0 * estar * sqrt(R);
    double e0 = -1, worst = 0.0;
    for (int i = 0; i < 400; ++i) {
        OK(sinter_stepper_advance(s.st, (i + 1) * 1e-4));
        double x[3], v[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x);
        get3(&s, SINTER_FIELD_VELOCITY, 0, v);
        const double delta = fmax(R - x[2], 0.0);
        const double energy = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
                              m * 9.81 * x[2] + 0.4 * k * pow(delta, 2.5);
        if (e0 < 0)
            e0 = energy;
        worst = fmax(worst, fabs(energy - e0) / e0);
    }
    scene_close(&s);
    return worst;
}

static void test_energy_error_is_second_order(void **state)
{
    (void)state;
    const double coarse = bounce_energy_error(4e-6), fine = bounce_energy_error(2e-6);
    /* Velocity Verlet is symplectic: the energy error stays bounded (no drift) and
     * is O(dt^2), so halving dt divides it by ~4 (accept 3..5.5). */
    print_message("energy error %.3e (dt 4 us), %.3e (dt 2 us), ratio %.3f\n", coarse, fine,
                  coarse / fine);
    assert_true(coarse < 1e-3);
    assert_true(coarse / fine > 3.0 && coarse / fine < 5.5);
}

static void test_momentum_conserved_in_collisions(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 0.3, 0.5);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.1));
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_DAMPING_RATIO, 0.2));
    scene_open(&s, "hertz_mindlin", 0);
    /* A small cluster of unequal spheres with oblique, spinning impacts. */
    for (int k = 0; k < 8; ++k)
        scene_add(&s, (k % 2) * 2.1 * R, ((k / 2) % 2) * 2.1 * R, (k / 4) * 2.1 * R,
                  R * (0.8 + 0.05 * k));
    double p0[3] = {0, 0, 0};
    for (int k = 0; k < 8; ++k) {
        const double v[3] = {0.05 * sin(k), 0.05 * cos(3 * k), -0.04 * sin(2 * k + 1)};
        const double w[3] = {10.0 * k, -5.0, 3.0};
        set3(&s, SINTER_FIELD_VELOCITY, (size_t)k, v);
        set3(&s, SINTER_FIELD_SPIN, (size_t)k, w);
        const double m = get1(&s, SINTER_FIELD_MASS, (size_t)k);
        for (int d = 0; d < 3; ++d)
            p0[d] += m * v[d];
    }
    OK(sinter_stepper_set_dt(s.st, 2e-6));
    OK(sinter_stepper_advance(s.st, 0.01));
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    double p1[3] = {0, 0, 0}, scale = 0.0;
    for (int k = 0; k < 8; ++k) {
        double v[3];
        get3(&s, SINTER_FIELD_VELOCITY, (size_t)k, v);
        const double m = get1(&s, SINTER_FIELD_MASS, (size_t)k);
        for (int d = 0; d < 3; ++d) {
            p1[d] += m * v[d];
            scale += m * fabs(v[d]);
        }
    }
    /* Forces are applied pairwise equal and opposite: only round-off remains. */
    for (int d = 0; d < 3; ++d)
        assert_close(p1[d], p0[d], 1e-12 * scale);
    assert_true(stats.steps == 5000);
    scene_close(&s);
}

/*
 * Rolling resistance at its slider's limit (seed 003 eq. 15-17): a sphere resting on a fixed
 * equal sphere under gravity, spinning about the line of centres. The contact points do not
 * slide (w is along n), so only the rolling moment acts, at its limit mu_r r* |f_n| once the
 * rolling spring has loaded (within a few steps), with |f_n| = m g at the resting overlap:
 * the spin falls at the constant rate mu_r r* m g / I, I = 2/5 m R^2. The law of the pair
 * contacts (the blocked law with rolling) against that rate to 0.2 %, measured from 1 to 2 ms
 * (after the spring's loading; f_n = m g to the resting overlap's round-off, the spin's
 * integration exact for a constant moment); a limit with R instead of
 * r* = R/2 would be off by a factor 2.
 */
static void test_spin_decays_at_rolling_slider_limit(void **state)
{
    (void)state;
    const double mu_r = 0.1, g = 9.81, w0 = 5.0, t_end = 2e-3;
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 0.3, 0.5);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, mu_r));
    scene_open(&s, "hertz_mindlin", 1);
    const double m = 4.0 / 3.0 * PI * R * R * R * RHO, rstar = 0.5 * R;
    const double estar = E / (2.0 * (1.0 - NU * NU));
    /* resting overlap: m g = 4/3 E* sqrt(r* delta) delta (seed 003 eq. 2) */
    const double delta = pow(m * g / (4.0 / 3.0 * estar * sqrt(rstar)), 2.0 / 3.0);
    scene_add(&s, 0.0, 0.0, 0.0, R);
    scene_add(&s, 0.0, 0.0, 2.0 * R - delta, R);
    uint32_t *flags = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_FLAGS, (void **)&flags, NULL, NULL));
    flags[0] |= SINTER_PARTICLE_FIXED;
    OK(sinter_particles_release(s.ps, SINTER_FIELD_FLAGS));
    const double w[3] = {0.0, 0.0, w0};
    set3(&s, SINTER_FIELD_SPIN, 1, w);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    /* the rate from 1 ms on (the rolling spring loads within the first steps) */
    double wa[3], wb[3], x1[3];
    OK(sinter_stepper_advance(s.st, 0.5 * t_end));
    get3(&s, SINTER_FIELD_SPIN, 1, wa);
    OK(sinter_stepper_advance(s.st, t_end));
    get3(&s, SINTER_FIELD_SPIN, 1, wb);
    get3(&s, SINTER_FIELD_POSITION, 1, x1);
    const double rate = mu_r * rstar * m * g / (0.4 * m * R * R);
    const double measured = (wa[2] - wb[2]) / (0.5 * t_end);
    print_message("spin %.6f -> %.6f rad/s: rate %.2f rad/s^2, the limit's %.2f\n", wa[2], wb[2],
                  measured, rate);
    assert_true(wb[2] > 0.4 * w0); /* still spinning: the limit, not a stop */
    assert_close(measured, rate, 2e-3 * rate);
    assert_close(x1[2], 2.0 * R - delta, 1e-3 * delta); /* at rest on the other sphere */
    scene_close(&s);
}

/*
 * The damped normal force of eq. 2 may pull while a contact opens fast (seed 003 eq. 2 as
 * printed); "no_tension" = 1 clamps it at zero. Two equal spheres (overlap 2 um) and a
 * sphere on a floor (overlap 1 um, the wall's E* and r* = r, m* = m), each separating or
 * approaching at speed v: the force on particle 0 against f_n = 4/3 E* sqrt(r* delta) delta
 * + 2 xi sqrt(2 E*) sqrt(m*) (r* delta)^(1/4) delta_dot (eq. 2, 6) by hand.
 */
static void normal_forces(double no_tension, double v, double f_pair[3], double f_wall[3])
{
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 1.0, 0.0);
    scene_open(&s, "hertz_mindlin", 0);
    OK(sinter_force_model_set(s.contact, "no_tension", no_tension));
    scene_floor(&s, 0.0);
    scene_add(&s, 0.0, 0.0, 0.01, R); /* the pair, far above the floor */
    scene_add(&s, 2.0 * R - 2e-6, 0.0, 0.01, R);
    scene_add(&s, 0.01, 0.0, R - 1e-6, R); /* on the floor */
    const double v0[3] = {-0.5 * v, 0, 0}, v1[3] = {0.5 * v, 0, 0}, v2[3] = {0, 0, v};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v0);
    set3(&s, SINTER_FIELD_VELOCITY, 1, v1);
    set3(&s, SINTER_FIELD_VELOCITY, 2, v2);
    OK(sinter_stepper_set_dt(s.st, 1e-7));
    OK(sinter_stepper_evaluate(s.st));
    get3(&s, SINTER_FIELD_FORCE, 0, f_pair);
    get3(&s, SINTER_FIELD_FORCE, 2, f_wall);
    scene_close(&s);
}

static void test_normal_force_never_pulls(void **state)
{
    (void)state;
    const double m = RHO * 4.0 / 3.0 * PI * R * R * R, xi = 1.0;
    /* pair: E* = E / (2 (1 - nu^2)), r* = R/2, m* = m/2, overlap 2 um */
    const double es = E / (2.0 * (1.0 - NU * NU)), rs = 0.5 * R, ms = 0.5 * m, d = 2e-6;
    /* wall of the same material: the same E*, r* = R, m* = m, overlap 1 um */
    const double dw = 1e-6;
    for (int c = 0; c < 2; ++c) {
        const double v = c == 0 ? 0.5 : -0.5; /* separating, then approaching */
        const double fn_pair = 4.0 / 3.0 * es * sqrt(rs * d) * d -
                               2.0 * xi * sqrt(2.0 * es) * sqrt(ms * sqrt(rs * d)) * v;
        const double fn_wall = 4.0 / 3.0 * es * sqrt(R * dw) * dw -
                               2.0 * xi * sqrt(2.0 * es) * sqrt(m * sqrt(R * dw)) * v;
        double fp[3], fw[3], gp[3], gw[3];
        normal_forces(0.0, v, fp, fw);
        normal_forces(1.0, v, gp, gw);
        print_message("v = %+.1f m/s: f_n pair %.6e N (eq. 2), wall %.6e N; literal %.6e, "
                      "%.6e; no_tension %.6e, %.6e\n",
                      v, fn_pair, fn_wall, -fp[0], fw[2], -gp[0], gw[2]);
        /* eq. 2 literally: the force on 0 is -f_n n with n = +x; on the floor +f_n z */
        assert_close(-fp[0], fn_pair, 1e-9 * fabs(fn_pair));
        assert_close(fw[2], fn_wall, 1e-9 * fabs(fn_wall));
        if (c == 0) { /* opening fast: eq. 2 pulls, the option does not */
            assert_true(fn_pair < 0.0 && fn_wall < 0.0);
            assert_true(gp[0] == 0.0 && gp[1] == 0.0 && gp[2] == 0.0);
            assert_true(gw[0] == 0.0 && gw[1] == 0.0 && gw[2] == 0.0);
        } else { /* closing: the same bits */
            assert_true(fn_pair > 0.0 && fn_wall > 0.0);
            assert_memory_equal(fp, gp, sizeof(fp));
            assert_memory_equal(fw, gw, sizeof(fw));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_head_on_contact_duration),
        cmocka_unit_test(test_restitution_from_damping_ratio),
        cmocka_unit_test(test_sphere_at_rest_on_plane),
        cmocka_unit_test(test_sliding_sphere_starts_rolling_at_five_sevenths),
        cmocka_unit_test(test_energy_error_is_second_order),
        cmocka_unit_test(test_momentum_conserved_in_collisions),
        cmocka_unit_test(test_spin_decays_at_rolling_slider_limit),
        cmocka_unit_test(test_normal_force_never_pulls),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
