/*
 * Decompositions of space into parts (libsinter_mpi, issue 44): the object, ownership of points,
 * the parts' loads, the imbalance metric and rebalancing above a threshold. The brick's grid is
 * in brick.c, the recursive coordinate bisection in rcb.c.
 */
#include "mpi/decomp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/exact_sums.h"

int sinter_mpi_box_valid(const double lo[3], const double hi[3])
{
    for (int a = 0; a < 3; ++a)
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || !(lo[a] < hi[a]))
            return 0;
    return 1;
}

sinter_status sinter_mpi_decomp_alloc(sinter_mpi_decomp **out, int kind, int parts,
                                      const double lo[3], const double hi[3])
{
    sinter_mpi_decomp *d = calloc(1, sizeof *d);
    if (d == NULL)
        return SINTER_ERR_NOMEM;
    d->kind = kind;
    d->parts = parts;
    memcpy(d->lo, lo, sizeof d->lo);
    memcpy(d->hi, hi, sizeof d->hi);
    const size_t p = (size_t)parts;
    d->box = malloc(6 * p * sizeof *d->box);
    d->plane_store = malloc((3 * p + 3) * sizeof *d->plane_store);
    d->axis = malloc(p * sizeof *d->axis);
    d->cut = malloc(p * sizeof *d->cut);
    d->child = malloc(2 * p * sizeof *d->child);
    if (d->box == NULL || d->plane_store == NULL || d->axis == NULL || d->cut == NULL ||
        d->child == NULL) {
        sinter_mpi_decomp_destroy(d);
        return SINTER_ERR_NOMEM;
    }
    *out = d;
    return SINTER_OK;
}

void sinter_mpi_decomp_destroy(sinter_mpi_decomp *d)
{
    if (d == NULL)
        return;
    free(d->box);
    free(d->plane_store);
    free(d->axis);
    free(d->cut);
    free(d->child);
    free(d);
}

sinter_status sinter_mpi_decomp_info(const sinter_mpi_decomp *d, int *kind, int *parts)
{
    if (d == NULL || (kind == NULL && parts == NULL))
        return SINTER_ERR_NULL;
    if (kind != NULL)
        *kind = d->kind;
    if (parts != NULL)
        *parts = d->parts;
    return SINTER_OK;
}

sinter_status sinter_mpi_decomp_grid(const sinter_mpi_decomp *d, int grid[3])
{
    if (d == NULL || grid == NULL)
        return SINTER_ERR_NULL;
    if (d->kind != SINTER_MPI_DECOMP_BRICK)
        return SINTER_ERR_STATE;
    memcpy(grid, d->grid, sizeof d->grid);
    return SINTER_OK;
}

sinter_status sinter_mpi_decomp_box(const sinter_mpi_decomp *d, int part, double lo[3],
                                    double hi[3])
{
    if (d == NULL || lo == NULL || hi == NULL)
        return SINTER_ERR_NULL;
    if (part < 0 || part >= d->parts)
        return SINTER_ERR_RANGE;
    memcpy(lo, d->box + 6 * (size_t)part, 3 * sizeof *lo);
    memcpy(hi, d->box + 6 * (size_t)part + 3, 3 * sizeof *hi);
    return SINTER_OK;
}

