/*
 * The validity guard's geometry (docs/7dof.md §2.6): how much of a particle's surface its necks
 * cover, the neck ratio at which Z equal necks impinge, and the relative density a pair's
 * shrinkage stands for.
 */
#include <math.h>

#include "neck/neck.h"

double sinter_neck_cap_share(double ratio)
{
    const double r = fmin(fmax(ratio, 0.0), 1.0);
    return 0.5 * (1.0 - sqrt(1.0 - r * r));
}

double sinter_neck_impingement_ratio(double coordination)
{
    if (!(coordination > 0.0))
        return INFINITY;
    /* Z caps of share (1 - cos theta) / 2 cover the limit share c: cos theta = 1 - 2 c / Z */
    const double cos_theta = 1.0 - 2.0 * SINTER_NECK_COVERAGE_LIMIT / coordination;
    if (!(cos_theta > 0.0))
        return INFINITY;
    return sqrt(1.0 - cos_theta * cos_theta);
}

double sinter_neck_pair_density(double green, double shrinkage)
{
    const double s = 1.0 - shrinkage;
    return green / (s * s * s);
}
