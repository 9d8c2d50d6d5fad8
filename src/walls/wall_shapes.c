/* Wall kinds other than the infinite plane: closest point, signed distance and contact normal
 * of a particle centre, their drawing, and their construction (sinter_walls_add_rectangle, _disc,
 * _cylinder). A kind is one case of sinter_wall_shape_contact; a later kind (a triangle mesh)
 * adds its case and its constructor here or in its own folder.
 *
 * The contact of a sphere with any kind is the contact with the closest point of the surface
 * treated locally as a plane (the wall as a particle of infinite radius, as for planes): the
 * overlap is r - s, the normal the direction from the closest point to the centre. */
#include <math.h>
#include <string.h>

#include "walls.h"

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A point at lateral offset `lateral` (in the wall's plane, from the closest edge point) beyond
 * the edge of a planar kind, at height h above the plane: distance and normal from the closest
 * edge point. The edge is a rim met from either side, so that the distance is continuous
 * beyond the edge (the neighbour list's skin bounds how far a contact can come between two
 * searches); behind the face itself the plane's signed distance holds (one-sided, as the
 * infinite plane: particles belong in front). */
static double edge_contact(const sinter_wall *w, const double *lateral, double h, double *n)
{
    double v[3];
    for (int d = 0; d < 3; ++d)
        v[d] = lateral[d] + h * w->n[d];
    const double s = sqrt(dot3(v, v));
    if (n != NULL) {
        if (s > 0.0)
            for (int d = 0; d < 3; ++d)
                n[d] = v[d] / s;
        else
            memcpy(n, w->n, 3 * sizeof(double));
    }
    return s;
}

static double rectangle_contact(const sinter_wall *w, const double *x, double *n)
{
    const double d[3] = {x[0] - w->p[0], x[1] - w->p[1], x[2] - w->p[2]};
    const double h = dot3(d, w->n), a = dot3(d, w->e1), b = dot3(d, w->e2);
    const double ca = fmin(fmax(a, -w->half[0]), w->half[0]);
    const double cb = fmin(fmax(b, -w->half[1]), w->half[1]);
    if (ca == a && cb == b) { /* over the face: the plane's distance */
        if (n != NULL)
            memcpy(n, w->n, 3 * sizeof(double));
        return h;
    }
    double lateral[3];
    for (int k = 0; k < 3; ++k)
        lateral[k] = (a - ca) * w->e1[k] + (b - cb) * w->e2[k];
    return edge_contact(w, lateral, h, n);
}

static double disc_contact(const sinter_wall *w, const double *x, double *n)
{
    const double d[3] = {x[0] - w->p[0], x[1] - w->p[1], x[2] - w->p[2]};
    const double h = dot3(d, w->n);
    double t[3];
    for (int k = 0; k < 3; ++k)
        t[k] = d[k] - h * w->n[k];
    const double rho = sqrt(dot3(t, t));
    if (rho <= w->radius) {
        if (n != NULL)
            memcpy(n, w->n, 3 * sizeof(double));
        return h;
    }
    const double f = (rho - w->radius) / rho;
    for (int k = 0; k < 3; ++k)
        t[k] *= f;
    return edge_contact(w, t, h, n);
}

/* A cylinder's lateral surface: the radial distance from the axis against the radius. Beyond
 * its ends (|axial offset| > half_length) an open tube's rim circle, met from either side (the
 * distance continuous there, as a finite plane's edge). */
