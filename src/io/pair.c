/*
 * Pair files (sinter_pair_run, `sinter pair`): the two-particle 7DOF model (src/neck) along a
 * temperature schedule read from a CSV file, for one pair or a population of pairs whose radii
 * are drawn from a size distribution, written as a neck-ratio and shrinkage series with its plot.
 * The file is a scene file (io/scene_text.c) with [scene], [material NAME] (the scene's reader,
 * scene_material_read) and one [pair] section, documented in docs/scene-reference.md.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io/path.h"
#include "io/scene.h"
#include "io/scene_text.h"
#include "neck/neck.h"

#define TRY(expr) SCENE_TRY(expr)

/* What a [pair] section asks for. */
typedef struct pair_plan {
    const char *material;     /* name of a [material NAME] section */
    double radius;            /* mean radius [m] */
    const char *distribution; /* "none" (every pair radius, radius), "uniform" or "normal" */
    double spread;            /* uniform: half-width; normal: standard deviation [m] */
    double pairs;             /* number of pairs drawn */
    double seed;              /* of the draw */
    const char *schedule;     /* CSV file: time [s], temperature [K] */
    const char *materials;    /* a file of [material NAME] sections, or NULL */
    double end_time;          /* [s]; default: the schedule's last time */
    double interval;          /* between outputs [s]; default: the run / 200 */
    double validity;          /* 0 off, 1 warn, 2 error (the neck model's guard) */
    double coordination;      /* neighbours a particle has, for the impingement limit */
    double green_density;     /* of the packing the pairs stand for */
} pair_plan;

static sinter_status optional(sinter_status st)
{
    return st == SINTER_ERR_NOT_FOUND ? SINTER_OK : st;
}

static sinter_status parse_error(scene_text *t, int line, const char *what)
{
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: %s", t->path, line, what);
}

static sinter_status read_plan(scene_text *t, scene_section *s, pair_plan *p)
{
    p->distribution = "none";
    p->pairs = 1.0;
    p->seed = 1.0;
    p->spread = 0.0;
    p->end_time = -1.0;
    p->interval = 0.0;
    p->validity = 1.0;
    p->coordination = 6.0;
    p->green_density = 0.6;
    p->material = p->schedule = p->materials = NULL;
    p->radius = 0.0;
    const struct {
        const char *key;
        const char **value;
    } words[] = {{"material", &p->material},
                 {"schedule", &p->schedule},
                 {"materials", &p->materials},
                 {"distribution", &p->distribution}};
    const struct {
        const char *key;
        double *value;
    } numbers[] = {{"radius", &p->radius},
                   {"spread", &p->spread},
                   {"pairs", &p->pairs},
                   {"seed", &p->seed},
                   {"end_time", &p->end_time},
                   {"output_interval", &p->interval},
                   {"validity", &p->validity},
                   {"coordination", &p->coordination},
                   {"green_density", &p->green_density}};
    for (size_t k = 0; k < sizeof(words) / sizeof(words[0]); ++k)
        TRY(optional(scene_get_word(t, s, words[k].key, words[k].value)));
    for (size_t k = 0; k < sizeof(numbers) / sizeof(numbers[0]); ++k)
        TRY(optional(scene_get_double(t, s, numbers[k].key, numbers[k].value)));
    if (p->material == NULL || p->schedule == NULL || !(p->radius > 0.0))
        return parse_error(t, s->line,
                           "[pair] needs 'material = NAME', 'schedule = FILE.csv' and "
                           "'radius = R' (> 0) [m]");
    if (strcmp(p->distribution, "none") != 0 && strcmp(p->distribution, "uniform") != 0 &&
        strcmp(p->distribution, "normal") != 0)
        return parse_error(t, scene_find(s, "distribution")->line,
                           "distribution: expected none, uniform or normal");
    if (!(p->spread >= 0.0 && p->spread < p->radius) || !(p->pairs >= 1.0 && p->pairs <= 1e6) ||
        p->pairs != floor(p->pairs) || !(p->seed >= 0.0) || p->seed != floor(p->seed))
        return parse_error(t, s->line,
                           "[pair]: expected 0 <= spread < radius, pairs a whole number in [1, "
                           "1e6] and seed a whole number >= 0");
    if (!(p->validity == 0.0 || p->validity == 1.0 || p->validity == 2.0) ||
        !(p->coordination >= 0.0 && p->coordination <= 100.0) ||
        !(p->green_density >= 0.0 && p->green_density <= 1.0) || !(p->interval >= 0.0))
        return parse_error(t, s->line,
                           "[pair]: expected validity 0, 1 or 2, coordination in [0, 100], "
                           "green_density in [0, 1] and output_interval >= 0");
    return SINTER_OK;
}

