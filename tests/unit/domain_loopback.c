/* A thread transport for the domain operations (domain_loopback.h). */
#include "domain_loopback.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "core/repro_sum.h"

/* The owned particles a subdomain publishes at a redistribution (struct of arrays). */
typedef struct published {
    size_t n, capacity;
    uint64_t *id;
    double *x, *v, *w, *rot; /* 3 each */
    double *r, *m, *inertia, *temp;
    int32_t *material;
    uint32_t *flags;
} published;

typedef struct member {
    loopback *lb;
    int rank;
    sinter_particles *ps;
    published own; /* its owned particles at the last redistribution */
    published gh;  /* its ghosts, in the order given to the set */
    int *src_rank; /* per ghost: the owning subdomain and the index there */
    size_t *src_index;
    unsigned char *slot; /* reduce and exscan */
    size_t slot_capacity;
    const sinter_halo *halo; /* published for the duration of a halo */
    uint64_t counts[3];
    unsigned char *out[LOOPBACK_MAX]; /* records for subdomain r at a migration */
    size_t out_bytes[LOOPBACK_MAX], out_capacity[LOOPBACK_MAX];
    uint64_t migrated; /* particles sent to others */
} member;

/* A barrier of mutex and condition (POSIX barriers are optional: macOS has none). */
typedef struct barrier {
    pthread_mutex_t lock;
    pthread_cond_t all_in;
    int waiting;
    unsigned long generation;
} barrier;

struct loopback {
    int size;
    int slabs;     /* 1: particles migrate between the slabs of [x0, x1) */
    double x0, x1; /* [m] */
    barrier barrier;
    member m[LOOPBACK_MAX];
};

static int grow_published(published *p, size_t n)
{
    if (n <= p->capacity)
        return 0;
    const size_t c = n + n / 2 + 8;
    void *a[11] = {realloc(p->id, c * 8),       realloc(p->x, 24 * c),      realloc(p->v, 24 * c),
                   realloc(p->w, 24 * c),       realloc(p->rot, 24 * c),    realloc(p->r, 8 * c),
                   realloc(p->m, 8 * c),        realloc(p->inertia, 8 * c), realloc(p->temp, 8 * c),
                   realloc(p->material, 4 * c), realloc(p->flags, 4 * c)};
    p->id = a[0] ? a[0] : p->id;
    p->x = a[1] ? a[1] : p->x;
    p->v = a[2] ? a[2] : p->v;
    p->w = a[3] ? a[3] : p->w;
    p->rot = a[4] ? a[4] : p->rot;
    p->r = a[5] ? a[5] : p->r;
    p->m = a[6] ? a[6] : p->m;
    p->inertia = a[7] ? a[7] : p->inertia;
    p->temp = a[8] ? a[8] : p->temp;
    p->material = a[9] ? a[9] : p->material;
    p->flags = a[10] ? a[10] : p->flags;
    for (int k = 0; k < 11; ++k)
        if (a[k] == NULL)
            return -1;
    p->capacity = c;
    return 0;
}

static void free_published(published *p)
{
    free(p->id);
    free(p->x);
    free(p->v);
    free(p->w);
    free(p->rot);
    free(p->r);
    free(p->m);
    free(p->inertia);
    free(p->temp);
    free(p->material);
    free(p->flags);
}

void loopback_barrier(loopback *lb)
{
    barrier *b = &lb->barrier;
    pthread_mutex_lock(&b->lock);
    const unsigned long generation = b->generation;
    if (++b->waiting == lb->size) {
        b->waiting = 0;
        b->generation++;
        pthread_cond_broadcast(&b->all_in);
    } else {
        while (generation == b->generation)
            pthread_cond_wait(&b->all_in, &b->lock);
    }
    pthread_mutex_unlock(&b->lock);
}

/* ---- reduce and exscan ------------------------------------------------------------------ */

