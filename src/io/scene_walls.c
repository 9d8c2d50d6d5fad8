/*
 * The [wall] section's wall kinds (plane, rectangle, disc, cylinder, mesh), spin, a mesh's
 * rotation and force servo: scene keys to sinter_walls_add_* and sinter_walls_set_spin /
 * _set_rotation / _set_servo. The keys are in
 * docs/scene-reference.md.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/path.h"
#include "io/scene_walls.h"

#define TRY(expr) SCENE_TRY(expr)

static sinter_status needs(scene_text *t, scene_section *s, sinter_status st, const char *key)
{
    if (st != SINTER_ERR_NOT_FOUND)
        return st;
    return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: [%s%s%s] needs '%s = ...'", t->path,
                       s->line, s->type, *s->name ? " " : "", s->name, key);
}

/* The library's own error, labelled with the file and line. */
static sinter_status labelled(scene_text *t, int line, sinter_status st)
{
    if (st == SINTER_OK || st == SINTER_ERR_PARSE)
        return st;
    char detail[SINTER_ERROR_TEXT_SIZE];
    snprintf(detail, sizeof(detail), "%s", sinter_last_error(t->ctx));
    return sinter_fail(t->ctx, st, "%s:%d: %s", t->path, line, detail);
}

/* A rectangle's two half lengths into out. */
static sinter_status get_half_lengths(scene_text *t, scene_section *s, double out[2])
{
    const char *key = "half_lengths";
    double *v = NULL;
    size_t n = 0;
    const sinter_status st = scene_get_numbers(t, s, "half_lengths", &v, &n);
    if (st != SINTER_OK)
        return st;
    sinter_status result = SINTER_OK;
    if (n != 2)
        result = sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: %s: expected 2 numbers, got %zu",
                             t->path, scene_find(s, key)->line, key, n);
    else
        out[0] = v[0], out[1] = v[1];
    sinter_free(t->ctx, v);
    return result;
}

/* An optional key: SINTER_OK when absent (out keeps its default). */
static sinter_status optional(sinter_status st)
{
    return st == SINTER_ERR_NOT_FOUND ? SINTER_OK : st;
}

/* kind = mesh: an STL file (relative to the scene's directory), placed by scale, rotate
 * [degrees, about x, then y, then z] and translate [m]. */
static sinter_status add_mesh(scene_text *t, sinter_scene *sc, scene_section *s,
                              const sinter_material *material, size_t *index)
{
    const char *file = NULL;
    TRY(needs(t, s, scene_get_word(t, s, "file", &file), "file"));
    char path[SINTER_PATH_SIZE];
    const int line = scene_find(s, "file")->line;
    TRY(labelled(t, line,
                 file[0] == '/'
                     ? sinter_path_format(t->ctx, path, sizeof(path), "%s", file)
                     : sinter_path_join(t->ctx, path, sizeof(path), sc->directory, file)));
    double scale = 1.0, rotate[3] = {0, 0, 0}, translate[3] = {0, 0, 0}, reach = 0.0;
    int flip = 0;
    TRY(optional(scene_get_double(t, s, "scale", &scale)));
    TRY(optional(scene_get_vec3(t, s, "rotate", rotate)));
    TRY(optional(scene_get_vec3(t, s, "translate", translate)));
    TRY(optional(scene_get_bool(t, s, "flip", &flip)));
    TRY(optional(scene_get_double(t, s, "reach", &reach)));
    for (int d = 0; d < 3; ++d)
        rotate[d] *= 3.14159265358979323846 / 180.0;
    return labelled(t, line,
                    sinter_walls_add_mesh(sc->walls, path, scale, rotate, translate, flip, reach,
                                          material, index));
}

