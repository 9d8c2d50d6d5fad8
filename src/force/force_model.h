/* Private interface of force submodels (built-in and host). */
#ifndef SINTER_FORCE_MODEL_H
#define SINTER_FORCE_MODEL_H

#include "sinter_submodel.h"
#include "contact/history.h"

#define SINTER_FORCE_MAX_PARAMS 8

/* Everything one evaluation of one force model reads and writes. */
typedef struct sinter_force_eval {
    sinter_ctx *ctx;
    const sinter_particles *ps;
    const sinter_walls *walls;      /* may be NULL */
    const sinter_contact_list *pp;  /* particle-particle contacts */
    const sinter_contact_list *pw;  /* particle-wall contacts */
    sinter_history *hist_pp;        /* this model's history (width may be 0) */
    sinter_history *hist_pw;
    double time;                    /* time of the state [s] */
    double dt;                      /* increment for history springs [s] (0 at a restart) */
    double *force;                  /* 3 per particle, accumulated */
    double *torque;                 /* 3 per particle, accumulated */
    double *wall_force;             /* 3 per wall, accumulated (force on the wall) */
    double *wall_moment;            /* 3 per wall, accumulated (moment about its point) for
                                       the walls that want it (sinter_wall.moment_wanted) */
    /* NULL, or 6 per wall contact (the stepper's reproducible mode): the force and moment the
     * contact puts on its wall, added beside wall_force and wall_moment, so that the stepper
     * can sum them in an order-independent way (stepper/wall_sums.c) */
    double *pw_reaction;
    const double *modulus_scale;    /* per particle E(theta)/E_0, or NULL for 1 */
    const sinter_state_view *view;  /* for host callbacks */
    /* pp->unconfirmed (sinter_contacts_find_pp_deferred): a model that confirms contacts
     * skips those no longer touching and sets the first one's index here (else SIZE_MAX) */
    size_t pp_ended;
    /* 1: arrays written now and read only at the next step (trial history) may be written
     * with streaming stores (core/stream_store.h; the stepper's choice) */
    int stream;
    /* Optional (the explicit stepper, for its last force model): a law that sums by the pair
     * partition's particle ranges (contact/chunks.h) may call range_final(range_user, r, lo, hi)
     * for every range r once each force and torque on particles [lo, hi) is final, on the
     * thread that summed them, and then sets ranges_final; the stepper's second half kick
     * then runs there, in the law's parallel region (issue 9: one fork and join fewer per
     * step, and the imbalances of the law and the kick between the threads partly cancel). */
    void (*range_final)(void *range_user, int range, size_t lo, size_t hi);
    /* Set only beside range_final: called on the thread of range s right after the law's own
     * pass over the contacts inside s (a phase that waits for nothing), for the stepper's work
     * that needs nothing of the law (its conduction: stepper/thermal.c), so that a thread
     * that next waits for another range's pass has that to do first. When it is set, a law
     * that calls range_final must call it too, for every range: the stepper's range_final
     * for range r waits until it was called for ranges 0 .. r. */
    void (*range_interior_done)(void *range_user, int range);
    void *range_user;
    int ranges_final;
    /* out: bonds this evaluation found broken (committed bonded, trial not): the stepper
     * counts the last evaluation's at the commit of an accepted step */
    uint64_t bonds_broken;
} sinter_force_eval;

typedef struct sinter_force_ops {
    const char *name;
    size_t history_pp; /* doubles of history per particle pair */
    size_t history_pw; /* per particle-wall pair */
    int uses_contacts;
    const char *keys[SINTER_FORCE_MAX_PARAMS]; /* model-level parameters, NULL-terminated */
    double defaults[SINTER_FORCE_MAX_PARAMS];
    sinter_status (*eval)(const sinter_force_model *fm, sinter_force_eval *e);
    /* optional: history width that depends on the model's parameters (read when the model
     * is added to a stepper); NULL means history_pp / history_pw */
    size_t (*history_width)(const sinter_force_model *fm, int wall);
    /* optional: 0 when an evaluation with this particle-particle history width reads no
     * geometry (n, delta, dist, area, branch) of e->pp, forming it from the centres itself;
     * NULL means it reads the geometry when it uses contacts */
    int (*reads_geometry)(const sinter_force_model *fm, size_t history_width);
    /* optional: 1 when an evaluation with this history width reads a lean list's centres,
     * skips every contact that no longer touches and reports the first in e->pp_ended, so that
     * the stepper may leave the search's check to it (sinter_contacts_find_pp_deferred);
     * NULL means it does not */
    int (*confirms_contacts)(const sinter_force_model *fm, size_t history_width);
    /* optional: 1 when the model's particle-particle history marks pairs that stay contacts
     * at any distance while their first history value is non-zero (bonds that hold in
     * tension: sinter_contact_list.held); NULL means none */
    int (*holds_pairs)(const sinter_force_model *fm);
    /* optional: the power [W] each contact dissipates in the state of the evaluation just
     * made (its committed history, e->dt), added into power[2 i] (normal damping) and
     * power[2 i + 1] (sliding friction) of its particles (heat/dissipation.c); NULL: none */
    sinter_status (*dissipation)(const sinter_force_model *fm, const sinter_force_eval *e,
                                 double *power);
} sinter_force_ops;

struct sinter_force_model {
    sinter_ctx *ctx;
    const sinter_force_ops *ops;
    char name[64];
    double param[SINTER_FORCE_MAX_PARAMS];
    /* host models */
    sinter_force_callbacks host;
    void *user;
    sinter_force_ops host_ops;
};

/* Built-in models, one file each. */
extern const sinter_force_ops sinter_force_hertz_mindlin;
extern const sinter_force_ops sinter_force_linear_spring;
extern const sinter_force_ops sinter_force_gravity;
extern const sinter_force_ops sinter_force_body_force;
extern const sinter_force_ops sinter_force_power_law;
extern const sinter_force_ops sinter_force_drag;

/* Host model evaluation (host.c). */
sinter_status sinter_force_host_eval(const sinter_force_model *fm, sinter_force_eval *e);

/* History widths of a model. */
static inline size_t sinter_force_history_pp(const sinter_force_model *fm)
{
    return fm->ops->history_width ? fm->ops->history_width(fm, 0) : fm->ops->history_pp;
}
static inline size_t sinter_force_history_pw(const sinter_force_model *fm)
{
    return fm->ops->history_width ? fm->ops->history_width(fm, 1) : fm->ops->history_pw;
}

/* 1 if fm's history marks held pairs (see holds_pairs). */
static inline int sinter_force_holds_pairs(const sinter_force_model *fm)
{
    return fm->ops->holds_pairs ? fm->ops->holds_pairs(fm) : 0;
}

/* 1 if an evaluation of fm may be given an unconfirmed list (see confirms_contacts). */
static inline int sinter_force_confirms_contacts(const sinter_force_model *fm, size_t width)
{
    return fm->ops->confirms_contacts ? fm->ops->confirms_contacts(fm, width) : 0;
}

/* 1 if an evaluation of fm (its particle-particle history width given) reads the contact
 * list's geometry (see sinter_contacts_find_pp_lean). */
static inline int sinter_force_reads_geometry(const sinter_force_model *fm, size_t width)
{
    return fm->ops->reads_geometry ? fm->ops->reads_geometry(fm, width) : fm->ops->uses_contacts;
}

#endif
