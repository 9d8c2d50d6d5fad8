/* Active contacts and their geometry (seed 000 eq. 7-12; seed 003 eq. 4-5, 33-34). */
#include <math.h>
#include <string.h>

#include "contacts.h"
#include "contact/chunks.h"
#include "core/ranges_run.h"
#include "core/stream_store.h"

#ifdef _OPENMP
#include <omp.h>
#endif

static const double PI = 3.14159265358979323846;

void sinter_contact_radii(const sinter_contact_list *c, double *a)
{
    for (size_t k = 0; k < c->count; ++k)
        a[k] = sqrt(c->area[k] / PI);
}

void sinter_contact_list_free(sinter_ctx *ctx, sinter_contact_list *c)
{
    void *arrays[] = {c->i,
                      c->j,
                      c->pair,
                      c->n,
                      c->delta,
                      c->dist,
                      c->area,
                      c->branch,
                      c->pair_to_contact,
                      c->chunk_scratch,
                      c->touch,
                      c->fill_scratch,
                      c->ended,
                      c->gaps,
                      c->hint,
                      c->hint_spare,
                      c->cert,
                      c->cert_spare};
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); ++k)
        sinter_free(ctx, arrays[k]);
    memset(c, 0, sizeof(*c));
}

static sinter_status reserve(sinter_ctx *ctx, sinter_contact_list *c, size_t need)
{
    if (need <= c->capacity)
        return SINTER_OK;
    size_t cap = c->capacity ? c->capacity : 256;
    while (cap < need)
        cap *= 2;
    void **slots[] = {(void **)&c->i,    (void **)&c->j,     (void **)&c->pair,
                      (void **)&c->n,    (void **)&c->delta, (void **)&c->dist,
                      (void **)&c->area, (void **)&c->branch};
    const size_t elem[] = {4, 4, 4, 3 * sizeof(double), 8, 8, 8, 8};
    for (size_t k = 0; k < sizeof(slots) / sizeof(slots[0]); ++k) {
        void *q = sinter_realloc_array(ctx, *slots[k], cap, elem[k]);
        if (q == NULL)
            return sinter_last_status(ctx);
        *slots[k] = q;
    }
    c->capacity = cap;
    return SINTER_OK;
}

int sinter_threads_allowed(const sinter_ctx *ctx)
{
#ifdef _OPENMP
    return ctx->threads > 0 ? ctx->threads : omp_get_max_threads();
#else
    (void)ctx;
    return 1;
#endif
}

int sinter_threads(const sinter_ctx *ctx)
{
    return ctx->step_threads > 0 ? ctx->step_threads : sinter_threads_allowed(ctx);
}

/* 1 if spheres i and j overlap (centres closer than the sum of the radii, and apart). */
static inline int overlapping(const double *x, const double *r, uint32_t i, uint32_t j)
{
    const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                 ez = x[3 * j + 2] - x[3 * i + 2];
    const double d2 = ex * ex + ey * ey + ez * ez, rs = r[i] + r[j];
    return d2 < rs * rs && d2 != 0.0;
}

/* 1 if pair p is in contact (the test of the fill pass, without its arithmetic): overlapping,
 * or held by c->held (a bond that holds in tension) at any distance but 0. */
static inline int touching(const sinter_contact_list *c, const sinter_pair_list *pairs,
                           const double *x, const double *r, size_t p)
{
    const uint32_t i = pairs->i[p], j = pairs->j[p];
    const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                 ez = x[3 * j + 2] - x[3 * i + 2];
    const double d2 = ex * ex + ey * ey + ez * ez, rs = r[i] + r[j];
    if (d2 < rs * rs)
        return d2 != 0.0;
    return c->held != NULL && c->held[c->held_stride * p] != 0.0 && d2 != 0.0;
}

/* Most threads the threaded search splits its pairs for. */
enum { MAX_CHUNKS = 256 };

/* What a fill pass learns for the partition (chunks.h): whether the contacts' smaller
 * particle indices ascend, and the first and last of them. */
typedef struct fill_part {
    int ascending, any;
    uint32_t first, last;
} fill_part;

/* Geometry of contact m from its particles' centres (sinter_pp_geometry; a^2 = R_i^2 - L_i^2,
 * seed 000 eq. 7, 11). */
static inline void put_geometry(sinter_contact_list *c, const double *x, const double *r, size_t m,
                                uint32_t i, uint32_t j)
{
    const sinter_pp_geom g = sinter_pp_geometry(x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                                                x[3 * j + 2] - x[3 * i + 2], r[i], r[j]);
    const double a2_raw = r[i] * r[i] - g.li * g.li, a2 = a2_raw > 0.0 ? a2_raw : 0.0;
    c->n[3 * m] = g.nx;
    c->n[3 * m + 1] = g.ny;
    c->n[3 * m + 2] = g.nz;
    c->delta[m] = g.delta;
    c->dist[m] = g.d;
    c->area[m] = PI * a2; /* the contact radius sqrt(a2) is derived on demand */
    c->branch[m] = g.li;
}

/* Contacts among pairs [lo, hi), written from index m on into ci, cj, cpair (the list's own
 * arrays, or a scratch copy: fill_segments); returns the next free index. With `touch` (the
 * counting pass's verdict per pair, from the same arithmetic) the pairs not in contact are
 * skipped without reading positions. `geometry` 0 writes the indices only. */
static inline __attribute__((always_inline)) size_t
fill_into(sinter_contact_list *c, uint32_t *restrict ci, uint32_t *restrict cj,
          uint32_t *restrict cpair, const sinter_pair_list *pairs, const sinter_particles *ps,
          size_t lo, size_t hi, size_t m, fill_part *part, const uint8_t *touch, int geometry)
{
    const double *restrict x = ps->x, *restrict r = ps->radius;
    const uint32_t *restrict pi = pairs->i, *restrict pj = pairs->j;
    uint32_t *restrict to_contact = c->pair_to_contact;
    const size_t m0 = m;
    uint32_t prev = 0;
    int ascending = 1;
    /* without a verdict array or held bonds, the plain overlap test, its inputs in registers
     * (c->held was read again at every pair; issue 41: a shaken bed's thousands of candidates
     * a step, a few dozen in contact) */
    const int plain = touch == NULL && c->held == NULL;
    for (size_t p = lo; p < hi; ++p) {
        const uint32_t i = pi[p], j = pj[p];
        if (plain           ? !overlapping(x, r, i, j)
            : touch != NULL ? !touch[p]
                            : !touching(c, pairs, x, r, p)) {
            to_contact[p] = SINTER_NO_PAIR;
            continue;
        }
        ci[m] = i;
        cj[m] = j;
        cpair[m] = (uint32_t)p;
        to_contact[p] = (uint32_t)m;
        if (geometry)
            put_geometry(c, x, r, m, i, j);
        const uint32_t key = i < j ? i : j; /* the particle whose scan found the pair */
        ascending &= key >= prev;
        prev = key;
        ++m;
    }
    part->ascending = ascending;
    part->any = m > m0;
    part->first = m > m0 ? (ci[m0] < cj[m0] ? ci[m0] : cj[m0]) : 0;
    part->last = prev;
    return m;
}

