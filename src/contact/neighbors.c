/* Cell-grid neighbour search with a Verlet skin and id-keyed pair matching. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "neighbors.h"
#include "contact/canonical_order.h"

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
    sinter_free(nb->ctx, nb->wall_near);
    sinter_free(nb->ctx, nb->wall_hint);
    sinter_free(nb->ctx, nb->cell_start);
    sinter_free(nb->ctx, nb->cell_items);
    sinter_free(nb->ctx, nb->cell_counts);
    sinter_free(nb->ctx, nb->hash);
    sinter_free(nb->ctx, nb->scan);
    sinter_free(nb->ctx, nb->keep_start);
    sinter_free(nb->ctx, nb->keep_j);
    sinter_free(nb->ctx, nb->order_scratch);
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

/* The displacement bound from a measure of it (`bound` [m]; NaN: none) for ps's generations. */
static void set_bound(sinter_neighbors *nb, const sinter_particles *ps, double bound)
{
    nb->moved_bound = bound;
    nb->bound_valid = bound >= 0.0; /* not NaN */
    nb->bound_layout = ps->layout_generation;
    nb->bound_write = ps->write_generation;
}

void sinter_neighbors_set_moved(sinter_neighbors *nb, const sinter_particles *ps, double moved2)
{
    nb->moved2 = moved2;
    nb->moved_valid = 1;
    nb->moved_layout = ps->layout_generation;
    nb->moved_write = ps->write_generation;
    set_bound(nb, ps, sqrt(moved2));
}

int sinter_neighbors_bound_holds(const sinter_neighbors *nb, const sinter_particles *ps)
{
    return nb->bound_valid && nb->bound_layout == ps->layout_generation &&
           nb->bound_write == ps->write_generation && nb->moved_bound < 0.25 * nb->skin;
}

void sinter_neighbors_add_step(sinter_neighbors *nb, const sinter_particles *ps, double step)
{
    const double bound = nb->moved_bound + step; /* |x - x_ref| <= the sum of the steps */
    nb->moved_valid = 0;
    if (!sinter_neighbors_bound_holds(nb, ps) || !(bound < 0.25 * nb->skin)) {
        nb->bound_valid = 0; /* the staleness test measures, and the next step too */
        return;
    }
    nb->moved_bound = bound;
    nb->moved2 = bound * bound;
    nb->moved_valid = 1;
    nb->moved_layout = ps->layout_generation;
    nb->moved_write = ps->write_generation;
}

void sinter_neighbors_clear_moved(sinter_neighbors *nb)
{
    nb->moved_valid = 0;
}

void sinter_neighbors_positions_restored(sinter_neighbors *nb)
{
    nb->moved_valid = 0;
    nb->bound_valid = 0;
}

/* Particle i's squared displacement from x0. */
static inline double moved2(const double *x, const double *x0, long i)
{
    const double dx = x[3 * i] - x0[3 * i], dy = x[3 * i + 1] - x0[3 * i + 1],
                 dz = x[3 * i + 2] - x0[3 * i + 2];
    return dx * dx + dy * dy + dz * dz;
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
        const double moved = sinter_wall_moved(&walls->wall[k], nb->wall_ref + 4 * k);
        if (moved > max_wall)
            max_wall = moved;
    }
    if (max_wall >= nb->skin)
        return 1;
    double max2 = 0.0;
    if (nb->moved_valid && nb->moved_layout == ps->layout_generation &&
        nb->moved_write == ps->write_generation) {
        max2 = nb->moved2;
    } else {
        const double *x = ps->x, *x0 = nb->x_ref;
        const long n = (long)ps->count;
        const int threads = n < 16384 ? 1 : sinter_threads(nb->ctx);
        /* a maximum does not depend on the order: the same for any number of threads */
        if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : max2)
            for (long i = 0; i < n; ++i) {
                const double d2 = moved2(x, x0, i);
                max2 = d2 > max2 ? d2 : max2;
            }
        } else { /* a region of one thread costs a team (core/ranges_run.h) */
            for (long i = 0; i < n; ++i) {
                const double d2 = moved2(x, x0, i);
                max2 = d2 > max2 ? d2 : max2;
            }
        }
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

/* The pair of `before` with now's pair q's keys in the open-addressed table (SINTER_NO_PAIR:
 * none). */
static inline uint32_t hash_find(const uint32_t *table, size_t mask, const sinter_pair_list *before,
                                 const sinter_pair_list *now, size_t q)
{
    size_t h = mix_key(now->key_i[q], now->key_j[q]) & mask;
    while (table[h] != SINTER_NO_PAIR) {
        const uint32_t p = table[h];
        if (before->key_i[p] == now->key_i[q] && before->key_j[p] == now->key_j[q])
            return p;
        h = (h + 1) & mask;
    }
    return SINTER_NO_PAIR;
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
    const long count = (long)now->count;
    const int threads = count < 4096 ? 1 : sinter_threads(nb->ctx);
    if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
        for (long q = 0; q < count; ++q)
            now->from[q] = hash_find(table, mask, before, now, (size_t)q);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        for (long q = 0; q < count; ++q)
            now->from[q] = hash_find(table, mask, before, now, (size_t)q);
    }
    return SINTER_OK;
}

