#define _POSIX_C_SOURCE 200809L
/*
 * Checkpoints: the complete state of a stepper in a versioned binary file.
 *
 * Layout (little-endian host order, checked by a marker): magic "SINTERCK",
 * u32 format version, u32 byte-order marker, then tagged sections, then an
 * FNV-1a 64-bit checksum of everything before it. The neighbour lists and the
 * committed contact history are stored as they are, so that a restarted run
 * sums forces in the same order and continues bit for bit.
 *
 * Reading stages everything in fresh buffers and changes the stepper only
 * when the whole file has been checked.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <sys/stat.h>

#include "core/fnv1a.h"
#include "electric/electric.h"
#include "io/checkpoint.h"
#include "io/path.h"
#include "stepper/insertion.h"
#include "stepper/stepper.h"

/* 2: material parameter count recorded (53 parameters since the neck data; 54 with
 *    melting_temperature: files with 53 are still read, the melting point then off; 58 with
 *    the 7DOF path constants neck_*_path and lattice_mobile_fraction (issue 42): files with 53
 *    to 57 are still read, those at their defaults, but their quasi-static links are not (the
 *    links carry the neck data, whose layout grew by the four constants))
 * 3: a quasi-static section at the end (links, necks, plane conditions: stepper/qs_state.c);
 *    version 2 files are still read (they hold no quasi-static state)
 * 4: then the electric network's warm start (the potentials its next solve starts from:
 *    electric/network.c); versions 2 and 3 are still read (the next solve starts from 0)
 * 5: then the particle ranges of the contact list's partition (contact/chunks.h), which the
 *    first search over a pair list makes from the contacts of that moment and the later ones
 *    keep: restored, the sums continue in the same order, bit for bit; earlier versions are
 *    still read (the partition is made afresh, and sums may differ in the last bits)
 * 6: then the steps since the last spatial sort (option sort_interval), whether the forces
 *    of the state are evaluated (a quasi-static step leaves them to the next advance, which
 *    evaluates them at its start: a restored run must do the same), and a host section
 *    (u64 bytes, then the bytes: a scene's program, io/scene_program.c; 0 bytes from
 *    sinter_checkpoint_write); earlier versions are still read (no host section, the sort
 *    counter as it was)
 * 7: then the iteration counts, and the staggered stepper's step controller and predictor
 *    history (scheme 1; staggered.c)
 * 8: then the walls' kinds' state (walls/wall_shapes.c, walls/servo.c): per wall its reaction
 *    moment (3), its servo's committed time, displacement, velocity and error integral (4),
 *    and the rest of its neighbour-list reference (3: a non-planar kind's point and angle);
 *    earlier versions are still read (they hold planes only: no moment, no servo)
 * 9: then the frozen heat stage (stepper/frozen_heat.h): whether the mechanics are frozen,
 *    the heat step's proposal, the mechanical steps since the last wake-up, the last kinetic
 *    energy of its rest test, its statistics, and while frozen the rates of the last heat step
 *    and the modulus factors of the freeze (per particle); earlier versions are still read (not
 *    frozen, the statistics at 0)
 * 10: then the count of bonds that held in tension and broke (sinter_stepper_stats.bonds_broken,
 *    a series column: force/power_law.c); earlier versions are still read (the count at 0)
 * 11: the quasi-static section keyed by ids (issue 43, stepper/qs_state.c): its plane
 *    conditions and displacements per particle in order of ascending id, and its links found by
 *    their particles' ids, so that it fits the particles in any order; versions 3 to 10 are
 *    still read (their records follow the particles' indices and are reordered)
 * 12: then the periodic boundaries (stepper/periodic.c, ghosts/ghosts.h): a mask of the
 *    periodic axes, each one's cell (lo, hi), the count of ghost rows (the last rows of the
 *    particles above) and for each its owner (u32) and shift (3 doubles); earlier versions are
 *    still read (no axis periodic, no ghosts)
 * 13: then the continuous insertion (stepper/insertion.h): 1 and its state (7 u64: the next
 *    insertion, the spheres inserted, the crowded insertions, the random stream; 3 doubles: the
 *    next sphere's radius, the mass inserted and its target), or 0 without one; restored into
 *    the stepper's insertion, which the host sets before reading (a scene's [insert]); earlier
 *    versions are still read (the insertion as the host set it). An insertion of a mixture
 *    (issue 38) writes 2 instead of 1, and after the 3 doubles the count of its materials
 *    (u64, at most SINTER_MAX_MATERIALS), the pending sphere's material index (u64) and count
 *    + 1 doubles (each material's inserted mass, then their total, kg); files without a
 *    mixture are unchanged
 * 14: then the neighbour search's reach (f64, m: contact/neighbors.h, widened by a heat law's
 *    gas_reach, heat/gas_gap.h), so that the restored list is not built again at the first
 *    step (a fresh stepper's reach is 0, and a wider reach rebuilds the list: the rebuild
 *    history, and with it the times of later builds and the partition a build makes for
 *    threads, then differed from the uninterrupted run's, issue 40); earlier versions are
 *    still read (reach 0: the first step builds the list again where a heat law reaches
 *    further)
 * 15: the quasi-static section (stepper/qs_state.c) ends with the periodic cell of the
 *    quasi-static stepper (issue 38: its axes, corner, lengths now and at the start), and each
 *    link carries its image across the cell's faces; earlier versions are still read (no
 *    periodic cell, every image 0) */
#define CHECKPOINT_VERSION 15u
/* doubles per wall in the version 8 section */
#define WALL_STATE_DOUBLES 10u
static const char MAGIC[8] = {'S', 'I', 'N', 'T', 'E', 'R', 'C', 'K'};

/* ---- writing ---------------------------------------------------------- */

typedef struct writer {
    FILE *f;
    uint64_t hash;
    int failed;
} writer;

static void put(writer *w, const void *data, size_t bytes)
{
    w->hash = sinter_fnv1a(w->hash, data, bytes);
    if (bytes > 0 && fwrite(data, 1, bytes, w->f) != bytes)
        w->failed = 1;
}

static void put_u64(writer *w, uint64_t v)
{
    put(w, &v, sizeof(v));
}

static void put_f64(writer *w, double v)
{
    put(w, &v, sizeof(v));
}

static void put_pairs(writer *w, const sinter_pair_list *l)
{
    put_u64(w, l->count);
    put(w, l->i, l->count * sizeof(uint32_t));
    put(w, l->j, l->count * sizeof(uint32_t));
    put(w, l->key_i, l->count * sizeof(uint64_t));
    put(w, l->key_j, l->count * sizeof(uint64_t));
}

static void put_history(writer *w, const sinter_history *h, size_t pairs)
{
    put_u64(w, h->width);
    put(w, h->committed, h->width * pairs * sizeof(double));
    put_u64(w, h->active_count);
    put(w, h->active, h->active_count * sizeof(uint32_t));
}

