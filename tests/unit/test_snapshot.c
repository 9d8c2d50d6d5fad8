/*
 * Snapshots of contacts and links (sinter_snapshot_create, issue 37). Each check fails when
 * its quantity is wrong:
 *  - a pile of frictional, damped spheres in a box pressed by a moving lid: the contacts'
 *    forces summed per wall give the wall reactions (sinter_walls_get_force), and summed per
 *    particle with gravity the particles' forces -- normal and tangential parts, with the
 *    half-step velocities the explicit step's law saw;
 *  - with conduction from hot walls: the contacts' heat flows, antisymmetric between the two
 *    particles of a pair, summed per particle give the particles' heat input;
 *  - with the "network" electric model: the contact currents balance at every particle
 *    (Kirchhoff) and those into the wall held at the higher potential sum to those out of
 *    the other;
 *  - the quasi-static stepper: one link record per link of the sintering statistics, with
 *    their neck ratio mean;
 *  - a scene run: the last sample of series.csv has, for each wall, the force and the heat
 *    flow that the snapshot's wall contacts sum to, and the coordination histogram of the
 *    snapshot's pair contacts; a quasi-static run's neck ratio histogram counts the snapshot's
 *    links in their bins;
 *  - taking snapshots does not change the run (bit for bit), a stale state and bad arguments
 *    are refused, and an allocation failure at any point leaks nothing.
 */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "scene_support.h"

static const double G = 9.81;

/* A 4 x 4 x 3 lattice of spheres (r = 1 mm, slightly jittered) in a box of six walls, the lid
 * moving down at 5 mm/s; gravity 2 seeds m g. */
static void pile(scene *s, int heat, int electric, sinter_heat_model **cond,
                 sinter_electric_model **em)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.4);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 10.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e3));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 10.0));
    scene_open(s, "hertz_mindlin", 2);
    const double r = 1e-3, L = 8e-3;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i)
                scene_add(s, (2 * i + 1) * r + 1e-5 * ((i + 2 * j + k) % 3),
                          (2 * j + 1) * r + 1e-5 * ((2 * i + j) % 3), (2 * k + 1) * r * 0.999, r);
    const double pts[6][3] = {{0, 0, 0}, {0, 0, 6.1e-3}, {0, 0, 0},
                              {L, 0, 0}, {0, 0, 0},      {0, L, 0}};
    const double nrm[6][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int w = 0; w < 6; ++w) {
        OK(sinter_walls_add_plane(s->walls, pts[w], nrm[w], s->wall_mat, NULL));
        if (heat)
            OK(sinter_walls_set_temperature(s->walls, (size_t)w, w == 0 ? 400.0 : 300.0));
    }
    const double lid[3] = {0, 0, -5e-3};
    OK(sinter_walls_set_velocity(s->walls, 1, lid));
    if (heat) {
        OK(sinter_heat_model_create(cond, s->ctx, "conduction"));
        OK(sinter_stepper_add_heat(s->st, *cond));
    }
    if (electric) {
        OK(sinter_walls_set_electric(s->walls, 0, SINTER_WALL_POTENTIAL, 0.0));
        OK(sinter_walls_set_electric(s->walls, 1, SINTER_WALL_POTENTIAL, 1.0));
        OK(sinter_electric_model_create(em, s->ctx, "network"));
        OK(sinter_stepper_set_electric(s->st, *em));
    }
    OK(sinter_stepper_set_dt(s->st, 2e-6));
    OK(sinter_stepper_set_skin(s->st, 2e-4));
}

/* Close a pile with its heat or electric model (after its stepper, before its context). */
static void close_with(scene *s, sinter_heat_model *hm, sinter_electric_model *em)
{
    sinter_stepper_destroy(s->st);
    s->st = NULL;
    sinter_heat_model_destroy(hm);
    sinter_electric_model_destroy(em);
    scene_close(s);
}

/* The snapshot's array q as doubles (count records of `comp`). */
static const double *contact_doubles(const sinter_snapshot *snap, sinter_contact_data q,
                                     size_t comp)
{
    const void *data = NULL;
    size_t count = 0, components = 0;
    sinter_dtype dtype = SINTER_DTYPE_UINT32;
    OK(sinter_snapshot_contacts(snap, q, &data, &count, &components, &dtype));
    assert_int_equal(components, comp);
    assert_int_equal(dtype, SINTER_DTYPE_DOUBLE);
    return data;
}

