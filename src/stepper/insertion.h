/* Continuous insertion from a region at a mass rate: a stage of the explicit step
 * (insertion.c, sinter_stepper_set_insertion). */
#ifndef SINTER_INSERTION_H
#define SINTER_INSERTION_H

#include "stepper.h"

struct sinter_insertion;

/* Insert the spheres due at st->time (none when no insertion is set or none is due), then
 * evaluate the forces of the new state. Called first in each explicit step. */
sinter_status sinter_insertion_stage(sinter_stepper *st);

void sinter_insertion_destroy(sinter_ctx *ctx, struct sinter_insertion *ins);

#endif
