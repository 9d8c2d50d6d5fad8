/* Bonds that hold in tension in `mpiexec sinter run` (run_mpi_bonds.h). */
#include "run_mpi_bonds.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LINE = 1 << 16 };

static const char NAME[] = "broken bonds [1]";

int run_mpi_bonds_key(const char *section, const char *line)
{
    if (strcmp(section, "force power_law") != 0 || strncmp(line, "bond_strength", 13) != 0)
        return 0;
    const char *eq = strchr(line, '=');
    if (eq == NULL || strspn(line + 13, " \t") != (size_t)(eq - line - 13))
        return 0;              /* another key that starts alike */
    return atof(eq + 1) > 0.0; /* as the power law: bonds hold for a strength above 0 */
}

void run_mpi_bonds_header(FILE *csv)
{
    fprintf(csv, ",%s", NAME);
}

/* The last row's value in the column NAME of the series.csv at `path`; nan without one. */
static double last_count(const char *path)
{
    static char head[LINE], line[LINE], last[LINE];
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return NAN;
    int ok = fgets(head, sizeof(head), fp) != NULL;
    last[0] = '\0';
    while (ok && fgets(line, sizeof(line), fp) != NULL)
        memcpy(last, line, sizeof(line));
    fclose(fp);
    long column = -1, k = 0;
    for (char *cell = ok ? strtok(head, ",\n") : NULL; cell != NULL && column < 0;
         cell = strtok(NULL, ",\n"), ++k)
        if (strcmp(cell, NAME) == 0)
            column = k;
    const char *at = last[0] != '\0' && column >= 0 ? last : NULL;
    for (long c = 0; at != NULL && c < column; ++c) {
        at = strchr(at, ',');
        at = at != NULL ? at + 1 : NULL;
    }
    return at != NULL ? strtod(at, NULL) : NAN;
}

int run_mpi_bonds_resume(const sinter_stepper *st, MPI_Comm comm, const char *series,
                         int64_t *offset)
{
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    double count = rank == 0 ? last_count(series) : 0.0;
    MPI_Bcast(&count, 1, MPI_DOUBLE, 0, comm);
    sinter_stepper_stats global;
    memset(&global, 0, sizeof(global));
    global.struct_size = sizeof(global);
    int ok =
        sinter_stepper_get_stats_global(st, &global) == SINTER_OK && count >= 0.0 && count < 9e15;
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm);
    if (all)
        *offset = (int64_t)count - (int64_t)global.bonds_broken;
    return all;
}
