/*
 * K u = f (seed 001 eq. 40) over links spread across subdomains (issue 43): each subdomain
 * holds the links it owns, its owned particles' rows first and copies ("ghosts") of the other
 * ends after them. The operator product adds each owned link's 12x12 stiffness into the rows
 * of both its ends, and the ghost rows go back to their owners (a reverse exchange); the
 * displacements of the ghosts come from their owners (a forward exchange); dot products are
 * summed over the owned rows and then across subdomains. PCG with a block-Jacobi preconditioner
 * (the 6x6 diagonal block of each particle, summed over every link that touches it), so the
 * preconditioner needs nothing from other subdomains. Constrained DOFs as bonded/solve.c: the
 * operator is P K P + (I - P), a free DOF without stiffness counts as constrained.
 *
 * Every decision (stop, continue, fail) follows reduced values only, so every subdomain runs
 * the same iterations.
 */
#ifndef SINTER_BONDED_SOLVE_SPLIT_H
#define SINTER_BONDED_SOLVE_SPLIT_H

#include "bonded/beam.h"
#include "core/repro_sum.h"

/* The collective operations the split solve needs (each returns 0 on success). */
typedef struct sinter_bonded_exchange {
    /* ghost rows of rows[(owned + ghosts) * width] copied from their owners */
    int (*forward)(double *rows, size_t width, void *user);
    /* ghost rows added into their owners' rows (the ghost rows are then undefined) */
    int (*reverse)(double *rows, size_t width, void *user);
    /* values[0..count) summed over every subdomain in place (identical bits everywhere) */
    int (*sum)(double *values, size_t count, void *user);
    void *user;
    /* 1: the reproducible mode (issue 43): every operator product, diagonal block and dot
     * product an exact sum (core/repro_sum.h), so that the iterations and the result are the
     * same bits for any split of the links and rows, one part included */
    int reproducible;
    /* in that mode: int64 MAX / SUM over every subdomain (NULL: one subdomain) */
    sinter_repro_reduce_fn reduce;
} sinter_bonded_exchange;

/*
 * Solve over `rows` particle rows of which the first `owned` are this subdomain's; links[k].a
 * and .b are rows (both < rows). fixed[6 rows] marks constrained DOFs (owned rows read),
 * f[6 rows] the loads (owned rows read: complete, ghosts' shares already added), guess[6 rows]
 * a start (NULL: 0; owned rows read). u[6 rows]: the displacements, ghost rows included
 * (from their owners). rtol: the target of the true residual |f - K u| relative to |f|, over
 * all subdomains. Collective. Errors: SINTER_ERR_NOMEM, SINTER_ERR_INVALID (a link's row out of
 * range), SINTER_ERR_NOT_CONVERGED, SINTER_ERR_CALLBACK (an exchange failed); a status of
 * this subdomain only for NOMEM and INVALID, which the caller must agree before going on.
 */
sinter_status sinter_bonded_solve_split(sinter_ctx *ctx, size_t owned, size_t rows,
                                        const sinter_beam *links, size_t count,
                                        const unsigned char *fixed, const double *f,
                                        const double *guess, double *u, double rtol,
                                        const sinter_bonded_exchange *ex, int *iterations);

#endif
