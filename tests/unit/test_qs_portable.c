#define _POSIX_C_SOURCE 200809L
/*
 * The quasi-static stepper's portable checkpoint (issue 43; src/stepper/qs_portable.c,
 * global_state.c, migrate.c) through the public API. The copper packing of test_qs_ids.c (23
 * spheres: a lattice on the principal planes, a triangle whose third link is made during the
 * run, a floating pair; ids scrambled against the places) runs to 40 s; there its global part
 * (sinter_stepper_save_global) and the records of its particles in three pieces
 * (sinter_stepper_export, remove = 0, in a shuffled order) are written. A fresh stepper loads
 * the part and imports the pieces, last first; both runs go on to 100 s. The restart must give
 * the uninterrupted run's bits (positions, rotations, links, necks, approaches, sintering
 * forces, statistics): its plane conditions, last displacements (the next solve's start),
 * initial positions (the shrinkage's reference), step control and counters came through the
 * part and the records, and every order of the stepper is one of ids. The uninterrupted run is
 * reordered as the restart holds its particles, as test_migrate.c's global-part test does.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "qs_copper_packing.h"
#include "scene_support.h"
#include "particles/particles.h"

/* The stepper of a run to 40 s, its global part and its records in three pieces. */
typedef struct pieces {
    unsigned char *part, *piece[3];
    size_t part_bytes, piece_bytes[3], cut[4];
    size_t order[N];
} pieces;

static void write_pieces(scene *s, pieces *w)
{
    OK(sinter_stepper_save_global(s->st, NULL, 0, &w->part_bytes));
    w->part = malloc(w->part_bytes);
    assert_non_null(w->part);
    OK(sinter_stepper_save_global(s->st, w->part, w->part_bytes, &w->part_bytes));
    shuffled(w->order); /* the places' order, as indices: the set holds id k at index k */
    const size_t cut[4] = {0, 7, 16, N};
    memcpy(w->cut, cut, sizeof(cut));
    for (int p = 0; p < 3; ++p) {
        const size_t n = cut[p + 1] - cut[p];
        OK(sinter_stepper_export_size(s->st, n, w->order + cut[p], &w->piece_bytes[p]));
        w->piece[p] = malloc(w->piece_bytes[p]);
        assert_non_null(w->piece[p]);
        size_t written = 0;
        OK(sinter_stepper_export(s->st, n, w->order + cut[p], w->piece[p], w->piece_bytes[p],
                                 &written, 0));
        assert_int_equal(written, w->piece_bytes[p]);
    }
}

static void portable_restart(int strategy)
{
    integration = strategy;
    scene a, c;
    open_run(&a, NULL, 0, 1);
    OK(sinter_stepper_advance(a.st, 40.0));
    pieces w;
    write_pieces(&a, &w);
    /* the original, reordered as the restart will hold its particles (last piece first) */
    size_t restart_order[N], m = 0;
    for (int p = 2; p >= 0; --p)
        for (size_t k = w.cut[p]; k < w.cut[p + 1]; ++k)
            restart_order[m++] = w.order[k];
    OK(sinter_particles_permute(a.ps, restart_order));
    /* the restart: a stepper set up alike, without particles */
    scene_init(&c);
    OK(sinter_ctx_set_threads(c.ctx, 1));
    scene_material(&c, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&c.ps, c.ctx));
    OK(sinter_particles_set_material(c.ps, 0, c.mat));
    OK(sinter_stepper_create(&c.st, c.ctx, SINTER_STEPPER_QUASISTATIC, c.ps, NULL));
    OK(sinter_stepper_set_option(c.st, "sort_interval", 0.0));
    if (strategy == 1)
        OK(sinter_stepper_set_option(c.st, "qs_strategy", 2.0));
    /* a damaged part is refused */
    w.part[w.part_bytes / 2] ^= 1;
    assert_int_equal(sinter_stepper_load_global(c.st, w.part, w.part_bytes), SINTER_ERR_CORRUPT);
    w.part[w.part_bytes / 2] ^= 1;
    OK(sinter_stepper_load_global(c.st, w.part, w.part_bytes));
    for (int p = 2; p >= 0; --p) {
        size_t count = 0;
        OK(sinter_stepper_import(c.st, w.piece[p], w.piece_bytes[p], &count));
        assert_int_equal(count, w.cut[p + 1] - w.cut[p]);
        free(w.piece[p]);
    }
    free(w.part);
    double ta = 0.0, tc = 0.0;
    OK(sinter_stepper_time(a.st, &ta));
    OK(sinter_stepper_time(c.st, &tc));
    assert_true(ta == tc);
    OK(sinter_stepper_advance(a.st, T_END));
    OK(sinter_stepper_advance(c.st, T_END));
    static outcome want, got;
    collect(&a, &want);
    collect(&c, &got);
    print_message("strategy option %d: links %zu, far corner moved in by %.4e R, %.0f PCG "
                  "iterations\n",
                  strategy, want.links, 5.0 - want.x[3 * id_of(17)] / R, want.stats[10]);
    /* the run did what the packing is for: a link made after the restart, shrinkage */
    assert_int_equal(want.links, LINKS_END);
    assert_true(want.x[3 * id_of(17)] < 5 * R * (1.0 - 1e-3));
    assert_same(&got, &want);
    /* and the stepper-wide state agrees too (time, counters, step control) */
    size_t ba = 0, bc = 0;
    OK(sinter_stepper_save_global(a.st, NULL, 0, &ba));
    OK(sinter_stepper_save_global(c.st, NULL, 0, &bc));
    assert_int_equal(ba, bc);
    unsigned char *ga = malloc(ba), *gc = malloc(bc);
    assert_non_null(ga);
    assert_non_null(gc);
    OK(sinter_stepper_save_global(a.st, ga, ba, &ba));
    OK(sinter_stepper_save_global(c.st, gc, bc, &bc));
    assert_memory_equal(ga, gc, ba);
    free(ga);
    free(gc);
    scene_close(&a);
    scene_close(&c);
    integration = 0;
}

/* The default neck integration (strategy 3) and strategy 2 (the copper_lattice scene's). */
static void test_portable_restart_continues_bit_for_bit(void **state)
{
    (void)state;
    portable_restart(0);
    portable_restart(1);
}

/* A quasi-static stepper's global part and records are refused by a stepper of another kind
 * (their quasi-static state would be lost). */
static void test_quasistatic_records_refused_by_another_stepper(void **state)
{
    (void)state;
    integration = 0;
    scene a, c;
    open_run(&a, NULL, 0, 1);
    OK(sinter_stepper_advance(a.st, 10.0));
    pieces w;
    write_pieces(&a, &w);
    scene_init(&c);
    scene_material(&c, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&c.ps, c.ctx));
    OK(sinter_particles_set_material(c.ps, 0, c.mat));
    OK(sinter_stepper_create(&c.st, c.ctx, SINTER_STEPPER_EXPLICIT, c.ps, NULL));
    assert_int_equal(sinter_stepper_load_global(c.st, w.part, w.part_bytes), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_import(c.st, w.piece[0], w.piece_bytes[0], NULL),
                     SINTER_ERR_INVALID);
    for (int p = 0; p < 3; ++p)
        free(w.piece[p]);
    free(w.part);
    scene_close(&a);
    scene_close(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_portable_restart_continues_bit_for_bit),
        cmocka_unit_test(test_quasistatic_records_refused_by_another_stepper),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
