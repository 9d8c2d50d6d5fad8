#define _POSIX_C_SOURCE 200809L
/*
 * sinter pair FILE... [-o DIR] [--quiet]: the two-particle 7DOF model for each pair file
 * (sinter_pair_run, docs/scene-reference.md "Pair files"), writing DIR/STEM.csv and
 * DIR/STEM.svg (STEM: the file's name without its folder and last extension; DIR: out/ by
 * default) and one summary line per file: the end's mean neck ratio and shrinkage and the first
 * time the run left the model's domain (the past_limit column, docs/7dof.md §2.6). The guard's
 * warnings go to stderr unless --quiet.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include <sinter.h>

#include "cli.h"

/* The summary line of one run, read back from its CSV. */
static sinter_status summary(sinter_ctx *ctx, const char *stem, const char *csv)
{
    sinter_series *s = NULL;
    sinter_status st = sinter_series_read_csv(&s, ctx, csv);
    size_t rows = 0;
    if (st == SINTER_OK)
        st = sinter_series_rows(s, &rows);
    if (st == SINTER_OK && rows == 0)
        st = SINTER_ERR_STATE;
    double t = 0.0, x = 0.0, shrink = 0.0, flagged_at = NAN, flag = 0.0;
    for (size_t k = 0; st == SINTER_OK && k < rows; ++k) {
        sinter_series_get(s, k, 9, &flag);
        if (flag != 0.0 && isnan(flagged_at))
            sinter_series_get(s, k, 0, &flagged_at);
    }
    if (st == SINTER_OK) {
        sinter_series_get(s, rows - 1, 0, &t);
        sinter_series_get(s, rows - 1, 2, &x);
        sinter_series_get(s, rows - 1, 3, &shrink);
        if (isnan(flagged_at))
            printf("%s: t = %.6g s: neck ratio x/R = %.4f, shrinkage = %.4e; within the model's "
                   "domain\n",
                   stem, t, x, shrink);
        else
            printf("%s: t = %.6g s: neck ratio x/R = %.4f, shrinkage = %.4e; PAST THE MODEL'S "
                   "LIMIT from t = %.6g s (past_limit column)\n",
                   stem, t, x, shrink, flagged_at);
    }
    sinter_series_destroy(s);
    return st;
}

int cli_pair(int argc, char **argv)
{
    const char *out_dir = "out";
    int quiet = 0, files = 0;
    for (int k = 2; k < argc; ++k) {
        if (strcmp(argv[k], "-o") == 0 && k + 1 < argc)
            out_dir = argv[++k];
        else if (strcmp(argv[k], "--quiet") == 0)
            quiet = 1;
        else if (argv[k][0] == '-')
            return 2;
        else
            ++files;
    }
    if (files == 0)
        return 2;
    if (mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "sinter: cannot make %s: %s\n", out_dir, strerror(errno));
        return 1;
    }
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    if (!quiet)
        sinter_ctx_set_log(ctx, cli_print_log, SINTER_LOG_WARNING, NULL);
    int rc = 0;
    for (int k = 2; k < argc; ++k) {
        if (strcmp(argv[k], "-o") == 0) {
            ++k;
            continue;
        }
        if (argv[k][0] == '-')
            continue;
        const char *base = strrchr(argv[k], '/');
        base = base != NULL ? base + 1 : argv[k];
        const char *dot = strrchr(base, '.');
        const int len = (int)(dot != NULL && dot != base ? (size_t)(dot - base) : strlen(base));
        char csv[4096], svg[4096], stem[256];
        snprintf(stem, sizeof(stem), "%.*s", len, base);
        if (snprintf(csv, sizeof(csv), "%s/%s.csv", out_dir, stem) >= (int)sizeof(csv) ||
            snprintf(svg, sizeof(svg), "%s/%s.svg", out_dir, stem) >= (int)sizeof(svg)) {
            fprintf(stderr, "sinter: %s: the output path is too long\n", argv[k]);
            rc = 1;
            continue;
        }
        sinter_status st = sinter_pair_run(ctx, argv[k], csv, svg);
        if (st == SINTER_OK)
            st = summary(ctx, stem, csv);
        if (st != SINTER_OK) {
            fprintf(stderr, "sinter: %s: %s (%s)\n", argv[k], sinter_last_error(ctx),
                    sinter_status_name(st));
            rc = 1;
        }
    }
    sinter_ctx_destroy(ctx);
    return rc;
}
