/*
 * Geometry of the 7DOF neck in parametrisation 2: two spherical caps joined by two cones
 * (frusta) meeting in the grain-boundary disc (docs/7dof.md §2.1-2.3, seed 001 fig. 1a).
 * Volumes, free-surface area and their analytic partial derivatives; the guards of §2.5.
 */
#include <math.h>
#include <stdio.h>

#include "neck/neck.h"

#define PI 3.14159265358979323846

#if defined(__GNUC__) && defined(__SSE2__)
#include <emmintrin.h>

/* Both sides at once: the same formulas as side_eval, operation for operation, on two lanes
 * (side A, side B), so the same bits; the two square roots and divisions of a side form a
 * chain, and the two sides' chains now share their instructions (issue 9: the geometry was a
 * sixth of the copper packing's run). */
typedef double lanes __attribute__((vector_size(16)));

static int sides_eval(double x, const double y[SINTER_NECK_DOF], sinter_neck_geometry *g,
                      double volume[2], double area[2], double dv[2][4], double da[2][4])
{
    const lanes R = {y[1], y[4]}, d = {y[2], y[5]}, L = {y[3], y[6]};
    for (int p = 0; p < 2; ++p)
        if (!(R[p] > 0.0) || !(fabs(d[p]) < R[p]))
            return -1;
    const lanes H = L - d;
    const lanes h = _mm_sqrt_pd((R - d) * (R + d));
    const lanes s = _mm_sqrt_pd(H * H + (h - x) * (h - x));
    for (int p = 0; p < 2; ++p)
        if (!(s[p] > 0.0) || !(h[p] > 0.0))
            return -1;
    const lanes one = {1.0, 1.0};
    const lanes inv_h = one / h, inv_s = one / s;
    const lanes frustum = x * x + x * h + h * h;
    const lanes vol = PI / 3.0 * (R + d) * (R + d) * (2.0 * R - d) + PI / 3.0 * H * frustum;
    const lanes ar = 2.0 * PI * R * (R + d) + PI * (x + h) * s;
    const lanes dv_dh = PI / 3.0 * H * (x + 2.0 * h);
    const lanes dv0 = PI / 3.0 * H * (2.0 * x + h);
    const lanes dv1 = 2.0 * PI * R * (R + d) + dv_dh * R * inv_h;
    const lanes dv2 = PI * h * h - PI / 3.0 * frustum - dv_dh * d * inv_h;
    const lanes dv3 = PI / 3.0 * frustum;
    const lanes da_dh = PI * (s + (h - x) * (h + x) * inv_s);
    const lanes da_dheight = PI * (x + h) * H * inv_s;
    const lanes da0 = PI * (H * H - 2.0 * x * (h - x)) * inv_s;
    const lanes da1 = 2.0 * PI * (2.0 * R + d) + da_dh * R * inv_h;
    const lanes da2 = 2.0 * PI * R - da_dh * d * inv_h - da_dheight;
    for (int p = 0; p < 2; ++p) {
        g->side[p].cone_height = H[p];
        g->side[p].junction_radius = h[p];
        g->side[p].slant = s[p];
        volume[p] = vol[p];
        area[p] = ar[p];
        dv[p][0] = dv0[p];
        dv[p][1] = dv1[p];
        dv[p][2] = dv2[p];
        dv[p][3] = dv3[p];
        da[p][0] = da0[p];
        da[p][1] = da1[p];
        da[p][2] = da2[p];
        da[p][3] = da_dheight[p];
    }
    return 0;
}
#else
/* Contributions of one side P to V, A_s and to dV/dy, dA_s/dy (docs/7dof.md §2.2-2.3). */
static int side_eval(double x, double radius, double junction, double centre_to_gb,
                     sinter_neck_side *side, double *volume, double *area, double dv[4],
                     double da[4])
{
    const double R = radius, d = junction, L = centre_to_gb;
    if (!(R > 0.0) || !(fabs(d) < R))
        return -1;
    /* docs/7dof.md §2.1: H = L - d, h = sqrt(R^2 - d^2) (as (R - d)(R + d) against cancellation
     * when d is close to R), s = sqrt(H^2 + (h - x)^2) (lengths of a neck: their squares are far
     * from overflow and underflow, so no hypot). */
    const double H = L - d;
    const double h = sqrt((R - d) * (R + d));
    const double s = sqrt(H * H + (h - x) * (h - x));
    if (!(s > 0.0) || !(h > 0.0))
        return -1;
    const double inv_h = 1.0 / h, inv_s = 1.0 / s;
    side->cone_height = H;
    side->junction_radius = h;
    side->slant = s;

    /* docs/7dof.md §2.2: V_cap = (pi/3)(R + d)^2 (2R - d), V_cone = (pi/3) H (x^2 + x h + h^2),
     * A_cap = 2 pi R (R + d), A_cone = pi (x + h) s. */
    const double frustum = x * x + x * h + h * h;
    *volume = PI / 3.0 * (R + d) * (R + d) * (2.0 * R - d) + PI / 3.0 * H * frustum;
    *area = 2.0 * PI * R * (R + d) + PI * (x + h) * s;

    /* docs/7dof.md §2.3, volume: dV/dx = (pi/3) H (2x + h); the frustum's h-derivative
     * (pi/3) H (x + 2h) enters through dh/dR = R/h and dh/dd = -d/h;
     * dV/dR = 2 pi R (R + d) + (pi/3) H (x + 2h) R/h;
     * dV/dd = pi h^2 - (pi/3)(x^2 + x h + h^2) - (pi/3) H (x + 2h) d/h   (L fixed);
     * dV/dL = (pi/3)(x^2 + x h + h^2)                                     (d fixed). */
    const double dv_dh = PI / 3.0 * H * (x + 2.0 * h);
    dv[0] = PI / 3.0 * H * (2.0 * x + h);
    dv[1] = 2.0 * PI * R * (R + d) + dv_dh * R * inv_h;
    dv[2] = PI * h * h - PI / 3.0 * frustum - dv_dh * d * inv_h;
    dv[3] = PI / 3.0 * frustum;

    /* docs/7dof.md §2.3, area: dA/dx = pi [H^2 - 2x(h - x)] / s; helper dA/dh = pi [s + (h^2 - x^2)/s];
     * dA/dR = 2 pi (2R + d) + (dA/dh) R/h; dA/dd = 2 pi R - (dA/dh) d/h - pi (x + h) H / s;
     * dA/dL = pi (x + h) H / s. */
    const double da_dh = PI * (s + (h - x) * (h + x) * inv_s);
    const double da_dheight = PI * (x + h) * H * inv_s;
    da[0] = PI * (H * H - 2.0 * x * (h - x)) * inv_s;
    da[1] = 2.0 * PI * (2.0 * R + d) + da_dh * R * inv_h;
    da[2] = 2.0 * PI * R - da_dh * d * inv_h - da_dheight;
    da[3] = da_dheight;
    return 0;
}

