/*
 * A heat model's scan path in a scene (issue 40): "scan_path = FILE" (vertices "x y speed
 * level" per line) or a hatch ("hatch = x0 y0 x1 y1" with its spacing, angle and speeds), and
 * "scan_start" [s]. See docs/scene-reference.md, "Scan paths".
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/path.h"
#include "io/scene_scan.h"
#include "io/text_file.h"

static const double PI = 3.14159265358979323846;

/* The vertices read so far from a scan path file. */
typedef struct scan_file {
    sinter_ctx *ctx;
    const char *path;
    double *points; /* 4 per vertex */
    size_t count, capacity;
} scan_file;

/* One line "x y speed level" (commas allowed; blank or '#': nothing). */
static sinter_status scan_line(void *user, int line, char *text)
{
    scan_file *f = user;
    char *hash = strchr(text, '#');
    if (hash)
        *hash = '\0';
    for (char *c = text; *c; ++c)
        if (*c == ',' || *c == ';')
            *c = ' ';
    double v[4];
    int used = 0;
    const int n = sscanf(text, "%lf %lf %lf %lf%n", &v[0], &v[1], &v[2], &v[3], &used);
    if (n <= 0)
        return SINTER_OK;
    const char *rest = n == 4 ? text + used : "";
    while (*rest == ' ' || *rest == '\t' || *rest == '\r')
        ++rest;
    if (n != 4 || *rest != '\0')
        return sinter_fail(f->ctx, SINTER_ERR_PARSE,
                           "%s:%d: expected 'x y speed level' ([m] [m] [m/s] [0..1]) and nothing "
                           "after",
                           f->path, line);
    const int first = f->count == 0;
    if (!isfinite(v[0]) || !isfinite(v[1]) || (!first && !(v[2] > 0.0 && isfinite(v[2]))) ||
        (!first && !(v[3] >= 0.0 && v[3] <= 1.0)))
        return sinter_fail(f->ctx, SINTER_ERR_PARSE,
                           "%s:%d: a vertex needs a finite position, a speed > 0 and a level in "
                           "[0, 1] (got %g %g %g %g; the first vertex's speed and level are "
                           "ignored)",
                           f->path, line, v[0], v[1], v[2], v[3]);
    sinter_status st =
        sinter_grow(f->ctx, (void **)&f->points, &f->capacity, 4 * (f->count + 1), sizeof(double));
    if (st != SINTER_OK)
        return st;
    memcpy(f->points + 4 * f->count, v, sizeof(v));
    f->count++;
    return SINTER_OK;
}

static sinter_status read_scan_file(scene_text *t, const char *directory, scene_section *s,
                                    double **points, size_t *count)
{
    const char *file = NULL;
    SCENE_TRY(scene_get_word(t, s, "scan_path", &file));
    const int line = scene_find(s, "scan_path")->line;
    char path[SINTER_PATH_SIZE];
    sinter_status st = file[0] == '/'
                           ? sinter_path_format(t->ctx, path, SINTER_PATH_SIZE, "%s", file)
                           : sinter_path_join(t->ctx, path, SINTER_PATH_SIZE, directory, file);
    if (st != SINTER_OK)
        return st;
    char where[SINTER_PATH_SIZE + 32];
    snprintf(where, sizeof(where), "%s:%d: scan_path: ", t->path, line);
    FILE *fp = NULL;
    SCENE_TRY(sinter_text_open(t->ctx, where, "scan path file", path, &fp));
    scan_file f = {t->ctx, path, NULL, 0, 0};
    char buf[512];
    st = sinter_text_each_line(t->ctx, fp, path, "a scan path file", buf, sizeof(buf), scan_line,
                               &f);
    fclose(fp);
    if (st == SINTER_OK && f.count < 2)
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                         "%s: a scan path needs at least 2 vertices, the file has %zu", path,
                         f.count);
    if (st != SINTER_OK) {
        sinter_free(t->ctx, f.points);
        return st;
    }
    *points = f.points;
    *count = f.count;
    return SINTER_OK;
}

/* An optional number: *out keeps its default when the key is absent. */
static sinter_status scene_get_optional(scene_text *t, scene_section *s, const char *key,
                                        double *out)
{
    const sinter_status st = scene_get_double(t, s, key, out);
    return st == SINTER_ERR_NOT_FOUND ? SINTER_OK : st;
}

