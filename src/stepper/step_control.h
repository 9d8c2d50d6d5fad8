#ifndef SINTER_STEP_CONTROL_H
#define SINTER_STEP_CONTROL_H

/*
 * Step controller of the Anderson staggered scheme (staggered.c, scheme 1): a PI controller
 * (Gustafsson, ACM TOMS 20 (1994) 496; Soderlind, Numer. Algorithms 31 (2002) 281) on the
 * contraction of the fixed-point iteration instead of on a local error.
 *
 * Seed 000 eq. 49 models the iteration error as eps_K = (S h^p)^K eps_0: the contraction
 * rho = S h^p. A step needs rho_t = (1/E_0)^(1/K_d) to bring its first correction E_0 (in units
 * of the tolerance, WRMS) to 1 in K_d iterations. The controlled ratio is x = rho / rho_t
 * (x > 1: the step is too long) and, with rho ~ h^p,
 *
 *   h_(n+1) = h_n * safety * x_n^(-k_I / p) * (x_(n-1) / x_n)^(k_P / p)
 *
 * with k_I = 0.3, k_P = 0.4 and safety 0.9, the growth bounded to [1/2, 2] (1 right after a
 * rejection). The integral part alone is eq. 49's Lambda with an exponent below 1/p, the
 * proportional part damps the oscillation that eq. 49 alone shows (the step grows twofold,
 * fails, is cut, grows again: the cycling of seed's scheme on the press).
 */
typedef struct sinter_step_control {
    double x_prev; /* x of the last accepted step; 0: none (the integral part alone) */
    int after_reject;
} sinter_step_control;

/*
 * Normalised contraction x of an accepted step from its first and last corrections E_0, E_K
 * (WRMS, tolerance units) after K iterations beyond the predictor, target K_d.
 */
double sinter_step_control_ratio(double e0, double ek, int k, int target_iterations);
/* Scale of the next step after an accepted one with ratio x; updates the history. */
double sinter_step_control_accept(sinter_step_control *sc, double x, double p);
/* Scale of the retry after a rejected attempt with ratio x (x > 1), in [0.2, 0.7]. */
double sinter_step_control_reject(sinter_step_control *sc, double x, double p);

#endif
