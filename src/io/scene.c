/*
 * Scene files: from sections to objects. The format is described in
 * docs/scene-reference.md. Every problem is reported as "file:line: ...".
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/file_name.h"
#include "io/scene.h"
#include "io/scene_text.h"
#include "io/text_file.h"
#include "particles/compact.h"

#define TRY(expr) SCENE_TRY(expr)

/* A getter whose key may be absent. */
#define OPTIONAL(expr)                                                                             \
    do {                                                                                           \
        sinter_status opt_st_ = (expr);                                                            \
        if (opt_st_ != SINTER_OK && opt_st_ != SINTER_ERR_NOT_FOUND)                               \
            return opt_st_;                                                                        \
    } while (0)

static sinter_status section_error(scene_text *t, const scene_section *s, const char *what)
{
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: [%s%s%s]: %s", t->path, s->line, s->type,
                       *s->name ? " " : "", s->name, what);
}

static sinter_status required(scene_text *t, scene_section *s, sinter_status st, const char *key)
{
    if (st != SINTER_ERR_NOT_FOUND)
        return st;
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: [%s%s%s] needs '%s = ...'", t->path,
                       s->line, s->type, *s->name ? " " : "", s->name, key);
}

/* Re-label an object's own error (e.g. an invalid material value) with the file and line. */
static sinter_status at_line(scene_text *t, int line, sinter_status st)
{
    if (st == SINTER_OK || st == SINTER_ERR_PARSE)
        return st;
    char detail[SINTER_ERROR_TEXT_SIZE];
    snprintf(detail, sizeof(detail), "%s", sinter_last_error(t->ctx));
    return sinter_fail(t->ctx, st, "%s:%d: %s", t->path, line, detail);
}

static int find_material(const sinter_scene *sc, const char *name)
{
    for (size_t k = 0; k < sc->material_count; ++k)
        if (strcmp(sc->material_names[k], name) == 0)
            return (int)k;
    return -1;
}

static sinter_status material_ref(scene_text *t, sinter_scene *sc, scene_section *s, int *id)
{
    const char *name = NULL;
    TRY(required(t, s, scene_get_word(t, s, "material", &name), "material"));
    *id = find_material(sc, name);
    if (*id < 0) {
        const scene_entry *e = scene_find(s, "material");
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: material: expected the name of a [material NAME] section "
                           "above, got '%s'",
                           t->path, e->line, name);
    }
    return SINTER_OK;
}

static sinter_status build_scene_header(scene_text *t, sinter_scene *sc, scene_section *s)
{
    const char *units = NULL;
    TRY(required(t, s, scene_get_word(t, s, "units", &units), "units"));
    if (strcmp(units, "SI") != 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: units: expected SI (m, kg, s, K, N, Pa, W, A, V), got '%s'",
                           t->path, scene_find(s, "units")->line, units);
    const char *name = NULL;
    OPTIONAL(scene_get_word(t, s, "name", &name));
    if (name == NULL)
        return SINTER_OK;
    /* the name makes the file name <name>.pvd in the output directory and the plot's title */
    const char *problem = sinter_file_name_problem(name);
    if (problem == NULL && strlen(name) >= sizeof(sc->name))
        problem = "it is longer than " SCENE_NAME_TEXT " bytes";
    if (problem != NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: name: expected a file name without '/', '..' or control "
                           "characters, in UTF-8, but %s",
                           t->path, scene_find(s, "name")->line, problem);
    snprintf(sc->name, sizeof(sc->name), "%s", name);
    return SINTER_OK;
}

sinter_status scene_material_read(scene_text *t, scene_section *s, sinter_material *m)
{
    for (size_t e = 0; e < s->count; ++e) {
        scene_entry *en = &s->entries[e];
        sinter_material_param p;
        if (sinter_material_param_find(en->key, &p) != SINTER_OK)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: '%s' is not a material parameter (see "
                               "sinter_material_param_info for the list)",
                               t->path, en->line, en->key);
        double v;
        TRY(scene_get_double(t, s, en->key, &v));
        TRY(at_line(t, en->line, sinter_material_set(m, p, v)));
    }
    return SINTER_OK;
}

static sinter_status build_material(scene_text *t, sinter_scene *sc, scene_section *s)
{
    if (*s->name == '\0')
        return section_error(t, s, "a material needs a name: [material NAME]");
    if (strlen(s->name) >= SCENE_NAME)
        return section_error(t, s, "the name is longer than " SCENE_NAME_TEXT " bytes");
    if (find_material(sc, s->name) >= 0)
        return section_error(t, s, "this material name is used twice");
    if (sc->material_count == SCENE_MAX_MATERIALS)
        return section_error(t, s, "too many materials");
    sinter_material *m = NULL;
    TRY(at_line(t, s->line, sinter_material_create(&m, t->ctx, s->name)));
    sc->materials[sc->material_count] = m;
    snprintf(sc->material_names[sc->material_count], SCENE_NAME, "%s", s->name);
    TRY(at_line(t, s->line, sinter_particles_set_material(sc->ps, (int32_t)sc->material_count, m)));
    sc->material_count++;
    TRY(scene_material_read(t, s, m));
    /* Register the final values. */
    return at_line(t, s->line,
                   sinter_particles_set_material(sc->ps, (int32_t)sc->material_count - 1, m));
}

