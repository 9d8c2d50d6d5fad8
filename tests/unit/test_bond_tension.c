/*
 * Bonds that hold in tension (power law option bond_strength, force/power_law.c): a bond formed
 * by seed 000's criterion (eq. 18-19, |E| >= E*) carries f = K_b E^p_b A_b towards the partner
 * when the pair is pulled apart (E = (d - S) / S > 0, S = R_i + R_j, A_b the largest contact
 * area the bonded pair reached) until K_b E^p_b exceeds the strength, then breaks for good and
 * is counted once in sinter_stepper_stats.bonds_broken.
 *
 * Tolerances: the forces are compared with the same closed form evaluated by hand from the
 * same positions; where a step must not move the particles they are heavy (1e6 kg/m^3) and the
 * step short (1 ns), so the area recorded at the committing step equals the hand area to
 * ~1e-13 (displacement a dt^2 / 2 ~ 1e-18 m for a ~ 2 m/s^2, against |E| S ~ 1e-4 m); 1e-9
 * relative leaves a wide margin while catching any wrong factor.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;
static const double R = 1e-3, KP = 1e7, KB = 1e6, PB = 1.5, ESTAR = 0.05;
static const double REL = 1e-9;

/* Two spheres of radius R on the x axis with a power law of bond_strength `strength` [Pa]
 * (0: the seed's bonds only), density rho, Verlet skin `skin` [m], step dt [s]. */
static void open_pair_soft(scene *s, double strength, double rho, double skin, double dt,
                           int soften);

static void open_pair(scene *s, double strength, double rho, double skin, double dt)
{
    open_pair_soft(s, strength, rho, skin, dt, 0);
}

/* soften: 0 no softening; 1 the material softens (linear law, E/E_0 = 1 - theta / 1600 K) and
 * bond_softening is 1; 2 the material softens, bond_softening 0. */
static void open_pair_soft(scene *s, double strength, double rho, double skin, double dt,
                           int soften)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, rho, 0.0, 0.0);
    if (soften) {
        OK(sinter_material_set(s->mat, SINTER_MAT_SOFTENING_LAW, 1.0));
        OK(sinter_material_set(s->mat, SINTER_MAT_SOFTENING_TEMPERATURE, 1600.0));
        OK(sinter_material_set(s->mat, SINTER_MAT_SOFTENING_FLOOR, 0.01));
    }
    OK(sinter_material_set(s->mat, SINTER_MAT_CONTACT_STIFFNESS, KP));
    OK(sinter_material_set(s->mat, SINTER_MAT_CONTACT_EXPONENT, 2.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_BOND_STIFFNESS, KB));
    OK(sinter_material_set(s->mat, SINTER_MAT_BOND_EXPONENT, PB));
    OK(sinter_material_set(s->mat, SINTER_MAT_BOND_CRITICAL_STRAIN, ESTAR));
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_walls_create(&s->walls, s->ctx));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_EXPLICIT, s->ps, s->walls));
    OK(sinter_stepper_set_option(s->st, "thread_choice", 0));
    OK(sinter_force_model_create(&s->contact, s->ctx, "power_law"));
    /* the history width follows the option: set it before the model joins the stepper */
    OK(sinter_force_model_set(s->contact, "bond_strength", strength));
    OK(sinter_force_model_set(s->contact, "bond_softening", soften == 1 ? 1.0 : 0.0));
    OK(sinter_stepper_add_force(s->st, s->contact));
    OK(sinter_stepper_set_skin(s->st, skin));
    OK(sinter_stepper_set_dt(s->st, dt));
    scene_add(s, 0, 0, 0, R);
    scene_add(s, 3.0 * R, 0, 0, R);
}

/* Particle 1 at centre distance S (1 + e) from particle 0 (e < 0: overlap), both at rest. */
static void place(scene *s, double e)
{
    const double x0[3] = {0, 0, 0}, x1[3] = {2.0 * R * (1.0 + e), 0, 0}, zero[3] = {0};
    set3(s, SINTER_FIELD_POSITION, 0, x0);
    set3(s, SINTER_FIELD_POSITION, 1, x1);
    set3(s, SINTER_FIELD_VELOCITY, 0, zero);
    set3(s, SINTER_FIELD_VELOCITY, 1, zero);
}

