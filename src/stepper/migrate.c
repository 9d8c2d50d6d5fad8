/*
 * Export and import of particles with everything the stepper keeps for them (issue 43): the
 * record stream of sinter_stepper_export / sinter_stepper_import (include/sinter.h). A host
 * that splits one body over several steppers (subdomains) moves a particle from one to another
 * with it; the receiving stepper continues the particle's contacts where the sending one left.
 *
 * Stream (host byte order, checked by a marker; all fields unaligned):
 *   "SINTERMG", u32 version, u32 marker 0x01020304, u64 total bytes, u64 records,
 *   u64 force slots, per slot: char[64] model name, u64 pp width, u64 pw width,
 *   u64 sizeof(sinter_qs_link), the records, u64 FNV-1a 64 checksum of all bytes before it.
 * Record:
 *   u64 id; f64 x[3], v[3], w[3], rot[3], force[3], torque[3], radius, mass, inertia,
 *   temperature, current, heat; f64 x, v, w, rot [3 each] and temperature at the start of the
 *   step (bit 1);
 *   i32 material; u32 flags; u64 record bits (bit 0: the electric warm start below is valid;
 *   bit 1: the particle left in the middle of an explicit step, after its drift, and the rows
 *   at the start of the step are its state at t, for a rollback on the side it enters; bit 2:
 *   it left a staggered stepper at an accepted state or between two steps (a portable
 *   checkpoint: the importer takes it at its next step, stepper.c; imported between two steps
 *   and exported again before the next, it passes on the rows it brought), and those rows hold the
 *   predictor's history, its force [3] and moment [3] of the step before, zeros [6] and its
 *   heat power of the step before; without bits 1 and 2 they repeat x, v, w, rot,
 *   temperature); f64 warm-start potential [V];
 *   per force slot: u64 count and (key_i, key_j, pp width values) of each particle-particle
 *   history entry the particle is an end of, u64 count and (id, wall, pw width values) of each
 *   particle-wall entry;
 *   u64 count and the quasi-static links whose smaller id it is (beam, neck state, neck data);
 *   from format 4 on, the quasi-static stepper's state of the particle (qs_portable.c): u64 bits,
 *   u8 plane conditions [6] and 2 zero bytes, f64 last displacements [6], f64 initial position
 *   [3] (zeros for other steppers). Format 3 (without them) is still read.
 * An entry whose two ends travel together is in both records; the importer keeps it once.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fnv1a.h"
#include "electric/electric.h"
#include "stepper/migrate.h"
#include "stepper/stepper.h"

#define MIGRATE_VERSION 4u
#define MIGRATE_VERSION_OLDEST 3u
#define MIGRATE_NAME 64
#define RECORD_F64 37
#define RECORD_FIXED (8 + 8 * RECORD_F64 + 4 + 4 + 8 + 8)

static const char MAGIC[8] = {'S', 'I', 'N', 'T', 'E', 'R', 'M', 'G'};

static size_t header_bytes(const sinter_stepper *st)
{
    return 8 + 4 + 4 + 8 + 8 + 8 + st->force_count * (MIGRATE_NAME + 16) + 8 + 8; /* + sum */
}

/* What travels with the exported particles, gathered before anything is written: one item
 * per history entry, staged entry or link, sorted by record and section. */
typedef struct item {
    uint32_t rec;     /* position in the export list */
    uint32_t section; /* 2 slot + (0 pp, 1 pw); 2 slots: a link */
    size_t seq;       /* order found (a stable sort) */
    uint64_t a, b;    /* keys */
    const void *data; /* values (width doubles) or the link */
} item;

static int item_order(const void *x, const void *y)
{
    const item *p = x, *q = y;
    if (p->rec != q->rec)
        return (p->rec > q->rec) - (p->rec < q->rec);
    if (p->section != q->section)
        return (p->section > q->section) - (p->section < q->section);
    return (p->seq > q->seq) - (p->seq < q->seq);
}

typedef struct gathered {
    size_t *pos; /* per particle index: 1 + position in the export list, 0: not exported */
    item *items;
    size_t count, capacity;
    size_t bytes; /* of the whole stream */
} gathered;

static void gathered_free(sinter_ctx *ctx, gathered *g)
{
    sinter_free(ctx, g->pos);
    sinter_free(ctx, g->items);
}

static sinter_status add_item(sinter_ctx *ctx, gathered *g, size_t rec, uint32_t section,
                              uint64_t a, uint64_t b, const void *data)
{
    sinter_status s =
        sinter_grow(ctx, (void **)&g->items, &g->capacity, g->count + 1, sizeof(item));
    if (s != SINTER_OK)
        return s;
    g->items[g->count] = (item){(uint32_t)rec, section, g->count, a, b, data};
    g->count++;
    return SINTER_OK;
}

/* The position in the export list of the particle of id `id`, or SIZE_MAX. */
static size_t rec_of(const sinter_particles *ps, const gathered *g, uint64_t id)
{
    const size_t i = sinter_id_index_find(&ps->id_index, ps, id);
    return i != SIZE_MAX && i < ps->count && g->pos[i] > 0 ? g->pos[i] - 1 : SIZE_MAX;
}

/* The entries of one history (committed over pair list L, or staged) with an exported end. */
static sinter_status gather_entries(sinter_stepper *st, gathered *g, uint32_t section, int wall,
                                    size_t w, const uint64_t *ki, const uint64_t *kj,
                                    const uint32_t *which, size_t count, const double *values)
{
    const sinter_particles *ps = st->ps;
    sinter_status s = SINTER_OK;
    for (size_t e = 0; e < count && s == SINTER_OK; ++e) {
        const size_t p = which != NULL ? which[e] : e;
        const size_t ra = rec_of(ps, g, ki[which != NULL ? p : 2 * e]);
        const uint64_t a = ki[which != NULL ? p : 2 * e];
        const uint64_t b = which != NULL ? kj[p] : ki[2 * e + 1];
        const size_t rb = wall ? SIZE_MAX : rec_of(ps, g, b);
        if (ra != SIZE_MAX)
            s = add_item(st->ctx, g, ra, section, a, b, values + w * p);
        if (s == SINTER_OK && rb != SIZE_MAX)
            s = add_item(st->ctx, g, rb, section, a, b, values + w * p);
    }
    return s;
}

/* Check the arguments of an export or a removal: pos (count + 1 zeros) receives for each
 * index listed its entry + 1. */
