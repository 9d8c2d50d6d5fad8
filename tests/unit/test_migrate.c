/*
 * Export and import of particles with everything the stepper keeps for them (issue 43,
 * src/stepper/migrate.c).
 *
 * The proof is a round trip that must not change a bit. A falling cloud of 64 spheres with
 * friction and rolling resistance (Hertz-Mindlin: a tangential spring and a rolling spring per
 * contact, committed history that the next steps read) falls into a box (wall contacts with
 * history too) for 2500 steps of 20 us; then the particles of odd id leave (export, remove = 1) for
 * a second stepper, which imports them and sends them all back, and the first imports them again.
 * The contacts between two travellers keep their springs only through the records; those between a
 * traveller and a particle that stayed are held on both sides, once each. A reference run, its
 * particles put in the same order in memory (the order decides the pair list's order and so the
 * order of the force sums), continues beside it: after 100 more steps a second round trip
 * (ids 1 and 2 mod 4) through the same second stepper, and after 400 more every field of every
 * particle must be equal bit for bit. A run whose travellers lose their springs differs (the
 * springs are a large part of the forces of a settling bed), so the comparison can fail.
 *
 * The quasi-static copper packing of test_qs_ids.c (a lattice, a triangle whose links are made
 * during the run, a floating pair; ids scrambled) makes the same round trip at 40 s: the links
 * leave with their smaller-id particle (beam and 7DOF neck state) and come back to their old
 * places; the run to 100 s must equal the reference run bit for bit (positions, rotations,
 * links, necks). Damaged, foreign and mismatched streams, and ids held already, are refused
 * with the set unchanged.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_support.h"
#include "core/fnv1a.h"
#include "electric/electric.h"
#include "stepper/migrate.h"
#include "stepper/qs_struct.h"
#include "stepper/stepper.h"

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* ---- the explicit cloud ---- */

enum { CLOUD = 64 };

