#define _POSIX_C_SOURCE 200809L
/*
 * The quasi-static stepper keyed by particle ids (issue 43, milestone M0; src/stepper/qs_ids.c),
 * through the public API. One packing of 23 copper spheres (R = 25 um, 1293 K, seed 001 table 2)
 * holds every part of the stepper whose order could follow the particles' indices:
 *   - a 3 x 3 x 2 lattice of touching spheres on the principal planes x, y, z = 0 (33 links,
 *     the bonded solve's main network, the plane conditions);
 *   - a triangle on the planes y, z = 0 only: A and B touching, C (0.6 R) above their midpoint a
 *     gap of 1e-4 of the contact distance away, which the A-B neck closes within 100 s: two
 *     links are made during the run (the order of new links), and the component floats along x
 *     (the free motion removed, qs_floating.c);
 *   - a pair linked only to each other along a skew axis, far from everything (a component free
 *     on every axis).
 * The particles' ids are scrambled against their places (no spatial order is the id order). The
 * run is 100 s at the temperature of the particles (their mean, summed by the stepper), with each
 * way of integrating the necks: strategy 3 (the default: young necks each in CVODE, grown ones
 * by RK4), strategy 2, strategy 1, and strategy 3 with all necks in CVODE batches. It is
 * repeated with the
 * particles added in another order (the same ids), with the option sort_interval (the particles
 * reordered in memory by position between steps), and on two threads: the final state sorted by
 * id (positions, rotations), the links in their order (ids, necks, approaches, last sintering
 * forces) and the statistics must be equal bit for bit to the run in id order. They are, and
 * not only to round-off, because every order the stepper makes (links, each particle's sum of
 * loads, the solve's sweeps and dot products, the components, the statistics) is an order of
 * ids, never of indices: sums in another order would differ in the last bits. Then a
 * checkpoint written from a reordered run restarts and continues bit for bit.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "qs_copper_packing.h"
#include "scene_support.h"

/* A run to 40 s and on to T_END (a checkpoint at 40 s written to `checkpoint`, when not NULL). */
static void run(const size_t *order, double sort_interval, int threads, const char *checkpoint,
                outcome *out)
{
    scene s;
    open_run(&s, order, sort_interval, threads);
    OK(sinter_stepper_step(s.st, 1));
    sinter_sintering_stats st;
    memset(&st, 0, sizeof(st));
    st.struct_size = sizeof(st);
    OK(sinter_stepper_sintering_stats(s.st, &st));
    const size_t first = st.links;
    OK(sinter_stepper_advance(s.st, 40.0)); /* every run stops there: its last step ends on it */
    if (checkpoint != NULL)
        OK(sinter_checkpoint_write(s.st, checkpoint));
    OK(sinter_stepper_advance(s.st, T_END));
    collect(&s, out);
    out->links_first = first;
    scene_close(&s);
}

static void reordered_runs(void)
{
    static outcome by_id, sorted, other_order, other_sorted_threads;
    size_t order[N];
    shuffled(order);
    run(NULL, 0, 1, NULL, &by_id);
    run(NULL, 1, 1, NULL, &sorted);                /* sorted before every step */
    run(order, 0, 1, NULL, &other_order);          /* ids never in index order */
    run(order, 3, 2, NULL, &other_sorted_threads); /* sorted every 3 steps, 2 threads */
    print_message("integration %d: links %zu -> %zu, the lattice's far corner moved in by %.4e R, "
                  "%.0f PCG iterations\n",
                  integration, by_id.links_first, by_id.links, 5.0 - by_id.x[3 * id_of(17)] / R,
                  by_id.stats[10]);
    /* the packing does what it is for: links made during the run, the lattice shrinks, and the
     * reordered runs did run with ids out of index order */
    assert_int_equal(by_id.links_first, LINKS_START);
    assert_int_equal(by_id.links, LINKS_END);
    /* the lattice's far corner (place 17) moved in by its links' shrinkage */
    assert_true(by_id.x[3 * id_of(17)] < 5 * R * (1.0 - 1e-3));
    assert_true(by_id.ids_ascending);
    assert_false(sorted.ids_ascending);
    assert_false(other_order.ids_ascending);
    assert_false(other_sorted_threads.ids_ascending);
    for (size_t k = 0; k < LINKS_END; ++k) /* links oriented by id */
        assert_true(by_id.link_a[k] < by_id.link_b[k]);
    assert_same(&sorted, &by_id);
    assert_same(&other_order, &by_id);
    assert_same(&other_sorted_threads, &by_id);
}

