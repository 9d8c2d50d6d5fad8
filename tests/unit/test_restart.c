#define _POSIX_C_SOURCE 200809L
/*
 * Restart that continues a scene, stop requests and output that survives (issue 35), through
 * the library (the command line's tests are in tests/restart/): a scene's checkpoint into
 * another scene is refused naming the difference; a directory, an empty file or a file of
 * another kind given as a checkpoint gets a clear error at once; a stop request ends a run at
 * a step with the last accepted state, and the run continues from it bit for bit; an
 * unwritable output directory is reported before the first step; the CSV reads back.
 */
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_support.h"

#include <string.h>

#define OK(call) assert_int_equal((call), SINTER_OK)

static char dir[256];

static int make_dir(void **state)
{
    (void)state;
    snprintf(dir, sizeof(dir), "/tmp/sinter_restart_XXXXXX");
    return mkdtemp(dir) == NULL ? -1 : 0;
}

static int remove_dir(void **state)
{
    (void)state;
    char cmd[512];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *in_dir(const char *name)
{
    static char paths[4][512];
    static int next = 0;
    char *path = paths[next++ % 4];
    snprintf(path, 512, "%s/%s", dir, name);
    return path;
}

static const char *write_file(const char *name, const char *text)
{
    const char *path = in_dir(name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Spheres dropped on a floor between two side walls; %s: extra text at the end. */
#define SCENE(particles, walls, stepper)                                                           \
    "[scene]\nname = drop\nunits = SI\n"                                                           \
    "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\ndamping_ratio = 0.2\n"                \
    "friction_static = 0.3\nfriction_dynamic = 0.3\n"                                              \
    "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = 0 0 0.0005\n" particles            \
    "radius = 0.0005\nspacing = 0.00105\n" walls "[force hertz_mindlin]\n[force gravity]\n"        \
    "[stepper]\n" stepper "dt = 2e-6\nskin = 1e-4\nend_time = 0.006\n"                             \
    "[output]\ninterval = 0.001\nvtu = yes\ncheckpoint_interval = 0.002\n"
#define BOX "box_max = 0.006 0.006 0.004\n"
#define WALLS                                                                                      \
    "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"                              \
    "[wall side]\npoint = -0.001 0 0\nnormal = 1 0 0\nmaterial = glass\n"
#define SWAPPED                                                                                    \
    "[wall side]\npoint = -0.001 0 0\nnormal = 1 0 0\nmaterial = glass\n"                          \
    "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"

static sinter_scene *load(sinter_ctx *ctx, const char *name, const char *text)
{
    sinter_scene *scene = NULL;
    OK(sinter_scene_load(&scene, ctx, write_file(name, text)));
    return scene;
}

static double scene_time(sinter_scene *scene)
{
    sinter_stepper *st = NULL;
    double t = -1;
    OK(sinter_scene_get_stepper(scene, &st));
    OK(sinter_stepper_time(st, &t));
    return t;
}

static char *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char *data = calloc(1 << 22, 1);
    *size = fread(data, 1, (1 << 22) - 1, f);
    fclose(f);
    return data;
}

static void expect_refused(sinter_ctx *ctx, sinter_scene *scene, const char *checkpoint,
                           sinter_status status, const char *fragment)
{
    const sinter_status got = sinter_scene_restart(scene, checkpoint);
    if (got != status)
        print_error("%s\n", sinter_last_error(ctx));
    assert_int_equal(got, status);
    if (strstr(sinter_last_error(ctx), fragment) == NULL) {
        print_error("message '%s' lacks '%s'\n", sinter_last_error(ctx), fragment);
        fail();
    }
    assert_true(scene_time(scene) == 0.0); /* nothing changed */
}

static void test_checkpoint_of_another_scene_is_refused(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    OK(sinter_scene_run(scene, in_dir("a"), NULL, NULL));
    sinter_scene_destroy(scene);
    char checkpoint[600];
    snprintf(checkpoint, sizeof(checkpoint), "%s", in_dir("a/checkpoint.bin"));
    const struct {
        const char *text, *fragment;
    } others[] = {
        {SCENE(BOX, SWAPPED, ""), "wall 0 is 'floor' in the checkpoint, 'side' in the scene"},
        {SCENE("box_max = 0.006 0.006 0.003\n", WALLS, ""), "particles, the scene"},
        {SCENE(BOX, WALLS, "kind = staggered\n"),
         "the checkpoint's stepper is explicit, the scene's staggered"},
        {SCENE(BOX, "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n", ""),
         "has 2 walls, the stepper 1"},
    };
    for (size_t k = 0; k < sizeof(others) / sizeof(others[0]); ++k) {
        scene = load(ctx, "other.scene", others[k].text);
        expect_refused(ctx, scene, checkpoint, SINTER_ERR_INVALID, others[k].fragment);
        sinter_scene_destroy(scene);
    }
    /* a material renamed */
    char renamed[4096];
    snprintf(renamed, sizeof(renamed), "%s", SCENE(BOX, WALLS, ""));
    for (char *p = strstr(renamed, "glass"); p != NULL; p = strstr(p, "glass"))
        memcpy(p, "flint", 5);
    scene = load(ctx, "renamed.scene", renamed);
    expect_refused(ctx, scene, checkpoint, SINTER_ERR_INVALID,
                   "material 0 is 'glass' in the checkpoint, 'flint' in the scene");
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_bad_checkpoint_paths(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    /* a directory: refused at once (it used to be read as a file of 2^63 bytes) */
    expect_refused(ctx, scene, dir, SINTER_ERR_INVALID, "is a directory");
    expect_refused(ctx, scene, write_file("empty.bin", ""), SINTER_ERR_CORRUPT, "is empty");
    expect_refused(ctx, scene, write_file("text.bin", "time,kinetic energy\n0,0\n"),
                   SINTER_ERR_CORRUPT, "not a libsinter checkpoint");
    expect_refused(ctx, scene, in_dir("missing.bin"), SINTER_ERR_IO, "cannot open");
    /* a stepper's own checkpoint has no program to continue */
    sinter_stepper *st = NULL;
    OK(sinter_scene_get_stepper(scene, &st));
    OK(sinter_stepper_step(st, 0));
    OK(sinter_checkpoint_write(st, in_dir("stepper.bin")));
    assert_int_equal(sinter_scene_restart(scene, in_dir("stepper.bin")), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "no scene program"));
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

/* An observer that asks its context to stop after `after` steps. */
typedef struct stopper {
    sinter_ctx *ctx;
    int steps, after;
} stopper;

static int stop_after(const sinter_stepper *st, double time, void *user)
{
    (void)st;
    (void)time;
    stopper *s = user;
    if (++s->steps == s->after)
        OK(sinter_ctx_request_stop(s->ctx));
    return 0;
}

static void test_stop_request_ends_a_run_at_a_step(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *straight = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    sinter_scene *stopped = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    sinter_stepper *a = NULL, *b = NULL;
    OK(sinter_scene_get_stepper(straight, &a));
    OK(sinter_scene_get_stepper(stopped, &b));
    /* a request made while nothing runs stops the next run before its first step */
    OK(sinter_ctx_request_stop(ctx));
    assert_int_equal(sinter_stepper_advance(b, 0.001), SINTER_ERR_INTERRUPTED);
    assert_true(scene_time(stopped) == 0.0);
    /* ... and is withdrawn: a request during the run stops it after that step */
    stopper s = {ctx, 0, 37};
    OK(sinter_stepper_set_observer(b, stop_after, &s));
    assert_int_equal(sinter_stepper_advance(b, 0.001), SINTER_ERR_INTERRUPTED);
    assert_non_null(strstr(sinter_last_error(ctx), "stopped on request"));
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(b, &stats));
    assert_int_equal(stats.steps, 37);
    /* the run continues from there as if it had not stopped */
    OK(sinter_stepper_advance(b, 0.001));
    OK(sinter_stepper_advance(a, 0.001));
    sinter_particles *pa = NULL, *pb = NULL;
    OK(sinter_scene_get_particles(straight, &pa));
    OK(sinter_scene_get_particles(stopped, &pb));
    const void *xa = NULL, *xb = NULL;
    size_t na = 0, nb = 0, ca = 0, cb = 0;
    OK(sinter_particles_view_read(pa, SINTER_FIELD_POSITION, &xa, &na, &ca));
    OK(sinter_particles_view_read(pb, SINTER_FIELD_POSITION, &xb, &nb, &cb));
    assert_int_equal(na, nb);
    assert_memory_equal(xa, xb, na * 3 * sizeof(double)); /* bit for bit */
    OK(sinter_particles_release(pa, SINTER_FIELD_POSITION));
    OK(sinter_particles_release(pb, SINTER_FIELD_POSITION));
    sinter_scene_destroy(straight);
    sinter_scene_destroy(stopped);
    sinter_ctx_destroy(ctx);
}

static int stop_at_3ms(double time, double end_time, void *user)
{
    (void)end_time;
    (void)user;
    return time >= 0.003;
}

/* A scene run stopped by its progress callback writes the checkpoint and the plot; continued
 * in a fresh scene into the same directory, its files equal the straight run's. */
static void test_interrupted_scene_continues(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    OK(sinter_scene_run(scene, in_dir("straight"), NULL, NULL));
    sinter_scene_destroy(scene);
    scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    assert_int_equal(sinter_scene_run(scene, in_dir("stopped"), stop_at_3ms, NULL),
                     SINTER_ERR_INTERRUPTED);
    assert_non_null(strstr(sinter_last_error(ctx), "stopped by its progress callback"));
    struct stat info;
    assert_int_equal(stat(in_dir("stopped/series.svg"), &info), 0);
    sinter_scene_destroy(scene);
    scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    OK(sinter_scene_restart(scene, in_dir("stopped/checkpoint.bin")));
    OK(sinter_scene_run(scene, in_dir("stopped"), NULL, NULL));
    sinter_scene_destroy(scene);
    const char *files[] = {"series.csv", "series.svg", "drop.pvd", "checkpoint.bin",
                           "frames/frame_00006.vtu"};
    for (size_t k = 0; k < sizeof(files) / sizeof(files[0]); ++k) {
        char a[600], b[600];
        snprintf(a, sizeof(a), "%s/straight/%s", dir, files[k]);
        snprintf(b, sizeof(b), "%s/stopped/%s", dir, files[k]);
        size_t na = 0, nb = 0;
        char *da = slurp(a, &na), *db = slurp(b, &nb);
        assert_int_equal(na, nb);
        assert_memory_equal(da, db, na);
        free(da);
        free(db);
    }
    sinter_ctx_destroy(ctx);
}

static void note(int level, const char *message, void *user)
{
    (void)level;
    char *log = user;
    strncat(log, message, 4095 - strlen(log));
}

static void test_overrides_are_reported(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    OK(sinter_scene_run(scene, in_dir("a"), NULL, NULL));
    sinter_scene_destroy(scene);
    char text[4096];
    snprintf(text, sizeof(text), "%s", SCENE(BOX, WALLS, ""));
    memcpy(strstr(text, "dt = 2e-6"), "dt = 3e-6", 9);
    memcpy(strstr(text, "density = 2500"), "density = 2600", 14);
    scene = load(ctx, "b.scene", text);
    static char log[4096];
    OK(sinter_ctx_set_log(ctx, note, SINTER_LOG_INFO, log));
    OK(sinter_scene_restart(scene, in_dir("a/checkpoint.bin")));
    /* an edited dt of the explicit stepper wins (a warning); materials stay the checkpoint's */
    assert_non_null(strstr(log, "the scene's time step dt = 3.0000000000000001e-06 s replaces "
                                "the checkpoint's 1.9999999999999999e-06 s"));
    assert_non_null(strstr(log, "material 'glass' density = 2500 from the checkpoint replaces"));
    sinter_stepper *st = NULL;
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_scene_get_stepper(scene, &st));
    OK(sinter_stepper_get_stats(st, &stats));
    assert_true(stats.dt == 3e-6);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_unwritable_output_is_reported_before_the_first_step(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    sinter_scene *scene = load(ctx, "a.scene", SCENE(BOX, WALLS, ""));
    const char *file = write_file("plain_file", "x");
    char under_file[600];
    snprintf(under_file, sizeof(under_file), "%s/out", file);
    assert_int_equal(sinter_scene_run(scene, under_file, NULL, NULL), SINTER_ERR_IO);
    assert_true(scene_time(scene) == 0.0);
    if (geteuid() != 0) { /* root writes anywhere */
        const char *locked = in_dir("locked");
        assert_int_equal(mkdir(locked, 0555), 0);
        assert_int_equal(sinter_scene_run(scene, locked, NULL, NULL), SINTER_ERR_IO);
        assert_non_null(strstr(sinter_last_error(ctx), "cannot be written"));
        assert_true(scene_time(scene) == 0.0);
    }
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_series_reads_back(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    const char *names[3] = {"time", "a, \"quoted\" one", "plain"};
    const char *units[3] = {"s", "N", ""};
    sinter_series *s = NULL, *back = NULL;
    OK(sinter_series_create(&s, ctx, 3, names, units));
    const double rows[3][3] = {{0, 1.0 / 3.0, -2e-300}, {1, NAN, INFINITY}, {2, 5, 6}};
    for (int k = 0; k < 3; ++k)
        OK(sinter_series_append(s, rows[k]));
    const char *path = in_dir("s.csv");
    OK(sinter_series_write_csv(s, path));
    OK(sinter_series_read_csv(&back, ctx, path));
    size_t n = 0;
    OK(sinter_series_rows(back, &n));
    assert_int_equal(n, 3);
    double v = 0;
    OK(sinter_series_get(back, 0, 1, &v));
    assert_true(v == 1.0 / 3.0);
    OK(sinter_series_get(back, 0, 2, &v));
    assert_true(v == -2e-300);
    OK(sinter_series_get(back, 1, 1, &v));
    assert_true(isnan(v));
    sinter_series_destroy(back);
    /* written back: the same bytes */
    OK(sinter_series_read_csv(&back, ctx, path));
    OK(sinter_series_write_csv(back, in_dir("again.csv")));
    size_t na = 0, nb = 0;
    char *a = slurp(path, &na), *b = slurp(in_dir("again.csv"), &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na);
    free(a);
    free(b);
    sinter_series_destroy(back);
    /* a last line cut by a crash is left out; a malformed one names its line */
    OK(sinter_series_read_csv(&back, ctx, write_file("cut.csv", "time [s],x\n0,1\n1,2\n2,")));
    OK(sinter_series_rows(back, &n));
    assert_int_equal(n, 2);
    sinter_series_destroy(back);
    assert_int_equal(sinter_series_read_csv(&back, ctx, write_file("bad.csv", "t,x\n0,1\n1,\n")),
                     SINTER_ERR_PARSE);
    assert_non_null(strstr(sinter_last_error(ctx), "bad.csv:3: expected 2 numbers"));
    sinter_series_destroy(s);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_checkpoint_of_another_scene_is_refused),
        cmocka_unit_test(test_bad_checkpoint_paths),
        cmocka_unit_test(test_stop_request_ends_a_run_at_a_step),
        cmocka_unit_test(test_interrupted_scene_continues),
        cmocka_unit_test(test_overrides_are_reported),
        cmocka_unit_test(test_unwritable_output_is_reported_before_the_first_step),
        cmocka_unit_test(test_series_reads_back),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
