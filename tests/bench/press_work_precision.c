/*
 * press_work_precision: CPU time and pipeline evaluations against error for the explicit
 * stepper (velocity Verlet, forward Euler heat; seed 003 sec. 4) at several steps, and for the
 * implicit staggered stepper (trapezoidal rule; seed 000 sec. 3, 6) in its two schemes at
 * several tolerances: scheme 0, the seed's Algorithm 1 (plain fixed-point iterations, eq. 47-49
 * step control), and scheme 1 (Anderson acceleration, WRMS test, PI control on the
 * contraction, extrapolating predictor; src/stepper/staggered.c, anderson.c, step_control.c).
 *
 *   press_work_precision [SCENE_DIR [OUT_DIR [PRESS_WINDOW [HEAT_WINDOW [REPEATS]]]]]
 *
 * SCENE_DIR holds press.scene and press_staggered.scene (default: the source tree's
 * examples/scenes); OUT_DIR receives work_precision.csv, work_precision.svg (error against
 * CPU) and work_precision_evaluations.svg (error against evaluations) (default ".").
 *
 * Two problems from the press scene (seed 000 sec. 7), each started from a checkpoint:
 *  - press: the scene is poured to rest (as `sinter run` does: every wall held, kinetic
 *    energy per particle below the scene's threshold), the top wall starts its schedule, and
 *    the explicit stepper at the scene's dt runs on for 0.85 s, to just before the top wall
 *    reaches the bed. The window (PRESS_WINDOW, default 0.1 s) covers the wall meeting the bed
 *    and compressing it: contacts multiply, the top wall force rises from 0 to ~10^5 N, and
 *    Joule heating and conduction from the 1000 K walls run throughout. It is short because a
 *    dense frictional packing is chaotic: over long windows differences of any size grow until
 *    the error measures the chaos, not the integrator.
 *  - heat: the poured bed, every wall held, settled 1 s beyond the end of the pour; the window
 *    (HEAT_WINDOW, default 0.5 s) has the mechanics nearly at rest while conduction from the
 *    1000 K walls and Joule heating drive the temperatures.
 *
 * Error: against a reference run of the explicit stepper at 1/400 of the scene's step (press)
 * or 1/40 (heat), at the end of the window, the RMS over particles of |x - x_ref| / R and of
 * |theta - theta_ref| [K]. The reference's own error is estimated by a run at twice its step.
 *
 * CPU: the process's CPU time of the stepper's advance, one thread; every configuration runs
 * REPEATS times (default 3), the configurations alternating within each round, and the median
 * is reported (the machine is shared and noisy).
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, CLOCK_MONOTONIC under -std=c11 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "press_work_precision"
#include "bench_support.h"
#include "sinter.h"

#ifndef SINTER_SOURCE_DIR
#define SINTER_SOURCE_DIR "."
#endif

enum { MAX_REPEATS = 9 };

/* One configuration and what it gave. */
typedef struct run {
    int problem;         /* 0: press, 1: heat */
    int scheme;          /* -1: explicit; 0, 1: staggered scheme */
    double dt;           /* explicit step, or the staggered dt_max [s] */
    double tolerance;    /* staggered: "tolerance" */
    double position_tol; /* staggered: "position_tolerance" [m] */
    int kd;              /* staggered: "target_iterations" */
    /* results */
    double cpu[MAX_REPEATS], seconds;
    double error_x, error_theta;
    sinter_stepper_stats stats;
} run;

typedef struct state {
    size_t n;
    double *x;
    double *theta;
    double radius;
} state;

static void read_state(sinter_scene *sc, state *out)
{
    sinter_particles *ps = NULL;
    CHECK(sinter_scene_get_particles(sc, &ps));
    CHECK(sinter_particles_count(ps, &out->n));
    const double *x = NULL, *theta = NULL, *r = NULL;
    out->x = malloc(3 * out->n * sizeof(double));
    out->theta = malloc(out->n * sizeof(double));
    if (out->x == NULL || out->theta == NULL)
        exit(2);
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    memcpy(out->x, x, 3 * out->n * sizeof(double));
    CHECK(sinter_particles_release(ps, SINTER_FIELD_POSITION));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&theta, NULL,
                                     NULL));
    memcpy(out->theta, theta, out->n * sizeof(double));
    CHECK(sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
    out->radius = r[0];
    CHECK(sinter_particles_release(ps, SINTER_FIELD_RADIUS));
}

static void free_state(state *s)
{
    free(s->x);
    free(s->theta);
}

