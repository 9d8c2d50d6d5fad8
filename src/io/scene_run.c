#define _POSIX_C_SOURCE 200809L
/*
 * Running a scene: an optional pour to rest and an optional triaxial compaction, then the
 * run to the end time, with global observables recorded every output interval into a series
 * (series.csv, appended as the run goes; series.svg drawn from it at the end), VTU frames with
 * a PVD collection rewritten after every frame, and checkpoints that carry the program
 * (io/scene_program.h), so that a restart continues the run where it stood.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "core/make_dirs.h"
#include "contact/snapshot.h"
#include "heat/heat_model.h"
#include "io/csv_stream.h"
#include "io/run_plot.h"
#include "io/scene_frames.h"
#include "io/scene_pair_reference.h"
#include "io/scene_track.h"
#include "io/scene.h"
#include "io/solid_fraction.h"
#include "io/vtk_appended.h"
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
    char partial[SINTER_PATH_SIZE];
    const int rc = sinter_make_dirs(path, partial, sizeof(partial));
    if (rc < 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "output directory '%.200s' is empty or too long", path);
    if (rc > 0)
        return sinter_fail(ctx, SINTER_ERR_IO, "cannot create directory '%s': %s", partial,
                           strerror(errno));
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
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i) { /* owned */
        const double r = ps->radius[i];
        solid += 4.0 / 3.0 * PI * r * r * r;
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], ps->x[3 * i + d] - r);
            hi[d] = fmax(hi[d], ps->x[3 * i + d] + r);
        }
    }
    return solid;
}

/* The box of the volume fraction (see there) into lo, hi; the spheres' summed volume. */
static double fraction_box(const sinter_scene *sc, double bed_top, double lo[3], double hi[3])
{
    const double solid = spheres_box(sc->ps, lo, hi);
    hi[2] = bed_top;
    for (size_t k = 0; k < sc->walls->count; ++k) {
        const sinter_wall *w = &sc->walls->wall[k];
        if (w->kind == SINTER_WALL_CYLINDER) { /* a die along an axis bounds the other two */
            for (int d = 0; d < 3 && w->inside; ++d)
                if (fabs(w->axis[d]) >= 1.0 - 1e-12)
                    for (int e = 1; e < 3; ++e) {
                        const int o = (d + e) % 3;
                        lo[o] = fmax(lo[o] == INFINITY ? w->p[o] - w->radius : lo[o],
                                     w->p[o] - w->radius);
                        hi[o] = fmin(hi[o], w->p[o] + w->radius);
                    }
            continue;
        }
        for (int d = 0; d < 3; ++d) {
            if (fabs(w->n[d]) < 1.0 - 1e-12)
                continue;
            if (w->n[d] > 0) /* a lower bound, facing +axis */
                lo[d] = fmax(lo[d] == INFINITY ? w->p[d] : lo[d], w->p[d]);
            else
                hi[d] = fmin(hi[d], w->p[d]);
        }
    }
    return solid;
}

static double volume_fraction(const sinter_scene *sc, double bed_top)
{
    double lo[3], hi[3];
    const double solid = fraction_box(sc, bed_top, lo, hi);
    const double volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    return volume > 0 ? solid / volume : NAN;
}

/* The same box's solid fraction without overlaps counted twice nor parts beyond its faces
 * (io/solid_fraction.c), over the overlapping pairs of the neighbour list. */