static double sum_f64(const loopback *lb, size_t k)
{
    /* the limb sum: the same bits for any order of the parts (core/repro_sum.h) */
    int e = INT32_MIN, finite = 1;
    for (int r = 0; r < lb->size; ++r) {
        int f = 1;
        const int er = sinter_repro_exponent((const double *)lb->m[r].slot + k, 1, 1, &f);
        e = er > e ? er : e;
        finite &= f;
    }
    if (!finite) { /* NaN or infinity: the plain sum in subdomain order carries it */
        double s = 0.0;
        for (int r = 0; r < lb->size; ++r)
            s += ((const double *)lb->m[r].slot)[k];
        return s;
    }
    if (e == INT32_MIN)
        return 0.0;
    sinter_repro_sum s;
    memset(&s, 0, sizeof(s));
    for (int r = 0; r < lb->size; ++r)
        sinter_repro_add(&s, e, (const double *)lb->m[r].slot + k, 1, 1);
    return sinter_repro_value(&s, e);
}

#define REDUCE_INTEGER(T, out)                                                                     \
    do {                                                                                           \
        T a = ((const T *)lb->m[0].slot)[k];                                                       \
        for (int r = 1; r < lb->size; ++r) {                                                       \
            const T b = ((const T *)lb->m[r].slot)[k];                                             \
            a = op == SINTER_REDUCE_SUM   ? (T)(a + b)                                             \
                : op == SINTER_REDUCE_MIN ? (b < a ? b : a)                                        \
                                          : (b > a ? b : a);                                       \
        }                                                                                          \
        ((T *)(out))[k] = a;                                                                       \
    } while (0)

static int lb_reduce(void *values, size_t count, int type, int op, void *user)
{
    member *me = user;
    loopback *lb = me->lb;
    me->counts[0]++;
    int bad = type < 0 || type > 2 || op < 0 || op > 2;
    const size_t bytes = 8 * count + 8;
    if (bytes > me->slot_capacity) {
        unsigned char *g = realloc(me->slot, bytes);
        if (g != NULL) {
            me->slot = g;
            me->slot_capacity = bytes;
        }
        bad |= g == NULL;
    }
    if (!bad)
        memcpy(me->slot, values, 8 * count);
    loopback_barrier(lb);
    for (size_t k = 0; k < count && !bad; ++k) {
        if (type == SINTER_REDUCE_I64) {
            REDUCE_INTEGER(int64_t, values);
        } else if (type == SINTER_REDUCE_U64) {
            REDUCE_INTEGER(uint64_t, values);
        } else if (op == SINTER_REDUCE_SUM) {
            ((double *)values)[k] = sum_f64(lb, k);
        } else {
            double a = ((const double *)lb->m[0].slot)[k];
            for (int r = 1; r < lb->size; ++r) {
                const double b = ((const double *)lb->m[r].slot)[k];
                a = op == SINTER_REDUCE_MIN ? (b < a ? b : a) : (b > a ? b : a);
            }
            ((double *)values)[k] = a;
        }
    }
    loopback_barrier(lb); /* the slots are read by all before any is reused */
    return bad ? -1 : 0;
}

static int lb_exscan(uint64_t value, uint64_t *before, uint64_t *total, void *user)
{
    member *me = user;
    loopback *lb = me->lb;
    me->counts[0]++;
    uint64_t v = value;
    int bad = me->slot_capacity < 8;
    if (bad) {
        unsigned char *g = realloc(me->slot, 64);
        bad = g == NULL;
        if (g != NULL) {
            me->slot = g;
            me->slot_capacity = 64;
        }
    }
    if (!bad)
        memcpy(me->slot, &v, 8);
    loopback_barrier(lb);
    uint64_t b = 0, t = 0;
    for (int r = 0; r < lb->size; ++r) {
        uint64_t x;
        memcpy(&x, lb->m[r].slot, 8);
        b += r < me->rank ? x : 0;
        t += x;
    }
    *before = b;
    *total = t;
    loopback_barrier(lb);
    return bad ? -1 : 0;
}

/* ---- halo ------------------------------------------------------------------------------- */

