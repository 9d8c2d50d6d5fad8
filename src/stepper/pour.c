/* Pour under gravity until the packing is at rest (kinetic energy below a threshold). */
#include <math.h>

#include "stepper.h"

static double kinetic_energy_per_particle(const sinter_particles *ps)
{
    const size_t n = ps->count - ps->ghost_count; /* owned: ghosts are images of them */
    if (n == 0)
        return 0.0;
    double ke = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const double *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        ke += 0.5 * ps->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
              0.5 * ps->inertia[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    return ke / (double)n;
}

sinter_status sinter_pack_pour(sinter_stepper *st, double ke_per_particle, double t_min,
                               double t_max)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (!isfinite(ke_per_particle) || ke_per_particle <= 0.0 || !isfinite(t_min) ||
        !isfinite(t_max) || t_min < 0.0 || t_max < t_min)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_pack_pour: need ke_per_particle > 0 (got %g J) and 0 <= t_min "
                           "<= t_max (got %g s, %g s)",
                           ke_per_particle, t_min, t_max);
    const double start = st->time;
    /* Check the energy every 100 steps. */
    for (;;) {
        const double elapsed = st->time - start;
        const double ke = kinetic_energy_per_particle(st->ps);
        if (elapsed >= t_min && elapsed > 0.0 && ke < ke_per_particle)
            return SINTER_OK;
        if (elapsed >= t_max)
            return sinter_fail(st->ctx, SINTER_ERR_NOT_CONVERGED,
                               "sinter_pack_pour: after %g s the kinetic energy is still %g J "
                               "per particle (threshold %g J); the state is kept",
                               elapsed, ke, ke_per_particle);
        const double next = fmin(start + t_max, st->time + 100.0 * st->dt);
        sinter_status s = sinter_stepper_advance(st, next);
        if (s != SINTER_OK)
            return s;
    }
}
