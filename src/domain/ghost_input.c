/* Ghosts of other subdomains supplied by the host (include/sinter_domain.h,
 * sinter_particles_set_ghosts): checked first, then copied after the owned particles. */
#include <math.h>
#include <string.h>

#include "domain/domain.h"

static int finite3(const double *a)
{
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

/* SINTER_OK when ghost k can enter the set, else the error naming it. */
static sinter_status check_ghost(sinter_particles *ps, const sinter_ghost_fields *g, size_t k)
{
    const char *bad = NULL;
    if (!finite3(g->position + 3 * k))
        bad = "position";
    else if (!finite3(g->velocity + 3 * k))
        bad = "velocity";
    else if (!finite3(g->spin + 3 * k))
        bad = "spin";
    else if (!finite3(g->rotation + 3 * k))
        bad = "rotation";
    else if (!(g->radius[k] > 0.0) || !isfinite(g->radius[k]))
        bad = "radius";
    else if (!(g->mass[k] > 0.0) || !isfinite(g->mass[k]))
        bad = "mass";
    else if (!(g->inertia[k] > 0.0) || !isfinite(g->inertia[k]))
        bad = "inertia";
    else if (!(g->temperature[k] > 0.0) || !isfinite(g->temperature[k]))
        bad = "temperature";
    if (bad != NULL)
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "sinter_particles_set_ghosts: ghost %zu (id %llu, subdomain %d) has a "
                           "%s that is not finite and > 0 (or not finite)",
                           k, (unsigned long long)g->id[k], g->owner ? g->owner[k] : -1, bad);
    const int32_t m = g->material[k];
    if (m < 0 || m >= SINTER_MAX_MATERIALS || !ps->material_used[m])
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "sinter_particles_set_ghosts: ghost %zu (id %llu) has material %d, "
                           "which is not registered in this particle set (register the same "
                           "materials on every subdomain)",
                           k, (unsigned long long)g->id[k], (int)m);
    if (sinter_id_index_find(&ps->id_index, ps, g->id[k]) != SIZE_MAX)
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "sinter_particles_set_ghosts: ghost %zu has id %llu, the id of an "
                           "owned particle of this subdomain",
                           k, (unsigned long long)g->id[k]);
    return SINTER_OK;
}

sinter_status sinter_particles_set_ghosts(sinter_particles *ps, const sinter_ghost_fields *g)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, g);
    if (g->struct_size != sizeof(sinter_ghost_fields))
        return sinter_fail(ps->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_particles_set_ghosts: struct_size %zu, expected %zu",
                           g->struct_size, sizeof(sinter_ghost_fields));
    const size_t n = g->count;
    if (n > 0) {
        SINTER_CHECK_NULL(ps->ctx, g->id);
        SINTER_CHECK_NULL(ps->ctx, g->position);
        SINTER_CHECK_NULL(ps->ctx, g->velocity);
        SINTER_CHECK_NULL(ps->ctx, g->spin);
        SINTER_CHECK_NULL(ps->ctx, g->rotation);
        SINTER_CHECK_NULL(ps->ctx, g->radius);
        SINTER_CHECK_NULL(ps->ctx, g->mass);
        SINTER_CHECK_NULL(ps->ctx, g->inertia);
        SINTER_CHECK_NULL(ps->ctx, g->temperature);
        SINTER_CHECK_NULL(ps->ctx, g->material);
    }
    /* the id index covers the owned particles only (ghosts share no id with them) */
    sinter_status s = sinter_id_index_update(&ps->id_index, ps);
    for (size_t k = 0; k < n && s == SINTER_OK; ++k)
        s = check_ghost(ps, g, k);
    if (s == SINTER_OK)
        s = sinter_particles_make_ghost_rows(ps, n);
    if (s != SINTER_OK || n == 0)
        return s;
    const size_t first = ps->count - n;
    memcpy(ps->x + 3 * first, g->position, 3 * n * sizeof(double));
    memcpy(ps->v + 3 * first, g->velocity, 3 * n * sizeof(double));
    memcpy(ps->w + 3 * first, g->spin, 3 * n * sizeof(double));
    memcpy(ps->rot + 3 * first, g->rotation, 3 * n * sizeof(double));
    memcpy(ps->radius + first, g->radius, n * sizeof(double));
    memcpy(ps->mass + first, g->mass, n * sizeof(double));
    memcpy(ps->inertia + first, g->inertia, n * sizeof(double));
    memcpy(ps->temperature + first, g->temperature, n * sizeof(double));
    memcpy(ps->material + first, g->material, n * sizeof(int32_t));
    memcpy(ps->id + first, g->id, n * sizeof(uint64_t));
    for (size_t k = 0; k < n; ++k)
        ps->flags[first + k] = g->flags != NULL ? g->flags[k] : 0u;
    return SINTER_OK;
}
