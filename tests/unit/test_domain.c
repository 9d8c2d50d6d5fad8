/*
 * libsinter on subdomains of a decomposition owned by the host (issue 43, include/
 * sinter_domain.h), run through the thread transport of domain_loopback.h: 1 to 4 subdomains
 * as threads of one process, slabs along x.
 *
 *  - A bed of 288 spheres (Hertz-Mindlin with friction, damping and rolling resistance,
 *    gravity, conduction, five walls) on 1, 2, 3 and 4 subdomains equals the single-domain
 *    run: on one subdomain bit for bit (nothing is summed in another order), on more within
 *    1e-10 relative, with the wall forces identical on every subdomain.
 *    Particles jiggling about the borders migrate (export/import with their histories).
 *  - The same bed on 3 and 4 slabs of which it fills two: the empty subdomains take part in
 *    every collective step with nothing to add, and the run equals the single-domain one.
 *  - A contact sliding across a subdomain border keeps its tangential spring, before and after
 *    the driven sphere migrates: equal to the single-domain run to 1e-12 of its largest force,
 *    and the same bits on both sides; a sphere sliding on a wall across the border keeps its
 *    wall contact's spring through its migration.
 *  - A NaN made on one subdomain stops all of them at the same step with the same status and
 *    message, which names the subdomain and the particle's id (no hang: ctest's timeout).
 *  - A step rejected right after a migration restores every particle, arrivals included.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>
#include <sinter_submodel.h>

#include "domain_bed.h"
#include "domain_lattice_bed.h"
#include "domain_loopback.h"
#include "rel_diff.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

enum { NW = 5, STEPS = 150 };

/* The upper end of the slabs' range: X1, except in the test of an empty subdomain. */
static double SLAB_X1 = R + 10 * A;

