/*
 * The explicit stepper's blocked velocity Verlet passes (src/stepper/verlet_blocks.c) against
 * the update written one particle at a time: kick and drift, the zeroed force and moment, the
 * displacements, the rotation vector (seed 003 eq. 45) and the first non-finite particle, to
 * the bit, for every combination of rotation, exact displacement and streaming stores, over
 * ranges that start and end inside a block; and the same with the factors kept between
 * steps (sinter_verlet_factors), which are made again when h, g or the particles change,
 * also when every particle has the same mass and moment (the uniform factors, read from the
 * first block).
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <string.h>

#include <cmocka.h>

#include "stepper/stepper.h"
#include "stepper/verlet_blocks.h"

enum { N = 77 }; /* two blocks of 32 and 13 more */

typedef struct state {
    double x[3 * N], v[3 * N], w[3 * N], rot[3 * N], f[3 * N], tq[3 * N], m[N], j[N], x0[3 * N];
} state;

static int uniform_masses; /* fill: every particle the same mass and moment */

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0 - 0.5;
}

static void fill(state *s, uint64_t seed)
{
    for (size_t k = 0; k < 3 * N; ++k) {
        s->x[k] = lcg(&seed), s->v[k] = lcg(&seed), s->w[k] = 100.0 * lcg(&seed);
        s->rot[k] = lcg(&seed), s->f[k] = 1e-3 * lcg(&seed), s->tq[k] = 1e-9 * lcg(&seed);
        s->x0[k] = s->x[k] + 1e-4 * lcg(&seed);
    }
    for (size_t i = 0; i < N; ++i)
        s->m[i] = 1e-6 * (1.5 + lcg(&seed)), s->j[i] = 1e-13 * (1.5 + lcg(&seed));
    if (uniform_masses) /* one powder of one size: the kept factors are uniform */
        for (size_t i = 0; i < N; ++i)
            s->m[i] = s->m[0], s->j[i] = s->j[0];
}

/* One particle at a time (the loop the blocks replaced). */
static sinter_drift_scan reference(state *s, double *nx, double *nv, double *nw, double *nrot,
                                   double h, const double g[3], int rotation, int exact, size_t lo,
                                   size_t hi)
{
    sinter_drift_scan out = {hi, 0.0, 0.0, {0.0, 0.0, 0.0}};
    for (size_t i = lo; i < hi; ++i) {
        const double a = 0.5 * h / s->m[i], b = 0.5 * h / s->j[i];
        double da[3], s2 = 0.0, d2 = 0.0, finite = 1;
        for (int d = 0; d < 3; ++d) {
            const size_t k = 3 * i + (size_t)d;
            nv[k] = s->v[k] + a * s->f[k];
            nx[k] = s->x[k] + h * nv[k];
            nw[k] = s->w[k] + b * s->tq[k];
            da[d] = h * nw[k];
            s->f[k] = 0.0 + s->m[i] * g[d];
            s->tq[k] = 0.0;
            finite = finite && isfinite(nx[k]);
            s2 += (nx[k] - s->x[k]) * (nx[k] - s->x[k]);
            const double a2 = (nx[k] - s->x[k]) * (nx[k] - s->x[k]);
            out.axis2[d] = a2 > out.axis2[d] ? a2 : out.axis2[d];
            d2 += (nx[k] - s->x0[k]) * (nx[k] - s->x0[k]);
        }
        if (rotation) {
            memcpy(nrot + 3 * i, s->rot + 3 * i, 3 * sizeof(double));
            sinter_compose_rotation(nrot + 3 * i, da);
            for (int d = 0; d < 3; ++d)
                finite = finite && isfinite(nrot[3 * i + (size_t)d]);
        }
        out.step2 = s2 > out.step2 ? s2 : out.step2;
        if (exact)
            out.moved2 = d2 > out.moved2 ? d2 : out.moved2;
        if (!finite && out.bad == hi)
            out.bad = i;
    }
    return out;
}

