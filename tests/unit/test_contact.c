/*
 * Contact detection internals: the cell-grid pair list against brute force,
 * id-keyed history across rebuilds, and trajectories that do not depend on
 * how often the list is rebuilt or on the particles' order in memory.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include <sinter_submodel.h>

#include "scene_support.h"
#include "contact/chunks.h"
#include "contact/contacts.h"
#include "contact/neighbors.h"
#include "stepper/stepper.h"

/* Deterministic uniform numbers in [0, 1). A scene draws them one statement at a time: the
 * order in which a call's arguments (or an initializer list's items) are evaluated is
 * unspecified in C, and gcc and clang differ, so draws inside one call would give each
 * compiler its own scene (the orders below are those gcc gave the scenes the tests were
 * written on: a call's last argument first). */
static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void random_cloud(scene *s, size_t n, uint64_t seed)
{
    for (size_t k = 0; k < n; ++k) {
        const double r = 1e-3 * (0.5 + lcg(&seed)); /* 2:1 size ratio */
        const double z = 0.02 * lcg(&seed), y = 0.02 * lcg(&seed), x = 0.02 * lcg(&seed);
        scene_add(s, x, y, z, r);
    }
}

/* n spheres of 0.35-1.05 mm at random in a 3 cm cube (about 4.7 candidate pairs each within
 * the 0.3 mm skin, some in contact) on `threads` threads, and their pair list. */
static void dense_cloud(scene *s, int threads, size_t n, sinter_neighbors *nb)
{
    scene_init(s);
    OK(sinter_ctx_set_threads(s->ctx, threads));
    scene_material(s, 1e7, 0.3, 2500, 0.0, 0.3);
    scene_open(s, "hertz_mindlin", 0);
    uint64_t seed = 11;
    for (size_t k = 0; k < n; ++k) {
        const double r = 0.7e-3 * (0.5 + lcg(&seed));
        const double z = 0.03 * lcg(&seed), y = 0.03 * lcg(&seed), x = 0.03 * lcg(&seed);
        scene_add(s, x, y, z, r);
    }
    sinter_neighbors_init(nb, s->ctx, 3e-4);
    OK(sinter_neighbors_build(nb, s->ps, s->walls));
}

static void test_pair_list_matches_brute_force(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
    scene_open(&s, "hertz_mindlin", 0);
    random_cloud(&s, 600, 7);
    scene_floor(&s, 0.001);
    const double skin = 2e-4;
    sinter_neighbors nb;
    sinter_neighbors_init(&nb, s.ctx, skin);
    OK(sinter_neighbors_build(&nb, s.ps, s.walls));
    const sinter_particles *ps = s.ps;
    size_t expected = 0, expected_walls = 0;
    for (size_t i = 0; i < ps->count; ++i) {
        for (size_t j = i + 1; j < ps->count; ++j) {
            double d2 = 0;
            for (int d = 0; d < 3; ++d)
                d2 += (ps->x[3 * i + d] - ps->x[3 * j + d]) * (ps->x[3 * i + d] - ps->x[3 * j + d]);
            const double cut = ps->radius[i] + ps->radius[j] + skin;
            if (d2 < cut * cut)
                ++expected;
        }
        if (ps->x[3 * i + 2] - 0.001 < ps->radius[i] + skin)
            ++expected_walls;
    }
    assert_int_equal(nb.pp.count, expected);
    assert_int_equal(nb.pw.count, expected_walls);
    /* every listed pair is within the cutoff, listed once, and keyed by ordered ids */
    for (size_t p = 0; p < nb.pp.count; ++p) {
        const uint32_t i = nb.pp.i[p], j = nb.pp.j[p];
        assert_true(i != j);
        assert_true(nb.pp.key_i[p] < nb.pp.key_j[p]);
        assert_true(ps->id[i] == nb.pp.key_i[p] && ps->id[j] == nb.pp.key_j[p]);
        assert_int_equal(nb.pp.from[p], SINTER_NO_PAIR); /* first build: nothing to carry */
    }
    /* A second build with nothing moved maps every pair onto itself. */
    OK(sinter_neighbors_build(&nb, s.ps, s.walls));
    for (size_t p = 0; p < nb.pp.count; ++p)
        assert_int_equal(nb.pp.from[p], p);
    assert_false(sinter_neighbors_stale(&nb, s.ps, s.walls));
    /* Particles moved (same indices): each new pair's old twin, found by brute force over
     * the old list's ids, is the one the build names (the run-wise match). */
    const size_t old_count = nb.pp.count;
    uint64_t *old_ki = malloc(old_count * sizeof(uint64_t)), *old_kj = malloc(old_count * 8);
    memcpy(old_ki, nb.pp.key_i, old_count * sizeof(uint64_t));
    memcpy(old_kj, nb.pp.key_j, old_count * sizeof(uint64_t));
    uint64_t seed = 3;
    for (size_t k = 0; k < 3 * ps->count; ++k)
        s.ps->x[k] += 4e-4 * (lcg(&seed) - 0.5);
    OK(sinter_neighbors_build(&nb, s.ps, s.walls));
    size_t kept = 0;
    for (size_t q = 0; q < nb.pp.count; ++q) {
        uint32_t twin = SINTER_NO_PAIR;
        for (size_t p = 0; p < old_count; ++p)
            if (old_ki[p] == nb.pp.key_i[q] && old_kj[p] == nb.pp.key_j[q])
                twin = (uint32_t)p;
        assert_int_equal(nb.pp.from[q], twin);
        kept += twin != SINTER_NO_PAIR;
    }
    assert_true(kept > 0 && kept < nb.pp.count); /* some pairs stayed, some are new */
    free(old_ki);
    free(old_kj);
    sinter_neighbors_free(&nb);
    scene_close(&s);
}

/* n spheres on a lattice of `row` x `row` layers `spacing` apart, radii 1 mm times
 * r0 + dr u, velocities with components in [-0.5, 0.5) m/s (u uniform in [0, 1) from seed),
 * above a floor at z = -1 mm. */
static void add_cloud(scene *s, size_t n, size_t row, double spacing, double r0, double dr,
                      uint64_t seed)
{
    for (size_t k = 0; k < n; ++k)
        scene_add(s, spacing * (double)(k % row), spacing * (double)((k / row) % row),
                  spacing * (double)(k / (row * row)), 1e-3 * (r0 + dr * lcg(&seed)));
    for (size_t k = 0; k < n; ++k) {
        const double vx = lcg(&seed) - 0.5, vy = lcg(&seed) - 0.5, vz = lcg(&seed) - 0.5;
        const double v[3] = {vx, vy, vz};
        set3(s, SINTER_FIELD_VELOCITY, k, v);
    }
    scene_floor(s, -0.001);
}

/* A falling, colliding cloud in a box, with friction (history) and rolling. */
static void run_cloud(double skin, int reorder_at, double *out_x, size_t n)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e6, 0.3, 2500, 0.3, 0.4);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    scene_open(&s, "hertz_mindlin", 1);
    /* jittered lattice with random velocities: many collisions, no initial overlap */
    add_cloud(&s, n, 4, 2.05e-3, 0.8, 0.2, 11);
    OK(sinter_stepper_set_skin(s.st, skin));
    OK(sinter_stepper_set_dt(s.st, 2e-5));
    if (reorder_at == -2) /* sorted by position in memory every 37 steps */
        OK(sinter_stepper_set_option(s.st, "sort_interval", 37));
    for (int k = 0; k < 3; ++k) {
        OK(sinter_stepper_step(s.st, 200));
        if (k == reorder_at) {
            /* reverse the particles in memory (as a spatial sort would shuffle them) */
            size_t order[64];
            for (size_t i = 0; i < n; ++i)
                order[i] = n - 1 - i;
            OK(sinter_particles_permute(s.ps, order));
        }
    }
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    assert_true(stats.contacts > 0);
    /* positions by persistent id */
    const uint64_t *id = s.ps->id;
    for (size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d)
            out_x[3 * id[i] + d] = s.ps->x[3 * i + d];
    print_message("skin %.1e m: %llu rebuilds, %llu contacts\n", skin,
                  (unsigned long long)stats.neighbor_builds, (unsigned long long)stats.contacts);
    scene_close(&s);
}

static void test_trajectory_independent_of_rebuilds_and_order(void **state)
{
    (void)state;
    enum { N = 60 };
    double every_step[3 * N], rarely[3 * N], reordered[3 * N], sorted[3 * N];
    run_cloud(0.0, -1, every_step, N); /* skin 0: rebuilt at every step */
    run_cloud(2e-3, -1, rarely, N);    /* large skin: rebuilt rarely */
    run_cloud(2e-3, 0, reordered, N);  /* reordered in memory after 200 steps */
    run_cloud(2e-3, -2, sorted, N);    /* stepper option sort_interval 37 */
    /* The same pairs interact in a possibly different order, so sums differ by
     * round-off only; 600 steps of a dissipative pile do not amplify 1e-16 to 1e-12 m. */
    for (size_t k = 0; k < 3 * N; ++k) {
        assert_close(rarely[k], every_step[k], 1e-12);
        assert_close(reordered[k], every_step[k], 1e-12);
        assert_close(sorted[k], every_step[k], 1e-12);
    }
}

/* A scene on `threads` threads whose particles conduct heat (k 100 W/m/K, C 100 J/kg/K). */
static void conducting_scene(scene *s, int threads)
{
    scene_init(s);
    OK(sinter_ctx_set_threads(s->ctx, threads));
    scene_material(s, 1e7, 0.3, 2500, 0.2, 0.3);
    OK(sinter_material_set(s->mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 100.0));
    OK(sinter_material_set(s->mat, SINTER_MAT_HEAT_CAPACITY, 100.0));
}

/* A packed, jittered lattice of 15^3 spheres (about 9000 contacts: the threaded paths run),
 * with explicit conduction from a 500 K floor and no rolling resistance when `heat` (the
 * threaded conduction sums and the blocked Hertz-Mindlin law): heat 1 conducts by eq. 34's
 * area, which the contact list carries; heat 2 by LIGGGHTS' projection, which reads no
 * geometry, so the list is found lean and the law forms the geometry itself. */
static void open_packed(scene *s, int threads, int heat, sinter_heat_model **cond);
static void open_packed_m(scene *s, int threads, int heat, sinter_heat_model **cond, int m);

/* Positions, velocities and spins of the scene's n particles into out (9 n). */
static void copy_motion(const scene *s, double *out, size_t n)
{
    memcpy(out, s->ps->x, 3 * n * sizeof(double));
    memcpy(out + 3 * n, s->ps->v, 3 * n * sizeof(double));
    memcpy(out + 6 * n, s->ps->w, 3 * n * sizeof(double));
}

/* run_packed on an m^3 lattice, for `steps` steps. */
static void run_packed_m(int threads, int heat, int reverse, double *out, size_t n, int m,
                         int steps);

static void run_packed(int threads, int heat, int reverse, double *out, size_t n)
{
    run_packed_m(threads, heat, reverse, out, n, 15, 50);
}

static int packed_ranges; /* the partition's ranges at the end of the last run_packed_m */

