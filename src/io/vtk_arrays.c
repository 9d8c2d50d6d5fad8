/* VTK XML data arrays, ascii or inline base64 binary: the writers of the particles' frames
 * (io/vtu.c) and of the contacts' and walls' files (io/vtp.c), see io/vtk_arrays.h. */
#include <inttypes.h>
#include <math.h>
#include <string.h>

#include "io/base64.h"
#include "io/series.h"
#include "io/vtk_arrays.h"

static void begin_array(FILE *fp, const char *type, const char *name, size_t components, int binary)
{
    fprintf(fp, "        <DataArray type=\"%s\" Name=\"", type);
    sinter_out_xml(fp, name);
    fputc('"', fp);
    if (components != 1)
        fprintf(fp, " NumberOfComponents=\"%zu\"", components);
    fputs(binary ? " format=\"binary\">\n" : " format=\"ascii\">\n", fp);
}

uint64_t sinter_vtk_double_bits(const void *data, size_t i)
{
    uint64_t bits;
    memcpy(&bits, (const double *)data + i, sizeof(bits));
    return bits;
}
/* The float nearest to element i of an array of doubles. */
static uint64_t float_bits(const void *data, size_t i)
{
    const float f = (float)((const double *)data)[i];
    uint32_t bits;
    memcpy(&bits, &f, sizeof(bits));
    return bits;
}
uint64_t sinter_vtk_int32_bits(const void *data, size_t i)
{
    return (uint32_t)((const int32_t *)data)[i];
}
uint64_t sinter_vtk_uint64_bits(const void *data, size_t i)
{
    return ((const uint64_t *)data)[i];
}
uint64_t sinter_vtk_index_bits(const void *data, size_t i)
{
    return (uint64_t)i;
}
uint64_t sinter_vtk_index_plus_one_bits(const void *data, size_t i)
{
    return (uint64_t)i + 1;
}
uint64_t sinter_vtk_vertex_type_bits(const void *data, size_t i)
{
    return 1; /* VTK_VERTEX */
}

/*
 * Inline binary data of a VTK XML file (header_type UInt64, little-endian): the byte count as
 * a UInt64, base64-encoded on its own, then the count elements of `width` bytes each, encoded
 * as one stream (the layout VTK's readers take; the bytes are put in order by shifts, so the
 * file is little-endian on any host).
 */
static void write_binary(FILE *fp, const void *data, size_t count, size_t width,
                         sinter_vtk_bits bits)
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
void sinter_vtk_doubles(FILE *fp, const char *name, const double *data, size_t count,
                        size_t components, int binary)
{
    const int single = (binary & SINTER_VTK_FLOAT32) != 0;
    binary &= SINTER_VTK_BINARY;
    if (binary && all_zero(data, count * components))
        binary = 0;
    begin_array(fp, single ? "Float32" : "Float64", name, components, binary);
    if (binary)
        write_binary(fp, data, count * components, single ? 4 : 8,
                     single ? float_bits : sinter_vtk_double_bits);
    else
        for (size_t i = 0; i < count; ++i) {
            for (size_t c = 0; c < components; ++c) {
                if (c > 0)
                    fputc(' ', fp);
                const double v =
                    single ? (double)(float)data[i * components + c] : data[i * components + c];
                if (single && isfinite(v))
                    fprintf(fp, "%.9g", v);
                else
                    sinter_out_double(fp, v); /* (nan and inf spelled as in every file) */
            }
            fputc('\n', fp);
        }
    fputs("        </DataArray>\n", fp);
}

/* An integer array of count elements: the ascii lines of print(i), or binary. */
void sinter_vtk_ints(FILE *fp, const char *type, const char *name, const void *data, size_t count,
                     size_t width, sinter_vtk_bits bits, int is_signed, int binary)
{
    binary &= SINTER_VTK_BINARY;
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