/* Contact area pi a^2 of equal spheres at overlap strain |E| (eq. 11-12: L = R (1 - |E|)). */
static double area_at(double strain)
{
    const double l = R * (1.0 - strain);
    return PI * (R * R - l * l);
}

static uint64_t broken(scene *s)
{
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s->st, &stats));
    return stats.bonds_broken;
}

static double force_x(scene *s, size_t i)
{
    double f[3];
    get3(s, SINTER_FIELD_FORCE, i, f);
    return f[0];
}

/* Bond at |E| = 0.06 (A_b = its area), then pulled apart in steps of E = 0.0007: the force is
 * K_b E^1.5 A_b towards the partner until K_b E^1.5 > strength (E_b = 0.01 here), then 0; the
 * break is counted once. */
static void test_pull_apart_until_strength(void **state)
{
    (void)state;
    const double eb = 0.01, strength = KB * pow(eb, PB);
    scene s;
    open_pair(&s, strength, 1e6, 2e-4, 1e-9);
    place(&s, -0.06);
    OK(sinter_stepper_step(s.st, 1)); /* commits the bond (|E| >= E*) */
    const double ab = area_at(0.06);
    assert_int_equal(broken(&s), 0);
    int broke_at = -1;
    for (int k = 1; k <= 25; ++k) {
        const double e = 0.0007 * k;
        place(&s, e);
        OK(sinter_stepper_evaluate(s.st));
        const double f0 = force_x(&s, 0), f1 = force_x(&s, 1);
        const double expect = KB * pow(e, PB) * ab <= strength * ab ? KB * pow(e, PB) * ab : 0.0;
        if (k < 3 || k == 14 || (expect == 0.0 && broke_at < 0))
            print_message("E = %.4f: f = %.9e N, closed form %.9e N\n", e, f0, expect);
        assert_close(f0, expect, REL * KB * pow(eb, PB) * ab); /* towards particle 1: +x */
        assert_close(f1, -f0, 1e-15 * fabs(f0) + 1e-300);
        OK(sinter_stepper_step(s.st, 1));
        if (expect == 0.0 && broke_at < 0)
            broke_at = k;
        assert_int_equal(broken(&s), expect == 0.0 ? 1 : 0);
    }
    assert_int_equal(broke_at, 15); /* 0.0007 * 15 = 0.0105: the first past E_b = 0.01 */
    /* a caller built before bonds_broken was appended gets the fields it knows only */
    sinter_stepper_stats older;
    memset(&older, 0xab, sizeof(older));
    older.struct_size = offsetof(sinter_stepper_stats, bonds_broken);
    OK(sinter_stepper_get_stats(s.st, &older));
    assert_int_equal(older.steps, 26);
    assert_int_equal(older.bonds_broken, 0xababababababababull);
    /* Back in contact below E*: no bond, the seed's contact force alone (eq. 2). */
    place(&s, -0.02);
    OK(sinter_stepper_evaluate(s.st));
    assert_close(force_x(&s, 0), -KP * 0.02 * 0.02 * area_at(0.02),
                 REL * KP * 0.02 * 0.02 * area_at(0.02));
    assert_int_equal(broken(&s), 1);
    scene_close(&s);
}

/* A bonded pair pulled past the Verlet skin stays a candidate (the rebuild keeps it): the
 * tension force is still there after the rebuild. */
