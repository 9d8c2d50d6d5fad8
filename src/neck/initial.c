/* Initial condition of two touching spheres with a small seeded neck (docs/7dof.md §4). */
#include <math.h>

#include "neck/neck.h"

int sinter_neck_initial_state(double radius_a, double radius_b, double epsilon, double h0_ratio,
                              double y[SINTER_NECK_DOF])
{
    if (!(radius_a > 0.0) || !(radius_b > 0.0) || !isfinite(radius_a) || !isfinite(radius_b))
        return -1;
    if (!(epsilon > 0.0 && epsilon < 0.5) || !(h0_ratio > 1.0 && h0_ratio < 2.0))
        return -1;
    /* docs/7dof.md §4: x0 = epsilon min(R_A, R_B) (the model cannot start at y1 = 0, where
     * dV/dy1 = 0); h0 = h0_ratio x0 in (x0, 2 x0) (2 x0 is tangency for x0 << R). */
    const double x0 = epsilon * fmin(radius_a, radius_b);
    const double h0 = h0_ratio * x0;
    if (!(h0 < fmin(radius_a, radius_b)))
        return -1;
    y[SINTER_NECK_X] = x0;
    /* docs/7dof.md §4: y2 = y4 = R_A (GB plane tangent to sphere A: touching, no overlap),
     * y3 = d_A0 = sqrt(R_A^2 - h0^2) (junction on sphere A); the same for B. The neck adds a
     * volume O(x0^4 / R), about 1e-8 relative for epsilon = 0.01, which is not subtracted. */
    const double radius[2] = {radius_a, radius_b};
    for (int p = 0; p < 2; ++p) {
        const double R = radius[p];
        y[1 + 3 * p] = R;
        y[2 + 3 * p] = sqrt((R - h0) * (R + h0));
        y[3 + 3 * p] = R;
    }
    return 0;
}

int sinter_neck_state_init(sinter_neck_state *state, double radius_a, double radius_b,
                           double epsilon, double h0_ratio, double t0)
{
    if (sinter_neck_initial_state(radius_a, radius_b, epsilon, h0_ratio, state->y) != 0)
        return -1;
    state->time = t0;
    /* Seed 001 eq. 11: L0 = y4(0) + y7(0). */
    state->center_distance0 = state->y[SINTER_NECK_LA] + state->y[SINTER_NECK_LB];
    state->last_dy4 = 0.0;
    state->last_dy7 = 0.0;
    state->step_hint = 0.0;
    return 0;
}
