/*
 * Bonded links of the quasi-static sintering model (seed 001 = Ivannikov et al. 2022,
 * sec. 2.3-2.4, 3.1, 3.3): the sintering force of a neck, the cohesive beam link between two
 * particles with 6 DOF each, and the preconditioned CG solve of K u = f over an assembly.
 *
 * Conventions (seed 001 fig. 3-4): the link runs from particle A to particle B along the unit
 * axis e3; the grain-boundary centre sits at l_A0 = L_A0 e3 from A and l_B0 = -L_B0 e3 from B
 * (eq. 21, L_A0 = y4, L_B0 = y7). The DOFs of a particle are y = [u (3), theta (3)] (eq. 28),
 * particle-major: DOF 6 i + d. The nodal vector P = H^T K_link H y (eq. 40) is the force that
 * holds the displacement y, so equilibrium is K y = f_external.
 *
 * Note on eq. 37: the lever terms of eq. 37b/37d have the opposite sign of H^T (eq. 39) applied
 * to eq. 29; this module uses eq. 39-40 (H^T K_link H is symmetric and is the gradient of the
 * link energy 1/2 y_link . K_link y_link, so it is the consistent choice).
 *
 * The stiffness is the Potyondy-Cundall bond of eq. 33-36, NOT an Euler-Bernoulli or Timoshenko
 * beam: K_F = diag(GA, GA, EA)/L0 and K_M = diag(EI, EI, GJ)/L0 in the local frame, with
 * A = pi R_m^2, I = pi R_m^4/4, J = pi R_m^4/2 (eq. 36) and R_m from eq. 16. A particle B held
 * by one link to a clamped particle A under a transverse force F at its centre therefore moves
 * F L0/(GA) + F L0 L_B0^2/(EI) and turns by F L0 L_B0/(EI) (see tests/unit/test_bonded.c).
 */
#ifndef SINTER_BONDED_BEAM_H
#define SINTER_BONDED_BEAM_H

#include <stddef.h>
#include <stdint.h>

#include "core/core.h"

#define SINTER_BEAM_DOF 6 /* per particle: u_x, u_y, u_z, theta_x, theta_y, theta_z */

typedef struct sinter_beam {
    uint32_t a, b;    /* particle indices */
    double axis[3];   /* e3, unit vector A -> B */
    double arm_a;     /* L_A0 = y4: centre A -> grain boundary (eq. 21a) [m] */
    double arm_b;     /* L_B0 = y7 (eq. 21b) [m] */
    double k_axial;   /* EA/L0 (eq. 34a) [N/m] */
    double k_shear;   /* GA/L0 [N/m] */
    double k_bend;    /* EI/L0 (eq. 34b) [N m] */
    double k_torsion; /* GJ/L0 [N m] */
} sinter_beam;

/*
 * Set up a link between particles a and b at centres xa, xb (axis from them), lever arms
 * arm_a, arm_b, mean radius rm (eq. 16), bar length length0 (eq. 11), E and nu (eq. 35).
 * Returns 0, or -1 if the centres coincide or a parameter is not positive and finite.
 */
int sinter_beam_init(sinter_beam *beam, uint32_t a, uint32_t b, const double xa[3],
                     const double xb[3], double arm_a, double arm_b, double rm, double length0,
                     double youngs, double poisson);

/* Re-orient (axis from new centres) and set new arms; the stiffness stays (seed 001 sec. 2.4:
 * the coefficients are constant). Returns -1 if the centres coincide. */
int sinter_beam_update(sinter_beam *beam, const double xa[3], const double xb[3], double arm_a,
                       double arm_b);

/*
 * Link deformation y_link = H y (eq. 25-27) from the DOFs of A and B: eps[3], gamma[3] in
 * global components.
 */
void sinter_beam_deformation(const sinter_beam *beam, const double ya[6], const double yb[6],
                             double eps[3], double gamma[3]);

/* Add P = H^T K_link H y (eq. 40) of the link to pa and pb (6 each). */
void sinter_beam_apply(const sinter_beam *beam, const double ya[6], const double yb[6],
                       double pa[6], double pb[6]);

/* The 12x12 element stiffness H^T K_link H in global coordinates, row-major, DOFs
 * [u_A, theta_A, u_B, theta_B] (eq. 28, 40). */
void sinter_beam_stiffness(const sinter_beam *beam, double k[144]);

/* Sintering force F_n = (pi/2) E R_m dL (seed 001 eq. 17) [N], compressive for dL > 0. */
double sinter_sintering_force(double youngs, double rm, double dl);

/* ---------------------------------------------------------------------------------------- */
/* K u = f over an assembly of links (seed 001 sec. 3.3), SUNDIALS PCG, block-Jacobi          */
/* ---------------------------------------------------------------------------------------- */

typedef struct sinter_bonded_solver sinter_bonded_solver;

sinter_status sinter_bonded_solver_create(sinter_bonded_solver **out, sinter_ctx *ctx);
void sinter_bonded_solver_destroy(sinter_bonded_solver *solver);

/*
 * Solve K u = f for n particles (6 n DOFs) with the links[0..count). fixed[6 n] (NULL: none)
 * marks constrained DOFs: their u is 0 and their row of f is ignored (reaction). rtol: the
 * residual norm target relative to |f|. u[6 n] is written. *iterations (may be NULL) gets the
 * PCG iterations. Errors: SINTER_ERR_NOMEM, SINTER_ERR_NOT_CONVERGED.
 */
sinter_status sinter_bonded_solve(sinter_bonded_solver *solver, size_t n, const sinter_beam *links,
                                  size_t count, const unsigned char *fixed, const double *f,
                                  double *u, double rtol, int *iterations);

/* The same, started from guess[6 n] (NULL: from 0): a quasi-static march passes the last step's
 * displacements scaled to the new step, which the smooth sintering loading makes a close start.
 * The stopping test (residual relative to |f|) is the same, so the result is as accurate. */
sinter_status sinter_bonded_solve_from(sinter_bonded_solver *solver, size_t n,
                                       const sinter_beam *links, size_t count,
                                       const unsigned char *fixed, const double *f,
                                       const double *guess, double *u, double rtol,
                                       int *iterations);

#endif /* SINTER_BONDED_BEAM_H */
