/*
 * qs_strategies: the quasi-static sintering stepper's three neck-integration strategies (seed
 * 001 sec. 3.3; src/stepper/quasistatic.h) compared at matched error on a sintering packing.
 *
 *   qs_strategies --make-packing FILE [--count N] [--box LX LY LZ] [--fraction F] [--friction MU]
 *   qs_strategies --packing FILE [--end T] [--rtols "1e-3 1e-4 ..."] [--strategies "1 2 3"]
 *                 [--max-strains "1e-3 1e-4 ..."] [--set KEY VALUE]...
 *                 [--reference STRATEGY RTOL] [--reference-set KEY VALUE]...
 *                 [--save-reference PATH | --load-reference PATH] [--svg PATH]
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
 * --max-strains: strategy 3 is run at every rtol for each of these qs_max_strain values (its
 * global-step criterion); strategies 1 and 2 ignore it. --set KEY VALUE sets any other
 * quasi-static option (sinter_qs_option_set keys, e.g. qs_dt_max) on every compared run,
 * --reference-set on the reference only (e.g. qs_max_strain 2.5e-5 for small global steps);
 * both may be repeated. --save-reference writes the reference's shrinkage and neck radii to
 * PATH, --load-reference reads them instead of running it again (the reference of a whole
 * run costs tens of minutes): "# strategy S rtol R max_strain M end T links N steps N pcg N
 * seconds S", "shrink x y z",
 * then one "key neck" line per link.
 * Each row also gives the global steps (and their CPU seconds) by the decade of simulated time
 * they end in, the PCG iterations, and for strategy 3 the CVODE steps (neck Jacobians) of its
 * young and grown batches.
 * CPU time is CLOCK_PROCESS_CPUTIME_ID.
 * Prints a table (and an SVG of log10 error against log10 CPU seconds with --svg).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "qs_strategies"
#include "bench_support.h"
#include "sinter.h"
#include "io/scene.h"          /* --scene: the material and the furnace of a scene file */
#include "stepper/qs_struct.h" /* the CVODE work counters of strategy 3 */
#include "stepper/quasistatic.h"
#include "stepper/stepper.h"

/* --scene: the scene's first material and its furnace (NULL / 0: copper at 1293 K). */
static sinter_material *g_scene_material;
static double *g_furnace; /* times, then temperatures */
static size_t g_furnace_count;

static void load_scene(const char *path, double *end)
{
    sinter_scene *sc = NULL;
    CHECK(sinter_scene_load(&sc, g_ctx, path));
    CHECK(sinter_material_clone(&g_scene_material, sc->materials[0]));
    g_furnace_count = sc->st->furnace_count;
    if (g_furnace_count > 0) {
        g_furnace = calloc(2 * g_furnace_count, sizeof(double));
        memcpy(g_furnace, sc->st->furnace, 2 * g_furnace_count * sizeof(double));
    }
    if (sc->end_time > 0.0)
        *end = sc->end_time;
    sinter_scene_destroy(sc);
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
    /* RSA in twice the final volume */
    pack_normal(ps, box, cbrt(2.0), 25e-6, 2.5e-6, 805, 1293.0, count);
    sinter_compaction_options co;
    CHECK(sinter_compaction_options_init(&co, sizeof(co)));
    co.friction = friction;
    co.volume_fraction = fraction; /* 0: the box as given */
    co.stop_at_jamming = 1;        /* a packing that jams first is taken as it is */
    double cpu = 0.0;
    const sinter_compaction_result res = compact_into(ps, &co, box, &cpu);
    fprintf(stderr,
            "packing: %zu spheres, fraction %.4f, coordination %.2f, largest overlap %.2e of "
            "the radius, %.1f s CPU\n",
            count, res.volume_fraction, res.coordination, res.max_overlap_ratio, cpu);
    char header[128];
    snprintf(header, sizeof(header),
             "seed 001 sec. 4.1 copper green body: x y z r [m]; fraction %.6f",
             res.volume_fraction);
    write_spheres(path, ps, header);
    sinter_particles_destroy(ps);
    sinter_material_destroy(cu);
}

