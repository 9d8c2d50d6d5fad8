/* The [wall] section's kinds, spin and force servo (scene_walls.c). */
#ifndef SINTER_SCENE_WALLS_H
#define SINTER_SCENE_WALLS_H

#include "io/scene.h"
#include "io/scene_text.h"

/* Add the wall of section s by its "kind" (plane by default) with material `material`; its
 * index into *index. Errors: SINTER_ERR_PARSE with file and line, the library's own. */
sinter_status scene_wall_add(scene_text *t, sinter_scene *sc, scene_section *s,
                             const sinter_material *material, size_t *index);

/* The wall's "spin", if any. */
sinter_status scene_wall_spin(scene_text *t, sinter_scene *sc, scene_section *s, size_t index);

/* motion = servo: the target (servo_force, or servo_pressure on the wall's area), gains and
 * velocity limit. */
sinter_status scene_wall_servo(scene_text *t, sinter_scene *sc, scene_section *s, size_t index);

#endif
