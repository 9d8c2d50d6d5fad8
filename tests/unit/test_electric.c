/*
 * Electric submodels (seed 000 sec. 5) and Joule heating (eq. 35, 50), evaluated directly on
 * real contact lists: particles and walls are built through the public API, the contact lists
 * with the neighbour grid, then sinter_electric_solve() / the heat model's eval are called.
 *
 * How the two electric models differ (what these tests pin down):
 *  - "averaged" is seed 000's model: a current MAGNITUDE imposed by the current walls and
 *    propagated by contact-area-weighted averaging (eq. 42-43). It smooths the wall values and
 *    does not conserve charge: between walls of 2 A and 8 A a chain goes linearly from 2 to 8
 *    (remark 4), and two parallel chains both carry the full wall value.
 *  - "network" solves Kirchhoff's current law on the contact resistors (eq. 39 exactly): a
 *    chain carries one current, V / (sum of resistances), and parallel chains split it in
 *    proportion to their conductances.
 *
 * Tolerances: closed forms are a few floating-point operations (1e-12 relative). Iterative
 * results are compared at a tolerance derived from the solver's own stopping test, stated at
 * each check.
 */
#include <string.h>

#include "test_support.h"
#include "sinter_submodel.h"
#include "contact/contacts.h"
#include "contact/snapshot.h"
#include "electric/electric.h"
#include "heat/heat_model.h"
#include "particles/particles.h"
#include "stepper/stepper.h"
#include "walls/walls.h"

#define OK(call) assert_int_equal((call), SINTER_OK)
#define assert_rel(a, b, rel) assert_close((a), (b), (rel)*fabs(b))

static const double PI = 3.14159265358979323846;
static const double R = 1e-3;              /* particle radius [m] */
static const double SIGMA[2] = {2.0, 5.0}; /* electric conductivity [S/m] */
static const double ABSORPTANCE[2] = {0.5, 0.8};

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_neighbors nb;
    sinter_contact_list pp, pw;
    sinter_electric_model *em;
    int warnings;
} fixture;

static void count_warnings(int level, const char *message, void *user)
{
    (void)message;
    if (level == SINTER_LOG_WARNING)
        ++*(int *)user;
}

/* Material 0: sigma 2 S/m, a 0.5; material 1: sigma 5 S/m, a 0.8; material 2: sigma 0. */
static void open_fixture(fixture *f)
{
    memset(f, 0, sizeof(*f));
    OK(sinter_ctx_create(&f->ctx, NULL));
    OK(sinter_ctx_set_log(f->ctx, count_warnings, SINTER_LOG_WARNING, &f->warnings));
    OK(sinter_particles_create(&f->ps, f->ctx));
    OK(sinter_walls_create(&f->walls, f->ctx));
    for (int m = 0; m < 3; ++m) {
        sinter_material *mat;
        OK(sinter_material_create(&mat, f->ctx, NULL));
        if (m < 2) {
            OK(sinter_material_set(mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, SIGMA[m]));
            OK(sinter_material_set(mat, SINTER_MAT_ABSORPTANCE, ABSORPTANCE[m]));
        }
        OK(sinter_particles_set_material(f->ps, m, mat));
        sinter_material_destroy(mat);
    }
    sinter_neighbors_init(&f->nb, f->ctx, 1e-4);
}

static void close_fixture(fixture *f)
{
    sinter_electric_model_destroy(f->em);
    sinter_contact_list_free(f->ctx, &f->pp);
    sinter_contact_list_free(f->ctx, &f->pw);
    sinter_neighbors_free(&f->nb);
    sinter_walls_destroy(f->walls);
    sinter_particles_destroy(f->ps);
    sinter_ctx_destroy(f->ctx);
}

static void add(fixture *f, double x, double y, double z, int32_t mat)
{
    const double p[3] = {x, y, z}, r = R;
    OK(sinter_particles_add(f->ps, 1, p, &r, mat, 300.0, NULL));
}

static size_t add_wall(fixture *f, double x, double nx, int mode, double value)
{
    const double p[3] = {x, 0, 0}, n[3] = {nx, 0, 0};
    sinter_material *wm;
    size_t k;
    OK(sinter_material_create(&wm, f->ctx, NULL));
    OK(sinter_walls_add_plane(f->walls, p, n, wm, &k));
    sinter_material_destroy(wm);
    OK(sinter_walls_set_electric(f->walls, k, mode, value));
    return k;
}

/*
 * n particles along x at height y, from a wall at x = 0: particle 0 overlaps that wall by
 * delta_wall, pair (k, k+1) overlaps by delta[k]. Returns where the right wall must be for
 * particle n-1 to overlap it by delta_wall.
 */
static double add_chain(fixture *f, size_t n, const double *delta, double delta_wall, double y,
                        int32_t mat)
{
    double x = R - delta_wall;
    for (size_t k = 0; k < n; ++k) {
        add(f, x, y, 0.0, mat);
        if (k + 1 < n)
            x += 2.0 * R - delta[k];
    }
    return x + R - delta_wall;
}

static void find_contacts(fixture *f)
{
    OK(sinter_neighbors_build(&f->nb, f->ps, f->walls));
    OK(sinter_contacts_find_pp(f->ctx, &f->pp, &f->nb.pp, f->ps));
    OK(sinter_contacts_find_pw(f->ctx, &f->pw, &f->nb.pw, f->ps, f->walls, NULL));
}

static sinter_status solve(fixture *f, size_t *iterations)
{
    return sinter_electric_solve(f->em, f->ps, f->walls, &f->pp, &f->pw, iterations);
}

static void model(fixture *f, const char *name, double tolerance)
{
    OK(sinter_electric_model_create(&f->em, f->ctx, name));
    if (tolerance > 0.0)
        OK(sinter_electric_model_set(f->em, "tolerance", tolerance));
}

/* Seed 000 eq. 7-12 for equal radii: A = pi (r^2 - (d/2)^2) with d = 2 r - delta. */
static double pair_area(double delta)
{
    const double half = R - 0.5 * delta;
    return PI * (R * R - half * half);
}

/* Particle-wall contact: A = pi (r^2 - s^2), s = r - delta the centre-plane distance. */
static double wall_area(double delta)
{
    const double s = R - delta;
    return PI * (R * R - s * s);
}

static int electrified(const fixture *f, size_t i)
{
    return (f->ps->flags[i] & SINTER_PARTICLE_ELECTRIFIED) != 0;
}

/* ---- "averaged" (eq. 42-44) ------------------------------------------------ */

/*
 * Remark 4 / eq. 44: a chain of 7 with equal contact areas between current walls of 2 A and
 * (-)8 A (the model uses magnitudes) is linear from 2 to 8; the end particles are electrified.
 */
static void test_averaged_chain_equal_areas(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 7 };
    const double delta[N - 1] = {1e-4, 1e-4, 1e-4, 1e-4, 1e-4, 1e-4};
    const double x_right = add_chain(&f, N, delta, 5e-5, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, 2.0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_CURRENT, -8.0);
    find_contacts(&f);
    assert_int_equal(f.pp.count, N - 1);
    assert_int_equal(f.pw.count, 2);
    for (size_t k = 0; k < f.pp.count; ++k)
        assert_rel(f.pp.area[k], pair_area(1e-4), 1e-9); /* equal areas, up to positions */

    /* Tight tolerance: the exact linear profile to ~1e-10. */
    model(&f, "averaged", 1e-13);
    size_t iterations = 0;
    OK(solve(&f, &iterations));
    print_message("averaged chain of %d: %zu Gauss-Seidel sweeps to 1e-13\n", N, iterations);
    assert_true(iterations > 1 && iterations < 10000);
    assert_int_equal(f.em->last_iterations, iterations);
    for (size_t k = 0; k < N; ++k) {
        const double exact = 2.0 + 6.0 * (double)k / (N - 1); /* eq. 44 applied recursively */
        assert_close(f.ps->current[k], exact, 1e-10);
        assert_int_equal(electrified(&f, k), k == 0 || k == N - 1);
    }
    /* Interior particles are the average of their two neighbours (eq. 44, equal areas). */
    for (size_t k = 1; k + 1 < N; ++k)
        assert_close(f.ps->current[k], 0.5 * (f.ps->current[k - 1] + f.ps->current[k + 1]), 1e-10);

    /*
     * Default tolerance 1e-6 from a cold start: Z_K <= 1e-6 bounds the last sweep's change;
     * for 5 unknowns the Gauss-Seidel contraction is rho = cos^2(pi/6) = 0.75, so the error is
     * at most about Z_K sum|J| rho / (1 - rho) = 3 x 1e-6 x 35 A; 1e-3 A is a safe bound.
     */
    sinter_electric_model_destroy(f.em);
    f.em = NULL;
    model(&f, "averaged", 0.0);
    double tol;
    OK(sinter_electric_model_get(f.em, "tolerance", &tol));
    assert_true(tol == 1e-6);
    memset(f.ps->current, 0, N * sizeof(double));
    size_t cold = 0;
    OK(solve(&f, &cold));
    for (size_t k = 0; k < N; ++k)
        assert_close(f.ps->current[k], 2.0 + 6.0 * (double)k / (N - 1), 1e-3);
    /* Warm start: a repeated solve starts from the previous currents and stops at once. */
    size_t warm = 0;
    OK(solve(&f, &warm));
    print_message("default tolerance: %zu sweeps cold, %zu warm\n", cold, warm);
    assert_true(warm >= 1 && warm < cold);
    close_fixture(&f);
}

