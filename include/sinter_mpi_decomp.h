/**
 * @file sinter_mpi_decomp.h
 * Spatial decompositions of libsinter_mpi (issue 44): which part (rank) owns which point of
 * space. Part of the companion library libsinter_mpi, but free of MPI itself: every function is
 * pure, and the few that need global sums take a reduction callback with the signature of the
 * `reduce` entry of libsinter's domain operations (sinter_mpi_reduce over MPI, or NULL when the
 * caller holds every point). So a decomposition can be built and tested in one process.
 *
 * Two kinds:
 *  - a Cartesian brick: g0 x g1 x g2 equal boxes over the global box [lo, hi] (static);
 *  - recursive coordinate bisection (RCB) with weights: the set of points is cut by a plane
 *    normal to the longest extent of its points, placed so that the weight on each side is
 *    proportional to the parts that side receives, and each side is cut again until every
 *    part has its box (the method of Berger and Bokhari 1987, "A partitioning strategy for
 *    nonuniform problems on multiprocessors", IEEE Trans. Computers C-36(5):570-580, the
 *    "rcb" of LAMMPS' balance command and of Zoltan). The cut planes are found by multisection
 *    on exact (integer-limb) sums of the weights below candidate planes, so the planes are the
 *    same bits however the points are spread over the callers: the cuts depend only on the set
 *    of points and weights.
 *
 * Lengths in metres (any unit works: only comparisons are made); weights are dimensionless
 * non-negative loads (particles, contacts, links or seconds of measured work).
 */
#ifndef SINTER_MPI_DECOMP_H
#define SINTER_MPI_DECOMP_H

#include <stddef.h>
#include <stdint.h>

#include "sinter.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Reduction operations of a reduce callback (the values of sinter_domain.h's sinter_reduce_op). */
#define SINTER_MPI_SUM 0
/** Element-wise minimum (see SINTER_MPI_SUM). */
#define SINTER_MPI_MIN 1
/** Element-wise maximum (see SINTER_MPI_SUM). */
#define SINTER_MPI_MAX 2
/** Value types of a reduce callback (the values of sinter_domain.h's sinter_reduce_type): double.
 */
#define SINTER_MPI_F64 0
/** int64_t values (see SINTER_MPI_F64). */
#define SINTER_MPI_I64 1
/** uint64_t values (see SINTER_MPI_F64). */
#define SINTER_MPI_U64 2

/**
 * Collective reduction: combine `count` values of `type` element-wise over every caller with
 * `op`, in place; every caller receives identical bits. Returns 0 (SINTER_OK) or a negative
 * sinter_status. The signature of the domain operations' `reduce`.
 */
typedef int (*sinter_mpi_reduce_fn)(void *values, size_t count, int type, int op, void *user);

/** Kinds of decomposition. */
typedef enum sinter_mpi_decomp_kind {
    SINTER_MPI_DECOMP_BRICK = 0, /**< g0 x g1 x g2 equal boxes (static) */
    SINTER_MPI_DECOMP_RCB = 1    /**< recursive coordinate bisection with weights */
} sinter_mpi_decomp_kind;

/** A decomposition of space into parts 0 .. parts-1 (opaque). */
typedef struct sinter_mpi_decomp sinter_mpi_decomp;

/**
 * A Cartesian brick of `parts` boxes over [lo, hi].
 * @param grid  boxes per axis; NULL or zeros: chosen (the factorisation of `parts` with the
 *              smallest total area of cut planes, fewer cuts along shorter axes); an axis given
 *              non-zero is kept and the others chosen. The product must equal `parts`.
 * Part numbers follow MPI_Cart_create's row-major order: (i0 g1 + i1) g2 + i2.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (parts < 1, hi <= lo, a grid that does not
 * multiply to parts), SINTER_ERR_NOMEM.
 */
SINTER_API sinter_status sinter_mpi_decomp_brick(sinter_mpi_decomp **out, int parts,
                                                 const int grid[3], const double lo[3],
                                                 const double hi[3]);

