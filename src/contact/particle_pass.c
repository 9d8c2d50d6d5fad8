/* A pass over the particles on the pair partition's ranges (see particle_pass.h). */
#include "contact/particle_pass.h"

#include "contact/neighbors.h"
#include "core/ranges_run.h"

typedef struct pass_job {
    const sinter_particle_ranges *r;
    sinter_particle_range_fn fn;
    void *data;
} pass_job;

static void pass_range(void *data, int t)
{
    const pass_job *job = data;
    job->fn(job->data, t, sinter_particle_range_lo(job->r, t),
            sinter_particle_range_lo(job->r, t + 1));
}

int sinter_particle_pass(const sinter_ctx *ctx, const sinter_contact_list *pp, size_t n,
                         sinter_particle_range_fn fn, void *data)
{
    const sinter_particle_ranges r =
        sinter_chunks_particle_ranges(pp != NULL ? &pp->chunks : NULL, n, sinter_threads(ctx));
    if (r.plo == NULL) {
        fn(data, 0, 0, n);
        return 1;
    }
    pass_job job = {&r, fn, data};
    sinter_ranges_run(r.team, r.count, pass_range, &job);
    return r.count;
}
