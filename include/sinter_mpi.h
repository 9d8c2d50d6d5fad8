/**
 * @file sinter_mpi.h
 * libsinter_mpi (issue 44): libsinter's optional companion library over the system MPI, built
 * with `cmake -DSINTER_MPI=ON`, linked with `pkg-config --libs libsinter-mpi` or CMake's
 * `find_package(libsinter COMPONENTS mpi)` and `libsinter::sinter_mpi`. The only header of the
 * project that includes <mpi.h>: libsinter.so and sinter.h never depend on MPI.
 *
 * What it holds today: a domain (a duplicated communicator with a decomposition of the global
 * box, sinter_mpi_decomp.h), collective reductions and an exclusive scan with the signatures of
 * the `reduce` and `exscan` entries of libsinter's domain operations, an exact global sum, load
 * balancing by recursive coordinate bisection, sinter_mpi_attach: the domain installed as an
 * explicit, staggered or quasi-static stepper's collective operations (migration, ghosts and
 * halos through MPI's neighbourhood collectives), with sinter_mpi_distribute for a set filled
 * on one rank and exchange counters (sinter_mpi_get_exchange_stats), and portable checkpoints
 * through MPI-IO that restart on another number of ranks.
 *
 * Every function is collective over the domain's communicator unless it says otherwise: every
 * rank calls it with the same non-local arguments (count, type, op, threshold). Argument errors
 * are found before any communication; every other error is returned by every rank alike.
 * Communication errors are returned (the duplicated communicator's error handler is
 * MPI_ERRORS_RETURN) as SINTER_ERR_IO.
 */
#ifndef SINTER_MPI_H
#define SINTER_MPI_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

#include "sinter.h"
#include "sinter_mpi_decomp.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A decomposed domain over an MPI communicator (opaque). */
typedef struct sinter_mpi_domain sinter_mpi_domain;

/** Options of sinter_mpi_domain_create; fill with sinter_mpi_options_init first. */
typedef struct sinter_mpi_options {
    size_t struct_size;       /**< sizeof(sinter_mpi_options) as the caller compiled it. */
    int decomposition;        /**< the initial kind, a sinter_mpi_decomp_kind (brick; an RCB without
                                   points yet is built at the first sinter_mpi_balance) */
    int grid[3];              /**< brick: ranks per axis; 0: chosen (sinter_mpi_decomp_brick) */
    double lo[3];             /**< the global box's lower corner (m) */
    double hi[3];             /**< the global box's upper corner (m) */
    double balance_threshold; /**< rebalance when the largest load over the mean exceeds it
                                   (>= 1; default 1.1) */
} sinter_mpi_options;

/**
 * Defaults: a brick chosen by the number of ranks over the unit box [0, 1]^3, threshold 1.1.
 * Not collective. Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE.
 */
SINTER_API sinter_status sinter_mpi_options_init(sinter_mpi_options *options, size_t struct_size);

/**
 * Create a domain over a duplicate of `comm` (the caller's communicator is not touched and may
 * be freed afterwards), decomposed as the options say into one part per rank.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_INVALID (options; MPI not
 * initialised), SINTER_ERR_NOMEM, SINTER_ERR_IO.
 */
SINTER_API sinter_status sinter_mpi_domain_create(sinter_mpi_domain **out, MPI_Comm comm,
                                                  const sinter_mpi_options *options);

/** Destroy a domain (collective: frees its communicator). NULL is allowed. */
SINTER_API void sinter_mpi_domain_destroy(sinter_mpi_domain *d);

/** This rank and the number of ranks. Not collective. Errors: SINTER_ERR_NULL. */
SINTER_API sinter_status sinter_mpi_domain_rank(const sinter_mpi_domain *d, int *rank, int *size);

/** The domain's own communicator (borrowed). Not collective. Errors: SINTER_ERR_NULL. */
SINTER_API sinter_status sinter_mpi_domain_comm(const sinter_mpi_domain *d, MPI_Comm *comm);

/** The current decomposition (borrowed, valid until the next balance). Not collective. */
SINTER_API sinter_status sinter_mpi_domain_decomp(const sinter_mpi_domain *d,
                                                  const sinter_mpi_decomp **decomp);