/* The snapshot's particle ids (a, b) and wall indices. */
static void contact_ids(const sinter_snapshot *snap, const uint64_t **ida, const uint64_t **idb,
                        const int32_t **wall)
{
    const void *pa = NULL, *pb = NULL, *pw = NULL;
    OK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_A, &pa, NULL, NULL, NULL));
    OK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_B, &pb, NULL, NULL, NULL));
    OK(sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_WALL, &pw, NULL, NULL, NULL));
    *ida = pa;
    *idb = pb;
    *wall = pw;
}

/* Index of particle id `id` in the set. */
static size_t index_of(const sinter_particles *ps, uint64_t id)
{
    size_t k = 0;
    OK(sinter_particles_find_id(ps, id, &k));
    return k;
}

static void test_forces_sum_to_walls_and_particles(void **state)
{
    (void)state;
    scene s;
    pile(&s, 0, 0, NULL, NULL);
    OK(sinter_stepper_advance(s.st, 0.04)); /* settled, the lid on the pile */
    sinter_snapshot *snap = NULL;
    OK(sinter_snapshot_create(&snap, s.st));
    size_t np = 0, nw = 0, nl = 0, n = 0;
    double t = 0.0;
    OK(sinter_snapshot_counts(snap, &np, &nw, &nl, &t));
    OK(sinter_particles_count(s.ps, &n));
    assert_true(np > 50);
    assert_true(nw > 20);
    assert_int_equal(nl, 0);
    assert_close(t, 0.04, 1e-12);
    const uint64_t *ida = NULL, *idb = NULL;
    const int32_t *wall = NULL;
    contact_ids(snap, &ida, &idb, &wall);
    const double *normal = contact_doubles(snap, SINTER_CONTACT_DATA_NORMAL, 3);
    const double *fn = contact_doubles(snap, SINTER_CONTACT_DATA_NORMAL_FORCE, 1);
    const double *ft = contact_doubles(snap, SINTER_CONTACT_DATA_TANGENTIAL_FORCE, 3);
    const double *overlap = contact_doubles(snap, SINTER_CONTACT_DATA_OVERLAP, 1);
    const double *radius = contact_doubles(snap, SINTER_CONTACT_DATA_RADIUS, 1);
    const double *area = contact_doubles(snap, SINTER_CONTACT_DATA_AREA, 1);
    double *sum = calloc(3 * n, sizeof(double)), wall_sum[18] = {0}, ft_max = 0.0;
    for (size_t q = 0; q < np + nw; ++q) {
        assert_true(overlap[q] > 0.0);
        assert_true(fn[q] > 0.0);
        assert_close(area[q], 3.14159265358979 * radius[q] * radius[q], 1e-12 * area[q]);
        const size_t a = index_of(s.ps, ida[q]);
        double f[3], tdotn = 0.0;
        for (int d = 0; d < 3; ++d) {
            f[d] = ft[3 * q + d] - fn[q] * normal[3 * q + d];
            tdotn += ft[3 * q + d] * normal[3 * q + d];
            sum[3 * a + d] += f[d];
        }
        assert_close(tdotn, 0.0, 1e-9 * fn[q]);
        ft_max = fmax(ft_max, sqrt(ft[3 * q] * ft[3 * q] + ft[3 * q + 1] * ft[3 * q + 1] +
                                   ft[3 * q + 2] * ft[3 * q + 2]));
        if (q < np) {
            assert_int_equal(wall[q], -1);
            const size_t b = index_of(s.ps, idb[q]);
            for (int d = 0; d < 3; ++d)
                sum[3 * b + d] -= f[d];
        } else {
            assert_true(wall[q] >= 0 && wall[q] < 6);
            assert_true(idb[q] == UINT64_MAX);
            for (int d = 0; d < 3; ++d)
                wall_sum[3 * wall[q] + d] -= f[d];
        }
    }
    assert_true(ft_max > 0.0); /* friction carries something */
    /* per wall: the reactions of the last step */
    double scale = 0.0;
    for (size_t w = 0; w < 6; ++w) {
        double rf[3];
        OK(sinter_walls_get_force(s.walls, w, rf));
        for (int d = 0; d < 3; ++d)
            scale = fmax(scale, fabs(rf[d]));
    }
    assert_true(scale > 0.0);
    for (size_t w = 0; w < 6; ++w) {
        double rf[3];
        OK(sinter_walls_get_force(s.walls, w, rf));
        for (int d = 0; d < 3; ++d)
            assert_close(wall_sum[3 * w + d], rf[d], 1e-9 * scale);
    }
    /* per particle: contacts plus m g give the evaluated force */
    const double *force = NULL, *mass = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_FORCE, (const void **)&force, NULL, NULL));
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_MASS, (const void **)&mass, NULL, NULL));
    for (size_t i = 0; i < n; ++i) {
        sum[3 * i + 2] -= mass[i] * G;
        for (int d = 0; d < 3; ++d)
            assert_close(sum[3 * i + d], force[3 * i + d], 1e-9 * scale);
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_FORCE));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_MASS));
    /* no link data on an explicit stepper; the arrays are empty */
    const void *links = &links;
    size_t count = 7;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &links, &count, NULL, NULL));
    assert_null(links);
    assert_int_equal(count, 0);
    /* the current is NaN without a network model, the heat flow 0 without conduction */
    const double *current = contact_doubles(snap, SINTER_CONTACT_DATA_CURRENT, 1);
    const double *heat = contact_doubles(snap, SINTER_CONTACT_DATA_HEAT_FLOW, 1);
    assert_true(isnan(current[0]));
    assert_close(heat[0], 0.0, 0.0);
    free(sum);
    sinter_snapshot_destroy(snap);
    scene_close(&s);
}

