/*
 * A subdomain's share of the coarse-grained fields and of the lamina profiles
 * (sinter_coarse_sums, sinter_lamina_sums; issue 44), on the loopback transport of
 * domain_loopback.h: two spheres pressed together across the border x = XB of two subdomains
 * (ids 3 and 7, 1 % overlap each) and sphere 3 pressed on the floor z = 0 (2 %), all held
 * fixed, one step. Each subdomain holds the pair (one end a ghost) and sums on the same grid;
 * the two shares summed must equal the single-domain sums:
 *  - the particle sums and the laminae bit for bit (each grid point adds the same two terms,
 *    one per subdomain: a ghost counted too would double them);
 *  - the contact stress to 1e-12 of its largest value (the pair counted once, by the
 *    subdomain of id 3; it integrates the branch from its own end, the same Gauss points in
 *    another order): a pair counted on both sides would double it, one counted on neither
 *    would leave the floor's contact only.
 * Then sinter_write_vti_sums writes the sums (ascii, base64), and the argument checks.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <sinter_domain.h>

#include "domain_loopback.h"
#include "test_support.h"

#define OK(call) assert_int_equal((call), SINTER_OK)

static const double R = 5e-4;  /* radius [m] */
static const double XB = 5e-3; /* the border [m] */
enum { NX = 13, NY = 9, NZ = 9, POINTS = NX * NY * NZ, LAMINAE = 8 };

typedef struct job {
    int rank, size; /* size 0: one domain, no domain operations */
    loopback *lb;
    int failed;
    double sums[POINTS * SINTER_COARSE_SUMS];
    double laminae[2 * LAMINAE];
} job;

static void grid(sinter_coarse_options *o)
{
    sinter_coarse_options_init(o, sizeof(*o));
    const double origin[3] = {XB - 3 * R, -2 * R, -R};
    const size_t points[3] = {NX, NY, NZ};
    for (int d = 0; d < 3; ++d) {
        o->origin[d] = origin[d];
        o->spacing[d] = 0.5 * R;
        o->points[d] = points[d];
    }
    o->width = R;
}

static const double BOX_LO[3] = {XB - 2 * R, -R, 0.0}, BOX_HI[3] = {XB + 2 * R, R, 2 * R};

static void *run(void *arg)
{
    job *j = arg;
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *contact = NULL;
    sinter_snapshot *snap = NULL;
    j->failed = 1;
    const uint64_t ids[2] = {3, 7};
    const double x[2][3] = {{XB - 0.99 * R, 0.0, 0.98 * R}, {XB + 0.99 * R, 0.0, 0.98 * R}};
    const double temperature[2] = {300.0, 500.0};
    const double floor_point[3] = {0, 0, 0}, floor_normal[3] = {0, 0, 1};
    if (sinter_ctx_create(&ctx, NULL) || sinter_ctx_set_threads(ctx, 1) ||
        sinter_material_create(&mat, ctx, "m") ||
        sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7) ||
        sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3) ||
        sinter_material_set(mat, SINTER_MAT_DENSITY, 2500) ||
        sinter_particles_create(&ps, ctx) || sinter_particles_set_material(ps, 0, mat) ||
        sinter_walls_create(&walls, ctx) ||
        sinter_walls_add_plane(walls, floor_point, floor_normal, mat, NULL) ||
        sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls) ||
        sinter_force_model_create(&contact, ctx, "hertz_mindlin") ||
        sinter_stepper_add_force(st, contact) || sinter_stepper_set_dt(st, 1e-7))
        goto done;
    for (int k = 0; k < 2; ++k)
        if ((j->size == 0 || (x[k][0] < XB ? 0 : 1) == j->rank) &&
            sinter_particles_add_with_ids(ps, 1, &ids[k], x[k], &R, 0, temperature[k], NULL))
            goto done;
    uint32_t *flags = NULL;
    size_t count = 0;
    if (sinter_particles_view(ps, SINTER_FIELD_FLAGS, (void **)&flags, &count, NULL))
        goto done;
    for (size_t i = 0; i < count; ++i)
        flags[i] = SINTER_PARTICLE_FIXED;
    sinter_particles_release(ps, SINTER_FIELD_FLAGS);
    if (j->lb != NULL && loopback_attach(j->lb, j->rank, st, ps))
        goto done;
    sinter_coarse_options o;
    grid(&o);
    memset(j->sums, 0, sizeof(j->sums));
    memset(j->laminae, 0, sizeof(j->laminae));
    if (sinter_stepper_step(st, 1) || sinter_snapshot_create(&snap, st) ||
        sinter_coarse_sums(ps, snap, &o, j->sums, POINTS * SINTER_COARSE_SUMS) ||
        sinter_lamina_sums(ps, 0, BOX_LO, BOX_HI, LAMINAE, j->laminae))
        goto done;
    j->failed = 0;
done:
    sinter_snapshot_destroy(snap);
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(contact);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return NULL;
}

