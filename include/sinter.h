/*
 * libsinter: discrete element simulation of powder sintering.
 *
 * This is the user API. Submodel authors also include sinter_submodel.h.
 *
 * Conventions (see docs in the README):
 *  - Every function returns a sinter_status; negative values are errors.
 *    The detail of the last error of a context is in sinter_last_error().
 *  - Handles are opaque. create functions take the out-parameter first and
 *    leave *out untouched on error; destroy functions accept NULL.
 *  - Units are SI throughout: m, kg, s, K, N, Pa, W, A, V.
 *  - Threads: a sinter_ctx and everything made from it is used by one thread
 *    at a time; distinct contexts are independent. There is no global state.
 *  - The library never aborts, never calls exit() and never prints unless a
 *    log callback is installed.
 *
 * The header is C99-compatible, uses only <stddef.h> and <stdint.h>, and its
 * preprocessed form parses as a cffi cdef.
 */
#ifndef SINTER_H
#define SINTER_H

/**
 * @file sinter.h
 * @brief The public API of libsinter: contexts, materials, particles, walls, force, heat and
 * electric submodels, steppers, the 7DOF neck model, packings, output and scenes.
 */

#include <stddef.h>
#include <stdint.h>

#include "sinter_version.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @def SINTER_API
 * Marks the functions the shared library exports; empty for users of the header.
 */
#if defined(SINTER_BUILDING_LIBRARY) && defined(__GNUC__)
#define SINTER_API __attribute__((visibility("default")))
#else
#define SINTER_API
#endif

/* ------------------------------------------------------------------------ */
/* Status codes                                                              */
/* ------------------------------------------------------------------------ */

/**
 * The one list of status codes: X(name, value, message). Values are pinned
 * once released; new codes are appended with the next free negative value.
 */
#define SINTER_STATUS_LIST(X)                                                        \
    X(SINTER_OK, 0, "success")                                                       \
    X(SINTER_ERR_NULL, -1, "a required pointer argument is NULL")                    \
    X(SINTER_ERR_INVALID, -2, "an argument has an invalid value")                    \
    X(SINTER_ERR_NOMEM, -3, "out of memory")                                         \
    X(SINTER_ERR_STRUCT_SIZE, -4, "struct_size does not match a known version")      \
    X(SINTER_ERR_BUSY, -5, "the object is locked by an outstanding view")            \
    X(SINTER_ERR_RANGE, -6, "an index or count is out of range")                     \
    X(SINTER_ERR_NOT_FOUND, -7, "no such name or id")                                \
    X(SINTER_ERR_OVERFLOW, -8, "a size computation overflows")                       \
    X(SINTER_ERR_STATE, -9, "the call is not valid in the object's current state")   \
    X(SINTER_ERR_IO, -10, "an input/output operation failed")                        \
    X(SINTER_ERR_PARSE, -11, "input text could not be parsed")                       \
    X(SINTER_ERR_CORRUPT, -12, "data is truncated or corrupted")                     \
    X(SINTER_ERR_UNSTABLE, -13, "the simulation went unstable")                      \
    X(SINTER_ERR_NOT_CONVERGED, -14, "an iteration did not converge")                \
    X(SINTER_ERR_CALLBACK, -15, "a host callback reported an error")                 \
    X(SINTER_ERR_UNSUPPORTED, -16, "the feature is not supported by this build")     \
    X(SINTER_ERR_LOST_PARTICLE, -17, "a particle left the simulation domain")        \
    X(SINTER_ERR_DOMAIN, -18, "a model left its domain of validity")                \
    X(SINTER_ERR_INTERRUPTED, -19, "the run was stopped on request")

/** Helper of SINTER_STATUS_LIST: one enumerator of sinter_status (undefined after use). */
#define SINTER_STATUS_ENUM_ENTRY_(name, value, message) name = value,
/** Status code returned by every function. Negative: error. */
typedef enum sinter_status { SINTER_STATUS_LIST(SINTER_STATUS_ENUM_ENTRY_) } sinter_status;
#undef SINTER_STATUS_ENUM_ENTRY_

/** Static English text for a status code; never NULL ("unknown status" for others). */
SINTER_API const char *sinter_status_string(int status);

/** Name of a status code's constant ("SINTER_ERR_NULL"); never NULL. */
SINTER_API const char *sinter_status_name(int status);

/* ------------------------------------------------------------------------ */
/* Version                                                                   */
/* ------------------------------------------------------------------------ */

/** Runtime version as SINTER_VERSION_NUMBER: major*10000 + minor*100 + patch. */
SINTER_API unsigned sinter_version_number(void);

/** Runtime version string "major.minor.patch" (static storage). */
SINTER_API const char *sinter_version_string(void);

/* ------------------------------------------------------------------------ */
/* Context                                                                   */
/* ------------------------------------------------------------------------ */

/** Owns the allocator, the last error text and the log callback. */
typedef struct sinter_ctx sinter_ctx;

/** A custom allocator. Callbacks follow malloc/realloc/free semantics; `user` is last. */
typedef struct sinter_allocator {
    size_t struct_size; /**< sizeof(sinter_allocator) as the caller compiled it. */
    /** Allocate `size` bytes (as malloc); NULL on failure. */
    void *(*alloc)(size_t size, void *user);
    /** Resize a block (as realloc); NULL on failure, the block then unchanged. */
    void *(*realloc)(void *ptr, size_t size, void *user);
    /** Release a block (as free); NULL is allowed. */
    void (*free)(void *ptr, void *user);
    /** Passed as the last argument of the three callbacks. */
    void *user;
} sinter_allocator;

/** Log levels, most severe first. */
typedef enum sinter_log_level {
    SINTER_LOG_ERROR = 0,
    SINTER_LOG_WARNING = 1,
    SINTER_LOG_INFO = 2,
    SINTER_LOG_DEBUG = 3
} sinter_log_level;

/** Log callback: called synchronously from the thread that uses the context. */
typedef void (*sinter_log_fn)(int level, const char *message, void *user);

/**
 * Create a context.
 * @param out        receives the new context (required).
 * @param allocator  custom allocator, copied; NULL for the C library's.
 *                   All three callbacks are required when given.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_INVALID, SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_ctx_create(sinter_ctx **out, const sinter_allocator *allocator);

/** Destroy a context. Every object made from it must be destroyed first. NULL is allowed. */
SINTER_API void sinter_ctx_destroy(sinter_ctx *ctx);

/**
 * Detail of the last error reported on this context (borrowed, valid until
 * the next failing call on the context). "" if no error happened yet.
 * A NULL ctx gives a static message.
 */
SINTER_API const char *sinter_last_error(const sinter_ctx *ctx);

/** Status code of the last error reported on this context (SINTER_OK if none). */
SINTER_API sinter_status sinter_last_status(const sinter_ctx *ctx);

/** Forget the last error. */
SINTER_API sinter_status sinter_clear_error(sinter_ctx *ctx);

/**
 * Install a log callback (NULL to remove) and the most verbose level passed to it.
 * Without a callback the library prints nothing.
 */
SINTER_API sinter_status sinter_ctx_set_log(sinter_ctx *ctx, sinter_log_fn fn, int max_level,
                                            void *user);

/** Number of threads the library may use internally (1 by default, 0 = all available). */
SINTER_API sinter_status sinter_ctx_set_threads(sinter_ctx *ctx, int threads);
/** Read the thread count set by sinter_ctx_set_threads (0 = all available). Errors: SINTER_ERR_NULL. */
SINTER_API sinter_status sinter_ctx_get_threads(const sinter_ctx *ctx, int *threads);

/**
 * Ask the runs of this context to stop: the next check between two steps (in
 * sinter_stepper_advance, sinter_stepper_step and sinter_scene_run) returns
 * SINTER_ERR_INTERRUPTED and withdraws the request. The step under way is
 * finished or refused as usual, so the state left is the last accepted one,
 * readable and checkpointable; a later call continues from it.
 *
 * The one function of the library that may be called from a signal handler
 * (it only stores to a lock-free atomic flag) or from another thread while the
 * context is in use. A request made while nothing runs stops the next run
 * before its first step. Errors: SINTER_ERR_NULL.
 */
SINTER_API sinter_status sinter_ctx_request_stop(sinter_ctx *ctx);

/* ------------------------------------------------------------------------ */
/* Materials                                                                 */
/* ------------------------------------------------------------------------ */

/**
 * The parameters of one material. A material is a named set of numbers, each
 * identified by a sinter_material_param, with an SI unit, a default and a
 * valid range (sinter_material_param_info()). Particle sets and walls copy a
 * material when it is assigned, so it can be changed or destroyed afterwards.
 */
typedef struct sinter_material sinter_material;

/** Material parameters. Values are pinned; new ones are appended. */
typedef enum sinter_material_param {
    /* --- mechanics ------------------------------------------------------ */
    SINTER_MAT_DENSITY = 0,              /**< mass density rho [kg/m^3] */
    SINTER_MAT_YOUNGS_MODULUS = 1,       /**< elasticity modulus E (at reference temperature) [Pa] */
    SINTER_MAT_POISSON_RATIO = 2,        /**< Poisson coefficient nu [-] */
    SINTER_MAT_DAMPING_RATIO = 3,        /**< normal damping rate xi_con, seed 003 eq. 6 [-] */
    SINTER_MAT_FRICTION_STATIC = 4,      /**< static friction coefficient mu_s, seed 003 eq. 8 [-] */
    SINTER_MAT_FRICTION_DYNAMIC = 5,     /**< dynamic friction coefficient mu_d, seed 003 eq. 8, seed 000 eq. 5 [-] */
    SINTER_MAT_FRICTION_DAMPING_RATIO = 6, /**< tangential damping rate xi_fric, seed 003 eq. 11 [-] */
    SINTER_MAT_ROLLING_FRICTION = 7,     /**< rolling resistance coefficient mu_r, seed 003 eq. 16 [-] */
    SINTER_MAT_ROLLING_DAMPING_RATIO = 8, /**< rolling damping rate xi_rol, seed 003 eq. 18 [-] */
    /* --- power-law contact of seed 000 ----------------------------------- */
    SINTER_MAT_CONTACT_STIFFNESS = 9,    /**< particle contact compliance constant K_p, seed 000 eq. 2 [Pa] */
    SINTER_MAT_CONTACT_EXPONENT = 10,    /**< particle contact exponent p_p, seed 000 eq. 2 [-] */
    SINTER_MAT_WALL_STIFFNESS = 11,      /**< wall contact compliance constant K_w, seed 000 eq. 13 [Pa] */
    SINTER_MAT_WALL_EXPONENT = 12,       /**< wall contact exponent p_w, seed 000 eq. 13 [-] */
    SINTER_MAT_BOND_STIFFNESS = 13,      /**< adhesive bond constant K_b, seed 000 eq. 19 [Pa] */
    SINTER_MAT_BOND_EXPONENT = 14,       /**< adhesive bond exponent p_b, seed 000 eq. 19 [-] */
    SINTER_MAT_BOND_CRITICAL_STRAIN = 15, /**< interpenetration |E*| that activates a bond, seed 000 eq. 19 [-] */
    SINTER_MAT_DRAG_COEFFICIENT = 16,    /**< interstitial drag c_env, seed 000 eq. 20 [kg/s] */
    /* --- heat -------------------------------------------------------------- */
    SINTER_MAT_THERMAL_CONDUCTIVITY = 17, /**< thermal conductivity k, seed 003 eq. 35 [W/(m K)] */
    SINTER_MAT_HEAT_CAPACITY = 18,       /**< specific heat C, seed 003 eq. 24 [J/(kg K)] */
    SINTER_MAT_EMISSIVITY = 19,          /**< emissivity epsilon, seed 003 eq. 41 [-] */
    SINTER_MAT_ABSORPTANCE = 20,         /**< absorptance a of external heat, seed 003 eq. 29, seed 000 eq. 35 [-] */
    SINTER_MAT_SOFTENING_LAW = 21,       /**< 0 none, 1 linear (seed 000), 2 exponential (seed 003 eq. 42), 3 tabulated curve, 4 host callback (sinter_particles_set_softening_curve / _callback) [-] */
    SINTER_MAT_SOFTENING_TEMPERATURE = 22, /**< temperature where softening starts theta* [K] */
    SINTER_MAT_SOFTENING_RATE = 23,      /**< linear: relative loss per kelvin; exponential: rate multiplying (theta/theta*) [1/K or -] */
    SINTER_MAT_SOFTENING_FLOOR = 24,     /**< lowest stiffness as a fraction of the reference value [-] */
    /* --- electric ------------------------------------------------------------ */
    SINTER_MAT_ELECTRIC_CONDUCTIVITY = 25, /**< electrical conductivity sigma, seed 000 eq. 35 [S/m] */
    /* --- solid-state sintering: the 7DOF neck model (seed 001 sec. 2.2, docs/7dof.md) ---------
     * Defaults: copper, seed 001 table 2. When phase_transition_temperature is > 0, the
     * neck model uses the *_HOT set at temperatures >= it (titanium beta, seed 001 table 4)
     * and the base set below it; the HOT defaults repeat the copper values.
     * Diffusivities follow D = D0 exp(-Q / (R T)), seed 001 eq. 5. */
    /** atomic volume Omega, seed 001 table 2/4 [m^3], (0, 1e-26] */
    SINTER_MAT_ATOMIC_VOLUME = 26,
    /** surface free energy gamma_s, seed 001 table 2/4 [J/m^2], [0, 100] */
    SINTER_MAT_SURFACE_ENERGY = 27,
    /** grain-boundary free energy gamma_gb, seed 001 table 2/4 [J/m^2], [0, 100] */
    SINTER_MAT_GRAIN_BOUNDARY_ENERGY = 28,
    /** surface diffusion layer thickness delta_s, seed 001 table 2/4 [m], [0, 1e-6] */
    SINTER_MAT_SURFACE_THICKNESS = 29,
    /** grain-boundary thickness delta_gb, seed 001 table 2/4 [m], [0, 1e-6] */
    SINTER_MAT_GRAIN_BOUNDARY_THICKNESS = 30,
    /** lattice (bulk) diffusion prefactor D_v0, seed 001 table 2/4 [m^2/s], [0, 1e30] */
    SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR = 31,
    /** lattice diffusion activation energy Q_v, seed 001 table 2/4 [J/mol], [0, 1e7] */
    SINTER_MAT_LATTICE_ACTIVATION_ENERGY = 32,
    /** surface diffusion prefactor D_s0, seed 001 table 2/4 [m^2/s], [0, 1e30] */
    SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR = 33,
    /** surface diffusion activation energy Q_s, seed 001 table 2/4 [J/mol], [0, 1e7] */
    SINTER_MAT_SURFACE_ACTIVATION_ENERGY = 34,
    /** grain-boundary diffusion prefactor D_gb0, seed 001 table 2/4 [m^2/s], [0, 1e30] */
    SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR = 35,
    /** grain-boundary diffusion activation energy Q_gb, seed 001 table 2/4 [J/mol], [0, 1e7] */
    SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY = 36,
    /** concentration of mobile atoms at the surface n_s, seed 001 table 2/4 [-], [0, 1] */
    SINTER_MAT_SURFACE_MOBILE_FRACTION = 37,
    /** concentration of mobile atoms in the grain boundary n_gb, seed 001 table 2/4 [-], [0, 1] */
    SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION = 38,
    /** Omega of the hot phase, seed 001 table 4 (beta) [m^3], (0, 1e-26] */
    SINTER_MAT_ATOMIC_VOLUME_HOT = 39,
    /** gamma_s of the hot phase, seed 001 table 4 [J/m^2], [0, 100] */
    SINTER_MAT_SURFACE_ENERGY_HOT = 40,
    /** gamma_gb of the hot phase, seed 001 table 4 [J/m^2], [0, 100] */
    SINTER_MAT_GRAIN_BOUNDARY_ENERGY_HOT = 41,
    /** delta_s of the hot phase, seed 001 table 4 [m], [0, 1e-6] */
    SINTER_MAT_SURFACE_THICKNESS_HOT = 42,
    /** delta_gb of the hot phase, seed 001 table 4 [m], [0, 1e-6] */
    SINTER_MAT_GRAIN_BOUNDARY_THICKNESS_HOT = 43,
    /** D_v0 of the hot phase, seed 001 table 4 [m^2/s], [0, 1e30] */
    SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT = 44,
    /** Q_v of the hot phase, seed 001 table 4 [J/mol], [0, 1e7] */
    SINTER_MAT_LATTICE_ACTIVATION_ENERGY_HOT = 45,
    /** D_s0 of the hot phase, seed 001 table 4 [m^2/s], [0, 1e30] */
    SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT = 46,
    /** Q_s of the hot phase, seed 001 table 4 [J/mol], [0, 1e7] */
    SINTER_MAT_SURFACE_ACTIVATION_ENERGY_HOT = 47,
    /** D_gb0 of the hot phase, seed 001 table 4 [m^2/s], [0, 1e30] */
    SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT = 48,
    /** Q_gb of the hot phase, seed 001 table 4 [J/mol], [0, 1e7] */
    SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY_HOT = 49,
    /** n_s of the hot phase, seed 001 table 4 [-], [0, 1] */
    SINTER_MAT_SURFACE_MOBILE_FRACTION_HOT = 50,
    /** n_gb of the hot phase, seed 001 table 4 [-], [0, 1] */
    SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION_HOT = 51,
    /** temperature at which the neck model switches to the HOT set, both ways, no hysteresis
     *  (titanium alpha/beta: 1156 K, seed 001 sec. 4.2) [K], 0 = single phase, [0, 1e5] */
    SINTER_MAT_PHASE_TRANSITION_TEMPERATURE = 52,
    /** melting point theta_m [K], 0 = none (the default). Without latent heat and with
     *  melting_stop = 1 a step that takes a particle of the material above it is refused with
     *  SINTER_ERR_DOMAIN; with latent_heat > 0 the particle melts through the apparent heat
     *  capacity (latent_heat), [0, 1e5] */
    SINTER_MAT_MELTING_TEMPERATURE = 53,
    /** latent heat of melting L [J/kg], 0 = none (the default): released uniformly over
     *  [theta_m, theta_m + melting_range] as an apparent heat capacity L / melting_range on top
     *  of C(theta) (an enthalpy method: the temperature is the enthalpy's inverse); needs
     *  melting_temperature > 0; the mechanics keep treating the particle as a solid, [0, 1e8] */
    SINTER_MAT_LATENT_HEAT = 54,
    /** width of the melting interval [K] over which latent_heat is absorbed, default 1,
     *  (0, 1e4] */
    SINTER_MAT_MELTING_RANGE = 55,
    /** 1 (the default): a step that takes a particle above melting_temperature is refused when
     *  the material has no latent heat; 0: it heats on (no melting modelled), [0, 1] whole */
    SINTER_MAT_MELTING_STOP = 56,
    /* --- the 7DOF reconstruction's path constants (docs/7dof.md §3), both phases -------------
     * The defaults are the reconstruction's; they are options so that a calibration can reach
     * them (docs/calibration.md). */
    /** diffusion path of the grain-boundary fluxes I and II as a fraction of the neck radius,
     *  Delta s = this x (docs/7dof.md §3) [-], default 0.25, (0, 100] */
    SINTER_MAT_NECK_BOUNDARY_PATH = 57,
    /** path of the cone-to-ring fluxes III and IV as a fraction of the cone's slant,
     *  Delta s = this s [-], default 0.5, (0, 100] */
    SINTER_MAT_NECK_CONE_PATH = 58,
    /** path of the cap-to-cone fluxes V and VI as a fraction of the slant, Delta s = this s [-],
     *  default 1, (0, 100] */
    SINTER_MAT_NECK_CAP_PATH = 59,
    /** concentration of mobile atoms of lattice diffusion n_v (seed 001 eq. 4; docs/7dof.md §3),
     *  both phases [-], default 1, [0, 1] */
    SINTER_MAT_LATTICE_MOBILE_FRACTION = 60,
    SINTER_MAT_PARAM_COUNT_ = 61         /**< number of parameters in this version (not a parameter) */
} sinter_material_param;

