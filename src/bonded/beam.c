/* Cohesive beam link and sintering force (seed 001 sec. 2.3-2.4, eq. 10-17, 18-40). */
#include <math.h>
#include <string.h>

#include "bonded/beam.h"

#define SINTER_BEAM_PI 3.14159265358979323846

static int positive(double v)
{
    return v > 0.0 && isfinite(v);
}

int sinter_beam_update(sinter_beam *beam, const double xa[3], const double xb[3], double arm_a,
                       double arm_b)
{
    const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
    const double len = sqrt(v3_dot(d, d));
    if (!positive(len))
        return -1;
    for (int k = 0; k < 3; ++k)
        beam->axis[k] = d[k] / len;
    beam->arm_a = arm_a;
    beam->arm_b = arm_b;
    return 0;
}

int sinter_beam_init(sinter_beam *beam, uint32_t a, uint32_t b, const double xa[3],
                     const double xb[3], double arm_a, double arm_b, double rm, double length0,
                     double youngs, double poisson)
{
    memset(beam, 0, sizeof(*beam));
    if (!positive(arm_a) || !positive(arm_b) || !positive(rm) || !positive(length0) ||
        !positive(youngs) || !(poisson > -1.0 && poisson < 0.5))
        return -1;
    beam->a = a;
    beam->b = b;
    if (sinter_beam_update(beam, xa, xb, arm_a, arm_b) != 0)
        return -1;
    const double shear = youngs / (2.0 * (1.0 + poisson)); /* eq. 35 */
    const double r2 = rm * rm;
    const double area = SINTER_BEAM_PI * r2;                /* eq. 36a */
    const double inertia = 0.25 * SINTER_BEAM_PI * r2 * r2; /* eq. 36b */
    const double polar = 0.5 * SINTER_BEAM_PI * r2 * r2;    /* eq. 36c */
    beam->k_axial = youngs * area / length0;                /* eq. 34a */
    beam->k_shear = shear * area / length0;
    beam->k_bend = youngs * inertia / length0; /* eq. 34b */
    beam->k_torsion = shear * polar / length0;
    return 0;
}

/*
 * H^T K_link H in closed form. With E the cross-product matrix of the axis e (E v = e x v),
 * P = I - e e^T, S_F = k_shear I + (k_axial - k_shear) e e^T and S_M likewise with k_bend and
 * k_torsion (eq. 34), H_A = [I, -L_A0 E; 0, I] and H_B = [-I, -L_B0 E; 0, -I] (eq. 25-29), and
 * since e^T E = E e = 0 and E E = -P:
 *
 *   K_AA = [S_F, -k_s L_A E; k_s L_A E, S_M + k_s L_A^2 P]
 *   K_BB = [S_F,  k_s L_B E; -k_s L_B E, S_M + k_s L_B^2 P]
 *   K_AB = [-S_F, -k_s L_B E; -k_s L_A E, k_s L_A L_B P - S_M],   K_BA = K_AB^T.
 *
 * tests/unit/test_bonded.c checks it column by column against sinter_beam_apply.
 */
void sinter_beam_stiffness(const sinter_beam *beam, double k[144])
{
    const double *e = beam->axis;
    const double ks = beam->k_shear, la = beam->arm_a, lb = beam->arm_b;
    const double cross[3][3] = {{0.0, -e[2], e[1]}, {e[2], 0.0, -e[0]}, {-e[1], e[0], 0.0}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            const double ee = e[r] * e[c], perp = (r == c ? 1.0 : 0.0) - ee;
            const double sf = ks * perp + beam->k_axial * ee;
            const double sm = beam->k_bend * perp + beam->k_torsion * ee;
            const double x = ks * cross[r][c];
#define K(R, C) k[12 * (R) + (C)]
            K(r, c) = sf; /* AA */
            K(r, 3 + c) = -la * x;
            K(3 + r, c) = la * x;
            K(3 + r, 3 + c) = sm + ks * la * la * perp;
            K(6 + r, 6 + c) = sf; /* BB */
            K(6 + r, 9 + c) = lb * x;
            K(9 + r, 6 + c) = -lb * x;
            K(9 + r, 9 + c) = sm + ks * lb * lb * perp;
            K(r, 6 + c) = -sf; /* AB */
            K(r, 9 + c) = -lb * x;
            K(3 + r, 6 + c) = -la * x;
            K(3 + r, 9 + c) = ks * la * lb * perp - sm;
#undef K
        }
    for (int r = 0; r < 6; ++r) /* BA */
        for (int c = 0; c < 6; ++c)
            k[12 * (6 + r) + c] = k[12 * c + 6 + r];
}

double sinter_sintering_force(double youngs, double rm, double dl)
{
    /* eq. 10 with A = pi R_m^2 (eq. 14) and L0 = 2 R_m (eq. 11, 16): F_n = (pi/2) E R_m dL. */
    return 0.5 * SINTER_BEAM_PI * youngs * rm * dl;
}
