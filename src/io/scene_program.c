#define _POSIX_C_SOURCE 200809L
/*
 * A scene's checkpoints: the stepper's state (io/checkpoint.c) with the scene's program as
 * the host section, and the restart that continues it.
 *
 * The program section: "SCENEPRG", u32 version (1), then what identifies the scene (the
 * particle count, the stepper kind, each wall's name and normal in order, each material's name
 * in id order, each heat model's name, whether there is an electric model), then the program
 * (phase, pour start, time origin, next output, next checkpoint, rows, frames and
 * the frames' times; version 2 then the output and checkpoint intervals of the run that wrote
 * it). A restart into a scene that differs in any of the identifying items is refused, naming
 * the first difference.
 *
 * A scene file edited between the run and its restart (docs/getting-started.md, "Stopping and
 * continuing"):
 *  - [stepper] dt of the explicit stepper: the scene's wins, with a warning (the run then no
 *    longer continues bit for bit). The staggered and quasi-static steppers adapt their step:
 *    the checkpoint's is where the adaptation stands and is kept (info level);
 *  - [output] interval and checkpoint_interval: the scene's win, with a warning; the next
 *    sample comes the new interval after the last one written (at the restart's time at the
 *    earliest), the next checkpoint likewise. A version 1 checkpoint does not know the
 *    intervals it ran with: its schedule is kept for one sample, as before;
 *  - material parameters: the checkpoint's are kept (the particles' state was made with them),
 *    reported at the info level.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "heat/heat_model.h"
#include "io/checkpoint.h"
#include "io/scene.h"

static const char PROGRAM_MAGIC[8] = {'S', 'C', 'E', 'N', 'E', 'P', 'R', 'G'};
enum { PROGRAM_VERSION = 2, NAME_BYTES = 64 };

sinter_status scene_program_add_frame(sinter_ctx *ctx, scene_program *p, double time)
{
    sinter_status st = sinter_grow(ctx, (void **)&p->frame_times, &p->frame_capacity,
                                   (size_t)p->frames + 1, sizeof(double));
    if (st != SINTER_OK)
        return st;
    p->frame_times[p->frames++] = time;
    return SINTER_OK;
}

void scene_program_free(sinter_ctx *ctx, scene_program *p)
{
    sinter_free(ctx, p->frame_times);
    memset(p, 0, sizeof(*p));
}

/* ---- writing ---------------------------------------------------------------------------- */

typedef struct buffer {
    unsigned char *data;
    size_t size, capacity;
    sinter_status status;
    sinter_ctx *ctx;
} buffer;

static void put(buffer *b, const void *data, size_t bytes)
{
    if (b->status != SINTER_OK)
        return;
    b->status = sinter_grow(b->ctx, (void **)&b->data, &b->capacity, b->size + bytes, 1);
    if (b->status == SINTER_OK && bytes > 0) {
        memcpy(b->data + b->size, data, bytes);
        b->size += bytes;
    }
}

static void put_u64(buffer *b, uint64_t v)
{
    put(b, &v, sizeof(v));
}

static void put_f64(buffer *b, double v)
{
    put(b, &v, sizeof(v));
}

static void put_name(buffer *b, const char *name)
{
    char field[NAME_BYTES] = {0};
    snprintf(field, sizeof(field), "%s", name);
    put(b, field, sizeof(field));
}

