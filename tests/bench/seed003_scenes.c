/*
 * seed003_scenes: the numbers of seed 003's examples 5.1-5.4 (the "Heat" issue), recorded in
 * tests/bench/RESULTS.md ("Seed 003 scenes (heat)"). Public API only. Each subcommand loads the
 * example scene file (materials, particles, walls) with sinter_scene_load and drives its own
 * steppers over the scene's particles and walls:
 *
 *   seed003_scenes hot_floor      [--scene examples/scenes/hot_floor.scene]
 *   seed003_scenes conduction_box [--scene ...] [--solid-volume V] [--dt LIST] [--t-end S]
 *                                 [--softening THETA_STAR] [--cycle S]
 *   seed003_scenes laser_bed      [--scene ...] [--dt S] [--coupled-steps N] [--sensitivity]
 *                                 [--checkpoint FILE]
 *   seed003_scenes vibrated_bed   [--scene ...] [--t-end S]
 *
 * hot_floor (sec. 5.1): a particle settling on a 700 K floor with and without thermal
 *   softening; static force, overlap, contact area, temperature at 8 s, times to equilibrium
 *   (700 K - theta < eps for eps = 1, 0.1, 0.01 K). Also the same two runs with the heat
 *   capacity x2, x3, x4 (the time constant m C d / (k A) x2..x4, i.e. the particle's
 *   conductance to the floor divided by 2..4), to show which time constant and which quantity
 *   the seed's "7 % higher at 8 s" needs.
 * conduction_box (sec. 5.3): pour (RSA + settle under gravity with hertz_mindlin at the stable
 *   Hertz step, sinter_pack_pour), then freeze the particles and run a second stepper with only
 *   the conduction model, implicit, hot wall (normal +x) at 1000 K, cold wall (normal -x) at
 *   300 K, the other walls adiabatic (the scene's k = 0). Effective conductivity from the
 *   seed's estimator sum m C dtheta / (grad T A t), from the heat that entered through the hot
 *   wall, and from the steady flux through the cold wall; Hashin-Shtrikman bounds (eq. 48).
 *   The wall heat flows are the library's (a contact snapshot after each step), so that the
 *   energy balance holds whatever the wall law.
 *   --solid-volume V keeps only the lowest particles of the RSA, V m^3 of solid (0.65e-3 m^3
 *   fills the seed's 0.1 m cube at the volume fraction the pour reaches). --softening THETA:
 *   exponential softening (eq. 42) with theta* = THETA, the mechanics re-settled (particles
 *   released, sinter_pack_pour) every --cycle seconds of thermal time (quasi-static
 *   staggering: thermal times are seconds, mechanical ones milliseconds).
 * laser_bed (sec. 5.4): pour to rest with the scene's step (5e-7 s), then freeze the
 *   mechanics and run heat-only steppers (conduction + laser [+ convection + radiation]) with
 *   a larger explicit step; "lit" = every particle whose centre has been inside the beam's
 *   cylinder at the start of some step while the beam was on. Mean and maximum temperature of
 *   the lit particles 0.24 s after the beam switches on. --coupled-steps N (needs
 *   --checkpoint) times N fully coupled steps (mechanics + heat at 5e-7 s) to estimate the cost
 *   of the unfrozen run, and compares the lit temperatures after them with a frozen run of the
 *   same beam time from the same poured bed.
 *   --sensitivity adds absorptance, attenuation, emissivity and intensity variations.
 *   --checkpoint FILE writes the poured bed there, or reads it if the file exists.
 * vibrated_bed (sec. 5.2): the scene's vibrated slab with conduction, with and without
 *   convection (air at 273 K), for --t-end seconds (the seed runs 60 s); mean and maximum
 *   temperature every 0.1 s (every 0.5 s printed on long runs).
 *
 * Paths are relative to the repository root (run from there after the README's build).
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c11 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "seed003_scenes"
#include "bench_support.h"
#include "sinter.h"

static const double PI = 3.14159265358979323846;
/* ---- small helpers over the public API ------------------------------------------------ */

typedef struct loaded {
    sinter_scene *scene;
    sinter_particles *ps;
    sinter_walls *walls;
    size_t n;
} loaded;

static loaded load(const char *path)
{
    loaded l;
    memset(&l, 0, sizeof(l));
    CHECK(sinter_scene_load(&l.scene, g_ctx, path));
    CHECK(sinter_scene_get_particles(l.scene, &l.ps));
    CHECK(sinter_scene_get_walls(l.scene, &l.walls));
    CHECK(sinter_particles_count(l.ps, &l.n));
    return l;
}

static double *view(sinter_particles *ps, sinter_field f)
{
    void *d = NULL;
    CHECK(sinter_particles_view(ps, f, &d, NULL, NULL));
    return d;
}

static const double *view_read(const sinter_particles *ps, sinter_field f)
{
    const void *d = NULL;
    CHECK(sinter_particles_view_read(ps, f, &d, NULL, NULL));
    return d;
}

static void release(const sinter_particles *ps, sinter_field f)
{
    CHECK(sinter_particles_release(ps, f));
}

/* Material id of particle 0 (every seed 003 scene has one particle material). */
static int32_t material_id(const sinter_particles *ps)
{
    const void *d = NULL;
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_MATERIAL, &d, NULL, NULL));
    const int32_t id = ((const int32_t *)d)[0];
    release(ps, SINTER_FIELD_MATERIAL);
    return id;
}

/* Replace one parameter of the particles' material (mass and inertia follow the density). */
static void set_particle_param(sinter_particles *ps, sinter_material_param p, double v)
{
    const int32_t id = material_id(ps);
    const sinter_material *m = NULL;
    sinter_material *c = NULL;
    CHECK(sinter_particles_get_material(ps, id, &m));
    CHECK(sinter_material_clone(&c, m));
    CHECK(sinter_material_set(c, p, v));
    CHECK(sinter_particles_set_material(ps, id, c));
    sinter_material_destroy(c);
}

static double particle_param(const sinter_particles *ps, sinter_material_param p)
{
    const sinter_material *m = NULL;
    double v = 0;
    CHECK(sinter_particles_get_material(ps, material_id(ps), &m));
    CHECK(sinter_material_get(m, p, &v));
    return v;
}

static void set_all_temperatures(sinter_particles *ps, size_t n, double theta)
{
    double *t = view(ps, SINTER_FIELD_TEMPERATURE);
    for (size_t i = 0; i < n; ++i)
        t[i] = theta;
    release(ps, SINTER_FIELD_TEMPERATURE);
}

/* Freeze (fixed = 1: positions not integrated, velocities and spins zeroed) or release. */
static void set_fixed(sinter_particles *ps, size_t n, int fixed)
{
    void *fl = NULL;
    CHECK(sinter_particles_view(ps, SINTER_FIELD_FLAGS, &fl, NULL, NULL));
    uint32_t *flags = fl;
    double *v = view(ps, SINTER_FIELD_VELOCITY), *w = view(ps, SINTER_FIELD_SPIN);
    for (size_t i = 0; i < n; ++i) {
        if (fixed) {
            flags[i] |= SINTER_PARTICLE_FIXED;
            for (int d = 0; d < 3; ++d)
                v[3 * i + d] = w[3 * i + d] = 0.0;
        } else {
            flags[i] &= ~(uint32_t)SINTER_PARTICLE_FIXED;
        }
    }
    release(ps, SINTER_FIELD_SPIN);
    release(ps, SINTER_FIELD_VELOCITY);
    release(ps, SINTER_FIELD_FLAGS);
}

