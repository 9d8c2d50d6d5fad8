/*
 * The global solves across subdomains (issue 43, domain/solve.h): implicit conduction and the
 * "network" electric model with the explicit stepper, 1 to 4 subdomains as threads of one
 * process (domain_loopback.h), slabs along x. Spheres without force models: they stay where
 * they are, so the contact network is the same in every run.
 *
 *  - Implicit conduction in a block of 72 spheres (no walls: an isolated body), 20 backward
 *    Euler steps of 20 ms, three times the explicit limit: on one subdomain the bits of the
 *    run without domain operations; on 2-4 the temperatures equal it within 1e-9 relative of
 *    the changes, and the enthalpy is conserved (a conservation law, to the PCG's residual).
 *  - A chain of 12 spheres between a wall at 1 V and a grounded one: on one subdomain the
 *    same bits; on 2-4 subdomains the current of every sphere is the chain's analytic
 *    V / (2 / G_w + 11 / G_pp) and the potentials, currents, Joule powers and the electrode
 *    current equal the single-domain run. With the left wall a current electrode of 0.25 A
 *    (its potential an unknown held by every subdomain) every sphere carries 0.25 A.
 *  - The block between a current electrode and a grounded wall, with Joule heating and
 *    implicit conduction for 10 steps: the same comparisons, and the same PCG iterations.
 *
 *  - The reproducible mode (stepper option "reproducible"; test_reproducible_mode): four of
 *    the scenes above without domain operations and on 1-4 subdomains, on 1 and 2 threads:
 *    every value above and the iteration counts the same bits (memcmp).
 *
 * Tolerances: both PCGs stop at a relative residual of 1e-13 (conduction's fixed test, the
 * network's "tolerance" set here); a decomposed run sums the same terms in another order, so
 * its iterates differ by round-off, and the two solutions differ by at most the condition
 * number (~ n^2 for the chain, ~ 1 + h G / m C for backward Euler, both below 1e3 here) times
 * the residual: 1e-9 relative leaves a factor of ten.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_submodel.h>

#include "domain_loopback.h"
#include "electric/electric.h"
#include "stepper/stepper.h"
#include "rel_diff.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

enum { NMAX = 72 };
static const double R = 1e-3;    /* radius [m] */
static const double A = 1.96e-3; /* lattice spacing [m]: overlap 4e-5 m */
static const double DW = 4e-5;   /* overlap with the electrode walls [m] */
static const double SIGMA = 1e5; /* electric conductivity [S/m] */
static const double PI = 3.14159265358979323846;

typedef enum scene_kind {
    CONDUCTION,
    CHAIN,
    CHAIN_CURRENT,
    CHAIN_BALANCED,
    BLOCK_JOULE
} scene_kind;

typedef struct scene {
    scene_kind kind;
    int nx, ny, nz, steps;
    double dt;
    int floating;  /* a chain of this many spheres touching neither wall, across the middle */
    double jiggle; /* > 0: random x velocities up to this [m/s] and slab borders just past
                      columns of spheres, which cross them back and forth (migrations) */
} scene;

/* What a run leaves, by id - 1. */
typedef struct result {
    double temp[NMAX], current[NMAX], phi[NMAX], joule[NMAX];
    double wall_phi[2], supplied, dissipated;
    uint64_t thermal_iterations, electric_iterations, migrated;
    int seen[NMAX];
} result;

typedef struct job {
    const scene *sc;
    int rank, size;
    loopback *lb;
    result *out;
    int failed;
    char message[512];
} job;

static pthread_mutex_t OUT_LOCK = PTHREAD_MUTEX_INITIALIZER;

/* The stepper's option "reproducible" and the context's threads of every run (set by the
 * reproducible mode's test; 0 and 1 otherwise). */
static int REPRO = 0, THREADS = 1;

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static int count_of(const scene *sc)
{
    return sc->nx * sc->ny * sc->nz + sc->floating;
}

static double length_of(const scene *sc) /* the wall-to-wall distance [m] */
{
    return A * (sc->nx - 1) + 2.0 * (R - DW);
}

/* The slabs' range along x: the walls', or with jiggling spheres 1e-5 m past the first column
 * and twelve spacings long (so that every border lies 1e-5 m past a column). */
