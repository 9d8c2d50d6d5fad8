/*
 * Pair histories of imported particles, staged by key until the next neighbour build (issue 43,
 * migrate.h). An imported particle has no pairs yet: its contacts' springs wait here, and the
 * build that lists its pairs gives each pair the history staged under its key, unless the pair
 * holds one already (the other end of a contact that never left: the same contact, kept once).
 */
#include <string.h>

#include "stepper/migrate.h"
#include "stepper/stepper.h"

static void entries_free(sinter_ctx *ctx, sinter_migrate_entries *l)
{
    sinter_free(ctx, l->key);
    sinter_free(ctx, l->value);
    memset(l, 0, sizeof(*l));
}

void sinter_migrate_stage_free(sinter_ctx *ctx, sinter_migrate_stage *stage)
{
    if (stage == NULL)
        return;
    for (size_t k = 0; k < 2 * stage->slots; ++k)
        entries_free(ctx, &stage->list[k]);
    sinter_free(ctx, stage->list);
    sinter_free(ctx, stage->width);
    sinter_free(ctx, stage);
}

sinter_migrate_stage *sinter_migrate_stage_get(sinter_stepper *st)
{
    sinter_migrate_stage *g = st->migrate;
    int same = g != NULL && g->slots == st->force_count;
    for (size_t k = 0; same && k < st->force_count; ++k)
        same = g->width[2 * k] == st->forces[k].pp.width &&
               g->width[2 * k + 1] == st->forces[k].pw.width;
    if (same)
        return g;
    /* force models added since: what was staged for the old ones cannot be matched */
    sinter_migrate_stage_free(st->ctx, g);
    st->migrate = NULL;
    g = sinter_calloc(st->ctx, 1, sizeof(*g));
    if (g == NULL)
        return NULL;
    g->slots = st->force_count;
    g->width = sinter_calloc(st->ctx, 2 * g->slots + 1, sizeof(size_t));
    g->list = sinter_calloc(st->ctx, 2 * g->slots + 1, sizeof(sinter_migrate_entries));
    if (g->width == NULL || g->list == NULL) {
        sinter_migrate_stage_free(st->ctx, g);
        return NULL;
    }
    for (size_t k = 0; k < g->slots; ++k) {
        g->width[2 * k] = st->forces[k].pp.width;
        g->width[2 * k + 1] = st->forces[k].pw.width;
    }
    st->migrate = g;
    return g;
}

sinter_status sinter_migrate_reserve(sinter_ctx *ctx, sinter_migrate_entries *l, size_t w,
                                     size_t more)
{
    const size_t need = l->count + more + 1;
    if (need <= l->capacity)
        return SINTER_OK;
    uint64_t *key = sinter_realloc_array(ctx, l->key, 2 * need, sizeof(uint64_t));
    if (key == NULL)
        return sinter_last_status(ctx);
    l->key = key;
    double *value = sinter_realloc_array(ctx, l->value, w * need + 1, sizeof(double));
    if (value == NULL)
        return sinter_last_status(ctx);
    l->value = value;
    l->capacity = need;
    return SINTER_OK;
}

void sinter_migrate_drop(sinter_migrate_entries *l, size_t w,
                         int (*drop)(const uint64_t key[2], void *user), void *user)
{
    size_t kept = 0;
    for (size_t e = 0; e < l->count; ++e) {
        if (drop(l->key + 2 * e, user))
            continue;
        if (kept != e) {
            l->key[2 * kept] = l->key[2 * e];
            l->key[2 * kept + 1] = l->key[2 * e + 1];
            memmove(l->value + w * kept, l->value + w * e, w * sizeof(double));
        }
        ++kept;
    }
    l->count = kept;
}

static inline uint64_t mix(uint64_t a, uint64_t b)
{
    uint64_t h = a * 0x9E3779B97F4A7C15ull ^ (b + 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2));
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return h;
}

size_t sinter_migrate_dedupe_slots(size_t count)
{
    size_t cap = 16;
    while (cap < 2 * count)
        cap *= 2;
    return cap;
}