/** Create a material with every parameter at its default. `name` is copied (may be NULL). */
SINTER_API sinter_status sinter_material_create(sinter_material **out, sinter_ctx *ctx,
                                                const char *name);
/** Destroy a material. NULL is allowed. */
SINTER_API void sinter_material_destroy(sinter_material *m);
/** Copy a material (name and every parameter). */
SINTER_API sinter_status sinter_material_clone(sinter_material **out, const sinter_material *m);

/** Set one parameter; values outside the documented range are refused with SINTER_ERR_INVALID. */
SINTER_API sinter_status sinter_material_set(sinter_material *m, sinter_material_param param,
                                             double value);
/** Get one parameter. */
SINTER_API sinter_status sinter_material_get(const sinter_material *m, sinter_material_param param,
                                             double *value);
/** The material's name (borrowed; "" if none). */
SINTER_API const char *sinter_material_name(const sinter_material *m);

/**
 * Describe a parameter: its key as used in scene files ("youngs_modulus"),
 * its SI unit ("Pa"), a one-line meaning, its default and its valid closed
 * range. Any output pointer may be NULL. Strings are static.
 */
SINTER_API sinter_status sinter_material_param_info(sinter_material_param param, const char **key,
                                                    const char **unit, const char **meaning,
                                                    double *default_value, double *min_value,
                                                    double *max_value);
/** Find a parameter by its key. Errors: SINTER_ERR_NULL, SINTER_ERR_NOT_FOUND. */
SINTER_API sinter_status sinter_material_param_find(const char *key, sinter_material_param *param);

/* ------------------------------------------------------------------------ */
/* Particle sets                                                             */
/* ------------------------------------------------------------------------ */

/** A struct-of-arrays set of spherical particles. */
typedef struct sinter_particles sinter_particles;

/** Per-particle fields. Values are pinned; new ones are appended. */
typedef enum sinter_field {
    SINTER_FIELD_POSITION = 0,    /**< centre x [m], 3 doubles per particle */
    SINTER_FIELD_VELOCITY = 1,    /**< v [m/s], 3 doubles */
    SINTER_FIELD_SPIN = 2,        /**< angular velocity omega [rad/s], 3 doubles */
    SINTER_FIELD_ROTATION = 3,    /**< total rotation vector alpha (Rodrigues), seed 003 eq. 45 [-], 3 doubles */
    SINTER_FIELD_RADIUS = 4,      /**< r [m], 1 double */
    SINTER_FIELD_MASS = 5,        /**< m [kg], 1 double */
    SINTER_FIELD_INERTIA = 6,     /**< moment of inertia j [kg m^2], 1 double */
    SINTER_FIELD_TEMPERATURE = 7, /**< theta [K], 1 double */
    SINTER_FIELD_CURRENT = 8,     /**< electric current through the particle [A], 1 double */
    SINTER_FIELD_FORCE = 9,       /**< total force of the last evaluation [N], 3 doubles */
    SINTER_FIELD_TORQUE = 10,     /**< total moment of the last evaluation [N m], 3 doubles */
    SINTER_FIELD_HEAT = 11,       /**< total heat power of the last evaluation [W], 1 double */
    SINTER_FIELD_MATERIAL = 12,   /**< material id, 1 int32 */
    SINTER_FIELD_FLAGS = 13,      /**< sinter_particle_flag bits, 1 uint32 */
    SINTER_FIELD_ID = 14,         /**< persistent particle id, 1 uint64 (read-only) */
    SINTER_FIELD_COUNT_ = 15      /**< number of fields in this version (not a field) */
} sinter_field;

/** Element type of a field. */
typedef enum sinter_dtype {
    SINTER_DTYPE_DOUBLE = 0,
    SINTER_DTYPE_INT32 = 1,
    SINTER_DTYPE_UINT32 = 2,
    SINTER_DTYPE_UINT64 = 3
} sinter_dtype;

/** Per-particle flag bits. */
typedef enum sinter_particle_flag {
    SINTER_PARTICLE_FIXED = 1,        /**< position and velocity are prescribed (not integrated) */
    SINTER_PARTICLE_NO_ROTATION = 2,  /**< spin is not integrated */
    SINTER_PARTICLE_FIXED_TEMPERATURE = 4, /**< temperature is not integrated */
    SINTER_PARTICLE_ELECTRIFIED = 8,  /**< set by the electric submodel: touches an electrified wall */
    SINTER_PARTICLE_LIT = 16          /**< set by the beam heat submodels (laser, nozzle, beam) on
                                           each particle they give power to; never cleared: the
                                           particles the beam has targeted (seed 003 sec. 5.4) */
} sinter_particle_flag;

/** Describe a field: its name ("position"), unit, element type and components per particle. */
SINTER_API sinter_status sinter_field_info(sinter_field field, const char **name, const char **unit,
                                           sinter_dtype *dtype, size_t *components);

/** Create an empty particle set. */
SINTER_API sinter_status sinter_particles_create(sinter_particles **out, sinter_ctx *ctx);
/** Destroy a particle set. NULL is allowed. Outstanding views become invalid. */
SINTER_API void sinter_particles_destroy(sinter_particles *ps);

/** Number of particles. */
SINTER_API sinter_status sinter_particles_count(const sinter_particles *ps, size_t *count);
/** Owned particles: the first *owned of the set; the rest (count - owned) are ghost particles,
 * images a periodic stepper made (sinter_stepper_set_periodic), which copy their owners. */
SINTER_API sinter_status sinter_particles_owned_count(const sinter_particles *ps, size_t *owned);
/** Capacity reserved (particles that fit without reallocation). */
SINTER_API sinter_status sinter_particles_capacity(const sinter_particles *ps, size_t *capacity);
/** Reserve room for `capacity` particles. Refused while a view is out (SINTER_ERR_BUSY). */
SINTER_API sinter_status sinter_particles_reserve(sinter_particles *ps, size_t capacity);

/**
 * Register (or replace) material `id` of this set with a copy of `m`.
 * Ids run from 0 to 255. Replacing a material recomputes mass and inertia of
 * its particles from the new density.
 */
SINTER_API sinter_status sinter_particles_set_material(sinter_particles *ps, int32_t id,
                                                       const sinter_material *m);
/** Host softening law: E(theta)/E_0 at temperature theta [K]; must return a finite value > 0. */
typedef double (*sinter_softening_fn)(double theta, void *user);

/**
 * Tabulated softening of material `id`: E(theta)/E_0 interpolated linearly through n points
 * (temperatures [K], strictly increasing; factors > 0), held constant outside. Copied. Sets the
 * material's softening_law to 3. The material must be registered.
 */
SINTER_API sinter_status sinter_particles_set_softening_curve(sinter_particles *ps, int32_t id,
                                                              size_t n,
                                                              const double *temperatures,
                                                              const double *factors);
/**
 * Host softening law for material `id` (sets softening_law to 4). Called for every particle of
 * the material whenever forces are evaluated; a non-finite or non-positive result stops the
 * stepper with SINTER_ERR_CALLBACK.
 */
SINTER_API sinter_status sinter_particles_set_softening_callback(sinter_particles *ps, int32_t id,
                                                                 sinter_softening_fn fn,
                                                                 void *user);
/** Material properties that may be given as functions of temperature by a table. */
typedef enum sinter_property {
    /** k(theta) [W/(m K)]: replaces thermal_conductivity in every conduction law */
    SINTER_PROPERTY_THERMAL_CONDUCTIVITY = 0,
    /** C(theta) [J/(kg K)]: replaces heat_capacity; temperatures advance through the specific
     *  enthalpy H(theta) = int_0^theta C (sinter_particles_specific_enthalpy) */
    SINTER_PROPERTY_HEAT_CAPACITY = 1,
    /** sigma(theta) [S/m]: replaces electric_conductivity (sigma_0 of seed 000 eq. 50, whose
     *  sigmoid, when on, multiplies it) in the electric network and the Joule model */
    SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY = 2,
    SINTER_PROPERTY_COUNT_ = 3 /**< number of properties (not a property) */
} sinter_property;

/**
 * Tabulate `property` of material `id` as a function of temperature: n points (temperatures
 * [K] strictly increasing, > 0 and finite; values finite and > 0, in the property's unit),
 * interpolated linearly between points and held at the end values outside the table (clamped).
 * The table replaces the material's constant value for particles of that material; n = 0 (the
 * arrays may then be NULL) removes it. Copied. The material must be registered; replacing the
 * material (sinter_particles_set_material) keeps its tables. Tables are materials' data, not
 * state: a checkpoint does not store them (set them again before sinter_checkpoint_read).
 */
SINTER_API sinter_status sinter_particles_set_property_table(sinter_particles *ps, int32_t id,
                                                             sinter_property property, size_t n,
                                                             const double *temperatures,
                                                             const double *values);
/** Value of `property` of material `id` at temperature theta [K] > 0: the table's or the
 *  material's constant (for the heat capacity without the latent heat). */
SINTER_API sinter_status sinter_particles_property(const sinter_particles *ps, int32_t id,
                                                   sinter_property property, double theta,
                                                   double *value);
/** Specific enthalpy of material `id` at theta [K] > 0: H = int_0^theta C(t) dt plus the part
 *  of the latent heat absorbed below theta [J/kg] (C held at its first value below the table).
 *  With constant C and no latent heat, H = C theta. */
SINTER_API sinter_status sinter_particles_specific_enthalpy(const sinter_particles *ps, int32_t id,
                                                            double theta, double *enthalpy);
/** Borrow the set's copy of material `id` (read-only, valid until it is replaced). */
SINTER_API sinter_status sinter_particles_get_material(const sinter_particles *ps, int32_t id,
                                                       const sinter_material **m);

/**
 * Append `n` particles of material `material_id` (which must be registered).
 * @param positions  3n doubles (x0,y0,z0,x1,...) [m], required.
 * @param radii      n doubles [m], required, each > 0 and small enough that the
 *                   mass and moment of inertia are finite (and large enough that
 *                   they are not 0).
 * @param temperature initial temperature of every new particle [K], > 0.
 * @param first_index receives the index of the first new particle (may be NULL).
 * Mass = rho 4/3 pi r^3 and inertia = 2/5 m r^2 follow from the material's
 * density; velocity, spin and rotation start at zero. Every value is validated
 * before anything is changed: on error the set is unchanged and the message
 * names the particle and the field.
 */
SINTER_API sinter_status sinter_particles_add(sinter_particles *ps, size_t n,
                                              const double *positions, const double *radii,
                                              int32_t material_id, double temperature,
                                              size_t *first_index);

/**
 * Add n particles as sinter_particles_add does, with ids chosen by the caller instead of the
 * set's counter: a host that splits one body over several particle sets (subdomains of a
 * decomposition) gives every particle an id unique across all of them. ids[k] (n values) must
 * not repeat, must not be held by the set already and must not be 2^64 - 1 (SINTER_ERR_INVALID
 * names the id and the particles); the set's counter moves above the largest, so later
 * sinter_particles_add calls never reuse one. Contact histories, quasi-static links and
 * checkpoints follow the particles by these ids. On error the set is unchanged.
 */
SINTER_API sinter_status sinter_particles_add_with_ids(sinter_particles *ps, size_t n,
                                                       const uint64_t *ids,
                                                       const double *positions,
                                                       const double *radii, int32_t material_id,
                                                       double temperature, size_t *first_index);

/**
 * Remove the particles whose indices are listed (each once, in any order).
 * The order of the remaining particles is kept; their ids are unchanged.
 */
SINTER_API sinter_status sinter_particles_remove(sinter_particles *ps, size_t n,
                                                 const size_t *indices);

/**
 * Borrow a field's array for reading and writing: count * components elements
 * of the field's dtype, particle-major (x0,y0,z0,x1,...). The set is locked
 * against add/remove/reserve (and steppers refuse to step) until every borrowed
 * view is released. The id field is read-only: borrow it with
 * sinter_particles_view_read(). An array's address is valid until its view is
 * released: the explicit stepper exchanges the position, velocity, spin and
 * rotation arrays with its own copy at each step, so borrow again after stepping.
 */
SINTER_API sinter_status sinter_particles_view(sinter_particles *ps, sinter_field field,
                                               void **data, size_t *count, size_t *components);
/** Borrow a field for reading only. */
SINTER_API sinter_status sinter_particles_view_read(const sinter_particles *ps, sinter_field field,
                                                    const void **data, size_t *count,
                                                    size_t *components);
/** Release a view obtained from sinter_particles_view or _view_read. */
SINTER_API sinter_status sinter_particles_release(const sinter_particles *ps, sinter_field field);
/** Number of views currently out. */
SINTER_API sinter_status sinter_particles_views_out(const sinter_particles *ps, size_t *views);

/**
 * Check every value of every particle: finite positions, velocities, spins and
 * rotations; positive finite radius, mass, inertia and temperature; registered
 * material. The first problem is reported as SINTER_ERR_INVALID with a message
 * that names the particle and the field; *bad_index (may be NULL) receives it.
 */
SINTER_API sinter_status sinter_particles_validate(const sinter_particles *ps, size_t *bad_index);

/**
 * Find the index of the particle with persistent id `id` (SINTER_ERR_NOT_FOUND if none). The
 * first lookup after particles were added, removed or reordered builds an index of the ids
 * (O(N), 4 bytes per particle and a half-full table); later lookups take O(1). Like the views,
 * this bookkeeping writes into the set: do not look up ids of one set from two threads at once.
 */
SINTER_API sinter_status sinter_particles_find_id(const sinter_particles *ps, uint64_t id,
                                                  size_t *index);

/**
 * Reorder the particles in memory by position: cells of the largest diameter, x fastest,
 * then y, then z (particles of one cell by id, so the result does not depend on the order
 * before). Neighbouring particles then sit near each other
 * in memory, which the contact loops need to be fast, and the threads' ranges of particles
 * become slabs. Every field moves with its particle, ids included, and a stepper carries the
 * contact history over; indices change, so find particles by id afterwards. The stepper
 * option "sort_interval" repeats this every so many steps. Errors: SINTER_ERR_NULL,
 * SINTER_ERR_BUSY (a view is out), SINTER_ERR_INVALID (a position is not finite; nothing
 * moves), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_particles_sort_spatial(sinter_particles *ps);


/* ------------------------------------------------------------------------ */
/* Walls                                                                     */
/* ------------------------------------------------------------------------ */

/**
 * A set of rigid walls. Wall k is the plane through point p_k(t) with unit
 * normal n_k pointing into the region where particles live (or a rectangle,
 * disc or cylinder: sinter_wall_kind); a particle touches it when its centre
 * is closer to the wall than its radius. Walls translate with a prescribed
 * motion or a force servo and may spin about their axis; their normals are
 * fixed.
 */
typedef struct sinter_walls sinter_walls;

/** Prescribed wall motions. */
typedef enum sinter_wall_motion {
    SINTER_WALL_FIXED = 0,      /**< does not move */
    SINTER_WALL_VELOCITY = 1,   /**< p(t) = p0 + u t, u constant [m/s] */
    SINTER_WALL_SCHEDULE = 2,   /**< piecewise-linear displacement d(t) through given (t, d) points, held constant outside */
    SINTER_WALL_SINE = 3,       /**< p(t) = p0 + A sin(omega t) e, amplitude vector A e [m], omega [rad/s] */
    SINTER_WALL_CALLBACK = 4    /**< host callback gives the displacement and velocity */
} sinter_wall_motion;

/**
 * Host wall motion: fill displacement[3] (p(t) - p0) [m] and velocity[3] [m/s]
 * at time t [s]. Return 0 on success, non-zero to stop the stepper.
 */
typedef int (*sinter_wall_motion_fn)(double t, double *displacement, double *velocity, void *user);

/** Create an empty wall set. Errors: SINTER_ERR_NULL, SINTER_ERR_NOMEM. */
SINTER_API sinter_status sinter_walls_create(sinter_walls **out, sinter_ctx *ctx);
/** Destroy a wall set (NULL is allowed); destroy the steppers using it first. */
SINTER_API void sinter_walls_destroy(sinter_walls *walls);
/** Number of walls. */
SINTER_API sinter_status sinter_walls_count(const sinter_walls *walls, size_t *count);

/**
 * Add a fixed plane through `point` [m] with normal `normal` (normalised here;
 * it must not be zero) pointing into the particle region. `material` is copied.
 */
SINTER_API sinter_status sinter_walls_add_plane(sinter_walls *walls, const double point[3],
                                                const double normal[3],
                                                const sinter_material *material, size_t *index);
/** Replace wall k's material with a copy of `material`. */
SINTER_API sinter_status sinter_walls_set_material(sinter_walls *walls, size_t k,
                                                   const sinter_material *material);
/** Constant velocity u [m/s]. */
SINTER_API sinter_status sinter_walls_set_velocity(sinter_walls *walls, size_t k,
                                                   const double velocity[3]);
/**
 * Piecewise-linear displacement schedule: n points (times[i] [s], strictly
 * increasing; displacements[3i..3i+2] [m]). Copied.
 */
SINTER_API sinter_status sinter_walls_set_schedule(sinter_walls *walls, size_t k, size_t n,
                                                   const double *times,
                                                   const double *displacements);
/** Sinusoidal vibration p0 + amplitude sin(omega t) (amplitude vector [m], omega [rad/s]). */
SINTER_API sinter_status sinter_walls_set_sine(sinter_walls *walls, size_t k,
                                               const double amplitude[3], double omega);
/** Host callback motion. */
SINTER_API sinter_status sinter_walls_set_callback(sinter_walls *walls, size_t k,
                                                   sinter_wall_motion_fn fn, void *user);
/**
 * Time [s] at which wall k's prescribed motion starts: before it the wall
 * stays at p0; after it the motion is evaluated at (t - start). Default 0;
 * HUGE_VAL holds the wall until a later call sets a finite start; NaN and
 * -HUGE_VAL are refused (SINTER_ERR_INVALID).
 */
SINTER_API sinter_status sinter_walls_set_motion_start(sinter_walls *walls, size_t k,
                                                       double start);
/** Wall temperature [K] (used by heat submodels). */
SINTER_API sinter_status sinter_walls_set_temperature(sinter_walls *walls, size_t k,
                                                      double temperature);
/** Position of the wall's point [m] and its velocity [m/s] at the stepper's current time. */
SINTER_API sinter_status sinter_walls_get_state(const sinter_walls *walls, size_t k,
                                                double point[3], double velocity[3]);
/** Unit normal of wall k (a cylinder: its axis). */
SINTER_API sinter_status sinter_walls_get_normal(const sinter_walls *walls, size_t k,
                                                 double normal[3]);
/**
 * Reaction force on wall k from every particle touching it in the last
 * accepted step [N] (the force the particles exert on the wall). With domain
 * operations (sinter_domain.h) the total over every subdomain.
 */
SINTER_API sinter_status sinter_walls_get_force(const sinter_walls *walls, size_t k,
                                                double force[3]);

/**
 * Wall kinds. Every kind is one-sided: particles live on the side its normal
 * points to (a cylinder: inside or outside, as chosen); behind a face the
 * plane's signed distance holds, as for an infinite plane. A sphere touches a
 * wall when its centre is closer than its radius to the wall's closest point;
 * the contact normal runs from that point to the centre, and every contact
 * law treats the wall locally as a plane there.
 */
