/*
 * A test transport for include/sinter_domain.h (issue 43): 1 to LOOPBACK_MAX subdomains run as
 * pthreads of one process, each with its own context, particles and stepper. Every collective
 * operation is a barrier, a copy into a shared slot, a second barrier for the results and a
 * third before the slots are reused, the way an MPI host would exchange messages.
 *
 * - reduce: every subdomain computes the result from all slots in the same order; sums of
 *   doubles go through the order-independent limb sum (core/repro_sum.h), integer sums are
 *   exact, MIN and MAX are order-free: every subdomain receives identical bits.
 * - redistribute: with slabs set (loopback_set_slabs), every owned particle whose centre
 *   left its subdomain's slab along x migrates to the subdomain whose slab holds it
 *   (sinter_stepper_export without removal per destination, then one sinter_stepper_remove
 *   of all of them there, sinter_stepper_import here, from the
 *   subdomains in order; when the removal is refused with SINTER_ERR_STATE, inside a
 *   staggered attempt, they stay until the stepper asks again at its accepted state); then
 *   every subdomain publishes its owned particles and takes as ghosts the particles of the
 *   others within the ghost cut-off of its owned particles' extent along x. Without slabs, particles stay where they started.
 * - halo: forward copies the owners' rows into the ghost rows; reverse adds ghost rows into
 *   their owners' rows (in subdomain order) and zeroes them.
 */
#ifndef SINTER_DOMAIN_LOOPBACK_H
#define SINTER_DOMAIN_LOOPBACK_H

#include <stddef.h>
#include <stdint.h>

#include <sinter_domain.h>

enum { LOOPBACK_MAX = 4 };

typedef struct loopback loopback;

/* A transport for `size` subdomains (1..LOOPBACK_MAX), NULL on failure. */
loopback *loopback_create(int size);
void loopback_destroy(loopback *lb);

/* Equal slabs of [x0, x1) along x, subdomain r the r-th (the outer ones open outwards):
 * particles migrate at every redistribution. Call before the subdomains step. */
void loopback_set_slabs(loopback *lb, double x0, double x1);

/* Particles subdomain `rank` sent to others so far (migrations). */
uint64_t loopback_migrated(const loopback *lb, int rank);

/* Install the transport on subdomain `rank`'s stepper over `ps` (called by its thread). */
sinter_status loopback_attach(loopback *lb, int rank, sinter_stepper *st, sinter_particles *ps);

/* Collective calls made so far by subdomain `rank`: reductions, halos, redistributions. */
void loopback_counts(const loopback *lb, int rank, uint64_t counts[3]);

/* A barrier of all subdomains (for the tests' own bookkeeping). */
void loopback_barrier(loopback *lb);

#endif
