/*
 * Snapshots of a stepper's contacts and quasi-static links (sinter_snapshot_create).
 *
 * Nothing is recorded while the stepper steps: the contact law sums its forces into the
 * particles and keeps no per-contact record (that is what makes it fast), so the snapshot forms
 * every per-contact quantity again from the state, the contact lists and the committed history.
 *
 *  - Geometry: sinter_pp_geometry from the centres (the lists' own formula), the wall lists'
 *    geometry as found.
 *  - Forces: every force model with contacts is evaluated again with the tangential springs'
 *    committed values and no increment (dt 0: the committed spring is the one the last force
 *    used), on sub-lists in which no particle has two contacts ("rounds"), so that the force a
 *    model adds to a particle in a round is that of its one contact. The explicit stepper's
 *    last force read the half-step velocities: they are formed again as v - lag F / m (lag =
 *    h / 2, stepper.h eval_lag), so that the contacts' forces sum to the wall reactions and
 *    the particles' forces to round-off.
 *  - Heat: the conduction models in their implicit form give the conductance G of each contact
 *    (heat_model.h), Q = G (theta_b - theta_a) into a.
 *  - Current: I = G (phi_a - phi_b) of the "network" model's last solve (network.c's edges).
 */
#include <math.h>
#include <string.h>

#include "contact/snapshot.h"
#include "contact/contacts.h"
#include "electric/electric.h"
#include "force/force_model.h"
#include "heat/heat_model.h"
#include "neck/neck.h"
#include "stepper/qs_struct.h"
#include "stepper/stepper.h"

static const double PI_ = 3.14159265358979323846;

struct sinter_snapshot {
    sinter_ctx *ctx;
    double time;
    size_t pairs, walls, links;
    /* every array, by its sinter_contact_data and sinter_link_data (owned) */
    void *contact[SINTER_CONTACT_DATA_COUNT_];
    void *link[SINTER_LINK_DATA_COUNT_];
    /* the same arrays by name: contacts (pairs then walls) */
    uint64_t *id_a, *id_b;
    int32_t *wall;
    double *normal, *overlap, *radius, *area, *fn, *ft, *heat, *current;
    /* links */
    uint64_t *link_a, *link_b;
    int32_t *phase;
    double *neck, *ratio, *approach, *age, *fsint, *beam_force, *beam_moment, *correction;
};

/* Components and element type of each array. */
typedef struct layout {
    size_t components;
    sinter_dtype dtype;
} layout;

#define D1_                                                                                        \
    {                                                                                              \
        1, SINTER_DTYPE_DOUBLE                                                                     \
    }
#define D3_                                                                                        \
    {                                                                                              \
        3, SINTER_DTYPE_DOUBLE                                                                     \
    }
#define U64_                                                                                       \
    {                                                                                              \
        1, SINTER_DTYPE_UINT64                                                                     \
    }
#define I32_                                                                                       \
    {                                                                                              \
        1, SINTER_DTYPE_INT32                                                                      \
    }
static const layout CONTACT_LAYOUT[SINTER_CONTACT_DATA_COUNT_] = {U64_, U64_, I32_, D3_, D1_, D1_,
                                                                  D1_,  D1_,  D3_,  D1_, D1_};
static const layout LINK_LAYOUT[SINTER_LINK_DATA_COUNT_] = {U64_, U64_, D1_, D1_, D1_, D1_,
                                                            I32_, D1_,  D3_, D3_, D1_};
#undef D1_
#undef D3_
#undef U64_
#undef I32_

static size_t dtype_size(sinter_dtype dtype)
{
    return dtype == SINTER_DTYPE_DOUBLE || dtype == SINTER_DTYPE_UINT64 ? 8 : 4;
}

void sinter_snapshot_destroy(sinter_snapshot *s)
{
    if (s == NULL)
        return;
    for (int q = 0; q < SINTER_CONTACT_DATA_COUNT_; ++q)
        sinter_free(s->ctx, s->contact[q]);
    for (int q = 0; q < SINTER_LINK_DATA_COUNT_; ++q)
        sinter_free(s->ctx, s->link[q]);
    sinter_free(s->ctx, s);
}

