/*
 * The relative difference the subdomain tests compare decomposed runs with: the largest
 * |a - b| over the largest |b - base| (base NULL: over the largest |b|), n values; the
 * absolute difference where that scale is 0.
 */
#ifndef SINTER_TEST_REL_DIFF_H
#define SINTER_TEST_REL_DIFF_H

#include <math.h>
#include <stddef.h>

static inline double rel_diff_from(const double *a, const double *b, const double *base, size_t n)
{
    double diff = 0.0, scale = 0.0;
    for (size_t i = 0; i < n; ++i) {
        diff = fmax(diff, fabs(a[i] - b[i]));
        scale = fmax(scale, fabs(b[i] - (base != NULL ? base[i] : 0.0)));
    }
    return scale > 0.0 ? diff / scale : diff;
}

/* max |a - b| / max |b| over n values. */
static inline double rel_diff(const double *a, const double *b, size_t n)
{
    return rel_diff_from(a, b, NULL, n);
}

#endif
