#define _POSIX_C_SOURCE 200809L
/* series.csv written as the run goes: see csv_stream.h. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/csv_stream.h"

static sinter_status io_error(sinter_csv_stream *cs, const char *what)
{
    return sinter_fail(cs->ctx, SINTER_ERR_IO, "cannot %s '%s': %s", what, cs->path,
                       strerror(errno));
}

/* The header line as sinter_series_csv_header writes it (owned by the caller). */
static char *header_text(sinter_ctx *ctx, const sinter_series *header, size_t *length)
{
    char *text = NULL;
    size_t size = 0;
    FILE *mem = open_memstream(&text, &size);
    if (mem == NULL) {
        sinter_fail(ctx, SINTER_ERR_NOMEM, "cannot format the series header");
        return NULL;
    }
    sinter_series_csv_header(mem, header);
    if (fclose(mem) != 0) {
        free(text);
        sinter_fail(ctx, SINTER_ERR_NOMEM, "cannot format the series header");
        return NULL;
    }
    *length = size;
    return text;
}

/*
 * The byte offset just after the header and keep_rows complete rows of `fp` when its header
 * is `header` (length bytes), or -1.
 */
static long kept_prefix(FILE *fp, const char *header, size_t length, uint64_t keep_rows)
{
    for (size_t k = 0; k < length; ++k)
        if (fgetc(fp) != (unsigned char)header[k])
            return -1;
    uint64_t rows = 0;
    int c;
    while (rows < keep_rows && (c = fgetc(fp)) != EOF)
        if (c == '\n')
            ++rows;
    return rows == keep_rows ? ftell(fp) : -1;
}

sinter_status sinter_csv_stream_open(sinter_csv_stream *cs, sinter_ctx *ctx, const char *path,
                                     const sinter_series *header, uint64_t keep_rows, int *kept)
{
    memset(cs, 0, sizeof(*cs));
    cs->ctx = ctx;
    cs->path = path;
    cs->columns = header->columns;
    *kept = 0;
    if (keep_rows > 0) {
        FILE *fp = fopen(path, "r+b");
        if (fp != NULL) {
            size_t length = 0;
            char *text = header_text(ctx, header, &length);
            if (text == NULL) {
                fclose(fp);
                return sinter_last_status(ctx);
            }
            const long end = kept_prefix(fp, text, length, keep_rows);
            free(text);
            if (end >= 0 && ftruncate(fileno(fp), (off_t)end) == 0 && fseek(fp, 0, SEEK_END) == 0) {
                cs->fp = fp;
                *kept = 1;
                return SINTER_OK;
            }
            fclose(fp);
        }
    }
    cs->fp = fopen(path, "wb");
    if (cs->fp == NULL)
        return io_error(cs, "write the series");
    sinter_series_csv_header(cs->fp, header);
    if (fflush(cs->fp) != 0)
        return io_error(cs, "write the series");
    return SINTER_OK;
}

sinter_status sinter_csv_stream_append(sinter_csv_stream *cs, const double *row)
{
    sinter_series_csv_row(cs->fp, row, cs->columns);
    if (fflush(cs->fp) != 0 || ferror(cs->fp))
        return io_error(cs, "append to the series");
    return SINTER_OK;
}

sinter_status sinter_csv_stream_sync(sinter_csv_stream *cs)
{
    if (fflush(cs->fp) != 0 || fsync(fileno(cs->fp)) != 0)
        return io_error(cs, "write the series");
    return SINTER_OK;
}

sinter_status sinter_csv_stream_close(sinter_csv_stream *cs)
{
    if (cs->fp == NULL)
        return SINTER_OK;
    const int failed = ferror(cs->fp) != 0;
    const int closed = fclose(cs->fp) == 0;
    cs->fp = NULL;
    if (failed || !closed)
        return io_error(cs, "write the series");
    return SINTER_OK;
}
