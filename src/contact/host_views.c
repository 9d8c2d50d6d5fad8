/* The state view and contact batches of host submodels: see host_views.h. */
#include "contact/host_views.h"

#include <string.h>

void sinter_host_state_view(sinter_state_view *v, const sinter_particles *ps,
                            const sinter_walls *walls, double *wall_arrays, double t, double dt)
{
    const size_t nw = walls != NULL ? walls->count : 0;
    for (size_t k = 0; k < nw; ++k) {
        const sinter_wall *w = &walls->wall[k];
        memcpy(wall_arrays + 3 * k, w->p, 3 * sizeof(double));
        memcpy(wall_arrays + 3 * (nw + k), w->n, 3 * sizeof(double));
        memcpy(wall_arrays + 3 * (2 * nw + k), w->u, 3 * sizeof(double));
    }
    memset(v, 0, sizeof(*v));
    v->count = ps->count;
    v->position = ps->x;
    v->velocity = ps->v;
    v->spin = ps->w;
    v->radius = ps->radius;
    v->mass = ps->mass;
    v->inertia = ps->inertia;
    v->temperature = ps->temperature;
    v->material = ps->material;
    v->wall_count = nw;
    v->wall_point = wall_arrays;
    v->wall_normal = wall_arrays + 3 * nw;
    v->wall_velocity = wall_arrays + 6 * nw;
    v->time = t;
    v->dt = dt;
}

void sinter_host_contact_batch(const sinter_contact_list *c, int kind, const double *radius,
                               sinter_contact_batch *b)
{
    memset(b, 0, sizeof(*b));
    b->count = c->count;
    b->kind = kind;
    b->i = c->i;
    b->j = c->j;
    b->normal = c->n;
    b->overlap = c->delta;
    b->distance = c->dist;
    b->contact_radius = radius;
    b->area = c->area;
    b->branch = c->branch;
}