typedef enum sinter_wall_kind {
    SINTER_WALL_PLANE = 0,     /**< infinite plane (sinter_walls_add_plane) */
    SINTER_WALL_RECTANGLE = 1, /**< finite plane: a rectangle; beyond its edges a sphere meets the
                                  edge (a rim, from either side) */
    SINTER_WALL_DISC = 2,      /**< finite plane: a disc, edges as the rectangle's */
    SINTER_WALL_CYLINDER = 3, /**< lateral surface of a circular cylinder; beyond a finite one's
                                 ends a sphere meets the rim circle */
    SINTER_WALL_MESH = 4      /**< triangle mesh read from STL (sinter_walls_add_mesh) */
} sinter_wall_kind;

/**
 * Add a fixed rectangle centred at `center` [m] with normal `normal` into the
 * particle region, its first edge along `edge` (its part normal to `normal`;
 * it must not be parallel to it) with half length `half_1` [m], the second
 * along normal x edge with half length `half_2` [m]. Errors: SINTER_ERR_INVALID
 * for a zero or non-finite vector, a half length that is not positive.
 */
SINTER_API sinter_status sinter_walls_add_rectangle(sinter_walls *walls, const double center[3],
                                                    const double normal[3], const double edge[3],
                                                    double half_1, double half_2,
                                                    const sinter_material *material,
                                                    size_t *index);
/** Add a fixed disc of radius `radius` [m] centred at `center` [m], normal into the particles. */
SINTER_API sinter_status sinter_walls_add_disc(sinter_walls *walls, const double center[3],
                                               const double normal[3], double radius,
                                               const sinter_material *material, size_t *index);
/**
 * Add a fixed cylinder: axis through `point` [m] along `axis` (normalised
 * here), radius `radius` [m]; its lateral surface reaches `half_length` [m]
 * along the axis from `point` either way (HUGE_VAL: infinite), and beyond it
 * a sphere meets its rim circles (open ends). `inside` = 1: particles
 * inside the cylinder (a die), 0: outside (a pin). The wall's normal
 * (sinter_walls_get_normal) is its axis.
 */
SINTER_API sinter_status sinter_walls_add_cylinder(sinter_walls *walls, const double point[3],
                                                   const double axis[3], double radius,
                                                   double half_length, int inside,
                                                   const sinter_material *material,
                                                   size_t *index);
/**
 * Add a fixed triangle mesh read from the STL file `path` (ASCII or binary):
 * each file point x placed at translate + R (scale x) [m], R turning by
 * rotate[0] about x, then rotate[1] about y, then rotate[2] about z [rad].
 * The particles are on the side the facets' normals point to, given by the
 * vertices' winding (right-hand rule); flip = 1 reverses them (a closed
 * surface's outward normals turned inwards: a die). The wall's point is
 * `translate` (its moment's origin; its motions move the mesh), its normal
 * the file's z axis as placed. A sphere touches the mesh once, at the closest
 * point of all its triangles (face, edge or vertex), the normal from that
 * point to its centre, so that a smooth surface made of many triangles acts
 * as one surface (one contact, its tangential history kept across
 * triangles); in a concave corner of one mesh only the closer face touches.
 * Open edges (of one triangle only) are rims met from either side, as a
 * rectangle's edge. Distances from the mesh come from a cell grid over its
 * triangles; beyond `reach` [m] (0: everywhere exact) one may come out as a
 * lower bound, so reach must exceed the largest particle radius plus the
 * neighbour list's skin (the neighbour list takes a sphere farther than its
 * radius plus the skin, in front of its last closest triangle's plane, as in
 * front: docs/models.md). A spin does not turn the mesh (it gives its surface
 * velocity, as for a cylinder); the mesh is not drawn in .vtp files.
 * Errors: SINTER_ERR_IO (unreadable), SINTER_ERR_PARSE (not STL, with the
 * line), SINTER_ERR_INVALID (a scale not positive, a non-finite placement, a
 * degenerate facet, an edge of more than two facets, neighbouring facets
 * wound opposite ways or a stored normal against the winding: inconsistent
 * normals; each names the facet).
 */
SINTER_API sinter_status sinter_walls_add_mesh(sinter_walls *walls, const char *path, double scale,
                                               const double rotate[3], const double translate[3],
                                               int flip, double reach,
                                               const sinter_material *material, size_t *index);
/** Kind of wall k (sinter_wall_kind). */
SINTER_API sinter_status sinter_walls_get_kind(const sinter_walls *walls, size_t k, int *kind);
/**
 * Shape of wall k at the current time: its axis (the normal of a planar
 * kind), its first edge direction (rectangle), and size: rectangle (half_1,
 * half_2, 0) [m]; disc (radius, 0, 0); cylinder (radius, half_length, inside); mesh
 * (0, 0, 0).
 * Any pointer may be NULL.
 */
SINTER_API sinter_status sinter_walls_get_shape(const sinter_walls *walls, size_t k,
                                                double axis[3], double edge[3], double size[3]);
/**
 * Spin of wall k about its axis through its point at angular velocity omega
 * [rad/s] (right-handed about the axis), from its motion's start on, added to
 * its translation: the surface velocity at a contact point c is
 * u + omega a x (c - p), which the contact laws take as the wall's velocity
 * (friction, tangential history). A rectangle turns with it, and a mesh
 * given an axis by sinter_walls_set_rotation; the other kinds are unchanged
 * by a spin about their axis.
 */
SINTER_API sinter_status sinter_walls_set_spin(sinter_walls *walls, size_t k, double omega);
/**
 * Turn mesh wall k rigidly about the axis through `point` [m] along `axis`
 * (any length, not zero) at angular velocity omega [rad/s] (right-handed),
 * from its motion's start on: its triangles at time t are those placed at
 * t = 0 turned by omega (t - start) about the axis, which the wall's
 * translation carries along. The wall's point (sinter_walls_get_state, the
 * reference of sinter_walls_get_moment) becomes `point` plus the
 * translation's displacement, its axis `axis`, its spin omega (a later
 * sinter_walls_set_spin changes the rate); the surface velocity at a contact
 * point c is u + omega a x (c - p) (friction, tangential history, damping).
 * Errors: SINTER_ERR_INVALID for a wall that is not a mesh, a non-finite
 * input or a zero axis.
 */
SINTER_API sinter_status sinter_walls_set_rotation(sinter_walls *walls, size_t k,
                                                   const double point[3], const double axis[3],
                                                   double omega);
/**
 * Reaction moment on wall k about its point p [N m] in the last accepted step:
 * the sum over its contacts of -(c - p) x f - m_r, f the force and m_r the
 * rolling moment each particle got at its contact point c. Summed for the
 * walls that want it (sinter_walls_set_moment), else 0.
 */
SINTER_API sinter_status sinter_walls_get_moment(const sinter_walls *walls, size_t k,
                                                 double moment[3]);
/**
 * Whether the contact laws sum wall k's reaction moment (on = 1) or not (0).
 * On by default for rectangles, discs and cylinders, and from a spin or a
 * servo on; off for other infinite planes, for which few hosts want it (it
 * costs about 1 % of a packed bed's step, where the planes' contacts are a
 * fifth of all). Errors: SINTER_ERR_INVALID for another value.
 */
SINTER_API sinter_status sinter_walls_set_moment(sinter_walls *walls, size_t k, int on);
/**
 * Drive wall k (a plane, rectangle or disc) along its normal a by a force
 * servo: a PI controller on e = F_target(t) - F, F = -force . a the force the
 * particles push against the wall, sets its velocity along a to
 * v = clamp(kp e + ki int e dt, -vmax, vmax) at each accepted step (the
 * integral held while v is at its limit: anti-windup). F_target(t) is the
 * piecewise-linear schedule (times [s] increasing, forces [N]; held outside),
 * timed from the wall's motion start, before which the wall is held;
 * a pressure P on area A is the force P A. Gains kp [m/(s N)], ki
 * [m/(s^2 N)] (>= 0, not both 0), vmax [m/s] > 0. Replaces the wall's
 * prescribed motion (the wall starts where it is); a later motion replaces
 * the servo. Guidance: kp ~ vmax / F_target makes the wall approach at its
 * limit and slow within the target's magnitude; ki adds a creep that removes
 * the steady error.
 */
SINTER_API sinter_status sinter_walls_set_servo(sinter_walls *walls, size_t k, size_t n,
                                                const double *times, const double *forces,
                                                double kp, double ki, double vmax);
/**
 * State of wall k's servo: target force [N] at the current time, the force
 * the particles push against it [N], its velocity along its normal [m/s]
 * (any pointer may be NULL). SINTER_ERR_INVALID when the wall has no servo.
 */
SINTER_API sinter_status sinter_walls_get_servo(const sinter_walls *walls, size_t k,
                                                double *target, double *pushed, double *velocity);

/* ------------------------------------------------------------------------ */
/* Force submodels                                                           */
/* ------------------------------------------------------------------------ */

/**
 * One force/moment submodel. Built-in models are chosen by name:
 *  - "hertz_mindlin": Hertz normal contact with viscous damping (seed 003
 *    eq. 2-6), Mindlin stick-slip friction (eq. 7-14), rolling resistance
 *    (eq. 15-20, active when the rolling coefficient is > 0); particle-particle
 *    and particle-wall contacts. Parameter "rolling" (default 1): 0 leaves the
 *    rolling model out (3 history values per contact instead of 6). While no
 *    material in use has a rolling coefficient > 0, the rolling moment is 0
 *    and costs nothing: the law without rolling runs, the rolling spring held
 *    at zero. Parameter "no_tension" (default 0: eq. 2 as printed, the
 *    damper may pull while a contact opens): 1 clamps the normal force at
 *    zero, f_n = max(f_n, 0).
 *  - "power_law": the contact-area-scaled power law of seed 000 (eq. 2-4),
 *    its sliding friction (eq. 5-6), wall contact (eq. 13-17) and adhesive
 *    bonds (eq. 18-19).
 *  - "drag": interstitial drag -c_env (v - v_env) (seed 000 eq. 20).
 *  - "gravity": m g, with g set by the parameters "gx", "gy", "gz" [m/s^2]
 *    (default 0, 0, -9.81).
 *  - "body_force": a constant force "fx", "fy", "fz" [N] on every particle.
 * Host models come from sinter_force_model_create_host (sinter_submodel.h).
 */
typedef struct sinter_force_model sinter_force_model;

/** Create a built-in force model by name. Errors: SINTER_ERR_NOT_FOUND names the unknown model. */
SINTER_API sinter_status sinter_force_model_create(sinter_force_model **out, sinter_ctx *ctx,
                                                   const char *name);
/** Destroy a force model (NULL is allowed); remove it from steppers first. */
SINTER_API void sinter_force_model_destroy(sinter_force_model *fm);
/** The model's name (borrowed). */
SINTER_API const char *sinter_force_model_name(const sinter_force_model *fm);
/** Set a model-level parameter by key (e.g. "gz" of gravity); unknown keys give SINTER_ERR_NOT_FOUND. */
SINTER_API sinter_status sinter_force_model_set(sinter_force_model *fm, const char *key,
                                                double value);
/** Read a model-level parameter by key. Errors: SINTER_ERR_NULL, SINTER_ERR_NOT_FOUND. */
SINTER_API sinter_status sinter_force_model_get(const sinter_force_model *fm, const char *key,
                                                double *value);

/* ------------------------------------------------------------------------ */
/* Steppers                                                                  */
/* ------------------------------------------------------------------------ */

/** A time integrator over a particle set, walls and submodels, all borrowed. */
typedef struct sinter_stepper sinter_stepper;

/** Stepper kinds. */
typedef enum sinter_stepper_kind {
    SINTER_STEPPER_EXPLICIT = 0, /**< velocity Verlet, fixed step (seed 003 sec. 4) */
    SINTER_STEPPER_STAGGERED = 1, /**< implicit staggered, adaptive step (seed 000 sec. 3, 6) */
    SINTER_STEPPER_QUASISTATIC = 2 /**< bonded links driven by 7DOF necks, K u = f each step (seed 001 sec. 3.3) */
} sinter_stepper_kind;

/** What a stepper did. */
typedef struct sinter_stepper_stats {
    size_t struct_size;       /**< set to sizeof(sinter_stepper_stats) by the caller */
    uint64_t steps;           /**< accepted steps */
    uint64_t rejected;        /**< rejected steps */
    uint64_t neighbor_builds; /**< neighbour list rebuilds */
    uint64_t contacts;        /**< particle-particle contacts in the last step */
    uint64_t wall_contacts;   /**< particle-wall contacts in the last step */
    double time;              /**< simulated time [s] */
    double dt;                /**< current step [s] */
    double seconds_neighbor;  /**< wall-clock time in neighbour search [s] */
    double seconds_force;     /**< wall-clock time in force evaluation [s] (on two or more
                                   threads the explicit step's conduction, summed in the
                                   contact law's parallel region, counts here) */
    double seconds_integrate; /**< wall-clock time in the update of positions and velocities [s] */
    double seconds_total;     /**< wall-clock time in sinter_stepper_advance [s] */
    /* Appended in 0.x (struct_size tells the library which fields a caller has). */
    uint64_t iterations;      /**< fixed-point iterations, accepted and rejected (staggered) */
    uint64_t evaluations;     /**< evaluations of the force/electric/heat pipeline */
    /* Appended later. */
    double contraction;       /**< staggered scheme 1: contraction (E_K/E_0)^(1/K) of the fixed-point
                                   iteration in the last accepted step (0: none measured) */
    uint64_t bonds_broken;    /**< bonds that held in tension and broke (power law option
                                   bond_strength), counted over the accepted steps */
} sinter_stepper_stats;

/**
 * Observer called after every accepted step with the time [s]. Return 0 to
 * continue, non-zero to stop advance (which then returns SINTER_OK early).
 */
typedef int (*sinter_observer_fn)(const sinter_stepper *stepper, double time, void *user);

/**
 * Create a stepper over `particles` and `walls` (walls may be NULL). Both are
 * borrowed: destroy the stepper first. SINTER_STEPPER_EXPLICIT takes fixed
 * steps of sinter_stepper_set_dt; SINTER_STEPPER_STAGGERED solves each step
 * by fixed-point iterations of the trapezoidal rule, positions then
 * temperatures, and adapts the step (see sinter_stepper_set_option).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_UNSUPPORTED (unknown kind),
 * SINTER_ERR_INVALID (objects of another context).
 */
SINTER_API sinter_status sinter_stepper_create(sinter_stepper **out, sinter_ctx *ctx,
                                               sinter_stepper_kind kind,
                                               sinter_particles *particles, sinter_walls *walls);
/** Destroy a stepper (NULL is allowed); the particles, walls and models it borrows remain. */
SINTER_API void sinter_stepper_destroy(sinter_stepper *stepper);
/** Add a force submodel (borrowed; it may be shared by several steppers). */
SINTER_API sinter_status sinter_stepper_add_force(sinter_stepper *stepper, sinter_force_model *fm);
/** Time step [s] (> 0). */
SINTER_API sinter_status sinter_stepper_set_dt(sinter_stepper *stepper, double dt);
/** Verlet skin [m] (>= 0): neighbour lists are rebuilt when a particle moved more than half of it. */
SINTER_API sinter_status sinter_stepper_set_skin(sinter_stepper *stepper, double skin);
/**
 * Simulation domain [m]: a step that leaves a particle's centre outside the
 * box lo..hi is rejected with SINTER_ERR_LOST_PARTICLE (the last accepted
 * state is kept). By default there is no domain.
 */
SINTER_API sinter_status sinter_stepper_set_domain(sinter_stepper *stepper, const double lo[3],
                                                   const double hi[3]);
/**
 * Periodic boundary along `axis` (0 x, 1 y, 2 z) with the cell lo..hi [m] (hi > lo); lo = hi = 0
 * makes the axis non-periodic again (the default). Every stepper kind. The quasi-static stepper
 * makes no ghost particles: its links join a particle to the image of another, and its cell
 * shrinks with the packing's mean strain (option "qs_cell_strain"; sinter_stepper_get_periodic
 * gives the cell now); every particle must lie in the cell at its first step. The rest of this
 * comment is about the explicit and staggered steppers. At every neighbour build the particles are wrapped
 * into the cell (between builds a centre may lie up to half the skin outside it) and each
 * particle within 2 r_max + skin of a periodic face gets an image beyond the opposite face: a
 * ghost particle, stored after the owned particles (sinter_particles_owned_count), refreshed
 * from its owner every step and never integrated for itself. Contacts, their history, heat and
 * current act across the faces; a pair across a face is evaluated once and its force, moment,
 * heat power and current reach both particles; a heat source of one particle acts on the
 * owned particle only. The "network" electric model's potential is periodic: electrodes are
 * walls across a non-periodic axis. The period must be at least twice 2 r_max + skin.
 * Not yet supported together with (SINTER_ERR_UNSUPPORTED at the step): the "averaged"
 * electric model, host heat models, a host force model with both a contact and a body
 * callback; the energy check does not run while an axis is periodic. A
 * domain check tests the non-periodic axes only; a bond in tension across a face is kept to
 * the nearest image of its far end.
 */
SINTER_API sinter_status sinter_stepper_set_periodic(sinter_stepper *stepper, int axis, double lo,
                                                     double hi);
/** Whether `axis` is periodic (*periodic 1 or 0) and its cell [m] (lo, hi may be NULL; 0 when
 * not periodic). */
SINTER_API sinter_status sinter_stepper_get_periodic(const sinter_stepper *stepper, int axis,
                                                     int *periodic, double *lo, double *hi);
