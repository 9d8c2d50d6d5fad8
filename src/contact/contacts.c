/* Active contacts and their geometry (seed 000 eq. 7-12; seed 003 eq. 4-5, 33-34). */
#include <math.h>
#include <string.h>

#include "contacts.h"

#ifdef _OPENMP
#include <omp.h>
#endif

static const double PI = 3.14159265358979323846;

void sinter_contact_radii(const sinter_contact_list *c, double *a)
{
    for (size_t k = 0; k < c->count; ++k)
        a[k] = sqrt(c->area[k] / PI);
}

void sinter_contact_list_free(sinter_ctx *ctx, sinter_contact_list *c)
{
    void *arrays[] = {c->i,    c->j,    c->pair,   c->n,
                      c->delta, c->dist, c->area, c->branch, c->pair_to_contact};
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); ++k)
        sinter_free(ctx, arrays[k]);
    memset(c, 0, sizeof(*c));
}

static sinter_status reserve(sinter_ctx *ctx, sinter_contact_list *c, size_t need)
{
    if (need <= c->capacity)
        return SINTER_OK;
    size_t cap = c->capacity ? c->capacity : 256;
    while (cap < need)
        cap *= 2;
    void **slots[] = {(void **)&c->i,     (void **)&c->j,    (void **)&c->pair,
                      (void **)&c->n,     (void **)&c->delta, (void **)&c->dist,
                      (void **)&c->area,  (void **)&c->branch};
    const size_t elem[] = {4, 4, 4, 3 * sizeof(double), 8, 8, 8, 8};
    for (size_t k = 0; k < sizeof(slots) / sizeof(slots[0]); ++k) {
        void *q = sinter_realloc_array(ctx, *slots[k], cap, elem[k]);
        if (q == NULL)
            return sinter_last_status(ctx);
        *slots[k] = q;
    }
    c->capacity = cap;
    return SINTER_OK;
}

int sinter_threads(const sinter_ctx *ctx)
{
#ifdef _OPENMP
    return ctx->threads > 0 ? ctx->threads : omp_get_max_threads();
#else
    (void)ctx;
    return 1;
#endif
}

/* 1 if pair p is in contact (the test of the fill pass, without its arithmetic). */
static inline int touching(const sinter_pair_list *pairs, const double *x, const double *r,
                           size_t p)
{
    const uint32_t i = pairs->i[p], j = pairs->j[p];
    const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                 ez = x[3 * j + 2] - x[3 * i + 2];
    const double d2 = ex * ex + ey * ey + ez * ez, rs = r[i] + r[j];
    return d2 < rs * rs && d2 != 0.0;
}

/* Contacts among pairs [lo, hi), written from index m on; returns the next free index. */
static size_t fill_pp(sinter_contact_list *c, const sinter_pair_list *pairs,
                      const sinter_particles *ps, size_t lo, size_t hi, size_t m)
{
    const double *x = ps->x, *r = ps->radius;
    for (size_t p = lo; p < hi; ++p) {
        const uint32_t i = pairs->i[p], j = pairs->j[p];
        const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                     ez = x[3 * j + 2] - x[3 * i + 2];
        const double d2 = ex * ex + ey * ey + ez * ez, rs = r[i] + r[j];
        if (d2 >= rs * rs || d2 == 0.0) {
            c->pair_to_contact[p] = SINTER_NO_PAIR;
            continue;
        }
        const double d = sqrt(d2), inv = 1.0 / d;
        /* L_i from seed 000 eq. 12; a^2 = R_i^2 - L_i^2 (eq. 7, 11). */
        const double li = 0.5 * (d - (r[j] * r[j] - r[i] * r[i]) * inv);
        const double a2_raw = r[i] * r[i] - li * li, a2 = a2_raw > 0.0 ? a2_raw : 0.0;
        c->i[m] = i;
        c->j[m] = j;
        c->pair[m] = (uint32_t)p;
        c->pair_to_contact[p] = (uint32_t)m;
        c->n[3 * m] = ex * inv;
        c->n[3 * m + 1] = ey * inv;
        c->n[3 * m + 2] = ez * inv;
        c->delta[m] = rs - d; /* seed 000 eq. 10 */
        c->dist[m] = d;
        c->area[m] = PI * a2; /* the contact radius sqrt(a2) is derived on demand */
        c->branch[m] = li;
        ++m;
    }
    return m;
}

