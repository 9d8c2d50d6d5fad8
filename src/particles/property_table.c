/* Temperature-dependent material properties: tables, the specific enthalpy and its inverse. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "particles.h"

static const char *const PROPERTY_NAMES[SINTER_PROPERTY_COUNT_] = {
    "thermal conductivity", "heat capacity", "electric conductivity"};

static const sinter_material_param PROPERTY_PARAMS[SINTER_PROPERTY_COUNT_] = {
    SINTER_MAT_THERMAL_CONDUCTIVITY, SINTER_MAT_HEAT_CAPACITY, SINTER_MAT_ELECTRIC_CONDUCTIVITY};

/* ---- the enthalpy --------------------------------------------------------- */

/* The k with a[k] <= v < a[k+1] in an increasing a[0..n) (0 below a[1], n-1 from a[n-1]). */
static size_t bracket(const double *a, size_t n, double v)
{
    size_t lo = 0, hi = n; /* a[lo] <= v < a[hi] (a[n] = +inf) */
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (a[mid] <= v)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The segment k with t_k <= theta < t_k+1 (0 below t_1, the last one above). */
static size_t segment_of(const sinter_enthalpy *H, double theta)
{
    return bracket(H->t, H->count, theta);
}

double sinter_enthalpy_at(const sinter_enthalpy *H, double theta)
{
    const size_t k = segment_of(H, theta);
    const double x = theta - H->t[k];
    return H->h[k] + x * (H->c[k] + 0.5 * H->b[k] * x);
}

double sinter_enthalpy_capacity(const sinter_enthalpy *H, double theta)
{
    const size_t k = segment_of(H, theta);
    return H->c[k] + H->b[k] * (theta - H->t[k]);
}

double sinter_enthalpy_inverse(const sinter_enthalpy *H, double h)
{
    const size_t lo = bracket(H->h, H->count, h); /* h[lo] <= h < h[lo+1] */
    const double dh = h - H->h[lo], c = H->c[lo], b = H->b[lo];
    if (dh < 0.0) /* below 0 K: linear, the sanity check refuses it */
        return H->t[lo] + dh / c;
    /* b/2 x^2 + c x = dh, in the form without cancellation (c > 0, c^2 + 2 b dh >= 0 on the
     * segment since C_app > 0 across it) */
    const double disc = c * c + 2.0 * b * dh;
    return H->t[lo] + 2.0 * dh / (c + sqrt(disc > 0.0 ? disc : 0.0));
}

static void enthalpy_free(sinter_ctx *ctx, sinter_enthalpy *H)
{
    sinter_free(ctx, H->t);
    sinter_free(ctx, H->h);
    sinter_free(ctx, H->c);
    sinter_free(ctx, H->b);
    memset(H, 0, sizeof(*H));
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* C(theta) without latent heat: the table's or the constant. */
static double capacity(const sinter_material_props *p, double constant, double theta)
{
    const sinter_property_curve *c = &p->curve[SINTER_PROPERTY_HEAT_CAPACITY];
    return c->count > 0 ? sinter_property_curve_at(c, theta) : constant;
}

/* Breakpoints 0, the C table's temperatures, theta_m and theta_m + w; on each segment C is
 * linear (the table's interpolation) plus L / w inside the melting interval. */
static sinter_status enthalpy_build(sinter_ctx *ctx, sinter_material_props *p,
                                    const sinter_material *m)
{
    const sinter_property_curve *cc = &p->curve[SINTER_PROPERTY_HEAT_CAPACITY];
    const double c0 = m->value[SINTER_MAT_HEAT_CAPACITY];
    const double melt = m->value[SINTER_MAT_MELTING_TEMPERATURE];
    const double latent = m->value[SINTER_MAT_LATENT_HEAT];
    const double width = m->value[SINTER_MAT_MELTING_RANGE];
    const int melting = latent > 0.0 && melt > 0.0;
    const size_t cap = 1 + cc->count + 2;
    sinter_enthalpy H = {0, NULL, NULL, NULL, NULL};
    H.t = sinter_calloc(ctx, cap, sizeof(double));
    H.h = sinter_calloc(ctx, cap, sizeof(double));
    H.c = sinter_calloc(ctx, cap, sizeof(double));
    H.b = sinter_calloc(ctx, cap, sizeof(double));
    if (H.t == NULL || H.h == NULL || H.c == NULL || H.b == NULL) {
        enthalpy_free(ctx, &H);
        return SINTER_ERR_NOMEM;
    }
    size_t n = 0;
    H.t[n++] = 0.0;
    for (size_t k = 0; k < cc->count; ++k)
        H.t[n++] = cc->t[k];
    if (melting) {
        H.t[n++] = melt;
        H.t[n++] = melt + width;
    }
    qsort(H.t, n, sizeof(double), compare_double);
    size_t u = 1; /* unique */
    for (size_t k = 1; k < n; ++k)
        if (H.t[k] > H.t[u - 1])
            H.t[u++] = H.t[k];
    H.count = u;
    for (size_t k = 0; k < u; ++k) {
        const double a = H.t[k];
        const double ca = capacity(p, c0, a);
        /* the slope of the table on [t_k, t_k+1); 0 on the last, unbounded segment */
        const double slope =
            k + 1 < u ? (capacity(p, c0, H.t[k + 1]) - ca) / (H.t[k + 1] - a) : 0.0;
        const double extra = melting && a >= melt && a < melt + width ? latent / width : 0.0;
        H.c[k] = ca + extra;
        H.b[k] = slope;
        if (k + 1 < u) {
            const double x = H.t[k + 1] - a;
            H.h[k + 1] = H.h[k] + x * (H.c[k] + 0.5 * slope * x);
        }
    }
    enthalpy_free(ctx, &p->H);
    p->H = H;
    return SINTER_OK;
}

/* ---- per particle (the accessors' tabulated branches, particles.h) -------- */

double sinter_particle_property_tabulated(const sinter_particles *ps, size_t i, sinter_property p,
                                          sinter_material_param c)
{
    const sinter_material_props *t = ps->props[ps->material[i]];
    if (t == NULL || t->curve[p].count == 0)
        return sinter_particle_param(ps, i, c);
    return sinter_property_curve_at(&t->curve[p], ps->temperature[i]);
}

double sinter_particle_heat_capacity_tabulated(const sinter_particles *ps, size_t i, double theta)
{
    const sinter_enthalpy *H = sinter_particle_enthalpy(ps, i);
    return H == NULL ? sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY)
                     : sinter_enthalpy_capacity(H, theta);
}

/* ---- per material --------------------------------------------------------- */

void sinter_material_props_free(sinter_ctx *ctx, sinter_material_props *p)
{
    if (p == NULL)
        return;
    for (int q = 0; q < SINTER_PROPERTY_COUNT_; ++q) {
        sinter_free(ctx, p->curve[q].t);
        sinter_free(ctx, p->curve[q].v);
    }
    enthalpy_free(ctx, &p->H);
    sinter_free(ctx, p);
}

static void update_flags(sinter_particles *ps)
{
    memset(ps->tabulated, 0, sizeof(ps->tabulated));
    ps->enthalpy = 0;
    for (int m = 0; m < ps->material_top; ++m) {
        const sinter_material_props *p = ps->props[m];
        if (p == NULL || !ps->material_used[m])
            continue;
        for (int q = 0; q < SINTER_PROPERTY_COUNT_; ++q)
            ps->tabulated[q] |= p->curve[q].count > 0;
        ps->enthalpy |= p->enthalpy;
    }
}

sinter_status sinter_particles_props_update(sinter_particles *ps, int32_t id)
{
    sinter_material_props *p = ps->props[id];
    const sinter_material *m = &ps->materials[id];
    const int melting = m->value[SINTER_MAT_LATENT_HEAT] > 0.0;
    if (melting && !(m->value[SINTER_MAT_MELTING_TEMPERATURE] > 0.0))
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "material %d ('%s'): latent_heat = %g J/kg needs a melting_temperature "
                           "> 0",
                           (int)id, m->name, m->value[SINTER_MAT_LATENT_HEAT]);
    int tables = 0;
    for (int q = 0; p != NULL && q < SINTER_PROPERTY_COUNT_; ++q)
        tables |= p->curve[q].count > 0;
    if (!tables && !melting) { /* all constant: the constant paths, bit for bit */
        sinter_material_props_free(ps->ctx, p);
        ps->props[id] = NULL;
        update_flags(ps);
        return SINTER_OK;
    }
    if (p == NULL) {
        p = sinter_calloc(ps->ctx, 1, sizeof(*p));
        if (p == NULL)
            return SINTER_ERR_NOMEM;
        ps->props[id] = p;
    }
    p->enthalpy = melting || p->curve[SINTER_PROPERTY_HEAT_CAPACITY].count > 0;
    sinter_status s = p->enthalpy ? enthalpy_build(ps->ctx, p, m) : SINTER_OK;
    update_flags(ps);
    return s;
}