static double cylinder_contact(const sinter_wall *w, const double *x, double *n)
{
    const double d[3] = {x[0] - w->p[0], x[1] - w->p[1], x[2] - w->p[2]};
    const double h = dot3(d, w->axis);
    double t[3];
    for (int k = 0; k < 3; ++k)
        t[k] = d[k] - h * w->axis[k];
    const double rho = sqrt(dot3(t, t));
    if (fabs(h) > w->half_length) { /* from the rim's closest point */
        const double beyond = h > 0.0 ? h - w->half_length : h + w->half_length;
        const double f = rho > 0.0 ? (rho - w->radius) / rho : 0.0;
        double v[3];
        for (int k = 0; k < 3; ++k)
            v[k] = (rho > 0.0 ? f * t[k] : -w->radius * w->e1[k]) + beyond * w->axis[k];
        const double s = sqrt(dot3(v, v));
        if (n != NULL) {
            if (s > 0.0)
                for (int k = 0; k < 3; ++k)
                    n[k] = v[k] / s;
            else
                memcpy(n, w->axis, 3 * sizeof(double));
        }
        return s;
    }
    if (n != NULL) {
        if (rho > 0.0) {
            const double sign = w->inside ? -1.0 : 1.0; /* inside: towards the axis */
            for (int k = 0; k < 3; ++k)
                n[k] = sign * t[k] / rho;
        } else { /* on the axis: any radial direction (e1 is one) */
            memcpy(n, w->e1, 3 * sizeof(double));
        }
    }
    return w->inside ? w->radius - rho : rho - w->radius;
}

double sinter_wall_shape_contact(const sinter_wall *w, const double *x, double *n)
{
    switch (w->kind) {
    case SINTER_WALL_RECTANGLE:
        return rectangle_contact(w, x, n);
    case SINTER_WALL_DISC:
        return disc_contact(w, x, n);
    case SINTER_WALL_CYLINDER:
        return cylinder_contact(w, x, n);
    case SINTER_WALL_MESH:
        return sinter_wall_mesh_contact(w, x, n);
    default: {
        const double s = sinter_plane_distance(w, x);
        if (n != NULL)
            memcpy(n, w->n, 3 * sizeof(double));
        return s;
    }
    }
}

static int finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* v / |v| into unit, scaled first (as add_plane's); 0 for the zero vector. */
static int unit_of(const double v[3], double unit[3])
{
    const double scale = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(scale > 0.0))
        return 0;
    const double s[3] = {v[0] / scale, v[1] / scale, v[2] / scale};
    const double len = sqrt(dot3(s, s));
    for (int d = 0; d < 3; ++d)
        unit[d] = s[d] / len;
    return 1;
}

/* A unit vector normal to unit a: a x (the axis a is least along). */
static void any_normal(const double *a, double *e)
{
    int m = 0;
    for (int d = 1; d < 3; ++d)
        if (fabs(a[d]) < fabs(a[m]))
            m = d;
    double z[3] = {0, 0, 0}, c[3];
    z[m] = 1.0;
    c[0] = a[1] * z[2] - a[2] * z[1];
    c[1] = a[2] * z[0] - a[0] * z[2];
    c[2] = a[0] * z[1] - a[1] * z[0];
    unit_of(c, e);
}

/* a x b into out */
static void cross3(const double *a, const double *b, double *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void sinter_wall_frame(sinter_wall *w)
{
    memcpy(w->axis, w->n, sizeof(w->axis));
    any_normal(w->axis, w->e1);
    memcpy(w->e1_0, w->e1, sizeof(w->e1));
    cross3(w->axis, w->e1, w->e2);
}

/* A plane wall added by add_plane (the common set-up), then given its kind. */
static sinter_status add_kind(sinter_walls *walls, const char *func, const double point[3],
                              const double axis[3], const sinter_material *material, size_t *index,
                              sinter_wall **out)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(walls->ctx, point);
    SINTER_CHECK_NULL(walls->ctx, axis);
    SINTER_CHECK_NULL(walls->ctx, material);
    double unit[3];
    if (!finite3(point) || !finite3(axis))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "%s: point (%g, %g, %g) and axis (%g, %g, %g) must be finite", func,
                           point[0], point[1], point[2], axis[0], axis[1], axis[2]);
    if (!unit_of(axis, unit))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "%s: the normal (or axis) is the zero vector", func);
    size_t k = 0;
    const sinter_status st = sinter_walls_add_plane(walls, point, unit, material, &k);
    if (st != SINTER_OK)
        return st;
    sinter_wall *w = &walls->wall[k];
    w->moment_wanted = 1;
    if (index)
        *index = k;
    *out = w;
    return SINTER_OK;
}