static double kinetic_energy(const sinter_particles *ps, size_t n)
{
    const double *v = view_read(ps, SINTER_FIELD_VELOCITY), *m = view_read(ps, SINTER_FIELD_MASS);
    double ke = 0;
    for (size_t i = 0; i < n; ++i)
        ke += 0.5 * m[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] +
                            v[3 * i + 2] * v[3 * i + 2]);
    release(ps, SINTER_FIELD_MASS);
    release(ps, SINTER_FIELD_VELOCITY);
    return ke;
}

static sinter_force_model *force(const char *name)
{
    sinter_force_model *f = NULL;
    CHECK(sinter_force_model_create(&f, g_ctx, name));
    return f;
}

static sinter_heat_model *heat(const char *name)
{
    sinter_heat_model *h = NULL;
    CHECK(sinter_heat_model_create(&h, g_ctx, name));
    return h;
}

static sinter_stepper *stepper(const loaded *l, double dt)
{
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_EXPLICIT, l->ps, l->walls));
    CHECK(sinter_stepper_set_dt(st, dt));
    return st;
}

static sinter_stepper_stats stats_of(const sinter_stepper *st)
{
    sinter_stepper_stats s;
    memset(&s, 0, sizeof(s));
    s.struct_size = sizeof(s);
    CHECK(sinter_stepper_get_stats(st, &s));
    return s;
}

static const char *opt(int argc, char **argv, const char *name, const char *dflt)
{
    for (int a = 2; a + 1 < argc; ++a)
        if (strcmp(argv[a], name) == 0)
            return argv[a + 1];
    return dflt;
}

static int flag(int argc, char **argv, const char *name)
{
    for (int a = 2; a < argc; ++a)
        if (strcmp(argv[a], name) == 0)
            return 1;
    return 0;
}

static void print_machine(void)
{
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[256];
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            printf("# machine: %s", strchr(line, ':') ? strchr(line, ':') + 2 : line);
            break;
        }
    if (f)
        fclose(f);
    printf("# libsinter %s\n", sinter_version_string());
}

/* ======================================================================================= */
/* 5.1 hot floor                                                                            */
/* ======================================================================================= */

enum { FLOOR_SAMPLES = 400 }; /* every 0.1 s up to 40 s */

typedef struct floor_run {
    double force, force_early, overlap, area, theta8;
    double t_eq[3]; /* 700 - theta < 1, 0.1, 0.01 K */
    double theta[FLOOR_SAMPLES + 1];
} floor_run;

static floor_run hot_floor_run(const char *path, int softening, double c_scale)
{
    loaded l = load(path);
    if (!softening)
        set_particle_param(l.ps, SINTER_MAT_SOFTENING_LAW, 0.0);
    set_particle_param(l.ps, SINTER_MAT_HEAT_CAPACITY,
                       c_scale * particle_param(l.ps, SINTER_MAT_HEAT_CAPACITY));
    sinter_stepper *st = stepper(&l, 2e-5); /* the seed's step */
    sinter_force_model *hm = force("hertz_mindlin"), *g = force("gravity");
    CHECK(sinter_force_model_set(hm, "rolling", 0.0));
    CHECK(sinter_stepper_add_force(st, hm));
    CHECK(sinter_stepper_add_force(st, g));
    sinter_heat_model *cond = heat("conduction");
    CHECK(sinter_stepper_add_heat(st, cond));
    floor_run out;
    memset(&out, 0, sizeof(out));
    const double eps[3] = {1.0, 0.1, 0.01};
    for (int k = 0; k < 3; ++k)
        out.t_eq[k] = NAN;
    out.theta[0] = view_read(l.ps, SINTER_FIELD_TEMPERATURE)[0];
    release(l.ps, SINTER_FIELD_TEMPERATURE);
    double f[3];
    for (int k = 1; k <= FLOOR_SAMPLES; ++k) {
        CHECK(sinter_stepper_advance(st, 0.1 * k));
        const double th = view_read(l.ps, SINTER_FIELD_TEMPERATURE)[0];
        release(l.ps, SINTER_FIELD_TEMPERATURE);
        out.theta[k] = th;
        if (k == 80)
            out.theta8 = th;
        if (k == 1) {
            CHECK(sinter_walls_get_force(l.walls, 0, f));
            out.force_early = -f[2];
        }
        for (int e = 0; e < 3; ++e)
            if (isnan(out.t_eq[e]) && 700.0 - th < eps[e])
                out.t_eq[e] = 0.1 * k;
    }
    CHECK(sinter_walls_get_force(l.walls, 0, f));
    out.force = -f[2];
    const double z = view_read(l.ps, SINTER_FIELD_POSITION)[2];
    release(l.ps, SINTER_FIELD_POSITION);
    const double r = view_read(l.ps, SINTER_FIELD_RADIUS)[0];
    release(l.ps, SINTER_FIELD_RADIUS);
    out.overlap = r - z;
    out.area = PI * (r * r - z * z); /* seed 003 eq. 34 with the floor (L = z) */
    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(cond);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(g);
    sinter_scene_destroy(l.scene);
    return out;
}

static int cmd_hot_floor(int argc, char **argv)
{
    const char *path = opt(argc, argv, "--scene", "examples/scenes/hot_floor.scene");
    printf("# seed 003 sec. 5.1, scene %s, dt 2e-5 s, 40 s\n", path);
    const double scales[4] = {1.0, 2.0, 3.0, 4.0};
    for (int s = 0; s < 4; ++s) {
        const double t0 = now();
        floor_run plain = hot_floor_run(path, 0, scales[s]);
        floor_run soft = hot_floor_run(path, 1, scales[s]);
        printf("\n## heat capacity x%g (time constant m C d/(k A) x%g)%s   [%.1f s wall]\n",
               scales[s], scales[s], s == 0 ? " = the seed's data" : "", now() - t0);
        printf("%-12s %12s %12s %12s %12s %10s %8s %8s %8s\n", "case", "F_static N",
               "F(0.1 s) N", "overlap m", "area m^2", "theta(8s)", "t_eq<1K", "<0.1K",
               "<0.01K");
        const floor_run *runs[2] = {&plain, &soft};
        const char *names[2] = {"no soften", "softening"};
        for (int k = 0; k < 2; ++k)
            printf("%-12s %12.5e %12.5e %12.5e %12.5e %10.3f %8.1f %8.1f %8.1f\n", names[k],
                   runs[k]->force, runs[k]->force_early, runs[k]->overlap, runs[k]->area,
                   runs[k]->theta8, runs[k]->t_eq[0], runs[k]->t_eq[1], runs[k]->t_eq[2]);
        /* largest relative temperature difference over time, and the rise ratio at 8 s */
        double best = 0, tbest = 0, gap = 0, tgap = 0;
        for (int k = 0; k <= FLOOR_SAMPLES; ++k) {
            const double d = soft.theta[k] / plain.theta[k] - 1.0;
            if (d > best)
                best = d, tbest = 0.1 * k;
            if (soft.theta[k] - plain.theta[k] > gap)
                gap = soft.theta[k] - plain.theta[k], tgap = 0.1 * k;
        }
        printf("area ratio soft/plain %.4f; theta(8 s) soft/plain - 1 = %.2f %%; rise ratio "
               "(theta-300) at 8 s %.4f; largest theta_soft/theta_plain - 1 = %.2f %% at t = "
               "%.1f s; t_eq ratio (1 K) %.3f, (0.01 K) %.3f\n",
               soft.area / plain.area, 100 * (soft.theta8 / plain.theta8 - 1),
               (soft.theta8 - 300) / (plain.theta8 - 300), 100 * best, tbest,
               soft.t_eq[0] / plain.t_eq[0], soft.t_eq[2] / plain.t_eq[2]);
        printf("gap theta_soft - theta_plain at 8 s %.2f K (%.2f %% of the 400 K span); largest "
               "gap %.2f K (%.2f %% of the span) at t = %.1f s\n",
               soft.theta8 - plain.theta8, 100 * (soft.theta8 - plain.theta8) / 400, gap,
               100 * gap / 400, tgap);
        printf("theta(t) [K]  t:");
        const int ts[] = {5, 10, 20, 30, 40, 60, 80, 120, 180};
        for (size_t k = 0; k < sizeof ts / sizeof ts[0]; ++k)
            printf(" %5.1f", 0.1 * ts[k]);
        printf("\n  no soften   ");
        for (size_t k = 0; k < sizeof ts / sizeof ts[0]; ++k)
            printf(" %5.1f", plain.theta[ts[k]]);
        printf("\n  softening   ");
        for (size_t k = 0; k < sizeof ts / sizeof ts[0]; ++k)
            printf(" %5.1f", soft.theta[ts[k]]);
        printf("\n");
    }
    return 0;
}