static sinter_status registered(const sinter_particles *ps, int32_t id, const char *func)
{
    if (id < 0 || id >= SINTER_MAX_MATERIALS || !ps->material_used[id])
        return sinter_fail(ps->ctx, SINTER_ERR_NOT_FOUND, "%s: material id %d is not registered",
                           func, (int)id);
    return SINTER_OK;
}

static sinter_status property_valid(const sinter_particles *ps, sinter_property q, const char *func)
{
    if ((int)q < 0 || (int)q >= SINTER_PROPERTY_COUNT_)
        return sinter_fail(ps->ctx, SINTER_ERR_RANGE, "%s: property %d is not one of 0..%d", func,
                           (int)q, SINTER_PROPERTY_COUNT_ - 1);
    return SINTER_OK;
}

sinter_status sinter_particles_set_property_table(sinter_particles *ps, int32_t id,
                                                  sinter_property property, size_t n,
                                                  const double *temperatures, const double *values)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_status s = registered(ps, id, __func__);
    if (s == SINTER_OK)
        s = property_valid(ps, property, __func__);
    if (s != SINTER_OK)
        return s;
    if (n > 0) {
        SINTER_CHECK_NULL(ps->ctx, temperatures);
        SINTER_CHECK_NULL(ps->ctx, values);
    }
    const char *name = PROPERTY_NAMES[property];
    for (size_t k = 0; k < n; ++k) {
        if (!isfinite(temperatures[k]) || !(temperatures[k] > 0.0) ||
            (k > 0 && !(temperatures[k] > temperatures[k - 1])))
            return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                               "%s: material %d, %s table: point %zu has temperature %g K; "
                               "temperatures must be finite, > 0 and strictly increasing",
                               __func__, (int)id, name, k, temperatures[k]);
        double lo = 0.0, hi = 0.0;
        sinter_material_param_info(PROPERTY_PARAMS[property], NULL, NULL, NULL, NULL, &lo, &hi);
        if (!isfinite(values[k]) || !(values[k] > 0.0) || values[k] > hi)
            return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                               "%s: material %d, %s table: point %zu (%g K) has value %g; values "
                               "must be finite, > 0 and at most %g",
                               __func__, (int)id, name, k, temperatures[k], values[k], hi);
    }
    sinter_material_props *p = ps->props[id];
    if (p == NULL && n > 0) {
        p = sinter_calloc(ps->ctx, 1, sizeof(*p));
        if (p == NULL)
            return SINTER_ERR_NOMEM;
        ps->props[id] = p;
    }
    if (p != NULL) {
        double *t = NULL, *v = NULL;
        if (n > 0 && sinter_copy_table(ps->ctx, n, temperatures, values, &t, &v) != SINTER_OK)
            return SINTER_ERR_NOMEM;
        sinter_property_curve *c = &p->curve[property];
        sinter_free(ps->ctx, c->t);
        sinter_free(ps->ctx, c->v);
        c->count = n;
        c->t = t;
        c->v = v;
    }
    ps->write_generation++; /* steppers evaluate again */
    return sinter_particles_props_update(ps, id);
}

