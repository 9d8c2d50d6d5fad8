/* A mesh from an STL soup: vertices welded where the file repeats them bit for bit, placed
 * (scale, rotation, translation), checked (degenerate triangles, edges of more than two
 * triangles, neighbours wound opposite ways, stored normals opposite to the winding: refused,
 * naming the facet; open edges accepted as rims), then the pseudo-normals that give the sign
 * of a distance to an edge or a vertex (Baerentzen & Aanaes, IEEE TVCG 11 (2005) 243) and the
 * cell grid over the triangles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh.h"

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void cross3(const double *a, const double *b, double *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void sinter_mesh_destroy(sinter_ctx *ctx, sinter_mesh *m)
{
    if (m == NULL)
        return;
    sinter_free(ctx, m->v);
    sinter_free(ctx, m->tri);
    sinter_free(ctx, m->fn);
    sinter_free(ctx, m->en);
    sinter_free(ctx, m->vn);
    sinter_free(ctx, m->disc);
    sinter_free(ctx, m->cull);
    sinter_free(ctx, m->start);
    sinter_free(ctx, m->item);
    sinter_free(ctx, m->layer);
    sinter_free(ctx, m);
}

/* qsort keys: a soup vertex (its 3 coordinates) and its position in the soup */
static const double *weld_coords;
static int by_coords(const void *a, const void *b)
{
    const double *p = weld_coords + 3 * *(const uint32_t *)a;
    const double *q = weld_coords + 3 * *(const uint32_t *)b;
    for (int d = 0; d < 3; ++d)
        if (p[d] != q[d])
            return p[d] < q[d] ? -1 : 1;
    return (int)(*(const uint32_t *)a > *(const uint32_t *)b) -
           (int)(*(const uint32_t *)a < *(const uint32_t *)b);
}

/* An edge of a triangle: its vertices low < high, the triangle, its slot, its direction. */
typedef struct edge_ref {
    uint32_t low, high, tri;
    int slot, forward; /* forward: the triangle runs low -> high */
} edge_ref;

static int by_edge(const void *a, const void *b)
{
    const edge_ref *p = a, *q = b;
    if (p->low != q->low)
        return p->low < q->low ? -1 : 1;
    if (p->high != q->high)
        return p->high < q->high ? -1 : 1;
    return (int)(p->tri > q->tri) - (int)(p->tri < q->tri);
}

/* The rotation matrix turning by r[0] about x, then r[1] about y, then r[2] about z. */
static void rotation(const double r[3], double m[3][3])
{
    const double cx = cos(r[0]), sx = sin(r[0]), cy = cos(r[1]), sy = sin(r[1]), cz = cos(r[2]),
                 sz = sin(r[2]);
    const double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
    const double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    const double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
    double yx[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            yx[i][j] = 0.0;
            for (int k = 0; k < 3; ++k)
                yx[i][j] += ry[i][k] * rx[k][j];
        }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            m[i][j] = 0.0;
            for (int k = 0; k < 3; ++k)
                m[i][j] += rz[i][k] * yx[k][j];
        }
}

