#define _POSIX_C_SOURCE 200809L
/*
 * Bad input that used to get through (issue 35): paths cut to fit a buffer, scene names that
 * escape the output directory or break the SVG, wall normals lost to overflow, a duplicate key
 * among many, malformed particle and scene files, and scenes that `sinter check` passed but
 * whose run could not start or end. Each is refused with a message naming what is wrong.
 */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_support.h"

static char dir[256];

static int make_dir(void **state)
{
    (void)state;
    snprintf(dir, sizeof(dir), "/tmp/sinter_bad_input_XXXXXX");
    return mkdtemp(dir) == NULL ? -1 : 0;
}

static int remove_dir(void **state)
{
    (void)state;
    char cmd[512];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Write `length` bytes of `text` to `path`. */
static void write_bytes(const char *path, const char *text, size_t length)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, length, f), length);
    fclose(f);
}

static const char *in_dir(const char *name)
{
    static char path[512];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    return path;
}

static const char *write_file(const char *name, const char *text)
{
    const char *path = in_dir(name);
    write_bytes(path, text, strlen(text));
    return path;
}

/* A small valid scene (HEAD, then the particles, then TAIL): spheres dropped on a floor. */
static const char *HEAD =
    "[scene]\nname = drop\nunits = SI\n"
    "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\ndamping_ratio = 0.2\n"
    "friction_static = 0.3\nfriction_dynamic = 0.3\nfriction_damping_ratio = 0.2\n";
static const char *LATTICE = "[particles]\nmethod = lattice\nmaterial = glass\n"
                             "box_min = 0 0 0.0005\nbox_max = 0.003 0.003 0.002\n"
                             "radius = 0.0005\nspacing = 0.00105\n";
static const char *TAIL = "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\n"
                          "[force hertz_mindlin]\nrolling = 0\n"
                          "[force gravity]\n"
                          "[stepper]\ndt = 2e-5\nskin = 1e-4\nend_time = 0.01\n";
static const char *OUTPUT = "[output]\ninterval = 0.002\nvtu = no\ncheckpoint_interval = 0\n";

/* HEAD + particles + TAIL + extra, into text. */
static const char *scene_text(char *text, size_t size, const char *particles, const char *extra)
{
    snprintf(text, size, "%s%s%s%s", HEAD, particles, TAIL, extra);
    return text;
}

