/*
 * A block-diagonal SUNMatrix of 7x7 blocks and the direct SUNLinearSolver for it (LU with
 * partial pivoting per block), for the batch of many necks in one CVODE system (batch.c).
 * Private: it exposes SUNDIALS types, which neck.h keeps out.
 */
#ifndef SINTER_NECK_BLOCKDIAG_H
#define SINTER_NECK_BLOCKDIAG_H

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "neck/neck.h"

/* n blocks of SINTER_NECK_DOF^2, zeroed; NULL when out of memory. */
SUNMatrix sinter_neck_blockdiag_matrix(sinter_ctx *ctx, SUNContext sunctx, size_t blocks);

/* Block k, column-major: entry (i, j) at [i + SINTER_NECK_DOF * j]. */
double *sinter_neck_blockdiag_block(SUNMatrix a, size_t k);

/* The direct solver: setup factorises each block of A in place, solve substitutes. */
SUNLinearSolver sinter_neck_blockdiag_solver(sinter_ctx *ctx, SUNContext sunctx, size_t blocks);

#endif