/**
 * Reduce `count` values of `type` (SINTER_MPI_F64, _I64, _U64) element-wise over the ranks with
 * `op` (SINTER_MPI_SUM, _MIN, _MAX), in place; `user` is the sinter_mpi_domain. Every rank
 * receives the same bits, and the bits do not depend on the number of ranks or the order in
 * which MPI combines them:
 *  - I64 and U64: MPI_Allreduce, exact (sums wrap modulo 2^64);
 *  - F64 SUM: through integer limbs below an agreed exponent (He and Ding 2001, J.
 *    Supercomputing 18:259-277; the method of CESM's shr_reprosum): the exact sum rounded the
 *    same way whatever the order (accurate to 2^-97 of the largest value's binary exponent
 *    times the number of ranks); a NaN anywhere, or +inf and -inf, gives NaN; else an infinity
 *    gives itself;
 *  - F64 MIN and MAX: a NaN anywhere gives NaN; -0 counts as below +0 (so the result does not
 *    depend on which rank holds which zero).
 * The signature of the `reduce` entry of libsinter's domain operations. Returns 0 or a
 * negative sinter_status (SINTER_ERR_NULL, SINTER_ERR_INVALID, SINTER_ERR_IO). Uses no heap.
 */
SINTER_API int sinter_mpi_reduce(void *values, size_t count, int type, int op, void *user);

/**
 * Exclusive prefix sum of `value` over the ranks in rank order (rank 0 gets 0), and the total;
 * `user` is the sinter_mpi_domain. The signature of the domain operations' `exscan` (global row
 * numbers). Returns 0 or SINTER_ERR_NULL, SINTER_ERR_IO.
 */
SINTER_API int sinter_mpi_exscan(uint64_t value, uint64_t *before, uint64_t *total, void *user);

/**
 * The sum of every rank's n terms, bit-identical for any number of ranks and any spread of the
 * terms over them (integer limbs, as sinter_mpi_reduce's F64 SUM). Non-finite terms as there.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_IO.
 */
SINTER_API sinter_status sinter_mpi_sum(sinter_mpi_domain *d, const double *terms, size_t n,
                                        double *sum);

/**
 * Rebalance the domain when its imbalance (largest rank load over the mean) exceeds the
 * options' threshold: the loads are the weights (NULL: 1 each) of this rank's n points
 * (positions: 3 doubles each) summed per owning part; above the threshold the decomposition
 * becomes a recursive coordinate bisection of the points (sinter_mpi_decomp_rebalance). The new
 * parts depend only on the set of points and weights, not on which rank holds them.
 * @param imbalance   receives the imbalance before (may be NULL).
 * @param rebalanced  receives 1 when the decomposition changed (may be NULL).
 * Errors: those of sinter_mpi_decomp_rebalance.
 */
SINTER_API sinter_status sinter_mpi_balance(sinter_mpi_domain *d, const double *positions,
                                            const double *weights, size_t n, double *imbalance,
                                            int *rebalanced);

/** Communication counters of a domain (this rank's). */
typedef struct sinter_mpi_stats {
    size_t struct_size;    /**< sizeof(sinter_mpi_stats) as the caller compiled it. */
    uint64_t reductions;   /**< collective reductions and scans made */
    uint64_t reduce_bytes; /**< bytes this rank contributed to them */
    uint64_t rebalances;   /**< decompositions replaced by sinter_mpi_balance */
    double seconds_comm;   /**< wall time inside them (MPI_Wtime), s */
} sinter_mpi_stats;

/** This rank's counters. Not collective. Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE. */
SINTER_API sinter_status sinter_mpi_get_stats(const sinter_mpi_domain *d, sinter_mpi_stats *stats);

/**
 * Write a portable checkpoint of a decomposed run into one file through MPI-IO (collective over
 * `comm`; every rank passes the same path): a header (magic, format version, byte-order
 * marker, the number of ranks, each rank's piece's offset, size, particle count and FNV-1a
 * checksum, its own checksum), the global part of rank 0's stepper (sinter_stepper_save_global)
 * and every rank's record stream of its owned particles (sinter_stepper_export, remove = 0) at
 * the exclusive prefix sum of the sizes before it (MPI_File_write_at_all). `particles` is the
 * set the stepper was created over. The stepper is not changed; a file of the same name is
 * replaced. comm = MPI_COMM_NULL or path = NULL: SINTER_ERR_NULL at once, without communication.
 * Errors (the same on every rank): SINTER_ERR_NULL, SINTER_ERR_NOMEM, those of
 * sinter_stepper_save_global and sinter_stepper_export (SINTER_ERR_UNSUPPORTED for the
 * quasi-static stepper and periodic boundaries), SINTER_ERR_IO (the file).
 */