static void put_program(buffer *b, const sinter_scene *sc)
{
    const scene_program *p = &sc->program;
    put(b, PROGRAM_MAGIC, sizeof(PROGRAM_MAGIC));
    const uint32_t version = PROGRAM_VERSION;
    put(b, &version, sizeof(version));
    put_u64(b, sc->ps->count);
    put_u64(b, (uint64_t)sc->st->kind);
    put_u64(b, sc->walls->count);
    for (size_t k = 0; k < sc->walls->count; ++k) {
        put_name(b, sc->wall_names[k]);
        put(b, sc->walls->wall[k].n, sizeof(sc->walls->wall[k].n));
    }
    put_u64(b, sc->material_count);
    for (size_t k = 0; k < sc->material_count; ++k)
        put_name(b, sc->material_names[k]);
    put_u64(b, sc->heat_count);
    for (size_t k = 0; k < sc->heat_count; ++k)
        put_name(b, sc->heats[k]->name);
    put_u64(b, sc->electric != NULL);
    put_u64(b, (uint64_t)p->phase);
    put_f64(b, p->pour_start);
    put_f64(b, p->origin);
    put_f64(b, p->next_output);
    put_f64(b, p->next_checkpoint);
    put_u64(b, p->rows);
    put_u64(b, p->frames);
    put(b, p->frame_times, (size_t)p->frames * sizeof(double));
    put_f64(b, sc->output_interval); /* version 2 */
    put_f64(b, sc->checkpoint_interval);
}

sinter_status sinter_scene_checkpoint_write(const sinter_scene *sc, const char *path)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(sc->ctx, path);
    if (sc->program.phase == SCENE_PHASE_NONE)
        return sinter_fail(sc->ctx, SINTER_ERR_STATE,
                           "sinter_scene_checkpoint_write: the scene has not started its run "
                           "(sinter_scene_run); there is no program to continue");
    buffer b = {NULL, 0, 0, SINTER_OK, sc->ctx};
    put_program(&b, sc);
    sinter_status st = b.status;
    if (st == SINTER_OK)
        st = sinter_checkpoint_write_with(sc->st, path, b.data, b.size);
    sinter_free(sc->ctx, b.data);
    return st;
}

/* ---- reading ---------------------------------------------------------------------------- */

typedef struct cursor {
    const unsigned char *data;
    size_t size, pos;
    int bad;
} cursor;

static const void *take(cursor *c, size_t bytes)
{
    if (c->bad || bytes > c->size - c->pos) {
        c->bad = 1;
        return NULL;
    }
    const void *p = c->data + c->pos;
    c->pos += bytes;
    return p;
}

static uint64_t take_u64(cursor *c)
{
    uint64_t v = 0;
    const void *p = take(c, sizeof(v));
    if (p != NULL)
        memcpy(&v, p, sizeof(v));
    return v;
}

static double take_f64(cursor *c)
{
    double v = 0;
    const void *p = take(c, sizeof(v));
    if (p != NULL)
        memcpy(&v, p, sizeof(v));
    return v;
}

/* A name field as a terminated string (the writer pads with zeros; "" if the file is short). */
static void take_name(cursor *c, char out[NAME_BYTES])
{
    const char *p = take(c, NAME_BYTES);
    memset(out, 0, NAME_BYTES);
    if (p != NULL)
        memcpy(out, p, NAME_BYTES - 1);
}

typedef struct restart_check {
    sinter_scene *sc;
    const char *path;
    scene_program staged; /* the program read, committed when the stepper's state is */
    int intervals;        /* the program has the run's intervals (version 2) */
    double output_interval, checkpoint_interval; /* [s] */
} restart_check;

static const char *const KIND_NAMES[3] = {"explicit", "staggered", "quasistatic"};

static const char *kind_name(uint64_t kind)
{
    return kind < 3 ? KIND_NAMES[kind] : "unknown";
}

