#define _POSIX_C_SOURCE 200809L
/*
 * sinter: run libsinter scene files from the command line.
 *
 *   sinter run SCENE [-o DIR] [--restart CHECKPOINT] [--threads N] [--log LEVEL]
 *   sinter check SCENE
 *   sinter info
 *
 * On a terminal, `run` shows progress (simulated time, steps per second, time
 * left); otherwise it is quiet apart from a one-line summary. --threads N runs the library on N
 * threads (sinter_ctx_set_threads; 0: as many as OpenMP offers, OMP_NUM_THREADS or the cores;
 * default 1): the results are the same for every N. --log LEVEL (error, warning, info or debug)
 * prints the library's messages up to that level to stderr, one per line (sinter_ctx_set_log):
 * info tells what the set-up did (the compaction's steps, its green body), debug also the
 * steppers' choices (the explicit stepper's thread count and stores, by timing).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <sinter.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct progress_state {
    sinter_scene *scene;
    double started;
    double last_print;
} progress_state;

static int show_progress(double time, double end_time, void *user)
{
    progress_state *p = user;
    const double t = now();
    if (t - p->last_print < 0.2)
        return 0;
    p->last_print = t;
    sinter_stepper *st = NULL;
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    if (sinter_scene_get_stepper(p->scene, &st) == SINTER_OK)
        sinter_stepper_get_stats(st, &stats);
    const double elapsed = t - p->started;
    const double rate = elapsed > 0 ? (double)stats.steps / elapsed : 0.0;
    const double left = time > 0 ? elapsed * (end_time - time) / time : 0.0;
    fprintf(stderr, "\r  t = %.4g / %.4g s   %.3g steps/s   %.0f s left      ", time, end_time,
            rate, left > 0 ? left : 0.0);
    fflush(stderr);
    return 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: sinter run SCENE [-o DIR] [--restart CHECKPOINT] [--threads N] "
                    "[--log error|warning|info|debug]\n"
                    "       sinter check SCENE\n"
                    "       sinter info\n");
    return 2;
}

static int fail(sinter_ctx *ctx, sinter_status st)
{
    fprintf(stderr, "sinter: %s (%s)\n", sinter_last_error(ctx), sinter_status_name(st));
    return 1;
}

static const char *const LOG_LEVELS[] = {"error", "warning", "info", "debug"};

/* --log: the library's messages to stderr, one a line, after the level's name. */
static void print_log(int level, const char *message, void *user)
{
    (void)user;
    fprintf(stderr, "sinter [%s]: %s\n", level >= 0 && level <= 3 ? LOG_LEVELS[level] : "?",
            message);
}

static int run(int argc, char **argv)
{
    const char *scene_path = NULL, *out_dir = "out", *restart = NULL;
    int threads = 1, log_level = -1;
    for (int k = 2; k < argc; ++k) {
        if (strcmp(argv[k], "-o") == 0 && k + 1 < argc)
            out_dir = argv[++k];
        else if (strcmp(argv[k], "--restart") == 0 && k + 1 < argc)
            restart = argv[++k];
        else if (strcmp(argv[k], "--threads") == 0 && k + 1 < argc) {
            char *end = NULL;
            const long value = strtol(argv[++k], &end, 10);
            if (end == argv[k] || *end != '\0' || value < 0 || value > 4096) {
                fprintf(stderr,
                        "sinter: --threads %s: expected a whole number from 0 (all) to "
                        "4096\n",
                        argv[k]);
                return 2;
            }
            threads = (int)value;
        } else if (strcmp(argv[k], "--log") == 0 && k + 1 < argc) {
            ++k;
            for (int level = 0; level < 4; ++level)
                if (strcmp(argv[k], LOG_LEVELS[level]) == 0)
                    log_level = level;
            if (log_level < 0) {
                fprintf(stderr, "sinter: --log %s: expected error, warning, info or debug\n",
                        argv[k]);
                return 2;
            }
        } else if (argv[k][0] != '-' && scene_path == NULL)
            scene_path = argv[k];
        else
            return usage();
    }
    if (scene_path == NULL)
        return usage();
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    sinter_status st = sinter_ctx_set_threads(ctx, threads);
    if (st == SINTER_OK && log_level >= 0)
        st = sinter_ctx_set_log(ctx, print_log, log_level, NULL);
    if (st != SINTER_OK) {
        const int rc = fail(ctx, st);
        sinter_ctx_destroy(ctx);
        return rc;
    }
    sinter_scene *scene = NULL;
    st = sinter_scene_load(&scene, ctx, scene_path);
    if (st == SINTER_OK && restart != NULL) {
        sinter_stepper *stepper = NULL;
        sinter_scene_get_stepper(scene, &stepper);
        st = sinter_checkpoint_read(stepper, restart);
    }
    int rc = 0;
    if (st == SINTER_OK) {
        const int tty = isatty(fileno(stderr));
        progress_state p = {scene, now(), 0.0};
        st = sinter_scene_run(scene, out_dir, tty ? show_progress : NULL, &p);
        if (tty)
            fprintf(stderr, "\n");
        if (st == SINTER_OK) {
            double end = 0;
            sinter_scene_end_time(scene, &end);
            printf("sinter: ran %s in %.1f s; results in %s/ (series.csv, series.svg, "
                   "ParaView collection *.pvd with frames/)\n",
                   scene_path, now() - p.started, out_dir);
        }
    }
    if (st != SINTER_OK)
        rc = fail(ctx, st);
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    return rc;
}

static int check(const char *path)
{
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    sinter_scene *scene = NULL;
    sinter_status st = sinter_scene_load(&scene, ctx, path);
    if (st == SINTER_OK) /* the set-up checks of a run, without stepping */
        st = sinter_scene_check(scene);
    int rc = 0;
    if (st != SINTER_OK) {
        rc = fail(ctx, st);
    } else {
        sinter_particles *ps = NULL;
        size_t n = 0;
        sinter_scene_get_particles(scene, &ps);
        sinter_particles_count(ps, &n);
        printf("%s: valid scene with %zu particles\n", path, n);
    }
    sinter_scene_destroy(scene);
    sinter_ctx_destroy(ctx);
    return rc;
}

static int info(void)
{
    printf("libsinter %s (version number %u)\n", sinter_version_string(), sinter_version_number());
    printf("force models: hertz_mindlin, power_law, linear_spring, drag, gravity, body_force\n");
    printf("steppers: explicit, staggered, quasistatic\n");
    printf("units: SI (m, kg, s, K, N, Pa, W, A, V)\n");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2)
        return usage();
    if (strcmp(argv[1], "run") == 0)
        return run(argc, argv);
    if (strcmp(argv[1], "check") == 0 && argc == 3)
        return check(argv[2]);
    if (strcmp(argv[1], "info") == 0)
        return info();
    return usage();
}
