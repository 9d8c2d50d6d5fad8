/*
 * Packing helpers: options, simple-cubic lattice, random sequential addition (seed 000 7.1),
 * triaxial compaction (seed 001 sec. 3.2).
 */
#include <math.h>
#include <string.h>

#include "test_support.h"

static const double PI = 3.14159265358979323846;

/*
 * Tolerance of the geometric checks: the packer accepts a sphere when the
 * squared centre distance is >= (ri + rj + gap)^2 in double precision; the test
 * recomputes the distance with a square root, which differs by a few ulp
 * (~1e-16 relative). 1e-12 relative is far above that and far below any
 * real overlap.
 */
#define GEOMETRY_RTOL 1e-12

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_material *mat;
    sinter_particles *ps;
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof(f));
    if (sinter_ctx_create(&f.ctx, NULL) != SINTER_OK ||
        sinter_material_create(&f.mat, f.ctx, "glass") != SINTER_OK ||
        sinter_particles_create(&f.ps, f.ctx) != SINTER_OK ||
        sinter_particles_set_material(f.ps, 0, f.mat) != SINTER_OK)
        return -1;
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sinter_particles_destroy(f->ps);
    sinter_material_destroy(f->mat);
    sinter_ctx_destroy(f->ctx);
    return 0;
}

static size_t count_of(const sinter_particles *ps)
{
    size_t n = 0;
    assert_int_equal(sinter_particles_count(ps, &n), SINTER_OK);
    return n;
}

/* Borrow positions and radii; give them back with release_xr. */
static size_t view_xr(const sinter_particles *ps, const double **x, const double **r)
{
    size_t n = 0;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)x, &n, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)r, NULL, NULL),
        SINTER_OK);
    return n;
}

static void release_xr(const sinter_particles *ps)
{
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_POSITION), SINTER_OK);
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_RADIUS), SINTER_OK);
}

/* Every pair keeps a surface gap >= gap (all pairs: n <= a few thousand). */
static void assert_no_overlap(const sinter_particles *ps, double gap)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
            const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1],
                         dz = x[3 * i + 2] - x[3 * j + 2];
            const double contact = r[i] + r[j] + gap;
            if (sqrt(dx * dx + dy * dy + dz * dz) < contact * (1.0 - GEOMETRY_RTOL)) {
                print_error("spheres %zu and %zu overlap\n", i, j);
                fail();
            }
        }
    release_xr(ps);
}

/* Particles first..count-1 lie in the box, keeping `gap` to its faces. */
static void assert_inside(const sinter_particles *ps, size_t first, const double lo[3],
                          const double hi[3], double gap)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    for (size_t i = first; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
            const double slack = GEOMETRY_RTOL * (hi[d] - lo[d]);
            assert_true(x[3 * i + d] - r[i] - gap >= lo[d] - slack);
            assert_true(x[3 * i + d] + r[i] + gap <= hi[d] + slack);
        }
    release_xr(ps);
}

static sinter_packing_options options_in_box(double lo, double hi)
{
    sinter_packing_options o;
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    for (int d = 0; d < 3; ++d) {
        o.box_min[d] = lo;
        o.box_max[d] = hi;
    }
    return o;
}

static void test_options_init(void **state)
{
    (void)state;
    sinter_packing_options o;
    memset(&o, 0xff, sizeof(o));
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o) - 1), SINTER_ERR_STRUCT_SIZE);
    assert_int_equal(sinter_packing_options_init(NULL, sizeof(o)), SINTER_ERR_NULL);
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    assert_int_equal(o.struct_size, sizeof(o));
    for (int d = 0; d < 3; ++d) {
        assert_close(o.box_min[d], 0.0, 0.0);
        assert_close(o.box_max[d], 1.0, 0.0);
    }
    assert_int_equal(o.distribution, SINTER_RADII_MONODISPERSE);
    assert_close(o.radius_mean, 0.05, 0.0);
    assert_close(o.radius_spread + o.radius_min + o.radius_max + o.gap, 0.0, 0.0);
    assert_int_equal(o.seed, 1);
    assert_int_equal(o.max_attempts, 100000);
    assert_int_equal(o.material, 0);
    assert_close(o.temperature, 293.15, 0.0);
}

static void test_lattice_exact(void **state)
{
    fixture *f = *state;
    /* Binary fractions, so every expected centre is exact; x ends exactly on box_max. */
    const double lo[3] = {0.0, 0.0, -0.25}, hi[3] = {1.0, 0.5, 0.3};
    const double r = 0.0625, spacing = 0.125;
    const size_t dims[3] = {8, 4, 4};
    size_t placed = 0;
    assert_int_equal(sinter_pack_lattice(f->ps, lo, hi, r, spacing, 0, 300.0, &placed), SINTER_OK);
    assert_int_equal(placed, 128);
    const double *x, *rad;
    assert_int_equal(view_xr(f->ps, &x, &rad), 128);
    size_t m = 0;
    for (size_t k = 0; k < dims[2]; ++k)
        for (size_t j = 0; j < dims[1]; ++j)
            for (size_t i = 0; i < dims[0]; ++i, ++m) {
                /* exact: same IEEE operations on exactly representable values */
                assert_close(x[3 * m], lo[0] + r + (double)i * spacing, 0.0);
                assert_close(x[3 * m + 1], lo[1] + r + (double)j * spacing, 0.0);
                assert_close(x[3 * m + 2], lo[2] + r + (double)k * spacing, 0.0);
                assert_close(rad[m], r, 0.0);
            }
    release_xr(f->ps);

    /* A wider spacing: centres 0.05 + 0.2 i with centre + r <= 1 give 5 per axis. */
    const double unit_lo[3] = {0, 0, 0}, unit_hi[3] = {1, 1, 1};
    assert_int_equal(sinter_pack_lattice(f->ps, unit_lo, unit_hi, 0.05, 0.2, 0, 300.0, &placed),
                     SINTER_OK);
    assert_int_equal(placed, 125);
    assert_int_equal(count_of(f->ps), 128 + 125);
    /* A box narrower than one sphere holds none. */
    const double thin_hi[3] = {1, 1, 0.05};
    assert_int_equal(sinter_pack_lattice(f->ps, unit_lo, thin_hi, 0.05, 0.2, 0, 300.0, &placed),
                     SINTER_OK);
    assert_int_equal(placed, 0);
    assert_int_equal(count_of(f->ps), 128 + 125);
    assert_int_equal(sinter_pack_lattice(f->ps, unit_lo, unit_hi, 0.05, 0.2, 0, 300.0, NULL),
                     SINTER_OK);
}

