/*
 * press_work_precision: error against wall time of the explicit stepper (velocity Verlet,
 * forward Euler heat; seed 003 sec. 4) at several steps and of the implicit staggered stepper
 * (trapezoidal rule, fixed-point iterations, adaptive step; seed 000 sec. 3, 6) at several
 * tolerances, on the compression phase of the press scene (seed 000 sec. 7,
 * examples/scenes/press.scene and press_staggered.scene).
 *
 *   press_work_precision [SCENE_DIR [OUT_DIR [WINDOW]]]
 *
 * SCENE_DIR holds press.scene and press_staggered.scene (default: the source tree's
 * examples/scenes); OUT_DIR receives work_precision.csv and work_precision.svg (default ".").
 *
 * Problem. The scene is poured to rest (as `sinter run` does: every wall held, kinetic energy
 * per particle below the scene's threshold), the top wall starts its schedule, and the explicit
 * stepper at the scene's dt runs on for 0.85 s, to just before the top wall reaches the bed.
 * That state is checkpointed; every run starts from it and covers the next WINDOW seconds
 * (default 0.1 s): the wall meets the bed and compresses it, contacts multiply, the top wall
 * force rises from 0 to ~10^5 N, and Joule heating and conduction from the 1000 K walls run
 * throughout. The window is kept short because a dense frictional packing is chaotic: over
 * long windows differences of any size grow until the error measures the chaos, not the
 * integrator.
 *
 * Error. Against a reference run of the explicit stepper at dt = 2.5e-6 s (1/400 of the
 * scene's step), at the end of the window: the RMS over particles of |x - x_ref| / R and of
 * |theta - theta_ref| [K]. The reference's own error is estimated by a second explicit run at
 * twice its step, printed with the table.
 *
 * Wall time: the stepper's advance only (clock_gettime, monotonic), one thread.
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

/* One configuration and what it gave. */
typedef struct run {
    int staggered;       /* 0: explicit */
    double dt;           /* explicit step, or the staggered dt_max [s] */
    double tolerance;    /* staggered: TOL of eq. 48 */
    double position_tol; /* staggered: absolute floor [m] */
    /* results */
    double seconds;
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

/* Pour to rest and run on to just before the top wall meets the bed; write the checkpoint. */
static double prepare(const char *dir, const char *checkpoint)
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
    for (size_t k = 0; k < nw; ++k)
        CHECK(sinter_walls_set_motion_start(walls, k, t));
    CHECK(sinter_stepper_advance(st, t + 0.85));
    CHECK(sinter_checkpoint_write(st, checkpoint));
    fprintf(stderr, "poured to rest at t = %.3f s; checkpoint at t = %.3f s (%.1f s)\n", t,
            t + 0.85, now() - t0);
    sinter_scene_destroy(sc);
    sinter_ctx_destroy(ctx);
    g_ctx = NULL;
    return t + 0.85;
}

