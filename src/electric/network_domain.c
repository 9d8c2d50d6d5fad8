/*
 * The network's clusters across subdomains (issue 43; network.c, domain/solve.h).
 *
 * Which nodes are unknowns depends on the cluster a node belongs to (network.c: touching a
 * potential wall, or balanced current walls), and a cluster may run through several
 * subdomains. Each subdomain joins its nodes locally (owned particles, walls, ghosts: a union
 * over the edges as on one domain), then every cluster takes a global label, the smallest key
 * of its members (wall w: w; a particle: the number of walls + its id, so that a cluster with
 * a current wall is labelled by its first one, its pin), and two flags (it touches a potential
 * wall; it holds a particle). Labels and flags spread by rounds until no subdomain changes
 * one: a forward halo gives each ghost its owner's, and a reduction gives each current wall,
 * which joins the clusters it touches on every subdomain, the smallest label and the flags
 * over all of them. Each round moves the information one subdomain further; a cluster's
 * state then follows from its label and flags exactly as on one domain, the current walls' sums
 * taken in wall order as there.
 */
#include <math.h>
#include <string.h>

#include "electric.h"

/* A node's key: wall w is w, a particle nw + its id. */
static uint64_t node_key(const sinter_particles *ps, size_t n, size_t nw, size_t p)
{
    if (p < n)
        return nw + ps->id[p];
    if (p < n + nw)
        return p - n;
    return nw + ps->id[p - nw]; /* a ghost: node n + nw + k is row n + k */
}

/* The smaller label and the union of the flags at root r; 1 if either changed. */
static int take(sinter_electric_model *em, uint32_t r, uint64_t label, unsigned char flags)
{
    int changed = 0;
    if (label < em->label[r]) {
        em->label[r] = label;
        changed = 1;
    }
    if ((em->state[r] | flags) != em->state[r]) {
        em->state[r] |= flags;
        changed = 1;
    }
    return changed;
}

/* Labels and flags of ghosts and current walls taken in one round; 1 if one changed here. */
static int take_ghosts(sinter_electric_model *em, size_t n, size_t nw, size_t ghosts)
{
    const double *rows = em->across.rows;
    int changed = 0;
    for (size_t k = 0; k < ghosts; ++k) {
        const uint32_t r = sinter_network_root(em->parent, (uint32_t)(n + nw + k));
        uint64_t label;
        memcpy(&label, rows + 2 * (n + k), sizeof(label)); /* (the bits of the owner's label) */
        const unsigned char flags = (unsigned char)rows[2 * (n + k) + 1];
        changed |= take(em, r, label, flags);
    }
    return changed;
}

static int take_walls(sinter_electric_model *em, size_t n, size_t nw)
{
    const uint64_t *word = em->wall_words;
    int changed = 0;
    for (size_t w = 0; w < nw; ++w) {
        if (em->wall_mode[w] != SINTER_WALL_CURRENT)
            continue;
        const uint32_t r = sinter_network_root(em->parent, (uint32_t)(n + w));
        const uint64_t label = UINT64_MAX - word[w]; /* (a maximum of the complements) */
        const unsigned char flags = (unsigned char)((word[nw + w] ? CLUSTER_GROUND : 0) |
                                                    (word[2 * nw + w] ? CLUSTER_PARTICLE : 0));
        changed |= take(em, r, label, flags);
    }
    return changed;
}

/* The global labels and flags (collective: every subdomain makes the same rounds). */
static sinter_status spread(sinter_electric_model *em, const sinter_particles *ps, size_t nw)
{
    const size_t n = ps->count - ps->ghost_count;
    sinter_domain_solve *ds = &em->across;
    sinter_status s = sinter_domain_solve_reserve(ds, 2);
    if (s != SINTER_OK)
        return s;
    uint64_t *word = em->wall_words;
    int walls_changed = 1; /* (the first round has news) */
    for (;;) {
        for (size_t p = 0; p < n; ++p) {
            const uint32_t r = sinter_network_root(em->parent, (uint32_t)p);
            memcpy(ds->rows + 2 * p, &em->label[r], sizeof(double));
            ds->rows[2 * p + 1] = (double)(em->state[r] & (CLUSTER_GROUND | CLUSTER_PARTICLE));
        }
        sinter_domain_solve_halo(ds, 2);
        if (ds->failed)
            return sinter_last_status(em->ctx);
        const int ghosts_changed = take_ghosts(em, n, nw, ps->ghost_count);
        for (size_t w = 0; w < nw; ++w) {
            const uint32_t r = sinter_network_root(em->parent, (uint32_t)(n + w));
            const int current = em->wall_mode[w] == SINTER_WALL_CURRENT;
            word[w] = current ? UINT64_MAX - em->label[r] : 0;
            word[nw + w] = current && (em->state[r] & CLUSTER_GROUND);
            word[2 * nw + w] = current && (em->state[r] & CLUSTER_PARTICLE);
        }
        /* whether anything changed anywhere: in this round's ghosts or the last round's walls
         * (a round with neither leaves the walls' reductions as they were: done) */
        word[3 * nw] = (uint64_t)(ghosts_changed | walls_changed);
        s = sinter_domain_reduce(em->ctx, em->domain, word, 3 * nw + 1, SINTER_REDUCE_U64,
                                 SINTER_REDUCE_MAX);
        if (s != SINTER_OK)
            return s;
        walls_changed = take_walls(em, n, nw);
        if (word[3 * nw] == 0)
            return SINTER_OK;
    }
}