/* The subdomain of a particle at x among `size` slabs (the loopback's rule). */
static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (SLAB_X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* One subdomain's run of the bed and what it leaves: its owned particles' state by id. */
typedef struct job {
    int rank, size;
    loopback *lb; /* NULL: a run without domain operations */
    int steps;
    uint64_t poison_id; /* 0: none */
    int poison_step;    /* the step (from 1) whose evaluation makes the NaN */
    int stop_step;      /* > 0: one advance, which this subdomain's observer stops after the
                           step stop_step (0: steps one by one) */
    double end_time;    /* the time it ended at [s] */
    double energy;      /* the conduction's energy into the particles, all subdomains [J] */
    /* results */
    int setup_failed;
    sinter_status status;
    int failed_at; /* the step that failed (from 1), 0: none */
    char message[512];
    double wall[3 * NW], wall_local[3 * NW];
    uint64_t builds, contacts;
    size_t owned;
    uint64_t migrated;           /* particles it sent to other subdomains */
    uint64_t sent[STEPS + 1];    /* particles it sent by the end of each step (from 1) */
    uint64_t reduces[STEPS + 1]; /* its reduce calls by the end of each step (from 1) */
    uint64_t built[STEPS + 1];   /* its neighbour builds by the end of each step (from 1) */
} job;

/* Final state by id - 1 (each subdomain writes the slots of its owned particles). */
typedef struct state {
    double x[3 * N], v[3 * N], w[3 * N], temp[N];
    int seen[N];
} state;

typedef struct job_and_state {
    job *j;
    state *out;
} job_and_state;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->setup_failed = __LINE__;                                                            \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void copy_owned(sinter_particles *ps, size_t owned, state *out)
{
    const uint64_t *id = NULL;
    const double *x = NULL, *v = NULL, *w = NULL, *t = NULL;
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

/* An observer that stops the run from time `*user` on. */
static int stop_after(const sinter_stepper *st, double time, void *user)
{
    (void)st;
    return time >= *(const double *)user;
}

static void *run_bed(void *arg)
{
    job_and_state *js = arg;
    job *j = js->j;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL, *host = NULL;
    sinter_heat_model *cond = NULL;
    poison p = {NULL, 0, 0.0};
    const double dt = 2e-6;
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
        if (slab_of(BED.x[3 * k], j->size) != j->rank)
            continue;
        TRY(domain_bed_add(ps, BED.id[k], BED.x + 3 * k, R, BED.temp[k], BED.v + 3 * k,
                           BED.w + 3 * k));
    }
    if (j->poison_id != 0) { /* on every subdomain: migration needs the same force models */
        p = (poison){ps, j->poison_id, (j->poison_step - 0.5) * dt};
        const sinter_force_callbacks cb = {.struct_size = sizeof(cb), .particles = poison_force};
        TRY(sinter_force_model_create_host(&host, ctx, "poison", &cb, &p));
        TRY(sinter_stepper_add_force(st, host));
    }
    TRY(sinter_stepper_set_dt(st, dt));
    TRY(sinter_stepper_set_skin(st, 1e-5)); /* rebuilds (and redistributions) every few steps */
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    j->status = SINTER_OK;
    const double stop_time = (j->stop_step - 0.5) * dt;
    if (j->stop_step > 0 && j->rank == j->size - 1)
        TRY(sinter_stepper_set_observer(st, stop_after, (void *)&stop_time));
    if (j->stop_step > 0)
        j->status = sinter_stepper_advance(st, j->steps * dt);
    for (int k = 1; k <= j->steps && j->stop_step == 0; ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (j->lb != NULL && k <= STEPS) { /* (its own counters: written by this thread) */
            j->sent[k] = loopback_migrated(j->lb, j->rank);
            uint64_t calls[3];
            loopback_counts(j->lb, j->rank, calls);
            j->reduces[k] = calls[0];
            sinter_stepper_stats local = {.struct_size = sizeof(local)};
            if (sinter_stepper_get_stats(st, &local) == SINTER_OK)
                j->built[k] = local.neighbor_builds;
        }
        if (s != SINTER_OK) {
            j->status = s;
            j->failed_at = k;
            snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
            break;
        }
    }
    TRY(sinter_stepper_time(st, &j->end_time));
    TRY(sinter_particles_owned_count(ps, &j->owned));
    TRY(sinter_stepper_heat_energy_global(st, 0, &j->energy));
    copy_owned(ps, j->owned, js->out);
    for (int k = 0; k < NW; ++k) {
        TRY(sinter_walls_get_force(walls, (size_t)k, j->wall + 3 * k));
        TRY(sinter_walls_get_force_local(walls, (size_t)k, j->wall_local + 3 * k));
    }
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    TRY(sinter_stepper_get_stats_global(st, &stats));
    j->builds = stats.neighbor_builds;
    j->contacts = stats.contacts;
done:
    if (j->setup_failed && j->lb != NULL)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
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

/* The bed on `size` subdomains (0: one run without domain operations). */
static void run_decomposed_stop(int size, int steps, uint64_t poison_id, int poison_step,
                                int stop_step, job *jobs, state *out);
static void run_decomposed(int size, int steps, uint64_t poison_id, int poison_step, job *jobs,
                           state *out)
{
    run_decomposed_stop(size, steps, poison_id, poison_step, 0, jobs, out);
}

static void run_decomposed_stop(int size, int steps, uint64_t poison_id, int poison_step,
                                int stop_step, job *jobs, state *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, X0, SLAB_X1);
    pthread_t threads[LOOPBACK_MAX];
    job_and_state js[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        memset(&jobs[r], 0, sizeof(job));
        jobs[r] = (job){.rank = r,
                        .size = n,
                        .lb = lb,
                        .steps = steps,
                        .poison_id = poison_id,
                        .poison_step = poison_step,
                        .stop_step = stop_step};
        js[r] = (job_and_state){&jobs[r], out};
        assert_int_equal(pthread_create(&threads[r], NULL, run_bed, &js[r]), 0);
    }
    for (int r = 0; r < n; ++r) {
        assert_int_equal(pthread_join(threads[r], NULL), 0);
        jobs[r].migrated = lb != NULL ? loopback_migrated(lb, r) : 0;
    }
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].setup_failed)
            print_error("subdomain %d: setup failed at line %d: %s\n", r, jobs[r].setup_failed,
                        jobs[r].message);
        assert_int_equal(jobs[r].setup_failed, 0);
    }
}

/* The bed's index of the particle with id k + 1. */
static int index_of(int k)
{
    for (int i = 0; i < N; ++i)
        if (BED.id[i] == (uint64_t)k + 1)
            return i;
    return -1;
}

static state REF, DEC;
static job REF_JOB[1], JOBS[LOOPBACK_MAX];

/* Reductions of one call of sinter_stepper_step(st, 1) without a rebuild (docs/scaleout.md):
 * the call's own three (its status agreed, the step's stability check agreed, whether the
 * forces are current) and the step's three: whether to go on, the status after the drift
 * together with the rebuild decision (stage A), and the status after the checks together
 * with the wall reactions (stage C). Before they were merged the step made six: the rebuild
 * decision, the commit's status and the reactions were reductions of their own (9 a call). */
enum { REDUCES_PER_CALL = 6 };