static void errors(const state *a, const state *ref, double *ex, double *et)
{
    double sx = 0.0, st = 0.0;
    for (size_t i = 0; i < a->n; ++i) {
        for (int d = 0; d < 3; ++d) {
            const double e = a->x[3 * i + d] - ref->x[3 * i + d];
            sx += e * e;
        }
        const double e = a->theta[i] - ref->theta[i];
        st += e * e;
    }
    *ex = sqrt(sx / (double)a->n) / ref->radius;
    *et = sqrt(st / (double)a->n);
}

static sinter_scene *load(sinter_ctx **ctx, const char *dir, const char *file)
{
    char path[4096];
    snprintf(path, sizeof(path), "%s/%s", dir, file);
    CHECK(sinter_ctx_create(ctx, NULL));
    g_ctx = *ctx;
    sinter_scene *sc = NULL;
    CHECK(sinter_scene_load(&sc, *ctx, path));
    return sc;
}

/*
 * Pour to rest and run on to just before the top wall meets the bed: the press window's
 * checkpoint. With `heat` the walls stay held and the bed settles 1 s more: the heat window's.
 */
static double prepare(const char *dir, const char *checkpoint, int heat)
{
    sinter_ctx *ctx = NULL;
    sinter_scene *sc = load(&ctx, dir, "press.scene");
    sinter_stepper *st = NULL;
    sinter_walls *walls = NULL;
    CHECK(sinter_scene_get_stepper(sc, &st));
    CHECK(sinter_scene_get_walls(sc, &walls));
    size_t nw = 0;
    CHECK(sinter_walls_count(walls, &nw));
    for (size_t k = 0; k < nw; ++k)
        CHECK(sinter_walls_set_motion_start(walls, k, HUGE_VAL));
    const double t0 = now();
    /* The scene's [pour]: 1e-3 J per particle after at least 0.5 s, at most 5 s. */
    CHECK(sinter_pack_pour(st, 1e-3, 0.5, 5.0));
    double t = 0;
    CHECK(sinter_stepper_time(st, &t));
    const double t_start = t + (heat ? 1.0 : 0.85);
    if (!heat)
        for (size_t k = 0; k < nw; ++k)
            CHECK(sinter_walls_set_motion_start(walls, k, t));
    CHECK(sinter_stepper_advance(st, t_start));
    CHECK(sinter_checkpoint_write(st, checkpoint));
    fprintf(stderr, "poured to rest at t = %.3f s; %s checkpoint at t = %.3f s (%.1f s)\n", t,
            heat ? "heat" : "press", t_start, now() - t0);
    sinter_scene_destroy(sc);
    sinter_ctx_destroy(ctx);
    g_ctx = NULL;
    return t_start;
}

