/*
 * Powder size distributions (issue 38): the log-normal sampler against its parameters, a
 * tabulated volume distribution converted to numbers against the Hatch-Choate closed form,
 * a table's volume-weighted D50 recovered, mixtures by mass fraction, the CSV reader's
 * refusals with their lines, the older options layout, and the scene keys.
 *
 * Statistical tolerances are 4 standard errors of the estimate for the sample size (a false
 * failure once in ~16000 runs for one check; the seeds are fixed, so a run is reproducible).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "particles/packing.h"
#include "test_support.h"

#define N_SAMPLES 20000

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_material *mat[3];
    sinter_particles *ps;
} fixture;

static int setup(void **state)
{
    static fixture f;
    static const double density[3] = {8960.0, 2700.0, 4500.0};
    memset(&f, 0, sizeof(f));
    if (sinter_ctx_create(&f.ctx, NULL) != SINTER_OK ||
        sinter_particles_create(&f.ps, f.ctx) != SINTER_OK)
        return -1;
    for (int k = 0; k < 3; ++k)
        if (sinter_material_create(&f.mat[k], f.ctx, "m") != SINTER_OK ||
            sinter_material_set(f.mat[k], SINTER_MAT_DENSITY, density[k]) != SINTER_OK ||
            sinter_particles_set_material(f.ps, k, f.mat[k]) != SINTER_OK)
            return -1;
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sinter_particles_destroy(f->ps);
    for (int k = 0; k < 3; ++k)
        sinter_material_destroy(f->mat[k]);
    sinter_ctx_destroy(f->ctx);
    return 0;
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Mean, standard deviation and median of ln x[0..n-1] (x is sorted on return). */
static void log_moments(double *x, size_t n, double *mean, double *sd, double *median)
{
    double s = 0.0, s2 = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += log(x[i]);
    *mean = s / (double)n;
    for (size_t i = 0; i < n; ++i)
        s2 += (log(x[i]) - *mean) * (log(x[i]) - *mean);
    *sd = sqrt(s2 / (double)(n - 1));
    qsort(x, n, sizeof(double), compare_double);
    *median = 0.5 * (log(x[n / 2 - 1]) + log(x[n / 2]));
}

/*
 * Log-normal by median and geometric standard deviation: for N radii, ln r has mean ln r50
 * (standard error sigma / sqrt N), median ln r50 (sigma sqrt(pi / 2) / sqrt N) and standard
 * deviation sigma = ln gsd (sigma / sqrt(2 N)); each within 4 standard errors. The truncation
 * is put at 6 sigma so that its bias (< 1e-7 sigma) is far below them.
 */
static void test_lognormal_sampler(void **state)
{
    fixture *f = *state;
    const double median = 10e-6, gsd = 1.6, sigma = log(gsd);
    sinter_packing_options o;
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    o.distribution = SINTER_RADII_LOGNORMAL;
    o.radius_median = median;
    o.radius_gsd = gsd;
    o.radius_min = median * exp(-6.0 * sigma);
    o.radius_max = median * exp(6.0 * sigma);
    o.seed = 38;
    double *r = malloc(N_SAMPLES * sizeof(double));
    assert_non_null(r);
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, N_SAMPLES, r), SINTER_OK);
    double mean, sd, med;
    log_moments(r, N_SAMPLES, &mean, &sd, &med);
    const double n = N_SAMPLES;
    assert_true(fabs(mean - log(median)) < 4.0 * sigma / sqrt(n));
    assert_true(fabs(med - log(median)) < 4.0 * sigma * sqrt(acos(-1.0) / 2.0) / sqrt(n));
    assert_true(fabs(sd - sigma) < 4.0 * sigma / sqrt(2.0 * n));
    /* the default truncation: 3 geometric standard deviations either side */
    o.radius_min = o.radius_max = 0.0;
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, N_SAMPLES, r), SINTER_OK);
    for (size_t i = 0; i < N_SAMPLES; ++i)
        assert_true(r[i] >= median / pow(gsd, 3.0) * (1 - 1e-12) &&
                    r[i] <= median * pow(gsd, 3.0) * (1 + 1e-12));
    /* gsd = 1: every radius is the median */
    o.radius_gsd = 1.0;
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, 10, r), SINTER_OK);
    assert_true(r[0] == median && r[9] == median);
    o.radius_gsd = 0.5;
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, 10, r), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f->ctx), "radius_gsd"));
    free(r);
}

