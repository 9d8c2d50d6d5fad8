/*
 * libsinter_mpi's sinter_mpi_attach with the quasi-static stepper (issue 44), under mpiexec on
 * 1 to 4 ranks: the copper lattice of tests/unit/test_qs_domain.c (8 x 3 x 3 spheres of seed
 * 001 table 2 copper at 1293 K, 159 links, strategy 2 as in the copper_lattice scene, 40 global
 * steps, the particles on x, y, z = 0 held on their planes, the solve's target 1e-12 |f|) on a
 * brick of x slabs. The stepper redistributes once per step call; each link is owned by the
 * rank of its smaller id, its loads on a ghost end come back through the reverse halo.
 *  - np 1: positions, rotations, necks, approaches and statistics the bits of the run without
 *    domain operations.
 *  - np 2-4: every particle owned once, every link once, the same time reached, and positions,
 *    displacements, rotations (R theta against the largest displacement), necks, approaches
 *    and statistics within 1e-10 relative of the single domain (the loopback test's bound;
 *    with strategy 2 it measured every difference below 5e-12).
 *  - Misplaced: each rank starts with the particles of the slabs moved by +2R, so the first
 *    redistribution migrates a column at each border (through MPI_Alltoallv: no graph yet);
 *    the same comparison.
 *  - The reproducible mode (stepper option "reproducible"), strategies 2 and 3, in place and
 *    misplaced: every particle's export record gathered to rank 0 by id (mpi_records.h; its
 *    quasi-static state and the links of its smaller id) the same bytes as the single
 *    domain's, and the statistics, steps and end time the same bits. In the default mode the
 *    decomposed runs differ (within 5e-12 above), so the comparison can fail.
 *  - np 2-4: an MPI-IO checkpoint of that mode written after 20 steps, read and continued on 2
 *    ranks for 20 more: the uninterrupted single domain's records and statistics (from 3 ranks
 *    the readers send particles on before any step: their records must pass on the
 *    quasi-static state they brought, src/stepper/qs_portable.c; without it all 72 differ).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_mpi.h>
#include <sinter_submodel.h>

#include "../unit/domain_copper.h"
#include "mpi_check.h"
#include "mpi_records.h"

enum { NX = COPPER_NX, NY = COPPER_NY, NZ = COPPER_NZ, N = COPPER_N, MAX_LINKS = COPPER_MAX_LINKS };
static const double R = COPPER_R;
enum { STEPS = 40 }; /* global steps of a run (the first, then the others in one or two calls) */
static double SOLVE_RTOL = 1e-12;

typedef copper_outcome outcome;

typedef struct job {
    int rank, size;
    sinter_mpi_domain *d;  /* NULL: without domain operations */
    int misplaced;         /* each rank adds the particles of the slabs moved by +2R */
    int strategy;          /* the option "qs_strategy" (0: 2) */
    int reproducible;      /* the option "reproducible" (0: not set, the default mode) */
    records *rec;          /* NULL, or the owned particles' records after the run */
    MPI_Comm comm;         /* the ranks of the checkpoint's write or read */
    const char *ckpt_save; /* NULL, or the MPI-IO checkpoint written after STEPS / 2 steps */
    const char *ckpt_load; /* NULL, or the checkpoint continued for STEPS / 2 steps */
    uint64_t migrated;
    double end_time;
    outcome *out;
    int setup_failed;
    sinter_status status;
    char message[512];
} job;

static const double LO[3] = {COPPER_X0, -COPPER_R, -COPPER_R};
static const double HI[3] = {COPPER_X1, (2 * COPPER_NY + 1) * COPPER_R,
                             (2 * COPPER_NZ + 1) * COPPER_R};

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
    /* collective: every rank calls it */
    if (copper_sintering_stats(st, &ss) != SINTER_OK)
        j->setup_failed = __LINE__;
    const int failed = copper_collect(j->out, 0, ps, st, &ss); /* (this rank's counts: slot 0) */
    if (failed)
        j->setup_failed = failed;
}

