#define _POSIX_C_SOURCE 200809L
/* Steppers: creation, submodels, the evaluation pipeline, advance and statistics. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "contact/host_views.h"
#include "heat/gas_gap.h"
#include "sanity.h"
#include "particles/id_index.h"
#include "core/id_row.h"
#include "stepper.h"
#include "stepper/wall_sums.h"
#include "stepper/qs_domain.h"
#include "electric/electric.h"
#include "insertion.h"
#include "migrate.h"

double sinter_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

sinter_status sinter_stepper_create(sinter_stepper **out, sinter_ctx *ctx, sinter_stepper_kind kind,
                                    sinter_particles *particles, sinter_walls *walls)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, particles);
    if (kind != SINTER_STEPPER_EXPLICIT && kind != SINTER_STEPPER_STAGGERED &&
        kind != SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_stepper_create: stepper kind %d is not available (0: "
                           "SINTER_STEPPER_EXPLICIT, 1: SINTER_STEPPER_STAGGERED, 2: "
                           "SINTER_STEPPER_QUASISTATIC)",
                           (int)kind);
    if (particles->ctx != ctx || (walls != NULL && walls->ctx != ctx))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_create: the particles and walls must belong to the "
                           "same context as the stepper");
    sinter_stepper *st = sinter_calloc(ctx, 1, sizeof(*st));
    if (st == NULL)
        return sinter_last_status(ctx);
    st->ctx = ctx;
    st->kind = kind;
    st->ps = particles;
    st->walls = walls;
    st->dt = 1e-5;
    st->rotation = 1;
    st->dt_check = 1;
    st->energy_check = SINTER_ENERGY_CHECK_INTERVAL;
    st->heat_interval = 1;
    st->stores.option = -1; /* measured (explicit.c) */
    st->stores.decided = -1;
    sinter_thread_choice_init(&st->threads_choice);
    st->domain.rank = -1;
    sinter_neighbors_init(&st->nb, ctx, 0.0);
    st->stats.struct_size = sizeof(sinter_stepper_stats);
    st->stats.dt = st->dt;
    sinter_staggered_init(&st->staggered);
    sinter_frozen_init(&st->frozen);
    sinter_qs_options_default(&st->quasistatic_options);
    *out = st;
    return SINTER_OK;
}

void sinter_stepper_destroy(sinter_stepper *st)
{
    if (st == NULL)
        return;
    sinter_ctx *ctx = st->ctx;
    for (size_t k = 0; k < st->force_count; ++k) {
        sinter_history_free(ctx, &st->forces[k].pp);
        sinter_history_free(ctx, &st->forces[k].pw);
    }
    sinter_free(ctx, st->forces);
    sinter_neighbors_free(&st->nb);
    sinter_ghosts_free(ctx, &st->ghosts);
    sinter_domain_free(ctx, &st->domain);
    sinter_contact_list_free(ctx, &st->pp);
    sinter_contact_list_free(ctx, &st->pw);
    sinter_wall_skip_free(ctx, &st->wall_skip);
    sinter_verlet_factors_free(ctx, &st->verlet_factors);
    sinter_free(ctx, st->wall_force);
    sinter_free(ctx, st->pw_reaction);
    sinter_free(ctx, st->wall_sums_scratch);
    sinter_insertion_destroy(ctx, st->insertion);
    sinter_free(ctx, st->dissipation);
    for (int k = 0; k < 4; ++k)
        sinter_free(ctx, st->spare[k]);
    sinter_free(ctx, st->wall_arrays);
    sinter_thermal_free(ctx, &st->thermal);
    sinter_staggered_free(ctx, &st->staggered);
    sinter_frozen_free(ctx, &st->frozen);
    sinter_qs_destroy(st->quasistatic);
    sinter_migrate_stage_free(ctx, st->migrate);
    if (st->quasistatic_options.host_law.destroy_user != NULL)
        st->quasistatic_options.host_law.destroy_user(st->quasistatic_options.host_law_user);
    sinter_free(ctx, st->furnace);
    sinter_free(ctx, st->energy_flag);
    sinter_free(ctx, st->energy_store);
    sinter_free(ctx, st->energy_start);
    sinter_free(ctx, st->energy_adj);
    sinter_free(ctx, st->energy_force);
    sinter_free(ctx, st);
}

sinter_status sinter_stepper_set_kind(sinter_stepper *st, int kind)
{
    if (kind != SINTER_STEPPER_EXPLICIT && kind != SINTER_STEPPER_STAGGERED &&
        kind != SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED, "stepper kind %d is not available",
                           kind);
    if (st->stats.steps > 0 || st->stats.rejected > 0)
        return sinter_fail(st->ctx, SINTER_ERR_STATE,
                           "the stepper has taken steps; its kind can no longer change");
    if (kind == SINTER_STEPPER_STAGGERED && st->thermal.scheme != SINTER_THERMAL_EXPLICIT)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "the staggered stepper integrates temperatures itself (seed 000 eq. "
                           "36); reset the thermal scheme to SINTER_THERMAL_EXPLICIT first");
    st->kind = kind;
    return SINTER_OK;
}

/* Option "sort_interval" (every stepper kind; the quasi-static one keys its links and orders
 * by particle id, qs_ids.c): sort the particles by position (sinter_particles_sort_spatial)
 * after every so many accepted steps; 0 (the default) never. */
static sinter_status set_sort_interval(sinter_stepper *st, double value)
{
    static const char *func = "sinter_stepper_set_option";
    if (!(value >= 0.0 && value <= 1e15 && value == floor(value)))
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "%s: sort_interval = %g must be a whole number of steps >= 0 (0: "
                           "never sort)",
                           func, value);
    st->sort_interval = (uint64_t)value;
    st->steps_since_sort = st->sort_interval; /* due: sorted before the next step */
    return SINTER_OK;
}

/* Option "rotation" (explicit and staggered steppers): 1 (the default) integrates the total
 * rotation vector of seed 003 eq. 45 (SINTER_FIELD_ROTATION); 0 leaves it as it is. */
static sinter_status set_rotation(sinter_stepper *st, double value)
{
    if (st->kind == SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_stepper_set_option: rotation: the quasi-static stepper has no "
                           "total rotation vector to integrate");
    if (value != 0.0 && value != 1.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: rotation = %g must be 1 (integrate the "
                           "total rotation vector, the default) or 0 (leave it as it is)",
                           value);
    st->rotation = value == 1.0;
    return SINTER_OK;
}

/* Option "stream_stores" (explicit stepper): -1 (the default) times steps with and without
 * streaming stores for the new positions, velocities and spins and keeps the faster; 1
 * always, 0 never (sinter_store_choice). */
static sinter_status set_stream_stores(sinter_stepper *st, double value)
{
    if (value != -1.0 && value != 0.0 && value != 1.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: stream_stores = %g must be -1 (measure "
                           "which is faster, the default), 0 (never) or 1 (always)",
                           value);
    st->stores.option = (int)value;
    st->stores.decided = -1;
    st->stores.threads = 0; /* measured afresh */
    return SINTER_OK;
}

/* Option "thread_choice" (explicit stepper): -1 (the default) times steps on the context's
 * threads and on one and takes the faster, measured again from time to time; 0 always the
 * context's threads (thread_choice.h). */
static sinter_status set_thread_choice(sinter_stepper *st, double value)
{
    if (value != -1.0 && value != 0.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: thread_choice = %g must be -1 (time "
                           "steps on the context's threads and on one and take the faster, the "
                           "default) or 0 (always the context's threads)",
                           value);
    sinter_thread_choice_init(&st->threads_choice);
    st->threads_choice.option = (int)value;
    return SINTER_OK;
}

/* Option "reproducible" (the explicit stepper's sums in an order fixed by the ids, issue 43):
 * 0, the default, off; 1 on. The neighbour lists are built again, in the mode's order, at the
 * next evaluation; forces already current stay (a restart that sets its options after reading
 * a checkpoint continues bit for bit: a build changes no bit in this mode). */
static sinter_status set_reproducible(sinter_stepper *st, double value)
{
    if (value != 0.0 && value != 1.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: reproducible = %g must be 0 (off, the "
                           "default) or 1 (results independent of the decomposition and the "
                           "order in memory)",
                           value);
    const int on = value == 1.0;
    if (on == st->reproducible)
        return SINTER_OK;
    st->reproducible = on;
    st->nb.canonical = on;
    st->nb.built = 0;
    st->pw_reaction_valid = 0; /* (until an evaluation in the mode) */
    return SINTER_OK;
}

/* Options "dt_check" and "energy_check" (any stepper; the explicit one uses them, issue 35):
 * 1, the default, on; 0 off. */
static sinter_status set_check(sinter_stepper *st, const char *key, int *flag, double value)
{
    if (value != 0.0 && value != 1.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_option: %s = %g must be 1 (check, the default) or "
                           "0 (do not check)",
                           key, value);
    *flag = value == 1.0;
    return SINTER_OK;
}

sinter_status sinter_stepper_set_option(sinter_stepper *st, const char *key, double value)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, key);
    if (strcmp(key, "sort_interval") == 0)
        return set_sort_interval(st, value);
    if (strcmp(key, "rotation") == 0)
        return set_rotation(st, value);
    if (strcmp(key, "stream_stores") == 0)
        return set_stream_stores(st, value);
    if (strcmp(key, "thread_choice") == 0)
        return set_thread_choice(st, value);
    if (strcmp(key, "dt_check") == 0)
        return set_check(st, key, &st->dt_check, value);
    if (strcmp(key, "reproducible") == 0)
        return set_reproducible(st, value);
    if (strcmp(key, "energy_check") == 0) {
        if (!(value >= 0.0 && value <= 1e6) || value != floor(value))
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_set_option: energy_check = %g must be a whole "
                               "number: 0 (do not check) or N >= 1 (check every N-th step; "
                               "default %d)",
                               value, SINTER_ENERGY_CHECK_INTERVAL);
        st->energy_check = (int)value;
        return SINTER_OK;
    }
    if (sinter_heat_interval_is_key(key))
        return sinter_heat_interval_set(st, value);
    if (sinter_frozen_is_key(key))
        return sinter_frozen_set(st, key, value);
    /* an unknown key of a quasi-static stepper is refused with the list of its qs_* keys */
    if (st->kind == SINTER_STEPPER_QUASISTATIC &&
        (strncmp(key, "qs_", 3) == 0 || !sinter_staggered_is_option(key)))
        return sinter_qs_option_set(&st->quasistatic_options, st->ctx, key, value);
    return sinter_staggered_set(st, key, value);
}

sinter_status sinter_stepper_set_neck_law(sinter_stepper *st,
                                          const sinter_neck_law_callbacks *callbacks, void *user)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (st->kind != SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_stepper_set_neck_law: only the quasi-static stepper has a "
                           "neck law");
    sinter_neck_law_callbacks table;
    memset(&table, 0, sizeof(table));
    if (callbacks != NULL) {
        if (callbacks->struct_size != sizeof(sinter_neck_law_callbacks))
            return sinter_fail(st->ctx, SINTER_ERR_STRUCT_SIZE,
                               "sinter_stepper_set_neck_law: struct_size is %zu, expected %zu",
                               callbacks->struct_size, sizeof(sinter_neck_law_callbacks));
        if (callbacks->advance == NULL)
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_set_neck_law: the table has no advance callback");
        table = *callbacks;
    }
    sinter_qs_options *o = &st->quasistatic_options;
    if (o->host_law.destroy_user != NULL)
        o->host_law.destroy_user(o->host_law_user);
    o->host_law = table;
    o->host_law_user = callbacks != NULL ? user : NULL;
    o->neck_law = callbacks != NULL ? 2.0 : 0.0;
    if (st->quasistatic != NULL)
        sinter_qs_set_host_law(st->quasistatic, o);
    return SINTER_OK;
}

