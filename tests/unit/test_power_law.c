/*
 * Seed 000's force submodels ("power_law", "drag") against values computed by hand from the
 * seed's equations: contact (eq. 2-4, 11-12), friction (eq. 5-6), wall contact (eq. 13-17),
 * bonds (eq. 18-19) and drag (eq. 20).
 *
 * Tolerances: the library and the test evaluate the same closed forms from the same positions,
 * so they differ by round-off only. The worst amplification is in |E| = (d - S) / S and in
 * A = pi (R^2 - L^2), where a cancellation loses about a factor 1 / |E| <= 50: relative errors
 * stay below ~1e-14, and 1e-12 leaves a wide margin while catching any wrong factor.
 */
#include <math.h>
#include <string.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;
static const double REL = 1e-12;

static double norm3(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Pair geometry by hand: n (eq. 4), |E| (eq. 3), L_i (eq. 12), A (eq. 11). */
typedef struct pair_geometry {
    double n[3], d, strain, li, area;
} pair_geometry;

static pair_geometry geometry(scene *s, double ri, double rj)
{
    double xi[3], xj[3];
    get3(s, SINTER_FIELD_POSITION, 0, xi);
    get3(s, SINTER_FIELD_POSITION, 1, xj);
    pair_geometry g;
    const double e[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    g.d = norm3(e);
    for (int k = 0; k < 3; ++k)
        g.n[k] = e[k] / g.d;
    g.strain = fabs((g.d - (ri + rj)) / (ri + rj));
    g.li = 0.5 * (g.d - (rj * rj - ri * ri) / g.d);
    g.area = PI * (ri * ri - g.li * g.li);
    return g;
}

static void assert_vec_close(const double a[3], const double b[3], double tol)
{
    for (int k = 0; k < 3; ++k)
        assert_close(a[k], b[k], tol);
}

/* Two particles at rest (no friction acts), radii 1 mm and 0.6 mm on an oblique line. */
static void check_pair_contact(double exponent, double overlap_fraction)
{
    scene s;
    scene_init(&s);
    const double ri = 1e-3, rj = 0.6e-3, kp = 3e7;
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, 0.3);
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_STIFFNESS, kp));
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_EXPONENT, exponent));
    scene_open(&s, "power_law", 0);
    const double d = (1.0 - overlap_fraction) * (ri + rj);
    scene_add(&s, 1e-4, -2e-4, 3e-4, ri);
    scene_add(&s, 1e-4 + d / 3.0, -2e-4 + 2.0 * d / 3.0, 3e-4 + 2.0 * d / 3.0, rj);
    OK(sinter_stepper_evaluate(s.st));
    const pair_geometry g = geometry(&s, ri, rj);
    const double mag = kp * pow(g.strain, exponent) * g.area; /* eq. 2 */
    double f0[3], f1[3], t0[3], t1[3];
    get3(&s, SINTER_FIELD_FORCE, 0, f0);
    get3(&s, SINTER_FIELD_FORCE, 1, f1);
    get3(&s, SINTER_FIELD_TORQUE, 0, t0);
    get3(&s, SINTER_FIELD_TORQUE, 1, t1);
    const double expect[3] = {-mag * g.n[0], -mag * g.n[1], -mag * g.n[2]};
    const double minus[3] = {mag * g.n[0], mag * g.n[1], mag * g.n[2]};
    print_message("p = %g, |E| = %.4f: |f| = %.12e N, by hand %.12e N\n", exponent, g.strain,
                  norm3(f0), mag);
    assert_vec_close(f0, expect, REL * mag);
    assert_vec_close(f1, minus, REL * mag); /* action = reaction */
    /* Central force: the moments L n x f vanish up to the rounding of the cross product. */
    const double zero[3] = {0, 0, 0};
    assert_vec_close(t0, zero, 1e-14 * ri * mag);
    assert_vec_close(t1, zero, 1e-14 * ri * mag);
    scene_close(&s);
}

static void test_pair_contact_force(void **state)
{
    (void)state;
    check_pair_contact(1.0, 0.05);
    check_pair_contact(2.0, 0.05);
    /* |E| = 0.12 is past the default E* = 0.1, but K_b = 0 (default) leaves no bond force. */
    check_pair_contact(2.0, 0.12);
    check_pair_contact(1.5, 0.02);
    /* the law's products for whole and half exponents, pow for the others (power_law.c) */
    check_pair_contact(3.0, 0.04);
    check_pair_contact(2.3, 0.04);
}

