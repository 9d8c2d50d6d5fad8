/*
 * The electric models with either stepper on subdomains (issue 43, include/sinter_domain.h),
 * through the thread transport of domain_loopback.h: slabs along x, 1 to 4 subdomains as
 * threads of one process, on the press of domain_press.h (240 spheres, the seed 000 power
 * law, drag, gravity, conduction and Joule heating, the top wall moving down).
 *
 *  - The "network" model inside the staggered stepper's fixed point (scheme 1, 20 adaptive
 *    steps): every evaluation of every iterate solves the network over all subdomains at
 *    once (domain/solve.h: the ghosts' potentials haloed before each operator product, the
 *    dot products reduced, the floor a current electrode whose potential every subdomain
 *    holds, its compliance limit compared with the reduced current).
 *  - The "averaged" model with the explicit stepper (examples/scenes/press.scene's pairing):
 *    its search and sweeps across borders (averaged.c) at every step.
 *  - On one subdomain each run gives the bits of the run without domain operations (a
 *    reduction of one part returns its bits).
 *  - On 2, 3 and 4 subdomains: the same steps, rejections and fixed-point iterations (and
 *    PCG or sweep counts equal on every subdomain); displacements, velocities, temperature
 *    changes, currents and wall forces within 1e-10 relative of the single domain, or ten
 *    times the spread of the serial run itself, whichever is larger. The spread: the serial
 *    run with its particles added last first, which sums every term in another order, as a
 *    decomposition does. Why it can exceed 1e-10: the network's PCG stops at a residual of
 *    1e-13 relative to the whole right-hand side, so round-off in its sums moves the currents
 *    by 1.7e-10 relative in the serial run alone (measured; every other quantity stays below
 *    3e-12); the seed's Coulomb friction (eq. 5-6, a jump of
 *    mu F_n when a sliding velocity changes sign) turns round-off into differences of 4e-4
 *    in the displacements and 1e-2 in the wall forces over the explicit run's 200 steps, in
 *    the serial run as in the decomposed ones. So the explicit run is compared twice:
 *    without friction (within 1e-10: it measures 3e-14) and with it (within ten times the
 *    serial spread). The averaged model's sweeps are Jacobi across a border and stop at a
 *    change of 1e-14: its currents agree to 1e-15.
 *  - With slab borders on columns of the lattice the particles about them migrate (the
 *    staggered stepper at its accepted states, the explicit one at its rebuilds; the
 *    network then restarts from zero on every subdomain): the same comparisons.
 *  - Implicit conduction never meets the staggered stepper (it integrates the temperatures
 *    in its own fixed point, seed 000 eq. 36): the stepper refuses the scheme itself, with
 *    or without subdomains.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_loopback.h"
#include "domain_press.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

enum { N = PRESS_N, NW = PRESS_WALLS };

typedef struct setting {
    const char *name;
    int kind, network, frictionless;
    int steps;
    double dt; /* the explicit stepper's */
    double x0, x1;
} setting;

typedef struct job_and_state {
    press_job *j;
    press_state *out;
    loopback *lb;
} job_and_state;

static press_spec PRESS;
static press_job REF_JOB, SPREAD_JOB, JOBS[LOOPBACK_MAX];
static press_state REF, SPREAD, DEC;
static double X_START[3 * N], T_START[N];

static sinter_status attach(void *user, sinter_stepper *st, sinter_particles *ps)
{
    const job_and_state *js = user;
    return loopback_attach(js->lb, js->j->rank, st, ps);
}

static void *run_thread(void *arg)
{
    job_and_state *js = arg;
    press_run(js->j, js->out);
    return NULL;
}

/* The press of `set` on `size` subdomains (0: one run without domain operations, its
 * particles added last first if `reverse`); returns the migrations made. */
