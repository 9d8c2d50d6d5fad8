/* 6x6 block storage of the bonded stiffness and Eisenstat's SSOR sweeps (see block_ssor.h). */
#include <math.h>
#include <string.h>

#include "contact/neighbors.h" /* sinter_threads */
#include "core/clones.h"
#include "core/two_parts.h"

#include "bonded/block_ssor.h"

void sinter_block_ssor_release(sinter_block_ssor *m)
{
    if (m == NULL)
        return;
    sinter_free(m->ctx, m->diag);
    sinter_free(m->ctx, m->diag_inv);
    sinter_free(m->ctx, m->row_start);
    sinter_free(m->ctx, m->row_cross);
    sinter_free(m->ctx, m->column);
    sinter_free(m->ctx, m->link_of);
    sinter_free(m->ctx, m->upper_rows);
    sinter_free(m->ctx, m->upper_cols);
    sinter_free(m->ctx, m->work);
    memset(m, 0, sizeof(*m));
}

sinter_status sinter_block_ssor_layout(sinter_block_ssor *m, size_t n, const uint32_t *lower,
                                       const uint32_t *upper, size_t count, size_t split_a,
                                       size_t split_b)
{
    sinter_ctx *ctx = m->ctx;
    if (split_a > split_b || split_b > n)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "block SSOR: domains [0, %zu) and [%zu, %zu) of %zu particles", split_a,
                           split_a, split_b, n);
    for (size_t k = 0; k < count; ++k)
        if (lower[k] < split_a && upper[k] >= split_a && upper[k] < split_b)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "block SSOR: link %zu joins particle %u of the first domain to "
                               "particle %u of the second",
                               k, (unsigned)lower[k], (unsigned)upper[k]);
    sinter_status st =
        sinter_grow(ctx, (void **)&m->diag, &m->diag_capacity, 36 * n + 1, sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&m->diag_inv, &m->diag_inv_capacity, 36 * n + 1,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&m->work, &m->work_capacity, 6 * n + 1, sizeof(double));
    if (st == SINTER_OK)
        st =
            sinter_grow(ctx, (void **)&m->row_start, &m->row_start_capacity, n + 2, sizeof(size_t));
    if (st == SINTER_OK)
        st =
            sinter_grow(ctx, (void **)&m->row_cross, &m->row_cross_capacity, n + 1, sizeof(size_t));
    if (st == SINTER_OK)
        st =
            sinter_grow(ctx, (void **)&m->column, &m->column_capacity, count + 1, sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&m->link_of, &m->link_of_capacity, count + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&m->upper_rows, &m->upper_rows_capacity, 36 * count + 1,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(ctx, (void **)&m->upper_cols, &m->upper_cols_capacity, 36 * count + 1,
                         sizeof(double));
    if (st != SINTER_OK)
        return st;
    m->n = n;
    m->split_a = split_a;
    m->split_b = split_b;
    /* Counting sort by lower particle; within a row the blocks into its own domain, then
     * those into S, each in link order. */
    size_t *start = m->row_start;
    memset(start, 0, (n + 2) * sizeof(size_t));
    for (size_t k = 0; k < count; ++k) /* counts, two places up */
        ++start[lower[k] + 2];
    for (size_t p = 2; p <= n + 1; ++p)
        start[p] += start[p - 1];
    for (int into_s = 0; into_s < 2; ++into_s) {
        for (size_t k = 0; k < count; ++k) { /* start[p + 1]: where p's next block goes */
            if ((upper[k] >= split_b) != into_s)
                continue;
            const size_t e = start[lower[k] + 1]++;
            m->column[e] = upper[k];
            m->link_of[e] = (uint32_t)k;
        }
        if (!into_s)
            for (size_t p = 0; p < n; ++p)
                m->row_cross[p] = start[p + 1];
    }
    return SINTER_OK;
}

/* In-place inverse of a 6x6 matrix by Gauss-Jordan with partial pivoting; -1 if singular. */
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

/* Particles [lo, hi) of sinter_block_ssor_finish: their rows' blocks by columns and their
 * diagonal blocks' inverses; the first singular one (SIZE_MAX: none). */
