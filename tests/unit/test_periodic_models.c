/*
 * Periodic boundaries with every model of the explicit stepper (issue 38): heat sources and
 * pair terms beyond conduction, implicit conduction and the electric network across a
 * periodic face. The test throughout: a lattice straddling the face behaves as the
 * same lattice away from it (to round-off: the two runs hold the positions as different
 * doubles, so each difference x_j - x_i rounds differently; see test_periodic.c), and a
 * periodic column between two electrodes has the column's analytic resistance.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <sinter_submodel.h>

#include "periodic_cluster.h"

/* The heat models of one run (destroyed with the scene). */
typedef struct heat_set {
    sinter_heat_model *m[4];
} heat_set;

/*
 * A compressed 3x3x3 cluster with random velocities, spins and temperatures (300-400 K),
 * Hertz-Mindlin with friction, and four heat models: conduction with the gas lens around
 * contacts and between pairs apart (gas_reach), radiation and convection to 300 K over the
 * exposed surface only (the fraction not shaded by touching neighbours: a contact across the
 * face shades both owners), and the contacts' dissipation (a pair term: half to each end).
 * Its first corner at x = x0; periodic along x on [0, L) or not; `scheme` explicit or
 * implicit conduction.
 */
static void heat_scene(scene *s, heat_set *h, double x0, int periodic, int scheme)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.5);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 400.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_EMISSIVITY, 0.8));
    scene_open(s, "hertz_mindlin", 0);
    OK(sinter_heat_model_create(&h->m[0], s->ctx, "conduction"));
    OK(sinter_heat_model_set(h->m[0], "gas_conductivity", 0.026));
    OK(sinter_heat_model_set(h->m[0], "gas_reach", 0.5));
    OK(sinter_heat_model_create(&h->m[1], s->ctx, "radiation"));
    OK(sinter_heat_model_set(h->m[1], "temperature", 300.0));
    OK(sinter_heat_model_set(h->m[1], "exposed", 1.0));
    OK(sinter_heat_model_create(&h->m[2], s->ctx, "convection"));
    OK(sinter_heat_model_set(h->m[2], "temperature", 300.0));
    OK(sinter_heat_model_set(h->m[2], "h", 2000.0));
    OK(sinter_heat_model_set(h->m[2], "exposed", 1.0));
    OK(sinter_heat_model_create(&h->m[3], s->ctx, "dissipation"));
    for (int k = 0; k < 4; ++k)
        OK(sinter_stepper_add_heat(s->st, h->m[k]));
    OK(sinter_stepper_set_thermal_scheme(s->st, scheme));
    periodic_cluster_fill(s, x0, periodic, 2e-6);
}

static void heat_close(scene *s, heat_set *h)
{
    sinter_stepper_destroy(s->st); /* (it holds the models) */
    s->st = NULL;
    for (int k = 0; k < 4; ++k)
        sinter_heat_model_destroy(h->m[k]);
    scene_close(s);
}

