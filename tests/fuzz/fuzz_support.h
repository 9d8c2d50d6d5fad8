/*
 * Shared helpers of the libFuzzer harnesses (tests/fuzz/run.sh builds them).
 *
 * A fuzzed scene may legitimately ask for a billion particles; the library
 * must then fail cleanly with SINTER_ERR_NOMEM. The harnesses give every
 * context a budgeted allocator (FUZZ_MAX_ALLOCATION per block, FUZZ_MAX_LIVE
 * in total) so that such inputs end in NOMEM instead of in libFuzzer's
 * malloc limit, and count live blocks so that a leak through the context's
 * allocator is caught even when LeakSanitizer is off.
 */
#ifndef SINTER_FUZZ_SUPPORT_H
#define SINTER_FUZZ_SUPPORT_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter.h>

#define FUZZ_MAX_ALLOCATION ((size_t)16 << 20)
#define FUZZ_MAX_LIVE ((size_t)128 << 20)

typedef struct fuzz_budget {
    size_t live_bytes;
    long live_blocks;
} fuzz_budget;

/* Each block carries its size in a 16-byte header (keeps malloc's alignment). */
#define FUZZ_HEADER 16

static void *fuzz_alloc(size_t size, void *user)
{
    fuzz_budget *b = user;
    if (size > FUZZ_MAX_ALLOCATION || size > FUZZ_MAX_LIVE - b->live_bytes)
        return NULL;
    unsigned char *p = malloc(size + FUZZ_HEADER);
    if (p == NULL)
        return NULL;
    memcpy(p, &size, sizeof(size));
    b->live_bytes += size;
    b->live_blocks++;
    return p + FUZZ_HEADER;
}

static void fuzz_free(void *ptr, void *user)
{
    fuzz_budget *b = user;
    if (ptr == NULL)
        return;
    unsigned char *p = (unsigned char *)ptr - FUZZ_HEADER;
    size_t size;
    memcpy(&size, p, sizeof(size));
    b->live_bytes -= size;
    b->live_blocks--;
    free(p);
}

static void *fuzz_realloc(void *ptr, size_t size, void *user)
{
    fuzz_budget *b = user;
    if (ptr == NULL)
        return fuzz_alloc(size, user);
    unsigned char *p = (unsigned char *)ptr - FUZZ_HEADER;
    size_t old;
    memcpy(&old, p, sizeof(old));
    if (size > FUZZ_MAX_ALLOCATION || size > FUZZ_MAX_LIVE - (b->live_bytes - old))
        return NULL;
    unsigned char *q = realloc(p, size + FUZZ_HEADER);
    if (q == NULL)
        return NULL;
    memcpy(q, &size, sizeof(size));
    b->live_bytes = b->live_bytes - old + size;
    return q + FUZZ_HEADER;
}

/* A context on a fresh budget; aborts (a fuzzer finding) if that fails. */
static sinter_ctx *fuzz_ctx(fuzz_budget *budget)
{
    memset(budget, 0, sizeof(*budget));
    const sinter_allocator a = {sizeof(sinter_allocator), fuzz_alloc, fuzz_realloc, fuzz_free,
                                budget};
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, &a) != SINTER_OK)
        abort();
    return ctx;
}

/* Destroy the context and abort if any block allocated through it is still live. */
static void fuzz_ctx_done(sinter_ctx *ctx, fuzz_budget *budget)
{
    sinter_ctx_destroy(ctx);
    if (budget->live_blocks != 0 || budget->live_bytes != 0) {
        fprintf(stderr, "fuzz: %ld block(s), %zu byte(s) leaked through the context allocator\n",
                budget->live_blocks, budget->live_bytes);
        abort();
    }
}

/* A failing call returns a known status and leaves a message on the (fresh) context. */
static void fuzz_check_error(sinter_ctx *ctx, sinter_status st, const char *call)
{
    if (st == SINTER_OK)
        return;
    if (strcmp(sinter_status_name(st), "SINTER_STATUS_UNKNOWN") == 0) {
        fprintf(stderr, "fuzz: %s returned the unknown status %d\n", call, (int)st);
        abort();
    }
    if (sinter_last_error(ctx)[0] == '\0') {
        fprintf(stderr, "fuzz: %s failed with %s but left no message\n", call,
                sinter_status_name(st));
        abort();
    }
}

/* Write `size` bytes to `path` (abort on failure: the harness itself is broken). */
static void fuzz_write_file(const char *path, const uint8_t *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL || (size > 0 && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror(path);
        abort();
    }
}

static char fuzz_dir_path[64];

static void fuzz_dir_remove(void)
{
    char cmd[128];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", fuzz_dir_path);
    if (system(cmd) != 0)
        fprintf(stderr, "fuzz: could not remove %s\n", fuzz_dir_path);
}

/* A private directory for the harness's files, created once, removed at exit. */
static const char *fuzz_dir(void)
{
    if (fuzz_dir_path[0] == '\0') {
        snprintf(fuzz_dir_path, sizeof(fuzz_dir_path), "/tmp/sinter_fuzz_XXXXXX");
        if (mkdtemp(fuzz_dir_path) == NULL) {
            perror("mkdtemp");
            abort();
        }
        atexit(fuzz_dir_remove);
    }
    return fuzz_dir_path;
}

#endif
