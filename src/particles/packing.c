/*
 * Packing helpers: random sequential addition (seed 000 sec. 7.1, remark 2) and
 * simple-cubic lattices. sinter_pack_pour lives elsewhere.
 *
 * Reproducibility: the random stream is integer arithmetic, and every floating
 * point operation on it is +, -, *, / or sqrt (correctly rounded in IEEE 754),
 * including the logarithm of the normal deviates (det_log below, no libm call).
 * Contraction into fused multiply-adds is turned off below (it would round
 * differently on machines with FMA), so a seed gives the same packing, bit for
 * bit, on every IEEE 754 machine.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "particles.h"
#include "particles/mixture.h"
#include "particles/packing.h"

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off") /* GCC ignores the STDC pragma */
#endif

static const double PI = 3.14159265358979323846;
static const char *const AXIS[3] = {"x", "y", "z"};
#define NO_ENTRY SIZE_MAX

/* ---- random numbers -------------------------------------------------------- */

/*
 * xoshiro256** 1.0 (Blackman and Vigna, 2018), its 256-bit state filled by
 * splitmix64 (Steele, Lea and Flood, 2014) from the 64-bit seed, as its authors
 * recommend. Period 2^256 - 1; no global state.
 */
typedef struct rng {
    uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

static void rng_seed(rng *g, uint64_t seed)
{
    for (int k = 0; k < 4; ++k)
        g->s[k] = splitmix64(&seed);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t rng_next(rng *g)
{
    uint64_t *s = g->s;
    const uint64_t result = rotl(s[1] * 5, 7) * 9;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

/* Uniform in [0, 1): the top 53 bits as a multiple of 2^-53 (exact). */
static double rng_uniform(rng *g)
{
    return (double)(rng_next(g) >> 11) * 0x1.0p-53;
}

/*
 * Natural logarithm of s > 0 from + - * / only: s = m 2^e with m in
 * [sqrt(1/2), sqrt(2)), ln m = 2 atanh f with f = (m - 1)/(m + 1), |f| < 0.1716,
 * summed to f^25 (next term < 1e-19 relative). Within a few ulp of log(s).
 */
static double det_log(double s)
{
    int e = 0;
    double m = frexp(s, &e);
    if (m < 0.70710678118654752440) {
        m *= 2.0;
        e -= 1;
    }
    const double f = (m - 1.0) / (m + 1.0), f2 = f * f;
    double series = 0.0;
    for (int k = 12; k >= 0; --k)
        series = series * f2 + 1.0 / (double)(2 * k + 1);
    return (double)e * 0.69314718055994530942 + 2.0 * f * series;
}

/*
 * exp(x) from + - * / and exact scalings only (as det_log): x = k ln 2 + f with |f| <= ln 2 / 2
 * (ln 2 in two parts, Cody and Waite), exp f summed as its Taylor series to f^22 (next term
 * < 1e-22), times 2^k. Within a few ulp of exp(x); |x| < 700.
 */
static double det_exp(double x)
{
    const double k = floor(x * 1.44269504088896340736 + 0.5);
    const double f = (x - k * 0.693145751953125) - k * 1.42860682030941723212e-6;
    double sum = 1.0;
    for (int n = 22; n >= 1; --n)
        sum = 1.0 + sum * f / (double)n;
    return ldexp(sum, (int)k);
}

/* Standard normal deviate, Marsaglia polar method (the second deviate is dropped). */
static double rng_normal(rng *g)
{
    double u, v, s;
    do {
        u = 2.0 * rng_uniform(g) - 1.0;
        v = 2.0 * rng_uniform(g) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    return u * sqrt(-2.0 * det_log(s) / s);
}

/* ---- options ----------------------------------------------------------------- */

/* The layout before issue 38 appended the log-normal, table and mixture fields, and the one
 * before the sizes per material. */
#define PACKING_OPTIONS_OLD_SIZE offsetof(sinter_packing_options, radius_median)
#define PACKING_OPTIONS_MIXTURE_SIZE offsetof(sinter_packing_options, mixture_sizes)

static int known_size(size_t struct_size)
{
    return struct_size == sizeof(sinter_packing_options) ||
           struct_size == PACKING_OPTIONS_OLD_SIZE || struct_size == PACKING_OPTIONS_MIXTURE_SIZE;
}

static void packing_defaults(sinter_packing_options *options)
{
    memset(options, 0, sizeof(*options));
    options->struct_size = sizeof(*options);
    for (int d = 0; d < 3; ++d) {
        options->box_min[d] = 0.0;
        options->box_max[d] = 1.0;
    }
    options->distribution = SINTER_RADII_MONODISPERSE;
    options->radius_mean = 0.05;
    options->radius_spread = 0.0;
    options->radius_min = 0.0;
    options->radius_max = 0.0;
    options->gap = 0.0;
    options->seed = 1;
    options->max_attempts = 100000;
    options->material = 0;
    options->temperature = 293.15;
    options->radius_median = 0.05;
    options->radius_gsd = 1.0;
    options->table_basis = SINTER_SIZE_BY_VOLUME;
}

sinter_status sinter_packing_options_init(sinter_packing_options *options, size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (!known_size(struct_size))
        return SINTER_ERR_STRUCT_SIZE;
    sinter_packing_options full;
    packing_defaults(&full);
    full.struct_size = struct_size;
    memcpy(options, &full, struct_size);
    return SINTER_OK;
}

/*
 * The radius range a validated distribution draws from ([lo, hi], both > 0), and what the
 * log-normal and table samplers need: ln gsd; the table's cumulative number weights
 * (cum[0] the point mass at the first diameter, cum[i] adds the interval (d[i-1], d[i])).
 */
typedef struct radius_range {
    double lo, hi;
    double log_gsd;
    double *cum; /* table_points entries, owned */
} radius_range;

static void range_free(sinter_ctx *ctx, radius_range *range)
{
    sinter_free(ctx, range->cum);
    range->cum = NULL;
}

static sinter_status invalid_option(sinter_ctx *ctx, const char *func, const char *name,
                                    double value, const char *rule)
{
    return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: option %s = %g %s", func, name, value, rule);
}

/* The lock, temperature and box checks shared by both packers. */
static sinter_status check_set_and_box(const sinter_particles *ps, const char *func,
                                       const double box_min[3], const double box_max[3],
                                       double temperature)
{
    sinter_ctx *ctx = ps->ctx;
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are still out; release "
                           "them before adding particles",
                           func, ps->views_out);
    if (!isfinite(temperature) || temperature <= 0.0)
        return invalid_option(ctx, func, "temperature", temperature,
                              "K must be positive and finite");
    for (int d = 0; d < 3; ++d) {
        if (!isfinite(box_max[d] - box_min[d]) || !(box_max[d] > box_min[d]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: box_max[%d] = %g must be finite and greater than "
                               "box_min[%d] = %g (%s axis)",
                               func, d, box_max[d], d, box_min[d], AXIS[d]);
    }
    return SINTER_OK;
}

static sinter_status check_material(const sinter_particles *ps, const char *func, int32_t material)
{
    if (material < 0 || material >= SINTER_MAX_MATERIALS || !ps->material_used[material])
        return sinter_fail(ps->ctx, SINTER_ERR_NOT_FOUND,
                           "%s: material %d is not registered in the particle set; call "
                           "sinter_particles_set_material first",
                           func, (int)material);
    return SINTER_OK;
}

/* Checks shared by both packers: lock, material, temperature, box. */
static sinter_status check_common(const sinter_particles *ps, const char *func,
                                  const double box_min[3], const double box_max[3],
                                  int32_t material, double temperature)
{
    sinter_status st = check_material(ps, func, material);
    if (st != SINTER_OK)
        return st;
    return check_set_and_box(ps, func, box_min, box_max, temperature);
}

/* SINTER_RADII_LOGNORMAL: median, gsd and the truncation (default 3 geometric deviations). */
static sinter_status check_lognormal(sinter_ctx *ctx, const char *func,
                                     const sinter_packing_options *o, radius_range *range)
{
    const double median = o->radius_median, gsd = o->radius_gsd;
    if (!isfinite(median) || !(median > 0.0))
        return invalid_option(ctx, func, "radius_median", median, "m must be positive and finite");
    if (!isfinite(gsd) || !(gsd >= 1.0) || gsd > 1e3)
        return invalid_option(ctx, func, "radius_gsd", gsd, "must be in [1, 1000]");
    range->log_gsd = det_log(gsd);
    const double g3 = det_exp(3.0 * range->log_gsd);
    range->lo = o->radius_min > 0.0 ? o->radius_min : median / g3;
    range->hi = o->radius_max > 0.0 ? o->radius_max : median * g3;
    if (!(range->lo <= median) || !(median <= range->hi))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: options radius_min = %g m and radius_max = %g m must bracket "
                           "radius_median = %g m",
                           func, range->lo, range->hi, median);
    if (range->log_gsd > 0.0) {
        const double a = log(range->lo / median) / (range->log_gsd * sqrt(2.0));
        const double b = log(range->hi / median) / (range->log_gsd * sqrt(2.0));
        if (0.5 * (erf(b) - erf(a)) < 1e-4)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: options radius_min = %g m and radius_max = %g m keep less than "
                               "1e-4 of the log-normal distribution; widen them",
                               func, range->lo, range->hi);
    }
    return SINTER_OK;
}

/* SINTER_RADII_TABLE: the rows, and their number weights (a volume table converted). */
static sinter_status check_table(sinter_ctx *ctx, const char *func, const sinter_packing_options *o,
                                 radius_range *range)
{
    const size_t n = o->table_points;
    const double *d = o->table_diameter, *q = o->table_cumulative;
    if (n == 0 || d == NULL || q == NULL)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the table distribution needs table_points >= 1 and the arrays "
                           "table_diameter and table_cumulative",
                           func);
    if (o->table_basis != SINTER_SIZE_BY_NUMBER && o->table_basis != SINTER_SIZE_BY_VOLUME)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: option table_basis = %d is not a sinter_size_basis", func,
                           o->table_basis);
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(d[i]) || !(d[i] > 0.0) || (i > 0 && !(d[i] > d[i - 1])))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: table_diameter[%zu] = %g m must be positive, finite and "
                               "larger than the row before",
                               func, i, d[i]);
        if (!isfinite(q[i]) || !(q[i] >= 0.0) || (i > 0 && !(q[i] >= q[i - 1])))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: table_cumulative[%zu] = %g must be finite, >= 0 and not "
                               "below the row before",
                               func, i, q[i]);
    }
    if (!(fabs(q[n - 1] - 1.0) <= 0.01))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: table_cumulative[%zu] = %g, the last row, must be 1 within 1 %%",
                           func, n - 1, q[n - 1]);
    range->cum = sinter_realloc_array(ctx, NULL, n, sizeof(double));
    if (range->cum == NULL)
        return sinter_last_status(ctx);
    /* By volume: q0(d) ~ q3(d) / d^3. On (a, b) q3 = dQ / (b - a), so the interval's number
     * weight is dQ / (b - a) * (a^-2 - b^-2) / 2 = dQ (a + b) / (2 a^2 b^2); the first row's
     * point mass weighs Q0 / d0^3 (the same factor pi / 6 dropped from both). */
    const int by_volume = o->table_basis == SINTER_SIZE_BY_VOLUME;
    range->cum[0] = by_volume ? q[0] / (d[0] * d[0] * d[0]) : q[0];
    for (size_t i = 1; i < n; ++i) {
        const double dq = q[i] - q[i - 1], a = d[i - 1], b = d[i];
        range->cum[i] = range->cum[i - 1] + (by_volume ? dq * (a + b) / (2.0 * a * a * b * b) : dq);
    }
    /* the smallest and largest diameters that carry weight */
    size_t first = 0, last = n - 1;
    while (first + 1 < n && range->cum[first] == 0.0)
        ++first;
    while (last > 0 && range->cum[last] == range->cum[last - 1])
        --last;
    range->lo = 0.5 * (first == 0 ? d[0] : d[first - 1]);
    range->hi = 0.5 * d[last];
    return SINTER_OK;
}

