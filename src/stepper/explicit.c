/*
 * Explicit stepper: velocity Verlet for translation and rotation (kick, drift,
 * force, kick), with the total rotation vector updated by the Rodrigues
 * composition of seed 003 eq. 45. A step whose new state is not finite is
 * rejected: the last accepted state is restored and the error names the
 * particle, the quantity and the time.
 */
#include <math.h>
#include <string.h>

#include "contact/chunks.h"
#include "core/ranges_run.h"
#include "core/stream_store.h"
#include "insertion.h"
#include "sanity.h"
#include "stepper.h"
#include "verlet_blocks.h"

/* The spare arrays at the set's capacity (the set may have grown since the last step); see
 * stepper.h. */
sinter_status sinter_explicit_reserve(sinter_stepper *st)
{
    const size_t cap = st->ps->capacity;
    if (st->spare_capacity == cap && st->spare[0] != NULL)
        return SINTER_OK;
    for (int k = 0; k < 4; ++k) {
        double *grown = sinter_realloc_array(st->ctx, st->spare[k], 3 * cap + 1, sizeof(double));
        if (grown == NULL)
            return sinter_last_status(st->ctx); /* the ones grown so far are grown again */
        if (k < 3 || st->rotation)              /* the ones the steps write: touched here, once */
            memset(grown, 0, (3 * cap + 1) * sizeof(double));
        st->spare[k] = grown;
    }
    st->spare_capacity = cap;
    return SINTER_OK;
}

sinter_status sinter_explicit_keep_spare(sinter_stepper *st)
{
    const size_t cap = st->ps->capacity;
    if (st->spare[0] == NULL || st->spare_capacity == cap)
        return SINTER_OK;
    for (int k = 0; k < 4; ++k) {
        double *grown = sinter_realloc_array(st->ctx, st->spare[k], 3 * cap + 1, sizeof(double));
        if (grown == NULL)
            return sinter_last_status(st->ctx);
        if (cap > st->spare_capacity)
            memset(grown + 3 * st->spare_capacity, 0,
                   (3 * (cap - st->spare_capacity) + 1) * sizeof(double));
        st->spare[k] = grown;
    }
    st->spare_capacity = cap;
    return SINTER_OK;
}

/* The acceleration of gravity when it is the stepper's first force model (kick_drift then
 * writes its force, m g, instead of zero), else NULL. */
static const double *first_gravity(const sinter_stepper *st)
{
    if (st->force_count == 0 || st->forces[0].model->ops != &sinter_force_gravity)
        return NULL;
    return st->forces[0].model->param;
}

/* Exchange the set's x, v, w and, when the stepper integrates it, rot with the spare arrays
 * (same capacity, same allocator). */
static void swap_spare(sinter_stepper *st)
{
    sinter_particles *ps = st->ps;
    double **fields[4] = {&ps->x, &ps->v, &ps->w, &ps->rot};
    for (int k = 0; k < (st->rotation ? 4 : 3); ++k) {
        double *t = *fields[k];
        *fields[k] = st->spare[k];
        st->spare[k] = t;
    }
}

/* 1 if any particle is fixed or does not rotate (then the general loop is needed); found
 * again only when the particles were added, removed, reordered or written (their flags may
 * have changed), with the smallest radius (the sanity check's measure of the step). */
static int any_special(sinter_stepper *st)
{
    const sinter_particles *ps = st->ps;
    if (st->particles_known && st->known_layout == ps->layout_generation &&
        st->known_write == ps->write_generation)
        return st->any_special;
    uint32_t all = 0;
    double rmin = INFINITY;
    for (size_t i = 0; i < ps->count; ++i) {
        all |= ps->flags[i];
        rmin = ps->radius[i] < rmin ? ps->radius[i] : rmin;
    }
    st->any_special = (all & (SINTER_PARTICLE_FIXED | SINTER_PARTICLE_NO_ROTATION)) != 0;
    st->rmin = rmin;
    st->particles_known = 1;
    st->known_layout = ps->layout_generation;
    st->known_write = ps->write_generation;
    return st->any_special;
}

/* 0 for a finite value, NaN for an infinite or NaN one: z * 0. Summing these tells, value by
 * value and without branches, whether all were finite (the sum of zeros cannot overflow). */
