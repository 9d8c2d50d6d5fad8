/*
 * The text layer of scene files: sections "[type name]" holding "key = value"
 * lines; '#' starts a comment. It knows nothing of physics: scene.c gives the
 * sections their meaning. Every entry remembers its line for error messages.
 */
#ifndef SINTER_SCENE_TEXT_H
#define SINTER_SCENE_TEXT_H

#include "core/core.h"
#include "io/key_set.h"

typedef struct scene_entry {
    char *key;
    char *value;
    int line;
    int used; /* set when the interpreter reads it; unused keys are errors */
} scene_entry;

typedef struct scene_section {
    char *type;
    char *name; /* "" when the header has no name */
    int line;
    scene_entry *entries;
    size_t count;
    size_t capacity;
    sinter_key_set keys; /* entry index by key */
} scene_section;

typedef struct scene_text {
    sinter_ctx *ctx;
    char *path;
    scene_section *sections;
    size_t count;
    size_t capacity;
} scene_text;

/* Return the status of `expr` from the calling function unless it is SINTER_OK (scene.c and
 * pair.c, as TRY). */
#define SCENE_TRY(expr)                                                                            \
    do {                                                                                           \
        sinter_status scene_try_st_ = (expr);                                                      \
        if (scene_try_st_ != SINTER_OK)                                                            \
            return scene_try_st_;                                                                  \
    } while (0)

/* The same for a getter whose key may be absent (SINTER_ERR_NOT_FOUND passes). */
#define SCENE_OPTIONAL(expr)                                                                       \
    do {                                                                                           \
        sinter_status scene_opt_st_ = (expr);                                                      \
        if (scene_opt_st_ != SINTER_OK && scene_opt_st_ != SINTER_ERR_NOT_FOUND)                   \
            return scene_opt_st_;                                                                  \
    } while (0)

/* Read and split a scene file. Errors name "path:line". */
sinter_status scene_text_read(scene_text *t, sinter_ctx *ctx, const char *path);
void scene_text_free(scene_text *t);

/* The entry `key` of a section (marked used), or NULL. */
scene_entry *scene_find(scene_section *s, const char *key);

/* Typed getters: SINTER_ERR_NOT_FOUND when absent (nothing recorded), SINTER_ERR_PARSE
 * with "path:line: key: expected ..." when malformed. */
sinter_status scene_get_double(scene_text *t, scene_section *s, const char *key, double *out);
sinter_status scene_get_vec3(scene_text *t, scene_section *s, const char *key, double out[3]);
sinter_status scene_get_word(scene_text *t, scene_section *s, const char *key, const char **out);
sinter_status scene_get_bool(scene_text *t, scene_section *s, const char *key, int *out);
/* A list of numbers separated by spaces, commas or semicolons; *values is allocated. */
sinter_status scene_get_numbers(scene_text *t, scene_section *s, const char *key, double **values,
                                size_t *count);

/* Report the first entry no interpreter read, as "path:line: unknown key". */
sinter_status scene_check_unused(scene_text *t);

#endif