static void test_decomposed_bed(void **st)
{
    (void)st;
    make_bed();
    run_decomposed(0, STEPS, 0, 0, REF_JOB, &REF);
    assert_int_equal(REF_JOB[0].status, SINTER_OK);
    assert_true(REF_JOB[0].builds >= 3); /* the skin is small: the lists are rebuilt */
    double heated = 0.0; /* conduction works: temperatures change by more than round-off */
    for (int k = 0; k < N; ++k)
        heated = fmax(heated, fabs(REF.temp[k] - BED.temp[index_of(k)]));
    print_message("largest temperature change %.3g K\n", heated);
    assert_true(heated > 1e-6);
    double x0[3 * N], dref[3 * N]; /* displacements over the run: what the comparison sees */
    for (int k = 0; k < N; ++k)
        for (int d = 0; d < 3; ++d) {
            x0[3 * (BED.id[k] - 1) + d] = BED.x[3 * k + d];
            dref[3 * (BED.id[k] - 1) + d] = REF.x[3 * (BED.id[k] - 1) + d] - BED.x[3 * k + d];
        }
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run_decomposed(size, STEPS, 0, 0, JOBS, &DEC);
        size_t owned = 0;
        uint64_t migrated = 0;
        for (int r = 0; r < size; ++r) {
            if (JOBS[r].status != SINTER_OK)
                print_error("%d subdomains, subdomain %d: %s\n", size, r, JOBS[r].message);
            assert_int_equal(JOBS[r].status, SINTER_OK);
            owned += JOBS[r].owned;
            migrated += JOBS[r].migrated;
            /* the collective decisions: the same rebuilds everywhere, and the wall forces
             * reduced to the same bits on every subdomain */
            assert_int_equal(JOBS[r].builds, JOBS[0].builds);
            assert_memory_equal(JOBS[r].wall, JOBS[0].wall, sizeof(JOBS[r].wall));
            assert_true(JOBS[r].energy == JOBS[0].energy);
        }
        assert_int_equal(owned, N); /* every particle owned once, wherever it went */
        for (int k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1);
        /* The cost of the collective stages: a call of sinter_stepper_step(st, 1) without a
         * rebuild makes REDUCES_PER_CALL reductions on every subdomain (see there). */
        for (int r = 0; r < size; ++r)
            for (int k = 2; k <= STEPS; ++k)
                if (JOBS[r].built[k] == JOBS[r].built[k - 1]) {
                    const uint64_t calls = JOBS[r].reduces[k] - JOBS[r].reduces[k - 1];
                    if (calls != REDUCES_PER_CALL)
                        print_error("subdomain %d, step %d: %llu reductions\n", r, k,
                                    (unsigned long long)calls);
                    assert_int_equal(calls, REDUCES_PER_CALL);
                }
        print_message("%d subdomains: %llu migrations\n", size, (unsigned long long)migrated);
        assert_true(size == 1 ? migrated == 0 : migrated > 0); /* the borders were crossed */
        if (size == 1) { /* nothing summed in another order: the same bits */
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.v, REF.v, sizeof(REF.v));
            assert_memory_equal(DEC.w, REF.w, sizeof(REF.w));
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(JOBS[0].wall, REF_JOB[0].wall, sizeof(REF_JOB[0].wall));
            continue;
        }
        /* More subdomains sum a particle's contacts in another order (pairs across a border
         * are evaluated on both sides): round-off, 1e-16 relative per sum, grown by the
         * contacts' stiffness over 150 steps; 1e-10 relative bounds it with room. */
        double dx[3 * N];
        for (int k = 0; k < 3 * N; ++k)
            dx[k] = DEC.x[k] - x0[k];
        double tref[N], tdec[N]; /* the temperature changes: what conduction did */
        for (int k = 0; k < N; ++k) {
            tref[k] = REF.temp[k] - BED.temp[index_of(k)];
            tdec[k] = DEC.temp[k] - BED.temp[index_of(k)];
        }
        const double ex = rel_diff(dx, dref, 3 * N), ev = rel_diff(DEC.v, REF.v, 3 * N),
                     ew = rel_diff(DEC.w, REF.w, 3 * N), et = rel_diff(tdec, tref, N);
        const double ef = rel_diff(JOBS[0].wall, REF_JOB[0].wall, 3 * NW);
        /* the heat the walls (reservoirs) took, over every subdomain */
        const double ee = fabs(JOBS[0].energy - REF_JOB[0].energy) / fabs(REF_JOB[0].energy);
        print_message("  conduction's energy %.6g J (single domain %.6g J): %.2g relative\n",
                      JOBS[0].energy, REF_JOB[0].energy, ee);
        assert_true(fabs(REF_JOB[0].energy) > 0.0);
        assert_true(ee <= 1e-10);
        print_message("%d subdomains: displacements %.2g, velocities %.2g, spins %.2g, "
                      "temperatures %.2g, wall forces %.2g (relative); %llu builds\n",
                      size, ex, ev, ew, et, ef, (unsigned long long)JOBS[0].builds);
        assert_true(ex <= 1e-10);
        assert_true(ev <= 1e-10);
        assert_true(ew <= 1e-10);
        assert_true(et <= 1e-10);
        assert_true(ef <= 1e-10);
        /* the shares add up to the total (to the reduction's round-off) */
        for (int c = 0; c < 3 * NW; ++c) {
            double sum = 0.0, m = 0.0;
            for (int r = 0; r < size; ++r) {
                sum += JOBS[r].wall_local[c];
                m = fmax(m, fabs(JOBS[r].wall_local[c]));
            }
            assert_close(sum, JOBS[0].wall[c], 1e-14 * m * size + 1e-300);
        }
    }
}

