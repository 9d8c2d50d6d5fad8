/*
 * Binary VTU frames (src/io/vtu.c, sinter_write_vtu_as; the scene runner's default): every array
 * decoded from its base64 (a UInt64 byte count encoded on its own, then the little-endian
 * elements) equals, bit for bit, the same array of the ascii frame ("%.17g", which reads back
 * exactly) and the particles' own values; byte counts that leave 0, 1 and 2 bytes over a
 * triplet, and arrays longer than the writer's 3072-byte chunks. Arrays of zeros (spin, force
 * and current here) stay ascii in a binary file, and only they. In single precision
 * (SINTER_VTK_FLOAT32, [output] vtu_precision = single) every floating-point array is Float32
 * holding the float nearest to each value, in binary and in ascii ("%.9g" reads back to it).
 * Made raw appended data (sinter_vtk_make_appended, vtu_format = appended), every binary
 * array's bytes at its offset in the <AppendedData> section are the inline array's, and the
 * ascii arrays stay as they were.
 */
#define _XOPEN_SOURCE 700 /* mkdtemp */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test_support.h"

#include "io/vtk_appended.h"
#include "io/vtk_arrays.h"
#include "io/vtu.h"

static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    const long size = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *doc = malloc((size_t)size + 1);
    assert_non_null(doc);
    assert_int_equal(fread(doc, 1, (size_t)size, fp), (size_t)size);
    doc[size] = '\0';
    fclose(fp);
    return doc;
}

/* The text between the opening tag of <DataArray ... Name="name" ...> and its closing tag;
 * the tag's type attribute into type. */
static const char *array_text(const char *doc, const char *name, char type[16], size_t *length)
{
    char key[96];
    snprintf(key, sizeof(key), " Name=\"%s\"", name);
    for (const char *p = strstr(doc, "<DataArray"); p != NULL; p = strstr(p + 1, "<DataArray")) {
        const char *end = strchr(p, '>');
        const char *k = strstr(p, key);
        if (end == NULL || k == NULL || k > end)
            continue;
        const char *t = strstr(p, "type=\"") + 6;
        const size_t tl = (size_t)(strchr(t, '"') - t);
        assert_true(tl < 16);
        memcpy(type, t, tl);
        type[tl] = '\0';
        const char *close = strstr(end, "</DataArray>");
        *length = (size_t)(close - (end + 1));
        return end + 1;
    }
    fail_msg("no DataArray %s", name);
    return NULL;
}

static int sextet(char c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    if (c == '+')
        return 62;
    if (c == '/')
        return 63;
    fail_msg("not base64: '%c'", c);
    return -1;
}

/* Decode `chars` base64 characters (a multiple of 4, padding included) into out; the bytes. */
static size_t decode(const char *in, size_t chars, unsigned char *out)
{
    assert_int_equal(chars % 4, 0);
    size_t n = 0;
    for (size_t k = 0; k < chars; k += 4) {
        const int pad = (in[k + 2] == '=') + (in[k + 3] == '=');
        const unsigned long v = ((unsigned long)sextet(in[k]) << 18) |
                                ((unsigned long)sextet(in[k + 1]) << 12) |
                                ((unsigned long)(pad >= 2 ? 0 : sextet(in[k + 2])) << 6) |
                                (unsigned long)(pad >= 1 ? 0 : sextet(in[k + 3]));
        out[n++] = (unsigned char)(v >> 16);
        if (pad < 2)
            out[n++] = (unsigned char)(v >> 8);
        if (pad < 1)
            out[n++] = (unsigned char)v;
        if (pad > 0) /* padding ends a stream */
            assert_int_equal(k + 4, chars);
    }
    return n;
}

static uint64_t little_endian(const unsigned char *b, size_t width)
{
    uint64_t v = 0;
    for (size_t k = 0; k < width; ++k)
        v |= (uint64_t)b[k] << (8 * k);
    return v;
}

/* The values of a binary array as bit patterns (doubles) or integers, into out; their count. */
static size_t binary_values(const char *doc, const char *name, uint64_t *out, size_t max)
{
    char type[16];
    size_t length;
    const char *text = array_text(doc, name, type, &length);
    while (*text == ' ' || *text == '\n')
        ++text, --length;
    while (length > 0 && (text[length - 1] == ' ' || text[length - 1] == '\n'))
        --length;
    /* the byte count: eight bytes encoded on their own (12 characters, one '=') */
    unsigned char header[9];
    assert_int_equal(decode(text, 12, header), 8);
    assert_true(text[11] == '=' && text[10] != '=');
    const uint64_t bytes = little_endian(header, 8);
    const size_t width = strcmp(type, "UInt8") == 0                                   ? 1
                         : strcmp(type, "Int32") == 0 || strcmp(type, "Float32") == 0 ? 4
                                                                                      : 8;
    unsigned char *data = malloc(length);
    assert_non_null(data);
    assert_int_equal(decode(text + 12, length - 12, data), bytes);
    assert_int_equal(bytes % width, 0);
    const size_t count = bytes / width;
    assert_true(count <= max);
    for (size_t i = 0; i < count; ++i) {
        uint64_t v = little_endian(data + width * i, width);
        if (strcmp(type, "Int32") == 0) /* sign-extended, as the ascii reading gives it */
            v = (uint64_t)(int64_t)(int32_t)(uint32_t)v;
        out[i] = v;
    }
    free(data);
    return count;
}