static size_t fill_pp_full(sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps, size_t lo, size_t hi, size_t m,
                           fill_part *part, const uint8_t *touch)
{
    return fill_into(c, c->i, c->j, c->pair, pairs, ps, lo, hi, m, part, touch, 1);
}

static size_t fill_pp_lean(sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps, size_t lo, size_t hi, size_t m,
                           fill_part *part, const uint8_t *touch)
{
    return fill_into(c, c->i, c->j, c->pair, pairs, ps, lo, hi, m, part, touch, 0);
}

/* The ordering findings of two consecutive stretches of contacts as one. */
static fill_part join_parts(fill_part a, fill_part b)
{
    fill_part j;
    j.ascending = a.ascending && b.ascending && (!a.any || !b.any || b.first >= a.last);
    j.any = a.any || b.any;
    j.first = a.any ? a.first : b.first;
    j.last = b.any ? b.last : a.last;
    return j;
}

/*
 * A lean search over the pairs the list was last found among (issue 9: a packed bed keeps its
 * contacts step after step, and at a million particles writing the same 16 bytes per contact
 * again costs more than checking them): the pairs from lo on are tested, and each verdict
 * compared with what pair_to_contact records, without writing. Stops at the first pair whose
 * verdict differs (a new contact, an ended one, or a contact that would now sit at another
 * index) and returns it (hi when all agree). *start is the index the first contact must hold
 * (0 for the whole list), or SIZE_MAX to accept the one it holds (a range of a threaded
 * search), and returns it; *checked counts the contacts confirmed; *part as fill_into.
 */
static size_t verify_range(const sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps, size_t lo, size_t hi, size_t *start,
                           size_t *checked, fill_part *part)
{
    const double *restrict x = ps->x, *restrict r = ps->radius;
    const uint32_t *restrict pi = pairs->i, *restrict pj = pairs->j;
    const uint32_t *restrict to_contact = c->pair_to_contact;
    size_t m = *start, k = 0, p = lo;
    uint32_t prev = 0, first = 0;
    int ascending = 1;
    for (; p < hi; ++p) {
        const uint32_t was = to_contact[p];
        if (!touching(c, pairs, x, r, p)) {
            if (was != SINTER_NO_PAIR)
                break;
            continue;
        }
        if (m == SIZE_MAX && was != SINTER_NO_PAIR)
            m = was; /* the range's first contact: where the list holds it */
        if ((size_t)was != m)
            break;
        const uint32_t key = pi[p] < pj[p] ? pi[p] : pj[p];
        if (k == 0) {
            first = key;
            *start = m;
        }
        ascending &= key >= prev;
        prev = key;
        ++m;
        ++k;
    }
    *checked = k;
    part->ascending = ascending;
    part->any = k > 0;
    part->first = first;
    part->last = prev;
    return p;
}

/* Ranges of pairs for a threaded pass over pairs [p0, n) on `threads` threads. */
typedef struct pair_ranges {
    int count;                 /* ranges */
    int team;                  /* threads of the loop over them, schedule(static) */
    size_t lo[MAX_CHUNKS + 1]; /* range t: pairs [lo[t], lo[t + 1]) */
} pair_ranges;

/* Fewest pairs a range of a threaded fill is given (fill_ranges). */
enum { FILL_RANGE_MIN = 4096 };

/* Fewest candidate pairs a particle-particle search runs on threads for (find_pp and the
 * deferred search's scan; the same list either way). 1024: the vibrated beds' 1 796 spheres
 * have fewer than 4096 pairs, and on two threads the worker waited through the search, the
 * largest single-thread stage of their steps (issue 41: the main thread's share of the step
 * 0.80, RESULTS.md "pairs proven apart, the heat's pace and the pair search on two threads"). */
enum { SEARCH_THREADED_MIN = 1024 };

/* The first k in [lo, hi) whose smaller index min(a[k], b[k]) is at least p (they ascend in
 * the neighbour build's pair order; any k in [lo, hi] when they do not). */