static sinter_status check_mixture(const sinter_particles *ps, const char *func,
                                   const sinter_packing_options *o)
{
    sinter_ctx *ctx = ps->ctx;
    if (o->mixture_materials == NULL || o->mixture_mass_fractions == NULL)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: mixture_count = %zu needs mixture_materials and "
                           "mixture_mass_fractions",
                           func, o->mixture_count);
    if (o->mixture_count > SINTER_MAX_MATERIALS)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: mixture_count = %zu exceeds the %d materials a set can hold", func,
                           o->mixture_count, SINTER_MAX_MATERIALS);
    double sum = 0.0;
    for (size_t k = 0; k < o->mixture_count; ++k) {
        sinter_status st = check_material(ps, func, o->mixture_materials[k]);
        if (st != SINTER_OK)
            return st;
        const double f = o->mixture_mass_fractions[k];
        if (!isfinite(f) || !(f > 0.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: mixture_mass_fractions[%zu] = %g must be positive and finite",
                               func, k, f);
        sum += f;
    }
    if (!(fabs(sum - 1.0) <= 1e-6))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the mixture's mass fractions sum to %.9g, not 1", func, sum);
    return SINTER_OK;
}

/* Validate the radius options and set up the sampler (range_free it, also on error). */
static sinter_status check_radii(sinter_ctx *ctx, const char *func, const sinter_packing_options *o,
                                 radius_range *range)
{
    const double mean = o->radius_mean, spread = o->radius_spread;
    if (!isfinite(mean) || !(mean > 0.0))
        return invalid_option(ctx, func, "radius_mean", mean, "m must be positive and finite");
    const struct {
        const char *name;
        double value;
    } lengths[] = {{"radius_spread", spread},
                   {"radius_min", o->radius_min},
                   {"radius_max", o->radius_max},
                   {"gap", o->gap}};
    for (size_t k = 0; k < sizeof(lengths) / sizeof(lengths[0]); ++k)
        if (!isfinite(lengths[k].value) || lengths[k].value < 0.0)
            return invalid_option(ctx, func, lengths[k].name, lengths[k].value,
                                  "m must be finite and >= 0");
    if (o->max_attempts == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: option max_attempts = 0 must be >= 1",
                           func);
    switch (o->distribution) {
    case SINTER_RADII_MONODISPERSE:
        range->lo = range->hi = mean;
        break;
    case SINTER_RADII_UNIFORM:
        if (!(spread < mean))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: option radius_spread = %g m must be less than radius_mean = "
                               "%g m for the uniform distribution (radii must stay positive)",
                               func, spread, mean);
        range->lo = mean - spread;
        range->hi = mean + spread;
        break;
    case SINTER_RADII_NORMAL: {
        /* 0 selects the defaults: mean - 3 spread (floored at mean/10), mean + 3 spread */
        range->lo = o->radius_min > 0.0 ? o->radius_min : fmax(mean - 3.0 * spread, 0.1 * mean);
        range->hi = o->radius_max > 0.0 ? o->radius_max : mean + 3.0 * spread;
        if (!(range->lo <= mean))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: option radius_min = %g m must not exceed radius_mean = %g m",
                               func, range->lo, mean);
        if (!(mean <= range->hi))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: option radius_max = %g m must not be below radius_mean = %g m",
                               func, range->hi, mean);
        /* Rejection sampling must terminate in reasonable time: keep >= 1e-4 of the mass. */
        if (spread > 0.0) {
            const double a = (range->lo - mean) / (spread * sqrt(2.0));
            const double b = (range->hi - mean) / (spread * sqrt(2.0));
            if (0.5 * (erf(b) - erf(a)) < 1e-4)
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "%s: options radius_min = %g m and radius_max = %g m keep less "
                                   "than 1e-4 of the normal distribution (mean %g m, "
                                   "radius_spread %g m); widen them",
                                   func, range->lo, range->hi, mean, spread);
        }
        break;
    }
    case SINTER_RADII_LOGNORMAL:
        return check_lognormal(ctx, func, o, range);
    case SINTER_RADII_TABLE:
        return check_table(ctx, func, o, range);
    default:
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: option distribution = %d is not a sinter_radius_distribution", func,
                           o->distribution);
    }
    return SINTER_OK;
}