static inline double nonfinite(double z)
{
    return z * 0.0;
}

/* The threads of the integrator's passes: the step's, from SINTER_THREADED_PARTICLES. */
static int pass_threads(const sinter_stepper *st)
{
    return st->ps->count < SINTER_THREADED_PARTICLES ? 1 : sinter_threads(st->ctx);
}

/* The particle ranges of the integrator's passes on `threads` threads (contact/chunks.h). */
static sinter_particle_ranges particle_ranges(const sinter_stepper *st, int threads)
{
    return sinter_chunks_particle_ranges(&st->pp.chunks, st->ps->count, threads);
}

/* The passes' factors for step h, made or kept (verlet_blocks.h; with gravity g as the first
 * force), or NULL (ghosts or subdomains: their rows' masses are copied by other stages). */
static const sinter_verlet_factors *factors_for(sinter_stepper *st, double h, const double g[3])
{
    const sinter_particles *ps = st->ps;
    if (ps->ghost_count > 0 || st->domain.on)
        return NULL;
    return sinter_verlet_factors_for(st->ctx, &st->verlet_factors, ps->count, ps->mass, ps->inertia,
                                     ps->layout_generation, ps->write_generation, h, g);
}

/* The factors kept by factors_for when they still hold for these particles and step h, else
 * NULL (the second kick: the evaluation between may have changed the particles). */
static const sinter_verlet_factors *kept_factors(const sinter_stepper *st, double h)
{
    const sinter_particles *ps = st->ps;
    const sinter_verlet_factors *c = &st->verlet_factors;
    const int holds = c->count == ps->count && c->count > 0 && ps->ghost_count == 0 &&
                      !st->domain.on && c->layout == ps->layout_generation &&
                      c->write == ps->write_generation && c->m == ps->mass && c->j == ps->inertia &&
                      memcmp(&c->h, &h, sizeof(h)) == 0;
    return holds ? c : NULL;
}

/* One range's part of plain_kick_drift (ranges_run.h): its temperatures, its kick and drift,
 * its heat powers zeroed; its first bad particles and largest displacements into the job. */
typedef struct kick_drift_job {
    sinter_stepper *st;
    const sinter_verlet_arrays *arrays;
    const sinter_particle_ranges *r;
    double h, h_heat; /* the mechanics' step, the temperatures' (heat_interval.h) */
    const double *g;
    int exact, stream, heat_update;
    double *heat; /* the heat powers to zero, or NULL */
    sinter_drift_scan scan[SINTER_CHUNKS_MAX];
    size_t heat_bad[SINTER_CHUNKS_MAX], heat_hot[SINTER_CHUNKS_MAX];
} kick_drift_job;

static void kick_drift_range(void *data, int t)
{
    kick_drift_job *job = data;
    const size_t lo = sinter_particle_range_lo(job->r, t),
                 hi = sinter_particle_range_lo(job->r, t + 1);
    const size_t n = job->st->ps->count;
    job->heat_bad[t] = job->heat_hot[t] = n;
    if (job->heat_update) { /* the temperatures first, with the heat powers zeroed below */
        size_t b, o;
        sinter_thermal_explicit_range(job->st, job->h_heat, lo, hi, &b, &o);
        job->heat_bad[t] = b < hi ? b : n;
        job->heat_hot[t] = o < hi ? o : n;
    }
    sinter_drift_scan d = sinter_verlet_kick_drift(job->arrays, job->h, job->g, job->st->rotation,
                                                   job->exact, job->stream, lo, hi);
    sinter_put_fence(job->stream); /* this thread's streamed stores before the barrier */
    if (job->heat != NULL)
        memset(job->heat + lo, 0, (hi - lo) * sizeof(double));
    d.bad = d.bad < hi ? d.bad : n;
    job->scan[t] = d;
}

/*
 * kick_drift for particles that are neither fixed nor without rotation (see there), by
 * particle ranges (particle_ranges) in vectorised blocks (verlet_blocks.c); with `exact`,
 * the displacement since the neighbour build is measured against x_ref; `stream`: streaming
 * stores for the new x, v, w. The first non-finite particle (n: none) and the largest squared
 * displacements are the ranges' (a first and a maximum: the same for any split); with
 * `heat_update`, each range's temperature update before its drift (kick_drift).
 */