static size_t first_with_smaller_index(const uint32_t *a, const uint32_t *b, size_t lo, size_t hi,
                                       size_t p)
{
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if ((a[mid] < b[mid] ? a[mid] : b[mid]) < p)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The first pair in [from, n) whose smaller particle index is at least p. */
static size_t first_pair_of(const sinter_pair_list *pairs, size_t from, size_t p)
{
    return first_with_smaller_index(pairs->i, pairs->j, from, pairs->count, p);
}

/*
 * The ranges of a threaded pass over pairs [p0, n): where c has a partition for these
 * particles, the pairs of its particle ranges, on its law's team (contact/chunks.h), so that
 * each thread reads the positions of the particles it integrates and sums, not the other
 * core's (issue 9); else `ranges` equal ranges, contiguous per thread.
 */
static pair_ranges pass_ranges(const sinter_contact_list *c, const sinter_pair_list *pairs,
                               size_t particles, size_t p0, int threads, int ranges)
{
    pair_ranges r;
    const size_t n = pairs->count;
    const sinter_chunks *k = &c->chunks;
    if (k->count > 0 && k->count <= MAX_CHUNKS && k->plo[k->count] == particles) {
        r.count = k->count;
        r.team = threads < k->count ? threads : k->count;
        r.lo[0] = p0;
        for (int s = 1; s < k->count; ++s)
            r.lo[s] = first_pair_of(pairs, r.lo[s - 1], k->plo[s]);
        r.lo[k->count] = n;
        return r;
    }
    r.count = ranges;
    r.team = threads < ranges ? threads : ranges;
    for (int t = 0; t <= ranges; ++t)
        r.lo[t] = p0 + (n - p0) * (size_t)t / (size_t)ranges;
    return r;
}

/*
 * A lean list on threads in one pass over the pairs from p0 on (the contacts before pair p0,
 * m0 of them, stay), in ranges r (pass_ranges): each thread fills its ranges of pairs into a
 * scratch copy at the range's own start (a range has at most as many contacts as pairs), then
 * copies its contacts to their place in the list and points their pairs at them: the same
 * list, in the same order, as one thread makes, without a counting pass. With `verify` (the
 * list holds the contacts of these pairs from the last search; p0 = m0 = 0), each range is
 * first checked against the list (verify_range) and filled from its first change only; a
 * range whose contacts all agree and still start at the same index is left as it is (no
 * write at all when none changed).
 * *change_pair and *change_contact tell where the list changed (sinter_contacts_changed;
 * SIZE_MAX: nowhere). Returns the number of contacts.
 */
static size_t fill_segments(sinter_contact_list *c, const sinter_pair_list *pairs,
                            const sinter_particles *ps, size_t m0, const pair_ranges *r, int verify,
                            fill_part *part, size_t *change_pair, size_t *change_contact)
{
    const size_t n = pairs->count;
    const int chunks = r->count;
    uint32_t *si = c->fill_scratch, *sj = si + n, *sp = sj + n;
    size_t found[MAX_CHUNKS], offset[MAX_CHUNKS + 1];
    size_t start[MAX_CHUNKS], checked[MAX_CHUNKS], stop[MAX_CHUNKS];
    int in_place[MAX_CHUNKS];
    int all_in_place = verify;
#define RANGE_LO(t) (r->lo[t])
#pragma omp parallel num_threads(r->team)
    {
#pragma omp for schedule(static)
        for (int t = 0; t < chunks; ++t) {
            const size_t lo = RANGE_LO(t), hi = RANGE_LO(t + 1);
            fill_part mine = {1, 0, 0, 0};
            size_t p = lo;
            start[t] = SIZE_MAX;
            checked[t] = 0;
            if (verify)
                p = verify_range(c, pairs, ps, lo, hi, &start[t], &checked[t], &mine);
            stop[t] = p;
            size_t tail = 0;
            if (p < hi) { /* from the first change on, into the scratch at the pair's index */
                fill_part rest = {1, 0, 0, 0};
                tail = fill_into(c, si, sj, sp, pairs, ps, p, hi, p, &rest, NULL, 0) - p;
                mine = join_parts(mine, rest);
            }
            found[t] = checked[t] + tail;
            part[t] = mine;
        }
#pragma omp single
        {
            offset[0] = m0;
            for (int t = 0; t < chunks; ++t) {
                offset[t + 1] = offset[t] + found[t];
                in_place[t] = verify && stop[t] == RANGE_LO(t + 1) &&
                              (checked[t] == 0 || start[t] == offset[t]);
                all_in_place &= in_place[t];
            }
        }
        /* a range that moves takes its confirmed contacts into the scratch too, before any
         * range overwrites the list (the barrier of this loop) */
#pragma omp for schedule(static, 1)
        for (int t = 0; t < chunks; ++t) {
            const size_t lo = RANGE_LO(t);
            if (!in_place[t] && checked[t] > 0) {
                memcpy(si + lo, c->i + start[t], checked[t] * sizeof(uint32_t));
                memcpy(sj + lo, c->j + start[t], checked[t] * sizeof(uint32_t));
                memcpy(sp + lo, c->pair + start[t], checked[t] * sizeof(uint32_t));
            }
        }
#pragma omp for schedule(static, 1)
        for (int t = 0; t < chunks; ++t) {
            if (in_place[t])
                continue;
            const size_t lo = RANGE_LO(t), to = offset[t], k = checked[t];
            const size_t tail = found[t] - k;
            memcpy(c->i + to, si + lo, k * sizeof(uint32_t));
            memcpy(c->j + to, sj + lo, k * sizeof(uint32_t));
            memcpy(c->pair + to, sp + lo, k * sizeof(uint32_t));
            memcpy(c->i + to + k, si + stop[t], tail * sizeof(uint32_t));
            memcpy(c->j + to + k, sj + stop[t], tail * sizeof(uint32_t));
            memcpy(c->pair + to + k, sp + stop[t], tail * sizeof(uint32_t));
            for (size_t m = to; m < to + found[t]; ++m)
                c->pair_to_contact[c->pair[m]] = (uint32_t)m;
        }
    }
    /* the first range not in place: the lists agree before its first change, or before the
     * range if it moved */
    *change_pair = *change_contact = SIZE_MAX;
    for (int t = 0; t < chunks && !all_in_place; ++t) {
        if (in_place[t])
            continue;
        const int moved = checked[t] > 0 && start[t] != offset[t];
        *change_pair = moved ? RANGE_LO(t) : stop[t];
        *change_contact = moved ? offset[t] : offset[t] + checked[t];
        break;
    }
#undef RANGE_LO
    return offset[chunks];
}

/* The ranges of a threaded fill of `pairs` pairs on `threads` threads: a few per thread, of
 * FILL_RANGE_MIN pairs at least (one per thread when there are not that many). */
static int fill_ranges(size_t pairs, int threads)
{
    int ranges = 4 * threads < MAX_CHUNKS ? 4 * threads : MAX_CHUNKS;
    while (ranges > threads && pairs / (size_t)ranges < FILL_RANGE_MIN)
        ranges /= 2;
    return ranges > threads ? ranges : threads;
}

/* S from the number of candidate pairs: a power of two (2, 4 or 8, so that 2 or 4 threads get
 * equal shares), about 32768 pairs per range; 0 (no partition) below 2048 pairs. */
static int chunk_count(size_t pairs)
{
    enum { MIN_PAIRS = 2048, PAIRS_PER_CHUNK = 32768 };
    if (pairs < MIN_PAIRS)
        return 0;
    int count = 2;
    while (count < SINTER_CHUNKS_MAX && (size_t)(2 * count) * PAIRS_PER_CHUNK <= pairs)
        count *= 2;
    return count;
}

/* The smaller particle index of contact q: the particle whose scan found its pair. */
static inline uint32_t smaller_index(const sinter_contact_list *c, size_t q)
{
    return c->i[q] < c->j[q] ? c->i[q] : c->j[q];
}

/* 1 if c was last found lean over these very pairs (and particles), so that its membership
 * may be checked rather than found afresh. */
static int over_same_pairs(const sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps)
{
    return c->revision != 0 && c->lean_source != 0 && c->lean_source == pairs->build_id &&
           c->pair_count == pairs->count && c->particle_count == ps->count;
}

/* First contact whose smaller particle index is at least p (they ascend). */
static size_t first_contact_of(const sinter_contact_list *c, size_t p)
{
    return first_with_smaller_index(c->i, c->j, 0, c->count, p);
}

/* The contact ranges of c's partition from its particle ranges. */
static void contact_ranges(sinter_contact_list *c)
{
    sinter_chunks *k = &c->chunks;
    k->qlo[0] = 0;
    for (int s = 1; s < k->count; ++s)
        k->qlo[s] = first_contact_of(c, k->plo[s]);
    k->qlo[k->count] = c->count;
}

/*
 * The work of a step on particles [0, p), in units of one contact's force law: the contacts
 * whose smaller particle index is below p, the candidate pairs the search tests (PAIR_COST
 * of a contact each) and the particles the integrator moves (PARTICLE_COST each). Measured
 * on one core of the falling pile and the packed bed (`peer_bench --stats`, RESULTS.md,
 * session 10): a contact 20-30 ns with its wall share and history, a pair's test 1.5-2 ns,
 * a particle's two Verlet passes about 10 ns.
 */
enum { COST_UNITS = 16, PAIR_COST = 1, PARTICLE_COST = 6 }; /* sixteenths of a contact */

static size_t work_below(const sinter_contact_list *c, const sinter_pair_list *pairs, size_t p)
{
    return COST_UNITS * first_contact_of(c, p) + PAIR_COST * first_pair_of(pairs, 0, p) +
           PARTICLE_COST * p;
}

/*
 * The partition from the fill passes' findings (parts in list order); count 0 when the list
 * is too small or its smaller particle indices do not ascend. The particle ranges are made
 * by the first search over a pair list and kept by the later ones (chunks.h); they hold about
 * equal work (work_below): the law's contacts, and the search and the integrator, which run
 * on the same ranges (a falling pile has its contacts all at the bottom: ranges of equal
 * contacts left the integrator's particles mostly to one thread).
 */
static void make_chunks(sinter_contact_list *c, const sinter_pair_list *pairs,
                        const fill_part *parts, int nparts, size_t n, int count)
{
    sinter_chunks *k = &c->chunks;
    if (pairs->canonical) /* the reproducible mode: every sum in list order (canonical_order.h) */
        count = 0;
    int seen = 0;
    uint32_t last = 0;
    for (int t = 0; t < nparts; ++t) {
        if (!parts[t].any)
            continue;
        if (!parts[t].ascending || (seen && parts[t].first < last))
            count = 0;
        last = parts[t].last;
        seen = 1;
    }
    if (count == 0) {
        k->count = 0;
        k->source = 0;
        return;
    }
    if (k->count == count && k->source == pairs->build_id) {
        contact_ranges(c);
        return;
    }
    k->count = count;
    k->source = pairs->build_id;
    /* the scratch was reserved for every pair in sinter_contacts_find_pp. Range s starts at
     * the first particle below which lies s / S of the work. */
    const double total = (double)work_below(c, pairs, n);
    k->plo[0] = 0;
    for (int s = 1; s < count; ++s) {
        const double target = total * (double)s / (double)count;
        size_t lo = k->plo[s - 1], hi = n;
        while (lo < hi) {
            const size_t mid = lo + (hi - lo) / 2;
            if ((double)work_below(c, pairs, mid) < target)
                lo = mid + 1;
            else
                hi = mid;
        }
        k->plo[s] = lo;
    }
    k->plo[count] = n;
    contact_ranges(c);
}

static sinter_status find_pp(sinter_ctx *ctx, sinter_contact_list *c, const sinter_pair_list *pairs,
                             const sinter_particles *ps, int geometry)
{
    /* Reserve for the worst case so the loops below never allocate. */
    sinter_status st = reserve(ctx, c, pairs->count + 1);
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->pair_to_contact, &c->pair_to_contact_capacity,
                         pairs->count + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    if (st == SINTER_OK && chunk_count(pairs->count) > 0)
        st = sinter_grow(ctx, &c->chunk_scratch, &c->chunk_scratch_capacity,
                         pairs->count * (3 * sizeof(double) + sizeof(uint32_t)) + 1, 1);
    if (st != SINTER_OK)
        return st;
    /* a lean search over the very pairs of the last one checks before it writes */
    const int verify = !geometry && over_same_pairs(c, pairs, ps);
    c->lean_source = 0; /* set again when a lean search completes */
    c->unconfirmed = 0;
    const int adjacency = pairs->adj_build != 0 && pairs->adj_build == pairs->build_id;
    c->adj_start = adjacency ? pairs->adj_start : NULL;
    c->adj_pair = adjacency ? pairs->adj_pair : NULL;
    c->particle_count = ps->count;
    c->pair_count = pairs->count;
    const int threads = pairs->count < SEARCH_THREADED_MIN ? 1 : sinter_threads(ctx);
    const int parts_count = chunk_count(pairs->count);
    c->geometry = geometry;
    size_t (*fill)(sinter_contact_list *, const sinter_pair_list *, const sinter_particles *,
                   size_t, size_t, size_t, fill_part *, const uint8_t *) =
        geometry ? fill_pp_full : fill_pp_lean;
    if (threads <= 1) {
        fill_part part = {1, 0, 0, 0};
        size_t p = 0, m = 0, checked = 0;
        if (verify)
            p = verify_range(c, pairs, ps, 0, pairs->count, &m, &checked, &part);
        if (!verify || p < pairs->count) { /* written from the first change on */
            fill_part rest = {1, 0, 0, 0};
            c->count = fill(c, pairs, ps, p, pairs->count, checked, &rest, NULL);
            part = join_parts(part, rest);
            sinter_contacts_changed(c, p, checked);
        }
        make_chunks(c, pairs, &part, 1, ps->count, parts_count);
        c->lean_source = geometry ? 0 : pairs->build_id;
        return SINTER_OK;
    }
    const int chunks = threads < MAX_CHUNKS ? threads : MAX_CHUNKS;
    if (!geometry) {
        const int ranges = fill_ranges(pairs->count, chunks);
        st = sinter_grow(ctx, (void **)&c->fill_scratch, &c->fill_scratch_capacity,
                         3 * pairs->count + 1, sizeof(uint32_t));
        if (st != SINTER_OK)
            return st;
        fill_part part[MAX_CHUNKS];
        size_t change_pair = 0, change_contact = 0;
        const pair_ranges r = pass_ranges(c, pairs, ps->count, 0, chunks, ranges);
        c->count = fill_segments(c, pairs, ps, 0, &r, verify, part, &change_pair, &change_contact);
        if (change_pair != SIZE_MAX)
            sinter_contacts_changed(c, change_pair, change_contact);
        make_chunks(c, pairs, part, r.count, ps->count, parts_count);
        c->lean_source = pairs->build_id;
        return SINTER_OK;
    }
    sinter_contacts_changed(c, 0, 0);
    /* Threads, with the geometry: count per chunk (keeping each pair's verdict), then fill
     * each chunk from its offset, visiting only the pairs in contact: the same list, in the
     * same order, as one thread makes. */
    st = sinter_grow(ctx, (void **)&c->touch, &c->touch_capacity, pairs->count + 1, 1);
    if (st != SINTER_OK)
        return st;
    uint8_t *touch = c->touch;
    size_t offset[MAX_CHUNKS + 1] = {0};
    fill_part part[MAX_CHUNKS];
    const size_t n = pairs->count;
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
    for (int t = 0; t < chunks; ++t) {
        const size_t lo = n * (size_t)t / (size_t)chunks, hi = n * (size_t)(t + 1) / (size_t)chunks;
        size_t count = 0;
        for (size_t p = lo; p < hi; ++p) {
            const int in_contact = touching(c, pairs, ps->x, ps->radius, p);
            touch[p] = (uint8_t)in_contact;
            count += (size_t)in_contact;
        }
        offset[t + 1] = count;
    }
    for (int t = 0; t < chunks; ++t)
        offset[t + 1] += offset[t];
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
    for (int t = 0; t < chunks; ++t) {
        const size_t lo = n * (size_t)t / (size_t)chunks, hi = n * (size_t)(t + 1) / (size_t)chunks;
        fill_part mine = {1, 0, 0, 0};
        fill(c, pairs, ps, lo, hi, offset[t], &mine, touch);
        part[t] = mine;
    }
    c->count = offset[chunks];
    make_chunks(c, pairs, part, chunks, ps->count, parts_count);
    return SINTER_OK;
}

sinter_status sinter_contacts_find_pp(sinter_ctx *ctx, sinter_contact_list *c,
                                      sinter_pair_list *pairs, const sinter_particles *ps)
{
    /* a list with its geometry may serve a law that sums per particle on threads */
    const sinter_status st = sinter_pairs_adjacency(ctx, pairs, ps->count);
    return st == SINTER_OK ? find_pp(ctx, c, pairs, ps, 1) : st;
}

sinter_status sinter_contacts_find_pp_lean(sinter_ctx *ctx, sinter_contact_list *c,
                                           const sinter_pair_list *pairs,
                                           const sinter_particles *ps)
{
    return find_pp(ctx, c, pairs, ps, 0);
}

/* Pairs of range [lo, hi) the list does not hold: the first in contact (hi: none), and the
 * others written to gaps[0 .. cap) while they fit (*count; SIZE_MAX when they did not). */
static size_t scan_range(const sinter_contact_list *c, const sinter_pair_list *pairs,
                         const sinter_particles *ps, size_t lo, size_t hi, uint32_t *gaps,
                         size_t cap, size_t *count)
{
    const uint32_t *restrict to_contact = c->pair_to_contact;
    const double *restrict x = ps->x, *restrict r = ps->radius;
    const uint32_t *restrict pi = pairs->i, *restrict pj = pairs->j;
    const int plain = c->held == NULL; /* the overlap test alone, its inputs in registers */
    size_t k = 0;
    for (size_t p = lo; p < hi; ++p) {
        if (to_contact[p] != SINTER_NO_PAIR)
            continue;
        if (plain ? overlapping(x, r, pi[p], pj[p]) : touching(c, pairs, x, r, p))
            return p;
        if (k < cap)
            gaps[k] = (uint32_t)p;
        k += k <= cap;
    }
    *count = k <= cap ? k : SIZE_MAX;
    return hi;
}

/* scan_range over range t of r, its gaps written to its share offset[t] .. offset[t + 1] of
 * gaps (none when gaps is NULL). */
static inline size_t scan_range_t(const sinter_contact_list *c, const sinter_pair_list *pairs,
                                  const sinter_particles *ps, const pair_ranges *r, uint32_t *gaps,
                                  const size_t *offset, size_t *count, int t)
{
    return scan_range(c, pairs, ps, r->lo[t], r->lo[t + 1], gaps != NULL ? gaps + offset[t] : NULL,
                      offset[t + 1] - offset[t], &count[t]);
}

/*
 * The first pair the list does not hold that is in contact (pairs->count: none). Scanning
 * every pair's entry costs a read of the whole pair list (2 % of a packed bed's step at half
 * a million particles), so a scan that finds none keeps the pairs out of contact when they
 * are few (an eighth of the pairs at most): until the list changes, only those are tested.
 */
static size_t first_new_contact(sinter_ctx *ctx, sinter_contact_list *c,
                                const sinter_pair_list *pairs, const sinter_particles *ps,
                                int threads)
{
    const size_t n = pairs->count;
    if (c->gap_revision != 0 && c->gap_revision == c->revision) {
        for (size_t k = 0; k < c->gap_count; ++k)
            if (touching(c, pairs, ps->x, ps->radius, c->gaps[k]))
                return c->gaps[k];
        return n;
    }
    c->gap_revision = 0;
    const size_t cap = n / 8 + (size_t)threads;
    uint32_t *gaps = NULL;
    if (sinter_grow(ctx, (void **)&c->gaps, &c->gap_capacity, cap + 1, sizeof(uint32_t)) ==
        SINTER_OK)
        gaps = c->gaps;
    else
        sinter_clear_error(ctx); /* no room for them: the scan still answers */
    size_t first[MAX_CHUNKS], count[MAX_CHUNKS], offset[MAX_CHUNKS + 1];
    const pair_ranges r =
        pass_ranges(c, pairs, ps->count, 0, threads, threads < MAX_CHUNKS ? threads : MAX_CHUNKS);
    const int ranges = r.count;
    offset[0] = 0;
    for (int t = 0; t < ranges; ++t) /* each range writes its share of the room */
        offset[t + 1] = gaps != NULL && n > 0 ? cap * r.lo[t + 1] / n : 0;
    if (r.team > 1) {
#pragma omp parallel for num_threads(r.team) schedule(static)
        for (int t = 0; t < ranges; ++t)
            first[t] = scan_range_t(c, pairs, ps, &r, gaps, offset, count, t);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        for (int t = 0; t < ranges; ++t)
            first[t] = scan_range_t(c, pairs, ps, &r, gaps, offset, count, t);
    }
    size_t kept = 0;
    for (int t = 0; t < ranges; ++t) {
        const size_t hi = r.lo[t + 1];
        if (first[t] < hi)
            return first[t];
        if (count[t] == SIZE_MAX)
            gaps = NULL;
        if (gaps != NULL)
            memmove(gaps + kept, gaps + offset[t], count[t] * sizeof(uint32_t));
        kept += gaps != NULL ? count[t] : 0;
    }
    if (gaps != NULL) {
        c->gap_count = kept;
        c->gap_revision = c->revision;
    }
    return n;
}

/* The first contact whose candidate pair is p or later (the list is in pair order). */
static size_t first_contact_from_pair(const sinter_contact_list *c, size_t p)
{
    return sinter_lower_bound_u32(c->pair, c->count, p);
}

sinter_status sinter_contacts_find_pp_deferred(sinter_ctx *ctx, sinter_contact_list *c,
                                               const sinter_pair_list *pairs,
                                               const sinter_particles *ps, int *deferred)
{
    /* searches done whole after one whose new contacts lay early in a threaded list: 1, 3,
     * 7, ... up to 63 (a falling pile gains contacts all over, nearly every step) */
    enum { MAX_WAIT = 63 };
    *deferred = 0;
    const int same_pairs = over_same_pairs(c, pairs, ps) && !c->unconfirmed;
    if (!same_pairs || c->defer_skip > 0) {
        c->defer_skip -= c->defer_skip > 0;
        return find_pp(ctx, c, pairs, ps, 0);
    }
    const size_t n = pairs->count;
    const int threads = n < SEARCH_THREADED_MIN ? 1 : sinter_threads(ctx);
    const size_t p = first_new_contact(ctx, c, pairs, ps, threads);
    if (p < n) {
        /* pairs from p on are searched afresh (on threads when there are enough of them), the
         * contacts before are left to the law; with threads, when p lies in the first half
         * (new contacts all over, as in a falling pile), the whole search is done instead */
        if (threads > 1 && n - p > n / 2) {
            c->defer_wait = c->defer_wait < MAX_WAIT ? 2 * c->defer_wait + 1 : MAX_WAIT;
            c->defer_skip = c->defer_wait;
            return find_pp(ctx, c, pairs, ps, 0);
        }
        const size_t m = first_contact_from_pair(c, p);
        fill_part rest = {1, 0, 0, 0};
        const uint32_t before = m > 0 ? smaller_index(c, m - 1) : 0;
        const int chunks = threads < MAX_CHUNKS ? threads : MAX_CHUNKS;
        int threaded = chunks > 1 && n - p >= 2 * FILL_RANGE_MIN;
        if (threaded && sinter_grow(ctx, (void **)&c->fill_scratch, &c->fill_scratch_capacity,
                                    3 * n + 1, sizeof(uint32_t)) != SINTER_OK) {
            sinter_clear_error(ctx); /* no room for the scratch: one thread fills them */
            threaded = 0;
        }
        if (threaded) {
            fill_part parts[MAX_CHUNKS];
            size_t change_pair = 0, change_contact = 0;
            const int ranges = fill_ranges(n - p, chunks);
            const pair_ranges r = pass_ranges(c, pairs, ps->count, p, chunks, ranges);
            c->count = fill_segments(c, pairs, ps, m, &r, 0, parts, &change_pair, &change_contact);
            for (int t = 0; t < r.count; ++t)
                rest = join_parts(rest, parts[t]);
        } else {
            c->count = fill_pp_lean(c, pairs, ps, p, n, m, &rest, NULL);
        }
        sinter_contacts_changed(c, p, m);
        if (!rest.ascending || (rest.any && rest.first < before)) {
            /* not in the neighbour build's order: the whole search decides the partition */
            return find_pp(ctx, c, pairs, ps, 0);
        }
        if (c->chunks.count > 0)
            contact_ranges(c);
    }
    if (c->count + 1 > c->ended_capacity) { /* the marks, all 0 (sinter_contacts_confirm) */
        const size_t cap = c->capacity + 1;
        uint8_t *grown = sinter_realloc_array(ctx, c->ended, cap, 1);
        if (grown == NULL)
            return sinter_last_status(ctx);
        memset(grown, 0, cap);
        c->ended = grown;
        c->ended_capacity = cap;
    }
    c->defer_wait = 0;
    c->unconfirmed = 1;
    *deferred = 1;
    return SINTER_OK;
}

/* Drop the contacts from index `from` on that no longer touch, keeping the others in order:
 * those marked in `ended` (clearing the marks), or without it those failing the search's
 * test; and record the change (pairs before the first dropped kept their verdicts). */
static void drop_contacts(sinter_contact_list *c, size_t from, uint8_t *ended,
                          const sinter_pair_list *pairs, const sinter_particles *ps, double *rows,
                          size_t width)
{
    const size_t first_pair = c->pair[from];
    uint32_t *to_contact = c->pair_to_contact;
    size_t kept = from;
    for (size_t q = from; q < c->count; ++q) {
        const uint32_t p = c->pair[q];
        const int touches = ended != NULL ? !ended[q] : touching(c, pairs, ps->x, ps->radius, p);
        if (ended != NULL)
            ended[q] = 0;
        if (!touches) {
            to_contact[p] = SINTER_NO_PAIR;
            continue;
        }
        c->i[kept] = c->i[q];
        c->j[kept] = c->j[q];
        c->pair[kept] = p;
        to_contact[p] = (uint32_t)kept;
        if (rows != NULL && kept != q)
            memcpy(rows + width * kept, rows + width * q, width * sizeof(double));
        ++kept;
    }
    sinter_contacts_changed(c, first_pair, from);
    c->count = kept;
    if (c->chunks.count > 0) /* the particle ranges stay (make_chunks) */
        contact_ranges(c);
}

void sinter_contacts_confirm(sinter_contact_list *c, size_t from, double *rows, size_t width)
{
    c->unconfirmed = 0;
    if (from < c->count)
        drop_contacts(c, from, c->ended, NULL, NULL, rows, width);
}

void sinter_contacts_check(sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps)
{
    c->unconfirmed = 0;
    if (c->ended != NULL)
        memset(c->ended, 0, c->ended_capacity);
    if (c->count > 0)
        drop_contacts(c, 0, NULL, pairs, ps, NULL, 0);
}

void sinter_contacts_geometry(const sinter_ctx *ctx, sinter_contact_list *c,
                              const sinter_particles *ps)
{
    if (c->geometry)
        return;
    const long count = (long)c->count;
    const int threads = count < 4096 ? 1 : sinter_threads(ctx);
    if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
        for (long m = 0; m < count; ++m)
            put_geometry(c, ps->x, ps->radius, (size_t)m, c->i[m], c->j[m]);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        for (long m = 0; m < count; ++m)
            put_geometry(c, ps->x, ps->radius, (size_t)m, c->i[m], c->j[m]);
    }
    c->geometry = 1;
}

