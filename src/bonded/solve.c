/*
 * K u = f over an assembly of bonded links (seed 001 eq. 40, sec. 3.3): SUNDIALS PCG with
 * matrix-free products from the link list and a 6x6 block-Jacobi preconditioner (one block per
 * particle), through the shared PCG wrapper of src/core/pcg.h.
 *
 * Constrained DOFs (the principal-plane conditions of sec. 3.3, or a clamp) are removed by
 * projection: the operator is P K P + (I - P) and the right-hand side P f, with P zeroing the
 * constrained DOFs, so the system stays symmetric positive (semi-)definite. A free DOF with no
 * stiffness at all (a particle without links) is treated as constrained. Zero-energy modes that
 * the plane conditions leave (a straight chain can twist about its own axis) are harmless: the
 * loads have no component on them and CG started from zero never enters them.
 */
#include <math.h>
#include <string.h>

#include "core/pcg.h"

#include "bonded/beam.h"

struct sinter_bonded_solver {
    sinter_ctx *ctx;
    sinter_pcg *pcg;
    size_t dofs;
    /* operator data of one solve */
    const sinter_beam *links;
    size_t count;
    unsigned char *mask; /* 1: constrained (user-fixed or without stiffness) */
    double *blocks;      /* 36 per particle: inverse of the diagonal block */
    size_t mask_capacity, blocks_capacity;
};

void sinter_bonded_solver_destroy(sinter_bonded_solver *solver)
{
    if (solver == NULL)
        return;
    sinter_pcg_free(solver->pcg);
    sinter_free(solver->ctx, solver->mask);
    sinter_free(solver->ctx, solver->blocks);
    sinter_free(solver->ctx, solver);
}

sinter_status sinter_bonded_solver_create(sinter_bonded_solver **out, sinter_ctx *ctx)
{
    SINTER_CHECK_NULL(ctx, out);
    *out = NULL;
    sinter_bonded_solver *s = sinter_calloc(ctx, 1, sizeof(*s));
    if (s == NULL)
        return SINTER_ERR_NOMEM;
    s->ctx = ctx;
    *out = s;
    return SINTER_OK;
}

/* z = (P K P + I - P) v */
static void apply_operator(const double *vv, double *zz, void *data)
{
    const sinter_bonded_solver *s = data;
    memset(zz, 0, s->dofs * sizeof(double));
    for (size_t k = 0; k < s->count; ++k) {
        const sinter_beam *l = &s->links[k];
        double ya[6], yb[6], pa[6] = {0}, pb[6] = {0};
        for (int d = 0; d < 6; ++d) {
            const size_t ia = 6 * (size_t)l->a + (size_t)d, ib = 6 * (size_t)l->b + (size_t)d;
            ya[d] = s->mask[ia] ? 0.0 : vv[ia];
            yb[d] = s->mask[ib] ? 0.0 : vv[ib];
        }
        sinter_beam_apply(l, ya, yb, pa, pb);
        for (int d = 0; d < 6; ++d) {
            zz[6 * (size_t)l->a + (size_t)d] += pa[d];
            zz[6 * (size_t)l->b + (size_t)d] += pb[d];
        }
    }
    for (size_t i = 0; i < s->dofs; ++i)
        if (s->mask[i])
            zz[i] = vv[i];
}

/* z = B^-1 r, B the 6x6 diagonal blocks. */
static void precondition(const double *rr, double *zz, void *data)
{
    const sinter_bonded_solver *s = data;
    for (size_t p = 0; p < s->dofs / 6; ++p) {
        const double *inv = s->blocks + 36 * p;
        for (int a = 0; a < 6; ++a) {
            double sum = 0.0;
            for (int c = 0; c < 6; ++c)
                sum += inv[6 * a + c] * rr[6 * p + (size_t)c];
            zz[6 * p + (size_t)a] = sum;
        }
    }
}