static double normal_cdf(double z)
{
    return 0.5 * erfc(-z / sqrt(2.0));
}

/*
 * Number / volume conversion against a closed form (Hatch and Choate 1929): the volume
 * distribution of a log-normal number distribution (count median d0, sigma) is log-normal
 * with the same sigma and the median d3 = d0 exp(3 sigma^2). A table of that volume CDF
 * (400 rows over +-5 sigma) sampled by the table sampler must give numbers with median
 * ln d0 and standard deviation sigma, within 4 standard errors plus the table's
 * interpolation error, allowed 0.005 sigma (a piecewise-linear CDF on a grid of h = 0.025 sigma
 * is off by about h^2 / 8 max |Phi''| < 2e-5 in probability, some 1e-4 sigma in a quantile:
 * the allowance is generous, the 4 standard errors dominate). The same table read by number
 * gives the volume median's numbers instead.
 */
static void test_volume_table_hatch_choate(void **state)
{
    fixture *f = *state;
    const double d0 = 20e-6, sigma = log(1.5), d3 = d0 * exp(3.0 * sigma * sigma);
    enum { ROWS = 400 };
    double d[ROWS], q[ROWS];
    for (int i = 0; i < ROWS; ++i) {
        const double z = -5.0 + 10.0 * i / (ROWS - 1);
        d[i] = d3 * exp(z * sigma);
        q[i] = normal_cdf(z);
    }
    sinter_packing_options o;
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    o.distribution = SINTER_RADII_TABLE;
    o.table_diameter = d;
    o.table_cumulative = q;
    o.table_points = ROWS;
    o.table_basis = SINTER_SIZE_BY_VOLUME;
    o.seed = 1929;
    double *r = malloc(N_SAMPLES * sizeof(double));
    assert_non_null(r);
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, N_SAMPLES, r), SINTER_OK);
    for (size_t i = 0; i < N_SAMPLES; ++i)
        r[i] *= 2.0; /* diameters */
    double mean, sd, med;
    const double n = N_SAMPLES, table = 0.005 * sigma;
    log_moments(r, N_SAMPLES, &mean, &sd, &med);
    assert_true(fabs(mean - log(d0)) < 4.0 * sigma / sqrt(n) + table);
    assert_true(fabs(med - log(d0)) < 4.0 * sigma * sqrt(acos(-1.0) / 2.0) / sqrt(n) + table);
    assert_true(fabs(sd - sigma) < 4.0 * sigma / sqrt(2.0 * n) + table);
    /* the shift is really there: 3 sigma^2 = 0.49 in ln d, some 170 standard errors */
    assert_true(log(d3) - med > 0.4);
    /* by number, the same table is sampled as it stands: median d3 */
    o.table_basis = SINTER_SIZE_BY_NUMBER;
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, N_SAMPLES, r), SINTER_OK);
    for (size_t i = 0; i < N_SAMPLES; ++i)
        r[i] *= 2.0;
    log_moments(r, N_SAMPLES, &mean, &sd, &med);
    assert_true(fabs(med - log(d3)) < 4.0 * sigma * sqrt(acos(-1.0) / 2.0) / sqrt(n) + table);
    free(r);
}

/*
 * A laser-diffraction-like table by volume (micrometres, percent): its volume-weighted D50 is
 * 30 + 30 (50 - 30) / (80 - 30) = 42 um. The particles are added to a set (no placement) and
 * sinter_particles_size_quantiles must recover it within 4 standard errors of a weighted
 * quantile: se = sqrt(sum w_i^2 (1[d_i <= D50] - 1/2)^2) / sum w_i / q3(D50), w = d^3,
 * q3 = 0.5 / 30 um the volume density there (delta method for an estimating equation).
 */