static void run_packed_m(int threads, int heat, int reverse, double *out, size_t n, int m,
                         int steps)
{
    scene s;
    sinter_heat_model *cond = NULL;
    open_packed_m(&s, threads, heat, &cond, m);
    if (reverse) {
        /* ids now descend with the index, so pairs, oriented by id, start from the larger
         * index: the partition must follow the smaller one */
        size_t *order = malloc(n * sizeof(size_t));
        for (size_t i = 0; i < n; ++i)
            order[i] = n - 1 - i;
        OK(sinter_particles_permute(s.ps, order));
        free(order);
    }
    OK(sinter_stepper_step(s.st, (uint64_t)steps));
    packed_ranges = s.st->pp.chunks.count;
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    assert_true(stats.contacts > 5000);
    memcpy(out, s.ps->x, 3 * n * sizeof(double));
    memcpy(out + 3 * n, s.ps->w, 3 * n * sizeof(double));
    memcpy(out + 6 * n, s.ps->temperature, n * sizeof(double));
    for (size_t k = 0; k < 5; ++k) /* the walls' reactions (threaded wall runs sum them) */
        OK(sinter_walls_get_force(s.walls, k, out + 7 * n + 3 * k));
    if (heat) { /* the floor heated the bottom layer */
        double hottest = 0.0;
        for (size_t i = 0; i < n; ++i)
            hottest = s.ps->temperature[i] > hottest ? s.ps->temperature[i] : hottest;
        assert_true(hottest > 300.0 + 1e-3);
    }
    sinter_heat_model_destroy(cond); /* before its context */
    scene_close(&s);
}

/* The packed lattice of run_packed, set up (dt 1e-5 s) but not stepped; *cond is its
 * conduction model when `heat` (else NULL). */
static void open_packed(scene *s_out, int threads, int heat, sinter_heat_model **cond_out)
{
    open_packed_m(s_out, threads, heat, cond_out, 15);
}

static void open_packed_m(scene *s_out, int threads, int heat, sinter_heat_model **cond_out, int m)
{
    scene s;
    conducting_scene(&s, threads);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 100.0));
    scene_open(&s, "hertz_mindlin", 1);
    scene_floor(&s, 0.0);
    /* and four side walls touching the lattice (1125 wall contacts at m = 15): the ranged
     * wall path */
    const double side = m * 2 * 0.5e-3 * 0.999;
    const double wp[4][3] = {{0, 0, 0}, {side, 0, 0}, {0, 0, 0}, {0, side, 0}};
    const double wn[4][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < 4; ++k)
        OK(sinter_walls_add_plane(s.walls, wp[k], wn[k], s.wall_mat, NULL));
    sinter_heat_model *cond = NULL;
    if (heat) {
        /* and the law without rolling resistance (the blocked path) */
        OK(sinter_force_model_set(s.contact, "rolling", 0.0));
        OK(sinter_walls_set_temperature(s.walls, 0, 500.0));
        OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
        OK(sinter_heat_model_set(cond, "area", heat == 2 ? 1.0 : 0.0));
        OK(sinter_stepper_add_heat(s.st, cond));
    }
    uint64_t seed = 5;
    const double r = 0.5e-3, a = 2 * r * 0.999;
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                const double dy = 1e-6 * lcg(&seed), dx = 1e-6 * lcg(&seed);
                scene_add(&s, (i + 0.5) * a + dx, (j + 0.5) * a + dy, (k + 0.5) * a, r);
            }
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    *s_out = s;
    *cond_out = cond;
}

/*
 * The partitioned law (hertz_mindlin.c, pp_chunked: ranges of particles on the threads, the
 * contacts between ranges added afterwards by the range of each particle) against Hertz's
 * closed form: a jittered packed lattice of 15^3 spheres at rest, overlapping their
 * neighbours by about 1 um, no gravity, no walls. At the first evaluation there is no
 * tangential history and no velocity, so each contact pushes its spheres apart with
 * 4/3 E* sqrt(R*) delta^(3/2) along the line of centres (seed 003 eq. 4); each sphere's net
 * force must be the sum over its overlapping neighbours, to 1e-9 of the largest contact
 * force (the law's arithmetic differs from this loop's), on 1-3 threads, with the list found
 * with and without its geometry (heat conduction by projection makes it lean).
 */
static void test_partitioned_law_matches_hertz(void **state)
{
    (void)state;
    enum { M = 15, N = M * M * M };
    const double e = 1e7, nu = 0.3, r = 0.5e-3, a = 2 * r * 0.999;
    const double estar = e / (2.0 * (1.0 - nu * nu)), k = 4.0 / 3.0 * estar * sqrt(0.5 * r);
    for (int lean = 0; lean <= 1; ++lean)
        for (int t = 1; t <= 3; ++t) {
            scene s;
            conducting_scene(&s, t);
            scene_open(&s, "hertz_mindlin", 0);
            OK(sinter_force_model_set(s.contact, "rolling", 0.0));
            sinter_heat_model *cond = NULL;
            if (lean) {
                OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
                OK(sinter_heat_model_set(cond, "area", 1.0));
                OK(sinter_stepper_add_heat(s.st, cond));
            }
            uint64_t seed = 9;
            for (int z = 0; z < M; ++z)
                for (int y = 0; y < M; ++y)
                    for (int x = 0; x < M; ++x)
                        scene_add(&s, (x + 0.5) * a + 2e-7 * lcg(&seed),
                                  (y + 0.5) * a + 2e-7 * lcg(&seed),
                                  (z + 0.5) * a + 2e-7 * lcg(&seed), r);
            OK(sinter_stepper_set_dt(s.st, 1e-6));
            OK(sinter_stepper_step(s.st, 0)); /* the first evaluation only */
            const double *x = s.ps->x, *f = s.ps->force;
            double *expected = calloc(3 * N, sizeof(double));
            double fmax = 0.0;
            size_t contacts = 0;
            for (size_t i = 0; i < N; ++i)
                for (size_t j = i + 1; j < N; ++j) {
                    double d[3], d2 = 0.0;
                    for (int c = 0; c < 3; ++c) {
                        d[c] = x[3 * j + c] - x[3 * i + c];
                        d2 += d[c] * d[c];
                    }
                    if (!(d2 < 4 * r * r))
                        continue;
                    const double dist = sqrt(d2), delta = 2 * r - dist;
                    const double fn = k * delta * sqrt(delta);
                    fmax = fn > fmax ? fn : fmax;
                    ++contacts;
                    for (int c = 0; c < 3; ++c) {
                        expected[3 * i + c] -= fn * d[c] / dist;
                        expected[3 * j + c] += fn * d[c] / dist;
                    }
                }
            assert_true(contacts > 9000);
            assert_true(s.st->pp.chunks.count >= 2); /* the partitioned path, boundaries */
            for (size_t q = 0; q < 3 * N; ++q)
                assert_close(f[q], expected[q], 1e-9 * fmax);
            free(expected);
            sinter_heat_model_destroy(cond);
            scene_close(&s);
        }
}

/* The checkpoint at `path` rewritten as format 4 (before the partition's section, version 5):
 * the section (its count, then count + 1 bounds), version 6's tail (the sort counter, the
 * forces' flag and an empty host section, 24 bytes), version 7's (56 bytes) and version 8's
 * walls' state (10 doubles per wall), version 9's frozen heat stage (80 bytes when not
 * frozen), version 10's broken-bond count (8 bytes), version 12's periodic section (no axis
 * periodic, no ghosts: 16 bytes), version 13's insertion flag (8 bytes, no insertion) and
 * version 14's neighbour search reach (8 bytes) dropped from before the checksum, the
 * version and the checksum (FNV-1a 64 of everything before it) rewritten; `ranges` is the
 * partition's count. */
static void checkpoint_as_format_4(const char *path, int ranges, size_t walls)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    unsigned char *data = malloc(1 << 24);
    assert_non_null(data);
    const size_t size = fread(data, 1, 1 << 24, f);
    fclose(f);
    /* + version 7's tail without a staggered history: 2 counts, 3 doubles, 2 flags (56 bytes),
     * version 8's walls, version 9's frozen heat section (not frozen: 10 words, 80 bytes) and
     * version 10's broken-bond count (8 bytes), version 12's periodic section (16 bytes),
     * version 13's insertion flag (8 bytes), version 14's reach (8 bytes) */
    const size_t section =
        8 * (ranges > 0 ? (size_t)ranges + 2 : 1) + 24 + 56 + 80 * walls + 80 + 8 + 16 + 8 + 8;
    assert_true(size > 16 + 8 + section);
    uint64_t count;
    memcpy(&count, data + size - 8 - section, 8);
    assert_int_equal(count, (uint64_t)ranges);
    const size_t body = size - 8 - section;
    const uint32_t version = 4;
    memcpy(data + 8, &version, 4); /* after the 8-byte magic */
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t k = 0; k < body; ++k) {
        h ^= data[k];
        h *= 0x100000001b3ull;
    }
    memcpy(data + body, &h, 8);
    f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, body + 8, f), body + 8);
    fclose(f);
    free(data);
}

/* A restart of the packed lattice with rolling resistance on 2 threads continues bit for bit
 * in a fresh stepper: the checkpoint keeps the partition's particle ranges (contact/chunks.h),
 * which the first search over a pair list made from the contacts of that moment; made afresh
 * from the contacts at the restart, they moved boundary contacts between ranges and the
 * sums' order with them (x differed in the last bits after 30 steps). A format 4 file (no
 * ranges) is still read, and that run stays within round-off of the straight one (1e-12 of the
 * largest value of each field). */
static void test_rolling_restart_on_threads(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    char dir[] = "/tmp/sinter_restart_XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof(path), "%s/state.ckpt", dir);
    double *out[3];
    int ranges = 0;
    for (int run = 0; run < 3; ++run) {
        out[run] = malloc(9 * N * sizeof(double));
        scene s;
        sinter_heat_model *cond = NULL;
        open_packed(&s, 2, 0, &cond);
        if (run == 0) {
            OK(sinter_stepper_step(s.st, 30));
            OK(sinter_checkpoint_write(s.st, path));
            ranges = s.st->pp.chunks.count;
        } else {
            size_t walls = 0;
            OK(sinter_walls_count(s.walls, &walls));
            if (run == 2)
                checkpoint_as_format_4(path, ranges, walls);
            OK(sinter_checkpoint_read(s.st, path));
        }
        OK(sinter_stepper_step(s.st, 30));
        assert_true(s.st->pp.chunks.count > 0); /* a partitioned list */
        copy_motion(&s, out[run], N);
        scene_close(&s);
    }
    assert_true(ranges > 0);
    assert_memory_equal(out[0], out[1], 9 * N * sizeof(double));
    size_t differ = 0;
    for (int field = 0; field < 3; ++field) {
        const double *a = out[0] + 3 * N * field, *b = out[2] + 3 * N * field;
        double largest = 0.0;
        for (size_t k = 0; k < 3 * N; ++k)
            largest = fmax(largest, fabs(a[k]));
        for (size_t k = 0; k < 3 * N; ++k) {
            assert_true(fabs(a[k] - b[k]) <= 1e-12 * largest);
            differ += a[k] != b[k];
        }
    }
    print_message("format 4 restart: %zu of %d values differ in their last bits\n", differ, 9 * N);
    for (int run = 0; run < 3; ++run)
        free(out[run]);
    remove(path);
    rmdir(dir);
}