/* What the tests read of a pile advanced to time t: its snapshot, contacts and particles. */
typedef struct taken {
    sinter_snapshot *snap;
    size_t np, nw, n; /* pair contacts, wall contacts, particles */
    const uint64_t *ida, *idb;
    const int32_t *wall;
} taken;

static taken take(scene *s, double t)
{
    taken k;
    memset(&k, 0, sizeof(k));
    OK(sinter_stepper_advance(s->st, t));
    OK(sinter_snapshot_create(&k.snap, s->st));
    OK(sinter_snapshot_counts(k.snap, &k.np, &k.nw, NULL, NULL));
    OK(sinter_particles_count(s->ps, &k.n));
    contact_ids(k.snap, &k.ida, &k.idb, &k.wall);
    return k;
}

static void test_heat_flows_balance(void **state)
{
    (void)state;
    scene s;
    sinter_heat_model *cond = NULL;
    pile(&s, 1, 0, &cond, NULL);
    const taken k = take(&s, 0.02);
    sinter_snapshot *snap = k.snap;
    const size_t np = k.np, nw = k.nw, n = k.n;
    const uint64_t *ida = k.ida, *idb = k.idb;
    const double *q_flow = contact_doubles(snap, SINTER_CONTACT_DATA_HEAT_FLOW, 1);
    double *sum = calloc(n, sizeof(double)), pair_total = 0.0, wall_total = 0.0, scale = 0.0;
    for (size_t q = 0; q < np + nw; ++q) {
        sum[index_of(s.ps, ida[q])] += q_flow[q];
        if (q < np) {
            sum[index_of(s.ps, idb[q])] -= q_flow[q]; /* antisymmetric: -Q into b */
            pair_total += q_flow[q] - q_flow[q];
        } else {
            wall_total += q_flow[q];
        }
        scale = fmax(scale, fabs(q_flow[q]));
    }
    assert_true(scale > 0.0);
    assert_true(wall_total > 0.0); /* the hot floor heats the pile */
    const double *heat = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_HEAT, (const void **)&heat, NULL, NULL));
    double heat_total = 0.0;
    for (size_t i = 0; i < n; ++i) {
        assert_close(sum[i], heat[i], 1e-9 * scale);
        heat_total += heat[i];
    }
    /* what the particles gain in all comes through the walls */
    assert_close(heat_total, wall_total + pair_total, 1e-9 * scale);
    OK(sinter_particles_release(s.ps, SINTER_FIELD_HEAT));
    free(sum);
    sinter_snapshot_destroy(snap);
    close_with(&s, cond, NULL);
}

/* Kirchhoff at every particle from the snapshot's contact currents, and the lid's current equal
 * to the power the model reports over the lid's 1 V. With eq50, the conductivities follow seed
 * 000 eq. 50's temperature term over particles at different temperatures: the snapshot must use
 * the solve's conductances (it once used sigma_0, which broke both checks). */
