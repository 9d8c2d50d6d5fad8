/* Exact sums over every caller of a reduce callback: see exact_sums.h. */
#include "mpi/exact_sums.h"

#include <math.h>
#include <string.h>

int sinter_mpi_weights_exponent(const double *weights, size_t n, int *bad)
{
    if (n == 0)
        return INT32_MIN;
    if (weights == NULL) {
        const double one = 1.0;
        return sinter_repro_exponent(&one, 1, 1, NULL);
    }
    for (size_t k = 0; k < n; ++k)
        if (!(weights[k] >= 0.0) || !isfinite(weights[k]))
            *bad = 1;
    return sinter_repro_exponent(weights, n, 1, NULL);
}

sinter_status sinter_mpi_agree_max(int64_t *values, size_t count, sinter_mpi_reduce_fn reduce,
                                   void *user)
{
    if (reduce == NULL)
        return SINTER_OK;
    const int rc = reduce(values, count, SINTER_MPI_I64, SINTER_MPI_MAX, user);
    return rc == 0 ? SINTER_OK : (sinter_status)rc;
}

sinter_status sinter_mpi_bins_reduce(sinter_repro_sum *sums, size_t bins, int64_t *scratch,
                                     sinter_mpi_reduce_fn reduce, void *user)
{
    const sinter_repro_sum zero = {{0}, 0};
    for (size_t b = 0; b < bins; ++b)
        sinter_repro_merge(&sums[b], &zero); /* carry: limbs 1.. in [0, 2^40), terms 0 */
    if (reduce == NULL)
        return SINTER_OK;
    for (size_t b = 0; b < bins; ++b)
        memcpy(scratch + b * SINTER_REPRO_LIMBS, sums[b].limb, sizeof sums[b].limb);
    const int rc = reduce(scratch, bins * SINTER_REPRO_LIMBS, SINTER_MPI_I64, SINTER_MPI_SUM, user);
    if (rc != 0)
        return (sinter_status)rc;
    for (size_t b = 0; b < bins; ++b) {
        memcpy(sums[b].limb, scratch + b * SINTER_REPRO_LIMBS, sizeof sums[b].limb);
        sums[b].terms = 0;
    }
    return SINTER_OK;
}
