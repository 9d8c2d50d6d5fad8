/* ParaView output beside the particles' frames: contacts, links and walls as VTK XML PolyData
 * (.vtp, ascii, full precision), see io/vtp.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/id_row.h"
#include "io/series.h"
#include "io/vtk_arrays.h"
#include "io/vtp.h"
#include "particles/particles.h"
#include "walls/walls.h"

/* Index of particle `id` in the sorted table, or SIZE_MAX. */
static size_t find(const sinter_id_row *table, size_t n, uint64_t id)
{
    const sinter_id_row key = {id, 0};
    const sinter_id_row *hit = bsearch(&key, table, n, sizeof(*table), sinter_id_row_compare);
    return hit != NULL ? hit->index : SIZE_MAX;
}

static void header(FILE *fp, size_t points, size_t lines, size_t polys, int binary)
{
    /* binary arrays need version 1.0 for their UInt64 byte counts (as the .vtu frames) */
    fprintf(fp,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"PolyData\" version=\"%s\" byte_order=\"LittleEndian\"%s>\n"
            "  <PolyData>\n"
            "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"0\" NumberOfLines=\"%zu\" "
            "NumberOfStrips=\"0\" NumberOfPolys=\"%zu\">\n",
            (binary & SINTER_VTK_BINARY) ? "1.0" : "0.1",
            (binary & SINTER_VTK_BINARY) ? " header_type=\"UInt64\"" : "", points, lines, polys);
}

static void footer(FILE *fp)
{
    fputs("    </Piece>\n"
          "  </PolyData>\n"
          "</VTKFile>\n",
          fp);
}

/* Offsets of cells of two points (lines), and of cells ending at the size_t offsets given. */
static uint64_t line_offset_bits(const void *data, size_t i)
{
    (void)data;
    return 2 * ((uint64_t)i + 1);
}

static uint64_t size_bits(const void *data, size_t i)
{
    return (uint64_t)((const size_t *)data)[i];
}

/* The cells' connectivity (0 .. points-1 in order) and offsets (`offsets`, or two points a
 * cell when NULL). */
static void cells(FILE *fp, const char *element, size_t points, size_t count, const size_t *offsets,
                  int binary)
{
    fprintf(fp, "      <%s>\n", element);
    sinter_vtk_ints(fp, "Int64", "connectivity", NULL, points, 8, sinter_vtk_index_bits, 0, binary);
    sinter_vtk_ints(fp, "Int64", "offsets", offsets, count, 8,
                    offsets != NULL ? size_bits : line_offset_bits, 0, binary);
    fprintf(fp, "      </%s>\n", element);
}

static const char *const CONTACT_NAMES[SINTER_CONTACT_DATA_COUNT_] = {
    "id_a",   "id_b", "wall",         "normal",           "overlap",
    "radius", "area", "normal_force", "tangential_force", "heat_flow",
    "current"};
static const char *const LINK_NAMES[SINTER_LINK_DATA_COUNT_] = {
    "id_a",       "id_b",        "neck_radius", "neck_ratio",
    "approach",   "age",         "phase",       "sintering_force",
    "beam_force", "beam_moment", "correction"};

/* The cell data: every array of the snapshot (contacts, or links). */
static sinter_status cell_data(FILE *fp, const sinter_snapshot *snap, int links, size_t count,
                               int binary)
{
    fputs("      <CellData>\n", fp);
    const int arrays = links ? SINTER_LINK_DATA_COUNT_ : SINTER_CONTACT_DATA_COUNT_;
    for (int q = 0; snap != NULL && q < arrays; ++q) {
        const void *data = NULL;
        size_t n = 0, components = 0;
        sinter_dtype dtype = SINTER_DTYPE_DOUBLE;
        const sinter_status s =
            links ? sinter_snapshot_links(snap, (sinter_link_data)q, &data, &n, &components, &dtype)
                  : sinter_snapshot_contacts(snap, (sinter_contact_data)q, &data, &n, &components,
                                             &dtype);
        if (s != SINTER_OK)
            return s;
        const char *name = links ? LINK_NAMES[q] : CONTACT_NAMES[q];
        if (n != count)
            continue;
        if (dtype == SINTER_DTYPE_DOUBLE)
            sinter_vtk_doubles(fp, name, data, n, components, binary);
        else if (dtype == SINTER_DTYPE_UINT64)
            sinter_vtk_ints(fp, "UInt64", name, data, n, 8, sinter_vtk_uint64_bits, 0, binary);
        else
            sinter_vtk_ints(fp, "Int32", name, data, n, 4, sinter_vtk_int32_bits, 1, binary);
    }
    fputs("      </CellData>\n", fp);
    return SINTER_OK;
}

