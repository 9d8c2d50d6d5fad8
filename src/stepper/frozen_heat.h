/*
 * Heat at its own pace (issue 41): while the mechanics of an explicit stepper are at rest, the
 * positions are frozen and the temperatures alone are advanced by the implicit thermal scheme
 * (backward Euler for conduction, thermal.c) at a step of its own accuracy control; the
 * mechanics wake when the forces would change. Off by default (option "frozen_heat").
 *
 * At rest: the kinetic energy per particle below "frozen_ke" [J] and not above the last step's
 * (a bed released from rest under gravity starts with a kinetic energy below any threshold,
 * growing), after at least "frozen_settle" mechanical steps since the start or the last
 * wake-up, no wall moving over the next heat step, no electric model (its currents follow the
 * contacts' forces).
 * Heat step control: backward Euler's local error is h^2/2 theta''; with the rates of the
 * step's start (r0) and end (r1 = (theta1 - theta0) / h) it is estimated as
 * e = h / 2 |r1 - r0|, and a step is accepted when max_i e_i / (atol + rtol |theta_i|) <= 1
 * (the weighted norm of SUNDIALS' integrators, maximum over particles); the next step is
 * h 0.9 / sqrt(err), within [h / 5, 5 h], at most "frozen_dt_max", and short enough that a
 * moving source's axis point (a laser, nozzle or beam on a schedule or scan path) travels at
 * most "frozen_travel" times the smallest particle radius in one step: the error estimate
 * compares two approximations of one step under the source's power at its start, so it cannot
 * see the source reach new particles within the step (issue 41, measured on the laser bed).
 * Wake-up: a wall that would move in the next heat step, or a particle whose modulus factor
 * (thermal softening, seed 003 eq. 42) changed by more than "frozen_wake" relative to its
 * value at the freeze. The forces are then evaluated again and the explicit steps resume.
 */
#ifndef SINTER_FROZEN_HEAT_H
#define SINTER_FROZEN_HEAT_H

#include <stddef.h>
#include <stdint.h>

#include "sinter.h"

typedef struct sinter_frozen {
    /* options */
    int enabled;           /* "frozen_heat": 0 (default) or 1 */
    double ke;             /* "frozen_ke": rest below this kinetic energy per particle [J] */
    double rtol;           /* "frozen_rtol": relative temperature tolerance [1] */
    double atol;           /* "frozen_atol": absolute temperature tolerance [K] */
    double dt_max;         /* "frozen_dt_max": largest heat step [s] */
    double travel; /* "frozen_travel": a source's axis moves at most this many smallest radii a step */
    double wake;           /* "frozen_wake": relative modulus change that wakes the mechanics */
    uint64_t settle_steps; /* "frozen_settle": mechanical steps before the rest test */
    /* state (carried by checkpoints) */
    int active;          /* the mechanics are frozen */
    double h;            /* the next heat step's proposal [s] (0: start from the rates) */
    uint64_t mech_steps; /* mechanical steps since the start or the last wake-up */
    double ke_last;      /* kinetic energy per particle after the last explicit step [J] */
    double *rate;        /* per particle: d theta / dt of the last accepted heat step [K/s] */
    double *scale0;      /* per particle: the modulus factor at the freeze (softening only) */
    size_t capacity;     /* particles of both arrays */
    int has_scale;       /* scale0 holds the factors (a material softens) */
    /* statistics */
    double time;       /* simulated time spent frozen [s] */
    uint64_t steps;    /* accepted heat steps */
    uint64_t rejected; /* rejected heat steps */
    uint64_t wakeups;  /* freezes ended by a wake-up */
    uint64_t freezes;  /* freezes begun */
} sinter_frozen;

struct sinter_stepper;

void sinter_frozen_init(sinter_frozen *fz);
void sinter_frozen_free(sinter_ctx *ctx, sinter_frozen *fz);

/* 1 if `key` names an option or a read-only statistic of the frozen heat stage. */
int sinter_frozen_is_key(const char *key);
sinter_status sinter_frozen_set(struct sinter_stepper *st, const char *key, double value);
sinter_status sinter_frozen_get(const struct sinter_stepper *st, const char *key, double *value);

/* After an accepted explicit step: freeze if the mechanics are at rest (see above). */
sinter_status sinter_frozen_consider(struct sinter_stepper *st);

/*
 * Frozen mechanics where the stage no longer applies (option "frozen_heat" 0, as after a
 * checkpoint of a frozen bed read by a stepper with the option off, issue 41; or no heat
 * model, an electric model, another stepper kind): woken, st->forces_current 0 for the caller
 * to evaluate the forces. Returns 1 if woken, 0 if nothing changed (not frozen, or the stage
 * applies: a restored freeze then continues as the uninterrupted run).
 */
int sinter_frozen_release(struct sinter_stepper *st);

/*
 * One accepted heat step over the frozen bed, ending at most at t_end, the step taken in
 * *taken; or none (*taken 0) when a wall would move in it. *woke is 1 when the mechanics woke
 * (before the step, or after it for softening): st->forces_current is then 0, and the caller
 * evaluates the forces of the state before the next explicit step.
 */
sinter_status sinter_frozen_step(struct sinter_stepper *st, double t_end, double *taken, int *woke);

#endif