/* The values of an ascii array the same way (strtod: exact for "%.17g"). */
static size_t ascii_values(const char *doc, const char *name, uint64_t *out, size_t max)
{
    char type[16];
    size_t length;
    const char *p = array_text(doc, name, type, &length), *end = p + length;
    size_t n = 0;
    while (p < end) {
        char *next;
        if (strcmp(type, "Float64") == 0) {
            const double d = strtod(p, &next);
            if (next != p)
                memcpy(&out[n], &d, sizeof(d));
        } else if (strcmp(type, "Float32") == 0) {
            const float f = strtof(p, &next);
            uint32_t bits = 0;
            memcpy(&bits, &f, sizeof(bits));
            if (next != p)
                out[n] = bits;
        } else {
            const long long v = strtoll(p, &next, 10);
            if (next != p)
                out[n] = (uint64_t)v;
        }
        if (next == p) {
            ++p;
            continue;
        }
        assert_true(++n <= max);
        p = next;
    }
    return n;
}

static const char *const ARRAYS[] = {"radius",       "velocity", "spin", "temperature", "current",
                                     "force",        "material", "id",   "contacts",    "position",
                                     "connectivity", "offsets",  "types"};

/* 1 if the array is written in binary. */
static int is_binary(const char *doc, const char *name)
{
    char key[96];
    snprintf(key, sizeof(key), " Name=\"%s\"", name);
    const char *tag = strstr(doc, key), *end = strchr(tag, '>');
    const char *format = strstr(tag, "format=\"binary\"");
    return format != NULL && format < end;
}

/* Write ps both ways (with one extra array) and compare every array. */
static void compare_frames(sinter_particles *ps, size_t n, const char *dir)
{
    char ascii_path[128], binary_path[128];
    snprintf(ascii_path, sizeof(ascii_path), "%s/a.vtu", dir);
    snprintf(binary_path, sizeof(binary_path), "%s/b.vtu", dir);
    double *contacts = malloc((n + 1) * sizeof(double));
    assert_non_null(contacts);
    for (size_t i = 0; i < n; ++i)
        contacts[i] = (double)(i % 7) / 3.0;
    const sinter_vtu_array extra[1] = {{"contacts", contacts, 1}};
    assert_int_equal(sinter_write_vtu_as(ps, ascii_path, extra, 1, 0), SINTER_OK);
    assert_int_equal(sinter_write_vtu_as(ps, binary_path, extra, 1, 1), SINTER_OK);
    char *a = slurp(ascii_path), *b = slurp(binary_path);
    assert_non_null(strstr(b, "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
                              "byte_order=\"LittleEndian\" header_type=\"UInt64\">"));
    assert_non_null(strstr(b, "format=\"ascii\"")); /* spin, force, current: zeros */
    const size_t max = 3 * n + 1;
    uint64_t *va = malloc(max * sizeof(uint64_t)), *vb = malloc(max * sizeof(uint64_t));
    assert_true(va != NULL && vb != NULL);
    for (size_t k = 0; k < sizeof(ARRAYS) / sizeof(ARRAYS[0]); ++k) {
        assert_false(is_binary(a, ARRAYS[k]));
        const size_t na = ascii_values(a, ARRAYS[k], va, max);
        const int binary = is_binary(b, ARRAYS[k]);
        const size_t nb =
            binary ? binary_values(b, ARRAYS[k], vb, max) : ascii_values(b, ARRAYS[k], vb, max);
        assert_int_equal(na, nb);
        assert_true(na == n || na == 3 * n);
        assert_memory_equal(va, vb, na * sizeof(uint64_t));
        int zeros = 1; /* every value +0.0 (the bits of an integer 0 too) */
        for (size_t i = 0; i < na; ++i)
            zeros &= va[i] == 0;
        const int is_double = strcmp(ARRAYS[k], "material") != 0 && strcmp(ARRAYS[k], "id") != 0 &&
                              strcmp(ARRAYS[k], "connectivity") != 0 &&
                              strcmp(ARRAYS[k], "offsets") != 0 && strcmp(ARRAYS[k], "types") != 0;
        if (binary == (zeros && is_double))
            fail_msg("array %s: %s in the binary file", ARRAYS[k], binary ? "binary" : "ascii");
    }
    /* and the particles' own positions, bit for bit */
    const double *x = NULL;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL),
        SINTER_OK);
    assert_int_equal(binary_values(b, "position", vb, max), 3 * n);
    assert_memory_equal(vb, x, 3 * n * sizeof(double));
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_POSITION), SINTER_OK);
    free(va);
    free(vb);
    free(a);
    free(b);
    free(contacts);
    remove(ascii_path);
    remove(binary_path);
}

