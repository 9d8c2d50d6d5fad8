/*
 * The reproducible mode's order of the candidate pairs (issue 43, stepper option
 * "reproducible"): a pair list sorted by its keys (the smaller id, then the larger; a wall
 * pair by particle id, then wall index), so that the contacts, and with them every particle's
 * sums of forces, moments and heat powers, come in an order fixed by the ids alone: not by
 * the particles' places in memory, the cell grid of the subdomain's bounding box or how the
 * body is split into subdomains. A particle p then receives its pair terms in ascending order
 * of its partners' ids (the pairs (q, p) with q < p first, then the pairs (p, q)), whether
 * both ends are owned here (newton on) or one is a ghost (newton off: the pair is evaluated
 * on both sides, in the same place of both sides' order).
 */
#ifndef SINTER_CANONICAL_ORDER_H
#define SINTER_CANONICAL_ORDER_H

#include "contact/neighbors.h"

/* Sort l's pairs (i, j, key_i, key_j; `from` is written later by the build's matching) by
 * (key_i, key_j), ties by (i, j); *scratch / *capacity: a buffer kept by the caller between
 * builds. Sets l->canonical. */
sinter_status sinter_pairs_sort_by_keys(sinter_ctx *ctx, sinter_pair_list *l, void **scratch,
                                        size_t *capacity);

#endif
