/* K u = f over links spread across subdomains: PCG with block-Jacobi (bonded/solve_split.h). */
#include <math.h>
#include <string.h>

#include "bonded/solve_split.h"

/* Rounds of "PCG, then the true residual" before the solve gives up (as bonded/solve.c). */
#define SPLIT_ROUNDS 6
/* PCG iterations per round at most, per global DOF (a CG in exact arithmetic needs one). */
#define SPLIT_ITERATIONS_PER_DOF 4
/* The largest relative residual taken for a rounding floor (as bonded/solve.c). */
#define SPLIT_ROUNDING_FLOOR 1e-6

typedef struct split {
    sinter_ctx *ctx;
    size_t owned, rows, count;
    const sinter_beam *links;
    const sinter_bonded_exchange *ex;
    double *k;           /* 144 per link: its element stiffness (bonded/beam.h) */
    double *inverse;     /* 36 per row: the inverse of the masked diagonal block */
    unsigned char *mask; /* 6 per row: 1 constrained */
    double *work;        /* 6 per row: the operator's input with its ghost rows */
    int failed;          /* an exchange failed */
    /* the reproducible mode (exchange.reproducible): each link's terms for its two rows, the
     * rows they go to, and the exact row sums' work (core/repro_sum.h) */
    double *terms; /* 72 per link (the diagonal blocks; 12 for the operator) */
    uint32_t *row; /* 2 per link: a, b */
    void *rows_work;
} split;

/* The reproducible mode's exact row sums of 2 contributions per link (width values each). */
static void exact_rows(split *s, size_t width, double *out)
{
    if (sinter_repro_rows(s->rows, s->owned, width, s->row, s->terms, 2 * s->count, s->ex->reduce,
                          s->ex->reverse, s->ex->user, s->rows_work, out) != 0)
        s->failed = 1;
}

/* count dot products over the owned rows, summed across subdomains (exact in the reproducible
 * mode; else each subdomain's in row order, then the host's sum); collective. */
static void dots_all(split *s, const double *const *a, const double *const *b, size_t count,
                     double *out)
{
    if (s->ex->reproducible) {
        if (sinter_repro_dots(a, b, 6 * s->owned, count, s->ex->reduce, s->ex->user, out) != 0)
            s->failed = 1;
        return;
    }
    for (size_t j = 0; j < count; ++j) {
        double sum = 0.0;
        for (size_t i = 0; i < 6 * s->owned; ++i)
            sum += a[j][i] * b[j][i];
        out[j] = sum;
    }
    if (s->ex->sum(out, count, s->ex->user) != 0)
        s->failed = 1;
}

static double owned_dot(const split *s, const double *a, const double *b)
{
    double sum = 0.0;
    for (size_t i = 0; i < 6 * s->owned; ++i)
        sum += a[i] * b[i];
    return sum;
}

/* Sum values across subdomains; on failure they are left and s->failed set. */
static void sum_all(split *s, double *values, size_t count)
{
    if (s->ex->sum(values, count, s->ex->user) != 0)
        s->failed = 1;
}

