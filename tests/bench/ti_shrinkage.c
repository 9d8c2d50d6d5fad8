/*
 * ti_shrinkage: why seed 001's titanium packing (examples/scenes/titanium_packing.scene) shrinks
 * more than its two-particle (pair) model while its necks follow the pairs (issue 7; the numbers
 * are in tests/bench/RESULTS.md, "Titanium packing's shrinkage against its pairs").
 *
 *   ti_shrinkage --make SCENE OUT [--count N] [--aspect A]
 *   ti_shrinkage --pairs SCENE PACKING [--schedule e14b|iso|cu] [--stride K] [--times LIST]
 *   ti_shrinkage --run SCENE PACKING [--schedule e14b|iso|cu] [--strategy S]
 *                [--new live|inert|off] [--times LIST] [--neck-stiffness 0|1]
 *
 * LIST: output times [s] in quotes, "720 1440 2160 3600 5040 7200 8880" by default (the last
 * one is the end). Schedules: e14b, the scene's furnace (793 K -> 1373 K at 1740 s, held to
 * 7140 s, 793 K at 8880 s); iso, 1373 K held; cu, 1293 K held (with copper_packing.scene as
 * SCENE, for the copper packing).
 *
 * SCENE gives the material (its first, titanium: table 4, alpha/beta at 1156 K) and, for
 * --make, the compaction options of its [compact] section.
 * --make: the scene's green body for N spheres (3619): radii normal, mean 32 um, std 3.2 um
 *   (truncated at 3 std), random sequential addition (seed 1) in a box 1.3 times the final one
 *   per axis, then sinter_pack_compact with the scene's options towards the final box, whose
 *   volume is the scene's 0.75 x 0.75 x 1.5 mm scaled by N / 3619 and whose z / x is A (2).
 *   Written as lines "x y z r" [m].
 * --pairs: the pair model (sinter_neck_two_particles, CVODE rtol 1e-8) along the schedule:
 *   (1) two spheres of the packing's mean radius seeded at 0 and at each output time but the
 *   last (a contact that forms during the run), (2) the population of the packing's actual
 *   initial links (every K-th, radii as in the packing): plain mean, and the mean weighted by
 *   R_m^2 L0 (the weight of a link's strain in the packing's homogeneous strain, see below),
 *   (3) 40 pairs of radii drawn from the distribution (how session 1's reference was made).
 * --run: the quasi-static stepper (strategy S, 2 as in the scene) on the packing along the
 *   schedule to the last output time, with an observer after every global step that follows each
 *   link from its birth: its natural (7DOF) approach, the sum of the per-step decrements d4 + d7 of
 *   eq. 43, and its mechanical approach L0 - y4 - y7 (after eq. 41-44 it is the sum of the link's
 *   compressions xi). --new inert: links born during the run get zero grain-boundary and lattice
 *   diffusion (no natural approach, docs/7dof.md sec. 3); off: also 1e-6 of the beam stiffness (as
 * if they were not detected). Prints, at the output times, the shrinkage, per cohort (links present
 *   at the start / born during the run) the mean natural and mechanical strains, and the affine
 *   estimate of the shrinkage: the sum over the global steps of the R_m^2 L0-weighted mean natural
 *   strain increment of the links present in that step, and per axis the diagonal strain increment
 *   that best carries those increments (weighted least squares over the links' directions).
 *
 * Why R_m^2 L0: the global step solves K u = f with f the sintering forces k_k d_k e_k of the
 * links' natural approaches d_k (k_k = E pi R_m^2 / L0, eq. 17 = eq. 34a times d_k). A uniform
 * contraction u = -x is a beam deformation without shear or bending, so the solution satisfies
 * sum_k k_k L_k (xi_k - d_k) = 0 (up to the principal-plane conditions): the mechanical
 * approaches carry the natural ones with weights k_k L_k ~ R_m^2, and the homogeneous strain
 * fitted to an affine field is sum k L d / sum k L^2 = sum w (d / L0) / sum w with w = R_m^2 L0.
 *
 * CPU time is CLOCK_PROCESS_CPUTIME_ID.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "ti_shrinkage"
#include "bench_support.h"
#include "sinter.h"
#include "io/scene.h"
#include "stepper/qs_struct.h"
#include "stepper/quasistatic.h"
#include "stepper/stepper.h"

/* E14B from 793 K (the scene's furnace) or 1373 K held. */
static const double E14B_TIMES[4] = {0.0, 1740.0, 7140.0, 8880.0};
static const double E14B_TEMPS[4] = {793.0, 1373.0, 1373.0, 793.0};
static const double ISO_TIMES[1] = {0.0};
static const double ISO_TEMPS[1] = {1373.0};
static const double CU_TEMPS[1] = {1293.0};

