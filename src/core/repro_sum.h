/*
 * Sums of doubles whose bits do not depend on the order of the terms or on how they are split
 * into parts (issue 43: the reductions of a decomposed run, "reproducible mode").
 *
 * The method (He and Ding 2001, "Using accurate arithmetics to improve numerical
 * reproducibility and stability in parallel applications", J. Supercomputing 18:259-277; as
 * used by CESM's shr_reprosum): every term is written in fixed point relative to 2^e, where e
 * bounds the exponent of every term of the whole sum, as SINTER_REPRO_LIMBS integer limbs of
 * SINTER_REPRO_LIMB_BITS bits each (with 23 bits of headroom above e, so that sums of up to 2^45
 * terms cannot overflow). Integer addition is associative, so the limbs' sums are the
 * same for any order and any split; the parts' limbs are added (an integer reduction across
 * subdomains) and converted to one double at the end. Bits of a term below 2^(e - 97) are
 * dropped (truncated toward zero, the same way in every order): the result is reproducible, and
 * accurate to n 2^(e - 97) absolutely, 44 bits below the largest term's last bit.
 *
 * Two passes: sinter_repro_exponent over every part (then a MAX across parts), then
 * sinter_repro_add with that exponent (then a SUM of the limbs across parts), then
 * sinter_repro_value.
 */
#ifndef SINTER_CORE_REPRO_SUM_H
#define SINTER_CORE_REPRO_SUM_H

#include <stddef.h>
#include <stdint.h>

#define SINTER_REPRO_LIMBS 3
#define SINTER_REPRO_LIMB_BITS 40

typedef struct sinter_repro_sum {
    int64_t limb[SINTER_REPRO_LIMBS]; /* limb k weighs 2^(e + 23 - 40 (k + 1)) */
    uint64_t terms;                   /* terms added since the last carry (overflow guard) */
} sinter_repro_sum;

/* The exponent e with |x[k]| < 2^e for every term (INT32_MIN when all are zero); *finite (may
 * be NULL) = 0 when a term is not finite (such terms are skipped). Combine parts with MAX. */
int sinter_repro_exponent(const double *x, size_t n, size_t stride, int *finite);

/* Add n terms x[0], x[stride], ... to s at the agreed exponent e. */
void sinter_repro_add(sinter_repro_sum *s, int e, const double *x, size_t n, size_t stride);

/* Add part b's limbs into a (the reduction across parts; also an integer SUM of the limbs). */
void sinter_repro_merge(sinter_repro_sum *a, const sinter_repro_sum *b);

/* The sum as a double (the same bits for the same limbs). */
double sinter_repro_value(const sinter_repro_sum *s, int e);

#endif