static void test_volume_table_d50(void **state)
{
    fixture *f = *state;
    const double d[5] = {10e-6, 20e-6, 30e-6, 60e-6, 100e-6}, q[5] = {0.0, 0.1, 0.3, 0.8, 1.0};
    sinter_packing_options o;
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    o.distribution = SINTER_RADII_TABLE;
    o.table_diameter = d;
    o.table_cumulative = q;
    o.table_points = 5;
    o.seed = 7;
    double *r = malloc(N_SAMPLES * sizeof(double)), *x = calloc(3 * N_SAMPLES, sizeof(double));
    assert_non_null(r);
    assert_non_null(x);
    assert_int_equal(sinter_packing_sample_radii(f->ps, &o, N_SAMPLES, r), SINTER_OK);
    for (size_t i = 0; i < N_SAMPLES; ++i) {
        assert_true(2.0 * r[i] >= d[0] && 2.0 * r[i] <= d[4]);
        x[3 * i] = 1e-3 * (double)i;
    }
    assert_int_equal(sinter_particles_add(f->ps, N_SAMPLES, x, r, 0, 300.0, NULL), SINTER_OK);
    const double fr[3] = {0.1, 0.5, 0.9};
    double dv[3], dn[3];
    assert_int_equal(
        sinter_particles_size_quantiles(f->ps, 0, N_SAMPLES, SINTER_SIZE_BY_VOLUME, 3, fr, dv),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_size_quantiles(f->ps, 0, N_SAMPLES, SINTER_SIZE_BY_NUMBER, 3, fr, dn),
        SINTER_OK);
    const double d50 = 42e-6;
    double sw = 0.0, s2 = 0.0;
    for (size_t i = 0; i < N_SAMPLES; ++i) {
        const double di = 2.0 * r[i], w = di * di * di, ind = (di <= d50) - 0.5;
        sw += w;
        s2 += w * w * ind * ind;
    }
    const double se = sqrt(s2) / sw / (0.5 / 30e-6);
    print_message("volume D50 %.4g um (expected 42, 4 se = %.3g um); by number D10 D50 D90 "
                  "%.3g %.3g %.3g um\n",
                  dv[1] * 1e6, 4e6 * se, dn[0] * 1e6, dn[1] * 1e6, dn[2] * 1e6);
    assert_true(fabs(dv[1] - d50) < 4.0 * se);
    assert_true(se < 1e-6); /* the check is tight: < 1 um on 42 um */
    /* by number the powder is finer: the d^-3 weighting moves every quantile down */
    for (int k = 0; k < 3; ++k)
        assert_true(dn[k] < dv[k]);
    /* quantiles of a hand-made set: diameters 1, 2, 3, 4 (volumes 1, 8, 27, 64 of 100) */
    sinter_particles *p = NULL;
    assert_int_equal(sinter_particles_create(&p, f->ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(p, 0, f->mat[0]), SINTER_OK);
    const double rr[4] = {0.5, 1.0, 1.5, 2.0};
    assert_int_equal(sinter_particles_add(p, 4, x, rr, 0, 300.0, NULL), SINTER_OK);
    const double g[4] = {0.0, 0.25, 0.5, 1.0};
    double out[4];
    assert_int_equal(sinter_particles_size_quantiles(p, 0, 4, SINTER_SIZE_BY_NUMBER, 4, g, out),
                     SINTER_OK);
    assert_true(out[0] == 1.0 && out[1] == 1.0 && out[2] == 2.0 && out[3] == 4.0);
    assert_int_equal(sinter_particles_size_quantiles(p, 0, 4, SINTER_SIZE_BY_VOLUME, 4, g, out),
                     SINTER_OK);
    assert_true(out[0] == 1.0 && out[1] == 3.0 && out[2] == 4.0 && out[3] == 4.0);
    assert_int_equal(sinter_particles_size_quantiles(p, 2, 3, SINTER_SIZE_BY_NUMBER, 1, g, out),
                     SINTER_ERR_INVALID);
    const double bad = 1.5;
    assert_int_equal(sinter_particles_size_quantiles(p, 0, 4, SINTER_SIZE_BY_NUMBER, 1, &bad, out),
                     SINTER_ERR_INVALID);
    sinter_particles_destroy(p);
    free(r);
    free(x);
}

/* Masses per material of particles first.. of the set. */
static void masses(const sinter_particles *ps, size_t first, double m[3], double *largest)
{
    const double *mass = NULL;
    const int32_t *mat = NULL;
    size_t n = 0;
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_MASS, (const void **)&mass, &n, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(ps, SINTER_FIELD_MATERIAL, (const void **)&mat, NULL, NULL),
        SINTER_OK);
    m[0] = m[1] = m[2] = *largest = 0.0;
    for (size_t i = first; i < n; ++i) {
        m[mat[i]] += mass[i];
        *largest = fmax(*largest, mass[i]);
    }
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_MASS), SINTER_OK);
    assert_int_equal(sinter_particles_release(ps, SINTER_FIELD_MATERIAL), SINTER_OK);
}

