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
#include "io/scene_scan.h"
#include "io/scene_tables.h"
#include "io/scene_text.h"
#include "io/scene_insert.h"
#include "io/scene_walls.h"
#include "io/text_file.h"
#include "particles/compact.h"

#define TRY(expr) SCENE_TRY(expr)

#define OPTIONAL(expr) SCENE_OPTIONAL(expr)

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
        if (scene_table_key(en->key)) /* a property table: the scene's builder reads it */
            continue;
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

static sinter_status scene_file_path(scene_text *t, const sinter_scene *sc, const char *file,
                                     int line, char path[SINTER_PATH_SIZE]);

/* One property table of material `id` (scene_tables.c): k, C or sigma (property >= 0) into the
 * particle set, or E(theta) (property -1) as the softening curve E / E_0 (law 3). */
static sinter_status material_table(scene_text *t, sinter_scene *sc, scene_section *s, int32_t id,
                                    const char *key, int property)
{
    const scene_entry *e = scene_find(s, key);
    char path[SINTER_PATH_SIZE];
    if (!scene_table_inline(e))
        TRY(scene_file_path(t, sc, e->value, e->line, path));
    double *theta = NULL, *value = NULL;
    size_t n = 0;
    sinter_status st =
        scene_table_read(t, s, key, scene_table_inline(e) ? NULL : path, &theta, &value, &n);
    sinter_material *m = sc->materials[id];
    if (st == SINTER_OK && property >= 0) {
        st = at_line(t, e->line,
                     sinter_particles_set_property_table(sc->ps, id, (sinter_property)property, n,
                                                         theta, value));
    } else if (st == SINTER_OK) {
        const double law = m->value[SINTER_MAT_SOFTENING_LAW],
                     e0 = m->value[SINTER_MAT_YOUNGS_MODULUS];
        if (law != 0.0 && law != 3.0)
            st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                             "%s:%d: %s: a Young's modulus table is softening law 3; the material "
                             "also gives softening_law = %g",
                             t->path, e->line, key, law);
        for (size_t k = 0; st == SINTER_OK && k < n; ++k)
            value[k] /= e0; /* E(theta) / E_0 with E_0 the material's youngs_modulus */
        if (st == SINTER_OK)
            st = at_line(t, e->line,
                         sinter_particles_set_softening_curve(sc->ps, id, n, theta, value));
        if (st == SINTER_OK) /* the scene's copy too, should it be registered again */
            st = sinter_material_set(m, SINTER_MAT_SOFTENING_LAW, 3.0);
    }
    sinter_free(t->ctx, theta);
    sinter_free(t->ctx, value);
    return st;
}

/* [material NAME] keys that give a property against temperature (docs/scene-reference.md). */
static sinter_status material_tables(scene_text *t, sinter_scene *sc, scene_section *s, int32_t id)
{
    if (scene_find(s, "conductivity_table") != NULL)
        TRY(material_table(t, sc, s, id, "conductivity_table",
                           SINTER_PROPERTY_THERMAL_CONDUCTIVITY));
    if (scene_find(s, "heat_capacity_table") != NULL)
        TRY(material_table(t, sc, s, id, "heat_capacity_table", SINTER_PROPERTY_HEAT_CAPACITY));
    if (scene_find(s, "electric_conductivity_table") != NULL)
        TRY(material_table(t, sc, s, id, "electric_conductivity_table",
                           SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY));
    if (scene_find(s, "youngs_modulus_table") != NULL)
        TRY(material_table(t, sc, s, id, "youngs_modulus_table", -1));
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
    /* Register the final values, then the tables. */
    TRY(at_line(t, s->line,
                sinter_particles_set_material(sc->ps, (int32_t)sc->material_count - 1, m)));
    return material_tables(t, sc, s, (int32_t)sc->material_count - 1);
}

/* A particle file being read: where its particles go. */
typedef struct xyzr_file {
    scene_text *t;
    sinter_scene *sc;
    scene_section *s;
    const char *path;
    int mat;
    double temperature;
} xyzr_file;

/* One line "x y z r" [m] of a particle file (blank or a '#' comment: nothing). */
static sinter_status particle_line(void *user, int line, char *text)
{
    const xyzr_file *x = user;
    scene_text *t = x->t;
    const char *path = x->path;
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
    return at_line(t, x->s->line,
                   sinter_particles_add(x->sc->ps, 1, row, &row[3], x->mat, x->temperature, NULL));
}

/* The path of a file a scene names on line `line`: as given if absolute, else relative to the
 * scene file's directory. */