static sinter_status check_list(sinter_stepper *st, size_t n, const size_t *indices, size_t *pos,
                                const char *func)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    for (size_t k = 0; k < n; ++k) {
        if (indices[k] >= owned || pos[indices[k]] > 0)
            return sinter_fail(ctx, indices[k] >= owned ? SINTER_ERR_RANGE : SINTER_ERR_INVALID,
                               "%s: index %zu (entry %zu) is %s", func, indices[k], k,
                               indices[k] >= owned ? "not an owned particle" : "listed twice");
        pos[indices[k]] = k + 1;
    }
    return SINTER_OK;
}

/* The state checks of an export or a removal. */
static sinter_status check_state(sinter_stepper *st, size_t n, const size_t *indices,
                                 const char *func)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_particles *ps = st->ps;
    if (n > 0)
        SINTER_CHECK_NULL(ctx, indices);
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are out", func,
                           ps->views_out);
    if (sinter_ghosts_on(&st->ghosts))
        return sinter_fail(ctx, SINTER_ERR_UNSUPPORTED,
                           "%s: the stepper has periodic boundaries, whose images are not "
                           "migrated",
                           func);
    if (st->frozen.active)
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "%s: the frozen heat stage holds per-particle rates; migrate while "
                           "the mechanics run",
                           func);
    return SINTER_OK;
}

/* Check the arguments of an export and gather what travels; g->bytes is the stream's size. */
static sinter_status gather(sinter_stepper *st, size_t n, const size_t *indices, gathered *g,
                            const char *func)
{
    memset(g, 0, sizeof(*g));
    sinter_ctx *ctx = st->ctx;
    sinter_particles *ps = st->ps;
    sinter_status s = check_state(st, n, indices, func);
    if (s != SINTER_OK)
        return s;
    g->pos = sinter_calloc(ctx, ps->count + 1, sizeof(size_t));
    if (g->pos == NULL)
        return SINTER_ERR_NOMEM;
    if ((s = check_list(st, n, indices, g->pos, func)) != SINTER_OK) {
        gathered_free(ctx, g);
        return s;
    }
    s = n > 0 ? sinter_id_index_update(&ps->id_index, ps) : SINTER_OK;
    /* committed histories (pairs of the current lists) and staged ones, slot by slot */
    const sinter_migrate_stage *stage = st->migrate;
    for (size_t k = 0; k < st->force_count && s == SINTER_OK && n > 0; ++k) {
        const sinter_history *h[2] = {&st->forces[k].pp, &st->forces[k].pw};
        const sinter_pair_list *L[2] = {&st->nb.pp, &st->nb.pw};
        for (int wall = 0; wall < 2 && s == SINTER_OK; ++wall) {
            const size_t w = h[wall]->width;
            if (w == 0)
                continue;
            const uint32_t section = (uint32_t)(2 * k + (size_t)wall);
            if (st->nb.built && h[wall]->committed != NULL) {
                size_t count = 0; /* active pairs of the current list */
                for (size_t a = 0; a < h[wall]->active_count; ++a)
                    count += h[wall]->active[a] < L[wall]->count;
                if (count == h[wall]->active_count)
                    s = gather_entries(st, g, section, wall, w, L[wall]->key_i, L[wall]->key_j,
                                       h[wall]->active, count, h[wall]->committed);
                else
                    s = sinter_fail(ctx, SINTER_ERR_STATE,
                                    "%s: a history names a pair the "
                                    "neighbour list does not hold",
                                    func);
            }
            if (s == SINTER_OK && stage != NULL && stage->slots == st->force_count &&
                stage->width[section] == w)
                s = gather_entries(st, g, section, wall, w, stage->list[section].key, NULL, NULL,
                                   stage->list[section].count, stage->list[section].value);
        }
    }
    /* quasi-static links, in the record of their smaller id */
    if (s == SINTER_OK && st->quasistatic != NULL && n > 0) {
        size_t m = 0;
        const sinter_qs_link *links = sinter_qs_links(st->quasistatic, &m);
        for (size_t k = 0; k < m && s == SINTER_OK; ++k) {
            const uint64_t lo = links[k].id_a < links[k].id_b ? links[k].id_a : links[k].id_b;
            const size_t r = rec_of(ps, g, lo);
            if (r != SIZE_MAX)
                s = add_item(ctx, g, r, (uint32_t)(2 * st->force_count), k, 0, &links[k]);
        }
    }
    if (s != SINTER_OK) {
        gathered_free(ctx, g);
        return s;
    }
    if (g->count > 1)
        qsort(g->items, g->count, sizeof(item), item_order);
    g->bytes =
        header_bytes(st) + n * (RECORD_FIXED + 16 * st->force_count + 8 + SINTER_QS_CARRIED_BYTES);
    for (size_t e = 0; e < g->count; ++e) {
        const uint32_t sec = g->items[e].section;
        g->bytes += sec == 2 * st->force_count ? sizeof(sinter_qs_link)
                                               : 16 + 8 * (sec % 2 ? st->forces[sec / 2].pw.width
                                                                   : st->forces[sec / 2].pp.width);
    }
    return SINTER_OK;
}

sinter_status sinter_stepper_export_size(const sinter_stepper *st, size_t n, const size_t *indices,
                                         size_t *bytes)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, bytes);
    gathered g;
    /* gather only reads the stepper (the id index it builds is a cache) */
    const sinter_status s =
        gather((sinter_stepper *)st, n, indices, &g, "sinter_stepper_export_size");
    if (s != SINTER_OK)
        return s;
    *bytes = g.bytes;
    gathered_free(st->ctx, &g);
    return SINTER_OK;
}

/* 1 when the stepper's forces and histories are those of the set's current state (between two
 * steps of a run): migration keeps them so (every record carries its force and history), so
 * that the next step continues as the run would have instead of evaluating the forces again. */
static int forces_in_step(const sinter_stepper *st)
{
    return st->forces_current && st->population_generation == st->ps->population_generation &&
           st->write_generation == st->ps->write_generation;
}

/* After particles left or came: the staggered predictor's history (per particle index) is
 * dropped, and the forces stay current when they were (forces_in_step). */
static void migrated(sinter_stepper *st, int current)
{
    st->staggered.history_valid = 0;
    if (current)
        st->population_generation = st->ps->population_generation;
}

/* ---- writing ---- */

typedef struct writer {
    unsigned char *p;
} writer;

static void put(writer *w, const void *data, size_t bytes)
{
    if (bytes > 0)
        memcpy(w->p, data, bytes);
    w->p += bytes;
}

static void put_u64(writer *w, uint64_t v)
{
    put(w, &v, 8);
}