/* Room for the records of s (count contacts, links links); every array or none. */
static sinter_status snapshot_alloc(sinter_snapshot *s, size_t count, size_t links)
{
    int ok = 1;
    for (int q = 0; q < SINTER_CONTACT_DATA_COUNT_; ++q) {
        const layout *l = &CONTACT_LAYOUT[q];
        s->contact[q] = sinter_calloc(s->ctx, (count + 1) * l->components, dtype_size(l->dtype));
        ok = ok && s->contact[q] != NULL;
    }
    for (int q = 0; q < SINTER_LINK_DATA_COUNT_; ++q) {
        const layout *l = &LINK_LAYOUT[q];
        s->link[q] = sinter_calloc(s->ctx, (links + 1) * l->components, dtype_size(l->dtype));
        ok = ok && s->link[q] != NULL;
    }
    if (!ok)
        return SINTER_ERR_NOMEM;
    void *const *c = s->contact, *const *k = s->link;
    s->id_a = c[SINTER_CONTACT_DATA_ID_A];
    s->id_b = c[SINTER_CONTACT_DATA_ID_B];
    s->wall = c[SINTER_CONTACT_DATA_WALL];
    s->normal = c[SINTER_CONTACT_DATA_NORMAL];
    s->overlap = c[SINTER_CONTACT_DATA_OVERLAP];
    s->radius = c[SINTER_CONTACT_DATA_RADIUS];
    s->area = c[SINTER_CONTACT_DATA_AREA];
    s->fn = c[SINTER_CONTACT_DATA_NORMAL_FORCE];
    s->ft = c[SINTER_CONTACT_DATA_TANGENTIAL_FORCE];
    s->heat = c[SINTER_CONTACT_DATA_HEAT_FLOW];
    s->current = c[SINTER_CONTACT_DATA_CURRENT];
    s->link_a = k[SINTER_LINK_DATA_ID_A];
    s->link_b = k[SINTER_LINK_DATA_ID_B];
    s->neck = k[SINTER_LINK_DATA_NECK_RADIUS];
    s->ratio = k[SINTER_LINK_DATA_NECK_RATIO];
    s->approach = k[SINTER_LINK_DATA_APPROACH];
    s->age = k[SINTER_LINK_DATA_AGE];
    s->phase = k[SINTER_LINK_DATA_PHASE];
    s->fsint = k[SINTER_LINK_DATA_SINTERING_FORCE];
    s->beam_force = k[SINTER_LINK_DATA_BEAM_FORCE];
    s->beam_moment = k[SINTER_LINK_DATA_BEAM_MOMENT];
    s->correction = k[SINTER_LINK_DATA_CORRECTION];
    return SINTER_OK;
}

/* The lists the re-evaluations run on: a copy of the stepper's pair list with its geometry,
 * and of its wall list, neither partitioned (the laws then take one thread, in list order). */
typedef struct lists {
    sinter_contact_list pp, pw;         /* the whole lists, with geometry */
    sinter_contact_list sub_pp, sub_pw; /* one round's contacts */
    sinter_contact_list none;           /* empty */
} lists;

static void list_free(sinter_ctx *ctx, sinter_contact_list *c)
{
    void *arrays[] = {c->i, c->j, c->pair, c->n, c->delta, c->dist, c->area, c->branch};
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); ++k)
        sinter_free(ctx, arrays[k]);
    memset(c, 0, sizeof(*c));
}

static sinter_status list_alloc(sinter_ctx *ctx, sinter_contact_list *c, size_t count)
{
    memset(c, 0, sizeof(*c));
    const size_t n = count + 1;
    c->capacity = count;
    c->i = sinter_calloc(ctx, n, sizeof(uint32_t));
    c->j = sinter_calloc(ctx, n, sizeof(uint32_t));
    c->pair = sinter_calloc(ctx, n, sizeof(uint32_t));
    c->n = sinter_calloc(ctx, 3 * n, sizeof(double));
    c->delta = sinter_calloc(ctx, n, sizeof(double));
    c->dist = sinter_calloc(ctx, n, sizeof(double));
    c->area = sinter_calloc(ctx, n, sizeof(double));
    c->branch = sinter_calloc(ctx, n, sizeof(double));
    c->geometry = 1;
    c->ascending = 1;
    c->revision = sinter_unique_id();
    if (c->i && c->j && c->pair && c->n && c->delta && c->dist && c->area && c->branch)
        return SINTER_OK;
    list_free(ctx, c);
    return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_snapshot_create: out of memory");
}

/* Contact k of `from` as contact m of `to`. */
static void list_put(sinter_contact_list *to, size_t m, const sinter_contact_list *from, size_t k)
{
    to->i[m] = from->i[k];
    to->j[m] = from->j[k];
    to->pair[m] = from->pair[k];
    memcpy(to->n + 3 * m, from->n + 3 * k, 3 * sizeof(double));
    to->delta[m] = from->delta[k];
    to->dist[m] = from->dist[k];
    to->area[m] = from->area[k];
    to->branch[m] = from->branch[k];
}

/* The stepper's pair contacts with their geometry (an unconfirmed list's ended contacts left
 * out by the search's own test), and its wall contacts. */
