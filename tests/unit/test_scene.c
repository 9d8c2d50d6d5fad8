#define _POSIX_C_SOURCE 200809L
/*
 * Scene files and checkpoints: broken files are refused with "file:line: what
 * was expected"; a run restarted from a checkpoint continues bit for bit; a
 * truncated or corrupted checkpoint is refused and changes nothing.
 */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "test_support.h"

#include <string.h>

static char dir[256];

static int make_dir(void **state)
{
    (void)state;
    snprintf(dir, sizeof(dir), "/tmp/sinter_scene_XXXXXX");
    return mkdtemp(dir) == NULL ? -1 : 0;
}

static int remove_dir(void **state)
{
    (void)state;
    char cmd[512];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *write_file(const char *name, const char *text)
{
    static char path[512];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* A small valid scene: a few spheres dropped on a floor. */
static const char *GOOD =
    "# a small valid scene\n"
    "[scene]\nname = drop\nunits = SI\n"
    "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\ndamping_ratio = 0.2\n"
    "friction_static = 0.3\nfriction_dynamic = 0.3\nfriction_damping_ratio = 0.2\n"
    "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = 0 0 0.0005\n"
    "box_max = 0.006 0.006 0.004\nradius = 0.0005\nspacing = 0.00105\n"
    "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
    "[force hertz_mindlin]\nrolling = 0\n"
    "[force gravity]\n"
    "[stepper]\ndt = auto\nimpact_speed = 0.5\nskin = 1e-4\nend_time = 0.01\n"
    "[output]\ninterval = 0.002\nvtu = no\ncheckpoint_interval = 0\n";

static void expect_parse_error(const char *text, sinter_status status, const char *fragment1,
                               const char *fragment2)
{
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = (sinter_scene *)0x1;
    const char *path = write_file("broken.scene", text);
    assert_int_equal(sinter_scene_load(&scene, ctx, path), status);
    assert_ptr_equal(scene, (sinter_scene *)0x1);
    const char *msg = sinter_last_error(ctx);
    if (strstr(msg, fragment1) == NULL || (fragment2 && strstr(msg, fragment2) == NULL)) {
        print_error("message '%s' lacks '%s' / '%s'\n", msg, fragment1, fragment2 ? fragment2 : "");
        fail();
    }
    sinter_ctx_destroy(ctx);
}

static void test_broken_scene_files(void **state)
{
    (void)state;
    char text[4096];
    expect_parse_error("[scene\nunits = SI\n", SINTER_ERR_PARSE,
                       "broken.scene:1:", "section header");
    expect_parse_error("units = SI\n", SINTER_ERR_PARSE, "broken.scene:1:", "before");
    expect_parse_error("[scene]\nunits SI\n", SINTER_ERR_PARSE,
                       "broken.scene:2:", "expected 'key = value'");
    expect_parse_error("[scene]\nunits = imperial\n", SINTER_ERR_PARSE,
                       "broken.scene:2:", "expected SI");
    expect_parse_error("[scene]\nunits = SI\nunits = SI\n", SINTER_ERR_PARSE,
                       "broken.scene:3:", "twice");
    expect_parse_error("", SINTER_ERR_PARSE, "no sections", NULL);
    /* unknown key, with its line */
    snprintf(text, sizeof(text), "%s[output]\n", GOOD);
    expect_parse_error(text, SINTER_ERR_PARSE, "only once", NULL);
    const char *bad_key = strstr(GOOD, "density");
    snprintf(text, sizeof(text), "%.*sdensty%s", (int)(bad_key - GOOD), GOOD, bad_key + 7);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:6:", "'densty' is not a material");
    /* a value out of a material's range: the library's message with the line */
    const char *dens = strstr(GOOD, "2500");
    snprintf(text, sizeof(text), "%.*s-5%s", (int)(dens - GOOD), GOOD, dens + 4);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:6:", "density");
    /* a vector with two numbers */
    const char *normal = strstr(GOOD, "0 0 1\n");
    snprintf(text, sizeof(text), "%.*s0 1\n%s", (int)(normal - GOOD), GOOD, normal + 6);
    expect_parse_error(text, SINTER_ERR_PARSE, "normal: expected three finite numbers", NULL);
    /* an undefined material */
    const char *mat = strstr(GOOD, "material = glass\n[force");
    snprintf(text, sizeof(text), "%.*smaterial = steel\n%s", (int)(mat - GOOD), GOOD, mat + 17);
    expect_parse_error(text, SINTER_ERR_PARSE, "material: expected the name of a [material",
                       "steel");
    /* an unknown force model */
    snprintf(text, sizeof(text), "%s[force magic]\n", GOOD);
    expect_parse_error(text, SINTER_ERR_NOT_FOUND, "no force model is called 'magic'", NULL);
    /* a misspelt key in [stepper] */
    snprintf(text, sizeof(text), "%s", GOOD);
    char *end = strstr(text, "end_time");
    memcpy(end, "end_tine", 8);
    expect_parse_error(text, SINTER_ERR_PARSE, "needs 'end_time", NULL);
    /* a missing section */
    const char *stepper = strstr(GOOD, "[stepper]");
    snprintf(text, sizeof(text), "%.*s", (int)(stepper - GOOD), GOOD);
    expect_parse_error(text, SINTER_ERR_PARSE, "needs a [stepper] section", NULL);
    /* unknown key left over */
    snprintf(text, sizeof(text), "%s", GOOD);
    char *skin = strstr(text, "skin");
    memcpy(skin, "skim", 4);
    expect_parse_error(text, SINTER_ERR_PARSE, "unknown key 'skim'", "[stepper]");
    /* a furnace schedule with a lone number, and one going back in time */
    snprintf(text, sizeof(text), "%.*stemperature_schedule = 0 1293, 10\n%s",
             (int)(strstr(GOOD, "[output]") - GOOD), GOOD, strstr(GOOD, "[output]"));
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:31:", "expected pairs 't T'");
    snprintf(text, sizeof(text), "%.*stemperature_schedule = 0 1293, 0 1300\n%s",
             (int)(strstr(GOOD, "[output]") - GOOD), GOOD, strstr(GOOD, "[output]"));
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:31:", "point 1");
    /* no force model with an explicit stepper */
    const char *forces = strstr(GOOD, "[force hertz_mindlin]");
    snprintf(text, sizeof(text), "%.*s%s", (int)(forces - GOOD), GOOD, strstr(GOOD, "[stepper]"));
    expect_parse_error(text, SINTER_ERR_PARSE, "needs a [force] section", "quasistatic");
    /* dt = a word that begins with "auto" is not auto (it was taken as auto) */
    snprintf(text, sizeof(text), "%s", GOOD);
    memcpy(strstr(text, "dt = auto\n"), "dt = autx\n", 10);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:27: dt:", "autx");
    /* domain_max without domain_min names the missing key (it said "unknown key 'domain_max'") */
    const char *end_time = strstr(GOOD, "end_time");
    snprintf(text, sizeof(text), "%.*sdomain_max = 1 1 1\n%s", (int)(end_time - GOOD), GOOD,
             end_time);
    expect_parse_error(text, SINTER_ERR_PARSE, "[stepper] needs 'domain_min = ...'", NULL);
    /* a missing file */
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, "/nonexistent/x.scene"), SINTER_ERR_IO);
    sinter_ctx_destroy(ctx);
}

