/* Output: VTU frames, PVD collections, series with CSV and SVG, safe writes and argument checks. */
#define _XOPEN_SOURCE 700 /* mkdtemp, symlink, nftw */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <ftw.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test_support.h"

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_material *mat;
    sinter_particles *ps;
    sinter_series *series;
    char dir[64];
} fixture;

/* ---- files ------------------------------------------------------------------------------ */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static void path_in(const fixture *f, const char *name, char *buf, size_t size)
{
    snprintf(buf, size, "%s/%s", f->dir, name);
}

static int exists(const char *path)
{
    struct stat sb;
    return lstat(path, &sb) == 0;
}

/* Whole file as a NUL-terminated string (free it), NULL if it cannot be read. */
static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (fp == NULL)
        return NULL;
    size_t size = 0, cap = 4096;
    char *text = malloc(cap);
    size_t got;
    while (text != NULL && (got = fread(text + size, 1, cap - size - 1, fp)) > 0) {
        size += got;
        if (cap - size - 1 == 0) {
            char *bigger = realloc(text, 2 * cap);
            if (bigger == NULL)
                free(text);
            text = bigger;
            cap *= 2;
        }
    }
    fclose(fp);
    if (text != NULL)
        text[size] = '\0';
    return text;
}

static size_t count_substrings(const char *text, const char *needle)
{
    size_t n = 0;
    for (const char *p = strstr(text, needle); p != NULL; p = strstr(p + 1, needle))
        n++;
    return n;
}

static size_t directory_entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    size_t n = 0;
    for (struct dirent *e = readdir(d); e != NULL; e = readdir(d))
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

static void assert_message(const sinter_ctx *ctx, const char *word)
{
    if (strstr(sinter_last_error(ctx), word) == NULL) {
        print_error("message \"%s\" does not name \"%s\"\n", sinter_last_error(ctx), word);
        fail();
    }
}

static void assert_same_bits(double a, double b)
{
    if (memcmp(&a, &b, sizeof(a)) != 0) {
        print_error("%.17g and %.17g differ bitwise\n", a, b);
        fail();
    }
}

/* ---- a small XML well-formedness checker ------------------------------------------------- */

static int xml_error(const char *why, const char *at)
{
    print_error("not well-formed XML: %s at \"%.40s\"\n", why, at);
    return 0;
}

static int name_start(int c)
{
    return isalpha(c) || c == '_' || c == ':' || c >= 0x80;
}

static int name_char(int c)
{
    return name_start(c) || isdigit(c) || c == '-' || c == '.';
}

static const char *skip_space(const char *p)
{
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        ++p;
    return p;
}

