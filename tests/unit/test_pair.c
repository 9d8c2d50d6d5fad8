#define _POSIX_C_SOURCE 200809L
/*
 * Pair files (sinter_pair_run, `sinter pair`) and the validity guard (docs/7dof.md §2.6):
 *  - at a constant temperature a pair file gives the library's own two-particle function called
 *    directly, to the last bit;
 *  - every Table 3 profile of examples/pair runs, its neck ratio never decreases, its shrinkage
 *    is never negative and it stays inside the model's domain;
 *  - the guard: quiet below its limits, a warning past them and, asked for, SINTER_ERR_DOMAIN
 *    naming the quantity and the time, for the two-particle model, a pair file and the
 *    quasi-static stepper.
 */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "scene_support.h"

#ifndef SINTER_PAIR_DIR
#error "SINTER_PAIR_DIR: the folder of the Table 3 pair files"
#endif
#ifndef SINTER_TEST_OUT
#error "SINTER_TEST_OUT: a folder the test may write"
#endif

typedef struct log_record {
    int warnings;
    char last[1024];
} log_record;

static void record_log(int level, const char *message, void *user)
{
    log_record *r = user;
    if (level == SINTER_LOG_WARNING) {
        r->warnings++;
        snprintf(r->last, sizeof(r->last), "%s", message);
    }
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static sinter_series *read_series(sinter_ctx *ctx, const char *path, size_t *rows)
{
    sinter_series *s = NULL;
    OK(sinter_series_read_csv(&s, ctx, path));
    OK(sinter_series_rows(s, rows));
    return s;
}

/* A copper pair (the material's defaults, seed 001 table 2) held at 1293 K. */
static const char COPPER_PAIR[] = "[scene]\nunits = SI\n\n[material copper]\n\n"
                                  "[pair]\nmaterial = copper\nradius = 25e-6\n"
                                  "schedule = hold.csv\nend_time = 5000\noutput_interval = 250\n";

static void test_constant_temperature_is_the_pair_function(void **state)
{
    (void)state;
    mkdir(SINTER_TEST_OUT, 0777);
    write_file(SINTER_TEST_OUT "/hold.csv", "time [s],temperature [K]\n0,1293\n");
    write_file(SINTER_TEST_OUT "/copper.pair", COPPER_PAIR);
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    OK(sinter_pair_run(ctx, SINTER_TEST_OUT "/copper.pair", SINTER_TEST_OUT "/copper.csv",
                       SINTER_TEST_OUT "/copper.svg"));
    size_t rows = 0;
    sinter_series *s = read_series(ctx, SINTER_TEST_OUT "/copper.csv", &rows);
    assert_int_equal(rows, 21);
    double out[21], x[21], shrink[21];
    for (size_t k = 0; k < 21; ++k)
        out[k] = 250.0 * (double)k;
    sinter_neck_model *nm = NULL;
    sinter_material *m = NULL;
    OK(sinter_neck_model_create(&nm, ctx));
    OK(sinter_material_create(&m, ctx, "copper"));
    const double t0 = 0.0, temp = 1293.0;
    OK(sinter_neck_two_particles(nm, m, 25e-6, 25e-6, 1, &t0, &temp, 21, out, x, shrink, NULL));
    for (size_t k = 0; k < 21; ++k) {
        double t, tt, ratio, sh, flag;
        OK(sinter_series_get(s, k, 0, &t));
        OK(sinter_series_get(s, k, 1, &tt));
        OK(sinter_series_get(s, k, 2, &ratio));
        OK(sinter_series_get(s, k, 3, &sh));
        OK(sinter_series_get(s, k, 9, &flag));
        assert_true(t == out[k] && tt == 1293.0 && flag == 0.0);
        assert_true(ratio == x[k] / 25e-6); /* the CSV holds 17 digits: round-off free */
        assert_true(sh == shrink[k]);
    }
    print_message("copper 1293 K, 5000 s: x/R %.5f, shrinkage %.5e, both as the pair function\n",
                  x[20] / 25e-6, shrink[20]);
    sinter_series_destroy(s);
    sinter_material_destroy(m);
    sinter_neck_model_destroy(nm);
    sinter_ctx_destroy(ctx);
}

static void test_table3_profiles(void **state)
{
    (void)state;
    mkdir(SINTER_TEST_OUT, 0777);
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    DIR *dir = opendir(SINTER_PAIR_DIR);
    assert_non_null(dir);
    int profiles = 0;
    const struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        const size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".pair") != 0)
            continue;
        char path[1024], csv[1024];
        snprintf(path, sizeof(path), "%s/%s", SINTER_PAIR_DIR, e->d_name);
        snprintf(csv, sizeof(csv), "%s/%.*s.csv", SINTER_TEST_OUT, (int)(n - 5), e->d_name);
        OK(sinter_pair_run(ctx, path, csv, NULL));
        size_t rows = 0;
        sinter_series *s = read_series(ctx, csv, &rows);
        assert_true(rows > 10);
        double last = 0.0, x = 0.0, sh = 0.0, flag = 0.0, temp = 0.0, last_temp = 0.0;
        double last_sh = 0.0;
        for (size_t k = 0; k < rows; ++k) {
            OK(sinter_series_get(s, k, 2, &x));
            OK(sinter_series_get(s, k, 3, &sh));
            OK(sinter_series_get(s, k, 9, &flag));
            OK(sinter_series_get(s, k, 1, &temp));
            /* the neck never shrinks while the furnace heats or holds; on cooling through the
             * beta -> alpha switch (1156 K) the model's alpha-phase surface diffusion narrows
             * it by 1-2 % (README.md) */
            if (temp >= last_temp)
                assert_true(x >= last);
            else
                assert_true(x >= 0.97 * last);
            assert_true(sh >= last_sh); /* the centres approach, never part */
            assert_true(flag == 0.0);
            last = x;
            last_sh = sh;
            last_temp = temp;
        }
        sinter_series_destroy(s);
        ++profiles;
    }
    closedir(dir);
    assert_int_equal(profiles, 28);
    sinter_ctx_destroy(ctx);
}

