/* Anderson(m) acceleration of a fixed-point iteration; see anderson.h. */
#include "stepper/anderson.h"

#include <math.h>
#include <string.h>

#include "core/core.h"

enum { ANDERSON_MAX_DEPTH = 10 };

void sinter_anderson_init(sinter_anderson *aa)
{
    memset(aa, 0, sizeof(*aa));
}

void sinter_anderson_free(sinter_ctx *ctx, sinter_anderson *aa)
{
    sinter_free(ctx, aa->df);
    sinter_anderson_init(aa);
}

sinter_status sinter_anderson_reset(sinter_ctx *ctx, sinter_anderson *aa, size_t length, int depth)
{
    if (depth < 0 || depth > ANDERSON_MAX_DEPTH)
        return SINTER_ERR_INVALID;
    /* One block: df, dg, q (depth x N each), f_prev, g_prev, wf (N each). */
    const size_t need = (3 * (size_t)depth + 3) * length + 1;
    if (need > aa->capacity) {
        double *p = sinter_realloc_array(ctx, aa->df, need, sizeof(double));
        if (p == NULL)
            return sinter_last_status(ctx);
        aa->df = p;
        aa->capacity = need;
    }
    aa->length = length;
    aa->depth = depth;
    aa->dg = aa->df + (size_t)depth * length;
    aa->q = aa->dg + (size_t)depth * length;
    aa->f_prev = aa->q + (size_t)depth * length;
    aa->g_prev = aa->f_prev + length;
    aa->wf = aa->g_prev + length;
    aa->stored = 0;
    aa->head = 0;
    aa->have_prev = 0;
    return SINTER_OK;
}

/* The inner products' sums over the parts of a distributed vector (nothing when whole). */
static int sum_parts(const sinter_anderson_sum *sum, double *values, size_t count)
{
    return sum != NULL ? sum->sum(values, count, sum->user) : 0;
}

/* count inner products out[c] = sum_i a[c][i] b[c][i] over every part: through sum->dots when
 * given (exact), else each part's sum in index order, then summed over the parts. */
static int inner(const sinter_anderson_sum *sum, const double *const *a, const double *const *b,
                 size_t n, size_t count, double *out)
{
    if (sum != NULL && sum->dots != NULL)
        return sum->dots(a, b, n, count, out, sum->user);
    for (size_t c = 0; c < count; ++c) {
        double d = 0.0;
        for (size_t i = 0; i < n; ++i)
            d += a[c][i] * b[c][i];
        out[c] = d;
    }
    return sum_parts(sum, out, count);
}

