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
