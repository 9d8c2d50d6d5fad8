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
 *
 * 4. Energy created (explicit stepper, issue 35). A damped contact cannot give back more
 *    energy than it took, so in one step a particle can gain kinetic energy (translation and
 *    spin) only from the work of gravity, body forces and the drag's moving medium, of a
 *    moving wall, and from the elastic energy its contacts release. A step far above the
 *    stable one breaks this at once: a sphere resting on a floor at 100 times its stable step
 *    drifts into an overlap it never had, and the force there throws it out with 24 times
 *    the elastic energy of that overlap in the same step (the explicit stepper kicks with the
 *    force at the end of the step). The test: a particle whose kinetic energy more than
 *    doubled in the step beyond the work of the body forces, and by more than
 *    SINTER_SANITY_ENERGY_FACTOR = 2 times the elastic energy of its contacts at t plus that
 *    at t + h, is rejected. The factor covers what the elastic energy here leaves out (the
 *    tangential and rolling springs of Mindlin's friction) and the energy a sound step passes
 *    on from a partner within the step: at the peak of a Hertz collision a step of t_c / 10
 *    moves 0.4 times the contact's energy, so that one step of t_c (far beyond the stable
 *    step, about 0.6 t_c) fires. The doubling requirement keeps the test on growth: a fast
 *    particle is not examined for a small relative gain. The gain is that of the particle's
 *    cluster, it and its contact partners, in their centre-of-mass frame (or the walls' frame
 *    when one of them touches a wall or is fixed): energy passed on between them within the
 *    step cancels (a slow particle hit from behind gains, in the step in which the contact
 *    forms, many times the energy of the small overlap reached, pushed along its own motion),
 *    and so does what gravity gives them all; what particles outside pass on to them through
 *    their contacts is bounded by each such contact's force (elastic and damping, unsoftened,
 *    times 1 + the friction coefficient: sinter_contact_force_bound, from the overlaps and
 *    normal speeds at t and t + h) times the member's displacement in that frame (plus r |w| h
 *    for its surface's turn), and counts with the elastic energy: in the laser bed scene a
 *    sphere falling onto one resting on the floor passes on, by the damping at the onset of
 *    the contact, ten times the elastic energy of the overlap. The gain must also exceed
 *    SINTER_SANITY_ENERGY_GROWTH = 1/2 of the cluster's kinetic energy at t in that frame: a
 *    small overshoot is not stopped (observed in the laser bed scene, steel with damping
 *    ratios 1: a sphere falling past one resting on the floor; in the step in which their
 *    contact forms the spins of both flip, and the pair gains a few times the elastic energy
 *    of its tiny overlap, 5e-4 of its kinetic energy, at the scene's step and at a fifth of it
 *    alike), while a blow-up multiplies the energy at every step (the resting sphere of issue
 *    35: from none to 24 times the elastic energy). Its resolution: a particle is examined
 *    only when its gain beyond doubling exceeds SINTER_SANITY_ENERGY_FLOOR = 1e-3 of the
 *    least elastic energy of a contact at the stable step's reference overlap (st->
 *    energy_floor, from stable_step.c: mech.scene 4.6e-13 J against the 1.3e-7 J of a landing
 *    sphere); a blow-up passes it within a few steps, and a settling bed's jiggle, in which
 *    tens of particles double their tiny energies every step, is not examined (mech.scene:
 *    the contacts examined in 270 of 10 000 steps instead of 4 887). Cost: one pass over the
 *    particles
 *    (their velocities, spins and displacements at t and t + h: spare arrays, no copy); only
 *    when a particle more than doubled its energy, three passes over the neighbour pairs find
 *    its partners and the contacts of both, with their overlaps at t and t + h from the
 *    positions (the elastic energy by sinter_contact_energy, unsoftened: an upper bound).
 *    Particles touching a moving wall are not examined, nor any when a host model computes
 *    contact forces. It reads the state only: the results are the same to the bit.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "contact/particle_pass.h"
