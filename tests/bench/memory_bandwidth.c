/*
 * memory_bandwidth: the main-memory bandwidth one and two cores get, as the STREAM "triad"
 * a[i] = b[i] + s c[i] counts it (24 bytes per i: two reads and one write; the write's line
 * is read first, as an ordinary store does, and that read is not counted, as in STREAM).
 *
 * The integrator's passes of a large set stream their arrays through memory (the first half
 * kick and drift reads 8 arrays of the particles and writes 6, RESULTS.md "Performance
 * (issue 9), session 11"): on two threads they cannot run faster than this program's
 * two-core figure allows, whatever the code. RESULTS.md quotes both figures with the 2-thread
 * speed-ups of the packed beds.
 *
 *   memory_bandwidth [megabytes per array (default 256)] [repetitions (default 5)]
 *
 * Threads are pinned to cores 0 and 1 (the project's VMs have two); each thread runs the
 * triad on its own half (or all, alone) of the arrays, first touched by the thread that uses
 * them. Prints the best of the repetitions, in GB/s (1e9 bytes).
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef struct part {
    int core;
    double *a, *b, *c;
    size_t lo, hi;
    pthread_barrier_t *start;
} part;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void pin(int core)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(core, &set);
    (void)pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

static void *fill(void *arg)
{
    part *p = arg;
    pin(p->core);
    for (size_t i = p->lo; i < p->hi; ++i) {
        p->a[i] = 0.0;
        p->b[i] = 1.0;
        p->c[i] = 2.0;
    }
    return NULL;
}

static void *triad(void *arg)
{
    part *p = arg;
    pin(p->core);
    pthread_barrier_wait(p->start);
    double *restrict a = p->a;
    const double *restrict b = p->b, *restrict c = p->c;
    for (size_t i = p->lo; i < p->hi; ++i)
        a[i] = b[i] + 3.0 * c[i];
    return NULL;
}

/* Seconds for one triad over n values on `threads` threads (1 or 2). */
static double run(int threads, double *a, double *b, double *c, size_t n, void *(*fn)(void *))
{
    pthread_t id[2];
    part parts[2];
    pthread_barrier_t start;
    pthread_barrier_init(&start, NULL, (unsigned)threads + 1);
    for (int t = 0; t < threads; ++t) {
        parts[t] = (part){t, a, b, c, n * (size_t)t / (size_t)threads,
                          n * (size_t)(t + 1) / (size_t)threads, &start};
        pthread_create(&id[t], NULL, fn, &parts[t]);
    }
    if (fn == fill) {
        for (int t = 0; t < threads; ++t)
            pthread_join(id[t], NULL);
        pthread_barrier_destroy(&start);
        return 0.0;
    }
    pthread_barrier_wait(&start);
    const double t0 = now();
    for (int t = 0; t < threads; ++t)
        pthread_join(id[t], NULL);
    const double seconds = now() - t0;
    pthread_barrier_destroy(&start);
    return seconds;
}

int main(int argc, char **argv)
{
    const long mb = argc > 1 ? atol(argv[1]) : 256;
    const int reps = argc > 2 ? atoi(argv[2]) : 5;
    if (mb < 1 || reps < 1) {
        fprintf(stderr, "usage: memory_bandwidth [megabytes per array] [repetitions]\n");
        return 2;
    }
    const size_t n = (size_t)mb * 1000000 / sizeof(double);
    double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)),
           *c = malloc(n * sizeof(double));
    if (a == NULL || b == NULL || c == NULL) {
        fprintf(stderr, "memory_bandwidth: cannot allocate 3 x %ld MB\n", mb);
        return 1;
    }
    (void)run(2, a, b, c, n, fill); /* pages first touched by the cores that use them */
    double best[3] = {0.0, 0.0, 0.0};
    for (int r = 0; r < reps; ++r)
        for (int threads = 1; threads <= 2; ++threads) {
            const double gbs = 24.0 * (double)n / run(threads, a, b, c, n, triad) / 1e9;
            best[threads] = gbs > best[threads] ? gbs : best[threads];
        }
    printf("memory_bandwidth triad, 3 arrays of %ld MB, best of %d: 1 core %.1f GB/s, "
           "2 cores %.1f GB/s (x%.2f)\n",
           mb, reps, best[1], best[2], best[2] / best[1]);
    free(a);
    free(b);
    free(c);
    return 0;
}
