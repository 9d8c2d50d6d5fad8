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
    sinter_free(o->ctx, o->level_work);
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
        st = sinter_grow(ctx, (void **)&o->level_work, &o->level_work_capacity, 2 * (n + 1),
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

/* The work of particle p in a sweep: its three diagonal-block products (backward sweep, D t,
 * forward sweep) and about one coupling-block product per link (two per link, shared by its
 * two particles), in block products. */
static size_t work_of(const sinter_domain_order *o, uint32_t p)
{
    return 3 + degree(o, p);
}

/* 1 if particle p has a neighbour one level deeper: then, in the separating level, it must stay
 * in S (B holds the deeper levels); without one it may join A. */
static int has_deeper(const sinter_domain_order *o, uint32_t p)
{
    for (size_t e = o->adjacency_start[p]; e < o->adjacency_start[p + 1]; ++e)
        if (o->level[o->adjacency[e]] == o->level[p] + 1)
            return 1;
    return 0;
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
    /* Per level: its work, and the work of its particles with a deeper neighbour (those that
     * stay in S if the level separates; the others join A). */
    size_t *level_work = o->level_work, *level_kept = o->level_work + (n + 1);
    memset(level_work, 0, 2 * (n + 1) * sizeof(size_t));
    size_t deepest = 0, total = 0;
    for (size_t p = 0; p < n; ++p) {
        const uint32_t l = o->level[p];
        const size_t w = work_of(o, (uint32_t)p);
        level_work[l] += w;
        level_kept[l] += has_deeper(o, (uint32_t)p) ? w : 0;
        total += w;
        deepest = l > deepest ? l : deepest;
    }
    /* The separating level L: the least work on the sweeps' longest path, the larger
     * domain's and then S's (alone), max(A, B) + S; the smaller L on ties. */
    size_t below = 0, best_level = 0, best_path = SIZE_MAX;
    for (size_t l = 0; n > 0 && l <= deepest; ++l) {
        const size_t s = level_kept[l], a = below + level_work[l] - s,
                     b = total - below - level_work[l];
        const size_t path = (a > b ? a : b) + s;
        if (path < best_path) {
            best_path = path;
            best_level = l;
        }
        below += level_work[l];
    }
    /* A, B and S, each in breadth-first order; the part of each particle in new_of_old first */
    size_t in_part[3] = {0, 0, 0};
    for (size_t p = 0; p < n; ++p) {
        const uint32_t l = o->level[p];
        const uint32_t part = l < best_level               ? 0
                              : l > best_level             ? 1
                              : has_deeper(o, (uint32_t)p) ? 2
                                                           : 0;
        o->new_of_old[p] = part;
        ++in_part[part];
    }
    size_t next[3] = {0, in_part[0], in_part[0] + in_part[1]};
    for (size_t i = 0; i < n; ++i) {
        const uint32_t p = o->queue[i], part = o->new_of_old[p];
        o->new_of_old[p] = (uint32_t)next[part];
        o->old_of_new[next[part]++] = p;
    }
    o->split_a = in_part[0];
    o->split_b = in_part[0] + in_part[1];
    return SINTER_OK;
}
