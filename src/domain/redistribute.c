/*
 * The host's redistribution as a stage of the rebuild (include/sinter_domain.h): the host
 * may migrate owned particles there (sinter_stepper_export / _import), which removes some
 * rows and appends others in the middle of a step. The explicit stepper's spare arrays hold
 * the state at t of the step under way, row by row (stepper/explicit.c: the rollback and the
 * sanity checks read them), so they are made to follow: every particle that stayed takes its
 * rows back by id; an arrival takes the state at t its record brought (an export during this
 * stage writes the spare rows, an import during it keeps them in the domain's arrival list), so
 * that a step rejected after a migration restores every particle on the side it entered, and
 * the displacement checks see an arrival's motion over the whole step. The rows an arrival brings
 * for force, moment and heat are not what this subdomain's drift left (zeroed, or m g seeded), so
 * the evaluation zeroes them all itself after a migration; and the kick that ends the step takes
 * its general path when an arrival is fixed or does not rotate.
 */
#include <string.h>

#include "domain/domain.h"
#include "particles/id_index.h"
#include "stepper/stepper.h"

/* The spare rows (x, v, w, rot at t) and the saved temperatures (thermal.h: at t when the
 * step advanced them) of the owned particles, by id, before a redistribution. */
typedef struct spare_rows {
    size_t n;
    uint64_t *id;
    double *rows; /* 13 per particle */
} spare_rows;

/* The saved temperatures by index, or NULL when the stepper keeps none. */
static double *saved_temperatures(const sinter_stepper *st)
{
    return st->thermal.count > 0 ? st->thermal.theta_backup : NULL;
}

static sinter_status keep_rows(sinter_stepper *st, spare_rows *k)
{
    const sinter_particles *ps = st->ps;
    memset(k, 0, sizeof(*k));
    if (st->spare[0] == NULL)
        return SINTER_OK;
    k->n = ps->count - ps->ghost_count;
    k->id = sinter_calloc(st->ctx, k->n + 1, sizeof(uint64_t));
    k->rows = sinter_calloc(st->ctx, 13 * k->n + 1, sizeof(double));
    if (k->id == NULL || k->rows == NULL)
        return sinter_fail(st->ctx, SINTER_ERR_NOMEM,
                           "the rebuild stage: no memory to keep %zu particles' state", k->n);
    if (k->n > 0)
        memcpy(k->id, ps->id, k->n * sizeof(uint64_t));
    for (int f = 0; f < 4; ++f)
        for (size_t i = 0; st->spare[f] != NULL && i < k->n; ++i)
            memcpy(k->rows + 13 * i + 3 * f, st->spare[f] + 3 * i, 3 * sizeof(double));
    const double *saved = saved_temperatures(st);
    for (size_t i = 0; saved != NULL && i < k->n && i < st->thermal.backup_capacity; ++i)
        k->rows[13 * i + 12] = saved[i];
    return SINTER_OK;
}

/* Row j of the spare arrays and of the saved temperatures from a kept row. */
static void put_row(sinter_stepper *st, size_t j, const double *row)
{
    for (int f = 0; f < 4; ++f)
        if (st->spare[f] != NULL)
            memcpy(st->spare[f] + 3 * j, row + 3 * f, 3 * sizeof(double));
    double *saved = saved_temperatures(st);
    if (saved != NULL)
        saved[j] = row[12];
}

/* The spare rows after particles left or came: the stayers' by id, the arrivals' those their
 * records brought (migrate.c), any other's from now. */
static sinter_status follow_rows(sinter_stepper *st, const spare_rows *k)
{
    sinter_particles *ps = st->ps;
    sinter_status s = sinter_explicit_keep_spare(st); /* (at the set's capacity) */
    if (s == SINTER_OK)
        s = sinter_id_index_update(&ps->id_index, ps);
    if (s == SINTER_OK && saved_temperatures(st) != NULL)
        s = sinter_grow(st->ctx, (void **)&st->thermal.theta_backup, &st->thermal.backup_capacity,
                        ps->count + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    const size_t owned = ps->count - ps->ghost_count;
    const double *now[4] = {ps->x, ps->v, ps->w, ps->rot};
    for (int f = 0; f < 4; ++f)
        if (st->spare[f] != NULL && owned > 0)
            memcpy(st->spare[f], now[f], 3 * owned * sizeof(double));
    if (saved_temperatures(st) != NULL && owned > 0)
        memcpy(st->thermal.theta_backup, ps->temperature, owned * sizeof(double));
    for (size_t i = 0; i < k->n; ++i) {
        const size_t j = sinter_id_index_find(&ps->id_index, ps, k->id[i]);
        if (j < owned)
            put_row(st, j, k->rows + 13 * i);
    }
    const sinter_domain *d = &st->domain;
    for (size_t i = 0; i < d->arrived_count; ++i) {
        const size_t j = sinter_id_index_find(&ps->id_index, ps, d->arrived_id[i]);
        if (j < owned)
            put_row(st, j, d->arrived_rows + 13 * i);
    }
    return SINTER_OK;
}

sinter_status sinter_domain_redistribute(sinter_stepper *st)
{
    sinter_domain *d = &st->domain;
    const uint64_t population = st->ps->population_generation;
    spare_rows k;
    sinter_status s = keep_rows(st, &k);
    d->arrived_count = 0;
    d->redistributing = 1; /* exports carry the state at t, imports keep it */
    d->layout_at_start = st->ps->layout_generation;
    if (s == SINTER_OK && d->ops.redistribute(st, d->user) != 0)
        s = sinter_fail(st->ctx, SINTER_ERR_CALLBACK,
                        "the host's redistribute callback failed at t = %.9g s", st->time);
    d->redistributing = 0;
    if (s == SINTER_OK && st->ps->population_generation != population) {
        /* particles migrated: an arrival's force, moment and heat rows are those its record
         * brought, not zeroed by this subdomain's drift, so the evaluation zeroes every row
         * itself (the same bits: 0 + m g either way) */
        st->forces_zeroed = st->gravity_seeded = 0;
        st->thermal.heat_zeroed = 0;
        /* the step's kick takes the general path when an arrival is fixed or does not rotate
         * (the drift found the particles plain before they came) */
        const sinter_particles *ps = st->ps;
        for (size_t i = 0; i < ps->count - ps->ghost_count && st->plain_particles; ++i)
            if (ps->flags[i] & (SINTER_PARTICLE_FIXED | SINTER_PARTICLE_NO_ROTATION))
                st->plain_particles = 0;
        if (k.id != NULL)
            s = follow_rows(st, &k);
    }
    sinter_free(st->ctx, k.id);
    sinter_free(st->ctx, k.rows);
    return s;
}