/*
 * Subdomains that own no particle: the slabs cut [X0, X0 + 6 A size) into `size` slabs of 6 A,
 * so that the bed (x up to R + 7 A) fills the first two (their border on a lattice column,
 * crossed by migrations) and leaves the others empty from start to end. An empty subdomain
 * takes part in every collective operation with nothing to add; the run must equal the
 * single-domain one within 1e-10 relative (the round-off argument of test_decomposed_bed),
 * and under the sanitizers run clean (no zero-size copy from a NULL array).
 */
static void test_empty_subdomains(void **st)
{
    (void)st;
    make_bed();
    run_decomposed(0, STEPS, 0, 0, REF_JOB, &REF);
    assert_int_equal(REF_JOB[0].status, SINTER_OK);
    for (int size = 3; size <= LOOPBACK_MAX; ++size) {
        SLAB_X1 = X0 + 6 * A * size;
        run_decomposed(size, STEPS, 0, 0, JOBS, &DEC);
        SLAB_X1 = X1;
        size_t owned = 0;
        for (int r = 0; r < size; ++r) {
            if (JOBS[r].status != SINTER_OK)
                print_error("%d subdomains, subdomain %d: %s\n", size, r, JOBS[r].message);
            assert_int_equal(JOBS[r].status, SINTER_OK);
            assert_int_equal(JOBS[r].builds, JOBS[0].builds);
            assert_memory_equal(JOBS[r].wall, JOBS[0].wall, sizeof(JOBS[r].wall));
            owned += JOBS[r].owned;
        }
        for (int r = 2; r < size; ++r) /* empty to the end: nothing came in */
            assert_int_equal(JOBS[r].owned, 0);
        assert_true(JOBS[0].migrated + JOBS[1].migrated > 0); /* the border was crossed */
        assert_int_equal(owned, N);
        for (int k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1);
        double dx[3 * N], dref[3 * N], tref[N], tdec[N];
        for (int k = 0; k < N; ++k) {
            const int i = index_of(k);
            for (int d = 0; d < 3; ++d) {
                dx[3 * k + d] = DEC.x[3 * k + d] - BED.x[3 * i + d];
                dref[3 * k + d] = REF.x[3 * k + d] - BED.x[3 * i + d];
            }
            tref[k] = REF.temp[k] - BED.temp[i];
            tdec[k] = DEC.temp[k] - BED.temp[i];
        }
        const double ex = rel_diff(dx, dref, 3 * N), ev = rel_diff(DEC.v, REF.v, 3 * N),
                     ew = rel_diff(DEC.w, REF.w, 3 * N), et = rel_diff(tdec, tref, N),
                     ef = rel_diff(JOBS[0].wall, REF_JOB[0].wall, 3 * NW);
        print_message("%d subdomains, %d empty: displacements %.2g, velocities %.2g, spins "
                      "%.2g, temperatures %.2g, wall forces %.2g (relative)\n",
                      size, size - 2, ex, ev, ew, et, ef);
        assert_true(ex <= 1e-10);
        assert_true(ev <= 1e-10);
        assert_true(ew <= 1e-10);
        assert_true(et <= 1e-10);
        assert_true(ef <= 1e-10);
    }
}

/*
 * Two spheres pressed together (2 % overlap), both held (FIXED), the one of subdomain 0
 * driven along x at 0.5 m/s across the border x = XB into subdomain 1's slab, where the other
 * sits; friction high enough that the contact sticks, so the tangential spring grows with
 * the slip. While the driven sphere is on subdomain 0 each side evaluates the pair (newton
 * off) from its own history; once it crossed it migrates (with its history) to subdomain 1,
 * which then holds the pair alone. The force on each sphere, read from the subdomain that
 * owns it at that step, must follow the single-domain run step by step (to 1e-12 of the
 * largest: the same operations on the same bits; a spring lost at a rebuild or a migration
 * would drop to zero), and the two forces must be exactly opposite (one history, twice).
 *
 * The wall variant: one sphere pressed on the floor z = 0 (2 % overlap) driven the same way,
 * its wall contact's tangential spring carried by the migration (keyed by id and wall). It is
 * the only particle: subdomain 1 owns nothing (its set has no arrays yet) until the sphere
 * arrives, and subdomain 0 nothing after it left.
 */
enum { SLIDE_STEPS = 600 };
static const double XB = 5e-3; /* the border [m] */

typedef struct slide_job {
    int rank, size; /* size 0: no domain operations */
    int wall;       /* 1: the sphere on a wall */
    loopback *lb;
    int failed;
    double f[2][SLIDE_STEPS]; /* x force on the held sphere (id 7) and the driven one (id 3),
                                 NAN where this subdomain does not own it */
    double fw[SLIDE_STEPS];   /* x force on the wall (reduced over the subdomains) */
    uint64_t builds, migrated;
    double end; /* the driven sphere's final x [m] (its owner's) */
} slide_job;