#include "core/clones.h"
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
                               i, j, (unsigned long long)ps->id[i], (unsigned long long)ps->id[j],
                               x[3 * i], x[3 * i + 1], x[3 * i + 2]);
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
        if (w->kind == SINTER_WALL_PLANE) {
            for (int d = 0; d < 3; ++d)
                s_old += (x_old[3 * i + d] - (w->p[d] - h * w->u[d])) * w->n[d];
        } else { /* the old centre against the wall moved back, as the new against it */
            const double xs[3] = {x_old[3 * i] + h * w->u[0], x_old[3 * i + 1] + h * w->u[1],
                                  x_old[3 * i + 2] + h * w->u[2]};
            s_old = sinter_wall_distance(w, xs);
        }
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
                           "not resolved; the time step %g s is too large for the contact "
                           "stiffness or the impact speed "
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

/* A material whose particles may not pass its melting point: a melting point, no latent
 * heat to melt through, and melting_stop = 1. */
static int melting_stops(const sinter_material *m)
{
    return m->value[SINTER_MAT_MELTING_TEMPERATURE] > 0.0 &&
           !(m->value[SINTER_MAT_LATENT_HEAT] > 0.0) && m->value[SINTER_MAT_MELTING_STOP] != 0.0;
}

sinter_status sinter_sanity_step(struct sinter_stepper *st, const double *x_old, double t, double h,
                                 const sinter_sanity_scan *scan)
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
        const sinter_wall *w = &st->walls->wall[k];
        const double *u = w->u;
        double turn = 0.0; /* a turning rectangle's corners move too */
        if (w->kind == SINTER_WALL_RECTANGLE)
            turn = fabs(w->spin) * sqrt(w->half[0] * w->half[0] + w->half[1] * w->half[1]);
        wall_moved = fmax(wall_moved, h * (sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) + turn));
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
    /* 4. melting: only when a material in use has a melting point, no latent heat and asks
     * for the stop (melting_stop = 1, the default) */
    int melts = 0;
    for (int id = 0; id < ps->material_top; ++id)
        melts |= ps->material_used[id] && melting_stops(&ps->materials[id]);
    for (size_t i = 0; melts && i < n; ++i) {
        const sinter_material *mat = &ps->materials[ps->material[i]];
        const double melt = mat->value[SINTER_MAT_MELTING_TEMPERATURE];
        if (!melting_stops(mat) || !(ps->temperature[i] > melt) ||
            (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE))
            continue;
        return sinter_fail(st->ctx, SINTER_ERR_DOMAIN,
                           "step from t = %.9g s to %.9g s rejected: particle %zu (id %llu) "
                           "reached %g K, above the melting point %g K of its material %d "
                           "('%s', melting_temperature) which has no latent heat: give the "
                           "material a latent_heat to melt it through (enthalpy method), or "
                           "melting_stop = 0 to heat on without melting. The last accepted "
                           "state is kept.",
                           t, t + h, i, (unsigned long long)ps->id[i], ps->temperature[i], melt,
                           (int)ps->material[i], mat->name);
    }
    return SINTER_OK;
}

/* Criterion 4: the body forces' acceleration and force, and the drag's medium. */
typedef struct body_work {
    double g[3], f[3]; /* sum of the gravity models' g and body force models' f */
    double env;        /* largest |v_env| of a drag model [m/s] */
} body_work;

