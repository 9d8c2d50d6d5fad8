/* The frame writer behind sinter_write_vtu, with the choice of encoding (src/io/vtu.c). */
#ifndef SINTER_IO_VTU_H
#define SINTER_IO_VTU_H

#include "core/core.h"

/* sinter_write_vtu with binary = 0 (ascii, "%.17g" per value); binary = 1 writes every array
 * as inline base64 binary (VTK XML version 1.0, header_type UInt64, little-endian): the same
 * values bit for bit, about half the size and much faster to write. */
sinter_status sinter_write_vtu_as(const sinter_particles *ps, const char *path,
                                  const sinter_vtu_array *extra, size_t extra_count, int binary);

/* sinter_write_pvd with the part of each entry (parts NULL: all 0): the files of one
 * timestep's parts (particles 0, contacts 1, walls 2) are listed with the same time. */
sinter_status sinter_write_pvd_parts(sinter_ctx *ctx, const char *path, size_t count,
                                     const double *times, const char *const *files,
                                     const unsigned *parts);

#endif