sinter_status sinter_vtp_write_contacts(sinter_ctx *ctx, const char *path,
                                        const sinter_snapshot *snap, const sinter_particles *ps,
                                        int binary)
{
    static const char *const fn = "sinter_vtp_write_contacts";
    size_t pairs = 0, walls = 0, links = 0;
    if (snap != NULL)
        (void)sinter_snapshot_counts(snap, &pairs, &walls, &links, NULL);
    const int as_links = links > 0;
    const size_t count = as_links ? links : pairs + walls;
    /* the two ends of every line */
    double *points = sinter_calloc(ctx, 6 * count + 6, sizeof(double));
    sinter_id_row *table = sinter_calloc(ctx, ps->count + 1, sizeof(sinter_id_row));
    if (points == NULL || table == NULL) {
        sinter_free(ctx, points);
        sinter_free(ctx, table);
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory", fn);
    }
    for (size_t i = 0; i < ps->count; ++i)
        table[i] = (sinter_id_row){ps->id[i], i};
    qsort(table, ps->count, sizeof(*table), sinter_id_row_compare);
    if (count > 0) {
        const void *a = NULL, *b = NULL, *nv = NULL, *ov = NULL;
        if (as_links) {
            (void)sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &a, NULL, NULL, NULL);
            (void)sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &b, NULL, NULL, NULL);
        } else {
            (void)sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_A, &a, NULL, NULL, NULL);
            (void)sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_B, &b, NULL, NULL, NULL);
            (void)sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_NORMAL, &nv, NULL, NULL, NULL);
            (void)sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_OVERLAP, &ov, NULL, NULL,
                                           NULL);
        }
        const uint64_t *ida = a, *idb = b;
        const double *normal = nv, *overlap = ov;
        for (size_t q = 0; q < count; ++q) {
            const size_t i = find(table, ps->count, ida[q]);
            const int wall = !as_links && q >= pairs;
            const size_t j = wall ? SIZE_MAX : find(table, ps->count, idb[q]);
            for (int d = 0; d < 3; ++d) {
                const double xi = i != SIZE_MAX ? ps->x[3 * i + (size_t)d] : NAN;
                points[6 * q + (size_t)d] = xi;
                /* a wall contact ends on the plane: the centre's distance r - delta along n */
                points[6 * q + 3 + (size_t)d] =
                    wall ? (i != SIZE_MAX
                                ? xi + (ps->radius[i] - overlap[q]) * normal[3 * q + (size_t)d]
                                : NAN)
                         : (j != SIZE_MAX ? ps->x[3 * j + (size_t)d] : NAN);
            }
        }
    }
    sinter_free(ctx, table);
    sinter_out_file out;
    sinter_status st = sinter_out_open(&out, ctx, fn, path);
    if (st != SINTER_OK) {
        sinter_free(ctx, points);
        return st;
    }
    header(out.fp, 2 * count, count, 0, binary);
    fputs("      <Points>\n", out.fp);
    sinter_vtk_doubles(out.fp, "points", points, 2 * count, 3, binary);
    fputs("      </Points>\n", out.fp);
    sinter_free(ctx, points);
    cells(out.fp, "Lines", 2 * count, count, NULL, binary);
    st = cell_data(out.fp, snap, as_links, count, binary);
    footer(out.fp);
    return sinter_out_close(&out, st);
}

/* Corners of the plane through p with unit normal n inside the box lo..hi, in order around
 * the polygon; returns their number (0, or 3 to 6). */
