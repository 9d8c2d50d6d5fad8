/*
 * A subdomain's share of the coarse-grained fields (sinter_coarse_sums, issue 44): the sums
 * sinter_coarse_grain forms its quantities from, of the owned particles and of the contacts
 * whose smaller id is owned, so that summing them over the subdomains counts every particle
 * and every contact once; sinter_write_vti_sums (io/vti.c) forms the fields after the sum.
 */
#include <sinter_domain.h>

#include "fields/coarse_grain.h"
#include "particles/particles.h"

_Static_assert(SINTER_COARSE_SUMS == SINTER_COARSE_PARTICLE_SUMS + 9,
               "the public count of sums is the particle sums and the stress");

sinter_status sinter_coarse_sums(const sinter_particles *ps, const sinter_snapshot *snapshot,
                                 const sinter_coarse_options *options, double *sums,
                                 size_t sums_count)
{
    static const char *const fn = "sinter_coarse_sums";
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    SINTER_CHECK_NULL(ctx, options);
    SINTER_CHECK_NULL(ctx, sums);
    sinter_status st = sinter_coarse_check(ctx, fn, options);
    if (st != SINTER_OK)
        return st;
    const size_t points = options->points[0] * options->points[1] * options->points[2];
    if (sums_count != points * SINTER_COARSE_SUMS)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: sums_count is %zu, the grid's %zu points need %zu", fn, sums_count,
                           points, points * SINTER_COARSE_SUMS);
    return sinter_coarse_accumulate(ps, snapshot, options, ps->count - ps->ghost_count, sums);
}
