/*
 * The quasi-static stepper's state in a checkpoint: the links (beam, neck state, neck data),
 * the principal-plane conditions, the initial extents, the next global step and the counters.
 * The work arrays are not stored: each global step rebuilds them. A restore builds a complete
 * new sinter_qs from checked bytes, so the caller can swap it in without failing half-way.
 *
 * Layout (host order, inside the checkpoint's checksum): u64 sizeof(sinter_qs_link), u64 link
 * count, the links, u64 particles, u64 plane-condition bytes, those bytes, f64 extent0[3],
 * f64 dt_next, u64 steps, rejected, pcg_iterations, substepped, f64 u_step and, when it is
 * > 0, the last displacements u (the next solve starts from them, so they are state too), then
 * u64 origin count and the origins (id, initial position: the reference of the shrinkage),
 * f64 green density; from version 15 on the periodic cell (qs_periodic.c): u64 mask of the
 * periodic axes, f64 lower corner[3], lengths now[3], lengths at the start[3], u64 1 once the
 * start's lengths are taken. Each link carries its image (version 15's link layout; the links
 * of earlier files, without it, are read with image 0).
 *
 * Keyed by ids (issue 43; checkpoint version 11): the plane conditions and displacements are per
 * particle in order of ascending id (the stepper's slots, qs_ids.c), and a restore finds the two
 * particles of each link by its ids (the indices stored in its beam are not read), so the section
 * fits the particles in any order. Files of versions 3 to 10 hold the plane conditions and
 * displacements in the order of the particles' indices (the same order when the ids ascend);
 * sinter_qs_state_restore reorders them (by_index).
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "stepper/qs_struct.h"

enum { QS_HEADER_U64 = 2, QS_TAIL_BYTES = 4 * 8 + 4 * 8 }; /* extent0, dt_next; 4 counters */
enum { QS_CELL_BYTES = 8 + 9 * 8 + 8 };                    /* mask, lo, len, len0, started */

static size_t fixed_bytes(const sinter_qs *qs)
{
    return qs->particles != SIZE_MAX && qs->fixed != NULL ? 6 * qs->particles : 0;
}

static size_t u_bytes(const sinter_qs *qs)
{
    return qs->u_step > 0.0 && fixed_bytes(qs) > 0 ? fixed_bytes(qs) * sizeof(double) : 0;
}

size_t sinter_qs_state_size(const sinter_qs *qs)
{
    return QS_HEADER_U64 * 8 + qs->count * sizeof(sinter_qs_link) + 16 + fixed_bytes(qs) +
           QS_TAIL_BYTES + 8 + u_bytes(qs) + 8 + qs->origin_count * sizeof(sinter_qs_origin) + 8 +
           QS_CELL_BYTES;
}

static unsigned char *put(unsigned char *p, const void *data, size_t bytes)
{
    if (bytes > 0)
        memcpy(p, data, bytes);
    return p + bytes;
}

static unsigned char *put_u64(unsigned char *p, uint64_t v)
{
    return put(p, &v, 8);
}

void sinter_qs_state_save(const sinter_qs *qs, unsigned char *out)
{
    unsigned char *p = out;
    p = put_u64(p, sizeof(sinter_qs_link));
    p = put_u64(p, qs->count);
    for (size_t k = 0; k < qs->count; ++k) {
        /* a copy with the padding zeroed, so equal states give equal bytes (and checksums) */
        sinter_qs_link l;
        memset(&l, 0, sizeof(l));
        l.beam = qs->links[k].beam;
        l.neck = qs->links[k].neck;
        l.rm = qs->links[k].rm;
        l.youngs = qs->links[k].youngs;
        l.material = qs->links[k].material;
        l.substepped = qs->links[k].substepped;
        l.id_a = qs->links[k].id_a;
        l.id_b = qs->links[k].id_b;
        l.born = qs->links[k].born;
        memcpy(l.image, qs->links[k].image, sizeof(l.image));
        p = put(p, &l, sizeof(l));
    }
    p = put_u64(p, qs->particles == SIZE_MAX ? UINT64_MAX : (uint64_t)qs->particles);
    p = put_u64(p, fixed_bytes(qs));
    p = put(p, qs->fixed, fixed_bytes(qs));
    p = put(p, qs->extent0, sizeof(qs->extent0));
    p = put(p, &qs->dt_next, 8);
    p = put_u64(p, qs->steps);
    p = put_u64(p, qs->rejected);
    p = put_u64(p, qs->pcg_iterations);
    p = put_u64(p, qs->substepped);
    const double u_step = u_bytes(qs) > 0 ? qs->u_step : 0.0;
    p = put(p, &u_step, 8);
    p = put(p, qs->u, u_bytes(qs));
    p = put_u64(p, qs->origin_count);
    p = put(p, qs->origins, qs->origin_count * sizeof(sinter_qs_origin));
    p = put(p, &qs->density0, 8);
    p = put_u64(p, (uint64_t)(qs->periodic[0] | qs->periodic[1] << 1 | qs->periodic[2] << 2));
    p = put(p, qs->cell_lo, sizeof(qs->cell_lo));
    p = put(p, qs->cell_len, sizeof(qs->cell_len));
    p = put(p, qs->cell_len0, sizeof(qs->cell_len0));
    (void)put_u64(p, (uint64_t)qs->cell_started);
}

