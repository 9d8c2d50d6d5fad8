#define _POSIX_C_SOURCE 200809L
/*
 * `mpiexec -n N sinter run SCENE [-o DIR] [--end-time T] [--stop-at T] [--restart CHECKPOINT]
 * [--progress S] [--log LEVEL]` in the MPI build (issue 44): the scene on N ranks through
 * libsinter_mpi.
 *
 * Every rank reads the scene file; rank 0 keeps the particles the scene made (compacted there
 * first by the scene's [compact] section, sinter_scene_compact, as the serial set-up does), the
 * others give theirs up, and sinter_mpi_attach + sinter_mpi_distribute spread them over a
 * brick of rank 0's particles' bounding box. The run then follows `sinter run`'s programme: the
 * state at the start with its forces (a step of 0), a sample, then sinter_stepper_advance to
 * each next sample (the current time plus the output interval) until the end time. With a
 * [pour] (run_mpi_pour.c) the walls are held after the first sample, the pour ends at the
 * first sample, after t_min, whose kinetic energy per particle over all ranks is below
 * ke_per_particle (the same decision on every rank), the walls' motions start then, and the end
 * time counts from then; a pour not at rest by t_max fails on every rank. Output:
 *  - series.csv from rank 0, the serial runner's columns, each through a reduction: every
 *    rank's partial sum in index order, then the ranks' partials summed exactly
 *    (sinter_mpi_reduce), so that one rank gives the serial bits; the wall heat flows, the
 *    network model's wall currents and the solid fraction's lenses from each rank's
 *    snapshot (sinter_snapshot_create), as the serial runner sums them (an [output]
 *    solid_box's sampled fraction is nan: not formed yet), and the contacts from them too,
 *    each pair once (the owner of its smaller id);
 *  - per sample one VTU piece per rank (frames/frame_NNNNN_rRRRR.vtu, its owned particles),
 *    an index frames/frame_NNNNN.pvtu and the collection NAME.pvd, from rank 0;
 *  - checkpoint.mpi through MPI-IO (sinter_mpi_checkpoint_write) at the [output]
 *    checkpoint_interval, at the end and at --stop-at's sample, which --restart reads on any
 *    number of ranks (sinter_mpi_checkpoint_read); series.csv and the frames then continue
 *    (with a pour, where it stood travels beside it in checkpoint.mpi.pour).
 * The explicit and staggered steppers (the staggered one's series has its columns and, with an
 * [electric] section, the particle currents, as the serial series), the quasi-static one
 * (run_mpi_qs.c: the sintering columns from the collective statistics; the contacts, the
 * coordination number and the solid fraction's lenses from the links, each held once by the
 * rank that owns its smaller id; its checkpoint carries the links in the records of their
 * smaller ids and its first step's extents in the global part); beam heat sources, the frozen
 * heat stage (run_mpi_heat.h), [insert] (run_mpi_insert.h), [fields] (run_mpi_fields.h:
 * the grid's and the laminae's sums over the ranks, each pair once, the ratios and the files on
 * rank 0) and bonds that hold in tension (run_mpi_bonds.h: the broken bonds, each counted
 * once). Refused, with the reason on every rank and exit status 1: [fields] with
 * vtu_format = appended, a [pour] with a [stepper]
 * temperature_schedule (the serial runner delays that furnace to the pour's end through an
 * internal call) or followed by a [compact], and what sinter_stepper_set_domain_ops refuses
 * (periodic axes, so copper_rve.scene; an electric model with host callbacks, qs_strategy 1,
 * sort_interval). Messages and progress come from rank 0 only.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <sinter.h>
#include <sinter_domain.h>
#include <sinter_mpi.h>

#include "core/id_row.h"
#include "core/make_dirs.h"
#include "core/sphere_volume.h"
#include "cli.h"
#include "run_mpi_pour.h"
#include "run_mpi_qs.h"
#include "run_mpi_heat.h"
#include "run_mpi_insert.h"
#include "run_mpi_fields.h"
#include "run_mpi_bonds.h"
#include "trim_line.h"

enum { MAX_WALLS = 64, NAME_SIZE = 128, PATH_SIZE = 4096 };

/* The scene file's facts the library does not tell: its name, its walls' names in order and
 * the sections the MPI runner refuses. */
typedef struct scene_facts {
    char name[NAME_SIZE];
    char walls[MAX_WALLS][NAME_SIZE];
    size_t wall_count;
    char refused[NAME_SIZE];    /* the first refused section, "" if none */
    int heat;                   /* a [heat conduction] section: the wall heat-flow columns */
    int solid_box;              /* [output] solid_box: the solid fraction sampled in a box */
    int electric;               /* an [electric ...] section: the particle-current columns */
    int network;                /* [electric network]: the wall current columns */
    int staggered;              /* [stepper] kind = staggered: its three more stepper columns */
    int quasistatic;            /* [stepper] kind = quasistatic: the sintering columns */
    int compact;                /* a [compact] section: compacted on rank 0 before spreading */
    run_mpi_heat_spec heat_out; /* the heat stage's columns (run_mpi_heat.h) */
    int insert;                 /* an [insert] section: its two columns (run_mpi_insert.h) */
    run_mpi_fields fields;      /* [fields]: its files with every frame (run_mpi_fields.h) */
    int bonds;                  /* bonds that hold in tension: "broken bonds" (run_mpi_bonds.h) */
} scene_facts;

