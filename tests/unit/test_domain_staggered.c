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

enum { NX = 8, NY = 6, NZ = 5, N = NX * NY * NZ, NW = 6, STEPS = 12 };
static const double R = 0.05, A = 0.099; /* radius and lattice spacing [m]: 1 % overlap */

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

typedef struct press_spec {
    double x[3 * N], v[3 * N], temp[N];
    uint64_t id[N];
} press_spec;

static press_spec PRESS;
static const double LX = R + A * (NX - 1) + R, LY = R + A * (NY - 1) + R;
static const double TOP = R + A * (NZ - 1) + 0.99 * R; /* the top wall at t = 0 [m] */

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
        PRESS.id[k] = 1 + (uint64_t)((k * 37) % N); /* (ids not in the lattice's order) */
    }
}

/* Slabs of [X0, X1) along x whose borders lie between two columns of the lattice for 2, 3
 * and 4 subdomains (X1 - X0 = 12 A, borders at odd multiples of A / 2 from the columns). */
static double X0 = R - 2.5 * A, X1 = R + 9.5 * A;

static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* A host force that makes the force of particle `id` NaN once an evaluation reached the time
 * `after`, at every evaluation from then on (the shorter retries too), on the subdomain that
 * owns it. */
typedef struct host_force {
    const sinter_particles *ps;
    uint64_t id;
    double after;
    int on;
} host_force;

static int host_eval(const sinter_state_view *s, double *force, double *torque, void *user)
{
    (void)torque;
    host_force *p = user;
    size_t i = SIZE_MAX, owned = 0;
    if (p->id == 0 || sinter_particles_owned_count(p->ps, &owned) != SINTER_OK ||
        sinter_particles_find_id(p->ps, p->id, &i) != SINTER_OK || i >= owned)
        return 0;
    p->on |= s->time > p->after;
    if (p->on)
        force[3 * i] = NAN;
    return 0;
}

typedef struct job {
    int rank, size;
    loopback *lb; /* NULL: without domain operations */
    int steps;
    int scheme;       /* the staggered stepper's option "scheme" */
    uint64_t host_id; /* the host force's particle (0: none) */
    double nan_after;
    /* results */
    int setup_failed, failed_at;
    sinter_status status;
    char message[512];
    double time, wall[3 * NW];
    sinter_stepper_stats stats;
    size_t owned;
} job;

/* The final state by id - 1. */
typedef struct state {
    double x[3 * N], v[3 * N], temp[N], current[N];
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
    const double *x = NULL, *v = NULL, *t = NULL, *c = NULL;
    if (sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&t, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_CURRENT, (const void **)&c, NULL, NULL))
        return;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(out->x + 3 * k, x + 3 * i, 24);
        memcpy(out->v + 3 * k, v + 3 * i, 24);
        out->temp[k] = t[i];
        out->current[k] = c[i];
        out->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
    sinter_particles_release(ps, SINTER_FIELD_CURRENT);
}