static void test_bond_kept_beyond_skin(void **state)
{
    (void)state;
    const double skin = 2e-6, strength = KB * pow(0.05, PB);
    scene s;
    open_pair(&s, strength, 1e6, skin, 1e-9);
    place(&s, -0.06);
    OK(sinter_stepper_step(s.st, 1));
    sinter_stepper_stats before = {.struct_size = sizeof(sinter_stepper_stats)};
    OK(sinter_stepper_get_stats(s.st, &before));
    const double e = 0.01; /* gap 2e-5 m = 10 skins */
    place(&s, e);
    OK(sinter_stepper_step(s.st, 1));
    OK(sinter_stepper_evaluate(s.st));
    sinter_stepper_stats after = {.struct_size = sizeof(sinter_stepper_stats)};
    OK(sinter_stepper_get_stats(s.st, &after));
    assert_true(after.neighbor_builds > before.neighbor_builds);
    const double expect = KB * pow(e, PB) * area_at(0.06);
    print_message("beyond the skin: f = %.9e N, closed form %.9e N, builds %llu -> %llu\n",
                  force_x(&s, 0), expect, (unsigned long long)before.neighbor_builds,
                  (unsigned long long)after.neighbor_builds);
    assert_close(force_x(&s, 0), expect, REL * expect);
    assert_int_equal(after.contacts, 1); /* the held pair is a contact (area 0) */
    assert_int_equal(after.bonds_broken, 0);
    scene_close(&s);
}

/* Largest centre gap d - S after an impact at relative speed 2 v0 and `steps` steps. */
static double rebound_gap(double strength, int steps, double *final_gap, uint64_t *breaks)
{
    const double v0 = 0.3;
    scene s;
    open_pair(&s, strength, 2500.0, 2e-4, 1e-6);
    place(&s, 0.0);
    const double va[3] = {v0, 0, 0}, vb[3] = {-v0, 0, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, va);
    set3(&s, SINTER_FIELD_VELOCITY, 1, vb);
    double largest = 0.0, gap = 0.0;
    int touched = 0;
    for (int k = 0; k < steps; ++k) {
        OK(sinter_stepper_step(s.st, 1));
        double x0[3], x1[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x0);
        get3(&s, SINTER_FIELD_POSITION, 1, x1);
        gap = x1[0] - x0[0] - 2.0 * R;
        touched |= gap < -ESTAR * 2.0 * R; /* the bond's criterion was reached */
        if (touched && gap > largest)
            largest = gap;
    }
    assert_true(touched);
    *final_gap = gap;
    *breaks = broken(&s);
    scene_close(&s);
    return largest;
}

/*
 * Springback of a compressed-then-released pair. Energy argument: without friction or damping
 * the law is conservative along each leg, and the bond only takes energy (it attracts over the
 * whole way out but only from E* on the way in), so the relative kinetic energy when the
 * contact opens is at most the initial m v0^2 (equal masses m, speeds +-v0). A holding bond's
 * tension well is W_b = K_b A_b S E_b^(p_b+1) / (p_b + 1) deep, with A_b >= the area at E*; when
 * W_b > m v0^2 the pair cannot separate past E_b: its gap stays below E_b S, while without
 * holding bonds it springs back freely (gap growing at the exit speed).
 */
static void test_springback_less_with_holding_bonds(void **state)
{
    (void)state;
    const double v0 = 0.3, eb = 0.2, strength = KB * pow(eb, PB), s2 = 2.0 * R;
    const double m = 2500.0 * 4.0 / 3.0 * PI * R * R * R;
    const double well = KB * area_at(ESTAR) * s2 * pow(eb, PB + 1.0) / (PB + 1.0);
    print_message("m v0^2 = %.3e J < tension well >= %.3e J\n", m * v0 * v0, well);
    assert_true(well > m * v0 * v0); /* the premise of the argument */
    const int steps = 6000;          /* 6 ms: about ten contact periods */
    double free_final, held_final;
    uint64_t free_breaks, held_breaks;
    const double free_gap = rebound_gap(0.0, steps, &free_final, &free_breaks);
    const double held_gap = rebound_gap(strength, steps, &held_final, &held_breaks);
    print_message("largest gap after the impact: %.4e m without, %.4e m with holding bonds "
                  "(bound E_b S = %.4e m); final %.4e m, %.4e m\n",
                  free_gap, held_gap, eb * s2, free_final, held_final);
    assert_true(held_gap < eb * s2);
    assert_int_equal(held_breaks, 0);
    assert_int_equal(free_breaks, 0);  /* the seed's bonds are not counted */
    assert_true(free_final > eb * s2); /* flew apart */
    assert_true(held_final < free_final);
}

