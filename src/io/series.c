/* Time series of named, unit-carrying columns; CSV output; the safe-write helpers of src/io/. */
#include <errno.h>
#include <math.h>
#include <string.h>

#include "io/series.h"

/* ---- files written to "<path>.tmp" and renamed ---------------------------------------------- */

sinter_status sinter_out_open(sinter_out_file *out, sinter_ctx *ctx, const char *func,
                              const char *path)
{
    memset(out, 0, sizeof(*out));
    out->ctx = ctx;
    out->func = func;
    out->path = path;
    if (path == NULL)
        return sinter_fail(ctx, SINTER_ERR_NULL, "%s: argument 'path' is NULL", func);
    if (path[0] == '\0')
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: the path is empty", func);
    const size_t n = strlen(path);
    out->tmp_path = sinter_alloc(ctx, n + sizeof(".tmp"));
    if (out->tmp_path == NULL)
        return sinter_last_status(ctx);
    memcpy(out->tmp_path, path, n);
    memcpy(out->tmp_path + n, ".tmp", sizeof(".tmp"));
    out->fp = fopen(out->tmp_path, "wb");
    if (out->fp == NULL) {
        const int err = errno;
        sinter_status st = sinter_fail(ctx, SINTER_ERR_IO, "%s: cannot create '%s': %s", func,
                                       out->tmp_path, strerror(err));
        sinter_free(ctx, out->tmp_path);
        out->tmp_path = NULL;
        return st;
    }
    return SINTER_OK;
}

sinter_status sinter_out_close(sinter_out_file *out, sinter_status status)
{
    if (out->fp == NULL) {
        sinter_free(out->ctx, out->tmp_path);
        out->tmp_path = NULL;
        return status;
    }
    if (status == SINTER_OK) {
        int err = errno;
        int failed = ferror(out->fp);
        if (fflush(out->fp) != 0 && !failed) {
            err = errno;
            failed = 1;
        }
        if (fclose(out->fp) != 0 && !failed) {
            err = errno;
            failed = 1;
        }
        out->fp = NULL;
        if (failed)
            status = sinter_fail(out->ctx, SINTER_ERR_IO, "%s: writing '%s' failed: %s", out->func,
                                 out->tmp_path, err ? strerror(err) : "write error");
        else if (rename(out->tmp_path, out->path) != 0)
            status = sinter_fail(out->ctx, SINTER_ERR_IO, "%s: cannot rename '%s' to '%s': %s",
                                 out->func, out->tmp_path, out->path, strerror(errno));
    } else {
        fclose(out->fp);
        out->fp = NULL;
    }
    if (status != SINTER_OK)
        remove(out->tmp_path);
    sinter_free(out->ctx, out->tmp_path);
    out->tmp_path = NULL;
    return status;
}

void sinter_out_double(FILE *fp, double value)
{
    if (isnan(value))
        fputs("nan", fp);
    else if (isinf(value))
        fputs(value > 0.0 ? "inf" : "-inf", fp);
    else
        fprintf(fp, "%.17g", value);
}

void sinter_out_xml_n(FILE *fp, const char *text, size_t length)
{
    for (size_t i = 0; i < length; ++i) {
        const unsigned char c = (unsigned char)text[i];
        switch (c) {
        case '&':
            fputs("&amp;", fp);
            break;
        case '<':
            fputs("&lt;", fp);
            break;
        case '>':
            fputs("&gt;", fp);
            break;
        case '"':
            fputs("&quot;", fp);
            break;
        case '\'':
            fputs("&apos;", fp);
            break;
        case '\t':
        case '\n':
        case '\r':
            fputc(' ', fp);
            break;
        default:
            fputc(c < 0x20 ? '?' : c, fp);
        }
    }
}

void sinter_out_xml(FILE *fp, const char *text)
{
    sinter_out_xml_n(fp, text, strlen(text));
}

size_t sinter_find_control_char(const char *text)
{
    for (size_t i = 0; text[i] != '\0'; ++i)
        if ((unsigned char)text[i] < 0x20 || text[i] == 0x7f)
            return i + 1;
    return 0;
}

/* ---- series ------------------------------------------------------------------------------- */

void sinter_series_destroy(sinter_series *s)
{
    if (s == NULL)
        return;
    for (size_t k = 0; k < s->columns; ++k) {
        if (s->names != NULL)
            sinter_free(s->ctx, s->names[k]);
        if (s->units != NULL)
            sinter_free(s->ctx, s->units[k]);
    }
    sinter_free(s->ctx, s->names);
    sinter_free(s->ctx, s->units);
    sinter_free(s->ctx, s->values);
    sinter_free(s->ctx, s);
}