/* y = (P K P + I - P) v over the owned rows (v's owned rows masked); collective. */
static void apply(split *s, const double *v, double *y)
{
    const size_t width = 6 * s->rows;
    memcpy(s->work, v, 6 * s->owned * sizeof(double));
    if (s->ex->forward(s->work, 6, s->ex->user) != 0)
        s->failed = 1;
    memset(y, 0, width * sizeof(double));
    if (s->ex->reproducible) { /* each link's two rows of terms, then exact row sums */
        for (size_t e = 0; e < s->count; ++e) {
            const double *k = s->k + 144 * e;
            const double *va = s->work + 6 * (size_t)s->links[e].a;
            const double *vb = s->work + 6 * (size_t)s->links[e].b;
            double *ta = s->terms + 12 * e, *tb = ta + 6;
            for (int r = 0; r < 6; ++r) {
                double sa = 0.0, sb = 0.0;
                for (int c = 0; c < 6; ++c) {
                    sa += k[12 * r + c] * va[c] + k[12 * r + 6 + c] * vb[c];
                    sb += k[12 * (6 + r) + c] * va[c] + k[12 * (6 + r) + 6 + c] * vb[c];
                }
                ta[r] = sa;
                tb[r] = sb;
            }
        }
        exact_rows(s, 6, y);
    }
    for (size_t e = 0; e < s->count && !s->ex->reproducible; ++e) {
        const double *k = s->k + 144 * e;
        const double *va = s->work + 6 * (size_t)s->links[e].a;
        const double *vb = s->work + 6 * (size_t)s->links[e].b;
        double *ya = y + 6 * (size_t)s->links[e].a, *yb = y + 6 * (size_t)s->links[e].b;
        for (int r = 0; r < 6; ++r) {
            double sa = 0.0, sb = 0.0;
            for (int c = 0; c < 6; ++c) {
                sa += k[12 * r + c] * va[c] + k[12 * r + 6 + c] * vb[c];
                sb += k[12 * (6 + r) + c] * va[c] + k[12 * (6 + r) + 6 + c] * vb[c];
            }
            ya[r] += sa;
            yb[r] += sb;
        }
    }
    if (!s->ex->reproducible && s->ex->reverse(y, 6, s->ex->user) != 0)
        s->failed = 1;
    for (size_t i = 0; i < 6 * s->owned; ++i)
        if (s->mask[i])
            y[i] = v[i];
}

/* z = M^-1 r, block by block over the owned rows. */
static void precondition(const split *s, const double *r, double *z)
{
    for (size_t p = 0; p < s->owned; ++p) {
        const double *m = s->inverse + 36 * p;
        for (int i = 0; i < 6; ++i) {
            double sum = 0.0;
            for (int j = 0; j < 6; ++j)
                sum += m[6 * i + j] * r[6 * p + (size_t)j];
            z[6 * p + (size_t)i] = sum;
        }
    }
}

/* Invert the symmetric positive definite 6x6 block a into inv (Gauss-Jordan with the
 * diagonal pivots, which an SPD block keeps positive). Returns -1 when a pivot is not. */
static int invert6(const double a[36], double inv[36])
{
    double m[36];
    memcpy(m, a, sizeof(m));
    for (int i = 0; i < 36; ++i)
        inv[i] = i % 7 == 0 ? 1.0 : 0.0;
    for (int c = 0; c < 6; ++c) {
        const double pivot = m[7 * c];
        if (!(pivot > 0.0) || !isfinite(pivot))
            return -1;
        for (int j = 0; j < 6; ++j) {
            m[6 * c + j] /= pivot;
            inv[6 * c + j] /= pivot;
        }
        for (int r = 0; r < 6; ++r) {
            if (r == c)
                continue;
            const double factor = m[6 * r + c];
            for (int j = 0; j < 6; ++j) {
                m[6 * r + j] -= factor * m[6 * c + j];
                inv[6 * r + j] -= factor * inv[6 * c + j];
            }
        }
    }
    return 0;
}

/* The element stiffnesses, the mask and the preconditioner's blocks; collective (one reverse
 * exchange of the diagonal blocks). Returns the index + 1 of an owned row whose block is
 * singular, or 0. */
static size_t assemble(split *s, const unsigned char *fixed, double *diag)
{
    memset(diag, 0, 36 * s->rows * sizeof(double));
    for (size_t e = 0; e < s->count; ++e) {
        double *k = s->k + 144 * e;
        sinter_beam_stiffness(&s->links[e], k);
        double *da = diag + 36 * (size_t)s->links[e].a, *db = diag + 36 * (size_t)s->links[e].b;
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c) {
                da[6 * r + c] += k[12 * r + c];
                db[6 * r + c] += k[12 * (6 + r) + 6 + c];
            }
    }
    if (s->ex->reproducible) { /* the blocks again as terms, then exact row sums */
        for (size_t e = 0; e < s->count; ++e) {
            const double *k = s->k + 144 * e;
            double *ta = s->terms + 72 * e, *tb = ta + 36;
            for (int r = 0; r < 6; ++r)
                for (int c = 0; c < 6; ++c) {
                    ta[6 * r + c] = k[12 * r + c];
                    tb[6 * r + c] = k[12 * (6 + r) + 6 + c];
                }
            s->row[2 * e] = s->links[e].a;
            s->row[2 * e + 1] = s->links[e].b;
        }
        exact_rows(s, 36, diag);
    } else if (s->ex->reverse(diag, 36, s->ex->user) != 0)
        s->failed = 1;
    size_t singular = 0;
    for (size_t p = 0; p < s->owned; ++p) {
        double *blk = diag + 36 * p;
        unsigned char *mk = s->mask + 6 * p;
        for (int d = 0; d < 6; ++d)
            mk[d] =
                (unsigned char)((fixed != NULL && fixed[6 * p + (size_t)d]) || !(blk[7 * d] > 0.0));
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                if (mk[r] || mk[c])
                    blk[6 * r + c] = r == c ? 1.0 : 0.0;
        if (invert6(blk, s->inverse + 36 * p) != 0 && singular == 0)
            singular = p + 1;
    }
    return singular;
}

