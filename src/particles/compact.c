/*
 * Triaxial compaction of a particle set into a dense green body (seed 001 sec. 3.2: "small
 * constant velocities are then applied to this plane and to the other two planes ...
 * performing thus triaxial compression of the packing until the relative density of about
 * 60 % has been reached").
 *
 * The run is an ordinary explicit DEM simulation assembled from the public objects and
 * thrown away afterwards:
 *  - a copy of the particle set (same radii, masses, inertias, material ids, temperatures;
 *    every particle free, at rest) whose materials carry the compaction's friction, the
 *    damping for its restitution, no rolling resistance, no thermal softening and a drag
 *    coefficient (below);
 *  - six frictionless plane walls of the stiffest material. Each wall's point is its final
 *    position; its displacement (1 - lambda) (start - final) follows a progress variable
 *    lambda in [0, 1] shared by all six (a proportional compression), given to the wall as a
 *    two-point schedule over each chunk of MOTION_CHUNK steps, so the walls move continuously
 *    and end exactly on the requested planes;
 *  - the "hertz_mindlin" and "drag" force models (no gravity) and an explicit stepper with a
 *    domain around both boxes (a particle escaping through a wall is reported, not lost),
 *    which keeps the copy sorted in memory by position (option sort_interval): the copy's
 *    ids are the set's indices, and the positions go back by id.
 *
 * Servo: over each chunk lambda advances at the rate that moves the farthest wall at
 * `velocity`, times max(0, 1 - p / p_max) where p is the mean normal stress on the walls at
 * the start of the chunk. Far from jamming p ~ 0 (the kinetic pressure of the moving spheres,
 * ~ rho v^2, is tiny); as the contact network forms the walls slow down and wait while the
 * packing rearranges, so the compaction stays quasi-static and ends with the walls loaded by
 * about p_max at most. When lambda gains less than 1 % of what full speed would give over
 * JAM_WINDOW automatic steps, the packing is jammed: that is an error, or with
 * stop_at_jamming the end of the motion. The default p_max is the mean stress of a packing
 * (coordination 6, fraction 0.6) of mean spheres whose contacts overlap by 1e-3 of the radius:
 * p = Z phi F / (pi d^2) with F = (4/3) E* sqrt(r*) delta^(3/2) (Hertz).
 * After the motion the walls stay put and the packing relaxes until its translational kinetic
 * energy per particle falls below the threshold (checked every CHECK_STEPS steps). Only then
 * are the positions copied back (velocities, spins, forces and torques zeroed): the caller's
 * set is untouched by any failure.
 *
 * Time step: seed 003 eq. 47 (sinter_stable_dt_hertz: a tenth of the Hertz contact duration)
 * at the impact speed whose Hertz collision between two equal spheres reaches an overlap of
 * OVERLAP_LIMIT r (at least the wall speed). For a collision at speed v between two spheres
 * of radius r, mass m and compliance c = (1 - nu^2)/E (m* = m/2, r* = r/2, E* = 1/(2c)) the
 * largest overlap is delta = (15 m* v^2 / (16 E* sqrt(r*)))^(2/5), so the speed for delta =
 * eps r is v^2 = 16 eps^(5/2) r^3 / (15 sqrt(2) c m). The step is then small enough for the
 * stiffest contact a tolerable packing has. Known limit: eq. 47 bounds the normal oscillation,
 * but a sticking Mindlin contact couples the tangential spring (k_t = 8 G* sqrt(r* delta),
 * 0.8 k_n for nu = 0.3) with rotation (inertia 2/5 m r^2), a mode about sqrt(1 + m r^2 / I) =
 * 1.9 times faster. At friction 0.1 the contacts of a jammed copper packing slip often enough
 * and it comes to rest; at friction 0.3 and 0.6 the 805-sphere copper packing kept a kinetic
 * energy of 1e-17..1e-15 J per sphere with this step and came to rest with half of it (the
 * dt option). Halving it always cost twice the run and, in a 100-sphere test at friction 0.1,
 * left a slow creep that missed the default rest threshold, so it is not the default.
 *
 * Drag: loose spheres ("rattlers") in the cages of a jammed packing lose energy only when
 * they hit a neighbour, so without a background damping the kinetic energy decays slowly.
 * A drag -c v with c = (mean mass) / tau and tau = 100 contact durations (DRAG_STEPS
 * automatic steps) stops them within a few tau. The drag on the column of spheres the walls
 * push is ~ N m v_wall / tau, negligible against the contact forces of a compacted packing.
 */
