/* The rigid motion the bonded solve leaves undetermined: removed (qs_floating.c). */
#ifndef SINTER_STEPPER_QS_FLOATING_H
#define SINTER_STEPPER_QS_FLOATING_H

#include "stepper/quasistatic.h"

/*
 * In the displacements u[6 n] of a solve (per slot; particles p, the step's beams qs->beams
 * numbered by slot, and the plane conditions of qs), remove the rigid motion of every component
 * of the link graph the planes do not hold on all three axes. SINTER_OK, or SINTER_ERR_NOMEM
 * (u unchanged).
 */
sinter_status sinter_qs_remove_free_motion(sinter_qs *qs, const sinter_qs_particles *p, double *u);

/*
 * The same on a subdomain of a decomposed body (qs_floating_domain.c): the components found
 * across the subdomains, their sums over every subdomain's owned particles. Collective (every
 * subdomain calls it after the split solve, whatever its status st: a failure is agreed
 * before the first exchange and returned). u per slot, ghosts included.
 */
sinter_status sinter_qs_domain_remove_free_motion(sinter_qs *qs, const sinter_qs_particles *p,
                                                  double *u, sinter_status st);

#endif