/* `file` relative to the folder of the pair file `path`. */
static sinter_status beside(sinter_ctx *ctx, const char *path, const char *file, char *out)
{
    const char *slash = strrchr(path, '/');
    if (file[0] == '/' || slash == NULL)
        return sinter_path_format(ctx, out, SINTER_PATH_SIZE, "%s", file);
    return sinter_path_format(ctx, out, SINTER_PATH_SIZE, "%.*s/%s", (int)(slash - path), path,
                              file);
}

/* The material `name`: its [material NAME] section in the pair file or else in the plan's
 * materials file, then the pair file's material parameters of its [pair] section (overrides). */
static sinter_status read_material(scene_text *t, scene_section *ps, const pair_plan *p,
                                   sinter_material *m)
{
    scene_text other;
    memset(&other, 0, sizeof(other));
    other.ctx = t->ctx;
    scene_text *where = t;
    scene_section *ms = NULL;
    sinter_status st = SINTER_OK;
    for (int pass = 0; pass < 2 && ms == NULL && st == SINTER_OK; ++pass) {
        if (pass == 1) {
            char file[SINTER_PATH_SIZE];
            if (p->materials == NULL)
                break;
            st = beside(t->ctx, t->path, p->materials, file);
            if (st == SINTER_OK)
                st = scene_text_read(&other, t->ctx, file);
            where = &other;
        }
        for (size_t k = 0; st == SINTER_OK && k < where->count; ++k)
            if (strcmp(where->sections[k].type, "material") == 0 &&
                strcmp(where->sections[k].name, p->material) == 0)
                ms = &where->sections[k];
    }
    if (st == SINTER_OK && ms == NULL)
        st = parse_error(t, scene_find(ps, "material")->line,
                         "material: expected the name of a [material NAME] section of this file "
                         "or of its 'materials' file");
    if (st == SINTER_OK)
        st = scene_material_read(where, ms, m);
    /* overrides: the [pair] lines that name a material parameter */
    for (size_t e = 0; st == SINTER_OK && e < ps->count; ++e) {
        sinter_material_param param;
        double v;
        if (ps->entries[e].used || sinter_material_param_find(ps->entries[e].key, &param))
            continue;
        st = scene_get_double(t, ps, ps->entries[e].key, &v);
        if (st == SINTER_OK)
            st = sinter_material_set(m, param, v);
        if (st != SINTER_OK && st != SINTER_ERR_PARSE) {
            char detail[SINTER_ERROR_TEXT_SIZE];
            snprintf(detail, sizeof(detail), "%s", sinter_last_error(t->ctx));
            st = sinter_fail(t->ctx, st, "%s:%d: %s", t->path, ps->entries[e].line, detail);
        }
    }
    scene_text_free(&other);
    return st;
}

/* The schedule's CSV (a header line, then time [s], temperature [K] per line). */
static sinter_status read_schedule_csv(sinter_ctx *ctx, const char *path, double **times,
                                       double **temps, size_t *n)
{
    sinter_series *series = NULL;
    TRY(sinter_series_read_csv(&series, ctx, path));
    sinter_status st = sinter_series_rows(series, n);
    double probe;
    if (st == SINTER_OK && (*n == 0 || sinter_series_get(series, 0, 1, &probe) != SINTER_OK))
        st = sinter_fail(ctx, SINTER_ERR_PARSE,
                         "%s: expected a header and rows 'time [s], temperature [K]'", path);
    if (st == SINTER_OK) {
        *times = sinter_calloc(ctx, *n, sizeof(double));
        *temps = sinter_calloc(ctx, *n, sizeof(double));
        if (*times == NULL || *temps == NULL)
            st = SINTER_ERR_NOMEM;
    }
    for (size_t k = 0; st == SINTER_OK && k < *n; ++k) {
        sinter_series_get(series, k, 0, &(*times)[k]);
        sinter_series_get(series, k, 1, &(*temps)[k]);
    }
    sinter_series_destroy(series);
    return st;
}

/* splitmix64: the pairs' radii, the same on every machine. */
static double uniform01(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return ((double)(z >> 11) + 0.5) * 0x1.0p-53;
}

/* A radius of the distribution: uniform in [R - spread, R + spread], or normal (Box-Muller)
 * truncated to R +- 3 spread by drawing again. */
static double draw_radius(const pair_plan *p, uint64_t *state)
{
    if (strcmp(p->distribution, "uniform") == 0)
        return p->radius + p->spread * (2.0 * uniform01(state) - 1.0);
    if (strcmp(p->distribution, "normal") == 0)
        for (;;) {
            const double u = uniform01(state), v = uniform01(state);
            const double z = sqrt(-2.0 * log(u)) * cos(2.0 * 3.14159265358979323846 * v);
            if (fabs(z) <= 3.0)
                return p->radius + p->spread * z;
        }
    return p->radius;
}

