/* Context, status codes, version, logging and the allocator hook. */
#include <string.h>

#include "test_support.h"

static void test_status_strings(void **state)
{
    (void)state;
    assert_string_equal(sinter_status_string(SINTER_OK), "success");
    assert_string_equal(sinter_status_name(SINTER_ERR_BUSY), "SINTER_ERR_BUSY");
    assert_string_equal(sinter_status_string(12345), "unknown status");
    /* Every code of the list has a distinct message and its own name. */
    const int codes[] = {
#define CODE_(name, value, message) value,
        SINTER_STATUS_LIST(CODE_)
#undef CODE_
    };
    const size_t n = sizeof(codes) / sizeof(codes[0]);
    for (size_t a = 0; a < n; ++a) {
        assert_true(codes[a] <= 0);
        assert_string_not_equal(sinter_status_string(codes[a]), "unknown status");
        for (size_t b = a + 1; b < n; ++b) {
            assert_int_not_equal(codes[a], codes[b]);
            assert_string_not_equal(sinter_status_string(codes[a]),
                                    sinter_status_string(codes[b]));
        }
    }
}

static void test_version(void **state)
{
    (void)state;
    assert_int_equal(sinter_version_number(), SINTER_VERSION_NUMBER);
    assert_string_equal(sinter_version_string(), SINTER_VERSION_STRING);
    assert_int_equal(SINTER_VERSION_NUMBER, SINTER_VERSION_MAJOR * 10000 +
                                                SINTER_VERSION_MINOR * 100 + SINTER_VERSION_PATCH);
}

static void test_ctx_misuse(void **state)
{
    (void)state;
    assert_int_equal(sinter_ctx_create(NULL, NULL), SINTER_ERR_NULL);
    sinter_ctx *ctx = (sinter_ctx *)0x1;
    sinter_allocator bad = {sizeof(sinter_allocator) - 1, NULL, NULL, NULL, NULL};
    assert_int_equal(sinter_ctx_create(&ctx, &bad), SINTER_ERR_STRUCT_SIZE);
    assert_ptr_equal(ctx, (sinter_ctx *)0x1); /* untouched on error */
    bad.struct_size = sizeof(sinter_allocator);
    assert_int_equal(sinter_ctx_create(&ctx, &bad), SINTER_ERR_INVALID);
    sinter_ctx_destroy(NULL);
    assert_non_null(sinter_last_error(NULL));
    assert_int_equal(sinter_clear_error(NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_ctx_set_threads(NULL, 1), SINTER_ERR_NULL);
}

static void test_ctx_errors_and_threads(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    assert_string_equal(sinter_last_error(ctx), "");
    assert_int_equal(sinter_last_status(ctx), SINTER_OK);
    assert_int_equal(sinter_ctx_set_threads(ctx, -2), SINTER_ERR_INVALID);
    assert_int_equal(sinter_last_status(ctx), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(ctx), "-2"));
    int threads = 0;
    assert_int_equal(sinter_ctx_get_threads(ctx, &threads), SINTER_OK);
    assert_int_equal(threads, 1);
    assert_int_equal(sinter_ctx_set_threads(ctx, 2), SINTER_OK);
    assert_int_equal(sinter_ctx_get_threads(ctx, &threads), SINTER_OK);
    assert_int_equal(threads, 2);
    assert_int_equal(sinter_clear_error(ctx), SINTER_OK);
    assert_string_equal(sinter_last_error(ctx), "");
    sinter_ctx_destroy(ctx);
}

typedef struct log_record {
    int calls;
    int level;
    char text[256];
} log_record;

static void record_log(int level, const char *message, void *user)
{
    log_record *r = user;
    r->calls++;
    r->level = level;
    strncpy(r->text, message, sizeof(r->text) - 1);
}

static void test_log_callback(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, NULL), SINTER_OK);
    log_record rec = {0, -1, ""};
    assert_int_equal(sinter_ctx_set_log(ctx, record_log, 99, &rec), SINTER_ERR_INVALID);
    assert_int_equal(sinter_ctx_set_log(ctx, record_log, SINTER_LOG_DEBUG, &rec), SINTER_OK);
    /* Errors are passed to the log at debug level with their detail. */
    assert_int_equal(sinter_ctx_set_threads(ctx, -5), SINTER_ERR_INVALID);
    assert_int_equal(rec.calls, 1);
    assert_int_equal(rec.level, SINTER_LOG_DEBUG);
    assert_non_null(strstr(rec.text, "-5"));
    /* Below the chosen level nothing is passed on. */
    assert_int_equal(sinter_ctx_set_log(ctx, record_log, SINTER_LOG_ERROR, &rec), SINTER_OK);
    assert_int_equal(sinter_ctx_set_threads(ctx, -6), SINTER_ERR_INVALID);
    assert_int_equal(rec.calls, 1);
    sinter_ctx_destroy(ctx);
}

static void test_allocator_hook_and_failure(void **state)
{
    (void)state;
    /* The context itself comes from the hook, and goes back to it. */
    counting_allocator c = {0, 0, -1, 0};
    sinter_allocator a = counting_allocator_hook(&c);
    sinter_ctx *ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, &a), SINTER_OK);
    assert_int_equal(c.allocations, 1);
    sinter_ctx_destroy(ctx);
    assert_int_equal(c.frees, 1);
    /* A failing first allocation gives SINTER_ERR_NOMEM and no context. */
    counting_allocator f = {0, 0, 0, 0};
    a = counting_allocator_hook(&f);
    ctx = NULL;
    assert_int_equal(sinter_ctx_create(&ctx, &a), SINTER_ERR_NOMEM);
    assert_null(ctx);
    assert_int_equal(f.allocations, f.frees);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_ctx_misuse),
        cmocka_unit_test(test_ctx_errors_and_threads),
        cmocka_unit_test(test_log_callback),
        cmocka_unit_test(test_allocator_hook_and_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
