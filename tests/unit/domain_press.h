/*
 * The small press of the subdomain tests (test_domain_staggered.c, test_domain_press.c,
 * tests/mpi/test_mpi_staggered.c), in the manner of examples/scenes/press_staggered.scene:
 * 240 spheres of 0.05 m in an 8 x 6 x 5 lattice (1 % overlap, positions jiggled by 0.1 % of a
 * radius, random velocities and temperatures, ids not in the lattice's order) in a box of six
 * walls at 400 K, with the seed 000 power law (softening with temperature), drag, gravity,
 * conduction and Joule heating; the top wall moves down at 0.05 m/s. The electric model is
 *  - "averaged" (seed 000 sec. 5): floor and top wall current walls of 1000 A, the sweeps'
 *    tolerance 1e-14;
 *  - or "network": the floor a current electrode of 1000 A with a compliance of 10 V (as
 *    examples/scenes/press_network.scene, whose supply then sits at its limit), the top wall
 *    grounded and moving down at 0.5 m/s, Joule heating energy-consistent (source 2), the
 *    PCG's tolerance 1e-13.
 * The stepper is the staggered one (dt_max 5 ms, adaptive) or the explicit one (fixed dt).
 * Each subdomain adds the particles of its slab of [x0, x1) along x; the final state of its
 * owned particles goes into a press_state by id - 1 (each slot written by one subdomain).
 * Everything is static inline: a file that includes this uses what it needs.
 */
#ifndef SINTER_TEST_DOMAIN_PRESS_H
#define SINTER_TEST_DOMAIN_PRESS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <sinter.h>
#include <sinter_domain.h>
#include <sinter_submodel.h>

#include "domain_press_models.h"
#include "rel_diff.h"

enum {
    PRESS_NX = 8,
    PRESS_NY = 6,
    PRESS_NZ = 5,
    PRESS_N = PRESS_NX * PRESS_NY * PRESS_NZ,
    PRESS_WALLS = 6
};
#define PRESS_R 0.05  /* radius [m] */
#define PRESS_A 0.099 /* lattice spacing [m]: 1 % overlap */
#define PRESS_LX (PRESS_R + PRESS_A * (PRESS_NX - 1) + PRESS_R)
#define PRESS_LY (PRESS_R + PRESS_A * (PRESS_NY - 1) + PRESS_R)
#define PRESS_TOP (PRESS_R + PRESS_A * (PRESS_NZ - 1) + 0.99 * PRESS_R) /* top wall at t = 0 */

/* Slabs whose borders lie between two columns of the lattice for 2, 3 and 4 subdomains
 * (x1 - x0 = 12 A, borders at odd multiples of A / 2 from the columns): no migration. */
#define PRESS_X0_BETWEEN (PRESS_R - 2.5 * PRESS_A)
#define PRESS_X1_BETWEEN (PRESS_R + 9.5 * PRESS_A)
/* Slabs whose borders lie on columns: the particles jiggling about them migrate. */
#define PRESS_X0_ON (PRESS_R - 2.0 * PRESS_A)
#define PRESS_X1_ON (PRESS_R + 10.0 * PRESS_A)

typedef struct press_spec {
    double x[3 * PRESS_N], v[3 * PRESS_N], temp[PRESS_N];
    uint64_t id[PRESS_N];
} press_spec;

static inline double press_lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static inline void press_make(press_spec *p)
{
    uint64_t seed = 28;
    const double R = PRESS_R, A = PRESS_A;
    for (int k = 0; k < PRESS_N; ++k) {
        const int i = k % PRESS_NX, j = (k / PRESS_NX) % PRESS_NY, l = k / (PRESS_NX * PRESS_NY);
        p->x[3 * k] = R + A * i + 0.002 * R * (press_lcg(&seed) - 0.5);
        p->x[3 * k + 1] = R + A * j + 0.002 * R * (press_lcg(&seed) - 0.5);
        p->x[3 * k + 2] = 0.99 * R + A * l + 0.002 * R * (press_lcg(&seed) - 0.5);
        for (int d = 0; d < 3; ++d)
            p->v[3 * k + d] = 0.01 * (press_lcg(&seed) - 0.5);
        p->temp[k] = 300.0 + 50.0 * press_lcg(&seed);
        p->id[k] = 1 + (uint64_t)((k * 37) % PRESS_N); /* (ids not in the lattice's order) */
    }
}

/* The slab of `size` equal ones of [x0, x1) that holds x (the outer ones open outwards). */
static inline int press_slab_of(double x, double x0, double x1, int size)
{
    const double r = floor((x - x0) / (x1 - x0) * size);
    return r < 0.0 ? 0 : r >= size ? size - 1 : (int)r;
}

/* A host force that makes the force of particle `id` NaN once an evaluation reached the time
 * `after`, at every evaluation from then on (the shorter retries too), on the subdomain that
 * owns it. */
