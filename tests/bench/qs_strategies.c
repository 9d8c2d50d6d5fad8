/*
 * qs_strategies: the quasi-static sintering stepper's three neck-integration strategies (seed
 * 001 sec. 3.3; src/stepper/quasistatic.h) compared at matched error on a sintering packing.
 *
 *   qs_strategies --make-packing FILE [--count N] [--box LX LY LZ] [--fraction F] [--friction MU]
 *   qs_strategies --packing FILE [--end T] [--rtols "1e-3 1e-4 ..."] [--strategies "1 2 3"]
 *                 [--reference STRATEGY RTOL] [--svg PATH]
 *
 * --make-packing: seed 001 sec. 4.1's copper green body: N (805) spheres of mean diameter
 * 50 um with a dispersion of 0.1 (normal, std 0.1 of the mean), placed by random sequential
 * addition in a box twice the volume of the final one, then compacted triaxially
 * (sinter_pack_compact, friction MU = 0.1) onto [0, LX] x [0, LY] x [0, LZ] (0.5 x 0.5 x
 * 0.4 mm), or with --fraction onto that box scaled to the green density F; written as lines
 * "x y z r" [m]. (805 such spheres fill only 0.53 of 0.5 x 0.5 x 0.4 mm, where they barely
 * touch; the seed's ~60 % green density needs the box scaled by 0.96.)
 * --packing: every strategy at every rtol (qs_rtol: the relative accuracy of the necks; the
 * RK4 step-doubling test of strategies 1 and 2 and CVODE's of strategy 3 use the same error
 * weights) sinters the packing at 1293 K to T (5000 s). The error of a run is measured against
 * a reference run (default strategy 2 at rtol 1e-9): the largest relative difference of the
 * neck radius over the grown necks (at least half the mean) both runs have, and the relative
 * difference of the shrinkage along x, y and z (links only one run has are counted).
 * CPU time is CLOCK_PROCESS_CPUTIME_ID.
 * Prints a table (and an SVG of log10 error against log10 CPU seconds with --svg).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sinter.h"
#include "stepper/quasistatic.h"
#include "stepper/stepper.h"

static sinter_ctx *g_ctx;

static void check(sinter_status s, const char *what)
{
    if (s != SINTER_OK) {
        fprintf(stderr, "qs_strategies: %s failed: %s (%s)\n", what, sinter_status_name(s),
                g_ctx ? sinter_last_error(g_ctx) : "");
        exit(1);
    }
}
#define CHECK(call) check((call), #call)

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static sinter_material *copper(void)
{
    sinter_material *m = NULL;
    CHECK(sinter_material_create(&m, g_ctx, "copper")); /* neck data: seed 001 table 2 */
    CHECK(sinter_material_set(m, SINTER_MAT_DENSITY, 8960.0));
    CHECK(sinter_material_set(m, SINTER_MAT_YOUNGS_MODULUS, 72e9));
    CHECK(sinter_material_set(m, SINTER_MAT_POISSON_RATIO, 0.3));
    return m;
}

static void make_packing(const char *path, size_t count, const double box[3], double fraction,
                         double friction)
{
    sinter_material *cu = copper();
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, cu));
    sinter_packing_options po;
    CHECK(sinter_packing_options_init(&po, sizeof(po)));
    const double scale = cbrt(2.0); /* RSA in twice the final volume */
    for (int d = 0; d < 3; ++d) {
        po.box_min[d] = 0.0;
        po.box_max[d] = box[d] * scale;
    }
    po.distribution = SINTER_RADII_NORMAL;
    po.radius_mean = 25e-6;
    po.radius_spread = 2.5e-6;
    po.seed = 805;
    po.material = 0;
    po.temperature = 1293.0;
    size_t placed = 0;
    CHECK(sinter_pack_random(ps, &po, count, &placed));
    if (placed != count) {
        fprintf(stderr, "qs_strategies: RSA placed only %zu of %zu spheres\n", placed, count);
        exit(1);
    }
    sinter_compaction_options co;
    CHECK(sinter_compaction_options_init(&co, sizeof(co)));
    for (int d = 0; d < 3; ++d) {
        co.box_min[d] = 0.0;
        co.box_max[d] = box[d];
    }
    co.friction = friction;
    co.volume_fraction = fraction; /* 0: the box as given */
    co.stop_at_jamming = 1;        /* a packing that jams first is taken as it is */
    sinter_compaction_result res;
    memset(&res, 0, sizeof(res));
    res.struct_size = sizeof(res);
    const double t0 = cpu_seconds();
    CHECK(sinter_pack_compact(ps, &co, &res));
    fprintf(stderr,
            "packing: %zu spheres, fraction %.4f, coordination %.2f, largest overlap %.2e of "
            "the radius, %.1f s CPU\n",
            count, res.volume_fraction, res.coordination, res.max_overlap_ratio,
            cpu_seconds() - t0);
    const double *x = NULL, *r = NULL;
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    fprintf(f, "# seed 001 sec. 4.1 copper green body: x y z r [m]; fraction %.6f\n",
            res.volume_fraction);
    for (size_t i = 0; i < count; ++i)
        fprintf(f, "%.17g %.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2], r[i]);
    fclose(f);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_RADIUS);
    sinter_particles_destroy(ps);
    sinter_material_destroy(cu);
}

