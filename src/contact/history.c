/* Commit/rollback of per-contact history and its transfer across neighbour rebuilds. */
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "history.h"

void sinter_history_free(sinter_ctx *ctx, sinter_history *h)
{
    sinter_free(ctx, h->committed);
    sinter_free(ctx, h->trial);
    sinter_free(ctx, h->active);
    sinter_free(ctx, h->scratch);
    const size_t width = h->width;
    memset(h, 0, sizeof(*h));
    h->width = width;
}

sinter_status sinter_history_prepare(sinter_ctx *ctx, sinter_history *h, size_t contacts, int zero)
{
    h->by_pair = 0;
    /* an evaluation that does not declare its writes by pair (sinter_history_by_pair) writes
     * the trial array by contact */
    h->written_before = h->trial_written;
    h->trial_written = SINTER_HISTORY_MIXED;
    if (h->width == 0)
        return SINTER_OK;
    sinter_status st = sinter_grow(ctx, (void **)&h->trial, &h->trial_capacity,
                                   h->width * contacts + 1, sizeof(double));
    if (st == SINTER_OK && zero)
        memset(h->trial, 0, h->width * contacts * sizeof(double));
    return st;
}

sinter_status sinter_history_by_pair(sinter_ctx *ctx, sinter_history *h,
                                     const sinter_contact_list *c)
{
    /* The swap clears every pair out of contact; it pays where few are (packed beds), while
     * a sparse scene (more pairs in the skin than in contact) keeps the copy. */
    if (h->width == 0 || c->pair_to_contact == NULL || c->pair_count - c->count > c->count / 4)
        return SINTER_OK; /* stays indexed by contact */
    sinter_status st = sinter_grow(ctx, (void **)&h->trial, &h->trial_capacity,
                                   h->width * c->pair_count + 1, sizeof(double));
    if (st == SINTER_OK) {
        h->by_pair = 1;
        const uint64_t before = h->written_before;
        h->trial_written =
            before == 0 || before == c->revision ? c->revision : SINTER_HISTORY_MIXED;
    }
    return st;
}

/* commit_swap's two loops, on the threads of the enclosing region or, outside one, on the
 * calling thread (orphaned loops). */
static void swap_loops(double *trial, size_t w, const uint32_t *p2c, long zero_lo, long pairs,
                       uint32_t *active, const uint32_t *pair, long copy_lo, long count)
{
#pragma omp for schedule(static) nowait
    for (long p = zero_lo; p < pairs; ++p)
        if (p2c[p] == SINTER_NO_PAIR)
            for (size_t d = 0; d < w; ++d)
                trial[w * (size_t)p + d] = 0.0;
#pragma omp for schedule(static) nowait
    for (long k = copy_lo; k < count; ++k)
        active[k] = pair[k];
}

/* Commit of a trial array indexed by pair: pairs not in contact are cleared in it, and it
 * becomes the committed array; the old committed array is the next trial array (every entry
 * is written before the next commit). Only from where the contact list changed since the
 * trial array was last zero off its contacts (the list's revisions) are pairs cleared, and
 * `active` copied from where it changed since `active` was written: a packed bed whose
 * contacts change only near its top, or not at all, costs that much (issue 9). */
static void commit_swap(sinter_history *h, const sinter_contact_list *c, int threads)
{
    const size_t w = h->width;
    double *trial = h->trial;
    const uint32_t *p2c = c->pair_to_contact;
    uint32_t *active = h->active;
    const uint32_t *pair = c->pair;
    size_t zero_from = 0, copy_from = 0, unused;
    if (h->trial_written == 0 || h->trial_written == c->revision)
        sinter_contacts_changed_since(c, h->trial_clean_rev, &zero_from, &unused);
    sinter_contacts_changed_since(c, h->active_rev, &unused, &copy_from);
    const long zero_lo = zero_from < c->pair_count ? (long)zero_from : (long)c->pair_count;
    const long copy_lo = copy_from < c->count ? (long)copy_from : (long)c->count;
    const long pairs = (long)c->pair_count, count = (long)c->count;
    if (zero_lo < pairs || copy_lo < count) {
        if (threads > 1) {
#pragma omp parallel num_threads(threads)
            swap_loops(trial, w, p2c, zero_lo, pairs, active, pair, copy_lo, count);
        } else { /* a region of one thread costs a team (core/ranges_run.h) */
            swap_loops(trial, w, p2c, zero_lo, pairs, active, pair, copy_lo, count);
        }
    }
    double *t = h->committed;
    const size_t cap = h->pair_capacity;
    h->committed = trial;
    h->pair_capacity = h->trial_capacity;
    h->trial = t;
    h->trial_capacity = cap;
    h->active_count = c->count;
    h->trial_clean_rev = h->committed_rev; /* the old committed array, zero off its list */
    h->trial_written = 0;
    h->committed_rev = h->active_rev = c->revision;
}

/* Trial values of contacts [lo, hi) into their pairs' committed slots, and the pairs into
 * `active`; inline copies for the built-in widths (a call per contact costs more than the
 * copy). */
static inline void copy_trial(double *restrict committed, const double *restrict trial,
                              uint32_t *restrict active, const uint32_t *restrict pair, size_t w,
                              size_t lo, size_t hi)
{
    if (w == 3) {
        for (size_t k = lo; k < hi; ++k) {
            double *dst = committed + 3 * (size_t)pair[k];
            dst[0] = trial[3 * k];
            dst[1] = trial[3 * k + 1];
            dst[2] = trial[3 * k + 2];
            active[k] = pair[k];
        }
    } else if (w == 6) {
        for (size_t k = lo; k < hi; ++k) {
            double *dst = committed + 6 * (size_t)pair[k];
            for (int d = 0; d < 6; ++d)
                dst[d] = trial[6 * k + (size_t)d];
            active[k] = pair[k];
        }
    } else {
        for (size_t k = lo; k < hi; ++k) {
            memcpy(committed + (size_t)pair[k] * w, trial + k * w, w * sizeof(double));
            active[k] = pair[k];
        }
    }
}

