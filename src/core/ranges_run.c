/* A loop over work ranges that enters OpenMP only for a team of two or more (ranges_run.h). */
#include "core/ranges_run.h"

void sinter_ranges_run(int team, int count, void (*range)(void *data, int t), void *data)
{
    if (team <= 1) {
        for (int t = 0; t < count; ++t)
            range(data, t);
        return;
    }
#pragma omp parallel for num_threads(team) schedule(static)
    for (int t = 0; t < count; ++t)
        range(data, t);
}
