/*
 * libsinter_mpi's domain installed as the stepper's collective operations (issue 44,
 * sinter_mpi_attach), under mpiexec on 1 to 4 ranks. The bed of tests/unit/test_domain.c:
 * 288 spheres (Hertz-Mindlin with friction, damping and rolling resistance, gravity,
 * conduction, five walls, a small skin: a rebuild every few steps) on a brick of x slabs whose
 * borders lie on columns of the lattice, so that the particles jiggling about them migrate.
 * Rank 0 fills the set alone and sinter_mpi_distribute hands the particles to their ranks (or
 * every rank adds those sinter_mpi_decomp_owners gives it: the same bits).
 *
 *  - np 1: the same bits as the run without domain operations (nothing summed in another
 *    order: the domain's exchanges are with no one).
 *  - np 2-4: every particle owned once; displacements, velocities, spins, temperature changes,
 *    wall forces and the conduction's energy within 1e-10 relative of the single-domain run
 *    (pairs across a border are summed in another order: round-off grown by 150 steps of stiff
 *    contacts; test_domain.c's argument), the wall forces the same bits on every rank; and the
 *    same bits as the thread transport of the tests (domain_loopback.c) on as many slabs, run
 *    here on rank 0 (both take ghosts and arrivals in ascending rank order, each rank's in its
 *    index order, and reduce through the same exact sums).
 *  - The statistics: migrations happened (np >= 2), ghosts exist, the bytes sent over all ranks
 *    equal the bytes received, and at every step without a rebuild each rank received exactly
 *    13 doubles per ghost per halo.
 *  - The halo callback itself, forward and reverse, on the last rebuild's ghosts (the explicit
 *    step uses the forward one only): ids arrive in the right ghost rows, and the reverse adds
 *    one per ghost into its owner and zeroes the ghost rows.
 *  - A NaN force made on the rank that owns one particle at step 37 stops every rank at step 37
 *    with SINTER_ERR_UNSTABLE and the same message, naming that rank's subdomain (no hang:
 *    ctest's timeout).
 *  - With rebalancing on (SINTER_MPI_ATTACH_BALANCE, threshold 1): the decomposition becomes a
 *    bisection and the run still equals the single-domain one within 1e-10.
 */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_mpi.h>
#include <sinter_submodel.h>

#include "../unit/domain_bed.h"
#include "../unit/domain_lattice_bed.h"
#include "../unit/domain_loopback.h"
#include "mpi/attach.h" /* (the installed halo callback, called directly below) */
#include "mpi/domain.h"
#include "mpi_check.h"

enum { NW = 5, STEPS = 150, POISON_STEP = 37 };
static const double DT = 2e-6;

/* The final state by id - 1 (each run writes its owned particles' slots). */
typedef struct state {
    double x[3 * N], v[3 * N], w[3 * N], temp[N];
    int seen[N];
    double wall[3 * NW], energy;
    uint64_t builds;
    sinter_status status;
    int failed_at;
    char message[256];
    sinter_mpi_exchange_stats xs;    /* the MPI runs' exchange counters at the end */
    int quiet_steps, counter_errors; /* steps without a rebuild; counters not as predicted */
    int halo_errors;                 /* check_halos' */
} state;

/* How a run is decomposed: alone, one thread of the loopback, or one rank of an MPI domain. */
typedef struct run_spec {
    loopback *lb;         /* the thread transport, or NULL */
    int rank, size;       /* the loopback's subdomain and count */
    sinter_mpi_domain *d; /* an MPI domain, or NULL */
    int attach_flags;
    int keep_own;       /* MPI: every rank adds the particles its part holds (no distribution) */
    uint64_t poison_id; /* 0: none */
    state *out;
    int failed; /* a setup line */
} run_spec;

