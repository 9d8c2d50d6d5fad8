/*
 * Touching pairs for the quasi-static stepper: a cell grid of edge 2 r_max (1 + tolerance) over
 * the centres, so finding the pairs costs O(n) instead of the O(n^2) of testing every pair. The
 * pairs come back as sorted keys a n + b (a < b), the order the all-pairs loop produced, so links
 * are created in the same order and runs are unchanged by the search method (the stepper passes
 * its particles in id order, qs_ids.c, so a and b are ids' ranks). The stepper keeps
 * the pairs within a skin and searches again only when a sphere has moved far enough
 * (sinter_qs_touching_pairs_near): the same pairs, without a search at every step.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stepper/quasistatic.h"

/* Cells per axis for the extent `ext` and edge `cell`, at least 1. */
static size_t cells_along(double ext, double cell)
{
    const double c = floor(ext / cell) + 1.0;
    return c < 1.0 ? 1 : (size_t)c;
}

sinter_status sinter_qs_touching_pairs(sinter_ctx *ctx, size_t n, const double *x,
                                       const double *radius, double tolerance, double margin,
                                       uint64_t **keys, size_t *capacity, size_t *count)
{
    *count = 0;
    if (n < 2)
        return SINTER_OK;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double rmax = 0.0;
    for (size_t i = 0; i < n; ++i) {
        for (int d = 0; d < 3; ++d) {
            const double v = x[3 * i + (size_t)d];
            if (!isfinite(v))
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "quasi-static stepper: particle %zu has a non-finite "
                                   "position (%c = %g m)",
                                   i, "xyz"[d], v);
            lo[d] = fmin(lo[d], v);
            hi[d] = fmax(hi[d], v);
        }
        rmax = fmax(rmax, radius[i]);
    }
    double cell = 2.0 * rmax * (1.0 + tolerance) + margin;
    size_t dim[3], cells;
    /* Keep the grid at most ~2 cells per particle (sparse or elongated sets). */
    for (;;) {
        for (int d = 0; d < 3; ++d)
            dim[d] = cells_along(hi[d] - lo[d], cell);
        cells = dim[0] * dim[1] * dim[2];
        if (cells <= 2 * n + 8 && dim[0] < (1u << 20) && dim[1] < (1u << 20) && dim[2] < (1u << 20))
            break;
        cell *= 1.5;
    }
    size_t *start = sinter_calloc(ctx, cells + 1, sizeof(size_t));
    size_t *order = sinter_calloc(ctx, n, sizeof(size_t));
    size_t *cell_of = sinter_calloc(ctx, n, sizeof(size_t));
    sinter_status s = SINTER_OK;
    if (start == NULL || order == NULL || cell_of == NULL) {
        s = SINTER_ERR_NOMEM;
        goto done;
    }
    /* Counting sort of the particles by cell (stable: ascending index within a cell). */
    for (size_t i = 0; i < n; ++i) {
        size_t c[3];
        for (int d = 0; d < 3; ++d) {
            c[d] = (size_t)((x[3 * i + (size_t)d] - lo[d]) / cell);
            if (c[d] >= dim[d])
                c[d] = dim[d] - 1;
        }
        cell_of[i] = (c[2] * dim[1] + c[1]) * dim[0] + c[0];
        start[cell_of[i] + 1]++;
    }
    for (size_t c = 0; c < cells; ++c)
        start[c + 1] += start[c];
    {
        size_t *fill = sinter_calloc(ctx, cells, sizeof(size_t));
        if (fill == NULL) {
            s = SINTER_ERR_NOMEM;
            goto done;
        }
        for (size_t i = 0; i < n; ++i)
            order[start[cell_of[i]] + fill[cell_of[i]]++] = i;
        sinter_free(ctx, fill);
    }
    for (size_t a = 0; a < n; ++a) {
        const size_t ca = cell_of[a];
        const size_t cx = ca % dim[0], cy = (ca / dim[0]) % dim[1], cz = ca / (dim[0] * dim[1]);
        const double *xa = x + 3 * a;
        for (int dz = -1; dz <= 1; ++dz) {
            if ((dz < 0 && cz == 0) || (dz > 0 && cz + 1 >= dim[2]))
                continue;
            for (int dy = -1; dy <= 1; ++dy) {
                if ((dy < 0 && cy == 0) || (dy > 0 && cy + 1 >= dim[1]))
                    continue;
                for (int dx = -1; dx <= 1; ++dx) {
                    if ((dx < 0 && cx == 0) || (dx > 0 && cx + 1 >= dim[0]))
                        continue;
                    const size_t cb = ((cz + (size_t)dz) * dim[1] + (cy + (size_t)dy)) * dim[0] +
                                      (cx + (size_t)dx);
                    for (size_t k = start[cb]; k < start[cb + 1]; ++k) {
                        const size_t b = order[k];
                        if (b <= a)
                            continue;
                        const double *xb = x + 3 * b;
                        const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
                        const double reach = (radius[a] + radius[b]) * (1.0 + tolerance) + margin;
                        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= reach * reach)
                            continue;
                        if ((s = sinter_grow(ctx, (void **)keys, capacity, *count + 1,
                                             sizeof(uint64_t))) != SINTER_OK)
                            goto done;
                        (*keys)[(*count)++] = (uint64_t)a * n + b;
                    }
                }
            }
        }
    }
    qsort(*keys, *count, sizeof(uint64_t), sinter_qs_key_compare);
