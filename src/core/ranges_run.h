/*
 * A loop over work ranges on a team of threads that costs nothing on one thread: libgomp
 * allocates a team at every parallel region of one thread and frees it at its end (a team of
 * two or more is kept for the next region), 1 000-1 500 instructions a region; a step of a
 * small scene opens five (issue 9: a fifth of a one-particle scene's instructions). And it
 * ends every region, of one thread too, with a futex wake: a system call, 1-2 us on a VM (issue
 * 41: 0.27 of the vibrated bed's CPU on one thread). With a team of one the ranges run on the
 * calling thread without entering OpenMP; every threaded loop that a run on one thread reaches
 * does the same (`if (threads > 1) { parallel loop } else { loop }`).
 */
#ifndef SINTER_CORE_RANGES_RUN_H
#define SINTER_CORE_RANGES_RUN_H

/* range(data, t) for t = 0 .. count - 1: on `team` threads, schedule(static), when team > 1
 * (and OpenMP is there), else in that order on the calling thread. */
void sinter_ranges_run(int team, int count, void (*range)(void *data, int t), void *data);

/* Two passes over `count` ranges whose second waits inside (range_flags.h) for the first
 * pass's ranges 0 .. t: interior(data, t) for every t, then rest(data, t) for every t, on
 * min(threads, count) threads. A thread takes interior passes before rests (nowait loops), so
 * no wait can hang: by a static schedule when the team has as many threads as ranges, else
 * each range to the next free thread (dynamic); on the calling thread, in that order, for a
 * team of one. Which thread runs a range must not change its sums. */
void sinter_ranges_run_two_passes(int threads, int count, void (*interior)(void *data, int t),
                                  void (*rest)(void *data, int t), void *data);

#endif