/* Weld, place and check: m->v, m->tri, m->fn. */
static sinter_status make_triangles(sinter_ctx *ctx, const sinter_stl *stl, const char *path,
                                    double scale, const double rotate[3], const double translate[3],
                                    int flip, sinter_mesh *m)
{
    const size_t ns = 3 * stl->count;
    if (ns > UINT32_MAX / 2)
        return sinter_fail(ctx, SINTER_ERR_RANGE, "STL file '%s': %zu facets are too many", path,
                           stl->count);
    uint32_t *order = sinter_alloc(ctx, ns * sizeof(uint32_t));
    m->tri = sinter_alloc(ctx, ns * sizeof(uint32_t));
    m->v = sinter_alloc(ctx, 3 * ns * sizeof(double));
    m->fn = sinter_alloc(ctx, 3 * stl->count * sizeof(double));
    m->disc = sinter_alloc(ctx, 4 * stl->count * sizeof(double));
    if (!order || !m->tri || !m->v || !m->fn || !m->disc) {
        sinter_free(ctx, order);
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
    }
    for (size_t k = 0; k < ns; ++k)
        order[k] = (uint32_t)k;
    weld_coords = stl->vertex; /* qsort has no context argument in C11 */
    qsort(order, ns, sizeof(uint32_t), by_coords);
    double r[3][3];
    rotation(rotate, r);
    size_t nv = 0;
    for (size_t k = 0; k < ns; ++k) {
        const double *p = stl->vertex + 3 * order[k];
        if (k == 0 || memcmp(p, stl->vertex + 3 * order[k - 1], 3 * sizeof(double)) != 0) {
            for (int i = 0; i < 3; ++i)
                m->v[3 * nv + i] =
                    translate[i] + scale * (r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]);
            ++nv;
        }
        m->tri[order[k]] = (uint32_t)(nv - 1);
    }
    sinter_free(ctx, order);
    m->nv = nv;
    m->nt = stl->count;
    for (size_t t = 0; t < m->nt; ++t) {
        uint32_t *c = m->tri + 3 * t;
        if (flip) {
            const uint32_t s = c[1];
            c[1] = c[2];
            c[2] = s;
        }
        const double *a = m->v + 3 * c[0], *b = m->v + 3 * c[1], *d = m->v + 3 * c[2];
        double e1[3], e2[3], e3[3], n[3];
        for (int i = 0; i < 3; ++i)
            e1[i] = b[i] - a[i], e2[i] = d[i] - a[i], e3[i] = d[i] - b[i];
        cross3(e1, e2, n);
        const double area2 = sqrt(dot3(n, n));
        const double longest = fmax(dot3(e1, e1), fmax(dot3(e2, e2), dot3(e3, e3)));
        /* degenerate: its smallest height below 1e-9 of its longest edge */
        if (!(area2 > 1e-9 * longest))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "STL file '%s': facet %zu is degenerate (its vertices are on "
                               "one line or coincide)",
                               path, t + 1);
        for (int i = 0; i < 3; ++i)
            m->fn[3 * t + i] = n[i] / area2;
        double *disc = m->disc + 4 * t;
        for (int i = 0; i < 3; ++i)
            disc[i] = (a[i] + b[i] + d[i]) / 3.0;
        disc[3] = 0.0;
        for (int p = 0; p < 3; ++p) {
            const double *q = m->v + 3 * c[p];
            const double g[3] = {q[0] - disc[0], q[1] - disc[1], q[2] - disc[2]};
            disc[3] = fmax(disc[3], sqrt(dot3(g, g)));
        }
        disc[3] *= 1.0 + 1e-12; /* round-off: the bound stays a bound */
        const double *sn = stl->normal + 3 * t;
        double stored[3];
        for (int i = 0; i < 3; ++i) /* the stored normal placed as the points (no scale) */
            stored[i] = (flip ? -1.0 : 1.0) * (r[i][0] * sn[0] + r[i][1] * sn[1] + r[i][2] * sn[2]);
        if (dot3(stored, stored) > 0.0 &&
            dot3(stored, m->fn + 3 * t) < -0.5 * sqrt(dot3(stored, stored)))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "STL file '%s': facet %zu's stored normal points against its "
                               "vertices' winding (right-hand rule): inconsistent normals",
                               path, t + 1);
    }
    return SINTER_OK;
}