typedef struct run {
    int strategy;
    double rtol;
    double max_strain; /* qs_max_strain of the run */
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
    uint64_t pcg;                                /* PCG iterations of the K u = f solves */
    uint64_t cvode_steps[2], cvode_jacobians[2]; /* strategy 3: young and grown batches */
    double cpu_by_decade[5], cpu_last;           /* CPU seconds of those steps */
    uint64_t by_decade[5]; /* global steps ending in [0, 1), [1, 10), [10, 100), [100, 1000) s
                            * and from 1000 s on */
} run;

/* Observer: the global steps and their CPU time counted by the decade of simulated time they
 * end in. */
static int count_step(const sinter_stepper *st, double time, void *user)
{
    (void)st;
    run *r = user;
    const int d = time < 1.0 ? 0 : time < 10.0 ? 1 : time < 100.0 ? 2 : time < 1000.0 ? 3 : 4;
    const double now = cpu_seconds();
    r->by_decade[d]++;
    r->cpu_by_decade[d] += now - r->cpu_last;
    r->cpu_last = now;
    return 0;
}

/* Extra quasi-static options (--set, --reference-set). */
#define MAX_SETS 8
typedef struct option_set {
    int count;
    const char *key[MAX_SETS];
    double value[MAX_SETS];
} option_set;

typedef struct keyed {
    uint64_t key;
    double neck;
} keyed;

static int keyed_order(const void *a, const void *b)
{
    const uint64_t x = ((const keyed *)a)->key, y = ((const keyed *)b)->key;
    return x < y ? -1 : x > y;
}

static run sinter_run(const spheres *pk, int strategy, double rtol, double max_strain,
                      const option_set *extra, double end)
{
    run out;
    memset(&out, 0, sizeof(out));
    out.strategy = strategy;
    out.rtol = rtol;
    sinter_material *cu = NULL;
    if (g_scene_material != NULL)
        CHECK(sinter_material_clone(&cu, g_scene_material));
    else
        cu = copper();
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, cu));
    const double temperature0 = g_furnace_count > 0 ? g_furnace[g_furnace_count] : 1293.0;
    CHECK(sinter_particles_add(ps, pk->n, pk->x, pk->r, 0, temperature0, NULL));
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    if (g_furnace_count > 0) { /* as the scene: the first global step 1 us */
        CHECK(sinter_stepper_set_dt(st, 1e-6));
        CHECK(sinter_stepper_set_furnace(st, g_furnace_count, g_furnace,
                                         g_furnace + g_furnace_count));
    }
    CHECK(sinter_stepper_set_option(st, "qs_strategy", strategy));
    CHECK(sinter_stepper_set_option(st, "qs_rtol", rtol));
    for (int k = 0; k < extra->count; ++k)
        CHECK(sinter_stepper_set_option(st, extra->key[k], extra->value[k]));
    if (max_strain > 0.0)
        CHECK(sinter_stepper_set_option(st, "qs_max_strain", max_strain));
    CHECK(sinter_stepper_get_option(st, "qs_max_strain", &out.max_strain));
    CHECK(sinter_stepper_set_observer(st, count_step, &out));
    const double t0 = cpu_seconds();
    out.cpu_last = t0;
    CHECK(sinter_stepper_advance(st, end));
    out.seconds = cpu_seconds() - t0;
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    CHECK(sinter_stepper_sintering_stats(st, &stats));
    memcpy(out.shrink, stats.shrinkage, sizeof(out.shrink));
    out.pcg = stats.pcg_iterations;
    sinter_stepper_stats ss;
    memset(&ss, 0, sizeof(ss));
    ss.struct_size = sizeof(ss);
    CHECK(sinter_stepper_get_stats(st, &ss));
    out.steps = ss.steps;
    for (int g = 0; g < 2; ++g) {
        out.cvode_steps[g] = st->quasistatic->batch_counters[g].steps;
        out.cvode_jacobians[g] = st->quasistatic->batch_counters[g].jacobian_evaluations;
    }
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

