/*
 * The built-in heat laws evaluated directly (seed 003 eq. 29-41): a sinter_heat_eval is
 * filled by hand from real contact lists and each power is compared with the formula.
 *
 * Tolerances: every law is a handful of floating-point operations, so the library and the
 * hand formula differ only by rounding (a few ulp, ~1e-16 relative); 1e-12 relative leaves
 * room for a different but equivalent arrangement of the operations (e.g. eq. 35 written as
 * k_i k_j (r_i + r_j) / (r_i k_j + r_j k_i)) while catching any wrong factor or term.
 */
#include <string.h>

#include "test_support.h"
#include "contact/contacts.h"
#include "heat/heat_model.h"
#include "particles/particles.h"
#include "walls/walls.h"

#define OK(call) assert_int_equal((call), SINTER_OK)
#define REL 1e-12
#define assert_rel(a, b) assert_close((a), (b), REL *fabs(b))

static const double PI = 3.14159265358979323846;
static const double SIGMA = 5.670374419e-8;

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_neighbors nb;
    sinter_contact_list pp, pw;
    double heat[8], g_pp[8], g_pw[8];
} fixture;

/* Material 0: k 50, emissivity 0.7, absorptance 0.6; material 1: k 20, 0.3, 0.9. */
static void open_fixture(fixture *f)
{
    memset(f, 0, sizeof(*f));
    OK(sinter_ctx_create(&f->ctx, NULL));
    const double k[2] = {50.0, 20.0}, eps[2] = {0.7, 0.3}, a[2] = {0.6, 0.9};
    OK(sinter_particles_create(&f->ps, f->ctx));
    OK(sinter_walls_create(&f->walls, f->ctx));
    for (int m = 0; m < 2; ++m) {
        sinter_material *mat;
        OK(sinter_material_create(&mat, f->ctx, NULL));
        OK(sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, k[m]));
        OK(sinter_material_set(mat, SINTER_MAT_EMISSIVITY, eps[m]));
        OK(sinter_material_set(mat, SINTER_MAT_ABSORPTANCE, a[m]));
        OK(sinter_particles_set_material(f->ps, m, mat));
        sinter_material_destroy(mat);
    }
    sinter_neighbors_init(&f->nb, f->ctx, 1e-4);
}

static void close_fixture(fixture *f)
{
    sinter_contact_list_free(f->ctx, &f->pp);
    sinter_contact_list_free(f->ctx, &f->pw);
    sinter_neighbors_free(&f->nb);
    sinter_walls_destroy(f->walls);
    sinter_particles_destroy(f->ps);
    sinter_ctx_destroy(f->ctx);
}

static void add(fixture *f, double x, double y, double z, double r, int32_t mat, double theta)
{
    const double p[3] = {x, y, z};
    OK(sinter_particles_add(f->ps, 1, p, &r, mat, theta, NULL));
}

static void find_contacts(fixture *f)
{
    OK(sinter_neighbors_build(&f->nb, f->ps, f->walls));
    OK(sinter_contacts_find_pp(f->ctx, &f->pp, &f->nb.pp, f->ps));
    OK(sinter_contacts_find_pw(f->ctx, &f->pw, &f->nb.pw, f->ps, f->walls, NULL));
}

/* One evaluation at time t into f->heat (zeroed first); implicit: into g_pp / g_pw. */
static sinter_status eval(fixture *f, const sinter_heat_model *hm, double t, int implicit)
{
    memset(f->heat, 0, sizeof(f->heat));
    memset(f->g_pp, 0, sizeof(f->g_pp));
    memset(f->g_pw, 0, sizeof(f->g_pw));
    sinter_heat_eval e = {f->ctx,
                          f->ps,
                          f->walls,
                          &f->pp,
                          &f->pw,
                          t,
                          f->heat,
                          implicit ? f->g_pp : NULL,
                          implicit ? f->g_pw : NULL,
                          NULL,
                          NULL,
                          NULL,
                          &f->nb.pp,
                          NULL,
                          f->ps->flags,
                          0,
                          NULL,
                          NULL};
    return hm->ops->eval(hm, &e);
}

static sinter_heat_model *model(fixture *f, const char *name)
{
    sinter_heat_model *hm = NULL;
    OK(sinter_heat_model_create(&hm, f->ctx, name));
    return hm;
}

/*
 * Sphere 0 (r1 = 1 mm, k1 = 50, 300 K) rests 0.1 mm into a 500 K floor; sphere 1
 * (r2 = 0.6 mm, k2 = 20, 400 K) overlaps it and touches nothing else.
 */
