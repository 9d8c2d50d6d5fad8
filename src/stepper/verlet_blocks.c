/*
 * Velocity Verlet's passes over plain particles in vectorised blocks (verlet_blocks.h).
 *
 * One particle at a time, the update is three lanes wide (x, y, z) with two divisions and a
 * handful of scalar operations per lane: the passes ran at the speed of scalar code, not of
 * memory (a 64k falling pile on a Zen 4 core: 8 ns per particle for kick and drift, the same
 * at 8k, whose arrays fit in the caches). Here a block of particles first spreads its
 * factors h/(2m), h/(2J) and m g over its lanes; the updates then run over the block's flat
 * arrays, which the compiler vectorises. What needs a whole particle (its displacement, the
 * rotation vector, the finiteness check) follows in a short pass over the block. Every value
 * is formed by the same operations in the same order as before, so the bits do not change.
 */
#include "verlet_blocks.h"

#include <string.h>

#include "core/clones.h"
#include "core/stream_store.h"
#include "stepper.h"

enum { BLOCK = 32 }; /* particles per block: its lanes' arrays stay in L1 */

/* The lanes of a block: no array written in the loop overlaps another array of it (GCC would
 * otherwise compare every pair of the dozen pointers before it vectorised, and gives up). */
#if defined(__GNUC__) && !defined(__clang__)
#define LANES_INDEPENDENT _Pragma("GCC ivdep")
#else
#define LANES_INDEPENDENT
#endif

/* h/(2m) and h/(2J) of the block's particles spread over their three lanes. */
static inline __attribute__((always_inline)) void
spread_factors(const double *restrict m, const double *restrict j, double half, size_t nb,
               double *restrict fa, double *restrict fb)
{
    double am[BLOCK], bj[BLOCK];
    for (size_t p = 0; p < nb; ++p) {
        am[p] = half / m[p];
        bj[p] = half / j[p];
    }
    for (size_t p = 0; p < nb; ++p)
        for (int d = 0; d < 3; ++d) {
            fa[3 * p + (size_t)d] = am[p];
            fb[3 * p + (size_t)d] = bj[p];
        }
}

/* The first particle of [lo, hi) whose a (and b, unless NULL) values are not all finite, the
 * sum of value * 0 over its lanes as the passes form it; hi when none. */
static size_t first_not_finite(const double *a, const double *b, size_t lo, size_t hi)
{
    for (size_t i = lo; i < hi; ++i) {
        double z = 0.0;
        if (b != NULL)
            z = a[3 * i] * 0.0 + b[3 * i] * 0.0 + (a[3 * i + 1] * 0.0 + b[3 * i + 1] * 0.0) +
                (a[3 * i + 2] * 0.0 + b[3 * i + 2] * 0.0);
        else
            z = a[3 * i] * 0.0 + a[3 * i + 1] * 0.0 + a[3 * i + 2] * 0.0;
        if (!(z == 0.0))
            return i;
    }
    return hi;
}