/* The potential of particle i in the electric model's warm start, if it holds one. */
static int warm_potential(const sinter_stepper *st, size_t i, double *phi)
{
    size_t nodes = 0;
    const double *warm =
        st->electric != NULL ? sinter_electric_warm_potentials(st->electric, &nodes) : NULL;
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    /* (a decomposed run exports with its ghosts there: the particle nodes are the owned rows) */
    const size_t rows = st->domain.on ? st->ps->count - st->ps->ghost_count : st->ps->count;
    if (warm == NULL || nodes != rows + nw || i >= rows)
        return 0;
    *phi = warm[i];
    return 1;
}

/* A particle imported into a staggered stepper between two steps holds its predictor history
 * among the arrivals (domain.h, arrived_*) until the next step adopts it; exported again before
 * that step (sinter_mpi_checkpoint_read sends the particles of its pieces on to their owners),
 * its record passes those rows on with bit 2, as the import took them. Sorted by id. */
typedef struct pending {
    uint64_t id;
    size_t row;
} pending;

static int pending_order(const void *x, const void *y)
{
    const uint64_t a = ((const pending *)x)->id, b = ((const pending *)y)->id;
    return (a > b) - (a < b);
}

/* The arrivals whose rows an export passes on (NULL and 0 when none; *s NOMEM on failure). */
static pending *pending_rows(sinter_stepper *st, size_t *count, sinter_status *s)
{
    const sinter_domain *d = &st->domain;
    *count = 0;
    if (st->kind != SINTER_STEPPER_STAGGERED || d->redistributing || d->in_attempt ||
        d->arrived_count == 0)
        return NULL;
    pending *p = sinter_alloc(st->ctx, d->arrived_count * sizeof(pending));
    if (p == NULL) {
        *s = SINTER_ERR_NOMEM;
        return NULL;
    }
    for (size_t k = 0; k < d->arrived_count; ++k)
        p[k] = (pending){d->arrived_id[k], k};
    qsort(p, d->arrived_count, sizeof(pending), pending_order);
    *count = d->arrived_count;
    return p;
}

static void write_stream(const sinter_stepper *st, size_t n, const size_t *indices,
                         const gathered *g, const pending *pend, size_t pend_n,
                         const uint64_t *qs_index, size_t qs_n, unsigned char *out)
{
    const sinter_particles *ps = st->ps;
    writer w = {out};
    put(&w, MAGIC, sizeof(MAGIC));
    const uint32_t version = MIGRATE_VERSION, marker = 0x01020304u;
    put(&w, &version, 4);
    put(&w, &marker, 4);
    put_u64(&w, g->bytes);
    put_u64(&w, n);
    put_u64(&w, st->force_count);
    for (size_t k = 0; k < st->force_count; ++k) {
        char name[MIGRATE_NAME] = {0};
        snprintf(name, sizeof(name), "%s", st->forces[k].model->name);
        put(&w, name, MIGRATE_NAME);
        put_u64(&w, st->forces[k].pp.width);
        put_u64(&w, st->forces[k].pw.width);
    }
    put_u64(&w, sizeof(sinter_qs_link));
    size_t e = 0;
    for (size_t r = 0; r < n; ++r) {
        const size_t i = indices[r];
        put_u64(&w, ps->id[i]);
        const double *vec[6] = {ps->x, ps->v, ps->w, ps->rot, ps->force, ps->torque};
        for (int f = 0; f < 6; ++f)
            put(&w, vec[f] + 3 * i, 3 * sizeof(double));
        const double *scalar[6] = {ps->radius,      ps->mass,    ps->inertia,
                                   ps->temperature, ps->current, ps->heat};
        for (int f = 0; f < 6; ++f)
            put(&w, scalar[f] + i, sizeof(double));
        /* the state at t: in the host's redistribution (after the drift, before any row
         * moved) the spare rows and the saved temperature */
        const int mid_step = st->domain.redistributing && st->spare[0] != NULL &&
                             ps->layout_generation == st->domain.layout_at_start;
        /* or the staggered predictor's history, at its accepted state (before any row moved),
         * or between two steps (a portable checkpoint's records: the restart continues it) */
        const sinter_staggered *sg = &st->staggered;
        const int history =
            st->domain.redistributing
                ? st->domain.keep_history && ps->layout_generation == st->domain.layout_at_start &&
                      sg->history_valid && i < sg->history_count
                : st->kind == SINTER_STEPPER_STAGGERED && !st->domain.in_attempt &&
                      sg->history_valid && sg->history_count == ps->count - ps->ghost_count &&
                      sg->h_prev > 0.0 && i < sg->history_count;
        const pending key = {ps->id[i], 0};
        const pending *hit = !history && pend_n > 0
                                 ? bsearch(&key, pend, pend_n, sizeof(pending), pending_order)
                                 : NULL;
        if (history) {
            const size_t m = sg->history_count;
            const double zero[6] = {0};
            put(&w, sg->hist + 3 * i, 3 * sizeof(double));
            put(&w, sg->hist + 3 * m + 3 * i, 3 * sizeof(double));
            put(&w, zero, sizeof(zero));
            put(&w, sg->hist + 6 * m + i, sizeof(double));
        } else if (hit != NULL) { /* (the rows as its record brought them) */
            put(&w, st->domain.arrived_rows + 13 * hit->row, 13 * sizeof(double));
        }
        for (int f = 0; f < 4 && !history && hit == NULL; ++f)
            put(&w, (mid_step && st->spare[f] != NULL ? st->spare[f] : vec[f]) + 3 * i,
                3 * sizeof(double));
        const int saved = mid_step && st->thermal.count > 0 && st->thermal.theta_backup != NULL &&
                          i < st->thermal.backup_capacity;
        if (!history && hit == NULL)
            put(&w, (saved ? st->thermal.theta_backup : ps->temperature) + i, sizeof(double));
        put(&w, ps->material + i, 4);
        put(&w, ps->flags + i, 4);
        double phi = 0.0;
        put_u64(&w, (uint64_t)warm_potential(st, i, &phi) | (uint64_t)mid_step << 1 |
                        (uint64_t)(history || hit != NULL) << 2);
        put(&w, &phi, 8);
        for (uint32_t sec = 0; sec <= 2 * st->force_count; ++sec) {
            size_t count = 0;
            while (e + count < g->count && g->items[e + count].rec == r &&
                   g->items[e + count].section == sec)
                ++count;
            put_u64(&w, count);
            for (size_t c = 0; c < count; ++c, ++e) {
                const item *it = &g->items[e];
                if (sec == 2 * st->force_count) { /* a link, its padding zeroed */
                    sinter_qs_link l;
                    memset(&l, 0, sizeof(l));
                    const sinter_qs_link *from = it->data;
                    l.beam = from->beam;
                    l.beam.a = l.beam.b = 0; /* (indices in this set only: the importer
                                              * finds the ends by id_a and id_b) */
                    l.neck = from->neck;
                    l.rm = from->rm;
                    l.youngs = from->youngs;
                    l.material = from->material;
                    l.substepped = from->substepped;
                    l.id_a = from->id_a;
                    l.id_b = from->id_b;
                    l.born = from->born;
                    put(&w, &l, sizeof(l));
                    continue;
                }
                const size_t width =
                    sec % 2 ? st->forces[sec / 2].pw.width : st->forces[sec / 2].pp.width;
                put_u64(&w, it->a);
                put_u64(&w, it->b);
                put(&w, it->data, width * sizeof(double));
            }
        }
        sinter_qs_carried c;
        sinter_qs_carried_of(st->kind == SINTER_STEPPER_QUASISTATIC ? st->quasistatic : NULL,
                             qs_index, qs_n, ps->count, i, ps->id[i], &c);
        put_u64(&w, c.bits);
        put(&w, c.fixed, sizeof(c.fixed));
        put(&w, c.u, sizeof(c.u));
        put(&w, c.origin, sizeof(c.origin));
    }
    const uint64_t sum = sinter_fnv1a(SINTER_FNV1A_START, out, (size_t)(w.p - out));
    put(&w, &sum, 8);
}