/**
 * Recursive coordinate bisection of the points of every caller into `parts` boxes of [lo, hi]
 * (collective through `reduce` when it is not NULL; every caller passes the same parts, lo, hi).
 * @param positions  this caller's n points, 3 doubles each (x, y, z); NULL when n = 0.
 * @param weights    n non-negative finite loads; NULL: 1 each.
 * @param reduce     the reduction over every caller; NULL when this caller holds every point.
 * Cuts go normal to the longest extent of the points of the set being cut (ties: x before y
 * before z), at the plane within the extent where the weight below it is closest to its share
 * (found to 4 bits per round of reductions; at most 16 rounds per level). A set without weight
 * is cut at the middle of its box's longest side. Points outside [lo, hi] belong to the nearest
 * part's side of every plane. Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (a weight negative or
 * not finite on any caller, a position not finite), SINTER_ERR_NOMEM, or a reduce error.
 */
SINTER_API sinter_status sinter_mpi_decomp_rcb(sinter_mpi_decomp **out, int parts,
                                               const double lo[3], const double hi[3],
                                               const double *positions, const double *weights,
                                               size_t n, sinter_mpi_reduce_fn reduce, void *user);

/** Destroy a decomposition; NULL is allowed. */
SINTER_API void sinter_mpi_decomp_destroy(sinter_mpi_decomp *d);

/** The kind (a sinter_mpi_decomp_kind) and the number of parts. Errors: SINTER_ERR_NULL. */
SINTER_API sinter_status sinter_mpi_decomp_info(const sinter_mpi_decomp *d, int *kind, int *parts);

/** A brick's boxes per axis. Errors: SINTER_ERR_NULL, SINTER_ERR_STATE (not a brick). */
SINTER_API sinter_status sinter_mpi_decomp_grid(const sinter_mpi_decomp *d, int grid[3]);

/**
 * The box [lo, hi] of a part (m). Parts of a brick or RCB tile [lo, hi] of the whole without
 * overlap; a point on a shared face belongs to the part above it.
 * Errors: SINTER_ERR_NULL, SINTER_ERR_RANGE (part).
 */
SINTER_API sinter_status sinter_mpi_decomp_box(const sinter_mpi_decomp *d, int part, double lo[3],
                                               double hi[3]);

/**
 * The part owning each of n points (3 doubles each); points outside the global box go to the
 * nearest part along each cut. Errors: SINTER_ERR_NULL.
 */
SINTER_API sinter_status sinter_mpi_decomp_owners(const sinter_mpi_decomp *d,
                                                  const double *positions, size_t n, int *parts);

/**
 * The load of every part: the sum of the weights (NULL: 1 each) of every caller's points that
 * the part owns, summed exactly (the same bits for any spread of the points over callers).
 * Collective through `reduce` (NULL: this caller holds every point).
 * @param loads  `parts` doubles. Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (a weight
 * negative or not finite on any caller), SINTER_ERR_NOMEM, or a reduce error.
 */
SINTER_API sinter_status sinter_mpi_decomp_loads(const sinter_mpi_decomp *d,
                                                 const double *positions, const double *weights,
                                                 size_t n, sinter_mpi_reduce_fn reduce, void *user,
                                                 double *loads);

/**
 * The imbalance of `parts` loads: the largest over the mean (1: perfect balance; `parts` when
 * one part holds everything; 1 when every load is zero). Errors: SINTER_ERR_NULL,
 * SINTER_ERR_INVALID (parts < 1, a load negative or not finite).
 */
SINTER_API sinter_status sinter_mpi_imbalance(const double *loads, int parts, double *imbalance);

/**
 * Rebalance when needed (collective through `reduce`): measure the imbalance of the points'
 * loads under `d`; when it exceeds `threshold` (>= 1; 1.1 is LAMMPS' customary choice), replace
 * d's parts by an RCB of the same points (d becomes an RCB; its number of parts stays). Call it
 * at neighbour-list rebuilds, where particles may change owner anyway.
 * @param imbalance    receives the imbalance before (may be NULL).
 * @param rebalanced   receives 1 when d was replaced, else 0 (may be NULL).
 * Errors: those of sinter_mpi_decomp_loads and sinter_mpi_decomp_rcb; SINTER_ERR_INVALID
 * (threshold < 1 or not finite). On an error d is unchanged.
 */
SINTER_API sinter_status sinter_mpi_decomp_rebalance(sinter_mpi_decomp *d, const double *positions,
                                                     const double *weights, size_t n,
                                                     double threshold, sinter_mpi_reduce_fn reduce,
                                                     void *user, double *imbalance,
                                                     int *rebalanced);

#ifdef __cplusplus
}
#endif

#endif
