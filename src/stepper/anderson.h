#ifndef SINTER_ANDERSON_H
#define SINTER_ANDERSON_H

#include <stddef.h>

#include "sinter.h"

/*
 * Anderson(m) acceleration of a fixed-point iteration u = G(u) (Walker and Ni, SIAM J. Numer.
 * Anal. 49 (2011) 1715, "Algorithm AA" with the least-squares form; the same scheme as SUNDIALS
 * KINSOL's fixed-point solver with KINSetMAA). With the residual f_k = G(u_k) - u_k and the
 * differences of the last m residuals and images, dF_j = f_(j+1) - f_j, dG_j = G(u_(j+1)) -
 * G(u_j), the next iterate is
 *
 *   u_(k+1) = G(u_k) - sum_j gamma_j dG_j,  gamma = argmin || W (f_k - sum_j gamma_j dF_j) ||_2
 *
 * with a diagonal weight W (the WRMS weights of the convergence test, so that the least-squares
 * problem measures what the test measures). m = 0 is the plain iteration u_(k+1) = G(u_k).
 * The least-squares problem is solved by modified Gram-Schmidt QR of W dF, rebuilt at every
 * iteration (m <= 10 columns); a column whose norm falls below 1e-10 of the largest drops the
 * oldest differences (the usual safeguard against a rank-deficient history).
 */
typedef struct sinter_anderson {
    size_t length;   /* N, unknowns */
    int depth;       /* m */
    int stored;      /* differences held, <= depth */
    int head;        /* ring index of the oldest difference */
    int have_prev;   /* f_prev, g_prev valid */
    double *df, *dg; /* depth x N each, ring */
    double *f_prev, *g_prev;
    double *q;       /* depth x N: Q of the QR */
    double *wf;      /* N: W f_k (the reproducible mode's inner products) */
    size_t capacity; /* doubles allocated per array group */
} sinter_anderson;

void sinter_anderson_init(sinter_anderson *aa);
void sinter_anderson_free(sinter_ctx *ctx, sinter_anderson *aa);
/* Size for N unknowns and depth m (allocates; keeps nothing of a previous solve). */
sinter_status sinter_anderson_reset(sinter_ctx *ctx, sinter_anderson *aa, size_t length, int depth);
/*
 * Sums over every part of a vector spread over subdomains (domain/domain.h), in place: each
 * subdomain holds the rows of its owned particles, and the least-squares problem's inner
 * products are the sums of the parts' (every subdomain receives the same bits, so every one
 * solves the same small problem and takes the same branches). Returns 0 on success.
 */
typedef struct sinter_anderson_sum {
    int (*sum)(double *values, size_t count, void *user);
    void *user;
    /* NULL, or every inner product through this instead (the stepper's reproducible mode,
     * issue 43): out[c] = sum_i a[c][i] b[c][i] over every part, c < count (<= 10), each
     * product rounded once and the products summed exactly, so that the bits depend neither on
     * the order of the rows nor on how they are split into parts (domain/exact_reduce.h).
     * Returns 0 on success. */
    int (*dots)(const double *const *a, const double *const *b, size_t n, size_t count, double *out,
                void *user);
} sinter_anderson_sum;

/*
 * One update: u holds u_k on entry and u_(k+1) on return; g holds G(u_k) (kept as is); w the
 * weights (length N, >= 0); `sum` NULL when the vectors are whole. Returns the number of
 * differences used, or -1 when a sum failed (u is then G(u_k)).
 */
int sinter_anderson_update(sinter_anderson *aa, double *u, const double *g, const double *w,
                           const sinter_anderson_sum *sum);

#endif