static sinter_drift_scan plain_kick_drift(sinter_stepper *st, double h, double h_heat,
                                          const double g[3], int threads, int exact, int stream,
                                          int heat_update, size_t heat_first[2])
{
    sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    const sinter_verlet_arrays arrays = {.x = ps->x,
                                         .v = ps->v,
                                         .w = ps->w,
                                         .rot = ps->rot,
                                         .f = ps->force,
                                         .tq = ps->torque,
                                         .m = ps->mass,
                                         .j = ps->inertia,
                                         .x0 = st->nb.x_ref,
                                         .nx = st->spare[0],
                                         .nv = st->spare[1],
                                         .nw = st->spare[2],
                                         .nrot = st->spare[3],
                                         .factors = factors_for(st, h, g)};
    const sinter_particle_ranges r = particle_ranges(st, threads);
    /* the heat powers are summed again by this step's evaluation: zeroed here, by the ranges
     * whose threads sum them (thermal.h, heat_zeroed) */
    kick_drift_job job = {.st = st,
                          .arrays = &arrays,
                          .r = &r,
                          .h = h,
                          .h_heat = h_heat,
                          .g = g,
                          .exact = exact,
                          .stream = stream,
                          .heat_update = heat_update,
                          .heat = st->thermal.count > 0 && !st->heat_skip ? ps->heat : NULL};
    sinter_ranges_run(r.team, r.count, kick_drift_range, &job);
    sinter_drift_scan all = {n, 0.0, 0.0, {0.0, 0.0, 0.0}};
    heat_first[0] = heat_first[1] = n;
    for (int t = 0; t < r.count; ++t) {
        const sinter_drift_scan d = job.scan[t];
        all.bad = d.bad < all.bad ? d.bad : all.bad;
        for (int a = 0; a < 3; ++a)
            all.axis2[a] = d.axis2[a] > all.axis2[a] ? d.axis2[a] : all.axis2[a];
        all.moved2 = d.moved2 > all.moved2 ? d.moved2 : all.moved2;
        all.step2 = d.step2 > all.step2 ? d.step2 : all.step2;
        heat_first[0] = job.heat_bad[t] < heat_first[0] ? job.heat_bad[t] : heat_first[0];
        heat_first[1] = job.heat_hot[t] < heat_first[1] ? job.heat_hot[t] : heat_first[1];
    }
    st->thermal.heat_zeroed = job.heat != NULL;
    return all;
}

/*
 * First half kick and drift, written into the spare arrays, which then become the set's
 * (the old state stays in the spare arrays for a rollback: no copy), and the total rotation
 * vector (seed 003 eq. 45, increment w h) in the same pass unless the option "rotation" is
 * 0. Positions and rotations are final for the step here, so their finiteness is checked
 * here; returns the first particle with a non-finite one, or n. The sanity check's measure
 * of the step (largest displacement; the smallest radius, kept between steps) goes into
 * *scan, and force and torque are zeroed after their last read (the next evaluation adds
 * into them). With `heat_update`, each range's explicit temperature update over h_heat (h, or
 * k h on every k-th step: heat_interval.h) first (thermal.h, sinter_thermal_explicit_range:
 * one parallel region fewer a step), its first particles with a bad and a hot temperature
 * into heat_first (the count for none).
 */
