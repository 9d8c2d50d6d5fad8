/*
 * Reading text files line by line, for the scene files and the particle files they name:
 * a directory given as a file, a line longer than the buffer and a NUL byte inside a line are
 * told apart, so that each gets its own message naming the file and line.
 */
#ifndef SINTER_IO_TEXT_FILE_H
#define SINTER_IO_TEXT_FILE_H

#include <stdio.h>

#include "core/core.h"

/*
 * Open `path`, a `what` ("scene file"), for reading. Errors, after `prefix` (such as
 * "a.scene:12: ", or ""): SINTER_ERR_IO "cannot open <what> 'path': reason" and
 * SINTER_ERR_INVALID "<what> 'path' is a directory, not a file".
 */
sinter_status sinter_text_open(sinter_ctx *ctx, const char *prefix, const char *what,
                               const char *path, FILE **out);

typedef enum sinter_line_result {
    SINTER_LINE_OK,       /* a line (without its newline) is in the buffer */
    SINTER_LINE_END,      /* end of file: no more lines */
    SINTER_LINE_TOO_LONG, /* longer than the buffer holds */
    SINTER_LINE_NUL,      /* holds a NUL byte */
    SINTER_LINE_ERROR     /* a read error (ferror): errno tells why */
} sinter_line_result;

/*
 * The next line of f into buf (size >= 2 bytes, NUL-terminated, without its '\n'). A line too
 * long or holding a NUL is not read to its end: the caller reports it and stops.
 */
sinter_line_result sinter_text_line(FILE *f, char *buf, size_t size);

#endif