/* Eq. 42 with unequal areas: J_1 = (J_0 A_01 + J_2 A_12) / (A_01 + A_12). */
static void test_averaged_unequal_areas(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double delta[2] = {0.5e-4, 3e-4}, j_left = 3.0, j_right = 11.0;
    const double x_right = add_chain(&f, 3, delta, 5e-5, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, j_left);
    add_wall(&f, x_right, -1.0, SINTER_WALL_CURRENT, j_right);
    find_contacts(&f);
    const double a01 = pair_area(delta[0]), a12 = pair_area(delta[1]);
    print_message("areas %.6g and %.6g m^2\n", a01, a12);
    model(&f, "averaged", 1e-13);
    size_t iterations = 0;
    OK(solve(&f, &iterations));
    const double expected = (j_left * a01 + j_right * a12) / (a01 + a12);
    assert_close(f.ps->current[0], j_left, 1e-15);
    assert_close(f.ps->current[2], j_right, 1e-15);
    assert_rel(f.ps->current[1], expected, 1e-9); /* areas from positions to ~1e-12 */
    assert_true(fabs(expected - 0.5 * (j_left + j_right)) > 1.0); /* not the plain mean */
    /* One free particle whose neighbours are fixed: exact after one sweep, confirmed by a second.
     */
    assert_int_equal(iterations, 2);
    close_fixture(&f);
}

/* ---- "network" (Kirchhoff) -------------------------------------------------- */

/*
 * A chain of n equal contacts between walls at V0 and 0: series resistors
 * R = 2 / G_w + (n - 1) / G_pp, current I = V0 / R in every particle, potentials falling
 * linearly by I / G_pp per contact. PCG tolerance 1e-13 relative residual; the system has
 * condition number ~ n^2, so 1e-10 relative on potentials and currents is safe.
 */
static void test_network_series_chain(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 6 };
    const double dp = 1e-4, dw = 2e-4, v0 = 1.5;
    const double delta[N - 1] = {dp, dp, dp, dp, dp};
    const double x_right = add_chain(&f, N, delta, dw, 0.0, 0);
    const size_t left = add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
    const size_t right = add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    const double g_pp = SIGMA[0] * pair_area(dp) / (2.0 * R - dp); /* sigma_ij = sigma */
    const double g_w = SIGMA[0] * wall_area(dw) / (R - dw);
    const double current = v0 / (2.0 / g_w + (N - 1) / g_pp);
    print_message("network chain: G_pp = %.6g S, G_w = %.6g S, I = %.9g A\n", g_pp, g_w, current);

    model(&f, "network", 1e-13);
    size_t iterations = 0;
    OK(solve(&f, &iterations));
    print_message("PCG iterations: %zu\n", iterations);
    assert_true(iterations >= 1 && iterations <= 2 * N);
    assert_int_equal(f.em->node_count, N + 2);
    const double *phi = f.em->potential;
    assert_true(phi[N + left] == v0);
    assert_true(phi[N + right] == 0.0);
    assert_rel(phi[0], v0 - current / g_w, 1e-10);
    for (size_t k = 0; k < N; ++k) {
        assert_rel(f.ps->current[k], current, 1e-10);
        assert_int_equal(electrified(&f, k), k == 0 || k == N - 1);
        if (k + 1 < N)
            assert_rel(phi[k] - phi[k + 1], current / g_pp, 1e-10); /* linear drop */
    }
    assert_rel(phi[N - 1], current / g_w, 1e-10);

    /* The left wall as a current electrode of I0 into the chain, the right one grounded. */
    const double i0 = 0.25;
    OK(sinter_walls_set_electric(f.walls, left, SINTER_WALL_CURRENT, i0));
    OK(solve(&f, &iterations));
    for (size_t k = 0; k < N; ++k)
        assert_rel(f.ps->current[k], i0, 1e-10);
    phi = f.em->potential;
    assert_rel(phi[N - 1], i0 / g_w, 1e-10);
    assert_rel(phi[N + left], i0 * (2.0 / g_w + (N - 1) / g_pp), 1e-10); /* V = I R */

    /* Two balanced electrodes (+I0 in, -I0 out) and no ground: the same current. */
    OK(sinter_walls_set_electric(f.walls, right, SINTER_WALL_CURRENT, -i0));
    OK(solve(&f, &iterations));
    for (size_t k = 0; k < N; ++k)
        assert_rel(f.ps->current[k], i0, 1e-10);
    assert_int_equal(f.warnings, 0);

    /* One electrode and an insulating wall: open circuit, no current, one warning. */
    OK(sinter_walls_set_electric(f.walls, right, SINTER_WALL_NEUTRAL, 0.0));
    OK(solve(&f, &iterations));
    assert_int_equal(f.em->open_clusters, 1);
    assert_int_equal(f.warnings, 1);
    for (size_t k = 0; k < N; ++k)
        assert_true(f.ps->current[k] == 0.0);
    assert_true(electrified(&f, 0) && !electrified(&f, N - 1));
    /* The same with a compliance limit on the electrode: a supply at its limit, no warning. */
    OK(sinter_walls_set_electric_limit(f.walls, left, 10.0));
    OK(solve(&f, &iterations));
    assert_int_equal(f.em->open_clusters, 0);
    assert_int_equal(f.warnings, 1);
    for (size_t k = 0; k < N; ++k)
        assert_true(f.ps->current[k] == 0.0);
    close_fixture(&f);
}

/*
 * The network's warm start (network.c): a solve starts from the last solve's potentials when
 * the node count is the same. Solving an unchanged network again takes no iteration and
 * changes no bit; a new wall potential is met to the same accuracy from the old start; after a
 * change of the node count or a failed solve the start is 0 again, the same bits as a new
 * model's solve.
 */
static void test_network_warm_start(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 8 };
    double delta[N - 1];
    for (size_t k = 0; k < N - 1; ++k)
        delta[k] = 1e-4 * (1.0 + 0.1 * (double)k); /* unequal conductances */
    const double x_right = add_chain(&f, N, delta, 2e-4, 0.0, 0);
    const size_t left = add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 1.0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    model(&f, "network", 1e-12);
    size_t first = 0, again = 0;
    OK(solve(&f, &first));
    double phi[N + 2], current[N];
    memcpy(phi, f.em->potential, sizeof(phi));
    memcpy(current, f.ps->current, sizeof(current));
    OK(solve(&f, &again));
    print_message("warm start: %zu PCG iterations from 0, %zu from the last solve\n", first, again);
    assert_true(first >= 2);
    assert_int_equal(again, 0);
    assert_memory_equal(phi, f.em->potential, sizeof(phi));
    assert_memory_equal(current, f.ps->current, sizeof(current));

    /* twice the wall potential: twice the current in every particle, from the old start */
    OK(sinter_walls_set_electric(f.walls, left, SINTER_WALL_POTENTIAL, 2.0));
    OK(solve(&f, &again));
    assert_true(again >= 1);
    for (size_t k = 0; k < N; ++k)
        assert_rel(f.ps->current[k], 2.0 * current[k], 1e-10);

    /* a failed solve (one iteration allowed), then a new node count: each next start is 0 */
    sinter_electric_model *fresh = NULL;
    OK(sinter_walls_set_electric(f.walls, left, SINTER_WALL_POTENTIAL, 3.0));
    OK(sinter_electric_model_set(f.em, "max_iterations", 1));
    assert_int_equal(solve(&f, &again), SINTER_ERR_NOT_CONVERGED);
    OK(sinter_electric_model_set(f.em, "max_iterations", 1000));
    for (int round = 0; round < 2; ++round) {
        if (round == 1) { /* an isolated particle: one node more */
            add(&f, 0.5 * x_right, 10.0 * R, 0.0, 0);
            find_contacts(&f);
        }
        OK(solve(&f, &again));
        double warm_phi[N + 3];
        const size_t nodes = f.em->node_count;
        assert_int_equal(nodes, N + 2 + (size_t)round);
        memcpy(warm_phi, f.em->potential, nodes * sizeof(double));
        OK(sinter_electric_model_create(&fresh, f.ctx, "network"));
        OK(sinter_electric_model_set(fresh, "tolerance", 1e-12));
        size_t cold = 0;
        OK(sinter_electric_solve(fresh, f.ps, f.walls, &f.pp, &f.pw, &cold));
        assert_int_equal(again, cold);
        assert_memory_equal(warm_phi, fresh->potential, nodes * sizeof(double));
        sinter_electric_model_destroy(fresh);
        /* the solve after this one starts warm again */
        OK(sinter_walls_set_electric(f.walls, left, SINTER_WALL_POTENTIAL, 4.0 + round));
    }
    close_fixture(&f);
}

/*
 * The warm start follows the particles when they are reordered (warm_ids.c): a chain added
 * right to left, solved, then sorted in memory by position (every row changes) and its contacts
 * found again. Solving the same circuit again starts from each particle's own potential, so
 * it needs no iteration (the first solve went to 1e-13, the second asks 1e-9: the new sum order
 * of the residual cannot reach that) and gives the same potentials per particle to the first
 * solve's accuracy. The potentials of the rows before the sort would be a start of the
 * reversed chain: a residual of the order of the drive, many iterations.
 */