/* ======================================================================================= */
/* 5.3 conduction box                                                                       */
/* ======================================================================================= */

/* Volume of the part of a sphere (centre height zc, radius r) between z = a and z = b. */
static double sphere_slab_volume(double zc, double r, double a, double b)
{
    const double lo = fmax(a - zc, -r), hi = fmin(b - zc, r);
    if (hi <= lo)
        return 0.0;
    /* integral of pi (r^2 - u^2) du from lo to hi */
    return PI * (r * r * (hi - lo) - (hi * hi * hi - lo * lo * lo) / 3.0);
}

typedef struct packing {
    double phi_plateau, phi_core, height, top, solid, coordination;
    size_t contacts, wall_contacts;
} packing;

/* Volume fraction in horizontal slabs over the whole cross-section (box_xy m^2). */
static packing measure_packing(const loaded *l, double box_x, double box_y,
                               const sinter_stepper *st)
{
    packing p;
    memset(&p, 0, sizeof(p));
    const double *x = view_read(l->ps, SINTER_FIELD_POSITION);
    const double *r = view_read(l->ps, SINTER_FIELD_RADIUS);
    for (size_t i = 0; i < l->n; ++i) {
        p.top = fmax(p.top, x[3 * i + 2] + r[i]);
        p.solid += 4.0 / 3.0 * PI * r[i] * r[i] * r[i];
    }
    /* plateau: mean fraction between 20 % and 80 % of the top */
    const double a = 0.2 * p.top, b = 0.8 * p.top;
    double vin = 0, vcore = 0;
    for (size_t i = 0; i < l->n; ++i) {
        const double v = sphere_slab_volume(x[3 * i + 2], r[i], a, b);
        vin += v;
        /* core: centres at least 1 cm from the x and y walls (approximate: whole spheres) */
        if (x[3 * i] > 0.01 && x[3 * i] < box_x - 0.01 && x[3 * i + 1] > 0.01 &&
            x[3 * i + 1] < box_y - 0.01)
            vcore += v;
    }
    p.phi_plateau = vin / (box_x * box_y * (b - a));
    p.phi_core = vcore / ((box_x - 0.02) * (box_y - 0.02) * (b - a));
    p.height = p.solid / (box_x * box_y * p.phi_plateau); /* uniform bed of that fraction */
    release(l->ps, SINTER_FIELD_RADIUS);
    release(l->ps, SINTER_FIELD_POSITION);
    if (st != NULL) {
        sinter_stepper_stats s = stats_of(st);
        p.contacts = (size_t)s.contacts;
        p.wall_contacts = (size_t)s.wall_contacts;
        p.coordination = 2.0 * (double)s.contacts / (double)l->n;
    }
    return p;
}

/* Hashin-Shtrikman bounds (seed 003 eq. 48) for k1 = matrix (void), k2 = particles. */
static void hashin_shtrikman(double k1, double k2, double v2, double *lo, double *hi)
{
    *lo = k1 > 0 ? k1 + v2 / (1.0 / (k2 - k1) + (1.0 - v2) / (3.0 * k1)) : 0.0;
    *hi = k2 + (1.0 - v2) / (1.0 / (k1 - k2) + v2 / (3.0 * k2));
}

/*
 * Heat flows of the hot and the cold wall as the library's conduction model computes them
 * (whatever its wall law: conduction.c), from a snapshot of the stepper's contacts
 * (SINTER_CONTACT_DATA_HEAT_FLOW of the wall contacts): *qh into the particles from the hot
 * wall, *qc out of the particles into the cold wall [W]. With cold_by_particle != NULL, each
 * particle's flow into the cold wall there (indexed as the particles). The snapshot is taken
 * after a step: with the implicit scheme, the flows of the step's new temperatures.
 */
static void wall_flows(const loaded *l, const sinter_stepper *st, size_t hot, size_t cold,
                       double *qh, double *qc, double *cold_by_particle)
{
    sinter_snapshot *snap = NULL;
    CHECK(sinter_snapshot_create(&snap, st));
    size_t np = 0, nw = 0;
    CHECK(sinter_snapshot_counts(snap, &np, &nw, NULL, NULL));
    const void *wd = NULL, *qd = NULL, *ida = NULL;
    CHECK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_WALL, &wd, NULL, NULL, NULL));
    CHECK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_HEAT_FLOW, &qd, NULL, NULL, NULL));
    CHECK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_A, &ida, NULL, NULL, NULL));
    const int32_t *w = wd;
    const double *q = qd;
    const uint64_t *id = ida;
    if (cold_by_particle != NULL)
        memset(cold_by_particle, 0, l->n * sizeof(double));
    *qh = *qc = 0.0;
    for (size_t c = np; c < np + nw; ++c) { /* the wall contacts follow the pairs */
        if (w[c] == (int32_t)hot)
            *qh += q[c]; /* into particle a from the wall */
        if (w[c] == (int32_t)cold) {
            *qc -= q[c];
            if (cold_by_particle != NULL) {
                size_t i = 0;
                CHECK(sinter_particles_find_id(l->ps, id[c], &i));
                cold_by_particle[i] -= q[c];
            }
        }
    }
    sinter_snapshot_destroy(snap);
}

/* Steady flux into the cold wall from particles in 4 height bands, as conductivities. */
static void band_conductivities(const loaded *l, const sinter_stepper *st, size_t hot, size_t cold,
                                double height)
{
    double *qcold = malloc(l->n * sizeof(double)), qh = 0, qc = 0;
    if (qcold == NULL)
        exit(1);
    wall_flows(l, st, hot, cold, &qh, &qc, qcold);
    const double *x = view_read(l->ps, SINTER_FIELD_POSITION);
    double q[4] = {0};
    for (size_t i = 0; i < l->n; ++i) {
        int b = (int)(x[3 * i + 2] / height * 4.0);
        b = b < 0 ? 0 : b > 3 ? 3 : b;
        q[b] += qcold[i];
    }
    release(l->ps, SINTER_FIELD_POSITION);
    free(qcold);
    printf("    k* from the cold-wall flux by height band (bottom to top quarter of H):");
    for (int b = 0; b < 4; ++b)
        printf(" %.3f", q[b] / (7000.0 * 0.1 * height / 4.0));
    printf(" W/(m K)\n");
}