/* One specialisation of the first pass (exact, stream and rotation fixed). */
static inline __attribute__((always_inline)) sinter_drift_scan
kick_drift_body(const sinter_verlet_arrays *a, double h, const double g[3], int rotation, int exact,
                int stream, size_t lo, size_t hi)
{
    const double *restrict x = a->x, *restrict v = a->v, *restrict w = a->w, *restrict x0 = a->x0,
                           *restrict m = a->m;
    double *restrict f = a->f, *restrict tq = a->tq;
    const double half = 0.5 * h;
    const sinter_verlet_factors *kept = a->factors;
    sinter_drift_scan out = {hi, 0.0, 0.0, {0.0, 0.0, 0.0}};
    double fa[3 * BLOCK], fb[3 * BLOCK], mg[3 * BLOCK];
    double lane2[3 * BLOCK] = {0.0}; /* each lane's largest squared step over the blocks */
    double lanez[3 * BLOCK] = {0.0}; /* without rotation: each lane's sum of x * 0 (NaN sticks) */
    double sq[3 * BLOCK], eq[3 * BLOCK], nf[3 * BLOCK], da[3 * BLOCK];
    double bx[3 * BLOCK], bv[3 * BLOCK], bw[3 * BLOCK]; /* staged for streaming */
    /* without rotation: each particle slot's largest squared step and displacement over the
     * blocks (the maxima of all particles at the end: a maximum does not depend on order) */
    double slot2[BLOCK] = {0.0}, slotd2[BLOCK] = {0.0};
    for (size_t i0 = lo; i0 < hi; i0 += BLOCK) {
        const size_t nb = hi - i0 < BLOCK ? hi - i0 : BLOCK, lanes = 3 * nb, k0 = 3 * i0;
        const double *restrict ka = fa, *restrict kb = fb, *restrict kg = mg;
        if (kept != NULL) { /* the same values, kept (sinter_verlet_factors) */
            const size_t at = kept->uniform ? 0 : k0; /* (uniform: the first block's) */
            ka = kept->fa + at, kb = kept->fb + at, kg = kept->mg + at;
        } else {
            spread_factors(m + i0, a->j + i0, half, nb, fa, fb);
            for (size_t p = 0; p < nb; ++p)
                for (int d = 0; d < 3; ++d) /* gravity's force, as its evaluation adds it */
                    mg[3 * p + (size_t)d] = 0.0 + m[i0 + p] * g[d];
        }
        double *restrict dx = stream ? bx : a->nx + k0;
        double *restrict dv = stream ? bv : a->nv + k0;
        double *restrict dw = stream ? bw : a->nw + k0;
        LANES_INDEPENDENT
        for (size_t k = 0; k < lanes; ++k) {
            const double xo = x[k0 + k];
            const double vk = v[k0 + k] + ka[k] * f[k0 + k];
            const double xk = xo + h * vk;
            const double wk = w[k0 + k] + kb[k] * tq[k0 + k];
            dv[k] = vk;
            dx[k] = xk;
            dw[k] = wk;
            if (rotation)
                da[k] = h * wk;
            f[k0 + k] = kg[k]; /* read for the last time: the next evaluation adds into it */
            tq[k0 + k] = 0.0;
            if (rotation)
                nf[k] = xk * 0.0; /* 0 when finite, NaN when not */
            else
                lanez[k] += xk * 0.0; /* (the first such particle found below) */
            const double sk = xk - xo;
            sq[k] = sk * sk;
            lane2[k] = sq[k] > lane2[k] ? sq[k] : lane2[k]; /* NaN not taken */
            if (exact) {
                const double e = xk - x0[k0 + k];
                eq[k] = e * e;
            }
        }
        if (stream)
            for (size_t k = 0; k < lanes; ++k) {
                sinter_put(a->nx + k0 + k, bx[k], 1);
                sinter_put(a->nv + k0 + k, bv[k], 1);
                sinter_put(a->nw + k0 + k, bw[k], 1);
            }
        if (!rotation) { /* per particle slot of the block, without a branch: vectorised */
            for (size_t p = 0; p < nb; ++p) {
                const double s2 = 0.0 + sq[3 * p] + sq[3 * p + 1] + sq[3 * p + 2];
                slot2[p] = s2 > slot2[p] ? s2 : slot2[p]; /* NaN not taken */
                if (exact) {
                    const double d2 = 0.0 + eq[3 * p] + eq[3 * p + 1] + eq[3 * p + 2];
                    slotd2[p] = d2 > slotd2[p] ? d2 : slotd2[p];
                }
            }
            continue;
        }
        for (size_t p = 0; p < nb; ++p) {
            const size_t k = 3 * p;
            double z = rotation ? nf[k] + nf[k + 1] + nf[k + 2] : 0.0;
            const double s2 = 0.0 + sq[k] + sq[k + 1] + sq[k + 2];
            out.step2 = s2 > out.step2 ? s2 : out.step2;
            if (exact) {
                const double d2 = 0.0 + eq[k] + eq[k + 1] + eq[k + 2];
                out.moved2 = d2 > out.moved2 ? d2 : out.moved2; /* NaN not taken */
            }
            if (rotation) {
                double *alpha = a->nrot + k0 + k;
                for (int d = 0; d < 3; ++d)
                    alpha[d] = a->rot[k0 + k + (size_t)d];
                sinter_compose_rotation(alpha, da + k);
                z += alpha[0] * 0.0 + alpha[1] * 0.0 + alpha[2] * 0.0;
            }
            if (!(z == 0.0) && out.bad == hi)
                out.bad = i0 + p;
        }
    }
    for (size_t p = 0; p < BLOCK && !rotation; ++p) {
        out.step2 = slot2[p] > out.step2 ? slot2[p] : out.step2;
        out.moved2 = slotd2[p] > out.moved2 ? slotd2[p] : out.moved2;
    }
    double any = 0.0;
    for (size_t k = 0; k < 3 * BLOCK; ++k) {
        double *a2 = &out.axis2[k % 3];
        *a2 = lane2[k] > *a2 ? lane2[k] : *a2;
        any += lanez[k];
    }
    if (!rotation && !(any == 0.0)) /* a position not finite: the first, as one at a time */
        out.bad = first_not_finite(a->nx, NULL, lo, hi);
    return out;
}

