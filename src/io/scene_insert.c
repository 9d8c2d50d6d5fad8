/*
 * [insert]: continuous insertion from a box or the cylinder inscribed in it at a mass rate
 * (sinter_stepper_set_insertion), the sizes by the keys of [particles] method = random, one
 * material or a mixture by mass fraction (materials, mass_fractions; sizes per material from
 * [size NAME] sections with `sizes`).
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

/* The arrays a powder borrows: a table's, a mixture's and its sizes' (freed together). */
typedef struct powder_arrays {
    double *d, *q, *fractions, *tables[2 * SCENE_MAX_MATERIALS];
    sinter_packing_options sizes[SCENE_MAX_MATERIALS];
} powder_arrays;

static void powder_free(sinter_ctx *ctx, powder_arrays *a)
{
    sinter_free(ctx, a->d);
    sinter_free(ctx, a->q);
    sinter_free(ctx, a->fractions);
    for (size_t k = 0; k < 2 * SCENE_MAX_MATERIALS; ++k)
        sinter_free(ctx, a->tables[k]);
}

/* The mixture (materials, mass_fractions, and sizes per material if given): into p and a. */
static sinter_status read_mixture(scene_text *t, sinter_scene *sc, scene_section *s,
                                  sinter_packing_options *p, powder_arrays *a)
{
    TRY(scene_read_mixture(t, sc, s, sc->insert_materials, &a->fractions, &p->mixture_count));
    sc->insert_mixture = p->mixture_count;
    p->mixture_materials = sc->insert_materials;
    p->mixture_mass_fractions = a->fractions;
    if (scene_find(s, "sizes") == NULL)
        return SINTER_OK;
    p->mixture_sizes = a->sizes;
    return scene_read_sizes(t, sc, s, p->mixture_count, a->sizes, a->tables);
}

/* The powder: material(s), temperature, box, seed, gap and size distribution (a's arrays:
 * free them, also on error). */
static sinter_status read_powder(scene_text *t, sinter_scene *sc, scene_section *s,
                                 sinter_packing_options *p, powder_arrays *a)
{
    memset(a, 0, sizeof(*a));
    TRY(sinter_packing_options_init(p, sizeof(*p)));
    const int mixture = scene_find(s, "materials") != NULL;
    if (!mixture || scene_find(s, "material") != NULL) {
        int mat = 0;
        TRY(scene_material_ref(t, sc, s, &mat));
        p->material = mat;
    }
    OPTIONAL(scene_get_double(t, s, "temperature", &p->temperature));
    TRY(need(t, s, scene_get_vec3(t, s, "box_min", p->box_min), "box_min"));
    TRY(need(t, s, scene_get_vec3(t, s, "box_max", p->box_max), "box_max"));
    double seed = 1, attempts = 1000;
    OPTIONAL(scene_get_double(t, s, "seed", &seed));
    OPTIONAL(scene_get_double(t, s, "max_attempts", &attempts));
    OPTIONAL(scene_get_double(t, s, "gap", &p->gap));
    if (!(seed >= 0 && seed < 18446744073709551616.0) || seed != floor(seed) ||
        !(attempts >= 1 && attempts <= 1e12) || attempts != floor(attempts))
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: [insert]: seed = %g and max_attempts = %g must be whole "
                           "numbers in [0, 2^64) and [1, 1e12]",
                           t->path, s->line, seed, attempts);
    p->seed = (uint64_t)seed;
    p->max_attempts = (uint64_t)attempts;
    if (mixture)
        TRY(read_mixture(t, sc, s, p, a));
    else if (scene_find(s, "sizes") != NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: sizes: sizes per material need materials = ... (a mixture)",
                           t->path, scene_find(s, "sizes")->line);
    if (p->mixture_sizes != NULL) /* each material has its own distribution */
        return SINTER_OK;
    const char *dist = "monodisperse";
    OPTIONAL(scene_get_word(t, s, "distribution", &dist));
    double radius = 0.0;
    if (strcmp(dist, "table") != 0) /* a table has its own sizes */
        TRY(need(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
    return scene_read_distribution(t, sc, s, p, dist, radius, &a->d, &a->q);
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
    powder_arrays a;
    sinter_status st = read_powder(t, sc, s, &p, &a);
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
    powder_free(t->ctx, &a);
    if (st != SINTER_OK)
        sc->insert_mixture = 0;
    return st;
}
