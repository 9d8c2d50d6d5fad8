/* The frame writer behind sinter_write_vtu, with the choice of encoding (src/io/vtu.c). */
#ifndef SINTER_IO_VTU_H
#define SINTER_IO_VTU_H

#include "core/core.h"

/* sinter_write_vtu with binary = 0 (ascii, "%.17g" per value); binary = 1 writes every array
 * as inline base64 binary (VTK XML version 1.0, header_type UInt64, little-endian): the same
 * values bit for bit, about half the size and much faster to write. */
sinter_status sinter_write_vtu_as(const sinter_particles *ps, const char *path,
                                  const sinter_vtu_array *extra, size_t extra_count, int binary);

#endif
