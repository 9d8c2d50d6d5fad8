/* Heat at its own pace over a frozen bed (issue 41): see frozen_heat.h. */
#include <math.h>
#include <string.h>

#include "contact/contacts.h"
#include "domain/domain.h"
#include "stepper/frozen_heat.h"
#include "stepper/sanity.h"
#include "stepper/stepper.h"
#include "walls/walls.h"

/* Step control of the heat steps (frozen_heat.h): safety factor, bounds of the change. */
#define FROZEN_SAFETY 0.9
#define FROZEN_GROW 5.0
#define FROZEN_SHRINK 0.2
/* The first heat step after a freeze: this many mechanical steps (the controller grows it). */
#define FROZEN_FIRST_STEPS 10.0

void sinter_frozen_init(sinter_frozen *fz)
{
    memset(fz, 0, sizeof(*fz));
    fz->ke = 1e-12;
    fz->rtol = 1e-4;
    fz->atol = 1e-2;
    fz->dt_max = 0.0;
    fz->travel = 0.05;
    fz->wake = 0.01;
    fz->settle_steps = 1000;
    fz->ke_last = INFINITY;
}

void sinter_frozen_free(sinter_ctx *ctx, sinter_frozen *fz)
{
    sinter_free(ctx, fz->rate);
    sinter_free(ctx, fz->scale0);
    fz->rate = fz->scale0 = NULL;
    fz->capacity = 0;
}

static const char *const OPTIONS[] = {"frozen_heat",   "frozen_ke",     "frozen_rtol",
                                      "frozen_atol",   "frozen_dt_max", "frozen_wake",
                                      "frozen_settle", "frozen_travel"};
static const char *const STATISTICS[] = {"frozen_time",    "frozen_steps",   "frozen_rejected",
                                         "frozen_wakeups", "frozen_freezes", "frozen_active",
                                         "frozen_dt"};

int sinter_frozen_is_key(const char *key)
{
    for (size_t k = 0; k < sizeof(OPTIONS) / sizeof(OPTIONS[0]); ++k)
        if (strcmp(key, OPTIONS[k]) == 0)
            return 1;
    for (size_t k = 0; k < sizeof(STATISTICS) / sizeof(STATISTICS[0]); ++k)
        if (strcmp(key, STATISTICS[k]) == 0)
            return 1;
    return 0;
}

sinter_status sinter_frozen_set(sinter_stepper *st, const char *key, double value)
{
    sinter_frozen *fz = &st->frozen;
    const char *need = NULL;
    if (strcmp(key, "frozen_heat") == 0) {
        if (value == 0.0 || value == 1.0) {
            if (st->kind != SINTER_STEPPER_EXPLICIT && value == 1.0)
                return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                                   "sinter_stepper_set_option: frozen_heat needs the explicit "
                                   "stepper (the others step heat and mechanics together)");
            fz->enabled = (int)value;
            return SINTER_OK;
        }
        need = "0 or 1";
    } else if (strcmp(key, "frozen_ke") == 0 || strcmp(key, "frozen_rtol") == 0 ||
               strcmp(key, "frozen_atol") == 0 || strcmp(key, "frozen_wake") == 0) {
        if (isfinite(value) && value > 0.0) {
            double *slot = key[7] == 'k'   ? &fz->ke
                           : key[7] == 'r' ? &fz->rtol
                           : key[7] == 'a' ? &fz->atol
                                           : &fz->wake;
            *slot = value;
            return SINTER_OK;
        }
        need = "finite and > 0";
    } else if (strcmp(key, "frozen_dt_max") == 0) {
        if (isfinite(value) && value >= 0.0) {
            fz->dt_max = value;
            return SINTER_OK;
        }
        need = "finite and >= 0 s (0: no limit)";
    } else if (strcmp(key, "frozen_travel") == 0) {
        if (isfinite(value) && value >= 0.0) {
            fz->travel = value;
            return SINTER_OK;
        }
        need = "finite and >= 0 radii (0: no limit)";
    } else if (strcmp(key, "frozen_settle") == 0) {
        if (value >= 0.0 && value <= 1e15 && value == floor(value)) {
            fz->settle_steps = (uint64_t)value;
            return SINTER_OK;
        }
        need = "a whole number of steps >= 0";
    } else {
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: '%s' is a statistic of the frozen heat "
                           "stage and cannot be set",
                           key);
    }
    return sinter_fail(st->ctx, SINTER_ERR_INVALID, "sinter_stepper_set_option: %s = %g must be %s",
                       key, value, need);
}