typedef struct cursor {
    const unsigned char *p, *end;
    int bad;
} cursor;

static const void *take(cursor *c, size_t bytes)
{
    if (c->bad || (size_t)(c->end - c->p) < bytes) {
        c->bad = 1;
        return NULL;
    }
    const void *at = c->p;
    c->p += bytes;
    return at;
}

static uint64_t take_u64(cursor *c)
{
    uint64_t v = 0;
    const void *at = take(c, 8);
    if (at != NULL)
        memcpy(&v, at, 8);
    return v;
}

const char *sinter_qs_link_numbers_wrong(const sinter_qs_link *l)
{
    for (int k = 0; k < SINTER_NECK_DOF; ++k)
        if (!isfinite(l->neck.y[k]) || !(l->neck.y[k] > 0.0))
            return "a quasi-static link's neck state is not finite and > 0";
    const double v[] = {l->neck.time,
                        l->neck.center_distance0,
                        l->neck.last_dy4,
                        l->neck.last_dy7,
                        l->neck.step_hint,
                        l->rm,
                        l->youngs,
                        l->beam.arm_a,
                        l->beam.arm_b,
                        l->beam.k_axial,
                        l->beam.k_shear,
                        l->beam.k_bend,
                        l->beam.k_torsion,
                        l->beam.axis[0],
                        l->beam.axis[1],
                        l->beam.axis[2],
                        l->born};
    for (size_t k = 0; k < sizeof(v) / sizeof(v[0]); ++k)
        if (!isfinite(v[k]))
            return "a quasi-static link holds a number that is not finite";
    if (!(l->rm > 0.0) || !(l->youngs > 0.0) || !(l->neck.center_distance0 > 0.0) ||
        !(l->born <= l->neck.time))
        return "a quasi-static link's lengths or times are out of their range";
    return NULL;
}

/* A link's particles (found by id in qs's map: their indices go into the beam) and its numbers
 * are usable: two particles that exist, lengths finite and positive. */
static int link_ok(const sinter_qs *qs, sinter_qs_link *l)
{
    const size_t a = sinter_qs_slot_of_id(qs, l->id_a), b = sinter_qs_slot_of_id(qs, l->id_b);
    if (a == SIZE_MAX || b == SIZE_MAX || a == b)
        return 0;
    l->beam.a = qs->index_of_slot[a];
    l->beam.b = qs->index_of_slot[b];
    return sinter_qs_link_numbers_wrong(l) == NULL;
}