SINTER_API sinter_status sinter_mpi_checkpoint_write(sinter_stepper *stepper,
                                                     sinter_particles *particles, MPI_Comm comm,
                                                     const char *path);

/**
 * Read a checkpoint of sinter_mpi_checkpoint_write on any number of ranks (collective over
 * `comm`; every rank passes the same path and the same decomposition): each rank's stepper, set
 * up alike (the same kind, force models, walls and materials) over a set without particles,
 * receives the global part and the particles whose centres lie in its part of `decomp` (part r
 * for rank r of comm; a brick or an RCB of sinter_mpi_decomp.h, `parts` = the number of ranks),
 * with every field, contact history and link, as the writer's ranks held them. The pieces are
 * read collectively (MPI_File_read_at_all), in contiguous runs of about the same bytes per rank,
 * then each particle is sent to its part's rank (MPI_Alltoallv). A restart continues as the run
 * would after a reordering of its particles (its neighbour lists are built afresh). For a
 * decomposed continuation attach the domain first (sinter_mpi_attach on the empty stepper), then
 * read: installing domain operations after the read makes the next step evaluate the forces
 * again at the full-step velocities instead of keeping the records' (the continuation then
 * differs by about 1e-6 within a few hundred steps; `sinter run` under mpiexec attaches first).
 * @param count  receives this rank's particles (may be NULL).
 * comm = MPI_COMM_NULL or path = NULL: SINTER_ERR_NULL at once, without communication.
 * Errors, the same on every rank, nothing changed on any: SINTER_ERR_NULL, SINTER_ERR_INVALID
 * (decomp's parts not the number of ranks; those of sinter_stepper_load_global and
 * sinter_stepper_import: a stepper not set up alike), SINTER_ERR_STATE (a set holding
 * particles), SINTER_ERR_CORRUPT (not a checkpoint, another format or byte order, truncated,
 * a checksum), SINTER_ERR_RANGE (more than 2 GiB of records to send or receive on one rank),
 * SINTER_ERR_NOMEM, SINTER_ERR_IO (no such file, a read failed).
 */
SINTER_API sinter_status sinter_mpi_checkpoint_read(sinter_stepper *stepper,
                                                    sinter_particles *particles, MPI_Comm comm,
                                                    const char *path,
                                                    const sinter_mpi_decomp *decomp, size_t *count);

/* ---- the domain installed as a stepper's collective operations (issue 44) ---------------- */

/** Flags of sinter_mpi_attach. */
#define SINTER_MPI_ATTACH_BALANCE 1 /**< rebalance at every neighbour-list rebuild (below) */