/* ---- removing the exported particles ---- */

static int id_order(const void *x, const void *y)
{
    const uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* The ids that left (sorted), for the tests below. */
typedef struct leaving {
    const uint64_t *id;
    size_t n;
    int wall;
} leaving;

static int left(const leaving *l, uint64_t id)
{
    return bsearch(&id, l->id, l->n, sizeof(uint64_t), id_order) != NULL;
}

/* The staged entries' verdicts, made before the removal, read in order by the drop. */
typedef struct verdicts {
    const unsigned char *drop;
    size_t next;
} verdicts;

static int staged_leaves(const uint64_t key[2], void *user)
{
    (void)key;
    verdicts *v = user;
    return v->drop[v->next++];
}

/* 1 when particle `id` is in the set and does not leave (the id index is current). */
static int stays(const sinter_particles *ps, const leaving *l, uint64_t id)
{
    return sinter_id_index_find(&ps->id_index, ps, id) != SIZE_MAX && !left(l, id);
}

/* The state that stays after the exported particles leave: the pairs of the current lists
 * whose ends all left made unmatchable at the next build (a pair with one end staying keeps
 * its history here: the other end's copy of the contact), the staged entries none of whose
 * ends stays a particle of the set, the
 * links that left with their smaller id, the warm-start potentials of the particles gone. */
static sinter_status remove_exported(sinter_stepper *st, size_t n, const size_t *indices)
{
    sinter_ctx *ctx = st->ctx;
    sinter_particles *ps = st->ps;
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    /* allocations and the removal first, so that a failure changes nothing */
    uint64_t *gone = sinter_alloc(ctx, (n + 1) * sizeof(uint64_t));
    size_t m = 0;
    if (st->quasistatic != NULL)
        (void)sinter_qs_links(st->quasistatic, &m);
    unsigned char *drop = sinter_calloc(ctx, m + 1, 1);
    size_t nodes = 0;
    const double *warm =
        st->electric != NULL ? sinter_electric_warm_potentials(st->electric, &nodes) : NULL;
    /* (a decomposed run removes its leavers with the ghosts still there: the warm start's
     * particle nodes are the owned rows, the walls after them) */
    const size_t rows = st->domain.on ? ps->count - ps->ghost_count : ps->count;
    const int keep_warm = warm != NULL && nodes == rows + nw;
    double *phi = keep_warm ? sinter_alloc(ctx, (nodes + 1) * sizeof(double)) : NULL;
    sinter_migrate_stage *stage = st->migrate;
    size_t staged = 0;
    for (size_t k = 0; stage != NULL && k < 2 * stage->slots; ++k)
        staged += stage->list[k].count;
    unsigned char *unheld = sinter_calloc(ctx, staged + 1, 1);
    sinter_status s = gone == NULL || drop == NULL || unheld == NULL || (keep_warm && phi == NULL)
                          ? SINTER_ERR_NOMEM
                          : SINTER_OK;
    size_t kept = 0;
    if (s == SINTER_OK) {
        for (size_t k = 0; k < n; ++k)
            gone[k] = ps->id[indices[k]];
        qsort(gone, n, sizeof(uint64_t), id_order);
        /* a staged entry stays while one of its ends stays a particle of this set (the entry
         * came with it); one whose ends are all gone would come back stale */
        const leaving l = {gone, n, 0};
        size_t e = 0;
        for (size_t k = 0; stage != NULL && k < 2 * stage->slots; ++k)
            for (size_t j = 0; j < stage->list[k].count; ++j, ++e) {
                const uint64_t *key = stage->list[k].key + 2 * j;
                unheld[e] = (unsigned char)!(stays(ps, &l, key[0]) ||
                                             (k % 2 == 0 && stays(ps, &l, key[1])));
            }
        for (size_t i = 0; keep_warm && i < nodes; ++i) {
            const int leaves = i < rows && left(&(leaving){gone, n, 0}, ps->id[i]);
            if (!leaves)
                phi[kept++] = warm[i];
        }
        s = sinter_particles_remove(ps, n, indices);
    }
    if (s != SINTER_OK) {
        sinter_free(ctx, gone);
        sinter_free(ctx, drop);
        sinter_free(ctx, phi);
        sinter_free(ctx, unheld);
        return s;
    }
    leaving l = {gone, n, 0};
    if (st->nb.built) {
        sinter_pair_list *pp = &st->nb.pp, *pw = &st->nb.pw;
        for (size_t p = 0; p < pp->count; ++p)
            if (left(&l, pp->key_i[p]) && left(&l, pp->key_j[p]))
                pp->key_i[p] = pp->key_j[p] = UINT64_MAX; /* no id is 2^64 - 1 */
        for (size_t p = 0; p < pw->count; ++p)
            if (left(&l, pw->key_i[p]))
                pw->key_i[p] = UINT64_MAX;
    }
    verdicts v = {unheld, 0};
    for (size_t k = 0; stage != NULL && k < 2 * stage->slots; ++k)
        sinter_migrate_drop(&stage->list[k], stage->width[k], staged_leaves, &v);
    if (st->quasistatic != NULL) {
        const sinter_qs_link *links = sinter_qs_links(st->quasistatic, &m);
        for (size_t k = 0; k < m; ++k)
            drop[k] = (unsigned char)left(&l, links[k].id_a < links[k].id_b ? links[k].id_a
                                                                            : links[k].id_b);
        sinter_qs_links_drop(st->quasistatic, drop);
    }
    if (st->electric != NULL) /* kept for the particles that stay, or cleared */
        s = sinter_electric_set_warm_potentials(st->electric, phi, keep_warm ? kept : 0);
    sinter_free(ctx, gone);
    sinter_free(ctx, drop);
    sinter_free(ctx, phi);
    sinter_free(ctx, unheld);
    return s;
}

/* A migration asked during the staggered stepper's fixed-point attempt (its state at t and its
 * histories are per index): refused, and made at the next accepted state (stepper.h,
 * sinter_stepper_domain_accepted_stage). */
static sinter_status refuse_in_attempt(sinter_stepper *st, const char *func)
{
    st->domain.migration_deferred = 1;
    return sinter_fail(st->ctx, SINTER_ERR_STATE,
                       "%s: the staggered stepper is inside a fixed-point attempt; the particles "
                       "stay where they are and migrate at the next accepted state",
                       func);
}

sinter_status sinter_stepper_export(sinter_stepper *st, size_t n, const size_t *indices,
                                    void *buffer, size_t capacity, size_t *written, int remove)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    SINTER_CHECK_NULL(ctx, written);
    *written = 0;
    if (remove != 0 && remove != 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_stepper_export: remove is %d, not 0 or 1", remove);
    if (remove && st->domain.in_attempt)
        return refuse_in_attempt(st, "sinter_stepper_export");
    gathered g;
    sinter_status s = gather(st, n, indices, &g, "sinter_stepper_export");
    if (s != SINTER_OK)
        return s;
    if (buffer == NULL || capacity < g.bytes) {
        s = sinter_fail(ctx, buffer == NULL ? SINTER_ERR_NULL : SINTER_ERR_RANGE,
                        "sinter_stepper_export: the records need %zu bytes, the buffer holds %zu "
                        "(sinter_stepper_export_size)",
                        g.bytes, buffer == NULL ? (size_t)0 : capacity);
        gathered_free(ctx, &g);
        return s;
    }
    size_t pend_n = 0, qs_n = 0;
    pending *pend = pending_rows(st, &pend_n, &s);
    uint64_t *qs_index = s == SINTER_OK && st->kind == SINTER_STEPPER_QUASISTATIC
                             ? sinter_qs_carried_index(st->quasistatic, ctx, &qs_n, &s)
                             : NULL;
    if (s != SINTER_OK) {
        sinter_free(ctx, pend);
        gathered_free(ctx, &g);
        return sinter_fail(ctx, s, "sinter_stepper_export: out of memory");
    }
    write_stream(st, n, indices, &g, pend, pend_n, qs_index, qs_n, buffer);
    sinter_free(ctx, pend);
    sinter_free(ctx, qs_index);
    *written = g.bytes;
    gathered_free(ctx, &g);
    if (remove && n > 0) {
        const int current = forces_in_step(st);
        s = remove_exported(st, n, indices);
        migrated(st, current && s == SINTER_OK);
    }
    return s;
}

sinter_status sinter_stepper_remove(sinter_stepper *st, size_t n, const size_t *indices)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    if (st->domain.in_attempt)
        return refuse_in_attempt(st, "sinter_stepper_remove");
    sinter_status s = check_state(st, n, indices, "sinter_stepper_remove");
    if (s != SINTER_OK || n == 0)
        return s;
    size_t *pos = sinter_calloc(ctx, st->ps->count + 1, sizeof(size_t));
    if (pos == NULL)
        return SINTER_ERR_NOMEM;
    s = check_list(st, n, indices, pos, "sinter_stepper_remove");
    sinter_free(ctx, pos);
    if (s != SINTER_OK)
        return s;
    /* what sinter_stepper_export with remove = 1 does after writing its records */
    const int current = forces_in_step(st);
    s = remove_exported(st, n, indices);
    migrated(st, current && s == SINTER_OK);
    return s;
}

