/* Open addressing with linear probing, at most half full. */
#include <string.h>

#include "io/key_set.h"

static size_t hash(const char *key)
{
    uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a */
    for (const unsigned char *c = (const unsigned char *)key; *c; ++c)
        h = (h ^ *c) * 0x100000001b3ull;
    return (size_t)h;
}

/* The slot holding `key`, or the empty slot where it would go (capacity > 0). */
static sinter_key_slot *slot_of(sinter_key_set *set, const char *key)
{
    const size_t mask = set->capacity - 1;
    for (size_t k = hash(key) & mask;; k = (k + 1) & mask) {
        sinter_key_slot *slot = &set->slots[k];
        if (slot->key == NULL)
            return slot;
        set->compares++;
        if (strcmp(slot->key, key) == 0)
            return slot;
    }
}

size_t sinter_key_set_find(sinter_key_set *set, const char *key)
{
    if (set->capacity == 0)
        return SIZE_MAX;
    const sinter_key_slot *slot = slot_of(set, key);
    return slot->key != NULL ? slot->index : SIZE_MAX;
}

static sinter_status grow(sinter_ctx *ctx, sinter_key_set *set)
{
    const size_t capacity = set->capacity ? 2 * set->capacity : 16;
    if (capacity > SIZE_MAX / (2 * sizeof(sinter_key_slot)))
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW, "%zu keys overflow the key set", set->count);
    sinter_key_slot *slots = sinter_calloc(ctx, capacity, sizeof(sinter_key_slot));
    if (slots == NULL)
        return sinter_last_status(ctx);
    sinter_key_set old = *set;
    set->slots = slots;
    set->capacity = capacity;
    for (size_t k = 0; k < old.capacity; ++k)
        if (old.slots[k].key != NULL)
            *slot_of(set, old.slots[k].key) = old.slots[k];
    sinter_free(ctx, old.slots);
    return SINTER_OK;
}

sinter_status sinter_key_set_insert(sinter_ctx *ctx, sinter_key_set *set, const char *key,
                                    size_t index)
{
    if (2 * (set->count + 1) > set->capacity) {
        const sinter_status st = grow(ctx, set);
        if (st != SINTER_OK)
            return st;
    }
    sinter_key_slot *slot = slot_of(set, key);
    slot->key = key;
    slot->index = index;
    set->count++;
    return SINTER_OK;
}

void sinter_key_set_free(sinter_ctx *ctx, sinter_key_set *set)
{
    sinter_free(ctx, set->slots);
    memset(set, 0, sizeof(*set));
}