static int sides_eval(double x, const double y[SINTER_NECK_DOF], sinter_neck_geometry *g,
                      double volume[2], double area[2], double dv[2][4], double da[2][4])
{
    for (int p = 0; p < 2; ++p)
        if (side_eval(x, y[1 + 3 * p], y[2 + 3 * p], y[3 + 3 * p], &g->side[p], &volume[p],
                      &area[p], dv[p], da[p]) != 0)
            return -1;
    return 0;
}
#endif

int sinter_neck_geometry_eval(const double y[SINTER_NECK_DOF], sinter_neck_geometry *g)
{
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        if (!isfinite(y[i]))
            return -1;
    const double x = y[SINTER_NECK_X];
    double volume[2], area[2], dv[2][4], da[2][4];
    if (sides_eval(x, y, g, volume, area, dv, da) != 0)
        return -1;

    /* docs/7dof.md §2.2: V = sum over sides, A_s = sum over sides, A_gb = pi y1^2. */
    g->volume = volume[0] + volume[1];
    g->surface_area = area[0] + area[1];
    g->boundary_area = PI * x * x;

    /* docs/7dof.md §2.3, assembled: y1 is shared by both sides; y2..y4 belong to A, y5..y7 to B;
     * A_gb depends on y1 only (dA_gb/dy1 = 2 pi y1). */
    g->dvolume[SINTER_NECK_X] = dv[0][0] + dv[1][0];
    g->dsurface[SINTER_NECK_X] = da[0][0] + da[1][0];
    g->dboundary[SINTER_NECK_X] = 2.0 * PI * x;
    for (int p = 0; p < 2; ++p) {
        for (int k = 1; k < 4; ++k) {
            g->dvolume[3 * p + k] = dv[p][k];
            g->dsurface[3 * p + k] = da[p][k];
            g->dboundary[3 * p + k] = 0.0;
        }
    }
    return 0;
}

