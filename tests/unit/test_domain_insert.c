/*
 * Continuous insertion across subdomains (issue 43, stepper/insertion.c): spheres poured at a
 * mass rate into a region that spans every slab of 1 to 4 subdomains (threads of one process,
 * domain_loopback.h, slabs along x), falling onto the floor of the bed of domain_bed.h (gravity,
 * Hertz-Mindlin, conduction, five walls). Every subdomain draws the same spheres (the near ones
 * gathered from all), subdomain 0 adds them with ids above every subdomain's, and the
 * redistribution moves each to its slab's subdomain.
 *  - one subdomain: the bits of the run without domain operations (every sphere's id,
 *    position, velocity, temperature; the insertion's counters);
 *  - 2-4 subdomains: the same spheres with the same ids (inserted and crowded counts, the
 *    inserted mass the same bits on every subdomain), each owned once, spread over the
 *    subdomains, and their positions within 1e-10 of the box and velocities within 1e-10 of
 *    the fall speed of the single domain's: the first spheres reach the floor at about 0.045 s
 *    and the run ends at 0.07 s, so contacts across borders sum their terms in another order
 *    (round-off: 9e-16 observed, not amplified over so few collisions).
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <sinter_domain.h>

#include "domain_bed.h"
#include "domain_loopback.h"
#include "particles/particles.h"
#include "test_support.h"

enum { NMAX = 512 };
static const double LX = 0.024, LY = 0.008; /* the box [m] */
static const double END = 0.07; /* [s]: the first spheres land at about 0.045 s */

typedef struct result {
    double x[NMAX][3], v[NMAX][3], temp[NMAX];
    int seen[NMAX];
    size_t owned[LOOPBACK_MAX];
    double mass[LOOPBACK_MAX];
    uint64_t inserted[LOOPBACK_MAX], crowded[LOOPBACK_MAX];
} result;

typedef struct job {
    int rank, size;
    loopback *lb;
    result *out;
    int failed;
    char message[512];
} job;

static pthread_mutex_t OUT_LOCK = PTHREAD_MUTEX_INITIALIZER;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->failed = __LINE__;                                                                  \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

static void *run_scene(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL;
    sinter_heat_model *cond = NULL;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(domain_bed_material(ctx, &mat));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(domain_bed_walls(ctx, mat, LX, LY, &walls));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(domain_bed_models(ctx, st, &gravity, &contact, &cond));
    sinter_packing_options p;
    TRY(sinter_packing_options_init(&p, sizeof(p)));
    p.distribution = SINTER_RADII_UNIFORM;
    p.radius_mean = 6e-4;
    p.radius_spread = 1e-4;
    p.seed = 43;
    p.max_attempts = 100;
    p.temperature = 350.0;
    const double lo[3] = {5e-4, 5e-4, 0.008}, hi[3] = {LX - 5e-4, LY - 5e-4, 0.014};
    memcpy(p.box_min, lo, sizeof(lo));
    memcpy(p.box_max, hi, sizeof(hi));
    sinter_insertion_options o;
    TRY(sinter_insertion_options_init(&o, sizeof(o)));
    o.mass_rate = 4e-3; /* kg/s: about 9 spheres an interval */
    o.interval = 5e-3;
    o.end = 0.04;
    o.velocity[2] = -0.1;
    TRY(sinter_stepper_set_insertion(st, &p, &o));
    TRY(sinter_stepper_set_dt(st, 1e-5));
    if (j->lb != NULL)
        TRY(loopback_attach(j->lb, j->rank, st, ps));
    const sinter_status s = sinter_stepper_advance(st, END);
    if (s != SINTER_OK) {
        snprintf(j->message, sizeof(j->message), "advance: %s", sinter_last_error(ctx));
        j->failed = -1;
        goto done;
    }
    size_t owned = 0;
    TRY(sinter_particles_owned_count(ps, &owned));
    double mass = 0.0;
    uint64_t inserted = 0, crowded = 0;
    TRY(sinter_stepper_get_insertion(st, &mass, NULL, &inserted, &crowded));
    pthread_mutex_lock(&OUT_LOCK);
    result *out = j->out;
    for (size_t i = 0; i < owned; ++i) {
        const uint64_t k = ps->id[i];
        if (k >= NMAX) {
            j->failed = __LINE__;
            break;
        }
        memcpy(out->x[k], ps->x + 3 * i, sizeof(out->x[k]));
        memcpy(out->v[k], ps->v + 3 * i, sizeof(out->v[k]));
        out->temp[k] = ps->temperature[i];
        out->seen[k]++;
    }
    out->owned[j->rank] = owned;
    out->mass[j->rank] = mass;
    out->inserted[j->rank] = inserted;
    out->crowded[j->rank] = crowded;
    pthread_mutex_unlock(&OUT_LOCK);
done:
    if (j->failed > 0)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->failed,
                 sinter_last_error(ctx));
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