/* In-place inverse of an SPD 6x6 matrix by Gauss-Jordan with partial pivoting; -1 if singular. */
static int invert6(double m[36])
{
    double a[6][12];
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 12; ++c)
            a[r][c] = c < 6 ? m[6 * r + c] : (c - 6 == r ? 1.0 : 0.0);
    for (int c = 0; c < 6; ++c) {
        int piv = c;
        for (int r = c + 1; r < 6; ++r)
            if (fabs(a[r][c]) > fabs(a[piv][c]))
                piv = r;
        if (!(fabs(a[piv][c]) > 0.0))
            return -1;
        if (piv != c)
            for (int k = 0; k < 12; ++k) {
                const double t = a[c][k];
                a[c][k] = a[piv][k];
                a[piv][k] = t;
            }
        const double d = a[c][c];
        for (int k = 0; k < 12; ++k)
            a[c][k] /= d;
        for (int r = 0; r < 6; ++r) {
            if (r == c || a[r][c] == 0.0)
                continue;
            const double f = a[r][c];
            for (int k = 0; k < 12; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c)
            m[6 * r + c] = a[r][6 + c];
    return 0;
}

static sinter_status prepare(sinter_bonded_solver *s, size_t n)
{
    const size_t dofs = 6 * n;
    sinter_status st = sinter_grow(s->ctx, (void **)&s->mask, &s->mask_capacity, dofs + 1, 1);
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->blocks, &s->blocks_capacity, 36 * n + 1,
                         sizeof(double));
    if (st != SINTER_OK)
        return st;
    const int maxl = (int)(2 * dofs < 1000 ? 1000 : 2 * dofs);
    st = sinter_pcg_reserve(s->ctx, &s->pcg, dofs, maxl);
    if (st != SINTER_OK)
        return st;
    s->dofs = dofs;
    return SINTER_OK;
}

sinter_status sinter_bonded_solve(sinter_bonded_solver *solver, size_t n, const sinter_beam *links,
                                  size_t count, const unsigned char *fixed, const double *f,
                                  double *u, double rtol, int *iterations)
{
    return sinter_bonded_solve_from(solver, n, links, count, fixed, f, NULL, u, rtol, iterations);
}

sinter_status sinter_bonded_solve_from(sinter_bonded_solver *solver, size_t n,
                                       const sinter_beam *links, size_t count,
                                       const unsigned char *fixed, const double *f,
                                       const double *guess, double *u, double rtol,
                                       int *iterations)
{
    SINTER_CHECK_NULL(NULL, solver);
    sinter_bonded_solver *s = solver;
    if (iterations)
        *iterations = 0;
    if (n == 0)
        return SINTER_OK;
    sinter_status st = prepare(s, n);
    if (st != SINTER_OK)
        return st;
    const size_t dofs = 6 * n;
    s->links = links;
    s->count = count;
    /* Diagonal blocks of K: the AA and BB blocks of each element (eq. 40). */
    memset(s->blocks, 0, 36 * n * sizeof(double));
    for (size_t k = 0; k < count; ++k) {
        double ke[144];
        sinter_beam_stiffness(&links[k], ke);
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c) {
                s->blocks[36 * (size_t)links[k].a + (size_t)(6 * r + c)] += ke[12 * r + c];
                s->blocks[36 * (size_t)links[k].b + (size_t)(6 * r + c)] +=
                    ke[12 * (r + 6) + c + 6];
            }
    }
    for (size_t i = 0; i < dofs; ++i) {
        const double diag = s->blocks[36 * (i / 6) + 7 * (i % 6)];
        s->mask[i] = (unsigned char)((fixed != NULL && fixed[i]) || !(diag > 0.0));
    }
    /* Constrained rows and columns of each block become the identity. */
    for (size_t p = 0; p < n; ++p) {
        double *blk = s->blocks + 36 * p;
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                if (s->mask[6 * p + (size_t)r] || s->mask[6 * p + (size_t)c])
                    blk[6 * r + c] = r == c ? 1.0 : 0.0;
        if (invert6(blk) != 0)
            return sinter_fail(s->ctx, SINTER_ERR_NOT_CONVERGED,
                               "bonded solve: the stiffness block of particle %zu is singular", p);
    }
    double *b = sinter_pcg_rhs(s->pcg), *x = sinter_pcg_solution(s->pcg);
    double norm = 0.0;
    for (size_t i = 0; i < dofs; ++i) {
        b[i] = s->mask[i] ? 0.0 : f[i];
        x[i] = s->mask[i] || guess == NULL ? 0.0 : guess[i]; /* PCG starts from x */
        norm += b[i] * b[i];
    }
    norm = sqrt(norm);
    if (norm == 0.0) {
        memset(u, 0, dofs * sizeof(double));
        return SINTER_OK;
    }
    int taken = 0;
    double residual = 0.0;
    const int rc =
        sinter_pcg_solve(s->pcg, apply_operator, precondition, s, rtol * norm, &taken, &residual);
    if (iterations)
        *iterations = taken;
    if (rc != 0)
        return sinter_fail(s->ctx, SINTER_ERR_NOT_CONVERGED,
                           "bonded solve: PCG returned %d after %d iterations (residual %g, "
                           "|f| %g) over %zu DOFs",
                           rc, taken, residual, norm, dofs);
    for (size_t i = 0; i < dofs; ++i)
        u[i] = s->mask[i] ? 0.0 : x[i];
    return SINTER_OK;
}
