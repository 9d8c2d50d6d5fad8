/* The closest point of a mesh to a particle centre, and the one contact it gives.
 *
 * One contact per (particle, mesh wall): the closest point over all triangles, whichever
 * feature (face, edge, vertex) it lies on; the normal runs from it to the centre. A sphere on
 * a smooth surface made of several triangles thus touches once, at the one closest point (the
 * point a face contact gives in a face's interior, the shared edge or vertex where the closest
 * point lies on it: the same point and normal from every triangle that holds it), and the
 * contact is the same (particle, wall) pair when the closest point moves from one triangle to
 * the next, so that its tangential history carries on unbroken. This is the rule of the
 * methods that drop edge and vertex contacts whose point lies on a face in contact (Hu et al.,
 * Powder Technol. 2013; Kremmer & Favier, Int. J. Numer. Meth. Eng. 51 (2001) 1407) where one
 * feature is touched; what it cannot do: a sphere in a concave corner of one mesh touching
 * two faces gets the contact with the closer face only (the other overlap is ignored); such
 * corners are two walls (two meshes) to get both.
 *
 * Sign: in front of a face its plane's signed distance; at an edge or a vertex the sign of
 * (x - c) . pseudo-normal (sum of the faces' normals, angle-weighted at a vertex: Baerentzen &
 * Aanaes 2005), positive at an open edge (a rim met from either side, as a rectangle's). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh.h"

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Closest point c of triangle (a, b, d) to x (Ericson, Real-Time Collision Detection, 5.1.5);
 * returns the feature: 0 face, 1 + s vertex s, 4 + s edge s (from vertex s to s + 1). */
static int closest_on_triangle(const double *x, const double *a, const double *b, const double *d,
                               double *c)
{
    double ab[3], ad[3], ax[3];
    for (int i = 0; i < 3; ++i)
        ab[i] = b[i] - a[i], ad[i] = d[i] - a[i], ax[i] = x[i] - a[i];
    const double d1 = dot3(ab, ax), d2 = dot3(ad, ax);
    if (d1 <= 0.0 && d2 <= 0.0) {
        memcpy(c, a, 3 * sizeof(double));
        return 1;
    }
    double bx[3];
    for (int i = 0; i < 3; ++i)
        bx[i] = x[i] - b[i];
    const double d3 = dot3(ab, bx), d4 = dot3(ad, bx);
    if (d3 >= 0.0 && d4 <= d3) {
        memcpy(c, b, 3 * sizeof(double));
        return 2;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        for (int i = 0; i < 3; ++i)
            c[i] = a[i] + v * ab[i];
        return 4;
    }
    double dx[3];
    for (int i = 0; i < 3; ++i)
        dx[i] = x[i] - d[i];
    const double d5 = dot3(ab, dx), d6 = dot3(ad, dx);
    if (d6 >= 0.0 && d5 <= d6) {
        memcpy(c, d, 3 * sizeof(double));
        return 3;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        for (int i = 0; i < 3; ++i)
            c[i] = a[i] + w * ad[i];
        return 6;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; ++i)
            c[i] = b[i] + w * (d[i] - b[i]);
        return 5;
    }
    const double denom = 1.0 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    for (int i = 0; i < 3; ++i)
        c[i] = a[i] + ab[i] * v + ad[i] * w;
    return 0;
}

/* The best candidate so far: squared distance, triangle, feature, closest point; and a lower
 * bound of the squared distance of every other triangle (what the search skipped or tested
 * and rejected, and the region beyond it: the margin of a certificate). */
typedef struct best_point {
    double d2;
    size_t tri;
    int feature;
    double c[3];
    double second;
} best_point;

