/* PI controller on the fixed-point iteration's contraction; see step_control.h. */
#include "stepper/step_control.h"

#include <math.h>

double sinter_step_control_ratio(double e0, double ek, int k, int target_iterations)
{
    if (k == 0 || !(e0 > 1.0)) {
        /* The predictor met the tolerance: no contraction was measured. E_0 is then the
         * difference between the extrapolating predictor and the trapezoidal rule, an estimate
         * of the local error (Milne's device), and x = sqrt(E_0) in [0.1, 1] grows the step the
         * faster the better the predictor was; the step settles where E_0 ~ 0.25. Letting it
         * grow further (x = sqrt(E_0) / 4 was tried) forces iterations and larger steps, which
         * on the press cost as much at equal error, and through a stiff contact leave the
         * trapezoidal rule's undamped oscillation (test_hard_cases.c: 6e-5 off Hertz's
         * overlap instead of 1e-10). */
        return fmax(sqrt(fmax(e0, 0.0)), 0.1);
    }
    const double rho = pow(fmax(ek, 1e-300) / e0, 1.0 / k);
    const double rho_t = pow(1.0 / e0, 1.0 / target_iterations);
    return fmax(rho / rho_t, 1e-3);
}

double sinter_step_control_accept(sinter_step_control *sc, double x, double p)
{
    const double k_i = 0.3, k_p = 0.4;
    double scale = 0.9 * pow(x, -k_i / p);
    if (sc->x_prev > 0.0)
        scale *= pow(sc->x_prev / x, k_p / p);
    scale = fmin(fmax(scale, 0.5), sc->after_reject ? 1.0 : 2.0);
    sc->x_prev = x;
    sc->after_reject = 0;
    return scale;
}

double sinter_step_control_reject(sinter_step_control *sc, double x, double p)
{
    sc->after_reject = 1;
    const double scale = 0.9 * pow(fmax(x, 1.0), -1.0 / p);
    return isfinite(scale) ? fmin(fmax(scale, 0.2), 0.7) : 0.2;
}
