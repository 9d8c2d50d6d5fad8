/* ParaView output: one VTK XML UnstructuredGrid frame per call (.vtu) and collections (.pvd). */
#include <inttypes.h>
#include <math.h>
#include <string.h>

#include "io/base64.h"
#include "io/series.h"
#include "io/vtu.h"
#include "particles/particles.h"

/* Point arrays every frame carries; extra arrays must not reuse these names. */
static const char *const BUILTIN_ARRAYS[] = {"radius",  "velocity", "spin",     "temperature",
                                             "current", "force",    "material", "id"};

static void begin_array(FILE *fp, const char *type, const char *name, size_t components, int binary)
{
    fprintf(fp, "        <DataArray type=\"%s\" Name=\"", type);
    sinter_out_xml(fp, name);
    fputc('"', fp);
    if (components != 1)
        fprintf(fp, " NumberOfComponents=\"%zu\"", components);
    fputs(binary ? " format=\"binary\">\n" : " format=\"ascii\">\n", fp);
}

/* The bit pattern of element i of an array, as an unsigned integer of the element's width. */
typedef uint64_t (*element_bits)(const void *data, size_t i);

static uint64_t double_bits(const void *data, size_t i)
{
    uint64_t bits;
    memcpy(&bits, (const double *)data + i, sizeof(bits));
    return bits;
}
static uint64_t int32_bits(const void *data, size_t i)
{
    return (uint32_t)((const int32_t *)data)[i];
}
static uint64_t uint64_bits(const void *data, size_t i)
{
    return ((const uint64_t *)data)[i];
}
static uint64_t index_bits(const void *data, size_t i)
{
    return (uint64_t)i;
}
static uint64_t index_plus_one_bits(const void *data, size_t i)
{
    return (uint64_t)i + 1;
}
static uint64_t vertex_type_bits(const void *data, size_t i)
{
    return 1; /* VTK_VERTEX */
}

/*
 * Inline binary data of a VTK XML file (header_type UInt64, little-endian): the byte count as
 * a UInt64, base64-encoded on its own, then the count elements of `width` bytes each, encoded
 * as one stream (the layout VTK's readers take; the bytes are put in order by shifts, so the
 * file is little-endian on any host).
 */
static void write_binary(FILE *fp, const void *data, size_t count, size_t width, element_bits bits)
{
    sinter_base64 b;
    unsigned char chunk[3072]; /* a multiple of 3 (no padding inside) and of 8 */
    const uint64_t bytes = (uint64_t)count * width;
    for (int k = 0; k < 8; ++k)
        chunk[k] = (unsigned char)(bytes >> (8 * k));
    sinter_base64_begin(&b, fp);
    sinter_base64_put(&b, chunk, 8);
    sinter_base64_end(&b);
    sinter_base64_begin(&b, fp);
    size_t used = 0;
    for (size_t i = 0; i < count; ++i) {
        const uint64_t v = bits(data, i);
        for (size_t k = 0; k < width; ++k)
            chunk[used++] = (unsigned char)(v >> (8 * k));
        if (used == sizeof(chunk)) {
            sinter_base64_put(&b, chunk, used);
            used = 0;
        }
    }
    sinter_base64_put(&b, chunk, used);
    sinter_base64_end(&b);
    fputc('\n', fp);
}

static int all_zero(const double *data, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        uint64_t bits;
        memcpy(&bits, data + i, sizeof(bits));
        if (bits != 0) /* +0.0 only */
            return 0;
    }
    return 1;
}

/* count * components doubles: one particle per line, or binary. An array of zeros (a
 * quasi-static run's velocities, say) stays ascii in a binary file, '0' per value being shorter
 * than its base64 (the format is per array in VTK XML). */
static void write_double_array(FILE *fp, const char *name, const double *data, size_t count,
                               size_t components, int binary)
{
    if (binary && all_zero(data, count * components))
        binary = 0;
    begin_array(fp, "Float64", name, components, binary);
    if (binary)
        write_binary(fp, data, count * components, 8, double_bits);
    else
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

/* An integer array of count elements: the ascii lines of print(i), or binary. */
static void write_int_array(FILE *fp, const char *type, const char *name, const void *data,
                            size_t count, size_t width, element_bits bits, int is_signed,
                            int binary)
{
    begin_array(fp, type, name, 1, binary);
    if (binary)
        write_binary(fp, data, count, width, bits);
    else
        for (size_t i = 0; i < count; ++i) {
            const uint64_t v = bits(data, i);
            if (is_signed) /* 32-bit signed values (material) */
                fprintf(fp, "%" PRId32 "\n", (int32_t)(uint32_t)v);
            else
                fprintf(fp, "%" PRIu64 "\n", v);
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
    const size_t n = ps->count;
    /* binary arrays need version 1.0 for their UInt64 byte counts */
    fprintf(fp,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"%s\" byte_order=\"LittleEndian\"%s>\n"
            "  <UnstructuredGrid>\n",
            binary ? "1.0" : "0.1", binary ? " header_type=\"UInt64\"" : "");
    fprintf(fp, "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", n, n);
    fputs("      <PointData Scalars=\"radius\">\n", fp);
    write_double_array(fp, "radius", ps->radius, n, 1, binary);
    write_double_array(fp, "velocity", ps->v, n, 3, binary);
    write_double_array(fp, "spin", ps->w, n, 3, binary);
    write_double_array(fp, "temperature", ps->temperature, n, 1, binary);
    write_double_array(fp, "current", ps->current, n, 1, binary);
    write_double_array(fp, "force", ps->force, n, 3, binary);
    write_int_array(fp, "Int32", "material", ps->material, n, 4, int32_bits, 1, binary);
    write_int_array(fp, "UInt64", "id", ps->id, n, 8, uint64_bits, 0, binary);
    for (size_t k = 0; k < extra_count; ++k)
        write_double_array(fp, extra[k].name, extra[k].data, n, extra[k].components, binary);
    fputs("      </PointData>\n"
          "      <Points>\n",
          fp);
    write_double_array(fp, "position", ps->x, n, 3, binary);
    fputs("      </Points>\n"
          "      <Cells>\n",
          fp);
    /* One VTK_VERTEX (type 1) per particle. */
    write_int_array(fp, "Int64", "connectivity", NULL, n, 8, index_bits, 0, binary);
    write_int_array(fp, "Int64", "offsets", NULL, n, 8, index_plus_one_bits, 0, binary);
    write_int_array(fp, "UInt8", "types", NULL, n, 1, vertex_type_bits, 0, binary);
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