/**
 * Options of the implicit staggered stepper (SINTER_STEPPER_STAGGERED, seed
 * 000 sec. 3 and 6, Algorithm 1). Keys, defaults and valid values:
 *  - "phi": trapezoidal parameter of eq. 24-25 and 36; 0.5 (second order),
 *    1 is backward Euler (first order); (0, 1].
 *  - "target_iterations": K_d of eq. 49, the fixed-point iterations a step
 *    should need; also the most a step may take before it is restarted from
 *    t with a smaller step; 10; whole number in [2, 1000].
 *  - "tolerance": TOL_r = TOL_theta of eq. 48, on the normalised iteration
 *    errors of eq. 47; 5e-4; (0, 1).
 *  - "exponent": p of eq. 49, the contraction constant of the iteration
 *    taken as S dt^p; 2 (the seed's value for the second-order particle
 *    dynamics); (0, 10].
 *  - "dt_max": upper bound dt_lim of the step [s] (Algorithm 1, step 6c);
 *    +infinity (HUGE_VAL); > 0.
 *  - "dt_min": a step that would fall below it fails with
 *    SINTER_ERR_NOT_CONVERGED naming the time and the field [s]; 1e-12;
 *    > 0 and <= dt_max.
 *  - "adaptive": 1 scales the step by Lambda_K of eq. 49 after each step; 0
 *    keeps the step of sinter_stepper_set_dt (a step that does not converge
 *    in K_d iterations then fails with SINTER_ERR_NOT_CONVERGED); 1.
 *  - "position_tolerance" [m], "temperature_tolerance" [K]: absolute floors
 *    added to eq. 47-48 (beyond the seed): a field also converges when the
 *    mean change per particle between two iterates is at most this; 0 (the
 *    seed's relative test alone); >= 0. A resting pile with Coulomb friction
 *    needs the position floor: friction flips direction between iterates and
 *    the relative test then forces the step towards zero.
 * Beyond eq. 49 the step control stops an attempt early when the iteration
 * stagnates (see src/stepper/staggered.c), grows the step at most twofold,
 * and not at all right after a restart.
 *  - "scheme": 0 the seed's Algorithm 1 as above; 1 (default) the same
 *    trapezoidal rule with Anderson acceleration of the fixed-point
 *    iteration, a weighted RMS convergence test per quantity (relative
 *    tolerance "tolerance", absolute "position_tolerance" [m] and
 *    "temperature_tolerance" [K]), a PI step controller on the measured
 *    contraction (growth in [1/2, 2]) and a predictor extrapolating the
 *    forces and heat powers of the two previous steps; an attempt takes at
 *    most 2 "target_iterations" (see src/stepper/staggered.c); 1 (chosen by
 *    measurement: tests/bench/RESULTS.md); 0 or 1.
 *  - "anderson_depth": m of Anderson(m) in scheme 1; 0 is the plain
 *    iteration; 3; whole number in [0, 10].
 * The step starts at the value of sinter_stepper_set_dt, capped by dt_max.
 * Every kind also takes "sort_interval": the particles are sorted in memory by
 * position (sinter_particles_sort_spatial; indices change, ids do not) before
 * the first step after the option is set and then before every step that
 * follows so many accepted steps; 0, the default, never. The quasi-static
 * stepper keys its links and orders its work by particle id, so a sorted run
 * gives the same bits as an unsorted one. The explicit and staggered steppers
 * also take "rotation": 1, the default, integrates the
 * total rotation vector of each particle (seed 003 eq. 45,
 * SINTER_FIELD_ROTATION); 0 leaves it as it is, which saves a quarter of the
 * explicit integrator's memory traffic when nothing reads it (no force or
 * heat model does: rolling resistance keeps its own relative rotation per
 * contact) (SINTER_ERR_UNSUPPORTED on a quasi-static stepper).
 * Any stepper takes "stream_stores", which only the explicit one uses: from
 * 65536 particles on an x86-64 machine, the new positions, velocities and
 * spins of a step may be written with streaming (non-temporal) stores, which
 * pay when the particle arrays do not fit in the caches and cost when they
 * do; -1, the default, times steps of both kinds after each change of the
 * particles or threads and keeps the faster; 1 always, 0 never. The results
 * are the same to the bit either way.
 * Any stepper takes "thread_choice", which only the explicit one uses: when the
 * context allows more than one thread (sinter_ctx_set_threads), -1, the
 * default, times a few steps on that many threads and on one, takes the
 * faster, and measures again after half a second or more (and at least 50
 * times the measurement's own time, so that measuring costs little): where
 * the threads' cores share no cache (two dies or sockets; the project's VMs
 * when the host places their cores so) a small system on two threads can take
 * twice as long as on one. 0 always takes the context's count. The results
 * are the same to the bit either way (no sum depends on the thread count).
 * Any stepper takes "dt_check" and "energy_check", which only the explicit one
 * uses (issue 35). "dt_check": 1, the default, refuses a fixed step above twice
 * the stable step estimate (sinter_stepper_stable_step) before the first step
 * of sinter_stepper_advance or sinter_stepper_step, with SINTER_ERR_INVALID
 * giving both numbers; 0 runs it knowingly. "energy_check": N >= 1 checks
 * every N-th step (1, the default; the check's pass over the particles costs
 * about 12 % of a step of a 64k packed bed, so a large run may check less
 * often, at the risk of missing energy created in the few steps of one
 * collision; the first step of a stepper is always checked), and rejects a
 * step that created energy in a contact (a damped contact cannot
 * return more than it took): a particle's kinetic energy more than doubled,
 * beyond the work of gravity, body forces and the drag's medium, and it and
 * its contact partners (in their centre-of-mass frame, or the walls' when one
 * touches a wall) gained more than twice the elastic energy of their contacts
 * at the start and at the end of the step and a bound of the work of their
 * contacts with others, plus half their kinetic energy (gains below a
 * thousandth of a contact's elastic energy at the estimate's reference
 * overlap are not examined); SINTER_ERR_UNSTABLE
 * names the particle(s), the energies and the time, and the last accepted
 * state is kept (src/stepper/sanity.c, criterion 4). Particles touching a
 * moving wall are not examined, nor any with a host contact model; 0 turns
 * it off. It reads the state only: results are the same to the bit either
 * way.
 * Any stepper takes "reproducible" (issue 43), made for the explicit and the
 * staggered steppers: 1 sorts the candidate pairs by the ids of their two particles at every
 * neighbour build (wall pairs by id, then wall index) and sums every
 * particle's contact forces, moments and heat powers in that order on one
 * thread (the integrator's passes stay on the threads: they work particle by
 * particle), so that the particles' state and contact histories are the same
 * bits for any order of the particles in memory, any number of threads and,
 * with domain operations (sinter_domain.h), any number of subdomains; the
 * walls' reactions are then exact sums of their contacts' (the same bits in
 * every case too). Its cost: a sort of the pairs at each build, the exact
 * sums of the wall reactions and the force law's threads
 * (tests/bench/RESULTS.md). 0, the default, keeps the build's order, which
 * gives the same bits on any number of threads only. The staggered stepper
 * (both schemes) also sums eq. 47's errors, its weighted RMS norms and
 * Anderson's inner products exactly (integer limb sums, two reductions each
 * with domain operations), and the averaged electric model sweeps Jacobi's
 * iteration (each current from its neighbours' of the last sweep) with exact
 * stopping sums instead of Gauss-Seidel: about 1.7 times the sweeps from a
 * cold start, as many once warm; its currents then differ from the default's
 * within the model's tolerance. The "network" electric model and implicit
 * conduction (SINTER_THERMAL_IMPLICIT) take every PCG dot product and norm
 * as an exact sum, a current electrode's row, diagonal and current too, with
 * or without domain operations: their solutions the same bits on any number
 * of subdomains and threads (the network's cold solves about twice the
 * default's instructions, tests/bench/RESULTS.md). The heat models' energies
 * (sinter_stepper_heat_energy_global) are not exact sums yet. Setting it
 * rebuilds the neighbour lists at the next evaluation; forces already
 * evaluated are kept.
 * The quasi-static stepper takes it too: 1 makes every sum over particles or
 * links exact (each particle's loads, the bonded solve's operator products,
 * diagonal blocks and dot products, the green density, mean temperature,
 * statistics and floating components), solves K u = f by PCG with a
 * per-particle block-Jacobi preconditioner with or without domain operations,
 * and integrates strategy 3's necks one by one, so that its results are the
 * same bits without domain operations and on any number of subdomains and
 * threads; 1.7-3.9 times the default's CPU on one thread (more PCG
 * iterations, exact row sums; tests/bench/RESULTS.md).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_NOT_FOUND (unknown key, the message
 * lists the keys), SINTER_ERR_INVALID (value out of range, or a stepper of
 * another kind; the message says which).
 */
SINTER_API sinter_status sinter_stepper_set_option(sinter_stepper *stepper, const char *key,
                                                   double value);
/** Read an option of sinter_stepper_set_option. Errors as there. */
SINTER_API sinter_status sinter_stepper_get_option(const sinter_stepper *stepper, const char *key,
                                                   double *value);
/**
 * Furnace: every particle's temperature follows the piecewise-linear schedule
 * T(t) through `count` points (times [s] strictly increasing, on the
 * stepper's clock; temperatures [K] finite and > 0; constant before the first
 * point and after the last). The quasi-static stepper integrates the necks
 * along T(t) itself (breakpoints at the points and at phase changes); every
 * stepper kind sets the particle temperatures to T(t) before its first step
 * and after each accepted step. The arrays are copied; count = 0 removes the
 * furnace. A furnace prescribes the temperatures, so it cannot be combined
 * with heat models. Errors: SINTER_ERR_NULL (NULL arrays with count > 0),
 * SINTER_ERR_INVALID (the message names the bad point), SINTER_ERR_STATE
 * (the stepper has heat models), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_stepper_set_furnace(sinter_stepper *stepper, size_t count,
                                                    const double *times,
                                                    const double *temperatures);
/** Set the observer (NULL to remove). */
SINTER_API sinter_status sinter_stepper_set_observer(sinter_stepper *stepper,
                                                     sinter_observer_fn fn, void *user);
/**
 * Advance to time t_end [s] (>= current time). The last step is shortened to
 * land on t_end. On an error the particle set holds the last accepted state,
 * with its forces evaluated again: it can be read and checkpointed at once.
 */
SINTER_API sinter_status sinter_stepper_advance(sinter_stepper *stepper, double t_end);
/** Take exactly n steps. */
SINTER_API sinter_status sinter_stepper_step(sinter_stepper *stepper, uint64_t n);
/** Current simulated time [s]. */
SINTER_API sinter_status sinter_stepper_time(const sinter_stepper *stepper, double *time);
/**
 * Fill `stats`. Its struct_size must be set: sizeof(sinter_stepper_stats), or
 * the size of an older layout (up to seconds_total, before iterations and
 * evaluations were appended; up to evaluations, before contraction; up to
 * contraction, before bonds_broken), in which case only the fields it covers
 * are written. Other sizes: SINTER_ERR_STRUCT_SIZE.
 */
SINTER_API sinter_status sinter_stepper_get_stats(const sinter_stepper *stepper,
                                                  sinter_stepper_stats *stats);
/**
 * Evaluate forces on the current state without stepping (fills the force and
 * torque fields and the wall reactions; history is not committed).
 */
SINTER_API sinter_status sinter_stepper_evaluate(sinter_stepper *stepper);

/**
 * Stable explicit step for Hertz contacts, seed 003 eq. 47: dt = t_c / 10 with
 * t_c = 2.87 (m*^2 / (r* E*^2 v_rel))^(1/5), taken over the smallest particle
 * pair of the set (and particle-wall pairs) at relative normal speed v_rel [m/s].
 * The particles are checked first (sinter_particles_validate: values written
 * through a view, such as an unregistered material id, give SINTER_ERR_INVALID).
 */
SINTER_API sinter_status sinter_stable_dt_hertz(const sinter_particles *particles,
                                                const sinter_walls *walls, double v_rel,
                                                double *dt);

/**
 * Stable step estimate [s] of the explicit stepper (issue 35): the critical
 * step of velocity Verlet, (2 / omega) (sqrt(1 + xi^2) - xi) with omega =
 * sqrt(k / m*), for the stiffest contact the particles can meet: every pair of
 * the materials they hold and every material against every wall, for each of
 * the stepper's built-in contact models, between the smallest particles of the
 * materials. Hertz: k = 2 E* sqrt(R* delta) at delta = 1 % of R*, xi the pair's
 * damping ratio; power law: k = 2 pi (p + 1) K R* E^p at strain E = 0.1;
 * linear spring: k = kn, xi = cn / (2 sqrt(kn m*)); unsoftened moduli. The
 * formula and its sources are in src/stepper/stable_step.c. +infinity
 * (HUGE_VAL) without a built-in contact model. The explicit stepper refuses a
 * step above twice this (option "dt_check"); steps of a fifth to a tenth of it
 * are advisable (a grain in several contacts vibrates faster than in one).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (an invalid particle set, as
 * sinter_particles_validate).
 */
SINTER_API sinter_status sinter_stepper_stable_step(sinter_stepper *stepper, double *dt);

/** Damping ratio xi of seed 003 eq. 6 that gives restitution e in a Hertz collision (0 < e <= 1). */
SINTER_API sinter_status sinter_damping_ratio_from_restitution(double e, double *xi);



/* ------------------------------------------------------------------------ */
/* Heat submodels                                                            */
/* ------------------------------------------------------------------------ */

/**
 * One heat-power submodel: it adds power [W] to particles, and the stepper
 * integrates m C dtheta/dt = sum of powers (seed 003 eq. 28, seed 000 eq. 31).
 * Built-in models, chosen by name, with their parameters (SI):
 *  - "conduction": through contacts, Q_ij = k_ij A_ij (theta_j - theta_i) / d_ij
 *    with (r_i + r_j)/k_ij = r_i/k_i + r_j/k_j (seed 003 eq. 32-35, seed 000
 *    eq. 33-34); particle-wall contacts conduct to the wall's temperature with
 *    G = k_iw A / d, k_iw = 2 k_i k_w / (k_i + k_w) (k_w of the wall's
 *    material: equal to the particle's, k_i; zero: adiabatic), and the
 *    area and distance of "wall_reading": 0 eq. 34's circle over the
 *    centre-plane distance s; 1 (default) Hertz's pi r delta over s; 2 eq. 34's
 *    circle over the mirror particle's 2 s; then each wall's thermal mode
 *    (sinter_walls_set_thermal).
 *    "area" = 0: contact area of eq. 34; 1: LIGGGHTS' "projection",
 *    conductance 4 k_i k_j/(k_i + k_j) sqrt(pi r_max^2) (walls: with the wall
 *    material's k, so k = 0 makes a wall adiabatic); 2: constriction
 *    conductance 4 a k_i k_j / (k_i + k_j) (Batchelor-O'Brien, 2 k a for
 *    equal k). "radius" = 0: eq. 34's contact radius, 1: Hertz's a^2 = r*
 *    delta (areas 0 and 2). "resistance" R'' [m^2 K/W]: an interface
 *    resistance in series, 1/G = 1/G_law + R''/A. "gas_conductivity" k_g
 *    [W/(m K)] > 0: conduction through the gas lens around each contact
 *    (Cheng et al. 1999), cut off at the gap "gas_gap" [m] (default 1e-7) and
 *    out to "gas_radius" (default 0.5) times the smaller radius; "gas_reach"
 *    f > 0: the same lens between pairs apart by less than f min(r_i, r_j)
 *    (explicit in the implicit scheme; the stepper widens its neighbour search
 *    by f times the largest radius; default 0: touching pairs only). "walls" = 1/0.
 *  - "convection": Newton's law Q = h (theta_E - theta) 4 pi r^2 (eq. 37) with
 *    h = Nu k_E / (2 r) and Whitaker's Nu (eq. 38-40). Parameters
 *    "temperature" theta_E [K], "h" [W/(m^2 K)] (> 0 overrides the
 *    correlation), "fluid_conductivity" [W/(m K)], "fluid_viscosity" [Pa s],
 *    "fluid_heat_capacity" [J/(kg K)], "fluid_density" [kg/m^3],
 *    "fluid_speed" [m/s] (0: stagnant, Nu = 2). "exposed" = 1: only the
 *    fraction of each surface that faces the surroundings (one minus the view
 *    factors to touching particles, (1 - sqrt(1 - (r_j/d)^2))/2 each, and walls,
 *    1/2 each). "fluid_law" = 1: conductivity and viscosity by Sutherland's law
 *    ("sutherland_conductivity", "sutherland_viscosity" [K], air's 194 and 111)
 *    and an ideal gas's density at the film temperature (theta + theta_E)/2, the
 *    fluid_* values holding at "fluid_reference_temperature" [K] (293.15).
 *  - "radiation": Q = epsilon sigma 4 pi r^2 (theta_E^4 - theta^4) (eq. 41),
 *    "temperature" theta_E [K]; "exposed" as for convection.
 *  - "nozzle": Q = a I0 pi r^2 (1 - z/d_max) for 0 <= z <= d_max (eq. 29-30);
 *  - "laser": Q = a I0 pi r^2 exp(-mu z) (eq. 31).
 *    Both: a beam along -z through ("x", "y") [m] of radius "radius" [m],
 *    intensity "intensity" I0 [W/m^2]; "depth" d_max [m] (nozzle) or
 *    "attenuation" mu [1/m] (laser); defaults: axis x = y = 0, radius 5 mm,
 *    intensity 0 (off), depth 1 mm, attenuation 1000 1/m. z is the depth of a
 *    particle's top below
 *    the highest particle top inside the beam. "x", "y" and "intensity" may
 *    follow schedules (sinter_heat_model_set_schedule).
 *  - "beam": a ray-traced beam in any direction with shadowing: the axis through
 *    ("x", "y", "z") along ("dx", "dy", "dz") (default -z), total power "power"
 *    [W] (default 0), "radius" [m] (top hat; Gaussian: the 1/e^2 radius),
 *    "profile" 0 top hat / 1 Gaussian, "attenuation" mu [1/m] inside particles
 *    (default 1e9: opaque), "rays" across the diameter (default 32). Each ray
 *    gives a particle it crosses along a chord L the fraction a (1 - exp(-mu L))
 *    of the power reaching it (a: absorptance), the rest goes on; absorbed plus
 *    transmitted is the beam's power. Outputs: sinter_heat_model_output.
 *  - "joule": Joule heating. With a "network" electric model (by default,
 *    "source" = 0): the power the network dissipates in its contacts,
 *    G (phi_a - phi_b)^2 per contact, half to each particle of a pair and all
 *    of it to the particle at an electrode, so that the heat put into the
 *    particles equals the walls' electrical work (sinter_electric_model_power).
 *    Otherwise, or with "source" = 1 (2: the network's, an error without one):
 *    H = a J^2 / sigma V (seed 000 eq. 35) with J the
 *    particle's current field (written by an electric model or the host),
 *    a the absorptance, sigma the electric conductivity of its material and
 *    V = 4/3 pi r^3. "sigmoid" = 1 makes sigma follow seed 000 eq. 50,
 *    sigma = sigma_0 (1 + "k1" s("gamma1" (theta - "theta_ref")) +
 *    "k2" s("gamma2" |E - "field_ref"|)), s(x) = 1 / (1 + e^-x), with
 *    sigma_0 the material's conductivity and the scalar field E = |J| / sigma_0
 *    (Ohm's law; "field_ref" in the units of J / sigma_0 and "gamma2" in their
 *    inverse; "theta_ref" [K], "gamma1" [1/K], "k1", "k2" [-]; defaults:
 *    sigmoid 0, theta_ref 293.15 K, the others 0). Each sigmoid is 1/2 at its
 *    reference, so eq. 50 at (theta_ref, field_ref) gives
 *    sigma_0 (1 + k1/2 + k2/2), not sigma_0. A current through a particle of
 *    zero conductivity is SINTER_ERR_INVALID, a conductivity <= 0 from eq. 50
 *    SINTER_ERR_DOMAIN.
 *  - "dissipation": heat from friction and inelastic impacts (seed 003 remark
 *    3). The force models report the power their contacts dissipate
 *    ("hertz_mindlin": the normal damper's (f_n - f_elastic) d(delta)/dt and,
 *    where a contact slides, |f_t . u_t|; the tangential damper while
 *    sticking and the rolling slider are not counted), half to each particle
 *    of a pair, all of it to the particle at a wall. "impact" (1/0) and
 *    "friction" (1/0), default 1. Explicit stepper only (elsewhere nothing).
 * Host models come from sinter_heat_model_create_host (sinter_submodel.h).
 */
typedef struct sinter_heat_model sinter_heat_model;

/** Create a built-in heat model by name (list above). Errors: SINTER_ERR_NOT_FOUND names the unknown model. */
SINTER_API sinter_status sinter_heat_model_create(sinter_heat_model **out, sinter_ctx *ctx,
                                                  const char *name);
/** Destroy a heat model (NULL is allowed). */
SINTER_API void sinter_heat_model_destroy(sinter_heat_model *hm);
/** The model's name (borrowed). */
SINTER_API const char *sinter_heat_model_name(const sinter_heat_model *hm);
/** Set a parameter by key (list above). Errors: SINTER_ERR_NOT_FOUND (unknown key), SINTER_ERR_INVALID. */
SINTER_API sinter_status sinter_heat_model_set(sinter_heat_model *hm, const char *key,
                                               double value);