/* 0 when a host model computes contact forces (their energy is not known here). */
static int body_forces(const sinter_stepper *st, body_work *b)
{
    memset(b, 0, sizeof(*b));
    for (size_t k = 0; k < st->force_count; ++k) {
        const sinter_force_model *fm = st->forces[k].model;
        const double *p = fm->param;
        if (fm->ops == &sinter_force_gravity || fm->ops == &sinter_force_body_force)
            for (int d = 0; d < 3; ++d)
                (fm->ops == &sinter_force_gravity ? b->g : b->f)[d] += p[d];
        else if (fm->ops == &sinter_force_drag)
            b->env = fmax(b->env, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
        else if (fm->ops->uses_contacts && fm->ops != &sinter_force_hertz_mindlin &&
                 fm->ops != &sinter_force_power_law && fm->ops != &sinter_force_linear_spring)
            return 0;
    }
    return 1;
}

/* Kinetic energy of particle i at t (from the spare arrays) and at t + h, and its gain beyond
 * the work of the body forces, in the laboratory frame. */
typedef struct energy_gain {
    double before, after, work, gain;
    double tolerance; /* round-off: of the energies, and of the work's displacement x - x0
                         (a short step far from the origin: its relative error eps |x| / dx) */
} energy_gain;

static energy_gain gain_of(const sinter_stepper *st, const body_work *b, size_t i)
{
    const sinter_particles *ps = st->ps;
    const double *x = ps->x + 3 * i, *v = ps->v + 3 * i, *w = ps->w + 3 * i;
    const double *x0 = st->spare[0] + 3 * i, *v0 = st->spare[1] + 3 * i, *w0 = st->spare[2] + 3 * i;
    const double m = ps->mass[i], J = ps->inertia[i];
    energy_gain e = {0.0, 0.0, 0.0, 0.0, 0.0};
    double moved2 = 0.0, spread = 0.0;
    for (int d = 0; d < 3; ++d) {
        const double dx = x[d] - x0[d], body = m * b->g[d] + b->f[d];
        e.before += 0.5 * (m * v0[d] * v0[d] + J * w0[d] * w0[d]);
        e.after += 0.5 * (m * v[d] * v[d] + J * w[d] * w[d]);
        e.work += body * dx;
        spread += fabs(body) * (fabs(x[d]) + fabs(x0[d]));
        moved2 += dx * dx;
    }
    if (b->env > 0.0) /* the drag pulls along the medium: at most c |v_env| per metre */
        e.work += sinter_particle_param(ps, i, SINTER_MAT_DRAG_COEFFICIENT) * b->env * sqrt(moved2);
    e.gain = e.after - e.before - e.work;
    e.tolerance = 1e-9 * (e.before + e.after) + 1e-14 * spread;
    return e;
}

/* More than doubled (beyond round-off): examined with its contacts. */
static int doubled(const energy_gain *e)
{
    return e->gain > e->before + e->tolerance;
}

/* Flags of criterion 4 per particle (st->energy_flag). */
enum {
    E_CANDIDATE = 1, /* its energy more than doubled */
    E_PARTNER = 2,   /* in contact with a candidate at t or t + h */
    E_MOVING = 4,    /* touches a moving wall: not examined, nor its cluster */
    E_ANCHORED = 8   /* touches a wall (or is fixed): its cluster's frame is the walls' */
};

/* The excess of particle i's gain (gain_of) over doubling its kinetic energy (doubled): > 0
 * when it more than doubled; far below zero for a fixed particle. Without calls or branches,
 * for the vectorised loop of any_doubled (it runs every step). */
typedef struct doubling_arrays {
    const double *restrict x; /* at t + h, then at t (the spare arrays) */
    const double *restrict v;
    const double *restrict w;
    const double *restrict x0;
    const double *restrict v0;
    const double *restrict w0;
    const double *restrict m;
    const double *restrict J;
    const uint32_t *restrict flags;
    double g[3], f[3];
    double floor; /* the check's resolution [J] (st->energy_floor) */
} doubling_arrays;

static inline double doubling_excess(const doubling_arrays *a, size_t i)
{
    const double *restrict x = a->x, *restrict v = a->v, *restrict w = a->w;
    const double *restrict x0 = a->x0, *restrict v0 = a->v0, *restrict w0 = a->w0;
    const double m = a->m[i], J = a->J[i];
    const double before = 0.5 * (m * (v0[3 * i] * v0[3 * i] + v0[3 * i + 1] * v0[3 * i + 1] +
                                      v0[3 * i + 2] * v0[3 * i + 2]) +
                                 J * (w0[3 * i] * w0[3 * i] + w0[3 * i + 1] * w0[3 * i + 1] +
                                      w0[3 * i + 2] * w0[3 * i + 2]));
    const double after =
        0.5 *
        (m * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]) +
         J * (w[3 * i] * w[3 * i] + w[3 * i + 1] * w[3 * i + 1] + w[3 * i + 2] * w[3 * i + 2]));
    const double b0 = m * a->g[0] + a->f[0], b1 = m * a->g[1] + a->f[1], b2 = m * a->g[2] + a->f[2];
    const double work = b0 * (x[3 * i] - x0[3 * i]) + b1 * (x[3 * i + 1] - x0[3 * i + 1]) +
                        b2 * (x[3 * i + 2] - x0[3 * i + 2]);
    const double spread = fabs(b0) * (fabs(x[3 * i]) + fabs(x0[3 * i])) +
                          fabs(b1) * (fabs(x[3 * i + 1]) + fabs(x0[3 * i + 1])) +
                          fabs(b2) * (fabs(x[3 * i + 2]) + fabs(x0[3 * i + 2]));
    const double tolerance = 1e-9 * (before + after) + 1e-14 * spread + a->floor;
    const double pinned = (double)(a->flags[i] & SINTER_PARTICLE_FIXED);
    return after - before - work - (before + tolerance) - 1e300 * pinned;
}