static void load_good(sinter_ctx **ctx, sinter_scene **scene, sinter_stepper **st)
{
    assert_int_equal(sinter_ctx_create(ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(scene, *ctx, write_file("good.scene", GOOD)), SINTER_OK);
    assert_int_equal(sinter_scene_get_stepper(*scene, st), SINTER_OK);
}

static void state_of(sinter_scene *scene, double *out, size_t n)
{
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
    const double *x = NULL, *v = NULL;
    size_t count = 0;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, &count, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL),
        SINTER_OK);
    assert_int_equal(count * 6, n);
    memcpy(out, x, 3 * count * sizeof(double));
    memcpy(out + 3 * count, v, 3 * count * sizeof(double));
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
}

/* A stepper option given in [stepper] (key = good) reaches the stepper; key = bad is refused at
 * its line. */
static void check_stepper_key(const char *key, double good, double bad)
{
    char text[4096], expected[64];
    const char *end = strstr(GOOD, "end_time = 0.01\n");
    assert_non_null(end);
    const int head = (int)(end - GOOD);
    snprintf(text, sizeof(text), "%.*s%s = %g\n%s", head, GOOD, key, good, end);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("option.scene", text)), SINTER_OK);
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
    double value = -1.0;
    assert_int_equal(sinter_stepper_get_option(st, key, &value), SINTER_OK);
    assert_true(value == good);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text, sizeof(text), "%.*s%s = %g\n%s", head, GOOD, key, bad, end);
    snprintf(expected, sizeof(expected), "%s = %g", key, bad);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:30:", expected);
}

/* [stepper] periodic_x = lo hi makes x periodic (sinter_stepper_set_periodic); a cell that is
 * not two numbers, or not hi > lo, is refused at its line. */
static void test_periodic_keys(void **state)
{
    (void)state;
    char text[4096];
    const char *end = strstr(GOOD, "end_time = 0.01\n");
    assert_non_null(end);
    const int head = (int)(end - GOOD);
    snprintf(text, sizeof(text), "%.*speriodic_x = 0 0.006\n%s", head, GOOD, end);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("periodic.scene", text)), SINTER_OK);
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
    int on = 0;
    double lo = 1.0, hi = 0.0;
    assert_int_equal(sinter_stepper_get_periodic(st, 0, &on, &lo, &hi), SINTER_OK);
    assert_true(on == 1 && lo == 0.0 && hi == 0.006);
    assert_int_equal(sinter_stepper_get_periodic(st, 1, &on, NULL, NULL), SINTER_OK);
    assert_int_equal(on, 0);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text, sizeof(text), "%.*speriodic_y = 0.006\n%s", head, GOOD, end);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:30:", "periodic_y: expected the cell");
    snprintf(text, sizeof(text), "%.*speriodic_z = 0.004 0.001\n%s", head, GOOD, end);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:30:", "periodic z");
}

/* The explicit stepper's streaming stores ([stepper] stream_stores: -1, 0 or 1) and its thread
 * choice by timing ([stepper] thread_choice: -1 or 0) from a scene file. */
static void test_stream_stores_key(void **state)
{
    (void)state;
    check_stepper_key("stream_stores", 1, 3);
    check_stepper_key("thread_choice", 0, 2);
}

static void test_restart_is_bit_for_bit(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    sinter_stepper *st = NULL;
    load_good(&ctx, &scene, &st);
    sinter_particles *ps = NULL;
    sinter_scene_get_particles(scene, &ps);
    size_t n = 0;
    sinter_particles_count(ps, &n);
    assert_true(n >= 75); /* 5 x 5 x 3 lattice */
    char ckpt[512];
    snprintf(ckpt, sizeof(ckpt), "%s/state.ckpt", dir);
    /* uninterrupted: 0 -> 5 ms (checkpoint) -> 10 ms */
    assert_int_equal(sinter_stepper_advance(st, 0.005), SINTER_OK);
    assert_int_equal(sinter_checkpoint_write(st, ckpt), SINTER_OK);
    assert_int_equal(sinter_stepper_advance(st, 0.01), SINTER_OK);
    double *straight = calloc(6 * n, sizeof(double)), *restarted = calloc(6 * n, sizeof(double));
    state_of(scene, straight, 6 * n);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    /* restarted: a fresh scene, the checkpoint, then 5 -> 10 ms */
    load_good(&ctx, &scene, &st);
    assert_int_equal(sinter_checkpoint_read(st, ckpt), SINTER_OK);
    double t = 0;
    sinter_stepper_time(st, &t);
    assert_true(t == 0.005);
    assert_int_equal(sinter_stepper_advance(st, 0.01), SINTER_OK);
    state_of(scene, restarted, 6 * n);
    assert_memory_equal(straight, restarted, 6 * n * sizeof(double)); /* bit for bit */
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    free(straight);
    free(restarted);
}

