/* Private layout of a stepper and the evaluation pipeline shared by all steppers. */
#ifndef SINTER_STEPPER_H
#define SINTER_STEPPER_H

#include "contact/history.h"
#include "force/force_model.h"
#include "stepper/thermal.h"

typedef struct sinter_force_slot {
    sinter_force_model *model;
    sinter_history pp;
    sinter_history pw;
} sinter_force_slot;

struct sinter_stepper {
    sinter_ctx *ctx;
    int kind;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_force_slot *forces;
    size_t force_count;
    size_t force_capacity;
    sinter_neighbors nb;
    int skin_set;
    sinter_contact_list pp;
    sinter_contact_list pw;
    double time;
    double dt;
    sinter_observer_fn observer;
    void *observer_user;
    sinter_stepper_stats stats;
    int forces_current;           /* forces of the current state are evaluated and committed */
    uint64_t write_generation;    /* particle write_generation when forces were evaluated */
    uint64_t population_generation; /* particle population_generation then */
    double *wall_force;           /* 3 per wall, from the last evaluation */
    size_t wall_force_capacity;
    double *backup;               /* x, v, w, rot of the last accepted state, 12 per particle */
    size_t backup_capacity;
    sinter_state_view view;
    double *wall_arrays;          /* point, normal, velocity: 9 per wall, for host views */
    size_t wall_arrays_capacity;
    sinter_thermal thermal;       /* heat submodels and the temperature update */
    double thermal_last_h;        /* step of the last temperature update [s] */
    uint64_t stats_thermal_iterations; /* PCG iterations of implicit conduction */
    double stats_seconds_heat;    /* wall-clock time in heat evaluation [s] */
    int has_domain;
    double domain_lo[3];
    double domain_hi[3];
    struct sinter_electric_model *electric; /* borrowed, NULL: no current solve */
    uint64_t electric_iterations;           /* sweeps / PCG iterations of its solves, total */
};

/* Seconds of a monotonic clock. */
double sinter_clock(void);

/* Evaluate every force model on the current state; spring increments use dt_hist. */
sinter_status sinter_stepper_eval_forces(sinter_stepper *st, double dt_hist);

/* Accept the last evaluation: commit history and wall reactions. */
sinter_status sinter_stepper_commit(sinter_stepper *st);

/* Explicit velocity-Verlet step of size h (explicit.c). */
sinter_status sinter_explicit_step(sinter_stepper *st, double h);

#endif