sinter_status sinter_qs_state_restore(sinter_qs **out, sinter_ctx *ctx,
                                      const sinter_qs_options *opt, const unsigned char *data,
                                      size_t bytes, size_t n, const void *ids, int by_index,
                                      int with_cell, const char **why)
{
    *out = NULL;
    *why = NULL;
    cursor c = {data, data + bytes, 0};
    const uint64_t link_size = take_u64(&c), count = take_u64(&c);
    /* before version 15 the links end before their image */
    const size_t old_size = offsetof(sinter_qs_link, image);
    if (!c.bad && link_size != sizeof(sinter_qs_link) && (with_cell || link_size != old_size)) {
        *why = "its quasi-static links were written by a build with another link layout";
        return SINTER_ERR_CORRUPT;
    }
    if (c.bad || count > bytes / link_size) {
        *why = "its quasi-static section does not fit its size";
        return SINTER_ERR_CORRUPT;
    }
    const unsigned char *links = take(&c, (size_t)count * (size_t)link_size);
    const uint64_t particles = take_u64(&c), nfixed = take_u64(&c);
    const unsigned char *fixed = nfixed <= bytes ? take(&c, (size_t)nfixed) : NULL;
    double tail[4];
    uint64_t counters[4];
    const void *tail_at = take(&c, sizeof(tail));
    const void *counters_at = take(&c, sizeof(counters));
    double u_step = 0.0;
    const void *u_step_at = take(&c, 8);
    if (u_step_at != NULL)
        memcpy(&u_step, u_step_at, 8);
    const size_t nu = u_step > 0.0 ? (size_t)nfixed * sizeof(double) : 0;
    const unsigned char *u = nu <= bytes ? take(&c, nu) : NULL;
    const uint64_t norigins = take_u64(&c);
    const unsigned char *origins = norigins <= bytes / sizeof(sinter_qs_origin)
                                       ? take(&c, (size_t)norigins * sizeof(sinter_qs_origin))
                                       : NULL;
    if (origins == NULL)
        c.bad = 1;
    double density0 = 0.0;
    const void *density0_at = take(&c, 8);
    if (density0_at != NULL)
        memcpy(&density0, density0_at, 8);
    if (!(density0 >= 0.0 && density0 < 1.0))
        c.bad = 1;
    uint64_t cell_mask = 0, cell_started = 0;
    double cell[9] = {0};
    if (with_cell) {
        cell_mask = take_u64(&c);
        const void *cell_at = take(&c, sizeof(cell));
        if (cell_at != NULL)
            memcpy(cell, cell_at, sizeof(cell));
        cell_started = take_u64(&c);
    }
    if (c.bad || fixed == NULL || c.p != c.end || !(u_step >= 0.0 && isfinite(u_step)) ||
        (u_step > 0.0 && (nfixed == 0 || u == NULL))) {
        *why = "its quasi-static section does not fit its size";
        return SINTER_ERR_CORRUPT;
    }
    memcpy(tail, tail_at, sizeof(tail));
    memcpy(counters, counters_at, sizeof(counters));
    if ((particles != UINT64_MAX && particles != 0 && particles != n) ||
        (nfixed != 0 && nfixed != 6 * (uint64_t)n) || (nfixed != 0 && particles != n)) {
        *why = "its quasi-static plane conditions are for another number of particles";
        return SINTER_ERR_CORRUPT;
    }
    for (uint64_t k = 0; k < nfixed; ++k)
        if (fixed[k] > 1) {
            *why = "its quasi-static plane conditions hold values other than 0 and 1";
            return SINTER_ERR_CORRUPT;
        }
    for (int d = 0; d < 3; ++d)
        if (cell_mask > 7u || cell_started > 1u ||
            ((cell_mask >> d) & 1u
                 ? !(isfinite(cell[d]) && cell[3 + d] > 0.0 && isfinite(cell[3 + d]) &&
                     cell[6 + d] > 0.0 && isfinite(cell[6 + d]))
                 : (cell[d] != 0.0 || cell[3 + d] != 0.0))) {
            *why = "its quasi-static periodic cell is not a finite positive box";
            return SINTER_ERR_CORRUPT;
        }
    for (int d = 0; d < 3; ++d)
        if (!isfinite(tail[d]) || tail[d] < 0.0) {
            *why = "its quasi-static initial extents are not finite and >= 0";
            return SINTER_ERR_CORRUPT;
        }
    if (!(tail[3] > 0.0) || !isfinite(tail[3])) {
        *why = "its quasi-static next step is not finite and > 0";
        return SINTER_ERR_CORRUPT;
    }
    sinter_qs *qs = NULL;
    sinter_status s = sinter_qs_create(&qs, ctx, opt);
    if (s != SINTER_OK)
        return s;
    /* the particles' id order (the ids may sit unaligned in a file buffer) */
    uint64_t *id_copy = sinter_alloc(ctx, (n + 1) * sizeof(uint64_t));
    if (id_copy == NULL) {
        sinter_qs_destroy(qs);
        return SINTER_ERR_NOMEM;
    }
    for (size_t i = 0; i < n; ++i) {
        if (ids != NULL)
            memcpy(&id_copy[i], (const unsigned char *)ids + 8 * i, 8);
        else
            id_copy[i] = i;
    }
    s = sinter_qs_slots_make(qs, n, id_copy);
    sinter_free(ctx, id_copy);
    if (s == SINTER_ERR_INVALID) {
        sinter_qs_destroy(qs);
        *why = "two of its particles have the same id";
        return SINTER_ERR_CORRUPT;
    }
    if (s == SINTER_OK && count > 0) {
        s = sinter_grow(ctx, (void **)&qs->links, &qs->capacity, (size_t)count,
                        sizeof(sinter_qs_link));
        if (s == SINTER_OK)
            s = sinter_grow(ctx, (void **)&qs->keys, &qs->keys_capacity, (size_t)count,
                            sizeof(sinter_qs_pair));
    }
    if (s == SINTER_OK && nfixed > 0)
        s = sinter_grow(ctx, (void **)&qs->fixed, &qs->fixed_capacity, (size_t)nfixed, 1);
    /* the step's work arrays the set-up would have made (it is skipped for stored conditions) */
    if (s == SINTER_OK && nfixed > 0)
        s = sinter_grow(ctx, (void **)&qs->f, &qs->f_capacity, (size_t)nfixed + 1, sizeof(double));
    if (s == SINTER_OK && nfixed > 0)
        s = sinter_grow(ctx, (void **)&qs->u, &qs->u_capacity, (size_t)nfixed + 1, sizeof(double));
    if (s != SINTER_OK) {
        sinter_qs_destroy(qs);
        return s;
    }
    for (uint64_t k = 0; k < count; ++k) {
        sinter_qs_link *l = &qs->links[k];
        memset(l, 0, sizeof(*l));
        memcpy(l, links + k * (size_t)link_size, (size_t)link_size);
        int image_ok = 1; /* an image only along a periodic axis, within a few periods */
        for (int d = 0; d < 3; ++d)
            image_ok =
                image_ok && (((cell_mask >> d) & 1u) ? abs(l->image[d]) <= 2 : l->image[d] == 0);
        if (!image_ok || !link_ok(qs, l)) {
            sinter_qs_destroy(qs);
            *why = "a quasi-static link names particles that do not exist or holds non-finite "
                   "or non-positive lengths";
            return SINTER_ERR_CORRUPT;
        }
        qs->keys[k] = sinter_qs_pair_of(l->id_a, l->id_b);
    }
    qs->count = (size_t)count;
    qsort(qs->keys, qs->count, sizeof(sinter_qs_pair), sinter_qs_pair_compare);
    for (size_t k = 1; k < qs->count; ++k)
        if (sinter_qs_pair_compare(&qs->keys[k], &qs->keys[k - 1]) == 0) {
            sinter_qs_destroy(qs);
            *why = "two quasi-static links join the same pair of particles";
            return SINTER_ERR_CORRUPT;
        }
    /* per slot; by_index: from the order of the particles' indices */
    for (size_t sl = 0; sl < (size_t)nfixed / 6; ++sl)
        memcpy(qs->fixed + 6 * sl, fixed + 6 * (by_index ? (size_t)qs->index_of_slot[sl] : sl), 6);
    if (norigins > 0) {
        if ((s = sinter_grow(ctx, (void **)&qs->origins, &qs->origin_capacity, (size_t)norigins,
                             sizeof(sinter_qs_origin))) != SINTER_OK) {
            sinter_qs_destroy(qs);
            return s;
        }
        memcpy(qs->origins, origins, (size_t)norigins * sizeof(sinter_qs_origin));
        for (size_t k = 0; k < (size_t)norigins; ++k)
            if (!isfinite(qs->origins[k].x[0]) || !isfinite(qs->origins[k].x[1]) ||
                !isfinite(qs->origins[k].x[2]) ||
                (k > 0 && qs->origins[k].id <= qs->origins[k - 1].id)) {
                sinter_qs_destroy(qs);
                *why = "its quasi-static initial positions are not finite or not sorted by id";
                return SINTER_ERR_CORRUPT;
            }
        qs->origin_count = (size_t)norigins;
    }
    qs->density0 = density0;
    if (nu > 0) {
        for (size_t sl = 0; sl < (size_t)nfixed / 6; ++sl)
            memcpy(qs->u + 6 * sl, u + 6 * sizeof(double) * (by_index ? qs->index_of_slot[sl] : sl),
                   6 * sizeof(double));
        for (size_t i = 0; i < (size_t)nfixed; ++i)
            if (!isfinite(qs->u[i])) {
                sinter_qs_destroy(qs);
                *why = "its quasi-static displacements are not finite";
                return SINTER_ERR_CORRUPT;
            }
        qs->u_step = u_step;
    }
    qs->particles = particles == UINT64_MAX ? SIZE_MAX : (size_t)particles;
    if (nfixed == 0 && qs->particles == n && n > 0)
        qs->particles = SIZE_MAX; /* no stored conditions: detect them at the next step */
    memcpy(qs->extent0, tail, sizeof(qs->extent0));
    qs->dt_next = tail[3];
    qs->steps = counters[0];
    qs->rejected = counters[1];
    qs->pcg_iterations = counters[2];
    qs->substepped = counters[3];
    for (int d = 0; d < 3; ++d) {
        qs->periodic[d] = (int)((cell_mask >> d) & 1u);
        qs->cell_lo[d] = cell[d];
        qs->cell_len[d] = cell[3 + d];
        qs->cell_len0[d] = cell[6 + d];
    }
    qs->cell_started = (int)cell_started;
    *out = qs;
    return SINTER_OK;
}