/* One line "x y z r" [m] of a particle file (blank or a '#' comment: nothing). */
static sinter_status particle_line(scene_text *t, sinter_scene *sc, scene_section *s,
                                   const char *path, int line, char *text, int mat,
                                   double temperature)
{
    char *hash = strchr(text, '#');
    if (hash)
        *hash = '\0';
    double row[4];
    int used = 0;
    const int n = sscanf(text, "%lf %lf %lf %lf%n", &row[0], &row[1], &row[2], &row[3], &used);
    if (n <= 0)
        return SINTER_OK;
    if (n != 4)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: expected 'x y z r' [m]", path, line);
    const char *rest = text + used;
    while (*rest == ' ' || *rest == '\t' || *rest == '\r')
        ++rest;
    if (*rest != '\0')
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: expected 'x y z r' [m] and nothing after, got '%.40s' after "
                           "the radius",
                           path, line, rest);
    return at_line(t, s->line,
                   sinter_particles_add(sc->ps, 1, row, &row[3], mat, temperature, NULL));
}

static sinter_status read_xyzr_file(scene_text *t, sinter_scene *sc, scene_section *s, int mat,
                                    double temperature)
{
    const char *file = NULL;
    TRY(required(t, s, scene_get_word(t, s, "file", &file), "file"));
    char path[SINTER_PATH_SIZE];
    const int line_of_file = scene_find(s, "file")->line;
    TRY(at_line(t, line_of_file,
                file[0] == '/'
                    ? sinter_path_format(t->ctx, path, sizeof(path), "%s", file)
                    : sinter_path_join(t->ctx, path, sizeof(path), sc->directory, file)));
    char where[SINTER_PATH_SIZE + 32];
    snprintf(where, sizeof(where), "%s:%d: file: ", t->path, line_of_file); /* a message prefix */
    FILE *f = NULL;
    TRY(sinter_text_open(t->ctx, where, "particle file", path, &f));
    int line = 0;
    sinter_status st = SINTER_OK;
    char buf[512];
    while (st == SINTER_OK) {
        const sinter_line_result got = sinter_text_line(f, buf, sizeof(buf));
        if (got == SINTER_LINE_END)
            break;
        ++line;
        if (got == SINTER_LINE_OK)
            st = particle_line(t, sc, s, path, line, buf, mat, temperature);
        else if (got == SINTER_LINE_TOO_LONG) /* also ends an endless line (/dev/zero) */
            st = sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: line longer than %zu characters",
                             path, line, sizeof(buf) - 1);
        else if (got == SINTER_LINE_NUL)
            st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                             "%s:%d: a NUL byte inside the line (a particle file is text)", path,
                             line);
        else
            st = sinter_fail(t->ctx, SINTER_ERR_IO, "%s:%d: error reading the file: %s", path, line,
                             strerror(errno));
    }
    fclose(f);
    return st;
}