sinter_status sinter_stepper_get_option(const sinter_stepper *st, const char *key, double *value)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, key);
    SINTER_CHECK_NULL(st->ctx, value);
    if (strcmp(key, "sort_interval") == 0) {
        *value = (double)st->sort_interval;
        return SINTER_OK;
    }
    if (strcmp(key, "rotation") == 0 && st->kind != SINTER_STEPPER_QUASISTATIC) {
        *value = st->rotation;
        return SINTER_OK;
    }
    if (strcmp(key, "stream_stores") == 0) {
        *value = st->stores.option;
        return SINTER_OK;
    }
    if (strcmp(key, "thread_choice") == 0) {
        *value = st->threads_choice.option;
        return SINTER_OK;
    }
    if (strcmp(key, "dt_check") == 0 || strcmp(key, "energy_check") == 0) {
        *value = key[0] == 'd' ? st->dt_check : st->energy_check;
        return SINTER_OK;
    }
    if (strcmp(key, "reproducible") == 0) {
        *value = st->reproducible;
        return SINTER_OK;
    }
    if (sinter_heat_interval_is_key(key)) {
        *value = (double)st->heat_interval;
        return SINTER_OK;
    }
    if (sinter_frozen_is_key(key))
        return sinter_frozen_get(st, key, value);
    if (st->kind == SINTER_STEPPER_QUASISTATIC &&
        (strncmp(key, "qs_", 3) == 0 || !sinter_staggered_is_option(key)))
        return sinter_qs_option_get(&st->quasistatic_options, st->ctx, key, value);
    return sinter_staggered_get(st, key, value);
}

sinter_status sinter_stepper_sintering_stats(const sinter_stepper *st,
                                             sinter_sintering_stats *stats)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, stats);
    if (stats->struct_size != sizeof(sinter_sintering_stats))
        return sinter_fail(st->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_stepper_sintering_stats: struct_size is %zu, expected %zu",
                           stats->struct_size, sizeof(sinter_sintering_stats));
    sinter_status ready = SINTER_OK;
    if (st->kind != SINTER_STEPPER_QUASISTATIC || st->quasistatic == NULL)
        ready = sinter_fail(st->ctx, SINTER_ERR_STATE,
                            "sinter_stepper_sintering_stats: the stepper is not quasi-static or "
                            "has taken no step yet");
    /* collective with domain operations: refused on every subdomain if on one (an import
     * makes a subdomain's stepper state before the first step, issue 44) */
    if (st->domain.on)
        ready = sinter_domain_agree(st->ctx, (sinter_domain *)&st->domain, ready);
    if (ready != SINTER_OK)
        return ready;
    const sinter_particles *ps = st->ps;
    /* the statistics read positions, radii and the links only */
    const sinter_qs_particles p = {ps->count,    ps->x,  ps->rot, ps->radius,
                                   ps->material, ps->id, NULL};
    /* with domain operations: collective, over every subdomain (stepper/qs_domain.h) */
    const sinter_status b = sinter_qs_domain_bind(st->quasistatic, (sinter_stepper *)st);
    if (b != SINTER_OK)
        return b;
    sinter_qs_stats q;
    sinter_qs_stats_get(st->quasistatic, &p, &q);
    stats->links = q.links;
    stats->neck_mean = q.neck_mean;
    stats->neck_min = q.neck_min;
    stats->neck_max = q.neck_max;
    stats->neck_ratio_mean = q.neck_ratio_mean;
    for (int d = 0; d < 3; ++d)
        stats->shrinkage[d] = q.shrinkage[d];
    stats->relative_density = q.relative_density;
    stats->coordination = q.coordination;
    stats->pcg_iterations = q.pcg_iterations;
    return SINTER_OK;
}

sinter_status sinter_stepper_add_force(sinter_stepper *st, sinter_force_model *fm)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, fm);
    if (fm->ctx != st->ctx)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_add_force: model '%s' belongs to another context",
                           fm->name);
    for (size_t k = 0; k < st->force_count; ++k)
        if (st->forces[k].model == fm)
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_add_force: model '%s' was already added", fm->name);
    if (st->force_count == st->force_capacity) {
        size_t cap = st->force_capacity ? 2 * st->force_capacity : 4;
        sinter_force_slot *grown =
            sinter_realloc_array(st->ctx, st->forces, cap, sizeof(sinter_force_slot));
        if (grown == NULL)
            return sinter_last_status(st->ctx);
        st->forces = grown;
        st->force_capacity = cap;
    }
    sinter_force_slot *slot = &st->forces[st->force_count];
    memset(slot, 0, sizeof(*slot));
    slot->model = fm;
    slot->pp.width = sinter_force_history_pp(fm);
    slot->pw.width = sinter_force_history_pw(fm);
    st->force_count++;
    /* The new model's history must follow the pair list from its next build. */
    st->nb.built = 0;
    st->forces_current = 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_set_dt(sinter_stepper *st, double dt)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (!isfinite(dt) || dt <= 0.0 || !isnormal(dt)) /* a subnormal step: ~1e308 steps a second */
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_dt: time step %g s must be positive, finite and "
                           "a normal double (at least %g s)",
                           dt, DBL_MIN);
    st->dt = dt;
    st->stats.dt = dt;
    return SINTER_OK;
}

sinter_status sinter_stepper_set_skin(sinter_stepper *st, double skin)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (!isfinite(skin) || skin < 0.0)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_skin: skin %g m must be finite and >= 0", skin);
    st->nb.skin = skin;
    st->skin_set = 1;
    st->nb.built = 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_set_domain(sinter_stepper *st, const double lo[3], const double hi[3])
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, lo);
    SINTER_CHECK_NULL(st->ctx, hi);
    for (int d = 0; d < 3; ++d)
        if (!isfinite(lo[d]) || !isfinite(hi[d]) || !(hi[d] > lo[d]))
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_set_domain: axis %d runs from %g m to %g m; the "
                               "bounds must be finite with lo < hi",
                               d, lo[d], hi[d]);
    memcpy(st->domain_lo, lo, sizeof(st->domain_lo));
    memcpy(st->domain_hi, hi, sizeof(st->domain_hi));
    st->has_domain = 1;
    st->domain_known = 0; /* the margin was to the old faces */
    return SINTER_OK;
}

sinter_status sinter_stepper_set_observer(sinter_stepper *st, sinter_observer_fn fn, void *user)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    st->observer = fn;
    st->observer_user = user;
    return SINTER_OK;
}

sinter_status sinter_stepper_time(const sinter_stepper *st, double *time)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, time);
    *time = st->time;
    return SINTER_OK;
}

sinter_status sinter_stepper_get_stats(const sinter_stepper *st, sinter_stepper_stats *stats)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, stats);
    /* The layouts before iterations and evaluations, and before contraction, were appended
     * are still served. */
    const size_t size = stats->struct_size, old = offsetof(sinter_stepper_stats, iterations),
                 mid = offsetof(sinter_stepper_stats, contraction),
                 late = offsetof(sinter_stepper_stats, bonds_broken);
    if (size != sizeof(sinter_stepper_stats) && size != old && size != mid && size != late)
        return sinter_fail(st->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_stepper_get_stats: struct_size is %zu, expected %zu (or %zu "
                           "for the layout without iterations and evaluations, %zu without "
                           "contraction, %zu without bonds_broken)",
                           size, sizeof(sinter_stepper_stats), old, mid, late);
    sinter_stepper_stats full = st->stats;
    full.contraction = st->staggered.contraction;
    full.struct_size = size;
    full.time = st->time;
    memcpy(stats, &full, size);
    return SINTER_OK;
}

/* Default skin: a fifth of the mean radius (LIGGGHTS' canonical deck uses 0.2 r); with
 * domain operations the mean over every subdomain's owned particles (collective: every
 * subdomain calls it at the same rebuild, with or without particles). */
