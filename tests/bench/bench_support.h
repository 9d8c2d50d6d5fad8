/*
 * Shared by the benchmark programs: stop with the library's message when a call fails, and
 * the clocks they time with. Define BENCH_NAME (the program's name, for messages) before
 * including; the program sets g_ctx to the context whose last error a failure prints.
 * Needs _POSIX_C_SOURCE >= 199309L (clock_gettime under -std=c11), defined before any header.
 */
#ifndef SINTER_BENCH_SUPPORT_H
#define SINTER_BENCH_SUPPORT_H

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "sinter.h"

static sinter_ctx *g_ctx;

static inline void bench_check(sinter_status s, const char *what, int line)
{
    if (s != SINTER_OK) {
        fprintf(stderr, "%s:%d: %s failed: %s (%s)\n", BENCH_NAME, line, what,
                sinter_status_name(s), g_ctx ? sinter_last_error(g_ctx) : "");
        exit(1);
    }
}
#define CHECK(call) bench_check((call), #call, __LINE__)

/* CPU seconds of this process (all threads). */
static inline double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds of a monotonic wall clock. */
static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