static sinter_status build_particles(scene_text *t, sinter_scene *sc, scene_section *s)
{
    int mat = 0;
    TRY(material_ref(t, sc, s, &mat));
    double temperature = 293.15;
    OPTIONAL(scene_get_double(t, s, "temperature", &temperature));
    const char *method = NULL;
    TRY(required(t, s, scene_get_word(t, s, "method", &method), "method"));
    if (strcmp(method, "file") == 0)
        return read_xyzr_file(t, sc, s, mat, temperature);
    if (strcmp(method, "list") == 0) {
        double *v = NULL;
        size_t n = 0;
        TRY(required(t, s, scene_get_numbers(t, s, "spheres", &v, &n), "spheres"));
        sinter_status st = SINTER_OK;
        if (n % 4 != 0)
            st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                             "%s:%d: spheres: expected groups of 'x y z r' [m], got %zu numbers",
                             t->path, scene_find(s, "spheres")->line, n);
        for (size_t k = 0; k + 3 < n && st == SINTER_OK; k += 4)
            st = at_line(t, s->line,
                         sinter_particles_add(sc->ps, 1, v + k, v + k + 3, mat, temperature, NULL));
        sinter_free(t->ctx, v);
        return st;
    }
    double lo[3], hi[3], radius = 0.0;
    TRY(required(t, s, scene_get_vec3(t, s, "box_min", lo), "box_min"));
    TRY(required(t, s, scene_get_vec3(t, s, "box_max", hi), "box_max"));
    TRY(required(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
    if (strcmp(method, "lattice") == 0) {
        double spacing = 2.0 * radius;
        OPTIONAL(scene_get_double(t, s, "spacing", &spacing));
        return at_line(
            t, s->line,
            sinter_pack_lattice(sc->ps, lo, hi, radius, spacing, mat, temperature, NULL));
    }
    if (strcmp(method, "random") != 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: method: expected random, lattice, list or file, got '%s'",
                           t->path, scene_find(s, "method")->line, method);
    sinter_packing_options o;
    TRY(sinter_packing_options_init(&o, sizeof(o)));
    memcpy(o.box_min, lo, sizeof(lo));
    memcpy(o.box_max, hi, sizeof(hi));
    o.radius_mean = radius;
    o.material = mat;
    o.temperature = temperature;
    double count = 0, seed = 1;
    TRY(required(t, s, scene_get_double(t, s, "count", &count), "count"));
    OPTIONAL(scene_get_double(t, s, "seed", &seed));
    OPTIONAL(scene_get_double(t, s, "spread", &o.radius_spread));
    OPTIONAL(scene_get_double(t, s, "radius_min", &o.radius_min));
    OPTIONAL(scene_get_double(t, s, "radius_max", &o.radius_max));
    OPTIONAL(scene_get_double(t, s, "gap", &o.gap));
    const char *dist = "monodisperse";
    OPTIONAL(scene_get_word(t, s, "distribution", &dist));
    if (strcmp(dist, "monodisperse") == 0)
        o.distribution = SINTER_RADII_MONODISPERSE;
    else if (strcmp(dist, "uniform") == 0)
        o.distribution = SINTER_RADII_UNIFORM;
    else if (strcmp(dist, "normal") == 0)
        o.distribution = SINTER_RADII_NORMAL;
    else
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: distribution: expected monodisperse, uniform or normal, got "
                           "'%s'",
                           t->path, scene_find(s, "distribution")->line, dist);
    /* Bounded before the conversions below (a double beyond the integer type is UB). */
    if (!(count >= 0 && count <= 1e12) || count != floor(count) ||
        !(seed >= 0 && seed < 18446744073709551616.0) || seed != floor(seed))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: [particles]: count = %g and seed = %g must be whole numbers "
                           "in [0, 1e12] and [0, 2^64)",
                           t->path, s->line, count, seed);
    o.seed = (uint64_t)seed;
    size_t placed = 0;
    TRY(at_line(t, s->line, sinter_pack_random(sc->ps, &o, (size_t)count, &placed)));
    if (placed < (size_t)count)
        return sinter_fail(t->ctx, SINTER_ERR_INVALID,
                           "%s:%d: only %zu of %zu spheres fit in the box by random sequential "
                           "addition; enlarge the box or lower the count",
                           t->path, s->line, placed, (size_t)count);
    return SINTER_OK;
}

/*
 * A schedule "KEY = t v, t v, ..." of a section (a wall's temperature or electric value, the
 * stepper's furnace): the times [s] and values in new arrays (free both), *count 0 when the key
 * is absent, *line the key's line. `units` names the pair in messages ("t T' [s, K"). Errors:
 * SINTER_ERR_PARSE (not pairs of numbers), SINTER_ERR_NOMEM.
 */
static sinter_status read_schedule(scene_text *t, scene_section *s, const char *key,
                                   const char *units, double **times, double **values,
                                   size_t *count, int *line)
{
    *times = *values = NULL;
    *count = 0;
    double *tv = NULL;
    size_t ntv = 0;
    sinter_status st = scene_get_numbers(t, s, key, &tv, &ntv);
    OPTIONAL(st);
    if (st != SINTER_OK)
        return SINTER_OK;
    *line = scene_find(s, key)->line;
    st = SINTER_OK;
    if (ntv % 2 != 0)
        st =
            sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: %s: expected pairs '%s], got %zu numbers",
                        t->path, *line, key, units, ntv);
    if (st == SINTER_OK) {
        *times = sinter_calloc(t->ctx, ntv / 2 + 1, sizeof(double));
        *values = sinter_calloc(t->ctx, ntv / 2 + 1, sizeof(double));
        if (*times == NULL || *values == NULL)
            st = SINTER_ERR_NOMEM;
    }
    for (size_t k = 0; k < ntv / 2 && st == SINTER_OK; ++k) {
        (*times)[k] = tv[2 * k];
        (*values)[k] = tv[2 * k + 1];
    }
    sinter_free(t->ctx, tv);
    if (st == SINTER_OK)
        *count = ntv / 2;
    return st;
}

static sinter_status read_temperature_schedule(scene_text *t, scene_section *s, double **times,
                                               double **temps, size_t *count, int *line)
{
    return read_schedule(t, s, "temperature_schedule", "t T' [s, K", times, temps, count, line);
}

