/* Continuous insertion in `mpiexec sinter run` (run_mpi_insert.h). */
#include "run_mpi_insert.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void run_mpi_insert_header(FILE *csv)
{
    fputs(",inserted mass [kg],insertion target [kg]", csv);
}

int run_mpi_insert_observe(const sinter_stepper *st, double *row)
{
    return sinter_stepper_get_insertion(st, &row[0], &row[1], NULL, NULL) == SINTER_OK;
}

/* The three numbers after '=' on a line "key = x y z" into v; 1 on success. */
static int vector(const char *line, double v[3])
{
    const char *eq = strchr(line, '=');
    if (eq == NULL)
        return 0;
    char *end = NULL;
    const char *at = eq + 1;
    for (int d = 0; d < 3; ++d, at = end) {
        v[d] = strtod(at, &end);
        if (end == at || !isfinite(v[d]))
            return 0;
    }
    return 1;
}

void run_mpi_insert_box(const char *path, double lo[3], double hi[3])
{
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return;
    char line[1024];
    int in = 0;
    while (fgets(line, sizeof(line), fp) != NULL) {
        const char *s = line + strspn(line, " \t");
        if (*s == '[') {
            in = strncmp(s, "[insert]", 8) == 0;
            continue;
        }
        double v[3];
        const int lower = strncmp(s, "box_min", 7) == 0, upper = strncmp(s, "box_max", 7) == 0;
        if (!in || !(lower || upper) || !vector(s, v))
            continue;
        for (int d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], v[d]);
            hi[d] = fmax(hi[d], v[d]);
        }
    }
    fclose(fp);
}