static void currents_balance(int eq50)
{
    scene s;
    sinter_electric_model *em = NULL;
    pile(&s, 0, 1, NULL, &em);
    if (eq50) {
        OK(sinter_electric_model_set(em, "sigmoid", 1));
        OK(sinter_electric_model_set(em, "k1", -0.8));
        OK(sinter_electric_model_set(em, "gamma1", 0.02));
        OK(sinter_electric_model_set(em, "theta_ref", 350));
        double *theta = NULL;
        size_t n = 0;
        OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&theta, &n, NULL));
        for (size_t i = 0; i < n; ++i)
            theta[i] = 300.0 + 10.0 * (double)i;
        OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE));
    }
    const taken k = take(&s, 0.04);
    sinter_snapshot *snap = k.snap;
    const size_t np = k.np, nw = k.nw, n = k.n;
    const uint64_t *ida = k.ida, *idb = k.idb;
    const int32_t *wall = k.wall;
    const double *current = contact_doubles(snap, SINTER_CONTACT_DATA_CURRENT, 1);
    double *net = calloc(n, sizeof(double)), into[6] = {0}, scale = 0.0;
    for (size_t q = 0; q < np + nw; ++q) {
        assert_false(isnan(current[q]));
        net[index_of(s.ps, ida[q])] -= current[q]; /* out of a */
        if (q < np)
            net[index_of(s.ps, idb[q])] += current[q];
        else
            into[wall[q]] += current[q];
        scale = fmax(scale, fabs(current[q]));
    }
    assert_true(scale > 0.0);
    for (size_t i = 0; i < n; ++i)
        assert_close(net[i], 0.0, 1e-6 * scale); /* Kirchhoff, to the solver's tolerance */
    assert_true(into[0] > 0.0);                  /* from the 1 V lid to the 0 V floor */
    assert_close(into[0], -into[1], 1e-6 * scale);
    double supplied = 0.0, dissipated = 0.0;
    OK(sinter_electric_model_power(em, &supplied, &dissipated));
    assert_close(-into[1], supplied / 1.0, 1e-6 * supplied); /* P = V I at the 1 V lid */
    free(net);
    sinter_snapshot_destroy(snap);
    close_with(&s, NULL, em);
}

static void test_currents_balance(void **state)
{
    (void)state;
    currents_balance(0);
}

static void test_currents_balance_eq50(void **state)
{
    (void)state;
    currents_balance(1);
}

/* Two identical runs, one taking a snapshot after every few steps: the same bits. */
static void test_snapshots_change_nothing(void **state)
{
    (void)state;
    scene a, b;
    sinter_heat_model *ca = NULL, *cb = NULL;
    pile(&a, 1, 0, &ca, NULL);
    pile(&b, 1, 0, &cb, NULL);
    for (int k = 0; k < 20; ++k) {
        OK(sinter_stepper_step(a.st, 50));
        OK(sinter_stepper_step(b.st, 50));
        sinter_snapshot *snap = NULL;
        OK(sinter_snapshot_create(&snap, b.st));
        sinter_snapshot_destroy(snap);
    }
    size_t n = 0;
    OK(sinter_particles_count(a.ps, &n));
    const sinter_field fields[] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,
                                   SINTER_FIELD_TEMPERATURE, SINTER_FIELD_FORCE};
    for (size_t f = 0; f < sizeof(fields) / sizeof(fields[0]); ++f) {
        const void *xa = NULL, *xb = NULL;
        size_t comp = 0;
        OK(sinter_particles_view_read(a.ps, fields[f], &xa, NULL, &comp));
        OK(sinter_particles_view_read(b.ps, fields[f], &xb, NULL, NULL));
        assert_memory_equal(xa, xb, n * comp * sizeof(double));
        OK(sinter_particles_release(a.ps, fields[f]));
        OK(sinter_particles_release(b.ps, fields[f]));
    }
    close_with(&a, ca, NULL);
    close_with(&b, cb, NULL);
}