/* The caller's options over the defaults (an older, shorter layout gets the defaults). */
static sinter_status read_options(sinter_ctx *ctx, const char *func,
                                  const sinter_packing_options *in, sinter_packing_options *o)
{
    if (!known_size(in->struct_size))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: options.struct_size is %zu, expected %zu (or %zu or %zu for the "
                           "layouts before the log-normal, table and mixture fields and before "
                           "mixture_sizes); fill the options with sinter_packing_options_init",
                           func, in->struct_size, sizeof(sinter_packing_options),
                           PACKING_OPTIONS_OLD_SIZE, PACKING_OPTIONS_MIXTURE_SIZE);
    packing_defaults(o);
    memcpy(o, in, in->struct_size);
    return SINTER_OK;
}

/* ---- sizes per material (mixture_sizes) ------------------------------------------ */

/* The distributions of a mixture whose materials have their own (mixture_sizes): each
 * validated as the options' own, its table copied. */
typedef struct size_set {
    size_t count;              /* 0: every material draws from the options' own distribution */
    sinter_packing_options *o; /* count, validated, their tables pointing into `table` */
    radius_range *range;       /* count */
    double *table;             /* the tables' copies */
} size_set;

static void sizes_free(sinter_ctx *ctx, size_set *z)
{
    for (size_t k = 0; k < z->count; ++k)
        range_free(ctx, &z->range[k]);
    sinter_free(ctx, z->o);
    sinter_free(ctx, z->range);
    sinter_free(ctx, z->table);
    memset(z, 0, sizeof(*z));
}

