/* The host's collective operations as stages of the step (domain.h). */
#include "domain/domain.h"
#include "ghosts/ghosts.h"

#include <string.h>

void sinter_domain_free(sinter_ctx *ctx, sinter_domain *d)
{
    if (d->on && d->ops.destroy_user != NULL)
        d->ops.destroy_user(d->user);
    sinter_free(ctx, d->halo);
    sinter_free(ctx, d->arrived_id);
    sinter_free(ctx, d->arrived_rows);
    memset(d, 0, sizeof(*d));
    d->rank = -1;
}

sinter_status sinter_domain_reduce(sinter_ctx *ctx, sinter_domain *d, void *values, size_t count,
                                   int type, int op)
{
    d->reductions++;
    if (d->ops.reduce(values, count, type, op, d->user) != 0)
        return sinter_fail(ctx, SINTER_ERR_CALLBACK,
                           "the host's reduce callback failed (%zu values, type %d, op %d)", count,
                           type, op);
    return SINTER_OK;
}

/* This subdomain's number: the exclusive prefix sum of 1 (collective). */
static sinter_status find_rank(sinter_ctx *ctx, sinter_domain *d)
{
    if (d->rank >= 0)
        return SINTER_OK;
    uint64_t before = 0, total = 0;
    if (d->ops.exscan(1, &before, &total, d->user) != 0)
        return sinter_fail(ctx, SINTER_ERR_CALLBACK, "the host's exscan callback failed");
    d->rank = (long)before;
    return SINTER_OK;
}

sinter_status sinter_domain_rank(sinter_ctx *ctx, sinter_domain *d, long *rank)
{
    const sinter_status s = find_rank(ctx, d);
    *rank = d->rank;
    return s;
}

enum { TEXT_WORDS = SINTER_ERROR_TEXT_SIZE / 8 };

sinter_status sinter_domain_agree(sinter_ctx *ctx, sinter_domain *d, sinter_status s)
{
    if (!d->on)
        return s;
    int64_t code = (int64_t)s;
    sinter_status r = sinter_domain_reduce(ctx, d, &code, 1, SINTER_REDUCE_I64, SINTER_REDUCE_MIN);
    if (r != SINTER_OK)
        return r;
    if (code >= 0)
        return SINTER_OK;
    /* every subdomain is on this path: the reporter is the lowest-numbered one with that code,
     * and its message goes to all (a MAX over words that the others leave at zero) */
    if ((r = find_rank(ctx, d)) != SINTER_OK)
        return r;
    int64_t who = (int64_t)s == code ? (int64_t)d->rank : INT64_MAX;
    if ((r = sinter_domain_reduce(ctx, d, &who, 1, SINTER_REDUCE_I64, SINTER_REDUCE_MIN)) !=
        SINTER_OK)
        return r;
    uint64_t words[TEXT_WORDS];
    memset(words, 0, sizeof(words));
    if (who == (int64_t)d->rank)
        memcpy(words, ctx->last_error, sizeof(words));
    if ((r = sinter_domain_reduce(ctx, d, words, TEXT_WORDS, SINTER_REDUCE_U64,
                                  SINTER_REDUCE_MAX)) != SINTER_OK)
        return r;
    char text[SINTER_ERROR_TEXT_SIZE];
    memcpy(text, words, sizeof(text));
    text[sizeof(text) - 1] = '\0';
    if (strncmp(text, "subdomain ", 10) == 0) /* agreed once already (a settled failure) */
        return sinter_fail(ctx, (sinter_status)code, "%s", text);
    return sinter_fail(ctx, (sinter_status)code, "subdomain %lld: %s", (long long)who, text);
}

sinter_status sinter_domain_agree_sum(sinter_ctx *ctx, sinter_domain *d, sinter_status s,
                                      double *values, size_t count)
{
    if (!d->on)
        return s;
    values[count] = s == SINTER_OK ? 0.0 : 1.0;
    const sinter_status r =
        sinter_domain_reduce(ctx, d, values, count + 1, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (r != SINTER_OK)
        return r;
    return values[count] > 0.0 ? sinter_domain_agree(ctx, d, s) : SINTER_OK;
}

sinter_status sinter_domain_forward(sinter_ctx *ctx, sinter_domain *d, sinter_particles *ps)
{
    const size_t images = d->periodic != NULL ? sinter_ghosts_images(d->periodic, ps) : 0;
    const size_t n = ps->count - images, owned = ps->count - ps->ghost_count,
                 w = SINTER_HALO_STATE_WIDTH;
    sinter_status s =
        sinter_grow(ctx, (void **)&d->halo, &d->halo_capacity, w * n + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    double *row = d->halo;
    for (size_t i = 0; i < owned; ++i, row += w) {
        memcpy(row, ps->x + 3 * i, 3 * sizeof(double));
        memcpy(row + 3, ps->v + 3 * i, 3 * sizeof(double));
        memcpy(row + 6, ps->w + 3 * i, 3 * sizeof(double));
        memcpy(row + 9, ps->rot + 3 * i, 3 * sizeof(double));
        row[12] = ps->temperature[i];
    }
    if ((s = sinter_domain_forward_rows(ctx, d, ps, d->halo, w)) != SINTER_OK)
        return s;
    for (size_t i = owned; i < n; ++i) {
        row = d->halo + w * i;
        memcpy(ps->x + 3 * i, row, 3 * sizeof(double));
        memcpy(ps->v + 3 * i, row + 3, 3 * sizeof(double));
        memcpy(ps->w + 3 * i, row + 6, 3 * sizeof(double));
        memcpy(ps->rot + 3 * i, row + 9, 3 * sizeof(double));
        ps->temperature[i] = row[12];
    }
    if (images > 0) /* the periodic images from their owners, the host's ghosts among them */
        sinter_ghosts_forward(d->periodic, ps);
    return SINTER_OK;
}

sinter_status sinter_domain_forward_rows(sinter_ctx *ctx, sinter_domain *d,
                                         const sinter_particles *ps, double *rows, size_t width)
{
    const size_t owned = ps->count - ps->ghost_count;
    /* (the host's ghost rows only: the periodic images come after them) */
    const size_t host =
        ps->ghost_count - (d->periodic != NULL ? sinter_ghosts_images(d->periodic, ps) : 0);
    const sinter_halo h = {.struct_size = sizeof(sinter_halo),
                           .direction = SINTER_HALO_FORWARD,
                           .width = width,
                           .data = rows,
                           .id = ps->id,
                           .owned = owned,
                           .ghosts = host};
    d->halos++;
    if (d->ops.halo(&h, d->user) != 0)
        return sinter_fail(ctx, SINTER_ERR_CALLBACK,
                           "the host's halo callback failed (forward, width %zu, %zu owned rows, "
                           "%zu ghost rows)",
                           width, owned, host);
    return SINTER_OK;
}

sinter_status sinter_domain_sum(sinter_ctx *ctx, sinter_domain *d, double *values, size_t count)
{
    if (!d->on)
        return SINTER_OK;
    return sinter_domain_reduce(ctx, d, values, count, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
}

void sinter_domain_discard_ghost_rows(sinter_particles *ps)
{
    const size_t first = ps->count - ps->ghost_count, n = ps->ghost_count;
    if (n == 0) /* (an empty set has no arrays) */
        return;
    memset(ps->force + 3 * first, 0, 3 * n * sizeof(double));
    memset(ps->torque + 3 * first, 0, 3 * n * sizeof(double));
    memset(ps->heat + first, 0, n * sizeof(double));
}
