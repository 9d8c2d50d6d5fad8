/* ParaView output: one VTK XML UnstructuredGrid frame per call (.vtu) and collections (.pvd). */
#include <inttypes.h>
#include <math.h>
#include <string.h>

#include "io/series.h"
#include "io/vtk_arrays.h"
#include "io/vtu.h"
#include "particles/particles.h"

/* Point arrays every frame carries; extra arrays must not reuse these names. */
static const char *const BUILTIN_ARRAYS[] = {"radius",  "velocity", "spin",     "temperature",
                                             "current", "force",    "material", "id"};

static sinter_status check_extra(sinter_ctx *ctx, const sinter_vtu_array *extra, size_t extra_count,
                                 size_t particles)
{
    static const char *const fn = "sinter_write_vtu";
    if (extra_count > 0 && extra == NULL)
        return sinter_fail(ctx, SINTER_ERR_NULL,
                           "%s: argument 'extra' is NULL but extra_count is %zu", fn, extra_count);
    for (size_t k = 0; k < extra_count; ++k) {
        const sinter_vtu_array *e = &extra[k];
        if (e->name == NULL)
            return sinter_fail(ctx, SINTER_ERR_NULL, "%s: extra[%zu].name is NULL", fn, k);
        if (e->name[0] == '\0')
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: extra[%zu].name is empty", fn, k);
        if (sinter_find_control_char(e->name))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: extra[%zu].name contains a control character", fn, k);
        if (e->components != 1 && e->components != 3)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: extra array '%s' (extra[%zu]) has %zu components; only 1 or "
                               "3 are supported",
                               fn, e->name, k, e->components);
        if (e->data == NULL && particles > 0)
            return sinter_fail(ctx, SINTER_ERR_NULL,
                               "%s: extra array '%s' (extra[%zu]) has NULL "
                               "data",
                               fn, e->name, k);
        for (size_t b = 0; b < sizeof(BUILTIN_ARRAYS) / sizeof(BUILTIN_ARRAYS[0]); ++b)
            if (strcmp(e->name, BUILTIN_ARRAYS[b]) == 0)
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "%s: extra array name '%s' (extra[%zu]) is already used by a "
                                   "built-in array",
                                   fn, e->name, k);
        for (size_t j = 0; j < k; ++j)
            if (strcmp(e->name, extra[j].name) == 0)
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "%s: extra array name '%s' is used by both extra[%zu] and "
                                   "extra[%zu]",
                                   fn, e->name, j, k);
    }
    return SINTER_OK;
}

sinter_status sinter_write_vtu(const sinter_particles *ps, const char *path,
                               const sinter_vtu_array *extra, size_t extra_count)
{
    return sinter_write_vtu_as(ps, path, extra, extra_count, 0);
}

sinter_status sinter_write_vtu_as(const sinter_particles *ps, const char *path,
                                  const sinter_vtu_array *extra, size_t extra_count, int binary)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    SINTER_CHECK_NULL(ctx, path);
    sinter_status st = check_extra(ctx, extra, extra_count, ps->count);
    if (st != SINTER_OK)
        return st;
    sinter_out_file out;
    st = sinter_out_open(&out, ctx, "sinter_write_vtu", path);
    if (st != SINTER_OK)
        return st;
    FILE *fp = out.fp;
    const size_t n = ps->count - ps->ghost_count; /* owned particles: ghosts are images */
    /* binary arrays need version 1.0 for their UInt64 byte counts */
    fprintf(fp,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"%s\" byte_order=\"LittleEndian\"%s>\n"
            "  <UnstructuredGrid>\n",
            (binary & SINTER_VTK_BINARY) ? "1.0" : "0.1",
            (binary & SINTER_VTK_BINARY) ? " header_type=\"UInt64\"" : "");
    fprintf(fp, "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", n, n);
    fputs("      <PointData Scalars=\"radius\">\n", fp);
    sinter_vtk_doubles(fp, "radius", ps->radius, n, 1, binary);
    sinter_vtk_doubles(fp, "velocity", ps->v, n, 3, binary);
    sinter_vtk_doubles(fp, "spin", ps->w, n, 3, binary);
    sinter_vtk_doubles(fp, "temperature", ps->temperature, n, 1, binary);
    sinter_vtk_doubles(fp, "current", ps->current, n, 1, binary);
    sinter_vtk_doubles(fp, "force", ps->force, n, 3, binary);
    sinter_vtk_ints(fp, "Int32", "material", ps->material, n, 4, sinter_vtk_int32_bits, 1, binary);
    sinter_vtk_ints(fp, "UInt64", "id", ps->id, n, 8, sinter_vtk_uint64_bits, 0, binary);
    for (size_t k = 0; k < extra_count; ++k)
        sinter_vtk_doubles(fp, extra[k].name, extra[k].data, n, extra[k].components, binary);
    fputs("      </PointData>\n"
          "      <Points>\n",
          fp);
    sinter_vtk_doubles(fp, "position", ps->x, n, 3, binary);
    fputs("      </Points>\n"
          "      <Cells>\n",
          fp);
    /* One VTK_VERTEX (type 1) per particle. */
    sinter_vtk_ints(fp, "Int64", "connectivity", NULL, n, 8, sinter_vtk_index_bits, 0, binary);
    sinter_vtk_ints(fp, "Int64", "offsets", NULL, n, 8, sinter_vtk_index_plus_one_bits, 0, binary);
    sinter_vtk_ints(fp, "UInt8", "types", NULL, n, 1, sinter_vtk_vertex_type_bits, 0, binary);
    fputs("      </Cells>\n"
          "    </Piece>\n"
          "  </UnstructuredGrid>\n"
          "</VTKFile>\n",
          fp);
    return sinter_out_close(&out, SINTER_OK);
}

sinter_status sinter_write_pvd(sinter_ctx *ctx, const char *path, size_t count, const double *times,
                               const char *const *files)
{
    return sinter_write_pvd_parts(ctx, path, count, times, files, NULL);
}

sinter_status sinter_write_pvd_parts(sinter_ctx *ctx, const char *path, size_t count,
                                     const double *times, const char *const *files,
                                     const unsigned *parts)
{
    static const char *const fn = "sinter_write_pvd";
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, path);
    if (count > 0) {
        SINTER_CHECK_NULL(ctx, times);
        SINTER_CHECK_NULL(ctx, files);
    }
    for (size_t k = 0; k < count; ++k) {
        if (files[k] == NULL)
            return sinter_fail(ctx, SINTER_ERR_NULL, "%s: files[%zu] is NULL", fn, k);
        if (files[k][0] == '\0')
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: files[%zu] is empty", fn, k);
        if (sinter_find_control_char(files[k]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: files[%zu] contains a control character", fn, k);
        if (!isfinite(times[k]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: times[%zu] is %g; frame times must be finite", fn, k, times[k]);
    }
    sinter_out_file out;
    sinter_status st = sinter_out_open(&out, ctx, fn, path);
    if (st != SINTER_OK)
        return st;
    fputs("<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          "  <Collection>\n",
          out.fp);
    for (size_t k = 0; k < count; ++k) {
        fputs("    <DataSet timestep=\"", out.fp);
        sinter_out_double(out.fp, times[k]);
        fprintf(out.fp, "\" group=\"\" part=\"%u\" file=\"", parts != NULL ? parts[k] : 0u);
        sinter_out_xml(out.fp, files[k]);
        fputs("\"/>\n", out.fp);
    }
    fputs("  </Collection>\n"
          "</VTKFile>\n",
          out.fp);
    return sinter_out_close(&out, SINTER_OK);
}
