/*
 * series.csv written as the run goes (io/scene_run.c): the header when the file is made, then
 * each sample appended and flushed, so that a crash or a kill loses at most the sample being
 * written; fsync at checkpoints. A restart keeps the rows the checkpoint's run had written and
 * drops the later ones, so that the file continues as the straight run's would.
 */
#ifndef SINTER_IO_CSV_STREAM_H
#define SINTER_IO_CSV_STREAM_H

#include <stdint.h>
#include <stdio.h>

#include "io/series.h"

typedef struct sinter_csv_stream {
    sinter_ctx *ctx;
    const char *path; /* borrowed */
    size_t columns;
    FILE *fp;
} sinter_csv_stream;

/*
 * Open `path` for the columns of `header` (its rows are not written). keep_rows == 0: a new
 * file with the header line. keep_rows > 0 (a restart): an existing file with the same header
 * and at least keep_rows complete rows keeps those rows and loses the rest; any other file is
 * started again with the header (*kept says which: 1 kept, 0 started again).
 * Errors: SINTER_ERR_IO naming the path.
 */
sinter_status sinter_csv_stream_open(sinter_csv_stream *cs, sinter_ctx *ctx, const char *path,
                                     const sinter_series *header, uint64_t keep_rows, int *kept);

/* Append one row and flush it to the system. Errors: SINTER_ERR_IO. */
sinter_status sinter_csv_stream_append(sinter_csv_stream *cs, const double *row);

/* Flush to the disk itself (fsync): at checkpoints. Errors: SINTER_ERR_IO. */
sinter_status sinter_csv_stream_sync(sinter_csv_stream *cs);

/* Close (no-op when not open). Errors: SINTER_ERR_IO if the last writes failed. */
sinter_status sinter_csv_stream_close(sinter_csv_stream *cs);

#endif
