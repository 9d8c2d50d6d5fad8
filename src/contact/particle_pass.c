/* A pass over the particles on the pair partition's ranges (see particle_pass.h). */
#include "contact/particle_pass.h"

#include "contact/neighbors.h"

int sinter_particle_pass(const sinter_ctx *ctx, const sinter_contact_list *pp, size_t n,
                         sinter_particle_range_fn fn, void *data)
{
    const sinter_particle_ranges r =
        sinter_chunks_particle_ranges(pp != NULL ? &pp->chunks : NULL, n, sinter_threads(ctx));
    if (r.plo == NULL) {
        fn(data, 0, 0, n);
        return 1;
    }
#pragma omp parallel for num_threads(r.team) schedule(static)
    for (int t = 0; t < r.count; ++t)
        fn(data, t, sinter_particle_range_lo(&r, t), sinter_particle_range_lo(&r, t + 1));
    return r.count;
}
