/* Order-independent sums of doubles through integer limbs: see repro_sum.h. */
#include "core/repro_sum.h"

#include <math.h>
#include <string.h>

/* Terms are scaled by 2^-(e + HEADROOM): the first limb then takes less than 2^17 from a term,
 * and 2^45 terms fit in it (a sum may be that many times larger than its largest term). */
#define HEADROOM 23
/* Limbs 1 and 2 hold values below 2^40 after a carry; 2^22 additions stay below 2^62. */
#define CARRY_EVERY ((uint64_t)1 << 22)

int sinter_repro_exponent(const double *x, size_t n, size_t stride, int *finite)
{
    int e = INT32_MIN;
    int ok = 1;
    for (size_t k = 0; k < n; ++k) {
        const double v = x[k * stride];
        if (!isfinite(v)) {
            ok = 0;
            continue;
        }
        if (v == 0.0)
            continue;
        int ev = 0;
        uint64_t bits;
        memcpy(&bits, &v, sizeof(bits));
        const int biased = (int)((bits >> 52) & 0x7ff);
        if (biased != 0)
            ev = biased - 1022; /* a normal number: frexp's exponent, without the call */
        else
            frexp(v, &ev); /* |v| < 2^ev */
        e = ev > e ? ev : e;
    }
    if (finite != NULL)
        *finite = ok;
    return e;
}

/* Move each limb's excess above 40 bits into the next larger limb (floor division keeps every
 * limb but the first in [0, 2^40)). */
static void carry(sinter_repro_sum *s)
{
    for (int k = SINTER_REPRO_LIMBS - 1; k > 0; --k) {
        const int64_t c = s->limb[k] >> SINTER_REPRO_LIMB_BITS; /* arithmetic shift: floor */
        s->limb[k] -= c * ((int64_t)1 << SINTER_REPRO_LIMB_BITS);
        s->limb[k - 1] += c;
    }
    s->terms = 0;
}

void sinter_repro_add(sinter_repro_sum *s, int e, const double *x, size_t n, size_t stride)
{
    if (e == INT32_MIN)
        return; /* every term is zero */
    /* scaling by a normal power of two: the correctly rounded product, as ldexp's (both exact
     * unless the result is subnormal, and then rounded alike); a scale out of range: ldexp */
    const int shift = -e - HEADROOM;
    const int by_product = shift >= -1022 && shift <= 1023;
    const double scale = by_product ? ldexp(1.0, shift) : 0.0;
    const double limb_scale = (double)((int64_t)1 << SINTER_REPRO_LIMB_BITS);
    for (size_t k = 0; k < n; ++k) {
        const double v = x[k * stride];
        if (v == 0.0 || !isfinite(v))
            continue;
        double r = by_product ? v * scale : ldexp(v, shift); /* |r| < 2^-23, exact */
        for (int j = 0; j < SINTER_REPRO_LIMBS; ++j) {
            r *= limb_scale;                  /* exact */
            const int64_t whole = (int64_t)r; /* toward zero, as trunc: |r| < 2^40, exact */
            s->limb[j] += whole;
            r -= (double)whole; /* exact */
        }
        if (++s->terms >= CARRY_EVERY)
            carry(s);
    }
}

void sinter_repro_merge(sinter_repro_sum *a, const sinter_repro_sum *b)
{
    sinter_repro_sum c = *b;
    carry(&c);
    carry(a);
    for (int j = 0; j < SINTER_REPRO_LIMBS; ++j)
        a->limb[j] += c.limb[j];
    carry(a);
}

double sinter_repro_value(const sinter_repro_sum *s, int e)
{
    if (e == INT32_MIN)
        return 0.0;
    sinter_repro_sum c = *s;
    carry(&c);
    /* smallest limb first: each is exact in a double (< 2^41), their sum rounds once or twice */
    double v = 0.0;
    for (int j = SINTER_REPRO_LIMBS - 1; j >= 0; --j)
        v += ldexp((double)c.limb[j], e + HEADROOM - SINTER_REPRO_LIMB_BITS * (j + 1));
    return v;
}

/* ---- across parts through a host's collectives ---- */

void sinter_repro_to_doubles(const sinter_repro_sum *s, double out[SINTER_REPRO_LIMBS])
{
    sinter_repro_sum c = *s;
    carry(&c);
    for (int j = 0; j < SINTER_REPRO_LIMBS; ++j)
        out[j] = (double)c.limb[j]; /* exact: |limb| < 2^53 after a carry */
}

void sinter_repro_from_doubles(sinter_repro_sum *s, const double in[SINTER_REPRO_LIMBS])
{
    for (int j = 0; j < SINTER_REPRO_LIMBS; ++j)
        s->limb[j] = (int64_t)in[j]; /* integers: exact */
    s->terms = 0;
}

/* A batch's exponent for a sum with a term that is not finite: above every finite one, so
 * that the MAX over the parts keeps it. */
#define NOT_FINITE ((int64_t)1 << 32)

enum { CHUNK = 256 }; /* products formed on the stack, this many at a time */