sinter_status sinter_frozen_get(const sinter_stepper *st, const char *key, double *value)
{
    const sinter_frozen *fz = &st->frozen;
    const struct {
        const char *key;
        double value;
    } table[] = {{"frozen_heat", fz->enabled},
                 {"frozen_ke", fz->ke},
                 {"frozen_rtol", fz->rtol},
                 {"frozen_atol", fz->atol},
                 {"frozen_dt_max", fz->dt_max},
                 {"frozen_wake", fz->wake},
                 {"frozen_settle", (double)fz->settle_steps},
                 {"frozen_travel", fz->travel},
                 {"frozen_time", fz->time},
                 {"frozen_steps", (double)fz->steps},
                 {"frozen_rejected", (double)fz->rejected},
                 {"frozen_wakeups", (double)fz->wakeups},
                 {"frozen_freezes", (double)fz->freezes},
                 {"frozen_active", fz->active},
                 {"frozen_dt", fz->h}};
    for (size_t k = 0; k < sizeof(table) / sizeof(table[0]); ++k)
        if (strcmp(key, table[k].key) == 0) {
            *value = table[k].value;
            return SINTER_OK;
        }
    return sinter_fail(st->ctx, SINTER_ERR_INVALID, "sinter_stepper_get_option: unknown key '%s'",
                       key);
}

/* The kinetic energy per particle of the owned particles (across subdomains: of every
 * subdomain's, their sums and counts reduced, so that every subdomain takes the same decision;
 * on one subdomain the bits of the sum without domain operations). */
