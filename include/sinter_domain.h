/*
 * libsinter on one subdomain of a decomposed body (issue 43, layer a: no MPI in the library).
 *
 * The host owns the decomposition. Every subdomain has its own context, particle set, walls
 * (the same walls everywhere) and stepper; the owned particles carry global ids
 * (sinter_particles_add_with_ids), and the host supplies copies ("ghosts") of the particles of
 * other subdomains that lie within sinter_stepper_ghost_cutoff of its owned ones. Through a
 * table of callbacks the library asks the host for the collective operations it needs.
 *
 * Contract (explicit, staggered and quasi-static steppers, this version):
 *  - Newton's third law is off across subdomain borders: each subdomain evaluates every pair
 *    with an owned end; the pair is oriented and keyed by the two ids, so both sides hold equal
 *    histories; forces, moments and heat powers on ghosts are discarded. No ghost-ghost pairs,
 *    no ghost wall contacts.
 *  - Every global quantity of a step (wall forces, the rebuild decision, the ghost cut-off and
 *    skin, the stopping of a run, every status; the staggered stepper's error norms, Anderson's
 *    inner products, accept/reject and next step; the averaged electric model's sweep norms)
 *    comes from `reduce`; control flow follows reduced values only, so every subdomain takes
 *    the same branch.
 *  - Errors are collective: every subdomain returns the same status at the same step, with the
 *    same message, which names the subdomain that reported it and the particle's id.
 *  - sinter_stepper_advance, _step and _evaluate become collective calls: every subdomain
 *    makes the same call with the same arguments.
 *  - With the stepper option "reproducible" (sinter_stepper_set_option) the particles' state
 *    and contact histories are the same bits for any number of subdomains and threads and
 *    any order of the particles in memory: every pair list is sorted by the two ids at each
 *    build and every particle's sums run in that order on one thread; the walls' reactions
 *    are exact sums of their contacts' (two integer reductions a step). The staggered
 *    stepper's norms and Anderson's inner products are exact sums too, and the averaged
 *    electric model sweeps Jacobi's iteration with exact stopping sums. Not yet through exact
 *    sums: the heat models' energies (each subdomain's share is summed in its own order, then
 *    the shares are reduced), which may differ in the last bits between decompositions.
 *  - Quasi-static stepper: each link is owned (and its neck advanced) by the subdomain of its
 *    smaller id; loads on a ghost end go to the owner through the reverse halo; K u = f is
 *    solved across subdomains (PCG, block-Jacobi, halos of 6 and 36 doubles per particle);
 *    sinter_stepper_sintering_stats becomes collective (docs/scaleout.md).
 *
 * Like sinter.h, this header uses only <stddef.h> and <stdint.h> and parses as a cffi cdef.
 */
#ifndef SINTER_DOMAIN_H
#define SINTER_DOMAIN_H

/**
 * @file sinter_domain.h
 * @brief Running libsinter on one subdomain of a decomposition owned by the host: ghosts, the
 * callback table of collective operations, global results.
 */

#include "sinter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One layer of ghosts: `count` particles of other subdomains (all arrays borrowed, particle
 * major). */
typedef struct sinter_ghost_fields {
    size_t struct_size; /**< sizeof(sinter_ghost_fields) */
    size_t count;       /**< ghosts */
    const uint64_t *id; /**< global ids (not ids of owned particles) */
    const double *position;    /**< 3 per ghost [m] */
    const double *velocity;    /**< 3 per ghost [m/s] */
    const double *spin;        /**< 3 per ghost [rad/s] */
    const double *rotation;    /**< 3 per ghost: total rotation vector (seed 003 eq. 45) [-] */
    const double *radius;      /**< 1 per ghost [m] */
    const double *mass;        /**< 1 per ghost [kg] */
    const double *inertia;     /**< 1 per ghost [kg m^2] */
    const double *temperature; /**< 1 per ghost [K] */
    const int32_t *material;                             /**< registered material ids of this set */
    const uint32_t *flags; /**< sinter_particle_flag bits (NULL: none) */
    const int32_t *owner;  /**< owning subdomain, for checks (NULL: unknown) */
} sinter_ghost_fields;