static size_t finish_rows(sinter_block_ssor *m, size_t lo, size_t hi)
{
    for (size_t e = m->row_start[lo]; e < m->row_start[hi]; ++e)
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                m->upper_cols[36 * e + (size_t)(6 * c + r)] =
                    m->upper_rows[36 * e + (size_t)(6 * r + c)];
    for (size_t p = lo; p < hi; ++p) {
        double *inv = m->diag_inv + 36 * p;
        memcpy(inv, m->diag + 36 * p, 36 * sizeof(double));
        if (invert6(inv) != 0)
            return p;
        /* D_p is symmetric; so is its inverse, up to rounding, which the kernels below rely on
         * (they read a symmetric block's rows as its columns). */
        for (int r = 0; r < 6; ++r)
            for (int c = r + 1; c < 6; ++c) {
                const double mean = 0.5 * (inv[6 * r + c] + inv[6 * c + r]);
                inv[6 * r + c] = inv[6 * c + r] = mean;
            }
    }
    return SIZE_MAX;
}

/* sinter_block_ssor_finish's share of a domain (sinter_two_parts). */
typedef struct finish_work {
    sinter_block_ssor *m;
    size_t singular[2];
} finish_work;

static void finish_part(void *data, int which)
{
    finish_work *w = data;
    sinter_block_ssor *m = w->m;
    w->singular[which] =
        which ? finish_rows(m, m->split_a, m->split_b) : finish_rows(m, 0, m->split_a);
}

int sinter_block_ssor_finish(sinter_block_ssor *m, size_t *singular)
{
    finish_work w = {m, {SIZE_MAX, SIZE_MAX}};
    sinter_two_parts(sinter_block_ssor_threads(m), finish_part, &w);
    size_t first = w.singular[0] < w.singular[1] ? w.singular[0] : w.singular[1];
    if (first == SIZE_MAX)
        first = finish_rows(m, m->split_b, m->n);
    if (first == SIZE_MAX)
        return 0;
    *singular = first;
    return -1;
}

/*
 * The kernels rest on one block product, out = B x with B given by columns (column c at
 * cols[6 c .. 6 c + 5]): six 6-long multiply-adds, in two partial sums (even and odd columns)
 * so that consecutive additions need not wait for each other. GCC and Clang get it as 4- and
 * 2-wide vector operations (GCC leaves the plain loops scalar: tests/bench/RESULTS.md,
 * session 14); other compilers the plain loops, same operations in the same order. A symmetric
 * block is its own column form; a coupling block U_pq is read by columns (upper_cols) for
 * U_pq x and by rows (upper_rows, the columns of U_pq^T) for U_pq^T x.
 */
#if defined(__GNUC__) || defined(__clang__)
typedef double block_v4 __attribute__((vector_size(32)));
typedef double block_v2 __attribute__((vector_size(16)));

/* (no function returns a vector: GCC warns of the ABI where AVX is not enabled) */
#define BLOCK_COLUMN(lo, hi, cols, c, xc)                                                          \
    do {                                                                                           \
        memcpy(&(lo), (cols) + 6 * (c), sizeof(lo));                                               \
        memcpy(&(hi), (cols) + 6 * (c) + 4, sizeof(hi));                                           \
        (lo) *= (xc);                                                                              \
        (hi) *= (xc);                                                                              \
    } while (0)

static inline void block_times(const double *restrict cols, const double *restrict x,
                               double *restrict out)
{
    block_v4 le, lo, l2, l3; /* rows 0-3: even and odd columns */
    block_v2 he, ho, h2, h3; /* rows 4-5 */
    BLOCK_COLUMN(le, he, cols, 0, x[0]);
    BLOCK_COLUMN(lo, ho, cols, 1, x[1]);
    for (int c = 2; c < 6; c += 2) {
        BLOCK_COLUMN(l2, h2, cols, c, x[c]);
        BLOCK_COLUMN(l3, h3, cols, c + 1, x[c + 1]);
        le += l2;
        lo += l3;
        he += h2;
        ho += h3;
    }
    le += lo;
    he += ho;
    memcpy(out, &le, sizeof(le));
    memcpy(out + 4, &he, sizeof(he));
}
#else
static inline void block_times(const double *restrict cols, const double *restrict x,
                               double *restrict out)
{
    for (int r = 0; r < 6; ++r)
        out[r] = (cols[r] * x[0] + cols[12 + r] * x[2] + cols[24 + r] * x[4]) +
                 (cols[6 + r] * x[1] + cols[18 + r] * x[3] + cols[30 + r] * x[5]);
}
#endif

/* Backward sweep over particles [lo, hi): x_p = D_p^-1 (v_p - sum_q>p U_pq x_q), x_q already
 * in v's place (every q > p of p's domain and of S is done before p). */