/* ---- reading ---- */

typedef struct reader {
    const unsigned char *p, *end;
    int bad;
} reader;

static const unsigned char *take(reader *r, size_t bytes)
{
    if (r->bad || (size_t)(r->end - r->p) < bytes) {
        r->bad = 1;
        return NULL;
    }
    const unsigned char *at = r->p;
    r->p += bytes;
    return at;
}

static uint64_t take_u64(reader *r)
{
    uint64_t v = 0;
    const unsigned char *at = take(r, 8);
    if (at != NULL)
        memcpy(&v, at, 8);
    return v;
}

static double f64_at(const unsigned char *p, size_t k)
{
    double v;
    memcpy(&v, p + 8 * k, 8);
    return v;
}

/* A record's quasi-static state (format 4), read from at (SINTER_QS_CARRIED_BYTES). */
static void read_carried(const unsigned char *at, sinter_qs_carried *c)
{
    memcpy(&c->bits, at, 8);
    memcpy(c->fixed, at + 8, sizeof(c->fixed));
    memcpy(c->u, at + 16, sizeof(c->u));
    memcpy(c->origin, at + 16 + sizeof(c->u), sizeof(c->origin));
}

/* A record's fixed part, read. */
typedef struct fixed_part {
    uint64_t id;
    double v[RECORD_F64];
    int32_t material;
    uint32_t flags;
    uint64_t bits;
    double phi;
} fixed_part;

static void read_fixed(const unsigned char *at, fixed_part *f)
{
    memcpy(&f->id, at, 8);
    memcpy(f->v, at + 8, sizeof(f->v));
    memcpy(&f->material, at + 8 + sizeof(f->v), 4);
    memcpy(&f->flags, at + 12 + sizeof(f->v), 4);
    memcpy(&f->bits, at + 16 + sizeof(f->v), 8);
    memcpy(&f->phi, at + 24 + sizeof(f->v), 8);
}

/* Why a record's numbers are unusable, or NULL. */
static const char *fixed_wrong(const fixed_part *f, const sinter_particles *ps)
{
    if (f->id == UINT64_MAX)
        return "its id is 2^64 - 1, which no particle has";
    for (int k = 0; k < RECORD_F64; ++k)
        if (!isfinite(f->v[k]))
            return "a field is not finite";
    if (!(f->v[18] > 0.0) || !(f->v[19] > 0.0) || !(f->v[20] > 0.0) || !(f->v[21] > 0.0))
        return "its radius, mass, inertia or temperature is not > 0";
    if (f->material < 0 || f->material >= SINTER_MAX_MATERIALS || !ps->material_used[f->material])
        return "its material is not registered in this particle set";
    if (f->bits > 7 || (f->bits & 6) == 6 || !isfinite(f->phi))
        return "its electric warm start is malformed";
    return NULL;
}