/**
 * Move the model's beam along a scan path (issue 40's scan strategies): `n` vertices of 4
 * values each, x [m], y [m], speed [m/s] > 0 and level [-] in [0, 1]; vertex 0 is the start
 * point (its speed and level are ignored), and the source moves from each vertex to the next
 * in a straight line at that vertex's speed with its power times that vertex's level (0: off,
 * a jump; 1: full power). The path starts at `start_time` [s]; before it the source stands at
 * the first vertex and after its end at the last, off. It drives the axis point ("x", "y")
 * and the power ("power" of "beam", "intensity" of "laser" and "nozzle": their values, or
 * schedules, times the level) of the models that have a beam; others: SINTER_ERR_INVALID.
 * n = 0 removes the path. Errors name the vertex (a non-finite value, a speed <= 0 on a
 * segment of non-zero length, a level outside [0, 1]); on error the model is unchanged.
 */
SINTER_API sinter_status sinter_heat_model_set_scan_path(sinter_heat_model *hm, size_t n,
                                                         const double *points, double start_time);
/** The time [s] at which the model's scan path ends. Errors: SINTER_ERR_NOT_FOUND (no path). */
SINTER_API sinter_status sinter_heat_model_scan_end(const sinter_heat_model *hm, double *end_time);
/**
 * The vertices of a hatch (parallel scan lines filling a rectangle, as powder-bed machines scan
 * an area) for sinter_heat_model_set_scan_path: lines along the direction `angle` [rad] from
 * the x axis, `spacing` [m] apart, centred across the rectangle lo..hi ([m], x and y), each
 * clipped to it and scanned at `speed` [m/s] at level 1, the jumps between them at
 * `jump_speed` [m/s] at level 0; `serpentine` = 1 scans every other line backwards. Writes at
 * most `capacity` vertices (4 values each) into `points` and their number into *count;
 * points == NULL only counts. Errors: SINTER_ERR_INVALID (an empty or non-finite rectangle,
 * spacing, speeds), SINTER_ERR_RANGE (capacity too small).
 */
SINTER_API sinter_status sinter_scan_hatch(sinter_ctx *ctx, const double lo[2], const double hi[2],
                                           double spacing, double angle, double speed,
                                           double jump_speed, int serpentine, double *points,
                                           size_t capacity, size_t *count);
/**
 * An output of the model's last evaluation by name ("beam": "absorbed" and
 * "transmitted" [W], "lit" [1], "lit_temperature" [K]; other models have none).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_NOT_FOUND (no such output).
 */
SINTER_API sinter_status sinter_heat_model_output(const sinter_heat_model *hm, const char *name,
                                                  double *value);
/** Read a parameter by key (its constant value, not a schedule's). Errors: SINTER_ERR_NOT_FOUND. */
SINTER_API sinter_status sinter_heat_model_get(const sinter_heat_model *hm, const char *key,
                                               double *value);
/**
 * Make parameter `key` follow a piecewise-linear schedule through n points
 * (times [s] strictly increasing, values in the parameter's unit), held
 * constant outside. Copied.
 */
SINTER_API sinter_status sinter_heat_model_set_schedule(sinter_heat_model *hm, const char *key,
                                                        size_t n, const double *times,
                                                        const double *values);

/** Thermal time integration of the explicit stepper. */
typedef enum sinter_thermal_scheme {
    SINTER_THERMAL_EXPLICIT = 0, /**< forward Euler, seed 003 eq. 46 (stable for dt < m C / sum G) */
    SINTER_THERMAL_IMPLICIT = 1  /**< backward Euler for conduction (PCG solve), other powers explicit */
} sinter_thermal_scheme;

/** Add a heat submodel (borrowed). A stepper without one does no thermal work at all. */
SINTER_API sinter_status sinter_stepper_add_heat(sinter_stepper *stepper, sinter_heat_model *hm);
/**
 * Choose the thermal scheme of the explicit stepper (default explicit). The
 * staggered stepper integrates temperatures by the trapezoidal rule inside
 * its fixed-point iteration (seed 000 eq. 36) and refuses
 * SINTER_THERMAL_IMPLICIT with SINTER_ERR_INVALID.
 */
SINTER_API sinter_status sinter_stepper_set_thermal_scheme(sinter_stepper *stepper, int scheme);
/**
 * Largest stable step of explicit thermal stepping in the current contact
 * state: min over particles of m C / (sum of contact conductances) [s]
 * (+infinity when nothing conducts).
 */
SINTER_API sinter_status sinter_stepper_stable_dt_thermal(sinter_stepper *stepper, double *dt);
/**
 * Energy bookkeeping of heat submodels [J]: the time integral of the power
 * model `index` (in order of addition) put into the particles so far.
 */
SINTER_API sinter_status sinter_stepper_heat_energy(const sinter_stepper *stepper, size_t index,
                                                    double *energy);
/** Wall temperature following a piecewise-linear schedule (times [s], temperatures [K]). */
SINTER_API sinter_status sinter_walls_set_temperature_schedule(sinter_walls *walls, size_t k,
                                                               size_t n, const double *times,
                                                               const double *temperatures);

/**
 * Thermal boundary condition of a wall for the "conduction" heat model (the
 * wall's temperature is sinter_walls_set_temperature's; its conductivity k_w
 * that of the wall's material).
 */
typedef enum sinter_wall_thermal_mode {
    SINTER_WALL_RESERVOIR = 0,  /**< conducts by the model's wall law to its temperature (default) */
    SINTER_WALL_ADIABATIC = 1,  /**< exchanges no heat */
    SINTER_WALL_RESISTANCE = 2, /**< the wall law in series with a specific contact resistance
                                     R'' [m^2 K/W]: 1/G = 1/G_law + R''/A */
    SINTER_WALL_TRANSFER = 3,   /**< a heat transfer coefficient h [W/(m^2 K)] over the contact
                                     area alone: G = h A */
    SINTER_WALL_IMPOSED = 4     /**< a touching particle takes the wall's temperature after each
                                     thermal update (seed 000 Fig. 5, remark 2) */
} sinter_wall_thermal_mode;

/**
 * Thermal boundary condition of wall k: `mode` is a sinter_wall_thermal_mode
 * and `value` R'' [m^2 K/W] for SINTER_WALL_RESISTANCE, h [W/(m^2 K)] for
 * SINTER_WALL_TRANSFER, ignored (stored as 0) otherwise. A is the contact area
 * of the conduction model's wall reading ("wall_reading").
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE (no wall k), SINTER_ERR_INVALID
 * (unknown mode, value negative or not finite).
 */
SINTER_API sinter_status sinter_walls_set_thermal(sinter_walls *walls, size_t k, int mode,
                                                  double value);

/* ------------------------------------------------------------------------ */
/* Electric submodels                                                        */
/* ------------------------------------------------------------------------ */

/** Electric boundary condition of a wall (seed 000 sec. 5, remark 2). */
typedef enum sinter_wall_electric_mode {
    SINTER_WALL_NEUTRAL = 0,  /**< insulating: carries no current (the default) */
    SINTER_WALL_CURRENT = 1,  /**< imposes a current J_ext [A] on the particles it touches */
    SINTER_WALL_POTENTIAL = 2 /**< held at an electric potential [V] ("network" model only) */
} sinter_wall_electric_mode;

/**
 * Electric boundary data of wall k: `mode` is a sinter_wall_electric_mode and
 * `value` its number, J_ext [A] for SINTER_WALL_CURRENT, the potential [V] for
 * SINTER_WALL_POTENTIAL, ignored (stored as 0) for SINTER_WALL_NEUTRAL.
 * The "averaged" model uses |J_ext| (a magnitude, seed 000 remark 2); the
 * "network" model reads J_ext as signed: > 0 flows from the wall into the
 * particles, < 0 out of them.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE (no wall k), SINTER_ERR_INVALID
 * (unknown mode, value not finite).
 */
SINTER_API sinter_status sinter_walls_set_electric(sinter_walls *walls, size_t k, int mode,
                                                   double value);

/**
 * Make wall k's electric value (the current [A] or potential [V] of its mode)
 * follow a piecewise-linear schedule of n points (times [s] strictly
 * increasing, in the simulation's time, as wall temperature schedules; held
 * constant outside); n = 0 removes it (the value of sinter_walls_set_electric
 * again). Copied. Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE, SINTER_ERR_INVALID
 * (the point named), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_walls_set_electric_schedule(sinter_walls *walls, size_t k,
                                                            size_t n, const double *times,
                                                            const double *values);

/**
 * Pulse wall k's drive: on for `on` seconds, then off (value 0) for `off`
 * seconds, repeated from t = 0 [s]; off = 0 makes it continuous again.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE, SINTER_ERR_INVALID (on <= 0,
 * off < 0, or not finite).
 */
SINTER_API sinter_status sinter_walls_set_electric_pulse(sinter_walls *walls, size_t k,
                                                         double on, double off);

/**
 * The compliance limit of wall k's supply, as a laboratory power supply has
 * one (used by the "network" model): a current electrode (SINTER_WALL_CURRENT)
 * is held at +-limit [V] when its potential would pass it, a potential
 * electrode (SINTER_WALL_POTENTIAL) carries +-limit [A] when its current would
 * pass it; 0 (the default) is no limit. Errors: SINTER_ERR_NULL,
 * SINTER_ERR_RANGE, SINTER_ERR_INVALID (negative or not finite).
 */
SINTER_API sinter_status sinter_walls_set_electric_limit(sinter_walls *walls, size_t k,
                                                         double limit);

/**
 * One electric submodel: the steady current through the contact graph
 * (seed 000 sec. 5, eq. 39-44), solved once per evaluation of a stepper that
 * has one, before forces and heat. It writes the particles' current field
 * [A] and their SINTER_PARTICLE_ELECTRIFIED flags; heat models (e.g. "joule")
 * read the current. Built-in models, chosen by name:
 *  - "averaged" (seed 000 eq. 42-43): a particle touching a current wall is
 *    electrified and takes the wall's |J_ext| (the contact-area-weighted mean
 *    if it touches several); every other particle takes the contact-area-
 *    weighted average of its neighbours' currents, J_i = sum_j J_j A_ij /
 *    sum_j A_ij, found by Gauss-Seidel sweeps particle by particle until
 *    sum_i |J_i^K - J_i^(K-1)| <= "tolerance" sum_i |J_i^K|. Particles not
 *    connected through contacts to an electrified particle get 0. A current
 *    magnitude propagated by averaging: it does not conserve charge. Walls
 *    held at a potential are refused (SINTER_ERR_INVALID).
 *  - "network": Kirchhoff's current law on the contact network of resistors.
 *    A particle pair conducts with G_ij = sigma_ij A_ij / d_ij, where
 *    (r_i + r_j) / sigma_ij = r_i / sigma_i + r_j / sigma_j (the rule of
 *    seed 003 eq. 35 for heat); a particle conducts to a non-neutral wall
 *    with its own conductivity, G = sigma_i A / d (d: centre-plane distance).
 *    A potential wall is a fixed potential (Dirichlet). A current wall is an
 *    equipotential electrode that injects the total J_ext: the network
 *    decides how it splits among the particles touching it. A cluster with
 *    no potential wall is solved only if its current walls' net current is
 *    zero (its potential is then fixed up to a constant, irrelevant to
 *    currents); otherwise the circuit is open and the cluster carries no
 *    current (a warning is logged, unless each of its current walls has a
 *    compliance limit: such a supply then simply sits at its limit). The node potentials are found with
 *    preconditioned conjugate gradients (SUNDIALS PCG, Jacobi) to a residual
 *    <= "tolerance" times the right-hand side. The particle's current is half
 *    the sum of |I| through its conducting contacts (what flows through it:
 *    in a chain, the chain's current). Particles not connected to a driven
 *    wall get 0. Particles of zero conductivity (the material default)
 *    do not conduct.
 * Parameters (both models): "tolerance" (> 0, < 1; default 1e-6 averaged,
 * 1e-10 network), "max_iterations" (sweeps or PCG iterations, integer >= 1,
 * default 10000); exceeding it is SINTER_ERR_NOT_CONVERGED. The network's
 * conductivities follow seed 000 eq. 50's temperature term with "sigmoid" = 1:
 * sigma_0 (1 + "k1" s("gamma1" (theta - "theta_ref"))), s(x) = 1 / (1 + e^-x)
 * (defaults 0, 0, 0 1/K, 293.15 K; a conductivity <= 0 from it is
 * SINTER_ERR_DOMAIN; the averaged model refuses these keys).
 * Only particles touching a non-neutral wall are flagged
 * SINTER_PARTICLE_ELECTRIFIED ("averaged": current walls only); the flag is
 * cleared on the others.
 */
typedef struct sinter_electric_model sinter_electric_model;

/** Create a built-in electric model by name. Errors: SINTER_ERR_NOT_FOUND names the known ones. */
SINTER_API sinter_status sinter_electric_model_create(sinter_electric_model **out,
                                                      sinter_ctx *ctx, const char *name);
/** Destroy an electric model (not while a stepper still uses it). NULL is allowed. */
SINTER_API void sinter_electric_model_destroy(sinter_electric_model *em);
/** The model's name (borrowed; "" for NULL). */
SINTER_API const char *sinter_electric_model_name(const sinter_electric_model *em);
/** Set a parameter by key. Errors: SINTER_ERR_NOT_FOUND (unknown key), SINTER_ERR_INVALID. */
SINTER_API sinter_status sinter_electric_model_set(sinter_electric_model *em, const char *key,
                                                   double value);
/** Read a parameter by key. Errors: SINTER_ERR_NULL, SINTER_ERR_NOT_FOUND. */
SINTER_API sinter_status sinter_electric_model_get(const sinter_electric_model *em,
                                                   const char *key, double *value);
/**
 * Give the stepper an electric model (borrowed; NULL removes it). The model
 * is solved on every evaluation, after the contacts are found and before
 * forces and heat. Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (another context).
 */
SINTER_API sinter_status sinter_stepper_set_electric(sinter_stepper *stepper,
                                                     sinter_electric_model *em);
/**
 * The power of the network model's last solve [W]: `supplied`, what the driven
 * walls deliver (sum over walls of its potential times the current from it
 * into the powder), and `dissipated`, Joule's G (phi_a - phi_b)^2 summed over
 * the conducting contacts. By Tellegen's theorem they are equal to the
 * accuracy of the solve ("tolerance"); the "joule" heat model puts the
 * dissipated power into the particles (its default with this model). Errors:
 * SINTER_ERR_NULL, SINTER_ERR_UNSUPPORTED (the "averaged" model, which has no
 * potentials).
 */
SINTER_API sinter_status sinter_electric_model_power(const sinter_electric_model *em,
                                                     double *supplied, double *dissipated);

/** Total iterations (sweeps or PCG iterations) of the stepper's electric solves so far. */
SINTER_API sinter_status sinter_stepper_electric_iterations(const sinter_stepper *stepper,
                                                            uint64_t *iterations);

/* ------------------------------------------------------------------------ */
/* Neck (7DOF) submodel                                                      */
/* ------------------------------------------------------------------------ */

/**
 * The two-particle solid-state sintering model of Thomsen et al. (seed 001 sec. 2.2, eqs. 1-9,
 * table 1) as specified by docs/7dof.md ("parametrisation 2", the path lengths of its §3): seven
 * lengths describe two spherical caps of radii R_A, R_B joined by two cones that meet in the
 * grain-boundary disc of radius x (the neck). Grain-boundary, surface and lattice diffusion move
 * volume between the ring, caps, cones and grain boundary, driven by the surface and
 * grain-boundary free energy. The material data are the material's neck parameters
 * (SINTER_MAT_ATOMIC_VOLUME .. SINTER_MAT_PHASE_TRANSITION_TEMPERATURE); a material with a
 * transition temperature switches to its *_HOT set at and above it, both ways.
 *
 * Options, by key (sinter_neck_model_set / _get; SINTER_ERR_NOT_FOUND for an unknown key,
 * SINTER_ERR_INVALID outside the range):
 *  - "epsilon": seeded neck radius x0 / min(R_A, R_B) (docs/7dof.md §4) [-]; 0.01, (0, 0.1]
 *  - "h0_ratio": junction radius of the seeded neck h0 / x0 (docs/7dof.md §4) [-]; 1.5, (1, 2)
 *  - "rtol": relative tolerance of every state component [-]; 1e-8, [1e-14, 1e-2]
 *  - "atol": absolute tolerance of the state lengths [m]; 0 = 1e-14 min(R_A, R_B); [0, 1]
 *  - "initial_step": first step [s]; 1e-12 (docs/7dof.md §4), 0 lets CVODE estimate; [0, 1e6]
 *  - "max_steps": most accepted steps of one run; 1e6, [1, 1e12], whole number
 *  - "integrator": 0 = CVODE BDF with Newton and a dense 7x7 solver (default); 1 = the seed's
 *    classical RK4 on a fixed grid, for comparisons (tolerances are then unused)
 *  - "rk4_steps": number of RK4 steps of a run; 20000, [1, 1e10], whole number
 *  - "rk4_time_scale": tau [s] of the RK4 grid, uniform in ln(1 + (t - t0)/tau); 1e-6, (0, 1e6]
 *  - "error_scale": what rtol is relative to. 1 (default): the geometry; the neck radius for
 *    y1 and the cone height H = L - d for the lengths of each side, the smallest length the
 *    state resolves, so the worst error stays within 10-30 rtol (rtol <= 1e-5). 0: each
 *    component's own magnitude, as docs/7dof.md §4 writes it; the side lengths are then ~R, a
 *    young neck's cone height ~1e-4 R goes unresolved at loose rtol, and at rtol 1e-4 the
 *    worst of 2400 copper necks was 11 % off in shrinkage (0.7 % with 1). Both cost about
 *    the same for the same error (tests/bench/RESULTS.md).
 *  - "validity": the validity guard (docs/7dof.md §2.6), checked at the output times: 0 off,
 *    1 (default) a warning (sinter_log, SINTER_LOG_WARNING) at the first output past each
 *    limit, 2 SINTER_ERR_DOMAIN there (naming the quantity and the time; later outputs NaN).
 *    Limits: the neck ratio x/min(R_A, R_B) past the impingement ratio of
 *    "validity_coordination" equal necks (their caps cover 0.8 of the sphere), and the
 *    relative density "validity_green_density" / (1 - shrinkage)^3 past 0.8 (seed 001 sec. 4.2)
 *  - "validity_coordination": neighbours of a particle, Z [-]; 6, [0, 100]; 0: no neck check
 *    (Z = 6: x/R = 0.68; 8: 0.60; 12: 0.50)
 *  - "validity_green_density": green density of the packing the pair stands for [-]; 0.6,
 *    [0, 1]; 0: no density check
 */
typedef struct sinter_neck_model sinter_neck_model;

/** Create a neck model with default options. Errors: SINTER_ERR_NULL, SINTER_ERR_NOMEM. */
SINTER_API sinter_status sinter_neck_model_create(sinter_neck_model **out, sinter_ctx *ctx);
/** Destroy a neck model. NULL is allowed. */
SINTER_API void sinter_neck_model_destroy(sinter_neck_model *nm);
/** Set an option (list above). */
SINTER_API sinter_status sinter_neck_model_set(sinter_neck_model *nm, const char *key,
                                               double value);
/** Get an option. */
SINTER_API sinter_status sinter_neck_model_get(const sinter_neck_model *nm, const char *key,
                                               double *value);

