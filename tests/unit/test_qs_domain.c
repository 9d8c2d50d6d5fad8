/*
 * The quasi-static stepper on subdomains (issue 43, include/sinter_domain.h, src/stepper/
 * qs_domain.c), through the thread transport of domain_loopback.h: slabs along x.
 *
 * A lattice of 8 x 3 x 3 copper spheres (R = 25 um, radii spread by up to 0.2 % so that the
 * necks differ, on a 2R lattice: every neighbour pair overlaps and becomes a link, 159 links;
 * seed 001 table 2 copper, 1293 K) sinters for 40 global steps (a first step of 1 ms, then
 * adaptive: to 6.5 ms with strategy 2, whose young necks sub-step, to 30 s with strategy 3)
 * with the particles on x, y, z = 0 held on their planes. The ids are a permutation of the places,
 * so a link's smaller id lies on either side of a border. Each link is owned by the subdomain of
 * its smaller id, its loads on a ghost end go back through the reverse halo, the step decision and
 * the statistics are reduced, and K u = f is solved by the split PCG (bonded/solve_split.h).
 *  - On one subdomain every position, rotation, neck, approach and statistic equals the run
 *    without domain operations bit for bit (reductions of one term are exact, and one
 *    subdomain keeps the serial solve).
 *  - On 2, 3 and 4 subdomains (every border between two columns; each subdomain owns particles
 *    and holds ghosts): the same time reached (the step decisions are reduced), and positions,
 * displacements, rotations (as R theta against the largest displacement), neck radii, approaches
 * and statistics within 1e-10 relative, or within ten times the serial run's own spread where that
 * is larger. The spread: the serial run with its solve's target at 1e-13 instead of 1e-12, a change
 * of u at round-off level, as the split solve's other sum order and preconditioner make. All runs
 * solve K u = f to 1e-12 |f| (at the default 1e-7 the two preconditioners' approximations
 * leave the approaches differing by about 2e-8, too much for 1e-10). With strategy 2 (per-pair RK4,
 * the copper_lattice scene's) every difference is below 5e-12; with the default strategy 3 the
 * young necks' CVODE turns the round-off of u into about 1.5e-9 on the necks, in the serial run as
 * in the decomposed ones (the test prints both, and the PCG iterations: about 2.2 times the serial
 * solve's).
 *  - A host neck law that fails on subdomain 2 of 3 stops all three at the same step with
 *    SINTER_ERR_CALLBACK and one message naming subdomain 2 (no hang: ctest's timeout).
 *  - Migration: the runs stop after 20 steps, the slabs move by -2R, and at the next call's
 *    redistribution the column at each border (9, 18, 27 spheres on 2, 3, 4 subdomains)
 *    migrates with the links of its smaller ids; the results equal the serial run's as above.
 *  - The validity guard (qs_validity 2) with necks of 0.9 R from a host law: 3 subdomains stop
 *    with the serial run's SINTER_ERR_DOMAIN message (the same particle and its 6 necks).
 *  - qs_strategy 1 is refused.
 *  - A floating layer (the top layer lifted off the lattice and off the x and y planes, a link
 *    component no plane holds, across every border): its rigid motion is removed on the
 *    subdomains as on one domain, so the comparison above holds (without the removal the
 *    displacements differ by about 2.5e-2).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_submodel.h>

#include "domain_copper.h"
#include "domain_loopback.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

enum { NX = COPPER_NX, NY = COPPER_NY, NZ = COPPER_NZ, N = COPPER_N, MAX_LINKS = COPPER_MAX_LINKS };
static const double R = COPPER_R;
enum { STEPS = 40 }; /* global steps of a run (the first, then the others in one or two calls) */
static double SOLVE_RTOL = 1e-12;
static int SHIFT = 0; /* the runs stop after STEPS / 2 steps; the slabs move then */
static int FLOAT = 0; /* the top layer lifted off and moved away from the planes (below) */

typedef copper_outcome outcome;

typedef struct job {
    int rank, size;
    loopback *lb; /* NULL: without domain operations */
    int strategy;
    int fail_call; /* > 0: a host neck law that fails at this call on subdomain size - 1 */
    int shift;     /* after STEPS / 2 the slabs move by -2R: a column migrates at each border */
    uint64_t migrated;
    double end_time;
    outcome *out;
    pthread_mutex_t *lock;
    int setup_failed;
    sinter_status status;
    char message[512];
} job;

/* A host neck law (sinter_submodel.h): the neck grows and the pair approaches at fixed rates;
 * on the subdomain `fail_rank` its call number `fail_call` fails. */
typedef struct failing_law {
    int rank, fail_rank, fail_call, calls;
} failing_law;

