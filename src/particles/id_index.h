/*
 * An index from persistent particle ids to indices (issue 43, milestone M0): open addressing
 * with linear probing over a power-of-two table at most half full. Slots hold index + 1
 * (0: empty); the key is read back from the set's id array, so a slot costs 4 bytes.
 *
 * The index is built lazily, on the first lookup after the set's layout changed (particles
 * added, removed or reordered: layout_generation), so a run that never looks particles up by id
 * pays nothing. Like the views' bookkeeping, building it writes into a logically const set:
 * lookups on one set must not run concurrently with each other or with changes to the set.
 */
#ifndef SINTER_ID_INDEX_H
#define SINTER_ID_INDEX_H

#include <stdint.h>

#include "core/core.h"

typedef struct sinter_id_index {
    uint32_t *slot;      /* index + 1, 0 = empty */
    size_t mask;         /* table size - 1 */
    uint64_t generation; /* the layout_generation it was built for */
    int built;           /* 0: never built or invalidated */
} sinter_id_index;

struct sinter_particles;

/* Release the table. */
void sinter_id_index_free(sinter_ctx *ctx, sinter_id_index *ix);

/* Make the index current for ps (rebuild when the layout changed). SINTER_ERR_INVALID names a
 * repeated id (the set then holds two particles with one id: only add_with_ids' own checks
 * prevent it); SINTER_ERR_NOMEM; SINTER_ERR_OVERFLOW above 2^32 - 2 particles. */
sinter_status sinter_id_index_update(sinter_id_index *ix, const struct sinter_particles *ps);

/* Index of id in ps, or SIZE_MAX (the index must be current). */
size_t sinter_id_index_find(const sinter_id_index *ix, const struct sinter_particles *ps,
                            uint64_t id);

/* The hash of an id (a 64-bit finaliser: consecutive ids spread over the table). */
static inline uint64_t sinter_id_hash(uint64_t id)
{
    id ^= id >> 33;
    id *= 0xff51afd7ed558ccdULL;
    id ^= id >> 33;
    id *= 0xc4ceb9fe1a85ec53ULL;
    id ^= id >> 33;
    return id;
}

#endif
