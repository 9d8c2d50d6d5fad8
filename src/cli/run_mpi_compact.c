#define _POSIX_C_SOURCE 200809L
/*
 * The compaction of `mpiexec -n N sinter run` (issue 44): a scene's [compact] without a [pour]
 * with the explicit or staggered stepper, as the serial runner does it (io/scene_run.c,
 * compact(): sinter_pack_compact on the scene's particles, its own walls and stepper, before
 * the first step). Every rank reads the scene, so every rank holds all its particles before
 * they are spread (run_mpi.c): rank 0 compacts its copy, the one sinter_mpi_distribute spreads
 * (the other ranks give theirs up), so that it is the serial runner's, and the decomposition's
 * box is taken from it. The compaction itself is not decomposed: it costs rank 0 what it
 * costs the serial runner. The options are the scene's [compact] keys (io/scene.c,
 * build_compact, which has checked them at the load); a [compact] after a [pour] (which would
 * gather the poured bed) is refused by run_mpi.c.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_mpi_compact.h"

enum { LINE_SIZE = 1024 };

static void trim(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n'))
        s[--n] = '\0';
    size_t k = 0;
    while (s[k] == ' ' || s[k] == '\t')
        ++k;
    memmove(s, s + k, n - k + 1);
}

/* The value of one key of [compact] into the options (an unknown key: nothing). */
static void take(sinter_compaction_options *o, const char *key, const char *value)
{
    const struct {
        const char *key;
        double *value;
    } numbers[] = {
        {"volume_fraction", &o->volume_fraction}, {"friction", &o->friction},
        {"restitution", &o->restitution},         {"velocity", &o->velocity},
        {"max_pressure", &o->max_pressure},       {"ke_per_particle", &o->ke_per_particle},
        {"relax_time_max", &o->relax_time_max},   {"dt", &o->dt}};
    for (size_t k = 0; k < sizeof(numbers) / sizeof(numbers[0]); ++k)
        if (strcmp(key, numbers[k].key) == 0)
            *numbers[k].value = strtod(value, NULL);
    if (strcmp(key, "box_min") == 0 || strcmp(key, "box_max") == 0) {
        double *v = key[5] == 'i' ? o->box_min : o->box_max;
        char *end = NULL;
        for (int d = 0; d < 3; ++d, value = end)
            v[d] = strtod(value, &end);
    }
    if (strcmp(key, "stop_at_jamming") == 0)
        o->stop_at_jamming =
            strcmp(value, "yes") == 0 || strcmp(value, "true") == 0 || strcmp(value, "1") == 0;
}

int mpi_compact_read(const char *scene_path, mpi_compact *c)
{
    memset(c, 0, sizeof(*c));
    if (sinter_compaction_options_init(&c->options, sizeof(c->options)) != SINTER_OK)
        return 0;
    FILE *fp = fopen(scene_path, "r");
    if (fp == NULL)
        return 0;
    char line[LINE_SIZE], section[64] = "";
    while (fgets(line, sizeof(line), fp) != NULL) {
        char *hash = strchr(line, '#');
        if (hash != NULL)
            *hash = '\0';
        trim(line);
        if (line[0] == '[') {
            snprintf(section, sizeof(section), "%.63s", line);
            c->on |= strcmp(section, "[compact]") == 0;
            continue;
        }
        char *eq = strchr(line, '=');
        if (eq == NULL || strcmp(section, "[compact]") != 0)
            continue;
        *eq = '\0';
        char *value = eq + 1;
        trim(line);
        trim(value);
        take(&c->options, line, value);
    }
    fclose(fp);
    return 1;
}

sinter_status mpi_compact_run(const mpi_compact *c, sinter_particles *particles, char *message,
                              size_t size)
{
    message[0] = '\0';
    if (!c->on)
        return SINTER_OK;
    sinter_compaction_result res;
    memset(&res, 0, sizeof(res));
    res.struct_size = sizeof(res);
    const sinter_status st = sinter_pack_compact(particles, &c->options, &res);
    if (st == SINTER_OK) /* io/scene_run.c's line */
        snprintf(message, size,
                 "compacted: box %g x %g x %g m, volume fraction %.4f%s, coordination %.3f, "
                 "largest overlap %.3g of the radius, wall stress %g Pa, %g s simulated",
                 res.box_max[0] - res.box_min[0], res.box_max[1] - res.box_min[1],
                 res.box_max[2] - res.box_min[2], res.volume_fraction,
                 res.jammed ? " (jammed)" : "", res.coordination, res.max_overlap_ratio,
                 res.pressure, res.time);
    return st;
}
