/*
 * The wall reactions of the reproducible mode (issue 43, stepper option "reproducible"): each
 * wall's force and moment summed from its contacts' own reactions (sinter_force_eval.
 * pw_reaction) through the order-independent limb sums of core/repro_sum.h, so that they are
 * the same bits for any order of the contacts and any split of them into subdomains.
 */
#ifndef SINTER_WALL_SUMS_H
#define SINTER_WALL_SUMS_H

#include "stepper/stepper.h"

/* Room for the reactions of the wall contacts of the evaluation under way, zeroed: 6 per
 * contact (force, then moment), or NULL when the mode is off or there are no walls. */
sinter_status sinter_wall_sums_prepare(sinter_stepper *st, double **reaction);

/* The walls' forces and moments (6 per wall: the forces of every wall, then the moments, as
 * st->wall_force holds them) summed exactly from the last evaluation's contact reactions:
 * this subdomain's share into `local` (may be NULL), and with domain operations the total
 * over every subdomain into `total` (collective: two integer reductions, the exponents'
 * maximum and the limbs' sum; without them the total is the share). */
sinter_status sinter_wall_sums(sinter_stepper *st, double *local, double *total);

#endif