static int failing_advance(sinter_neck_law_batch *b, void *user)
{
    failing_law *law = user;
    if (++law->calls == law->fail_call && law->rank == law->fail_rank)
        return 1;
    for (size_t k = 0; k < b->count && law->fail_call < 0; ++k) { /* necks of 0.9 R at once */
        double *y = b->state + SINTER_NECK_LAW_STATE * k;
        y[0] = 0.9 * fmin(y[1], y[4]);
    }
    if (law->fail_call < 0)
        return 0;
    for (size_t k = 0; k < b->count; ++k) {
        double *y = b->state + SINTER_NECK_LAW_STATE * k;
        y[0] *= 1.0 + 0.01 * b->dt;
        y[3] -= 1e-6 * y[3] * b->dt;
        y[6] -= 1e-6 * y[6] * b->dt;
    }
    return 0;
}

static void place(size_t p, double x[3], double *r)
{
    copper_place(p, FLOAT, x, r);
}

static const double X0 = COPPER_X0, X1 = COPPER_X1;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->setup_failed = __LINE__;                                                            \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void collect(job *j, sinter_particles *ps, sinter_stepper *st)
{
    sinter_sintering_stats ss;
    /* collective: every subdomain calls it */
    if (copper_sintering_stats(st, &ss) != SINTER_OK)
        j->setup_failed = __LINE__;
    pthread_mutex_lock(j->lock);
    const int failed = copper_collect(j->out, (size_t)j->rank, ps, st, &ss);
    pthread_mutex_unlock(j->lock);
    if (failed)
        j->setup_failed = failed;
}

static void *run(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    failing_law law = {j->rank, j->size - 1, j->fail_call, 0};
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(copper_setup(ctx, j->strategy, SOLVE_RTOL, &mat, &ps, &st));
    if (j->fail_call > 0) {
        const sinter_neck_law_callbacks cb = {sizeof(cb), failing_advance, NULL};
        TRY(sinter_stepper_set_neck_law(st, &cb, &law));
    }
    if (j->fail_call < 0) { /* the necks that law makes: the validity guard as an error */
        const sinter_neck_law_callbacks cb = {sizeof(cb), failing_advance, NULL};
        TRY(sinter_stepper_set_neck_law(st, &cb, &law));
        TRY(sinter_stepper_set_option(st, "qs_validity", 2.0));
    }
    TRY(copper_add(ps, j->rank, j->lb != NULL ? j->size : 0, 0.0, FLOAT));
    if (j->lb != NULL)
        j->status = loopback_attach(j->lb, j->rank, st, ps);
    if (j->status == SINTER_OK)
        j->status = sinter_stepper_step(st, 1);
    if (j->status == SINTER_OK && j->shift) {
        j->status = sinter_stepper_step(st, STEPS / 2 - 1);
        if (j->lb != NULL) { /* every subdomain between two calls */
            loopback_barrier(j->lb);
            if (j->rank == 0)
                loopback_set_slabs(j->lb, X0 - 2.0 * R, X1 - 2.0 * R);
            loopback_barrier(j->lb);
        }
    }
    if (j->status == SINTER_OK)
        j->status = sinter_stepper_step(st, j->shift ? STEPS / 2 : STEPS - 1);
    if (j->lb != NULL)
        j->migrated = loopback_migrated(j->lb, j->rank);
    TRY(sinter_stepper_time(st, &j->end_time));
    if (j->status != SINTER_OK) {
        snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
        goto done;
    }
    collect(j, ps, st);
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The lattice on `size` subdomains (0: one run without domain operations) into out. */
static void run_on_failing(int size, int strategy, int fail_call, outcome *out,
                           job jobs[LOOPBACK_MAX]);
static void run_on(int size, int strategy, outcome *out, job jobs[LOOPBACK_MAX])
{
    run_on_failing(size, strategy, 0, out, jobs);
}

static void run_on_failing(int size, int strategy, int fail_call, outcome *out,
                           job jobs[LOOPBACK_MAX])
{
    memset(out, 0, sizeof(*out));
    pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, X0, X1);
    const int threads = size > 0 ? size : 1;
    pthread_t t[LOOPBACK_MAX];
    for (int r = 0; r < threads; ++r) {
        jobs[r] = (job){.rank = r,
                        .size = threads,
                        .lb = lb,
                        .strategy = strategy,
                        .fail_call = fail_call,
                        .shift = SHIFT,
                        .out = out,
                        .lock = &lock,
                        .status = SINTER_OK};
        assert_int_equal(pthread_create(&t[r], NULL, run, &jobs[r]), 0);
    }
    for (int r = 0; r < threads; ++r)
        assert_int_equal(pthread_join(t[r], NULL), 0);
    loopback_destroy(lb);
    pthread_mutex_destroy(&lock);
}