/* A wall's electric_schedule, electric_pulse and electric_limit (walls/electric_drive.c). */
static sinter_status build_wall_drive(scene_text *t, sinter_scene *sc, scene_section *s,
                                      size_t index)
{
    double *times = NULL, *values = NULL;
    size_t points = 0;
    int line = 0;
    sinter_status st = read_schedule(t, s, "electric_schedule", "t value' [s, A or V", &times,
                                     &values, &points, &line);
    if (st == SINTER_OK && points > 0)
        st = at_line(t, line,
                     sinter_walls_set_electric_schedule(sc->walls, index, points, times, values));
    sinter_free(t->ctx, times);
    sinter_free(t->ctx, values);
    TRY(st);
    double *pulse = NULL;
    size_t n = 0;
    st = scene_get_numbers(t, s, "electric_pulse", &pulse, &n);
    OPTIONAL(st);
    if (st == SINTER_OK) {
        line = scene_find(s, "electric_pulse")->line;
        st = n == 2 ? at_line(t, line,
                              sinter_walls_set_electric_pulse(sc->walls, index, pulse[0], pulse[1]))
                    : sinter_fail(t->ctx, SINTER_ERR_PARSE,
                                  "%s:%d: electric_pulse: expected 'on off' [s, s], got %zu "
                                  "numbers",
                                  t->path, line, n);
        sinter_free(t->ctx, pulse);
        TRY(st);
    }
    double limit = 0.0;
    st = scene_get_double(t, s, "electric_limit", &limit);
    OPTIONAL(st);
    if (st == SINTER_OK)
        TRY(at_line(t, scene_find(s, "electric_limit")->line,
                    sinter_walls_set_electric_limit(sc->walls, index, limit)));
    return SINTER_OK;
}

static sinter_status build_wall(scene_text *t, sinter_scene *sc, scene_section *s)
{
    size_t index = 0, nw = 0;
    TRY(sinter_walls_count(sc->walls, &nw));
    if (nw == SCENE_MAX_WALLS)
        return section_error(t, s, "too many walls");
    if (strlen(s->name) >= SCENE_NAME)
        return section_error(t, s, "the name is longer than " SCENE_NAME_TEXT " bytes");
    double point[3], normal[3];
    int mat = 0;
    TRY(required(t, s, scene_get_vec3(t, s, "point", point), "point"));
    TRY(required(t, s, scene_get_vec3(t, s, "normal", normal), "normal"));
    TRY(material_ref(t, sc, s, &mat));
    TRY(at_line(t, s->line,
                sinter_walls_add_plane(sc->walls, point, normal, sc->materials[mat], &index)));
    snprintf(sc->wall_names[index], SCENE_NAME, "%s", *s->name ? s->name : "wall");
    double temperature;
    sinter_status st = scene_get_double(t, s, "temperature", &temperature);
    OPTIONAL(st);
    if (st == SINTER_OK)
        TRY(at_line(t, scene_find(s, "temperature")->line,
                    sinter_walls_set_temperature(sc->walls, index, temperature)));
    double *heat_times = NULL, *heat_temps = NULL;
    size_t heat_points = 0;
    int heat_line = 0;
    st = read_temperature_schedule(t, s, &heat_times, &heat_temps, &heat_points, &heat_line);
    if (st == SINTER_OK && heat_points > 0)
        st = at_line(t, heat_line,
                     sinter_walls_set_temperature_schedule(sc->walls, index, heat_points,
                                                           heat_times, heat_temps));
    sinter_free(t->ctx, heat_times);
    sinter_free(t->ctx, heat_temps);
    TRY(st);
    const char *electric = NULL;
    st = scene_get_word(t, s, "electric", &electric);
    OPTIONAL(st);
    if (st == SINTER_OK) {
        const int mode = strcmp(electric, "neutral") == 0     ? SINTER_WALL_NEUTRAL
                         : strcmp(electric, "current") == 0   ? SINTER_WALL_CURRENT
                         : strcmp(electric, "potential") == 0 ? SINTER_WALL_POTENTIAL
                                                              : -1;
        if (mode < 0)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: electric: expected neutral, current or potential, got '%s'",
                               t->path, scene_find(s, "electric")->line, electric);
        double value = 0.0;
        if (mode != SINTER_WALL_NEUTRAL)
            TRY(required(t, s, scene_get_double(t, s, "electric_value", &value), "electric_value"));
        TRY(at_line(t, scene_find(s, "electric")->line,
                    sinter_walls_set_electric(sc->walls, index, mode, value)));
    }
    TRY(build_wall_drive(t, sc, s, index));
    const char *motion = "fixed";
    OPTIONAL(scene_get_word(t, s, "motion", &motion));
    if (strcmp(motion, "fixed") == 0)
        return SINTER_OK;
    if (strcmp(motion, "velocity") == 0) {
        double u[3];
        TRY(required(t, s, scene_get_vec3(t, s, "velocity", u), "velocity"));
        return at_line(t, s->line, sinter_walls_set_velocity(sc->walls, index, u));
    }
    if (strcmp(motion, "sine") == 0) {
        double amplitude[3], omega = 0;
        TRY(required(t, s, scene_get_vec3(t, s, "amplitude", amplitude), "amplitude"));
        TRY(required(t, s, scene_get_double(t, s, "omega", &omega), "omega"));
        return at_line(t, s->line, sinter_walls_set_sine(sc->walls, index, amplitude, omega));
    }
    if (strcmp(motion, "schedule") == 0) {
        double *v = NULL;
        size_t n = 0;
        TRY(required(t, s, scene_get_numbers(t, s, "schedule", &v, &n), "schedule"));
        sinter_status st2 = SINTER_OK;
        if (n % 4 != 0) {
            st2 = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                              "%s:%d: schedule: expected groups of 't dx dy dz' [s, m], got %zu "
                              "numbers",
                              t->path, scene_find(s, "schedule")->line, n);
        } else {
            const size_t points = n / 4;
            double *times = sinter_calloc(t->ctx, points, sizeof(double));
            double *disp = sinter_calloc(t->ctx, 3 * points, sizeof(double));
            if (times == NULL || disp == NULL)
                st2 = SINTER_ERR_NOMEM;
            for (size_t k = 0; k < points && st2 == SINTER_OK; ++k) {
                times[k] = v[4 * k];
                memcpy(disp + 3 * k, v + 4 * k + 1, 3 * sizeof(double));
            }
            if (st2 == SINTER_OK)
                st2 = at_line(t, scene_find(s, "schedule")->line,
                              sinter_walls_set_schedule(sc->walls, index, points, times, disp));
            sinter_free(t->ctx, times);
            sinter_free(t->ctx, disp);
        }
        sinter_free(t->ctx, v);
        return st2;
    }
    return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                       "%s:%d: motion: expected fixed, velocity, schedule or sine, got '%s'",
                       t->path, scene_find(s, "motion")->line, motion);
}

