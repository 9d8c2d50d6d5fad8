/*
 * VTK XML files with raw appended data ([output] vtu_format = appended; io/vtk_appended.c,
 * issue 37): a file the writers wrote with inline base64 binary arrays (io/vtk_arrays.h)
 * rewritten so that every such array is a `format="appended"` element whose bytes follow,
 * unencoded, in the file's <AppendedData encoding="raw"> section (a UInt64 byte count, then
 * the little-endian elements, as inline). A quarter smaller than base64 and read without
 * decoding; ascii arrays (arrays of zeros) stay inline.
 */
#ifndef SINTER_IO_VTK_APPENDED_H
#define SINTER_IO_VTK_APPENDED_H

#include "core/core.h"

/* Rewrite `path` in place (through a temporary file and a rename). Errors: SINTER_ERR_IO,
 * SINTER_ERR_NOMEM, SINTER_ERR_CORRUPT (not a file of the writers: no binary header type or
 * a damaged base64 array). */
sinter_status sinter_vtk_make_appended(sinter_ctx *ctx, const char *path);

#endif
