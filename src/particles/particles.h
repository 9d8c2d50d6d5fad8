/* Private layout of a particle set (struct of arrays). */
#ifndef SINTER_PARTICLES_H
#define SINTER_PARTICLES_H

#include "core/core.h"
#include "particles/id_index.h"
#include "particles/material.h"
#include "particles/property_table.h"

#define SINTER_MAX_MATERIALS 256

struct sinter_particles {
    sinter_ctx *ctx;
    size_t count;
    size_t capacity;
    size_t ghost_count; /* the last ghost_count rows are ghosts (ghosts/ghosts.h); 0 without */
    /* vector fields: 3 doubles per particle, particle-major */
    double *x;      /* position [m] */
    double *v;      /* velocity [m/s] */
    double *w;      /* spin [rad/s] */
    double *rot;    /* total rotation vector [-] */
    double *force;  /* last evaluated force [N] */
    double *torque; /* last evaluated moment [N m] */
    /* scalar fields */
    double *radius;
    double *mass;
    double *inertia;
    double *temperature;
    double *current;
    double *heat;
    int32_t *material;
    uint32_t *flags;
    uint64_t *id;
    uint64_t next_id;         /* sinter_particles_add's next id: above every id in the set */
    sinter_id_index id_index; /* id -> index, built on the first lookup after a change */
    /* borrowed views */
    size_t views_out;
    unsigned field_views[SINTER_FIELD_COUNT_];
    /* materials, copied at registration */
    unsigned char material_used[SINTER_MAX_MATERIALS];
    /* 1 + the largest registered id (0: none): the per-step loops over the materials in use
     * stop there instead of reading all SINTER_MAX_MATERIALS (issue 9) */
    int material_top;
    sinter_material materials[SINTER_MAX_MATERIALS];
    /* softening laws 3 (tabulated) and 4 (host callback), per material */
    struct sinter_softening_curve {
        size_t count;
        double *temperature;
        double *factor;
        sinter_softening_fn fn;
        void *user;
    } softening[SINTER_MAX_MATERIALS];
    /* temperature-dependent properties per material (property_table.h), NULL: all constant;
     * tabulated[p]: a material in the set has a table of property p; enthalpy: a material
     * advances its temperatures through a nonlinear enthalpy (a C table or latent heat) */
    sinter_material_props *props[SINTER_MAX_MATERIALS];
    int tabulated[SINTER_PROPERTY_COUNT_];
    int enthalpy;
    /* bumped whenever particles are added, removed or reordered */
    uint64_t layout_generation;
    /* bumped when particles are added or removed (not when they are only reordered, nor when
     * ghost rows come and go) */
    uint64_t population_generation;
    /* bumped whenever a writable view is lent (the host may have changed the state) */
    uint64_t write_generation;
};

/* Material parameter of particle i (no checks). */
static inline double sinter_particle_param(const sinter_particles *ps, size_t i,
                                           sinter_material_param p)
{
    return ps->materials[ps->material[i]].value[p];
}

/* Drop the ghost rows (ghosts/ghosts.h), if any: the set holds its owned particles only. */
void sinter_particles_drop_ghosts(sinter_particles *ps);

/* Replace the ghost rows by n copies of owned particles: ghost k copies every field of owned
 * particle owner[k], its position shifted by shift[3k..3k+2], its force, moment and heat zero. */
sinter_status sinter_particles_set_ghost_rows(sinter_particles *ps, size_t n, const uint32_t *owner,
                                              const double *shift);
/* The same rows appended after the ghost rows there are (the periodic images of a decomposed
 * run, after the host's ghosts: ghosts/ghosts.h); owner[k] may be any row, owned or ghost. */
sinter_status sinter_particles_append_ghost_rows(sinter_particles *ps, size_t n,
                                                 const uint32_t *owner, const double *shift);
/* Replace the ghost rows by n rows whose fields the caller fills (sinter_particles_set_ghosts,
 * domain/ghost_input.c): force, moment, heat power and current zero, the rest unset. */
sinter_status sinter_particles_make_ghost_rows(sinter_particles *ps, size_t n);
/* The tabulated branches of the accessors below, out of line (property_table.c) so that the
 * constant path stays a flag test and the load it always was. */
double sinter_particle_property_tabulated(const sinter_particles *ps, size_t i, sinter_property p,
                                          sinter_material_param c);
double sinter_particle_heat_capacity_tabulated(const sinter_particles *ps, size_t i, double theta);

/* Property p of particle i at its temperature: its material's table, else the constant c. */
static inline double sinter_particle_property(const sinter_particles *ps, size_t i,
                                              sinter_property p, sinter_material_param c)
{
    if (__builtin_expect(ps->tabulated[p], 0))
        return sinter_particle_property_tabulated(ps, i, p, c);
    return sinter_particle_param(ps, i, c);
}

/* The enthalpy of particle i's material, NULL when its temperature advances by the constant
 * heat capacity (theta += E / (m C)). */
static inline const sinter_enthalpy *sinter_particle_enthalpy(const sinter_particles *ps, size_t i)
{
    if (!ps->enthalpy)
        return NULL;
    const sinter_material_props *t = ps->props[ps->material[i]];
    return t != NULL && t->enthalpy ? &t->H : NULL;
}

/* Apparent heat capacity of particle i at temperature theta [J/(kg K)] (the latent heat's
 * share on the melting interval included). */
static inline double sinter_particle_heat_capacity(const sinter_particles *ps, size_t i,
                                                   double theta)
{
    if (__builtin_expect(ps->enthalpy, 0))
        return sinter_particle_heat_capacity_tabulated(ps, i, theta);
    return sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY);
}

/* Reorder particles: new index k holds old particle order[k]. Refused while views are out. */
sinter_status sinter_particles_permute(sinter_particles *ps, const size_t *order);

#endif