SINTER_CLONES
sinter_drift_scan sinter_verlet_kick_drift(const sinter_verlet_arrays *a, double h,
                                           const double g[3], int rotation, int exact, int stream,
                                           size_t lo, size_t hi)
{
    /* each combination its own loop, with no branch inside */
#define KD(r, e, s) kick_drift_body(a, h, g, r, e, s, lo, hi)
    if (rotation)
        return exact ? (stream ? KD(1, 1, 1) : KD(1, 1, 0)) : (stream ? KD(1, 0, 1) : KD(1, 0, 0));
    return exact ? (stream ? KD(0, 1, 1) : KD(0, 1, 0)) : (stream ? KD(0, 0, 1) : KD(0, 0, 0));
#undef KD
}

SINTER_CLONES
size_t sinter_verlet_kick(double *restrict v, double *restrict w, const double *restrict f,
                          const double *restrict tq, const double *restrict m,
                          const double *restrict j, const sinter_verlet_factors *kept, double h,
                          size_t lo, size_t hi)
{
    const double half = 0.5 * h;
    double fa[3 * BLOCK], fb[3 * BLOCK];
    double lanez[3 * BLOCK] = {0.0}; /* each lane's sum of v * 0 + w * 0 (NaN sticks) */
    for (size_t i0 = lo; i0 < hi; i0 += BLOCK) {
        const size_t nb = hi - i0 < BLOCK ? hi - i0 : BLOCK, lanes = 3 * nb, k0 = 3 * i0;
        const double *restrict ka = fa, *restrict kb = fb;
        if (kept != NULL) {
            const size_t at = kept->uniform ? 0 : k0; /* (uniform: the first block's) */
            ka = kept->fa + at, kb = kept->fb + at;
        } else
            spread_factors(m + i0, j + i0, half, nb, fa, fb);
        LANES_INDEPENDENT
        for (size_t k = 0; k < lanes; ++k) {
            const double vk = v[k0 + k] + ka[k] * f[k0 + k];
            const double wk = w[k0 + k] + kb[k] * tq[k0 + k];
            v[k0 + k] = vk;
            w[k0 + k] = wk;
            lanez[k] += vk * 0.0 + wk * 0.0;
        }
    }
    double any = 0.0;
    for (size_t k = 0; k < 3 * BLOCK; ++k)
        any += lanez[k];
    /* a value not finite: the first such particle, from the values written */
    return any == 0.0 ? hi : first_not_finite(v, w, lo, hi);
}

const sinter_verlet_factors *sinter_verlet_factors_for(sinter_ctx *ctx, sinter_verlet_factors *c,
                                                       size_t n, const double *m, const double *j,
                                                       uint64_t layout, uint64_t write, double h,
                                                       const double g[3])
{
    if (c->count == n && n > 0 && c->layout == layout && c->write == write && c->m == m &&
        c->j == j && memcmp(&c->h, &h, sizeof(h)) == 0 && memcmp(c->g, g, sizeof(c->g)) == 0)
        return c;
    c->count = 0;
    if (n > c->capacity) {
        double **arrays[3] = {&c->fa, &c->fb, &c->mg};
        for (int k = 0; k < 3; ++k) {
            double *grown = sinter_realloc_array(ctx, *arrays[k], 3 * n, sizeof(double));
            if (grown == NULL) {
                sinter_verlet_factors_free(ctx, c);
                return NULL;
            }
            *arrays[k] = grown;
        }
        c->capacity = n;
    }
    const double half = 0.5 * h; /* as the passes form them */
    for (size_t i = 0; i < n; ++i) {
        const double a = half / m[i], b = half / j[i];
        for (int d = 0; d < 3; ++d) {
            c->fa[3 * i + (size_t)d] = a;
            c->fb[3 * i + (size_t)d] = b;
            c->mg[3 * i + (size_t)d] = 0.0 + m[i] * g[d];
        }
    }
    int uniform = 1;
    for (size_t k = 3; k < 3 * n && uniform; ++k)
        uniform = memcmp(&c->fa[k], &c->fa[k % 3], sizeof(double)) == 0 &&
                  memcmp(&c->fb[k], &c->fb[k % 3], sizeof(double)) == 0 &&
                  memcmp(&c->mg[k], &c->mg[k % 3], sizeof(double)) == 0;
    c->uniform = uniform;
    c->count = n;
    c->layout = layout;
    c->write = write;
    c->m = m;
    c->j = j;
    c->h = h;
    memcpy(c->g, g, sizeof(c->g));
    return c;
}

void sinter_verlet_factors_free(sinter_ctx *ctx, sinter_verlet_factors *c)
{
    sinter_free(ctx, c->fa);
    sinter_free(ctx, c->fb);
    sinter_free(ctx, c->mg);
    memset(c, 0, sizeof(*c));
}