/* Why a link's numbers are unusable, or NULL (the checks of a checkpoint's links). */
static const char *link_wrong(const sinter_qs_link *l, uint64_t id)
{
    if ((l->id_a < l->id_b ? l->id_a : l->id_b) != id || l->id_a == l->id_b)
        return "a quasi-static link is not one of the particle's own (its smaller id)";
    return sinter_qs_link_numbers_wrong(l);
}

/* The parsed stream: where each record starts, how many entries each section holds. */
typedef struct parsed {
    size_t records;
    const unsigned char **at; /* per record */
    uint64_t *ids;            /* sorted, for the repeat test */
    size_t *entries;          /* per section (2 per slot), all records together */
    size_t links;
    uint32_t version;
    sinter_qs_carried *carried; /* per record (format 4 on a quasi-static stepper), or NULL */
} parsed;

static void parsed_free(sinter_ctx *ctx, parsed *p)
{
    sinter_free(ctx, p->at);
    sinter_free(ctx, p->ids);
    sinter_free(ctx, p->entries);
    sinter_free(ctx, p->carried);
}

/* Check a stream against the stepper: SINTER_ERR_CORRUPT (not a stream, damaged), or
 * SINTER_ERR_INVALID (a stream for another stepper, an id held, a material missing). */
static sinter_status parse(sinter_stepper *st, const unsigned char *data, size_t bytes, parsed *p)
{
    sinter_ctx *ctx = st->ctx;
    sinter_particles *ps = st->ps;
    const char *F = "sinter_stepper_import";
    memset(p, 0, sizeof(*p));
    reader r = {data, data + bytes, 0};
    const unsigned char *magic = take(&r, 8);
    if (magic == NULL || memcmp(magic, MAGIC, 8) != 0)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the buffer is not a record stream of "
                           "sinter_stepper_export",
                           F);
    uint32_t version = 0, marker = 0;
    const unsigned char *vm = take(&r, 8);
    if (vm != NULL) {
        memcpy(&version, vm, 4);
        memcpy(&marker, vm + 4, 4);
    }
    if (marker != 0x01020304u)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the records were written in another byte order", F);
    if (version < MIGRATE_VERSION_OLDEST || version > MIGRATE_VERSION)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the records are of format %u; this build reads formats %u to %u", F,
                           version, MIGRATE_VERSION_OLDEST, MIGRATE_VERSION);
    const uint64_t total = take_u64(&r);
    if (r.bad || total != bytes || bytes < header_bytes(st) - st->force_count * (MIGRATE_NAME + 16))
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the stream says %llu bytes but %zu were given (truncated?)", F,
                           (unsigned long long)total, bytes);
    uint64_t sum;
    memcpy(&sum, data + bytes - 8, 8);
    if (sinter_fnv1a(SINTER_FNV1A_START, data, bytes - 8) != sum)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the records' checksum does not match "
                           "(the buffer is damaged)",
                           F);
    r.end = data + bytes - 8;
    const uint64_t records = take_u64(&r), slots = take_u64(&r);
    if (r.bad || slots != st->force_count)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the records are of a stepper with %llu force models; this one "
                           "has %zu",
                           F, (unsigned long long)slots, st->force_count);
    for (size_t k = 0; k < st->force_count; ++k) {
        const unsigned char *name = take(&r, MIGRATE_NAME);
        const uint64_t wpp = take_u64(&r), wpw = take_u64(&r);
        char here[MIGRATE_NAME] = {0};
        snprintf(here, sizeof(here), "%s", st->forces[k].model->name);
        if (r.bad || memcmp(name, here, MIGRATE_NAME) != 0 || wpp != st->forces[k].pp.width ||
            wpw != st->forces[k].pw.width)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: force model %zu of the records is not this stepper's '%s' "
                               "with history widths %zu and %zu",
                               F, k, here, st->forces[k].pp.width, st->forces[k].pw.width);
    }
    const uint64_t link_size = take_u64(&r);
    if (r.bad || records > bytes / RECORD_FIXED)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the stream is shorter than its %llu "
                           "records",
                           F, (unsigned long long)records);
    p->records = (size_t)records;
    p->at = sinter_calloc(ctx, p->records + 1, sizeof(*p->at));
    p->ids = sinter_calloc(ctx, p->records + 1, sizeof(uint64_t));
    p->entries = sinter_calloc(ctx, 2 * st->force_count + 1, sizeof(size_t));
    p->version = version;
    const int qs = version >= 4 && st->kind == SINTER_STEPPER_QUASISTATIC;
    if (qs)
        p->carried = sinter_calloc(ctx, p->records + 1, sizeof(sinter_qs_carried));
    if (p->at == NULL || p->ids == NULL || p->entries == NULL || (qs && p->carried == NULL)) {
        parsed_free(ctx, p);
        return SINTER_ERR_NOMEM;
    }
    sinter_status s = sinter_id_index_update(&ps->id_index, ps);
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    const char *why = NULL;
    int invalid = 0; /* a stream that is sound but does not fit this stepper */
    size_t bad = 0;
    for (size_t k = 0; k < p->records && s == SINTER_OK && why == NULL; ++k) {
        bad = k;
        p->at[k] = take(&r, RECORD_FIXED);
        if (p->at[k] == NULL) {
            why = "the stream ends inside a record";
            break;
        }
        fixed_part f;
        read_fixed(p->at[k], &f);
        p->ids[k] = f.id;
        if ((why = fixed_wrong(&f, ps)) != NULL) {
            invalid = f.id != UINT64_MAX && f.material >= 0 && f.material < SINTER_MAX_MATERIALS;
            break;
        }
        if (sinter_id_index_find(&ps->id_index, ps, f.id) != SIZE_MAX) {
            why = "its id is held by a particle of this set already";
            invalid = 1;
            break;
        }
        for (size_t sec = 0; sec < 2 * st->force_count && why == NULL; ++sec) {
            const uint64_t count = take_u64(&r);
            const size_t w = sec % 2 ? st->forces[sec / 2].pw.width : st->forces[sec / 2].pp.width;
            if (r.bad || count > bytes / (16 + 8 * w)) {
                why = "the stream ends inside a record's contact history";
                break;
            }
            p->entries[sec] += (size_t)count;
            for (uint64_t e = 0; e < count && why == NULL; ++e) {
                const uint64_t a = take_u64(&r), b = take_u64(&r);
                const unsigned char *v = take(&r, 8 * w);
                if (v == NULL)
                    why = "the stream ends inside a record's contact history";
                else if (sec % 2 ? a != f.id || b >= nw : (a != f.id && b != f.id) || a == b)
                    why = sec % 2 ? "a wall contact names another particle or a wall this "
                                    "stepper does not have"
                                  : "a contact history entry does not name the particle";
                for (size_t d = 0; d < w && why == NULL; ++d)
                    if (!isfinite(f64_at(v, d)))
                        why = "a contact history value is not finite";
                invalid = why != NULL && sec % 2 && a == f.id && b >= nw;
            }
        }
        const uint64_t links = take_u64(&r);
        if (why == NULL && (r.bad || (links > 0 && link_size != sizeof(sinter_qs_link)) ||
                            links > bytes / sizeof(sinter_qs_link)))
            why = "its quasi-static links do not fit the stream or this build's link layout";
        if (why == NULL && links > 0 && st->kind != SINTER_STEPPER_QUASISTATIC) {
            why = "it carries quasi-static links, and this stepper is not quasi-static";
            invalid = 1;
        }
        for (uint64_t e = 0; e < links && why == NULL; ++e) {
            const unsigned char *at = take(&r, sizeof(sinter_qs_link));
            sinter_qs_link l;
            if (at == NULL) {
                why = "the stream ends inside a record's links";
                break;
            }
            memcpy(&l, at, sizeof(l));
            why = link_wrong(&l, f.id);
        }
        p->links += (size_t)links;
        if (why == NULL && version >= 4) {
            const unsigned char *at = take(&r, SINTER_QS_CARRIED_BYTES);
            sinter_qs_carried c;
            if (at == NULL)
                why = "the stream ends inside a record's quasi-static state";
            else {
                read_carried(at, &c);
                why = sinter_qs_carried_wrong(&c);
                if (why == NULL && c.bits != 0 && !qs) {
                    why = "it carries a quasi-static state, and this stepper is not quasi-static";
                    invalid = 1;
                }
                if (why == NULL && qs)
                    p->carried[k] = c;
            }
        }
    }
    if (s == SINTER_OK && why == NULL && r.p != r.end) {
        why = "the stream is longer than its records";
        bad = p->records;
    }
    if (s == SINTER_OK && why == NULL) { /* ids repeated within the stream */
        qsort(p->ids, p->records, sizeof(uint64_t), id_order);
        for (size_t k = 1; k < p->records && why == NULL; ++k)
            if (p->ids[k] == p->ids[k - 1]) {
                const unsigned long long id = (unsigned long long)p->ids[k];
                parsed_free(ctx, p);
                return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: two records have the id %llu", F,
                                   id);
            }
    }
    if (s == SINTER_OK && why != NULL)
        s = sinter_fail(ctx, invalid ? SINTER_ERR_INVALID : SINTER_ERR_CORRUPT,
                        "%s: record %zu (id %llu): %s", F, bad,
                        (unsigned long long)(bad < p->records ? p->ids[bad] : 0), why);
    if (s != SINTER_OK)
        parsed_free(ctx, p);
    return s;
}

