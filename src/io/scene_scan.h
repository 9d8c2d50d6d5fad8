/* A heat model's scan path read from its scene section (scene_scan.c). */
#ifndef SINTER_IO_SCENE_SCAN_H
#define SINTER_IO_SCENE_SCAN_H

#include "io/scene_text.h"

/* Read the section's scan keys (if any) into hm's scan path; file names relative to
 * `directory`. Errors name the scene's line. */
sinter_status scene_heat_scan(scene_text *t, const char *directory, scene_section *s,
                              sinter_heat_model *hm);

/* 1 if `key` is one of the scan keys scene_heat_scan reads (not a model parameter). */
int scene_heat_scan_key(const char *key);

#endif
