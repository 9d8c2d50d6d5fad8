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

/* ---- across parts through a host's collectives (the quasi-static stepper, issue 43) ---- */

/* The operations of sinter_repro_reduce_fn. */
enum { SINTER_REPRO_MAX = 0, SINTER_REPRO_SUM = 1 };

/* values[0..count) combined over every part in place (op SINTER_REPRO_MAX or _SUM; identical
 * results on every part). Returns 0 on success. NULL where there is one part. */
typedef int (*sinter_repro_reduce_fn)(int64_t *values, size_t count, int op, void *user);

/* Ghost rows of rows[] (width doubles a row, the owned rows first) added into their owners'
 * rows. Returns 0 on success. NULL where there are no ghosts. */
typedef int (*sinter_repro_reverse_fn)(double *rows, size_t width, void *user);

/* The limbs of s (carried) as doubles, and back: integers below 2^53, so that an exchange that
 * adds doubles (a reverse halo of a few copies) adds them exactly. */
void sinter_repro_to_doubles(const sinter_repro_sum *s, double out[SINTER_REPRO_LIMBS]);
void sinter_repro_from_doubles(sinter_repro_sum *s, const double in[SINTER_REPRO_LIMBS]);

/*
 * A batch of up to SINTER_REPRO_BATCH sums over every part, each of terms a[k] or of products
 * a[k] b[k] (each rounded once, the same bits wherever it is formed): sinter_repro_begin, then
 * each sum's terms through sinter_repro_scan (their exponents), sinter_repro_agree (one MAX
 * through reduce), the same terms through sinter_repro_accumulate, then sinter_repro_finish
 * (one SUM of the limbs through reduce). reduce NULL: one part, the same bits as on any number
 * of parts. A sum with a term that is not finite on any part is NaN on every part. The
 * callbacks' results: 0, or -1 when reduce failed.
 */
#define SINTER_REPRO_BATCH 16

typedef struct sinter_repro_batch {
    size_t count;                  /* sums in the batch */
    int64_t e[SINTER_REPRO_BATCH]; /* exponents (above every finite one: a term not finite) */
    sinter_repro_sum s[SINTER_REPRO_BATCH];
} sinter_repro_batch;

/* `count` sums (count <= SINTER_REPRO_BATCH), all zero. */
void sinter_repro_begin(sinter_repro_batch *x, size_t count);

/* The exponents of sum c's terms: a[k] (b NULL) or a[k] b[k], k < n. */
void sinter_repro_scan(sinter_repro_batch *x, size_t c, const double *a, const double *b, size_t n);

/* The exponents' maximum over every part. */
int sinter_repro_agree(sinter_repro_batch *x, sinter_repro_reduce_fn reduce, void *user);

/* The same terms as scanned, added to sum c at the agreed exponent. */
void sinter_repro_accumulate(sinter_repro_batch *x, size_t c, const double *a, const double *b,
                             size_t n);

/* The sums over every part into out[0 .. count). */
int sinter_repro_finish(sinter_repro_batch *x, sinter_repro_reduce_fn reduce, void *user,
                        double *out);

/* out[j] = sum[j] (at its exponent e[j], agreed over the parts by a MAX) totalled over every
 * part: the limbs (carried in sum) summed through reduce (NULL: one part). Returns 0, or -1
 * when reduce failed. */
int sinter_repro_totals(sinter_repro_sum *sum, const int64_t *e, size_t count,
                        sinter_repro_reduce_fn reduce, void *user, double *out);

/* out[j] = the exact sum over every part of count series of n terms each (terms[j n + i]), in
 * batches. Returns 0, or -1 when reduce failed. */
int sinter_repro_series(const double *terms, size_t n, size_t count, sinter_repro_reduce_fn reduce,
                        void *user, double *out);

/* out[j] = the exact sum over every part of a[j][i] b[j][i], i < n: dot products whose bits do
 * not depend on the split, one batch (count <= SINTER_REPRO_BATCH). Returns 0, or -1 when
 * reduce failed or count is too large. */
int sinter_repro_dots(const double *const *a, const double *const *b, size_t n, size_t count,
                      sinter_repro_reduce_fn reduce, void *user, double *out);

/* Bytes of work for sinter_repro_rows over `rows` rows of `width` values. */
size_t sinter_repro_rows_bytes(size_t rows, size_t width);

/* Per-row exact sums of contributions: contribution k adds terms[k width .. + width) to row
 * row[k] (rows: owned first, then ghosts). One exponent per column, agreed by a MAX through
 * reduce; the ghost rows' limbs go to their owners through reverse (as doubles, exactly). out[r
 * width + c] (r < rows): the owned rows' totals over every part, 0 on the ghost rows; the same
 * bits for any split of the contributions and any order. work: sinter_repro_rows_bytes. Returns
 * 0, or -1 when a callback failed. */
int sinter_repro_rows(size_t rows, size_t owned, size_t width, const uint32_t *row,
                      const double *terms, size_t count, sinter_repro_reduce_fn reduce,
                      sinter_repro_reverse_fn reverse, void *user, void *work, double *out);

#endif
