/* Private entry of the triaxial compaction (compact.c) for the scene reader. */
#ifndef SINTER_COMPACT_H
#define SINTER_COMPACT_H

#include "particles/particles.h"

/*
 * Check `options` against the particle set exactly as sinter_pack_compact does before it
 * runs (every value, the final box against the spheres), without running anything. The
 * limit on the number of steps needs the time step and is checked by the run only.
 */
sinter_status sinter_compaction_check(const sinter_particles *ps,
                                      const sinter_compaction_options *options);

#endif