static void open_cloud(scene *s)
{
    scene_init(s);
    scene_material(s, 1e6, 0.3, 2500, 0.3, 0.4);
    OK(sinter_material_set(s->mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    scene_open(s, "hertz_mindlin", 1);
    OK(sinter_force_model_set(s->contact, "rolling", 1.0));
    OK(sinter_stepper_set_dt(s->st, 2e-5));
    scene_floor(s, -0.001);
    /* side walls: a box of 8.2 mm, so that the cloud settles in four layers */
    for (int d = 0; d < 2; ++d)
        for (int side = 0; side < 2; ++side) {
            double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            p[d] = side ? 7.2e-3 : -1.05e-3;
            n[d] = side ? -1.0 : 1.0;
            OK(sinter_walls_add_plane(s->walls, p, n, s->wall_mat, NULL));
        }
}

/* The cloud of test_contact.c: a jittered 4 x 4 x 4 lattice with random velocities. */
static void fill_cloud(scene *s)
{
    uint64_t seed = 11;
    const double spacing = 2.05e-3;
    for (size_t k = 0; k < CLOUD; ++k)
        scene_add(s, spacing * (double)(k % 4), spacing * (double)((k / 4) % 4),
                  spacing * (double)(k / 16), 1e-3 * (0.8 + 0.2 * lcg(&seed)));
    for (size_t k = 0; k < CLOUD; ++k) {
        const double v[3] = {lcg(&seed) - 0.5, lcg(&seed) - 0.5, lcg(&seed) - 0.5};
        set3(s, SINTER_FIELD_VELOCITY, k, v);
    }
}

/* Every field of every particle, by id (16 doubles each: x, v, w, rot, force, torque,
 * temperature, heat). */
static void by_id(const sinter_particles *ps, double *out, size_t n)
{
    assert_int_equal(ps->count, n);
    for (size_t i = 0; i < n; ++i) {
        const uint64_t id = ps->id[i];
        assert_true(id < n);
        double *o = out + 20 * id;
        const double *vec[6] = {ps->x, ps->v, ps->w, ps->rot, ps->force, ps->torque};
        for (int f = 0; f < 6; ++f)
            memcpy(o + 3 * f, vec[f] + 3 * i, 3 * sizeof(double));
        o[18] = ps->temperature[i];
        o[19] = ps->heat[i];
    }
}

/* Contacts of slot k with a non-zero history of the stepper (pp), and with walls (pw). */
static size_t springs(const sinter_stepper *st, size_t k, int wall)
{
    const sinter_history *h = wall ? &st->forces[k].pw : &st->forces[k].pp;
    size_t n = 0;
    for (size_t a = 0; a < h->active_count; ++a) {
        const double *v = h->committed + h->width * h->active[a];
        int any = 0;
        for (size_t d = 0; d < h->width; ++d)
            any |= v[d] != 0.0;
        n += (size_t)any;
    }
    return n;
}

/* Export the particles of odd id (trip 1; trip 2: id 1 or 2 mod 4) from a (removed), round
 * trip through b, import back.
 * lose_springs: the travellers' staged histories are dropped before they return (the control
 * run that must differ). */
static int g_remove_apart; /* 1: a's export without removal, then sinter_stepper_remove */

static void round_trip(scene *a, scene *b, int trip, int lose_springs, size_t *staged_pp)
{
    size_t idx[CLOUD], n = 0;
    for (size_t i = 0; i < a->ps->count; ++i) {
        const uint64_t id = a->ps->id[i];
        if (trip == 1 ? id % 2 == 1 : id % 4 == 1 || id % 4 == 2)
            idx[n++] = i;
    }
    size_t bytes = 0, written = 0, count = 0;
    OK(sinter_stepper_export_size(a->st, n, idx, &bytes));
    unsigned char *buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(a->st, n, idx, buf, bytes, &written, !g_remove_apart));
    assert_int_equal(written, bytes);
    if (g_remove_apart) { /* the removal without a second record stream */
        assert_int_equal(a->ps->count, CLOUD);
        size_t twice[2] = {idx[0], idx[0]}, outside[1] = {CLOUD};
        assert_int_equal(sinter_stepper_remove(a->st, 2, twice), SINTER_ERR_INVALID);
        assert_int_equal(sinter_stepper_remove(a->st, 1, outside), SINTER_ERR_RANGE);
        assert_int_equal(sinter_stepper_remove(a->st, 1, NULL), SINTER_ERR_NULL);
        assert_int_equal(sinter_stepper_remove(NULL, 0, NULL), SINTER_ERR_NULL);
        OK(sinter_stepper_remove(a->st, 0, NULL));
        assert_int_equal(a->ps->count, CLOUD); /* refused or empty: nothing taken */
        OK(sinter_stepper_remove(a->st, n, idx));
    }
    assert_int_equal(a->ps->count, CLOUD - n);
    OK(sinter_stepper_import(b->st, buf, bytes, &count));
    assert_int_equal(count, n);
    assert_int_equal(b->ps->count, n);
    /* the travellers' contacts wait in b's stage, keyed by ids */
    assert_non_null(b->st->migrate);
    *staged_pp = b->st->migrate->list[0].count;
    if (lose_springs)
        for (size_t k = 0; k < 2 * b->st->migrate->slots; ++k)
            b->st->migrate->list[k].count = 0;
    free(buf);
    /* all of them back */
    size_t all[CLOUD];
    for (size_t i = 0; i < n; ++i)
        all[i] = i;
    OK(sinter_stepper_export_size(b->st, n, all, &bytes));
    buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(b->st, n, all, buf, bytes, &written, 1));
    assert_int_equal(b->ps->count, 0);
    OK(sinter_stepper_import(a->st, buf, written, &count));
    assert_int_equal(count, n);
    free(buf);
}

/* The reference's particles in the order of a's (by id). */
static void same_order(scene *ref, const scene *a)
{
    size_t where[CLOUD], order[CLOUD];
    for (size_t i = 0; i < CLOUD; ++i)
        where[ref->ps->id[i]] = i;
    for (size_t k = 0; k < CLOUD; ++k)
        order[k] = where[a->ps->id[k]];
    OK(sinter_particles_permute(ref->ps, order));
}