static sinter_status scene_file_path(scene_text *t, const sinter_scene *sc, const char *file,
                                     int line, char path[SINTER_PATH_SIZE])
{
    return at_line(t, line,
                   file[0] == '/'
                       ? sinter_path_format(t->ctx, path, SINTER_PATH_SIZE, "%s", file)
                       : sinter_path_join(t->ctx, path, SINTER_PATH_SIZE, sc->directory, file));
}

static sinter_status read_xyzr_file(scene_text *t, sinter_scene *sc, scene_section *s, int mat,
                                    double temperature)
{
    const char *file = NULL;
    TRY(required(t, s, scene_get_word(t, s, "file", &file), "file"));
    char path[SINTER_PATH_SIZE];
    const int line_of_file = scene_find(s, "file")->line;
    TRY(scene_file_path(t, sc, file, line_of_file, path));
    char where[SINTER_PATH_SIZE + 32];
    snprintf(where, sizeof(where), "%s:%d: file: ", t->path, line_of_file); /* a message prefix */
    FILE *f = NULL;
    TRY(sinter_text_open(t->ctx, where, "particle file", path, &f));
    xyzr_file x = {t, sc, s, path, mat, temperature};
    char buf[512];
    const sinter_status st = sinter_text_each_line(t->ctx, f, path, "a particle file", buf,
                                                   sizeof(buf), particle_line, &x);
    fclose(f);
    return st;
}

/*
 * [particles] distribution = table: the CSV file of `table` (relative to the scene's directory)
 * read into new arrays (*d and *q, free both) with its units (table_units), scale
 * (table_values) and basis (table_basis). A bad row is reported by the reader as
 * "psdfile:line: ...".
 */
static sinter_status read_psd_table(scene_text *t, sinter_scene *sc, scene_section *s,
                                    sinter_packing_options *o, double **d, double **q)
{
    *d = *q = NULL;
    const char *file = NULL, *units = "m", *values = "fraction", *basis = "volume";
    TRY(required(t, s, scene_get_word(t, s, "table", &file), "table"));
    OPTIONAL(scene_get_word(t, s, "table_units", &units));
    OPTIONAL(scene_get_word(t, s, "table_values", &values));
    OPTIONAL(scene_get_word(t, s, "table_basis", &basis));
    static const struct {
        const char *name;
        double metres;
    } unit_names[] = {{"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}, {"nm", 1e-9}};
    double unit = 0.0;
    for (size_t k = 0; k < sizeof(unit_names) / sizeof(unit_names[0]); ++k)
        if (strcmp(units, unit_names[k].name) == 0)
            unit = unit_names[k].metres;
    if (unit == 0.0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: table_units: expected m, mm, um or nm, got '%s'", t->path,
                           scene_find(s, "table_units")->line, units);
    const int percent = strcmp(values, "percent") == 0;
    if (!percent && strcmp(values, "fraction") != 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: table_values: expected fraction or percent, got '%s'", t->path,
                           scene_find(s, "table_values")->line, values);
    if (strcmp(basis, "volume") == 0)
        o->table_basis = SINTER_SIZE_BY_VOLUME;
    else if (strcmp(basis, "number") == 0)
        o->table_basis = SINTER_SIZE_BY_NUMBER;
    else
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: table_basis: expected number or volume, got '%s'", t->path,
                           scene_find(s, "table_basis")->line, basis);
    char path[SINTER_PATH_SIZE];
    const int line = scene_find(s, "table")->line;
    TRY(scene_file_path(t, sc, file, line, path));
    size_t rows = 0;
    TRY(at_line(t, line, sinter_psd_read_csv(t->ctx, path, unit, percent, NULL, NULL, 0, &rows)));
    *d = sinter_calloc(t->ctx, rows, sizeof(double));
    *q = sinter_calloc(t->ctx, rows, sizeof(double));
    if (*d == NULL || *q == NULL)
        return SINTER_ERR_NOMEM;
    TRY(at_line(t, line, sinter_psd_read_csv(t->ctx, path, unit, percent, *d, *q, rows, &rows)));
    o->table_diameter = *d;
    o->table_cumulative = *q;
    o->table_points = rows;
    return SINTER_OK;
}

/* The next word of `*rest`, a list separated by blanks, commas or semicolons: ended in place
 * with a NUL, `*rest` moved past it; NULL when no word is left. */
static char *next_list_word(char **rest)
{
    char *word = *rest + strspn(*rest, " \t,;");
    const size_t len = strcspn(word, " \t,;");
    if (len == 0)
        return NULL;
    *rest = word + len + (word[len] != '\0');
    word[len] = '\0';
    return word;
}

/*
 * [particles] or [insert] materials = A B ... with mass_fractions = f_A f_B ...: the mixture
 * of sinter_pack_random, the ids into mat[] and the fractions into a new array (*fractions).
 */
sinter_status scene_read_mixture(scene_text *t, sinter_scene *sc, scene_section *s,
                                 int32_t mat[SCENE_MAX_MATERIALS], double **fractions,
                                 size_t *count)
{
    *fractions = NULL;
    *count = 0;
    const scene_entry *e = scene_find(s, "materials");
    char names[1024];
    if (strlen(e->value) >= sizeof(names))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: materials: the list is too long",
                           t->path, e->line);
    snprintf(names, sizeof(names), "%s", e->value);
    size_t n = 0;
    char *rest = names;
    for (char *w; (w = next_list_word(&rest)) != NULL;) {
        const int id = find_material(sc, w);
        if (id < 0)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: materials: '%s' is not the name of a [material NAME] "
                               "section above",
                               t->path, e->line, w);
        if (n == SCENE_MAX_MATERIALS)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: materials: too many", t->path,
                               e->line);
        mat[n++] = (int32_t)id;
    }
    size_t nf = 0;
    TRY(required(t, s, scene_get_numbers(t, s, "mass_fractions", fractions, &nf),
                 "mass_fractions"));
    if (nf != n || n == 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: mass_fractions: expected one fraction for each of the %zu "
                           "materials, got %zu",
                           t->path, scene_find(s, "mass_fractions")->line, n, nf);
    *count = n;
    return SINTER_OK;
}