sinter_status sinter_contacts_find_pp(sinter_ctx *ctx, sinter_contact_list *c,
                                      const sinter_pair_list *pairs, const sinter_particles *ps)
{
    /* Reserve for the worst case so the loops below never allocate. */
    sinter_status st = reserve(ctx, c, pairs->count + 1);
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->pair_to_contact, &c->pair_to_contact_capacity,
                         pairs->count + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    c->adj_start = pairs->adj_start;
    c->adj_pair = pairs->adj_pair;
    c->particle_count = ps->count;
    c->pair_count = pairs->count;
    const int threads = pairs->count < 4096 ? 1 : sinter_threads(ctx);
    if (threads <= 1) {
        c->count = fill_pp(c, pairs, ps, 0, pairs->count, 0);
        return SINTER_OK;
    }
    /* Threads: count per chunk, then fill each chunk from its offset: the same list, in the
     * same order, as one thread makes. */
    enum { MAX_CHUNKS = 256 };
    const int chunks = threads < MAX_CHUNKS ? threads : MAX_CHUNKS;
    size_t offset[MAX_CHUNKS + 1] = {0};
    const size_t n = pairs->count;
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
    for (int t = 0; t < chunks; ++t) {
        const size_t lo = n * (size_t)t / (size_t)chunks, hi = n * (size_t)(t + 1) / (size_t)chunks;
        size_t count = 0;
        for (size_t p = lo; p < hi; ++p)
            count += (size_t)touching(pairs, ps->x, ps->radius, p);
        offset[t + 1] = count;
    }
    for (int t = 0; t < chunks; ++t)
        offset[t + 1] += offset[t];
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
    for (int t = 0; t < chunks; ++t) {
        const size_t lo = n * (size_t)t / (size_t)chunks, hi = n * (size_t)(t + 1) / (size_t)chunks;
        fill_pp(c, pairs, ps, lo, hi, offset[t]);
    }
    c->count = offset[chunks];
    return SINTER_OK;
}

sinter_status sinter_contacts_find_pw(sinter_ctx *ctx, sinter_contact_list *c,
                                      const sinter_pair_list *pairs, const sinter_particles *ps,
                                      const sinter_walls *walls)
{
    sinter_status st = reserve(ctx, c, pairs->count + 1);
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&c->pair_to_contact, &c->pair_to_contact_capacity,
                         pairs->count + 1, sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    c->particle_count = ps->count;
    c->pair_count = pairs->count;
    const double *x = ps->x, *r = ps->radius;
    size_t m = 0;
    for (size_t p = 0; p < pairs->count; ++p) {
        const uint32_t i = pairs->i[p], k = pairs->j[p];
        const sinter_wall *w = &walls->wall[k];
        const double s = (x[3 * i] - w->p[0]) * w->n[0] + (x[3 * i + 1] - w->p[1]) * w->n[1] +
                         (x[3 * i + 2] - w->p[2]) * w->n[2];
        c->pair_to_contact[p] = SINTER_NO_PAIR;
        if (s >= r[i])
            continue;
        c->pair_to_contact[p] = (uint32_t)m;
        /* The wall is a particle of infinite radius (seed 003 remark 1): L_i = s. */
        const double a2_raw = r[i] * r[i] - s * s, a2 = a2_raw > 0.0 ? a2_raw : 0.0;
        c->i[m] = i;
        c->j[m] = k;
        c->pair[m] = (uint32_t)p;
        c->n[3 * m] = -w->n[0];
        c->n[3 * m + 1] = -w->n[1];
        c->n[3 * m + 2] = -w->n[2];
        c->delta[m] = r[i] - s;
        c->dist[m] = s;
        c->area[m] = PI * a2;
        c->branch[m] = s;
        ++m;
    }
    c->count = m;
    return SINTER_OK;
}