static void test_bad_checkpoints_are_refused(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    sinter_stepper *st = NULL;
    load_good(&ctx, &scene, &st);
    char ckpt[512], bad[512];
    snprintf(ckpt, sizeof(ckpt), "%s/good.ckpt", dir);
    snprintf(bad, sizeof(bad), "%s/bad.ckpt", dir);
    assert_int_equal(sinter_checkpoint_write(st, ckpt), SINTER_ERR_STATE); /* no step yet */
    assert_int_equal(sinter_stepper_advance(st, 0.002), SINTER_OK);
    assert_int_equal(sinter_checkpoint_write(st, ckpt), SINTER_OK);
    FILE *f = fopen(ckpt, "rb");
    fseek(f, 0, SEEK_END);
    const long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)size);
    assert_int_equal(fread(buf, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    assert_int_equal(sinter_stepper_advance(st, 0.004), SINTER_OK);
    double before[4096];
    sinter_particles *ps = NULL;
    sinter_scene_get_particles(scene, &ps);
    size_t n = 0;
    sinter_particles_count(ps, &n);
    assert_true(6 * n <= 4096);
    state_of(scene, before, 6 * n);
    /* truncated, a flipped byte, and not a checkpoint at all */
    const long cuts[3] = {size / 2, size - 1, 12};
    for (int k = 0; k < 4; ++k) {
        f = fopen(bad, "wb");
        if (k < 3) {
            fwrite(buf, 1, (size_t)cuts[k], f);
        } else {
            buf[size / 3] ^= 0x10;
            fwrite(buf, 1, (size_t)size, f);
            buf[size / 3] ^= 0x10;
        }
        fclose(f);
        assert_int_equal(sinter_checkpoint_read(st, bad), SINTER_ERR_CORRUPT);
        assert_non_null(strstr(sinter_last_error(ctx), "nothing was changed"));
        double after[4096];
        state_of(scene, after, 6 * n);
        assert_memory_equal(before, after, 6 * n * sizeof(double));
        double t = 0;
        sinter_stepper_time(st, &t);
        assert_true(t == 0.004);
    }
    /* A failed write does not clobber the good checkpoint. */
    char in_missing_dir[600];
    snprintf(in_missing_dir, sizeof(in_missing_dir), "%s/no/such/dir.ckpt", dir);
    assert_int_equal(sinter_checkpoint_write(st, in_missing_dir), SINTER_ERR_IO);
    assert_int_equal(sinter_checkpoint_read(st, ckpt), SINTER_OK);
    free(buf);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_run_writes_outputs(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    sinter_stepper *st = NULL;
    load_good(&ctx, &scene, &st);
    char out[512];
    snprintf(out, sizeof(out), "%s/run/nested/twice", dir); /* parents are created */
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    char path[600];
    snprintf(path, sizeof(path), "%s/series.csv", out);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[2048];
    int lines = 0;
    while (fgets(line, sizeof(line), f))
        ++lines;
    fclose(f);
    assert_int_equal(lines, 1 + 6); /* header, t = 0 and five intervals of 2 ms */
    snprintf(path, sizeof(path), "%s/series.svg", out);
    f = fopen(path, "r");
    assert_non_null(f);
    fclose(f);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

/* The quasi-static stepper from a scene file; VTU frames carry the neck count per particle. */
/* [stepper] temperature_schedule: the particles (given 300 K) follow the furnace, and the necks
 * grow, which at 300 K they would not measurably do. */
/* Scan paths in a scene ([heat laser] scan_path / hatch, io/scene_scan.c): a file and a hatch
 * load and run; a bad vertex is refused with the file's line, a hatch without its spacing, both
 * at once and an unreadable file with the scene's line. */
static void test_scan_path_keys(void **state)
{
    (void)state;
    char text[4096];
    write_file("path.txt", "# x y speed level\n0 0 0 0\n3e-3, 0, 0.5, 1\n3e-3 1e-3 1.0 0\n");
    const char *laser = "[heat laser]\nradius = 1e-3\nintensity = 1e5\n";
    snprintf(text, sizeof(text), "%s%sscan_path = path.txt\nscan_start = 0.001\n", GOOD, laser);
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("scan.scene", text)), SINTER_OK);
    char out[512];
    snprintf(out, sizeof(out), "%s/scan", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    sinter_scene_destroy(scene);
    snprintf(text, sizeof(text),
             "%s%shatch = 0 0 6e-3 6e-3\nhatch_spacing = 1e-3\nhatch_speed = 1\n"
             "hatch_angle = 90\nhatch_serpentine = no\n",
             GOOD, laser);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("hatch.scene", text)), SINTER_OK);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    write_file("bad_path.txt", "0 0 0 0\n1e-3 0 -2 1\n");
    snprintf(text, sizeof(text), "%s%sscan_path = bad_path.txt\n", GOOD, laser);
    expect_parse_error(text, SINTER_ERR_PARSE, "bad_path.txt:2:", "speed > 0");
    snprintf(text, sizeof(text), "%s%shatch = 0 0 6e-3 6e-3\nhatch_speed = 1\n", GOOD, laser);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "hatch_spacing and hatch_speed");
    snprintf(text, sizeof(text),
             "%s%shatch = 0 0 6e-3 6e-3\nhatch_spacing = 1e-3\n"
             "hatch_speed = 1\nscan_path = path.txt\n",
             GOOD, laser);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "not both");
    snprintf(text, sizeof(text), "%s%sscan_path = missing.txt\n", GOOD, laser);
    expect_parse_error(text, SINTER_ERR_IO, "scan_path", "missing.txt");
    snprintf(text, sizeof(text), "%s[heat radiation]\nscan_path = path.txt\n", GOOD);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "no beam to move");
}

/* [output] temperature_bins: the histogram's columns are named by their bins and sum to the
 * particles at every sample; bad specifications are refused with the line. */
