/* The two-particle reference of a quasi-static scene (io/scene_pair_reference.h). */
#include <math.h>

#include "io/scene_pair_reference.h"
#include "particles/particles.h"

void scene_pair_reference(const sinter_scene *sc, double *q)
{
    q[0] = q[1] = NAN;
    const sinter_particles *ps = sc->ps;
    const sinter_stepper *st = sc->st;
    if (ps->count == 0)
        return;
    double radius = 0.0, temperature = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        radius += ps->radius[i] / (double)ps->count;
        temperature += ps->temperature[i] / (double)ps->count;
    }
    /* the schedule from the origin (the pair touches then): the furnace's points after it,
     * or the particles' mean temperature held (the stepper's own rule without a furnace) */
    const double t0 = sc->program.origin, t = st->time;
    const size_t n = st->furnace_count;
    double *times = sinter_calloc(sc->ctx, 2 * (n + 1), sizeof(double));
    if (times == NULL)
        return;
    double *temps = times + n + 1;
    size_t m = 1;
    times[0] = t0;
    temps[0] = n > 0 ? sinter_interpolate(n, st->furnace, st->furnace + n, t0) : temperature;
    for (size_t k = 0; k < n; ++k)
        if (st->furnace[k] > times[m - 1]) {
            times[m] = st->furnace[k];
            temps[m++] = st->furnace[n + k];
        }
    sinter_neck_model *nm = NULL;
    double x = NAN, shrinkage = NAN;
    const double when = fmax(t, t0);
    if (sinter_neck_model_create(&nm, sc->ctx) == SINTER_OK &&
        sinter_neck_two_particles(nm, &ps->materials[ps->material[0]], radius, radius, m, times,
                                  temps, 1, &when, &x, &shrinkage, NULL) == SINTER_OK) {
        q[0] = x / radius;
        q[1] = shrinkage;
    }
    sinter_neck_model_destroy(nm);
    sinter_free(sc->ctx, times);
}
