/*
 * libsinter_mpi's sinter_mpi_attach with the staggered stepper (issue 44), under mpiexec on 1
 * to 4 ranks: the small press of tests/unit/test_domain_staggered.c (240 spheres, the seed 000
 * power law, drag, gravity, conduction, Joule heating and the averaged electric model between
 * two current walls, scheme 1 with adaptive steps) on a brick of x slabs, each rank adding the
 * particles of its slab.
 *  - np 1: the same bits as the run without domain operations.
 *  - np 2-4: every particle owned once, the same steps, rejections and fixed-point iterations
 *    as the single domain (the decisions come from reductions), displacements, velocities,
 *    temperature changes, currents and wall forces within 1e-10 relative of it (the loopback
 *    test's tolerance and argument), the wall forces the same bits on every rank; and the same
 *    values as the thread transport (domain_loopback.c) on as many slabs, run on rank 0 (both
 *    take ghosts and arrivals in ascending rank order and reduce alike).
 *  - Slabs whose borders lie on columns of the lattice: the particles about them migrate, at
 *    the accepted states only (the stepper refuses a migration inside an attempt; the leavers
 *    stay and go at the next accepted state); the same tolerances.
 *  - The press with the "network" electric model instead (domain_press.h: a supply at its
 *    compliance limit, the top electrode grounded; 20 steps), its global solve at every
 *    iterate through MPI: the same comparisons, the currents within 1e-9 (the serial run's
 *    own spread is 1.7e-10, tests/unit/test_domain_electric.c), and the same values as the
 *    thread transport.
 *  - The reproducible mode (stepper option "reproducible"), both schemes, borders between
 *    columns and (scheme 1) on them: every particle's export record gathered to rank 0 by id
 *    (mpi_records.h) the same bytes as the single domain's and as the thread transport's on
 *    as many slabs; the time, wall reactions, steps, rejections, iterations and sweeps the same,
 *    the global part too where nothing migrates (a migration counts a neighbour build of its
 *    own). In the default mode these runs differ (3e-13 above), so the comparison can fail.
 *  - np 2-4: an MPI-IO checkpoint of that mode written at step 5 (the single domain's global
 *    part and records at that step), read and continued on 2 ranks: the uninterrupted run's
 *    records, time and counts (from 3 ranks the readers send particles on before any step:
 *    their records must pass on the predictor's history they brought, src/stepper/migrate.c).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_mpi.h>
#include <sinter_submodel.h>

#include "../unit/domain_loopback.h"
#include "../unit/domain_press.h"
#include "mpi_check.h"
#include "mpi_records.h"

enum { N = PRESS_N, NW = PRESS_WALLS };

static int NETWORK = 0; /* the electric model of the next runs: 1 "network", 0 "averaged" */

static press_spec PRESS;

/* The slabs (domain_press.h): borders between columns of the lattice, then on them. */
static double X0 = PRESS_X0_BETWEEN, X1 = PRESS_X1_BETWEEN;

typedef press_state state;

/* A run: the press job, and its transport (the thread one, an MPI domain, or neither:
 * without domain operations). */
typedef struct job {
    press_job p;
    loopback *lb;
    sinter_mpi_domain *d;
    uint64_t migrated;     /* MPI: particles this rank sent to others */
    sinter_particles *ps;  /* (from attach) */
    records *rec;          /* NULL, or the owned particles' records after the run */
    MPI_Comm comm;         /* the ranks of the checkpoint's write or read */
    const char *ckpt_save; /* NULL, or the MPI-IO checkpoint written after the run */
    const char *ckpt_load; /* NULL, or the checkpoint read instead of the spec's particles */
} job;

typedef struct job_and_state {
    job *j;
    state *out;
} job_and_state;