/* Copy src into dst of `size` bytes, cut short where it does not fit. */
static void copy(char *dst, size_t size, const char *src)
{
    const size_t n = strlen(src) < size - 1 ? strlen(src) : size - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

/* 1 for a key line of a section whose output the MPI runner does not write yet: the series
 * columns of [output] distributions, track, pair_reference, the frames' extra
 * files (contacts, walls). */
static int refused_key(const char *section, const char *line)
{
    static const char *const keys[][2] = {{"output", "distributions"},  {"output", "track"},
                                          {"output", "pair_reference"}, {"output", "contacts"},
                                          {"output", "walls"},          {"insert", "materials"}};
    const char *eq = strchr(line, '=');
    if (eq == NULL)
        return 0;
    char key[NAME_SIZE], value[NAME_SIZE];
    copy(key, sizeof(key), line);
    key[eq - line < NAME_SIZE ? eq - line : NAME_SIZE - 1] = '\0';
    trim(key);
    copy(value, sizeof(value), eq + 1);
    trim(value);
    for (size_t k = 0; k < sizeof(keys) / sizeof(keys[0]); ++k)
        if (strcmp(section, keys[k][0]) == 0 && strcmp(key, keys[k][1]) == 0)
            return strcmp(value, "no") != 0 && strcmp(value, "none") != 0;
    return 0;
}

static int read_facts(const char *path, scene_facts *f)
{
    memset(f, 0, sizeof(*f));
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return 0;
    char line[1024], section[NAME_SIZE] = "";
    while (fgets(line, sizeof(line), fp) != NULL) {
        char *hash = strchr(line, '#');
        if (hash != NULL)
            *hash = '\0';
        trim(line);
        if (line[0] == '[') {
            char *end = strchr(line, ']');
            if (end == NULL)
                continue;
            *end = '\0';
            copy(section, sizeof(section), line + 1);
            trim(section);
            if (strncmp(section, "wall ", 5) == 0 && f->wall_count < MAX_WALLS) {
                copy(f->walls[f->wall_count], NAME_SIZE, section + 5);
                trim(f->walls[f->wall_count++]);
            }
            if (strncmp(section, "heat conduction", 15) == 0)
                f->heat = 1;
            if (strncmp(section, "electric", 8) == 0)
                f->electric = 1;
            if (strcmp(section, "electric network") == 0)
                f->network = 1;
            if (strcmp(section, "compact") == 0)
                f->compact = 1;
            if (strncmp(section, "heat laser", 10) == 0 ||
                strncmp(section, "heat nozzle", 11) == 0 || strncmp(section, "heat beam", 9) == 0)
                f->heat_out.beam = 1; /* (across ranks since issue 43: run_mpi_heat.h) */
            f->insert |= strcmp(section, "insert") == 0;
        } else if (strcmp(section, "stepper") == 0 && strncmp(line, "kind", 4) == 0 &&
                   strstr(line, "quasistatic") != NULL) {
            f->quasistatic = 1; /* its sintering columns (run_mpi_qs.c) */
        } else if (run_mpi_bonds_key(section, line)) {
            f->bonds = 1;
        } else if (f->refused[0] == '\0' && refused_key(section, line)) {
            snprintf(f->refused, sizeof(f->refused), "[%.50s] %.60s", section, line);
        } else if (strcmp(section, "stepper") == 0 && strncmp(line, "kind", 4) == 0 &&
                   strstr(line, "staggered") != NULL) {
            f->staggered = 1;
        } else if (strcmp(section, "output") == 0 && strncmp(line, "solid_box", 9) == 0) {
            f->solid_box = 1;
        } else if (strcmp(section, "scene") == 0 && strncmp(line, "name", 4) == 0) {
            char *eq = strchr(line, '=');
            if (eq != NULL) {
                copy(f->name, sizeof(f->name), eq + 1);
                trim(f->name);
            }
        }
    }
    fclose(fp);
    run_mpi_heat_read(path, &f->heat_out);
    run_mpi_fields_read(path, &f->fields);
    if (f->refused[0] == '\0' && f->fields.on && f->fields.appended)
        snprintf(f->refused, sizeof(f->refused), "[fields] with [output] vtu_format = appended");
    if (f->name[0] == '\0')
        snprintf(f->name, sizeof(f->name), "scene");
    return 1;
}

typedef struct mpi_run {
    int rank, size;
    sinter_ctx *ctx;
    sinter_scene *scene;
    sinter_stepper *st;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_mpi_domain *domain;
    MPI_Comm comm;
    scene_facts facts;
    const char *out_dir;
    FILE *csv;
    uint64_t frame;      /* the next frame's number */
    double *frame_times; /* the frames' times so far (room for frame_room) */
    size_t frame_room;
    mpi_pour pour;        /* [pour] (run_mpi_pour.c) */
    int log_level;        /* --log: rank 0 prints messages up to it (-1: none) */
    int64_t bonds_offset; /* added to the broken bonds after a restart (run_mpi_bonds.h) */
} mpi_run;

/* Every rank's error as one: the lowest failing status (0 when none failed). */
static int agree(MPI_Comm comm, int status)
{
    int worst = status;
    MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MIN, comm);
    return worst;
}

static int make_dir(const char *path)
{
    char partial[PATH_SIZE];
    return sinter_make_dirs(path, partial, sizeof(partial)) == 0;
}

static const double PI = 3.14159265358979323846;

/* The owned particles' sums and extremes (scene_run.c's observe(): index order). */
typedef struct observed {
    double sum[5]; /* kinetic energy, temperatures, sphere volumes, owned count, |currents| */
    double max[9]; /* bed top, max temperature, box hi (3), -box lo (3), largest |current| */
} observed;

static int observe_local(const mpi_run *r, observed *o)
{
    static const sinter_field fields[] = {
        SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,       SINTER_FIELD_RADIUS,
        SINTER_FIELD_MASS,     SINTER_FIELD_INERTIA,  SINTER_FIELD_TEMPERATURE};
    enum { FIELDS = sizeof(fields) / sizeof(fields[0]) };
    const double *a[FIELDS] = {NULL};
    int ok = 1;
    size_t got = 0;
    for (; got < FIELDS && ok; ++got)
        ok = sinter_particles_view_read(r->ps, fields[got], (const void **)&a[got], NULL, NULL) ==
             SINTER_OK;
    size_t owned = 0;
    ok = ok && sinter_particles_owned_count(r->ps, &owned) == SINTER_OK;
    const double *x = a[0], *v = a[1], *w = a[2], *rad = a[3], *m = a[4], *j = a[5], *t = a[6];
    double ke = 0, top = -INFINITY, tsum = 0, tmax = -INFINITY, solid = 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; ok && i < owned; ++i) {
        const double *vi = v + 3 * i, *wi = w + 3 * i;
        ke += 0.5 * m[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]) +
              0.5 * j[i] * (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]);
        top = fmax(top, x[3 * i + 2] + rad[i]);
        tsum += t[i];
        tmax = fmax(tmax, t[i]);
        solid += 4.0 / 3.0 * PI * rad[i] * rad[i] * rad[i];
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], x[3 * i + d] - rad[i]);
            hi[d] = fmax(hi[d], x[3 * i + d] + rad[i]);
        }
    }
    for (size_t k = 0; k < got; ++k)
        if (a[k] != NULL)
            sinter_particles_release(r->ps, fields[k]);
    /* the particles' current magnitudes (seed 000 sec. 7), as the serial series has them */
    double isum = 0.0, imax = 0.0;
    const double *c = NULL;
    if (ok && r->facts.electric && owned > 0) {
        ok = sinter_particles_view_read(r->ps, SINTER_FIELD_CURRENT, (const void **)&c, NULL,
                                        NULL) == SINTER_OK;
        for (size_t i = 0; ok && i < owned; ++i) {
            isum += fabs(c[i]);
            imax = fmax(imax, fabs(c[i]));
        }
        if (ok)
            sinter_particles_release(r->ps, SINTER_FIELD_CURRENT);
    }
    const double sum[5] = {ke, tsum, solid, (double)owned, isum};
    const double max[9] = {top, tmax, hi[0], hi[1], hi[2], -lo[0], -lo[1], -lo[2], imax};
    memcpy(o->sum, sum, sizeof(sum));
    memcpy(o->max, max, sizeof(max));
    return ok;
}