/* The --log info line of a random packing: what was generated, D10, D50, D90 both ways. */
static void log_sizes(scene_text *t, const sinter_scene *sc, const scene_section *s, size_t first,
                      size_t placed)
{
    static const double f[3] = {0.1, 0.5, 0.9};
    double dn[3], dv[3];
    if (placed == 0 ||
        sinter_particles_size_quantiles(sc->ps, first, placed, SINTER_SIZE_BY_NUMBER, 3, f, dn) !=
            SINTER_OK ||
        sinter_particles_size_quantiles(sc->ps, first, placed, SINTER_SIZE_BY_VOLUME, 3, f, dv) !=
            SINTER_OK)
        return;
    sinter_log(t->ctx, SINTER_LOG_INFO,
               "%s:%d: [particles]: %zu spheres; diameters D10 D50 D90 by number %.4g %.4g %.4g "
               "m, by volume %.4g %.4g %.4g m",
               t->path, s->line, placed, dn[0], dn[1], dn[2], dv[0], dv[1], dv[2]);
}

/* The --log info line of a mixture: the mass fraction each material reached. */
static void log_mixture(scene_text *t, const sinter_scene *sc, const scene_section *s,
                        const sinter_packing_options *o, size_t first, size_t placed)
{
    const double *mass = NULL;
    const int32_t *mat = NULL;
    if (placed == 0 || sinter_particles_view_read(sc->ps, SINTER_FIELD_MASS, (const void **)&mass,
                                                  NULL, NULL) != SINTER_OK)
        return;
    if (sinter_particles_view_read(sc->ps, SINTER_FIELD_MATERIAL, (const void **)&mat, NULL,
                                   NULL) == SINTER_OK) {
        double total = 0.0;
        for (size_t i = first; i < first + placed; ++i)
            total += mass[i];
        for (size_t k = 0; k < o->mixture_count; ++k) {
            double m = 0.0;
            for (size_t i = first; i < first + placed; ++i)
                m += mat[i] == o->mixture_materials[k] ? mass[i] : 0.0;
            sinter_log(t->ctx, SINTER_LOG_INFO,
                       "%s:%d: [particles]: material %s: mass fraction %.5f (asked %.5f)", t->path,
                       s->line, sc->material_names[o->mixture_materials[k]], m / total,
                       o->mixture_mass_fractions[k]);
        }
        sinter_particles_release(sc->ps, SINTER_FIELD_MATERIAL);
    }
    sinter_particles_release(sc->ps, SINTER_FIELD_MASS);
}

/* The size distribution keys of a section ([particles] method = random, [insert]) into o;
 * a table's arrays into *d and *q (free both, also on error). */