static double stored_energy(const loaded *l, double c, double theta0)
{
    const double *t = view_read(l->ps, SINTER_FIELD_TEMPERATURE);
    const double *m = view_read(l->ps, SINTER_FIELD_MASS);
    double e = 0;
    for (size_t i = 0; i < l->n; ++i)
        e += m[i] * c * (t[i] - theta0);
    release(l->ps, SINTER_FIELD_MASS);
    release(l->ps, SINTER_FIELD_TEMPERATURE);
    return e;
}

/* Least-squares slope d theta / d x over particles with x in [x0, x1]. */
static double bulk_slope(const loaded *l, double x0, double x1)
{
    const double *x = view_read(l->ps, SINTER_FIELD_POSITION);
    const double *t = view_read(l->ps, SINTER_FIELD_TEMPERATURE);
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (size_t i = 0; i < l->n; ++i) {
        const double xi = x[3 * i];
        if (xi < x0 || xi > x1)
            continue;
        sx += xi, sy += t[i], sxx += xi * xi, sxy += xi * t[i], n += 1;
    }
    release(l->ps, SINTER_FIELD_TEMPERATURE);
    release(l->ps, SINTER_FIELD_POSITION);
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

static void temperature_profile(const loaded *l, double width)
{
    const double *x = view_read(l->ps, SINTER_FIELD_POSITION);
    const double *t = view_read(l->ps, SINTER_FIELD_TEMPERATURE);
    double s[10] = {0}, c[10] = {0};
    for (size_t i = 0; i < l->n; ++i) {
        int b = (int)(x[3 * i] / width * 10.0);
        b = b < 0 ? 0 : b > 9 ? 9 : b;
        s[b] += t[i], c[b] += 1;
    }
    release(l->ps, SINTER_FIELD_TEMPERATURE);
    release(l->ps, SINTER_FIELD_POSITION);
    printf("    profile (mean theta in 10 x-bins) K:");
    for (int b = 0; b < 10; ++b)
        printf(" %.0f", c[b] > 0 ? s[b] / c[b] : NAN);
    printf("\n");
}

/* Find the walls with normals +x (hot) and -x (cold). */
static void find_x_walls(const loaded *l, size_t *hot, size_t *cold)
{
    size_t nw = 0;
    CHECK(sinter_walls_count(l->walls, &nw));
    *hot = *cold = nw;
    for (size_t k = 0; k < nw; ++k) {
        double nrm[3];
        CHECK(sinter_walls_get_normal(l->walls, k, nrm));
        if (nrm[0] > 0.99)
            *hot = k;
        if (nrm[0] < -0.99)
            *cold = k;
    }
    if (*hot == nw || *cold == nw) {
        fprintf(stderr, "seed003_scenes: the scene needs walls with normals +x and -x\n");
        exit(1);
    }
}

typedef struct box_result {
    double k_seed350, k_in350, k_cold350, k_seed_end, k_cold_end, k_hot_end, k_bulk_end;
    double balance350, t_end, seconds;
    uint64_t pcg_steps;
} box_result;

/*
 * Heat-only run over the frozen packing: implicit conduction with step h to t_end, sampling at
 * 350 s. With mech != NULL (softening), the particles are released and re-settled with `mech`
 * every `cycle` seconds of thermal time.
 */
static box_result box_heat_run(loaded *l, double h, double t_end, double area,
                               sinter_stepper *mech, double cycle, int verbose)
{
    box_result res;
    memset(&res, 0, sizeof(res));
    const double grad = 700.0 / 0.1, c = particle_param(l->ps, SINTER_MAT_HEAT_CAPACITY);
    size_t hot, cold;
    find_x_walls(l, &hot, &cold);
    CHECK(sinter_walls_set_temperature(l->walls, hot, 1000.0)); /* clears the scene's schedule */
    CHECK(sinter_walls_set_temperature(l->walls, cold, 300.0));
    set_all_temperatures(l->ps, l->n, 300.0);
    set_fixed(l->ps, l->n, 1);
    sinter_stepper *st = stepper(l, h);
    sinter_heat_model *cond = heat("conduction");
    CHECK(sinter_stepper_add_heat(st, cond));
    CHECK(sinter_stepper_set_thermal_scheme(st, SINTER_THERMAL_IMPLICIT));
    const double t0 = now();
    double e_in = 0, e_out = 0, next_cycle = cycle;
    const uint64_t nsteps = (uint64_t)llround(t_end / h), n350 = (uint64_t)llround(350.0 / h);
    for (uint64_t s = 1; s <= nsteps; ++s) {
        CHECK(sinter_stepper_step(st, 1));
        const double t = (double)s * h;
        double qh = 0, qc = 0;
        wall_flows(l, st, hot, cold, &qh, &qc, NULL);
        e_in += h * qh; /* backward Euler: the fluxes of the new temperatures */
        e_out += h * qc;
        if (s == n350) {
            const double e = stored_energy(l, c, 300.0);
            res.k_seed350 = e / (grad * area * t);
            res.k_in350 = e_in / (grad * area * t);
            res.k_cold350 = qc / (grad * area);
            res.balance350 = (e - (e_in - e_out)) / e;
            if (verbose) {
                printf("  t = %.0f s: stored %.5g J, in %.5g J, out %.5g J, balance error "
                       "%.2e; Q_hot %.5g W, Q_cold %.5g W\n",
                       t, e, e_in, e_out, res.balance350, qh, qc);
                temperature_profile(l, 0.1);
            }
        }
        if (verbose && (s % (uint64_t)llround(100.0 / h) == 0) && s != n350)
            printf("  t = %4.0f s: Q_hot %.5g W, Q_cold %.5g W, stored %.5g J\n", t, qh, qc,
                   stored_energy(l, c, 300.0));
        if (mech != NULL && t >= next_cycle - 1e-9 && s < nsteps) {
            /* re-settle with the softened moduli, then refreeze (the heat stepper's next
             * step finds the new contacts) */
            set_fixed(l->ps, l->n, 0);
            CHECK(sinter_pack_pour(mech, 1e-10, 0.1, 2.0));
            set_fixed(l->ps, l->n, 1);
            next_cycle += cycle;
        }
    }
    const double e = stored_energy(l, c, 300.0);
    double qh = 0, qc = 0;
    wall_flows(l, st, hot, cold, &qh, &qc, NULL);
    res.t_end = t_end;
    res.k_seed_end = e / (grad * area * t_end);
    res.k_cold_end = qc / (grad * area);
    res.k_hot_end = qh / (grad * area);
    const double slope = bulk_slope(l, 0.02, 0.08);
    res.k_bulk_end = 0.5 * (qh + qc) / (area * fabs(slope));
    res.seconds = now() - t0;
    if (verbose) {
        printf("  t = %.0f s (end): Q_hot %.6g W, Q_cold %.6g W, bulk slope %.1f K/m "
               "(imposed 7000)\n",
               t_end, qh, qc, slope);
        temperature_profile(l, 0.1);
        band_conductivities(l, st, hot, cold, area / 0.1);
    }
    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(cond);
    return res;
}

static int cmd_conduction_box(int argc, char **argv)
{
    const char *path = opt(argc, argv, "--scene", "examples/scenes/conduction_box.scene");
    const double solid_keep = atof(opt(argc, argv, "--solid-volume", "0"));
    const int fill_cube = solid_keep > 0;
    const double t_end = atof(opt(argc, argv, "--t-end", "1500"));
    const double soft = atof(opt(argc, argv, "--softening", "0"));
    const double cycle = atof(opt(argc, argv, "--cycle", "25"));
    const char *dts = opt(argc, argv, "--dt", "0.5,0.25,0.1,0.05");
    printf("# seed 003 sec. 5.3, scene %s%s%s\n", path,
           fill_cube ? ", only the lowest spheres (--solid-volume)" : "",
           soft > 0 ? ", softening" : "");
    loaded l = load(path);
    if (fill_cube) {
        /* keep the lowest spheres of the RSA (uniform in z) up to solid_keep m^3 of solid */
        const double *x = view_read(l.ps, SINTER_FIELD_POSITION);
        const double *r = view_read(l.ps, SINTER_FIELD_RADIUS);
        size_t *order = malloc(l.n * sizeof(size_t)), *drop = malloc(l.n * sizeof(size_t));
        for (size_t i = 0; i < l.n; ++i)
            order[i] = i;
        /* sort the indices by height (shell sort on a copy of z) */
        double *z = malloc(l.n * sizeof(double));
        for (size_t i = 0; i < l.n; ++i)
            z[i] = x[3 * i + 2];
        for (size_t gap = l.n / 2; gap > 0; gap /= 2) /* shell sort */
            for (size_t i = gap; i < l.n; ++i)
                for (size_t j = i; j >= gap && z[order[j - gap]] > z[order[j]]; j -= gap) {
                    const size_t tmp = order[j];
                    order[j] = order[j - gap];
                    order[j - gap] = tmp;
                }
        double v = 0;
        size_t nd = 0;
        for (size_t k = 0; k < l.n; ++k) {
            const size_t i = order[k];
            if (v < solid_keep)
                v += 4.0 / 3.0 * PI * r[i] * r[i] * r[i];
            else
                drop[nd++] = i;
        }
        release(l.ps, SINTER_FIELD_RADIUS);
        release(l.ps, SINTER_FIELD_POSITION);
        CHECK(sinter_particles_remove(l.ps, nd, drop));
        CHECK(sinter_particles_count(l.ps, &l.n));
        free(order);
        free(drop);
        free(z);
    }
    if (soft > 0) {
        set_particle_param(l.ps, SINTER_MAT_SOFTENING_LAW, 2.0);
        set_particle_param(l.ps, SINTER_MAT_SOFTENING_TEMPERATURE, soft);
    }
    /* ---- pour: hertz_mindlin + gravity at the stable Hertz step for a 3.5 m/s impact ---- */
    double dt_mech = 0;
    CHECK(sinter_stable_dt_hertz(l.ps, l.walls, 3.5, &dt_mech));
    sinter_stepper *mech = stepper(&l, dt_mech);
    sinter_force_model *hm = force("hertz_mindlin"), *g = force("gravity");
    CHECK(sinter_stepper_add_force(mech, hm));
    CHECK(sinter_stepper_add_force(mech, g));
    double lo[3] = {-0.01, -0.01, -0.01}, hi[3] = {0.11, 0.11, 0.7};
    CHECK(sinter_stepper_set_domain(mech, lo, hi));
    double t0 = now();
    CHECK(sinter_pack_pour(mech, 1e-10, 0.5, 10.0));
    double t_pour = 0;
    CHECK(sinter_stepper_time(mech, &t_pour));
    const packing p = measure_packing(&l, 0.1, 0.1, mech);
    printf("N = %zu, solid volume %.4e m^3, mechanical dt %.3e s (seed 003 eq. 47, v = 3.5 "
           "m/s); at rest (KE < 1e-10 J per particle) after %.3f s of pouring, %.1f s wall\n",
           l.n, p.solid, dt_mech, t_pour, now() - t0);
    printf("packing: volume fraction %.4f (plateau, whole cross-section), %.4f (core, 1 cm "
           "from the side walls), top of the highest sphere %.4f m, bed height at the plateau "
           "fraction H = %.4f m, coordination %.2f, %zu contacts, %zu wall contacts\n",
           p.phi_plateau, p.phi_core, p.top, p.height, p.coordination, p.contacts,
           p.wall_contacts);
    const double area = 0.1 * p.height, kp = particle_param(l.ps, SINTER_MAT_THERMAL_CONDUCTIVITY);
    double hs_lo, hs_hi, hs_seed_lo, hs_seed_hi;
    hashin_shtrikman(0.0, kp, p.phi_plateau, &hs_lo, &hs_hi);
    hashin_shtrikman(0.0, kp, 0.54, &hs_seed_lo, &hs_seed_hi);
    printf("Hashin-Shtrikman (eq. 48, k1 = 0, k2 = %g): [%.2f, %.2f] W/(m K) at %.4f; [%.2f, "
           "%.2f] at the seed's 0.54\n",
           kp, hs_lo, hs_hi, p.phi_plateau, hs_seed_lo, hs_seed_hi);
    printf("cross-section A = 0.1 m x H = %.5f m^2; grad T = 7000 K/m; wall heat flows from the "
           "library's conduction model (its default wall law; snapshot of the wall contacts)\n",
           area);
    /* ---- heat-only runs --------------------------------------------------------------- */
    double dtv[8];
    int ndt = 0;
    for (const char *s = dts; s && *s && ndt < 8;) {
        dtv[ndt++] = strtod(s, NULL);
        s = strchr(s, ',');
        if (s)
            ++s;
    }
    if (soft > 0) {
        printf("\nsoftening theta* = %g K, mechanics re-settled every %g s; implicit dt %g s\n",
               soft, cycle, dtv[0]);
        box_result r = box_heat_run(&l, dtv[0], t_end, area, mech, cycle, 1);
        const packing p2 = measure_packing(&l, 0.1, 0.1, NULL);
        printf("after heating: volume fraction %.4f, H %.4f m\n", p2.phi_plateau, p2.height);
        printf("RESULT soft dt %.3g: k_seed(350) %.4f  k_in(350) %.4f  k_cold(350) %.4f  "
               "k_cold(end) %.4f  k_hot(end) %.4f  k_bulk(end) %.4f  (A of the unheated bed; "
               "%.1f s)\n",
               dtv[0], r.k_seed350, r.k_in350, r.k_cold350, r.k_cold_end, r.k_hot_end,
               r.k_bulk_end, r.seconds);
    } else {
        for (int k = 0; k < ndt; ++k) {
            printf("\nimplicit thermal step %g s, to t = %g s\n", dtv[k], k == 0 ? t_end : 350.0);
            box_result r =
                box_heat_run(&l, dtv[k], k == 0 ? t_end : 350.0, area, NULL, 0, k == 0);
            if (k == 0)
                printf("RESULT dt %.3g: k_seed(350) %.4f  k_in(350) %.4f  k_cold(350) %.4f  "
                       "k_seed(%g) %.4f  k_cold(end) %.4f  k_hot(end) %.4f  k_bulk(end) %.4f  "
                       "balance(350) %.1e  (%.1f s)\n",
                       dtv[k], r.k_seed350, r.k_in350, r.k_cold350, r.t_end, r.k_seed_end,
                       r.k_cold_end, r.k_hot_end, r.k_bulk_end, r.balance350, r.seconds);
            else
                printf("RESULT dt %.3g: k_seed(350) %.4f  k_in(350) %.4f  k_cold(350) %.4f  "
                       "balance(350) %.1e  (%.1f s)\n",
                       dtv[k], r.k_seed350, r.k_in350, r.k_cold350, r.balance350, r.seconds);
        }
        /* the explicit limit of this packing, for the scheme discussion */
        sinter_stepper *st = stepper(&l, 1.0);
        sinter_heat_model *cond = heat("conduction");
        CHECK(sinter_stepper_add_heat(st, cond));
        CHECK(sinter_stepper_step(st, 0));
        double dt_th = 0;
        CHECK(sinter_stepper_stable_dt_thermal(st, &dt_th));
        printf("\nexplicit thermal limit min m C / sum G = %.4g s (mechanical step %.3g s)\n",
               dt_th, dt_mech);
        sinter_stepper_destroy(st);
        sinter_heat_model_destroy(cond);
    }
    sinter_stepper_destroy(mech);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(g);
    sinter_scene_destroy(l.scene);
    return 0;
}

/* ======================================================================================= */
/* 5.4 laser bed                                                                            */
/* ======================================================================================= */

typedef struct laser_cfg {
    double absorptance, attenuation, emissivity, intensity_scale, dt;
    int conv_rad;
} laser_cfg;

typedef struct laser_result {
    double mean, max, max_all, energy_laser, energy_conv, energy_rad, lit_mc, seconds, dt_th;
    size_t lit;
} laser_result;

static double LASER_T = 0.24; /* beam time [s]; shortened for the coupled check */
static const double LASER_V = 0.1, LASER_Y = 0.02, LASER_R = 0.005,
                    LASER_I0 = 1000.0 / (PI * 0.005 * 0.005), THETA0 = 373.0, THETA_E = 273.0;

/* Mark every particle whose centre is inside the beam at time t (beam on from t = 0). */
static void mark_lit(const loaded *l, double t, unsigned char *lit)
{
    const double bx = LASER_V * t;
    const double *x = view_read(l->ps, SINTER_FIELD_POSITION);
    for (size_t i = 0; i < l->n; ++i) {
        const double dx = x[3 * i] - bx, dy = x[3 * i + 1] - LASER_Y;
        if (dx * dx + dy * dy <= LASER_R * LASER_R)
            lit[i] = 1;
    }
    release(l->ps, SINTER_FIELD_POSITION);
}

static void add_laser_models(sinter_stepper *st, const laser_cfg *c, sinter_heat_model **hs,
                             size_t *nh)
{
    *nh = 0;
    hs[(*nh)++] = heat("conduction");
    sinter_heat_model *las = heat("laser");
    CHECK(sinter_heat_model_set(las, "y", LASER_Y));
    CHECK(sinter_heat_model_set(las, "radius", LASER_R));
    CHECK(sinter_heat_model_set(las, "attenuation", c->attenuation));
    CHECK(sinter_heat_model_set(las, "intensity", LASER_I0 * c->intensity_scale));
    const double xt[2] = {0.0, 0.5}, xv[2] = {0.0, 0.5 * LASER_V};
    CHECK(sinter_heat_model_set_schedule(las, "x", 2, xt, xv));
    hs[(*nh)++] = las;
    if (c->conv_rad) {
        sinter_heat_model *cv = heat("convection"), *rd = heat("radiation");
        CHECK(sinter_heat_model_set(cv, "temperature", THETA_E));
        CHECK(sinter_heat_model_set(rd, "temperature", THETA_E));
        hs[(*nh)++] = cv;
        hs[(*nh)++] = rd;
    }
    for (size_t k = 0; k < *nh; ++k)
        CHECK(sinter_stepper_add_heat(st, hs[k]));
}

/* Mean and maximum temperature of the lit particles, their count and heat capacity. */
static void lit_stats(const loaded *l, const unsigned char *lit, laser_result *res)
{
    const double *t = view_read(l->ps, SINTER_FIELD_TEMPERATURE);
    const double *m = view_read(l->ps, SINTER_FIELD_MASS);
    const double cp = particle_param(l->ps, SINTER_MAT_HEAT_CAPACITY);
    double sum = 0;
    res->lit = 0;
    res->max = res->max_all = res->lit_mc = 0;
    for (size_t i = 0; i < l->n; ++i) {
        res->max_all = fmax(res->max_all, t[i]);
        if (!lit[i])
            continue;
        res->lit++;
        sum += t[i];
        res->lit_mc += m[i] * cp;
        res->max = fmax(res->max, t[i]);
    }
    res->mean = sum / (double)res->lit;
    release(l->ps, SINTER_FIELD_MASS);
    release(l->ps, SINTER_FIELD_TEMPERATURE);
}

/* Heat-only run over the frozen bed for LASER_T seconds. */
static laser_result laser_frozen(loaded *l, const laser_cfg *c)
{
    laser_result res;
    memset(&res, 0, sizeof(res));
    set_particle_param(l->ps, SINTER_MAT_ABSORPTANCE, c->absorptance);
    set_particle_param(l->ps, SINTER_MAT_EMISSIVITY, c->emissivity);
    set_all_temperatures(l->ps, l->n, THETA0);
    sinter_stepper *st = stepper(l, c->dt);
    sinter_heat_model *hs[4];
    size_t nh = 0;
    add_laser_models(st, c, hs, &nh);
    unsigned char *lit = calloc(l->n, 1);
    const uint64_t nsteps = (uint64_t)llround(LASER_T / c->dt);
    const double t0 = now();
    CHECK(sinter_stepper_step(st, 0));
    CHECK(sinter_stepper_stable_dt_thermal(st, &res.dt_th));
    for (uint64_t s = 0; s < nsteps; ++s) {
        mark_lit(l, (double)s * c->dt, lit); /* the state the step's powers are taken from */
        CHECK(sinter_stepper_step(st, 1));
    }
    res.seconds = now() - t0;
    lit_stats(l, lit, &res);
    CHECK(sinter_stepper_heat_energy(st, 1, &res.energy_laser));
    if (c->conv_rad) {
        CHECK(sinter_stepper_heat_energy(st, 2, &res.energy_conv));
        CHECK(sinter_stepper_heat_energy(st, 3, &res.energy_rad));
    }
    sinter_stepper_destroy(st);
    for (size_t k = 0; k < nh; ++k)
        sinter_heat_model_destroy(hs[k]);
    free(lit);
    return res;
}

static void laser_pair(loaded *l, laser_cfg c, const char *label)
{
    c.conv_rad = 0;
    laser_result a = laser_frozen(l, &c);
    c.conv_rad = 1;
    laser_result b = laser_frozen(l, &c);
    printf("%-34s %5zu %8.1f %8.1f %8.1f %8.1f %7.2f %7.2f %7.1f %8.2f %8.2f %6.1f\n", label,
           a.lit, a.mean, b.mean, a.max, b.max, 100 * (a.mean / b.mean - 1),
           100 * (a.max / b.max - 1), a.energy_laser, -b.energy_conv, -b.energy_rad,
           a.seconds + b.seconds);
}

static int cmd_laser_bed(int argc, char **argv)
{
    const char *path = opt(argc, argv, "--scene", "examples/scenes/laser_bed.scene");
    const double dt_heat = atof(opt(argc, argv, "--dt", "1e-4"));
    const long coupled = atol(opt(argc, argv, "--coupled-steps", "0"));
    printf("# seed 003 sec. 5.4, scene %s\n", path);
    loaded l = load(path);
    /* ---- pour at the scene's step ------------------------------------------------------- */
    const double dt_mech = 5e-7;
    double dt_hz = 0;
    CHECK(sinter_stable_dt_hertz(l.ps, l.walls, 0.5, &dt_hz));
    sinter_stepper *mech = stepper(&l, dt_mech);
    sinter_force_model *hm = force("hertz_mindlin"), *g = force("gravity");
    CHECK(sinter_stepper_add_force(mech, hm));
    CHECK(sinter_stepper_add_force(mech, g));
    double t0 = now();
    const char *ckpt = opt(argc, argv, "--checkpoint", NULL);
    FILE *probe = ckpt ? fopen(ckpt, "rb") : NULL;
    double t_rest = 0;
    if (probe != NULL) {
        /* a bed poured by an earlier run of this program (same scene, same models) */
        fclose(probe);
        CHECK(sinter_checkpoint_read(mech, ckpt));
        CHECK(sinter_stepper_evaluate(mech)); /* contact counts for the report */
        CHECK(sinter_stepper_time(mech, &t_rest));
        printf("bed read from checkpoint %s (poured to rest at t = %.4f s)\n", ckpt, t_rest);
    } else {
        /* report the kinetic energy as the bed lands, then the pour criterion */
        printf("pour at dt = %.1e s (eq. 47 at 0.5 m/s for the smallest pair: %.2e s)\n",
               dt_mech, dt_hz);
        printf("  t [s]   KE per particle [J]\n");
        for (int k = 1; k <= 16; ++k) {
            CHECK(sinter_stepper_advance(mech, 0.005 * k));
            printf("  %.3f   %.3e\n", 0.005 * k, kinetic_energy(l.ps, l.n) / (double)l.n);
        }
        CHECK(sinter_pack_pour(mech, 1e-12, 0.0, 0.3));
        CHECK(sinter_stepper_time(mech, &t_rest));
        if (ckpt != NULL)
            CHECK(sinter_checkpoint_write(mech, ckpt));
    }
    const packing p = measure_packing(&l, 0.04, 0.04, mech);
    printf("at rest (KE < 1e-12 J per particle) at t = %.4f s (%.0f s wall); bed top %.4f m, "
           "volume fraction %.3f, bed height %.4f m, coordination %.2f\n",
           t_rest, now() - t0, p.top, p.phi_plateau, p.height, p.coordination);
    laser_cfg base = {1.0, 2000.0, 1.0, 1.0, dt_heat, 1};
    if (coupled > 0 && ckpt == NULL) {
        fprintf(stderr, "seed003_scenes: --coupled-steps needs --checkpoint\n");
        return 1;
    }
    if (coupled > 0) {
        /* time fully coupled steps: mechanics + conduction + laser + convection + radiation */
        sinter_heat_model *hs[4];
        size_t nh = 0;
        sinter_stepper *st = stepper(&l, dt_mech);
        CHECK(sinter_stepper_add_force(st, hm));
        CHECK(sinter_stepper_add_force(st, g));
        set_particle_param(l.ps, SINTER_MAT_ABSORPTANCE, 1.0);
        set_particle_param(l.ps, SINTER_MAT_EMISSIVITY, 1.0);
        add_laser_models(st, &base, hs, &nh);
        CHECK(sinter_stepper_step(st, 0));
        const double *x0 = view_read(l.ps, SINTER_FIELD_POSITION);
        double *xs = malloc(3 * l.n * sizeof(double));
        memcpy(xs, x0, 3 * l.n * sizeof(double));
        release(l.ps, SINTER_FIELD_POSITION);
        set_all_temperatures(l.ps, l.n, THETA0);
        unsigned char *lit = calloc(l.n, 1);
        const double c0 = now();
        for (long done = 0; done < coupled; done += 100) { /* lit marked every 100 steps */
            mark_lit(&l, (double)done * dt_mech, lit);
            CHECK(sinter_stepper_step(st, (uint64_t)(coupled - done < 100 ? coupled - done : 100)));
        }
        const double sec = now() - c0;
        LASER_T = (double)coupled * dt_mech;
        laser_result rc;
        memset(&rc, 0, sizeof(rc));
        lit_stats(&l, lit, &rc);
        const double *x1 = view_read(l.ps, SINTER_FIELD_POSITION);
        double dmax = 0;
        for (size_t i = 0; i < 3 * l.n; ++i)
            dmax = fmax(dmax, fabs(x1[i] - xs[i]));
        release(l.ps, SINTER_FIELD_POSITION);
        const double full = sec / (double)coupled * 0.24 / dt_mech;
        printf("coupled: %ld steps (%.4f s of beam) of %zu particles in %.2f s = %.3g s/step; the "
               "0.24 s run (%.0f steps) would take %.0f s (%.1f min); KE per particle after: "
               "%.3e J; largest displacement %.3e m\n",
               coupled, LASER_T, l.n, sec, sec / (double)coupled, 0.24 / dt_mech, full,
               full / 60, kinetic_energy(l.ps, l.n) / (double)l.n, dmax);
        printf("coupled  (cond+conv+rad): lit %zu, mean %.2f K, max %.2f K\n", rc.lit, rc.mean,
               rc.max);
        /* the same beam time over the frozen bed, from the same poured state */
        CHECK(sinter_checkpoint_read(mech, ckpt));
        set_fixed(l.ps, l.n, 1);
        laser_cfg fz = base;
        fz.dt = 1e-4;
        laser_result rf = laser_frozen(&l, &fz);
        printf("frozen   (cond+conv+rad, dt 1e-4 s): lit %zu, mean %.2f K, max %.2f K\n", rf.lit,
               rf.mean, rf.max);
        free(lit);
        free(xs);
        sinter_stepper_destroy(st);
        for (size_t k = 0; k < nh; ++k)
            sinter_heat_model_destroy(hs[k]);
        sinter_stepper_destroy(mech);
        sinter_force_model_destroy(hm);
        sinter_force_model_destroy(g);
        sinter_scene_destroy(l.scene);
        return 0;
    }
    /* ---- frozen mechanics, heat only ----------------------------------------------------- */
    set_fixed(l.ps, l.n, 1);
    {
        /* the explicit thermal limit of the settled bed (conduction only) */
        sinter_stepper *st = stepper(&l, dt_heat);
        sinter_heat_model *cond = heat("conduction");
        CHECK(sinter_stepper_add_heat(st, cond));
        CHECK(sinter_stepper_step(st, 0));
        double dt_th = 0;
        CHECK(sinter_stepper_stable_dt_thermal(st, &dt_th));
        const double *r = view_read(l.ps, SINTER_FIELD_RADIUS);
        double rmin = INFINITY, rmax = 0;
        for (size_t i = 0; i < l.n; ++i)
            rmin = fmin(rmin, r[i]), rmax = fmax(rmax, r[i]);
        release(l.ps, SINTER_FIELD_RADIUS);
        /* a lit sphere absorbs at most I0 pi r^2 (a = 1, depth 0) for at most 2 R / v: its rise
         * is at most 3 I0 (2 R / v) / (4 rho r C) */
        const double rho = particle_param(l.ps, SINTER_MAT_DENSITY),
                     cp = particle_param(l.ps, SINTER_MAT_HEAT_CAPACITY),
                     dwell = 2 * LASER_R / LASER_V, mc = rho * 4.0 / 3.0 * PI * 1.25e-10 * cp;
        printf("explicit conduction limit of the settled bed min m C / sum G = %.4g s; radii "
               "%.3g..%.3g m; m C of an r = 0.5 mm sphere %.4g J/K; laser power on it I0 pi r^2 "
               "= %.3f W; beam dwell on the centre line 2 R / v = %.3f s -> at most %.0f K rise "
               "(%.0f K for the smallest sphere); beam energy in %.2f s: %.0f J\n",
               dt_th, rmin, rmax, mc, LASER_I0 * PI * 0.0005 * 0.0005, dwell,
               3 * LASER_I0 * dwell / (4 * rho * 0.0005 * cp),
               3 * LASER_I0 * dwell / (4 * rho * rmin * cp), LASER_T, 1000.0 * LASER_T);
        sinter_stepper_destroy(st);
        sinter_heat_model_destroy(cond);
    }
    printf("\nheat-only steppers over the frozen bed (explicit thermal scheme), %.2f s of beam; "
           "columns: lit count, mean lit theta cond-only / cond+conv+rad, max lit theta "
           "cond-only / cond+conv+rad, mean and max differences, laser energy J, convected "
           "and radiated energy J (cond+conv+rad run), wall s\n",
           LASER_T);
    printf("%-34s %5s %8s %8s %8s %8s %7s %7s %7s %8s %8s %6s\n", "case", "lit", "mean c",
           "mean crr", "max c", "max crr", "dmean%", "dmax%", "E_las", "E_conv", "E_rad", "s");
    char label[64];
    snprintf(label, sizeof label, "a=1 mu=2000 eps=1 dt=%g", dt_heat);
    laser_pair(&l, base, label);
    laser_cfg c = base;
    c.dt = dt_heat / 2;
    snprintf(label, sizeof label, "a=1 mu=2000 eps=1 dt=%g", c.dt);
    laser_pair(&l, c, label);
    if (flag(argc, argv, "--sensitivity")) {
        const struct {
            double a, mu, eps, scale;
            const char *label;
        } v[] = {
            {1.0, 1000.0, 1.0, 1.0, "mu=1000"},    {1.0, 4000.0, 1.0, 1.0, "mu=4000"},
            {1.0, 1e5, 1.0, 1.0, "mu=1e5 (top surface only)"},
            {0.5, 2000.0, 1.0, 1.0, "a=0.5"},      {0.3, 2000.0, 1.0, 1.0, "a=0.3"},
            {1.0, 2000.0, 0.5, 1.0, "eps=0.5"},    {1.0, 2000.0, 0.3, 1.0, "eps=0.3"},
            {1.0, 2000.0, 1.0, 4.0, "what-if: intensity x4"},
            {1.0, 2000.0, 1.0, 8.0, "what-if: intensity x8"},
            {1.0, 2000.0, 1.0, 16.0, "what-if: intensity x16"},
            {1.0, 0.0, 1.0, 1.0, "mu=0 (no attenuation)"},
            {1.0, 0.0, 1.0, 10.0, "what-if: mu=0, intensity x10"},
        };
        for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) {
            c = base;
            c.absorptance = v[k].a, c.attenuation = v[k].mu, c.emissivity = v[k].eps;
            c.intensity_scale = v[k].scale;
            laser_pair(&l, c, v[k].label);
        }
    }
    sinter_stepper_destroy(mech);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(g);
    sinter_scene_destroy(l.scene);
    return 0;
}

