#define _POSIX_C_SOURCE 200809L
/* Text files read line by line, with the errors told apart. */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "io/text_file.h"

sinter_status sinter_text_open(sinter_ctx *ctx, const char *prefix, const char *what,
                               const char *path, FILE **out)
{
    *out = NULL;
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return sinter_fail(ctx, SINTER_ERR_IO, "%scannot open %s '%s': %s", prefix, what, path,
                           strerror(errno));
    /* fopen opens a directory for reading on POSIX systems; its first read fails (EISDIR) */
    struct stat info;
    if (fstat(fileno(f), &info) == 0 && S_ISDIR(info.st_mode)) {
        fclose(f);
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s%s '%s' is a directory, not a file", prefix,
                           what, path);
    }
    *out = f;
    return SINTER_OK;
}

sinter_line_result sinter_text_line(FILE *f, char *buf, size_t size)
{
    size_t n = 0;
    int c;
    while ((c = getc(f)) != EOF && c != '\n') {
        if (c == '\0') {
            buf[n] = '\0';
            return SINTER_LINE_NUL;
        }
        if (n + 1 == size) {
            buf[n] = '\0';
            return SINTER_LINE_TOO_LONG;
        }
        buf[n++] = (char)c;
    }
    buf[n] = '\0';
    if (c == EOF && ferror(f))
        return SINTER_LINE_ERROR;
    if (c == EOF && n == 0)
        return SINTER_LINE_END;
    return SINTER_LINE_OK;
}

sinter_status sinter_text_each_line(sinter_ctx *ctx, FILE *f, const char *path, const char *what,
                                    char *buf, size_t size, sinter_text_line_fn fn, void *user)
{
    sinter_status st = SINTER_OK;
    int line = 0;
    while (st == SINTER_OK) {
        const sinter_line_result got = sinter_text_line(f, buf, size);
        if (got == SINTER_LINE_END)
            break;
        ++line;
        if (got == SINTER_LINE_OK)
            st = fn(user, line, buf);
        else if (got == SINTER_LINE_TOO_LONG) /* also ends an endless line (/dev/zero) */
            st = sinter_fail(ctx, SINTER_ERR_PARSE, "%s:%d: line longer than %zu characters", path,
                             line, size - 1);
        else if (got == SINTER_LINE_NUL)
            st = sinter_fail(ctx, SINTER_ERR_PARSE,
                             "%s:%d: a NUL byte inside the line (%s is text)", path, line, what);
        else
            st = sinter_fail(ctx, SINTER_ERR_IO, "%s:%d: error reading the file: %s", path, line,
                             strerror(errno));
    }
    return st;
}
