/*
 * libsinter: the API for people who write submodels (force, heat, electric,
 * neck). Include after sinter.h.
 *
 * Callback conventions (after SUNDIALS):
 *  - every callback table starts with `size_t struct_size` and is copied at
 *    registration; the library reads only the fields the caller's size covers;
 *  - `void *user` is the last argument of every callback;
 *  - a callback returns 0 on success, > 0 for a recoverable failure (the
 *    stepper may retry with a smaller step) and < 0 for a fatal one (the
 *    stepper stops with SINTER_ERR_CALLBACK and keeps the last accepted state);
 *  - an optional destroy_user is called exactly once, when the submodel is
 *    destroyed.
 *
 * Commit/rollback contract: evaluation is pure. A submodel reads the state
 * and its committed per-contact history and writes forces (or heat) and a
 * trial history; the stepper commits the trial history only when a step is
 * accepted. A rejected step leaves the committed history untouched.
 */
#ifndef SINTER_SUBMODEL_H
#define SINTER_SUBMODEL_H

/**
 * @file sinter_submodel.h
 * @brief The API for submodel authors: force and heat models written as batched host callbacks.
 */

#include "sinter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Callback result values. */
typedef enum sinter_callback_result {
    SINTER_CALLBACK_OK = 0,
    SINTER_CALLBACK_RETRY = 1,
    SINTER_CALLBACK_FATAL = -1
} sinter_callback_result;


/** The state a submodel reads (borrowed for the duration of a callback). */
typedef struct sinter_state_view {
    size_t count;               /**< particles */
    const double *position;     /**< 3 per particle [m] */
    const double *velocity;     /**< 3 per particle [m/s] */
    const double *spin;         /**< 3 per particle [rad/s] */
    const double *radius;       /**< [m] */
    const double *mass;         /**< [kg] */
    const double *inertia;      /**< [kg m^2] */
    const double *temperature;  /**< [K] */
    const int32_t *material;    /**< material ids */
    size_t wall_count;          /**< walls */
    const double *wall_point;   /**< 3 per wall: current point of the plane [m] */
    const double *wall_normal;  /**< 3 per wall: unit normal into the particle region */
    const double *wall_velocity; /**< 3 per wall [m/s] */
    double time;                /**< time of the state [s] */
    double dt;                  /**< step being taken [s] */
} sinter_state_view;

/** Kinds of contact in a batch. */
typedef enum sinter_contact_kind {
    SINTER_CONTACT_PARTICLE = 0, /**< particle i with particle j */
    SINTER_CONTACT_WALL = 1      /**< particle i with wall j */
} sinter_contact_kind;

/**
 * A batch of active contacts (overlap > 0) as arrays, all of length `count`
 * (times 3 for vectors). Geometry follows seed 000 eq. 7-12: contact area
 * A = pi a^2 with a^2 = r_i^2 - L_i^2 and L_i the distance from the centre of
 * i to the contact plane. For a wall, L_i is the centre-to-plane distance.
 */
typedef struct sinter_contact_batch {
    /** Number of contacts in the batch. */
    size_t count;
    int kind;                    /**< a sinter_contact_kind */
    const uint32_t *i;           /**< particle index */
    const uint32_t *j;           /**< other particle index, or wall index */
    const double *normal;        /**< unit normal from i towards j (or towards the wall), 3 per contact */
    const double *overlap;       /**< r_i + r_j - d, or r_i - plane distance [m] */
    const double *distance;      /**< centre distance, or centre-plane distance [m] */
    const double *contact_radius; /**< a [m] */
    const double *area;          /**< pi a^2 [m^2] */
    const double *branch;        /**< L_i [m]: contact point of i is x_i + L_i n */
    size_t history_size;         /**< doubles of history per contact (as registered) */
    const double *history;       /**< committed history, history_size per contact (NULL if 0) */
    double *history_trial;       /**< history after this step, to be written (NULL if 0) */
    double *force;               /**< out: force on i, 3 per contact (j receives -force); zeroed */
    double *torque_i;            /**< out: moment on i about its centre, 3 per contact; zeroed */
    double *torque_j;            /**< out: moment on j about its centre (particle pairs), 3 per contact; zeroed */
} sinter_contact_batch;

/**
 * Host force submodel. Either callback may be NULL.
 *  - contacts: called once per evaluation for the particle-particle batch and
 *    once for the particle-wall batch; fills force / torques / history_trial.
 *    History starts at zero when a contact forms and is dropped when it ends.
 *  - particles: body forces; force and torque are 3 per particle, zeroed
 *    before the call, and are added to the totals afterwards.
 */
