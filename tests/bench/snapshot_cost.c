/*
 * What a snapshot of the contacts costs (issue 37): the example scenes advanced past their
 * start, then 40 rounds of 100 steps each followed by one sinter_snapshot_create; the median
 * and the shortest of each, and the snapshot's cost as a share of the 100 steps. Usage:
 * snapshot_cost SCENE... (run from examples/scenes, whose scenes name their particle files
 * relatively). Figures in RESULTS.md, "Snapshots of the contacts (issue 37)".
 */
#define _POSIX_C_SOURCE 200809L
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
    double steps[ROUNDS], snaps[ROUNDS];
    size_t pairs = 0, walls = 0;
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
        sinter_snapshot_destroy(snap);
    }
    qsort(steps, ROUNDS, sizeof(double), by_value);
    qsort(snaps, ROUNDS, sizeof(double), by_value);
    printf("%-22s %6zu %6zu %10.2f %10.2f %10.3f %10.3f %7.1f %%\n", path, pairs, walls,
           1e3 * steps[ROUNDS / 2], 1e3 * steps[0], 1e3 * snaps[ROUNDS / 2], 1e3 * snaps[0],
           100.0 * snaps[ROUNDS / 2] / steps[ROUNDS / 2]);
    sinter_scene_destroy(sc);
    return 0;
}

int main(int argc, char **argv)
{
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    printf("%-22s %6s %6s %10s %10s %10s %10s %9s\n", "scene", "pairs", "walls", "100 st ms",
           "(min)", "snap ms", "(min)", "share");
    int failed = 0;
    for (int k = 1; k < argc; ++k)
        failed |= measure(ctx, argv[k]);
    sinter_ctx_destroy(ctx);
    return failed;
}
