/*
 * The bonded links' stiffness K (seed 001 eq. 40) assembled in 6x6 blocks for Eisenstat's form
 * of block-SSOR-preconditioned CG (S. C. Eisenstat, SIAM J. Sci. Stat. Comput. 2 (1981) 1-4).
 *
 * K = L + D + U: D the particles' diagonal blocks, U the links' coupling blocks above the
 * diagonal (row: the link's lower particle index, column: the upper one), L = U^T. With
 * E = D + L, the symmetric Gauss-Seidel preconditioner is M = E D^-1 E^T, and PCG on K with M
 * is PCG on the transformed system
 *
 *     K^ x^ = b^,   K^ = E^-1 K E^-T,   b^ = E^-1 b,   x = E^-T x^,
 *
 * preconditioned by D^-1 (its solve: z = D r). Since K = E + E^T - D,
 *
 *     K^ v = t + E^-1 (v - D t),   t = E^-T v,
 *
 * two triangular sweeps that touch every coupling block once each: the price of one product
 * with K, where preconditioning with M itself would add both sweeps to that product.
 *
 * Constrained DOFs (bonded/solve.c) have identity rows and columns in D and zero rows and
 * columns in U, so they stay out of every sweep.
 *
 * Two threads: the particles may come in the order of bonded/domain_order.h, two domains
 * A = [0, split_a) and B = [split_a, split_b) that no block couples, then the separator
 * S = [split_b, n). The backward sweep does S, then A and B; the forward sweep A and B (each
 * within itself), then the blocks from A and B into S in particle order, then S. Every
 * particle's sums come in the same order whether A and B run one after the other or side by
 * side, so the results do not depend on the number of threads.
 */
#ifndef SINTER_BONDED_BLOCK_SSOR_H
#define SINTER_BONDED_BLOCK_SSOR_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

typedef struct sinter_block_ssor {
    sinter_ctx *ctx;
    size_t n;           /* particles */
    double *diag;       /* 36 per particle: D_p, row-major */
    double *diag_inv;   /* 36 per particle: D_p^-1, row-major */
    size_t split_a, split_b; /* the domains A = [0, split_a), B = [split_a, split_b) */
    size_t *row_start;  /* coupling blocks of lower particle p: row_start[p] .. [p + 1] */
    size_t *row_cross;  /* p < split_b: its first block into S (its blocks within its domain
                           come first) */
    uint32_t *column;   /* per coupling block: its upper particle q */
    uint32_t *link_of;  /* per coupling block: the link it came from */
    double *upper_rows; /* 36 per coupling block: U_pq row-major */
    double *upper_cols; /* 36 per coupling block: U_pq column-major (U_pq^T row-major) */
    double *work;       /* 6 per particle */
    size_t diag_capacity, diag_inv_capacity, row_start_capacity, row_cross_capacity,
        column_capacity, link_of_capacity, upper_rows_capacity, upper_cols_capacity, work_capacity;
} sinter_block_ssor;

void sinter_block_ssor_release(sinter_block_ssor *m);

/*
 * Order the coupling blocks of `count` links between n particles (links[k] joins particles
 * lower[k] != upper[k], lower[k] < upper[k]) by lower particle, and make room for n particles.
 * The domains: A = [0, split_a), B = [split_a, split_b) (0, 0: none, every particle in S);
 * a link between A and B is refused (SINTER_ERR_INVALID). The blocks themselves are filled by
 * the caller through diag, upper_rows (row-major) and link_of, then sinter_block_ssor_finish.
 */
sinter_status sinter_block_ssor_layout(sinter_block_ssor *m, size_t n, const uint32_t *lower,
                                       const uint32_t *upper, size_t count, size_t split_a,
                                       size_t split_b);

/* Fill upper_cols from upper_rows and invert the diagonal blocks; -1 (and *singular = p) if
 * D_p is singular. */
int sinter_block_ssor_finish(sinter_block_ssor *m, size_t *singular);

/* v <- E^-T v = (D + U)^-1 v: a backward sweep over the particles. */
void sinter_block_ssor_upper_solve(const sinter_block_ssor *m, double *v);

/* v <- E^-1 v = (D + L)^-1 v: a forward sweep over the particles. */
void sinter_block_ssor_lower_solve(const sinter_block_ssor *m, double *v);

/* y = E^T x = (D + U) x. */
void sinter_block_ssor_upper_multiply(const sinter_block_ssor *m, const double *x, double *y);

/* y = K x = (L + D + U) x. */
void sinter_block_ssor_multiply(const sinter_block_ssor *m, const double *x, double *y);

/* The threads the products below use: 2 where the context has them, there are two domains
 * and enough particles; the first thread takes A (and S), the second B. */
int sinter_block_ssor_threads(const sinter_block_ssor *m);

/* y = D x. */
void sinter_block_ssor_diag_multiply(const sinter_block_ssor *m, const double *x, double *y);

/* y = K^ v = E^-1 K E^-T v by Eisenstat's two sweeps (uses m->work), on two of the context's
 * threads when it has them and there are two domains. */
void sinter_block_ssor_transformed(const sinter_block_ssor *m, const double *v, double *y);

#endif
