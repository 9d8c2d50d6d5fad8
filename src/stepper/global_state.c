/*
 * The stepper's global part (issue 43, portable checkpoints): what is not kept per particle
 * and is the same on every subdomain of a decomposed run (time, step, counters, the neighbour
 * search's skin and reach, the walls' state, the staggered step controller, the frozen heat
 * stage's counters, the continuous insertion, the quasi-static stepper's step control, counters,
 * initial extents and cell, qs_portable.c). A portable checkpoint is this part plus the
 * export records of every particle (migrate.c); a restart loads the part into a stepper set
 * up alike with no particles, then imports the records, in any order and split in any way.
 *
 * Stream (host byte order, checked by a marker): "SINTERGL", u32 version, u32 marker, u64 total
 * bytes, u64 stepper kind, u64 force slots and each one's name (char[64]), u64 walls, the
 * values below in the order written, u64 FNV-1a 64 checksum of all bytes before it. Version 2
 * appends the quasi-static values (zeros for other steppers); version 1 is not read.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/fnv1a.h"
#include "stepper/insertion.h"
#include "stepper/migrate.h"
#include "stepper/stepper.h"

#define GLOBAL_VERSION 2u
#define GLOBAL_NAME 64
#define WALL_F64 12 /* motion start, temperature, force (3), moment (3), servo (4) */
enum { STEPPER_F64 = 13, STEPPER_U64 = 15 };

static const char MAGIC[8] = {'S', 'I', 'N', 'T', 'E', 'R', 'G', 'L'};

static size_t walls_of(const sinter_stepper *st)
{
    return st->walls != NULL ? st->walls->count : 0;
}

static size_t global_bytes(const sinter_stepper *st)
{
    return 8 + 4 + 4 + 8 + 8 + 8 + GLOBAL_NAME * st->force_count + 8 +
           8 * (STEPPER_F64 + STEPPER_U64) + 8 * WALL_F64 * walls_of(st) +
           8 * (1 + SINTER_INSERTION_U64 + SINTER_INSERTION_F64) +
           8 * (SINTER_QS_GLOBAL_F64 + SINTER_QS_GLOBAL_U64) + 8;
}

/* The stepper's values, in the stream's order. */
static void values_of(const sinter_stepper *st, double f[STEPPER_F64], uint64_t u[STEPPER_U64])
{
    const sinter_staggered *sg = &st->staggered;
    const sinter_frozen *fz = &st->frozen;
    const double fv[STEPPER_F64] = {
        st->time,   st->dt,          st->nb.skin,        st->nb.reach, st->thermal_last_h,
        sg->h_prev, sg->contraction, sg->control.x_prev, fz->h,        fz->ke_last,
        fz->time,   st->eval_lag,    st->stats.dt};
    const uint64_t uv[STEPPER_U64] = {st->stats.steps,
                                      st->stats.rejected,
                                      st->stats.neighbor_builds,
                                      st->stats.iterations,
                                      st->stats.evaluations,
                                      st->stats.bonds_broken,
                                      st->steps_since_sort,
                                      (uint64_t)st->forces_current,
                                      st->electric_iterations,
                                      (uint64_t)st->skin_set,
                                      (uint64_t)sg->control.after_reject,
                                      fz->mech_steps,
                                      fz->steps,
                                      fz->rejected,
                                      fz->wakeups + (fz->freezes << 32)};
    memcpy(f, fv, sizeof(fv));
    memcpy(u, uv, sizeof(uv));
}

static sinter_status check_kind(const sinter_stepper *st, const char *func)
{
    if (st->frozen.active)
        return sinter_fail(st->ctx, SINTER_ERR_STATE,
                           "%s: the frozen heat stage holds per-particle rates; save while the "
                           "mechanics run",
                           func);
    if (sinter_ghosts_on(&st->ghosts))
        return sinter_fail(st->ctx, SINTER_ERR_UNSUPPORTED,
                           "%s: the stepper has periodic boundaries, whose images are not "
                           "portable",
                           func);
    return SINTER_OK;
}

sinter_status sinter_stepper_save_global(const sinter_stepper *st, void *buf, size_t cap,
                                         size_t *bytes)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(st->ctx, bytes);
    const char *F = "sinter_stepper_save_global";
    sinter_status s = check_kind(st, F);
    if (s != SINTER_OK)
        return s;
    const size_t need = global_bytes(st);
    *bytes = need;
    if (buf == NULL)
        return SINTER_OK; /* the size only */
    if (cap < need)
        return sinter_fail(st->ctx, SINTER_ERR_RANGE,
                           "%s: the global part needs %zu bytes, the buffer holds %zu", F, need,
                           cap);
    unsigned char *p = buf;
