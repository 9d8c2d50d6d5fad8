/*
 * lockstep_probe: the best 2-thread speed-up this machine allows a code that meets once per
 * step, as an explicit DEM step does (RESULTS.md, issue 9, session 19).
 *
 *   lockstep_probe [step_us] [steps] [block]
 *
 * A "step" is step_us microseconds of pure arithmetic (a chain of dependent multiply-adds in
 * registers: no memory traffic, no shared data), split evenly between the threads, which then
 * meet at a barrier, as the law's parallel region ends each step. Blocks of `block` steps
 * alternate between one thread doing the whole step and two threads doing half each (one
 * first, then two, then two, then one, ...), so that both sides see the same minutes of the
 * host. With cores of their own and no one else on the host the speed-up is 2 less the
 * barrier's cost (about 1-2 us on the project's VMs); where the host takes a vCPU away now and
 * then, every step of the other thread waits for it, and the speed-up falls, whatever the code.
 * Prints the ratio of the summed times and the median and range of the block pairs' ratios.
 */
#define _POSIX_C_SOURCE 200809L
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* `n` dependent multiply-adds; the result keeps the compiler from dropping them (not
 * inlined, and the start value comes from a volatile, so that no call is computed at compile
 * time). */
static volatile double spin_start = 1.0;
__attribute__((noinline)) static double spin(long n, double x)
{
    for (long k = 0; k < n; ++k)
        x = x * 0.999999999 + 1e-9;
    return x;
}

static int compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    const double step_us = argc > 1 ? atof(argv[1]) : 500.0;
    const long steps = argc > 2 ? atol(argv[2]) : 20000;
    const long block = argc > 3 ? atol(argv[3]) : 100;
    if (!(step_us > 0.0) || steps < 2 * block || block < 1) {
        fprintf(stderr, "usage: lockstep_probe [step_us > 0] [steps >= 2 block] [block >= 1]\n");
        return 1;
    }
    /* calibrate: multiply-adds per microsecond on one thread */
    double sink = 0.0, t = now();
    sink += spin(200000000, spin_start);
    const double per_us = 200000000.0 / ((now() - t) * 1e6);
    const long work = (long)(step_us * per_us); /* a step's multiply-adds */
    double side[2] = {0.0, 0.0};
    long done[2] = {0, 0}, pairs = 0;
    size_t nratio = 0;
    double *ratios = malloc((size_t)(steps / block / 2 + 2) * sizeof(double));
    if (ratios == NULL)
        return 1;
    for (long k = 0; k + 2 * block <= steps; k += 2 * block, ++pairs) {
        double pair[2] = {0.0, 0.0};
        for (int turn = 0; turn < 2; ++turn) {
            const int threads = 1 + ((int)(pairs % 2) ^ turn);
            double part = 0.0;
            const double t0 = now();
#pragma omp parallel num_threads(threads) reduction(+ : part)
            for (long s = 0; s < block; ++s) {
                part += spin(work / threads, spin_start + (double)s);
#pragma omp barrier
            }
            pair[threads - 1] = now() - t0;
            sink += part;
        }
        side[0] += pair[0], side[1] += pair[1];
        done[0] += block, done[1] += block;
        ratios[nratio++] = pair[0] / pair[1];
    }
    qsort(ratios, nratio, sizeof(double), compare);
    printf("LOCKSTEP step_us=%g steps=%ld block=%ld one=%.4g s many=%.4g s speedup=%.4f "
           "pairs=%zu pair_median=%.4f pair_range=%.3f-%.3f (sink %g)\n",
           step_us, done[0] + done[1], block, side[0], side[1], side[0] / side[1], nratio,
           nratio % 2 ? ratios[nratio / 2] : 0.5 * (ratios[nratio / 2 - 1] + ratios[nratio / 2]),
           ratios[0], ratios[nratio - 1], sink > 0.0 ? 1.0 : 0.0);
    free(ratios);
    return 0;
}