/* The warm start after the import: the set's potentials, the records', the walls' (NULL when
 * the set's or a record's is missing: the next solve then starts from 0; an empty set without
 * one takes the records' with its walls' from 0). */
static double *warm_after(sinter_stepper *st, const parsed *p, size_t owned)
{
    size_t nodes = 0;
    const double *warm =
        st->electric != NULL ? sinter_electric_warm_potentials(st->electric, &nodes) : NULL;
    const size_t nw = st->walls != NULL ? st->walls->count : 0;
    const int empty = owned == 0 && (warm == NULL || nodes == nw); /* a set filled by imports */
    if (st->electric == NULL || (!empty && (warm == NULL || nodes != owned + nw)))
        return NULL;
    double *phi = sinter_calloc(st->ctx, owned + nw + p->records + 1, sizeof(double));
    if (phi == NULL)
        return NULL;
    if (owned > 0)
        memcpy(phi, warm, owned * sizeof(double));
    for (size_t k = 0; k < p->records; ++k) {
        fixed_part f;
        read_fixed(p->at[k], &f);
        if (!(f.bits & 1)) {
            sinter_free(st->ctx, phi);
            return NULL;
        }
        phi[owned + k] = f.phi;
    }
    if (warm != NULL) /* the walls' (an empty set without a warm start: from 0) */
        memcpy(phi + owned + p->records, warm + owned, nw * sizeof(double));
    return phi;
}