static inline uint32_t key_of(const sinter_pair_list *l, size_t p)
{
    return l->i[p] < l->j[p] ? l->i[p] : l->j[p];
}

/* match_by_runs' two loops, on the threads of the enclosing region or, outside one, on the
 * calling thread (orphaned loops). */
static void runs_loops(sinter_pair_list *now, const sinter_pair_list *before, size_t n,
                       uint32_t *start)
{
    const long pairs = (long)before->count, count = (long)now->count;
    /* each run start p fills start[a] for the particles a from the previous key up */
#pragma omp for schedule(static)
    for (long p = 0; p <= pairs; ++p) {
        const size_t key = p < pairs ? key_of(before, (size_t)p) : n;
        const size_t prev = p > 0 ? (size_t)key_of(before, (size_t)p - 1) + 1 : 0;
        for (size_t a = prev; a <= key && a <= n; ++a)
            start[a] = (uint32_t)p;
    }
#pragma omp for schedule(static)
    for (long q = 0; q < count; ++q) {
        const uint32_t i = now->i[q], j = now->j[q], a = key_of(now, (size_t)q);
        uint32_t found = SINTER_NO_PAIR;
        for (uint32_t p = start[a]; p < start[a + 1]; ++p)
            if (before->i[p] == i && before->j[p] == j) {
                found = p;
                break;
            }
        now->from[q] = found;
    }
}

/*
 * match_pairs for particle-particle lists when the particles kept their indices since the
 * last build (the common case): both lists come from the scan, so their pairs are grouped
 * by the smaller particle index in ascending order, and a pair's old twin is among the old
 * pairs of the same smaller particle, with the same i and j (pairs are oriented by id, and
 * ids stay with the indices). A table of where each particle's old run starts replaces the
 * hash; both passes run on the threads. Returns 0 (nothing written) if the old list's runs do
 * not ascend, and the caller uses the hash.
 */
static int match_by_runs(sinter_neighbors *nb, sinter_pair_list *now,
                         const sinter_pair_list *before, size_t n)
{
    const size_t old_count = before->count;
    for (size_t p = 1; p < old_count; ++p) /* cheap: one pass over the old keys */
        if (key_of(before, p) < key_of(before, p - 1))
            return 0;
    if (sinter_grow(nb->ctx, (void **)&nb->hash, &nb->hash_capacity, n + 2, sizeof(uint32_t)) !=
        SINTER_OK)
        return 0;               /* the hash path reports the failure */
    uint32_t *start = nb->hash; /* old pairs of particle a: [start[a], start[a + 1]) */
    const long count = (long)now->count;
    const int threads = count < 4096 ? 1 : sinter_threads(nb->ctx);
    if (threads > 1) {
#pragma omp parallel num_threads(threads)
        runs_loops(now, before, n, start);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        runs_loops(now, before, n, start);
    }
    return 1;
}

/* 1 if the pairs of l ascend by (key_i, key_j), each pair once. */
static int keys_ascend(const sinter_pair_list *l)
{
    for (size_t p = 1; p < l->count; ++p)
        if (l->key_i[p] < l->key_i[p - 1] ||
            (l->key_i[p] == l->key_i[p - 1] && l->key_j[p] <= l->key_j[p - 1]))
            return 0;
    return 1;
}

/*
 * match_pairs for lists that both ascend by their keys (a particle-wall list is written by
 * particle and then wall, and a particle's id keeps its order while the layout does): one
 * merge of the two lists instead of a hash table (issue 41: the slab's 3 592 front and back
 * wall pairs were hashed at every rebuild). Returns 0 (nothing written) when either list
 * does not ascend, and the caller uses the hash.
 */
static int match_by_merge(sinter_pair_list *now, const sinter_pair_list *before)
{
    if (!keys_ascend(now) || !keys_ascend(before))
        return 0;
    size_t p = 0;
    for (size_t q = 0; q < now->count; ++q) {
        const uint64_t ki = now->key_i[q], kj = now->key_j[q];
        while (p < before->count &&
               (before->key_i[p] < ki || (before->key_i[p] == ki && before->key_j[p] < kj)))
            ++p;
        now->from[q] = p < before->count && before->key_i[p] == ki && before->key_j[p] == kj
                           ? (uint32_t)p
                           : SINTER_NO_PAIR;
    }
    return 1;
}

