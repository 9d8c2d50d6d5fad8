/*
 * Temperature-dependent material properties (issues 39, 40): piecewise-linear tables of k, C
 * and sigma against temperature, and each material's specific enthalpy H(theta) = int_0^theta
 * C_app, where the apparent heat capacity C_app = C(theta) + L / w on the melting interval
 * [theta_m, theta_m + w] carries the latent heat L (an enthalpy method with the latent heat
 * spread over a stated interval, so that the temperature alone is the state).
 */
#ifndef SINTER_PROPERTY_TABLE_H
#define SINTER_PROPERTY_TABLE_H

#include "core/core.h"

/* One tabulated property: count points (count 0: none). */
typedef struct sinter_property_curve {
    size_t count;
    double *t; /* temperatures [K], strictly increasing */
    double *v; /* values */
} sinter_property_curve;

/*
 * H(theta) on segments [t_k, t_k+1) (t_0 = 0, the last one unbounded): C_app = c_k + b_k (theta
 * - t_k) there and H = h_k + c_k x + b_k x^2 / 2 with x = theta - t_k. Continuous and strictly
 * increasing (C_app > 0), so its inverse is exact to round-off.
 */
typedef struct sinter_enthalpy {
    size_t count; /* segments */
    double *t, *h, *c, *b;
} sinter_enthalpy;

typedef struct sinter_material_props {
    sinter_property_curve curve[SINTER_PROPERTY_COUNT_];
    int enthalpy;      /* 1: H below is in use (a C table or latent heat) */
    sinter_enthalpy H; /* the specific enthalpy [J/kg] */
} sinter_material_props;

/* H(theta) [J/kg], C_app(theta) [J/(kg K)], and theta(H) [K]. */
double sinter_enthalpy_at(const sinter_enthalpy *H, double theta);
double sinter_enthalpy_capacity(const sinter_enthalpy *H, double theta);
double sinter_enthalpy_inverse(const sinter_enthalpy *H, double h);

/* A property's value at theta from its table (which must have points). */
static inline double sinter_property_curve_at(const sinter_property_curve *c, double theta)
{
    return sinter_interpolate(c->count, c->t, c->v, theta);
}

void sinter_material_props_free(sinter_ctx *ctx, sinter_material_props *p);

struct sinter_particles;

/* After material `id` or one of its tables changed: its enthalpy rebuilt from the material's
 * heat capacity, C table, melting point and latent heat, its props dropped when nothing is
 * tabulated, and the set's flags updated. */
sinter_status sinter_particles_props_update(struct sinter_particles *ps, int32_t id);

#endif