static sinter_status kinetic_energy_per_particle(sinter_stepper *st, double *out)
{
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    double sum[2] = {0.0, (double)owned}; /* energy, particles */
    for (size_t i = 0; i < owned; ++i) {
        const double *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        sum[0] += 0.5 * ps->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
                  0.5 * ps->inertia[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    const sinter_status s = sinter_domain_sum(st->ctx, &st->domain, sum, 2);
    *out = sum[1] > 0.0 ? sum[0] / sum[1] : 0.0;
    return s;
}

/* The largest of v over every subdomain (v itself without domain operations). */
static sinter_status domain_max(sinter_stepper *st, double *v)
{
    if (!st->domain.on)
        return SINTER_OK;
    return sinter_domain_reduce(st->ctx, &st->domain, v, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
}

static int fixed_temperature(const sinter_particles *ps, size_t i)
{
    return (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE) != 0;
}

/* A wall moves at t or at t + h (its point or velocity not those of a wall at rest). */
static int walls_move_within(sinter_stepper *st, double h, sinter_status *s)
{
    sinter_walls *walls = st->walls;
    *s = SINTER_OK;
    if (walls == NULL)
        return 0;
    for (size_t k = 0; k < walls->count; ++k) {
        const sinter_wall *w = &walls->wall[k];
        if (w->u[0] != 0.0 || w->u[1] != 0.0 || w->u[2] != 0.0)
            return 1;
    }
    double p[3 * 64];
    const size_t nw = walls->count < 64 ? walls->count : 64;
    for (size_t k = 0; k < nw; ++k)
        memcpy(p + 3 * k, walls->wall[k].p, sizeof(walls->wall[k].p));
    *s = sinter_walls_move(walls, st->time + h); /* also the wall temperatures of t + h */
    if (*s != SINTER_OK)
        return 0;
    for (size_t k = 0; k < walls->count; ++k) {
        const sinter_wall *w = &walls->wall[k];
        if (k >= nw || memcmp(p + 3 * k, w->p, sizeof(w->p)) != 0 || w->u[0] != 0.0 ||
            w->u[1] != 0.0 || w->u[2] != 0.0)
            return 1;
    }
    return 0;
}

/* The rates at a freeze: the last evaluation's powers (ps->heat) over m C. */
static sinter_status begin_freeze(sinter_stepper *st)
{
    sinter_frozen *fz = &st->frozen;
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    if (n + 1 > fz->capacity) {
        double *r = sinter_realloc_array(st->ctx, fz->rate, n + 1, sizeof(double));
        if (r == NULL)
            return sinter_last_status(st->ctx);
        fz->rate = r;
        double *q = sinter_realloc_array(st->ctx, fz->scale0, n + 1, sizeof(double));
        if (q == NULL)
            return sinter_last_status(st->ctx);
        fz->scale0 = q;
        fz->capacity = n + 1;
    }
    for (size_t i = 0; i < n; ++i) {
        const double mc = ps->mass[i] * sinter_particle_heat_capacity(ps, i, ps->temperature[i]);
        fz->rate[i] = fixed_temperature(ps, i) || !(mc > 0.0) ? 0.0 : ps->heat[i] / mc;
    }
    const double *scale = NULL;
    sinter_status s = sinter_thermal_softening(st, &scale);
    if (s != SINTER_OK)
        return s;
    fz->has_scale = scale != NULL;
    if (scale != NULL)
        memcpy(fz->scale0, scale, n * sizeof(double));
    if (!(fz->h > 0.0))
        fz->h = FROZEN_FIRST_STEPS * st->dt;
    fz->active = 1;
    fz->freezes++;
    sinter_log(st->ctx, SINTER_LOG_DEBUG,
               "frozen heat: mechanics at rest at t = %.9g s, heat steps from %g s", st->time,
               fz->h);
    return SINTER_OK;
}

/* The stage applies: the option on, the explicit stepper, heat models, no electric model. */
static int stage_applies(const sinter_stepper *st)
{
    /* (not with periodic images: its heat steps do not keep them in step with their owners) */
    return st->frozen.enabled && st->kind == SINTER_STEPPER_EXPLICIT && st->thermal.count > 0 &&
           st->electric == NULL && !sinter_ghosts_on(&st->ghosts);
}

sinter_status sinter_frozen_consider(sinter_stepper *st)
{
    sinter_frozen *fz = &st->frozen;
    if (fz->active || !stage_applies(st))
        return SINTER_OK;
    if (++fz->mech_steps < fz->settle_steps)
        return SINTER_OK;
    /* below the threshold and not growing: a bed released from rest is not at rest */
    double ke = 0.0;
    sinter_status s = kinetic_energy_per_particle(st, &ke);
    if (s != SINTER_OK)
        return s;
    const double last = fz->ke_last;
    fz->ke_last = ke;
    if (ke >= fz->ke || !(last < INFINITY) || ke > last)
        return SINTER_OK;
    if (walls_move_within(st, st->dt, &s) || s != SINTER_OK) {
        if (s == SINTER_OK)
            s = st->walls ? sinter_walls_move(st->walls, st->time) : SINTER_OK;
        return s;
    }
    s = st->walls ? sinter_walls_move(st->walls, st->time) : SINTER_OK;
    if (s == SINTER_OK)
        s = begin_freeze(st);
    /* across subdomains every one freezes, or none (a failure is agreed) */
    return sinter_domain_agree(st->ctx, &st->domain, s);
}

static void wake(sinter_stepper *st, const char *why)
{
    sinter_frozen *fz = &st->frozen;
    fz->active = 0;
    fz->mech_steps = 0;
    fz->ke_last = INFINITY;
    fz->wakeups++;
    st->forces_current = 0; /* the caller evaluates the forces of the new temperatures */
    sinter_log(st->ctx, SINTER_LOG_DEBUG, "frozen heat: mechanics woken at t = %.9g s (%s)",
               st->time, why);
}

int sinter_frozen_release(sinter_stepper *st)
{
    if (!st->frozen.active || stage_applies(st))
        return 0;
    wake(st, "the frozen heat stage no longer applies (option frozen_heat off)");
    return 1;
}

/* The error of the update just made (theta_backup -> temperature over h), frozen_heat.h: of
 * the owned particles (the largest over every subdomain: domain_max). */
static double step_error(const sinter_stepper *st, double h)
{
    const sinter_frozen *fz = &st->frozen;
    const sinter_particles *ps = st->ps;
    const double *theta0 = st->thermal.theta_backup, *theta1 = ps->temperature;
    double err = 0.0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i) {
        if (!(theta1[i] > 0.0 && theta1[i] <= SINTER_SANITY_MAX_TEMPERATURE))
            return INFINITY;
        if (fixed_temperature(ps, i))
            continue;
        const double r1 = (theta1[i] - theta0[i]) / h;
        const double e = 0.5 * h * fabs(r1 - fz->rate[i]);
        const double w = fz->atol + fz->rtol * fmax(fabs(theta0[i]), fabs(theta1[i]));
        err = fmax(err, e / w);
    }
    return err;
}

static double step_factor(double err)
{
    const double f = err > 0.0 ? FROZEN_SAFETY / sqrt(err) : FROZEN_GROW;
    return fmin(FROZEN_GROW, fmax(FROZEN_SHRINK, f));
}

/* 1 if a particle's modulus factor left the band of wake-up around its value at the freeze. */
static int softened(sinter_stepper *st, sinter_status *s)
{
    const sinter_frozen *fz = &st->frozen;
    const double *scale = NULL;
    *s = SINTER_OK;
    if (!fz->has_scale)
        return 0;
    *s = sinter_thermal_softening(st, &scale);
    if (*s != SINTER_OK || scale == NULL)
        return 0;
    double moved = 0.0; /* of the owned particles, then over every subdomain */
    for (size_t i = 0; i < st->ps->count - st->ps->ghost_count && moved == 0.0; ++i)
        if (fabs(scale[i] - fz->scale0[i]) > fz->wake * fz->scale0[i])
            moved = 1.0;
    *s = domain_max(st, &moved);
    return *s == SINTER_OK && moved != 0.0;
}

/* Backward Euler over h from st->time (the walls already at t + h). */
static sinter_status heat_update(sinter_stepper *st, double h)
{
    sinter_thermal *th = &st->thermal;
    const int scheme = th->scheme;
    th->scheme = SINTER_THERMAL_IMPLICIT;
    st->view.time = st->time;
    const double t0 = sinter_clock();
    /* the contacts of the frozen positions, from the neighbour lists (which a checkpoint
     * carries, unlike the contact lists: a restored run finds the same) */
    sinter_status s = sinter_contacts_find_pp(st->ctx, &st->pp, &st->nb.pp, st->ps);
    if (s == SINTER_OK && st->walls != NULL)
        s = sinter_contacts_find_pw(st->ctx, &st->pw, &st->nb.pw, st->ps, st->walls,
                                    &st->pp.chunks);
    /* across subdomains the evaluation is collective (the beams): agreed first; the solve
     * agrees again (thermal.c), and the ghosts take their owners' new temperatures */
    s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK)
        s = sinter_domain_agree(st->ctx, &st->domain, sinter_thermal_eval(st));
    if (s == SINTER_OK)
        s = sinter_thermal_implicit_advance(st, h);
    if (s == SINTER_OK && st->domain.on)
        s = sinter_domain_agree(st->ctx, &st->domain,
                                sinter_domain_forward(st->ctx, &st->domain, st->ps));
    st->stats_seconds_heat += sinter_clock() - t0;
    th->scheme = scheme;
    return s;
}

/* The proposal h shortened so that no heat source's axis point travels more than
 * `frozen_travel` smallest radii over it (frozen_heat.h); at least h_floor. */
static double travel_limit(sinter_stepper *st, double h, double h_floor)
{
    const sinter_frozen *fz = &st->frozen;
    if (fz->travel <= 0.0)
        return h;
    const sinter_particles *ps = st->ps;
    double rmin = INFINITY;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i)
        rmin = ps->radius[i] < rmin ? ps->radius[i] : rmin;
    if (st->domain.on) { /* every subdomain's smallest (a reduction failing on every one) */
        double neg = -rmin;
        if (domain_max(st, &neg) != SINTER_OK)
            return h;
        rmin = -neg;
    }
    const double reach = fz->travel * rmin;
    if (!(reach < INFINITY))
        return h;
    for (size_t k = 0; k < st->thermal.count; ++k)
        for (int pass = 0; pass < 3 && h > h_floor; ++pass) { /* the chord of a bend: again */
            const double d = sinter_heat_axis_travel(st->thermal.slots[k].model, st->time, h);
            if (!(d > reach))
                break;
            h = fmax(h * (reach / d), h_floor);
        }
    return h;
}