static void slabs_of(const scene *sc, double *x0, double *x1)
{
    *x0 = sc->jiggle > 0.0 ? R - DW + 1e-5 : 0.0;
    *x1 = sc->jiggle > 0.0 ? *x0 + 12.0 * A : length_of(sc);
}

static int slab_of(const scene *sc, double x, int size)
{
    double x0, x1;
    slabs_of(sc, &x0, &x1);
    const double r = floor((x - x0) / (x1 - x0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->failed = __LINE__;                                                                  \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void *run_scene(void *arg)
{
    job *j = arg;
    const scene *sc = j->sc;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL, *wall_mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_heat_model *cond = NULL, *joule = NULL;
    sinter_electric_model *em = NULL;
    const int electric = sc->kind != CONDUCTION;
    const int heat = sc->kind == CONDUCTION || sc->kind == BLOCK_JOULE;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, THREADS));
    TRY(sinter_material_create(&mat, ctx, "sphere"));
    TRY(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500));
    TRY(sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400));
    TRY(sinter_material_set(mat, SINTER_MAT_HEAT_CAPACITY, 400));
    TRY(sinter_material_set(mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, SIGMA));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    if (electric) {
        TRY(sinter_walls_create(&walls, ctx));
        TRY(sinter_material_create(&wall_mat, ctx, "electrode"));
        const double p0[3] = {0, 0, 0}, n0[3] = {1, 0, 0};
        const double p1[3] = {length_of(sc), 0, 0}, n1[3] = {-1, 0, 0};
        TRY(sinter_walls_add_plane(walls, p0, n0, wall_mat, NULL));
        TRY(sinter_walls_add_plane(walls, p1, n1, wall_mat, NULL));
        if (sc->kind == CHAIN)
            TRY(sinter_walls_set_electric(walls, 0, SINTER_WALL_POTENTIAL, 1.0));
        else
            TRY(sinter_walls_set_electric(walls, 0, SINTER_WALL_CURRENT, 0.25));
        if (sc->kind == CHAIN_BALANCED) /* (0.25 A out: wall 0 is pinned at 0 V) */
            TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_CURRENT, -0.25));
        else
            TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    }
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "reproducible", REPRO));
    if (heat) {
        TRY(sinter_heat_model_create(&cond, ctx, "conduction"));
        TRY(sinter_stepper_add_heat(st, cond));
        TRY(sinter_stepper_set_thermal_scheme(st, SINTER_THERMAL_IMPLICIT));
    }
    if (electric) {
        TRY(sinter_electric_model_create(&em, ctx, "network"));
        TRY(sinter_electric_model_set(em, "tolerance", 1e-13));
        TRY(sinter_stepper_set_electric(st, em));
    }
    if (sc->kind == BLOCK_JOULE) {
        TRY(sinter_heat_model_create(&joule, ctx, "joule"));
        TRY(sinter_stepper_add_heat(st, joule));
    }
    uint64_t seed = 28;
    const int lattice = sc->nx * sc->ny * sc->nz;
    for (int k = 0; k < count_of(sc); ++k) {
        const int i = k < lattice ? k % sc->nx : sc->nx / 2 - sc->floating / 2 + k - lattice;
        const int l = k < lattice ? (k / sc->nx) % sc->ny : 3 * sc->ny; /* (apart) */
        const int m = k < lattice ? k / (sc->nx * sc->ny) : 0;
        const double x[3] = {R - DW + A * i, A * l, A * m};
        const double theta = 300.0 + 200.0 * i / (sc->nx - 1) + 20.0 * lcg(&seed);
        /* ids in another order than the lattice's */
        const uint64_t id = 1 + (uint64_t)((k * 29) % count_of(sc));
        const double vx = sc->jiggle * (2.0 * lcg(&seed) - 1.0);
        if (slab_of(sc, x[0], j->size) != j->rank)
            continue;
        size_t first = 0;
        TRY(sinter_particles_add_with_ids(ps, 1, &id, x, &R, 0, theta, &first));
        double *v = NULL;
        TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
        v[3 * first] = vx;
        TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
    }
    TRY(sinter_stepper_set_dt(st, sc->dt));
    if (sc->jiggle > 0.0) /* rebuilds, and so redistributions, every few steps */
        TRY(sinter_stepper_set_skin(st, 1e-5));
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    for (int k = 0; k < sc->steps; ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (s != SINTER_OK) {
            snprintf(j->message, sizeof(j->message), "step %d: %s", k + 1, sinter_last_error(ctx));
            j->failed = -1;
            goto done;
        }
    }
    size_t owned = 0;
    TRY(sinter_particles_owned_count(ps, &owned));
    pthread_mutex_lock(&OUT_LOCK);
    result *out = j->out;
    const int solved = electric && em->node_count == owned + 2 && em->dissipation_count > 0;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)ps->id[i] - 1;
        out->temp[k] = ps->temperature[i];
        out->current[k] = ps->current[i];
        out->phi[k] = solved ? em->potential[i] : 0.0;
        out->joule[k] = solved ? em->dissipation[i] : 0.0;
        out->seen[k]++;
    }
    if (j->rank == 0) {
        out->thermal_iterations = st->stats_thermal_iterations;
        if (solved) {
            memcpy(out->wall_phi, em->potential + owned, sizeof(out->wall_phi));
            TRY(sinter_electric_model_power(em, &out->supplied, &out->dissipated));
            TRY(sinter_stepper_electric_iterations(st, &out->electric_iterations));
        }
    }
    pthread_mutex_unlock(&OUT_LOCK);