typedef struct sinter_force_callbacks {
    size_t struct_size;  /**< sizeof(sinter_force_callbacks) */
    size_t history_size; /**< doubles of per-contact history the model keeps */
    /** Contact law: fills force, torque_i, torque_j and history_trial of a batch (may be NULL). */
    int (*contacts)(const sinter_state_view *state, sinter_contact_batch *batch, void *user);
    /** Body forces: fills force and torque, 3 per particle (may be NULL). */
    int (*particles)(const sinter_state_view *state, double *force, double *torque, void *user);
    void (*destroy_user)(void *user); /**< called once when the model is destroyed (may be NULL) */
} sinter_force_callbacks;

/**
 * Create a force model from host callbacks (copied). `name` is copied. On
 * error destroy_user is not called: the caller still owns `user`.
 */
SINTER_API sinter_status sinter_force_model_create_host(sinter_force_model **out, sinter_ctx *ctx,
                                                        const char *name,
                                                        const sinter_force_callbacks *callbacks,
                                                        void *user);


/**
 * Host heat submodel: adds power [W] to particles. `heat` has one entry per
 * particle, zeroed before the call; the library adds it to the totals. The
 * contact batches (particle-particle first, then particle-wall) are the same
 * geometry a force model sees; force/torque/history fields are NULL there.
 */
typedef struct sinter_heat_callbacks {
    size_t struct_size; /**< sizeof(sinter_heat_callbacks) */
    /** Fills heat [W], one per particle, from the state and the two contact batches. */
    int (*power)(const sinter_state_view *state, const sinter_contact_batch *particle_contacts,
                 const sinter_contact_batch *wall_contacts, double *heat, void *user);
    void (*destroy_user)(void *user); /**< called once when the model is destroyed (may be NULL) */
} sinter_heat_callbacks;

/**
 * Create a heat model from host callbacks (copied; `name` copied, may be NULL). On error
 * destroy_user is not called: the caller still owns `user`. Errors: SINTER_ERR_NULL,
 * SINTER_ERR_STRUCT_SIZE, SINTER_ERR_INVALID (no power callback), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_heat_model_create_host(sinter_heat_model **out, sinter_ctx *ctx,
                                                       const char *name,
                                                       const sinter_heat_callbacks *callbacks,
                                                       void *user);

/**
 * Host submodels of the "network" electric model (sinter.h): the contact
 * conductance law and the Joule split. Either callback may be NULL (the
 * built-in rule then applies). Each is called once per solve for the
 * particle-particle batch and once for the particle-wall batch (when not
 * empty); the batches carry the geometry only (force/torque/history NULL).
 * In the state view given to them, time and dt are NaN (the electric solve
 * does not know the stepper's clock).
 *  - conductance: fills conductance[k] [S], one per contact (zeroed before
 *    the call). `sigma` holds
 *    each particle's conductivity [S/m] after seed 000 eq. 50's temperature
 *    term when the model's "sigmoid" is 1 (state->count values). A value of 0
 *    makes the contact an insulator; a negative or non-finite value is
 *    SINTER_ERR_DOMAIN. Entries of contacts with neutral walls are ignored.
 *    The built-in law is G = sigma_ij A / d with the harmonic rule
 *    (r_i + r_j) / sigma_ij = r_i / sigma_i + r_j / sigma_j (pairs) and
 *    G = sigma_i A / d (walls).
 *  - joule_split: fills share[k], in [0, 1], the fraction of contact k's
 *    Joule power power[k] = G (phi_a - phi_b)^2 [W] that heats particle i
 *    (filled with the built-in split before the call; 0 power: no edge);
 *    the rest heats j (a particle) or the wall (an electrode: that heat
 *    leaves the powder, see sinter_electric_model_electrode_heat). The
 *    built-in split is 1/2 for pairs and 1 for wall contacts. A value
 *    outside [0, 1] is SINTER_ERR_DOMAIN.
 */
typedef struct sinter_electric_callbacks {
    size_t struct_size; /**< sizeof(sinter_electric_callbacks) */
    /** Contact conductances [S] of a batch (may be NULL). */
    int (*conductance)(const sinter_state_view *state, const sinter_contact_batch *contacts,
                       const double *sigma, double *conductance, void *user);
    /** Share of each contact's Joule power that goes to particle i (may be NULL). */
    int (*joule_split)(const sinter_state_view *state, const sinter_contact_batch *contacts,
                       const double *power, double *share, void *user);
    void (*destroy_user)(void *user); /**< called once when replaced or destroyed (may be NULL) */
} sinter_electric_callbacks;