int sinter_anderson_update(sinter_anderson *aa, double *u, const double *g, const double *w,
                           const sinter_anderson_sum *sum)
{
    const size_t n = aa->length;
    const int m = aa->depth;
    if (m == 0) {
        memcpy(u, g, n * sizeof(double));
        return 0;
    }
    /* The newest differences: slot after the newest (overwrites the oldest when full). */
    if (aa->have_prev) {
        int slot;
        if (aa->stored < m) {
            slot = (aa->head + aa->stored) % m;
            aa->stored++;
        } else {
            slot = aa->head;
            aa->head = (aa->head + 1) % m;
        }
        double *df = aa->df + (size_t)slot * n, *dg = aa->dg + (size_t)slot * n;
        for (size_t i = 0; i < n; ++i) {
            const double f = g[i] - u[i];
            df[i] = f - aa->f_prev[i];
            dg[i] = g[i] - aa->g_prev[i];
        }
    }
    for (size_t i = 0; i < n; ++i) {
        aa->f_prev[i] = g[i] - u[i];
        aa->g_prev[i] = g[i];
    }
    aa->have_prev = 1;
    const int k = aa->stored;
    if (k == 0) {
        memcpy(u, g, n * sizeof(double));
        return 0;
    }
    /* Modified Gram-Schmidt QR of W dF, columns oldest to newest; a column that is (nearly) a
     * combination of the earlier ones is left out (gamma_j = 0). */
    double r[ANDERSON_MAX_DEPTH][ANDERSON_MAX_DEPTH] = {{0}};
    int used[ANDERSON_MAX_DEPTH] = {0};
    double largest = 0.0;
    int failed = 0; /* a sum failed: every later one is still made (collective) */
    for (int j = 0; j < k; ++j) {
        const int slot = (aa->head + j) % m;
        const double *df = aa->df + (size_t)slot * n;
        double *qj = aa->q + (size_t)j * n;
        const double *qq[1] = {qj};
        for (size_t i = 0; i < n; ++i)
            qj[i] = w[i] * df[i];
        double norm0 = 0.0;
        if (inner(sum, qq, qq, n, 1, &norm0) != 0)
            failed = 1;
        norm0 = sqrt(norm0);
        largest = fmax(largest, norm0);
        for (int l = 0; l < j; ++l) {
            if (!used[l])
                continue;
            const double *ql[1] = {aa->q + (size_t)l * n};
            double dot = 0.0;
            if (inner(sum, ql, qq, n, 1, &dot) != 0)
                failed = 1;
            r[l][j] = dot;
            for (size_t i = 0; i < n; ++i)
                qj[i] -= dot * ql[0][i];
        }
        double norm = 0.0;
        if (inner(sum, qq, qq, n, 1, &norm) != 0)
            failed = 1;
        norm = sqrt(norm);
        if (!(norm > 1e-10 * largest) || !(norm > 0.0))
            continue;
        used[j] = 1;
        r[j][j] = norm;
        for (size_t i = 0; i < n; ++i)
            qj[i] /= norm;
    }
    /* gamma = R^-1 Q^T W f_k */
    double c[ANDERSON_MAX_DEPTH] = {0}, gamma[ANDERSON_MAX_DEPTH] = {0};
    int any = 0;
    if (sum != NULL && sum->dots != NULL) { /* exact: (W f_k) . q_j for the columns used */
        const double *qs[ANDERSON_MAX_DEPTH], *wfs[ANDERSON_MAX_DEPTH];
        double out[ANDERSON_MAX_DEPTH];
        size_t count = 0;
        for (size_t i = 0; i < n; ++i)
            aa->wf[i] = w[i] * aa->f_prev[i];
        for (int j = 0; j < k; ++j) {
            if (!used[j])
                continue;
            qs[count] = aa->q + (size_t)j * n;
            wfs[count++] = aa->wf;
        }
        any = count > 0;
        if (any && sum->dots(qs, wfs, n, count, out, sum->user) != 0)
            failed = 1;
        for (int j = 0, at = 0; j < k && any; ++j)
            if (used[j])
                c[j] = out[at++];
    } else {
        for (int j = 0; j < k; ++j) {
            if (!used[j])
                continue;
            any = 1;
            const double *qj = aa->q + (size_t)j * n;
            double dot = 0.0;
            for (size_t i = 0; i < n; ++i)
                dot += qj[i] * w[i] * aa->f_prev[i];
            c[j] = dot;
        }
        if (any && sum_parts(sum, c, (size_t)k) != 0) /* (the unused ones are 0) */
            failed = 1;
    }
    if (failed) {
        memcpy(u, g, n * sizeof(double));
        return -1;
    }
    for (int j = k - 1; j >= 0; --j) {
        if (!used[j])
            continue;
        double v = c[j];
        for (int l = j + 1; l < k; ++l)
            if (used[l])
                v -= r[j][l] * gamma[l];
        gamma[j] = v / r[j][j];
    }
    memcpy(u, g, n * sizeof(double));
    if (!any)
        return 0;
    int count = 0;
    for (int j = 0; j < k; ++j) {
        if (!used[j])
            continue;
        count++;
        const double *dg = aa->dg + (size_t)((aa->head + j) % m) * n;
        for (size_t i = 0; i < n; ++i)
            u[i] -= gamma[j] * dg[i];
    }
    return count;
}