/* The checkpoint's scene against this one: NULL if they match, else what differs (in `why`). */
static const char *compare_scene(cursor *c, const sinter_scene *sc, char *why, size_t size)
{
    const uint64_t n = take_u64(c), kind = take_u64(c), nw = take_u64(c);
    if (c->bad)
        return "";
    /* a scene that inserts ([insert]) has gained particles since its start */
    const int inserts = sc->st->insertion != NULL;
    if (inserts ? n < sc->ps->count : n != sc->ps->count) {
        snprintf(why, size, "the checkpoint has %llu particles, the scene %zu",
                 (unsigned long long)n, sc->ps->count);
        return why;
    }
    if (kind != (uint64_t)sc->st->kind) {
        snprintf(why, size, "the checkpoint's stepper is %s, the scene's %s", kind_name(kind),
                 kind_name((uint64_t)sc->st->kind));
        return why;
    }
    if (nw != sc->walls->count) {
        snprintf(why, size, "the checkpoint has %llu walls, the scene %zu", (unsigned long long)nw,
                 sc->walls->count);
        return why;
    }
    char name[NAME_BYTES];
    for (size_t k = 0; k < nw && !c->bad; ++k) {
        take_name(c, name);
        double normal[3] = {0, 0, 0};
        const void *p = take(c, sizeof(normal));
        if (p != NULL)
            memcpy(normal, p, sizeof(normal));
        if (c->bad)
            return "";
        if (strcmp(name, sc->wall_names[k]) != 0) {
            snprintf(why, size, "wall %zu is '%s' in the checkpoint, '%s' in the scene", k, name,
                     sc->wall_names[k]);
            return why;
        }
        const double *m = sc->walls->wall[k].n;
        if (normal[0] != m[0] || normal[1] != m[1] || normal[2] != m[2]) {
            snprintf(why, size,
                     "wall '%s' faces (%g, %g, %g) in the checkpoint, (%g, %g, %g) in the scene",
                     name, normal[0], normal[1], normal[2], m[0], m[1], m[2]);
            return why;
        }
    }
    const uint64_t nm = take_u64(c);
    if (!c->bad && nm != sc->material_count) {
        snprintf(why, size, "the checkpoint has %llu materials, the scene %zu",
                 (unsigned long long)nm, sc->material_count);
        return why;
    }
    for (size_t k = 0; k < nm && !c->bad; ++k) {
        take_name(c, name);
        if (!c->bad && strcmp(name, sc->material_names[k]) != 0) {
            snprintf(why, size, "material %zu is '%s' in the checkpoint, '%s' in the scene", k,
                     name, sc->material_names[k]);
            return why;
        }
    }
    const uint64_t nh = take_u64(c);
    if (!c->bad && nh != sc->heat_count) {
        snprintf(why, size, "the checkpoint has %llu heat models, the scene %zu",
                 (unsigned long long)nh, sc->heat_count);
        return why;
    }
    for (size_t k = 0; k < nh && !c->bad; ++k) {
        take_name(c, name);
        if (!c->bad && strcmp(name, sc->heats[k]->name) != 0) {
            snprintf(why, size, "heat model %zu is '%s' in the checkpoint, '%s' in the scene", k,
                     name, sc->heats[k]->name);
            return why;
        }
    }
    const uint64_t electric = take_u64(c);
    if (!c->bad && electric != (sc->electric != NULL)) {
        snprintf(why, size, "the checkpoint %s an electric model, the scene %s",
                 electric ? "has" : "has no", sc->electric ? "has one" : "has none");
        return why;
    }
    return c->bad ? "" : NULL;
}

