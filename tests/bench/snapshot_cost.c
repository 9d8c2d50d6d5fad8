/*
 * What a snapshot of the contacts costs (issue 37): the example scenes advanced past their
 * start, then 40 rounds of 100 steps each followed by one sinter_snapshot_create and one
 * coarse-grained stress field from it (sinter_coarse_grain, which forms every field: a kernel
 * of width one mean particle diameter, cut at 3 widths, on a grid of that spacing over the
 * particles' bounding box grown by the cut); the median and the shortest of each, and each
 * one's cost as a share of the 100 steps. Usage:
 * snapshot_cost SCENE... (run from examples/scenes, whose scenes name their particle files
 * relatively). Figures in RESULTS.md, "Snapshots of the contacts (issue 37)".
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <sinter.h>

enum { ROUNDS = 40, STEPS = 100 };

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The grid of the fields: spacing and width one mean diameter over the grown bounding box. */
static int field_grid(const sinter_particles *ps, sinter_coarse_options *o)
{
    const double *x = NULL, *r = NULL;
    size_t n = 0;
    if (sinter_coarse_options_init(o, sizeof(*o)) != SINTER_OK ||
        sinter_particles_count(ps, &n) != SINTER_OK || n == 0 ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) !=
            SINTER_OK)
        return 1;
    if (sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL) !=
        SINTER_OK) {
        sinter_particles_release(ps, SINTER_FIELD_POSITION);
        return 1;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double mean = 0.0;
    for (size_t i = 0; i < n; ++i) {
        mean += r[i] / (double)n;
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], x[3 * i + (size_t)d]);
            hi[d] = fmax(hi[d], x[3 * i + (size_t)d]);
        }
    }
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_RADIUS);
    o->width = 2.0 * mean;
    for (int d = 0; d < 3; ++d) {
        o->origin[d] = lo[d] - 3.0 * o->width;
        o->spacing[d] = o->width;
        o->points[d] = (size_t)((hi[d] - lo[d]) / o->width) + 7;
    }
    return 0;
}

static int measure(sinter_ctx *ctx, const char *path)
{
    sinter_scene *sc = NULL;
    sinter_stepper *st = NULL;
    if (sinter_scene_load(&sc, ctx, path) != SINTER_OK ||
        sinter_scene_get_stepper(sc, &st) != SINTER_OK || sinter_stepper_step(st, 3000) != 0) {
        fprintf(stderr, "%s: %s\n", path, sinter_last_error(ctx));
        sinter_scene_destroy(sc);
        return 1;
    }
    double steps[ROUNDS], snaps[ROUNDS], fields[ROUNDS];
    size_t pairs = 0, walls = 0;
    sinter_particles *ps = NULL;
    sinter_coarse_options grid;
    if (sinter_scene_get_particles(sc, &ps) != SINTER_OK || field_grid(ps, &grid) != 0) {
        fprintf(stderr, "%s: no particles\n", path);
        sinter_scene_destroy(sc);
        return 1;
    }
    const size_t points = grid.points[0] * grid.points[1] * grid.points[2];
    double *stress = malloc(9 * points * sizeof(double));
    if (stress == NULL) {
        sinter_scene_destroy(sc);
        return 1;
    }
    for (int k = 0; k < ROUNDS; ++k) {
        double t0 = now();
        if (sinter_stepper_step(st, STEPS) != SINTER_OK)
            break;
        steps[k] = now() - t0;
        sinter_snapshot *snap = NULL;
        t0 = now();
        if (sinter_snapshot_create(&snap, st) != SINTER_OK) {
            fprintf(stderr, "%s: %s\n", path, sinter_last_error(ctx));
            sinter_scene_destroy(sc);
            return 1;
        }
        snaps[k] = now() - t0;
        (void)sinter_snapshot_counts(snap, &pairs, &walls, NULL, NULL);
        t0 = now();
        const sinter_status fs =
            sinter_coarse_grain(ps, snap, &grid, SINTER_COARSE_STRESS, stress, 9 * points);
        fields[k] = now() - t0;
        sinter_snapshot_destroy(snap);
        if (fs != SINTER_OK) {
            fprintf(stderr, "%s: %s\n", path, sinter_last_error(ctx));
            free(stress);
            sinter_scene_destroy(sc);
            return 1;
        }
    }
    qsort(steps, ROUNDS, sizeof(double), by_value);
    qsort(snaps, ROUNDS, sizeof(double), by_value);
    qsort(fields, ROUNDS, sizeof(double), by_value);
    printf("%-22s %6zu %6zu %10.2f %10.2f %10.3f %10.3f %7.1f %% %8zu %10.3f %10.3f %7.1f %%\n",
           path, pairs, walls, 1e3 * steps[ROUNDS / 2], 1e3 * steps[0], 1e3 * snaps[ROUNDS / 2],
           1e3 * snaps[0], 100.0 * snaps[ROUNDS / 2] / steps[ROUNDS / 2], points,
           1e3 * fields[ROUNDS / 2], 1e3 * fields[0],
           100.0 * fields[ROUNDS / 2] / steps[ROUNDS / 2]);
    free(stress);
    sinter_scene_destroy(sc);
    return 0;
}

int main(int argc, char **argv)
{
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    printf("%-22s %6s %6s %10s %10s %10s %10s %9s %8s %10s %10s %9s\n", "scene", "pairs", "walls",
           "100 st ms", "(min)", "snap ms", "(min)", "share", "points", "fields ms", "(min)",
           "share");
    int failed = 0;
    for (int k = 1; k < argc; ++k)
        failed |= measure(ctx, argv[k]);
    sinter_ctx_destroy(ctx);
    return failed;
}