#include <math.h>
#include <string.h>

#include "particles/compact.h"
#include "stepper/stepper.h"
#include "walls/walls.h"

static const double PI = 3.14159265358979323846;
static const char *const AXIS[3] = {"x", "y", "z"};

/* pi / sqrt(18): the densest packing of equal spheres (Kepler, Hales). */
#define DENSEST_PACKING 0.7404804896930610
/* Overlap (relative to the smallest radius) the automatic step is made for. */
#define OVERLAP_LIMIT 0.01
/* Drag time constant in automatic time steps (100 Hertz contact durations). */
#define DRAG_STEPS 1000.0
/* Steps between two checks of the kinetic energy during the relaxation. */
#define CHECK_STEPS 100
/* Steps between two updates of the wall speeds. */
#define MOTION_CHUNK 10
/* Window of the jamming test, in automatic steps. */
#define JAM_WINDOW 5000.0
/* Mean overlap / radius of the default stress limit. */
#define OVERLAP_SERVO 1e-3
/* Steps between two spatial sorts of the working copy (the stepper's sort_interval): a set
 * made by random sequential addition lies in memory in no spatial order, so the contact loops
 * miss the caches and, on two threads, most contacts cross the threads' particle ranges
 * (tests/bench/RESULTS.md, session 17). The spheres move a few diameters in the compaction. */
#define SORT_STEPS 1000
/* Longest run accepted (motion or relaxation), in steps. */
#define MAX_STEPS 1e9
/* Default rest threshold: this fraction of (1/2) m v^2 at the impact speed of the automatic
 * step (an rms speed of 3.2e-5 of it: for copper spheres of 25 um, 1.3e-4 m/s, or 1e-4 of the
 * radius per drag time constant). Jammed packings of a few thousand spheres keep creeping at
 * about a tenth of that (1e-18 J per titanium sphere of 64 um) for a long time; 1e-10 was too
 * strict for them. */
#define REST_FRACTION 1e-9

static const char *FUNC = "sinter_pack_compact";

sinter_status sinter_compaction_options_init(sinter_compaction_options *options,
                                             size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (struct_size != sizeof(sinter_compaction_options))
        return SINTER_ERR_STRUCT_SIZE;
    memset(options, 0, sizeof(*options));
    options->struct_size = sizeof(*options);
    for (int d = 0; d < 3; ++d) {
        options->box_min[d] = 0.0;
        options->box_max[d] = 1.0;
    }
    options->volume_fraction = 0.0;
    options->friction = 0.1;
    options->restitution = 0.5;
    options->velocity = 0.5;
    options->max_pressure = 0.0;
    options->stop_at_jamming = 0;
    options->ke_per_particle = 0.0;
    options->relax_time_max = 0.0;
    options->dt = 0.0;
    return SINTER_OK;
}

/* What the options and the set give, before anything runs. */
typedef struct plan {
    double start_lo[3], start_hi[3]; /* bounding box of the spheres [m] */
    double lo[3], hi[3];             /* final box [m] */
    double solid;                    /* sphere volume [m^3] */
    double r_min, r_max, m_mean;
} plan;

static sinter_status bad_option(sinter_ctx *ctx, const char *name, double value, const char *rule)
{
    return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: option %s = %g %s", FUNC, name, value, rule);
}