sinter_status scene_read_distribution(scene_text *t, sinter_scene *sc, scene_section *s,
                                      sinter_packing_options *o, const char *dist, double radius,
                                      double **d, double **q)
{
    *d = *q = NULL;
    OPTIONAL(scene_get_double(t, s, "spread", &o->radius_spread));
    OPTIONAL(scene_get_double(t, s, "radius_min", &o->radius_min));
    OPTIONAL(scene_get_double(t, s, "radius_max", &o->radius_max));
    if (strcmp(dist, "table") != 0)
        o->radius_mean = radius;
    if (strcmp(dist, "monodisperse") == 0)
        o->distribution = SINTER_RADII_MONODISPERSE;
    else if (strcmp(dist, "uniform") == 0)
        o->distribution = SINTER_RADII_UNIFORM;
    else if (strcmp(dist, "normal") == 0)
        o->distribution = SINTER_RADII_NORMAL;
    else if (strcmp(dist, "lognormal") == 0) {
        o->distribution = SINTER_RADII_LOGNORMAL;
        o->radius_median = radius;
        TRY(required(t, s, scene_get_double(t, s, "gsd", &o->radius_gsd), "gsd"));
    } else if (strcmp(dist, "table") == 0)
        o->distribution = SINTER_RADII_TABLE;
    else
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: distribution: expected monodisperse, uniform, normal, "
                           "lognormal or table, got '%s'",
                           t->path, scene_find(s, "distribution")->line, dist);
    if (o->distribution == SINTER_RADII_TABLE)
        return read_psd_table(t, sc, s, o, d, q);
    return SINTER_OK;
}

/* [size NAME]: a size distribution of a mixture's material of its own: distribution, radius
 * and the distribution's keys into o (a table's arrays into *d and *q, free both). */
static sinter_status read_size_section(scene_text *t, sinter_scene *sc, scene_section *s,
                                       sinter_packing_options *o, double **d, double **q)
{
    *d = *q = NULL;
    TRY(sinter_packing_options_init(o, sizeof(*o)));
    const char *dist = "monodisperse";
    OPTIONAL(scene_get_word(t, s, "distribution", &dist));
    double radius = 0.0;
    if (strcmp(dist, "table") != 0) /* a table has its own sizes */
        TRY(required(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
    return scene_read_distribution(t, sc, s, o, dist, radius, d, q);
}

/* [size NAME] sections are read where a mixture names them (`sizes`); here each is read once
 * for its keys' sake (an unknown key or a bad table is reported even when none names it). */
static sinter_status build_size(scene_text *t, sinter_scene *sc, scene_section *s)
{
    if (s->name[0] == '\0')
        return section_error(t, s, "a size distribution needs a name: [size NAME]");
    for (size_t k = 0; &t->sections[k] != s; ++k)
        if (strcmp(t->sections[k].type, "size") == 0 && strcmp(t->sections[k].name, s->name) == 0)
            return section_error(t, s, "a [size] section of this name is above");
    sinter_packing_options o;
    double *d = NULL, *q = NULL;
    const sinter_status st = read_size_section(t, sc, s, &o, &d, &q);
    sinter_free(t->ctx, d);
    sinter_free(t->ctx, q);
    return st;
}

sinter_status scene_read_sizes(scene_text *t, sinter_scene *sc, scene_section *s, size_t count,
                               sinter_packing_options *sizes, double **tables)
{
    for (size_t k = 0; k < 2 * count; ++k)
        tables[k] = NULL;
    const scene_entry *e = scene_find(s, "sizes");
    char names[1024];
    if (strlen(e->value) >= sizeof(names))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: sizes: the list is too long", t->path,
                           e->line);
    snprintf(names, sizeof(names), "%s", e->value);
    size_t n = 0;
    char *rest = names;
    for (char *w; (w = next_list_word(&rest)) != NULL;) {
        scene_section *size = NULL;
        for (size_t k = 0; k < t->count && size == NULL; ++k)
            if (strcmp(t->sections[k].type, "size") == 0 && strcmp(t->sections[k].name, w) == 0)
                size = &t->sections[k];
        if (size == NULL)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: sizes: '%s' is not the name of a [size NAME] section",
                               t->path, e->line, w);
        if (n == count)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: sizes: expected one [size] name for each of the %zu "
                               "materials, got more",
                               t->path, e->line, count);
        TRY(read_size_section(t, sc, size, &sizes[n], &tables[2 * n], &tables[2 * n + 1]));
        ++n;
    }
    if (n != count)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: sizes: expected one [size] name for each of the %zu "
                           "materials, got %zu",
                           t->path, e->line, count, n);
    return SINTER_OK;
}

sinter_status scene_material_ref(scene_text *t, sinter_scene *sc, scene_section *s, int *id)
{
    return material_ref(t, sc, s, id);
}

