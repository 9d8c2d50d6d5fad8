/*
 * The press of the staggered stepper's reproducible-mode test (test_domain_staggered_repro.c)
 * and of tests/bench/staggered_repro_cost.c, in the manner of
 * examples/scenes/press_staggered.scene: a powder with the seed 000 power law, drag, gravity,
 * conduction, Joule heating and the averaged electric model (seed 000 sec. 5) in a box of six
 * plane walls at 400 K, the floor and the top wall carrying 1000 A, the top one moving down
 * at 0.05 m/s. The particles, the stepper's options and the decomposition are the caller's.
 * domain_press.h builds its press (and the network variant) from the same pieces.
 */
#ifndef SINTER_TEST_DOMAIN_PRESS_MODELS_H
#define SINTER_TEST_DOMAIN_PRESS_MODELS_H

#include <stddef.h>

#include <sinter.h>

enum { DOMAIN_PRESS_WALLS = 6 };

/* The material "powder": 2000 kg/m^3, K_p = 1e7 Pa, the dynamic friction coefficient
 * `friction`, drag 0.1414 kg/s, 100 W/(m K), 100 J/(kg K), 0.1 S/m, linear softening from
 * 320 K to a floor of 0.1. */
static inline sinter_status domain_press_material_friction(sinter_ctx *ctx, double friction,
                                                           sinter_material **mat)
{
    sinter_status s = sinter_material_create(mat, ctx, "powder");
    const struct {
        sinter_material_param p;
        double v;
    } props[] = {{SINTER_MAT_DENSITY, 2000},
                 {SINTER_MAT_CONTACT_STIFFNESS, 1e7},
                 {SINTER_MAT_FRICTION_DYNAMIC, friction},
                 {SINTER_MAT_DRAG_COEFFICIENT, 0.1414},
                 {SINTER_MAT_THERMAL_CONDUCTIVITY, 100},
                 {SINTER_MAT_HEAT_CAPACITY, 100},
                 {SINTER_MAT_ELECTRIC_CONDUCTIVITY, 0.1},
                 {SINTER_MAT_SOFTENING_LAW, 1},
                 {SINTER_MAT_SOFTENING_TEMPERATURE, 320},
                 {SINTER_MAT_SOFTENING_FLOOR, 0.1}};
    for (size_t k = 0; s == SINTER_OK && k < sizeof(props) / sizeof(props[0]); ++k)
        s = sinter_material_set(*mat, props[k].p, props[k].v);
    return s;
}

/* The material with friction 0.1 (the press's). */
static inline sinter_status domain_press_material(sinter_ctx *ctx, sinter_material **mat)
{
    return domain_press_material_friction(ctx, 0.1, mat);
}

/* The floor z = 0, the top wall z = top, and the side walls x = 0, x = lx, y = 0, y = ly [m],
 * in this order, all at 400 K, into a new wall set *walls (no electric role, at rest). */
static inline sinter_status domain_press_plane_walls(sinter_ctx *ctx, sinter_material *mat,
                                                     double lx, double ly, double top,
                                                     sinter_walls **walls)
{
    sinter_status s = sinter_walls_create(walls, ctx);
    const double wp[DOMAIN_PRESS_WALLS][3] = {{0, 0, 0},  {0, 0, top}, {0, 0, 0},
                                              {lx, 0, 0}, {0, 0, 0},   {0, ly, 0}};
    const double wn[DOMAIN_PRESS_WALLS][3] = {{0, 0, 1},  {0, 0, -1}, {1, 0, 0},
                                              {-1, 0, 0}, {0, 1, 0},  {0, -1, 0}};
    for (int k = 0; s == SINTER_OK && k < DOMAIN_PRESS_WALLS; ++k) {
        s = sinter_walls_add_plane(*walls, wp[k], wn[k], mat, NULL);
        if (s == SINTER_OK)
            s = sinter_walls_set_temperature(*walls, (size_t)k, 400.0);
    }
    return s;
}

/* The plane walls, the floor and the top wall current walls of 1000 A, the top one moving
 * down at 0.05 m/s. */
static inline sinter_status domain_press_walls(sinter_ctx *ctx, sinter_material *mat, double lx,
                                               double ly, double top, sinter_walls **walls)
{
    sinter_status s = domain_press_plane_walls(ctx, mat, lx, ly, top, walls);
    for (size_t k = 0; s == SINTER_OK && k < 2; ++k)
        s = sinter_walls_set_electric(*walls, k, SINTER_WALL_CURRENT, 1000.0);
    const double down[3] = {0, 0, -0.05};
    return s == SINTER_OK ? sinter_walls_set_velocity(*walls, 1, down) : s;
}

/* The press's models, added to the stepper in this order. */
typedef struct domain_press_models {
    sinter_force_model *law, *drag, *gravity;
    sinter_heat_model *conduction, *joule;
    sinter_electric_model *electric;
} domain_press_models;

/* The power law, drag and gravity; conduction and Joule heat (its option "source" set to
 * `joule_source` first when that is not 0); no electric model. */
static inline sinter_status domain_press_add_forces_heat(sinter_ctx *ctx, sinter_stepper *st,
                                                         double joule_source,
                                                         domain_press_models *m)
{
    sinter_force_model **law[3] = {&m->law, &m->drag, &m->gravity};
    const char *laws[3] = {"power_law", "drag", "gravity"};
    sinter_heat_model **heat[2] = {&m->conduction, &m->joule};
    const char *heats[2] = {"conduction", "joule"};
    sinter_status s = SINTER_OK;
    for (int k = 0; s == SINTER_OK && k < 3; ++k)
        if ((s = sinter_force_model_create(law[k], ctx, laws[k])) == SINTER_OK)
            s = sinter_stepper_add_force(st, *law[k]);
    for (int k = 0; s == SINTER_OK && k < 2; ++k) {
        s = sinter_heat_model_create(heat[k], ctx, heats[k]);
        if (s == SINTER_OK && k == 1 && joule_source != 0.0)
            s = sinter_heat_model_set(*heat[k], "source", joule_source);
        if (s == SINTER_OK)
            s = sinter_stepper_add_heat(st, *heat[k]);
    }
    return s;
}

/* The forces and heat models and the averaged electric model with `tolerance` (the scene's:
 * 1e-4) and up to 1e5 sweeps. */
static inline sinter_status domain_press_add_models(sinter_ctx *ctx, sinter_stepper *st,
                                                    double tolerance, domain_press_models *m)
{
    sinter_status s = domain_press_add_forces_heat(ctx, st, 0.0, m);
    if (s == SINTER_OK)
        s = sinter_electric_model_create(&m->electric, ctx, "averaged");
    if (s == SINTER_OK)
        s = sinter_electric_model_set(m->electric, "tolerance", tolerance);
    if (s == SINTER_OK)
        s = sinter_electric_model_set(m->electric, "max_iterations", 1e5);
    return s == SINTER_OK ? sinter_stepper_set_electric(st, m->electric) : s;
}

static inline void domain_press_models_destroy(domain_press_models *m)
{
    sinter_force_model_destroy(m->law);
    sinter_force_model_destroy(m->drag);
    sinter_force_model_destroy(m->gravity);
    sinter_heat_model_destroy(m->conduction);
    sinter_heat_model_destroy(m->joule);
    sinter_electric_model_destroy(m->electric);
}

#endif