/* The box of the volume fraction, as scene_run.c's fraction_box for plane walls: each axis
 * bounded by the axis-aligned walls facing each other, else by the spheres' extent; the top is
 * the lower of the top wall and the bed's top. 0 when a wall is not a plane (not formed yet). */
static int fraction_box(const mpi_run *r, double top, double lo[3], double hi[3])
{
    size_t n = 0;
    sinter_walls_count(r->walls, &n);
    hi[2] = top;
    for (size_t k = 0; k < n; ++k) {
        int kind = -1;
        double p[3], vel[3], nrm[3];
        if (sinter_walls_get_kind(r->walls, k, &kind) != SINTER_OK || kind != SINTER_WALL_PLANE ||
            sinter_walls_get_state(r->walls, k, p, vel) != SINTER_OK ||
            sinter_walls_get_normal(r->walls, k, nrm) != SINTER_OK)
            return 0;
        for (int d = 0; d < 3; ++d) {
            if (fabs(nrm[d]) < 1.0 - 1e-12)
                continue;
            if (nrm[d] > 0)
                lo[d] = fmax(lo[d] == INFINITY ? p[d] : lo[d], p[d]);
            else
                hi[d] = fmin(hi[d], p[d]);
        }
    }
    return 1;
}

/* The heat flow from each wall into the particles [W] (a conduction model; `data`
 * SINTER_CONTACT_DATA_HEAT_FLOW, sign 1) or the current from the particles into each wall [A]
 * (the network model; SINTER_CONTACT_DATA_CURRENT, sign -1): this rank's wall contacts in the
 * stepper's order (those of a public snapshot, as the serial runner sums them), summed over
 * the ranks; nan where no snapshot can be taken. Collective. */
static int wall_flows(mpi_run *r, sinter_contact_data data, double sign, double *flow)
{
    const size_t nw = r->facts.wall_count;
    double local[MAX_WALLS + 1];
    memset(local, 0, sizeof(local));
    sinter_snapshot *snap = NULL;
    const double *heat = NULL;
    const int32_t *wall = NULL;
    size_t pairs = 0, walls = 0;
    int ok =
        sinter_snapshot_create(&snap, r->st) == SINTER_OK &&
        sinter_snapshot_counts(snap, &pairs, &walls, NULL, NULL) == SINTER_OK &&
        sinter_snapshot_contacts(snap, data, (const void **)&heat, NULL, NULL, NULL) == SINTER_OK &&
        sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_WALL, (const void **)&wall, NULL, NULL,
                                 NULL) == SINTER_OK;
    for (size_t q = pairs; ok && q < pairs + walls; ++q)
        if (wall[q] >= 0 && (size_t)wall[q] < nw)
            local[wall[q]] += sign * heat[q]; /* heat into the particle, current out */
    sinter_snapshot_destroy(snap);
    local[nw] = ok ? 0.0 : 1.0; /* ranks without a snapshot */
    if (sinter_mpi_reduce(local, nw + 1, SINTER_MPI_F64, SINTER_MPI_SUM, r->domain) != 0)
        return 0;
    for (size_t k = 0; k < nw; ++k)
        flow[k] = local[nw] == 0.0 ? local[k] : NAN;
    return 1;
}

static int row_of(const sinter_id_row *table, size_t n, uint64_t id, size_t *index)
{
    const sinter_id_row key = {id, 0};
    const sinter_id_row *hit =
        bsearch(&key, table, n, sizeof(sinter_id_row), sinter_id_row_compare);
    if (hit != NULL)
        *index = hit->index;
    return hit != NULL;
}

/*
 * This rank's share of the spheres' union inside the box (the serial series' "solid
 * fraction" times the box): its owned spheres less their caps beyond the box's faces, in
 * index order, then less the lens of each overlapping pair of its snapshot in the contact
 * list's order (the neighbour list's order of the overlapping pairs, which the serial runner
 * follows; pairs that do not overlap subtract nothing). A pair with a ghost end is listed on
 * both ranks: the rank that owns its smaller id subtracts it. 0 without a snapshot.
 */
static int solid_volume(const mpi_run *r, const double lo[3], const double hi[3], double *out,
                        double *contacts)
{
    const double *x = NULL, *rad = NULL;
    const uint64_t *id = NULL;
    size_t owned = 0, rows = 0;
    int ok = sinter_particles_owned_count(r->ps, &owned) == SINTER_OK;
    ok = ok && sinter_particles_view_read(r->ps, SINTER_FIELD_ID, (const void **)&id, &rows,
                                          NULL) == SINTER_OK;
    sinter_id_row *table = ok ? malloc((rows + 1) * sizeof(sinter_id_row)) : NULL;
    ok = ok && table != NULL;
    for (size_t i = 0; ok && i < rows; ++i) {
        table[i].id = id[i];
        table[i].index = i;
    }
    if (ok)
        qsort(table, rows, sizeof(sinter_id_row), sinter_id_row_compare);
    ok = ok && sinter_particles_view_read(r->ps, SINTER_FIELD_POSITION, (const void **)&x, NULL,
                                          NULL) == SINTER_OK;
    ok = ok && sinter_particles_view_read(r->ps, SINTER_FIELD_RADIUS, (const void **)&rad, NULL,
                                          NULL) == SINTER_OK;
    double volume = 0.0;
    for (size_t i = 0; ok && i < owned; ++i) {
        const double ri = rad[i], *xi = x + 3 * i;
        volume += 4.0 / 3.0 * PI * ri * ri * ri;
        for (int d = 0; d < 3; ++d)
            volume -= sinter_sphere_cap_volume(ri, xi[d] - lo[d]) +
                      sinter_sphere_cap_volume(ri, hi[d] - xi[d]);
    }
    if (r->facts.quasistatic) /* its links instead of contacts (run_mpi_qs.c) */
        ok = ok && cli_mpi_qs_lenses(r->st, table, rows, owned, x, rad, &volume, contacts);
    sinter_snapshot *snap = NULL;
    const uint64_t *ida = NULL, *idb = NULL;
    size_t pairs = 0;
    ok = ok && (r->facts.quasistatic ||
                (sinter_snapshot_create(&snap, r->st) == SINTER_OK &&
                 sinter_snapshot_counts(snap, &pairs, NULL, NULL, NULL) == SINTER_OK &&
                 sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_A, (const void **)&ida, NULL,
                                          NULL, NULL) == SINTER_OK &&
                 sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_ID_B, (const void **)&idb, NULL,
                                          NULL, NULL) == SINTER_OK));
    for (size_t k = 0; ok && k < pairs; ++k) {
        size_t i = 0, j = 0;
        ok = row_of(table, rows, ida[k], &i) && row_of(table, rows, idb[k], &j);
        if (!ok || (ida[k] < idb[k] ? i : j) >= owned)
            continue; /* the other rank owns the smaller id */
        *contacts += 1.0;
        const double *a = x + 3 * i, *b = x + 3 * j;
        const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        volume -= sinter_sphere_lens_volume(rad[i], rad[j], sqrt(dx * dx + dy * dy + dz * dz));
    }
    sinter_snapshot_destroy(snap);
    free(table);
    if (id != NULL)
        sinter_particles_release(r->ps, SINTER_FIELD_ID);
    if (x != NULL)
        sinter_particles_release(r->ps, SINTER_FIELD_POSITION);
    if (rad != NULL)
        sinter_particles_release(r->ps, SINTER_FIELD_RADIUS);
    *out = volume;
    return ok;
}

