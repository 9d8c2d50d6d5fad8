/*
 * Exact sums of doubles over every caller of a reduce callback (libsinter_mpi, issue 44), through
 * the integer limbs of src/core/repro_sum.h: each caller adds its terms into per-bin limb sums
 * below an exponent all callers agree on (a MAX reduction), the limbs are summed as int64 (a
 * SUM reduction: integer addition is associative, so the result does not depend on how the terms
 * are spread over callers or on the reduction's order), and converted to doubles. Free of MPI:
 * the reduction is the callback of sinter_mpi_decomp.h (NULL: one caller holds every term).
 */
#ifndef SINTER_MPI_EXACT_SUMS_H
#define SINTER_MPI_EXACT_SUMS_H

#include <stddef.h>
#include <stdint.h>

#include "core/repro_sum.h"
#include "sinter_mpi_decomp.h"

/* The exponent bounding n weights (NULL: n ones), INT32_MIN when every one is zero or n = 0;
 * *bad = 1 when a weight is negative or not finite (else unchanged). */
int sinter_mpi_weights_exponent(const double *weights, size_t n, int *bad);

/* Element-wise MAX of `count` int64 values over every caller (nothing to do when reduce is NULL):
 * the agreed exponent and error flags, so that an error on one caller stops every caller. */
sinter_status sinter_mpi_agree_max(int64_t *values, size_t count, sinter_mpi_reduce_fn reduce,
                                   void *user);

/* Replace each of `bins` local limb sums by the sum over every caller (carried limbs, terms 0);
 * scratch holds SINTER_REPRO_LIMBS * bins int64. */
sinter_status sinter_mpi_bins_reduce(sinter_repro_sum *sums, size_t bins, int64_t *scratch,
                                     sinter_mpi_reduce_fn reduce, void *user);

#endif
