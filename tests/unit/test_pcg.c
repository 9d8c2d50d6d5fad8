/*
 * The PCG wrapper (src/core/pcg.c) and the vector kernels its N_Vectors use instead of
 * SUNDIALS' serial ones: the 8-lane dot product, the linear sum, and a solve that runs on them.
 */
#include <stdio.h>
#include <string.h>

#include "test_support.h"
#include "core/core.h"
#include "core/pcg.h"

/* A dot product of integer-valued vectors is exact in any order of summation (every partial
 * sum below 2^53): the kernel must give the exact value for every length, so that a dropped,
 * doubled or misplaced lane or tail element fails. */
static void test_dot_exact_for_every_length(void **state)
{
    (void)state;
    enum { MAX = 4837 };
    double *x = malloc(MAX * sizeof(double)), *y = malloc(MAX * sizeof(double));
    assert_non_null(x);
    assert_non_null(y);
    for (size_t i = 0; i < MAX; ++i) {
        x[i] = (double)((long)((i * 7919u) % 2001u) - 1000);
        y[i] = (double)((long)((i * 104729u) % 1999u) - 999);
    }
    const size_t lengths[] = {0, 1, 2, 3, 7, 8, 9, 15, 16, 17, 63, 64, 65, 4830, MAX};
    for (size_t t = 0; t < sizeof(lengths) / sizeof(lengths[0]); ++t) {
        const size_t n = lengths[t];
        long long exact = 0;
        for (size_t i = 0; i < n; ++i)
            exact += (long long)x[i] * (long long)y[i];
        assert_true(sinter_pcg_dot(x, y, n) == (double)exact);
        /* an offset start (unaligned for vector loads) */
        if (n > 1) {
            long long shifted = 0;
            for (size_t i = 1; i < n; ++i)
                shifted += (long long)x[i] * (long long)y[i];
            assert_true(sinter_pcg_dot(x + 1, y + 1, n - 1) == (double)shifted);
        }
    }
    free(x);
    free(y);
}

/* z = a x + b y elementwise, to the bit, also written over x or y. */
static void test_linear_sum_elementwise(void **state)
{
    (void)state;
    enum { N = 37 };
    double x[N], y[N], z[N], w[N];
    for (int i = 0; i < N; ++i) {
        x[i] = sin(0.3 * i) * 1e3;
        y[i] = cos(0.7 * i) / 3.0;
    }
    const double a = 0.37, b = -2.5;
    sinter_pcg_linear_sum(a, x, b, y, z, N);
    for (int i = 0; i < N; ++i)
        assert_true(z[i] == a * x[i] + b * y[i]);
    memcpy(w, x, sizeof(w));
    sinter_pcg_linear_sum(a, w, b, y, w, N); /* over x */
    assert_memory_equal(w, z, sizeof(w));
    memcpy(w, y, sizeof(w));
    sinter_pcg_linear_sum(a, x, b, w, w, N); /* over y */
    assert_memory_equal(w, z, sizeof(w));
}

/* The 1D Laplacian tridiag(-1, 2, -1) of n unknowns (a Dirichlet rod), matrix-free. */
static void laplacian(const double *v, double *z, void *data)
{
    const size_t n = *(const size_t *)data;
    for (size_t i = 0; i < n; ++i)
        z[i] = 2.0 * v[i] - (i > 0 ? v[i - 1] : 0.0) - (i + 1 < n ? v[i + 1] : 0.0);
}

static void jacobi(const double *r, double *z, void *data)
{
    const size_t n = *(const size_t *)data;
    for (size_t i = 0; i < n; ++i)
        z[i] = 0.5 * r[i];
}

/* A solve through SUNDIALS PCG on the replaced kernels: b = A x_true for a known x_true; CG
 * recovers it in at most n iterations (exactly, but for rounding), to the accuracy the
 * residual tolerance allows (condition number 4 n^2 / pi^2 ~ 1.6e4 here). */
static void test_solve_recovers_known_solution(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    size_t n = 200;
    sinter_pcg *pcg = NULL;
    assert_int_equal(sinter_pcg_reserve(ctx, &pcg, n, 1000), SINTER_OK);
    double x_true[200], bnorm = 0.0;
    for (size_t i = 0; i < n; ++i)
        x_true[i] = sin(3.0 * (double)(i + 1) / (double)(n + 1)) + 0.01 * (double)(i % 7);
    laplacian(x_true, sinter_pcg_rhs(pcg), &n);
    for (size_t i = 0; i < n; ++i)
        bnorm += sinter_pcg_rhs(pcg)[i] * sinter_pcg_rhs(pcg)[i];
    bnorm = sqrt(bnorm);
    memset(sinter_pcg_solution(pcg), 0, n * sizeof(double));
    int iterations = 0;
    double residual = 0.0;
    const int rc = sinter_pcg_solve(pcg, laplacian, jacobi, &n, 1e-13 * bnorm, &iterations,
                                    &residual);
    assert_int_equal(rc, 0);
    assert_true(iterations > 0 && iterations <= (int)n);
    assert_true(residual <= 1e-13 * bnorm);
    double worst = 0.0;
    for (size_t i = 0; i < n; ++i)
        worst = fmax(worst, fabs(sinter_pcg_solution(pcg)[i] - x_true[i]));
    assert_true(worst <= 1e-8); /* |x_true| ~ 1; cond x tol = 1.6e-9 */
    sinter_pcg_free(pcg);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dot_exact_for_every_length),
        cmocka_unit_test(test_linear_sum_elementwise),
        cmocka_unit_test(test_solve_recovers_known_solution),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
