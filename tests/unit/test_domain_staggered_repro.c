/*
 * The staggered stepper's reproducible mode (stepper option "reproducible", issue 43) on
 * subdomains of the thread transport of domain_loopback.h (slabs along x).
 *
 * The press of test_domain_staggered.c (240 spheres in a lattice, the seed 000 power law,
 * drag, gravity, conduction, Joule heating and the averaged electric model between two current
 * walls, the top one moving down; adaptive steps with rejections and neighbour rebuilds) in
 * reproducible mode, at the averaged model's tolerance of the scene (1e-4):
 *  - without domain operations and on 1, 2, 3 and 4 slabs, on one and on two threads, both
 *    schemes: every particle's export record (every field, the contact histories keyed by
 *    ids, the predictor's history) is the same bytes after the run, and so are the global part
 *    of a portable checkpoint (time, counters, the step controller, the walls' reactions), the
 *    counts of steps, rejections and fixed-point iterations and the electric model's sweeps. In the
 *    default mode on 3 slabs the records differ (the averaged model's Gauss-Seidel sweeps and
 *    the sums follow the decomposition), so the comparison can fail.
 *  - A portable checkpoint (the global part and every particle's record) written on 4 slabs
 *    continues on 2 slabs bit for bit: equal to the uninterrupted run.
 *  - With slab borders on columns of the lattice (10, 33 and 42 migrations on 2, 3 and 4
 *    slabs, made at accepted states with the predictor's history in the records): the same
 *    records as without domain operations.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_loopback.h"
#include "domain_records.h"
#include "domain_press_models.h"
#include "test_support.h"

enum { NX = 8, NY = 6, NZ = 5, N = NX * NY * NZ, STEPS = 12, SPLIT = 5 };
static const double R = 0.05, A = 0.099; /* radius and lattice spacing [m]: 1 % overlap */
static const double LX = R + A * (NX - 1) + R, LY = R + A * (NY - 1) + R;
static const double TOP = R + A * (NZ - 1) + 0.99 * R; /* the top wall at t = 0 [m] */
/* slab borders between two columns of the lattice for 2, 3 and 4 slabs (test_domain_staggered),
 * or (test_migrations) on columns, which the particles then cross */
static double X0 = R - 2.5 * A, X1 = R + 9.5 * A;
static int MIGRATIONS; /* 1: the runs migrate (else none may) */
/* 1: the "network" electric model instead of the averaged one, the top wall grounded
 * (test_network_press) */
static int NETWORK;

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* The press of test_domain_staggered.c: a jiggled lattice, random velocities and
 * temperatures, ids a permutation of the lattice order. */
static struct {
    double x[3 * N], v[3 * N], temp[N];
    uint64_t id[N];
} PRESS;

static void make_press(void)
{
    uint64_t seed = 28;
    for (int k = 0; k < N; ++k) {
        const int i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
        PRESS.x[3 * k] = R + A * i + 0.002 * R * (lcg(&seed) - 0.5);
        PRESS.x[3 * k + 1] = R + A * j + 0.002 * R * (lcg(&seed) - 0.5);
        PRESS.x[3 * k + 2] = 0.99 * R + A * l + 0.002 * R * (lcg(&seed) - 0.5);
        for (int d = 0; d < 3; ++d)
            PRESS.v[3 * k + d] = 0.01 * (lcg(&seed) - 0.5);
        PRESS.temp[k] = 300.0 + 50.0 * lcg(&seed);
        PRESS.id[k] = 1 + (uint64_t)((k * 37) % N);
    }
}

static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* Every particle's export record by id - 1, and what the run counted. */
typedef struct records {
    unsigned char *rec[N];
    size_t len[N];
    unsigned char *global; /* the global part (subdomain 0's) */
    size_t global_len;
    sinter_stepper_stats stats; /* over every subdomain (subdomain 0's) */
    uint64_t sweeps;            /* the electric model's sweeps (subdomain 0's) */
} records;

static void records_free(records *r)
{
    domain_records_free(r->rec, N);
    free(r->global);
    memset(r, 0, sizeof(*r));
}

typedef struct job {
    int rank, size;
    loopback *lb; /* NULL: without domain operations */
    int reproducible, threads, scheme, steps;
    const records *restart; /* NULL: from the lattice; else the checkpoint to continue */
    records *out;
    int failed; /* the line of the first failure */
    char message[256];
} job;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->failed = __LINE__;                                                                  \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