/* 1 if a particle's kinetic energy more than doubled (an integer reduction: vectorised, unlike
 * a floating-point one). */
SINTER_CLONES
static size_t any_doubled(const doubling_arrays *a, size_t n)
{
    long hits = 0;
    for (size_t i = 0; i < n; ++i)
        hits |= (long)(doubling_excess(a, i) > 0.0);
    return (size_t)hits;
}

/* Each particle's doubling_excess into out[0 .. n) (vectorised too). */
SINTER_CLONES
static void store_excess(const doubling_arrays *a, size_t n, double *restrict out)
{
    for (size_t i = 0; i < n; ++i)
        out[i] = doubling_excess(a, i);
}

/* With `flag`, `scratch` holds n doubles. */
static size_t doubled_pass(const sinter_stepper *st, const body_work *b, unsigned char *flag,
                           double *scratch)
{
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    if (!(b->env > 0.0)) { /* (the drag's medium: gain_of's own allowance) */
        const doubling_arrays a = {.x = ps->x,
                                   .v = ps->v,
                                   .w = ps->w,
                                   .x0 = st->spare[0],
                                   .v0 = st->spare[1],
                                   .w0 = st->spare[2],
                                   .m = ps->mass,
                                   .J = ps->inertia,
                                   .flags = ps->flags,
                                   .g = {b->g[0], b->g[1], b->g[2]},
                                   .f = {b->f[0], b->f[1], b->f[2]},
                                   .floor = st->energy_floor};
        if (flag == NULL)
            return any_doubled(&a, n);
        store_excess(&a, n, scratch);
        size_t count = 0;
        for (size_t i = 0; i < n; ++i) {
            flag[i] = scratch[i] > 0.0 ? E_CANDIDATE : 0;
            count += flag[i];
        }
        return count;
    }
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const energy_gain e = gain_of(st, b, i);
        const int c = doubled(&e) && !(ps->flags[i] & SINTER_PARTICLE_FIXED);
        count += (size_t)c;
        if (flag != NULL)
            flag[i] = c ? E_CANDIDATE : 0;
    }
    return count;
}

/* The overlaps of neighbour pair k at t (x0) and at t + h. */
static void pair_overlaps(const sinter_stepper *st, size_t i, size_t j, double d[2])
{
    const double *x = st->ps->x, *x0 = st->spare[0], *r = st->ps->radius;
    d[0] = r[i] + r[j] - distance(x0 + 3 * i, x0 + 3 * j);
    d[1] = r[i] + r[j] - distance(x + 3 * i, x + 3 * j);
}

/* |(v_i - v_j) . n| at t (spare arrays) plus at t + h: a bound of the normal speed the step's
 * damping read (the half-kicked velocity lies between them up to the kick). */
static double pair_speed(const sinter_stepper *st, size_t i, size_t j)
{
    const double *x = st->ps->x, *v = st->ps->v, *v0 = st->spare[1];
    double n[3], len = 0.0, a = 0.0, b = 0.0;
    for (int d = 0; d < 3; ++d) {
        n[d] = x[3 * j + d] - x[3 * i + d];
        len += n[d] * n[d];
    }
    len = sqrt(len);
    if (!(len > 0.0))
        return 0.0;
    for (int d = 0; d < 3; ++d) {
        a += (v0[3 * i + d] - v0[3 * j + d]) * n[d];
        b += (v[3 * i + d] - v[3 * j + d]) * n[d];
    }
    return (fabs(a) + fabs(b)) / len;
}