static sinter_status attach(void *user, sinter_stepper *st, sinter_particles *ps)
{
    job *j = user;
    j->ps = ps;
    if (j->lb != NULL)
        return loopback_attach(j->lb, j->p.rank, st, ps);
    if (j->d != NULL)
        return sinter_mpi_attach(j->d, st, ps, 0);
    return SINTER_OK;
}

static const double LO[3] = {0, -PRESS_A, -PRESS_A}; /* (x from X0 or X1) */
static const double HI[3] = {0, PRESS_LY + PRESS_A, PRESS_TOP + PRESS_A};

/* The checkpoint read on this job's slabs (after attach, as sinter_mpi.h asks). */
static sinter_status load(void *user, sinter_stepper *st, sinter_particles *ps)
{
    job *j = user;
    const int grid[3] = {j->p.size, 1, 1};
    const double lo[3] = {X0, LO[1], LO[2]}, hi[3] = {X1, HI[1], HI[2]};
    sinter_mpi_decomp *dc = NULL;
    sinter_status s = sinter_mpi_decomp_brick(&dc, j->p.size, grid, lo, hi);
    if (s == SINTER_OK)
        s = sinter_mpi_checkpoint_read(st, ps, j->comm, j->ckpt_load, dc, NULL);
    sinter_mpi_decomp_destroy(dc);
    return s;
}

static sinter_status finish(void *user, sinter_stepper *st)
{
    job *j = user;
    sinter_status s = SINTER_OK;
    if (j->rec != NULL)
        s = records_export(st, j->ps, N, j->rec);
    if (s == SINTER_OK && j->rec != NULL && (j->lb == NULL || j->p.rank == 0))
        s = records_save_global(st, j->rec);
    if (s == SINTER_OK && j->ckpt_save != NULL)
        s = sinter_mpi_checkpoint_write(st, j->ps, j->comm, j->ckpt_save);
    if (j->d == NULL || s != SINTER_OK)
        return s;
    sinter_mpi_exchange_stats xs = {.struct_size = sizeof xs};
    s = sinter_mpi_get_exchange_stats(j->d, &xs);
    j->migrated = xs.migrated_out;
    return s;
}

static int REPRO = 0, SCHEME = 1; /* the next runs' options "reproducible" and "scheme" */

/* The staggered press of `rank` among `size`. */
static job make_job(int rank, int size, loopback *lb, sinter_mpi_domain *d)
{
    job j = {.lb = lb, .d = d, .comm = MPI_COMM_WORLD};
    j.p = (press_job){.spec = &PRESS,
                      .rank = rank,
                      .size = size,
                      .x0 = X0,
                      .x1 = X1,
                      .kind = SINTER_STEPPER_STAGGERED,
                      .scheme = SCHEME,
                      .reproducible = REPRO,
                      .network = NETWORK,
                      .steps = NETWORK ? 20 : 12,
                      .nan_after = INFINITY,
                      .attach = lb != NULL || d != NULL || REPRO ? attach : NULL,
                      .finish = finish};
    return j;
}

static void *run_press(void *arg)
{
    job_and_state *js = arg;
    js->j->p.user = js->j;
    press_run(&js->j->p, js->out);
    return NULL;
}

static job REF_JOB, MY_JOB, LOOP_JOBS[LOOPBACK_MAX];
static state REF, MINE, ALL, LOOP;
static records REF_REC, MINE_REC, ALL_REC, LOOP_REC;
static double X_START[3 * N], T_START[N];

