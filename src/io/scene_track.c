/* Particles followed in series.csv (io/scene_track.h). */
#include <math.h>
#include <stdio.h>

#include "contact/snapshot.h"
#include "io/scene_track.h"
#include "particles/particles.h"

static const char *const WHAT[SCENE_TRACK_COLUMNS] = {
    "temperature", "contact force", "largest overlap", "contact area", "heat flow"};
static const char *const UNIT[SCENE_TRACK_COLUMNS] = {"K", "N", "m", "m^2", "W"};

size_t scene_track_labels(const sinter_scene *sc, const char **names, const char **units,
                          char (*labels)[SCENE_NAME + 16], size_t first)
{
    size_t n = 0;
    for (size_t k = 0; k < sc->track_count; ++k)
        for (int c = 0; c < SCENE_TRACK_COLUMNS; ++c, ++n) {
            snprintf(labels[n], sizeof(labels[n]), "particle %llu %s",
                     (unsigned long long)sc->track_ids[k], WHAT[c]);
            names[first + n] = labels[n];
            units[first + n] = UNIT[c];
        }
    return n;
}

/* Sum the contacts of particle `id` in the snapshot: the normal forces (> 0 compressive),
 * the largest overlap, the areas, the heat flowing into it (seed 003 Fig. 5c-f). */
static void contacts_of(const sinter_snapshot *snap, uint64_t id, double *q)
{
    size_t pairs = 0, walls = 0;
    const void *raw[6] = {NULL, NULL, NULL, NULL, NULL, NULL};
    static const sinter_contact_data WANT[6] = {
        SINTER_CONTACT_DATA_ID_A,    SINTER_CONTACT_DATA_ID_B, SINTER_CONTACT_DATA_NORMAL_FORCE,
        SINTER_CONTACT_DATA_OVERLAP, SINTER_CONTACT_DATA_AREA, SINTER_CONTACT_DATA_HEAT_FLOW};
    sinter_status st = sinter_snapshot_counts(snap, &pairs, &walls, NULL, NULL);
    for (int k = 0; k < 6 && st == SINTER_OK; ++k)
        st = sinter_snapshot_contacts(snap, WANT[k], &raw[k], NULL, NULL, NULL);
    q[1] = q[3] = q[4] = 0.0;
    q[2] = 0.0;
    if (st != SINTER_OK)
        return;
    const uint64_t *a = raw[0], *b = raw[1];
    const double *fn = raw[2], *overlap = raw[3], *area = raw[4], *heat = raw[5];
    for (size_t c = 0; c < pairs + walls; ++c) {
        const int on_a = a[c] == id, on_b = c < pairs && b[c] == id;
        if (!on_a && !on_b)
            continue;
        q[1] += fn[c];
        q[2] = fmax(q[2], overlap[c]);
        q[3] += area[c];
        q[4] += on_a ? heat[c] : -heat[c]; /* the flow into a, and out of b */
    }
}

void scene_track_observe(const sinter_scene *sc, double *q)
{
    if (sc->track_count == 0)
        return;
    sinter_snapshot *snap = NULL;
    /* one snapshot for all (a quasi-static stepper's has no contacts: zeros) */
    if (!sinter_snapshot_possible(sc->st) || sinter_snapshot_create(&snap, sc->st) != SINTER_OK)
        snap = NULL;
    const sinter_particles *ps = sc->ps;
    for (size_t k = 0; k < sc->track_count; ++k) {
        double *v = q + SCENE_TRACK_COLUMNS * k;
        size_t i = 0;
        while (i < ps->count && ps->id[i] != sc->track_ids[k])
            ++i;
        for (int c = 0; c < SCENE_TRACK_COLUMNS; ++c)
            v[c] = NAN;
        if (i == ps->count)
            continue; /* removed */
        v[0] = ps->temperature[i];
        if (snap != NULL)
            contacts_of(snap, sc->track_ids[k], v);
    }
    sinter_snapshot_destroy(snap);
}