static void cloud_run(int lose_springs, double *got, double *want)
{
    scene ref, a, b;
    open_cloud(&ref);
    open_cloud(&a);
    open_cloud(&b);
    fill_cloud(&ref);
    fill_cloud(&a);
    OK(sinter_stepper_step(ref.st, 2500));
    OK(sinter_stepper_step(a.st, 2500));
    /* the bed has what the test is about: springs between particles and with the floor */
    const size_t pp = springs(a.st, 0, 0), pw = springs(a.st, 0, 1);
    assert_true(pp >= 40);
    assert_true(pw >= 8);
    size_t staged = 0;
    round_trip(&a, &b, 1, lose_springs, &staged);
    /* the pair lists are the old layout's until the next step: no index checkpoint of them */
    assert_int_equal(sinter_checkpoint_write(a.st, "/tmp/sinter_migrate_refused.bin"),
                     SINTER_ERR_STATE);
    assert_true(staged >= 20); /* springs between two travellers, or a traveller's, in b */
    int moved = 0;             /* a's order is not the one it started in */
    for (size_t i = 0; i < CLOUD; ++i)
        moved |= a.ps->id[i] != i;
    assert_true(moved);
    same_order(&ref, &a);
    OK(sinter_stepper_step(ref.st, 100));
    OK(sinter_stepper_step(a.st, 100));
    /* a second round trip through the same second stepper, of other particles, which must find
     * nothing of the first there (a staged entry of particles it no longer has would come back
     * with the springs of 100 steps ago) */
    size_t staged_again = 0;
    round_trip(&a, &b, 2, lose_springs, &staged_again);
    assert_true(staged_again >= 20);
    same_order(&ref, &a);
    OK(sinter_stepper_step(ref.st, 400));
    OK(sinter_stepper_step(a.st, 400));
    if (!lose_springs)
        print_message("cloud: %zu springs between particles, %zu with the floor; %zu entries "
                      "staged in the second stepper\n",
                      pp, pw, staged);
    by_id(ref.ps, want, CLOUD);
    by_id(a.ps, got, CLOUD);
    scene_close(&ref);
    scene_close(&a);
    scene_close(&b);
}

static void test_round_trip_keeps_every_bit(void **state)
{
    (void)state;
    static double got[20 * CLOUD], want[20 * CLOUD];
    cloud_run(0, got, want);
    assert_memory_equal(got, want, sizeof(got));
    /* the same with the removal apart from the export (sinter_stepper_remove): the same bits */
    static double apart[20 * CLOUD], want_apart[20 * CLOUD];
    g_remove_apart = 1;
    cloud_run(0, apart, want_apart);
    g_remove_apart = 0;
    assert_memory_equal(apart, got, sizeof(got));
    assert_memory_equal(want_apart, want, sizeof(want));
    /* without the travellers' springs the run differs: the comparison can fail */
    cloud_run(1, got, want);
    assert_true(memcmp(got, want, sizeof(got)) != 0);
}

/*
 * A contact between two particles of one stream arrives in both their records; the import
 * stages it once, so that a stream exported right after the import (before any step) is no
 * larger than the one imported (every staged entry goes into the records of both its ends:
 * two staged copies would make four).
 */
static void test_import_stages_each_contact_once(void **state)
{
    (void)state;
    scene a, b;
    open_cloud(&a);
    open_cloud(&b);
    fill_cloud(&a);
    OK(sinter_stepper_step(a.st, 2500));
    size_t idx[CLOUD], n = 0;
    for (size_t i = 0; i < CLOUD; ++i)
        if (a.ps->id[i] % 2 == 1 || a.ps->id[i] < 16) /* neighbours in one stream */
            idx[n++] = i;
    size_t bytes = 0, written = 0, count = 0;
    OK(sinter_stepper_export_size(a.st, n, idx, &bytes));
    unsigned char *buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(a.st, n, idx, buf, bytes, &written, 0));
    OK(sinter_stepper_import(b.st, buf, written, &count));
    assert_int_equal(count, n);
    const sinter_migrate_entries *l = &b.st->migrate->list[0];
    size_t inner = 0; /* staged contacts with both ends in the stream */
    for (size_t e = 0; e < l->count; ++e) {
        int ends = 0;
        for (size_t i = 0; i < b.ps->count; ++i)
            ends += (b.ps->id[i] == l->key[2 * e]) + (b.ps->id[i] == l->key[2 * e + 1]);
        inner += ends == 2;
        for (size_t f = 0; f < e; ++f) /* no key twice */
            assert_false(l->key[2 * f] == l->key[2 * e] && l->key[2 * f + 1] == l->key[2 * e + 1]);
    }
    print_message("%zu particles: %zu contacts staged, %zu of them between two of them\n", n,
                  l->count, inner);
    assert_true(inner >= 20); /* the case at stake is there */
    size_t all[CLOUD], again = 0;
    for (size_t i = 0; i < n; ++i)
        all[i] = i;
    OK(sinter_stepper_export_size(b.st, n, all, &again));
    assert_int_equal(again, bytes);
    free(buf);
    scene_close(&a);
    scene_close(&b);
}