static sinter_status choose_skin(sinter_stepper *st)
{
    if (st->skin_set)
        return SINTER_OK;
    const size_t n = st->ps->count - st->ps->ghost_count;
    double sum[2] = {0.0, (double)n};
    for (size_t i = 0; i < n; ++i)
        sum[0] += st->ps->radius[i];
    if (st->domain.on) {
        const sinter_status s = sinter_domain_reduce(st->ctx, &st->domain, sum, 2,
                                                     SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
        if (s != SINTER_OK)
            return s;
    }
    if (!(sum[1] > 0.0))
        return SINTER_OK;
    st->nb.skin = 0.2 * sum[0] / sum[1];
    st->skin_set = 1;
    return SINTER_OK;
}

/* Periodic images (ghosts/ghosts.h): first[o] the first ghost row of owned particle o (its
 * images are consecutive rows), or UINT32_MAX; NULL when out of memory. */
static uint32_t *first_images(sinter_stepper *st)
{
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    uint32_t *first = sinter_realloc_array(st->ctx, NULL, owned + 1, sizeof(uint32_t));
    if (first == NULL)
        return NULL;
    for (size_t o = 0; o < owned; ++o)
        first[o] = UINT32_MAX;
    const size_t host = st->ghosts.host; /* (a decomposed run's: ghosts before the images) */
    for (size_t k = sinter_ghosts_images(&st->ghosts, ps); k-- > 0;)
        if (st->ghosts.owner[k] < owned)
            first[st->ghosts.owner[k]] = (uint32_t)(owned + host + k);
    return first;
}

/* The row of owned particle j's image nearest to row i: j or one of its ghosts, so that a
 * bond across a periodic face is kept to the image it spans to, not to the owner a period
 * away (issue 38). */
static double distance2(const double *x, size_t i, size_t j)
{
    const double d[3] = {x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                         x[3 * j + 2] - x[3 * i + 2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

static size_t nearest_image(const sinter_stepper *st, const uint32_t *first, size_t i, size_t j)
{
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    size_t best = j;
    double best2 = distance2(ps->x, i, j);
    const size_t host = st->ghosts.host; /* (image k is row owned + host + k) */
    for (size_t q = first[j]; q < ps->count && st->ghosts.owner[q - owned - host] == j; ++q) {
        const double d2 = distance2(ps->x, i, q);
        if (d2 < best2) {
            best2 = d2;
            best = q;
        }
    }
    return best;
}

/* With subdomains (domain.h) the ghost rows are other ranks' particles, which the id index
 * (owned rows only) does not list: their rows by id, sorted (*n of them), for find_row; NULL
 * and *n 0 without such ghosts or without memory (then a held pair with a ghost end is found
 * only by the cell search, as before). */
static sinter_id_row *domain_ghost_rows(sinter_stepper *st, size_t *n)
{
    const sinter_particles *ps = st->ps;
    *n = 0;
    if (ps->ghost_count == 0 || sinter_ghosts_on(&st->ghosts))
        return NULL;
    const size_t owned = ps->count - ps->ghost_count;
    sinter_id_row *t = sinter_realloc_array(st->ctx, NULL, ps->ghost_count, sizeof(*t));
    if (t == NULL) {
        sinter_clear_error(st->ctx);
        return NULL;
    }
    for (size_t k = 0; k < ps->ghost_count; ++k) {
        t[k].id = ps->id[owned + k];
        t[k].index = owned + k;
    }
    qsort(t, ps->ghost_count, sizeof(*t), sinter_id_row_compare); /* ids unique on a rank */
    *n = ps->ghost_count;
    return t;
}

/* The row of particle `id`: owned (the id index, current) or a subdomain's ghost; SIZE_MAX. */
static size_t find_row(sinter_particles *ps, const sinter_id_row *ghosts, size_t n, uint64_t id)
{
    const size_t row = sinter_id_index_find(&ps->id_index, ps, id);
    if (row != SIZE_MAX || n == 0)
        return row;
    const sinter_id_row key = {id, 0};
    const sinter_id_row *hit = bsearch(&key, ghosts, n, sizeof(*ghosts), sinter_id_row_compare);
    return hit != NULL ? hit->index : SIZE_MAX;
}

/* The slot of the first model that holds pairs (bonds in tension), or force_count. */
static size_t held_slot(const sinter_stepper *st)
{
    for (size_t k = 0; k < st->force_count; ++k)
        if (sinter_force_holds_pairs(st->forces[k].model) && st->forces[k].pp.width > 0)
            return k;
    return st->force_count;
}

/* The history of the first model that holds pairs (bonds in tension), or NULL. */
static const sinter_history *held_history(const sinter_stepper *st)
{
    const size_t k = held_slot(st);
    return k < st->force_count ? &st->forces[k].pp : NULL;
}

/* The bonded pairs' entries that imported records brought for that model (migrate.h), staged
 * until the next build, or NULL: a bond of a particle that moved to this stepper. */
static const sinter_migrate_entries *held_staged(const sinter_stepper *st)
{
    const size_t k = held_slot(st);
    const sinter_migrate_stage *g = st->migrate;
    if (k == st->force_count || g == NULL || g->slots != st->force_count ||
        g->width[2 * k] != st->forces[k].pp.width)
        return NULL;
    return &g->list[2 * k];
}

/* Add the staged bonds of `l` (width w) whose two ends this stepper holds to the count pairs
 * of both (room for `room` pairs, first ends then second ends at both + room), each pair once. */
static size_t add_staged_bonds(sinter_stepper *st, const sinter_migrate_entries *l, size_t w,
                               const sinter_id_row *ghosts, size_t nghost, uint32_t *both,
                               size_t room, size_t count)
{
    sinter_particles *ps = st->ps;
    for (size_t e = 0; l != NULL && e < l->count && count < room; ++e) {
        if (l->value[w * e] == 0.0)
            continue; /* not bonded */
        const size_t i = find_row(ps, ghosts, nghost, l->key[2 * e]),
                     j = find_row(ps, ghosts, nghost, l->key[2 * e + 1]);
        if (i == SIZE_MAX || j == SIZE_MAX)
            continue;
        int listed = 0;
        for (size_t q = 0; q < count && !listed; ++q)
            listed = (both[q] == i && both[room + q] == j) || (both[q] == j && both[room + q] == i);
        if (!listed) {
            both[count] = (uint32_t)i;
            both[room + count] = (uint32_t)j;
            ++count;
        }
    }
    return count;
}

/* Periodic images: the largest gap [m] of a held pair to the nearest image of its far end
 * (by ids, so any layout), which the ghost cut-off must cover for that image to exist; 0
 * without held pairs (or when the index cannot be made: then the usual cut-off). */
static double held_gap(sinter_stepper *st)
{
    const sinter_history *h = held_history(st);
    sinter_neighbors *nb = &st->nb;
    sinter_particles *ps = st->ps;
    if (h == NULL || h->committed == NULL || h->active_count == 0 || !nb->built)
        return 0.0;
    if (sinter_id_index_update(&ps->id_index, ps) != SINTER_OK) {
        sinter_clear_error(st->ctx);
        return 0.0;
    }
    const sinter_ghosts *g = &st->ghosts;
    size_t nghost = 0;
    sinter_id_row *ghosts = domain_ghost_rows(st, &nghost);
    double gap = 0.0;
    for (size_t a = 0; a < h->active_count; ++a) {
        const uint32_t p = h->active[a];
        if (p >= nb->pp.count || h->committed[h->width * p] == 0.0)
            continue;
        const size_t i = find_row(ps, ghosts, nghost, nb->pp.key_i[p]),
                     j = find_row(ps, ghosts, nghost, nb->pp.key_j[p]);
        if (i == SIZE_MAX || j == SIZE_MAX)
            continue;
        double e2 = 0.0;
        for (int d = 0; d < 3; ++d) {
            double e = ps->x[3 * j + d] - ps->x[3 * i + d];
            if (g->periodic[d]) {
                const double period = g->hi[d] - g->lo[d];
                e -= period * nearbyint(e / period);
            }
            e2 += e * e;
        }
        gap = fmax(gap, sqrt(e2) - ps->radius[i] - ps->radius[j]);
    }
    sinter_free(st->ctx, ghosts);
    return gap;
}

/* The bonded pairs of a model that holds pairs (set_held), in the current layout, for the
 * next build to keep at any distance (sinter_neighbors_keep): the pairs it lists hold
 * their history whatever their distance. With periodic images the pair's first end (the
 * smaller id, owned) is kept with the nearest image of the other. */
static sinter_status keep_held_pairs(sinter_stepper *st)
{
    sinter_neighbors *nb = &st->nb;
    const sinter_history *h = held_history(st);
    const sinter_migrate_entries *staged = held_staged(st);
    const size_t arrived = staged != NULL ? staged->count : 0;
    if (h == NULL || ((h->committed == NULL || h->active_count == 0) && arrived == 0) ||
        !nb->built) {
        nb->keep_count = 0;
        return SINTER_OK;
    }
    const size_t w = h->width, room = h->active_count + arrived;
    uint32_t *both = sinter_realloc_array(st->ctx, NULL, 2 * room + 1, sizeof(uint32_t));
    if (both == NULL)
        return sinter_last_status(st->ctx);
    sinter_particles *ps = st->ps;
    const int moved = nb->layout_generation != ps->layout_generation; /* indices changed */
    sinter_status s = moved || arrived > 0 ? sinter_id_index_update(&ps->id_index, ps) : SINTER_OK;
    uint32_t *first = NULL;
    /* periodic images only: a subdomain's ghost rows (domain.h) are other ranks' particles */
    if (s == SINTER_OK && ps->ghost_count > 0 && sinter_ghosts_on(&st->ghosts) &&
        (first = first_images(st)) == NULL)
        s = sinter_last_status(st->ctx);
    size_t nghost = 0;
    sinter_id_row *ghosts = s == SINTER_OK ? domain_ghost_rows(st, &nghost) : NULL;
    size_t count = 0;
    for (size_t a = 0; h->committed != NULL && a < h->active_count && s == SINTER_OK; ++a) {
        const uint32_t p = h->active[a];
        if (p >= nb->pp.count || h->committed[w * p] == 0.0)
            continue;
        size_t i = nb->pp.i[p], j = nb->pp.j[p];
        if (moved) {
            i = find_row(ps, ghosts, nghost, nb->pp.key_i[p]);
            j = find_row(ps, ghosts, nghost, nb->pp.key_j[p]);
            if (i == SIZE_MAX || j == SIZE_MAX)
                continue; /* a particle was removed: its bonds go with it */
            if (first != NULL)
                j = nearest_image(st, first, i, j);
        }
        both[count] = (uint32_t)i;
        both[room + count] = (uint32_t)j;
        ++count;
    }
    /* with subdomains: the bonds that arrived with migrated particles, which the cell search
     * finds only within its reach, kept at any distance as those that stayed (first_images is
     * NULL there: no periodic axes) */
    if (s == SINTER_OK && arrived > 0 && first == NULL)
        count = add_staged_bonds(st, staged, w, ghosts, nghost, both, room, count);
    if (s == SINTER_OK)
        s = sinter_neighbors_keep(nb, ps, both, both + room, count);
    sinter_free(st->ctx, both);
    sinter_free(st->ctx, first);
    sinter_free(st->ctx, ghosts);
    return s;
}

/* The largest "gas_reach" fraction of the heat models (heat/gas_gap.h), 0 without one. */
static double heat_reach_fraction(const sinter_stepper *st)
{
    double fraction = 0.0;
    for (size_t k = 0; k < st->thermal.count; ++k) {
        const double f = sinter_heat_gas_reach(st->thermal.slots[k].model, st->time);
        fraction = f > fraction ? f : fraction;
    }
    return fraction > 0.0 ? fraction : 0.0;
}

/* The gap [m] within which a heat model reads pairs apart (heat/gas_gap.h): the largest
 * "gas_reach" of the heat models times the largest radius; 0 without one (the default, no
 * pass over the radii). */
static double heat_reach(const sinter_stepper *st)
{
    const double fraction = heat_reach_fraction(st);
    if (!(fraction > 0.0))
        return 0.0;
    double rmax = 0.0;
    for (size_t i = 0; i < st->ps->count; ++i)
        rmax = st->ps->radius[i] > rmax ? st->ps->radius[i] : rmax;
    return fraction * rmax;
}

/* This subdomain's side of the rebuild decision: whether its lists are stale (or ghosts are
 * due), and its largest radius. */
static void rebuild_values(const sinter_stepper *st, int local, double v[2])
{
    const sinter_particles *ps = st->ps;
    v[0] = local || st->domain.rebuild_due ? 1.0 : 0.0;
    v[1] = 0.0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i)
        v[1] = ps->radius[i] > v[1] ? ps->radius[i] : v[1];
}

sinter_status sinter_stepper_agree_drift(sinter_stepper *st, sinter_status s)
{
    sinter_domain *d = &st->domain;
    d->decided = 0;
    double v[3] = {0.0, 0.0, s == SINTER_OK ? 0.0 : 1.0};
    if (s == SINTER_OK) /* (the ghosts' rows are refreshed after this: their owners decide) */
        rebuild_values(st, sinter_neighbors_stale(&st->nb, st->ps, st->walls), v);
    const sinter_status r =
        sinter_domain_reduce(st->ctx, d, v, 3, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
    if (r != SINTER_OK)
        return r;
    if (v[2] > 0.0) /* a subdomain failed: the code and the message agreed */
        return sinter_domain_agree(st->ctx, d, s);
    d->decided = 1;
    d->decision[0] = v[0];
    d->decision[1] = v[1];
    return SINTER_OK;
}

/*
 * The rebuild stage of a decomposed run (domain/domain.h): the decision is every subdomain's
 * (a MAX of the flags, with the largest radius for the ghost cut-off); then the host
 * redistributes (migration and new ghosts, sinter_particles_set_ghosts) before the build,
 * and the build gives the migrated particles' pairs their staged histories, as a build
 * without domain operations does.
 * The decision comes from sinter_stepper_agree_drift when the explicit step reduced it
 * there. Returns the status, *rebuild whether the lists must be built.
 */
static sinter_status domain_rebuild_stage(sinter_stepper *st, double fraction, int *rebuild)
{
    sinter_domain *d = &st->domain;
    double v[2];
    if (d->decided) { /* reduced with the agreement after the drift */
        v[0] = d->decision[0];
        v[1] = d->decision[1];
        d->decided = 0;
    } else {
        rebuild_values(st, sinter_neighbors_stale(&st->nb, st->ps, st->walls), v);
        sinter_status s =
            sinter_domain_reduce(st->ctx, d, v, 2, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
        if (s != SINTER_OK)
            return s;
    }
    sinter_status s = SINTER_OK;
    const double reach = fraction * v[1];
    const int wider = reach > st->nb.reach;
    if (wider)
        st->nb.reach = reach;
    *rebuild = v[0] > 0.0 || wider;
    if (!*rebuild)
        return SINTER_OK;
    if ((s = choose_skin(st)) != SINTER_OK)
        return s;
    /* bonds in tension (power law bond_strength): the halo reaches the far end of every held
     * pair, as the periodic images' cut-off does, so that both sides keep the bond */
    double held = 0.0;
    for (size_t k = 0; k < st->force_count; ++k)
        if (sinter_force_holds_pairs(st->forces[k].model)) { /* the same on every rank */
            held = held_gap(st);
            s = sinter_domain_reduce(st->ctx, d, &held, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
            if (s != SINTER_OK)
                return s;
            break;
        }
    d->cutoff = 2.0 * v[1] + st->nb.skin + fmax(st->nb.reach, held);
    d->rebuild_due = 0;
    /* periodic axes (domain_periodic.c): the images' cut-off as without domain operations (a
     * bond in tension may be longer than a contact: its far end needs its image), then the
     * owned particles wrapped before the host sees them */
    const int periodic = sinter_ghosts_on(&st->ghosts);
    const double image_cutoff =
        periodic ? 2.0 * v[1] + (st->nb.skin + fmax(st->nb.reach, held_gap(st))) : 0.0;
    s = sinter_domain_periodic_wrap(st);
    if (s == SINTER_OK)
        s = sinter_domain_redistribute(st); /* migration, then the new ghosts */
    if (s == SINTER_OK)
        s = sinter_explicit_keep_spare(st);
    /* the spare arrays (explicit.c: the state at t) get the new ghosts' rows as they are now:
     * a rollback restores the owners, and a forward halo the ghosts */
    const sinter_particles *ps = st->ps;
    const size_t first = ps->count - ps->ghost_count;
    double *rows[4] = {ps->x, ps->v, ps->w, ps->rot};
    for (int k = 0; k < 4 && s == SINTER_OK && st->spare[k] != NULL && ps->ghost_count > 0; ++k)
        memcpy(st->spare[k] + 3 * first, rows[k] + 3 * first, 3 * ps->ghost_count * sizeof(double));
    if (s == SINTER_OK && periodic) /* (after the host's ghosts: images of them too) */
        s = sinter_domain_periodic_images(st, image_cutoff);
    return s;
}

/* The neighbour lists of a decomposed run: the rebuild stage (collective), then the build when
 * it decided one. */
static sinter_status domain_refresh(sinter_stepper *st)
{
    int rebuild = 0;
    sinter_status s = domain_rebuild_stage(st, heat_reach_fraction(st), &rebuild);
    if (s != SINTER_OK || !rebuild)
        return s;
    const double t0 = sinter_clock();
    s = keep_held_pairs(st);
    if (s == SINTER_OK)
        s = sinter_neighbors_build(&st->nb, st->ps, st->walls);
    for (size_t k = 0; k < st->force_count && s == SINTER_OK; ++k) {
        s = sinter_history_remap(st->ctx, &st->forces[k].pp, st->nb.old_pp.count, &st->nb.pp);
        if (s == SINTER_OK)
            s = sinter_history_remap(st->ctx, &st->forces[k].pw, st->nb.old_pw.count, &st->nb.pw);
    }
    if (s == SINTER_OK) /* the histories migrated particles brought, by key (migrate.h) */
        s = sinter_migrate_match(st);
    st->stats.neighbor_builds++;
    st->stats.seconds_neighbor += sinter_clock() - t0;
    return s;
}

/* The staggered predictor's history (7 doubles a particle: force, moment, heat of the step
 * before) after a redistribution: the stayers' rows by id from `kept` (ids `kept_id`, `kept_n`
 * of them), the arrivals' from their records (domain.h, arrived_*). Returns 1 when every owned
 * particle has its rows (the history stays valid), 0 otherwise or without memory. */
static int follow_history(sinter_stepper *st, const uint64_t *kept_id, const double *kept,
                          size_t kept_n)
{
    sinter_particles *ps = st->ps;
    sinter_staggered *sg = &st->staggered;
    const sinter_domain *d = &st->domain;
    const size_t n = ps->count - ps->ghost_count;
    if (sinter_grow(st->ctx, (void **)&sg->hist, &sg->hist_capacity, 7 * n + 1, sizeof(double)) !=
            SINTER_OK ||
        sinter_id_index_update(&ps->id_index, ps) != SINTER_OK)
        return 0;
    unsigned char *have = sinter_calloc(st->ctx, n + 1, 1);
    if (have == NULL)
        return 0;
    for (size_t k = 0; k < kept_n + d->arrived_count; ++k) {
        const int stayed = k < kept_n;
        const uint64_t id = stayed ? kept_id[k] : d->arrived_id[k - kept_n];
        const size_t j = sinter_id_index_find(&ps->id_index, ps, id);
        if (j >= n)
            continue;
        const double *f = stayed ? kept + 7 * k : d->arrived_rows + 13 * (k - kept_n);
        memcpy(sg->hist + 3 * j, f, 3 * sizeof(double));
        memcpy(sg->hist + 3 * n + 3 * j, f + 3, 3 * sizeof(double));
        sg->hist[6 * n + j] = stayed ? f[6] : f[12];
        have[j] = 1;
    }
    size_t count = 0;
    for (size_t j = 0; j < n; ++j)
        count += have[j];
    sinter_free(st->ctx, have);
    sg->history_count = n;
    return count == n;
}

void sinter_stepper_adopt_history(sinter_stepper *st)
{
    sinter_domain *d = &st->domain;
    if (d->arrived_count == 0 || d->redistributing)
        return;
    /* (valid only when every owned particle brought its own; else the predictor restarts) */
    if (!st->staggered.history_valid && follow_history(st, NULL, NULL, 0))
        st->staggered.history_valid = 1;
    d->arrived_count = 0;
}

/*
 * The staggered stepper's redistribution at an accepted state (stepper.h): the host's
 * migrations are refused during its fixed-point attempts (the state at t, the predictor's and
 * Anderson's histories are per index), so a migration refused there is made here, before the
 * next step saves its state at t. One reduction a step: whether a migration waits anywhere,
 * and whether any subdomain's predictor history restarts (then every one restarts it, so that
 * the subdomains predict alike). The predictor's history follows the particles: the stayers'
 * by id, the arrivals' in their records (record bit 2, migrate.c); a second reduction then
 * says whether every subdomain has it for every particle.
 */
sinter_status sinter_stepper_domain_accepted_stage(sinter_stepper *st)
{
    sinter_domain *d = &st->domain;
    sinter_staggered *sg = &st->staggered;
    sinter_particles *ps = st->ps;
    const size_t n = ps->count - ps->ghost_count;
    const int valid = sg->history_valid && sg->history_count == n && sg->h_prev > 0.0;
    int64_t v[2] = {d->migration_deferred, !valid};
    sinter_status s = sinter_domain_reduce(st->ctx, d, v, 2, SINTER_REDUCE_I64, SINTER_REDUCE_MAX);
    if (s != SINTER_OK)
        return s;
    d->migration_deferred = 0;
    if (v[0] != 0) { /* rebuilt with the host's redistribution, migrations allowed */
        /* the stayers' history by id (the rows move when particles leave or come) */
        uint64_t *kept_id = sinter_alloc(st->ctx, (n + 1) * sizeof(uint64_t));
        double *kept = sinter_alloc(st->ctx, (7 * n + 1) * sizeof(double));
        const int keep = v[1] == 0 && kept_id != NULL && kept != NULL;
        for (size_t i = 0; keep && i < n; ++i) {
            kept_id[i] = ps->id[i];
            memcpy(kept + 7 * i, sg->hist + 3 * i, 3 * sizeof(double));
            memcpy(kept + 7 * i + 3, sg->hist + 3 * n + 3 * i, 3 * sizeof(double));
            kept[7 * i + 6] = sg->hist[6 * n + i];
        }
        const uint64_t population = ps->population_generation;
        d->rebuild_due = 1;
        d->keep_history = keep;
        s = domain_refresh(st);
        d->keep_history = 0;
        int64_t lost = 0; /* a subdomain without the history of one of its particles */
        if (s == SINTER_OK && ps->population_generation != population)
            lost = !keep || !follow_history(st, kept_id, kept, n);
        sinter_free(st->ctx, kept_id);
        sinter_free(st->ctx, kept);
        d->arrived_count = 0; /* (taken: not for sinter_stepper_adopt_history) */
        if ((s = sinter_domain_agree(st->ctx, d, s)) != SINTER_OK)
            return s;
        if (v[1] == 0 && (s = sinter_domain_reduce(st->ctx, d, &lost, 1, SINTER_REDUCE_I64,
                                                   SINTER_REDUCE_MAX)) != SINTER_OK)
            return s;
        v[1] = v[1] != 0 || lost != 0;
    }
    sg->history_valid = v[1] == 0; /* (an export or import dropped it: kept, it is valid) */
    return s;
}

static sinter_status refresh_neighbors(sinter_stepper *st)
{
    if (st->domain.on)
        return domain_refresh(st);
    /* the quasi-static stepper makes no images: its links see them (stepper/qs_periodic.c) */
    const int periodic = sinter_ghosts_on(&st->ghosts) && st->kind != SINTER_STEPPER_QUASISTATIC;
    /* a wider reach than the list was built with: built again now, whatever the skin */
    const double reach = st->thermal.count > 0 ? heat_reach(st) : 0.0;
    const int wider = reach > st->nb.reach;
    if (wider)
        st->nb.reach = reach;
    if (!wider && !sinter_neighbors_stale(&st->nb, st->ps, st->walls) &&
        (!periodic || sinter_ghosts_current(&st->ghosts, st->ps)))
        return SINTER_OK;
    const double t0 = sinter_clock();
    sinter_status s = choose_skin(st);
    if (periodic) { /* owned particles wrapped into the cell, their images made (ghosts.h) */
        /* the spare arrays (explicit.c: the state at t of the step under way) follow: wrapped
         * the same, their ghost rows made alike */
        /* (a bond in tension may be longer than a contact: its far end needs its image) */
        s = sinter_ghosts_rebuild(
            &st->ghosts, st->ps,
            sinter_ghosts_cutoff(st->ps, st->nb.skin + fmax(st->nb.reach, held_gap(st))),
            st->spare[0] != NULL && st->spare_capacity >= st->ps->count ? st->spare[0] : NULL);
        if (s == SINTER_OK)
            s = sinter_explicit_keep_spare(st);
        if (s != SINTER_OK)
            return s;
        for (int k = 0; k < 4 && st->spare[k] != NULL; ++k)
            sinter_ghosts_copy_rows(&st->ghosts, st->ps, st->spare[k], k == 0);
    }
    /* A changed particle layout (add/remove/reorder) invalidates pair indices, but
     * the id-keyed matching carries history over all the same. */
    s = keep_held_pairs(st);
    if (s == SINTER_OK)
        s = sinter_neighbors_build(&st->nb, st->ps, st->walls);
    for (size_t k = 0; k < st->force_count && s == SINTER_OK; ++k) {
        s = sinter_history_remap(st->ctx, &st->forces[k].pp, st->nb.old_pp.count, &st->nb.pp);
        if (s == SINTER_OK)
            s = sinter_history_remap(st->ctx, &st->forces[k].pw, st->nb.old_pw.count, &st->nb.pw);
    }
    if (s == SINTER_OK) /* the histories imported particles brought, by key (migrate.h) */
        s = sinter_migrate_match(st);
    st->stats.neighbor_builds++;
    st->stats.seconds_neighbor += sinter_clock() - t0;
    return s;
}

/* For a "dissipation" heat model (heat/dissipation.c): the power the contacts of the force
 * evaluation e just made dissipate, from each force model that reports it
 * (sinter_force_ops.dissipation), into st->dissipation; nothing without such a heat model. */
static sinter_status contact_dissipation(sinter_stepper *st, sinter_force_eval *e)
{
    st->dissipation_valid = 0;
    int wanted = 0;
    for (size_t k = 0; k < st->thermal.count; ++k)
        wanted |= st->thermal.slots[k].model->ops == &sinter_heat_dissipation;
    if (!wanted)
        return SINTER_OK;
    const size_t n = st->ps->count;
    sinter_status s = sinter_grow(st->ctx, (void **)&st->dissipation, &st->dissipation_capacity,
                                  2 * n + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    memset(st->dissipation, 0, 2 * n * sizeof(double));
    sinter_contacts_geometry(st->ctx, &st->pp, st->ps);
    for (size_t k = 0; k < st->force_count && s == SINTER_OK; ++k) {
        sinter_force_slot *slot = &st->forces[k];
        if (slot->model->ops->dissipation == NULL)
            continue;
        e->hist_pp = &slot->pp;
        e->hist_pw = &slot->pw;
        s = slot->model->ops->dissipation(slot->model, e, st->dissipation);
    }
    st->dissipation_valid = s == SINTER_OK;
    return s;
}

static sinter_status fill_view(sinter_stepper *st, double dt)
{
    sinter_state_view *v = &st->view;
    const size_t nw = st->walls ? st->walls->count : 0;
    if (9 * nw + 1 > st->wall_arrays_capacity) {
        double *grown = sinter_realloc_array(st->ctx, st->wall_arrays, 9 * nw + 1, sizeof(double));
        if (grown == NULL)
            return sinter_last_status(st->ctx);
        st->wall_arrays = grown;
        st->wall_arrays_capacity = 9 * nw + 1;
    }
    sinter_host_state_view(v, st->ps, st->walls, st->wall_arrays, st->time, dt);
    return SINTER_OK;
}

/* 1 if a submodel of this evaluation reads the particle-particle contacts' geometry; when
 * none does, the list is found lean (sinter_contacts_find_pp_lean, issue 9). A reader the
 * test misses still gets it: each reader asks sinter_contacts_geometry first. */
static int geometry_needed(const sinter_stepper *st)
{
    if (st->electric != NULL)
        return 1;
    for (size_t k = 0; k < st->force_count; ++k)
        if (sinter_force_reads_geometry(st->forces[k].model, st->forces[k].pp.width))
            return 1;
    for (size_t k = 0; k < st->thermal.count && !st->heat_skip; ++k)
        if (sinter_heat_reads_geometry(st->thermal.slots[k].model, st->time))
            return 1;
    return 0;
}

/* The force slot that may confirm a lean list's contacts in its law
 * (sinter_contacts_find_pp_deferred): the only slot that uses contacts, if it can; else -1. */
static long confirming_slot(const sinter_stepper *st)
{
    long slot = -1;
    for (size_t k = 0; k < st->force_count; ++k) {
        const sinter_force_model *fm = st->forces[k].model;
        if (!fm->ops->uses_contacts)
            continue;
        if (slot >= 0 || !sinter_force_confirms_contacts(fm, st->forces[k].pp.width))
            return -1;
        slot = (long)k;
    }
    return slot;
}

/* After the law of `slot` ran on a deferred list: drop the contacts it skipped (from index
 * `ended` on); trial history indexed by contact moves with the contacts kept, and trial
 * history by pair was written on the pairs of the list that results. */
static void confirm_contacts(sinter_stepper *st, sinter_force_slot *slot, size_t ended)
{
    const uint64_t before = st->pp.revision;
    st->law_confirmed++;
    st->law_dropped += ended != SIZE_MAX;
    sinter_history *h = &slot->pp;
    sinter_contacts_confirm(&st->pp, ended, h->by_pair || h->width == 0 ? NULL : h->trial,
                            h->width);
    if (h->trial_written == before)
        h->trial_written = st->pp.revision;
}

/* An evaluation that stops before the law: a deferred list is checked by the search's test,
 * so that no reader sees contacts that ended. */
static sinter_status stop_before_law(sinter_stepper *st, int deferred, sinter_status s)
{
    if (deferred)
        sinter_contacts_check(&st->pp, &st->nb.pp, st->ps);
    return s;
}

/* A range's final work in the law's region when the conduction runs there: its conduction
 * (the boundary and wall contacts), then the stepper's own (the second half kick), if any. */
static void heat_then_final(void *user, int range, size_t lo, size_t hi)
{
    sinter_stepper *st = user;
    sinter_thermal_law_rest(st, range);
    if (st->range_final != NULL)
        st->range_final(st->range_final_user, range, lo, hi);
}

/* Bonds that hold in tension (force/power_law.c): the first model whose history marks held
 * pairs lets the contact search keep them (sinter_contact_list.held) while its committed
 * history covers the current pairs. */
static void set_held(sinter_stepper *st)
{
    st->pp.held = NULL;
    for (size_t k = 0; k < st->force_count; ++k) {
        const sinter_history *h = &st->forces[k].pp;
        if (sinter_force_holds_pairs(st->forces[k].model) && h->width > 0 && h->committed != NULL &&
            h->pair_capacity >= h->width * st->nb.pp.count) {
            st->pp.held = h->committed;
            st->pp.held_stride = h->width;
            return;
        }
    }
}

/* Force and moment of the ghost rows zeroed (ghosts/ghosts.h). */
static void clear_ghost_rows(sinter_particles *ps)
{
    const size_t first = ps->count - ps->ghost_count;
    memset(ps->force + 3 * first, 0, 3 * ps->ghost_count * sizeof(double));
    memset(ps->torque + 3 * first, 0, 3 * ps->ghost_count * sizeof(double));
}

sinter_status sinter_stepper_eval_forces(sinter_stepper *st, double dt_hist)
{
    sinter_ctx *ctx = st->ctx;
    sinter_particles *ps = st->ps;
    sinter_wall_skip_begin(&st->wall_skip); /* kept only when drifts alone moved them */
    sinter_status s = refresh_neighbors(st);
    if (s != SINTER_OK)
        return s;
    const double t0 = sinter_clock();
    st->stats.evaluations++;
    st->eval_lag = 0.0;
    /* a lean list whose only contact model tests its contacts itself: the search checks
     * only the pairs out of contact, the law the contacts (issue 9) */
    int deferred = 0;
    const int geometry = geometry_needed(st);
    const long confirmer = geometry ? -1 : confirming_slot(st);
    set_held(st);
    if (geometry)
        s = sinter_contacts_find_pp(ctx, &st->pp, &st->nb.pp, ps);
    else if (confirmer >= 0)
        s = sinter_contacts_find_pp_deferred(ctx, &st->pp, &st->nb.pp, ps, &deferred);
    else
        s = sinter_contacts_find_pp_lean(ctx, &st->pp, &st->nb.pp, ps);
    st->pp.held = NULL; /* the history moves at commits and rebuilds */
    /* (ghosts and subdomains move particles by other stages: no certificate kept) */
    const int skip_walls = ps->ghost_count == 0 && !st->domain.on && !sinter_ghosts_on(&st->ghosts);
    if (!skip_walls)
        st->wall_skip.valid = 0;
    if (s == SINTER_OK && st->walls != NULL)
        s = sinter_contacts_find_pw_skip(ctx, &st->pw, &st->nb.pw, ps, st->walls, &st->pp.chunks,
                                         skip_walls ? &st->wall_skip : NULL);
    /* the network's solve is collective (domain/solve.h): every subdomain or none */
    if (st->domain.on && st->electric != NULL)
        s = sinter_domain_agree(ctx, &st->domain, s);
    if (s != SINTER_OK)
        return stop_before_law(st, deferred, s);
    if (st->walls == NULL && (st->pw.count != 0 || st->pw.revision == 0)) {
        st->pw.count = 0;
        st->pw.lean_source = 0;
        st->pw.revision = sinter_unique_id();
    }
    if (st->electric != NULL) {
        /* Currents on the contact graph of this state (seed 000 sec. 5), before heat reads them. */
        size_t electric_iterations = 0;
        sinter_contacts_geometry(ctx, &st->pp, ps);
        /* a decomposed run: the network's solve (network_domain.c) or the averaged model's sums
         * and halos (averaged.c) through the host's operations */
        st->electric->domain =
            st->domain.on && st->electric->kind == SINTER_ELECTRIC_NETWORK ? &st->domain : NULL;
        st->electric->averaged_domain = st->domain.on ? &st->domain : NULL;
        st->electric->reproducible = st->reproducible;
        s = sinter_electric_solve_images(
            st->electric, ps, st->walls, &st->pp, &st->pw,
            ps->ghost_count > 0 && !st->domain.on ? st->ghosts.owner : NULL, &electric_iterations);
        st->electric->domain = NULL;
        st->electric_iterations += electric_iterations;
        if (s != SINTER_OK)
            return s;
    }
    const size_t nw = st->walls ? st->walls->count : 0;
    if (nw + 1 > st->wall_force_capacity) {
        double *grown = sinter_realloc_array(ctx, st->wall_force, 6 * (nw + 1), sizeof(double));
        if (grown == NULL)
            return stop_before_law(st, deferred, sinter_last_status(ctx));
        st->wall_force = grown;
        st->wall_force_capacity = nw + 1;
    }
    memset(st->wall_force, 0, 6 * nw * sizeof(double)); /* forces, then moments */
    /* the integrator zeroed force and torque after their last read, and may have written m g
     * (gravity as the first model: 0 + m g, the same bits as its evaluation) into the force */
    const size_t first_model = st->forces_zeroed && st->gravity_seeded ? 1 : 0;
    if (!st->forces_zeroed && ps->count > 0) { /* (an empty set has no arrays) */
        memset(ps->force, 0, 3 * ps->count * sizeof(double));
        memset(ps->torque, 0, 3 * ps->count * sizeof(double));
    }
    st->forces_zeroed = 0;
    st->gravity_seeded = 0;
    /* ghosts: their rows gather only what pairs put there (the reverse halo below) */
    const int ghosts = !st->domain.on ? ps->ghost_count > 0 /* periodic images */
                                      : sinter_ghosts_images(&st->ghosts, ps) > 0;
    if (ps->ghost_count > 0)
        clear_ghost_rows(ps);
    s = fill_view(st, dt_hist);
    if (s != SINTER_OK)
        return stop_before_law(st, deferred, s);
    sinter_force_eval e;
    memset(&e, 0, sizeof(e));
    e.ctx = ctx;
    e.ps = ps;
    e.walls = st->walls;
    e.pp = &st->pp;
    e.pw = &st->pw;
    e.time = st->time;
    e.dt = dt_hist;
    e.force = ps->force;
    e.torque = ps->torque;
    e.wall_force = st->wall_force;
    e.wall_moment = st->wall_force + 3 * nw;
    e.view = &st->view;
    e.stream = st->stores.stream_now;
    s = sinter_thermal_softening(st, &e.modulus_scale);
    if (s == SINTER_OK) /* the reproducible mode: each wall contact's own reaction too */
        s = sinter_wall_sums_prepare(st, &e.pw_reaction);
    /* the explicit step's conduction in the last law's region, by ranges (thermal.h) */
    const int heat_ranges = s == SINTER_OK && st->heat_in_law && sinter_thermal_law_begin(st);
    st->ranges_final = 0;
    for (size_t k = first_model; k < st->force_count && s == SINTER_OK; ++k) {
        sinter_force_slot *slot = &st->forces[k];
        const int host = slot->model->ops->eval == sinter_force_host_eval;
        s = sinter_history_prepare(ctx, &slot->pp, st->pp.count, host);
        if (s == SINTER_OK)
            s = sinter_history_prepare(ctx, &slot->pw, st->pw.count, host);
        if (s != SINTER_OK)
            break;
        e.hist_pp = &slot->pp;
        e.hist_pw = &slot->pw;
        if (sinter_force_reads_geometry(slot->model, slot->pp.width))
            sinter_contacts_geometry(ctx, &st->pp, ps);
        e.pp_ended = SIZE_MAX;
        const int last = k + 1 == st->force_count;
        e.range_final = !last ? NULL : heat_ranges ? heat_then_final : st->range_final;
        e.range_interior_done = last && heat_ranges ? sinter_thermal_law_interior : NULL;
        e.range_user = !last ? NULL : heat_ranges ? (void *)st : st->range_final_user;
        e.ranges_final = 0;
        e.bonds_broken = 0;
        /* a body force acts on the owner, not on its image (ghosts.h) */
        const int body = ghosts && !slot->model->ops->uses_contacts;
        if (body && (s = sinter_ghosts_save_rows(ctx, &st->ghosts, ps)) != SINTER_OK)
            break;
        s = slot->model->ops->eval(slot->model, &e);
        if (body)
            sinter_ghosts_restore_rows(&st->ghosts, ps);
        slot->bonds_broken = e.bonds_broken;
        st->ranges_final = last && e.ranges_final;
        if (s == SINTER_OK && deferred && (long)k == confirmer) {
            confirm_contacts(st, slot, e.pp_ended);
            deferred = 0;
        }
    }
    if (heat_ranges)
        sinter_thermal_law_end(st, s == SINTER_OK && st->ranges_final);
    (void)stop_before_law(st, deferred, s); /* when the law did not run */
    st->stats.contacts = st->pp.count;
    st->stats.wall_contacts = st->pw.count;
    st->stats.seconds_force += sinter_clock() - t0;
    /* heat_interval: an evaluation whose heat powers no update reads leaves them out */
    const int heat = st->thermal.count > 0 && !st->heat_skip;
    if (s == SINTER_OK && heat)
        s = contact_dissipation(st, &e);
    if (heat && sinter_thermal_collective(st)) /* (the beams gather: every subdomain or none) */
        s = sinter_domain_agree(ctx, &st->domain, s);
    if (s == SINTER_OK && heat) {
        const double t1 = sinter_clock();
        s = sinter_thermal_eval(st);
        st->stats_seconds_heat += sinter_clock() - t1;
    }
    /* reverse halo: what the pairs put on the images goes to their owners (ghosts.h); ghosts
     * of other subdomains: discarded, their owners evaluate the same pairs (newton off) */
    if (s == SINTER_OK && ghosts)
        sinter_ghosts_reverse(&st->ghosts, ps);
    if (s == SINTER_OK && st->domain.on)
        sinter_domain_discard_ghost_rows(ps);
    return s;
}

sinter_status sinter_stepper_add_heat(sinter_stepper *st, sinter_heat_model *hm)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, hm);
    if (hm->ctx != st->ctx)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_add_heat: model '%s' belongs to another context",
                           hm->name);
    if (st->furnace_count > 0)
        return sinter_fail(st->ctx, SINTER_ERR_STATE,
                           "sinter_stepper_add_heat: the stepper has a furnace, which prescribes "
                           "the temperatures; remove it (count 0) before adding heat model '%s'",
                           hm->name);
    sinter_thermal *th = &st->thermal;
    for (size_t k = 0; k < th->count; ++k)
        if (th->slots[k].model == hm)
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_add_heat: model '%s' was already added", hm->name);
    if (th->count == th->capacity) {
        size_t cap = th->capacity ? 2 * th->capacity : 4;
        sinter_heat_slot *grown =
            sinter_realloc_array(st->ctx, th->slots, cap, sizeof(sinter_heat_slot));
        if (grown == NULL)
            return sinter_last_status(st->ctx);
        th->slots = grown;
        th->capacity = cap;
    }
    memset(&th->slots[th->count], 0, sizeof(sinter_heat_slot));
    th->slots[th->count].model = hm;
    th->count++;
    st->forces_current = 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_set_thermal_scheme(sinter_stepper *st, int scheme)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (scheme != SINTER_THERMAL_EXPLICIT && scheme != SINTER_THERMAL_IMPLICIT)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_thermal_scheme: scheme %d is neither "
                           "SINTER_THERMAL_EXPLICIT (0) nor SINTER_THERMAL_IMPLICIT (1)",
                           scheme);
    if (st->kind == SINTER_STEPPER_STAGGERED && scheme == SINTER_THERMAL_IMPLICIT)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_thermal_scheme: the staggered stepper integrates "
                           "temperatures by the trapezoidal rule in its fixed-point iteration "
                           "(seed 000 eq. 36); SINTER_THERMAL_IMPLICIT is for the explicit "
                           "stepper");
    st->thermal.scheme = scheme;
    st->forces_current = 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_heat_energy(const sinter_stepper *st, size_t index, double *energy)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, energy);
    if (index >= st->thermal.count)
        return sinter_fail(st->ctx, SINTER_ERR_RANGE,
                           "sinter_stepper_heat_energy: heat model %zu does not exist (%zu added)",
                           index, st->thermal.count);
    *energy = st->thermal.slots[index].energy;
    return SINTER_OK;
}

sinter_status sinter_stepper_stable_dt_thermal(sinter_stepper *st, double *dt)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, dt);
    sinter_particles *ps = st->ps;
    /* Material ids written through a view index the material table below: check them. */
    const sinter_status valid = sinter_particles_validate(ps, NULL);
    if (valid != SINTER_OK)
        return valid;
    /* Sum of conductances per particle from a conduction-only evaluation in implicit form. */
    double *g = sinter_calloc(st->ctx, ps->count + 1, sizeof(double));
    if (g == NULL)
        return SINTER_ERR_NOMEM;
    const int scheme = st->thermal.scheme;
    st->thermal.scheme = SINTER_THERMAL_IMPLICIT;
    double *heat_copy = sinter_calloc(st->ctx, ps->count + 1, sizeof(double));
    sinter_status s = heat_copy ? SINTER_OK : SINTER_ERR_NOMEM;
    if (s == SINTER_OK) {
        const size_t bytes = ps->count * sizeof(double); /* (an empty set has no arrays) */
        if (bytes > 0)
            memcpy(heat_copy, ps->heat, bytes);
        st->thermal.local_eval = 1; /* this subdomain's estimate: no collective call */
        s = sinter_thermal_eval(st);
        st->thermal.local_eval = 0;
        if (bytes > 0)
            memcpy(ps->heat, heat_copy, bytes);
    }
    st->thermal.scheme = scheme;
    if (s == SINTER_OK) {
        for (size_t k = 0; k < st->pp.count; ++k) {
            g[st->pp.i[k]] += st->thermal.g_pp[k];
            g[st->pp.j[k]] += st->thermal.g_pp[k];
        }
        for (size_t k = 0; k < st->pw.count; ++k)
            g[st->pw.i[k]] += st->thermal.g_pw[k];
        double best = INFINITY;
        for (size_t i = 0; i < ps->count; ++i)
            if (g[i] > 0.0)
                best =
                    fmin(best, ps->mass[i] *
                                   sinter_particle_heat_capacity(ps, i, ps->temperature[i]) / g[i]);
        *dt = best;
    }
    sinter_free(st->ctx, g);
    sinter_free(st->ctx, heat_copy);
    return s;
}

