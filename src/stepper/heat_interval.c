/* Heat every k-th step of the explicit stepper (heat_interval.h, issue 41). */
#include <math.h>
#include <string.h>

#include "heat_interval.h"
#include "stepper.h"

int sinter_heat_interval_is_key(const char *key)
{
    return strcmp(key, "heat_interval") == 0;
}

sinter_status sinter_heat_interval_set(sinter_stepper *st, double value)
{
    if (!(value >= 1.0 && value <= SINTER_HEAT_INTERVAL_MAX) || value != floor(value))
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: heat_interval = %g must be a whole number "
                           "from 1 (the temperatures advanced every step, the default) to %d",
                           value, SINTER_HEAT_INTERVAL_MAX);
    st->heat_interval = (uint64_t)value;
    return SINTER_OK;
}

sinter_status sinter_heat_interval_check(sinter_stepper *st)
{
    if (st->heat_interval <= 1 || st->thermal.count == 0)
        return SINTER_OK;
    if (st->thermal.scheme != SINTER_THERMAL_EXPLICIT || st->frozen.enabled)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "heat_interval = %llu: only with the explicit thermal scheme and "
                           "without frozen_heat (use 1)",
                           (unsigned long long)st->heat_interval);
    for (size_t k = 0; k < st->thermal.count; ++k) {
        const sinter_heat_model *hm = st->thermal.slots[k].model;
        if (hm->ops != &sinter_heat_conduction && hm->ops != &sinter_heat_convection)
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "heat_interval = %llu: heat model '%s' must be evaluated every "
                               "step (only conduction and convection may be sampled every "
                               "k-th step; use 1)",
                               (unsigned long long)st->heat_interval, hm->name);
    }
    return SINTER_OK;
}

int sinter_heat_interval_update(const sinter_stepper *st, uint64_t step)
{
    return st->heat_interval <= 1 || step % st->heat_interval == 0;
}

int sinter_heat_interval_eval(const sinter_stepper *st, uint64_t step)
{
    return st->heat_interval <= 1 || (step + 1) % st->heat_interval == 0;
}
