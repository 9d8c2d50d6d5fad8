/*
 * The stepper's side of a decomposed run (issue 43, include/sinter_domain.h): the host's
 * collective operations and the few helpers the explicit step calls as stages of its own
 * (reductions, the collective status, the forward halo of the state).
 *
 * Control flow in a decomposed run comes only from reduced values: a status is agreed
 * (sinter_domain_agree) before any branch that skips a collective call, so that no
 * subdomain waits for another that went elsewhere.
 */
#ifndef SINTER_DOMAIN_INTERNAL_H
#define SINTER_DOMAIN_INTERNAL_H

#include "core/core.h"
#include "particles/particles.h"
#include "sinter_domain.h"

typedef struct sinter_domain {
    int on;                /* 1 while the host's operations are installed */
    sinter_domain_ops ops; /* copied */
    void *user;
    long rank;            /* this subdomain's number (exscan of 1), -1 until known */
    double cutoff;        /* the ghost cut-off of the last rebuild [m] (0: none yet) */
    int rebuild_due;      /* a rejected step left ghosts to be made again */
    double *halo;         /* the forward halo's rows, (owned + ghosts) * width */
    size_t halo_capacity; /* doubles */
    uint64_t reductions;  /* reduce calls made */
    /* the rebuild decision reduced ahead, with the explicit step's agreement after the drift
     * (stepper.h, sinter_stepper_agree_drift): 1 until the step's evaluation takes it */
    int decided;
    double decision[2]; /* rebuild flag, largest radius: the MAX over every subdomain */
    uint64_t halos;     /* halo calls made */
    /* the redistribution stage (redistribute.c): 1 during the host's callback, and the state
     * at t (x, v, w, rot, temperature: 13 doubles) of the particles imported then, by id, for
     * a rollback */
    int redistributing;
    uint64_t layout_at_start; /* the set's layout generation when the callback began */
    /* the staggered stepper (staggered.c): 1 while a fixed-point attempt is under way, when
     * migration is refused (sinter_stepper_export with removal, _import), and 1 when a host
     * was refused so: the stepper redistributes again at the next accepted state */
    int in_attempt;
    int migration_deferred;
    /* 1 during the staggered stepper's redistribution at an accepted state: the records carry
     * the predictor's history (record bit 2), the arrivals' kept in arrived_id / _rows */
    int keep_history;
    /* the stepper's periodic images (ghosts/ghosts.h), after the host's ghost rows: the host's
     * halo sees only its own rows, the images take theirs from their owners after it */
    struct sinter_ghosts *periodic;
    uint64_t *arrived_id;
    double *arrived_rows;
    size_t arrived_count, arrived_id_capacity, arrived_rows_capacity;
} sinter_domain;

void sinter_domain_free(sinter_ctx *ctx, sinter_domain *d);

/* Reduce `count` values in place through the host; SINTER_ERR_CALLBACK when it fails (the
 * same on every subdomain only if the host's failure is: hosts fail collectively or abort). */
sinter_status sinter_domain_reduce(sinter_ctx *ctx, sinter_domain *d, void *values, size_t count,
                                   int type, int op);

/* This subdomain's number into *rank (collective the first time: an exscan of 1). */
sinter_status sinter_domain_rank(sinter_ctx *ctx, sinter_domain *d, long *rank);

/* The collective status: every subdomain passes its own status `s` and receives the same
 * one, the most negative code reported anywhere, with the message of the lowest-numbered
 * subdomain that reported it, prefixed by "subdomain R: ". SINTER_OK costs one reduction. */
sinter_status sinter_domain_agree(sinter_ctx *ctx, sinter_domain *d, sinter_status s);

/* The collective status and a sum of `count` doubles in one reduction (the explicit step's
 * stage C and its wall reactions): `values` has room for count + 1 doubles, the last one
 * written here with the number of subdomains that failed (an exact small integer in a SUM of
 * doubles). The values are summed in place (the same bits as a reduction of the `count`
 * alone: every value is reduced on its own); only when a subdomain failed does
 * sinter_domain_agree follow, to agree the code and the message. Without domain operations
 * `s`, the values untouched. */
sinter_status sinter_domain_agree_sum(sinter_ctx *ctx, sinter_domain *d, sinter_status s,
                                      double *values, size_t count);

/* The forward halo of the state (SINTER_HALO_STATE_WIDTH doubles per particle): the owned
 * rows packed, the host fills the ghost rows, which are unpacked into the set. */
sinter_status sinter_domain_forward(sinter_ctx *ctx, sinter_domain *d, sinter_particles *ps);

/* A forward halo of `width` doubles per particle: `rows` holds (owned + ghosts) * width
 * doubles, the owned rows filled by the caller; the host fills the ghost rows. */
sinter_status sinter_domain_forward_rows(sinter_ctx *ctx, sinter_domain *d,
                                         const sinter_particles *ps, double *rows, size_t width);

/* Sum `count` doubles over every subdomain in place (nothing without domain operations). */
sinter_status sinter_domain_sum(sinter_ctx *ctx, sinter_domain *d, double *values, size_t count);

/* Every subdomain's `count` records of `width` doubles to every subdomain, in subdomain order
 * (collective): *all (sinter_free) holds *total records, this subdomain's from record *first.
 * The records travel as bits (an integer sum of each slot's one writer and zeros), so any
 * double, NaN included, arrives unchanged. `s` is this subdomain's status so far: a failure
 * anywhere makes every subdomain return the agreed one (sinter_domain_agree) with *all NULL.
 * Cost: an exscan (counts and failure), one agreement (the buffer's allocation) and one
 * reduction of total * width words; meant for a few records per subdomain (the beam's
 * candidates), not for every particle. */
sinter_status sinter_domain_allgather(sinter_ctx *ctx, sinter_domain *d, sinter_status s,
                                      const double *mine, size_t count, size_t width, double **all,
                                      size_t *total, size_t *first);

/* Forces, moments and heat powers on the ghost rows discarded (newton off across borders). */
void sinter_domain_discard_ghost_rows(sinter_particles *ps);

/* SINTER_OK when the stepper's settings work across subdomains, else SINTER_ERR_UNSUPPORTED
 * naming the first that does not (domain/stepper_domain.c). */
struct sinter_stepper;
sinter_status sinter_domain_check(struct sinter_stepper *st);

/* The host's redistribute callback (migration and new ghosts), with the explicit stepper's
 * spare rows (the state at t) following the particles that stayed, by id
 * (domain/redistribute.c). SINTER_ERR_CALLBACK when the host fails. */
sinter_status sinter_domain_redistribute(struct sinter_stepper *st);

#endif