static sinter_status build_force(scene_text *t, sinter_scene *sc, scene_section *s)
{
    if (*s->name == '\0')
        return section_error(t, s, "name the model: [force hertz_mindlin], [force gravity], ...");
    if (sc->force_count == SCENE_MAX_FORCES)
        return section_error(t, s, "too many force models");
    sinter_force_model *fm = NULL;
    sinter_status st = sinter_force_model_create(&fm, t->ctx, s->name);
    if (st != SINTER_OK)
        return at_line(t, s->line, st);
    sc->forces[sc->force_count++] = fm;
    for (size_t e = 0; e < s->count; ++e) {
        scene_entry *en = &s->entries[e];
        double v;
        TRY(scene_get_double(t, s, en->key, &v));
        TRY(at_line(t, en->line, sinter_force_model_set(fm, en->key, v)));
    }
    return at_line(t, s->line, sinter_stepper_add_force(sc->st, fm));
}

/* "KEY_schedule = t v, t v, ..." makes parameter KEY follow a piecewise-linear schedule. */
static sinter_status heat_schedule(scene_text *t, scene_section *s, scene_entry *en,
                                   sinter_heat_model *hm)
{
    char key[128];
    snprintf(key, sizeof(key), "%.*s", (int)(strlen(en->key) - strlen("_schedule")), en->key);
    double *v = NULL;
    size_t n = 0;
    TRY(scene_get_numbers(t, s, en->key, &v, &n));
    sinter_status st = SINTER_OK;
    double *times = NULL, *values = NULL;
    if (n % 2 != 0) {
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                         "%s:%d: %s: expected pairs 't value', got %zu numbers", t->path, en->line,
                         en->key, n);
    } else {
        times = sinter_calloc(t->ctx, n / 2 + 1, sizeof(double));
        values = sinter_calloc(t->ctx, n / 2 + 1, sizeof(double));
        if (times == NULL || values == NULL)
            st = SINTER_ERR_NOMEM;
        for (size_t k = 0; k < n / 2 && st == SINTER_OK; ++k) {
            times[k] = v[2 * k];
            values[k] = v[2 * k + 1];
        }
        if (st == SINTER_OK)
            st =
                at_line(t, en->line, sinter_heat_model_set_schedule(hm, key, n / 2, times, values));
    }
    sinter_free(t->ctx, v);
    sinter_free(t->ctx, times);
    sinter_free(t->ctx, values);
    return st;
}

static sinter_status build_heat(scene_text *t, sinter_scene *sc, scene_section *s)
{
    if (*s->name == '\0')
        return section_error(t, s, "name the model: [heat conduction], [heat laser], ...");
    if (sc->heat_count == SCENE_MAX_FORCES)
        return section_error(t, s, "too many heat models");
    sinter_heat_model *hm = NULL;
    sinter_status st = sinter_heat_model_create(&hm, t->ctx, s->name);
    if (st != SINTER_OK)
        return at_line(t, s->line, st);
    sc->heats[sc->heat_count++] = hm;
    for (size_t e = 0; e < s->count; ++e) {
        scene_entry *en = &s->entries[e];
        const size_t len = strlen(en->key), suffix = strlen("_schedule");
        if (len > suffix && strcmp(en->key + len - suffix, "_schedule") == 0) {
            TRY(heat_schedule(t, s, en, hm));
            continue;
        }
        double v;
        TRY(scene_get_double(t, s, en->key, &v));
        TRY(at_line(t, en->line, sinter_heat_model_set(hm, en->key, v)));
    }
    return at_line(t, s->line, sinter_stepper_add_heat(sc->st, hm));
}

static sinter_status build_electric(scene_text *t, sinter_scene *sc, scene_section *s)
{
    if (*s->name == '\0')
        return section_error(t, s, "name the model: [electric averaged] or [electric network]");
    sinter_status st = sinter_electric_model_create(&sc->electric, t->ctx, s->name);
    if (st != SINTER_OK)
        return at_line(t, s->line, st);
    for (size_t e = 0; e < s->count; ++e) {
        scene_entry *en = &s->entries[e];
        double v;
        TRY(scene_get_double(t, s, en->key, &v));
        TRY(at_line(t, en->line, sinter_electric_model_set(sc->electric, en->key, v)));
    }
    return at_line(t, s->line, sinter_stepper_set_electric(sc->st, sc->electric));
}