typedef struct schedule {
    size_t n;
    const double *times, *temps;
} schedule;

static schedule schedule_named(const char *name)
{
    if (strcmp(name, "iso") == 0)
        return (schedule){1, ISO_TIMES, ISO_TEMPS};
    if (strcmp(name, "cu") == 0) /* the copper packing's 1293 K (with the copper scene) */
        return (schedule){1, ISO_TIMES, CU_TEMPS};
    if (strcmp(name, "e14b") != 0) {
        fprintf(stderr, "ti_shrinkage: --schedule e14b, iso or cu\n");
        exit(2);
    }
    return (schedule){4, E14B_TIMES, E14B_TEMPS};
}

static double temperature_at(const schedule *s, double t)
{
    if (t <= s->times[0])
        return s->temps[0];
    for (size_t k = 1; k < s->n; ++k)
        if (t <= s->times[k])
            return s->temps[k - 1] + (s->temps[k] - s->temps[k - 1]) * (t - s->times[k - 1]) /
                                         (s->times[k] - s->times[k - 1]);
    return s->temps[s->n - 1];
}

/* The schedule from t_birth on (the first point at t_birth): the furnace a contact born then
 * sees. */
static size_t schedule_from(const schedule *s, double t_birth, double *times, double *temps)
{
    size_t m = 0;
    times[m] = t_birth;
    temps[m++] = temperature_at(s, t_birth);
    for (size_t k = 0; k < s->n; ++k)
        if (s->times[k] > t_birth) {
            times[m] = s->times[k];
            temps[m++] = s->temps[k];
        }
    return m;
}

/* The scene's first material, cloned; the scene is kept for --make. */
static sinter_material *scene_material(const char *path, sinter_scene **keep)
{
    sinter_scene *sc = NULL;
    CHECK(sinter_scene_load(&sc, g_ctx, path));
    sinter_material *m = NULL;
    CHECK(sinter_material_clone(&m, sc->materials[0]));
    if (keep != NULL)
        *keep = sc;
    else
        sinter_scene_destroy(sc);
    return m;
}

/* ---- --make ------------------------------------------------------------------------------ */

static void make_packing(const char *scene_path, const char *out, size_t count, double aspect)
{
    sinter_scene *sc = NULL;
    sinter_material *ti = scene_material(scene_path, &sc);
    const double volume = 0.75e-3 * 0.75e-3 * 1.5e-3 * (double)count / 3619.0;
    const double lx = cbrt(volume / aspect), box[3] = {lx, lx, aspect * lx};
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, ti));
    pack_normal(ps, box, 1.3, 32e-6, 3.2e-6, 1, 793.0, count);
    sinter_compaction_options co = sc->compact_options;
    double cpu = 0.0;
    const sinter_compaction_result res = compact_into(ps, &co, box, &cpu);
    fprintf(stderr,
            "packing: %zu spheres, box %.4g x %.4g x %.4g mm%s, fraction %.4f, coordination "
            "%.2f, %.1f s CPU\n",
            count, 1e3 * (res.box_max[0] - res.box_min[0]), 1e3 * (res.box_max[1] - res.box_min[1]),
            1e3 * (res.box_max[2] - res.box_min[2]), res.jammed ? " (jammed)" : "",
            res.volume_fraction, res.coordination, cpu);
    char header[160];
    snprintf(header, sizeof(header),
             "titanium green body (ti_shrinkage --make): x y z r [m]; %zu spheres, fraction %.6f",
             count, res.volume_fraction);
    write_spheres(out, ps, header);
    sinter_particles_destroy(ps);
    sinter_material_destroy(ti);
    sinter_scene_destroy(sc);
}