/**
 * Replace every ghost row of `particles` by `ghosts` (owned particles untouched; ghosts come
 * after them, in the given order). Called by the host from its redistribute callback, and
 * once before the first step. Between two calls the ghost list (membership and order) is
 * fixed: only the values change, through the halo callback. Forces, moments, heat powers and
 * currents of the rows start at zero. Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE,
 * SINTER_ERR_INVALID (a non-finite value, a radius, mass or inertia <= 0, an unregistered
 * material, an id of an owned particle), SINTER_ERR_BUSY (views out), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_particles_set_ghosts(sinter_particles *particles,
                                                     const sinter_ghost_fields *ghosts);

/** Operations of sinter_domain_ops.reduce. */
typedef enum sinter_reduce_op {
    SINTER_REDUCE_SUM = 0,
    SINTER_REDUCE_MIN = 1,
    SINTER_REDUCE_MAX = 2
} sinter_reduce_op;

/** Value types of sinter_domain_ops.reduce: double, int64_t, uint64_t. */
typedef enum sinter_reduce_type {
    SINTER_REDUCE_F64 = 0,
    SINTER_REDUCE_I64 = 1,
    SINTER_REDUCE_U64 = 2
} sinter_reduce_type;

/** Directions of sinter_domain_ops.halo. */
typedef enum sinter_halo_dir {
    SINTER_HALO_FORWARD = 0, /**< owners' rows copied into the ghost rows */
    SINTER_HALO_REVERSE = 1  /**< ghost rows added into their owners' rows, then zeroed */
} sinter_halo_dir;

/** One exchange of per-particle rows (sinter_domain_ops.halo). */
typedef struct sinter_halo {
    size_t struct_size; /**< sizeof(sinter_halo) */
    int direction;      /**< a sinter_halo_dir */
    size_t width;       /**< doubles per particle */
    double *data;       /**< (owned + ghosts) * width doubles, in the set's index order */
    const uint64_t *id; /**< the set's ids in the same order */
    size_t owned;       /**< owned rows, first */
    size_t ghosts;      /**< ghost rows, after them */
} sinter_halo;

/** The explicit step's forward halo: 13 doubles per particle, x (3) [m], v (3) [m/s], spin (3)
 * [rad/s], rotation vector (3) [-], temperature (1) [K]. */
#define SINTER_HALO_STATE_WIDTH 13

/**
 * The host's collective operations. Every callback returns 0 on success; a non-zero return
 * becomes SINTER_ERR_CALLBACK on every subdomain (reduced, as every status is). Every
 * subdomain calls them in the same order.
 */
typedef struct sinter_domain_ops {
    size_t struct_size; /**< sizeof(sinter_domain_ops) */
    /** Reduce `count` values of `type` (sinter_reduce_type) with `op` (sinter_reduce_op) in
     * place; every subdomain must receive identical bits. */
    int (*reduce)(void *values, size_t count, int type, int op, void *user);
    /** Exclusive prefix sum of `value` over the subdomains (in the host's order), and the
     * total. The library learns its subdomain's number (exscan of 1) from it. */
    int (*exscan)(uint64_t value, uint64_t *before, uint64_t *total, void *user);
    /** Refresh ghost rows from their owners (forward) or add ghost rows into owners (reverse). */
    int (*halo)(const sinter_halo *h, void *user);
    /** At a neighbour-list rebuild (every subdomain at once): move the owned particles that
     * left the subdomain (migration: sinter_stepper_export with remove = 1 here, or one
     * export without removal per destination and then sinter_stepper_remove of all of them,
     * sinter_stepper_import on the subdomain they entered), then call
     * sinter_particles_set_ghosts with every particle within sinter_stepper_ghost_cutoff of an
     * owned one. The set's owned particles may be read (not written) here. The records
     * exported here carry each particle's state at the start of the step, so that a step
     * rejected after a migration restores the arrivals too; export every leaver before the
     * first removal or import (a record exported after the rows moved carries its state now).
     * Inside a staggered stepper's attempt the removal and the import are refused with
     * SINTER_ERR_STATE: keep the particles (ghosts are still made) until the next call. */
    int (*redistribute)(sinter_stepper *st, void *user);
    /** Called once when the stepper is destroyed or the table replaced (may be NULL). */
    void (*destroy_user)(void *user);
} sinter_domain_ops;