/* Edge pseudo-normals and topology checks: m->en, m->vn, m->open_edges. */
static sinter_status make_pseudo_normals(sinter_ctx *ctx, const char *path, sinter_mesh *m)
{
    const size_t ne = 3 * m->nt;
    edge_ref *e = sinter_alloc(ctx, ne * sizeof(edge_ref));
    unsigned char *open_vertex = sinter_calloc(ctx, m->nv + 1, 1);
    m->en = sinter_calloc(ctx, 9 * m->nt, sizeof(double));
    m->vn = sinter_calloc(ctx, 3 * m->nv, sizeof(double));
    sinter_status st = SINTER_OK;
    if (!e || !open_vertex || !m->en || !m->vn)
        st = sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
    for (size_t t = 0; t < m->nt && st == SINTER_OK; ++t)
        for (int s = 0; s < 3; ++s) {
            const uint32_t a = m->tri[3 * t + s], b = m->tri[3 * t + (s + 1) % 3];
            e[3 * t + s] = (edge_ref){a < b ? a : b, a < b ? b : a, (uint32_t)t, s, a < b};
        }
    if (st == SINTER_OK)
        qsort(e, ne, sizeof(edge_ref), by_edge);
    size_t open = 0;
    for (size_t k = 0; k < ne && st == SINTER_OK;) {
        size_t j = k + 1;
        while (j < ne && e[j].low == e[k].low && e[j].high == e[k].high)
            ++j;
        if (j - k > 2) {
            st = sinter_fail(ctx, SINTER_ERR_INVALID,
                             "STL file '%s': an edge is shared by %zu facets (%u, %u, %u...): "
                             "not a surface",
                             path, j - k, e[k].tri + 1, e[k + 1].tri + 1, e[k + 2].tri + 1);
        } else if (j - k == 2 && e[k].forward == e[k + 1].forward) {
            st = sinter_fail(ctx, SINTER_ERR_INVALID,
                             "STL file '%s': facets %u and %u share an edge but are wound the "
                             "same way along it: inconsistent normals",
                             path, e[k].tri + 1, e[k + 1].tri + 1);
        } else if (j - k == 2) {
            double sum[3];
            for (int i = 0; i < 3; ++i)
                sum[i] = m->fn[3 * e[k].tri + i] + m->fn[3 * e[k + 1].tri + i];
            memcpy(m->en + 9 * e[k].tri + 3 * e[k].slot, sum, sizeof(sum));
            memcpy(m->en + 9 * e[k + 1].tri + 3 * e[k + 1].slot, sum, sizeof(sum));
        } else {
            ++open;
            open_vertex[e[k].low] = open_vertex[e[k].high] = 1;
        }
        k = j;
    }
    m->open_edges = open;
    for (size_t t = 0; t < m->nt && st == SINTER_OK; ++t) /* angle-weighted vertex normals */
        for (int s = 0; s < 3; ++s) {
            const uint32_t a = m->tri[3 * t + s], b = m->tri[3 * t + (s + 1) % 3],
                           c = m->tri[3 * t + (s + 2) % 3];
            double u[3], w[3];
            for (int i = 0; i < 3; ++i)
                u[i] = m->v[3 * b + i] - m->v[3 * a + i], w[i] = m->v[3 * c + i] - m->v[3 * a + i];
            const double cosine = dot3(u, w) / sqrt(dot3(u, u) * dot3(w, w));
            const double angle = acos(fmin(fmax(cosine, -1.0), 1.0));
            for (int i = 0; i < 3; ++i)
                m->vn[3 * a + i] += angle * m->fn[3 * t + i];
        }
    for (size_t v = 0; v < m->nv && st == SINTER_OK; ++v)
        if (open_vertex[v])
            memset(m->vn + 3 * v, 0, 3 * sizeof(double));
    sinter_free(ctx, e);
    sinter_free(ctx, open_vertex);
    return st;
}

/* The cell grid: cells of edge h, about the mean of the triangles' longest edges (at most
 * 8 nt + 4096 cells), each listing the triangles whose box meets it; layer[c] the Chebyshev
 * distance to the nearest listed cell (passes of the 26-neighbour minimum, capped at 65535). */