static void expect_error(const fixture *f, sinter_status got, sinter_status want, const char *word)
{
    assert_int_equal(got, want);
    assert_int_equal(sinter_last_status(f->ctx), want);
    if (strstr(sinter_last_error(f->ctx), word) == NULL) {
        print_error("message \"%s\" does not name \"%s\"\n", sinter_last_error(f->ctx), word);
        fail();
    }
}

static void test_lattice_rejects_bad_arguments(void **state)
{
    fixture *f = *state;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, flat[3] = {1, 0, 1};
    const double bad[3] = {1, 1, NAN};
    size_t placed = 7;
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, 0.1, 0.19, 0, 300.0, &placed),
                 SINTER_ERR_INVALID, "spacing");
    assert_int_equal(placed, 0);
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, 0.0, 0.2, 0, 300.0, NULL),
                 SINTER_ERR_INVALID, "radius");
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, NAN, 0.2, 0, 300.0, NULL),
                 SINTER_ERR_INVALID, "radius");
    expect_error(f, sinter_pack_lattice(f->ps, lo, flat, 0.1, 0.2, 0, 300.0, NULL),
                 SINTER_ERR_INVALID, "box_max[1]");
    expect_error(f, sinter_pack_lattice(f->ps, lo, bad, 0.1, 0.2, 0, 300.0, NULL),
                 SINTER_ERR_INVALID, "box_max[2]");
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, 0.1, 0.2, 5, 300.0, NULL),
                 SINTER_ERR_NOT_FOUND, "material 5");
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, 0.1, 0.2, 0, -1.0, NULL), SINTER_ERR_INVALID,
                 "temperature");
    expect_error(f, sinter_pack_lattice(f->ps, lo, hi, 1e-9, 2e-9, 0, 300.0, NULL),
                 SINTER_ERR_OVERFLOW, "lattice overflows");
    expect_error(f, sinter_pack_lattice(f->ps, NULL, hi, 0.1, 0.2, 0, 300.0, NULL), SINTER_ERR_NULL,
                 "box_min");
    assert_int_equal(sinter_pack_lattice(NULL, lo, hi, 0.1, 0.2, 0, 300.0, NULL), SINTER_ERR_NULL);
    assert_int_equal(count_of(f->ps), 0);
}

/* The press scene of seed 000: 1000 spheres R = 0.075 m in [-1, 1]^3, phi = 0.22. */
static void test_random_press_scene(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(-1.0, 1.0);
    o.radius_mean = 0.075;
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(f->ps, &o, 1000, &placed), SINTER_OK);
    assert_int_equal(placed, 1000);
    assert_int_equal(count_of(f->ps), 1000);
    const double *x, *r;
    view_xr(f->ps, &x, &r);
    double volume = 0.0;
    for (size_t i = 0; i < 1000; ++i) {
        assert_close(r[i], 0.075, 0.0); /* monodisperse: exact */
        volume += 4.0 / 3.0 * PI * r[i] * r[i] * r[i];
    }
    release_xr(f->ps);
    /* phi = 1000 4/3 pi R^3 / 8 = 0.2209; 1000 summed terms round to ~1e-13, so 1e-12. */
    assert_close(volume / 8.0, 1000.0 * 4.0 / 3.0 * PI * pow(0.075, 3) / 8.0, 1e-12);
    assert_true(volume / 8.0 > 0.22);
    assert_no_overlap(f->ps, 0.0);
    assert_inside(f->ps, 0, o.box_min, o.box_max, 0.0);
}

static void pack_into_new_set(const fixture *f, const sinter_packing_options *o, size_t n,
                              sinter_particles **out)
{
    assert_int_equal(sinter_particles_create(out, f->ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(*out, 0, f->mat), SINTER_OK);
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(*out, o, n, &placed), SINTER_OK);
    assert_int_equal(placed, n);
}

static int same_bits(const sinter_particles *a, const sinter_particles *b)
{
    const double *xa, *ra, *xb, *rb;
    const size_t n = view_xr(a, &xa, &ra);
    assert_int_equal(view_xr(b, &xb, &rb), n);
    const int same =
        memcmp(xa, xb, 3 * n * sizeof(double)) == 0 && memcmp(ra, rb, n * sizeof(double)) == 0;
    release_xr(a);
    release_xr(b);
    return same;
}

static void test_random_is_deterministic(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(0.0, 1.0);
    o.distribution = SINTER_RADII_NORMAL;
    o.radius_mean = 0.04;
    o.radius_spread = 0.01;
    o.gap = 0.001;
    o.seed = 42;
    sinter_particles *a, *b, *c;
    pack_into_new_set(f, &o, 300, &a);
    pack_into_new_set(f, &o, 300, &b);
    o.seed = 43;
    pack_into_new_set(f, &o, 300, &c);
    assert_true(same_bits(a, b));  /* same seed: bitwise identical */
    assert_false(same_bits(a, c)); /* another seed: another packing */
    sinter_particles_destroy(a);
    sinter_particles_destroy(b);
    sinter_particles_destroy(c);
}