/* The error a chart shows: 0 the shrinkage's, 1 the 99th percentile of the neck radius'. */
static double chart_error(const run *r, int metric)
{
    return metric == 0 ? r->shrink_err : r->neck_p99;
}

static void write_svg(const char *path, const run *runs, size_t count, const char *title)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        return;
    }
    const double W = 680, H = 440, L = 70, R = 20, T = 30, B = 50;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (size_t k = 0; k < count; ++k)
        for (int m = 0; m < 2; ++m) {
            const double e = chart_error(&runs[k], m);
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
    fprintf(f, "<text x=\"%g\" y=\"18\" text-anchor=\"middle\">Work-precision, %s</text>\n", W / 2,
            title);
    fprintf(f,
            "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"#000\"/>\n",
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
            "against the reference [1]</text>\n",
            T + (H - T - B) / 2, T + (H - T - B) / 2);
    static const char *colors[4] = {"#000", "#1f77b4", "#ff7f0e", "#2ca02c"};
    static const char *metric_name[2] = {"shrinkage", "neck 99 %"};
    int legend = 0;
    for (int s = 1; s <= 3; ++s)
        for (int m = 0; m < 2; ++m) {
            int any = 0;
            for (size_t k = 0; k < count; ++k) {
                const double e = chart_error(&runs[k], m);
                if (runs[k].strategy != s || !(e > 0.0))
                    continue;
                const double x = L + (log10(runs[k].seconds) - xmin) / (xmax - xmin) * (W - L - R);
                const double y = H - B - (log10(e) - ymin) / (ymax - ymin) * (H - T - B);
                if (m == 0)
                    fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", x, y,
                            colors[s]);
                else
                    fprintf(f,
                            "<rect x=\"%.1f\" y=\"%.1f\" width=\"7\" height=\"7\" fill=\"none\" "
                            "stroke=\"%s\"/>\n",
                            x - 3.5, y - 3.5, colors[s]);
                any = 1;
            }
            if (any)
                fprintf(f, "<text x=\"%g\" y=\"%g\" fill=\"%s\">%s strategy %d: %s</text>\n",
                        W - R - 210, T + 16.0 * ++legend, colors[s], m == 0 ? "o" : "[]", s,
                        metric_name[m]);
        }
    fprintf(f, "</svg>\n");
    fclose(f);
}

/* The reference's shrinkage and neck radii to / from a file (--save-reference, --load-reference).
 */
static void save_reference(const char *path, const run *ref, double end)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    fprintf(f,
            "# strategy %d rtol %.3g max_strain %.3g end %.17g links %zu steps %llu pcg %llu "
            "seconds %.3f\n",
            ref->strategy, ref->rtol, ref->max_strain, end, ref->links,
            (unsigned long long)ref->steps, (unsigned long long)ref->pcg, ref->seconds);
    fprintf(f, "shrink %.17g %.17g %.17g\n", ref->shrink[0], ref->shrink[1], ref->shrink[2]);
    for (size_t k = 0; k < ref->links; ++k)
        fprintf(f, "%llu %.17g\n", (unsigned long long)ref->keys[k], ref->necks[k]);
    fclose(f);
}

