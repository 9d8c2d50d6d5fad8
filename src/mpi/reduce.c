/*
 * Collective reductions of libsinter_mpi (issue 44) with the signatures of the domain
 * operations' `reduce` and `exscan`: the same bits on every rank, for any number of ranks and
 * any order in which MPI combines the contributions. Integers go through MPI_Allreduce as they
 * are (exact). Doubles never go through a floating-point MPI_SUM, whose result depends on the
 * reduction tree: a sum goes through the integer limbs of src/core/repro_sum.h below an exponent
 * agreed with MPI_MAX, and a minimum or maximum through integer keys that order doubles totally.
 * Values are processed in chunks with buffers on the stack, so no rank can fail to allocate
 * while the others wait.
 */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "core/repro_sum.h"
#include "mpi/domain.h"
#include "mpi/exact_sums.h"

/* The constants are those of libsinter's domain operations (include/sinter_domain.h, issue 43),
 * so that sinter_mpi_reduce can be installed there as it is: checked wherever that header is. */
#if defined(__has_include)
#if __has_include("sinter_domain.h")
#include "sinter_domain.h"
_Static_assert(SINTER_REDUCE_SUM == SINTER_MPI_SUM && SINTER_REDUCE_MIN == SINTER_MPI_MIN &&
                   SINTER_REDUCE_MAX == SINTER_MPI_MAX && SINTER_REDUCE_F64 == SINTER_MPI_F64 &&
                   SINTER_REDUCE_I64 == SINTER_MPI_I64 && SINTER_REDUCE_U64 == SINTER_MPI_U64,
               "sinter_mpi_decomp.h's reduce constants differ from sinter_domain.h's");
#endif
#endif

#define CHUNK 64                    /* doubles per round of a floating-point reduction */
#define INT_CHUNK ((size_t)1 << 28) /* integers per MPI_Allreduce (its count is an int) */

/* One MPI_Allreduce in place, counted and timed. */
static int allreduce(sinter_mpi_domain *d, void *buf, size_t count, MPI_Datatype type, size_t size,
                     MPI_Op op)
{
    const double t0 = MPI_Wtime();
    const int rc = MPI_Allreduce(MPI_IN_PLACE, buf, (int)count, type, op, d->comm);
    d->stats.seconds_comm += MPI_Wtime() - t0;
    d->stats.reductions += 1;
    d->stats.reduce_bytes += count * size;
    return rc == MPI_SUCCESS ? SINTER_OK : SINTER_ERR_IO;
}

/* A signed integer with the order of doubles (-0 below +0; NaNs beyond the infinities):
 * negative doubles' magnitude bits reversed. Its own inverse. */
static int64_t order_key(int64_t bits)
{
    return bits < 0 ? bits ^ INT64_MAX : bits;
}

static int64_t key_of(double x)
{
    int64_t bits;
    memcpy(&bits, &x, sizeof bits);
    return order_key(bits);
}

static double double_of(int64_t key)
{
    const int64_t bits = order_key(key);
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/* MIN or MAX of doubles: one MPI_MAX over the keys (complemented for MIN, ~ reverses the
 * order without overflow) and the NaN flags. */
static int minmax_f64(sinter_mpi_domain *d, double *v, size_t n, int op)
{
    int64_t buf[2 * CHUNK];
    for (size_t k = 0; k < n; ++k) {
        const int64_t key = key_of(v[k]);
        buf[k] = op == SINTER_MPI_MIN ? ~key : key;
        buf[n + k] = isnan(v[k]) ? 1 : 0;
    }
    const int st = allreduce(d, buf, 2 * n, MPI_INT64_T, sizeof(int64_t), MPI_MAX);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < n; ++k)
        v[k] = buf[n + k] ? (double)NAN : double_of(op == SINTER_MPI_MIN ? ~buf[k] : buf[k]);
    return SINTER_OK;
}

/* The flags of non-finite values: a NaN, +inf, -inf. */
enum { FLAG_NAN = 1, FLAG_PINF = 2, FLAG_NINF = 4 };

static int64_t flags_of(double x)
{
    if (isnan(x))
        return FLAG_NAN;
    if (isinf(x))
        return x > 0 ? FLAG_PINF : FLAG_NINF;
    return 0;
}

static double nonfinite_result(int64_t nan, int64_t pinf, int64_t ninf)
{
    if (nan || (pinf && ninf))
        return (double)NAN;
    return pinf ? (double)INFINITY : -(double)INFINITY;
}