/* Each owned particle's record, by itself (remove = 0), into out by id. */
static sinter_status export_owned(sinter_stepper *st, sinter_particles *ps, records *out)
{
    return domain_records_export_owned(st, ps, N, out->rec, out->len);
}

/* The documented restart: the global part, then the records of the particles in this slab. */
static sinter_status restart(const job *j, sinter_stepper *st, sinter_particles *ps)
{
    sinter_status s = sinter_stepper_load_global(st, j->restart->global, j->restart->global_len);
    for (int k = 0; k < N && s == SINTER_OK; ++k)
        s = domain_records_import_in_slab(st, ps, j->restart->rec[k], j->restart->len[k],
                                          j->lb != NULL ? j->size : 0, j->rank, X0, X1);
    return s;
}

static void *run(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    domain_press_models models = {NULL, NULL, NULL, NULL, NULL, NULL};
    sinter_electric_model *network = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, j->threads));
    TRY(domain_press_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_press_walls(ctx, mat, LX, LY, TOP, &walls));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_STAGGERED, ps, walls));
    TRY(domain_press_add_models(ctx, st, 1e-4, &models)); /* the scene's electric tolerance */
    if (NETWORK) { /* the floor's 1 A to the grounded top wall through the network */
        TRY(sinter_electric_model_create(&network, ctx, "network"));
        TRY(sinter_electric_model_set(network, "tolerance", 1e-10));
        TRY(sinter_stepper_set_electric(st, network));
        TRY(sinter_walls_set_electric(walls, 0, SINTER_WALL_CURRENT, 1.0));
        TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    }
    TRY(sinter_stepper_set_option(st, "reproducible", j->reproducible));
    TRY(sinter_stepper_set_option(st, "scheme", j->scheme));
    TRY(sinter_stepper_set_dt(st, 0.005));
    TRY(sinter_stepper_set_option(st, "dt_max", 0.005));
    TRY(sinter_stepper_set_option(st, "dt_min", 1e-7));
    TRY(sinter_stepper_set_option(st, "position_tolerance", 1e-6));
    TRY(sinter_stepper_set_skin(st, 0.01)); /* rebuilds within the run */
    if (j->lb != NULL) /* before the particles: the restart's imports keep their forces */
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    if (j->restart != NULL) {
        TRY(restart(j, st, ps));
    } else {
        for (int k = 0; k < N; ++k) {
            if (j->lb != NULL && slab_of(PRESS.x[3 * k], j->size) != j->rank)
                continue;
            size_t first = 0;
            TRY(sinter_particles_add_with_ids(ps, 1, &PRESS.id[k], PRESS.x + 3 * k, &R, 0,
                                              PRESS.temp[k], &first));
            double *v = NULL;
            TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
            memcpy(v + 3 * first, PRESS.v + 3 * k, 24);
            TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
        }
    }
    for (int k = 0; k < j->steps; ++k)
        TRY(sinter_stepper_step(st, 1));
    TRY(export_owned(st, ps, j->out));
    sinter_stepper_stats stats = {.struct_size = sizeof(stats)};
    TRY(sinter_stepper_get_stats_global(st, &stats)); /* (collective) */
    if (j->rank == 0) { /* the global part and the counts: the same on every subdomain */
        TRY(domain_records_save_global(st, &j->out->global, &j->out->global_len));
        j->out->stats = stats;
        TRY(sinter_stepper_electric_iterations(st, &j->out->sweeps));
    }
done:
    if (j->failed)
        snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    domain_press_models_destroy(&models);
    sinter_electric_model_destroy(network);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The press on `size` slabs (0: without domain operations) for `steps` steps, from the
 * lattice or from checkpoint `from`; every particle's record into out. */