enum { COL_TIME, COL_T, COL_X, COL_S, COL_XMIN, COL_XMAX, COL_SMIN, COL_SMAX, COL_RHO, COL_FLAG };
#define PAIR_COLUMNS 10

/* The population's outputs: per pair and output time, x/R and shrinkage, reduced to the
 * series' rows with the validity flag (docs/7dof.md §2.6). */
static sinter_status write_outputs(sinter_ctx *ctx, const pair_plan *p, size_t n_out,
                                   const double *out_times, size_t n_times, const double *times,
                                   const double *temps, size_t pairs, const double *ratio,
                                   const double *shrink, const char *csv_path, const char *svg_path,
                                   const char *title)
{
    static const char *const names[PAIR_COLUMNS] = {
        "time",           "temperature",   "neck_ratio",    "shrinkage",        "neck_ratio_min",
        "neck_ratio_max", "shrinkage_min", "shrinkage_max", "relative_density", "past_limit"};
    static const char *const units[PAIR_COLUMNS] = {"s", "K", "1", "1", "1",
                                                    "1", "1", "1", "1", "1"};
    sinter_series *series = NULL;
    TRY(sinter_series_create(&series, ctx, PAIR_COLUMNS, names, units));
    const double ratio_limit = sinter_neck_impingement_ratio(p->coordination);
    int warned = 0;
    sinter_status st = SINTER_OK;
    for (size_t k = 0; k < n_out && st == SINTER_OK; ++k) {
        double row[PAIR_COLUMNS] = {out_times[k], 0,        0,         0, INFINITY,
                                    -INFINITY,    INFINITY, -INFINITY, 0, 0};
        /* the schedule's temperature, linear between its points, held outside */
        size_t j = 0;
        while (j + 1 < n_times && times[j + 1] <= out_times[k])
            ++j;
        row[COL_T] = j + 1 < n_times && out_times[k] > times[j]
                         ? temps[j] + (temps[j + 1] - temps[j]) * (out_times[k] - times[j]) /
                                          (times[j + 1] - times[j])
                         : temps[j];
        for (size_t q = 0; q < pairs; ++q) {
            const double x = ratio[q * n_out + k], s = shrink[q * n_out + k];
            row[COL_X] += x / (double)pairs;
            row[COL_S] += s / (double)pairs;
            row[COL_XMIN] = fmin(row[COL_XMIN], x);
            row[COL_XMAX] = fmax(row[COL_XMAX], x);
            row[COL_SMIN] = fmin(row[COL_SMIN], s);
            row[COL_SMAX] = fmax(row[COL_SMAX], s);
        }
        row[COL_RHO] = sinter_neck_pair_density(p->green_density, row[COL_S]);
        const int necks = row[COL_XMAX] > ratio_limit;
        const int dense = p->green_density > 0.0 && row[COL_RHO] > SINTER_NECK_DENSITY_LIMIT;
        row[COL_FLAG] = (double)(necks + 2 * dense);
        if (p->validity > 0.0 && (necks || dense) && !warned) {
            warned = 1;
            sinter_log(ctx, SINTER_LOG_WARNING,
                       "sinter_pair_run: %s at t = %.6g s (largest x/R %.4g, limit %.4g for %g "
                       "neighbours; relative density %.4g, limit %g; docs/7dof.md section 2.6)",
                       necks ? "the necks impinge" : "the relative density passed the model's",
                       out_times[k], row[COL_XMAX], ratio_limit, p->coordination, row[COL_RHO],
                       SINTER_NECK_DENSITY_LIMIT);
        }
        st = sinter_series_append(series, row);
    }
    if (st == SINTER_OK)
        st = sinter_series_write_csv(series, csv_path);
    if (st == SINTER_OK && svg_path != NULL) {
        const size_t start[5] = {0, 1, 4, 7, 8};
        const size_t columns[8] = {COL_T, COL_X,    COL_XMIN, COL_XMAX,
                                   COL_S, COL_SMIN, COL_SMAX, COL_RHO};
        st = sinter_series_write_svg(series, svg_path, title, COL_TIME, 4, start, columns);
    }
    sinter_series_destroy(series);
    return st;
}

