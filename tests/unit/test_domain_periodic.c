/*
 * Periodic axes across subdomains (issues 38, 43; stepper/domain_periodic.c), through the
 * thread transport of domain_loopback.h (slabs along x).
 *
 * A granular gas of 288 spheres (Hertz-Mindlin with friction and rolling resistance, no
 * gravity), periodic along y and z, between two walls x = 0 and x = LX, starts squeezed (layers
 * of triangular rows in x-y stacked along z, every neighbour overlapping by 1 % of a diameter,
 * positions jittered, random velocities), so that
 * contacts form and break across the periodic faces, across the slab borders, and across both
 * at once (a pair whose image is a ghost of another subdomain).
 *  - On one subdomain it equals the run without domain operations bit for bit (the same images,
 *    the same pairs in the same order).
 *  - On 2, 3 and 4 slabs along x (the periodic axes stay whole on every subdomain) it equals it
 *    within 1e-10 relative (positions, velocities, spins): the sums of forces on a particle run
 *    in another order, and a pair across a periodic face and a border is evaluated on each side
 *    from positions shifted by one period in different places (round-off of one ulp), which the
 *    contacts amplify as in any DEM run; test_domain.c accepts the same order of difference
 *    without periodic axes. The reference's final state has contacts across the periodic faces
 *    and, at 4 slabs, across a face and a border at once, so both kinds are exercised.
 *  - The same gas periodic along x, cut into slabs along x, is refused with
 *    SINTER_ERR_UNSUPPORTED on every subdomain, the message naming why; so is the option
 *    "reproducible" with periodic axes (the two sides of a pair do not see the same bits).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_bed.h"
#include "domain_loopback.h"
#include "rel_diff.h"
#include "test_support.h"

enum { NX = 8, NY = 6, NZ = 6, N = NX * NY * NZ, STEPS = 300 };

static const double R = 5e-4;              /* radius [m] */
static const double SPACING = 0.99 * 1e-3; /* 2 R less 1 %: every neighbour in contact */
#define SY (0.8660254037844386 * SPACING)  /* rows along y, each shifted by half a spacing in x */
#define LX ((NX + 0.5) * SPACING + 2 * R)
#define LY (NY * SY)
#define LZ (NZ * SPACING)

static double X0[3 * N], V0[3 * N];
static uint64_t ID[N];

/* The jittered lattice and velocities (a fixed LCG: the same every run). */
static void make_gas(void)
{
    uint64_t seed = 12345;
    for (int k = 0; k < N; ++k) {
        const int ix = k % NX, iy = (k / NX) % NY, iz = k / (NX * NY);
        const double c[3] = {R + SPACING * (ix + 0.5 + 0.5 * (iy % 2)), SY * (iy + 0.5),
                             SPACING * (iz + 0.5)};
        for (int d = 0; d < 3; ++d) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            const double u = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            const double w = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
            X0[3 * k + d] = c[d] + 0.004 * R * u * (d == 0 ? 0.0 : 1.0);
            V0[3 * k + d] = 0.1 * w; /* [m/s] */
        }
        ID[k] = (uint64_t)(N - k); /* ids against the layout's order */
    }
}

typedef struct state {
    double x[3 * N], v[3 * N], w[3 * N];
    int seen[N];
} state;

typedef struct job {
    int rank, size, periodic_x;
    loopback *lb;
    state *out;
    int setup_failed;
    sinter_status status;
    char message[512];
} job;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->setup_failed = __LINE__;                                                            \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static int slab_of(double x, int size)
{
    const double r = floor(x / LX * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

static void copy_owned(sinter_particles *ps, state *out)
{
    size_t owned = 0;
    const uint64_t *id = NULL;
    const double *x = NULL, *v = NULL, *w = NULL;
    if (sinter_particles_owned_count(ps, &owned) ||
        sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_SPIN, (const void **)&w, NULL, NULL))
        return;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(out->x + 3 * k, x + 3 * i, 24);
        memcpy(out->v + 3 * k, v + 3 * i, 24);
        memcpy(out->w + 3 * k, w + 3 * i, 24);
        out->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    sinter_particles_release(ps, SINTER_FIELD_SPIN);
}

static void *run_gas(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *contact = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(domain_bed_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(sinter_walls_create(&walls, ctx));
    const double p0[3] = {0, 0, 0}, n0[3] = {1, 0, 0}, p1[3] = {LX, 0, 0}, n1[3] = {-1, 0, 0};
    TRY(sinter_walls_add_plane(walls, p0, n0, mat, NULL));
    TRY(sinter_walls_add_plane(walls, p1, n1, mat, NULL));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "thread_choice", 0));
    TRY(sinter_force_model_create(&contact, ctx, "hertz_mindlin"));
    TRY(sinter_stepper_add_force(st, contact));
    if (j->periodic_x)
        TRY(sinter_stepper_set_periodic(st, 0, 0.0, LX));
    TRY(sinter_stepper_set_periodic(st, 1, 0.0, LY));
    TRY(sinter_stepper_set_periodic(st, 2, 0.0, LZ));
    for (int k = 0; k < N; ++k) {
        if (slab_of(X0[3 * k], j->size) != j->rank)
            continue;
        size_t first = 0;
        TRY(sinter_particles_add_with_ids(ps, 1, &ID[k], X0 + 3 * k, &R, 0, 300.0, &first));
        double *v = NULL;
        TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
        memcpy(v + 3 * first, V0 + 3 * k, 24);
        TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
    }
    TRY(sinter_stepper_set_dt(st, 2e-6));   /* under 5 % of the Rayleigh time, about 4e-5 s */
    TRY(sinter_stepper_set_skin(st, 1e-5)); /* a rebuild (and migration) every few steps */
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    j->status = SINTER_OK;
    for (int k = 0; k < STEPS && j->status == SINTER_OK; ++k)
        j->status = sinter_stepper_step(st, 1);
    if (j->status != SINTER_OK)
        snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
    else
        copy_owned(ps, j->out);
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(contact);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The gas on `size` slabs (0: one run without domain operations). */
static void run_gas_on(int size, int periodic_x, job *jobs, state *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, 0.0, LX);
    pthread_t threads[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.rank = r, .size = n, .periodic_x = periodic_x, .lb = lb, .out = out};
        assert_int_equal(pthread_create(&threads[r], NULL, run_gas, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(threads[r], NULL), 0);
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].setup_failed)
            print_error("subdomain %d: %s\n", r, jobs[r].message);
        assert_int_equal(jobs[r].setup_failed, 0);
    }
}

