/*
 * Active contacts (overlap > 0) and their geometry: seed 000 eq. 7-12,
 * identical to seed 003 eq. 33-34.
 */
#ifndef SINTER_CONTACTS_H
#define SINTER_CONTACTS_H

#include <math.h>

#include "contact/neighbors.h"
#include "contact/wall_skip.h"

/* A fixed partition of a particle-particle list for thread-count independent sums
 * (contact/chunks.h), made by sinter_contacts_find_pp. A particle-wall list made by
 * sinter_contacts_find_pw uses qlo only: runs of contacts that never split a particle's
 * contacts (the list is in particle order), so threads add into distinct particles; where
 * the pair list is partitioned, the wall law and conduction take the runs of its particle
 * ranges instead (sinter_chunks_wall_runs), so that each thread works on its own particles. */
enum { SINTER_CHUNKS_MAX = 8 };
typedef struct sinter_chunks {
    int count;                         /* S; 0 when the list is not partitioned */
    size_t plo[SINTER_CHUNKS_MAX + 1]; /* particle ranges [plo[s], plo[s+1]) */
    size_t qlo[SINTER_CHUNKS_MAX + 1]; /* contact ranges [qlo[s], qlo[s+1]) */
    /* build_id of the pair list plo was made over (0: none); later searches over the same
     * pairs keep plo (contact/chunks.h) */
    uint64_t source;
} sinter_chunks;

typedef struct sinter_contact_list {
    size_t count;
    size_t capacity;
    size_t pair_count; /* candidate pairs the contacts were found among */
    uint32_t *i;       /* particle */
    uint32_t *j;       /* particle or wall */
    uint32_t *pair;    /* index of the candidate pair (history slot) */
    double *n;         /* unit normal from i towards j, 3 per contact */
    double *delta;     /* overlap [m] */
    double *dist;      /* centre distance or centre-plane distance [m] */
    double *area;      /* pi a^2 [m^2] */
    double *branch;    /* L_i: distance from the centre of i to the contact plane [m] */
    /* 1 when n, delta, dist, area and branch hold this list's geometry; 0 for a list made by
     * sinter_contacts_find_pp_lean until sinter_contacts_geometry fills them */
    int geometry;
    /* the contact of each candidate pair, or SINTER_NO_PAIR; particle-particle lists found
     * with their geometry also borrow the pairs' per-particle adjacency from the pair list
     * (NULL otherwise) */
    uint32_t *pair_to_contact;
    size_t pair_to_contact_capacity;
    const uint32_t *adj_start;
    const uint32_t *adj_pair;
    size_t particle_count;
    sinter_chunks chunks; /* the partition (see sinter_chunks) */
    /* a particle-wall list: 1 when its particle indices ascend (sinter_contacts_find_pw),
     * so that it splits at any particle index (sinter_chunks_wall_runs) */
    int ascending;
    /* with chunks: room for 3 doubles and one index per contact, for one consumer at a time
     * (kept across evaluations, so no allocation per step) */
    void *chunk_scratch;
    size_t chunk_scratch_capacity;
    uint8_t *touch; /* threaded search: 1 per candidate pair in contact (the counting pass) */
    size_t touch_capacity;
    /* particle-wall lists: per candidate pair of the pair list build hint_source
     * (hint_count pairs) the mesh triangle its last search ended on (sinter_wall_contact_
     * hinted: a start that changes no bit), carried over a rebuild by the pairs' `from` */
    uint32_t *hint, *hint_spare;
    size_t hint_capacity, hint_spare_capacity, hint_count;
    /* and 4 doubles per pair: the certificate of its last search (sinter_wall_contact_
     * certified: where the hint's triangle is still the closest), carried with the hint */
    double *cert, *cert_spare;
    size_t cert_capacity, cert_spare_capacity;
    uint64_t hint_source;
    uint32_t *fill_scratch; /* threaded search of a lean list: i, j, pair per candidate pair */
    size_t fill_scratch_capacity;
    /* identity of the membership (count, i, j, pair, pair_to_contact): a new sinter_unique_id
     * whenever a search changes it, kept when a search finds the same contacts again, so that
     * history commits can tell what changed (contact/history.c); 0 before the first search */
    uint64_t revision;
    /* the last two changes of membership, newest first: the revision changed from, and the
     * first candidate pair and the first contact index from which the lists may differ (0, 0
     * after a search that did not compare) */
    struct sinter_list_change {
        uint64_t from;
        size_t pair, contact;
    } change[2];
    /* build_id of the pair list the last lean search ran over (0 after any other search): a
     * lean search over the same pairs first checks the contacts against the list it holds
     * and writes only from the first pair whose verdict changed. A wall list: the pair list
     * of its last search (sinter_contacts_find_pw, which compares in the same way) */
    uint64_t lean_source;
    /* 1 after sinter_contacts_find_pp_deferred left the contacts it holds unchecked, until
     * sinter_contacts_confirm; defer_wait and defer_skip space out the deferred searches
     * after one that found new contacts */
    int unconfirmed;
    uint32_t defer_wait, defer_skip;
    /* an unconfirmed list: the law sets 1 for each contact it skipped (0 otherwise, and
     * everywhere outside a deferred evaluation) */
    uint8_t *ended;
    size_t ended_capacity;
    /* the candidate pairs not in contact, when they are few, for membership gap_revision
     * (0: none kept): what a deferred search tests */
    uint32_t *gaps;
    size_t gap_count, gap_capacity;
    uint64_t gap_revision;
    /* set by the stepper before each search (NULL: none, the default): the committed history
     * of a force model that holds pairs, held_stride doubles per candidate pair; a pair whose
     * first value is non-zero is a contact at any distance (delta < 0, area 0: a bond in
     * tension, force/power_law.c), so that the commit keeps its history */
    const double *held;
    size_t held_stride;
} sinter_contact_list;