static sinter_ctx *ctx;
static sinter_verlet_factors kept; /* (made for state 7's masses, h and g below) */

static void check_kick_drift(int rotation, int exact, int stream, size_t poisoned, int keep)
{
    const double h = 1e-5, g[3] = {0.0, 0.0, -9.81};
    const size_t lo = 13, hi = N;
    static state a, b;
    static double nx[2][3 * N], nv[2][3 * N], nw[2][3 * N], nrot[2][3 * N];
    fill(&a, 7);
    if (poisoned < N) /* their new positions are not finite; the first is reported */
        a.v[3 * poisoned + 1] = INFINITY, a.v[3 * (N - 1)] = -INFINITY;
    b = a;
    memset(nx, 0, sizeof nx), memset(nv, 0, sizeof nv), memset(nw, 0, sizeof nw);
    memset(nrot, 0, sizeof nrot);
    const sinter_drift_scan want =
        reference(&a, nx[0], nv[0], nw[0], nrot[0], h, g, rotation, exact, lo, hi);
    const sinter_verlet_arrays arrays = {
        .x = b.x,
        .v = b.v,
        .w = b.w,
        .rot = b.rot,
        .f = b.f,
        .tq = b.tq,
        .m = b.m,
        .j = b.j,
        .x0 = b.x0,
        .nx = nx[1],
        .nv = nv[1],
        .nw = nw[1],
        .nrot = nrot[1],
        .factors = keep ? sinter_verlet_factors_for(ctx, &kept, N, b.m, b.j, 1,
                                                    1 + (uint64_t)uniform_masses, h, g)
                        : NULL};
    assert_true(!keep || arrays.factors != NULL);
    assert_true(!keep || arrays.factors->uniform == uniform_masses);
    const sinter_drift_scan got =
        sinter_verlet_kick_drift(&arrays, h, g, rotation, exact, stream, lo, hi);
    assert_int_equal(got.bad, want.bad);
    assert_int_equal(got.bad, poisoned < N ? poisoned : hi);
    if (poisoned >= N) { /* the maxima compare values only when all are finite */
        assert_memory_equal(&got.step2, &want.step2, sizeof(double));
        assert_memory_equal(&got.moved2, &want.moved2, sizeof(double));
        /* the largest step along each axis (the walls' certificate, contact/wall_skip.h) */
        assert_memory_equal(got.axis2, want.axis2, sizeof want.axis2);
        assert_true(want.axis2[0] > 0.0 && want.axis2[1] > 0.0 && want.axis2[2] > 0.0);
        assert_true(want.axis2[0] + want.axis2[1] + want.axis2[2] >= want.step2);
        assert_true(want.step2 > 0.0);
        assert_true(exact ? want.moved2 > 0.0 : want.moved2 == 0.0);
    }
    assert_memory_equal(nx[1], nx[0], sizeof nx[0]);
    assert_memory_equal(nv[1], nv[0], sizeof nv[0]);
    assert_memory_equal(nw[1], nw[0], sizeof nw[0]);
    assert_memory_equal(nrot[1], nrot[0], sizeof nrot[0]);
    assert_memory_equal(b.f, a.f, sizeof a.f);
    assert_memory_equal(b.tq, a.tq, sizeof a.tq);
    assert_true(nx[1][3 * lo] != 0.0 && nx[1][3 * lo - 1] == 0.0); /* [lo, hi) only */
}

static void test_kick_drift_every_variant(void **unused)
{
    (void)unused;
    for (uniform_masses = 0; uniform_masses < 2; ++uniform_masses)
        for (int rotation = 0; rotation < 2; ++rotation)
            for (int exact = 0; exact < 2; ++exact)
                for (int stream = 0; stream < 4; ++stream) {
                    check_kick_drift(rotation, exact, stream & 1, N, stream >> 1);  /* finite */
                    check_kick_drift(rotation, exact, stream & 1, 50, stream >> 1); /* 2nd block */
                    check_kick_drift(rotation, exact, stream & 1, 76, stream >> 1); /* last */
                }
    uniform_masses = 0;
}