static void run(job *j)
{
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(copper_setup(ctx, j->strategy ? j->strategy : 2, SOLVE_RTOL, &mat, &ps, &st));
    if (j->reproducible)
        TRY(sinter_stepper_set_option(st, "reproducible", 1));
    const double shift = j->misplaced ? 2.0 * R : 0.0;
    if (j->ckpt_load == NULL)
        TRY(copper_add(ps, j->rank, j->d != NULL ? j->size : 0, shift, 0));
    if (j->d != NULL)
        j->status = sinter_mpi_attach(j->d, st, ps, 0);
    if (j->ckpt_load != NULL) { /* read after the attach (sinter_mpi.h) */
        const int grid[3] = {j->size, 1, 1};
        sinter_mpi_decomp *dc = NULL;
        if (j->status == SINTER_OK)
            j->status = sinter_mpi_decomp_brick(&dc, j->size, grid, LO, HI);
        if (j->status == SINTER_OK)
            j->status = sinter_mpi_checkpoint_read(st, ps, j->comm, j->ckpt_load, dc, NULL);
        sinter_mpi_decomp_destroy(dc);
        if (j->status == SINTER_OK)
            j->status = sinter_stepper_step(st, STEPS / 2);
    } else {
        if (j->status == SINTER_OK)
            j->status = sinter_stepper_step(st, 1);
        if (j->status == SINTER_OK && j->ckpt_save != NULL) {
            j->status = sinter_stepper_step(st, STEPS / 2 - 1);
            if (j->status == SINTER_OK)
                j->status = sinter_mpi_checkpoint_write(st, ps, j->comm, j->ckpt_save);
            if (j->status == SINTER_OK)
                j->status = sinter_stepper_step(st, STEPS / 2);
        } else if (j->status == SINTER_OK) {
            j->status = sinter_stepper_step(st, STEPS - 1);
        }
    }
    if (j->d != NULL) {
        sinter_mpi_exchange_stats xs = {.struct_size = sizeof xs};
        TRY(sinter_mpi_get_exchange_stats(j->d, &xs));
        j->migrated = xs.migrated_out;
    }
    TRY(sinter_stepper_time(st, &j->end_time));
    if (j->status != SINTER_OK) {
        snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
        goto done;
    }
    collect(j, ps, st);
    if (j->rec != NULL)
        TRY(records_export(st, ps, N, j->rec));
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
}

static outcome REF, MINE;
/* every rank's links in the reference's order (by their ids), summed over the ranks */
static double NECK[MAX_LINKS], APPROACH[MAX_LINKS];
static int LINK_SEEN[MAX_LINKS];
static double X_ALL[3 * N], ROT_ALL[3 * N];
static int SEEN_ALL[N];

static void gather(void)
{
    memset(NECK, 0, sizeof NECK);
    memset(APPROACH, 0, sizeof APPROACH);
    memset(LINK_SEEN, 0, sizeof LINK_SEEN);
    for (size_t q = 0; q < MINE.links; ++q) {
        size_t found = SIZE_MAX;
        for (size_t k = 0; k < REF.links && found == SIZE_MAX; ++k)
            if (MINE.link_a[q] == REF.link_a[k] && MINE.link_b[q] == REF.link_b[k])
                found = k;
        CHECK(found != SIZE_MAX);
        if (found == SIZE_MAX)
            continue;
        NECK[found] = MINE.neck[q];
        APPROACH[found] = MINE.approach[q];
        LINK_SEEN[found]++;
    }
    memcpy(X_ALL, MINE.x, sizeof X_ALL);
    memcpy(ROT_ALL, MINE.rot, sizeof ROT_ALL);
    memcpy(SEEN_ALL, MINE.seen, sizeof SEEN_ALL);
    MPI_Allreduce(MPI_IN_PLACE, NECK, MAX_LINKS, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, APPROACH, MAX_LINKS, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, LINK_SEEN, MAX_LINKS, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, X_ALL, 3 * N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, ROT_ALL, 3 * N, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, SEEN_ALL, N, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
}

static sinter_mpi_domain *make_domain_on(MPI_Comm comm, int size)
{
    sinter_mpi_options o;
    sinter_mpi_options_init(&o, sizeof o);
    o.decomposition = SINTER_MPI_DECOMP_BRICK;
    const int grid[3] = {size, 1, 1};
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, LO, sizeof LO);
    memcpy(o.hi, HI, sizeof HI);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, comm, &o) == SINTER_OK);
    return d;
}

static sinter_mpi_domain *make_domain(int size)
{
    return make_domain_on(MPI_COMM_WORLD, size);
}

