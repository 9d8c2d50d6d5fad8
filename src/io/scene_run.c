#define _POSIX_C_SOURCE 200809L
/*
 * Running a scene: an optional pour to rest and an optional triaxial compaction, then the
 * run to the end time, with global observables recorded every output interval into a series
 * (CSV and SVG), VTU frames with a PVD collection, and checkpoints.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "io/scene.h"
#include "io/vtu.h"

static const double PI = 3.14159265358979323846;

enum {
    COL_TIME,
    COL_KE,
    COL_CONTACTS,
    COL_COORDINATION,
    COL_BED_TOP,
    COL_FRACTION,
    COL_T_MEAN,
    COL_T_MAX,
    COL_FIXED_ /* wall force columns follow */
};

/* Create `path` and any missing parents (like mkdir -p). */
static sinter_status make_dir(sinter_ctx *ctx, const char *path)
{
    char partial[4096];
    const size_t len = strlen(path);
    if (len == 0 || len >= sizeof(partial))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "output directory '%.200s' is empty or too long", path);
    memcpy(partial, path, len + 1);
    for (size_t k = 1; k <= len; ++k) {
        if (partial[k] != '/' && partial[k] != '\0')
            continue;
        const char keep = partial[k];
        partial[k] = '\0';
        if (mkdir(partial, 0777) != 0 && errno != EEXIST)
            return sinter_fail(ctx, SINTER_ERR_IO, "cannot create directory '%s': %s", partial,
                               strerror(errno));
        partial[k] = keep;
    }
    return SINTER_OK;
}

/*
 * Volume fraction of the solid inside the box the walls enclose (seed 000
 * sec. 7, remark 1: "within the lowest compression point"): each axis is
 * bounded by axis-aligned walls facing each other, or by the particles'
 * extent where there is no wall; the top is the lower of the top wall and the
 * top of the bed.
 */
/* Volume of the spheres and their bounding box [m^3, m]. */
static double spheres_box(const sinter_particles *ps, double lo[3], double hi[3])
{
    double solid = 0.0;
    for (int d = 0; d < 3; ++d) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (size_t i = 0; i < ps->count; ++i) {
        const double r = ps->radius[i];
        solid += 4.0 / 3.0 * PI * r * r * r;
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], ps->x[3 * i + d] - r);
            hi[d] = fmax(hi[d], ps->x[3 * i + d] + r);
        }
    }
    return solid;
}

static double volume_fraction(const sinter_scene *sc, double bed_top)
{
    double lo[3], hi[3];
    const double solid = spheres_box(sc->ps, lo, hi);
    hi[2] = bed_top;
    for (size_t k = 0; k < sc->walls->count; ++k) {
        const sinter_wall *w = &sc->walls->wall[k];
        for (int d = 0; d < 3; ++d) {
            if (fabs(w->n[d]) < 1.0 - 1e-12)
                continue;
            if (w->n[d] > 0) /* a lower bound, facing +axis */
                lo[d] = fmax(lo[d] == INFINITY ? w->p[d] : lo[d], w->p[d]);
            else
                hi[d] = fmin(hi[d], w->p[d]);
        }
    }
    const double volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    return volume > 0 ? solid / volume : NAN;
}

/* Columns after the wall forces for the quasi-static stepper (seed 001 sec. 4). */
enum { SINTERING_COLUMNS = 9 };
static const char *const SINTERING_NAMES[SINTERING_COLUMNS] = {
    "links",       "neck radius mean", "neck radius min", "neck radius max", "neck ratio mean",
    "shrinkage x", "shrinkage y",      "shrinkage z",     "relative density"};
static const char *const SINTERING_UNITS[SINTERING_COLUMNS] = {"1", "m", "m", "m", "1",
                                                               "1", "1", "1", "1"};

/* Columns after those: the particle currents, when the scene has an electric model. */
enum { ELECTRIC_COLUMNS = 2 };

static size_t electric_column(const sinter_scene *sc)
{
    return COL_FIXED_ + sc->walls->count +
           (sc->st->kind == SINTER_STEPPER_QUASISTATIC ? SINTERING_COLUMNS : 0);
}