static double solid_fraction(const sinter_scene *sc, double bed_top)
{
    if (sc->solid_box) /* [output] solid_box: a box the spheres may cross */
        return sinter_solid_fraction_sampled(sc->ctx, sc->ps, sc->solid_lo, sc->solid_hi, 2e7);
    double lo[3], hi[3];
    fraction_box(sc, bed_top, lo, hi);
    const double volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    const sinter_pair_list *pairs = sc->st->nb.built ? &sc->st->nb.pp : NULL;
    return volume > 0 ? sinter_solid_volume_in_box(sc->ps, pairs, lo, hi) / volume : NAN;
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

/*
 * Columns after those (issue 37): with a conduction model, the heat flow from each wall into
 * the particles; with the "network" electric model, the current from each wall into them;
 * then the stepper's time step (the next one it proposes) and its counts so far (those a
 * checkpoint carries).
 */
enum { STEPPER_COLUMNS = 6 };
static const char *const STEPPER_NAMES[STEPPER_COLUMNS] = {"time step",
                                                           "rejected steps",
                                                           "neighbour rebuilds",
                                                           "fixed-point iterations",
                                                           "pipeline evaluations",
                                                           "contraction"};
static const char *const STEPPER_UNITS[STEPPER_COLUMNS] = {"s", "1", "1", "1", "1", "1"};

/* The last three only with the staggered stepper (its iterations so far, the evaluations of
 * the pipeline so far and the contraction estimate of its last step; staggered.c). */
static size_t stepper_base_columns(const sinter_scene *sc)
{
    return sc->st->kind == SINTER_STEPPER_STAGGERED ? 6 : 3;
}

/* 1 when a force model holds bonds in tension (power law bond_strength > 0): then one more
 * column, the bonds broken so far (sinter_stepper_stats.bonds_broken; a checkpoint carries it,
 * version 10). */
static int holds_bonds(const sinter_scene *sc)
{
    for (size_t k = 0; k < sc->st->force_count; ++k)
        if (sinter_force_holds_pairs(sc->st->forces[k].model))
            return 1;
    return 0;
}

/* 2 when the scene inserts ([insert]): then the mass inserted so far and its target
 * (sinter_stepper_get_insertion; a checkpoint carries both, version 11), after those; and for
 * a mixture the mass inserted of each material (sinter_stepper_get_insertion_mixture). */
static size_t insertion_columns(const sinter_scene *sc)
{
    return sc->st->insertion != NULL ? 2 + sc->insert_mixture : 0;
}

static size_t stepper_columns(const sinter_scene *sc)
{
    return stepper_base_columns(sc) + (size_t)holds_bonds(sc) + insertion_columns(sc);
}

static size_t wall_heat_column(const sinter_scene *sc)
{
    return electric_column(sc) + (sc->electric != NULL ? ELECTRIC_COLUMNS : 0);
}

static size_t wall_current_column(const sinter_scene *sc)
{
    return wall_heat_column(sc) + (sinter_snapshot_conducts_heat(sc->st) ? sc->walls->count : 0);
}

static size_t stepper_column(const sinter_scene *sc)
{
    return wall_current_column(sc) +
           (sinter_snapshot_conducts_current(sc->st) ? sc->walls->count : 0);
}

/* After those, the solid fraction (solid_fraction), then the distributions. */
static size_t solid_column(const sinter_scene *sc)
{
    return stepper_column(sc) + stepper_columns(sc);
}

static size_t distribution_column(const sinter_scene *sc)
{
    return solid_column(sc) + 1;
}

/*
 * With [output] distributions = yes, after those (issue 37): how many particles have k contacts
 * (k = 0 .. COORDINATION_MAX - 1, then COORDINATION_MAX or more; the quasi-static stepper's
 * links), and for the quasi-static stepper how many links have a neck ratio in each bin of
 * NECK_BIN (the last bin: NECK_BINS NECK_BIN or more), then how many links had a relative
 * correction of their approach (seed 001 eq. 44 over the 7DOF model's own change dy4 + dy7 of
 * the step, Fig. 20) below CORRECTION_LOW, in each bin of CORRECTION_BIN from it, and above.
 * Each histogram sums to the particles or the links.
 */
enum { COORDINATION_MAX = 13, NECK_BINS = 10, CORRECTION_BINS = 10 };
static const double NECK_BIN = 0.05, CORRECTION_BIN = 0.25, CORRECTION_LOW = -1.25;

static size_t distribution_columns(const sinter_scene *sc)
{
    if (!sc->write_distributions)
        return 0;
    return COORDINATION_MAX + 1 +
           (sc->st->kind == SINTER_STEPPER_QUASISTATIC ? NECK_BINS + 1 + CORRECTION_BINS + 2 : 0);
}

/* The relative corrections' histogram (q: CORRECTION_BINS + 2 counts) from a snapshot of the
 * links; NaN before a step of this run (no correction known). */
static void observe_corrections(const sinter_scene *sc, const sinter_qs_link *link, size_t links,
                                double *q)
{
    sinter_snapshot *snap = NULL;
    const void *data = NULL;
    size_t count = 0;
    if (sinter_snapshot_create(&snap, sc->st) != SINTER_OK ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_CORRECTION, &data, &count, NULL, NULL) !=
            SINTER_OK ||
        count != links) {
        for (size_t k = 0; k < CORRECTION_BINS + 2; ++k)
            q[k] = NAN;
        sinter_snapshot_destroy(snap);
        return;
    }
    const double *correction = data;
    for (size_t k = 0; k < links; ++k) {
        const double r = correction[k] / (link[k].neck.last_dy4 + link[k].neck.last_dy7);
        const double bin = floor((r - CORRECTION_LOW) / CORRECTION_BIN);
        if (isnan(correction[k])) {
            for (size_t j = 0; j < CORRECTION_BINS + 2; ++j)
                q[j] = NAN;
            break;
        }
        /* (a link without an approach of its own this step, r infinite: a tail) */
        q[bin < 0 || isnan(r)     ? 0
          : bin < CORRECTION_BINS ? 1 + (size_t)bin
                                  : CORRECTION_BINS + 1] += 1.0;
    }
    sinter_snapshot_destroy(snap);
}

static size_t distribution_column(const sinter_scene *sc);

/* After those, the followed particles' columns (io/scene_track.h). */
static size_t track_column(const sinter_scene *sc)
{
    return distribution_column(sc) + distribution_columns(sc);
}

/* After those, the two-particle reference (io/scene_pair_reference.h). */
static size_t pair_column(const sinter_scene *sc)
{
    return track_column(sc) + SCENE_TRACK_COLUMNS * sc->track_count;
}

/* Last, with the frozen heat stage (option frozen_heat, issue 41): whether the mechanics are
 * frozen, the simulated time spent frozen, the heat steps, the wake-ups and the heat step's
 * proposal. Absent otherwise, so that the series of other scenes keep their bytes. */
enum { FROZEN_COLUMNS = 5 };
static const char *const FROZEN_NAMES[FROZEN_COLUMNS] = {"frozen", "frozen time", "heat steps",
                                                         "wake-ups", "heat step"};
static const char *const FROZEN_UNITS[FROZEN_COLUMNS] = {"1", "s", "1", "1", "s"};
static const char *const FROZEN_KEYS[FROZEN_COLUMNS] = {
    "frozen_active", "frozen_time", "frozen_steps", "frozen_wakeups", "frozen_dt"};

static size_t frozen_columns(const sinter_scene *sc)
{
    double on = 0.0;
    return sinter_stepper_get_option(sc->st, "frozen_heat", &on) == SINTER_OK && on != 0.0
               ? FROZEN_COLUMNS
               : 0;
}

static size_t frozen_column(const sinter_scene *sc)
{
    return pair_column(sc) + (sc->pair_reference ? SCENE_PAIR_COLUMNS : 0);
}

/* Very last, with [output] temperature_bins = lo hi n: how many particles have a temperature
 * below lo, in each of the n bins of (hi - lo) / n from lo, and at hi or above; they sum to
 * the particles (issue 37: the distribution of the particles' temperatures). */
static size_t temperature_columns(const sinter_scene *sc)
{
    return sc->temperature_bins > 0 ? sc->temperature_bins + 2 : 0;
}