static void test_lattice(int rank, int size, int misplaced)
{
    memset(&REF, 0, sizeof REF);
    job rj = {.rank = 0, .size = 1, .out = &REF};
    run(&rj);
    CHECK(rj.setup_failed == 0 && rj.status == SINTER_OK);
    CHECK(REF.steps == STEPS);
    CHECK(REF.links >= 2 * N - NY * NZ - NX * NZ - NX * NY); /* every neighbour pair */
    memset(&MINE, 0, sizeof MINE);
    sinter_mpi_domain *d = make_domain(size);
    job mj = {.rank = rank, .size = size, .d = d, .misplaced = misplaced, .out = &MINE};
    if (d != NULL)
        run(&mj);
    if (mj.setup_failed || mj.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, mj.message);
    CHECK(mj.setup_failed == 0 && mj.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    gather();
    for (size_t k = 0; k < N; ++k)
        CHECK(SEEN_ALL[k] == 1);
    for (size_t k = 0; k < REF.links; ++k)
        CHECK(LINK_SEEN[k] == 1);
    uint64_t links = MINE.links;
    MPI_Allreduce(MPI_IN_PLACE, &links, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(links == REF.links);
    CHECK(MINE.steps == REF.steps);
    CHECK(same_on_every_rank(MINE.stats, (int)sizeof MINE.stats)); /* reduced */
    CHECK(mj.end_time == rj.end_time);                             /* the same global steps */
    uint64_t migrated = mj.migrated;
    MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(migrated == (misplaced ? (uint64_t)(size - 1) * NY * NZ : 0));
    if (size == 1) { /* bit for bit */
        CHECK(memcmp(X_ALL, REF.x, sizeof REF.x) == 0);
        CHECK(memcmp(ROT_ALL, REF.rot, sizeof REF.rot) == 0);
        CHECK(memcmp(NECK, REF.neck, REF.links * sizeof(double)) == 0);
        CHECK(memcmp(APPROACH, REF.approach, REF.links * sizeof(double)) == 0);
        CHECK(memcmp(MINE.stats, REF.stats, sizeof REF.stats) == 0);
        return;
    }
    CHECK(MINE.owned[0] >= NY * NZ && MINE.ghosts[0] >= NY * NZ);
    double ua[3 * N], ub[3 * N], umax = 0.0, rot = 0.0;
    for (size_t k = 0; k < N; ++k) { /* the displacements, by id */
        double x[3], r;
        copper_place(k, 0, x, &r);
        const size_t i = (size_t)copper_id_of(k) - 1;
        for (size_t c = 0; c < 3; ++c) {
            ua[3 * i + c] = REF.x[3 * i + c] - x[c];
            ub[3 * i + c] = X_ALL[3 * i + c] - x[c];
        }
    }
    for (size_t i = 0; i < 3 * N; ++i) {
        umax = fmax(umax, fabs(ua[i]));
        rot = fmax(rot, R * fabs(REF.rot[i] - ROT_ALL[i]));
    }
    const double e[6] = {copper_rel_diff(REF.x, X_ALL, 3 * N),
                         copper_rel_diff(ua, ub, 3 * N),
                         rot / umax,
                         copper_rel_diff(REF.neck, NECK, REF.links),
                         copper_rel_diff(REF.approach, APPROACH, REF.links),
                         copper_rel_diff(REF.stats, MINE.stats, 9)};
    if (rank == 0)
        fprintf(stderr,
                "%s, %d ranks: %llu migrations; relative differences x %.2e, u %.2e, rot %.2e, "
                "neck %.2e, approach %.2e, stats %.2e (PCG iterations %.0f, serial %.0f)\n",
                misplaced ? "misplaced" : "in place", size, (unsigned long long)migrated, e[0],
                e[1], e[2], e[3], e[4], e[5], MINE.stats[10], REF.stats[10]);
    for (int k = 0; k < 6; ++k)
        CHECK(e[k] <= 1e-10);
    CHECK(REF.stats[4] > 0.0); /* it shrank */
}

static records REF_REC, MINE_REC, ALL_REC;

/* The reproducible mode (stepper option "reproducible", issue 43) through MPI with strategy
 * 2 or 3: every particle's export record (its state, its quasi-static state, the links of its
 * smaller id with their neck state), the statistics, the steps and the time reached the same
 * bits as the single domain's. (The thread transport gives the single domain's bits too on 1
 * to 4 slabs: tests/unit/test_qs_domain_repro.c. The global part is not compared: its count
 * of neighbour builds follows the redistributions.) */
static void test_reproducible(int rank, int size, int strategy, int misplaced)
{
    memset(&REF, 0, sizeof REF);
    records_free(&REF_REC);
    job rj = {.rank = 0,
              .size = 1,
              .out = &REF,
              .strategy = strategy,
              .reproducible = 1,
              .rec = &REF_REC};
    run(&rj);
    CHECK(rj.setup_failed == 0 && rj.status == SINTER_OK);
    CHECK(REF.steps == STEPS);
    memset(&MINE, 0, sizeof MINE);
    records_free(&MINE_REC);
    sinter_mpi_domain *d = make_domain(size);
    job mj = {.rank = rank,
              .size = size,
              .d = d,
              .misplaced = misplaced,
              .out = &MINE,
              .strategy = strategy,
              .reproducible = 1,
              .rec = &MINE_REC};
    if (d != NULL)
        run(&mj);
    if (mj.setup_failed || mj.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, mj.message);
    CHECK(mj.setup_failed == 0 && mj.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    CHECK(MINE.steps == REF.steps);
    CHECK(mj.end_time == rj.end_time);
    CHECK(memcmp(MINE.stats, REF.stats, sizeof REF.stats) == 0); /* (collective) */
    uint64_t migrated = mj.migrated;
    MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(!records_gather(&MINE_REC, &ALL_REC, N, MPI_COMM_WORLD));
    records_free(&MINE_REC);
    if (rank != 0)
        return;
    const int dm = records_differing(&ALL_REC, &REF_REC, N);
    fprintf(stderr,
            "reproducible, strategy %d, %s, %d ranks: %llu steps, %llu migrations; %d of %d "
            "records differ from the single domain's\n",
            strategy, misplaced ? "misplaced" : "in place", size, (unsigned long long)REF.steps,
            (unsigned long long)migrated, dm, N);
    CHECK(dm == 0);
}

/* An MPI-IO checkpoint of the reproducible mode written on every rank after STEPS / 2 steps,
 * read and continued on 2 ranks (ranks 0 and 1) for STEPS / 2 more: the records, statistics
 * and end time of the uninterrupted single domain (REF_REC, REF: test_reproducible's last, of
 * the same strategy). */
static void test_checkpoint_to_2(int rank, int size, int strategy, const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/mpi_qs_repro_np%d.bin", dir, size);
    outcome *w = calloc(1, sizeof(outcome));
    CHECK(w != NULL);
    if (w == NULL)
        return;
    sinter_mpi_domain *d = make_domain(size);
    job wj = {.rank = rank,
              .size = size,
              .d = d,
              .out = w,
              .strategy = strategy,
              .reproducible = 1,
              .comm = MPI_COMM_WORLD,
              .ckpt_save = path};
    if (d != NULL)
        run(&wj);
    CHECK(wj.setup_failed == 0 && wj.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    free(w);
    MPI_Comm two = MPI_COMM_NULL;
    MPI_Comm_split(MPI_COMM_WORLD, rank < 2 ? 0 : MPI_UNDEFINED, rank, &two);
    if (two != MPI_COMM_NULL) {
        memset(&MINE, 0, sizeof MINE);
        records_free(&MINE_REC);
        d = make_domain_on(two, 2);
        job mj = {.rank = rank,
                  .size = 2,
                  .d = d,
                  .out = &MINE,
                  .strategy = strategy,
                  .reproducible = 1,
                  .rec = &MINE_REC,
                  .comm = two,
                  .ckpt_load = path};
        if (d != NULL)
            run(&mj);
        if (mj.setup_failed || mj.status != SINTER_OK)
            fprintf(stderr, "rank %d: %s\n", rank, mj.message);
        CHECK(mj.setup_failed == 0 && mj.status == SINTER_OK);
        sinter_mpi_domain_destroy(d);
        CHECK(MINE.steps == REF.steps);
        CHECK(memcmp(MINE.stats, REF.stats, sizeof REF.stats) == 0);
        CHECK(!records_gather(&MINE_REC, &ALL_REC, N, two));
        records_free(&MINE_REC);
        MPI_Comm_free(&two);
        if (rank == 0) {
            const int dm = records_differing(&ALL_REC, &REF_REC, N);
            fprintf(stderr,
                    "reproducible checkpoint, strategy %d, of %d ranks at step %d, continued on "
                    "2: %d of %d records differ from the uninterrupted single domain's\n",
                    strategy, size, STEPS / 2, dm, N);
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
    test_lattice(rank, size, 0);
    if (size > 1)
        test_lattice(rank, size, 1);
    for (int strategy = 2; strategy <= 3; ++strategy) {
        test_reproducible(rank, size, strategy, 0);
        if (size > 1)
            test_reproducible(rank, size, strategy, 1);
        if (size > 1)
            test_checkpoint_to_2(rank, size, strategy, argc > 1 ? argv[1] : ".");
    }
    records_free(&REF_REC);
    records_free(&ALL_REC);
    const int failed = mpi_check_finish("test_mpi_qs");
    MPI_Finalize();
    return failed;
}
