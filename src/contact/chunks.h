/*
 * A fixed partition of a particle-particle contact list, so that threads add contact forces
 * (or heat) straight into the particles' sums without a race and with results that do not
 * depend on the number of threads (issue 9). sinter_contacts_find_pp makes it (c->chunks).
 *
 * The particles are split into S index ranges holding about equal work (contacts, candidate
 * pairs and particles, weighted by their cost: contacts.c, work_below), and the contacts into
 * the S runs of contacts whose smaller particle index lies in each range: in the neighbour
 * build's pair order that index (the particle whose scan found the pair) ascends, whatever the
 * pair's orientation by persistent id. A contact of range s whose two particles both lie in
 * particle range s is interior: only range s touches those particles, so a thread per range
 * adds it directly. Every other contact is a boundary contact: its value is kept (in a scratch
 * array at the range's own contact offset, so no count is needed beforehand) and added after
 * all ranges, in list order, by the range of each of its particles. The search, the
 * integrator and the explicit temperature update run on the same ranges and threads
 * (sinter_chunks_particle_ranges), so a particle's lines stay on one core all step.
 *
 * The particle ranges are made by the first search over a pair list and kept by the later
 * searches over it (which find the runs of contacts again): the partition does not depend on
 * how the list came to hold its contacts, so a force law that drops ended contacts itself
 * sums in the order a search would give (sinter_contacts_confirm). A neighbour rebuild (every
 * few tens of steps where particles move) balances the ranges again.
 *
 * S depends on the number of candidate pairs only, never on the number of threads, so each
 * particle receives the same additions in the same order (its interior contacts in list
 * order, then its boundary contacts in list order) whatever the thread count: the same bits.
 * With the particles in a spatial order (cell order, as the benchmark lattices and the
 * packings are) the index ranges are slabs, and the boundary contacts are the few that cross
 * between two. A list of fewer than 2048 pairs, or one whose smaller indices do not ascend
 * (not made by the neighbour build), is not partitioned (c->chunks.count 0): its sums run in
 * list order on one thread.
 */
#ifndef SINTER_CHUNKS_H
#define SINTER_CHUNKS_H

#include "contact/contacts.h"
#include "core/range_flags.h"

/* the loops over a partition's ranges wait for them with these flags (the force law's and
 * the conduction's pp_chunked) */
_Static_assert((int)SINTER_CHUNKS_MAX <= (int)SINTER_RANGE_FLAGS_MAX, "a flag per partition range");

/* 1 if contact (i, j) of range s is interior. */
static inline int sinter_chunks_interior(const sinter_chunks *k, int s, uint32_t i, uint32_t j)
{
    const size_t lo = k->plo[s], hi = k->plo[s + 1];
    return i >= lo && i < hi && j >= lo && j < hi;
}

/* The reach of a range's boundary contacts, 1 + the largest particle index among them (0 for
 * none), grown by contact (i, j): a later range's boundary pass reads the lists whose reach
 * exceeds its first particle only (the others add nothing to its particles). */
static inline uint32_t sinter_chunks_reach(uint32_t reach, uint32_t i, uint32_t j)
{
    reach = i >= reach ? i + 1 : reach;
    return j >= reach ? j + 1 : reach;
}

/* The first k in [0, n) with a[k] >= value, a ascending (n when there is none; any index in
 * [0, n] when a does not ascend). */
static inline size_t sinter_lower_bound_u32(const uint32_t *a, size_t n, size_t value)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < value)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/*
 * Ranges of particles for a loop over the particles on threads (the integrator, the explicit
 * temperature update): the pair partition's particle ranges when it has one for n particles,
 * looped over as its law loops over them (`omp for schedule(static)` over `count` ranges on
 * `team` threads), so that each thread updates the particles whose contact forces it summed
 * and whose positions its next search and law read (issue 9: on a falling pile, whose
 * contacts crowd at the bottom, equal ranges of particles left a third of them on the other
 * core); else `threads` equal ranges. Any split gives the same bits (particle by particle).
 */
typedef struct sinter_particle_ranges {
    int count;         /* ranges */
    int team;          /* threads of the loop over them */
    size_t n;          /* particles */
    const size_t *plo; /* the partition's bounds (count + 1), or NULL: equal ranges */
} sinter_particle_ranges;

static inline sinter_particle_ranges sinter_chunks_particle_ranges(const sinter_chunks *pp,
                                                                   size_t n, int threads)
{
    sinter_particle_ranges r = {threads, threads, n, NULL};
    if (threads > 1 && pp != NULL && pp->count > 0 && pp->plo[pp->count] == n) {
        r.count = pp->count;
        r.team = threads < pp->count ? threads : pp->count;
        r.plo = pp->plo;
    }
    return r;
}

/* First particle of range s (s = count: n). */
static inline size_t sinter_particle_range_lo(const sinter_particle_ranges *r, int s)
{
    return r->plo != NULL ? r->plo[s] : r->n * (size_t)s / (size_t)r->count;
}

/*
 * The runs of wall list pw that hold the wall contacts of the particle ranges of the
 * particle-particle partition pp: qlo[s] .. qlo[s + 1] for s < S. Returns S, or 0 when pp
 * has no partition or pw's particle indices do not ascend (then pw's own runs serve).
 *
 * A loop over these runs with the same thread count and schedule as the pp ranges' loop
 * (`omp for schedule(static)` over S on min(threads, S) threads) gives each thread the
 * particles it already added the pair forces into: their cache lines stay on its core
 * (issue 9: on a two-core machine a line fetched from the other core costs 60-350 ns). The
 * runs, like the partition, depend on the lists only: the same bits on any thread count.
 */
static inline int sinter_chunks_wall_runs(const sinter_chunks *pp, const sinter_contact_list *pw,
                                          size_t qlo[SINTER_CHUNKS_MAX + 1])
{
    if (pp->count == 0 || !pw->ascending || pw->count == 0)
        return 0;
    qlo[0] = 0;
    for (int s = 1; s < pp->count; ++s)
        qlo[s] = sinter_lower_bound_u32(pw->i, pw->count, pp->plo[s]);
    qlo[pp->count] = pw->count;
    return pp->count;
}

/* The runs a loop over wall list pw takes: the pair partition's (sinter_chunks_wall_runs,
 * *aligned 1), else pw's own (contacts.c, wall_ranges, from 1024 contacts; *aligned 0);
 * aligned may be NULL. Returns their number; 0: one pass over the list on one thread. */
static inline int sinter_chunks_wall_plan(const sinter_chunks *pp, const sinter_contact_list *pw,
                                          size_t qlo[SINTER_CHUNKS_MAX + 1], int *aligned)
{
    int runs = sinter_chunks_wall_runs(pp, pw, qlo);
    if (aligned != NULL)
        *aligned = runs > 0;
    if (runs == 0 && pw->chunks.count > 0) {
        runs = pw->chunks.count;
        for (int s = 0; s <= runs; ++s)
            qlo[s] = pw->chunks.qlo[s];
    }
    return runs;
}

#endif
