/*
 * The global solves of a decomposed run (issue 43): implicit conduction and the electric
 * network, whose unknowns are the owned particles of every subdomain.
 *
 * Each subdomain keeps the rows of its owned particles; a ghost of another subdomain is not an
 * unknown: its value is its owner's, brought by a forward halo of width 1 before every
 * operator product. Newton's third law is off across borders, as in the forces: each side
 * assembles the conductances of the pairs with an owned end, and the product on an owned row
 * reads the ghost's value. Dot products, norms and so the stopping test go through `reduce`
 * (sinter_pcg_set_sum), so that every subdomain takes the same steps and stops at the same
 * iteration. The preconditioner (Jacobi) is pointwise: it needs no exchange and is the
 * single-domain one, so the iterations are those of the single-domain solve up to rounding.
 */
#ifndef SINTER_DOMAIN_SOLVE_H
#define SINTER_DOMAIN_SOLVE_H

#include "domain/domain.h"

typedef struct sinter_domain_solve {
    sinter_ctx *ctx;
    sinter_domain *d;     /* the host's operations (on) */
    sinter_particles *ps; /* owned rows first, then the ghosts */
    double *rows;         /* (owned + ghosts) values: the halo's rows */
    size_t rows_capacity;
    int failed; /* a collective call failed inside the solve (the error is in ctx) */
} sinter_domain_solve;

void sinter_domain_solve_free(sinter_domain_solve *ds);

/* Room for `width` values per row of the set's owned particles and ghosts. */
sinter_status sinter_domain_solve_reserve(sinter_domain_solve *ds, size_t width);

/* The forward halo of ds->rows, `width` values per row, whose owned rows the caller filled.
 * On a failure ds->failed is set and the ghost rows are zero. */
void sinter_domain_solve_halo(sinter_domain_solve *ds, size_t width);

/* The rows' ghost values from their owners (forward halo, width 1): `owned` values are copied
 * into ds->rows first, the ghost rows follow. On a failure ds->failed is set and the ghost
 * rows are zero. */
void sinter_domain_solve_forward(sinter_domain_solve *ds, const double *owned);

/* A sinter_pcg_sum: the sum of `local` over every subdomain (data: a sinter_domain_solve). */
double sinter_domain_solve_sum(double local, void *data);

/*
 * A sinter_pcg_dot_fn for the reproducible mode (issue 43): the exact sum of x[k] y[k], k < n,
 * over every subdomain (domain/exact_reduce.h: each product rounded once, then limb sums, two
 * integer reductions), the same bits for any split of the terms. Without domain operations
 * (ds->d NULL) the local exact sum, the same bits as on any number of subdomains. On a failure
 * ds->failed is set and the result is 0.
 */
double sinter_domain_solve_exact_dot(const double *x, const double *y, size_t n, void *data);

#endif