/**
 * Two particles of radii radius_a, radius_b [m] (> 0) touching at t0 = times[0], sintered
 * under the piecewise-linear temperature schedule (times[k] [s], strictly increasing;
 * temperatures[k] [K], > 0; n_times >= 1; held constant outside, so n_times = 1 is isothermal).
 * The neck is seeded at t0 as in docs/7dof.md §4. Outputs at the n_out out_times [s]
 * (nondecreasing, each >= t0; may lie beyond the last schedule time):
 *  - neck_radius: x = y1 [m] (divide by min(R_A, R_B) for the neck ratio, docs/7dof.md §5),
 *  - shrinkage: centre approach Delta L / L0 = (L0 - y4 - y7) / L0 with L0 = y4(t0) + y7(t0)
 *    (seed 001 eqs. 11, 13),
 *  - state (may be NULL): the 7 lengths [m] y1..y7 per output time (docs/7dof.md §2.1).
 * All arrays are the caller's (borrowed); outputs are written, NaN for times a failed run did
 * not reach. With n_out = 0 the output pointers may be NULL (nothing is integrated).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (arguments), SINTER_ERR_DOMAIN (the neck left
 * the model's domain of validity, docs/7dof.md §2.5; the message names the quantity and the time),
 * SINTER_ERR_NOT_CONVERGED (CVODE failure or max_steps), SINTER_ERR_UNSTABLE (RK4 left the
 * domain: too few steps), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_neck_two_particles(sinter_neck_model *nm, const sinter_material *m,
                                                   double radius_a, double radius_b,
                                                   size_t n_times, const double *times,
                                                   const double *temperatures, size_t n_out,
                                                   const double *out_times, double *neck_radius,
                                                   double *shrinkage, double *state);

/**
 * Forward sensitivities of the two-particle model (docs/calibration.md §3): the neck ratio
 * x / min(R_A, R_B) [-] and the shrinkage Delta L / L0 [-] of sinter_neck_two_particles (same
 * pair, schedule and seeded neck, the options of nm: epsilon, h0_ratio, rtol, atol,
 * initial_step, max_steps, error_scale; integrator must be 0, CVODE), and their derivatives
 * with respect to n_params (1-16, distinct) parameters of material m:
 *  - a *_DIFFUSION_PREFACTOR or *_DIFFUSION_PREFACTOR_HOT key: the derivative with respect to
 *    ln D0 [-] (per unit of ln D0, i.e. D0 dy/dD0),
 *  - a *_ACTIVATION_ENERGY or *_ACTIVATION_ENERGY_HOT key: the derivative with respect to
 *    Q [J/mol],
 *  - SINTER_MAT_NECK_BOUNDARY_PATH, _CONE_PATH, _CAP_PATH or SINTER_MAT_LATTICE_MOBILE_FRACTION
 *    (docs/7dof.md §3; both phases): the derivative with respect to the natural log of the
 *    value [-] (p dy/dp).
 * The sensitivity equations ds/dt = J s + df/dp are integrated together with the state by
 * CVODE, under the same error control. Outputs at the n_out out_times [s] (nondecreasing, each
 * >= times[0]): neck_ratio[k], shrinkage[k], and d_neck_ratio[k * n_params + j],
 * d_shrinkage[k * n_params + j] for parameter j; NaN for times a failed run did not reach.
 * The validity guard (docs/7dof.md §2.6) is not applied. ctx receives the error messages.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (arguments, a parameter not listed above, a
 * repeated one, integrator = 1), SINTER_ERR_DOMAIN,
 * SINTER_ERR_NOT_CONVERGED, SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_neck_sensitivities(
    sinter_ctx *ctx, const sinter_neck_model *nm, const sinter_material *m, double radius_a,
    double radius_b, size_t n_times, const double *times, const double *temperatures,
    size_t n_params, const sinter_material_param *params, size_t n_out, const double *out_times,
    double *neck_ratio, double *shrinkage, double *d_neck_ratio, double *d_shrinkage);

/** Work of the last sinter_neck_two_particles call (also after a failure). */
typedef struct sinter_neck_stats {
    size_t struct_size;            /**< set to sizeof(sinter_neck_stats) by the caller */
    uint64_t steps;                /**< accepted steps (CVODE or RK4) */
    uint64_t rhs_evaluations;      /**< right-hand side evaluations, including the Jacobian's */
    uint64_t jacobian_evaluations; /**< 7x7 Jacobian evaluations (finite differences) */
    uint64_t error_test_failures;  /**< steps rejected by CVODE's local error test */
    uint64_t nonlinear_iterations; /**< Newton iterations */
    uint64_t nonlinear_failures;   /**< Newton convergence failures */
    uint64_t segments;             /**< smooth pieces of the schedule integrated (CVODE restarts) */
    double seconds;                /**< wall-clock time of the call [s] */
} sinter_neck_stats;

/** Fill `stats` (its struct_size must be set). Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE. */
SINTER_API sinter_status sinter_neck_get_stats(const sinter_neck_model *nm,
                                               sinter_neck_stats *stats);

/**
 * Run a pair file (`sinter pair`; docs/scene-reference.md, "Pair files"): the two-particle model
 * (sinter_neck_two_particles) along the temperature schedule of the CSV file its [pair] section
 * names (a header line, then "time [s], temperature [K]" rows, piecewise linear), for one pair
 * of the given radius or a population of `pairs` pairs whose radii are drawn from a uniform or
 * normal distribution, with the material of a [material NAME] section (in the file or in its
 * `materials` file; [pair] lines naming a material parameter override it). Writes `csv_path`:
 * time [s], temperature [K], the population's mean neck ratio x/min(R_A, R_B) and shrinkage
 * Delta L / L0 with their minimum and maximum over the pairs, the relative density
 * green_density / (1 - shrinkage)^3 of a packing shrinking as the pairs, and past_limit: 0
 * inside the model's domain, +1 where the largest neck ratio passed the impingement limit of
 * the [pair] coordination, +2 where the relative density passed 0.8 (docs/7dof.md §2.6; a
 * warning is logged at the first such time, and with validity = 2 the run stops with
 * SINTER_ERR_DOMAIN). `svg_path` (may be NULL) gets the plot. Errors: SINTER_ERR_NULL,
 * SINTER_ERR_IO, SINTER_ERR_PARSE ("file:line: what was expected"), SINTER_ERR_INVALID, and
 * those of sinter_neck_two_particles.
 */
SINTER_API sinter_status sinter_pair_run(sinter_ctx *ctx, const char *path, const char *csv_path,
                                         const char *svg_path);

/* ------------------------------------------------------------------------ */
/* Solid-state sintering: the quasi-static stepper                           */
/* ------------------------------------------------------------------------ */

/**
 * What the quasi-static stepper (SINTER_STEPPER_QUASISTATIC) reports: every
 * touching pair of particles becomes a bonded beam link (seed 001 eq. 18-40)
 * whose 7DOF neck (docs/7dof.md) is advanced each global step along the furnace's
 * T(t) (sinter_stepper_set_furnace) or, without one, at the particles' mean
 * temperature held over the step; the sintering forces (eq. 17) load the links and K u = f
 * is solved with SUNDIALS PCG, with particles on the principal planes x, y or
 * z = 0 held on them (sec. 3.3); y4 and y7 are corrected as eq. 41-44.
 * Options ("qs_*" keys of sinter_stepper_set_option) are listed in
 * src/stepper/quasistatic.h and take effect if set before the first step. Among them
 * "qs_validity", the validity guard (docs/7dof.md §2.6), checked after every step: 0 off,
 * 1 (default) a warning, 2 SINTER_ERR_DOMAIN naming the quantity and the time, when the necks
 * of a particle cover more than 0.8 of its surface (they impinge) or the relative density
 * passes 0.8 (seed 001 sec. 4.2); each is reported once per run.
 * "qs_neck_stiffness" 1 gives each link the section of its neck, pi x^2, instead of the full
 * pi R_m^2 of eq. 36 (stiffness and sintering force by (x/R_m)^2, bending and torsion by
 * (x/R_m)^4; docs/models.md); 0, the default, keeps the seed's constant section.
 * "qs_neck_law" chooses the pair law that advances the necks: 0 (default) the 7DOF model,
 * 1 the classic grain-boundary diffusion contact law of Bouvard and McMeeking (docs/7dof.md
 * §7.4), 2 a host law (sinter_stepper_set_neck_law, sinter_submodel.h).
 * With periodic axes (sinter_stepper_set_periodic) "qs_cell_strain" 1 (default) shrinks the cell
 * with the links' mean approach, 0 keeps its size; along a periodic axis the shrinkage below is
 * the cell's strain 1 - L/L0 and the relative density is over the cell (docs/steppers.md).
 */
typedef struct sinter_sintering_stats {
    size_t struct_size;      /**< sizeof(sinter_sintering_stats) */
    uint64_t links;          /**< bonded links (necks) */
    double neck_mean;        /**< mean neck radius [m] */
    double neck_min;         /**< [m] */
    double neck_max;         /**< [m] */
    double neck_ratio_mean;  /**< mean neck radius / smaller particle radius [1] */
    double shrinkage[3];     /**< homogeneous strain along x, y, z: minus the least-squares slope
                                  of the displacement against the initial position, over the
                                  particles with links (rattlers excluded) [1] */
    double relative_density; /**< green density (sphere volume / the spheres' bounding box at
                                  the start) over (1 - s_x)(1 - s_y)(1 - s_z) of `shrinkage` [1] */
    double coordination;     /**< 2 links / particles [1] */
    uint64_t pcg_iterations; /**< linear-solver iterations so far */
} sinter_sintering_stats;

/** Fill `stats` (struct_size set) for a quasi-static stepper that has taken a step. With domain
 * operations (sinter_domain.h) a collective call: the statistics of every subdomain. */
SINTER_API sinter_status sinter_stepper_sintering_stats(const sinter_stepper *stepper,
                                                        sinter_sintering_stats *stats);

/* ------------------------------------------------------------------------ */
/* Snapshots: the contacts and links of a state                              */
/* ------------------------------------------------------------------------ */

/**
 * A copy of the contacts (particle-particle, then particle-wall) and of the quasi-static links
 * of a stepper's current state, with what each carries, taken by sinter_snapshot_create. It
 * owns its arrays and stays valid after the stepper moves on or is destroyed. Nothing is
 * recorded while the stepper steps: the snapshot forms every quantity again from the state,
 * the contact lists and the committed history when it is taken, so a run that takes none
 * costs nothing and gives the same bits.
 */
typedef struct sinter_snapshot sinter_snapshot;

/**
 * Per-contact arrays of a snapshot: count = pair contacts + wall contacts, pair contacts
 * first. Values are pinned; new ones are appended.
 */
typedef enum sinter_contact_data {
    SINTER_CONTACT_DATA_ID_A = 0,   /**< persistent id of particle a, 1 uint64 */
    SINTER_CONTACT_DATA_ID_B = 1,   /**< id of particle b; UINT64_MAX for a wall contact, 1 uint64 */
    SINTER_CONTACT_DATA_WALL = 2,   /**< wall index, -1 for a particle pair, 1 int32 */
    SINTER_CONTACT_DATA_NORMAL = 3, /**< unit normal from a towards b (towards the wall) [-], 3 doubles */
    SINTER_CONTACT_DATA_OVERLAP = 4, /**< overlap delta = r_a + r_b - d, or r_a - distance to the plane [m] */
    SINTER_CONTACT_DATA_RADIUS = 5, /**< contact radius a = sqrt(A / pi) [m] */
    SINTER_CONTACT_DATA_AREA = 6,   /**< contact area A (seed 000 eq. 11, seed 003 eq. 34) [m^2] */
    SINTER_CONTACT_DATA_NORMAL_FORCE = 7, /**< normal force, > 0 compressive: -F_a . n [N] */
    SINTER_CONTACT_DATA_TANGENTIAL_FORCE = 8, /**< tangential part of F_a, the contact force on a [N], 3 doubles */
    SINTER_CONTACT_DATA_HEAT_FLOW = 9, /**< conductive heat flow into a from b or the wall [W] (-Q for b) */
    SINTER_CONTACT_DATA_CURRENT = 10, /**< electric current from a to b or the wall [A]; NaN where the
                                      electric model defines no contact current ("averaged") */
    SINTER_CONTACT_DATA_COUNT_ = 11 /**< number of quantities in this version (not one) */
} sinter_contact_data;

/** Per-link arrays of a snapshot (quasi-static stepper). Values are pinned; new ones are appended. */
typedef enum sinter_link_data {
    SINTER_LINK_DATA_ID_A = 0,        /**< persistent id of particle A, 1 uint64 */
    SINTER_LINK_DATA_ID_B = 1,        /**< persistent id of particle B, 1 uint64 */
    SINTER_LINK_DATA_NECK_RADIUS = 2, /**< neck radius x = y1 (docs/7dof.md) [m] */
    SINTER_LINK_DATA_NECK_RATIO = 3,  /**< x / min(r_A, r_B), the smaller particle radius (as neck_ratio_mean) [-] */
    SINTER_LINK_DATA_APPROACH = 4,    /**< centre approach L0 - (y4 + y7) (seed 001 eq. 11, 13) [m] */
    SINTER_LINK_DATA_AGE = 5,         /**< time of the neck state minus the time the link was
                                      made [s] (0 for the links of the first step) */
    SINTER_LINK_DATA_PHASE = 6,       /**< neck phase at the pair's mean temperature (0, 1 hot), 1 int32 */
    SINTER_LINK_DATA_SINTERING_FORCE = 7, /**< sintering force of the last step, seed 001 eq. 17, > 0
                                          pulls the pair together [N] */
    SINTER_LINK_DATA_BEAM_FORCE = 8,  /**< link force K_F eps of the last step's solve (seed 001 eq. 32-34a,
                                      the increment of that step, global components) [N], 3 doubles;
                                      NaN before a step of this run (after a restart) */
    SINTER_LINK_DATA_BEAM_MOMENT = 9, /**< link moment K_M gamma of that solve (eq. 34b) [N m], 3 doubles */
    SINTER_LINK_DATA_CORRECTION = 10, /**< seed 001 eq. 44 of the last step: the corrected minus the
                                      7DOF model's change of the centre distance, dy4 + dy7 - xi
                                      (eq. 41, 43) [m]; NaN before a step of this run */
    SINTER_LINK_DATA_COUNT_ = 11 /**< number of quantities in this version (not one) */
} sinter_link_data;

/**
 * Take a snapshot of the stepper's current state. Valid from the moment a step or an advance
 * returned (successfully or not: the state is then the last accepted one) until the particles
 * are written, added, removed or sorted, or the stepper steps again; before the first step
 * and after such a change it is refused with SINTER_ERR_STATE (call sinter_stepper_step with
 * n = 0 or sinter_stepper_advance to the current time, which evaluate the state). The stepper
 * is not changed.
 *
 * Contact forces are those of the stepper's force models with contacts, evaluated again on the
 * state: the tangential springs are the committed ones, and for the explicit stepper the
 * velocities those its last evaluation saw (half a step back, v - h F / 2 m), so that they sum
 * to the wall reactions (sinter_walls_get_force) and the particles' forces to round-off. Heat
 * flows are those of the conduction models, currents those of a "network" electric model. A
 * quasi-static stepper has no contacts, only links.
 * @param out      receives the snapshot (owned: sinter_snapshot_destroy).
 * @param stepper  borrowed, not changed.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STATE, SINTER_ERR_NOMEM, and the errors of the models.
 */
SINTER_API sinter_status sinter_snapshot_create(sinter_snapshot **out,
                                                const sinter_stepper *stepper);
/** Destroy a snapshot (NULL is allowed); the arrays it lent become invalid. */
SINTER_API void sinter_snapshot_destroy(sinter_snapshot *snapshot);
/**
 * Sizes of a snapshot: particle-particle contacts, particle-wall contacts and links (any
 * pointer may be NULL), and the stepper's time when it was taken [s] (may be NULL).
 * Errors: SINTER_ERR_NULL.
 */
SINTER_API sinter_status sinter_snapshot_counts(const sinter_snapshot *snapshot,
                                                size_t *pair_contacts, size_t *wall_contacts,
                                                size_t *links, double *time);
/**
 * Borrow one per-contact array (valid until the snapshot is destroyed; read-only): count
 * records (pair contacts then wall contacts) of `components` elements of type `dtype`,
 * record-major. Any of count, components, dtype may be NULL; *data is NULL when count is 0.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE (unknown quantity).
 */
SINTER_API sinter_status sinter_snapshot_contacts(const sinter_snapshot *snapshot,
                                                  sinter_contact_data quantity,
                                                  const void **data, size_t *count,
                                                  size_t *components, sinter_dtype *dtype);
/** Borrow one per-link array, as sinter_snapshot_contacts. Errors: as there. */
SINTER_API sinter_status sinter_snapshot_links(const sinter_snapshot *snapshot,
                                               sinter_link_data quantity, const void **data,
                                               size_t *count, size_t *components,
                                               sinter_dtype *dtype);

/* ------------------------------------------------------------------------ */
/* Coarse-grained fields: density, temperature, velocity and stress on a grid */
/* ------------------------------------------------------------------------ */

/**
 * Quantities of sinter_coarse_grain (Goldhirsch 2010; Weinhart et al. 2012, docs/models.md).
 * Values are pinned; new ones are appended.
 */
typedef enum sinter_coarse_quantity {
    SINTER_COARSE_SOLID_FRACTION = 0, /**< sum of V_i W(r - r_i), V_i = 4/3 pi r_i^3 (overlaps
                                           counted in both spheres) [1], 1 double */
    SINTER_COARSE_DENSITY = 1,        /**< mass density rho = sum m_i W(r - r_i) [kg/m^3] */
    SINTER_COARSE_TEMPERATURE = 2,    /**< mass-weighted temperature sum m_i T_i W / rho [K]; NaN
                                           where rho = 0 */
    SINTER_COARSE_VELOCITY = 3,       /**< momentum density over rho [m/s], 3 doubles; 0 where
                                           rho = 0 */
    SINTER_COARSE_STRESS = 4,         /**< Cauchy stress, tension positive [Pa], 9 doubles (xx xy
                                           xz yx ... zz): kinetic part plus the contacts of the
                                           snapshot, pairs along their branch line and wall
                                           contacts from the centre to the contact point */
    SINTER_COARSE_COUNT_ = 5          /**< number of quantities in this version (not one) */
} sinter_coarse_quantity;

/** A regular grid and a kernel; fill with sinter_coarse_options_init. */
typedef struct sinter_coarse_options {
    size_t struct_size; /**< sizeof(sinter_coarse_options) */
    double origin[3];   /**< the first grid point [m] */
    double spacing[3];  /**< distance between grid points along x, y, z [m], > 0 */
    size_t points[3];   /**< grid points along x, y, z, >= 1 (x runs fastest in the output) */
    double width;       /**< kernel width w: the Gaussian's standard deviation [m], > 0 */
    double cutoff;      /**< the kernel is cut at cutoff * w and normalised over its support
                             (1 to 10, default 3) [1] */
} sinter_coarse_options;

/** Defaults: origin 0, spacing 1 mm, 1 x 1 x 1 points, width 1 mm, cutoff 3.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE. */
SINTER_API sinter_status sinter_coarse_options_init(sinter_coarse_options *options,
                                                    size_t struct_size);

/** Components of a quantity (1, 3 or 9), its name ("solid_fraction") and unit; any may be NULL.
 * Errors: SINTER_ERR_RANGE. */
SINTER_API sinter_status sinter_coarse_quantity_info(sinter_coarse_quantity quantity,
                                                     const char **name, const char **unit,
                                                     size_t *components);