static void try_cell(const sinter_mesh *m, const double *x, size_t cell, best_point *best)
{
    for (uint32_t k = m->start[cell]; k < m->start[cell + 1]; ++k) {
        const size_t t = m->item[k];
        if (t == best->tri) /* met again (listed in every cell it meets): it cannot win */
            continue;
        const double *a = m->cull + 10 * t, *fn = a + 3;
        const double h = (x[0] - a[0]) * fn[0] + (x[1] - a[1]) * fn[1] + (x[2] - a[2]) * fn[2];
        if (h * h > best->d2) { /* its plane is farther than the best point */
            best->second = fmin(best->second, h * h);
            continue;
        }
        /* in its plane the triangle lies within its disc: |x - q|^2 >= h^2 + (lateral - rho)^2
         * for every point q of it */
        const double *disc = a + 6;
        const uint32_t *v = m->tri + 3 * t;
        const double g[3] = {x[0] - disc[0], x[1] - disc[1], x[2] - disc[2]};
        const double lateral = sqrt(fmax(dot3(g, g) - h * h, 0.0)) - disc[3];
        if (lateral > 0.0 && h * h + lateral * lateral > best->d2) {
            best->second = fmin(best->second, h * h + lateral * lateral);
            continue;
        }
        double c[3];
        const int f = closest_on_triangle(x, m->v + 3 * v[0], m->v + 3 * v[1], m->v + 3 * v[2], c);
        const double r[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
        const double d2 = dot3(r, r);
        /* the closer point; at a tie a face's (its plane's arithmetic) */
        if (d2 < best->d2 || (d2 == best->d2 && f == 0 && best->feature != 0)) {
            if (best->tri != SIZE_MAX) /* the one it replaces */
                best->second = fmin(best->second, best->d2);
            best->d2 = d2;
            best->tri = t;
            best->feature = f;
            memcpy(best->c, c, sizeof(c));
        } else {
            best->second = fmin(best->second, d2);
        }
    }
}

/* The cells at Chebyshev distance exactly k from cell (i, j, l), visited. */
static void try_ring(const sinter_mesh *m, const double *x, const int *at, int k, best_point *best)
{
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        lo[d] = at[d] - k < 0 ? 0 : at[d] - k;
        hi[d] = at[d] + k >= m->dim[d] ? m->dim[d] - 1 : at[d] + k;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y) {
            const int inner = abs(z - at[2]) < k && abs(y - at[1]) < k;
            for (int xx = lo[0]; xx <= hi[0]; ++xx) {
                if (inner && abs(xx - at[0]) < k) { /* skip to the ring's far side */
                    xx = at[0] + k - 1;
                    continue;
                }
                const size_t c =
                    ((size_t)z * (size_t)m->dim[1] + (size_t)y) * (size_t)m->dim[0] + (size_t)xx;
                if (m->start[c] == m->start[c + 1])
                    continue;
                /* a cell whose box is farther than the best point cannot hold a closer one */
                const int idx[3] = {xx, y, z};
                double gap2 = 0.0;
                for (int d = 0; d < 3; ++d) {
                    const double lo_d = m->lo[d] + idx[d] * m->h;
                    const double g = x[d] < lo_d ? lo_d - x[d] : x[d] - (lo_d + m->h);
                    if (g > 0.0)
                        gap2 += g * g;
                }
                if (gap2 > best->d2) {
                    best->second = fmin(best->second, gap2);
                    continue;
                }
                try_cell(m, x, c, best);
            }
        }
}

/* The search from x's cell outwards, ring by ring (the search of sinter_mesh_closest_hinted,
 * with best seeded); 0 and the lower bound in *lower when x is beyond the reach. */
static int search(const sinter_mesh *m, const double *x, best_point *best, double *lower)
{
    int at[3], kmax = 0;
    for (int d = 0; d < 3; ++d) {
        const double f = floor((x[d] - m->lo[d]) / m->h);
        at[d] = f < 0.0 ? 0 : f >= (double)m->dim[d] ? m->dim[d] - 1 : (int)f;
        kmax = at[d] > kmax ? at[d] : kmax;
        kmax = m->dim[d] - 1 - at[d] > kmax ? m->dim[d] - 1 - at[d] : kmax;
    }
    const size_t cell =
        ((size_t)at[2] * (size_t)m->dim[1] + (size_t)at[1]) * (size_t)m->dim[0] + (size_t)at[0];
    const int first = m->layer[cell]; /* the rings nearer hold no triangle */
    /* a cell k rings away is at least (k - 1) h from x (x anywhere in its cell, or beyond
     * the grid's side of it) */
    if (first >= 2 && (first - 1) * m->h >= m->reach) {
        *lower = (first - 1) * m->h; /* a lower bound, beyond the reach */
        return 0;
    }
    /* every triangle farther than the best point (a seeded bound: sinter_mesh_within's, a
     * hint's): none can win, nothing to search */
    if (first >= 2 && (first - 1) * m->h * ((first - 1) * m->h) > best->d2) {
        best->second = fmin(best->second, (first - 1) * m->h * ((first - 1) * m->h));
        return 1;
    }
    for (int k = first; k <= kmax; ++k) {
        try_ring(m, x, at, k, best);
        /* the distance from x to the cells beyond the block searched: at least k h */
        double bound = INFINITY;
        for (int d = 0; d < 3; ++d) {
            if (at[d] - k > 0)
                bound = fmin(bound, x[d] - (m->lo[d] + (at[d] - k) * m->h));
            if (at[d] + k < m->dim[d] - 1)
                bound = fmin(bound, m->lo[d] + (at[d] + k + 1) * m->h - x[d]);
        }
        if (best->d2 <= bound * bound) {
            best->second = fmin(best->second, bound * bound);
            break;
        }
        if (bound >= m->reach) { /* beyond the reach: a lower bound */
            *lower = bound;
            return 0;
        }
    }
    return 1;
}