typedef struct press_host_force {
    const sinter_particles *ps;
    uint64_t id;
    double after;
    int on;
} press_host_force;

static inline int press_host_eval(const sinter_state_view *s, double *force, double *torque,
                                  void *user)
{
    (void)torque;
    press_host_force *p = user;
    size_t i = SIZE_MAX, owned = 0;
    if (p->id == 0 || sinter_particles_owned_count(p->ps, &owned) != SINTER_OK ||
        sinter_particles_find_id(p->ps, p->id, &i) != SINTER_OK || i >= owned)
        return 0;
    p->on |= s->time > p->after;
    if (p->on)
        force[3 * i] = NAN;
    return 0;
}

/* The final state by id - 1. */
typedef struct press_state {
    double x[3 * PRESS_N], v[3 * PRESS_N], temp[PRESS_N], current[PRESS_N];
    int seen[PRESS_N];
} press_state;

typedef struct press_job {
    /* the set-up */
    const press_spec *spec;
    int rank, size;   /* this subdomain's slab of `size` (size 1: every particle) */
    double x0, x1;    /* the slabs' range along x [m] */
    int kind;         /* SINTER_STEPPER_STAGGERED or SINTER_STEPPER_EXPLICIT */
    int network;      /* 1: the "network" electric model, 0: "averaged" */
    int frictionless; /* 1: no Coulomb friction (0: the scene's 0.1) */
    int reverse;      /* 1: the particles added last first (another order of every sum) */
    int scheme;       /* the staggered stepper's option "scheme" */
    int reproducible; /* the stepper's option "reproducible" (0: not set, the default mode) */
    double dt;        /* the explicit stepper's step [s] (the staggered one starts at 5 ms) */
    int steps;        /* calls of sinter_stepper_step(st, 1) */
    uint64_t host_id; /* the NaN host force's particle (0: none) */
    double nan_after; /* ... from this time on [s] */
    /* the host's domain operations installed on the stepper (NULL: none), the particles
     * loaded after them instead of the spec's (NULL: the spec's slab), and what the caller
     * reads before the stepper is destroyed (NULL: nothing) */
    sinter_status (*attach)(void *user, sinter_stepper *st, sinter_particles *ps);
    sinter_status (*load)(void *user, sinter_stepper *st, sinter_particles *ps);
    sinter_status (*finish)(void *user, sinter_stepper *st);
    void *user;
    /* the results */
    int setup_failed, failed_at; /* the line of a failed set-up; the step that failed */
    sinter_status status;
    char message[512];
    double time, wall[3 * PRESS_WALLS];
    sinter_stepper_stats stats;
    uint64_t electric_iterations; /* sweeps or PCG iterations, every solve of the run */
    size_t owned;
} press_job;

static inline void press_copy_owned(sinter_particles *ps, size_t owned, press_state *out)
{
    const uint64_t *id = NULL;
    const double *x = NULL, *v = NULL, *t = NULL, *c = NULL;
    if (sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&t, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_CURRENT, (const void **)&c, NULL, NULL))
        return;
    for (size_t i = 0; i < owned; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(out->x + 3 * k, x + 3 * i, 24);
        memcpy(out->v + 3 * k, v + 3 * i, 24);
        out->temp[k] = t[i];
        out->current[k] = c[i];
        out->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
    sinter_particles_release(ps, SINTER_FIELD_CURRENT);
}

#define PRESS_TRY(call)                                                                            \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            j->setup_failed = __LINE__;                                                            \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

/* Set up, run and tear down the press of job `j` on its subdomain (thread-safe: its own
 * context); its owned particles' final state into `out`. */
