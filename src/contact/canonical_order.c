/* The reproducible mode's order of the candidate pairs (canonical_order.h). */
#include <stdlib.h>

#include "contact/canonical_order.h"

typedef struct keyed_pair {
    uint64_t ki, kj;
    uint32_t i, j;
} keyed_pair;

static int by_keys(const void *pa, const void *pb)
{
    const keyed_pair *a = pa, *b = pb;
    if (a->ki != b->ki)
        return a->ki < b->ki ? -1 : 1;
    if (a->kj != b->kj)
        return a->kj < b->kj ? -1 : 1;
    if (a->i != b->i) /* (equal keys only between periodic images: any fixed order) */
        return a->i < b->i ? -1 : 1;
    return a->j < b->j ? -1 : a->j > b->j;
}

sinter_status sinter_pairs_sort_by_keys(sinter_ctx *ctx, sinter_pair_list *l, void **scratch,
                                        size_t *capacity)
{
    l->canonical = 1;
    const size_t n = l->count;
    if (n < 2)
        return SINTER_OK;
    const sinter_status s = sinter_grow(ctx, scratch, capacity, n, sizeof(keyed_pair));
    if (s != SINTER_OK)
        return s;
    keyed_pair *p = *scratch;
    int sorted = 1;
    for (size_t k = 0; k < n; ++k) {
        p[k] = (keyed_pair){l->key_i[k], l->key_j[k], l->i[k], l->j[k]};
        sorted &= k == 0 || by_keys(&p[k - 1], &p[k]) < 0;
    }
    if (sorted)
        return SINTER_OK;
    qsort(p, n, sizeof(keyed_pair), by_keys);
    for (size_t k = 0; k < n; ++k) {
        l->key_i[k] = p[k].ki;
        l->key_j[k] = p[k].kj;
        l->i[k] = p[k].i;
        l->j[k] = p[k].j;
    }
    return SINTER_OK;
}
