/* The files of a scene's frame beside the particles' .vtu (io/scene_frames.h). */
#include <math.h>
#include <stdio.h>
#include <sys/stat.h>

#include "contact/snapshot.h"
#include "fields/coarse_grain.h"
#include "io/path.h"
#include "io/scene_frames.h"
#include "io/series.h"
#include "io/vti.h"
#include "io/vtk_appended.h"
#include "io/vtp.h"
#include "particles/particles.h"
#include "stepper/stepper.h"

/* frames/<kind>_NNNNN.vt? of the k-th extra a scene writes (0 contacts or links, 1 walls,
 * 2 the coarse-grained fields). */
static int extra_name(const sinter_scene *sc, int which, uint64_t frame, char rel[64])
{
    const int qs = sc->st->kind == SINTER_STEPPER_QUASISTATIC;
    static const char *const kinds[SCENE_FRAME_EXTRAS] = {"contacts", "walls", "fields"};
    const char *kind = which == 0 && qs ? "links" : kinds[which];
    const int wanted[SCENE_FRAME_EXTRAS] = {sc->write_contacts, sc->write_walls,
                                            sc->fields && sc->fields_grid};
    if (!wanted[which])
        return 0;
    snprintf(rel, 64, "frames/%s_%05llu.%s", kind, (unsigned long long)frame,
             which == 2 ? "vti" : "vtp");
    return 1;
}

/* The particles' bounding box (a unit box about the origin without particles). */
static void particle_box(const sinter_particles *ps, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; ++d) {
        lo[d] = ps->count > 0 ? INFINITY : -0.5;
        hi[d] = ps->count > 0 ? -INFINITY : 0.5;
    }
    for (size_t i = 0; i < ps->count; ++i)
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], ps->x[3 * i + (size_t)d] - ps->radius[i]);
            hi[d] = fmax(hi[d], ps->x[3 * i + (size_t)d] + ps->radius[i]);
        }
}

/* The box the walls are drawn in. */
static void wall_box(const sinter_scene *sc, double lo[3], double hi[3])
{
    const sinter_stepper *st = sc->st;
    if (st->has_domain) {
        for (int d = 0; d < 3; ++d) {
            lo[d] = st->domain_lo[d];
            hi[d] = st->domain_hi[d];
        }
        return;
    }
    const sinter_particles *ps = sc->ps;
    particle_box(ps, lo, hi);
    double diagonal = 0.0;
    for (int d = 0; d < 3; ++d)
        diagonal += ps->count > 0 ? (hi[d] - lo[d]) * (hi[d] - lo[d]) : 0.0;
    const double grow = ps->count > 0 ? 0.1 * sqrt(diagonal) : 1.0;
    for (int d = 0; d < 3; ++d) {
        lo[d] = ps->count > 0 ? lo[d] - grow : -grow;
        hi[d] = ps->count > 0 ? hi[d] + grow : grow;
    }
}

/* The grid of the fields: box_min to box_max, or the walls' box, at the scene's spacing. */
static void field_grid(const sinter_scene *sc, sinter_coarse_options *o)
{
    double lo[3], hi[3];
    (void)sinter_coarse_options_init(o, sizeof(*o));
    if (sc->fields_box)
        for (int d = 0; d < 3; ++d) {
            lo[d] = sc->fields_lo[d];
            hi[d] = sc->fields_hi[d];
        }
    else
        wall_box(sc, lo, hi);
    for (int d = 0; d < 3; ++d) {
        const double cells = floor((hi[d] - lo[d]) / sc->fields_spacing * (1 + 1e-12));
        o->origin[d] = lo[d];
        o->spacing[d] = sc->fields_spacing;
        o->points[d] = cells >= 0 && cells < 1e9 ? (size_t)cells + 1 : (size_t)1e9;
    }
    o->width = sc->fields_width;
    o->cutoff = sc->fields_cutoff;
}

/* frames/profile_<axis>_NNNNN.csv: the laminae of sinter_lamina_profile across box_min ..
 * box_max, or the particles' bounding box. */
