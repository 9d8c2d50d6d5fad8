/* The quasi-static stepper's collective stages on one subdomain (qs_domain.h, issue 43). */
#include <math.h>
#include <string.h>

#include "bonded/solve_split.h"
#include "stepper/qs_repro.h"
#include "stepper/qs_domain.h"
#include "stepper/stepper.h"

#define QS_PI 3.14159265358979323846

sinter_status sinter_qs_domain_bind(sinter_qs *qs, struct sinter_stepper *st)
{
    sinter_qs_domain *dom = &qs->dom;
    const sinter_particles *ps = st->ps;
    dom->on = st->domain.on;
    dom->repro = st->reproducible;
    if (!dom->on) { /* (one part of every row: what the reproducible mode's stages read) */
        dom->owned = ps->count;
        dom->ghosts = 0;
        dom->id = ps->id;
        return SINTER_OK;
    }
    dom->d = &st->domain;
    dom->owned = ps->count - ps->ghost_count;
    dom->ghosts = ps->ghost_count;
    dom->id = ps->id;
    if (dom->size == 0) {
        uint64_t before = 0, total = 0;
        if (dom->d->ops.exscan(1, &before, &total, dom->d->user) != 0)
            return sinter_fail(qs->ctx, SINTER_ERR_CALLBACK, "the host's exscan callback failed");
        dom->size = total;
    }
    dom->split = dom->size > 1;
    return SINTER_OK;
}

sinter_status sinter_qs_domain_agree(sinter_qs *qs, sinter_status s)
{
    return qs->dom.on ? sinter_domain_agree(qs->ctx, qs->dom.d, s) : s;
}

sinter_status sinter_qs_domain_reduce(sinter_qs *qs, void *values, size_t count, int type, int op)
{
    return qs->dom.on ? sinter_domain_reduce(qs->ctx, qs->dom.d, values, count, type, op)
                      : SINTER_OK;
}

