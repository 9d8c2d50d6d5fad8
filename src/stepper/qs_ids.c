/*
 * The quasi-static stepper's id order (issue 43, milestone M0).
 *
 * The stepper numbers the particles by ascending id: particle slots. Its links are keyed by the
 * ids of their two particles (sinter_qs_pair), new links are made in the order of their id
 * pairs, and every array it keeps per particle (plane conditions, loads, displacements, the
 * link graph's components, the kept pairs of the contact search) is per slot. The bonded solve
 * receives the links numbered by slot, so its sweep order (bonded/domain_order.h) and its sums
 * follow the ids too. What the caller's indices decide is only where a particle's numbers are
 * read and written, so a reordering of the particles (the stepper option sort_interval, a host
 * that adds its particles in another order) gives the same bits, and the only work a
 * reordering costs is a new map and new indices in the links.
 *
 * The links keep the caller's indices in their beams (a, b: what the snapshot, the scene's
 * outputs and the statistics read); sinter_qs_remap sets them again from the ids after a
 * reordering. When the ids ascend with the index (a set filled by sinter_particles_add, the
 * scenes), slot and index coincide and every order is the one the stepper had before it was
 * keyed by ids: the same bits.
 */
#include <stdlib.h>
#include <string.h>

#include "stepper/qs_struct.h"

int sinter_qs_pair_compare(const void *a, const void *b)
{
    const sinter_qs_pair *x = a, *y = b;
    if (x->lo != y->lo)
        return (x->lo > y->lo) - (x->lo < y->lo);
    return (x->hi > y->hi) - (x->hi < y->hi);
}

