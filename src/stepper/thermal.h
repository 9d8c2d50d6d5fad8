/*
 * Thermal part of a stepper: evaluation of the heat submodels, the update of
 * temperatures (explicit: seed 003 eq. 46; implicit: backward Euler for
 * conduction solved with SUNDIALS PCG), energy bookkeeping, and the thermal
 * softening factors the force submodels use (seed 000 sec. 7, seed 003 eq. 42).
 * A stepper without heat submodels never calls into here except for softening,
 * which only runs when a material asks for it.
 */
#ifndef SINTER_THERMAL_H
#define SINTER_THERMAL_H

#include "heat/conduction_ranges.h"
#include "heat/heat_model.h"

typedef struct sinter_heat_slot {
    sinter_heat_model *model;
    double power;   /* total power of the last evaluation [W] */
    double energy;  /* time integral of the power applied so far [J] */
    double applied; /* energy added by the last update, taken back on a rollback [J] */
} sinter_heat_slot;

typedef struct sinter_thermal_solver sinter_thermal_solver;

typedef struct sinter_thermal {
    sinter_heat_slot *slots;
    size_t count;
    size_t capacity;
    int scheme;
    /* 1 while an evaluation is a local estimate (sinter_stepper_stable_dt_thermal): the heat
     * models then make no collective call across subdomains (heat_model.h, domain) */
    int local_eval;
    double *g_pp; /* conductance per particle contact of the last evaluation (implicit) */
    size_t g_pp_capacity;
    double *g_pw;
    size_t g_pw_capacity;
    double *modulus_scale; /* E(theta)/E_0 per particle, when a material softens */
    size_t scale_capacity;
    int softening;        /* 1 if the last evaluation computed modulus_scale */
    double *theta_backup; /* temperatures of the last accepted state */
    size_t backup_capacity;
    /* the explicit update of this step also took the sanity check's temperature test
     * (sanity.c, criterion 3): the first free particle above its limit, or the count */
    int hot_checked;
    size_t hot;
    /* 1: the explicit step's drift zeroed ps->heat range by range, on the threads that sum
     * into it (issue 9), so the evaluation of that step adds into it without a memset of its
     * own; set by the drift and cleared by the evaluation (explicit.c) */
    int heat_zeroed;
    /* The explicit step's first heat model, conduction, summed in the contact law's parallel
     * region by the pair partition's ranges (sinter_thermal_law_begin; issue 9): its job and
     * scratch; first_in_law: this evaluation's first model is in ps->heat already (set after
     * the law, cleared by sinter_thermal_eval); law_evaluations counts such evaluations. */
    sinter_conduction_ranges law_job;
    void *law_scratch;
    size_t law_scratch_capacity;
    int first_in_law;
    uint64_t law_evaluations;
    sinter_thermal_solver *solver;
    double *conductivity; /* k(theta) per particle, when a material tabulates it */
    size_t conductivity_capacity;
} sinter_thermal;

struct sinter_stepper;

void sinter_thermal_free(sinter_ctx *ctx, sinter_thermal *th);

/* Softening factors of the current temperatures; *scale is NULL when no material softens. */
sinter_status sinter_thermal_softening(struct sinter_stepper *st, const double **scale);

/* k(theta) of every particle at its temperature when a material has a conductivity table
 * (into st->thermal.conductivity), else *k = NULL. */
sinter_status sinter_thermal_conductivities(struct sinter_stepper *st, const double **k);

/* 1 when an evaluation of the heat models is collective across subdomains (a laser, nozzle or
 * beam with domain operations: heat/beam.c, beam_rays.c), so that a failure before it must be
 * agreed first. */
int sinter_thermal_collective(const struct sinter_stepper *st);

/* Evaluate every heat submodel into ps->heat (and conductances when implicit). */
sinter_status sinter_thermal_eval(struct sinter_stepper *st);

/*
 * The explicit step's conduction in the contact law's region (issue 9). Before the last
 * force model's law, with the contact lists of the state found: returns 1 if the first heat
 * model is conduction and can be summed by the pair partition's ranges; ps->heat is then
 * zeroed and the law is to call sinter_thermal_law_interior(st, s) after its pass over the
 * contacts of each range s (range_interior_done) and sinter_thermal_law_rest(st, r) for each
 * range r (from range_final). After the law, sinter_thermal_law_end(st, ran): ran is 1 if the
 * law called both for every range (ranges_final); then sinter_thermal_eval does not evaluate
 * that model again, else it evaluates it as usual. The sums are those of an evaluation after
 * the law, to the bit (conduction_ranges.h).
 */
int sinter_thermal_law_begin(struct sinter_stepper *st);
void sinter_thermal_law_interior(void *stepper, int range);
void sinter_thermal_law_rest(struct sinter_stepper *st, int range);
void sinter_thermal_law_end(struct sinter_stepper *st, int ran);

/* Advance temperatures over h by the implicit scheme (backward Euler, conduction solved with
 * PCG); nothing without heat models. The explicit scheme's update runs in pieces (below), in
 * the explicit step's kick and drift. */
sinter_status sinter_thermal_implicit_advance(struct sinter_stepper *st, double h);

/*
 * The explicit scheme's update (seed 003 eq. 46) in pieces, for the caller that runs it by
 * particle ranges in a pass of its own (the explicit step's kick and drift, issue 9: no
 * parallel region of its own): begin (the saved temperatures' room), then every particle
 * once through range(lo, hi), which saves and advances the temperatures of [lo, hi) and gives
 * the first particle whose new temperature is not positive and finite (*bad) and the first
 * free one above the sanity check's limit (*hot), hi for none; then end with the smallest of
 * each (the count for none), which refuses the update (temperatures restored, with the
 * step limit in the error) or books its energies.
 */
sinter_status sinter_thermal_explicit_begin(struct sinter_stepper *st);
void sinter_thermal_explicit_range(struct sinter_stepper *st, double h, size_t lo, size_t hi,
                                   size_t *bad, size_t *hot);
sinter_status sinter_thermal_explicit_end(struct sinter_stepper *st, double h, size_t bad,
                                          size_t hot);

/* Restore the temperatures saved by the last update (either scheme). */
void sinter_thermal_rollback(struct sinter_stepper *st);

#endif