static void swap_lists(sinter_pair_list *a, sinter_pair_list *b)
{
    sinter_pair_list t = *a;
    *a = *b;
    *b = t;
}

/* fmin and fmax (a NaN loses), inlined: libm calls cost more than the rest of this loop. */
static inline double min_num(double a, double b)
{
    return b < a || a != a ? b : a;
}

static inline double max_num(double a, double b)
{
    return b > a || a != a ? b : a;
}

/* The cell grid of one build: items[start[c] .. start[c+1]) are the particles of cell c. */
typedef struct grid {
    size_t dims[3];
    const uint32_t *start, *items, *cell_of;
    const uint32_t *keep_start, *keep_j; /* the pairs kept at any distance, or NULL */
} grid;

/*
 * Candidate pairs (i, j) with j > i in index of particles lo .. hi-1, in the order of the
 * serial build, into pi/pj (at most cap). Returns the count; *stop is the first particle whose
 * pairs did not all fit (hi when all did), and its pairs are not in the count.
 * Pairs are oriented by persistent id, so that per-pair history (a tangential spring seen
 * from i) survives reordering.
 */
static size_t scan(const grid *g, const sinter_particles *ps, double skin, size_t lo, size_t hi,
                   uint32_t *pi, uint32_t *pj, size_t cap, size_t *stop)
{
    const double *x = ps->x, *r = ps->radius;
    const uint64_t *id = ps->id;
    const size_t *dims = g->dims;
    size_t m = 0;
    for (size_t i = lo; i < hi; ++i) {
        const size_t mark = m;
        const size_t ci = g->cell_of[i];
        const long cx = (long)(ci % dims[0]), cy = (long)((ci / dims[0]) % dims[1]),
                   cz = (long)(ci / (dims[0] * dims[1]));
        const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2], rsi = r[i] + skin;
        const long z0 = cz > 0 ? cz - 1 : 0, z1 = cz + 1 < (long)dims[2] ? cz + 1 : cz;
        const long y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < (long)dims[1] ? cy + 1 : cy;
        const long x0 = cx > 0 ? cx - 1 : 0, x1 = cx + 1 < (long)dims[0] ? cx + 1 : cx;
        for (long z = z0; z <= z1; ++z)
            for (long y = y0; y <= y1; ++y) {
                /* cells x0..x1 of one row are contiguous: one run of items */
                const size_t row = ((size_t)z * dims[1] + (size_t)y) * dims[0];
                const uint32_t k0 = g->start[row + (size_t)x0], k1 = g->start[row + (size_t)x1 + 1];
                if (cap - m >= k1 - k0) {
                    /* room for every candidate of the run: each is written where the next
                     * pair goes and kept by advancing m, without a branch (the verdicts j > i
                     * and "within the cut-off" went either way and were mispredicted about
                     * once a candidate: issue 41, the vibrated beds' rebuilds). The same
                     * pairs in the same order as the loop below. */
                    for (uint32_t k = k0; k < k1; ++k) {
                        const uint32_t j = g->items[k];
                        const double ex = x[3 * j] - xi, ey = x[3 * j + 1] - yi,
                                     ez = x[3 * j + 2] - zi;
                        const double cut = rsi + r[j];
                        /* oriented by id with a mask (no branch on the ids' order) */
                        const uint32_t ii = (uint32_t)i,
                                       flip = (ii ^ j) & ((uint32_t)0 - (uint32_t)(id[j] < id[i]));
                        pi[m] = ii ^ flip;
                        pj[m] = j ^ flip;
                        m += (size_t)((j > i) & (ex * ex + ey * ey + ez * ez < cut * cut));
                    }
                    continue;
                }
                for (uint32_t k = k0; k < k1; ++k) {
                    const uint32_t j = g->items[k];
                    if (j <= i)
                        continue;
                    const double ex = x[3 * j] - xi, ey = x[3 * j + 1] - yi, ez = x[3 * j + 2] - zi;
                    const double cut = rsi + r[j];
                    if (ex * ex + ey * ey + ez * ez < cut * cut) {
                        if (m == cap) {
                            *stop = i;
                            return mark;
                        }
                        const int keep = id[i] < id[j];
                        pi[m] = keep ? (uint32_t)i : j;
                        pj[m] = keep ? j : (uint32_t)i;
                        ++m;
                    }
                }
            }
        /* kept pairs beyond the cutoff (the same test as above: those within were found) */
        for (uint32_t k = g->keep_start ? g->keep_start[i] : 0;
             g->keep_start && k < g->keep_start[i + 1]; ++k) {
            const uint32_t j = g->keep_j[k];
            const double ex = x[3 * j] - xi, ey = x[3 * j + 1] - yi, ez = x[3 * j + 2] - zi;
            const double cut = rsi + r[j];
            if (ex * ex + ey * ey + ez * ez < cut * cut)
                continue;
            if (m == cap) {
                *stop = i;
                return mark;
            }
            const int keep = id[i] < id[j];
            pi[m] = keep ? (uint32_t)i : j;
            pj[m] = keep ? j : (uint32_t)i;
            ++m;
        }
    }
    *stop = hi;
    return m;
}

