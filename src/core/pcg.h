/*
 * Matrix-free preconditioned conjugate gradients (SUNDIALS PCG) for the
 * library's symmetric positive-definite solves: implicit conduction, the
 * electric resistor network and the bonded links' K u = f.
 */
#ifndef SINTER_PCG_H
#define SINTER_PCG_H

#include "core.h"

typedef struct sinter_pcg sinter_pcg;

/* z = A v (or z = P^-1 v for a preconditioner), n doubles each. */
typedef void (*sinter_pcg_operator)(const double *v, double *z, void *data);

/* Create *pcg, or recreate it when n or max_iterations changed. */
sinter_status sinter_pcg_reserve(sinter_ctx *ctx, sinter_pcg **pcg, size_t n, int max_iterations);
void sinter_pcg_free(sinter_pcg *pcg);

/* The right-hand side b and the solution x (holding the initial guess), n doubles each. */
double *sinter_pcg_rhs(sinter_pcg *pcg);
double *sinter_pcg_solution(sinter_pcg *pcg);

/*
 * Split the unknowns into three parts, [0, a), [a, b) and [b, n), for the solver's vector
 * operations (dot products summed part by part, then joined as (first + second) + third), with
 * the second part on a second thread when `threads` is 2 and the first two are not empty: an
 * operator that owns the parts the same way (the bonded solve's domains, bonded/block_ssor.h)
 * keeps each part's vectors in one core's cache. The results do not depend on `threads`.
 * b = 0 (the default): one part.
 */
void sinter_pcg_set_parts(sinter_pcg *pcg, size_t a, size_t b, int threads);

/*
 * A solve spread over subdomains (issue 43, domain/solve.h): every dot product is the local
 * one over the first `counted` unknowns (the others are copies that another subdomain counts)
 * passed through `sum`, which returns the total over all subdomains, the same bits on each, so
 * that every subdomain takes the same steps and stops at the same iteration. Parts
 * (sinter_pcg_set_parts) are then not used for the dot products. `sum` NULL: a local solve.
 */
typedef double (*sinter_pcg_sum)(double local, void *data);
void sinter_pcg_set_sum(sinter_pcg *pcg, sinter_pcg_sum sum, void *data, size_t counted);

/*
 * The reproducible mode (issue 43): every dot product (and so every norm and the stopping test)
 * is dot(x, y, counted, data) instead, over the first `counted` unknowns: an exact sum over
 * every subdomain (domain/solve.h), whose bits do not depend on the split. Takes precedence over
 * sinter_pcg_set_sum and the parts. `dot` NULL: off.
 */
typedef double (*sinter_pcg_dot_fn)(const double *x, const double *y, size_t n, void *data);
void sinter_pcg_set_dot(sinter_pcg *pcg, sinter_pcg_dot_fn dot, void *data, size_t counted);

/*
 * Solve A x = b until |b - A x|_2 <= tol, preconditioned by `precondition`.
 * Returns SUNDIALS' code (0: converged); *iterations and *residual (may be NULL) get the
 * iterations taken and the final residual norm.
 */
int sinter_pcg_solve(sinter_pcg *pcg, sinter_pcg_operator apply, sinter_pcg_operator precondition,
                     void *data, double tol, int *iterations, double *residual);

/*
 * The vector kernels the PCG's N_Vectors use instead of SUNDIALS' serial ones (pcg.c): a dot
 * product summed in 8 lanes (SUNDIALS' is one chain of additions, a floating-point add's
 * latency per element), and the elementwise z = a x + b y (z = c x too, inside pcg.c).
 */
double sinter_pcg_dot(const double *x, const double *y, size_t n);
void sinter_pcg_linear_sum(double a, const double *x, double b, const double *y, double *z,
                           size_t n);

#endif
