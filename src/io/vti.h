/*
 * The coarse-grained fields of a frame as a VTK XML ImageData file (.vti; src/io/vti.c, issue
 * 37): the grid of sinter_coarse_options as the image's extent, origin and spacing, and every
 * quantity of sinter_coarse_fields as point data under its sinter_coarse_quantity_info name.
 * Written to a temporary name and renamed (io/series.h); arrays ascii (binary 0) or inline
 * base64 (1; io/vtk_arrays.h), as the particles' frames.
 */
#ifndef SINTER_IO_VTI_H
#define SINTER_IO_VTI_H

#include "fields/coarse_grain.h"

sinter_status sinter_vti_write_fields(sinter_ctx *ctx, const char *path,
                                      const sinter_coarse_options *grid,
                                      const sinter_coarse_fields *fields, int binary);

#endif
