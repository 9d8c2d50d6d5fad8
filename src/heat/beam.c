/*
 * External heating by a vertical beam: fire nozzle (seed 003 eq. 29-30) and laser
 * (eq. 29, 31). Q_i = a_i I0 A_i f(z_i), A_i = pi r_i^2 (frontal area), a_i = the particle
 * material's absorptance, f = 1 - z/d_max for 0 <= z <= d_max and 0 beyond (nozzle, eq. 30),
 * f = exp(-mu z) (laser, Lambert-Beer, eq. 31).
 *
 * What is modelled: the beam points along -z through ("x", "y") with a top-hat profile of
 * radius "radius" and intensity "intensity" I0 [W/m^2]. A particle is lit when the horizontal
 * distance of its CENTRE to the beam axis is <= radius; a lit particle receives its whole
 * frontal area pi r^2, an unlit one nothing. Its depth z_i = (highest top z + r among the lit
 * particles) - (z_i + r_i), measured along the beam from the bed's top surface under the beam
 * (Fig. 1 of the seed). All parameters are read at the evaluation time, so "x", "y",
 * "intensity" (and the rest) may follow schedules: a moving beam.
 *
 * What is not: no shadowing between particles other than through the depth z (a particle in
 * a hollow is attenuated as if the space above it down from the highest lit top were
 * material); no partial illumination of particles cut by the beam's edge; the beam is not
 * depleted by what it deposits, so the sum of the powers may exceed I0 pi radius^2 (eq. 29-31
 * are per-particle laws); walls absorb nothing; no reflection; the direction is fixed (-z).
 *
 * A particle given power (> 0) is marked SINTER_PARTICLE_LIT (never cleared): the particles
 * the beam has targeted so far, whose mean temperature seed 003 sec. 5.4 reports.
 *
 * Defaults: beam on the z axis, radius 5 mm (seed 003 §5.4's 10 mm beam), intensity 0 (off
 * until set), d_max 1 mm, mu 1000 1/m.
 */
#include <math.h>

#include "contact/particle_pass.h"
#include "domain/domain.h"
#include "heat_model.h"
#include "particles/particles.h"

enum { P_X = 0, P_Y, P_RADIUS, P_INTENSITY, P_REACH };

static const double PI = 3.14159265358979323846;

/* 1 if particle i's centre is inside the beam's cylinder. */
static inline int lit(const double *x, size_t i, double bx, double by, double rb2)
{
    const double dx = x[3 * i] - bx, dy = x[3 * i + 1] - by;
    return dx * dx + dy * dy <= rb2;
}

/* One evaluation's beam (the parameters at its time) and, per range of the particle pass
 * (contact/particle_pass.h), the highest top of its lit particles. */
typedef struct beam_job {
    const sinter_particles *ps;
    double *heat;
    uint32_t *flags; /* marked SINTER_PARTICLE_LIT where power is given, or NULL */
    double bx, by, rb2, top, c, reach;
    int laser;
    double range_top[SINTER_CHUNKS_MAX];
} beam_job;

/* Pass 1: the highest top z + r of the lit particles of [lo, hi) (-inf: none). */
static void top_range(void *data, int range, size_t lo, size_t hi)
{
    beam_job *job = data;
    const double *x = job->ps->x, *r = job->ps->radius;
    double top = -HUGE_VAL;
    for (size_t i = lo; i < hi; ++i)
        if (lit(x, i, job->bx, job->by, job->rb2))
            top = fmax(top, x[3 * i + 2] + r[i]);
    job->range_top[range] = top;
}

/* Pass 2: the power of the lit particles (eq. 29-31); `laser` is constant per call. */
static inline void deposit(const beam_job *job, size_t lo, size_t hi, int laser)
{
    const sinter_particles *ps = job->ps;
    const double *x = ps->x, *r = ps->radius;
    const double inv_d = laser ? 0.0 : 1.0 / job->reach;
    for (size_t i = lo; i < hi; ++i) {
        if (!lit(x, i, job->bx, job->by, job->rb2))
            continue;
        const double z = job->top - (x[3 * i + 2] + r[i]);   /* depth along the beam, >= 0 */
        const double f = laser ? exp(-job->reach * z)        /* eq. 31 */
                               : fmax(1.0 - z * inv_d, 0.0); /* eq. 30, 0 beyond d_max */
        const double q =
            sinter_particle_param(ps, i, SINTER_MAT_ABSORPTANCE) * job->c * r[i] * r[i] * f;
        job->heat[i] += q;
        if (q > 0.0 && job->flags != NULL) /* targeted (seed 003 sec. 5.4's "lit" particles) */
            job->flags[i] |= (uint32_t)SINTER_PARTICLE_LIT;
    }
}

static void deposit_range(void *data, int range, size_t lo, size_t hi)
{
    (void)range;
    const beam_job *job = data;
    if (job->laser)
        deposit(job, lo, hi, 1);
    else
        deposit(job, lo, hi, 0);
}

static sinter_status beam_eval(const sinter_heat_model *hm, sinter_heat_eval *e, int laser)
{
    const double bx = sinter_heat_param(hm, P_X, e->time), by = sinter_heat_param(hm, P_Y, e->time);
    const double rb = sinter_heat_param(hm, P_RADIUS, e->time);
    const double i0 = sinter_heat_param(hm, P_INTENSITY, e->time);
    const double reach = sinter_heat_param(hm, P_REACH, e->time); /* d_max or mu */
    if (!(rb >= 0.0) || (laser ? !(reach >= 0.0) : !(reach > 0.0)))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s' at t = %g s: needs radius >= 0 (is %g) and %s (is %g)",
                           hm->name, e->time, rb, laser ? "attenuation >= 0" : "depth > 0", reach);
    /* A_i = pi r_i^2, so a_i I0 A_i f = a_i (pi I0) r_i^2 f. */
    beam_job job = {e->ps,     e->heat, e->flags, bx,    by,   rb * rb,
                    -HUGE_VAL, PI * i0, reach,    laser, {0.0}};
    /* Pass 1: the bed's top surface under the beam (a maximum: the same for any split). */
    const int ranges = sinter_particle_pass(e->ctx, e->pp, sinter_heat_owned(e), top_range, &job);
    for (int k = 0; k < ranges; ++k)
        job.top = fmax(job.top, job.range_top[k]);
    /* across subdomains the top is every subdomain's: a maximum, the same bits as one domain's */
    if (e->domain != NULL) {
        const sinter_status s = sinter_domain_reduce(e->ctx, e->domain, &job.top, 1,
                                                     SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
        if (s != SINTER_OK)
            return s;
    }
    if (job.top == -HUGE_VAL)
        return SINTER_OK; /* nothing under the beam */
    sinter_particle_pass(e->ctx, e->pp, sinter_heat_owned(e), deposit_range, &job);
    return SINTER_OK;
}

static sinter_status nozzle_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    return beam_eval(hm, e, 0);
}

static sinter_status laser_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    return beam_eval(hm, e, 1);
}

const sinter_heat_ops sinter_heat_nozzle = {
    "nozzle",    0,   {"x", "y", "radius", "intensity", "depth", NULL}, {0.0, 0.0, 5e-3, 0.0, 1e-3},
    nozzle_eval, NULL};

const sinter_heat_ops sinter_heat_laser = {"laser",
                                           0,
                                           {"x", "y", "radius", "intensity", "attenuation", NULL},
                                           {0.0, 0.0, 5e-3, 0.0, 1e3},
                                           laser_eval,
                                           NULL};