static void test_refusals(void **state)
{
    (void)state;
    scene s;
    pile(&s, 0, 0, NULL, NULL);
    sinter_snapshot *snap = NULL;
    /* before the first step: nothing evaluated */
    assert_int_equal(sinter_snapshot_create(&snap, s.st), SINTER_ERR_STATE);
    assert_null(snap);
    assert_int_equal(sinter_snapshot_create(NULL, s.st), SINTER_ERR_NULL);
    assert_int_equal(sinter_snapshot_create(&snap, NULL), SINTER_ERR_NULL);
    OK(sinter_stepper_step(s.st, 10));
    OK(sinter_snapshot_create(&snap, s.st));
    const void *data = NULL;
    assert_int_equal(
        sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_COUNT_, &data, NULL, NULL, NULL),
        SINTER_ERR_RANGE);
    assert_int_equal(
        sinter_snapshot_contacts(snap, (sinter_contact_data)-1, &data, NULL, NULL, NULL),
        SINTER_ERR_RANGE);
    assert_int_equal(sinter_snapshot_links(snap, SINTER_LINK_DATA_COUNT_, &data, NULL, NULL, NULL),
                     SINTER_ERR_RANGE);
    assert_int_equal(
        sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_AREA, NULL, NULL, NULL, NULL),
        SINTER_ERR_NULL);
    assert_int_equal(
        sinter_snapshot_contacts(NULL, SINTER_CONTACT_DATA_AREA, &data, NULL, NULL, NULL),
        SINTER_ERR_NULL);
    assert_int_equal(sinter_snapshot_counts(NULL, NULL, NULL, NULL, NULL), SINTER_ERR_NULL);
    sinter_snapshot_destroy(snap);
    sinter_snapshot_destroy(NULL);
    /* the host wrote the state: the contact lists are stale */
    void *x = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_POSITION, &x, NULL, NULL));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    snap = NULL;
    assert_int_equal(sinter_snapshot_create(&snap, s.st), SINTER_ERR_STATE);
    assert_null(snap);
    OK(sinter_stepper_step(s.st, 0)); /* evaluates the state again */
    OK(sinter_snapshot_create(&snap, s.st));
    sinter_snapshot_destroy(snap);
    /* sorted: indices changed */
    OK(sinter_particles_sort_spatial(s.ps));
    assert_int_equal(sinter_snapshot_create(&snap, s.st), SINTER_ERR_STATE);
    scene_close(&s);
}

static void test_allocation_failures(void **state)
{
    (void)state;
    for (long fail = 0;; ++fail) {
        counting_allocator c = {0, 0, -1, 0};
        sinter_allocator hook = counting_allocator_hook(&c);
        scene s;
        memset(&s, 0, sizeof(s));
        OK(sinter_ctx_create(&s.ctx, &hook));
        scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.4);
        scene_open(&s, "hertz_mindlin", 2);
        scene_add(&s, 0, 0, 0.99e-3, 1e-3);
        scene_add(&s, 0, 0, 2.98e-3, 1e-3);
        const double p[3] = {0, 0, 0}, nrm[3] = {0, 0, 1};
        OK(sinter_walls_add_plane(s.walls, p, nrm, s.wall_mat, NULL));
        OK(sinter_stepper_set_dt(s.st, 1e-6));
        OK(sinter_stepper_step(s.st, 5));
        c.fail_after = fail;
        c.calls = 0;
        sinter_snapshot *snap = NULL;
        const sinter_status st = sinter_snapshot_create(&snap, s.st);
        c.fail_after = -1;
        if (st == SINTER_OK) {
            size_t np = 0, nw = 0;
            OK(sinter_snapshot_counts(snap, &np, &nw, NULL, NULL));
            assert_int_equal(np, 1);
            assert_int_equal(nw, 1);
            sinter_snapshot_destroy(snap);
        } else {
            assert_int_equal(st, SINTER_ERR_NOMEM);
            assert_null(snap);
        }
        scene_close(&s);
        assert_int_equal(c.allocations, c.frees);
        if (st == SINTER_OK)
            break;
    }
}