/**
 * Install the host's collective operations (copied; NULL removes them). From then on the
 * stepper's global quantities go through `ops`. The explicit, staggered and quasi-static
 * steppers, without an electric model with host callbacks or the option
 * sort_interval (continuous insertion: every subdomain makes the same spheres, subdomain 0 adds
 * them with ids above every subdomain's and the redistribution moves them, so a host's
 * redistribute must move any owned particle to its owner); either electric model ("network"
 * or "averaged") with either the explicit or the staggered stepper, and implicit conduction
 * (explicit stepper). Periodic axes (sinter_stepper_set_periodic): the explicit stepper
 * only, without implicit conduction, an electric model or the option "reproducible", and
 * only for a decomposition that leaves every periodic axis whole (each subdomain spans the
 * cell along it: slabs or a brick cut along non-periodic axes). The host makes its ghosts as
 * without periodic axes (by real distance; the library wraps the owned particles into the
 * cell before calling redistribute) and its halo fills only its own ghost rows; the library
 * appends the periodic images of its owned particles and of the host's ghosts after them
 * and refreshes them itself. A decomposition that seems to cut a periodic axis (a subdomain
 * owning particles, none within the ghost cut-off of one of the axis' faces) is refused at
 * the rebuild, on every subdomain
 * (SINTER_ERR_UNSUPPORTED names the setting, here or at the next step); reduce, exscan, halo
 * and redistribute are required. Implicit conduction and the "network" electric model solve
 * over every subdomain at once: the owned particles are the unknowns, a ghost's value comes
 * from its owner through a forward halo of width 1 before each operator product (the
 * network's cluster labels travel as the bits of a double: the halo must copy bits), and dot
 * products, norms and the stopping test go through reduce, so every subdomain stops at the
 * same iteration; sinter_electric_model_power then returns the totals. The averaged model's
 * sweeps are reduced and its currents haloed to the ghosts. The staggered stepper halos the
 * state before every evaluation of its fixed-point iteration and reduces its norms and
 * Anderson's inner products; during one of its attempts the host's redistribute callback may
 * make new ghosts but not migrate: sinter_stepper_export with removal and
 * sinter_stepper_import return SINTER_ERR_STATE there, and the stepper calls redistribute
 * again at the next accepted state, where migration is allowed. The option "reproducible"
 * (explicit and staggered steppers) makes the results the same bits for any decomposition.
 * The quasi-static stepper (given them before its first step) redistributes once per
 * sinter_stepper_advance or _step call, at its start: migration then, links travelling with
 * their smaller id; the ghosts serve the whole call (set a skin, sinter_stepper_set_skin, that
 * covers the pairs coming into contact). Not with qs_strategy 1. The rigid motion of link
 * components that no plane holds is removed as on one domain, the components found across the
 * subdomains (a few more halos and reductions per step). On one subdomain
 * its results are the bits of the run without domain operations; on more they equal them to
 * round-off when the solve's target qs_solve_rtol is tight (another PCG: at the default 1e-7
 * the approaches differ by about 2e-8).
 * sinter_checkpoint_write refuses such a stepper (SINTER_ERR_UNSUPPORTED): a decomposed run
 * (not the quasi-static stepper's, whose global part is refused) writes a portable checkpoint instead, between two
 * steps: the global part (sinter_stepper_save_global; the same bytes on every subdomain, so one
 * subdomain writes it) and the records of every subdomain's owned particles
 * (sinter_stepper_export with remove = 0; ghosts are not written). It restarts on any number
 * of subdomains: each sets up its stepper alike (the same force and heat models in the same
 * order, walls, materials and options), installs its domain operations, loads the global
 * part (sinter_stepper_load_global) and imports the records of the particles it owns (in any
 * order and split; a record in the wrong subdomain is moved by the next redistribution). With
 * the option "reproducible" the run then continues bit for bit as the uninterrupted one
 * (tests/unit/test_domain_repro.c and, for the staggered stepper, whose records then carry
 * its predictor's history, test_domain_staggered_repro.c: written on 4 subdomains,
 * continued on 2); in the default
 * mode to round-off, as any other decomposition would.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_UNSUPPORTED.
 */
SINTER_API sinter_status sinter_stepper_set_domain_ops(sinter_stepper *stepper,
                                                       const sinter_domain_ops *ops, void *user);