/* Load `path`: the status, and the message holding both fragments (NULL: not checked). */
static void expect_load(const char *path, sinter_status status, const char *fragment1,
                        const char *fragment2)
{
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_scene *scene = NULL;
    const sinter_status got = sinter_scene_load(&scene, ctx, path);
    const char *msg = sinter_last_error(ctx);
    if (got != status || (fragment1 && strstr(msg, fragment1) == NULL) ||
        (fragment2 && strstr(msg, fragment2) == NULL)) {
        print_error("status %s, message '%s'; expected %s with '%s' / '%s'\n",
                    sinter_status_name(got), msg, sinter_status_name(status),
                    fragment1 ? fragment1 : "", fragment2 ? fragment2 : "");
        fail();
    }
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void expect_text(const char *text, sinter_status status, const char *fragment1,
                        const char *fragment2)
{
    expect_load(write_file("bad.scene", text), status, fragment1, fragment2);
}

/* ---- 1. paths too long are refused, not cut ---------------------------------------------- */

/* dir, then "/./" repeated until the path is `length` bytes with `name` at its end. */
static void long_path(char *out, size_t size, size_t length, const char *name)
{
    int n = snprintf(out, size, "%s/", dir);
    while ((size_t)n + 2 + strlen(name) <= length)
        n += snprintf(out + n, size - (size_t)n, "./");
    if ((size_t)n + strlen(name) < length)
        out[n++] = '/';
    snprintf(out + n, size - (size_t)n, "%s", name);
    assert_int_equal(strlen(out), length);
}

static void test_long_checkpoint_path_is_refused(void **state)
{
    (void)state;
    char text[4096], path[8192];
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    sinter_stepper *st = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(
        sinter_scene_load(
            &scene, ctx, write_file("good.scene", scene_text(text, sizeof(text), LATTICE, OUTPUT))),
        SINTER_OK);
    assert_int_equal(sinter_scene_get_stepper(scene, &st), SINTER_OK);
    assert_int_equal(sinter_stepper_step(st, 0), SINTER_OK);
    /* 4095 bytes: the system takes the path, but not its temporary "<path>.tmp" */
    long_path(path, sizeof(path), 4095, "ck.bin");
    assert_int_equal(sinter_checkpoint_write(st, path), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "the path '"));
    assert_int_equal(access(path, F_OK), -1); /* nothing written under a cut name */
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_long_particle_file_path(void **state)
{
    (void)state;
    char text[8192], path[8192], particles[256];
    write_file("p.xyz", "0 0 0.001 0.0005\n0.002 0 0.001 0.0005\n");
    snprintf(particles, sizeof(particles),
             "[particles]\nmethod = file\nmaterial = glass\nfile = p.xyz\n");
    scene_text(text, sizeof(text), particles, OUTPUT);
    /* a scene whose directory is 3000 bytes long: its particle file is found */
    long_path(path, sizeof(path), 3000 + strlen("/s.scene"), "s.scene");
    write_bytes(path, text, strlen(text));
    expect_load(path, SINTER_OK, NULL, NULL);
    /* a directory and a file name together longer than the system allows: refused */
    char name[8192];
    long_path(name, sizeof(name), strlen(dir) + 1 + 4080, "p.xyz"); /* 4080 after dir/ */
    snprintf(particles, sizeof(particles), "[particles]\nmethod = file\nmaterial = glass\n");
    snprintf(text, sizeof(text), "%s%sfile = %s\n%s%s", HEAD, particles, name + strlen(dir) + 1,
             TAIL, OUTPUT);
    expect_text(text, SINTER_ERR_INVALID, "bad.scene:14: the path '", "the system allows");
}

/* ---- 2. scene names --------------------------------------------------------------------- */

static void expect_bad_name(const char *name, const char *why)
{
    char text[4096], head[512];
    snprintf(head, sizeof(head), "[scene]\nname = %s\nunits = SI\n", name);
    snprintf(text, sizeof(text), "%s%s%s%s%s", head, strstr(HEAD, "[material"), LATTICE, TAIL,
             OUTPUT);
    expect_text(text, SINTER_ERR_PARSE, "bad.scene:2: name:", why);
}

static void test_scene_names(void **state)
{
    (void)state;
    expect_bad_name("../escape", "'/'");
    expect_bad_name("a/b", "'/'");
    expect_bad_name("..", "'..'");
    expect_bad_name("a\xff"
                    "b",
                    "UTF-8");
    expect_bad_name("a\xc3", "UTF-8");         /* a sequence cut short */
    expect_bad_name("a\xc0\xaf", "UTF-8");     /* overlong '/' */
    expect_bad_name("a\xed\xa0\x80", "UTF-8"); /* a surrogate */
    expect_bad_name("a\x7f", "control");
    expect_bad_name("n123456789012345678901234567890123456789012345678901234567890123",
                    "longer than 63");
    /* a long material name would be cut and then not found: refused */
    char text[4096];
    snprintf(text, sizeof(text),
             "[scene]\nunits = SI\n"
             "[material m1234567890123456789012345678901234567890123456789012345678901234]\n");
    expect_text(text, SINTER_ERR_PARSE, "bad.scene:3:", "longer than 63");
}

/* A name with XML's special characters (and UTF-8) is escaped in the plot. */
static void test_scene_name_is_escaped_in_svg(void **state)
{
    (void)state;
    char text[4096], head[512];
    snprintf(head, sizeof(head), "[scene]\nname = a<b&c>\"d'\xc3\xa9\nunits = SI\n");
    snprintf(text, sizeof(text), "%s%s%s%s%s", head, strstr(HEAD, "[material"), LATTICE, TAIL,
             OUTPUT);
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("xml.scene", text)), SINTER_OK);
    assert_int_equal(sinter_scene_run(scene, in_dir("xml_out"), NULL, NULL), SINTER_OK);
    FILE *f = fopen(in_dir("xml_out/series.svg"), "r");
    assert_non_null(f);
    static char svg[1 << 20];
    const size_t n = fread(svg, 1, sizeof(svg) - 1, f);
    fclose(f);
    svg[n] = '\0';
    assert_non_null(strstr(svg, "a&lt;b&amp;c&gt;&quot;d&apos;\xc3\xa9"));
    assert_null(strstr(svg, "a<b"));
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

/* ---- 3. wall normals -------------------------------------------------------------------- */

static void expect_normal(sinter_walls *walls, sinter_material *m, double nx, double ny, double nz,
                          double ex, double ey, double ez)
{
    const double p[3] = {0, 0, 0}, n[3] = {nx, ny, nz};
    size_t k = 0;
    assert_int_equal(sinter_walls_add_plane(walls, p, n, m, &k), SINTER_OK);
    double got[3];
    assert_int_equal(sinter_walls_get_normal(walls, k, got), SINTER_OK);
    assert_close(got[0], ex, 1e-15);
    assert_close(got[1], ey, 1e-15);
    assert_close(got[2], ez, 1e-15);
}