static size_t temperature_column(const sinter_scene *sc)
{
    return frozen_column(sc) + frozen_columns(sc);
}

static void observe_temperatures(const sinter_scene *sc, double *row)
{
    const size_t columns = temperature_columns(sc);
    if (columns == 0)
        return;
    double *q = row + temperature_column(sc);
    for (size_t k = 0; k < columns; ++k)
        q[k] = 0.0;
    const double lo = sc->temperature_low, hi = sc->temperature_high;
    const double width = (hi - lo) / (double)sc->temperature_bins;
    for (size_t i = 0; i < sc->ps->count - sc->ps->ghost_count; ++i) { /* owned */
        const double theta = sc->ps->temperature[i];
        size_t k;
        if (theta < lo)
            k = 0;
        else if (!(theta < hi)) /* at hi or above */
            k = columns - 1;
        else {
            const double b = floor((theta - lo) / width);
            k = 1 + (b < (double)sc->temperature_bins ? (size_t)b : sc->temperature_bins - 1);
        }
        q[k] += 1.0;
    }
}

/* Last of all, with a beam heat model ("laser", "nozzle" or "beam"): how many particles the
 * beam has given power so far (the beam models mark them SINTER_PARTICLE_LIT; the flag is
 * particle state, so a checkpoint carries it) and their mean temperature, 0 K while there are
 * none: seed 003 sec. 5.4 reports this mean ("only those that have been targeted by the
 * beam"). Absent otherwise, so that the series of other scenes keep their bytes. */
enum { LIT_COLUMNS = 2 };

static size_t lit_columns(const sinter_scene *sc)
{
    for (size_t k = 0; k < sc->st->thermal.count; ++k) {
        const char *name = sc->st->thermal.slots[k].model->ops->name;
        if (strcmp(name, "laser") == 0 || strcmp(name, "nozzle") == 0 || strcmp(name, "beam") == 0)
            return LIT_COLUMNS;
    }
    return 0;
}

static size_t lit_column(const sinter_scene *sc)
{
    return temperature_column(sc) + temperature_columns(sc);
}

static void observe_lit(const sinter_scene *sc, double *row)
{
    if (lit_columns(sc) == 0)
        return;
    const sinter_particles *ps = sc->ps;
    double count = 0.0, sum = 0.0;
    for (size_t i = 0; i < ps->count - ps->ghost_count; ++i) /* owned */
        if (ps->flags[i] & (uint32_t)SINTER_PARTICLE_LIT) {
            count += 1.0;
            sum += ps->temperature[i];
        }
    row[lit_column(sc)] = count;
    row[lit_column(sc) + 1] = count > 0.0 ? sum / count : 0.0;
}

/* Columns after those (issue 38): a quasi-static stepper with periodic axes writes its cell's
 * lengths along x, y, z (0 along an axis that is not periodic) and the volumetric strain
 * 1 - (1 - s_x)(1 - s_y)(1 - s_z) of the shrinkage columns (stepper/qs_periodic.c: on a
 * periodic axis the shrinkage is the cell's strain). Absent otherwise: other series keep their
 * bytes. */
enum { CELL_COLUMNS = 4 };

static size_t cell_columns(const sinter_scene *sc)
{
    return sc->st->kind == SINTER_STEPPER_QUASISTATIC && sinter_ghosts_on(&sc->st->ghosts)
               ? CELL_COLUMNS
               : 0;
}

static size_t cell_column(const sinter_scene *sc)
{
    return lit_column(sc) + lit_columns(sc);
}

static void observe_cell(const sinter_scene *sc, double *row)
{
    if (cell_columns(sc) == 0)
        return;
    double *c = row + cell_column(sc);
    for (int d = 0; d < 3; ++d) {
        int periodic = 0;
        double lo = 0.0, hi = 0.0;
        c[d] = sinter_stepper_get_periodic(sc->st, d, &periodic, &lo, &hi) == SINTER_OK ? hi - lo
                                                                                        : NAN;
    }
    /* the shrinkage columns, written before this */
    const double *q = row + COL_FIXED_ + sc->walls->count + 5;
    c[3] = 1.0 - (1.0 - q[0]) * (1.0 - q[1]) * (1.0 - q[2]);
}

static void observe_frozen(const sinter_scene *sc, double *row)
{
    for (size_t k = 0; k < frozen_columns(sc); ++k)
        if (sinter_stepper_get_option(sc->st, FROZEN_KEYS[k], row + frozen_column(sc) + k) !=
            SINTER_OK)
            row[frozen_column(sc) + k] = NAN;
}

/* The histograms of the row (NaN where the contacts of the state are not known yet). */
static void observe_distributions(const sinter_scene *sc, double *row)
{
    const size_t columns = distribution_columns(sc);
    if (columns == 0)
        return;
    double *q = row + distribution_column(sc);
    const sinter_particles *ps = sc->ps;
    const int qs = sc->st->kind == SINTER_STEPPER_QUASISTATIC;
    size_t links = 0;
    const sinter_qs_link *link =
        qs && sc->st->quasistatic ? sinter_qs_links(sc->st->quasistatic, &links) : NULL;
    if (!qs && !sinter_snapshot_possible(sc->st)) {
        for (size_t k = 0; k < columns; ++k)
            q[k] = NAN;
        return;
    }
    for (size_t k = 0; k < columns; ++k)
        q[k] = 0.0;
    uint32_t *count = sinter_calloc(sc->ctx, ps->count + 1, sizeof(uint32_t));
    if (count == NULL) {
        for (size_t k = 0; k < columns; ++k)
            q[k] = NAN; /* out of memory: the sample says so */
        return;
    }
    const sinter_contact_list *c = &sc->st->pp;
    for (size_t k = 0; !qs && k < c->count; ++k) {
        count[c->i[k]]++;
        count[c->j[k]]++;
    }
    for (size_t k = 0; k < links; ++k) {
        const uint32_t a = link[k].beam.a, b = link[k].beam.b;
        if (a >= ps->count || b >= ps->count)
            continue;
        count[a]++;
        count[b]++;
        /* the neck ratio as the sintering statistics form it */
        const double ratio = link[k].neck.y[SINTER_NECK_X] / fmin(ps->radius[a], ps->radius[b]);
        const double bin = floor(ratio / NECK_BIN);
        q[COORDINATION_MAX + 1 + (bin >= 0 && bin < NECK_BINS ? (size_t)bin : NECK_BINS)] += 1.0;
    }
    for (size_t i = 0; i < ps->count; ++i)
        q[count[i] < COORDINATION_MAX ? count[i] : COORDINATION_MAX] += 1.0;
    sinter_free(sc->ctx, count);
    if (qs)
        observe_corrections(sc, link, links, q + COORDINATION_MAX + 1 + NECK_BINS + 1);
}