/**
 * The distance [m] within which the host must supply ghosts of an owned particle: 2 r_max +
 * skin (+ the heat models' gas reach), r_max over every subdomain. Valid inside
 * `redistribute`; before the first rebuild it is computed from this subdomain's particles.
 */
SINTER_API sinter_status sinter_stepper_ghost_cutoff(const sinter_stepper *stepper, double *cutoff);

/**
 * This subdomain's share of wall k's reaction force [N]; with domain ops sinter_walls_get_force
 * returns the total over all subdomains (reduced once per accepted step). Without domain ops
 * both are equal. Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE.
 */
SINTER_API sinter_status sinter_walls_get_force_local(const sinter_walls *walls, size_t k,
                                                      double force[3]);

/**
 * Collective: the statistics over all subdomains (counts and times summed, dt and time as
 * they are: equal everywhere). Contacts across a border count on both sides.
 * sinter_stepper_get_stats stays local. Without domain ops the same as sinter_stepper_get_stats.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_CALLBACK.
 */
SINTER_API sinter_status sinter_stepper_get_stats_global(const sinter_stepper *stepper,
                                                         sinter_stepper_stats *stats);

/**
 * Collective: the energy heat model `index` has put into the particles so far [J], summed
 * over every subdomain (sinter_stepper_heat_energy stays this subdomain's share, its owned
 * particles'). Without domain operations the same as sinter_stepper_heat_energy.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE, SINTER_ERR_CALLBACK.
 */
SINTER_API sinter_status sinter_stepper_heat_energy_global(const sinter_stepper *stepper,
                                                           size_t index, double *energy);

/**
 * Doubles per grid point of sinter_coarse_sums: 15 particle sums (volume, mass, m T, momentum,
 * m v v) and 9 of the contact stress.
 */
#define SINTER_COARSE_SUMS 24

/**
 * This subdomain's share of sinter_coarse_grain's fields (a [fields] section over subdomains,
 * issue 44): at every grid point the kernel-weighted sums of its owned particles and of the
 * snapshot's contacts (NULL: none), each pair counted once over the subdomains, by the one
 * that owns its smaller id; a wall contact by its particle's. Layout: points * 15 particle sums
 * (volume [m^3], mass [kg], m T [kg K], m v [kg m/s] (3), m v v [kg m^2/s^2] (9), each times
 * W [1/m^3]), then points * 9 contact stresses [Pa]. Added to `sums` (zero it first);
 * sums_count = points * SINTER_COARSE_SUMS. Summed over the subdomains (in any grouping: the
 * same terms), sinter_write_vti_sums forms the fields; without ghosts these are the sums
 * sinter_coarse_grain forms its quantities from, bit for bit.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (options, sums_count, a snapshot of other
 * particles), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_coarse_sums(const sinter_particles *ps,
                                            const sinter_snapshot *snapshot,
                                            const sinter_coarse_options *options, double *sums,
                                            size_t sums_count);

/**
 * Write the fields of summed sinter_coarse_sums as VTK ImageData (.vti): every
 * sinter_coarse_quantity as point data, formed as sinter_coarse_grain forms them (a `scene
 * run`'s frames/fields_NNNNN.vti). flags: 1 inline base64 arrays (else ascii), 2 single
 * precision. Written to a temporary name and renamed.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (options, sums_count, flags), SINTER_ERR_IO,
 * SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_write_vti_sums(sinter_ctx *ctx, const char *path,
                                               const sinter_coarse_options *options,
                                               const double *sums, size_t sums_count, int flags);

/**
 * This subdomain's share of sinter_lamina_profile: for its owned particles the volume of the
 * spheres' slices in each lamina [m^3] (sums[s]) and that volume times their temperature
 * [m^3 K] (sums[count + s]), added to `sums` (2 count doubles; zero it first). Summed over the
 * subdomains, lamina s has fraction sums[s] / its volume and temperature sums[count + s] /
 * sums[s].
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (as sinter_lamina_profile).
 */
SINTER_API sinter_status sinter_lamina_sums(const sinter_particles *ps, int axis,
                                            const double lo[3], const double hi[3], size_t count,
                                            double *sums);

#ifdef __cplusplus
}
#endif

#endif