static void *run_slide(void *arg)
{
    slide_job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *contact = NULL;
    j->failed = 1;
    const uint64_t ids[2] = {7, 3};
    const double x[2][3] = {{XB + 2e-5, 0.0, 0.0}, {XB - 1e-4, 2 * R * 0.98, 0.0}};
    const double on_wall[3] = {XB - 1e-4, 0.0, 0.98 * R};
    const double floor_point[3] = {0, 0, 0}, floor_normal[3] = {0, 0, 1};
    if (sinter_ctx_create(&ctx, NULL) || sinter_ctx_set_threads(ctx, 1) ||
        sinter_material_create(&mat, ctx, "m") ||
        sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7) ||
        sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3) ||
        sinter_material_set(mat, SINTER_MAT_DENSITY, 2500) ||
        sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, 0.0) ||
        sinter_material_set(mat, SINTER_MAT_FRICTION_STATIC, 100.0) ||
        sinter_material_set(mat, SINTER_MAT_FRICTION_DYNAMIC, 100.0) ||
        sinter_particles_create(&ps, ctx) || sinter_particles_set_material(ps, 0, mat))
        goto done;
    if (j->wall && (sinter_walls_create(&walls, ctx) ||
                    sinter_walls_add_plane(walls, floor_point, floor_normal, mat, NULL)))
        goto done;
    if (sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls) ||
        sinter_stepper_set_option(st, "thread_choice", 0) ||
        sinter_force_model_create(&contact, ctx, "hertz_mindlin") ||
        sinter_stepper_add_force(st, contact) || sinter_stepper_set_dt(st, 1e-6))
        goto done;
    for (int k = j->wall; k < 2; ++k) {
        const double *xk = j->wall ? on_wall : x[k];
        const int owner = xk[0] < XB ? 0 : 1;
        if (j->size > 0 && owner != j->rank)
            continue;
        if (sinter_particles_add_with_ids(ps, 1, &ids[k], xk, &R, 0, 300.0, NULL))
            goto done;
    }
    uint32_t *flags = NULL;
    double *v = NULL;
    size_t count = 0, driven = SIZE_MAX;
    if (sinter_particles_view(ps, SINTER_FIELD_FLAGS, (void **)&flags, &count, NULL))
        goto done;
    for (size_t i = 0; i < count; ++i)
        flags[i] = SINTER_PARTICLE_FIXED;
    sinter_particles_release(ps, SINTER_FIELD_FLAGS);
    if (sinter_particles_find_id(ps, ids[1], &driven) == SINTER_OK) {
        if (sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL))
            goto done;
        v[3 * driven] = 0.5;
        sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    }
    if (j->lb != NULL && loopback_attach(j->lb, j->rank, st, ps))
        goto done;
    for (int s = 0; s < SLIDE_STEPS; ++s) {
        if (sinter_stepper_step(st, 1) != SINTER_OK)
            goto done;
        const double *f = NULL;
        size_t owned = 0;
        if (sinter_particles_owned_count(ps, &owned) ||
            sinter_particles_view_read(ps, SINTER_FIELD_FORCE, (const void **)&f, NULL, NULL))
            goto done;
        for (int k = 0; k < 2; ++k) { /* by id: a migration changes the indices */
            size_t i = SIZE_MAX;
            const int mine = sinter_particles_find_id(ps, ids[k], &i) == SINTER_OK && i < owned;
            j->f[k][s] = mine ? f[3 * i] : NAN;
        }
        sinter_particles_release(ps, SINTER_FIELD_FORCE);
        double fw[3] = {0, 0, 0};
        if (walls != NULL && sinter_walls_get_force(walls, 0, fw))
            goto done;
        j->fw[s] = fw[0];
    }
    size_t owned = 0;
    if (sinter_particles_owned_count(ps, &owned))
        goto done;
    if (sinter_particles_find_id(ps, ids[1], &driven) == SINTER_OK && driven < owned) {
        const double *p = NULL;
        if (sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&p, NULL, NULL))
            goto done;
        j->end = p[3 * driven];
        sinter_particles_release(ps, SINTER_FIELD_POSITION);
    }
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    if (sinter_stepper_get_stats_global(st, &stats))
        goto done;
    j->builds = stats.neighbor_builds;
    j->failed = 0;
done:
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(contact);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

static slide_job SERIAL, SIDE[2];

/* The slide on one domain and on two with migration; returns the step after which the
 * driven sphere (id 3) is owned by subdomain 1. */
