/*
 * Completion flags of the ranges of a partition inside one parallel region: a thread that
 * needs ranges 0 .. r-1 finished waits for their flags only, instead of every thread meeting
 * at a barrier (issue 9: on two threads the faster one runs on into its next phase). The
 * flags start cleared before the region (its fork orders that write before every thread's
 * reads); a range is marked done with a release store and waited for with acquire loads, so
 * what its thread wrote before is visible after the wait.
 *
 * A wait only ever waits for work that itself waits for nothing (the callers mark ranges in
 * a phase without waits), so it ends on any number of threads; past a few thousand spins it
 * yields the processor, for a team larger than the machine.
 */
#ifndef SINTER_RANGE_FLAGS_H
#define SINTER_RANGE_FLAGS_H

#include <sched.h>
#include <stdatomic.h>

#if defined(__x86_64__) && defined(__SSE2__)
#include <emmintrin.h>
#define SINTER_SPIN_PAUSE() _mm_pause()
#else
#define SINTER_SPIN_PAUSE() ((void)0)
#endif

enum { SINTER_RANGE_FLAGS_MAX = 64 };

typedef struct sinter_range_flags {
    atomic_int done[SINTER_RANGE_FLAGS_MAX];
} sinter_range_flags;

/* Ranges 0 .. count-1 not done (before the parallel region). */
static inline void sinter_range_flags_clear(sinter_range_flags *f, int count)
{
    for (int s = 0; s < count && s < SINTER_RANGE_FLAGS_MAX; ++s)
        atomic_init(&f->done[s], 0);
}

/* Range s done: what this thread wrote for it is visible to the threads that wait for it. */
static inline void sinter_range_flags_set(sinter_range_flags *f, int s)
{
    atomic_store_explicit(&f->done[s], 1, memory_order_release);
}

/* Returns once ranges 0 .. r-1 are done (r at most the count cleared). */
static inline void sinter_range_flags_wait_below(sinter_range_flags *f, int r)
{
    for (int s = 0; s < r; ++s) {
        unsigned spins = 0;
        while (!atomic_load_explicit(&f->done[s], memory_order_acquire)) {
            SINTER_SPIN_PAUSE();
            if (++spins % 4096 == 0)
                sched_yield();
        }
    }
}

#endif
