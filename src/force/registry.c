/* Force models: creation by name, model-level parameters, destruction. */
#include <string.h>

#include "force_model.h"

/* Appended by later files through this table only. */
static const sinter_force_ops *const BUILTIN[] = {
    &sinter_force_hertz_mindlin,
    &sinter_force_linear_spring,
    &sinter_force_gravity,
    &sinter_force_body_force,
    &sinter_force_power_law,
    &sinter_force_drag,
};

static const char *builtin_name(size_t k)
{
    return BUILTIN[k]->name;
}

static void init_params(sinter_force_model *fm)
{
    for (int k = 0; k < SINTER_FORCE_MAX_PARAMS && fm->ops->keys[k] != NULL; ++k)
        fm->param[k] = fm->ops->defaults[k];
}

sinter_status sinter_force_model_create(sinter_force_model **out, sinter_ctx *ctx,
                                        const char *name)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, name);
    const size_t n = sizeof(BUILTIN) / sizeof(BUILTIN[0]);
    for (size_t k = 0; k < n; ++k) {
        if (strcmp(BUILTIN[k]->name, name) != 0)
            continue;
        sinter_force_model *fm = sinter_calloc(ctx, 1, sizeof(*fm));
        if (fm == NULL)
            return sinter_last_status(ctx);
        fm->ctx = ctx;
        fm->ops = BUILTIN[k];
        strncpy(fm->name, name, sizeof(fm->name) - 1);
        init_params(fm);
        *out = fm;
        return SINTER_OK;
    }
    char known[256];
    sinter_join_names(known, sizeof(known), n, builtin_name);
    return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                       "sinter_force_model_create: no force model is called '%s' (known: %s)",
                       name, known);
}

sinter_status sinter_force_model_create_host(sinter_force_model **out, sinter_ctx *ctx,
                                             const char *name,
                                             const sinter_force_callbacks *callbacks, void *user)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, callbacks);
    if (callbacks->struct_size != sizeof(sinter_force_callbacks))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_force_model_create_host: struct_size is %zu, expected %zu",
                           callbacks->struct_size, sizeof(sinter_force_callbacks));
    if (callbacks->contacts == NULL && callbacks->particles == NULL)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_force_model_create_host: both callbacks are NULL");
    if (callbacks->history_size > 64)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_force_model_create_host: history_size %zu exceeds 64",
                           callbacks->history_size);
    sinter_force_model *fm = sinter_calloc(ctx, 1, sizeof(*fm));
    if (fm == NULL)
        return sinter_last_status(ctx);
    fm->ctx = ctx;
    fm->host = *callbacks;
    fm->user = user;
    strncpy(fm->name, name ? name : "host", sizeof(fm->name) - 1);
    fm->host_ops.name = fm->name;
    fm->host_ops.history_pp = callbacks->contacts ? callbacks->history_size : 0;
    fm->host_ops.history_pw = callbacks->contacts ? callbacks->history_size : 0;
    fm->host_ops.uses_contacts = callbacks->contacts != NULL;
    fm->host_ops.keys[0] = NULL;
    fm->host_ops.eval = sinter_force_host_eval;
    fm->ops = &fm->host_ops;
    *out = fm;
    return SINTER_OK;
}

void sinter_force_model_destroy(sinter_force_model *fm)
{
    if (fm == NULL)
        return;
    if (fm->ops == &fm->host_ops && fm->host.destroy_user != NULL)
        fm->host.destroy_user(fm->user);
    sinter_free(fm->ctx, fm);
}

const char *sinter_force_model_name(const sinter_force_model *fm)
{
    return fm == NULL ? "" : fm->name;
}

static int find_key(const sinter_force_model *fm, const char *key)
{
    return sinter_find_key(fm->ops->keys, SINTER_FORCE_MAX_PARAMS, key);
}

sinter_status sinter_force_model_set(sinter_force_model *fm, const char *key, double value)
{
    if (fm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(fm->ctx, key);
    const int k = find_key(fm, key);
    if (k < 0)
        return sinter_unknown_key(fm->ctx, "force model", fm->name, key, fm->ops->keys,
                                 SINTER_FORCE_MAX_PARAMS);
    if (value != value || value - value != 0.0)
        return sinter_fail(fm->ctx, SINTER_ERR_INVALID,
                           "force model '%s': parameter '%s' = %g must be finite", fm->name, key,
                           value);
    fm->param[k] = value;
    return SINTER_OK;
}

sinter_status sinter_force_model_get(const sinter_force_model *fm, const char *key, double *value)
{
    if (fm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(fm->ctx, key);
    SINTER_CHECK_NULL(fm->ctx, value);
    const int k = find_key(fm, key);
    if (k < 0)
        return sinter_unknown_key(fm->ctx, "force model", fm->name, key, fm->ops->keys,
                                 SINTER_FORCE_MAX_PARAMS);
    *value = fm->param[k];
    return SINTER_OK;
}
