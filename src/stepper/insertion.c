/*
 * Continuous insertion (issue 38; LAMMPS' fix pour and LIGGGHTS' insertion by rate are the
 * peers): at times start + k interval the stage inserts spheres of the powder's size
 * distribution into a box or the cylinder inscribed in it, each at a random place where it
 * overlaps no particle and no wall, until the mass inserted since start reaches, within one
 * sphere's mass, the target mass_rate (k + 1) interval. The next sphere is drawn before it is
 * placed and is inserted only when its whole mass fits under the target, so the inserted mass
 * M_k after insertion k satisfies target_k - m_next < M_k <= target_k: the mass rate is met to
 * within one particle's mass per interval (tests/unit/test_insertion.c).
 *
 * The overlap check runs over the particles that can reach the region (gathered once per
 * insertion) and the spheres inserted so far in it: O(N) to gather, then O(near) per try.
 *
 * A mixture by mass fraction: the next sphere's material is chosen when it is drawn, by the
 * apportionment of particles/mixture.c over the spheres inserted so far (its radius then from
 * that material's sizes, or the shared ones), so each material's inserted mass stays within
 * one particle's mass of its share of the total inserted.
 *
 * Across subdomains (issue 43, domain/domain.h): every subdomain gathers every subdomain's
 * particles near the region (sinter_domain_allgather), so that every one draws the same
 * random numbers, finds the same places and makes the same spheres (the overlap test asks
 * whether any near sphere is too close: the order of the list does not matter). Subdomain 0
 * adds them with the ids above every subdomain's (a maximum of the sets' next ids), and the
 * host's redistribution at the rebuild that follows moves each to the subdomain that owns its
 * place; the inserted mass is subdomain 0's (a maximum: the others hold the smaller value
 * before it), so the bookkeeping stays the same bits everywhere. On one subdomain: the bits
 * of the run without domain operations.
 */
#include <math.h>
#include <string.h>

#include "domain/domain.h"
#include "insertion.h"
#include "particles/packing.h"
#include "particles/particles.h"
#include "walls/walls.h"

static const double PI = 3.14159265358979323846;

struct sinter_insertion {
    sinter_radius_sampler *sampler;
    sinter_insertion_options o;
    uint64_t next;      /* index k of the next insertion */
    double pending;     /* radius of the next sphere (drawn, not yet placed) [m] */
    double mass_done;   /* inserted so far [kg] */
    double mass_target; /* of the insertions made so far [kg] */
    uint64_t inserted;  /* spheres */
    uint64_t crowded;   /* insertions that ended with a sphere finding no room */
    double *near;       /* x, y, z, r of the spheres the new ones may touch */
    size_t near_count, near_capacity;
    int32_t *made; /* the material of each sphere placed in the insertion under way */
    size_t made_capacity;
};

void sinter_insertion_destroy(sinter_ctx *ctx, struct sinter_insertion *ins)
{
    if (ins == NULL)
        return;
    sinter_radius_sampler_destroy(ctx, ins->sampler);
    sinter_free(ctx, ins->near);
    sinter_free(ctx, ins->made);
    sinter_free(ctx, ins);
}

void sinter_insertion_get_state(const struct sinter_insertion *ins,
                                uint64_t u[SINTER_INSERTION_U64], double d[SINTER_INSERTION_F64])
{
    u[0] = ins->next;
    u[1] = ins->inserted;
    u[2] = ins->crowded;
    sinter_radius_sampler_get_stream(ins->sampler, u + 3);
    d[0] = ins->pending;
    d[1] = ins->mass_done;
    d[2] = ins->mass_target;
}

int sinter_insertion_state_valid(const double d[SINTER_INSERTION_F64])
{
    return isfinite(d[0]) && d[0] > 0.0 && isfinite(d[1]) && d[1] >= 0.0 && isfinite(d[2]) &&
           d[2] >= 0.0;
}

void sinter_insertion_set_state(struct sinter_insertion *ins,
                                const uint64_t u[SINTER_INSERTION_U64],
                                const double d[SINTER_INSERTION_F64])
{
    ins->next = u[0];
    ins->inserted = u[1];
    ins->crowded = u[2];
    sinter_radius_sampler_set_stream(ins->sampler, u + 3);
    ins->pending = d[0];
    ins->mass_done = d[1];
    ins->mass_target = d[2];
}

size_t sinter_insertion_mixture_count(const struct sinter_insertion *ins)
{
    return sinter_radius_sampler_mixture(ins->sampler, NULL);
}

