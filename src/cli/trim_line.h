/* Blanks and line ends taken off both ends of a scene file's line, in place (the MPI runner's
 * readers of scene sections: run_mpi.c, run_mpi_pour.c, run_mpi_fields.c). */
#ifndef SINTER_CLI_TRIM_LINE_H
#define SINTER_CLI_TRIM_LINE_H

#include <string.h>

static inline void trim(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n'))
        s[--n] = '\0';
    size_t k = 0;
    while (s[k] == ' ' || s[k] == '\t')
        ++k;
    memmove(s, s + k, n - k + 1);
}

#endif