static void test_results_independent_of_thread_count(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    /* heat 1: the blocked contact law and conduction, summed by the partitioned list
     * (contact/chunks.h); heat 2: the same from a lean list; reversed: the particles in
     * reverse order (not partitioned: the serial sums) */
    const int cases[5][2] = {{0, 0}, {1, 0}, {1, 1}, {2, 0}, {2, 1}}; /* heat, reverse */
    enum { SIZE = 7 * N + 15 }; /* x, w, temperature; the 5 walls' reactions */
    double *with_geometry[2] = {NULL, NULL};
    for (int c = 0; c < 5; ++c) {
        const int heat = cases[c][0], reverse = cases[c][1];
        double *one = calloc(SIZE, sizeof(double)), *two = calloc(SIZE, sizeof(double)),
               *three = calloc(SIZE, sizeof(double));
        run_packed(1, heat, reverse, one, N);
        run_packed(2, heat, reverse, two, N);
        run_packed(3, heat, reverse, three, N);
        /* The threaded sums run in the serial order: equal to the bit. */
        assert_memory_equal(one, two, SIZE * sizeof(double));
        assert_memory_equal(one, three, SIZE * sizeof(double));
        if (heat == 1) {
            with_geometry[reverse] = one;
        } else {
            if (heat == 2) { /* the law's own geometry is the list's: the same motion, bit for
                                bit, and the same wall reactions */
                assert_memory_equal(one, with_geometry[reverse], 6 * N * sizeof(double));
                assert_memory_equal(one + 7 * N, with_geometry[reverse] + 7 * N,
                                    15 * sizeof(double));
            }
            free(one);
        }
        free(two);
        free(three);
    }
    free(with_geometry[0]);
    free(with_geometry[1]);
}

/*
 * More ranges than threads (force/hertz_mindlin.c and heat/conduction.c, pp_chunked and
 * all_ranges: the ranges go to whichever thread is free): a packed 38^3 lattice (160 000
 * pairs, so 4 ranges) on a heated floor between four side walls, 10 steps on 1, 2 and 3
 * threads, with rolling resistance (the general law) and with the blocked law and conduction
 * from a lean list: positions, spins, temperatures and the walls' reactions equal to the bit.
 * A range whose boundary contacts were added before its interior pass ended, or a wall run
 * or kick taken out of its range's order, would change them.
 */
static void test_ranges_shared_by_threads(void **state)
{
    (void)state;
    enum { M = 38, N = M * M * M, SIZE = 7 * N + 15 };
    for (int heat = 0; heat <= 2; heat += 2) {
        double *out[3];
        for (int t = 0; t < 3; ++t) {
            out[t] = calloc(SIZE, sizeof(double));
            run_packed_m(t + 1, heat, 0, out[t], N, M, 10);
            assert_true(packed_ranges > 3); /* more than the threads */
        }
        assert_memory_equal(out[0], out[1], SIZE * sizeof(double));
        assert_memory_equal(out[0], out[2], SIZE * sizeof(double));
        double moved = 0.0; /* the lattice settled under gravity: the test sees motion */
        for (size_t k = 0; k < 3 * (size_t)N; ++k)
            moved = fmax(moved, fabs(out[0][3 * N + k]));
        assert_true(moved > 0.0);
        for (int t = 0; t < 3; ++t)
            free(out[t]);
    }
}

/*
 * The blocked law's pair and wall contacts in one parallel region (force/hertz_mindlin.c,
 * pp_chunked with the wall runs of the pair partition's ranges): pair forces cancel in pairs
 * and each wall contact's force on its particle is minus its share of the wall's reaction, so
 * after a step the particles' forces less gravity plus the walls' reactions must sum to zero,
 * to round-off (1e-12 of the largest reaction), on 1, 2 and 3 threads, in a packed lattice
 * pressed against a floor and four side walls (1125 wall contacts), without and with rolling
 * resistance (a wall contact evaluated twice, as in a first version of the rolling law on a
 * partitioned list, fails it).
 */