sinter_status sinter_bonded_solve_split(sinter_ctx *ctx, size_t owned, size_t rows,
                                        const sinter_beam *links, size_t count,
                                        const unsigned char *fixed, const double *f,
                                        const double *guess, double *u, double rtol,
                                        const sinter_bonded_exchange *ex, int *iterations)
{
    SINTER_CHECK_NULL(ctx, ex);
    if (iterations)
        *iterations = 0;
    split s = {ctx, owned, rows, count, links, ex, NULL, NULL, NULL, NULL, 0, NULL, NULL, NULL};
    sinter_status st = SINTER_OK;
    for (size_t e = 0; e < count && st == SINTER_OK; ++e)
        if (links[e].a >= rows || links[e].b >= rows || links[e].a == links[e].b)
            st = sinter_fail(ctx, SINTER_ERR_INVALID,
                             "split bonded solve: link %zu joins rows %u and %u of %zu", e,
                             (unsigned)links[e].a, (unsigned)links[e].b, rows);
    const size_t w = 6 * rows + 1;
    double *vec = NULL, *diag = NULL;
    if (st == SINTER_OK) {
        s.k = sinter_alloc(ctx, (144 * count + 1) * sizeof(double));
        s.inverse = sinter_alloc(ctx, (36 * owned + 1) * sizeof(double));
        s.mask = sinter_alloc(ctx, w);
        s.work = sinter_alloc(ctx, w * sizeof(double));
        diag = sinter_alloc(ctx, (36 * rows + 1) * sizeof(double));
        vec = sinter_alloc(ctx, 6 * w * sizeof(double)); /* b, r, z, p, q, x */
        if (ex->reproducible) {
            s.terms = sinter_alloc(ctx, (72 * count + 1) * sizeof(double));
            s.row = sinter_alloc(ctx, (2 * count + 1) * sizeof(uint32_t));
            s.rows_work = sinter_alloc(ctx, sinter_repro_rows_bytes(rows, 36) + 1);
        }
        if (s.k == NULL || s.inverse == NULL || s.mask == NULL || s.work == NULL || diag == NULL ||
            vec == NULL ||
            (ex->reproducible && (s.terms == NULL || s.row == NULL || s.rows_work == NULL)))
            st = SINTER_ERR_NOMEM;
    }
    /* every subdomain learns whether one cannot go on before any exchange */
    double failed_somewhere = st != SINTER_OK ? 1.0 : 0.0;
    sum_all(&s, &failed_somewhere, 1);
    if (st != SINTER_OK || failed_somewhere != 0.0 || s.failed) {
        if (st == SINTER_OK && s.failed)
            st = sinter_fail(ctx, SINTER_ERR_CALLBACK, "split bonded solve: an exchange failed");
        if (u != NULL && st == SINTER_OK) /* another subdomain failed: its status is agreed */
            memset(u, 0, 6 * rows * sizeof(double));
        goto done;
    }
    double *b = vec, *r = vec + w, *z = vec + 2 * w, *p = vec + 3 * w, *q = vec + 4 * w,
           *x = vec + 5 * w;
    double singular = (double)assemble(&s, fixed, diag);
    const size_t dofs = 6 * owned;
    double sums[3];
    for (size_t i = 0; i < dofs; ++i) {
        b[i] = s.mask[i] ? 0.0 : f[i];
        x[i] = s.mask[i] || guess == NULL ? 0.0 : guess[i];
    }
    sums[0] = ex->reproducible ? 0.0 : owned_dot(&s, b, b);
    sums[1] = singular > 0.0 ? 1.0 : 0.0;
    sums[2] = (double)dofs;
    sum_all(&s, sums, 3);
    if (ex->reproducible) { /* |b|^2 exactly (the others are counts: exact sums already) */
        const double *bb[1] = {b};
        dots_all(&s, bb, bb, 1, sums);
    }
    const double norm = sqrt(sums[0]), target = rtol * norm, total_dofs = sums[2];
    if (sums[1] > 0.0 || s.failed) {
        if (s.failed)
            st = sinter_fail(ctx, SINTER_ERR_CALLBACK, "split bonded solve: an exchange failed");
        else if (singular > 0.0)
            st = sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                             "split bonded solve: the stiffness block of row %zu is singular",
                             (size_t)singular - 1);
        memset(u, 0, 6 * rows * sizeof(double)); /* (another subdomain's block: agreed) */
        goto done;
    }
    if (norm == 0.0) {
        memset(u, 0, 6 * rows * sizeof(double));
        goto done;
    }
    const double max_iterations = SPLIT_ITERATIONS_PER_DOF * total_dofs + 10.0;
    int taken = 0, done = 0;
    double true_residual = HUGE_VAL;
    for (int round = 0; !s.failed; ++round) {
        /* r = b - A x, then plain PCG until the recursive residual meets the target */
        apply(&s, x, q);
        for (size_t i = 0; i < dofs; ++i)
            r[i] = b[i] - q[i];
        precondition(&s, r, z);
        memcpy(p, z, dofs * sizeof(double));
        double rr[2];
        const double *ra[2] = {r, r}, *rb[2] = {z, r};
        dots_all(&s, ra, rb, 2, rr);
        const double last = true_residual;
        true_residual = sqrt(rr[1]);
        done = true_residual <= target || (round > 0 && true_residual > 0.5 * last &&
                                           true_residual <= SPLIT_ROUNDING_FLOOR * norm);
        if (done || round == SPLIT_ROUNDS)
            break;
        double rz = rr[0];
        for (double it = 0.0; !s.failed && it < max_iterations; it += 1.0) {
            apply(&s, p, q);
            double pq;
            const double *pa[1] = {p}, *pb[1] = {q};
            dots_all(&s, pa, pb, 1, &pq);
            if (!(pq > 0.0))
                break; /* no descent left (the rounding floor): the round ends */
            const double alpha = rz / pq;
            for (size_t i = 0; i < dofs; ++i) {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
            }
            precondition(&s, r, z);
            double next[2];
            dots_all(&s, ra, rb, 2, next);
            ++taken;
            if (sqrt(next[1]) <= 0.5 * target)
                break; /* aim a bit under: the true residual is checked next round */
            const double beta = next[0] / rz;
            rz = next[0];
            for (size_t i = 0; i < dofs; ++i)
                p[i] = z[i] + beta * p[i];
        }
    }
    if (iterations)
        *iterations = taken;
    for (size_t i = 0; i < dofs; ++i)
        u[i] = s.mask[i] ? 0.0 : x[i];
    if (!s.failed && ex->forward(u, 6, ex->user) != 0)
        s.failed = 1;
    if (s.failed)
        st = sinter_fail(ctx, SINTER_ERR_CALLBACK, "split bonded solve: an exchange failed");
    else if (!done)
        st = sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                         "split bonded solve: PCG did not meet the target after %d iterations "
                         "(residual %g, |f| %g) over %.0f DOFs",
                         taken, true_residual, norm, total_dofs);
done:
    sinter_free(ctx, s.k);
    sinter_free(ctx, s.inverse);
    sinter_free(ctx, s.mask);
    sinter_free(ctx, s.work);
    sinter_free(ctx, diag);
    sinter_free(ctx, vec);
    sinter_free(ctx, s.terms);
    sinter_free(ctx, s.row);
    sinter_free(ctx, s.rows_work);
    return st;
}