/* "temperature_schedule = t T, t T, ..." in [stepper]: the furnace every particle follows
 * (sinter_stepper_set_furnace), timed like the wall motions (from the end of a pour). */
static sinter_status build_furnace(scene_text *t, sinter_scene *sc, scene_section *s)
{
    double *times = NULL, *temps = NULL;
    size_t points = 0;
    int line = 0;
    sinter_status st = read_temperature_schedule(t, s, &times, &temps, &points, &line);
    if (st == SINTER_OK && points > 0)
        st = at_line(t, line, sinter_stepper_set_furnace(sc->st, points, times, temps));
    sinter_free(t->ctx, times);
    sinter_free(t->ctx, temps);
    return st;
}

static sinter_status build_stepper(scene_text *t, sinter_scene *sc, scene_section *s)
{
    const char *kind = "explicit";
    OPTIONAL(scene_get_word(t, s, "kind", &kind));
    const int staggered = strcmp(kind, "staggered") == 0;
    const int quasistatic = strcmp(kind, "quasistatic") == 0;
    if (strcmp(kind, "explicit") != 0 && !staggered && !quasistatic)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: kind: expected explicit, staggered or quasistatic, got '%s'",
                           t->path, scene_find(s, "kind")->line, kind);
    if (staggered || quasistatic) /* the scene's stepper was created explicit, before [stepper] */
        TRY(at_line(t, scene_find(s, "kind")->line,
                    sinter_stepper_set_kind(sc->st, staggered ? SINTER_STEPPER_STAGGERED
                                                              : SINTER_STEPPER_QUASISTATIC)));
    /* Options of the quasi-static stepper (seed 001 sec. 3.3): every "qs_*" key. */
    for (size_t e = 0; e < s->count; ++e) {
        scene_entry *en = &s->entries[e];
        if (strncmp(en->key, "qs_", 3) != 0)
            continue;
        double value;
        TRY(scene_get_double(t, s, en->key, &value));
        TRY(at_line(t, en->line, sinter_stepper_set_option(sc->st, en->key, value)));
    }
    /* The spatial sort and the rotation vector (any kind but quasi-static), the explicit
     * stepper's streaming stores and the options of the staggered stepper (seed 000 sec. 3,
     * 6; the explicit one refuses those). */
    static const char *const options[] = {"sort_interval",
                                          "rotation",
                                          "stream_stores",
                                          "thread_choice",
                                          "phi",
                                          "target_iterations",
                                          "tolerance",
                                          "exponent",
                                          "dt_min",
                                          "dt_max",
                                          "adaptive",
                                          "position_tolerance",
                                          "temperature_tolerance"};
    for (size_t k = 0; k < sizeof(options) / sizeof(options[0]); ++k) {
        double value;
        const sinter_status got = scene_get_double(t, s, options[k], &value);
        OPTIONAL(got);
        if (got == SINTER_OK)
            TRY(at_line(t, scene_find(s, options[k])->line,
                        sinter_stepper_set_option(sc->st, options[k], value)));
    }
    TRY(required(t, s, scene_get_double(t, s, "end_time", &sc->end_time), "end_time"));
    if (!(sc->end_time > 0))
        return section_error(t, s, "end_time must be > 0 s");
    TRY(build_furnace(t, sc, s));
    const char *thermal = "explicit";
    OPTIONAL(scene_get_word(t, s, "thermal", &thermal));
    if (strcmp(thermal, "explicit") != 0 && strcmp(thermal, "implicit") != 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: thermal: expected explicit or implicit, got '%s'", t->path,
                           scene_find(s, "thermal")->line, thermal);
    const scene_entry *thermal_entry = scene_find(s, "thermal");
    TRY(at_line(t, thermal_entry ? thermal_entry->line : s->line,
                sinter_stepper_set_thermal_scheme(sc->st, strcmp(thermal, "implicit") == 0
                                                              ? SINTER_THERMAL_IMPLICIT
                                                              : SINTER_THERMAL_EXPLICIT)));
    double skin;
    sinter_status st = scene_get_double(t, s, "skin", &skin);
    OPTIONAL(st);
    if (st == SINTER_OK)
        TRY(at_line(t, scene_find(s, "skin")->line, sinter_stepper_set_skin(sc->st, skin)));
    double lo[3], hi[3];
    st = scene_get_vec3(t, s, "domain_min", lo);
    OPTIONAL(st);
    if (st == SINTER_OK) {
        TRY(required(t, s, scene_get_vec3(t, s, "domain_max", hi), "domain_max"));
        TRY(at_line(t, s->line, sinter_stepper_set_domain(sc->st, lo, hi)));
    }
    /* dt last: "auto" needs the particles and walls (seed 003 eq. 47). */
    scene_entry *e = scene_find(s, "dt");
    if (e == NULL)
        return required(t, s, SINTER_ERR_NOT_FOUND, "dt");
    double dt = 0;
    if (strncmp(e->value, "auto", 4) == 0) {
        double v_rel = 1.0;
        OPTIONAL(scene_get_double(t, s, "impact_speed", &v_rel));
        TRY(at_line(t, e->line, sinter_stable_dt_hertz(sc->ps, sc->walls, v_rel, &dt)));
    } else {
        TRY(scene_get_double(t, s, "dt", &dt));
    }
    return at_line(t, e->line, sinter_stepper_set_dt(sc->st, dt));
}

