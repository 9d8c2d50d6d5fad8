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
#include "mpi_check.h"

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
    loopback *lb;         /* the thread transport, or NULL */
    sinter_mpi_domain *d; /* an MPI domain, or NULL (neither: without domain operations) */
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
    uint64_t migrated; /* MPI: particles this rank sent to others */
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
    sinter_force_model *law = NULL, *drag = NULL, *gravity = NULL, *host = NULL;
    sinter_heat_model *cond = NULL, *joule = NULL;
    sinter_electric_model *em = NULL;
    host_force hf = {NULL, 0, INFINITY, 0};
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(sinter_material_create(&mat, ctx, "powder"));
    const struct {
        sinter_material_param p;
        double v;
    } props[] = {{SINTER_MAT_DENSITY, 2000},
                 {SINTER_MAT_CONTACT_STIFFNESS, 1e7},
                 {SINTER_MAT_FRICTION_DYNAMIC, 0.1},
                 {SINTER_MAT_DRAG_COEFFICIENT, 0.1414},
                 {SINTER_MAT_THERMAL_CONDUCTIVITY, 100},
                 {SINTER_MAT_HEAT_CAPACITY, 100},
                 {SINTER_MAT_ELECTRIC_CONDUCTIVITY, 0.1},
                 {SINTER_MAT_SOFTENING_LAW, 1},
                 {SINTER_MAT_SOFTENING_TEMPERATURE, 320},
                 {SINTER_MAT_SOFTENING_FLOOR, 0.1}};
    for (size_t k = 0; k < sizeof(props) / sizeof(props[0]); ++k)
        TRY(sinter_material_set(mat, props[k].p, props[k].v));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(sinter_walls_create(&walls, ctx));
    const double wp[NW][3] = {{0, 0, 0}, {0, 0, TOP}, {0, 0, 0}, {LX, 0, 0}, {0, 0, 0}, {0, LY, 0}};
    const double wn[NW][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < NW; ++k) {
        TRY(sinter_walls_add_plane(walls, wp[k], wn[k], mat, NULL));
        TRY(sinter_walls_set_temperature(walls, (size_t)k, 400.0));
    }
    TRY(sinter_walls_set_electric(walls, 0, SINTER_WALL_CURRENT, 1000.0));
    TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_CURRENT, 1000.0));
    const double down[3] = {0, 0, -0.05};
    TRY(sinter_walls_set_velocity(walls, 1, down));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_STAGGERED, ps, walls));
    TRY(sinter_force_model_create(&law, ctx, "power_law"));
    TRY(sinter_stepper_add_force(st, law));
    TRY(sinter_force_model_create(&drag, ctx, "drag"));
    TRY(sinter_stepper_add_force(st, drag));
    TRY(sinter_force_model_create(&gravity, ctx, "gravity"));
    TRY(sinter_stepper_add_force(st, gravity));
    TRY(sinter_heat_model_create(&cond, ctx, "conduction"));
    TRY(sinter_stepper_add_heat(st, cond));
    TRY(sinter_heat_model_create(&joule, ctx, "joule"));
    TRY(sinter_stepper_add_heat(st, joule));
    TRY(sinter_electric_model_create(&em, ctx, "averaged"));
    TRY(sinter_electric_model_set(em, "tolerance", 1e-14));
    TRY(sinter_electric_model_set(em, "max_iterations", 1e5));
    TRY(sinter_stepper_set_electric(st, em));
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
    if (j->d != NULL)
        TRY(sinter_mpi_attach(j->d, st, ps, 0));
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
    if (j->d != NULL) {
        sinter_mpi_exchange_stats xs = {.struct_size = sizeof xs};
        TRY(sinter_mpi_get_exchange_stats(j->d, &xs));
        j->migrated = xs.migrated_out;
    }
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(law);
    sinter_force_model_destroy(drag);
    sinter_force_model_destroy(gravity);
    sinter_force_model_destroy(host);
    sinter_heat_model_destroy(cond);
    sinter_heat_model_destroy(joule);
    sinter_electric_model_destroy(em);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

static job REF_JOB, MY_JOB, LOOP_JOBS[LOOPBACK_MAX];
static state REF, MINE, ALL, LOOP;
static double X_START[3 * N], T_START[N];

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
    loopback *lb = loopback_create(size);
    CHECK(lb != NULL);
    if (lb == NULL)
        return;
    loopback_set_slabs(lb, X0, X1);
    pthread_t threads[LOOPBACK_MAX];
    job_and_state js[LOOPBACK_MAX];
    for (int r = 0; r < size; ++r) {
        LOOP_JOBS[r] = (job){
            .rank = r, .size = size, .lb = lb, .steps = STEPS, .scheme = 1, .nan_after = INFINITY};
        js[r] = (job_and_state){&LOOP_JOBS[r], &LOOP};
        CHECK(pthread_create(&threads[r], NULL, run_thread, &js[r]) == 0);
    }
    for (int r = 0; r < size; ++r)
        CHECK(pthread_join(threads[r], NULL) == 0);
    loopback_destroy(lb);
}