void sinter_contact_list_free(sinter_ctx *ctx, sinter_contact_list *c);

/* Where list c may differ from its own earlier membership of revision r: from candidate pair
 * *pair and contact index *contact on (SIZE_MAX for both when r is c's revision; 0 for both
 * when r is 0 or older than c's last two changes). */
static inline void sinter_contacts_changed_since(const sinter_contact_list *c, uint64_t r,
                                                 size_t *pair, size_t *contact)
{
    if (r != 0 && r == c->revision) {
        *pair = *contact = SIZE_MAX;
        return;
    }
    size_t p = SIZE_MAX, m = SIZE_MAX;
    for (int k = 0; k < 2 && r != 0; ++k) {
        p = c->change[k].pair < p ? c->change[k].pair : p;
        m = c->change[k].contact < m ? c->change[k].contact : m;
        if (c->change[k].from == r) {
            *pair = p;
            *contact = m;
            return;
        }
    }
    *pair = *contact = 0;
}

/* Record a change of c's membership from pair and contact index on: a new revision. */
static inline void sinter_contacts_changed(sinter_contact_list *c, size_t pair, size_t contact)
{
    c->change[1] = c->change[0];
    c->change[0].from = c->revision;
    c->change[0].pair = pair;
    c->change[0].contact = contact;
    c->revision = sinter_unique_id();
}

/* Contact radii a = sqrt(A / pi) [m] into a[count] (host batches report them). */
void sinter_contact_radii(const sinter_contact_list *c, double *a);

/* Particle-particle contacts among the candidate pairs, with their geometry and the pairs'
 * per-particle adjacency (made for the pairs if they lack it: sinter_pairs_adjacency). */
sinter_status sinter_contacts_find_pp(sinter_ctx *ctx, sinter_contact_list *c,
                                      sinter_pair_list *pairs, const sinter_particles *ps);

/* The same list without its geometry (c->geometry 0): i, j, pair, pair_to_contact and the
 * partition only, for a stepper whose submodels form the geometry themselves from the
 * centres (issue 9: the 8 doubles per contact are neither written nor read back). */
sinter_status sinter_contacts_find_pp_lean(sinter_ctx *ctx, sinter_contact_list *c,
                                           const sinter_pair_list *pairs,
                                           const sinter_particles *ps);