static sinter_status sizes_copy_tables(sinter_ctx *ctx, size_set *z)
{
    size_t points = 0;
    for (size_t k = 0; k < z->count; ++k)
        points += z->o[k].distribution == SINTER_RADII_TABLE ? z->o[k].table_points : 0;
    z->table = sinter_realloc_array(ctx, NULL, 2 * points + 1, sizeof(double));
    if (z->table == NULL)
        return sinter_last_status(ctx);
    double *at = z->table;
    for (size_t k = 0; k < z->count; ++k) {
        sinter_packing_options *e = &z->o[k];
        e->mixture_count = 0;
        e->mixture_materials = NULL;
        e->mixture_mass_fractions = NULL;
        e->mixture_sizes = NULL;
        if (e->distribution != SINTER_RADII_TABLE) {
            e->table_diameter = e->table_cumulative = NULL;
            e->table_points = 0;
            continue;
        }
        const size_t n = e->table_points;
        memcpy(at, e->table_diameter, n * sizeof(double));
        memcpy(at + n, e->table_cumulative, n * sizeof(double));
        e->table_diameter = at;
        e->table_cumulative = at + n;
        at += 2 * n;
    }
    return SINTER_OK;
}

/* o->mixture_sizes (if any) validated into z, and `range` widened to every material's. */
static sinter_status sizes_check(sinter_ctx *ctx, const char *func, const sinter_packing_options *o,
                                 radius_range *range, size_set *z)
{
    memset(z, 0, sizeof(*z));
    if (o->mixture_sizes == NULL)
        return SINTER_OK;
    if (o->mixture_count == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: mixture_sizes is set but mixture_count is 0 (sizes per material "
                           "need a mixture)",
                           func);
    const size_t m = o->mixture_count;
    z->o = sinter_calloc(ctx, m, sizeof(*z->o));
    z->range = sinter_calloc(ctx, m, sizeof(*z->range));
    if (z->o == NULL || z->range == NULL)
        return SINTER_ERR_NOMEM;
    z->count = m;
    for (size_t k = 0; k < m; ++k) {
        char where[160];
        snprintf(where, sizeof(where), "%s: mixture_sizes[%zu] (material %d)", func, k,
                 (int)o->mixture_materials[k]);
        sinter_status st = read_options(ctx, where, &o->mixture_sizes[k], &z->o[k]);
        if (st == SINTER_OK)
            st = check_radii(ctx, where, &z->o[k], &z->range[k]);
        if (st != SINTER_OK)
            return st;
        range->lo = k == 0 ? z->range[k].lo : fmin(range->lo, z->range[k].lo);
        range->hi = k == 0 ? z->range[k].hi : fmax(range->hi, z->range[k].hi);
    }
    return sizes_copy_tables(ctx, z);
}

static sinter_status check_fields(const sinter_particles *ps, const char *func,
                                  const sinter_packing_options *in, size_t n,
                                  sinter_packing_options *o, radius_range *range, size_set *z)
{
    sinter_ctx *ctx = ps->ctx;
    sinter_status st = read_options(ctx, func, in, o);
    if (st != SINTER_OK)
        return st;
    st = o->mixture_count == 0
             ? check_common(ps, func, o->box_min, o->box_max, o->material, o->temperature)
             : check_set_and_box(ps, func, o->box_min, o->box_max, o->temperature);
    if (st == SINTER_OK && o->mixture_count > 0)
        st = check_mixture(ps, func, o);
    if (st == SINTER_OK)
        st = check_radii(ctx, func, o, range);
    if (st == SINTER_OK)
        st = sizes_check(ctx, func, o, range, z);
    if (st != SINTER_OK)
        return st;
    for (int d = 0; d < 3; ++d) {
        const double need = 2.0 * (range->hi + o->gap);
        if (o->box_max[d] - o->box_min[d] < need)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the box is %g m wide along %s (box_min[%d] to box_max[%d]), "
                               "less than the %g m a sphere of radius %g m with gap %g m needs",
                               func, o->box_max[d] - o->box_min[d], AXIS[d], d, d, need, range->hi,
                               o->gap);
    }
    if (n > SIZE_MAX / 3 - ps->count)
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW,
                           "%s: %zu new particles on top of %zu overflow the position array", func,
                           n, ps->count);
    return SINTER_OK;
}

/*
 * The caller's options `in` read into `o` and checked for n new spheres, and the sampler set up
 * in `range` and the sizes per material in `z` (range_free and sizes_free them after a
 * success; on an error nothing is left to free).
 */
static sinter_status check_options(const sinter_particles *ps, const char *func,
                                   const sinter_packing_options *in, size_t n,
                                   sinter_packing_options *o, radius_range *range, size_set *z)
{
    memset(range, 0, sizeof(*range));
    memset(z, 0, sizeof(*z));
    const sinter_status st = check_fields(ps, func, in, n, o, range, z);
    if (st != SINTER_OK) {
        range_free(ps->ctx, range);
        sizes_free(ps->ctx, z);
    }
    return st;
}

static double draw_table_radius(rng *g, const sinter_packing_options *o, const radius_range *range);

static double draw_radius(rng *g, const sinter_packing_options *o, const radius_range *range)
{
    switch (o->distribution) {
    case SINTER_RADII_UNIFORM:
        return o->radius_mean + o->radius_spread * (2.0 * rng_uniform(g) - 1.0);
    case SINTER_RADII_NORMAL:
        if (o->radius_spread == 0.0)
            return o->radius_mean;
        for (;;) {
            const double r = o->radius_mean + o->radius_spread * rng_normal(g);
            if (r >= range->lo && r <= range->hi)
                return r;
        }
    case SINTER_RADII_LOGNORMAL:
        if (range->log_gsd == 0.0)
            return o->radius_median;
        for (;;) {
            const double r = o->radius_median * det_exp(range->log_gsd * rng_normal(g));
            if (r >= range->lo && r <= range->hi)
                return r;
        }
    case SINTER_RADII_TABLE:
        return draw_table_radius(g, o, range);
    default:
        return o->radius_mean;
    }
}

