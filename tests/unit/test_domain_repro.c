/*
 * The reproducible mode (stepper option "reproducible", issue 43) and portable checkpoints
 * across decompositions, through the thread transport of domain_loopback.h.
 *
 * The bed of test_domain.c (288 spheres, Hertz-Mindlin with friction, damping and rolling
 * resistance, gravity, conduction, five walls, ids in a permuted order) in reproducible mode:
 *  - on 1, 2, 3 and 4 slabs, on one and on two threads, and without domain operations, the
 *    final state is the same bits: each particle's export record (every field, and the
 *    contact history of every contact it is an end of, keyed by ids) compared with memcmp.
 *    In the default mode the same comparison fails on 2 or more slabs (the sums come in
 *    another order), so the test can fail.
 *  - A checkpoint written on 4 slabs (the global part and every particle's record) restarts
 *    on 2 slabs and continues bit for bit: equal to the uninterrupted run.
 */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_bed.h"
#include "domain_loopback.h"
#include "domain_records.h"
#include "test_support.h"

enum { N_MAX = 12 * 12 * 12, NW = 5, STEPS = 150, SPLIT = 80 };
static const double R = 1e-3, A = 1.97e-3; /* radius and lattice spacing [m]: 1.5 % overlap */
static const double X0 = R - 2 * A, X1 = R + 10 * A; /* slab borders on lattice columns */
static const double DT = 2e-6;                       /* [s] */

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* The bed of test_domain.c (8 x 6 x 6; larger ones for the threads): a jiggled lattice,
 * random velocities, spins and temperatures, ids a multiplicative permutation of the lattice
 * order (or, `ids_ascending`, the lattice order); `reversed`: added to the set last first
 * (another order in memory). */
static struct {
    int n, nx, ny, reversed;
    double lx, ly; /* the box [m] */
    double x[3 * N_MAX], v[3 * N_MAX], w[3 * N_MAX], temp[N_MAX];
    uint64_t id[N_MAX];
} BED;

static void make_bed(int nx, int ny, int nz, int reversed, int ids_ascending)
{
    uint64_t seed = 43;
    BED.n = nx * ny * nz;
    BED.nx = nx;
    BED.ny = ny;
    BED.reversed = reversed;
    BED.lx = R + A * (nx - 1) + 0.99 * R;
    BED.ly = R + A * (ny - 1) + 0.99 * R;
    for (int k = 0; k < BED.n; ++k) {
        const int i = k % nx, j = (k / nx) % ny, l = k / (nx * ny);
        BED.x[3 * k] = R + A * i + 0.01 * R * (lcg(&seed) - 0.5);
        BED.x[3 * k + 1] = R + A * j + 0.01 * R * (lcg(&seed) - 0.5);
        BED.x[3 * k + 2] = 0.99 * R + A * l + 0.01 * R * (lcg(&seed) - 0.5);
        for (int d = 0; d < 3; ++d) {
            BED.v[3 * k + d] = 0.04 * (lcg(&seed) - 0.5);
            BED.w[3 * k + d] = 20.0 * (lcg(&seed) - 0.5);
        }
        BED.temp[k] = 300.0 + 100.0 * lcg(&seed);
        /* (37 is prime to 288 and 1728) */
        BED.id[k] = 1 + (uint64_t)(ids_ascending ? k : (k * 37) % BED.n);
    }
}

static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* Every particle's export record by id - 1 (a run's result or a checkpoint's records). */
typedef struct records {
    unsigned char *rec[N_MAX];
    size_t len[N_MAX];
    unsigned char *global; /* a checkpoint's global part (subdomain 0's) */
    double wall[3 * NW];   /* the walls' total reaction forces [N] (subdomain 0's) */
    size_t global_len;
} records;

static void records_free(records *r)
{
    domain_records_free(r->rec, N_MAX);
    free(r->global);
    memset(r, 0, sizeof(*r));
}

typedef struct job {
    int rank, size;
    loopback *lb; /* NULL: without domain operations */
    int reproducible, threads, steps;
    const records *restart; /* NULL: from the bed; else the checkpoint to continue from */
    records *out;           /* every owned particle's record at the end */
    int failed;             /* the line of the first failure */
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
    return domain_records_export_owned(st, ps, BED.n, out->rec, out->len);
}

static void *run(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL;
    sinter_heat_model *cond = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, j->threads));
    TRY(domain_bed_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_bed_walls(ctx, mat, BED.lx, BED.ly, &walls));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "thread_choice", 0));
    TRY(sinter_stepper_set_option(st, "reproducible", j->reproducible));
    TRY(domain_bed_models(ctx, st, &gravity, &contact, &cond));
    TRY(sinter_stepper_set_dt(st, DT));
    TRY(sinter_stepper_set_skin(st, 1e-5));
    if (j->lb != NULL) /* before the particles: the restart's imports keep their forces */
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    if (j->restart != NULL) {
        /* the documented restart: the global part, then the records of the particles whose
         * centres lie in this slab (any split of the records would do) */
        TRY(sinter_stepper_load_global(st, j->restart->global, j->restart->global_len));
        for (int k = 0; k < BED.n; ++k)
            TRY(domain_records_import_in_slab(st, ps, j->restart->rec[k], j->restart->len[k],
                                              j->lb != NULL ? j->size : 0, j->rank, X0, X1));
    } else {
        for (int m = 0; m < BED.n; ++m) {
            const int k = BED.reversed ? BED.n - 1 - m : m;
            if (j->lb != NULL && slab_of(BED.x[3 * k], j->size) != j->rank)
                continue;
            TRY(domain_bed_add(ps, BED.id[k], BED.x + 3 * k, R, BED.temp[k], BED.v + 3 * k,
                               BED.w + 3 * k));
        }
    }
    for (int k = 0; k < j->steps; ++k)
        TRY(sinter_stepper_step(st, 1));
    TRY(export_owned(st, ps, j->out));
    if (j->rank == 0) { /* the global part: the same on every subdomain */
        TRY(domain_records_save_global(st, &j->out->global, &j->out->global_len));
        for (int k = 0; k < NW; ++k)
            TRY(sinter_walls_get_force(walls, (size_t)k, j->out->wall + 3 * k));
    }
