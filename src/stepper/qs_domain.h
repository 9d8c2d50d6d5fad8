/*
 * The quasi-static stepper on one subdomain of a decomposed body (issue 43, docs/scaleout.md):
 * the collective stages its step calls when domain operations are installed. Each link is
 * owned by the subdomain of its smaller id (the other end may be a ghost); the loads on a
 * ghost end go back to its owner through a reverse halo; the global quantities (extents, green
 * density, the step decision, the statistics) through reductions; K u = f through the split
 * solve (bonded/solve_split.h). Without domain operations none of these is called, but in the
 * reproducible mode (qs_repro.h), whose serial run takes the split solve and the floating
 * components of qs_floating_domain.c on one part (their exchanges then do nothing).
 */
#ifndef SINTER_STEPPER_QS_DOMAIN_H
#define SINTER_STEPPER_QS_DOMAIN_H

#include "stepper/qs_struct.h"

struct sinter_stepper;

/* Bind qs to st's domain operations and particles (qs->dom.on = 0 without). Collective the
 * first time with domain operations (the number of subdomains). */
sinter_status sinter_qs_domain_bind(sinter_qs *qs, struct sinter_stepper *st);

/* The status every subdomain agrees on (s itself without domain operations). */
sinter_status sinter_qs_domain_agree(sinter_qs *qs, sinter_status s);

/* Reduce values in place (nothing without domain operations). */
sinter_status sinter_qs_domain_reduce(sinter_qs *qs, void *values, size_t count, int type, int op);

/* 1 when the particle at index i is a ghost. */
static inline int sinter_qs_domain_ghost(const sinter_qs *qs, size_t i)
{
    return qs->dom.on && i >= qs->dom.owned;
}

/* The extents of the centres and the green density over every subdomain's owned particles
 * (qs->extent0, qs->density0). Collective. */
sinter_status sinter_qs_domain_start(sinter_qs *qs, const sinter_qs_particles *p);

/* Per-slot rows (width doubles each) of the ghosts added into their owners' rows (a reverse
 * halo); the ghost slots' rows are zeroed. Collective. */
sinter_status sinter_qs_domain_reverse(sinter_qs *qs, double *per_slot, size_t width);

/* K u = f over the owned links (qs->beams, slots), per slot; the ghosts' u from their owners.
 * Collective. */
sinter_status sinter_qs_domain_solve(sinter_qs *qs, size_t n, const double *f, const double *guess,
                                     double *u, int *iterations);

/* Marks per index (n: the step's particles) of the particles with a link: the ghosts' marks
 * go to their owners (a reverse halo), and are cleared. Collective. */
sinter_status sinter_qs_domain_linked(sinter_qs *qs, size_t n, unsigned char *linked);

/* Rows per index (width doubles each, owned then ghosts): the ghost rows added into their
 * owners' (a reverse halo), then zero. Nothing without domain operations. Collective. */
sinter_status sinter_qs_domain_reverse_index(sinter_qs *qs, double *rows, size_t width);

/* Rows per index (width doubles each, owned then ghosts): the ghost rows replaced by their
 * owners' (a forward halo). Nothing without domain operations. Collective. */
sinter_status sinter_qs_domain_forward_index(sinter_qs *qs, double *rows, size_t width);

#endif