static void run_on(int size, int reproducible, int threads, int scheme, int steps,
                   const records *from, records *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, X0, X1);
    pthread_t t[LOOPBACK_MAX];
    job jobs[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.rank = r,
                        .size = n,
                        .lb = lb,
                        .reproducible = reproducible,
                        .threads = threads,
                        .scheme = scheme,
                        .steps = steps,
                        .restart = from,
                        .out = out};
        assert_int_equal(pthread_create(&t[r], NULL, run, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(t[r], NULL), 0);
    uint64_t migrated = 0;
    for (int r = 0; r < n && lb != NULL; ++r)
        migrated += loopback_migrated(lb, r);
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].failed)
            print_error("%d slabs, subdomain %d: failed at line %d: %s\n", size, r, jobs[r].failed,
                        jobs[r].message);
        assert_int_equal(jobs[r].failed, 0);
    }
    if (!MIGRATIONS)
        assert_int_equal(migrated, 0); /* (the slabs' borders lie between columns) */
    else if (size >= 2)
        print_message("%d slabs: %llu migrations\n", size, (unsigned long long)migrated);
    for (int k = 0; k < N; ++k) /* every particle owned once */
        assert_non_null(out->rec[k]);
}

/* The number of particles whose records differ (length or bytes). */
static int differing(const records *a, const records *b)
{
    return domain_records_differing(a->rec, a->len, b->rec, b->len, N);
}

static records REF, RUN;

static void compare_decompositions(int scheme)
{
    make_press();
    run_on(0, 1, 1, scheme, STEPS, NULL, &REF); /* without domain operations, one thread */
    const sinter_stepper_stats *ref = &REF.stats;
    print_message("scheme %d, reproducible, one domain: %llu steps, %llu rejected, %llu "
                  "iterations, %llu builds, %llu Jacobi sweeps of the averaged model\n",
                  scheme, (unsigned long long)ref->steps, (unsigned long long)ref->rejected,
                  (unsigned long long)ref->iterations, (unsigned long long)ref->neighbor_builds,
                  (unsigned long long)REF.sweeps);
    /* the run does what the test needs: rejections, rebuilds, iterations */
    assert_int_equal(ref->steps, STEPS);
    assert_true(ref->rejected >= 1);
    assert_true(ref->neighbor_builds >= 1); /* (one made by the first step) */
    assert_true(ref->iterations > 2 * ref->steps);
    for (int threads = 1; threads <= 2; ++threads)
        for (int size = threads == 1 ? 1 : 0; size <= LOOPBACK_MAX; ++size) {
            run_on(size, 1, threads, scheme, STEPS, NULL, &RUN);
            const int d = differing(&RUN, &REF);
            print_message("scheme %d, reproducible, %d slabs, %d threads: %d of %d records "
                          "differ\n",
                          scheme, size, threads, d, N);
            assert_int_equal(d, 0);
            assert_int_equal(RUN.stats.steps, ref->steps);
            assert_int_equal(RUN.stats.rejected, ref->rejected);
            assert_int_equal(RUN.stats.iterations, ref->iterations);
            assert_int_equal(RUN.sweeps, REF.sweeps);
            /* the global part: time, step, counters, the step controller, the walls' reactions */
            assert_int_equal(RUN.global_len, REF.global_len);
            assert_memory_equal(RUN.global, REF.global, REF.global_len);
            records_free(&RUN);
        }
    records_free(&REF);
}

static void test_reproducible_scheme1(void **unused)
{
    (void)unused;
    compare_decompositions(1);
}

static void test_reproducible_scheme0(void **unused)
{
    (void)unused;
    compare_decompositions(0);
}

/* The default mode on 3 slabs gives other bits (the comparison above can fail); its
 * averaged model sweeps Gauss-Seidel, for the count of sweeps against Jacobi's. */
static void test_default_mode_differs(void **unused)
{
    (void)unused;
    make_press();
    records one, three;
    run_on(0, 0, 1, 1, STEPS, NULL, &one);
    run_on(3, 0, 1, 1, STEPS, NULL, &three);
    const int d = differing(&one, &three);
    print_message("default mode, 3 slabs: %d of %d records differ from one domain; %llu "
                  "Gauss-Seidel sweeps on one domain\n",
                  d, N, (unsigned long long)one.sweeps);
    assert_true(d > 0);
    records_free(&one);
    records_free(&three);
}