static void test_partitioned_law_balances_walls(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    for (int run = 0; run < 6; ++run) {
        const int t = 1 + run % 3, rolling = run >= 3;
        scene s;
        sinter_heat_model *cond = NULL;
        open_packed(&s, t, !rolling, &cond); /* heat 1: no rolling resistance */
        if (rolling) {
            OK(sinter_material_set(s.wall_mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
            for (size_t k = 0; k < 5; ++k)
                OK(sinter_walls_set_material(s.walls, k, s.wall_mat));
        }
        double g[3];
        OK(sinter_force_model_get(s.gravity, "gx", &g[0]));
        OK(sinter_force_model_get(s.gravity, "gy", &g[1]));
        OK(sinter_force_model_get(s.gravity, "gz", &g[2]));
        OK(sinter_stepper_step(s.st, 20));
        assert_true(s.st->pp.chunks.count > 0 && s.st->pw.count > 1000);
        const double *f = NULL;
        OK(sinter_particles_view_read(s.ps, SINTER_FIELD_FORCE, (const void **)&f, NULL, NULL));
        double sum[3] = {0.0, 0.0, 0.0}, largest = 0.0;
        for (size_t i = 0; i < N; ++i)
            for (int d = 0; d < 3; ++d)
                sum[d] += f[3 * i + d] - s.ps->mass[i] * g[d];
        OK(sinter_particles_release(s.ps, SINTER_FIELD_FORCE));
        for (size_t k = 0; k < 5; ++k) {
            double r[3];
            OK(sinter_walls_get_force(s.walls, k, r));
            for (int d = 0; d < 3; ++d) {
                sum[d] += r[d];
                largest = fabs(r[d]) > largest ? fabs(r[d]) : largest;
            }
        }
        assert_true(largest > 0.0);
        for (int d = 0; d < 3; ++d)
            assert_true(fabs(sum[d]) < 1e-12 * largest);
        sinter_heat_model_destroy(cond); /* before its context */
        scene_close(&s);
    }
}

/*
 * Drag (seed 000 eq. 20) on the pair partition's particle ranges (force/drag.c): in the packed
 * lattice after 20 steps, the forces evaluated with drag after the contact law minus those
 * without must be -c v particle by particle (to one rounding of the sum: 1e-12 of |f| + |c v|),
 * on 1 thread (one loop) and on 2 and 3 (the ranges), with the same bits on each.
 */
static void test_partitioned_drag(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    const double c = 2e-3; /* [kg/s]: c v ~ 1e-5 of the contact forces' scale here */
    double *first = malloc(3 * N * sizeof(double)), *plain = malloc(3 * N * sizeof(double));
    for (int t = 1; t <= 3; ++t) {
        scene s;
        sinter_heat_model *cond = NULL;
        open_packed(&s, t, 0, &cond);
        OK(sinter_stepper_step(s.st, 20));
        assert_true(t == 1 || s.st->pp.chunks.count > 0);
        OK(sinter_stepper_evaluate(s.st));
        memcpy(plain, s.ps->force, 3 * N * sizeof(double));
        sinter_force_model *drag = NULL;
        OK(sinter_force_model_create(&drag, s.ctx, "drag"));
        s.ps->materials[s.ps->material[0]].value[SINTER_MAT_DRAG_COEFFICIENT] = c;
        OK(sinter_stepper_add_force(s.st, drag));
        OK(sinter_stepper_evaluate(s.st));
        double moving = 0.0;
        for (size_t k = 0; k < 3 * N; ++k) {
            const double want = -c * s.ps->v[k], got = s.ps->force[k] - plain[k];
            assert_true(fabs(got - want) <= 1e-12 * (fabs(plain[k]) + fabs(want)));
            moving = fmax(moving, fabs(s.ps->v[k]));
        }
        assert_true(moving > 0.0);
        if (t == 1)
            memcpy(first, s.ps->force, 3 * N * sizeof(double));
        else
            assert_memory_equal(first, s.ps->force, 3 * N * sizeof(double));
        sinter_stepper_destroy(s.st); /* before the model it holds */
        s.st = NULL;
        sinter_force_model_destroy(drag);
        scene_close(&s);
    }
    free(first);
    free(plain);
}

/*
 * The per-particle heat sources and the softening factor on the pair partition's particle
 * ranges (contact/particle_pass.h): in the packed lattice, temperatures spread over 600-900 K,
 * radiation (eq. 41), convection with a given film coefficient (eq. 37) and a laser down the
 * lattice's axis (eq. 29, 31: depth from the highest lit top) must give each particle the sum
 * of the three formulas (to 1e-12), and the exponential softening law (eq. 42) its factor, on
 * 1 thread (one loop) and on 2 and 3 (the ranges), with the same bits on each.
 */
static void test_partitioned_heat_sources(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    const double pi = 3.14159265358979323846, sigma = 5.670374419e-8;
    const double eps = 0.6, h = 25.0, absorb = 0.4, i0 = 1e6, mu = 800.0, t_env = 500.0;
    const double axis = 7.5 * 2 * 0.5e-3 * 0.999, beam = 3e-3, ts = 600.0, rate = 0.8;
    double *first = malloc(2 * N * sizeof(double));
    for (int t = 1; t <= 3; ++t) {
        scene s;
        sinter_heat_model *cond = NULL;
        open_packed(&s, t, 0, &cond);
        double *v = s.ps->materials[s.ps->material[0]].value;
        v[SINTER_MAT_EMISSIVITY] = eps;
        v[SINTER_MAT_ABSORPTANCE] = absorb;
        v[SINTER_MAT_SOFTENING_LAW] = 2.0;
        v[SINTER_MAT_SOFTENING_TEMPERATURE] = ts;
        v[SINTER_MAT_SOFTENING_RATE] = rate;
        v[SINTER_MAT_SOFTENING_FLOOR] = 0.05;
        uint64_t seed = 41;
        for (size_t i = 0; i < N; ++i)
            s.ps->temperature[i] = 600.0 + 300.0 * lcg(&seed);
        sinter_heat_model *hm[3] = {NULL, NULL, NULL};
        OK(sinter_heat_model_create(&hm[0], s.ctx, "radiation"));
        OK(sinter_heat_model_set(hm[0], "temperature", t_env));
        OK(sinter_heat_model_create(&hm[1], s.ctx, "convection"));
        OK(sinter_heat_model_set(hm[1], "temperature", t_env));
        OK(sinter_heat_model_set(hm[1], "h", h));
        OK(sinter_heat_model_create(&hm[2], s.ctx, "laser"));
        OK(sinter_heat_model_set(hm[2], "x", axis));
        OK(sinter_heat_model_set(hm[2], "y", axis));
        OK(sinter_heat_model_set(hm[2], "radius", beam));
        OK(sinter_heat_model_set(hm[2], "intensity", i0));
        OK(sinter_heat_model_set(hm[2], "attenuation", mu));
        for (int k = 0; k < 3; ++k)
            OK(sinter_stepper_add_heat(s.st, hm[k]));
        OK(sinter_stepper_evaluate(s.st));
        assert_true(t == 1 || s.st->pp.chunks.count > 0);
        const double *x = s.ps->x, *r = s.ps->radius, *theta = s.ps->temperature;
        double top = -HUGE_VAL;
        size_t lit = 0;
        for (size_t i = 0; i < N; ++i) {
            const double dx = x[3 * i] - axis, dy = x[3 * i + 1] - axis;
            if (dx * dx + dy * dy <= beam * beam)
                top = fmax(top, x[3 * i + 2] + r[i]), ++lit;
        }
        assert_true(lit > 100);
        for (size_t i = 0; i < N; ++i) {
            const double dx = x[3 * i] - axis, dy = x[3 * i + 1] - axis, r2 = r[i] * r[i];
            const double t2 = theta[i] * theta[i], te2 = t_env * t_env;
            double want = eps * 4.0 * pi * sigma * r2 * (te2 * te2 - t2 * t2);
            want += h * 4.0 * pi * r2 * (t_env - theta[i]);
            if (dx * dx + dy * dy <= beam * beam)
                want += absorb * pi * i0 * r2 * exp(-mu * (top - (x[3 * i + 2] + r[i])));
            assert_true(fabs(s.ps->heat[i] - want) <= 1e-12 * fabs(want));
            const double f = fmax(fmin(1.0, exp(rate * (1.0 - theta[i] / ts))), 0.05);
            assert_true(fabs(s.st->thermal.modulus_scale[i] - f) <= 1e-15 * f);
        }
        if (t == 1) {
            memcpy(first, s.ps->heat, N * sizeof(double));
            memcpy(first + N, s.st->thermal.modulus_scale, N * sizeof(double));
        } else {
            assert_memory_equal(first, s.ps->heat, N * sizeof(double));
            assert_memory_equal(first + N, s.st->thermal.modulus_scale, N * sizeof(double));
        }
        sinter_stepper_destroy(s.st); /* before the models it holds */
        s.st = NULL;
        for (int k = 0; k < 3; ++k)
            sinter_heat_model_destroy(hm[k]);
        scene_close(&s);
    }
    free(first);
}

/*
 * The domain's test on the pair partition's particle ranges (stepper/sanity.c): in the packed
 * lattice with a domain around it, two particles put beyond its top, one in the last slab and
 * one in the first half (the partition's two ranges here), must stop the step with
 * SINTER_ERR_LOST_PARTICLE naming the one of lower index, on 1, 2 and 3 threads, and keep the
 * last accepted state.
 */
static void test_partitioned_domain(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    const size_t late = N - 20, middle = N / 4;
    for (int t = 1; t <= 3; ++t) {
        scene s;
        sinter_heat_model *cond = NULL;
        open_packed(&s, t, 0, &cond);
        const double lo[3] = {-0.01, -0.01, -0.01}, hi[3] = {0.03, 0.03, 0.03};
        OK(sinter_stepper_set_domain(s.st, lo, hi));
        OK(sinter_stepper_step(s.st, 5));
        assert_true(t == 1 || s.st->pp.chunks.count > 0);
        double *x = NULL;
        OK(sinter_particles_view(s.ps, SINTER_FIELD_POSITION, (void **)&x, NULL, NULL));
        x[3 * late + 2] = 0.05;
        x[3 * middle + 2] = 0.04;
        OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
        double before = 0.0;
        OK(sinter_stepper_time(s.st, &before));
        assert_int_equal(sinter_stepper_step(s.st, 1), SINTER_ERR_LOST_PARTICLE);
        char want[64];
        snprintf(want, sizeof(want), "particle %zu (id %zu) left the domain at z", middle, middle);
        if (strstr(sinter_last_error(s.ctx), want) == NULL) {
            print_error("message '%s'\n", sinter_last_error(s.ctx));
            fail();
        }
        double after = 0.0;
        OK(sinter_stepper_time(s.st, &after));
        assert_true(after == before);
        scene_close(&s);
    }
}

/*
 * Conduction on a partitioned list (contact/chunks.h, heat/conduction.c): each range adds its
 * interior contacts, then each range its particles' share of the boundary contacts, in one
 * parallel region. Exchange between particles is antisymmetric (eq. 32), so with the walls'
 * conduction off, sum m c theta must stay to round-off (1e-13 relative over 50 steps of a
 * 15^3 lattice whose temperatures are spread over 300-500 K), on 1, 2 and 3 threads; a boundary
 * contact added twice, or by no range, would change it by 1e-6 or more. With the walls on
 * the wall runs join the same region: the energy must change, and by the
 * same amount on every thread count (the floor at 500 K, the four side walls at 293.15 K).
 */
static void test_partitioned_conduction_conserves_energy(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15, STEPS = 50 };
    double gained[2][3];
    for (int walls = 0; walls <= 1; ++walls)
        for (int t = 1; t <= 3; ++t) {
            scene s;
            sinter_heat_model *cond = NULL;
            open_packed(&s, t, 1, &cond);
            OK(sinter_heat_model_set(cond, "walls", walls));
            uint64_t seed = 23;
            double *theta = NULL;
            OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&theta, NULL, NULL));
            for (size_t i = 0; i < N; ++i)
                theta[i] = 300.0 + 200.0 * lcg(&seed);
            OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE));
            const double c = 100.0; /* conducting_scene's heat capacity */
            double e0 = 0.0, e1 = 0.0, spread0 = 0.0, spread1 = 0.0;
            for (size_t i = 0; i < N; ++i) {
                e0 += s.ps->mass[i] * c * s.ps->temperature[i];
                spread0 += fabs(s.ps->temperature[i] - 400.0);
            }
            OK(sinter_stepper_step(s.st, STEPS));
            assert_true(s.st->pp.chunks.count > 0);
            for (size_t i = 0; i < N; ++i) {
                e1 += s.ps->mass[i] * c * s.ps->temperature[i];
                spread1 += fabs(s.ps->temperature[i] - 400.0);
            }
            /* the step's heat powers (summed into an array its drift zeroed by ranges) are a
             * fresh evaluation's of the same state (a zeroed array), to the bit */
            double *heat = malloc(N * sizeof(double));
            assert_non_null(heat);
            memcpy(heat, s.ps->heat, N * sizeof(double));
            OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&theta, NULL, NULL));
            OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE)); /* state "written" */
            OK(sinter_stepper_evaluate(s.st));
            assert_memory_equal(heat, s.ps->heat, N * sizeof(double));
            free(heat);
            print_message("walls %d, %d threads: spread %.9g -> %.9g K, energy change %.3g\n",
                          walls, t, spread0 / N, spread1 / N, (e1 - e0) / e0);
            /* heat did flow between the particles (a time constant m c / G of about 1 s) */
            assert_true(spread1 < (1.0 - 1e-5) * spread0);
            gained[walls][t - 1] = (e1 - e0) / e0;
            if (!walls)
                assert_true(fabs(gained[walls][t - 1]) < 1e-13);
            else /* the floor at 500 K heats, the side walls at 293.15 K cool: a net change */
                assert_true(fabs(gained[walls][t - 1]) > 1e-6);
            sinter_heat_model_destroy(cond); /* before its context */
            scene_close(&s);
        }
    for (int walls = 0; walls <= 1; ++walls)
        for (int t = 1; t < 3; ++t)
            assert_true(gained[walls][t] == gained[walls][0]);
}

/*
 * A colliding cloud: contacts begin and end every few steps, more pairs in the skin than in
 * contact, so the history is committed by contact (history.c: the ended pairs cleared, the
 * trial values copied by the list's runs on the threads). On 1, 2 and 3 threads, with and
 * without rolling resistance (3 and 6 values per contact), 300 steps must give the same
 * positions, velocities and spins to the bit (issue 9: a commit that read `active` while
 * another thread rewrote it left ended springs uncleared on two threads). With gravity as the
 * first model (gravity 2) and no rolling, the contact law is the last model and runs the
 * second half kick by ranges in its own parallel region on two and three threads.
 */
static void run_colliding_cloud(int threads, int rolling, int gravity, double *out, size_t n)
{
    scene s;
    scene_init(&s);
    OK(sinter_ctx_set_threads(s.ctx, threads));
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.4);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, rolling ? 0.05 : 0.0));
    scene_open(&s, "hertz_mindlin", gravity);
    OK(sinter_force_model_set(s.contact, "rolling", rolling ? 1.0 : 0.0));
    add_cloud(&s, n, 16, 2.02e-3, 0.9, 0.1, 19); /* 16 x 16 layers, gaps of 0.02-0.22 mm */
    OK(sinter_stepper_set_dt(s.st, 2e-5));
    int by_contact = 0; /* steps committed by contact on a partitioned list */
    int kicked_by_law = 0;
    const size_t law = gravity == 2 ? 1 : 0;
    for (int k = 0; k < 300; ++k) {
        OK(sinter_stepper_step(s.st, 1));
        by_contact += s.st->pp.chunks.count > 0 && !s.st->forces[law].pp.by_pair;
        kicked_by_law += s.st->ranges_final;
    }
    assert_true(by_contact >= 250);
    if (gravity == 2 && sinter_threads_allowed(s.ctx) > 1) /* 1 without OpenMP */
        assert_true(kicked_by_law >= 250);
    else
        assert_int_equal(kicked_by_law, 0);
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    print_message("cloud: %d, %llu contacts, %llu builds\n", by_contact,
                  (unsigned long long)stats.contacts, (unsigned long long)stats.neighbor_builds);
    assert_true(stats.contacts > 200);
    copy_motion(&s, out, n);
    scene_close(&s);
}

static void test_colliding_cloud_independent_of_thread_count(void **state)
{
    (void)state;
    enum { N = 16 * 16 * 12 };
    double *one = malloc(9 * N * sizeof(double)), *other = malloc(9 * N * sizeof(double));
    assert_non_null(one);
    assert_non_null(other);
    for (int rolling = 0; rolling <= 1; ++rolling)
        for (int gravity = 1; gravity <= 2; ++gravity) {
            run_colliding_cloud(1, rolling, gravity, one, N);
            for (int t = 2; t <= 3; ++t) {
                run_colliding_cloud(t, rolling, gravity, other, N);
                assert_memory_equal(one, other, 9 * N * sizeof(double));
            }
        }
    free(one);
    free(other);
}

/*
 * The explicit step's conduction summed in the contact law's parallel region, range by range,
 * on more than one thread (stepper/thermal.c, sinter_thermal_law_begin; conduction_ranges.h),
 * against the same model evaluated after the law: a lattice of 16 x 16 x 12 spheres pressed
 * together (spacing 0.998 diameters, jittered) on a floor and released, so that its contacts
 * end one after another and none begin, with random temperatures (300-500 K); conduction by
 * eq. 34's area (the list carries its geometry) and by projection (a lean list that the law
 * confirms: it only marks the contacts that ended while the conduction reads the list). After every
 * step the step's heat powers must equal a fresh evaluation's of the same state to the bit,
 * on 1, 2 and 3 threads; on 2 and 3 every step's conduction must have run in the law's region
 * (on one thread none), and with projection some of those steps must have dropped ended
 * contacts (a conduction that counted them differs there).
 */
