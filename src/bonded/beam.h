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
#include "force/vec3.h"

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
static inline void sinter_beam_deformation(const sinter_beam *beam, const double ya[6],
                                           const double yb[6], double eps[3], double gamma[3])
{
    /* eq. 25: eps = u_A - u_B - L_A0 theta_A + L_B0 theta_B, with L theta = l x theta,
     * l_A0 = L_A0 e3, l_B0 = -L_B0 e3 (eq. 21); eq. 26: gamma = theta_A - theta_B. */
    double la_x_ta[3], lb_x_tb[3];
    const double *e = beam->axis;
    const double la[3] = {beam->arm_a * e[0], beam->arm_a * e[1], beam->arm_a * e[2]};
    const double lb[3] = {-beam->arm_b * e[0], -beam->arm_b * e[1], -beam->arm_b * e[2]};
    v3_cross(la, ya + 3, la_x_ta);
    v3_cross(lb, yb + 3, lb_x_tb);
    for (int k = 0; k < 3; ++k) {
        eps[k] = ya[k] - yb[k] - la_x_ta[k] + lb_x_tb[k];
        gamma[k] = ya[3 + k] - yb[3 + k];
    }
}

/* v -> (k_perp (I - e e^T) + k_par e e^T) v: a local diag(k_perp, k_perp, k_par) in global
 * components (eq. 34 rotated to the global frame). */
static inline void sinter_beam_axial_split(const double e[3], double k_perp, double k_par,
                                           const double v[3], double out[3])
{
    const double p = v3_dot(e, v);
    for (int k = 0; k < 3; ++k)
        out[k] = k_perp * (v[k] - p * e[k]) + k_par * p * e[k];
}

/* Add P = H^T K_link H y (eq. 40) of the link to pa and pb (6 each). */
static inline void sinter_beam_apply(const sinter_beam *beam, const double ya[6],
                                     const double yb[6], double pa[6], double pb[6])
{
    double eps[3], gamma[3], f[3], m[3];
    sinter_beam_deformation(beam, ya, yb, eps, gamma);
    sinter_beam_axial_split(beam->axis, beam->k_shear, beam->k_axial, eps, f); /* eq. 32-34a */
    sinter_beam_axial_split(beam->axis, beam->k_bend, beam->k_torsion, gamma, m); /* eq. 34b */
    /* P = H^T P_link (eq. 39) with H of eq. 29: (-L_A0)^T F = l_A0 x F, L_B0^T F = -l_B0 x F. */
    const double *e = beam->axis;
    const double la[3] = {beam->arm_a * e[0], beam->arm_a * e[1], beam->arm_a * e[2]};
    const double lb[3] = {-beam->arm_b * e[0], -beam->arm_b * e[1], -beam->arm_b * e[2]};
    double la_x_f[3], lb_x_f[3];
    v3_cross(la, f, la_x_f);
    v3_cross(lb, f, lb_x_f);
    for (int k = 0; k < 3; ++k) {
        pa[k] += f[k];
        pa[3 + k] += la_x_f[k] + m[k];
        pb[k] -= f[k];
        pb[3 + k] += -lb_x_f[k] - m[k];
    }
}

/* The 12x12 element stiffness H^T K_link H in global coordinates, row-major, DOFs
 * [u_A, theta_A, u_B, theta_B] (eq. 28, 40). */
void sinter_beam_stiffness(const sinter_beam *beam, double k[144]);

/* Sintering force F_n = (pi/2) E R_m dL (seed 001 eq. 17) [N], compressive for dL > 0. */
double sinter_sintering_force(double youngs, double rm, double dl);

/* ---------------------------------------------------------------------------------------- */
/* K u = f over an assembly of links (seed 001 sec. 3.3): SUNDIALS PCG, block SSOR           */
/* ---------------------------------------------------------------------------------------- */

typedef struct sinter_bonded_solver sinter_bonded_solver;

sinter_status sinter_bonded_solver_create(sinter_bonded_solver **out, sinter_ctx *ctx);
void sinter_bonded_solver_destroy(sinter_bonded_solver *solver);

/*
 * Solve K u = f for n particles (6 n DOFs) with the links[0..count). fixed[6 n] (NULL: none)
 * marks constrained DOFs: their u is 0 and their row of f is ignored (reaction). rtol: the
 * target of the true residual |f - K u| relative to |f| (met, or the rounding floor of K u if
 * that is higher: bonded/solve.c). u[6 n] is written, also on failure. *iterations (may be NULL)
 * gets the PCG iterations. Errors: SINTER_ERR_NOMEM, SINTER_ERR_INVALID (a link's particle
 * out of range), SINTER_ERR_NOT_CONVERGED.
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