static void test_temperature_bins(void **state)
{
    (void)state;
    char text[4096];
    const char *output = strstr(GOOD, "[output]");
    snprintf(text, sizeof(text), "%.*s[heat conduction]\n%stemperature_bins = 290 300 2\n",
             (int)(output - GOOD), GOOD, output);
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("tbins.scene", text)), SINTER_OK);
    char out[512];
    snprintf(out, sizeof(out), "%s/tbins", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
    size_t n = 0;
    assert_int_equal(sinter_particles_count(ps, &n), SINTER_OK);
    char csv[600];
    snprintf(csv, sizeof(csv), "%s/series.csv", out);
    FILE *f = fopen(csv, "r");
    assert_non_null(f);
    static char line[8192];
    assert_non_null(fgets(line, sizeof(line), f));
    const char *first = strstr(line, "temperature below 290 [1],temperature 290-295 [1],"
                                     "temperature 295-300 [1],temperature 300 or more [1]");
    assert_non_null(first);
    size_t column = 0; /* the first histogram column's index */
    for (const char *c = line; c < first; ++c)
        column += *c == ',';
    int rows = 0;
    while (fgets(line, sizeof(line), f) != NULL) {
        char *p = line;
        for (size_t k = 0; k < column; ++k)
            p = strchr(p, ',') + 1;
        double sum = 0.0;
        for (int k = 0; k < 4; ++k) {
            sum += strtod(p, &p);
            if (*p == ',')
                ++p;
        }
        assert_true(sum == (double)n);
        ++rows;
    }
    fclose(f);
    assert_true(rows > 1);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text, sizeof(text), "%.*s%stemperature_bins = 300 290 2\n", (int)(output - GOOD), GOOD,
             output);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "temperature_bins");
    snprintf(text, sizeof(text), "%.*s%stemperature_bins = 290 300 2.5\n", (int)(output - GOOD),
             GOOD, output);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "whole number");
}

/* [material NAME] property tables: inline pairs and a CSV file (a header, comments), read back
 * through the particle set; E(theta) becomes the softening curve E / E_0; bad tables name the
 * line. */
static void test_property_tables(void **state)
{
    (void)state;
    char text[4096];
    const char *particles = strstr(GOOD, "[particles]");
    write_file("k.csv", "temperature [K], k [W/(m K)]\n# copper, rounded\n300, 400\n1300;200\n");
    snprintf(text, sizeof(text),
             "%.*sheat_capacity_table = 300 400, 1300 500\nconductivity_table = k.csv\n"
             "electric_conductivity_table = 300 6e7, 1300 1e7\n"
             "youngs_modulus_table = 300 1e7, 1300 5e6\n%s",
             (int)(particles - GOOD), GOOD, particles);
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("tables.scene", text)), SINTER_OK);
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
    double v = 0.0;
    assert_int_equal(sinter_particles_property(ps, 0, SINTER_PROPERTY_HEAT_CAPACITY, 800.0, &v),
                     SINTER_OK);
    assert_true(v == 450.0);
    assert_int_equal(
        sinter_particles_property(ps, 0, SINTER_PROPERTY_THERMAL_CONDUCTIVITY, 800.0, &v),
        SINTER_OK);
    assert_true(v == 300.0);
    assert_int_equal(
        sinter_particles_property(ps, 0, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY, 1300.0, &v),
        SINTER_OK);
    assert_true(v == 1e7);
    const sinter_material *m = NULL;
    assert_int_equal(sinter_particles_get_material(ps, 0, &m), SINTER_OK);
    assert_int_equal(sinter_material_get(m, SINTER_MAT_SOFTENING_LAW, &v), SINTER_OK);
    assert_true(v == 3.0);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text, sizeof(text), "%.*sheat_capacity_table = 300 400, 1300\n%s",
             (int)(particles - GOOD), GOOD, particles);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "expected pairs");
    snprintf(text, sizeof(text), "%.*sheat_capacity_table = 300 400, 200 500\n%s",
             (int)(particles - GOOD), GOOD, particles);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:", "strictly increasing");
    write_file("bad.csv", "theta,C\n300,400\nhot,500\n");
    snprintf(text, sizeof(text), "%.*sheat_capacity_table = bad.csv\n%s", (int)(particles - GOOD),
             GOOD, particles);
    expect_parse_error(text, SINTER_ERR_PARSE, "bad.csv:3:", "two finite numbers");
    snprintf(text, sizeof(text), "%.*slatent_heat = 1e5\n%s", (int)(particles - GOOD), GOOD,
             particles);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:", "melting_temperature");
}

static void test_furnace_scene(void **state)
{
    (void)state;
    const char *text = "[scene]\nname = furnace\nunits = SI\n"
                       "[material copper]\ndensity = 8960\nyoungs_modulus = 72e9\n"
                       "[particles]\nmethod = list\nmaterial = copper\n"
                       "spheres = 25e-6 25e-6 25e-6 25e-6, 75e-6 25e-6 25e-6 25e-6\n"
                       "temperature = 300\n"
                       "[stepper]\nkind = quasistatic\ndt = 1e-6\nend_time = 20\n"
                       "temperature_schedule = 0 1000, 10 1293\n"
                       "[output]\ninterval = 20\nvtu = no\n";
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("furnace.scene", text)), SINTER_OK);
    char out[512];
    snprintf(out, sizeof(out), "%s/furnace", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
    assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
    const double *temp = NULL;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&temp, NULL, NULL),
        SINTER_OK);
    assert_close(temp[0], 1293.0, 0.0);
    assert_close(temp[1], 1293.0, 0.0);
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE), SINTER_OK);
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    assert_int_equal(sinter_stepper_sintering_stats(st, &stats), SINTER_OK);
    /* seeded at x/R = 0.01 (docs/7dof.md §4); at >= 1000 K it grows several-fold in 20 s */
    assert_true(stats.neck_ratio_mean > 0.03);
    /* the series carries the sintering outputs (seed 001 sec. 4): the last row's neck ratio and
     * shrinkage along x are the stepper's */
    char csv[600];
    snprintf(csv, sizeof(csv), "%s/series.csv", out);
    FILE *f = fopen(csv, "r");
    assert_non_null(f);
    static char line[4096], last[4096];
    assert_non_null(fgets(line, sizeof(line), f));
    assert_non_null(strstr(line, "neck ratio mean [1],shrinkage x [1],shrinkage y [1]"));
    while (fgets(line, sizeof(line), f) != NULL)
        memcpy(last, line, sizeof(line));
    fclose(f);
    double v[17];
    char *p = last;
    for (int k = 0; k < 17; ++k) {
        v[k] = strtod(p, &p);
        if (*p == ',')
            ++p;
    }
    assert_close(v[8], 1.0, 0.0); /* links */
    assert_close(v[12], stats.neck_ratio_mean, 1e-15 * stats.neck_ratio_mean);
    assert_close(v[13], stats.shrinkage[0], 1e-15 * fabs(stats.shrinkage[0]));
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static int count_of(const char *doc, const char *what)
{
    int n = 0;
    for (const char *p = strstr(doc, what); p != NULL; p = strstr(p + 1, what))
        ++n;
    return n;
}