/* With bond_softening the stiffness in tension is K_b times the pair's softening factor: at
 * 800 K the linear law gives E/E_0 = 1 - 800 / 1600 = 0.5, so at E = 0.012 the force is
 * 0.5 K_b E^1.5 A_b and the bond holds (breaks at E_b = 0.01 * 2^(1/1.5) = 0.0159), while
 * without it the stress K_b E^1.5 exceeds the strength (E_b = 0.01) and the bond breaks. */
static void test_softened_bond_stiffness(void **state)
{
    (void)state;
    const double e = 0.012, strength = KB * pow(0.01, PB);
    for (int soften = 1; soften <= 2; ++soften) {
        scene s;
        open_pair_soft(&s, strength, 1e6, 2e-4, 1e-9, soften);
        for (size_t i = 0; i < 2; ++i) {
            double *t = NULL;
            OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&t, NULL, NULL));
            t[i] = 800.0;
            OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE));
        }
        place(&s, -0.06);
        OK(sinter_stepper_step(s.st, 1));
        place(&s, e);
        OK(sinter_stepper_evaluate(s.st));
        const double expect = soften == 1 ? 0.5 * KB * pow(e, PB) * area_at(0.06) : 0.0;
        print_message("bond_softening %d at 800 K, E = %.3f: f = %.9e N, closed form %.9e N\n",
                      soften == 1, e, force_x(&s, 0), expect);
        assert_close(force_x(&s, 0), expect, REL * KB * pow(e, PB) * area_at(0.06));
        OK(sinter_stepper_step(s.st, 1));
        assert_int_equal(broken(&s), soften == 1 ? 0 : 1);
        scene_close(&s);
    }
}

/* Two particles meeting at +-0.3 m/s, with holding bonds that break at E_b = eb, skin `skin`. */
static void impact(scene *s, double eb, double skin)
{
    open_pair(s, KB * pow(eb, PB), 2500.0, skin, 1e-6);
    place(s, 0.0);
    const double va[3] = {0.3, 0, 0}, vb[3] = {-0.3, 0, 0};
    set3(s, SINTER_FIELD_VELOCITY, 0, va);
    set3(s, SINTER_FIELD_VELOCITY, 1, vb);
}

static void state_of(scene *s, double out[12])
{
    get3(s, SINTER_FIELD_POSITION, 0, out);
    get3(s, SINTER_FIELD_POSITION, 1, out + 3);
    get3(s, SINTER_FIELD_VELOCITY, 0, out + 6);
    get3(s, SINTER_FIELD_VELOCITY, 1, out + 9);
}

/* A restart continues bit for bit: the bond flag and area are contact history (the checkpoint
 * keeps it and the pair list with the held pairs), the count is in the checkpoint (version 10).
 * Two runs: a bond that breaks on the way out after the checkpoint (eb = 0.03: its tension well
 * is far below the impact's energy) and one that holds, apart beyond a skin of 2 um, across
 * rebuilds (eb = 0.2). */
static void test_restart_bit_for_bit(void **state)
{
    (void)state;
    const double ebs[2] = {0.03, 0.2};
    const uint64_t expect_breaks[2] = {1, 0};
    char dir[] = "/tmp/sinter_bonds_XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof(path), "%s/state.bin", dir);
    for (int c = 0; c < 2; ++c) {
        scene a, b;
        impact(&a, ebs[c], 2e-6);
        OK(sinter_stepper_step(a.st, 200)); /* bonded, in compression */
        OK(sinter_checkpoint_write(a.st, path));
        OK(sinter_stepper_step(a.st, 1800));
        impact(&b, ebs[c], 2e-6);
        OK(sinter_checkpoint_read(b.st, path));
        OK(sinter_stepper_step(b.st, 1800));
        double xa[12], xb[12];
        state_of(&a, xa);
        state_of(&b, xb);
        print_message("E_b = %.2f: gap %.4e m, broken %llu\n", ebs[c], xa[3] - xa[0] - 2.0 * R,
                      (unsigned long long)broken(&a));
        assert_memory_equal(xa, xb, sizeof(xa));
        assert_int_equal(broken(&a), expect_breaks[c]);
        assert_int_equal(broken(&b), expect_breaks[c]);
        scene_close(&a);
        scene_close(&b);
    }
    remove(path);
    rmdir(dir);
}

