/*
 * Quasi-static links that leave with a particle and come back with it (issue 43, migrate.h): a
 * link travels in the record of its smaller-id particle, with its beam and 7DOF neck state.
 */
#include <stdlib.h>
#include <string.h>

#include "stepper/migrate.h"
#include "stepper/qs_struct.h"

/* The keys of qs's links, sorted (after links were added or dropped). */
static void keys_again(sinter_qs *qs)
{
    for (size_t k = 0; k < qs->count; ++k)
        qs->keys[k] = sinter_qs_pair_of(qs->links[k].id_a, qs->links[k].id_b);
    qsort(qs->keys, qs->count, sizeof(sinter_qs_pair), sinter_qs_pair_compare);
}

void sinter_qs_links_drop(sinter_qs *qs, const unsigned char *drop)
{
    size_t kept = 0;
    for (size_t k = 0; k < qs->count; ++k)
        if (!drop[k])
            qs->links[kept++] = qs->links[k];
    if (kept == qs->count)
        return;
    qs->count = kept;
    keys_again(qs);
}

/* The order in which a run makes its links: by the time made, then by key (the new links of
 * one step are made in the order of their id pairs, quasistatic.c). */
static int made_order(const void *a, const void *b)
{
    const sinter_qs_link *x = a, *y = b;
    if (x->born != y->born)
        return (x->born > y->born) - (x->born < y->born);
    const sinter_qs_pair kx = sinter_qs_pair_of(x->id_a, x->id_b),
                         ky = sinter_qs_pair_of(y->id_a, y->id_b);
    return sinter_qs_pair_compare(&kx, &ky);
}

sinter_status sinter_qs_links_insert(sinter_qs *qs, const sinter_qs_link *links, size_t m,
                                     size_t *added)
{
    *added = 0;
    if (m == 0)
        return SINTER_OK;
    sinter_status s = sinter_grow(qs->ctx, (void **)&qs->links, &qs->capacity, qs->count + m + 1,
                                  sizeof(sinter_qs_link));
    if (s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->keys, &qs->keys_capacity, qs->count + m + 1,
                        sizeof(sinter_qs_pair));
    if (s != SINTER_OK)
        return s;
    int in_order = 1;
    for (size_t k = 1; k < qs->count && in_order; ++k)
        in_order = made_order(&qs->links[k - 1], &qs->links[k]) < 0;
    const size_t before = qs->count;
    for (size_t k = 0; k < m; ++k) {
        const sinter_qs_pair key = sinter_qs_pair_of(links[k].id_a, links[k].id_b);
        if (before > 0 &&
            bsearch(&key, qs->keys, before, sizeof(sinter_qs_pair), sinter_qs_pair_compare))
            continue; /* held already: kept once */
        qs->links[qs->count++] = links[k];
    }
    *added = qs->count - before;
    if (in_order)
        qsort(qs->links, qs->count, sizeof(sinter_qs_link), made_order);
    keys_again(qs);
    return SINTER_OK;
}

void sinter_qs_particles_back(sinter_qs *qs, size_t n, const uint64_t *ids, uint64_t population)
{
    if (!qs->slots_valid || !qs->population_known || qs->slots != n)
        return;
    for (size_t i = 0; i < n; ++i)
        if (sinter_qs_slot_of_id(qs, ids[i]) == SIZE_MAX)
            return;
    qs->population_generation = population; /* the same particles: only their order changed */
}
