/*
 * Particles followed in series.csv ([output] track; io/scene_track.c, issue 37): for each,
 * its temperature and what its contacts carry, so that a run gives the single-particle
 * histories of seed 003 Fig. 5 (temperature, overlap, contact area, heat flow, contact force).
 */
#ifndef SINTER_IO_SCENE_TRACK_H
#define SINTER_IO_SCENE_TRACK_H

#include "io/scene.h"

/* Columns per followed particle. */
#define SCENE_TRACK_COLUMNS 5

/* The columns' names ("particle ID temperature"; written into labels, SCENE_TRACK_COLUMNS per
 * particle) and units into names[first ..] and units[first ..]; returns their number. */
size_t scene_track_labels(const sinter_scene *sc, const char **names, const char **units,
                          char (*labels)[SCENE_NAME + 16], size_t first);

/* The followed particles' values into q (scene_track_labels' order): NaN for the contact
 * quantities where the state's contacts are not known (before the first step), and for a
 * particle no longer there. */
void scene_track_observe(const sinter_scene *sc, double *q);

#endif