static sinter_status write_profile(const sinter_scene *sc, const char *out_dir, uint64_t frame,
                                   int axis)
{
    sinter_ctx *ctx = sc->ctx;
    char rel[64], path[SINTER_PATH_SIZE];
    snprintf(rel, sizeof(rel), "frames/profile_%c_%05llu.csv", 'x' + axis,
             (unsigned long long)frame);
    sinter_status st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
    if (st != SINTER_OK)
        return st;
    double lo[3], hi[3];
    if (sc->fields_box)
        for (int d = 0; d < 3; ++d) {
            lo[d] = sc->fields_lo[d];
            hi[d] = sc->fields_hi[d];
        }
    else
        particle_box(sc->ps, lo, hi);
    for (int d = 0; d < 3; ++d)
        if (!(hi[d] > lo[d])) /* one particle layer across a plane: give it width */
            hi[d] = lo[d] + 1.0;
    const size_t n = (size_t)sc->laminae;
    double *fraction = sinter_calloc(ctx, 2 * n, sizeof(double));
    if (fraction == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "out of memory for the lamina profile");
    double *temperature = fraction + n;
    st = sinter_lamina_profile(sc->ps, axis, lo, hi, n, fraction, temperature);
    sinter_out_file out;
    if (st == SINTER_OK)
        st = sinter_out_open(&out, ctx, "sinter_scene_run", path);
    if (st == SINTER_OK) {
        fputs("position [m],solid_fraction [1],temperature [K]\n", out.fp);
        const double q = (hi[axis] - lo[axis]) / (double)n;
        for (size_t s = 0; s < n; ++s) {
            sinter_out_double(out.fp, lo[axis] + ((double)s + 0.5) * q); /* lamina centre */
            fputc(',', out.fp);
            sinter_out_double(out.fp, fraction[s]);
            fputc(',', out.fp);
            sinter_out_double(out.fp, temperature[s]);
            fputc('\n', out.fp);
        }
        st = sinter_out_close(&out, SINTER_OK);
    }
    sinter_free(ctx, fraction);
    return st;
}

sinter_status scene_frame_extras_write(const sinter_scene *sc, const char *out_dir, uint64_t frame)
{
    sinter_ctx *ctx = sc->ctx;
    char rel[64], path[SINTER_PATH_SIZE];
    sinter_status st = SINTER_OK;
    sinter_snapshot *snap = NULL;
    /* one snapshot for the contacts and the fields' stress; a state not evaluated yet (the
     * first sample) has no contacts to show */
    if ((extra_name(sc, 0, frame, rel) || extra_name(sc, 2, frame, rel)) &&
        sinter_snapshot_possible(sc->st))
        st = sinter_snapshot_create(&snap, sc->st);
    if (st == SINTER_OK && extra_name(sc, 0, frame, rel)) {
        st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
        if (st == SINTER_OK)
            st = sinter_vtp_write_contacts(ctx, path, snap, sc->ps, scene_vtk_format(sc));
        if (st == SINTER_OK && sc->vtu_appended)
            st = sinter_vtk_make_appended(ctx, path);
    }
    if (st == SINTER_OK && extra_name(sc, 2, frame, rel)) {
        sinter_coarse_options grid;
        sinter_coarse_fields fields;
        field_grid(sc, &grid);
        st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
        if (st == SINTER_OK)
            st = sinter_coarse_check(ctx, "[fields]", &grid);
        if (st == SINTER_OK)
            st = sinter_coarse_fields_compute(sc->ps, snap, &grid, &fields);
        if (st == SINTER_OK) {
            st = sinter_vti_write_fields(ctx, path, &grid, &fields, scene_vtk_format(sc));
            if (st == SINTER_OK && sc->vtu_appended)
                st = sinter_vtk_make_appended(ctx, path);
            sinter_coarse_fields_free(ctx, &fields);
        }
    }
    sinter_snapshot_destroy(snap);
    for (int axis = 0; axis < 3 && st == SINTER_OK; ++axis)
        if (sc->fields && (sc->profile_axes >> axis & 1u))
            st = write_profile(sc, out_dir, frame, axis);
    if (st == SINTER_OK && extra_name(sc, 1, frame, rel)) {
        double lo[3], hi[3];
        wall_box(sc, lo, hi);
        st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
        if (st == SINTER_OK)
            st = sinter_vtp_write_walls(ctx, path, sc->walls, lo, hi, scene_vtk_format(sc));
        if (st == SINTER_OK && sc->vtu_appended)
            st = sinter_vtk_make_appended(ctx, path);
    }
    return st;
}

size_t scene_frame_extras_list(const sinter_scene *sc, const char *out_dir, uint64_t frame,
                               char rel[SCENE_FRAME_EXTRAS][64], unsigned parts[SCENE_FRAME_EXTRAS])
{
    size_t count = 0;
    for (int which = 0; which < SCENE_FRAME_EXTRAS; ++which) {
        char path[SINTER_PATH_SIZE];
        struct stat info;
        if (!extra_name(sc, which, frame, rel[count]))
            continue;
        if (sinter_path_join(sc->ctx, path, sizeof(path), out_dir, rel[count]) != SINTER_OK ||
            stat(path, &info) != 0)
            continue;
        parts[count++] = (unsigned)which + 1;
    }
    return count;
}
