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
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_mpi.h>
#include <sinter_submodel.h>

#include "mpi_check.h"

enum { LOOPBACK_MAX = 4 };

enum { NX = 8, NY = 3, NZ = 3, N = NX * NY * NZ, MAX_LINKS = 4 * N };
static const double R = 25e-6;
enum { STEPS = 40 }; /* global steps of a run (the first, then the others in one or two calls) */
static double SOLVE_RTOL = 1e-12;
static const int FLOAT = 0; /* the top layer lifted off and moved away from the planes (below) */

typedef struct outcome {
    double x[3 * N], rot[3 * N]; /* by id - 1 */
    int seen[N];
    size_t links;
    uint64_t link_a[MAX_LINKS], link_b[MAX_LINKS];
    double neck[MAX_LINKS], approach[MAX_LINKS];
    double stats[11];
    uint64_t steps;
    size_t owned, ghosts; /* this rank's */
} outcome;

typedef struct job {
    int rank, size;
    sinter_mpi_domain *d; /* NULL: without domain operations */
    int misplaced;        /* each rank adds the particles of the slabs moved by +2R */
    uint64_t migrated;
    double end_time;
    outcome *out;
    int setup_failed;
    sinter_status status;
    char message[512];
} job;

static void place(size_t p, double x[3], double *r)
{
    const size_t i = p / (NY * NZ), j = (p / NZ) % NY, k = p % NZ;
    x[0] = (1 + 2 * (double)i) * R;
    x[1] = (1 + 2 * (double)j) * R;
    x[2] = (1 + 2 * (double)k) * R;
    if (FLOAT && k == NZ - 1) /* 0.5 R from the layer below and from the x and y planes */
        for (size_t d = 0; d < 3; ++d)
            x[d] += 0.5 * R;
    *r = R * (1.0 + 2e-3 * (double)((p * 7919u) % 97u) / 96.0);
}

static uint64_t id_of(size_t p)
{
    return 1 + (uint64_t)((p * 37u) % N); /* 37 is prime to 72 */
}

static const double X0 = 0.0, X1 = 2.0 * NX * 25e-6;

static int slab_of(double x, int size)
{
    int r = (int)floor((x - X0) / ((X1 - X0) / size));
    return r < 0 ? 0 : r >= size ? size - 1 : r;
}

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->setup_failed = __LINE__;                                                            \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void collect(job *j, sinter_particles *ps, sinter_stepper *st)
{
    size_t owned = 0;
    const uint64_t *id = NULL;
    const double *x = NULL, *rot = NULL;
    sinter_snapshot *snap = NULL;
    sinter_sintering_stats ss;
    memset(&ss, 0, sizeof(ss));
    ss.struct_size = sizeof(ss);
    /* collective: every rank calls it */
    if (sinter_stepper_sintering_stats(st, &ss) != SINTER_OK)
        j->setup_failed = __LINE__;
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    if (sinter_stepper_get_stats(st, &stats) != SINTER_OK ||
        sinter_particles_owned_count(ps, &owned) != SINTER_OK ||
        sinter_snapshot_create(&snap, st) != SINTER_OK) {
        j->setup_failed = __LINE__;
        return;
    }
    outcome *o = j->out;
    o->owned = owned;
    {
        size_t n = 0;
        sinter_particles_count(ps, &n);
        o->ghosts = n - owned;
    }
    if (sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_ROTATION, (const void **)&rot, NULL, NULL))
        j->setup_failed = __LINE__;
    for (size_t i = 0; i < owned && id != NULL && x != NULL && rot != NULL; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(o->x + 3 * k, x + 3 * i, 24);
        memcpy(o->rot + 3 * k, rot + 3 * i, 24);
        o->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_ROTATION);
    size_t m = 0;
    const void *a = NULL, *b = NULL, *neck = NULL, *appr = NULL;
    if (sinter_snapshot_counts(snap, NULL, NULL, &m, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &a, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &b, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &neck, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &appr, NULL, NULL, NULL) ||
        o->links + m > MAX_LINKS)
        j->setup_failed = __LINE__;
    for (size_t k = 0; k < m && !j->setup_failed; ++k, ++o->links) {
        o->link_a[o->links] = ((const uint64_t *)a)[k];
        o->link_b[o->links] = ((const uint64_t *)b)[k];
        o->neck[o->links] = ((const double *)neck)[k];
        o->approach[o->links] = ((const double *)appr)[k];
    }
    sinter_snapshot_destroy(snap);
    const double v[11] = {ss.neck_mean,
                          ss.neck_min,
                          ss.neck_max,
                          ss.neck_ratio_mean,
                          ss.shrinkage[0],
                          ss.shrinkage[1],
                          ss.shrinkage[2],
                          ss.relative_density,
                          ss.coordination,
                          (double)ss.links,
                          (double)ss.pcg_iterations};
    memcpy(o->stats, v, sizeof(v)); /* the same on every rank */
    o->steps = stats.steps;
}

