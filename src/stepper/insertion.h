/* Continuous insertion from a region at a mass rate: a stage of the explicit step
 * (insertion.c, sinter_stepper_set_insertion). */
#ifndef SINTER_INSERTION_H
#define SINTER_INSERTION_H

#include "stepper.h"

struct sinter_insertion;

/* Insert the spheres due at st->time (none when no insertion is set or none is due), then
 * evaluate the forces of the new state. Called first in each explicit step. */
sinter_status sinter_insertion_stage(sinter_stepper *st);

/* The state a checkpoint holds (io/checkpoint.c, version 11): u = the next insertion's index,
 * the spheres inserted, the crowded insertions and the random stream (4); d = the next
 * sphere's radius [m], the mass inserted and the target so far [kg]. */
enum { SINTER_INSERTION_U64 = 7, SINTER_INSERTION_F64 = 3 };
void sinter_insertion_get_state(const struct sinter_insertion *ins,
                                uint64_t u[SINTER_INSERTION_U64], double d[SINTER_INSERTION_F64]);
/* 0 if the values cannot be an insertion's (not finite, a radius not positive, a mass negative) */
int sinter_insertion_state_valid(const double d[SINTER_INSERTION_F64]);
void sinter_insertion_set_state(struct sinter_insertion *ins,
                                const uint64_t u[SINTER_INSERTION_U64],
                                const double d[SINTER_INSERTION_F64]);

/* A mixture's state (a checkpoint's, io/checkpoint.c): its number of materials (0: none), and
 * the pending sphere's material index with count + 1 masses (each material's inserted, then
 * their total) [kg]; set returns 0 (changing nothing) for values that cannot be the mixture's. */
size_t sinter_insertion_mixture_count(const struct sinter_insertion *ins);
void sinter_insertion_get_mixture(const struct sinter_insertion *ins, uint64_t *pending,
                                  double *mass);
int sinter_insertion_set_mixture(struct sinter_insertion *ins, uint64_t pending,
                                 const double *mass);

void sinter_insertion_destroy(sinter_ctx *ctx, struct sinter_insertion *ins);

#endif
