/*
 * The quasi-static stepper's reproducible mode (issue 43; stepper option "reproducible"): every
 * sum that mixes particles or links is an exact sum (core/repro_sum.h), so that the step gives
 * the same bits on any number of subdomains, without domain operations and on any number of
 * threads. Each particle's loads are exact row sums of its links' terms (the ghost ends' limbs
 * to their owners through a reverse halo), K u = f is the split solve (bonded/solve_split.h)
 * with exact operator products, diagonal blocks and dot products on one subdomain too, the
 * strategy-3 necks are integrated link by link (no CVODE norm across links), and the extents,
 * green density, mean temperature, statistics and the floating components' sums are exact.
 */
#ifndef SINTER_STEPPER_QS_REPRO_H
#define SINTER_STEPPER_QS_REPRO_H

#include "core/repro_sum.h"
#include "stepper/qs_struct.h"

/* The int64 reduction over qs's subdomains for core/repro_sum.h (NULL without domain ops). */
sinter_repro_reduce_fn sinter_qs_repro_reduce(const sinter_qs *qs);

/* The reverse halo of index rows for core/repro_sum.h (NULL without ghosts). */
sinter_repro_reverse_fn sinter_qs_repro_reverse(const sinter_qs *qs);

/* out[j] = the exact sum over every subdomain of terms[j n + i], i < n (n: this subdomain's
 * terms). Collective. Errors: SINTER_ERR_CALLBACK. */
sinter_status sinter_qs_repro_series(sinter_qs *qs, const double *terms, size_t n, size_t count,
                                     double *out);

/* The loads f (6 per slot of the n particles) of the links' axial forces fn[k] (+fn axis on
 * end a, -fn axis on end b): each owned particle's the exact sum over every subdomain's links;
 * the ghost slots' rows 0. Collective (a failure to allocate is agreed). Errors:
 * SINTER_ERR_NOMEM, SINTER_ERR_CALLBACK. */
sinter_status sinter_qs_repro_loads(sinter_qs *qs, size_t n, const double *fn, double *f);

#endif
