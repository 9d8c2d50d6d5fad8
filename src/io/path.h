/*
 * Paths built from parts, refused rather than cut: a path that does not fit its buffer (at most
 * SINTER_PATH_SIZE bytes, the system's PATH_MAX with its NUL) would name another file.
 */
#ifndef SINTER_IO_PATH_H
#define SINTER_IO_PATH_H

#include "core/core.h"

/* Bytes of a path buffer, its NUL included (Linux's PATH_MAX). */
#define SINTER_PATH_SIZE 4096

/*
 * printf `fmt` into buf (size bytes). SINTER_ERR_INVALID naming the path (its first 200
 * characters) when it would not fit; buf then holds "" rather than a cut path.
 */
sinter_status sinter_path_format(sinter_ctx *ctx, char *buf, size_t size, const char *fmt, ...)
    SINTER_PRINTF(4, 5);

/* "dir/name" into buf (size bytes), as sinter_path_format. */
sinter_status sinter_path_join(sinter_ctx *ctx, char *buf, size_t size, const char *dir,
                               const char *name);

#endif