/* End of the entity or character reference at p ('&'), NULL if invalid. */
static const char *reference_end(const char *p)
{
    static const char *const named[] = {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"};
    for (size_t i = 0; i < sizeof(named) / sizeof(named[0]); ++i)
        if (strncmp(p, named[i], strlen(named[i])) == 0)
            return p + strlen(named[i]);
    if (p[1] != '#')
        return NULL;
    const char *q = p + 2;
    const int hex = *q == 'x';
    q += hex;
    const char *digits = q;
    while (hex ? isxdigit((unsigned char)*q) : isdigit((unsigned char)*q))
        ++q;
    return q > digits && *q == ';' ? q + 1 : NULL;
}

/*
 * One root element; start and end tags balance and nest; attributes are
 * quoted, unique and free of '<'; every '&' starts a reference; no control
 * characters; only white space outside the root.
 */
static int xml_well_formed(const char *doc)
{
    const char *open_names[64];
    size_t open_lengths[64], depth = 0;
    int roots = 0;
    const char *p = doc;
    if (strncmp(p, "<?xml", 5) == 0) {
        p = strstr(p, "?>");
        if (p == NULL)
            return xml_error("unterminated declaration", doc);
        p += 2;
    }
    while (*p != '\0') {
        const unsigned char c = (unsigned char)*p;
        if (c < 0x20 && c != '\n' && c != '\r' && c != '\t')
            return xml_error("control character", p);
        if (strncmp(p, "<!--", 4) == 0) {
            const char *end = strstr(p + 4, "-->");
            if (end == NULL)
                return xml_error("unterminated comment", p);
            p = end + 3;
        } else if (strncmp(p, "</", 2) == 0) {
            const char *name = p + 2;
            for (p = name; name_char((unsigned char)*p); ++p) {
            }
            const size_t n = (size_t)(p - name);
            p = skip_space(p);
            if (n == 0 || *p != '>')
                return xml_error("bad end tag", name - 2);
            if (depth == 0 || open_lengths[depth - 1] != n ||
                strncmp(open_names[depth - 1], name, n) != 0)
                return xml_error("end tag does not match the open element", name - 2);
            depth--;
            ++p;
        } else if (*p == '<') {
            const char *name = p + 1;
            if (!name_start((unsigned char)*name))
                return xml_error("bad tag name", p);
            for (p = name; name_char((unsigned char)*p); ++p) {
            }
            const size_t n = (size_t)(p - name);
            if (depth == 0 && roots++ > 0)
                return xml_error("second root element", name - 1);
            const char *attr_names[64];
            size_t attr_lengths[64], attrs = 0;
            for (;;) {
                const char *q = skip_space(p);
                if (*q == '>' || strncmp(q, "/>", 2) == 0) {
                    p = q;
                    break;
                }
                if (q == p)
                    return xml_error("no space before an attribute", p);
                const char *attr = q;
                if (!name_start((unsigned char)*attr))
                    return xml_error("bad attribute name", attr);
                for (p = attr; name_char((unsigned char)*p); ++p) {
                }
                const size_t an = (size_t)(p - attr);
                for (size_t k = 0; k < attrs; ++k)
                    if (attr_lengths[k] == an && strncmp(attr_names[k], attr, an) == 0)
                        return xml_error("duplicate attribute", attr);
                if (attrs == 64)
                    return xml_error("too many attributes", attr);
                attr_names[attrs] = attr;
                attr_lengths[attrs++] = an;
                p = skip_space(p);
                if (*p != '=')
                    return xml_error("attribute without a value", attr);
                p = skip_space(p + 1);
                const char quote = *p;
                if (quote != '"' && quote != '\'')
                    return xml_error("unquoted attribute value", attr);
                for (++p; *p != quote; ++p) {
                    if (*p == '\0' || *p == '<')
                        return xml_error("bad attribute value", attr);
                    if (*p == '&') {
                        const char *end = reference_end(p);
                        if (end == NULL)
                            return xml_error("bad reference", p);
                        p = end - 1;
                    }
                }
                ++p;
            }
            if (*p == '/') {
                p += 2;
            } else {
                if (depth == 64)
                    return xml_error("nesting too deep", name);
                open_names[depth] = name;
                open_lengths[depth++] = n;
                ++p;
            }
        } else if (*p == '&') {
            const char *end = reference_end(p);
            if (end == NULL)
                return xml_error("bad reference", p);
            if (depth == 0)
                return xml_error("text outside the root element", p);
            p = end;
        } else {
            if (depth == 0 && !isspace(c))
                return xml_error("text outside the root element", p);
            ++p;
        }
    }
    if (depth != 0)
        return xml_error("unclosed element", open_names[depth - 1]);
    if (roots != 1)
        return xml_error("no root element", doc);
    return 1;
}

/* ---- VTU structure ------------------------------------------------------------------------- */

/* Content of <DataArray Name="name" ...> (escaped name) and its NumberOfComponents, or NULL. */
static const char *find_array(const char *doc, const char *name, size_t *components)
{
    char key[160], tag[512];
    snprintf(key, sizeof(key), " Name=\"%s\"", name);
    for (const char *p = strstr(doc, "<DataArray"); p != NULL; p = strstr(p + 1, "<DataArray")) {
        const char *end = strchr(p, '>');
        if (end == NULL || (size_t)(end - p) >= sizeof(tag))
            return NULL;
        memcpy(tag, p, (size_t)(end - p));
        tag[end - p] = '\0';
        if (strstr(tag, key) == NULL)
            continue;
        const char *nc = strstr(tag, "NumberOfComponents=\"");
        *components = nc != NULL ? strtoul(nc + 20, NULL, 10) : 1;
        return end + 1;
    }
    return NULL;
}

/* Parse the numbers of an array's content (up to its closing tag) into out[max]; return the count.
 */
static size_t read_values(const char *content, double *out, size_t max)
{
    size_t n = 0;
    const char *p = skip_space(content);
    while (*p != '<' && *p != '\0') {
        char *end;
        const double v = strtod(p, &end);
        if (end == p)
            return (size_t)-1;
        if (n < max)
            out[n] = v;
        n++;
        p = skip_space(end);
    }
    return n;
}

static size_t array_values(const char *doc, const char *name, size_t components)
{
    size_t found = 0;
    const char *content = find_array(doc, name, &found);
    if (content == NULL) {
        print_error("no DataArray named %s\n", name);
        fail();
    }
    assert_int_equal(found, components);
    return read_values(content, NULL, 0);
}

/* ---- fixture ----------------------------------------------------------------------------- */

static const char *const NAMES[] = {"time", "temperature", "density", "neck"};
static const char *const UNITS[] = {"s", "K", "1", "1"};

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof(f));
    strcpy(f.dir, "/tmp/sinter_output_XXXXXX");
    if (mkdtemp(f.dir) == NULL || sinter_ctx_create(&f.ctx, NULL) != SINTER_OK ||
        sinter_material_create(&f.mat, f.ctx, "copper") != SINTER_OK ||
        sinter_particles_create(&f.ps, f.ctx) != SINTER_OK ||
        sinter_particles_set_material(f.ps, 0, f.mat) != SINTER_OK ||
        sinter_series_create(&f.series, f.ctx, 4, NAMES, UNITS) != SINTER_OK)
        return -1;
    for (int k = 0; k < 60; ++k) {
        const double t = 0.05 * k;
        const double row[4] = {t, 300.0 + 900.0 * (1.0 - exp(-t)), 0.6 + 0.3 * tanh(t - 1.0),
                               0.05 * t * t};
        if (sinter_series_append(f.series, row) != SINTER_OK)
            return -1;
    }
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sinter_series_destroy(f->series);
    sinter_particles_destroy(f->ps);
    sinter_material_destroy(f->mat);
    sinter_ctx_destroy(f->ctx);
    return nftw(f->dir, remove_entry, 8, FTW_DEPTH | FTW_PHYS);
}