/* ---- --pairs ----------------------------------------------------------------------------- */

#define MAX_OUT 16

/* Pair model seeded at t_birth along s; shrinkage and neck ratio (x / min R) at out[]. */
static void pair_run(sinter_neck_model *nm, const sinter_material *m, const schedule *s, double ra,
                     double rb, double t_birth, size_t n_out, const double *out, double *shrink,
                     double *ratio)
{
    double times[8], temps[8];
    const size_t nt = schedule_from(s, t_birth, times, temps);
    double t_ok[MAX_OUT] = {0}, x[MAX_OUT] = {0}, dl[MAX_OUT] = {0};
    size_t k0 = 0;
    for (size_t k = 0; k < n_out; ++k)
        if (out[k] >= t_birth)
            t_ok[k0++] = out[k];
    CHECK(sinter_neck_two_particles(nm, m, ra, rb, nt, times, temps, k0, t_ok, x, dl, NULL));
    for (size_t k = 0, j = 0; k < n_out; ++k) {
        if (out[k] >= t_birth) {
            shrink[k] = dl[j];
            ratio[k] = x[j] / fmin(ra, rb);
            ++j;
        } else {
            shrink[k] = ratio[k] = 0.0;
        }
    }
}

/* Normal radius (Box-Muller with a small LCG) truncated at 3 std, as the RSA draws them. */
static double draw_radius(uint64_t *state)
{
    for (;;) {
        double u[2];
        for (int k = 0; k < 2; ++k) {
            *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
            u[k] = ((double)(*state >> 11) + 0.5) / 9007199254740992.0;
        }
        const double g = sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
        if (fabs(g) <= 3.0)
            return 32e-6 + 3.2e-6 * g;
    }
}