static sinter_status check_values(sinter_ctx *ctx, const sinter_compaction_options *o)
{
    for (int d = 0; d < 3; ++d)
        if (!isfinite(o->box_min[d]) || !isfinite(o->box_max[d]) ||
            !(o->box_max[d] > o->box_min[d]) || !isfinite(o->box_max[d] - o->box_min[d]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: option box_max[%d] = %g must be finite and greater than "
                               "box_min[%d] = %g (%s axis)",
                               FUNC, d, o->box_max[d], d, o->box_min[d], AXIS[d]);
    const double phi = o->volume_fraction;
    if (!(phi >= 0.0 && phi <= DENSEST_PACKING))
        return bad_option(ctx, "volume_fraction", phi,
                          "must be 0 (use the box as given) or in (0, 0.7405] (the densest "
                          "sphere packing)");
    if (!(o->friction >= 0.0 && o->friction <= 100.0))
        return bad_option(ctx, "friction", o->friction, "must be in [0, 100]");
    if (!(o->restitution > 0.0 && o->restitution <= 1.0))
        return bad_option(ctx, "restitution", o->restitution, "must be in (0, 1]");
    if (!(o->velocity > 0.0) || !isfinite(o->velocity))
        return bad_option(ctx, "velocity", o->velocity, "m/s must be positive and finite");
    if (o->stop_at_jamming != 0 && o->stop_at_jamming != 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: option stop_at_jamming = %d must be 0 or 1",
                           FUNC, o->stop_at_jamming);
    const struct {
        const char *name, *unit;
        double value;
    } nonnegative[] = {{"max_pressure", "Pa", o->max_pressure},
                       {"ke_per_particle", "J", o->ke_per_particle},
                       {"relax_time_max", "s", o->relax_time_max},
                       {"dt", "s", o->dt}};
    for (size_t k = 0; k < sizeof(nonnegative) / sizeof(nonnegative[0]); ++k)
        if (!(nonnegative[k].value >= 0.0) || !isfinite(nonnegative[k].value))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: option %s = %g %s must be finite and >= 0 (0: automatic)",
                               FUNC, nonnegative[k].name, nonnegative[k].value,
                               nonnegative[k].unit);
    return SINTER_OK;
}

/* Every check of sinter_pack_compact that needs no time step; fills *p. */
static sinter_status make_plan(const sinter_particles *ps, const sinter_compaction_options *o,
                               plan *p)
{
    sinter_ctx *ctx = ps->ctx;
    if (o->struct_size != sizeof(sinter_compaction_options))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: options.struct_size is %zu, expected %zu; fill the options with "
                           "sinter_compaction_options_init",
                           FUNC, o->struct_size, sizeof(sinter_compaction_options));
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are still out; release "
                           "them before compacting",
                           FUNC, ps->views_out);
    if (ps->count == 0)
        return sinter_fail(ctx, SINTER_ERR_STATE, "%s: the particle set is empty", FUNC);
    sinter_status st = check_values(ctx, o);
    if (st != SINTER_OK)
        return st;
    st = sinter_particles_validate(ps, NULL);
    if (st != SINTER_OK)
        return st;
    memset(p, 0, sizeof(*p));
    p->r_min = INFINITY;
    double mass = 0.0;
    for (int d = 0; d < 3; ++d) {
        p->start_lo[d] = INFINITY;
        p->start_hi[d] = -INFINITY;
    }
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i];
        p->solid += 4.0 / 3.0 * PI * r * r * r;
        p->r_min = fmin(p->r_min, r);
        p->r_max = fmax(p->r_max, r);
        mass += ps->mass[i];
        for (int d = 0; d < 3; ++d) {
            p->start_lo[d] = fmin(p->start_lo[d], ps->x[3 * i + d] - r);
            p->start_hi[d] = fmax(p->start_hi[d], ps->x[3 * i + d] + r);
        }
    }
    p->m_mean = mass / (double)ps->count;
    /* The final box: as given, or scaled about box_min to the volume fraction. */
    double volume = 1.0;
    for (int d = 0; d < 3; ++d)
        volume *= o->box_max[d] - o->box_min[d];
    const double scale =
        o->volume_fraction > 0.0 ? cbrt(p->solid / (o->volume_fraction * volume)) : 1.0;
    volume = 1.0;
    for (int d = 0; d < 3; ++d) {
        p->lo[d] = o->box_min[d];
        p->hi[d] = o->volume_fraction > 0.0
                       ? o->box_min[d] + scale * (o->box_max[d] - o->box_min[d])
                       : o->box_max[d];
        const double width = p->hi[d] - p->lo[d];
        if (!isfinite(width) || !(width > 2.0 * p->r_max))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the final box is %g m wide along %s, not wider than the "
                               "largest sphere (diameter %g m)",
                               FUNC, width, AXIS[d], 2.0 * p->r_max);
        volume *= width;
    }
    const double fraction = p->solid / volume;
    if (!(fraction <= DENSEST_PACKING))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the spheres (%g m^3) would fill %g of the final box (%g m^3), "
                           "more than the densest sphere packing (0.7405); enlarge the box",
                           FUNC, p->solid, fraction, volume);
    return SINTER_OK;
}

