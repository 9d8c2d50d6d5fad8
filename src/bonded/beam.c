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