static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            spec->failed = __LINE__;                                                               \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void copy_owned(sinter_particles *ps, state *out)
{
    size_t owned = 0;
    const uint64_t *id = NULL;
    const double *x = NULL, *v = NULL, *w = NULL, *t = NULL;
    sinter_particles_owned_count(ps, &owned);
    if (owned == 0)
        return;
    if (sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_SPIN, (const void **)&w, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&t, NULL, NULL))
        return;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(out->x + 3 * k, x + 3 * i, 24);
        memcpy(out->v + 3 * k, v + 3 * i, 24);
        memcpy(out->w + 3 * k, w + 3 * i, 24);
        out->temp[k] = t[i];
        out->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    sinter_particles_release(ps, SINTER_FIELD_SPIN);
    sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
}

/* The halo callback in both directions, on the ghosts of the last rebuild: forward, one
 * column holding each owned row's id, must bring every ghost row its own particle's id;
 * reverse, ghost rows of 1, must add to each owned row the number of ranks holding it as a
 * ghost (summed over the ranks: the number of ghosts) and zero the ghost rows. */
static int check_halos(sinter_mpi_domain *d, sinter_particles *ps, int *errors)
{
    size_t owned = 0, count = 0;
    const uint64_t *id = NULL;
    if (sinter_particles_owned_count(ps, &owned) != SINTER_OK ||
        sinter_particles_count(ps, &count) != SINTER_OK)
        return -1;
    double *data = calloc(2 * count + 2, sizeof(double));
    if (data == NULL || (count > 0 && sinter_particles_view_read(ps, SINTER_FIELD_ID,
                                                                 (const void **)&id, NULL, NULL)))
        return -1;
    for (size_t i = 0; i < owned; ++i)
        data[2 * i + 1] = (double)id[i];
    sinter_halo h = {.struct_size = sizeof h,
                     .direction = SINTER_HALO_FORWARD,
                     .width = 2,
                     .data = data,
                     .id = id,
                     .owned = owned,
                     .ghosts = count - owned};
    int rc = d->attached->ops.halo(&h, d->attached);
    for (size_t i = owned; i < count; ++i)
        *errors += data[2 * i + 1] != (double)id[i];
    for (size_t i = 0; i < count; ++i)
        data[2 * i] = i < owned ? 0.0 : 1.0;
    h.direction = SINTER_HALO_REVERSE;
    rc |= d->attached->ops.halo(&h, d->attached);
    uint64_t sums[2] = {0, count - owned}; /* ghosts counted by their owners, and held */
    for (size_t i = 0; i < count; ++i) {
        if (i < owned)
            sums[0] += (uint64_t)data[2 * i];
        else
            *errors += data[2 * i] != 0.0;
    }
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    *errors += sums[0] != sums[1];
    if (count > 0)
        sinter_particles_release(ps, SINTER_FIELD_ID);
    free(data);
    return rc;
}