static sinter_neck_violation report(sinter_neck_domain_error *err, sinter_neck_violation what,
                                    int side, double value, double limit)
{
    if (err != NULL) {
        err->what = what;
        err->side = side;
        err->value = value;
        err->limit = limit;
        err->time = NAN;
    }
    return what;
}

sinter_neck_violation sinter_neck_check_domain(const double y[SINTER_NECK_DOF],
                                               const sinter_neck_geometry *g,
                                               sinter_neck_domain_error *err)
{
    /* docs/7dof.md §2.5, in order: finite values; 0 < y1; R_P > 0; |d_P| < R_P (so h_P <= R_P);
     * H_P = L_P - d_P > 0; |dV/dy3|, |dV/dy6| >= 1e-3 pi h_P^2 (cone not tangent to sphere). */
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        if (!isfinite(y[i]))
            return report(err, SINTER_NECK_NOT_FINITE, i, y[i], 0.0);
    if (!(y[SINTER_NECK_X] > 0.0))
        return report(err, SINTER_NECK_NECK_RADIUS, -1, y[SINTER_NECK_X], 0.0);
    for (int p = 0; p < 2; ++p) {
        const double R = y[1 + 3 * p], d = y[2 + 3 * p], L = y[3 + 3 * p];
        if (!(R > 0.0))
            return report(err, SINTER_NECK_SPHERE_RADIUS, p, R, 0.0);
        if (!(fabs(d) < R))
            return report(err, SINTER_NECK_JUNCTION, p, d, R);
        if (!(L - d > 0.0))
            return report(err, SINTER_NECK_CONE_HEIGHT, p, L - d, 0.0);
    }
    sinter_neck_geometry local;
    if (g == NULL) {
        if (sinter_neck_geometry_eval(y, &local) != 0)
            return report(err, SINTER_NECK_NOT_FINITE, -1, NAN, 0.0);
        g = &local;
    }
    for (int p = 0; p < 2; ++p) {
        const double h = g->side[p].junction_radius;
        const double dv_dd = g->dvolume[2 + 3 * p];
        const double limit = 1e-3 * PI * h * h;
        if (!(fabs(dv_dd) >= limit))
            return report(err, SINTER_NECK_TANGENT, p, dv_dd, limit);
    }
    return SINTER_NECK_VALID;
}

void sinter_neck_describe_violation(const sinter_neck_domain_error *err, char *text, size_t size)
{
    static const char *const STATE_NAMES[SINTER_NECK_DOF] = {
        "y1 (x)", "y2 (R_A)", "y3 (d_A)", "y4 (L_A)", "y5 (R_B)", "y6 (d_B)", "y7 (L_B)"};
    const char side = err->side == 1 ? 'B' : 'A';
    switch (err->what) {
    case SINTER_NECK_VALID:
        snprintf(text, size, "the state is valid");
        break;
    case SINTER_NECK_NOT_FINITE:
        if (err->side >= 0 && err->side < SINTER_NECK_DOF)
            snprintf(text, size, "state %s = %g is not finite", STATE_NAMES[err->side], err->value);
        else
            snprintf(text, size, "the geometry is not finite");
        break;
    case SINTER_NECK_NECK_RADIUS:
        snprintf(text, size, "neck radius x = y1 = %g m must be > 0", err->value);
        break;
    case SINTER_NECK_SPHERE_RADIUS:
        snprintf(text, size, "sphere radius R_%c = %g m must be > 0", side, err->value);
        break;
    case SINTER_NECK_JUNCTION:
        snprintf(text, size,
                 "junction distance |d_%c| = %g m must be < R_%c = %g m (junction radius "
                 "h_%c <= R_%c)",
                 side, fabs(err->value), side, err->limit, side, side);
        break;
    case SINTER_NECK_CONE_HEIGHT:
        snprintf(text, size, "cone height H_%c = L_%c - d_%c = %g m must be > 0", side, side, side,
                 err->value);
        break;
    case SINTER_NECK_TANGENT:
        snprintf(text, size,
                 "dV/dd_%c = %g m^2 is below 1e-3 pi h_%c^2 = %g m^2 in magnitude: cone %c is "
                 "tangent to sphere %c",
                 side, err->value, side, err->limit, side, side);
        break;
    }
}

double sinter_neck_free_energy(const sinter_neck_geometry *g, const sinter_neck_coeffs *c)
{
    /* Seed 001 eq. 8: G = gamma_s A_s + gamma_gb A_gb. */
    return c->surface_energy * g->surface_area + c->boundary_energy * g->boundary_area;
}