static run load_reference(const char *path, double end)
{
    run ref;
    memset(&ref, 0, sizeof(ref));
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    double ref_end = 0.0;
    unsigned long long steps = 0, pcg = 0;
    if (fscanf(f,
               "# strategy %d rtol %lf max_strain %lf end %lf links %zu steps %llu pcg %llu "
               "seconds %lf\n",
               &ref.strategy, &ref.rtol, &ref.max_strain, &ref_end, &ref.links, &steps, &pcg,
               &ref.seconds) != 8 ||
        fscanf(f, "shrink %lf %lf %lf\n", ref.shrink, ref.shrink + 1, ref.shrink + 2) != 3) {
        fprintf(stderr, "qs_strategies: %s is not a reference file\n", path);
        exit(1);
    }
    if (fabs(ref_end - end) > 1e-9 * end) {
        fprintf(stderr, "qs_strategies: %s ends at %g s, not at --end %g s\n", path, ref_end, end);
        exit(1);
    }
    ref.steps = steps;
    ref.pcg = pcg;
    ref.keys = calloc(ref.links + 1, sizeof(uint64_t));
    ref.necks = calloc(ref.links + 1, sizeof(double));
    for (size_t k = 0; k < ref.links; ++k) {
        unsigned long long key = 0;
        if (fscanf(f, "%llu %lf", &key, ref.necks + k) != 2) {
            fprintf(stderr, "qs_strategies: %s: short at link %zu\n", path, k);
            exit(1);
        }
        ref.keys[k] = key;
    }
    fclose(f);
    return ref;
}

