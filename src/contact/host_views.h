/*
 * What host submodels (force, heat and electric callbacks, include/sinter_submodel.h) see: the
 * state view of the particles and walls, and a contact list as a batch. One copy for every kind
 * of host submodel.
 */
#ifndef SINTER_CONTACT_HOST_VIEWS_H
#define SINTER_CONTACT_HOST_VIEWS_H

#include "contact/contacts.h"
#include "particles/particles.h"
#include "sinter_submodel.h"
#include "walls/walls.h"

/* v over ps and walls (NULL: none) at time t with step dt; wall_arrays holds 9 doubles per
 * wall (points, normals, velocities, written here) and must outlive the view. */
void sinter_host_state_view(sinter_state_view *v, const sinter_particles *ps,
                            const sinter_walls *walls, double *wall_arrays, double t, double dt);

/* b over list c of `kind` (a sinter_contact_kind) with the contact radii `radius`. */
void sinter_host_contact_batch(const sinter_contact_list *c, int kind, const double *radius,
                               sinter_contact_batch *b);

#endif