static void test_wall_normals_of_any_scale(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_walls *walls = NULL;
    sinter_material *m = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_walls_create(&walls, ctx), SINTER_OK);
    assert_int_equal(sinter_material_create(&m, ctx, "steel"), SINTER_OK);
    expect_normal(walls, m, 1e200, 0, 0, 1, 0, 0);    /* the square overflows */
    expect_normal(walls, m, 0, -1e-200, 0, 0, -1, 0); /* the square underflows */
    expect_normal(walls, m, 3e300, 0, -4e300, 0.6, 0, -0.8);
    expect_normal(walls, m, 0, 3e-310, 4e-310, 0, 0.6, 0.8); /* subnormal */
    const double p[3] = {0, 0, 0}, zero[3] = {0, 0, 0};
    assert_int_equal(sinter_walls_add_plane(walls, p, zero, m, NULL), SINTER_ERR_INVALID);
    sinter_material_destroy(m);
    sinter_walls_destroy(walls);
    sinter_ctx_destroy(ctx);
}

/* ---- 4. a duplicate key among many ------------------------------------------------------- */

static void test_duplicate_key_among_many(void **state)
{
    (void)state;
    enum { KEYS = 20000 };
    static char text[KEYS * 24 + 1024];
    size_t n = (size_t)snprintf(text, sizeof(text), "[scene]\nunits = SI\n");
    for (int k = 0; k < KEYS; ++k)
        n += (size_t)snprintf(text + n, sizeof(text) - n, "key%d = %d\n", k, k);
    /* lines 1-2 are the header and units; key k is on line k + 3 */
    snprintf(text + n, sizeof(text) - n, "key%d = again\n", KEYS - 7);
    char fragment[128];
    snprintf(fragment, sizeof(fragment),
             "bad.scene:%d: key 'key%d' is given twice in [scene] (first on line %d)", KEYS + 3,
             KEYS - 7, KEYS - 7 + 3);
    expect_text(text, SINTER_ERR_PARSE, fragment, NULL);
}

/* ---- 5. malformed particle and scene files ---------------------------------------------- */

static void expect_particles(const char *file_line, const char *bytes, size_t length,
                             sinter_status status, const char *fragment1, const char *fragment2)
{
    write_bytes(in_dir("p.xyz"), bytes, length);
    char text[4096], particles[256];
    snprintf(particles, sizeof(particles), "[particles]\nmethod = file\nmaterial = glass\n%s\n",
             file_line);
    expect_text(scene_text(text, sizeof(text), particles, OUTPUT), status, fragment1, fragment2);
}

static void test_bad_particle_files(void **state)
{
    (void)state;
    static const char trailing[] = "0 0 0.001 0.0005\n0.002 0 0.001 0.0005 7\n";
    expect_particles("file = p.xyz", trailing, sizeof(trailing) - 1, SINTER_ERR_PARSE,
                     "p.xyz:2: expected 'x y z r' [m] and nothing after", "'7'");
    static const char nul[] = "0 0 0.001 0.0005\n0.002 0 0.001\0 0.0005\n";
    expect_particles("file = p.xyz", nul, sizeof(nul) - 1, SINTER_ERR_PARSE,
                     "p.xyz:2:", "a NUL byte inside the line");
    /* still fine: a comment after the radius, and spaces */
    static const char good[] = "0 0 0.001 0.0005   # one\n0.002 0 0.001 0.0005 \r\n";
    expect_particles("file = p.xyz", good, sizeof(good) - 1, SINTER_OK, NULL, NULL);
    assert_int_equal(mkdir(in_dir("adir"), 0700), 0);
    expect_particles("file = adir", good, sizeof(good) - 1, SINTER_ERR_INVALID,
                     "bad.scene:14: file: particle file '", "adir' is a directory, not a file");
}

static void test_bad_scene_files(void **state)
{
    (void)state;
    static const char nul[] = "[scene]\nunits\0 = SI\n";
    write_bytes(in_dir("bad.scene"), nul, sizeof(nul) - 1);
    expect_load(in_dir("bad.scene"), SINTER_ERR_PARSE,
                "bad.scene:2:", "a NUL byte inside the line");
    assert_int_equal(mkdir(in_dir("dir.scene"), 0700), 0);
    expect_load(in_dir("dir.scene"), SINTER_ERR_INVALID, "scene file '",
                "dir.scene' is a directory, not a file");
}

