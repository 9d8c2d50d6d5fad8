/* Cell-grid neighbour search with a Verlet skin and id-keyed pair matching. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "neighbors.h"

void sinter_neighbors_init(sinter_neighbors *nb, sinter_ctx *ctx, double skin)
{
    memset(nb, 0, sizeof(*nb));
    nb->ctx = ctx;
    nb->skin = skin;
}

static void free_pairs(sinter_ctx *ctx, sinter_pair_list *l)
{
    sinter_free(ctx, l->i);
    sinter_free(ctx, l->j);
    sinter_free(ctx, l->key_i);
    sinter_free(ctx, l->key_j);
    sinter_free(ctx, l->from);
    sinter_free(ctx, l->adj_start);
    sinter_free(ctx, l->adj_pair);
    memset(l, 0, sizeof(*l));
}

void sinter_neighbors_free(sinter_neighbors *nb)
{
    free_pairs(nb->ctx, &nb->pp);
    free_pairs(nb->ctx, &nb->pw);
    free_pairs(nb->ctx, &nb->old_pp);
    free_pairs(nb->ctx, &nb->old_pw);
    sinter_free(nb->ctx, nb->x_ref);
    sinter_free(nb->ctx, nb->wall_ref);
    sinter_free(nb->ctx, nb->cell_start);
    sinter_free(nb->ctx, nb->cell_items);
    sinter_free(nb->ctx, nb->hash);
    memset(nb, 0, sizeof(*nb));
}

static sinter_status reserve_pairs(sinter_ctx *ctx, sinter_pair_list *l, size_t need)
{
    if (need <= l->capacity)
        return SINTER_OK;
    size_t c = l->capacity ? l->capacity : 256;
    while (c < need)
        c *= 2;
    void *arrays[5] = {l->i, l->j, l->key_i, l->key_j, l->from};
    const size_t elem[5] = {sizeof(uint32_t), sizeof(uint32_t), sizeof(uint64_t), sizeof(uint64_t),
                            sizeof(uint32_t)};
    for (int a = 0; a < 5; ++a) {
        void *q = sinter_realloc_array(ctx, arrays[a], c, elem[a]);
        if (q == NULL) {
            /* keep what was already grown so nothing leaks */
            l->i = arrays[0], l->j = arrays[1], l->key_i = arrays[2], l->key_j = arrays[3];
            l->from = arrays[4];
            return sinter_last_status(ctx);
        }
        arrays[a] = q;
    }
    l->i = arrays[0], l->j = arrays[1], l->key_i = arrays[2], l->key_j = arrays[3];
    l->from = arrays[4];
    l->capacity = c;
    return SINTER_OK;
}

static inline sinter_status push_pair(sinter_ctx *ctx, sinter_pair_list *l, uint32_t i, uint32_t j,
                                      uint64_t ki, uint64_t kj)
{
    if (l->count == l->capacity) {
        sinter_status st = reserve_pairs(ctx, l, l->count + 1);
        if (st != SINTER_OK)
            return st;
    }
    l->i[l->count] = i;
    l->j[l->count] = j;
    l->key_i[l->count] = ki;
    l->key_j[l->count] = kj;
    l->count++;
    return SINTER_OK;
}

int sinter_neighbors_stale(const sinter_neighbors *nb, const sinter_particles *ps,
                           const sinter_walls *walls)
{
    const size_t nw = walls ? walls->count : 0;
    if (!nb->built || nb->layout_generation != ps->layout_generation || nb->wall_count != nw)
        return 1;
    const double half = 0.5 * nb->skin;
    double max_wall = 0.0;
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *w = &walls->wall[k];
        const double s = w->n[0] * w->p[0] + w->n[1] * w->p[1] + w->n[2] * w->p[2];
        const double moved = fabs(s - nb->wall_ref[k]);
        if (moved > max_wall)
            max_wall = moved;
    }
    if (max_wall >= nb->skin)
        return 1;
    double max2 = 0.0;
    const double *x = ps->x, *x0 = nb->x_ref;
    for (size_t i = 0; i < 3 * ps->count; i += 3) {
        const double dx = x[i] - x0[i], dy = x[i + 1] - x0[i + 1], dz = x[i + 2] - x0[i + 2];
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 > max2)
            max2 = d2;
    }
    const double max_particle = sqrt(max2);
    return max_particle >= half || max_particle + max_wall >= nb->skin;
}

static inline uint64_t mix_key(uint64_t a, uint64_t b)
{
    uint64_t h = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2));
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return h;
}