static void pairs(const char *scene_path, const char *pack_path, const schedule *s, size_t stride,
                  const char *time_list)
{
    sinter_material *ti = scene_material(scene_path, NULL);
    sinter_neck_model *nm = NULL;
    CHECK(sinter_neck_model_create(&nm, g_ctx));
    double out[MAX_OUT];
    const size_t n_out = parse_numbers(time_list, out, MAX_OUT);
    double shrink[MAX_OUT], ratio[MAX_OUT];
    const double t0 = cpu_seconds();

    /* The packing's initial links. */
    const spheres pk = read_spheres(pack_path);
    uint64_t *keys = NULL;
    size_t cap = 0, found = 0;
    CHECK(sinter_qs_touching_pairs(g_ctx, pk.n, pk.x, pk.r, 1e-9, 0.0, &keys, &cap, &found));
    double rmean_particles = 0.0;
    for (size_t i = 0; i < pk.n; ++i)
        rmean_particles += pk.r[i] / (double)pk.n;
    printf("## pair model of the mean radius (%.2f um), seeded at the birth time\n\n| birth [s] "
           "| T at birth [K] |",
           1e6 * rmean_particles);
    for (size_t k = 0; k < n_out; ++k)
        printf(" %g s |", out[k]);
    printf("\n|---|---|");
    for (size_t k = 0; k < n_out; ++k)
        printf("---|");
    printf("\n");
    for (size_t b = 0; b < n_out; ++b) {
        const double birth = b == 0 ? 0.0 : out[b - 1];
        pair_run(nm, ti, s, rmean_particles, rmean_particles, birth, n_out, out, shrink, ratio);
        printf("| %g | %.0f |", birth, temperature_at(s, birth));
        for (size_t k = 0; k < n_out; ++k)
            if (out[k] > birth)
                printf(" %.3e (%.3f) |", shrink[k], ratio[k]);
            else
                printf(" |");
        printf("\n");
    }
    printf("\n(cells: shrinkage dL/L0 (neck ratio x/R))\n\n");

    double sum[MAX_OUT] = {0}, sumw[MAX_OUT] = {0}, sumr[MAX_OUT] = {0}, wsum = 0.0;
    double rsum = 0.0, r2sum = 0.0;
    size_t used = 0;
    for (size_t c = 0; c < found; c += stride) {
        const size_t a = (size_t)(keys[c] / pk.n), b = (size_t)(keys[c] % pk.n);
        const double ra = pk.r[a], rb = pk.r[b], rm = 0.5 * (ra + rb), w = rm * rm * (ra + rb);
        pair_run(nm, ti, s, ra, rb, 0.0, n_out, out, shrink, ratio);
        for (size_t k = 0; k < n_out; ++k) {
            sum[k] += shrink[k];
            sumw[k] += w * shrink[k];
            sumr[k] += ratio[k];
        }
        wsum += w;
        rsum += rm;
        r2sum += rm * rm;
        ++used;
    }
    const double rmean = rsum / (double)used;
    printf("## pair model over the packing's initial links: %zu of %zu links (every %zu-th), "
           "R_m mean %.3f um, std %.3f um\n\n",
           used, found, stride, 1e6 * rmean,
           1e6 * sqrt(fmax(0.0, r2sum / (double)used - rmean * rmean)));
    printf("| t [s] | T [K] | mean shrinkage | R_m^2 L0-weighted shrinkage | mean neck ratio |\n"
           "|---|---|---|---|---|\n");
    for (size_t k = 0; k < n_out; ++k)
        printf("| %g | %.0f | %.4e | %.4e | %.4f |\n", out[k], temperature_at(s, out[k]),
               sum[k] / (double)used, sumw[k] / wsum, sumr[k] / (double)used);

    /* 40 pairs of radii drawn from the distribution (session 1's reference). */
    uint64_t state = 40;
    double dsum[MAX_OUT] = {0}, dratio[MAX_OUT] = {0};
    for (int p = 0; p < 40; ++p) {
        const double ra = draw_radius(&state), rb = draw_radius(&state);
        pair_run(nm, ti, s, ra, rb, 0.0, n_out, out, shrink, ratio);
        for (size_t k = 0; k < n_out; ++k) {
            dsum[k] += shrink[k] / 40.0;
            dratio[k] += ratio[k] / 40.0;
        }
    }
    printf("\n## pair model over 40 pairs of radii drawn from N(32, 3.2) um (titanium)\n\n| t [s] "
           "| mean "
           "shrinkage | mean neck ratio |\n|---|---|---|\n");
    for (size_t k = 0; k < n_out; ++k)
        printf("| %g | %.4e | %.4f |\n", out[k], dsum[k], dratio[k]);
    printf("\n%.1f s CPU\n", cpu_seconds() - t0);
    free(keys);
    free(pk.x);
    free(pk.r);
    sinter_neck_model_destroy(nm);
    sinter_material_destroy(ti);
}

/* ---- --run ------------------------------------------------------------------------------- */

enum { NEW_LIVE, NEW_INERT, NEW_OFF };

typedef struct tracker {
    int mode;
    size_t initial; /* links after the first step (present at the start) */
    size_t count, cap;
    double *birth;     /* [s] */
    double *natural;   /* sum of d4 + d7 [m] */
    double *orient;    /* 3 per link: e_d^2 at birth */
    double *overlap;   /* (R_A + R_B - centre distance) / L0 at birth */
    double affine;     /* sum over the steps of sum w dd / L0 / sum w over the links of the step */
    double affine3[3]; /* the same along x, y, z (below) */
    uint64_t steps;
} tracker;

