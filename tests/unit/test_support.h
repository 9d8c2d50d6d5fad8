/* Shared helpers of the cmocka tests: a counting allocator that can be told to fail. */
#ifndef SINTER_TEST_SUPPORT_H
#define SINTER_TEST_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include <math.h>

#include <sinter.h>

/* |a - b| <= tol, with both values printed on failure (cmocka 1.1.5 has no double assert). */
#define assert_close(a, b, tol)                                                            \
    do {                                                                                   \
        const double a_ = (a), b_ = (b), t_ = (tol);                                       \
        if (!(fabs(a_ - b_) <= t_)) {                                                      \
            print_error("%s = %.17g and %s = %.17g differ by %.3g > %.3g\n", #a, a_, #b, b_, \
                        fabs(a_ - b_), t_);                                                \
            fail();                                                                        \
        }                                                                                  \
    } while (0)

typedef struct counting_allocator {
    long allocations; /* successful alloc + realloc(NULL) calls */
    long frees;
    long fail_after;  /* calls that succeed before every later one fails; < 0 never fails */
    long calls;
} counting_allocator;

static void *counting_alloc(size_t size, void *user)
{
    counting_allocator *c = user;
    if (c->fail_after >= 0 && c->calls++ >= c->fail_after)
        return NULL;
    c->allocations++;
    return malloc(size);
}

static void *counting_realloc(void *ptr, size_t size, void *user)
{
    counting_allocator *c = user;
    if (c->fail_after >= 0 && c->calls++ >= c->fail_after)
        return NULL;
    if (ptr == NULL)
        c->allocations++;
    return realloc(ptr, size);
}

static void counting_free(void *ptr, void *user)
{
    counting_allocator *c = user;
    if (ptr != NULL)
        c->frees++;
    free(ptr);
}

static inline sinter_allocator counting_allocator_hook(counting_allocator *c)
{
    sinter_allocator a = {sizeof(sinter_allocator), counting_alloc, counting_realloc,
                          counting_free, c};
    return a;
}

#endif