/* The cluster after 100 steps: owned positions, temperatures, and each model's energy. */
static void run_heat(double x0, int periodic, int scheme, double *x, double *temp, double energy[4])
{
    scene s;
    heat_set h;
    heat_scene(&s, &h, x0, periodic, scheme);
    OK(sinter_stepper_step(s.st, 100));
    size_t owned = 0, count = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    OK(sinter_particles_count(s.ps, &count));
    assert_int_equal(owned, N);
    if (periodic)
        assert_true(count > owned); /* the cluster straddles the face */
    for (size_t i = 0; i < N; ++i) {
        get3(&s, SINTER_FIELD_POSITION, i, x + 3 * i);
        temp[i] = get1(&s, SINTER_FIELD_TEMPERATURE, i);
    }
    for (size_t k = 0; k < 4; ++k)
        OK(sinter_stepper_heat_energy(s.st, k, &energy[k]));
    heat_close(&s, &h);
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
 * The straddling cluster (x0 = -A: its first layer beyond the face x = 0) against the same
 * cluster in open space (x0 = 4 mm), with sources (radiation, convection: each particle once,
 * not again on its image) and pair terms (gas, dissipation: once per pair, the image's share
 * to its owner). Tolerances: positions 1e-13 m and temperatures `ttol` (explicit: 1e-9 K,
 * round-off of ~1e-13 K a step over 100 steps; implicit: 1e-7 K, the PCG's stopping test
 * 1e-13 |b| gives ~1e-10 K a step), the models' energies 1e-9 of the largest. A source counted on
 * an image too (radiation of a face particle is ~0.01 W, 0.5 K over the run), a missed gas
 * pair or a shade lost across the face would be off by orders more.
 */
static void straddle(int scheme, double ttol)
{
    double xa[3 * N], ta[N], ea[4], xb[3 * N], tb[N], eb[4];
    run_heat(-A, 1, scheme, xa, ta, ea);
    run_heat(4e-3, 0, scheme, xb, tb, eb);
    for (int i = 0; i < N; ++i) {
        assert_close(periodic_diff(xa[3 * i], xb[3 * i] - (4e-3 + A)), 0.0, 1e-13);
        for (int d = 1; d < 3; ++d)
            assert_close(xa[3 * i + d], xb[3 * i + d], 1e-13);
        assert_close(ta[i], tb[i], ttol);
    }
    /* conduction's total is 0 (antisymmetric pairs): the energies to 1e-9 of the largest */
    const double emax = fmax(fmax(fabs(eb[1]), fabs(eb[2])), fabs(eb[3]));
    for (int k = 0; k < 4; ++k)
        assert_close(ea[k], eb[k], 1e-9 * emax);
    assert_true(eb[3] > 0.0);                /* the contacts dissipated */
    assert_true(eb[1] < 0.0 && eb[2] < 0.0); /* radiation and convection cool it */
}

static void test_heat_sources_straddling(void **state)
{
    (void)state;
    straddle(SINTER_THERMAL_EXPLICIT, 1e-9);
}

static void test_implicit_conduction_straddling(void **state)
{
    (void)state;
    straddle(SINTER_THERMAL_IMPLICIT, 1e-7);
}

/* ---- the electric network ---------------------------------------------------------- */

enum { M = 4, NZ = 5 };                 /* columns per periodic axis, layers between electrodes */
static const double S = 1.96e-3;        /* lattice spacing [m] (x, y and z) */
static const double H = 0.97e-3;        /* a bottom or top centre's distance to its electrode [m] */
static const double SIGMA_E = 2.0e4;    /* electric conductivity [S/m] */
static const double VOLT = 1e-3;        /* the top electrode's potential; the bottom at 0 [V] */
static const double CELL = M * 1.96e-3; /* the period along x and y [m] */

/*
 * A column of M x M x NZ fixed spheres, periodic along x and y (the slab between two
 * electrodes: walls across z, the non-periodic axis, the only place a potential drop can be
 * imposed), its lattice shifted by (ox, oy) in the cell. Column (0, 0) may be of a second
 * material four times as conductive (`odd`), which makes current cross between columns,
 * also across the faces. With a "joule" heat model.
 */
static void column_scene(scene *s, sinter_electric_model **em, sinter_heat_model **joule, double ox,
                         double oy, int odd)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.5);
    OK(sinter_material_set(s->mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, SIGMA_E));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 400.0));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, SIGMA_E));
    scene_open(s, "hertz_mindlin", 0);
    sinter_material *second = NULL;
    OK(sinter_material_clone(&second, s->mat));
    OK(sinter_material_set(second, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 4.0 * SIGMA_E));
    OK(sinter_particles_set_material(s->ps, 1, second));
    sinter_material_destroy(second);
    const double top = 2.0 * H + (NZ - 1) * S;
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1}, p1[3] = {0, 0, top}, n1[3] = {0, 0, -1};
    OK(sinter_walls_add_plane(s->walls, p0, n0, s->wall_mat, NULL));
    OK(sinter_walls_add_plane(s->walls, p1, n1, s->wall_mat, NULL));
    OK(sinter_walls_set_electric(s->walls, 0, SINTER_WALL_POTENTIAL, 0.0));
    OK(sinter_walls_set_electric(s->walls, 1, SINTER_WALL_POTENTIAL, VOLT));
    OK(sinter_electric_model_create(em, s->ctx, "network"));
    OK(sinter_electric_model_set(*em, "tolerance", 1e-13));
    OK(sinter_stepper_set_electric(s->st, *em));
    OK(sinter_heat_model_create(joule, s->ctx, "joule"));
    OK(sinter_stepper_add_heat(s->st, *joule));
    OK(sinter_stepper_set_periodic(s->st, 0, 0.0, CELL));
    OK(sinter_stepper_set_periodic(s->st, 1, 0.0, CELL));
    for (int k = 0; k < M * M * NZ; ++k) {
        const int cx = k % M, cy = (k / M) % M, cz = k / (M * M);
        const double p[3] = {fmod(ox + S * (0.5 + cx), CELL), fmod(oy + S * (0.5 + cy), CELL),
                             H + S * cz};
        OK(sinter_particles_add(s->ps, 1, p, &R, odd && cx == 0 && cy == 0 ? 1 : 0, 300.0, NULL));
    }
    uint32_t *flags = NULL;
    OK(sinter_particles_view(s->ps, SINTER_FIELD_FLAGS, (void **)&flags, NULL, NULL));
    for (int k = 0; k < M * M * NZ; ++k)
        flags[k] = SINTER_PARTICLE_FIXED;
    OK(sinter_particles_release(s->ps, SINTER_FIELD_FLAGS));
    OK(sinter_stepper_set_dt(s->st, 1e-6));
}