static sinter_mpi_domain *make_domain(int size)
{
    sinter_mpi_options o;
    sinter_mpi_options_init(&o, sizeof o);
    o.decomposition = SINTER_MPI_DECOMP_BRICK;
    const int grid[3] = {size, 1, 1};
    const double lo[3] = {X0, -A, -A}, hi[3] = {X1, LY + A, TOP + A};
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK);
    return d;
}

/* The press through MPI against the single-domain run (and the loopback's on rank 0). */
static void test_press(int rank, int size, const char *what)
{
    make_press();
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)PRESS.id[k] - 1;
        memcpy(X_START + 3 * i, PRESS.x + 3 * k, 24);
        T_START[i] = PRESS.temp[k];
    }
    memset(&REF, 0, sizeof REF);
    REF_JOB = (job){.rank = 0, .size = 1, .steps = STEPS, .scheme = 1, .nan_after = INFINITY};
    job_and_state rs = {&REF_JOB, &REF};
    run_press(&rs);
    CHECK(REF_JOB.setup_failed == 0 && REF_JOB.status == SINTER_OK);
    CHECK(REF_JOB.stats.iterations > 2 * REF_JOB.stats.steps);

    memset(&MINE, 0, sizeof MINE);
    sinter_mpi_domain *d = make_domain(size);
    MY_JOB = (job){
        .rank = rank, .size = size, .d = d, .steps = STEPS, .scheme = 1, .nan_after = INFINITY};
    job_and_state ms = {&MY_JOB, &MINE};
    if (d != NULL)
        run_press(&ms);
    if (MY_JOB.setup_failed || MY_JOB.status != SINTER_OK)
        fprintf(stderr, "rank %d: %s\n", rank, MY_JOB.message);
    CHECK(MY_JOB.setup_failed == 0 && MY_JOB.status == SINTER_OK);
    sinter_mpi_domain_destroy(d);
    gather(&MINE, &ALL);
    for (int k = 0; k < N; ++k)
        CHECK(ALL.seen[k] == 1);
    uint64_t migrated = MY_JOB.migrated;
    MPI_Allreduce(MPI_IN_PLACE, &migrated, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    /* collective: the same time, steps, rejections, iterations and wall forces everywhere */
    CHECK(same_on_every_rank(&MY_JOB.time, sizeof MY_JOB.time));
    CHECK(same_on_every_rank(MY_JOB.wall, sizeof MY_JOB.wall));
    CHECK(MY_JOB.stats.steps == REF_JOB.stats.steps);
    CHECK(MY_JOB.stats.rejected == REF_JOB.stats.rejected);
    CHECK(MY_JOB.stats.iterations == REF_JOB.stats.iterations);
    if (size == 1) { /* the same bits */
        CHECK(MY_JOB.time == REF_JOB.time);
        CHECK(memcmp(ALL.x, REF.x, sizeof REF.x) == 0);
        CHECK(memcmp(ALL.v, REF.v, sizeof REF.v) == 0);
        CHECK(memcmp(ALL.temp, REF.temp, sizeof REF.temp) == 0);
        CHECK(memcmp(ALL.current, REF.current, sizeof REF.current) == 0);
        CHECK(memcmp(MY_JOB.wall, REF_JOB.wall, sizeof REF_JOB.wall) == 0);
        return;
    }
    const double dx = rel_diff(ALL.x, REF.x, X_START, 3 * N);
    const double dv = rel_diff(ALL.v, REF.v, NULL, 3 * N);
    const double dt = rel_diff(ALL.temp, REF.temp, T_START, N);
    const double dc = rel_diff(ALL.current, REF.current, NULL, N);
    const double dw = rel_diff(MY_JOB.wall, REF_JOB.wall, NULL, 3 * NW);
    if (rank == 0)
        fprintf(stderr,
                "%s, %d ranks: %llu migrations; displacements %.2g, velocities %.2g, "
                "temperature changes %.2g, currents %.2g, wall forces %.2g (relative)\n",
                what, size, (unsigned long long)migrated, dx, dv, dt, dc, dw);
    CHECK(fabs(MY_JOB.time - REF_JOB.time) <= 1e-10 * REF_JOB.time);
    CHECK(dx <= 1e-10);
    CHECK(dv <= 1e-10);
    CHECK(dt <= 1e-10);
    CHECK(dc <= 1e-10);
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
    CHECK(LOOP_JOBS[0].time == MY_JOB.time);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    /* borders between two columns of the lattice: no migration */
    test_press(rank, size, "borders between columns");
    /* borders on columns: the particles about them migrate at accepted states */
    X0 = R - 2.0 * A;
    X1 = R + 10.0 * A;
    test_press(rank, size, "borders on columns");
    const int failed = mpi_check_finish("test_mpi_staggered");
    MPI_Finalize();
    return failed;
}
