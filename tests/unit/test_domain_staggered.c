/*
 * The staggered stepper on subdomains (issue 43, include/sinter_domain.h), through the thread
 * transport of domain_loopback.h: slabs along x, 1 to 4 subdomains as threads of one process.
 *
 * A small press in the manner of examples/scenes/press_staggered.scene: 240 spheres in a
 * lattice with the seed 000 power law, drag, gravity, conduction, Joule heating and the
 * averaged electric model (seed 000 sec. 5) between two current walls, the top one moving
 * down; scheme 1 (Anderson acceleration) with adaptive steps.
 *  - On one subdomain the run equals the run without domain operations bit for bit (every
 *    reduction of one part returns its bits, so nothing is summed in another order).
 *  - On 2, 3 and 4 subdomains it equals it within 1e-10 relative (both schemes) (displacements,
 * velocities, temperature changes, currents, wall forces) with the same accepted and rejected steps
 * and the same fixed-point iterations: the error norms, Anderson's inner products and the decisions
 * come from reductions. The averaged model's sweeps are Gauss-Seidel within a subdomain and Jacobi
 * across its border, so its iterates differ from the single domain's; its tolerance is set to 1e-14
 * here so that they agree to round-off (at the scene's 1e-4 the currents differ by 6e-6 relative on
 * two subdomains, the temperature changes by 1.5e-4). With Anderson's inner products left local,
 * the displacements differ by 3e-3.
 *  - Particles that cross a border migrate at the next accepted state (migration is refused
 *    inside a fixed-point attempt), with the predictor's history: every particle stays owned
 *    once and the run equals the single-domain one within 1e-10 relative.
 *  - A NaN force made on one subdomain stops all of them at the same step with the same
 *    status and message, naming the subdomain and the particle's id.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_submodel.h>

#include "domain_loopback.h"
#include "domain_press.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

enum { NX = PRESS_NX, NY = PRESS_NY, N = PRESS_N, NW = PRESS_WALLS, STEPS = 12 };

static press_spec PRESS;

/* The slabs of the next runs (domain_press.h): borders between columns, or on them. */
static double X0 = PRESS_X0_BETWEEN, X1 = PRESS_X1_BETWEEN;

typedef press_job job;
typedef press_state state;

typedef struct job_and_state {
    job *j;
    state *out;
    loopback *lb;
} job_and_state;

static sinter_status attach(void *user, sinter_stepper *st, sinter_particles *ps)
{
    const job_and_state *js = user;
    return loopback_attach(js->lb, js->j->rank, st, ps);
}

static void *run_press(void *arg)
{
    job_and_state *js = arg;
    press_run(js->j, js->out);
    return NULL;
}

/* The press on `size` subdomains (0: one run without domain operations). */
static int SCHEME = 1; /* the scheme of the next runs */

static void run_decomposed(int size, int steps, uint64_t host_id, double nan_after, job *jobs,
                           state *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, X0, X1);
    pthread_t threads[LOOPBACK_MAX];
    job_and_state js[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.spec = &PRESS,
                        .rank = r,
                        .size = n,
                        .x0 = X0,
                        .x1 = X1,
                        .kind = SINTER_STEPPER_STAGGERED,
                        .steps = steps,
                        .scheme = SCHEME,
                        .host_id = host_id,
                        .nan_after = nan_after,
                        .attach = lb != NULL ? attach : NULL,
                        .user = &js[r]};
        js[r] = (job_and_state){&jobs[r], out, lb};
        assert_int_equal(pthread_create(&threads[r], NULL, run_press, &js[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(threads[r], NULL), 0);
    uint64_t migrated = 0;
    for (int r = 0; r < n && lb != NULL; ++r)
        migrated += loopback_migrated(lb, r);
    jobs[0].stats.bonds_broken = migrated; /* (the tests read the migrations here) */
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].setup_failed)
            fprintf(stderr, "subdomain %d: %s\n", r, jobs[r].message);
        assert_int_equal(jobs[r].setup_failed, 0);
    }
}

static job REF_JOB[1], JOBS[LOOPBACK_MAX];
static state REF, DEC;
static double X_START[3 * N], T_START[N];