static void column_close(scene *s, sinter_electric_model *em, sinter_heat_model *joule)
{
    sinter_stepper_destroy(s->st);
    s->st = NULL;
    sinter_electric_model_destroy(em);
    sinter_heat_model_destroy(joule);
    scene_close(s);
}

/*
 * The uniform column: every vertical chain carries V / R_chain with R_chain = 2 / G_w +
 * (NZ - 1) / G_p, G_p = sigma pi a_p^2 / S (a_p^2 = R^2 - S^2 / 4, seed 000 eq. 7 for equal
 * spheres) and G_w = sigma pi a_w^2 / H (a_w^2 = R^2 - H^2); the lateral contacts, across the
 * faces too, carry nothing (equal potentials layer by layer). The walls supply V^2 M^2 /
 * R_chain, all of it Joule heat in the particles (the "joule" model's energy over the first
 * step). Tolerance 1e-9 relative: the solve stops at 1e-13 of the right-hand side's norm and
 * the closed form is a few operations.
 */
static void test_periodic_column_resistance(void **state)
{
    (void)state;
    scene s;
    sinter_electric_model *em = NULL;
    sinter_heat_model *joule = NULL;
    column_scene(&s, &em, &joule, 0.0, 0.0, 0);
    OK(sinter_stepper_step(s.st, 1));
    double supplied = 0.0, dissipated = 0.0, energy = 0.0;
    OK(sinter_electric_model_power(em, &supplied, &dissipated));
    OK(sinter_stepper_heat_energy(s.st, 0, &energy));
    const double pi = 3.14159265358979323846;
    const double gp = SIGMA_E * pi * (R * R - 0.25 * S * S) / S;
    const double gw = SIGMA_E * pi * (R * R - H * H) / H;
    const double chain = 2.0 / gw + (NZ - 1) / gp;
    const double expect = VOLT * VOLT * M * M / chain;
    size_t owned = 0, count = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    OK(sinter_particles_count(s.ps, &count));
    assert_true(count > owned); /* images across the faces */
    assert_close(supplied, expect, 1e-9 * expect);
    assert_close(dissipated, expect, 1e-9 * expect);
    assert_close(energy / 1e-6, expect, 1e-9 * expect);
    /* every particle carries its chain's current: V / R_chain */
    const double *current = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_CURRENT, (const void **)&current, NULL, NULL));
    for (size_t i = 0; i < owned; ++i)
        assert_close(current[i], VOLT / chain, 1e-9 * VOLT / chain);
    OK(sinter_particles_release(s.ps, SINTER_FIELD_CURRENT));
    column_close(&s, em, joule);
}