static sinter_status lists_make(const sinter_stepper *st, lists *L)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_particles *ps = st->ps;
    const sinter_contact_list *pp = &st->pp, *pw = &st->pw;
    sinter_status s = list_alloc(ctx, &L->pp, pp->count);
    if (s == SINTER_OK)
        s = list_alloc(ctx, &L->pw, pw->count);
    if (s == SINTER_OK)
        s = list_alloc(ctx, &L->sub_pp, pp->count);
    if (s == SINTER_OK)
        s = list_alloc(ctx, &L->sub_pw, pw->count);
    if (s == SINTER_OK)
        s = list_alloc(ctx, &L->none, 0);
    if (s != SINTER_OK)
        return s;
    const double *x = ps->x, *r = ps->radius;
    size_t m = 0;
    for (size_t k = 0; k < pp->count; ++k) {
        const uint32_t i = pp->i[k], j = pp->j[k];
        const sinter_pp_geom g =
            sinter_pp_geometry(x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                               x[3 * j + 2] - x[3 * i + 2], r[i], r[j]);
        if (pp->unconfirmed && !(g.d < r[i] + r[j] && g.d != 0.0))
            continue;
        const double a2 = r[i] * r[i] - g.li * g.li;
        L->pp.i[m] = i;
        L->pp.j[m] = j;
        L->pp.pair[m] = pp->pair[k];
        L->pp.n[3 * m] = g.nx;
        L->pp.n[3 * m + 1] = g.ny;
        L->pp.n[3 * m + 2] = g.nz;
        L->pp.delta[m] = g.delta;
        L->pp.dist[m] = g.d;
        L->pp.area[m] = PI_ * (a2 > 0.0 ? a2 : 0.0);
        L->pp.branch[m] = g.li;
        ++m;
    }
    L->pp.count = L->pp.pair_count = m;
    for (size_t k = 0; k < pw->count; ++k)
        list_put(&L->pw, k, pw, k);
    L->pw.count = L->pw.pair_count = pw->count;
    return SINTER_OK;
}

static void lists_free(sinter_ctx *ctx, lists *L)
{
    list_free(ctx, &L->pp);
    list_free(ctx, &L->pw);
    list_free(ctx, &L->sub_pp);
    list_free(ctx, &L->sub_pw);
    list_free(ctx, &L->none);
}

/* Scratch of the force re-evaluation. */
typedef struct force_work {
    sinter_particles *view; /* a shallow copy of the set with the velocities the law saw */
    double *v, *w;          /* those velocities */
    double *force, *torque; /* 3 per particle */
    double *wall_force;     /* 3 per wall, then 3 per wall of moments */
    uint32_t *round;        /* per particle: the last round that took it */
    int32_t *done;          /* per contact: 1 once evaluated */
} force_work;

/* Evaluate the contact models on the round's lists e->pp, e->pw into w->force (zeroed at the
 * round's particles first). */
static sinter_status eval_round(const sinter_stepper *st, sinter_force_eval *e, force_work *w)
{
    sinter_ctx *ctx = st->ctx;
    for (size_t q = 0; q < e->pp->count; ++q) {
        memset(w->force + 3 * (size_t)e->pp->i[q], 0, 3 * sizeof(double));
        memset(w->force + 3 * (size_t)e->pp->j[q], 0, 3 * sizeof(double));
    }
    for (size_t q = 0; q < e->pw->count; ++q)
        memset(w->force + 3 * (size_t)e->pw->i[q], 0, 3 * sizeof(double));
    for (size_t k = 0; k < st->force_count; ++k) {
        const sinter_force_slot *slot = &st->forces[k];
        const sinter_force_model *fm = slot->model;
        if (!fm->ops->uses_contacts)
            continue;
        /* the committed history, read only; trial history into scratch of our own */
        sinter_history hp = {0}, hw = {0};
        hp.width = slot->pp.width;
        hp.committed = slot->pp.committed;
        hp.pair_capacity = slot->pp.pair_capacity;
        hw.width = slot->pw.width;
        hw.committed = slot->pw.committed;
        hw.pair_capacity = slot->pw.pair_capacity;
        const int host = fm->ops->eval == sinter_force_host_eval;
        sinter_status s = sinter_history_prepare(ctx, &hp, e->pp->count, host);
        if (s == SINTER_OK)
            s = sinter_history_prepare(ctx, &hw, e->pw->count, host);
        e->hist_pp = &hp;
        e->hist_pw = &hw;
        e->pp_ended = SIZE_MAX;
        if (s == SINTER_OK)
            s = fm->ops->eval(fm, e);
        sinter_free(ctx, hp.trial);
        sinter_free(ctx, hw.trial);
        if (s != SINTER_OK)
            return s;
    }
    return SINTER_OK;
}