/* A wall list's ranges for threads (contacts.h, sinter_chunks): 4 runs of about equal size
 * that never split a particle's contacts, when the particles ascend and there are enough. */
static void wall_ranges(sinter_contact_list *c, int ascending)
{
    enum { MIN_CONTACTS = 1024, RANGES = 4 };
    sinter_chunks *k = &c->chunks;
    k->count = 0;
    if (!ascending || c->count < MIN_CONTACTS)
        return;
    k->count = RANGES;
    k->qlo[0] = 0;
    for (int s = 1; s < RANGES; ++s) {
        size_t q = c->count * (size_t)s / RANGES;
        q = q > k->qlo[s - 1] ? q : k->qlo[s - 1];
        while (q > 0 && q < c->count && c->i[q] == c->i[q - 1])
            ++q;
        k->qlo[s] = q;
    }
    k->qlo[RANGES] = c->count;
}

/* The overlap, distance, area and branch of wall contact m at centre-plane distance s from
 * the wall (the wall is a particle of infinite radius, seed 003 remark 1: L_i = s). */
static inline void put_wall_distances(sinter_contact_list *c, size_t m, double r, double s)
{
    const double a2_raw = r * r - s * s, a2 = a2_raw > 0.0 ? a2_raw : 0.0;
    c->delta[m] = r - s;
    c->dist[m] = s;
    c->area[m] = PI * a2;
    c->branch[m] = s;
}