static void test_network_warm_start_follows_a_sort(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 9 };
    double delta[N - 1];
    for (size_t k = 0; k < N - 1; ++k)
        delta[k] = 1e-4 * (1.0 + 0.1 * (double)k); /* unequal conductances */
    double x = R - 2e-4, xs[N];
    for (size_t k = 0; k < N; ++k) {
        xs[k] = x;
        if (k + 1 < N)
            x += 2.0 * R - delta[k];
    }
    for (size_t k = N; k-- > 0;) /* right to left: id 0 is the rightmost */
        add(&f, xs[k], 0.0, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 1.0);
    add_wall(&f, x + R - 2e-4, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    model(&f, "network", 1e-13);
    size_t first = 0, again = 0;
    OK(solve(&f, &first));
    double phi_by_id[N];
    for (size_t i = 0; i < N; ++i)
        phi_by_id[f.ps->id[i]] = f.em->potential[i];
    OK(sinter_particles_sort_spatial(f.ps));
    assert_true(f.ps->id[0] != 0 && f.ps->id[N - 1] != N - 1); /* sorted by x: reversed */
    find_contacts(&f);
    OK(sinter_electric_model_set(f.em, "tolerance", 1e-9));
    OK(solve(&f, &again));
    print_message("after a sort: %zu PCG iterations from 0, %zu from the moved warm start\n", first,
                  again);
    assert_true(first >= 3);
    assert_int_equal(again, 0);
    for (size_t i = 0; i < N; ++i) /* the potentials are the first solve's (0..1 V) */
        assert_close(f.em->potential[i], phi_by_id[f.ps->id[i]], 1e-12);
    /* a warm start restored by row (a checkpoint's) is taken as it is */
    double restored[N + 2];
    memcpy(restored, f.em->potential, sizeof(restored));
    OK(sinter_electric_set_warm_potentials(f.em, restored, N + 2));
    OK(solve(&f, &again));
    assert_int_equal(again, 0);
    close_fixture(&f);
}

/*
 * The same through a stepper (option sort_interval): two chains added right to left, held
 * still (no force model: the contacts stay as they are), an explicit step to start the warm
 * start in that order, then a sort before each step. The PCG iterations of the run are those
 * of the same run without the sort (the first solve's 6; every later one starts at the
 * solution), and every particle carries the same current to the solves' accuracy (tolerance
 * 1e-12; the sort changes only the order of the sums). The rows' potentials as a start would
 * cost 6 more iterations after the first sort.
 */
static void run_with_sort(uint64_t sort_interval, uint64_t *iterations, double *current_by_id)
{
    fixture f;
    open_fixture(&f);
    sinter_material *mat;
    OK(sinter_material_create(&mat, f.ctx, NULL));
    OK(sinter_material_set(mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e4));
    OK(sinter_material_set(mat, SINTER_MAT_DENSITY, 8000.0));
    OK(sinter_particles_set_material(f.ps, 0, mat));
    sinter_material_destroy(mat);
    enum { N = 6 };
    double delta[N - 1], x = R - 2e-4, xs[N];
    for (size_t k = 0; k < N - 1; ++k)
        delta[k] = 1e-4 * (1.0 + 0.2 * (double)k);
    for (size_t k = 0; k < N; ++k) {
        xs[k] = x;
        if (k + 1 < N)
            x += 2.0 * R - delta[k];
    }
    for (int chain = 0; chain < 2; ++chain)
        for (size_t k = N; k-- > 0;)
            add(&f, xs[k], 3.0 * R * chain, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 0.5);
    add_wall(&f, x + R - 2e-4, -1.0, SINTER_WALL_POTENTIAL, -0.5);
    model(&f, "network", 1e-12);
    sinter_stepper *st;
    OK(sinter_stepper_create(&st, f.ctx, SINTER_STEPPER_EXPLICIT, f.ps, f.walls));
    OK(sinter_stepper_set_electric(st, f.em));
    OK(sinter_stepper_set_dt(st, 2e-6));
    OK(sinter_stepper_step(st, 1)); /* solved in the order added */
    OK(sinter_stepper_set_option(st, "sort_interval", (double)sort_interval));
    OK(sinter_stepper_step(st, 40));
    OK(sinter_stepper_electric_iterations(st, iterations));
    for (size_t i = 0; i < 2 * N; ++i)
        current_by_id[f.ps->id[i]] = f.ps->current[i];
    if (sort_interval > 0)
        assert_true(f.ps->id[0] != 0); /* the sort did move the particles */
    sinter_stepper_destroy(st);
    close_fixture(&f);
}

static void test_network_sort_interval_same_iterations(void **state)
{
    (void)state;
    uint64_t plain = 0, sorted = 0;
    double current[12], current_sorted[12];
    run_with_sort(0, &plain, current);
    run_with_sort(1, &sorted, current_sorted);
    print_message("PCG iterations over the run: %llu without sorts, %llu with a sort each step\n",
                  (unsigned long long)plain, (unsigned long long)sorted);
    assert_true(plain > 0);
    assert_true(plain == sorted);
    for (size_t i = 0; i < 12; ++i) {
        assert_true(current[i] > 0.0);
        assert_rel(current_sorted[i], current[i], 1e-9);
    }
}

/*
 * Two separate chains of 3 between the same two walls, one of sigma 2 S/m, one of 5 S/m, with
 * the same geometry: currents in the ratio of the conductances. With potential walls each
 * chain carries V0 / R_c; with a current electrode the total I0 splits as G_c / (G_a + G_b).
 * The "averaged" model on the same scene does not split: both chains carry the wall value.
 */
static void test_parallel_chains(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double dp = 1.5e-4, dw = 1e-4, v0 = 0.3, i0 = 0.7;
    const double delta[2] = {dp, dp};
    const double x_right = add_chain(&f, 3, delta, dw, 0.0, 0);
    assert_true(add_chain(&f, 3, delta, dw, 3.0 * R, 1) == x_right);
    const size_t left = add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
    const size_t right = add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    assert_int_equal(f.pp.count, 4);
    assert_int_equal(f.pw.count, 4);
    double resistance[2];
    for (int c = 0; c < 2; ++c)
        resistance[c] = 2.0 * (R - dw) / (SIGMA[c] * wall_area(dw)) +
                        2.0 * (2.0 * R - dp) / (SIGMA[c] * pair_area(dp));

    model(&f, "network", 1e-13);
    OK(solve(&f, NULL));
    for (size_t k = 0; k < 6; ++k)
        assert_rel(f.ps->current[k], v0 / resistance[k / 3], 1e-10);
    assert_rel(f.ps->current[0] / f.ps->current[3], SIGMA[0] / SIGMA[1], 1e-10);

    OK(sinter_walls_set_electric(f.walls, left, SINTER_WALL_CURRENT, i0));
    OK(solve(&f, NULL));
    const double g_a = 1.0 / resistance[0], g_b = 1.0 / resistance[1];
    for (size_t k = 0; k < 3; ++k) {
        assert_rel(f.ps->current[k], i0 * g_a / (g_a + g_b), 1e-10);
        assert_rel(f.ps->current[3 + k], i0 * g_b / (g_a + g_b), 1e-10);
    }
    assert_rel(f.ps->current[0] + f.ps->current[3], i0, 1e-10); /* charge is conserved */

    /* "averaged": a magnitude, not a split. */
    OK(sinter_walls_set_electric(f.walls, right, SINTER_WALL_CURRENT, i0));
    sinter_electric_model_destroy(f.em);
    f.em = NULL;
    model(&f, "averaged", 1e-12);
    OK(solve(&f, NULL));
    for (size_t k = 0; k < 6; ++k)
        assert_close(f.ps->current[k], i0, 1e-12);
    close_fixture(&f);
}

/*
 * Particles not connected to a driven wall get 0 and lose a stale ELECTRIFIED flag: a lone
 * particle, a pair resting on an insulating floor (neutral wall), a pair of zero conductivity
 * touching a potential wall (network: it cannot conduct, but it touches the wall).
 */
static void test_isolated_particles(void **state)
{
    (void)state;
    const char *names[2] = {"averaged", "network"};
    for (int m = 0; m < 2; ++m) {
        fixture f;
        open_fixture(&f);
        const double delta[2] = {1e-4, 1e-4};
        const double x_right = add_chain(&f, 3, delta, 1e-4, 0.0, 0); /* particles 0-2 */
        add(&f, 3e-3, 8e-3, 0.0, 0);                                  /* 3: alone */
        add(&f, 2e-3, -8e-3, -1.05e-3, 0);                            /* 4, 5: on the floor */
        add(&f, 3.95e-3, -8e-3, -1.05e-3, 0);
        add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, 1.0);
        const int right_mode = m == 0 ? SINTER_WALL_CURRENT : SINTER_WALL_POTENTIAL;
        add_wall(&f, x_right, -1.0, right_mode, m == 0 ? 1.0 : 0.0);
        const double p[3] = {0, 0, -2e-3}, n[3] = {0, 0, 1};
        sinter_material *wm;
        OK(sinter_material_create(&wm, f.ctx, NULL));
        OK(sinter_walls_add_plane(f.walls, p, n, wm, NULL)); /* neutral by default */
        sinter_material_destroy(wm);
        for (size_t i = 0; i < 6; ++i) {
            f.ps->current[i] = 7.0; /* stale values */
            f.ps->flags[i] |= SINTER_PARTICLE_ELECTRIFIED;
        }
        find_contacts(&f);
        assert_int_equal(f.pp.count, 3);
        assert_int_equal(f.pw.count, 4);
        model(&f, names[m], 1e-12);
        OK(solve(&f, NULL));
        for (size_t i = 3; i < 6; ++i) {
            assert_true(f.ps->current[i] == 0.0);
            assert_false(electrified(&f, i));
        }
        for (size_t i = 0; i < 3; ++i)
            assert_true(f.ps->current[i] > 0.0);
        assert_int_equal(f.warnings, 0);
        close_fixture(&f);
    }
    /* network: zero-conductivity particles touching a potential wall carry nothing */
    fixture f;
    open_fixture(&f);
    const double delta[1] = {1e-4};
    const double x_right = add_chain(&f, 2, delta, 1e-4, 0.0, 2);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 1.0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    model(&f, "network", 0.0);
    size_t iterations = 5;
    OK(solve(&f, &iterations));
    assert_int_equal(iterations, 0);
    assert_true(f.ps->current[0] == 0.0 && f.ps->current[1] == 0.0);
    assert_true(electrified(&f, 0) && electrified(&f, 1));
    close_fixture(&f);
}

