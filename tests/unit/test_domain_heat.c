/*
 * The heat sources across subdomains (issues 43/44): a block of 12 x 3 x 3 spheres on 1 to 4
 * subdomains (threads of one process, domain_loopback.h, slabs along x whose borders lie
 * between columns), without force models (the spheres stay where they are), with explicit
 * conduction and every source that reads more than its own particle:
 *  - a laser from above (seed 003 eq. 31): its depth is measured from the highest lit top,
 *    a maximum over every subdomain;
 *  - a ray-traced beam that enters the block from its -x end and runs along it, slanted down:
 *    its rays are shadowed by spheres on other subdomains;
 *  - radiation and convection of the exposed surface (heat/exposure.h): a pair across a border
 *    shades its owned end on each side once.
 * On one subdomain the run gives the bits of the run without domain operations. On 2-4 the
 * beam's outputs (absorbed, transmitted, lit particles) are the same bits (they depend on the
 * positions and ids only, which every decomposition has alike), and the temperature changes
 * equal the single domain's within 1e-12 relative: conduction sums a particle's pair terms in
 * another order across a border (round-off, about 1e-16 a step over 40 steps); a beam that
 * ignored the other subdomains' shadows heats the far slabs' spheres by tens of percent more.
 *
 * The frozen heat stage (frozen_heat.h) over the same block: at rest (no force models) it
 * freezes after 3 steps and advances the heat alone by backward Euler (implicit conduction
 * across subdomains, domain/solve.h) at its controlled step; the spheres soften exponentially
 * from 300 K, so the laser's heating wakes the mechanics (a modulus factor moved by 0.1 %), which
 * freeze again. Every decision (at rest, the step's error, the wake-up, the travel limit) comes
 * from reductions: on 2-4 subdomains the same heat steps, rejections, wake-ups and freezes as
 * on one, and the temperature changes within 1e-9 relative (the PCG stops at a residual of
 * 1e-13 of its right-hand side, round-off moves its iterates, and backward Euler's condition
 * number, 1 + h G / m C, stays below 1e3: test_domain_solve.c's argument).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_loopback.h"
#include "particles/particles.h"
#include "test_support.h"

enum { NX = 12, NY = 3, NZ = 3, N = NX * NY * NZ, STEPS = 40, OUTS = 4 };
static const double R = 1e-3;         /* radius [m] */
static const double A = 1.96e-3;      /* lattice spacing [m]: overlap 4e-5 m */
static const double DT = 1e-3;        /* [s]: below the explicit conduction limit (about 7 ms) */
static const double BEAM_POWER = 2.0; /* [W] */
static const double FROZEN_END = 0.3; /* [s] */

enum { FROZEN_STATS = 5 };
static const char *const FROZEN_KEYS[FROZEN_STATS] = {
    "frozen_steps", "frozen_rejected", "frozen_wakeups", "frozen_freezes", "frozen_time"};

typedef struct result {
    double frozen[LOOPBACK_MAX][FROZEN_STATS]; /* the stage's statistics on each subdomain */
    double temp[N];
    uint32_t flags[N];
    int seen[N];
    double beam[LOOPBACK_MAX][OUTS]; /* the beam's outputs on each subdomain */
    double energy[LOOPBACK_MAX][5];  /* each model's energy, reduced, on each [J] */
} result;

typedef struct job {
    int rank, size, frozen;
    loopback *lb;
    result *out;
    int failed;
    char message[512];
} job;

static pthread_mutex_t OUT_LOCK = PTHREAD_MUTEX_INITIALIZER;
static const char *const OUTPUT[OUTS] = {"absorbed", "transmitted", "lit", "lit_temperature"};

