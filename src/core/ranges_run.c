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

void sinter_ranges_run_two_passes(int threads, int count, void (*interior)(void *data, int t),
                                  void (*rest)(void *data, int t), void *data)
{
    const int team = threads < count ? threads : count, shared = team > 1 && team < count;
    if (team <= 1) {
        for (int t = 0; t < count; ++t)
            interior(data, t);
        for (int t = 0; t < count; ++t)
            rest(data, t);
        return;
    }
#pragma omp parallel num_threads(team)
    {
        if (shared) {
#pragma omp for schedule(dynamic, 1) nowait
            for (int t = 0; t < count; ++t)
                interior(data, t);
#pragma omp for schedule(dynamic, 1) nowait
            for (int t = 0; t < count; ++t)
                rest(data, t);
        } else {
#pragma omp for schedule(static) nowait
            for (int t = 0; t < count; ++t)
                interior(data, t);
#pragma omp for schedule(static) nowait
            for (int t = 0; t < count; ++t)
                rest(data, t);
        }
    }
}
