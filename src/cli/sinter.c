#define _POSIX_C_SOURCE 200809L
/*
 * sinter: run libsinter scene files from the command line.
 *
 *   sinter run SCENE [-o DIR] [--restart CHECKPOINT] [--end-time T] [--stop-at T]
 *                    [--threads N] [--log LEVEL] [--progress S]
 *   sinter check SCENE
 *   sinter plot DIR [--title TEXT] [--file CSV] [--x NAME] [--panel NAMES]... [-o SVG]
 *   sinter pair FILE... [-o DIR] [--quiet]   (pair.c)
 *   sinter info | --help | --version
 *
 * `run` reports its progress (simulated time, share done, steps per second, time left) on
 * stderr at a bounded rate, whatever the output files (issue 41): on a terminal one line
 * updated in place (\r) at most once a second, otherwise a line at most every 5 s;
 * --progress S sets that interval [s] (0: no progress), and a one-line summary ends the run.
 * --threads N runs the library on N threads (sinter_ctx_set_threads; 0: as many as OpenMP offers,
 * OMP_NUM_THREADS or the cores; default the scene's [stepper] threads, else 1): the results
 * are the same for every N. --log LEVEL
 * (error, warning, info or debug) prints the library's messages up to that level to stderr, one per
 * line (sinter_ctx_set_log): info tells what the set-up did (the compaction's steps, its green
 * body, what a restart took from its checkpoint), debug also the steppers' choices (the explicit
 * stepper's thread count and stores, by timing).
 *
 * --restart continues the run of DIR/checkpoint.bin (sinter_scene_restart): the series and
 * frames of -o DIR are continued where they hold the run's earlier samples. A scene file
 * edited since the run: its explicit dt and its [output] interval and checkpoint_interval win
 * over the checkpoint's, and the restart prints a warning for each (also without --log;
 * docs/getting-started.md, "Stopping and continuing"). --end-time T
 * replaces the scene's end time; --stop-at T stops at the first sample at or after the
 * simulated time T (a sample within a relative 1e-12 below T counts as at T: sample times carry
 * their steps' rounding), writing the checkpoint to continue from (exit status 0).
 * In a build with -DSINTER_MPI=ON, `run` started by mpiexec runs on the ranks instead
 * (run_mpi.c, over libsinter_mpi; a pour in run_mpi_pour.c, quasi-static output in
 * run_mpi_qs.c; docs/scaleout.md).
 *
 * SIGINT (Ctrl-C) or SIGTERM ends the current step, writes the checkpoint and the plot and
 * exits with 130 or 143; a second signal ends the program at once.
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <sinter.h>

#include "cli.h"

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
    int tty;        /* stderr is a terminal: \r updates */
    double every;   /* the least interval between two reports [s] (0: none) */
    double stop_at; /* --stop-at [s], or infinity */
    int stopped_at; /* the run was stopped by --stop-at */
} progress_state;

static int show_progress(double time, double end_time, void *user)
{
    progress_state *p = user;
    /* a sample's time carries its steps' rounding (0.029999999999999999 for 0.03): within a
     * relative 1e-12 below T it is the sample at T */
    if (time >= p->stop_at - 1e-12 * fabs(p->stop_at)) {
        p->stopped_at = 1;
        return 1;
    }
    if (!(p->every > 0.0))
        return 0;
    const double t = now();
    if (t - p->last_print < p->every)
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
    const double share = end_time > 0 ? 100.0 * time / end_time : 0.0;
    fprintf(stderr, "%st = %.4g / %.4g s (%.1f %%)   %.3g steps/s   %.0f s left%s",
            p->tty ? "\r  " : "sinter: ", time, end_time, share, rate, left > 0 ? left : 0.0,
            p->tty ? "      " : "\n");
    fflush(stderr);
    return 0;
}