/* Awkward but finite values: thirds, signed zero, subnormals, huge and tiny magnitudes. */
static const double AWKWARD[] = {1.0 / 3.0, -0.0,   1e-300,    0.1, -2.5e-7, 123456.789,
                                 5e-324,    -1e300, 2.0 / 7.0, 1.0, -0.3,    6.02214076e23,
                                 DBL_MIN,   -4.9,   1e-12,     0.7, 3.0,     -1.0 / 9.0};

static void add_particles(fixture *f, size_t n)
{
    double pos[3 * 6], rad[6];
    assert_true(n <= 6);
    for (size_t i = 0; i < 3 * n; ++i)
        pos[i] = AWKWARD[i];
    for (size_t i = 0; i < n; ++i)
        rad[i] = 1e-3 * (1.0 + (double)i / 3.0);
    assert_int_equal(sinter_particles_add(f->ps, n, pos, rad, 0, 300.0, NULL), SINTER_OK);
    double *v = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL),
                     SINTER_OK);
    for (size_t i = 0; i < 3 * n; ++i)
        v[i] = AWKWARD[3 * n - 1 - i] / 7.0;
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_VELOCITY), SINTER_OK);
}

/* ---- VTU --------------------------------------------------------------------------------- */

static void test_vtu_frame(void **state)
{
    fixture *f = *state;
    enum { N = 5 };
    add_particles(f, N);
    double contacts[N], necks[3 * N];
    for (size_t i = 0; i < N; ++i)
        contacts[i] = (double)i;
    for (size_t i = 0; i < 3 * N; ++i)
        necks[i] = 0.25 * (double)i;
    const sinter_vtu_array extra[2] = {{"contacts", contacts, 1}, {"neck <a&b>", necks, 3}};
    char path[256], tmp[256];
    path_in(f, "frame.vtu", path, sizeof(path));
    path_in(f, "frame.vtu.tmp", tmp, sizeof(tmp));
    assert_int_equal(sinter_write_vtu(f->ps, path, extra, 2), SINTER_OK);
    assert_false(exists(tmp));
    char *doc = slurp(path);
    assert_non_null(doc);
    assert_true(xml_well_formed(doc));
    assert_non_null(strstr(doc, "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
                                "byte_order=\"LittleEndian\">"));
    assert_non_null(strstr(doc, "<Piece NumberOfPoints=\"5\" NumberOfCells=\"5\">"));
    assert_non_null(strstr(doc, "<PointData Scalars=\"radius\">"));
    assert_int_equal(count_substrings(doc, "<DataArray"), 14);
    assert_int_equal(count_substrings(doc, "format=\"ascii\""), 14);
    static const struct {
        const char *name;
        size_t components;
    } arrays[] = {{"radius", 1},   {"velocity", 3},
                  {"spin", 3},     {"temperature", 1},
                  {"current", 1},  {"force", 3},
                  {"material", 1}, {"id", 1},
                  {"contacts", 1}, {"neck &lt;a&amp;b&gt;", 3},
                  {"position", 3}, {"connectivity", 1},
                  {"offsets", 1},  {"types", 1}};
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); ++k)
        assert_int_equal(array_values(doc, arrays[k].name, arrays[k].components),
                         N * arrays[k].components);
    assert_non_null(strstr(doc, "<DataArray type=\"Int32\" Name=\"material\""));
    assert_non_null(strstr(doc, "<DataArray type=\"UInt64\" Name=\"id\""));

    /* Positions and velocities read back bitwise; cells are vertices 0..N-1. */
    size_t comp;
    double values[3 * N];
    assert_int_equal(read_values(find_array(doc, "position", &comp), values, 3 * N), 3 * N);
    for (size_t i = 0; i < 3 * N; ++i)
        assert_same_bits(values[i], AWKWARD[i]);
    assert_int_equal(read_values(find_array(doc, "velocity", &comp), values, 3 * N), 3 * N);
    for (size_t i = 0; i < 3 * N; ++i)
        assert_same_bits(values[i], AWKWARD[3 * N - 1 - i] / 7.0);
    assert_int_equal(read_values(find_array(doc, "radius", &comp), values, N), N);
    for (size_t i = 0; i < N; ++i)
        assert_same_bits(values[i], 1e-3 * (1.0 + (double)i / 3.0));
    assert_int_equal(read_values(find_array(doc, "connectivity", &comp), values, N), N);
    for (size_t i = 0; i < N; ++i)
        assert_same_bits(values[i], (double)i);
    assert_int_equal(read_values(find_array(doc, "offsets", &comp), values, N), N);
    for (size_t i = 0; i < N; ++i)
        assert_same_bits(values[i], (double)(i + 1));
    assert_int_equal(read_values(find_array(doc, "types", &comp), values, N), N);
    for (size_t i = 0; i < N; ++i)
        assert_same_bits(values[i], 1.0);
    free(doc);
}

