/*
 * The two-particle reference of a quasi-static scene ([output] pair_reference;
 * io/scene_pair_reference.c, issue 37): the 7DOF model of one pair of the packing's mean
 * radius and material along the run's temperature, as the series' columns "two-particle neck
 * ratio" and "two-particle shrinkage", which the plot overlays on the packing's (seed 001
 * Figs. 11, 19).
 */
#ifndef SINTER_IO_SCENE_PAIR_REFERENCE_H
#define SINTER_IO_SCENE_PAIR_REFERENCE_H

#include "io/scene.h"

#define SCENE_PAIR_COLUMNS 2

/* The pair's neck ratio x / R and shrinkage Delta L / L0 at the stepper's time, the pair
 * touching at the run's origin (q[0], q[1]; NaN where the model fails, or without particles). */
void scene_pair_reference(const sinter_scene *sc, double *q);

#endif