/* The energy gain of candidate i's cluster (i and its contact partners, adj[lo..hi)) in the
 * frame of its centre of mass, or of the walls when a member touches one or is fixed: energy
 * passed on between members within the step cancels, and so does what a uniform body force
 * gives the cluster as a whole. Also the members' elastic energies and the tolerance. */
typedef struct cluster_gain {
    double gain, work, elastic[2], tolerance;
    double kinetic;  /* kinetic energy at t, in the same frame */
    double transfer; /* bound of the work of contacts with particles outside the cluster */
    int moving;
} cluster_gain;

/* A bound of the work on member p through its contacts with non-members: their force bounds
 * (`force`: all of p's contacts' but the one with the candidate; a contact between two
 * partners counts too, which only widens the bound) times p's displacement in the cluster's
 * frame plus its surface's turn (r |w| h). */
static double boundary_work(const sinter_stepper *st, size_t p, double force, const double frame[3],
                            double h)
{
    const sinter_particles *ps = st->ps;
    double s2 = 0.0, w2 = 0.0;
    if (!(force > 0.0))
        return 0.0;
    for (int d = 0; d < 3; ++d) {
        const double s = ps->x[3 * p + d] - st->spare[0][3 * p + d] - frame[d];
        const double w = fmax(fabs(ps->w[3 * p + d]), fabs(st->spare[2][3 * p + d]));
        s2 += s * s;
        w2 += w * w;
    }
    return force * (sqrt(s2) + ps->radius[p] * sqrt(w2) * h);
}

static cluster_gain cluster_of(const sinter_stepper *st, const body_work *b, size_t i,
                               const uint32_t *adj, size_t lo, size_t hi, double h)
{
    const sinter_particles *ps = st->ps;
    const unsigned char *flag = st->energy_flag;
    const double *store = st->energy_store;
    cluster_gain c = {0.0, 0.0, {0.0, 0.0}, 0.0, 0.0, 0.0, 0};
    double mass = 0.0, p0[3] = {0, 0, 0}, p1[3] = {0, 0, 0}, dx[3] = {0, 0, 0}, count = 0.0;
    int anchored = 0;
    for (size_t k = lo; k <= hi; ++k) {
        const size_t p = k == hi ? i : adj[k];
        const energy_gain e = gain_of(st, b, p);
        c.gain += e.after - e.before;
        c.kinetic += e.before;
        c.work += e.work;
        c.tolerance += e.tolerance;
        c.elastic[0] += store[2 * p];
        c.elastic[1] += store[2 * p + 1];
        c.moving |= (flag[p] & E_MOVING) != 0;
        anchored |= (flag[p] & E_ANCHORED) || (ps->flags[p] & SINTER_PARTICLE_FIXED);
        const double m = ps->mass[p];
        mass += m;
        count += 1.0;
        for (int d = 0; d < 3; ++d) {
            p0[d] += m * st->spare[1][3 * p + d];
            p1[d] += m * ps->v[3 * p + d];
            dx[d] += m * (ps->x[3 * p + d] - st->spare[0][3 * p + d]);
        }
    }
    double frame[3] = {0.0, 0.0, 0.0}; /* the frame's displacement in the step */
    if (!anchored) /* the centre of mass's energy and the body forces' work on it go */
        for (int d = 0; d < 3; ++d) {
            c.gain -= 0.5 * (p1[d] * p1[d] - p0[d] * p0[d]) / mass;
            c.kinetic -= 0.5 * p0[d] * p0[d] / mass;
            c.work -= (mass * b->g[d] + count * b->f[d]) * dx[d] / mass;
            frame[d] = dx[d] / mass;
        }
    c.gain -= c.work;
    /* energy passed on to or from particles outside (by the elastic force or the damping):
     * every contact of the candidate is with a partner */
    const double *force_sum = store + 2 * ps->count;
    for (size_t k = lo; k < hi; ++k)
        c.transfer += boundary_work(st, adj[k], force_sum[adj[k]] - st->energy_force[k], frame, h);
    return c;
}