/*
 * A lean search that leaves its contacts to the force law to confirm (issue 9: a packed bed
 * keeps its contacts, and the law reads both centres of each contact a moment later anyway).
 * Over the pairs of the last lean search, only the pairs the list does not hold are tested;
 * if none has come into contact, *deferred is 1 and the list is kept as it is, unconfirmed
 * (when some have, the pairs from the first of them on are searched afresh and the contacts
 * before kept unconfirmed). The law must skip every contact that no longer touches (the test
 * of the search, d^2 < (r_i + r_j)^2 and d^2 != 0, from the same centres), set c->ended[q] to
 * 1 for each, and give the first one's index to sinter_contacts_confirm before anything else
 * reads the list (sinter_contacts_check if the law did not run; the one reader meanwhile is
 * the conduction in the law's region, which reads a range after the law's pass over it and
 * leaves out the marked contacts: heat/conduction_ranges.h). Otherwise (other pairs, new
 * contacts in the first half of a threaded list) it is sinter_contacts_find_pp_lean and
 * *deferred is 0. The list after sinter_contacts_confirm equals the one
 * sinter_contacts_find_pp_lean makes, partition included (chunks.h).
 */
sinter_status sinter_contacts_find_pp_deferred(sinter_ctx *ctx, sinter_contact_list *c,
                                               const sinter_pair_list *pairs,
                                               const sinter_particles *ps, int *deferred);

/* Drop the contacts of an unconfirmed list that the law marked in c->ended, from contact
 * index `from` on (the first it marked; SIZE_MAX: none), and record the change. `rows` (or
 * NULL): `width` doubles per contact that the law wrote by contact index (trial history not
 * indexed by pair), moved along with the contacts kept. */
void sinter_contacts_confirm(sinter_contact_list *c, size_t from, double *rows, size_t width);

/* Confirm an unconfirmed list by the search's own test of every contact (the law did not
 * run). */
void sinter_contacts_check(sinter_contact_list *c, const sinter_pair_list *pairs,
                           const sinter_particles *ps);

/* Fill n, delta, dist, area and branch of a lean list from the particles' current centres
 * (which must be those it was found at); nothing to do when c->geometry is 1. */
void sinter_contacts_geometry(const sinter_ctx *ctx, sinter_contact_list *c,
                              const sinter_particles *ps);

/* Geometry of a particle pair from the centre difference e = x_j - x_i and the radii (seed
 * 000 eq. 7-12): the one formula of the contact list and of the laws that form it
 * themselves, so that both give the same bits. */
typedef struct sinter_pp_geom {
    double nx, ny, nz; /* unit normal from i towards j */
    double d;          /* centre distance [m] */
    double delta;      /* overlap r_i + r_j - d [m] (eq. 10) */
    double li;         /* L_i (eq. 12) */
} sinter_pp_geom;

static inline sinter_pp_geom sinter_pp_geometry(double ex, double ey, double ez, double ri,
                                                double rj)
{
    sinter_pp_geom g;
    const double d2 = ex * ex + ey * ey + ez * ez;
    const double d = sqrt(d2), inv = 1.0 / d;
    g.nx = ex * inv;
    g.ny = ey * inv;
    g.nz = ez * inv;
    g.d = d;
    g.delta = (ri + rj) - d;
    g.li = 0.5 * (d - (rj * rj - ri * ri) * inv);
    return g;
}

/* Particle-wall contacts among the candidate pairs. owner (may be NULL): the partition of
 * the particle-particle list found this step, whose particle ranges then split the search
 * among the threads (each its own particles; the contacts found are the same). */
sinter_status sinter_contacts_find_pw(sinter_ctx *ctx, sinter_contact_list *c,
                                      const sinter_pair_list *pairs, const sinter_particles *ps,
                                      const sinter_walls *walls, const sinter_chunks *owner);
/* sinter_contacts_find_pw with walls proven out of reach left untested (skip, may be NULL:
 * none; contact/wall_skip.h): the same contacts. */
sinter_status sinter_contacts_find_pw_skip(sinter_ctx *ctx, sinter_contact_list *c,
                                           const sinter_pair_list *pairs,
                                           const sinter_particles *ps, const sinter_walls *walls,
                                           const sinter_chunks *owner, sinter_wall_skip *skip);

#endif
