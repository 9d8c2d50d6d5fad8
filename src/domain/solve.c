/* The collective pieces of the global solves across subdomains (domain/solve.h). */
#include "domain/solve.h"

#include <string.h>

#include "domain/exact_reduce.h"

void sinter_domain_solve_free(sinter_domain_solve *ds)
{
    if (ds->ctx != NULL)
        sinter_free(ds->ctx, ds->rows);
    ds->rows = NULL;
    ds->rows_capacity = 0;
}

sinter_status sinter_domain_solve_reserve(sinter_domain_solve *ds, size_t width)
{
    return sinter_grow(ds->ctx, (void **)&ds->rows, &ds->rows_capacity, width * ds->ps->count + 1,
                       sizeof(double));
}

void sinter_domain_solve_forward(sinter_domain_solve *ds, const double *owned)
{
    const size_t n = ds->ps->count - ds->ps->ghost_count;
    if (n > 0)
        memcpy(ds->rows, owned, n * sizeof(double));
    sinter_domain_solve_halo(ds, 1);
}

void sinter_domain_solve_halo(sinter_domain_solve *ds, size_t width)
{
    const sinter_particles *ps = ds->ps;
    const size_t n = ps->count - ps->ghost_count;
    const sinter_halo h = {.struct_size = sizeof(sinter_halo),
                           .direction = SINTER_HALO_FORWARD,
                           .width = width,
                           .data = ds->rows,
                           .id = ps->id,
                           .owned = n,
                           .ghosts = ps->ghost_count};
    ds->d->halos++;
    if (ds->failed || ds->d->ops.halo(&h, ds->d->user) != 0) {
        if (!ds->failed)
            (void)sinter_fail(ds->ctx, SINTER_ERR_CALLBACK,
                              "the host's halo callback failed (forward, width %zu, %zu owned "
                              "rows, %zu ghost rows) in a global solve",
                              width, n, ps->ghost_count);
        ds->failed = 1;
        memset(ds->rows + width * n, 0, width * ps->ghost_count * sizeof(double));
    }
}

double sinter_domain_solve_sum(double local, void *data)
{
    sinter_domain_solve *ds = data;
    double v = local;
    if (!ds->failed && sinter_domain_reduce(ds->ctx, ds->d, &v, 1, SINTER_REDUCE_F64,
                                            SINTER_REDUCE_SUM) != SINTER_OK)
        ds->failed = 1;
    return ds->failed ? 0.0 : v;
}

double sinter_domain_solve_exact_dot(const double *x, const double *y, size_t n, void *data)
{
    sinter_domain_solve *ds = data;
    double v = 0.0;
    if (ds->failed || sinter_domain_exact_sums(ds->ctx, ds->d, 1, &x, &y, &n, &v) != SINTER_OK)
        ds->failed = 1;
    return ds->failed ? 0.0 : v;
}
