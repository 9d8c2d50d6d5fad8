/*
 * Periodic boundaries of the explicit stepper (issue 38): the settings, and the check that the
 * submodels in use are right across a periodic face. Particles wrap into the cell and their
 * images are ghost particles (ghosts/ghosts.h), made at every neighbour build.
 */
#include "electric/electric.h"
#include "heat/heat_model.h"
#include "stepper.h"

sinter_status sinter_stepper_set_periodic(sinter_stepper *st, int axis, double lo, double hi)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    /* every stepper kind: the quasi-static one keeps its own cell (stepper/qs_periodic.c), taken
     * from here */
    const sinter_status s = sinter_ghosts_set_periodic(st->ctx, &st->ghosts, axis, lo, hi);
    if (s == SINTER_OK && !sinter_ghosts_on(&st->ghosts))
        sinter_particles_drop_ghosts(st->ps); /* no axis left: no images */
    return s;
}

sinter_status sinter_stepper_get_periodic(const sinter_stepper *st, int axis, int *periodic,
                                          double *lo, double *hi)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, periodic);
    if (axis < 0 || axis > 2)
        return sinter_fail(st->ctx, SINTER_ERR_RANGE,
                           "sinter_stepper_get_periodic: axis %d is not 0, 1 or 2", axis);
    *periodic = st->ghosts.periodic[axis];
    if (lo != NULL)
        *lo = st->ghosts.periodic[axis] ? st->ghosts.lo[axis] : 0.0;
    if (hi != NULL)
        *hi = st->ghosts.periodic[axis] ? st->ghosts.hi[axis] : 0.0;
    return SINTER_OK;
}

sinter_status sinter_periodic_check(sinter_stepper *st)
{
    const char *why = NULL;
    /* the network's unknowns are the owned particles, an image stands for its owner
     * (electric/network.c); implicit conduction maps them alike (thermal.c) */
    if (st->electric != NULL && st->electric->kind != SINTER_ELECTRIC_NETWORK)
        why = "the 'averaged' electric model (it spreads a current magnitude over the "
              "particles and has no potential an image could share; use 'network')";
    for (size_t k = 0; why == NULL && k < st->force_count; ++k) {
        const sinter_force_model *fm = st->forces[k].model;
        if (fm->ops->eval == sinter_force_host_eval && fm->host.contacts != NULL &&
            fm->host.particles != NULL)
            why = "a host force model with both a contact and a body callback (its body forces "
                  "on the images could not be told from its contact forces; make them two "
                  "models)";
    }
    /* the built-in heat models tell a source from a pair term (heat_model.h, owned) */
    for (size_t k = 0; why == NULL && k < st->thermal.count; ++k)
        if (st->thermal.slots[k].model->ops->eval == sinter_heat_host_eval)
            why = "a host heat model (its power on an image could be a pair's share or a "
                  "source counted twice)";
    if (why == NULL)
        return SINTER_OK;
    return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                       "periodic boundaries do not support %s yet; remove it or make every axis "
                       "non-periodic",
                       why);
}