/*
 * Golden values: the first spheres of seed 1 as this implementation draws
 * them. The stream uses only exactly rounded operations, so these bits hold on
 * every IEEE 754 machine; a change here changes every seeded packing.
 */
static void test_random_golden_values(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(0.0, 1.0);
    o.distribution = SINTER_RADII_NORMAL;
    o.radius_spread = 0.01;
    assert_int_equal(sinter_pack_random(f->ps, &o, 2, NULL), SINTER_OK);
    const double *x, *r;
    view_xr(f->ps, &x, &r);
    const double want_x[6] = {0x1.20b7cb5f5485bp-1, 0x1.a00ad65947f68p-2, 0x1.570e15984b8a6p-1,
                              0x1.17fe6d59acb42p-1, 0x1.c8b7b63072f9cp-1, 0x1.d42749b71842ap-1};
    const double want_r[2] = {0x1.19fc2013a4d44p-4, 0x1.7fed0309ca237p-5};
    for (int k = 0; k < 6; ++k)
        assert_close(x[k], want_x[k], 0.0);
    for (int k = 0; k < 2; ++k)
        assert_close(r[k], want_r[k], 0.0);
    release_xr(f->ps);
}

static void sample_moments(const sinter_particles *ps, double *mean, double *std)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    double sum = 0.0, sum2 = 0.0;
    for (size_t i = 0; i < n; ++i)
        sum += r[i];
    *mean = sum / (double)n;
    for (size_t i = 0; i < n; ++i)
        sum2 += (r[i] - *mean) * (r[i] - *mean);
    *std = sqrt(sum2 / (double)(n - 1));
    release_xr(ps);
}

static void assert_radii_within(const sinter_particles *ps, double lo, double hi)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    for (size_t i = 0; i < n; ++i)
        assert_true(r[i] >= lo && r[i] <= hi);
    release_xr(ps);
}

/* 2000 small spheres in a unit box (phi < 0.02): every draw is placed, so radii are i.i.d. */
enum { SAMPLE = 2000 };

static void test_random_uniform_radii(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(0.0, 1.0);
    o.distribution = SINTER_RADII_UNIFORM;
    o.radius_mean = 0.01;
    o.radius_spread = 0.004;
    o.gap = 0.0005;
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(f->ps, &o, SAMPLE, &placed), SINTER_OK);
    assert_int_equal(placed, SAMPLE);
    assert_radii_within(f->ps, o.radius_mean - o.radius_spread, o.radius_mean + o.radius_spread);
    double mean, std;
    sample_moments(f->ps, &mean, &std);
    /* Standard error of the mean of U(m - s, m + s): s / sqrt(3 n); 4 SE fail with p = 6e-5. */
    assert_close(mean, o.radius_mean, 4.0 * o.radius_spread / sqrt(3.0 * SAMPLE));
    assert_no_overlap(f->ps, o.gap);
    assert_inside(f->ps, 0, o.box_min, o.box_max, o.gap);
}

static double phi(double z)
{
    return exp(-0.5 * z * z) / sqrt(2.0 * PI);
}

/* Mean and standard deviation of normal(mu, sigma) truncated to [lo, hi]. */
static void truncated_normal(double mu, double sigma, double lo, double hi, double *mean,
                             double *std)
{
    const double a = (lo - mu) / sigma, b = (hi - mu) / sigma;
    const double z = 0.5 * (erf(b / sqrt(2.0)) - erf(a / sqrt(2.0)));
    const double shift = (phi(a) - phi(b)) / z;
    *mean = mu + sigma * shift;
    *std = sigma * sqrt(1.0 + (a * phi(a) - b * phi(b)) / z - shift * shift);
}

static void check_normal(const fixture *f, double lo_option, double hi_option, double lo, double hi)
{
    sinter_particles *ps;
    sinter_packing_options o = options_in_box(0.0, 1.0);
    o.distribution = SINTER_RADII_NORMAL;
    o.radius_mean = 0.01;
    o.radius_spread = 0.002;
    o.radius_min = lo_option;
    o.radius_max = hi_option;
    o.seed = 7;
    pack_into_new_set(f, &o, SAMPLE, &ps);
    assert_radii_within(ps, lo, hi);
    double mean, std, want_mean, want_std;
    sample_moments(ps, &mean, &std);
    truncated_normal(o.radius_mean, o.radius_spread, lo, hi, &want_mean, &want_std);
    /*
     * Mean: 4 standard errors sigma_t / sqrt(n). Standard deviation: its
     * standard error is about sigma_t / sqrt(2 n) for a near-normal sample
     * (truncation lowers the kurtosis, which only shrinks it); 4 of those.
     */
    assert_close(mean, want_mean, 4.0 * want_std / sqrt((double)SAMPLE));
    assert_close(std, want_std, 4.0 * want_std / sqrt(2.0 * SAMPLE));
    assert_no_overlap(ps, 0.0);
    sinter_particles_destroy(ps);
}

static void test_random_normal_radii(void **state)
{
    const fixture *f = *state;
    check_normal(f, 0.0, 0.0, 0.004, 0.016);     /* defaults: mean -+ 3 spread */
    check_normal(f, 0.009, 0.013, 0.009, 0.013); /* asymmetric truncation */
}

static void test_random_overfull_box(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(0.0, 0.5);
    o.max_attempts = 1000;
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(f->ps, &o, 100000, &placed), SINTER_OK);
    assert_true(placed > 0 && placed < 100000);
    assert_int_equal(count_of(f->ps), placed);
    assert_no_overlap(f->ps, 0.0);
    assert_inside(f->ps, 0, o.box_min, o.box_max, 0.0);
}

