/*
 * The copper packing of the quasi-static stepper's id tests (test_qs_ids.c, test_qs_portable.c):
 * 23 spheres of copper (R = 25 um, 1293 K, seed 001 table 2) on a 3 x 3 x 2 lattice on the
 * principal planes, a triangle whose third link is made during the run and a floating pair, with
 * ids scrambled against their places; the stepper of a run over it (open_run), what a run leaves
 * (collect, by id and in link order) and the bit-for-bit comparison of two runs (assert_same).
 */
#ifndef SINTER_TEST_QS_COPPER_PACKING_H
#define SINTER_TEST_QS_COPPER_PACKING_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "scene_support.h"

enum { N = 23, LINKS_START = 35, LINKS_END = 37 };
static const double R = 25e-6, T_END = 100.0;

/* The layout, by place p: the lattice, the triangle and the pair. */
static void layout(double x[3 * N], double r[N])
{
    size_t n = 0;
    for (int i = 0; i < 3; ++i) /* the lattice, z fastest */
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 2; ++k) {
                x[3 * n] = (1 + 2 * i) * R;
                x[3 * n + 1] = (1 + 2 * j) * R;
                x[3 * n + 2] = (1 + 2 * k) * R;
                r[n++] = R;
            }
    /* the triangle (test_bonded.c's, moved 10 R along x) */
    const double rc = 0.6 * R, d = (R + rc) * (1.0 + 1e-4), h = sqrt(d * d - R * R);
    const double tri[9] = {11 * R, R, R, 13 * R, R, R, 12 * R, R + h, R};
    memcpy(x + 3 * n, tri, sizeof(tri));
    r[n] = r[n + 1] = R;
    r[n + 2] = rc;
    n += 3;
    /* the floating pair */
    const double a[3] = {20 * R, 20.3 * R, 20 * R}, dir[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
    for (int q = 0; q < 3; ++q) {
        x[3 * n + (size_t)q] = a[q];
        x[3 * n + 3 + (size_t)q] = a[q] + 2 * R * dir[q];
    }
    r[n] = r[n + 1] = R;
}

/* The id of place p: scrambled (7 p mod 23), so that no order of the positions (the spatial
 * sort's cells) is the order of the ids. */
static uint64_t id_of(size_t p)
{
    return (uint64_t)(7 * p % N);
}

/* The centre and radius of the particle of id k: x[3 k], r[k]. */
static void packing(double x[3 * N], double r[N])
{
    double xp[3 * N], rp[N];
    layout(xp, rp);
    for (size_t p = 0; p < N; ++p) {
        memcpy(x + 3 * id_of(p), xp + 3 * p, 3 * sizeof(double));
        r[id_of(p)] = rp[p];
    }
}

/* What a run leaves, by id and in link order. */
typedef struct outcome {
    double x[3 * (N + 1)], rot[3 * (N + 1)]; /* by id; id N: the particle added in a run */
    size_t links, links_first;
    uint64_t link_a[LINKS_END], link_b[LINKS_END];
    double neck[LINKS_END], approach[LINKS_END], fsint[LINKS_END];
    double stats[11];  /* neck mean, min, max, ratio; shrinkage (3); density; coordination; links,
                          PCG iterations */
    int ids_ascending; /* the ids were in ascending order in memory at the end */
} outcome;

/* The neck integration of the runs: 0 the defaults (strategy 3: young necks each in CVODE,
 * grown ones by RK4), 1 strategy 2 (per-pair RK4 sub-steps), 2 strategy 1 (one RK4 step for
 * all), 3 strategy 3 with every neck in CVODE batches (young and grown, shared steps). */
static int integration;

/* The stepper of a run: particles added in the order of the ids in `order` (NULL: by id),
 * sort_interval, threads. */
static void open_run(scene *s, const size_t *order, double sort_interval, int threads)
{
    scene_init(s);
    OK(sinter_ctx_set_threads(s->ctx, threads));
    scene_material(s, 72e9, 0.3, 8960, 0.0, 0.0); /* copper; neck data: the defaults */
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_QUASISTATIC, s->ps, NULL));
    OK(sinter_stepper_set_option(s->st, "sort_interval", sort_interval));
    if (integration == 1 || integration == 2)
        OK(sinter_stepper_set_option(s->st, "qs_strategy", integration == 1 ? 2.0 : 1.0));
    if (integration == 3) {
        OK(sinter_stepper_set_option(s->st, "qs_young_pairs", 0.0));
        OK(sinter_stepper_set_option(s->st, "qs_grown_rk4", 0.0));
    }
    double x[3 * N], r[N];
    packing(x, r);
    for (size_t k = 0; k < N; ++k) {
        const size_t p = order != NULL ? order[k] : k;
        const uint64_t id = p;
        OK(sinter_particles_add_with_ids(s->ps, 1, &id, x + 3 * p, r + p, 0, 1293.0, NULL));
    }
}

