/*
 * [insert]: continuous insertion from a box or the cylinder inscribed in it at a mass rate
 * (sinter_stepper_set_insertion), the sizes by the keys of [particles] method = random.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/scene_insert.h"

#define TRY(expr) SCENE_TRY(expr)

#define OPTIONAL(expr) SCENE_OPTIONAL(expr)

static sinter_status need(scene_text *t, scene_section *s, sinter_status st, const char *key)
{
    if (st != SINTER_ERR_NOT_FOUND)
        return st;
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: [insert] needs '%s = ...'", t->path,
                       s->line, key);
}

/* The powder: material, temperature, box, seed and size distribution (d, q: a table's). */
static sinter_status read_powder(scene_text *t, sinter_scene *sc, scene_section *s,
                                 sinter_packing_options *p, double **d, double **q)
{
    *d = *q = NULL;
    TRY(sinter_packing_options_init(p, sizeof(*p)));
    int mat = 0;
    TRY(scene_material_ref(t, sc, s, &mat));
    p->material = mat;
    OPTIONAL(scene_get_double(t, s, "temperature", &p->temperature));
    TRY(need(t, s, scene_get_vec3(t, s, "box_min", p->box_min), "box_min"));
    TRY(need(t, s, scene_get_vec3(t, s, "box_max", p->box_max), "box_max"));
    double seed = 1, attempts = 1000;
    OPTIONAL(scene_get_double(t, s, "seed", &seed));
    OPTIONAL(scene_get_double(t, s, "max_attempts", &attempts));
    if (!(seed >= 0 && seed < 18446744073709551616.0) || seed != floor(seed) ||
        !(attempts >= 1 && attempts <= 1e12) || attempts != floor(attempts))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: [insert]: seed = %g and max_attempts = %g must be whole "
                           "numbers in [0, 2^64) and [1, 1e12]",
                           t->path, s->line, seed, attempts);
    p->seed = (uint64_t)seed;
    p->max_attempts = (uint64_t)attempts;
    const char *dist = "monodisperse";
    OPTIONAL(scene_get_word(t, s, "distribution", &dist));
    double radius = 0.0;
    if (strcmp(dist, "table") != 0) /* a table has its own sizes */
        TRY(need(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
    return scene_read_distribution(t, sc, s, p, dist, radius, d, q);
}

static sinter_status read_options(scene_text *t, scene_section *s, sinter_insertion_options *o)
{
    TRY(sinter_insertion_options_init(o, sizeof(*o)));
    TRY(need(t, s, scene_get_double(t, s, "mass_rate", &o->mass_rate), "mass_rate"));
    OPTIONAL(scene_get_double(t, s, "start", &o->start));
    OPTIONAL(scene_get_double(t, s, "end", &o->end));
    OPTIONAL(scene_get_double(t, s, "interval", &o->interval));
    OPTIONAL(scene_get_vec3(t, s, "velocity", o->velocity));
    const char *region = "box";
    OPTIONAL(scene_get_word(t, s, "region", &region));
    if (strcmp(region, "box") == 0)
        o->region = SINTER_INSERT_BOX;
    else if (strcmp(region, "cylinder") == 0)
        o->region = SINTER_INSERT_CYLINDER;
    else
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: region: expected box or cylinder, got '%s'", t->path,
                           scene_find(s, "region")->line, region);
    return SINTER_OK;
}

sinter_status scene_build_insert(scene_text *t, sinter_scene *sc, scene_section *s)
{
    sinter_packing_options p;
    sinter_insertion_options o;
    double *d = NULL, *q = NULL;
    sinter_status st = read_powder(t, sc, s, &p, &d, &q);
    if (st == SINTER_OK)
        st = read_options(t, s, &o);
    if (st == SINTER_OK) {
        st = sinter_stepper_set_insertion(sc->st, &p, &o);
        if (st != SINTER_OK && st != SINTER_ERR_PARSE) {
            char detail[SINTER_ERROR_TEXT_SIZE];
            snprintf(detail, sizeof(detail), "%s", sinter_last_error(t->ctx));
            st = sinter_fail(t->ctx, st, "%s:%d: %s", t->path, s->line, detail);
        }
    }
    sinter_free(t->ctx, d);
    sinter_free(t->ctx, q);
    return st;
}
