/* Cohesive beam link and sintering force (seed 001 sec. 2.3-2.4, eq. 10-17, 18-40). */
#include <math.h>
#include <string.h>

#include "bonded/beam.h"

#define SINTER_BEAM_PI 3.14159265358979323846

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static int positive(double v)
{
    return v > 0.0 && isfinite(v);
}

int sinter_beam_update(sinter_beam *beam, const double xa[3], const double xb[3], double arm_a,
                       double arm_b)
{
    const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
    const double len = sqrt(dot3(d, d));
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

void sinter_beam_deformation(const sinter_beam *beam, const double ya[6], const double yb[6],
                             double eps[3], double gamma[3])
{
    /* eq. 25: eps = u_A - u_B - L_A0 theta_A + L_B0 theta_B, with L theta = l x theta,
     * l_A0 = L_A0 e3, l_B0 = -L_B0 e3 (eq. 21); eq. 26: gamma = theta_A - theta_B. */
    double la_x_ta[3], lb_x_tb[3];
    const double *e = beam->axis;
    const double la[3] = {beam->arm_a * e[0], beam->arm_a * e[1], beam->arm_a * e[2]};
    const double lb[3] = {-beam->arm_b * e[0], -beam->arm_b * e[1], -beam->arm_b * e[2]};
    cross3(la, ya + 3, la_x_ta);
    cross3(lb, yb + 3, lb_x_tb);
    for (int k = 0; k < 3; ++k) {
        eps[k] = ya[k] - yb[k] - la_x_ta[k] + lb_x_tb[k];
        gamma[k] = ya[3 + k] - yb[3 + k];
    }
}

/* v -> (k_perp (I - e e^T) + k_par e e^T) v: a local diag(k_perp, k_perp, k_par) in global
 * components (eq. 34 rotated to the global frame). */
static void axial_split(const double e[3], double k_perp, double k_par, const double v[3],
                        double out[3])
{
    const double p = dot3(e, v);
    for (int k = 0; k < 3; ++k)
        out[k] = k_perp * (v[k] - p * e[k]) + k_par * p * e[k];
}

void sinter_beam_apply(const sinter_beam *beam, const double ya[6], const double yb[6],
                       double pa[6], double pb[6])
{
    double eps[3], gamma[3], f[3], m[3];
    sinter_beam_deformation(beam, ya, yb, eps, gamma);
    axial_split(beam->axis, beam->k_shear, beam->k_axial, eps, f);    /* F_link, eq. 32-34a */
    axial_split(beam->axis, beam->k_bend, beam->k_torsion, gamma, m); /* M_link, eq. 34b */
    /* P = H^T P_link (eq. 39) with H of eq. 29: (-L_A0)^T F = l_A0 x F, L_B0^T F = -l_B0 x F. */
    const double *e = beam->axis;
    const double la[3] = {beam->arm_a * e[0], beam->arm_a * e[1], beam->arm_a * e[2]};
    const double lb[3] = {-beam->arm_b * e[0], -beam->arm_b * e[1], -beam->arm_b * e[2]};
    double la_x_f[3], lb_x_f[3];
    cross3(la, f, la_x_f);
    cross3(lb, f, lb_x_f);
    for (int k = 0; k < 3; ++k) {
        pa[k] += f[k];
        pa[3 + k] += la_x_f[k] + m[k];
        pb[k] -= f[k];
        pb[3 + k] += -lb_x_f[k] - m[k];
    }
}

void sinter_beam_stiffness(const sinter_beam *beam, double k[144])
{
    /* Column c of H^T K_link H is its product with the unit vector c. */
    for (int c = 0; c < 12; ++c) {
        double y[12] = {0}, p[12] = {0};
        y[c] = 1.0;
        sinter_beam_apply(beam, y, y + 6, p, p + 6);
        for (int r = 0; r < 12; ++r)
            k[12 * r + c] = p[r];
    }
}

double sinter_sintering_force(double youngs, double rm, double dl)
{
    /* eq. 10 with A = pi R_m^2 (eq. 14) and L0 = 2 R_m (eq. 11, 16): F_n = (pi/2) E R_m dL. */
    return 0.5 * SINTER_BEAM_PI * youngs * rm * dl;
}