/* Copper, R = 25 um, 1293 K: 1000 s is well inside the model's domain; 100 h is far past it. */
static void test_neck_model_guard(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    log_record r = {0, ""};
    OK(sinter_ctx_set_log(ctx, record_log, SINTER_LOG_WARNING, &r));
    sinter_neck_model *nm = NULL;
    sinter_material *m = NULL;
    OK(sinter_neck_model_create(&nm, ctx));
    OK(sinter_material_create(&m, ctx, "copper"));
    const double t0 = 0.0, temp = 1293.0, r0 = 25e-6;
    double out[50], x[50], shrink[50];
    for (size_t k = 0; k < 50; ++k)
        out[k] = 1000.0 * (double)k / 49.0;
    OK(sinter_neck_two_particles(nm, m, r0, r0, 1, &t0, &temp, 50, out, x, shrink, NULL));
    assert_int_equal(r.warnings, 0);
    for (size_t k = 0; k < 50; ++k)
        out[k] = 3.6e5 * (double)k / 49.0;
    OK(sinter_neck_two_particles(nm, m, r0, r0, 1, &t0, &temp, 50, out, x, shrink, NULL));
    print_message("100 h: x/R %.4f, shrinkage %.4f; %d warnings, the last: %s\n", x[49] / r0,
                  shrink[49], r.warnings, r.last);
    assert_true(r.warnings >= 1);
    assert_non_null(strstr(r.last, " at t = "));
    /* error mode: the first output past a limit ends the run */
    OK(sinter_neck_model_set(nm, "validity", 2));
    assert_int_equal(
        sinter_neck_two_particles(nm, m, r0, r0, 1, &t0, &temp, 50, out, x, shrink, NULL),
        SINTER_ERR_DOMAIN);
    const char *msg = sinter_last_error(ctx);
    print_message("error: %s\n", msg);
    assert_true(strstr(msg, "neck ratio x/R") != NULL || strstr(msg, "relative density") != NULL);
    assert_non_null(strstr(msg, " at t = "));
    assert_true(isnan(x[49]) && isnan(shrink[49]));
    /* the neck limit alone (no density check): x/R past 0.68 for 6 neighbours */
    OK(sinter_neck_model_set(nm, "validity_green_density", 0));
    assert_int_equal(
        sinter_neck_two_particles(nm, m, r0, r0, 1, &t0, &temp, 50, out, x, shrink, NULL),
        SINTER_ERR_DOMAIN);
    assert_non_null(strstr(sinter_last_error(ctx), "neck ratio x/R"));
    /* off: quiet */
    OK(sinter_neck_model_set(nm, "validity", 0));
    r.warnings = 0;
    OK(sinter_neck_two_particles(nm, m, r0, r0, 1, &t0, &temp, 50, out, x, shrink, NULL));
    assert_int_equal(r.warnings, 0);
    assert_int_equal(sinter_neck_model_set(nm, "validity", 1.5), SINTER_ERR_INVALID);
    sinter_material_destroy(m);
    sinter_neck_model_destroy(nm);
    sinter_ctx_destroy(ctx);
}