static void test_conduction_in_law_matches_after_law(void **state)
{
    (void)state;
    enum { M = 16, L = 12, N = M * M * L, STEPS = 120 };
    double *heat = malloc(N * sizeof(double));
    assert_non_null(heat);
    for (int projection = 0; projection <= 1; ++projection)
        for (int t = 1; t <= 3; ++t) {
            scene s;
            conducting_scene(&s, t);
            scene_open(&s, "hertz_mindlin", 0);
            scene_floor(&s, -0.499e-3); /* touching the bottom layer: the law's ranged walls */
            OK(sinter_force_model_set(s.contact, "rolling", 0.0));
            sinter_heat_model *cond = NULL;
            OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
            OK(sinter_heat_model_set(cond, "area", projection));
            OK(sinter_stepper_add_heat(s.st, cond));
            uint64_t seed = 31;
            const double r = 0.5e-3, a = 2 * r * 0.998;
            for (int k = 0; k < L; ++k)
                for (int j = 0; j < M; ++j)
                    for (int i = 0; i < M; ++i) {
                        const double dz = 1e-6 * lcg(&seed), dy = 1e-6 * lcg(&seed),
                                     dx = 1e-6 * lcg(&seed);
                        scene_add(&s, i * a + dx, j * a + dy, k * a + dz, r);
                    }
            for (size_t i = 0; i < N; ++i)
                s.ps->temperature[i] = 300.0 + 200.0 * lcg(&seed);
            OK(sinter_stepper_set_dt(s.st, 1e-5));
            OK(sinter_stepper_set_option(s.st, "thread_choice", 0.0)); /* t threads throughout */
            const int fusing = t > 1 && sinter_threads_allowed(s.ctx) > 1; /* 1 without OpenMP */
            int dropped = 0, partitioned = 0;
            double largest = 0.0;
            for (int k = 0; k < STEPS; ++k) {
                const uint64_t fused = s.st->thermal.law_evaluations, ended = s.st->law_dropped;
                OK(sinter_stepper_step(s.st, 1));
                const int ranges = s.st->pp.chunks.count > 0;
                partitioned += ranges;
                assert_true(s.st->thermal.law_evaluations == fused + (uint64_t)(fusing && ranges));
                dropped += s.st->law_dropped > ended;
                memcpy(heat, s.ps->heat, N * sizeof(double));
                OK(sinter_stepper_evaluate(s.st)); /* conduction after the law */
                assert_memory_equal(heat, s.ps->heat, N * sizeof(double));
                for (size_t i = 0; i < N; ++i)
                    largest = fmax(largest, fabs(heat[i]));
            }
            print_message("conduction in the law's region: area %s, %d thread(s): %d of %d "
                          "steps partitioned, %d dropped ended contacts, %zu contacts left, "
                          "largest power %.3g W\n",
                          projection ? "projection" : "eq. 34", t, partitioned, STEPS, dropped,
                          s.st->pp.count, largest);
            assert_true(partitioned >= STEPS - 10);
            assert_true(largest > 0.0); /* heat flowed */
            if (projection)
                assert_true(dropped > 10);
            sinter_heat_model_destroy(cond); /* before its context */
            scene_close(&s);
        }
    free(heat);
}

/*
 * The colliding cloud with the rolling model on (6 values of history) and the material's
 * rolling friction mu_r set in three phases of 100 steps (`mu`), its rolling damping 0.3.
 * Returns positions, velocities and spins in out (9 n) and the largest rolling spring |Delta
 * theta| committed after each phase in roll[3]. param 0: the model with rolling off.
 */
static void run_rolling_phases(int param, const double mu[3], double *out, size_t n, double roll[3])
{
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500, 0.3, 0.4);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_DAMPING_RATIO, 0.3));
    scene_open(&s, "hertz_mindlin", 1);
    OK(sinter_force_model_set(s.contact, "rolling", param));
    add_cloud(&s, n, 16, 2.02e-3, 0.9, 0.1, 19);
    OK(sinter_stepper_set_dt(s.st, 2e-5));
    for (int phase = 0; phase < 3; ++phase) {
        OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, mu[phase]));
        OK(sinter_particles_set_material(s.ps, 0, s.mat));
        OK(sinter_stepper_step(s.st, 100));
        /* particle pairs and particle-wall pairs */
        const sinter_history *h[2] = {&s.st->forces[0].pp, &s.st->forces[0].pw};
        const size_t pairs[2] = {s.st->nb.pp.count, s.st->nb.pw.count};
        roll[phase] = 0.0;
        for (int k = 0; k < 2; ++k)
            for (size_t p = 0; p < pairs[k] && h[k]->width == 6; ++p)
                for (int d = 3; d < 6; ++d)
                    roll[phase] = fmax(roll[phase], fabs(h[k]->committed[6 * p + (size_t)d]));
    }
    copy_motion(&s, out, n);
    scene_close(&s);
}

/*
 * Rolling resistance a scene does not use costs nothing (issue 9): with mu_r = 0 in every
 * material every rolling moment is 0 (eq. 17: the slider's limit mu_r r* |f_n|), so the
 * rolling model runs the blocked law without rolling and its trajectory is that of the model
 * with rolling off, to the bit, with the rolling spring held at zero (phase 2, after springs
 * loaded in phase 1). With mu_r > 0 the rolling law acts: the trajectories part.
 */
static void test_rolling_without_rolling_friction_is_rolling_off(void **state)
{
    (void)state;
    enum { N = 16 * 16 * 12 };
    double *off = malloc(9 * N * sizeof(double)), *on = malloc(9 * N * sizeof(double));
    assert_non_null(off);
    assert_non_null(on);
    double roll[3];
    const double none[3] = {0.0, 0.0, 0.0}, middle[3] = {0.05, 0.0, 0.05};
    run_rolling_phases(0, none, off, N, roll);
    run_rolling_phases(1, none, on, N, roll);
    assert_memory_equal(off, on, 9 * N * sizeof(double));
    assert_true(roll[0] == 0.0 && roll[1] == 0.0 && roll[2] == 0.0);
    run_rolling_phases(1, middle, on, N, roll);
    print_message("rolling springs after the phases: %.3g, %.3g, %.3g rad\n", roll[0], roll[1],
                  roll[2]);
    assert_true(roll[0] > 0.0);
    assert_true(roll[1] == 0.0); /* no rolling friction: held at zero */
    assert_true(roll[2] > 0.0);
    size_t parted = 0;
    for (size_t k = 0; k < 9 * N; ++k)
        parted += off[k] != on[k];
    assert_true(parted > N); /* most particles moved differently */
    free(off);
    free(on);
}

/* The threaded cell-grid build gives the same list, pair by pair, for 1, 2 and 3 threads: a
 * dense cloud of 12000 spheres (about 9 pairs each, so the first build overflows the
 * per-thread segments sized for 4 and finishes them serially) and a rebuild after a shuffle. */
static void test_pair_list_independent_of_thread_count(void **state)
{
    (void)state;
    enum { N = 20000 }; /* the bounding box and cell sort run on threads from 16384 */
    size_t counts[3], rebuilt[3], walls[3];
    uint32_t *ref_i = NULL, *ref_j = NULL, *ref_from = NULL, *ref_wi = NULL, *ref_wj = NULL;
    uint32_t *same_layout = NULL;
    size_t same_count = 0;
    for (int t = 0; t < 3; ++t) {
        scene s;
        sinter_neighbors nb;
        dense_cloud(&s, t + 1, N, &nb);
        /* two walls through the cloud (the wall pairs are found on threads too) */
        const double p0[3] = {0.0, 0.0, 0.01}, n0[3] = {0.0, 0.0, 1.0};
        const double p1[3] = {0.02, 0.0, 0.0}, n1[3] = {-1.0, 0.0, 0.0};
        OK(sinter_walls_add_plane(s.walls, p0, n0, s.wall_mat, NULL));
        OK(sinter_walls_add_plane(s.walls, p1, n1, s.wall_mat, NULL));
        OK(sinter_neighbors_build(&nb, s.ps, s.walls));
        counts[t] = nb.pp.count;
        walls[t] = nb.pw.count;
        for (size_t p = 0; p < nb.pw.count; ++p) /* by particle, then wall; keys by id */
            assert_true(p == 0 || nb.pw.i[p] > nb.pw.i[p - 1] ||
                        (nb.pw.i[p] == nb.pw.i[p - 1] && nb.pw.j[p] > nb.pw.j[p - 1]));
        if (t == 0) {
            ref_i = malloc(nb.pp.count * sizeof(uint32_t));
            ref_j = malloc(nb.pp.count * sizeof(uint32_t));
            memcpy(ref_i, nb.pp.i, nb.pp.count * sizeof(uint32_t));
            memcpy(ref_j, nb.pp.j, nb.pp.count * sizeof(uint32_t));
            assert_true(nb.pp.count > 4 * (size_t)N + 2048);
            ref_wi = malloc(nb.pw.count * sizeof(uint32_t));
            ref_wj = malloc(nb.pw.count * sizeof(uint32_t));
            memcpy(ref_wi, nb.pw.i, nb.pw.count * sizeof(uint32_t));
            memcpy(ref_wj, nb.pw.j, nb.pw.count * sizeof(uint32_t));
            assert_true(nb.pw.count > 1000);
            print_message("%zu pairs, %zu wall pairs\n", nb.pp.count, nb.pw.count);
        } else {
            assert_int_equal(nb.pp.count, counts[0]);
            assert_memory_equal(nb.pp.i, ref_i, nb.pp.count * sizeof(uint32_t));
            assert_memory_equal(nb.pp.j, ref_j, nb.pp.count * sizeof(uint32_t));
            assert_int_equal(walls[t], walls[0]);
            assert_memory_equal(nb.pw.i, ref_wi, nb.pw.count * sizeof(uint32_t));
            assert_memory_equal(nb.pw.j, ref_wj, nb.pw.count * sizeof(uint32_t));
        }
        for (size_t p = 0; p < nb.pw.count; ++p)
            assert_int_equal(nb.pw.key_i[p], s.ps->id[nb.pw.i[p]]);
        for (size_t p = 0; p < nb.pp.count; ++p) {
            assert_int_equal(nb.pp.key_i[p], s.ps->id[nb.pp.i[p]]);
            assert_int_equal(nb.pp.key_j[p], s.ps->id[nb.pp.j[p]]);
            assert_true(nb.pp.key_i[p] < nb.pp.key_j[p]);
        }
        /* the upper half of the cloud lifted by 1.5 cm (the pairs across the cut go): rebuilt
         * with the same particle order (the build that keeps the particle ranges' segments
         * and matches by runs), the list must be the one thread's */
        for (size_t i = 0; i < N; ++i)
            if (s.ps->x[3 * i + 2] > 0.015)
                s.ps->x[3 * i + 2] += 0.015;
        OK(sinter_neighbors_build(&nb, s.ps, s.walls));
        if (t == 0) {
            same_count = nb.pp.count;
            same_layout = malloc(2 * same_count * sizeof(uint32_t));
            memcpy(same_layout, nb.pp.i, nb.pp.count * sizeof(uint32_t));
            memcpy(same_layout + nb.pp.count, nb.pp.j, nb.pp.count * sizeof(uint32_t));
        } else {
            assert_int_equal(nb.pp.count, same_count);
            assert_memory_equal(nb.pp.i, same_layout, nb.pp.count * sizeof(uint32_t));
            assert_memory_equal(nb.pp.j, same_layout + same_count, nb.pp.count * sizeof(uint32_t));
        }
        /* reversed order in memory: every pair is found again, through the id-keyed match */
        size_t order[N];
        for (size_t i = 0; i < N; ++i)
            order[i] = N - 1 - i;
        OK(sinter_particles_permute(s.ps, order));
        OK(sinter_neighbors_build(&nb, s.ps, s.walls));
        rebuilt[t] = nb.pp.count;
        size_t matched = 0;
        for (size_t p = 0; p < nb.pp.count; ++p)
            matched += nb.pp.from[p] != SINTER_NO_PAIR;
        assert_int_equal(matched, nb.pp.count);
        if (t == 0) {
            ref_from = malloc(nb.pp.count * sizeof(uint32_t));
            memcpy(ref_from, nb.pp.from, nb.pp.count * sizeof(uint32_t));
        } else {
            assert_memory_equal(nb.pp.from, ref_from, nb.pp.count * sizeof(uint32_t));
        }
        sinter_neighbors_free(&nb);
        scene_close(&s);
    }
    assert_int_equal(rebuilt[1], rebuilt[0]);
    assert_int_equal(rebuilt[2], rebuilt[0]);
    free(ref_i);
    free(ref_j);
    free(ref_from);
    free(ref_wi);
    free(ref_wj);
    free(same_layout);
}