/* A radius from the table: a row's point mass or an interval by its number weight, then a
 * diameter inside the interval: uniform (by number) or of density ~ d^-3 (by volume). */
static double draw_table_radius(rng *g, const sinter_packing_options *o, const radius_range *range)
{
    const size_t n = o->table_points;
    const double *d = o->table_diameter;
    const double u = rng_uniform(g) * range->cum[n - 1];
    size_t lo = 0, hi = n - 1; /* the first i with u < cum[i] */
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (u < range->cum[mid])
            hi = mid;
        else
            lo = mid + 1;
    }
    if (lo == 0)
        return 0.5 * d[0];
    const double a = d[lo - 1], b = d[lo], v = rng_uniform(g);
    double x;
    if (o->table_basis == SINTER_SIZE_BY_NUMBER) {
        x = a + (b - a) * v;
    } else { /* inverse of the CDF (a^-2 - x^-2) / (a^-2 - b^-2) */
        const double ia = 1.0 / (a * a), ib = 1.0 / (b * b);
        x = 1.0 / sqrt(ia - v * (ia - ib));
    }
    return 0.5 * fmin(fmax(x, a), b);
}

/* ---- cell grid ------------------------------------------------------------- */

/*
 * Uniform grid over the box with cells at least w = 2 r_hi + gap wide, where
 * r_hi is the largest radius the distribution draws. A sphere is listed in the
 * cell of its centre; a sphere with r_j > r_hi (only existing ones) in every
 * cell within r_j - r_hi of its centre. A candidate of radius r <= r_hi can
 * then only touch spheres listed in its own cell and the 26 around it. Entries
 * carry the centre and radius, so a check reads one contiguous record.
 */
typedef struct grid_entry {
    double x[3], r;
    size_t next; /* next entry of the same cell, NO_ENTRY at the end */
} grid_entry;

typedef struct cell_grid {
    double origin[3], width;
    size_t dims[3];
    size_t *head; /* first entry of each cell, NO_ENTRY if empty */
    grid_entry *entry;
    size_t entries, capacity;
} cell_grid;

/* Relative margin on cell widths and reaches, so that rounding never hides a neighbour. */
#define GRID_MARGIN (1.0 + 1e-6)

static size_t cell_coord(const cell_grid *g, int d, double x)
{
    const double t = floor((x - g->origin[d]) / g->width);
    if (!(t > 0.0))
        return 0; /* also NaN */
    if (t >= (double)(g->dims[d] - 1))
        return g->dims[d] - 1;
    return (size_t)t;
}

/* List a sphere in every cell within `extent` of its centre. */
static sinter_status grid_insert(cell_grid *g, sinter_ctx *ctx, const double x[3], double r,
                                 double extent)
{
    size_t lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        lo[d] = cell_coord(g, d, x[d] - extent);
        hi[d] = cell_coord(g, d, x[d] + extent);
    }
    for (size_t k = lo[2]; k <= hi[2]; ++k)
        for (size_t j = lo[1]; j <= hi[1]; ++j)
            for (size_t i = lo[0]; i <= hi[0]; ++i) {
                if (g->entries == g->capacity) {
                    const size_t cap = g->capacity < 256 ? 256 : 2 * g->capacity;
                    grid_entry *e = sinter_realloc_array(ctx, g->entry, cap, sizeof(*e));
                    if (e == NULL)
                        return sinter_last_status(ctx);
                    g->entry = e;
                    g->capacity = cap;
                }
                const size_t cell = i + g->dims[0] * (j + g->dims[1] * k);
                grid_entry *e = &g->entry[g->entries];
                memcpy(e->x, x, sizeof(e->x));
                e->r = r;
                e->next = g->head[cell];
                g->head[cell] = g->entries++;
            }
    return SINTER_OK;
}

/* 1 if a sphere (x, r) keeps the gap to every sphere listed around its cell. */
static int grid_fits(const cell_grid *g, const double x[3], double r, double gap)
{
    size_t lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        const size_t c = cell_coord(g, d, x[d]);
        lo[d] = c > 0 ? c - 1 : 0;
        hi[d] = c + 1 < g->dims[d] ? c + 1 : c;
    }
    for (size_t k = lo[2]; k <= hi[2]; ++k)
        for (size_t j = lo[1]; j <= hi[1]; ++j)
            for (size_t i = lo[0]; i <= hi[0]; ++i) {
                size_t e = g->head[i + g->dims[0] * (j + g->dims[1] * k)];
                for (; e != NO_ENTRY; e = g->entry[e].next) {
                    const grid_entry *s = &g->entry[e];
                    const double dx = x[0] - s->x[0], dy = x[1] - s->x[1], dz = x[2] - s->x[2];
                    const double contact = r + s->r + gap;
                    if (dx * dx + dy * dy + dz * dz < contact * contact)
                        return 0;
                }
            }
    return 1;
}

