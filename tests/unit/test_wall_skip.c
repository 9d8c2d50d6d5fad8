/*
 * Plane walls proven out of reach (contact/wall_skip.h): the particle-wall search that leaves
 * them untested finds exactly the contacts of a full search, step after step, and skips
 * them only while the bound of wall_skip.h holds.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdlib.h>

#include "scene_support.h"
#include "contact/contacts.h"
#include "contact/neighbors.h"

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Wall lists a and b hold the same contacts with the same geometry and pairs. */
static void assert_same(const sinter_contact_list *a, const sinter_contact_list *b)
{
    assert_int_equal(a->count, b->count);
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
    assert_int_equal(a->ascending, b->ascending);
}

/*
 * A one-sphere-thick slab (walls at y = -+(r + 1e-5 m), normals +-e_y) on a floor, the
 * spheres within reach of all three, on 1-3 threads (the search is threaded from 1024 pairs).
 * Every round moves the spheres by a random step in x and z (some onto and off the floor),
 * reports the largest step along each axis as the explicit drift does, and compares the
 * skipping search with a full one:
 * - no motion along y: the slab's walls stay skipped (their pairs untested);
 * - round 10: the back wall moves 6e-6 m towards the spheres: still out of reach, skipped;
 *   round 15: 6e-6 m more, into contact with every sphere: tested again, the contacts found
 *   at that round, as the full search finds them;
 * - round 20: one sphere 8e-6 m towards the front wall: still out of reach, the wall
 *   skipped (8e-6 < 1e-5); round 21: 3e-6 more, into contact: tested again, the contact
 *   found at that round;
 * - round 30: an evaluation without a reported drift drops the certificate.
 * The same contacts in every round are the proof; the skipped pairs are the point.
 */
static void test_skipping_search_matches_a_full_one(void **state)
{
    (void)state;
    enum { N = 1200, ROUNDS = 32 };
    const double r0 = 0.5e-3, gap = 1e-5;
    for (int t = 1; t <= 3; ++t) {
        scene s;
        scene_init(&s);
        OK(sinter_ctx_set_threads(s.ctx, t));
        scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
        scene_open(&s, "hertz_mindlin", 0);
        scene_floor(&s, 0.0);
        const double pf[3] = {0, -(r0 + gap), 0}, nf[3] = {0, 1, 0};
        const double pb[3] = {0, r0 + gap, 0}, nb_[3] = {0, -1, 0};
        OK(sinter_walls_add_plane(s.walls, pf, nf, s.wall_mat, NULL));  /* wall 1: front */
        OK(sinter_walls_add_plane(s.walls, pb, nb_, s.wall_mat, NULL)); /* wall 2: back */
        uint64_t seed = 3;
        for (size_t k = 0; k < N; ++k) { /* a row, some touching the floor */
            const double z = r0 * (0.98 + 0.1 * lcg(&seed));
            scene_add(&s, 2.2 * r0 * (double)k, 0.0, z, r0);
        }
        sinter_neighbors nb;
        sinter_neighbors_init(&nb, s.ctx, 1e-4);
        OK(sinter_neighbors_build(&nb, s.ps, s.walls));
        assert_true(nb.pw.count >= 2 * N + 100);
        sinter_contact_list kept, fresh;
        memset(&kept, 0, sizeof(kept));
        memset(&fresh, 0, sizeof(fresh));
        sinter_wall_skip skip;
        memset(&skip, 0, sizeof(skip));
        double *x = s.ps->x;
        const size_t mover = N / 2;
        for (int round = 0; round < ROUNDS; ++round) {
            double axis2[3] = {0.0, 0.0, 0.0};
            for (size_t i = 0; i < N && round > 0; ++i) {
                const double dz = 4e-6 * (lcg(&seed) - 0.5), dx = 4e-6 * (lcg(&seed) - 0.5);
                const double x0 = x[3 * i], z0 = x[3 * i + 2];
                x[3 * i] += dx;
                x[3 * i + 2] += dz;
                const double sx = x[3 * i] - x0, sz = x[3 * i + 2] - z0;
                axis2[0] = fmax(axis2[0], sx * sx);
                axis2[2] = fmax(axis2[2], sz * sz);
            }
            if (round == 20 || round == 21) {
                const double y0 = x[3 * mover + 1];
                x[3 * mover + 1] -= round == 20 ? 8e-6 : 3e-6;
                const double sy = x[3 * mover + 1] - y0;
                axis2[1] = sy * sy;
            }
            if (round == 10 || round == 15) /* (as a servo writes it) */
                s.walls->wall[2].p[1] -= 6e-6;
            if (round > 0 && round != 30)
                sinter_wall_skip_moved(&skip, axis2);
            sinter_wall_skip_begin(&skip);
            if (round == 30)
                assert_false(skip.valid);
            OK(sinter_contacts_find_pw_skip(s.ctx, &kept, &nb.pw, s.ps, s.walls, NULL, &skip));
            OK(sinter_contacts_find_pw(s.ctx, &fresh, &nb.pw, s.ps, s.walls, NULL));
            assert_same(&kept, &fresh);
            assert_true(fresh.count > 0);
            assert_true(skip.valid);
            /* which walls are skipped: the floor never (spheres on it), the front until the
             * mover reaches it, the back until it moves */
            const int front = round < 21, back = round < 15;
            if (round >= 21 && round < 30) { /* the mover touches the front wall */
                int touching = 0;
                for (size_t q = 0; q < fresh.count; ++q)
                    touching |= fresh.i[q] == mover && fresh.j[q] == 1;
                assert_true(touching);
            }
            if (round >= 15) { /* the back wall touches every sphere */
                size_t touching = 0;
                for (size_t q = 0; q < fresh.count; ++q)
                    touching += fresh.j[q] == 2;
                assert_int_equal(touching, round < 20 ? N : N - 1); /* (the mover left it) */
            }
            assert_false(skip.mask & 1u);
            assert_int_equal((int)(skip.mask >> 1 & 1u), front);
            assert_int_equal((int)(skip.mask >> 2 & 1u), back);
            if (round > 0 && (front || back))
                assert_true(skip.active_count <= nb.pw.count - (size_t)N);
        }
        sinter_wall_skip_free(s.ctx, &skip);
        sinter_contact_list_free(s.ctx, &kept);
        sinter_contact_list_free(s.ctx, &fresh);
        sinter_neighbors_free(&nb);
        scene_close(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_skipping_search_matches_a_full_one),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