static void *run_bed(void *arg)
{
    run_spec *spec = arg;
    state *out = spec->out;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL, *host = NULL;
    sinter_heat_model *cond = NULL;
    poison p = {NULL, 0, 0.0};
    int mpi_rank = 0;
    if (spec->d != NULL)
        sinter_mpi_domain_rank(spec->d, &mpi_rank, NULL);
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(domain_bed_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_bed_walls(ctx, mat, LX, LY, &walls));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "thread_choice", 0));
    TRY(domain_bed_models(ctx, st, &gravity, &contact, &cond));
    for (int k = 0; k < N; ++k) {
        /* the loopback: each subdomain its slab; MPI: rank 0 all of them (distributed below),
         * or each rank those of its part */
        int part = 0;
        if (spec->d != NULL && spec->keep_own) {
            const sinter_mpi_decomp *decomp = NULL;
            TRY(sinter_mpi_domain_decomp(spec->d, &decomp));
            TRY(sinter_mpi_decomp_owners(decomp, BED.x + 3 * k, 1, &part));
        }
        if ((spec->lb != NULL && slab_of(BED.x[3 * k], spec->size) != spec->rank) ||
            (spec->d != NULL && part != mpi_rank))
            continue;
        TRY(domain_bed_add(ps, BED.id[k], BED.x + 3 * k, R, BED.temp[k], BED.v + 3 * k,
                           BED.w + 3 * k));
    }
    if (spec->poison_id != 0) { /* on every rank: migration needs the same force models */
        p = (poison){ps, spec->poison_id, (POISON_STEP - 0.5) * DT};
        const sinter_force_callbacks cb = {.struct_size = sizeof(cb), .particles = poison_force};
        TRY(sinter_force_model_create_host(&host, ctx, "poison", &cb, &p));
        TRY(sinter_stepper_add_force(st, host));
    }
    TRY(sinter_stepper_set_dt(st, DT));
    TRY(sinter_stepper_set_skin(st, 1e-5));
    if (spec->lb != NULL)
        TRY(loopback_attach(spec->lb, spec->rank, st, ps));
    if (spec->d != NULL) {
        TRY(sinter_mpi_attach(spec->d, st, ps, spec->attach_flags));
        if (!spec->keep_own)
            TRY(sinter_mpi_distribute(spec->d));
    }
    out->status = SINTER_OK;
    sinter_mpi_exchange_stats before = {.struct_size = sizeof before}, after = before;
    if (spec->d != NULL)
        TRY(sinter_mpi_get_exchange_stats(spec->d, &before));
    for (int k = 1; k <= STEPS; ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (s != SINTER_OK) {
            out->status = s;
            out->failed_at = k;
            snprintf(out->message, sizeof(out->message), "%s", sinter_last_error(ctx));
            break;
        }
        if (spec->d == NULL)
            continue;
        /* the counters of a step without a rebuild: its halos (forward only, the explicit
         * step's state rows) received 13 doubles per ghost, sent 13 per row a neighbour
         * holds, in one message per neighbour that has rows to send */
        TRY(sinter_mpi_get_exchange_stats(spec->d, &after));
        if (after.redistributions == before.redistributions) {
            const uint64_t halos = after.halos - before.halos;
            out->quiet_steps++;
            out->counter_errors += halos < 1 || after.bytes_received - before.bytes_received !=
                                                    halos * after.ghosts * 13 * sizeof(double);
        }
        before = after;
    }
    if (spec->d != NULL && out->status == SINTER_OK && check_halos(spec->d, ps, &out->halo_errors))
        out->halo_errors++;
    copy_owned(ps, out);
    for (int k = 0; k < NW; ++k)
        TRY(sinter_walls_get_force(walls, (size_t)k, out->wall + 3 * k));
    TRY(sinter_stepper_heat_energy_global(st, 0, &out->energy));
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    TRY(sinter_stepper_get_stats_global(st, &stats));
    out->builds = stats.neighbor_builds;
    if (spec->d != NULL) {
        out->xs.struct_size = sizeof out->xs;
        TRY(sinter_mpi_get_exchange_stats(spec->d, &out->xs));
    }