/*
 * A portable checkpoint: the global part and the records of every particle, written in three
 * pieces in another order than the particles' (reversed); a stepper set up alike without
 * particles loads the part and imports the pieces, last first. The original run is reordered
 * the same way (the restart builds its neighbour lists afresh, and so does a reordered run);
 * 500 steps later both hold the same bits, and the same time and counts.
 */
static void test_portable_checkpoint_restarts_bit_for_bit(void **state)
{
    (void)state;
    scene a, c;
    open_cloud(&a);
    open_cloud(&c);
    fill_cloud(&a);
    OK(sinter_stepper_step(a.st, 2500));
    size_t part_bytes = 0;
    OK(sinter_stepper_save_global(a.st, NULL, 0, &part_bytes));
    unsigned char *part = malloc(part_bytes);
    assert_non_null(part);
    OK(sinter_stepper_save_global(a.st, part, part_bytes, &part_bytes));
    size_t order[CLOUD];
    for (size_t k = 0; k < CLOUD; ++k)
        order[k] = CLOUD - 1 - k;
    unsigned char *piece[3];
    size_t piece_bytes[3];
    const size_t cut[4] = {0, 20, 41, CLOUD};
    for (int p = 0; p < 3; ++p) {
        const size_t n = cut[p + 1] - cut[p];
        OK(sinter_stepper_export_size(a.st, n, order + cut[p], &piece_bytes[p]));
        piece[p] = malloc(piece_bytes[p]);
        assert_non_null(piece[p]);
        size_t written = 0;
        OK(sinter_stepper_export(a.st, n, order + cut[p], piece[p], piece_bytes[p], &written, 0));
    }
    /* the original, reordered as the restart will hold its particles (last piece first) */
    size_t restart_order[CLOUD], m = 0;
    for (int p = 2; p >= 0; --p)
        for (size_t k = cut[p]; k < cut[p + 1]; ++k)
            restart_order[m++] = order[k];
    OK(sinter_particles_permute(a.ps, restart_order));
    /* a part refused when the set holds particles, or damaged */
    scene_add(&c, 0.0, 0.0, 0.0, 1e-3);
    assert_int_equal(sinter_stepper_load_global(c.st, part, part_bytes), SINTER_ERR_STATE);
    const size_t first = 0;
    OK(sinter_particles_remove(c.ps, 1, &first));
    part[part_bytes / 2] ^= 1;
    assert_int_equal(sinter_stepper_load_global(c.st, part, part_bytes), SINTER_ERR_CORRUPT);
    part[part_bytes / 2] ^= 1;
    OK(sinter_stepper_load_global(c.st, part, part_bytes));
    for (int p = 2; p >= 0; --p) {
        size_t count = 0;
        OK(sinter_stepper_import(c.st, piece[p], piece_bytes[p], &count));
        assert_int_equal(count, cut[p + 1] - cut[p]);
        free(piece[p]);
    }
    free(part);
    OK(sinter_stepper_step(a.st, 500));
    OK(sinter_stepper_step(c.st, 500));
    static double got[20 * CLOUD], want[20 * CLOUD];
    by_id(a.ps, want, CLOUD);
    by_id(c.ps, got, CLOUD);
    assert_memory_equal(got, want, sizeof(got));
    assert_true(a.st->time == c.st->time);
    assert_int_equal(a.st->stats.steps, c.st->stats.steps);
    assert_int_equal(a.st->stats.neighbor_builds, c.st->stats.neighbor_builds);
    assert_memory_equal(a.walls->wall[0].force, c.walls->wall[0].force, 3 * sizeof(double));
    scene_close(&a);
    scene_close(&c);
}

/*
 * The electric network's warm start (the potentials its next solve starts from): a chain of 8
 * spheres pressed between two electrodes (1 V and 0 V) sends its particles of odd index to a
 * second stepper and back. The potentials come back with their particles (the warm start of
 * the first stepper, reordered, equals the reference's by id, walls included), and the next
 * solve gives the same currents to its tolerance in as many iterations as the reference's.
 */