/* ======================================================================================= */
/* 5.2 vibrated bed                                                                         */
/* ======================================================================================= */

static int cmd_vibrated_bed(int argc, char **argv)
{
    const char *path = opt(argc, argv, "--scene", "examples/scenes/vibrated_bed.scene");
    const double t_end = atof(opt(argc, argv, "--t-end", "2"));
    printf("# seed 003 sec. 5.2, scene %s, %g s of the seed's 60 s\n", path, t_end);
    const int nrow = (int)llround(t_end / 0.1);
    double *mean[2], *maxv[2], dt_th_min[2] = {INFINITY, INFINITY}, secs[2];
    for (int conv = 1; conv >= 0; --conv) {
        loaded l = load(path);
        sinter_stepper *st = stepper(&l, 5e-6);
        CHECK(sinter_stepper_set_skin(st, 1e-4));
        const double lo[3] = {-0.01, -0.01, -0.05}, hi[3] = {0.31, 0.01, 0.3};
        CHECK(sinter_stepper_set_domain(st, lo, hi));
        sinter_force_model *hm = force("hertz_mindlin"), *g = force("gravity");
        CHECK(sinter_force_model_set(g, "gz", -9.8));
        CHECK(sinter_stepper_add_force(st, hm));
        CHECK(sinter_stepper_add_force(st, g));
        sinter_heat_model *cond = heat("conduction"), *cv = NULL;
        CHECK(sinter_stepper_add_heat(st, cond));
        if (conv) {
            cv = heat("convection");
            CHECK(sinter_heat_model_set(cv, "temperature", 273.0));
            CHECK(sinter_heat_model_set(cv, "fluid_conductivity", 0.025));
            CHECK(sinter_heat_model_set(cv, "fluid_heat_capacity", 1000.0));
            CHECK(sinter_stepper_add_heat(st, cv));
        }
        mean[conv] = calloc((size_t)nrow + 1, sizeof(double));
        maxv[conv] = calloc((size_t)nrow + 1, sizeof(double));
        const double t0 = now();
        for (int k = 1; k <= nrow; ++k) {
            CHECK(sinter_stepper_advance(st, 0.1 * k));
            const double *t = view_read(l.ps, SINTER_FIELD_TEMPERATURE);
            double s = 0, mx = 0;
            for (size_t i = 0; i < l.n; ++i)
                s += t[i], mx = fmax(mx, t[i]);
            release(l.ps, SINTER_FIELD_TEMPERATURE);
            mean[conv][k] = s / (double)l.n;
            maxv[conv][k] = mx;
            double d = 0;
            CHECK(sinter_stepper_stable_dt_thermal(st, &d));
            dt_th_min[conv] = fmin(dt_th_min[conv], d);
        }
        secs[conv] = now() - t0;
        sinter_stepper_destroy(st);
        sinter_heat_model_destroy(cond);
        sinter_heat_model_destroy(cv);
        sinter_force_model_destroy(hm);
        sinter_force_model_destroy(g);
        sinter_scene_destroy(l.scene);
    }
    printf("%6s %12s %12s %12s %12s\n", "t s", "mean conv", "max conv", "mean noconv",
           "max noconv");
    for (int k = 1; k <= nrow; ++k)
        if (nrow <= 20 || k % 5 == 0 || k < 5) /* every 0.5 s on long runs */
            printf("%6.1f %12.2f %12.2f %12.2f %12.2f\n", 0.1 * k, mean[1][k], maxv[1][k],
                   mean[0][k], maxv[0][k]);
    printf("smallest explicit thermal limit m C / sum G sampled every 0.1 s: %.3g s (conv), "
           "%.3g s (no conv); dt = 5e-6 s. Wall time %.0f s and %.0f s\n",
           dt_th_min[1], dt_th_min[0], secs[1], secs[0]);
    for (int c = 0; c < 2; ++c)
        free(mean[c]), free(maxv[c]);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: seed003_scenes hot_floor|conduction_box|laser_bed|vibrated_bed "
                        "[options] (see the comment at the top of seed003_scenes.c)\n");
        return 1;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* progress visible in logs */
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    print_machine();
    int rc = 1;
    if (strcmp(argv[1], "hot_floor") == 0)
        rc = cmd_hot_floor(argc, argv);
    else if (strcmp(argv[1], "conduction_box") == 0)
        rc = cmd_conduction_box(argc, argv);
    else if (strcmp(argv[1], "laser_bed") == 0)
        rc = cmd_laser_bed(argc, argv);
    else if (strcmp(argv[1], "vibrated_bed") == 0)
        rc = cmd_vibrated_bed(argc, argv);
    else
        fprintf(stderr, "seed003_scenes: unknown subcommand '%s'\n", argv[1]);
    sinter_ctx_destroy(g_ctx);
    return rc;
}
