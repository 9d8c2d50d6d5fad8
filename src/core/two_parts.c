/* Two parts side by side (see two_parts.h). */
#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/two_parts.h"

void sinter_two_parts(int threads, void (*part)(void *data, int which), void *data)
{
#ifdef _OPENMP
    if (threads == 2) {
#pragma omp parallel num_threads(2)
        {
            if (omp_get_num_threads() < 2) { /* OpenMP gave one thread (a limit, nesting) */
                part(data, 0);
                part(data, 1);
            } else {
                part(data, omp_get_thread_num() == 1);
            }
        }
        return;
    }
#endif
    (void)threads;
    part(data, 0);
    part(data, 1);
}