#define PUT(src, n)                                                                                \
    do {                                                                                           \
        memcpy(p, (src), (n));                                                                     \
        p += (n);                                                                                  \
    } while (0)
    const uint32_t version = GLOBAL_VERSION, marker = 0x01020304u;
    const uint64_t head[3] = {need, (uint64_t)st->kind, st->force_count};
    PUT(MAGIC, 8);
    PUT(&version, 4);
    PUT(&marker, 4);
    PUT(head, sizeof(head));
    for (size_t k = 0; k < st->force_count; ++k) {
        char name[GLOBAL_NAME] = {0};
        snprintf(name, sizeof(name), "%s", st->forces[k].model->name);
        PUT(name, GLOBAL_NAME);
    }
    const uint64_t nw = walls_of(st);
    PUT(&nw, 8);
    double f[STEPPER_F64];
    uint64_t u[STEPPER_U64];
    values_of(st, f, u);
    PUT(f, sizeof(f));
    PUT(u, sizeof(u));
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *w = &st->walls->wall[k];
        const double v[WALL_F64] = {w->motion_start, w->temperature, w->force[0],  w->force[1],
                                    w->force[2],     w->moment[0],   w->moment[1], w->moment[2],
                                    w->servo_time,   w->servo_disp,  w->servo_v,   w->servo_int};
        PUT(v, sizeof(v));
    }
    uint64_t iu[SINTER_INSERTION_U64] = {0};
    double id[SINTER_INSERTION_F64] = {0};
    const uint64_t has = st->insertion != NULL;
    if (has)
        sinter_insertion_get_state(st->insertion, iu, id);
    PUT(&has, 8);
    PUT(iu, sizeof(iu));
    PUT(id, sizeof(id));
    double qf[SINTER_QS_GLOBAL_F64];
    uint64_t qu[SINTER_QS_GLOBAL_U64];
    sinter_qs_global_values(st->quasistatic, qf, qu);
    PUT(qf, sizeof(qf));
    PUT(qu, sizeof(qu));
    const uint64_t sum = sinter_fnv1a(SINTER_FNV1A_START, buf, (size_t)(p - (unsigned char *)buf));
    PUT(&sum, 8);
#undef PUT
    return SINTER_OK;
}