/* A copy of a contact list's membership, to compare the next search with. */
typedef struct membership {
    size_t count, pairs;
    uint32_t *i, *j, *pair, *to_contact;
    uint64_t revision;
} membership;

static void take_membership(membership *m, const sinter_contact_list *c)
{
    m->count = c->count;
    m->pairs = c->pair_count;
    m->revision = c->revision;
    m->i = realloc(m->i, (c->count + 1) * sizeof(uint32_t));
    m->j = realloc(m->j, (c->count + 1) * sizeof(uint32_t));
    m->pair = realloc(m->pair, (c->count + 1) * sizeof(uint32_t));
    m->to_contact = realloc(m->to_contact, (c->pair_count + 1) * sizeof(uint32_t));
    memcpy(m->i, c->i, c->count * sizeof(uint32_t));
    memcpy(m->j, c->j, c->count * sizeof(uint32_t));
    memcpy(m->pair, c->pair, c->count * sizeof(uint32_t));
    memcpy(m->to_contact, c->pair_to_contact, c->pair_count * sizeof(uint32_t));
}

/* Lists a and b hold the same contacts, in the same order, over `pairs` candidate pairs. */
static void assert_same_contacts(const sinter_contact_list *a, const sinter_contact_list *b,
                                 size_t pairs)
{
    assert_int_equal(a->count, b->count);
    assert_memory_equal(a->i, b->i, b->count * sizeof(uint32_t));
    assert_memory_equal(a->j, b->j, b->count * sizeof(uint32_t));
    assert_memory_equal(a->pair, b->pair, b->count * sizeof(uint32_t));
    assert_memory_equal(a->pair_to_contact, b->pair_to_contact, pairs * sizeof(uint32_t));
}

/* The first contact index and the first pair at which list c differs from m (SIZE_MAX when
 * it does not). */
static void first_difference(const membership *m, const sinter_contact_list *c, size_t *contact,
                             size_t *pair)
{
    *contact = *pair = SIZE_MAX;
    const size_t both = m->count < c->count ? m->count : c->count;
    for (size_t k = 0; k < both && *contact == SIZE_MAX; ++k)
        if (m->i[k] != c->i[k] || m->j[k] != c->j[k] || m->pair[k] != c->pair[k])
            *contact = k;
    if (*contact == SIZE_MAX && m->count != c->count)
        *contact = both;
    for (size_t p = 0; p < c->pair_count && *pair == SIZE_MAX; ++p)
        if (m->to_contact[p] != c->pair_to_contact[p])
            *pair = p;
}

/* The first pair of nb not in c's list whose spheres now overlap (nb->pp.count: none). */
static size_t first_new_pair(const sinter_neighbors *nb, const sinter_contact_list *c,
                             const sinter_particles *ps)
{
    for (size_t p = 0; p < nb->pp.count; ++p) {
        const uint32_t i = nb->pp.i[p], j = nb->pp.j[p];
        double d2 = 0.0;
        for (int d = 0; d < 3; ++d)
            d2 += (ps->x[3 * j + d] - ps->x[3 * i + d]) * (ps->x[3 * j + d] - ps->x[3 * i + d]);
        const double rs = ps->radius[i] + ps->radius[j];
        if (c->pair_to_contact[p] == SINTER_NO_PAIR && d2 < rs * rs)
            return p;
    }
    return nb->pp.count;
}

/* Grow the spheres of the first pair apart from pair `from` on just into contact (each by
 * 0.51 of the gap), where that makes it the first new contact of c's pairs; returns it. */
static size_t grow_into_contact(const sinter_neighbors *nb, const sinter_contact_list *c,
                                sinter_particles *ps, size_t from)
{
    for (size_t p = from; p < nb->pp.count; ++p) {
        const uint32_t i = nb->pp.i[p], j = nb->pp.j[p];
        if (c->pair_to_contact[p] != SINTER_NO_PAIR)
            continue;
        double d2 = 0.0;
        for (int d = 0; d < 3; ++d)
            d2 += (ps->x[3 * j + d] - ps->x[3 * i + d]) * (ps->x[3 * j + d] - ps->x[3 * i + d]);
        const double ri = ps->radius[i], rj = ps->radius[j];
        const double gap = sqrt(d2) - ri - rj;
        ps->radius[i] = ri + 0.51 * gap;
        ps->radius[j] = rj + 0.51 * gap;
        if (first_new_pair(nb, c, ps) == p)
            return p;
        ps->radius[i] = ri; /* it made others touch before it: the next */
        ps->radius[j] = rj;
    }
    fail_msg("no pair from %zu on could be grown into contact alone", from);
    return nb->pp.count;
}

/* Wall lists a and b hold the same contacts with the same geometry, partition and pairs. */
static void assert_same_wall_contacts(const sinter_contact_list *a, const sinter_contact_list *b)
{
    assert_int_equal(a->count, b->count);
    assert_int_equal(a->geometry, 1);
    assert_int_equal(b->geometry, 1);
    const size_t n = a->count;
    assert_memory_equal(a->i, b->i, n * sizeof(uint32_t));
    assert_memory_equal(a->j, b->j, n * sizeof(uint32_t));
    assert_memory_equal(a->pair, b->pair, n * sizeof(uint32_t));
    assert_memory_equal(a->n, b->n, 3 * n * sizeof(double));
    assert_memory_equal(a->delta, b->delta, n * sizeof(double));
    assert_memory_equal(a->dist, b->dist, n * sizeof(double));
    assert_memory_equal(a->area, b->area, n * sizeof(double));
    assert_memory_equal(a->branch, b->branch, n * sizeof(double));
    assert_int_equal(a->pair_count, b->pair_count);
    assert_memory_equal(a->pair_to_contact, b->pair_to_contact, a->pair_count * sizeof(uint32_t));
    assert_int_equal(a->chunks.count, b->chunks.count);
    assert_memory_equal(a->chunks.qlo, b->chunks.qlo, sizeof(a->chunks.qlo));
}

/*
 * A wall search over the same pairs as the last one compares the contacts as it goes and,
 * when none came or went, renews their geometry in place and keeps the revision (issue 9).
 * A layer of spheres on a floor between two side walls, on 1-3 threads (the search is
 * threaded from 1024 pairs): after rounds that move every sphere a little (the membership
 * kept), lift the first contact off, press a sphere apart into contact, or move nothing, the
 * kept list must equal a fresh one in every field, and its revision change exactly when the
 * membership did.
 */
static void test_wall_search_matches_a_fresh_one(void **state)
{
    (void)state;
    enum { N = 3000, ROUNDS = 5 };
    for (int t = 1; t <= 3; ++t) {
        scene s;
        scene_init(&s);
        OK(sinter_ctx_set_threads(s.ctx, t));
        scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
        scene_open(&s, "hertz_mindlin", 0);
        scene_floor(&s, 0.0);
        const double px[3] = {0, 0, 0}, nx[3] = {1, 0, 0};
        const double qx[3] = {0.02, 0, 0}, mx[3] = {-1, 0, 0};
        OK(sinter_walls_add_plane(s.walls, px, nx, s.wall_mat, NULL));
        OK(sinter_walls_add_plane(s.walls, qx, mx, s.wall_mat, NULL));
        uint64_t seed = 5;
        for (size_t k = 0; k < N; ++k) { /* centres within 0.1 r of touching the floor */
            const double r = 0.4e-3 * (0.5 + lcg(&seed));
            const double z = r * (0.9 + 0.2 * lcg(&seed)), y = 0.02 * lcg(&seed),
                         x = 0.02 * lcg(&seed);
            scene_add(&s, x, y, z, r);
        }
        sinter_neighbors nb;
        sinter_neighbors_init(&nb, s.ctx, 2e-4);
        OK(sinter_neighbors_build(&nb, s.ps, s.walls));
        assert_true(nb.pw.count > 2048);
        sinter_contact_list kept;
        memset(&kept, 0, sizeof(kept));
        double *x = s.ps->x;
        const double *r = s.ps->radius;
        for (int round = 0; round < ROUNDS; ++round) {
            const uint64_t revision = kept.revision;
            uint32_t *before = NULL;
            if (round > 0) {
                before = malloc(kept.pair_count * sizeof(uint32_t));
                memcpy(before, kept.pair_to_contact, kept.pair_count * sizeof(uint32_t));
            }
            if (round == 1) /* every sphere down by 1e-9 of its radius: the same contacts */
                for (size_t i = 0; i < N; ++i)
                    x[3 * i + 2] -= 1e-9 * r[i];
            if (round == 2) /* the first contact's sphere lifted off the floor */
                x[3 * kept.i[0] + 2] = 1.05 * r[kept.i[0]];
            if (round == 3) /* a sphere apart, pressed onto the floor */
                for (size_t p = 0; p < nb.pw.count; ++p) {
                    const uint32_t i = nb.pw.i[p];
                    if (nb.pw.j[p] == 0 && kept.pair_to_contact[p] == SINTER_NO_PAIR &&
                        x[3 * i] > 0.001 && x[3 * i] < 0.019) {
                        x[3 * i + 2] = 0.95 * r[i];
                        break;
                    }
                }
            OK(sinter_contacts_find_pw(s.ctx, &kept, &nb.pw, s.ps, s.walls, NULL));
            sinter_contact_list fresh;
            memset(&fresh, 0, sizeof(fresh));
            OK(sinter_contacts_find_pw(s.ctx, &fresh, &nb.pw, s.ps, s.walls, NULL));
            assert_true(fresh.count > 1000 && fresh.count < nb.pw.count);
            assert_true(fresh.chunks.count > 0);
            assert_same_wall_contacts(&kept, &fresh);
            /* split by a pair partition's particle ranges (the owners): the same contacts;
             * its runs hold each range's contacts, and all of them */
            const sinter_chunks owner = {.count = 4, .plo = {0, N / 5, N / 2, 2 * N / 3, N}};
            sinter_contact_list owned;
            memset(&owned, 0, sizeof(owned));
            OK(sinter_contacts_find_pw(s.ctx, &owned, &nb.pw, s.ps, s.walls, &owner));
            assert_same_wall_contacts(&owned, &fresh);
            size_t qlo[SINTER_CHUNKS_MAX + 1];
            assert_int_equal(sinter_chunks_wall_runs(&owner, &owned, qlo), 4);
            assert_int_equal(qlo[0], 0);
            assert_int_equal(qlo[4], owned.count);
            for (int u = 0; u < 4; ++u) {
                assert_true(qlo[u + 1] > qlo[u]);
                for (size_t q = qlo[u]; q < qlo[u + 1]; ++q)
                    assert_true(owned.i[q] >= owner.plo[u] && owned.i[q] < owner.plo[u + 1]);
            }
            sinter_contact_list_free(s.ctx, &owned);
            if (round > 0) {
                const int changed = round == 2 || round == 3;
                assert_int_equal(
                    memcmp(before, kept.pair_to_contact, kept.pair_count * sizeof(uint32_t)) != 0,
                    changed);
                assert_int_equal(kept.revision != revision, changed);
            }
            free(before);
            sinter_contact_list_free(s.ctx, &fresh);
        }
        sinter_contact_list_free(s.ctx, &kept);
        sinter_neighbors_free(&nb);
        scene_close(&s);
    }
}