/**
 * Install the domain as the collective operations of this rank's explicit, staggered or
 * quasi-static stepper (sinter_stepper_set_domain_ops of sinter_domain.h, which says what each
 * stepper supports), over `particles`, the stepper's set:
 *  - reduce and exscan: sinter_mpi_reduce and sinter_mpi_exscan (the same bits on every rank);
 *  - redistribute, whenever the stepper asks (the explicit and staggered ones at every
 *    neighbour-list rebuild, the quasi-static one at the start of each advance or step call):
 *    each owned particle goes to the rank whose part of the decomposition holds its centre
 *    (sinter_stepper_export / _import, one MPI_Neighbor_alltoallv of record streams; received
 *    from the ranks in ascending order),
 *    then every rank receives as ghosts the owned particles of its neighbours within
 *    sinter_stepper_ghost_cutoff of the bounding box of its own owned particles (the boxes
 *    traded by MPI_Neighbor_allgather; one MPI_Neighbor_alltoallv of 144-byte records;
 *    ghosts in ascending rank order, each rank's in its index order);
 *  - halo: forward (owners' rows into ghost rows) and reverse (ghost rows added into their
 *    owners' rows in ascending rank order, then zeroed), one MPI_Neighbor_alltoallv each.
 * Inside a staggered stepper's fixed-point attempt, where the stepper refuses removals and
 * imports, the particles that left their part stay (only ghosts are made) and migrate at the
 * stepper's next accepted state, when it redistributes again.
 * The neighbours are the parts whose boxes (outer faces pushed to infinity: a point outside
 * the global box belongs to the nearest part) lie within the ghost cut-off of this rank's:
 * a graph communicator (MPI_Dist_graph_create_adjacent) made anew when the cut-off or the
 * decomposition changes. A particle that moved farther than a neighbour (a decomposition
 * replaced, or the first redistribution) goes through MPI_Alltoallv over the domain's
 * communicator instead. With SINTER_MPI_ATTACH_BALANCE, each rebuild first measures the parts'
 * loads (one per owned particle) and bisects anew above the options' threshold
 * (sinter_mpi_balance); without it the decomposition stays as it is, unless the domain was
 * created as a bisection (options.decomposition = SINTER_MPI_DECOMP_RCB), which balances at
 * every rebuild as well (its first rebuild bisects the brick it starts as).
 *
 * Collective. One stepper per domain at a time; the domain must outlive the stepper (or
 * sinter_stepper_set_domain_ops(stepper, NULL, NULL) first, which detaches it). Local errors
 * inside the callbacks are agreed over the ranks before the next exchange, so every rank
 * returns the same status (SINTER_ERR_CALLBACK from the stepper) and none waits forever.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (flags), SINTER_ERR_STATE (a stepper attached
 * already), SINTER_ERR_NOMEM, SINTER_ERR_IO, or those of sinter_stepper_set_domain_ops.
 */
SINTER_API sinter_status sinter_mpi_attach(sinter_mpi_domain *d, sinter_stepper *stepper,
                                           sinter_particles *particles, int flags);

/**
 * Move every owned particle of the attached stepper to the rank whose part holds its centre
 * (MPI_Alltoallv over the domain's communicator, records imported in ascending rank order):
 * the initial distribution of a set that rank 0 (or any rank) filled alone. Call after
 * sinter_mpi_attach and before the first step; a host whose ranks all read the same input can
 * instead keep the particles sinter_mpi_decomp_owners gives to its rank. Collective.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STATE (nothing attached), SINTER_ERR_NOMEM,
 * SINTER_ERR_IO, or the export's and import's errors (agreed: the same on every rank).
 */
SINTER_API sinter_status sinter_mpi_distribute(sinter_mpi_domain *d);

/** This rank's counters of the exchanges of an attached stepper (cumulative since the attach:
 * a host takes differences between two steps for per-step figures). */
typedef struct sinter_mpi_exchange_stats {
    size_t struct_size;         /**< sizeof(sinter_mpi_exchange_stats) as the caller compiled it */
    uint64_t halos;             /**< forward and reverse halos */
    uint64_t redistributions;   /**< redistributions (neighbour-list rebuilds) */
    uint64_t messages_sent;     /**< non-empty messages this rank sent in them */
    uint64_t bytes_sent;        /**< bytes this rank sent in them */
    uint64_t bytes_received;    /**< bytes this rank received in them */
    uint64_t migrated_out;      /**< particles this rank sent to others */
    uint64_t migrated_in;       /**< particles this rank received from others */
    uint64_t global_migrations; /**< migrations through MPI_Alltoallv (not the neighbours) */
    uint64_t graph_builds;      /**< neighbourhood graphs made */
    uint64_t ghosts;            /**< ghosts now */
    uint64_t owned;             /**< owned particles now */
    int neighbours;             /**< ranks in the neighbourhood now */
    double imbalance;           /**< the last imbalance measured (largest owned count over the
                                     mean, at the last redistribution) */
    double seconds_comm;        /**< wall time in the exchanges (MPI_Wtime), s; the reductions'
                                     is in sinter_mpi_stats */
} sinter_mpi_exchange_stats;

/** The attached stepper's exchange counters on this rank. Not collective.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_STRUCT_SIZE, SINTER_ERR_STATE (nothing attached). */
SINTER_API sinter_status sinter_mpi_get_exchange_stats(const sinter_mpi_domain *d,
                                                       sinter_mpi_exchange_stats *stats);

#ifdef __cplusplus
}
#endif

#endif