static void execute(const char *dir, const char *checkpoint, double t_start, double window, run *r,
                    state *out, double *cpu)
{
    sinter_ctx *ctx = NULL;
    sinter_scene *sc = load(&ctx, dir, r->scheme >= 0 ? "press_staggered.scene" : "press.scene");
    sinter_stepper *st = NULL;
    CHECK(sinter_scene_get_stepper(sc, &st));
    CHECK(sinter_checkpoint_read(st, checkpoint));
    CHECK(sinter_stepper_set_dt(st, r->dt));
    if (r->scheme >= 0) {
        CHECK(sinter_stepper_set_option(st, "scheme", r->scheme));
        CHECK(sinter_stepper_set_option(st, "dt_max", r->dt));
        CHECK(sinter_stepper_set_option(st, "tolerance", r->tolerance));
        CHECK(sinter_stepper_set_option(st, "position_tolerance", r->position_tol));
        CHECK(sinter_stepper_set_option(st, "target_iterations", r->kd));
    }
    sinter_stepper_stats before;
    before.struct_size = sizeof(before);
    CHECK(sinter_stepper_get_stats(st, &before));
    const double t0 = cpu_seconds();
    CHECK(sinter_stepper_advance(st, t_start + window));
    *cpu = cpu_seconds() - t0;
    r->stats.struct_size = sizeof(r->stats);
    CHECK(sinter_stepper_get_stats(st, &r->stats));
    r->stats.steps -= before.steps; /* the checkpoint carries the counts of the preparation */
    r->stats.rejected -= before.rejected;
    r->stats.iterations -= before.iterations;
    r->stats.evaluations -= before.evaluations;
    if (out != NULL)
        read_state(sc, out);
    sinter_scene_destroy(sc);
    sinter_ctx_destroy(ctx);
    g_ctx = NULL;
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#define EXPL(p, dt)                                                                                \
    {                                                                                              \
        p, -1, dt, 0, 0, 0, {0}, 0, 0, 0,                                                          \
        {                                                                                          \
            0                                                                                      \
        }                                                                                          \
    }
#define STAG(p, scheme, dt, tol, ptol, kd)                                                         \
    {                                                                                              \
        p, scheme, dt, tol, ptol, kd, {0}, 0, 0, 0,                                                \
        {                                                                                          \
            0                                                                                      \
        }                                                                                          \
    }

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : SINTER_SOURCE_DIR "/examples/scenes";
    const char *out_dir = argc > 2 ? argv[2] : ".";
    const double window[2] = {argc > 3 ? atof(argv[3]) : 0.1, argc > 4 ? atof(argv[4]) : 0.5};
    const int repeats = argc > 5 ? atoi(argv[5]) : 3;
    if (!(window[0] > 0.0) || !(window[1] > 0.0) || repeats < 1 || repeats > MAX_REPEATS) {
        fprintf(stderr, "usage: press_work_precision [SCENE_DIR [OUT_DIR [PRESS_WINDOW "
                        "[HEAT_WINDOW [REPEATS (1-9)]]]]]\n");
        return 1;
    }
    char checkpoint[2][4096];
    snprintf(checkpoint[0], sizeof(checkpoint[0]), "%s/press_work_precision.ckpt", out_dir);
    snprintf(checkpoint[1], sizeof(checkpoint[1]), "%s/press_work_precision_heat.ckpt", out_dir);
    double t_start[2];
    t_start[0] = prepare(dir, checkpoint[0], 0);
    t_start[1] = prepare(dir, checkpoint[1], 1);
    const char *problem_name[2] = {"press", "heat"};

    /* References and their error estimates. */
    state s_ref[2];
    double ref_error[2][2];
    const double ref_dt[2] = {2.5e-6, 2.5e-5};
    for (int p = 0; p < 2; ++p) {
        run ref = EXPL(p, ref_dt[p]), ref2 = EXPL(p, 2.0 * ref_dt[p]);
        state s2;
        double cpu;
        execute(dir, checkpoint[p], t_start[p], window[p], &ref, &s_ref[p], &cpu);
        execute(dir, checkpoint[p], t_start[p], window[p], &ref2, &s2, &cpu);
        errors(&s2, &s_ref[p], &ref_error[p][0], &ref_error[p][1]);
        free_state(&s2);
        fprintf(stderr, "%s reference: explicit dt %g s; at %g s it differs by %.2e R and %.2e K\n",
                problem_name[p], ref_dt[p], 2.0 * ref_dt[p], ref_error[p][0], ref_error[p][1]);
    }

    /* The explicit stepper from 5 ms (stable in both windows) down; the staggered one in
     * scheme 0 at the seed's settings (dt_max 0.005 s, TOL 5e-4, position floor 1e-6 m, K_d =
     * 10) and tighter tolerances, the floor scaled with TOL (2e-3 m x TOL), and in scheme 1
     * from TOL 0.03 (or 0.05) to 1e-6 with the same floors, its step bounded by 0.02 s (press)
     * or 0.05 s (heat, also scheme 0's). */
    run runs[] = {
        EXPL(0, 5e-3),
        EXPL(0, 2e-3),
        EXPL(0, 1e-3),
        EXPL(0, 5e-4),
        EXPL(0, 2.5e-4),
        EXPL(0, 1.25e-4),
        STAG(0, 0, 5e-3, 5e-4, 1e-6, 10),
        STAG(0, 0, 5e-3, 1e-4, 2e-7, 10),
        STAG(0, 0, 5e-3, 1e-5, 2e-8, 10),
        STAG(0, 1, 2e-2, 3e-2, 6e-5, 10),
        STAG(0, 1, 2e-2, 5e-3, 1e-5, 10),
        STAG(0, 1, 2e-2, 5e-4, 1e-6, 10),
        STAG(0, 1, 2e-2, 1e-4, 2e-7, 10),
        STAG(0, 1, 2e-2, 1e-5, 2e-8, 10),
        STAG(0, 1, 2e-2, 1e-6, 2e-9, 10),
        EXPL(1, 5e-3),
        EXPL(1, 2e-3),
        EXPL(1, 1e-3),
        EXPL(1, 5e-4),
        STAG(1, 0, 5e-2, 5e-4, 1e-6, 10),
        STAG(1, 0, 5e-2, 1e-4, 2e-7, 10),
        STAG(1, 1, 5e-2, 5e-2, 1e-4, 10),
        STAG(1, 1, 5e-2, 1e-2, 2e-5, 10),
        STAG(1, 1, 5e-2, 1e-3, 2e-6, 10),
        STAG(1, 1, 5e-2, 1e-4, 2e-7, 10),
    };
    const size_t count = sizeof(runs) / sizeof(runs[0]);
    for (int rep = 0; rep < repeats; ++rep) {
        for (size_t k = 0; k < count; ++k) {
            run *r = &runs[k];
            state s;
            execute(dir, checkpoint[r->problem], t_start[r->problem], window[r->problem], r,
                    rep == 0 ? &s : NULL, &r->cpu[rep]);
            if (rep == 0) {
                errors(&s, &s_ref[r->problem], &r->error_x, &r->error_theta);
                free_state(&s);
            }
            fprintf(stderr, "round %d, run %zu: %.2f s\n", rep + 1, k + 1, r->cpu[rep]);
        }
    }
    /* Columns: log10 CPU, log10 evaluations, then per problem and quantity one column per
     * stepper (explicit, scheme 0, scheme 1). */
    enum { COLS = 11 };
    const char *names[COLS] = {"log10 CPU time",
                               "log10 evaluations",
                               "press position: explicit",
                               "press position: staggered, seed",
                               "press position: staggered, Anderson",
                               "press temperature: explicit",
                               "press temperature: staggered, seed",
                               "press temperature: staggered, Anderson",
                               "heat temperature: explicit",
                               "heat temperature: staggered, seed",
                               "heat temperature: staggered, Anderson"};
    const char *units[COLS] = {"log10 s", "log10 1", "log10 R", "log10 R", "log10 R", "log10 K",
                               "log10 K", "log10 K", "log10 K", "log10 K", "log10 K"};
    sinter_ctx *ctx = NULL;
    CHECK(sinter_ctx_create(&ctx, NULL));
    g_ctx = ctx;
    sinter_series *series = NULL;
    CHECK(sinter_series_create(&series, ctx, COLS, names, units));
    printf("| problem | stepper | dt or dt_max [s] | TOL | position floor [m] | K_d | CPU [s] "
           "(median of %d) | steps | rejected | evaluations | position error [R] | temperature "
           "error [K] |\n",
           repeats);
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t k = 0; k < count; ++k) {
        run *r = &runs[k];
        qsort(r->cpu, (size_t)repeats, sizeof(double), compare_double);
        r->seconds = r->cpu[repeats / 2];
        char tol[32] = "-", floor_text[32] = "-", kd[16] = "-";
        if (r->scheme >= 0) {
            snprintf(tol, sizeof(tol), "%g", r->tolerance);
            snprintf(floor_text, sizeof(floor_text), "%g", r->position_tol);
            snprintf(kd, sizeof(kd), "%d", r->kd);
        }
        const char *kind = r->scheme < 0    ? "explicit"
                           : r->scheme == 0 ? "staggered, seed (scheme 0)"
                                            : "staggered, Anderson (scheme 1)";
        printf("| %s | %s | %g | %s | %s | %s | %.3f | %llu | %llu | %llu | %.3e | %.3e |\n",
               problem_name[r->problem], kind, r->dt, tol, floor_text, kd, r->seconds,
               (unsigned long long)r->stats.steps, (unsigned long long)r->stats.rejected,
               (unsigned long long)r->stats.evaluations, r->error_x, r->error_theta);
        double row[COLS];
        for (int c = 0; c < COLS; ++c)
            row[c] = NAN;
        row[0] = log10(r->seconds);
        row[1] = log10((double)r->stats.evaluations);
        const int which = r->scheme + 1;
        if (r->problem == 0) {
            row[2 + which] = log10(r->error_x);
            row[5 + which] = log10(r->error_theta);
        } else {
            row[8 + which] = log10(r->error_theta);
        }
        CHECK(sinter_series_append(series, row));
    }
    for (int p = 0; p < 2; ++p)
        printf("\n%s reference: explicit, dt = %g s; the same at %g s differs from it by %.3e R "
               "and %.3e K\n",
               problem_name[p], ref_dt[p], 2.0 * ref_dt[p], ref_error[p][0], ref_error[p][1]);
    char path[4096];
    snprintf(path, sizeof(path), "%s/work_precision.csv", out_dir);
    CHECK(sinter_series_write_csv(series, path));
    const size_t start[4] = {0, 3, 6, 9}, cols[9] = {2, 3, 4, 5, 6, 7, 8, 9, 10};
    snprintf(path, sizeof(path), "%s/work_precision.svg", out_dir);
    CHECK(sinter_series_write_svg(
        series, path, "press and heat windows: error against CPU time (log10)", 0, 3, start, cols));
    snprintf(path, sizeof(path), "%s/work_precision_evaluations.svg", out_dir);
    CHECK(sinter_series_write_svg(series, path,
                                  "press and heat windows: error against evaluations (log10)", 1, 3,
                                  start, cols));
    remove(checkpoint[0]);
    remove(checkpoint[1]);
    sinter_series_destroy(series);
    sinter_ctx_destroy(ctx);
    free_state(&s_ref[0]);
    free_state(&s_ref[1]);
    return 0;
}