static void test_vtu_zero_particles(void **state)
{
    fixture *f = *state;
    const sinter_vtu_array extra = {"contacts", NULL, 1};
    char path[256];
    path_in(f, "empty.vtu", path, sizeof(path));
    assert_int_equal(sinter_write_vtu(f->ps, path, &extra, 1), SINTER_OK);
    char *doc = slurp(path);
    assert_non_null(doc);
    assert_true(xml_well_formed(doc));
    assert_non_null(strstr(doc, "NumberOfPoints=\"0\" NumberOfCells=\"0\""));
    assert_int_equal(array_values(doc, "position", 3), 0);
    assert_int_equal(array_values(doc, "radius", 1), 0);
    assert_int_equal(array_values(doc, "contacts", 1), 0);
    assert_int_equal(array_values(doc, "types", 1), 0);
    free(doc);
}

static void test_vtu_rejects_bad_arguments(void **state)
{
    fixture *f = *state;
    add_particles(f, 2);
    const double data[6] = {0};
    char path[256];
    path_in(f, "bad.vtu", path, sizeof(path));
    assert_int_equal(sinter_write_vtu(NULL, path, NULL, 0), SINTER_ERR_NULL);
    assert_int_equal(sinter_write_vtu(f->ps, NULL, NULL, 0), SINTER_ERR_NULL);
    assert_message(f->ctx, "path");
    assert_int_equal(sinter_write_vtu(f->ps, "", NULL, 0), SINTER_ERR_INVALID);
    assert_message(f->ctx, "empty");
    assert_int_equal(sinter_write_vtu(f->ps, path, NULL, 1), SINTER_ERR_NULL);
    assert_message(f->ctx, "extra");
    sinter_vtu_array two = {"stress", data, 2};
    assert_int_equal(sinter_write_vtu(f->ps, path, &two, 1), SINTER_ERR_INVALID);
    assert_message(f->ctx, "stress");
    assert_message(f->ctx, "2 components");
    sinter_vtu_array unnamed = {NULL, data, 1};
    assert_int_equal(sinter_write_vtu(f->ps, path, &unnamed, 1), SINTER_ERR_NULL);
    assert_message(f->ctx, "extra[0].name");
    sinter_vtu_array no_data = {"contacts", NULL, 1};
    assert_int_equal(sinter_write_vtu(f->ps, path, &no_data, 1), SINTER_ERR_NULL);
    assert_message(f->ctx, "contacts");
    sinter_vtu_array builtin = {"radius", data, 1};
    assert_int_equal(sinter_write_vtu(f->ps, path, &builtin, 1), SINTER_ERR_INVALID);
    assert_message(f->ctx, "radius");
    const sinter_vtu_array twice[2] = {{"c", data, 1}, {"c", data, 3}};
    assert_int_equal(sinter_write_vtu(f->ps, path, twice, 2), SINTER_ERR_INVALID);
    assert_message(f->ctx, "extra[1]");
    assert_int_equal(directory_entries(f->dir), 0);
}

/* ---- PVD --------------------------------------------------------------------------------- */

static void test_pvd_lists_frames(void **state)
{
    fixture *f = *state;
    const double times[3] = {0.0, 0.1, 1.0 / 3.0};
    const char *const files[3] = {"frames/f_0000.vtu", "a&b<c>.vtu", "say \"hi\".vtu"};
    char path[256];
    path_in(f, "run.pvd", path, sizeof(path));
    assert_int_equal(sinter_write_pvd(f->ctx, path, 3, times, files), SINTER_OK);
    char *doc = slurp(path);
    assert_non_null(doc);
    assert_true(xml_well_formed(doc));
    assert_non_null(strstr(doc, "<VTKFile type=\"Collection\""));
    assert_int_equal(count_substrings(doc, "<DataSet "), 3);
    assert_non_null(strstr(doc, "file=\"frames/f_0000.vtu\""));
    assert_non_null(strstr(doc, "file=\"a&amp;b&lt;c&gt;.vtu\""));
    assert_non_null(strstr(doc, "file=\"say &quot;hi&quot;.vtu\""));
    size_t k = 0;
    for (const char *p = strstr(doc, "timestep=\""); p != NULL; p = strstr(p + 1, "timestep=\""))
        assert_same_bits(strtod(p + 10, NULL), times[k++]);
    assert_int_equal(k, 3);
    free(doc);

    /* An empty collection is still a valid file. */
    assert_int_equal(sinter_write_pvd(f->ctx, path, 0, NULL, NULL), SINTER_OK);
    doc = slurp(path);
    assert_true(xml_well_formed(doc));
    assert_int_equal(count_substrings(doc, "<DataSet"), 0);
    free(doc);
}