/* Cells of width >= 2 r_hi + gap, widened until there are at most 2 per expected sphere. */
static sinter_status grid_create(cell_grid *g, sinter_ctx *ctx, const sinter_packing_options *o,
                                 const radius_range *range, size_t n, size_t existing)
{
    double volume = 1.0;
    for (int d = 0; d < 3; ++d)
        volume *= o->box_max[d] - o->box_min[d];
    const double fit = volume / (4.0 / 3.0 * PI * range->lo * range->lo * range->lo);
    const double max_cells = 2.0 * ((double)existing + fmin((double)n, fit)) + 8.0;
    double width = (2.0 * range->hi + o->gap) * GRID_MARGIN, cells;
    for (;;) {
        cells = 1.0;
        for (int d = 0; d < 3; ++d)
            cells *= fmax(1.0, ceil((o->box_max[d] - o->box_min[d]) / width));
        if (cells <= max_cells)
            break;
        width *= 1.25;
    }
    memset(g, 0, sizeof(*g));
    g->width = width;
    for (int d = 0; d < 3; ++d) {
        g->origin[d] = o->box_min[d];
        g->dims[d] = (size_t)fmax(1.0, ceil((o->box_max[d] - o->box_min[d]) / width));
    }
    g->head = sinter_realloc_array(ctx, NULL, (size_t)cells, sizeof(size_t));
    if (g->head == NULL)
        return sinter_last_status(ctx);
    for (size_t c = 0; c < (size_t)cells; ++c)
        g->head[c] = NO_ENTRY;
    return SINTER_OK;
}

static void grid_destroy(cell_grid *g, sinter_ctx *ctx)
{
    sinter_free(ctx, g->head);
    sinter_free(ctx, g->entry);
}

/* ---- random sequential addition ------------------------------------------------ */

/* The new spheres, kept apart so that they reach the set in one sinter_particles_add (and
 * each one's material in a mixture: an index into the mixture's materials). */
typedef struct sphere_list {
    double *x, *r;
    uint32_t *kind;
    size_t count, capacity;
} sphere_list;

static sinter_status spheres_push(sphere_list *s, sinter_ctx *ctx, const double x[3], double r,
                                  size_t kind, size_t limit)
{
    if (s->count == s->capacity) {
        size_t cap = s->capacity < 1024 ? 1024 : 2 * s->capacity;
        if (cap > limit)
            cap = limit;
        double *nx = sinter_realloc_array(ctx, s->x, 3 * cap, sizeof(double));
        if (nx == NULL)
            return sinter_last_status(ctx);
        s->x = nx;
        double *nr = sinter_realloc_array(ctx, s->r, cap, sizeof(double));
        if (nr == NULL)
            return sinter_last_status(ctx);
        s->r = nr;
        uint32_t *nk = sinter_realloc_array(ctx, s->kind, cap, sizeof(uint32_t));
        if (nk == NULL)
            return sinter_last_status(ctx);
        s->kind = nk;
        s->capacity = cap;
    }
    memcpy(s->x + 3 * s->count, x, 3 * sizeof(double));
    s->kind[s->count] = (uint32_t)kind;
    s->r[s->count++] = r;
    return SINTER_OK;
}

/* 1 if existing particle i can touch a new sphere inside the box. */
static int near_box(const sinter_particles *ps, size_t i, const sinter_packing_options *o,
                    const radius_range *range)
{
    const double reach = (ps->radius[i] + range->hi + o->gap) * GRID_MARGIN;
    for (int d = 0; d < 3; ++d)
        if (!(ps->x[3 * i + d] + reach >= o->box_min[d] &&
              ps->x[3 * i + d] - reach <= o->box_max[d]))
            return 0; /* also skips non-finite values */
    return 1;
}

/* With sizes per material (z) each sphere's material is chosen (mx) before its radius. */
static sinter_status pack_random(sinter_particles *ps, const sinter_packing_options *o, size_t n,
                                 const radius_range *range, const size_set *z, sinter_mixture *mx,
                                 sphere_list *s, cell_grid *g)
{
    sinter_ctx *ctx = ps->ctx;
    /* Existing particles that can touch the box take part in the overlap test. */
    size_t existing = 0;
    for (size_t i = 0; i < ps->count; ++i)
        existing += (size_t)near_box(ps, i, o, range);
    sinter_status st = grid_create(g, ctx, o, range, n, existing);
    for (size_t i = 0; i < ps->count && st == SINTER_OK; ++i)
        if (near_box(ps, i, o, range))
            st = grid_insert(g, ctx, ps->x + 3 * i, ps->radius[i],
                             fmax(0.0, ps->radius[i] - range->hi) * GRID_MARGIN);
    if (st != SINTER_OK)
        return st;
    rng gen;
    rng_seed(&gen, o->seed);
    for (size_t k = 0; k < n; ++k) {
        const size_t kind = z->count > 0 ? sinter_mixture_next(mx) : 0;
        const double r = z->count > 0 ? draw_radius(&gen, &z->o[kind], &z->range[kind])
                                      : draw_radius(&gen, o, range);
        double lo[3], hi[3], x[3];
        for (int d = 0; d < 3; ++d) {
            lo[d] = o->box_min[d] + r + o->gap;
            hi[d] = o->box_max[d] - r - o->gap;
        }
        int placed = 0;
        for (uint64_t attempt = 0; attempt < o->max_attempts && !placed; ++attempt) {
            for (int d = 0; d < 3; ++d)
                x[d] = fmin(lo[d] + (hi[d] - lo[d]) * rng_uniform(&gen), hi[d]);
            placed = grid_fits(g, x, r, o->gap);
        }
        if (!placed)
            break; /* max_attempts failures in a row: the box is (nearly) jammed */
        st = spheres_push(s, ctx, x, r, kind, n);
        if (st == SINTER_OK)
            st = grid_insert(g, ctx, x, r, 0.0);
        if (st != SINTER_OK)
            return st;
        if (z->count > 0)
            sinter_mixture_add(mx, kind, r);
    }
    return SINTER_OK;
}

/*
 * Add the placed spheres, each of the material the mixture chooses for it (mixture.c): with
 * one distribution for all, in placement order now (the random stream does not depend on the
 * mixture); with sizes per material, as chosen before each radius was drawn. Runs of one
 * material go to the set in one call each, after a reserve (so that no call after the first
 * can run out of memory and leave the set half filled).
 */