enum { CHAIN = 8 };

static void open_chain(scene *s, sinter_electric_model **em, int fill)
{
    scene_init(s);
    scene_material(s, 1e7, 0.3, 2500, 0.3, 0.0);
    OK(sinter_material_set(s->mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e6));
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e6));
    scene_open(s, "hertz_mindlin", 0);
    OK(sinter_stepper_set_dt(s->st, 1e-7));
    const double r = 1e-3, pitch = 1.99e-3;
    const double lo[3] = {-r + 1e-5, 0, 0}, hi[3] = {pitch * (CHAIN - 1) + r - 1e-5, 0, 0};
    const double up[3] = {1, 0, 0}, down[3] = {-1, 0, 0};
    OK(sinter_walls_add_plane(s->walls, lo, up, s->wall_mat, NULL));
    OK(sinter_walls_add_plane(s->walls, hi, down, s->wall_mat, NULL));
    OK(sinter_walls_set_electric(s->walls, 0, SINTER_WALL_POTENTIAL, 1.0));
    OK(sinter_walls_set_electric(s->walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    OK(sinter_electric_model_create(em, s->ctx, "network"));
    OK(sinter_electric_model_set(*em, "tolerance", 1e-10));
    OK(sinter_stepper_set_electric(s->st, *em));
    for (size_t k = 0; fill && k < CHAIN; ++k)
        scene_add(s, pitch * (double)k, 0.0, 0.0, r);
}

static void test_electric_warm_start_travels(void **state)
{
    (void)state;
    scene ref, a, b;
    sinter_electric_model *em_ref, *em_a, *em_b;
    open_chain(&ref, &em_ref, 1);
    open_chain(&a, &em_a, 1);
    open_chain(&b, &em_b, 0);
    OK(sinter_stepper_step(ref.st, 3));
    OK(sinter_stepper_step(a.st, 3));
    size_t nodes = 0;
    const double *warm = sinter_electric_warm_potentials(em_ref, &nodes);
    assert_int_equal(nodes, CHAIN + 2);
    double want[CHAIN + 2];
    memcpy(want, warm, sizeof(want));                    /* by id: the ids are the indices */
    assert_true(want[0] > 0.5 && want[CHAIN - 1] < 0.5); /* a gradient along the chain */
    size_t odd[CHAIN / 2], all[CHAIN / 2], bytes = 0, written = 0, count = 0;
    for (size_t k = 0; k < CHAIN / 2; ++k) {
        odd[k] = 2 * k + 1;
        all[k] = k;
    }
    OK(sinter_stepper_export_size(a.st, CHAIN / 2, odd, &bytes));
    unsigned char *buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(a.st, CHAIN / 2, odd, buf, bytes, &written, 1));
    OK(sinter_stepper_import(b.st, buf, written, &count));
    free(buf);
    OK(sinter_stepper_export_size(b.st, CHAIN / 2, all, &bytes));
    buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(b.st, CHAIN / 2, all, buf, bytes, &written, 1));
    OK(sinter_stepper_import(a.st, buf, written, &count));
    free(buf);
    warm = sinter_electric_warm_potentials(em_a, &nodes);
    assert_int_equal(nodes, CHAIN + 2);
    double got[CHAIN + 2];
    for (size_t i = 0; i < CHAIN; ++i)
        got[a.ps->id[i]] = warm[i];
    got[CHAIN] = warm[CHAIN];
    got[CHAIN + 1] = warm[CHAIN + 1];
    assert_memory_equal(got, want, sizeof(got));
    /* the next solve starts from them: the same currents to the solver's tolerance, in as
     * many iterations as the reference's (a start that lost them takes more) */
    OK(sinter_stepper_step(ref.st, 1));
    OK(sinter_stepper_step(a.st, 1));
    for (size_t i = 0; i < CHAIN; ++i) {
        const double j = ref.ps->current[a.ps->id[i]];
        assert_true(fabs(a.ps->current[i] - j) <= 1e-8 * fabs(j));
    }
    print_message("electric: %zu PCG iterations after the round trip, %zu in the reference\n",
                  em_a->last_iterations, em_ref->last_iterations);
    assert_int_equal(em_a->last_iterations, em_ref->last_iterations);
    sinter_electric_model *em[3] = {em_ref, em_a, em_b};
    scene *sc[3] = {&ref, &a, &b};
    for (int k = 0; k < 3; ++k) { /* the model after its stepper, before its context */
        sinter_stepper_destroy(sc[k]->st);
        sc[k]->st = NULL;
        sinter_electric_model_destroy(em[k]);
        scene_close(sc[k]);
    }
}