static void execute(const char *dir, const char *checkpoint, double t_start, double window, run *r,
                    state *out)
{
    sinter_ctx *ctx = NULL;
    sinter_scene *sc = load(&ctx, dir, r->staggered ? "press_staggered.scene" : "press.scene");
    sinter_stepper *st = NULL;
    CHECK(sinter_scene_get_stepper(sc, &st));
    CHECK(sinter_checkpoint_read(st, checkpoint));
    CHECK(sinter_stepper_set_dt(st, r->dt));
    if (r->staggered) {
        CHECK(sinter_stepper_set_option(st, "dt_max", r->dt));
        CHECK(sinter_stepper_set_option(st, "tolerance", r->tolerance));
        CHECK(sinter_stepper_set_option(st, "position_tolerance", r->position_tol));
    }
    sinter_stepper_stats before;
    before.struct_size = sizeof(before);
    CHECK(sinter_stepper_get_stats(st, &before));
    const double t0 = now();
    CHECK(sinter_stepper_advance(st, t_start + window));
    r->seconds = now() - t0;
    r->stats.struct_size = sizeof(r->stats);
    CHECK(sinter_stepper_get_stats(st, &r->stats));
    r->stats.steps -= before.steps; /* the checkpoint carries the counts of the preparation */
    r->stats.rejected -= before.rejected;
    r->stats.iterations -= before.iterations;
    r->stats.evaluations -= before.evaluations;
    read_state(sc, out);
    sinter_scene_destroy(sc);
    sinter_ctx_destroy(ctx);
    g_ctx = NULL;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : SINTER_SOURCE_DIR "/examples/scenes";
    const char *out_dir = argc > 2 ? argv[2] : ".";
    const double window = argc > 3 ? atof(argv[3]) : 0.1;
    if (!(window > 0.0)) {
        fprintf(stderr, "usage: press_work_precision [SCENE_DIR [OUT_DIR [WINDOW]]]\n");
        return 1;
    }
    char checkpoint[4096];
    snprintf(checkpoint, sizeof(checkpoint), "%s/press_work_precision.ckpt", out_dir);
    const double t_start = prepare(dir, checkpoint);

    /* Reference and its error estimate. */
    run ref = {0, 2.5e-6, 0, 0, 0, 0, 0, {0}}, ref2 = {0, 5e-6, 0, 0, 0, 0, 0, {0}};
    state s_ref, s_ref2;
    execute(dir, checkpoint, t_start, window, &ref, &s_ref);
    execute(dir, checkpoint, t_start, window, &ref2, &s_ref2);
    errors(&s_ref2, &s_ref, &ref2.error_x, &ref2.error_theta);
    free_state(&s_ref2);
    fprintf(stderr,
            "reference: explicit dt 2.5e-6 s, %.1f s; at 5e-6 s it differs by %.2e R and "
            "%.2e K\n",
            ref.seconds, ref2.error_x, ref2.error_theta);

    /* The runs: the explicit stepper at halved steps from the scene's 1e-3 s; the staggered
     * one at the seed's settings (dt_max 0.005 s, TOL 5e-4, position floor 1e-6 m) and tighter
     * tolerances, the floor scaled with TOL (2e-3 m x TOL). */
    run runs[] = {
        {0, 1e-3, 0, 0, 0, 0, 0, {0}},       {0, 5e-4, 0, 0, 0, 0, 0, {0}},
        {0, 2.5e-4, 0, 0, 0, 0, 0, {0}},     {0, 1.25e-4, 0, 0, 0, 0, 0, {0}},
        {0, 6.25e-5, 0, 0, 0, 0, 0, {0}},    {1, 5e-3, 5e-4, 1e-6, 0, 0, 0, {0}},
        {1, 5e-3, 1e-4, 2e-7, 0, 0, 0, {0}}, {1, 5e-3, 1e-5, 2e-8, 0, 0, 0, {0}},
        {1, 5e-3, 1e-6, 2e-9, 0, 0, 0, {0}},
    };
    const size_t count = sizeof(runs) / sizeof(runs[0]);
    const char *names[5] = {"log10 wall time", "explicit, position", "staggered, position",
                            "explicit, temperature", "staggered, temperature"};
    const char *units[5] = {"log10 s", "log10 RMS |x - x_ref| / R", "log10 RMS |x - x_ref| / R",
                            "log10 RMS |theta - theta_ref| / K",
                            "log10 RMS |theta - theta_ref| / K"};
    sinter_ctx *ctx = NULL;
    CHECK(sinter_ctx_create(&ctx, NULL));
    g_ctx = ctx;
    sinter_series *series = NULL;
    CHECK(sinter_series_create(&series, ctx, 5, names, units));
    printf("| stepper | dt or dt_max [s] | TOL | position floor [m] | wall time [s] | steps | "
           "rejected | evaluations | position error [R] | temperature error [K] |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t k = 0; k < count; ++k) {
        run *r = &runs[k];
        state s;
        execute(dir, checkpoint, t_start, window, r, &s);
        g_ctx = ctx;
        errors(&s, &s_ref, &r->error_x, &r->error_theta);
        free_state(&s);
        char tol[32] = "-", floor_text[32] = "-";
        if (r->staggered) {
            snprintf(tol, sizeof(tol), "%g", r->tolerance);
            snprintf(floor_text, sizeof(floor_text), "%g", r->position_tol);
        }
        printf("| %s | %g | %s | %s | %.2f | %llu | %llu | %llu | %.3e | %.3e |\n",
               r->staggered ? "staggered" : "explicit", r->dt, tol, floor_text, r->seconds,
               (unsigned long long)r->stats.steps, (unsigned long long)r->stats.rejected,
               (unsigned long long)r->stats.evaluations, r->error_x, r->error_theta);
        fflush(stdout);
        double row[5] = {log10(r->seconds), NAN, NAN, NAN, NAN};
        row[1 + r->staggered] = log10(r->error_x);
        row[3 + r->staggered] = log10(r->error_theta);
        CHECK(sinter_series_append(series, row));
    }
    printf("\nreference: explicit, dt = 2.5e-6 s, %.2f s; the same at 5e-6 s differs from it by "
           "%.3e R and %.3e K\n",
           ref.seconds, ref2.error_x, ref2.error_theta);
    char path[4096];
    snprintf(path, sizeof(path), "%s/work_precision.csv", out_dir);
    CHECK(sinter_series_write_csv(series, path));
    snprintf(path, sizeof(path), "%s/work_precision.svg", out_dir);
    const size_t start[3] = {0, 2, 4}, cols[4] = {1, 2, 3, 4};
    CHECK(sinter_series_write_svg(
        series, path, "press compression: error against wall time (log10)", 0, 2, start, cols));
    remove(checkpoint);
    sinter_series_destroy(series);
    sinter_ctx_destroy(ctx);
    free_state(&s_ref);
    return 0;
}