static sinter_status build_pour(scene_text *t, sinter_scene *sc, scene_section *s)
{
    sc->pour = 1;
    TRY(required(t, s, scene_get_double(t, s, "ke_per_particle", &sc->pour_ke), "ke_per_particle"));
    sc->pour_t_min = 0;
    OPTIONAL(scene_get_double(t, s, "t_min", &sc->pour_t_min));
    TRY(required(t, s, scene_get_double(t, s, "t_max", &sc->pour_t_max), "t_max"));
    if (!(sc->pour_ke > 0) || sc->pour_t_min < 0 || sc->pour_t_max < sc->pour_t_min)
        return section_error(t, s, "need ke_per_particle > 0 J and 0 <= t_min <= t_max [s]");
    return SINTER_OK;
}

/* [compact]: sinter_pack_compact's options, checked against the particles now, run by
 * sinter_scene_run before the run (after [pour]). */
static sinter_status build_compact(scene_text *t, sinter_scene *sc, scene_section *s)
{
    sinter_compaction_options *o = &sc->compact_options;
    TRY(sinter_compaction_options_init(o, sizeof(*o)));
    sc->compact = 1;
    TRY(required(t, s, scene_get_vec3(t, s, "box_min", o->box_min), "box_min"));
    TRY(required(t, s, scene_get_vec3(t, s, "box_max", o->box_max), "box_max"));
    const struct {
        const char *key;
        double *value;
    } numbers[] = {
        {"volume_fraction", &o->volume_fraction}, {"friction", &o->friction},
        {"restitution", &o->restitution},         {"velocity", &o->velocity},
        {"max_pressure", &o->max_pressure},       {"ke_per_particle", &o->ke_per_particle},
        {"relax_time_max", &o->relax_time_max},   {"dt", &o->dt}};
    for (size_t k = 0; k < sizeof(numbers) / sizeof(numbers[0]); ++k)
        OPTIONAL(scene_get_double(t, s, numbers[k].key, numbers[k].value));
    OPTIONAL(scene_get_bool(t, s, "stop_at_jamming", &o->stop_at_jamming));
    return at_line(t, s->line, sinter_compaction_check(sc->ps, o));
}

static sinter_status build_output(scene_text *t, sinter_scene *sc, scene_section *s)
{
    TRY(required(t, s, scene_get_double(t, s, "interval", &sc->output_interval), "interval"));
    if (!(sc->output_interval > 0))
        return section_error(t, s, "interval must be > 0 s");
    OPTIONAL(scene_get_bool(t, s, "vtu", &sc->write_vtu));
    const char *format = NULL;
    OPTIONAL(scene_get_word(t, s, "vtu_format", &format));
    if (format != NULL) {
        if (strcmp(format, "binary") != 0 && strcmp(format, "ascii") != 0)
            return section_error(t, s, "vtu_format must be binary or ascii");
        sc->vtu_binary = strcmp(format, "binary") == 0;
    }
    OPTIONAL(scene_get_bool(t, s, "csv", &sc->write_csv));
    OPTIONAL(scene_get_bool(t, s, "plot", &sc->write_plot));
    OPTIONAL(scene_get_double(t, s, "checkpoint_interval", &sc->checkpoint_interval));
    if (sc->checkpoint_interval < 0)
        return section_error(t, s, "checkpoint_interval must be >= 0 s (0: none)");
    OPTIONAL(scene_get_double(t, s, "max_frames", &sc->max_frames));
    if (!(sc->max_frames >= 1) || sc->max_frames != floor(sc->max_frames))
        return section_error(t, s, "max_frames must be a whole number >= 1");
    /* [stepper] and [pour] are built: the run's length is known */
    return at_line(t, scene_find(s, "interval")->line,
                   sinter_scene_check_output(t->ctx, sc->end_time, sc->pour ? sc->pour_t_max : 0.0,
                                             sc->output_interval, sc->max_frames));
}

typedef sinter_status (*section_builder)(scene_text *, sinter_scene *, scene_section *);

/* Sections are built in this order of types, each type in file order. */
static const struct {
    const char *type;
    section_builder build;
    int required;
} BUILDERS[] = {
    {"scene", build_scene_header, 1},  {"material", build_material, 1},
    {"particles", build_particles, 1}, {"wall", build_wall, 0},
    {"force", build_force, 0},         {"heat", build_heat, 0},
    {"electric", build_electric, 0},   {"stepper", build_stepper, 1},
    {"pour", build_pour, 0},           {"compact", build_compact, 0},
    {"output", build_output, 0},
};