static int lb_halo(const sinter_halo *h, void *user)
{
    member *me = user;
    loopback *lb = me->lb;
    me->counts[1]++;
    me->halo = h;
    const int bad = h->ghosts != me->gh.n; /* (the ghosts are the last redistribution's) */
    loopback_barrier(lb);
    const size_t w = h->width;
    if (!bad && h->direction == SINTER_HALO_FORWARD) {
        for (size_t k = 0; k < me->gh.n; ++k) {
            const sinter_halo *src = lb->m[me->src_rank[k]].halo;
            memcpy(h->data + (h->owned + k) * w, src->data + me->src_index[k] * w,
                   w * sizeof(double));
        }
    } else if (!bad) { /* reverse: the others' ghost rows of my particles, in subdomain order */
        for (int r = 0; r < lb->size; ++r) {
            const member *o = &lb->m[r];
            for (size_t k = 0; r != me->rank && k < o->gh.n; ++k)
                if (o->src_rank[k] == me->rank)
                    for (size_t c = 0; c < w; ++c)
                        h->data[o->src_index[k] * w + c] +=
                            o->halo->data[(o->halo->owned + k) * w + c];
        }
    }
    loopback_barrier(lb);
    if (!bad && h->direction == SINTER_HALO_REVERSE)
        memset(h->data + h->owned * w, 0, h->ghosts * w * sizeof(double));
    me->halo = NULL;
    return bad ? -1 : 0;
}

/* ---- redistribute ----------------------------------------------------------------------- */

/* Copy `count` items of `size` bytes of field f of the set's first rows into out. */
static int read_field(const sinter_particles *ps, sinter_field f, void *out, size_t size,
                      size_t count)
{
    const void *a = NULL;
    if (sinter_particles_view_read(ps, f, &a, NULL, NULL) != SINTER_OK)
        return -1;
    if (count > 0)
        memcpy(out, a, size * count);
    return sinter_particles_release(ps, f) == SINTER_OK ? 0 : -1;
}

static int publish_owned(member *me)
{
    published *p = &me->own;
    size_t n = 0;
    if (sinter_particles_owned_count(me->ps, &n) != SINTER_OK || grow_published(p, n) != 0)
        return -1;
    p->n = n;
    int bad = 0;
    bad |= read_field(me->ps, SINTER_FIELD_ID, p->id, 8, n);
    bad |= read_field(me->ps, SINTER_FIELD_POSITION, p->x, 24, n);
    bad |= read_field(me->ps, SINTER_FIELD_VELOCITY, p->v, 24, n);
    bad |= read_field(me->ps, SINTER_FIELD_SPIN, p->w, 24, n);
    bad |= read_field(me->ps, SINTER_FIELD_ROTATION, p->rot, 24, n);
    bad |= read_field(me->ps, SINTER_FIELD_RADIUS, p->r, 8, n);
    bad |= read_field(me->ps, SINTER_FIELD_MASS, p->m, 8, n);
    bad |= read_field(me->ps, SINTER_FIELD_INERTIA, p->inertia, 8, n);
    bad |= read_field(me->ps, SINTER_FIELD_TEMPERATURE, p->temp, 8, n);
    bad |= read_field(me->ps, SINTER_FIELD_MATERIAL, p->material, 4, n);
    bad |= read_field(me->ps, SINTER_FIELD_FLAGS, p->flags, 4, n);
    return bad;
}

/* Ghost k of `me` copies particle j of subdomain r. */
static void take_ghost(member *me, size_t k, int r, size_t j)
{
    const published *s = &me->lb->m[r].own;
    published *g = &me->gh;
    g->id[k] = s->id[j];
    memcpy(g->x + 3 * k, s->x + 3 * j, 24);
    memcpy(g->v + 3 * k, s->v + 3 * j, 24);
    memcpy(g->w + 3 * k, s->w + 3 * j, 24);
    memcpy(g->rot + 3 * k, s->rot + 3 * j, 24);
    g->r[k] = s->r[j];
    g->m[k] = s->m[j];
    g->inertia[k] = s->inertia[j];
    g->temp[k] = s->temp[j];
    g->material[k] = s->material[j];
    g->flags[k] = s->flags[j];
    me->src_rank[k] = r;
    me->src_index[k] = j;
}

