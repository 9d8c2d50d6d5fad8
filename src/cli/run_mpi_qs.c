/*
 * The quasi-static stepper under `mpiexec -n N sinter run` (issue 44): the series columns that
 * the serial runner writes for it, formed on the ranks.
 *  - The sintering columns (links, neck radius mean/min/max, neck ratio mean, shrinkage x/y/z,
 *    relative density; seed 001 sec. 4) from sinter_stepper_sintering_stats, which is
 *    collective with domain operations: the library reduces the neck sums and the shrinkage's
 *    regression sums over every rank, so each rank receives the same bits, and one rank the
 *    serial bits.
 *  - The contacts, the coordination number and the solid fraction's lenses from the links: a
 *    link lives on the rank that owns its smaller id (its other end may be a ghost there), so
 *    each rank's snapshot lists every link once, and the runner sums the ranks' counts and
 *    lens volumes exactly (sinter_mpi_reduce). The serial runner counts instead the pairs that
 *    overlapped when the forces were last evaluated (at the start of the advance call, one
 *    sample behind) and subtracts the lenses of the neighbour list's pairs in its order: its
 *    contacts column lags the links by a sample and its solid fraction differs in the last
 *    bits (the same lenses summed in another order; a pair that overlaps becomes a link at the
 *    next step, qs_new_contacts).
 */
#include "run_mpi_qs.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sphere_volume.h"

void cli_mpi_qs_header(FILE *csv)
{
    fputs(",links [1],neck radius mean [m],neck radius min [m],neck radius max [m],neck ratio "
          "mean [1],shrinkage x [1],shrinkage y [1],shrinkage z [1],relative density [1]",
          csv);
}

int cli_mpi_qs_sintering(sinter_stepper *st, double solid, const double lo[3], const double hi[3],
                         double q[CLI_MPI_QS_COLUMNS])
{
    sinter_sintering_stats s;
    memset(&s, 0, sizeof(s));
    s.struct_size = sizeof(s);
    /* refused alike on every rank before the first step (no stepper state yet) */
    if (sinter_stepper_sintering_stats(st, &s) != SINTER_OK) {
        memset(&s, 0, sizeof(s));
        s.relative_density = solid / ((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]));
    }
    const double v[CLI_MPI_QS_COLUMNS] = {(double)s.links, s.neck_mean,       s.neck_min,
                                          s.neck_max,      s.neck_ratio_mean, s.shrinkage[0],
                                          s.shrinkage[1],  s.shrinkage[2],    s.relative_density};
    memcpy(q, v, sizeof(v));
    return 1;
}

static int row_of(const sinter_id_row *table, size_t n, uint64_t id, size_t *index)
{
    const sinter_id_row key = {id, 0};
    const sinter_id_row *hit =
        bsearch(&key, table, n, sizeof(sinter_id_row), sinter_id_row_compare);
    if (hit != NULL)
        *index = hit->index;
    return hit != NULL;
}

/* The sweep's order: rows by the lower end of their sphere along x. */
typedef struct swept {
    double lo;
    size_t row;
} swept;

static int swept_order(const void *a, const void *b)
{
    const swept *p = a, *q = b;
    if (p->lo != q->lo)
        return p->lo < q->lo ? -1 : 1;
    return (p->row > q->row) - (p->row < q->row);
}

/* Before the first step: the overlapping pairs with an end owned here whose smaller id is
 * owned here, by a sweep along x (the rows sorted by x - r; a pair overlaps along x first). */
static int overlaps(const sinter_id_row *table, size_t rows, size_t owned, const double *x,
                    const double *radius, double *volume, double *pairs)
{
    swept *order = malloc((rows + 1) * sizeof(swept));
    uint64_t *id = malloc((rows + 1) * sizeof(uint64_t));
    if (order == NULL || id == NULL) {
        free(order);
        free(id);
        return 0;
    }
    for (size_t k = 0; k < rows; ++k)
        id[table[k].index] = table[k].id;
    for (size_t i = 0; i < rows; ++i) {
        order[i].lo = x[3 * i] - radius[i];
        order[i].row = i;
    }
    qsort(order, rows, sizeof(swept), swept_order);
    for (size_t p = 0; p < rows; ++p) {
        const size_t i = order[p].row;
        /* a margin of 1e-9 r over the rounding of x +- r: the test below decides */
        const double hi = x[3 * i] + radius[i] * (1.0 + 1e-9);
        for (size_t q = p + 1; q < rows && order[q].lo <= hi; ++q) {
            const size_t j = order[q].row;
            if ((id[i] < id[j] ? i : j) >= owned)
                continue; /* no end owned here, or the other rank owns the smaller id */
            const double *a = x + 3 * i, *b = x + 3 * j;
            const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
            /* the contact search's test (contact/contacts.c): d^2 < (r_i + r_j)^2, d > 0 */
            const double d2 = dx * dx + dy * dy + dz * dz, rs = radius[i] + radius[j];
            if (!(d2 < rs * rs) || d2 == 0.0)
                continue;
            *volume -= sinter_sphere_lens_volume(radius[i], radius[j], sqrt(d2));
            *pairs += 1.0;
        }
    }
    free(order);
    free(id);
    return 1;
}

int cli_mpi_qs_lenses(const sinter_stepper *st, const sinter_id_row *table, size_t rows,
                      size_t owned, const double *x, const double *radius, double *volume,
                      double *links)
{
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    if (sinter_stepper_get_stats(st, &stats) != SINTER_OK)
        return 0;
    if (stats.steps == 0) /* the same on every rank */
        return overlaps(table, rows, owned, x, radius, volume, links);
    sinter_snapshot *snap = NULL;
    if (sinter_snapshot_create(&snap, st) != SINTER_OK)
        return 0;
    const uint64_t *ida = NULL, *idb = NULL;
    size_t count = 0;
    int ok = sinter_snapshot_counts(snap, NULL, NULL, &count, NULL) == SINTER_OK &&
             sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, (const void **)&ida, NULL, NULL,
                                   NULL) == SINTER_OK &&
             sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, (const void **)&idb, NULL, NULL,
                                   NULL) == SINTER_OK;
    for (size_t k = 0; ok && k < count; ++k) {
        size_t i = 0, j = 0;
        ok = row_of(table, rows, ida[k], &i) && row_of(table, rows, idb[k], &j);
        if (!ok)
            break;
        const double *a = x + 3 * i, *b = x + 3 * j;
        const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        *volume -=
            sinter_sphere_lens_volume(radius[i], radius[j], sqrt(dx * dx + dy * dy + dz * dz));
        *links += 1.0;
    }
    sinter_snapshot_destroy(snap);
    return ok;
}