sinter_status sinter_checkpoint_write(const sinter_stepper *st, const char *path)
{
    return sinter_checkpoint_write_with(st, path, NULL, 0);
}

sinter_status sinter_checkpoint_write_with(const sinter_stepper *st, const char *path,
                                           const void *host, size_t host_bytes)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    SINTER_CHECK_NULL(ctx, path);
    if (st->domain.on) /* (the ghosts are the host's: a portable checkpoint comes with migration) */
        return sinter_fail(ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_checkpoint_write: a stepper with domain operations "
                           "(sinter_stepper_set_domain_ops) writes a portable checkpoint: "
                           "sinter_stepper_save_global on one subdomain and "
                           "sinter_stepper_export (remove = 0) of every subdomain's owned "
                           "particles (include/sinter_domain.h)");
    if (st->kind != SINTER_STEPPER_QUASISTATIC && (!st->forces_current || !st->nb.built))
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "sinter_checkpoint_write: take at least one step (or step 0) before "
                           "writing a checkpoint");
    /* the pair lists and their reference positions are by index: particles added, removed or
     * reordered since the last build (a migration keeps the forces current: migrate.c) make
     * them another layout's, until the next step builds them again */
    if (st->kind != SINTER_STEPPER_QUASISTATIC &&
        st->nb.layout_generation != st->ps->layout_generation)
        return sinter_fail(ctx, SINTER_ERR_STATE,
                           "sinter_checkpoint_write: the particles were added, removed or "
                           "reordered since the last step; take a step before writing a "
                           "checkpoint (or write a portable one: sinter_stepper_save_global)");
    char tmp[SINTER_PATH_SIZE];
    const sinter_status named = sinter_path_format(ctx, tmp, sizeof(tmp), "%s.tmp", path);
    if (named != SINTER_OK)
        return named;
    writer w = {fopen(tmp, "wb"), SINTER_FNV1A_START, 0};
    if (w.f == NULL)
        return sinter_fail(ctx, SINTER_ERR_IO, "cannot write checkpoint '%s': %s", tmp,
                           strerror(errno));
    const sinter_particles *ps = st->ps;
    const size_t n = ps->count, nw = st->walls ? st->walls->count : 0;
    put(&w, MAGIC, sizeof(MAGIC));
    const uint32_t version = CHECKPOINT_VERSION, marker = 0x01020304u;
    put(&w, &version, sizeof(version));
    put(&w, &marker, sizeof(marker));
    /* stepper */
    put_f64(&w, st->time);
    put_f64(&w, st->dt);
    put_u64(&w, st->stats.steps);
    put_u64(&w, st->stats.rejected);
    put_u64(&w, st->stats.neighbor_builds);
    put_u64(&w, st->force_count);
    for (size_t k = 0; k < st->force_count; ++k) {
        char name[64] = {0};
        snprintf(name, sizeof(name), "%s", st->forces[k].model->name);
        put(&w, name, sizeof(name));
    }
    /* particles: every field, then the material table */
    put_u64(&w, n);
    put_u64(&w, ps->next_id);
    const sinter_field fields[] = {
        SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY,    SINTER_FIELD_SPIN,
        SINTER_FIELD_ROTATION, SINTER_FIELD_RADIUS,      SINTER_FIELD_MASS,
        SINTER_FIELD_INERTIA,  SINTER_FIELD_TEMPERATURE, SINTER_FIELD_CURRENT,
        SINTER_FIELD_FORCE,    SINTER_FIELD_TORQUE,      SINTER_FIELD_HEAT,
        SINTER_FIELD_MATERIAL, SINTER_FIELD_FLAGS,       SINTER_FIELD_ID};
    const void *arrays[] = {ps->x,      ps->v,       ps->w,           ps->rot,     ps->radius,
                            ps->mass,   ps->inertia, ps->temperature, ps->current, ps->force,
                            ps->torque, ps->heat,    ps->material,    ps->flags,   ps->id};
    for (size_t f = 0; f < sizeof(fields) / sizeof(fields[0]); ++f) {
        sinter_dtype dtype;
        size_t comps;
        sinter_field_info(fields[f], NULL, NULL, &dtype, &comps);
        const size_t elem = dtype == SINTER_DTYPE_DOUBLE || dtype == SINTER_DTYPE_UINT64 ? 8 : 4;
        put(&w, arrays[f], n * comps * elem);
    }
    put_u64(&w, SINTER_MAT_PARAM_COUNT_);
    put(&w, ps->material_used, sizeof(ps->material_used));
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        if (ps->material_used[m])
            put(&w, ps->materials[m].value, sizeof(ps->materials[m].value));
    /* walls: motion start, temperature and reaction (motions come from the set-up) */
    put_u64(&w, nw);
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *wall = &st->walls->wall[k];
        put_f64(&w, wall->motion_start);
        put_f64(&w, wall->temperature);
        put(&w, wall->force, sizeof(wall->force));
    }
    /* neighbour lists and history */
    put_f64(&w, st->nb.skin);
    put_pairs(&w, &st->nb.pp);
    put_pairs(&w, &st->nb.pw);
    put(&w, st->nb.x_ref, 3 * n * sizeof(double));
    for (size_t k = 0; k < nw; ++k) /* the first of each wall's 4 (version 8: the rest) */
        put_f64(&w, st->nb.wall_ref[4 * k]);
    for (size_t k = 0; k < st->force_count; ++k) {
        put_history(&w, &st->forces[k].pp, st->nb.pp.count);
        put_history(&w, &st->forces[k].pw, st->nb.pw.count);
    }
    /* quasi-static links and necks (version 3) */
    put_u64(&w, st->quasistatic != NULL);
    if (st->quasistatic != NULL) {
        const size_t bytes = sinter_qs_state_size(st->quasistatic);
        unsigned char *buf = sinter_calloc(ctx, bytes, 1);
        if (buf == NULL) {
            fclose(w.f);
            remove(tmp);
            return SINTER_ERR_NOMEM;
        }
        sinter_qs_state_save(st->quasistatic, buf);
        put_u64(&w, bytes);
        put(&w, buf, bytes);
        sinter_free(ctx, buf);
    }
    /* the electric network's warm start (version 4): node count (0: none), potentials */
    size_t warm_nodes = 0;
    const double *warm =
        st->electric != NULL ? sinter_electric_warm_potentials(st->electric, &warm_nodes) : NULL;
    put_u64(&w, warm_nodes);
    put(&w, warm, warm_nodes * sizeof(double));
    /* the partition's particle ranges (version 5), when made over the pair list written */
    const sinter_chunks *ch = &st->pp.chunks;
    const int keep = ch->count > 0 && ch->source == st->nb.pp.build_id;
    put_u64(&w, keep ? (uint64_t)ch->count : 0);
    for (int k = 0; keep && k <= ch->count; ++k)
        put_u64(&w, ch->plo[k]);
    /* the sort counter and the host's section (version 6) */
    put_u64(&w, st->steps_since_sort);
    put_u64(&w, (uint64_t)st->forces_current);
    put_u64(&w, host_bytes);
    put(&w, host, host_bytes);
    /* version 7: the iteration counts, and the staggered stepper's step controller and
     * predictor history (scheme 1; staggered.c), so that a restart continues bit for bit */
    const sinter_staggered *sg = &st->staggered;
    /* (its rows are the owned particles: with periodic images each of its three blocks is
     * written padded to n rows with zeros, and read back to the owned rows) */
    const size_t owned = n - ps->ghost_count;
    const int history = sg->history_valid && sg->history_count == owned && sg->hist != NULL;
    put_u64(&w, st->stats.iterations);
    put_u64(&w, st->stats.evaluations);
    put_f64(&w, sg->h_prev);
    put_f64(&w, sg->contraction);
    put_f64(&w, sg->control.x_prev);
    put_u64(&w, (uint64_t)sg->control.after_reject);
    put_u64(&w, (uint64_t)history);
    if (history && owned == n)
        put(&w, sg->hist, 7 * n * sizeof(double));
    else if (history)
        for (int b = 0; b < 3; ++b) { /* F, torques (3 per row), Q (1) */
            const size_t c = b < 2 ? 3 : 1;
            put(&w, sg->hist + 3 * owned * (size_t)b, c * owned * sizeof(double));
            for (size_t k = 0; k < c * (n - owned); ++k)
                put_f64(&w, 0.0);
        }
    /* the walls' kinds' state (version 8) */
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *wall = &st->walls->wall[k];
        const double v[WALL_STATE_DOUBLES] = {wall->moment[0],
                                              wall->moment[1],
                                              wall->moment[2],
                                              wall->servo_time,
                                              wall->servo_disp,
                                              wall->servo_v,
                                              wall->servo_int,
                                              st->nb.wall_ref[4 * k + 1],
                                              st->nb.wall_ref[4 * k + 2],
                                              st->nb.wall_ref[4 * k + 3]};
        put(&w, v, sizeof(v));
    }
    /* the frozen heat stage (version 9) */
    const sinter_frozen *fz = &st->frozen;
    put_u64(&w, (uint64_t)fz->active);
    put_f64(&w, fz->h);
    put_u64(&w, fz->mech_steps);
    put_f64(&w, fz->ke_last);
    put_f64(&w, fz->time);
    put_u64(&w, fz->steps);
    put_u64(&w, fz->rejected);
    put_u64(&w, fz->wakeups);
    put_u64(&w, fz->freezes);
    put_u64(&w, (uint64_t)(fz->active && fz->has_scale));
    if (fz->active) {
        put(&w, fz->rate, n * sizeof(double));
        if (fz->has_scale)
            put(&w, fz->scale0, n * sizeof(double));
    }
    put_u64(&w, st->stats.bonds_broken); /* version 10 */
    /* version 12: periodic axes and the ghost rows' owners and shifts */
    const sinter_ghosts *g = &st->ghosts;
    put_u64(&w, (uint64_t)(g->periodic[0] | g->periodic[1] << 1 | g->periodic[2] << 2));
    for (int d = 0; d < 3; ++d)
        if (g->periodic[d]) {
            put_f64(&w, g->lo[d]);
            put_f64(&w, g->hi[d]);
        }
    put_u64(&w, ps->ghost_count);
    if (ps->ghost_count > 0) {
        put(&w, g->owner, ps->ghost_count * sizeof(uint32_t));
        put(&w, g->shift, 3 * ps->ghost_count * sizeof(double));
    }
    const size_t mixed = st->insertion != NULL ? sinter_insertion_mixture_count(st->insertion) : 0;
    put_u64(&w, st->insertion == NULL ? 0u : mixed > 0 ? 2u : 1u); /* version 13 */
    if (st->insertion != NULL) {
        uint64_t u[SINTER_INSERTION_U64];
        double d[SINTER_INSERTION_F64];
        sinter_insertion_get_state(st->insertion, u, d);
        for (int k = 0; k < SINTER_INSERTION_U64; ++k)
            put_u64(&w, u[k]);
        for (int k = 0; k < SINTER_INSERTION_F64; ++k)
            put_f64(&w, d[k]);
    }
    if (mixed > 0) {
        uint64_t pending = 0;
        double mass[SINTER_MAX_MATERIALS + 1];
        sinter_insertion_get_mixture(st->insertion, &pending, mass);
        put_u64(&w, (uint64_t)mixed);
        put_u64(&w, pending);
        for (size_t k = 0; k <= mixed; ++k)
            put_f64(&w, mass[k]);
    }
    put_f64(&w, st->nb.reach); /* version 14 */
    const uint64_t sum = w.hash;
    put(&w, &sum, sizeof(sum));
    if (fclose(w.f) != 0)
        w.failed = 1;
    if (w.failed || rename(tmp, path) != 0) {
        remove(tmp);
        return sinter_fail(ctx, SINTER_ERR_IO, "cannot write checkpoint '%s': %s", path,
                           strerror(errno));
    }
    return SINTER_OK;
}

