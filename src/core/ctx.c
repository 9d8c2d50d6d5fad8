/* The context: allocator hook, last error, log callback, thread count. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"

static void *default_alloc(size_t size, void *user)
{
    (void)user;
    return malloc(size);
}

static void *default_realloc(void *ptr, size_t size, void *user)
{
    (void)user;
    return realloc(ptr, size);
}

static void default_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

sinter_status sinter_ctx_create(sinter_ctx **out, const sinter_allocator *allocator)
{
    if (out == NULL)
        return SINTER_ERR_NULL;
    sinter_allocator a = {sizeof(sinter_allocator), default_alloc, default_realloc, default_free,
                          NULL};
    if (allocator != NULL) {
        if (allocator->struct_size != sizeof(sinter_allocator))
            return SINTER_ERR_STRUCT_SIZE;
        if (allocator->alloc == NULL || allocator->realloc == NULL || allocator->free == NULL)
            return SINTER_ERR_INVALID;
        a = *allocator;
    }
    sinter_ctx *ctx = a.alloc(sizeof(*ctx), a.user);
    if (ctx == NULL)
        return SINTER_ERR_NOMEM;
    memset(ctx, 0, sizeof(*ctx));
    ctx->allocator = a;
    ctx->last_status = SINTER_OK;
    ctx->threads = 1;
    atomic_init(&ctx->stop_requested, 0);
    ctx->log_level = SINTER_LOG_WARNING;
    *out = ctx;
    return SINTER_OK;
}

void sinter_ctx_destroy(sinter_ctx *ctx)
{
    if (ctx == NULL)
        return;
    sinter_allocator a = ctx->allocator;
    a.free(ctx, a.user);
}

const char *sinter_last_error(const sinter_ctx *ctx)
{
    if (ctx == NULL)
        return "no context (NULL sinter_ctx)";
    return ctx->last_error;
}

sinter_status sinter_last_status(const sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    return ctx->last_status;
}

sinter_status sinter_clear_error(sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    ctx->last_status = SINTER_OK;
    ctx->last_error[0] = '\0';
    return SINTER_OK;
}

sinter_status sinter_ctx_set_log(sinter_ctx *ctx, sinter_log_fn fn, int max_level, void *user)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    if (max_level < SINTER_LOG_ERROR || max_level > SINTER_LOG_DEBUG)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_ctx_set_log: log level %d is outside [%d, %d]", max_level,
                           SINTER_LOG_ERROR, SINTER_LOG_DEBUG);
    ctx->log_fn = fn;
    ctx->log_user = user;
    ctx->log_level = max_level;
    return SINTER_OK;
}

sinter_status sinter_ctx_set_threads(sinter_ctx *ctx, int threads)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    if (threads < 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_ctx_set_threads: thread count %d is negative", threads);
    ctx->threads = threads;
    return SINTER_OK;
}

sinter_status sinter_ctx_get_threads(const sinter_ctx *ctx, int *threads)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    /* the error record is bookkeeping on a logically const context */
    SINTER_CHECK_NULL((sinter_ctx *)ctx, threads);
    *threads = ctx->threads;
    return SINTER_OK;
}

sinter_status sinter_ctx_request_stop(sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    atomic_store(&ctx->stop_requested, 1); /* async-signal-safe: a lock-free store, no error record */
    return SINTER_OK;
}

sinter_status sinter_ctx_take_stop(sinter_ctx *ctx, const char *where, double time)
{
    if (atomic_load_explicit(&ctx->stop_requested, memory_order_relaxed) == 0 ||
        atomic_exchange(&ctx->stop_requested, 0) == 0)
        return SINTER_OK;
    return sinter_fail(ctx, SINTER_ERR_INTERRUPTED,
                       "%s: stopped on request at t = %.17g s (the last accepted state)", where,
                       time);
}

sinter_status sinter_fail(sinter_ctx *ctx, sinter_status status, const char *fmt, ...)
{
    if (ctx == NULL)
        return status;
    va_list args;
    va_start(args, fmt);
    vsnprintf(ctx->last_error, sizeof(ctx->last_error), fmt, args);
    va_end(args);
    ctx->last_status = status;
    if (ctx->log_fn != NULL && ctx->log_level >= SINTER_LOG_DEBUG)
        ctx->log_fn(SINTER_LOG_DEBUG, ctx->last_error, ctx->log_user);
    return status;
}

void sinter_log(sinter_ctx *ctx, int level, const char *fmt, ...)
{
    if (ctx == NULL || ctx->log_fn == NULL || level > ctx->log_level)
        return;
    char text[SINTER_ERROR_TEXT_SIZE];
    va_list args;
    va_start(args, fmt);
    vsnprintf(text, sizeof(text), fmt, args);
    va_end(args);
    ctx->log_fn(level, text, ctx->log_user);
}

void *sinter_alloc(sinter_ctx *ctx, size_t size)
{
    if (size == 0)
        size = 1;
    void *p = ctx->allocator.alloc(size, ctx->allocator.user);
    if (p == NULL)
        sinter_fail(ctx, SINTER_ERR_NOMEM, "out of memory allocating %zu bytes", size);
    return p;
}

void *sinter_calloc(sinter_ctx *ctx, size_t count, size_t size)
{
    if (sinter_mul_overflows(count, size)) {
        sinter_fail(ctx, SINTER_ERR_OVERFLOW, "allocation of %zu x %zu bytes overflows", count,
                    size);
        return NULL;
    }
    void *p = sinter_alloc(ctx, count * size);
    if (p != NULL)
        memset(p, 0, count * size > 0 ? count * size : 1);
    return p;
}

void *sinter_realloc_array(sinter_ctx *ctx, void *ptr, size_t count, size_t size)
{
    if (sinter_mul_overflows(count, size)) {
        sinter_fail(ctx, SINTER_ERR_OVERFLOW, "allocation of %zu x %zu bytes overflows", count,
                    size);
        return NULL;
    }
    size_t bytes = count * size > 0 ? count * size : 1;
    void *p = ctx->allocator.realloc(ptr, bytes, ctx->allocator.user);
    if (p == NULL)
        sinter_fail(ctx, SINTER_ERR_NOMEM, "out of memory allocating %zu bytes", bytes);
    return p;
}

void sinter_free(sinter_ctx *ctx, void *ptr)
{
    if (ptr != NULL)
        ctx->allocator.free(ptr, ctx->allocator.user);
}

static atomic_uint_fast64_t last_unique_id;

uint64_t sinter_unique_id(void)
{
    return (uint64_t)atomic_fetch_add(&last_unique_id, 1) + 1;
}

sinter_status sinter_grow(sinter_ctx *ctx, void **ptr, size_t *capacity, size_t need, size_t elem)
{
    if (*ptr != NULL && need <= *capacity)
        return SINTER_OK;
    size_t cap = *capacity > 0 ? *capacity : 64;
    while (cap < need)
        cap = cap > SIZE_MAX / 2 ? need : 2 * cap;
    void *grown = sinter_realloc_array(ctx, *ptr, cap, elem);
    if (grown == NULL)
        return sinter_last_status(ctx);
    *ptr = grown;
    *capacity = cap;
    return SINTER_OK;
}

char *sinter_strdup(sinter_ctx *ctx, const char *text)
{
    size_t n = strlen(text) + 1;
    char *copy = sinter_alloc(ctx, n);
    if (copy != NULL)
        memcpy(copy, text, n);
    return copy;
}