sinter_status sinter_sanity_energy(sinter_stepper *st, double t, double h)
{
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    body_work b;
    if (!body_forces(st, &b))
        return SINTER_OK;
    if (doubled_pass(st, &b, NULL, NULL) == 0)
        return SINTER_OK;
    sinter_status s =
        sinter_grow(st->ctx, (void **)&st->energy_flag, &st->energy_flag_capacity, n + 1, 1);
    if (s == SINTER_OK)
        s = sinter_grow(st->ctx, (void **)&st->energy_store, &st->energy_store_capacity, 3 * n + 3,
                        sizeof(double));
    if (s == SINTER_OK)
        s = sinter_grow(st->ctx, (void **)&st->energy_start, &st->energy_start_capacity, n + 2,
                        sizeof(size_t));
    if (s != SINTER_OK)
        return s;
    unsigned char *flag = st->energy_flag;
    double *store = st->energy_store;
    size_t *start = st->energy_start;
    (void)doubled_pass(st, &b, flag, store);
    memset(store, 0, 3 * n * sizeof(double));
    memset(start, 0, (n + 2) * sizeof(size_t));
    /* the candidates' partners (any contact at t or t + h: a pair that ended in the step
     * released its energy too), and the candidates' lists counted */
    const sinter_pair_list *pp = &st->nb.pp;
    for (size_t k = 0; k < pp->count; ++k) {
        const size_t i = pp->i[k], j = pp->j[k];
        if (!((flag[i] | flag[j]) & E_CANDIDATE))
            continue;
        double d[2];
        pair_overlaps(st, i, j, d);
        if (!(d[0] > 0.0 || d[1] > 0.0))
            continue;
        start[i + 2] += (flag[i] & E_CANDIDATE) != 0;
        start[j + 2] += (flag[j] & E_CANDIDATE) != 0;
        flag[i] |= (flag[j] & E_CANDIDATE) ? E_PARTNER : 0;
        flag[j] |= (flag[i] & E_CANDIDATE) ? E_PARTNER : 0;
    }
    for (size_t i = 0; i < n; ++i)
        start[i + 2] += start[i + 1];
    const size_t links = start[n + 1];
    s = sinter_grow(st->ctx, (void **)&st->energy_adj, &st->energy_adj_capacity, links + 1,
                    sizeof(uint32_t));
    if (s == SINTER_OK)
        s = sinter_grow(st->ctx, (void **)&st->energy_force, &st->energy_force_capacity, links + 1,
                        sizeof(double));
    if (s != SINTER_OK)
        return s;
    uint32_t *adj = st->energy_adj;
    /* elastic energies and force bounds of every contact of a candidate or partner (store:
     * 3 per particle, at t, at t + h, and the sum of the force bounds); the candidates' lists
     * (start[i + 1] runs from start[i] to start[i + 1] as they fill) */
    double *force_sum = store + 2 * n;
    for (size_t k = 0; k < pp->count; ++k) {
        const size_t i = pp->i[k], j = pp->j[k];
        if (!(flag[i] | flag[j]))
            continue;
        double d[2];
        pair_overlaps(st, i, j, d);
        if (!(d[0] > 0.0 || d[1] > 0.0))
            continue;
        for (int a = 0; a < 2; ++a) {
            const double u = d[a] > 0.0 ? sinter_contact_energy(st, i, j, 0, d[a]) : 0.0;
            store[2 * i + (size_t)a] += u;
            store[2 * j + (size_t)a] += u;
        }
        const double speed = pair_speed(st, i, j);
        const double f =
            fmax(d[0] > 0.0 ? sinter_contact_force_bound(st, i, j, 0, d[0], speed) : 0.0,
                 d[1] > 0.0 ? sinter_contact_force_bound(st, i, j, 0, d[1], speed) : 0.0);
        force_sum[i] += f;
        force_sum[j] += f;
        if (flag[i] & E_CANDIDATE) {
            st->energy_force[start[i + 1]] = f;
            adj[start[i + 1]++] = (uint32_t)j;
        }
        if (flag[j] & E_CANDIDATE) {
            st->energy_force[start[j + 1]] = f;
            adj[start[j + 1]++] = (uint32_t)i;
        }
    }
    const sinter_pair_list *pw = &st->nb.pw;
    const double *x = ps->x, *x0 = st->spare[0], *r = ps->radius;
    for (size_t k = 0; k < pw->count && st->walls != NULL; ++k) {
        const size_t i = pw->i[k], j = pw->j[k];
        if (!flag[i])
            continue;
        const sinter_wall *w = &st->walls->wall[j];
        const double d0 = r[i] - sinter_wall_distance(w, x0 + 3 * i);
        const double d1 = r[i] - sinter_wall_distance(w, x + 3 * i);
        if (!(d0 > 0.0 || d1 > 0.0))
            continue;
        if (w->u[0] != 0.0 || w->u[1] != 0.0 || w->u[2] != 0.0 || w->spin != 0.0) {
            flag[i] |= E_MOVING; /* the wall's work is not known here */
            continue;
        }
        flag[i] |= E_ANCHORED;
        store[2 * i] += d0 > 0.0 ? sinter_contact_energy(st, i, SIZE_MAX, j, d0) : 0.0;
        store[2 * i + 1] += d1 > 0.0 ? sinter_contact_energy(st, i, SIZE_MAX, j, d1) : 0.0;
    }
    size_t worst = n, count = 0, named[4] = {0, 0, 0, 0};
    double worst_ratio = 1.0;
    cluster_gain worst_c = {0.0, 0.0, {0.0, 0.0}, 0.0, 0.0, 0.0, 0};
    for (size_t i = 0; i < n; ++i) {
        if (!(flag[i] & E_CANDIDATE))
            continue;
        const cluster_gain c = cluster_of(st, &b, i, adj, start[i], start[i + 1], h);
        const double bound =
            SINTER_SANITY_ENERGY_FACTOR * (c.elastic[0] + c.elastic[1] + c.transfer) +
            SINTER_SANITY_ENERGY_GROWTH * fmax(c.kinetic, 0.0) + c.tolerance;
        if (c.moving || !(c.gain > bound))
            continue;
        if (count < 4)
            named[count] = i;
        count++;
        const double ratio = bound > 0.0 ? c.gain / bound : INFINITY;
        if (worst == n || ratio > worst_ratio) {
            worst = i;
            worst_ratio = ratio;
            worst_c = c;
        }
    }
    if (count == 0)
        return SINTER_OK;
    char others[160] = "";
    size_t used = 0;
    for (size_t k = 0; k < count && k < 4; ++k)
        if (named[k] != worst && used < sizeof(others))
            used += (size_t)snprintf(others + used, sizeof(others) - used, "%s%zu (id %llu)",
                                     used == 0 ? ". Also particle(s) " : ", ", named[k],
                                     (unsigned long long)ps->id[named[k]]);
    if (count > 4 && used < sizeof(others))
        snprintf(others + used, sizeof(others) - used, " and %zu more", count - 4);
    const energy_gain e = gain_of(st, &b, worst);
    return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                       "step from t = %.9g s to %.9g s rejected: energy created in a contact: "
                       "particle %zu (id %llu) and %zu contact partner(s) gained %g J of "
                       "kinetic energy (its own: %g J to %g J) beyond the body forces' work, "
                       "over %g x (elastic "
                       "energy %g J at t, %g J at t + h, work with others <= %g J) + %g x "
                       "their kinetic energy %g J. The step %g s is too large (see "
                       "sinter_stepper_stable_step; option \"energy_check\" = 0 turns this "
                       "check off); the last accepted state is kept%s",
                       t, t + h, worst, (unsigned long long)ps->id[worst],
                       start[worst + 1] - start[worst], worst_c.gain, e.before, e.after,
                       SINTER_SANITY_ENERGY_FACTOR, worst_c.elastic[0], worst_c.elastic[1],
                       worst_c.transfer, SINTER_SANITY_ENERGY_GROWTH, worst_c.kinetic, h, others);
}

