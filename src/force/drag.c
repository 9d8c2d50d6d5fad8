/*
 * Interstitial drag of seed 000 eq. 20: f_i = -c_env (v_i - v_env), with c_env the particle's
 * material SINTER_MAT_DRAG_COEFFICIENT [kg/s] and v_env the medium's velocity from the model
 * parameters "vx", "vy", "vz" [m/s] (default 0, the seed's v_env ~ 0).
 *
 * Each particle on its own: on the pair partition's particle ranges (contact/chunks.h) when the
 * step has threads and the contact law a partition, so each thread writes the forces of the
 * particles whose contact forces it sums; the same operations on any thread count.
 */
#include "contact/chunks.h"
#include "contact/neighbors.h"
#include "force_model.h"

static void drag_range(const sinter_force_model *fm, const sinter_force_eval *e,
                       const double *coefficient, size_t lo, size_t hi)
{
    const sinter_particles *ps = e->ps;
    const double *v = ps->v;
    const int32_t *material = ps->material;
    double *force = e->force;
    for (size_t i = lo; i < hi; ++i) {
        const double c = coefficient[material[i]];
        for (int d = 0; d < 3; ++d)
            force[3 * i + d] -= c * (v[3 * i + d] - fm->param[d]); /* eq. 20 */
    }
}

static sinter_status drag_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    double coefficient[SINTER_MAX_MATERIALS];
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        coefficient[m] = ps->materials[m].value[SINTER_MAT_DRAG_COEFFICIENT];
    const sinter_particle_ranges r = sinter_chunks_particle_ranges(
        e->pp != NULL ? &e->pp->chunks : NULL, ps->count, sinter_threads(e->ctx));
    if (r.plo == NULL) {
        drag_range(fm, e, coefficient, 0, ps->count);
        return SINTER_OK;
    }
#pragma omp parallel for num_threads(r.team) schedule(static)
    for (int t = 0; t < r.count; ++t)
        drag_range(fm, e, coefficient, sinter_particle_range_lo(&r, t),
                   sinter_particle_range_lo(&r, t + 1));
    return SINTER_OK;
}

const sinter_force_ops sinter_force_drag = {
    "drag", 0, 0, 0, {"vx", "vy", "vz", NULL}, {0.0, 0.0, 0.0}, drag_eval, NULL, NULL, NULL};