/* Pairs of particles lo .. hi-1 appended to the list, growing it as needed (serial). */
static sinter_status scan_append(sinter_neighbors *nb, const grid *g, const sinter_particles *ps,
                                 size_t lo, size_t hi)
{
    sinter_pair_list *l = &nb->pp;
    sinter_status st = reserve_pairs(nb->ctx, l, l->count + 1024);
    while (st == SINTER_OK && lo < hi) {
        size_t stop;
        l->count += scan(g, ps, nb->skin + nb->reach, lo, hi, l->i + l->count, l->j + l->count,
                         l->capacity - l->count, &stop);
        if (stop < hi) /* the pairs of particle `stop` did not fit in the room left */
            st = reserve_pairs(nb->ctx, l, 2 * l->capacity);
        lo = stop;
    }
    return st;
}

/* The bounding box of particles [a, b) and their largest radius into q (lo[3], hi[3], rmax);
 * a >= 1 particle. */
static void bounds_range(const double *x, const double *r, size_t a, size_t b, double q[7])
{
    for (int d = 0; d < 3; ++d)
        q[d] = q[3 + d] = x[3 * a + d];
    q[6] = 0.0;
    for (size_t i = a; i < b; ++i) {
        for (int d = 0; d < 3; ++d) {
            q[d] = min_num(q[d], x[3 * i + d]);
            q[3 + d] = max_num(q[3 + d], x[3 * i + d]);
        }
        q[6] = max_num(q[6], r[i]);
    }
}

/* The cells of particles [a, b) into cell_of, counted per cell into count[0 .. ncell). */
static void count_cells(const double *x, const double lo[3], double inv, const size_t dims[3],
                        size_t a, size_t b, uint32_t *cell_of, uint32_t *count, size_t ncell)
{
    memset(count, 0, ncell * sizeof(uint32_t));
    for (size_t i = a; i < b; ++i) {
        size_t c[3];
        for (int d = 0; d < 3; ++d) {
            /* >= 0, possibly +inf (overflowed difference) or NaN (inf * 0): clamp first */
            const double q = (x[3 * i + d] - lo[d]) * inv;
            c[d] = q < (double)dims[d] ? (size_t)q : dims[d] - 1;
        }
        cell_of[i] = (uint32_t)((c[2] * dims[1] + c[1]) * dims[0] + c[0]);
        count[cell_of[i]]++;
    }
}

/* Particles [a, b) into their cells' next slots (slot: the range's first slot per cell). */
static void place_items(uint32_t *items, const uint32_t *cell_of, uint32_t *slot, size_t a,
                        size_t b)
{
    for (size_t i = a; i < b; ++i)
        items[slot[cell_of[i]]++] = (uint32_t)i;
}

