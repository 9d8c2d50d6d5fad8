/* The heat stage's series columns of `mpiexec sinter run` (run_mpi_heat.h). */
#include "run_mpi_heat.h"

#include <math.h>
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

size_t run_mpi_heat_columns(const sinter_stepper *st, int beam)
{
    return (frozen_on(st) ? FROZEN_COLUMNS : 0) + (beam ? LIT_COLUMNS : 0);
}

void run_mpi_heat_header(FILE *csv, const sinter_stepper *st, int beam)
{
    for (size_t k = 0; frozen_on(st) && k < FROZEN_COLUMNS; ++k)
        fprintf(csv, ",%s", FROZEN_NAMES[k]);
    if (beam)
        fputs(",lit particles [1],lit mean temperature [K]", csv);
}

int run_mpi_heat_observe(const sinter_stepper *st, int beam, sinter_particles *ps,
                         sinter_mpi_domain *domain, double *row)
{
    size_t c = 0;
    for (size_t k = 0; frozen_on(st) && k < FROZEN_COLUMNS; ++k, ++c)
        if (sinter_stepper_get_option(st, FROZEN_KEYS[k], row + c) != SINTER_OK)
            row[c] = NAN;
    if (!beam)
        return 1;
    /* the particles a beam marked SINTER_PARTICLE_LIT (particle state: it migrates with them)
     * and their temperatures, in index order here, then summed over the ranks */
    size_t owned = 0;
    const uint32_t *flags = NULL;
    const double *theta = NULL;
    int ok = sinter_particles_owned_count(ps, &owned) == SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_FLAGS, (const void **)&flags, NULL,
                                        NULL) == SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&theta, NULL,
                                        NULL) == SINTER_OK;
    double sum[3] = {0.0, 0.0, ok ? 0.0 : 1.0}; /* count, temperatures, ranks that failed */
    for (size_t i = 0; ok && i < owned; ++i)
        if (flags[i] & (uint32_t)SINTER_PARTICLE_LIT) {
            sum[0] += 1.0;
            sum[1] += theta[i];
        }
    if (flags != NULL)
        sinter_particles_release(ps, SINTER_FIELD_FLAGS);
    if (theta != NULL)
        sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
    if (sinter_mpi_reduce(sum, 3, SINTER_MPI_F64, SINTER_MPI_SUM, domain) != 0 || sum[2] != 0.0)
        return 0;
    row[c] = sum[0];
    row[c + 1] = sum[0] > 0.0 ? sum[1] / sum[0] : 0.0;
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