static size_t kick_drift(sinter_stepper *st, double h_heat, double h, int heat_update,
                         size_t heat_first[2], sinter_sanity_scan *scan)
{
    sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    const double *restrict x = ps->x, *restrict v = ps->v, *restrict w = ps->w,
                           *restrict rot = ps->rot;
    double *restrict f = ps->force, *restrict tq = ps->torque;
    const double *restrict m = ps->mass, *restrict j = ps->inertia;
    double *restrict nx = st->spare[0], *restrict nv = st->spare[1], *restrict nw = st->spare[2],
                     *restrict nrot = st->spare[3];
    const uint32_t *flags = ps->flags;
    const double half = 0.5 * h;
    const int threads = pass_threads(st);
    const int rotation = st->rotation;
    size_t bad = n;
    /* The neighbour list's staleness test needs the largest displacement since its build:
     * measured here, where the new positions are made, instead of in a pass of its own. */
    sinter_neighbors *nb = &st->nb;
    const double *restrict x0 = nb->x_ref;
    const int measure = nb->built && nb->layout_generation == ps->layout_generation &&
                        nb->ref_capacity >= 3 * n && x0 != NULL;
    /* gravity's force written where the force is zeroed: 0 + m g, as its evaluation adds it
     * (0 + m 0 = +0 without it) */
    const double *gravity = first_gravity(st);
    const double g[3] = {gravity ? gravity[0] : 0.0, gravity ? gravity[1] : 0.0,
                         gravity ? gravity[2] : 0.0};
    st->plain_particles = !any_special(st);
    if (st->plain_particles) {
        /* while the neighbour list's displacement bound holds, the step's largest
         * displacement is all it needs (sinter_neighbors_add_step): x_ref is not read */
        const int exact = measure && !sinter_neighbors_bound_holds(nb, ps);
        const sinter_drift_scan d = plain_kick_drift(
            st, h, h_heat, g, threads, exact, st->stores.stream_now, heat_update, heat_first);
        swap_spare(st);
        /* the walls' certificate: every particle moved by at most this along each axis */
        sinter_wall_skip_moved(&st->wall_skip, d.axis2);
        if (exact)
            sinter_neighbors_set_moved(nb, ps, d.moved2);
        else if (measure)
            sinter_neighbors_add_step(nb, ps, sqrt(d.step2));
        st->forces_zeroed = 1;
        st->gravity_seeded = gravity != NULL;
        scan->moved2 = d.step2;
        scan->rmin = st->rmin; /* found with any_special */
        return d.bad;
    }
    /* fixed or non-rotating particles among them: one thread, every case by its flags */
    heat_first[0] = heat_first[1] = n;
    if (heat_update)
        sinter_thermal_explicit_range(st, h_heat, 0, n, &heat_first[0], &heat_first[1]);
    double moved2 = 0.0, step2 = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const uint32_t fl = flags[i];
        double vi[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
        double wi[3] = {w[3 * i], w[3 * i + 1], w[3 * i + 2]};
        if (!(fl & SINTER_PARTICLE_FIXED)) {
            const double a = half / m[i];
            for (int d = 0; d < 3; ++d)
                vi[d] += a * f[3 * i + d];
        }
        if (!(fl & (SINTER_PARTICLE_NO_ROTATION | SINTER_PARTICLE_FIXED))) {
            const double b = half / j[i];
            for (int d = 0; d < 3; ++d)
                wi[d] += b * tq[3 * i + d];
        }
        const double da[3] = {h * wi[0], h * wi[1], h * wi[2]};
        double alpha[3];
        double z = 0.0, s2 = 0.0, d2 = 0.0;
        for (int d = 0; d < 3; ++d) {
            const size_t k = 3 * i + (size_t)d;
            nv[k] = vi[d];
            nw[k] = wi[d];
            nx[k] = x[k] + h * vi[d];
            alpha[d] = rot[k];
            const double s = nx[k] - x[k];
            s2 += s * s;
            if (measure) {
                const double e = nx[k] - x0[k];
                d2 += e * e;
            }
        }
        if (rotation) {
            sinter_compose_rotation(alpha, da);
            for (int d = 0; d < 3; ++d)
                nrot[3 * i + d] = alpha[d];
        }
        for (int d = 0; d < 3; ++d)
            z += nonfinite(nx[3 * i + d]) + nonfinite(alpha[d]);
        moved2 = d2 > moved2 ? d2 : moved2;
        step2 = s2 > step2 ? s2 : step2;
        if (!(z == 0.0) && i < bad)
            bad = i;
    }
    swap_spare(st);
    if (measure)
        sinter_neighbors_set_moved(nb, ps, moved2);
    scan->moved2 = step2;
    scan->rmin = st->rmin; /* found with any_special */
    return bad;
}

/* The second half kick of the particles of one partition range, run by the force law on the
 * thread that summed their forces (sinter_force_eval.range_final): the same operations as
 * kick's, so the same bits. */
typedef struct range_kick {
    sinter_stepper *st;
    double h;
    size_t bad[SINTER_CHUNKS_MAX];   /* per range: the first non-finite particle, or n */
    const sinter_particle_ranges *r; /* kick's own pass (kick_one_range); NULL in the law */
} range_kick;

