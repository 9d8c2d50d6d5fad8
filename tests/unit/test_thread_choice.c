/*
 * The explicit stepper's thread count chosen by timing (src/stepper/thread_choice.c), driven
 * with made-up step times so that every decision is known: 5 steps on the context's threads
 * and 5 on one, the first of each untimed; the faster count kept until the interval ends;
 * measured again after a rejected step, a change of the particles or of the context's
 * threads; nothing chosen with option 0, with one thread, or while the streaming stores are
 * being timed. (That the choice changes no bit is test_stepper's
 * test_thread_choice_changes_nothing.)
 */
#include <stdio.h>

#include "scene_support.h"
#include "contact/neighbors.h"
#include "core/stream_store.h"
#include "stepper/stepper.h"

typedef struct log_seen {
    int count;
    char last[256];
} log_seen;

static void keep_log(int level, const char *message, void *user)
{
    log_seen *seen = user;
    (void)level;
    seen->count++;
    snprintf(seen->last, sizeof(seen->last), "%s", message);
}

/* A stepper over a few spheres on a context of `threads` threads, with option thread_choice
 * -1 (scene_open sets 0 for the other tests). */
static void open_scene(scene *s, int threads, log_seen *seen)
{
    scene_init(s);
    OK(sinter_ctx_set_threads(s->ctx, threads));
    OK(sinter_ctx_set_log(s->ctx, keep_log, SINTER_LOG_DEBUG, seen));
    scene_material(s, 1e7, 0.3, 2500, 0.2, 0.3);
    scene_open(s, "hertz_mindlin", 1);
    for (int k = 0; k < 8; ++k)
        scene_add(s, 3e-3 * k, 0.0, 1e-3, 1e-3);
    OK(sinter_stepper_set_option(s->st, "thread_choice", -1));
}

/* One step of the choice: the threads it sets for the step, then the step's made-up time. */
static int step(sinter_stepper *st, double seconds, int accepted)
{
    sinter_thread_choice_begin(st);
    const int used = sinter_threads(st->ctx);
    sinter_thread_choice_end(st, seconds, accepted);
    return used;
}

#ifdef _OPENMP
/* A measurement: 5 steps on 2 threads, then 5 on one, with these times (the first of each
 * block `warm`); returns the count it chose. */
static int measure(scene *s, double two, double one, double warm)
{
    for (int k = 0; k < 10; ++k) {
        const int first = k % 5 == 0;
        const int used = step(s->st, first ? warm : (k < 5 ? two : one), 1);
        assert_int_equal(used, k < 5 ? 2 : 1);
    }
    assert_int_equal(sinter_threads(s->ctx), 2); /* the context's own count after a step */
    return s->st->threads_choice.decided;
}
#endif

static void test_faster_count_is_kept(void **unused)
{
    (void)unused;
    scene s;
    log_seen seen = {0, ""};
    open_scene(&s, 2, &seen);
#ifdef _OPENMP
    /* one thread faster; the untimed first steps would say otherwise */
    assert_int_equal(measure(&s, 2e-3, 1e-3, 1e-9), 1);
    assert_int_equal(seen.count, 1);
    assert_non_null(strstr(seen.last, "1 thread for the next"));
    assert_non_null(strstr(seen.last, "(shortest step 2 ms on 2 threads, 1 ms on one)"));
    for (int k = 0; k < 20; ++k) /* kept, whatever the steps take, until the interval ends */
        assert_int_equal(step(s.st, 1.0, 1), 1);
    s.st->threads_choice.next = 0.0; /* the interval over: measured again */
    assert_int_equal(measure(&s, 1e-3, 2e-3, 1.0), 2);
    assert_non_null(strstr(seen.last, "2 threads for the next"));
    assert_int_equal(step(s.st, 1.0, 1), 2);
    /* a rejected step in a measurement starts it again */
    s.st->threads_choice.next = 0.0;
    for (int k = 0; k < 7; ++k)
        step(s.st, 1e-3, 1);
    assert_int_equal(step(s.st, 1e-3, 0), 1); /* the 8th, on one thread, rejected */
    assert_int_equal(s.st->threads_choice.decided, 0);
    assert_int_equal(measure(&s, 2e-3, 1e-3, 1.0), 1);
    /* other particles, or another thread count, are measured again */
    scene_add(&s, 0.0, 5e-3, 1e-3, 1e-3);
    assert_int_equal(step(s.st, 1e-3, 1), 2);
    assert_int_equal(s.st->threads_choice.decided, 0);
    OK(sinter_ctx_set_threads(s.ctx, 3));
    assert_int_equal(step(s.st, 1e-3, 1), 3);
    assert_int_equal(s.st->threads_choice.requested, 3);
#else
    /* a build without OpenMP has one thread: nothing to choose */
    for (int k = 0; k < 12; ++k)
        assert_int_equal(step(s.st, 1e-3, 1), 1);
    assert_int_equal(seen.count, 0);
#endif
    scene_close(&s);
}

static void test_nothing_chosen(void **unused)
{
    (void)unused;
    scene s;
    log_seen seen = {0, ""};
    open_scene(&s, 1, &seen); /* one thread */
    for (int k = 0; k < 12; ++k)
        assert_int_equal(step(s.st, k < 5 ? 2e-3 : 1e-3, 1), 1);
    assert_int_equal(s.ctx->step_threads, 0);
    OK(sinter_ctx_set_threads(s.ctx, 2));
    OK(sinter_stepper_set_option(s.st, "thread_choice", 0)); /* always the context's */
    for (int k = 0; k < 12; ++k)
        assert_int_equal(step(s.st, k < 5 ? 2e-3 : 1e-3, 1), sinter_threads_allowed(s.ctx));
    assert_int_equal(s.st->threads_choice.decided, 0);
    assert_int_equal(seen.count, 0);
    /* while the streaming stores are being timed (from 65536 particles), the choice waits */
    OK(sinter_stepper_set_option(s.st, "thread_choice", -1));
    s.st->stores.decided = -1;
    const size_t real = s.ps->count;
    s.ps->count = 65536; /* as if there were that many: only the count is read */
    const int waits = sinter_explicit_stores_measuring(s.st);
    const int used = step(s.st, 1e-3, 1);
    s.ps->count = real;
#if SINTER_STREAMING_STORES
    assert_true(waits);
#endif
    if (waits) /* no step of the thread choice's measurement was taken */
        assert_int_equal(s.st->threads_choice.trial, 0);
    assert_int_equal(used, sinter_threads_allowed(s.ctx));
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_faster_count_is_kept),
        cmocka_unit_test(test_nothing_chosen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
