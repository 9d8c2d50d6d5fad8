/*
 * A material's property against temperature in a scene ([material NAME] keys such as
 * `conductivity_table`): inline pairs "theta value, theta value, ..." or the name of a CSV
 * file of rows "theta,value" (docs/scene-reference.md).
 */
#ifndef SINTER_SCENE_TABLES_H
#define SINTER_SCENE_TABLES_H

#include "core/core.h"
#include "io/scene_text.h"

/* 1 if `key` names a property table (ends in "_table"), which scene_material_read leaves to
 * the scene's builder. */
int scene_table_key(const char *key);

/* 1 if the entry's value is inline numbers (it starts with a digit, a sign or a point), else it
 * names a file. */
int scene_table_inline(const scene_entry *e);

/*
 * The table of entry `key` of section s: inline pairs, or (when path is not NULL) the CSV file
 * at `path`: rows "theta,value" (commas, semicolons or blanks between), '#' comments and blank
 * lines skipped, a first line that is not numbers taken as a header. *theta and *value are
 * allocated (free both), *n points. Errors name the scene's or the file's line.
 */
sinter_status scene_table_read(scene_text *t, scene_section *s, const char *key, const char *path,
                               double **theta, double **value, size_t *n);

#endif
