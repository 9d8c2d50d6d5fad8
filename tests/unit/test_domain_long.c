/*
 * Issue 43's long-horizon acceptance for the explicit stepper with heat: over a horizon long
 * enough for round-off to grow into O(1) differences of individual particles (the gas is
 * chaotic), the default (not reproducible) mode on 2, 3 and 4 subdomains of the loopback
 * transport (domain_loopback.h, slabs along x) lies within the spread of serial runs that
 * differ from one another only in the order the particles were added (their storage order,
 * hence the order of every sum), for the bulk quantities.
 *
 * The gas: every other site of the lattice bed of test_domain.c (domain_lattice_bed.h: 144 of
 * its 288 spheres, R = 1 mm, 0.79 R apart, in a checkerboard), its velocities scaled by 50 (up
 * to 1 m/s), with domain_bed.h's material (damping ratio lowered to 0.05), walls and models
 * (gravity, Hertz-Mindlin with friction and rolling resistance, conduction); the side walls
 * adiabatic, the floor a heat reservoir (the default). 6000 steps of 20 us (0.12 s: the gas
 * collides, falls and heaps on the floor; a collision at 1 m/s lasts about 10 steps, and the
 * stepper's stable step estimate is 1.9e-4 s).
 *  - Chaos: the K_SERIAL = 6 serial runs (seeded shuffles of the adding order) end with some
 *    particle's position differing by 3.8 R (2026-11-28, x86-64, gcc and clang alike; at
 *    least 0.1 R asserted), where the short horizon of test_domain.c agrees to 1e-10
 *    relative.
 *  - Bulk quantities: the kinetic energy (translation and rotation) and the mean height, each
 *    averaged over the last WINDOW = 2000 steps; the floor's force and the side walls' mean
 *    |normal force| averaged over the same window; the standard deviation of the temperatures
 *    and the conduction's energy into the particles at the end. The serial spread (sd over the
 *    6 runs): 1.2 %, 0.18 %, 1.3 %, 8.7 %, 0.11 % and 1.2 % of the means. Asserted:
 *    |decomposed - mean(serial)| <= K_SD sd(serial) + 1e-12 |mean|, K_SD = 5. A decomposed run
 *    is one more member of the ensemble (another summation order): (x - mean) / (sd sqrt(1 +
 *    1/6)) follows Student's t with 5 degrees of freedom, and 5 sd is t = 4.6, exceeded with
 *    probability 0.6 % per check. Measured: within 0.30, 1.04 and 1.00 sd on 2, 3 and 4
 *    subdomains (with 14 serial runs, 1.25 sd at most).
 *  - Exactly determined, to round-off in every run: every particle owned once (the mass), and
 *    the energy balance sum m c (T - T0) = the conduction's energy into the particles
 *    (adiabatic side walls; conduction between particles is antisymmetric).
 * Cost: 9 runs of 6000 steps, 2 s of CPU (7 s under ASan + UBSan; 8 s and 37 s of wall time on
 * the shared 2-core machine, whose threads wait at the loopback's barriers).
 * Tried before: the lattice bed itself (jammed, 1.5 % overlap) stays within 1e-12 R between
 * the serial runs over 3000 steps (no chaos); this gas over 9000 steps of 10 us had its serial
 * runs 1.7 R apart, but the 2-subdomain run's end-of-run mean height lay 5.4 sd from theirs (a
 * single bouncing sphere moves it by several sd: hence the window averages and the longer
 * horizon).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_bed.h"
#include "domain_lattice_bed.h"
#include "domain_loopback.h"
#include "test_support.h"

enum { NW = DOMAIN_BED_WALLS, K_SERIAL = 6, STEPS = 6000, WINDOW = 2000, NQ = 6 };
static const double DAMPING = 0.05; /* the gas's damping ratio (the bed's 0.3: lightly damped) */
static const double SPEED = 50.0;   /* the lattice bed's velocities scaled by it (up to 1 m/s) */
static const double K_SD = 5.0;
static const double DT = 2e-5;           /* [s] */
static const double HEAT_CAPACITY = 400; /* [J/(kg K)], domain_bed_material's */