static sinter_status add_mixture(sinter_particles *ps, const sinter_packing_options *o,
                                 const size_set *z, sinter_mixture *mx, sphere_list *s)
{
    if (z->count == 0)
        for (size_t i = 0; i < s->count; ++i) {
            const size_t k = sinter_mixture_next(mx);
            sinter_mixture_add(mx, k, s->r[i]);
            s->kind[i] = (uint32_t)k;
        }
    sinter_status st = sinter_particles_reserve(ps, ps->count + s->count);
    for (size_t i = 0; i < s->count && st == SINTER_OK;) {
        size_t j = i + 1;
        while (j < s->count && s->kind[j] == s->kind[i])
            ++j;
        st = sinter_particles_add(ps, j - i, s->x + 3 * i, s->r + i, mx->material[s->kind[i]],
                                  o->temperature, NULL);
        i = j;
    }
    return st;
}

sinter_status sinter_pack_random(sinter_particles *particles, const sinter_packing_options *options,
                                 size_t n, size_t *placed)
{
    if (particles == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = particles->ctx;
    SINTER_CHECK_NULL(ctx, options);
    if (placed)
        *placed = 0;
    sinter_packing_options o;
    radius_range range;
    size_set sizes;
    sinter_status st =
        check_options(particles, "sinter_pack_random", options, n, &o, &range, &sizes);
    if (st != SINTER_OK)
        return st;
    sinter_mixture mx;
    st = sinter_mixture_init(&mx, particles, &o);
    if (st != SINTER_OK || n == 0) {
        sizes_free(ctx, &sizes);
        range_free(ctx, &range);
        return st;
    }
    sphere_list spheres = {NULL, NULL, NULL, 0, 0};
    cell_grid grid;
    memset(&grid, 0, sizeof(grid));
    st = pack_random(particles, &o, n, &range, &sizes, &mx, &spheres, &grid);
    const size_t count = spheres.count;
    if (st == SINTER_OK && count > 0)
        st = o.mixture_count > 0 ? add_mixture(particles, &o, &sizes, &mx, &spheres)
                                 : sinter_particles_add(particles, count, spheres.x, spheres.r,
                                                        o.material, o.temperature, NULL);
    grid_destroy(&grid, ctx);
    sinter_mixture_free(ctx, &mx);
    sizes_free(ctx, &sizes);
    range_free(ctx, &range);
    sinter_free(ctx, spheres.x);
    sinter_free(ctx, spheres.r);
    sinter_free(ctx, spheres.kind);
    if (st == SINTER_OK && placed)
        *placed = count;
    return st;
}

sinter_status sinter_packing_sample_radii(sinter_particles *particles,
                                          const sinter_packing_options *options, size_t n,
                                          double *radii)
{
    sinter_ctx *ctx = particles->ctx;
    sinter_packing_options o;
    radius_range range;
    size_set sizes;
    const sinter_status st =
        check_options(particles, "sinter_packing_sample_radii", options, 0, &o, &range, &sizes);
    if (st == SINTER_OK) {
        rng gen;
        rng_seed(&gen, o.seed);
        for (size_t k = 0; k < n; ++k)
            radii[k] = draw_radius(&gen, &o, &range);
    }
    sizes_free(ctx, &sizes);
    range_free(ctx, &range);
    return st;
}

/* ---- a sampler that outlives the call (packing.h) ------------------------------ */

struct sinter_radius_sampler {
    sinter_packing_options o;
    radius_range range;
    size_set sizes; /* a mixture's sizes per material, if any */
    sinter_mixture mix;
    size_t pending; /* the mixture's index of the material of the last radius drawn */
    rng gen;
    double *table; /* 2 table_points: the diameters, then the cumulative fractions */
};

sinter_status sinter_radius_sampler_create(sinter_radius_sampler **out, sinter_particles *particles,
                                           const sinter_packing_options *options, const char *func)
{
    sinter_ctx *ctx = particles->ctx;
    *out = NULL;
    sinter_radius_sampler *s = sinter_calloc(ctx, 1, sizeof(*s));
    if (s == NULL)
        return sinter_last_status(ctx);
    sinter_status st = check_options(particles, func, options, 0, &s->o, &s->range, &s->sizes);
    if (st == SINTER_OK)
        st = sinter_mixture_init(&s->mix, particles, &s->o);
    if (st == SINTER_OK && s->o.distribution == SINTER_RADII_TABLE) {
        const size_t n = s->o.table_points;
        s->table = sinter_realloc_array(ctx, NULL, 2 * n, sizeof(double));
        if (s->table == NULL)
            st = sinter_last_status(ctx);
        else {
            memcpy(s->table, s->o.table_diameter, n * sizeof(double));
            memcpy(s->table + n, s->o.table_cumulative, n * sizeof(double));
            s->o.table_diameter = s->table;
            s->o.table_cumulative = s->table + n;
        }
    }
    if (s->o.distribution != SINTER_RADII_TABLE) {
        s->o.table_diameter = s->o.table_cumulative = NULL;
        s->o.table_points = 0;
    }
    /* borrowed: the mixture and its sizes are copied (s->mix, s->sizes) */
    s->o.mixture_materials = NULL;
    s->o.mixture_mass_fractions = NULL;
    s->o.mixture_sizes = NULL;
    if (st != SINTER_OK) {
        sinter_radius_sampler_destroy(ctx, s);
        return st;
    }
    rng_seed(&s->gen, s->o.seed);
    *out = s;
    return SINTER_OK;
}

double sinter_radius_sampler_radius(sinter_radius_sampler *s)
{
    if (s->mix.count > 0)
        s->pending = sinter_mixture_next(&s->mix);
    if (s->sizes.count > 0)
        return draw_radius(&s->gen, &s->sizes.o[s->pending], &s->sizes.range[s->pending]);
    return draw_radius(&s->gen, &s->o, &s->range);
}

int32_t sinter_radius_sampler_material(const sinter_radius_sampler *s)
{
    return s->mix.count > 0 ? s->mix.material[s->pending] : s->o.material;
}

void sinter_radius_sampler_placed(sinter_radius_sampler *s, double r)
{
    if (s->mix.count > 0)
        sinter_mixture_add(&s->mix, s->pending, r);
}

size_t sinter_radius_sampler_mixture(const sinter_radius_sampler *s, const double **mass)
{
    if (mass != NULL)
        *mass = s->mix.mass;
    return s->mix.count;
}

void sinter_radius_sampler_get_mixture(const sinter_radius_sampler *s, uint64_t *pending,
                                       double *mass)
{
    *pending = s->pending;
    memcpy(mass, s->mix.mass, s->mix.count * sizeof(double));
    mass[s->mix.count] = s->mix.total;
}

int sinter_radius_sampler_set_mixture(sinter_radius_sampler *s, uint64_t pending,
                                      const double *mass)
{
    if (pending >= s->mix.count)
        return 0;
    for (size_t k = 0; k <= s->mix.count; ++k)
        if (!isfinite(mass[k]) || mass[k] < 0.0)
            return 0;
    s->pending = (size_t)pending;
    memcpy(s->mix.mass, mass, s->mix.count * sizeof(double));
    s->mix.total = mass[s->mix.count];
    return 1;
}

double sinter_radius_sampler_uniform(sinter_radius_sampler *s)
{
    return rng_uniform(&s->gen);
}

double sinter_radius_sampler_max(const sinter_radius_sampler *s)
{
    return s->range.hi;
}

const sinter_packing_options *sinter_radius_sampler_options(const sinter_radius_sampler *s)
{
    return &s->o;
}

void sinter_radius_sampler_get_stream(const sinter_radius_sampler *s, uint64_t state[4])
{
    memcpy(state, s->gen.s, sizeof(s->gen.s));
}

void sinter_radius_sampler_set_stream(sinter_radius_sampler *s, const uint64_t state[4])
{
    memcpy(s->gen.s, state, sizeof(s->gen.s));
}

void sinter_radius_sampler_destroy(sinter_ctx *ctx, sinter_radius_sampler *s)
{
    if (s == NULL)
        return;
    range_free(ctx, &s->range);
    sizes_free(ctx, &s->sizes);
    sinter_mixture_free(ctx, &s->mix);
    sinter_free(ctx, s->table);
    sinter_free(ctx, s);
}

/* ---- lattice ----------------------------------------------------------------------- */

/* Centres lo + r + i spacing with centre + r <= hi, i = 0 .. *count - 1. */
static sinter_status lattice_axis(sinter_ctx *ctx, double lo, double hi, double r, double spacing,
                                  int d, size_t *count)
{
    *count = 0;
    if (hi - lo < 2.0 * r)
        return SINTER_OK;
    const double estimate = floor((hi - lo - 2.0 * r) / spacing) + 1.0;
    if (!(estimate < 1e15))
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW,
                           "sinter_pack_lattice: %g spheres along %s is too many", estimate,
                           AXIS[d]);
    size_t k = (size_t)estimate;
    /* Settle rounding with the exact test used for the positions. */
    while (k > 0 && lo + r + (double)(k - 1) * spacing + r > hi)
        k--;
    while (lo + r + (double)k * spacing + r <= hi)
        k++;
    *count = k;
    return SINTER_OK;
}