/* Wall contact m: pair p of particle i with wall k, and its geometry (wn: the wall's normal
 * at the contact, towards the particle). */
static inline void put_wall_geometry(sinter_contact_list *c, size_t m, uint32_t p, uint32_t i,
                                     uint32_t k, const double *wn, double r, double s)
{
    c->i[m] = i;
    c->j[m] = k;
    c->pair[m] = p;
    c->n[3 * m] = -wn[0];
    c->n[3 * m + 1] = -wn[1];
    c->n[3 * m + 2] = -wn[2];
    put_wall_distances(c, m, r, s);
}

/* The geometry of wall contact m renewed, for a contact that holds the same pair as before:
 * the values of put_wall_geometry, written only where they may have changed (the indices
 * never; the normal when the wall turned). A store to a cache line another core has read
 * costs a round trip to it even when the value is the same (issue 9: 40 % of a 1k bed's wall
 * search on two threads). */
static inline void renew_wall_geometry(sinter_contact_list *c, size_t m, const double *wn, double r,
                                       double s)
{
    const double n[3] = {-wn[0], -wn[1], -wn[2]};
    sinter_put_changed(c->n + 3 * m, n, sizeof(n));
    put_wall_distances(c, m, r, s);
}

/* Wall w's signed distance from centre x and its normal there (*wn: a plane's own, else the
 * kind's, into buf) from one evaluation of the kind's closest point (a mesh's search is not
 * repeated, and starts from the pair's hint; the arithmetic of sinter_wall_distance and of
 * the kind's normal). */