/* Iteration counts, their limit, and the stepper's bookkeeping. */
static void test_iterations(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 12 };
    double delta[N - 1];
    for (size_t k = 0; k < N - 1; ++k)
        delta[k] = 1e-4;
    const double x_right = add_chain(&f, N, delta, 1e-4, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, 1.0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_CURRENT, 5.0);
    find_contacts(&f);
    model(&f, "averaged", 0.0);
    OK(sinter_electric_model_set(f.em, "max_iterations", 3));
    size_t iterations = 0;
    assert_int_equal(solve(&f, &iterations), SINTER_ERR_NOT_CONVERGED);
    assert_int_equal(iterations, 3);
    print_message("%s\n", sinter_last_error(f.ctx));
    assert_non_null(strstr(sinter_last_error(f.ctx), "max_iterations"));

    sinter_electric_model_destroy(f.em);
    f.em = NULL;
    model(&f, "network", 0.0);
    OK(sinter_walls_set_electric(f.walls, 0, SINTER_WALL_POTENTIAL, 1.0));
    OK(sinter_walls_set_electric(f.walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    OK(sinter_electric_model_set(f.em, "max_iterations", 2));
    assert_int_equal(solve(&f, &iterations), SINTER_ERR_NOT_CONVERGED);
    assert_int_equal(iterations, 2);
    assert_non_null(strstr(sinter_last_error(f.ctx), "PCG"));
    OK(sinter_electric_model_set(f.em, "max_iterations", 1000));
    OK(solve(&f, &iterations));
    print_message("network chain of %d: %zu PCG iterations\n", N, iterations);
    assert_true(iterations > 2 && iterations <= N + 2);

    /* The stepper borrows the model and reports the total of its solves (0 before any). */
    sinter_stepper *st;
    OK(sinter_stepper_create(&st, f.ctx, SINTER_STEPPER_EXPLICIT, f.ps, f.walls));
    uint64_t total = 99;
    OK(sinter_stepper_electric_iterations(st, &total));
    assert_true(total == 0);
    OK(sinter_stepper_set_electric(st, f.em));
    assert_ptr_equal(st->electric, f.em);
    OK(sinter_stepper_set_electric(st, NULL));
    assert_null(st->electric);
    assert_int_equal(sinter_stepper_set_electric(NULL, f.em), SINTER_ERR_NULL);
    assert_int_equal(sinter_stepper_electric_iterations(st, NULL), SINTER_ERR_NULL);
    sinter_ctx *other;
    sinter_electric_model *foreign;
    OK(sinter_ctx_create(&other, NULL));
    OK(sinter_electric_model_create(&foreign, other, "averaged"));
    assert_int_equal(sinter_stepper_set_electric(st, foreign), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f.ctx), "another context"));
    sinter_electric_model_destroy(foreign);
    sinter_ctx_destroy(other);
    sinter_stepper_destroy(st);
    close_fixture(&f);
}

/* ---- Joule heating (eq. 35, 50) -------------------------------------------- */

static double joule(fixture *f, sinter_heat_model *hm, sinter_status expect)
{
    double heat[4] = {0, 0, 0, 0};
    sinter_heat_eval e;
    memset(&e, 0, sizeof(e));
    e.ctx = f->ctx;
    e.ps = f->ps;
    e.walls = f->walls;
    e.pp = &f->pp;
    e.pw = &f->pw;
    e.heat = heat;
    assert_int_equal(hm->ops->eval(hm, &e), expect);
    return heat[0];
}