static sinter_status build(scene_text *t, sinter_scene *sc)
{
    const size_t nb = sizeof(BUILDERS) / sizeof(BUILDERS[0]);
    for (size_t k = 0; k < t->count; ++k) {
        size_t b = 0;
        while (b < nb && strcmp(BUILDERS[b].type, t->sections[k].type) != 0)
            ++b;
        if (b == nb)
            return section_error(t, &t->sections[k],
                                 "unknown section type; expected scene, material, particles, "
                                 "wall, force, heat, electric, stepper, pour, compact or output");
    }
    for (size_t b = 0; b < nb; ++b) {
        int seen = 0;
        for (size_t k = 0; k < t->count; ++k) {
            scene_section *s = &t->sections[k];
            if (strcmp(s->type, BUILDERS[b].type) != 0)
                continue;
            const int single = strcmp(s->type, "scene") == 0 || strcmp(s->type, "stepper") == 0 ||
                               strcmp(s->type, "electric") == 0 || strcmp(s->type, "pour") == 0 ||
                               strcmp(s->type, "compact") == 0 || strcmp(s->type, "output") == 0;
            if (seen && single)
                return section_error(t, s, "this section may appear only once");
            seen = 1;
            TRY(BUILDERS[b].build(t, sc, s));
        }
        if (!seen && BUILDERS[b].required)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s: the scene needs a [%s] section",
                               t->path, BUILDERS[b].type);
    }
    /* Every stepper but the quasi-static one (bonded links, no contact forces) needs forces. */
    if (sc->force_count == 0 && sc->st->kind != SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s: the scene needs a [force] section (only kind = quasistatic runs "
                           "without one)",
                           t->path);
    TRY(scene_check_unused(t));
    size_t n = 0;
    TRY(sinter_particles_count(sc->ps, &n));
    if (n == 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s: the scene has no particles", t->path);
    return SINTER_OK;
}

void sinter_scene_destroy(sinter_scene *sc)
{
    if (sc == NULL)
        return;
    sinter_stepper_destroy(sc->st);
    sinter_electric_model_destroy(sc->electric);
    for (size_t k = 0; k < sc->force_count; ++k)
        sinter_force_model_destroy(sc->forces[k]);
    for (size_t k = 0; k < sc->heat_count; ++k)
        sinter_heat_model_destroy(sc->heats[k]);
    for (size_t k = 0; k < sc->material_count; ++k)
        sinter_material_destroy(sc->materials[k]);
    sinter_walls_destroy(sc->walls);
    sinter_particles_destroy(sc->ps);
    scene_program_free(sc->ctx, &sc->program);
    sinter_free(sc->ctx, sc);
}

sinter_status sinter_scene_load(sinter_scene **out, sinter_ctx *ctx, const char *path)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, path);
    sinter_scene *sc = sinter_calloc(ctx, 1, sizeof(*sc));
    if (sc == NULL)
        return sinter_last_status(ctx);
    sc->ctx = ctx;
    snprintf(sc->name, sizeof(sc->name), "scene");
    sinter_status st = sinter_path_format(ctx, sc->directory, sizeof(sc->directory), "%s", path);
    if (st != SINTER_OK) {
        sinter_free(ctx, sc);
        return st;
    }
    char *slash = strrchr(sc->directory, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(sc->directory, sizeof(sc->directory), ".");
    sc->write_vtu = sc->write_csv = sc->write_plot = 1;
    sc->vtu_binary = 1;
    sc->output_interval = 0.0;
    sc->max_frames = SCENE_MAX_FRAMES;
    scene_text t;
    st = scene_text_read(&t, ctx, path);
    if (st == SINTER_OK)
        st = sinter_particles_create(&sc->ps, ctx);
    if (st == SINTER_OK)
        st = sinter_walls_create(&sc->walls, ctx);
    if (st == SINTER_OK)
        st = sinter_stepper_create(&sc->st, ctx, SINTER_STEPPER_EXPLICIT, sc->ps, sc->walls);
    if (st == SINTER_OK)
        st = build(&t, sc);
    scene_text_free(&t);
    if (st != SINTER_OK) {
        sinter_scene_destroy(sc);
        return st;
    }
    if (sc->output_interval <= 0.0)
        sc->output_interval = sc->end_time / 100.0;
    *out = sc;
    return SINTER_OK;
}

sinter_status sinter_scene_get_stepper(sinter_scene *sc, sinter_stepper **st)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(sc->ctx, st);
    *st = sc->st;
    return SINTER_OK;
}

sinter_status sinter_scene_get_particles(sinter_scene *sc, sinter_particles **ps)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(sc->ctx, ps);
    *ps = sc->ps;
    return SINTER_OK;
}

sinter_status sinter_scene_get_walls(sinter_scene *sc, sinter_walls **walls)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(sc->ctx, walls);
    *walls = sc->walls;
    return SINTER_OK;
}

sinter_status sinter_scene_end_time(const sinter_scene *sc, double *end_time)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(sc->ctx, end_time);
    *end_time = sc->end_time;
    return SINTER_OK;
}