static sinter_status read_hatch(scene_text *t, scene_section *s, double **points, size_t *count)
{
    double *box = NULL;
    size_t n = 0;
    SCENE_TRY(scene_get_numbers(t, s, "hatch", &box, &n));
    const int line = scene_find(s, "hatch")->line;
    double spacing = NAN, angle = 0.0, speed = NAN, jump = NAN;
    int serpentine = 1;
    sinter_status st = n == 4 ? SINTER_OK
                              : sinter_fail(t->ctx, SINTER_ERR_PARSE,
                                            "%s:%d: hatch: expected 'x0 y0 x1 y1' [m], got %zu "
                                            "numbers",
                                            t->path, line, n);
    if (st == SINTER_OK)
        st = scene_get_double(t, s, "hatch_spacing", &spacing);
    if (st == SINTER_OK)
        st = scene_get_double(t, s, "hatch_speed", &speed);
    if (st == SINTER_OK)
        st = scene_get_optional(t, s, "hatch_angle", &angle);
    if (st == SINTER_OK) {
        jump = speed;
        st = scene_get_optional(t, s, "hatch_jump_speed", &jump);
    }
    if (st == SINTER_OK) {
        st = scene_get_bool(t, s, "hatch_serpentine", &serpentine);
        st = st == SINTER_ERR_NOT_FOUND ? SINTER_OK : st;
    }
    if (st == SINTER_ERR_NOT_FOUND)
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                         "%s:%d: hatch: hatch_spacing and hatch_speed are required", t->path, line);
    const double lo[2] = {n == 4 ? fmin(box[0], box[2]) : 0.0, n == 4 ? fmin(box[1], box[3]) : 0.0};
    const double hi[2] = {n == 4 ? fmax(box[0], box[2]) : 0.0, n == 4 ? fmax(box[1], box[3]) : 0.0};
    sinter_free(t->ctx, box);
    size_t m = 0;
    const double radians = angle * PI / 180.0;
    if (st == SINTER_OK)
        st = sinter_scan_hatch(t->ctx, lo, hi, spacing, radians, speed, jump, serpentine, NULL, 0,
                               &m);
    double *pts = NULL;
    if (st == SINTER_OK && m < 2)
        st = sinter_fail(t->ctx, SINTER_ERR_INVALID, "%s:%d: hatch: no line crosses the rectangle",
                         t->path, line);
    if (st == SINTER_OK && (pts = sinter_alloc(t->ctx, 4 * m * sizeof(double))) == NULL)
        st = sinter_last_status(t->ctx);
    if (st == SINTER_OK)
        st = sinter_scan_hatch(t->ctx, lo, hi, spacing, radians, speed, jump, serpentine, pts, m,
                               &m);
    if (st != SINTER_OK) {
        sinter_free(t->ctx, pts);
        return st == SINTER_ERR_INVALID || st == SINTER_ERR_RANGE
                   ? sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: hatch: %s", t->path, line,
                                 sinter_last_error(t->ctx))
                   : st;
    }
    *points = pts;
    *count = m;
    return SINTER_OK;
}

sinter_status scene_heat_scan(scene_text *t, const char *directory, scene_section *s,
                              sinter_heat_model *hm)
{
    const int by_file = scene_find(s, "scan_path") != NULL,
              by_hatch = scene_find(s, "hatch") != NULL;
    if (!by_file && !by_hatch)
        return SINTER_OK;
    if (by_file && by_hatch)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: give a scan path either as scan_path (a file) or as a hatch, "
                           "not both",
                           t->path, scene_find(s, "hatch")->line);
    double start = 0.0;
    SCENE_TRY(scene_get_optional(t, s, "scan_start", &start));
    double *points = NULL;
    size_t n = 0;
    SCENE_TRY(by_file ? read_scan_file(t, directory, s, &points, &n)
                      : read_hatch(t, s, &points, &n));
    const int line = scene_find(s, by_file ? "scan_path" : "hatch")->line;
    const sinter_status st = sinter_heat_model_set_scan_path(hm, n, points, start);
    sinter_free(t->ctx, points);
    if (st != SINTER_OK)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: %s", t->path, line,
                           sinter_last_error(t->ctx));
    return SINTER_OK;
}

int scene_heat_scan_key(const char *key)
{
    static const char *const keys[] = {"scan_path",        "scan_start",      "hatch",
                                       "hatch_spacing",    "hatch_angle",     "hatch_speed",
                                       "hatch_jump_speed", "hatch_serpentine"};
    for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); ++k)
        if (strcmp(key, keys[k]) == 0)
            return 1;
    return 0;
}
