/* The heat stage's series columns of `mpiexec sinter run` (run_mpi_heat.h). */
#include "run_mpi_heat.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { FROZEN_COLUMNS = 5, LIT_COLUMNS = 2 };

static const char *const FROZEN_NAMES[FROZEN_COLUMNS] = {
    "frozen [1]", "frozen time [s]", "heat steps [1]", "wake-ups [1]", "heat step [s]"};
static const char *const FROZEN_KEYS[FROZEN_COLUMNS] = {
    "frozen_active", "frozen_time", "frozen_steps", "frozen_wakeups", "frozen_dt"};

static int frozen_on(const sinter_stepper *st)
{
    double on = 0.0;
    return sinter_stepper_get_option(st, "frozen_heat", &on) == SINTER_OK && on != 0.0;
}

void run_mpi_heat_read(const char *path, run_mpi_heat_spec *spec)
{
    spec->bins = 0;
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return;
    char line[1024];
    int in = 0;
    while (fgets(line, sizeof(line), fp) != NULL) {
        char *hash = strchr(line, '#');
        if (hash != NULL)
            *hash = '\0';
        const char *s = line + strspn(line, " \t");
        if (*s == '[') {
            in = strncmp(s, "[output]", 8) == 0;
            continue;
        }
        const char *eq = strchr(s, '=');
        if (!in || eq == NULL || strncmp(s, "temperature_bins", 16) != 0)
            continue;
        double v[3];
        const char *at = eq + 1;
        int got = 0;
        for (; got < 3; ++got) {
            at += strspn(at, " \t,");
            char *end = NULL;
            v[got] = strtod(at, &end);
            if (end == at)
                break;
            at = end;
        }
        if (got == 3 && v[0] < v[1] && v[2] >= 1.0 && v[2] <= RUN_MPI_HEAT_MAX_BINS) {
            spec->lo = v[0];
            spec->hi = v[1];
            spec->bins = (size_t)v[2];
        }
    }
    fclose(fp);
}

static size_t bin_columns(const run_mpi_heat_spec *spec)
{
    return spec->bins > 0 ? spec->bins + 2 : 0;
}

size_t run_mpi_heat_columns(const sinter_stepper *st, const run_mpi_heat_spec *spec)
{
    return (frozen_on(st) ? FROZEN_COLUMNS : 0) + bin_columns(spec) +
           (spec->beam ? LIT_COLUMNS : 0);
}

void run_mpi_heat_header(FILE *csv, const sinter_stepper *st, const run_mpi_heat_spec *spec)
{
    for (size_t k = 0; frozen_on(st) && k < FROZEN_COLUMNS; ++k)
        fprintf(csv, ",%s", FROZEN_NAMES[k]);
    /* the histogram's labels as scene_run.c writes them */
    const size_t columns = bin_columns(spec);
    const double width = (spec->hi - spec->lo) / (double)(spec->bins ? spec->bins : 1);
    for (size_t k = 0; k < columns; ++k) {
        if (k == 0)
            fprintf(csv, ",temperature below %g [1]", spec->lo);
        else if (k == columns - 1)
            fprintf(csv, ",temperature %g or more [1]", spec->hi);
        else
            fprintf(csv, ",temperature %g-%g [1]", spec->lo + width * (double)(k - 1),
                    spec->lo + width * (double)k);
    }
    if (spec->beam)
        fputs(",lit particles [1],lit mean temperature [K]", csv);
}

int run_mpi_heat_observe(const sinter_stepper *st, const run_mpi_heat_spec *spec,
                         sinter_particles *ps, sinter_mpi_domain *domain, double *row)
{
    size_t c = 0;
    for (size_t k = 0; frozen_on(st) && k < FROZEN_COLUMNS; ++k, ++c)
        if (sinter_stepper_get_option(st, FROZEN_KEYS[k], row + c) != SINTER_OK)
            row[c] = NAN;
    const size_t bins = bin_columns(spec);
    if (bins == 0 && !spec->beam)
        return 1;
    /* the owned particles' histogram (scene_run.c's observe_temperatures) and those a beam
     * marked SINTER_PARTICLE_LIT (particle state: it migrates with them) with their
     * temperatures, in index order here, then summed over the ranks (counts: exact) */
    size_t owned = 0;
    const uint32_t *flags = NULL;
    const double *theta = NULL;
    int ok = sinter_particles_owned_count(ps, &owned) == SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_FLAGS, (const void **)&flags, NULL,
                                        NULL) == SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&theta, NULL,
                                        NULL) == SINTER_OK;
    double *sum = calloc(bins + 3, sizeof(double)); /* bins, lit count, lit temperatures, failed */
    ok = ok && sum != NULL;
    const double width = (spec->hi - spec->lo) / (double)(spec->bins ? spec->bins : 1);
    for (size_t i = 0; ok && i < owned; ++i) {
        if (bins > 0) {
            size_t k;
            if (theta[i] < spec->lo)
                k = 0;
            else if (!(theta[i] < spec->hi)) /* at hi or above */
                k = bins - 1;
            else {
                const double b = floor((theta[i] - spec->lo) / width);
                k = 1 + (b < (double)spec->bins ? (size_t)b : spec->bins - 1);
            }
            sum[k] += 1.0;
        }
        if (flags[i] & (uint32_t)SINTER_PARTICLE_LIT) {
            sum[bins] += 1.0;
            sum[bins + 1] += theta[i];
        }
    }
    if (flags != NULL)
        sinter_particles_release(ps, SINTER_FIELD_FLAGS);
    if (theta != NULL)
        sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
    double failed[1] = {ok ? 0.0 : 1.0}; /* (the ranks that failed, before the sums) */
    if (sinter_mpi_reduce(failed, 1, SINTER_MPI_F64, SINTER_MPI_SUM, domain) != 0 ||
        failed[0] != 0.0) {
        free(sum);
        return 0;
    }
    if (sinter_mpi_reduce(sum, bins + 2, SINTER_MPI_F64, SINTER_MPI_SUM, domain) != 0) {
        free(sum);
        return 0;
    }
    for (size_t k = 0; k < bins; ++k)
        row[c + k] = sum[k];
    c += bins;
    if (spec->beam) {
        row[c] = sum[bins];
        row[c + 1] = sum[bins] > 0.0 ? sum[bins + 1] / sum[bins] : 0.0;
    }
    free(sum);
    return 1;
}

sinter_status run_mpi_heat_checkpoint(sinter_stepper *st, sinter_particles *ps, MPI_Comm comm,
                                      const char *path, int *skipped)
{
    double active = 0.0;
    *skipped =
        sinter_stepper_get_option(st, "frozen_active", &active) == SINTER_OK && active != 0.0;
    return *skipped ? SINTER_OK : sinter_mpi_checkpoint_write(st, ps, comm, path);
}
