/*
 * A hash set of borrowed strings, each with the index of what it names: the keys of a scene
 * section, so that finding one (and refusing a key given twice) takes constant time and a
 * section of n keys is read in O(n), not O(n^2).
 */
#ifndef SINTER_IO_KEY_SET_H
#define SINTER_IO_KEY_SET_H

#include "core/core.h"

typedef struct sinter_key_slot {
    const char *key; /* NULL: empty */
    size_t index;
} sinter_key_slot;

typedef struct sinter_key_set {
    sinter_key_slot *slots;
    size_t capacity; /* a power of two, or 0 */
    size_t count;
    size_t compares; /* string comparisons made so far (lets a test bound the work) */
} sinter_key_set;

/* The index stored with `key`, or SIZE_MAX when the set does not hold it. */
size_t sinter_key_set_find(sinter_key_set *set, const char *key);

/* Add `key` (not in the set; borrowed, must outlive the set) with `index`. Errors:
 * SINTER_ERR_NOMEM. */
sinter_status sinter_key_set_insert(sinter_ctx *ctx, sinter_key_set *set, const char *key,
                                    size_t index);

void sinter_key_set_free(sinter_ctx *ctx, sinter_key_set *set);

#endif