static void test_pair_friction(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double r = 1e-3, kp = 1e7, mu = 0.4;
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, mu);
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_EXPONENT, 2.0));
    scene_open(&s, "power_law", 0);
    scene_add(&s, 0, 0, 0, r);
    scene_add(&s, 1.9e-3, 0, 0, r); /* |E| = 0.05 along x */
    const double v0[3] = {0.0, 0.1, 0.05}, v1[3] = {0.02, -0.1, 0.0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v0);
    set3(&s, SINTER_FIELD_VELOCITY, 1, v1);
    OK(sinter_stepper_evaluate(s.st));
    const pair_geometry g = geometry(&s, r, r);
    const double fcon = kp * g.strain * g.strain * g.area; /* eq. 2 */
    /* Relative velocity (0 - 1) and its tangential part (the normal is x). */
    const double ut[3] = {0.0, v0[1] - v1[1], v0[2] - v1[2]};
    const double ut_len = norm3(ut);
    double f[3]; /* expected force on 0: eq. 2 plus eq. 5-6 */
    for (int k = 0; k < 3; ++k)
        f[k] = -fcon * g.n[k] - mu * fcon * ut[k] / ut_len;
    double f0[3], f1[3], t0[3], t1[3];
    get3(&s, SINTER_FIELD_FORCE, 0, f0);
    get3(&s, SINTER_FIELD_FORCE, 1, f1);
    get3(&s, SINTER_FIELD_TORQUE, 0, t0);
    get3(&s, SINTER_FIELD_TORQUE, 1, t1);
    const double ft[3] = {0.0, f0[1], f0[2]};
    print_message("friction %.12e N = mu |f_con| %.12e N\n", norm3(ft), mu * fcon);
    assert_vec_close(f0, f, REL * fcon);
    for (int k = 0; k < 3; ++k)
        assert_close(f1[k], -f[k], REL * fcon);
    /* Moments about the centres: b_0 = L_0 n, b_1 = -(d - L_0) n (eq. 12: L_0 = d / 2). */
    const double b0[3] = {g.li * g.n[0], g.li * g.n[1], g.li * g.n[2]};
    const double b1[3] = {-(g.d - g.li) * g.n[0], -(g.d - g.li) * g.n[1], -(g.d - g.li) * g.n[2]};
    const double fm[3] = {-f[0], -f[1], -f[2]};
    double e0[3], e1[3];
    cross3(b0, f, e0);
    cross3(b1, fm, e1);
    print_message("torque on 0 %.12e N m, r x f %.12e N m\n", norm3(t0), norm3(e0));
    assert_vec_close(t0, e0, REL * r * fcon);
    assert_vec_close(t1, e1, REL * r * fcon);

    /* Spin 0 so that its contact point moves with particle 1's: no sliding, no friction. */
    const double w0[3] = {0.0, ut[2] / g.li, -ut[1] / g.li}; /* w x (L n) = -u_t */
    set3(&s, SINTER_FIELD_SPIN, 0, w0);
    OK(sinter_stepper_evaluate(s.st));
    get3(&s, SINTER_FIELD_FORCE, 0, f0);
    get3(&s, SINTER_FIELD_TORQUE, 0, t0);
    const double normal_only[3] = {-fcon * g.n[0], -fcon * g.n[1], -fcon * g.n[2]};
    assert_vec_close(f0, normal_only, REL * fcon);
    const double zero[3] = {0, 0, 0};
    assert_vec_close(t0, zero, 1e-14 * r * fcon);
    scene_close(&s);
}

