/*
 * Sanity checks of the steppers (issue 10): a starting state that cannot be simulated is
 * refused, and a trial step that shows an instability is rejected with a message naming the
 * particle or pair, the quantity and the time. The caller keeps the last accepted state.
 *
 * Why these criteria (each must not fire on a sound run, and must catch a blow-up early):
 *
 * 1. A particle centre behind a wall. Walls are one-sided planes; a particle whose centre is
 *    on the far side is in contact with an overlap above its radius and is thrown out with an
 *    enormous force (the wall contact is evaluated as r - s for every s < r). At the start this
 *    is bad input (SINTER_ERR_INVALID). During a run the particle can only have got there by
 *    passing through the plane in one step, which is a step far too large for its speed
 *    (SINTER_ERR_LOST_PARTICLE: it has left the region the walls bound).
 *
 * 2. Overlap growth per step. An explicit (or implicit) step resolves a contact only when the
 *    contact lasts several steps. For a Hertz impact at normal speed v the largest overlap is
 *    delta_max and the contact lasts t_c = 2.94 delta_max / v; at the stable step of seed 003
 *    eq. 47, t_c / 10, the overlap grows by at most v t_c / 10 = 0.29 delta_max per step, and
 *    every contact law in the library assumes delta_max << R. Growth by more than
 *    SINTER_SANITY_APPROACH_LIMIT = R_min / 2 in one step means that the pair went from (at
 *    most) touching to half a radius deep without a single step in between at which the
 *    contact force could act: the collision is not resolved at all (the pair is then thrown
 *    apart with energy it never had, or tunnels through). The limit is set by the scenes: the
 *    pour of the press scene (seed 000 sec. 7) at its own steps reaches 0.09 R_min per step
 *    (explicit, 1 ms) and 0.20 R_min (staggered, 5 ms), and 0.5 leaves a margin of 2.5. The
 *    test is on the growth, not on the overlap itself: deep but slowly reached overlaps are
 *    legitimate (a packing created overlapping; the press scene compacts to overlaps of
 *    1.9 R_min), and a limit on the overlap would stop them. What this does not catch: a step
 *    only a few times too large, at which Verlet injects energy into each collision without
 *    a deep jump (tests/bench/RESULTS.md, "Hard cases"); such runs are stopped by the
 *    finiteness check or the domain box once they blow up.
 *    Cost: one pass over the particles (displacement in the step, smallest radius); only when
 *    a particle moved more than R_min / 4 (two of them can then close R_min / 2), or a wall
 *    and a particle together more than R_min / 2, the contacts are examined, each with its
 *    overlap at the start of the step recomputed from x_old.
 *
 * 3. Temperature. A free temperature must stay positive, finite and at most
 *    SINTER_SANITY_MAX_TEMPERATURE = 1e5 K: 17 times the boiling point of tungsten (5828 K),
 *    so no solid-state sintering, contact or heat law applies; it is reached only by runaway
 *    heating (Joule heating with a current far too large for the packing, or a step too large
 *    for the heat submodels). One pass over the temperatures, only with heat submodels.
 *    (The explicit thermal update already refuses a non-positive or non-finite temperature
 *    and quotes the stable thermal step; this check also covers the implicit schemes.)
 */
#include <math.h>

#include "contact/particle_pass.h"
#include "sanity.h"
#include "stepper.h"