static inline double wall_distance_normal(const sinter_wall *w, const double *x, int planes,
                                          double *buf, const double **wn, uint32_t *hint,
                                          double *cert)
{
    if (planes || w->kind == SINTER_WALL_PLANE)
        return sinter_plane_distance(w, x);
    *wn = buf;
    return sinter_wall_contact_certified(w, x, buf, hint, cert);
}

/* The pairs' mesh hints (c->hint) for pair list `pairs`: the last search's, carried to the
 * same (particle, wall) pairs of a rebuilt list by its `from`, none for new pairs. Any hint
 * gives the same bits (sinter_mesh_closest_hinted): only the cost depends on them. */
static sinter_status carry_hints(sinter_ctx *ctx, sinter_contact_list *c,
                                 const sinter_pair_list *pairs)
{
    sinter_status st =
        sinter_grow(ctx, (void **)&c->hint, &c->hint_capacity, pairs->count + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->hint_spare, &c->hint_spare_capacity, pairs->count + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->cert, &c->cert_capacity, 4 * pairs->count + 4,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->cert_spare, &c->cert_spare_capacity,
                         4 * pairs->count + 4, sizeof(double));
    if (st != SINTER_OK)
        return st;
    if (c->hint_source == pairs->build_id && c->hint_count == pairs->count)
        return SINTER_OK;
    for (size_t p = 0; p < pairs->count; ++p) {
        const uint32_t q = pairs->from != NULL ? pairs->from[p] : SINTER_NO_PAIR;
        const int kept = q != SINTER_NO_PAIR && q < c->hint_count;
        c->hint_spare[p] = kept ? c->hint[q] : UINT32_MAX;
        if (kept)
            memcpy(c->cert_spare + 4 * p, c->cert + 4 * (size_t)q, 4 * sizeof(double));
        else
            c->cert_spare[4 * p + 3] = -1.0; /* none */
    }
    uint32_t *swap = c->hint;
    c->hint = c->hint_spare;
    c->hint_spare = swap;
    size_t cap = c->hint_capacity;
    c->hint_capacity = c->hint_spare_capacity;
    c->hint_spare_capacity = cap;
    double *cswap = c->cert;
    c->cert = c->cert_spare;
    c->cert_spare = cswap;
    cap = c->cert_capacity;
    c->cert_capacity = c->cert_spare_capacity;
    c->cert_spare_capacity = cap;
    c->hint_count = pairs->count;
    c->hint_source = pairs->build_id;
    return SINTER_OK;
}

