/*
 * An order of the particles for the bonded solve's block SSOR sweeps (bonded/block_ssor.h) in
 * which two threads can sweep at once: two domains A and B that no link joins, then a
 * separator S holding every particle between them,
 *
 *     new order = A, B, S:   A = [0, split_a),  B = [split_a, split_b),  S = [split_b, n).
 *
 * A backward sweep then does S first and A and B side by side; a forward sweep A and B side by
 * side and S last (block_ssor.c). The domains come from a breadth-first level structure of the
 * link graph, rooted at a pseudo-peripheral particle of each component (George and Liu,
 * ACM TOMS 5 (1979) 284-295): a link joins particles of the same or of neighbouring levels,
 * so one level L separates the levels below it (A) from those above (B). Only the particles of
 * L with a neighbour in level L + 1 need to stay in S; the others join A. L is the level that
 * gives the sweeps the shortest longest path, max(work of A, work of B) + work of S, where a
 * particle's work is 3 + its number of links (block products per sweep). Within each part the
 * particles keep the breadth-first order, which puts linked particles near each other in the
 * sweeps, as a spatial order would.
 *
 * The order depends on the links alone (their particles and their order), never on the number
 * of threads, so the sweeps and the solve give the same bits on any number of threads. It
 * depends on how the particles are numbered (the roots and ties of the searches go by number):
 * the quasi-static stepper numbers them by ascending id and lists its links in an order of ids
 * (stepper/qs_ids.c), so the order follows the ids, whatever the particles' places in memory.
 */
#ifndef SINTER_BONDED_DOMAIN_ORDER_H
#define SINTER_BONDED_DOMAIN_ORDER_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

typedef struct sinter_domain_order {
    sinter_ctx *ctx;
    uint32_t *new_of_old; /* per particle: its place in the new order */
    uint32_t *old_of_new; /* per place: the particle there */
    size_t split_a, split_b;
    /* scratch: the link graph's adjacency, levels, the breadth-first queue */
    size_t *adjacency_start;
    uint32_t *adjacency, *level, *queue;
    size_t *level_work; /* per level: its work, then the work that stays in S */
    size_t new_of_old_capacity, old_of_new_capacity, adjacency_start_capacity, adjacency_capacity,
        level_capacity, queue_capacity, level_work_capacity;
} sinter_domain_order;

void sinter_domain_order_release(sinter_domain_order *o);

/* Order n particles joined by `count` links (links[k] joins lower[k] and upper[k], distinct,
 * both < n): fills o->new_of_old, o->old_of_new, o->split_a and o->split_b. Errors:
 * SINTER_ERR_NOMEM. */
sinter_status sinter_domain_order_make(sinter_domain_order *o, size_t n, const uint32_t *lower,
                                       const uint32_t *upper, size_t count);

#endif