/* Wall k's force (j < 3 nw) or moment component j of the reactions' layout, in the walls. */
static double *reaction_slot(sinter_walls *walls, size_t nw, size_t j)
{
    return j < 3 * nw ? &walls->wall[j / 3].force[j % 3]
                      : &walls->wall[(j - 3 * nw) / 3].moment[j % 3];
}

/* The last evaluation's wall forces and moments into the walls, and the status `s` of this
 * subdomain; with domain operations both are collective and go in one reduction
 * (sinter_domain_agree_sum) for up to 10 walls: the sums over all subdomains, this
 * subdomain's force kept as its share (sinter_walls_get_force_local). The values travel
 * through a buffer on the stack, in as many reductions as they need (a shape that depends
 * only on the number of walls, the same everywhere, and no allocation that could fail on
 * one subdomain only). The walls are written only when the status agreed is SINTER_OK. */
sinter_status sinter_stepper_agree_reactions(sinter_stepper *st, sinter_status s)
{
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    /* the reproducible mode: each wall's reaction the exact sum of its contacts' own
     * (wall_sums.h), over the subdomains through two integer reductions after the status */
    if (st->reproducible && st->pw_reaction_valid && nw > 0) {
        double *total = st->wall_force;
        if (st->domain.on) {
            if (s == SINTER_OK)
                s = sinter_grow(st->ctx, (void **)&st->domain.halo, &st->domain.halo_capacity,
                                6 * nw, sizeof(double));
            s = sinter_domain_agree(st->ctx, &st->domain, s);
            total = st->domain.halo; /* (a work array between two halos) */
        }
        if (s == SINTER_OK)
            s = sinter_wall_sums(st, st->wall_force, total);
        if (s != SINTER_OK)
            return s;
        for (size_t k = 0; k < nw; ++k) {
            memcpy(st->walls->wall[k].force_local, st->wall_force + 3 * k, 3 * sizeof(double));
            memcpy(st->walls->wall[k].force, total + 3 * k, 3 * sizeof(double));
            memcpy(st->walls->wall[k].moment, total + 3 * (nw + k), 3 * sizeof(double));
        }
        return SINTER_OK;
    }
    if (st->domain.on) {
        enum { CHUNK = 63 }; /* values a reduction, the flag after them */
        double buf[CHUNK + 1];
        size_t j = 0;
        do {
            const size_t m = 6 * nw - j < CHUNK ? 6 * nw - j : CHUNK;
            if (m > 0)
                memcpy(buf, st->wall_force + j, m * sizeof(double));
            const sinter_status a = sinter_domain_agree_sum(st->ctx, &st->domain, s, buf, m);
            if (a != SINTER_OK)
                return a; /* (the same chunk everywhere: its flag sum is) */
            for (size_t i = 0; i < m; ++i)
                *reaction_slot(st->walls, nw, j + i) = buf[i];
            j += m;
        } while (j < 6 * nw);
    } else if (s != SINTER_OK) {
        return s;
    }
    for (size_t k = 0; k < nw; ++k) {
        memcpy(st->walls->wall[k].force_local, st->wall_force + 3 * k, 3 * sizeof(double));
        if (!st->domain.on) {
            memcpy(st->walls->wall[k].force, st->wall_force + 3 * k, 3 * sizeof(double));
            memcpy(st->walls->wall[k].moment, st->wall_force + 3 * (nw + k), 3 * sizeof(double));
        }
    }
    return SINTER_OK;
}