static state REF, DEC;

/* Contacts in the final state across a periodic face (the direct distance is over 2 R, the
 * nearest image's under it), and of those the ones whose ends are on different slabs of 4. */
static void count_face_contacts(const state *s, int *faces, int *corners)
{
    *faces = *corners = 0;
    const double period[3] = {0.0, LY, LZ};
    for (int a = 0; a < N; ++a)
        for (int b = a + 1; b < N; ++b) {
            double direct = 0.0, image = 0.0;
            for (int d = 0; d < 3; ++d) {
                double e = s->x[3 * b + d] - s->x[3 * a + d];
                direct += e * e;
                if (period[d] > 0.0)
                    e -= period[d] * nearbyint(e / period[d]);
                image += e * e;
            }
            if (image < 4 * R * R && direct >= 4 * R * R) {
                ++*faces;
                *corners += slab_of(s->x[3 * a], 4) != slab_of(s->x[3 * b], 4);
            }
        }
}

static void test_periodic_slabs(void **unused)
{
    (void)unused;
    make_gas();
    job ref[1], jobs[LOOPBACK_MAX];
    run_gas_on(0, 0, ref, &REF);
    assert_int_equal(ref[0].status, SINTER_OK);
    int faces = 0, corners = 0;
    count_face_contacts(&REF, &faces, &corners);
    print_message("contacts across a periodic face at the end: %d, of which across a slab "
                  "border of 4 too: %d\n",
                  faces, corners);
    assert_true(faces >= 10);
    assert_true(corners >= 2);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run_gas_on(size, 0, jobs, &DEC);
        for (int r = 0; r < size; ++r) {
            if (jobs[r].status != SINTER_OK)
                print_error("subdomain %d: %s\n", r, jobs[r].message);
            assert_int_equal(jobs[r].status, SINTER_OK);
        }
        for (int k = 0; k < N; ++k)
            assert_int_equal(DEC.seen[k], 1); /* every particle owned once */
        const double dx = rel_diff(DEC.x, REF.x, 3 * N), dv = rel_diff(DEC.v, REF.v, 3 * N),
                     dw = rel_diff(DEC.w, REF.w, 3 * N);
        print_message("%d subdomain(s): relative differences x %.3g, v %.3g, spin %.3g\n", size, dx,
                      dv, dw);
        if (size == 1) {
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.v, REF.v, sizeof(REF.v));
            assert_memory_equal(DEC.w, REF.w, sizeof(REF.w));
        }
        assert_true(dx < 1e-10 && dv < 1e-10 && dw < 1e-10);
    }
}

static void test_cut_axis_refused(void **unused)
{
    (void)unused;
    make_gas();
    job jobs[LOOPBACK_MAX];
    run_gas_on(2, 1, jobs, &DEC);
    for (int r = 0; r < 2; ++r) {
        assert_int_equal(jobs[r].status, SINTER_ERR_UNSUPPORTED);
        assert_non_null(strstr(jobs[r].message, "cut that axis"));
    }
}

/* Settings refused with periodic axes across subdomains, each naming why. */
static void test_settings_refused(void **unused)
{
    (void)unused;
    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
    assert_int_equal(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, NULL), SINTER_OK);
    assert_int_equal(sinter_stepper_set_periodic(st, 1, 0.0, 1.0), SINTER_OK);
    assert_int_equal(sinter_stepper_set_option(st, "reproducible", 1.0), SINTER_OK);
    loopback *lb = loopback_create(1);
    assert_non_null(lb);
    assert_int_equal(loopback_attach(lb, 0, st, ps), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(ctx), "reproducible"));
    assert_int_equal(sinter_stepper_set_option(st, "reproducible", 0.0), SINTER_OK);
    assert_int_equal(loopback_attach(lb, 0, st, ps), SINTER_OK);
    sinter_stepper_destroy(st);
    loopback_destroy(lb);
    sinter_particles_destroy(ps);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_periodic_slabs),
        cmocka_unit_test(test_cut_axis_refused),
        cmocka_unit_test(test_settings_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
