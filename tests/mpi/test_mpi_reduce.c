/* libsinter_mpi's reductions under mpiexec (issue 44), at any number of ranks: integers exact;
 * sums of doubles the same bits on every rank and equal to the serial limb sum of the same terms
 * (so independent of the rank count and of MPI's reduction tree); minimum and maximum with -0
 * below +0 and NaN propagated; the exclusive scan; argument errors without communication. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

#include "core/repro_sum.h"
#include "sinter_mpi.h"

static int rank, size;

static double uniform(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) * 0x1p-53;
}

/* A term with a wide range of magnitudes and both signs, a function of its index only. */
static double term(uint64_t i)
{
    uint64_t s = 0x9E3779B97F4A7C15ull ^ (i * 0xBF58476D1CE4E5B9ull);
    for (int k = 0; k < 3; ++k)
        uniform(&s);
    const double mag = ldexp(1.0 + uniform(&s), (int)(uniform(&s) * 60.0) - 30);
    return uniform(&s) < 0.5 ? -mag : mag;
}

/* The serial limb sum of terms [0, n) by index (the reference every rank count must match). */
static double serial_sum(const double *x, size_t n)
{
    const int e = sinter_repro_exponent(x, n, 1, NULL);
    sinter_repro_sum s;
    memset(&s, 0, sizeof s);
    sinter_repro_add(&s, e, x, n, 1);
    return sinter_repro_value(&s, e);
}

static void integers(sinter_mpi_domain *d)
{
    int64_t v[3] = {rank + 1, -(int64_t)(rank + 1) * 1000000000000000ll, rank};
    CHECK(sinter_mpi_reduce(v, 3, SINTER_MPI_I64, SINTER_MPI_SUM, d) == 0);
    CHECK(v[0] == (int64_t)size * (size + 1) / 2);
    CHECK(v[1] == -(int64_t)size * (size + 1) / 2 * 1000000000000000ll);
    int64_t m[2] = {rank - 7, rank - 7};
    CHECK(sinter_mpi_reduce(m, 1, SINTER_MPI_I64, SINTER_MPI_MIN, d) == 0);
    CHECK(sinter_mpi_reduce(m + 1, 1, SINTER_MPI_I64, SINTER_MPI_MAX, d) == 0);
    CHECK(m[0] == -7 && m[1] == size - 8);
    uint64_t u = UINT64_MAX; /* wraps: size * (2^64 - 1) = -size mod 2^64 */
    CHECK(sinter_mpi_reduce(&u, 1, SINTER_MPI_U64, SINTER_MPI_SUM, d) == 0);
    CHECK(u == (uint64_t)0 - (uint64_t)size);
}

/* One value per rank and element: the same bits everywhere, equal to the serial limb sum of
 * the ranks' values; 2^60 + 1 - 2^60 + 1 = 2 exactly (a floating-point sum gives 0, 1 or 2
 * depending on the order). */
static void float_sums(sinter_mpi_domain *d)
{
    enum { N = 100 };
    double v[N], all[N][4];
    for (int k = 0; k < N; ++k) {
        for (int r = 0; r < size && r < 4; ++r)
            all[k][r] = term((uint64_t)k * 4 + (uint64_t)r);
        v[k] = all[k][rank % 4];
    }
    const double cancel[4] = {0x1p60, 1.0, -0x1p60, 1.0};
    v[0] = cancel[rank % 4];
    for (int r = 0; r < 4; ++r)
        all[0][r] = cancel[r];
    CHECK(sinter_mpi_reduce(v, N, SINTER_MPI_F64, SINTER_MPI_SUM, d) == 0);
    CHECK(same_on_every_rank(v, sizeof v));
    if (size <= 4) {
        for (int k = 0; k < N; ++k)
            CHECK(memcmp(&v[k], &(double){serial_sum(all[k], (size_t)size)}, sizeof v[k]) == 0);
        const double exact[5] = {0.0, 0x1p60, 0x1p60 /* 2^60 + 1 rounded */, 1.0, 2.0};
        CHECK(v[0] == exact[size]);
    }
    /* non-finite values: NaN anywhere, or +inf with -inf, give NaN */
    double inf[3] = {rank == 0 ? INFINITY : 1.0, rank == size - 1 ? -INFINITY : 1.0,
                     rank == 0 ? INFINITY : (rank == size - 1 ? -INFINITY : 1.0)};
    CHECK(sinter_mpi_reduce(inf, 3, SINTER_MPI_F64, SINTER_MPI_SUM, d) == 0);
    CHECK(inf[0] == INFINITY && inf[1] == -INFINITY);
    CHECK(size > 1 ? isnan(inf[2]) : inf[2] == INFINITY); /* +inf - inf: NaN */
    double nan_sum = rank == size / 2 ? NAN : 1.0;
    CHECK(sinter_mpi_reduce(&nan_sum, 1, SINTER_MPI_F64, SINTER_MPI_SUM, d) == 0);
    CHECK(isnan(nan_sum));
}

/* Every rank's share of 2^16 terms (round-robin, then in reversed blocks): the sum is the
 * serial limb sum of all of them, the same bits at every rank count. */
