/*
 * Streaming (non-temporal) stores, x86-64 SSE2: a value written this way goes past the
 * caches, so its line is not read first and does not evict data the next passes read. They
 * pay only for arrays that do not fit in the caches (issue 9; the stepper chooses by timing,
 * sinter_store_choice in stepper/stepper.h). Elsewhere they are plain stores.
 */
#ifndef SINTER_STREAM_STORE_H
#define SINTER_STREAM_STORE_H

#include <string.h>

#if defined(__x86_64__) && defined(__SSE2__)
#include <emmintrin.h>
#define SINTER_STREAMING_STORES 1
#else
#define SINTER_STREAMING_STORES 0
#endif

/* *p = v, streamed with `stream`. */
static inline void sinter_put(double *p, double v, int stream)
{
#if SINTER_STREAMING_STORES
    if (stream) {
        long long bits;
        memcpy(&bits, &v, sizeof(bits));
        _mm_stream_si64((long long *)p, bits);
        return;
    }
#endif
    (void)stream;
    *p = v;
}

/* dst = src (size bytes) only where the bits differ (so that a zero keeps its sign): a
 * store, even of the same value, takes the cache line from every other core that holds it,
 * which then fetches it again (issue 9: wall contacts' normals, walls' points). */
static inline void sinter_put_changed(void *dst, const void *src, size_t size)
{
    if (memcmp(dst, src, size) != 0)
        memcpy(dst, src, size);
}

/* After a thread's streamed stores, before other threads read them (the end of its share
 * of a parallel loop). */
static inline void sinter_put_fence(int stream)
{
#if SINTER_STREAMING_STORES
    if (stream)
        _mm_sfence();
#endif
    (void)stream;
}

#endif