sinter_status sinter_compaction_check(const sinter_particles *ps,
                                      const sinter_compaction_options *options)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, options);
    plan p;
    return make_plan(ps, options, &p);
}

/* ---- the run -------------------------------------------------------------------------- */

/* The objects of the run, destroyed together. */
typedef struct compaction {
    sinter_particles *work;
    sinter_walls *walls;
    sinter_force_model *hertz, *drag;
    sinter_stepper *stepper;
} compaction;

static void compaction_free(compaction *c)
{
    sinter_stepper_destroy(c->stepper);
    sinter_force_model_destroy(c->hertz);
    sinter_force_model_destroy(c->drag);
    sinter_walls_destroy(c->walls);
    sinter_particles_destroy(c->work);
}

static double compliance(const sinter_material *m)
{
    const double nu = m->value[SINTER_MAT_POISSON_RATIO];
    return (1.0 - nu * nu) / m->value[SINTER_MAT_YOUNGS_MODULUS];
}

/* The material a particle (or wall) has during the compaction. */
static void compaction_material(sinter_material *m, const sinter_compaction_options *o, double xi,
                                double drag)
{
    m->value[SINTER_MAT_FRICTION_STATIC] = o->friction;
    m->value[SINTER_MAT_FRICTION_DYNAMIC] = o->friction;
    m->value[SINTER_MAT_DAMPING_RATIO] = xi;
    m->value[SINTER_MAT_FRICTION_DAMPING_RATIO] = xi;
    m->value[SINTER_MAT_ROLLING_FRICTION] = 0.0;
    m->value[SINTER_MAT_ROLLING_DAMPING_RATIO] = 0.0;
    m->value[SINTER_MAT_SOFTENING_LAW] = 0.0;
    m->value[SINTER_MAT_DRAG_COEFFICIENT] = drag;
}

/* Impact speed of the automatic step (see the top of the file) [m/s]. */
static double overlap_speed(const sinter_particles *ps)
{
    const double eps = OVERLAP_LIMIT, k = 16.0 * eps * eps * sqrt(eps) / (15.0 * sqrt(2.0));
    double v2 = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i];
        const double c = compliance(&ps->materials[ps->material[i]]);
        v2 = fmax(v2, k * r * r * r / (c * ps->mass[i]));
    }
    return sqrt(v2);
}

/* The copy of the set, with the compaction's materials (drag set later). */
static sinter_status copy_set(const sinter_particles *ps, const sinter_compaction_options *o,
                              double xi, sinter_particles **out)
{
    sinter_particles *w = NULL;
    sinter_status st = sinter_particles_create(&w, ps->ctx);
    int32_t first = -1;
    for (int32_t m = 0; m < SINTER_MAX_MATERIALS && st == SINTER_OK; ++m) {
        if (!ps->material_used[m])
            continue;
        sinter_material mat = ps->materials[m];
        compaction_material(&mat, o, xi, 0.0);
        st = sinter_particles_set_material(w, m, &mat);
        if (first < 0)
            first = m;
    }
    if (st == SINTER_OK)
        st = sinter_particles_add(w, ps->count, ps->x, ps->radius, first, ps->temperature[0],
                                  NULL);
    if (st != SINTER_OK) {
        sinter_particles_destroy(w);
        return st;
    }
    /* The caller's values as they are (masses may have been set through a view). */
    memcpy(w->material, ps->material, ps->count * sizeof(int32_t));
    memcpy(w->mass, ps->mass, ps->count * sizeof(double));
    memcpy(w->inertia, ps->inertia, ps->count * sizeof(double));
    memcpy(w->temperature, ps->temperature, ps->count * sizeof(double));
    *out = w;
    return SINTER_OK;
}

/*
 * Translational kinetic energy per particle [J]. Spin is left out: a loose sphere keeps the
 * spin friction gave it (neither the drag nor a frictionless wall brakes it) without moving,
 * and the spins are zeroed at the end anyway.
 */