done:
    if (j->failed > 0)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(cond);
    sinter_heat_model_destroy(joule);
    sinter_electric_model_destroy(em);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_material_destroy(wall_mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The scene on `size` subdomains (0: one run without domain operations). */
static void run(const scene *sc, int size, result *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    double x0, x1;
    slabs_of(sc, &x0, &x1);
    if (lb != NULL)
        loopback_set_slabs(lb, x0, x1);
    pthread_t threads[LOOPBACK_MAX];
    job jobs[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.sc = sc, .rank = r, .size = n, .lb = lb, .out = out};
        assert_int_equal(pthread_create(&threads[r], NULL, run_scene, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r) {
        assert_int_equal(pthread_join(threads[r], NULL), 0);
        out->migrated += lb != NULL ? loopback_migrated(lb, r) : 0;
    }
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].failed)
            print_error("%d subdomains, subdomain %d: %s\n", size, r, jobs[r].message);
        assert_int_equal(jobs[r].failed, 0);
    }
    for (int k = 0; k < count_of(sc); ++k)
        assert_int_equal(out->seen[k], 1);
}

static result REF, DEC, START;

/* The scene on 1-4 subdomains against the run without domain operations: one subdomain the
 * same bits, more within 1e-9 relative. */
static void compare_decompositions(const scene *sc)
{
    const int n = count_of(sc);
    run(sc, 0, &REF);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run(sc, size, &DEC);
        if (size == 1) {
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(DEC.current, REF.current, sizeof(REF.current));
            assert_memory_equal(DEC.phi, REF.phi, sizeof(REF.phi));
            assert_memory_equal(DEC.joule, REF.joule, sizeof(REF.joule));
            assert_memory_equal(DEC.wall_phi, REF.wall_phi, sizeof(REF.wall_phi));
            assert_true(DEC.supplied == REF.supplied && DEC.dissipated == REF.dissipated);
            assert_true(DEC.thermal_iterations == REF.thermal_iterations);
            assert_true(DEC.electric_iterations == REF.electric_iterations);
            continue;
        }
        double dt_ref[NMAX], dt_dec[NMAX]; /* temperature changes */
        for (int k = 0; k < n; ++k) {
            dt_ref[k] = REF.temp[k] - START.temp[k];
            dt_dec[k] = DEC.temp[k] - START.temp[k];
        }
        const double et = rel_diff(dt_dec, dt_ref, n), ei = rel_diff(DEC.current, REF.current, n),
                     ep = rel_diff(DEC.phi, REF.phi, n), ej = rel_diff(DEC.joule, REF.joule, n),
                     ew = rel_diff(DEC.wall_phi, REF.wall_phi, 2);
        print_message("%d subdomains: temperature changes %.2g, currents %.2g, potentials %.2g, "
                      "Joule %.2g, walls %.2g relative; iterations %llu + %llu (single domain "
                      "%llu + %llu)\n",
                      size, et, ei, ep, ej, ew, (unsigned long long)DEC.thermal_iterations,
                      (unsigned long long)DEC.electric_iterations,
                      (unsigned long long)REF.thermal_iterations,
                      (unsigned long long)REF.electric_iterations);
        assert_true(et <= 1e-9 && ei <= 1e-9 && ep <= 1e-9 && ej <= 1e-9 && ew <= 1e-9);
        assert_true(fabs(DEC.supplied - REF.supplied) <= 1e-9 * fabs(REF.supplied));
        assert_true(fabs(DEC.dissipated - REF.dissipated) <= 1e-9 * fabs(REF.dissipated));
        if (sc->jiggle > 0.0) { /* (migrations: a solve's start may differ by round-off) */
            print_message("%d subdomains: %llu migrations\n", size,
                          (unsigned long long)DEC.migrated);
            assert_true(DEC.migrated > 0);
            continue;
        }
        /* Jacobi is pointwise: the single-domain preconditioner, the same iterations but for
         * round-off deciding the last one (at most one per solve) */
        const double solves = sc->steps + 1.0;
        assert_true(fabs((double)DEC.thermal_iterations - (double)REF.thermal_iterations) <=
                    solves);
        assert_true(fabs((double)DEC.electric_iterations - (double)REF.electric_iterations) <=
                    2.0 * solves);
    }
}

