/* Spatial order of a particle set in memory (issue 9): cell order, x fastest. */
#include <math.h>
#include <stdlib.h>

#include "particles/particles.h"

typedef struct keyed {
    uint64_t key; /* cell index */
    uint64_t id;  /* persistent id: ties go by id, so the order does not depend on the old one */
    size_t index; /* particle index before the sort */
} keyed;

static int keyed_compare(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key)
        return (x->key > y->key) - (x->key < y->key);
    return (x->id > y->id) - (x->id < y->id);
}

sinter_status sinter_particles_sort_spatial(sinter_particles *ps)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_particles_drop_ghosts(ps); /* owned particles only: ghosts are made again */
    const size_t n = ps->count;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double rmax = 0.0;
    for (size_t i = 0; i < n; ++i) {
        for (int d = 0; d < 3; ++d) {
            const double x = ps->x[3 * i + d];
            if (!isfinite(x))
                return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                                   "sinter_particles_sort_spatial: the position of particle %zu "
                                   "(id %llu) is not finite; nothing was moved",
                                   i, (unsigned long long)ps->id[i]);
            lo[d] = x < lo[d] ? x : lo[d];
            hi[d] = x > hi[d] ? x : hi[d];
        }
        rmax = ps->radius[i] > rmax ? ps->radius[i] : rmax;
    }
    if (n < 2)
        return sinter_particles_permute(ps, (const size_t[]){0}); /* checks the lock too */
    /* cells of the largest diameter, at most about 8 per particle along the whole set */
    double cell = 2.0 * rmax;
    size_t dims[3];
    for (;;) {
        double cells = 1.0;
        for (int d = 0; d < 3; ++d) {
            const double c = cell > 0.0 ? floor((hi[d] - lo[d]) / cell) + 1.0 : 1.0;
            dims[d] = (size_t)c;
            cells *= c;
        }
        if (cell > 0.0 && cells <= 8.0 * (double)n + 64.0)
            break;
        cell = cell > 0.0 ? 2.0 * cell : (hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]) + 1.0;
    }
    keyed *k = sinter_alloc(ps->ctx, n * sizeof(keyed));
    size_t *order = sinter_alloc(ps->ctx, n * sizeof(size_t));
    sinter_status st = k != NULL && order != NULL ? SINTER_OK : SINTER_ERR_NOMEM;
    if (st == SINTER_OK) {
        for (size_t i = 0; i < n; ++i) {
            size_t c[3];
            for (int d = 0; d < 3; ++d) {
                const size_t v = (size_t)((ps->x[3 * i + d] - lo[d]) / cell);
                c[d] = v < dims[d] ? v : dims[d] - 1;
            }
            k[i].key = ((uint64_t)c[2] * dims[1] + c[1]) * dims[0] + c[0];
            k[i].id = ps->id[i];
            k[i].index = i;
        }
        qsort(k, n, sizeof(keyed), keyed_compare);
        for (size_t i = 0; i < n; ++i)
            order[i] = k[i].index;
        st = sinter_particles_permute(ps, order);
    }
    sinter_free(ps->ctx, k);
    sinter_free(ps->ctx, order);
    return st;
}