static double kinetic_energy(const sinter_particles *ps)
{
    double ke = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        const double *v = ps->v + 3 * i;
        ke += 0.5 * ps->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    return ke / (double)ps->count;
}

/* Six walls on the final box, held on the start box; the stiffest material. */
static sinter_status make_walls(compaction *c, const plan *p, const sinter_compaction_options *o,
                                double xi)
{
    const sinter_particles *ps = c->work;
    sinter_status st = sinter_walls_create(&c->walls, ps->ctx);
    int stiffest = -1;
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        if (ps->material_used[m] &&
            (stiffest < 0 || compliance(&ps->materials[m]) < compliance(&ps->materials[stiffest])))
            stiffest = m;
    sinter_material mat = ps->materials[stiffest];
    compaction_material(&mat, o, xi, 0.0);
    mat.value[SINTER_MAT_FRICTION_STATIC] = mat.value[SINTER_MAT_FRICTION_DYNAMIC] = 0.0;
    for (int d = 0; d < 3 && st == SINTER_OK; ++d)
        for (int side = 0; side < 2 && st == SINTER_OK; ++side) {
            double point[3], normal[3] = {0.0, 0.0, 0.0};
            for (int e = 0; e < 3; ++e)
                point[e] = 0.5 * (p->lo[e] + p->hi[e]);
            point[d] = side == 0 ? p->lo[d] : p->hi[d];
            normal[d] = side == 0 ? 1.0 : -1.0;
            st = sinter_walls_add_plane(c->walls, point, normal, &mat, NULL);
        }
    return st;
}

/* Wall k (axis k / 2, lower side for even k) at progress lambda: displacement from its point. */
static double wall_offset(const plan *p, size_t k, double lambda)
{
    const int d = (int)(k / 2);
    const double start = k % 2 == 0 ? p->start_lo[d] : p->start_hi[d];
    const double final = k % 2 == 0 ? p->lo[d] : p->hi[d];
    return (1.0 - lambda) * (start - final);
}