static int slab_of(double x, int size)
{
    const double r = floor(x / (NX * A) * size); /* borders between columns (NX / size apart) */
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->failed = __LINE__;                                                                  \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static sinter_status add_heat(sinter_ctx *ctx, sinter_stepper *st, const char *kind,
                              const char *const *keys, const double *values, size_t count,
                              sinter_heat_model **hm)
{
    sinter_status s = sinter_heat_model_create(hm, ctx, kind);
    for (size_t k = 0; s == SINTER_OK && k < count; ++k)
        s = sinter_heat_model_set(*hm, keys[k], values[k]);
    return s == SINTER_OK ? sinter_stepper_add_heat(st, *hm) : s;
}

static void *run_scene(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    enum { MODELS = 5 };
    sinter_heat_model *hm[MODELS] = {NULL};
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(sinter_material_create(&mat, ctx, "sphere"));
    TRY(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500));
    TRY(sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 400));
    TRY(sinter_material_set(mat, SINTER_MAT_HEAT_CAPACITY, 400));
    TRY(sinter_material_set(mat, SINTER_MAT_EMISSIVITY, 0.8));
    TRY(sinter_material_set(mat, SINTER_MAT_ABSORPTANCE, 0.3));
    if (j->frozen) { /* exponential softening (seed 003 eq. 42) from 300 K: 1e-3 per kelvin */
        TRY(sinter_material_set(mat, SINTER_MAT_SOFTENING_LAW, 2));
        TRY(sinter_material_set(mat, SINTER_MAT_SOFTENING_TEMPERATURE, 300));
        TRY(sinter_material_set(mat, SINTER_MAT_SOFTENING_RATE, 0.3));
        TRY(sinter_material_set(mat, SINTER_MAT_SOFTENING_FLOOR, 0.1));
        TRY(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    }
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, NULL));
    TRY(sinter_heat_model_create(&hm[0], ctx, "conduction"));
    TRY(sinter_stepper_add_heat(st, hm[0]));
    /* a laser over the middle of the block, wide enough to light columns of two slabs */
    const char *const laser_keys[] = {"x", "y", "radius", "intensity", "attenuation"};
    const double laser[] = {NX * A / 2, A, 2.5 * A, 1e6, 500.0};
    TRY(add_heat(ctx, st, "laser", laser_keys, laser, 5, &hm[1]));
    /* the beam: from x < 0 along the block, slanted down, through every slab */
    const char *const beam_keys[] = {"x", "y", "z", "dx", "dy", "dz", "radius", "power", "rays"};
    const double beam[] = {-3 * R, A, 2.2 * A, 1.0, 0.0, -0.15, 1.6 * A, BEAM_POWER, 24};
    TRY(add_heat(ctx, st, "beam", beam_keys, beam, 9, &hm[2]));
    const char *const rad_keys[] = {"temperature", "exposed"};
    const double rad[] = {293.15, 1.0};
    TRY(add_heat(ctx, st, "radiation", rad_keys, rad, 2, &hm[3]));
    const char *const conv_keys[] = {"temperature", "fluid_speed", "exposed"};
    const double conv[] = {300.0, 2.0, 1.0};
    TRY(add_heat(ctx, st, "convection", conv_keys, conv, 3, &hm[4]));
    for (int k = 0; k < N; ++k) { /* ids ascending with the lattice (as a scene's) */
        const int i = k % NX, l = (k / NX) % NY, m = k / (NX * NY);
        const double x[3] = {R + A * i, A * l, R + A * m};
        const double theta = 300.0 + 100.0 * i / (NX - 1) + 7.0 * ((k * 37) % 11) / 11.0;
        const uint64_t id = 1 + (uint64_t)k;
        if (j->size > 1 && slab_of(x[0], j->size) != j->rank)
            continue;
        TRY(sinter_particles_add_with_ids(ps, 1, &id, x, &R, 0, theta, NULL));
    }
    TRY(sinter_stepper_set_dt(st, DT));
    if (j->frozen) {
        TRY(sinter_stepper_set_option(st, "frozen_heat", 1));
        TRY(sinter_stepper_set_option(st, "frozen_settle", 3));
        TRY(sinter_stepper_set_option(st, "frozen_rtol", 1e-5));
        TRY(sinter_stepper_set_option(st, "frozen_wake", 1e-3)); /* 1 K above the freeze's */
    }
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    if (j->frozen) {
        const sinter_status s = sinter_stepper_advance(st, FROZEN_END);
        if (s != SINTER_OK) {
            snprintf(j->message, sizeof(j->message), "advance: %s", sinter_last_error(ctx));
            j->failed = -1;
            goto done;
        }
    }
    for (int k = 0; k < (j->frozen ? 0 : STEPS); ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (s != SINTER_OK) {
            snprintf(j->message, sizeof(j->message), "step %d: %s", k + 1, sinter_last_error(ctx));
            j->failed = -1;
            goto done;
        }
    }
    double energy[MODELS];
    for (size_t k = 0; k < MODELS; ++k)
        TRY(j->lb != NULL ? sinter_stepper_heat_energy_global(st, k, &energy[k])
                          : sinter_stepper_heat_energy(st, k, &energy[k]));
    size_t owned = 0;
    TRY(sinter_particles_owned_count(ps, &owned));
    pthread_mutex_lock(&OUT_LOCK);
    result *out = j->out;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)ps->id[i] - 1;
        out->temp[k] = ps->temperature[i];
        out->flags[k] = ps->flags[i];
        out->seen[k]++;
    }
    for (int k = 0; k < OUTS; ++k)
        if (sinter_heat_model_output(hm[2], OUTPUT[k], &out->beam[j->rank][k]) != SINTER_OK)
            j->failed = __LINE__;
    memcpy(out->energy[j->rank], energy, sizeof(energy));
    for (int k = 0; k < FROZEN_STATS; ++k)
        if (sinter_stepper_get_option(st, FROZEN_KEYS[k], &out->frozen[j->rank][k]) != SINTER_OK)
            j->failed = __LINE__;
    pthread_mutex_unlock(&OUT_LOCK);