void sinter_migrate_dedupe(sinter_migrate_entries *l, size_t w, uint32_t *table, size_t cap)
{
    const size_t mask = cap - 1;
    memset(table, 0xff, cap * sizeof(uint32_t));
    size_t kept = 0;
    for (size_t e = 0; e < l->count; ++e) {
        const uint64_t a = l->key[2 * e], b = l->key[2 * e + 1];
        size_t at = mix(a, b) & mask;
        int seen = 0;
        for (; table[at] != UINT32_MAX; at = (at + 1) & mask)
            if (l->key[2 * table[at]] == a && l->key[2 * table[at] + 1] == b) {
                seen = 1; /* a copy of a kept entry (the same contact, the same bits) */
                break;
            }
        if (seen)
            continue;
        if (kept != e) {
            l->key[2 * kept] = a;
            l->key[2 * kept + 1] = b;
            memmove(l->value + w * kept, l->value + w * e, w * sizeof(double));
        }
        table[at] = (uint32_t)kept++;
    }
    l->count = kept;
}

/* The staged entries of l into history h over pair list L (see sinter_migrate_match). */
static sinter_status match_list(sinter_ctx *ctx, sinter_history *h, const sinter_pair_list *L,
                                const sinter_migrate_entries *l)
{
    const size_t w = h->width, n = L->count;
    if (w == 0 || l->count == 0 || n == 0)
        return SINTER_OK;
    size_t cap = 16;
    while (cap < 2 * l->count)
        cap *= 2;
    uint32_t *table = sinter_alloc(ctx, cap * sizeof(uint32_t));
    unsigned char *held = sinter_calloc(ctx, n, 1);
    sinter_status s = table != NULL && held != NULL ? SINTER_OK : SINTER_ERR_NOMEM;
    if (s == SINTER_OK)
        s = sinter_grow(ctx, (void **)&h->active, &h->active_capacity, n + 1, sizeof(uint32_t));
    if (s != SINTER_OK) {
        sinter_free(ctx, table);
        sinter_free(ctx, held);
        return s;
    }
    const size_t mask = cap - 1;
    memset(table, 0xff, cap * sizeof(uint32_t));
    for (size_t e = 0; e < l->count; ++e) {
        size_t at = mix(l->key[2 * e], l->key[2 * e + 1]) & mask;
        while (table[at] != UINT32_MAX)
            at = (at + 1) & mask;
        table[at] = (uint32_t)e;
    }
    for (size_t a = 0; a < h->active_count; ++a)
        held[h->active[a]] = 1;
    for (size_t q = 0; q < n; ++q) {
        if (held[q])
            continue; /* the pair's history is held here already (its other end stayed) */
        size_t at = mix(L->key_i[q], L->key_j[q]) & mask;
        for (; table[at] != UINT32_MAX; at = (at + 1) & mask) {
            const size_t e = table[at];
            if (l->key[2 * e] != L->key_i[q] || l->key[2 * e + 1] != L->key_j[q])
                continue;
            memcpy(h->committed + w * q, l->value + w * e, w * sizeof(double));
            h->active[h->active_count++] = (uint32_t)q;
            held[q] = 1;
            break;
        }
    }
    sinter_history_forget(h);
    sinter_free(ctx, table);
    sinter_free(ctx, held);
    return SINTER_OK;
}

sinter_status sinter_migrate_match(sinter_stepper *st)
{
    sinter_migrate_stage *g = st->migrate;
    if (g == NULL)
        return SINTER_OK;
    sinter_status s = SINTER_OK;
    if (g->slots == st->force_count)
        for (size_t k = 0; k < g->slots && s == SINTER_OK; ++k) {
            if (g->width[2 * k] == st->forces[k].pp.width)
                s = match_list(st->ctx, &st->forces[k].pp, &st->nb.pp, &g->list[2 * k]);
            if (s == SINTER_OK && g->width[2 * k + 1] == st->forces[k].pw.width)
                s = match_list(st->ctx, &st->forces[k].pw, &st->nb.pw, &g->list[2 * k + 1]);
        }
    if (s == SINTER_OK) {
        sinter_migrate_stage_free(st->ctx, g);
        st->migrate = NULL;
    }
    return s;
}