static void compare_press(int scheme)
{
    SCHEME = scheme;
    press_make(&PRESS);
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)PRESS.id[k] - 1;
        memcpy(X_START + 3 * i, PRESS.x + 3 * k, 24);
        T_START[i] = PRESS.temp[k];
    }
    run_decomposed(0, STEPS, 0, INFINITY, REF_JOB, &REF);
    assert_int_equal(REF_JOB[0].status, SINTER_OK);
    const sinter_stepper_stats *ref = &REF_JOB[0].stats;
    /* the run does what the test needs: rebuilds, Anderson iterations, currents, heating */
    double current = 0.0, heated = 0.0;
    for (int k = 0; k < N; ++k) {
        current = fmax(current, REF.current[k]);
        heated = fmax(heated, fabs(REF.temp[k] - T_START[k]));
    }
    fprintf(stderr,
            "scheme %d, single domain: %llu steps, %llu rejected, %llu iterations, %llu builds, t "
            "= %g s, "
            "largest current %g A, temperature change %g K\n",
            scheme, (unsigned long long)ref->steps, (unsigned long long)ref->rejected,
            (unsigned long long)ref->iterations, (unsigned long long)ref->neighbor_builds,
            REF_JOB[0].time, current, heated);
    assert_true(ref->neighbor_builds >= (scheme == 1 ? 2 : 1)); /* (one made by the first) */
    assert_true(ref->iterations > 2 * ref->steps);
    assert_true(current > 0.0);
    assert_true(heated > 1e-3);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run_decomposed(size, STEPS, 0, INFINITY, JOBS, &DEC);
        size_t owned = 0;
        for (int r = 0; r < size; ++r) {
            if (JOBS[r].status != SINTER_OK)
                fprintf(stderr, "subdomain %d: %s\n", r, JOBS[r].message);
            assert_int_equal(JOBS[r].status, SINTER_OK);
            owned += JOBS[r].owned;
            /* collective: every subdomain took the same steps, iterations and wall forces */
            assert_true(JOBS[r].time == JOBS[0].time);
            assert_int_equal(JOBS[r].stats.steps, ref->steps);
            assert_int_equal(JOBS[r].stats.rejected, ref->rejected);
            assert_int_equal(JOBS[r].stats.iterations, ref->iterations);
            assert_int_equal(JOBS[r].stats.evaluations, JOBS[0].stats.evaluations);
            assert_memory_equal(JOBS[r].wall, JOBS[0].wall, sizeof(JOBS[r].wall));
        }
        assert_int_equal(owned, N);
        for (int k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1);
        assert_int_equal(JOBS[0].stats.bonds_broken, 0); /* no migration: see the slabs */
        if (size == 1) {                                 /* the same bits */
            assert_true(JOBS[0].time == REF_JOB[0].time);
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.v, REF.v, sizeof(REF.v));
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(DEC.current, REF.current, sizeof(REF.current));
            assert_memory_equal(JOBS[0].wall, REF_JOB[0].wall, sizeof(REF_JOB[0].wall));
            continue;
        }
        const double dx = press_rel_diff(DEC.x, REF.x, X_START, 3 * N);
        const double dv = press_rel_diff(DEC.v, REF.v, NULL, 3 * N);
        const double dt = press_rel_diff(DEC.temp, REF.temp, T_START, N);
        const double dc = press_rel_diff(DEC.current, REF.current, NULL, N);
        const double dw = press_rel_diff(JOBS[0].wall, REF_JOB[0].wall, NULL, 3 * NW);
        fprintf(stderr,
                "%d subdomains: displacements %.2g, velocities %.2g, temperature changes %.2g, "
                "currents %.2g, wall forces %.2g (relative); t %.17g s (single %.17g s)\n",
                size, dx, dv, dt, dc, dw, JOBS[0].time, REF_JOB[0].time);
        assert_true(fabs(JOBS[0].time - REF_JOB[0].time) <= 1e-10 * REF_JOB[0].time);
        assert_true(dx <= 1e-10);
        assert_true(dv <= 1e-10);
        assert_true(dt <= 1e-10);
        assert_true(dc <= 1e-10);
        assert_true(dw <= 1e-10);
    }
}

static void test_decomposed_press(void **unused)
{
    (void)unused;
    compare_press(1);
}

/* The same with scheme 0 (the seed's Algorithm 1: eq. 47's sums reduced). */
static void test_decomposed_press_scheme0(void **unused)
{
    (void)unused;
    compare_press(0);
}