/*
 * A lean search over the same pairs as the last one checks the list it holds before it
 * writes (contacts.c, verify_range; issue 9). After rounds in which nothing changes, or
 * particles shrink out of or grow into contact near the start, the middle or the end of the
 * list, the list must equal one found from scratch, entry for entry, with the particle
 * ranges of its first search, for 1, 2 and 3 threads (the threaded search checks and moves
 * ranges); its
 * revision must stay exactly when nothing changed, and the change it records must start no
 * later than the first entry that differs (history commits clear and copy only from there).
 */
static void test_lean_search_matches_a_fresh_one(void **state)
{
    (void)state;
    enum { N = 12000, ROUNDS = 10 };
    for (int t = 1; t <= 3; ++t) {
        scene s;
        sinter_neighbors nb;
        dense_cloud(&s, t, N, &nb);
        sinter_contact_list kept, late;
        memset(&kept, 0, sizeof(kept));
        memset(&late, 0, sizeof(late));
        membership before;
        memset(&before, 0, sizeof(before));
        double *r = s.ps->radius;
        const double *x = s.ps->x;
        int kept_revision = 0, changed = 0;
        size_t plo_before[SINTER_CHUNKS_MAX + 1];
        for (int round = 0; round < ROUNDS; ++round) {
            /* rounds 1, 4, 8 change nothing; the others shrink a particle out of its contacts
             * (at the start, middle and end of the list) or grow a pair into contact (the
             * first, the last, and one at 3/5 of the pairs: with threads, the pairs from it
             * on are searched on threads) */
            const size_t at[ROUNDS] = {0, 0, 3, kept.count / 2, 0, kept.count - 4, 0, 0, 0, 0};
            if (round == 2 || round == 3 || round == 5)
                r[kept.i[at[round]]] *= 0.3;
            if (round == 9) { /* the deferred search's new contact: with threads, the pairs
                               * from it on (8192 or more, less than half) on threads */
                const size_t p = grow_into_contact(&nb, &kept, s.ps, nb.pp.count * 3 / 5);
                assert_in_range(nb.pp.count - p, 8192, nb.pp.count / 2);
            }
            if (round == 6 || round == 7) { /* the first / last pair apart, now touching */
                for (size_t q = 0; q < nb.pp.count; ++q) {
                    const size_t p = round == 6 ? q : nb.pp.count - 1 - q;
                    if (kept.pair_to_contact[p] != SINTER_NO_PAIR)
                        continue;
                    const uint32_t i = nb.pp.i[p], j = nb.pp.j[p];
                    double d2 = 0.0;
                    for (int d = 0; d < 3; ++d)
                        d2 += (x[3 * j + d] - x[3 * i + d]) * (x[3 * j + d] - x[3 * i + d]);
                    r[i] = r[j] = 0.51 * sqrt(d2);
                    break;
                }
            }
            OK(sinter_contacts_find_pp_lean(s.ctx, &kept, &nb.pp, s.ps));
            /* the same by a deferred search whose contacts a law confirms: here the test of
             * the search written out, each contact that fails it marked and the first given
             * to confirm; on round 2 as if the law had not run (sinter_contacts_check) */
            int deferred = 0;
            OK(sinter_contacts_find_pp_deferred(s.ctx, &late, &nb.pp, s.ps, &deferred));
            /* deferred over the same pairs; with threads, new contacts at the first pair
             * (round 6) send the search whole, and the next one too (spaced out); a build
             * without OpenMP has one thread whatever t */
            const int one_thread = sinter_threads(s.ctx) == 1;
            assert_int_equal(deferred, round > 0 && (one_thread || (round != 6 && round != 7)));
            assert_int_equal(late.unconfirmed, deferred);
            size_t ended = SIZE_MAX;
            for (size_t q = 0; deferred && q < late.count; ++q) {
                const uint32_t i = late.i[q], j = late.j[q];
                double d2 = 0.0;
                for (int d = 0; d < 3; ++d)
                    d2 += (x[3 * j + d] - x[3 * i + d]) * (x[3 * j + d] - x[3 * i + d]);
                assert_int_equal(late.ended[q], 0);
                if (!(d2 < (r[i] + r[j]) * (r[i] + r[j]))) {
                    late.ended[q] = 1;
                    ended = ended < q ? ended : q;
                }
            }
            const int shrunk = round == 2 || round == 3 || round == 5;
            assert_int_equal(ended != SIZE_MAX, deferred && shrunk);
            if (deferred && round == 2) {
                memset(late.ended, 0, late.count);
                sinter_contacts_check(&late, &nb.pp, s.ps);
            } else if (deferred) {
                sinter_contacts_confirm(&late, ended, NULL, 0);
            }
            assert_int_equal(late.unconfirmed, 0);
            assert_same_contacts(&late, &kept, nb.pp.count);
            assert_memory_equal(&late.chunks, &kept.chunks, sizeof(kept.chunks));
            sinter_contact_list fresh;
            memset(&fresh, 0, sizeof(fresh));
            OK(sinter_contacts_find_pp_lean(s.ctx, &fresh, &nb.pp, s.ps));
            assert_true(fresh.count > 1000);
            assert_same_contacts(&kept, &fresh, nb.pp.count);
            assert_int_equal(kept.chunks.count, fresh.chunks.count);
            assert_true(kept.chunks.count > 0);
            /* the particle ranges: made by the first search over the pairs, kept by the
             * others (contacts.c, make_chunks); the contact ranges follow them */
            if (round == 0)
                assert_memory_equal(kept.chunks.plo, fresh.chunks.plo, sizeof(fresh.chunks.plo));
            else
                assert_memory_equal(kept.chunks.plo, plo_before, sizeof(plo_before));
            memcpy(plo_before, kept.chunks.plo, sizeof(plo_before));
            for (int k = 0; k <= kept.chunks.count; ++k) {
                size_t q = 0;
                while (q < kept.count &&
                       (k == kept.chunks.count ||
                        (kept.i[q] < kept.j[q] ? kept.i[q] : kept.j[q]) < kept.chunks.plo[k]))
                    ++q;
                assert_int_equal(kept.chunks.qlo[k], q);
            }
            if (round > 0) {
                size_t contact = 0, pair = 0;
                first_difference(&before, &kept, &contact, &pair);
                const int same = contact == SIZE_MAX && pair == SIZE_MAX;
                assert_int_equal(same, round == 1 || round == 4 || round == 8);
                assert_int_equal(kept.revision == before.revision, same);
                if (!same) {
                    assert_int_equal(kept.change[0].from, before.revision);
                    assert_true(kept.change[0].contact <= contact);
                    assert_true(kept.change[0].pair <= pair);
                    /* one thread records the first difference itself; threads, at worst
                     * the start of the range that holds it (the ranges before agree) */
                    if (t == 1) {
                        assert_int_equal(kept.change[0].contact, contact);
                        assert_int_equal(kept.change[0].pair, pair);
                    } else {
                        const size_t range = pair * (size_t)t / nb.pp.count;
                        size_t lo = nb.pp.count * range / (size_t)t;
                        if (lo > pair) /* the division's rounding */
                            lo = nb.pp.count * (range - 1) / (size_t)t;
                        assert_true(kept.change[0].pair >= lo);
                    }
                    size_t p2 = 0, m2 = 0;
                    sinter_contacts_changed_since(&kept, before.revision, &p2, &m2);
                    assert_true(p2 == kept.change[0].pair && m2 == kept.change[0].contact);
                    ++changed;
                } else {
                    ++kept_revision;
                }
            }
            take_membership(&before, &kept);
            sinter_contact_list_free(s.ctx, &fresh);
        }
        assert_int_equal(kept_revision, 3);
        assert_int_equal(changed, ROUNDS - 1 - 3);
        free(before.i);
        free(before.j);
        free(before.pair);
        free(before.to_contact);
        sinter_contact_list_free(s.ctx, &kept);
        sinter_contact_list_free(s.ctx, &late);
        sinter_neighbors_free(&nb);
        scene_close(&s);
    }
}

/* Neighbour builds of scene s so far. */
static uint64_t builds_of(scene *s)
{
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s->st, &stats));
    return stats.neighbor_builds;
}

/*
 * The integrator reports a bound on the displacement since the neighbour build (the sum of
 * the steps' largest displacements) instead of measuring it, while that is under a quarter
 * of the skin (neighbors.c, sinter_neighbors_add_step; issue 9), and measures beyond. The
 * list must still be rebuilt exactly when a particle has moved half the skin: free spheres
 * drifting at most 1/10.5 of half the skin per step are rebuilt every 11 steps, on 1 and 2
 * threads. A particle moved by the host (a view write) voids the bound: moved 0.3 mm
 * further along its way right after a build, the fastest one closes the skin's half
 * (0.5 mm) 5 steps later, not 11.
 */