/* The pour on `size` subdomains (0: one run without domain operations). */
static void run(int size, result *out)
{
    memset(out, 0, sizeof(*out));
    const int n = size > 0 ? size : 1;
    loopback *lb = size > 0 ? loopback_create(size) : NULL;
    assert_true(size == 0 || lb != NULL);
    if (lb != NULL)
        loopback_set_slabs(lb, 0.0, LX);
    pthread_t threads[LOOPBACK_MAX];
    job jobs[LOOPBACK_MAX];
    for (int r = 0; r < n; ++r) {
        jobs[r] = (job){.rank = r, .size = n, .lb = lb, .out = out};
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
    for (int r = 1; r < n; ++r) { /* the insertion's state: the same bits everywhere */
        assert_memory_equal(&out->mass[r], &out->mass[0], sizeof(double));
        assert_true(out->inserted[r] == out->inserted[0] && out->crowded[r] == out->crowded[0]);
    }
}

static result REF, DEC;

static void test_insertion_across_subdomains(void **state)
{
    (void)state;
    run(0, &REF);
    const uint64_t n = REF.inserted[0];
    print_message("single domain: %llu spheres inserted (%llu crowded), %.4g kg\n",
                  (unsigned long long)n, (unsigned long long)REF.crowded[0], REF.mass[0]);
    assert_true(n >= 40 && n < NMAX); /* about 9 an interval over 8 intervals */
    for (uint64_t k = 0; k < n; ++k)  /* ids 0 .. n-1, as sinter_particles_add gives them */
        assert_int_equal(REF.seen[k], 1);
    double vmax = 0.0;
    for (uint64_t k = 0; k < n; ++k)
        vmax = fmax(vmax, fabs(REF.v[k][2]));
    for (int size = 1; size <= LOOPBACK_MAX; ++size) {
        run(size, &DEC);
        assert_true(DEC.inserted[0] == n && DEC.crowded[0] == REF.crowded[0]);
        assert_memory_equal(DEC.seen, REF.seen, sizeof(REF.seen)); /* each owned once */
        if (size == 1) {
            assert_memory_equal(DEC.x, REF.x, sizeof(REF.x));
            assert_memory_equal(DEC.v, REF.v, sizeof(REF.v));
            assert_memory_equal(DEC.temp, REF.temp, sizeof(REF.temp));
            assert_memory_equal(&DEC.mass[0], &REF.mass[0], sizeof(double));
            continue;
        }
        double dx = 0.0, dv = 0.0;
        for (uint64_t k = 0; k < n; ++k)
            for (int d = 0; d < 3; ++d) {
                dx = fmax(dx, fabs(DEC.x[k][d] - REF.x[k][d]));
                dv = fmax(dv, fabs(DEC.v[k][d] - REF.v[k][d]));
            }
        int spread = 0; /* subdomains that own spheres */
        for (int r = 0; r < size; ++r)
            spread += DEC.owned[r] > 0;
        print_message("%d subdomains: positions within %.2g of the box, velocities %.2g of the "
                      "fall speed; owned %zu %zu %zu %zu\n",
                      size, dx / LX, dv / vmax, DEC.owned[0], DEC.owned[1], DEC.owned[2],
                      DEC.owned[3]);
        assert_int_equal(spread, size);
        assert_close(DEC.mass[0], REF.mass[0], 1e-15 * REF.mass[0]);
        assert_true(dx <= 1e-10 * LX && dv <= 1e-10 * vmax);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_insertion_across_subdomains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
