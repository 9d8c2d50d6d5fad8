/*
 * The quasi-static stepper's reproducible mode against the default on one subdomain (issue 43;
 * tests/bench/RESULTS.md): a simple-cubic lattice of n^3 copper spheres (R = 25 um, radii spread
 * by up to 0.2 %, 1293 K, the particles on x, y, z = 0 held on their planes) sintered for a
 * number of global steps, the default mode and the reproducible mode by turns in the same run
 * (so that both meet the same load of the host), several rounds. Prints the CPU seconds of
 * each run, the ratio per round, the PCG iterations and the final time of each mode.
 *
 * Usage: qs_repro_cost [n = 8] [steps = 100] [rounds = 3] [strategy = 2]
 */
#define _POSIX_C_SOURCE 199309L
#define BENCH_NAME "qs_repro_cost"
#include "bench_support.h"

static double run(int n, int steps, int strategy, int reproducible, double *end_time,
                  unsigned long long *pcg)
{
    const double R = 25e-6;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    CHECK(sinter_material_create(&mat, g_ctx, "copper"));
    CHECK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 72e9));
    CHECK(sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_DENSITY, 8960));
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, mat));
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_QUASISTATIC, ps, NULL));
    CHECK(sinter_stepper_set_option(st, "qs_strategy", strategy));
    CHECK(sinter_stepper_set_option(st, "reproducible", reproducible));
    CHECK(sinter_stepper_set_dt(st, 1e-3));
    for (int p = 0; p < n * n * n; ++p) {
        const int i = p / (n * n), j = (p / n) % n, k = p % n;
        const double x[3] = {(1 + 2 * i) * R, (1 + 2 * j) * R, (1 + 2 * k) * R};
        const double r = R * (1.0 + 2e-3 * (double)((p * 7919) % 97) / 96.0);
        const uint64_t id = 1 + (uint64_t)p;
        CHECK(sinter_particles_add_with_ids(ps, 1, &id, x, &r, 0, 1293.0, NULL));
    }
    const double t0 = cpu_seconds();
    CHECK(sinter_stepper_step(st, (size_t)steps));
    const double cpu = cpu_seconds() - t0;
    sinter_sintering_stats ss;
    memset(&ss, 0, sizeof(ss));
    ss.struct_size = sizeof(ss);
    CHECK(sinter_stepper_sintering_stats(st, &ss));
    CHECK(sinter_stepper_time(st, end_time));
    *pcg = (unsigned long long)ss.pcg_iterations;
    sinter_stepper_destroy(st);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    return cpu;
}

int main(int argc, char **argv)
{
    const int n = argc > 1 ? atoi(argv[1]) : 8, steps = argc > 2 ? atoi(argv[2]) : 100;
    const int rounds = argc > 3 ? atoi(argv[3]) : 3, strategy = argc > 4 ? atoi(argv[4]) : 2;
    if (n < 2 || steps < 1 || rounds < 1 || strategy < 2 || strategy > 3) {
        fprintf(stderr, "usage: qs_repro_cost [n >= 2] [steps >= 1] [rounds >= 1] [2|3]\n");
        return 2;
    }
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    CHECK(sinter_ctx_set_threads(g_ctx, 1));
    printf("%d spheres, %d global steps, strategy %d, one thread\n", n * n * n, steps, strategy);
    for (int r = 0; r < rounds; ++r) {
        double t[2];
        unsigned long long pcg[2];
        double cpu[2];
        for (int mode = 0; mode < 2; ++mode)
            cpu[mode] = run(n, steps, strategy, mode, &t[mode], &pcg[mode]);
        printf("round %d: default %.3f s CPU (t = %g s, %llu PCG iterations), reproducible %.3f s "
               "(t = %g s, %llu PCG iterations): ratio %.2f\n",
               r + 1, cpu[0], t[0], pcg[0], cpu[1], t[1], pcg[1], cpu[1] / cpu[0]);
        fflush(stdout);
    }
    sinter_ctx_destroy(g_ctx);
    return 0;
}
