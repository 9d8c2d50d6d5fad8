/*
 * Per-contact history of one force submodel (tangential springs, rolling
 * springs, bonds). Committed history lives per candidate pair; an evaluation
 * writes trial history per active contact; commit copies trial into the pair
 * slots and clears pairs whose contact ended (the commit/rollback contract of
 * include/sinter_submodel.h: evaluation is pure, history is committed only when a step is
 * accepted).
 */
#ifndef SINTER_HISTORY_H
#define SINTER_HISTORY_H

#include "contact/contacts.h"

typedef struct sinter_history {
    size_t width;      /* doubles per contact */
    double *committed; /* width per candidate pair */
    size_t pair_capacity;
    double *trial; /* width per active contact */
    size_t trial_capacity;
    uint32_t *active; /* candidate pairs in contact at the last commit */
    size_t active_count;
    size_t active_capacity;
    double *scratch; /* remapping buffer */
    size_t scratch_capacity;
    /* set by a model for one evaluation: its trial history is indexed by candidate pair
     * (width per pair, contacts only written), so the commit swaps the arrays instead of
     * copying them; cleared by sinter_history_prepare */
    int by_pair;
    /* contact list revisions (sinter_contact_list.revision; 0: unknown) that let a commit
     * redo only what changed (issue 9): the list off whose pairs the committed array is
     * zero, the one whose pairs `active` copies, and the one off whose pairs the trial array
     * (by pair) was zero at the last commit; trial_written is the list the evaluations since
     * wrote it on by pair (0: none yet, SINTER_HISTORY_MIXED: another or by contact) */
    uint64_t committed_rev, active_rev, trial_clean_rev, trial_written, written_before;
} sinter_history;

#define SINTER_HISTORY_MIXED UINT64_MAX

/* The arrays were changed from outside (a restore, a remap): no revision is known to hold. */
static inline void sinter_history_forget(sinter_history *h)
{
    h->committed_rev = h->active_rev = h->trial_clean_rev = 0;
    h->trial_written = SINTER_HISTORY_MIXED;
}

void sinter_history_free(sinter_ctx *ctx, sinter_history *h);

/* Make room for trial history of `contacts` contacts, zeroed if `zero` (built-in models
 * write every entry, so they skip the zeroing; host models get zeros). */
sinter_status sinter_history_prepare(sinter_ctx *ctx, sinter_history *h, size_t contacts, int zero);

/* Let a model write trial history by candidate pair for this evaluation (pairs of `c`). */
sinter_status sinter_history_by_pair(sinter_ctx *ctx, sinter_history *h,
                                     const sinter_contact_list *c);

/* Accept the trial history of the active contacts `c`. */
sinter_status sinter_history_commit(sinter_ctx *ctx, sinter_history *h,
                                    const sinter_contact_list *c);

/* The memory sinter_history_commit needs for `c`, taken now: the commit that follows (same
 * list) cannot fail. */
sinter_status sinter_history_commit_reserve(sinter_ctx *ctx, sinter_history *h,
                                            const sinter_contact_list *c);

/* Carry committed history to a rebuilt pair list (pairs->from maps new to old). */
sinter_status sinter_history_remap(sinter_ctx *ctx, sinter_history *h, size_t old_pairs,
                                   const sinter_pair_list *pairs);

#endif