static void test_pvd_rejects_bad_arguments(void **state)
{
    fixture *f = *state;
    const double times[2] = {0.0, NAN};
    const char *const files[2] = {"a.vtu", NULL};
    const char *const good[2] = {"a.vtu", "b.vtu"};
    char path[256];
    path_in(f, "bad.pvd", path, sizeof(path));
    assert_int_equal(sinter_write_pvd(NULL, path, 2, times, good), SINTER_ERR_NULL);
    assert_int_equal(sinter_write_pvd(f->ctx, NULL, 2, times, good), SINTER_ERR_NULL);
    assert_int_equal(sinter_write_pvd(f->ctx, "", 1, times, good), SINTER_ERR_INVALID);
    assert_int_equal(sinter_write_pvd(f->ctx, path, 2, NULL, good), SINTER_ERR_NULL);
    assert_message(f->ctx, "times");
    assert_int_equal(sinter_write_pvd(f->ctx, path, 2, times, NULL), SINTER_ERR_NULL);
    assert_message(f->ctx, "files");
    assert_int_equal(sinter_write_pvd(f->ctx, path, 2, times, files), SINTER_ERR_NULL);
    assert_message(f->ctx, "files[1]");
    assert_int_equal(sinter_write_pvd(f->ctx, path, 2, times, good), SINTER_ERR_INVALID);
    assert_message(f->ctx, "times[1]");
    const char *const blank[1] = {""};
    assert_int_equal(sinter_write_pvd(f->ctx, path, 1, times, blank), SINTER_ERR_INVALID);
    assert_message(f->ctx, "files[0]");
    assert_int_equal(directory_entries(f->dir), 0);
}

/* ---- series and CSV ---------------------------------------------------------------------- */

static void test_csv_round_trip(void **state)
{
    fixture *f = *state;
    const char *const names[3] = {"time", "temp, mean", "ratio \"r\""};
    const char *const units[3] = {"s", "K", NULL};
    sinter_series *s = NULL;
    assert_int_equal(sinter_series_create(&s, f->ctx, 3, names, units), SINTER_OK);
    enum { ROWS = 8 };
    double rows[ROWS][3];
    for (size_t r = 0; r < ROWS; ++r)
        for (size_t c = 0; c < 3; ++c)
            rows[r][c] = AWKWARD[(3 * r + c) % 18];
    rows[2][1] = NAN;
    rows[3][1] = -NAN;
    rows[4][0] = INFINITY;
    rows[4][2] = -INFINITY;
    rows[5][2] = DBL_MAX;
    rows[6][0] = -DBL_MIN;
    for (size_t r = 0; r < ROWS; ++r)
        assert_int_equal(sinter_series_append(s, rows[r]), SINTER_OK);
    size_t n = 0;
    assert_int_equal(sinter_series_rows(s, &n), SINTER_OK);
    assert_int_equal(n, ROWS);
    double v;
    assert_int_equal(sinter_series_get(s, 5, 2, &v), SINTER_OK);
    assert_same_bits(v, DBL_MAX);

    char path[256];
    path_in(f, "series.csv", path, sizeof(path));
    assert_int_equal(sinter_series_write_csv(s, path), SINTER_OK);
    char *doc = slurp(path);
    assert_non_null(doc);
    const char *header = "time [s],\"temp, mean [K]\",\"ratio \"\"r\"\"\"\n";
    assert_memory_equal(doc, header, strlen(header));
    const char *p = doc + strlen(header);
    for (size_t r = 0; r < ROWS; ++r) {
        for (size_t c = 0; c < 3; ++c) {
            char *end;
            const double x = strtod(p, &end);
            assert_true(end > p);
            if (isnan(rows[r][c])) {
                assert_memory_equal(p, "nan", 3);
                assert_true(end - p == 3 && isnan(x));
            } else {
                assert_same_bits(x, rows[r][c]);
            }
            assert_int_equal(*end, c < 2 ? ',' : '\n');
            p = end + 1;
        }
    }
    assert_int_equal(*p, '\0');
    assert_non_null(strstr(doc, "\ninf,"));
    assert_non_null(strstr(doc, ",-inf\n"));
    free(doc);
    sinter_series_destroy(s);

    /* Without units the header carries the names alone. */
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, names, NULL), SINTER_OK);
    assert_int_equal(sinter_series_write_csv(s, path), SINTER_OK);
    doc = slurp(path);
    assert_string_equal(doc, "time,\"temp, mean\"\n");
    free(doc);
    sinter_series_destroy(s);
}