static void test_conduction(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r1 = 1e-3, r2 = 0.6e-3, k1 = 50.0, k2 = 20.0, tw = 500.0;
    add(&f, 0.0, 0.0, 0.9e-3, r1, 0, 300.0);
    add(&f, 1.2e-3, 0.0, 1.5e-3, r2, 1, 400.0);
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1};
    sinter_material *wm;
    OK(sinter_material_create(&wm, f.ctx, NULL));
    OK(sinter_walls_add_plane(f.walls, p0, n0, wm, NULL));
    sinter_material_destroy(wm);
    OK(sinter_walls_set_temperature(f.walls, 0, tw));
    find_contacts(&f);
    assert_int_equal(f.pp.count, 1);
    assert_int_equal(f.pw.count, 1);
    assert_int_equal(f.pw.i[0], 0);

    /* By hand: eq. 34 (L_1, A), eq. 35 (k_12), eq. 32 (Q into sphere 0). */
    const double d = sqrt(1.2e-3 * 1.2e-3 + 0.6e-3 * 0.6e-3);
    const double l1 = 0.5 * (d - (r2 * r2 - r1 * r1) / d);
    const double area = PI * (r1 * r1 - l1 * l1);
    const double k12 = (r1 + r2) / (r1 / k1 + r2 / k2);
    const double g = k12 * area / d, q = g * (400.0 - 300.0);
    /* wall: eq. 35 with the wall as a body of the particle's size, k_w = 1 (default material) */
    const double kw_wall = 1.0, k1w = 2.0 * k1 * kw_wall / (k1 + kw_wall);
    const double s = 0.9e-3, gw = k1w * PI * (r1 * r1 - s * s) / s, qw = gw * (tw - 300.0);
    print_message("conduction eq. 34: G = %.12g W/K, Q = %.12g W; wall G = %.12g, Q = %.12g W\n", g,
                  q, gw, qw);

    sinter_heat_model *hm = model(&f, "conduction");
    double v;
    OK(sinter_heat_model_get(hm, "area", &v));
    assert_true(v == 0.0);
    OK(sinter_heat_model_get(hm, "wall_reading", &v));
    assert_true(v == 1.0); /* Hertz's area at walls (docs/validation.md, seed 003 sec. 5.1) */
    OK(sinter_heat_model_set(hm, "wall_reading", 0.0)); /* the centre-plane reading, by hand */
    OK(sinter_heat_model_get(hm, "walls", &v));
    assert_true(v == 1.0);
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[0], q + qw);
    assert_rel(f.heat[1], -q);

    /* walls off: pure exchange, antisymmetric to the bit. */
    OK(sinter_heat_model_set(hm, "walls", 0.0));
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[0], q);
    assert_true(f.heat[0] + f.heat[1] == 0.0);

    /* Implicit: conductances only, nothing into heat. */
    OK(sinter_heat_model_set(hm, "walls", 1.0));
    OK(eval(&f, hm, 0.0, 1));
    assert_rel(f.g_pp[0], g);
    assert_rel(f.g_pw[0], gw);
    assert_true(f.heat[0] == 0.0 && f.heat[1] == 0.0);

    /* area = 1: LIGGGHTS projection, 4 k1 k2 / (k1 + k2) sqrt(pi max(r)^2); the wall with the
     * wall material's k (default 1 W/(m K) here): 4 k1 kw / (k1 + kw) sqrt(pi r1^2). */
    OK(sinter_heat_model_set(hm, "area", 1.0));
    const double gl = 4.0 * k1 * k2 / (k1 + k2) * sqrt(PI * r1 * r1);
    const double kw = 1.0;
    const double glw = 4.0 * k1 * kw / (k1 + kw) * sqrt(PI * r1 * r1);
    print_message("conduction projection: G = %.12g W/K, wall G = %.12g W/K\n", gl, glw);
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[0], gl * 100.0 + glw * (tw - 300.0));
    assert_rel(f.heat[1], -gl * 100.0);
    OK(eval(&f, hm, 0.0, 1));
    assert_rel(f.g_pp[0], gl);
    assert_rel(f.g_pw[0], glw);
    OK(sinter_heat_model_set(hm, "walls", 0.0));
    OK(eval(&f, hm, 0.0, 0));
    assert_true(f.heat[0] + f.heat[1] == 0.0);

    /* Any other area mode is refused at evaluation. */
    OK(sinter_heat_model_set(hm, "area", 3.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * The particle-wall readings and each wall's thermal mode: sphere 0 (r = 1 mm, k = 50, 300 K)
 * 0.1 mm into a 500 K floor of conductivity k_w = 50 (so k_iw = k = 50), sphere 1 far away.
 */
static void test_wall_laws(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r = 1e-3, k = 50.0, tw = 500.0, s = 0.9e-3, delta = r - s;
    add(&f, 0.0, 0.0, s, r, 0, 300.0);
    add(&f, 5e-3, 0.0, 3e-3, r, 0, 300.0);
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1};
    sinter_material *wm;
    OK(sinter_material_create(&wm, f.ctx, NULL));
    OK(sinter_material_set(wm, SINTER_MAT_THERMAL_CONDUCTIVITY, k));
    OK(sinter_walls_add_plane(f.walls, p0, n0, wm, NULL));
    sinter_material_destroy(wm);
    OK(sinter_walls_set_temperature(f.walls, 0, tw));
    find_contacts(&f);
    assert_int_equal(f.pp.count, 0);
    assert_int_equal(f.pw.count, 1);

    /* the three readings of G = k_iw A / d: eq. 34's circle over s, Hertz's pi r delta over s,
     * eq. 34's circle over the mirror distance 2 s */
    const double a_geo = PI * (r * r - s * s), a_hertz = PI * r * delta;
    const double g[3] = {k * a_geo / s, k * a_hertz / s, k * a_geo / (2.0 * s)};
    sinter_heat_model *hm = model(&f, "conduction");
    for (int reading = 0; reading < 3; ++reading) {
        OK(sinter_heat_model_set(hm, "wall_reading", reading));
        OK(eval(&f, hm, 0.0, 0));
        assert_rel(f.heat[0], g[reading] * (tw - 300.0));
        assert_true(f.heat[1] == 0.0);
        OK(eval(&f, hm, 0.0, 1));
        assert_rel(f.g_pw[0], g[reading]);
    }
    /* the Hertz and mirror readings halve eq. 34's to first order in delta / r */
    assert_close(g[1] / g[0], 0.5, delta / r);
    /* constriction (area 2) at a wall of the particle's conductivity: 2 k a (Batchelor &
     * O'Brien), a from the reading's area; the mirror reading reads no distance */
    OK(sinter_heat_model_set(hm, "area", 2.0));
    const double gc[3] = {2.0 * k * sqrt(r * r - s * s), 2.0 * k * sqrt(r * delta),
                          2.0 * k * sqrt(r * r - s * s)};
    for (int reading = 0; reading < 3; ++reading) {
        OK(sinter_heat_model_set(hm, "wall_reading", reading));
        OK(eval(&f, hm, 0.0, 1));
        assert_rel(f.g_pw[0], gc[reading]);
    }
    OK(sinter_heat_model_set(hm, "area", 0.0));
    OK(sinter_heat_model_set(hm, "wall_reading", 1.0));

    /* the wall's own modes (Hertz reading: A = pi r delta) */
    const double rc = 2e-5, h = 3000.0;
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_ADIABATIC, 7.0));
    OK(eval(&f, hm, 0.0, 0));
    assert_true(f.heat[0] == 0.0);
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_RESISTANCE, rc));
    const double g_series = 1.0 / (1.0 / g[1] + rc / a_hertz);
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[0], g_series * (tw - 300.0));
    assert_true(g_series < g[1]);
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_RESISTANCE, 0.0)); /* the law alone */
    OK(eval(&f, hm, 0.0, 1));
    assert_rel(f.g_pw[0], g[1]);
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_TRANSFER, h));
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[0], h * a_hertz * (tw - 300.0));
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_IMPOSED, 0.0)); /* set by the stepper */
    OK(eval(&f, hm, 0.0, 1));
    assert_true(f.g_pw[0] == 0.0);
    OK(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_RESERVOIR, 0.0));
    OK(eval(&f, hm, 0.0, 1));
    assert_rel(f.g_pw[0], g[1]);

    /* refusals */
    assert_int_equal(sinter_walls_set_thermal(f.walls, 0, 5, 0.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_TRANSFER, -1.0),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_thermal(f.walls, 0, SINTER_WALL_RESISTANCE, INFINITY),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_thermal(f.walls, 1, SINTER_WALL_ADIABATIC, 0.0),
                     SINTER_ERR_RANGE);
    OK(sinter_heat_model_set(hm, "wall_reading", 3.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * Pair laws beyond eq. 32-35 on the conduction fixture's pair (r1 = 1 mm, k1 = 50; r2 = 0.6 mm,
 * k2 = 20), walls off: the constriction conductance 4 a k1 k2 / (k1 + k2) (Batchelor &
 * O'Brien 1977, 2 k a for equal conductivities) with eq. 34's or Hertz's radius, eq. 32 with
 * Hertz's area, and an interface resistance in series; every one antisymmetric to the bit.
 */
static void test_pair_laws(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r1 = 1e-3, r2 = 0.6e-3, k1 = 50.0, k2 = 20.0;
    add(&f, 0.0, 0.0, 0.0, r1, 0, 300.0);
    add(&f, 1.2e-3, 0.0, 0.6e-3, r2, 1, 400.0);
    find_contacts(&f);
    assert_int_equal(f.pp.count, 1);
    const double d = sqrt(1.2e-3 * 1.2e-3 + 0.6e-3 * 0.6e-3), delta = r1 + r2 - d;
    const double l1 = 0.5 * (d - (r2 * r2 - r1 * r1) / d);
    const double a2_geo = r1 * r1 - l1 * l1, a2_hertz = r1 * r2 / (r1 + r2) * delta;
    const double k12 = (r1 + r2) / (r1 / k1 + r2 / k2), kh = 2.0 * k1 * k2 / (k1 + k2);
    sinter_heat_model *hm = model(&f, "conduction");
    OK(sinter_heat_model_set(hm, "walls", 0.0));
    struct {
        double area, radius, resistance, g;
    } cases[] = {
        {2.0, 0.0, 0.0, 2.0 * kh * sqrt(a2_geo)},
        {2.0, 1.0, 0.0, 2.0 * kh * sqrt(a2_hertz)},
        {0.0, 1.0, 0.0, k12 * PI * a2_hertz / d},
        {0.0, 0.0, 1e-5, 1.0 / (d / (k12 * PI * a2_geo) + 1e-5 / (PI * a2_geo))},
        {2.0, 1.0, 3e-6, 1.0 / (1.0 / (2.0 * kh * sqrt(a2_hertz)) + 3e-6 / (PI * a2_hertz))},
        {1.0, 0.0, 1e-5,
         1.0 / (1.0 / (4.0 * k1 * k2 / (k1 + k2) * sqrt(PI) * r1) + 1e-5 / (PI * r1 * r1))},
    };
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); ++c) {
        OK(sinter_heat_model_set(hm, "area", cases[c].area));
        OK(sinter_heat_model_set(hm, "radius", cases[c].radius));
        OK(sinter_heat_model_set(hm, "resistance", cases[c].resistance));
        OK(eval(&f, hm, 0.0, 0));
        print_message("pair law %zu: G = %.12g W/K\n", c, cases[c].g);
        assert_rel(f.heat[0], cases[c].g * 100.0);
        assert_true(f.heat[0] + f.heat[1] == 0.0);
        OK(eval(&f, hm, 0.0, 1));
        assert_rel(f.g_pp[0], cases[c].g);
    }
    /* the geometric radius is Hertz's times sqrt(2) to first order: eq. 34 vs Hertz */
    assert_close(a2_geo / a2_hertz, 2.0, 2.0 * delta / r2);
    OK(sinter_heat_model_set(hm, "radius", 2.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    OK(sinter_heat_model_set(hm, "radius", 0.0));
    OK(sinter_heat_model_set(hm, "resistance", -1.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * The gas lens around a contact (Cheng, Yu & Zulli 1999) in parallel with eq. 32-35, for a
 * pair barely overlapping (r1 = 1 mm, k 50; r2 = 0.6 mm, k 20; delta = 2 um), against a
 * quadrature of int 2 pi k_g rho / max(h + rho^2 / (2 r*), g_min) d rho over [a, gas_radius
 * r2] (in u = rho^2: pi k_g / max(h + u / (2 r*), g_min) du, 2e6 midpoints).
 */
static void test_gas_lens(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r1 = 1e-3, r2 = 0.6e-3, k1 = 50.0, k2 = 20.0, delta = 2e-6;
    const double d = r1 + r2 - delta;
    add(&f, 0.0, 0.0, 0.0, r1, 0, 300.0);
    add(&f, d, 0.0, 0.0, r2, 1, 400.0);
    find_contacts(&f);
    assert_int_equal(f.pp.count, 1);
    const double l1 = 0.5 * (d - (r2 * r2 - r1 * r1) / d), a2_geo = r1 * r1 - l1 * l1;
    const double k12 = (r1 + r2) / (r1 / k1 + r2 / k2);
    sinter_heat_model *hm = model(&f, "conduction");
    OK(sinter_heat_model_set(hm, "walls", 0.0));
    const double kg = 0.026, gaps[3] = {1e-7, 2e-5, 1e-7}, fractions[3] = {0.5, 1.0, 0.2};
    const double g_eq34 = k12 * PI * a2_geo / d, rstar = r1 * r2 / (r1 + r2);
    double g_gas[3];
    for (int c = 0; c < 3; ++c) {
        OK(sinter_heat_model_set(hm, "gas_conductivity", kg));
        OK(sinter_heat_model_set(hm, "gas_gap", gaps[c]));
        OK(sinter_heat_model_set(hm, "gas_radius", fractions[c]));
        const double u0 = a2_geo, u1 = fractions[c] * fractions[c] * r2 * r2;
        assert_true(u1 > u0);
        const int nq = 2000000;
        double sum = 0.0;
        for (int q = 0; q < nq; ++q) {
            const double u = u0 + (q + 0.5) * (u1 - u0) / nq, gap = -delta + u / (2.0 * rstar);
            sum += PI * kg / (gap > gaps[c] ? gap : gaps[c]);
        }
        g_gas[c] = sum * (u1 - u0) / nq;
        OK(eval(&f, hm, 0.0, 0));
        print_message("gas lens (g_min %g m, rho_out %g r2): G_gas = %.9g W/K, solid %.9g W/K\n",
                      gaps[c], fractions[c], g_gas[c], g_eq34);
        assert_close(f.heat[0], (g_eq34 + g_gas[c]) * 100.0, 1e-6 * (g_eq34 + g_gas[c]) * 100.0);
        assert_true(f.heat[0] + f.heat[1] == 0.0);
        OK(eval(&f, hm, 0.0, 1));
        assert_close(f.g_pp[0], g_eq34 + g_gas[c], 1e-6 * (g_eq34 + g_gas[c]));
    }
    /* a wider lens conducts more, a larger cut-off less */
    assert_true(g_gas[0] > g_gas[2] && g_gas[0] > 0.0);
    OK(sinter_heat_model_set(hm, "gas_gap", 0.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    OK(sinter_heat_model_set(hm, "gas_gap", 1e-7));
    OK(sinter_heat_model_set(hm, "gas_radius", 1.5));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * The gas between spheres apart (issue 40, heat/gas_gap.h): r1 = 1 mm, r2 = 0.6 mm at gaps
 * h = 20 um and 50 nm (below g_min = 100 nm, the cut-off branch) on the line of centres, no
 * solid contact. Against a quadrature of int pi k_g / max(h + u / (2 r*), g_min) du over
 * u = rho^2 in [0, (gas_radius r2)^2] (2e6 midpoints: relative error ~1e-10 where the
 * integrand is smooth, 1e-6 allowed for the kink at g_min); heat leaving one sphere enters the
 * other to the bit; a pair beyond gas_reach r2, or with gas_reach 0, exchanges nothing; the
 * implicit scheme takes the pairs apart explicitly (no contact conductance to add).
 */
static void test_gas_near_pairs(void **state)
{
    (void)state;
    const double r1 = 1e-3, r2 = 0.6e-3, kg = 0.026, gmin = 1e-7, frac = 0.5;
    const double gaps[2] = {2e-5, 5e-8}, rstar = r1 * r2 / (r1 + r2);
    for (int c = 0; c < 2; ++c) {
        fixture f;
        open_fixture(&f);
        add(&f, 0.0, 0.0, 0.0, r1, 0, 300.0);
        add(&f, r1 + r2 + gaps[c], 0.0, 0.0, r2, 1, 400.0);
        find_contacts(&f);
        assert_int_equal(f.pp.count, 0);
        assert_int_equal(f.nb.pp.count, 1); /* within the fixture's skin of 0.1 mm */
        sinter_heat_model *hm = model(&f, "conduction");
        OK(sinter_heat_model_set(hm, "walls", 0.0));
        OK(sinter_heat_model_set(hm, "gas_conductivity", kg));
        OK(sinter_heat_model_set(hm, "gas_gap", gmin));
        OK(sinter_heat_model_set(hm, "gas_radius", frac));
        OK(eval(&f, hm, 0.0, 0)); /* gas_reach 0 (default): contacts only */
        assert_true(f.heat[0] == 0.0 && f.heat[1] == 0.0);
        OK(sinter_heat_model_set(hm, "gas_reach", 0.1)); /* 60 um */
        const double u1 = frac * frac * r2 * r2;
        const int nq = 2000000;
        double sum = 0.0;
        for (int q = 0; q < nq; ++q) {
            const double u = (q + 0.5) * u1 / nq, gap = gaps[c] + u / (2.0 * rstar);
            sum += PI * kg / (gap > gmin ? gap : gmin);
        }
        const double g = sum * u1 / nq;
        OK(eval(&f, hm, 0.0, 0));
        print_message("gas apart (h = %g m): G_gas = %.9g W/K (quadrature %.9g)\n", gaps[c],
                      f.heat[0] / 100.0, g);
        assert_close(f.heat[0], g * 100.0, 1e-6 * g * 100.0);
        assert_true(f.heat[0] + f.heat[1] == 0.0);
        const double explicit_heat = f.heat[0];
        OK(eval(&f, hm, 0.0, 1));
        assert_true(f.heat[0] == explicit_heat && f.heat[1] == -explicit_heat);
        OK(sinter_heat_model_set(hm, "gas_reach", 0.02)); /* 12 um: only the nearer pair */
        OK(eval(&f, hm, 0.0, 0));
        if (c == 0)
            assert_true(f.heat[0] == 0.0 && f.heat[1] == 0.0);
        else
            assert_true(f.heat[0] == explicit_heat);
        OK(sinter_heat_model_set(hm, "gas_reach", -1.0));
        assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
        sinter_heat_model_destroy(hm);
        close_fixture(&f);
    }
}

/*
 * The ray-traced "beam": the power absorbed plus the power transmitted is the beam's power
 * (to round-off, every case); a sphere in a wide top-hat beam absorbs a P (pi r^2 / pi R^2)
 * (to the rays' sampling of its disc); a sphere behind an equal one on the axis gets the
 * fraction (1 - a) of what the first absorbed, ray by ray (shadowing); a beam along +x gives
 * what a beam along -z gives (any direction); a small sphere on a Gaussian beam's axis absorbs
 * a I(0) pi r^2 with I(0) = 2 P / (pi w^2); a semi-transparent sphere absorbs a (1 -
 * exp(-mu L)) of each ray, L its chord.
 */
static double beam_output(sinter_heat_model *hm, const char *name)
{
    double v = -1.0;
    OK(sinter_heat_model_output(hm, name, &v));
    return v;
}

static void test_beam_rays(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f); /* material 0: absorptance 0.6, material 1: 0.9 */
    const double r = 1e-3, a0 = 0.6, power = 10.0, rb = 5e-3;
    add(&f, 0.0, 0.0, 0.0, r, 0, 300.0);
    find_contacts(&f);
    sinter_heat_model *hm = model(&f, "beam");
    OK(sinter_heat_model_set(hm, "z", 0.01));
    OK(sinter_heat_model_set(hm, "power", power));
    OK(sinter_heat_model_set(hm, "radius", rb));
    OK(sinter_heat_model_set(hm, "rays", 400.0));
    OK(eval(&f, hm, 0.0, 0));
    const double expected = a0 * power * r * r / (rb * rb);
    print_message("beam, one sphere: absorbed %.9g W (closed form %.9g W), transmitted %.9g W\n",
                  f.heat[0], expected, beam_output(hm, "transmitted"));
    assert_close(f.heat[0], expected, 2e-3 * expected); /* the rays' sampling of the disc */
    assert_rel(beam_output(hm, "absorbed"), f.heat[0]);
    assert_close(beam_output(hm, "absorbed") + beam_output(hm, "transmitted"), power,
                 1e-12 * power);
    assert_true(beam_output(hm, "lit") == 1.0 && beam_output(hm, "lit_temperature") == 300.0);

    /* any direction: the same sphere lit along +x from x = -0.01 */
    const double q_down = f.heat[0];
    OK(sinter_heat_model_set(hm, "x", -0.01));
    OK(sinter_heat_model_set(hm, "z", 0.0));
    OK(sinter_heat_model_set(hm, "dx", 2.0)); /* normalised by the model */
    OK(sinter_heat_model_set(hm, "dz", 0.0));
    OK(eval(&f, hm, 0.0, 0));
    assert_close(f.heat[0], q_down, 2e-3 * q_down);
    /* the beam pointing away lights nothing: all transmitted */
    OK(sinter_heat_model_set(hm, "dx", -1.0));
    OK(eval(&f, hm, 0.0, 0));
    assert_true(f.heat[0] == 0.0);
    assert_close(beam_output(hm, "transmitted"), power, 1e-12 * power);
    assert_true(beam_output(hm, "lit") == 0.0);

    /* shadowing: an equal sphere of material 1 (a = 0.9) right below, then another beside */
    add(&f, 0.0, 0.0, -3e-3, r, 1, 400.0);
    add(&f, 3e-3, 0.0, -3e-3, r, 1, 500.0);
    OK(sinter_heat_model_set(hm, "x", 0.0));
    OK(sinter_heat_model_set(hm, "z", 0.01));
    OK(sinter_heat_model_set(hm, "dx", 0.0));
    OK(sinter_heat_model_set(hm, "dz", -1.0));
    OK(eval(&f, hm, 0.0, 0));
    print_message("beam, shadowing: %.9g W above, %.9g W below, %.9g W beside\n", f.heat[0],
                  f.heat[1], f.heat[2]);
    assert_rel(f.heat[1], 0.9 * (1.0 - a0) / a0 * f.heat[0]); /* every ray through both */
    assert_close(f.heat[2], 0.9 * power * r * r / (rb * rb), 2e-3 * f.heat[2]); /* unshaded */
    assert_close(beam_output(hm, "absorbed") + beam_output(hm, "transmitted"), power,
                 1e-12 * power);
    assert_true(beam_output(hm, "lit") == 3.0);
    assert_rel(beam_output(hm, "lit_temperature"), 400.0);

    /* Gaussian (w = 5 mm, sampled to 2 w): a 0.5 mm sphere on the axis, alone in the beam:
     * a I(0) (pi w^2 / 2) (1 - exp(-2 r^2 / w^2)) */
    sinter_heat_model *g = model(&f, "beam");
    OK(sinter_heat_model_set(g, "z", 0.01));
    OK(sinter_heat_model_set(g, "x", 0.02)); /* away from the three spheres above */
    add(&f, 0.02, 0.0, 0.0, 5e-4, 0, 300.0);
    OK(sinter_heat_model_set(g, "power", power));
    OK(sinter_heat_model_set(g, "profile", 1.0));
    OK(sinter_heat_model_set(g, "rays", 2000.0));
    OK(eval(&f, g, 0.0, 0));
    const double i0 = 2.0 * power / (PI * rb * rb) / (1.0 - exp(-8.0)); /* truncated at 2 w */
    const double gexp = a0 * i0 * 0.5 * PI * rb * rb * -expm1(-2.0 * 2.5e-7 / (rb * rb));
    print_message("beam, Gaussian: %.9g W on the axis (closed form %.9g W)\n", f.heat[3], gexp);
    assert_close(f.heat[3], gexp, 2e-3 * gexp); /* the rays' sampling of the disc */
    assert_close(beam_output(g, "absorbed") + beam_output(g, "transmitted"), power, 1e-12 * power);

    /* semi-transparent: mu = 1000 1/m; one ray down the axis of sphere 3 crosses 2 r = 1 mm */
    OK(sinter_heat_model_set(g, "profile", 0.0));
    OK(sinter_heat_model_set(g, "radius", 1e-6));
    OK(sinter_heat_model_set(g, "rays", 1.0));
    OK(sinter_heat_model_set(g, "attenuation", 1000.0));
    OK(eval(&f, g, 0.0, 0));
    assert_rel(f.heat[3], power * a0 * (1.0 - exp(-1000.0 * 1e-3)));
    assert_rel(beam_output(g, "transmitted"), power - f.heat[3]);

    /* refusals */
    double v;
    assert_int_equal(sinter_heat_model_output(hm, "power", &v), SINTER_ERR_NOT_FOUND);
    sinter_heat_model *cond = model(&f, "conduction");
    assert_int_equal(sinter_heat_model_output(cond, "absorbed", &v), SINTER_ERR_NOT_FOUND);
    sinter_heat_model_destroy(cond);
    OK(sinter_heat_model_set(g, "rays", 0.5));
    assert_int_equal(eval(&f, g, 0.0, 0), SINTER_ERR_INVALID);
    OK(sinter_heat_model_set(g, "rays", 8.0));
    OK(sinter_heat_model_set(g, "dz", 0.0));
    assert_int_equal(eval(&f, g, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(g);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/* Two spheres (1 mm and 0.5 mm) at 400 K in air at 293.15 K. */
static void test_convection(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r[2] = {1e-3, 0.5e-3}, te = 293.15, ke = 0.026;
    add(&f, 0.0, 0.0, 0.0, r[0], 0, 400.0);
    add(&f, 1e-2, 0.0, 0.0, r[1], 1, 400.0);
    sinter_heat_model *hm = model(&f, "convection");
    const char *keys[] = {"temperature",         "h",
                          "fluid_conductivity",  "fluid_viscosity",
                          "fluid_heat_capacity", "fluid_density",
                          "fluid_speed"};
    const double defaults[] = {293.15, 0.0, 0.026, 1.8e-5, 1005.0, 1.2, 0.0};
    for (int k = 0; k < 7; ++k) {
        double v;
        OK(sinter_heat_model_get(hm, keys[k], &v));
        assert_true(v == defaults[k]);
        assert_string_equal(hm->ops->keys[k], keys[k]);
    }
    /* Stagnant: Nu = 2, h = k_E / r (eq. 38-39), Q = h (theta_E - theta) 4 pi r^2 (eq. 37). */
    OK(eval(&f, hm, 0.0, 0));
    for (int i = 0; i < 2; ++i)
        assert_rel(f.heat[i], ke / r[i] * (te - 400.0) * 4.0 * PI * r[i] * r[i]);

    /* 2 m/s: Re = 266.67 / 133.33, Pr = 0.69577, Whitaker Nu = 9.79982 / 7.34944 (eq. 39-40). */
    OK(sinter_heat_model_set(hm, "fluid_speed", 2.0));
    OK(eval(&f, hm, 0.0, 0));
    const double pr = 1005.0 * 1.8e-5 / ke;
    for (int i = 0; i < 2; ++i) {
        const double re = 1.2 * 2.0 * 2.0 * r[i] / 1.8e-5;
        const double nu = 2.0 + (0.4 * sqrt(re) + 0.06 * pow(re, 2.0 / 3.0)) * pow(pr, 0.4);
        assert_rel(f.heat[i], nu * ke / (2.0 * r[i]) * (te - 400.0) * 4.0 * PI * r[i] * r[i]);
    }
    /* The same values computed independently (Python, double precision). */
    assert_close(f.heat[0], -0.17105900169212637, 1e-12 * 0.171);
    assert_close(f.heat[1], -0.06414338787101277, 1e-12 * 0.0641);

    /* "h" > 0 overrides the correlation; the fluid temperature may follow a schedule. */
    OK(sinter_heat_model_set(hm, "h", 25.0));
    const double times[2] = {0.0, 1.0}, temps[2] = {300.0, 500.0};
    OK(sinter_heat_model_set_schedule(hm, "temperature", 2, times, temps));
    OK(eval(&f, hm, 0.5, 0));
    for (int i = 0; i < 2; ++i)
        assert_true(f.heat[i] == 0.0); /* theta_E(0.5) = 400 K = theta */
    OK(eval(&f, hm, 1.0, 0));
    for (int i = 0; i < 2; ++i)
        assert_rel(f.heat[i], 25.0 * (500.0 - 400.0) * 4.0 * PI * r[i] * r[i]);

    /* The correlation refuses a zero viscosity (it divides by it). */
    OK(sinter_heat_model_set(hm, "h", 0.0));
    OK(sinter_heat_model_set(hm, "fluid_viscosity", 0.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/* Eq. 41 for two materials (emissivity 0.7 and 0.3), hot and cold against 300 K. */
static void test_radiation(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    add(&f, 0.0, 0.0, 0.0, 1e-3, 0, 1000.0);
    add(&f, 1e-2, 0.0, 0.0, 0.5e-3, 1, 250.0);
    sinter_heat_model *hm = model(&f, "radiation");
    double v;
    OK(sinter_heat_model_get(hm, "temperature", &v));
    assert_true(v == 293.15);
    OK(sinter_heat_model_set(hm, "temperature", 300.0));
    OK(eval(&f, hm, 0.0, 0));
    const double q0 = 0.7 * SIGMA * 4.0 * PI * 1e-6 * (pow(300.0, 4) - pow(1000.0, 4));
    const double q1 = 0.3 * SIGMA * 4.0 * PI * 0.25e-6 * (pow(300.0, 4) - pow(250.0, 4));
    print_message("radiation: Q = %.12g W, %.12g W\n", q0, q1);
    assert_rel(f.heat[0], q0); /* -0.4948 W */
    assert_rel(f.heat[1], q1);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * Exposed surfaces (heat/exposure.c) and gas properties by temperature: sphere 0 rests on a
 * floor and touches sphere 1 (r 0.6 mm) beside it; sphere 2 is alone. Radiation with
 * exposed = 1 gives sphere 0 the fraction 1 - 1/2 - F01 of eq. 41, sphere 1 1 - F10, sphere 2
 * all of it, F_ij = (1 - sqrt(1 - (r_j / d)^2)) / 2 (a sphere to a sphere); convection's
 * Sutherland law at the film temperature matches the closed form, and at the reference
 * temperature gives the constant law's power.
 */
static void test_exposed_and_gas_law(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r0 = 1e-3, r1 = 0.6e-3;
    add(&f, 0.0, 0.0, 0.9e-3, r0, 0, 1000.0);
    add(&f, 1.2e-3, 0.0, 1.5e-3, r1, 0, 1000.0);
    add(&f, 1e-2, 0.0, 5e-3, r0, 0, 1000.0);
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1};
    sinter_material *wm;
    OK(sinter_material_create(&wm, f.ctx, NULL));
    OK(sinter_walls_add_plane(f.walls, p0, n0, wm, NULL));
    sinter_material_destroy(wm);
    find_contacts(&f);
    assert_int_equal(f.pp.count, 1);
    assert_int_equal(f.pw.count, 1);
    sinter_heat_model *hm = model(&f, "radiation");
    OK(eval(&f, hm, 0.0, 0));
    double whole[3];
    memcpy(whole, f.heat, sizeof(whole));
    OK(sinter_heat_model_set(hm, "exposed", 1.0));
    OK(eval(&f, hm, 0.0, 0));
    const double d = sqrt(1.2e-3 * 1.2e-3 + 0.6e-3 * 0.6e-3);
    const double f01 = 0.5 * (1.0 - sqrt(1.0 - (r1 / d) * (r1 / d)));
    const double f10 = 0.5 * (1.0 - sqrt(1.0 - (r0 / d) * (r0 / d)));
    print_message("exposed fractions: %.6f %.6f %.6f (closed form %.6f %.6f 1)\n",
                  f.heat[0] / whole[0], f.heat[1] / whole[1], f.heat[2] / whole[2], 0.5 - f01,
                  1.0 - f10);
    assert_rel(f.heat[0], (0.5 - f01) * whole[0]);
    assert_rel(f.heat[1], (1.0 - f10) * whole[1]);
    assert_true(f.heat[2] == whole[2]);
    OK(sinter_heat_model_set(hm, "exposed", 0.5));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);

    /* convection, stagnant, exposed: the same fractions */
    sinter_heat_model *cm = model(&f, "convection");
    OK(eval(&f, cm, 0.0, 0));
    memcpy(whole, f.heat, sizeof(whole));
    OK(sinter_heat_model_set(cm, "exposed", 1.0));
    OK(eval(&f, cm, 0.0, 0));
    assert_rel(f.heat[0], (0.5 - f01) * whole[0]);
    assert_rel(f.heat[1], (1.0 - f10) * whole[1]);
    assert_rel(f.heat[2], whole[2]);
    /* the gas law at 2 m/s: particles at 1000 K in air at 300 K, film 650 K */
    OK(sinter_heat_model_set(cm, "exposed", 0.0));
    OK(sinter_heat_model_set(cm, "temperature", 300.0));
    OK(sinter_heat_model_set(cm, "fluid_speed", 2.0));
    OK(sinter_heat_model_set(cm, "fluid_law", 1.0));
    OK(eval(&f, cm, 0.0, 0));
    const double t0 = 293.15, tf = 650.0;
    const double k = 0.026 * pow(tf / t0, 1.5) * (t0 + 194.0) / (tf + 194.0);
    const double mu = 1.8e-5 * pow(tf / t0, 1.5) * (t0 + 111.0) / (tf + 111.0);
    const double rho = 1.2 * t0 / tf;
    const double re = rho * 2.0 * 2.0 * r0 / mu, pr = 1005.0 * mu / k;
    const double nu = 2.0 + (0.4 * sqrt(re) + 0.06 * pow(re, 2.0 / 3.0)) * pow(pr, 0.4);
    const double q = nu * k / (2.0 * r0) * (300.0 - 1000.0) * 4.0 * PI * r0 * r0;
    print_message("gas law: %.9g W at a 650 K film\n", f.heat[2]);
    assert_rel(f.heat[2], q);
    /* at the reference temperature the law gives the constant properties' power */
    OK(sinter_heat_model_set(cm, "fluid_reference_temperature", tf));
    OK(eval(&f, cm, 0.0, 0));
    const double law_at_ref = f.heat[2];
    OK(sinter_heat_model_set(cm, "fluid_law", 0.0));
    OK(eval(&f, cm, 0.0, 0));
    assert_rel(law_at_ref, f.heat[2]);
    OK(sinter_heat_model_set(cm, "fluid_law", 2.0));
    assert_int_equal(eval(&f, cm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(cm);
    close_fixture(&f);
}

/*
 * A column of three r = 0.5 mm spheres on the z axis (tops at 1, 2, 3 mm; material 0,
 * absorptance 0.6) and one sphere of material 1 (absorptance 0.9) at x = 3 mm whose top is
 * higher (5.5 mm) but outside a 1 mm beam on the axis.
 */
static void beam_bed(fixture *f)
{
    for (int k = 0; k < 3; ++k)
        add(f, 0.0, 0.0, 0.5e-3 + 1e-3 * k, 0.5e-3, 0, 300.0);
    add(f, 3e-3, 0.0, 5e-3, 0.5e-3, 1, 300.0);
}

static void test_laser(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    beam_bed(&f);
    const double r = 0.5e-3, i0 = 1e6, mu = 500.0, a0 = 0.6, a1 = 0.9;
    sinter_heat_model *hm = model(&f, "laser");
    OK(sinter_heat_model_set(hm, "radius", 1e-3));
    OK(sinter_heat_model_set(hm, "intensity", i0));
    OK(sinter_heat_model_set(hm, "attenuation", mu));
    OK(eval(&f, hm, 0.0, 0));
    /* Depths below the top of the lit column: z = 4r, 2r, 0 (eq. 31). */
    for (int k = 0; k < 3; ++k)
        assert_rel(f.heat[k], a0 * i0 * PI * r * r * exp(-mu * (4 - 2 * k) * r));
    assert_true(f.heat[3] == 0.0);
    print_message("laser: Q = %.12g, %.12g, %.12g W (z = 4r, 2r, 0)\n", f.heat[0], f.heat[1],
                  f.heat[2]);

    /* A scheduled "x" moves the beam: at t = 1 it is over sphere 3 only (depth 0). */
    const double times[2] = {0.0, 1.0}, xs[2] = {0.0, 3e-3};
    OK(sinter_heat_model_set_schedule(hm, "x", 2, times, xs));
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[2], a0 * i0 * PI * r * r);
    OK(eval(&f, hm, 1.0, 0));
    for (int k = 0; k < 3; ++k)
        assert_true(f.heat[k] == 0.0);
    assert_rel(f.heat[3], a1 * i0 * PI * r * r);
    /* Half way (x = 1.5 mm) nothing is within 1 mm of the axis. */
    OK(eval(&f, hm, 0.5, 0));
    for (int k = 0; k < 4; ++k)
        assert_true(f.heat[k] == 0.0);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

static void test_nozzle(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    beam_bed(&f);
    const double r = 0.5e-3, i0 = 2e5, a0 = 0.6;
    sinter_heat_model *hm = model(&f, "nozzle");
    OK(sinter_heat_model_set(hm, "radius", 1e-3));
    OK(sinter_heat_model_set(hm, "intensity", i0));
    /* d_max = 1.5 mm: z = 0 -> 1, z = 1 mm -> 1/3, z = 2 mm > d_max -> 0 (eq. 30). */
    OK(sinter_heat_model_set(hm, "depth", 1.5e-3));
    OK(eval(&f, hm, 0.0, 0));
    assert_rel(f.heat[2], a0 * i0 * PI * r * r);
    assert_rel(f.heat[1], a0 * i0 * PI * r * r * (1.0 - 1e-3 / 1.5e-3));
    assert_true(f.heat[0] == 0.0);
    assert_true(f.heat[3] == 0.0);
    /* d_max = 3 mm: linear in depth, 1, 2/3, 1/3. */
    OK(sinter_heat_model_set(hm, "depth", 3e-3));
    OK(eval(&f, hm, 0.0, 0));
    for (int k = 0; k < 3; ++k)
        assert_rel(f.heat[k], a0 * i0 * PI * r * r * (1.0 - (2 - k) * 1e-3 / 3e-3));
    /* A non-positive reach is refused. */
    OK(sinter_heat_model_set(hm, "depth", 0.0));
    assert_int_equal(eval(&f, hm, 0.0, 0), SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/*
 * Scan paths (heat/scan_path.c): positions and levels along a path at chosen times (exact:
 * straight segments at constant speed); a laser crossing one sphere on a line at distance dy
 * from its centre delivers the closed-form energy a I0 pi r^2 * 2 sqrt(R^2 - dy^2) / v (the
 * time its centre is inside the top hat), to the sampling step; the ray-traced beam's absorbed
 * plus transmitted power is the power times the path's level at every time; hatches fill a
 * rectangle with the stated lines; bad paths are refused naming the vertex.
 */
static void test_scan_paths(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double r = 0.5e-3, i0 = 1e6, a0 = 0.6, rb = 1e-3, v = 0.1, dy = 0.6e-3;
    add(&f, 0.0, 0.0, 0.5e-3, r, 0, 300.0);
    sinter_heat_model *hm = model(&f, "laser");
    OK(sinter_heat_model_set(hm, "radius", rb));
    OK(sinter_heat_model_set(hm, "intensity", i0));
    /* start 0.5 ms; 4 mm along x at 0.1 m/s (level 1), a jump up 1 mm (level 0, 1 m/s), back
     * 2 mm at 0.2 m/s at half power */
    const double path[16] = {-2e-3, dy,        0.0, 0.0, 2e-3, dy,        v,   1.0,
                             2e-3,  dy + 1e-3, 1.0, 0.0, 0.0,  dy + 1e-3, 0.2, 0.5};
    OK(sinter_heat_model_set_scan_path(hm, 4, path, 0.5e-3));
    double end = 0.0;
    OK(sinter_heat_model_scan_end(hm, &end));
    const double t1 = 0.5e-3 + 4e-3 / v, t2 = t1 + 1e-3 / 1.0, t3 = t2 + 2e-3 / 0.2;
    assert_rel(end, t3);
    const sinter_heat_model *cm = hm;
    /* positions and the power level: x, y and intensity read through sinter_heat_param */
    const int kx = 0, ky = 1;
    int ki = -1;
    for (int p = 0; cm->ops->keys[p] != NULL; ++p)
        if (strcmp(cm->ops->keys[p], "intensity") == 0)
            ki = p;
    assert_true(ki >= 0 && strcmp(cm->ops->keys[kx], "x") == 0 &&
                strcmp(cm->ops->keys[ky], "y") == 0);
    const double probe[6] = {0.0, 0.5e-3 + 1e-2, t1 + 0.25e-3, t2 + 5e-3, t3, t3 + 1.0};
    const double want_x[6] = {-2e-3, -2e-3 + v * 1e-2, 2e-3, 2e-3 - 0.2 * 5e-3, 0.0, 0.0};
    const double want_y[6] = {dy, dy, dy + 0.25e-3, dy + 1e-3, dy + 1e-3, dy + 1e-3};
    const double want_level[6] = {0.0, 1.0, 0.0, 0.5, 0.0, 0.0};
    for (int k = 0; k < 6; ++k) {
        assert_close(sinter_heat_param(cm, kx, probe[k]), want_x[k], 1e-15);
        assert_close(sinter_heat_param(cm, ky, probe[k]), want_y[k], 1e-15);
        assert_close(sinter_heat_param(cm, ki, probe[k]), i0 * want_level[k], 1e-9 * i0);
    }
    /* the energy the sphere receives during the first segment, sampled at the midpoints of
     * 4000 steps: the closed form to within one step's power at each edge */
    const int steps = 4000;
    const double h = (t1 - 0.5e-3) / steps;
    double energy = 0.0;
    for (int k = 0; k < steps; ++k) {
        OK(eval(&f, hm, 0.5e-3 + (k + 0.5) * h, 0));
        energy += f.heat[0] * h;
    }
    const double q = a0 * i0 * PI * r * r, lit = 2.0 * sqrt(rb * rb - dy * dy) / v;
    print_message("scan path: %.9g J delivered, closed form %.9g J\n", energy, q * lit);
    assert_close(energy, q * lit, 2.0 * q * h);
    /* the ray-traced beam on the same path: absorbed + transmitted = P level(t) */
    sinter_heat_model *bm = model(&f, "beam");
    OK(sinter_heat_model_set(bm, "power", 50.0));
    OK(sinter_heat_model_set(bm, "radius", rb));
    OK(sinter_heat_model_set(bm, "z", 5e-3));
    OK(sinter_heat_model_set_scan_path(bm, 4, path, 0.5e-3));
    for (int k = 0; k < 6; ++k) {
        OK(eval(&f, bm, probe[k], 0));
        double absorbed = 0.0, transmitted = 0.0;
        OK(sinter_heat_model_output(bm, "absorbed", &absorbed));
        OK(sinter_heat_model_output(bm, "transmitted", &transmitted));
        assert_close(absorbed + transmitted, 50.0 * want_level[k], 1e-12 * 50.0);
    }
    /* bad paths: the model is unchanged */
    double bad[8] = {0.0, 0.0, 0.0, 0.0, 1e-3, 0.0, -1.0, 1.0};
    assert_int_equal(sinter_heat_model_set_scan_path(hm, 2, bad, 0.0), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f.ctx), "vertex 1"));
    bad[6] = 0.1;
    bad[7] = 1.5;
    assert_int_equal(sinter_heat_model_set_scan_path(hm, 2, bad, 0.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_heat_model_set_scan_path(hm, 1, bad, 0.0), SINTER_ERR_INVALID);
    bad[4] = NAN;
    bad[7] = 1.0;
    assert_int_equal(sinter_heat_model_set_scan_path(hm, 2, bad, 0.0), SINTER_ERR_INVALID);
    OK(sinter_heat_model_scan_end(hm, &end));
    assert_rel(end, t3);
    sinter_heat_model *cond = model(&f, "conduction");
    assert_int_equal(sinter_heat_model_set_scan_path(cond, 4, path, 0.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_heat_model_scan_end(cond, &end), SINTER_ERR_NOT_FOUND);
    /* n = 0 removes the path: the intensity is the parameter's again */
    OK(sinter_heat_model_set_scan_path(hm, 0, NULL, 0.0));
    assert_true(sinter_heat_param(cm, ki, 100.0) == i0);

    /* a hatch of a 2 x 1 mm rectangle, lines along x 0.25 mm apart: 5 lines at y = 0 .. 1 mm,
     * 10 vertices, serpentine; at 90 degrees: 9 lines along y */
    const double lo[2] = {0.0, 0.0}, hi[2] = {2e-3, 1e-3};
    size_t count = 0;
    OK(sinter_scan_hatch(f.ctx, lo, hi, 0.25e-3, 0.0, 0.5, 2.0, 1, NULL, 0, &count));
    assert_int_equal(count, 10);
    double pts[4 * 18];
    OK(sinter_scan_hatch(f.ctx, lo, hi, 0.25e-3, 0.0, 0.5, 2.0, 1, pts, 10, &count));
    for (size_t k = 0; k < 5; ++k) {
        const double *a = pts + 8 * k, *b = a + 4;
        assert_close(a[1], 0.25e-3 * (double)k, 1e-15);
        assert_close(b[1], a[1], 1e-18);
        assert_close(fabs(b[0] - a[0]), 2e-3, 1e-15);
        assert_true((b[0] > a[0]) == (k % 2 == 0)); /* serpentine */
        assert_true(a[3] == 0.0 && b[3] == 1.0 && b[2] == 0.5 && (k == 0 || a[2] == 2.0));
    }
    OK(sinter_scan_hatch(f.ctx, lo, hi, 0.25e-3, PI / 2, 0.5, 2.0, 0, pts, 18, &count));
    assert_int_equal(count, 18);
    for (size_t k = 0; k < 9; ++k)
        assert_true(pts[8 * k + 5] > pts[8 * k + 1]); /* unidirectional: every line upwards */
    assert_int_equal(sinter_scan_hatch(f.ctx, lo, hi, 0.25e-3, 0.0, 0.5, 2.0, 1, pts, 9, &count),
                     SINTER_ERR_RANGE);
    assert_int_equal(sinter_scan_hatch(f.ctx, hi, lo, 0.25e-3, 0.0, 0.5, 2.0, 1, pts, 18, &count),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_scan_hatch(f.ctx, lo, hi, 0.0, 0.0, 0.5, 2.0, 1, pts, 18, &count),
                     SINTER_ERR_INVALID);
    /* a hatched path over the rectangle at 0.5 m/s lasts 5 x 4 ms of scanning plus the jumps */
    OK(sinter_scan_hatch(f.ctx, lo, hi, 0.25e-3, 0.0, 0.5, 2.0, 1, pts, 10, &count));
    OK(sinter_heat_model_set_scan_path(hm, count, pts, 0.0));
    OK(sinter_heat_model_scan_end(hm, &end));
    assert_rel(end, 5 * 2e-3 / 0.5 + 4 * 0.25e-3 / 2.0);
    sinter_heat_model_destroy(cond);
    sinter_heat_model_destroy(bm);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

static void test_names_and_schedules(void **state)
{
    (void)state;
    sinter_ctx *ctx;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_heat_model *hm = NULL;
    assert_int_equal(sinter_heat_model_create(&hm, ctx, "conductoin"), SINTER_ERR_NOT_FOUND);
    assert_null(hm);
    const char *msg = sinter_last_error(ctx);
    assert_non_null(strstr(msg, "conductoin"));
    assert_non_null(strstr(msg, "conduction, convection, radiation, nozzle, laser"));
    const char *names[] = {"conduction", "convection", "radiation", "nozzle", "laser"};
    for (int k = 0; k < 5; ++k) {
        OK(sinter_heat_model_create(&hm, ctx, names[k]));
        assert_string_equal(sinter_heat_model_name(hm), names[k]);
        assert_int_equal(hm->ops->conduction, k == 0);
        sinter_heat_model_destroy(hm);
    }
    OK(sinter_heat_model_create(&hm, ctx, "laser"));
    const double t_ok[2] = {0.0, 1.0}, t_bad[2] = {1.0, 1.0}, v[2] = {0.0, 1.0};
    const double v_nan[2] = {0.0, NAN};
    assert_int_equal(sinter_heat_model_set_schedule(hm, "x", 0, t_ok, v), SINTER_ERR_INVALID);
    assert_int_equal(sinter_heat_model_set_schedule(hm, "x", 2, t_bad, v), SINTER_ERR_INVALID);
    assert_int_equal(sinter_heat_model_set_schedule(hm, "x", 2, t_ok, v_nan), SINTER_ERR_INVALID);
    assert_int_equal(sinter_heat_model_set_schedule(hm, "depth", 2, t_ok, v),
                     SINTER_ERR_NOT_FOUND); /* a nozzle key, not a laser one */
    assert_int_equal(sinter_heat_model_set_schedule(hm, "x", 2, NULL, v), SINTER_ERR_NULL);
    assert_int_equal(sinter_heat_model_set(hm, "intensity", INFINITY), SINTER_ERR_INVALID);
    OK(sinter_heat_model_set_schedule(hm, "intensity", 2, t_ok, v));
    assert_close(sinter_heat_param(hm, 3, 0.25), 0.25, 1e-15);
    assert_close(sinter_heat_param(hm, 3, -1.0), 0.0, 0.0); /* held outside */
    assert_close(sinter_heat_param(hm, 3, 7.0), 1.0, 0.0);
    sinter_heat_model_destroy(hm);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conduction),
        cmocka_unit_test(test_wall_laws),
        cmocka_unit_test(test_pair_laws),
        cmocka_unit_test(test_gas_lens),
        cmocka_unit_test(test_gas_near_pairs),
        cmocka_unit_test(test_beam_rays),
        cmocka_unit_test(test_convection),
        cmocka_unit_test(test_radiation),
        cmocka_unit_test(test_exposed_and_gas_law),
        cmocka_unit_test(test_laser),
        cmocka_unit_test(test_nozzle),
        cmocka_unit_test(test_scan_paths),
        cmocka_unit_test(test_names_and_schedules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