sinter_status scene_wall_add(scene_text *t, sinter_scene *sc, scene_section *s,
                             const sinter_material *material, size_t *index)
{
    const char *kind = "plane";
    sinter_status st = scene_get_word(t, s, "kind", &kind);
    if (st != SINTER_OK && st != SINTER_ERR_NOT_FOUND)
        return st;
    if (strcmp(kind, "mesh") == 0)
        return add_mesh(t, sc, s, material, index);
    double point[3], normal[3];
    TRY(needs(t, s, scene_get_vec3(t, s, "point", point), "point"));
    if (strcmp(kind, "plane") == 0) {
        TRY(needs(t, s, scene_get_vec3(t, s, "normal", normal), "normal"));
        return labelled(t, s->line,
                        sinter_walls_add_plane(sc->walls, point, normal, material, index));
    }
    if (strcmp(kind, "rectangle") == 0) {
        double edge[3], half[2] = {0.0, 0.0};
        TRY(needs(t, s, scene_get_vec3(t, s, "normal", normal), "normal"));
        TRY(needs(t, s, scene_get_vec3(t, s, "edge", edge), "edge"));
        TRY(needs(t, s, get_half_lengths(t, s, half), "half_lengths"));
        return labelled(t, s->line,
                        sinter_walls_add_rectangle(sc->walls, point, normal, edge, half[0], half[1],
                                                   material, index));
    }
    double radius = 0.0;
    if (strcmp(kind, "disc") == 0) {
        TRY(needs(t, s, scene_get_vec3(t, s, "normal", normal), "normal"));
        TRY(needs(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
        return labelled(t, s->line,
                        sinter_walls_add_disc(sc->walls, point, normal, radius, material, index));
    }
    if (strcmp(kind, "cylinder") == 0) {
        double axis[3], half_length = HUGE_VAL;
        int inside = 1;
        TRY(needs(t, s, scene_get_vec3(t, s, "axis", axis), "axis"));
        TRY(needs(t, s, scene_get_double(t, s, "radius", &radius), "radius"));
        st = scene_get_double(t, s, "half_length", &half_length);
        if (st != SINTER_OK && st != SINTER_ERR_NOT_FOUND)
            return st;
        st = scene_get_bool(t, s, "inside", &inside);
        if (st != SINTER_OK && st != SINTER_ERR_NOT_FOUND)
            return st;
        return labelled(t, s->line,
                        sinter_walls_add_cylinder(sc->walls, point, axis, radius, half_length,
                                                  inside, material, index));
    }
    return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                       "%s:%d: kind: expected plane, rectangle, disc, cylinder or mesh, got '%s'",
                       t->path, scene_find(s, "kind")->line, kind);
}

sinter_status scene_wall_spin(scene_text *t, sinter_scene *sc, scene_section *s, size_t index)
{
    double omega = 0.0;
    const sinter_status st = scene_get_double(t, s, "spin", &omega);
    if (st != SINTER_OK && st != SINTER_ERR_NOT_FOUND)
        return st;
    double axis[3], point[3];
    sinter_status sa = scene_get_vec3(t, s, "rotation_axis", axis);
    if (sa == SINTER_OK) { /* a mesh turning about its own axis at `spin` */
        TRY(sinter_walls_get_state(sc->walls, index, point, NULL));
        const sinter_status sp = scene_get_vec3(t, s, "rotation_point", point);
        if (sp != SINTER_OK && sp != SINTER_ERR_NOT_FOUND)
            return sp;
        return labelled(t, scene_find(s, "rotation_axis")->line,
                        sinter_walls_set_rotation(sc->walls, index, point, axis, omega));
    }
    if (sa != SINTER_ERR_NOT_FOUND)
        return sa;
    if (scene_find(s, "rotation_point") != NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE, "%s:%d: rotation_point needs rotation_axis",
                           t->path, scene_find(s, "rotation_point")->line);
    if (st == SINTER_ERR_NOT_FOUND)
        return SINTER_OK;
    return labelled(t, scene_find(s, "spin")->line, sinter_walls_set_spin(sc->walls, index, omega));
}

/* The area [m^2] a servo's pressure acts on: servo_area, else a disc's or a rectangle's. */
static sinter_status servo_area(scene_text *t, sinter_scene *sc, scene_section *s, size_t index,
                                double *area)
{
    const sinter_status st = scene_get_double(t, s, "servo_area", area);
    if (st != SINTER_ERR_NOT_FOUND)
        return st;
    int kind = 0;
    double size[3];
    TRY(sinter_walls_get_kind(sc->walls, index, &kind));
    TRY(sinter_walls_get_shape(sc->walls, index, NULL, NULL, size));
    if (kind == SINTER_WALL_DISC) {
        *area = 3.14159265358979323846 * size[0] * size[0];
        return SINTER_OK;
    }
    if (kind == SINTER_WALL_RECTANGLE) {
        *area = 4.0 * size[0] * size[1];
        return SINTER_OK;
    }
    return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                       "%s:%d: servo_pressure on a wall without an area of its own (a plane): "
                       "give servo_area [m^2]",
                       t->path, scene_find(s, "servo_pressure")->line);
}