static void test_series_rejects_bad_arguments(void **state)
{
    fixture *f = *state;
    sinter_series *s = NULL;
    const char *const holes[2] = {"time", NULL};
    const char *const blank[2] = {"time", ""};
    assert_int_equal(sinter_series_create(&s, NULL, 2, NAMES, UNITS), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_create(NULL, f->ctx, 2, NAMES, UNITS), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_create(&s, f->ctx, 0, NAMES, UNITS), SINTER_ERR_INVALID);
    assert_message(f->ctx, "columns");
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, NULL, UNITS), SINTER_ERR_NULL);
    assert_message(f->ctx, "names");
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, holes, UNITS), SINTER_ERR_NULL);
    assert_message(f->ctx, "names[1]");
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, blank, UNITS), SINTER_ERR_INVALID);
    assert_message(f->ctx, "names[1]");
    assert_null(s);

    double v = 0.0;
    size_t rows = 0;
    assert_int_equal(sinter_series_append(NULL, &v), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_append(f->series, NULL), SINTER_ERR_NULL);
    assert_message(f->ctx, "row");
    assert_int_equal(sinter_series_rows(NULL, &rows), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_rows(f->series, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_get(f->series, 60, 0, &v), SINTER_ERR_RANGE);
    assert_message(f->ctx, "row 60");
    assert_int_equal(sinter_series_get(f->series, 0, 4, &v), SINTER_ERR_RANGE);
    assert_message(f->ctx, "column 4");
    assert_int_equal(sinter_series_get(f->series, 0, 0, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_get(NULL, 0, 0, &v), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_write_csv(NULL, "x.csv"), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_write_csv(f->series, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_write_csv(f->series, ""), SINTER_ERR_INVALID);
    sinter_series_destroy(NULL);
    assert_int_equal(directory_entries(f->dir), 0);
}

/* ---- SVG --------------------------------------------------------------------------------- */

static char *write_svg(fixture *f, const sinter_series *s, const char *title, size_t panels,
                       const size_t *start, const size_t *columns)
{
    char path[256];
    path_in(f, "plot.svg", path, sizeof(path));
    assert_int_equal(sinter_series_write_svg(s, path, title, 0, panels, start, columns), SINTER_OK);
    char *doc = slurp(path);
    assert_non_null(doc);
    assert_true(xml_well_formed(doc));
    assert_null(strstr(doc, "nan"));
    assert_null(strstr(doc, "inf"));
    return doc;
}

static void test_svg_plot(void **state)
{
    fixture *f = *state;
    const size_t start[3] = {0, 1, 3}, columns[3] = {1, 2, 3};
    char *doc = write_svg(f, f->series, "Sintering <&> \"run\"", 2, start, columns);
    assert_non_null(strstr(doc, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert_int_equal(count_substrings(doc, "<polyline"), 3);
    assert_non_null(strstr(doc, ">Sintering &lt;&amp;&gt; &quot;run&quot;</text>"));
    assert_null(strstr(doc, "<&>"));
    assert_non_null(strstr(doc, ">time [s]</text>"));
    assert_non_null(strstr(doc, ">temperature [K]</text>"));
    assert_non_null(strstr(doc, ">density [1]</text>"));
    assert_non_null(strstr(doc, ">density, neck [1]</text>"));
    free(doc);

    /* The same column may appear in several panels; no title. */
    const size_t start3[4] = {0, 1, 2, 5}, columns3[5] = {1, 1, 1, 2, 3};
    doc = write_svg(f, f->series, NULL, 3, start3, columns3);
    assert_int_equal(count_substrings(doc, "<polyline"), 5);
    free(doc);
}

static void test_svg_degenerate_data(void **state)
{
    fixture *f = *state;
    const char *const names[2] = {"t", "y"};
    const size_t start[2] = {0, 1}, columns[1] = {1};
    sinter_series *s = NULL;
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, names, NULL), SINTER_OK);
    /* No rows at all. */
    char *doc = write_svg(f, s, "empty", 1, start, columns);
    assert_int_equal(count_substrings(doc, "<polyline"), 0);
    free(doc);
    /* A single row: a dot, no division by zero. */
    const double one[2] = {2.0, 5.0};
    assert_int_equal(sinter_series_append(s, one), SINTER_OK);
    doc = write_svg(f, s, NULL, 1, start, columns);
    assert_int_equal(count_substrings(doc, "<polyline"), 0);
    assert_int_equal(count_substrings(doc, "<circle"), 1);
    free(doc);
    /* Constant y. */
    for (int k = 1; k < 10; ++k) {
        const double row[2] = {2.0 + k, 5.0};
        assert_int_equal(sinter_series_append(s, row), SINTER_OK);
    }
    doc = write_svg(f, s, NULL, 1, start, columns);
    assert_int_equal(count_substrings(doc, "<polyline"), 1);
    free(doc);
    /* A NaN or infinite y breaks the line; a row with NaN x is skipped. */
    const double gap[2] = {20.0, NAN}, more[2] = {21.0, 6.0}, lost[2] = {NAN, 100.0},
                 last[2] = {22.0, 7.0}, spike[2] = {23.0, INFINITY}, end[2] = {24.0, 7.5};
    assert_int_equal(sinter_series_append(s, gap), SINTER_OK);
    assert_int_equal(sinter_series_append(s, more), SINTER_OK);
    assert_int_equal(sinter_series_append(s, lost), SINTER_OK);
    assert_int_equal(sinter_series_append(s, last), SINTER_OK);
    assert_int_equal(sinter_series_append(s, spike), SINTER_OK);
    assert_int_equal(sinter_series_append(s, end), SINTER_OK);
    doc = write_svg(f, s, NULL, 1, start, columns);
    assert_int_equal(count_substrings(doc, "<polyline"), 2);
    assert_int_equal(count_substrings(doc, "<circle"), 1);
    free(doc);
    sinter_series_destroy(s);

    /* Constant x, and tiny values around a large offset. */
    assert_int_equal(sinter_series_create(&s, f->ctx, 2, names, NULL), SINTER_OK);
    for (int k = 0; k < 5; ++k) {
        const double row[2] = {0.0, 1000.0 + 1e-3 * k};
        assert_int_equal(sinter_series_append(s, row), SINTER_OK);
    }
    doc = write_svg(f, s, NULL, 1, start, columns);
    assert_int_equal(count_substrings(doc, "<polyline"), 1);
    assert_non_null(strstr(doc, ">1000.002</text>"));
    free(doc);
    sinter_series_destroy(s);
}

static void test_svg_rejects_bad_arguments(void **state)
{
    fixture *f = *state;
    const size_t start[2] = {0, 1}, columns[1] = {1}, empty[3] = {0, 0, 1}, wild[1] = {9};
    char path[256];
    path_in(f, "bad.svg", path, sizeof(path));
    sinter_series *s = f->series;
    assert_int_equal(sinter_series_write_svg(NULL, path, NULL, 0, 1, start, columns),
                     SINTER_ERR_NULL);
    assert_int_equal(sinter_series_write_svg(s, NULL, NULL, 0, 1, start, columns), SINTER_ERR_NULL);
    assert_int_equal(sinter_series_write_svg(s, "", NULL, 0, 1, start, columns),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 4, 1, start, columns),
                     SINTER_ERR_RANGE);
    assert_message(f->ctx, "x_column 4");
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 0, 0, start, columns),
                     SINTER_ERR_INVALID);
    assert_message(f->ctx, "panels");
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 0, 1, NULL, columns), SINTER_ERR_NULL);
    assert_message(f->ctx, "panel_start");
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 0, 1, start, NULL), SINTER_ERR_NULL);
    assert_message(f->ctx, "panel_columns");
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 0, 2, empty, columns),
                     SINTER_ERR_INVALID);
    assert_message(f->ctx, "panel 0");
    assert_int_equal(sinter_series_write_svg(s, path, NULL, 0, 1, start, wild), SINTER_ERR_RANGE);
    assert_message(f->ctx, "column 9");
    assert_int_equal(directory_entries(f->dir), 0);
}

