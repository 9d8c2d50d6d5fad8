/* The [insert] section: continuous insertion at a mass rate (scene_insert.c). */
#ifndef SINTER_SCENE_INSERT_H
#define SINTER_SCENE_INSERT_H

#include "io/scene.h"
#include "io/scene_text.h"

/* Set the stepper's insertion from the section (sinter_stepper_set_insertion). Errors:
 * SINTER_ERR_PARSE with file and line, the library's own labelled with the section's line. */
sinter_status scene_build_insert(scene_text *t, sinter_scene *sc, scene_section *s);

#endif