/* Split the force f on particle a of contact q (normal n from a) into the record. */
static void put_force(sinter_snapshot *s, size_t q, const double *n, const double *f)
{
    const double fn = -(f[0] * n[0] + f[1] * n[1] + f[2] * n[2]);
    s->fn[q] = fn;
    for (int d = 0; d < 3; ++d)
        s->ft[3 * q + (size_t)d] = f[d] + fn * n[d];
}

/*
 * Contacts `all` (pair or wall contacts, records from `first` on) in rounds: each round takes
 * every contact left whose particles no earlier contact of the round took.
 */
static sinter_status forces_of(const sinter_stepper *st, sinter_snapshot *snap,
                               sinter_force_eval *e, force_work *w, lists *L, int walls)
{
    const sinter_contact_list *all = walls ? &L->pw : &L->pp;
    sinter_contact_list *sub = walls ? &L->sub_pw : &L->sub_pp;
    const size_t first = walls ? L->pp.count : 0;
    e->pp = walls ? &L->none : sub;
    e->pw = walls ? sub : &L->none;
    memset(w->done, 0, (all->count + 1) * sizeof(int32_t));
    memset(w->round, 0, (st->ps->count + 1) * sizeof(uint32_t));
    size_t left = all->count;
    for (uint32_t round = 1; left > 0; ++round) {
        size_t m = 0;
        for (size_t q = 0; q < all->count; ++q) {
            if (w->done[q])
                continue;
            const uint32_t i = all->i[q], j = all->j[q];
            if (w->round[i] == round || (!walls && w->round[j] == round))
                continue;
            w->round[i] = round;
            if (!walls)
                w->round[j] = round;
            w->done[q] = 1;
            list_put(sub, m++, all, q);
        }
        sub->count = sub->pair_count = m;
        sub->revision = sinter_unique_id();
        left -= m;
        sinter_status s = eval_round(st, e, w);
        if (s != SINTER_OK)
            return s;
        /* the records of this round's contacts, found again by their order */
        size_t taken = 0;
        for (size_t q = 0; q < all->count && taken < m; ++q) {
            if (w->done[q] != 1)
                continue;
            w->done[q] = 2;
            put_force(snap, first + q, all->n + 3 * q, w->force + 3 * (size_t)all->i[q]);
            ++taken;
        }
    }
    return SINTER_OK;
}

static sinter_status contact_forces(const sinter_stepper *st, sinter_snapshot *snap, lists *L)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count, nw = st->walls ? st->walls->count : 0;
    force_work w = {0};
    sinter_status s = SINTER_OK;
    w.view = sinter_alloc(ctx, sizeof(sinter_particles));
    w.v = sinter_calloc(ctx, 3 * n + 3, sizeof(double));
    w.w = sinter_calloc(ctx, 3 * n + 3, sizeof(double));
    w.force = sinter_calloc(ctx, 3 * n + 3, sizeof(double));
    w.torque = sinter_calloc(ctx, 3 * n + 3, sizeof(double));
    w.wall_force = sinter_calloc(ctx, 6 * nw + 3, sizeof(double)); /* forces, moments */
    w.round = sinter_calloc(ctx, n + 1, sizeof(uint32_t));
    const size_t most = L->pp.count > L->pw.count ? L->pp.count : L->pw.count;
    w.done = sinter_calloc(ctx, most + 1, sizeof(int32_t));
    if (!w.view || !w.v || !w.w || !w.force || !w.torque || !w.wall_force || !w.round || !w.done)
        s = sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_snapshot_create: out of memory");
    if (s == SINTER_OK) {
        /* the velocities the last evaluation saw: lag before the set's (stepper.h) */
        const double lag = st->eval_lag;
        memcpy(w.view, ps, sizeof(*ps));
        for (size_t i = 0; i < n; ++i) {
            const uint32_t flags = ps->flags[i];
            const int moves = !(flags & SINTER_PARTICLE_FIXED);
            const int turns = moves && !(flags & SINTER_PARTICLE_NO_ROTATION);
            for (int d = 0; d < 3; ++d) {
                const size_t k = 3 * i + (size_t)d;
                w.v[k] =
                    moves && lag > 0.0 ? ps->v[k] - lag * ps->force[k] / ps->mass[i] : ps->v[k];
                w.w[k] =
                    turns && lag > 0.0 ? ps->w[k] - lag * ps->torque[k] / ps->inertia[i] : ps->w[k];
            }
        }
        w.view->v = w.v;
        w.view->w = w.w;
        sinter_force_eval e;
        memset(&e, 0, sizeof(e));
        e.ctx = ctx;
        e.ps = w.view;
        e.walls = st->walls;
        e.time = st->time;
        e.dt = 0.0; /* the committed springs, no increment */
        e.force = w.force;
        e.torque = w.torque;
        e.wall_force = w.wall_force;
        e.wall_moment = w.wall_force + 3 * nw;
        e.view = &st->view;
        s = sinter_thermal_softening((sinter_stepper *)st, &e.modulus_scale);
        if (s == SINTER_OK)
            s = forces_of(st, snap, &e, &w, L, 0);
        if (s == SINTER_OK && st->walls != NULL)
            s = forces_of(st, snap, &e, &w, L, 1);
    }
    sinter_free(ctx, w.view);
    sinter_free(ctx, w.v);
    sinter_free(ctx, w.w);
    sinter_free(ctx, w.force);
    sinter_free(ctx, w.torque);
    sinter_free(ctx, w.wall_force);
    sinter_free(ctx, w.round);
    sinter_free(ctx, w.done);
    return s;
}

