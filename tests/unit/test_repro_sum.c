/* Order-independent sums (core/repro_sum.c, issue 43): the same bits for any order and any split
 * into parts, exact where the exact sum is representable, and within the stated truncation of a
 * compensated reference otherwise. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

#include "core/repro_sum.h"

static uint64_t next_random(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

/* Sum of x in parts [cut[k], cut[k + 1]): the parts' exponents MAX-ed, their limbs merged. */
static double sum_in_parts(const double *x, const size_t *cut, int parts)
{
    int e = INT32_MIN;
    for (int k = 0; k < parts; ++k) {
        const int ek = sinter_repro_exponent(x + cut[k], cut[k + 1] - cut[k], 1, NULL);
        e = ek > e ? ek : e;
    }
    sinter_repro_sum total;
    memset(&total, 0, sizeof(total));
    for (int k = parts - 1; k >= 0; --k) { /* parts merged in reverse: merging is an integer sum */
        sinter_repro_sum part;
        memset(&part, 0, sizeof(part));
        sinter_repro_add(&part, e, x + cut[k], cut[k + 1] - cut[k], 1);
        sinter_repro_merge(&total, &part);
    }
    return sinter_repro_value(&total, e);
}

static double sum_once(const double *x, size_t n)
{
    const size_t cut[2] = {0, n};
    return sum_in_parts(x, cut, 1);
}

/* Neumaier's compensated sum: the reference (error about 2 ulp of the result + n eps^2 sum|x|). */
static double compensated(const double *x, size_t n)
{
    double s = 0.0, c = 0.0;
    for (size_t k = 0; k < n; ++k) {
        const double t = s + x[k];
        c += fabs(s) >= fabs(x[k]) ? (s - t) + x[k] : (x[k] - t) + s;
        s = t;
    }
    return s + c;
}

/* Terms over 40 decades with both signs: every order and every split gives the same bits. */
static void test_order_and_split_independent(void **state)
{
    (void)state;
    enum { N = 100003 };
    double *x = malloc(N * sizeof(double)), *y = malloc(N * sizeof(double));
    assert_non_null(x);
    assert_non_null(y);
    uint64_t seed = 0x9e3779b97f4a7c15ULL;
    for (size_t k = 0; k < N; ++k) {
        const double mantissa = 1.0 + (double)(next_random(&seed) >> 11) * 0x1p-53;
        const int decade = (int)(next_random(&seed) % 41) - 20;
        x[k] = (next_random(&seed) & 1 ? -1.0 : 1.0) * mantissa * pow(10.0, decade);
    }
    const double reference = sum_once(x, N);
    /* against the compensated sum: truncation below 2^(e - 97) per term, plus the final roundings
     */
    int e = sinter_repro_exponent(x, N, 1, NULL);
    const double bound = (double)N * ldexp(1.0, e - 97) + 4.0 * 0x1p-52 * fabs(reference);
    assert_true(fabs(reference - compensated(x, N)) <= bound);
    /* reversed, shuffled five times, and split into 2, 3 and 4 parts */
    for (size_t k = 0; k < N; ++k)
        y[k] = x[N - 1 - k];
    double got = sum_once(y, N);
    assert_memory_equal(&got, &reference, sizeof(double));
    for (int round = 0; round < 5; ++round) {
        for (size_t k = N - 1; k > 0; --k) {
            const size_t j = (size_t)(next_random(&seed) % (k + 1));
            const double t = y[k];
            y[k] = y[j];
            y[j] = t;
        }
        got = sum_once(y, N);
        assert_memory_equal(&got, &reference, sizeof(double));
        for (int parts = 2; parts <= 4; ++parts) {
            size_t cut[5] = {0};
            for (int p = 1; p < parts; ++p)
                cut[p] = (size_t)(next_random(&seed) % N);
            cut[parts] = N;
            for (int p = 1; p < parts; ++p) /* sort the inner cuts */
                for (int q = p + 1; q < parts; ++q)
                    if (cut[q] < cut[p]) {
                        const size_t t = cut[p];
                        cut[p] = cut[q];
                        cut[q] = t;
                    }
            got = sum_in_parts(y, cut, parts);
            assert_memory_equal(&got, &reference, sizeof(double));
        }
    }
    /* a naive sum of the same terms depends on the order (so the test can tell the difference) */
    double forward = 0.0, backward = 0.0;
    for (size_t k = 0; k < N; ++k) {
        forward += x[k];
        backward += x[N - 1 - k];
    }
    assert_true(forward != backward);
    free(y);
    free(x);
}