done:
    if (spec->failed)
        fprintf(stderr, "setup failed at line %d: %s\n", spec->failed, sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(gravity);
    sinter_force_model_destroy(contact);
    sinter_force_model_destroy(host);
    sinter_heat_model_destroy(cond);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The loopback's run on `size` subdomains (threads of this rank), merged into one state. */
static void run_loopback(int size, state *out)
{
    static state parts[LOOPBACK_MAX];
    loopback *lb = loopback_create(size);
    CHECK(lb != NULL);
    if (lb == NULL)
        return;
    loopback_set_slabs(lb, X0, X1);
    pthread_t threads[LOOPBACK_MAX];
    run_spec specs[LOOPBACK_MAX];
    for (int r = 0; r < size; ++r) {
        memset(&parts[r], 0, sizeof parts[r]);
        specs[r] = (run_spec){.lb = lb, .rank = r, .size = size, .out = &parts[r]};
        CHECK(pthread_create(&threads[r], NULL, run_bed, &specs[r]) == 0);
    }
    memset(out, 0, sizeof *out);
    for (int r = 0; r < size; ++r) {
        pthread_join(threads[r], NULL);
        CHECK(specs[r].failed == 0);
        for (int k = 0; k < N; ++k)
            if (parts[r].seen[k]) {
                memcpy(out->x + 3 * k, parts[r].x + 3 * k, 24);
                memcpy(out->v + 3 * k, parts[r].v + 3 * k, 24);
                memcpy(out->w + 3 * k, parts[r].w + 3 * k, 24);
                out->temp[k] = parts[r].temp[k];
                out->seen[k] += parts[r].seen[k];
            }
    }
    out->status = parts[0].status;
    memcpy(out->wall, parts[0].wall, sizeof out->wall);
    out->energy = parts[0].energy;
    loopback_destroy(lb);
}

/* Every rank's owned particles gathered into `all` on every rank (each slot written by one). */
static void gather(const state *mine, state *all)
{
    *all = *mine;
    double *bufs[4] = {all->x, all->v, all->w, all->temp};
    const int counts[4] = {3 * N, 3 * N, 3 * N, N};
    /* a slot is non-zero on one rank only: a sum of it and zeros is its bits (-0 aside) */
    for (int b = 0; b < 4; ++b)
        MPI_Allreduce(MPI_IN_PLACE, bufs[b], counts[b], MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, all->seen, N, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
}

static double rel_diff(const double *a, const double *b, size_t n)
{
    double d = 0.0, m = 0.0;
    for (size_t k = 0; k < n; ++k) {
        d = fmax(d, fabs(a[k] - b[k]));
        m = fmax(m, fabs(b[k]));
    }
    return m > 0.0 ? d / m : d;
}

/* Displacements and temperature changes (what the comparison sees) of a state, by id. */
static void changes(const state *s, double *dx, double *dt)
{
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)BED.id[k] - 1;
        for (int d = 0; d < 3; ++d)
            dx[3 * i + d] = s->x[3 * i + d] - BED.x[3 * k + d];
        dt[i] = s->temp[i] - BED.temp[k];
    }
}

/* x slabs over [X0, X1) (the loopback's), or with `tall` z slabs over a box three times the
 * bed's height (the bed in its bottom third, as after a pour). */
static sinter_mpi_domain *make_domain(int size, int tall, int rcb)
{
    sinter_mpi_options o;
    sinter_mpi_options_init(&o, sizeof o);
    o.decomposition = rcb ? SINTER_MPI_DECOMP_RCB : SINTER_MPI_DECOMP_BRICK;
    const int grid[3] = {tall ? 1 : size, 1, tall ? size : 1};
    const double lo[3] = {X0, -A, tall ? 0.0 : -A},
                 hi[3] = {X1, LY + A, tall ? 3 * A * NZ : A * (NZ + 1)};
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK);
    return d;
}

static state REF, MINE, ALL, LOOP;