/* Spheres already in the set (inside the box and just outside it) are avoided. */
static void test_random_avoids_existing_particles(void **state)
{
    fixture *f = *state;
    const double x[3 * 4] = {0.5, 0.5, 0.5, 1.03, 0.5, 0.5, 0.2, -0.01, 0.3, 5.0, 5.0, 5.0};
    const double r[4] = {0.3, 0.06, 0.04, 1.0};
    assert_int_equal(sinter_particles_add(f->ps, 4, x, r, 0, 300.0, NULL), SINTER_OK);
    sinter_packing_options o = options_in_box(0.0, 1.0);
    o.distribution = SINTER_RADII_UNIFORM;
    o.radius_mean = 0.03;
    o.radius_spread = 0.01;
    o.gap = 0.002;
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(f->ps, &o, 800, &placed), SINTER_OK);
    assert_int_equal(placed, 800);
    assert_int_equal(count_of(f->ps), 804);
    assert_no_overlap(f->ps, o.gap);
    assert_inside(f->ps, 4, o.box_min, o.box_max, o.gap);
}

static void test_random_rejects_bad_options(void **state)
{
    fixture *f = *state;
    typedef struct bad_case {
        const char *field;
        sinter_status status;
        const char *word;
    } bad_case;
    static const bad_case cases[] = {
        {"box_max", SINTER_ERR_INVALID, "box_max[1]"},
        {"box_nan", SINTER_ERR_INVALID, "box_max[0]"},
        {"mean_zero", SINTER_ERR_INVALID, "radius_mean"},
        {"mean_nan", SINTER_ERR_INVALID, "radius_mean"},
        {"spread_negative", SINTER_ERR_INVALID, "radius_spread"},
        {"uniform_spread", SINTER_ERR_INVALID, "radius_spread"},
        {"normal_min", SINTER_ERR_INVALID, "radius_min"},
        {"normal_max", SINTER_ERR_INVALID, "radius_max"},
        {"normal_narrow", SINTER_ERR_INVALID, "radius_min"},
        {"gap", SINTER_ERR_INVALID, "gap"},
        {"gap_inf", SINTER_ERR_INVALID, "gap"},
        {"distribution", SINTER_ERR_INVALID, "distribution"},
        {"max_attempts", SINTER_ERR_INVALID, "max_attempts"},
        {"material", SINTER_ERR_NOT_FOUND, "material 3"},
        {"temperature", SINTER_ERR_INVALID, "temperature"},
        {"too_small", SINTER_ERR_INVALID, "wide along y"},
        {"struct_size", SINTER_ERR_STRUCT_SIZE, "struct_size"},
    };
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); ++k) {
        sinter_packing_options o = options_in_box(0.0, 1.0);
        const char *c = cases[k].field;
        if (!strcmp(c, "box_max"))
            o.box_max[1] = 0.0;
        else if (!strcmp(c, "box_nan"))
            o.box_min[0] = NAN;
        else if (!strcmp(c, "mean_zero"))
            o.radius_mean = 0.0;
        else if (!strcmp(c, "mean_nan"))
            o.radius_mean = NAN;
        else if (!strcmp(c, "spread_negative"))
            o.radius_spread = -0.01;
        else if (!strcmp(c, "uniform_spread")) {
            o.distribution = SINTER_RADII_UNIFORM;
            o.radius_spread = o.radius_mean;
        } else if (!strcmp(c, "normal_min")) {
            o.distribution = SINTER_RADII_NORMAL;
            o.radius_spread = 0.01;
            o.radius_min = 0.06;
        } else if (!strcmp(c, "normal_max")) {
            o.distribution = SINTER_RADII_NORMAL;
            o.radius_spread = 0.01;
            o.radius_max = 0.04;
        } else if (!strcmp(c, "normal_narrow")) {
            o.distribution = SINTER_RADII_NORMAL;
            o.radius_spread = 0.01;
            o.radius_min = o.radius_max = o.radius_mean;
        } else if (!strcmp(c, "gap"))
            o.gap = -1e-3;
        else if (!strcmp(c, "gap_inf"))
            o.gap = INFINITY;
        else if (!strcmp(c, "distribution"))
            o.distribution = 7;
        else if (!strcmp(c, "max_attempts"))
            o.max_attempts = 0;
        else if (!strcmp(c, "material"))
            o.material = 3;
        else if (!strcmp(c, "temperature"))
            o.temperature = 0.0;
        else if (!strcmp(c, "too_small"))
            o.box_max[1] = 0.09; /* 0.09 m < 2 r = 0.1 m */
        else if (!strcmp(c, "struct_size"))
            o.struct_size = 8;
        size_t placed = 99;
        expect_error(f, sinter_pack_random(f->ps, &o, 10, &placed), cases[k].status, cases[k].word);
        assert_int_equal(placed, 0);
        assert_int_equal(count_of(f->ps), 0);
    }
    sinter_packing_options o = options_in_box(0.0, 1.0);
    expect_error(f, sinter_pack_random(f->ps, &o, SIZE_MAX, NULL), SINTER_ERR_OVERFLOW, "overflow");
    expect_error(f, sinter_pack_random(f->ps, NULL, 10, NULL), SINTER_ERR_NULL, "options");
    assert_int_equal(sinter_pack_random(NULL, &o, 10, NULL), SINTER_ERR_NULL);
    size_t placed = 99;
    assert_int_equal(sinter_pack_random(f->ps, &o, 0, &placed), SINTER_OK);
    assert_int_equal(placed, 0);
    assert_int_equal(count_of(f->ps), 0);
}