/* --compare REF "RUN ...": runs saved with --save-runs against a saved reference. */
static int compare_files(const char *ref_path, const char *list, double end, const char *svg,
                         const char *title)
{
    run ref = load_reference(ref_path, end);
    static run runs[64];
    size_t nr = 0;
    printf("reference %s: strategy %d, rtol %g, max strain %g, %zu links, %llu global steps, "
           "%.1f s CPU, shrinkage %.6e %.6e %.6e\n\n",
           ref_path, ref.strategy, ref.rtol, ref.max_strain, ref.links,
           (unsigned long long)ref.steps, ref.seconds, ref.shrink[0], ref.shrink[1], ref.shrink[2]);
    printf("| run | strategy | rtol | max strain | CPU [s] | global steps | PCG iterations | links "
           "(unmatched) | neck error median / 99 %% / max (link key) | shrinkage error |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    char buffer[8192];
    snprintf(buffer, sizeof(buffer), "%s", list);
    for (char *save = NULL, *file = strtok_r(buffer, " ", &save); file != NULL && nr < 64;
         file = strtok_r(NULL, " ", &save)) {
        runs[nr] = load_reference(file, end);
        compare(&runs[nr], &ref);
        const run *r = &runs[nr];
        printf("| %s | %d | %.0e | %.1e | %.2f | %llu | %llu | %zu (%zu) | %.1e / %.1e / %.1e "
               "(key %llu) | %.2e |\n",
               file, r->strategy, r->rtol, r->max_strain, r->seconds, (unsigned long long)r->steps,
               (unsigned long long)r->pcg, r->links, r->unmatched, r->neck_median, r->neck_p99,
               r->neck_err, (unsigned long long)r->worst_key, r->shrink_err);
        nr++;
    }
    if (svg != NULL)
        write_svg(svg, runs, nr, title != NULL ? title : ref_path);
    return 0;
}

static void add_set(option_set *set, const char *key, const char *value)
{
    if (set->count == MAX_SETS) {
        fprintf(stderr, "qs_strategies: at most %d options per --set list\n", MAX_SETS);
        exit(2);
    }
    set->key[set->count] = key;
    set->value[set->count++] = strtod(value, NULL);
}

int main(int argc, char **argv)
{
    const char *make = NULL, *pack = NULL, *svg = NULL, *save_ref = NULL, *load_ref = NULL;
    const char *rtols = "1e-3 1e-4 1e-5 1e-6 1e-7", *strategies = "1 2 3", *strains = "0";
    size_t count = 805;
    double fraction = 0.0, friction = 0.1, ref_rtol = 1e-9;
    int ref_strategy = 2, repeat = 1, no_reference = 0;
    const char *scene = NULL, *save_runs = NULL, *compare_ref = NULL, *run_files = NULL;
    option_set sets = {0, {NULL}, {0}}, ref_sets = {0, {NULL}, {0}};
    double box[3] = {0.5e-3, 0.5e-3, 0.4e-3}, end = 5000.0;
    for (int k = 1; k < argc; ++k) {
        if (strcmp(argv[k], "--make-packing") == 0 && k + 1 < argc)
            make = argv[++k];
        else if (strcmp(argv[k], "--packing") == 0 && k + 1 < argc)
            pack = argv[++k];
        else if (strcmp(argv[k], "--scene") == 0 && k + 1 < argc)
            scene = argv[++k];
        else if (strcmp(argv[k], "--repeat") == 0 && k + 1 < argc)
            repeat = atoi(argv[++k]);
        else if (strcmp(argv[k], "--no-reference") == 0)
            no_reference = 1;
        else if (strcmp(argv[k], "--save-runs") == 0 && k + 1 < argc)
            save_runs = argv[++k];
        else if (strcmp(argv[k], "--compare") == 0 && k + 2 < argc) {
            compare_ref = argv[++k];
            run_files = argv[++k];
        } else if (strcmp(argv[k], "--fraction") == 0 && k + 1 < argc)
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
        else if (strcmp(argv[k], "--max-strains") == 0 && k + 1 < argc)
            strains = argv[++k];
        else if (strcmp(argv[k], "--set") == 0 && k + 2 < argc) {
            add_set(&sets, argv[k + 1], argv[k + 2]);
            k += 2;
        } else if (strcmp(argv[k], "--reference-set") == 0 && k + 2 < argc) {
            add_set(&ref_sets, argv[k + 1], argv[k + 2]);
            k += 2;
        } else if (strcmp(argv[k], "--save-reference") == 0 && k + 1 < argc)
            save_ref = argv[++k];
        else if (strcmp(argv[k], "--load-reference") == 0 && k + 1 < argc)
            load_ref = argv[++k];
        else if (strcmp(argv[k], "--reference") == 0 && k + 2 < argc) {
            ref_strategy = atoi(argv[++k]);
            ref_rtol = strtod(argv[++k], NULL);
        } else if (strcmp(argv[k], "--svg") == 0 && k + 1 < argc)
            svg = argv[++k];
        else {
            fprintf(stderr, "usage: qs_strategies --make-packing FILE [--count N] [--box LX LY LZ] "
                            "[--fraction F] [--friction MU]\n"
                            "       qs_strategies --packing FILE [--scene SCENE] [--repeat N] "
                            "[--end T] [--rtols LIST] "
                            "[--strategies LIST] [--max-strains LIST] [--set KEY VALUE]...\n"
                            "                     [--reference S RTOL] [--reference-set KEY "
                            "VALUE]... [--save-reference PATH | --load-reference PATH] "
                            "[--svg PATH]\n");
            return 2;
        }
    }
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    if (make != NULL) {
        make_packing(make, count, box, fraction, friction);
        sinter_ctx_destroy(g_ctx);
        return 0;
    }
    if (compare_ref != NULL)
        return compare_files(compare_ref, run_files, end, svg, scene);
    if (pack == NULL) {
        fprintf(stderr, "qs_strategies: give --make-packing, --packing or --compare\n");
        return 2;
    }
    if (scene != NULL)
        load_scene(scene, &end); /* its end_time unless --end follows */
    for (int k = 1; k + 1 < argc; ++k)
        if (strcmp(argv[k], "--end") == 0)
            end = strtod(argv[k + 1], NULL);
    const spheres pk = read_spheres(pack);
    run ref;
    memset(&ref, 0, sizeof(ref));
    if (no_reference) {
        ref.shrink[0] = ref.shrink[1] = ref.shrink[2] = 1.0; /* no errors: compare with --compare */
    } else if (load_ref != NULL) {
        ref = load_reference(load_ref, end);
    } else {
        fprintf(stderr, "reference: strategy %d at rtol %g ...\n", ref_strategy, ref_rtol);
        ref = sinter_run(&pk, ref_strategy, ref_rtol, 0.0, &ref_sets, end);
        if (save_ref != NULL)
            save_reference(save_ref, &ref, end);
    }
    printf("reference (strategy %d, rtol %g, max strain %g, to %g s%s): %zu links, %llu global "
           "steps, %llu PCG iterations, shrinkage x %.6e y %.6e z %.6e, %.2f s CPU\n\n",
           ref.strategy, ref.rtol, ref.max_strain, end, load_ref ? ", loaded" : "", ref.links,
           (unsigned long long)ref.steps, (unsigned long long)ref.pcg, ref.shrink[0], ref.shrink[1],
           ref.shrink[2], ref.seconds);
    double strain_list[16];
    size_t nstrain = parse_numbers(strains, strain_list, 16);
    if (nstrain == 0)
        strain_list[nstrain++] = 0.0;
    static run runs[64];
    size_t nr = 0;
    printf("| strategy | rtol | max strain | CPU [s] | global steps | steps (CPU s) ending <1 / "
           "<10 / <100 / "
           "<1000 / >=1000 s | PCG iterations | CVODE steps (Jacobians) young / grown | links (not "
           "in the "
           "reference) | neck error median / 99 %% / "
           "max (link) | shrinkage error |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int rep = 0; rep < repeat; ++rep)
        for (const char *sp = strategies; *sp && nr < 64;) {
            char *se = NULL;
            const int s = (int)strtol(sp, &se, 10);
            if (se == sp)
                break;
            sp = se;
            for (size_t ms = 0; ms < (s == 3 ? nstrain : 1) && nr < 64; ++ms) {
                for (const char *rp = rtols; *rp && nr < 64;) {
                    char *re = NULL;
                    const double rt = strtod(rp, &re);
                    if (re == rp)
                        break;
                    rp = re;
                    runs[nr] = sinter_run(&pk, s, rt, s == 3 ? strain_list[ms] : 0.0, &sets, end);
                    compare(&runs[nr], &ref);
                    if (save_runs != NULL) {
                        char path[512];
                        snprintf(path, sizeof(path), "%s-s%d-r%.0e-m%.1e-%d.txt", save_runs, s, rt,
                                 runs[nr].max_strain, rep);
                        save_reference(path, &runs[nr], end);
                    }
                    char strain_text[32] = "-";
                    char cvode_text[96] = "-";
                    if (s == 3) {
                        snprintf(strain_text, sizeof(strain_text), "%.1e", runs[nr].max_strain);
                        snprintf(cvode_text, sizeof(cvode_text), "%llu (%llu) / %llu (%llu)",
                                 (unsigned long long)runs[nr].cvode_steps[0],
                                 (unsigned long long)runs[nr].cvode_jacobians[0],
                                 (unsigned long long)runs[nr].cvode_steps[1],
                                 (unsigned long long)runs[nr].cvode_jacobians[1]);
                    }
                    char decade_text[160] = "";
                    for (int d = 0; d < 5; ++d) {
                        const size_t len = strlen(decade_text);
                        snprintf(decade_text + len, sizeof(decade_text) - len, "%s%llu (%.1f)",
                                 d > 0 ? " / " : "", (unsigned long long)runs[nr].by_decade[d],
                                 runs[nr].cpu_by_decade[d]);
                    }
                    printf(
                        "| %d | %.0e | %s | %.3f | %llu | %s | %llu | %s | %zu (%zu) | %.1e / %.1e "
                        "/ %.1e (%llu-%llu) | %.2e |\n",
                        s, rt, strain_text, runs[nr].seconds, (unsigned long long)runs[nr].steps,
                        decade_text, (unsigned long long)runs[nr].pcg, cvode_text, runs[nr].links,
                        runs[nr].unmatched, runs[nr].neck_median, runs[nr].neck_p99,
                        runs[nr].neck_err, (unsigned long long)(runs[nr].worst_key / pk.n),
                        (unsigned long long)(runs[nr].worst_key % pk.n), runs[nr].shrink_err);
                    fflush(stdout);
                    nr++;
                }
            }
        }
    if (svg != NULL)
        write_svg(svg, runs, nr, scene != NULL ? scene : "805 copper spheres at 1293 K");
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