done:
    if (j->failed > 0)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    for (int k = 0; k < MODELS; ++k)
        sinter_heat_model_destroy(hm[k]);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

/* The block on `size` subdomains (0: one run without domain operations). */
static void run(int size, int frozen, result *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, 0.0, NX * A);
    pthread_t threads[LOOPBACK_MAX];
    job jobs[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.rank = r, .size = n, .frozen = frozen, .lb = lb, .out = out};
        assert_int_equal(pthread_create(&threads[r], NULL, run_scene, &jobs[r]), 0);
    }
    for (int r = 0; r < n; ++r)
        assert_int_equal(pthread_join(threads[r], NULL), 0);
    loopback_destroy(lb);
    for (int r = 0; r < n; ++r) {
        if (jobs[r].failed)
            print_error("%d subdomains, subdomain %d: %s\n", size, r, jobs[r].message);
        assert_int_equal(jobs[r].failed, 0);
    }
    for (int k = 0; k < N; ++k)
        assert_int_equal(out->seen[k], 1);
    for (int r = 1; r < n; ++r) { /* every subdomain holds the same outputs */
        assert_memory_equal(out->beam[r], out->beam[0], sizeof(out->beam[0]));
        assert_memory_equal(out->energy[r], out->energy[0], sizeof(out->energy[0]));
        assert_memory_equal(out->frozen[r], out->frozen[0], sizeof(out->frozen[0]));
    }
}

static result REF, DEC;