/* ---- refusals ---- */

static void test_bad_streams_are_refused(void **state)
{
    (void)state;
    scene a, b;
    open_cloud(&a);
    open_cloud(&b);
    fill_cloud(&a);
    OK(sinter_stepper_step(a.st, 200));
    const size_t idx[3] = {5, 1, 9};
    size_t bytes = 0, written = 0, count = 7;
    OK(sinter_stepper_export_size(a.st, 3, idx, &bytes));
    unsigned char *buf = malloc(bytes + 1);
    assert_non_null(buf);
    /* a buffer too small, an index twice or out of range, remove not 0 or 1 */
    assert_int_equal(sinter_stepper_export(a.st, 3, idx, buf, bytes - 1, &written, 0),
                     SINTER_ERR_RANGE);
    const size_t twice[2] = {4, 4}, beyond[1] = {CLOUD};
    assert_int_equal(sinter_stepper_export(a.st, 2, twice, buf, bytes, &written, 0),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_export(a.st, 1, beyond, buf, bytes, &written, 0),
                     SINTER_ERR_RANGE);
    assert_int_equal(sinter_stepper_export(a.st, 3, idx, buf, bytes, &written, 2),
                     SINTER_ERR_INVALID);
    OK(sinter_stepper_export(a.st, 3, idx, buf, bytes, &written, 0));
    assert_int_equal(a.ps->count, CLOUD);
    /* ids the set holds already: refused, nothing changed */
    assert_int_equal(sinter_stepper_import(a.st, buf, bytes, &count), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(a.ctx), "id 5"));
    assert_int_equal(count, 0);
    assert_int_equal(a.ps->count, CLOUD);
    /* damaged: every single flipped byte, a truncated or longer stream */
    for (size_t k = 0; k < bytes; k += 1 + k / 64) {
        buf[k] ^= 0x10;
        const sinter_status s = sinter_stepper_import(b.st, buf, bytes, &count);
        assert_true(s == SINTER_ERR_CORRUPT);
        buf[k] ^= 0x10;
    }
    assert_int_equal(sinter_stepper_import(b.st, buf, bytes - 1, &count), SINTER_ERR_CORRUPT);
    buf[bytes] = 0;
    assert_int_equal(sinter_stepper_import(b.st, buf, bytes + 1, &count), SINTER_ERR_CORRUPT);
    assert_int_equal(sinter_stepper_import(b.st, "not a stream", 12, &count), SINTER_ERR_CORRUPT);
    assert_int_equal(b.ps->count, 0);
    assert_null(b.st->migrate);
    /* a stepper with other force models */
    scene c;
    scene_init(&c);
    scene_material(&c, 1e6, 0.3, 2500, 0.3, 0.4);
    scene_open(&c, "linear_spring", 0);
    assert_int_equal(sinter_stepper_import(c.st, buf, bytes, &count), SINTER_ERR_INVALID);
    assert_int_equal(c.ps->count, 0);
    /* an empty stream: no particle, nothing changes */
    unsigned char empty[512];
    OK(sinter_stepper_export(a.st, 0, NULL, empty, sizeof(empty), &written, 1));
    assert_true(written > 0 && written < sizeof(empty));
    OK(sinter_stepper_import(b.st, empty, written, &count));
    assert_int_equal(count, 0);
    assert_int_equal(a.ps->count, CLOUD);
    assert_int_equal(b.ps->count, 0);
    /* the stream itself was sound */
    OK(sinter_stepper_import(b.st, buf, bytes, &count));
    assert_int_equal(count, 3);
    assert_int_equal(b.ps->id[0], a.ps->id[5]);
    assert_int_equal(b.ps->id[2], a.ps->id[9]);
    assert_memory_equal(b.ps->x + 3, a.ps->x + 3, 3 * sizeof(double));
    free(buf);
    scene_close(&a);
    scene_close(&b);
    scene_close(&c);
}

