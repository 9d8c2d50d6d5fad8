/*
 * Heat every k-th step (issue 41, option "heat_interval" k, default 1: every step). The
 * explicit stepper advances the temperatures on the steps whose number is a multiple of k,
 * by forward Euler over k h (seed 003 eq. 46 with the step k h) from the heat powers of the
 * evaluation just before; the heat models are evaluated only there, so that the k - 1 other
 * evaluations are the mechanics' alone (and find their contact list without the geometry
 * the conduction law reads). Conduction and convection only (the power a contact dissipates
 * belongs to every step), the explicit thermal scheme only, not with frozen_heat.
 *
 * The phase is the stepper's step count (carried by checkpoints), so a restart continues
 * bit for bit. The error is that of sampling: a contact shorter than k h is seen at one
 * step in k and counted k times, so each collision's heat is off by up to its own size
 * while the sum over many collisions is not biased; k h must stay below the explicit thermal
 * limit (sinter_stepper_stable_dt_thermal), which the update checks as at k = 1.
 */
#ifndef SINTER_HEAT_INTERVAL_H
#define SINTER_HEAT_INTERVAL_H

#include <stdint.h>

#include "sinter.h"

struct sinter_stepper;

/* 1 if `key` is "heat_interval". */
int sinter_heat_interval_is_key(const char *key);

/* Set the option: a whole number from 1 to SINTER_HEAT_INTERVAL_MAX. */
sinter_status sinter_heat_interval_set(struct sinter_stepper *st, double value);

/* The explicit step with the option above 1: the models and the scheme it can serve
 * (SINTER_ERR_INVALID naming the one it cannot), else SINTER_OK. */
sinter_status sinter_heat_interval_check(struct sinter_stepper *st);

/* 1 if the explicit step numbered `step` (accepted steps before it) advances the
 * temperatures, 0 if it leaves them. */
int sinter_heat_interval_update(const struct sinter_stepper *st, uint64_t step);

/* 1 if the evaluation that ends step `step` must give the heat powers (the next step
 * advances the temperatures), 0 if it may skip the heat models. */
int sinter_heat_interval_eval(const struct sinter_stepper *st, uint64_t step);

#define SINTER_HEAT_INTERVAL_MAX 1000

#endif