static void test_views_make_packing_busy(void **state)
{
    fixture *f = *state;
    sinter_packing_options o = options_in_box(0.0, 1.0);
    void *data = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_VELOCITY, &data, NULL, NULL),
                     SINTER_OK);
    expect_error(f, sinter_pack_random(f->ps, &o, 10, NULL), SINTER_ERR_BUSY, "view");
    expect_error(f, sinter_pack_lattice(f->ps, o.box_min, o.box_max, 0.1, 0.2, 0, 300.0, NULL),
                 SINTER_ERR_BUSY, "view");
    assert_int_equal(count_of(f->ps), 0);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_VELOCITY), SINTER_OK);
    assert_int_equal(sinter_pack_random(f->ps, &o, 10, NULL), SINTER_OK);
    assert_int_equal(count_of(f->ps), 10);
}

/* Every allocation may fail: the set is then unchanged and nothing leaks. */
static void test_allocation_failure_injection(void **state)
{
    (void)state;
    int failures_seen = 0;
    for (long k = 0; k < 200; ++k) {
        counting_allocator c = {0, 0, -1, 0};
        sinter_allocator hook = counting_allocator_hook(&c);
        sinter_ctx *ctx;
        sinter_material *m;
        sinter_particles *ps;
        assert_int_equal(sinter_ctx_create(&ctx, &hook), SINTER_OK);
        assert_int_equal(sinter_material_create(&m, ctx, NULL), SINTER_OK);
        assert_int_equal(sinter_particles_create(&ps, ctx), SINTER_OK);
        assert_int_equal(sinter_particles_set_material(ps, 0, m), SINTER_OK);
        const double x[3] = {0.5, 0.5, 0.5}, r = 0.1;
        assert_int_equal(sinter_particles_add(ps, 1, x, &r, 0, 300.0, NULL), SINTER_OK);
        sinter_packing_options o = options_in_box(0.0, 1.0);
        o.radius_mean = 0.01;
        c.fail_after = k; /* k more allocations succeed */
        size_t placed = 0;
        const sinter_status st = sinter_pack_random(ps, &o, 2500, &placed);
        c.fail_after = -1;
        assert_int_equal(count_of(ps), st == SINTER_OK ? 2501 : 1);
        if (st != SINTER_OK) {
            assert_int_equal(st, SINTER_ERR_NOMEM);
            failures_seen++;
        }
        sinter_particles_destroy(ps);
        sinter_material_destroy(m);
        sinter_ctx_destroy(ctx);
        assert_int_equal(c.allocations, c.frees);
        if (st == SINTER_OK)
            break;
    }
    assert_true(failures_seen >= 5);
}


/* ---- triaxial compaction (sinter_pack_compact) --------------------------------------------- */

/*
 * The compaction tests use copper spheres of the seed 001 sec. 4.1 size (r = 25 um +- 10 %,
 * uniform) in boxes a few diameters wide: N = 100 spheres keep each run near 1 s in a Debug
 * build. Tolerances:
 *  - overlaps below 1 % of the radius: the automatic step is made for contacts up to that
 *    overlap (seed 003 eq. 47 at the impact speed giving it), and the stress limit of the
 *    walls aims at a mean overlap of 1e-3 r, so the largest of a few hundred contacts (a few
 *    times the mean) must stay below 1e-2; the quasi-static stepper then starts its links from
 *    touching spheres (docs/7dof.md sec. 4) with a centre approach of at most 0.5 % of a diameter.
 *  - "inside the box": centre - r >= box_min - (largest wall overlap), likewise at box_max.
 *  - the final box is the requested one exactly (the walls' points are the requested planes
 *    and their last displacement is exactly 0).
 */
#define COMPACT_N 100
#define COPPER_R 25e-6

typedef struct compact_fixture {
    sinter_ctx *ctx;
    sinter_material *copper;
} compact_fixture;

static int compact_setup(void **state)
{
    static compact_fixture f;
    memset(&f, 0, sizeof(f));
    if (sinter_ctx_create(&f.ctx, NULL) != SINTER_OK ||
        sinter_material_create(&f.copper, f.ctx, "copper") != SINTER_OK ||
        sinter_material_set(f.copper, SINTER_MAT_DENSITY, 8960.0) != SINTER_OK ||
        sinter_material_set(f.copper, SINTER_MAT_YOUNGS_MODULUS, 72e9) != SINTER_OK ||
        sinter_material_set(f.copper, SINTER_MAT_POISSON_RATIO, 0.3) != SINTER_OK)
        return -1;
    *state = &f;
    return 0;
}

static int compact_teardown(void **state)
{
    compact_fixture *f = *state;
    sinter_material_destroy(f->copper);
    sinter_ctx_destroy(f->ctx);
    return 0;
}

/* COMPACT_N copper spheres by random sequential addition in [0, side]^3. */
static sinter_particles *loose_copper(const compact_fixture *f, double side, uint64_t seed)
{
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_particles_create(&ps, f->ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(ps, 0, f->copper), SINTER_OK);
    sinter_packing_options o = options_in_box(0.0, side);
    o.distribution = SINTER_RADII_UNIFORM;
    o.radius_mean = COPPER_R;
    o.radius_spread = 0.1 * COPPER_R;
    o.seed = seed;
    size_t placed = 0;
    assert_int_equal(sinter_pack_random(ps, &o, COMPACT_N, &placed), SINTER_OK);
    assert_int_equal(placed, COMPACT_N);
    return ps;
}

static double sphere_volume(const sinter_particles *ps)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    double v = 0.0;
    for (size_t i = 0; i < n; ++i)
        v += 4.0 / 3.0 * PI * r[i] * r[i] * r[i];
    release_xr(ps);
    return v;
}