static void test_sources_across_subdomains(void **state)
{
    (void)state;
    run(0, 0, &REF);
    /* the beam's balance: absorbed + transmitted = P to round-off; it lit particles deep in
     * the block (the test is not vacuous: the far slabs are in its path) */
    assert_close(REF.beam[0][0] + REF.beam[0][1], BEAM_POWER, 1e-12 * BEAM_POWER);
    assert_true(REF.beam[0][0] > 0.1 * BEAM_POWER && REF.beam[0][2] >= 8.0);
    int lit_far = 0;
    for (int k = 0; k < N; ++k)
        lit_far += (REF.flags[k] & SINTER_PARTICLE_LIT) && k % NX >= NX / 2;
    assert_true(lit_far > 0);
    double start[N];
    for (int k = 0; k < N; ++k)
        start[k] = 300.0 + 100.0 * (k % NX) / (NX - 1) + 7.0 * ((k * 37) % 11) / 11.0;
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run(size, 0, &DEC);
        assert_memory_equal(DEC.flags, REF.flags, sizeof(REF.flags));
        assert_memory_equal(DEC.beam[0], REF.beam[0], 3 * sizeof(double));
        if (size == 1) {
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(DEC.beam[0], REF.beam[0], sizeof(REF.beam[0]));
            assert_memory_equal(DEC.energy[0], REF.energy[0], sizeof(REF.energy[0]));
            continue;
        }
        double d = 0.0, m = 0.0;
        for (int k = 0; k < N; ++k) {
            d = fmax(d, fabs((DEC.temp[k] - start[k]) - (REF.temp[k] - start[k])));
            m = fmax(m, fabs(REF.temp[k] - start[k]));
        }
        /* the energies: each source's within 1e-12 of the largest (conduction's is the round-off
         * of a conserved zero) */
        double e = 0.0, big = 0.0;
        for (int k = 0; k < 5; ++k) {
            e = fmax(e, fabs(DEC.energy[0][k] - REF.energy[0][k]));
            big = fmax(big, fabs(REF.energy[0][k]));
        }
        print_message("%d subdomains: temperature changes within %.2g relative, lit temperature "
                      "%.2g, energies %.2g\n",
                      size, d / m, fabs(DEC.beam[0][3] - REF.beam[0][3]) / REF.beam[0][3], e / big);
        assert_true(d <= 1e-12 * m);
        assert_close(DEC.beam[0][3], REF.beam[0][3], 1e-12 * REF.beam[0][3]);
        assert_true(e <= 1e-12 * big);
    }
}

static double start_temperature(int k)
{
    return 300.0 + 100.0 * (k % NX) / (NX - 1) + 7.0 * ((k * 37) % 11) / 11.0;
}

static void test_frozen_heat_across_subdomains(void **state)
{
    (void)state;
    run(0, 1, &REF);
    print_message("frozen stage alone: %g heat steps, %g rejected, %g wake-ups, %g freezes, "
                  "%g s frozen\n",
                  REF.frozen[0][0], REF.frozen[0][1], REF.frozen[0][2], REF.frozen[0][3],
                  REF.frozen[0][4]);
    /* the stage ran: it froze, stepped the heat, woke on the softening and froze again */
    assert_true(REF.frozen[0][0] >= 5.0 && REF.frozen[0][2] >= 1.0 && REF.frozen[0][3] >= 2.0);
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run(size, 1, &DEC);
        assert_memory_equal(DEC.frozen[0], REF.frozen[0], 4 * sizeof(double)); /* the counts */
        if (size == 1) {
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(DEC.frozen[0], REF.frozen[0], sizeof(REF.frozen[0]));
            continue;
        }
        double d = 0.0, m = 0.0;
        for (int k = 0; k < N; ++k) {
            d = fmax(d, fabs(DEC.temp[k] - REF.temp[k]));
            m = fmax(m, fabs(REF.temp[k] - start_temperature(k)));
        }
        print_message("%d subdomains: the same heat steps; temperature changes within %.2g "
                      "relative, frozen time %.2g relative\n",
                      size, d / m, fabs(DEC.frozen[0][4] - REF.frozen[0][4]) / REF.frozen[0][4]);
        assert_true(d <= 1e-9 * m);
        assert_close(DEC.frozen[0][4], REF.frozen[0][4], 1e-12 * REF.frozen[0][4]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sources_across_subdomains),
        cmocka_unit_test(test_frozen_heat_across_subdomains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