sinter_status sinter_series_create(sinter_series **out, sinter_ctx *ctx, size_t columns,
                                   const char *const *names, const char *const *units)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    if (columns == 0)
        return sinter_fail(
            ctx, SINTER_ERR_INVALID,
            "sinter_series_create: columns is 0; a series needs at least one column");
    SINTER_CHECK_NULL(ctx, names);
    for (size_t k = 0; k < columns; ++k) {
        if (names[k] == NULL)
            return sinter_fail(ctx, SINTER_ERR_NULL, "sinter_series_create: names[%zu] is NULL", k);
        if (names[k][0] == '\0')
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "sinter_series_create: names[%zu] is empty; every column needs "
                               "a name",
                               k);
    }
    sinter_series *s = sinter_calloc(ctx, 1, sizeof(*s));
    if (s == NULL)
        return sinter_last_status(ctx);
    s->ctx = ctx;
    s->names = sinter_calloc(ctx, columns, sizeof(char *));
    s->units = sinter_calloc(ctx, columns, sizeof(char *));
    if (s->names == NULL || s->units == NULL) {
        sinter_series_destroy(s);
        return sinter_last_status(ctx);
    }
    s->columns = columns;
    for (size_t k = 0; k < columns; ++k) {
        const char *unit = units != NULL && units[k] != NULL ? units[k] : "";
        s->names[k] = sinter_strdup(ctx, names[k]);
        s->units[k] = sinter_strdup(ctx, unit);
        if (s->names[k] == NULL || s->units[k] == NULL) {
            sinter_series_destroy(s);
            return sinter_last_status(ctx);
        }
    }
    *out = s;
    return SINTER_OK;
}

sinter_status sinter_series_append(sinter_series *s, const double *row)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(s->ctx, row);
    if (s->rows == s->capacity) {
        if (s->capacity > SIZE_MAX / 2)
            return sinter_fail(s->ctx, SINTER_ERR_OVERFLOW,
                               "sinter_series_append: %zu rows overflow", s->rows);
        const size_t cap = s->capacity == 0 ? 64 : 2 * s->capacity;
        if (sinter_mul_overflows(cap, s->columns))
            return sinter_fail(s->ctx, SINTER_ERR_OVERFLOW,
                               "sinter_series_append: %zu rows of %zu columns overflow", cap,
                               s->columns);
        double *p = sinter_realloc_array(s->ctx, s->values, cap * s->columns, sizeof(double));
        if (p == NULL)
            return sinter_last_status(s->ctx);
        s->values = p;
        s->capacity = cap;
    }
    memcpy(s->values + s->rows * s->columns, row, s->columns * sizeof(double));
    s->rows++;
    return SINTER_OK;
}

sinter_status sinter_series_rows(const sinter_series *s, size_t *rows)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(s->ctx, rows);
    *rows = s->rows;
    return SINTER_OK;
}

sinter_status sinter_series_get(const sinter_series *s, size_t row, size_t column, double *value)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(s->ctx, value);
    if (row >= s->rows)
        return sinter_fail(s->ctx, SINTER_ERR_RANGE,
                           "sinter_series_get: row %zu is out of range; the series has %zu rows",
                           row, s->rows);
    if (column >= s->columns)
        return sinter_fail(s->ctx, SINTER_ERR_RANGE,
                           "sinter_series_get: column %zu is out of range; the series has %zu "
                           "columns",
                           column, s->columns);
    *value = s->values[row * s->columns + column];
    return SINTER_OK;
}

/* ---- CSV ---------------------------------------------------------------------------------- */

static int csv_needs_quotes(const char *text)
{
    return strpbrk(text, ",\"\r\n") != NULL;
}

static void csv_write_quoted(FILE *fp, const char *text)
{
    for (; *text != '\0'; ++text) {
        if (*text == '"')
            fputc('"', fp);
        fputc(*text, fp);
    }
}

/* Header field "name [unit]" ("name" alone when the unit is empty), quoted when needed. */
static void csv_write_header_field(FILE *fp, const char *name, const char *unit)
{
    const int quote = csv_needs_quotes(name) || csv_needs_quotes(unit);
    if (quote)
        fputc('"', fp);
    csv_write_quoted(fp, name);
    if (unit[0] != '\0') {
        fputs(" [", fp);
        csv_write_quoted(fp, unit);
        fputc(']', fp);
    }
    if (quote)
        fputc('"', fp);
}

void sinter_series_csv_header(FILE *fp, const sinter_series *s)
{
    for (size_t c = 0; c < s->columns; ++c) {
        if (c > 0)
            fputc(',', fp);
        csv_write_header_field(fp, s->names[c], s->units[c]);
    }
    fputc('\n', fp);
}

void sinter_series_csv_row(FILE *fp, const double *row, size_t columns)
{
    for (size_t c = 0; c < columns; ++c) {
        if (c > 0)
            fputc(',', fp);
        sinter_out_double(fp, row[c]);
    }
    fputc('\n', fp);
}

sinter_status sinter_series_write_csv(const sinter_series *s, const char *path)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    sinter_out_file out;
    sinter_status st = sinter_out_open(&out, s->ctx, "sinter_series_write_csv", path);
    if (st != SINTER_OK)
        return st;
    sinter_series_csv_header(out.fp, s);
    for (size_t r = 0; r < s->rows; ++r)
        sinter_series_csv_row(out.fp, s->values + r * s->columns, s->columns);
    return sinter_out_close(&out, SINTER_OK);
}
