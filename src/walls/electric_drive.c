/*
 * A wall's electric drive, as a power supply sets it: the value of sinter_walls_set_electric
 * (a current [A] or a potential [V]), or a piecewise-linear schedule of it in time, switched
 * on and off in pulses (on for pulse_on, off for pulse_off, from t = 0), and a compliance
 * limit: a current electrode whose potential would pass the limit is held at the limit, a
 * potential electrode whose current would pass it carries the limit (the network model,
 * electric/network.c, applies it; the averaged model has no potentials and ignores it).
 * Times are the simulation's, as for wall temperature schedules.
 */
#include <math.h>
#include <string.h>

#include "walls/walls.h"

double sinter_wall_drive_value(const sinter_wall *w, double t)
{
    if (w->electric_mode == SINTER_WALL_NEUTRAL)
        return 0.0;
    double value = w->electric_count > 0
                       ? sinter_interpolate(w->electric_count, w->electric_t, w->electric_v, t)
                       : w->electric_set;
    if (w->pulse_off > 0.0 && t >= 0.0) {
        const double period = w->pulse_on + w->pulse_off;
        if (t - period * floor(t / period) >= w->pulse_on)
            value = 0.0; /* off */
    }
    return value;
}

void sinter_wall_drive_free(sinter_walls *walls, sinter_wall *w)
{
    sinter_free(walls->ctx, w->electric_t);
    sinter_free(walls->ctx, w->electric_v);
    w->electric_t = w->electric_v = NULL;
    w->electric_count = 0;
}

sinter_status sinter_walls_set_electric_schedule(sinter_walls *walls, size_t k, size_t n,
                                                 const double *times, const double *values)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (n > 0) {
        SINTER_CHECK_NULL(walls->ctx, times);
        SINTER_CHECK_NULL(walls->ctx, values);
    }
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(times[i]) || !isfinite(values[i]) || (i > 0 && !(times[i] > times[i - 1])))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_set_electric_schedule: point %zu of wall %zu (t = "
                               "%g s, value %g) is invalid: times must increase and values be "
                               "finite",
                               i, k, times[i], values[i]);
    double *t = NULL, *v = NULL;
    if (n > 0 && sinter_copy_table(walls->ctx, n, times, values, &t, &v) != SINTER_OK)
        return SINTER_ERR_NOMEM;
    sinter_wall_drive_free(walls, w);
    w->electric_t = t;
    w->electric_v = v;
    w->electric_count = n;
    w->electric_value = sinter_wall_drive_value(w, walls->time);
    return SINTER_OK;
}

sinter_status sinter_walls_set_electric_pulse(sinter_walls *walls, size_t k, double on, double off)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (!(on > 0.0) || !isfinite(on) || !(off >= 0.0) || !isfinite(off))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_electric_pulse: wall %zu: on = %g s must be > 0 and "
                           "off = %g s >= 0 (0: not pulsed), both finite",
                           k, on, off);
    w->pulse_on = on;
    w->pulse_off = off;
    w->electric_value = sinter_wall_drive_value(w, walls->time);
    return SINTER_OK;
}

sinter_status sinter_walls_set_electric_limit(sinter_walls *walls, size_t k, double limit)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (!(limit >= 0.0) || !isfinite(limit))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_electric_limit: wall %zu: limit %g must be >= 0 "
                           "and finite (0: none)",
                           k, limit);
    w->electric_limit = limit;
    return SINTER_OK;
}