sinter_status scene_wall_servo(scene_text *t, sinter_scene *sc, scene_section *s, size_t index)
{
    const int by_pressure = scene_find(s, "servo_pressure") != NULL;
    const char *key = by_pressure ? "servo_pressure" : "servo_force";
    if (by_pressure && scene_find(s, "servo_force") != NULL)
        return sinter_fail(t->ctx, SINTER_ERR_PARSE,
                           "%s:%d: give servo_force [N] or servo_pressure [Pa], not both", t->path,
                           scene_find(s, "servo_force")->line);
    double *v = NULL;
    size_t n = 0;
    TRY(needs(t, s, scene_get_numbers(t, s, key, &v, &n), "servo_force' or 'servo_pressure"));
    const int line = scene_find(s, key)->line;
    double kp = 0.0, ki = 0.0, vmax = 0.0, area = 1.0;
    sinter_status st = SINTER_OK;
    if (n == 0 || (n > 1 && n % 2 != 0))
        st = sinter_fail(t->ctx, SINTER_ERR_PARSE,
                         "%s:%d: %s: expected one value or pairs 't value' [s, N or Pa], got %zu "
                         "numbers",
                         t->path, line, key, n);
    if (st == SINTER_OK)
        st = needs(t, s, scene_get_double(t, s, "servo_kp", &kp), "servo_kp");
    if (st == SINTER_OK) {
        st = scene_get_double(t, s, "servo_ki", &ki);
        st = st == SINTER_ERR_NOT_FOUND ? SINTER_OK : st;
    }
    if (st == SINTER_OK)
        st = needs(t, s, scene_get_double(t, s, "servo_vmax", &vmax), "servo_vmax");
    if (st == SINTER_OK && by_pressure)
        st = servo_area(t, sc, s, index, &area);
    const size_t points = n == 1 ? 1 : n / 2;
    double times[1] = {0.0}, forces[1] = {0.0};
    double *tt = times, *ff = forces;
    if (st == SINTER_OK && n > 1) {
        tt = sinter_calloc(t->ctx, points, sizeof(double));
        ff = sinter_calloc(t->ctx, points, sizeof(double));
        if (tt == NULL || ff == NULL)
            st = SINTER_ERR_NOMEM;
    }
    for (size_t k = 0; k < points && st == SINTER_OK; ++k) {
        tt[k] = n == 1 ? 0.0 : v[2 * k];
        ff[k] = (n == 1 ? v[0] : v[2 * k + 1]) * area; /* a pressure on its area */
    }
    if (st == SINTER_OK)
        st = labelled(t, line,
                      sinter_walls_set_servo(sc->walls, index, points, tt, ff, kp, ki, vmax));
    if (tt != times) {
        sinter_free(t->ctx, tt);
        sinter_free(t->ctx, ff);
    }
    sinter_free(t->ctx, v);
    return st;
}
