/* Scan paths of a heat source: see scan_path.h. */
#include "heat/scan_path.h"

#include <math.h>
#include <string.h>

sinter_status sinter_scan_path_create(sinter_ctx *ctx, size_t n, const double *points, double start,
                                      sinter_scan_path **out, const char *func)
{
    if (n < 2)
        return sinter_fail(
            ctx, SINTER_ERR_INVALID,
            "%s: a scan path needs at least 2 vertices (a start and an end), got %zu", func, n);
    if (!isfinite(start))
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: the start time %g s is not finite", func,
                           start);
    if (sinter_mul_overflows(n, 4 * sizeof(double)))
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW, "%s: %zu vertices overflow", func, n);
    for (size_t k = 0; k < n; ++k) {
        const double *p = points + 4 * k;
        if (!isfinite(p[0]) || !isfinite(p[1]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: vertex %zu of the scan path is at (%g, %g) m: not finite", func,
                               k, p[0], p[1]);
        if (k == 0)
            continue;
        const double length = hypot(p[0] - p[-4], p[1] - p[-3]);
        if (length > 0.0 && !(p[2] > 0.0 && isfinite(p[2])))
            return sinter_fail(
                ctx, SINTER_ERR_INVALID,
                "%s: the segment to vertex %zu of the scan path has speed %g m/s; it "
                "must be positive and finite",
                func, k, p[2]);
        if (!(p[3] >= 0.0 && p[3] <= 1.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the segment to vertex %zu of the scan path has level %g; it "
                               "must lie in [0, 1] (0: off, 1: full power)",
                               func, k, p[3]);
    }
    sinter_scan_path *path = sinter_calloc(ctx, 1, sizeof(*path));
    if (path == NULL)
        return sinter_last_status(ctx);
    path->t = sinter_alloc(ctx, n * sizeof(double));
    path->xy = sinter_alloc(ctx, 2 * n * sizeof(double));
    path->level = sinter_alloc(ctx, n * sizeof(double));
    if (path->t == NULL || path->xy == NULL || path->level == NULL) {
        sinter_scan_path_destroy(ctx, path);
        return SINTER_ERR_NOMEM;
    }
    path->vertices = n;
    double t = start;
    for (size_t k = 0; k < n; ++k) {
        const double *p = points + 4 * k;
        if (k > 0) {
            const double length = hypot(p[0] - p[-4], p[1] - p[-3]);
            t += length > 0.0 ? length / p[2] : 0.0;
            path->level[k - 1] = p[3];
        }
        path->t[k] = t;
        path->xy[2 * k] = p[0];
        path->xy[2 * k + 1] = p[1];
    }
    path->level[n - 1] = 0.0; /* after the end: off */
    *out = path;
    return SINTER_OK;
}

void sinter_scan_path_destroy(sinter_ctx *ctx, sinter_scan_path *path)
{
    if (path == NULL)
        return;
    sinter_free(ctx, path->t);
    sinter_free(ctx, path->xy);
    sinter_free(ctx, path->level);
    sinter_free(ctx, path);
}

void sinter_scan_path_at(const sinter_scan_path *path, double t, double xy[2], double *level)
{
    const size_t n = path->vertices;
    if (!(t >= path->t[0])) { /* before the start (or NaN): at the first vertex, off */
        xy[0] = path->xy[0];
        xy[1] = path->xy[1];
        *level = 0.0;
        return;
    }
    if (t >= path->t[n - 1]) { /* at or after the end: at the last vertex, off */
        xy[0] = path->xy[2 * (n - 1)];
        xy[1] = path->xy[2 * (n - 1) + 1];
        *level = 0.0;
        return;
    }
    /* the segment k with t[k] <= t < t[k + 1] (binary search; zero-length segments skipped) */
    size_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        const size_t mid = lo + (hi - lo) / 2;
        if (path->t[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const double span = path->t[lo + 1] - path->t[lo];
    const double s = span > 0.0 ? (t - path->t[lo]) / span : 0.0;
    for (int d = 0; d < 2; ++d)
        xy[d] = path->xy[2 * lo + (size_t)d] +
                s * (path->xy[2 * (lo + 1) + (size_t)d] - path->xy[2 * lo + (size_t)d]);
    *level = path->level[lo];
}

/* The part [*u0, *u1] of the line p + u d inside the rectangle lo..hi (Liang-Barsky); 0 if none. */
static int clip(const double p[2], const double d[2], const double lo_in[2], const double hi_in[2],
                double *u0, double *u1)
{
    /* the rectangle grown by a round-off's width, so that edge lines are kept */
    const double grow = 1e-12 * ((hi_in[0] - lo_in[0]) + (hi_in[1] - lo_in[1]));
    const double lo[2] = {lo_in[0] - grow, lo_in[1] - grow},
                 hi[2] = {hi_in[0] + grow, hi_in[1] + grow};
    double a = -INFINITY, b = INFINITY;
    for (int k = 0; k < 2; ++k) {
        if (fabs(d[k]) < 1e-15) {
            if (p[k] < lo[k] || p[k] > hi[k])
                return 0;
            continue;
        }
        double ua = (lo[k] - p[k]) / d[k], ub = (hi[k] - p[k]) / d[k];
        if (ua > ub) {
            const double w = ua;
            ua = ub;
            ub = w;
        }
        a = ua > a ? ua : a;
        b = ub < b ? ub : b;
    }
    *u0 = a;
    *u1 = b;
    return b > a;
}

sinter_status sinter_scan_hatch_build(sinter_ctx *ctx, const double lo[2], const double hi[2],
                                      double spacing, double angle, double speed, double jump_speed,
                                      int serpentine, double *points, size_t capacity,
                                      size_t *count)
{
    const char *func = "sinter_scan_hatch";
    for (int k = 0; k < 2; ++k)
        if (!isfinite(lo[k]) || !isfinite(hi[k]) || !(hi[k] > lo[k]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the rectangle's %c range [%g, %g] m must be finite and not "
                               "empty",
                               func, "xy"[k], lo[k], hi[k]);
    if (!(spacing > 0.0) || !isfinite(spacing))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the hatch spacing %g m must be positive and finite", func, spacing);
    if (!isfinite(angle))
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: the hatch angle %g is not finite", func,
                           angle);
    if (!(speed > 0.0) || !isfinite(speed) || !(jump_speed > 0.0) || !isfinite(jump_speed))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the scan speed %g m/s and the jump speed %g m/s must be positive "
                           "and finite",
                           func, speed, jump_speed);
    const double d[2] = {cos(angle), sin(angle)}, nrm[2] = {-d[1], d[0]};
    /* the rectangle's extent across the lines */
    double smin = INFINITY, smax = -INFINITY;
    for (int c = 0; c < 4; ++c) {
        const double corner[2] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1]};
        const double s = corner[0] * nrm[0] + corner[1] * nrm[1];
        smin = s < smin ? s : smin;
        smax = s > smax ? s : smax;
    }
    /* (a width that is a whole number of spacings counts both edge lines despite round-off) */
    const double lines_real = floor((smax - smin) / spacing * (1.0 + 1e-12)) + 1.0;
    if (lines_real > 1e7)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: spacing %g m gives %.0f lines across the rectangle (at most 1e7)",
                           func, spacing, lines_real);
    const size_t lines = (size_t)lines_real;
    const double first = 0.5 * (smin + smax) - 0.5 * (double)(lines - 1) * spacing;
    size_t m = 0, made = 0;
    for (size_t k = 0; k < lines; ++k) {
        const double s = first + (double)k * spacing;
        const double p[2] = {s * nrm[0], s * nrm[1]};
        double u0, u1;
        if (!clip(p, d, lo, hi, &u0, &u1))
            continue; /* a line that only touches a corner */
        if (serpentine && (made & 1)) {
            const double w = u0;
            u0 = u1;
            u1 = w;
        }
        double a[2] = {p[0] + u0 * d[0], p[1] + u0 * d[1]},
               b[2] = {p[0] + u1 * d[0], p[1] + u1 * d[1]};
        for (int c = 0; c < 2; ++c) { /* back inside the rectangle clip() grew */
            a[c] = fmin(fmax(a[c], lo[c]), hi[c]);
            b[c] = fmin(fmax(b[c], lo[c]), hi[c]);
        }
        /* the start of this line: vertex 0, or reached by a jump (level 0) */
        if (points != NULL && m + 2 > capacity)
            return sinter_fail(ctx, SINTER_ERR_RANGE,
                               "%s: room for %zu vertices, the hatch has more", func, capacity);
        if (points != NULL) {
            double *q = points + 4 * m;
            q[0] = a[0], q[1] = a[1], q[2] = jump_speed, q[3] = 0.0;
            q[4] = b[0], q[5] = b[1], q[6] = speed, q[7] = 1.0;
        }
        m += 2;
        made++;
    }
    if (count != NULL)
        *count = m;
    return SINTER_OK;
}