/* The bulk quantities, and their names for the messages. */
static const char *const QNAME[NQ] = {"kinetic energy [J]", "mean height [m]",
                                      "floor force z [N]",  "side wall |force| [N]",
                                      "temperature sd [K]", "conduction energy [J]"};

/* One run's result: the particles' state by id - 1 and the window's wall forces. */
typedef struct run {
    double x[3 * N], v[3 * N], w[3 * N], temp[N], mass[N], inertia[N];
    int seen[N];
    double wall_mean[3 * NW]; /* wall forces averaged over the last WINDOW steps [N] */
    double energy;            /* the conduction's energy into the particles [J] */
    /* each subdomain's sums, over the window's WINDOW steps, of its owned particles' kinetic
     * energy [J] and heights [m] */
    double ke_sum[LOOPBACK_MAX], z_sum[LOOPBACK_MAX];
    int setup_failed[LOOPBACK_MAX];
    sinter_status status[LOOPBACK_MAX];
    pthread_mutex_t lock;
} run;

typedef struct job {
    int rank, size; /* size 0: serial, no domain operations */
    loopback *lb;
    const int *order; /* the adding order (bed indices) */
    run *out;
} job;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->out->setup_failed[j->rank] = __LINE__;                                              \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

/* The gas: every other site of the lattice (a checkerboard), 144 spheres. */
static int kept(int k)
{
    const int i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
    return (i + j + l) % 2 == 0;
}

static int slab_of(double x, int size)
{
    const double r = floor((x - X0) / (X1 - X0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* Add the kinetic energy and the heights of the owned particles to *ke and *z. */
static sinter_status add_owned(sinter_particles *ps, double *ke, double *z)
{
    size_t owned = 0;
    const double *f[5] = {NULL};
    const sinter_field fields[5] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,
                                    SINTER_FIELD_MASS, SINTER_FIELD_INERTIA};
    sinter_status s = sinter_particles_owned_count(ps, &owned);
    for (int k = 0; s == SINTER_OK && k < 5; ++k)
        s = sinter_particles_view_read(ps, fields[k], (const void **)&f[k], NULL, NULL);
    if (s != SINTER_OK)
        return s;
    for (size_t i = 0; i < owned; ++i) {
        for (int d = 0; d < 3; ++d)
            *ke += 0.5 * (f[3][i] * f[1][3 * i + d] * f[1][3 * i + d] +
                          f[4][i] * f[2][3 * i + d] * f[2][3 * i + d]);
        *z += f[0][3 * i + 2];
    }
    for (int k = 0; k < 5; ++k)
        sinter_particles_release(ps, fields[k]);
    return SINTER_OK;
}

static sinter_status copy_owned(sinter_particles *ps, run *out)
{
    size_t owned = 0;
    const uint64_t *id = NULL;
    const double *f[6] = {NULL};
    const sinter_field fields[6] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY,
                                    SINTER_FIELD_SPIN,     SINTER_FIELD_TEMPERATURE,
                                    SINTER_FIELD_MASS,     SINTER_FIELD_INERTIA};
    sinter_status s = sinter_particles_owned_count(ps, &owned);
    if (s == SINTER_OK)
        s = sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL);
    for (int k = 0; s == SINTER_OK && k < 6; ++k)
        s = sinter_particles_view_read(ps, fields[k], (const void **)&f[k], NULL, NULL);
    if (s != SINTER_OK)
        return s;
    pthread_mutex_lock(&out->lock);
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(out->x + 3 * k, f[0] + 3 * i, 24);
        memcpy(out->v + 3 * k, f[1] + 3 * i, 24);
        memcpy(out->w + 3 * k, f[2] + 3 * i, 24);
        out->temp[k] = f[3][i];
        out->mass[k] = f[4][i];
        out->inertia[k] = f[5][i];
        out->seen[k]++;
    }
    pthread_mutex_unlock(&out->lock);
    sinter_particles_release(ps, SINTER_FIELD_ID);
    for (int k = 0; k < 6; ++k)
        sinter_particles_release(ps, fields[k]);
    return SINTER_OK;
}