/* One series row on every rank (collective); 0 on a failed view or reduction. */
static int observe(mpi_run *r, double *row, size_t columns)
{
    observed o;
    int ok = observe_local(r, &o);
    ok = agree(r->comm, ok ? 0 : -1) == 0;
    /* each rank's partial sums, summed exactly: one rank keeps its own bits */
    ok = ok && sinter_mpi_reduce(o.sum, 5, SINTER_MPI_F64, SINTER_MPI_SUM, r->domain) == 0;
    ok = ok && sinter_mpi_reduce(o.max, 9, SINTER_MPI_F64, SINTER_MPI_MAX, r->domain) == 0;
    sinter_stepper_stats local, global;
    memset(&local, 0, sizeof(local));
    memset(&global, 0, sizeof(global));
    local.struct_size = global.struct_size = sizeof(local);
    ok = ok && sinter_stepper_get_stats(r->st, &local) == SINTER_OK;
    ok = ok && sinter_stepper_get_stats_global(r->st, &global) == SINTER_OK;
    if (!ok)
        return 0;
    const double n = o.sum[3] > 0 ? o.sum[3] : 1.0;
    const size_t solid_col = columns - 1 - run_mpi_heat_columns(r->st, &r->facts.heat_out);
    double t = 0.0;
    sinter_stepper_time(r->st, &t);
    for (size_t k = 0; k < columns; ++k)
        row[k] = NAN;
    row[0] = t;
    row[1] = o.sum[0];
    row[2] = (double)global.contacts; /* without a snapshot: a border pair on both sides */
    row[3] = 2.0 * (double)global.contacts / n;
    row[4] = o.max[0];
    double lo[3] = {-o.max[5], -o.max[6], -o.max[7]}, hi[3] = {o.max[2], o.max[3], o.max[4]};
    if (fraction_box(r, o.max[0], lo, hi)) {
        const double volume = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
        row[5] = volume > 0 ? o.sum[2] / volume : NAN;
        /* the solid fraction in the same box ([output] solid_box: nan, not formed yet) */
        double solid[3] = {0.0, 0.0, 0.0}; /* volume, ranks without a snapshot, contacts */
        solid[1] = solid_volume(r, lo, hi, &solid[0], &solid[2]) ? 0.0 : 1.0;
        if (sinter_mpi_reduce(solid, 3, SINTER_MPI_F64, SINTER_MPI_SUM, r->domain) != 0)
            return 0;
        if (solid[1] == 0.0 && !r->facts.solid_box)
            row[solid_col] = volume > 0 ? solid[0] / volume : NAN;
        if (solid[1] == 0.0) { /* each contact once, also those across a border */
            row[2] = solid[2];
            row[3] = 2.0 * solid[2] / n;
        }
    }
    row[6] = o.sum[1] / n;
    row[7] = o.max[1];
    const size_t nw = r->facts.wall_count;
    for (size_t k = 0; k < nw; ++k) {
        double f[3] = {0, 0, 0}, nrm[3] = {0, 0, 0};
        sinter_walls_get_force(r->walls, k, f); /* the total over the ranks */
        sinter_walls_get_normal(r->walls, k, nrm);
        row[8 + k] = -(f[0] * nrm[0] + f[1] * nrm[1] + f[2] * nrm[2]);
    }
    /* the quasi-static stepper's sintering columns (run_mpi_qs.c) */
    const size_t nq = r->facts.quasistatic ? CLI_MPI_QS_COLUMNS : 0;
    const double box_lo[3] = {-o.max[5], -o.max[6], -o.max[7]},
                 box_hi[3] = {o.max[2], o.max[3], o.max[4]};
    if (nq > 0 && !cli_mpi_qs_sintering(r->st, o.sum[2], box_lo, box_hi, row + 8 + nw))
        return 0;
    const size_t ne = r->facts.electric ? 2 : 0;
    if (ne > 0) {
        row[8 + nw + nq] = o.sum[4] / n;
        row[8 + nw + nq + 1] = o.max[8];
    }
    const size_t nh = r->facts.heat ? nw : 0;
    if (r->facts.heat && !wall_flows(r, SINTER_CONTACT_DATA_HEAT_FLOW, 1.0, row + 8 + nw + nq + ne))
        return 0;
    if (r->facts.network &&
        !wall_flows(r, SINTER_CONTACT_DATA_CURRENT, -1.0, row + 8 + nw + nq + ne + nh))
        return 0;
    size_t c = 8 + nw + nq + ne + nh + (r->facts.network ? nw : 0);
    row[c] = global.dt;
    row[c + 1] = (double)local.rejected;        /* decided together: equal on every rank */
    row[c + 2] = (double)local.neighbor_builds; /* likewise */
    if (r->facts.staggered) {                   /* likewise (reduced norms and decisions) */
        row[c + 3] = (double)local.iterations;
        row[c + 4] = (double)local.evaluations;
        row[c + 5] = local.contraction;
    }
    c += r->facts.staggered ? 6 : 3;
    if (r->facts.bonds) /* each bond once: counted by the owner of its smaller id */
        row[c++] = (double)((int64_t)global.bonds_broken + r->bonds_offset);
    if (r->facts.insert && !run_mpi_insert_observe(r->st, row + c))
        return 0;
    return run_mpi_heat_observe(r->st, &r->facts.heat_out, r->ps, r->domain, row + solid_col + 1);
}

static size_t column_count(const mpi_run *r)
{
    const size_t nw = r->facts.wall_count;
    return 8 + nw + (r->facts.quasistatic ? CLI_MPI_QS_COLUMNS : 0) + (r->facts.electric ? 2 : 0) +
           (r->facts.heat ? nw : 0) + (r->facts.network ? nw : 0) + (r->facts.staggered ? 6 : 3) +
           (size_t)r->facts.bonds + (r->facts.insert ? RUN_MPI_INSERT_COLUMNS : 0) + 1 +
           run_mpi_heat_columns(r->st, &r->facts.heat_out);
}