/* The column with its odd chain, lattice offset (ox, oy): each particle's current (by index:
 * the same particle in both runs) and temperature after 3 steps, the supplied power. */
static double run_column(double ox, double oy, double *current, double *temp)
{
    scene s;
    sinter_electric_model *em = NULL;
    sinter_heat_model *joule = NULL;
    column_scene(&s, &em, &joule, ox, oy, 1);
    OK(sinter_stepper_step(s.st, 3));
    double supplied = 0.0, dissipated = 0.0;
    OK(sinter_electric_model_power(em, &supplied, &dissipated));
    for (size_t i = 0; i < M * M * NZ; ++i) {
        current[i] = get1(&s, SINTER_FIELD_CURRENT, i);
        temp[i] = get1(&s, SINTER_FIELD_TEMPERATURE, i);
    }
    column_close(&s, em, joule);
    return supplied;
}

/*
 * Current between columns across the faces: the odd chain (four times as conductive) draws
 * current from its neighbours, and half of them lie across a face when the lattice starts at
 * the cell's corner, none when it is shifted by 1.5 columns (the odd chain then in the
 * middle). Both runs must agree: currents to 1e-9 relative (the solve's tolerance, 1e-13 of
 * the right-hand side, in two different orders of the same network) and the Joule-heated
 * temperatures to 1e-9 K. An image that did not stand for its owner (a node of its own, or
 * none) would leave the odd chain's neighbours across the face without that current.
 */
static void test_periodic_column_shifted(void **state)
{
    (void)state;
    enum { P = M * M * NZ };
    double ca[P], ta[P], cb[P], tb[P];
    const double pa = run_column(0.0, 0.0, ca, ta);
    const double pb = run_column(1.5 * S, 1.5 * S, cb, tb);
    double cmax = 0.0, spread = 0.0;
    for (int i = 0; i < P; ++i) {
        cmax = fmax(cmax, fabs(cb[i]));
        spread = fmax(spread, fabs(cb[i] - cb[NZ / 2 * M * M + 1])); /* vs a plain chain */
    }
    assert_true(spread > 0.1 * cmax); /* the odd chain does change the currents */
    assert_close(pa, pb, 1e-9 * pb);
    for (int i = 0; i < P; ++i) {
        assert_close(ca[i], cb[i], 1e-9 * cmax);
        assert_close(ta[i], tb[i], 1e-9);
    }
}

/* The averaged electric model is refused with periodic axes (it has no potential an image
 * could share), with a message; the network is not. */
static void test_periodic_averaged_refused(void **state)
{
    (void)state;
    scene s;
    sinter_electric_model *em = NULL;
    sinter_heat_model *joule = NULL;
    column_scene(&s, &em, &joule, 0.0, 0.0, 0);
    sinter_electric_model *avg = NULL;
    OK(sinter_electric_model_create(&avg, s.ctx, "averaged"));
    OK(sinter_stepper_set_electric(s.st, avg));
    assert_int_equal(sinter_stepper_step(s.st, 1), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(s.ctx), "averaged"));
    OK(sinter_stepper_set_electric(s.st, em));
    OK(sinter_stepper_step(s.st, 1));
    sinter_electric_model_destroy(avg);
    column_close(&s, em, joule);
}

/* ---- bonds that hold in tension, and the domain check ------------------------------------ */

/* Two power-law spheres (bonds that hold in tension: test_bond_tension.c's held springback)
 * centred on x = c, colliding at +-0.3 m/s; the centre gap d - 2 R after each of 6000 steps
 * (1 us) into gap[]. Skin 20 um, so that the bonded pair, pulled apart by up to E_b 2 R =
 * 0.4 mm, leaves the neighbour reach and is kept as a held pair. */