/* sinter_history_commit's loops for a history indexed by contact, on the threads of the
 * enclosing region or, outside one, on the calling thread (orphaned loops). */
static void commit_loops(sinter_history *h, const sinter_contact_list *c, long ended, long count,
                         int runs)
{
    const size_t w = h->width;
    double *restrict committed = h->committed;
    const double *restrict trial = h->trial;
    uint32_t *restrict active = h->active;
    const uint32_t *p2c = c->pair_to_contact;
    const size_t *qlo = c->chunks.qlo;
#pragma omp for schedule(static) /* the barrier: the copies overwrite `active` */
    for (long k = 0; k < ended; ++k)
        if (p2c == NULL || p2c[active[k]] == SINTER_NO_PAIR)
            memset(committed + (size_t)active[k] * w, 0, w * sizeof(double));
    if (runs > 1) {
#pragma omp for schedule(static)
        for (int r = 0; r < runs; ++r)
            copy_trial(committed, trial, active, c->pair, w, qlo[r], qlo[r + 1]);
    } else {
#ifdef _OPENMP
        const long t = omp_get_thread_num(), nt = omp_get_num_threads();
#else
        const long t = 0, nt = 1;
#endif
        copy_trial(committed, trial, active, c->pair, w, (size_t)(count * t / nt),
                   (size_t)(count * (t + 1) / nt));
    }
}

sinter_status sinter_history_commit_reserve(sinter_ctx *ctx, sinter_history *h,
                                            const sinter_contact_list *c)
{
    if (h->width == 0)
        return SINTER_OK;
    return sinter_grow(ctx, (void **)&h->active, &h->active_capacity, c->count + 1,
                       sizeof(uint32_t));
}

sinter_status sinter_history_commit(sinter_ctx *ctx, sinter_history *h,
                                    const sinter_contact_list *c)
{
    if (h->width == 0)
        return SINTER_OK;
    sinter_status st =
        sinter_grow(ctx, (void **)&h->active, &h->active_capacity, c->count + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    if (h->by_pair) {
        commit_swap(h, c, c->pair_count < 4096 ? 1 : sinter_threads(ctx));
        return SINTER_OK;
    }
    /* Clear the pairs whose contact ended; the others are overwritten just below. Each loop
     * writes distinct pairs (a pair is active once and in contact once), and the two loops
     * write disjoint pairs, so the threads need no order in either. The copies go by the
     * list's runs where it has them (contact/chunks.h: a pair list's ranges), so that each
     * thread copies the trial values its share of the law wrote, at any size (issue 9); else
     * by equal shares from 4096 contacts. */
    const long ended = (long)h->active_count, count = (long)c->count;
    const int runs = c->chunks.count > 0 ? c->chunks.count : 1;
    const int allowed = sinter_threads(ctx);
    const int threads = runs > 1 ? (allowed < runs ? allowed : runs) : count < 4096 ? 1 : allowed;
    if (threads > 1) {
#pragma omp parallel num_threads(threads)
        commit_loops(h, c, ended, count, runs);
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        commit_loops(h, c, ended, count, runs);
    }
    h->active_count = c->count;
    h->committed_rev = h->active_rev = c->revision;
    h->trial_clean_rev = 0; /* indexed by contact */
    h->trial_written = SINTER_HISTORY_MIXED;
    return SINTER_OK;
}

sinter_status sinter_history_remap(sinter_ctx *ctx, sinter_history *h, size_t old_pairs,
                                   const sinter_pair_list *pairs)
{
    if (h->width == 0)
        return SINTER_OK;
    const size_t w = h->width, n = pairs->count;
    /* old -> new map, then move the active pairs' history into a zeroed buffer. */
    sinter_status st = sinter_grow(ctx, (void **)&h->scratch, &h->scratch_capacity,
                                   w * n + old_pairs + 1, sizeof(double));
    if (st != SINTER_OK)
        return st;
    double *fresh = h->scratch;
    uint32_t *old_to_new = (uint32_t *)(h->scratch + w * n);
    memset(fresh, 0, w * n * sizeof(double));
    for (size_t p = 0; p < old_pairs; ++p)
        old_to_new[p] = SINTER_NO_PAIR;
    for (size_t q = 0; q < n; ++q)
        if (pairs->from[q] != SINTER_NO_PAIR)
            old_to_new[pairs->from[q]] = (uint32_t)q;
    size_t kept = 0;
    for (size_t k = 0; k < h->active_count; ++k) {
        const uint32_t q = old_to_new[h->active[k]];
        if (q == SINTER_NO_PAIR)
            continue; /* the pair left the list, so it was not in contact any more */
        memcpy(fresh + (size_t)q * w, h->committed + (size_t)h->active[k] * w, w * sizeof(double));
        h->active[kept++] = q;
    }
    h->active_count = kept;
    sinter_history_forget(h); /* new pair indices */
    /* swap buffers: the old committed array becomes scratch */
    double *old = h->committed;
    size_t old_cap = h->pair_capacity;
    h->committed = h->scratch;
    h->pair_capacity = h->scratch_capacity;
    h->scratch = old;
    h->scratch_capacity = old_cap;
    return SINTER_OK;
}