static int observe(const sinter_stepper *st, double time, void *user)
{
    tracker *tr = user;
    const sinter_qs *qs = st->quasistatic;
    if (qs == NULL)
        return 0;
    tr->steps++;
    if (qs->count > tr->cap) {
        tr->cap = 2 * qs->count;
        tr->birth = realloc(tr->birth, tr->cap * sizeof(double));
        tr->natural = realloc(tr->natural, tr->cap * sizeof(double));
        tr->orient = realloc(tr->orient, 3 * tr->cap * sizeof(double));
        tr->overlap = realloc(tr->overlap, tr->cap * sizeof(double));
    }
    /* Along x, y, z: the diagonal strain increment e that best carries the links' natural
     * strain increments, min sum w (sum_i e_i n_i^2 - dd / L0)^2: A e = b with
     * A_ij = sum w n_i^2 n_j^2, b_i = sum w (dd / L0) n_i^2. */
    double wsum = 0.0, wd = 0.0, A[3][3] = {{0}}, bv[3] = {0};
    for (size_t k = 0; k < tr->count; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const double dd = l->neck.last_dy4 + l->neck.last_dy7, l0 = l->neck.center_distance0;
        const double w = l->beam.k_axial * l0 * l0; /* E pi R_m^2 L0 (times 1e-6 when off) */
        tr->natural[k] += dd;
        wsum += w;
        wd += w * dd / l0;
        const double *e = l->beam.axis;
        for (int i = 0; i < 3; ++i) {
            bv[i] += w * dd / l0 * e[i] * e[i];
            for (int j = 0; j < 3; ++j)
                A[i][j] += w * e[i] * e[i] * e[j] * e[j];
        }
    }
    if (wsum > 0.0) {
        tr->affine += wd / wsum;
        /* Cramer's rule on the 3 x 3 system */
        const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                           A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                           A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
        for (int c = 0; c < 3 && det != 0.0; ++c) {
            double M[3][3];
            memcpy(M, A, sizeof(M));
            for (int r = 0; r < 3; ++r)
                M[r][c] = bv[r];
            tr->affine3[c] += (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                               M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                               M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
                              det;
        }
    }
    for (size_t k = tr->count; k < qs->count; ++k) {
        sinter_qs_link *l = &qs->links[k];
        tr->birth[k] = tr->steps == 1 ? 0.0 : time;
        tr->natural[k] = 0.0;
        double d2 = 0.0;
        for (int d = 0; d < 3; ++d) {
            tr->orient[3 * k + (size_t)d] = l->beam.axis[d] * l->beam.axis[d];
            const double dd =
                st->ps->x[3 * l->beam.b + (size_t)d] - st->ps->x[3 * l->beam.a + (size_t)d];
            d2 += dd * dd;
        }
        tr->overlap[k] = 1.0 - sqrt(d2) / l->neck.center_distance0;
        if (tr->steps > 1 && tr->mode != NEW_LIVE) {
            for (int p = 0; p < 2; ++p) {
                l->material.phase[p].boundary_d0 = 0.0;
                l->material.phase[p].lattice_d0 = 0.0;
            }
            if (tr->mode == NEW_OFF) {
                l->beam.k_axial *= 1e-6;
                l->beam.k_shear *= 1e-6;
                l->beam.k_bend *= 1e-6;
                l->beam.k_torsion *= 1e-6;
                l->youngs *= 1e-6;
            }
        }
    }
    tr->count = qs->count;
    if (tr->steps == 1)
        tr->initial = qs->count;
    return 0;
}

typedef struct cohort {
    size_t n;
    double nat, mech, ratio, w, wnat, wmech, ez2, overlap;
} cohort;

static void report(const sinter_stepper *st, const tracker *tr, const schedule *s, double t,
                   double cpu)
{
    const sinter_qs *qs = st->quasistatic;
    sinter_sintering_stats ss;
    memset(&ss, 0, sizeof(ss));
    ss.struct_size = sizeof(ss);
    CHECK(sinter_stepper_sintering_stats(st, &ss));
    cohort c[2];
    memset(c, 0, sizeof(c));
    double wall = 0.0;
    for (size_t k = 0; k < qs->count && k < tr->count; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const double *y = l->neck.y, l0 = l->neck.center_distance0;
        const double w = l->rm * l->rm * l0;
        cohort *h = &c[k >= tr->initial];
        const double nat = tr->natural[k] / l0;
        const double mech = (l0 - y[SINTER_NECK_LA] - y[SINTER_NECK_LB]) / l0;
        h->n++;
        h->nat += nat;
        h->mech += mech;
        h->ratio += y[SINTER_NECK_X] / fmin(y[SINTER_NECK_RA], y[SINTER_NECK_RB]);
        h->w += w;
        h->wnat += w * nat;
        h->wmech += w * mech;
        h->ez2 += tr->orient[3 * k + 2];
        h->overlap += tr->overlap[k];
        wall += w;
    }
    printf("| %g | %.0f | %zu | %zu | %.3e / %.3e / %.3e | %.4f | %.3e | %.3e | %.4f | %.3e "
           "| %.3e | %.4f | %.3e | %.3e | %.3e / %.3e / %.3e | %.3f | %.3f | %.1e / %.1e | %.1f "
           "|\n",
           t, temperature_at(s, t), c[0].n, c[1].n, ss.shrinkage[0], ss.shrinkage[1],
           ss.shrinkage[2], ss.neck_ratio_mean, c[0].n ? c[0].wnat / c[0].w : 0.0,
           c[0].n ? c[0].wmech / c[0].w : 0.0, c[0].n ? c[0].ratio / (double)c[0].n : 0.0,
           c[1].n ? c[1].wnat / c[1].w : 0.0, c[1].n ? c[1].wmech / c[1].w : 0.0,
           c[1].n ? c[1].ratio / (double)c[1].n : 0.0, (c[0].wnat + c[1].wnat) / wall, tr->affine,
           tr->affine3[0], tr->affine3[1], tr->affine3[2], c[0].n ? c[0].ez2 / (double)c[0].n : 0.0,
           c[1].n ? c[1].ez2 / (double)c[1].n : 0.0, c[0].n ? c[0].overlap / (double)c[0].n : 0.0,
           c[1].n ? c[1].overlap / (double)c[1].n : 0.0, cpu);
    fflush(stdout);
}

/* qs_neck_stiffness of --run (--neck-stiffness): 1 grows each link's section with its neck */
static double g_neck_stiffness = 0.0;

static void run(const char *scene_path, const char *pack_path, const schedule *s, int strategy,
                int mode, const char *time_list)
{
    sinter_material *ti = scene_material(scene_path, NULL);
    const spheres pk = read_spheres(pack_path);
    double temperature0 = s->temps[0];
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, ti));
    CHECK(sinter_particles_add(ps, pk.n, pk.x, pk.r, 0, temperature0, NULL));
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    CHECK(sinter_stepper_set_option(st, "qs_strategy", strategy));
    CHECK(sinter_stepper_set_option(st, "qs_neck_stiffness", g_neck_stiffness));
    CHECK(sinter_stepper_set_dt(st, 1e-6));
    CHECK(sinter_stepper_set_furnace(st, s->n, s->times, s->temps));
    tracker tr;
    memset(&tr, 0, sizeof(tr));
    tr.mode = mode;
    CHECK(sinter_stepper_set_observer(st, observe, &tr));
    double out[MAX_OUT];
    const size_t n_out = parse_numbers(time_list, out, MAX_OUT);
    printf("%zu spheres, strategy %d, new links %s, qs_neck_stiffness %g\n\n", pk.n, strategy,
           mode == NEW_LIVE    ? "live"
           : mode == NEW_INERT ? "inert"
                               : "off",
           g_neck_stiffness);
    printf("| t [s] | T [K] | links at start | born since | shrinkage x / y / z | neck ratio | "
           "start: natural | start: mechanical | start: ratio | born: natural | born: "
           "mechanical | born: ratio | all: natural | affine estimate | affine x / y / z | start: "
           "e_z^2 "
           "| born: e_z^2 | overlap at birth start / born | CPU [s] |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    const double t0 = cpu_seconds();
    for (size_t k = 0; k < n_out; ++k) {
        CHECK(sinter_stepper_advance(st, out[k]));
        report(st, &tr, s, out[k], cpu_seconds() - t0);
    }
    printf("\n(strains: R_m^2 L0-weighted means of the natural approach sum(d4 + d7) / L0 and of "
           "the mechanical approach (L0 - y4 - y7) / L0; affine estimate: the sum over the steps "
           "of the k L0^2-weighted mean natural strain increment of the links of the step; "
           "%llu global steps)\n",
           (unsigned long long)tr.steps);
    free(tr.birth);
    free(tr.natural);
    free(tr.orient);
    free(tr.overlap);
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(ti);
    free(pk.x);
    free(pk.r);
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *a = NULL, *mode = NULL, *sched = "e14b";
    const char *times = "720 1440 2160 3600 5040 7200 8880";
    const char *newmode = "live";
    size_t count = 3619, stride = 1;
    double aspect = 2.0;
    int strategy = 2;
    for (int k = 1; k < argc; ++k) {
        if ((strcmp(argv[k], "--make") == 0 || strcmp(argv[k], "--pairs") == 0 ||
             strcmp(argv[k], "--run") == 0) &&
            k + 2 < argc) {
            mode = argv[k] + 2;
            scene = argv[++k];
            a = argv[++k];
        } else if (strcmp(argv[k], "--count") == 0 && k + 1 < argc)
            count = (size_t)strtoull(argv[++k], NULL, 10);
        else if (strcmp(argv[k], "--aspect") == 0 && k + 1 < argc)
            aspect = strtod(argv[++k], NULL);
        else if (strcmp(argv[k], "--stride") == 0 && k + 1 < argc)
            stride = (size_t)strtoull(argv[++k], NULL, 10);
        else if (strcmp(argv[k], "--schedule") == 0 && k + 1 < argc)
            sched = argv[++k];
        else if (strcmp(argv[k], "--times") == 0 && k + 1 < argc)
            times = argv[++k];
        else if (strcmp(argv[k], "--strategy") == 0 && k + 1 < argc)
            strategy = atoi(argv[++k]);
        else if (strcmp(argv[k], "--new") == 0 && k + 1 < argc)
            newmode = argv[++k];
        else if (strcmp(argv[k], "--neck-stiffness") == 0 && k + 1 < argc)
            g_neck_stiffness = strtod(argv[++k], NULL);
        else {
            fprintf(stderr, "usage: ti_shrinkage --make SCENE OUT [--count N] [--aspect A]\n"
                            "       ti_shrinkage --pairs SCENE PACKING [--schedule e14b|iso|cu] "
                            "[--stride K] [--times LIST]\n"
                            "       ti_shrinkage --run SCENE PACKING [--schedule e14b|iso|cu] "
                            "[--strategy S] [--new live|inert|off] [--times LIST] "
                            "[--neck-stiffness 0|1]\n");
            return 2;
        }
    }
    if (mode == NULL || stride == 0) {
        fprintf(stderr, "ti_shrinkage: give --make, --pairs or --run (see the file's header)\n");
        return 2;
    }
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    const schedule s = schedule_named(sched);
    if (strcmp(mode, "make") == 0)
        make_packing(scene, a, count, aspect);
    else if (strcmp(mode, "pairs") == 0)
        pairs(scene, a, &s, stride, times);
    else
        run(scene, a, &s, strategy,
            strcmp(newmode, "inert") == 0 ? NEW_INERT
            : strcmp(newmode, "off") == 0 ? NEW_OFF
                                          : NEW_LIVE,
            times);
    sinter_ctx_destroy(g_ctx);
    return 0;
}