/* The wall flows and the stepper's columns of the row. */
static void observe_flows(const sinter_scene *sc, double *row)
{
    const int heat = sinter_snapshot_conducts_heat(sc->st);
    const int current = sinter_snapshot_conducts_current(sc->st);
    if ((heat || current) &&
        sinter_snapshot_wall_flows(sc->st, heat ? row + wall_heat_column(sc) : NULL,
                                   current ? row + wall_current_column(sc) : NULL) != SINTER_OK)
        for (size_t k = wall_heat_column(sc); k < stepper_column(sc); ++k)
            row[k] = NAN; /* out of memory: the sample says so */
    const sinter_stepper_stats *s = &sc->st->stats;
    double *q = row + stepper_column(sc);
    q[0] = sc->st->dt;
    q[1] = (double)s->rejected;
    q[2] = (double)s->neighbor_builds;
    const size_t base = stepper_base_columns(sc);
    if (base > 3) { /* a checkpoint carries these too (version 7) */
        q[3] = (double)s->iterations;
        q[4] = (double)s->evaluations;
        q[5] = sc->st->staggered.contraction;
    }
    if (holds_bonds(sc))
        q[base] = (double)s->bonds_broken;
    if (insertion_columns(sc) > 0) {
        double *ins = q + base + (size_t)holds_bonds(sc);
        sinter_stepper_get_insertion(sc->st, &ins[0], &ins[1], NULL, NULL);
        sinter_stepper_get_insertion_mixture(sc->st, ins + 2, sc->insert_mixture, NULL);
    }
    observe_distributions(sc, row);
    scene_track_observe(sc, row + track_column(sc));
    if (sc->pair_reference)
        scene_pair_reference(sc, row + pair_column(sc));
}

static void observe(const sinter_scene *sc, double *row)
{
    const sinter_particles *ps = sc->ps;
    const size_t owned = ps->count - ps->ghost_count; /* ghosts are images of these */
    double ke = 0, top = -INFINITY, tsum = 0, tmax = -INFINITY;
    for (size_t i = 0; i < owned; ++i) {
        const double *v = ps->v + 3 * i, *w = ps->w + 3 * i;
        ke += 0.5 * ps->mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
              0.5 * ps->inertia[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        top = fmax(top, ps->x[3 * i + 2] + ps->radius[i]);
        tsum += ps->temperature[i];
        tmax = fmax(tmax, ps->temperature[i]);
    }
    const double n = (double)(owned ? owned : 1);
    row[COL_TIME] = sc->st->time;
    row[COL_KE] = ke;
    row[COL_CONTACTS] = (double)sc->st->stats.contacts;
    row[COL_COORDINATION] = 2.0 * (double)sc->st->stats.contacts / n;
    row[COL_BED_TOP] = top;
    row[COL_FRACTION] = volume_fraction(sc, top);
    row[solid_column(sc)] = solid_fraction(sc, top);
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
        for (size_t i = 0; i < owned; ++i) {
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
            for (int d = 0; d < 3; ++d) { /* a periodic axis: the cell (qs_periodic.c) */
                int periodic = 0;
                double cell_lo = 0.0, cell_hi = 0.0;
                if (sinter_stepper_get_periodic(sc->st, d, &periodic, &cell_lo, &cell_hi) ==
                        SINTER_OK &&
                    periodic) {
                    lo[d] = cell_lo;
                    hi[d] = cell_hi;
                }
            }
            s.relative_density = solid / ((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]));
        }
        const double v[SINTERING_COLUMNS] = {
            (double)s.links, s.neck_mean,    s.neck_min,     s.neck_max,        s.neck_ratio_mean,
            s.shrinkage[0],  s.shrinkage[1], s.shrinkage[2], s.relative_density};
        memcpy(q, v, sizeof(v));
    }
    observe_flows(sc, row);
    observe_frozen(sc, row);
    observe_temperatures(sc, row);
    observe_lit(sc, row);
    observe_cell(sc, row);
}

/*
 * [compact]: the triaxial compaction of sinter_pack_compact on the scene's particles (its own
 * walls and stepper; the scene's walls take no part). A stepper that has already stepped (a
 * restart from a checkpoint) keeps its state: the compaction belongs to the set-up.
 */
static sinter_status compact(sinter_scene *sc)
{
    return sinter_scene_compact(sc); /* io/scene_compact.c */
}

typedef struct run_state {
    sinter_scene *sc;
    const char *out_dir;
    sinter_series *series; /* the columns; rows kept only when a plot is drawn without a CSV */
    sinter_csv_stream csv;
    double *row;
    char csv_path[SINTER_PATH_SIZE];
    uint64_t earlier;       /* frames of the program written before this call */
    unsigned char *present; /* which of them are in out_dir (listed in the collection) */
} run_state;