/* ---- the quasi-static copper packing of test_qs_ids.c ---- */

enum { N = 23 };
static const double R = 25e-6;

static void layout(double x[3 * N], double r[N])
{
    size_t n = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 2; ++k) {
                x[3 * n] = (1 + 2 * i) * R;
                x[3 * n + 1] = (1 + 2 * j) * R;
                x[3 * n + 2] = (1 + 2 * k) * R;
                r[n++] = R;
            }
    const double rc = 0.6 * R, d = (R + rc) * (1.0 + 1e-4), h = sqrt(d * d - R * R);
    const double tri[9] = {11 * R, R, R, 13 * R, R, R, 12 * R, R + h, R};
    memcpy(x + 3 * n, tri, sizeof(tri));
    r[n] = r[n + 1] = R;
    r[n + 2] = rc;
    n += 3;
    const double a[3] = {20 * R, 20.3 * R, 20 * R}, dir[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
    for (int q = 0; q < 3; ++q) {
        x[3 * n + (size_t)q] = a[q];
        x[3 * n + 3 + (size_t)q] = a[q] + 2 * R * dir[q];
    }
    r[n] = r[n + 1] = R;
}

static void open_copper(scene *s, int fill)
{
    scene_init(s);
    scene_material(s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_QUASISTATIC, s->ps, NULL));
    if (!fill)
        return;
    double x[3 * N], r[N];
    layout(x, r);
    for (size_t p = 0; p < N; ++p) {
        const uint64_t id = 7 * p % N; /* scrambled against the places */
        OK(sinter_particles_add_with_ids(s->ps, 1, &id, x + 3 * p, r + p, 0, 1293.0, NULL));
    }
}

static void links_equal(const sinter_qs *p, const sinter_qs *q)
{
    assert_int_equal(p->count, q->count);
    for (size_t k = 0; k < p->count; ++k) {
        const sinter_qs_link *a = &p->links[k], *b = &q->links[k];
        assert_int_equal(a->id_a, b->id_a);
        assert_int_equal(a->id_b, b->id_b);
        assert_memory_equal(&a->neck, &b->neck, sizeof(a->neck));
        assert_memory_equal(a->beam.axis, b->beam.axis, sizeof(a->beam.axis));
        assert_true(a->born == b->born && a->rm == b->rm && a->youngs == b->youngs);
    }
}

/* A stream of the previous format (3: records without the quasi-static state) is still read:
 * one written now with its last 88 bytes of the record (the state, zeros for an explicit
 * stepper) cut and its header and checksum made again imports to the same particle; format 2
 * is refused. */
static void test_format_3_is_read(void **state)
{
    (void)state;
    scene a, b;
    open_cloud(&a);
    open_cloud(&b);
    scene_add(&a, 1e-3, 2e-3, 3e-3, 0.9e-3);
    const double v[3] = {0.1, -0.2, 0.3};
    set3(&a, SINTER_FIELD_VELOCITY, 0, v);
    const size_t idx[1] = {0};
    size_t bytes = 0, written = 0, count = 0;
    OK(sinter_stepper_export_size(a.st, 1, idx, &bytes));
    unsigned char *buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(a.st, 1, idx, buf, bytes, &written, 0));
    const size_t cut = bytes - 88; /* the record is last: its state ends before the checksum */
    static const unsigned char zero[88];
    assert_memory_equal(buf + bytes - 8 - 88, zero, 88);
    memmove(buf + bytes - 8 - 88, buf + bytes - 8, 8);
    uint32_t version = 3;
    uint64_t total = cut;
    memcpy(buf + 8, &version, 4);
    memcpy(buf + 16, &total, 8);
    const uint64_t sum = sinter_fnv1a(SINTER_FNV1A_START, buf, cut - 8);
    memcpy(buf + cut - 8, &sum, 8);
    OK(sinter_stepper_import(b.st, buf, cut, &count));
    assert_int_equal(count, 1);
    assert_memory_equal(b.ps->x, a.ps->x, 3 * sizeof(double));
    assert_memory_equal(b.ps->v, a.ps->v, 3 * sizeof(double));
    scene c;
    open_cloud(&c);
    version = 2;
    memcpy(buf + 8, &version, 4);
    const uint64_t sum2 = sinter_fnv1a(SINTER_FNV1A_START, buf, cut - 8);
    memcpy(buf + cut - 8, &sum2, 8);
    assert_int_equal(sinter_stepper_import(c.st, buf, cut, &count), SINTER_ERR_CORRUPT);
    free(buf);
    scene_close(&a);
    scene_close(&b);
    scene_close(&c);
}