sinter_status sinter_particles_property(const sinter_particles *ps, int32_t id,
                                        sinter_property property, double theta, double *value)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, value);
    sinter_status s = registered(ps, id, __func__);
    if (s == SINTER_OK)
        s = property_valid(ps, property, __func__);
    if (s != SINTER_OK)
        return s;
    if (!(theta > 0.0 && theta < INFINITY))
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "%s: temperature %g K must be finite and > 0", __func__, theta);
    const sinter_material_props *p = ps->props[id];
    *value = p != NULL && p->curve[property].count > 0
                 ? sinter_property_curve_at(&p->curve[property], theta)
                 : ps->materials[id].value[PROPERTY_PARAMS[property]];
    return SINTER_OK;
}

sinter_status sinter_particles_specific_enthalpy(const sinter_particles *ps, int32_t id,
                                                 double theta, double *enthalpy)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, enthalpy);
    sinter_status s = registered(ps, id, __func__);
    if (s != SINTER_OK)
        return s;
    if (!(theta > 0.0 && theta < INFINITY))
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "%s: temperature %g K must be finite and > 0", __func__, theta);
    const sinter_material_props *p = ps->props[id];
    *enthalpy = p != NULL && p->enthalpy
                    ? sinter_enthalpy_at(&p->H, theta)
                    : ps->materials[id].value[SINTER_MAT_HEAT_CAPACITY] * theta;
    return SINTER_OK;
}