/* Kept factors are those of the masses, h and g asked for: made again when one changes. */
static void test_factors_follow_their_inputs(void **unused)
{
    (void)unused;
    static state a;
    fill(&a, 7);
    const double g[3] = {0.0, 0.0, -9.81}, g2[3] = {0.0, 0.0, -1.62};
    const struct {
        uint64_t write;
        double h;
        const double *g;
    } cases[] = {{1, 1e-5, g}, {1, 1e-5, g}, {1, 2e-5, g}, {2, 2e-5, g}, {2, 2e-5, g2}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        if (c == 3) /* the masses written, under a new write generation */
            for (size_t i = 0; i < N; ++i)
                a.m[i] *= 1.5, a.j[i] *= 0.5;
        const sinter_verlet_factors *f = sinter_verlet_factors_for(
            ctx, &kept, N, a.m, a.j, 1, cases[c].write, cases[c].h, cases[c].g);
        assert_non_null(f);
        for (size_t i = 0; i < N; ++i)
            for (int d = 0; d < 3; ++d) {
                const size_t k = 3 * i + (size_t)d;
                const double fa = 0.5 * cases[c].h / a.m[i], fb = 0.5 * cases[c].h / a.j[i],
                             mg = 0.0 + a.m[i] * cases[c].g[d];
                assert_memory_equal(&f->fa[k], &fa, sizeof fa);
                assert_memory_equal(&f->fb[k], &fb, sizeof fb);
                assert_memory_equal(&f->mg[k], &mg, sizeof mg);
            }
    }
}

static void check_kick(void);

static void test_kick(void **unused)
{
    (void)unused;
    for (uniform_masses = 0; uniform_masses < 2; ++uniform_masses)
        check_kick();
    uniform_masses = 0;
}

static void check_kick(void)
{
    const double h = 1e-5;
    static state a, b;
    fill(&a, 11);
    a.f[3 * 40 + 2] = NAN, a.tq[3 * 70] = INFINITY; /* the first of the two is reported */
    b = a;
    const size_t lo = 5, hi = 71;
    for (size_t i = lo; i < hi; ++i)
        for (int d = 0; d < 3; ++d) {
            const size_t k = 3 * i + (size_t)d;
            a.v[k] = a.v[k] + 0.5 * h / a.m[i] * a.f[k];
            a.w[k] = a.w[k] + 0.5 * h / a.j[i] * a.tq[k];
        }
    const state b0 = b;
    for (int keep = 0; keep < 2; ++keep) {
        const double g[3] = {0.0, 0.0, 0.0};
        const sinter_verlet_factors *f =
            keep ? sinter_verlet_factors_for(ctx, &kept, N, b.m, b.j, 3,
                                             3 + (uint64_t)uniform_masses, h, g)
                 : NULL;
        assert_true(!keep || (f != NULL && f->uniform == uniform_masses));
        b = b0;
        assert_int_equal(sinter_verlet_kick(b.v, b.w, b.f, b.tq, b.m, b.j, f, h, lo, hi), 40);
        assert_memory_equal(b.v, a.v, sizeof a.v);
        assert_memory_equal(b.w, a.w, sizeof a.w);
        fill(&b, 11); /* all finite */
        assert_int_equal(sinter_verlet_kick(b.v, b.w, b.f, b.tq, b.m, b.j, f, h, lo, hi), hi);
    }
}

static int setup(void **unused)
{
    (void)unused;
    return sinter_ctx_create(&ctx, NULL) == SINTER_OK ? 0 : -1;
}

static int teardown(void **unused)
{
    (void)unused;
    sinter_verlet_factors_free(ctx, &kept);
    sinter_ctx_destroy(ctx);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kick_drift_every_variant),
        cmocka_unit_test(test_kick),
        cmocka_unit_test(test_factors_follow_their_inputs),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