/* The PVD collection of the frames written so far (those of an earlier run only where their
 * files are in this directory: a restart into another directory lists its own). */
static sinter_status write_collection(run_state *r)
{
    sinter_scene *sc = r->sc;
    sinter_ctx *ctx = sc->ctx;
    const scene_program *p = &sc->program;
    /* each frame: its particles, then its contacts and walls where written (parts 1, 2) */
    const size_t most = (size_t)p->frames * (1 + SCENE_FRAME_EXTRAS) + 1;
    char **files = sinter_calloc(ctx, most, sizeof(char *));
    double *times = sinter_calloc(ctx, most, sizeof(double));
    unsigned *parts = sinter_calloc(ctx, most, sizeof(unsigned));
    char rel[64], path[SINTER_PATH_SIZE];
    sinter_status st = files && times && parts ? SINTER_OK : sinter_last_status(ctx);
    size_t listed = 0;
    for (uint64_t k = 0; k < p->frames && st == SINTER_OK; ++k) {
        if (k < r->earlier && !r->present[k])
            continue;
        char extra[SCENE_FRAME_EXTRAS][64];
        unsigned extra_parts[SCENE_FRAME_EXTRAS];
        const size_t extras = scene_frame_extras_list(sc, r->out_dir, k, extra, extra_parts);
        for (size_t e = 0; e <= extras && st == SINTER_OK; ++e) {
            snprintf(rel, sizeof(rel), "frames/frame_%05llu.vtu", (unsigned long long)k);
            files[listed] = sinter_strdup(ctx, e == 0 ? rel : extra[e - 1]);
            times[listed] = p->frame_times[k];
            parts[listed] = e == 0 ? 0u : extra_parts[e - 1];
            st = files[listed] != NULL ? SINTER_OK : sinter_last_status(ctx);
            listed += st == SINTER_OK;
        }
    }
    char name[SCENE_NAME + 8];
    snprintf(name, sizeof(name), "%s.pvd", sc->name);
    if (st == SINTER_OK)
        st = sinter_path_join(ctx, path, sizeof(path), r->out_dir, name);
    if (st == SINTER_OK)
        st = sinter_write_pvd_parts(ctx, path, listed, times, (const char *const *)files, parts);
    for (size_t k = 0; files != NULL && k < listed; ++k)
        sinter_free(ctx, files[k]);
    sinter_free(ctx, files);
    sinter_free(ctx, times);
    sinter_free(ctx, parts);
    return st;
}

static sinter_status write_frame(run_state *r)
{
    sinter_scene *sc = r->sc;
    sinter_ctx *ctx = sc->ctx;
    char rel[64], path[SINTER_PATH_SIZE];
    snprintf(rel, sizeof(rel), "frames/frame_%05llu.vtu", (unsigned long long)sc->program.frames);
    sinter_status st = sinter_path_join(ctx, path, sizeof(path), r->out_dir, rel);
    if (st != SINTER_OK)
        return st;
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
    st = sinter_write_vtu_as(sc->ps, path, extra, 2, scene_vtk_format(sc));
    if (st == SINTER_OK && sc->vtu_appended)
        st = sinter_vtk_make_appended(ctx, path);
    sinter_free(ctx, contacts);
    sinter_free(ctx, necks);
    if (st == SINTER_OK)
        st = scene_frame_extras_write(sc, r->out_dir, sc->program.frames);
    if (st == SINTER_OK)
        st = scene_program_add_frame(ctx, &sc->program, sc->st->time);
    return st == SINTER_OK ? write_collection(r) : st;
}

/* The plot, from the CSV (or the rows kept in memory when no CSV is written). */
static sinter_status write_plot(run_state *r)
{
    sinter_scene *sc = r->sc;
    if (!sc->write_plot)
        return SINTER_OK;
    if (sc->write_csv)
        return sinter_plot_run(sc->ctx, r->out_dir, sc->name);
    char path[SINTER_PATH_SIZE];
    sinter_status st = sinter_path_join(sc->ctx, path, sizeof(path), r->out_dir, "series.svg");
    return st == SINTER_OK ? sinter_plot_series(r->series, path, sc->name) : st;
}

/* One sample: the series row (appended to the CSV at once) and a frame. */
static sinter_status record(run_state *r)
{
    sinter_scene *sc = r->sc;
    observe(sc, r->row);
    sinter_status st = SINTER_OK;
    if (sc->write_csv)
        st = sinter_csv_stream_append(&r->csv, r->row);
    else if (sc->write_plot)
        st = sinter_series_append(r->series, r->row);
    if (st == SINTER_OK && sc->write_vtu)
        st = write_frame(r);
    if (st == SINTER_OK) {
        sc->program.rows++;
        sc->program.next_output = sc->st->time + sc->output_interval;
    }
    return st;
}

static sinter_status checkpoint(run_state *r)
{
    sinter_scene *sc = r->sc;
    char path[SINTER_PATH_SIZE];
    sinter_status st = sinter_path_join(sc->ctx, path, sizeof(path), r->out_dir, "checkpoint.bin");
    if (st == SINTER_OK && sc->write_csv)
        st = sinter_csv_stream_sync(&r->csv); /* the rows the checkpoint counts are on disk */
    return st == SINTER_OK ? sinter_scene_checkpoint_write(sc, path) : st;
}

static sinter_status maybe_checkpoint(run_state *r)
{
    sinter_scene *sc = r->sc;
    if (sc->checkpoint_interval <= 0.0 || sc->st->time < sc->program.next_checkpoint)
        return SINTER_OK;
    sc->program.next_checkpoint = sc->st->time + sc->checkpoint_interval;
    return checkpoint(r);
}