static void test_displacement_bound_keeps_rebuilds(void **state)
{
    (void)state;
    enum { N = 5000 };
    const double skin = 1e-3, h = 1e-4, vmax = 0.5 * skin / (10.5 * h);
    for (int t = 1; t <= 2; ++t) {
        scene s;
        scene_init(&s);
        OK(sinter_ctx_set_threads(s.ctx, t));
        scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
        scene_open(&s, "hertz_mindlin", 0);
        uint64_t seed = 3;
        for (size_t k = 0; k < N; ++k) /* 2 cm apart: never in contact */
            scene_add(&s, 2e-2 * (double)(k % 20), 2e-2 * (double)((k / 20) % 20),
                      2e-2 * (double)(k / 400), 0.5e-3);
        for (size_t k = 0; k < N; ++k) { /* the first at vmax along x, the others slower */
            const double u = k == 0 ? 1.0 : 0.9 * lcg(&seed);
            const double v[3] = {u * vmax, 0.0, 0.0};
            set3(&s, SINTER_FIELD_VELOCITY, k, v);
        }
        OK(sinter_stepper_set_skin(s.st, skin));
        OK(sinter_stepper_set_dt(s.st, h));
        OK(sinter_stepper_step(s.st, 1)); /* the first build, then one step */
        const uint64_t first = builds_of(&s);
        OK(sinter_stepper_step(s.st, 109)); /* 110 steps since the first build */
        assert_int_equal(builds_of(&s) - first, 10);
        double x[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x);
        x[0] += 0.3e-3;
        set3(&s, SINTER_FIELD_POSITION, 0, x);
        OK(sinter_stepper_step(s.st, 4));
        assert_int_equal(builds_of(&s) - first, 10);
        OK(sinter_stepper_step(s.st, 1));
        assert_int_equal(builds_of(&s) - first, 11);
        scene_close(&s);
    }
}

/* A host force model adding nothing but a NaN on particle 0's force at its fail_at-th call
 * (counted from 1; 0: never): one rejected step. */
typedef struct nan_once {
    int calls, fail_at;
} nan_once;

static int nan_once_force(const sinter_state_view *view, double *force, double *torque, void *user)
{
    (void)view;
    (void)torque;
    nan_once *p = user;
    if (++p->calls == p->fail_at)
        force[0] = NAN;
    return 0;
}

/* Whether the neighbour list's displacement bound, when it claims to hold, bounds the
 * particles' largest displacement since the build. */
static int bound_covers_displacement(scene *s)
{
    const sinter_neighbors *nb = &s->st->nb;
    if (!sinter_neighbors_bound_holds(nb, s->ps))
        return 1;
    double moved = 0.0;
    for (size_t k = 0; k < 3 * s->ps->count; ++k)
        moved = fmax(moved, fabs(s->ps->x[k] - nb->x_ref[k]));
    return moved <= nb->moved_bound;
}

/*
 * A rejected step puts the particles back where they were, and what the integrator measured
 * of the undone positions must go with them: here the rejected step rebuilt the neighbour
 * list at its new positions (bound 0 there), so the restored particles are one step from
 * x_ref. Free spheres moving at 0.1 skin a step; the bound, whenever it claims to hold, must
 * cover the displacement, after the rejection and over the 30 steps after it.
 */
static void test_displacement_bound_after_a_rejected_step(void **state)
{
    (void)state;
    const double skin = 1e-4, h = 1e-5, v = 0.1 * skin / h;
    int fail_call = 0; /* attempt 0 finds the call of the rebuild's step; 1 makes it fail */
    for (int attempt = 0; attempt < 2; ++attempt) {
        scene s;
        scene_init(&s);
        scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
        scene_open(&s, "hertz_mindlin", 0);
        for (int k = 0; k < 8; ++k) { /* 1 cm apart: never in contact */
            scene_add(&s, 1e-2 * k, 0.0, 0.0, 0.5e-3);
            const double u[3] = {v * (k % 2 ? 1.0 : -0.5), 0.0, 0.0};
            set3(&s, SINTER_FIELD_VELOCITY, (size_t)k, u);
        }
        nan_once job = {0, attempt == 0 ? 0 : fail_call};
        sinter_force_callbacks cb;
        memset(&cb, 0, sizeof(cb));
        cb.struct_size = sizeof(cb);
        cb.particles = nan_once_force;
        sinter_force_model *fm = NULL;
        OK(sinter_force_model_create_host(&fm, s.ctx, "nan_once", &cb, &job));
        OK(sinter_stepper_add_force(s.st, fm));
        OK(sinter_stepper_set_skin(s.st, skin));
        OK(sinter_stepper_set_dt(s.st, h));
        OK(sinter_stepper_step(s.st, 1)); /* the first build, then one step */
        if (attempt == 0) {
            const uint64_t first = builds_of(&s);
            for (int k = 0; k < 20 && fail_call == 0; ++k) {
                OK(sinter_stepper_step(s.st, 1));
                if (builds_of(&s) > first)
                    fail_call = job.calls; /* the evaluation after that step's rebuild */
            }
            assert_true(fail_call > 0);
        } else {
            sinter_status st = SINTER_OK;
            while (st == SINTER_OK)
                st = sinter_stepper_step(s.st, 1);
            assert_int_equal(st, SINTER_ERR_UNSTABLE);
            assert_true(job.calls >= fail_call); /* (the rollback may evaluate again) */
            assert_true(bound_covers_displacement(&s));
            for (int k = 0; k < 30; ++k) {
                OK(sinter_stepper_step(s.st, 1));
                assert_true(bound_covers_displacement(&s));
            }
        }
        sinter_stepper_destroy(s.st);
        s.st = NULL;
        sinter_force_model_destroy(fm);
        scene_close(&s);
    }
}

/*
 * A packed lattice whose top layer rattles: its contacts open and close step after step
 * while the rest stay. Found lean (projection conduction), the list is kept or rewritten
 * from its first change, and the history commit clears and copies only from where it
 * changed (history.c); with eq. 34 conduction the list carries the geometry and is written
 * whole every step, and every commit is a full one. The lean list's only contact model
 * tests the contacts in its law (sinter_contacts_find_pp_deferred): the search checks only
 * the pairs out of contact, and the law drops the contacts that ended. The motion must be
 * the same, bit for bit, for 1 and 2 threads (2 ranges of the partition); the lean runs must
 * have kept their list on some steps and changed it past the start on others, and their law
 * must have confirmed the list on some steps and dropped contacts on others.
 */
static void run_rattling(int threads, int heat, double skin, double *out, size_t n, int *kept,
                         int *partial, int *confirmed, int *dropped)
{
    scene s;
    conducting_scene(&s, threads);
    scene_open(&s, "hertz_mindlin", 1);
    if (skin > 0.0)
        OK(sinter_stepper_set_skin(s.st, skin));
    OK(sinter_force_model_set(s.contact, "rolling", 0.0));
    scene_floor(&s, 0.0);
    sinter_heat_model *cond = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_heat_model_set(cond, "area", heat == 2 ? 1.0 : 0.0));
    OK(sinter_stepper_add_heat(s.st, cond));
    const double r = 0.5e-3, a = 2 * r * 0.999;
    const size_t side = 12;
    /* side walls touching the lattice keep it packed */
    const double wp[4][3] = {{0, 0, 0}, {side * a, 0, 0}, {0, 0, 0}, {0, side * a, 0}};
    const double wn[4][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < 4; ++k)
        OK(sinter_walls_add_plane(s.walls, wp[k], wn[k], s.wall_mat, NULL));
    uint64_t seed = 7;
    for (size_t k = 0; k < n; ++k)
        scene_add(&s, ((double)(k % side) + 0.5) * a, ((double)(k / side % side) + 0.5) * a,
                  ((double)(k / (side * side)) + 0.5) * a, r);
    for (size_t k = n - side * side; k < n; ++k) { /* the top layer rattles */
        const double vx = 0.02 * (lcg(&seed) - 0.5), vy = 0.02 * (lcg(&seed) - 0.5),
                     vz = 0.02 * (lcg(&seed) - 0.5);
        const double v[3] = {vx, vy, vz};
        set3(&s, SINTER_FIELD_VELOCITY, k, v);
    }
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    OK(sinter_stepper_step(s.st, 0));
    *kept = *partial = 0;
    for (int step = 0; step < 150; ++step) {
        const uint64_t revision = s.st->pp.revision;
        OK(sinter_stepper_step(s.st, 1));
        if (s.st->pp.revision == revision)
            ++*kept;
        else if (s.st->pp.change[0].pair > 0)
            ++*partial;
    }
    /* the commits swap, unless the skin holds many more pairs than contacts */
    assert_int_equal(s.st->forces[0].pp.by_pair, skin == 0.0);
    *confirmed = (int)s.st->law_confirmed;
    *dropped = (int)s.st->law_dropped;
    copy_motion(&s, out, n);
    sinter_heat_model_destroy(cond);
    scene_close(&s);
}

static void test_commit_follows_a_changing_list(void **state)
{
    (void)state;
    enum { N = 12 * 12 * 12, SIZE = 9 * N };
    double *whole = malloc(SIZE * sizeof(double)), *lean = malloc(SIZE * sizeof(double));
    int kept = 0, partial = 0, confirmed = 0, dropped = 0;
    /* skin 0.6 mm: the diagonal neighbours are candidate pairs too, so the trial history is
     * indexed by contact and moves with the contacts the law drops */
    const double skins[2] = {0.0, 0.6e-3};
    for (int k = 0; k < 2; ++k) {
        run_rattling(1, 1, skins[k], whole, N, &kept, &partial, &confirmed, &dropped);
        assert_int_equal(kept, 0); /* the list with geometry is written every step */
        assert_int_equal(partial, 0);
        assert_int_equal(confirmed, 0);
        for (int threads = 1; threads <= 2; ++threads) {
            run_rattling(threads, 2, skins[k], lean, N, &kept, &partial, &confirmed, &dropped);
            print_message("skin %g m, %d thread(s): list kept on %d steps, changed past its "
                          "start on %d; confirmed by the law on %d, of which it dropped "
                          "contacts on %d\n",
                          skins[k], threads, kept, partial, confirmed, dropped);
            assert_true(kept >= 3 && partial >= 10);
            assert_true(confirmed >= 10 && dropped >= 5 && confirmed - dropped >= 5);
            assert_memory_equal(lean, whole, SIZE * sizeof(double));
        }
    }
    free(whole);
    free(lean);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pair_list_matches_brute_force),
        cmocka_unit_test(test_trajectory_independent_of_rebuilds_and_order),
        cmocka_unit_test(test_rolling_restart_on_threads),
        cmocka_unit_test(test_partitioned_law_matches_hertz),
        cmocka_unit_test(test_results_independent_of_thread_count),
        cmocka_unit_test(test_colliding_cloud_independent_of_thread_count),
        cmocka_unit_test(test_rolling_without_rolling_friction_is_rolling_off),
        cmocka_unit_test(test_partitioned_conduction_conserves_energy),
        cmocka_unit_test(test_partitioned_law_balances_walls),
        cmocka_unit_test(test_ranges_shared_by_threads),
        cmocka_unit_test(test_conduction_in_law_matches_after_law),
        cmocka_unit_test(test_partitioned_drag),
        cmocka_unit_test(test_partitioned_heat_sources),
        cmocka_unit_test(test_partitioned_domain),
        cmocka_unit_test(test_pair_list_independent_of_thread_count),
        cmocka_unit_test(test_lean_search_matches_a_fresh_one),
        cmocka_unit_test(test_wall_search_matches_a_fresh_one),
        cmocka_unit_test(test_commit_follows_a_changing_list),
        cmocka_unit_test(test_displacement_bound_keeps_rebuilds),
        cmocka_unit_test(test_displacement_bound_after_a_rejected_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
