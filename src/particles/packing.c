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
#include <string.h>

#include "particles.h"

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

sinter_status sinter_packing_options_init(sinter_packing_options *options, size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (struct_size != sizeof(sinter_packing_options))
        return SINTER_ERR_STRUCT_SIZE;
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
    return SINTER_OK;
}

/* The radius range a validated distribution draws from ([lo, hi], both > 0). */
typedef struct radius_range {
    double lo, hi;
} radius_range;

static sinter_status invalid_option(sinter_ctx *ctx, const char *func, const char *name,
                                    double value, const char *rule)
{
    return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: option %s = %g %s", func, name, value, rule);
}

/* Checks shared by both packers: lock, material, temperature, box. */
static sinter_status check_common(const sinter_particles *ps, const char *func,
                                  const double box_min[3], const double box_max[3],
                                  int32_t material, double temperature)
{
    sinter_ctx *ctx = ps->ctx;
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are still out; release "
                           "them before adding particles",
                           func, ps->views_out);
    if (material < 0 || material >= SINTER_MAX_MATERIALS || !ps->material_used[material])
        return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                           "%s: material %d is not registered in the particle set; call "
                           "sinter_particles_set_material first",
                           func, (int)material);
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

static sinter_status check_options(const sinter_particles *ps, const sinter_packing_options *o,
                                   size_t n, radius_range *range)
{
    static const char *func = "sinter_pack_random";
    sinter_ctx *ctx = ps->ctx;
    if (o->struct_size != sizeof(sinter_packing_options))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: options.struct_size is %zu, expected %zu; fill the options "
                           "with sinter_packing_options_init",
                           func, o->struct_size, sizeof(sinter_packing_options));
    sinter_status st = check_common(ps, func, o->box_min, o->box_max, o->material, o->temperature);
    if (st != SINTER_OK)
        return st;
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
    default:
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: option distribution = %d is not a sinter_radius_distribution", func,
                           o->distribution);
    }
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
    default:
        return o->radius_mean;
    }
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

/* The new spheres, kept apart so that they reach the set in one sinter_particles_add. */
typedef struct sphere_list {
    double *x, *r;
    size_t count, capacity;
} sphere_list;

static sinter_status spheres_push(sphere_list *s, sinter_ctx *ctx, const double x[3], double r,
                                  size_t limit)
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
        s->capacity = cap;
    }
    memcpy(s->x + 3 * s->count, x, 3 * sizeof(double));
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

static sinter_status pack_random(sinter_particles *ps, const sinter_packing_options *o, size_t n,
                                 const radius_range *range, sphere_list *s, cell_grid *g)
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
        const double r = draw_radius(&gen, o, range);
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
        st = spheres_push(s, ctx, x, r, n);
        if (st == SINTER_OK)
            st = grid_insert(g, ctx, x, r, 0.0);
        if (st != SINTER_OK)
            return st;
    }
    return SINTER_OK;
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
    radius_range range = {0.0, 0.0};
    sinter_status st = check_options(particles, options, n, &range);
    if (st != SINTER_OK || n == 0)
        return st;
    sphere_list spheres = {NULL, NULL, 0, 0};
    cell_grid grid;
    memset(&grid, 0, sizeof(grid));
    st = pack_random(particles, options, n, &range, &spheres, &grid);
    const size_t count = spheres.count;
    if (st == SINTER_OK && count > 0)
        st = sinter_particles_add(particles, count, spheres.x, spheres.r, options->material,
                                  options->temperature, NULL);
    grid_destroy(&grid, ctx);
    sinter_free(ctx, spheres.x);
    sinter_free(ctx, spheres.r);
    if (st == SINTER_OK && placed)
        *placed = count;
    return st;
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