static void expect_ctx_error(sinter_ctx *ctx, sinter_status got, sinter_status want,
                             const char *word)
{
    assert_int_equal(got, want);
    assert_int_equal(sinter_last_status(ctx), want);
    if (strstr(sinter_last_error(ctx), word) == NULL) {
        print_error("message \"%s\" does not name \"%s\"\n", sinter_last_error(ctx), word);
        fail();
    }
}

static sinter_compaction_options compaction_in_box(double lo, double hi)
{
    sinter_compaction_options o;
    assert_int_equal(sinter_compaction_options_init(&o, sizeof(o)), SINTER_OK);
    for (int d = 0; d < 3; ++d) {
        o.box_min[d] = lo;
        o.box_max[d] = hi;
    }
    o.velocity = 1.0;
    return o;
}

/* Largest overlap / smaller radius and contact count, recomputed from the positions. */
static double overlaps_of(const sinter_particles *ps, uint64_t *contacts)
{
    const double *x, *r;
    const size_t n = view_xr(ps, &x, &r);
    double worst = 0.0;
    *contacts = 0;
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) {
            const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1],
                         dz = x[3 * i + 2] - x[3 * j + 2];
            const double delta = r[i] + r[j] - sqrt(dx * dx + dy * dy + dz * dz);
            if (delta > 0.0) {
                (*contacts)++;
                worst = fmax(worst, delta / fmin(r[i], r[j]));
            }
        }
    release_xr(ps);
    return worst;
}

/* The state after a successful compaction: at rest, inside the box, overlaps bounded. */
static void assert_compacted(const sinter_particles *ps, const sinter_compaction_result *res)
{
    const double *x, *r, *v, *w;
    const size_t n = view_xr(ps, &x, &r);
    assert_int_equal(sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v,
                                                NULL, NULL),
                     SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_SPIN, (const void **)&w, NULL, NULL),
        SINTER_OK);
    for (size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
            assert_true(v[3 * i + d] == 0.0 && w[3 * i + d] == 0.0); /* zeroed at the end */
            const double slack = res->max_wall_overlap_ratio * r[i] * (1.0 + 1e-9);
            assert_true(x[3 * i + d] - r[i] >= res->box_min[d] - slack);
            assert_true(x[3 * i + d] + r[i] <= res->box_max[d] + slack);
        }
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_VELOCITY), SINTER_OK);
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_SPIN), SINTER_OK);
    release_xr(ps);
    assert_true(res->max_wall_overlap_ratio < 0.01);
    assert_true(res->max_overlap_ratio < 0.01);
    uint64_t contacts = 0;
    const double worst = overlaps_of(ps, &contacts);
    /* The same pairs and overlaps as the stepper's contact list (to round-off). */
    assert_int_equal(contacts, res->contacts);
    assert_close(worst, res->max_overlap_ratio, 1e-9);
    assert_close(res->coordination, 2.0 * (double)contacts / (double)n, 1e-12);
    /* Static: the default threshold is 1e-9 (1/2) m v^2 at the step's impact speed (~4 m/s
     * for copper), i.e. an rms speed below 1.3e-4 m/s: 4.7e-18 J for these spheres. */
    assert_true(res->kinetic_energy >= 0.0 && res->kinetic_energy < 5e-18);
    assert_true(res->steps > 0 && res->dt > 0.0 && res->time > 0.0);
    assert_close(res->time, (double)res->steps * res->dt, 1e-9 * res->time);
}

static void test_compaction_options_init(void **state)
{
    (void)state;
    sinter_compaction_options o;
    memset(&o, 0xff, sizeof(o));
    assert_int_equal(sinter_compaction_options_init(&o, sizeof(o)), SINTER_OK);
    assert_int_equal(o.struct_size, sizeof(o));
    assert_close(o.box_max[2], 1.0, 0.0);
    assert_close(o.volume_fraction, 0.0, 0.0);
    assert_close(o.friction, 0.1, 0.0);
    assert_close(o.restitution, 0.5, 0.0);
    assert_close(o.velocity, 0.5, 0.0);
    assert_int_equal(o.stop_at_jamming, 0);
    assert_close(o.dt, 0.0, 0.0);
    assert_int_equal(sinter_compaction_options_init(&o, sizeof(o) - 8), SINTER_ERR_STRUCT_SIZE);
    assert_int_equal(sinter_compaction_options_init(NULL, sizeof(o)), SINTER_ERR_NULL);
}

/*
 * A box below the jamming density (phi = 0.50 < ~0.56 for friction 0.1) is reached exactly;
 * the same input gives the same packing bit for bit.
 */
static void test_compaction_reaches_box(void **state)
{
    compact_fixture *f = *state;
    sinter_particles *a = loose_copper(f, 20.0 * COPPER_R, 7);
    sinter_particles *b = loose_copper(f, 20.0 * COPPER_R, 7);
    const double solid = sphere_volume(a);
    const double side = cbrt(solid / 0.5);
    sinter_compaction_options o = compaction_in_box(0.0, side);
    o.box_max[2] = 0.8 * side; /* not a cube, like the seed's 0.5 x 0.5 x 0.4 mm */
    o.box_max[0] = side / 0.8;
    sinter_compaction_result ra, rb;
    ra.struct_size = rb.struct_size = sizeof(ra);
    assert_int_equal(sinter_pack_compact(a, &o, &ra), SINTER_OK);
    for (int d = 0; d < 3; ++d) {
        assert_true(ra.box_min[d] == o.box_min[d]); /* exactly the requested planes */
        assert_true(ra.box_max[d] == o.box_max[d]);
    }
    assert_int_equal(ra.jammed, 0);
    assert_close(ra.volume_fraction, 0.5, 1e-12);
    assert_compacted(a, &ra);
    /* Below jamming the walls carry (almost) nothing: less than 1 % of the servo's limit. */
    assert_true(ra.pressure < 0.01 * 3.4e5);
    /* Reproducible: the same set and options, the same bits. */
    assert_int_equal(sinter_pack_compact(b, &o, &rb), SINTER_OK);
    assert_true(same_bits(a, b));
    assert_memory_equal(&ra, &rb, sizeof(ra));
    sinter_particles_destroy(a);
    sinter_particles_destroy(b);
}