static job SERIAL, SIDE[2];
static double SUMMED[POINTS * SINTER_COARSE_SUMS];

static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (fp == NULL)
        return NULL;
    fseek(fp, 0, SEEK_END);
    const long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *text = calloc((size_t)n + 1, 1);
    if (text != NULL && fread(text, 1, (size_t)n, fp) != (size_t)n) {
        free(text);
        text = NULL;
    }
    fclose(fp);
    return text;
}

static void test_shares_sum_to_the_whole(void **state)
{
    (void)state;
    SERIAL.size = 0;
    run(&SERIAL);
    assert_false(SERIAL.failed);
    loopback *lb = loopback_create(2);
    assert_non_null(lb);
    loopback_set_slabs(lb, 0.0, 2 * XB);
    pthread_t t[2];
    for (int r = 0; r < 2; ++r) {
        SIDE[r] = (job){.rank = r, .size = 2, .lb = lb};
        assert_int_equal(pthread_create(&t[r], NULL, run, &SIDE[r]), 0);
    }
    for (int r = 0; r < 2; ++r)
        assert_int_equal(pthread_join(t[r], NULL), 0);
    loopback_destroy(lb);
    assert_false(SIDE[0].failed || SIDE[1].failed);
    const size_t particle_sums = POINTS * (SINTER_COARSE_SUMS - 9);
    double largest = 0.0, worst = 0.0, mass = 0.0;
    for (size_t k = 0; k < POINTS * SINTER_COARSE_SUMS; ++k) {
        SUMMED[k] = SIDE[0].sums[k] + SIDE[1].sums[k];
        if (k < particle_sums)
            assert_true(SUMMED[k] == SERIAL.sums[k]); /* each point: the same two terms */
        else
            largest = fmax(largest, fabs(SERIAL.sums[k]));
        if (k < particle_sums && k % (SINTER_COARSE_SUMS - 9) == 1)
            mass += SUMMED[k];
    }
    for (size_t k = particle_sums; k < POINTS * SINTER_COARSE_SUMS; ++k)
        worst = fmax(worst, fabs(SUMMED[k] - SERIAL.sums[k]));
    assert_true(largest > 0 && mass > 0);
    assert_true(worst <= 1e-12 * largest);
    for (int s = 0; s < 2 * LAMINAE; ++s)
        assert_true(SIDE[0].laminae[s] + SIDE[1].laminae[s] == SERIAL.laminae[s]);
    /* the laminae hold both spheres' volume, the hot one's on its side of the border */
    double volume = 0.0;
    for (int s = 0; s < LAMINAE; ++s)
        volume += SERIAL.laminae[s];
    assert_true(fabs(volume - 2 * 4.0 / 3.0 * 3.14159265358979323846 * R * R * R) < 1e-12 * volume);
    assert_true(SERIAL.laminae[LAMINAE + LAMINAE - 1] / SERIAL.laminae[LAMINAE - 1] == 500.0);

    /* the fields of the single domain's sums and of the summed shares */
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_coarse_options o;
    grid(&o);
    char whole[256], shares[256];
    snprintf(whole, sizeof(whole), "test_coarse_sums_%ld_whole.vti", (long)getpid());
    snprintf(shares, sizeof(shares), "test_coarse_sums_%ld_shares.vti", (long)getpid());
    OK(sinter_write_vti_sums(ctx, whole, &o, SERIAL.sums, POINTS * SINTER_COARSE_SUMS, 0));
    OK(sinter_write_vti_sums(ctx, shares, &o, SUMMED, POINTS * SINTER_COARSE_SUMS, 1));
    char *a = slurp(whole), *b = slurp(shares);
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(strstr(a, "Name=\"stress\""));
    assert_non_null(strstr(b, "format=\"binary\""));
    free(a);
    free(b);
    /* the argument checks */
    assert_int_equal(sinter_write_vti_sums(ctx, whole, &o, SERIAL.sums, 5, 0),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_write_vti_sums(ctx, whole, &o, SERIAL.sums,
                                           POINTS * SINTER_COARSE_SUMS, 4),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_write_vti_sums(NULL, whole, &o, SERIAL.sums, 1, 0), SINTER_ERR_NULL);
    sinter_particles *ps = NULL;
    OK(sinter_particles_create(&ps, ctx));
    assert_int_equal(sinter_coarse_sums(ps, NULL, &o, SUMMED, 7), SINTER_ERR_INVALID);
    assert_int_equal(sinter_coarse_sums(NULL, NULL, &o, SUMMED, 7), SINTER_ERR_NULL);
    assert_int_equal(sinter_lamina_sums(ps, 3, BOX_LO, BOX_HI, 4, SUMMED), SINTER_ERR_INVALID);
    assert_int_equal(sinter_lamina_sums(ps, 0, BOX_LO, BOX_HI, 4, NULL), SINTER_ERR_NULL);
    sinter_particles_destroy(ps);
    sinter_ctx_destroy(ctx);
    remove(whole);
    remove(shares);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shares_sum_to_the_whole),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
