#define _POSIX_C_SOURCE 200809L
/*
 * The key sets of scene sections (src/io/key_set.c): keys are found and a section of n keys
 * is read with O(n) string comparisons, so that a duplicate among a million keys is refused at
 * once (issue 35: the old search compared every key with every earlier one).
 */
#include <stdio.h>
#include <string.h>

#include "test_support.h"

#include "io/key_set.h"
#include "io/scene_text.h"

static void test_find_and_insert(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    sinter_key_set set;
    memset(&set, 0, sizeof(set));
    assert_true(sinter_key_set_find(&set, "a") == SIZE_MAX);
    static char keys[1000][16];
    for (size_t k = 0; k < 1000; ++k) {
        snprintf(keys[k], sizeof(keys[k]), "k%zu", k);
        assert_true(sinter_key_set_find(&set, keys[k]) == SIZE_MAX);
        assert_int_equal(sinter_key_set_insert(ctx, &set, keys[k], k), SINTER_OK);
    }
    for (size_t k = 0; k < 1000; ++k)
        assert_true(sinter_key_set_find(&set, keys[k]) == k);
    assert_true(sinter_key_set_find(&set, "k1000") == SIZE_MAX);
    sinter_key_set_free(ctx, &set);
    sinter_ctx_destroy(ctx);
}

/* A section of n keys costs O(n) comparisons to read (a structural bound, not a timing). */
static void test_reading_is_linear(void **state)
{
    (void)state;
    enum { KEYS = 50000 };
    char path[] = "/tmp/sinter_key_set_XXXXXX";
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fprintf(f, "[scene]\n");
    for (int k = 0; k < KEYS; ++k)
        fprintf(f, "key%d = %d\n", k, k);
    fclose(f);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    scene_text t;
    assert_int_equal(scene_text_read(&t, ctx, path), SINTER_OK);
    assert_int_equal(t.count, 1);
    assert_int_equal(t.sections[0].count, KEYS);
    /* a quadratic search makes KEYS^2 / 2 = 1.25e9 comparisons */
    if (t.sections[0].keys.compares > 4 * (size_t)KEYS) {
        print_error("%zu string comparisons for %d keys\n", t.sections[0].keys.compares, KEYS);
        fail();
    }
    assert_non_null(scene_find(&t.sections[0], "key49999"));
    assert_null(scene_find(&t.sections[0], "key50000"));
    scene_text_free(&t);
    sinter_ctx_destroy(ctx);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_find_and_insert),
        cmocka_unit_test(test_reading_is_linear),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