static void test_joule_constant_conductivity(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    add(&f, 0.0, 0.0, 0.0, 0);
    add(&f, 1.0, 0.0, 0.0, 2); /* sigma = 0, no current: no heat, no error */
    find_contacts(&f);
    sinter_heat_model *hm;
    OK(sinter_heat_model_create(&hm, f.ctx, "joule"));
    assert_string_equal(sinter_heat_model_name(hm), "joule");
    assert_int_equal(hm->ops->conduction, 0);
    const double current = 3.0, volume = 4.0 / 3.0 * PI * R * R * R;
    f.ps->current[0] = current;
    const double expected = ABSORPTANCE[0] * current * current / SIGMA[0] * volume; /* eq. 35 */
    print_message("joule: H = %.12g W\n", expected);
    assert_rel(joule(&f, hm, SINTER_OK), expected, 1e-12);
    f.ps->current[0] = -current; /* J^2: the sign does not matter */
    assert_rel(joule(&f, hm, SINTER_OK), expected, 1e-12);
    /* sigma(theta) from a table (issue 39): 4 S/m at 300 K to 1 S/m at 500 K, 2.5 S/m at the
     * particle's 400 K; removed, the material's constant again */
    const double tt[2] = {300.0, 500.0}, sv[2] = {4.0, 1.0};
    OK(sinter_particles_set_property_table(f.ps, 0, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY, 2, tt,
                                           sv));
    f.ps->temperature[0] = 400.0;
    assert_rel(joule(&f, hm, SINTER_OK), ABSORPTANCE[0] * current * current / 2.5 * volume, 1e-12);
    OK(sinter_particles_set_property_table(f.ps, 0, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY, 0, NULL,
                                           NULL));
    assert_rel(joule(&f, hm, SINTER_OK), expected, 1e-12);

    f.ps->current[1] = 0.1; /* a current through a non-conductor */
    joule(&f, hm, SINTER_ERR_INVALID);
    print_message("%s\n", sinter_last_error(f.ctx));
    assert_non_null(strstr(sinter_last_error(f.ctx), "conductivity"));
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

static double logistic(double x)
{
    return 1.0 / (1.0 + exp(-x));
}

/*
 * Eq. 50 by hand: sigma = sigma_0 (1 + K1 s(g1 (theta - theta_R)) + K2 s(g2 |E - E_R|)),
 * E = |J| / sigma_0. At (theta_R, E_R) both sigmoids are 1/2: sigma_0 (1 + K1/2 + K2/2).
 */
static void test_joule_sigmoid(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    add(&f, 0.0, 0.0, 0.0, 1);
    find_contacts(&f);
    sinter_heat_model *hm;
    OK(sinter_heat_model_create(&hm, f.ctx, "joule"));
    const double theta_r = 500.0, k1 = -0.4, g1 = 0.01, k2 = 0.3, g2 = 0.5, e_r = 1.0;
    OK(sinter_heat_model_set(hm, "sigmoid", 1.0));
    OK(sinter_heat_model_set(hm, "theta_ref", theta_r));
    OK(sinter_heat_model_set(hm, "k1", k1));
    OK(sinter_heat_model_set(hm, "gamma1", g1));
    OK(sinter_heat_model_set(hm, "k2", k2));
    OK(sinter_heat_model_set(hm, "gamma2", g2));
    OK(sinter_heat_model_set(hm, "field_ref", e_r));
    const double s0 = SIGMA[1], a = ABSORPTANCE[1], volume = 4.0 / 3.0 * PI * R * R * R;

    const double theta = 650.0, current = 12.5, field = current / s0; /* E = 2.5 */
    f.ps->temperature[0] = theta;
    f.ps->current[0] = current;
    const double sigma =
        s0 * (1.0 + k1 * logistic(g1 * (theta - theta_r)) + k2 * logistic(g2 * fabs(field - e_r)));
    print_message("eq. 50: sigma = %.12g S/m (sigma_0 = %g)\n", sigma, s0);
    assert_rel(joule(&f, hm, SINTER_OK), a * current * current / sigma * volume, 1e-12);

    /* At the reference state: 1 + K1/2 + K2/2, not 1. */
    f.ps->temperature[0] = theta_r;
    f.ps->current[0] = e_r * s0;
    const double sigma_ref = s0 * (1.0 + 0.5 * k1 + 0.5 * k2);
    assert_rel(joule(&f, hm, SINTER_OK), a * e_r * s0 * e_r * s0 / sigma_ref * volume, 1e-12);

    /* Switched off: the material's conductivity. */
    OK(sinter_heat_model_set(hm, "sigmoid", 0.0));
    assert_rel(joule(&f, hm, SINTER_OK), a * e_r * s0 * e_r * s0 / s0 * volume, 1e-12);

    /* Eq. 50 leaving its domain (sigma <= 0), and a bad switch. */
    OK(sinter_heat_model_set(hm, "sigmoid", 1.0));
    OK(sinter_heat_model_set(hm, "k1", -3.0));
    f.ps->temperature[0] = 2000.0;
    joule(&f, hm, SINTER_ERR_DOMAIN);
    print_message("%s\n", sinter_last_error(f.ctx));
    OK(sinter_heat_model_set(hm, "sigmoid", 0.5));
    joule(&f, hm, SINTER_ERR_INVALID);
    sinter_heat_model_destroy(hm);
    close_fixture(&f);
}

/* ---- misuse ---------------------------------------------------------------- */

static void test_misuse(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const size_t w = add_wall(&f, 0.0, 1.0, SINTER_WALL_NEUTRAL, 0.0);
    assert_int_equal(sinter_walls_set_electric(f.walls, w, 3, 1.0), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f.ctx), "SINTER_WALL_POTENTIAL"));
    assert_int_equal(sinter_walls_set_electric(f.walls, w, -1, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_electric(f.walls, w, SINTER_WALL_CURRENT, NAN),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_electric(f.walls, 5, SINTER_WALL_CURRENT, 1.0),
                     SINTER_ERR_RANGE);
    assert_int_equal(sinter_walls_set_electric(NULL, 0, SINTER_WALL_CURRENT, 1.0), SINTER_ERR_NULL);
    OK(sinter_walls_set_electric(f.walls, w, SINTER_WALL_CURRENT, -4.0));
    assert_int_equal(f.walls->wall[w].electric_mode, SINTER_WALL_CURRENT);
    assert_true(f.walls->wall[w].electric_value == -4.0);
    OK(sinter_walls_set_electric(f.walls, w, SINTER_WALL_NEUTRAL, 9.0));
    assert_true(f.walls->wall[w].electric_value == 0.0);

    sinter_electric_model *em = NULL;
    assert_int_equal(sinter_electric_model_create(&em, f.ctx, "kirchhoff"), SINTER_ERR_NOT_FOUND);
    assert_null(em);
    print_message("%s\n", sinter_last_error(f.ctx));
    assert_non_null(strstr(sinter_last_error(f.ctx), "averaged, network"));
    assert_int_equal(sinter_electric_model_create(&em, NULL, "averaged"), SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_model_create(NULL, f.ctx, "averaged"), SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_model_create(&em, f.ctx, NULL), SINTER_ERR_NULL);
    sinter_electric_model_destroy(NULL);
    assert_string_equal(sinter_electric_model_name(NULL), "");

    model(&f, "network", 0.0);
    assert_string_equal(sinter_electric_model_name(f.em), "network");
    double v = 0.0;
    OK(sinter_electric_model_get(f.em, "tolerance", &v));
    assert_true(v == 1e-10);
    OK(sinter_electric_model_get(f.em, "max_iterations", &v));
    assert_true(v == 10000.0);
    assert_int_equal(sinter_electric_model_set(f.em, "omega", 1.0), SINTER_ERR_NOT_FOUND);
    assert_non_null(strstr(sinter_last_error(f.ctx), "omega"));
    assert_int_equal(sinter_electric_model_get(f.em, "omega", &v), SINTER_ERR_NOT_FOUND);
    assert_int_equal(sinter_electric_model_get(f.em, "tolerance", NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_model_set(f.em, NULL, 1.0), SINTER_ERR_NULL);
    const double bad_tolerance[4] = {0.0, 1.0, -1e-3, NAN};
    for (int k = 0; k < 4; ++k)
        assert_int_equal(sinter_electric_model_set(f.em, "tolerance", bad_tolerance[k]),
                         SINTER_ERR_INVALID);
    const double bad_max[4] = {0.0, 2.5, -3.0, INFINITY};
    for (int k = 0; k < 4; ++k)
        assert_int_equal(sinter_electric_model_set(f.em, "max_iterations", bad_max[k]),
                         SINTER_ERR_INVALID);
    OK(sinter_electric_model_set(f.em, "max_iterations", 50.0));
    OK(sinter_electric_model_get(f.em, "max_iterations", &v));
    assert_true(v == 50.0);
    assert_int_equal(sinter_electric_model_set(NULL, "tolerance", 1e-3), SINTER_ERR_NULL);

    /* solve: NULL arguments, and "averaged" refuses a potential wall */
    assert_int_equal(sinter_electric_solve(NULL, f.ps, f.walls, &f.pp, &f.pw, NULL),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_solve(f.em, NULL, f.walls, &f.pp, &f.pw, NULL),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_solve(f.em, f.ps, f.walls, NULL, &f.pw, NULL),
                     SINTER_ERR_NULL);
    add(&f, R - 1e-4, 0.0, 0.0, 0);
    find_contacts(&f);
    assert_int_equal(f.pw.count, 1);
    assert_int_equal(sinter_electric_solve(f.em, f.ps, NULL, &f.pp, &f.pw, NULL),
                     SINTER_ERR_INVALID); /* a wall contact without walls */
    sinter_electric_model_destroy(f.em);
    f.em = NULL;
    model(&f, "averaged", 0.0);
    OK(sinter_walls_set_electric(f.walls, w, SINTER_WALL_POTENTIAL, 1.0));
    assert_int_equal(solve(&f, NULL), SINTER_ERR_INVALID);
    print_message("%s\n", sinter_last_error(f.ctx));
    assert_non_null(strstr(sinter_last_error(f.ctx), "network"));
    /* an electrode alone (no return path) is fine for "averaged": a magnitude */
    OK(sinter_walls_set_electric(f.walls, w, SINTER_WALL_CURRENT, 2.0));
    OK(solve(&f, NULL));
    assert_true(f.ps->current[0] == 2.0);
    close_fixture(&f);
}

/* ---- the network's power and energy-consistent Joule heating (issue 39) ----------------- */

/*
 * A series chain between walls at v0 and 0: each contact dissipates G (phi_a - phi_b)^2; a
 * pair gives half to each particle, an electrode contact all to its particle; the walls deliver
 * v0 I. Closed forms: the chain's I = v0 / (2 / G_w + (N - 1) / G_pp), an end particle gets
 * I^2 / G_w + I^2 / (2 G_pp), an inner one I^2 / G_pp; the total is v0 I = I^2 R (Tellegen).
 * The "joule" model (source 0, automatic) puts exactly these shares into the particles; with
 * source = 1 it is eq. 35 again; source = 2 without a network solve is refused.
 */
static void test_network_power_and_joule_shares(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 5 };
    const double dp = 1e-4, dw = 2e-4, v0 = 2.0;
    const double delta[N - 1] = {dp, dp, dp, dp};
    const double x_right = add_chain(&f, N, delta, dw, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    const double g_pp = SIGMA[0] * pair_area(dp) / (2.0 * R - dp);
    const double g_w = SIGMA[0] * wall_area(dw) / (R - dw);
    const double current = v0 / (2.0 / g_w + (N - 1) / g_pp);
    model(&f, "network", 1e-14);
    OK(solve(&f, NULL));
    double supplied = 0, dissipated = 0;
    OK(sinter_electric_model_power(f.em, &supplied, &dissipated));
    print_message("chain: I = %.9g A, v0 I = %.9g W, supplied %.9g W, dissipated %.9g W\n", current,
                  v0 * current, supplied, dissipated);
    assert_rel(supplied, v0 * current, 1e-12);
    assert_rel(dissipated, v0 * current, 1e-12);
    const double *p = sinter_electric_dissipation(f.em, N);
    assert_non_null(p);
    const double end = current * current / g_w + 0.5 * current * current / g_pp;
    for (size_t k = 0; k < N; ++k)
        assert_rel(p[k], k == 0 || k == N - 1 ? end : current * current / g_pp, 1e-12);
    assert_null(sinter_electric_dissipation(f.em, N + 1)); /* another particle count */

    sinter_heat_model *hm;
    OK(sinter_heat_model_create(&hm, f.ctx, "joule"));
    double heat[N] = {0};
    sinter_heat_eval e;
    memset(&e, 0, sizeof(e));
    e.ctx = f.ctx;
    e.ps = f.ps;
    e.walls = f.walls;
    e.pp = &f.pp;
    e.pw = &f.pw;
    e.heat = heat;
    e.joule_dissipation = p;
    OK(hm->ops->eval(hm, &e));
    double sum = 0;
    for (size_t k = 0; k < N; ++k) {
        assert_true(heat[k] == p[k]);
        sum += heat[k];
    }
    assert_rel(sum, supplied, 1e-12); /* the walls' work, all of it into the particles */
    OK(sinter_heat_model_set(hm, "source", 1));
    memset(heat, 0, sizeof(heat));
    OK(hm->ops->eval(hm, &e));
    const double volume = 4.0 / 3.0 * PI * R * R * R;
    assert_rel(heat[1], ABSORPTANCE[0] * current * current / SIGMA[0] * volume, 1e-10);
    OK(sinter_heat_model_set(hm, "source", 2));
    e.joule_dissipation = NULL;
    assert_int_equal(hm->ops->eval(hm, &e), SINTER_ERR_STATE);
    OK(sinter_heat_model_set(hm, "source", 0)); /* automatic without a network: eq. 35 */
    memset(heat, 0, sizeof(heat));
    OK(hm->ops->eval(hm, &e));
    assert_rel(heat[1], ABSORPTANCE[0] * current * current / SIGMA[0] * volume, 1e-10);
    sinter_heat_model_destroy(hm);
    /* the averaged model has no potentials and so no power */
    sinter_electric_model *averaged;
    OK(sinter_electric_model_create(&averaged, f.ctx, "averaged"));
    assert_int_equal(sinter_electric_model_power(averaged, &supplied, &dissipated),
                     SINTER_ERR_UNSUPPORTED);
    assert_int_equal(sinter_electric_model_set(averaged, "sigmoid", 1), SINTER_ERR_INVALID);
    sinter_electric_model_destroy(averaged);
    close_fixture(&f);
}

/*
 * Seed 000 eq. 50's temperature term in the network's conductances: two particles at 300 K
 * and 900 K between walls; sigma(theta) = sigma_0 (1 + k1 s(gamma1 (theta - theta_ref))), the
 * pair's harmonic rule (r_i + r_j) / sigma_ij = r / sigma_i + r / sigma_j, each wall contact
 * with its particle's own sigma: the current against the closed form of the three resistors.
 */
static void test_network_conductivity_follows_temperature(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double dp = 1e-4, dw = 2e-4, v0 = 1.0, k1 = -0.6, gamma1 = 0.01, theta_ref = 600.0;
    const double delta[1] = {dp};
    const double x_right = add_chain(&f, 2, delta, dw, 0.0, 0);
    f.ps->temperature[0] = 300.0;
    f.ps->temperature[1] = 900.0;
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    model(&f, "network", 1e-14);
    OK(sinter_electric_model_set(f.em, "sigmoid", 1));
    OK(sinter_electric_model_set(f.em, "k1", k1));
    OK(sinter_electric_model_set(f.em, "gamma1", gamma1));
    OK(sinter_electric_model_set(f.em, "theta_ref", theta_ref));
    double sigma[2];
    for (int k = 0; k < 2; ++k)
        sigma[k] =
            SIGMA[0] * (1.0 + k1 / (1.0 + exp(-gamma1 * (f.ps->temperature[k] - theta_ref))));
    const double s_pair = 2.0 * sigma[0] * sigma[1] / (sigma[0] + sigma[1]);
    const double r_total = (R - dw) / (sigma[0] * wall_area(dw)) +
                           (2.0 * R - dp) / (s_pair * pair_area(dp)) +
                           (R - dw) / (sigma[1] * wall_area(dw));
    OK(solve(&f, NULL));
    print_message("sigma(300 K) = %.6g, sigma(900 K) = %.6g S/m; I = %.9g A\n", sigma[0], sigma[1],
                  f.ps->current[0]);
    assert_rel(f.ps->current[0], v0 / r_total, 1e-12);
    assert_rel(f.ps->current[1], v0 / r_total, 1e-12);
    /* a law that makes a conductivity negative is refused */
    OK(sinter_electric_model_set(f.em, "k1", -3.0));
    assert_int_equal(solve(&f, NULL), SINTER_ERR_DOMAIN);
    close_fixture(&f);
}

/*
 * sigma(theta) from a material's table (issue 39): the same series chain with material 0's
 * conductivity tabulated, 2 S/m at 300 K to 0.5 S/m at 1100 K, particles at 300 K and 700 K
 * (1.25 S/m, interpolated): the current is V / (sum of the three resistances) with the table's
 * values; with eq. 50's sigmoid on, its temperature term multiplies the table's value.
 */
static void test_network_conductivity_table(void **state)
{
    (void)state;
    for (int sigmoid = 0; sigmoid < 2; ++sigmoid) {
        fixture f;
        open_fixture(&f);
        const double dp = 1e-4, dw = 2e-4, v0 = 1.0, k1 = -0.6, gamma1 = 0.01, theta_ref = 600.0;
        const double delta[1] = {dp}, tt[2] = {300.0, 1100.0}, sv[2] = {2.0, 0.5};
        OK(sinter_particles_set_property_table(f.ps, 0, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY, 2,
                                               tt, sv));
        const double x_right = add_chain(&f, 2, delta, dw, 0.0, 0);
        f.ps->temperature[0] = 300.0;
        f.ps->temperature[1] = 700.0;
        add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
        add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
        find_contacts(&f);
        model(&f, "network", 1e-14);
        double sigma[2] = {2.0, 1.25};
        if (sigmoid) {
            OK(sinter_electric_model_set(f.em, "sigmoid", 1));
            OK(sinter_electric_model_set(f.em, "k1", k1));
            OK(sinter_electric_model_set(f.em, "gamma1", gamma1));
            OK(sinter_electric_model_set(f.em, "theta_ref", theta_ref));
            for (int k = 0; k < 2; ++k)
                sigma[k] *= 1.0 + k1 / (1.0 + exp(-gamma1 * (f.ps->temperature[k] - theta_ref)));
        }
        const double s_pair = 2.0 * sigma[0] * sigma[1] / (sigma[0] + sigma[1]);
        const double r_total = (R - dw) / (sigma[0] * wall_area(dw)) +
                               (2.0 * R - dp) / (s_pair * pair_area(dp)) +
                               (R - dw) / (sigma[1] * wall_area(dw));
        OK(solve(&f, NULL));
        assert_rel(f.ps->current[0], v0 / r_total, 1e-12);
        assert_rel(f.ps->current[1], v0 / r_total, 1e-12);
        close_fixture(&f);
    }
}

/* ---- host conductance law and Joule split (issue 39) ---------------------------------------- */

/* The built-in law of network.c written as a host callback: the same operations in the same
 * order, so the same bits. */
static int builtin_conductance(const sinter_state_view *v, const sinter_contact_batch *b,
                               const double *sigma, double *g, void *user)
{
    ++*(int *)user;
    const double *r = v->radius;
    for (size_t k = 0; k < b->count; ++k) {
        const uint32_t i = b->i[k], j = b->j[k];
        if (b->kind == SINTER_CONTACT_WALL) {
            g[k] = b->distance[k] > 0.0 ? sigma[i] * b->area[k] / b->distance[k] : 0.0;
            continue;
        }
        const double den = r[i] * sigma[j] + r[j] * sigma[i];
        g[k] = den > 0.0 && b->distance[k] > 0.0
                   ? sigma[i] * sigma[j] * (r[i] + r[j]) / den * b->area[k] / b->distance[k]
                   : 0.0;
    }
    return 0;
}

static int builtin_split(const sinter_state_view *v, const sinter_contact_batch *b,
                         const double *power, double *share, void *user)
{
    (void)v;
    (void)power;
    (void)user;
    for (size_t k = 0; k < b->count; ++k)
        share[k] = b->kind == SINTER_CONTACT_WALL ? 1.0 : 0.5;
    return 0;
}

/* A constant share *user for pairs (a wall contact's power all to its particle). */
static int fixed_split(const sinter_state_view *v, const sinter_contact_batch *b,
                       const double *power, double *share, void *user)
{
    (void)v;
    (void)power;
    for (size_t k = 0; k < b->count; ++k)
        share[k] = b->kind == SINTER_CONTACT_WALL ? 1.0 : *(const double *)user;
    return 0;
}

/* The series split: a contact resistor is the two bodies' halves r / sigma in series (seed 003
 * eq. 35's harmonic rule), and a current I through them dissipates I^2 R in each, so body i
 * takes R_i / (R_i + R_j); an electrode contact gives *user of its power to the particle. */
static int series_split(const sinter_state_view *v, const sinter_contact_batch *b,
                        const double *power, double *share, void *user)
{
    (void)power;
    const double *sigma = SIGMA;
    for (size_t k = 0; k < b->count; ++k) {
        if (b->kind == SINTER_CONTACT_WALL) {
            share[k] = *(const double *)user;
            continue;
        }
        const uint32_t i = b->i[k], j = b->j[k];
        const double ri = v->radius[i] / sigma[v->material[i]];
        const double rj = v->radius[j] / sigma[v->material[j]];
        share[k] = ri / (ri + rj);
    }
    return 0;
}

/* Per evaluation: the power the walls' supplies deliver [W] and, with wall_heat, the walls'
 * conductive heat flow into the particles summed over the walls [W] (the series' columns). */
typedef struct energy_log {
    sinter_electric_model *em;
    double power[400], wall_heat[400];
    int count, with_wall_heat;
} energy_log;

static int log_power(const sinter_stepper *st, double time, void *user)
{
    (void)time;
    energy_log *l = user;
    double dissipated = 0;
    if (l->count >= 400)
        return 0;
    if (l->with_wall_heat) {
        double flows[2] = {0.0, 0.0};
        OK(sinter_snapshot_wall_flows(st, flows, NULL));
        l->wall_heat[l->count] = flows[0] + flows[1];
    }
    OK(sinter_electric_model_power(l->em, &l->power[l->count++], &dissipated));
    return 0;
}

/*
 * The energy balance of a run (the explicit stepper, the network model, energy-consistent
 * Joule heating, no other heat): sum_i m_i C (theta_i - theta_i0) equals the walls' electrical
 * work, sum over steps of h times the power delivered at the state each temperature update
 * used (the update of step n uses the powers of the evaluation before it), to round-off.
 * With wall_heat the particles also conduct ("conduction", k = 50 W/(m K)) and the electrodes
 * are thermal walls of two kinds: a 400 K reservoir and a 250 K wall of transfer coefficient
 * h_w = 2e4 W/(m^2 K); then sum m C dtheta equals the electrical work plus the walls' heat flow
 * into the particles, integrated the same way (issue 39).
 */
static void energy_balance_over_a_run(int host_split, int wall_heat);

static void test_joule_energy_balance_over_a_run(void **state)
{
    (void)state;
    energy_balance_over_a_run(0, 0);
}

static void test_joule_and_wall_heat_balance_over_a_run(void **state)
{
    (void)state;
    energy_balance_over_a_run(0, 1);
}

static void energy_balance_over_a_run(int host_split, int wall_heat)
{
    fixture f;
    open_fixture(&f);
    const double heat_capacity = 500.0, h = 2e-6;
    sinter_material *mat;
    OK(sinter_material_create(&mat, f.ctx, NULL));
    OK(sinter_material_set(mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e4));
    OK(sinter_material_set(mat, SINTER_MAT_HEAT_CAPACITY, heat_capacity));
    OK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    OK(sinter_material_set(mat, SINTER_MAT_DENSITY, 8000.0));
    OK(sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 50.0));
    OK(sinter_particles_set_material(f.ps, 0, mat));
    const double dp = 1e-4, dw = 2e-4;
    const double delta[3] = {dp, 2 * dp, dp};
    const double x_right = add_chain(&f, 4, delta, dw, 0.0, 0);
    add_chain(&f, 4, delta, dw, 3.0 * R, 0); /* a second, parallel chain */
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 0.5);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, -0.5);
    if (wall_heat) {
        for (size_t k = 0; k < 2; ++k)
            OK(sinter_walls_set_material(f.walls, k, mat));
        OK(sinter_walls_set_temperature(f.walls, 0, 400.0));
        OK(sinter_walls_set_temperature(f.walls, 1, 250.0));
        OK(sinter_walls_set_thermal(f.walls, 1, SINTER_WALL_TRANSFER, 2e4));
    }
    sinter_material_destroy(mat);
    model(&f, "network", 1e-14);
    double pair_share = 0.8;
    if (host_split) {
        const sinter_electric_callbacks cb = {sizeof(cb), NULL, fixed_split, NULL};
        OK(sinter_electric_model_set_host(f.em, &cb, &pair_share));
    }
    sinter_stepper *st;
    sinter_force_model *contact;
    sinter_heat_model *joule, *conduction = NULL;
    OK(sinter_stepper_create(&st, f.ctx, SINTER_STEPPER_EXPLICIT, f.ps, f.walls));
    OK(sinter_force_model_create(&contact, f.ctx, "hertz_mindlin"));
    OK(sinter_stepper_add_force(st, contact));
    OK(sinter_heat_model_create(&joule, f.ctx, "joule"));
    OK(sinter_stepper_add_heat(st, joule));
    if (wall_heat) {
        OK(sinter_heat_model_create(&conduction, f.ctx, "conduction"));
        OK(sinter_stepper_add_heat(st, conduction));
    }
    OK(sinter_stepper_set_electric(st, f.em));
    OK(sinter_stepper_set_dt(st, h));
    const size_t n = f.ps->count;
    double theta0[8];
    memcpy(theta0, f.ps->temperature, n * sizeof(double));
    energy_log l = {f.em, {0}, {0}, 0, wall_heat};
    OK(sinter_stepper_step(st, 0)); /* the first evaluation: the powers the first update uses */
    log_power(st, 0.0, &l);
    OK(sinter_stepper_set_observer(st, log_power, &l));
    enum { STEPS = 300 };
    OK(sinter_stepper_step(st, STEPS));
    double work = 0, walls = 0, gained = 0;
    for (int k = 0; k < STEPS; ++k) {
        work += h * l.power[k];
        walls += h * l.wall_heat[k];
    }
    for (size_t i = 0; i < n; ++i)
        gained += f.ps->mass[i] * heat_capacity * (f.ps->temperature[i] - theta0[i]);
    print_message("electrical work %.12g J, walls' heat %.12g J, heat gained %.12g J (power %.6g "
                  "-> %.6g W)\n",
                  work, walls, gained, l.power[0], l.power[STEPS - 1]);
    assert_true(work > 0.0 && l.power[0] != l.power[STEPS - 1]); /* the contacts moved */
    /* round-off: 300 updates of theta ~ 300 K by ~2e-5 K each (ulp(300 K) / 2e-5 K ~ 3e-9 per
     * update at worst; solves to 1e-14) */
    assert_rel(gained, work + walls, 1e-9);
    if (wall_heat) {
        /* both walls conduct: the reservoir gives, the colder transfer wall takes, and the
         * models' books agree with the walls' flows and the supplies' work */
        double booked_joule = 0, booked_conduction = 0;
        OK(sinter_stepper_heat_energy(st, 0, &booked_joule));
        OK(sinter_stepper_heat_energy(st, 1, &booked_conduction));
        double flows[2];
        OK(sinter_snapshot_wall_flows(st, flows, NULL));
        print_message("wall flows at the end: reservoir %.6g W, transfer %.6g W\n", flows[0],
                      flows[1]);
        assert_true(flows[0] > 0.0 && flows[1] < 0.0 && fabs(walls) > 1e-3 * work);
        assert_rel(booked_joule, work, 1e-9);
        assert_rel(booked_conduction, walls, 1e-9);
    }
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(contact);
    sinter_heat_model_destroy(joule);
    sinter_heat_model_destroy(conduction);
    close_fixture(&f);
}

