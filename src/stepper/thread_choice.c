/*
 * The explicit stepper's thread count, chosen by timing (thread_choice.h).
 *
 * A measurement takes BLOCK steps on the context's T threads, then BLOCK on one; the first
 * step of each block moves the particles' cache lines to the threads that now own them and
 * is not timed, and the shortest of the others decides. The choice holds for at least
 * MIN_INTERVAL seconds and for at least INTERVAL_FACTOR times the measurement's own time,
 * so that measuring costs a few per cent at most where a step is long (a million particles:
 * a step of 0.1 s on one thread, measured every 40 s or so). The streaming-store choice of
 * the same steps (explicit.c) is made first, on T threads.
 */
#include "thread_choice.h"

#include <math.h>

#include "core/core.h"
#include "stepper.h"

enum { BLOCK = 5, INTERVAL_FACTOR = 50 };
static const double MIN_INTERVAL = 0.5; /* [s] */

void sinter_thread_choice_init(sinter_thread_choice *c)
{
    *c = (sinter_thread_choice){.option = -1};
}

static void restart(sinter_thread_choice *c, int requested, uint64_t layout)
{
    c->requested = requested;
    c->layout = layout;
    c->decided = 0;
    c->trial = 0;
    c->best[0] = c->best[1] = INFINITY;
}

void sinter_thread_choice_begin(sinter_stepper *st)
{
    sinter_thread_choice *c = &st->threads_choice;
    sinter_ctx *ctx = st->ctx;
    ctx->step_threads = 0;
    const int requested = sinter_threads_allowed(ctx);
    if (c->option == 0 || requested <= 1 || sinter_explicit_stores_measuring(st))
        return;
    const double now = sinter_clock();
    if (c->requested != requested || c->layout != st->ps->layout_generation ||
        (c->decided > 0 && now >= c->next))
        restart(c, requested, st->ps->layout_generation);
    if (c->decided > 0) {
        ctx->step_threads = c->decided;
    } else {
        if (c->trial == 0)
            c->started = now;
        ctx->step_threads = c->trial < BLOCK ? requested : 1;
    }
}

void sinter_thread_choice_end(sinter_stepper *st, double seconds, int accepted)
{
    sinter_thread_choice *c = &st->threads_choice;
    const int chosen = st->ctx->step_threads; /* 0: the step was not the choice's */
    st->ctx->step_threads = 0;
    if (chosen == 0 || c->decided > 0)
        return;
    if (!accepted) { /* measured again from the next step */
        restart(c, c->requested, c->layout);
        return;
    }
    const int k = c->trial++;
    if (k % BLOCK != 0 && seconds < c->best[k / BLOCK])
        c->best[k / BLOCK] = seconds;
    if (c->trial == 2 * BLOCK) {
        c->decided = c->best[1] < c->best[0] ? 1 : c->requested;
        const double now = sinter_clock();
        c->next = now + fmax(MIN_INTERVAL, INTERVAL_FACTOR * (now - c->started));
        sinter_log(st->ctx, SINTER_LOG_DEBUG,
                   "explicit stepper: %d thread%s for the next %.3g s (shortest step %.3g ms on "
                   "%d threads, %.3g ms on one)",
                   c->decided, c->decided == 1 ? "" : "s", c->next - now, 1e3 * c->best[0],
                   c->requested, 1e3 * c->best[1]);
    }
}