/* The wall's normal, point and the particle's position, for messages. */
sinter_status sinter_sanity_start(struct sinter_stepper *st)
{
    const sinter_particles *ps = st->ps;
    const sinter_contact_list *pw = &st->pw;
    for (size_t k = 0; k < pw->count && st->walls != NULL; ++k) {
        if (!(pw->dist[k] < 0.0))
            continue;
        const size_t i = pw->i[k], j = pw->j[k];
        const sinter_wall *w = &st->walls->wall[j];
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "particle %zu (id %llu) is behind wall %zu: its centre is %g m on the "
                           "wrong side of the plane through (%g, %g, %g) m with normal (%g, %g, "
                           "%g); particles must start on the side the normal points to (it would "
                           "be thrown out with an overlap of %g m)",
                           i, (unsigned long long)ps->id[i], j, -pw->dist[k], w->p[0], w->p[1],
                           w->p[2], w->n[0], w->n[1], w->n[2], pw->delta[k]);
    }
    /* Coincident centres: the contact search skips them (the normal is undefined). */
    const sinter_pair_list *pairs = &st->nb.pp;
    const double *x = ps->x;
    for (size_t p = 0; p < pairs->count; ++p) {
        const size_t i = pairs->i[p], j = pairs->j[p];
        if (x[3 * i] == x[3 * j] && x[3 * i + 1] == x[3 * j + 1] && x[3 * i + 2] == x[3 * j + 2])
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "particles %zu and %zu (ids %llu and %llu) have the same centre "
                               "(%g, %g, %g) m: their contact normal is undefined and the "
                               "overlap would be ignored; move one of them",
                               i, j, (unsigned long long)ps->id[i],
                               (unsigned long long)ps->id[j], x[3 * i], x[3 * i + 1],
                               x[3 * i + 2]);
    }
    return SINTER_OK;
}

static double distance(const double *a, const double *b)
{
    const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* Criterion 2 on the contacts, once the cheap test has tripped. */
static sinter_status check_approach(struct sinter_stepper *st, const double *x_old, double t,
                                    double h)
{
    const sinter_particles *ps = st->ps;
    const double *x = ps->x, *r = ps->radius;
    const double limit = SINTER_SANITY_APPROACH_LIMIT;
    double worst = limit, growth = 0.0;
    size_t worst_k = SIZE_MAX;
    int wall = 0;
    sinter_contacts_geometry(st->ctx, &st->pp, ps); /* a lean list gets its overlaps */
    const sinter_contact_list *pp = &st->pp;
    for (size_t k = 0; k < pp->count; ++k) {
        const size_t i = pp->i[k], j = pp->j[k];
        const double rmin = fmin(r[i], r[j]);
        if (!(pp->delta[k] > limit * rmin))
            continue; /* cannot have grown by more */
        const double before = fmax(r[i] + r[j] - distance(x_old + 3 * i, x_old + 3 * j), 0.0);
        const double ratio = (pp->delta[k] - before) / rmin;
        if (ratio > worst) {
            worst = ratio;
            worst_k = k;
            growth = pp->delta[k] - before;
        }
    }
    const sinter_contact_list *pw = &st->pw;
    for (size_t k = 0; k < pw->count && st->walls != NULL; ++k) {
        const size_t i = pw->i[k];
        if (!(pw->delta[k] > limit * r[i]))
            continue;
        /* the wall at t, from its velocity (exact for a constant velocity) */
        const sinter_wall *w = &st->walls->wall[pw->j[k]];
        double s_old = 0.0;
        for (int d = 0; d < 3; ++d)
            s_old += (x_old[3 * i + d] - (w->p[d] - h * w->u[d])) * w->n[d];
        const double before = fmax(r[i] - s_old, 0.0);
        const double ratio = (pw->delta[k] - before) / r[i];
        if (ratio > worst) {
            worst = ratio;
            worst_k = k;
            growth = pw->delta[k] - before;
            wall = 1;
        }
    }
    if (worst_k == SIZE_MAX)
        return SINTER_OK;
    const sinter_contact_list *c = wall ? pw : pp;
    const size_t i = c->i[worst_k], j = c->j[worst_k];
    const double vn = distance(x + 3 * i, x_old + 3 * i) / h;
    if (wall)
        return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                           "step from t = %.9g s to %.9g s rejected: the overlap of particle %zu "
                           "(id %llu) with wall %zu grew by %g m in one step, %.3g of its radius "
                           "(limit %g), to %g m, the particle moving at %g m/s: the contact is "
                           "not resolved; the time step %g s is too large for the contact stiffness or the impact speed "
                           "(see sinter_stable_dt_hertz). The last accepted state is kept.",
                           t, t + h, i, (unsigned long long)ps->id[i], j, growth, worst, limit,
                           c->delta[worst_k], vn, h);
    return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                       "step from t = %.9g s to %.9g s rejected: the overlap of particles %zu and "
                       "%zu (ids %llu and %llu) grew by %g m in one step, %.3g of the smaller "
                       "radius (limit %g), to %g m: the contact is not resolved; the time step %g "
                       "s is too large for the contact stiffness or the impact speed (see "
                       "sinter_stable_dt_hertz). The last accepted state is kept.",
                       t, t + h, i, j, (unsigned long long)ps->id[i], (unsigned long long)ps->id[j],
                       growth, worst, limit, c->delta[worst_k], h);
}

