/*
 * Mixtures by mass fraction (issue 38): each new particle takes the material furthest below
 * its mass share, f_k M - M_k largest (M the mass placed so far, M_k that of material k). The
 * chosen material is never above its share before the particle, so it is at most one
 * particle's mass above it after; the others only fall further behind. Every material thus
 * stays within one particle's mass above its share (two materials: also within one below),
 * which is tighter than an independent draw by number, whose mass fraction scatters as a
 * binomial. This is the largest-remainder apportionment applied online (docs/models.md,
 * "Powder size distributions").
 */
#include <math.h>
#include <string.h>

#include "mixture.h"
#include "particles.h"

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off") /* the same bits on every machine, as packing.c */
#endif

static const double PI = 3.14159265358979323846;

sinter_status sinter_mixture_init(sinter_mixture *mx, const sinter_particles *ps,
                                  const sinter_packing_options *o)
{
    sinter_ctx *ctx = ps->ctx;
    memset(mx, 0, sizeof(*mx));
    const size_t m = o->mixture_count;
    if (m == 0)
        return SINTER_OK;
    mx->material = sinter_realloc_array(ctx, NULL, m, sizeof(int32_t));
    mx->fraction = sinter_calloc(ctx, 3 * m, sizeof(double));
    if (mx->material == NULL || mx->fraction == NULL) {
        sinter_mixture_free(ctx, mx);
        return SINTER_ERR_NOMEM;
    }
    mx->density = mx->fraction + m;
    mx->mass = mx->fraction + 2 * m;
    mx->count = m;
    for (size_t k = 0; k < m; ++k) {
        mx->material[k] = o->mixture_materials[k];
        mx->fraction[k] = o->mixture_mass_fractions[k];
        mx->density[k] = ps->materials[mx->material[k]].value[SINTER_MAT_DENSITY];
        mx->sum += mx->fraction[k];
    }
    return SINTER_OK;
}

void sinter_mixture_free(sinter_ctx *ctx, sinter_mixture *mx)
{
    sinter_free(ctx, mx->material);
    sinter_free(ctx, mx->fraction);
    memset(mx, 0, sizeof(*mx));
}

size_t sinter_mixture_next(const sinter_mixture *mx)
{
    size_t best = 0;
    double best_deficit = -INFINITY;
    for (size_t k = 0; k < mx->count; ++k) {
        const double deficit = mx->fraction[k] / mx->sum * mx->total - mx->mass[k];
        if (deficit > best_deficit) {
            best = k;
            best_deficit = deficit;
        }
    }
    return best;
}

double sinter_mixture_particle_mass(const sinter_mixture *mx, size_t k, double r)
{
    return mx->density[k] * (4.0 / 3.0) * PI * r * r * r;
}

void sinter_mixture_add(sinter_mixture *mx, size_t k, double r)
{
    const double particle = sinter_mixture_particle_mass(mx, k, r);
    mx->mass[k] += particle;
    mx->total += particle;
}