/* ---- reading ---------------------------------------------------------- */

typedef struct reader {
    const unsigned char *data;
    size_t size;
    size_t pos;
    int bad;
} reader;

static const void *take(reader *r, size_t bytes)
{
    if (r->bad || bytes > r->size - r->pos) {
        r->bad = 1;
        return NULL;
    }
    const void *p = r->data + r->pos;
    r->pos += bytes;
    return p;
}

static uint64_t take_u64(reader *r)
{
    uint64_t v = 0;
    const void *p = take(r, sizeof(v));
    if (p)
        memcpy(&v, p, sizeof(v));
    return v;
}

static double take_f64(reader *r)
{
    double v = 0;
    const void *p = take(r, sizeof(v));
    if (p)
        memcpy(&v, p, sizeof(v));
    return v;
}

/* Pointers into the file buffer for one pair list / history (copied on apply). */
typedef struct staged_pairs {
    size_t count;
    const void *i, *j, *key_i, *key_j;
} staged_pairs;

typedef struct staged_history {
    size_t width, active_count;
    const void *committed, *active;
} staged_history;

/* A pair list whose i are particles (< n) and j particles other than i (< n) or walls (< nw). */
static void take_pairs(reader *r, staged_pairs *p, size_t max_i, size_t max_j, int distinct)
{
    p->count = take_u64(r);
    if (p->count > r->size) {
        r->bad = 1;
        return;
    }
    p->i = take(r, p->count * sizeof(uint32_t));
    p->j = take(r, p->count * sizeof(uint32_t));
    p->key_i = take(r, p->count * sizeof(uint64_t));
    p->key_j = take(r, p->count * sizeof(uint64_t));
    if (r->bad)
        return;
    for (size_t k = 0; k < p->count; ++k) {
        uint32_t a, b;
        memcpy(&a, (const char *)p->i + 4 * k, 4);
        memcpy(&b, (const char *)p->j + 4 * k, 4);
        if (a >= max_i || b >= max_j || (distinct && a == b))
            r->bad = 1;
    }
}