/* Slabs whose borders lie on columns of the lattice (2, 3 and 4 of them): the particles of
 * those columns, jiggling about them, cross them. Their migrations are refused inside the
 * fixed-point attempts and made at the next accepted state, their records carrying the
 * predictor's history; every particle stays owned once, and the run equals the single-domain
 * one within 1e-10 relative, with the same steps, rejections and iterations. (With the
 * predictor restarted after each migration instead, the iterates differed by up to the
 * fixed-point tolerance: 2.2e-4 relative in the displacements on two slabs.) */
static void test_migration_at_accepted_state(void **unused)
{
    (void)unused;
    SCHEME = 1;
    press_make(&PRESS);
    X0 = PRESS_X0_ON;
    X1 = PRESS_X1_ON;
    run_decomposed(0, STEPS, 0, INFINITY, REF_JOB, &REF);
    for (int size = 2; size <= LOOPBACK_MAX; ++size) {
        run_decomposed(size, STEPS, 0, INFINITY, JOBS, &DEC);
        size_t owned = 0;
        for (int r = 0; r < size; ++r) {
            if (JOBS[r].status != SINTER_OK)
                fprintf(stderr, "subdomain %d: %s\n", r, JOBS[r].message);
            assert_int_equal(JOBS[r].status, SINTER_OK);
            owned += JOBS[r].owned;
            assert_int_equal(JOBS[r].stats.steps, REF_JOB[0].stats.steps);
            assert_int_equal(JOBS[r].stats.rejected, REF_JOB[0].stats.rejected);
            assert_int_equal(JOBS[r].stats.iterations, REF_JOB[0].stats.iterations);
        }
        assert_int_equal(owned, N);
        for (int i = 0; i < N; ++i)
            assert_int_equal(DEC.seen[i], 1);
        const double dx = press_rel_diff(DEC.x, REF.x, X_START, 3 * N);
        const double dv = press_rel_diff(DEC.v, REF.v, NULL, 3 * N);
        const double dt = press_rel_diff(DEC.temp, REF.temp, T_START, N);
        fprintf(stderr,
                "%d slabs with borders on columns: %llu migrations; displacements %.2g, "
                "velocities %.2g, temperature changes %.2g (relative)\n",
                size, (unsigned long long)JOBS[0].stats.bonds_broken, dx, dv, dt);
        assert_true(JOBS[0].stats.bonds_broken >= 1);
        assert_true(dx <= 1e-10);
        assert_true(dv <= 1e-10);
        assert_true(dt <= 1e-10);
    }
    X0 = PRESS_X0_BETWEEN;
    X1 = PRESS_X1_BETWEEN;
}

/* A NaN force on one subdomain's particle stops every subdomain at the same step. */
static void test_nan_stops_all(void **unused)
{
    (void)unused;
    SCHEME = 1;
    press_make(&PRESS);
    const int k = 2 * NX * NY + 3 * NX + 6; /* in the third slab of 4 */
    assert_int_equal(press_slab_of(PRESS.x[3 * k], X0, X1, 4), 2);
    const double after = 0.012; /* in the third step */
    run_decomposed(4, STEPS, PRESS.id[k], after, JOBS, &DEC);
    char id[32];
    snprintf(id, sizeof(id), "id %llu", (unsigned long long)PRESS.id[k]);
    for (int r = 0; r < 4; ++r) {
        assert_int_equal(JOBS[r].status, SINTER_ERR_NOT_CONVERGED);
        assert_int_equal(JOBS[r].failed_at, JOBS[0].failed_at);
        assert_string_equal(JOBS[r].message, JOBS[0].message);
        assert_true(JOBS[r].time == JOBS[0].time); /* the last accepted state, everywhere */
    }
    fprintf(stderr, "stopped at step %d: %s\n", JOBS[0].failed_at, JOBS[0].message);
    assert_true(JOBS[0].failed_at >= 3); /* (t = 0.012 s comes in the third step or later) */
    assert_non_null(strstr(JOBS[0].message, "subdomain 2:"));
    assert_non_null(strstr(JOBS[0].message, id));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decomposed_press),
        cmocka_unit_test(test_decomposed_press_scheme0),
        cmocka_unit_test(test_migration_at_accepted_state),
        cmocka_unit_test(test_nan_stops_all),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
