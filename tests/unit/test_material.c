/* Materials: defaults, ranges, units, lookup by key. */
#include <math.h>
#include <string.h>

#include "test_support.h"

static void test_defaults_and_info(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *m = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_material_create(&m, ctx, "glass"), SINTER_OK);
    assert_string_equal(sinter_material_name(m), "glass");
    for (int p = 0; p < SINTER_MAT_PARAM_COUNT_; ++p) {
        const char *key = NULL, *unit = NULL, *meaning = NULL;
        double def = NAN, lo = NAN, hi = NAN, value = NAN;
        assert_int_equal(sinter_material_param_info((sinter_material_param)p, &key, &unit,
                                                    &meaning, &def, &lo, &hi),
                         SINTER_OK);
        assert_non_null(key);
        assert_true(strlen(unit) > 0);
        assert_true(strlen(meaning) > 0);
        assert_true(lo <= def && def <= hi);
        assert_int_equal(sinter_material_get(m, (sinter_material_param)p, &value), SINTER_OK);
        assert_true(value == def);
        /* Each key finds its own parameter. */
        sinter_material_param found;
        assert_int_equal(sinter_material_param_find(key, &found), SINTER_OK);
        assert_int_equal(found, p);
        /* The default itself is accepted by set. */
        assert_int_equal(sinter_material_set(m, (sinter_material_param)p, def), SINTER_OK);
    }
    sinter_material_param found;
    assert_int_equal(sinter_material_param_find("no_such_key", &found), SINTER_ERR_NOT_FOUND);
    assert_int_equal(sinter_material_param_info(SINTER_MAT_PARAM_COUNT_, NULL, NULL, NULL, NULL,
                                                NULL, NULL),
                     SINTER_ERR_RANGE);
    const char *unit = NULL;
    sinter_material_param_info(SINTER_MAT_YOUNGS_MODULUS, NULL, &unit, NULL, NULL, NULL, NULL);
    assert_string_equal(unit, "Pa");
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
}

static void test_invalid_values_are_refused(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    sinter_material *m = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_int_equal(sinter_material_create(&m, ctx, "steel"), SINTER_OK);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_YOUNGS_MODULUS, 200e9), SINTER_OK);
    /* Zero density (open lower bound), NaN, infinity, out of range, non-integer law. */
    assert_int_equal(sinter_material_set(m, SINTER_MAT_DENSITY, 0.0), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "density"));
    assert_non_null(strstr(sinter_last_error(ctx), "steel"));
    assert_int_equal(sinter_material_set(m, SINTER_MAT_YOUNGS_MODULUS, NAN), SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_YOUNGS_MODULUS, INFINITY),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_POISSON_RATIO, 0.5), SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_EMISSIVITY, -0.1), SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, SINTER_MAT_SOFTENING_LAW, 1.5), SINTER_ERR_INVALID);
    assert_int_equal(sinter_material_set(m, (sinter_material_param)-1, 1.0), SINTER_ERR_RANGE);
    /* The refused values changed nothing. */
    double e = 0.0;
    assert_int_equal(sinter_material_get(m, SINTER_MAT_YOUNGS_MODULUS, &e), SINTER_OK);
    assert_true(e == 200e9);
    /* Misuse. */
    assert_int_equal(sinter_material_set(NULL, SINTER_MAT_DENSITY, 1.0), SINTER_ERR_NULL);
    assert_int_equal(sinter_material_get(m, SINTER_MAT_DENSITY, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_material_create(NULL, ctx, "x"), SINTER_ERR_NULL);
    assert_int_equal(sinter_material_create(&m, NULL, "x"), SINTER_ERR_NULL);
    char long_name[100];
    memset(long_name, 'a', sizeof(long_name) - 1);
    long_name[99] = '\0';
    sinter_material *other = NULL;
    assert_int_equal(sinter_material_create(&other, ctx, long_name), SINTER_ERR_INVALID);
    assert_null(other);
    /* A clone is independent. */
    sinter_material *copy = NULL;
    assert_int_equal(sinter_material_clone(&copy, m), SINTER_OK);
    assert_int_equal(sinter_material_set(copy, SINTER_MAT_YOUNGS_MODULUS, 1e9), SINTER_OK);
    assert_int_equal(sinter_material_get(m, SINTER_MAT_YOUNGS_MODULUS, &e), SINTER_OK);
    assert_true(e == 200e9);
    sinter_material_destroy(copy);
    sinter_material_destroy(m);
    sinter_material_destroy(NULL);
    sinter_ctx_destroy(ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_and_info),
        cmocka_unit_test(test_invalid_values_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