/* The slab of a brick axis holding x: the largest i with planes[i] <= x, within [0, g). */
static int brick_slab(const double *planes, int g, double x)
{
    int lo = 0, hi = g - 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (planes[mid] <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

int sinter_mpi_decomp_owner(const sinter_mpi_decomp *d, const double x[3])
{
    if (d->kind == SINTER_MPI_DECOMP_BRICK) {
        int i[3];
        for (int a = 0; a < 3; ++a)
            i[a] = brick_slab(d->planes[a], d->grid[a], x[a]);
        return (i[0] * d->grid[1] + i[1]) * d->grid[2] + i[2];
    }
    if (d->parts == 1)
        return 0;
    int node = 0;
    for (;;) {
        const int c = d->child[2 * node + (x[d->axis[node]] < d->cut[node] ? 0 : 1)];
        if (c < 0)
            return -(c + 1);
        node = c;
    }
}

sinter_status sinter_mpi_decomp_owners(const sinter_mpi_decomp *d, const double *positions,
                                       size_t n, int *parts)
{
    if (d == NULL || ((positions == NULL || parts == NULL) && n > 0))
        return SINTER_ERR_NULL;
    for (size_t k = 0; k < n; ++k)
        parts[k] = sinter_mpi_decomp_owner(d, positions + 3 * k);
    return SINTER_OK;
}

/* The loads; `loads` NULL: this caller ran out of memory, and still takes part in the reductions
 * (every caller then returns SINTER_ERR_NOMEM). */
static sinter_status loads_collective(const sinter_mpi_decomp *d, const double *positions,
                                      const double *weights, size_t n, sinter_mpi_reduce_fn reduce,
                                      void *user, double *loads)
{
    const size_t p = (size_t)d->parts;
    sinter_repro_sum *sums = calloc(p, sizeof *sums);
    int64_t *scratch = malloc(SINTER_REPRO_LIMBS * p * sizeof *scratch);
    int bad = 0;
    /* every caller learns of an error anywhere before the sums: [exponent, bad weight, nomem] */
    int64_t agree[3] = {sinter_mpi_weights_exponent(weights, n, &bad), bad,
                        sums == NULL || scratch == NULL || loads == NULL};
    sinter_status st = sinter_mpi_agree_max(agree, 3, reduce, user);
    if (st == SINTER_OK && agree[2])
        st = SINTER_ERR_NOMEM;
    else if (st == SINTER_OK && agree[1])
        st = SINTER_ERR_INVALID;
    if (st == SINTER_OK) {
        const int e = (int)agree[0];
        const double one = 1.0;
        for (size_t k = 0; k < n; ++k)
            sinter_repro_add(&sums[sinter_mpi_decomp_owner(d, positions + 3 * k)], e,
                             weights != NULL ? &weights[k] : &one, 1, 1);
        st = sinter_mpi_bins_reduce(sums, p, scratch, reduce, user);
        for (size_t b = 0; st == SINTER_OK && b < p; ++b)
            loads[b] = sinter_repro_value(&sums[b], e);
    }
    free(sums);
    free(scratch);
    return st;
}

sinter_status sinter_mpi_decomp_loads(const sinter_mpi_decomp *d, const double *positions,
                                      const double *weights, size_t n, sinter_mpi_reduce_fn reduce,
                                      void *user, double *loads)
{
    if (d == NULL || loads == NULL || (positions == NULL && n > 0))
        return SINTER_ERR_NULL;
    return loads_collective(d, positions, weights, n, reduce, user, loads);
}

sinter_status sinter_mpi_imbalance(const double *loads, int parts, double *imbalance)
{
    if (loads == NULL || imbalance == NULL)
        return SINTER_ERR_NULL;
    if (parts < 1)
        return SINTER_ERR_INVALID;
    double sum = 0.0, max = 0.0;
    for (int k = 0; k < parts; ++k) {
        if (!(loads[k] >= 0.0) || !isfinite(loads[k]))
            return SINTER_ERR_INVALID;
        sum += loads[k];
        max = loads[k] > max ? loads[k] : max;
    }
    *imbalance = sum > 0.0 ? max / (sum / parts) : 1.0;
    return SINTER_OK;
}

sinter_status sinter_mpi_decomp_rebalance(sinter_mpi_decomp *d, const double *positions,
                                          const double *weights, size_t n, double threshold,
                                          sinter_mpi_reduce_fn reduce, void *user,
                                          double *imbalance, int *rebalanced)
{
    if (d == NULL || (positions == NULL && n > 0))
        return SINTER_ERR_NULL;
    if (!(threshold >= 1.0) || !isfinite(threshold))
        return SINTER_ERR_INVALID;
    if (rebalanced != NULL)
        *rebalanced = 0;
    double *loads = malloc((size_t)d->parts * sizeof *loads);
    sinter_status st = loads_collective(d, positions, weights, n, reduce, user, loads);
    double before = 1.0;
    if (st == SINTER_OK)
        st = sinter_mpi_imbalance(loads, d->parts, &before);
    free(loads);
    if (st != SINTER_OK)
        return st;
    if (imbalance != NULL)
        *imbalance = before;
    if (!(before > threshold))
        return SINTER_OK;
    sinter_mpi_decomp *fresh = NULL;
    st = sinter_mpi_decomp_rcb(&fresh, d->parts, d->lo, d->hi, positions, weights, n, reduce, user);
    if (st != SINTER_OK)
        return st;
    const sinter_mpi_decomp old = *d; /* swap the contents: d keeps its address */
    *d = *fresh;
    *fresh = old;
    sinter_mpi_decomp_destroy(fresh);
    if (rebalanced != NULL)
        *rebalanced = 1;
    return SINTER_OK;
}