/* The memory the history commits need, taken before the status is agreed, so that
 * sinter_stepper_commit_agreed cannot fail afterwards. */
sinter_status sinter_stepper_commit_reserve(sinter_stepper *st)
{
    sinter_status s = SINTER_OK;
    for (size_t k = 0; k < st->force_count && s == SINTER_OK; ++k) {
        s = sinter_history_commit_reserve(st->ctx, &st->forces[k].pp, &st->pp);
        if (s == SINTER_OK)
            s = sinter_history_commit_reserve(st->ctx, &st->forces[k].pw, &st->pw);
    }
    return s;
}

static sinter_status commit_histories(sinter_stepper *st)
{
    sinter_status s = SINTER_OK;
    for (size_t k = 0; k < st->force_count && s == SINTER_OK; ++k) {
        st->stats.bonds_broken += st->forces[k].bonds_broken;
        st->forces[k].bonds_broken = 0;
        s = sinter_history_commit(st->ctx, &st->forces[k].pp, &st->pp);
        if (s == SINTER_OK)
            s = sinter_history_commit(st->ctx, &st->forces[k].pw, &st->pw);
    }
    return s;
}

sinter_status sinter_stepper_commit_agreed(sinter_stepper *st)
{
    const sinter_status s = commit_histories(st); /* (reserved: cannot fail) */
    if (st->walls != NULL && s == SINTER_OK)
        sinter_walls_servo_commit(st->walls, st->time); /* servos act on the accepted step */
    return s;
}