/* Every rank's owned slots summed into `all` (each slot written by one rank only). */
static void gather(state *mine, state *all)
{
    *all = *mine;
    MPI_Allreduce(MPI_IN_PLACE, all->x, 3 * N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, all->v, 3 * N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, all->temp, N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, all->current, N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, all->seen, N, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
}

static void *run_thread(void *arg)
{
    return run_press(arg);
}

/* The press on the thread transport's `size` slabs (rank 0 only). */
static void run_loopback(int size)
{
    memset(&LOOP, 0, sizeof LOOP);
    records_free(&LOOP_REC);
    loopback *lb = loopback_create(size);
    CHECK(lb != NULL);
    if (lb == NULL)
        return;
    loopback_set_slabs(lb, X0, X1);
    pthread_t threads[LOOPBACK_MAX];
    job_and_state js[LOOPBACK_MAX];
    for (int r = 0; r < size; ++r) {
        LOOP_JOBS[r] = make_job(r, size, lb, NULL);
        LOOP_JOBS[r].rec = REPRO ? &LOOP_REC : NULL;
        js[r] = (job_and_state){&LOOP_JOBS[r], &LOOP};
        CHECK(pthread_create(&threads[r], NULL, run_thread, &js[r]) == 0);
    }
    for (int r = 0; r < size; ++r)
        CHECK(pthread_join(threads[r], NULL) == 0);
    loopback_destroy(lb);
}

static sinter_mpi_domain *make_domain(MPI_Comm comm, int size)
{
    sinter_mpi_options o;
    sinter_mpi_options_init(&o, sizeof o);
    o.decomposition = SINTER_MPI_DECOMP_BRICK;
    const int grid[3] = {size, 1, 1};
    const double lo[3] = {X0, -PRESS_A, -PRESS_A},
                 hi[3] = {X1, PRESS_LY + PRESS_A, PRESS_TOP + PRESS_A};
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, comm, &o) == SINTER_OK);
    return d;
}

/* The press through MPI against the single-domain run (and the loopback's on rank 0). */
static void test_press(int rank, int size, const char *what)
{
    press_make(&PRESS);
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)PRESS.id[k] - 1;
        memcpy(X_START + 3 * i, PRESS.x + 3 * k, 24);
        T_START[i] = PRESS.temp[k];
    }
    memset(&REF, 0, sizeof REF);
    REF_JOB = make_job(0, 1, NULL, NULL);
    job_and_state rs = {&REF_JOB, &REF};
    run_press(&rs);
    CHECK(REF_JOB.p.setup_failed == 0 && REF_JOB.p.status == SINTER_OK);
    CHECK(REF_JOB.p.stats.iterations > 2 * REF_JOB.p.stats.steps);

    memset(&MINE, 0, sizeof MINE);
    sinter_mpi_domain *d = make_domain(MPI_COMM_WORLD, size);
    MY_JOB = make_job(rank, size, NULL, d);
    job_and_state ms = {&MY_JOB, &MINE};
    if (d != NULL)
        run_press(&ms);
    if (MY_JOB.p.setup_failed || MY_JOB.p.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, MY_JOB.p.message);
    CHECK(MY_JOB.p.setup_failed == 0 && MY_JOB.p.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    gather(&MINE, &ALL);
    for (int k = 0; k < N; ++k)
        CHECK(ALL.seen[k] == 1);
    uint64_t migrated = MY_JOB.migrated;
    MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    /* collective: the same time, steps, rejections, iterations and wall forces everywhere */
    CHECK(same_on_every_rank(&MY_JOB.p.time, sizeof MY_JOB.p.time));
    CHECK(same_on_every_rank(MY_JOB.p.wall, sizeof MY_JOB.p.wall));
    CHECK(MY_JOB.p.stats.steps == REF_JOB.p.stats.steps);
    CHECK(MY_JOB.p.stats.rejected == REF_JOB.p.stats.rejected);
    CHECK(MY_JOB.p.stats.iterations == REF_JOB.p.stats.iterations);
    if (size == 1) { /* the same bits */
        CHECK(MY_JOB.p.time == REF_JOB.p.time);
        CHECK(memcmp(ALL.x, REF.x, sizeof REF.x) == 0);
        CHECK(memcmp(ALL.v, REF.v, sizeof REF.v) == 0);
        CHECK(memcmp(ALL.temp, REF.temp, sizeof REF.temp) == 0);
        CHECK(memcmp(ALL.current, REF.current, sizeof REF.current) == 0);
        CHECK(memcmp(MY_JOB.p.wall, REF_JOB.p.wall, sizeof REF_JOB.p.wall) == 0);
        return;
    }
    const double dx = press_rel_diff(ALL.x, REF.x, X_START, 3 * N);
    const double dv = press_rel_diff(ALL.v, REF.v, NULL, 3 * N);
    const double dt = press_rel_diff(ALL.temp, REF.temp, T_START, N);
    const double dc = press_rel_diff(ALL.current, REF.current, NULL, N);
    const double dw = press_rel_diff(MY_JOB.p.wall, REF_JOB.p.wall, NULL, 3 * NW);
    if (rank == 0)
        fprintf(stderr,
                "%s, %d ranks: %llu migrations; displacements %.2g, velocities %.2g, "
                "temperature changes %.2g, currents %.2g, wall forces %.2g (relative)\n",
                what, size, (unsigned long long)migrated, dx, dv, dt, dc, dw);
    CHECK(fabs(MY_JOB.p.time - REF_JOB.p.time) <= 1e-10 * REF_JOB.p.time);
    CHECK(dx <= 1e-10);
    CHECK(dv <= 1e-10);
    CHECK(dt <= 1e-10);
    CHECK(dc <= (NETWORK ? 1e-9 : 1e-10));
    CHECK(dw <= 1e-10);
    if (rank != 0)
        return;
    /* the thread transport on as many slabs: the same values */
    run_loopback(size);
    int differ = 0;
    for (int i = 0; i < 3 * N; ++i)
        differ += !(LOOP.x[i] == ALL.x[i]) + !(LOOP.v[i] == ALL.v[i]);
    for (int i = 0; i < N; ++i)
        differ += !(LOOP.temp[i] == ALL.temp[i]) + !(LOOP.current[i] == ALL.current[i]);
    fprintf(stderr, "%s, %d ranks: %d values differ from the thread transport's\n", what, size,
            differ);
    CHECK(differ == 0);
    CHECK(LOOP_JOBS[0].p.time == MY_JOB.p.time);
}

