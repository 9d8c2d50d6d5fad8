/* Two domains and a separator for the bonded solve's sweeps (see domain_order.h). */
#include <string.h>

#include "bonded/domain_order.h"

#define UNSET UINT32_MAX
/* Breadth-first searches per component in the hunt for a pseudo-peripheral root; George and
 * Liu's search stops as soon as the depth stops growing, which takes two or three. */
#define ROOT_SEARCHES 4

void sinter_domain_order_release(sinter_domain_order *o)
{
    if (o == NULL)
        return;
    sinter_free(o->ctx, o->new_of_old);
    sinter_free(o->ctx, o->old_of_new);
    sinter_free(o->ctx, o->adjacency_start);
    sinter_free(o->ctx, o->adjacency);
    sinter_free(o->ctx, o->level);
    sinter_free(o->ctx, o->queue);
    sinter_free(o->ctx, o->level_count);
    memset(o, 0, sizeof(*o));
}

static sinter_status reserve(sinter_domain_order *o, size_t n, size_t count)
{
    sinter_ctx *ctx = o->ctx;
    sinter_status st =
        sinter_grow(ctx, (void **)&o->new_of_old, &o->new_of_old_capacity, n + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->old_of_new, &o->old_of_new_capacity, n + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->adjacency_start, &o->adjacency_start_capacity, n + 2,
                         sizeof(size_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->adjacency, &o->adjacency_capacity, 2 * count + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->level, &o->level_capacity, n + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->queue, &o->queue_capacity, n + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&o->level_count, &o->level_count_capacity, n + 1,
                         sizeof(size_t));
    return st;
}

/* The undirected link graph, each particle's neighbours in link order. */
static void build_adjacency(sinter_domain_order *o, size_t n, const uint32_t *lower,
                            const uint32_t *upper, size_t count)
{
    size_t *start = o->adjacency_start;
    memset(start, 0, (n + 2) * sizeof(size_t));
    for (size_t k = 0; k < count; ++k) { /* counts, two places up */
        ++start[lower[k] + 2];
        ++start[upper[k] + 2];
    }
    for (size_t p = 2; p <= n + 1; ++p)
        start[p] += start[p - 1];
    for (size_t k = 0; k < count; ++k) { /* start[p + 1]: where p's next neighbour goes */
        o->adjacency[start[lower[k] + 1]++] = upper[k];
        o->adjacency[start[upper[k] + 1]++] = lower[k];
    }
}

static size_t degree(const sinter_domain_order *o, uint32_t p)
{
    return o->adjacency_start[p + 1] - o->adjacency_start[p];
}

/* Breadth-first search from root over particles whose level is UNSET: their levels, and the
 * particles in visiting order in q. Returns how many it reached. */
static size_t search(sinter_domain_order *o, uint32_t root, uint32_t *q)
{
    size_t head = 0, tail = 0;
    q[tail++] = root;
    o->level[root] = 0;
    while (head < tail) {
        const uint32_t p = q[head++];
        for (size_t e = o->adjacency_start[p]; e < o->adjacency_start[p + 1]; ++e) {
            const uint32_t next = o->adjacency[e];
            if (o->level[next] == UNSET) {
                o->level[next] = o->level[p] + 1;
                q[tail++] = next;
            }
        }
    }
    return tail;
}

/* The level structure of the component of root (its particles' levels UNSET), rooted at a
 * pseudo-peripheral particle: search again from the deepest level's particle of least degree
 * while that makes the structure deeper. Its particles in breadth-first order go to q. */
static size_t component_levels(sinter_domain_order *o, uint32_t root, uint32_t *q)
{
    const size_t c = search(o, root, q);
    for (int round = 1; round < ROOT_SEARCHES; ++round) {
        const uint32_t depth = o->level[q[c - 1]];
        uint32_t best = q[c - 1];
        for (size_t i = c; i-- > 0 && o->level[q[i]] == depth;)
            if (degree(o, q[i]) < degree(o, best))
                best = q[i];
        if (best == q[0])
            break;
        for (size_t i = 0; i < c; ++i)
            o->level[q[i]] = UNSET;
        search(o, best, q);
        if (o->level[q[c - 1]] <= depth)
            break;
    }
    return c;
}

sinter_status sinter_domain_order_make(sinter_domain_order *o, size_t n, const uint32_t *lower,
                                       const uint32_t *upper, size_t count)
{
    sinter_status st = reserve(o, n, count);
    if (st != SINTER_OK)
        return st;
    build_adjacency(o, n, lower, upper, count);
    for (size_t p = 0; p < n; ++p)
        o->level[p] = UNSET;
    for (size_t p = 0, done = 0; p < n; ++p)
        if (o->level[p] == UNSET)
            done += component_levels(o, (uint32_t)p, o->queue + done);
    /* The separating level L: the most even split of the rest (the smaller L on ties). */
    size_t *per_level = o->level_count;
    memset(per_level, 0, (n + 1) * sizeof(size_t));
    size_t deepest = 0;
    for (size_t p = 0; p < n; ++p) {
        ++per_level[o->level[p]];
        deepest = o->level[p] > deepest ? o->level[p] : deepest;
    }
    size_t below = 0, best_level = 0, best_smaller = 0;
    for (size_t l = 0; l <= deepest; ++l) {
        const size_t above = n - below - per_level[l];
        const size_t smaller = below < above ? below : above;
        if (smaller > best_smaller) {
            best_smaller = smaller;
            best_level = l;
        }
        below += per_level[l];
    }
    size_t in_a = 0, in_b = 0;
    for (size_t l = 0; l <= deepest; ++l) {
        in_a += l < best_level ? per_level[l] : 0;
        in_b += l > best_level ? per_level[l] : 0;
    }
    /* A, B and S, each in breadth-first order */
    size_t next[3] = {0, in_a, in_a + in_b};
    for (size_t i = 0; i < n; ++i) {
        const uint32_t p = o->queue[i];
        const int part = o->level[p] < best_level ? 0 : o->level[p] > best_level ? 1 : 2;
        o->new_of_old[p] = (uint32_t)next[part];
        o->old_of_new[next[part]++] = p;
    }
    o->split_a = in_a;
    o->split_b = in_a + in_b;
    return SINTER_OK;
}
