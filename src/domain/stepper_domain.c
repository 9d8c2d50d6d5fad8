/* The stepper's public side of a decomposed run (include/sinter_domain.h): the host's
 * operations installed, the ghost cut-off, and the global results. */
#include <string.h>

#include "electric/electric.h"
#include "stepper/stepper.h"
#include "walls/walls.h"
#include "stepper/qs_struct.h"

/* SINTER_OK when the stepper's settings work across subdomains in this version, else
 * SINTER_ERR_UNSUPPORTED naming the first that does not (checked again at every step). */
sinter_status sinter_domain_check(sinter_stepper *st)
{
    const char *what = NULL;
    if (st->kind == SINTER_STEPPER_QUASISTATIC && st->quasistatic_options.strategy == 1)
        what = "qs_strategy 1 (its whole-step rejections are not agreed yet)";
    else if (st->kind == SINTER_STEPPER_QUASISTATIC && st->quasistatic != NULL &&
             st->quasistatic->steps > 0 && !st->quasistatic->dom.on &&
             !st->quasistatic->dom.restored) /* (a portable restart's links come by record) */
        what = "a quasi-static stepper that has stepped without them (its links are all here)";
    else if (sinter_ghosts_on(&st->ghosts))
        what = "periodic axes (sinter_stepper_set_periodic)";
    else if (st->electric != NULL && st->electric->host.struct_size != 0)
        what = "an electric model with host callbacks";
    else if (st->sort_interval > 0)
        what = "the option sort_interval (a sort drops the ghosts)";
    if (what == NULL)
        return SINTER_OK;
    return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                       "domain operations (include/sinter_domain.h) do not support %s yet", what);
}

sinter_status sinter_stepper_set_domain_ops(sinter_stepper *st, const sinter_domain_ops *ops,
                                            void *user)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    if (ops != NULL) {
        if (ops->struct_size != sizeof(sinter_domain_ops))
            return sinter_fail(st->ctx, SINTER_ERR_STRUCT_SIZE,
                               "sinter_stepper_set_domain_ops: struct_size %zu, expected %zu",
                               ops->struct_size, sizeof(sinter_domain_ops));
        if (ops->reduce == NULL || ops->exscan == NULL || ops->halo == NULL ||
            ops->redistribute == NULL)
            return sinter_fail(st->ctx, SINTER_ERR_NULL,
                               "sinter_stepper_set_domain_ops: reduce, exscan, halo and "
                               "redistribute are required");
        const sinter_status s = sinter_domain_check(st);
        if (s != SINTER_OK)
            return s;
    }
    sinter_domain *d = &st->domain;
    if (d->on && d->ops.destroy_user != NULL)
        d->ops.destroy_user(d->user);
    d->on = ops != NULL;
    if (ops != NULL)
        d->ops = *ops;
    else
        memset(&d->ops, 0, sizeof(d->ops));
    d->user = user;
    d->rank = -1;
    d->cutoff = 0.0;
    d->rebuild_due = 1; /* the first step rebuilds, with the host's redistribution */
    st->nb.both_sides = d->on;
    st->nb.built = 0;
    st->forces_current = 0;
    return SINTER_OK;
}

sinter_status sinter_stepper_ghost_cutoff(const sinter_stepper *st, double *cutoff)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, cutoff);
    if (st->domain.on && st->domain.cutoff > 0.0) {
        *cutoff = st->domain.cutoff;
        return SINTER_OK;
    }
    /* before the first rebuild: this set's owned particles, and the skin if set */
    *cutoff = sinter_ghosts_cutoff(st->ps, st->nb.skin + st->nb.reach);
    return SINTER_OK;
}

sinter_status sinter_walls_get_force_local(const sinter_walls *walls, size_t k, double force[3])
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(walls->ctx, force);
    if (k >= walls->count)
        return sinter_fail(walls->ctx, SINTER_ERR_RANGE,
                           "sinter_walls_get_force_local: wall %zu of %zu", k, walls->count);
    memcpy(force, walls->wall[k].force_local, 3 * sizeof(double));
    return SINTER_OK;
}

sinter_status sinter_stepper_heat_energy_global(const sinter_stepper *st, size_t index,
                                                double *energy)
{
    sinter_status s = sinter_stepper_heat_energy(st, index, energy);
    if (s != SINTER_OK || !st->domain.on)
        return s;
    return sinter_domain_reduce(st->ctx, (sinter_domain *)&st->domain, energy, 1, SINTER_REDUCE_F64,
                                SINTER_REDUCE_SUM);
}

sinter_status sinter_stepper_get_stats_global(const sinter_stepper *st, sinter_stepper_stats *stats)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, stats);
    if (stats->struct_size != sizeof(sinter_stepper_stats))
        return sinter_fail(st->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_stepper_get_stats_global: struct_size %zu, expected %zu",
                           stats->struct_size, sizeof(sinter_stepper_stats));
    sinter_stepper_stats s;
    s.struct_size = sizeof(s);
    sinter_status r = sinter_stepper_get_stats(st, &s);
    if (r != SINTER_OK || !st->domain.on) {
        if (r == SINTER_OK)
            *stats = s;
        return r;
    }
    /* the reductions change only counters of the domain (a const stepper otherwise) */
    sinter_domain *d = (sinter_domain *)&st->domain;
    uint64_t sum[3] = {s.contacts, s.wall_contacts, s.bonds_broken};
    double seconds[5] = {s.seconds_neighbor, s.seconds_force, s.seconds_integrate, s.seconds_total,
                         0.0};
    r = sinter_domain_reduce(st->ctx, d, sum, 3, SINTER_REDUCE_U64, SINTER_REDUCE_SUM);
    if (r == SINTER_OK)
        r = sinter_domain_reduce(st->ctx, d, seconds, 4, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (r != SINTER_OK)
        return r;
    s.contacts = sum[0];
    s.wall_contacts = sum[1];
    s.bonds_broken = sum[2];
    s.seconds_neighbor = seconds[0];
    s.seconds_force = seconds[1];
    s.seconds_integrate = seconds[2];
    s.seconds_total = seconds[3];
    *stats = s; /* steps, rejections, builds and evaluations are collective: equal everywhere */
    return SINTER_OK;
}