/* [particles] method = random: sinter_pack_random with the section's distribution. */
static sinter_status pack_random_section(scene_text *t, sinter_scene *sc, scene_section *s,
                                         sinter_packing_options *o, const char *dist, double radius)
{
    double count = 0, seed = 1;
    TRY(required(t, s, scene_get_double(t, s, "count", &count), "count"));
    OPTIONAL(scene_get_double(t, s, "seed", &seed));
    /* Bounded before the conversions below (a double beyond the integer type is UB). */
    if (!(count >= 0 && count <= 1e12) || count != floor(count) ||
        !(seed >= 0 && seed < 18446744073709551616.0) || seed != floor(seed))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: [particles]: count = %g and seed = %g must be whole numbers "
                           "in [0, 1e12] and [0, 2^64)",
                           t->path, s->line, count, seed);
    o->seed = (uint64_t)seed;
    OPTIONAL(scene_get_double(t, s, "gap", &o->gap));
    double *d = NULL, *q = NULL, *fractions = NULL, *tables[2 * SCENE_MAX_MATERIALS] = {NULL};
    int32_t mat[SCENE_MAX_MATERIALS];
    sinter_packing_options sizes[SCENE_MAX_MATERIALS];
    const int own_sizes = scene_find(s, "sizes") != NULL; /* then no distribution of its own */
    sinter_status st =
        own_sizes ? SINTER_OK : scene_read_distribution(t, sc, s, o, dist, radius, &d, &q);
    if (st == SINTER_OK && scene_find(s, "materials") != NULL) {
        st = scene_read_mixture(t, sc, s, mat, &fractions, &o->mixture_count);
        o->mixture_materials = mat;
        o->mixture_mass_fractions = fractions;
    }
    if (st == SINTER_OK && own_sizes && o->mixture_count == 0)
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                         "%s:%d: sizes: sizes per material need materials = ... (a mixture)",
                         t->path, scene_find(s, "sizes")->line);
    if (st == SINTER_OK && own_sizes) {
        st = scene_read_sizes(t, sc, s, o->mixture_count, sizes, tables);
        o->mixture_sizes = sizes;
    }
    size_t first = 0, placed = 0;
    if (st == SINTER_OK)
        st = sinter_particles_count(sc->ps, &first);
    if (st == SINTER_OK)
        st = at_line(t, s->line, sinter_pack_random(sc->ps, o, (size_t)count, &placed));
    sinter_free(t->ctx, d);
    sinter_free(t->ctx, q);
    for (size_t k = 0; k < 2 * SCENE_MAX_MATERIALS; ++k)
        sinter_free(t->ctx, tables[k]);
    if (st == SINTER_OK && o->mixture_count > 0)
        log_mixture(t, sc, s, o, first, placed);
    sinter_free(t->ctx, fractions);
    if (st != SINTER_OK)
        return st;
    if (placed < (size_t)count)
        return sinter_fail(t->ctx, SINTER_ERR_INVALID,
                           "%s:%d: only %zu of %zu spheres fit in the box by random sequential "
                           "addition; enlarge the box or lower the count",
                           t->path, s->line, placed, (size_t)count);
    log_sizes(t, sc, s, first, placed);
    return SINTER_OK;
}

static sinter_status build_particles(scene_text *t, sinter_scene *sc, scene_section *s)
{
    int mat = 0;
    const int mixture = scene_find(s, "materials") != NULL;
    if (!mixture || scene_find(s, "material") != NULL)
        TRY(material_ref(t, sc, s, &mat));
    double temperature = 293.15;
    OPTIONAL(scene_get_double(t, s, "temperature", &temperature));
    const char *method = NULL;
    TRY(required(t, s, scene_get_word(t, s, "method", &method), "method"));
    if (mixture && strcmp(method, "random") != 0)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: materials: a mixture needs method = random", t->path,
                           scene_find(s, "materials")->line);
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
    const char *dist = "monodisperse";
    if (strcmp(method, "random") == 0)
        OPTIONAL(scene_get_word(t, s, "distribution", &dist));
    /* a table has its own sizes, and so have the materials of a mixture with `sizes` */
    if (strcmp(dist, "table") != 0 &&
        !(strcmp(method, "random") == 0 && scene_find(s, "sizes") != NULL))
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
    o.material = mat;
    o.temperature = temperature;
    return pack_random_section(t, sc, s, &o, dist, radius);
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

/* Keys periodic_x, periodic_y, periodic_z: "lo hi" [m], the periodic cell along that axis
 * (sinter_stepper_set_periodic). */