void sinter_repro_begin(sinter_repro_batch *x, size_t count)
{
    memset(x, 0, sizeof(*x));
    x->count = count < SINTER_REPRO_BATCH ? count : SINTER_REPRO_BATCH;
    for (size_t c = 0; c < x->count; ++c)
        x->e[c] = INT32_MIN; /* (every term zero so far) */
}

/* Terms [k0, k0 + m) of a sum into p: a[k] or a[k] b[k] (each product rounded once, the same
 * bits wherever it is formed). */
static const double *terms_at(const double *a, const double *b, size_t k0, size_t m, double *p)
{
    if (b == NULL)
        return a + k0;
    for (size_t k = 0; k < m; ++k)
        p[k] = a[k0 + k] * b[k0 + k];
    return p;
}

void sinter_repro_scan(sinter_repro_batch *x, size_t c, const double *a, const double *b, size_t n)
{
    double p[CHUNK];
    for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
        const size_t m = n - k0 < CHUNK ? n - k0 : CHUNK;
        int finite = 1;
        const int e = sinter_repro_exponent(terms_at(a, b, k0, m, p), m, 1, &finite);
        const int64_t ec = finite ? e : NOT_FINITE;
        x->e[c] = ec > x->e[c] ? ec : x->e[c];
    }
}

int sinter_repro_agree(sinter_repro_batch *x, sinter_repro_reduce_fn reduce, void *user)
{
    return reduce != NULL && reduce(x->e, x->count, SINTER_REPRO_MAX, user) != 0 ? -1 : 0;
}

void sinter_repro_accumulate(sinter_repro_batch *x, size_t c, const double *a, const double *b,
                             size_t n)
{
    if (x->e[c] == NOT_FINITE)
        return; /* NaN in the end */
    double p[CHUNK];
    for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
        const size_t m = n - k0 < CHUNK ? n - k0 : CHUNK;
        sinter_repro_add(&x->s[c], (int)x->e[c], terms_at(a, b, k0, m, p), m, 1);
    }
}

int sinter_repro_finish(sinter_repro_batch *x, sinter_repro_reduce_fn reduce, void *user,
                        double *out)
{
    return sinter_repro_totals(x->s, x->e, x->count, reduce, user, out);
}

int sinter_repro_totals(sinter_repro_sum *sum, const int64_t *e, size_t count,
                        sinter_repro_reduce_fn reduce, void *user, double *out)
{
    int64_t limbs[SINTER_REPRO_BATCH * SINTER_REPRO_LIMBS];
    for (size_t j0 = 0; j0 < count; j0 += SINTER_REPRO_BATCH) {
        const size_t c = count - j0 < SINTER_REPRO_BATCH ? count - j0 : SINTER_REPRO_BATCH;
        for (size_t j = 0; j < c; ++j) {
            carry(&sum[j0 + j]); /* each part's limbs carried: their sum cannot overflow */
            for (int k = 0; k < SINTER_REPRO_LIMBS; ++k)
                limbs[SINTER_REPRO_LIMBS * j + (size_t)k] = sum[j0 + j].limb[k];
        }
        if (reduce != NULL && reduce(limbs, SINTER_REPRO_LIMBS * c, SINTER_REPRO_SUM, user) != 0)
            return -1;
        for (size_t j = 0; j < c; ++j) {
            sinter_repro_sum all = {{0}, 0};
            for (int k = 0; k < SINTER_REPRO_LIMBS; ++k)
                all.limb[k] = limbs[SINTER_REPRO_LIMBS * j + (size_t)k];
            out[j0 + j] = e[j0 + j] == NOT_FINITE ? NAN : sinter_repro_value(&all, (int)e[j0 + j]);
        }
    }
    return 0;
}

int sinter_repro_series(const double *terms, size_t n, size_t count, sinter_repro_reduce_fn reduce,
                        void *user, double *out)
{
    for (size_t j0 = 0; j0 < count; j0 += SINTER_REPRO_BATCH) {
        sinter_repro_batch x;
        sinter_repro_begin(&x, count - j0);
        for (size_t j = 0; j < x.count; ++j)
            sinter_repro_scan(&x, j, terms + (j0 + j) * n, NULL, n);
        if (sinter_repro_agree(&x, reduce, user) != 0)
            return -1;
        for (size_t j = 0; j < x.count; ++j)
            sinter_repro_accumulate(&x, j, terms + (j0 + j) * n, NULL, n);
        if (sinter_repro_finish(&x, reduce, user, out + j0) != 0)
            return -1;
    }
    return 0;
}

int sinter_repro_dots(const double *const *a, const double *const *b, size_t n, size_t count,
                      sinter_repro_reduce_fn reduce, void *user, double *out)
{
    if (count > SINTER_REPRO_BATCH)
        return -1;
    sinter_repro_batch x;
    sinter_repro_begin(&x, count);
    for (size_t j = 0; j < count; ++j) /* the products twice: each the same rounded double */
        sinter_repro_scan(&x, j, a[j], b[j], n);
    if (sinter_repro_agree(&x, reduce, user) != 0)
        return -1;
    for (size_t j = 0; j < count; ++j)
        sinter_repro_accumulate(&x, j, a[j], b[j], n);
    return sinter_repro_finish(&x, reduce, user, out);
}