/* Conductive heat flows: the conduction models' conductances (implicit form). */
static sinter_status contact_heat(const sinter_stepper *st, sinter_snapshot *snap, lists *L)
{
    sinter_ctx *ctx = st->ctx;
    const sinter_particles *ps = st->ps;
    const size_t np = L->pp.count, nwc = L->pw.count;
    double *g_pp = sinter_calloc(ctx, np + 1, sizeof(double));
    double *g_pw = sinter_calloc(ctx, nwc + 1, sizeof(double));
    double *heat = sinter_calloc(ctx, ps->count + 1, sizeof(double));
    /* k(theta) per particle when a material tabulates it (as sinter_thermal_eval) */
    const int tabulated = ps->tabulated[SINTER_PROPERTY_THERMAL_CONDUCTIVITY];
    double *kp = tabulated ? sinter_calloc(ctx, ps->count + 1, sizeof(double)) : NULL;
    sinter_status s = SINTER_OK;
    if (!g_pp || !g_pw || !heat || (tabulated && kp == NULL))
        s = sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_snapshot_create: out of memory");
    for (size_t i = 0; kp != NULL && i < ps->count; ++i)
        kp[i] = sinter_particle_property(ps, i, SINTER_PROPERTY_THERMAL_CONDUCTIVITY,
                                         SINTER_MAT_THERMAL_CONDUCTIVITY);
    for (size_t k = 0; k < st->thermal.count && s == SINTER_OK; ++k) {
        const sinter_heat_model *hm = st->thermal.slots[k].model;
        if (!hm->ops->conduction)
            continue;
        sinter_heat_eval e;
        memset(&e, 0, sizeof(e));
        e.ctx = ctx;
        e.ps = ps;
        e.walls = st->walls;
        e.pp = &L->pp;
        e.pw = &L->pw;
        e.time = st->time;
        e.heat = heat;
        e.g_pp = g_pp;
        e.g_pw = g_pw;
        e.view = &st->view;
        e.conductivity = kp;
        s = hm->ops->eval(hm, &e);
    }
    if (s == SINTER_OK) {
        const double *theta = ps->temperature;
        for (size_t q = 0; q < np; ++q)
            snap->heat[q] = g_pp[q] * (theta[L->pp.j[q]] - theta[L->pp.i[q]]);
        for (size_t q = 0; q < nwc; ++q)
            snap->heat[np + q] =
                g_pw[q] * (st->walls->wall[L->pw.j[q]].temperature - theta[L->pw.i[q]]);
    }
    sinter_free(ctx, g_pp);
    sinter_free(ctx, g_pw);
    sinter_free(ctx, heat);
    sinter_free(ctx, kp);
    return s;
}

/* The network's node of particle row j (n owned): the row itself; a ghost's: its image's
 * owner (periodic), or across subdomains its own node after the walls, whose potential the
 * solve brought from its owner (electric/network.c). */
static size_t current_node(const sinter_stepper *st, uint32_t j, size_t n)
{
    if (j < n)
        return j;
    return st->domain.on ? j + (st->walls ? st->walls->count : 0) : st->ghosts.owner[j - n];
}

/* Contact currents of the "network" model's last solve, I = G (phi_a - phi_b) with its edge
 * conductances (network.c, build_edges); NaN for another model or none. */