/* The header line, as the serial series.csv's. */
static void write_header(mpi_run *r)
{
    static const char *const fixed[] = {
        "time [s]",    "kinetic energy [J]",  "contacts [1]",         "coordination number [1]",
        "bed top [m]", "volume fraction [1]", "mean temperature [K]", "max temperature [K]"};
    for (size_t k = 0; k < 8; ++k)
        fprintf(r->csv, "%s%s", k ? "," : "", fixed[k]);
    for (size_t k = 0; k < r->facts.wall_count; ++k)
        fprintf(r->csv, ",%s force [N]", r->facts.walls[k]);
    if (r->facts.quasistatic)
        cli_mpi_qs_header(r->csv);
    if (r->facts.electric)
        fputs(",mean particle current [A],max particle current [A]", r->csv);
    for (size_t k = 0; r->facts.heat && k < r->facts.wall_count; ++k)
        fprintf(r->csv, ",%s heat flow [W]", r->facts.walls[k]);
    for (size_t k = 0; r->facts.network && k < r->facts.wall_count; ++k)
        fprintf(r->csv, ",%s current [A]", r->facts.walls[k]);
    fputs(",time step [s],rejected steps [1],neighbour rebuilds [1]", r->csv);
    if (r->facts.staggered)
        fputs(",fixed-point iterations [1],pipeline evaluations [1],contraction [1]", r->csv);
    if (r->facts.bonds)
        run_mpi_bonds_header(r->csv);
    if (r->facts.insert)
        run_mpi_insert_header(r->csv);
    fputs(",solid fraction [1]", r->csv);
    run_mpi_heat_header(r->csv, r->st, &r->facts.heat_out);
    fputc('\n', r->csv);
}

static void write_row(mpi_run *r, const double *row, size_t columns)
{
    for (size_t k = 0; k < columns; ++k) {
        if (k)
            fputc(',', r->csv);
        if (isnan(row[k]))
            fputs("nan", r->csv);
        else
            fprintf(r->csv, "%.17g", row[k]);
    }
    fputc('\n', r->csv);
    fflush(r->csv);
}

/* Record frame k's time [s], growing the list; 0 when out of memory. */
static int frame_time(mpi_run *r, uint64_t k, double time)
{
    if (k >= r->frame_room) {
        size_t room = r->frame_room ? 2 * r->frame_room : 256;
        while (room <= k)
            room *= 2;
        double *grown = realloc(r->frame_times, room * sizeof(double));
        if (grown == NULL)
            return 0;
        r->frame_times = grown;
        r->frame_room = room;
    }
    r->frame_times[k] = time;
    return 1;
}

/* The piece of this rank, then (rank 0) the frame's .pvtu and the collection. */
static int write_frame(mpi_run *r, double time)
{
    char path[PATH_SIZE];
    snprintf(path, sizeof(path), "%s/frames/frame_%05llu_r%04d.vtu", r->out_dir,
             (unsigned long long)r->frame, r->rank);
    int ok = sinter_write_vtu(r->ps, path, NULL, 0) == SINTER_OK;
    if (!frame_time(r, r->frame, time))
        ok = 0;
    if (r->rank == 0 && ok) {
        snprintf(path, sizeof(path), "%s/frames/frame_%05llu.pvtu", r->out_dir,
                 (unsigned long long)r->frame);
        FILE *fp = fopen(path, "w");
        ok = fp != NULL;
        if (fp != NULL) {
            static const char *const arrays[][3] = {
                {"Float64", "radius", "1"},  {"Float64", "velocity", "3"},
                {"Float64", "spin", "3"},    {"Float64", "temperature", "1"},
                {"Float64", "current", "1"}, {"Float64", "force", "3"},
                {"Int32", "material", "1"},  {"UInt64", "id", "1"}};
            fputs("<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" "
                  "byte_order=\"LittleEndian\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n"
                  "    <PPointData Scalars=\"radius\">\n",
                  fp);
            for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); ++k)
                fprintf(fp,
                        "      <PDataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%s\"/>\n",
                        arrays[k][0], arrays[k][1], arrays[k][2]);
            fputs("    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" "
                  "Name=\"position\" NumberOfComponents=\"3\"/>\n    </PPoints>\n",
                  fp);
            for (int q = 0; q < r->size; ++q)
                fprintf(fp, "    <Piece Source=\"frame_%05llu_r%04d.vtu\"/>\n",
                        (unsigned long long)r->frame, q);
            fputs("  </PUnstructuredGrid>\n</VTKFile>\n", fp);
            ok = fclose(fp) == 0;
        }
        const size_t frames = (size_t)r->frame + 1;
        char **files = calloc(frames, sizeof(char *));
        ok = ok && files != NULL;
        for (size_t k = 0; ok && k < frames; ++k) {
            files[k] = malloc(64);
            ok = files[k] != NULL;
            if (ok)
                snprintf(files[k], 64, "frames/frame_%05zu.pvtu", k);
        }
        snprintf(path, sizeof(path), "%s/%s.pvd", r->out_dir, r->facts.name);
        ok = ok && sinter_write_pvd(r->ctx, path, frames, r->frame_times,
                                    (const char *const *)files) == SINTER_OK;
        for (size_t k = 0; files != NULL && k < frames; ++k)
            free(files[k]);
        free(files);
    }
    r->frame++;
    return ok;
}

/* Rank 0, at a restart: keep the header and the rows of series.csv up to the time t of the
 * checkpoint (their times are the frames'), drop later ones; the rows kept, -1 without a file. */
static long long resume_series(mpi_run *r, double t)
{
    char path[PATH_SIZE], tmp[PATH_SIZE + 8];
    snprintf(path, sizeof(path), "%s/series.csv", r->out_dir);
    snprintf(tmp, sizeof(tmp), "%s.tmp", path);
    FILE *in = fopen(path, "r");
    if (in == NULL)
        return -1;
    FILE *out = fopen(tmp, "w");
    if (out == NULL) {
        fclose(in);
        return -1;
    }
    static char line[1 << 16];
    long long rows = 0;
    for (int first = 1; fgets(line, sizeof(line), in) != NULL; first = 0) {
        const double time = first ? 0.0 : strtod(line, NULL);
        if (!first && (time > t + 1e-12 * fabs(t) || strchr(line, '\n') == NULL))
            break;
        fputs(line, out);
        if (!first && !frame_time(r, (uint64_t)rows++, time)) {
            rows = -1;
            break;
        }
    }
    fclose(in);
    if (fclose(out) != 0 || rename(tmp, path) != 0)
        return -1;
    return rows;
}