sinter_status sinter_stepper_commit(sinter_stepper *st)
{
    /* a stage of its own with domain operations: the status and the reactions summed over the
     * subdomains agreed in one reduction (collective) */
    sinter_status s = sinter_stepper_agree_reactions(st, commit_histories(st));
    if (st->walls != NULL && s == SINTER_OK)
        sinter_walls_servo_commit(st->walls, st->time); /* servos act on the accepted step */
    return s;
}

static sinter_status check_ready(sinter_stepper *st, const char *func)
{
    if (st->ps->views_out > 0)
        return sinter_fail(st->ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are out; release them "
                           "before stepping",
                           func, st->ps->views_out);
    return sinter_particles_validate(st->ps, NULL);
}

/* Bring forces, wall positions and history in line with the current state. */
static sinter_status prepare(sinter_stepper *st)
{
    sinter_domain *d = &st->domain;
    if (st->kind == SINTER_STEPPER_EXPLICIT) { /* its fixed step against the estimate */
        const sinter_status c = sinter_domain_agree(st->ctx, d, sinter_stable_step_check(st));
        if (c != SINTER_OK)
            return c;
    }
    if (st->write_generation != st->ps->write_generation ||
        st->population_generation != st->ps->population_generation)
        st->forces_current = 0; /* the host changed the state through a view, or added/removed
                                   particles; a mere reordering moves forces along */
    if (d->on) {                /* evaluated everywhere if anywhere (collective) */
        int64_t stale = !st->forces_current;
        const sinter_status r =
            sinter_domain_reduce(st->ctx, d, &stale, 1, SINTER_REDUCE_I64, SINTER_REDUCE_MAX);
        if (r != SINTER_OK)
            return r;
        st->forces_current = stale == 0;
        if (stale) /* the host may have written owned particles: their ghosts made again */
            d->rebuild_due = 1;
    }
    if (st->forces_current)
        return SINTER_OK;
    sinter_stepper_apply_furnace(st);
    sinter_status s = st->walls ? sinter_walls_move(st->walls, st->time) : SINTER_OK;
    if (s == SINTER_OK && st->kind == SINTER_STEPPER_EXPLICIT)
        s = sinter_explicit_reserve(st);
    s = sinter_domain_agree(st->ctx, d, s);
    if (s == SINTER_OK)
        s = sinter_stepper_eval_forces(st, 0.0);
    if (s == SINTER_OK && st->kind != SINTER_STEPPER_QUASISTATIC)
        s = sinter_sanity_start(st); /* particles behind a wall, coincident centres */
    s = sinter_domain_agree(st->ctx, d, s);
    if (s == SINTER_OK)
        s = sinter_stepper_commit(st);
    if (s == SINTER_OK) {
        st->forces_current = 1;
        st->write_generation = st->ps->write_generation;
        st->population_generation = st->ps->population_generation;
    }
    return s;
}