static sinter_status check_program(void *user, const void *data, size_t bytes,
                                   const sinter_checkpoint_facts *facts)
{
    restart_check *rc = user;
    sinter_ctx *ctx = rc->sc->ctx;
    if (data == NULL || bytes < sizeof(PROGRAM_MAGIC) + 4 ||
        memcmp(data, PROGRAM_MAGIC, sizeof(PROGRAM_MAGIC)) != 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "checkpoint '%s' holds a stepper's state but no scene program (it "
                           "was written by sinter_checkpoint_write, not by a scene's run): "
                           "restore it with sinter_checkpoint_read; nothing was changed",
                           rc->path);
    cursor c = {data, bytes, sizeof(PROGRAM_MAGIC), 0};
    uint32_t version = 0;
    memcpy(&version, take(&c, sizeof(version)), sizeof(version));
    if (version != 1 && version != PROGRAM_VERSION)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "checkpoint '%s': scene program version %u, this library reads 1 to "
                           "%d; nothing was changed",
                           rc->path, version, PROGRAM_VERSION);
    char why[400];
    const char *differs = compare_scene(&c, rc->sc, why, sizeof(why));
    if (differs != NULL && differs[0] != '\0')
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "checkpoint '%s' does not belong to this scene: %s; nothing was "
                           "changed",
                           rc->path, differs);
    scene_program *p = &rc->staged;
    p->phase = (int)take_u64(&c);
    p->pour_start = take_f64(&c);
    p->origin = take_f64(&c);
    p->next_output = take_f64(&c);
    p->next_checkpoint = take_f64(&c);
    p->rows = take_u64(&c);
    const uint64_t frames = take_u64(&c);
    const void *times = frames <= bytes / sizeof(double) ? take(&c, frames * sizeof(double)) : NULL;
    rc->intervals = version >= 2;
    if (rc->intervals) {
        rc->output_interval = take_f64(&c);
        rc->checkpoint_interval = take_f64(&c);
    }
    const int valid =
        !c.bad && c.pos == c.size && (times != NULL || frames == 0) &&
        (!rc->intervals || (rc->output_interval > 0.0 && isfinite(rc->output_interval) &&
                            rc->checkpoint_interval >= 0.0 && isfinite(rc->checkpoint_interval))) &&
        (p->phase == SCENE_PHASE_POUR || p->phase == SCENE_PHASE_MAIN) && isfinite(p->pour_start) &&
        isfinite(p->origin) && isfinite(p->next_output) && isfinite(p->next_checkpoint) &&
        p->next_output >= facts->time;
    if (!valid)
        return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                           "checkpoint '%s' is refused: its scene program is malformed; nothing "
                           "was changed",
                           rc->path);
    for (uint64_t k = 0; k < frames; ++k) {
        double t;
        memcpy(&t, (const char *)times + 8 * k, sizeof(t));
        sinter_status st = scene_program_add_frame(ctx, p, t);
        if (st != SINTER_OK)
            return st;
    }
    return SINTER_OK;
}

/* The scene's time step against the checkpoint's (see the top): the explicit stepper takes
 * the scene's back, the adaptive ones keep the checkpoint's. */
static sinter_status reconcile_dt(sinter_scene *sc, double dt_before)
{
    const double dt_after = sc->st->dt;
    if (dt_after == dt_before)
        return SINTER_OK;
    if (sc->st->kind != SINTER_STEPPER_EXPLICIT) {
        sinter_log(sc->ctx, SINTER_LOG_INFO,
                   "restart: the %s stepper continues with the checkpoint's adapted time step "
                   "%.17g s (the scene's dt = %.17g s is its first step)",
                   kind_name((uint64_t)sc->st->kind), dt_after, dt_before);
        return SINTER_OK;
    }
    sinter_log(sc->ctx, SINTER_LOG_WARNING,
               "restart: the scene's time step dt = %.17g s replaces the checkpoint's %.17g s; "
               "the run no longer continues bit for bit",
               dt_before, dt_after);
    return sinter_stepper_set_dt(sc->st, dt_before);
}

/* The next time of a schedule whose last event was at `next - old` when its interval becomes
 * `now_interval`: that event plus the new interval, not before time t. */
static double rescheduled(double next, double old, double now_interval, double t)
{
    return fmax(t, next - old + now_interval);
}