/* One sample: the row (rank 0 writes it) and the frame. Collective. */
static int record(mpi_run *r, double *row, size_t columns)
{
    if (!observe(r, row, columns))
        return 0;
    int ok = 1;
    if (r->rank == 0)
        write_row(r, row, columns);
    ok = run_mpi_fields_write(&r->facts.fields, r->ctx, r->st, r->ps, r->domain, r->rank,
                              r->out_dir, (unsigned long long)r->frame);
    ok = write_frame(r, row[0]) && ok;
    return agree(r->comm, ok ? 0 : -1) == 0;
}

/* The MPI checkpoint and, with a pour, its state beside it (rank 0). Collective. */
static sinter_status write_checkpoint(mpi_run *r, const char *path, int *frozen_skip)
{
    sinter_status st = run_mpi_heat_checkpoint(r->st, r->ps, r->comm, path, frozen_skip);
    if (st == SINTER_OK && !*frozen_skip && r->pour.on)
        st = agree(r->comm, r->rank != 0 || mpi_pour_save(&r->pour, path) ? 0 : SINTER_ERR_IO);
    return st;
}

/* Rank 0's message, every rank's status. */
static int say(const mpi_run *r, const char *what, sinter_status st)
{
    if (r->rank == 0)
        fprintf(stderr, "sinter (MPI, %d ranks): %s: %s (%s)\n", r->size, what,
                sinter_last_error(r->ctx), sinter_status_name(st));
    return 1;
}

static int refuse(const mpi_run *r, const char *what)
{
    if (r->rank == 0)
        fprintf(stderr, "sinter (MPI, %d ranks): %s\n", r->size, what);
    return 1;
}

/* The decomposition's box: the scene's particles as every rank read them and its insertion
 * region, with a margin of their largest diameter (a particle outside the box belongs to the
 * nearest part anyway). */
static int scene_box(const mpi_run *r, const char *path, double lo[3], double hi[3])
{
    const double *x = NULL, *rad = NULL;
    size_t n = 0;
    if (sinter_particles_view_read(r->ps, SINTER_FIELD_POSITION, (const void **)&x, &n, NULL) !=
        SINTER_OK)
        return 0;
    if (sinter_particles_view_read(r->ps, SINTER_FIELD_RADIUS, (const void **)&rad, NULL, NULL) !=
        SINTER_OK) {
        sinter_particles_release(r->ps, SINTER_FIELD_POSITION);
        return 0;
    }
    double rmax = 0.0;
    for (int d = 0; d < 3; ++d) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (size_t i = 0; i < n; ++i) {
        rmax = fmax(rmax, rad[i]);
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], x[3 * i + d]);
            hi[d] = fmax(hi[d], x[3 * i + d]);
        }
    }
    sinter_particles_release(r->ps, SINTER_FIELD_POSITION);
    sinter_particles_release(r->ps, SINTER_FIELD_RADIUS);
    if (r->facts.insert) /* and the insertion's region (a scene may start empty) */
        run_mpi_insert_box(path, lo, hi);
    for (int d = 0; d < 3; ++d) {
        if (!(lo[d] < INFINITY)) { /* nothing to size it */
            lo[d] = 0.0;
            hi[d] = 1.0;
        }
        lo[d] -= 2.0 * rmax;
        hi[d] += 2.0 * rmax;
        if (!(hi[d] > lo[d]))
            hi[d] = lo[d] + 1.0;
    }
    return 1;
}

/* Remove every particle of this rank's set (the others' copies of rank 0's, or before a
 * restart reads the checkpoint's). */
static sinter_status remove_all(mpi_run *r)
{
    size_t n = 0;
    sinter_particles_count(r->ps, &n);
    if (n == 0)
        return SINTER_OK;
    size_t *index = malloc(n * sizeof(size_t));
    if (index == NULL)
        return SINTER_ERR_NOMEM;
    for (size_t i = 0; i < n; ++i)
        index[i] = i;
    const sinter_status st = sinter_particles_remove(r->ps, n, index);
    free(index);
    return st;
}

static int parse(int argc, char **argv, const char **scene_path, const char **out_dir,
                 const char **restart, double *end_time, double *every, double *stop_at,
                 int *log_level)
{
    static const char *const levels[] = {"error", "warning", "info", "debug"};
    for (int k = 2; k < argc; ++k) {
        const int more = k + 1 < argc;
        if (strcmp(argv[k], "-o") == 0 && more)
            *out_dir = argv[++k];
        else if (strcmp(argv[k], "--restart") == 0 && more)
            *restart = argv[++k];
        else if ((strcmp(argv[k], "--end-time") == 0 || strcmp(argv[k], "--progress") == 0 ||
                  strcmp(argv[k], "--stop-at") == 0) &&
                 more) {
            char *end = NULL;
            const double value = strtod(argv[k + 1], &end);
            if (end == argv[k + 1] || *end != '\0' || !(value >= 0.0) || value > 1e300)
                return 0;
            *(strcmp(argv[k], "--end-time") == 0   ? end_time
              : strcmp(argv[k], "--progress") == 0 ? every
                                                   : stop_at) = value;
            ++k;
        } else if (strcmp(argv[k], "--log") == 0 && more) {
            ++k;
            for (int level = 0; level < 4; ++level)
                if (strcmp(argv[k], levels[level]) == 0)
                    *log_level = level;
            if (*log_level < 0)
                return 0;
        } else if (argv[k][0] != '-' && *scene_path == NULL)
            *scene_path = argv[k];
        else
            return 0;
    }
    return *scene_path != NULL;
}