static void observe(const sinter_scene *sc, double *row)
{
    const sinter_particles *ps = sc->ps;
    double ke = 0, top = -INFINITY, tsum = 0, tmax = -INFINITY;
    for (size_t i = 0; i < ps->count; ++i) {
        const double *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        ke += 0.5 * ps->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
              0.5 * ps->inertia[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        top = fmax(top, ps->x[3 * i + 2] + ps->radius[i]);
        tsum += ps->temperature[i];
        tmax = fmax(tmax, ps->temperature[i]);
    }
    const double n = (double)(ps->count ? ps->count : 1);
    row[COL_TIME] = sc->st->time;
    row[COL_KE] = ke;
    row[COL_CONTACTS] = (double)sc->st->stats.contacts;
    row[COL_COORDINATION] = 2.0 * (double)sc->st->stats.contacts / n;
    row[COL_BED_TOP] = top;
    row[COL_FRACTION] = volume_fraction(sc, top);
    row[COL_T_MEAN] = tsum / n;
    row[COL_T_MAX] = tmax;
    for (size_t k = 0; k < sc->walls->count; ++k) {
        const sinter_wall *w = &sc->walls->wall[k];
        /* force pushing the wall outwards, i.e. against its normal [N] */
        row[COL_FIXED_ + k] =
            -(w->force[0] * w->n[0] + w->force[1] * w->n[1] + w->force[2] * w->n[2]);
    }
    if (sc->electric != NULL) {
        /* seed 000 sec. 7: the current through the powder (the particles' current magnitudes) */
        double isum = 0.0, imax = 0.0;
        for (size_t i = 0; i < ps->count; ++i) {
            isum += fabs(ps->current[i]);
            imax = fmax(imax, fabs(ps->current[i]));
        }
        row[electric_column(sc)] = isum / n;
        row[electric_column(sc) + 1] = imax;
    }
    if (sc->st->kind == SINTER_STEPPER_QUASISTATIC) {
        /* seed 001 sec. 4 outputs: necks, shrinkage per axis, relative density */
        double *q = row + COL_FIXED_ + sc->walls->count;
        sinter_sintering_stats s;
        memset(&s, 0, sizeof(s));
        s.struct_size = sizeof(s);
        if (sc->st->quasistatic == NULL ||
            sinter_stepper_sintering_stats(sc->st, &s) != SINTER_OK) {
            /* before the first step: no links yet; the density of the spheres' bounding box */
            memset(&s, 0, sizeof(s));
            double lo[3], hi[3];
            const double solid = spheres_box(ps, lo, hi);
            s.relative_density = solid / ((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]));
        }
        const double v[SINTERING_COLUMNS] = {
            (double)s.links, s.neck_mean,    s.neck_min,     s.neck_max,        s.neck_ratio_mean,
            s.shrinkage[0],  s.shrinkage[1], s.shrinkage[2], s.relative_density};
        memcpy(q, v, sizeof(v));
    }
}

/*
 * [compact]: the triaxial compaction of sinter_pack_compact on the scene's particles (its own
 * walls and stepper; the scene's walls take no part). A stepper that has already stepped (a
 * restart from a checkpoint) keeps its state: the compaction belongs to the set-up.
 */
static sinter_status compact(sinter_scene *sc)
{
    sinter_compaction_result res;
    memset(&res, 0, sizeof(res));
    res.struct_size = sizeof(res);
    const sinter_status st = sinter_pack_compact(sc->ps, &sc->compact_options, &res);
    if (st == SINTER_OK)
        sinter_log(sc->ctx, SINTER_LOG_INFO,
                   "compacted: box %g x %g x %g m, volume fraction %.4f%s, coordination %.3f, "
                   "largest overlap %.3g of the radius, wall stress %g Pa, %g s simulated",
                   res.box_max[0] - res.box_min[0], res.box_max[1] - res.box_min[1],
                   res.box_max[2] - res.box_min[2], res.volume_fraction,
                   res.jammed ? " (jammed)" : "", res.coordination, res.max_overlap_ratio,
                   res.pressure, res.time);
    return st;
}