/* ---- 6. sinter_scene_check ---------------------------------------------------------------- */

/* Load text, then sinter_scene_check: its status and message. */
static void expect_scene_check(const char *text, sinter_status status, const char *fragment)
{
    sinter_ctx *ctx = NULL;
    sinter_scene *scene = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_scene_load(&scene, ctx, write_file("check.scene", text)), SINTER_OK);
    const sinter_status got = sinter_scene_check(scene);
    if (got != status || (fragment && strstr(sinter_last_error(ctx), fragment) == NULL)) {
        print_error("status %s, message '%s'; expected %s with '%s'\n", sinter_status_name(got),
                    sinter_last_error(ctx), sinter_status_name(status), fragment ? fragment : "");
        fail();
    }
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
}

static void test_scene_check(void **state)
{
    (void)state;
    char text[4096];
    assert_int_equal(sinter_scene_check(NULL), SINTER_ERR_NULL);
    expect_scene_check(scene_text(text, sizeof(text), LATTICE, OUTPUT), SINTER_OK, NULL);
    /* a particle below the floor */
    static const char *const below = "[particles]\nmethod = list\nmaterial = glass\n"
                                     "spheres = 0 0 0.001 0.0005, 0.002 0 -0.0001 0.0005\n";
    expect_scene_check(scene_text(text, sizeof(text), below, OUTPUT), SINTER_ERR_INVALID,
                       "particle 1 (id 1) is behind wall 0 (floor)");
    /* two particles with the same centre */
    static const char *const twice = "[particles]\nmethod = list\nmaterial = glass\n"
                                     "spheres = 0 0 0.001 0.0005, 0.002 0 0.001 0.0005, "
                                     "0 0 0.001 0.0004\n";
    expect_scene_check(scene_text(text, sizeof(text), twice, OUTPUT), SINTER_ERR_INVALID,
                       "particles 0 and 2 (ids 0 and 2) have the same centre");
    /* a particle outside the stepper's domain */
    char extra[512];
    snprintf(extra, sizeof(extra), "domain_min = -1 -1 -1\ndomain_max = 0.001 1 1\n%s", OUTPUT);
    expect_scene_check(scene_text(text, sizeof(text), LATTICE, extra), SINTER_ERR_INVALID,
                       "starts outside the domain: x = ");
}

static void test_output_intervals(void **state)
{
    (void)state;
    char text[4096];
    /* t + interval == t at the end time: the run would never end (refused at load) */
    expect_text(scene_text(text, sizeof(text), LATTICE, "[output]\ninterval = 1e-300\nvtu = no\n"),
                SINTER_ERR_INVALID, "bad.scene:30: output interval 1e-300 s cannot advance", NULL);
    /* 1e7 records over 0.01 s: more than max_frames = 1e6 */
    expect_text(scene_text(text, sizeof(text), LATTICE, "[output]\ninterval = 1e-9\nvtu = no\n"),
                SINTER_ERR_INVALID, "bad.scene:30:", "more than max_frames = 1000000");
    /* ... unless max_frames says so */
    expect_scene_check(scene_text(text, sizeof(text), LATTICE,
                                  "[output]\ninterval = 1e-9\nvtu = no\nmax_frames = 2e7\n"),
                       SINTER_OK, NULL);
    /* 6 records (t = 0 and five intervals) with max_frames = 5: refused; 6 is fine */
    expect_text(scene_text(text, sizeof(text), LATTICE,
                           "[output]\ninterval = 0.002\nvtu = no\nmax_frames = 5\n"),
                SINTER_ERR_INVALID, "makes 6 records", NULL);
    expect_scene_check(scene_text(text, sizeof(text), LATTICE,
                                  "[output]\ninterval = 0.002\nvtu = no\nmax_frames = 6\n"),
                       SINTER_OK, NULL);
    expect_text(
        scene_text(text, sizeof(text), LATTICE, "[output]\ninterval = 0.002\nmax_frames = 0.5\n"),
        SINTER_ERR_PARSE, "max_frames must be a whole number >= 1", NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_long_checkpoint_path_is_refused),
        cmocka_unit_test(test_long_particle_file_path),
        cmocka_unit_test(test_scene_names),
        cmocka_unit_test(test_scene_name_is_escaped_in_svg),
        cmocka_unit_test(test_wall_normals_of_any_scale),
        cmocka_unit_test(test_duplicate_key_among_many),
        cmocka_unit_test(test_bad_particle_files),
        cmocka_unit_test(test_bad_scene_files),
        cmocka_unit_test(test_scene_check),
        cmocka_unit_test(test_output_intervals),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}