static void contact_current(const sinter_stepper *st, sinter_snapshot *snap, const lists *L)
{
    const sinter_particles *ps = st->ps;
    const struct sinter_electric_model *em = st->electric;
    /* the nodes: the owned particles, then the walls; an image has its owner's potential */
    const size_t np = L->pp.count, nwc = L->pw.count, n = ps->count - ps->ghost_count;
    const int network = em != NULL && em->kind == SINTER_ELECTRIC_NETWORK &&
                        em->potential != NULL &&
                        em->node_count == n + (st->walls ? st->walls->count : 0);
    const double *phi = network ? em->potential : NULL;
    for (size_t q = 0; q < np; ++q) {
        if (!network) {
            snap->current[q] = NAN;
            continue;
        }
        /* the solve's own conductance, eq. 50's term included (NaN under a host law) */
        const uint32_t i = L->pp.i[q], j = L->pp.j[q];
        const double g =
            sinter_electric_contact_conductance(em, ps, i, j, 0, L->pp.area[q], L->pp.dist[q]);
        snap->current[q] = g * (phi[current_node(st, i, n)] - phi[current_node(st, j, n)]);
    }
    for (size_t q = 0; q < nwc; ++q) {
        if (!network) {
            snap->current[np + q] = NAN;
            continue;
        }
        const uint32_t i = L->pw.i[q], wi = L->pw.j[q];
        if (st->walls->wall[wi].electric_mode == SINTER_WALL_NEUTRAL) {
            snap->current[np + q] = 0.0;
            continue;
        }
        const double g =
            sinter_electric_contact_conductance(em, ps, i, wi, 1, L->pw.area[q], L->pw.dist[q]);
        snap->current[np + q] = g * (phi[current_node(st, i, n)] - phi[n + wi]);
    }
}

static sinter_status take_contacts(const sinter_stepper *st, sinter_snapshot *snap, lists *L)
{
    const sinter_particles *ps = st->ps;
    const size_t np = L->pp.count;
    for (size_t q = 0; q < np; ++q) {
        snap->id_a[q] = ps->id[L->pp.i[q]];
        snap->id_b[q] = ps->id[L->pp.j[q]];
        snap->wall[q] = -1;
        memcpy(snap->normal + 3 * q, L->pp.n + 3 * q, 3 * sizeof(double));
        snap->overlap[q] = L->pp.delta[q];
        snap->area[q] = L->pp.area[q];
        snap->radius[q] = sqrt(L->pp.area[q] / PI_);
    }
    for (size_t q = 0; q < L->pw.count; ++q) {
        const size_t m = np + q;
        snap->id_a[m] = ps->id[L->pw.i[q]];
        snap->id_b[m] = UINT64_MAX;
        snap->wall[m] = (int32_t)L->pw.j[q];
        memcpy(snap->normal + 3 * m, L->pw.n + 3 * q, 3 * sizeof(double));
        snap->overlap[m] = L->pw.delta[q];
        snap->area[m] = L->pw.area[q];
        snap->radius[m] = sqrt(L->pw.area[q] / PI_);
    }
    sinter_status s = contact_forces(st, snap, L);
    if (s == SINTER_OK)
        s = contact_heat(st, snap, L);
    if (s == SINTER_OK)
        contact_current(st, snap, L);
    return s;
}

/* The quasi-static links: the neck states, the sintering force of the last step from its
 * approach (eq. 17 with y4, y7 decrements of eq. 43), the beam's force and moment from the
 * last solve's displacements (eq. 32-34; u is kept until the next step scales it), and eq.
 * 44's correction from them: the step moved the centres together by xi = (u_A - u_B) . e3
 * (eq. 41; e3 the axis after the step, the same to second order), the model alone by
 * dy4 + dy7 (eq. 43), and eq. 42's shares make the corrected y4 + y7 fall by xi, so
 * eq. 44 = (y4' + y7') - (y4 + y7) = dy4 + dy7 - xi. */