/* ---- safe writes ------------------------------------------------------------------------- */

enum { KIND_VTU, KIND_PVD, KIND_CSV, KIND_SVG, KINDS };

static sinter_status write_kind(fixture *f, int kind, const char *path)
{
    const double times[1] = {0.5};
    const char *const files[1] = {"a.vtu"};
    const size_t start[2] = {0, 2}, columns[2] = {1, 2};
    switch (kind) {
    case KIND_VTU:
        return sinter_write_vtu(f->ps, path, NULL, 0);
    case KIND_PVD:
        return sinter_write_pvd(f->ctx, path, 1, times, files);
    case KIND_CSV:
        return sinter_series_write_csv(f->series, path);
    default:
        return sinter_series_write_svg(f->series, path, "t", 0, 1, start, columns);
    }
}

static void test_missing_directory(void **state)
{
    fixture *f = *state;
    add_particles(f, 3);
    char path[256];
    path_in(f, "missing/out.file", path, sizeof(path));
    for (int kind = 0; kind < KINDS; ++kind) {
        assert_int_equal(write_kind(f, kind, path), SINTER_ERR_IO);
        assert_int_equal(sinter_last_status(f->ctx), SINTER_ERR_IO);
        assert_message(f->ctx, path);
        assert_message(f->ctx, strerror(ENOENT));
    }
    assert_int_equal(directory_entries(f->dir), 0);
}