/* For each pair of `now`, find the pair with the same keys in `before`. */
static sinter_status match_pairs(sinter_neighbors *nb, sinter_pair_list *now,
                                 const sinter_pair_list *before)
{
    if (before->count == 0) {
        for (size_t p = 0; p < now->count; ++p)
            now->from[p] = SINTER_NO_PAIR;
        return SINTER_OK;
    }
    size_t cap = 64;
    while (cap < 2 * before->count)
        cap *= 2;
    sinter_status st =
        sinter_grow(nb->ctx, (void **)&nb->hash, &nb->hash_capacity, cap, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    uint32_t *table = nb->hash;
    const size_t mask = cap - 1;
    memset(table, 0xff, cap * sizeof(uint32_t));
    for (size_t p = 0; p < before->count; ++p) {
        size_t h = mix_key(before->key_i[p], before->key_j[p]) & mask;
        while (table[h] != SINTER_NO_PAIR)
            h = (h + 1) & mask;
        table[h] = (uint32_t)p;
    }
    for (size_t q = 0; q < now->count; ++q) {
        size_t h = mix_key(now->key_i[q], now->key_j[q]) & mask;
        uint32_t found = SINTER_NO_PAIR;
        while (table[h] != SINTER_NO_PAIR) {
            const uint32_t p = table[h];
            if (before->key_i[p] == now->key_i[q] && before->key_j[p] == now->key_j[q]) {
                found = p;
                break;
            }
            h = (h + 1) & mask;
        }
        now->from[q] = found;
    }
    return SINTER_OK;
}

static void swap_lists(sinter_pair_list *a, sinter_pair_list *b)
{
    sinter_pair_list t = *a;
    *a = *b;
    *b = t;
}

/* Particle-particle candidates: particles binned in cells of side >= the largest cutoff. */
static sinter_status build_pp(sinter_neighbors *nb, const sinter_particles *ps)
{
    sinter_ctx *ctx = nb->ctx;
    const size_t n = ps->count;
    nb->pp.count = 0;
    if (n < 2)
        return SINTER_OK;
    const double *x = ps->x, *r = ps->radius;
    double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]}, rmax = 0.0;
    for (size_t i = 0; i < n; ++i) {
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], x[3 * i + d]);
            hi[d] = fmax(hi[d], x[3 * i + d]);
        }
        rmax = fmax(rmax, r[i]);
    }
    /* Finite inputs can still overflow: a span beyond DBL_MAX (particles near +-1e308)
     * or a cell of radius ~1e308 counts as DBL_MAX, so every quotient below is finite
     * or +inf and the loop ends (the cell grows until the count fits). */
    double cell = fmin(2.0 * rmax + nb->skin, DBL_MAX), span[3];
    for (int d = 0; d < 3; ++d)
        span[d] = fmin(hi[d] - lo[d], DBL_MAX);
    /* Keep the grid at most ~2 cells per particle (sparse scenes). */
    size_t dims[3];
    for (;;) {
        double total = 1.0;
        int too_many = 0;
        for (int d = 0; d < 3; ++d) {
            const double cells = floor(span[d] / cell) + 1.0;
            if (!(cells <= 4e6) || total * cells > 2.0 * (double)n + 64.0) {
                too_many = 1;
                break;
            }
            dims[d] = (size_t)cells; /* converted only once known to fit */
            total *= cells;
        }
        if (!too_many)
            break;
        cell = fmin(cell * 1.5, DBL_MAX);
    }
    const size_t ncell = dims[0] * dims[1] * dims[2];
    sinter_status st =
        sinter_grow(ctx, (void **)&nb->cell_start, &nb->cell_capacity, ncell + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->cell_items, &nb->items_capacity, 2 * n,
                         sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    uint32_t *start = nb->cell_start, *items = nb->cell_items, *cell_of = nb->cell_items + n;
    memset(start, 0, (ncell + 1) * sizeof(uint32_t));
    const double inv = 1.0 / cell;
    for (size_t i = 0; i < n; ++i) {
        size_t c[3];
        for (int d = 0; d < 3; ++d) {
            /* >= 0, possibly +inf (overflowed difference) or NaN (inf * 0): clamp first */
            const double q = (x[3 * i + d] - lo[d]) * inv;
            c[d] = q < (double)dims[d] ? (size_t)q : dims[d] - 1;
        }
        cell_of[i] = (uint32_t)((c[2] * dims[1] + c[1]) * dims[0] + c[0]);
        start[cell_of[i] + 1]++;
    }
    for (size_t c = 0; c < ncell; ++c)
        start[c + 1] += start[c];
    /* counting sort: items[start[c] .. start[c+1]) are the particles of cell c, by index */
    for (size_t i = 0; i < n; ++i)
        items[start[cell_of[i]]++] = (uint32_t)i;
    for (size_t c = ncell; c > 0; --c)
        start[c] = start[c - 1];
    start[0] = 0;

    const double skin = nb->skin;
    const uint64_t *id = ps->id;
    for (size_t i = 0; i < n; ++i) {
        const size_t ci = cell_of[i];
        const long cx = (long)(ci % dims[0]), cy = (long)((ci / dims[0]) % dims[1]),
                   cz = (long)(ci / (dims[0] * dims[1]));
        for (long dz = -1; dz <= 1; ++dz) {
            const long z = cz + dz;
            if (z < 0 || z >= (long)dims[2])
                continue;
            for (long dy = -1; dy <= 1; ++dy) {
                const long y = cy + dy;
                if (y < 0 || y >= (long)dims[1])
                    continue;
                for (long dx = -1; dx <= 1; ++dx) {
                    const long xc = cx + dx;
                    if (xc < 0 || xc >= (long)dims[0])
                        continue;
                    const size_t c = ((size_t)z * dims[1] + (size_t)y) * dims[0] + (size_t)xc;
                    for (uint32_t k = start[c]; k < start[c + 1]; ++k) {
                        const uint32_t j = items[k];
                        if (j <= i)
                            continue;
                        const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                                     ez = x[3 * j + 2] - x[3 * i + 2];
                        const double cut = r[i] + r[j] + skin;
                        if (ex * ex + ey * ey + ez * ez < cut * cut) {
                            /* Orient the pair by persistent id, so that per-pair history
                             * (a tangential spring seen from i) survives reordering. */
                            const int keep = id[i] < id[j];
                            st = push_pair(ctx, &nb->pp, keep ? (uint32_t)i : j,
                                           keep ? j : (uint32_t)i, keep ? id[i] : id[j],
                                           keep ? id[j] : id[i]);
                            if (st != SINTER_OK)
                                return st;
                        }
                    }
                }
            }
        }
    }
    return SINTER_OK;
}