static int positive(double v)
{
    return v > 0.0 && v < INFINITY;
}

sinter_status sinter_walls_add_rectangle(sinter_walls *walls, const double center[3],
                                         const double normal[3], const double edge[3],
                                         double half_1, double half_2,
                                         const sinter_material *material, size_t *index)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(walls->ctx, edge);
    if (!positive(half_1) || !positive(half_2))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_rectangle: half lengths %g m and %g m must be "
                           "positive and finite",
                           half_1, half_2);
    SINTER_CHECK_NULL(walls->ctx, normal);
    double n[3], e[3] = {0, 0, 0};
    if (finite3(normal) && unit_of(normal, n)) { /* else add_kind names the normal */
        const double en = finite3(edge) ? dot3(edge, n) : 0.0;
        for (int d = 0; d < 3; ++d) /* the edge's part in the plane */
            e[d] = edge[d] - en * n[d];
        if (!finite3(edge) || !unit_of(e, e))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_add_rectangle: the edge direction (%g, %g, %g) "
                               "must be finite and not parallel to the normal",
                               edge[0], edge[1], edge[2]);
    }
    sinter_wall *w = NULL;
    const sinter_status st =
        add_kind(walls, "sinter_walls_add_rectangle", center, normal, material, index, &w);
    if (st != SINTER_OK)
        return st;
    w->kind = SINTER_WALL_RECTANGLE;
    memcpy(w->e1, e, sizeof(e));
    memcpy(w->e1_0, e, sizeof(e));
    cross3(w->axis, w->e1, w->e2);
    w->half[0] = half_1;
    w->half[1] = half_2;
    return SINTER_OK;
}

sinter_status sinter_walls_add_disc(sinter_walls *walls, const double center[3],
                                    const double normal[3], double radius,
                                    const sinter_material *material, size_t *index)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    if (!positive(radius))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_disc: radius %g m must be positive and finite",
                           radius);
    sinter_wall *w = NULL;
    const sinter_status st =
        add_kind(walls, "sinter_walls_add_disc", center, normal, material, index, &w);
    if (st != SINTER_OK)
        return st;
    w->kind = SINTER_WALL_DISC;
    w->radius = radius;
    return SINTER_OK;
}

sinter_status sinter_walls_add_cylinder(sinter_walls *walls, const double point[3],
                                        const double axis[3], double radius, double half_length,
                                        int inside, const sinter_material *material, size_t *index)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    if (!positive(radius))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_cylinder: radius %g m must be positive and finite",
                           radius);
    if (!(half_length > 0.0)) /* INFINITY: an infinite cylinder */
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_cylinder: half length %g m must be positive "
                           "(HUGE_VAL: infinite)",
                           half_length);
    if (inside != 0 && inside != 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_cylinder: inside = %d must be 1 (particles inside) "
                           "or 0 (outside)",
                           inside);
    sinter_wall *w = NULL;
    const sinter_status st =
        add_kind(walls, "sinter_walls_add_cylinder", point, axis, material, index, &w);
    if (st != SINTER_OK)
        return st;
    w->kind = SINTER_WALL_CYLINDER;
    w->radius = radius;
    w->half_length = half_length;
    w->inside = inside;
    return SINTER_OK;
}

sinter_status sinter_walls_get_kind(const sinter_walls *walls, size_t k, int *kind)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, kind);
    *kind = w->kind;
    return SINTER_OK;
}

sinter_status sinter_walls_get_shape(const sinter_walls *walls, size_t k, double axis[3],
                                     double edge[3], double size[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (axis)
        memcpy(axis, w->axis, 3 * sizeof(double));
    if (edge)
        memcpy(edge, w->e1, 3 * sizeof(double));
    if (size) {
        size[0] = w->kind == SINTER_WALL_RECTANGLE ? w->half[0] : w->radius;
        size[1] = w->kind == SINTER_WALL_RECTANGLE ? w->half[1] : w->half_length;
        size[2] = w->inside;
    }
    return SINTER_OK;
}

sinter_status sinter_walls_set_spin(sinter_walls *walls, size_t k, double omega)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (!isfinite(omega))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_spin: angular velocity %g rad/s of wall %zu must "
                           "be finite",
                           omega, k);
    w->spin = omega;
    w->moment_wanted = 1;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_set_moment(sinter_walls *walls, size_t k, int on)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (on != 0 && on != 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_moment: on = %d of wall %zu must be 0 or 1", on, k);
    w->moment_wanted = on;
    if (!on)
        memset(w->moment, 0, sizeof(w->moment));
    return SINTER_OK;
}