static int run_slides(int wall)
{
    SERIAL = (slide_job){.size = 0, .wall = wall};
    run_slide(&SERIAL);
    assert_int_equal(SERIAL.failed, 0);
    loopback *lb = loopback_create(2);
    assert_non_null(lb);
    loopback_set_slabs(lb, 0.0, 2 * XB); /* the border at XB */
    pthread_t t[2];
    for (int r = 0; r < 2; ++r) {
        SIDE[r] = (slide_job){.rank = r, .size = 2, .wall = wall, .lb = lb};
        assert_int_equal(pthread_create(&t[r], NULL, run_slide, &SIDE[r]), 0);
    }
    for (int r = 0; r < 2; ++r) {
        assert_int_equal(pthread_join(t[r], NULL), 0);
        SIDE[r].migrated = loopback_migrated(lb, r);
    }
    loopback_destroy(lb);
    assert_int_equal(SIDE[0].failed, 0);
    assert_int_equal(SIDE[1].failed, 0);
    assert_true(SIDE[1].end > XB + 1e-4);  /* the driven sphere crossed the border */
    assert_int_equal(SIDE[0].migrated, 1); /* and migrated, once */
    assert_int_equal(SIDE[1].migrated, 0);
    int moved = -1; /* its owner at every step: subdomain 0, then 1 */
    for (int s = 0; s < SLIDE_STEPS; ++s) {
        assert_true(isnan(SIDE[0].f[1][s]) != isnan(SIDE[1].f[1][s]));
        if (moved < 0 && isnan(SIDE[0].f[1][s]))
            moved = s;
        assert_true(moved < 0 || isnan(SIDE[0].f[1][s]));
    }
    print_message("the driven sphere migrated at step %d of %d\n", moved, SLIDE_STEPS);
    assert_true(moved > 0 && moved < SLIDE_STEPS - 100); /* with room after it */
    return moved;
}

/* (the owner's value) */
static double owned_value(double a, double b)
{
    return isnan(a) ? b : a;
}

static void test_sliding_across_border(void **st)
{
    (void)st;
    run_slides(0);
    assert_true(SIDE[0].builds >= 3); /* the lists and ghosts were made again */
    double top = 0.0;
    for (int s = 0; s < SLIDE_STEPS; ++s)
        top = fmax(top, fabs(SERIAL.f[0][s]));
    assert_true(top > 1e-4);                                     /* the spring did grow */
    assert_true(fabs(SERIAL.f[0][SLIDE_STEPS - 1]) > 0.9 * top); /* and holds */
    for (int s = 0; s < SLIDE_STEPS; ++s) {
        const double held = owned_value(SIDE[0].f[0][s], SIDE[1].f[0][s]);
        const double driven = owned_value(SIDE[0].f[1][s], SIDE[1].f[1][s]);
        assert_true(isnan(SIDE[0].f[0][s])); /* the held sphere stays on subdomain 1 */
        assert_close(held, SERIAL.f[0][s], 1e-12 * top);
        assert_close(driven, SERIAL.f[1][s], 1e-12 * top);
        assert_true(held == -driven); /* one history, twice (or one pair after the move) */
    }
}

/* A sphere sliding on a wall across the border keeps its wall contact's tangential spring
 * through the migration: its force equals the single-domain run's to 1e-12 relative (of the
 * largest), and the wall force, reduced over the subdomains, is its opposite. */
static void test_sliding_on_wall_across_border(void **st)
{
    (void)st;
    const int moved = run_slides(1);
    double top = 0.0;
    for (int s = 0; s < SLIDE_STEPS; ++s)
        top = fmax(top, fabs(SERIAL.f[1][s]));
    assert_true(top > 1e-4);                                     /* the spring did grow */
    assert_true(fabs(SERIAL.f[1][SLIDE_STEPS - 1]) > 0.9 * top); /* and holds */
    assert_true(fabs(SERIAL.f[1][moved]) > 0.1 * top);           /* it was loaded there */
    for (int s = 0; s < SLIDE_STEPS; ++s) {
        const double driven = owned_value(SIDE[0].f[1][s], SIDE[1].f[1][s]);
        assert_close(driven, SERIAL.f[1][s], 1e-12 * top);
        assert_true(SIDE[0].fw[s] == SIDE[1].fw[s]); /* reduced: the same bits */
        assert_close(SIDE[0].fw[s], SERIAL.fw[s], 1e-12 * top);
        assert_close(SIDE[0].fw[s], -driven, 1e-12 * top);
    }
}

/* A NaN force made on subdomain 2 of 3 at step 37 stops every subdomain at step 37 with
 * SINTER_ERR_UNSTABLE and one message, naming subdomain 2 and the particle's id. */