static inline void press_run(press_job *j, press_state *out)
{
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *host = NULL;
    domain_press_models models = {.law = NULL};
    press_host_force hf = {NULL, 0, INFINITY, 0};
    const press_spec *p = j->spec;
    const double R = PRESS_R;
    PRESS_TRY(sinter_ctx_create(&ctx, NULL));
    PRESS_TRY(sinter_ctx_set_threads(ctx, 1));
    PRESS_TRY(domain_press_material_friction(ctx, j->frictionless ? 0.0 : 0.1, &mat));
    PRESS_TRY(sinter_particles_create(&ps, ctx));
    PRESS_TRY(sinter_particles_set_material(ps, 0, mat));
    PRESS_TRY(domain_press_plane_walls(ctx, mat, PRESS_LX, PRESS_LY, PRESS_TOP, &walls));
    PRESS_TRY(sinter_walls_set_electric(walls, 0, SINTER_WALL_CURRENT, 1000.0));
    if (j->network) {
        PRESS_TRY(sinter_walls_set_electric_limit(walls, 0, 10.0));
        PRESS_TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    } else {
        PRESS_TRY(sinter_walls_set_electric(walls, 1, SINTER_WALL_CURRENT, 1000.0));
    }
    /* (the network's top electrode must keep up with the bed, which settles under gravity
     * by about 2 cm in 0.06 s: it closes the circuit) */
    const double down[3] = {0, 0, j->network ? -0.5 : -0.05};
    PRESS_TRY(sinter_walls_set_velocity(walls, 1, down));
    PRESS_TRY(sinter_stepper_create(&st, ctx, j->kind, ps, walls));
    PRESS_TRY(domain_press_add_forces_heat(ctx, st, j->network ? 2.0 : 0.0, &models));
    if (j->network) {
        PRESS_TRY(sinter_electric_model_create(&models.electric, ctx, "network"));
        PRESS_TRY(sinter_electric_model_set(models.electric, "tolerance", 1e-13));
    } else {
        PRESS_TRY(sinter_electric_model_create(&models.electric, ctx, "averaged"));
        PRESS_TRY(sinter_electric_model_set(models.electric, "tolerance", 1e-14));
        PRESS_TRY(sinter_electric_model_set(models.electric, "max_iterations", 1e5));
    }
    PRESS_TRY(sinter_stepper_set_electric(st, models.electric));
    for (int q = 0; q < PRESS_N; ++q) {
        const int k = j->reverse ? PRESS_N - 1 - q : q;
        if (j->load != NULL || press_slab_of(p->x[3 * k], j->x0, j->x1, j->size) != j->rank)
            continue;
        size_t first = 0;
        PRESS_TRY(sinter_particles_add_with_ids(ps, 1, &p->id[k], p->x + 3 * k, &R, 0, p->temp[k],
                                                &first));
        double *v = NULL;
        PRESS_TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
        memcpy(v + 3 * first, p->v + 3 * k, 24);
        PRESS_TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
    }
    if (j->host_id != 0) { /* on every subdomain: migration needs the same force models */
        hf = (press_host_force){ps, j->host_id, j->nan_after, 0};
        const sinter_force_callbacks cb = {.struct_size = sizeof(cb), .particles = press_host_eval};
        PRESS_TRY(sinter_force_model_create_host(&host, ctx, "host", &cb, &hf));
        PRESS_TRY(sinter_stepper_add_force(st, host));
    }
    if (j->kind == SINTER_STEPPER_STAGGERED) {
        PRESS_TRY(sinter_stepper_set_option(st, "scheme", j->scheme));
        PRESS_TRY(sinter_stepper_set_dt(st, 0.005));
        PRESS_TRY(sinter_stepper_set_option(st, "dt_max", 0.005));
        PRESS_TRY(sinter_stepper_set_option(st, "dt_min", 1e-7));
        PRESS_TRY(sinter_stepper_set_option(st, "position_tolerance", 1e-6));
    } else {
        PRESS_TRY(sinter_stepper_set_dt(st, j->dt));
    }
    PRESS_TRY(sinter_stepper_set_skin(st, 0.01)); /* rebuilds within the run */
    if (j->reproducible)
        PRESS_TRY(sinter_stepper_set_option(st, "reproducible", 1));
    if (j->attach != NULL)
        PRESS_TRY(j->attach(j->user, st, ps));
    if (j->load != NULL)
        PRESS_TRY(j->load(j->user, st, ps));
    j->status = SINTER_OK;
    for (int k = 1; k <= j->steps; ++k) {
        const sinter_status s = sinter_stepper_step(st, 1);
        if (s != SINTER_OK) {
            j->status = s;
            j->failed_at = k;
            snprintf(j->message, sizeof(j->message), "%s", sinter_last_error(ctx));
            break;
        }
    }
    PRESS_TRY(sinter_stepper_time(st, &j->time));
    PRESS_TRY(sinter_particles_owned_count(ps, &j->owned));
    press_copy_owned(ps, j->owned, out);
    for (int k = 0; k < PRESS_WALLS; ++k)
        PRESS_TRY(sinter_walls_get_force(walls, (size_t)k, j->wall + 3 * k));
    j->stats.struct_size = sizeof(j->stats);
    PRESS_TRY(sinter_stepper_get_stats_global(st, &j->stats));
    PRESS_TRY(sinter_stepper_electric_iterations(st, &j->electric_iterations));
    if (j->finish != NULL)
        PRESS_TRY(j->finish(j->user, st));
done:
    if (j->setup_failed)
        snprintf(j->message, sizeof(j->message), "setup failed at line %d: %s", j->setup_failed,
                 sinter_last_error(ctx));
    sinter_stepper_destroy(st);
    domain_press_models_destroy(&models);
    sinter_force_model_destroy(host);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
}

#undef PRESS_TRY

/* The largest |a - b| over the largest |b - base| (base NULL: |b|), k values. */
static inline double press_rel_diff(const double *a, const double *b, const double *base, size_t k)
{
    return rel_diff_from(a, b, base, k);
}

#endif