sinter_status sinter_walls_get_moment(const sinter_walls *walls, size_t k, double moment[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, moment);
    memcpy(moment, w->moment, sizeof(w->moment));
    return SINTER_OK;
}

/* The axial range [m] of a box's corners about point p along unit a (an infinite cylinder
 * drawn over the domain). */
static void axial_range(const double *p, const double *a, const double lo[3], const double hi[3],
                        double *amin, double *amax)
{
    *amin = INFINITY;
    *amax = -INFINITY;
    for (int c = 0; c < 8; ++c) {
        const double x[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1],
                             (c & 4) ? hi[2] : lo[2]};
        const double h = (x[0] - p[0]) * a[0] + (x[1] - p[1]) * a[1] + (x[2] - p[2]) * a[2];
        *amin = fmin(*amin, h);
        *amax = fmax(*amax, h);
    }
}

int sinter_wall_outline(const sinter_wall *w, const double lo[3], const double hi[3],
                        double (*points)[3], int *sizes, double (*normals)[3])
{
    const double *p = w->p;
    if (w->kind == SINTER_WALL_MESH) /* its triangles instead (sinter_wall_mesh_draw) */
        return 0;
    if (w->kind == SINTER_WALL_RECTANGLE) {
        static const double sign[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (int c = 0; c < 4; ++c)
            for (int d = 0; d < 3; ++d)
                points[c][d] =
                    p[d] + sign[c][0] * w->half[0] * w->e1[d] + sign[c][1] * w->half[1] * w->e2[d];
        sizes[0] = 4;
        memcpy(normals[0], w->n, 3 * sizeof(double));
        return 1;
    }
    const int segments = SINTER_WALL_OUTLINE_SEGMENTS;
    if (w->kind == SINTER_WALL_DISC) {
        for (int c = 0; c < segments; ++c) {
            const double phi = 2.0 * 3.14159265358979323846 * c / segments;
            for (int d = 0; d < 3; ++d)
                points[c][d] = p[d] + w->radius * (cos(phi) * w->e1[d] + sin(phi) * w->e2[d]);
        }
        sizes[0] = segments;
        memcpy(normals[0], w->n, 3 * sizeof(double));
        return 1;
    }
    /* a cylinder: quads around it, over its length or the domain's */
    double amin = -w->half_length, amax = w->half_length;
    if (!isfinite(w->half_length))
        axial_range(p, w->axis, lo, hi, &amin, &amax);
    for (int c = 0; c < segments; ++c) {
        double radial[2][3];
        for (int e = 0; e < 2; ++e) {
            const double phi = 2.0 * 3.14159265358979323846 * (c + e) / segments;
            for (int d = 0; d < 3; ++d)
                radial[e][d] = cos(phi) * w->e1[d] + sin(phi) * w->e2[d];
        }
        const double along[4] = {amin, amin, amax, amax};
        const int side[4] = {0, 1, 1, 0};
        for (int v = 0; v < 4; ++v)
            for (int d = 0; d < 3; ++d)
                points[4 * c + v][d] =
                    p[d] + w->radius * radial[side[v]][d] + along[v] * w->axis[d];
        const double mid = 2.0 * 3.14159265358979323846 * (c + 0.5) / segments;
        for (int d = 0; d < 3; ++d) /* into the particles: inwards for a die */
            normals[c][d] = (w->inside ? -1.0 : 1.0) * (cos(mid) * w->e1[d] + sin(mid) * w->e2[d]);
        sizes[c] = 4;
    }
    return segments;
}
