/*
 * A fixed partition of a particle-particle contact list, so that threads add contact forces
 * (or heat) straight into the particles' sums without a race and with results that do not
 * depend on the number of threads (issue 9). sinter_contacts_find_pp makes it (c->chunks).
 *
 * The particles are split into S index ranges, and the contacts, whose first particles
 * ascend (the pair order of the neighbour build), into the S runs of contacts whose first
 * particle lies in each range. A contact of range s whose second particle lies in particle
 * range s too is interior: only range s touches those particles, so a thread per range adds
 * it directly. Every other contact is a boundary contact: its value is kept (in a scratch
 * array at the range's own contact offset, so no count is needed beforehand) and added after
 * all ranges, in list order, by one thread.
 *
 * S depends on the number of candidate pairs only, never on the number of threads, so each
 * particle receives the same additions in the same order (its interior contacts in list
 * order, then its boundary contacts in list order) whatever the thread count: the same bits.
 * With the particles in a spatial order (cell order, as the benchmark lattices and the
 * packings are) the index ranges are slabs, and the boundary contacts are the few that cross
 * between two. A list whose first particles do not ascend (a set reordered so that pairs,
 * oriented by persistent id, start from the larger index) and a list of fewer than 2048
 * pairs are not partitioned (c->chunks.count 0): their sums run in list order on one thread.
 */
#ifndef SINTER_CHUNKS_H
#define SINTER_CHUNKS_H

#include "contact/contacts.h"

/* 1 if contact (i, j) of range s is interior. */
static inline int sinter_chunks_interior(const sinter_chunks *k, int s, uint32_t i, uint32_t j)
{
    const size_t lo = k->plo[s], hi = k->plo[s + 1];
    return i >= lo && i < hi && j >= lo && j < hi;
}

#endif