/**
 * Give a "network" electric model host callbacks (copied; NULL removes them
 * and restores the built-in law and split). The previous callbacks' destroy_user
 * is called. On error destroy_user is not called: the caller still owns `user`.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_UNSUPPORTED (the
 * "averaged" model, which has no conductances), SINTER_ERR_INVALID (a table
 * with neither callback).
 */
SINTER_API sinter_status sinter_electric_model_set_host(sinter_electric_model *em,
                                                        const sinter_electric_callbacks *callbacks,
                                                        void *user);

/**
 * The Joule heat of the network model's last solve that a host split gave to
 * the electrodes [W] (0 with the built-in split): the particles receive the
 * dissipated power (sinter_electric_model_power) less this. Errors:
 * SINTER_ERR_NULL, SINTER_ERR_UNSUPPORTED (the "averaged" model).
 */
SINTER_API sinter_status sinter_electric_model_electrode_heat(const sinter_electric_model *em,
                                                              double *heat);

/** Doubles of state a neck law keeps per link (the 7DOF model's y1..y7). */
#define SINTER_NECK_LAW_STATE 7

/**
 * A batch of the quasi-static stepper's links (sinter.h, "qs_neck_law") for a host neck law,
 * all arrays of length `count` (state: SINTER_NECK_LAW_STATE per link). The law advances each
 * link's pair as if it were free over [time, time + dt] at the schedule's temperatures.
 * State of link k, s = state + 7 k (lengths in m):
 *  - s[0]: the neck radius x (the validity guard, the statistics and qs_neck_stiffness read it);
 *  - s[3], s[6]: L_A, L_B, the distances from the centres to the neck plane; the stepper takes
 *    the decrease of L_A + L_B over the step as the pair's free approach (the sintering force,
 *    seed 001 eq. 13, 17) and afterwards moves L_A, L_B by the network's actual approach,
 *    shared in the same ratio;
 *  - s[1], s[4]: the radii R_A, R_B; s[2], s[5]: the law's own.
 * Every link starts from the 7DOF model's seed (x = qs_epsilon min(R_A, R_B), L_A = R_A,
 * L_B = R_B, docs/7dof.md §4). Every value must stay finite and > 0 (a checkpoint stores it).
 */
typedef struct sinter_neck_law_batch {
    size_t count;                       /**< links */
    double time;                        /**< start of the step [s] */
    double dt;                          /**< step [s]: the state goes from time to time + dt */
    size_t schedule_count;              /**< points of the temperature schedule T(t) */
    const double *schedule_time;        /**< [s], increasing */
    const double *schedule_temperature; /**< [K]: T(t) is piecewise linear, constant outside */
    const uint32_t *a;                  /**< particle index of side A */
    const uint32_t *b;                  /**< particle index of side B */
    const int32_t *material;            /**< material id of particle A (whose neck data a
                                             built-in law uses) */
    const double *radius_a;             /**< [m] */
    const double *radius_b;             /**< [m] */
    double *state;                      /**< in: at time; out: at time + dt */
} sinter_neck_law_batch;

/**
 * Host neck law of the quasi-static stepper: `advance` is called once per global step with
 * every link (in link order) and fills each state at time + dt; a non-zero return stops the
 * step with SINTER_ERR_CALLBACK and the state at time is kept, as is every state when a value
 * comes back not finite or <= 0 (SINTER_ERR_DOMAIN).
 */
typedef struct sinter_neck_law_callbacks {
    size_t struct_size; /**< sizeof(sinter_neck_law_callbacks) */
    /** Advance every link of the batch over the step (required). */
    int (*advance)(sinter_neck_law_batch *batch, void *user);
    void (*destroy_user)(void *user); /**< called once when replaced or destroyed (may be NULL) */
} sinter_neck_law_callbacks;

/**
 * Give a quasi-static stepper a host neck law (copied) and select it ("qs_neck_law" = 2);
 * NULL removes it and selects the 7DOF model again ("qs_neck_law" = 0). The previous law's
 * destroy_user is called. On error destroy_user is not called: the caller still owns `user`.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_INVALID (no advance callback),
 * SINTER_ERR_UNSUPPORTED (not a quasi-static stepper).
 */
SINTER_API sinter_status sinter_stepper_set_neck_law(sinter_stepper *stepper,
                                                     const sinter_neck_law_callbacks *callbacks,
                                                     void *user);

#ifdef __cplusplus
}
#endif

#endif /* SINTER_SUBMODEL_H */