static void kick_range(void *user, int range, size_t lo, size_t hi)
{
    range_kick *job = user;
    sinter_particles *ps = job->st->ps;
    const size_t b = sinter_verlet_kick(ps->v, ps->w, ps->force, ps->torque, ps->mass, ps->inertia,
                                        kept_factors(job->st, job->h), job->h, lo, hi);
    job->bad[range] = b < hi ? b : ps->count;
}

/* Range t of kick's own pass over the particle ranges (ranges_run.h). */
static void kick_one_range(void *user, int t)
{
    range_kick *job = user;
    kick_range(user, t, sinter_particle_range_lo(job->r, t),
               sinter_particle_range_lo(job->r, t + 1));
}

/* The second half kick of particles [lo, hi), any of them fixed or without rotation, every
 * case by its flags; returns the first particle whose velocity or spin is not finite, or n. */
static size_t kick_flagged(sinter_stepper *st, double h, size_t lo, size_t hi)
{
    sinter_particles *ps = st->ps;
    double *restrict v = ps->v, *restrict w = ps->w;
    const double *restrict f = ps->force, *restrict tq = ps->torque, *restrict m = ps->mass,
                           *restrict j = ps->inertia;
    const uint32_t *flags = ps->flags;
    const double half = 0.5 * h;
    size_t bad = ps->count;
    for (size_t i = lo; i < hi; ++i) {
        const uint32_t fl = flags[i];
        if (!(fl & SINTER_PARTICLE_FIXED)) {
            const double a = half / m[i];
            for (int d = 0; d < 3; ++d)
                v[3 * i + d] += a * f[3 * i + d];
        }
        if (!(fl & (SINTER_PARTICLE_NO_ROTATION | SINTER_PARTICLE_FIXED))) {
            const double b = half / j[i];
            for (int d = 0; d < 3; ++d)
                w[3 * i + d] += b * tq[3 * i + d];
        }
        /* Every value must be finite (the rotation too: sinter_particles_validate refuses a
         * non-finite one, so a step that makes one could never be continued). */
        double z = 0.0;
        for (int d = 0; d < 3; ++d)
            z += nonfinite(v[3 * i + d]) + nonfinite(w[3 * i + d]);
        if (!(z == 0.0) && bad == ps->count)
            bad = i;
    }
    return bad;
}

/* Second half kick; returns the index of the first particle whose velocity or spin is not
 * finite, or n (positions and rotations were checked by kick_drift). */
static size_t kick(sinter_stepper *st, double h)
{
    const size_t n = st->ps->count;
    const int threads = pass_threads(st);
    size_t bad = n;
    if (st->plain_particles) { /* kick_drift found none fixed or without rotation */
        const sinter_particle_ranges r = particle_ranges(st, threads);
        range_kick job = {st, h, {0}, &r};
        sinter_ranges_run(r.team, r.count, kick_one_range, &job);
        for (int t = 0; t < r.count; ++t)
            bad = job.bad[t] < bad ? job.bad[t] : bad;
        return bad;
    }
    if (threads <= 1) /* (a region of one thread costs a team's allocation: ranges_run.h) */
        return kick_flagged(st, h, 0, n);
#pragma omp parallel for num_threads(threads) schedule(static) reduction(min : bad)
    for (int t = 0; t < threads; ++t) {
        const size_t b = kick_flagged(st, h, n * (size_t)t / (size_t)threads,
                                      n * (size_t)(t + 1) / (size_t)threads);
        bad = b < bad ? b : bad;
    }
    return bad;
}

/* 1 if this step's second half kick may run in the law's region: plain particles integrated
 * on the partition's ranges, and no host heat model, which might read the velocities of the
 * state after the law (the half-kicked ones, as before). */
static int kick_with_law(const sinter_stepper *st)
{
    if (st->ps->ghost_count > 0) /* the reverse halo comes after the law, before the kick */
        return 0;
    if (!st->plain_particles || particle_ranges(st, pass_threads(st)).plo == NULL)
        return 0;
    for (size_t k = 0; k < st->thermal.count; ++k)
        if (st->thermal.slots[k].model->ops->eval == sinter_heat_host_eval)
            return 0;
    return 1;
}

/* Steps timed before the choice of stores (sinter_store_choice): the first few of each kind
 * warm the caches and are not counted; then the shortest of 8 steps of each kind decides. */
