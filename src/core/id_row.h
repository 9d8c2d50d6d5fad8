/*
 * A particle id and its row, sorted by id (qsort) to find a particle by its id (bsearch): the
 * table that the VTP writer, the coarse-graining of snapshots and the MPI command-line runner
 * each build. Header-only so that the runner, which sees only the shared library's public API,
 * uses the same comparison.
 */
#ifndef SINTER_CORE_ID_ROW_H
#define SINTER_CORE_ID_ROW_H

#include <stddef.h>
#include <stdint.h>

typedef struct sinter_id_row {
    uint64_t id;
    size_t index;
} sinter_id_row;

/* qsort/bsearch order of sinter_id_row by id (ascending). */
static inline int sinter_id_row_compare(const void *a, const void *b)
{
    const uint64_t x = ((const sinter_id_row *)a)->id, y = ((const sinter_id_row *)b)->id;
    return (x > y) - (x < y);
}

#endif