void sinter_insertion_get_mixture(const struct sinter_insertion *ins, uint64_t *pending,
                                  double *mass)
{
    sinter_radius_sampler_get_mixture(ins->sampler, pending, mass);
}

int sinter_insertion_set_mixture(struct sinter_insertion *ins, uint64_t pending, const double *mass)
{
    return sinter_radius_sampler_set_mixture(ins->sampler, pending, mass);
}

sinter_status sinter_insertion_options_init(sinter_insertion_options *options, size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (struct_size != sizeof(sinter_insertion_options))
        return SINTER_ERR_STRUCT_SIZE;
    memset(options, 0, sizeof(*options));
    options->struct_size = sizeof(*options);
    options->region = SINTER_INSERT_BOX;
    options->mass_rate = 1e-3;
    options->start = 0.0;
    options->end = HUGE_VAL;
    options->interval = 1e-3;
    return SINTER_OK;
}

static sinter_status check_options(sinter_ctx *ctx, const sinter_insertion_options *o,
                                   const sinter_packing_options *powder, double rmax)
{
    static const char *fn = "sinter_stepper_set_insertion";
    if (o->struct_size != sizeof(sinter_insertion_options))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: options.struct_size is %zu, expected %zu; fill the options with "
                           "sinter_insertion_options_init",
                           fn, o->struct_size, sizeof(sinter_insertion_options));
    if (o->region != SINTER_INSERT_BOX && o->region != SINTER_INSERT_CYLINDER)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: region = %d is not a sinter_insertion_region", fn, o->region);
    if (!isfinite(o->mass_rate) || !(o->mass_rate > 0.0))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: mass_rate = %g kg/s must be positive and finite", fn, o->mass_rate);
    if (!isfinite(o->interval) || !(o->interval > 0.0))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: interval = %g s must be positive and finite", fn, o->interval);
    if (!isfinite(o->start) || isnan(o->end) || !(o->end > o->start))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: need a finite start before end (got start %g s, end %g s)", fn,
                           o->start, o->end);
    for (int d = 0; d < 3; ++d)
        if (!isfinite(o->velocity[d]))
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: velocity[%d] = %g m/s is not finite",
                               fn, d, o->velocity[d]);
    if (o->region == SINTER_INSERT_CYLINDER) {
        const double radius = 0.5 * fmin(powder->box_max[0] - powder->box_min[0],
                                         powder->box_max[1] - powder->box_min[1]);
        if (!(radius > rmax + powder->gap))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the cylinder's radius %g m leaves no room for a sphere of "
                               "radius %g m with gap %g m",
                               fn, radius, rmax, powder->gap);
    }
    return SINTER_OK;
}

sinter_status sinter_stepper_set_insertion(sinter_stepper *st, const sinter_packing_options *powder,
                                           const sinter_insertion_options *options)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    if (powder == NULL) {
        sinter_insertion_destroy(ctx, st->insertion);
        st->insertion = NULL;
        return SINTER_OK;
    }
    SINTER_CHECK_NULL(ctx, options);
    if (st->kind != SINTER_STEPPER_EXPLICIT)
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "sinter_stepper_set_insertion: only the explicit stepper inserts "
                           "particles");
    struct sinter_insertion *ins = sinter_calloc(ctx, 1, sizeof(*ins));
    if (ins == NULL)
        return sinter_last_status(ctx);
    sinter_status s =
        sinter_radius_sampler_create(&ins->sampler, st->ps, powder, "sinter_stepper_set_insertion");
    if (s == SINTER_OK)
        s = check_options(ctx, options, sinter_radius_sampler_options(ins->sampler),
                          sinter_radius_sampler_max(ins->sampler));
    /* a set that starts empty gets its arrays now: the pipeline's passes over the particles
     * take their arrays as they are, also for none */
    if (s == SINTER_OK && st->ps->capacity == 0)
        s = sinter_particles_reserve(st->ps, 64);
    if (s != SINTER_OK) {
        sinter_insertion_destroy(ctx, ins);
        return s;
    }
    ins->o = *options;
    ins->pending = sinter_radius_sampler_radius(ins->sampler);
    sinter_insertion_destroy(ctx, st->insertion);
    st->insertion = ins;
    return SINTER_OK;
}