static sinter_status read_periodic(scene_text *t, sinter_scene *sc, scene_section *s)
{
    static const char *const keys[3] = {"periodic_x", "periodic_y", "periodic_z"};
    for (int d = 0; d < 3; ++d) {
        double *v = NULL;
        size_t n = 0;
        sinter_status st = scene_get_numbers(t, s, keys[d], &v, &n);
        OPTIONAL(st);
        if (st != SINTER_OK)
            continue;
        const int line = scene_find(s, keys[d])->line;
        if (n != 2)
            st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                             "%s:%d: %s: expected the cell 'lo hi' [m], got %zu numbers", t->path,
                             line, keys[d], n);
        else
            st = at_line(t, line, sinter_stepper_set_periodic(sc->st, d, v[0], v[1]));
        sinter_free(t->ctx, v);
        TRY(st);
    }
    return SINTER_OK;
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
    int mat = 0;
    TRY(material_ref(t, sc, s, &mat));
    TRY(scene_wall_add(t, sc, s, sc->materials[mat], &index)); /* its kind (scene_walls.c) */
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
    const char *thermal = NULL;
    st = scene_get_word(t, s, "thermal", &thermal);
    OPTIONAL(st);
    if (st == SINTER_OK) {
        const int mode = strcmp(thermal, "reservoir") == 0    ? SINTER_WALL_RESERVOIR
                         : strcmp(thermal, "adiabatic") == 0  ? SINTER_WALL_ADIABATIC
                         : strcmp(thermal, "resistance") == 0 ? SINTER_WALL_RESISTANCE
                         : strcmp(thermal, "transfer") == 0   ? SINTER_WALL_TRANSFER
                         : strcmp(thermal, "imposed") == 0    ? SINTER_WALL_IMPOSED
                                                              : -1;
        if (mode < 0)
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: thermal: expected reservoir, adiabatic, resistance, "
                               "transfer or imposed, got '%s'",
                               t->path, scene_find(s, "thermal")->line, thermal);
        double value = 0.0;
        if (mode == SINTER_WALL_RESISTANCE || mode == SINTER_WALL_TRANSFER)
            TRY(required(t, s, scene_get_double(t, s, "thermal_value", &value), "thermal_value"));
        TRY(at_line(t, scene_find(s, "thermal")->line,
                    sinter_walls_set_thermal(sc->walls, index, mode, value)));
    }
    TRY(scene_wall_spin(t, sc, s, index));
    const char *motion = "fixed";
    OPTIONAL(scene_get_word(t, s, "motion", &motion));
    if (strcmp(motion, "fixed") == 0)
        return SINTER_OK;
    if (strcmp(motion, "servo") == 0)
        return scene_wall_servo(t, sc, s, index);
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
                       "%s:%d: motion: expected fixed, velocity, schedule, sine or servo, got "
                       "'%s'",
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
        if (scene_heat_scan_key(en->key))
            continue; /* read by scene_heat_scan below */
        if (len > suffix && strcmp(en->key + len - suffix, "_schedule") == 0) {
            TRY(heat_schedule(t, s, en, hm));
            continue;
        }
        double v;
        TRY(scene_get_double(t, s, en->key, &v));
        TRY(at_line(t, en->line, sinter_heat_model_set(hm, en->key, v)));
    }
    TRY(scene_heat_scan(t, sc->directory, s, hm));
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
    /* The spatial sort (any kind), the rotation vector (any kind but quasi-static), the explicit
     * stepper's streaming stores and the options of the staggered stepper (seed 000 sec. 3,
     * 6; the explicit one refuses those). */
    static const char *const options[] = {"sort_interval",
                                          "rotation",
                                          "stream_stores",
                                          "thread_choice",
                                          "dt_check",
                                          "energy_check",
                                          "reproducible",
                                          "heat_interval",
                                          "phi",
                                          "target_iterations",
                                          "tolerance",
                                          "exponent",
                                          "dt_min",
                                          "dt_max",
                                          "adaptive",
                                          "position_tolerance",
                                          "temperature_tolerance",
                                          "scheme",
                                          "anderson_depth",
                                          "frozen_heat",
                                          "frozen_ke",
                                          "frozen_rtol",
                                          "frozen_atol",
                                          "frozen_dt_max",
                                          "frozen_wake",
                                          "frozen_settle",
                                          "frozen_travel"};
    for (size_t k = 0; k < sizeof(options) / sizeof(options[0]); ++k) {
        double value;
        const sinter_status got = scene_get_double(t, s, options[k], &value);
        OPTIONAL(got);
        if (got == SINTER_OK)
            TRY(at_line(t, scene_find(s, options[k])->line,
                        sinter_stepper_set_option(sc->st, options[k], value)));
    }
    /* The threads the scene runs on (its context's, sinter_ctx_set_threads; the command line's
     * --threads overrides it): any count gives the same bits (issue 41). */
    double threads;
    const sinter_status got_threads = scene_get_double(t, s, "threads", &threads);
    OPTIONAL(got_threads);
    if (got_threads == SINTER_OK) {
        if (!(threads >= 0.0 && threads <= 4096.0) || threads != floor(threads))
            return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                               "%s:%d: threads: expected a whole number from 0 (all OpenMP "
                               "offers) to 4096, got %g",
                               t->path, scene_find(s, "threads")->line, threads);
        TRY(at_line(t, scene_find(s, "threads")->line,
                    sinter_ctx_set_threads(t->ctx, (int)threads)));
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
    } else if (scene_find(s, "domain_max") != NULL) { /* (not "unknown key") */
        return required(t, s, SINTER_ERR_NOT_FOUND, "domain_min");
    }
    TRY(read_periodic(t, sc, s));
    /* dt last: "auto" needs the particles and walls (seed 003 eq. 47). */
    scene_entry *e = scene_find(s, "dt");
    if (e == NULL)
        return required(t, s, SINTER_ERR_NOT_FOUND, "dt");
    double dt = 0;
    if (strcmp(e->value, "auto") == 0) { /* (a word that only begins so is not a number) */
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

/* [output] track: the persistent ids of particles whose histories series.csv carries. */
/* [output] temperature_bins = lo hi n: n bins of (hi - lo) / n between lo and hi [K]. */
static sinter_status build_temperature_bins(scene_text *t, sinter_scene *sc, scene_section *s)
{
    double *v = NULL;
    size_t n = 0;
    const sinter_status got = scene_get_numbers(t, s, "temperature_bins", &v, &n);
    if (got == SINTER_ERR_NOT_FOUND)
        return SINTER_OK;
    if (got != SINTER_OK)
        return got;
    const int ok = n == 3 && isfinite(v[0]) && isfinite(v[1]) && v[0] < v[1] && v[2] >= 1.0 &&
                   v[2] <= SCENE_MAX_TEMPERATURE_BINS && v[2] == floor(v[2]);
    if (ok) {
        sc->temperature_low = v[0];
        sc->temperature_high = v[1];
        sc->temperature_bins = (size_t)v[2];
    }
    sinter_free(t->ctx, v);
    if (!ok)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: temperature_bins: expected 'low high n' (K, K, a whole number "
                           "of bins in [1, %d]) with low < high",
                           t->path, scene_find(s, "temperature_bins")->line,
                           SCENE_MAX_TEMPERATURE_BINS);
    return SINTER_OK;
}

static sinter_status build_track(scene_text *t, sinter_scene *sc, scene_section *s)
{
    double *ids = NULL;
    size_t n = 0;
    sinter_status st = scene_get_numbers(t, s, "track", &ids, &n);
    if (st == SINTER_ERR_NOT_FOUND)
        return SINTER_OK;
    if (st != SINTER_OK)
        return st;
    if (n > SCENE_MAX_TRACKED)
        st = section_error(t, s, "track: at most 8 particle ids");
    for (size_t k = 0; st == SINTER_OK && k < n; ++k) {
        const double id = ids[k];
        size_t found = 0;
        for (size_t i = 0; id >= 0 && id == floor(id) && i < sc->ps->count && !found; ++i)
            found = (double)sc->ps->id[i] == id;
        if (!found)
            st = section_error(t, s, "track: a particle id the scene's particles do not have");
        sc->track_ids[k] = found ? (uint64_t)id : 0;
    }
    sc->track_count = st == SINTER_OK ? n : 0;
    sinter_free(t->ctx, ids);
    return st;
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
        if (strcmp(format, "binary") != 0 && strcmp(format, "ascii") != 0 &&
            strcmp(format, "appended") != 0)
            return section_error(t, s, "vtu_format must be binary, ascii or appended");
        sc->vtu_binary = strcmp(format, "ascii") != 0;
        sc->vtu_appended = strcmp(format, "appended") == 0;
    }
    const char *precision = NULL;
    OPTIONAL(scene_get_word(t, s, "vtu_precision", &precision));
    if (precision != NULL) {
        if (strcmp(precision, "double") != 0 && strcmp(precision, "single") != 0)
            return section_error(t, s, "vtu_precision must be double or single");
        sc->vtu_single = strcmp(precision, "single") == 0;
    }
    OPTIONAL(scene_get_bool(t, s, "contacts", &sc->write_contacts));
    OPTIONAL(scene_get_bool(t, s, "walls", &sc->write_walls));
    OPTIONAL(scene_get_bool(t, s, "distributions", &sc->write_distributions));
    TRY(build_temperature_bins(t, sc, s));
    TRY(build_track(t, sc, s));
    OPTIONAL(scene_get_bool(t, s, "pair_reference", &sc->pair_reference));
    if (sc->pair_reference && sc->st->kind != SINTER_STEPPER_QUASISTATIC)
        return section_error(t, s, "pair_reference needs [stepper] kind = quasistatic");
    double *box = NULL;
    size_t box_n = 0;
    sinter_status got = scene_get_numbers(t, s, "solid_box", &box, &box_n);
    OPTIONAL(got);
    if (got == SINTER_OK) {
        int ok = box_n == 6;
        for (int d = 0; d < 3 && ok; ++d) {
            sc->solid_lo[d] = box[d];
            sc->solid_hi[d] = box[3 + d];
            ok = isfinite(box[d]) && isfinite(box[3 + d]) && box[d] < box[3 + d];
        }
        sinter_free(t->ctx, box);
        if (!ok)
            return section_error(t, s,
                                 "solid_box must be 'x0 y0 z0 x1 y1 z1' [m] with x0 < x1, "
                                 "y0 < y1, z0 < z1");
        sc->solid_box = 1;
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

/* [fields]: the kernel, the grid and the profiles of io/scene_frames.h. */
static sinter_status build_fields(scene_text *t, sinter_scene *sc, scene_section *s)
{
    sc->fields = sc->fields_grid = 1;
    sc->fields_cutoff = 3.0;
    sc->laminae = 20;
    TRY(required(t, s, scene_get_double(t, s, "width", &sc->fields_width), "width"));
    if (!(sc->fields_width > 0) || !isfinite(sc->fields_width))
        return section_error(t, s, "width must be > 0 m");
    sc->fields_spacing = sc->fields_width;
    OPTIONAL(scene_get_double(t, s, "spacing", &sc->fields_spacing));
    OPTIONAL(scene_get_double(t, s, "cutoff", &sc->fields_cutoff));
    if (!(sc->fields_spacing > 0) || !isfinite(sc->fields_spacing))
        return section_error(t, s, "spacing must be > 0 m");
    if (!(sc->fields_cutoff >= 1 && sc->fields_cutoff <= 10))
        return section_error(t, s, "cutoff must be in [1, 10] (kernel widths)");
    const int has_lo = scene_find(s, "box_min") != NULL, has_hi = scene_find(s, "box_max") != NULL;
    if (has_lo != has_hi)
        return section_error(t, s, "give both box_min and box_max, or neither");
    if (has_lo) {
        TRY(scene_get_vec3(t, s, "box_min", sc->fields_lo));
        TRY(scene_get_vec3(t, s, "box_max", sc->fields_hi));
        sc->fields_box = 1;
        for (int d = 0; d < 3; ++d)
            if (!(sc->fields_lo[d] < sc->fields_hi[d]))
                return section_error(t, s, "need box_min < box_max along every axis");
    }
    OPTIONAL(scene_get_bool(t, s, "grid", &sc->fields_grid));
    const char *axes = NULL;
    OPTIONAL(scene_get_word(t, s, "profiles", &axes));
    if (axes != NULL && strcmp(axes, "none") != 0)
        for (const char *c = axes; *c != '\0'; ++c) {
            if (*c < 'x' || *c > 'z')
                return section_error(t, s, "profiles: expected none or axes among x, y, z (xyz)");
            sc->profile_axes |= 1u << (*c - 'x');
        }
    OPTIONAL(scene_get_double(t, s, "laminae", &sc->laminae));
    if (!(sc->laminae >= 1 && sc->laminae <= 1e6) || sc->laminae != floor(sc->laminae))
        return section_error(t, s, "laminae must be a whole number in [1, 1e6]");
    return SINTER_OK;
}

typedef sinter_status (*section_builder)(scene_text *, sinter_scene *, scene_section *);

/* Sections are built in this order of types, each type in file order. */
static const struct {
    const char *type;
    section_builder build;
    int required;
} BUILDERS[] = {
    {"scene", build_scene_header, 1}, {"material", build_material, 1},
    {"size", build_size, 0},          {"particles", build_particles, 0},
    {"wall", build_wall, 0},          {"force", build_force, 0},
    {"heat", build_heat, 0},          {"electric", build_electric, 0},
    {"stepper", build_stepper, 1},    {"insert", scene_build_insert, 0},
    {"pour", build_pour, 0},          {"compact", build_compact, 0},
    {"output", build_output, 0},      {"fields", build_fields, 0},
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
                                 "unknown section type; expected scene, material, size, "
                                 "particles, wall, force, heat, electric, stepper, insert, pour, "
                                 "compact, output or fields");
    }
    for (size_t b = 0; b < nb; ++b) {
        int seen = 0;
        for (size_t k = 0; k < t->count; ++k) {
            scene_section *s = &t->sections[k];
            if (strcmp(s->type, BUILDERS[b].type) != 0)
                continue;
            const int single = strcmp(s->type, "scene") == 0 || strcmp(s->type, "stepper") == 0 ||
                               strcmp(s->type, "electric") == 0 || strcmp(s->type, "pour") == 0 ||
                               strcmp(s->type, "insert") == 0 || strcmp(s->type, "compact") == 0 ||
                               strcmp(s->type, "output") == 0 || strcmp(s->type, "fields") == 0;
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
    if (n == 0 && sc->st->insertion == NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s: the scene has no particles (and no [insert] section)", t->path);
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