/* Move the walls linearly from progress a at time t0 to b at t1 (b == a: held). */
static sinter_status schedule_walls(sinter_walls *walls, const plan *p, double t0, double t1,
                                    double a, double b)
{
    sinter_status st = SINTER_OK;
    for (size_t k = 0; k < 6 && st == SINTER_OK; ++k) {
        const int d = (int)(k / 2);
        double times[2] = {t0, t1}, disp[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        disp[d] = wall_offset(p, k, a);
        disp[3 + d] = wall_offset(p, k, b);
        st = sinter_walls_set_schedule(walls, k, 2, times, disp);
    }
    return st;
}

/* The current box of the walls and the mean normal stress the particles put on them [Pa]. */
static double wall_stress(const sinter_walls *walls, double lo[3], double hi[3])
{
    for (size_t k = 0; k < 6; ++k) {
        const int d = (int)(k / 2);
        if (k % 2 == 0)
            lo[d] = walls->wall[k].p[d];
        else
            hi[d] = walls->wall[k].p[d];
    }
    const double size[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double pressure = 0.0;
    for (size_t k = 0; k < 6; ++k) {
        const sinter_wall *w = &walls->wall[k];
        const int d = (int)(k / 2);
        const double face = size[(d + 1) % 3] * size[(d + 2) % 3];
        pressure += -(w->force[0] * w->n[0] + w->force[1] * w->n[1] + w->force[2] * w->n[2]) /
                    face;
    }
    return pressure / 6.0;
}

/* Default stress limit of the servo (see the top of the file) [Pa]. */
static double default_pressure(const sinter_particles *ps)
{
    double r = 0.0, c = 0.0;
    for (size_t i = 0; i < ps->count; ++i) {
        r += ps->radius[i];
        c += compliance(&ps->materials[ps->material[i]]);
    }
    r /= (double)ps->count;
    c /= (double)ps->count;
    const double estar = 0.5 / c, rstar = 0.5 * r, delta = OVERLAP_SERVO * r;
    const double force = 4.0 / 3.0 * estar * sqrt(rstar) * delta * sqrt(delta);
    return 6.0 * 0.6 * force / (PI * 4.0 * r * r);
}

/* Relabel an error of the inner run as the compaction's. */
static sinter_status inner_error(sinter_ctx *ctx, sinter_status st, const char *phase)
{
    if (st == SINTER_OK || st == SINTER_ERR_NOMEM)
        return st;
    char detail[SINTER_ERROR_TEXT_SIZE];
    memcpy(detail, ctx->last_error, sizeof(detail));
    return sinter_fail(ctx, st,
                       "%s: during the %s (particle ids there: the indices in the set): %s", FUNC,
                       phase, detail);
}

static void fill_result(const compaction *c, const plan *p, double ke, double relax_time,
                        sinter_compaction_result *r)
{
    const sinter_particles *ps = c->work;
    sinter_stepper *s = c->stepper;
    sinter_contacts_geometry(s->ctx, &s->pp, s->ps); /* a lean list gets its overlaps */
    r->pressure = wall_stress(c->walls, r->box_min, r->box_max);
    const double size[3] = {r->box_max[0] - r->box_min[0], r->box_max[1] - r->box_min[1],
                            r->box_max[2] - r->box_min[2]};
    r->volume_fraction = p->solid / (size[0] * size[1] * size[2]);
    r->contacts = (uint64_t)s->pp.count;
    r->coordination = 2.0 * (double)s->pp.count / (double)ps->count;
    r->max_overlap = 0.0;
    r->max_overlap_ratio = 0.0;
    for (size_t k = 0; k < s->pp.count; ++k) {
        const double delta = s->pp.delta[k];
        const double rmin = fmin(ps->radius[s->pp.i[k]], ps->radius[s->pp.j[k]]);
        r->max_overlap = fmax(r->max_overlap, delta);
        r->max_overlap_ratio = fmax(r->max_overlap_ratio, delta / rmin);
    }
    r->max_wall_overlap_ratio = 0.0;
    for (size_t k = 0; k < s->pw.count; ++k)
        r->max_wall_overlap_ratio =
            fmax(r->max_wall_overlap_ratio, s->pw.delta[k] / ps->radius[s->pw.i[k]]);
    r->kinetic_energy = ke;
    r->time = s->time;
    r->relax_time = relax_time;
    r->dt = s->dt;
    r->steps = s->stats.steps;
}

/* The servo-controlled motion (see the top of the file); *jammed set when it stopped early. */
static sinter_status move_walls(compaction *c, const plan *p, const sinter_compaction_options *o,
                                double dt, double dt_auto, double p_max, int *jammed)
{
    sinter_ctx *ctx = c->work->ctx;
    double travel = 0.0;
    for (size_t k = 0; k < 6; ++k)
        travel = fmax(travel, fabs(wall_offset(p, k, 0.0)));
    /* Progress per chunk at full speed; the window of the jamming test in chunks. */
    const double full = travel > 0.0 ? o->velocity * MOTION_CHUNK * dt / travel : 1.0;
    const double window = ceil(JAM_WINDOW * dt_auto / (MOTION_CHUNK * dt));
    if (!(1.0 / full <= MAX_STEPS / MOTION_CHUNK))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the walls would need %.3g steps of %g s to travel %g m at "
                           "velocity = %g m/s (more than 1e9); raise velocity or dt",
                           FUNC, MOTION_CHUNK / full, dt, travel, o->velocity);
    double lambda = 0.0, window_start = 0.0, chunks = 0.0;
    *jammed = 0;
    while (lambda < 1.0) {
        double lo[3], hi[3];
        const double stress = wall_stress(c->walls, lo, hi);
        const double next = fmin(1.0, lambda + full * fmax(0.0, 1.0 - stress / p_max));
        const double t = c->stepper->time;
        sinter_status st = schedule_walls(c->walls, p, t, t + MOTION_CHUNK * dt, lambda, next);
        if (st == SINTER_OK)
            st = inner_error(ctx, sinter_stepper_step(c->stepper, MOTION_CHUNK), "wall motion");
        if (st != SINTER_OK)
            return st;
        lambda = next;
        if (++chunks >= window) {
            if (lambda - window_start < 0.01 * full * window) {
                if (o->stop_at_jamming) {
                    *jammed = 1;
                    break;
                }
                double solid_box = 1.0;
                for (int d = 0; d < 3; ++d)
                    solid_box *= hi[d] - lo[d];
                double final_box = 1.0;
                for (int d = 0; d < 3; ++d)
                    final_box *= p->hi[d] - p->lo[d];
                return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                   "%s: the packing jammed at volume fraction %.4f (mean wall "
                                   "stress %g Pa, limit %g Pa) before the final box (%.4f) was "
                                   "reached; lower the friction, enlarge the box or set "
                                   "stop_at_jamming. The set is unchanged",
                                   FUNC, p->solid / solid_box, stress, p_max,
                                   p->solid / final_box);
            }
            chunks = 0.0;
            window_start = lambda;
        }
    }
    /* Hold the walls where they are (on the final box unless jammed). */
    const double t = c->stepper->time;
    return schedule_walls(c->walls, p, t, t + 1.0, lambda, lambda);
}