static void collect(scene *s, outcome *out)
{
    memset(out, 0, sizeof(*out));
    size_t n = 0;
    const uint64_t *id = NULL;
    const double *x = NULL, *rot = NULL;
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_ID, (const void **)&id, &n, NULL));
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_ROTATION, (const void **)&rot, NULL, NULL));
    assert_true(n <= N);
    out->ids_ascending = 1;
    for (size_t i = 0; i < n; ++i) {
        assert_true(id[i] <= N);
        memcpy(out->x + 3 * id[i], x + 3 * i, 3 * sizeof(double));
        memcpy(out->rot + 3 * id[i], rot + 3 * i, 3 * sizeof(double));
        if (i > 0 && id[i] < id[i - 1])
            out->ids_ascending = 0;
    }
    OK(sinter_particles_release(s->ps, SINTER_FIELD_ID));
    OK(sinter_particles_release(s->ps, SINTER_FIELD_POSITION));
    OK(sinter_particles_release(s->ps, SINTER_FIELD_ROTATION));
    sinter_snapshot *snap = NULL;
    OK(sinter_snapshot_create(&snap, s->st));
    OK(sinter_snapshot_counts(snap, NULL, NULL, &out->links, NULL));
    assert_true(out->links <= LINKS_END);
    const size_t m = out->links;
    const void *data = NULL;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &data, NULL, NULL, NULL));
    memcpy(out->link_a, data, m * sizeof(uint64_t));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &data, NULL, NULL, NULL));
    memcpy(out->link_b, data, m * sizeof(uint64_t));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &data, NULL, NULL, NULL));
    memcpy(out->neck, data, m * sizeof(double));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &data, NULL, NULL, NULL));
    memcpy(out->approach, data, m * sizeof(double));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_SINTERING_FORCE, &data, NULL, NULL, NULL));
    memcpy(out->fsint, data, m * sizeof(double));
    sinter_snapshot_destroy(snap);
    sinter_sintering_stats st;
    memset(&st, 0, sizeof(st));
    st.struct_size = sizeof(st);
    OK(sinter_stepper_sintering_stats(s->st, &st));
    const double v[11] = {st.neck_mean,
                          st.neck_min,
                          st.neck_max,
                          st.neck_ratio_mean,
                          st.shrinkage[0],
                          st.shrinkage[1],
                          st.shrinkage[2],
                          st.relative_density,
                          st.coordination,
                          (double)st.links,
                          (double)st.pcg_iterations};
    memcpy(out->stats, v, sizeof(v));
}

/* A permutation of the N particles: every third from the end, then the rest reversed. */
static void shuffled(size_t order[N])
{
    unsigned char used[N] = {0};
    size_t k = 0;
    for (size_t p = N; p-- > 0;)
        if (p % 3 == 1) {
            order[k++] = p;
            used[p] = 1;
        }
    for (size_t p = N; p-- > 0;)
        if (!used[p])
            order[k++] = p;
    assert_int_equal(k, N);
}

static void assert_same(const outcome *a, const outcome *b)
{
    assert_memory_equal(a->x, b->x, sizeof(a->x));
    assert_memory_equal(a->rot, b->rot, sizeof(a->rot));
    assert_int_equal(a->links, b->links);
    assert_int_equal(a->links_first, b->links_first);
    assert_memory_equal(a->link_a, b->link_a, sizeof(a->link_a));
    assert_memory_equal(a->link_b, b->link_b, sizeof(a->link_b));
    assert_memory_equal(a->neck, b->neck, sizeof(a->neck));
    assert_memory_equal(a->approach, b->approach, sizeof(a->approach));
    assert_memory_equal(a->fsint, b->fsint, sizeof(a->fsint));
    assert_memory_equal(a->stats, b->stats, sizeof(a->stats));
}

#endif