static void test_nan_stops_all(void **st)
{
    (void)st;
    make_bed();
    uint64_t id = 0;
    for (int k = 0; k < N && id == 0; ++k)
        if (slab_of(BED.x[3 * k], 3) == 2 && BED.x[3 * k + 2] > 3 * R)
            id = BED.id[k];
    run_decomposed(3, 60, id, 37, JOBS, &DEC);
    char want[64];
    snprintf(want, sizeof(want), "(id %llu)", (unsigned long long)id);
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(JOBS[r].status, SINTER_ERR_UNSTABLE);
        assert_int_equal(JOBS[r].failed_at, 37);
        assert_string_equal(JOBS[r].message, JOBS[0].message);
    }
    print_message("%s\n", JOBS[0].message);
    assert_non_null(strstr(JOBS[0].message, "subdomain 2: "));
    assert_non_null(strstr(JOBS[0].message, want));
}

/* A step rejected right after a migration: on 3 subdomains, the first step whose rebuild
 * migrates particles is made to fail (a NaN force); every subdomain restores the state at the
 * step's start, arrivals included (their records carry their state at t), so the state equals
 * the single-domain run of one step less within 1e-10 relative (the round-off bound of
 * test_decomposed_bed). An arrival left at its drifted state would be off by its motion over
 * one step, about 1/P of its displacement over the P steps. */
static void test_rejected_after_migration(void **st)
{
    (void)st;
    make_bed();
    run_decomposed(3, STEPS, 0, 0, JOBS, &DEC);
    int p = 0; /* the first step (after the first) in which particles migrated */
    for (int k = 2; k <= STEPS && p == 0; ++k)
        for (int r = 0; r < 3; ++r)
            if (JOBS[r].sent[k] > JOBS[r].sent[k - 1])
                p = k;
    print_message("first migration after step 1: in step %d\n", p);
    assert_true(p >= 2);
    run_decomposed(0, p - 1, 0, 0, REF_JOB, &REF);
    assert_int_equal(REF_JOB[0].status, SINTER_OK);
    run_decomposed(3, STEPS, BED.id[0], p, JOBS, &DEC);
    uint64_t moved = 0;
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(JOBS[r].status, SINTER_ERR_UNSTABLE);
        assert_int_equal(JOBS[r].failed_at, p);
        assert_true(JOBS[r].end_time == REF_JOB[0].end_time);
        moved += JOBS[r].sent[p] - JOBS[r].sent[p - 1];
    }
    assert_true(moved > 0); /* the failed step did migrate particles */
    for (int k = 0; k < N; ++k)
        assert_int_equal(DEC.seen[k], 1);
    double dx[3 * N], dref[3 * N], tdec[N], tref[N]; /* changes over the run */
    for (int k = 0; k < N; ++k) {
        const int i = index_of(k);
        for (int d = 0; d < 3; ++d) {
            dx[3 * k + d] = DEC.x[3 * k + d] - BED.x[3 * i + d];
            dref[3 * k + d] = REF.x[3 * k + d] - BED.x[3 * i + d];
        }
        tdec[k] = DEC.temp[k] - BED.temp[i];
        tref[k] = REF.temp[k] - BED.temp[i];
    }
    const double ex = rel_diff(dx, dref, 3 * N), ev = rel_diff(DEC.v, REF.v, 3 * N),
                 ew = rel_diff(DEC.w, REF.w, 3 * N), et = rel_diff(tdec, tref, N);
    print_message("rejected step %d (%llu migrated in it): displacements %.2g, velocities %.2g, "
                  "spins %.2g, temperatures %.2g (relative to %d steps on one domain)\n",
                  p, (unsigned long long)moved, ex, ev, ew, et, p - 1);
    assert_true(ex <= 1e-10);
    assert_true(ev <= 1e-10);
    assert_true(ew <= 1e-10);
    assert_true(et <= 1e-10);
}

/* The observer of the last of 3 subdomains stops its advance after step 12 of 40: every
 * subdomain stops there (no hang), at the same time, with SINTER_OK. */
static void test_observer_stops_all(void **st)
{
    (void)st;
    make_bed();
    run_decomposed_stop(3, 40, 0, 0, 12, JOBS, &DEC);
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(JOBS[r].status, SINTER_OK);
        assert_true(JOBS[r].end_time == JOBS[0].end_time);
    }
    assert_close(JOBS[0].end_time, 12 * 2e-6, 1e-15);
}

/* Arguments and settings refused with the status the header gives. */
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