/* The domain's test (option domain_min / domain_max) of particles [lo, hi): the first one
 * whose centre is not inside the box (a non-finite one is not), or SIZE_MAX. Batches of
 * particles are tested without branches, and only a batch with one outside is searched. */
typedef struct domain_job {
    const sinter_stepper *st;
    size_t first[SINTER_CHUNKS_MAX];
    double lo[3], hi[3]; /* the domain (domain_box) */
} domain_job;

/* The domain's box, unbounded along a periodic axis (issue 38: the particles wrap along it,
 * and their images, outside the cell, are not tested), and the rows tested: the owned ones. */
static size_t domain_box(const sinter_stepper *st, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; ++d) {
        const int periodic = st->ghosts.periodic[d];
        lo[d] = periodic ? -INFINITY : st->domain_lo[d];
        hi[d] = periodic ? INFINITY : st->domain_hi[d];
    }
    return st->ps->count - st->ps->ghost_count;
}

enum { DOMAIN_BATCH = 64 };

static inline int outside(const double *x, const double *a, const double *b, int d)
{
    return !(x[d] >= a[d]) | !(x[d] <= b[d]);
}

static void domain_range(void *data, int range, size_t lo, size_t hi)
{
    domain_job *job = data;
    const double *x = job->st->ps->x, *a = job->lo, *b = job->hi;
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
    domain_job job = {st, {0}, {0}, {0}};
    const size_t n = domain_box(st, job.lo, job.hi);
    const int ranges = sinter_particle_pass(st->ctx, &st->pp, n, domain_range, &job);
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
    while (d < 3 &&
           (st->ghosts.periodic[d] || (x[d] >= st->domain_lo[d] && x[d] <= st->domain_hi[d])))
        ++d;
    return sinter_fail(st->ctx, SINTER_ERR_LOST_PARTICLE,
                       "%s from t = %.9g s to %.9g s rejected: particle %zu (id %llu) left the "
                       "domain at %c = %g m (domain %g m to %g m); the last accepted state is "
                       "kept",
                       step, t, t + h, i, (unsigned long long)ps->id[i], "xyz"[d], x[d],
                       st -> domain_lo[d], st -> domain_hi[d]);
}