done:
    sinter_free(ctx, start);
    sinter_free(ctx, order);
    sinter_free(ctx, cell_of);
    if (s != SINTER_OK)
        *count = 0;
    return s;
}

/* The skin of the kept pairs, in units of the largest diameter: a search every 0.45 of it, about
 * 1.4 um of the largest displacement for seed 001's 32 um titanium spheres. */
#define NEAR_SKIN 0.05
#define NEAR_MOVE 0.45

void sinter_qs_near_free(sinter_ctx *ctx, sinter_qs_near *near)
{
    sinter_free(ctx, near->keys);
    sinter_free(ctx, near->x0);
    sinter_free(ctx, near->r0);
    memset(near, 0, sizeof(*near));
}

/* 1 if near's pairs hold every touching pair of the spheres now. */
static int near_valid(const sinter_qs_near *near, size_t n, const double *x, const double *radius,
                      double tolerance)
{
    if (!near->valid || near->n != n || near->tolerance != tolerance)
        return 0;
    double moved2 = 0.0; /* the largest squared displacement; NaN for a non-finite position */
    for (size_t i = 0; i < n; ++i) {
        if (radius[i] != near->r0[i])
            return 0;
        const double dx = x[3 * i] - near->x0[3 * i], dy = x[3 * i + 1] - near->x0[3 * i + 1],
                     dz = x[3 * i + 2] - near->x0[3 * i + 2];
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (!(d2 <= moved2))
            moved2 = d2;
    }
    /* a pair touching now was at most 2 x 0.45 skin further apart at the search */
    return moved2 <= (NEAR_MOVE * near->skin) * (NEAR_MOVE * near->skin);
}

sinter_status sinter_qs_touching_pairs_near(sinter_ctx *ctx, sinter_qs_near *near, size_t n,
                                            const double *x, const double *radius, double tolerance,
                                            uint64_t **keys, size_t *capacity, size_t *count,
                                            int *searched)
{
    *count = 0;
    if (searched)
        *searched = 0;
    if (!near_valid(near, n, x, radius, tolerance)) {
        near->valid = 0;
        double rmax = 0.0;
        for (size_t i = 0; i < n; ++i)
            rmax = fmax(rmax, radius[i]);
        const double skin = NEAR_SKIN * 2.0 * rmax;
        sinter_status s =
            sinter_grow(ctx, (void **)&near->x0, &near->x0_capacity, 3 * n + 1, sizeof(double));
        if (s == SINTER_OK)
            s = sinter_grow(ctx, (void **)&near->r0, &near->r0_capacity, n + 1, sizeof(double));
        if (s == SINTER_OK)
            s = sinter_qs_touching_pairs(ctx, n, x, radius, tolerance, skin, &near->keys,
                                         &near->keys_capacity, &near->count);
        if (s != SINTER_OK)
            return s;
        memcpy(near->x0, x, 3 * n * sizeof(double));
        memcpy(near->r0, radius, n * sizeof(double));
        near->n = n;
        near->tolerance = tolerance;
        near->skin = skin;
        near->valid = 1;
        if (searched)
            *searched = 1;
    }
    sinter_status s = sinter_grow(ctx, (void **)keys, capacity, near->count + 1, sizeof(uint64_t));
    if (s != SINTER_OK)
        return s;
    for (size_t k = 0; k < near->count; ++k) { /* the test of sinter_qs_touching_pairs */
        const size_t a = (size_t)(near->keys[k] / n), b = (size_t)(near->keys[k] % n);
        const double *xa = x + 3 * a, *xb = x + 3 * b;
        const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
        const double reach = (radius[a] + radius[b]) * (1.0 + tolerance);
        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach * reach)
            (*keys)[(*count)++] = near->keys[k];
    }
    return SINTER_OK;
}