static void take_links(const sinter_stepper *st, sinter_snapshot *snap)
{
    const struct sinter_qs *qs = st->quasistatic;
    const sinter_particles *ps = st->ps;
    for (size_t k = 0; k < qs->count; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const double *y = l->neck.y;
        snap->link_a[k] = l->id_a;
        snap->link_b[k] = l->id_b;
        snap->neck[k] = y[SINTER_NECK_X];
        /* over the smaller particle radius, as the sintering statistics */
        snap->ratio[k] = y[SINTER_NECK_X] / fmin(ps->radius[l->beam.a], ps->radius[l->beam.b]);
        snap->approach[k] = l->neck.center_distance0 - (y[SINTER_NECK_LA] + y[SINTER_NECK_LB]);
        snap->age[k] = l->neck.time - l->born;
        const uint32_t a = l->beam.a, b = l->beam.b;
        const double theta = 0.5 * (ps->temperature[a] + ps->temperature[b]);
        snap->phase[k] = (int32_t)sinter_neck_phase_at(&l->material, theta);
        snap->fsint[k] =
            sinter_sintering_force(l->youngs, l->rm, l->neck.last_dy4 + l->neck.last_dy7);
        /* the displacements are per slot, in id order (stepper/qs_ids.c) */
        const int slots = qs->slots_valid && qs->slots == ps->count;
        const size_t sa = slots && a < ps->count ? qs->slot_of[a] : 0;
        const size_t sb = slots && b < ps->count ? qs->slot_of[b] : 0;
        if (qs->u_step > 0.0 && qs->u != NULL && slots && a < ps->count && b < ps->count) {
            double eps[3], gamma[3];
            sinter_beam_deformation(&l->beam, qs->u + 6 * sa, qs->u + 6 * sb, eps, gamma);
            /* the link force and moment of eq. 32-34 (sinter_beam_apply adds them to A) */
            double f[3], m[3];
            sinter_beam_axial_split(l->beam.axis, l->beam.k_shear, l->beam.k_axial, eps, f);
            sinter_beam_axial_split(l->beam.axis, l->beam.k_bend, l->beam.k_torsion, gamma, m);
            double xi = 0.0;
            for (int d = 0; d < 3; ++d) {
                snap->beam_force[3 * k + (size_t)d] = f[d];
                snap->beam_moment[3 * k + (size_t)d] = m[d];
                xi += (qs->u[6 * sa + (size_t)d] - qs->u[6 * sb + (size_t)d]) * l->beam.axis[d];
            }
            snap->correction[k] = l->neck.last_dy4 + l->neck.last_dy7 - xi;
        } else {
            for (int d = 0; d < 3; ++d)
                snap->beam_force[3 * k + (size_t)d] = snap->beam_moment[3 * k + (size_t)d] = NAN;
            snap->correction[k] = NAN;
        }
    }
}

/* The contact lists are those of the state (no write, addition, removal or reordering since
 * their evaluation); the links those of a quasi-static stepper that has stepped (they follow
 * the particles by index: not after an addition, removal or reordering). */
int sinter_snapshot_possible(const sinter_stepper *st)
{
    const sinter_particles *ps = st->ps;
    if (st->kind == SINTER_STEPPER_QUASISTATIC)
        return st->quasistatic != NULL && st->population_generation == ps->population_generation &&
               st->quasistatic->layout_generation == ps->layout_generation;
    return st->forces_current && st->write_generation == ps->write_generation &&
           st->population_generation == ps->population_generation && st->nb.built &&
           st->nb.layout_generation == ps->layout_generation;
}

sinter_status sinter_snapshot_create(sinter_snapshot **out, const sinter_stepper *st)
{
    if (out == NULL || st == NULL)
        return st != NULL
                   ? sinter_fail(st->ctx, SINTER_ERR_NULL, "sinter_snapshot_create: out is NULL")
                   : SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    const int qs = st->kind == SINTER_STEPPER_QUASISTATIC;
    if (!sinter_snapshot_possible(st))
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "sinter_snapshot_create: the stepper has not evaluated the current "
                           "state (no step yet, or the particles were written, added, removed "
                           "or sorted since); step or advance first");
    sinter_snapshot *snap = sinter_calloc(ctx, 1, sizeof(*snap));
    if (snap == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_snapshot_create: out of memory");
    snap->ctx = ctx;
    snap->time = st->time;
    lists L;
    memset(&L, 0, sizeof(L));
    sinter_status s = qs ? SINTER_OK : lists_make(st, &L);
    if (s == SINTER_OK) {
        snap->pairs = L.pp.count;
        snap->walls = L.pw.count;
        snap->links = qs ? st->quasistatic->count : 0;
        s = snapshot_alloc(snap, snap->pairs + snap->walls, snap->links);
        if (s != SINTER_OK)
            s = sinter_fail(ctx, s, "sinter_snapshot_create: out of memory");
    }
    if (s == SINTER_OK && !qs)
        s = take_contacts(st, snap, &L);
    if (s == SINTER_OK && qs)
        take_links(st, snap);
    lists_free(ctx, &L);
    if (s != SINTER_OK) {
        sinter_snapshot_destroy(snap);
        return s;
    }
    *out = snap;
    return SINTER_OK;
}

sinter_status sinter_snapshot_counts(const sinter_snapshot *s, size_t *pair_contacts,
                                     size_t *wall_contacts, size_t *links, double *time)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    if (pair_contacts != NULL)
        *pair_contacts = s->pairs;
    if (wall_contacts != NULL)
        *wall_contacts = s->walls;
    if (links != NULL)
        *links = s->links;
    if (time != NULL)
        *time = s->time;
    return SINTER_OK;
}

/* Lend array q of `arrays` (count records each, of layouts[q]); `max` arrays; `fn` names the
 * public function in the message. */