/* The initial temperatures (a run of no steps). */
static void start_of(const scene *sc)
{
    scene s0 = *sc;
    s0.steps = 0;
    run(&s0, 0, &START);
}

static void test_implicit_conduction(void **state)
{
    (void)state;
    const scene sc = {CONDUCTION, 12, 3, 2, 20, 0.02, 0, 0.0};
    start_of(&sc);
    compare_decompositions(&sc);
    /* an isolated body: sum m C theta conserved (C constant) */
    const double m = 2500.0 * 4.0 / 3.0 * PI * R * R * R, C = 400.0;
    double moved = 0.0, net = 0.0, changed = 0.0;
    for (int k = 0; k < count_of(&sc); ++k) {
        net += m * C * (DEC.temp[k] - START.temp[k]);
        moved += m * C * fabs(DEC.temp[k] - START.temp[k]);
        changed = fmax(changed, fabs(DEC.temp[k] - START.temp[k]));
    }
    print_message("conduction: largest change %.3g K, energy moved %.3g J, net %.3g J\n", changed,
                  moved, net);
    assert_true(changed > 1.0); /* 3 times the explicit limit: the heat moved */
    assert_true(fabs(net) <= 1e-9 * moved);
}

/* Seed 000 eq. 7-12 for equal radii and the wall contact (tests/unit/test_electric.c). */
static void chain_conductances(double *g_pp, double *g_w)
{
    const double dp = 2.0 * R - A, half = R - 0.5 * dp, s = R - DW;
    *g_pp = SIGMA * PI * (R * R - half * half) / A;
    *g_w = SIGMA * PI * (R * R - s * s) / s;
}

static void test_network_chain(void **state)
{
    (void)state;
    const scene sc = {CHAIN, 12, 1, 1, 2, 1e-6, 4, 0.0};
    start_of(&sc);
    compare_decompositions(&sc);
    double g_pp, g_w;
    chain_conductances(&g_pp, &g_w);
    const double current = 1.0 / (2.0 / g_w + (sc.nx - 1) / g_pp);
    print_message("chain: I = %.9g A analytic, electrode current %.9g A (4 subdomains)\n", current,
                  DEC.supplied / 1.0);
    for (int k = 0; k < count_of(&sc); ++k) {
        const int id = (k * 29) % count_of(&sc); /* (id - 1 of the sphere made k-th) */
        if (k >= sc.nx) /* the floating chain, across a border: no driven wall, no current */
            assert_true(DEC.current[id] == 0.0 && DEC.phi[id] == 0.0);
        else
            assert_true(fabs(DEC.current[id] - current) <= 1e-10 * current);
    }
    assert_true(fabs(DEC.supplied - current) <= 1e-10 * current); /* P = V I at 1 V */
}