static void test_quasistatic_scene_writes_neck_counts(void **state)
{
    (void)state;
    const char *text = "[scene]\nname = cube\nunits = SI\n"
                       "[material copper]\ndensity = 8960\nyoungs_modulus = 72e9\n"
                       "[particles]\nmethod = lattice\nmaterial = copper\nbox_min = 0 0 0\n"
                       "box_max = 0.000101 0.000101 0.000101\nradius = 25e-6\nspacing = 50e-6\n"
                       "temperature = 1293\n"
                       "[force gravity]\ngz = 0\n"
                       "[stepper]\nkind = quasistatic\nqs_strategy = 2\ndt = 1e-6\nend_time = 10\n"
                       "[output]\ninterval = 10\nvtu_format = ascii\n";
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("cube.scene", text)), SINTER_OK);
    char out[512], frame[600];
    snprintf(out, sizeof(out), "%s/cube", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    snprintf(frame, sizeof(frame), "%s/frames/frame_00001.vtu", out);
    FILE *f = fopen(frame, "r");
    assert_non_null(f);
    static char buf[1 << 16];
    const size_t len = fread(buf, 1, sizeof(buf) - 1, f);
    fclose(f);
    buf[len] = '\0';
    const char *necks = strstr(buf, "Name=\"necks\"");
    assert_non_null(necks);
    necks = strchr(necks, '>') + 1;
    /* a 2 x 2 x 2 cube: every sphere touches three others */
    for (int k = 0; k < 8; ++k) {
        char *end = NULL;
        assert_close(strtod(necks, &end), 3.0, 0.0);
        necks = end;
    }
    sinter_scene_destroy(scene);
    /* without vtu_format the frames are binary (their content: test_vtu_binary.c) */
    char text2[2048];
    snprintf(text2, sizeof(text2), "%.*s", (int)(strstr(text, "vtu_format") - text), text);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("cube2.scene", text2)), SINTER_OK);
    snprintf(out, sizeof(out), "%s/cube2", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    snprintf(frame, sizeof(frame), "%s/frames/frame_00001.vtu", out);
    f = fopen(frame, "r");
    assert_non_null(f);
    const size_t len2 = fread(buf, 1, sizeof(buf) - 1, f);
    fclose(f);
    buf[len2] = '\0';
    assert_non_null(strstr(buf, "header_type=\"UInt64\""));
    /* velocity, spin, force, current and the DEM contact counts are zeros in a quasi-static
     * run: those stay ascii */
    assert_int_equal(count_of(buf, "format=\"binary\""), 9);
    assert_int_equal(count_of(buf, "format=\"ascii\""), 5);
    assert_non_null(strstr(buf, "Name=\"contacts\" format=\"ascii\""));
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text2, sizeof(text2), "%.*svtu_format = text\n",
             (int)(strstr(text, "vtu_format") - text), text);
    expect_parse_error(text2, SINTER_ERR_PARSE, "vtu_format must be binary, ascii or appended",
                       NULL);
}

/*
 * [compact] (sinter_pack_compact before the run): parser errors name the file and the line;
 * a quasi-static run of a compacted copper packing starts from the compacted state (every
 * sphere inside the jammed box, lower corner at the origin) with links between the spheres
 * the compaction left touching.
 */
static const char *COMPACT =
    "[scene]\nname = green\nunits = SI\n"
    "[material copper]\ndensity = 8960\nyoungs_modulus = 72e9\npoisson_ratio = 0.3\n"
    "[particles]\nmethod = random\nmaterial = copper\ncount = 60\nradius = 25e-6\n"
    "distribution = uniform\nspread = 2.5e-6\nbox_min = 0 0 0\n"
    "box_max = 0.0004 0.0004 0.0004\nseed = 4\ntemperature = 1293\n"
    "[force gravity]\ngz = 0\n"
    "[stepper]\nkind = quasistatic\ndt = 1e-6\nend_time = 1\n"
    "[output]\ninterval = 1\nvtu = no\n"
    "[compact]\nbox_min = 0 0 0\nbox_max = 0.0002 0.0002 0.0002\nvolume_fraction = 0.7\n"
    "stop_at_jamming = yes\nvelocity = 1\n";

