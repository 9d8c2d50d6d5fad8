/* STL files, ASCII and binary, into a triangle soup (mesh.h). Binary: an 80-byte header, a
 * little-endian uint32 facet count, then per facet 12 float32 (normal, three vertices) and a
 * 2-byte attribute; a file is binary when its size is 84 + 50 count, else ASCII when it starts
 * with "solid" (some binary headers start with "solid" too: the size decides first). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh.h"

void sinter_stl_free(sinter_ctx *ctx, sinter_stl *stl)
{
    sinter_free(ctx, stl->vertex);
    sinter_free(ctx, stl->normal);
    memset(stl, 0, sizeof(*stl));
}

static sinter_status read_all(sinter_ctx *ctx, const char *path, char **text, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return sinter_fail(ctx, SINTER_ERR_IO, "STL file '%s': cannot open: %s", path,
                           strerror(errno));
    size_t cap = 0, n = 0;
    char *buf = NULL;
    sinter_status st = SINTER_OK;
    for (;;) {
        if (n + 65536 + 1 > cap) {
            st = sinter_grow(ctx, (void **)&buf, &cap, n + 65536 + 1, 1);
            if (st != SINTER_OK)
                break;
        }
        const size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0) {
            if (ferror(f))
                st = sinter_fail(ctx, SINTER_ERR_IO, "STL file '%s': read error", path);
            break;
        }
    }
    fclose(f);
    if (st != SINTER_OK) {
        sinter_free(ctx, buf);
        return st;
    }
    buf[n] = '\0';
    *text = buf;
    *size = n;
    return SINTER_OK;
}

static sinter_status reserve(sinter_ctx *ctx, sinter_stl *stl, size_t count)
{
    stl->vertex = sinter_calloc(ctx, 9 * count + 9, sizeof(double));
    stl->normal = sinter_calloc(ctx, 3 * count + 3, sizeof(double));
    if (stl->vertex == NULL || stl->normal == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL: out of memory for %zu facets", count);
    return SINTER_OK;
}

static double f32_at(const unsigned char *b)
{
    const uint32_t u =
        (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, sizeof(f));
    return (double)f;
}

static sinter_status read_binary(sinter_ctx *ctx, const char *path, const unsigned char *b,
                                 size_t count, sinter_stl *stl)
{
    sinter_status st = reserve(ctx, stl, count);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < count; ++k) {
        const unsigned char *f = b + 84 + 50 * k;
        for (int d = 0; d < 3; ++d)
            stl->normal[3 * k + d] = f32_at(f + 4 * d);
        for (int d = 0; d < 9; ++d) {
            stl->vertex[9 * k + d] = f32_at(f + 12 + 4 * d);
            if (!isfinite(stl->vertex[9 * k + d]))
                return sinter_fail(ctx, SINTER_ERR_PARSE,
                                   "STL file '%s': facet %zu has a non-finite coordinate", path,
                                   k + 1);
        }
    }
    stl->count = count;
    return SINTER_OK;
}

/* The ASCII reader's cursor: the next whitespace-separated word and its line. */
typedef struct cursor {
    char *at;
    int line;
} cursor;

static char *word(cursor *c)
{
    while (*c->at == ' ' || *c->at == '\t' || *c->at == '\r' || *c->at == '\n') {
        if (*c->at == '\n')
            ++c->line;
        ++c->at;
    }
    if (*c->at == '\0')
        return NULL;
    char *w = c->at;
    while (*c->at != '\0' && *c->at != ' ' && *c->at != '\t' && *c->at != '\r' && *c->at != '\n')
        ++c->at;
    if (*c->at != '\0') {
        if (*c->at == '\n')
            ++c->line;
        *c->at++ = '\0';
    }
    return w;
}

static sinter_status expect(sinter_ctx *ctx, const char *path, cursor *c, const char *want)
{
    const char *w = word(c);
    if (w == NULL || strcmp(w, want) != 0)
        return sinter_fail(ctx, SINTER_ERR_PARSE, "STL file '%s':%d: expected '%s', got '%s'", path,
                           c->line, want, w ? w : "end of file");
    return SINTER_OK;
}