static inline void backward_rows(const sinter_block_ssor *m, double *v, size_t lo, size_t hi)
{
    for (size_t p = hi; p-- > lo;) {
        double acc[6], t[6];
        memcpy(acc, v + 6 * p, sizeof(acc));
        for (size_t e = m->row_start[p]; e < m->row_start[p + 1]; ++e) {
            block_times(m->upper_cols + 36 * e, v + 6 * (size_t)m->column[e], t);
            for (int r = 0; r < 6; ++r)
                acc[r] -= t[r];
        }
        block_times(m->diag_inv + 36 * p, acc, v + 6 * p);
    }
}

/* Push form of the forward sweep over particles [lo, hi): x_p = D_p^-1 v_p once every lower
 * particle has subtracted its L_pq x_q = U_qp^T x_q from v_p; then p subtracts its own from its
 * upper neighbours, through its blocks within its domain only (all of them: within_only 0, in
 * S). */
static inline void forward_rows(const sinter_block_ssor *m, double *v, size_t lo, size_t hi,
                                int within_only)
{
    for (size_t p = lo; p < hi; ++p) {
        double x[6], t[6];
        block_times(m->diag_inv + 36 * p, v + 6 * p, x);
        memcpy(v + 6 * p, x, sizeof(x));
        const size_t end = within_only ? m->row_cross[p] : m->row_start[p + 1];
        for (size_t e = m->row_start[p]; e < end; ++e) {
            double *vq = v + 6 * (size_t)m->column[e];
            block_times(m->upper_rows + 36 * e, x, t);
            for (int r = 0; r < 6; ++r)
                vq[r] -= t[r];
        }
    }
}

/* The forward sweep's pushes from the domains' particles, solved, into S, in particle order:
 * each particle of S receives them in the order a sweep over all particles would give. */
static inline void forward_cross(const sinter_block_ssor *m, double *v)
{
    for (size_t p = 0; p < m->split_b; ++p) {
        const double *x = v + 6 * p;
        for (size_t e = m->row_cross[p]; e < m->row_start[p + 1]; ++e) {
            double *vq = v + 6 * (size_t)m->column[e], t[6];
            block_times(m->upper_rows + 36 * e, x, t);
            for (int r = 0; r < 6; ++r)
                vq[r] -= t[r];
        }
    }
}

SINTER_CLONES
void sinter_block_ssor_upper_solve(const sinter_block_ssor *m, double *v)
{
    backward_rows(m, v, m->split_b, m->n);
    backward_rows(m, v, m->split_a, m->split_b);
    backward_rows(m, v, 0, m->split_a);
}

SINTER_CLONES
void sinter_block_ssor_lower_solve(const sinter_block_ssor *m, double *v)
{
    forward_rows(m, v, 0, m->split_a, 1);
    forward_rows(m, v, m->split_a, m->split_b, 1);
    forward_cross(m, v);
    forward_rows(m, v, m->split_b, m->n, 0);
}

SINTER_CLONES
void sinter_block_ssor_upper_multiply(const sinter_block_ssor *m, const double *x, double *y)
{
    for (size_t p = 0; p < m->n; ++p) {
        double acc[6], t[6];
        block_times(m->diag + 36 * p, x + 6 * p, acc);
        for (size_t e = m->row_start[p]; e < m->row_start[p + 1]; ++e) {
            block_times(m->upper_cols + 36 * e, x + 6 * (size_t)m->column[e], t);
            for (int r = 0; r < 6; ++r)
                acc[r] += t[r];
        }
        memcpy(y + 6 * p, acc, sizeof(acc));
    }
}

SINTER_CLONES
void sinter_block_ssor_multiply(const sinter_block_ssor *m, const double *x, double *y)
{
    memset(y, 0, 6 * m->n * sizeof(double));
    for (size_t p = 0; p < m->n; ++p) {
        double acc[6], t[6];
        block_times(m->diag + 36 * p, x + 6 * p, acc);
        for (size_t e = m->row_start[p]; e < m->row_start[p + 1]; ++e) {
            double *yq = y + 6 * (size_t)m->column[e];
            block_times(m->upper_cols + 36 * e, x + 6 * (size_t)m->column[e], t);
            for (int r = 0; r < 6; ++r)
                acc[r] += t[r];
            block_times(m->upper_rows + 36 * e, x + 6 * p, t);
            for (int r = 0; r < 6; ++r)
                yq[r] += t[r];
        }
        for (int r = 0; r < 6; ++r) /* y_p holds the lower particles' U_qp^T x_q */
            y[6 * p + (size_t)r] += acc[r];
    }
}