static int same_counts(const job *a, const job *b)
{
    return a->p.stats.steps == b->p.stats.steps && a->p.stats.rejected == b->p.stats.rejected &&
           a->p.stats.iterations == b->p.stats.iterations &&
           a->p.electric_iterations == b->p.electric_iterations;
}

enum { STEPS = 12, SPLIT = 5 }; /* the reproducible runs' steps; the checkpoint's step */

/* The reproducible mode (stepper option "reproducible", issue 43) through MPI: every
 * particle's export record, the time, the wall reactions and the counts the same bits as the
 * single-domain run's, and as the thread transport's on as many slabs (rank 0); the whole
 * global part too where no particle migrates (a migration makes a neighbour build of its own,
 * which the part counts: with migrations only that counter differs). */
static void test_reproducible(int rank, int size, const char *what)
{
    press_make(&PRESS);
    REPRO = 1;
    records_free(&REF_REC);
    REF_JOB = make_job(0, 1, NULL, NULL);
    REF_JOB.rec = &REF_REC;
    job_and_state rs = {&REF_JOB, &REF};
    run_press(&rs);
    CHECK(REF_JOB.p.setup_failed == 0 && REF_JOB.p.status == SINTER_OK);
    /* the run does what the comparison needs: rejections and fixed-point iterations */
    CHECK(REF_JOB.p.stats.steps == STEPS && REF_JOB.p.stats.rejected >= 1);
    CHECK(REF_JOB.p.stats.iterations > 2 * REF_JOB.p.stats.steps);

    records_free(&MINE_REC);
    sinter_mpi_domain *d = make_domain(MPI_COMM_WORLD, size);
    MY_JOB = make_job(rank, size, NULL, d);
    MY_JOB.rec = &MINE_REC;
    job_and_state ms = {&MY_JOB, &MINE};
    if (d != NULL)
        run_press(&ms);
    if (MY_JOB.p.setup_failed || MY_JOB.p.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, MY_JOB.p.message);
    CHECK(MY_JOB.p.setup_failed == 0 && MY_JOB.p.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    uint64_t migrated = MY_JOB.migrated;
    MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    /* on every rank: the counts, the global part and the wall reactions of the single domain */
    CHECK(same_counts(&MY_JOB, &REF_JOB));
    CHECK(MY_JOB.p.time == REF_JOB.p.time);
    CHECK(records_same_global(&MINE_REC, &REF_REC) || migrated > 0);
    CHECK(memcmp(MY_JOB.p.wall, REF_JOB.p.wall, sizeof REF_JOB.p.wall) == 0);
    CHECK(!records_gather(&MINE_REC, &ALL_REC, N, MPI_COMM_WORLD));
    records_free(&MINE_REC);
    if (rank != 0)
        return;
    const int dm = records_differing(&ALL_REC, &REF_REC, N);
    run_loopback(size); /* the thread transport on as many slabs */
    const int dl = records_differing(&LOOP_REC, &REF_REC, N);
    fprintf(stderr,
            "%s, scheme %d, reproducible, %d ranks: %llu steps, %llu rejected, %llu iterations, "
            "%llu sweeps, %llu migrations; %d of %d records differ from the single domain's, "
            "%d the thread transport's from it\n",
            what, SCHEME, size, (unsigned long long)REF_JOB.p.stats.steps,
            (unsigned long long)REF_JOB.p.stats.rejected,
            (unsigned long long)REF_JOB.p.stats.iterations,
            (unsigned long long)REF_JOB.p.electric_iterations, (unsigned long long)migrated, dm, N,
            dl);
    CHECK(dm == 0);
    CHECK(dl == 0);
    CHECK(same_counts(&LOOP_JOBS[0], &REF_JOB));
    CHECK(LOOP_JOBS[0].p.time == REF_JOB.p.time);
    CHECK(records_same_global(&LOOP_REC, &REF_REC) || migrated > 0);
    CHECK(memcmp(LOOP_JOBS[0].p.wall, REF_JOB.p.wall, sizeof REF_JOB.p.wall) == 0);
}

/* An MPI-IO checkpoint of the reproducible mode written on every rank at step SPLIT (its global
 * part and records the single domain's at that step), read and continued on 2 ranks (ranks 0
 * and 1): the records, time and counts of the uninterrupted single-domain run (REF_REC,
 * REF_JOB: test_reproducible's last, on the same slabs and scheme). From 3 ranks the readers
 * send on particles imported from the pieces of others before any step: their records carry
 * the predictor's history they brought (record bit 2, src/stepper/migrate.c; without it all
 * 240 records differ after 7 more steps, 51 fixed-point iterations instead of 52). */
static void test_checkpoint_to_2(int rank, int size, const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/mpi_staggered_repro_np%d.bin", dir, size);
    REPRO = 1;
    records at_split = {0}, written = {0}, all = {0};
    job one = make_job(0, 1, NULL, NULL); /* the single domain at step SPLIT */
    one.p.steps = SPLIT;
    one.rec = &at_split;
    job_and_state os = {&one, &LOOP};
    run_press(&os);
    sinter_mpi_domain *d = make_domain(MPI_COMM_WORLD, size);
    MY_JOB = make_job(rank, size, NULL, d);
    MY_JOB.p.steps = SPLIT;
    MY_JOB.ckpt_save = path;
    MY_JOB.rec = &written;
    job_and_state ms = {&MY_JOB, &MINE};
    if (d != NULL)
        run_press(&ms);
    CHECK(MY_JOB.p.setup_failed == 0 && MY_JOB.p.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    /* what the checkpoint holds: the single domain's state at that step */
    CHECK(records_same_global(&written, &at_split));
    CHECK(!records_gather(&written, &all, N, MPI_COMM_WORLD));
    if (rank == 0) {
        const int dw = records_differing(&all, &at_split, N);
        fprintf(stderr, "at step %d, %d ranks: %d of %d records differ from the single domain's\n",
                SPLIT, size, dw, N);
        CHECK(dw == 0);
    }
    records_free(&written);
    records_free(&all);
    records_free(&at_split);
    MPI_Comm two = MPI_COMM_NULL;
    MPI_Comm_split(MPI_COMM_WORLD, rank < 2 ? 0 : MPI_UNDEFINED, rank, &two);
    if (two != MPI_COMM_NULL) {
        records_free(&MINE_REC);
        d = make_domain(two, 2);
        MY_JOB = make_job(rank, 2, NULL, d);
        MY_JOB.p.steps = STEPS - SPLIT;
        MY_JOB.comm = two;
        MY_JOB.ckpt_load = path;
        MY_JOB.p.load = load;
        MY_JOB.rec = &MINE_REC;
        if (d != NULL)
            run_press(&ms);
        if (MY_JOB.p.setup_failed || MY_JOB.p.status != SINTER_OK)
            fprintf(stderr, "rank %d: %s\n", rank, MY_JOB.p.message);
        CHECK(MY_JOB.p.setup_failed == 0 && MY_JOB.p.status == SINTER_OK);
        sinter_mpi_domain_destroy(d);
        /* (the electric model's count of sweeps is its own, not in the checkpoint) */
        CHECK(MY_JOB.p.stats.steps == REF_JOB.p.stats.steps);
        CHECK(MY_JOB.p.stats.rejected == REF_JOB.p.stats.rejected);
        CHECK(MY_JOB.p.stats.iterations == REF_JOB.p.stats.iterations);
        CHECK(MY_JOB.p.time == REF_JOB.p.time);
        CHECK(records_same_global(&MINE_REC, &REF_REC) || X0 == PRESS_X0_ON); /* (builds: above) */
        CHECK(!records_gather(&MINE_REC, &ALL_REC, N, two));
        records_free(&MINE_REC);
        MPI_Comm_free(&two);
        if (rank == 0) {
            const int dm = records_differing(&ALL_REC, &REF_REC, N);
            fprintf(stderr,
                    "reproducible checkpoint of %d ranks at step %d, continued on 2: %d of %d "
                    "records differ from the uninterrupted single domain's\n",
                    size, SPLIT, dm, N);
            CHECK(dm == 0);
        }
    }
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        remove(path);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const char *dir = argc > 1 ? argv[1] : ".";
    /* borders between two columns of the lattice: no migration */
    test_press(rank, size, "borders between columns");
    /* borders on columns: the particles about them migrate at accepted states */
    X0 = PRESS_X0_ON;
    X1 = PRESS_X1_ON;
    test_press(rank, size, "borders on columns");
    /* the network's global solve inside the fixed point */
    NETWORK = 1;
    test_press(rank, size, "network, borders on columns");
    /* the reproducible mode, both schemes: the single domain's bits (the averaged model) */
    NETWORK = 0;
    X0 = PRESS_X0_BETWEEN;
    X1 = PRESS_X1_BETWEEN;
    for (SCHEME = 0; SCHEME <= 1; ++SCHEME)
        test_reproducible(rank, size, "borders between columns");
    SCHEME = 1;
    if (size >= 2)
        test_checkpoint_to_2(rank, size, dir);
    X0 = PRESS_X0_ON;
    X1 = PRESS_X1_ON;
    test_reproducible(rank, size, "borders on columns");
    if (size >= 2)
        test_checkpoint_to_2(rank, size, dir);
    records_free(&REF_REC);
    records_free(&ALL_REC);
    records_free(&LOOP_REC);
    const int failed = mpi_check_finish("test_mpi_staggered");
    MPI_Finalize();
    return failed;
}