typedef struct packing {
    size_t n;
    double *x, *r;
} packing;

static packing read_packing(const char *path)
{
    packing p = {0, NULL, NULL};
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    char line[512];
    size_t cap = 0;
    while (fgets(line, sizeof(line), f) != NULL) {
        double v[4];
        if (line[0] == '#' || sscanf(line, "%lf %lf %lf %lf", v, v + 1, v + 2, v + 3) != 4)
            continue;
        if (p.n == cap) {
            cap = cap ? 2 * cap : 1024;
            p.x = realloc(p.x, 3 * cap * sizeof(double));
            p.r = realloc(p.r, cap * sizeof(double));
        }
        memcpy(p.x + 3 * p.n, v, 3 * sizeof(double));
        p.r[p.n++] = v[3];
    }
    fclose(f);
    return p;
}

typedef struct run {
    int strategy;
    double rtol;
    double seconds;
    size_t links;
    uint64_t *keys;   /* id_a * n + id_b per link, sorted with the neck radii */
    double *necks;    /* [m] */
    double shrink[3]; /* x, y, z */
    double neck_err, shrink_err;
    double neck_median, neck_p99; /* of the grown necks' relative errors */
    uint64_t worst_key;           /* the link of neck_err */
    size_t unmatched;             /* links only one of the two runs has */
    uint64_t steps;
} run;

typedef struct keyed {
    uint64_t key;
    double neck;
} keyed;

static int keyed_order(const void *a, const void *b)
{
    const uint64_t x = ((const keyed *)a)->key, y = ((const keyed *)b)->key;
    return x < y ? -1 : x > y;
}

static run sinter_run(const packing *pk, int strategy, double rtol, double end)
{
    run out;
    memset(&out, 0, sizeof(out));
    out.strategy = strategy;
    out.rtol = rtol;
    sinter_material *cu = copper();
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, cu));
    CHECK(sinter_particles_add(ps, pk->n, pk->x, pk->r, 0, 1293.0, NULL));
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    CHECK(sinter_stepper_set_option(st, "qs_strategy", strategy));
    CHECK(sinter_stepper_set_option(st, "qs_rtol", rtol));
    const double t0 = cpu_seconds();
    CHECK(sinter_stepper_advance(st, end));
    out.seconds = cpu_seconds() - t0;
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    CHECK(sinter_stepper_sintering_stats(st, &stats));
    memcpy(out.shrink, stats.shrinkage, sizeof(out.shrink));
    sinter_stepper_stats ss;
    memset(&ss, 0, sizeof(ss));
    ss.struct_size = sizeof(ss);
    CHECK(sinter_stepper_get_stats(st, &ss));
    out.steps = ss.steps;
    size_t nl = 0;
    const sinter_qs_link *links = sinter_qs_links(st->quasistatic, &nl);
    keyed *k = calloc(nl + 1, sizeof(keyed));
    for (size_t l = 0; l < nl; ++l) {
        const uint64_t a = links[l].id_a, b = links[l].id_b;
        k[l].key = a < b ? a * pk->n + b : b * pk->n + a;
        k[l].neck = links[l].neck.y[SINTER_NECK_X];
    }
    qsort(k, nl, sizeof(keyed), keyed_order);
    out.links = nl;
    out.keys = calloc(nl + 1, sizeof(uint64_t));
    out.necks = calloc(nl + 1, sizeof(double));
    for (size_t l = 0; l < nl; ++l) {
        out.keys[l] = k[l].key;
        out.necks[l] = k[l].neck;
    }
    free(k);
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(cu);
    return out;
}

/* Worst relative neck-radius difference over the grown necks both runs have (links that
 * formed in one run only, at a step boundary of the other's global stepping, are counted
 * apart), and the largest relative shrinkage difference over x, y, z. */
