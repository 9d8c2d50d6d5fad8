/*
 * [compact]: the triaxial compaction of sinter_pack_compact on the scene's particles (its own
 * walls and stepper; the scene's walls take no part; seed 001 sec. 3.2). sinter_scene_run calls
 * it in its set-up; a host that steps the scene itself (the MPI runner) calls it before it
 * distributes the particles.
 */
#include <string.h>

#include "io/scene.h"

sinter_status sinter_scene_compact(sinter_scene *sc)
{
    if (sc == NULL)
        return SINTER_ERR_NULL;
    if (!sc->compact)
        return sinter_fail(sc->ctx, SINTER_ERR_STATE,
                           "sinter_scene_compact: the scene has no [compact] section");
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
