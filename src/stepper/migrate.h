/*
 * Migration of particles between steppers (issue 43): the record stream of
 * sinter_stepper_export / sinter_stepper_import (migrate.c), the pair histories that imported
 * records bring, staged by key until the next neighbour build (migrate_stage.c), and the
 * quasi-static links that travel with their smaller-id particle (qs_migrate.c).
 *
 * A contact history entry is keyed by the ids of its two particles, oriented as the pair list
 * orients them (particle-particle), or by the particle's id and the wall's index
 * (particle-wall), so that it names the same contact in any stepper that holds both ends.
 */
#ifndef SINTER_STEPPER_MIGRATE_H
#define SINTER_STEPPER_MIGRATE_H

#include "stepper/quasistatic.h"

struct sinter_stepper;

/* Entries of one force slot's history of one kind (pp or pw), waiting for their pair. */
typedef struct sinter_migrate_entries {
    size_t count, capacity;
    uint64_t *key; /* 2 per entry: key_i, key_j (pw: particle id, wall index) */
    double *value; /* width per entry */
} sinter_migrate_entries;

/* What imported records brought for the stepper's force slots: 2 lists per slot (pp, pw). */
typedef struct sinter_migrate_stage {
    size_t slots;
    size_t *width; /* 2 per slot: the pp and pw history widths the entries were made for */
    sinter_migrate_entries *list; /* 2 per slot */
} sinter_migrate_stage;

/* The stage of st made for its force slots (created empty on first use). NULL: out of memory. */
sinter_migrate_stage *sinter_migrate_stage_get(struct sinter_stepper *st);

/* Room for `more` entries in list l of width w (nothing else changes). */
sinter_status sinter_migrate_reserve(sinter_ctx *ctx, sinter_migrate_entries *l, size_t w,
                                     size_t more);

/* Drop entries for which drop(key, user) is 1. */
void sinter_migrate_drop(sinter_migrate_entries *l, size_t w,
                         int (*drop)(const uint64_t key[2], void *user), void *user);

/* Keep one entry per key in l (the first; the order of the kept ones unchanged): a contact
 * between two particles of one stream arrives in both records. table: `cap` slots of scratch,
 * cap = sinter_migrate_dedupe_slots(l->count) or more (a power of 2). */
size_t sinter_migrate_dedupe_slots(size_t count);
void sinter_migrate_dedupe(sinter_migrate_entries *l, size_t w, uint32_t *table, size_t cap);

/* After a neighbour build and the history remap: each new pair that holds no history yet and
 * whose key is staged takes the staged values (committed, active); every staged entry is then
 * dropped (a pair that is not a candidate any more is not in contact). No-op without a stage. */
sinter_status sinter_migrate_match(struct sinter_stepper *st);

void sinter_migrate_stage_free(sinter_ctx *ctx, sinter_migrate_stage *stage);

/* ---- quasi-static links (qs_migrate.c) ---- */

/* Drop the links flagged in drop[k] (1: drop), keeping the order of the others. */
void sinter_qs_links_drop(sinter_qs *qs, const unsigned char *drop);

/* Add m links (copied, no two with one key) whose key qs does not hold yet; *added of them. When
 * the links held are in the order in which a run makes them (time made, then ids), the whole list
 * is put back in that order, so that a link leaving and coming back takes its old place (the loads
 * are summed in link order). Errors: SINTER_ERR_NOMEM (then nothing changed). */
sinter_status sinter_qs_links_insert(sinter_qs *qs, const sinter_qs_link *links, size_t m,
                                     size_t *added);

/* After an import: when the n ids of the set are those of qs's last step (every particle that
 * left came back), the set counts for qs as the same particles reordered (population: the set's
 * population_generation), so that the principal-plane conditions, the last displacements and
 * the kept pairs stay (they are per id); any other set has them detected again at the next
 * step, as for particles added or removed. */
void sinter_qs_particles_back(sinter_qs *qs, size_t n, const uint64_t *ids, uint64_t population);

/* ---- the quasi-static stepper's portable state (qs_portable.c, issue 43) ---- */

/* What a particle's record carries of the quasi-static stepper (stream format 4): bits (1: the
 * plane conditions, 2: the last displacements, 4: the initial position), the six conditions
 * (0/1, two bytes of padding), the six displacements [m, rad] and the initial position [m]. */
typedef struct sinter_qs_carried {
    uint64_t bits;
    unsigned char fixed[8];
    double u[6];
    double origin[3];
} sinter_qs_carried;
#define SINTER_QS_CARRIED_BYTES (8 + 8 + 8 * 6 + 8 * 3)

/* The carried states an import left pending until the next remap, indexed for
 * sinter_qs_carried_of: (id, entry) pairs in ascending order, 2 * *count values (NULL with
 * *count 0 when none; NULL with *s SINTER_ERR_NOMEM without memory). */
uint64_t *sinter_qs_carried_index(const sinter_qs *qs, sinter_ctx *ctx, size_t *count,
                                  sinter_status *s);

/* The state qs (may be NULL) keeps for the particle of index i of a set of n with id `id`:
 * its slot's, or for a particle imported and not yet remapped the last state its record
 * brought (index: sinter_qs_carried_index's, may be NULL). */
void sinter_qs_carried_of(const sinter_qs *qs, const uint64_t *index, size_t count, size_t n,
                          size_t i, uint64_t id, sinter_qs_carried *out);

/* Keep m carried states of particles of ids id[] until the next remap (which gives them their
 * slots when they cover every particle) and merge their initial positions. Errors:
 * SINTER_ERR_NOMEM (then nothing changed). */
sinter_status sinter_qs_carried_add(sinter_qs *qs, const uint64_t *id, const sinter_qs_carried *c,
                                    size_t m);

/* Why a carried state is unusable, or NULL. */
const char *sinter_qs_carried_wrong(const sinter_qs_carried *c);

/* The stepper-wide state in the global part: SINTER_QS_GLOBAL_F64 doubles, SINTER_QS_GLOBAL_U64
 * integers (zeros for qs NULL). sinter_qs_global_load: why the values are unusable (nothing
 * changed) or NULL (loaded). */
enum { SINTER_QS_GLOBAL_F64 = 15, SINTER_QS_GLOBAL_U64 = 9 };
void sinter_qs_global_values(const sinter_qs *qs, double f[SINTER_QS_GLOBAL_F64],
                             uint64_t u[SINTER_QS_GLOBAL_U64]);
const char *sinter_qs_global_wrong(const double f[SINTER_QS_GLOBAL_F64],
                                   const uint64_t u[SINTER_QS_GLOBAL_U64]);
/* domain_on: loaded under domain operations (a decomposed run's restart, issue 44). */
void sinter_qs_global_load(sinter_qs *qs, const double f[SINTER_QS_GLOBAL_F64],
                           const uint64_t u[SINTER_QS_GLOBAL_U64], int domain_on);

#endif
