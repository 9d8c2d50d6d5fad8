/*
 * Block-diagonal 7x7 SUNMatrix and its direct solver (blockdiag.h). CVODE's matrix-based
 * linear-solver interface needs of the matrix only clone, destroy, zero, copy and
 * I + c A (scaleaddi), and of the solver setup (factorise A = I - gamma J) and solve; it keeps
 * its own copy of J and decides when to re-evaluate it. Each block is factorised on its own:
 * O(n) work and storage for n necks, where a band matrix of half-bandwidth 6 spends most of
 * its time on the zeros between blocks.
 */
#include <math.h>
#include <string.h>

#include "neck/blockdiag.h"

#define N SINTER_NECK_DOF
#define BLOCK (N * N)

typedef struct matrix_content {
    sinter_ctx *ctx;
    size_t blocks;
    double *data; /* blocks * BLOCK doubles */
} matrix_content;

typedef struct solver_content {
    sinter_ctx *ctx;
    size_t blocks;
    int *pivots; /* blocks * N row indices */
    sunindextype last_flag;
} solver_content;

static matrix_content *content_of(SUNMatrix a)
{
    return (matrix_content *)a->content;
}

double *sinter_neck_blockdiag_block(SUNMatrix a, size_t k)
{
    return content_of(a)->data + BLOCK * k;
}

static SUNMatrix_ID matrix_id(SUNMatrix a)
{
    (void)a;
    return SUNMATRIX_CUSTOM;
}

static void matrix_destroy(SUNMatrix a)
{
    if (a == NULL)
        return;
    matrix_content *c = content_of(a);
    if (c != NULL) {
        sinter_free(c->ctx, c->data);
        sinter_free(c->ctx, c);
    }
    a->content = NULL;
    SUNMatFreeEmpty(a);
}

static SUNMatrix matrix_clone(SUNMatrix a)
{
    const matrix_content *c = content_of(a);
    return sinter_neck_blockdiag_matrix(c->ctx, a->sunctx, c->blocks);
}

static int matrix_zero(SUNMatrix a)
{
    matrix_content *c = content_of(a);
    memset(c->data, 0, c->blocks * BLOCK * sizeof(double));
    return 0;
}

static int matrix_copy(SUNMatrix a, SUNMatrix b)
{
    /* B = A */
    const matrix_content *ca = content_of(a);
    matrix_content *cb = content_of(b);
    if (ca->blocks != cb->blocks)
        return -1;
    memcpy(cb->data, ca->data, ca->blocks * BLOCK * sizeof(double));
    return 0;
}

static int matrix_scale_add_identity(realtype c, SUNMatrix a)
{
    /* A = c A + I, block by block. */
    matrix_content *m = content_of(a);
    for (size_t k = 0; k < m->blocks; ++k) {
        double *block = m->data + BLOCK * k;
        for (int e = 0; e < BLOCK; ++e)
            block[e] *= c;
        for (int i = 0; i < N; ++i)
            block[i + N * i] += 1.0;
    }
    return 0;
}

static int matrix_space(SUNMatrix a, long *real_words, long *int_words)
{
    *real_words = (long)(content_of(a)->blocks * BLOCK);
    *int_words = 2;
    return 0;
}

SUNMatrix sinter_neck_blockdiag_matrix(sinter_ctx *ctx, SUNContext sunctx, size_t blocks)
{
    if (blocks == 0 || sinter_mul_overflows(blocks, BLOCK * sizeof(double)))
        return NULL;
    SUNMatrix a = SUNMatNewEmpty(sunctx);
    if (a == NULL)
        return NULL;
    matrix_content *c = sinter_calloc(ctx, 1, sizeof(*c));
    double *data = c != NULL ? sinter_calloc(ctx, blocks * BLOCK, sizeof(double)) : NULL;
    if (data == NULL) {
        sinter_free(ctx, c);
        SUNMatFreeEmpty(a);
        return NULL;
    }
    c->ctx = ctx;
    c->blocks = blocks;
    c->data = data;
    a->content = c;
    a->ops->getid = matrix_id;
    a->ops->clone = matrix_clone;
    a->ops->destroy = matrix_destroy;
    a->ops->zero = matrix_zero;
    a->ops->copy = matrix_copy;
    a->ops->scaleaddi = matrix_scale_add_identity;
    a->ops->space = matrix_space;
    return a;
}

/* --- the solver ---------------------------------------------------------------------------- */

/* In-place LU with partial pivoting of one column-major block (rows swapped across the whole
 * block, LAPACK getrf style). Returns 0, or 1 + the column of a zero pivot. */
