/*
 * The bonded solve K u = f (seed 001 eq. 40, src/bonded/solve.c) alone, on 1 and 2 threads:
 * a simple cubic lattice of NX x NY x NZ copper spheres (coordination 6, as seed 001's packings'
 * 5.5-5.8) bonded by necks of random radii, the particles numbered in a random order (as the
 * packings' random sequential addition leaves them), held on the principal planes as the
 * quasi-static stepper holds a packing, under sintering-like loads along each link, solved to
 * the stepper's tolerance (1e-7) from zero. Prints the time per solve (the best of `rounds`
 * rounds of `solves` solves), the PCG iterations, and a checksum of u (the same on 1 and 2
 * threads).
 *
 *   bonded_bench [NX NY NZ [solves [rounds]]]     (default 16 16 14 20 5: 3584 spheres)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bonded/beam.h"

static double next_uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0 * 2.0 - 1.0;
}

/* Lattice site (i, j, k) of an ny x nz-wide lattice, in lattice order. */
static size_t site(int i, int j, int k, int ny, int nz)
{
    return ((size_t)i * (size_t)ny + (size_t)j) * (size_t)nz + (size_t)k;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    const int nx = argc > 3 ? atoi(argv[1]) : 16, ny = argc > 3 ? atoi(argv[2]) : 16,
              nz = argc > 3 ? atoi(argv[3]) : 14;
    const int solves = argc > 4 ? atoi(argv[4]) : 20, rounds = argc > 5 ? atoi(argv[5]) : 5;
    if (nx < 2 || ny < 2 || nz < 2 || solves < 1 || rounds < 1) {
        fprintf(stderr, "usage: bonded_bench [NX NY NZ [solves [rounds]]]\n");
        return 2;
    }
    const size_t n = (size_t)nx * (size_t)ny * (size_t)nz;
    const double r = 25e-6;
    uint64_t seed = 2026;
    uint32_t *label = malloc(n * sizeof(*label));
    double *x = malloc(3 * n * sizeof(double)), *f = calloc(6 * n, sizeof(double)),
           *u = malloc(6 * n * sizeof(double));
    unsigned char *fixed = calloc(6 * n, 1);
    sinter_beam *links = malloc(3 * n * sizeof(*links));
    if (!label || !x || !f || !u || !fixed || !links)
        return 1;
    for (size_t p = 0; p < n; ++p)
        label[p] = (uint32_t)p;
    for (size_t p = n; p-- > 1;) { /* a random numbering */
        const size_t q = (size_t)((next_uniform(&seed) + 1.0) * 0.5 * (double)(p + 1)) % (p + 1);
        const uint32_t t = label[p];
        label[p] = label[q];
        label[q] = t;
    }
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                double *xp = x + 3 * (size_t)label[site(i, j, k, ny, nz)];
                xp[0] = (2 * i + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
                xp[1] = (2 * j + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
                xp[2] = (2 * k + 1) * r * 0.98 + 0.5e-6 * next_uniform(&seed);
            }
    size_t count = 0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                const int next[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
                for (int d = 0; d < 3; ++d) {
                    if (next[d][0] >= nx || next[d][1] >= ny || next[d][2] >= nz)
                        continue;
                    const uint32_t a = label[site(i, j, k, ny, nz)],
                                   b = label[site(next[d][0], next[d][1], next[d][2], ny, nz)];
                    const double rm = (0.25 + 0.15 * next_uniform(&seed)) * r;
                    if (sinter_beam_init(&links[count], a, b, x + 3 * a, x + 3 * b, 0.97 * r,
                                         0.99 * r, rm, 2 * r, 72e9, 0.3) != 0)
                        return 1;
                    ++count;
                }
            }
    for (size_t p = 0; p < n; ++p)
        for (int d = 0; d < 3; ++d)
            fixed[6 * p + (size_t)d] = x[3 * p + (size_t)d] < 1.5 * r;
    for (size_t k = 0; k < count; ++k) {
        const double fn = 1e-3 * (1.0 + 0.5 * next_uniform(&seed));
        for (int d = 0; d < 3; ++d) {
            f[6 * links[k].a + (size_t)d] += fn * links[k].axis[d];
            f[6 * links[k].b + (size_t)d] -= fn * links[k].axis[d];
        }
    }
    printf("bonded_bench: %zu spheres (%d x %d x %d, random numbering), %zu links, rtol 1e-7, "
           "best of %d rounds of %d solves\n",
           n, nx, ny, nz, count, rounds, solves);
    for (int threads = 1; threads <= 2; ++threads) {
        sinter_ctx *ctx = NULL;
        sinter_bonded_solver *sv = NULL;
        if (sinter_ctx_create(&ctx, NULL) != SINTER_OK ||
            sinter_ctx_set_threads(ctx, threads) != SINTER_OK ||
            sinter_bonded_solver_create(&sv, ctx) != SINTER_OK)
            return 1;
        double best = HUGE_VAL;
        int iterations = 0;
        for (int round = 0; round < rounds; ++round) {
            const double t0 = now();
            for (int s = 0; s < solves; ++s)
                if (sinter_bonded_solve(sv, n, links, count, fixed, f, u, 1e-7, &iterations) !=
                    SINTER_OK) {
                    fprintf(stderr, "solve failed: %s\n", sinter_last_error(ctx));
                    return 1;
                }
            best = fmin(best, (now() - t0) / solves);
        }
        double checksum = 0.0;
        for (size_t i = 0; i < 6 * n; ++i)
            checksum += fabs(u[i]);
        printf("threads %d: %.3f ms a solve, %d PCG iterations, %.3f us an iteration, "
               "sum |u| %.17g\n",
               threads, 1e3 * best, iterations, 1e6 * best / iterations, checksum);
        sinter_bonded_solver_destroy(sv);
        sinter_ctx_destroy(ctx);
    }
    free(label);
    free(x);
    free(f);
    free(u);
    free(fixed);
    free(links);
    return 0;
}