static void test_wall_contact_and_reaction(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double r = 1e-3, mu_p = 0.2, mu_w = 0.4;
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, mu_p);
    OK(sinter_material_set(s.mat, SINTER_MAT_WALL_STIFFNESS, 2e7));
    OK(sinter_material_set(s.mat, SINTER_MAT_WALL_EXPONENT, 2.0));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_WALL_STIFFNESS, 1e7));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_WALL_EXPONENT, 1.0));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_FRICTION_DYNAMIC, mu_w));
    scene_open(&s, "power_law", 0);
    scene_floor(&s, 0.0);
    const double u_wall[3] = {0.0, 0.05, 0.0};
    OK(sinter_walls_set_velocity(s.walls, 0, u_wall));
    scene_add(&s, 2e-4, -1e-4, 0.97e-3, r);
    const double v[3] = {0.1, 0.0, -0.01};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v);
    OK(sinter_stepper_evaluate(s.st));
    double x[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    /* Pair values: arithmetic means K_w = 1.5e7 Pa, p_w = 1.5; friction the geometric mean. */
    const double kw = 1.5e7, pw = 1.5, mu = sqrt(mu_p * mu_w);
    const double strain = fabs((x[2] - r) / r);      /* eq. 14 */
    const double area = PI * (r * r - x[2] * x[2]);  /* eq. 11 with L_i = plane distance */
    const double fcon = kw * pow(strain, pw) * area; /* eq. 13, away from the wall (+z) */
    const double ut[3] = {v[0] - u_wall[0], v[1] - u_wall[1], 0.0}; /* tangential, eq. 17 */
    const double ut_len = norm3(ut);
    double f[3];
    for (int k = 0; k < 3; ++k)
        f[k] = -mu * fcon * ut[k] / ut_len; /* eq. 16 */
    f[2] += fcon;
    double f0[3], t0[3], fw[3];
    get3(&s, SINTER_FIELD_FORCE, 0, f0);
    get3(&s, SINTER_FIELD_TORQUE, 0, t0);
    OK(sinter_walls_get_force(s.walls, 0, fw));
    print_message("wall: f_con %.12e N (by hand %.12e N), reaction z %.12e N\n", f0[2], fcon,
                  fw[2]);
    assert_vec_close(f0, f, REL * fcon);
    for (int k = 0; k < 3; ++k)
        assert_close(fw[k], -f0[k], 1e-15 * fcon); /* the same numbers, negated */
    const double b[3] = {0.0, 0.0, -x[2]};         /* from the centre to the contact plane */
    double e[3];
    cross3(b, f, e);
    assert_vec_close(t0, e, REL * r * fcon);
    scene_close(&s);
}

/* Bond scene: equal spheres (r = 1 mm) on the x axis, K_p = 1e7 Pa, p_p = 2, K_b = 1e6 Pa,
 * p_b = 1.5, E* = 0.05. */
static const double BR = 1e-3, KP = 1e7, KB = 1e6, PB = 1.5, ESTAR = 0.05;

static void place_pair(scene *s, double strain)
{
    const double x0[3] = {0, 0, 0}, x1[3] = {2.0 * BR * (1.0 - strain), 0, 0}, zero[3] = {0};
    set3(s, SINTER_FIELD_POSITION, 0, x0);
    set3(s, SINTER_FIELD_POSITION, 1, x1);
    set3(s, SINTER_FIELD_VELOCITY, 0, zero);
    set3(s, SINTER_FIELD_VELOCITY, 1, zero);
}

/* Evaluate; return the x force on particle 0 and the hand values of contact and bond parts. */
static double evaluate_x(scene *s, double *contact, double *bond)
{
    OK(sinter_stepper_evaluate(s->st));
    const pair_geometry g = geometry(s, BR, BR);
    *contact = -KP * g.strain * g.strain * g.area; /* eq. 2, along n = +x */
    *bond = KB * pow(g.strain, PB) * g.area;       /* eq. 19, towards particle 1 */
    double f[3];
    get3(s, SINTER_FIELD_FORCE, 0, f);
    return f[0];
}

static void test_bond_activation_and_breaking(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, 0.0);
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_STIFFNESS, KP));
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_EXPONENT, 2.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_STIFFNESS, KB));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_EXPONENT, PB));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_CRITICAL_STRAIN, ESTAR));
    scene_open(&s, "power_law", 0);
    scene_add(&s, 0, 0, 0, BR);
    scene_add(&s, 3.0 * BR, 0, 0, BR);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    double fcon, fbond, fx;

    /* 1. Below E*: contact only. */
    place_pair(&s, 0.02);
    fx = evaluate_x(&s, &fcon, &fbond);
    assert_close(fx, fcon, REL * fabs(fcon));

    /* 2. Past E*: the bond acts in the same evaluation (contact + bond). */
    place_pair(&s, 0.06);
    fx = evaluate_x(&s, &fcon, &fbond);
    print_message("|E| = 0.06: f = %.12e N = contact %.6e + bond %.6e\n", fx, fcon, fbond);
    assert_close(fx, fcon + fbond, REL * fabs(fcon));

    /* 3. evaluate does not commit: back below E*, there is no bond. */
    place_pair(&s, 0.02);
    fx = evaluate_x(&s, &fcon, &fbond);
    assert_close(fx, fcon, REL * fabs(fcon));

    /* 4. An accepted step past E* commits the bond; it then acts below E* too. */
    place_pair(&s, 0.06);
    OK(sinter_stepper_step(s.st, 1));
    place_pair(&s, 0.02);
    fx = evaluate_x(&s, &fcon, &fbond);
    print_message("bonded at |E| = 0.02: f = %.12e N = contact %.6e + bond %.6e\n", fx, fcon,
                  fbond);
    assert_close(fx, fcon + fbond, REL * fabs(fcon));

    /* 5. Pulled apart by velocities until the contact ends: the bond breaks. */
    const double away0[3] = {-1.0, 0, 0}, away1[3] = {1.0, 0, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, away0);
    set3(&s, SINTER_FIELD_VELOCITY, 1, away1);
    OK(sinter_stepper_step(s.st, 100)); /* 2 m/s for 100 us: gap 0.2 mm >> overlap 0.04 mm */
    double x0[3], x1[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x0);
    get3(&s, SINTER_FIELD_POSITION, 1, x1);
    assert_true(x1[0] - x0[0] > 2.0 * BR);

    /* 6. Re-approach at |E| = 0.02 < E*: no bond force. */
    place_pair(&s, 0.02);
    fx = evaluate_x(&s, &fcon, &fbond);
    assert_close(fx, fcon, REL * fabs(fcon));
    scene_close(&s);
}