enum { STREAM_MIN_PARTICLES = 65536, STREAM_WARMUP = 4, STREAM_TRIALS = 16 };

/* The kind of stores for the next step: 1 streaming, 0 plain. */
static int choose_stores(sinter_stepper *st)
{
    sinter_store_choice *c = &st->stores;
    const size_t n = st->ps->count;
    /* the context's count, not the thread choice's of this step (thread_choice.h) */
    const int threads = n < 4096 ? 1 : sinter_threads_allowed(st->ctx);
    if (!SINTER_STREAMING_STORES || c->option == 0)
        return 0;
    if (c->option == 1)
        return 1;
    if (n < STREAM_MIN_PARTICLES) /* arrays of a few MB: in the caches of any machine */
        return 0;
    if (c->layout != st->ps->layout_generation || c->threads != threads) {
        c->decided = -1; /* other particles or threads: measured again */
        c->layout = st->ps->layout_generation;
        c->threads = threads;
        c->trials = 0;
        c->best[0] = c->best[1] = INFINITY;
    }
    return c->decided >= 0 ? c->decided : c->trials & 1;
}

int sinter_explicit_stores_measuring(const sinter_stepper *st)
{
    const sinter_store_choice *c = &st->stores;
    return SINTER_STREAMING_STORES && c->option == -1 && c->decided < 0 &&
           st->ps->count >= STREAM_MIN_PARTICLES;
}

/* An accepted step of `seconds`, taken with the stores of choose_stores. */
static void time_stores(sinter_stepper *st, double seconds)
{
    sinter_store_choice *c = &st->stores;
    if (c->option != -1 || c->decided >= 0 || st->ps->count < STREAM_MIN_PARTICLES ||
        c->threads == 0)
        return;
    const int k = c->trials++;
    if (k >= STREAM_WARMUP && seconds < c->best[k & 1])
        c->best[k & 1] = seconds;
    if (c->trials == STREAM_WARMUP + STREAM_TRIALS)
        c->decided = c->best[1] < c->best[0];
}

static const char *first_bad_quantity(const sinter_particles *ps, size_t i)
{
    for (int d = 0; d < 3; ++d)
        if (!isfinite(ps->force[3 * i + d]))
            return "force";
    for (int d = 0; d < 3; ++d)
        if (!isfinite(ps->x[3 * i + d]))
            return "position";
    for (int d = 0; d < 3; ++d)
        if (!isfinite(ps->v[3 * i + d]))
            return "velocity";
    for (int d = 0; d < 3; ++d)
        if (!isfinite(ps->w[3 * i + d]))
            return "spin";
    return "rotation";
}

/* A rejected step undone: the state at t back from the spare arrays, the temperatures, the
 * time and the walls; the forces and heat powers the drift zeroed are evaluated again. */
static void undo_step(sinter_stepper *st, double t_start, int heat_now)
{
    swap_spare(st);
    sinter_neighbors_positions_restored(&st->nb);
    if (heat_now) /* (temperatures saved this step: heat_interval.h) */
        sinter_thermal_rollback(st);
    st->time = t_start;
    if (st->walls != NULL)
        sinter_walls_move(st->walls, t_start);
    st->forces_current = 0;
    st->forces_zeroed = st->gravity_seeded = 0;
    st->thermal.heat_zeroed = 0;
    st->ghosts.built = 0; /* made again, from the restored owners, at the next build */
    st->stats.rejected++;
}

/* The first particle of `bad` that is owned (ghosts are their owners' to check), or n. */
static size_t owned_bad(const sinter_particles *ps, size_t bad, int domain)
{
    return domain && bad >= ps->count - ps->ghost_count ? ps->count : bad;
}

/*
 * One step. With domain operations (domain/domain.h) its collective stages are: the status
 * agreed after the drift together with the rebuild decision (A, one reduction), the forward
 * halo, the host's redistribution inside the evaluation when A decided a rebuild, the status
 * agreed after the kick and the checks together with the wall reactions (C, one reduction),
 * the forward halo of the accepted state, and the commit (local). Between two of them a
 * subdomain that failed only skips its own work, so none waits for another.
 */