static int double_order(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void compare(run *r, const run *ref)
{
    double worst = 0.0, mean = 0.0;
    double *errs = calloc(ref->links + 1, sizeof(double));
    size_t nerr = 0;
    for (size_t k = 0; k < ref->links; ++k)
        mean += ref->necks[k] / (double)ref->links;
    size_t i = 0, j = 0, unmatched = 0;
    while (i < r->links || j < ref->links) {
        if (i < r->links && j < ref->links && r->keys[i] == ref->keys[j]) {
            /* necks that formed during the run are young and small: their relative error
             * mostly says when the contact was detected (at a global step boundary), so the
             * worst error is taken over the grown necks (at least half the mean radius) */
            if (ref->necks[j] >= 0.5 * mean) {
                const double e = fabs(r->necks[i] - ref->necks[j]) / ref->necks[j];
                errs[nerr++] = e;
                if (e > worst) {
                    worst = e;
                    r->worst_key = ref->keys[j];
                }
            }
            ++i, ++j;
        } else {
            ++unmatched;
            if (j >= ref->links || (i < r->links && r->keys[i] < ref->keys[j]))
                ++i;
            else
                ++j;
        }
    }
    r->neck_err = worst;
    r->unmatched = unmatched;
    qsort(errs, nerr, sizeof(double), double_order);
    r->neck_median = nerr > 0 ? errs[nerr / 2] : 0.0;
    r->neck_p99 = nerr > 0 ? errs[(size_t)(0.99 * (double)(nerr - 1))] : 0.0;
    free(errs);
    double s = 0.0;
    for (int d = 0; d < 3; ++d)
        s = fmax(s, fabs(r->shrink[d] - ref->shrink[d]) / fabs(ref->shrink[d]));
    r->shrink_err = s;
}

static void write_svg(const char *path, const run *runs, size_t count)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        return;
    }
    const double W = 640, H = 420, L = 70, R = 20, T = 30, B = 50;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (size_t k = 0; k < count; ++k) {
        const double e = fmax(runs[k].neck_err, runs[k].shrink_err);
        if (!(e > 0.0))
            continue;
        xmin = fmin(xmin, floor(log10(runs[k].seconds)));
        xmax = fmax(xmax, ceil(log10(runs[k].seconds)));
        ymin = fmin(ymin, floor(log10(e)));
        ymax = fmax(ymax, ceil(log10(e)));
    }
    if (!(xmax > xmin))
        xmax = xmin + 1;
    if (!(ymax > ymin))
        ymax = ymin + 1;
    fprintf(f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
            "width=\"%g\" height=\"%g\" font-family=\"DejaVu Sans, Arial, sans-serif\" "
            "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"#fff\"/>\n",
            W, H);
    fprintf(f,
            "<text x=\"%g\" y=\"18\" text-anchor=\"middle\">Quasi-static strategies, 805 copper "
            "spheres at 1293 K: error against CPU time</text>\n",
            W / 2);
    fprintf(f, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"#000\"/>\n",
            L, T, W - L - R, H - T - B);
    for (double v = xmin; v <= xmax + 1e-9; v += 1)
        fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">1e%g</text>\n",
                L + (v - xmin) / (xmax - xmin) * (W - L - R), H - B + 16, v);
    for (double v = ymin; v <= ymax + 1e-9; v += 1)
        fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"end\">1e%g</text>\n", L - 6,
                H - B - (v - ymin) / (ymax - ymin) * (H - T - B) + 4, v);
    fprintf(f, "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">CPU time [s]</text>\n",
            L + (W - L - R) / 2, H - 12);
    fprintf(f,
            "<text x=\"16\" y=\"%g\" text-anchor=\"middle\" transform=\"rotate(-90 16 %g)\">error "
            "(neck radius, shrinkage) [1]</text>\n",
            T + (H - T - B) / 2, T + (H - T - B) / 2);
    static const char *colors[4] = {"#000", "#1f77b4", "#ff7f0e", "#2ca02c"};
    for (int s = 1; s <= 3; ++s) {
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"",
                colors[s]);
        for (size_t k = 0; k < count; ++k) {
            const double e = fmax(runs[k].neck_err, runs[k].shrink_err);
            if (runs[k].strategy != s || !(e > 0.0))
                continue;
            fprintf(f, "%.1f,%.1f ",
                    L + (log10(runs[k].seconds) - xmin) / (xmax - xmin) * (W - L - R),
                    H - B - (log10(e) - ymin) / (ymax - ymin) * (H - T - B));
        }
        fprintf(f, "\"/>\n<text x=\"%g\" y=\"%g\" fill=\"%s\">strategy %d</text>\n", W - R - 90,
                T + 16.0 * s, colors[s], s);
    }
    fprintf(f, "</svg>\n");
    fclose(f);
}