/* The scene's output and checkpoint intervals against the run's (version 2 programs). */
static void reconcile_schedule(sinter_scene *sc, const restart_check *rc)
{
    scene_program *p = &sc->program;
    const double t = sc->st->time;
    if (!rc->intervals)
        return;
    if (sc->output_interval != rc->output_interval) {
        p->next_output = rescheduled(p->next_output, rc->output_interval, sc->output_interval, t);
        sinter_log(sc->ctx, SINTER_LOG_WARNING,
                   "restart: the scene's [output] interval = %.17g s replaces the run's %.17g s; "
                   "the next sample is at t = %.17g s",
                   sc->output_interval, rc->output_interval, p->next_output);
    }
    if (sc->checkpoint_interval != rc->checkpoint_interval) {
        p->next_checkpoint =
            rescheduled(p->next_checkpoint, rc->checkpoint_interval, sc->checkpoint_interval, t);
        sinter_log(sc->ctx, SINTER_LOG_WARNING,
                   "restart: the scene's [output] checkpoint_interval = %.17g s replaces the "
                   "run's %.17g s",
                   sc->checkpoint_interval, rc->checkpoint_interval);
    }
}

/* What the checkpoint changed of the scene's materials, at the info level. */
static void report_overrides(sinter_scene *sc, const double before[][SINTER_MAT_PARAM_COUNT_])
{
    for (size_t m = 0; m < sc->material_count; ++m)
        for (int p = 0; p < SINTER_MAT_PARAM_COUNT_; ++p) {
            const double after = sc->ps->materials[m].value[p];
            if (after == before[m][p] || (isnan(after) && isnan(before[m][p])))
                continue;
            const char *key = "?";
            sinter_material_param_info((sinter_material_param)p, &key, NULL, NULL, NULL, NULL,
                                       NULL);
            sinter_log(sc->ctx, SINTER_LOG_INFO,
                       "restart: material '%s' %s = %.17g from the checkpoint replaces the "
                       "scene's %.17g",
                       sc->material_names[m], key, after, before[m][p]);
        }
}

sinter_status sinter_scene_restart(sinter_scene *sc, const char *path)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = sc->ctx;
    SINTER_CHECK_NULL(ctx, path);
    const double dt_before = sc->st->dt;
    double(*before)[SINTER_MAT_PARAM_COUNT_] =
        sinter_calloc(ctx, sc->material_count + 1, sizeof(*before));
    if (before == NULL)
        return sinter_last_status(ctx);
    for (size_t m = 0; m < sc->material_count; ++m)
        memcpy(before[m], sc->ps->materials[m].value, sizeof(before[m]));
    restart_check rc;
    memset(&rc, 0, sizeof(rc));
    rc.sc = sc;
    rc.path = path;
    sinter_status st = sinter_checkpoint_read_with(sc->st, path, check_program, &rc);
    if (st == SINTER_OK) {
        report_overrides(sc, (const double(*)[SINTER_MAT_PARAM_COUNT_])before);
        st = reconcile_dt(sc, dt_before); /* (a dt the scene's parser accepted) */
        scene_program_free(ctx, &sc->program);
        sc->program = rc.staged;
        reconcile_schedule(sc, &rc);
        /* the furnace, as loaded, is timed from 0: delay it to the program's origin */
        sinter_stepper_shift_furnace(sc->st, sc->program.origin - sc->furnace_shift);
        sc->furnace_shift = sc->program.origin;
        sinter_log(ctx, SINTER_LOG_INFO,
                   "restart: continuing '%s' from t = %.17g s (%s), %llu samples and %llu frames "
                   "written before",
                   sc->name, sc->st->time,
                   sc->program.phase == SCENE_PHASE_POUR ? "pouring" : "the main run",
                   (unsigned long long)sc->program.rows, (unsigned long long)sc->program.frames);
    } else {
        scene_program_free(ctx, &rc.staged);
    }
    sinter_free(ctx, before);
    return st;
}

sinter_status sinter_scene_set_end_time(sinter_scene *sc, double end_time)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    if (!isfinite(end_time) || !(end_time > 0.0))
        return sinter_fail(sc->ctx, SINTER_ERR_INVALID,
                           "sinter_scene_set_end_time: end time %g s must be positive and finite",
                           end_time);
    sc->end_time = end_time;
    return SINTER_OK;
}
