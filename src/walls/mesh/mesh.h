/* A triangle-mesh wall (SINTER_WALL_MESH): its triangles read from STL (stl_read.c), checked
 * and given their pseudo-normals and cell grid (mesh_build.c), and the closest feature of a
 * particle centre (mesh_contact.c). */
#ifndef SINTER_WALL_MESH_H
#define SINTER_WALL_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

/* A triangle soup as read: 9 doubles per facet (three vertices, file coordinates) and the
 * facet's stored normal (3 per facet; zero where the file gives none). */
typedef struct sinter_stl {
    size_t count;
    double *vertex; /* 9 per facet */
    double *normal; /* 3 per facet */
} sinter_stl;

/* Read an ASCII or binary STL file into stl (freed by sinter_stl_free). Errors:
 * SINTER_ERR_IO (cannot read), SINTER_ERR_PARSE (not STL, with the line or facet). */
sinter_status sinter_stl_read(sinter_ctx *ctx, const char *path, sinter_stl *stl);
void sinter_stl_free(sinter_ctx *ctx, sinter_stl *stl);

typedef struct sinter_mesh {
    size_t nv, nt;
    double *v;         /* 3 per vertex [m], at the wall's point p0 (its motion moves them all) */
    uint32_t *tri;     /* 3 vertex indices per triangle, counter-clockwise seen from the front */
    double *fn;        /* 3 per triangle: unit normal (right-hand rule) into the particles */
    double *en;        /* 9 per triangle: for edges (v0 v1), (v1 v2), (v2 v0) the sum of the two
                          faces' normals (its sign's pseudo-normal); zero on an open edge */
    double *disc;      /* 4 per triangle: its centroid [m] and the largest distance from it to
                          a vertex [m] (the triangle lies in that disc of its plane) */
    double *vn;        /* 3 per vertex: angle-weighted sum of its faces' normals; zero on an
                          open edge's vertex */
    double *cull;      /* 10 per triangle, what the search's first tests read, together: its
                          first vertex, fn and disc (copies) */
    size_t open_edges; /* edges of one triangle only: rims met from either side */
    /* the cell grid over the triangles' boxes */
    double lo[3];    /* its corner [m] */
    double h;        /* cell edge [m] */
    int dim[3];      /* cells per axis */
    uint32_t *start; /* cell c's triangles: item[start[c] .. start[c + 1]) */
    uint32_t *item;
    uint16_t *layer; /* Chebyshev distance in cells to the nearest cell with a triangle */
    double reach;    /* distances beyond it may come out as a lower bound [m] (INFINITY: never) */
} sinter_mesh;

/* The mesh of stl's facets placed by x' = translate + R (scale x), R turning by rotate[0]
 * about x, then rotate[1] about y, then rotate[2] about z [rad]; flip: normals reversed.
 * Checks (SINTER_ERR_INVALID naming the facet): degenerate triangles, an edge of more than
 * two triangles, neighbours with opposite windings, a stored normal opposite to the winding.
 * `path` names the file in messages. */
sinter_status sinter_mesh_build(sinter_ctx *ctx, const sinter_stl *stl, const char *path,
                                double scale, const double rotate[3], const double translate[3],
                                int flip, double reach, sinter_mesh **out);
void sinter_mesh_destroy(sinter_ctx *ctx, sinter_mesh *mesh);

/* Signed distance [m] of point x (in the mesh's frame) from the closest point of the mesh,
 * positive in front, and the unit normal n there towards x (may be NULL). */
double sinter_mesh_closest(const sinter_mesh *mesh, const double *x, double *n);

/* The same bits as sinter_mesh_closest, its search started from triangle *hint's distance
 * (UINT32_MAX or any index past the mesh: none) so that a hint near the answer (the triangle
 * of the last step's closest point) leaves few triangles to test; *hint becomes the triangle
 * of the closest point (unchanged when the distance is a lower bound beyond the reach). */
double sinter_mesh_closest_hinted(const sinter_mesh *mesh, const double *x, double *n,
                                  uint32_t *hint);

/* sinter_mesh_closest_hinted with a certificate cert[4] (the last search's point and a radius;
 * radius <= 0: none) kept by the caller per contact: within the radius the hint's triangle is
 * still the closest and is taken without a search (the same bits); otherwise the search, and a
 * new certificate. */
double sinter_mesh_closest_certified(const sinter_mesh *mesh, const double *x, double *n,
                                     uint32_t *hint, double cert[4]);

/* 1 if sinter_mesh_closest_hinted(mesh, x, ..) < bound [m] (a neighbour list's r + skin), by a
 * search that ends at the bound; a sphere farther than it, in front of the plane of its hint
 * triangle, is taken as in front (0). Updates *hint as sinter_mesh_closest_hinted when it
 * finds a triangle. */
int sinter_mesh_within(const sinter_mesh *mesh, const double *x, double bound, uint32_t *hint);

#endif