/* The pour's end: the walls' programs, the furnace and the end time start from now. */
static sinter_status end_pour(run_state *r)
{
    sinter_scene *sc = r->sc;
    scene_program *p = &sc->program;
    sinter_status st = SINTER_OK;
    for (size_t k = 0; k < sc->walls->count && st == SINTER_OK; ++k)
        st = sinter_walls_set_motion_start(sc->walls, k, sc->st->time);
    if (st != SINTER_OK)
        return st;
    p->origin = sc->st->time;
    sinter_stepper_shift_furnace(sc->st, p->origin - sc->furnace_shift);
    sc->furnace_shift = p->origin;
    p->phase = SCENE_PHASE_MAIN;
    sinter_log(sc->ctx, SINTER_LOG_INFO, "poured: at rest at t = %g s", sc->st->time);
    return sc->compact ? compact(sc) : SINTER_OK;
}

/* The set-up of a fresh run: the compaction (without a pour), the first sample, the pour. */
static sinter_status begin(run_state *r)
{
    sinter_scene *sc = r->sc;
    scene_program *p = &sc->program;
    sinter_status st = SINTER_OK;
    if (sc->compact && !sc->pour)
        st = compact(sc);
    /* The state at the start, with forces evaluated. */
    if (st == SINTER_OK)
        st = sinter_stepper_step(sc->st, 0);
    if (st != SINTER_OK)
        return st;
    p->phase = sc->pour ? SCENE_PHASE_POUR : SCENE_PHASE_MAIN;
    p->pour_start = p->origin = 0.0;
    st = record(r);
    p->next_checkpoint = sc->st->time + sc->checkpoint_interval;
    if (st == SINTER_OK && sc->pour) {
        /* Pour to rest with every wall held; wall motions are timed from the end of the pour. */
        p->pour_start = sc->st->time;
        for (size_t k = 0; k < sc->walls->count && st == SINTER_OK; ++k)
            st = sinter_walls_set_motion_start(sc->walls, k, HUGE_VAL);
    }
    return st;
}

/*
 * The program from where it stands: sample after sample (each output interval), the pour's
 * end when the bed is at rest, checkpoints; to the end time after the origin.
 */
static sinter_status run_program(run_state *r, sinter_progress_fn progress, void *user)
{
    sinter_scene *sc = r->sc;
    sinter_ctx *ctx = sc->ctx;
    scene_program *p = &sc->program;
    for (;;) {
        const int pouring = p->phase == SCENE_PHASE_POUR;
        const double end = pouring ? p->pour_start + sc->pour_t_max : sc->end_time + p->origin;
        if (sc->st->time >= end) {
            if (pouring)
                return sinter_fail(ctx, SINTER_ERR_NOT_CONVERGED,
                                   "the pour did not come to rest within t_max = %g s (kinetic "
                                   "energy %g J per particle, threshold %g J)",
                                   sc->pour_t_max,
                                   r->row[COL_KE] / (double)(sc->ps->count - sc->ps->ghost_count),
                                   sc->pour_ke);
            return SINTER_OK;
        }
        sinter_status st = sinter_stepper_advance(sc->st, fmin(end, p->next_output));
        if (st == SINTER_OK)
            st = record(r);
        if (st == SINTER_OK && pouring && sc->st->time - p->pour_start >= sc->pour_t_min &&
            r->row[COL_KE] / (double)(sc->ps->count - sc->ps->ghost_count) < sc->pour_ke)
            st = end_pour(r);
        if (st == SINTER_OK)
            st = maybe_checkpoint(r);
        if (st != SINTER_OK)
            return st;
        if (progress != NULL && progress(sc->st->time, sc->end_time + p->origin, user) != 0)
            return sinter_fail(ctx, SINTER_ERR_INTERRUPTED,
                               "the run was stopped by its progress callback at t = %.17g s",
                               sc->st->time);
    }
}

