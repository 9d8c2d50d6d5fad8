/*
 * The network model's warm start follows the particles by id (network.c).
 *
 * A solve starts from the potentials of the last one. Those are kept by node, and node p < n is
 * particle row p; a reordering of the particles between two solves (the stepper option
 * sort_interval, sinter_particles_sort_spatial, a host that rebuilds its set in another order)
 * would hand each particle another particle's potential, a worse start and so other iteration
 * counts and other bits than the same run without the reordering. So the model keeps the ids of
 * its last solve's particle nodes and, when the ids of the rows differ from them, moves each
 * potential to its particle's new row first. A particle id the last solve did not have (the
 * count stayed but the set changed) makes the solve start from 0, as a change of count does.
 *
 * Potentials restored without ids (a checkpoint, sinter_stepper_import) are taken by row: they
 * were written in the order of the rows they are read back into.
 */
#include <stdlib.h>
#include <string.h>

#include "electric.h"

/* (id, row) pairs by ascending id (qsort). */
static int id_row_compare(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* The row of the last solve that held `id`, or SIZE_MAX: binary search in the n pairs. */
static size_t old_row(const uint64_t *pairs, size_t n, uint64_t id)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (pairs[2 * mid] < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && pairs[2 * lo] == id ? (size_t)pairs[2 * lo + 1] : SIZE_MAX;
}

sinter_status sinter_electric_warm_follow(sinter_electric_model *em, const sinter_particles *ps,
                                          size_t n, size_t nodes)
{
    if (em->warm_nodes != nodes || em->warm_id_count != n)
        return SINTER_OK; /* no warm start, or one restored by row */
    size_t p = 0;
    while (p < n && ps->id[p] == em->warm_id[p])
        ++p;
    if (p == n)
        return SINTER_OK; /* the same order: nothing moves (the usual case) */
    SINTER_ELECTRIC_RESERVE(em, warm_pairs, 2 * n + 2);
    SINTER_ELECTRIC_RESERVE(em, warm_moved, n + 1);
    for (size_t k = 0; k < n; ++k) {
        em->warm_pairs[2 * k] = em->warm_id[k];
        em->warm_pairs[2 * k + 1] = (uint64_t)k;
    }
    qsort(em->warm_pairs, n, 2 * sizeof(uint64_t), id_row_compare);
    for (size_t k = 0; k < n; ++k) {
        const size_t from = old_row(em->warm_pairs, n, ps->id[k]);
        if (from == SIZE_MAX) {
            em->warm_nodes = 0; /* another set of particles: start from 0 */
            return SINTER_OK;
        }
        em->warm_moved[k] = em->potential[from];
    }
    memcpy(em->potential, em->warm_moved, n * sizeof(double)); /* walls keep their nodes */
    memcpy(em->warm_id, ps->id, n * sizeof(uint64_t));
    return SINTER_OK;
}

sinter_status sinter_electric_warm_record_ids(sinter_electric_model *em, const sinter_particles *ps,
                                              size_t n)
{
    em->warm_id_count = 0;
    SINTER_ELECTRIC_RESERVE(em, warm_id, n + 1);
    memcpy(em->warm_id, ps->id, n * sizeof(uint64_t));
    em->warm_id_count = n;
    return SINTER_OK;
}