static void bonded_pair(double c, int periodic, double *gap, int steps)
{
    const double kb = 1e6, pb = 1.5, strength = kb * pow(0.2, pb);
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500.0, 0.0, 0.0);
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_STIFFNESS, 1e7));
    OK(sinter_material_set(s.mat, SINTER_MAT_CONTACT_EXPONENT, 2.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_STIFFNESS, kb));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_EXPONENT, pb));
    OK(sinter_material_set(s.mat, SINTER_MAT_BOND_CRITICAL_STRAIN, 0.05));
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_walls_create(&s.walls, s.ctx));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_EXPLICIT, s.ps, s.walls));
    OK(sinter_force_model_create(&s.contact, s.ctx, "power_law"));
    OK(sinter_force_model_set(s.contact, "bond_strength", strength));
    OK(sinter_stepper_add_force(s.st, s.contact));
    OK(sinter_stepper_set_skin(s.st, 2e-5));
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    if (periodic)
        OK(sinter_stepper_set_periodic(s.st, 0, 0.0, L));
    scene_add(&s, c - 1.5 * R, 0, 0, R);
    scene_add(&s, c + 1.5 * R, 0, 0, R);
    const double va[3] = {0.3, 0, 0}, vb[3] = {-0.3, 0, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, va);
    set3(&s, SINTER_FIELD_VELOCITY, 1, vb);
    for (int k = 0; k < steps; ++k) {
        OK(sinter_stepper_step(s.st, 1));
        double x0[3], x1[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x0);
        get3(&s, SINTER_FIELD_POSITION, 1, x1);
        gap[k] = periodic_diff(x1[0], x0[0]) - 2.0 * R;
    }
    sinter_stepper_stats stats = {.struct_size = sizeof(stats)};
    OK(sinter_stepper_get_stats(s.st, &stats));
    assert_int_equal(stats.bonds_broken, 0);
    scene_close(&s);
}

/*
 * A bond across the face: the pair collides across x = 0 of the periodic cell, bonds (overlap
 * past E* = 0.05) and springs back against the bond's tension, which keeps the gap below
 * E_b 2 R (test_bond_tension.c's energy argument); the same pair away from the face must give
 * the same gaps step by step to round-off (1e-13 m: positions a few ulp(1e-2 m) apart over 6000
 * steps). A bond kept to the far end's owner, a period away, would pull the pair apart with a
 * force ~ K_b E^1.5 A_b at E ~ 5, or drop the bond's tension: gaps off by far more.
 */
static void test_bond_across_face(void **state)
{
    (void)state;
    enum { STEPS = 6000 };
    static double ga[STEPS], gb[STEPS];
    bonded_pair(0.0, 1, ga, STEPS);
    bonded_pair(5e-3, 0, gb, STEPS);
    double largest = -INFINITY, smallest = INFINITY; /* largest: after the bond formed */
    for (int k = 0; k < STEPS; ++k) {
        if (smallest < -0.05 * 2.0 * R)
            largest = fmax(largest, gb[k]);
        smallest = fmin(smallest, gb[k]);
        assert_close(ga[k], gb[k], 1e-13);
    }
    assert_true(smallest < -0.05 * 2.0 * R); /* the bond formed */
    assert_true(largest > 2e-5);             /* pulled past the skin: a held pair */
    assert_true(largest < 0.2 * 2.0 * R);    /* and held */
}

/* The domain check with a periodic axis: along it the particles wrap (and their images lie
 * outside the cell), so only the other axes are checked. A sphere crossing the face x = L
 * stays; one leaving the domain along z is refused (SINTER_ERR_LOST_PARTICLE). */
static void test_domain_with_periodic_axis(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.5);
    scene_open(&s, "hertz_mindlin", 0);
    OK(sinter_stepper_set_periodic(s.st, 0, 0.0, L));
    const double lo[3] = {0.0, -5e-3, -5e-3}, hi[3] = {L, 5e-3, 5e-3};
    OK(sinter_stepper_set_domain(s.st, lo, hi));
    scene_add(&s, L - 0.2e-3, 0, 0, R);
    const double u[3] = {1.0, 0.0, 0.0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, u);
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    OK(sinter_stepper_step(s.st, 100)); /* 1 mm along x: across the face */
    double x[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    assert_true(x[0] < 2e-3); /* wrapped */
    const double up[3] = {0.0, 0.0, 10.0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, up);
    assert_int_equal(sinter_stepper_step(s.st, 100), SINTER_ERR_LOST_PARTICLE);
    scene_close(&s);
}