/* The state of the cluster labelled `label` with flags `flags`: CLUSTER_SOLVED when it is
 * solved, and in *pin its pinned wall node (UINT32_MAX: none). *open: an open circuit. */
static unsigned char cluster_state(const sinter_electric_model *em, const sinter_walls *walls,
                                   size_t n, size_t nw, uint64_t label, unsigned char flags,
                                   uint32_t *pin, int *open)
{
    const uint64_t *word = em->wall_words;
    unsigned char c = flags;
    double net = 0.0, scale = 0.0;
    *pin = UINT32_MAX;
    for (size_t w = 0; w < nw; ++w) { /* in wall order, as network.c sums them */
        if (em->wall_mode[w] != SINTER_WALL_CURRENT || UINT64_MAX - word[w] != label)
            continue;
        c |= CLUSTER_CURRENT;
        if (!(walls->wall[w].electric_limit > 0.0))
            c |= CLUSTER_UNLIMITED;
        net += em->wall_value[w];
        scale += fabs(em->wall_value[w]);
        if (*pin == UINT32_MAX)
            *pin = (uint32_t)(n + w);
    }
    *open = 0;
    if (c & CLUSTER_GROUND)
        c |= CLUSTER_SOLVED;
    else if ((c & CLUSTER_CURRENT) && fabs(net) <= 1e-9 * scale)
        c |= CLUSTER_SOLVED;
    else if ((c & CLUSTER_CURRENT) && (c & CLUSTER_PARTICLE) && (c & CLUSTER_UNLIMITED))
        *open = 1;
    return c;
}

sinter_status sinter_network_classify_across(sinter_electric_model *em, const sinter_walls *walls,
                                             const sinter_particles *ps, size_t nw)
{
    const size_t n = ps->count - ps->ghost_count, nodes = n + nw, all = nodes + ps->ghost_count;
    SINTER_ELECTRIC_RESERVE(em, parent, all + 1);
    SINTER_ELECTRIC_RESERVE(em, state, all + 1);
    SINTER_ELECTRIC_RESERVE(em, pin, all + 1);
    SINTER_ELECTRIC_RESERVE(em, label, all + 1);
    SINTER_ELECTRIC_RESERVE(em, wall_words, 3 * nw + 1);
    uint32_t *parent = em->parent;
    unsigned char *state = em->state;
    for (size_t p = 0; p < all; ++p) {
        parent[p] = (uint32_t)p;
        state[p] = 0;
        em->label[p] = UINT64_MAX;
        em->pin[p] = UINT32_MAX;
    }
    for (size_t e = 0; e < em->edge_count; ++e) { /* a potential wall joins nothing */
        const uint32_t b = em->edge_b[e];
        if (b < n || b >= nodes || em->wall_mode[b - n] == SINTER_WALL_CURRENT)
            sinter_network_unite(parent, em->edge_a[e], b);
    }
    for (size_t p = 0; p < all; ++p) {
        const uint32_t r = sinter_network_root(parent, (uint32_t)p);
        const uint64_t key = node_key(ps, n, nw, p);
        em->label[r] = key < em->label[r] ? key : em->label[r];
        if (p < n || p >= nodes)
            state[r] |= CLUSTER_PARTICLE;
    }
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t b = em->edge_b[e];
        if (b >= n && b < nodes && em->wall_mode[b - n] == SINTER_WALL_POTENTIAL)
            state[sinter_network_root(parent, em->edge_a[e])] |= CLUSTER_GROUND;
    }
    const sinter_status s = spread(em, ps, nw);
    if (s != SINTER_OK)
        return s;
    /* each root's state; the open circuits counted once, by their pin (the same on every
     * subdomain: the walls' words are) */
    for (size_t p = 0; p < all; ++p) {
        if (parent[p] != p)
            continue;
        int open = 0;
        state[p] = cluster_state(em, walls, n, nw, em->label[p], state[p], &em->pin[p], &open);
    }
    for (size_t w = 0; w < nw; ++w) {
        const uint64_t *word = em->wall_words;
        if (em->wall_mode[w] != SINTER_WALL_CURRENT || UINT64_MAX - word[w] != w)
            continue; /* (a cluster's first current wall is its label) */
        const unsigned char flags = (unsigned char)((word[nw + w] ? CLUSTER_GROUND : 0) |
                                                    (word[2 * nw + w] ? CLUSTER_PARTICLE : 0));
        uint32_t pin;
        int open = 0;
        (void)cluster_state(em, walls, n, nw, w, flags, &pin, &open);
        em->open_clusters += (size_t)open;
    }
    for (size_t p = 0; p < all; ++p) {
        const uint32_t r = sinter_network_root(parent, (uint32_t)p);
        if (!(state[r] & CLUSTER_SOLVED))
            continue;
        if (p >= n && p < nodes && em->wall_mode[p - n] != SINTER_WALL_CURRENT)
            continue; /* potential and neutral walls are never free */
        if ((state[r] & CLUSTER_GROUND) || em->pin[r] != p)
            state[p] |= NODE_FREE;
    }
    return SINTER_OK;
}
