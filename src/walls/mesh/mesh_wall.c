/* The triangle-mesh wall kind: sinter_walls_add_mesh, its contact for
 * sinter_wall_shape_contact (the mesh carried by the wall's motion) and its release. */
#include <math.h>
#include <string.h>

#include "mesh.h"
#include "walls/walls.h"

/* Point x in the frame the mesh was placed in: carried back by the wall's translation and,
 * for a mesh that turns, by the inverse turn about the axis through p: p0 + R^T (x - p)
 * (the search, its hints and certificates then work in that fixed frame). */
static inline void to_mesh(const sinter_wall *w, const double *x, double *local)
{
    if (!w->turns) {
        for (int d = 0; d < 3; ++d)
            local[d] = x[d] - (w->p[d] - w->p0[d]);
        return;
    }
    const double r[3] = {x[0] - w->p[0], x[1] - w->p[1], x[2] - w->p[2]};
    const double *m = w->rot;
    for (int d = 0; d < 3; ++d)
        local[d] = w->p0[d] + (m[d] * r[0] + m[3 + d] * r[1] + m[6 + d] * r[2]);
}

/* A normal found in the mesh's frame turned into the world's: R n (n may be NULL). */
static inline void normal_to_world(const sinter_wall *w, double *n)
{
    if (!w->turns || n == NULL)
        return;
    const double *m = w->rot, l[3] = {n[0], n[1], n[2]};
    for (int d = 0; d < 3; ++d)
        n[d] = m[3 * d] * l[0] + m[3 * d + 1] * l[1] + m[3 * d + 2] * l[2];
}

double sinter_wall_mesh_contact(const sinter_wall *w, const double *x, double *n)
{
    /* the mesh was placed at p0: the centre in that frame */
    double local[3];
    to_mesh(w, x, local);
    const double s = sinter_mesh_closest(w->mesh, local, n);
    normal_to_world(w, n);
    return s;
}

size_t sinter_wall_mesh_draw(const sinter_wall *w, double *points, double *normals)
{
    const sinter_mesh *m = w->mesh;
    if (m == NULL)
        return 0;
    if (points != NULL && !w->turns) {
        const double shift[3] = {w->p[0] - w->p0[0], w->p[1] - w->p0[1], w->p[2] - w->p0[2]};
        for (size_t t = 0; t < m->nt; ++t)
            for (int c = 0; c < 3; ++c)
                for (int d = 0; d < 3; ++d)
                    points[9 * t + 3 * c + d] = m->v[3 * m->tri[3 * t + c] + d] + shift[d];
    } else if (points != NULL) { /* p + R (v - p0) */
        const double *r = w->rot;
        for (size_t t = 0; t < m->nt; ++t)
            for (int c = 0; c < 3; ++c) {
                const double *v = m->v + 3 * m->tri[3 * t + c];
                const double l[3] = {v[0] - w->p0[0], v[1] - w->p0[1], v[2] - w->p0[2]};
                for (int d = 0; d < 3; ++d)
                    points[9 * t + 3 * c + d] =
                        w->p[d] + r[3 * d] * l[0] + r[3 * d + 1] * l[1] + r[3 * d + 2] * l[2];
            }
    }
    if (normals != NULL)
        memcpy(normals, m->fn, 3 * m->nt * sizeof(double));
    if (normals != NULL && w->turns)
        for (size_t t = 0; t < m->nt; ++t)
            normal_to_world(w, normals + 3 * t);
    return m->nt;
}

double sinter_wall_contact_hinted(const sinter_wall *w, const double *x, double *n, uint32_t *hint)
{
    if (w->kind != SINTER_WALL_MESH)
        return sinter_wall_shape_contact(w, x, n);
    double local[3];
    to_mesh(w, x, local);
    const double s = sinter_mesh_closest_hinted(w->mesh, local, n, hint);
    normal_to_world(w, n);
    return s;
}

double sinter_wall_contact_certified(const sinter_wall *w, const double *x, double *n,
                                     uint32_t *hint, double cert[4])
{
    if (w->kind != SINTER_WALL_MESH)
        return sinter_wall_shape_contact(w, x, n);
    double local[3];
    to_mesh(w, x, local);
    const double s = sinter_mesh_closest_certified(w->mesh, local, n, hint, cert);
    normal_to_world(w, n);
    return s;
}

int sinter_wall_mesh_within(const sinter_wall *w, const double *x, double bound, uint32_t *hint)
{
    double local[3];
    to_mesh(w, x, local);
    return sinter_mesh_within(w->mesh, local, bound, hint);
}

void sinter_wall_mesh_free(sinter_walls *walls, sinter_wall *w)
{
    sinter_mesh_destroy(walls->ctx, w->mesh);
    w->mesh = NULL;
}

static int finite3(const double *v)
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

sinter_status sinter_walls_add_mesh(sinter_walls *walls, const char *path, double scale,
                                    const double rotate[3], const double translate[3], int flip,
                                    double reach, const sinter_material *material, size_t *index)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(walls->ctx, path);
    SINTER_CHECK_NULL(walls->ctx, rotate);
    SINTER_CHECK_NULL(walls->ctx, translate);
    SINTER_CHECK_NULL(walls->ctx, material);
    if (!(scale > 0.0 && scale < INFINITY) || !finite3(rotate) || !finite3(translate))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_mesh: scale %g must be positive and finite, rotate "
                           "and translate finite",
                           scale);
    if (flip != 0 && flip != 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_mesh: flip = %d must be 0 or 1", flip);
    if (!(reach >= 0.0)) /* INFINITY allowed: exact everywhere, as 0 */
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_mesh: reach %g m must not be negative", reach);
    sinter_stl stl;
    sinter_status st = sinter_stl_read(walls->ctx, path, &stl);
    if (st != SINTER_OK)
        return st;
    sinter_mesh *mesh = NULL;
    st = sinter_mesh_build(walls->ctx, &stl, path, scale, rotate, translate, flip, reach, &mesh);
    sinter_stl_free(walls->ctx, &stl);
    if (st != SINTER_OK)
        return st;
    /* the wall's point: translate; its normal (and axis): the file's z axis as placed */
    const double cx = cos(rotate[0]), sx = sin(rotate[0]), cy = cos(rotate[1]), sy = sin(rotate[1]),
                 cz = cos(rotate[2]), sz = sin(rotate[2]);
    const double z[3] = {cz * sy * cx + sz * sx, sz * sy * cx - cz * sx, cy * cx};
    size_t k = 0;
    st = sinter_walls_add_plane(walls, translate, z, material, &k);
    if (st != SINTER_OK) {
        sinter_mesh_destroy(walls->ctx, mesh);
        return st;
    }
    sinter_wall *w = &walls->wall[k];
    w->kind = SINTER_WALL_MESH;
    w->mesh = mesh;
    w->moment_wanted = 1;
    if (index)
        *index = k;
    return SINTER_OK;
}