sinter_status sinter_stepper_import(sinter_stepper *st, const void *buffer, size_t bytes,
                                    size_t *count)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    SINTER_CHECK_NULL(ctx, buffer);
    if (count != NULL)
        *count = 0;
    sinter_particles *ps = st->ps;
    const char *F = "sinter_stepper_import";
    if (st->domain.in_attempt)
        return refuse_in_attempt(st, F);
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are out", F, ps->views_out);
    if (sinter_ghosts_on(&st->ghosts))
        return sinter_fail(ctx, SINTER_ERR_UNSUPPORTED,
                           "%s: the stepper has periodic boundaries, whose images are not "
                           "migrated",
                           F);
    if (st->frozen.active)
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "%s: the frozen heat stage holds per-particle rates; migrate while "
                           "the mechanics run",
                           F);
    parsed p;
    sinter_status s = parse(st, buffer, bytes, &p);
    if (s != SINTER_OK)
        return s;
    const int current = forces_in_step(st);
    const size_t owned = ps->count - ps->ghost_count, nw = st->walls ? st->walls->count : 0;
    /* everything that can fail first: room in the set, the stage, the links */
    sinter_migrate_stage *stage = NULL;
    sinter_qs_link *links = NULL;
    s = sinter_particles_reserve(ps, owned + p.records + 1);
    if (s == SINTER_OK && (stage = sinter_migrate_stage_get(st)) == NULL)
        s = SINTER_ERR_NOMEM;
    size_t most = 0; /* entries of the fullest list after the import */
    for (size_t sec = 0; sec < 2 * st->force_count && s == SINTER_OK; ++sec) {
        s = sinter_migrate_reserve(ctx, &stage->list[sec], stage->width[sec], p.entries[sec]);
        const size_t after = stage->list[sec].count + p.entries[sec];
        most = after > most ? after : most;
    }
    /* scratch for dropping the second copy of a contact both of whose ends came */
    const size_t slots = sinter_migrate_dedupe_slots(most);
    uint32_t *table = s == SINTER_OK ? sinter_alloc(ctx, slots * sizeof(uint32_t)) : NULL;
    if (s == SINTER_OK && table == NULL)
        s = SINTER_ERR_NOMEM;
    if (s == SINTER_OK && p.links > 0) {
        links = sinter_alloc(ctx, p.links * sizeof(sinter_qs_link));
        if (links == NULL)
            s = SINTER_ERR_NOMEM;
        if (s == SINTER_OK && st->quasistatic == NULL)
            s = sinter_qs_create(&st->quasistatic, ctx, &st->quasistatic_options);
    }
    /* in the host's redistribution: room for the arrivals' state at t (redistribute.c); into
     * a staggered stepper between steps: their predictor history (stepper.c, adopted at the
     * next step) */
    sinter_domain *dom = &st->domain;
    const int keep_arrivals = dom->redistributing || st->kind == SINTER_STEPPER_STAGGERED;
    if (s == SINTER_OK && keep_arrivals)
        s = sinter_grow(ctx, (void **)&dom->arrived_id, &dom->arrived_id_capacity,
                        dom->arrived_count + p.records + 1, sizeof(uint64_t));
    if (s == SINTER_OK && keep_arrivals)
        s = sinter_grow(ctx, (void **)&dom->arrived_rows, &dom->arrived_rows_capacity,
                        13 * (dom->arrived_count + p.records) + 1, sizeof(double));
    if (s == SINTER_OK && p.carried != NULL && p.records > 0) { /* kept by id (qs_portable.c) */
        if (st->quasistatic == NULL)
            s = sinter_qs_create(&st->quasistatic, ctx, &st->quasistatic_options);
        uint64_t *ids = s == SINTER_OK ? sinter_alloc(ctx, p.records * sizeof(uint64_t)) : NULL;
        if (s == SINTER_OK && ids == NULL)
            s = SINTER_ERR_NOMEM;
        for (size_t k = 0; s == SINTER_OK && k < p.records; ++k)
            memcpy(&ids[k], p.at[k], 8);
        if (s == SINTER_OK)
            s = sinter_qs_carried_add(st->quasistatic, ids, p.carried, p.records);
        sinter_free(ctx, ids);
    }
    double *phi = s == SINTER_OK ? warm_after(st, &p, owned) : NULL;
    if (s == SINTER_OK && p.links > 0) { /* the links, in the stream's order */
        size_t m = 0;
        for (size_t k = 0; k < p.records; ++k) {
            reader r = {p.at[k] + RECORD_FIXED, (const unsigned char *)buffer + bytes - 8, 0};
            for (size_t sec = 0; sec < 2 * st->force_count; ++sec) {
                const uint64_t n = take_u64(&r);
                const size_t w =
                    sec % 2 ? st->forces[sec / 2].pw.width : st->forces[sec / 2].pp.width;
                (void)take(&r, (size_t)n * (16 + 8 * w));
            }
            const uint64_t n = take_u64(&r);
            if (n > 0)
                memcpy(links + m, take(&r, (size_t)n * sizeof(sinter_qs_link)),
                       (size_t)n * sizeof(sinter_qs_link));
            m += (size_t)n;
        }
        size_t added = 0;
        s = sinter_qs_links_insert(st->quasistatic, links, p.links, &added);
    }
    sinter_free(ctx, links);
    if (s != SINTER_OK) {
        sinter_free(ctx, table);
        sinter_free(ctx, phi);
        parsed_free(ctx, &p);
        return s;
    }
    /* Nothing can fail from here on: the particles appended, owned, ghosts after them (they
     * come back at the next neighbour build), their histories staged. */
    sinter_particles_drop_ghosts(ps);
    for (size_t k = 0; k < p.records; ++k) {
        const size_t i = owned + k;
        fixed_part f;
        read_fixed(p.at[k], &f);
        double *vec[6] = {ps->x, ps->v, ps->w, ps->rot, ps->force, ps->torque};
        for (int d = 0; d < 6; ++d)
            memcpy(vec[d] + 3 * i, f.v + 3 * d, 3 * sizeof(double));
        double *scalar[6] = {ps->radius,      ps->mass,    ps->inertia,
                             ps->temperature, ps->current, ps->heat};
        for (int d = 0; d < 6; ++d)
            scalar[d][i] = f.v[18 + d];
        /* left its side after the drift (its state at t), or at a staggered stepper's accepted
         * state (its predictor history): kept by id for the redistribution stage */
        if (dom->redistributing ? (f.bits & 6) != 0 : keep_arrivals && (f.bits & 4) != 0) {
            dom->arrived_id[dom->arrived_count] = f.id;
            memcpy(dom->arrived_rows + 13 * dom->arrived_count, f.v + 24, 13 * sizeof(double));
            dom->arrived_count++;
        }
        ps->material[i] = f.material;
        ps->flags[i] = f.flags;
        ps->id[i] = f.id;
        if (f.id >= ps->next_id)
            ps->next_id = f.id + 1;
        reader r = {p.at[k] + RECORD_FIXED, (const unsigned char *)buffer + bytes - 8, 0};
        for (size_t sec = 0; sec < 2 * st->force_count; ++sec) {
            const uint64_t n = take_u64(&r);
            const size_t w = stage->width[sec];
            for (uint64_t e = 0; e < n; ++e) {
                const uint64_t a = take_u64(&r), b = take_u64(&r);
                const unsigned char *at = take(&r, 8 * w);
                sinter_migrate_entries *l = &stage->list[sec]; /* room reserved above */
                l->key[2 * l->count] = a;
                l->key[2 * l->count + 1] = b;
                if (w > 0)
                    memcpy(l->value + w * l->count, at, 8 * w);
                l->count++;
            }
        }
    }
    for (size_t sec = 0; sec < 2 * st->force_count; ++sec)
        sinter_migrate_dedupe(&stage->list[sec], stage->width[sec], table, slots);
    sinter_free(ctx, table);
    ps->count = owned + p.records;
    ps->layout_generation++;
    ps->population_generation++;
    if (st->electric != NULL) {
        if (sinter_electric_set_warm_potentials(st->electric, phi, phi ? ps->count + nw : 0) !=
            SINTER_OK) {
            (void)sinter_clear_error(ctx); /* a warm start only: the next solve starts from 0 */
            (void)sinter_electric_set_warm_potentials(st->electric, NULL, 0);
        }
    }
    if (st->quasistatic != NULL)
        sinter_qs_particles_back(st->quasistatic, ps->count, ps->id, ps->population_generation);
    migrated(st, current);
    if (count != NULL)
        *count = p.records;
    sinter_free(ctx, phi);
    parsed_free(ctx, &p);
    return SINTER_OK;
}
