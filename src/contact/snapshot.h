/* What the scene runner's series reads of the contacts without a whole snapshot (snapshot.c). */
#ifndef SINTER_CONTACT_SNAPSHOT_H
#define SINTER_CONTACT_SNAPSHOT_H

#include "stepper/stepper.h"

/* 1 when sinter_snapshot_create would take a snapshot of the stepper: its state is evaluated
 * (0: SINTER_ERR_STATE). */
int sinter_snapshot_possible(const sinter_stepper *st);

/* 1 when the stepper's heat models conduct (a conduction model), 1 when its electric model
 * gives contact currents (the "network" model): whether the sums below mean anything. */
int sinter_snapshot_conducts_heat(const sinter_stepper *st);
int sinter_snapshot_conducts_current(const sinter_stepper *st);

/* Per wall of the stepper, the conductive heat flow from the wall into the particles [W] and
 * the current from the wall into the particles [A] of its current contacts, as
 * sinter_snapshot_create forms them (heat[nw], current[nw]; either may be NULL). NaN where the
 * state is not evaluated (sinter_snapshot_create would refuse it); a quasi-static stepper
 * gives zeros. Errors:
 * SINTER_ERR_NOMEM and the heat models'. */
sinter_status sinter_snapshot_wall_flows(const sinter_stepper *st, double *heat,
                                         double *current);

#endif