static void test_refusals(void **st)
{
    (void)st;
    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *step = NULL, *stag = NULL, *qs = NULL;
    sinter_material *mat = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_material_create(&mat, ctx, "m"));
    OK(sinter_particles_create(&ps, ctx));
    OK(sinter_particles_set_material(ps, 0, mat));
    const uint64_t id = 5;
    const double x[3] = {0, 0, 0};
    OK(sinter_particles_add_with_ids(ps, 1, &id, x, &R, 0, 300.0, NULL));
    OK(sinter_stepper_create(&step, ctx, SINTER_STEPPER_EXPLICIT, ps, NULL));
    OK(sinter_stepper_create(&stag, ctx, SINTER_STEPPER_STAGGERED, ps, NULL));
    OK(sinter_stepper_create(&qs, ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    loopback *lb = loopback_create(1);
    assert_non_null(lb);
    /* the quasi-static stepper runs on subdomains (test_qs_domain.c), but not its strategy 1 */
    OK(sinter_stepper_set_option(qs, "qs_strategy", 1.0));
    assert_int_equal(loopback_attach(lb, 0, qs, ps), SINTER_ERR_UNSUPPORTED);
    /* the staggered stepper: with the network's global solve (test_domain_electric.c), but
     * not with its host callbacks */
    sinter_electric_model *network = NULL;
    OK(sinter_electric_model_create(&network, ctx, "network"));
    const sinter_electric_callbacks host = {.struct_size = sizeof(host), .joule_split = host_split};
    OK(sinter_electric_model_set_host(network, &host, NULL));
    OK(sinter_stepper_set_electric(stag, network));
    assert_int_equal(loopback_attach(lb, 0, stag, ps), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(ctx), "host callbacks"));
    OK(sinter_electric_model_set_host(network, NULL, NULL));
    OK(loopback_attach(lb, 0, stag, ps));
    OK(sinter_stepper_set_electric(stag, NULL));
    /* periodic axes: the explicit stepper only (test_domain_periodic.c) */
    OK(sinter_stepper_set_periodic(stag, 0, -1.0, 1.0));
    assert_int_equal(loopback_attach(lb, 0, stag, ps), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(ctx), "periodic axes"));
    OK(sinter_stepper_set_periodic(stag, 0, 0.0, 0.0));
    sinter_domain_ops ops = {.struct_size = sizeof(ops) - 1};
    assert_int_equal(sinter_stepper_set_domain_ops(step, &ops, NULL), SINTER_ERR_STRUCT_SIZE);
    ops.struct_size = sizeof(ops);
    assert_int_equal(sinter_stepper_set_domain_ops(step, &ops, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_stepper_set_domain_ops(NULL, &ops, NULL), SINTER_ERR_NULL);
    OK(loopback_attach(lb, 0, step, ps));
    /* a stepper with domain operations keeps its kind */
    /* ghosts: an owned id, an unregistered material, a mass <= 0 */
    const uint64_t gid[1] = {5};
    const double zero3[3] = {0, 0, 0}, one = 1.0, temp = 300.0;
    int32_t material = 0;
    double mass = 1.0;
    sinter_ghost_fields g = {.struct_size = sizeof(g),
                             .count = 1,
                             .id = gid,
                             .position = zero3,
                             .velocity = zero3,
                             .spin = zero3,
                             .rotation = zero3,
                             .radius = &R,
                             .mass = &mass,
                             .inertia = &one,
                             .temperature = &temp,
                             .material = &material};
    assert_int_equal(sinter_particles_set_ghosts(ps, &g), SINTER_ERR_INVALID); /* owned id */
    const uint64_t other[1] = {6};
    g.id = other;
    material = 3;
    assert_int_equal(sinter_particles_set_ghosts(ps, &g), SINTER_ERR_INVALID); /* material */
    material = 0;
    mass = 0.0;
    assert_int_equal(sinter_particles_set_ghosts(ps, &g), SINTER_ERR_INVALID); /* mass */
    mass = 1.0;
    g.struct_size = 8;
    assert_int_equal(sinter_particles_set_ghosts(ps, &g), SINTER_ERR_STRUCT_SIZE);
    g.struct_size = sizeof(g);
    OK(sinter_particles_set_ghosts(ps, &g));
    size_t count = 0, owned = 0;
    OK(sinter_particles_count(ps, &count));
    OK(sinter_particles_owned_count(ps, &owned));
    assert_int_equal(count, 2);
    assert_int_equal(owned, 1);
    double cutoff = 0.0;
    OK(sinter_stepper_ghost_cutoff(step, &cutoff));
    assert_true(cutoff >= 2 * R);
    double f[3];
    assert_int_equal(sinter_walls_get_force_local(NULL, 0, f), SINTER_ERR_NULL);
    assert_int_equal(sinter_checkpoint_write(step, "never_written.ck"), SINTER_ERR_UNSUPPORTED);
    OK(sinter_stepper_set_domain_ops(step, NULL, NULL)); /* removed */
    loopback_destroy(lb);
    sinter_stepper_destroy(step);
    sinter_stepper_destroy(stag);
    sinter_stepper_destroy(qs);
    sinter_electric_model_destroy(network);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decomposed_bed),
        cmocka_unit_test(test_empty_subdomains),
        cmocka_unit_test(test_sliding_across_border),
        cmocka_unit_test(test_sliding_on_wall_across_border),
        cmocka_unit_test(test_nan_stops_all),
        cmocka_unit_test(test_rejected_after_migration),
        cmocka_unit_test(test_observer_stops_all),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