/*
 * Power supplies (walls/electric_drive.c): a chain of resistance R between a driven wall and a
 * grounded one. A current drive I0 with a voltage limit V < I0 R is held at V and carries V / R;
 * a potential drive V0 with a current limit I < V0 / R carries I (its potential I R); a limit
 * above the operating point changes nothing. A pulsed drive is 0 in its off time; a schedule is
 * interpolated.
 */
static void test_supply_limits_pulses_and_schedules(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 4 };
    const double dp = 1e-4, dw = 2e-4;
    const double delta[N - 1] = {dp, dp, dp};
    const double x_right = add_chain(&f, N, delta, dw, 0.0, 0);
    const size_t drive = add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, 1e-3);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    const double g_pp = SIGMA[0] * pair_area(dp) / (2.0 * R - dp);
    const double g_w = SIGMA[0] * wall_area(dw) / (R - dw);
    const double resistance = 2.0 / g_w + (N - 1) / g_pp;
    model(&f, "network", 1e-14);
    OK(solve(&f, NULL));
    assert_rel(f.ps->current[1], 1e-3, 1e-12); /* no limit: the current set */
    const double v_limit = 0.5 * 1e-3 * resistance;
    OK(sinter_walls_set_electric_limit(f.walls, drive, v_limit));
    OK(solve(&f, NULL));
    print_message("current drive 1 mA, R = %.6g ohm, limit %.6g V: I = %.9g A\n", resistance,
                  v_limit, f.ps->current[1]);
    assert_rel(f.ps->current[1], v_limit / resistance, 1e-12);
    assert_rel(f.em->potential[N + drive], v_limit, 1e-15);
    OK(sinter_walls_set_electric_limit(f.walls, drive, 10.0 * v_limit)); /* not reached */
    OK(solve(&f, NULL));
    assert_rel(f.ps->current[1], 1e-3, 1e-12);
    /* a potential drive with a current limit */
    const double v0 = 2.0, i_limit = 0.25 * v0 / resistance;
    OK(sinter_walls_set_electric(f.walls, drive, SINTER_WALL_POTENTIAL, v0));
    OK(sinter_walls_set_electric_limit(f.walls, drive, i_limit));
    OK(solve(&f, NULL));
    assert_rel(f.ps->current[1], i_limit, 1e-12);
    assert_rel(f.em->potential[N + drive], i_limit * resistance, 1e-12);
    OK(sinter_walls_set_electric_limit(f.walls, drive, 0.0));
    /* pulses: on 2 ms, off 3 ms */
    OK(sinter_walls_set_electric_pulse(f.walls, drive, 2e-3, 3e-3));
    const double times[4] = {0.0, 1.9e-3, 2.1e-3, 5.5e-3};
    for (int k = 0; k < 4; ++k) {
        OK(sinter_walls_move(f.walls, times[k]));
        OK(solve(&f, NULL));
        const double expected = k == 2 ? 0.0 : v0 / resistance;
        assert_true(fabs(f.ps->current[1] - expected) <= 1e-12 * v0 / resistance);
    }
    assert_int_equal(sinter_walls_set_electric_pulse(f.walls, drive, 0.0, 1.0), SINTER_ERR_INVALID);
    OK(sinter_walls_set_electric_pulse(f.walls, drive, 1.0, 0.0)); /* continuous again */
    /* a schedule: 0 V at 0 s to 4 V at 1 s */
    const double st[2] = {0.0, 1.0}, sv[2] = {0.0, 4.0};
    OK(sinter_walls_set_electric_schedule(f.walls, drive, 2, st, sv));
    OK(sinter_walls_move(f.walls, 0.25));
    OK(solve(&f, NULL));
    assert_rel(f.ps->current[1], 1.0 / resistance, 1e-12);
    const double bad_t[2] = {1.0, 0.5};
    assert_int_equal(sinter_walls_set_electric_schedule(f.walls, drive, 2, bad_t, sv),
                     SINTER_ERR_INVALID);
    close_fixture(&f);
}

