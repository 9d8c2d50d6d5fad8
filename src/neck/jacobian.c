/*
 * Dense 7x7 Jacobian of the neck right-hand side by forward differences (the issue allows
 * "dense 7x7 or analytic"; an analytic one needs second derivatives of V and A_s). One RHS call
 * per column; used by the CVODE driver's Newton iteration and by the batch's block factors.
 */
#include <float.h>
#include <math.h>

#include "neck/neck.h"

sinter_neck_violation sinter_neck_jacobian(const double y[SINTER_NECK_DOF],
                                           const double f[SINTER_NECK_DOF],
                                           const sinter_neck_coeffs *c,
                                           double jac[SINTER_NECK_DOF * SINTER_NECK_DOF])
{
    /* Increment sqrt(eps) |y_j|, floored at sqrt(eps) |y1| so that no column divides by zero;
     * this is CVODE's own difference-quotient choice with the state scale in place of 1/ewt.
     * The increment is re-derived from the rounded perturbed value so that (y + dy) - y is
     * exact. A perturbed state outside the domain is retried on the other side. */
    const double root_eps = sqrt(DBL_EPSILON);
    double yp[SINTER_NECK_DOF], fp[SINTER_NECK_DOF];
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        yp[i] = y[i];
    for (int j = 0; j < SINTER_NECK_DOF; ++j) {
        const double scale = fmax(fabs(y[j]), fabs(y[SINTER_NECK_X]));
        sinter_neck_violation bad = SINTER_NECK_VALID;
        double step = 0.0;
        for (int direction = 1; direction >= -1; direction -= 2) {
            yp[j] = y[j] + direction * root_eps * scale;
            step = yp[j] - y[j];
            bad = sinter_neck_rhs(yp, c, fp, NULL, NULL);
            if (bad == SINTER_NECK_VALID)
                break;
        }
        yp[j] = y[j];
        if (bad != SINTER_NECK_VALID)
            return bad;
        for (int i = 0; i < SINTER_NECK_DOF; ++i)
            jac[i + SINTER_NECK_DOF * j] = (fp[i] - f[i]) / step;
    }
    return SINTER_NECK_VALID;
}