/* SUM of doubles: MPI_MAX of [exponents, NaN, +inf, -inf flags], then MPI_SUM of the limbs. */
static int sum_f64(sinter_mpi_domain *d, double *v, size_t n)
{
    int64_t agree[4 * CHUNK];
    int64_t limbs[SINTER_REPRO_LIMBS * CHUNK];
    for (size_t k = 0; k < n; ++k) {
        agree[k] = sinter_repro_exponent(&v[k], 1, 1, NULL);
        const int64_t f = flags_of(v[k]);
        agree[n + k] = (f & FLAG_NAN) != 0;
        agree[2 * n + k] = (f & FLAG_PINF) != 0;
        agree[3 * n + k] = (f & FLAG_NINF) != 0;
    }
    int st = allreduce(d, agree, 4 * n, MPI_INT64_T, sizeof(int64_t), MPI_MAX);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < n; ++k) {
        sinter_repro_sum s = {{0}, 0};
        sinter_repro_add(&s, (int)agree[k], &v[k], 1, 1);
        memcpy(limbs + SINTER_REPRO_LIMBS * k, s.limb, sizeof s.limb);
    }
    st = allreduce(d, limbs, SINTER_REPRO_LIMBS * n, MPI_INT64_T, sizeof(int64_t), MPI_SUM);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < n; ++k) {
        if (agree[n + k] || agree[2 * n + k] || agree[3 * n + k]) {
            v[k] = nonfinite_result(agree[n + k], agree[2 * n + k], agree[3 * n + k]);
            continue;
        }
        sinter_repro_sum s = {{0}, 0};
        memcpy(s.limb, limbs + SINTER_REPRO_LIMBS * k, sizeof s.limb);
        v[k] = sinter_repro_value(&s, (int)agree[k]);
    }
    return SINTER_OK;
}

int sinter_mpi_reduce(void *values, size_t count, int type, int op, void *user)
{
    sinter_mpi_domain *d = user;
    if (d == NULL || (values == NULL && count > 0))
        return SINTER_ERR_NULL;
    if ((type != SINTER_MPI_F64 && type != SINTER_MPI_I64 && type != SINTER_MPI_U64) ||
        (op != SINTER_MPI_SUM && op != SINTER_MPI_MIN && op != SINTER_MPI_MAX))
        return SINTER_ERR_INVALID;
    if (type != SINTER_MPI_F64) {
        const MPI_Datatype t = type == SINTER_MPI_I64 ? MPI_INT64_T : MPI_UINT64_T;
        const MPI_Op o =
            op == SINTER_MPI_SUM ? MPI_SUM : (op == SINTER_MPI_MIN ? MPI_MIN : MPI_MAX);
        for (size_t k = 0; k < count; k += INT_CHUNK) {
            const size_t n = count - k < INT_CHUNK ? count - k : INT_CHUNK;
            const int st = allreduce(d, (uint64_t *)values + k, n, t, sizeof(uint64_t), o);
            if (st != SINTER_OK)
                return st;
        }
        return SINTER_OK;
    }
    double *v = values;
    for (size_t k = 0; k < count; k += CHUNK) {
        const size_t n = count - k < CHUNK ? count - k : CHUNK;
        const int st = op == SINTER_MPI_SUM ? sum_f64(d, v + k, n) : minmax_f64(d, v + k, n, op);
        if (st != SINTER_OK)
            return st;
    }
    return SINTER_OK;
}

int sinter_mpi_exscan(uint64_t value, uint64_t *before, uint64_t *total, void *user)
{
    sinter_mpi_domain *d = user;
    if (d == NULL || before == NULL || total == NULL)
        return SINTER_ERR_NULL;
    const double t0 = MPI_Wtime();
    uint64_t scan = 0;
    int rc = MPI_Exscan(&value, &scan, 1, MPI_UINT64_T, MPI_SUM, d->comm);
    d->stats.reductions += 1;
    d->stats.reduce_bytes += sizeof value;
    d->stats.seconds_comm += MPI_Wtime() - t0;
    if (rc != MPI_SUCCESS)
        return SINTER_ERR_IO;
    *before = d->rank == 0 ? 0 : scan; /* MPI leaves rank 0's result undefined */
    *total = value;
    return allreduce(d, total, 1, MPI_UINT64_T, sizeof(uint64_t), MPI_SUM);
}

sinter_status sinter_mpi_sum(sinter_mpi_domain *d, const double *terms, size_t n, double *sum)
{
    if (d == NULL || sum == NULL || (terms == NULL && n > 0))
        return SINTER_ERR_NULL;
    int64_t agree[4] = {sinter_repro_exponent(terms, n, 1, NULL), 0, 0, 0};
    for (size_t k = 0; k < n; ++k) {
        const int64_t f = flags_of(terms[k]);
        agree[1] |= (f & FLAG_NAN) != 0;
        agree[2] |= (f & FLAG_PINF) != 0;
        agree[3] |= (f & FLAG_NINF) != 0;
    }
    sinter_status st = (sinter_status)allreduce(d, agree, 4, MPI_INT64_T, sizeof(int64_t), MPI_MAX);
    if (st != SINTER_OK)
        return st;
    sinter_repro_sum s = {{0}, 0};
    sinter_repro_add(&s, (int)agree[0], terms, n, 1);
    int64_t scratch[SINTER_REPRO_LIMBS];
    st = sinter_mpi_bins_reduce(&s, 1, scratch, sinter_mpi_reduce, d);
    if (st != SINTER_OK)
        return st;
    *sum = agree[1] || agree[2] || agree[3] ? nonfinite_result(agree[1], agree[2], agree[3])
                                            : sinter_repro_value(&s, (int)agree[0]);
    return SINTER_OK;
}