typedef struct run_state {
    sinter_scene *sc;
    const char *out_dir;
    sinter_series *series;
    double *row;
    size_t frames;
    size_t frame_capacity;
    double *frame_times;
    char **frame_files;
    double next_checkpoint;
} run_state;

static sinter_status write_frame(run_state *r)
{
    sinter_scene *sc = r->sc;
    sinter_ctx *ctx = sc->ctx;
    if (r->frames == r->frame_capacity) {
        size_t cap = r->frame_capacity ? 2 * r->frame_capacity : 64;
        double *t = sinter_realloc_array(ctx, r->frame_times, cap, sizeof(double));
        if (t == NULL)
            return SINTER_ERR_NOMEM;
        r->frame_times = t;
        char **f = sinter_realloc_array(ctx, r->frame_files, cap, sizeof(char *));
        if (f == NULL)
            return SINTER_ERR_NOMEM;
        r->frame_files = f;
        r->frame_capacity = cap;
    }
    char rel[64], path[2048];
    snprintf(rel, sizeof(rel), "frames/frame_%05zu.vtu", r->frames);
    snprintf(path, sizeof(path), "%s/%s", r->out_dir, rel);
    /* contact count per particle, for ParaView */
    double *contacts = sinter_calloc(ctx, sc->ps->count + 1, sizeof(double));
    if (contacts == NULL)
        return SINTER_ERR_NOMEM;
    const sinter_contact_list *c = &sc->st->pp;
    for (size_t k = 0; k < c->count; ++k) {
        contacts[c->i[k]] += 1.0;
        contacts[c->j[k]] += 1.0;
    }
    /* necks (bonded links) per particle, for the quasi-static stepper */
    double *necks = sinter_calloc(ctx, sc->ps->count + 1, sizeof(double));
    if (necks == NULL) {
        sinter_free(ctx, contacts);
        return SINTER_ERR_NOMEM;
    }
    size_t link_count = 0;
    const sinter_qs_link *links =
        sc->st->quasistatic ? sinter_qs_links(sc->st->quasistatic, &link_count) : NULL;
    for (size_t k = 0; k < link_count; ++k) {
        if (links[k].beam.a < sc->ps->count && links[k].beam.b < sc->ps->count) {
            necks[links[k].beam.a] += 1.0;
            necks[links[k].beam.b] += 1.0;
        }
    }
    const sinter_vtu_array extra[2] = {{"contacts", contacts, 1}, {"necks", necks, 1}};
    sinter_status st = sinter_write_vtu_as(sc->ps, path, extra, 2, sc->vtu_binary);
    sinter_free(ctx, contacts);
    sinter_free(ctx, necks);
    if (st != SINTER_OK)
        return st;
    r->frame_times[r->frames] = sc->st->time;
    r->frame_files[r->frames] = sinter_strdup(ctx, rel);
    if (r->frame_files[r->frames] == NULL)
        return SINTER_ERR_NOMEM;
    r->frames++;
    snprintf(path, sizeof(path), "%s/%s.pvd", r->out_dir, sc->name);
    return sinter_write_pvd(ctx, path, r->frames, r->frame_times,
                            (const char *const *)r->frame_files);
}