sinter_status sinter_stepper_get_insertion(const sinter_stepper *st, double *mass_inserted,
                                           double *mass_target, uint64_t *inserted,
                                           uint64_t *crowded)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    const struct sinter_insertion *ins = st->insertion;
    if (mass_inserted)
        *mass_inserted = ins ? ins->mass_done : 0.0;
    if (mass_target)
        *mass_target = ins ? ins->mass_target : 0.0;
    if (inserted)
        *inserted = ins ? ins->inserted : 0;
    if (crowded)
        *crowded = ins ? ins->crowded : 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_get_insertion_mixture(const sinter_stepper *st, double *mass,
                                                   size_t capacity, size_t *count)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (capacity > 0)
        SINTER_CHECK_NULL(st->ctx, mass);
    const double *m = NULL;
    const size_t n =
        st->insertion != NULL ? sinter_radius_sampler_mixture(st->insertion->sampler, &m) : 0;
    for (size_t k = 0; k < n && k < capacity; ++k)
        mass[k] = m[k];
    if (count != NULL)
        *count = n;
    return SINTER_OK;
}

static sinter_status near_push(sinter_ctx *ctx, struct sinter_insertion *ins, const double x[3],
                               double r)
{
    if (ins->near_count == ins->near_capacity) {
        const size_t cap = ins->near_capacity ? 2 * ins->near_capacity : 64;
        double *grown = sinter_realloc_array(ctx, ins->near, 4 * cap, sizeof(double));
        if (grown == NULL)
            return sinter_last_status(ctx);
        ins->near = grown;
        ins->near_capacity = cap;
    }
    double *e = ins->near + 4 * ins->near_count++;
    e[0] = x[0], e[1] = x[1], e[2] = x[2], e[3] = r;
    return SINTER_OK;
}

/* The particles that can touch a sphere of the powder inside the region. With periodic axes
 * (issue 38) the owned particles, near the region along the other axes: fits() measures to
 * the nearest image along a periodic axis. */
static sinter_status gather_near(sinter_stepper *st, struct sinter_insertion *ins)
{
    const sinter_particles *ps = st->ps;
    const sinter_packing_options *p = sinter_radius_sampler_options(ins->sampler);
    const double reach = sinter_radius_sampler_max(ins->sampler) + p->gap;
    const int *periodic = st->ghosts.periodic;
    ins->near_count = 0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i) {
        const double *x = ps->x + 3 * i, r = ps->radius[i] + reach;
        int in = 1;
        for (int d = 0; d < 3; ++d)
            in &= periodic[d] || (x[d] + r >= p->box_min[d] && x[d] - r <= p->box_max[d]);
        if (in) {
            const sinter_status s = near_push(st->ctx, ins, x, ps->radius[i]);
            if (s != SINTER_OK)
                return s;
        }
    }
    return SINTER_OK;
}

/* gather_near over every subdomain (collective): every subdomain's near spheres, in subdomain
 * order, on every subdomain. Without domain operations gather_near. */
static sinter_status gather_near_all(sinter_stepper *st, struct sinter_insertion *ins)
{
    sinter_status s = gather_near(st, ins);
    if (!st->domain.on)
        return s;
    double *all = NULL;
    size_t total = 0, first = 0;
    s = sinter_domain_allgather(st->ctx, &st->domain, s, ins->near, ins->near_count, 4, &all,
                                &total, &first);
    ins->near_count = 0;
    for (size_t k = 0; s == SINTER_OK && k < total; ++k)
        s = near_push(st->ctx, ins, all + 4 * k, all[4 * k + 3]);
    sinter_free(st->ctx, all);
    return s;
}

/* Across subdomains: n new spheres (xr: positions then radii, materials ins->made) added by
 * subdomain 0 with the ids above every subdomain's, the inserted mass and the status agreed
 * (collective). */