static void test_network_chain_current_wall(void **state)
{
    (void)state;
    const scene sc = {CHAIN_CURRENT, 12, 1, 1, 2, 1e-6, 0, 0.0};
    start_of(&sc);
    compare_decompositions(&sc);
    double g_pp, g_w;
    chain_conductances(&g_pp, &g_w);
    for (int k = 0; k < sc.nx; ++k)
        assert_true(fabs(DEC.current[k] - 0.25) <= 1e-10 * 0.25);
    const double v = 0.25 * (2.0 / g_w + (sc.nx - 1) / g_pp); /* the electrode's potential */
    assert_true(fabs(DEC.wall_phi[0] - v) <= 1e-10 * v);
}

/* Both electrodes current walls, +0.25 A and -0.25 A: balanced, the first pinned at 0 V (on
 * every subdomain: the cluster's label is its first current wall), the other at -0.25 A times
 * the chain's resistance. */
static void test_network_chain_balanced(void **state)
{
    (void)state;
    const scene sc = {CHAIN_BALANCED, 12, 1, 1, 2, 1e-6, 0, 0.0};
    start_of(&sc);
    compare_decompositions(&sc);
    double g_pp, g_w;
    chain_conductances(&g_pp, &g_w);
    for (int k = 0; k < sc.nx; ++k)
        assert_true(fabs(DEC.current[k] - 0.25) <= 1e-10 * 0.25);
    assert_true(DEC.wall_phi[0] == 0.0);
    const double v = -0.25 * (2.0 / g_w + (sc.nx - 1) / g_pp);
    assert_true(fabs(DEC.wall_phi[1] - v) <= 1e-10 * fabs(v));
}

static void test_network_block_joule(void **state)
{
    (void)state;
    const scene sc = {BLOCK_JOULE, 12, 3, 2, 10, 0.02, 0, 0.0};
    start_of(&sc);
    compare_decompositions(&sc);
    /* Tellegen: what the electrodes supply is what the contacts dissipate */
    assert_true(fabs(DEC.supplied - DEC.dissipated) <= 1e-9 * DEC.supplied);
}

/* What is not yet distributed is refused, naming it: the network's host callbacks; the
 * plain network and the "averaged" model are accepted (the averaged model with the explicit
 * stepper: test_domain_electric.c). */
/* A Joule split for the refusal below (never called: the model is refused first). */
static int host_split(const sinter_state_view *view, const sinter_contact_batch *contacts,
                      const double *power, double *share, void *user)
{
    (void)view;
    (void)contacts;
    (void)power;
    (void)share;
    (void)user;
    return 0;
}

static void test_refused_models(void **state)
{
    (void)state;
    sinter_ctx *ctx;
    sinter_particles *ps;
    sinter_stepper *st;
    sinter_electric_model *averaged, *network;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_particles_create(&ps, ctx));
    OK(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, NULL));
    OK(sinter_electric_model_create(&averaged, ctx, "averaged"));
    OK(sinter_electric_model_create(&network, ctx, "network"));
    loopback *lb = loopback_create(1);
    assert_non_null(lb);
    OK(sinter_stepper_set_electric(st, averaged));
    OK(loopback_attach(lb, 0, st, ps));
    const sinter_electric_callbacks host = {.struct_size = sizeof(host), .joule_split = host_split};
    OK(sinter_electric_model_set_host(network, &host, NULL));
    OK(sinter_stepper_set_electric(st, network));
    assert_int_equal(loopback_attach(lb, 0, st, ps), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(ctx), "electric model with host callbacks"));
    OK(sinter_electric_model_set_host(network, NULL, NULL));
    OK(loopback_attach(lb, 0, st, ps));
    /* installed afterwards: refused at the next step, on every subdomain */
    OK(sinter_electric_model_set_host(network, &host, NULL));
    OK(sinter_stepper_set_dt(st, 1e-6));
    assert_int_equal(sinter_stepper_step(st, 1), SINTER_ERR_UNSUPPORTED);
    OK(sinter_stepper_set_electric(st, NULL));
    sinter_stepper_destroy(st);
    loopback_destroy(lb);
    sinter_electric_model_destroy(averaged);
    sinter_electric_model_destroy(network);
    sinter_particles_destroy(ps);
    sinter_ctx_destroy(ctx);
}

/* The block with Joule heating and implicit conduction, its spheres jiggling along x across
 * the slab borders: migrations in the middle of the solves' runs, the ghosts made again. */
