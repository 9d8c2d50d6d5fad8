/* Private layout of a time series and the file helpers shared by the writers of src/io/. */
#ifndef SINTER_IO_SERIES_H
#define SINTER_IO_SERIES_H

#include <stdio.h>

#include "core/core.h"

struct sinter_series {
    sinter_ctx *ctx;
    size_t columns;
    char **names;   /* columns strings */
    char **units;   /* columns strings ("" when none) */
    double *values; /* rows * columns values, row-major */
    size_t rows;
    size_t capacity; /* rows that fit in values */
};

/*
 * A file written to "<path>.tmp" and renamed onto `path` when complete, so a
 * failure never leaves a partial file at `path` nor clobbers an existing one.
 */
typedef struct sinter_out_file {
    sinter_ctx *ctx;
    const char *func; /* public function named in messages */
    const char *path; /* borrowed */
    char *tmp_path;   /* owned */
    FILE *fp;
} sinter_out_file;

/* Check `path` (NULL: SINTER_ERR_NULL, "": SINTER_ERR_INVALID) and create its temporary file. */
sinter_status sinter_out_open(sinter_out_file *out, sinter_ctx *ctx, const char *func,
                              const char *path);

/*
 * Finish the file: with status == SINTER_OK, flush, close and rename it onto
 * the final path; otherwise (or when any of that fails) close and remove the
 * temporary file. Returns the resulting status.
 */
sinter_status sinter_out_close(sinter_out_file *out, sinter_status status);

/* Write a double with full precision (%.17g); NaN as "nan", infinities as "inf"/"-inf". */
void sinter_out_double(FILE *fp, double value);

/*
 * Write the first `length` bytes of `text` escaped for XML text and attribute
 * values (& < > " '); tab, newline and carriage return become spaces and other
 * control characters '?', so the result is always well-formed.
 */
void sinter_out_xml_n(FILE *fp, const char *text, size_t length);
void sinter_out_xml(FILE *fp, const char *text);

/* The CSV header line ("name [unit],...") and one row, as sinter_series_write_csv writes them. */
void sinter_series_csv_header(FILE *fp, const sinter_series *s);
void sinter_series_csv_row(FILE *fp, const double *row, size_t columns);

/* Index + 1 of the first control character (bytes 0x01-0x1f, 0x7f) of `text`, 0 if none. */
size_t sinter_find_control_char(const char *text);

#endif