static sinter_status write_series(run_state *r)
{
    sinter_scene *sc = r->sc;
    char path[2048];
    sinter_status st = SINTER_OK;
    if (sc->write_csv) {
        snprintf(path, sizeof(path), "%s/series.csv", r->out_dir);
        st = sinter_series_write_csv(r->series, path);
    }
    if (st == SINTER_OK && sc->write_plot) {
        snprintf(path, sizeof(path), "%s/series.svg", r->out_dir);
        const size_t nw = sc->walls->count;
        size_t cols[8 + SCENE_MAX_WALLS + SINTERING_COLUMNS + ELECTRIC_COLUMNS], start[8],
            panels = 0, nc = 0;
        if (sc->st->kind == SINTER_STEPPER_QUASISTATIC) {
            const size_t q = COL_FIXED_ + nw; /* links, neck mean/min/max, ratio, shrinkage... */
            start[panels++] = nc;
            cols[nc++] = q + 5;
            cols[nc++] = q + 6;
            cols[nc++] = q + 7;
            start[panels++] = nc;
            cols[nc++] = q + 4;
            start[panels++] = nc;
            cols[nc++] = q + 8;
            start[panels++] = nc;
            cols[nc++] = COL_T_MEAN;
            start[panels] = nc;
            return sinter_series_write_svg(r->series, path, sc->name, COL_TIME, panels, start,
                                           cols);
        }
        start[panels++] = nc;
        cols[nc++] = COL_FRACTION;
        start[panels++] = nc;
        cols[nc++] = COL_T_MEAN;
        cols[nc++] = COL_T_MAX;
        if (nw > 0) {
            start[panels++] = nc;
            for (size_t k = 0; k < nw; ++k)
                cols[nc++] = COL_FIXED_ + k;
        }
        if (sc->electric != NULL) {
            start[panels++] = nc;
            cols[nc++] = electric_column(sc);
            cols[nc++] = electric_column(sc) + 1;
        }
        start[panels++] = nc;
        cols[nc++] = COL_KE;
        start[panels] = nc;
        st = sinter_series_write_svg(r->series, path, sc->name, COL_TIME, panels, start, cols);
    }
    return st;
}

static sinter_status record(run_state *r)
{
    observe(r->sc, r->row);
    sinter_status st = sinter_series_append(r->series, r->row);
    if (st == SINTER_OK && r->sc->write_vtu)
        st = write_frame(r);
    return st;
}

static sinter_status maybe_checkpoint(run_state *r, int force)
{
    sinter_scene *sc = r->sc;
    if (sc->checkpoint_interval <= 0.0 || (!force && sc->st->time < r->next_checkpoint))
        return SINTER_OK;
    char path[2048];
    snprintf(path, sizeof(path), "%s/checkpoint.bin", r->out_dir);
    r->next_checkpoint = sc->st->time + sc->checkpoint_interval;
    return sinter_checkpoint_write(sc->st, path);
}

/* Advance to t, in output intervals, recording each. */
static sinter_status run_to(run_state *r, double t_end, sinter_progress_fn progress, void *user,
                            double ke_stop, double t_min_stop, int *stopped_at_rest)
{
    sinter_scene *sc = r->sc;
    const double t_begin = sc->st->time;
    while (sc->st->time < t_end) {
        const double next = fmin(t_end, sc->st->time + sc->output_interval);
        sinter_status st = sinter_stepper_advance(sc->st, next);
        if (st == SINTER_OK)
            st = record(r);
        if (st == SINTER_OK)
            st = maybe_checkpoint(r, 0);
        if (st != SINTER_OK)
            return st;
        if (progress != NULL && progress(sc->st->time, sc->end_time, user) != 0)
            return sinter_fail(sc->ctx, SINTER_ERR_CALLBACK, "the run was stopped at t = %g s",
                               sc->st->time);
        if (stopped_at_rest != NULL && sc->st->time - t_begin >= t_min_stop &&
            r->row[COL_KE] / (double)sc->ps->count < ke_stop) {
            *stopped_at_rest = 1;
            return SINTER_OK;
        }
    }
    return SINTER_OK;
}