static void test_drag_decay(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double c = 0.01;
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, 0.0);
    OK(sinter_material_set(s.mat, SINTER_MAT_DRAG_COEFFICIENT, c));
    scene_open(&s, "drag", 0);
    const double venv[3] = {0.2, 0.0, -0.1};
    OK(sinter_force_model_set(s.contact, "vx", venv[0]));
    OK(sinter_force_model_set(s.contact, "vz", venv[2]));
    scene_add(&s, 0, 0, 0, 1e-3);
    const double v0[3] = {1.0, -2.0, 0.5};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v0);
    const double m = get1(&s, SINTER_FIELD_MASS, 0), tau = m / c; /* ~1.05 ms */
    const double h = 1e-6;
    const int n = 2000;
    OK(sinter_stepper_set_dt(s.st, h));
    OK(sinter_stepper_step(s.st, (uint64_t)n));
    double v[3];
    get3(&s, SINTER_FIELD_VELOCITY, 0, v);
    /*
     * The stepper's second kick uses forces evaluated with the half-kicked velocity, so for a
     * velocity-dependent force one step maps v - v_env by (1 - h/(2 tau))^2 the first time and
     * (1 - h/tau) afterwards (exactly, up to round-off) - forward Euler, first order. Against
     * exp(-t/tau) the relative error is n (h/tau)^2 / 2 = t h / (2 tau^2) ~ 9.1e-4 here.
     */
    const double a = h / (2.0 * tau), t = n * h;
    const double discrete = (1.0 - a) * (1.0 - a) * pow(1.0 - 2.0 * a, n - 1);
    const double closed = exp(-t / tau);
    const double euler_error = t * h / (2.0 * tau * tau);
    print_message("drag: decay %.10f, closed form %.10f (rel. diff %.3e, predicted %.3e)\n",
                  (v[0] - venv[0]) / (v0[0] - venv[0]), closed,
                  fabs((v[0] - venv[0]) / (v0[0] - venv[0]) / closed - 1.0), euler_error);
    for (int k = 0; k < 3; ++k) {
        const double dv0 = v0[k] - venv[k];
        assert_close(v[k] - venv[k], dv0 * discrete, 1e-12 * fabs(dv0));
        assert_close(v[k] - venv[k], dv0 * closed, 1.2 * euler_error * fabs(dv0 * closed));
    }
    scene_close(&s);
}

static void test_unknown_model_lists_known_ones(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_force_model *fm = NULL;
    assert_int_equal(sinter_force_model_create(&fm, ctx, "power-law"), SINTER_ERR_NOT_FOUND);
    assert_null(fm);
    const char *msg = sinter_last_error(ctx);
    assert_non_null(strstr(msg, "'power-law'"));
    assert_non_null(strstr(msg, "power_law"));
    assert_non_null(strstr(msg, "drag"));
    assert_non_null(strstr(msg, "hertz_mindlin"));
    OK(sinter_force_model_create(&fm, ctx, "power_law"));
    assert_string_equal(sinter_force_model_name(fm), "power_law");
    sinter_force_model_destroy(fm);
    OK(sinter_force_model_create(&fm, ctx, "drag"));
    double vx = -1.0;
    OK(sinter_force_model_get(fm, "vx", &vx));
    assert_true(vx == 0.0);
    sinter_force_model_destroy(fm);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pair_contact_force),
        cmocka_unit_test(test_pair_friction),
        cmocka_unit_test(test_wall_contact_and_reaction),
        cmocka_unit_test(test_bond_activation_and_breaking),
        cmocka_unit_test(test_drag_decay),
        cmocka_unit_test(test_unknown_model_lists_known_ones),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