sinter_status sinter_stepper_prepare(sinter_stepper *st)
{
    return prepare(st);
}

sinter_status sinter_stepper_evaluate(sinter_stepper *st)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_status s = check_ready(st, "sinter_stepper_evaluate");
    if (s == SINTER_OK && st->walls)
        s = sinter_walls_move(st->walls, st->time);
    s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK)
        s = sinter_stepper_eval_forces(st, 0.0);
    return sinter_stepper_agree_reactions(st, s);
}

/*
 * One accepted step of at most h (the staggered stepper may shorten it after rejections; the
 * step taken is in *taken), then the observer. *stop is set if the observer asks.
 */
/*
 * A rejected step keeps the last accepted state, but the trial overwrote its forces (and
 * maybe its neighbour lists): evaluate them again, exactly as the next advance would, so that
 * the kept state is complete, readable and checkpointable right away. The step's error stays
 * the one reported; if this evaluation fails too, the next advance retries it.
 */
static void settle_after_failure(sinter_stepper *st)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_status status = ctx->last_status;
    char message[SINTER_ERROR_TEXT_SIZE];
    memcpy(message, ctx->last_error, sizeof(message));
    (void)prepare(st);
    ctx->last_status = status;
    memcpy(ctx->last_error, message, sizeof(message));
}

