#define _POSIX_C_SOURCE 200809L
/*
 * The pour of `mpiexec -n N sinter run` (issue 44), the serial runner's programme
 * (io/scene_run.c: begin, run_program, end_pour) on the ranks:
 *  - the particles are the scene's [particles] (rank 0 creates them as the serial runner does,
 *    run_mpi.c spreads them with sinter_mpi_distribute);
 *  - after the first sample every wall is held (sinter_walls_set_motion_start at HUGE_VAL);
 *  - after each sample, once the pour has lasted t_min, it ends when the kinetic energy per
 *    particle is below ke_per_particle: the energy is the series' column, every rank's partial
 *    sum summed exactly (sinter_mpi_reduce), divided by the particles over all ranks, so every
 *    rank takes the same decision at the same sample, and on one rank the serial one;
 *  - at its end the walls' motions start and the end time counts from then (the origin);
 *    a pour that has not come to rest within t_max fails, as serially.
 * The serial runner also delays a [stepper] temperature_schedule (the furnace) to the pour's
 * end through an internal call; the MPI runner refuses that combination (none of the example
 * scenes has it). The state (pouring or not, the origin) travels beside the MPI checkpoint in
 * CHECKPOINT.pour, a line of text, so that a restart continues the programme; the walls' motion
 * starts travel in the checkpoint itself (the stepper's global part).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_mpi_pour.h"
#include "trim_line.h"

enum { LINE_SIZE = 1024, PATH_SIZE = 4096 };

int mpi_pour_read(const char *scene_path, mpi_pour *p)
{
    memset(p, 0, sizeof(*p));
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
            p->on |= strcmp(section, "[pour]") == 0;
            continue;
        }
        char *eq = strchr(line, '=');
        if (eq == NULL)
            continue;
        *eq = '\0';
        trim(line);
        const double value = strtod(eq + 1, NULL);
        if (strcmp(section, "[pour]") == 0 && strcmp(line, "ke_per_particle") == 0)
            p->ke = value;
        else if (strcmp(section, "[pour]") == 0 && strcmp(line, "t_min") == 0)
            p->t_min = value;
        else if (strcmp(section, "[pour]") == 0 && strcmp(line, "t_max") == 0)
            p->t_max = value;
        else if (strcmp(section, "[stepper]") == 0 && strcmp(line, "temperature_schedule") == 0)
            p->furnace = 1;
    }
    fclose(fp);
    return 1;
}

static sinter_status hold_walls(sinter_walls *walls, double start)
{
    size_t n = 0;
    sinter_status st = sinter_walls_count(walls, &n);
    for (size_t k = 0; k < n && st == SINTER_OK; ++k)
        st = sinter_walls_set_motion_start(walls, k, start);
    return st;
}

sinter_status mpi_pour_begin(mpi_pour *p, sinter_walls *walls, double t)
{
    p->pouring = p->on;
    p->start = p->origin = t;
    p->energy = NAN;
    /* io/scene_run.c's begin(): the pour's start after the first sample, the walls held */
    return p->on ? hold_walls(walls, HUGE_VAL) : SINTER_OK;
}

double mpi_pour_phase_end(const mpi_pour *p, double end_time)
{
    return p->pouring ? p->start + p->t_max : p->origin + end_time;
}

sinter_status mpi_pour_sample(mpi_pour *p, sinter_walls *walls, sinter_particles *ps,
                              sinter_mpi_domain *domain, double t, double ke, int *ended)
{
    *ended = 0;
    if (!p->pouring)
        return SINTER_OK;
    size_t owned = 0;
    sinter_status st = sinter_particles_owned_count(ps, &owned);
    uint64_t count[2] = {(uint64_t)owned, st == SINTER_OK ? 0u : 1u}; /* and failed ranks */
    if (sinter_mpi_reduce(count, 2, SINTER_MPI_U64, SINTER_MPI_SUM, domain) != 0)
        return SINTER_ERR_IO;
    if (count[1] != 0)
        return SINTER_ERR_STATE;
    /* run_program's test after each sample, over the owned particles of every rank (the
     * serial runner divides by its own; the same bits on one rank) */
    p->energy = ke / (double)count[0];
    if (!(t - p->start >= p->t_min) || !(p->energy < p->ke))
        return SINTER_OK;
    st = hold_walls(walls, t); /* end_pour(): their motions start now */
    if (st != SINTER_OK)
        return st;
    p->origin = t;
    p->pouring = 0;
    *ended = 1;
    return SINTER_OK;
}

int mpi_pour_save(const mpi_pour *p, const char *checkpoint_path)
{
    char path[PATH_SIZE], tmp[PATH_SIZE + 8];
    snprintf(path, sizeof(path), "%s.pour", checkpoint_path);
    snprintf(tmp, sizeof(tmp), "%s.tmp", path);
    FILE *fp = fopen(tmp, "w");
    if (fp == NULL)
        return 0;
    /* %a: the times' bits */
    int ok = fprintf(fp, "sinter pour 1 pouring %d start %a origin %a\n", p->pouring, p->start,
                     p->origin) > 0;
    ok = fclose(fp) == 0 && ok;
    return ok && rename(tmp, path) == 0;
}

int mpi_pour_load(mpi_pour *p, const char *checkpoint_path)
{
    char path[PATH_SIZE], line[LINE_SIZE];
    snprintf(path, sizeof(path), "%s.pour", checkpoint_path);
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return 0;
    int pouring = 0, ok = fgets(line, sizeof(line), fp) != NULL;
    fclose(fp);
    double start = 0.0, origin = 0.0;
    ok = ok && sscanf(line, "sinter pour 1 pouring %d start %la origin %la", &pouring, &start,
                      &origin) == 3;
    ok = ok && (pouring == 0 || pouring == 1) && isfinite(start) && isfinite(origin);
    if (ok) {
        p->pouring = pouring;
        p->start = start;
        p->origin = origin;
    }
    return ok;
}