static void take_history(reader *r, staged_history *h, size_t pairs, size_t expect_width)
{
    h->width = take_u64(r);
    if (h->width != expect_width) {
        r->bad = 1;
        return;
    }
    h->committed = take(r, h->width * pairs * sizeof(double));
    h->active_count = take_u64(r);
    if (h->active_count > pairs) {
        r->bad = 1;
        return;
    }
    h->active = take(r, h->active_count * sizeof(uint32_t));
    for (size_t k = 0; k < h->active_count && !r->bad; ++k) {
        uint32_t a;
        memcpy(&a, (const char *)h->active + 4 * k, 4);
        if (a >= pairs)
            r->bad = 1; /* history of a pair that is not in the list */
    }
}

static sinter_status copy_into(sinter_ctx *ctx, void **dst, size_t *cap, const void *src,
                               size_t count, size_t elem)
{
    if (count + 1 > *cap) {
        void *q = sinter_realloc_array(ctx, *dst, count + 1, elem);
        if (q == NULL)
            return sinter_last_status(ctx);
        *dst = q;
        *cap = count + 1;
    }
    if (count)
        memcpy(*dst, src, count * elem);
    return SINTER_OK;
}

static double f64_at(const void *base, size_t k)
{
    double v;
    memcpy(&v, (const char *)base + 8 * k, sizeof(v));
    return v;
}

/*
 * Values a well-formed file may still get wrong (a writer never produces them):
 * the rules of sinter_particles_validate and of the setters. NULL if all is well.
 */
static const char *check_values(double time, double dt, double skin, size_t n, uint64_t next_id,
                                const void *const field_data[15], const unsigned char *used,
                                const void *const material_values[SINTER_MAX_MATERIALS], size_t nw,
                                const void *wall_data, const void *x_ref)
{
    if (!isfinite(time) || !isfinite(dt) || !(dt > 0.0))
        return "its time or time step is not finite (or the step is not positive)";
    if (!isfinite(skin) || skin < 0.0)
        return "its neighbour skin is negative or not finite";
    for (size_t k = 0; k < 3 * n; ++k)
        for (int f = SINTER_FIELD_POSITION; f <= SINTER_FIELD_ROTATION; ++f)
            if (!isfinite(f64_at(field_data[f], k)) || !isfinite(f64_at(x_ref, k)))
                return "a particle position, velocity, spin or rotation is not finite";
    for (size_t i = 0; i < n; ++i) {
        for (int f = SINTER_FIELD_RADIUS; f <= SINTER_FIELD_TEMPERATURE; ++f) {
            const double v = f64_at(field_data[f], i);
            if (!isfinite(v) || !(v > 0.0))
                return "a particle radius, mass, inertia or temperature is not positive and "
                       "finite";
        }
        int32_t mat;
        uint64_t id;
        memcpy(&mat, (const char *)field_data[SINTER_FIELD_MATERIAL] + 4 * i, 4);
        memcpy(&id, (const char *)field_data[SINTER_FIELD_ID] + 8 * i, 8);
        if (mat < 0 || mat >= SINTER_MAX_MATERIALS || !used[mat])
            return "a particle has a material that is not registered";
        if (id >= next_id)
            return "a particle id is not below the next id";
    }
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        for (int p = 0; used[m] && p < SINTER_MAT_PARAM_COUNT_; ++p)
            if (!sinter_material_value_valid((sinter_material_param)p,
                                             f64_at(material_values[m], (size_t)p)))
                return "a material parameter is outside its valid range";
    for (size_t k = 0; k < nw; ++k) {
        const double start = f64_at(wall_data, 5 * k), temperature = f64_at(wall_data, 5 * k + 1);
        if (isnan(start) || start == -HUGE_VAL || !isfinite(temperature) || !(temperature > 0.0))
            return "a wall's motion start or temperature is invalid";
    }
    return NULL;
}

static sinter_status load_file(sinter_ctx *ctx, const char *path, unsigned char **data,
                               size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return sinter_fail(ctx, SINTER_ERR_IO, "cannot open checkpoint '%s': %s", path,
                           strerror(errno));
    sinter_status st = SINTER_OK;
    long len = -1;
    struct stat info;
    if (fstat(fileno(f), &info) != 0)
        st = sinter_fail(ctx, SINTER_ERR_IO, "cannot read checkpoint '%s': %s", path,
                         strerror(errno));
    else if (!S_ISREG(info.st_mode))
        st = sinter_fail(ctx, SINTER_ERR_INVALID,
                         "checkpoint '%s' is refused: it is %s, not a file written by a run "
                         "(give the checkpoint file itself, e.g. OUT/checkpoint.bin)",
                         path, S_ISDIR(info.st_mode) ? "a directory" : "not a regular file");
    else if (info.st_size == 0)
        st = sinter_fail(ctx, SINTER_ERR_CORRUPT, "checkpoint '%s' is refused: the file is empty",
                         path);
    if (st == SINTER_OK && fseek(f, 0, SEEK_END) == 0)
        len = ftell(f);
    if (st == SINTER_OK && (len < 0 || fseek(f, 0, SEEK_SET) != 0))
        st = sinter_fail(ctx, SINTER_ERR_IO, "cannot read checkpoint '%s'", path);
    unsigned char *buf = NULL;
    if (st == SINTER_OK) {
        buf = sinter_alloc(ctx, (size_t)len + 1);
        if (buf == NULL)
            st = SINTER_ERR_NOMEM;
        else if (len > 0 && fread(buf, 1, (size_t)len, f) != (size_t)len)
            st = sinter_fail(ctx, SINTER_ERR_IO, "cannot read checkpoint '%s'", path);
    }
    fclose(f);
    if (st != SINTER_OK) {
        sinter_free(ctx, buf);
        return st;
    }
    *data = buf;
    *size = (size_t)len;
    return SINTER_OK;
}

static sinter_status corrupt(sinter_ctx *ctx, const char *path, const char *why)
{
    return sinter_fail(ctx, SINTER_ERR_CORRUPT,
                       "checkpoint '%s' is refused: %s; nothing was changed", path, why);
}

sinter_status sinter_checkpoint_read(sinter_stepper *st, const char *path)
{
    return sinter_checkpoint_read_with(st, path, NULL, NULL);
}