static void test_compact_section(void **state)
{
    (void)state;
    char text[4096];
    const char *section = strstr(COMPACT, "[compact]");
    const int head = (int)(section - COMPACT);
    /* [compact] is line 28, its keys 29-33; a line added at the end is 34 */
    snprintf(text, sizeof(text), "%.*s[compact]\nbox_min = 0 0 0\n", head, COMPACT);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:28:", "needs 'box_max");
    snprintf(text, sizeof(text), "%.*s[compact]\nbox_min = 0 0\nbox_max = 1 1 1\n", head, COMPACT);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:29:", "box_min: expected three");
    snprintf(text, sizeof(text), "%s%s", COMPACT, "friction = -0.5\n");
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:28:", "friction = -0.5");
    snprintf(text, sizeof(text),
             "%.*s[compact]\nbox_min = 0 0 0\nbox_max = 1 1 1\n"
             "velocity = fast\n",
             head, COMPACT);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:31:", "velocity: expected");
    snprintf(text, sizeof(text),
             "%.*s[compact]\nbox_min = 0 0 0\nbox_max = 1 1 1\n"
             "stop_at_jamming = maybe\n",
             head, COMPACT);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:31:", "yes or no");
    snprintf(text, sizeof(text),
             "%.*s[compact]\nbox_min = 0 0 0\n"
             "box_max = 0.0001 0.0001 0.0001\n",
             head, COMPACT);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:28:", "densest sphere packing");
    snprintf(text, sizeof(text), "%s%s", COMPACT, "wall_speed = 1\n");
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:34:", "unknown key 'wall_speed'");
    snprintf(text, sizeof(text), "%s%s", COMPACT, "[compact]\nbox_min = 0 0 0\nbox_max = 1 1 1\n");
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:34:", "only once");
    snprintf(text, sizeof(text), "%s%s", COMPACT, "[compaction]\n");
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:34:", "compact, output or fields");

    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("green.scene", COMPACT)), SINTER_OK);
    char out[512];
    snprintf(out, sizeof(out), "%s/green", dir);
    assert_int_equal(sinter_scene_run(scene, out, NULL, NULL), SINTER_OK);
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
    assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
    sinter_sintering_stats stats;
    stats.struct_size = sizeof(stats);
    assert_int_equal(sinter_stepper_sintering_stats(st, &stats), SINTER_OK);
    /* The 100-sphere packings of test_packing jam with coordination 3.7; 60 spheres in a box
     * 5 diameters wide have more of them at the walls: at least 2 links per sphere. */
    assert_true(stats.coordination > 2.0);
    const double *x = NULL, *r = NULL;
    size_t n = 0;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, &n, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL),
        SINTER_OK);
    assert_int_equal(n, 60);
    /* The jammed box starts at the origin (the principal planes of the stepper) and is far
     * smaller than the RSA box; the run (1 s of sintering) moves spheres by less than 1e-3 of
     * a radius, so 1 % of a radius is a wide margin for "inside". */
    double lo[3] = {1, 1, 1}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], x[3 * i + d] - r[i]);
            hi[d] = fmax(hi[d], x[3 * i + d] + r[i]);
        }
    for (int d = 0; d < 3; ++d) {
        assert_true(fabs(lo[d]) < 0.01 * 25e-6);
        assert_true(hi[d] < 0.0003);
    }
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_RADIUS);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

/* The keys of issue 37's outputs: [output] track, pair_reference, vtu_precision and a [fields]
 * section refuse what they cannot do, naming the line; a good [fields] section loads. */
static void test_output_and_fields_keys(void **state)
{
    (void)state;
    char text[4096];
    static const struct {
        const char *added, *status_text;
        sinter_status status;
    } bad[] = {
        {"track = 99\n", "track: a particle id", SINTER_ERR_PARSE},
        {"track = 1.5\n", "track: a particle id", SINTER_ERR_PARSE},
        {"track = 0 1 2 3 4 5 6 7 8\n", "at most 8", SINTER_ERR_PARSE},
        {"pair_reference = yes\n", "needs [stepper] kind = quasistatic", SINTER_ERR_PARSE},
        {"vtu_precision = half\n", "double or single", SINTER_ERR_PARSE},
        {"[fields]\ncutoff = 3\n", "needs 'width", SINTER_ERR_PARSE},
        {"[fields]\nwidth = -1\n", "width must be > 0", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\ncutoff = 20\n", "cutoff must be in [1, 10]", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\nbox_min = 0 0 0\n", "both box_min and box_max", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\nbox_min = 0 0 0\nbox_max = 1 0 1\n", "box_min < box_max",
         SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\nprofiles = xw\n", "profiles: expected", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\nlaminae = 2.5\n", "laminae must be a whole", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\n[fields]\nwidth = 1e-3\n", "only once", SINTER_ERR_PARSE},
        {"[fields]\nwidth = 1e-3\nkernel = lucy\n", "unknown key 'kernel'", SINTER_ERR_PARSE},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        snprintf(text, sizeof(text), "%s%s", GOOD, bad[k].added);
        expect_parse_error(text, bad[k].status, "broken.scene:", bad[k].status_text);
    }
    snprintf(text, sizeof(text), "%s%s", GOOD,
             "track = 0 5\nvtu_precision = single\n[fields]\nwidth = 1e-3\ncutoff = 4\n"
             "spacing = 5e-4\nbox_min = 0 0 0\nbox_max = 0.006 0.006 0.004\ngrid = no\n"
             "profiles = zx\nlaminae = 8\n");
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("fields.scene", text)), SINTER_OK);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

/* A quasi-static run (links, necks, plane conditions) restarted from a checkpoint continues bit
 * for bit, for the per-pair (2) and the CVODE batch (3) strategies; an explicit stepper refuses
 * a checkpoint holding links. The packing is a touching 2 x 2 x 2 cube (12 links). */