int main(int argc, char **argv)
{
    const char *make = NULL, *pack = NULL, *svg = NULL;
    const char *rtols = "1e-3 1e-4 1e-5 1e-6 1e-7", *strategies = "1 2 3";
    size_t count = 805;
    double fraction = 0.0, friction = 0.1, ref_rtol = 1e-9;
    int ref_strategy = 2;
    double box[3] = {0.5e-3, 0.5e-3, 0.4e-3}, end = 5000.0;
    for (int k = 1; k < argc; ++k) {
        if (strcmp(argv[k], "--make-packing") == 0 && k + 1 < argc)
            make = argv[++k];
        else if (strcmp(argv[k], "--packing") == 0 && k + 1 < argc)
            pack = argv[++k];
        else if (strcmp(argv[k], "--fraction") == 0 && k + 1 < argc)
            fraction = strtod(argv[++k], NULL);
        else if (strcmp(argv[k], "--friction") == 0 && k + 1 < argc)
            friction = strtod(argv[++k], NULL);
        else if (strcmp(argv[k], "--count") == 0 && k + 1 < argc)
            count = (size_t)strtoull(argv[++k], NULL, 10);
        else if (strcmp(argv[k], "--box") == 0 && k + 3 < argc) {
            for (int d = 0; d < 3; ++d)
                box[d] = strtod(argv[++k], NULL);
        } else if (strcmp(argv[k], "--end") == 0 && k + 1 < argc)
            end = strtod(argv[++k], NULL);
        else if (strcmp(argv[k], "--rtols") == 0 && k + 1 < argc)
            rtols = argv[++k];
        else if (strcmp(argv[k], "--strategies") == 0 && k + 1 < argc)
            strategies = argv[++k];
        else if (strcmp(argv[k], "--reference") == 0 && k + 2 < argc) {
            ref_strategy = atoi(argv[++k]);
            ref_rtol = strtod(argv[++k], NULL);
        } else if (strcmp(argv[k], "--svg") == 0 && k + 1 < argc)
            svg = argv[++k];
        else {
            fprintf(stderr, "usage: qs_strategies --make-packing FILE [--count N] [--box LX LY LZ] "
                            "[--fraction F] [--friction MU]\n"
                            "       qs_strategies --packing FILE [--end T] [--rtols LIST] "
                            "[--strategies LIST] [--reference S RTOL] [--svg PATH]\n");
            return 2;
        }
    }
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    if (make != NULL) {
        make_packing(make, count, box, fraction, friction);
        sinter_ctx_destroy(g_ctx);
        return 0;
    }
    if (pack == NULL) {
        fprintf(stderr, "qs_strategies: give --make-packing or --packing\n");
        return 2;
    }
    const packing pk = read_packing(pack);
    fprintf(stderr, "reference: strategy %d at rtol %g ...\n", ref_strategy, ref_rtol);
    run ref = sinter_run(&pk, ref_strategy, ref_rtol, end);
    printf("reference (strategy %d, rtol %g, to %g s): %zu links, shrinkage x %.6e y %.6e z "
           "%.6e, %.2f s CPU\n\n",
           ref_strategy, ref_rtol, end, ref.links, ref.shrink[0], ref.shrink[1], ref.shrink[2],
           ref.seconds);
    run runs[64];
    size_t nr = 0;
    printf("| strategy | rtol | CPU [s] | global steps | links (not in the reference) | neck error "
           "median / 99 %% / max (link) | shrinkage error |\n|---|---|---|---|---|---|---|\n");
    for (const char *sp = strategies; *sp && nr < 64;) {
        char *se = NULL;
        const int s = (int)strtol(sp, &se, 10);
        if (se == sp)
            break;
        sp = se;
        for (const char *rp = rtols; *rp && nr < 64;) {
            char *re = NULL;
            const double rt = strtod(rp, &re);
            if (re == rp)
                break;
            rp = re;
            runs[nr] = sinter_run(&pk, s, rt, end);
            compare(&runs[nr], &ref);
            printf("| %d | %.0e | %.3f | %llu | %zu (%zu) | %.1e / %.1e / %.1e (%llu-%llu) | "
                   "%.2e |\n",
                   s, rt, runs[nr].seconds, (unsigned long long)runs[nr].steps, runs[nr].links,
                   runs[nr].unmatched, runs[nr].neck_median, runs[nr].neck_p99,
                   runs[nr].neck_err, (unsigned long long)(runs[nr].worst_key / pk.n),
                   (unsigned long long)(runs[nr].worst_key % pk.n), runs[nr].shrink_err);
            fflush(stdout);
            nr++;
        }
    }
    if (svg != NULL)
        write_svg(svg, runs, nr);
    for (size_t k = 0; k < nr; ++k) {
        free(runs[k].keys);
        free(runs[k].necks);
    }
    free(ref.keys);
    free(ref.necks);
    free(pk.x);
    free(pk.r);
    sinter_ctx_destroy(g_ctx);
    return 0;
}