static void *run_press(void *arg)
{
    job_and_state *js = arg;
    job *j = js->j;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *host = NULL;
    domain_press_models models = {NULL, NULL, NULL, NULL, NULL, NULL};
    host_force hf = {NULL, 0, INFINITY, 0};
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(domain_press_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_press_walls(ctx, mat, LX, LY, TOP, &walls));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_STAGGERED, ps, walls));
    TRY(domain_press_add_models(ctx, st, 1e-14, &models));
    for (int k = 0; k < N; ++k) {
        if (slab_of(PRESS.x[3 * k], j->size) != j->rank)
            continue;
        size_t first = 0;
        TRY(sinter_particles_add_with_ids(ps, 1, &PRESS.id[k], PRESS.x + 3 * k, &R, 0,
                                          PRESS.temp[k], &first));
        double *v = NULL;
        TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
        memcpy(v + 3 * first, PRESS.v + 3 * k, 24);
        TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
    }
    if (j->host_id != 0) { /* on every subdomain: migration needs the same force models */
        hf = (host_force){ps, j->host_id, j->nan_after, 0};
        const sinter_force_callbacks cb = {.struct_size = sizeof(cb), .particles = host_eval};
        TRY(sinter_force_model_create_host(&host, ctx, "host", &cb, &hf));
        TRY(sinter_stepper_add_force(st, host));
    }
    TRY(sinter_stepper_set_option(st, "scheme", j->scheme));
    TRY(sinter_stepper_set_dt(st, 0.005));
    TRY(sinter_stepper_set_option(st, "dt_max", 0.005));
    TRY(sinter_stepper_set_option(st, "dt_min", 1e-7));
    TRY(sinter_stepper_set_option(st, "position_tolerance", 1e-6));
    TRY(sinter_stepper_set_skin(st, 0.01)); /* rebuilds within the run */
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    j->status = SINTER_OK;
    for (int k = 1; k <= j->steps; ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (s != SINTER_OK) {
            j->status = s;
            j->failed_at = k;
            snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
            break;
        }
    }
    TRY(sinter_stepper_time(st, &j->time));
    TRY(sinter_particles_owned_count(ps, &j->owned));
    copy_owned(ps, j->owned, js->out);
    for (int k = 0; k < NW; ++k)
        TRY(sinter_walls_get_force(walls, (size_t)k, j->wall + 3 * k));
    j->stats.struct_size = sizeof(j->stats);
    TRY(sinter_stepper_get_stats_global(st, &j->stats));
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(host);
    domain_press_models_destroy(&models);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
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
        jobs[r] = (job){.rank = r,
                        .size = n,
                        .lb = lb,
                        .steps = steps,
                        .scheme = SCHEME,
                        .host_id = host_id,
                        .nan_after = nan_after};
        js[r] = (job_and_state){&jobs[r], out};
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

/* The largest |a - b| over the largest |ref - base| (base NULL: |ref|), k values. */
static double rel_diff(const double *a, const double *b, const double *base, size_t k)
{
    double diff = 0.0, scale = 0.0;
    for (size_t i = 0; i < k; ++i) {
        diff = fmax(diff, fabs(a[i] - b[i]));
        scale = fmax(scale, fabs(b[i] - (base != NULL ? base[i] : 0.0)));
    }
    return scale > 0.0 ? diff / scale : diff;
}

static job REF_JOB[1], JOBS[LOOPBACK_MAX];
static state REF, DEC;
static double X_START[3 * N], T_START[N];

static void compare_press(int scheme)
{
    SCHEME = scheme;
    make_press();
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
        const double dx = rel_diff(DEC.x, REF.x, X_START, 3 * N);
        const double dv = rel_diff(DEC.v, REF.v, NULL, 3 * N);
        const double dt = rel_diff(DEC.temp, REF.temp, T_START, N);
        const double dc = rel_diff(DEC.current, REF.current, NULL, N);
        const double dw = rel_diff(JOBS[0].wall, REF_JOB[0].wall, NULL, 3 * NW);
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
    make_press();
    X0 = R - 2.0 * A;
    X1 = R + 10.0 * A;
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
        const double dx = rel_diff(DEC.x, REF.x, X_START, 3 * N);
        const double dv = rel_diff(DEC.v, REF.v, NULL, 3 * N);
        const double dt = rel_diff(DEC.temp, REF.temp, T_START, N);
        fprintf(stderr,
                "%d slabs with borders on columns: %llu migrations; displacements %.2g, "
                "velocities %.2g, temperature changes %.2g (relative)\n",
                size, (unsigned long long)JOBS[0].stats.bonds_broken, dx, dv, dt);
        assert_true(JOBS[0].stats.bonds_broken >= 1);
        assert_true(dx <= 1e-10);
        assert_true(dv <= 1e-10);
        assert_true(dt <= 1e-10);
    }
    X0 = R - 2.5 * A;
    X1 = R + 9.5 * A;
}

/* A NaN force on one subdomain's particle stops every subdomain at the same step. */
static void test_nan_stops_all(void **unused)
{
    (void)unused;
    SCHEME = 1;
    make_press();
    const int k = 2 * NX * NY + 3 * NX + 6; /* in the third slab of 4 */
    assert_int_equal(slab_of(PRESS.x[3 * k], 4), 2);
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