/* Run the plan: every pair through sinter_neck_two_particles. */
static sinter_status run_plan(sinter_ctx *ctx, const pair_plan *p, const sinter_material *m,
                              size_t n_times, const double *times, const double *temps,
                              const char *csv_path, const char *svg_path, const char *title)
{
    const double t0 = times[0];
    const double end = p->end_time >= 0.0 ? p->end_time : times[n_times - 1];
    if (!(end > t0))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_pair_run: the end time %g s must lie after the schedule's "
                           "start %g s",
                           end, t0);
    const double interval = p->interval > 0.0 ? p->interval : (end - t0) / 200.0;
    const double steps = ceil((end - t0) / interval * (1.0 - 1e-12));
    if (!(steps <= 1e6))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_pair_run: output_interval %g s gives more than 1e6 outputs",
                           interval);
    const size_t n_out = (size_t)steps + 1, pairs = (size_t)p->pairs;
    double *out_times = sinter_calloc(ctx, n_out, sizeof(double));
    double *ratio = sinter_calloc(ctx, n_out * pairs, sizeof(double));
    double *shrink = sinter_calloc(ctx, n_out * pairs, sizeof(double));
    sinter_neck_model *nm = NULL;
    sinter_status st =
        out_times && ratio && shrink ? sinter_neck_model_create(&nm, ctx) : SINTER_ERR_NOMEM;
    for (size_t k = 0; k < n_out && out_times != NULL; ++k)
        out_times[k] = k + 1 == n_out ? end : t0 + (double)k * interval;
    /* the guard's error mode stops at the first pair past a limit; the population's warning is
     * written once, with the flags (write_outputs) */
    if (st == SINTER_OK)
        st = sinter_neck_model_set(nm, "validity", p->validity == 2.0 ? 2.0 : 0.0);
    if (st == SINTER_OK)
        st = sinter_neck_model_set(nm, "validity_coordination", p->coordination);
    if (st == SINTER_OK)
        st = sinter_neck_model_set(nm, "validity_green_density", p->green_density);
    uint64_t state = (uint64_t)p->seed;
    for (size_t q = 0; q < pairs && st == SINTER_OK; ++q) {
        const double ra = draw_radius(p, &state), rb = draw_radius(p, &state);
        double *x = ratio + q * n_out, *s = shrink + q * n_out;
        st = sinter_neck_two_particles(nm, m, ra, rb, n_times, times, temps, n_out, out_times, x, s,
                                       NULL);
        for (size_t k = 0; k < n_out; ++k)
            x[k] /= fmin(ra, rb);
    }
    if (st == SINTER_OK)
        st = write_outputs(ctx, p, n_out, out_times, n_times, times, temps, pairs, ratio, shrink,
                           csv_path, svg_path, title);
    sinter_neck_model_destroy(nm);
    sinter_free(ctx, out_times);
    sinter_free(ctx, ratio);
    sinter_free(ctx, shrink);
    return st;
}

static sinter_status find_sections(scene_text *t, scene_section **pair, const char **name)
{
    *pair = NULL;
    *name = NULL;
    for (size_t k = 0; k < t->count; ++k) {
        scene_section *s = &t->sections[k];
        if (strcmp(s->type, "pair") == 0) {
            if (*pair != NULL)
                return parse_error(t, s->line, "a pair file has one [pair] section");
            *pair = s;
        } else if (strcmp(s->type, "scene") == 0) {
            const char *units = NULL;
            TRY(optional(scene_get_word(t, s, "units", &units)));
            TRY(optional(scene_get_word(t, s, "name", name)));
            if (units != NULL && strcmp(units, "SI") != 0)
                return parse_error(t, s->line, "units: expected SI");
        } else if (strcmp(s->type, "material") != 0) {
            return parse_error(t, s->line,
                               "a pair file holds [scene], [material NAME] and [pair] sections");
        }
    }
    if (*pair == NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s: no [pair] section", t->path);
    return SINTER_OK;
}

sinter_status sinter_pair_run(sinter_ctx *ctx, const char *path, const char *csv_path,
                              const char *svg_path)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, path);
    SINTER_CHECK_NULL(ctx, csv_path);
    scene_text t;
    memset(&t, 0, sizeof(t));
    TRY(scene_text_read(&t, ctx, path));
    scene_section *ps = NULL;
    const char *name = NULL;
    pair_plan plan;
    sinter_material *m = NULL;
    double *times = NULL, *temps = NULL;
    size_t n_times = 0;
    sinter_status st = find_sections(&t, &ps, &name);
    if (st == SINTER_OK)
        st = read_plan(&t, ps, &plan);
    if (st == SINTER_OK)
        st = sinter_material_create(&m, ctx, plan.material);
    if (st == SINTER_OK)
        st = read_material(&t, ps, &plan, m);
    char schedule[SINTER_PATH_SIZE];
    if (st == SINTER_OK)
        st = beside(ctx, path, plan.schedule, schedule);
    if (st == SINTER_OK)
        st = read_schedule_csv(ctx, schedule, &times, &temps, &n_times);
    if (st == SINTER_OK)
        st = scene_check_unused(&t);
    if (st == SINTER_OK)
        st = run_plan(ctx, &plan, m, n_times, times, temps, csv_path, svg_path, name);
    sinter_free(ctx, times);
    sinter_free(ctx, temps);
    sinter_material_destroy(m);
    scene_text_free(&t);
    return st;
}
