/* The files of a scene's frame beside the particles' .vtu (io/scene_frames.h). */
#include <math.h>
#include <stdio.h>
#include <sys/stat.h>

#include "contact/snapshot.h"
#include "io/path.h"
#include "io/scene_frames.h"
#include "io/vtp.h"
#include "particles/particles.h"
#include "stepper/stepper.h"

/* frames/<kind>_NNNNN.vtp of the k-th extra a scene writes (0 contacts or links, 1 walls). */
static int extra_name(const sinter_scene *sc, int which, uint64_t frame, char rel[64])
{
    const int qs = sc->st->kind == SINTER_STEPPER_QUASISTATIC;
    const char *kind = which == 0 ? (qs ? "links" : "contacts") : "walls";
    if (which == 0 ? !sc->write_contacts : !sc->write_walls)
        return 0;
    snprintf(rel, 64, "frames/%s_%05llu.vtp", kind, (unsigned long long)frame);
    return 1;
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
    for (int d = 0; d < 3; ++d) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (size_t i = 0; i < ps->count; ++i)
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], ps->x[3 * i + (size_t)d] - ps->radius[i]);
            hi[d] = fmax(hi[d], ps->x[3 * i + (size_t)d] + ps->radius[i]);
        }
    double diagonal = 0.0;
    for (int d = 0; d < 3; ++d)
        diagonal += ps->count > 0 ? (hi[d] - lo[d]) * (hi[d] - lo[d]) : 0.0;
    const double grow = ps->count > 0 ? 0.1 * sqrt(diagonal) : 1.0;
    for (int d = 0; d < 3; ++d) {
        lo[d] = ps->count > 0 ? lo[d] - grow : -grow;
        hi[d] = ps->count > 0 ? hi[d] + grow : grow;
    }
}

sinter_status scene_frame_extras_write(const sinter_scene *sc, const char *out_dir, uint64_t frame)
{
    sinter_ctx *ctx = sc->ctx;
    char rel[64], path[SINTER_PATH_SIZE];
    sinter_status st = SINTER_OK;
    if (extra_name(sc, 0, frame, rel)) {
        st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
        sinter_snapshot *snap = NULL;
        /* a state not evaluated yet (the first sample) has no contacts to show */
        if (st == SINTER_OK && sinter_snapshot_possible(sc->st))
            st = sinter_snapshot_create(&snap, sc->st);
        if (st == SINTER_OK)
            st = sinter_vtp_write_contacts(ctx, path, snap, sc->ps, sc->vtu_binary);
        sinter_snapshot_destroy(snap);
    }
    if (st == SINTER_OK && extra_name(sc, 1, frame, rel)) {
        double lo[3], hi[3];
        wall_box(sc, lo, hi);
        st = sinter_path_join(ctx, path, sizeof(path), out_dir, rel);
        if (st == SINTER_OK)
            st = sinter_vtp_write_walls(ctx, path, sc->walls, lo, hi, sc->vtu_binary);
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