/* sinter_repro_add's inner step for one term r = x 2^-(e + HEADROOM), already scaled by the
 * correctly rounded product (the same limbs as sinter_repro_add gives x). */
static void add_scaled(sinter_repro_sum *s, double r)
{
    const double limb_scale = (double)((int64_t)1 << SINTER_REPRO_LIMB_BITS);
    for (int j = 0; j < SINTER_REPRO_LIMBS; ++j) {
        r *= limb_scale;
        const int64_t whole = (int64_t)r;
        s->limb[j] += whole;
        r -= (double)whole;
    }
    if (++s->terms >= CARRY_EVERY)
        carry(s);
}

/* sinter_repro_value with the limbs' weights pw[j] = 2^(e + HEADROOM - 40 (j + 1)) given, all
 * normal numbers (a product by an exact power of two rounds as ldexp does): the same bits. */
static double value_by(const sinter_repro_sum *s, const double pw[SINTER_REPRO_LIMBS])
{
    sinter_repro_sum c = *s;
    carry(&c);
    double v = 0.0;
    for (int j = SINTER_REPRO_LIMBS - 1; j >= 0; --j)
        v += (double)c.limb[j] * pw[j];
    return v;
}

size_t sinter_repro_rows_bytes(size_t rows, size_t width)
{
    return width * sizeof(int64_t) + rows * width * sizeof(sinter_repro_sum) +
           rows * width * SINTER_REPRO_LIMBS * sizeof(double);
}

int sinter_repro_rows(size_t rows, size_t owned, size_t width, const uint32_t *row,
                      const double *terms, size_t count, sinter_repro_reduce_fn reduce,
                      sinter_repro_reverse_fn reverse, void *user, void *work, double *out)
{
    int64_t *e = work;
    sinter_repro_sum *sum = (sinter_repro_sum *)(e + width);
    double *limbs = (double *)(sum + rows * width);
    for (size_t c = 0; c < width; ++c) /* one exponent per column, over every part */
        e[c] = sinter_repro_exponent(terms + c, count, width, NULL);
    if (reduce != NULL && reduce(e, width, SINTER_REPRO_MAX, user) != 0)
        return -1;
    memset(sum, 0, rows * width * sizeof(sinter_repro_sum));
    enum { MOST = 64 }; /* columns whose scales are taken once (the others term by term) */
    double scale[MOST];
    for (size_t c = 0; c < width && c < MOST; ++c) {
        const int shift = e[c] == INT32_MIN ? 0 : -(int)e[c] - HEADROOM;
        scale[c] = shift >= -1022 && shift <= 1023 ? ldexp(1.0, shift) : 0.0;
    }
    for (size_t k = 0; k < count; ++k) {
        sinter_repro_sum *s = sum + (size_t)row[k] * width;
        const double *t = terms + k * width;
        for (size_t c = 0; c < width; ++c) {
            if (t[c] == 0.0 || !isfinite(t[c]))
                continue;
            if (c >= MOST || scale[c] == 0.0) {
                sinter_repro_add(&s[c], (int)e[c], t + c, 1, 1);
                continue;
            }
            add_scaled(&s[c], t[c] * scale[c]); /* as sinter_repro_add: the same limbs */
        }
    }
    if (reverse != NULL) { /* the ghost rows' limbs into their owners' (integer-valued doubles) */
        for (size_t q = 0; q < rows * width; ++q)
            sinter_repro_to_doubles(&sum[q], limbs + SINTER_REPRO_LIMBS * q);
        if (reverse(limbs, SINTER_REPRO_LIMBS * width, user) != 0)
            return -1;
        for (size_t q = 0; q < owned * width; ++q)
            sinter_repro_from_doubles(&sum[q], limbs + SINTER_REPRO_LIMBS * q);
    }
    double pw[MOST][SINTER_REPRO_LIMBS]; /* the limbs' weights, where all are normal */
    int by[MOST];
    for (size_t c = 0; c < width && c < MOST; ++c) {
        by[c] = e[c] != INT32_MIN;
        for (int j = 0; j < SINTER_REPRO_LIMBS && by[c]; ++j) {
            const int64_t k = e[c] + HEADROOM - SINTER_REPRO_LIMB_BITS * (j + 1);
            by[c] = k >= -1022 && k <= 1023;
            pw[c][j] = by[c] ? ldexp(1.0, (int)k) : 0.0;
        }
    }
    for (size_t r = 0; r < rows; ++r)
        for (size_t c = 0; c < width; ++c) {
            const sinter_repro_sum *q = &sum[r * width + c];
            out[r * width + c] = r >= owned          ? 0.0
                                 : c < MOST && by[c] ? value_by(q, pw[c])
                                                     : sinter_repro_value(q, (int)e[c]);
        }
    return 0;
}