/* The cheap measure of criterion 2 when no integrator pass made it. */
static sinter_sanity_scan scan_step(const sinter_particles *ps, const double *x_old)
{
    sinter_sanity_scan m = {0.0, INFINITY};
    for (size_t i = 0; i < ps->count; ++i) {
        const double *a = ps->x + 3 * i, *b = x_old + 3 * i;
        const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
        /* plain comparisons (not fmax/fmin, which are library calls here): the loop runs
         * every step; a non-finite position is rejected by the stepper's own test */
        const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        m.moved2 = dd > m.moved2 ? dd : m.moved2;
        m.rmin = ps->radius[i] < m.rmin ? ps->radius[i] : m.rmin;
    }
    return m;
}

sinter_status sinter_sanity_step(struct sinter_stepper *st, const double *x_old, double t,
                                 double h, const sinter_sanity_scan *scan)
{
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    /* 1. through a wall */
    const sinter_contact_list *pw = &st->pw;
    for (size_t k = 0; k < pw->count && st->walls != NULL; ++k) {
        if (!(pw->dist[k] < 0.0))
            continue;
        const size_t i = pw->i[k], j = pw->j[k];
        const double moved = distance(ps->x + 3 * i, x_old + 3 * i);
        return sinter_fail(st->ctx, SINTER_ERR_LOST_PARTICLE,
                           "step from t = %.9g s to %.9g s rejected: particle %zu (id %llu) "
                           "passed through wall %zu: its centre is %g m behind the plane after "
                           "moving %g m in one step; the time step %g s is too large for its "
                           "speed. The last accepted state is kept.",
                           t, t + h, i, (unsigned long long)ps->id[i], j,
                           -sinter_wall_distance(&st->walls->wall[j], ps->x + 3 * i), moved, h);
    }
    /* 2. overlap growth: the cheap test first (a pair closes at most twice the largest
     * displacement, a wall contact at most the displacement plus the wall's) */
    const sinter_sanity_scan m = scan != NULL ? *scan : scan_step(ps, x_old);
    const double moved2 = m.moved2, rmin = m.rmin;
    double wall_moved = 0.0;
    for (size_t k = 0; st->walls != NULL && k < st->walls->count; ++k) {
        const double *u = st->walls->wall[k].u;
        wall_moved = fmax(wall_moved, h * sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    }
    const double moved = sqrt(moved2), gap = SINTER_SANITY_APPROACH_LIMIT * rmin;
    if (n > 0 && (2.0 * moved > gap || moved + wall_moved > gap)) {
        const sinter_status s = check_approach(st, x_old, t, h);
        if (s != SINTER_OK)
            return s;
    }
    /* 3. temperatures (the explicit update of this step took the test in its own pass) */
    if (st->thermal.count == 0)
        return SINTER_OK;
    sinter_thermal *th = &st->thermal;
    const size_t from = th->hot_checked ? th->hot : 0;
    th->hot_checked = 0;
    for (size_t i = from; i < n; ++i) {
        const double theta = ps->temperature[i];
        if (theta > 0.0 && theta <= SINTER_SANITY_MAX_TEMPERATURE)
            continue;
        if (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE)
            continue;
        return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                           "step from t = %.9g s to %.9g s rejected: the temperature of particle "
                           "%zu (id %llu) became %g K (it must stay above 0 and at most %g K): "
                           "runaway heating (Joule heating or a heat source far too strong, or a "
                           "step too large for the heat submodels). The last accepted state is "
                           "kept.",
                           t, t + h, i, (unsigned long long)ps->id[i], theta,
                           SINTER_SANITY_MAX_TEMPERATURE);
    }
    /* 4. melting: only when a material in use has a melting point (no melting model) */
    int melts = 0;
    for (int id = 0; id < ps->material_top; ++id)
        melts |=
            ps->material_used[id] && ps->materials[id].value[SINTER_MAT_MELTING_TEMPERATURE] > 0.0;
    for (size_t i = 0; melts && i < n; ++i) {
        const sinter_material *mat = &ps->materials[ps->material[i]];
        const double melt = mat->value[SINTER_MAT_MELTING_TEMPERATURE];
        if (!(melt > 0.0 && ps->temperature[i] > melt) ||
            (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE))
            continue;
        return sinter_fail(st->ctx, SINTER_ERR_DOMAIN,
                           "step from t = %.9g s to %.9g s rejected: particle %zu (id %llu) "
                           "reached %g K, above the melting point %g K of its material %d "
                           "('%s', melting_temperature); libsinter has no melting model (no "
                           "latent heat, no liquid). The last accepted state is kept.",
                           t, t + h, i, (unsigned long long)ps->id[i], ps->temperature[i], melt,
                           (int)ps->material[i], mat->name);
    }
    return SINTER_OK;
}

