/*
 * Particle pairs proven out of contact (pair_skip.h): the keys' validity and the travel.
 */
#include "contact/pair_skip.h"

#include <math.h>
#include <string.h>

void sinter_pair_skip_free(sinter_ctx *ctx, sinter_pair_skip *s)
{
    sinter_free(ctx, s->key);
    memset(s, 0, sizeof(*s));
}

void sinter_pair_skip_moved(sinter_pair_skip *s, double step2)
{
    s->travel += 2.0 * sqrt(step2); /* NaN (a rejected step): every pair tested, keys dropped */
    s->moved = 1;
}

void sinter_pair_skip_drop(sinter_pair_skip *s)
{
    s->valid = 0;
    s->moved = 0;
}

double *sinter_pair_skip_begin(sinter_ctx *ctx, sinter_pair_skip *s, const sinter_pair_list *pairs,
                               const sinter_particles *ps, double *travel)
{
    const int holds = s->valid && s->moved && s->build_id == pairs->build_id &&
                      s->pair_count == pairs->count && s->layout == ps->layout_generation &&
                      s->write == ps->write_generation && s->particles == ps->count &&
                      s->travel < INFINITY; /* (false for NaN) */
    s->moved = 0;
    if (!holds) {
        s->valid = 0;
        if (sinter_grow(ctx, (void **)&s->key, &s->capacity, pairs->count + 1, sizeof(double)) !=
            SINTER_OK) {
            sinter_clear_error(ctx); /* no room for keys: every pair tested */
            return NULL;
        }
        memset(s->key, 0, pairs->count * sizeof(double)); /* 0 <= T: tested */
        s->travel = 0.0;
        s->build_id = pairs->build_id;
        s->pair_count = pairs->count;
        s->layout = ps->layout_generation;
        s->write = ps->write_generation;
        s->particles = ps->count;
        s->valid = 1;
    }
    *travel = s->travel;
    return s->key;
}