/* Exact where the exact sum is a double: 2^53 + 1 - 2^53 repeated, x and -x cancelling. */
static void test_exact_cancellation(void **state)
{
    (void)state;
    enum { N = 3000 };
    double x[N];
    for (size_t k = 0; k < N; k += 3) {
        x[k] = 0x1p53;
        x[k + 1] = 1.0;
        x[k + 2] = -0x1p53;
    }
    assert_true(sum_once(x, N) == (double)(N / 3));
    uint64_t seed = 12345;
    for (size_t k = 0; k < N; k += 2) {
        x[k] = ldexp((double)(next_random(&seed) >> 11), (int)(next_random(&seed) % 200) - 100);
        x[k + 1] = -x[k];
    }
    assert_true(sum_once(x, N) == 0.0);
    double zeros[4] = {0.0, -0.0, 0.0, 0.0};
    assert_int_equal(sinter_repro_exponent(zeros, 4, 1, NULL), INT32_MIN);
    assert_true(sum_once(zeros, 4) == 0.0);
}

/* More terms than one carry interval: 2^23 + 4321 terms of 1 - 2^-52 put nearly 2^40 into the
 * second limb each, which would overflow 64 bits without the carries; the sum is the correctly
 * rounded n (1 - 2^-52) to an ulp. */
static void test_carry_over_many_terms(void **state)
{
    (void)state;
    const size_t n = ((size_t)1 << 23) + 4321;
    double *x = malloc(n * sizeof(double));
    assert_non_null(x);
    for (size_t k = 0; k < n; ++k)
        x[k] = 1.0 - 0x1p-52;
    const double expected = (double)n * (1.0 - 0x1p-52);
    const double got = sum_once(x, n);
    assert_true(fabs(got - expected) <= 0x1p-52 * expected);
    free(x);
}

/* Non-finite terms are reported and skipped; strides read every stride-th value. */
static void test_non_finite_and_stride(void **state)
{
    (void)state;
    double x[6] = {1.0, 100.0, NAN, 200.0, 2.0, 300.0};
    int finite = 1;
    (void)sinter_repro_exponent(x, 6, 1, &finite);
    assert_int_equal(finite, 0);
    const int e = sinter_repro_exponent(x + 1, 3, 2, &finite); /* 100, 200, 300 */
    assert_int_equal(finite, 1);
    assert_int_equal(e, 9); /* 300 < 2^9 */
    sinter_repro_sum s;
    memset(&s, 0, sizeof(s));
    sinter_repro_add(&s, e, x + 1, 3, 2);
    assert_true(sinter_repro_value(&s, e) == 600.0);
}

/* Per-row sums (sinter_repro_rows) with ghost rows: contributions to owned row r made on a ghost
 * copy of r (rows owned + g, reversed into their owners by the callback, as a host's reverse
 * halo adds doubles) give the same bits as the contributions made on r itself, in any order,
 * and match a compensated sum per row to the truncation's bound. */
enum { ROWS = 16, GHOSTS = 8, WIDTH = 3, CONTRIB = 400 };

static int owner_of_ghost(size_t g)
{
    return (int)((g * 5) % ROWS);
}

static int reverse_ghosts(double *rows, size_t width, void *user)
{
    (void)user;
    for (size_t g = 0; g < GHOSTS; ++g)
        for (size_t c = 0; c < width; ++c)
            rows[width * (size_t)owner_of_ghost(g) + c] += rows[width * (ROWS + g) + c];
    return 0;
}

static int reduce_one_part(int64_t *values, size_t count, int op, void *user)
{
    (void)values;
    (void)count;
    (*(int *)user)++;
    return op == SINTER_REPRO_MAX || op == SINTER_REPRO_SUM ? 0 : -1;
}