static sinter_status run(sinter_particles *ps, const sinter_compaction_options *o, const plan *p,
                         compaction *c, sinter_compaction_result *result)
{
    sinter_ctx *ctx = ps->ctx;
    double xi = 0.0;
    sinter_status st = sinter_damping_ratio_from_restitution(o->restitution, &xi);
    if (st == SINTER_OK)
        st = copy_set(ps, o, xi, &c->work);
    if (st == SINTER_OK)
        st = make_walls(c, p, o, xi);
    if (st != SINTER_OK)
        return st;
    /* The automatic step, with the walls' material. */
    const double v_overlap = overlap_speed(c->work);
    double dt_auto = 0.0;
    st = sinter_stable_dt_hertz(c->work, c->walls, fmax(v_overlap, o->velocity), &dt_auto);
    if (st != SINTER_OK)
        return st;
    const double dt = o->dt > 0.0 ? o->dt : dt_auto;
    const double relax_max =
        o->relax_time_max > 0.0 ? o->relax_time_max : 50.0 * DRAG_STEPS * dt_auto;
    const double relax = ceil(relax_max / dt);
    if (!(relax <= MAX_STEPS))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the relaxation may take %.3g steps of %g s (more than 1e9); "
                           "raise dt or shorten relax_time_max",
                           FUNC, relax, dt);
    const double ke_rest = o->ke_per_particle > 0.0
                               ? o->ke_per_particle
                               : REST_FRACTION * 0.5 * p->m_mean * v_overlap * v_overlap;
    const double p_max = o->max_pressure > 0.0 ? o->max_pressure : default_pressure(c->work);
    /* Drag time constant tau = DRAG_STEPS automatic steps, c = mean mass / tau. */
    const double drag = p->m_mean / (DRAG_STEPS * dt_auto);
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        if (c->work->material_used[m])
            c->work->materials[m].value[SINTER_MAT_DRAG_COEFFICIENT] = drag;
    st = schedule_walls(c->walls, p, 0.0, 1.0, 0.0, 0.0);
    if (st == SINTER_OK)
        st = sinter_force_model_create(&c->hertz, ctx, "hertz_mindlin");
    if (st == SINTER_OK) /* no rolling resistance (compaction_material): 3 history values,
                            contacts without stored geometry */
        st = sinter_force_model_set(c->hertz, "rolling", 0.0);
    if (st == SINTER_OK)
        st = sinter_force_model_create(&c->drag, ctx, "drag");
    if (st == SINTER_OK)
        st = sinter_stepper_create(&c->stepper, ctx, SINTER_STEPPER_EXPLICIT, c->work, c->walls);
    /* the drag first: the stepper's last force model gives each thread's particles their
     * second half kick as it finishes them (stepper.h, range_final), which the contact law does */
    if (st == SINTER_OK)
        st = sinter_stepper_add_force(c->stepper, c->drag);
    if (st == SINTER_OK)
        st = sinter_stepper_add_force(c->stepper, c->hertz);
    if (st == SINTER_OK)
        st = sinter_stepper_set_dt(c->stepper, dt);
    if (st == SINTER_OK) /* the copy in spatial order (its ids: the set's indices) */
        st = sinter_stepper_set_option(c->stepper, "sort_interval", SORT_STEPS);
    if (st == SINTER_OK) {
        /* A particle pushed through a wall (a step far too large) stops the run. */
        double lo[3], hi[3];
        for (int d = 0; d < 3; ++d) {
            const double margin = 4.0 * p->r_max;
            lo[d] = fmin(p->lo[d], p->start_lo[d]) - margin;
            hi[d] = fmax(p->hi[d], p->start_hi[d]) + margin;
        }
        st = sinter_stepper_set_domain(c->stepper, lo, hi);
    }
    if (st == SINTER_OK)
        st = sinter_stepper_evaluate(c->stepper); /* wall stresses of the start */
    int jammed = 0;
    if (st == SINTER_OK)
        st = move_walls(c, p, o, dt, dt_auto, p_max, &jammed);
    if (st != SINTER_OK)
        return st;
    /* Relaxation with the walls held. */
    const double t_motion = c->stepper->time;
    uint64_t relaxed = 0;
    double ke = kinetic_energy(c->work);
    while (!(ke < ke_rest)) {
        if ((double)relaxed >= relax)
            return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                               "%s: after %g s of relaxation the kinetic energy is still %g J "
                               "per particle (threshold %g J); raise relax_time_max or "
                               "ke_per_particle. The set is unchanged",
                               FUNC, (double)relaxed * dt, ke, ke_rest);
        st = inner_error(ctx, sinter_stepper_step(c->stepper, CHECK_STEPS), "relaxation");
        if (st != SINTER_OK)
            return st;
        relaxed += CHECK_STEPS;
        ke = kinetic_energy(c->work);
    }
    fill_result(c, p, ke, c->stepper->time - t_motion, result);
    result->jammed = jammed;
    /* Stopped at jamming, the walls are short of box_min too: the packing is moved so that its
     * box starts there (a translation, nothing else changes). */
    double shift[3] = {0.0, 0.0, 0.0};
    if (jammed)
        for (int d = 0; d < 3; ++d) {
            shift[d] = p->lo[d] - result->box_min[d];
            result->box_max[d] = p->lo[d] + (result->box_max[d] - result->box_min[d]);
            result->box_min[d] = p->lo[d];
        }
    /* Write back: positions by particle id (the copy's ids are 0 .. n-1 in the set's order). */
    const sinter_particles *w = c->work;
    for (size_t k = 0; k < w->count; ++k) {
        const size_t i = (size_t)w->id[k];
        for (int d = 0; d < 3; ++d)
            ps->x[3 * i + d] = w->x[3 * k + d] + shift[d];
    }
    memset(ps->v, 0, 3 * ps->count * sizeof(double));
    memset(ps->w, 0, 3 * ps->count * sizeof(double));
    memset(ps->force, 0, 3 * ps->count * sizeof(double));
    memset(ps->torque, 0, 3 * ps->count * sizeof(double));
    ps->write_generation++; /* steppers over the set evaluate their forces again */
    return SINTER_OK;
}

