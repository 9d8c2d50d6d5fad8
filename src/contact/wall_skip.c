/*
 * Plane walls proven out of reach (wall_skip.h): the certificate, its bound and the pairs
 * left to test.
 */
#include "contact/wall_skip.h"

#include <math.h>
#include <string.h>

void sinter_wall_skip_free(sinter_ctx *ctx, sinter_wall_skip *s)
{
    sinter_free(ctx, s->active);
    memset(s, 0, sizeof(*s));
}

void sinter_wall_skip_moved(sinter_wall_skip *s, const double axis2[3])
{
    for (int d = 0; d < 3; ++d)
        s->travel[d] += sqrt(axis2[d]); /* NaN (a rejected step) keeps every wall tested */
    s->moved = 1;
}

void sinter_wall_skip_begin(sinter_wall_skip *s)
{
    if (!s->moved)
        s->valid = 0;
    s->moved = 0;
}

/* d when n is +e_d or -e_d exactly, else -1. */
static int axis_of(const double *n)
{
    for (int d = 0; d < 3; ++d) {
        const int e = d == 0 ? 1 : 0, f = d == 2 ? 1 : 2;
        if (fabs(n[d]) == 1.0 && n[e] == 0.0 && n[f] == 0.0)
            return d;
    }
    return -1;
}

/* 1 while wall k, certified with gap g and scale S, is still out of reach of every candidate
 * (the bound of wall_skip.h, written so that a NaN anywhere fails it). */
static int out_of_reach(const sinter_wall_skip *s, const sinter_wall *w, size_t k)
{
    const int d = s->axis[k];
    const double t = s->travel[d], dp = fabs(w->p[d] - s->p[k][d]);
    return s->gap[k] - t - dp > 1e-9 * (s->scale[k] + t + dp);
}

/* The candidate pairs of the walls not in the mask, ascending. */
static void list_active(sinter_wall_skip *s, const sinter_pair_list *pairs)
{
    size_t m = 0;
    for (size_t p = 0; p < pairs->count; ++p) {
        const uint32_t k = pairs->j[p];
        if (k >= SINTER_WALL_SKIP_MAX || !(s->mask >> k & 1u))
            s->active[m++] = (uint32_t)p;
    }
    s->active_count = m;
}

int sinter_wall_skip_holds(sinter_wall_skip *s, const sinter_pair_list *pairs,
                           const sinter_particles *ps, const sinter_walls *walls)
{
    if (!s->valid || s->build_id != pairs->build_id || s->pair_count != pairs->count ||
        s->layout != ps->layout_generation || s->write != ps->write_generation ||
        s->particles != ps->count || s->walls != walls || s->wall_count != walls->count) {
        s->valid = 0;
        return 0;
    }
    uint64_t mask = s->mask;
    for (size_t k = 0; k < walls->count && k < SINTER_WALL_SKIP_MAX; ++k) {
        if (!(mask >> k & 1u))
            continue;
        const sinter_wall *w = &walls->wall[k];
        if (w->kind != SINTER_WALL_PLANE || memcmp(w->n, s->n[k], sizeof(w->n)) != 0) {
            s->valid = 0; /* a wall turned or changed kind: take it again */
            return 0;
        }
        if (!out_of_reach(s, w, k))
            mask &= ~((uint64_t)1 << k);
    }
    if (mask != s->mask) { /* walls come within reach: their pairs tested from now on */
        s->mask = mask;
        list_active(s, pairs);
    }
    return s->mask != 0;
}

sinter_status sinter_wall_skip_take(sinter_ctx *ctx, sinter_wall_skip *s,
                                    const sinter_pair_list *pairs, const sinter_particles *ps,
                                    const sinter_walls *walls, int ascending)
{
    s->valid = 0;
    sinter_status st = sinter_grow(ctx, (void **)&s->active, &s->active_capacity, pairs->count + 1,
                                   sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    const size_t nw = walls->count < SINTER_WALL_SKIP_MAX ? walls->count : SINTER_WALL_SKIP_MAX;
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *w = &walls->wall[k];
        s->axis[k] = w->kind == SINTER_WALL_PLANE ? axis_of(w->n) : -1;
        s->gap[k] = INFINITY;
        s->scale[k] = 0.0;
        memcpy(s->p[k], w->p, sizeof(w->p));
        memcpy(s->n[k], w->n, sizeof(w->n));
    }
    const double *x = ps->x, *r = ps->radius;
    for (size_t p = 0; p < pairs->count; ++p) {
        const uint32_t i = pairs->i[p], k = pairs->j[p];
        if (k >= nw || s->axis[k] < 0)
            continue;
        const double sd = sinter_plane_distance(&walls->wall[k], x + 3 * i), g = sd - r[i],
                     a = fabs(sd) + r[i];
        s->gap[k] = g < s->gap[k] || g != g ? g : s->gap[k]; /* NaN: not certified */
        s->scale[k] = a > s->scale[k] ? a : s->scale[k];
    }
    s->travel[0] = s->travel[1] = s->travel[2] = 0.0;
    s->mask = 0;
    for (size_t k = 0; k < nw; ++k)
        if (s->axis[k] >= 0 && out_of_reach(s, &walls->wall[k], k))
            s->mask |= (uint64_t)1 << k;
    list_active(s, pairs);
    s->build_id = pairs->build_id;
    s->pair_count = pairs->count;
    s->layout = ps->layout_generation;
    s->write = ps->write_generation;
    s->particles = ps->count;
    s->walls = walls;
    s->wall_count = walls->count;
    s->ascending = ascending;
    s->valid = 1;
    return SINTER_OK;
}
