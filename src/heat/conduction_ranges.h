/*
 * Explicit conduction by the ranges of the pair partition (contact/chunks.h), one range at a
 * time, for a caller that runs the ranges on its own threads: conduction.c's own parallel
 * region, or the contact law's (stepper/thermal.c, issue 9: the step's conduction in the
 * law's region, one fork and join fewer, and a thread that waits there for another range's
 * law has its conduction to do first).
 *
 * sinter_conduction_ranges_begin prepares an evaluation; then, for every range s,
 * sinter_conduction_range_interior(s) adds the contacts with both particles in range s and
 * keeps the others (it waits for nothing; on a list the law is to confirm, it runs after the
 * law's pass over range s, whose marks of ended contacts it reads: contact/contacts.h); and
 * for every range r, on any thread, sinter_conduction_range_rest(r) waits for the interior
 * passes of ranges 0 .. r and adds the kept contacts that reach r's particles, in list order,
 * then r's wall contacts. Each particle receives its powers in the order of one pass over the
 * list whatever the thread that runs a range: the same bits on any number of threads.
 */
#ifndef SINTER_CONDUCTION_RANGES_H
#define SINTER_CONDUCTION_RANGES_H

#include "contact/chunks.h"
#include "core/range_flags.h"
#include "heat_model.h"
#include "particles/particles.h"

typedef struct sinter_conduction_ranges {
    sinter_heat_eval e;
    double kmat[SINTER_MAX_MATERIALS]; /* conductivity of each material [W/(m K)] */
    int law;                           /* which conductance (conduction.c, enum law) */
    int reading;                       /* the wall reading ("wall_reading") */
    double factor;                     /* the projection's factor with one material */
    sinter_chunks ch;
    int skip_ended;                    /* an unconfirmed list: leave out c->ended's contacts */
    uint32_t *bq;                      /* kept (boundary) contacts, at each range's offset */
    double *bpower;                    /* their powers [W] */
    int walls;                         /* 1: wq holds the wall runs of the ranges */
    int walls_left;                    /* 1: the model conducts to walls whose runs do not
                                        * align with the ranges: the caller's to add */
    size_t wq[SINTER_CHUNKS_MAX + 1];
    size_t boundary[SINTER_CHUNKS_MAX];
    uint32_t reach[SINTER_CHUNKS_MAX];
    sinter_range_flags interior_done;
} sinter_conduction_ranges;

/* Bytes of scratch an evaluation of a list of `contacts` contacts needs. */
static inline size_t sinter_conduction_ranges_scratch(size_t contacts)
{
    return contacts * (sizeof(double) + sizeof(uint32_t)) + 1;
}

/*
 * Prepares *j for one explicit evaluation of conduction model hm (e: heat into e->heat, no
 * g_pp) by ranges, with `scratch` (sinter_conduction_ranges_scratch bytes, double-aligned).
 * Returns 1 if it can run so: hm is the built-in conduction with valid parameters, e->pp is
 * partitioned and carries the geometry the law reads (a lean list does not); else 0 and the
 * model is to be evaluated as usual. Its wall contacts are added by the ranges' rest when
 * their runs align with the ranges (j->walls), else left to the caller (j->walls_left).
 */
int sinter_conduction_ranges_begin(const sinter_heat_model *hm, const sinter_heat_eval *e,
                                   void *scratch, sinter_conduction_ranges *j);

void sinter_conduction_range_interior(sinter_conduction_ranges *j, int s);
void sinter_conduction_range_rest(sinter_conduction_ranges *j, int r);

#endif