static void test_links_match_statistics(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double r = 25e-6;
    scene_material(&s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, NULL));
    /* a chain of three touching spheres and one apart: two links */
    const double p[12] = {0, 0, 0, 2 * r, 0, 0, 4 * r, 0, 0, 10 * r, 0, 0};
    const double rad[4] = {r, r, r, r};
    OK(sinter_particles_add(s.ps, 4, p, rad, 0, 1293.0, NULL));
    sinter_snapshot *snap = NULL;
    assert_int_equal(sinter_snapshot_create(&snap, s.st), SINTER_ERR_STATE);
    OK(sinter_stepper_advance(s.st, 100.0));
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_sintering_stats(s.st, &stats));
    OK(sinter_snapshot_create(&snap, s.st));
    size_t np = 9, nw = 9, nl = 0;
    OK(sinter_snapshot_counts(snap, &np, &nw, &nl, NULL));
    assert_int_equal(np, 0);
    assert_int_equal(nw, 0);
    assert_int_equal(nl, stats.links);
    assert_int_equal(nl, 2);
    const void *data = NULL;
    size_t count = 0, comp = 0;
    sinter_dtype dtype;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RATIO, &data, &count, &comp, &dtype));
    assert_int_equal(count, 2);
    assert_int_equal(comp, 1);
    assert_int_equal(dtype, SINTER_DTYPE_DOUBLE);
    const double *ratio = data;
    assert_close(0.5 * (ratio[0] + ratio[1]), stats.neck_ratio_mean, 1e-12);
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &data, NULL, NULL, NULL));
    const double *neck = data;
    assert_close(neck[0], ratio[0] * r, 1e-15);
    assert_true(stats.neck_min <= neck[0] && neck[0] <= stats.neck_max);
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &data, NULL, NULL, NULL));
    const double *approach = data;
    assert_true(approach[0] > 0.0 && approach[0] < 0.1 * r);
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &data, NULL, NULL, &dtype));
    assert_int_equal(dtype, SINTER_DTYPE_UINT64);
    const uint64_t *ida = data;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &data, NULL, NULL, NULL));
    const uint64_t *idb = data;
    for (size_t k = 0; k < 2; ++k)
        assert_true(idb[k] == ida[k] + 1 && idb[k] <= 2); /* the chain's neighbours */
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_SINTERING_FORCE, &data, NULL, NULL, NULL));
    const double *fs = data;
    assert_true(fs[0] > 0.0); /* the pair is pulled together */
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_PHASE, &data, NULL, NULL, &dtype));
    assert_int_equal(dtype, SINTER_DTYPE_INT32);
    assert_int_equal(((const int32_t *)data)[0], 0);
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_BEAM_FORCE, &data, NULL, &comp, NULL));
    assert_int_equal(comp, 3);
    assert_false(isnan(((const double *)data)[0]));
    sinter_snapshot_destroy(snap);
    scene_close(&s);
}

/* A lattice of glass spheres dropped into a box on a 500 K floor, with conduction. */
static const char *SCENE =
    "[scene]\nname = snapshot_box\nunits = SI\n"
    "[material glass]\ndensity = 2500\nyoungs_modulus = 1e7\npoisson_ratio = 0.3\n"
    "damping_ratio = 0.2\nfriction_static = 0.3\nfriction_dynamic = 0.3\n"
    "thermal_conductivity = 100\nheat_capacity = 100\n"
    "[particles]\nmethod = lattice\nmaterial = glass\nbox_min = 0 0 0.0002\n"
    "box_max = 0.0035 0.0035 0.003\nradius = 0.0005\nspacing = 0.00105\ntemperature = 300\n"
    "[wall floor]\npoint = 0 0 0\nnormal = 0 0 1\nmaterial = glass\ntemperature = 500\n"
    "[wall x_low]\npoint = -0.0001 0 0\nnormal = 1 0 0\nmaterial = glass\ntemperature = 300\n"
    "[wall x_high]\npoint = 0.0036 0 0\nnormal = -1 0 0\nmaterial = glass\n"
    "temperature = 300\n"
    "[force hertz_mindlin]\n[force gravity]\n[heat conduction]\n"
    "[stepper]\ndt = 1e-5\nskin = 1e-4\nend_time = 0.03\n[output]\ninterval = 0.01\n"
    "distributions = yes\n";

/* Column `name` of the last row of the CSV file at `path`. */
static double last_value(const char *path, const char *name)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char header[4096], line[4096], last[4096] = "";
    assert_non_null(fgets(header, sizeof(header), f));
    while (fgets(line, sizeof(line), f) != NULL)
        memcpy(last, line, sizeof(line));
    fclose(f);
    int column = -1, k = 0;
    for (char *save = NULL, *tok = strtok_r(header, ",\n", &save); tok != NULL;
         tok = strtok_r(NULL, ",\n", &save), ++k)
        if (strcmp(tok, name) == 0)
            column = k;
    assert_true(column >= 0);
    char *p = last;
    for (k = 0; k < column; ++k)
        p = strchr(p, ',') + 1;
    return strtod(p, NULL);
}

/* A scene file's text run in a fresh directory, and its snapshot at the end. */
typedef struct ran {
    char dir[32];
    char csv[128]; /* its series.csv */
    sinter_ctx *ctx;
    sinter_scene *sc;
    sinter_snapshot *snap;
} ran;