static int bad_conductance(const sinter_state_view *v, const sinter_contact_batch *b,
                           const double *sigma, double *g, void *user)
{
    (void)v;
    (void)sigma;
    if (b->count > 0)
        g[0] = *(const double *)user;
    return 0;
}

static int failing_split(const sinter_state_view *v, const sinter_contact_batch *b,
                         const double *power, double *share, void *user)
{
    (void)v;
    (void)b;
    (void)power;
    (void)share;
    (void)user;
    return -1;
}

static int destroyed;
static void count_destroy(void *user)
{
    (void)user;
    ++destroyed;
}

/* Two parallel chains of the two materials at different temperatures with eq. 50's term on, a
 * current drive: solved by the built-in law and split, then by a fresh model given the same law
 * and split as host callbacks; currents, potentials and per-particle powers agree bit for bit. */
static void test_host_callbacks_reproduce_builtin(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double dp = 1.5e-4, dw = 1e-4;
    const double delta[2] = {dp, 0.5 * dp};
    const double x_right = add_chain(&f, 3, delta, dw, 0.0, 0);
    add_chain(&f, 3, delta, dw, 3.0 * R, 1);
    for (size_t i = 0; i < 6; ++i)
        f.ps->temperature[i] = 300.0 + 100.0 * (double)i;
    add_wall(&f, 0.0, 1.0, SINTER_WALL_CURRENT, 0.7);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    double runs[2][3 * 8];
    int calls = 0;
    for (int host = 0; host < 2; ++host) {
        sinter_electric_model_destroy(f.em);
        f.em = NULL;
        model(&f, "network", 1e-13);
        OK(sinter_electric_model_set(f.em, "sigmoid", 1));
        OK(sinter_electric_model_set(f.em, "k1", -0.4));
        OK(sinter_electric_model_set(f.em, "gamma1", 0.01));
        OK(sinter_electric_model_set(f.em, "theta_ref", 500.0));
        if (host) {
            const sinter_electric_callbacks cb = {sizeof(cb), builtin_conductance, builtin_split,
                                                  NULL};
            OK(sinter_electric_model_set_host(f.em, &cb, &calls));
        }
        OK(solve(&f, NULL));
        const double *p = sinter_electric_dissipation(f.em, 6);
        assert_non_null(p);
        memcpy(runs[host], f.ps->current, 6 * sizeof(double));
        memcpy(runs[host] + 6, p, 6 * sizeof(double));
        memcpy(runs[host] + 12, f.em->potential, 8 * sizeof(double));
        double heat = -1.0;
        OK(sinter_electric_model_electrode_heat(f.em, &heat));
        assert_true(heat == 0.0);
    }
    assert_int_equal(calls, 2); /* one call per batch */
    assert_true(runs[0][0] > 0.0);
    assert_memory_equal(runs[0], runs[1], 20 * sizeof(double));
    close_fixture(&f);
}