static void test_quasistatic_restart_is_bit_for_bit(void **state)
{
    (void)state;
    for (int strategy = 2; strategy <= 3; ++strategy) {
        char text[1024];
        snprintf(text, sizeof(text),
                 "[scene]\nname = qs\nunits = SI\n"
                 "[material copper]\ndensity = 8960\nyoungs_modulus = 72e9\n"
                 "[particles]\nmethod = list\nmaterial = copper\ntemperature = 1293\n"
                 "spheres = 25e-6 25e-6 25e-6 25e-6, 75e-6 25e-6 25e-6 25e-6, "
                 "25e-6 75e-6 25e-6 25e-6, 75e-6 75e-6 25e-6 25e-6, "
                 "25e-6 25e-6 75e-6 25e-6, 75e-6 25e-6 75e-6 25e-6, "
                 "25e-6 75e-6 75e-6 25e-6, 75e-6 75e-6 75e-6 25e-6\n"
                 "[stepper]\nkind = quasistatic\nqs_strategy = %d\ndt = 1e-6\nend_time = 40\n",
                 strategy);
        const char *path = write_file("qs_restart.scene", text);
        char ckpt[512];
        snprintf(ckpt, sizeof(ckpt), "%s/qs.ckpt", dir);
        double straight[24], restarted[24];
        sinter_sintering_stats a, b;
        for (int pass = 0; pass < 2; ++pass) {
            sinter_ctx *ctx = NULL;
            sinter_scene *scene = NULL;
            sinter_stepper *st = NULL;
            sinter_particles *ps = NULL;
            assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
            assert_int_equal(sinter_scene_load(&scene, ctx, path), SINTER_OK);
            assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
            assert_int_equal(sinter_scene_get_particles(scene, &ps), SINTER_OK);
            if (pass == 0) {
                assert_int_equal(sinter_stepper_advance(st, 20.0), SINTER_OK);
                assert_int_equal(sinter_checkpoint_write(st, ckpt), SINTER_OK);
            } else {
                assert_int_equal(sinter_checkpoint_read(st, ckpt), SINTER_OK);
            }
            assert_int_equal(sinter_stepper_advance(st, 40.0), SINTER_OK);
            const double *x = NULL;
            assert_int_equal(sinter_particles_view_read(ps, SINTER_FIELD_POSITION,
                                                        (const void **)&x, NULL, NULL),
                             SINTER_OK);
            memcpy(pass == 0 ? straight : restarted, x, sizeof(straight));
            assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_POSITION), SINTER_OK);
            sinter_sintering_stats *out = pass == 0 ? &a : &b;
            memset(out, 0, sizeof(*out));
            out->struct_size = sizeof(*out);
            assert_int_equal(sinter_stepper_sintering_stats(st, out), SINTER_OK);
            sinter_scene_destroy(scene);
            sinter_ctx_destroy(ctx);
        }
        assert_memory_equal(straight, restarted, sizeof(straight));
        print_message("strategy %d: %llu links, shrinkage x %.6e\n", strategy,
                      (unsigned long long)a.links, a.shrinkage[0]);
        assert_true(a.links == b.links && a.links == 12);
        assert_true(a.shrinkage[0] > 0.0);
        assert_true(a.neck_mean == b.neck_mean && a.shrinkage[0] == b.shrinkage[0]);
        assert_true(a.pcg_iterations == b.pcg_iterations);
    }
    /* an explicit stepper on the same particles cannot take the links */
    sinter_ctx *ctx = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    char ckpt[512];
    snprintf(ckpt, sizeof(ckpt), "%s/qs.ckpt", dir);
    assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
    assert_int_equal(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, NULL), SINTER_OK);
    assert_int_equal(sinter_checkpoint_read(st, ckpt), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "quasi-static"));
    size_t n = 1;
    assert_int_equal(sinter_particles_count(ps, &n), SINTER_OK);
    assert_int_equal(n, 0); /* nothing was changed */
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_ctx_destroy(ctx);
}

/* The [wall] kinds, spin and servo keys: a die of a cylinder with disc punches loads with each
 * wall of its kind and shape, a servo_pressure on a disc becomes the force P pi r^2 (checked
 * once the servo runs: the target at t = 0); bad kinds and missing keys are refused with the
 * file and line. */