static sinter_status add_across(sinter_stepper *st, struct sinter_insertion *ins, const double *xr,
                                size_t n)
{
    sinter_domain *d = &st->domain;
    sinter_particles *ps = st->ps;
    const sinter_packing_options *p = sinter_radius_sampler_options(ins->sampler);
    uint64_t next = ps->next_id;
    long rank = -1;
    sinter_status s =
        sinter_domain_reduce(st->ctx, d, &next, 1, SINTER_REDUCE_U64, SINTER_REDUCE_MAX);
    if (s == SINTER_OK)
        s = sinter_domain_rank(st->ctx, d, &rank);
    if (s != SINTER_OK)
        return s;
    uint64_t *ids = rank == 0 ? sinter_alloc(st->ctx, n * sizeof(uint64_t)) : NULL;
    if (rank == 0 && ids == NULL)
        s = sinter_last_status(st->ctx);
    for (size_t k = 0; ids != NULL && k < n; ++k)
        ids[k] = next + k;
    /* runs of one material, as the single domain adds them */
    if (s == SINTER_OK && rank == 0 && sinter_radius_sampler_mixture(ins->sampler, NULL) > 0)
        s = sinter_particles_reserve(ps, ps->count + n);
    size_t first = 0;
    for (size_t k = 0; rank == 0 && k < n && s == SINTER_OK;) {
        size_t j = k + 1, at = 0;
        while (j < n && ins->made[j] == ins->made[k])
            ++j;
        s = sinter_particles_add_with_ids(ps, j - k, ids + k, xr + 3 * k, xr + 3 * n + k,
                                          ins->made[k], p->temperature, &at);
        first = k == 0 ? at : first;
        k = j;
    }
    sinter_free(st->ctx, ids);
    for (size_t i = first; rank == 0 && s == SINTER_OK && i < first + n; ++i) {
        for (int c = 0; c < 3; ++c)
            ps->v[3 * i + c] = ins->o.velocity[c];
        ins->mass_done += ps->mass[i];
    }
    /* their state at t (this step's start) in the rows a redistribution within the step sends
     * with them (the spare rows, the saved temperatures: stepper/migrate.c) */
    if (s == SINTER_OK && rank == 0)
        s = sinter_explicit_keep_spare(st);
    const double *now[4] = {ps->x, ps->v, ps->w, ps->rot};
    for (int f = 0; rank == 0 && s == SINTER_OK && f < 4; ++f)
        if (st->spare[f] != NULL && first + n <= st->spare_capacity)
            memcpy(st->spare[f] + 3 * first, now[f] + 3 * first, 3 * n * sizeof(double));
    for (size_t i = first; rank == 0 && s == SINTER_OK && st->thermal.theta_backup != NULL &&
                           i < first + n && i < st->thermal.backup_capacity;
         ++i)
        st->thermal.theta_backup[i] = ps->temperature[i];
    s = sinter_domain_agree(st->ctx, d, s);
    if (s == SINTER_OK) /* subdomain 0's sum (the others hold the one before it, smaller) */
        s = sinter_domain_reduce(st->ctx, d, &ins->mass_done, 1, SINTER_REDUCE_F64,
                                 SINTER_REDUCE_MAX);
    return s;
}

/* 1 if a sphere (x, r) keeps the gap g to every near sphere and every wall. */
static int fits(const sinter_stepper *st, const struct sinter_insertion *ins, const double x[3],
                double r, double g)
{
    const sinter_ghosts *pg = &st->ghosts;
    const int periodic = sinter_ghosts_on(pg);
    for (size_t k = 0; k < ins->near_count; ++k) {
        const double *e = ins->near + 4 * k;
        double dx = x[0] - e[0], dy = x[1] - e[1], dz = x[2] - e[2];
        const double c = r + e[3] + g;
        if (periodic) { /* the nearest image along a periodic axis */
            double *dd[3] = {&dx, &dy, &dz};
            for (int a = 0; a < 3; ++a)
                if (pg->periodic[a]) {
                    const double period = pg->hi[a] - pg->lo[a];
                    *dd[a] -= period * nearbyint(*dd[a] / period);
                }
        }
        if (dx * dx + dy * dy + dz * dz < c * c)
            return 0;
    }
    if (st->walls != NULL)
        for (size_t k = 0; k < st->walls->count; ++k)
            if (!(sinter_wall_distance(&st->walls->wall[k], x) >= r + g))
                return 0;
    return 1;
}

/* A random place for a sphere of radius r in the region; 0 after max_attempts tries. */
static int place(const sinter_stepper *st, struct sinter_insertion *ins, double r, double x[3])
{
    const sinter_packing_options *p = sinter_radius_sampler_options(ins->sampler);
    const double g = p->gap, m = r + g;
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        lo[d] = p->box_min[d] + m;
        hi[d] = p->box_max[d] - m;
    }
    const double cx = 0.5 * (p->box_min[0] + p->box_max[0]),
                 cy = 0.5 * (p->box_min[1] + p->box_max[1]),
                 reach =
                     0.5 * fmin(p->box_max[0] - p->box_min[0], p->box_max[1] - p->box_min[1]) - m;
    for (uint64_t a = 0; a < p->max_attempts; ++a) {
        for (int d = 0; d < 3; ++d)
            x[d] =
                fmin(lo[d] + (hi[d] - lo[d]) * sinter_radius_sampler_uniform(ins->sampler), hi[d]);
        if (ins->o.region == SINTER_INSERT_CYLINDER) {
            const double dx = x[0] - cx, dy = x[1] - cy;
            if (dx * dx + dy * dy > reach * reach)
                continue; /* outside the cylinder: another try */
        }
        if (fits(st, ins, x, r, g))
            return 1;
    }
    return 0;
}