sinter_status sinter_stepper_load_global(sinter_stepper *st, const void *buf, size_t bytes)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    SINTER_CHECK_NULL(ctx, buf);
    const char *F = "sinter_stepper_load_global";
    sinter_status s = check_kind(st, F);
    if (s != SINTER_OK)
        return s;
    if (st->ps->count > 0)
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "%s: load the global part into a stepper without particles, then "
                           "import the records (sinter_stepper_import)",
                           F);
    const unsigned char *p = buf;
    uint32_t version = 0, marker = 0;
    uint64_t head[3] = {0, 0, 0};
    if (bytes < 48 || memcmp(p, MAGIC, 8) != 0)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the buffer is not a global part of sinter_stepper_save_global", F);
    memcpy(&version, p + 8, 4);
    memcpy(&marker, p + 12, 4);
    memcpy(head, p + 16, sizeof(head));
    if (marker != 0x01020304u || version != GLOBAL_VERSION || head[0] != bytes)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: format %u, byte order or size (%llu bytes, %zu given) not this "
                           "build's",
                           F, version, (unsigned long long)head[0], bytes);
    uint64_t sum;
    memcpy(&sum, p + bytes - 8, 8);
    if (sinter_fnv1a(SINTER_FNV1A_START, p, bytes - 8) != sum)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "%s: the checksum does not match (the buffer is damaged)", F);
    if (head[1] != (uint64_t)st->kind || head[2] != st->force_count)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the part is of a stepper of kind %llu with %llu force models; "
                           "this one is of kind %d with %zu",
                           F, (unsigned long long)head[1], (unsigned long long)head[2], st->kind,
                           st->force_count);
    if (bytes != global_bytes(st))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the part is for another number of walls than this stepper's %zu", F,
                           walls_of(st));
    p += 40;
    for (size_t k = 0; k < st->force_count; ++k, p += GLOBAL_NAME) {
        char name[GLOBAL_NAME] = {0};
        snprintf(name, sizeof(name), "%s", st->forces[k].model->name);
        if (memcmp(name, p, GLOBAL_NAME) != 0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: force model %zu of the part is not this stepper's '%s'", F, k,
                               name);
    }
    p += 8; /* the wall count, checked through the size */
    double f[STEPPER_F64];
    uint64_t u[STEPPER_U64];
    memcpy(f, p, sizeof(f));
    memcpy(u, p + sizeof(f), sizeof(u));
    p += sizeof(f) + sizeof(u);
    const size_t nw = walls_of(st);
    const unsigned char *walls = p;
    p += 8 * WALL_F64 * nw;
    uint64_t has;
    uint64_t iu[SINTER_INSERTION_U64];
    double id[SINTER_INSERTION_F64];
    memcpy(&has, p, 8);
    memcpy(iu, p + 8, sizeof(iu));
    memcpy(id, p + 8 + sizeof(iu), sizeof(id));
    p += 8 + sizeof(iu) + sizeof(id);
    double qf[SINTER_QS_GLOBAL_F64];
    uint64_t qu[SINTER_QS_GLOBAL_U64];
    memcpy(qf, p, sizeof(qf));
    memcpy(qu, p + sizeof(qf), sizeof(qu));
    const char *why = sinter_qs_global_wrong(qf, qu);
    if (why != NULL)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT, "%s: %s", F, why);
    if (qu[0] && st->kind != SINTER_STEPPER_QUASISTATIC)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: the part holds a quasi-static state; this stepper is not one", F);
    for (int k = 0; k < STEPPER_F64; ++k)
        if (!isfinite(f[k]) && !(k == 9 && f[k] > 0.0)) /* ke_last: +inf before a measure */
            return sinter_fail(ctx, SINTER_ERR_CORRUPT, "%s: value %d is not finite", F, k);
    if (!(f[1] > 0.0) || !(f[2] >= 0.0) || u[7] > 1 || u[9] > 1 || u[10] > 1 || has > 1)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT, "%s: a step, skin or flag is out of range", F);
    if (qu[0] && st->quasistatic == NULL &&
        (s = sinter_qs_create(&st->quasistatic, ctx, &st->quasistatic_options)) != SINTER_OK)
        return s;
    /* Nothing can fail from here on. */
    st->time = f[0];
    st->dt = f[1];
    st->nb.skin = f[2];
    st->nb.reach = f[3];
    st->thermal_last_h = f[4];
    st->staggered.h_prev = f[5];
    st->staggered.contraction = f[6];
    st->staggered.control.x_prev = f[7];
    st->staggered.history_valid = 0; /* per particle index: restarts */
    st->frozen.h = f[8];
    st->frozen.ke_last = f[9];
    st->frozen.time = f[10];
    st->eval_lag = f[11];
    st->stats.dt = f[12];
    st->stats.steps = u[0];
    st->stats.rejected = u[1];
    st->stats.neighbor_builds = u[2];
    st->stats.iterations = u[3];
    st->stats.evaluations = u[4];
    st->stats.bonds_broken = u[5];
    st->steps_since_sort = u[6];
    st->forces_current = (int)u[7];
    st->electric_iterations = u[8];
    st->skin_set = (int)u[9];
    st->staggered.control.after_reject = (int)u[10];
    st->frozen.mech_steps = u[11];
    st->frozen.steps = u[12];
    st->frozen.rejected = u[13];
    st->frozen.wakeups = u[14] & 0xffffffffu;
    st->frozen.freezes = u[14] >> 32;
    for (size_t k = 0; k < nw; ++k) {
        sinter_wall *w = &st->walls->wall[k];
        double v[WALL_F64];
        memcpy(v, walls + 8 * WALL_F64 * k, sizeof(v));
        w->motion_start = v[0];
        w->temperature = v[1];
        memcpy(w->force, v + 2, 3 * sizeof(double));
        memcpy(w->moment, v + 5, 3 * sizeof(double));
        w->servo_time = v[8];
        w->servo_disp = v[9];
        w->servo_v = v[10];
        w->servo_int = v[11];
    }
    if (qu[0]) /* the quasi-static stepper's own; its per-particle state comes with the records */
        sinter_qs_global_load(st->quasistatic, qf, qu, st->domain.on);
    if (has && st->insertion != NULL) /* a host without one ignores it */
        sinter_insertion_set_state(st->insertion, iu, id);
    if (st->walls != NULL) /* motions come from the set-up, as for a checkpoint */
        (void)sinter_walls_move(st->walls, st->time);
    /* the (empty) set's state is the one the forces are current for: the records bring theirs */
    st->write_generation = st->ps->write_generation;
    st->population_generation = st->ps->population_generation;
    return SINTER_OK;
}
