/* ParaView output: one VTK XML UnstructuredGrid frame per call (.vtu) and collections (.pvd). */
#include <inttypes.h>
#include <math.h>
#include <string.h>

#include "io/series.h"
#include "particles/particles.h"

/* Point arrays every frame carries; extra arrays must not reuse these names. */
static const char *const BUILTIN_ARRAYS[] = {"radius",  "velocity", "spin",     "temperature",
                                             "current", "force",    "material", "id"};

static void begin_array(FILE *fp, const char *type, const char *name, size_t components)
{
    fprintf(fp, "        <DataArray type=\"%s\" Name=\"", type);
    sinter_out_xml(fp, name);
    fputc('"', fp);
    if (components != 1)
        fprintf(fp, " NumberOfComponents=\"%zu\"", components);
    fputs(" format=\"ascii\">\n", fp);
}

/* count * components doubles, one particle per line. */
static void write_double_array(FILE *fp, const char *name, const double *data, size_t count,
                               size_t components)
{
    begin_array(fp, "Float64", name, components);
    for (size_t i = 0; i < count; ++i) {
        for (size_t c = 0; c < components; ++c) {
            if (c > 0)
                fputc(' ', fp);
            sinter_out_double(fp, data[i * components + c]);
        }
        fputc('\n', fp);
    }
    fputs("        </DataArray>\n", fp);
}

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
    const size_t n = ps->count;
    fputs("<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          "  <UnstructuredGrid>\n",
          fp);
    fprintf(fp, "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", n, n);
    fputs("      <PointData Scalars=\"radius\">\n", fp);
    write_double_array(fp, "radius", ps->radius, n, 1);
    write_double_array(fp, "velocity", ps->v, n, 3);
    write_double_array(fp, "spin", ps->w, n, 3);
    write_double_array(fp, "temperature", ps->temperature, n, 1);
    write_double_array(fp, "current", ps->current, n, 1);
    write_double_array(fp, "force", ps->force, n, 3);
    begin_array(fp, "Int32", "material", 1);
    for (size_t i = 0; i < n; ++i)
        fprintf(fp, "%" PRId32 "\n", ps->material[i]);
    fputs("        </DataArray>\n", fp);
    begin_array(fp, "UInt64", "id", 1);
    for (size_t i = 0; i < n; ++i)
        fprintf(fp, "%" PRIu64 "\n", ps->id[i]);
    fputs("        </DataArray>\n", fp);
    for (size_t k = 0; k < extra_count; ++k)
        write_double_array(fp, extra[k].name, extra[k].data, n, extra[k].components);
    fputs("      </PointData>\n"
          "      <Points>\n",
          fp);
    write_double_array(fp, "position", ps->x, n, 3);
    fputs("      </Points>\n"
          "      <Cells>\n",
          fp);
    /* One VTK_VERTEX (type 1) per particle. */
    begin_array(fp, "Int64", "connectivity", 1);
    for (size_t i = 0; i < n; ++i)
        fprintf(fp, "%zu\n", i);
    fputs("        </DataArray>\n", fp);
    begin_array(fp, "Int64", "offsets", 1);
    for (size_t i = 0; i < n; ++i)
        fprintf(fp, "%zu\n", i + 1);
    fputs("        </DataArray>\n", fp);
    begin_array(fp, "UInt8", "types", 1);
    for (size_t i = 0; i < n; ++i)
        fputs("1\n", fp);
    fputs("        </DataArray>\n"
          "      </Cells>\n"
          "    </Piece>\n"
          "  </UnstructuredGrid>\n"
          "</VTKFile>\n",
          fp);
    return sinter_out_close(&out, SINTER_OK);
}

sinter_status sinter_write_pvd(sinter_ctx *ctx, const char *path, size_t count, const double *times,
                               const char *const *files)
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
        fputs("\" group=\"\" part=\"0\" file=\"", out.fp);
        sinter_out_xml(out.fp, files[k]);
        fputs("\"/>\n", out.fp);
    }
    fputs("  </Collection>\n"
          "</VTKFile>\n",
          out.fp);
    return sinter_out_close(&out, SINTER_OK);
}