/* Column names and units of the series, into names and units (room for every column). */
static size_t columns(const sinter_scene *sc, const char **names, const char **units,
                      char (*wall_labels)[SCENE_NAME + 16])
{
    static const char *const fixed[COL_FIXED_] = {
        "time",    "kinetic energy",  "contacts",         "coordination number",
        "bed top", "volume fraction", "mean temperature", "max temperature"};
    static const char *const fixed_units[COL_FIXED_] = {"s", "J", "1", "1", "m", "1", "K", "K"};
    for (size_t k = 0; k < COL_FIXED_; ++k) {
        names[k] = fixed[k];
        units[k] = fixed_units[k];
    }
    const size_t nw = sc->walls->count;
    for (size_t k = 0; k < nw; ++k) {
        snprintf(wall_labels[k], sizeof(wall_labels[k]), "%s force", sc->wall_names[k]);
        names[COL_FIXED_ + k] = wall_labels[k];
        units[COL_FIXED_ + k] = "N";
    }
    for (size_t k = 0; sc->st->kind == SINTER_STEPPER_QUASISTATIC && k < SINTERING_COLUMNS; ++k) {
        names[COL_FIXED_ + nw + k] = SINTERING_NAMES[k];
        units[COL_FIXED_ + nw + k] = SINTERING_UNITS[k];
    }
    if (sc->electric != NULL) {
        names[electric_column(sc)] = "mean particle current";
        names[electric_column(sc) + 1] = "max particle current";
        units[electric_column(sc)] = units[electric_column(sc) + 1] = "A";
    }
    for (size_t k = 0; sinter_snapshot_conducts_heat(sc->st) && k < nw; ++k) {
        snprintf(wall_labels[nw + k], sizeof(wall_labels[nw + k]), "%s heat flow",
                 sc->wall_names[k]);
        names[wall_heat_column(sc) + k] = wall_labels[nw + k];
        units[wall_heat_column(sc) + k] = "W";
    }
    for (size_t k = 0; sinter_snapshot_conducts_current(sc->st) && k < nw; ++k) {
        snprintf(wall_labels[2 * nw + k], sizeof(wall_labels[2 * nw + k]), "%s current",
                 sc->wall_names[k]);
        names[wall_current_column(sc) + k] = wall_labels[2 * nw + k];
        units[wall_current_column(sc) + k] = "A";
    }
    for (size_t k = 0; k < stepper_base_columns(sc); ++k) {
        names[stepper_column(sc) + k] = STEPPER_NAMES[k];
        units[stepper_column(sc) + k] = STEPPER_UNITS[k];
    }
    if (holds_bonds(sc)) {
        names[stepper_column(sc) + stepper_base_columns(sc)] = "broken bonds";
        units[stepper_column(sc) + stepper_base_columns(sc)] = "1";
    }
    if (insertion_columns(sc) > 0) {
        const size_t k = stepper_column(sc) + stepper_base_columns(sc) + (size_t)holds_bonds(sc);
        names[k] = "inserted mass";
        units[k] = "kg";
        names[k + 1] = "insertion target";
        units[k + 1] = "kg";
        /* a mixture's labels after the temperature histogram's */
        char(*ml)[SCENE_NAME + 16] = wall_labels + 3 * nw + distribution_columns(sc) +
                                     SCENE_MAX_TRACKED * SCENE_TRACK_COLUMNS +
                                     temperature_columns(sc);
        for (size_t m = 0; m < sc->insert_mixture; ++m) {
            snprintf(ml[m], sizeof(ml[m]), "inserted mass %s",
                     sc->material_names[sc->insert_materials[m]]);
            names[k + 2 + m] = ml[m];
            units[k + 2 + m] = "kg";
        }
    }
    names[solid_column(sc)] = "solid fraction";
    units[solid_column(sc)] = "1";
    for (size_t k = 0; k < distribution_columns(sc); ++k) {
        char *label = wall_labels[3 * nw + k];
        const size_t size = sizeof(wall_labels[0]);
        if (k < COORDINATION_MAX)
            snprintf(label, size, "coordination %zu", k);
        else if (k == COORDINATION_MAX)
            snprintf(label, size, "coordination %d or more", COORDINATION_MAX);
        else if (k - COORDINATION_MAX - 1 < NECK_BINS)
            snprintf(label, size, "neck ratio %.2f-%.2f",
                     NECK_BIN * (double)(k - COORDINATION_MAX - 1),
                     NECK_BIN * (double)(k - COORDINATION_MAX));
        else if (k - COORDINATION_MAX - 1 == NECK_BINS)
            snprintf(label, size, "neck ratio %.2f or more", NECK_BIN * NECK_BINS);
        else if (k - COORDINATION_MAX - 1 == NECK_BINS + 1)
            snprintf(label, size, "correction below %.2f", CORRECTION_LOW);
        else if (k - COORDINATION_MAX - 1 < NECK_BINS + 2 + CORRECTION_BINS) {
            const double b = (double)(k - COORDINATION_MAX - 1 - NECK_BINS - 2);
            snprintf(label, size, "correction %.2f to %.2f", CORRECTION_LOW + CORRECTION_BIN * b,
                     CORRECTION_LOW + CORRECTION_BIN * (b + 1));
        } else
            snprintf(label, size, "correction %.2f or more",
                     CORRECTION_LOW + CORRECTION_BIN * CORRECTION_BINS);
        names[distribution_column(sc) + k] = label;
        units[distribution_column(sc) + k] = "1";
    }
    (void)scene_track_labels(sc, names, units, wall_labels + 3 * nw + distribution_columns(sc),
                             track_column(sc));
    if (sc->pair_reference) {
        names[pair_column(sc)] = "two-particle neck ratio";
        names[pair_column(sc) + 1] = "two-particle shrinkage";
        units[pair_column(sc)] = units[pair_column(sc) + 1] = "1";
    }
    for (size_t k = 0; k < frozen_columns(sc); ++k) {
        names[frozen_column(sc) + k] = FROZEN_NAMES[k];
        units[frozen_column(sc) + k] = FROZEN_UNITS[k];
    }
    /* the temperature histogram's labels after the walls', histograms' and tracked ones */
    char(*tl)[SCENE_NAME + 16] =
        wall_labels + 3 * nw + distribution_columns(sc) + SCENE_MAX_TRACKED * SCENE_TRACK_COLUMNS;
    const size_t size = sizeof(wall_labels[0]);
    const double lo = sc->temperature_low, hi = sc->temperature_high;
    const double width = (hi - lo) / (double)(sc->temperature_bins ? sc->temperature_bins : 1);
    for (size_t k = 0; k < temperature_columns(sc); ++k) {
        if (k == 0)
            snprintf(tl[k], size, "temperature below %g", lo);
        else if (k == temperature_columns(sc) - 1)
            snprintf(tl[k], size, "temperature %g or more", hi);
        else
            snprintf(tl[k], size, "temperature %g-%g", lo + width * (double)(k - 1),
                     lo + width * (double)k);
        names[temperature_column(sc) + k] = tl[k];
        units[temperature_column(sc) + k] = "1";
    }
    if (lit_columns(sc) > 0) {
        names[lit_column(sc)] = "lit particles";
        names[lit_column(sc) + 1] = "lit mean temperature";
        units[lit_column(sc)] = "1";
        units[lit_column(sc) + 1] = "K";
    }
    static const char *const cell_names[CELL_COLUMNS] = {"cell x", "cell y", "cell z",
                                                         "volumetric strain"};
    for (size_t k = 0; k < cell_columns(sc); ++k) {
        names[cell_column(sc) + k] = cell_names[k];
        units[cell_column(sc) + k] = k < 3 ? "m" : "1";
    }
    return cell_column(sc) + cell_columns(sc);
}