/* Set up the ranks' run: load, refuse, decompose, fill or restart. 0 on success. */
static int set_up(mpi_run *r, const char *scene_path, const char *restart, double end_time,
                  int log_level)
{
    sinter_status st = sinter_ctx_create(&r->ctx, NULL);
    if (agree(r->comm, st) != SINTER_OK)
        return refuse(r, "cannot create a context");
    st = sinter_ctx_set_threads(r->ctx, 1);
    if (st == SINTER_OK && log_level >= 0 && r->rank == 0)
        st = sinter_ctx_set_log(r->ctx, cli_print_log, log_level, NULL);
    if (st == SINTER_OK)
        st = sinter_scene_load(&r->scene, r->ctx, scene_path);
    if (st == SINTER_OK && end_time >= 0.0)
        st = sinter_scene_set_end_time(r->scene, end_time);
    /* every rank read the same file: the same outcome everywhere, agreed all the same */
    if (agree(r->comm, st) != SINTER_OK)
        return say(r, scene_path, st);
    const int facts = read_facts(scene_path, &r->facts) && mpi_pour_read(scene_path, &r->pour);
    if (agree(r->comm, facts ? 0 : -1) != 0)
        return refuse(r, "cannot read the scene file");
    if (r->pour.on && r->pour.furnace && r->facts.refused[0] == '\0')
        snprintf(r->facts.refused, sizeof(r->facts.refused),
                 "a [stepper] temperature_schedule timed from a [pour]'s end");
    if (r->pour.on && r->facts.compact && r->facts.refused[0] == '\0')
        snprintf(r->facts.refused, sizeof(r->facts.refused), "a [compact] after a [pour]");
    if (r->facts.refused[0] != '\0') {
        if (r->rank == 0)
            fprintf(stderr,
                    "sinter (MPI, %d ranks): %s: %s is not supported over MPI yet (run the "
                    "scene with the serial sinter)\n",
                    r->size, scene_path, r->facts.refused);
        return 1;
    }
    sinter_scene_get_stepper(r->scene, &r->st);
    sinter_scene_get_particles(r->scene, &r->ps);
    sinter_scene_get_walls(r->scene, &r->walls);
    size_t walls = 0;
    sinter_walls_count(r->walls, &walls);
    if (walls != r->facts.wall_count || walls > MAX_WALLS)
        return refuse(r, "the scene's walls are not its [wall NAME] sections");
    if (r->facts.compact && restart == NULL) { /* as the serial set-up: on rank 0's copy */
        st = r->rank == 0 ? sinter_scene_compact(r->scene) : SINTER_OK;
        if (agree(r->comm, st) != SINTER_OK)
            return say(r, "the compaction ([compact], on rank 0)", st);
    }
    sinter_mpi_options options;
    sinter_mpi_options_init(&options, sizeof(options));
    /* rank 0's particles (the others' copies are not compacted) */
    if (agree(r->comm, scene_box(r, scene_path, options.lo, options.hi) ? 0 : -1) != 0)
        return refuse(r, "cannot read the scene's particles");
    MPI_Bcast(options.lo, 3, MPI_DOUBLE, 0, r->comm); /* rank 0's (compacted) copy's box */
    MPI_Bcast(options.hi, 3, MPI_DOUBLE, 0, r->comm);
    st = sinter_mpi_domain_create(&r->domain, r->comm, &options);
    if (agree(r->comm, st) != SINTER_OK)
        return say(r, "the MPI domain", st);
    if (restart != NULL || r->rank != 0)
        st = remove_all(r);
    if (agree(r->comm, st) != SINTER_OK)
        return say(r, "removing the copies of rank 0's particles", st);
    /* what the library does not run across subdomains (periodic axes, an electric model with
     * host callbacks, sort_interval, qs_strategy 1) is refused here,
     * with the library's reason */
    st = sinter_mpi_attach(r->domain, r->st, r->ps, 0);
    if (st != SINTER_OK)
        return say(r, "not supported over MPI yet", st);
    if (restart != NULL) { /* read into the attached stepper: each rank its part */
        const sinter_mpi_decomp *decomp = NULL;
        sinter_mpi_domain_decomp(r->domain, &decomp);
        st = sinter_mpi_checkpoint_read(r->st, r->ps, r->comm, restart, decomp, NULL);
        if (st != SINTER_OK)
            return say(r, restart, st);
        /* a pour's programme: where it stood (run_mpi_pour.c) */
        if (agree(r->comm, !r->pour.on || mpi_pour_load(&r->pour, restart) ? 0 : -1) != 0) {
            char what[PATH_SIZE + 96];
            snprintf(what, sizeof(what),
                     "--restart: %s.pour, the pour's state: none or not readable", restart);
            return refuse(r, what);
        }
    } else {
        st = sinter_mpi_distribute(r->domain);
    }
    if (st != SINTER_OK)
        return say(r, "distributing the particles", st);
    return 0;
}