size_t sinter_qs_slot_of_id(const sinter_qs *qs, uint64_t id)
{
    if (id < qs->slots && qs->slot_id[id] == id) /* the ids 0, 1, ... of sinter_particles_add */
        return (size_t)id;
    size_t lo = 0, hi = qs->slots; /* binary search in the ascending ids */
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (qs->slot_id[mid] < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < qs->slots && qs->slot_id[lo] == id ? lo : SIZE_MAX;
}

/* (id, index) pairs, ordered by id (qsort). */
static int id_index_compare(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* The map of n particles; *same (may be NULL) gets 1 when the ids are those of the map before
 * (the same particles, perhaps reordered). */
static sinter_status slots_make(sinter_qs *qs, size_t n, const uint64_t *ids, int *same)
{
    sinter_ctx *ctx = qs->ctx;
    const int had = qs->slots_valid;
    const size_t before = qs->slots;
    qs->slots_valid = 0;
    if (same)
        *same = 0;
    if (n >= UINT32_MAX - 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "quasi-static stepper: %zu particles, more than 2^32 - 2", n);
    int ascending = 1;
    for (size_t i = 1; ids != NULL && i < n && ascending; ++i)
        ascending = ids[i] > ids[i - 1];
    uint64_t(*pairs)[2] = NULL;
    if (!ascending) {
        pairs = sinter_alloc(ctx, (n + 1) * sizeof(*pairs));
        if (pairs == NULL)
            return SINTER_ERR_NOMEM;
        for (size_t i = 0; i < n; ++i) {
            pairs[i][0] = ids[i];
            pairs[i][1] = i;
        }
        qsort(pairs, n, sizeof(*pairs), id_index_compare);
        for (size_t s = 1; s < n; ++s)
            if (pairs[s][0] == pairs[s - 1][0]) {
                const uint64_t id = pairs[s][0];
                const size_t i = (size_t)pairs[s - 1][1], j = (size_t)pairs[s][1];
                sinter_free(ctx, pairs);
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "quasi-static stepper: particles %zu and %zu have the same id "
                                   "%llu",
                                   i < j ? i : j, i < j ? j : i, (unsigned long long)id);
            }
    }
    sinter_status st =
        sinter_grow(ctx, (void **)&qs->slot_id, &qs->slot_id_capacity, n + 1, sizeof(uint64_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&qs->index_of_slot, &qs->index_of_slot_capacity, n + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st =
            sinter_grow(ctx, (void **)&qs->slot_of, &qs->slot_of_capacity, n + 1, sizeof(uint32_t));
    if (st != SINTER_OK) {
        sinter_free(ctx, pairs);
        return st;
    }
    int equal = had && before == n;
    for (size_t s = 0; s < n; ++s) {
        const uint64_t id = pairs != NULL ? pairs[s][0] : ids != NULL ? ids[s] : (uint64_t)s;
        const size_t i = pairs != NULL ? (size_t)pairs[s][1] : s;
        equal = equal && qs->slot_id[s] == id;
        qs->slot_id[s] = id;
        qs->index_of_slot[s] = (uint32_t)i;
        qs->slot_of[i] = (uint32_t)s;
    }
    sinter_free(ctx, pairs);
    qs->slots = n;
    qs->slots_valid = 1;
    qs->slots_identity = ascending;
    if (same)
        *same = equal;
    return SINTER_OK;
}

sinter_status sinter_qs_slots_make(sinter_qs *qs, size_t n, const uint64_t *ids)
{
    return slots_make(qs, n, ids, NULL);
}

sinter_status sinter_qs_remap(sinter_qs *qs, size_t n, const uint64_t *ids)
{
    SINTER_CHECK_NULL(NULL, qs);
    if (n > 0)
        SINTER_CHECK_NULL(qs->ctx, ids);
    int same = 0;
    sinter_status st = slots_make(qs, n, ids, &same);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < qs->count && qs->dom.on; ++k) {
        /* a subdomain keeps its links: the other end of each must be one of its ghosts */
        const sinter_qs_link *l = &qs->links[k];
        const uint64_t gone = sinter_qs_slot_of_id(qs, l->id_a) == SIZE_MAX   ? l->id_a
                              : sinter_qs_slot_of_id(qs, l->id_b) == SIZE_MAX ? l->id_b
                                                                              : UINT64_MAX;
        if (gone != UINT64_MAX) {
            qs->slots_valid = 0; /* (the links still name the old indices) */
            return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                               "quasi-static stepper: particle id %llu of the link of ids %llu "
                               "and %llu is neither owned nor a ghost here; the host's ghosts "
                               "must hold every particle within the ghost cut-off",
                               (unsigned long long)gone, (unsigned long long)l->id_a,
                               (unsigned long long)l->id_b);
        }
    }
    size_t kept = 0;
    for (size_t k = 0; k < qs->count; ++k) {
        sinter_qs_link *l = &qs->links[k];
        const size_t a = sinter_qs_slot_of_id(qs, l->id_a), b = sinter_qs_slot_of_id(qs, l->id_b);
        if (a == SIZE_MAX || b == SIZE_MAX)
            continue; /* a particle of the link was removed */
        l->beam.a = qs->index_of_slot[a];
        l->beam.b = qs->index_of_slot[b];
        qs->links[kept++] = *l;
    }
    if (kept != qs->count) { /* the keys of the links kept (the ids of a key never change) */
        for (size_t k = 0; k < kept; ++k)
            qs->keys[k] = sinter_qs_pair_of(qs->links[k].id_a, qs->links[k].id_b);
        qsort(qs->keys, kept, sizeof(sinter_qs_pair), sinter_qs_pair_compare);
    }
    qs->count = kept;
    const int carried = !same && sinter_qs_carried_apply(qs); /* a portable restart */
    qs->carried_count = 0;
    if (carried)
        qs->near.valid = 0;
    else if (!same) {
        /* Other particles: the plane conditions are detected again at the next step (the
         * initial extents and positions are kept), and the kept pairs are searched again. A
         * reordering of the same particles keeps both: they are per slot. */
        if (qs->particles != 0)
            qs->particles = SIZE_MAX;
        qs->near.valid = 0;
    }
    return SINTER_OK;
}

sinter_status sinter_qs_follow_ids(sinter_qs *qs, const sinter_qs_particles *p)
{
    const size_t n = p->count;
    int current = qs->slots_valid && qs->slots == n;
    for (size_t s = 0; s < n && current; ++s) {
        const size_t i = qs->index_of_slot[s];
        current = (p->id != NULL ? p->id[i] : (uint64_t)i) == qs->slot_id[s];
    }
    if (current) {
        qs->carried_count = 0; /* imported state is for a new map only */
        return SINTER_OK;
    }
    if (p->id != NULL)
        return sinter_qs_remap(qs, n, p->id);
    /* the index is the id */
    uint64_t *ids = sinter_alloc(qs->ctx, (n + 1) * sizeof(uint64_t));
    if (ids == NULL)
        return SINTER_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i)
        ids[i] = i;
    const sinter_status st = sinter_qs_remap(qs, n, ids);
    sinter_free(qs->ctx, ids);
    return st;
}

sinter_status sinter_qs_slot_geometry(sinter_qs *qs, const sinter_qs_particles *p, const double **x,
                                      const double **radius)
{
    const size_t n = p->count;
    if (qs->slots_identity) {
        *x = p->x;
        *radius = p->radius;
        return SINTER_OK;
    }
    sinter_status st =
        sinter_grow(qs->ctx, (void **)&qs->slot_x, &qs->slot_x_capacity, 3 * n + 1, sizeof(double));
    if (st == SINTER_OK)
        st =
            sinter_grow(qs->ctx, (void **)&qs->slot_r, &qs->slot_r_capacity, n + 1, sizeof(double));
    if (st != SINTER_OK)
        return st;
    for (size_t s = 0; s < n; ++s) {
        const size_t i = qs->index_of_slot[s];
        memcpy(qs->slot_x + 3 * s, p->x + 3 * i, 3 * sizeof(double));
        qs->slot_r[s] = p->radius[i];
    }
    *x = qs->slot_x;
    *radius = qs->slot_r;
    return SINTER_OK;
}