sinter_status sinter_checkpoint_read_with(sinter_stepper *st, const char *path,
                                          sinter_checkpoint_host_fn host_check, void *user)
{
    if (st == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = st->ctx;
    SINTER_CHECK_NULL(ctx, path);
    sinter_particles *ps = st->ps;
    if (ps->views_out > 0)
        return sinter_fail(ctx, SINTER_ERR_BUSY,
                           "sinter_checkpoint_read: release the particle views first");
    unsigned char *data = NULL;
    size_t size = 0;
    sinter_status s = load_file(ctx, path, &data, &size);
    if (s != SINTER_OK)
        return s;
    /* checksum over everything before the last 8 bytes */
    if (size < sizeof(MAGIC) + 16 || memcmp(data, MAGIC, sizeof(MAGIC)) != 0) {
        sinter_free(ctx, data);
        return corrupt(ctx, path, "it is not a libsinter checkpoint (bad magic or too short)");
    }
    const uint64_t h = sinter_fnv1a(SINTER_FNV1A_START, data, size - 8);
    uint64_t stored = 0;
    memcpy(&stored, data + size - 8, 8);
    if (h != stored) {
        sinter_free(ctx, data);
        return corrupt(ctx, path, "the checksum does not match (truncated or corrupted file)");
    }
    reader r = {data, size - 8, sizeof(MAGIC), 0};
    uint32_t version = 0, marker = 0;
    memcpy(&version, take(&r, 4), 4);
    memcpy(&marker, take(&r, 4), 4);
    if (version < 2u || version > CHECKPOINT_VERSION || marker != 0x01020304u) {
        sinter_free(ctx, data);
        return corrupt(ctx, path,
                       "unsupported format version (this library reads versions 2 "
                       "to 14) or byte order");
    }
    const double time = take_f64(&r), dt = take_f64(&r);
    const uint64_t steps = take_u64(&r), rejected = take_u64(&r), builds = take_u64(&r);
    const uint64_t nforces = take_u64(&r);
    s = SINTER_OK;
    if (!r.bad && nforces != st->force_count)
        s = sinter_fail(ctx, SINTER_ERR_INVALID,
                        "checkpoint '%s' has %llu force models, the stepper %zu; nothing was "
                        "changed",
                        path, (unsigned long long)nforces, st->force_count);
    for (size_t k = 0; k < nforces && s == SINTER_OK && !r.bad; ++k) {
        const char *name = take(&r, 64);
        if (name && strncmp(name, st->forces[k].model->name, 64) != 0)
            s = sinter_fail(ctx, SINTER_ERR_INVALID,
                            "checkpoint '%s': force model %zu is '%.63s', the stepper's is '%s'; "
                            "nothing was changed",
                            path, k, name, st->forces[k].model->name);
    }
    const size_t n = (size_t)take_u64(&r);
    const uint64_t next_id = take_u64(&r);
    if (n > size)
        r.bad = 1;
    const void *field_data[15];
    size_t field_bytes[15];
    for (int f = 0; f < 15 && !r.bad; ++f) {
        sinter_dtype dtype;
        size_t comps;
        sinter_field_info((sinter_field)f, NULL, NULL, &dtype, &comps);
        const size_t elem = dtype == SINTER_DTYPE_DOUBLE || dtype == SINTER_DTYPE_UINT64 ? 8 : 4;
        field_bytes[f] = n * comps * elem;
        field_data[f] = take(&r, field_bytes[f]);
    }
    const uint64_t param_count = take_u64(&r);
    /* a file from before parameters were appended (53 since the neck data): the appended ones
     * take their defaults */
    const int older = param_count >= 53 && param_count < SINTER_MAT_PARAM_COUNT_;
    if (s == SINTER_OK && !r.bad && param_count != SINTER_MAT_PARAM_COUNT_ && !older)
        s = sinter_fail(ctx, SINTER_ERR_INVALID,
                        "checkpoint '%s' stores %llu material parameters, this library %d; "
                        "nothing was changed",
                        path, (unsigned long long)param_count, SINTER_MAT_PARAM_COUNT_);
    const unsigned char *used = take(&r, SINTER_MAX_MATERIALS);
    const void *material_values[SINTER_MAX_MATERIALS] = {0};
    double *padded = NULL; /* an older file's values with the appended parameters' defaults */
    for (int m = 0; m < SINTER_MAX_MATERIALS && used && !r.bad && s == SINTER_OK; ++m) {
        if (!used[m])
            continue;
        if (!older) {
            material_values[m] = take(&r, sizeof(ps->materials[m].value));
            continue;
        }
        const void *old_values = take(&r, (size_t)param_count * sizeof(double));
        if (padded == NULL)
            padded = sinter_calloc(ctx, (size_t)SINTER_MAX_MATERIALS * SINTER_MAT_PARAM_COUNT_,
                                   sizeof(double));
        if (padded == NULL) {
            s = sinter_last_status(ctx);
            break;
        }
        double *v = padded + (size_t)m * SINTER_MAT_PARAM_COUNT_;
        sinter_material_defaults(v);
        if (old_values != NULL)
            memcpy(v, old_values, (size_t)param_count * sizeof(double));
        material_values[m] = v;
    }
    const size_t nw = (size_t)take_u64(&r);
    const size_t have_walls = st->walls ? st->walls->count : 0;
    if (s == SINTER_OK && !r.bad && nw != have_walls)
        s = sinter_fail(ctx, SINTER_ERR_INVALID,
                        "checkpoint '%s' has %zu walls, the stepper %zu; nothing was changed", path,
                        nw, have_walls);
    const void *wall_data = take(&r, nw * 5 * sizeof(double));
    const double skin = take_f64(&r);
    staged_pairs pp = {0, NULL, NULL, NULL, NULL}, pw = {0, NULL, NULL, NULL, NULL};
    take_pairs(&r, &pp, n, n, 1);
    take_pairs(&r, &pw, n, nw, 0);
    const void *x_ref = take(&r, 3 * n * sizeof(double));
    const void *wall_ref = take(&r, nw * sizeof(double));
    staged_history hist[2 * 16];
    if (nforces > 16)
        r.bad = 1;
    for (size_t k = 0; k < nforces && !r.bad && s == SINTER_OK; ++k) {
        take_history(&r, &hist[2 * k], pp.count, st->forces[k].pp.width);
        take_history(&r, &hist[2 * k + 1], pw.count, st->forces[k].pw.width);
    }
    const uint64_t has_qs = version >= 3u ? take_u64(&r) : 0;
    const uint64_t qs_bytes = has_qs == 1 ? take_u64(&r) : 0;
    const unsigned char *qs_data = qs_bytes <= size ? take(&r, (size_t)qs_bytes) : NULL;
    if (has_qs > 1 || (has_qs && qs_data == NULL))
        r.bad = 1;
    const uint64_t warm_nodes = version >= 4u ? take_u64(&r) : 0;
    const void *warm = NULL; /* nodes doubles, unaligned in the file */
    if (warm_nodes > 0 && !r.bad) {
        if (warm_nodes != (uint64_t)n + nw) /* particles then walls */
            r.bad = 1;
        else
            warm = take(&r, (size_t)warm_nodes * sizeof(double));
    }
    const uint64_t ranges = version >= 5u ? take_u64(&r) : 0;
    size_t plo[SINTER_CHUNKS_MAX + 1];
    if (ranges > SINTER_CHUNKS_MAX || ranges == 1)
        r.bad = 1;
    for (uint64_t k = 0; k <= ranges && ranges > 0 && !r.bad; ++k) {
        const uint64_t v = take_u64(&r);
        /* ascending from 0 to the particle count */
        if (v > n || (k == 0 && v != 0) || (k == ranges && v != n) || (k > 0 && v < plo[k - 1]))
            r.bad = 1;
        else
            plo[k] = (size_t)v;
    }
    const uint64_t since_sort = version >= 6u ? take_u64(&r) : st->steps_since_sort;
    const uint64_t forces_current = version >= 6u ? take_u64(&r) : 1;
    if (forces_current > 1)
        r.bad = 1;
    /* the frozen heat stage (version 7): staged, applied below */
    const uint64_t host_bytes = version >= 6u ? take_u64(&r) : 0;
    const void *host = host_bytes <= size ? take(&r, (size_t)host_bytes) : NULL;
    if (host_bytes > 0 && host == NULL)
        r.bad = 1;
    const int v7 = version >= 7u;
    const uint64_t iterations = v7 ? take_u64(&r) : st->stats.iterations;
    const uint64_t evaluations = v7 ? take_u64(&r) : st->stats.evaluations;
    const double h_prev = v7 ? take_f64(&r) : 0.0, contraction = v7 ? take_f64(&r) : 0.0;
    const double x_prev = v7 ? take_f64(&r) : 0.0;
    const uint64_t after_reject = v7 ? take_u64(&r) : 0, history = v7 ? take_u64(&r) : 0;
    if (after_reject > 1 || history > 1 || !(x_prev >= 0.0) || !(h_prev >= 0.0))
        r.bad = 1;
    const void *hist_data =
        history && n <= size / 56 ? take(&r, 7 * (size_t)n * sizeof(double)) : NULL;
    if (history && hist_data == NULL)
        r.bad = 1;
    const void *wall_state =
        version >= 8u ? take(&r, nw * WALL_STATE_DOUBLES * sizeof(double)) : NULL;
    uint64_t fz_active = 0, fz_mech = 0, fz_steps = 0, fz_rejected = 0, fz_wakeups = 0,
             fz_freezes = 0, fz_scaled = 0;
    double fz_h = 0.0, fz_time = 0.0, fz_ke = INFINITY;
    const void *fz_rate = NULL, *fz_scale = NULL; /* n doubles each, unaligned in the file */
    if (version >= 9u) {
        fz_active = take_u64(&r);
        fz_h = take_f64(&r);
        fz_mech = take_u64(&r);
        fz_ke = take_f64(&r);
        fz_time = take_f64(&r);
        fz_steps = take_u64(&r);
        fz_rejected = take_u64(&r);
        fz_wakeups = take_u64(&r);
        fz_freezes = take_u64(&r);
        fz_scaled = take_u64(&r);
        if (fz_active > 1 || fz_scaled > fz_active || !(fz_h >= 0.0) || !isfinite(fz_h))
            r.bad = 1;
        if (fz_active && !r.bad)
            fz_rate = take(&r, n * sizeof(double));
        if (fz_scaled && !r.bad)
            fz_scale = take(&r, n * sizeof(double));
    }
    const uint64_t bonds_broken = version >= 10u && !r.bad ? take_u64(&r) : 0;
    /* version 12: periodic axes and ghosts */
    const uint64_t periodic_mask = version >= 12u && !r.bad ? take_u64(&r) : 0;
    double cell[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    for (int d = 0; d < 3 && !r.bad; ++d)
        if (periodic_mask & (1u << d)) {
            cell[d][0] = take_f64(&r);
            cell[d][1] = take_f64(&r);
            if (!(isfinite(cell[d][0]) && isfinite(cell[d][1]) && cell[d][1] > cell[d][0]))
                r.bad = 1;
        }
    const uint64_t ghost_count = version >= 12u && !r.bad ? take_u64(&r) : 0;
    if (periodic_mask > 7u || ghost_count > n || (ghost_count > 0 && periodic_mask == 0))
        r.bad = 1;
    const uint32_t *ghost_owner = NULL;
    const void *ghost_shift = NULL;
    if (ghost_count > 0 && !r.bad) {
        ghost_owner = take(&r, (size_t)ghost_count * sizeof(uint32_t));
        ghost_shift = take(&r, 3 * (size_t)ghost_count * sizeof(double));
        for (uint64_t k = 0; k < ghost_count && ghost_owner != NULL; ++k) {
            uint32_t o;
            memcpy(&o, (const char *)ghost_owner + 4 * k, 4);
            if ((uint64_t)o >= n - ghost_count)
                r.bad = 1;
        }
    }
    const uint64_t has_insertion = version >= 13u && !r.bad ? take_u64(&r) : 0;
    uint64_t ins_u[SINTER_INSERTION_U64] = {0};
    double ins_d[SINTER_INSERTION_F64] = {0};
    if (has_insertion > 2)
        r.bad = 1;
    for (int k = 0; k < SINTER_INSERTION_U64 && has_insertion && !r.bad; ++k)
        ins_u[k] = take_u64(&r);
    for (int k = 0; k < SINTER_INSERTION_F64 && has_insertion && !r.bad; ++k)
        ins_d[k] = take_f64(&r);
    if (has_insertion && !r.bad && !sinter_insertion_state_valid(ins_d))
        r.bad = 1;
    /* a mixture's state (has_insertion 2) */
    const uint64_t mixed = has_insertion == 2 && !r.bad ? take_u64(&r) : 0;
    const uint64_t mix_pending = mixed > 0 && !r.bad ? take_u64(&r) : 0;
    double mix_mass[SINTER_MAX_MATERIALS + 1] = {0};
    if (has_insertion == 2 && (mixed == 0 || mixed > SINTER_MAX_MATERIALS || mix_pending >= mixed))
        r.bad = 1;
    for (uint64_t k = 0; mixed > 0 && k <= mixed && !r.bad; ++k) {
        mix_mass[k] = take_f64(&r);
        if (!(isfinite(mix_mass[k]) && mix_mass[k] >= 0.0))
            r.bad = 1;
    }
    const double reach = version >= 14u && !r.bad ? take_f64(&r) : 0.0;
    if (!(isfinite(reach) && reach >= 0.0))
        r.bad = 1;
    if (s == SINTER_OK && (r.bad || r.pos != r.size))
        s = corrupt(ctx, path, "its sections do not fit its size");
    if (s == SINTER_OK && has_insertion && st->insertion != NULL &&
        (uint64_t)sinter_insertion_mixture_count(st->insertion) != mixed)
        s = sinter_fail(ctx, SINTER_ERR_INVALID,
                        "checkpoint '%s' holds an insertion of a mixture of %llu materials, but "
                        "the stepper's insertion mixes %zu (0: none); set the same insertion "
                        "before reading; nothing was changed",
                        path, (unsigned long long)mixed,
                        sinter_insertion_mixture_count(st->insertion));
    if (s == SINTER_OK && has_qs && st->kind != SINTER_STEPPER_QUASISTATIC)
        s = sinter_fail(ctx, SINTER_ERR_INVALID,
                        "checkpoint '%s' holds quasi-static links and necks, but the stepper is "
                        "not of the quasi-static kind; nothing was changed",
                        path);
    if (s == SINTER_OK) {
        const char *why = check_values(time, dt, skin, n, next_id, field_data, used,
                                       material_values, nw, wall_data, x_ref);
        if (why != NULL)
            s = corrupt(ctx, path, why);
    }
    /* The host's section (a scene's program): checked, and staged by the host, before
     * anything changes. */
    if (s == SINTER_OK && host_check != NULL) {
        const sinter_checkpoint_facts facts = {time, dt, n, nw, version};
        s = host_check(user, host_bytes > 0 ? host : NULL, (size_t)host_bytes, &facts);
    }
    /* The quasi-static state, built whole before anything changes. */
    sinter_qs *qs_new = NULL;
    if (s == SINTER_OK && has_qs) {
        const char *why = NULL;
        s = sinter_qs_state_restore(&qs_new, ctx, &st->quasistatic_options, qs_data,
                                    (size_t)qs_bytes, n, field_data[SINTER_FIELD_ID], version < 11u,
                                    version >= 15u, &why);
        if (s == SINTER_ERR_CORRUPT)
            s = corrupt(ctx, path, why);
    }
    /* Apply: grow everything first so that nothing can fail half-way. */
    if (s == SINTER_OK)
        s = sinter_particles_reserve(ps, n);
    if (s == SINTER_OK)
        s = sinter_ghosts_reserve(ctx, &st->ghosts, (size_t)ghost_count);
    sinter_staggered *sg = &st->staggered;
    if (s == SINTER_OK && history && 7 * n + 1 > sg->hist_capacity) {
        double *q = sinter_realloc_array(ctx, sg->hist, 7 * n + 1, sizeof(double));
        if (q == NULL)
            s = sinter_last_status(ctx);
        else {
            sg->hist = q;
            sg->hist_capacity = 7 * n + 1;
        }
    }
    sinter_neighbors *nb = &st->nb;
    sinter_pair_list *lists[2] = {&nb->pp, &nb->pw};
    const staged_pairs *staged[2] = {&pp, &pw};
    for (int l = 0; l < 2 && s == SINTER_OK; ++l) {
        sinter_pair_list *L = lists[l];
        size_t cap = L->capacity;
        /* the pair list's arrays share one capacity: grow them together */
        if (staged[l]->count + 1 > cap) {
            void **slots[5] = {(void **)&L->i, (void **)&L->j, (void **)&L->key_i,
                               (void **)&L->key_j, (void **)&L->from};
            const size_t elem[5] = {4, 4, 8, 8, 4};
            for (int a = 0; a < 5 && s == SINTER_OK; ++a) {
                void *q = sinter_realloc_array(ctx, *slots[a], staged[l]->count + 1, elem[a]);
                if (q == NULL)
                    s = sinter_last_status(ctx);
                else
                    *slots[a] = q;
            }
            if (s == SINTER_OK)
                L->capacity = staged[l]->count + 1;
        }
    }
    size_t ref_cap = nb->ref_capacity, wref_cap = nb->wall_ref_capacity;
    if (s == SINTER_OK)
        s = copy_into(ctx, (void **)&nb->x_ref, &ref_cap, NULL, 0, 3 * sizeof(double));
    if (s == SINTER_OK && 3 * n + 3 > nb->ref_capacity) {
        void *q = sinter_realloc_array(ctx, nb->x_ref, 3 * n + 3, sizeof(double));
        if (q == NULL)
            s = sinter_last_status(ctx);
        else
            nb->x_ref = q, nb->ref_capacity = 3 * n + 3;
    }
    if (s == SINTER_OK && 4 * nw + 4 > nb->wall_ref_capacity) {
        void *q = sinter_realloc_array(ctx, nb->wall_ref, 4 * nw + 4, sizeof(double));
        if (q == NULL)
            s = sinter_last_status(ctx);
        else
            nb->wall_ref = q, nb->wall_ref_capacity = 4 * nw + 4;
    }
    (void)wref_cap;
    for (size_t k = 0; k < nforces && s == SINTER_OK; ++k) {
        sinter_history *hs[2] = {&st->forces[k].pp, &st->forces[k].pw};
        const size_t pairs[2] = {pp.count, pw.count};
        for (int l = 0; l < 2 && s == SINTER_OK; ++l) {
            const staged_history *sh = &hist[2 * k + (size_t)l];
            if (hs[l]->width == 0)
                continue;
            s = copy_into(ctx, (void **)&hs[l]->committed, &hs[l]->pair_capacity, NULL, 0, 8);
            if (s == SINTER_OK && sh->width * pairs[l] + 1 > hs[l]->pair_capacity) {
                void *q = sinter_realloc_array(ctx, hs[l]->committed, sh->width * pairs[l] + 1, 8);
                if (q == NULL)
                    s = sinter_last_status(ctx);
                else
                    hs[l]->committed = q, hs[l]->pair_capacity = sh->width * pairs[l] + 1;
            }
            if (s == SINTER_OK && sh->active_count + 1 > hs[l]->active_capacity) {
                void *q = sinter_realloc_array(ctx, hs[l]->active, sh->active_count + 1, 4);
                if (q == NULL)
                    s = sinter_last_status(ctx);
                else
                    hs[l]->active = q, hs[l]->active_capacity = sh->active_count + 1;
            }
        }
    }
    /* the electric model's warm start: the checkpoint's, or none (the last step that can fail;
     * it touches nothing but the model's starting potentials) */
    sinter_frozen *fz = &st->frozen;
    if (s == SINTER_OK && fz_active && n + 1 > fz->capacity) {
        double *q[2] = {sinter_realloc_array(ctx, fz->rate, n + 1, sizeof(double)), NULL};
        if (q[0] != NULL)
            fz->rate = q[0];
        q[1] = q[0] != NULL ? sinter_realloc_array(ctx, fz->scale0, n + 1, sizeof(double)) : NULL;
        if (q[1] != NULL) {
            fz->scale0 = q[1];
            fz->capacity = n + 1;
        } else {
            s = sinter_last_status(ctx);
        }
    }
    if (s == SINTER_OK && st->electric != NULL)
        s = sinter_electric_set_warm_potentials(st->electric, warm,
                                                warm != NULL ? (size_t)warm_nodes : 0);
    if (s != SINTER_OK) {
        sinter_qs_destroy(qs_new);
        sinter_free(ctx, padded);
        sinter_free(ctx, data);
        return s;
    }
    /* Nothing can fail from here on. */
    if (st->kind == SINTER_STEPPER_QUASISTATIC) {
        sinter_qs_destroy(st->quasistatic);
        st->quasistatic = qs_new; /* NULL: links are detected afresh at the next step; the
                                     links name particles by the checkpoint's order */
    }
    void *targets[15] = {ps->x,      ps->v,       ps->w,           ps->rot,     ps->radius,
                         ps->mass,   ps->inertia, ps->temperature, ps->current, ps->force,
                         ps->torque, ps->heat,    ps->material,    ps->flags,   ps->id};
    for (int f = 0; f < 15; ++f)
        memcpy(targets[f], field_data[f], field_bytes[f]);
    ps->count = n;
    ps->next_id = next_id;
    ps->material_top = 0;
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m) {
        ps->material_used[m] = used[m];
        if (used[m]) {
            ps->material_top = m + 1;
            memcpy(ps->materials[m].value, material_values[m], sizeof(ps->materials[m].value));
            ps->materials[m].ctx = ctx;
            /* the set's property tables stay (materials' data); the enthalpy follows the
             * restored heat capacity and latent heat (the same values: the same bits) */
            if (sinter_particles_props_update(ps, m) != SINTER_OK)
                sinter_clear_error(ctx);
        }
    }
    ps->ghost_count = (size_t)ghost_count;
    ps->layout_generation++;
    ps->population_generation++;
    {
        sinter_ghosts *g = &st->ghosts;
        for (int d = 0; d < 3; ++d) {
            g->periodic[d] = (periodic_mask >> d) & 1u;
            g->lo[d] = cell[d][0];
            g->hi[d] = cell[d][1];
        }
        g->count = (size_t)ghost_count;
        if (ghost_count > 0) {
            memcpy(g->owner, ghost_owner, (size_t)ghost_count * sizeof(uint32_t));
            memcpy(g->shift, ghost_shift, 3 * (size_t)ghost_count * sizeof(double));
        }
        g->layout = ps->layout_generation;
        g->built = periodic_mask != 0;
    }
    for (size_t k = 0; k < nw; ++k) {
        sinter_wall *wall = &st->walls->wall[k];
        double v[5];
        memcpy(v, (const char *)wall_data + 40 * k, sizeof(v));
        wall->motion_start = v[0];
        wall->temperature = v[1];
        memcpy(wall->force, v + 2, 3 * sizeof(double));
        double u[WALL_STATE_DOUBLES] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
        if (wall_state != NULL)
            memcpy(u, (const char *)wall_state + sizeof(u) * k, sizeof(u));
        memcpy(wall->moment, u, 3 * sizeof(double));
        if (wall_state != NULL) {
            wall->servo_time = u[3];
            wall->servo_disp = u[4];
            wall->servo_v = u[5];
            wall->servo_int = u[6];
        }
        memcpy(nb->wall_ref + 4 * k + 1, u + 7, 3 * sizeof(double));
    }
    if (st->walls)
        sinter_walls_move(st->walls, time); /* motions come from the set-up: no callback error here
                                               unless the host's callback fails */
    for (int l = 0; l < 2; ++l) {
        sinter_pair_list *L = lists[l];
        L->count = staged[l]->count;
        memcpy(L->i, staged[l]->i, L->count * 4);
        memcpy(L->j, staged[l]->j, L->count * 4);
        memcpy(L->key_i, staged[l]->key_i, L->count * 8);
        memcpy(L->key_j, staged[l]->key_j, L->count * 8);
        L->build_id = sinter_unique_id();
        L->canonical = nb->canonical; /* (written in the order of the mode it was made in) */
    }
    nb->old_pp.count = nb->old_pw.count = 0;
    /* the partition over the restored pairs: kept by the next search (contact/chunks.h) */
    st->pp.chunks.count = (int)ranges;
    st->pp.chunks.source = ranges > 0 ? nb->pp.build_id : 0;
    for (uint64_t k = 0; k <= ranges && ranges > 0; ++k)
        st->pp.chunks.plo[k] = plo[k];
    memcpy(nb->x_ref, x_ref, 3 * n * sizeof(double));
    for (size_t k = 0; k < nw; ++k)
        memcpy(nb->wall_ref + 4 * k, (const char *)wall_ref + sizeof(double) * k, sizeof(double));
    nb->skin = skin;
    nb->reach = reach;
    nb->built = 1;
    nb->wall_count = nw;
    nb->layout_generation = ps->layout_generation;
    st->skin_set = 1;
    for (size_t k = 0; k < nforces; ++k) {
        sinter_history *hs[2] = {&st->forces[k].pp, &st->forces[k].pw};
        const size_t pairs[2] = {pp.count, pw.count};
        for (int l = 0; l < 2; ++l) {
            const staged_history *sh = &hist[2 * k + (size_t)l];
            if (hs[l]->width == 0)
                continue;
            memcpy(hs[l]->committed, sh->committed, sh->width * pairs[l] * sizeof(double));
            memcpy(hs[l]->active, sh->active, sh->active_count * sizeof(uint32_t));
            hs[l]->active_count = sh->active_count;
            sinter_history_forget(hs[l]);
        }
    }
    st->time = time;
    st->dt = dt;
    st->stats.dt = dt;
    st->steps_since_sort = since_sort;
    st->stats.steps = steps;
    st->stats.rejected = rejected;
    st->stats.neighbor_builds = builds;
    st->stats.iterations = iterations;
    st->stats.evaluations = evaluations;
    st->stats.bonds_broken = bonds_broken;
    if (has_insertion && st->insertion != NULL) { /* a host without one ignores it */
        sinter_insertion_set_state(st->insertion, ins_u, ins_d);
        if (mixed > 0) /* checked above: it fits */
            (void)sinter_insertion_set_mixture(st->insertion, mix_pending, mix_mass);
    }
    sg->h_prev = h_prev;
    sg->contraction = contraction;
    sg->control.x_prev = x_prev;
    sg->control.after_reject = (int)after_reject;
    sg->history_valid = (int)history;
    sg->history_count = (size_t)(n - ghost_count); /* the owned rows (see the writer) */
    for (int b = 0; history && b < 3; ++b) {
        const size_t c = b < 2 ? 3 : 1, o = (size_t)(n - ghost_count);
        memcpy(sg->hist + 3 * o * (size_t)b,
               (const char *)hist_data + 3 * (size_t)n * 8 * (size_t)b, c * o * sizeof(double));
    }
    st->forces_current = (int)forces_current || st->kind != SINTER_STEPPER_QUASISTATIC;
    fz->active = (int)fz_active;
    fz->h = fz_h;
    fz->mech_steps = fz_mech;
    fz->ke_last = fz_ke;
    fz->time = fz_time;
    fz->steps = fz_steps;
    fz->rejected = fz_rejected;
    fz->wakeups = fz_wakeups;
    fz->freezes = fz_freezes;
    fz->has_scale = (int)fz_scaled;
    if (fz_rate != NULL)
        memcpy(fz->rate, fz_rate, n * sizeof(double));
    if (fz_scale != NULL)
        memcpy(fz->scale0, fz_scale, n * sizeof(double));
    st->write_generation = ps->write_generation;
    st->population_generation = ps->population_generation;
    sinter_free(ctx, padded);
    sinter_free(ctx, data);
    return SINTER_OK;
}