/* Particle-particle candidates: particles binned in cells of side >= the largest cutoff. */
static sinter_status build_pp(sinter_neighbors *nb, const sinter_particles *ps)
{
    sinter_ctx *ctx = nb->ctx;
    const size_t n = ps->count;
    const size_t expected = nb->pp.count; /* the last build's count: size of the scratch */
    nb->pp.count = 0;
    if (n < 2)
        return SINTER_OK;
    const double *x = ps->x, *r = ps->radius;
    /* the bounding box and largest radius, in ranges on the threads (a minimum and a maximum
     * do not depend on the order) */
    enum { RANGES_MAX = 64 };
    const int threads = n < 16384 ? 1 : sinter_threads(ctx);
    const int ranges = threads < RANGES_MAX ? threads : RANGES_MAX;
    double part[RANGES_MAX][7];
    if (ranges > 1) {
#pragma omp parallel for num_threads(ranges) schedule(static, 1)
        for (int t = 0; t < ranges; ++t)
            bounds_range(x, r, n * (size_t)t / (size_t)ranges, n * (size_t)(t + 1) / (size_t)ranges,
                         part[t]);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        bounds_range(x, r, 0, n, part[0]);
    }
    double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]}, rmax = 0.0;
    for (int t = 0; t < ranges; ++t) {
        for (int d = 0; d < 3; ++d) {
            lo[d] = min_num(lo[d], part[t][d]);
            hi[d] = max_num(hi[d], part[t][3 + d]);
        }
        rmax = max_num(rmax, part[t][6]);
    }
    /* Finite inputs can still overflow: a span beyond DBL_MAX (particles near +-1e308)
     * or a cell of radius ~1e308 counts as DBL_MAX, so every quotient below is finite
     * or +inf and the loop ends (the cell grows until the count fits). */
    double cell = fmin(2.0 * rmax + (nb->skin + nb->reach), DBL_MAX), span[3];
    for (int d = 0; d < 3; ++d)
        span[d] = fmin(hi[d] - lo[d], DBL_MAX);
    /* Keep the grid at most ~8 cells per particle (sparse scenes). 8, not 2: a shallow bed shaken
     * to a few times its height (the vibrated beds of issue 41: 1796 spheres across 0.3 m, one cell
     * deep) fits cells of the cut-off in 4-8 per particle; at 2 the cells grew 1.5 times and each
     * sphere tested 2.3 times the candidates. */
    size_t dims[3];
    for (;;) {
        double total = 1.0;
        int too_many = 0;
        for (int d = 0; d < 3; ++d) {
            const double cells = floor(span[d] / cell) + 1.0;
            if (!(cells <= 4e6) || total * cells > 8.0 * (double)n + 64.0) {
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
    /* the counting sort's ranges, each with a count per cell: at most about four counts a
     * particle in all (the same grid and the same order from any number of them) */
    int sorters = ranges;
    while (sorters > 1 && (size_t)sorters * ncell > 4 * n + 64)
        sorters /= 2;
    sinter_status st =
        sinter_grow(ctx, (void **)&nb->cell_start, &nb->cell_capacity, ncell + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->cell_items, &nb->items_capacity, 2 * n,
                         sizeof(uint32_t));
    /* each range's count of particles per cell, then where its particles of each cell go */
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->cell_counts, &nb->cell_counts_capacity,
                         (size_t)sorters * ncell + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    uint32_t *start = nb->cell_start, *items = nb->cell_items, *cell_of = nb->cell_items + n;
    const double inv = 1.0 / cell;
    if (sorters > 1) {
#pragma omp parallel for num_threads(sorters) schedule(static, 1)
        for (int t = 0; t < sorters; ++t)
            count_cells(x, lo, inv, dims, n * (size_t)t / (size_t)sorters,
                        n * (size_t)(t + 1) / (size_t)sorters, cell_of,
                        nb->cell_counts + (size_t)t * ncell, ncell);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        count_cells(x, lo, inv, dims, 0, n, cell_of, nb->cell_counts, ncell);
    }
    /* counting sort: items[start[c] .. start[c+1]) are the particles of cell c, by index
     * (the ranges in order within a cell) */
    uint32_t next = 0;
    for (size_t c = 0; c < ncell; ++c) {
        start[c] = next;
        for (int t = 0; t < sorters; ++t) {
            uint32_t *count = nb->cell_counts + (size_t)t * ncell + c;
            const uint32_t k = *count;
            *count = next; /* the range's first slot in cell c */
            next += k;
        }
    }
    start[ncell] = next;
    if (sorters > 1) {
#pragma omp parallel for num_threads(sorters) schedule(static, 1)
        for (int t = 0; t < sorters; ++t)
            place_items(items, cell_of, nb->cell_counts + (size_t)t * ncell,
                        n * (size_t)t / (size_t)sorters, n * (size_t)(t + 1) / (size_t)sorters);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        place_items(items, cell_of, nb->cell_counts, 0, n);
    }
    const int kept = nb->keep_count > 0;
    const grid g = {
        {dims[0], dims[1], dims[2]}, start, items, cell_of, kept ? nb->keep_start : NULL,
        kept ? nb->keep_j : NULL};

    /* from 1024 particles (issue 41: the vibrated beds' 1 796 spheres rebuild every 40-50
     * steps, and the other thread waited through the scan) */
    const int scanners = n < 1024 ? 1 : sinter_threads(ctx);
    if (scanners <= 1)
        return scan_append(nb, &g, ps, 0, n);
    /*
     * Threads: each scans a contiguous range of particles into its own segment of a scratch
     * buffer sized from the last build; the segments are appended in range order (the serial
     * order), and a range whose segment filled up is finished serially. The list is the same
     * for any number of threads.
     */
    enum { MAX_CHUNKS = 64 };
    const int chunks = scanners < MAX_CHUNKS ? scanners : MAX_CHUNKS;
    const size_t guess = (expected > 0 ? expected + expected / 4 : 4 * n) / (size_t)chunks + 1024;
    st = sinter_grow(ctx, (void **)&nb->scan, &nb->scan_capacity, 2 * guess * (size_t)chunks,
                     sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    const size_t seg = nb->scan_capacity / (2 * (size_t)chunks);
    size_t found[MAX_CHUNKS], stop[MAX_CHUNKS];
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
    for (int t = 0; t < chunks; ++t) {
        const size_t a = n * (size_t)t / (size_t)chunks, b = n * (size_t)(t + 1) / (size_t)chunks;
        uint32_t *pi = nb->scan + 2 * seg * (size_t)t;
        found[t] = scan(&g, ps, nb->skin + nb->reach, a, b, pi, pi + seg, seg, &stop[t]);
    }
    for (int t = 0; t < chunks && st == SINTER_OK; ++t) {
        st = reserve_pairs(ctx, &nb->pp, nb->pp.count + found[t]);
        if (st != SINTER_OK)
            break;
        const uint32_t *pi = nb->scan + 2 * seg * (size_t)t;
        if (found[t] > 0) { /* (no pairs at all: the list's arrays may not exist yet) */
            memcpy(nb->pp.i + nb->pp.count, pi, found[t] * sizeof(uint32_t));
            memcpy(nb->pp.j + nb->pp.count, pi + seg, found[t] * sizeof(uint32_t));
        }
        nb->pp.count += found[t];
        const size_t b = n * (size_t)(t + 1) / (size_t)chunks;
        if (stop[t] < b)
            st = scan_append(nb, &g, ps, stop[t], b);
    }
    return st;
}

/* With ghosts (ghosts/ghosts.h): a pair is kept when its first end, the one of smaller id, is
 * owned; ghost-ghost pairs go, and of the two copies of a pair across a periodic face (owned i
 * with the image of j, the image of i with owned j) the one seen from the smaller id stays. */
static int owned_image(const sinter_neighbors *nb, size_t i, size_t owned)
{
    return i >= nb->image_first && i - nb->image_first < nb->image_count &&
           nb->image_owner[i - nb->image_first] < owned;
}

static void drop_ghost_pairs(const sinter_neighbors *nb, sinter_pair_list *l, size_t owned,
                             int both_sides)
{
    size_t m = 0;
    for (size_t p = 0; p < l->count; ++p)
        if (l->i[p] < owned ||
            (both_sides && l->j[p] < owned && !owned_image(nb, l->i[p], owned))) {
            l->i[m] = l->i[p];
            l->j[m] = l->j[p];
            ++m;
        }
    l->count = m;
}

/* Persistent ids of both ends of every pair (the keys that carry history across builds). */
static void fill_keys(sinter_pair_list *l, const uint64_t *id, int threads)
{
    const long count = (long)l->count;
    if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
        for (long p = 0; p < count; ++p) {
            l->key_i[p] = id[l->i[p]];
            l->key_j[p] = id[l->j[p]];
        }
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        for (long p = 0; p < count; ++p) {
            l->key_i[p] = id[l->i[p]];
            l->key_j[p] = id[l->j[p]];
        }
    }
}

/* The particle-wall candidates of particles [a, b) when every wall is a plane (its distance
 * inline): the walls closer than r + skin, counted. */
static inline size_t count_pw(const sinter_walls *walls, const double *x, const double *r,
                              double skin, size_t a, size_t b)
{
    size_t count = 0;
    for (size_t i = a; i < b; ++i)
        for (size_t k = 0; k < walls->count; ++k)
            count += sinter_plane_distance(&walls->wall[k], x + 3 * i) < r[i] + skin;
    return count;
}

/* count_pw for walls of any kind: each verdict kept in near (i nw + k), a mesh's search
 * started from the triangle of the particle's last (hint, i nw + k; the same bits from any)
 * and ended at r + skin (sinter_mesh_within: a sphere farther in front of its last triangle's
 * plane is not searched out to the mesh). */
static size_t count_pw_kinds(const sinter_walls *walls, const double *x, const double *r,
                             double skin, size_t a, size_t b, uint8_t *near, uint32_t *hint)
{
    const size_t nw = walls->count;
    size_t count = 0;
    for (size_t i = a; i < b; ++i)
        for (size_t k = 0; k < nw; ++k) {
            const sinter_wall *w = &walls->wall[k];
            near[i * nw + k] = (uint8_t)(w->kind == SINTER_WALL_MESH
                                             ? sinter_wall_mesh_within(w, x + 3 * i, r[i] + skin,
                                                                       hint + i * nw + k)
                                             : sinter_wall_distance(w, x + 3 * i) < r[i] + skin);
            count += near[i * nw + k];
        }
    return count;
}

/* The candidates of particles [a, b) written from m on (planes: every wall a plane, its
 * distance inline; else the counting pass's verdicts, near). */
static inline void put_pw(sinter_pair_list *l, const sinter_walls *walls,
                          const sinter_particles *ps, double skin, size_t a, size_t b, size_t m,
                          int planes, const uint8_t *near)
{
    const double *x = ps->x, *r = ps->radius;
    for (size_t i = a; i < b; ++i)
        for (size_t k = 0; k < walls->count; ++k)
            if (planes ? sinter_plane_distance(&walls->wall[k], x + 3 * i) < r[i] + skin
                       : near[i * walls->count + k]) {
                l->i[m] = (uint32_t)i;
                l->j[m] = (uint32_t)k;
                l->key_i[m] = ps->id[i];
                l->key_j[m] = k;
                ++m;
            }
}

/* count_pw (planes) or count_pw_kinds over range t of `ranges` equal ranges of n particles. */
static size_t count_pw_range(const sinter_walls *walls, const double *x, const double *r,
                             double skin, size_t n, int ranges, int t, int planes, uint8_t *near,
                             uint32_t *hint)
{
    const size_t a = n * (size_t)t / (size_t)ranges, b = n * (size_t)(t + 1) / (size_t)ranges;
    return planes ? count_pw(walls, x, r, skin, a, b)
                  : count_pw_kinds(walls, x, r, skin, a, b, near, hint);
}

/* put_pw over range t of `ranges` equal ranges of n particles, from m on. */
static void put_pw_range(sinter_pair_list *l, const sinter_walls *walls, const sinter_particles *ps,
                         double skin, size_t n, int ranges, int t, size_t m, int planes,
                         const uint8_t *near)
{
    const size_t a = n * (size_t)t / (size_t)ranges, b = n * (size_t)(t + 1) / (size_t)ranges;
    if (planes)
        put_pw(l, walls, ps, skin, a, b, m, 1, NULL);
    else
        put_pw(l, walls, ps, skin, a, b, m, 0, near);
}

/* Particle-wall candidates, by particle and then wall: counted in ranges of particles on the
 * threads, then written from each range's offset (the order of one thread). */
static sinter_status build_pw(sinter_neighbors *nb, const sinter_particles *ps,
                              const sinter_walls *walls)
{
    nb->pw.count = 0;
    if (walls == NULL || walls->count == 0)
        return SINTER_OK;
    enum { RANGES_MAX = 64 };
    const size_t n = ps->count - ps->ghost_count, nw = walls->count; /* no ghost wall contacts */
    const double *x = ps->x, *r = ps->radius, skin = nb->skin;
    int planes = 1; /* only planes: their distance inline, without the kind's test */
    for (size_t k = 0; k < nw; ++k)
        planes &= walls->wall[k].kind == SINTER_WALL_PLANE;
    int meshes = 0; /* hints only for meshes (the other kinds' closest point is closed-form) */
    for (size_t k = 0; k < nw; ++k)
        meshes |= walls->wall[k].kind == SINTER_WALL_MESH;
    if (!planes) {
        const size_t had = nb->wall_hint_capacity;
        sinter_status st =
            sinter_grow(nb->ctx, (void **)&nb->wall_near, &nb->wall_near_capacity, n * nw + 1, 1);
        if (st == SINTER_OK && meshes)
            st = sinter_grow(nb->ctx, (void **)&nb->wall_hint, &nb->wall_hint_capacity, n * nw + 1,
                             sizeof(uint32_t));
        if (st != SINTER_OK)
            return st;
        if (nb->wall_hint_capacity != had) /* no hints yet (stale ones cost time only) */
            memset(nb->wall_hint, 0xff, nb->wall_hint_capacity * sizeof(uint32_t));
    }
    uint8_t *near = nb->wall_near;
    uint32_t *hint = nb->wall_hint; /* NULL without a mesh: not read */
    const int threads = n * nw < 16384 ? 1 : sinter_threads(nb->ctx);
    const int ranges = threads < RANGES_MAX ? threads : RANGES_MAX;
    size_t offset[RANGES_MAX + 1] = {0};
    if (ranges > 1) {
#pragma omp parallel for num_threads(ranges) schedule(static, 1)
        for (int t = 0; t < ranges; ++t)
            offset[t + 1] = count_pw_range(walls, x, r, skin, n, ranges, t, planes, near, hint);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        offset[1] = count_pw_range(walls, x, r, skin, n, 1, 0, planes, near, hint);
    }
    for (int t = 0; t < ranges; ++t)
        offset[t + 1] += offset[t];
    sinter_pair_list *l = &nb->pw;
    const sinter_status st = reserve_pairs(nb->ctx, l, offset[ranges] + 1);
    if (st != SINTER_OK)
        return st;
    if (ranges > 1) {
#pragma omp parallel for num_threads(ranges) schedule(static, 1)
        for (int t = 0; t < ranges; ++t)
            put_pw_range(l, walls, ps, skin, n, ranges, t, offset[t], planes, near);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        put_pw_range(l, walls, ps, skin, n, 1, 0, offset[0], planes, near);
    }
    l->count = offset[ranges];
    return SINTER_OK;
}

/* Per-particle lists of pairs, in ascending pair index (a stable counting sort). */
sinter_status sinter_pairs_adjacency(sinter_ctx *ctx, sinter_pair_list *l, size_t n)
{
    if (l->adj_build != 0 && l->adj_build == l->build_id)
        return SINTER_OK;
    l->adj_build = 0;
    sinter_status st =
        sinter_grow(ctx, (void **)&l->adj_start, &l->adj_start_capacity, n + 2, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&l->adj_pair, &l->adj_pair_capacity, 2 * l->count + 1,
                         sizeof(uint32_t));
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
    l->adj_build = l->build_id;
    return SINTER_OK;
}

sinter_status sinter_neighbors_keep(sinter_neighbors *nb, const sinter_particles *ps,
                                    const uint32_t *ki, const uint32_t *kj, size_t count)
{
    nb->keep_count = 0;
    if (count == 0)
        return SINTER_OK;
    const size_t n = ps->count;
    sinter_status st = sinter_grow(nb->ctx, (void **)&nb->keep_start, &nb->keep_start_capacity,
                                   n + 2, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(nb->ctx, (void **)&nb->keep_j, &nb->keep_j_capacity, count + 1,
                         sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    uint32_t *start = nb->keep_start;
    memset(start, 0, (n + 2) * sizeof(uint32_t));
    for (size_t k = 0; k < count; ++k) /* counts, shifted by 2: then starts shifted by 1 */
        if (ki[k] < n && kj[k] < n && ki[k] != kj[k])
            start[(ki[k] < kj[k] ? ki[k] : kj[k]) + 2]++;
    for (size_t a = 2; a < n + 2; ++a)
        start[a] += start[a - 1];
    for (size_t k = 0; k < count; ++k) /* in the given order within a particle */
        if (ki[k] < n && kj[k] < n && ki[k] != kj[k]) {
            const uint32_t a = ki[k] < kj[k] ? ki[k] : kj[k], b = ki[k] < kj[k] ? kj[k] : ki[k];
            nb->keep_j[start[a + 1]++] = b;
        }
    nb->keep_count = start[n];
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
    nb->pp.build_id = nb->pw.build_id = 0;
    sinter_status st = build_pp(nb, ps);
    if (st == SINTER_OK && ps->ghost_count > 0)
        drop_ghost_pairs(nb, &nb->pp, ps->count - ps->ghost_count, nb->both_sides);
    if (st == SINTER_OK)
        fill_keys(&nb->pp, ps->id, nb->pp.count < 4096 ? 1 : sinter_threads(ctx));
    if (st == SINTER_OK)
        st = build_pw(nb, ps, walls);
    nb->pp.canonical = nb->pw.canonical = 0;
    if (st == SINTER_OK && nb->canonical) /* the reproducible mode's order */
        st = sinter_pairs_sort_by_keys(ctx, &nb->pp, &nb->order_scratch,
                                       &nb->order_scratch_capacity);
    if (st == SINTER_OK && nb->canonical)
        st = sinter_pairs_sort_by_keys(ctx, &nb->pw, &nb->order_scratch,
                                       &nb->order_scratch_capacity);
    if (st == SINTER_OK)
        st = reserve_pairs(ctx, &nb->pp, 1);
    if (st == SINTER_OK)
        st = reserve_pairs(ctx, &nb->pw, 1);
    /* the last build's indices still name the same particles: match by runs */
    const int same_layout = nb->built && nb->layout_generation == ps->layout_generation;
    if (st == SINTER_OK && !(same_layout && nb->old_pp.count > 0 &&
                             match_by_runs(nb, &nb->pp, &nb->old_pp, ps->count)))
        st = match_pairs(nb, &nb->pp, &nb->old_pp);
    if (st == SINTER_OK && !match_by_merge(&nb->pw, &nb->old_pw))
        st = match_pairs(nb, &nb->pw, &nb->old_pw);
    const size_t nw = walls ? walls->count : 0;
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->x_ref, &nb->ref_capacity, 3 * ps->count + 3,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&nb->wall_ref, &nb->wall_ref_capacity, 4 * nw + 4,
                         sizeof(double));
    if (st != SINTER_OK) {
        nb->built = 0;
        return st;
    }
    if (ps->count > 0) /* an empty set (a subdomain that owns nothing) has no arrays */
        memcpy(nb->x_ref, ps->x, 3 * ps->count * sizeof(double));
    for (size_t k = 0; k < nw; ++k)
        sinter_wall_reference(&walls->wall[k], nb->wall_ref + 4 * k);
    nb->wall_count = nw;
    nb->layout_generation = ps->layout_generation;
    set_bound(nb, ps, 0.0); /* nothing moved since */
    nb->pp.build_id = sinter_unique_id();
    nb->pw.build_id = sinter_unique_id();
    nb->built = 1;
    return SINTER_OK;
}