static void global_sums(sinter_mpi_domain *d)
{
    const size_t n = (size_t)1 << 16;
    double *x = malloc(n * sizeof *x), *mine = malloc(n * sizeof *mine);
    CHECK(x != NULL && mine != NULL);
    if (x == NULL || mine == NULL)
        return;
    for (size_t i = 0; i < n; ++i)
        x[i] = term(i + 1000);
    const double reference = serial_sum(x, n);
    size_t m = 0;
    for (size_t i = (size_t)rank; i < n; i += (size_t)size)
        mine[m++] = x[i];
    double sum = 0.0;
    CHECK(sinter_mpi_sum(d, mine, m, &sum) == SINTER_OK);
    CHECK(memcmp(&sum, &reference, sizeof sum) == 0);
    const size_t block = n / (size_t)size, first = (size_t)(size - 1 - rank) * block;
    const size_t count = rank == 0 ? n - first : block; /* rank 0 takes the last block's rest */
    CHECK(sinter_mpi_sum(d, x + first, count, &sum) == SINTER_OK);
    CHECK(memcmp(&sum, &reference, sizeof sum) == 0);
    /* MPI's own floating-point sum of the ranks' partial sums, for comparison only */
    double partial = 0.0, mpi_sum = 0.0;
    for (size_t i = 0; i < m; ++i)
        partial += mine[i];
    MPI_Allreduce(&partial, &mpi_sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    uint64_t bits_ref, bits_mpi;
    memcpy(&bits_ref, &reference, sizeof bits_ref);
    memcpy(&bits_mpi, &mpi_sum, sizeof bits_mpi);
    if (rank == 0)
        printf("sum of 2^16 terms: limbs %016llx at every rank count; MPI_SUM of partial sums "
               "%016llx (%s)\n",
               (unsigned long long)bits_ref, (unsigned long long)bits_mpi,
               bits_ref == bits_mpi ? "the same here" : "differs");
    free(x);
    free(mine);
}

static void minima_and_maxima(sinter_mpi_domain *d)
{
    /* zeros of both signs: the minimum is -0 once a rank holds one, the maximum +0 */
    double z[2] = {rank % 2 ? -0.0 : 0.0, rank % 2 ? -0.0 : 0.0};
    CHECK(sinter_mpi_reduce(z, 1, SINTER_MPI_F64, SINTER_MPI_MIN, d) == 0);
    CHECK(sinter_mpi_reduce(z + 1, 1, SINTER_MPI_F64, SINTER_MPI_MAX, d) == 0);
    CHECK(z[0] == 0.0 && (signbit(z[0]) != 0) == (size > 1));
    CHECK(z[1] == 0.0 && !signbit(z[1]));
    double v[4] = {-1.0 - rank, 1.0 + rank, rank == size - 1 ? NAN : rank, -INFINITY};
    double w[4];
    memcpy(w, v, sizeof v);
    CHECK(sinter_mpi_reduce(v, 4, SINTER_MPI_F64, SINTER_MPI_MIN, d) == 0);
    CHECK(sinter_mpi_reduce(w, 4, SINTER_MPI_F64, SINTER_MPI_MAX, d) == 0);
    CHECK(v[0] == -(double)size && v[1] == 1.0 && isnan(v[2]) && v[3] == -INFINITY);
    CHECK(w[0] == -1.0 && w[1] == (double)size && isnan(w[2]) && w[3] == -INFINITY);
    /* more values than one chunk of the implementation (64) */
    double many[200];
    for (int k = 0; k < 200; ++k)
        many[k] = (double)((k * 7 + rank * 13) % 101);
    CHECK(sinter_mpi_reduce(many, 200, SINTER_MPI_F64, SINTER_MPI_MAX, d) == 0);
    for (int k = 0; k < 200; ++k) {
        double best = 0.0;
        for (int r = 0; r < size; ++r)
            best = fmax(best, (double)((k * 7 + r * 13) % 101));
        CHECK(many[k] == best);
    }
}

static void scan(sinter_mpi_domain *d)
{
    uint64_t before = 99, total = 99;
    CHECK(sinter_mpi_exscan((uint64_t)rank + 1, &before, &total, d) == 0);
    CHECK(before == (uint64_t)rank * (rank + 1) / 2);
    CHECK(total == (uint64_t)size * (size + 1) / 2);
}

static void refusals(sinter_mpi_domain *d)
{
    double x = 1.0;
    CHECK(sinter_mpi_reduce(&x, 1, 7, SINTER_MPI_SUM, d) == SINTER_ERR_INVALID);
    CHECK(sinter_mpi_reduce(&x, 1, SINTER_MPI_F64, 9, d) == SINTER_ERR_INVALID);
    CHECK(sinter_mpi_reduce(NULL, 1, SINTER_MPI_F64, SINTER_MPI_SUM, d) == SINTER_ERR_NULL);
    CHECK(sinter_mpi_reduce(&x, 1, SINTER_MPI_F64, SINTER_MPI_SUM, NULL) == SINTER_ERR_NULL);
    CHECK(sinter_mpi_reduce(NULL, 0, SINTER_MPI_F64, SINTER_MPI_SUM, d) == 0);
    CHECK(sinter_mpi_exscan(1, NULL, NULL, d) == SINTER_ERR_NULL);
    sinter_mpi_stats stats;
    stats.struct_size = sizeof stats;
    CHECK(sinter_mpi_get_stats(d, &stats) == SINTER_OK);
    CHECK(stats.reductions > 10 && stats.reduce_bytes > 0 && stats.seconds_comm >= 0.0);
    stats.struct_size = 3;
    CHECK(sinter_mpi_get_stats(d, &stats) == SINTER_ERR_STRUCT_SIZE);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    sinter_mpi_options o;
    CHECK(sinter_mpi_options_init(&o, sizeof o) == SINTER_OK);
    sinter_mpi_domain *d = NULL;
    CHECK(sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK);
    if (d != NULL) {
        integers(d);
        float_sums(d);
        global_sums(d);
        minima_and_maxima(d);
        scan(d);
        refusals(d);
    }
    sinter_mpi_domain_destroy(d);
    const int rc = mpi_check_finish("test_mpi_reduce");
    MPI_Finalize();
    return rc;
}
