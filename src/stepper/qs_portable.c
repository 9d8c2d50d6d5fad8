/*
 * The quasi-static stepper in a portable checkpoint (issue 43): the stepper-wide state goes
 * into the global part (global_state.c), the per-particle state into the particles' records
 * (migrate.c), so that a restart may split and order the particles in any way.
 *
 * Global: f64 extent0[3], dt_next, u_step, density0, cell lower corner[3], lengths now[3],
 * lengths at the start[3]; u64 1 when a state is held, steps, rejected, pcg_iterations,
 * substepped, 1 once set up (the first set-up's extents, origins and density taken), the mask
 * of the periodic axes, 1 once the cell's start is taken, the validity guard's warnings.
 * Per particle (sinter_qs_carried): the principal-plane conditions and the last displacements
 * of its slot, and its initial position (the reference of the shrinkage). The importer keeps
 * them by id; the remap that follows (qs_ids.c) gives them to the new slots when they cover
 * every particle, so the next solve starts where the uninterrupted run's would.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stepper/migrate.h"
#include "stepper/qs_domain.h"
#include "stepper/qs_struct.h"

/* The origin of id among the first count of o (sorted by id), or NULL. */
static const sinter_qs_origin *origin_in(const sinter_qs_origin *o, size_t count, uint64_t id)
{
    size_t lo = 0, hi = count;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (o[mid].id < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < count && o[lo].id == id ? &o[lo] : NULL;
}

static int pair_order(const void *a, const void *b);

uint64_t *sinter_qs_carried_index(const sinter_qs *qs, sinter_ctx *ctx, size_t *count,
                                  sinter_status *s)
{
    *count = 0;
    if (qs == NULL || qs->carried_count == 0)
        return NULL;
    uint64_t *index = sinter_alloc(ctx, 2 * qs->carried_count * sizeof(uint64_t));
    if (index == NULL) {
        *s = SINTER_ERR_NOMEM;
        return NULL;
    }
    for (size_t k = 0; k < qs->carried_count; ++k) {
        index[2 * k] = qs->carried_id[k];
        index[2 * k + 1] = k;
    }
    qsort(index, qs->carried_count, 2 * sizeof(uint64_t), pair_order);
    *count = qs->carried_count;
    return index;
}

void sinter_qs_carried_of(const sinter_qs *qs, const uint64_t *index, size_t count, size_t n,
                          size_t i, uint64_t id, sinter_qs_carried *out)
{
    memset(out, 0, sizeof(*out));
    if (qs == NULL)
        return;
    if (qs->slots_valid && qs->slots == n && i < n && qs->slot_id[qs->slot_of[i]] == id &&
        qs->particles == n && qs->fixed != NULL) {
        const size_t sl = qs->slot_of[i];
        out->bits |= 1;
        memcpy(out->fixed, qs->fixed + 6 * sl, 6);
        if (qs->u_step > 0.0 && qs->u != NULL) {
            out->bits |= 2;
            memcpy(out->u, qs->u + 6 * sl, sizeof(out->u));
        }
    }
    /* imported and exported again before a remap gave it a slot (a checkpoint's reader sends
     * the particles of its pieces on to their owners): the state its record brought, the last
     * of its id */
    if (!(out->bits & 1) && index != NULL) {
        size_t lo = 0, hi = count; /* the first pair of an id above `id` */
        while (lo < hi) {
            const size_t mid = lo + (hi - lo) / 2;
            if (index[2 * mid] <= id)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo > 0 && index[2 * (lo - 1)] == id) {
            const sinter_qs_carried *c = &qs->carried[index[2 * (lo - 1) + 1]];
            out->bits |= c->bits & 3;
            memcpy(out->fixed, c->fixed, sizeof(out->fixed));
            memcpy(out->u, c->u, sizeof(out->u));
        }
    }
    const sinter_qs_origin *o = origin_in(qs->origins, qs->origin_count, id);
    if (o != NULL) {
        out->bits |= 4;
        memcpy(out->origin, o->x, sizeof(out->origin));
    }
}

const char *sinter_qs_carried_wrong(const sinter_qs_carried *c)
{
    if (c->bits > 7 || ((c->bits & 2) && !(c->bits & 1)))
        return "its quasi-static state's flags are malformed";
    for (int k = 0; k < 8; ++k)
        if (c->fixed[k] > (k < 6 && (c->bits & 1) ? 1 : 0))
            return "its quasi-static plane conditions hold values other than 0 and 1";
    for (int k = 0; k < 6; ++k)
        if (!isfinite(c->u[k]) || (!(c->bits & 2) && c->u[k] != 0.0))
            return "its quasi-static displacements are not finite";
    for (int k = 0; k < 3; ++k)
        if (!isfinite(c->origin[k]) || (!(c->bits & 4) && c->origin[k] != 0.0))
            return "its quasi-static initial position is not finite";
    return NULL;
}

static int origin_order(const void *a, const void *b)
{
    const sinter_qs_origin *x = a, *y = b;
    return (x->id > y->id) - (x->id < y->id);
}

sinter_status sinter_qs_carried_add(sinter_qs *qs, const uint64_t *id, const sinter_qs_carried *c,
                                    size_t m)
{
    const size_t need = qs->carried_count + m + 1;
    sinter_status s =
        sinter_grow(qs->ctx, (void **)&qs->carried_id, &qs->carried_id_capacity, need, 8);
    if (s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->carried, &qs->carried_capacity, need,
                        sizeof(sinter_qs_carried));
    if (s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->origins, &qs->origin_capacity,
                        qs->origin_count + m + 1, sizeof(sinter_qs_origin));
    if (s != SINTER_OK)
        return s;
    const size_t before = qs->origin_count;
    for (size_t k = 0; k < m; ++k) {
        qs->carried_id[qs->carried_count] = id[k];
        qs->carried[qs->carried_count++] = c[k];
        if ((c[k].bits & 4) && origin_in(qs->origins, before, id[k]) == NULL) {
            sinter_qs_origin *o = &qs->origins[qs->origin_count++];
            o->id = id[k];
            memcpy(o->x, c[k].origin, sizeof(o->x));
        }
    }
    if (qs->origin_count > before) /* sorted by id again (the ids of one import differ) */
        qsort(qs->origins, qs->origin_count, sizeof(sinter_qs_origin), origin_order);
    return SINTER_OK;
}

static int pair_order(const void *a, const void *b)
{
    const uint64_t *x = a, *y = b;
    if (x[0] != y[0])
        return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

int sinter_qs_carried_apply(sinter_qs *qs)
{
    const size_t n = qs->slots;
    /* with domain operations the owned particles' states: a ghost's conditions and
     * displacements are not read (the split solve and the floating components read the owned
     * rows; the ghosts' u come from their owners), so they are left 0 */
    const size_t needed = qs->dom.on && qs->dom.owned <= n ? qs->dom.owned : n;
    if (qs->carried_count < needed || n == 0 || qs->particles == 0 || !qs->slots_valid)
        return 0;
    /* the carried state of each slot: (id, entry) sorted by id, the last entry of an id kept,
     * walked along the ascending slot ids */
    const size_t m = qs->carried_count;
    uint64_t(*pairs)[2] = sinter_alloc(qs->ctx, (m + 1) * sizeof(*pairs));
    size_t *at = sinter_alloc(qs->ctx, (n + 1) * sizeof(size_t));
    if (pairs == NULL || at == NULL) {
        sinter_free(qs->ctx, pairs);
        sinter_free(qs->ctx, at);
        (void)sinter_clear_error(qs->ctx); /* detected again instead */
        return 0;
    }
    for (size_t k = 0; k < m; ++k) {
        pairs[k][0] = qs->carried_id[k];
        pairs[k][1] = k;
    }
    qsort(pairs, m, sizeof(*pairs), pair_order);
    int all_u = 1, ok = 1;
    size_t k = 0;
    for (size_t sl = 0; sl < n && ok; ++sl) {
        if (sinter_qs_domain_ghost(qs, qs->index_of_slot[sl])) {
            at[sl] = SIZE_MAX;
            continue;
        }
        while (k < m && pairs[k][0] < qs->slot_id[sl])
            ++k;
        while (k + 1 < m && pairs[k + 1][0] == qs->slot_id[sl])
            ++k;
        ok = k < m && pairs[k][0] == qs->slot_id[sl] && (qs->carried[pairs[k][1]].bits & 1);
        at[sl] = ok ? (size_t)pairs[k][1] : 0;
        all_u = all_u && ok && (qs->carried[at[sl]].bits & 2);
    }
    sinter_free(qs->ctx, pairs);
    sinter_status s = SINTER_OK;
    if (ok)
        s = sinter_grow(qs->ctx, (void **)&qs->fixed, &qs->fixed_capacity, 6 * n + 1, 1);
    if (ok && s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->f, &qs->f_capacity, 6 * n + 1, sizeof(double));
    if (ok && s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->u, &qs->u_capacity, 6 * n + 1, sizeof(double));
    if (!ok || s != SINTER_OK) {
        sinter_free(qs->ctx, at);
        if (s != SINTER_OK)
            (void)sinter_clear_error(qs->ctx); /* detected again instead */
        return 0;
    }
    for (size_t sl = 0; sl < n; ++sl) {
        if (at[sl] == SIZE_MAX) { /* a ghost (above) */
            memset(qs->fixed + 6 * sl, 0, 6);
            memset(qs->u + 6 * sl, 0, 6 * sizeof(double));
            continue;
        }
        const sinter_qs_carried *c = &qs->carried[at[sl]];
        memcpy(qs->fixed + 6 * sl, c->fixed, 6);
        if (all_u)
            memcpy(qs->u + 6 * sl, c->u, sizeof(c->u));
    }
    sinter_free(qs->ctx, at);
    qs->particles = n;
    if (!all_u)
        qs->u_step = 0.0;
    return 1;
}

void sinter_qs_global_values(const sinter_qs *qs, double f[SINTER_QS_GLOBAL_F64],
                             uint64_t u[SINTER_QS_GLOBAL_U64])
{
    memset(f, 0, SINTER_QS_GLOBAL_F64 * sizeof(double));
    memset(u, 0, SINTER_QS_GLOBAL_U64 * sizeof(uint64_t));
    if (qs == NULL)
        return;
    memcpy(f, qs->extent0, 3 * sizeof(double));
    f[3] = qs->dt_next;
    f[4] = qs->u_step;
    f[5] = qs->density0;
    memcpy(f + 6, qs->cell_lo, 3 * sizeof(double));
    memcpy(f + 9, qs->cell_len, 3 * sizeof(double));
    memcpy(f + 12, qs->cell_len0, 3 * sizeof(double));
    u[0] = 1;
    u[1] = qs->steps;
    u[2] = qs->rejected;
    u[3] = qs->pcg_iterations;
    u[4] = qs->substepped;
    u[5] = qs->particles != 0;
    u[6] = (uint64_t)(qs->periodic[0] | qs->periodic[1] << 1 | qs->periodic[2] << 2);
    u[7] = (uint64_t)qs->cell_started;
    u[8] = (uint64_t)(qs->warned_coverage | qs->warned_density << 1);
}

const char *sinter_qs_global_wrong(const double f[SINTER_QS_GLOBAL_F64],
                                   const uint64_t u[SINTER_QS_GLOBAL_U64])
{
    for (int k = 0; k < SINTER_QS_GLOBAL_F64; ++k)
        if (!isfinite(f[k]))
            return "a quasi-static value is not finite";
    if (u[0] > 1 || u[5] > 1 || u[6] > 7 || u[7] > 1 || u[8] > 3)
        return "a quasi-static flag is out of range";
    if (u[0] == 1 && (!(f[3] > 0.0) || f[4] < 0.0 || f[5] < 0.0 || f[5] >= 1.0))
        return "the quasi-static next step, displacement step or density is out of range";
    return NULL;
}

void sinter_qs_global_load(sinter_qs *qs, const double f[SINTER_QS_GLOBAL_F64],
                           const uint64_t u[SINTER_QS_GLOBAL_U64], int domain_on)
{
    memcpy(qs->extent0, f, 3 * sizeof(double));
    qs->dt_next = f[3];
    qs->u_step = f[4];
    qs->density0 = f[5];
    memcpy(qs->cell_lo, f + 6, 3 * sizeof(double));
    memcpy(qs->cell_len, f + 9, 3 * sizeof(double));
    memcpy(qs->cell_len0, f + 12, 3 * sizeof(double));
    qs->steps = u[1];
    qs->rejected = u[2];
    qs->pcg_iterations = u[3];
    qs->substepped = u[4];
    qs->particles = u[5] ? SIZE_MAX : 0; /* set up: the conditions come with the records */
    qs->dom.started = u[5] != 0;         /* and the extents and green density with this part */
    qs->dom.restored = 1;
    for (int d = 0; d < 3; ++d)
        qs->periodic[d] = (int)((u[6] >> d) & 1u);
    qs->cell_started = (int)u[7];
    qs->warned_coverage = (int)(u[8] & 1u);
    qs->warned_density = (int)(u[8] >> 1);
    /* the first set-up's extents and green density came above: a decomposed run does not
     * take them again at its next step (qs_domain.c) */
    qs->dom.started = u[5] != 0;
    /* under domain operations each link arrives with the record of its smaller id, on the
     * subdomain that owns that id, as a decomposed run keeps its links */
    if (domain_on)
        qs->dom.on = 1;
}