/* A checkpoint written on 4 slabs at step SPLIT, continued on 2: the uninterrupted run's bits. */
static void test_checkpoint_4_to_2(void **unused)
{
    (void)unused;
    make_press();
    run_on(4, 1, 1, 1, STEPS, NULL, &REF); /* uninterrupted */
    records ckpt;
    run_on(4, 1, 1, 1, SPLIT, NULL, &ckpt);
    run_on(2, 1, 1, 1, STEPS - SPLIT, &ckpt, &RUN);
    const int d = differing(&RUN, &REF);
    print_message("checkpoint of 4 slabs at step %d, continued on 2: %d of %d records differ; "
                  "%llu and %llu iterations\n",
                  SPLIT, d, N, (unsigned long long)RUN.stats.iterations,
                  (unsigned long long)REF.stats.iterations);
    assert_int_equal(d, 0);
    assert_int_equal(RUN.stats.steps, REF.stats.steps);
    assert_int_equal(RUN.stats.rejected, REF.stats.rejected);
    assert_int_equal(RUN.stats.iterations, REF.stats.iterations);
    records_free(&RUN);
    records_free(&ckpt);
    records_free(&REF);
}

/* Slabs whose borders lie on columns of the lattice: the particles of those columns cross
 * them and migrate at accepted states, their records carrying the predictor's history. */
static void test_migrations(void **unused)
{
    (void)unused;
    make_press();
    X0 = R - 2.0 * A;
    X1 = R + 10.0 * A;
    MIGRATIONS = 1;
    run_on(0, 1, 1, 1, STEPS, NULL, &REF);
    for (int size = 2; size <= LOOPBACK_MAX; ++size) {
        run_on(size, 1, 1, 1, STEPS, NULL, &RUN);
        const int d = differing(&RUN, &REF);
        print_message("borders on columns, %d slabs: %d of %d records differ\n", size, d, N);
        assert_int_equal(d, 0);
        assert_int_equal(RUN.stats.iterations, REF.stats.iterations);
        records_free(&RUN);
    }
    records_free(&REF);
    X0 = R - 2.5 * A;
    X1 = R + 9.5 * A;
    MIGRATIONS = 0;
}

/*
 * The press with the "network" electric model (the floor's 1 A to the grounded top wall;
 * PCG tolerance 1e-10), scheme 1: the network's PCG in the mode (exact dot products and norms,
 * domain/solve.h) gives every record, the global part and the counts the same bytes without
 * domain operations and on 1-4 slabs, on one and two threads; in the default mode on 3 slabs
 * the records differ.
 */
static void test_network_press(void **unused)
{
    (void)unused;
    make_press();
    NETWORK = 1;
    records one, three;
    run_on(0, 0, 1, 1, STEPS, NULL, &one);
    run_on(3, 0, 1, 1, STEPS, NULL, &three);
    const int d_default = differing(&one, &three);
    records_free(&one);
    records_free(&three);
    run_on(0, 1, 1, 1, STEPS, NULL, &REF);
    print_message("network press, reproducible, one domain: %llu steps, %llu rejected, %llu "
                  "iterations, %llu PCG iterations; default mode on 3 slabs: %d of %d records "
                  "differ\n",
                  (unsigned long long)REF.stats.steps, (unsigned long long)REF.stats.rejected,
                  (unsigned long long)REF.stats.iterations, (unsigned long long)REF.sweeps,
                  d_default, N);
    assert_true(d_default > 0);
    assert_true(REF.sweeps > 0);
    for (int threads = 1; threads <= 2; ++threads)
        for (int size = threads == 1 ? 1 : 0; size <= LOOPBACK_MAX; ++size) {
            run_on(size, 1, threads, 1, STEPS, NULL, &RUN);
            const int d = differing(&RUN, &REF);
            print_message("network press, reproducible, %d slabs, %d threads: %d of %d records "
                          "differ\n",
                          size, threads, d, N);
            assert_int_equal(d, 0);
            assert_int_equal(RUN.stats.steps, REF.stats.steps);
            assert_int_equal(RUN.stats.rejected, REF.stats.rejected);
            assert_int_equal(RUN.stats.iterations, REF.stats.iterations);
            assert_int_equal(RUN.sweeps, REF.sweeps);
            assert_int_equal(RUN.global_len, REF.global_len);
            assert_memory_equal(RUN.global, REF.global, REF.global_len);
            records_free(&RUN);
        }
    records_free(&REF);
    NETWORK = 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reproducible_scheme1), cmocka_unit_test(test_reproducible_scheme0),
        cmocka_unit_test(test_default_mode_differs), cmocka_unit_test(test_checkpoint_4_to_2),
        cmocka_unit_test(test_migrations),           cmocka_unit_test(test_network_press),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