static const char USAGE[] =
    "usage: sinter run SCENE [-o DIR] [--restart CHECKPOINT] [--end-time T] [--stop-at T]\n"
    "                        [--threads N] [--log error|warning|info|debug] [--progress S]\n"
    "       sinter check SCENE\n"
    "       sinter plot DIR [--title TEXT] [--file CSV] [--x NAME] [--panel NAMES]... [-o SVG]\n"
    "       sinter pair FILE... [-o DIR] [--quiet]\n"
    "       sinter info | --help | --version\n";

static int usage(void)
{
    fputs(USAGE, stderr);
    return 2;
}

static int help(void)
{
    fputs(USAGE, stdout);
    fputs("\n"
          "run      run a scene file, writing DIR (default out/): series.csv, series.svg,\n"
          "         the ParaView collection NAME.pvd with frames/, checkpoint.bin\n"
          "         --restart F   continue the run that wrote checkpoint F\n"
          "         --end-time T  the scene's end time [s] instead of the file's\n"
          "         --stop-at T   stop at the first sample at or after T [s], with a checkpoint\n"
          "         --progress S  progress on stderr at most every S seconds (0: none; default\n"
          "                       1 on a terminal, updated in place, else 5, one line each)\n"
          "         Ctrl-C stops after the current step, with a checkpoint (exit status 130)\n"
#ifdef SINTER_CLI_MPI
          "         under mpiexec (this MPI build): on the ranks ([pour], [compact] too), writing\n"
          "         series.csv, frames/*.pvtu over one piece per rank and checkpoint.mpi\n"
          "         (--restart it on any number of ranks); docs/scaleout.md\n"
#endif
          "check    read and check a scene without running it\n"
          "plot     draw DIR/series.svg from DIR/series.csv (any run, finished or not);\n"
          "         with --panel NAMES (comma-separated column names or their prefixes, one\n"
          "         panel each, up to 8) those columns of DIR/series.csv or of --file CSV\n"
          "         (relative to DIR, e.g. frames/profile_z_00010.csv) against --x NAME\n"
          "         (default: the first column), into -o SVG (default: the CSV's name .svg)\n"
          "pair     the two-particle 7DOF model of each pair file along its temperature\n"
          "         schedule: DIR/STEM.csv (neck ratio, shrinkage, past_limit) and DIR/STEM.svg\n"
          "         (default out/); --quiet leaves out the validity guard's warnings\n"
          "info     the library's version, models and units\n"
          "Units are SI throughout. Scene files: examples/scenes/README.md.\n",
          stdout);
    return 0;
}

static int fail(sinter_ctx *ctx, sinter_status st)
{
    fprintf(stderr, "sinter: %s (%s)\n", sinter_last_error(ctx), sinter_status_name(st));
    return 1;
}

static const char *const LOG_LEVELS[] = {"error", "warning", "info", "debug"};

/* --log: the library's messages to stderr, one a line, after the level's name. */
void cli_print_log(int level, const char *message, void *user)
{
    (void)user;
    fprintf(stderr, "sinter [%s]: %s\n", level >= 0 && level <= 3 ? LOG_LEVELS[level] : "?",
            message);
}

/* SIGINT and SIGTERM: a stop request to the running context (sinter_ctx_request_stop is
 * async-signal-safe); the handler is reset, so a second signal ends the program at once. */
static sinter_ctx *volatile signal_ctx = NULL;
static volatile sig_atomic_t signal_number = 0;

static void on_signal(int sig)
{
    signal_number = sig;
    if (signal_ctx != NULL)
        sinter_ctx_request_stop(signal_ctx);
}

static void catch_signals(sinter_ctx *ctx)
{
    signal_ctx = ctx;
    struct sigaction action;
    memset(&action, 0, sizeof(action));
    action.sa_handler = on_signal;
    action.sa_flags = (int)SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, NULL);
    sigaction(SIGTERM, &action, NULL);
}

/* A time option's value [s]: finite and not negative. */
static int time_value(const char *option, const char *text, double *value)
{
    char *end = NULL;
    *value = strtod(text, &end);
    if (end == text || *end != '\0' || !(*value >= 0.0) || *value > 1e300) {
        fprintf(stderr, "sinter: %s %s: expected a time in seconds (a number >= 0)\n", option,
                text);
        return 0;
    }
    return 1;
}