/*
 * Continuous insertion into a cell periodic along x and y, from a region wider than the cell
 * (0.5 mm beyond each periodic face, so that places a period apart are the same place): spheres
 * are inserted until the region crowds, and no pair may overlap, measured to the nearest image
 * (a sphere placed beyond a face is wrapped onto the other side, where an image of another
 * already is, unless the placement measures across the face). Every velocity stays exactly 0
 * (no contact ever formed) and every centre ends in the cell.
 */
static void test_insertion_periodic(void **state)
{
    (void)state;
    const double half = 1e-3, cell = 2.0 * half;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.5, 0.3);
    scene_open(&s, "hertz_mindlin", 0);
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1}, p1[3] = {0, 0, cell}, n1[3] = {0, 0, -1};
    OK(sinter_walls_add_plane(s.walls, p0, n0, s.wall_mat, NULL));
    OK(sinter_walls_add_plane(s.walls, p1, n1, s.wall_mat, NULL));
    OK(sinter_stepper_set_periodic(s.st, 0, -half, half));
    OK(sinter_stepper_set_periodic(s.st, 1, -half, half));
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    sinter_packing_options p;
    OK(sinter_packing_options_init(&p, sizeof(p)));
    p.distribution = SINTER_RADII_LOGNORMAL;
    p.radius_median = 1e-4;
    p.radius_gsd = 1.3;
    p.seed = 38;
    p.max_attempts = 200;
    for (int d = 0; d < 2; ++d) {
        p.box_min[d] = -half - 0.5e-3;
        p.box_max[d] = half + 0.5e-3;
    }
    p.box_min[2] = 0.0;
    p.box_max[2] = cell;
    sinter_insertion_options o;
    OK(sinter_insertion_options_init(&o, sizeof(o)));
    o.mass_rate = 1e-2; /* far more than fits: the cell crowds */
    o.interval = 1e-4;
    o.end = 1e-3;
    OK(sinter_stepper_set_insertion(s.st, &p, &o));
    OK(sinter_stepper_advance(s.st, 1e-3));
    uint64_t n = 0, crowded = 0;
    OK(sinter_stepper_get_insertion(s.st, NULL, NULL, &n, &crowded));
    assert_true(n > 50);
    assert_true(crowded > 0);
    size_t owned = 0;
    OK(sinter_particles_owned_count(s.ps, &owned));
    assert_int_equal(owned, n);
    const double *x = NULL, *v = NULL, *r = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL));
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
    for (size_t i = 0; i < owned; ++i) {
        for (int d = 0; d < 3; ++d)
            assert_true(v[3 * i + d] == 0.0);
        for (int d = 0; d < 2; ++d) /* wrapped (up to half the skin) */
            assert_true(x[3 * i + d] > -half - r[i] && x[3 * i + d] < half + r[i]);
        for (size_t j = 0; j < i; ++j) {
            double e[3];
            for (int d = 0; d < 3; ++d) {
                e[d] = x[3 * i + d] - x[3 * j + d];
                if (d < 2)
                    e[d] -= cell * nearbyint(e[d] / cell);
            }
            assert_true(sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) >= r[i] + r[j]);
        }
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_RADIUS));
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_heat_sources_straddling),
        cmocka_unit_test(test_implicit_conduction_straddling),
        cmocka_unit_test(test_periodic_column_resistance),
        cmocka_unit_test(test_periodic_column_shifted),
        cmocka_unit_test(test_periodic_averaged_refused),
        cmocka_unit_test(test_bond_across_face),
        cmocka_unit_test(test_domain_with_periodic_axis),
        cmocka_unit_test(test_insertion_periodic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