/* The links of `o` in the order of the reference's (by their ids). */
static void links_like(const outcome *ref, const outcome *o, double *neck, double *approach)
{
    assert_int_equal(o->links, ref->links);
    for (size_t k = 0; k < ref->links; ++k) {
        size_t found = SIZE_MAX;
        for (size_t q = 0; q < o->links && found == SIZE_MAX; ++q)
            if (o->link_a[q] == ref->link_a[k] && o->link_b[q] == ref->link_b[k])
                found = q;
        assert_true(found != SIZE_MAX);
        neck[k] = o->neck[found];
        approach[k] = o->approach[found];
    }
}

static outcome REF, DEC;
static job JOBS[LOOPBACK_MAX];

static void check_jobs(int size)
{
    for (int r = 0; r < (size > 0 ? size : 1); ++r) {
        if (JOBS[r].setup_failed || JOBS[r].status != SINTER_OK)
            print_message("subdomain %d of %d: %s\n", r, size, JOBS[r].message);
        assert_int_equal(JOBS[r].setup_failed, 0);
        assert_int_equal(JOBS[r].status, SINTER_OK);
    }
}

/* The largest relative difference of the quantities compared below between outcomes a and b
 * (links in a's order), into e[6]: positions, displacements, rotations (as the motion R theta
 * they give a sphere's surface, relative to the largest displacement: the lattice turns little),
 * neck radii, approaches, the statistics. */
static void differences(const outcome *a, const outcome *b, double e[6])
{
    static double neck[MAX_LINKS], approach[MAX_LINKS];
    links_like(a, b, neck, approach);
    double ua[3 * N], ub[3 * N], ra[3 * N], rb[3 * N];
    for (size_t k = 0; k < N; ++k) { /* the displacements, by id */
        double x[3], r;
        place(k, x, &r);
        const size_t i = (size_t)copper_id_of(k) - 1;
        for (size_t d = 0; d < 3; ++d) {
            ua[3 * i + d] = a->x[3 * i + d] - x[d];
            ub[3 * i + d] = b->x[3 * i + d] - x[d];
        }
    }
    double umax = 0.0, rot = 0.0;
    for (size_t i = 0; i < 3 * N; ++i) {
        umax = fmax(umax, fabs(ua[i]));
        rot = fmax(rot, R * fabs(a->rot[i] - b->rot[i]));
        ra[i] = a->rot[i];
        rb[i] = b->rot[i];
    }
    (void)ra;
    (void)rb;
    e[0] = copper_rel_diff(a->x, b->x, 3 * N);
    e[1] = copper_rel_diff(ua, ub, 3 * N);
    e[2] = rot / umax;
    e[3] = copper_rel_diff(a->neck, neck, a->links);
    e[4] = copper_rel_diff(a->approach, approach, a->links);
    e[5] = copper_rel_diff(a->stats, b->stats, 9);
}

static void compare_runs(int strategy)
{
    /* the spread of the serial run itself under a perturbation of the solve at the level of
     * round-off: its target 1e-13 instead of 1e-12 */
    static outcome PERTURBED;
    SOLVE_RTOL = 1e-13;
    run_on(0, strategy, &PERTURBED, JOBS);
    check_jobs(0);
    SOLVE_RTOL = 1e-12;
    run_on(0, strategy, &REF, JOBS);
    check_jobs(0);
    double spread[6];
    differences(&REF, &PERTURBED, spread);
    print_message("strategy %d, serial spread (solve target 1e-12 against 1e-13): x %.2e, u %.2e, "
                  "rot %.2e, neck %.2e, approach %.2e, stats %.2e\n",
                  strategy, spread[0], spread[1], spread[2], spread[3], spread[4], spread[5]);
    assert_true(REF.links >= 2 * N - NY * NZ - NX * NZ - NX * NY); /* every neighbour pair */
    assert_int_equal(REF.steps, STEPS);
    const double end_time = JOBS[0].end_time;
    print_message("strategy %d, %d steps to t = %g s\n", strategy, STEPS, end_time);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run_on(size, strategy, &DEC, JOBS);
        check_jobs(size);
        for (size_t k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1);
        assert_int_equal(DEC.steps, REF.steps);
        for (int r = 0; r < size; ++r) /* the same global steps: the same time reached */
            assert_true(JOBS[r].end_time == end_time);
        static double neck[MAX_LINKS], approach[MAX_LINKS];
        links_like(&REF, &DEC, neck, approach);
        if (size == 1) { /* bit for bit */
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.rot, REF.rot, sizeof(REF.rot));
            assert_memory_equal(neck, REF.neck, REF.links * sizeof(double));
            assert_memory_equal(approach, REF.approach, REF.links * sizeof(double));
            assert_memory_equal(DEC.stats, REF.stats, sizeof(REF.stats));
            continue;
        }
        double e[6];
        differences(&REF, &DEC, e);
        uint64_t migrated = 0;
        for (int r = 0; r < size; ++r) { /* every subdomain owns a part, sees its neighbours */
            assert_true(DEC.owned[r] >= NY * NZ && DEC.ghosts[r] >= NY * NZ);
            migrated += JOBS[r].migrated;
        }
        assert_int_equal(migrated, SHIFT ? (uint64_t)(size - 1) * NY * NZ : 0);
        print_message("strategy %d, %d subdomains: relative differences x %.2e, u %.2e, rot "
                      "%.2e, neck %.2e, approach %.2e, stats %.2e (%llu steps, %zu links, PCG "
                      "iterations %.0f, serial %.0f)\n",
                      strategy, size, e[0], e[1], e[2], e[3], e[4], e[5],
                      (unsigned long long)DEC.steps, DEC.links, DEC.stats[10], REF.stats[10]);
        /* 1e-10, or ten times the serial run's own spread where its adaptive neck integration
         * (CVODE, strategy 3) turns round-off into more */
        for (int k = 0; k < 6; ++k)
            assert_true(e[k] <= fmax(1e-10, 10.0 * spread[k]));
        assert_true(REF.stats[4] > 0.0); /* it shrank */
    }
}