/*
 * Compaction to jamming: the walls advance until the packing carries the stress limit and
 * stop there (stop_at_jamming), keeping box_min and the box's proportions. A jammed packing
 * of frictional spheres has the isostatic coordination 4 among its load-bearing spheres
 * (rattlers and the wall layer lower the mean), so 2 C / N > 3.5 (4.4 in the 805-sphere
 * copper packing); without stop_at_jamming the same run is an error that leaves the set as
 * it was.
 */
static void test_compaction_to_jamming(void **state)
{
    compact_fixture *f = *state;
    sinter_particles *ps = loose_copper(f, 20.0 * COPPER_R, 11);
    const double *x0, *r0;
    const size_t n = view_xr(ps, &x0, &r0);
    double *before = malloc(3 * n * sizeof(double));
    assert_non_null(before);
    memcpy(before, x0, 3 * n * sizeof(double));
    release_xr(ps);
    sinter_compaction_options o = compaction_in_box(0.0, 10.0 * COPPER_R);
    o.box_min[0] = 1e-4; /* lower corner kept where it is asked to be */
    o.box_max[0] = 1e-4 + 10.0 * COPPER_R;
    o.volume_fraction = 0.7; /* beyond any jamming density */
    expect_ctx_error(f->ctx, sinter_pack_compact(ps, &o, NULL),
                 SINTER_ERR_NOT_CONVERGED, "jammed at volume fraction");
    const double *x1, *r1;
    view_xr(ps, &x1, &r1);
    assert_memory_equal(before, x1, 3 * n * sizeof(double)); /* unchanged */
    release_xr(ps);
    o.stop_at_jamming = 1;
    sinter_compaction_result res;
    res.struct_size = sizeof(res);
    assert_int_equal(sinter_pack_compact(ps, &o, &res), SINTER_OK);
    assert_int_equal(res.jammed, 1);
    assert_compacted(ps, &res);
    /* The box: lower corner as asked; on the way from the spheres' box (the RSA cube, up to a
     * gap of a fraction of a radius) to the requested cube, so a cube to 1 %. */
    for (int d = 0; d < 3; ++d)
        assert_true(res.box_min[d] == o.box_min[d]);
    const double w[3] = {res.box_max[0] - res.box_min[0], res.box_max[1] - res.box_min[1],
                         res.box_max[2] - res.box_min[2]};
    assert_close(w[1], w[0], 0.01 * w[0]);
    assert_close(w[2], w[0], 0.01 * w[0]);
    assert_true(res.volume_fraction > 0.5 && res.volume_fraction < 0.7);
    assert_close(res.volume_fraction, sphere_volume(ps) / (w[0] * w[1] * w[2]), 1e-9);
    assert_true(res.coordination > 3.5);
    /* Nearly stress-free: the walls stopped once the stress reached the limit (3.4e5 Pa for
     * copper spheres of 25 um: Hertz contacts at a mean overlap of 1e-3 r), and the
     * relaxation only lowers it; a jammed packing carries some of it (> 1 %). */
    assert_true(res.pressure > 0.01 * 3.4e5 && res.pressure < 1.05 * 3.4e5);
    free(before);
    sinter_particles_destroy(ps);
}

/* A volume fraction below jamming is reached: the box scaled about box_min. */
static void test_compaction_reaches_fraction(void **state)
{
    compact_fixture *f = *state;
    sinter_particles *ps = loose_copper(f, 20.0 * COPPER_R, 3);
    sinter_compaction_options o = compaction_in_box(0.0, 1.0);
    o.box_max[2] = 2.0; /* proportions 1:1:2, like the seed's titanium packing */
    o.volume_fraction = 0.45;
    o.friction = 0.0;
    sinter_compaction_result res;
    res.struct_size = sizeof(res);
    assert_int_equal(sinter_pack_compact(ps, &o, &res), SINTER_OK);
    assert_close(res.volume_fraction, 0.45, 1e-12);
    const double w = res.box_max[0];
    assert_close(res.box_max[1], w, 0.0);
    assert_close(res.box_max[2], 2.0 * w, 1e-15 * w);
    assert_close(sphere_volume(ps) / (2.0 * w * w * w), 0.45, 1e-12);
    assert_compacted(ps, &res);
    sinter_particles_destroy(ps);
}

