/*
 * The stepper's electric model (seed 000 sec. 5-6): borrowed, solved by the stepper on every
 * evaluation once the contacts are known (the call lives in the stepper's evaluation pipeline,
 * src/stepper/stepper.c), and its iteration count.
 */
#include "electric.h"
#include "stepper/stepper.h"

sinter_status sinter_stepper_set_electric(sinter_stepper *st, sinter_electric_model *em)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (em != NULL && em->ctx != st->ctx)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_electric: model '%s' belongs to another context",
                           em->name);
    st->electric = em;
    return SINTER_OK;
}

sinter_status sinter_stepper_electric_iterations(const sinter_stepper *st, uint64_t *iterations)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, iterations);
    *iterations = st->electric_iterations;
    return SINTER_OK;
}
