/* Every subdomain's records to every subdomain (domain.h, sinter_domain_allgather). */
#include "domain/domain.h"

#include <string.h>

/* The failure flag rides in the exscan's total: a count above it is a failure somewhere. */
static const uint64_t FAILED = (uint64_t)1 << 48;

sinter_status sinter_domain_allgather(sinter_ctx *ctx, sinter_domain *d, sinter_status s,
                                      const double *mine, size_t count, size_t width, double **all,
                                      size_t *total, size_t *first)
{
    *all = NULL;
    *total = 0;
    *first = 0;
    uint64_t before = 0, sum = 0;
    const uint64_t value = (uint64_t)count + (s != SINTER_OK ? FAILED : 0);
    d->reductions++;
    if (d->ops.exscan(value, &before, &sum, d->user) != 0)
        return sinter_fail(ctx, SINTER_ERR_CALLBACK, "the host's exscan callback failed");
    if (sum >= FAILED) /* every subdomain is here: agree the code and the message */
        return sinter_domain_agree(ctx, d, s);
    /* (no failure anywhere: before and sum are plain counts) */
    const size_t n = (size_t)sum * width;
    uint64_t *buf = sinter_calloc(ctx, n + 1, sizeof(uint64_t));
    double *out = sinter_alloc(ctx, (n + 1) * sizeof(double));
    sinter_status r =
        sinter_domain_agree(ctx, d, buf == NULL || out == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
    if (r != SINTER_OK) {
        sinter_free(ctx, buf);
        sinter_free(ctx, out);
        return r;
    }
    /* the bits of this subdomain's records in its slots, zeros elsewhere: an integer sum of
     * one non-zero word and zeros is that word, whatever order the host adds them in */
    if (count > 0)
        memcpy(buf + (size_t)before * width, mine, count * width * sizeof(double));
    r = n > 0 ? sinter_domain_reduce(ctx, d, buf, n, SINTER_REDUCE_U64, SINTER_REDUCE_SUM)
              : SINTER_OK;
    if (r == SINTER_OK && n > 0)
        memcpy(out, buf, n * sizeof(double));
    sinter_free(ctx, buf);
    if (r != SINTER_OK) {
        sinter_free(ctx, out);
        return r;
    }
    *all = out;
    *total = (size_t)sum;
    *first = (size_t)before;
    return SINTER_OK;
}