/* The wall search's ranges of pairs (sinter_contacts_find_pw), run by sinter_ranges_run. */
typedef struct wall_search {
    sinter_contact_list *c;
    const sinter_pair_list *pairs;
    const sinter_particles *ps;
    const sinter_walls *walls;
    const size_t *bound;    /* range t: pairs [bound[t], bound[t + 1]) */
    int compare;            /* the list holds these pairs' contacts: compared, geometry renewed */
    int planes;             /* every wall is a plane */
    const uint32_t *active; /* the pairs to test (wall_skip.h), or NULL: all */
    size_t active_count;
    int ascending_all; /* with active: the pairs' particles ascend */
    int same[SINTER_CHUNKS_MAX], ascending[SINTER_CHUNKS_MAX];
    size_t offset[SINTER_CHUNKS_MAX + 1]; /* range t's contacts at offset[t + 1], then summed */
} wall_search;

/* Range t's verdicts: which pairs touch, whether they are the contacts the list holds (their
 * geometry renewed in place), whether the particles ascend, how many contacts (planes: every
 * wall is a plane, a constant where called, so that the planes' loop has no kind's test). */
static inline void wall_test_pairs(wall_search *job, int t, int planes)
{
    sinter_contact_list *c = job->c;
    const double *x = job->ps->x, *r = job->ps->radius;
    const uint32_t *pi = job->pairs->i, *pk = job->pairs->j;
    const uint32_t *to_contact = c->pair_to_contact;
    uint8_t *touch = c->touch;
    const size_t lo = job->bound[t], hi = job->bound[t + 1];
    size_t count = 0;
    int same = 1, ascending = 1;
    /* with walls proven out of reach (wall_skip.h): only the other walls' pairs, whose
     * particles ascend as the certificate found them; the skipped pairs' touch bytes and
     * contacts stay those of the full test that took it (none) */
    const uint32_t *active = job->active;
    const size_t qlo = active ? sinter_lower_bound_u32(active, job->active_count, lo) : lo,
                 qhi = active ? sinter_lower_bound_u32(active, job->active_count, hi) : hi;
    for (size_t q = qlo; q < qhi; ++q) {
        const size_t p = active ? active[q] : q;
        const uint32_t i = pi[p], k = pk[p];
        ascending &= active ? job->ascending_all : p == 0 || i >= pi[p - 1];
        const sinter_wall *w = &job->walls->wall[k];
        double buf[3];
        const double *wn = w->n;
        const double sd =
            wall_distance_normal(w, x + 3 * i, planes, buf, &wn, planes ? NULL : c->hint + p,
                                 planes ? NULL : c->cert + 4 * p);
        const int touches = sd < r[i];
        touch[p] = (uint8_t)touches;
        count += (size_t)touches;
        const uint32_t was = job->compare ? to_contact[p] : SINTER_NO_PAIR;
        if (touches != (was != SINTER_NO_PAIR)) {
            same = 0;
        } else if (job->compare && touches) {
            renew_wall_geometry(c, was, wn, r[i], sd);
        }
    }
    job->same[t] = same;
    job->ascending[t] = ascending;
    job->offset[t + 1] = count;
}

