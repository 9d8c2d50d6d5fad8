/* A triangle-mesh wall turning rigidly about an axis (sinter_walls_set_rotation): the mesh
 * stays fixed in the frame it was placed in, and each query point is carried into that frame
 * by the inverse turn, R(t)^T (x - c), its contact normal back by R(t) (mesh_wall.c); the
 * surface velocity at a contact point is u + omega a x (c_p - c) (sinter_wall_velocity_at:
 * the wall's point p is the axis point c), which the contact laws' tangential history and
 * damping take. The angle is the spin's, omega (t - motion start), as a rectangle's. */
#include <math.h>
#include <string.h>

#include "mesh.h"
#include "walls/walls.h"

void sinter_wall_rotation_matrix(const double *a, double angle, double *rot)
{
    /* R = cos I + sin [a]x + (1 - cos) a a^T */
    const double c = cos(angle), s = sin(angle), t = 1.0 - c;
    rot[0] = c + t * a[0] * a[0];
    rot[1] = t * a[0] * a[1] - s * a[2];
    rot[2] = t * a[0] * a[2] + s * a[1];
    rot[3] = t * a[1] * a[0] + s * a[2];
    rot[4] = c + t * a[1] * a[1];
    rot[5] = t * a[1] * a[2] - s * a[0];
    rot[6] = t * a[2] * a[0] - s * a[1];
    rot[7] = t * a[2] * a[1] + s * a[0];
    rot[8] = c + t * a[2] * a[2];
}

static int finite3(const double *v)
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

sinter_status sinter_walls_set_rotation(sinter_walls *walls, size_t k, const double point[3],
                                        const double axis[3], double omega)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, point);
    SINTER_CHECK_NULL(walls->ctx, axis);
    if (w->kind != SINTER_WALL_MESH)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_rotation: wall %zu is not a mesh (a rectangle "
                           "turns with sinter_walls_set_spin)",
                           k);
    if (!finite3(point) || !finite3(axis) || !isfinite(omega))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_rotation: point (%g, %g, %g), axis (%g, %g, %g) and "
                           "angular velocity %g rad/s of wall %zu must be finite",
                           point[0], point[1], point[2], axis[0], axis[1], axis[2], omega, k);
    const double scale = fmax(fabs(axis[0]), fmax(fabs(axis[1]), fabs(axis[2])));
    if (!(scale > 0.0))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_rotation: the axis of wall %zu is the zero vector", k);
    const double s[3] = {axis[0] / scale, axis[1] / scale, axis[2] / scale};
    const double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    /* the wall's point becomes the axis point, carried by the translation as before: the
     * displacement p - p0 is kept, and the mesh (placed at t = 0) turns about point */
    for (int d = 0; d < 3; ++d) {
        w->p[d] = point[d] + (w->p[d] - w->p0[d]);
        w->p0[d] = point[d];
        w->axis[d] = s[d] / len;
    }
    double reach = 0.0;
    const sinter_mesh *m = w->mesh;
    for (size_t v = 0; v < m->nv; ++v) {
        const double r[3] = {m->v[3 * v] - point[0], m->v[3 * v + 1] - point[1],
                             m->v[3 * v + 2] - point[2]};
        reach = fmax(reach, sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
    }
    w->turn_reach = reach;
    w->turns = 1;
    w->spin = omega;
    w->angle = 0.0;
    sinter_wall_rotation_matrix(w->axis, 0.0, w->rot);
    w->moment_wanted = 1;
    return sinter_walls_move(walls, walls->time);
}
