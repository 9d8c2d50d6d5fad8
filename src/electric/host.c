/*
 * Host submodels of the "network" electric model (issue 39): a contact conductance law and a
 * Joule split given as callbacks, in the manner of the host force and heat models
 * (force/host.c, heat/host.c). network.c calls them once per solve with the batches of the
 * particle-particle and particle-wall contacts; the values they return are checked here.
 */
#include <math.h>
#include <string.h>

#include "contact/host_views.h"
#include "electric.h"

sinter_status sinter_electric_model_set_host(sinter_electric_model *em,
                                             const sinter_electric_callbacks *callbacks, void *user)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    if (em->kind != SINTER_ELECTRIC_NETWORK)
        return sinter_fail(em->ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_electric_model_set_host: the '%s' model has no contact "
                           "conductances; host callbacks need 'network'",
                           em->name);
    if (callbacks != NULL && callbacks->struct_size != sizeof(sinter_electric_callbacks))
        return sinter_fail(em->ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_electric_model_set_host: struct_size is %zu, expected %zu",
                           callbacks->struct_size, sizeof(sinter_electric_callbacks));
    if (callbacks != NULL && callbacks->conductance == NULL && callbacks->joule_split == NULL)
        return sinter_fail(em->ctx, SINTER_ERR_INVALID,
                           "sinter_electric_model_set_host: neither a conductance nor a "
                           "joule_split callback (pass NULL to remove the host callbacks)");
    if (em->host.struct_size != 0 && em->host.destroy_user != NULL)
        em->host.destroy_user(em->host_user);
    memset(&em->host, 0, sizeof(em->host));
    em->host_user = NULL;
    if (callbacks != NULL) {
        em->host = *callbacks;
        em->host_user = user;
    }
    return SINTER_OK;
}

sinter_status sinter_electric_model_electrode_heat(const sinter_electric_model *em, double *heat)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(em->ctx, heat);
    if (em->kind != SINTER_ELECTRIC_NETWORK)
        return sinter_fail(em->ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_electric_model_electrode_heat: the '%s' model has no power",
                           em->name);
    *heat = em->electrode_heat;
    return SINTER_OK;
}

/* The state view of the particles and walls (time and dt unknown here: NaN). */
static sinter_status fill_view(sinter_electric_model *em, const sinter_particles *ps,
                               const sinter_walls *walls, sinter_state_view *v)
{
    const size_t nw = walls != NULL ? walls->count : 0;
    SINTER_ELECTRIC_RESERVE(em, host_walls, 9 * nw + 1);
    sinter_host_state_view(v, ps, walls, em->host_walls, NAN, NAN);
    return SINTER_OK;
}

/* The geometry batch of list c (radii written to `radius`). */
static void batch_of(const sinter_contact_list *c, int kind, double *radius,
                     sinter_contact_batch *b)
{
    sinter_contact_radii(c, radius);
    sinter_host_contact_batch(c, kind, radius, b);
}

/* Both batches and the view; radii in em->host_radius. */
static sinter_status prepare(sinter_electric_model *em, const sinter_particles *ps,
                             const sinter_walls *walls, const sinter_contact_list *pp,
                             const sinter_contact_list *pw, sinter_state_view *view,
                             sinter_contact_batch batch[2])
{
    SINTER_ELECTRIC_RESERVE(em, host_radius, pp->count + pw->count + 1);
    batch_of(pp, SINTER_CONTACT_PARTICLE, em->host_radius, &batch[0]);
    batch_of(pw, SINTER_CONTACT_WALL, em->host_radius + pp->count, &batch[1]);
    return fill_view(em, ps, walls, view);
}

static sinter_status callback_failed(const sinter_electric_model *em, const char *which, int rc,
                                     const sinter_contact_batch *b)
{
    return sinter_fail(em->ctx, SINTER_ERR_CALLBACK,
                       "electric model '%s': the host %s callback returned %d for a batch of %zu "
                       "%s contacts",
                       em->name, which, rc, b->count,
                       b->kind == SINTER_CONTACT_WALL ? "wall" : "particle");
}

sinter_status
sinter_electric_host_conductance(sinter_electric_model *em, const sinter_particles *ps,
                                 const sinter_walls *walls, const sinter_contact_list *pp,
                                 const sinter_contact_list *pw, const double *sigma, double *g)
{
    sinter_state_view view;
    sinter_contact_batch batch[2];
    sinter_status s = prepare(em, ps, walls, pp, pw, &view, batch);
    if (s != SINTER_OK)
        return s;
    double *out[2] = {g, g + pp->count};
    for (int b = 0; b < 2; ++b) {
        if (batch[b].count == 0)
            continue;
        memset(out[b], 0, batch[b].count * sizeof(double));
        const int rc = em->host.conductance(&view, &batch[b], sigma, out[b], em->host_user);
        if (rc != 0)
            return callback_failed(em, "conductance", rc, &batch[b]);
        for (size_t k = 0; k < batch[b].count; ++k)
            if (!(out[b][k] >= 0.0 && isfinite(out[b][k])))
                return sinter_fail(em->ctx, SINTER_ERR_DOMAIN,
                                   "electric model '%s': the host conductance of %s contact %zu "
                                   "is %g S; it must be finite and >= 0",
                                   em->name, b ? "wall" : "particle", k, out[b][k]);
    }
    return SINTER_OK;
}

sinter_status sinter_electric_host_split(sinter_electric_model *em, const sinter_particles *ps,
                                         const sinter_walls *walls, const sinter_contact_list *pp,
                                         const sinter_contact_list *pw, const double *power,
                                         double *share)
{
    sinter_state_view view;
    sinter_contact_batch batch[2];
    sinter_status s = prepare(em, ps, walls, pp, pw, &view, batch);
    if (s != SINTER_OK)
        return s;
    const double *in[2] = {power, power + pp->count};
    double *out[2] = {share, share + pp->count};
    for (int b = 0; b < 2; ++b) {
        if (batch[b].count == 0)
            continue;
        /* the built-in split, for entries the host leaves as they are */
        for (size_t k = 0; k < batch[b].count; ++k)
            out[b][k] = b == 0 ? 0.5 : 1.0;
        const int rc = em->host.joule_split(&view, &batch[b], in[b], out[b], em->host_user);
        if (rc != 0)
            return callback_failed(em, "joule_split", rc, &batch[b]);
        for (size_t k = 0; k < batch[b].count; ++k)
            if (!(out[b][k] >= 0.0 && out[b][k] <= 1.0))
                return sinter_fail(em->ctx, SINTER_ERR_DOMAIN,
                                   "electric model '%s': the host Joule share of %s contact %zu "
                                   "is %g; it must lie in [0, 1]",
                                   em->name, b ? "wall" : "particle", k, out[b][k]);
    }
    return SINTER_OK;
}
