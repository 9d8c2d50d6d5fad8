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

/* What sinter_text_each_line calls for each line: its number (from 1) and text (writable). */
typedef sinter_status (*sinter_text_line_fn)(void *user, int line, char *text);

/*
 * Read f line by line into buf (size >= 2 bytes), calling fn for each line until it returns an
 * error or the file ends. A line too long, a NUL byte inside a line and a read error end the
 * loop as SINTER_ERR_PARSE or SINTER_ERR_IO "path:line: ..." (`what`, such as "a particle
 * file", names the kind of file in the NUL message). Does not close f.
 */
sinter_status sinter_text_each_line(sinter_ctx *ctx, FILE *f, const char *path, const char *what,
                                    char *buf, size_t size, sinter_text_line_fn fn, void *user);

#endif