static uint64_t run_decomposed(const setting *set, int size, int reverse, press_job *jobs,
                               press_state *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, set->x0, set->x1);
    pthread_t threads[LOOPBACK_MAX];
    job_and_state js[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (press_job){.spec = &PRESS,
                              .rank = r,
                              .size = n,
                              .x0 = set->x0,
                              .x1 = set->x1,
                              .kind = set->kind,
                              .network = set->network,
                              .frictionless = set->frictionless,
                              .reverse = reverse,
                              .scheme = 1,
                              .dt = set->dt,
                              .steps = set->steps,
                              .nan_after = INFINITY,
                              .attach = lb != NULL ? attach : NULL,
                              .user = &js[r]};
        js[r] = (job_and_state){&jobs[r], out, lb};
        assert_int_equal(pthread_create(&threads[r], NULL, run_thread, &js[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(threads[r], NULL), 0);
    uint64_t migrated = 0;
    for (int r = 0; r < n && lb != NULL; ++r)
        migrated += loopback_migrated(lb, r);
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].setup_failed || jobs[r].status != SINTER_OK)
            fprintf(stderr, "%s, subdomain %d: %s\n", set->name, r, jobs[r].message);
        assert_int_equal(jobs[r].setup_failed, 0);
        assert_int_equal(jobs[r].status, SINTER_OK);
    }
    return migrated;
}

static void compare(const setting *set, int migrations)
{
    press_make(&PRESS);
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)PRESS.id[k] - 1;
        memcpy(X_START + 3 * i, PRESS.x + 3 * k, 24);
        T_START[i] = PRESS.temp[k];
    }
    (void)run_decomposed(set, 0, 0, &REF_JOB, &REF);
    const sinter_stepper_stats *ref = &REF_JOB.stats;
    /* the run does what the test needs: rebuilds, currents, heating */
    double current = 0.0, heated = 0.0;
    for (int k = 0; k < N; ++k) {
        current = fmax(current, fabs(REF.current[k]));
        heated = fmax(heated, fabs(REF.temp[k] - T_START[k]));
    }
    fprintf(stderr,
            "%s, single domain: %llu steps, %llu rejected, %llu iterations, %llu builds, "
            "%llu electric iterations, t = %g s, largest current %g A, temperature change %g K\n",
            set->name, (unsigned long long)ref->steps, (unsigned long long)ref->rejected,
            (unsigned long long)ref->iterations, (unsigned long long)ref->neighbor_builds,
            (unsigned long long)REF_JOB.electric_iterations, REF_JOB.time, current, heated);
    /* the serial run's own spread, and the bounds: 1e-10 or ten times the spread */
    (void)run_decomposed(set, 0, 1, &SPREAD_JOB, &SPREAD);
    const double spread[5] = {press_rel_diff(SPREAD.x, REF.x, X_START, 3 * N),
                              press_rel_diff(SPREAD.v, REF.v, NULL, 3 * N),
                              press_rel_diff(SPREAD.temp, REF.temp, T_START, N),
                              press_rel_diff(SPREAD.current, REF.current, NULL, N),
                              press_rel_diff(SPREAD_JOB.wall, REF_JOB.wall, NULL, 3 * NW)};
    double bound[5];
    for (int q = 0; q < 5; ++q)
        bound[q] = fmax(1e-10, 10.0 * spread[q]);
    fprintf(stderr,
            "%s, the serial run added last first: displacements %.2g, velocities %.2g, "
            "temperature changes %.2g, currents %.2g, wall forces %.2g (relative)\n",
            set->name, spread[0], spread[1], spread[2], spread[3], spread[4]);
    assert_true(ref->neighbor_builds >= 2); /* (one made by the first step) */
    assert_true(current > 0.0);
    assert_true(heated > 1e-3);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        const uint64_t migrated = run_decomposed(set, size, 0, JOBS, &DEC);
        size_t owned = 0;
        for (int r = 0; r < size; ++r) {
            owned += JOBS[r].owned;
            /* collective: every subdomain took the same steps, iterations and wall forces */
            assert_true(JOBS[r].time == JOBS[0].time);
            assert_int_equal(JOBS[r].stats.steps, ref->steps);
            assert_int_equal(JOBS[r].stats.rejected, ref->rejected);
            assert_int_equal(JOBS[r].stats.iterations, ref->iterations);
            assert_int_equal(JOBS[r].stats.evaluations, JOBS[0].stats.evaluations);
            assert_int_equal(JOBS[r].electric_iterations, JOBS[0].electric_iterations);
            assert_memory_equal(JOBS[r].wall, JOBS[0].wall, sizeof(JOBS[r].wall));
        }
        assert_int_equal(owned, N);
        for (int k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1);
        if (size == 1) { /* the same bits */
            assert_int_equal(migrated, 0);
            assert_true(JOBS[0].time == REF_JOB.time);
            assert_int_equal(JOBS[0].electric_iterations, REF_JOB.electric_iterations);
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.v, REF.v, sizeof(REF.v));
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(DEC.current, REF.current, sizeof(REF.current));
            assert_memory_equal(JOBS[0].wall, REF_JOB.wall, sizeof(REF_JOB.wall));
            continue;
        }
        const double d[5] = {press_rel_diff(DEC.x, REF.x, X_START, 3 * N),
                             press_rel_diff(DEC.v, REF.v, NULL, 3 * N),
                             press_rel_diff(DEC.temp, REF.temp, T_START, N),
                             press_rel_diff(DEC.current, REF.current, NULL, N),
                             press_rel_diff(JOBS[0].wall, REF_JOB.wall, NULL, 3 * NW)};
        fprintf(stderr,
                "%s, %d subdomains: %llu migrations, %llu electric iterations; displacements "
                "%.2g, velocities %.2g, temperature changes %.2g, currents %.2g, wall forces "
                "%.2g (relative)\n",
                set->name, size, (unsigned long long)migrated,
                (unsigned long long)JOBS[0].electric_iterations, d[0], d[1], d[2], d[3], d[4]);
        if (migrations)
            assert_true(migrated >= 1);
        else
            assert_int_equal(migrated, 0);
        assert_true(fabs(JOBS[0].time - REF_JOB.time) <= 1e-10 * REF_JOB.time);
        for (int q = 0; q < 5; ++q)
            assert_true(d[q] <= bound[q]);
    }
}