/* The subdomain whose slab holds x. */
static int slab_of(const loopback *lb, double x)
{
    const double r = floor((x - lb->x0) / (lb->x1 - lb->x0) * lb->size);
    return r < 0.0 ? 0 : r >= lb->size ? lb->size - 1 : (int)r;
}

/* Export the owned particles of `me` listed for subdomain r into me->out[r]. */
static int export_to(member *me, sinter_stepper *st, int r, size_t n, const size_t *list)
{
    size_t bytes = 0, written = 0;
    me->out_bytes[r] = 0;
    if (n == 0)
        return 0;
    if (sinter_stepper_export_size(st, n, list, &bytes) != SINTER_OK)
        return -1;
    if (bytes > me->out_capacity[r]) {
        unsigned char *g = realloc(me->out[r], bytes);
        if (g == NULL)
            return -1;
        me->out[r] = g;
        me->out_capacity[r] = bytes;
    }
    if (sinter_stepper_export(st, n, list, me->out[r], me->out_capacity[r], &written, 0))
        return -1;
    me->out_bytes[r] = written;
    return 0;
}

/* Migration: the owned particles whose centre left this slab go, with everything the stepper
 * keeps for them, to the subdomain whose slab holds them; those of the others come here
 * (from subdomain 0 up). Collective (two barriers). */
static int migrate(member *me, sinter_stepper *st)
{
    loopback *lb = me->lb;
    int bad = publish_owned(me); /* (positions and ids; no view stays out) */
    const size_t n = me->own.n;
    size_t *list = malloc((n + 1) * sizeof(size_t)), *all = malloc((n + 1) * sizeof(size_t));
    bad |= list == NULL || all == NULL;
    size_t leaving = 0;
    for (int r = 0; r < lb->size && !bad; ++r) {
        size_t m = 0;
        for (size_t i = 0; r != me->rank && i < n; ++i)
            if (slab_of(lb, me->own.x[3 * i]) == r)
                list[m++] = all[leaving++] = i;
        bad |= export_to(me, st, r, m, list);
    }
    if (!bad && leaving > 0) { /* one removal of all of them (the indices stay valid) */
        const sinter_status r = sinter_stepper_remove(st, leaving, all);
        if (r == SINTER_ERR_STATE) /* the staggered stepper in an attempt: they stay (for now) */
            for (int q = 0; q < lb->size; ++q)
                me->out_bytes[q] = 0;
        else if (r == SINTER_OK)
            me->migrated += leaving;
        else
            bad = 1;
    }
    free(list);
    free(all);
    for (int r = 0; r < lb->size && bad; ++r)
        me->out_bytes[r] = 0;
    loopback_barrier(lb); /* every record written */
    for (int r = 0; r < lb->size && !bad; ++r) {
        const member *o = &lb->m[r];
        if (r != me->rank && o->out_bytes[me->rank] > 0)
            bad |= sinter_stepper_import(st, o->out[me->rank], o->out_bytes[me->rank], NULL) !=
                   SINTER_OK;
    }
    loopback_barrier(lb); /* every record read before any is written again */
    return bad;
}