/* Particles below which one thread does the products alone: the two threads' meeting points
 * cost about a microsecond, a sweep over so many particles about ten. */
#define TWO_THREADS_FROM 256

int sinter_block_ssor_threads(const sinter_block_ssor *m)
{
#ifdef _OPENMP
    if (m->n >= TWO_THREADS_FROM && m->split_a > 0 && m->split_b > m->split_a &&
        sinter_threads(m->ctx) >= 2)
        return 2;
#endif
    (void)m;
    return 1;
}

SINTER_CLONES
static void diag_rows(const sinter_block_ssor *m, const double *x, double *y, size_t lo, size_t hi)
{
    for (size_t p = lo; p < hi; ++p)
        block_times(m->diag + 36 * p, x + 6 * p, y + 6 * p);
}

/* A domain's share of a product (sinter_two_parts): domain A (which 0) or B (1). */
typedef struct domain_work {
    const sinter_block_ssor *m;
    const double *v;
    double *y, *s;
} domain_work;

static void domain_rows(const sinter_block_ssor *m, int which, size_t *lo, size_t *hi)
{
    *lo = which ? m->split_a : 0;
    *hi = which ? m->split_b : m->split_a;
}

static void diag_part(void *data, int which)
{
    const domain_work *w = data;
    size_t lo, hi;
    domain_rows(w->m, which, &lo, &hi);
    diag_rows(w->m, w->v, w->y, lo, hi);
}

void sinter_block_ssor_diag_multiply(const sinter_block_ssor *m, const double *x, double *y)
{
    domain_work w = {m, x, y, NULL};
    sinter_two_parts(sinter_block_ssor_threads(m), diag_part, &w);
    diag_rows(m, x, y, m->split_b, m->n);
}

/* Eisenstat's product on particles [lo, hi) up to the forward sweep's pushes into S:
 * y = t = E^-T v there (the particles above them done), s = v - D t. */
static inline void transformed_backward(const sinter_block_ssor *m, const double *v, double *y,
                                        double *s, size_t lo, size_t hi)
{
    memcpy(y + 6 * lo, v + 6 * lo, 6 * (hi - lo) * sizeof(double));
    backward_rows(m, y, lo, hi);
    for (size_t p = lo; p < hi; ++p) {
        double dt[6];
        block_times(m->diag + 36 * p, y + 6 * p, dt);
        for (int r = 0; r < 6; ++r)
            s[6 * p + (size_t)r] = v[6 * p + (size_t)r] - dt[r];
    }
}

/* A domain [lo, hi) of Eisenstat's product after S's backward sweep: all of it. (Cloned on
 * its own: the threads call it from outside sinter_block_ssor_transformed's clone.) */
SINTER_CLONES
static void transformed_domain(const sinter_block_ssor *m, const double *v, double *y, double *s,
                               size_t lo, size_t hi)
{
    transformed_backward(m, v, y, s, lo, hi);
    forward_rows(m, s, lo, hi, 1);
    for (size_t i = 6 * lo; i < 6 * hi; ++i)
        y[i] += s[i];
}

static void transformed_part(void *data, int which)
{
    const domain_work *w = data;
    size_t lo, hi;
    domain_rows(w->m, which, &lo, &hi);
    transformed_domain(w->m, w->v, w->y, w->s, lo, hi);
}

/* S's end of Eisenstat's product, after both domains. */
static inline void transformed_separator_end(const sinter_block_ssor *m, double *y, double *s)
{
    forward_cross(m, s);
    forward_rows(m, s, m->split_b, m->n, 0);
    for (size_t i = 6 * m->split_b; i < 6 * m->n; ++i)
        y[i] += s[i];
}

/* K^ v = t + E^-1 (v - D t), t = E^-T v (block_ssor.h): S's backward sweep, then the two
 * domains, each all the way (side by side on two threads), then S's forward sweep. */
SINTER_CLONES
void sinter_block_ssor_transformed(const sinter_block_ssor *m, const double *v, double *y)
{
    double *s = m->work;
    transformed_backward(m, v, y, s, m->split_b, m->n);
    domain_work w = {m, v, y, s};
    sinter_two_parts(sinter_block_ssor_threads(m), transformed_part, &w);
    transformed_separator_end(m, y, s);
}