static const setting STAGGERED_NETWORK = {
    "staggered, network", SINTER_STEPPER_STAGGERED, 1, 0, 20, 0.0,
    PRESS_X0_BETWEEN,     PRESS_X1_BETWEEN};
static const setting EXPLICIT_AVERAGED = {"explicit, averaged, frictionless",
                                          SINTER_STEPPER_EXPLICIT,
                                          0,
                                          1,
                                          200,
                                          2e-4,
                                          PRESS_X0_BETWEEN,
                                          PRESS_X1_BETWEEN};

static void test_staggered_network(void **unused)
{
    (void)unused;
    compare(&STAGGERED_NETWORK, 0);
}

static void test_staggered_network_migration(void **unused)
{
    (void)unused;
    setting set = STAGGERED_NETWORK;
    set.name = "staggered, network, borders on columns";
    set.x0 = PRESS_X0_ON;
    set.x1 = PRESS_X1_ON;
    compare(&set, 1);
}

static void test_explicit_averaged(void **unused)
{
    (void)unused;
    compare(&EXPLICIT_AVERAGED, 0);
}

/* With the seed's friction: within ten times the serial run's own spread (see the top). */
static void test_explicit_averaged_friction(void **unused)
{
    (void)unused;
    setting set = EXPLICIT_AVERAGED;
    set.name = "explicit, averaged, with friction";
    set.frictionless = 0;
    compare(&set, 0);
}

static void test_explicit_averaged_migration(void **unused)
{
    (void)unused;
    setting set = EXPLICIT_AVERAGED;
    set.name = "explicit, averaged, frictionless, borders on columns";
    set.x0 = PRESS_X0_ON;
    set.x1 = PRESS_X1_ON;
    compare(&set, 1);
}

/* The staggered stepper takes no implicit conduction, with or without domain operations (so
 * no subdomain can meet it): its temperatures are iterated in its fixed point. */
static void test_staggered_refuses_implicit_conduction(void **unused)
{
    (void)unused;
    sinter_ctx *ctx;
    sinter_particles *ps;
    sinter_stepper *st;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_particles_create(&ps, ctx));
    OK(sinter_stepper_create(&st, ctx, SINTER_STEPPER_STAGGERED, ps, NULL));
    loopback *lb = loopback_create(1);
    assert_non_null(lb);
    OK(loopback_attach(lb, 0, st, ps));
    assert_int_equal(sinter_stepper_set_thermal_scheme(st, SINTER_THERMAL_IMPLICIT),
                     SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "staggered stepper integrates"));
    sinter_stepper_destroy(st);
    loopback_destroy(lb);
    sinter_particles_destroy(ps);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_staggered_network),
        cmocka_unit_test(test_staggered_network_migration),
        cmocka_unit_test(test_explicit_averaged),
        cmocka_unit_test(test_explicit_averaged_migration),
        cmocka_unit_test(test_explicit_averaged_friction),
        cmocka_unit_test(test_staggered_refuses_implicit_conduction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
