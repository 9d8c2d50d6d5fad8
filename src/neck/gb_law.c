/*
 * The classic viscous contact law of grain-boundary diffusion (Bouvard & McMeeking 1996;
 * Parhami & McMeeking 1998; Henrich et al. 2007; Martin et al. 2006; docs/bibliography.md), as a
 * free two-particle law for comparison with the 7DOF model (docs/7dof.md §7):
 *
 *   normal force      N = pi a^4 / (8 Delta_b) d(delta)/dt - F_s
 *   diffusion param.  Delta_b = Omega delta_gb D_gb(T) / (k_B T),  D_gb = D_gb0 exp(-Q_gb / (R T))
 *   sintering force   F_s = pi gamma_s [4 R* (1 - cos(psi/2)) + a sin(psi/2)],
 *                     cos(psi/2) = gamma_gb / (2 gamma_s) (the equilibrium dihedral angle psi)
 *   neck (Coble)      a^2 = 4 R* delta,  R* = R_A R_B / (R_A + R_B)
 *
 * with delta the approach of the centres. A free pair carries N = 0, so
 *   d(delta)/dt = 8 Delta_b F_s / (pi a^4)   and   da/dt = 2 R* d(delta)/dt / a
 *              = 16 R* gamma_s Delta_b (B + S a) / a^5,   B = 4 R* (1 - cos(psi/2)), S =
 * sin(psi/2). At one phase the right-hand side separates: with theta = integral of Delta_b dt,
 *   integral_{a0}^{a1} a^5 / (B + S a) da = 16 R* gamma_s (theta1 - theta0),
 * which is solved for a1 by Newton in w = a^6 (the left side is concave and increasing in w, so
 * Newton from the lower bound w = a0^6 + 6 B (right side) climbs monotonically to the root). The
 * integral over a is an 8-point Gauss-Legendre rule on [a0, a1] (the integrand is a polynomial
 * over a factor whose pole, a = -B/S, is farther than 2 R* from the interval: relative error
 * below 1e-10), theta a composite 4-point rule with one panel per 5 K of the linear piece.
 */
#include <math.h>

#include "neck/neck.h"

#define PI 3.14159265358979323846

double sinter_gb_law_diffusion(const sinter_neck_phase *p, double temperature)
{
    if (p->boundary_d0 == 0.0)
        return 0.0;
    const double d =
        p->boundary_d0 * exp(-p->boundary_q / (SINTER_NECK_GAS_CONSTANT * temperature));
    return p->atomic_volume * p->grain_boundary_thickness * d / (SINTER_NECK_KB * temperature);
}

/* B and S of the header comment; 0 when the energies give no driving force. */
static int driving_terms(const sinter_neck_phase *p, double rstar, double *b, double *s)
{
    const double gs = p->surface_energy;
    if (!(gs > 0.0))
        return 0;
    const double c = p->grain_boundary_energy / (2.0 * gs); /* cos(psi/2), Young's relation */
    if (!(c < 1.0))
        return 0;
    *b = 4.0 * rstar * (1.0 - c);
    *s = sqrt((1.0 - c) * (1.0 + c));
    return 1;
}

double sinter_gb_law_sintering_force(const sinter_neck_phase *p, double rstar, double a)
{
    double b, s;
    return driving_terms(p, rstar, &b, &s) ? PI * p->surface_energy * (b + s * a) : 0.0;
}

double sinter_gb_law_approach_rate(const sinter_neck_phase *p, double temperature, double rstar,
                                   double a)
{
    const double a2 = a * a;
    return 8.0 * sinter_gb_law_diffusion(p, temperature) *
           sinter_gb_law_sintering_force(p, rstar, a) / (PI * a2 * a2);
}

/* integral of Delta_b over [t0, t1] on one linear piece of the schedule (composite 4-point
 * Gauss-Legendre, one panel per 5 K of temperature change). */
static double theta_piece(const sinter_neck_phase *p, const sinter_neck_schedule *s, double t0,
                          double t1)
{
    static const double node[2] = {0.33998104358485626, 0.86113631159405258};
    static const double weight[2] = {0.65214515486254614, 0.34785484513745386};
    const double span =
        fabs(sinter_neck_schedule_temperature(s, t1) - sinter_neck_schedule_temperature(s, t0));
    const double panels = fmin(fmax(ceil(span / 5.0), 1.0), 1e4);
    const double width = (t1 - t0) / panels;
    double sum = 0.0;
    for (double k = 0.0; k < panels; k += 1.0) {
        const double mid = t0 + (k + 0.5) * width, half = 0.5 * width;
        for (int q = 0; q < 2; ++q) {
            sum += weight[q] * half *
                   (sinter_gb_law_diffusion(
                        p, sinter_neck_schedule_temperature(s, mid - half * node[q])) +
                    sinter_gb_law_diffusion(
                        p, sinter_neck_schedule_temperature(s, mid + half * node[q])));
        }
    }
    return sum;
}

/* integral_{a0}^{a1} a^5 / (b + s a) da by 8-point Gauss-Legendre. */
static double neck_integral(double b, double s, double a0, double a1)
{
    static const double node[4] = {0.18343464249564981, 0.52553240991632899, 0.79666647741362674,
                                   0.96028985649753623};
    static const double weight[4] = {0.36268378337836198, 0.31370664587788729, 0.22238103445337447,
                                     0.10122853629037626};
    const double mid = 0.5 * (a0 + a1), half = 0.5 * (a1 - a0);
    double sum = 0.0;
    for (int q = 0; q < 4; ++q)
        for (int sign = -1; sign <= 1; sign += 2) {
            const double a = mid + sign * half * node[q], a2 = a * a;
            sum += weight[q] * a2 * a2 * a / (b + s * a);
        }
    return half * sum;
}

double sinter_gb_law_grow(double b, double s, double a0, double target)
{
    if (!(target > 0.0))
        return a0;
    const double w0 = a0 * a0 * a0 * a0 * a0 * a0;
    double w = w0 + 6.0 * b * target; /* lower bound (header comment) */
    for (int k = 0; k < 100; ++k) {
        const double a = cbrt(sqrt(w));
        const double next = w - (neck_integral(b, s, a0, a) - target) * 6.0 * (b + s * a);
        const int done = !(fabs(next - w) > 4.0 * 2.220446049250313e-16 * w);
        w = next;
        if (done)
            break;
    }
    return cbrt(sqrt(w));
}

int sinter_gb_law_advance(const sinter_neck_material *m, const sinter_neck_schedule *s,
                          double radius_a, double radius_b, double t0, double t1, double *a)
{
    if (!(radius_a > 0.0) || !(radius_b > 0.0) || !(*a > 0.0) || !isfinite(*a) || !(t1 >= t0))
        return -1;
    const double rstar = radius_a * radius_b / (radius_a + radius_b);
    double t = t0, neck = *a;
    while (t < t1) {
        /* one smooth piece: a schedule point or a phase switch ends it */
        const double next = sinter_neck_schedule_next_break(s, m, t, t1);
        const sinter_neck_phase *p = &m->phase[sinter_neck_schedule_phase(s, m, t, next)];
        double b, sn;
        if (driving_terms(p, rstar, &b, &sn)) {
            const double target = 16.0 * rstar * p->surface_energy * theta_piece(p, s, t, next);
            neck = sinter_gb_law_grow(b, sn, neck, target);
        }
        t = next;
    }
    if (!isfinite(neck) || !(neck > 0.0))
        return -1;
    *a = neck;
    return 0;
}