static void test_compaction_rejects_bad_input(void **state)
{
    compact_fixture *f = *state;
    sinter_particles *ps = loose_copper(f, 20.0 * COPPER_R, 5);
    const double *x0, *r0;
    const size_t n = view_xr(ps, &x0, &r0);
    double *before = malloc(3 * n * sizeof(double));
    assert_non_null(before);
    memcpy(before, x0, 3 * n * sizeof(double));
    release_xr(ps);
    typedef struct bad_case {
        const char *field;
        sinter_status status;
        const char *word;
    } bad_case;
    static const bad_case cases[] = {
        {"box_flat", SINTER_ERR_INVALID, "box_max[1]"},
        {"box_nan", SINTER_ERR_INVALID, "box_max[2]"},
        {"box_inf", SINTER_ERR_INVALID, "box_max[0]"},
        {"box_narrow", SINTER_ERR_INVALID, "wide along y"},
        {"box_dense", SINTER_ERR_INVALID, "densest sphere packing"},
        {"fraction_high", SINTER_ERR_INVALID, "volume_fraction = 0.75"},
        {"fraction_negative", SINTER_ERR_INVALID, "volume_fraction = -0.1"},
        {"friction", SINTER_ERR_INVALID, "friction = -1"},
        {"restitution_zero", SINTER_ERR_INVALID, "restitution = 0"},
        {"restitution_high", SINTER_ERR_INVALID, "restitution = 1.5"},
        {"velocity", SINTER_ERR_INVALID, "velocity = 0"},
        {"velocity_nan", SINTER_ERR_INVALID, "velocity = nan"},
        {"velocity_tiny", SINTER_ERR_INVALID, "more than 1e9"},
        {"pressure", SINTER_ERR_INVALID, "max_pressure = -1"},
        {"jamming", SINTER_ERR_INVALID, "stop_at_jamming = 2"},
        {"ke", SINTER_ERR_INVALID, "ke_per_particle = inf"},
        {"relax", SINTER_ERR_INVALID, "relax_time_max = -1"},
        {"dt", SINTER_ERR_INVALID, "dt = nan"},
        {"struct_size", SINTER_ERR_STRUCT_SIZE, "options.struct_size"},
    };
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); ++k) {
        sinter_compaction_options o = compaction_in_box(0.0, 12.0 * COPPER_R);
        const char *c = cases[k].field;
        if (!strcmp(c, "box_flat"))
            o.box_max[1] = 0.0;
        else if (!strcmp(c, "box_nan"))
            o.box_max[2] = NAN;
        else if (!strcmp(c, "box_inf"))
            o.box_max[0] = INFINITY;
        else if (!strcmp(c, "box_narrow"))
            o.box_max[1] = 1.5 * COPPER_R;
        else if (!strcmp(c, "box_dense"))
            o.box_max[0] = o.box_max[1] = o.box_max[2] = 6.0 * COPPER_R;
        else if (!strcmp(c, "fraction_high"))
            o.volume_fraction = 0.75;
        else if (!strcmp(c, "fraction_negative"))
            o.volume_fraction = -0.1;
        else if (!strcmp(c, "friction"))
            o.friction = -1.0;
        else if (!strcmp(c, "restitution_zero"))
            o.restitution = 0.0;
        else if (!strcmp(c, "restitution_high"))
            o.restitution = 1.5;
        else if (!strcmp(c, "velocity"))
            o.velocity = 0.0;
        else if (!strcmp(c, "velocity_nan"))
            o.velocity = NAN;
        else if (!strcmp(c, "velocity_tiny"))
            o.velocity = 1e-12;
        else if (!strcmp(c, "pressure"))
            o.max_pressure = -1.0;
        else if (!strcmp(c, "jamming"))
            o.stop_at_jamming = 2;
        else if (!strcmp(c, "ke"))
            o.ke_per_particle = INFINITY;
        else if (!strcmp(c, "relax"))
            o.relax_time_max = -1.0;
        else if (!strcmp(c, "dt"))
            o.dt = NAN;
        else if (!strcmp(c, "struct_size"))
            o.struct_size = 8;
        sinter_compaction_result res;
        res.struct_size = sizeof(res);
        expect_ctx_error(f->ctx, sinter_pack_compact(ps, &o, &res), cases[k].status, cases[k].word);
    }
    sinter_compaction_options o = compaction_in_box(0.0, 12.0 * COPPER_R);
    sinter_compaction_result res;
    res.struct_size = 4;
    expect_ctx_error(f->ctx, sinter_pack_compact(ps, &o, &res), SINTER_ERR_STRUCT_SIZE, "result.struct_size");
    expect_ctx_error(f->ctx, sinter_pack_compact(ps, NULL, NULL), SINTER_ERR_NULL, "options");
    assert_int_equal(sinter_pack_compact(NULL, &o, NULL), SINTER_ERR_NULL);
    /* A view out: busy. */
    void *data = NULL;
    assert_int_equal(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, &data, NULL, NULL),
                     SINTER_OK);
    expect_ctx_error(f->ctx, sinter_pack_compact(ps, &o, NULL), SINTER_ERR_BUSY, "view");
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_VELOCITY), SINTER_OK);
    /* Nothing moved. */
    const double *x1, *r1;
    view_xr(ps, &x1, &r1);
    assert_memory_equal(before, x1, 3 * n * sizeof(double));
    release_xr(ps);
    /* An empty set. */
    sinter_particles *empty = NULL;
    assert_int_equal(sinter_particles_create(&empty, f->ctx), SINTER_OK);
    expect_ctx_error(f->ctx, sinter_pack_compact(empty, &o, NULL), SINTER_ERR_STATE, "empty");
    sinter_particles_destroy(empty);
    free(before);
    sinter_particles_destroy(ps);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_options_init),
        cmocka_unit_test_setup_teardown(test_lattice_exact, setup, teardown),
        cmocka_unit_test_setup_teardown(test_lattice_rejects_bad_arguments, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_press_scene, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_is_deterministic, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_golden_values, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_uniform_radii, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_normal_radii, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_overfull_box, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_avoids_existing_particles, setup, teardown),
        cmocka_unit_test_setup_teardown(test_random_rejects_bad_options, setup, teardown),
        cmocka_unit_test_setup_teardown(test_views_make_packing_busy, setup, teardown),
        cmocka_unit_test(test_allocation_failure_injection),
        cmocka_unit_test(test_compaction_options_init),
        cmocka_unit_test_setup_teardown(test_compaction_reaches_box, compact_setup,
                                        compact_teardown),
        cmocka_unit_test_setup_teardown(test_compaction_to_jamming, compact_setup,
                                        compact_teardown),
        cmocka_unit_test_setup_teardown(test_compaction_reaches_fraction, compact_setup,
                                        compact_teardown),
        cmocka_unit_test_setup_teardown(test_compaction_rejects_bad_input, compact_setup,
                                        compact_teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