static void test_failed_write_keeps_existing_file(void **state)
{
    fixture *f = *state;
    add_particles(f, 3);
    char path[256], tmp[256];
    path_in(f, "out.file", path, sizeof(path));
    path_in(f, "out.file.tmp", tmp, sizeof(tmp));
    static const char original[] = "an existing good file\n";
    const int have_dev_full = access("/dev/full", W_OK) == 0;
    for (int kind = 0; kind < KINDS; ++kind) {
        FILE *fp = fopen(path, "wb");
        assert_non_null(fp);
        fputs(original, fp);
        fclose(fp);

        /* Writing fails midway (the temporary file is a link to a full device). */
        if (have_dev_full) {
            assert_int_equal(symlink("/dev/full", tmp), 0);
            assert_int_equal(write_kind(f, kind, path), SINTER_ERR_IO);
            assert_message(f->ctx, strerror(ENOSPC));
            assert_false(exists(tmp));
            char *doc = slurp(path);
            assert_string_equal(doc, original);
            free(doc);
        }
        /* The temporary file cannot be created: it is not ours, so it stays. */
        assert_int_equal(mkdir(tmp, 0700), 0);
        assert_int_equal(write_kind(f, kind, path), SINTER_ERR_IO);
        assert_message(f->ctx, tmp);
        char *doc = slurp(path);
        assert_string_equal(doc, original);
        free(doc);
        assert_int_equal(rmdir(tmp), 0);
        /* Then it works and replaces the file. */
        assert_int_equal(write_kind(f, kind, path), SINTER_OK);
        assert_false(exists(tmp));
        doc = slurp(path);
        assert_string_not_equal(doc, original);
        free(doc);
    }
    /* The rename fails (the target is a directory): the temporary file is removed. */
    char dir[256], dir_tmp[256];
    path_in(f, "taken", dir, sizeof(dir));
    path_in(f, "taken.tmp", dir_tmp, sizeof(dir_tmp));
    assert_int_equal(mkdir(dir, 0700), 0);
    for (int kind = 0; kind < KINDS; ++kind) {
        assert_int_equal(write_kind(f, kind, dir), SINTER_ERR_IO);
        assert_message(f->ctx, "rename");
        assert_false(exists(dir_tmp));
    }
}

static void test_allocation_failure(void **state)
{
    fixture *f = *state;
    char path[256], tmp[256];
    path_in(f, "alloc.file", path, sizeof(path));
    path_in(f, "alloc.file.tmp", tmp, sizeof(tmp));
    for (int kind = 0; kind < KINDS; ++kind) {
        int failures_seen = 0;
        for (long budget = 0; budget < 64; ++budget) {
            counting_allocator c = {0, 0, -1, 0};
            const sinter_allocator hook = counting_allocator_hook(&c);
            fixture g;
            memset(&g, 0, sizeof(g));
            strcpy(g.dir, f->dir);
            assert_int_equal(sinter_ctx_create(&g.ctx, &hook), SINTER_OK);
            assert_int_equal(sinter_material_create(&g.mat, g.ctx, "m"), SINTER_OK);
            assert_int_equal(sinter_particles_create(&g.ps, g.ctx), SINTER_OK);
            assert_int_equal(sinter_particles_set_material(g.ps, 0, g.mat), SINTER_OK);
            assert_int_equal(sinter_series_create(&g.series, g.ctx, 4, NAMES, UNITS), SINTER_OK);
            const double row[4] = {0.0, 1.0, 2.0, 3.0}, row2[4] = {1.0, 2.0, 1.0, 0.0};
            assert_int_equal(sinter_series_append(g.series, row), SINTER_OK);
            assert_int_equal(sinter_series_append(g.series, row2), SINTER_OK);
            add_particles(&g, 2);
            c.fail_after = c.calls + budget;
            const sinter_status st = write_kind(&g, kind, path);
            if (st != SINTER_OK) {
                assert_int_equal(st, SINTER_ERR_NOMEM);
                assert_false(exists(path));
                assert_false(exists(tmp));
                failures_seen++;
            }
            sinter_series_destroy(g.series);
            sinter_particles_destroy(g.ps);
            sinter_material_destroy(g.mat);
            sinter_ctx_destroy(g.ctx);
            assert_int_equal(c.allocations, c.frees);
            if (st == SINTER_OK)
                break;
        }
        assert_true(failures_seen >= 1);
        assert_int_equal(remove(path), 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_vtu_frame, setup, teardown),
        cmocka_unit_test_setup_teardown(test_vtu_zero_particles, setup, teardown),
        cmocka_unit_test_setup_teardown(test_vtu_rejects_bad_arguments, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pvd_lists_frames, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pvd_rejects_bad_arguments, setup, teardown),
        cmocka_unit_test_setup_teardown(test_csv_round_trip, setup, teardown),
        cmocka_unit_test_setup_teardown(test_series_rejects_bad_arguments, setup, teardown),
        cmocka_unit_test_setup_teardown(test_svg_plot, setup, teardown),
        cmocka_unit_test_setup_teardown(test_svg_degenerate_data, setup, teardown),
        cmocka_unit_test_setup_teardown(test_svg_rejects_bad_arguments, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_directory, setup, teardown),
        cmocka_unit_test_setup_teardown(test_failed_write_keeps_existing_file, setup, teardown),
        cmocka_unit_test_setup_teardown(test_allocation_failure, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