/* The output directory made and writable, and the series opened in it: before the first step. */
static sinter_status open_output(run_state *r)
{
    sinter_scene *sc = r->sc;
    sinter_ctx *ctx = sc->ctx;
    char path[SINTER_PATH_SIZE];
    sinter_status st = make_dir(ctx, r->out_dir);
    if (st == SINTER_OK && sc->write_vtu)
        st = sinter_path_join(ctx, path, sizeof(path), r->out_dir, "frames");
    if (st == SINTER_OK && sc->write_vtu)
        st = make_dir(ctx, path);
    if (st == SINTER_OK)
        st = sinter_path_join(ctx, path, sizeof(path), r->out_dir, ".sinter_write_test");
    if (st == SINTER_OK) {
        FILE *probe = fopen(path, "wb");
        if (probe == NULL)
            return sinter_fail(ctx, SINTER_ERR_IO,
                               "the output directory '%s' cannot be written: %s", r->out_dir,
                               strerror(errno));
        fclose(probe);
        remove(path);
    }
    /* a restart's earlier frames: listed where they are in this directory */
    r->earlier = sc->write_vtu ? sc->program.frames : 0;
    r->present = sinter_calloc(ctx, (size_t)r->earlier + 1, 1);
    if (r->present == NULL)
        return sinter_last_status(ctx);
    for (uint64_t k = 0; k < r->earlier && st == SINTER_OK; ++k) {
        char rel[64];
        struct stat info;
        snprintf(rel, sizeof(rel), "frames/frame_%05llu.vtu", (unsigned long long)k);
        st = sinter_path_join(ctx, path, sizeof(path), r->out_dir, rel);
        r->present[k] = st == SINTER_OK && stat(path, &info) == 0;
    }
    enum {
        HISTOGRAMS = COORDINATION_MAX + 1 + NECK_BINS + 1 + CORRECTION_BINS + 2,
        TRACKED = SCENE_MAX_TRACKED * SCENE_TRACK_COLUMNS,
        TEMPERATURES = SCENE_MAX_TEMPERATURE_BINS + 2,
        MOST = COL_FIXED_ + 3 * SCENE_MAX_WALLS + SINTERING_COLUMNS + ELECTRIC_COLUMNS +
               STEPPER_COLUMNS + 1 + HISTOGRAMS + TRACKED + SCENE_PAIR_COLUMNS + FROZEN_COLUMNS +
               TEMPERATURES + LIT_COLUMNS + CELL_COLUMNS /* 1: the solid fraction */ + 2 +
               SCENE_MAX_MATERIALS
    }; /* 2 + SCENE_MAX_MATERIALS: the insertion's */
    const char *names[MOST];
    const char *units[MOST];
    /* the walls' labels, then the histograms', then the followed particles' */
    char wall_labels[3 * SCENE_MAX_WALLS + HISTOGRAMS + TRACKED + TEMPERATURES +
                     SCENE_MAX_MATERIALS][SCENE_NAME + 16];
    const size_t ncol = columns(sc, names, units, wall_labels);
    r->row = sinter_calloc(ctx, ncol, sizeof(double));
    if (r->row == NULL)
        return sinter_last_status(ctx);
    if (st == SINTER_OK)
        st = sinter_series_create(&r->series, ctx, ncol, names, units);
    if (st == SINTER_OK)
        st = sinter_path_join(ctx, r->csv_path, sizeof(r->csv_path), r->out_dir, "series.csv");
    if (st == SINTER_OK && sc->write_csv) {
        int kept = 0;
        st = sinter_csv_stream_open(&r->csv, ctx, r->csv_path, r->series, sc->program.rows, &kept);
        if (st == SINTER_OK && sc->program.rows > 0 && !kept)
            sinter_log(ctx, SINTER_LOG_INFO,
                       "restart: '%s' does not hold the %llu samples written before the "
                       "checkpoint; it starts again from the restart",
                       r->csv_path, (unsigned long long)sc->program.rows);
    }
    return st;
}

sinter_status sinter_scene_run(sinter_scene *sc, const char *out_dir, sinter_progress_fn progress,
                               void *user)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = sc->ctx;
    SINTER_CHECK_NULL(ctx, out_dir);
    run_state r;
    memset(&r, 0, sizeof(r));
    r.sc = sc;
    r.out_dir = out_dir;
    sinter_status st = open_output(&r);
    const int fresh = sc->program.phase == SCENE_PHASE_NONE;
    if (st == SINTER_OK && fresh)
        st = begin(&r);
    if (st == SINTER_OK)
        st = run_program(&r, progress, user);
    /* Stopped on request, or at the end: a checkpoint to continue from. */
    if ((st == SINTER_ERR_INTERRUPTED && sc->program.phase != SCENE_PHASE_NONE) ||
        (st == SINTER_OK && sc->checkpoint_interval > 0.0)) {
        char message[SINTER_ERROR_TEXT_SIZE];
        snprintf(message, sizeof(message), "%s", sinter_last_error(ctx));
        const sinter_status written = checkpoint(&r);
        if (st == SINTER_OK)
            st = written;
        else if (written == SINTER_OK)
            sinter_fail(ctx, st, "%s", message); /* the interruption's message stands */
    }
    /* Whatever happened, close the series and draw what was recorded (the last good state). */
    if (sc->write_csv) {
        const sinter_status closed = sinter_csv_stream_close(&r.csv);
        if (st == SINTER_OK)
            st = closed;
    }
    if (r.series != NULL && sc->program.rows > 0) {
        char message[SINTER_ERROR_TEXT_SIZE];
        snprintf(message, sizeof(message), "%s", sinter_last_error(ctx));
        const sinter_status drawn = write_plot(&r);
        if (st == SINTER_OK)
            st = drawn;
        else
            sinter_fail(ctx, st, "%s", message); /* the run's own error stands */
    }
    sinter_series_destroy(r.series);
    sinter_free(ctx, r.row);
    sinter_free(ctx, r.present);
    return st;
}