static int clip_plane(const double p[3], const double n[3], const double lo[3], const double hi[3],
                      double corner[12][3])
{
    double c[8][3], s[8];
    for (int k = 0; k < 8; ++k) {
        c[k][0] = k & 1 ? hi[0] : lo[0];
        c[k][1] = k & 2 ? hi[1] : lo[1];
        c[k][2] = k & 4 ? hi[2] : lo[2];
        s[k] = n[0] * (c[k][0] - p[0]) + n[1] * (c[k][1] - p[1]) + n[2] * (c[k][2] - p[2]);
    }
    int count = 0;
    for (int a = 0; a < 8; ++a)
        for (int bit = 1; bit < 8; bit <<= 1) {
            const int b = a | bit;
            if (b == a)
                continue; /* each edge once: from the corner without the bit */
            double x[3];
            if (s[a] == 0.0)
                memcpy(x, c[a], sizeof(x));
            else if (s[b] == 0.0)
                memcpy(x, c[b], sizeof(x));
            else if ((s[a] < 0.0) != (s[b] < 0.0)) {
                const double t = s[a] / (s[a] - s[b]);
                for (int d = 0; d < 3; ++d)
                    x[d] = c[a][d] + t * (c[b][d] - c[a][d]);
            } else {
                continue;
            }
            int seen = 0;
            for (int k = 0; k < count && !seen; ++k)
                seen = x[0] == corner[k][0] && x[1] == corner[k][1] && x[2] == corner[k][2];
            if (!seen && count < 12)
                memcpy(corner[count++], x, sizeof(x));
        }
    if (count < 3)
        return 0;
    /* order by angle about the centroid, in a basis (u, v) of the plane */
    double m[3] = {0, 0, 0}, u[3], v[3];
    for (int k = 0; k < count; ++k)
        for (int d = 0; d < 3; ++d)
            m[d] += corner[k][d] / count;
    const double a[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    u[0] = a[1] * n[2] - a[2] * n[1];
    u[1] = a[2] * n[0] - a[0] * n[2];
    u[2] = a[0] * n[1] - a[1] * n[0];
    v[0] = n[1] * u[2] - n[2] * u[1];
    v[1] = n[2] * u[0] - n[0] * u[2];
    v[2] = n[0] * u[1] - n[1] * u[0];
    double angle[12];
    for (int k = 0; k < count; ++k) {
        double e[3];
        for (int d = 0; d < 3; ++d)
            e[d] = corner[k][d] - m[d];
        angle[k] =
            atan2(e[0] * v[0] + e[1] * v[1] + e[2] * v[2], e[0] * u[0] + e[1] * u[1] + e[2] * u[2]);
    }
    for (int k = 1; k < count; ++k) /* insertion sort of at most 6 corners */
        for (int j = k; j > 0 && angle[j - 1] > angle[j]; --j) {
            double t = angle[j];
            angle[j] = angle[j - 1];
            angle[j - 1] = t;
            double x[3];
            memcpy(x, corner[j], sizeof(x));
            memcpy(corner[j], corner[j - 1], sizeof(x));
            memcpy(corner[j - 1], x, sizeof(x));
        }
    return count;
}

sinter_status sinter_vtp_write_walls(sinter_ctx *ctx, const char *path, const sinter_walls *walls,
                                     const double lo[3], const double hi[3], int binary)
{
    static const char *const fn = "sinter_vtp_write_walls";
    const size_t nw = walls != NULL ? walls->count : 0;
    /* a plane: one polygon of at most 12 points; the other kinds (sinter_wall_outline) up to
     * SEGMENTS polygons of 4 points */
    enum { SEGMENTS = SINTER_WALL_OUTLINE_SEGMENTS, POINTS = 4 * SEGMENTS };
    /* a mesh: its triangles, where its motion has carried them */
    size_t triangles = 0;
    for (size_t k = 0; k < nw; ++k)
        if (walls->wall[k].kind == SINTER_WALL_MESH)
            triangles += sinter_wall_mesh_draw(&walls->wall[k], NULL, NULL);
    const size_t most = SEGMENTS * nw + triangles + 1; /* polygons */
    double *points = sinter_calloc(ctx, 3 * (POINTS * nw + 3 * triangles) + 3, sizeof(double));
    size_t *offsets = sinter_calloc(ctx, most, sizeof(size_t));
    int32_t *index = sinter_calloc(ctx, most, sizeof(int32_t));
    double *normal = sinter_calloc(ctx, 3 * most, sizeof(double));
    double *force = sinter_calloc(ctx, 3 * most, sizeof(double));
    double *temperature = sinter_calloc(ctx, most, sizeof(double));
    sinter_status st = SINTER_OK;
    if (!points || !offsets || !index || !normal || !force || !temperature)
        st = sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory", fn);
    size_t npoints = 0, polys = 0;
    for (size_t k = 0; k < nw && st == SINTER_OK; ++k) {
        const sinter_wall *w = &walls->wall[k];
        if (w->kind == SINTER_WALL_MESH) { /* its triangles, unclipped */
            const size_t nt = sinter_wall_mesh_draw(w, points + 3 * npoints, normal + 3 * polys);
            for (size_t t = 0; t < nt; ++t) {
                npoints += 3;
                offsets[polys] = npoints;
                index[polys] = (int32_t)k;
                memcpy(force + 3 * polys, w->force, 3 * sizeof(double));
                temperature[polys] = w->temperature;
                ++polys;
            }
            continue;
        }
        if (w->kind != SINTER_WALL_PLANE) { /* its own outline, unclipped */
            double corner[POINTS][3], normals[SEGMENTS][3];
            int sizes[SEGMENTS];
            const int count = sinter_wall_outline(w, lo, hi, corner, sizes, normals);
            for (int c = 0, at = 0; c < count; at += sizes[c], ++c) {
                memcpy(points + 3 * npoints, corner[at], 3 * (size_t)sizes[c] * sizeof(double));
                npoints += (size_t)sizes[c];
                offsets[polys] = npoints;
                index[polys] = (int32_t)k;
                memcpy(normal + 3 * polys, normals[c], 3 * sizeof(double));
                memcpy(force + 3 * polys, w->force, 3 * sizeof(double));
                temperature[polys] = w->temperature;
                ++polys;
            }
            continue;
        }
        double corner[12][3];
        const int m = clip_plane(w->p, w->n, lo, hi, corner);
        if (m == 0)
            continue;
        memcpy(points + 3 * npoints, corner, 3 * (size_t)m * sizeof(double));
        npoints += (size_t)m;
        offsets[polys] = npoints;
        index[polys] = (int32_t)k;
        memcpy(normal + 3 * polys, w->n, 3 * sizeof(double));
        memcpy(force + 3 * polys, w->force, 3 * sizeof(double));
        temperature[polys] = w->temperature;
        ++polys;
    }
    sinter_out_file out;
    if (st == SINTER_OK)
        st = sinter_out_open(&out, ctx, fn, path);
    if (st == SINTER_OK) {
        header(out.fp, npoints, 0, polys, binary);
        fputs("      <Points>\n", out.fp);
        sinter_vtk_doubles(out.fp, "points", points, npoints, 3, binary);
        fputs("      </Points>\n", out.fp);
        cells(out.fp, "Polys", npoints, polys, offsets, binary);
        fputs("      <CellData>\n", out.fp);
        sinter_vtk_ints(out.fp, "Int32", "wall", index, polys, 4, sinter_vtk_int32_bits, 1, binary);
        sinter_vtk_doubles(out.fp, "normal", normal, polys, 3, binary);
        sinter_vtk_doubles(out.fp, "force", force, polys, 3, binary);
        sinter_vtk_doubles(out.fp, "temperature", temperature, polys, 1, binary);
        fputs("      </CellData>\n", out.fp);
        footer(out.fp);
        st = sinter_out_close(&out, SINTER_OK);
    }
    sinter_free(ctx, points);
    sinter_free(ctx, offsets);
    sinter_free(ctx, index);
    sinter_free(ctx, normal);
    sinter_free(ctx, force);
    sinter_free(ctx, temperature);
    return st;
}
