/*
 * Shared by the benchmark programs: stop with the library's message when a call fails, the
 * clocks they time with, a sphere-file reader and writer, a list parser, a random packing and
 * its compaction. Define BENCH_NAME (the program's name, for messages) before
 * including; the program sets g_ctx to the context whose last error a failure prints.
 * Needs _POSIX_C_SOURCE >= 199309L (clock_gettime under -std=c11), defined before any header.
 */
#ifndef SINTER_BENCH_SUPPORT_H
#define SINTER_BENCH_SUPPORT_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sinter.h"

static sinter_ctx *g_ctx;

static inline void bench_check(sinter_status s, const char *what, int line)
{
    if (s != SINTER_OK) {
        fprintf(stderr, "%s:%d: %s failed: %s (%s)\n", BENCH_NAME, line, what,
                sinter_status_name(s), g_ctx ? sinter_last_error(g_ctx) : "");
        exit(1);
    }
}
#define CHECK(call) bench_check((call), #call, __LINE__)

/* CPU seconds of this process (all threads). */
static inline double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds of a monotonic wall clock. */
static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Spheres read from "x y z r" lines [m] (lines starting with '#' or not of four numbers are
 * skipped); stops the program when the file cannot be read or holds no sphere. */
typedef struct spheres {
    size_t n;
    double *x, *r; /* 3 and 1 per sphere, malloc'ed */
} spheres;

static inline spheres read_spheres(const char *path)
{
    spheres p = {0, NULL, NULL};
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    char line[512];
    size_t cap = 0;
    while (fgets(line, sizeof(line), f) != NULL) {
        double v[4];
        if (line[0] == '#' || sscanf(line, "%lf %lf %lf %lf", v, v + 1, v + 2, v + 3) != 4)
            continue;
        if (p.n == cap) {
            cap = cap ? 2 * cap : 1024;
            double *x = realloc(p.x, 3 * cap * sizeof(double)),
                   *r = x ? realloc(p.r, cap * sizeof(double)) : NULL;
            if (x == NULL || r == NULL) {
                fprintf(stderr, "%s: out of memory reading %s\n", BENCH_NAME, path);
                exit(1);
            }
            p.x = x, p.r = r;
        }
        memcpy(p.x + 3 * p.n, v, 3 * sizeof(double));
        p.r[p.n++] = v[3];
    }
    fclose(f);
    if (p.n == 0) {
        fprintf(stderr, "%s: no spheres in %s\n", BENCH_NAME, path);
        exit(1);
    }
    return p;
}

/* The set's spheres as "x y z r" lines [m] under the comment line `header` (no '#', no
 * newline), the format read_spheres reads; stops the program when the file cannot be written. */
static inline void write_spheres(const char *path, sinter_particles *ps, const char *header)
{
    size_t count = 0;
    const double *x = NULL, *r = NULL;
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, &count, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
        exit(1);
    }
    fprintf(f, "# %s\n", header);
    for (size_t i = 0; i < count; ++i)
        fprintf(f, "%.17g %.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2], r[i]);
    if (fclose(f) != 0) {
        perror(path);
        exit(1);
    }
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_RADIUS);
}

/* A space-separated list of numbers into out[0..max); returns the count. */
static inline size_t parse_numbers(const char *list, double *out, size_t max)
{
    size_t n = 0;
    for (const char *p = list; *p && n < max;) {
        char *e = NULL;
        const double v = strtod(p, &e);
        if (e == p)
            break;
        out[n++] = v;
        p = e;
    }
    return n;
}

/* count spheres of normally distributed radii (mean, spread [m]) placed by random sequential
 * addition into [0, box * scale] (material 0, temperature [K]); stops the program unless all
 * were placed. */
static inline void pack_normal(sinter_particles *ps, const double box[3], double scale,
                               double mean, double spread, uint64_t seed, double temperature,
                               size_t count)
{
    sinter_packing_options po;
    CHECK(sinter_packing_options_init(&po, sizeof(po)));
    for (int d = 0; d < 3; ++d) {
        po.box_min[d] = 0.0;
        po.box_max[d] = box[d] * scale;
    }
    po.distribution = SINTER_RADII_NORMAL;
    po.radius_mean = mean;
    po.radius_spread = spread;
    po.seed = seed;
    po.material = 0;
    po.temperature = temperature;
    size_t placed = 0;
    CHECK(sinter_pack_random(ps, &po, count, &placed));
    if (placed != count) {
        fprintf(stderr, "%s: RSA placed only %zu of %zu spheres\n", BENCH_NAME, placed, count);
        exit(1);
    }
}

/* Compact the set into the box [0, box] with the options co (their box is set here); returns
 * the result and the CPU seconds it took in *cpu. */
static inline sinter_compaction_result compact_into(sinter_particles *ps,
                                                    sinter_compaction_options *co,
                                                    const double box[3], double *cpu)
{
    for (int d = 0; d < 3; ++d) {
        co->box_min[d] = 0.0;
        co->box_max[d] = box[d];
    }
    sinter_compaction_result res;
    memset(&res, 0, sizeof(res));
    res.struct_size = sizeof(res);
    const double t0 = cpu_seconds();
    CHECK(sinter_pack_compact(ps, co, &res));
    *cpu = cpu_seconds() - t0;
    return res;
}

#endif
