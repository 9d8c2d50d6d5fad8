/*
 * Recursive coordinate bisection with weights (libsinter_mpi, issue 44; Berger and Bokhari 1987,
 * IEEE Trans. Computers C-36(5):570-580), our own cut-plane balancing rather than Zoltan's: its
 * planes come from exact sums, so they are the same bits for any spread of the points over the
 * callers (Zoltan's median search sums doubles in the order of its reduction tree).
 *
 * Level by level, every set still holding more than one part is cut at once: one MIN and one MAX
 * reduction give the extent of its points, the cut goes normal to the longest extent, and
 * multisection places it: each round evaluates CANDIDATES planes spread over the bracket with one
 * SUM reduction of integer limbs (each point adds its weight to the interval it falls in, and
 * prefix sums of the limbs give the weight below each plane exactly), keeps the plane whose
 * weight below is closest to the set's share and narrows the bracket to the interval where the
 * share is reached. A set stops when its best plane is within TOLERANCE of its weight or its
 * bracket cannot narrow. Every decision reads reduced values only, so every caller takes the same
 * branches and makes the same reductions.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/decomp.h"
#include "mpi/exact_sums.h"

#define CANDIDATES 15  /* planes per round: the bracket shrinks 16-fold (4 bits) per reduction */
#define MAX_ROUNDS 16  /* 64 bits: more than a double's mantissa */
#define TOLERANCE 1e-4 /* of the set's weight: far below the 1.1 imbalance a run asks for */

typedef struct region {
    int parts, first; /* parts [first, first + parts) */
    double lo[3], hi[3];
    int parent, side; /* the node whose child this set is (-1: the root) */
} region;

typedef struct search {
    int axis, done;
    double a, b;     /* bracket of the plane */
    double cut, err; /* the best plane so far and |its weight below - target| */
    double total, target;
} search;

typedef struct work {
    region *cur, *next;
    search *s;
    int *active; /* region -> its index among the sets being cut, or -1 */
    int *first_child;
    int *where; /* point -> region */
    double *ext, *cand;
    sinter_repro_sum *sums;
    int64_t *scratch;
} work;

static void work_free(work *w)
{
    free(w->cur);
    free(w->next);
    free(w->s);
    free(w->active);
    free(w->first_child);
    free(w->where);
    free(w->ext);
    free(w->cand);
    free(w->sums);
    free(w->scratch);
}

static int work_alloc(work *w, size_t parts, size_t n)
{
    const size_t bins = (CANDIDATES + 1) * parts;
    w->cur = malloc(parts * sizeof *w->cur);
    w->next = malloc(parts * sizeof *w->next);
    w->s = malloc(parts * sizeof *w->s);
    w->active = malloc(parts * sizeof *w->active);
    w->first_child = malloc(parts * sizeof *w->first_child);
    w->where = malloc((n > 0 ? n : 1) * sizeof *w->where);
    w->ext = malloc(6 * parts * sizeof *w->ext);
    w->cand = malloc(CANDIDATES * parts * sizeof *w->cand);
    w->sums = malloc(bins * sizeof *w->sums);
    w->scratch = malloc(SINTER_REPRO_LIMBS * bins * sizeof *w->scratch);
    return w->cur && w->next && w->s && w->active && w->first_child && w->where && w->ext &&
           w->cand && w->sums && w->scratch;
}

static int longest_axis(const double *len)
{
    int axis = 0;
    for (int a = 1; a < 3; ++a)
        if (len[a] > len[axis])
            axis = a;
    return axis;
}