/* The smallest distance of a centre of particles [lo, hi) to the domain's faces [m], by range
 * (a minimum: the same for any split). */
typedef struct margin_job {
    const sinter_stepper *st;
    double margin[SINTER_CHUNKS_MAX];
    double lo[3], hi[3]; /* the domain (domain_box) */
} margin_job;

static void margin_range(void *data, int range, size_t lo, size_t hi)
{
    margin_job *job = data;
    const double *x = job->st->ps->x, *a = job->lo, *b = job->hi;
    double m = INFINITY;
    for (size_t i = lo; i < hi; ++i)
        for (int d = 0; d < 3; ++d) {
            const double below = x[3 * i + d] - a[d], above = b[d] - x[3 * i + d];
            m = below < m ? below : m;
            m = above < m ? above : m;
        }
    job->margin[range] = m;
}

sinter_status sinter_sanity_domain_moved(sinter_stepper *st, const char *step, double t, double h,
                                         double moved)
{
    if (!st->has_domain)
        return SINTER_OK;
    const sinter_particles *ps = st->ps;
    if (st->domain_known && st->domain_layout == ps->layout_generation &&
        st->domain_write == ps->write_generation) {
        /* |x - x_known| <= the sum of the steps' largest displacements; a rolled back step's
         * stays in the sum, which then bounds the restored positions too. The margin is cut by
         * a relative 1e-9 for the rounding of the sum. */
        const double sum = st->domain_moved + moved;
        if (sum < st->domain_margin * (1.0 - 1e-9)) {
            st->domain_moved = sum;
            return SINTER_OK;
        }
    }
    st->domain_known = 0;
    const sinter_status s = sinter_sanity_domain(st, step, t, h);
    if (s != SINTER_OK)
        return s;
    margin_job job = {st, {0}, {0}, {0}};
    const size_t n = domain_box(st, job.lo, job.hi);
    const int ranges = sinter_particle_pass(st->ctx, &st->pp, n, margin_range, &job);
    double margin = INFINITY;
    for (int k = 0; k < ranges; ++k)
        margin = job.margin[k] < margin ? job.margin[k] : margin;
    st->domain_margin = margin;
    st->domain_moved = 0.0;
    st->domain_known = margin > 0.0; /* not NaN */
    st->domain_layout = ps->layout_generation;
    st->domain_write = ps->write_generation;
    return SINTER_OK;
}
