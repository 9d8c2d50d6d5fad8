/* Schedules and tables (wall temperatures and drives, heat-model parameters, softening curves):
 * their copies and their piecewise-linear interpolation. */
#include <string.h>

#include "core.h"

double sinter_interpolate(size_t n, const double *t, const double *v, double x)
{
    if (x <= t[0])
        return v[0];
    if (x >= t[n - 1])
        return v[n - 1];
    size_t lo = 0, hi = n - 1; /* t[lo] <= x < t[hi] */
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (t[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return v[lo] + (v[hi] - v[lo]) * (x - t[lo]) / (t[hi] - t[lo]);
}

sinter_status sinter_copy_table(sinter_ctx *ctx, size_t n, const double *t, const double *v,
                                double **t_out, double **v_out)
{
    double *a = sinter_calloc(ctx, n + 1, sizeof(double));
    double *b = sinter_calloc(ctx, n + 1, sizeof(double));
    if (a == NULL || b == NULL) {
        sinter_free(ctx, a);
        sinter_free(ctx, b);
        return SINTER_ERR_NOMEM;
    }
    if (n > 0) {
        memcpy(a, t, n * sizeof(double));
        memcpy(b, v, n * sizeof(double));
    }
    *t_out = a;
    *v_out = b;
    return SINTER_OK;
}