/**
 * One coarse-grained quantity at every grid point: out[(i + nx (j + ny k)) * components + c]
 * for the point origin + (i, j, k) * spacing. Each particle is smeared by a Gaussian kernel of
 * width w cut at cutoff * w; so the integral of the density over space is the particles' mass,
 * and on a grid finer than w its sum times the cell volume is too, away from the grid's edges.
 * @param snapshot  contacts for the stress (sinter_snapshot_create on a stepper of `ps`); NULL:
 *                  the kinetic stress only. Ignored by the other quantities. Links carry no
 *                  total force and add nothing.
 * @param out_count  number of doubles at out: points * components.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (options, out_count, a snapshot of other
 * particles), SINTER_ERR_RANGE (quantity), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_coarse_grain(const sinter_particles *ps,
                                             const sinter_snapshot *snapshot,
                                             const sinter_coarse_options *options,
                                             sinter_coarse_quantity quantity, double *out,
                                             size_t out_count);

/**
 * The relative density of laminae (seed 001 eq. 48, Fig. 10): the box lo..hi cut along `axis`
 * (0 x, 1 y, 2 z) into `count` equal laminae; lamina s has fraction[s] = the volume of the
 * spheres' slices between its two planes over its volume, and temperature[s] the
 * slice-volume-weighted mean temperature (NaN where no sphere reaches it). Slices are whole
 * across the other two axes (the box should hold the packing's cross-section) and overlaps
 * count in both spheres, as the paper's measure. Either output may be NULL.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (axis, count 0, lo >= hi).
 */
SINTER_API sinter_status sinter_lamina_profile(const sinter_particles *ps, int axis,
                                               const double lo[3], const double hi[3],
                                               size_t count, double *fraction,
                                               double *temperature);

/* ------------------------------------------------------------------------ */
/* Packing helpers                                                           */
/* ------------------------------------------------------------------------ */

/** Radius distributions of the packing helpers. */
typedef enum sinter_radius_distribution {
    SINTER_RADII_MONODISPERSE = 0, /**< every radius = mean */
    SINTER_RADII_UNIFORM = 1,      /**< uniform in [mean - spread, mean + spread] */
    SINTER_RADII_NORMAL = 2,       /**< normal(mean, spread) truncated to [min, max] by rejection */
    SINTER_RADII_LOGNORMAL = 3,    /**< ln r normal: number median radius_median, geometric
                                        standard deviation radius_gsd, truncated to [min, max] */
    SINTER_RADII_TABLE = 4         /**< a tabulated cumulative distribution of diameters
                                        (table_*), by number or by volume; see sinter_pack_random */
} sinter_radius_distribution;

/** What the cumulative fraction of a size distribution counts. */
typedef enum sinter_size_basis {
    SINTER_SIZE_BY_NUMBER = 0, /**< the fraction of the particles (Q0) */
    SINTER_SIZE_BY_VOLUME = 1  /**< the fraction of the particle volume (Q3; mass for one density) */
} sinter_size_basis;

/** Options of sinter_pack_random; fill with sinter_packing_options_init. */
typedef struct sinter_packing_options {
    size_t struct_size;          /**< sizeof(sinter_packing_options) */
    double box_min[3];           /**< lower corner of the box the spheres must lie in [m] */
    double box_max[3];           /**< upper corner [m] */
    int distribution;            /**< a sinter_radius_distribution */
    double radius_mean;          /**< [m] */
    double radius_spread;        /**< half-width (uniform) or standard deviation (normal) [m] */
    double radius_min;           /**< truncation of the normal distribution [m] (0: mean - 3 spread, floored at mean/10) */
    double radius_max;           /**< [m] (0: mean + 3 spread) */
    double gap;                  /**< smallest surface gap between spheres and to the box [m] */
    uint64_t seed;               /**< random seed (same seed, same packing on every machine) */
    uint64_t max_attempts;       /**< attempts per sphere before giving up (default 100000) */
    int32_t material;            /**< material id of the new particles */
    double temperature;          /**< initial temperature [K] */
    /* Appended in 0.x (issue 38). A caller compiled with the layout that ended at temperature
     * passes that struct_size and gets the defaults below for the rest. */
    double radius_median;        /**< lognormal: number median radius [m] (default 0.05) */
    double radius_gsd;           /**< lognormal: geometric standard deviation exp(sd of ln r),
                                      >= 1 [1] (default 1); truncation as radius_min/max, 0:
                                      median / gsd^3 and median gsd^3 */
    const double *table_diameter;   /**< table: table_points diameters [m], positive and strictly
                                         increasing (borrowed for the call) */
    const double *table_cumulative; /**< table: cumulative fraction at each diameter, >= 0,
                                         non-decreasing, the last 1 within 1 % (the values
                                         are divided by it) */
    size_t table_points;         /**< table: number of rows (>= 1) */
    int table_basis;             /**< table: a sinter_size_basis (default by volume) */
    size_t mixture_count;        /**< 0 (default): every particle is of `material`; else the
                                      number of materials in the mixture */
    const int32_t *mixture_materials;     /**< mixture: material ids (borrowed) */
    const double *mixture_mass_fractions; /**< mixture: mass fractions, positive, sum 1 within
                                               1e-6 (then divided by their sum) */
    /* Appended in 0.x (issue 38, a size distribution per material); the layout that ended at
     * mixture_mass_fractions is still served (struct_size = offsetof(.., mixture_sizes)). */
    const struct sinter_packing_options *mixture_sizes; /**< mixture: NULL (default): every
                                      material draws its radii from this struct's distribution;
                                      else mixture_count options (each filled by
                                      sinter_packing_options_init) whose size fields
                                      (distribution, radius_*, table_*) give material k its own
                                      distribution; their other fields are ignored (borrowed) */
} sinter_packing_options;

/** Fill `options` with defaults: unit box, monodisperse r = 0.05 m, seed 1, 293.15 K.
 * struct_size: sizeof(sinter_packing_options), or offsetof(sinter_packing_options,
 * radius_median) for the layout before issue 38, or offsetof(sinter_packing_options,
 * mixture_sizes) for the layout before the sizes per material. */
SINTER_API sinter_status sinter_packing_options_init(sinter_packing_options *options,
                                                     size_t struct_size);

/**
 * Random sequential addition (seed 000 sec. 7.1, remark 2): place up to n
 * spheres one by one at uniformly random positions inside the box, each
 * accepted only if it overlaps no sphere already in the set. Stops early when
 * max_attempts fail in a row; *placed (may be NULL) receives the number added.
 *
 * Radii (docs/models.md, "Powder size distributions"): SINTER_RADII_LOGNORMAL draws
 * r = radius_median exp(z ln radius_gsd), z standard normal, redrawn outside [radius_min,
 * radius_max]. SINTER_RADII_TABLE reads the cumulative distribution Q(d) of diameters as
 * piecewise linear between the rows; the first row's fraction is a point mass at the smallest
 * diameter (nothing is smaller). A table by volume is converted to numbers before sampling:
 * the number density is the volume density divided by d^3 (q0 ~ q3 / d^3, ISO 9276-2), exact
 * for the piecewise-linear Q3; radius_min/max are ignored. A mixture chooses each placed
 * particle's material greedily, the one furthest below its mass share, so that each
 * material's mass exceeds its share of the total by at most one particle's mass (and, for two
 * materials, falls short by at most one particle's mass). With mixture_sizes each particle's
 * material is chosen by that rule before its radius is drawn from the material's own
 * distribution (the same bound, with the largest particle of any material). The random
 * stream of the first three distributions is that of earlier versions (a mixture draws no
 * random numbers of its own).
 * Errors: SINTER_ERR_INVALID for an empty box or bad radii, tables or fractions;
 * SINTER_ERR_NOT_FOUND for an unregistered material; the set is unchanged on error.
 */
SINTER_API sinter_status sinter_pack_random(sinter_particles *particles,
                                            const sinter_packing_options *options, size_t n,
                                            size_t *placed);

/**
 * Size quantiles of particles first .. first + count - 1: diameters[k] is the smallest
 * particle diameter d (2 r) at which the cumulative fraction by `basis` (a sinter_size_basis:
 * the count, or the volume d^3) of the particles with diameter <= d reaches fractions[k]
 * (the inverse of the empirical distribution). With fractions 0.1, 0.5, 0.9 these are D10,
 * D50 and D90 [m].
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (an empty or out-of-range particle range, a
 * fraction outside [0, 1], a bad basis), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_particles_size_quantiles(const sinter_particles *particles,
                                                         size_t first, size_t count, int basis,
                                                         size_t nfractions,
                                                         const double *fractions,
                                                         double *diameters);

/**
 * Read a cumulative size distribution (sieve or laser-diffraction data) from a CSV file:
 * one row "diameter, cumulative" a line (separated by a comma, semicolon, tab or spaces);
 * blank lines and '#' comments skipped; a first line that is not two numbers is a header.
 * Diameters are multiplied by `unit` (1e-6 for micrometres) to give metres; the cumulative
 * values are fractions, or percent when `percent` is 1. The table is refused (SINTER_ERR_PARSE
 * "path:line: ...") when a diameter is not positive or not larger than the one above, a
 * cumulative value is negative or smaller than the one above, or the last one is not 1 (100 %)
 * within 1 % of it; within that tolerance the values are divided by the last one, so the
 * table ends at exactly 1. With capacity 0 only *count is set (the number of rows); otherwise
 * the rows go to diameter[] [m] and cumulative[] (SINTER_ERR_INVALID when more rows than
 * capacity). Other errors: SINTER_ERR_NULL, SINTER_ERR_IO, SINTER_ERR_INVALID (bad unit, an
 * empty table).
 */
SINTER_API sinter_status sinter_psd_read_csv(sinter_ctx *ctx, const char *path, double unit,
                                             int percent, double *diameter, double *cumulative,
                                             size_t capacity, size_t *count);

/**
 * Simple-cubic lattice of spheres of radius r with centre spacing `spacing`
 * (>= 2 r) filling the box from its lower corner; *placed receives the count.
 */
SINTER_API sinter_status sinter_pack_lattice(sinter_particles *particles, const double box_min[3],
                                             const double box_max[3], double radius,
                                             double spacing, int32_t material, double temperature,
                                             size_t *placed);

/**
 * Pour: advance `stepper` (which should include gravity) until the total
 * kinetic energy per particle falls below `ke_per_particle` [J] after at least
 * t_min [s], or until t_max [s] of simulated time has passed
 * (SINTER_ERR_NOT_CONVERGED then, with the state kept).
 */
SINTER_API sinter_status sinter_pack_pour(sinter_stepper *stepper, double ke_per_particle,
                                          double t_min, double t_max);

/** Regions of the continuous insertion (sinter_stepper_set_insertion). */
typedef enum sinter_insertion_region {
    SINTER_INSERT_BOX = 0,     /**< the powder's box (box_min, box_max) */
    SINTER_INSERT_CYLINDER = 1 /**< the cylinder inscribed in that box along z: axis through the
                                    box's centre, radius half the smaller of its x and y widths */
} sinter_insertion_region;

/** Options of the continuous insertion; fill with sinter_insertion_options_init. */
typedef struct sinter_insertion_options {
    size_t struct_size;  /**< sizeof(sinter_insertion_options) */
    int region;          /**< a sinter_insertion_region (default box) */
    double mass_rate;    /**< target mass flow [kg/s], > 0 (default 1e-3) */
    double start;        /**< time of the first insertion [s] (default 0) */
    double end;          /**< no insertion at or after this time [s] (default HUGE_VAL) */
    double interval;     /**< time between insertions [s], > 0 (default 1e-3) */
    double velocity[3];  /**< initial velocity of every inserted particle [m/s] (default 0) */
} sinter_insertion_options;

/** Fill `options` with the defaults above; struct_size: sizeof(sinter_insertion_options). */
SINTER_API sinter_status sinter_insertion_options_init(sinter_insertion_options *options,
                                                       size_t struct_size);

/**
 * Continuous insertion (a stage at the start of each explicit step): at the times start + k
 * interval before `end`, the first step at or after each inserts spheres of the powder's size
 * distribution until the mass inserted since `start` is within one particle's mass of
 * mass_rate (k + 1) interval (capped at mass_rate (end - start)): the mass of each interval is
 * inserted at its beginning, and no more than the target is inserted. Each sphere goes to a
 * uniformly random place in the region (options->region over powder->box_min, box_max, with
 * powder->gap to the region's faces) where it overlaps no particle and no wall (a surface gap
 * of at least powder->gap to both), tried at most powder->max_attempts times; a sphere that
 * finds no room waits for the next insertion (the shortfall is in
 * sinter_stepper_get_insertion). `powder` gives the size distribution (every
 * sinter_radius_distribution; a table is copied), the material, the temperature, the seed and
 * the gap. A mixture (mixture_count > 0, with or without mixture_sizes) chooses each sphere's
 * material as sinter_pack_random does, before its radius is drawn, from the masses inserted
 * so far: each material's inserted mass stays within one particle's mass of its share
 * (sinter_stepper_get_insertion_mixture reports them). The inserted spheres move at
 * options->velocity, without spin;
 * their forces are evaluated at once, and the step's stability check (sinter_stable_dt_hertz)
 * then covers them. One random stream (powder->seed) gives radii and places in order, so a run
 * inserts the same spheres on every machine and any thread count. A later call replaces the
 * insertion; powder = NULL removes it. A checkpoint carries its state (format 13): set the same
 * insertion before sinter_checkpoint_read, and the run continues bit for bit. Only the
 * explicit stepper inserts (SINTER_ERR_STATE for another kind).
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_INVALID (a bad option, a region
 * narrower than the largest sphere, mass fractions not positive or not summing to 1),
 * SINTER_ERR_NOT_FOUND (an unregistered material).
 */
SINTER_API sinter_status sinter_stepper_set_insertion(sinter_stepper *stepper,
                                                      const sinter_packing_options *powder,
                                                      const sinter_insertion_options *options);

/**
 * What the insertion did so far: the mass inserted [kg], the target mass for the insertions
 * made so far [kg] (mass_rate times the time they cover), the spheres inserted, and the
 * insertions that ended with a sphere finding no room. Any pointer may be NULL; all are 0
 * without an insertion.
 */
SINTER_API sinter_status sinter_stepper_get_insertion(const sinter_stepper *stepper,
                                                      double *mass_inserted, double *mass_target,
                                                      uint64_t *inserted, uint64_t *crowded);

/**
 * The mass inserted so far of each material of the insertion's mixture [kg], in the order of
 * powder->mixture_materials: mass[k] for k < capacity; *count (may be NULL) receives the number
 * of materials (0 without a mixture or without an insertion, 1 entry then not written).
 * Errors: SINTER_ERR_NULL (stepper, or mass with capacity > 0).
 */
SINTER_API sinter_status sinter_stepper_get_insertion_mixture(const sinter_stepper *stepper,
                                                              double *mass, size_t capacity,
                                                              size_t *count);

/** Options of sinter_pack_compact; fill with sinter_compaction_options_init. */
typedef struct sinter_compaction_options {
    size_t struct_size;      /**< sizeof(sinter_compaction_options) */
    double box_min[3];       /**< lower corner of the final box [m] (default 0 0 0) */
    double box_max[3];       /**< upper corner of the final box [m] (default 1 1 1) */
    double volume_fraction;  /**< 0 (default): the final box is box_min..box_max; in (0, 0.7405]:
                                  that box is scaled about box_min, keeping its proportions, so
                                  that the spheres fill this fraction of it [1] */
    double friction;         /**< particle-particle friction coefficient during the compaction,
                                  static = dynamic (walls are frictionless); default 0.1 [1] */
    double restitution;      /**< restitution of the contacts during the compaction, (0, 1];
                                  default 0.5 [1] */
    double velocity;         /**< largest wall speed [m/s]; default 0.5 */
    double max_pressure;     /**< mean wall stress at which the walls stop advancing [Pa]; 0
                                  (default): the stress of a packing whose contacts overlap by
                                  1e-3 of the mean radius */
    int stop_at_jamming;     /**< 1: if the packing jams before the final box, end there (the
                                  final box is the box at jamming); 0 (default): that is an error */
    double ke_per_particle;  /**< the relaxation ends when the translational kinetic energy per
                                  particle is below this [J]; 0 (default): 1e-9 of (1/2) m v^2
                                  of a particle of mean mass at the impact speed of the step */
    double relax_time_max;   /**< longest relaxation [s]; 0 (default): 5e4 automatic steps */
    double dt;               /**< time step [s]; 0 (default): seed 003 eq. 47 (see sinter_pack_compact) */
} sinter_compaction_options;

/** What sinter_pack_compact achieved; fill struct_size before the call. */
typedef struct sinter_compaction_result {
    size_t struct_size;       /**< sizeof(sinter_compaction_result) */
    double box_min[3];        /**< the final box [m] */
    double box_max[3];        /**< [m] */
    double volume_fraction;   /**< sphere volume / final box volume [1] */
    int jammed;               /**< 1 if the walls stopped at jamming before the requested box */
    double coordination;      /**< particle-particle contacts per particle, 2 C / N [1] */
    uint64_t contacts;        /**< particle-particle contacts C at the end */
    double max_overlap;       /**< largest overlap of two particles [m] */
    double max_overlap_ratio; /**< largest overlap / smaller radius of the pair [1] */
    double max_wall_overlap_ratio; /**< largest overlap of a particle and a wall / its radius [1] */
    double pressure;          /**< mean normal stress on the six walls at the end [Pa] */
    double kinetic_energy;    /**< translational kinetic energy per particle before the
                                   velocities are zeroed [J] */
    double time;              /**< simulated time, motion and relaxation [s] */
    double relax_time;        /**< of which relaxation [s] */
    double dt;                /**< time step used [s] */
    uint64_t steps;           /**< steps taken */
} sinter_compaction_result;

/**
 * Fill `options` with defaults: final box [0, 1]^3 m, no volume fraction, friction 0.1,
 * restitution 0.5, wall speed 0.5 m/s, automatic stress limit, rest threshold, relaxation and
 * step. Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE.
 */
SINTER_API sinter_status sinter_compaction_options_init(sinter_compaction_options *options,
                                                        size_t struct_size);

/**
 * Triaxial compaction to a dense green body (seed 001 sec. 3.2): six frictionless plane walls
 * start on the bounding box of the spheres and move together along straight lines onto the
 * final box, all arriving at the same time (a proportional compression of the three axes),
 * then stay there while the packing relaxes until its translational kinetic energy per
 * particle is below ke_per_particle. The walls move at `velocity` (the fastest one) slowed
 * down in proportion as the mean wall stress approaches max_pressure, and wait while it is
 * above: the packing is compacted quasi-statically and ends nearly stress-free. When it jams
 * before the final box (the walls make no progress for 5000 automatic steps) the call fails
 * with SINTER_ERR_NOT_CONVERGED naming the volume fraction reached, or, with stop_at_jamming,
 * ends there: the final box is then the walls' box at that moment (on the way from the
 * spheres' box to the requested one, so of the requested proportions when the spheres start
 * in a box of those proportions), translated with the packing so that it starts at box_min. The compaction is an explicit DEM run of its own (velocity Verlet, Hertz
 * contacts with Mindlin friction of coefficient `friction`, damping for `restitution`, no
 * gravity, a background drag with a time constant of 100 contact durations so that loose
 * particles come to rest too) on a copy of the set; only its end state is written back:
 * positions, with velocities, spins, forces and torques zeroed (a stepper over the set
 * evaluates its forces again). Particles start at rest; flags (fixed particles) and thermal
 * softening are ignored; masses, radii and the materials' elastic constants are used as they
 * are. The time step is seed 003 eq. 47 (sinter_stable_dt_hertz) at the impact speed that
 * gives an overlap of 1 % of the radius in a Hertz collision (at least the wall speed); with
 * friction of 0.3 and more, sticking contacts couple tangential springs and spins in a faster
 * mode and a jammed packing may not come to rest: set dt to half of that step.
 * Friction sets how dense the packing gets before it jams: with friction 0 the spheres reach
 * the random close packing (about 0.64 away from the walls), with 0.1 a box fraction of about
 * 0.59 for 10-diameter boxes, with 0.5 and more they jam near the random loose packing. A final
 * box below the jamming density leaves a loose packing (see coordination in the result).
 * @param particles  the set (at least one particle, no views out).
 * @param options    required; every value is checked first.
 * @param result     may be NULL; its struct_size must be set.
 * Errors (the set is unchanged on every error): SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE,
 * SINTER_ERR_BUSY, SINTER_ERR_STATE (empty set), SINTER_ERR_INVALID (a bad option, named with
 * its value; a box not wider than the largest sphere or denser than the densest packing,
 * 0.7405; a run of more than 1e9 steps), SINTER_ERR_NOT_CONVERGED (jammed before the final
 * box, or not at rest after relax_time_max), SINTER_ERR_UNSTABLE, SINTER_ERR_LOST_PARTICLE
 * (dt far too large), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_pack_compact(sinter_particles *particles,
                                             const sinter_compaction_options *options,
                                             sinter_compaction_result *result);


/* ------------------------------------------------------------------------ */
/* Output: ParaView frames, time series, plots                               */
/* ------------------------------------------------------------------------ */