/*
 * Mixtures by mass fraction: 400 log-normal spheres of copper (8960 kg/m^3) and aluminium
 * (2700), then three materials; each material's mass is within one particle's mass (the
 * largest) of its share of the total.
 */
static void test_mixture_mass_fractions(void **state)
{
    fixture *f = *state;
    static const int32_t ids[3] = {0, 1, 2};
    static const double two[2] = {0.7, 0.3}, three[3] = {0.5, 0.3, 0.2};
    const double *fractions[2] = {two, three};
    for (size_t c = 0; c < 2; ++c) {
        size_t first = 0, placed = 0;
        assert_int_equal(sinter_particles_count(f->ps, &first), SINTER_OK);
        sinter_packing_options o;
        assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
        o.distribution = SINTER_RADII_LOGNORMAL;
        o.radius_median = 0.01;
        o.radius_gsd = 1.4;
        for (int d = 0; d < 3; ++d) {
            o.box_min[d] = 2.0 * (double)c;
            o.box_max[d] = 2.0 * (double)c + 1.0;
        }
        o.mixture_count = c + 2;
        o.mixture_materials = ids;
        o.mixture_mass_fractions = fractions[c];
        assert_int_equal(sinter_pack_random(f->ps, &o, 400, &placed), SINTER_OK);
        assert_int_equal(placed, 400);
        double m[3], largest;
        masses(f->ps, first, m, &largest);
        const double total = m[0] + m[1] + m[2];
        for (size_t k = 0; k < c + 2; ++k) {
            print_message("material %zu: %.5f of the mass (share %.2f), off by %.2f particles\n", k,
                          m[k] / total, fractions[c][k],
                          (m[k] - fractions[c][k] * total) / largest);
            assert_true(fabs(m[k] - fractions[c][k] * total) <= largest);
        }
    }
    /* refused: fractions not summing to 1, an unregistered material */
    sinter_packing_options o;
    assert_int_equal(sinter_packing_options_init(&o, sizeof(o)), SINTER_OK);
    const double bad[2] = {0.7, 0.4};
    const int32_t unknown[2] = {0, 7};
    o.mixture_count = 2;
    o.mixture_materials = ids;
    o.mixture_mass_fractions = bad;
    assert_int_equal(sinter_pack_random(f->ps, &o, 10, NULL), SINTER_ERR_INVALID);
    o.mixture_materials = unknown;
    o.mixture_mass_fractions = two;
    assert_int_equal(sinter_pack_random(f->ps, &o, 10, NULL), SINTER_ERR_NOT_FOUND);
}

