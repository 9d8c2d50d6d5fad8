/*
 * core_latency: the round trip of one cache line between two cores, in nanoseconds.
 *
 * Two threads, pinned to the cores given (default 0 and 1), pass a counter back and forth
 * through one atomic word. On this project's 2-core VMs the round trip is 60-80 ns when the
 * host runs both virtual cores on one die and about 340-360 ns when it puts them on two; the
 * host moves them within seconds, and every 2-thread time follows (a 1k packed bed on 2
 * threads: 1.5 s or 2.9 s; RESULTS.md, "Performance (issue 9), session 8"). peer_table.sh
 * prints it before and after each cell's runs, so that a 2-thread figure can be read with
 * the machine's state it was taken in.
 *
 *   core_latency [core_a core_b [rounds]]
 */
#define _GNU_SOURCE
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static _Alignas(64) atomic_long turn;

typedef struct peer {
    int core;
    long rounds;
} peer;

static int pin(int core)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(core, &set);
    return pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

/* The second core: answers each odd count with the next even one. */
static void *answer(void *arg)
{
    const peer *p = arg;
    (void)pin(p->core); /* unpinned if it cannot be: still answers */
    for (long i = 0; i < p->rounds; ++i) {
        while (atomic_load_explicit(&turn, memory_order_acquire) != 2 * i + 1)
            ;
        atomic_store_explicit(&turn, 2 * i + 2, memory_order_release);
    }
    return NULL;
}

int main(int argc, char **argv)
{
    const int a = argc > 2 ? atoi(argv[1]) : 0, b = argc > 2 ? atoi(argv[2]) : 1;
    const long rounds = argc > 3 ? atol(argv[3]) : 200000;
    if (rounds <= 0 || pin(a) != 0) {
        fprintf(stderr, "core_latency: cannot pin to core %d (or no rounds)\n", a);
        return 1;
    }
    peer other = {b, rounds};
    atomic_store(&turn, 0);
    pthread_t thread;
    if (pthread_create(&thread, NULL, answer, &other) != 0) {
        fprintf(stderr, "core_latency: no second thread\n");
        return 1;
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (long i = 0; i < rounds; ++i) {
        atomic_store_explicit(&turn, 2 * i + 1, memory_order_release);
        while (atomic_load_explicit(&turn, memory_order_acquire) != 2 * i + 2)
            ;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    pthread_join(thread, NULL);
    const double ns = ((double)(t1.tv_sec - t0.tv_sec) * 1e9 + (double)(t1.tv_nsec - t0.tv_nsec));
    printf("core_latency cores %d-%d round trip %.0f ns\n", a, b, ns / (double)rounds);
    return 0;
}