static void run(job *j)
{
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(sinter_material_create(&mat, ctx, "copper")); /* neck data: the defaults (copper) */
    TRY(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 72e9));
    TRY(sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3));
    TRY(sinter_material_set(mat, SINTER_MAT_DENSITY, 8960));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    TRY(sinter_stepper_set_option(st, "qs_strategy", 2));
    TRY(sinter_stepper_set_option(st, "qs_solve_rtol", SOLVE_RTOL));
    TRY(sinter_stepper_set_skin(st, 0.5 * R));
    TRY(sinter_stepper_set_dt(st, 1e-3)); /* the first global step [s] */
    const double shift = j->misplaced ? 2.0 * R : 0.0;
    for (size_t p = 0; p < N; ++p) {
        double x[3], r;
        place(p, x, &r);
        if (j->d != NULL && slab_of(x[0] - shift, j->size) != j->rank)
            continue;
        const uint64_t id = id_of(p);
        TRY(sinter_particles_add_with_ids(ps, 1, &id, x, &r, 0, 1293.0, NULL));
    }
    if (j->d != NULL)
        j->status = sinter_mpi_attach(j->d, st, ps, 0);
    if (j->status == SINTER_OK)
        j->status = sinter_stepper_step(st, 1);
    if (j->status == SINTER_OK)
        j->status = sinter_stepper_step(st, STEPS - 1);
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
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
}

static double rel_diff(const double *a, const double *b, size_t n)
{
    double worst = 0.0, scale = 0.0;
    for (size_t i = 0; i < n; ++i)
        scale = fmax(scale, fabs(a[i]));
    for (size_t i = 0; i < n; ++i)
        worst = fmax(worst, fabs(a[i] - b[i]));
    return scale > 0.0 ? worst / scale : worst;
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

static sinter_mpi_domain *make_domain(int size)
{
    sinter_mpi_options o;
    sinter_mpi_options_init(&o, sizeof o);
    o.decomposition = SINTER_MPI_DECOMP_BRICK;
    const int grid[3] = {size, 1, 1};
    const double lo[3] = {X0, -R, -R}, hi[3] = {X1, (2 * NY + 1) * R, (2 * NZ + 1) * R};
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK);
    return d;
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
    CHECK(MINE.owned >= NY * NZ && MINE.ghosts >= NY * NZ);
    double ua[3 * N], ub[3 * N], umax = 0.0, rot = 0.0;
    for (size_t k = 0; k < N; ++k) { /* the displacements, by id */
        double x[3], r;
        place(k, x, &r);
        const size_t i = (size_t)id_of(k) - 1;
        for (size_t c = 0; c < 3; ++c) {
            ua[3 * i + c] = REF.x[3 * i + c] - x[c];
            ub[3 * i + c] = X_ALL[3 * i + c] - x[c];
        }
    }
    for (size_t i = 0; i < 3 * N; ++i) {
        umax = fmax(umax, fabs(ua[i]));
        rot = fmax(rot, R * fabs(REF.rot[i] - ROT_ALL[i]));
    }
    const double e[6] = {rel_diff(REF.x, X_ALL, 3 * N),
                         rel_diff(ua, ub, 3 * N),
                         rot / umax,
                         rel_diff(REF.neck, NECK, REF.links),
                         rel_diff(REF.approach, APPROACH, REF.links),
                         rel_diff(REF.stats, MINE.stats, 9)};
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

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    test_lattice(rank, size, 0);
    if (size > 1)
        test_lattice(rank, size, 1);
    const int failed = mpi_check_finish("test_mpi_qs");
    MPI_Finalize();
    return failed;
}