/* The layout before issue 38: the old struct_size is served and packs as before. */
static void test_old_options_layout(void **state)
{
    fixture *f = *state;
    const size_t old = offsetof(sinter_packing_options, radius_median);
    sinter_packing_options o, full;
    memset(&o, 0xab, sizeof(o));
    assert_int_equal(sinter_packing_options_init(&o, old), SINTER_OK);
    assert_int_equal(o.struct_size, old);
    assert_true(o.radius_median != 0.05); /* the bytes beyond struct_size are not written */
    assert_int_equal(sinter_packing_options_init(&full, sizeof(full)), SINTER_OK);
    o.distribution = full.distribution = SINTER_RADII_NORMAL;
    o.radius_spread = full.radius_spread = 0.01;
    sinter_particles *a = NULL, *b = NULL;
    assert_int_equal(sinter_particles_create(&a, f->ctx), SINTER_OK);
    assert_int_equal(sinter_particles_create(&b, f->ctx), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(a, 0, f->mat[0]), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(b, 0, f->mat[0]), SINTER_OK);
    size_t na = 0, nb = 0;
    assert_int_equal(sinter_pack_random(a, &o, 50, &na), SINTER_OK);
    assert_int_equal(sinter_pack_random(b, &full, 50, &nb), SINTER_OK);
    assert_int_equal(na, nb);
    const double *ra = NULL, *rb = NULL;
    assert_int_equal(
        sinter_particles_view_read(a, SINTER_FIELD_RADIUS, (const void **)&ra, NULL, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(b, SINTER_FIELD_RADIUS, (const void **)&rb, NULL, NULL),
        SINTER_OK);
    assert_memory_equal(ra, rb, na * sizeof(double));
    assert_int_equal(sinter_particles_release(a, SINTER_FIELD_RADIUS), SINTER_OK);
    assert_int_equal(sinter_particles_release(b, SINTER_FIELD_RADIUS), SINTER_OK);
    sinter_particles_destroy(a);
    sinter_particles_destroy(b);
    o.struct_size = old + 8;
    assert_int_equal(sinter_pack_random(f->ps, &o, 1, NULL), SINTER_ERR_STRUCT_SIZE);
}

static char dir[64];

static const char *write_file(const char *name, const char *text)
{
    static char path[128];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(text, fp);
    fclose(fp);
    return path;
}

/* A table refused with SINTER_ERR_PARSE naming "file:line:" and `what`. */
static void expect_refused(sinter_ctx *ctx, const char *text, int percent, int line,
                           const char *what)
{
    const char *path = write_file("bad.csv", text);
    char where[160];
    snprintf(where, sizeof(where), "%s:%d: ", path, line);
    size_t n = 0;
    assert_int_equal(sinter_psd_read_csv(ctx, path, 1e-6, percent, NULL, NULL, 0, &n),
                     SINTER_ERR_PARSE);
    print_message("%s\n", sinter_last_error(ctx));
    assert_non_null(strstr(sinter_last_error(ctx), where));
    assert_non_null(strstr(sinter_last_error(ctx), what));
}

/* The CSV reader: header, comments, units, percent, normalisation; each bad file refused. */
static void test_psd_csv(void **state)
{
    fixture *f = *state;
    snprintf(dir, sizeof(dir), "/tmp/sinter_psd_XXXXXX");
    assert_non_null(mkdtemp(dir));
    const char *good = write_file("good.csv", "# laser diffraction, volume\n"
                                              "size_um,Q3_percent\n"
                                              "\n"
                                              "10, 0\n"
                                              "20; 10.5\n"
                                              "40\t60 # comment\n"
                                              "80 100.4\n");
    size_t n = 0;
    assert_int_equal(sinter_psd_read_csv(f->ctx, good, 1e-6, 1, NULL, NULL, 0, &n), SINTER_OK);
    assert_int_equal(n, 4);
    double d[4], q[4];
    assert_int_equal(sinter_psd_read_csv(f->ctx, good, 1e-6, 1, d, q, 4, &n), SINTER_OK);
    assert_true(fabs(d[0] - 10e-6) < 1e-20 && fabs(d[3] - 80e-6) < 1e-19);
    assert_true(q[0] == 0.0 && q[3] == 1.0); /* normalised: ends at exactly 1 */
    assert_true(fabs(q[1] - 0.105 / 1.004) < 1e-15);
    assert_int_equal(sinter_psd_read_csv(f->ctx, good, 1e-6, 1, d, q, 3, &n), SINTER_ERR_INVALID);
    expect_refused(f->ctx, "d,Q\n10,0\n20,0.5\n15,0.7\n30,1\n", 0, 4, "increasing sizes");
    expect_refused(f->ctx, "10,0\n20,0.5\n30,0.4\n40,1\n", 0, 3, "never decreases");
    expect_refused(f->ctx, "10,0\n-20,0.5\n30,1\n", 0, 2, "negative");
    expect_refused(f->ctx, "10,0\n20,0.5\n30,0.9\n", 0, 3, "not normalised");
    expect_refused(f->ctx, "10,0\n20,50\n30,97\n", 1, 3, "not normalised");
    expect_refused(f->ctx, "10,0\n20,50\n30,100\n", 0, 2, "must be in [0, 1]");
    expect_refused(f->ctx, "size,Q\n10,0\nx,1\n", 0, 3, "two numbers");
    expect_refused(f->ctx, "10,0\n20,0,4\n", 0, 2, "two numbers");
    assert_int_equal(sinter_psd_read_csv(f->ctx, "/nonexistent/psd.csv", 1.0, 0, NULL, NULL, 0, &n),
                     SINTER_ERR_IO);
}

/* The scene keys: a table in micrometres and percent by volume, a two-material mixture. */
static void test_scene_keys(void **state)
{
    fixture *f = *state;
    write_file("powder.csv", "diameter_um,cumulative_percent\n20,0\n30,10\n50,50\n70,90\n90,100\n");
    char scene_path[128];
    snprintf(
        scene_path, sizeof(scene_path), "%s",
        write_file(
            "psd.scene",
            "[scene]\nunits = SI\n"
            "[material cu]\ndensity = 8960\nyoungs_modulus = 1e9\n"
            "[material al]\ndensity = 2700\nyoungs_modulus = 1e9\n"
            "[particles]\nmethod = random\nmaterials = cu, al\nmass_fractions = 0.6 0.4\n"
            "box_min = 0 0 0\nbox_max = 6e-4 6e-4 6e-4\ncount = 200\n"
            "distribution = table\ntable = powder.csv\ntable_units = um\ntable_values = percent\n"
            "table_basis = volume\n"
            "[particles]\nmethod = random\nmaterial = cu\nbox_min = 1e-3 0 0\n"
            "box_max = 1.6e-3 6e-4 6e-4\ncount = 100\ndistribution = lognormal\nradius = 1e-5\n"
            "gsd = 1.3\n"
            "[force hertz_mindlin]\n[stepper]\ndt = 1e-9\nend_time = 1e-6\n[output]\ninterval = "
            "1\nvtu = no\n"));
    sinter_scene *sc = NULL;
    sinter_status st = sinter_scene_load(&sc, f->ctx, scene_path);
    if (st != SINTER_OK)
        print_message("%s\n", sinter_last_error(f->ctx));
    assert_int_equal(st, SINTER_OK);
    sinter_particles *ps = NULL;
    assert_int_equal(sinter_scene_get_particles(sc, &ps), SINTER_OK);
    size_t n = 0;
    assert_int_equal(sinter_particles_count(ps, &n), SINTER_OK);
    assert_int_equal(n, 300);
    double dv[1];
    const double half = 0.5;
    assert_int_equal(
        sinter_particles_size_quantiles(ps, 0, 200, SINTER_SIZE_BY_VOLUME, 1, &half, dv),
        SINTER_OK);
    print_message("scene: volume D50 %g um\n", dv[0] * 1e6);
    assert_true(dv[0] > 40e-6 && dv[0] < 60e-6); /* D50 by volume of the table: 50 um */
    sinter_scene_destroy(sc);
    /* a bad table through the scene: the table's own file and line */
    write_file("powder.csv", "diameter_um,cumulative_percent\n20,0\n30,10\n25,50\n90,100\n");
    assert_int_equal(sinter_scene_load(&sc, f->ctx, scene_path), SINTER_ERR_PARSE);
    assert_non_null(strstr(sinter_last_error(f->ctx), "powder.csv:4:"));
    char cmd[128];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_lognormal_sampler, setup, teardown),
        cmocka_unit_test_setup_teardown(test_volume_table_hatch_choate, setup, teardown),
        cmocka_unit_test_setup_teardown(test_volume_table_d50, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mixture_mass_fractions, setup, teardown),
        cmocka_unit_test_setup_teardown(test_old_options_layout, setup, teardown),
        cmocka_unit_test_setup_teardown(test_psd_csv, setup, teardown),
        cmocka_unit_test_setup_teardown(test_scene_keys, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