sinter_status sinter_frozen_step(sinter_stepper *st, double t_end, double *taken, int *woke)
{
    sinter_frozen *fz = &st->frozen;
    *taken = 0.0;
    *woke = 0;
    const double h_floor = st->dt; /* no heat step below the mechanical one */
    for (;;) {
        double proposal = fz->h;
        if (fz->dt_max > 0.0)
            proposal = fmin(proposal, fz->dt_max);
        proposal = travel_limit(st, fmax(proposal, h_floor), h_floor);
        const double remaining = t_end - st->time;
        const int lands = remaining <= proposal * (1.0 + 1e-6);
        const double h = lands ? remaining : proposal;
        sinter_status s;
        if (walls_move_within(st, h, &s) || s != SINTER_OK) {
            if (s == SINTER_OK)
                wake(st, "a wall moves");
            *woke = s == SINTER_OK;
            return s;
        }
        s = heat_update(st, h);
        if (s != SINTER_OK)
            return s;
        double err = step_error(st, h);
        if ((s = domain_max(st, &err)) != SINTER_OK)
            return s;
        if (err > 1.0 && h > h_floor) {
            sinter_thermal_rollback(st);
            fz->rejected++;
            fz->h = h * step_factor(err);
            continue;
        }
        if (!isfinite(err)) {
            sinter_thermal_rollback(st);
            return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                               "frozen heat step of %g s at t = %g s gave a temperature that is "
                               "not positive or above the sanity limit, at the smallest step",
                               h, st->time);
        }
        const double *theta0 = st->thermal.theta_backup;
        for (size_t i = 0; i < st->ps->count - st->ps->ghost_count; ++i)
            fz->rate[i] =
                fixed_temperature(st->ps, i) ? 0.0 : (st->ps->temperature[i] - theta0[i]) / h;
        st->time = lands ? t_end : st->time + h;
        fz->time += h;
        fz->steps++;
        fz->h = h * step_factor(err);
        if (lands && fz->h < proposal)
            fz->h = proposal; /* a step shortened to land says nothing against the proposal */
        *taken = h;
        if (softened(st, &s)) {
            wake(st, "thermal softening changed a modulus");
            *woke = 1;
        }
        return s;
    }
}