static void test_binary_frames_match_ascii(void **state)
{
    (void)state;
    char dir[] = "/tmp/sinter_vtu_XXXXXX";
    assert_non_null(mkdtemp(dir));
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_material_create(&mat, ctx, "copper"), SINTER_OK);
    assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(ps, 0, mat), SINTER_OK);
    /* 5 particles: 40-byte arrays (1 byte over a triplet), 120 (none), 20 and 5 (2 over);
     * awkward values: signed zero, subnormals, huge and tiny magnitudes */
    static const double awkward[15] = {1.0 / 3.0,  -0.0,          1e-300,  0.1,     -2.5e-7,
                                       123456.789, 5e-324,        -1e300,  2.0 / 7, 1.0,
                                       -0.3,       6.02214076e23, DBL_MIN, -4.9,    1e-12};
    const double radius[5] = {1e-3, 2e-3, 1.5e-3, 1e-3 / 3.0, 7e-4};
    assert_int_equal(sinter_particles_add(ps, 5, awkward, radius, 0, 300.0, NULL), SINTER_OK);
    compare_frames(ps, 5, dir);
    /* 1000 more: arrays of 8048 and 24 144 bytes, several chunks */
    enum { M = 1000 };
    double *x = malloc(3 * M * sizeof(double)), *r = malloc(M * sizeof(double));
    assert_true(x != NULL && r != NULL);
    for (size_t i = 0; i < M; ++i) {
        for (int d = 0; d < 3; ++d)
            x[3 * i + (size_t)d] = 0.01 * (double)((i * (size_t)(d + 3)) % 97) / 7.0;
        r[i] = 1e-4 * (1.0 + (double)(i % 11) / 13.0);
    }
    assert_int_equal(sinter_particles_add(ps, M, x, r, 0, 500.0, NULL), SINTER_OK);
    compare_frames(ps, 5 + M, dir);
    free(x);
    free(r);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    rmdir(dir);
}

/* Single precision, binary and ascii: the positions and radii are the floats nearest to the
 * particles' values; the integer arrays are unchanged. */
static void test_single_precision(void **state)
{
    (void)state;
    char dir[] = "/tmp/sinter_vtu_XXXXXX";
    assert_non_null(mkdtemp(dir));
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_material_create(&mat, ctx, "copper"), SINTER_OK);
    assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(ps, 0, mat), SINTER_OK);
    enum { M = 700 };
    double *x = malloc(3 * M * sizeof(double)), *r = malloc(M * sizeof(double));
    assert_true(x != NULL && r != NULL);
    for (size_t i = 0; i < M; ++i) {
        for (int d = 0; d < 3; ++d)
            x[3 * i + (size_t)d] = 0.01 * (double)((i * (size_t)(d + 3)) % 97) / 7.0 + 1e-9;
        r[i] = 1e-4 * (1.0 + (double)(i % 11) / 13.0);
    }
    assert_int_equal(sinter_particles_add(ps, M, x, r, 0, 500.0, NULL), SINTER_OK);
    uint64_t *v = malloc(3 * M * sizeof(uint64_t));
    assert_non_null(v);
    for (int binary = 0; binary <= 1; ++binary) {
        char path[128];
        snprintf(path, sizeof(path), "%s/s%d.vtu", dir, binary);
        assert_int_equal(sinter_write_vtu_as(ps, path, NULL, 0, binary | SINTER_VTK_FLOAT32),
                         SINTER_OK);
        char *doc = slurp(path);
        assert_null(strstr(doc, "Float64"));
        const struct {
            const char *name;
            const double *values;
            size_t count;
        } arrays[2] = {{"position", x, 3 * M}, {"radius", r, M}};
        for (int k = 0; k < 2; ++k) {
            const size_t n = binary ? binary_values(doc, arrays[k].name, v, 3 * M)
                                    : ascii_values(doc, arrays[k].name, v, 3 * M);
            assert_int_equal(n, arrays[k].count);
            for (size_t i = 0; i < n; ++i) {
                const float f = (float)arrays[k].values[i];
                uint32_t bits;
                memcpy(&bits, &f, sizeof(bits));
                assert_int_equal(v[i], bits);
            }
        }
        assert_int_equal(binary ? binary_values(doc, "id", v, M) : ascii_values(doc, "id", v, M),
                         M);
        assert_int_equal(v[M - 1], M - 1);
        free(doc);
        remove(path);
    }
    free(v);
    free(x);
    free(r);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    rmdir(dir);
}