static void test_moving_block(void **state)
{
    (void)state;
    const scene sc = {BLOCK_JOULE, 12, 3, 2, 20, 1e-3, 0, 2e-3};
    start_of(&sc);
    compare_decompositions(&sc);
    assert_true(fabs(DEC.supplied - DEC.dissipated) <= 1e-9 * DEC.supplied);
}

/*
 * The reproducible mode (stepper option "reproducible" = 1, issue 43): the PCGs' dot products
 * and norms exact sums, each row's terms in the order of the id-sorted pair list, a free
 * current wall's row and diagonal exact sums over the subdomains, and the run without domain
 * operations on the same arithmetic. Without domain operations on one thread, and on 1-4
 * subdomains on one and two threads: every sphere's temperature, current, potential and Joule
 * power, the electrodes' potentials, the supplied and dissipated powers and the iterations of
 * both solves the same bits. Scenes: the conduction block, the balanced chain (both
 * electrodes current walls: a free wall row on every subdomain), the block with Joule heating,
 * and the jiggling block (migrations between the solves). The default mode on 3 subdomains
 * differs in some value of each scene (what the test would miss without the mode).
 */
static int same_bits(const result *a, const result *b)
{
    return memcmp(a->temp, b->temp, sizeof(a->temp)) == 0 &&
           memcmp(a->current, b->current, sizeof(a->current)) == 0 &&
           memcmp(a->phi, b->phi, sizeof(a->phi)) == 0 &&
           memcmp(a->joule, b->joule, sizeof(a->joule)) == 0 &&
           memcmp(a->wall_phi, b->wall_phi, sizeof(a->wall_phi)) == 0 &&
           memcmp(&a->supplied, &b->supplied, sizeof(double)) == 0 &&
           memcmp(&a->dissipated, &b->dissipated, sizeof(double)) == 0 &&
           a->thermal_iterations == b->thermal_iterations &&
           a->electric_iterations == b->electric_iterations;
}

static void test_reproducible_mode(void **state)
{
    (void)state;
    const scene scenes[] = {{CONDUCTION, 12, 3, 2, 20, 0.02, 0, 0.0},
                            {CHAIN_BALANCED, 12, 1, 1, 2, 1e-6, 0, 0.0},
                            {BLOCK_JOULE, 12, 3, 2, 10, 0.02, 0, 0.0},
                            {BLOCK_JOULE, 12, 3, 2, 20, 1e-3, 0, 2e-3}};
    for (size_t c = 0; c < sizeof(scenes) / sizeof(scenes[0]); ++c) {
        const scene *sc = &scenes[c];
        REPRO = 0;
        run(sc, 0, &REF);
        run(sc, 3, &DEC);
        const int default_same = same_bits(&DEC, &REF);
        REPRO = 1;
        THREADS = 1;
        run(sc, 0, &REF);
        int differing = 0;
        for (int threads = 1; threads <= 2; ++threads)
            for (int size = 1; size <= LOOPBACK_MAX; ++size) {
                THREADS = threads;
                run(sc, size, &DEC);
                if (!same_bits(&DEC, &REF)) {
                    print_error("scene %zu, %d subdomains, %d threads: not the same bits\n", c,
                                size, threads);
                    differing++;
                }
            }
        REPRO = 0;
        THREADS = 1;
        print_message("scene %zu: reproducible mode the same bits on 0-4 subdomains, 1-2 threads "
                      "(%d runs differ; the default mode on 3 subdomains %s); iterations %llu + "
                      "%llu, migrations %llu\n",
                      c, differing, default_same ? "the same" : "differs",
                      (unsigned long long)REF.thermal_iterations,
                      (unsigned long long)REF.electric_iterations,
                      (unsigned long long)DEC.migrated);
        assert_int_equal(differing, 0);
        assert_false(default_same);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_implicit_conduction),
        cmocka_unit_test(test_network_chain),
        cmocka_unit_test(test_network_chain_current_wall),
        cmocka_unit_test(test_network_chain_balanced),
        cmocka_unit_test(test_network_block_joule),
        cmocka_unit_test(test_moving_block),
        cmocka_unit_test(test_refused_models),
        cmocka_unit_test(test_reproducible_mode),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