/* The bed through MPI against the single-domain run (and the loopback's, same slabs). */
static void test_bed(int rank, int size, int flags, int tall, int rcb)
{
    memset(&MINE, 0, sizeof MINE);
    sinter_mpi_domain *d = make_domain(size, tall, rcb);
    run_spec spec = {.d = d, .attach_flags = flags, .out = &MINE};
    run_bed(&spec);
    CHECK(spec.failed == 0);
    CHECK(MINE.status == SINTER_OK);
    if (MINE.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, MINE.message);
    sinter_mpi_exchange_stats xs;
    xs.struct_size = sizeof xs;
    /* (the stepper is gone: its statistics went with it) */
    CHECK(sinter_mpi_get_exchange_stats(d, &xs) == SINTER_ERR_STATE);
    /* the counters: over all ranks, what was sent was received; migrations when np > 1 */
    uint64_t c[6] = {MINE.xs.bytes_sent,  MINE.xs.bytes_received, MINE.xs.migrated_out,
                     MINE.xs.migrated_in, MINE.xs.ghosts,         MINE.xs.redistributions};
    MPI_Allreduce(MPI_IN_PLACE, c, 5, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(c[0] == c[1] && c[2] == c[3]);
    /* (z slabs without balancing leave the bed on the bottom rank(s): at np 2 and 3 on one) */
    if (!tall || flags)
        CHECK(size == 1 ? c[2] == 0 && c[4] == 0 : c[2] > 0 && c[4] > 0);
    CHECK(MINE.xs.redistributions == MINE.builds);
    CHECK(MINE.quiet_steps > 100 && MINE.counter_errors == 0);
    CHECK(MINE.halo_errors == 0);
    CHECK(MINE.xs.owned > 0 || size > 1);
    if (rank == 0)
        printf("np %d%s: %llu redistributions, %llu migrations, %llu ghosts now, %llu bytes sent "
               "(all ranks), %d neighbours of rank 0, imbalance %.3f\n",
               size, flags ? " (balanced)" : "", (unsigned long long)MINE.xs.redistributions,
               (unsigned long long)c[2], (unsigned long long)c[4], (unsigned long long)c[0],
               MINE.xs.neighbours, MINE.xs.imbalance);
    gather(&MINE, &ALL);
    for (int k = 0; k < N; ++k)
        CHECK(ALL.seen[k] == 1);
    CHECK(same_on_every_rank(MINE.wall, (int)sizeof MINE.wall));
    CHECK(same_on_every_rank(&MINE.energy, (int)sizeof MINE.energy));
    CHECK(MINE.builds == REF.builds);
    sinter_mpi_stats ms;
    ms.struct_size = sizeof ms;
    CHECK(sinter_mpi_get_stats(d, &ms) == SINTER_OK);
    if (tall && size > 1) {
        /* the imbalance (largest owned count over the mean) at the last rebuild: z slabs over a
         * box three times the bed's height leave the top part(s) empty (about 2 at np 2, 3 at
         * np 3 and 4); rebalanced at the first rebuild, it stays below the threshold 1.1 */
        if (rank == 0)
            printf("np %d, z slabs%s: imbalance %.3f, %llu rebalances\n", size,
                   flags ? " (balanced)"
                   : rcb ? " (an RCB domain)"
                         : "",
                   MINE.xs.imbalance, (unsigned long long)ms.rebalances);
        CHECK(flags || rcb ? MINE.xs.imbalance <= 1.1 && ms.rebalances >= 1
                           : MINE.xs.imbalance >= 1.9 && ms.rebalances == 0);
    }
    if (size == 1 && flags == 0) { /* the same bits */
        CHECK(memcmp(ALL.x, REF.x, sizeof REF.x) == 0);
        CHECK(memcmp(ALL.v, REF.v, sizeof REF.v) == 0);
        CHECK(memcmp(ALL.w, REF.w, sizeof REF.w) == 0);
        CHECK(memcmp(ALL.temp, REF.temp, sizeof REF.temp) == 0);
        CHECK(memcmp(MINE.wall, REF.wall, sizeof REF.wall) == 0);
    }
    static double dx[3 * N], dxr[3 * N], dtm[N], dtr[N];
    changes(&ALL, dx, dtm);
    changes(&REF, dxr, dtr);
    const double ex = rel_diff(dx, dxr, 3 * N), ev = rel_diff(ALL.v, REF.v, 3 * N),
                 ew = rel_diff(ALL.w, REF.w, 3 * N), et = rel_diff(dtm, dtr, N),
                 ef = rel_diff(MINE.wall, REF.wall, 3 * NW),
                 ee = fabs(MINE.energy - REF.energy) / fabs(REF.energy);
    if (rank == 0)
        printf("np %d%s%s: displacements %.2g, velocities %.2g, spins %.2g, temperatures %.2g, "
               "wall forces %.2g, energy %.2g (relative); %llu builds\n",
               size, tall ? ", z slabs" : "",
               flags ? " (balanced)"
               : rcb ? " (an RCB domain)"
                     : "",
               ex, ev, ew, et, ef, ee, (unsigned long long)MINE.builds);
    CHECK(ex <= 1e-10 && ev <= 1e-10 && ew <= 1e-10 && et <= 1e-10 && ef <= 1e-10 && ee <= 1e-10);
    if (rank == 0 && flags == 0 && !tall &&
        size <= LOOPBACK_MAX) { /* the thread transport's bits */
        run_loopback(size, &LOOP);
        const int same = memcmp(ALL.x, LOOP.x, sizeof LOOP.x) == 0 &&
                         memcmp(ALL.v, LOOP.v, sizeof LOOP.v) == 0 &&
                         memcmp(ALL.w, LOOP.w, sizeof LOOP.w) == 0 &&
                         memcmp(ALL.temp, LOOP.temp, sizeof LOOP.temp) == 0 &&
                         memcmp(MINE.wall, LOOP.wall, sizeof LOOP.wall) == 0;
        printf("np %d: %s the loopback's bits on %d slabs\n", size,
               same ? "equals" : "DIFFERS from", size);
        CHECK(same);
    }
    sinter_mpi_domain_destroy(d);
    if (flags == 0 && !tall) { /* every rank keeps its own: the same particles in the same order */
        static state own, own_all;
        memset(&own, 0, sizeof own);
        d = make_domain(size, 0, 0);
        run_spec keep = {.d = d, .keep_own = 1, .out = &own};
        run_bed(&keep);
        CHECK(keep.failed == 0 && own.status == SINTER_OK);
        gather(&own, &own_all);
        CHECK(memcmp(own_all.x, ALL.x, sizeof ALL.x) == 0 &&
              memcmp(own_all.v, ALL.v, sizeof ALL.v) == 0 &&
              memcmp(own_all.temp, ALL.temp, sizeof ALL.temp) == 0);
        CHECK(memcmp(own.wall, MINE.wall, sizeof MINE.wall) == 0);
        sinter_mpi_domain_destroy(d);
    }
}

/* A NaN on one rank stops every rank at the same step with the same error. */
static void test_nan(int rank, int size)
{
    memset(&MINE, 0, sizeof MINE);
    sinter_mpi_domain *d = make_domain(size, 0, 0);
    const uint64_t victim = BED.id[N / 2 + 3]; /* (in the middle of the bed) */
    run_spec spec = {.d = d, .poison_id = victim, .out = &MINE};
    run_bed(&spec);
    CHECK(MINE.status == SINTER_ERR_UNSTABLE);
    CHECK(MINE.failed_at == POISON_STEP);
    CHECK(same_on_every_rank(&MINE.status, (int)sizeof MINE.status));
    CHECK(same_on_every_rank(&MINE.failed_at, (int)sizeof MINE.failed_at));
    CHECK(same_on_every_rank(MINE.message, (int)sizeof MINE.message));
    char id[32];
    snprintf(id, sizeof id, "%llu", (unsigned long long)victim);
    CHECK(strstr(MINE.message, id) != NULL);
    if (rank == 0)
        printf("np %d: NaN at step %d on every rank: %s\n", size, MINE.failed_at, MINE.message);
    sinter_mpi_domain_destroy(d);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    make_bed();
    run_spec ref = {.out = &REF}; /* every rank runs the reference alone */
    run_bed(&ref);
    CHECK(ref.failed == 0 && REF.status == SINTER_OK);
    CHECK(REF.builds >= 3);
    test_bed(rank, size, 0, 0, 0);
    if (size > 1) {
        test_bed(rank, size, SINTER_MPI_ATTACH_BALANCE, 0, 0);
        test_bed(rank, size, 0, 1, 0);
        test_bed(rank, size, SINTER_MPI_ATTACH_BALANCE, 1, 0);
        test_bed(rank, size, 0, 1, 1); /* an RCB domain balances without the flag */
    }
    test_nan(rank, size);
    const int rc = mpi_check_finish("test_mpi_attach");
    MPI_Finalize();
    return rc;
}