static sinter_status numbers(sinter_ctx *ctx, const char *path, cursor *c, double *out)
{
    for (int d = 0; d < 3; ++d) {
        const char *w = word(c);
        char *end = NULL;
        out[d] = w ? strtod(w, &end) : 0.0;
        if (w == NULL || *end != '\0' || !isfinite(out[d]))
            return sinter_fail(ctx, SINTER_ERR_PARSE,
                               "STL file '%s':%d: expected a finite number, got '%s'", path,
                               c->line, w ? w : "end of file");
    }
    return SINTER_OK;
}

static sinter_status read_ascii(sinter_ctx *ctx, const char *path, char *text, sinter_stl *stl)
{
    size_t facets = 0; /* an upper bound: the word "facet" counted */
    for (const char *s = strstr(text, "facet"); s != NULL; s = strstr(s + 5, "facet"))
        ++facets;
    sinter_status st = reserve(ctx, stl, facets);
    if (st != SINTER_OK)
        return st;
    cursor c = {text, 1};
    word(&c); /* "solid", then its name: the rest of its line (none if the word ended it) */
    while (c.line == 1 && c.at[0] != '\0' && c.at[0] != '\n')
        ++c.at;
    size_t k = 0;
    for (;;) {
        const char *w = word(&c);
        if (w != NULL && strcmp(w, "endsolid") == 0)
            break;
        if (w == NULL || strcmp(w, "facet") != 0)
            return sinter_fail(ctx, SINTER_ERR_PARSE,
                               "STL file '%s':%d: expected 'facet' or 'endsolid', got '%s'", path,
                               c.line, w ? w : "end of file");
        if (k >= facets)
            return sinter_fail(ctx, SINTER_ERR_PARSE, "STL file '%s':%d: too many facets", path,
                               c.line);
        if ((st = expect(ctx, path, &c, "normal")) != SINTER_OK ||
            (st = numbers(ctx, path, &c, stl->normal + 3 * k)) != SINTER_OK ||
            (st = expect(ctx, path, &c, "outer")) != SINTER_OK ||
            (st = expect(ctx, path, &c, "loop")) != SINTER_OK)
            return st;
        for (int v = 0; v < 3; ++v)
            if ((st = expect(ctx, path, &c, "vertex")) != SINTER_OK ||
                (st = numbers(ctx, path, &c, stl->vertex + 9 * k + 3 * v)) != SINTER_OK)
                return st;
        if ((st = expect(ctx, path, &c, "endloop")) != SINTER_OK ||
            (st = expect(ctx, path, &c, "endfacet")) != SINTER_OK)
            return st;
        ++k;
    }
    stl->count = k;
    return SINTER_OK;
}

sinter_status sinter_stl_read(sinter_ctx *ctx, const char *path, sinter_stl *stl)
{
    memset(stl, 0, sizeof(*stl));
    char *text = NULL;
    size_t size = 0;
    sinter_status st = read_all(ctx, path, &text, &size);
    if (st != SINTER_OK)
        return st;
    const unsigned char *b = (const unsigned char *)text;
    const size_t count =
        size >= 84
            ? ((size_t)b[80] | (size_t)b[81] << 8 | (size_t)b[82] << 16 | (size_t)b[83] << 24)
            : 0;
    if (size >= 84 && (size - 84) % 50 == 0 && (size - 84) / 50 == count)
        st = read_binary(ctx, path, b, count, stl);
    else if (size >= 5 && memcmp(text, "solid", 5) == 0)
        st = read_ascii(ctx, path, text, stl);
    else
        st = sinter_fail(ctx, SINTER_ERR_PARSE,
                         "STL file '%s': neither ASCII (starting with 'solid') nor binary (84 "
                         "bytes + 50 per facet; %zu bytes)",
                         path, size);
    sinter_free(ctx, text);
    if (st == SINTER_OK && stl->count == 0)
        st = sinter_fail(ctx, SINTER_ERR_PARSE, "STL file '%s' has no facets", path);
    if (st != SINTER_OK)
        sinter_stl_free(ctx, stl);
    return st;
}