/*
 * A host split conserves energy: a chain of alternating materials between walls at v0 and 0,
 * split by the series rule. Closed form (equal radii): pair (i, j) gives i the fraction
 * sigma_j / (sigma_i + sigma_j) of I^2 / G_ij, G_ij = sigma_ij A / d; an end particle also
 * takes its electrode contact's I^2 / G_w. The particles' powers sum to the walls' work v0 I;
 * with an electrode share of 3/4 a quarter of the electrode contacts' power goes to the
 * electrodes, and particles plus electrodes still sum to v0 I (round-off: 1e-12).
 */
static void test_host_split_energy_balance(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    enum { N = 5 };
    const double dp = 1e-4, dw = 2e-4, v0 = 2.0;
    const double delta[N - 1] = {dp, dp, dp, dp};
    const double x_right = add_chain(&f, N, delta, dw, 0.0, 0);
    for (size_t i = 1; i < N; i += 2)
        f.ps->material[i] = 1;
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, v0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    const double s_pair = 2.0 * SIGMA[0] * SIGMA[1] / (SIGMA[0] + SIGMA[1]);
    const double g_pp = s_pair * pair_area(dp) / (2.0 * R - dp);
    const double g_w = SIGMA[0] * wall_area(dw) / (R - dw);
    const double current = v0 / (2.0 / g_w + (N - 1) / g_pp);
    model(&f, "network", 1e-14);
    double wall_share = 1.0;
    const sinter_electric_callbacks cb = {sizeof(cb), NULL, series_split, NULL};
    OK(sinter_electric_model_set_host(f.em, &cb, &wall_share));
    for (int pass = 0; pass < 2; ++pass) {
        wall_share = pass == 0 ? 1.0 : 0.75;
        OK(solve(&f, NULL));
        double supplied = 0, dissipated = 0, electrodes = 0;
        OK(sinter_electric_model_power(f.em, &supplied, &dissipated));
        OK(sinter_electric_model_electrode_heat(f.em, &electrodes));
        const double *p = sinter_electric_dissipation(f.em, N);
        assert_non_null(p);
        const double pair = current * current / g_pp, wall = current * current / g_w;
        double sum = 0.0;
        for (size_t k = 0; k < N; ++k) {
            const int m = f.ps->material[k];
            const double own = SIGMA[1 - m] / (SIGMA[0] + SIGMA[1]); /* of each of its pairs */
            const double expected =
                (k == 0 || k == N - 1) ? wall_share * wall + own * pair : 2.0 * own * pair;
            assert_rel(p[k], expected, 1e-12);
            sum += p[k];
        }
        print_message("series split, electrode share %.2f: particles %.12g W + electrodes %.12g W "
                      "= %.12g W, supplied %.12g W\n",
                      wall_share, sum, electrodes, sum + electrodes, supplied);
        assert_rel(supplied, v0 * current, 1e-12);
        assert_rel(electrodes, 2.0 * (1.0 - wall_share) * wall, 1e-12);
        assert_rel(sum + electrodes, supplied, 1e-12);
    }
    close_fixture(&f);
}

/* The Joule energy balance of a run (test_joule_energy_balance_over_a_run) with a host split
 * that gives particle i 0.8 of each pair's power. */
static void test_host_split_energy_balance_over_a_run(void **state)
{
    (void)state;
    energy_balance_over_a_run(1, 0);
}

/* Misuse: the averaged model, a wrong struct_size, an empty table, a negative conductance, a
 * share above 1, a failing callback; destroy_user runs once when replaced and once at the end. */
static void test_host_callbacks_misuse(void **state)
{
    (void)state;
    fixture f;
    open_fixture(&f);
    const double dp = 1e-4, dw = 2e-4;
    const double delta[1] = {dp};
    const double x_right = add_chain(&f, 2, delta, dw, 0.0, 0);
    add_wall(&f, 0.0, 1.0, SINTER_WALL_POTENTIAL, 1.0);
    add_wall(&f, x_right, -1.0, SINTER_WALL_POTENTIAL, 0.0);
    find_contacts(&f);
    double value = -1.0;
    sinter_electric_callbacks cb = {sizeof(cb), bad_conductance, NULL, count_destroy};
    model(&f, "averaged", 0.0);
    assert_int_equal(sinter_electric_model_set_host(f.em, &cb, &value), SINTER_ERR_UNSUPPORTED);
    assert_int_equal(sinter_electric_model_electrode_heat(f.em, &value), SINTER_ERR_UNSUPPORTED);
    sinter_electric_model_destroy(f.em);
    f.em = NULL;
    model(&f, "network", 0.0);
    assert_int_equal(sinter_electric_model_set_host(NULL, &cb, &value), SINTER_ERR_NULL);
    assert_int_equal(sinter_electric_model_electrode_heat(f.em, NULL), SINTER_ERR_NULL);
    cb.struct_size = 8;
    assert_int_equal(sinter_electric_model_set_host(f.em, &cb, &value), SINTER_ERR_STRUCT_SIZE);
    const sinter_electric_callbacks empty = {sizeof(empty), NULL, NULL, count_destroy};
    assert_int_equal(sinter_electric_model_set_host(f.em, &empty, &value), SINTER_ERR_INVALID);
    cb.struct_size = sizeof(cb);
    destroyed = 0;
    OK(sinter_electric_model_set_host(f.em, &cb, &value));
    value = -1.0;
    assert_int_equal(solve(&f, NULL), SINTER_ERR_DOMAIN);
    value = NAN;
    assert_int_equal(solve(&f, NULL), SINTER_ERR_DOMAIN);
    value = 0.0; /* an insulating first contact: the chain carries nothing */
    OK(solve(&f, NULL));
    assert_true(f.ps->current[1] == 0.0);
    double share = 1.5;
    const sinter_electric_callbacks split = {sizeof(split), NULL, fixed_split, count_destroy};
    OK(sinter_electric_model_set_host(f.em, &split, &share));
    assert_int_equal(destroyed, 1);
    assert_int_equal(solve(&f, NULL), SINTER_ERR_DOMAIN);
    const sinter_electric_callbacks fail = {sizeof(fail), NULL, failing_split, count_destroy};
    OK(sinter_electric_model_set_host(f.em, &fail, NULL));
    assert_int_equal(solve(&f, NULL), SINTER_ERR_CALLBACK);
    OK(sinter_electric_model_set_host(f.em, NULL, NULL)); /* the built-in again */
    assert_int_equal(destroyed, 3);
    OK(solve(&f, NULL));
    assert_true(f.ps->current[1] > 0.0);
    OK(sinter_electric_model_set_host(f.em, &split, &share));
    close_fixture(&f);
    assert_int_equal(destroyed, 4);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_averaged_chain_equal_areas),
        cmocka_unit_test(test_averaged_unequal_areas),
        cmocka_unit_test(test_network_series_chain),
        cmocka_unit_test(test_network_warm_start),
        cmocka_unit_test(test_network_warm_start_follows_a_sort),
        cmocka_unit_test(test_network_sort_interval_same_iterations),
        cmocka_unit_test(test_parallel_chains),
        cmocka_unit_test(test_isolated_particles),
        cmocka_unit_test(test_iterations),
        cmocka_unit_test(test_joule_constant_conductivity),
        cmocka_unit_test(test_joule_sigmoid),
        cmocka_unit_test(test_misuse),
        cmocka_unit_test(test_network_power_and_joule_shares),
        cmocka_unit_test(test_network_conductivity_follows_temperature),
        cmocka_unit_test(test_network_conductivity_table),
        cmocka_unit_test(test_joule_energy_balance_over_a_run),
        cmocka_unit_test(test_joule_and_wall_heat_balance_over_a_run),
        cmocka_unit_test(test_supply_limits_pulses_and_schedules),
        cmocka_unit_test(test_host_callbacks_reproduce_builtin),
        cmocka_unit_test(test_host_split_energy_balance),
        cmocka_unit_test(test_host_split_energy_balance_over_a_run),
        cmocka_unit_test(test_host_callbacks_misuse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
