/* Paths built from parts: refused when they do not fit, never silently cut. */
#include <stdarg.h>
#include <stdio.h>

#include "io/path.h"

sinter_status sinter_path_format(sinter_ctx *ctx, char *buf, size_t size, const char *fmt, ...)
{
    if (size == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "no room for a path from '%.200s'", fmt);
    va_list args;
    va_start(args, fmt);
    const int n = vsnprintf(buf, size, fmt, args);
    va_end(args);
    if (n >= 0 && (size_t)n < size)
        return SINTER_OK;
    if (n < 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "cannot format a path from '%.200s'", fmt);
    const sinter_status st = sinter_fail(
        ctx, SINTER_ERR_INVALID,
        "the path '%.200s...' is %d bytes long; the system allows at most %zu", buf, n, size - 1);
    buf[0] = '\0';
    return st;
}

sinter_status sinter_path_join(sinter_ctx *ctx, char *buf, size_t size, const char *dir,
                               const char *name)
{
    return sinter_path_format(ctx, buf, size, "%s/%s", dir, name);
}