static void test_strategy2_on_subdomains(void **state)
{
    (void)state;
    compare_runs(2);
}

static void test_strategy3_on_subdomains(void **state)
{
    (void)state;
    compare_runs(3);
}

/* Migration: the runs stop after STEPS / 2 steps, the slabs move by -2R, and at the next call's
 * redistribution the column at each border migrates with its links (those of its smaller ids)
 * to the next subdomain; the plane conditions are found again there. */
static void test_migration(void **state)
{
    (void)state;
    SHIFT = 1;
    compare_runs(2);
    SHIFT = 0;
}

/* A host neck law that fails on subdomain 2 of 3 at its 7th call stops all three in the same
 * step, with the same status and message, which names subdomain 2; the time stays the one
 * before that step everywhere. */
static void test_failure_stops_all(void **state)
{
    (void)state;
    run_on_failing(3, 3, 7, &DEC, JOBS);
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(JOBS[r].setup_failed, 0);
        assert_int_equal(JOBS[r].status, SINTER_ERR_CALLBACK);
        assert_string_equal(JOBS[r].message, JOBS[0].message);
        assert_true(JOBS[r].end_time == JOBS[0].end_time);
    }
    assert_non_null(strstr(JOBS[0].message, "subdomain 2"));
    assert_true(JOBS[0].end_time > 0.0); /* after 6 steps */
}

/* The validity guard over the subdomains: necks of 0.9 R (a host law) cover more than 0.8 of
 * the particles' surfaces at the first step; on 3 subdomains every one stops with
 * SINTER_ERR_DOMAIN and the serial run's message (the same particle, its 6 necks, wherever
 * they are owned). */
static void test_validity_guard(void **state)
{
    (void)state;
    char serial[512];
    run_on_failing(0, 3, -1, &REF, JOBS);
    assert_int_equal(JOBS[0].setup_failed, 0);
    assert_int_equal(JOBS[0].status, SINTER_ERR_DOMAIN);
    assert_non_null(strstr(JOBS[0].message, "the necks impinge: the 6 necks"));
    snprintf(serial, sizeof(serial), "%s", JOBS[0].message);
    run_on_failing(3, 3, -1, &DEC, JOBS);
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(JOBS[r].setup_failed, 0);
        assert_int_equal(JOBS[r].status, SINTER_ERR_DOMAIN);
        assert_string_equal(JOBS[r].message, serial);
    }
}

static void test_strategy1_refused(void **state)
{
    (void)state;
    run_on(1, 1, &DEC, JOBS);
    assert_int_equal(JOBS[0].setup_failed, 0);
    assert_int_equal(JOBS[0].status, SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(JOBS[0].message, "qs_strategy 1"));
}

/* A floating component across every border: the top layer (8 x 3 spheres, 37 links) lifted by
 * 0.5 R off the lattice and moved by 0.5 R off the x and y planes, so that no plane holds it and
 * no link joins it to the held lattice. K leaves its rigid motion free; one domain removes it
 * (qs_floating.c), and so must the subdomains, which find the layer's component across them
 * (qs_floating_domain.c): the same comparison as above. */
static void test_floating_on_subdomains(void **state)
{
    (void)state;
    FLOAT = 1;
    compare_runs(2);
    FLOAT = 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_strategy2_on_subdomains),
        cmocka_unit_test(test_strategy3_on_subdomains),
        cmocka_unit_test(test_migration),
        cmocka_unit_test(test_failure_stops_all),
        cmocka_unit_test(test_validity_guard),
        cmocka_unit_test(test_strategy1_refused),
        cmocka_unit_test(test_floating_on_subdomains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