/* The file's bytes and their count (the appended section holds NUL bytes). */
static unsigned char *slurp_bytes(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    *size = (size_t)ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *doc = malloc(*size + 1);
    assert_non_null(doc);
    assert_int_equal(fread(doc, 1, *size, fp), *size);
    doc[*size] = 0;
    fclose(fp);
    return doc;
}

static void test_appended_matches_inline(void **state)
{
    (void)state;
    char dir[] = "/tmp/sinter_vtu_XXXXXX";
    assert_non_null(mkdtemp(dir));
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_material_create(&mat, ctx, "copper"), SINTER_OK);
    assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(ps, 0, mat), SINTER_OK);
    enum { M = 1500 };
    double *x = malloc(3 * M * sizeof(double)), *r = malloc(M * sizeof(double));
    assert_true(x != NULL && r != NULL);
    for (size_t i = 0; i < M; ++i) {
        for (int d = 0; d < 3; ++d)
            x[3 * i + (size_t)d] = 0.01 * (double)((i * (size_t)(d + 5)) % 89) / 3.0;
        r[i] = 1e-4 * (1.0 + (double)(i % 7) / 9.0);
    }
    assert_int_equal(sinter_particles_add(ps, M, x, r, 0, 400.0, NULL), SINTER_OK);
    char inline_path[128], appended_path[128];
    snprintf(inline_path, sizeof(inline_path), "%s/i.vtu", dir);
    snprintf(appended_path, sizeof(appended_path), "%s/a.vtu", dir);
    assert_int_equal(sinter_write_vtu_as(ps, inline_path, NULL, 0, SINTER_VTK_BINARY), SINTER_OK);
    assert_int_equal(sinter_write_vtu_as(ps, appended_path, NULL, 0, SINTER_VTK_BINARY), SINTER_OK);
    assert_int_equal(sinter_vtk_make_appended(ctx, appended_path), SINTER_OK);
    char *in = slurp(inline_path);
    size_t size = 0;
    unsigned char *ap = slurp_bytes(appended_path, &size);
    const char *doc = (const char *)ap;
    const char *start = strstr(doc, "<AppendedData encoding=\"raw\">");
    assert_non_null(start);
    const unsigned char *raw = (const unsigned char *)strchr(start, '_') + 1;
    uint64_t *v = malloc(3 * M * sizeof(uint64_t));
    assert_non_null(v);
    size_t arrays = 0;
    for (size_t k = 0; k < sizeof(ARRAYS) / sizeof(ARRAYS[0]); ++k) {
        if (strcmp(ARRAYS[k], "contacts") == 0)
            continue; /* (no extra array here) */
        char key[96];
        snprintf(key, sizeof(key), " Name=\"%s\"", ARRAYS[k]);
        const char *tag = strstr(doc, key);
        assert_non_null(tag);
        const char *offset = strstr(tag, "offset=\"");
        if (!is_binary(in, ARRAYS[k])) { /* zeros: ascii in both */
            assert_true(offset == NULL || offset > strchr(tag, '>'));
            continue;
        }
        assert_true(offset != NULL && offset < strchr(tag, '>'));
        const size_t at = (size_t)strtoull(offset + 8, NULL, 10);
        const size_t n = binary_values(in, ARRAYS[k], v, 3 * M);
        char type[16];
        size_t length;
        (void)array_text(in, ARRAYS[k], type, &length);
        const size_t width = strcmp(type, "UInt8") == 0 ? 1 : strcmp(type, "Int32") == 0 ? 4 : 8;
        assert_int_equal(little_endian(raw + at, 8), n * width);
        for (size_t i = 0; i < n; ++i) {
            uint64_t got = little_endian(raw + at + 8 + width * i, width);
            if (width == 4) /* sign-extended as binary_values gives it */
                got = (uint64_t)(int64_t)(int32_t)(uint32_t)got;
            assert_int_equal(got, v[i]);
        }
        ++arrays;
    }
    assert_true(arrays >= 8);
    assert_memory_equal(ap + size - strlen("</VTKFile>\n"), "</VTKFile>\n", strlen("</VTKFile>\n"));
    /* a file without binary arrays is refused, and left as it was */
    assert_int_equal(sinter_write_vtu_as(ps, inline_path, NULL, 0, 0), SINTER_OK);
    assert_int_equal(sinter_vtk_make_appended(ctx, inline_path), SINTER_ERR_CORRUPT);
    free(v);
    free(in);
    free(ap);
    free(x);
    free(r);
    remove(inline_path);
    remove(appended_path);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_binary_frames_match_ascii),
        cmocka_unit_test(test_single_precision),
        cmocka_unit_test(test_appended_matches_inline),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
