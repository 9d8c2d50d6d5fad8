/* Inline base64 arrays made raw appended data (io/vtk_appended.h). */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "io/series.h"
#include "io/vtk_appended.h"

static const char *const FN = "sinter_vtk_make_appended";

/* The value of a base64 character; -1 for '=' and anything else. */
static int sextet(char c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

/* Decode base64 text[0, n) (padded quads) into out; the bytes written, or -1 when damaged. */
static long decode(const char *text, size_t n, unsigned char *out)
{
    if (n % 4 != 0)
        return -1;
    size_t used = 0;
    for (size_t i = 0; i < n; i += 4) {
        int v[4], pad = 0;
        for (int k = 0; k < 4; ++k) {
            v[k] = sextet(text[i + (size_t)k]);
            if (v[k] < 0) {
                if (text[i + (size_t)k] != '=' || k < 2 || i + 4 != n)
                    return -1;
                v[k] = 0;
                ++pad;
            }
        }
        const uint32_t q =
            (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 | (uint32_t)v[2] << 6 | (uint32_t)v[3];
        out[used++] = (unsigned char)(q >> 16);
        if (pad < 2)
            out[used++] = (unsigned char)(q >> 8);
        if (pad < 1)
            out[used++] = (unsigned char)q;
    }
    return (long)used;
}

/* The file's bytes (NUL-terminated) into *text, their count into *size. */
static sinter_status slurp(sinter_ctx *ctx, const char *path, char **text, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    if (fp == NULL)
        return sinter_fail(ctx, SINTER_ERR_IO, "%s: cannot open '%s': %s", FN, path,
                           strerror(errno));
    size_t capacity = 1 << 16, n = 0;
    char *buf = sinter_alloc(ctx, capacity);
    while (buf != NULL) {
        n += fread(buf + n, 1, capacity - n - 1, fp);
        if (n < capacity - 1)
            break;
        char *grown = sinter_realloc_array(ctx, buf, 2 * capacity, 1);
        if (grown == NULL) {
            sinter_free(ctx, buf);
            buf = NULL;
            break;
        }
        buf = grown;
        capacity *= 2;
    }
    const int failed = ferror(fp);
    fclose(fp);
    if (buf == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory reading '%s'", FN, path);
    if (failed) {
        sinter_free(ctx, buf);
        return sinter_fail(ctx, SINTER_ERR_IO, "%s: cannot read '%s'", FN, path);
    }
    buf[n] = '\0';
    *text = buf;
    *size = n;
    return SINTER_OK;
}

static int is_space(char c)
{
    return c == ' ' || c == '\n' || c == '\r' || c == '\t';
}

/*
 * Write the file anew: the text up to each binary <DataArray ...>, the tag closed at once with
 * format="appended" and its offset, then after the dataset the raw bytes of every array.
 */
static sinter_status convert(sinter_ctx *ctx, const char *path, const char *text, size_t size,
                             unsigned char *raw)
{
    static const char binary[] = " format=\"binary\">";
    const char *end_tag = strstr(text, "</VTKFile>");
    if (end_tag == NULL || strstr(text, "header_type=\"UInt64\"") == NULL)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: '%s' is not a VTK XML file with binary arrays", FN, path);
    sinter_out_file out;
    sinter_status st = sinter_out_open(&out, ctx, FN, path);
    if (st != SINTER_OK)
        return st;
    size_t raw_size = 0; /* the appended bytes so far (decoded into raw, in place order) */
    const char *p = text;
    for (;;) {
        const char *tag = strstr(p, "<DataArray");
        const char *format = tag != NULL ? strstr(tag, binary) : NULL;
        const char *close = tag != NULL ? strchr(tag, '>') : NULL;
        if (tag == NULL || tag > end_tag || format == NULL || close == NULL) {
            fwrite(p, 1, (size_t)(end_tag - p), out.fp);
            break;
        }
        if (format + sizeof(binary) - 2 != close) { /* an ascii array: copy it whole */
            fwrite(p, 1, (size_t)(close + 1 - p), out.fp);
            p = close + 1;
            continue;
        }
        /* the element's text: the 12-character byte count, then the data's base64 */
        const char *body = close + 1, *stop = strstr(body, "</DataArray>");
        while (body < stop && is_space(*body))
            ++body;
        const char *last = stop;
        while (last > body && is_space(last[-1]))
            --last;
        unsigned char header[9];
        const long header_bytes = last - body >= 12 ? decode(body, 12, header) : -1;
        const long data_bytes =
            header_bytes == 8 ? decode(body + 12, (size_t)(last - body - 12), raw + raw_size + 8)
                              : -1;
        uint64_t count = 0;
        for (int k = 0; k < 8 && header_bytes == 8; ++k)
            count |= (uint64_t)header[k] << (8 * k);
        if (stop == NULL || data_bytes < 0 || (uint64_t)data_bytes != count) {
            st = sinter_fail(ctx, SINTER_ERR_CORRUPT, "%s: '%s' has a damaged binary array", FN,
                             path);
            break;
        }
        memcpy(raw + raw_size, header, 8);
        fwrite(p, 1, (size_t)(format - p), out.fp);
        fprintf(out.fp, " format=\"appended\" offset=\"%zu\"/>", raw_size);
        raw_size += 8 + (size_t)data_bytes;
        p = stop + strlen("</DataArray>");
    }
    if (st == SINTER_OK) {
        fputs("  <AppendedData encoding=\"raw\">\n   _", out.fp);
        fwrite(raw, 1, raw_size, out.fp);
        fputs("\n  </AppendedData>\n", out.fp);
        fwrite(end_tag, 1, (size_t)(text + size - end_tag), out.fp);
    }
    return sinter_out_close(&out, st);
}

sinter_status sinter_vtk_make_appended(sinter_ctx *ctx, const char *path)
{
    char *text = NULL;
    size_t size = 0;
    sinter_status st = slurp(ctx, path, &text, &size);
    if (st != SINTER_OK)
        return st;
    /* the raw bytes are at most 3/4 of the text */
    unsigned char *raw = sinter_alloc(ctx, size + 16);
    st = raw != NULL ? convert(ctx, path, text, size, raw)
                     : sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory", FN);
    sinter_free(ctx, raw);
    sinter_free(ctx, text);
    return st;
}