static void *run_bed(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL;
    sinter_heat_model *cond = NULL;
    const int size = j->size > 0 ? j->size : 1;
    j->out->status[j->rank] = SINTER_ERR_STATE;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(domain_bed_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, DAMPING));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_bed_walls(ctx, mat, LX, LY, &walls));
    for (size_t k = 1; k < NW; ++k) /* side walls adiabatic; the floor a reservoir */
        TRY(sinter_walls_set_thermal(walls, k, SINTER_WALL_ADIABATIC, 0.0));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "thread_choice", 0));
    TRY(domain_bed_models(ctx, st, &gravity, &contact, &cond));
    for (int n = 0; n < N; ++n) {
        const int k = j->order[n];
        if (!kept(k) || slab_of(BED.x[3 * k], size) != j->rank)
            continue;
        TRY(domain_bed_add(ps, BED.id[k], BED.x + 3 * k, R, BED.temp[k], BED.v + 3 * k,
                           BED.w + 3 * k));
    }
    TRY(sinter_stepper_set_dt(st, DT));
    TRY(sinter_stepper_set_skin(st, 1e-5));
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    sinter_status s = sinter_stepper_step(st, STEPS - WINDOW);
    double sum[3 * NW] = {0};
    for (int k = 0; s == SINTER_OK && k < WINDOW; ++k) {
        s = sinter_stepper_step(st, 1);
        for (int c = 0; s == SINTER_OK && c < NW; ++c) {
            double f[3];
            s = sinter_walls_get_force(walls, (size_t)c, f); /* reduced: the same everywhere */
            for (int d = 0; d < 3; ++d)
                sum[3 * c + d] += f[d];
        }
        if (s == SINTER_OK)
            s = add_owned(ps, &j->out->ke_sum[j->rank], &j->out->z_sum[j->rank]);
    }
    j->out->status[j->rank] = s;
    if (s != SINTER_OK)
        goto done;
    TRY(copy_owned(ps, j->out));
    double energy = 0.0;
    TRY(sinter_stepper_heat_energy_global(st, 0, &energy));
    if (j->rank == 0) {
        j->out->energy = energy;
        for (int c = 0; c < 3 * NW; ++c)
            j->out->wall_mean[c] = sum[c] / WINDOW;
    }
done:
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

/* The bed on `size` subdomains (0: serial), particles added in `order`. */
static void run_bed_on(int size, const int *order, run *out)
{
    memset(out, 0, sizeof(*out));
    assert_int_equal(pthread_mutex_init(&out->lock, NULL), 0);
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, X0, X1);
    pthread_t threads[LOOPBACK_MAX];
    job jobs[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.rank = r, .size = size, .lb = lb, .order = order, .out = out};
        assert_int_equal(pthread_create(&threads[r], NULL, run_bed, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(threads[r], NULL), 0);
    loopback_destroy(lb);
    pthread_mutex_destroy(&out->lock);
    for (int r = 0; r < n; ++r) {
        if (out->setup_failed[r])
            print_error("%d subdomains, subdomain %d: setup failed at line %d\n", size, r,
                        out->setup_failed[r]);
        assert_int_equal(out->setup_failed[r], 0);
        assert_int_equal(out->status[r], SINTER_OK);
    }
    for (int k = 0; k < N; ++k) /* every particle owned once: the mass is kept */
        assert_int_equal(out->seen[BED.id[k] - 1], kept(k));
}

/* The bulk quantities of a run (see QNAME), and the heat content's change sum m c (T - T0)
 * [J] (the energy balance's left side). */
static void bulk(const run *r, double q[NQ], double *heat_content)
{
    const double n = N / 2; /* the gas's spheres */
    double ke = 0.0, z = 0.0, t = 0.0, t2 = 0.0, content = 0.0;
    for (int k = 0; k < LOOPBACK_MAX; ++k) { /* the window's sums, subdomain by subdomain */
        ke += r->ke_sum[k];
        z += r->z_sum[k];
    }
    for (int k = 0; k < N; ++k) {
        const size_t i = (size_t)BED.id[k] - 1; /* the state is by id, the bed by index */
        if (!kept(k))
            continue;
        t += r->temp[i];
        t2 += r->temp[i] * r->temp[i];
        content += r->mass[i] * HEAT_CAPACITY * (r->temp[i] - BED.temp[k]);
    }
    t /= n;
    q[0] = ke / WINDOW;
    q[1] = z / WINDOW / n;
    q[2] = r->wall_mean[2]; /* the floor's z (the force the gas exerts on it) */
    q[3] = 0.25 * (fabs(r->wall_mean[3 * 1]) + fabs(r->wall_mean[3 * 2]) +
                   fabs(r->wall_mean[3 * 3 + 1]) + fabs(r->wall_mean[3 * 4 + 1]));
    q[4] = sqrt(fmax(0.0, t2 / n - t * t));
    q[5] = r->energy;
    *heat_content = content;
}