static sinter_status make_grid(sinter_ctx *ctx, const char *path, sinter_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double mean = 0.0;
    for (size_t t = 0; t < m->nt; ++t) {
        double longest = 0.0;
        for (int s = 0; s < 3; ++s) {
            const double *a = m->v + 3 * m->tri[3 * t + s],
                         *b = m->v + 3 * m->tri[3 * t + (s + 1) % 3];
            const double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            longest = fmax(longest, sqrt(dot3(d, d)));
            for (int i = 0; i < 3; ++i)
                lo[i] = fmin(lo[i], a[i]), hi[i] = fmax(hi[i], a[i]);
        }
        mean += longest / (double)m->nt;
    }
    double h = mean;
    for (;;) {
        double cells = 1.0;
        for (int i = 0; i < 3; ++i)
            cells *= floor((hi[i] - lo[i]) / h) + 1.0;
        if (cells <= 8.0 * (double)m->nt + 4096.0)
            break;
        h *= 1.25;
    }
    size_t nc = 1;
    for (int i = 0; i < 3; ++i) {
        m->dim[i] = (int)floor((hi[i] - lo[i]) / h) + 1;
        m->lo[i] = lo[i] - 0.5 * (m->dim[i] * h - (hi[i] - lo[i])); /* centred */
        nc *= (size_t)m->dim[i];
    }
    m->h = h;
    m->cull = sinter_alloc(ctx, 10 * m->nt * sizeof(double));
    if (!m->cull)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
    for (size_t t = 0; t < m->nt; ++t) {
        memcpy(m->cull + 10 * t, m->v + 3 * m->tri[3 * t], 3 * sizeof(double));
        memcpy(m->cull + 10 * t + 3, m->fn + 3 * t, 3 * sizeof(double));
        memcpy(m->cull + 10 * t + 6, m->disc + 4 * t, 4 * sizeof(double));
    }
    m->start = sinter_calloc(ctx, nc + 1, sizeof(uint32_t));
    m->layer = sinter_alloc(ctx, nc * sizeof(uint16_t));
    if (!m->start || !m->layer)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
    /* two passes: count, then list */
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t t = 0; t < m->nt; ++t) {
            int a[3], b[3];
            for (int i = 0; i < 3; ++i) {
                double tl = INFINITY, th = -INFINITY;
                for (int s = 0; s < 3; ++s) {
                    tl = fmin(tl, m->v[3 * m->tri[3 * t + s] + i]);
                    th = fmax(th, m->v[3 * m->tri[3 * t + s] + i]);
                }
                a[i] = (int)floor((tl - m->lo[i]) / h);
                b[i] = (int)floor((th - m->lo[i]) / h);
                a[i] = a[i] < 0 ? 0 : a[i] >= m->dim[i] ? m->dim[i] - 1 : a[i];
                b[i] = b[i] < 0 ? 0 : b[i] >= m->dim[i] ? m->dim[i] - 1 : b[i];
            }
            for (int z = a[2]; z <= b[2]; ++z)
                for (int y = a[1]; y <= b[1]; ++y)
                    for (int x = a[0]; x <= b[0]; ++x) {
                        const size_t c =
                            ((size_t)z * (size_t)m->dim[1] + (size_t)y) * (size_t)m->dim[0] +
                            (size_t)x;
                        if (pass == 0)
                            ++m->start[c + 1];
                        else
                            m->item[m->start[c + 1]++] = (uint32_t)t;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < nc; ++c)
                m->start[c + 1] += m->start[c];
            m->item = sinter_alloc(ctx, (size_t)m->start[nc] * sizeof(uint32_t) + 1);
            if (!m->item)
                return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
            memmove(m->start + 1, m->start, nc * sizeof(uint32_t)); /* start[c + 1] = start[c] */
            m->start[0] = 0;
        }
    }
    /* after the second pass start[c + 1] is the end of cell c, start[0] = 0 */
    for (size_t c = 0; c < nc; ++c)
        m->layer[c] = m->start[c + 1] > m->start[c] ? 0 : 65535;
    for (int changed = 1, sweep = 0; changed; ++sweep) { /* forward and backward sweeps */
        changed = 0;
        for (size_t q = 0; q < nc; ++q) {
            const size_t c = sweep % 2 ? nc - 1 - q : q;
            const int x = (int)(c % (size_t)m->dim[0]);
            const int y = (int)(c / (size_t)m->dim[0] % (size_t)m->dim[1]);
            const int z = (int)(c / ((size_t)m->dim[0] * (size_t)m->dim[1]));
            unsigned best = m->layer[c];
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int X = x + dx, Y = y + dy, Z = z + dz;
                        if (X < 0 || Y < 0 || Z < 0 || X >= m->dim[0] || Y >= m->dim[1] ||
                            Z >= m->dim[2])
                            continue;
                        const size_t o =
                            ((size_t)Z * (size_t)m->dim[1] + (size_t)Y) * (size_t)m->dim[0] +
                            (size_t)X;
                        if (m->layer[o] + 1u < best)
                            best = m->layer[o] + 1u;
                    }
            if (best < m->layer[c]) {
                m->layer[c] = (uint16_t)best;
                changed = 1;
            }
        }
    }
    return SINTER_OK;
}

sinter_status sinter_mesh_build(sinter_ctx *ctx, const sinter_stl *stl, const char *path,
                                double scale, const double rotate[3], const double translate[3],
                                int flip, double reach, sinter_mesh **out)
{
    sinter_mesh *m = sinter_calloc(ctx, 1, sizeof(sinter_mesh));
    if (m == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "STL file '%s': out of memory", path);
    m->reach = reach > 0.0 ? reach : INFINITY;
    sinter_status st = make_triangles(ctx, stl, path, scale, rotate, translate, flip, m);
    if (st == SINTER_OK)
        st = make_pseudo_normals(ctx, path, m);
    if (st == SINTER_OK)
        st = make_grid(ctx, path, m);
    if (st != SINTER_OK) {
        sinter_mesh_destroy(ctx, m);
        return st;
    }
    *out = m;
    return SINTER_OK;
}