sinter_status sinter_pack_compact(sinter_particles *particles,
                                  const sinter_compaction_options *options,
                                  sinter_compaction_result *result)
{
    if (particles == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = particles->ctx;
    SINTER_CHECK_NULL(ctx, options);
    if (result != NULL && result->struct_size != sizeof(sinter_compaction_result))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: result.struct_size is %zu, expected %zu", FUNC,
                           result->struct_size, sizeof(sinter_compaction_result));
    plan p;
    sinter_status st = make_plan(particles, options, &p);
    if (st != SINTER_OK)
        return st;
    sinter_compaction_result r;
    memset(&r, 0, sizeof(r));
    r.struct_size = sizeof(r);
    compaction c;
    memset(&c, 0, sizeof(c));
    st = run(particles, options, &p, &c, &r);
    compaction_free(&c);
    if (st == SINTER_OK) {
        if (result != NULL)
            *result = r;
        sinter_log(ctx, SINTER_LOG_INFO,
                   "%s: volume fraction %.4f, coordination %.3f, largest overlap %.3g of the "
                   "radius, %llu steps of %g s (%g s simulated, %g s relaxation)",
                   FUNC, r.volume_fraction, r.coordination, r.max_overlap_ratio,
                   (unsigned long long)r.steps, r.dt, r.time, r.relax_time);
    }
    return st;
}
