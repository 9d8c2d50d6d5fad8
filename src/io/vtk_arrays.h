/*
 * VTK XML data arrays (src/io/vtk_arrays.c): ascii, or inline binary (base64, header_type
 * UInt64, little-endian, which needs version="1.0" in the VTKFile element) for the particles'
 * frames (io/vtu.c) and the contacts' and walls' files (io/vtp.c).
 */
#ifndef SINTER_IO_VTK_ARRAYS_H
#define SINTER_IO_VTK_ARRAYS_H

#include <stdint.h>
#include <stdio.h>

/* The `binary` argument of the writers below and of the frame writers (vtu.h, vtp.h, vti.h):
 * these bits. 0: ascii doubles. */
enum {
    SINTER_VTK_BINARY = 1, /* inline base64 binary */
    SINTER_VTK_FLOAT32 = 2 /* floating-point arrays in single precision (Float32) */
};

/* The bit pattern of element i of an array, as an unsigned integer of the element's width. */
typedef uint64_t (*sinter_vtk_bits)(const void *data, size_t i);

uint64_t sinter_vtk_double_bits(const void *data, size_t i);
uint64_t sinter_vtk_int32_bits(const void *data, size_t i);
uint64_t sinter_vtk_uint64_bits(const void *data, size_t i);
uint64_t sinter_vtk_index_bits(const void *data, size_t i);          /* i (data unused) */
uint64_t sinter_vtk_index_plus_one_bits(const void *data, size_t i); /* i + 1 */
uint64_t sinter_vtk_vertex_type_bits(const void *data, size_t i);    /* 1: VTK_VERTEX */

/* count * components doubles named `name`: one record per line (%.17g), or binary; an array of
 * zeros stays ascii (shorter than its base64). With SINTER_VTK_FLOAT32 as Float32 (each value
 * rounded to the nearest float; ascii %.9g, which reads back to that float). */
void sinter_vtk_doubles(FILE *fp, const char *name, const double *data, size_t count,
                        size_t components, int binary);

/* count integers of `width` bytes (bits(data, i)) as VTK `type` ("Int32", "UInt64", ...): one
 * per line (signed 32-bit when is_signed), or binary. */
void sinter_vtk_ints(FILE *fp, const char *type, const char *name, const void *data, size_t count,
                     size_t width, sinter_vtk_bits bits, int is_signed, int binary);

#endif
