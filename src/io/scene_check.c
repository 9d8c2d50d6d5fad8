/*
 * sinter_scene_check: the checks a run makes before its first step, without stepping. The
 * output plan (the interval must advance the time; at most max_frames records), the
 * particles' values, and the starting state the steppers refuse: particles behind a wall, two
 * particles with the same centre, particles outside the domain.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/scene.h"
#include "walls/walls.h"

sinter_status sinter_scene_check_output(sinter_ctx *ctx, double end_time, double pour_time,
                                        double interval, double max_frames)
{
    /* the last time the run records at (a pour ends by t_max, and the run follows it) */
    const double last = end_time + pour_time;
    if (!(last + interval > last))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "output interval %g s cannot advance the time at t = %g s (t + "
                           "interval == t in double precision): the run would never end",
                           interval, last);
    const double records = 1.0 + ceil(pour_time / interval) + ceil(end_time / interval);
    if (records > max_frames)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "output interval %g s makes %.3g records (rows of series.csv and VTU "
                           "frames) over %g s, more than max_frames = %.15g; raise the "
                           "interval or max_frames",
                           interval, records, last, max_frames);
    return SINTER_OK;
}

static sinter_status check_walls(const sinter_scene *sc)
{
    const sinter_particles *ps = sc->ps;
    for (size_t j = 0; j < sc->walls->count; ++j) {
        const sinter_wall *w = &sc->walls->wall[j];
        for (size_t i = 0; i < ps->count; ++i) {
            const double s = sinter_wall_distance(w, ps->x + 3 * i);
            if (s < 0.0)
                return sinter_fail(sc->ctx, SINTER_ERR_INVALID,
                                   "particle %zu (id %llu) is behind wall %zu (%s): its centre is "
                                   "%g m on the wrong side of the plane through (%g, %g, %g) m "
                                   "with normal (%g, %g, %g); particles must start on the side "
                                   "the normal points to",
                                   i, (unsigned long long)ps->id[i], j, sc->wall_names[j], -s,
                                   w->p[0], w->p[1], w->p[2], w->n[0], w->n[1], w->n[2]);
        }
    }
    return SINTER_OK;
}

static sinter_status check_domain(const sinter_scene *sc)
{
    const sinter_stepper *st = sc->st;
    const sinter_particles *ps = sc->ps;
    for (size_t i = 0; st->has_domain && i < ps->count; ++i)
        for (int d = 0; d < 3; ++d) {
            const double x = ps->x[3 * i + d];
            if (!(x >= st->domain_lo[d] && x <= st->domain_hi[d]))
                return sinter_fail(sc->ctx, SINTER_ERR_INVALID,
                                   "particle %zu (id %llu) starts outside the domain: %c = %g m "
                                   "(domain %g m to %g m)",
                                   i, (unsigned long long)ps->id[i], "xyz"[d], x,
                                   st -> domain_lo[d], st -> domain_hi[d]);
        }
    return SINTER_OK;
}

typedef struct centre {
    double x[3];
    size_t index;
} centre;

static int by_position(const void *a, const void *b)
{
    const centre *p = a, *q = b;
    for (int d = 0; d < 3; ++d)
        if (p->x[d] != q->x[d])
            return p->x[d] < q->x[d] ? -1 : 1;
    return p->index < q->index ? -1 : p->index > q->index;
}

/* Two particles with the same centre, found by sorting the centres. */
static sinter_status check_coincident(const sinter_scene *sc)
{
    const sinter_particles *ps = sc->ps;
    if (ps->count < 2)
        return SINTER_OK;
    centre *c = sinter_calloc(sc->ctx, ps->count, sizeof(centre));
    if (c == NULL)
        return sinter_last_status(sc->ctx);
    for (size_t i = 0; i < ps->count; ++i) {
        memcpy(c[i].x, ps->x + 3 * i, sizeof(c[i].x));
        c[i].index = i;
    }
    qsort(c, ps->count, sizeof(centre), by_position);
    sinter_status st = SINTER_OK;
    for (size_t k = 1; k < ps->count && st == SINTER_OK; ++k) {
        if (!(c[k - 1].x[0] == c[k].x[0] && c[k - 1].x[1] == c[k].x[1] &&
              c[k - 1].x[2] == c[k].x[2]))
            continue;
        const size_t i = c[k - 1].index, j = c[k].index;
        st = sinter_fail(sc->ctx, SINTER_ERR_INVALID,
                         "particles %zu and %zu (ids %llu and %llu) have the same centre (%g, %g, "
                         "%g) m: their contact normal is undefined; move one of them",
                         i, j, (unsigned long long)ps->id[i], (unsigned long long)ps->id[j],
                         c[k].x[0], c[k].x[1], c[k].x[2]);
    }
    sinter_free(sc->ctx, c);
    return st;
}

sinter_status sinter_scene_check(const sinter_scene *sc)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    sinter_status st =
        sinter_scene_check_output(sc->ctx, sc->end_time, sc->pour ? sc->pour_t_max : 0.0,
                                  sc->output_interval, sc->max_frames);
    if (st != SINTER_OK)
        return st;
    if (sc->ps->views_out > 0)
        return sinter_fail(sc->ctx, SINTER_ERR_BUSY,
                           "sinter_scene_check: %zu field view(s) of the particle set are out; "
                           "release them before running",
                           sc->ps->views_out);
    st = sinter_particles_validate(sc->ps, NULL);
    /* [compact] without [pour] replaces the positions before the first step: nothing more to
     * check now. The quasi-static stepper has neither contact laws nor a domain. */
    if (st != SINTER_OK || (sc->compact && !sc->pour) || sc->st->kind == SINTER_STEPPER_QUASISTATIC)
        return st;
    st = check_walls(sc);
    if (st == SINTER_OK)
        st = check_domain(sc);
    if (st == SINTER_OK)
        st = check_coincident(sc);
    return st;
}