done:
    if (j->failed)
        snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(gravity);
    sinter_force_model_destroy(contact);
    sinter_heat_model_destroy(cond);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The bed on `size` slabs (0: one run without domain operations) for `steps` steps, from the
 * bed or from checkpoint `restart`; every particle's record into out. */
static void run_on(int size, int reproducible, int threads, int steps, const records *restart,
                   records *out)
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
                        .steps = steps,
                        .restart = restart,
                        .out = out};
        assert_int_equal(pthread_create(&t[r], NULL, run, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(t[r], NULL), 0);
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].failed)
            print_error("%d slabs, subdomain %d: failed at line %d: %s\n", size, r, jobs[r].failed,
                        jobs[r].message);
        assert_int_equal(jobs[r].failed, 0);
    }
    for (int k = 0; k < BED.n; ++k) /* every particle owned once */
        assert_non_null(out->rec[k]);
}

/* The number of particles whose records differ (length or bytes). */
static int differing(const records *a, const records *b)
{
    return domain_records_differing(a->rec, a->len, b->rec, b->len, BED.n);
}

static records REF, RUN;

static void test_reproducible_decompositions(void **unused)
{
    (void)unused;
    make_bed(8, 6, 6, 0, 0);
    run_on(0, 1, 1, STEPS, NULL, &REF); /* without domain operations, one thread */
    for (int threads = 1; threads <= 2; ++threads)
        for (int size = threads == 1 ? 1 : 0; size <= LOOPBACK_MAX; ++size) {
            run_on(size, 1, threads, STEPS, NULL, &RUN);
            const int d = differing(&RUN, &REF);
            print_message("reproducible, %d slabs, %d threads: %d of %d records differ\n", size,
                          threads, d, BED.n);
            assert_int_equal(d, 0);
            /* the global part: time, counters, the walls' reactions (exact sums) */
            assert_int_equal(RUN.global_len, REF.global_len);
            assert_memory_equal(RUN.global, REF.global, REF.global_len);
            records_free(&RUN);
        }
    /* the default mode on 3 slabs: other sums, other bits (the comparison can fail) */
    records def;
    run_on(0, 0, 1, STEPS, NULL, &def);
    run_on(3, 0, 1, STEPS, NULL, &RUN);
    const int d = differing(&RUN, &def);
    print_message("default mode, 3 slabs: %d of %d records differ from one domain\n", d, BED.n);
    assert_true(d > 0);
    records_free(&RUN);
    records_free(&def);
    records_free(&REF);
}

static void test_checkpoint_across_decompositions(void **unused)
{
    (void)unused;
    make_bed(8, 6, 6, 0, 0);
    run_on(4, 1, 1, STEPS, NULL, &REF); /* uninterrupted */
    records ckpt;
    run_on(4, 1, 1, SPLIT, NULL, &ckpt); /* the checkpoint at step SPLIT, on 4 slabs */
    run_on(2, 1, 1, STEPS - SPLIT, &ckpt, &RUN);
    const int d = differing(&RUN, &REF);
    print_message("checkpoint of 4 slabs at step %d, continued on 2: %d of %d records differ\n",
                  SPLIT, d, BED.n);
    assert_int_equal(d, 0);
    /* the walls' reactions (the global parts differ in the count of neighbour builds: the
     * restart builds its lists afresh) */
    assert_memory_equal(RUN.wall, REF.wall, sizeof(REF.wall));
    records_free(&RUN);
    records_free(&ckpt);
    records_free(&REF);
}

/*
 * Threads and the order in memory, without domain operations: a bed of 1728 spheres (about
 * 5 000 candidate pairs: the default mode partitions its list for the threads, and from 512
 * particles the integrator's passes run on them), ids in lattice order, in reproducible mode
 * on one thread in lattice order and on two threads added last first: the same bits. (In
 * lattice order the pairs sorted by id are also sorted by index, which the partition takes
 * for the build's order: the mode must refuse it, or the sums of its boundary contacts come
 * later than in the reversed run.) In the default mode the
 * reversed order gives other bits (a particle's sums come in another order).
 */
static void test_reproducible_threads_and_order(void **unused)
{
    (void)unused;
    enum { SHORT = 30 };
    make_bed(12, 12, 12, 0, 1);
    records one, two;
    run_on(0, 1, 1, SHORT, NULL, &one);
    BED.reversed = 1;
    run_on(0, 1, 2, SHORT, NULL, &two);
    const int d = differing(&one, &two);
    print_message("reproducible, %d spheres: 1 thread in order against 2 threads reversed: %d "
                  "records differ\n",
                  BED.n, d);
    assert_int_equal(d, 0);
    records_free(&one);
    records_free(&two);
    run_on(0, 0, 2, SHORT, NULL, &two); /* default mode, reversed */
    BED.reversed = 0;
    run_on(0, 0, 2, SHORT, NULL, &one);
    const int e = differing(&one, &two);
    print_message("default mode: in order against reversed: %d records differ\n", e);
    assert_true(e > 0);
    records_free(&one);
    records_free(&two);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reproducible_decompositions),
        cmocka_unit_test(test_checkpoint_across_decompositions),
        cmocka_unit_test(test_reproducible_threads_and_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