static void test_rows_with_ghosts(void **state)
{
    (void)state;
    static double terms[CONTRIB * WIDTH], shuffled[CONTRIB * WIDTH];
    static uint32_t row[CONTRIB], row_g[CONTRIB], row_s[CONTRIB];
    uint64_t seed = 0x9e3779b97f4a7c15u;
    for (size_t k = 0; k < CONTRIB; ++k) {
        row[k] = (uint32_t)(next_random(&seed) % ROWS);
        for (size_t c = 0; c < WIDTH; ++c) { /* both signs over 12 decades */
            const double m = (double)(next_random(&seed) % 1000000) / 1e6 - 0.5;
            terms[WIDTH * k + c] = m * pow(10.0, (double)(next_random(&seed) % 12) - 6.0);
        }
        row_g[k] = row[k]; /* every third on a ghost copy of its row, where it has one */
        for (size_t g = 0; g < GHOSTS && k % 3 == 0; ++g)
            if ((uint32_t)owner_of_ghost(g) == row[k])
                row_g[k] = (uint32_t)(ROWS + g);
    }
    for (size_t k = 0; k < CONTRIB; ++k) { /* the contributions reversed */
        row_s[k] = row_g[CONTRIB - 1 - k];
        memcpy(shuffled + WIDTH * k, terms + WIDTH * (CONTRIB - 1 - k), WIDTH * sizeof(double));
    }
    void *work = malloc(sinter_repro_rows_bytes(ROWS + GHOSTS, WIDTH));
    assert_non_null(work);
    double plain[(ROWS + GHOSTS) * WIDTH], ghosts[(ROWS + GHOSTS) * WIDTH],
        reversed[(ROWS + GHOSTS) * WIDTH];
    int calls = 0;
    assert_int_equal(
        sinter_repro_rows(ROWS, ROWS, WIDTH, row, terms, CONTRIB, NULL, NULL, NULL, work, plain),
        0);
    assert_int_equal(sinter_repro_rows(ROWS + GHOSTS, ROWS, WIDTH, row_g, terms, CONTRIB,
                                       reduce_one_part, reverse_ghosts, &calls, work, ghosts),
                     0);
    assert_int_equal(calls, 1); /* the exponents' MAX */
    assert_int_equal(sinter_repro_rows(ROWS + GHOSTS, ROWS, WIDTH, row_s, shuffled, CONTRIB, NULL,
                                       reverse_ghosts, NULL, work, reversed),
                     0);
    assert_memory_equal(plain, ghosts, ROWS * WIDTH * sizeof(double));
    assert_memory_equal(plain, reversed, ROWS * WIDTH * sizeof(double));
    for (size_t q = ROWS * WIDTH; q < (ROWS + GHOSTS) * WIDTH; ++q)
        assert_true(ghosts[q] == 0.0); /* the ghost rows: 0 */
    /* each row against a compensated sum: within the truncation, n 2^(e - 97) with |terms| <
     * 2^e <= 2 * 0.5e6 */
    static double one[CONTRIB];
    for (size_t r = 0; r < ROWS; ++r)
        for (size_t c = 0; c < WIDTH; ++c) {
            size_t n = 0;
            for (size_t k = 0; k < CONTRIB; ++k)
                if (row[k] == r)
                    one[n++] = terms[WIDTH * k + c];
            const double ref = compensated(one, n);
            assert_true(fabs(plain[WIDTH * r + c] - ref) <=
                        2.0 * DBL_EPSILON * fabs(ref) + CONTRIB * ldexp(1.0, 20 - 97));
        }
    free(work);
}

/* Dot products (sinter_repro_dots) and series (sinter_repro_series) in one part: the same bits
 * in reverse order, and within 2 ulp of a compensated sum of the rounded products. */
