/* Private core of libsinter: context, errors, allocation, logging. */
#ifndef SINTER_CORE_H
#define SINTER_CORE_H

#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "sinter.h"

#define SINTER_ERROR_TEXT_SIZE 512

struct sinter_ctx {
    sinter_allocator allocator;
    sinter_status last_status;
    char last_error[SINTER_ERROR_TEXT_SIZE];
    sinter_log_fn log_fn;
    void *log_user;
    int log_level;
    int threads;
    int step_threads; /* > 0: the threads of the step being taken (stepper/thread_choice.h) */
    atomic_int stop_requested; /* sinter_ctx_request_stop: set by a signal handler or a thread */
};

/* SINTER_ERR_INTERRUPTED (and the request withdrawn) if a stop was requested, else SINTER_OK;
 * `where` names the run in the message ("sinter_stepper_advance"), `time` its time [s]. */
sinter_status sinter_ctx_take_stop(sinter_ctx *ctx, const char *where, double time);

#if defined(__GNUC__)
#define SINTER_PRINTF(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define SINTER_PRINTF(fmt_index, first_arg)
#endif

/* Record an error on ctx (which may be NULL) and return `status`. */
sinter_status sinter_fail(sinter_ctx *ctx, sinter_status status, const char *fmt, ...)
    SINTER_PRINTF(3, 4);

/* Log a message if the context has a callback at that level. */
void sinter_log(sinter_ctx *ctx, int level, const char *fmt, ...) SINTER_PRINTF(3, 4);

/* Allocation through the context's allocator. Sizes are checked for overflow. */
void *sinter_alloc(sinter_ctx *ctx, size_t size);
void *sinter_calloc(sinter_ctx *ctx, size_t count, size_t size);
void *sinter_realloc_array(sinter_ctx *ctx, void *ptr, size_t count, size_t size);
void sinter_free(sinter_ctx *ctx, void *ptr);

/* Grow *ptr (an array of `elem`-byte items with *capacity items) to hold at least `need`
 * items, doubling; *ptr and *capacity change only on success. */
sinter_status sinter_grow(sinter_ctx *ctx, void **ptr, size_t *capacity, size_t need, size_t elem);

/* A number no earlier call in this process returned, never 0 (thread-safe): versions of the
 * internal lists (a pair list's build, a contact list's membership) are told apart by it. */
uint64_t sinter_unique_id(void);

/* Index of `key` in a NULL-terminated list of at most `max` keys, or -1. */
int sinter_find_key(const char *const *keys, int max, const char *key);

/* SINTER_ERR_NOT_FOUND: "<what> '<name>' has no parameter '<key>' (known: <keys>)", the
 * keys from a NULL-terminated list of at most `max`. */
sinter_status sinter_unknown_key(sinter_ctx *ctx, const char *what, const char *name,
                                 const char *key, const char *const *keys, int max);

/* The names name_at(0) .. name_at(count - 1) joined with ", " into buf (cut to fit). */
void sinter_join_names(char *buf, size_t size, size_t count, const char *(*name_at)(size_t k));

/* New copies of the n points of a table (t[k], v[k]) in *t_out and *v_out (the caller frees
 * both). Errors: SINTER_ERR_NOMEM (nothing allocated then). */
sinter_status sinter_copy_table(sinter_ctx *ctx, size_t n, const double *t, const double *v,
                                double **t_out, double **v_out);

/* Piecewise-linear interpolation through (t[k], v[k]), k < n, held constant outside. */
double sinter_interpolate(size_t n, const double *t, const double *v, double x);
char *sinter_strdup(sinter_ctx *ctx, const char *text);

/* 1 if count * size overflows size_t. */
static inline int sinter_mul_overflows(size_t count, size_t size)
{
    return size != 0 && count > SIZE_MAX / size;
}

/* Argument checks that record a named error and return from the caller. */
#define SINTER_CHECK_NULL(ctx, ptr)                                                                \
    do {                                                                                           \
        if ((ptr) == NULL)                                                                         \
            return sinter_fail((ctx), SINTER_ERR_NULL, "%s: argument '%s' is NULL", __func__,      \
                               #ptr);                                                              \
    } while (0)

#endif /* SINTER_CORE_H */
