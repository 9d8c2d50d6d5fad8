/*
 * Two parts of one piece of work (the bonded solve's two domains, bonded/domain_order.h) side
 * by side on two threads, or one after the other on one. The calling thread takes part 0, so a
 * part's data stays in the same core's cache from one call to the next.
 */
#ifndef SINTER_CORE_TWO_PARTS_H
#define SINTER_CORE_TWO_PARTS_H

/* part(data, 0) and part(data, 1): at once when threads is 2 (and OpenMP is there), else in
 * that order. */
void sinter_two_parts(int threads, void (*part)(void *data, int which), void *data);

#endif