sinter_status sinter_pack_lattice(sinter_particles *particles, const double box_min[3],
                                  const double box_max[3], double radius, double spacing,
                                  int32_t material, double temperature, size_t *placed)
{
    static const char *func = "sinter_pack_lattice";
    if (particles == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = particles->ctx;
    SINTER_CHECK_NULL(ctx, box_min);
    SINTER_CHECK_NULL(ctx, box_max);
    if (placed)
        *placed = 0;
    sinter_status st = check_common(particles, func, box_min, box_max, material, temperature);
    if (st != SINTER_OK)
        return st;
    if (!isfinite(radius) || radius <= 0.0)
        return invalid_option(ctx, func, "radius", radius, "m must be positive and finite");
    if (!isfinite(spacing) || !(spacing >= 2.0 * radius))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: spacing = %g m must be finite and at least twice the radius "
                           "(%g m) so that spheres do not overlap",
                           func, spacing, 2.0 * radius);
    size_t dims[3];
    for (int d = 0; d < 3; ++d) {
        st = lattice_axis(ctx, box_min[d], box_max[d], radius, spacing, d, &dims[d]);
        if (st != SINTER_OK)
            return st;
    }
    if (sinter_mul_overflows(dims[0], dims[1]) ||
        sinter_mul_overflows(dims[0] * dims[1], dims[2]) ||
        sinter_mul_overflows(dims[0] * dims[1] * dims[2], 3))
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW, "%s: a %zu x %zu x %zu lattice overflows",
                           func, dims[0], dims[1], dims[2]);
    const size_t n = dims[0] * dims[1] * dims[2];
    if (n == 0)
        return SINTER_OK;
    double *x = sinter_realloc_array(ctx, NULL, 3 * n, sizeof(double));
    double *r = x == NULL ? NULL : sinter_realloc_array(ctx, NULL, n, sizeof(double));
    if (r == NULL) {
        sinter_free(ctx, x);
        return sinter_last_status(ctx);
    }
    size_t m = 0;
    for (size_t k = 0; k < dims[2]; ++k)
        for (size_t j = 0; j < dims[1]; ++j)
            for (size_t i = 0; i < dims[0]; ++i, ++m) {
                x[3 * m] = box_min[0] + radius + (double)i * spacing;
                x[3 * m + 1] = box_min[1] + radius + (double)j * spacing;
                x[3 * m + 2] = box_min[2] + radius + (double)k * spacing;
                r[m] = radius;
            }
    st = sinter_particles_add(particles, n, x, r, material, temperature, NULL);
    sinter_free(ctx, x);
    sinter_free(ctx, r);
    if (st == SINTER_OK && placed)
        *placed = n;
    return st;
}