/* A 16^3 lattice at |E| = 0.06 (every neighbour bonds at the first step) thrown apart by
 * velocities of up to 2 m/s per component (a fixed pseudo-random sequence), 100 steps on
 * `threads` threads: the final state and the broken-bond count. Over 4096 pairs, so the contact
 * search runs its threaded passes. */
static uint64_t lattice_run(int threads, double *x, size_t *held)
{
    enum { M = 16, N = M * M * M };
    scene s;
    open_pair(&s, KB * pow(0.02, PB), 2500.0, 2e-4, 1e-6);
    OK(sinter_ctx_set_threads(s.ctx, threads));
    uint64_t lcg = 12345u;
    const double a = 2.0 * R * (1.0 - 0.06);
    for (size_t k = 2; k < N; ++k)
        scene_add(&s, 0, 0, 0, R);
    double *p = NULL, *v = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_POSITION, (void **)&p, NULL, NULL));
    for (size_t k = 0; k < N; ++k) {
        p[3 * k] = a * (double)(k % M);
        p[3 * k + 1] = a * (double)((k / M) % M);
        p[3 * k + 2] = a * (double)(k / (M * M));
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    OK(sinter_particles_view(s.ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    for (size_t k = 0; k < 3 * N; ++k) {
        lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
        v[k] = 2.0 * ((double)(lcg >> 11) / 9007199254740992.0 * 2.0 - 1.0);
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_VELOCITY));
    OK(sinter_stepper_step(s.st, 100));
    const double *xr = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&xr, NULL, NULL));
    memcpy(x, xr, 3 * N * sizeof(double));
    /* bonded pairs apart: contacts whose centres are farther than 2 R */
    *held = 0;
    sinter_stepper_stats stats = {.struct_size = sizeof(sinter_stepper_stats)};
    OK(sinter_stepper_get_stats(s.st, &stats));
    size_t overlapping = 0;
    for (size_t i = 0; i < N; ++i)
        for (size_t j = i + 1; j < N && j < i + M * M + 2; ++j) {
            const double dx = xr[3 * j] - xr[3 * i], dy = xr[3 * j + 1] - xr[3 * i + 1],
                         dz = xr[3 * j + 2] - xr[3 * i + 2];
            overlapping += dx * dx + dy * dy + dz * dz < 4.0 * R * R;
        }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    *held = stats.contacts > overlapping ? stats.contacts - overlapping : 0;
    const uint64_t breaks = broken(&s);
    scene_close(&s);
    return breaks;
}

/* The same bits on 1 and 2 threads (the determinism the library keeps for every contact law). */
static void test_threads_same_bits(void **state)
{
    (void)state;
    enum { N = 16 * 16 * 16 };
    double *x1 = malloc(3 * N * sizeof(double)), *x2 = malloc(3 * N * sizeof(double));
    assert_non_null(x1);
    assert_non_null(x2);
    size_t held1 = 0, held2 = 0;
    const uint64_t b1 = lattice_run(1, x1, &held1), b2 = lattice_run(2, x2, &held2);
    print_message("lattice: %llu bonds broken, %zu held apart (1 thread); %llu, %zu (2)\n",
                  (unsigned long long)b1, held1, (unsigned long long)b2, held2);
    assert_true(b1 > 0);
    assert_true(held1 > 0);
    assert_int_equal(b1, b2);
    assert_int_equal(held1, held2);
    assert_memory_equal(x1, x2, 3 * N * sizeof(double));
    free(x1);
    free(x2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pull_apart_until_strength),
        cmocka_unit_test(test_bond_kept_beyond_skin),
        cmocka_unit_test(test_softened_bond_stiffness),
        cmocka_unit_test(test_springback_less_with_holding_bonds),
        cmocka_unit_test(test_restart_bit_for_bit),
        cmocka_unit_test(test_threads_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