static sinter_status build_pw(sinter_neighbors *nb, const sinter_particles *ps,
                              const sinter_walls *walls)
{
    nb->pw.count = 0;
    if (walls == NULL)
        return SINTER_OK;
    const double *x = ps->x, *r = ps->radius;
    for (size_t i = 0; i < ps->count; ++i) {
        for (size_t k = 0; k < walls->count; ++k) {
            const sinter_wall *w = &walls->wall[k];
            const double s = (x[3 * i] - w->p[0]) * w->n[0] + (x[3 * i + 1] - w->p[1]) * w->n[1] +
                             (x[3 * i + 2] - w->p[2]) * w->n[2];
            if (s < r[i] + nb->skin) {
                sinter_status st =
                    push_pair(nb->ctx, &nb->pw, (uint32_t)i, (uint32_t)k, ps->id[i], k);
                if (st != SINTER_OK)
                    return st;
            }
        }
    }
    return SINTER_OK;
}

/* Per-particle lists of pairs, in ascending pair index (a stable counting sort). */
static sinter_status build_adjacency(sinter_neighbors *nb, size_t n)
{
    sinter_pair_list *l = &nb->pp;
    sinter_status st = sinter_grow(nb->ctx, (void **)&l->adj_start, &l->adj_start_capacity,
                                   n + 2, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(nb->ctx, (void **)&l->adj_pair, &l->adj_pair_capacity,
                         2 * l->count + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    uint32_t *start = l->adj_start, *list = l->adj_pair;
    memset(start, 0, (n + 2) * sizeof(uint32_t));
    for (size_t p = 0; p < l->count; ++p) {
        start[l->i[p] + 2]++;
        start[l->j[p] + 2]++;
    }
    for (size_t i = 2; i < n + 2; ++i)
        start[i] += start[i - 1];
    /* start[p + 1] is the running cursor of particle p; afterwards start[p] begins its list */
    for (size_t p = 0; p < l->count; ++p) {
        list[start[l->i[p] + 1]++] = (uint32_t)p;
        list[start[l->j[p] + 1]++] = (uint32_t)p;
    }
    return SINTER_OK;
}

sinter_status sinter_neighbors_build(sinter_neighbors *nb, const sinter_particles *ps,
                                     const sinter_walls *walls)
{
    sinter_ctx *ctx = nb->ctx;
    if (ps->count >= SINTER_NO_PAIR)
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW,
                           "%zu particles exceed the neighbour list's 32-bit indices", ps->count);
    swap_lists(&nb->pp, &nb->old_pp);
    swap_lists(&nb->pw, &nb->old_pw);
    sinter_status st = build_pp(nb, ps);
    if (st == SINTER_OK)
        st = build_pw(nb, ps, walls);
    if (st == SINTER_OK)
        st = reserve_pairs(ctx, &nb->pp, 1);
    if (st == SINTER_OK)
        st = reserve_pairs(ctx, &nb->pw, 1);
    if (st == SINTER_OK)
        st = build_adjacency(nb, ps->count);
    if (st == SINTER_OK)
        st = match_pairs(nb, &nb->pp, &nb->old_pp);
    if (st == SINTER_OK)
        st = match_pairs(nb, &nb->pw, &nb->old_pw);
    const size_t nw = walls ? walls->count : 0;
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->x_ref, &nb->ref_capacity, 3 * ps->count + 3,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->wall_ref, &nb->wall_ref_capacity, nw + 1,
                         sizeof(double));
    if (st != SINTER_OK) {
        nb->built = 0;
        return st;
    }
    memcpy(nb->x_ref, ps->x, 3 * ps->count * sizeof(double));
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *w = &walls->wall[k];
        nb->wall_ref[k] = w->n[0] * w->p[0] + w->n[1] * w->p[1] + w->n[2] * w->p[2];
    }
    nb->wall_count = nw;
    nb->layout_generation = ps->layout_generation;
    nb->built = 1;
    return SINTER_OK;
}