int cli_run_mpi(int argc, char **argv)
{
    const char *scene_path = NULL, *out_dir = "out", *restart = NULL;
    double end_time = -1.0, every = -1.0, stop_at = HUGE_VAL;
    int log_level = -1;
    if (!parse(argc, argv, &scene_path, &out_dir, &restart, &end_time, &every, &stop_at,
               &log_level)) {
        /* before MPI_Init: rank 0 by the launcher's environment */
        const char *rank = getenv("OMPI_COMM_WORLD_RANK");
        rank = rank != NULL                 ? rank
               : getenv("PMI_RANK") != NULL ? getenv("PMI_RANK")
                                            : getenv("PMIX_RANK");
        if (rank == NULL || strcmp(rank, "0") == 0)
            fputs("sinter (MPI): usage: mpiexec -n N sinter run SCENE [-o DIR] [--restart "
                  "DIR/checkpoint.mpi] [--end-time T] [--stop-at T] [--progress S] [--log LEVEL]\n"
                  "(--threads is not supported over MPI: one thread per rank)\n",
                  stderr);
        return 1;
    }
    int provided = 0;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return 1;
    mpi_run *r = calloc(1, sizeof(mpi_run));
    int rc = 1;
    if (r == NULL)
        goto done;
    r->comm = MPI_COMM_WORLD;
    r->out_dir = out_dir;
    r->log_level = log_level;
    MPI_Comm_rank(r->comm, &r->rank);
    MPI_Comm_size(r->comm, &r->size);
    const double started = MPI_Wtime();
    if (set_up(r, scene_path, restart, end_time, log_level) != 0)
        goto done;
    char path[PATH_SIZE];
    int ok = make_dir(out_dir);
    snprintf(path, sizeof(path), "%s/frames", out_dir);
    ok = ok && make_dir(path);
    if (agree(r->comm, ok ? 0 : -1) != 0) {
        refuse(r, "cannot create the output directory");
        goto done;
    }
    double t = 0.0, end = 0.0, interval = 0.0, checkpoint_every = 0.0;
    sinter_stepper_time(r->st, &t);
    sinter_scene_end_time(r->scene, &end);
    /* the output interval: the scene's [output] interval through the checkpoint-free route
     * of the scene reference (sinter_scene has no getter): read from the file */
    FILE *fp = fopen(scene_path, "r");
    char line[1024], section[64] = "";
    while (fp != NULL && fgets(line, sizeof(line), fp) != NULL) {
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        trim(line);
        if (line[0] == '[')
            copy(section, sizeof(section), line);
        else if (strcmp(section, "[output]") == 0 && strchr(line, '=') != NULL) {
            char key[64];
            copy(key, sizeof(key), line);
            key[strchr(line, '=') - line < 63 ? strchr(line, '=') - line : 63] = '\0';
            trim(key);
            if (strcmp(key, "interval") == 0)
                interval = strtod(strchr(line, '=') + 1, NULL);
            else if (strcmp(key, "checkpoint_interval") == 0)
                checkpoint_every = strtod(strchr(line, '=') + 1, NULL);
        }
    }
    if (fp != NULL)
        fclose(fp);
    if (!(interval > 0.0)) /* without an [output] section: a hundredth of the end time */
        interval = end / 100.0;
    const size_t columns = column_count(r);
    double row[8 + 3 * MAX_WALLS + CLI_MPI_QS_COLUMNS + 16 + RUN_MPI_HEAT_MAX_COLUMNS];
    if (restart != NULL) { /* the series and frames written up to the checkpoint's time */
        long long rows = r->rank == 0 ? resume_series(r, t) : 0;
        MPI_Bcast(&rows, 1, MPI_LONG_LONG, 0, r->comm);
        int ok_times = rows <= 0 || r->rank == 0 || frame_time(r, (uint64_t)rows - 1, 0.0);
        ok_times = agree(r->comm, ok_times ? 0 : -1) == 0;
        if (ok_times && rows > 0)
            MPI_Bcast(r->frame_times, (int)rows, MPI_DOUBLE, 0, r->comm);
        if (rows < 0 || !ok_times) {
            refuse(r, "--restart: no series.csv in the output directory to continue");
            goto done;
        }
        r->frame = (uint64_t)rows;
        snprintf(path, sizeof(path), "%s/series.csv", out_dir);
        if (r->facts.bonds && !run_mpi_bonds_resume(r->st, r->comm, path, &r->bonds_offset)) {
            refuse(r, "--restart: series.csv has no broken bonds at the checkpoint's time");
            goto done;
        }
    }
    if (r->rank == 0) {
        snprintf(path, sizeof(path), "%s/series.csv", out_dir);
        r->csv = fopen(path, restart != NULL ? "a" : "w");
        ok = r->csv != NULL;
        if (ok && restart == NULL)
            write_header(r);
    }
    if (agree(r->comm, ok ? 0 : -1) != 0) {
        refuse(r, "cannot write series.csv");
        goto done;
    }
    sinter_status st = SINTER_OK;
    if (restart == NULL) { /* the state at the start, with forces evaluated; its sample */
        st = sinter_stepper_step(r->st, 0);
        if (st == SINTER_OK && !record(r, row, columns))
            st = SINTER_ERR_IO;
        sinter_stepper_time(r->st, &t);
        if (st == SINTER_OK) /* a pour: every wall held from now until it ends */
            st = mpi_pour_begin(&r->pour, r->walls, t);
    }
    double next = t + interval, next_checkpoint = t + checkpoint_every, last_print = started;
    int stopped = 0, pour_failed = 0, frozen_skip = 0;
    snprintf(path, sizeof(path), "%s/checkpoint.mpi", out_dir);
    while (st == SINTER_OK) {
        sinter_stepper_time(r->st, &t);
        /* the pour's longest end while it lasts, then the end time after its end */
        const double phase_end = mpi_pour_phase_end(&r->pour, end);
        if (t >= phase_end) {
            if (r->pour.pouring && r->rank == 0)
                fprintf(stderr,
                        "sinter (MPI, %d ranks): the pour did not come to rest within t_max = %g "
                        "s (kinetic energy %g J per particle, threshold %g J)\n",
                        r->size, r->pour.t_max, r->pour.energy, r->pour.ke);
            pour_failed = r->pour.pouring;
            st = r->pour.pouring ? SINTER_ERR_NOT_CONVERGED : SINTER_OK;
            break;
        }
        st = sinter_stepper_advance(r->st, fmin(phase_end, next));
        if (st == SINTER_OK && !record(r, row, columns))
            st = SINTER_ERR_IO;
        sinter_stepper_time(r->st, &t);
        next = t + interval;
        int poured = 0; /* row[1]: the kinetic energy over the ranks */
        if (st == SINTER_OK)
            st = mpi_pour_sample(&r->pour, r->walls, r->ps, r->domain, t, row[1], &poured);
        if (poured && r->rank == 0 && r->log_level >= SINTER_LOG_INFO) {
            char message[96];
            snprintf(message, sizeof(message), "poured: at rest at t = %g s", t);
            cli_print_log(SINTER_LOG_INFO, message, NULL);
        }
        /* --stop-at: the first sample at or after it (within a relative 1e-12, as serially) */
        if (st == SINTER_OK && t >= stop_at - 1e-12 * fabs(stop_at)) {
            stopped = 1;
            break;
        }
        if (st == SINTER_OK && checkpoint_every > 0.0 && t >= next_checkpoint) {
            next_checkpoint = t + checkpoint_every;
            st = write_checkpoint(r, path, &frozen_skip);
        }
        const double now = MPI_Wtime();
        if (r->rank == 0 && every != 0.0 && now - last_print >= (every > 0 ? every : 5.0)) {
            const double last = mpi_pour_phase_end(&r->pour, end); /* a pour: its t_max */
            fprintf(stderr, "sinter: t = %.4g / %.4g s (%.1f %%)%s\n", t, last, 100.0 * t / last,
                    r->pour.pouring ? ", pouring" : "");
            last_print = now;
        }
    }
    if (st == SINTER_OK)
        st = write_checkpoint(r, path, &frozen_skip);
    if (st == SINTER_OK && frozen_skip && r->rank == 0)
        fprintf(stderr,
                "sinter: no checkpoint at t = %.9g s: the frozen heat stage holds the "
                "mechanics (its rates do not travel in portable checkpoints yet)\n",
                t);
    if (r->csv != NULL) {
        fclose(r->csv);
        r->csv = NULL;
    }
    if (st == SINTER_OK && r->rank == 0 &&
        sinter_plot_run(r->ctx, out_dir, r->facts.name) != SINTER_OK)
        fprintf(stderr, "sinter: no plot: %s\n", sinter_last_error(r->ctx));
    if (st != SINTER_OK) {
        if (!pour_failed) /* (else said above) */
            say(r, "the run failed", st);
        goto done;
    }
    if (r->rank == 0 && stopped)
        printf("sinter: stopped (--stop-at) at t = %.9g s; continue with: mpiexec -n N sinter "
               "run %s -o %s --restart %s\n",
               t, scene_path, out_dir, path);
    else if (r->rank == 0)
        printf("sinter: ran %s on %d MPI ranks in %.1f s; results in %s/ (series.csv, "
               "series.svg, %s.pvd with frames/*.pvtu, checkpoint.mpi)\n",
               scene_path, r->size, MPI_Wtime() - started, out_dir, r->facts.name);
    rc = 0;
done:
    if (r != NULL) {
        if (r->csv != NULL)
            fclose(r->csv);
        if (r->st != NULL)
            sinter_stepper_set_domain_ops(r->st, NULL, NULL);
        sinter_mpi_domain_destroy(r->domain);
        sinter_scene_destroy(r->scene);
        sinter_ctx_destroy(r->ctx);
        free(r->frame_times);
        free(r);
    }
    MPI_Finalize();
    return rc;
}

/* Started by mpiexec (Open MPI, MPICH/PMI or PMIx set these in every rank's environment). */
int cli_mpi_launched(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") != NULL || getenv("PMI_SIZE") != NULL ||
           getenv("PMIX_RANK") != NULL;
}
