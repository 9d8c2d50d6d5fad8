/* Small scene builders shared by the mechanics tests (public API only). */
#ifndef SINTER_SCENE_SUPPORT_H
#define SINTER_SCENE_SUPPORT_H

#include <string.h>

#include "test_support.h"

typedef struct scene {
    sinter_ctx *ctx;
    sinter_material *mat;
    sinter_material *wall_mat;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_stepper *st;
    sinter_force_model *contact;
    sinter_force_model *gravity;
} scene;

#define OK(call) assert_int_equal((call), SINTER_OK)

/* Material with E, nu, rho, damping ratio and friction coefficient mu (static = dynamic). */
static inline void scene_material(scene *s, double e, double nu, double rho, double xi, double mu)
{
    OK(sinter_material_create(&s->mat, s->ctx, "particles"));
    OK(sinter_material_set(s->mat, SINTER_MAT_YOUNGS_MODULUS, e));
    OK(sinter_material_set(s->mat, SINTER_MAT_POISSON_RATIO, nu));
    OK(sinter_material_set(s->mat, SINTER_MAT_DENSITY, rho));
    OK(sinter_material_set(s->mat, SINTER_MAT_DAMPING_RATIO, xi));
    OK(sinter_material_set(s->mat, SINTER_MAT_FRICTION_STATIC, mu));
    OK(sinter_material_set(s->mat, SINTER_MAT_FRICTION_DYNAMIC, mu));
    OK(sinter_material_clone(&s->wall_mat, s->mat));
}

/* gravity: 0 none, 1 after the contact model, 2 before it (then the integrator seeds m g and
 * the contact law, the last model, may run the second half kick in its parallel region) */
static inline void scene_open(scene *s, const char *contact_model, int gravity)
{
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_walls_create(&s->walls, s->ctx));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_EXPLICIT, s->ps, s->walls));
    /* on exactly the context's threads: the tests that compare thread counts need every step
     * on the count they set (the choice by timing has a test of its own, test_stepper.c) */
    OK(sinter_stepper_set_option(s->st, "thread_choice", 0));
    if (gravity) {
        OK(sinter_force_model_create(&s->gravity, s->ctx, "gravity"));
        if (gravity == 2)
            OK(sinter_stepper_add_force(s->st, s->gravity));
    }
    OK(sinter_force_model_create(&s->contact, s->ctx, contact_model));
    OK(sinter_stepper_add_force(s->st, s->contact));
    if (gravity == 1)
        OK(sinter_stepper_add_force(s->st, s->gravity));
}

static inline void scene_init(scene *s)
{
    memset(s, 0, sizeof(*s));
    OK(sinter_ctx_create(&s->ctx, NULL));
}

static inline void scene_close(scene *s)
{
    sinter_stepper_destroy(s->st);
    sinter_force_model_destroy(s->contact);
    sinter_force_model_destroy(s->gravity);
    sinter_walls_destroy(s->walls);
    sinter_particles_destroy(s->ps);
    sinter_material_destroy(s->mat);
    sinter_material_destroy(s->wall_mat);
    sinter_ctx_destroy(s->ctx);
}

static inline void scene_add(scene *s, double x, double y, double z, double r)
{
    const double p[3] = {x, y, z};
    OK(sinter_particles_add(s->ps, 1, p, &r, 0, 300.0, NULL));
}

static inline void scene_floor(scene *s, double z)
{
    const double p[3] = {0, 0, z}, n[3] = {0, 0, 1};
    OK(sinter_walls_add_plane(s->walls, p, n, s->wall_mat, NULL));
}

/* Copy of a vector field of particle i. */
static inline void get3(scene *s, sinter_field f, size_t i, double out[3])
{
    const double *a = NULL;
    OK(sinter_particles_view_read(s->ps, f, (const void **)&a, NULL, NULL));
    memcpy(out, a + 3 * i, 3 * sizeof(double));
    OK(sinter_particles_release(s->ps, f));
}

static inline void set3(scene *s, sinter_field f, size_t i, const double in[3])
{
    double *a = NULL;
    OK(sinter_particles_view(s->ps, f, (void **)&a, NULL, NULL));
    memcpy(a + 3 * i, in, 3 * sizeof(double));
    OK(sinter_particles_release(s->ps, f));
}

static inline double get1(scene *s, sinter_field f, size_t i)
{
    const double *a = NULL;
    OK(sinter_particles_view_read(s->ps, f, (const void **)&a, NULL, NULL));
    const double v = a[i];
    OK(sinter_particles_release(s->ps, f));
    return v;
}

#endif