static void test_reordered_runs_give_the_same_bits(void **state)
{
    (void)state;
    for (integration = 0; integration < 4; ++integration)
        reordered_runs();
    integration = 0;
}

/* A checkpoint written at 40 s by a run whose particles are out of id order and sorted every 3
 * steps restarts into a fresh stepper (particles added in id order, then replaced by the
 * checkpoint's) and continues to the same bits as the run that wrote it, and as the run in id
 * order: its quasi-static section (links found by id, plane conditions and the last solve's
 * displacements per particle in id order) fits the particles. */
static void test_checkpoint_of_a_reordered_run_restarts(void **state)
{
    (void)state;
    char dir[] = "/tmp/sinter_qs_ids_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[64];
    snprintf(path, sizeof(path), "%s/at40.bin", dir);
    static outcome by_id, straight, restarted;
    size_t order[N];
    shuffled(order);
    run(NULL, 0, 1, NULL, &by_id);
    run(order, 3, 1, path, &straight);
    scene s;
    open_run(&s, NULL, 3, 1);
    OK(sinter_checkpoint_read(s.st, path));
    double t = 0.0;
    OK(sinter_stepper_time(s.st, &t));
    assert_true(t >= 40.0 && t < T_END);
    OK(sinter_stepper_advance(s.st, T_END));
    collect(&s, &restarted);
    restarted.links_first = straight.links_first;
    scene_close(&s);
    assert_false(straight.ids_ascending);
    assert_same(&straight, &by_id);
    assert_same(&restarted, &straight);
    remove(path);
    rmdir(dir);
}

/* A run to 40 s; then the floating pair's second particle (place 22) is removed and a particle
 * of id N (0.9 R, touching nothing) added far from everything; then on to T_END. */
static void changed_run(const size_t *order, double sort_interval, outcome *out)
{
    scene s;
    open_run(&s, order, sort_interval, 1);
    OK(sinter_stepper_advance(s.st, 40.0));
    size_t index = SIZE_MAX;
    OK(sinter_particles_find_id(s.ps, id_of(22), &index));
    OK(sinter_particles_remove(s.ps, 1, &index));
    const uint64_t id = N;
    const double far[3] = {30 * R, 30 * R, 30 * R}, smaller = 0.9 * R;
    OK(sinter_particles_add_with_ids(s.ps, 1, &id, far, &smaller, 0, 1293.0, NULL));
    OK(sinter_stepper_advance(s.st, T_END));
    collect(&s, out);
    scene_close(&s);
}

/* A particle removed and one added during a run: the stepper drops the links of the removed one
 * and detects the plane conditions again, in id order, so the run whose particles are out of id
 * order and sorted gives the bits of the run in id order. */
static void test_removal_and_addition_follow_the_ids(void **state)
{
    (void)state;
    static outcome by_id, other_sorted;
    size_t order[N];
    shuffled(order);
    changed_run(NULL, 0, &by_id);
    changed_run(order, 3, &other_sorted);
    assert_int_equal(by_id.links, LINKS_END - 1); /* the floating pair's link is gone */
    for (size_t k = 0; k < by_id.links; ++k)
        assert_true(by_id.link_a[k] != id_of(22) && by_id.link_b[k] != id_of(22));
    const double far[3] = {30 * R, 30 * R, 30 * R};
    assert_memory_equal(by_id.x + 3 * N, far, sizeof(far)); /* linked to nothing: not moved */
    assert_false(other_sorted.ids_ascending);
    assert_same(&other_sorted, &by_id);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reordered_runs_give_the_same_bits),
        cmocka_unit_test(test_checkpoint_of_a_reordered_run_restarts),
        cmocka_unit_test(test_removal_and_addition_follow_the_ids),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