static int run(int argc, char **argv)
{
    const char *scene_path = NULL, *out_dir = "out", *restart = NULL;
    int threads = -1, log_level = -1; /* threads: -1 the scene's, else 1 */
    double end_time = -1.0, stop_at = HUGE_VAL, every = -1.0;
    for (int k = 2; k < argc; ++k) {
        if (strcmp(argv[k], "-o") == 0 && k + 1 < argc)
            out_dir = argv[++k];
        else if (strcmp(argv[k], "--restart") == 0 && k + 1 < argc)
            restart = argv[++k];
        else if (strcmp(argv[k], "--end-time") == 0 && k + 1 < argc) {
            if (!time_value(argv[k], argv[k + 1], &end_time))
                return 2;
            ++k;
        } else if (strcmp(argv[k], "--stop-at") == 0 && k + 1 < argc) {
            if (!time_value(argv[k], argv[k + 1], &stop_at))
                return 2;
            ++k;
        } else if (strcmp(argv[k], "--progress") == 0 && k + 1 < argc) {
            if (!time_value(argv[k], argv[k + 1], &every))
                return 2;
            ++k;
        } else if (strcmp(argv[k], "--threads") == 0 && k + 1 < argc) {
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
    sinter_status st = sinter_ctx_set_threads(ctx, threads >= 0 ? threads : 1);
    if (st == SINTER_OK && log_level >= 0)
        st = sinter_ctx_set_log(ctx, cli_print_log, log_level, NULL);
    if (st != SINTER_OK) {
        const int rc = fail(ctx, st);
        sinter_ctx_destroy(ctx);
        return rc;
    }
    sinter_scene *scene = NULL;
    st = sinter_scene_load(&scene, ctx, scene_path);
    if (st == SINTER_OK && threads >= 0) /* over the scene's [stepper] threads */
        st = sinter_ctx_set_threads(ctx, threads);
    if (st == SINTER_OK && end_time >= 0.0)
        st = sinter_scene_set_end_time(scene, end_time);
    if (st == SINTER_OK && restart != NULL) {
        /* what the restart takes from the scene over the checkpoint (an edited dt or output
         * schedule) is a warning, printed even without --log */
        if (log_level < 0)
            st = sinter_ctx_set_log(ctx, cli_print_log, SINTER_LOG_WARNING, NULL);
        if (st == SINTER_OK)
            st = sinter_scene_restart(scene, restart);
        if (log_level < 0)
            (void)sinter_ctx_set_log(ctx, NULL, 0, NULL);
    }
    int rc = 0;
    const int tty = isatty(fileno(stderr));
    progress_state p = {scene,   now(), now(), tty, every >= 0.0 ? every : tty ? 1.0 : 5.0,
                        stop_at, 0};
    if (st == SINTER_OK) {
        catch_signals(ctx);
        st = sinter_scene_run(scene, out_dir, show_progress, &p);
        if (p.tty && p.every > 0.0 && p.last_print > p.started)
            fprintf(stderr, "\n");
    }
    double t = 0.0;
    sinter_stepper *stepper = NULL;
    if (scene != NULL && sinter_scene_get_stepper(scene, &stepper) == SINTER_OK)
        sinter_stepper_time(stepper, &t);
    if (st == SINTER_OK) {
        printf("sinter: ran %s in %.1f s; results in %s/ (series.csv, series.svg, "
               "ParaView collection *.pvd with frames/)\n",
               scene_path, now() - p.started, out_dir);
    } else if (st == SINTER_ERR_INTERRUPTED) {
        const int sig = (int)signal_number;
        printf("sinter: %s at t = %.9g s; continue with: sinter run %s -o %s --restart "
               "%s/checkpoint.bin\n",
               sig ? "interrupted" : "stopped (--stop-at)", t, scene_path, out_dir, out_dir);
        rc = sig ? 128 + sig : 0;
        if (sig)
            fprintf(stderr, "sinter: %s\n", sinter_last_error(ctx));
    } else {
        rc = fail(ctx, st);
    }
    signal_ctx = NULL;
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

/*
 * plot DIR [--title TEXT]: series.svg from series.csv, for any run, finished or not;
 * plot DIR [--file CSV] [--x NAME] [--panel NAMES]... [-o SVG] [--title TEXT]: chosen columns
 * of any CSV of the run (sinter_plot_csv), into the CSV's name with .svg unless -o.
 */
static int plot(int argc, char **argv)
{
    enum { MAX_PANELS = 8 };
    const char *dir = NULL, *title = NULL, *file = NULL, *x = NULL, *svg = NULL;
    const char *panels[MAX_PANELS];
    size_t panel_count = 0;
    for (int k = 2; k < argc; ++k) {
        const int more = k + 1 < argc;
        if (strcmp(argv[k], "--title") == 0 && more)
            title = argv[++k];
        else if (strcmp(argv[k], "--file") == 0 && more)
            file = argv[++k];
        else if (strcmp(argv[k], "--x") == 0 && more)
            x = argv[++k];
        else if (strcmp(argv[k], "-o") == 0 && more)
            svg = argv[++k];
        else if (strcmp(argv[k], "--panel") == 0 && more && panel_count < MAX_PANELS)
            panels[panel_count++] = argv[++k];
        else if (argv[k][0] != '-' && dir == NULL)
            dir = argv[k];
        else
            return usage();
    }
    if (dir == NULL)
        return usage();
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    sinter_status st = SINTER_OK;
    char csv_path[4096], svg_path[4096 + 8];
    if (file == NULL && x == NULL && svg == NULL && panel_count == 0) {
        st = sinter_plot_run(ctx, dir, title);
        snprintf(svg_path, sizeof(svg_path), "%s/series.svg", dir);
    } else {
        const int n =
            snprintf(csv_path, sizeof(csv_path), "%s/%s", dir, file != NULL ? file : "series.csv");
        const size_t len = strlen(csv_path);
        if (svg != NULL)
            snprintf(svg_path, sizeof(svg_path), "%s", svg);
        else if (len > 4 && strcmp(csv_path + len - 4, ".csv") == 0)
            snprintf(svg_path, sizeof(svg_path), "%.*s.svg", (int)(len - 4), csv_path);
        else
            snprintf(svg_path, sizeof(svg_path), "%s.svg", csv_path);
        if (n < 0 || (size_t)n >= sizeof(csv_path) - 4) {
            fprintf(stderr, "sinter: path too long\n");
            sinter_ctx_destroy(ctx);
            return 2;
        }
        st = sinter_plot_csv(ctx, csv_path, svg_path, title, x, panels, panel_count);
    }
    const int rc = st == SINTER_OK ? 0 : fail(ctx, st);
    if (st == SINTER_OK)
        printf("sinter: drew %s\n", svg_path);
    sinter_ctx_destroy(ctx);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2)
        return usage();
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
        strcmp(argv[1], "help") == 0)
        return help();
    if (strcmp(argv[1], "--version") == 0) {
        printf("sinter %s\n", sinter_version_string());
        return 0;
    }
    if (strcmp(argv[1], "plot") == 0)
        return plot(argc, argv);
#ifdef SINTER_CLI_MPI
    if (strcmp(argv[1], "run") == 0 && cli_mpi_launched()) {
        return cli_run_mpi(argc, argv);
    }
#endif
    if (strcmp(argv[1], "run") == 0)
        return run(argc, argv);
    if (strcmp(argv[1], "check") == 0 && argc == 3)
        return check(argv[2]);
    if (strcmp(argv[1], "info") == 0)
        return info();
    if (strcmp(argv[1], "pair") == 0) {
        const int rc = cli_pair(argc, argv);
        return rc == 2 ? usage() : rc;
    }
    return usage();
}
