#define _POSIX_C_SOURCE 200809L
/*
 * sinter_series_read_csv: a series back from the CSV that sinter_series_write_csv or a run
 * (io/csv_stream.c) wrote, so that a plot can be drawn from the file of any run, finished or
 * not. A last line without its newline (a run killed while writing it) is left out.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "io/series.h"

typedef struct csv_file {
    sinter_ctx *ctx;
    const char *path;
    char *text; /* the whole file, NUL-terminated */
    size_t size;
} csv_file;

static sinter_status parse_error(const csv_file *f, size_t line, const char *what)
{
    return sinter_fail(f->ctx, SINTER_ERR_PARSE, "%s:%zu: %s", f->path, line, what);
}

static sinter_status slurp(csv_file *f)
{
    FILE *fp = fopen(f->path, "rb");
    if (fp == NULL)
        return sinter_fail(f->ctx, SINTER_ERR_IO, "cannot open '%s': %s", f->path, strerror(errno));
    sinter_status st = SINTER_OK;
    size_t capacity = 0;
    char chunk[65536];
    size_t got;
    while (st == SINTER_OK && (got = fread(chunk, 1, sizeof(chunk), fp)) > 0) {
        st = sinter_grow(f->ctx, (void **)&f->text, &capacity, f->size + got + 1, 1);
        if (st == SINTER_OK) {
            memcpy(f->text + f->size, chunk, got);
            f->size += got;
        }
    }
    if (st == SINTER_OK && ferror(fp))
        st = sinter_fail(f->ctx, SINTER_ERR_IO, "cannot read '%s': %s", f->path, strerror(errno));
    fclose(fp);
    if (st == SINTER_OK && f->size == 0)
        st = sinter_fail(f->ctx, SINTER_ERR_PARSE, "%s: the file is empty", f->path);
    if (st == SINTER_OK && memchr(f->text, '\0', f->size) != NULL)
        st = sinter_fail(f->ctx, SINTER_ERR_PARSE, "%s: the file holds a NUL byte", f->path);
    if (st == SINTER_OK)
        f->text[f->size] = '\0';
    return st;
}

/* One header field, unquoted, at *p (moved past it and its comma): written into out. */
static const char *header_field(const char *p, char *out, size_t size, int *bad)
{
    size_t n = 0;
    const int quoted = *p == '"';
    if (quoted)
        ++p;
    for (; *p != '\0' && *p != '\n'; ++p) {
        if (quoted && *p == '"') {
            if (p[1] != '"') {
                ++p;
                break;
            }
            ++p; /* "" is one quote */
        } else if (!quoted && *p == ',') {
            break;
        }
        if (n + 1 < size)
            out[n++] = *p;
    }
    out[n] = '\0';
    if (*p == ',')
        ++p;
    else if (*p != '\n' && *p != '\0')
        *bad = 1;
    return p;
}

/* "name [unit]" into name and unit ("" when there is none). */
static void split_unit(char *field, const char **name, const char **unit)
{
    *name = field;
    *unit = "";
    const size_t n = strlen(field);
    char *open = strrchr(field, '[');
    if (n > 0 && field[n - 1] == ']' && open != NULL && open > field && open[-1] == ' ') {
        open[-1] = '\0';
        field[n - 1] = '\0';
        *unit = open + 1;
    }
}

static sinter_status read_header(csv_file *f, const char **cursor, sinter_series **out)
{
    const char *p = f->text;
    size_t columns = 1;
    for (const char *q = p; *q != '\n' && *q != '\0'; ++q)
        columns += *q == ',';
    if (strchr(p, '\n') == NULL)
        return parse_error(f, 1, "the header line is not complete");
    char **fields = sinter_calloc(f->ctx, columns, sizeof(char *));
    const char **names = sinter_calloc(f->ctx, columns, sizeof(char *));
    const char **units = sinter_calloc(f->ctx, columns, sizeof(char *));
    sinter_status st = fields && names && units ? SINTER_OK : sinter_last_status(f->ctx);
    size_t found = 0;
    int bad = 0;
    while (st == SINTER_OK && *p != '\n' && found < columns) {
        fields[found] = sinter_alloc(f->ctx, 256);
        if (fields[found] == NULL) {
            st = sinter_last_status(f->ctx);
            break;
        }
        p = header_field(p, fields[found], 256, &bad);
        split_unit(fields[found], &names[found], &units[found]);
        ++found;
    }
    if (st == SINTER_OK && (bad || *p != '\n'))
        st = parse_error(f, 1, "the header line is not a list of \"name [unit]\" fields");
    if (st == SINTER_OK)
        st = sinter_series_create(out, f->ctx, found, names, units);
    for (size_t k = 0; fields != NULL && k < columns; ++k)
        sinter_free(f->ctx, fields[k]);
    sinter_free(f->ctx, fields);
    sinter_free(f->ctx, names);
    sinter_free(f->ctx, units);
    *cursor = p + 1;
    return st;
}

static sinter_status read_rows(csv_file *f, const char *p, sinter_series *s)
{
    double *row = sinter_calloc(f->ctx, s->columns, sizeof(double));
    if (row == NULL)
        return sinter_last_status(f->ctx);
    sinter_status st = SINTER_OK;
    for (size_t line = 2; st == SINTER_OK && *p != '\0'; ++line) {
        const char *end = strchr(p, '\n');
        if (end == NULL)
            break; /* the last line was being written when the run stopped */
        size_t k = 0;
        const char *q = p;
        for (; k < s->columns && q < end; ++k) {
            if (*q == ',' || *q == '\n' || *q == ' ')
                break; /* an empty field (strtod would skip the blanks to the next line) */
            char *after = NULL;
            row[k] = strtod(q, &after);
            if (after == q || (after != end && *after != ','))
                break;
            q = after == end ? end : after + 1;
        }
        if (k != s->columns || q != end) {
            char what[96];
            snprintf(what, sizeof(what), "expected %zu numbers separated by commas", s->columns);
            st = parse_error(f, line, what);
        } else {
            st = sinter_series_append(s, row);
        }
        p = end + 1;
    }
    sinter_free(f->ctx, row);
    return st;
}

sinter_status sinter_series_read_csv(sinter_series **out, sinter_ctx *ctx, const char *path)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, path);
    csv_file f = {ctx, path, NULL, 0};
    sinter_series *s = NULL;
    const char *rows = NULL;
    sinter_status st = slurp(&f);
    if (st == SINTER_OK)
        st = read_header(&f, &rows, &s);
    if (st == SINTER_OK)
        st = read_rows(&f, rows, s);
    sinter_free(ctx, f.text);
    if (st != SINTER_OK) {
        sinter_series_destroy(s);
        return st;
    }
    *out = s;
    return SINTER_OK;
}