static void test_dots_and_series(void **state)
{
    (void)state;
    enum { M = 1000 };
    static double a[M], b[M], ar[M], br[M], prod[2 * M];
    uint64_t seed = 12345;
    for (size_t i = 0; i < M; ++i) {
        a[i] = ((double)(next_random(&seed) % 2000001) - 1e6) * 1e-3;
        b[i] = ((double)(next_random(&seed) % 2000001) - 1e6) * 1e-9;
    }
    for (size_t i = 0; i < M; ++i) {
        ar[i] = a[M - 1 - i];
        br[i] = b[M - 1 - i];
        prod[i] = a[i] * b[i];
        prod[M + i] = a[i] * a[i];
    }
    const double *x[2] = {a, a}, *y[2] = {b, a}, *xr[2] = {ar, ar}, *yr[2] = {br, ar};
    double d[2], dr[2], sr[2];
    int calls = 0;
    assert_int_equal(sinter_repro_dots(x, y, M, 2, reduce_one_part, &calls, d), 0);
    assert_int_equal(calls, 2); /* MAX, then SUM */
    assert_int_equal(sinter_repro_dots(xr, yr, M, 2, NULL, NULL, dr), 0);
    assert_int_equal(sinter_repro_series(prod, M, 2, NULL, NULL, sr), 0);
    assert_memory_equal(d, dr, sizeof(d));
    assert_memory_equal(d, sr, sizeof(d)); /* the same rounded products, the same sums */
    for (int j = 0; j < 2; ++j) {
        const double ref = compensated(prod + (size_t)j * M, M);
        assert_true(fabs(d[j] - ref) <= 2.0 * DBL_EPSILON * fabs(ref));
    }
}

/* A batch (the mechanism of every cross-part sum: the domain layer's and the quasi-static
 * stepper's) over two parts, their collectives played by hand (the exponents' MAX, the limbs'
 * SUM): the same bits as one part holding every term, for products and plain terms; a term that
 * is not finite on one part only makes its sum NaN on both, and leaves the other sum alone. */
static void test_batch_over_two_parts(void **state)
{
    (void)state;
    enum { M = 700, CUT = 300 };
    static double a[M], b[M];
    uint64_t seed = 777;
    for (size_t i = 0; i < M; ++i) {
        a[i] = ldexp((double)(next_random(&seed) % 2000001) - 1e6, (int)(i % 41) - 20);
        b[i] = ((double)(next_random(&seed) % 2000001) - 1e6) * 1e-6;
    }
    for (int bad = 0; bad < 2; ++bad) {
        if (bad)
            b[M - 5] = INFINITY; /* in part 1's share of sum 0 only */
        sinter_repro_batch one, part[2];
        double all[2], split[2];
        sinter_repro_begin(&one, 2);
        sinter_repro_scan(&one, 0, a, b, M);
        sinter_repro_scan(&one, 1, a, NULL, M);
        sinter_repro_accumulate(&one, 0, a, b, M);
        sinter_repro_accumulate(&one, 1, a, NULL, M);
        assert_int_equal(sinter_repro_finish(&one, NULL, NULL, all), 0);
        const size_t k0[2] = {0, CUT}, n[2] = {CUT, M - CUT};
        for (int p = 0; p < 2; ++p) {
            sinter_repro_begin(&part[p], 2);
            sinter_repro_scan(&part[p], 0, a + k0[p], b + k0[p], n[p]);
            sinter_repro_scan(&part[p], 1, a + k0[p], NULL, n[p]);
        }
        for (int c = 0; c < 2; ++c) /* the MAX */
            part[0].e[c] = part[1].e[c] = part[0].e[c] > part[1].e[c] ? part[0].e[c] : part[1].e[c];
        for (int p = 0; p < 2; ++p) {
            sinter_repro_accumulate(&part[p], 0, a + k0[p], b + k0[p], n[p]);
            sinter_repro_accumulate(&part[p], 1, a + k0[p], NULL, n[p]);
        }
        for (int c = 0; c < 2; ++c) /* the SUM */
            sinter_repro_merge(&part[0].s[c], &part[1].s[c]);
        assert_int_equal(sinter_repro_finish(&part[0], NULL, NULL, split), 0);
        assert_memory_equal(all, split, sizeof(all));
        assert_true(bad ? isnan(all[0]) : isfinite(all[0]));
        assert_true(isfinite(all[1]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_and_split_independent),
        cmocka_unit_test(test_exact_cancellation),
        cmocka_unit_test(test_carry_over_many_terms),
        cmocka_unit_test(test_non_finite_and_stride),
        cmocka_unit_test(test_rows_with_ghosts),
        cmocka_unit_test(test_dots_and_series),
        cmocka_unit_test(test_batch_over_two_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