static int lb_redistribute(sinter_stepper *st, void *user)
{
    member *me = user;
    loopback *lb = me->lb;
    me->counts[2]++;
    int bad = lb->slabs ? migrate(me, st) : 0;
    double cutoff = 0.0;
    bad |= sinter_stepper_ghost_cutoff(st, &cutoff) != SINTER_OK;
    bad |= publish_owned(me);
    double lo = INFINITY, hi = -INFINITY; /* the owned particles' extent along x */
    for (size_t i = 0; i < me->own.n; ++i) {
        lo = fmin(lo, me->own.x[3 * i]);
        hi = fmax(hi, me->own.x[3 * i]);
    }
    loopback_barrier(lb);
    size_t count = 0;
    for (int r = 0; r < lb->size && !bad; ++r) {
        const published *s = &lb->m[r].own;
        for (size_t j = 0; r != me->rank && j < s->n; ++j) {
            const double x = s->x[3 * j];
            if (!(x >= lo - cutoff && x <= hi + cutoff))
                continue;
            if (grow_published(&me->gh, count + 1) != 0) {
                bad = 1;
                break;
            }
            int *sr = realloc(me->src_rank, me->gh.capacity * sizeof(int));
            size_t *si = sr ? realloc(me->src_index, me->gh.capacity * sizeof(size_t)) : NULL;
            me->src_rank = sr ? sr : me->src_rank;
            me->src_index = si ? si : me->src_index;
            if (sr == NULL || si == NULL) {
                bad = 1;
                break;
            }
            take_ghost(me, count++, r, j);
        }
    }
    me->gh.n = bad ? 0 : count;
    int32_t *owner = malloc((count + 1) * sizeof(int32_t));
    bad |= owner == NULL;
    for (size_t k = 0; k < count && owner != NULL; ++k)
        owner[k] = me->src_rank[k];
    const published *g = &me->gh;
    const sinter_ghost_fields gf = {.struct_size = sizeof(sinter_ghost_fields),
                                    .count = me->gh.n,
                                    .id = g->id,
                                    .position = g->x,
                                    .velocity = g->v,
                                    .spin = g->w,
                                    .rotation = g->rot,
                                    .radius = g->r,
                                    .mass = g->m,
                                    .inertia = g->inertia,
                                    .temperature = g->temp,
                                    .material = g->material,
                                    .flags = g->flags,
                                    .owner = owner};
    if (!bad && sinter_particles_set_ghosts(me->ps, &gf) != SINTER_OK)
        bad = 1;
    free(owner);
    loopback_barrier(lb); /* every set made before the next publication */
    return bad ? -1 : 0;
}

/* ---- the transport ---------------------------------------------------------------------- */

loopback *loopback_create(int size)
{
    if (size < 1 || size > LOOPBACK_MAX)
        return NULL;
    loopback *lb = calloc(1, sizeof(*lb));
    if (lb == NULL)
        return NULL;
    lb->size = size;
    if (pthread_mutex_init(&lb->barrier.lock, NULL) != 0) {
        free(lb);
        return NULL;
    }
    if (pthread_cond_init(&lb->barrier.all_in, NULL) != 0) {
        pthread_mutex_destroy(&lb->barrier.lock);
        free(lb);
        return NULL;
    }
    for (int r = 0; r < size; ++r) {
        lb->m[r].lb = lb;
        lb->m[r].rank = r;
    }
    return lb;
}

void loopback_destroy(loopback *lb)
{
    if (lb == NULL)
        return;
    for (int r = 0; r < lb->size; ++r) {
        member *m = &lb->m[r];
        free_published(&m->own);
        free_published(&m->gh);
        free(m->src_rank);
        free(m->src_index);
        free(m->slot);
        for (int k = 0; k < LOOPBACK_MAX; ++k)
            free(m->out[k]);
    }
    pthread_cond_destroy(&lb->barrier.all_in);
    pthread_mutex_destroy(&lb->barrier.lock);
    free(lb);
}

sinter_status loopback_attach(loopback *lb, int rank, sinter_stepper *st, sinter_particles *ps)
{
    if (lb == NULL || rank < 0 || rank >= lb->size)
        return SINTER_ERR_INVALID;
    lb->m[rank].ps = ps;
    const sinter_domain_ops ops = {.struct_size = sizeof(sinter_domain_ops),
                                   .reduce = lb_reduce,
                                   .exscan = lb_exscan,
                                   .halo = lb_halo,
                                   .redistribute = lb_redistribute,
                                   .destroy_user = NULL};
    return sinter_stepper_set_domain_ops(st, &ops, &lb->m[rank]);
}

void loopback_counts(const loopback *lb, int rank, uint64_t counts[3])
{
    memcpy(counts, lb->m[rank].counts, sizeof(lb->m[rank].counts));
}

void loopback_set_slabs(loopback *lb, double x0, double x1)
{
    lb->slabs = x1 > x0;
    lb->x0 = x0;
    lb->x1 = x1;
}

uint64_t loopback_migrated(const loopback *lb, int rank)
{
    return lb->m[rank].migrated;
}
