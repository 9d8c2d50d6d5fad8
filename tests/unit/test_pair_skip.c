/*
 * Particle pairs proven out of contact (contact/pair_skip.h): the particle-particle search
 * that skips the pairs its keys prove apart finds exactly the contacts of a full search,
 * round after round, and skips them only while the bound of pair_skip.h holds.
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
#include "contact/pair_skip.h"

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* Lean lists a and b hold the same contacts for the same pairs. */
static void assert_same(const sinter_contact_list *a, const sinter_contact_list *b)
{
    assert_int_equal(a->count, b->count);
    const size_t n = a->count;
    assert_memory_equal(a->i, b->i, n * sizeof(uint32_t));
    assert_memory_equal(a->j, b->j, n * sizeof(uint32_t));
    assert_memory_equal(a->pair, b->pair, n * sizeof(uint32_t));
    assert_int_equal(a->pair_count, b->pair_count);
    assert_memory_equal(a->pair_to_contact, b->pair_to_contact, a->pair_count * sizeof(uint32_t));
}

/*
 * A square lattice of 70 x 70 spheres (r = 0.5 mm, 0.1 mm apart: about 9 700 candidate pairs,
 * so that the search is threaded), on 1-3 threads. Every round moves each sphere by a random
 * step of at most 1e-6 m per component in x and z, and two neighbours A and B straight towards
 * each other by 2e-6 m each (the largest step: the drift reports it), so that their gap of
 * 3e-5 m closes by 4e-6 m a round, twice the largest step: they touch from round 8 on. A
 * bound with the largest step counted once would keep their key until round 15 and miss
 * that contact. Each round compares the keyed search with a full one (same pairs, no keys):
 * - the same contacts every round; A and B in contact from round 8 on (from round 20 they
 *   move apart again, still overlapping at round 29);
 * - round 25 moves the spheres without a report: all keys dropped (every pair tested), the
 *   same contacts;
 * - most pairs are skipped (keys above the travel) in the rounds with reports.
 */
static void test_keyed_search_matches_a_full_one(void **state)
{
    (void)state;
    enum { SIDE = 70, N = SIDE * SIDE, ROUNDS = 30 };
    const double r0 = 0.5e-3, spacing = 2.0 * r0 + 1e-4;
    for (int t = 1; t <= 3; ++t) {
        scene s;
        scene_init(&s);
        OK(sinter_ctx_set_threads(s.ctx, t));
        scene_material(&s, 1e7, 0.3, 2500, 0.0, 0.3);
        scene_open(&s, "hertz_mindlin", 0);
        for (size_t a = 0; a < SIDE; ++a)
            for (size_t b = 0; b < SIDE; ++b)
                scene_add(&s, spacing * (double)b, 0.0, spacing * (double)a, r0);
        const size_t pa = SIDE * (SIDE / 2) + SIDE / 2, pb = pa + 1; /* A, its right neighbour */
        double *x = s.ps->x;
        x[3 * pb] = x[3 * pa] + 2.0 * r0 + 3e-5;
        sinter_neighbors nb;
        sinter_neighbors_init(&nb, s.ctx, 2e-4);
        OK(sinter_neighbors_build(&nb, s.ps, NULL));
        assert_true(nb.pp.count > 9000);
        sinter_contact_list kept, fresh;
        memset(&kept, 0, sizeof(kept));
        memset(&fresh, 0, sizeof(fresh));
        sinter_pair_skip skip;
        memset(&skip, 0, sizeof(skip));
        uint64_t seed = 7;
        for (int round = 0; round < ROUNDS; ++round) {
            double step2 = 0.0;
            for (size_t i = 0; i < N && round > 0; ++i) {
                double d[3] = {1e-6 * (2.0 * lcg(&seed) - 1.0), 0.0,
                               1e-6 * (2.0 * lcg(&seed) - 1.0)};
                if (i == pa || i == pb) { /* towards each other, apart from round 20 */
                    const double dir = (i == pa) == (round < 20) ? 1.0 : -1.0;
                    d[0] = dir * 2e-6;
                    d[2] = 0.0;
                }
                double s2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double x0 = x[3 * i + k];
                    x[3 * i + k] += d[k];
                    const double sk = x[3 * i + k] - x0; /* as the drift measures it */
                    s2 += sk * sk;
                }
                step2 = s2 > step2 ? s2 : step2;
            }
            if (round > 0 && round != 25)
                sinter_pair_skip_moved(&skip, step2);
            kept.skip_key = sinter_pair_skip_begin(s.ctx, &skip, &nb.pp, s.ps, &kept.skip_travel);
            assert_non_null(kept.skip_key);
            size_t proven = 0; /* pairs the keys skip in this search */
            for (size_t p = 0; p < nb.pp.count; ++p)
                proven += kept.skip_travel < kept.skip_key[p];
            if (round == 25 || round == 0)
                assert_int_equal(proven, 0); /* dropped (or none yet): every pair tested */
            else
                assert_true(proven > nb.pp.count / 2);
            OK(sinter_contacts_find_pp_lean(s.ctx, &kept, &nb.pp, s.ps));
            kept.skip_key = NULL;
            OK(sinter_contacts_find_pp_lean(s.ctx, &fresh, &nb.pp, s.ps));
            assert_same(&kept, &fresh);
            int ab = 0;
            for (size_t q = 0; q < fresh.count; ++q)
                ab |= (fresh.i[q] == pa && fresh.j[q] == pb) ||
                      (fresh.i[q] == pb && fresh.j[q] == pa);
            assert_int_equal(ab, round >= 8); /* (apart again only after round 30) */
        }
        sinter_pair_skip_free(s.ctx, &skip);
        sinter_contact_list_free(s.ctx, &kept);
        sinter_contact_list_free(s.ctx, &fresh);
        sinter_neighbors_free(&nb);
        scene_close(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keyed_search_matches_a_full_one),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
