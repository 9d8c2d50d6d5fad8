/*
 * The FNV-1a hash (64-bit; Fowler, Noll and Vo), the checksum of the library's byte streams:
 * checkpoints (io/checkpoint.c), migration records (stepper/migrate.c) and the stepper's global
 * part (stepper/global_state.c). Start from SINTER_FNV1A_START and fold bytes in, in any pieces.
 */
#ifndef SINTER_CORE_FNV1A_H
#define SINTER_CORE_FNV1A_H

#include <stddef.h>
#include <stdint.h>

#define SINTER_FNV1A_START 0xcbf29ce484222325ull

/* h with the n bytes at p folded in. */
static inline uint64_t sinter_fnv1a(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t k = 0; k < n; ++k) {
        h ^= b[k];
        h *= 0x100000001b3ull;
    }
    return h;
}

#endif
