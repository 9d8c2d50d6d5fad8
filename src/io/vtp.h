/*
 * ParaView output beside the particles' frames (issue 37): the contacts or the quasi-static
 * links of a snapshot as VTK XML PolyData lines, and the walls as polygons (src/io/vtp.c).
 * Every file is written to a temporary name and renamed (io/series.h, sinter_out_open). The
 * arrays are ascii (binary 0) or inline base64 binary (1; io/vtk_arrays.h), as the frames'.
 */
#ifndef SINTER_IO_VTP_H
#define SINTER_IO_VTP_H

#include "core/core.h"

/* One line per contact of `snap` (pair contacts: centre to centre; wall contacts: centre to
 * the contact point on the plane) or, for a snapshot of links, per link (centre to centre),
 * with the snapshot's arrays as cell data under their names (sinter_contact_data and
 * sinter_link_data, e.g. "normal_force", "neck_radius"). `ps`: the particles the snapshot was
 * taken of (their centres now). snap NULL writes an empty file (no contacts known). */
sinter_status sinter_vtp_write_contacts(sinter_ctx *ctx, const char *path,
                                        const sinter_snapshot *snap, const sinter_particles *ps,
                                        int binary);

/* One polygon per wall: its plane clipped to the box lo..hi (3 to 6 corners; a wall that
 * misses the box has none and no cell); the other kinds their outlines, a mesh one triangle
 * per facet where its motion has carried it; with cell data "wall" (index), "normal", "force" (the
 * reaction of sinter_walls_get_force [N]) and "temperature" [K]. */
sinter_status sinter_vtp_write_walls(sinter_ctx *ctx, const char *path, const sinter_walls *walls,
                                     const double lo[3], const double hi[3], int binary);

#endif