static double clamp(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* The extents of the sets' points (one MIN, one MAX reduction), the axis and first bracket. */
static sinter_status start_searches(work *w, int nregions, int nactive, const double *pos, size_t n,
                                    sinter_mpi_reduce_fn reduce, void *user)
{
    double *min = w->ext, *max = w->ext + 3 * (size_t)nactive;
    for (size_t k = 0; k < 3 * (size_t)nactive; ++k) {
        min[k] = INFINITY;
        max[k] = -INFINITY;
    }
    for (size_t i = 0; i < n; ++i) {
        const int k = w->active[w->where[i]];
        if (k < 0)
            continue;
        for (int a = 0; a < 3; ++a) {
            min[3 * k + a] = fmin(min[3 * k + a], pos[3 * i + a]);
            max[3 * k + a] = fmax(max[3 * k + a], pos[3 * i + a]);
        }
    }
    if (reduce != NULL && nactive > 0) {
        int rc = reduce(min, 3 * (size_t)nactive, SINTER_MPI_F64, SINTER_MPI_MIN, user);
        if (rc == 0)
            rc = reduce(max, 3 * (size_t)nactive, SINTER_MPI_F64, SINTER_MPI_MAX, user);
        if (rc != 0)
            return (sinter_status)rc;
    }
    for (int r = 0; r < nregions; ++r) {
        const int k = w->active[r];
        if (k < 0)
            continue;
        const region *g = &w->cur[r];
        double len[3];
        for (int a = 0; a < 3; ++a) /* a set without points: its box */
            len[a] = min[3 * k + a] <= max[3 * k + a] ? max[3 * k + a] - min[3 * k + a]
                                                      : g->hi[a] - g->lo[a];
        search *s = &w->s[k];
        s->axis = longest_axis(len);
        const int ax = s->axis;
        const int empty = !(min[3 * k + ax] <= max[3 * k + ax]);
        s->a = empty ? g->lo[ax] : clamp(min[3 * k + ax], g->lo[ax], g->hi[ax]);
        s->b = empty ? g->hi[ax] : clamp(max[3 * k + ax], g->lo[ax], g->hi[ax]);
        s->cut = 0.5 * (s->a + s->b);
        s->err = INFINITY;
        s->done = 0;
    }
    return SINTER_OK;
}

/* One round of multisection for every set not done; *all_done = 1 when none is left. */
static sinter_status search_round(work *w, int round, int nregions, int nactive, const double *pos,
                                  const double *weights, size_t n, int e,
                                  sinter_mpi_reduce_fn reduce, void *user, int *all_done)
{
    const size_t stride = CANDIDATES + 1;
    memset(w->sums, 0, stride * (size_t)nactive * sizeof *w->sums);
    for (int k = 0; k < nactive; ++k) {
        const search *s = &w->s[k];
        for (int j = 0; j < CANDIDATES; ++j)
            w->cand[CANDIDATES * k + j] = s->a + (s->b - s->a) * (j + 1) / (CANDIDATES + 1);
    }
    const double one = 1.0;
    for (size_t i = 0; i < n; ++i) {
        const int k = w->active[w->where[i]];
        if (k < 0 || w->s[k].done)
            continue;
        const double x = pos[3 * i + w->s[k].axis];
        const double *c = w->cand + CANDIDATES * k;
        int lo = 0, hi = CANDIDATES; /* the first j with x < c[j]; CANDIDATES: none */
        while (lo < hi) {
            const int mid = (lo + hi) / 2;
            if (x < c[mid])
                hi = mid;
            else
                lo = mid + 1;
        }
        sinter_repro_add(&w->sums[stride * k + lo], e, weights != NULL ? &weights[i] : &one, 1, 1);
    }
    const sinter_status st =
        sinter_mpi_bins_reduce(w->sums, stride * (size_t)nactive, w->scratch, reduce, user);
    if (st != SINTER_OK)
        return st;
    *all_done = 1;
    for (int r = 0; r < nregions; ++r) {
        const int k = w->active[r];
        if (k < 0 || w->s[k].done)
            continue;
        search *s = &w->s[k];
        const region *g = &w->cur[r];
        double below[CANDIDATES + 1];
        sinter_repro_sum run = {{0}, 0};
        for (int j = 0; j <= CANDIDATES; ++j) { /* prefix sums in the limbs: exact */
            sinter_repro_merge(&run, &w->sums[stride * k + j]);
            below[j] = sinter_repro_value(&run, e);
        }
        if (round == 0) {
            s->total = below[CANDIDATES];
            s->target = s->total * (g->parts / 2) / g->parts;
            if (!(s->total > 0.0)) { /* no weight: the middle of the box's longest side */
                const double len[3] = {g->hi[0] - g->lo[0], g->hi[1] - g->lo[1],
                                       g->hi[2] - g->lo[2]};
                s->axis = longest_axis(len);
                s->cut = 0.5 * (g->lo[s->axis] + g->hi[s->axis]);
                s->done = 1;
                continue;
            }
        }
        const double *c = w->cand + CANDIDATES * k;
        int reach = CANDIDATES; /* the first plane with the share below it */
        for (int j = 0; j < CANDIDATES; ++j) {
            const double err = fabs(below[j] - s->target);
            if (err < s->err) {
                s->err = err;
                s->cut = c[j];
            }
            if (reach == CANDIDATES && below[j] >= s->target)
                reach = j;
        }
        const double a = reach == 0 ? s->a : c[reach - 1];
        const double b = reach == CANDIDATES ? s->b : c[reach];
        if (s->err <= TOLERANCE * s->total || !(a < b) || (a == s->a && b == s->b))
            s->done = 1;
        s->a = a;
        s->b = b;
        if (!s->done)
            *all_done = 0;
    }
    return SINTER_OK;
}

/* Make the level's cuts nodes of the tree and their two sides the next level's sets. */
static int split_level(sinter_mpi_decomp *d, work *w, int nregions, int *nodes, const double *pos,
                       size_t n)
{
    int next = 0;
    for (int r = 0; r < nregions; ++r) {
        const region *g = &w->cur[r];
        const int k = w->active[r];
        w->first_child[r] = next;
        if (k < 0) {
            w->next[next++] = *g;
            continue;
        }
        search *s = &w->s[k];
        const int node = (*nodes)++;
        const double cut = clamp(s->cut, g->lo[s->axis], g->hi[s->axis]);
        s->cut = cut; /* the points below follow the node's comparison */
        d->axis[node] = s->axis;
        d->cut[node] = cut;
        if (g->parent >= 0)
            d->child[2 * g->parent + g->side] = node;
        const int left = g->parts / 2;
        for (int side = 0; side < 2; ++side) {
            region *c = &w->next[next++];
            *c = *g;
            c->parts = side == 0 ? left : g->parts - left;
            c->first = side == 0 ? g->first : g->first + left;
            if (side == 0)
                c->hi[s->axis] = cut;
            else
                c->lo[s->axis] = cut;
            c->parent = node;
            c->side = side;
            if (c->parts == 1) {
                d->child[2 * node + side] = -(c->first + 1);
                memcpy(d->box + 6 * (size_t)c->first, c->lo, sizeof c->lo);
                memcpy(d->box + 6 * (size_t)c->first + 3, c->hi, sizeof c->hi);
            }
        }
    }
    for (size_t i = 0; i < n; ++i) {
        const int r = w->where[i];
        const int k = w->active[r];
        w->where[i] =
            w->first_child[r] + (k >= 0 && !(pos[3 * i + w->s[k].axis] < w->s[k].cut) ? 1 : 0);
    }
    return next;
}

sinter_status sinter_mpi_decomp_rcb(sinter_mpi_decomp **out, int parts, const double lo[3],
                                    const double hi[3], const double *positions,
                                    const double *weights, size_t n, sinter_mpi_reduce_fn reduce,
                                    void *user)
{
    if (out == NULL || lo == NULL || hi == NULL || (positions == NULL && n > 0))
        return SINTER_ERR_NULL;
    *out = NULL;
    if (parts < 1 || !sinter_mpi_box_valid(lo, hi))
        return SINTER_ERR_INVALID;
    sinter_mpi_decomp *d = NULL;
    work w = {0};
    int bad = 0;
    const int e = sinter_mpi_weights_exponent(weights, n, &bad);
    for (size_t k = 0; k < 3 * n; ++k)
        if (!isfinite(positions[k]))
            bad = 1;
    const int ok = sinter_mpi_decomp_alloc(&d, SINTER_MPI_DECOMP_RCB, parts, lo, hi) == SINTER_OK &&
                   work_alloc(&w, (size_t)parts, n);
    /* every caller learns of an error anywhere before the cuts: [exponent, bad input, nomem] */
    int64_t agree[3] = {e, bad, !ok};
    sinter_status st = sinter_mpi_agree_max(agree, 3, reduce, user);
    if (st == SINTER_OK && agree[2])
        st = SINTER_ERR_NOMEM;
    else if (st == SINTER_OK && agree[1])
        st = SINTER_ERR_INVALID;
    if (st == SINTER_OK) {
        w.cur[0] = (region){parts, 0, {lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, -1, 0};
        memcpy(d->box, lo, 3 * sizeof *lo);
        memcpy(d->box + 3, hi, 3 * sizeof *hi);
        for (size_t i = 0; i < n; ++i)
            w.where[i] = 0;
    }
    int nregions = 1, nodes = 0;
    while (st == SINTER_OK) {
        int nactive = 0;
        for (int r = 0; r < nregions; ++r)
            w.active[r] = w.cur[r].parts > 1 ? nactive++ : -1;
        if (nactive == 0)
            break;
        st = start_searches(&w, nregions, nactive, positions, n, reduce, user);
        int all_done = 0;
        for (int round = 0; st == SINTER_OK && round < MAX_ROUNDS && !all_done; ++round)
            st = search_round(&w, round, nregions, nactive, positions, weights, n, (int)agree[0],
                              reduce, user, &all_done);
        if (st != SINTER_OK)
            break;
        nregions = split_level(d, &w, nregions, &nodes, positions, n);
        region *t = w.cur;
        w.cur = w.next;
        w.next = t;
    }
    work_free(&w);
    if (st != SINTER_OK) {
        sinter_mpi_decomp_destroy(d);
        return st;
    }
    *out = d;
    return SINTER_OK;
}