static void test_quasistatic_links_travel(void **state)
{
    (void)state;
    scene ref, a, b;
    open_copper(&ref, 1);
    open_copper(&a, 1);
    open_copper(&b, 0);
    OK(sinter_stepper_advance(ref.st, 40.0));
    OK(sinter_stepper_advance(a.st, 40.0));
    const size_t links = a.st->quasistatic->count;
    assert_int_equal(links, 37); /* 35 at the start, the triangle's two made during the run */
    /* the particles of odd id leave with the links whose smaller id they are */
    size_t idx[N], n = 0, owned = 0;
    for (size_t i = 0; i < N; ++i)
        if (a.ps->id[i] % 2 == 1)
            idx[n++] = i;
    for (size_t k = 0; k < links; ++k)
        owned += a.st->quasistatic->links[k].id_a % 2 == 1;
    assert_true(owned > 5 && owned < links);
    size_t bytes = 0, written = 0, count = 0;
    OK(sinter_stepper_export_size(a.st, n, idx, &bytes));
    unsigned char *buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(a.st, n, idx, buf, bytes, &written, 1));
    assert_int_equal(a.st->quasistatic->count, links - owned);
    OK(sinter_stepper_import(b.st, buf, written, &count));
    assert_int_equal(count, n);
    assert_int_equal(b.st->quasistatic->count, owned);
    for (size_t k = 0, m = 0; k < links; ++k) /* with their neck state, in their order */
        if (ref.st->quasistatic->links[k].id_a % 2 == 1) {
            const sinter_qs_link *want = &ref.st->quasistatic->links[k];
            const sinter_qs_link *got = &b.st->quasistatic->links[m++];
            assert_int_equal(got->id_a, want->id_a);
            assert_int_equal(got->id_b, want->id_b);
            assert_memory_equal(&got->neck, &want->neck, sizeof(got->neck));
        }
    free(buf);
    size_t all[N];
    for (size_t i = 0; i < n; ++i)
        all[i] = i;
    OK(sinter_stepper_export_size(b.st, n, all, &bytes));
    buf = malloc(bytes);
    assert_non_null(buf);
    OK(sinter_stepper_export(b.st, n, all, buf, bytes, &written, 1));
    assert_int_equal(b.st->quasistatic->count, 0);
    OK(sinter_stepper_import(a.st, buf, written, &count));
    free(buf);
    links_equal(a.st->quasistatic, ref.st->quasistatic); /* back in their places */
    OK(sinter_stepper_advance(ref.st, 100.0));
    OK(sinter_stepper_advance(a.st, 100.0));
    links_equal(a.st->quasistatic, ref.st->quasistatic);
    double got[3 * N], want[3 * N], got_rot[3 * N], want_rot[3 * N];
    for (size_t i = 0; i < N; ++i) {
        memcpy(got + 3 * a.ps->id[i], a.ps->x + 3 * i, 3 * sizeof(double));
        memcpy(want + 3 * ref.ps->id[i], ref.ps->x + 3 * i, 3 * sizeof(double));
        memcpy(got_rot + 3 * a.ps->id[i], a.ps->rot + 3 * i, 3 * sizeof(double));
        memcpy(want_rot + 3 * ref.ps->id[i], ref.ps->rot + 3 * i, 3 * sizeof(double));
    }
    assert_memory_equal(got, want, sizeof(got));
    assert_memory_equal(got_rot, want_rot, sizeof(got_rot));
    /* the run did move the particles after the round trip */
    assert_true(a.st->quasistatic->links[0].neck.time > 99.0);
    scene_close(&ref);
    scene_close(&a);
    scene_close(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_keeps_every_bit),
        cmocka_unit_test(test_import_stages_each_contact_once),
        cmocka_unit_test(test_portable_checkpoint_restarts_bit_for_bit),
        cmocka_unit_test(test_electric_warm_start_travels),
        cmocka_unit_test(test_bad_streams_are_refused),
        cmocka_unit_test(test_format_3_is_read),
        cmocka_unit_test(test_quasistatic_links_travel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