static void test_wall_kinds_in_scenes(void **state)
{
    (void)state;
    const char *head =
        "[scene]\nname = die\nunits = SI\n"
        "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\n"
        "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = -0.001 -0.001 0.0005\n"
        "box_max = 0.001 0.001 0.002\nradius = 0.0005\nspacing = 0.00105\n";
    const char *walls =
        "[wall floor]\nkind = disc\npoint = 0 0 0\nnormal = 0 0 1\nradius = 0.003\nmaterial = "
        "glass\n"
        "[wall die]\nkind = cylinder\npoint = 0 0 0\naxis = 0 0 1\nradius = 0.003\n"
        "half_length = 0.01\ninside = yes\nspin = 2\nmaterial = glass\n"
        "[wall plate]\nkind = rectangle\npoint = 0 0 -0.001\nnormal = 0 0 1\nedge = 1 0 0\n"
        "half_lengths = 0.004 0.005\nmaterial = glass\n"
        "[wall punch]\nkind = disc\npoint = 0 0 0.0026\nnormal = 0 0 -1\nradius = 0.003\n"
        "material = glass\nmotion = servo\nservo_pressure = 1e3\nservo_kp = 0.1\n"
        "servo_vmax = 0.01\n";
    const char *tail = "[force hertz_mindlin]\n[stepper]\ndt = 1e-6\nend_time = 1e-5\n"
                       "[output]\ninterval = 1e-5\nvtu = yes\n";
    char text[4096];
    snprintf(text, sizeof(text), "%s%s%s", head, walls, tail);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("die.scene", text)), SINTER_OK);
    sinter_walls *w = NULL;
    assert_int_equal(sinter_scene_get_walls(scene, &w), SINTER_OK);
    const int kinds[4] = {SINTER_WALL_DISC, SINTER_WALL_CYLINDER, SINTER_WALL_RECTANGLE,
                          SINTER_WALL_DISC};
    for (size_t k = 0; k < 4; ++k) {
        int kind = -1;
        assert_int_equal(sinter_walls_get_kind(w, k, &kind), SINTER_OK);
        assert_int_equal(kind, kinds[k]);
    }
    double size[3];
    assert_int_equal(sinter_walls_get_shape(w, 1, NULL, NULL, size), SINTER_OK);
    assert_true(size[0] == 0.003 && size[1] == 0.01 && size[2] == 1.0);
    assert_int_equal(sinter_walls_get_shape(w, 2, NULL, NULL, size), SINTER_OK);
    assert_true(size[0] == 0.004 && size[1] == 0.005);
    double target = 0.0;
    assert_int_equal(sinter_walls_get_servo(w, 3, &target, NULL, NULL), SINTER_OK);
    assert_true(fabs(target - 1e3 * 3.14159265358979323846 * 0.003 * 0.003) < 1e-15);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);

    snprintf(text, sizeof(text), "%s[wall w]\nkind = cone\npoint = 0 0 0\nmaterial = glass\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "expected plane, rectangle, disc");
    snprintf(text, sizeof(text),
             "%s[wall w]\nkind = cylinder\npoint = 0 0 0\naxis = 0 0 1\n"
             "material = glass\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "needs 'radius = ...'");
    snprintf(text, sizeof(text),
             "%s[wall w]\nkind = disc\npoint = 0 0 0\nnormal = 0 0 1\n"
             "radius = 0\nmaterial = glass\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:", "radius 0 m");
    snprintf(text, sizeof(text),
             "%s[wall w]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
             "motion = servo\nservo_pressure = 1e3\nservo_kp = 1\nservo_vmax = 1\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "give servo_area");
}

/* kind = mesh: an STL file named relative to the scene, placed by scale, rotate [degrees] and
 * translate (a square in mm, facing -z, turned half a turn about x to face +z: the wall's
 * normal is the file's z axis turned, its point the translation); a missing file key and a
 * file with neighbours wound opposite ways are refused with the scene's file and line. */
static void test_mesh_wall_in_scenes(void **state)
{
    (void)state;
    const char *facet = " facet normal 0 0 -1\n  outer loop\n   vertex %s\n   vertex %s\n"
                        "   vertex %s\n  endloop\n endfacet\n";
    char stl[1024], one[256];
    snprintf(stl, sizeof(stl), "solid square\n");
    snprintf(one, sizeof(one), facet, "-5 -5 0", "5 5 0", "5 -5 0");
    strcat(stl, one);
    snprintf(one, sizeof(one), facet, "-5 -5 0", "-5 5 0", "5 5 0");
    strcat(stl, one);
    strcat(stl, "endsolid square\n");
    write_file("square.stl", stl);
    const char *head =
        "[scene]\nname = mesh\nunits = SI\n"
        "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\n"
        "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = -0.001 -0.001 0.0005\n"
        "box_max = 0.001 0.001 0.002\nradius = 0.0005\nspacing = 0.00105\n";
    const char *tail = "[force hertz_mindlin]\n[stepper]\ndt = 1e-6\nend_time = 1e-5\n";
    char text[4096];
    snprintf(text, sizeof(text),
             "%s[wall floor]\nkind = mesh\nfile = square.stl\nscale = 0.001\n"
             "rotate = 180 0 0\ntranslate = 0 0 -0.0001\nreach = 0.002\nmaterial = glass\n%s",
             head, tail);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("mesh.scene", text)), SINTER_OK);
    sinter_walls *w = NULL;
    assert_int_equal(sinter_scene_get_walls(scene, &w), SINTER_OK);
    int kind = -1;
    assert_int_equal(sinter_walls_get_kind(w, 0, &kind), SINTER_OK);
    assert_int_equal(kind, SINTER_WALL_MESH);
    double n[3], p[3];
    assert_int_equal(sinter_walls_get_normal(w, 0, n), SINTER_OK);
    assert_int_equal(sinter_walls_get_state(w, 0, p, NULL), SINTER_OK);
    assert_true(fabs(n[0]) < 1e-15 && fabs(n[1]) < 1e-15 && n[2] == -1.0);
    assert_true(p[0] == 0.0 && p[1] == 0.0 && p[2] == -0.0001);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);

    /* turning about an axis (rotation_axis, rotation_point, the rate from spin): the wall's
     * point becomes the axis point, its axis the one given (normalised) */
    snprintf(text, sizeof(text),
             "%s[wall floor]\nkind = mesh\nfile = square.stl\nscale = 0.001\n"
             "rotate = 180 0 0\ntranslate = 0 0 -0.0001\nmaterial = glass\nspin = 3\n"
             "rotation_axis = 0 0 2\nrotation_point = 0.001 0 -0.0001\n%s",
             head, tail);
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("mesh.scene", text)), SINTER_OK);
    assert_int_equal(sinter_scene_get_walls(scene, &w), SINTER_OK);
    double axis[3];
    assert_int_equal(sinter_walls_get_state(w, 0, p, NULL), SINTER_OK);
    assert_int_equal(sinter_walls_get_shape(w, 0, axis, NULL, NULL), SINTER_OK);
    assert_true(p[0] == 0.001 && p[1] == 0.0 && p[2] == -0.0001);
    assert_true(axis[0] == 0.0 && axis[1] == 0.0 && axis[2] == 1.0);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    snprintf(text, sizeof(text),
             "%s[wall w]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
             "rotation_axis = 0 0 1\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:", "is not a mesh");
    snprintf(text, sizeof(text),
             "%s[wall w]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
             "rotation_point = 0 0 1\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_PARSE,
                       "broken.scene:", "rotation_point needs rotation_axis");

    snprintf(text, sizeof(text), "%s[wall w]\nkind = mesh\nmaterial = glass\n%s", head, tail);
    expect_parse_error(text, SINTER_ERR_PARSE, "broken.scene:", "needs 'file = ...'");
    snprintf(one, sizeof(one), facet, "-5 -5 0", "5 5 0", "-5 5 0"); /* against its neighbour */
    snprintf(stl, sizeof(stl), "solid bad\n");
    strcat(stl, one);
    snprintf(one, sizeof(one), facet, "-5 -5 0", "5 5 0", "5 -5 0");
    strcat(stl, one);
    strcat(stl, "endsolid bad\n");
    write_file("bad.stl", stl);
    snprintf(text, sizeof(text), "%s[wall w]\nkind = mesh\nfile = bad.stl\nmaterial = glass\n%s",
             head, tail);
    expect_parse_error(text, SINTER_ERR_INVALID, "broken.scene:", "inconsistent normals");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_broken_scene_files),
        cmocka_unit_test(test_wall_kinds_in_scenes),
        cmocka_unit_test(test_mesh_wall_in_scenes),
        cmocka_unit_test(test_stream_stores_key),
        cmocka_unit_test(test_periodic_keys),
        cmocka_unit_test(test_restart_is_bit_for_bit),
        cmocka_unit_test(test_bad_checkpoints_are_refused),
        cmocka_unit_test(test_run_writes_outputs),
        cmocka_unit_test(test_quasistatic_scene_writes_neck_counts),
        cmocka_unit_test(test_property_tables),
        cmocka_unit_test(test_furnace_scene),
        cmocka_unit_test(test_scan_path_keys),
        cmocka_unit_test(test_temperature_bins),
        cmocka_unit_test(test_quasistatic_restart_is_bit_for_bit),
        cmocka_unit_test(test_compact_section),
        cmocka_unit_test(test_output_and_fields_keys),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