sinter_status sinter_qs_domain_start(sinter_qs *qs, const sinter_qs_particles *p)
{
    /* lo (3), -hi (3) of the centres, lo (3), -hi (3) of the spheres: one MIN */
    double v[12];
    for (int k = 0; k < 12; ++k)
        v[k] = INFINITY;
    double volume = 0.0; /* summed in id order over the owned slots */
    for (size_t s = 0; s < p->count; ++s) {
        const size_t i = qs->index_of_slot[s];
        if (sinter_qs_domain_ghost(qs, i))
            continue;
        const double r = p->radius[i];
        volume += 4.0 / 3.0 * QS_PI * r * r * r;
        for (size_t d = 0; d < 3; ++d) {
            const double x = p->x[3 * i + d];
            v[d] = fmin(v[d], x);
            v[3 + d] = fmin(v[3 + d], -x);
            v[6 + d] = fmin(v[6 + d], x - r);
            v[9 + d] = fmin(v[9 + d], -(x + r));
        }
    }
    double count = (double)qs->dom.owned;
    sinter_status st = sinter_qs_domain_reduce(qs, v, 12, SINTER_REDUCE_F64, SINTER_REDUCE_MIN);
    double sums[2] = {volume, count};
    double *terms = NULL;
    if (qs->dom.repro) { /* the volume an exact sum (qs_repro.h) */
        terms = sinter_alloc(qs->ctx, (p->count + 1) * sizeof(double));
        size_t k = 0;
        for (size_t i = 0; i < p->count && terms != NULL; ++i)
            if (!sinter_qs_domain_ghost(qs, i))
                terms[k++] = 4.0 / 3.0 * QS_PI * p->radius[i] * p->radius[i] * p->radius[i];
        const sinter_status agreed =
            sinter_qs_domain_agree(qs, terms == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
        st = st == SINTER_OK ? agreed : st;
        if (st == SINTER_OK)
            st = sinter_qs_repro_series(qs, terms, k, 1, &volume);
        sinter_free(qs->ctx, terms);
        sums[0] = 0.0; /* (the sum below then adds only the counts) */
    }
    if (st == SINTER_OK)
        st = sinter_qs_domain_reduce(qs, sums, 2, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (qs->dom.repro)
        sums[0] = volume;
    if (st != SINTER_OK)
        return st;
    qs->dom.started = 1;
    for (int d = 0; d < 3; ++d)
        qs->extent0[d] = sums[1] > 0.0 ? -v[3 + d] - v[d] : 0.0;
    qs->density0 =
        sums[1] > 0.0 ? sums[0] / ((-v[9] - v[6]) * (-v[10] - v[7]) * (-v[11] - v[8])) : 0.0;
    return SINTER_OK;
}

/* The host's halo over rows (index order, width doubles each). */
static sinter_status halo(sinter_qs *qs, double *rows, size_t width, int direction)
{
    sinter_qs_domain *dom = &qs->dom;
    const sinter_halo h = {.struct_size = sizeof(sinter_halo),
                           .direction = direction,
                           .width = width,
                           .data = rows,
                           .id = dom->id,
                           .owned = dom->owned,
                           .ghosts = dom->ghosts};
    dom->d->halos++;
    if (dom->d->ops.halo(&h, dom->d->user) != 0)
        return sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                           "the host's halo callback failed (%s, width %zu, quasi-static stepper)",
                           direction == SINTER_HALO_FORWARD ? "forward" : "reverse", width);
    return SINTER_OK;
}

static sinter_status rows_for(sinter_qs *qs, size_t width)
{
    const size_t n = qs->dom.owned + qs->dom.ghosts;
    return sinter_grow(qs->ctx, (void **)&qs->dom.rows, &qs->dom.rows_capacity, width * n + 1,
                       sizeof(double));
}

sinter_status sinter_qs_domain_reverse(sinter_qs *qs, double *per_slot, size_t width)
{
    if (!qs->dom.on || qs->dom.ghosts == 0)
        return SINTER_OK;
    sinter_status st = rows_for(qs, width);
    if (st != SINTER_OK)
        return st;
    const size_t n = qs->dom.owned + qs->dom.ghosts;
    double *rows = qs->dom.rows;
    for (size_t i = 0; i < n; ++i)
        memcpy(rows + width * i, per_slot + width * (size_t)qs->slot_of[i], width * sizeof(double));
    if ((st = halo(qs, rows, width, SINTER_HALO_REVERSE)) != SINTER_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        double *row = per_slot + width * (size_t)qs->slot_of[i];
        if (i < qs->dom.owned)
            memcpy(row, rows + width * i, width * sizeof(double));
        else
            memset(row, 0, width * sizeof(double));
    }
    return SINTER_OK;
}

/* The split solve's exchanges over the qs's rows (index order). */
/* (without domain operations, the reproducible mode's solve on one part: nothing to do) */
static int ex_forward(double *rows, size_t width, void *user)
{
    const sinter_qs *qs = user;
    return qs->dom.on && halo(user, rows, width, SINTER_HALO_FORWARD) != SINTER_OK;
}

static int ex_reverse(double *rows, size_t width, void *user)
{
    const sinter_qs *qs = user;
    return qs->dom.on && halo(user, rows, width, SINTER_HALO_REVERSE) != SINTER_OK;
}

static int ex_sum(double *values, size_t count, void *user)
{
    sinter_qs *qs = user;
    return qs->dom.on && sinter_domain_reduce(qs->ctx, qs->dom.d, values, count, SINTER_REDUCE_F64,
                                              SINTER_REDUCE_SUM) != SINTER_OK;
}

sinter_status sinter_qs_domain_solve(sinter_qs *qs, size_t n, const double *f, const double *guess,
                                     double *u, int *iterations)
{
    const size_t m = qs->count;
    /* everything in index order: the beams' ends, the conditions, the loads, the start */
    sinter_beam *beams = sinter_alloc(qs->ctx, (m + 1) * sizeof(sinter_beam));
    unsigned char *fixed = sinter_alloc(qs->ctx, 6 * n + 1);
    double *vec = sinter_alloc(qs->ctx, (18 * n + 1) * sizeof(double));
    sinter_status st = beams == NULL || fixed == NULL || vec == NULL ? SINTER_ERR_NOMEM : SINTER_OK;
    double *fi = vec, *gi = vec + 6 * n, *ui = vec + 12 * n;
    if (st == SINTER_OK) {
        for (size_t k = 0; k < m; ++k) {
            beams[k] = qs->beams[k];
            beams[k].a = qs->index_of_slot[qs->beams[k].a];
            beams[k].b = qs->index_of_slot[qs->beams[k].b];
        }
        for (size_t i = 0; i < n; ++i) {
            const size_t s = qs->slot_of[i];
            memcpy(fixed + 6 * i, qs->fixed + 6 * s, 6);
            memcpy(fi + 6 * i, f + 6 * s, 6 * sizeof(double));
            if (guess != NULL)
                memcpy(gi + 6 * i, guess + 6 * s, 6 * sizeof(double));
        }
    }
    /* a failure here is agreed inside the solve, before its first exchange */
    const sinter_bonded_exchange ex = {ex_forward, ex_reverse,    ex_sum,
                                       qs,         qs->dom.repro, sinter_qs_repro_reduce(qs)};
    if (st == SINTER_OK)
        st = sinter_bonded_solve_split(qs->ctx, qs->dom.on ? qs->dom.owned : n, n, beams, m, fixed,
                                       fi, guess != NULL ? gi : NULL, ui, qs->opt.solve_rtol, &ex,
                                       iterations);
    else { /* take part in the solve's first agreement, then stop */
        double failed = 1.0;
        (void)ex_sum(&failed, 1, qs);
    }
    if (st == SINTER_OK)
        for (size_t i = 0; i < n; ++i)
            memcpy(u + 6 * (size_t)qs->slot_of[i], ui + 6 * i, 6 * sizeof(double));
    sinter_free(qs->ctx, beams);
    sinter_free(qs->ctx, fixed);
    sinter_free(qs->ctx, vec);
    return st;
}

sinter_status sinter_qs_domain_linked(sinter_qs *qs, size_t n, unsigned char *linked)
{
    if (!qs->dom.on || qs->dom.ghosts == 0)
        return SINTER_OK;
    sinter_status st = rows_for(qs, 1);
    if (st != SINTER_OK)
        return st;
    for (size_t i = 0; i < n; ++i)
        qs->dom.rows[i] = linked[i];
    if ((st = halo(qs, qs->dom.rows, 1, SINTER_HALO_REVERSE)) != SINTER_OK)
        return st;
    for (size_t i = 0; i < n; ++i)
        linked[i] = (unsigned char)(i < qs->dom.owned && qs->dom.rows[i] > 0.0);
    return SINTER_OK;
}

sinter_status sinter_qs_domain_reverse_index(sinter_qs *qs, double *rows, size_t width)
{
    if (!qs->dom.on || qs->dom.ghosts == 0)
        return SINTER_OK;
    return halo(qs, rows, width, SINTER_HALO_REVERSE);
}

sinter_status sinter_qs_domain_forward_index(sinter_qs *qs, double *rows, size_t width)
{
    if (!qs->dom.on || qs->dom.ghosts == 0)
        return SINTER_OK;
    return halo(qs, rows, width, SINTER_HALO_FORWARD);
}
