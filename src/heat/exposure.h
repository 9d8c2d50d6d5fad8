/*
 * The fraction of each particle's surface exposed to the surroundings (issue 40), for
 * convection and radiation of particles buried in a bed: f_i = 1 - sum of the view factors
 * from sphere i to what touches it, clamped to [0, 1]. A touching sphere j at centre distance
 * d subtends F_ij = (1 - sqrt(1 - (r_j / d)^2)) / 2 (the sphere-to-sphere configuration factor,
 * Howell, Menguc, Daun and Siegel, Thermal Radiation Heat Transfer, 7th ed., CRC Press 2021,
 * the catalogue of configuration factors: a sphere to a sphere), a touching wall 1/2 (a sphere
 * to a plane through its neighbourhood). Only contacts count (near but separated neighbours
 * shade too) and shadows that overlap are counted twice (the clamp at 0 bounds that): an
 * estimate, exact for an isolated sphere (1), one touching a plane (1/2) and a pair (both
 * 1 - F).
 */
#ifndef SINTER_HEAT_EXPOSURE_H
#define SINTER_HEAT_EXPOSURE_H

#include "heat_model.h"

/* The exposed fraction of every particle of e->ps into a new array of e->ps->count doubles
 * (freed by the caller with sinter_free(e->ctx, ...)). */
sinter_status sinter_heat_exposed_fraction(const sinter_heat_eval *e, double **out);

/* Check a model's "exposed" parameter: 0 or 1. */
sinter_status sinter_heat_exposed_check(const sinter_heat_model *hm, double exposed,
                                        sinter_ctx *ctx);

#endif