sinter_status sinter_insertion_stage(sinter_stepper *st)
{
    struct sinter_insertion *ins = st->insertion;
    if (ins == NULL)
        return SINTER_OK;
    const sinter_insertion_options *o = &ins->o;
    const double t = st->time;
    double tk = o->start + (double)ins->next * o->interval;
    if (!(t >= tk) || !(tk < o->end))
        return SINTER_OK;
    /* the latest insertion time passed (steps longer than the interval merge insertions) */
    while (o->start + (double)(ins->next + 1) * o->interval <= t &&
           o->start + (double)(ins->next + 1) * o->interval < o->end)
        ins->next++;
    const double covered = fmin((double)(ins->next + 1) * o->interval, o->end - o->start);
    ins->next++;
    ins->mass_target = o->mass_rate * covered;
    const sinter_packing_options *p = sinter_radius_sampler_options(ins->sampler);
    sinter_status s = gather_near_all(st, ins);
    const size_t first_new = ins->near_count;
    double mass = ins->mass_done;
    for (;;) {
        const int32_t mat = sinter_radius_sampler_material(ins->sampler);
        const double density = st->ps->materials[mat].value[SINTER_MAT_DENSITY];
        const double r = ins->pending, m = density * (4.0 / 3.0) * PI * r * r * r;
        if (s != SINTER_OK || !(mass + m <= ins->mass_target))
            break;
        double x[3];
        if (!place(st, ins, r, x)) {
            ins->crowded++;
            break;
        }
        const size_t made = ins->near_count - first_new;
        s = near_push(st->ctx, ins, x, r);
        if (s == SINTER_OK)
            s = sinter_grow(st->ctx, (void **)&ins->made, &ins->made_capacity, made + 1,
                            sizeof(int32_t));
        if (s != SINTER_OK)
            break;
        ins->made[made] = mat;
        sinter_radius_sampler_placed(ins->sampler, r);
        mass += m;
        ins->pending = sinter_radius_sampler_radius(ins->sampler);
    }
    const size_t n = ins->near_count - first_new;
    s = sinter_domain_agree(st->ctx, &st->domain, s); /* (every subdomain made the same n) */
    if (s != SINTER_OK || n == 0)
        return s;
    /* the new spheres: x, y, z, r records into positions and radii */
    double *xr = sinter_realloc_array(st->ctx, NULL, 4 * n, sizeof(double));
    if (xr == NULL && !st->domain.on)
        return sinter_last_status(st->ctx);
    for (size_t k = 0; xr != NULL && k < n; ++k) {
        const double *e = ins->near + 4 * (first_new + k);
        memcpy(xr + 3 * k, e, 3 * sizeof(double));
        xr[3 * n + k] = e[3];
    }
    if (st->domain.on) {
        s = sinter_domain_agree(st->ctx, &st->domain,
                                xr != NULL ? SINTER_OK : sinter_last_status(st->ctx));
        if (s == SINTER_OK)
            s = add_across(st, ins, xr, n);
        sinter_free(st->ctx, xr);
        if (s != SINTER_OK)
            return s;
        ins->inserted += n;
        st->forces_current = 0;
        return sinter_stepper_prepare(st);
    }
    /* runs of one material in one call each (one run without a mixture), after a reserve so
     * that no call after the first runs out of memory */
    size_t first = 0;
    if (sinter_radius_sampler_mixture(ins->sampler, NULL) > 0)
        s = sinter_particles_reserve(st->ps, st->ps->count + n);
    for (size_t k = 0; k < n && s == SINTER_OK;) {
        size_t j = k + 1, at = 0;
        while (j < n && ins->made[j] == ins->made[k])
            ++j;
        s = sinter_particles_add(st->ps, j - k, xr + 3 * k, xr + 3 * n + k, ins->made[k],
                                 p->temperature, &at);
        first = k == 0 ? at : first;
        k = j;
    }
    sinter_free(st->ctx, xr);
    if (s != SINTER_OK)
        return s;
    sinter_particles *ps = st->ps;
    for (size_t i = first; i < first + n; ++i) {
        for (int d = 0; d < 3; ++d)
            ps->v[3 * i + d] = o->velocity[d];
        ins->mass_done += ps->mass[i];
    }
    ins->inserted += n;
    st->forces_current = 0;
    return sinter_stepper_prepare(st);
}