static void wall_test_range(void *data, int t)
{
    wall_search *job = data;
    if (job->planes)
        wall_test_pairs(job, t, 1);
    else
        wall_test_pairs(job, t, 0);
}

/* Range t's contacts written from offset[t] on, their pairs pointed at them (planes: as in
 * wall_test_pairs). */
static inline void wall_put_pairs(wall_search *job, int t, int planes)
{
    sinter_contact_list *c = job->c;
    const double *x = job->ps->x, *r = job->ps->radius;
    const uint32_t *pi = job->pairs->i, *pk = job->pairs->j;
    uint32_t *to_contact = c->pair_to_contact;
    const uint8_t *touch = c->touch;
    const size_t lo = job->bound[t], hi = job->bound[t + 1];
    size_t m = job->offset[t];
    /* with walls proven out of reach, only the other walls' pairs, as wall_test_pairs: the
     * skipped pairs were out of contact at the full test that took the certificate, and
     * their pair_to_contact entries stay as that search wrote them (none) */
    const uint32_t *active = job->active;
    const size_t qlo = active ? sinter_lower_bound_u32(active, job->active_count, lo) : lo,
                 qhi = active ? sinter_lower_bound_u32(active, job->active_count, hi) : hi;
    for (size_t q = qlo; q < qhi; ++q) {
        const size_t p = active ? active[q] : q;
        if (!touch[p]) {
            to_contact[p] = SINTER_NO_PAIR;
            continue;
        }
        const uint32_t i = pi[p], k = pk[p];
        const sinter_wall *w = &job->walls->wall[k];
        to_contact[p] = (uint32_t)m;
        double buf[3];
        const double *wn = w->n;
        const double sd =
            wall_distance_normal(w, x + 3 * i, planes, buf, &wn, planes ? NULL : c->hint + p,
                                 planes ? NULL : c->cert + 4 * p);
        put_wall_geometry(c, m, (uint32_t)p, i, k, wn, r[i], sd);
        ++m;
    }
}

static void wall_put_range(void *data, int t)
{
    wall_search *job = data;
    if (job->planes)
        wall_put_pairs(job, t, 1);
    else
        wall_put_pairs(job, t, 0);
}

sinter_status sinter_contacts_find_pw(sinter_ctx *ctx, sinter_contact_list *c,
                                      const sinter_pair_list *pairs, const sinter_particles *ps,
                                      const sinter_walls *walls, const sinter_chunks *owner)
{
    return sinter_contacts_find_pw_skip(ctx, c, pairs, ps, walls, owner, NULL);
}

sinter_status sinter_contacts_find_pw_skip(sinter_ctx *ctx, sinter_contact_list *c,
                                           const sinter_pair_list *pairs,
                                           const sinter_particles *ps, const sinter_walls *walls,
                                           const sinter_chunks *owner, sinter_wall_skip *skip)
{
    sinter_status st = reserve(ctx, c, pairs->count + 1);
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->pair_to_contact, &c->pair_to_contact_capacity,
                         pairs->count + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->touch, &c->touch_capacity, pairs->count + 1, 1);
    int planes = 1;
    for (size_t k = 0; k < walls->count; ++k)
        planes &= walls->wall[k].kind == SINTER_WALL_PLANE;
    if (st == SINTER_OK && !planes) /* the meshes' hints (planes: none read) */
        st = carry_hints(ctx, c, pairs);
    if (st != SINTER_OK)
        return st;
    /* over the pairs of the last search, the membership is compared as the verdicts come
     * (and the geometry of the contacts that stay written in place) */
    const int compare = c->revision != 0 && c->lean_source == pairs->build_id &&
                        c->pair_count == pairs->count && c->particle_count == ps->count;
    int same = compare;
    c->particle_count = ps->count;
    c->pair_count = pairs->count;
    c->lean_source = pairs->build_id; /* for the comparison only: the list has its geometry */
    const size_t n = pairs->count;
    /* Ranges of pairs: by preference the pair partition's particle ranges (owner), so that
     * each thread reads the positions it wrote and writes the contacts its law will read
     * (chunks.h, sinter_chunks_wall_runs); else equal ranges, one per thread, from 1024
     * pairs. */
    enum { RANGES_MAX = SINTER_CHUNKS_MAX };
    const int threads = sinter_threads(ctx);
    size_t bound[RANGES_MAX + 1];
    int ranges = owner != NULL && owner->count > 0 && threads > 1 ? owner->count : 0;
    if (ranges > 0) {
        bound[0] = 0;
        for (int t = 1; t < ranges; ++t) {
            /* any index when the pairs' particles do not ascend: still a partition */
            const size_t b = sinter_lower_bound_u32(pairs->i, n, owner->plo[t]);
            bound[t] = b > bound[t - 1] ? b : bound[t - 1];
        }
    } else {
        ranges = n < 1024 ? 1 : threads < RANGES_MAX ? threads : RANGES_MAX;
        for (int t = 0; t < ranges; ++t)
            bound[t] = n * (size_t)t / (size_t)ranges;
    }
    bound[ranges] = n;
    const int team = threads < ranges ? threads : ranges;
    const int skipping = skip != NULL && sinter_wall_skip_holds(skip, pairs, ps, walls);
    wall_search job = {c,
                       pairs,
                       ps,
                       walls,
                       bound,
                       compare,
                       planes,
                       skipping ? skip->active : NULL,
                       skipping ? skip->active_count : 0,
                       skipping ? skip->ascending : 1,
                       {0},
                       {0},
                       {0}};
    sinter_ranges_run(team, ranges, wall_test_range, &job);
    int ascending = 1;
    for (int t = 0; t < ranges; ++t) {
        same &= job.same[t];
        ascending &= job.ascending[t];
    }
    c->geometry = 1;
    c->ascending = ascending;
    if (!same) {
        for (int t = 0; t < ranges; ++t)
            job.offset[t + 1] += job.offset[t];
        sinter_ranges_run(team, ranges, wall_put_range, &job);
        c->count = job.offset[ranges];
        sinter_contacts_changed(c, 0, 0);
        wall_ranges(c, ascending);
    }                                 /* (else the same contacts, their geometry renewed) */
    if (skip != NULL && !skip->valid) /* a full test at these positions: take it */
        return sinter_wall_skip_take(ctx, skip, pairs, ps, walls, ascending);
    return SINTER_OK;
}
