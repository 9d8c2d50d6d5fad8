/* Helpers for Hertz contacts: the stable explicit step and damping from restitution. */
#include <math.h>

#include "force_model.h"

static const double PI = 3.14159265358979323846;

static double compliance(const sinter_material *m)
{
    const double nu = m->value[SINTER_MAT_POISSON_RATIO];
    return (1.0 - nu * nu) / m->value[SINTER_MAT_YOUNGS_MODULUS];
}

/* Hertz contact duration, seed 003 eq. 47. */
static double contact_time(double mstar, double rstar, double estar, double v)
{
    return 2.87 * pow(mstar * mstar / (rstar * estar * estar * v), 0.2);
}

sinter_status sinter_stable_dt_hertz(const sinter_particles *ps, const sinter_walls *walls,
                                     double v_rel, double *dt)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, dt);
    if (!isfinite(v_rel) || v_rel <= 0.0)
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "sinter_stable_dt_hertz: relative speed %g m/s must be positive", v_rel);
    if (ps->count == 0)
        return sinter_fail(ps->ctx, SINTER_ERR_STATE,
                           "sinter_stable_dt_hertz: the particle set is empty");
    /* Values written through views (material ids index the table below) are checked first. */
    sinter_status st = sinter_particles_validate(ps, NULL);
    if (st != SINTER_OK)
        return st;
    /* The shortest contact: the lightest particle against itself (or a wall), stiffest material. */
    double tmin = INFINITY;
    for (size_t i = 0; i < ps->count; ++i) {
        const sinter_material *mi = &ps->materials[ps->material[i]];
        const double ci = compliance(mi);
        const double t_pp = contact_time(0.5 * ps->mass[i], 0.5 * ps->radius[i], 0.5 / ci, v_rel);
        tmin = fmin(tmin, t_pp);
        for (size_t k = 0; walls != NULL && k < walls->count; ++k) {
            const double estar = 1.0 / (ci + compliance(&walls->wall[k].material));
            tmin = fmin(tmin, contact_time(ps->mass[i], ps->radius[i], estar, v_rel));
        }
    }
    *dt = tmin / 10.0;
    return SINTER_OK;
}

/*
 * For seed 003's damping d = 2 xi sqrt(2 E* m* sqrt(r*)) delta^(1/4) the
 * restitution is independent of the impact speed and, exactly (Antypov &
 * Elliott, EPL 94 (2011) 50004), xi = sqrt(5/6) (-ln e) / sqrt(pi^2 + ln^2 e).
 */
sinter_status sinter_damping_ratio_from_restitution(double e, double *xi)
{
    if (xi == NULL)
        return SINTER_ERR_NULL;
    if (!(e > 0.0 && e <= 1.0))
        return SINTER_ERR_INVALID;
    const double l = log(e);
    *xi = sqrt(5.0 / 6.0) * (-l) / sqrt(PI * PI + l * l);
    return SINTER_OK;
}
