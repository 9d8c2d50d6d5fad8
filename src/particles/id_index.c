/* Persistent id -> particle index (issue 43, M0): see id_index.h. */
#include "particles/id_index.h"

#include <string.h>

#include "particles/particles.h"

void sinter_id_index_free(sinter_ctx *ctx, sinter_id_index *ix)
{
    sinter_free(ctx, ix->slot);
    memset(ix, 0, sizeof(*ix));
}

size_t sinter_id_index_find(const sinter_id_index *ix, const sinter_particles *ps, uint64_t id)
{
    if (ix->slot == NULL)
        return SIZE_MAX;
    for (size_t s = (size_t)sinter_id_hash(id) & ix->mask;; s = (s + 1) & ix->mask) {
        const uint32_t v = ix->slot[s];
        if (v == 0)
            return SIZE_MAX;
        if (ps->id[v - 1] == id)
            return (size_t)v - 1;
    }
}

sinter_status sinter_id_index_update(sinter_id_index *ix, const sinter_particles *ps)
{
    if (ix->built && ix->generation == ps->layout_generation)
        return SINTER_OK;
    sinter_ctx *ctx = ps->ctx;
    const size_t n = ps->count - ps->ghost_count; /* ghosts share their owners' ids */
    if (n >= (size_t)UINT32_MAX - 1)
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW,
                           "particle id index: %zu particles exceed the index's 2^32 - 2", n);
    size_t size = 16;
    while (size < 2 * n)
        size *= 2;
    if (ix->slot == NULL || ix->mask + 1 != size) {
        uint32_t *slot = sinter_alloc(ctx, size * sizeof(uint32_t));
        if (slot == NULL)
            return sinter_last_status(ctx);
        sinter_free(ctx, ix->slot);
        ix->slot = slot;
        ix->mask = size - 1;
    }
    memset(ix->slot, 0, size * sizeof(uint32_t));
    ix->built = 0;
    for (size_t i = 0; i < n; ++i) {
        const uint64_t id = ps->id[i];
        size_t s = (size_t)sinter_id_hash(id) & ix->mask;
        while (ix->slot[s] != 0) {
            const size_t j = ix->slot[s] - 1;
            if (ps->id[j] == id)
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "particles %zu and %zu have the same id %llu", j, i,
                                   (unsigned long long)id);
            s = (s + 1) & ix->mask;
        }
        ix->slot[s] = (uint32_t)(i + 1);
    }
    ix->generation = ps->layout_generation;
    ix->built = 1;
    return SINTER_OK;
}