static sinter_status lend(const sinter_snapshot *s, void *const *arrays, const layout *layouts,
                          int max, int q, size_t count, const char *fn, const char *type,
                          const void **data, size_t *count_out, size_t *components,
                          sinter_dtype *dtype)
{
    SINTER_CHECK_NULL(s->ctx, data);
    if (q < 0 || q >= max)
        return sinter_fail(s->ctx, SINTER_ERR_RANGE, "%s: quantity %d is not a %s (0 .. %d)", fn, q,
                           type, max - 1);
    *data = count > 0 ? arrays[q] : NULL;
    if (count_out != NULL)
        *count_out = count;
    if (components != NULL)
        *components = layouts[q].components;
    if (dtype != NULL)
        *dtype = layouts[q].dtype;
    return SINTER_OK;
}

sinter_status sinter_snapshot_contacts(const sinter_snapshot *s, sinter_contact_data q,
                                       const void **data, size_t *count, size_t *components,
                                       sinter_dtype *dtype)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    return lend(s, s->contact, CONTACT_LAYOUT, SINTER_CONTACT_DATA_COUNT_, (int)q,
                s->pairs + s->walls, "sinter_snapshot_contacts", "sinter_contact_data", data, count,
                components, dtype);
}

sinter_status sinter_snapshot_links(const sinter_snapshot *s, sinter_link_data q, const void **data,
                                    size_t *count, size_t *components, sinter_dtype *dtype)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    return lend(s, s->link, LINK_LAYOUT, SINTER_LINK_DATA_COUNT_, (int)q, s->links,
                "sinter_snapshot_links", "sinter_link_data", data, count, components, dtype);
}

int sinter_snapshot_conducts_heat(const sinter_stepper *st)
{
    for (size_t k = 0; st != NULL && k < st->thermal.count; ++k)
        if (st->thermal.slots[k].model->ops->conduction)
            return 1;
    return 0;
}

int sinter_snapshot_conducts_current(const sinter_stepper *st)
{
    return st != NULL && st->electric != NULL && st->electric->kind == SINTER_ELECTRIC_NETWORK;
}

sinter_status sinter_snapshot_wall_flows(const sinter_stepper *st, double *heat, double *current)
{
    sinter_ctx *ctx = st->ctx;
    const size_t nw = st->walls ? st->walls->count : 0;
    for (size_t k = 0; k < nw; ++k) {
        if (heat != NULL)
            heat[k] = 0.0;
        if (current != NULL)
            current[k] = 0.0;
    }
    if (nw == 0 || st->kind == SINTER_STEPPER_QUASISTATIC)
        return SINTER_OK;
    if (!sinter_snapshot_possible(st)) {
        for (size_t k = 0; k < nw; ++k) {
            if (heat != NULL)
                heat[k] = NAN;
            if (current != NULL)
                current[k] = NAN;
        }
        return SINTER_OK;
    }
    if (st->pw.count == 0)
        return SINTER_OK;
    /* the wall contacts alone (an empty pair list): the records of a snapshot's wall part */
    lists L;
    memset(&L, 0, sizeof(L));
    sinter_status s = list_alloc(ctx, &L.pw, st->pw.count);
    if (s == SINTER_OK)
        s = list_alloc(ctx, &L.pp, 0);
    sinter_snapshot snap;
    memset(&snap, 0, sizeof(snap));
    snap.heat = s == SINTER_OK ? sinter_calloc(ctx, st->pw.count, sizeof(double)) : NULL;
    snap.current = s == SINTER_OK ? sinter_calloc(ctx, st->pw.count, sizeof(double)) : NULL;
    if (s == SINTER_OK && (snap.heat == NULL || snap.current == NULL))
        s = sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_snapshot_wall_flows: out of memory");
    if (s == SINTER_OK) {
        for (size_t k = 0; k < st->pw.count; ++k)
            list_put(&L.pw, k, &st->pw, k);
        L.pw.count = L.pw.pair_count = st->pw.count;
        if (heat != NULL)
            s = contact_heat(st, &snap, &L);
        if (current != NULL)
            contact_current(st, &snap, &L);
    }
    for (size_t q = 0; s == SINTER_OK && q < L.pw.count; ++q) {
        const uint32_t w = L.pw.j[q];
        if (heat != NULL)
            heat[w] += snap.heat[q]; /* into the particle, from the wall */
        if (current != NULL)
            current[w] -= snap.current[q]; /* from the particle to the wall */
    }
    sinter_free(ctx, snap.heat);
    sinter_free(ctx, snap.current);
    list_free(ctx, &L.pw);
    list_free(ctx, &L.pp);
    return s;
}