/* The domain's test (option domain_min / domain_max) of particles [lo, hi): the first one
 * whose centre is not inside the box (a non-finite one is not), or SIZE_MAX. Batches of
 * particles are tested without branches, and only a batch with one outside is searched. */
typedef struct domain_job {
    const sinter_stepper *st;
    size_t first[SINTER_CHUNKS_MAX];
} domain_job;

enum { DOMAIN_BATCH = 64 };

static inline int outside(const double *x, const double *a, const double *b, int d)
{
    return !(x[d] >= a[d]) | !(x[d] <= b[d]);
}

static void domain_range(void *data, int range, size_t lo, size_t hi)
{
    domain_job *job = data;
    const double *x = job->st->ps->x, *a = job->st->domain_lo, *b = job->st->domain_hi;
    job->first[range] = SIZE_MAX;
    for (size_t i0 = lo; i0 < hi; i0 += DOMAIN_BATCH) {
        const size_t i1 = hi - i0 < DOMAIN_BATCH ? hi : i0 + DOMAIN_BATCH;
        int out = 0;
        for (size_t i = i0; i < i1; ++i)
            out |= outside(x + 3 * i, a, b, 0) | outside(x + 3 * i, a, b, 1) |
                   outside(x + 3 * i, a, b, 2);
        if (!out)
            continue;
        for (size_t i = i0; i < i1; ++i)
            if (outside(x + 3 * i, a, b, 0) | outside(x + 3 * i, a, b, 1) |
                outside(x + 3 * i, a, b, 2)) {
                job->first[range] = i;
                return;
            }
    }
}

static size_t first_outside(const sinter_stepper *st)
{
    domain_job job = {st, {0}};
    const int ranges =
        sinter_particle_pass(st->ctx, &st->pp, st->ps->count, domain_range, &job);
    for (int k = 0; k < ranges; ++k)
        if (job.first[k] != SIZE_MAX)
            return job.first[k];
    return st->ps->count;
}

sinter_status sinter_sanity_domain(sinter_stepper *st, const char *step, double t, double h)
{
    const sinter_particles *ps = st->ps;
    if (!st->has_domain)
        return SINTER_OK;
    const size_t i = first_outside(st);
    if (i == ps->count)
        return SINTER_OK;
    const double *x = ps->x + 3 * i;
    int d = 0;
    while (d < 3 && x[d] >= st->domain_lo[d] && x[d] <= st->domain_hi[d])
        ++d;
    return sinter_fail(st->ctx, SINTER_ERR_LOST_PARTICLE,
                       "%s from t = %.9g s to %.9g s rejected: particle %zu (id %llu) left the "
                       "domain at %c = %g m (domain %g m to %g m); the last accepted state is "
                       "kept",
                       step, t, t + h, i, (unsigned long long)ps->id[i], "xyz"[d], x[d],
                       st->domain_lo[d], st->domain_hi[d]);
}