sinter_status sinter_stepper_set_furnace(sinter_stepper *st, size_t count, const double *times,
                                         const double *temperatures)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (count > 0) {
        SINTER_CHECK_NULL(st->ctx, times);
        SINTER_CHECK_NULL(st->ctx, temperatures);
    }
    if (count > 0 && st->thermal.count > 0)
        return sinter_fail(st->ctx, SINTER_ERR_STATE,
                           "sinter_stepper_set_furnace: the stepper has %zu heat model(s); a "
                           "furnace prescribes the temperatures and cannot be combined with them",
                           st->thermal.count);
    if (count > SIZE_MAX / (2 * sizeof(double)))
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_set_furnace: %zu points overflow the size", count);
    for (size_t k = 0; k < count; ++k) {
        if (!isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_set_furnace: time %g s of point %zu is not finite "
                               "or not after the previous point's",
                               times[k], k);
        if (!isfinite(temperatures[k]) || !(temperatures[k] > 0.0))
            return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                               "sinter_stepper_set_furnace: temperature %g K of point %zu must be "
                               "finite and > 0",
                               temperatures[k], k);
    }
    double *copy = NULL;
    if (count > 0) {
        copy = sinter_calloc(st->ctx, 2 * count, sizeof(double));
        if (copy == NULL)
            return SINTER_ERR_NOMEM;
        memcpy(copy, times, count * sizeof(double));
        memcpy(copy + count, temperatures, count * sizeof(double));
    }
    sinter_free(st->ctx, st->furnace);
    st->furnace = copy;
    st->furnace_count = count;
    st->forces_current = 0; /* softening reads the temperatures */
    return SINTER_OK;
}

void sinter_stepper_apply_furnace(sinter_stepper *st)
{
    if (st->furnace_count == 0)
        return;
    const double T = sinter_interpolate(st->furnace_count, st->furnace,
                                        st->furnace + st->furnace_count, st->time);
    for (size_t i = 0; i < st->ps->count; ++i)
        st->ps->temperature[i] = T;
}

void sinter_stepper_shift_furnace(sinter_stepper *st, double delay)
{
    for (size_t k = 0; k < st->furnace_count; ++k)
        st->furnace[k] += delay;
}

static sinter_status take_step(sinter_stepper *st, double h, double t_end, double *taken, int *stop)
{
    sinter_status s;
    if (sinter_frozen_release(st) && (s = prepare(st)) != SINTER_OK)
        return s; /* frozen with the stage off (a restart, issue 41): the mechanics step on */
    if (st->frozen.active) {
        /* the frozen heat stage: one heat step over the frozen bed, or a wake-up */
        int woke = 0;
        s = sinter_frozen_step(st, t_end, taken, &woke);
        if (s == SINTER_OK && !st->forces_current) /* woken: the forces of the new state */
            s = prepare(st);
        if (s == SINTER_OK && *taken > 0.0 && st->observer != NULL &&
            st->observer(st, st->time, st->observer_user) != 0)
            *stop = 1;
        return s;
    }
    if (st->sort_interval > 0 && st->steps_since_sort >= st->sort_interval) {
        /* option sort_interval: forces and history move with the particles, and the step
         * rebuilds the contact lists for the new order (a quasi-static step sets its links'
         * indices from their ids) */
        s = sinter_particles_sort_spatial(st->ps);
        if (s != SINTER_OK)
            return s;
        st->steps_since_sort = 0;
        st->staggered.history_valid = 0; /* the predictor's history is indexed by particle */
    }
    if (st->kind == SINTER_STEPPER_STAGGERED) {
        s = sinter_staggered_step(st, h, taken);
    } else if (st->kind == SINTER_STEPPER_QUASISTATIC) {
        s = sinter_quasistatic_step(st, &st->quasistatic, &st->quasistatic_options, h, taken);
    } else {
        sinter_thread_choice_begin(st); /* 1 or the context's threads, by timing */
        const double clock_start = sinter_clock();
        s = sinter_explicit_step(st, h);
        sinter_thread_choice_end(st, sinter_clock() - clock_start, s == SINTER_OK);
        *taken = h;
        st->eval_lag = s == SINTER_OK ? 0.5 * h : 0.0;
        if (s == SINTER_OK) /* at rest: the next steps are heat steps (frozen_heat.h; across
                               subdomains decided from reductions) */
            s = sinter_frozen_consider(st);
    }
    if (s != SINTER_OK) {
        settle_after_failure(st);
        return s;
    }
    sinter_stepper_apply_furnace(st);
    st->stats.steps++;
    st->steps_since_sort++;
    if (st->observer != NULL && st->observer(st, st->time, st->observer_user) != 0)
        *stop = 1;
    return SINTER_OK;
}

/* With domain operations, whether the run goes on, the same on every subdomain (one
 * reduction): a stop asked of one subdomain's context (status `s`) or by its observer
 * (*stop) stops all of them. Without, `s` as it is. */
static sinter_status go_on_together(sinter_stepper *st, sinter_status s, int *stop)
{
    if (!st->domain.on)
        return s;
    int64_t v[2] = {(int64_t)s, *stop ? -1 : 0}; /* (a MIN of both) */
    const sinter_status r =
        sinter_domain_reduce(st->ctx, &st->domain, v, 2, SINTER_REDUCE_I64, SINTER_REDUCE_MIN);
    if (r != SINTER_OK)
        return r;
    *stop = v[1] < 0;
    return v[0] < 0 ? sinter_domain_agree(st->ctx, &st->domain, s) : SINTER_OK;
}

/* The step to try next: the set (explicit) or adapted (staggered) step, capped by dt_max. */
static double next_step(const sinter_stepper *st)
{
    if (st->kind == SINTER_STEPPER_STAGGERED)
        return fmin(st->dt, st->staggered.dt_max);
    if (st->kind == SINTER_STEPPER_QUASISTATIC)
        return fmin(st->dt, st->quasistatic_options.dt_max);
    return st->dt;
}

sinter_status sinter_stepper_advance(sinter_stepper *st, double t_end)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (!isfinite(t_end))
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_advance: end time %g s is not a finite number", t_end);
    if (t_end < st->time)
        return sinter_fail(st->ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_advance: end time %g s is before the current time %g "
                           "s (time cannot go backwards)",
                           t_end, st->time);
    const double t0 = sinter_clock();
    sinter_status s = check_ready(st, "sinter_stepper_advance");
    s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK)
        s = prepare(st);
    int stop = 0;
    while (s == SINTER_OK && (!stop || st->domain.on) && st->time < t_end) {
        s = sinter_ctx_take_stop(st->ctx, "sinter_stepper_advance", st->time);
        if ((s = go_on_together(st, s, &stop)) != SINTER_OK || stop)
            break;
        const double proposal = next_step(st);
        double h = proposal, taken = 0.0;
        const double remaining = t_end - st->time;
        /* Land exactly on t_end: a last step up to 1e-6 longer absorbs the remainder, and a
         * sliver below 1e-6 of a step left by round-off in the accumulated time is skipped
         * rather than taken as an extra tiny step. */
        if (remaining <= h * (1.0 + 1e-6))
            h = remaining;
        if (h <= 1e-6 * proposal) {
            st->time = t_end;
            break;
        }
        s = take_step(st, h, t_end, &taken, &stop);
        if (s == SINTER_OK && taken == remaining) {
            st->time = t_end;
            /* A step shortened to land on t_end says nothing against the longer proposal. */
            if (h < proposal && st->dt < proposal) {
                st->dt = proposal;
                st->stats.dt = proposal;
            }
        }
    }
    st->stats.seconds_total += sinter_clock() - t0;
    return s;
}

sinter_status sinter_stepper_step(sinter_stepper *st, uint64_t n)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    const double t0 = sinter_clock();
    sinter_status s = check_ready(st, "sinter_stepper_step");
    s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK)
        s = prepare(st);
    int stop = 0;
    double taken = 0.0;
    for (uint64_t k = 0; k < n && s == SINTER_OK && (!stop || st->domain.on); ++k) {
        s = sinter_ctx_take_stop(st->ctx, "sinter_stepper_step", st->time);
        if ((s = go_on_together(st, s, &stop)) != SINTER_OK || stop)
            break;
        s = take_step(st, next_step(st), INFINITY, &taken, &stop);
    }
    st->stats.seconds_total += sinter_clock() - t0;
    return s;
}