static void run_text(ran *r, const char *text)
{
    char path[96], out[64];
    snprintf(r->dir, sizeof(r->dir), "/tmp/sinter_snapshot_XXXXXX");
    assert_non_null(mkdtemp(r->dir));
    snprintf(path, sizeof(path), "%s/run.scene", r->dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    snprintf(out, sizeof(out), "%s/out", r->dir);
    snprintf(r->csv, sizeof(r->csv), "%s/series.csv", out);
    OK(sinter_ctx_create(&r->ctx, NULL));
    OK(sinter_scene_load(&r->sc, r->ctx, path));
    OK(sinter_scene_run(r->sc, out, NULL, NULL));
    sinter_stepper *st = NULL;
    OK(sinter_scene_get_stepper(r->sc, &st));
    OK(sinter_snapshot_create(&r->snap, st));
}

static void ran_close(ran *r)
{
    sinter_snapshot_destroy(r->snap);
    sinter_scene_destroy(r->sc);
    sinter_ctx_destroy(r->ctx);
    char cmd[96];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", r->dir);
    assert_int_equal(system(cmd), 0);
}

static void test_series_walls_match_contacts(void **state)
{
    (void)state;
    ran r;
    run_text(&r, SCENE);
    sinter_scene *sc = r.sc;
    sinter_snapshot *snap = r.snap;
    const char *path = r.csv;
    sinter_walls *walls = NULL;
    OK(sinter_scene_get_walls(sc, &walls));
    size_t np = 0, nw = 0;
    OK(sinter_snapshot_counts(snap, &np, &nw, NULL, NULL));
    assert_true(nw > 0);
    const uint64_t *ida = NULL, *idb = NULL;
    const int32_t *wall = NULL;
    contact_ids(snap, &ida, &idb, &wall);
    const double *normal = contact_doubles(snap, SINTER_CONTACT_DATA_NORMAL, 3);
    const double *fn = contact_doubles(snap, SINTER_CONTACT_DATA_NORMAL_FORCE, 1);
    const double *ft = contact_doubles(snap, SINTER_CONTACT_DATA_TANGENTIAL_FORCE, 3);
    const double *heat = contact_doubles(snap, SINTER_CONTACT_DATA_HEAT_FLOW, 1);
    double push[3] = {0}, flow[3] = {0};
    for (size_t q = np; q < np + nw; ++q) {
        double n_wall[3], f_on_wall[3];
        OK(sinter_walls_get_normal(walls, (size_t)wall[q], n_wall));
        for (int d = 0; d < 3; ++d)
            f_on_wall[d] = -(ft[3 * q + d] - fn[q] * normal[3 * q + d]);
        /* the series' wall force: pushing the wall outwards, against its normal */
        push[wall[q]] -=
            f_on_wall[0] * n_wall[0] + f_on_wall[1] * n_wall[1] + f_on_wall[2] * n_wall[2];
        flow[wall[q]] += heat[q];
    }
    const char *names[3] = {"floor", "x_low", "x_high"};
    const double weight = last_value(path, "floor force [N]");
    assert_true(weight > 0.0);
    assert_true(flow[0] > 0.0); /* the hot floor heats the spheres */
    for (int w = 0; w < 3; ++w) {
        char column[64];
        snprintf(column, sizeof(column), "%s force [N]", names[w]);
        assert_close(push[w], last_value(path, column), 1e-9 * weight);
        snprintf(column, sizeof(column), "%s heat flow [W]", names[w]);
        assert_close(flow[w], last_value(path, column), 1e-12 * fabs(flow[0]) + 1e-300);
    }
    /* the coordination histogram: particles by their number of pair contacts */
    size_t n = 0;
    sinter_particles *ps = NULL;
    OK(sinter_scene_get_particles(sc, &ps));
    OK(sinter_particles_count(ps, &n));
    size_t *per = calloc(n, sizeof(size_t)), hist[14] = {0};
    for (size_t q = 0; q < np; ++q) {
        per[index_of(ps, ida[q])]++;
        per[index_of(ps, idb[q])]++;
    }
    for (size_t i = 0; i < n; ++i)
        hist[per[i] < 13 ? per[i] : 13]++;
    double particles = 0.0, ends = 0.0;
    for (size_t k = 0; k < 14; ++k) {
        char column[64];
        if (k < 13)
            snprintf(column, sizeof(column), "coordination %zu [1]", k);
        else
            snprintf(column, sizeof(column), "coordination 13 or more [1]");
        const double count = last_value(path, column);
        assert_close(count, (double)hist[k], 0.0);
        particles += count;
        ends += (double)k * count;
    }
    assert_close(particles, (double)n, 0.0);
    assert_close(ends, 2.0 * last_value(path, "contacts [1]"), 0.0);
    assert_true(ends > 0.0);
    free(per);
    assert_close(last_value(path, "time step [s]"), 1e-5, 0.0);
    assert_true(last_value(path, "neighbour rebuilds [1]") >= 1.0);
    ran_close(&r);
}

/* 27 copper spheres on a lattice sintered by the quasi-static stepper, with the histograms. */
static const char *QS_SCENE =
    "[scene]\nname = qs_lattice\nunits = SI\n"
    "[material copper]\ndensity = 8960\nyoungs_modulus = 72e9\npoisson_ratio = 0.3\n"
    "[particles]\nmethod = lattice\nmaterial = copper\nbox_min = 0 0 0\n"
    "box_max = 0.000151 0.000151 0.000151\nradius = 25e-6\nspacing = 50e-6\n"
    "temperature = 1293\n"
    "[stepper]\nkind = quasistatic\ndt = 1e-6\nend_time = 200\n"
    "[output]\ninterval = 100\nvtu = no\ndistributions = yes\n";

/* The neck ratio histogram of series.csv: one count per link of the snapshot, in its bin. */
static void test_neck_histogram_counts_links(void **state)
{
    (void)state;
    ran r;
    run_text(&r, QS_SCENE);
    sinter_snapshot *snap = r.snap;
    const char *path = r.csv;
    size_t links = 0;
    OK(sinter_snapshot_counts(snap, NULL, NULL, &links, NULL));
    const void *data = NULL;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RATIO, &data, NULL, NULL, NULL));
    const double *ratio = data;
    double bins[11] = {0};
    for (size_t k = 0; k < links; ++k) {
        const double b = floor(ratio[k] / 0.05);
        bins[b >= 0 && b < 10 ? (size_t)b : 10] += 1.0;
    }
    assert_close(last_value(path, "links [1]"), (double)links, 0.0);
    assert_true(links == 54);
    double total = 0.0;
    for (int k = 0; k <= 10; ++k) {
        char column[64];
        if (k < 10)
            snprintf(column, sizeof(column), "neck ratio %.2f-%.2f [1]", 0.05 * k, 0.05 * (k + 1));
        else
            snprintf(column, sizeof(column), "neck ratio 0.50 or more [1]");
        assert_close(last_value(path, column), bins[k], 0.0);
        total += bins[k];
    }
    assert_close(total, (double)links, 0.0);
    /* eq. 44's corrections: one count per link; the lattice shrinks as free pairs, so every
     * link's correction is round-off against its own approach (|r| < 1e-6: the two middle
     * bins), and the snapshot's corrections are so against the links' approach */
    const void *corr = NULL;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_CORRECTION, &corr, NULL, NULL, NULL));
    const void *approach = NULL;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &approach, NULL, NULL, NULL));
    for (size_t k = 0; k < links; ++k)
        assert_true(fabs(((const double *)corr)[k]) < 1e-9 * ((const double *)approach)[k]);
    double middle = 0.0, all = 0.0;
    for (int k = -1; k <= 10; ++k) {
        char column[64];
        if (k < 0)
            snprintf(column, sizeof(column), "correction below -1.25 [1]");
        else if (k < 10)
            snprintf(column, sizeof(column), "correction %.2f to %.2f [1]", -1.25 + 0.25 * k,
                     -1.25 + 0.25 * (k + 1));
        else
            snprintf(column, sizeof(column), "correction 1.25 or more [1]");
        const double v = last_value(path, column);
        all += v;
        middle += k == 4 || k == 5 ? v : 0.0;
    }
    assert_close(all, (double)links, 0.0);
    assert_close(middle, (double)links, 0.0);
    /* every particle of the lattice: 3 to 6 links */
    assert_close(last_value(path, "coordination 3 [1]"), 8.0, 0.0);
    assert_close(last_value(path, "coordination 6 [1]"), 1.0, 0.0);
    ran_close(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forces_sum_to_walls_and_particles),
        cmocka_unit_test(test_heat_flows_balance),
        cmocka_unit_test(test_currents_balance),
        cmocka_unit_test(test_currents_balance_eq50),
        cmocka_unit_test(test_snapshots_change_nothing),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_links_match_statistics),
        cmocka_unit_test(test_series_walls_match_contacts),
        cmocka_unit_test(test_neck_histogram_counts_links),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