static int factor_block(double *a, int *pivot)
{
    for (int k = 0; k < N; ++k) {
        int p = k;
        double largest = fabs(a[k + N * k]);
        for (int i = k + 1; i < N; ++i)
            if (fabs(a[i + N * k]) > largest) {
                largest = fabs(a[i + N * k]);
                p = i;
            }
        pivot[k] = p;
        if (largest == 0.0)
            return k + 1;
        if (p != k)
            for (int j = 0; j < N; ++j) {
                const double swap = a[k + N * j];
                a[k + N * j] = a[p + N * j];
                a[p + N * j] = swap;
            }
        const double inverse = 1.0 / a[k + N * k];
        for (int i = k + 1; i < N; ++i)
            a[i + N * k] *= inverse;
        for (int j = k + 1; j < N; ++j) {
            const double akj = a[k + N * j];
            if (akj != 0.0)
                for (int i = k + 1; i < N; ++i)
                    a[i + N * j] -= a[i + N * k] * akj;
        }
    }
    return 0;
}

/* Solve with a factored block: b is overwritten by the solution. */
static void solve_block(const double *lu, const int *pivot, double *b)
{
    for (int k = 0; k < N; ++k) {
        const double swap = b[k];
        b[k] = b[pivot[k]];
        b[pivot[k]] = swap;
    }
    for (int k = 0; k < N; ++k)
        for (int i = k + 1; i < N; ++i)
            b[i] -= lu[i + N * k] * b[k];
    for (int k = N - 1; k >= 0; --k) {
        b[k] /= lu[k + N * k];
        for (int i = 0; i < k; ++i)
            b[i] -= lu[i + N * k] * b[k];
    }
}

static solver_content *solver_of(SUNLinearSolver s)
{
    return (solver_content *)s->content;
}

static SUNLinearSolver_Type solver_type(SUNLinearSolver s)
{
    (void)s;
    return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID solver_id(SUNLinearSolver s)
{
    (void)s;
    return SUNLINEARSOLVER_CUSTOM;
}

static int solver_initialize(SUNLinearSolver s)
{
    solver_of(s)->last_flag = 0;
    return SUNLS_SUCCESS;
}

static int solver_setup(SUNLinearSolver s, SUNMatrix a)
{
    solver_content *c = solver_of(s);
    const matrix_content *m = content_of(a);
    if (m->blocks != c->blocks)
        return SUNLS_ILL_INPUT;
    for (size_t k = 0; k < c->blocks; ++k) {
        const int zero = factor_block(m->data + BLOCK * k, c->pivots + N * k);
        if (zero != 0) {
            c->last_flag = (sunindextype)(N * k) + zero;
            return SUNLS_LUFACT_FAIL; /* recoverable: CVODE retries with a smaller step */
        }
    }
    c->last_flag = 0;
    return SUNLS_SUCCESS;
}

static int solver_solve(SUNLinearSolver s, SUNMatrix a, N_Vector x, N_Vector b, realtype tol)
{
    (void)tol;
    const solver_content *c = solver_of(s);
    const matrix_content *m = content_of(a);
    double *xd = N_VGetArrayPointer(x);
    N_VScale(1.0, b, x);
    for (size_t k = 0; k < c->blocks; ++k)
        solve_block(m->data + BLOCK * k, c->pivots + N * k, xd + N * k);
    return SUNLS_SUCCESS;
}

static sunindextype solver_last_flag(SUNLinearSolver s)
{
    return solver_of(s)->last_flag;
}

static int solver_free(SUNLinearSolver s)
{
    if (s == NULL)
        return SUNLS_SUCCESS;
    solver_content *c = solver_of(s);
    if (c != NULL) {
        sinter_free(c->ctx, c->pivots);
        sinter_free(c->ctx, c);
    }
    s->content = NULL;
    SUNLinSolFreeEmpty(s);
    return SUNLS_SUCCESS;
}

SUNLinearSolver sinter_neck_blockdiag_solver(sinter_ctx *ctx, SUNContext sunctx, size_t blocks)
{
    if (blocks == 0 || sinter_mul_overflows(blocks, N * sizeof(int)))
        return NULL;
    SUNLinearSolver s = SUNLinSolNewEmpty(sunctx);
    if (s == NULL)
        return NULL;
    solver_content *c = sinter_calloc(ctx, 1, sizeof(*c));
    int *pivots = c != NULL ? sinter_calloc(ctx, blocks * N, sizeof(int)) : NULL;
    if (pivots == NULL) {
        sinter_free(ctx, c);
        SUNLinSolFreeEmpty(s);
        return NULL;
    }
    c->ctx = ctx;
    c->blocks = blocks;
    c->pivots = pivots;
    s->content = c;
    s->ops->gettype = solver_type;
    s->ops->getid = solver_id;
    s->ops->initialize = solver_initialize;
    s->ops->setup = solver_setup;
    s->ops->solve = solver_solve;
    s->ops->lastflag = solver_last_flag;
    s->ops->free = solver_free;
    return s;
}
