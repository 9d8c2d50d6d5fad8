/*
 * The explicit stepper's thread count, chosen by timing (issue 9).
 *
 * On the project's 2-core VMs the host moves the two virtual cores between one die (a cache
 * line's round trip 60-80 ns) and two (320-360 ns) within seconds, and on two dies a step on
 * two threads can take longer than on one (a 1k falling pile 2.3 times as long, a 64k one
 * 1.16 times; RESULTS.md, "Performance (issue 9), session 8"). A machine with two sockets
 * behaves alike. So when the context allows T > 1 threads, the stepper times a few steps on
 * T threads and on one, takes the faster, and measures again after a while. The results do
 * not depend on the number of threads (every threaded sum has a fixed order), so the choice
 * changes the time of a step only, never its bits.
 */
#ifndef SINTER_THREAD_CHOICE_H
#define SINTER_THREAD_CHOICE_H

#include <stdint.h>

typedef struct sinter_thread_choice {
    int option;      /* option "thread_choice": -1 measure (the default), 0 never */
    int requested;   /* the context's thread count T the choice was made for (0: none) */
    int decided;     /* T or 1, or 0 while measuring */
    int trial;       /* steps of the measurement so far */
    uint64_t layout; /* the particles' layout_generation */
    double best[2];  /* the shortest timed step on T threads [0] and on one [1] [s] */
    double started;  /* clock at the measurement's first step [s] */
    double next;     /* clock after which to measure again [s] */
} sinter_thread_choice;

/* The explicit step's per-particle passes (the integrator's kicks, the forward Euler update of
 * the temperatures) run on the step's threads from this many particles, on the pair
 * partition's particle ranges (contact/chunks.h, sinter_chunks_particle_ranges), so each
 * thread updates the particles whose forces and heat it summed; on one thread instead, half of
 * those lines would cross to the other core and back every step (1k packed bed, 2 threads,
 * cores on one die: 1.55-1.59 s -> 1.26-1.55 s; RESULTS.md, sessions 9 and 10). */
enum { SINTER_THREADED_PARTICLES = 512 };

struct sinter_stepper;

/* The option's default (measure) and nothing measured. */
void sinter_thread_choice_init(sinter_thread_choice *c);

/* Before an explicit step: the threads it takes, set on the stepper's context for the step
 * (sinter_threads), measuring when due. */
void sinter_thread_choice_begin(struct sinter_stepper *st);

/* After it: the context's own count back; an accepted step of `seconds` is timed when
 * measuring (a rejected one restarts the measurement). */
void sinter_thread_choice_end(struct sinter_stepper *st, double seconds, int accepted);

#endif