sinter_status sinter_explicit_step(sinter_stepper *st, double h)
{
    const int periodic = sinter_ghosts_on(&st->ghosts);
    const int domain = st->domain.on;
    sinter_status s = periodic ? sinter_periodic_check(st) : SINTER_OK;
    if (s == SINTER_OK && domain) /* (settings not yet supported across subdomains) */
        s = sinter_domain_check(st);
    /* continuous insertion: the spheres due now, their forces evaluated (insertion.c) */
    if (s == SINTER_OK)
        s = sinter_insertion_stage(st);
    if (s == SINTER_OK)
        s = sinter_explicit_reserve(st);
    if (s != SINTER_OK && !domain)
        return s;
    const double t_start = st->time, clock_start = sinter_clock();
    st->stores.stream_now = choose_stores(st);
    /* Temperatures first, with the heat powers of the state at t (seed 003 sec. 4, step 5):
     * the explicit scheme's in the kick and drift's pass, range by range (thermal.h) */
    const int explicit_heat =
        st->thermal.count > 0 && st->thermal.scheme == SINTER_THERMAL_EXPLICIT;
    /* heat_interval k (heat_interval.h): the temperatures advance over k h on every k-th step,
     * and only the evaluation before such a step sums the heat models */
    if (s == SINTER_OK && (s = sinter_heat_interval_check(st)) != SINTER_OK) {
        st->stats.rejected++;
        if (!domain)
            return s;
    }
    const uint64_t step = st->stats.steps;
    const int heat_update = explicit_heat && sinter_heat_interval_update(st, step);
    const double h_heat = heat_update && st->heat_interval > 1 ? (double)st->heat_interval * h : h;
    st->heat_skip = explicit_heat && !sinter_heat_interval_eval(st, step);
    /* implicit conduction's solve is collective (domain/solve.h): every subdomain or none */
    if (domain && !explicit_heat && st->thermal.count > 0)
        s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK) {
        s = heat_update     ? sinter_thermal_explicit_begin(st)
            : explicit_heat ? SINTER_OK
                            : sinter_thermal_implicit_advance(st, h);
        if (s != SINTER_OK) {
            st->heat_skip = 0;
            st->stats.rejected++;
            if (!domain)
                return s;
        }
    }
    if (explicit_heat && !heat_update) { /* the temperatures stay those the last step tested */
        st->thermal.hot_checked = 1;
        st->thermal.hot = st->ps->count;
    }
    const int heat_now = heat_update || !explicit_heat; /* temperatures saved this step */
    int drifted = 0;
    sinter_sanity_scan scan;
    size_t heat_first[2];
    const size_t n_drift = st->ps->count; /* (a neighbour build may make other ghosts) */
    size_t bad_drift = n_drift;
    if (s == SINTER_OK) {
        const double t0 = sinter_clock();
        bad_drift =
            owned_bad(st->ps, kick_drift(st, h_heat, h, heat_update, heat_first, &scan), domain);
        drifted = 1;
        st->stats.seconds_integrate += sinter_clock() - t0;
    }
    if (drifted && heat_update) {
        s = sinter_thermal_explicit_end(st, h_heat, heat_first[0], heat_first[1]);
        if (s != SINTER_OK) { /* refused: temperatures restored; the drift undone, and the
                               * forces and heat powers it zeroed evaluated again */
            st->heat_skip = 0;
            swap_spare(st);
            sinter_neighbors_positions_restored(&st->nb);
            st->forces_current = 0;
            st->forces_zeroed = st->gravity_seeded = 0;
            st->thermal.heat_zeroed = 0;
            st->stats.rejected++;
            drifted = 0;
            if (!domain)
                return s;
        }
    }
    if (drifted) {
        st->time = t_start + h;
        if (st->walls != NULL)
            s = sinter_walls_move(st->walls, st->time);
    }
    if (domain) { /* stage A: every subdomain drifted, or all stop here (with the rebuild
                   * decision in the same reduction) */
        const sinter_status a = sinter_stepper_agree_drift(st, s);
        if (a != SINTER_OK) {
            if (drifted)
                undo_step(st, t_start, heat_now);
            return a;
        }
    }
    range_kick job = {st, h, {0}, NULL};
    for (int r = 0; r < SINTER_CHUNKS_MAX; ++r)
        job.bad[r] = st->ps->count;
    if (s == SINTER_OK && kick_with_law(st)) {
        st->range_final = kick_range;
        st->range_final_user = &job;
    }
    /* halo: the ghosts take their owners' new state (ghosts/ghosts.h); a neighbour build in
     * the evaluation makes them again from the owners */
    if (s == SINTER_OK && st->ps->ghost_count > 0 && !domain)
        sinter_ghosts_forward(&st->ghosts, st->ps);
    if (s == SINTER_OK && domain) /* (the host's ghosts of other subdomains) */
        s = sinter_domain_forward(st->ctx, &st->domain, st->ps);
    st->heat_in_law = !st->heat_skip; /* conduction in the law's region when it can (thermal.h) */
    if (s == SINTER_OK)
        s = sinter_stepper_eval_forces(st, h);
    st->domain.decided = 0; /* (taken by that evaluation, or by none) */
    const int kicked = st->range_final != NULL && st->ranges_final;
    st->range_final = NULL;
    st->range_final_user = NULL;
    st->heat_in_law = 0;
    st->heat_skip = 0;                     /* other evaluations sum the heat */
    st->thermal.heat_zeroed = 0;           /* for that evaluation only */
    sinter_neighbors_clear_moved(&st->nb); /* valid for that evaluation only */
    size_t bad = st->ps->count;
    if (s == SINTER_OK) {
        const double t0 = sinter_clock();
        bad = st->ps->count;
        if (kicked) /* by the law, range by range */
            for (int r = 0; r < SINTER_CHUNKS_MAX; ++r)
                bad = job.bad[r] < bad ? job.bad[r] : bad;
        else
            bad = kick(st, h);
        bad = owned_bad(st->ps, bad, domain);
        if (bad_drift < n_drift)
            bad = bad_drift < bad ? bad_drift : bad;
        /* halo again: the accepted state's ghosts are exact images of their owners (the
         * host's ghosts after stage C below) */
        if (st->ps->ghost_count > 0 && !domain)
            sinter_ghosts_forward(&st->ghosts, st->ps);
        st->stats.seconds_integrate += sinter_clock() - t0;
    }
    if (s == SINTER_OK && bad == st->ps->count)
        s = sinter_sanity_step(st, st->spare[0], t_start, h, &scan); /* spare: x at t */
    if (s == SINTER_OK && bad == st->ps->count)
        s = sinter_sanity_domain_moved(st, "step", t_start, h, sqrt(scan.moved2));
    /* (the energy check's clusters do not follow pairs across a periodic face or a
     * subdomain border yet) */
    if (s == SINTER_OK && bad == st->ps->count && st->energy_check > 0 && !periodic && !domain &&
        st->stats.steps % (uint64_t)st->energy_check == 0)
        s = sinter_sanity_energy(st, t_start, h); /* energy created (sanity.c, 4) */
    if (s == SINTER_OK && bad < st->ps->count) {
        const char *what = first_bad_quantity(st->ps, bad);
        s = sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                        "step from t = %.9g s to %.9g s rejected: the %s of particle %zu (id "
                        "%llu) is not finite; the time step %g s is probably too large for the "
                        "contact stiffness (see sinter_stable_dt_hertz). The last accepted "
                        "state is kept.",
                        t_start, t_start + h, what, bad, (unsigned long long)st->ps->id[bad], h);
    }
    /* stage C with domain operations: the status agreed together with the wall reactions
     * (one reduction), the commit's memory taken before so that the commit cannot fail */
    if (domain && s == SINTER_OK)
        s = sinter_stepper_commit_reserve(st);
    if (domain)
        s = sinter_stepper_agree_reactions(st, s);
    if (s != SINTER_OK) {
        /* Roll back: state (the spare arrays hold it), time and walls; history was never
         * committed. */
        undo_step(st, t_start, heat_now);
        if (domain) { /* the ghosts too, and made again at the next step */
            st->domain.rebuild_due = 1;
            const sinter_status r = sinter_domain_forward(st->ctx, &st->domain, st->ps);
            (void)r; /* (the step's error is the one reported) */
        }
        return s;
    }
    if (domain && (s = sinter_domain_forward(st->ctx, &st->domain, st->ps)) != SINTER_OK)
        return s;
    s = domain ? sinter_stepper_commit_agreed(st) : sinter_stepper_commit(st);
    if (s == SINTER_OK)
        time_stores(st, sinter_clock() - clock_start);
    return s;
}