/* A pair file run past the limits: the past_limit column and, with validity = 2, an error. */
static void test_pair_file_flags_the_limit(void **state)
{
    (void)state;
    mkdir(SINTER_TEST_OUT, 0777);
    write_file(SINTER_TEST_OUT "/hold.csv", "time [s],temperature [K]\n0,1293\n");
    write_file(SINTER_TEST_OUT "/long.pair",
               "[material copper]\n[pair]\nmaterial = copper\nradius = 25e-6\n"
               "schedule = hold.csv\nend_time = 3.6e5\noutput_interval = 3600\n"
               "distribution = normal\nspread = 2.5e-6\npairs = 4\nseed = 3\n");
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    log_record r = {0, ""};
    OK(sinter_ctx_set_log(ctx, record_log, SINTER_LOG_WARNING, &r));
    OK(sinter_pair_run(ctx, SINTER_TEST_OUT "/long.pair", SINTER_TEST_OUT "/long.csv", NULL));
    assert_int_equal(r.warnings, 1);
    size_t rows = 0;
    sinter_series *s = read_series(ctx, SINTER_TEST_OUT "/long.csv", &rows);
    double first = 0.0, flag = 0.0, xmin = 0.0, xmax = 0.0;
    OK(sinter_series_get(s, 1, 9, &first));
    OK(sinter_series_get(s, rows - 1, 9, &flag));
    OK(sinter_series_get(s, rows - 1, 4, &xmin));
    OK(sinter_series_get(s, rows - 1, 5, &xmax));
    assert_true(first == 0.0 && flag != 0.0);
    assert_true(xmin < xmax); /* the radii differ */
    sinter_series_destroy(s);
    write_file(SINTER_TEST_OUT "/long2.pair",
               "[material copper]\n[pair]\nmaterial = copper\nradius = 25e-6\n"
               "schedule = hold.csv\nend_time = 3.6e5\noutput_interval = 3600\nvalidity = 2\n");
    assert_int_equal(
        sinter_pair_run(ctx, SINTER_TEST_OUT "/long2.pair", SINTER_TEST_OUT "/long2.csv", NULL),
        SINTER_ERR_DOMAIN);
    assert_non_null(strstr(sinter_last_error(ctx), " at t = "));
    /* a key that is neither a [pair] key nor a material parameter */
    write_file(SINTER_TEST_OUT "/bad.pair", "[material copper]\n[pair]\nmaterial = copper\n"
                                            "radius = 25e-6\nschedule = hold.csv\nradios = 1\n");
    assert_int_equal(
        sinter_pair_run(ctx, SINTER_TEST_OUT "/bad.pair", SINTER_TEST_OUT "/bad.csv", NULL),
        SINTER_ERR_PARSE);
    sinter_ctx_destroy(ctx);
}

/* A copper sphere with six neighbours (+-x, +-y, +-z) in the quasi-static stepper at 1293 K:
 * its six necks cover 0.8 of its surface at x/R = 0.68 (docs/7dof.md §2.6). */
static void qs_cluster(scene *s, log_record *r, double validity)
{
    scene_init(s);
    scene_material(s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_ctx_set_log(s->ctx, record_log, SINTER_LOG_WARNING, r));
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_QUASISTATIC, s->ps, NULL));
    OK(sinter_stepper_set_option(s->st, "qs_validity", validity));
    OK(sinter_stepper_set_option(s->st, "qs_dt_max", 2000.0));
    /* the necks in one CVODE system, long global steps (a test of the guard, not of accuracy) */
    OK(sinter_stepper_set_option(s->st, "qs_strategy", 3.0));
    OK(sinter_stepper_set_option(s->st, "qs_max_strain", 0.01));
    const double r0 = 25e-6, c = 3 * r0;
    const double p[21] = {c, c, c, c - 2 * r0, c, c, c + 2 * r0,
                          c, c, c, c - 2 * r0, c, c, c + 2 * r0,
                          c, c, c, c - 2 * r0, c, c, c + 2 * r0};
    const double rad[7] = {r0, r0, r0, r0, r0, r0, r0};
    OK(sinter_particles_add(s->ps, 7, p, rad, 0, 1293.0, NULL));
}

static void test_quasistatic_guard(void **state)
{
    (void)state;
    scene s;
    log_record r = {0, ""};
    qs_cluster(&s, &r, 1.0);
    OK(sinter_stepper_advance(s.st, 1000.0));
    assert_int_equal(r.warnings, 0);
    const sinter_status st = sinter_stepper_advance(s.st, 3e5);
    if (st != SINTER_OK)
        print_message("%s\n", sinter_last_error(s.ctx));
    OK(st);
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_sintering_stats(s.st, &stats));
    print_message("cluster: %d warnings (%s); x/R max %.4f\n", r.warnings, r.last,
                  stats.neck_max / 25e-6);
    assert_int_equal(r.warnings, 1);
    assert_non_null(strstr(r.last, "necks impinge"));
    scene_close(&s);

    log_record r2 = {0, ""};
    qs_cluster(&s, &r2, 2.0);
    OK(sinter_stepper_advance(s.st, 1000.0));
    assert_int_equal(sinter_stepper_advance(s.st, 3e5), SINTER_ERR_DOMAIN);
    const char *msg = sinter_last_error(s.ctx);
    print_message("error: %s\n", msg);
    assert_non_null(strstr(msg, "necks impinge"));
    assert_non_null(strstr(msg, " at t = "));
    assert_int_not_equal(sinter_stepper_set_option(s.st, "qs_validity", 0.5), SINTER_OK);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_temperature_is_the_pair_function),
        cmocka_unit_test(test_table3_profiles),
        cmocka_unit_test(test_neck_model_guard),
        cmocka_unit_test(test_pair_file_flags_the_limit),
        cmocka_unit_test(test_quasistatic_guard),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
