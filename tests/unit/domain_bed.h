/*
 * The bed of the subdomain tests (test_domain.c, test_domain_repro.c, tests/mpi/
 * test_mpi_attach.c, test_domain_long.c): a heat-conducting glass-like material, a floor and four
 * side walls around the box [0, lx] x [0, ly], and the explicit stepper's models (gravity,
 * Hertz-Mindlin contact, conduction). The particles, the stepper and its options are the caller's.
 */
#ifndef SINTER_TEST_DOMAIN_BED_H
#define SINTER_TEST_DOMAIN_BED_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <sinter.h>

enum { DOMAIN_BED_WALLS = 5 };

/* The material "bed": E = 1e7 Pa, nu = 0.3, 2500 kg/m^3, damping ratio 0.3, friction 0.5
 * (static and dynamic), rolling friction 0.1, 400 W/(m K), 400 J/(kg K). */
static inline sinter_status domain_bed_material(sinter_ctx *ctx, sinter_material **mat)
{
    sinter_status s = sinter_material_create(mat, ctx, "bed");
    const struct {
        sinter_material_param p;
        double v;
    } props[] = {{SINTER_MAT_YOUNGS_MODULUS, 1e7},   {SINTER_MAT_POISSON_RATIO, 0.3},
                 {SINTER_MAT_DENSITY, 2500},         {SINTER_MAT_DAMPING_RATIO, 0.3},
                 {SINTER_MAT_FRICTION_STATIC, 0.5},  {SINTER_MAT_FRICTION_DYNAMIC, 0.5},
                 {SINTER_MAT_ROLLING_FRICTION, 0.1}, {SINTER_MAT_THERMAL_CONDUCTIVITY, 400},
                 {SINTER_MAT_HEAT_CAPACITY, 400}};
    for (size_t k = 0; s == SINTER_OK && k < sizeof(props) / sizeof(props[0]); ++k)
        s = sinter_material_set(*mat, props[k].p, props[k].v);
    return s;
}

/* The floor z = 0 and the side walls x = 0, x = lx, y = 0, y = ly [m] (in this order), of
 * material `mat`, into a new wall set *walls. */
static inline sinter_status domain_bed_walls(sinter_ctx *ctx, sinter_material *mat, double lx,
                                             double ly, sinter_walls **walls)
{
    sinter_status s = sinter_walls_create(walls, ctx);
    const double wp[DOMAIN_BED_WALLS][3] = {
        {0, 0, 0}, {0, 0, 0}, {lx, 0, 0}, {0, 0, 0}, {0, ly, 0}};
    const double wn[DOMAIN_BED_WALLS][3] = {
        {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; s == SINTER_OK && k < DOMAIN_BED_WALLS; ++k)
        s = sinter_walls_add_plane(*walls, wp[k], wn[k], mat, NULL);
    return s;
}

/* Gravity (first: the integrator seeds m g), Hertz-Mindlin contact and conduction, created
 * into *gravity, *contact, *cond and added to the stepper in this order. */
static inline sinter_status domain_bed_models(sinter_ctx *ctx, sinter_stepper *st,
                                              sinter_force_model **gravity,
                                              sinter_force_model **contact,
                                              sinter_heat_model **cond)
{
    sinter_status s = sinter_force_model_create(gravity, ctx, "gravity");
    if (s == SINTER_OK)
        s = sinter_stepper_add_force(st, *gravity);
    if (s == SINTER_OK)
        s = sinter_force_model_create(contact, ctx, "hertz_mindlin");
    if (s == SINTER_OK)
        s = sinter_stepper_add_force(st, *contact);
    if (s == SINTER_OK)
        s = sinter_heat_model_create(cond, ctx, "conduction");
    if (s == SINTER_OK)
        s = sinter_stepper_add_heat(st, *cond);
    return s;
}

/* One sphere of the bed added to ps with the caller's id: centre x, radius r, temperature
 * temp, velocity v and spin w (3 each; material 0). */
static inline sinter_status domain_bed_add(sinter_particles *ps, uint64_t id, const double *x,
                                           double r, double temp, const double *v, const double *w)
{
    size_t first = 0;
    double *pv = NULL, *pw = NULL;
    sinter_status s = sinter_particles_add_with_ids(ps, 1, &id, x, &r, 0, temp, &first);
    if (s == SINTER_OK)
        s = sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&pv, NULL, NULL);
    if (s == SINTER_OK) {
        memcpy(pv + 3 * first, v, 3 * sizeof(double));
        s = sinter_particles_release(ps, SINTER_FIELD_VELOCITY);
    }
    if (s == SINTER_OK)
        s = sinter_particles_view(ps, SINTER_FIELD_SPIN, (void **)&pw, NULL, NULL);
    if (s == SINTER_OK) {
        memcpy(pw + 3 * first, w, 3 * sizeof(double));
        s = sinter_particles_release(ps, SINTER_FIELD_SPIN);
    }
    return s;
}

#endif