/* A seeded shuffle (Fisher-Yates) of the bed's indices. */
static void shuffle(int *order, uint64_t seed)
{
    for (int k = 0; k < N; ++k)
        order[k] = k;
    for (int k = N - 1; k > 0; --k) {
        const int m = (int)(lcg(&seed) * (k + 1));
        const int tmp = order[k];
        order[k] = order[m];
        order[m] = tmp;
    }
}

static run RUN;
static double SERIAL_X[K_SERIAL][3 * N];

/* The energy balance of one run: sum m c (T - T0) equals the conduction's energy into the
 * particles to round-off: STEPS updates of heat contents m c T of about 1.3 J each, round-off
 * 1e-16 relative per update and particle; 1e-11 J bounds it with room. */
static void check_balance(double content, double energy)
{
    assert_close(content, energy, 1e-11);
}

static void test_long_horizon(void **unused)
{
    (void)unused;
    make_bed();
    for (int k = 0; k < 3 * N; ++k)
        BED.v[k] *= SPEED;
    int order[N];
    double qs[K_SERIAL][NQ], content = 0.0;
    for (int s = 0; s < K_SERIAL; ++s) {
        shuffle(order, 1000 + (uint64_t)s);
        run_bed_on(0, order, &RUN);
        bulk(&RUN, qs[s], &content);
        check_balance(content, qs[s][5]);
        memcpy(SERIAL_X[s], RUN.x, sizeof(RUN.x));
    }
    /* chaos: the largest difference of a particle's position between two serial runs */
    double chaos = 0.0;
    for (int a = 0; a < K_SERIAL; ++a)
        for (int b = a + 1; b < K_SERIAL; ++b)
            for (int k = 0; k < 3 * N; ++k)
                chaos = fmax(chaos, fabs(SERIAL_X[a][k] - SERIAL_X[b][k]));
    print_message("serial runs: largest position difference %.3g m (%.3g R)\n", chaos, chaos / R);
    assert_true(chaos >= 0.1 * R); /* round-off grown to O(1): chaos */
    double mean[NQ], sd[NQ];
    for (int q = 0; q < NQ; ++q) {
        double m = 0.0, v = 0.0;
        for (int s = 0; s < K_SERIAL; ++s)
            m += qs[s][q];
        m /= K_SERIAL;
        for (int s = 0; s < K_SERIAL; ++s)
            v += (qs[s][q] - m) * (qs[s][q] - m);
        mean[q] = m;
        sd[q] = sqrt(v / (K_SERIAL - 1));
        print_message("  %-24s mean %.10g sd %.3g (%.2g relative)\n", QNAME[q], m, sd[q],
                      sd[q] / fabs(m));
    }
    for (int size = 2; size <= LOOPBACK_MAX; ++size) {
        for (int k = 0; k < N; ++k)
            order[k] = k;
        run_bed_on(size, order, &RUN);
        double q[NQ];
        bulk(&RUN, q, &content);
        check_balance(content, q[5]);
        double worst = 0.0;
        for (int c = 0; c < NQ; ++c) {
            const double z = fabs(q[c] - mean[c]) / fmax(sd[c], 1e-300);
            worst = fmax(worst, z);
            if (!(fabs(q[c] - mean[c]) <= K_SD * sd[c] + 1e-12 * fabs(mean[c])))
                print_error("%d subdomains: %s %.10g, %.2f sd from the serial mean\n", size,
                            QNAME[c], q[c], z);
            assert_true(fabs(q[c] - mean[c]) <= K_SD * sd[c] + 1e-12 * fabs(mean[c]));
        }
        print_message("%d subdomains: within %.2f sd of the serial mean\n", size, worst);
    }
}

int main(void)
{
    (void)poison_force; /* the shared bed's NaN force: not used here */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_long_horizon),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