double sinter_mesh_closest(const sinter_mesh *m, const double *x, double *n)
{
    uint32_t none = UINT32_MAX;
    return sinter_mesh_closest_hinted(m, x, n, &none);
}

/* The hint: the best point's squared distance may only come down from its triangle's, so
 * that d2 (with a margin for the bounds' round-off) seeds the search as a best point of no
 * triangle. Every triangle, cell and ring the search skips with it lies farther than the
 * hint's triangle and would lose; those it tries come in the order of the search without
 * it and win by the same comparisons once one is taken: the same point, normal and distance
 * bits, only fewer triangles tested. */
static best_point seed(const sinter_mesh *m, const double *x, uint32_t hint)
{
    best_point best = {INFINITY, SIZE_MAX, 0, {0, 0, 0}, INFINITY};
    if (hint >= m->nt)
        return best;
    const uint32_t *v = m->tri + 3 * (size_t)hint;
    double c[3];
    (void)closest_on_triangle(x, m->v + 3 * v[0], m->v + 3 * v[1], m->v + 3 * v[2], c);
    const double r[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
    const double d2 = dot3(r, r), tiny = 1e-12 * m->h;
    const double bound = d2 * (1.0 + 1e-9) + tiny * tiny;
    if (bound < m->reach * m->reach) /* beyond, the search may end at a lower bound: none */
        best.d2 = bound;
    return best;
}

/* The signed distance and normal of the closest point found (best.tri a triangle). */
static double finish(const sinter_mesh *m, const double *x, const best_point *bp, double *n)
{
    const best_point best = *bp;
    const double r[3] = {x[0] - best.c[0], x[1] - best.c[1], x[2] - best.c[2]};
    const double *fn = m->fn + 3 * best.tri;
    if (best.feature == 0) { /* in front of (or behind) a face: its plane's distance */
        if (n != NULL)
            memcpy(n, fn, 3 * sizeof(double));
        return dot3(r, fn);
    }
    const double *pseudo = best.feature >= 4 ? m->en + 9 * best.tri + 3 * (best.feature - 4)
                                             : m->vn + 3 * m->tri[3 * best.tri + best.feature - 1];
    const double sign = dot3(r, pseudo) < 0.0 ? -1.0 : 1.0;
    const double s = sqrt(best.d2);
    if (n != NULL) {
        if (s > 0.0)
            for (int i = 0; i < 3; ++i)
                n[i] = sign * r[i] / s;
        else
            memcpy(n, fn, 3 * sizeof(double));
    }
    return sign * s;
}

/* The closest triangle to x by the search seeded with triangle `hint`; seeded and nothing
 * taken (a bound's round-off past the margin), the search again without the seed. 0 when no
 * triangle lies within the reach (*lower is then a lower bound of the distance). */
static int seeded_search(const sinter_mesh *m, const double *x, uint32_t hint, best_point *best,
                         double *lower)
{
    *best = seed(m, x, hint);
    *lower = 0.0;
    int found = search(m, x, best, lower);
    if (found && best->tri == SIZE_MAX) {
        *best = (best_point){INFINITY, SIZE_MAX, 0, {0, 0, 0}, INFINITY};
        found = search(m, x, best, lower);
    }
    return found;
}

double sinter_mesh_closest_hinted(const sinter_mesh *m, const double *x, double *n, uint32_t *hint)
{
    best_point best;
    double lower;
    if (!seeded_search(m, x, *hint, &best, &lower)) {
        if (n != NULL)
            memcpy(n, m->fn, 3 * sizeof(double));
        return lower;
    }
    *hint = (uint32_t)best.tri;
    return finish(m, x, &best, n);
}

/*
 * A certificate (cert[0..2] the point x0 of the last full search, in the mesh's frame, and
 * cert[3] a radius rho, negative: none): every distance function to a triangle changes by at
 * most |x - x0| (1-Lipschitz), so while |x - x0| < rho = (d_2 - d_1) / 2, d_1 the closest
 * triangle's distance at x0 and d_2 a lower bound of every other's, that triangle stays
 * strictly the closest, the search would end on it again, and its closest point alone gives
 * the same bits. rho is shrunk by 1e-9 of d_2 (the bounds' round-off) and kept below the
 * reach (the search would give a lower bound beyond it); a tie (a shared edge or vertex
 * closest) gives no certificate.
 */
double sinter_mesh_closest_certified(const sinter_mesh *m, const double *x, double *n,
                                     uint32_t *hint, double cert[4])
{
    const uint32_t t = *hint;
    if (t < m->nt && cert[3] > 0.0) {
        const double dx = x[0] - cert[0], dy = x[1] - cert[1], dz = x[2] - cert[2];
        if (dx * dx + dy * dy + dz * dz < cert[3] * cert[3]) {
            const uint32_t *v = m->tri + 3 * (size_t)t;
            best_point best = {0.0, t, 0, {0, 0, 0}, INFINITY};
            best.feature =
                closest_on_triangle(x, m->v + 3 * v[0], m->v + 3 * v[1], m->v + 3 * v[2], best.c);
            const double r[3] = {x[0] - best.c[0], x[1] - best.c[1], x[2] - best.c[2]};
            best.d2 = dot3(r, r);
            return finish(m, x, &best, n);
        }
    }
    cert[3] = -1.0;
    best_point best;
    double lower;
    if (!seeded_search(m, x, t, &best, &lower)) {
        if (n != NULL)
            memcpy(n, m->fn, 3 * sizeof(double));
        return lower;
    }
    *hint = (uint32_t)best.tri;
    const double d1 = sqrt(best.d2), d2 = sqrt(best.second);
    double rho = 0.5 * (d2 - d1) - 1e-9 * d2 - 1e-12 * m->h;
    rho = fmin(rho, (m->reach - d1) * (1.0 - 1e-9));
    if (rho > 0.0) { /* (NaN and infinite bounds give none) */
        memcpy(cert, x, 3 * sizeof(double));
        cert[3] = rho;
    }
    return finish(m, x, &best, n);
}

/*
 * The neighbour list's question, whether the signed distance is below `bound`, by a search
 * seeded with the bound itself (times the hint's margin) as a best point of no triangle: a
 * triangle closer than the bound is found as the search without the seed finds it (the
 * hint's argument), and then its signed distance decides, the same bits. When none is closer
 * the search ends at the bound instead of at the mesh: the sphere is at least `bound` from
 * the mesh, and taken as in front of it (not near) if it is in front of the plane of its hint
 * triangle (the last closest). Behind that plane, without a hint, or with a bound beyond the
 * reach, the full search answers (a sphere behind the mesh stays a candidate, so that the
 * step refuses it as passed through the wall).
 */
int sinter_mesh_within(const sinter_mesh *m, const double *x, double bound, uint32_t *hint)
{
    const uint32_t t = *hint;
    int front = 0;
    if (t < m->nt && bound > 0.0 && bound < m->reach) {
        const double *a = m->cull + 10 * (size_t)t, *fn = a + 3;
        front = (x[0] - a[0]) * fn[0] + (x[1] - a[1]) * fn[1] + (x[2] - a[2]) * fn[2] >= 0.0;
    }
    if (!front)
        return sinter_mesh_closest_hinted(m, x, NULL, hint) < bound;
    best_point best = seed(m, x, t);
    const double tiny = 1e-12 * m->h, b2 = bound * bound * (1.0 + 1e-9) + tiny * tiny;
    if (b2 < best.d2)
        best.d2 = b2;
    double lower = 0.0;
    if (!search(m, x, &best, &lower))
        return lower < bound; /* beyond the reach from the first layer: a lower bound */
    if (best.tri == SIZE_MAX)
        return 0; /* nothing within the bound, in front of the hint's plane */
    *hint = (uint32_t)best.tri;
    return finish(m, x, &best, NULL) < bound;
}