sinter_status sinter_scene_run(sinter_scene *sc, const char *out_dir, sinter_progress_fn progress,
                               void *user)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = sc->ctx;
    SINTER_CHECK_NULL(ctx, out_dir);
    char frames[2048];
    snprintf(frames, sizeof(frames), "%s/frames", out_dir);
    sinter_status st = make_dir(ctx, out_dir);
    if (st == SINTER_OK && sc->write_vtu)
        st = make_dir(ctx, frames);
    if (st != SINTER_OK)
        return st;
    const int sintering = sc->st->kind == SINTER_STEPPER_QUASISTATIC;
    const size_t nw = sc->walls->count,
                 ncol = electric_column(sc) + (sc->electric != NULL ? ELECTRIC_COLUMNS : 0);
    const char *names[COL_FIXED_ + SCENE_MAX_WALLS + SINTERING_COLUMNS + ELECTRIC_COLUMNS] = {
        "time",    "kinetic energy",  "contacts",         "coordination number",
        "bed top", "volume fraction", "mean temperature", "max temperature"};
    const char *units[COL_FIXED_ + SCENE_MAX_WALLS + SINTERING_COLUMNS + ELECTRIC_COLUMNS] = {
        "s", "J", "1", "1", "m", "1", "K", "K"};
    char wall_labels[SCENE_MAX_WALLS][SCENE_NAME + 16];
    for (size_t k = 0; k < nw; ++k) {
        snprintf(wall_labels[k], sizeof(wall_labels[k]), "%s force", sc->wall_names[k]);
        names[COL_FIXED_ + k] = wall_labels[k];
        units[COL_FIXED_ + k] = "N";
    }
    for (size_t k = 0; sintering && k < SINTERING_COLUMNS; ++k) {
        names[COL_FIXED_ + nw + k] = SINTERING_NAMES[k];
        units[COL_FIXED_ + nw + k] = SINTERING_UNITS[k];
    }
    if (sc->electric != NULL) {
        names[electric_column(sc)] = "mean particle current";
        names[electric_column(sc) + 1] = "max particle current";
        units[electric_column(sc)] = units[electric_column(sc) + 1] = "A";
    }
    run_state r;
    memset(&r, 0, sizeof(r));
    r.sc = sc;
    r.out_dir = out_dir;
    r.row = sinter_calloc(ctx, ncol, sizeof(double));
    if (r.row == NULL)
        return SINTER_ERR_NOMEM;
    st = sinter_series_create(&r.series, ctx, ncol, names, units);
    const int fresh = sc->st->stats.steps == 0 && sc->st->time == 0.0;
    if (st == SINTER_OK && sc->compact && fresh && !sc->pour)
        st = compact(sc);
    /* The state at the start, with forces evaluated. */
    if (st == SINTER_OK)
        st = sinter_stepper_step(sc->st, 0);
    if (st == SINTER_OK)
        st = record(&r);
    r.next_checkpoint = sc->st->time + sc->checkpoint_interval;
    if (st == SINTER_OK && sc->pour) {
        /* Pour to rest with every wall held; wall motions are timed from the end of the pour. */
        for (size_t k = 0; k < nw && st == SINTER_OK; ++k)
            st = sinter_walls_set_motion_start(sc->walls, k, HUGE_VAL);
        int at_rest = 0;
        st = run_to(&r, sc->st->time + sc->pour_t_max, progress, user, sc->pour_ke, sc->pour_t_min,
                    &at_rest);
        if (st == SINTER_OK && !at_rest)
            st = sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                             "the pour did not come to rest within t_max = %g s (kinetic energy "
                             "%g J per particle, threshold %g J)",
                             sc->pour_t_max, r.row[COL_KE] / (double)sc->ps->count, sc->pour_ke);
        for (size_t k = 0; k < nw && st == SINTER_OK; ++k)
            st = sinter_walls_set_motion_start(sc->walls, k, sc->st->time);
        sinter_stepper_shift_furnace(sc->st, sc->st->time); /* timed from the pour's end too */
        if (st == SINTER_OK)
            sinter_log(ctx, SINTER_LOG_INFO, "poured: at rest at t = %g s", sc->st->time);
        if (st == SINTER_OK && sc->compact && fresh)
            st = compact(sc);
    }
    if (st == SINTER_OK)
        st = run_to(&r, sc->end_time + (sc->pour ? sc->st->time : 0.0), progress, user, 0, 0, NULL);
    /* Whatever happened, write what was recorded (the last good state is in the series). */
    const sinter_status written = r.series ? write_series(&r) : SINTER_OK;
    if (st == SINTER_OK)
        st = written;
    if (st == SINTER_OK)
        st = maybe_checkpoint(&r, 1);
    for (size_t k = 0; k < r.frames; ++k)
        sinter_free(ctx, r.frame_files[k]);
    sinter_free(ctx, r.frame_files);
    sinter_free(ctx, r.frame_times);
    sinter_series_destroy(r.series);
    sinter_free(ctx, r.row);
    return st;
}
