/*
 * Scan paths of a heat source (issue 40): the beam's axis point moves along a polyline in the
 * x-y plane, segment by segment at each segment's speed, with each segment's power level (0: the
 * source is off while it moves, a jump; 1: full power). A path drives the models that have an
 * axis point ("x", "y") and a power ("power" of "beam", "intensity" of "laser" and "nozzle"):
 * at time t the axis point is the path's position and the power is the parameter's value times
 * the path's level. Before the path's start time the source stands at the first vertex with
 * level 0; after its end at the last vertex with level 0 (off).
 */
#ifndef SINTER_HEAT_SCAN_PATH_H
#define SINTER_HEAT_SCAN_PATH_H

#include <stddef.h>

#include "core/core.h"

typedef struct sinter_scan_path {
    size_t vertices; /* segments + 1 */
    double *t;       /* time at each vertex [s], non-decreasing */
    double *xy;      /* 2 per vertex [m] */
    double *level;   /* per segment [-], in [0, 1] */
} sinter_scan_path;

/* Build a path from `n` vertices of 4 values each (x [m], y [m], speed [m/s], level [-]; vertex
 * 0's speed and level are ignored: it is the start point), starting at `start` [s]. Errors name
 * the vertex: a non-finite value, a speed <= 0 on a segment of non-zero length, a level outside
 * [0, 1]; fewer than 2 vertices. */
sinter_status sinter_scan_path_create(sinter_ctx *ctx, size_t n, const double *points, double start,
                                      sinter_scan_path **out, const char *func);
void sinter_scan_path_destroy(sinter_ctx *ctx, sinter_scan_path *path);

/* Position (x, y) [m] and level [-] at time t [s]. */
void sinter_scan_path_at(const sinter_scan_path *path, double t, double xy[2], double *level);

/* The vertices (4 values each, as sinter_scan_path_create reads them) of a hatch filling the
 * rectangle lo..hi (see sinter.h, sinter_scan_hatch); points == NULL only counts them. */
sinter_status sinter_scan_hatch_build(sinter_ctx *ctx, const double lo[2], const double hi[2],
                                      double spacing, double angle, double speed, double jump_speed,
                                      int serpentine, double *points, size_t capacity,
                                      size_t *count);

#endif