/** An extra per-particle array written into a VTU frame (borrowed). */
typedef struct sinter_vtu_array {
    const char *name;   /**< array name shown in ParaView */
    const double *data; /**< count * components values, particle-major */
    size_t components;  /**< 1 or 3 */
} sinter_vtu_array;

/**
 * Write the particle set as one VTK XML UnstructuredGrid frame (.vtu, one
 * vertex per particle) with point arrays radius, velocity, spin, temperature,
 * current, force, material and id, plus the `extra` arrays (e.g. contact and
 * neck counts). The file is written to a temporary name and renamed, so an
 * existing file is never left half-written.
 */
SINTER_API sinter_status sinter_write_vtu(const sinter_particles *particles, const char *path,
                                          const sinter_vtu_array *extra, size_t extra_count);

/**
 * Write a ParaView collection (.pvd) listing `count` frames: files[k] (paths
 * as they should appear in the .pvd, usually relative to it) at times[k] [s].
 */
SINTER_API sinter_status sinter_write_pvd(sinter_ctx *ctx, const char *path, size_t count,
                                          const double *times, const char *const *files);

/** A time series of named, unit-carrying columns, written as CSV and drawn as SVG. */
typedef struct sinter_series sinter_series;

/** Create a series with `columns` columns; names and units are copied. */
SINTER_API sinter_status sinter_series_create(sinter_series **out, sinter_ctx *ctx, size_t columns,
                                              const char *const *names, const char *const *units);
/** Destroy a series (NULL is allowed). */
SINTER_API void sinter_series_destroy(sinter_series *series);
/** Append one row of `columns` values (NaN is allowed and written as "nan"). */
SINTER_API sinter_status sinter_series_append(sinter_series *series, const double *row);
/** Number of rows. */
SINTER_API sinter_status sinter_series_rows(const sinter_series *series, size_t *rows);
/** Read value (row, column). */
SINTER_API sinter_status sinter_series_get(const sinter_series *series, size_t row, size_t column,
                                           double *value);
/**
 * Read a series back from a CSV file written by sinter_series_write_csv or by
 * a run: names and units from the header, every complete row (a last line
 * without its newline is left out). Errors: SINTER_ERR_NULL, SINTER_ERR_IO,
 * SINTER_ERR_PARSE ("file:line: what was expected"), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_series_read_csv(sinter_series **out, sinter_ctx *ctx,
                                                const char *path);
/** Write as CSV: a header line "name [unit],..." then one line per row, full precision. */
SINTER_API sinter_status sinter_series_write_csv(const sinter_series *series, const char *path);
/**
 * Draw an SVG plot with one panel per entry of `panels`: panel k plots the
 * columns panel_columns[panel_start[k] .. panel_start[k+1]) against column
 * `x_column`, with axes, ticks, labels (name and unit) and a legend.
 * `panel_start` has panels + 1 entries. `title` may be NULL.
 */
SINTER_API sinter_status sinter_series_write_svg(const sinter_series *series, const char *path,
                                                 const char *title, size_t x_column, size_t panels,
                                                 const size_t *panel_start,
                                                 const size_t *panel_columns);


/* ------------------------------------------------------------------------ */
/* Scenes                                                                    */
/* ------------------------------------------------------------------------ */

/**
 * A scene read from a scene file: materials, particles, walls, submodels, the
 * stepper and the output schedule (see examples/scenes/README.md for the
 * format). The scene owns every object it creates.
 */
typedef struct sinter_scene sinter_scene;

/**
 * Read, validate and build a scene. Errors: SINTER_ERR_IO (cannot read),
 * SINTER_ERR_PARSE (with "file:line: what was expected" in the message), and
 * the errors of the objects the scene builds.
 */
SINTER_API sinter_status sinter_scene_load(sinter_scene **out, sinter_ctx *ctx, const char *path);
/** Destroy a scene and every object it built (NULL is allowed). */
SINTER_API void sinter_scene_destroy(sinter_scene *scene);

/**
 * Progress callback of sinter_scene_run, called after every sample: time reached and the
 * run's end time [s] (after a pour, the pour's end plus the scene's end time). Non-zero stops
 * the run as sinter_ctx_request_stop does.
 */
typedef int (*sinter_progress_fn)(double time, double end_time, void *user);

/**
 * Run the scene from where it stands to its end time, writing into `out_dir`
 * (created if missing) as the scene's [output] section asks: series.csv (each
 * sample appended and flushed as the run goes, so that a crash loses at most
 * the sample being written), VTU frames in frames/ with the PVD collection
 * rewritten after every frame, checkpoint.bin at the checkpoint interval and
 * at the end, and series.svg, drawn from series.csv at the end, whatever
 * ended the run. `out_dir` is made and checked writable before the first step.
 *
 * A fresh scene first does its set-up (compaction, the first sample, the pour
 * to rest); a scene restored with sinter_scene_restart continues its program
 * without repeating any of it, appending to the series.csv and frames of
 * `out_dir` where they hold the samples written before the checkpoint (else
 * starting them at the restart). A stop request (sinter_ctx_request_stop) or a
 * progress callback returning non-zero ends the run after the current step
 * with SINTER_ERR_INTERRUPTED, writing checkpoint.bin (even without a
 * checkpoint interval) and the plot. `progress` may be NULL.
 */
SINTER_API sinter_status sinter_scene_run(sinter_scene *scene, const char *out_dir,
                                          sinter_progress_fn progress, void *user);

/**
 * Write the scene's checkpoint: the stepper's state (sinter_checkpoint_write)
 * and the scene's program (its phase, the time origin its pour fixed, the
 * output schedule, the samples and frames written), so that
 * sinter_scene_restart continues the run exactly. sinter_scene_run writes
 * these itself. Errors: SINTER_ERR_NULL, SINTER_ERR_STATE (the run has not
 * started), SINTER_ERR_IO, SINTER_ERR_INVALID (a path too long).
 */
SINTER_API sinter_status sinter_scene_checkpoint_write(const sinter_scene *scene, const char *path);

/**
 * Restore a scene loaded from its scene file to a checkpoint written by its
 * run; the next sinter_scene_run continues the run as the straight run would
 * have gone on, bit for bit. A checkpoint of another scene (other particle
 * count, stepper kind, walls or their order, materials, heat or electric
 * models) is refused with SINTER_ERR_INVALID naming the first difference, a
 * stepper checkpoint without a scene program likewise; a path that is a
 * directory or not a regular file with SINTER_ERR_INVALID, an empty, truncated
 * or corrupted file with SINTER_ERR_CORRUPT; nothing is changed then. A scene
 * file edited since the run: the explicit stepper's time step and the [output]
 * interval and checkpoint_interval are the scene's (the next sample comes the
 * new interval after the last one written), each change logged as a warning
 * (the run then no longer repeats the straight run); the adaptive steppers
 * keep the checkpoint's current step and material parameters are the
 * checkpoint's, named at the info log level. The end time stays the scene's
 * (sinter_scene_set_end_time).
 */
SINTER_API sinter_status sinter_scene_restart(sinter_scene *scene, const char *path);

/**
 * Change the scene's end time [s] (its [stepper] end_time: after a pour,
 * counted from the pour's end), also after a restart, to run a scene shorter
 * or longer. Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (not positive and
 * finite).
 */
SINTER_API sinter_status sinter_scene_set_end_time(sinter_scene *scene, double end_time);

/**
 * Draw `out_dir`/series.svg from `out_dir`/series.csv, as a run does at its
 * end, for any run, finished or not (a last line without its newline is left
 * out). `title` may be NULL. Errors: SINTER_ERR_NULL, SINTER_ERR_IO,
 * SINTER_ERR_PARSE (naming the line), SINTER_ERR_STATE (no sample yet).
 */
SINTER_API sinter_status sinter_plot_run(sinter_ctx *ctx, const char *out_dir, const char *title);

/**
 * Draw chosen columns of any CSV file a run writes (series.csv, a lamina profile
 * frames/profile_z_NNNNN.csv, ...) into the SVG file `svg_path`: panel k draws the columns
 * named in panels[k], a comma-separated list ("max temperature,mean temperature"), against
 * the column named `x` (NULL: the first column). A name is a column's name without its unit;
 * a name that is no column's selects every column that starts with it ("coordination": the
 * histogram's columns). panel_count 0: every column but x, one panel each. At most 8 panels.
 * `title` may be NULL. Errors: SINTER_ERR_NULL, SINTER_ERR_IO, SINTER_ERR_PARSE,
 * SINTER_ERR_STATE (no row), SINTER_ERR_INVALID (a name that selects no column; too many
 * panels).
 */
SINTER_API sinter_status sinter_plot_csv(sinter_ctx *ctx, const char *csv_path,
                                         const char *svg_path, const char *title, const char *x,
                                         const char *const *panels, size_t panel_count);

/** Borrow the scene's objects (valid until the scene is destroyed). */
SINTER_API sinter_status sinter_scene_get_stepper(sinter_scene *scene, sinter_stepper **stepper);
/** Borrow the scene's particle set (valid until the scene is destroyed). */
SINTER_API sinter_status sinter_scene_get_particles(sinter_scene *scene,
                                                    sinter_particles **particles);
/** Borrow the scene's walls (valid until the scene is destroyed). */
SINTER_API sinter_status sinter_scene_get_walls(sinter_scene *scene, sinter_walls **walls);
/** The scene's end time [s]. */
SINTER_API sinter_status sinter_scene_end_time(const sinter_scene *scene, double *end_time);

/**
 * Check a scene as sinter_scene_run would before its first step, without stepping or
 * writing anything: the output plan (an interval too small to advance the time at the end,
 * or more than [output] max_frames records), the particles' values
 * (sinter_particles_validate), no field view out (SINTER_ERR_BUSY), and, for the explicit
 * and staggered steppers, a starting state with no particle centre behind a wall, none outside
 * the stepper's domain and no two particles with the same centre (SINTER_ERR_INVALID naming
 * the particle). A scene with [compact] and no [pour] is compacted before its first step, so
 * its starting state is not checked. Used by `sinter check`.
 */
SINTER_API sinter_status sinter_scene_check(const sinter_scene *scene);

/**
 * Run the scene's [compact] section on its particles now: the triaxial compaction of
 * sinter_pack_compact with the section's options (its own walls and stepper; the scene's
 * stepper and walls are not touched), as sinter_scene_run does before the first step of a
 * fresh scene without [pour]. For a host that runs the scene's stepper itself, e.g. the MPI
 * runner, which compacts on one rank before it distributes the particles. Logs the outcome at
 * SINTER_LOG_INFO. SINTER_ERR_STATE when the scene has no [compact] section; the compaction's
 * own errors otherwise (SINTER_ERR_NOT_CONVERGED, ...).
 */
SINTER_API sinter_status sinter_scene_compact(sinter_scene *scene);

/* ------------------------------------------------------------------------ */
/* Checkpoints                                                               */
/* ------------------------------------------------------------------------ */

/**
 * Write the complete state of a stepper (time, step, particles, walls,
 * neighbour lists, contact history; for the quasi-static kind also its bonded
 * links, their 7DOF necks and the principal-plane conditions; with a "network"
 * electric model the potentials its next solve starts from; the particle
 * ranges its contact sums follow, the steps since its last spatial sort) to
 * a versioned binary file (format 14, which also carries the stepper's counts, the
 * frozen heat stage, the periodic cell, the neighbour search's reach and its continuous
 * insertion's state, sinter_stepper_set_insertion: set the insertion before reading;
 * formats 2-13 are still read, and a run restored from formats 2-4, or from 2-13 with a
 * heat law's gas_reach, may differ from the straight run in the last bits) with a checksum.
 * Written to a temporary file and renamed: an existing checkpoint is never
 * left half-written.
 */
SINTER_API sinter_status sinter_checkpoint_write(const sinter_stepper *stepper, const char *path);

/**
 * Restore a stepper from a checkpoint written by a stepper with the same
 * submodels and walls; the run then continues bit for bit as it would have.
 * A truncated, corrupted or mismatched file is refused with SINTER_ERR_CORRUPT
 * (or SINTER_ERR_INVALID for a mismatch, e.g. quasi-static links for a stepper
 * of another kind) and nothing is changed.
 */
SINTER_API sinter_status sinter_checkpoint_read(sinter_stepper *stepper, const char *path);

/* ---- migration of particles between steppers (issue 43) ---------------------------------- */

/**
 * Bytes sinter_stepper_export needs for the particles of the n indices listed (owned particles,
 * each once, in any order). The same checks as sinter_stepper_export.
 */
SINTER_API sinter_status sinter_stepper_export_size(const sinter_stepper *stepper, size_t n,
                                                   const size_t *indices, size_t *bytes);

/**
 * Write the particles of the n indices listed, with everything the stepper keeps for them, as
 * a record stream into buffer (capacity bytes; *written receives the bytes written): every
 * field (id, position [m], velocity [m/s], spin [rad/s], rotation, force [N], moment [N m],
 * radius [m], mass [kg], inertia [kg m^2], temperature [K], current [A], heat [W], material,
 * flags), the contact history of every force model in which the particle is an end (keyed by
 * the two ids; wall contacts by id and wall index), its quasi-static links where it is the
 * smaller id (beam and 7DOF neck state), its quasi-static state (principal-plane conditions,
 * last displacements [m, rad], initial position [m]) and its electric warm-start potential [V].
 * The stream
 * is versioned and checksummed, in the host's byte order. remove = 1 then takes the particles
 * out of the set (the order of the others kept), with their links and the histories of the
 * contacts both of whose ends left; a contact with one end staying keeps its history here too
 * (each side holds the contact once). Between two steps the forces stay current: the next step
 * continues as the run would have. Errors: SINTER_ERR_RANGE (an index not an owned particle, or
 * a buffer too small: see sinter_stepper_export_size), SINTER_ERR_INVALID (an index listed
 * twice, remove not 0 or 1), SINTER_ERR_BUSY (views out), SINTER_ERR_UNSUPPORTED (periodic
 * boundaries), SINTER_ERR_STATE (the frozen heat stage active).
 */
SINTER_API sinter_status sinter_stepper_export(sinter_stepper *stepper, size_t n,
                                              const size_t *indices, void *buffer,
                                              size_t capacity, size_t *written, int remove);

/**
 * Take the particles of the n indices listed out of the set, as sinter_stepper_export with
 * remove = 1 does, without writing their records: for a host that exported them already
 * (remove = 0, one stream per destination), so that a migration writes each leaver once. The
 * same effects (the order of the others kept, their links and the histories of the contacts
 * both of whose ends left dropped, the forces current between two steps) and the same errors
 * as that export, less the buffer's; inside a staggered stepper's attempt SINTER_ERR_STATE
 * (include/sinter_domain.h). n = 0 changes nothing.
 */
SINTER_API sinter_status sinter_stepper_remove(sinter_stepper *stepper, size_t n,
                                              const size_t *indices);

/**
 * Append the particles of a record stream of sinter_stepper_export (any alignment) as owned
 * particles; *count (may be NULL) receives how many. Their contact histories are staged by key
 * and taken by their pairs at the next neighbour build; a contact this stepper holds already
 * (its other end never left) keeps its own history, the same bits. Their quasi-static links
 * join the stepper's (created with the options set so far when it has none yet), one per pair;
 * their quasi-static states are kept by id and taken at the next step when the set's particles
 * all brought one (a portable restart), else the plane conditions are detected again. Streams
 * of the previous format (without the quasi-static states) are read too.
 * The stepper must have the same force models in the same order, and the set the records'
 * materials. Ghost rows, if any, are dropped (owned particles stay first; the host or the
 * periodic boundaries give them again). The staggered stepper's predictor history restarts
 * after any migration. Errors:
 * SINTER_ERR_CORRUPT (not a stream, another format or byte order, truncated, checksum),
 * SINTER_ERR_INVALID (an id the set holds or two records with one id, other force models, a
 * material not registered, links for a stepper that is not quasi-static, a wall it does not
 * have), SINTER_ERR_BUSY, SINTER_ERR_UNSUPPORTED, SINTER_ERR_STATE as for the export. On error
 * nothing is changed.
 */
SINTER_API sinter_status sinter_stepper_import(sinter_stepper *stepper, const void *buffer,
                                              size_t bytes, size_t *count);

/**
 * The stepper's global part, for a portable checkpoint: what is not kept per particle (time
 * [s], step [s], counters, the neighbour search's skin and reach [m], the walls' motion start,
 * temperature, reaction and servo state, the staggered step controller, the frozen heat stage's
 * counters, the continuous insertion's state, the quasi-static stepper's next step [s],
 * counters, initial extents [m], green density and cell), versioned and checksummed (a part of
 * the previous format, without the quasi-static values, is refused). buf = NULL: *bytes
 * receives the size only. A portable checkpoint is this part plus the records of every
 * particle (sinter_stepper_export, remove = 0, in any order and any number of pieces); a
 * restart calls sinter_stepper_load_global on a stepper set up alike without particles (the
 * same force models, walls and materials), then imports the records: the run continues bit
 * for bit as the original would after a reordering of its particles (which rebuilds its
 * neighbour lists, as the restart does). Errors: SINTER_ERR_RANGE (cap too small),
 * SINTER_ERR_UNSUPPORTED (periodic boundaries: use sinter_checkpoint_write), SINTER_ERR_STATE
 * (the frozen heat stage active).
 */
SINTER_API sinter_status sinter_stepper_save_global(const sinter_stepper *stepper, void *buf,
                                                   size_t cap, size_t *bytes);

/**
 * Load a global part of sinter_stepper_save_global into a stepper without particles (then
 * import the records). Errors: SINTER_ERR_CORRUPT (damaged, another format), SINTER_ERR_INVALID
 * (another kind of stepper, other force models or another number of walls, a quasi-static
 * state for a stepper of another kind), SINTER_ERR_STATE
 * (the set holds particles), SINTER_ERR_UNSUPPORTED as for the save. On error nothing changes.
 */
SINTER_API sinter_status sinter_stepper_load_global(sinter_stepper *stepper, const void *buf,
                                                   size_t bytes);

#ifdef __cplusplus
}
#endif

#endif /* SINTER_H */
