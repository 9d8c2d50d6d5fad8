/* Heat models: creation by name, parameters and their schedules, host callbacks. */
#include <math.h>
#include <string.h>

#include "heat/scan_path.h"
#include "heat_model.h"

static const sinter_heat_ops *const BUILTIN[] = {
    &sinter_heat_conduction, &sinter_heat_convection,  &sinter_heat_radiation,
    &sinter_heat_nozzle,     &sinter_heat_laser,       &sinter_heat_joule,
    &sinter_heat_beam,       &sinter_heat_dissipation,
};

static const char *builtin_name(size_t k)
{
    return BUILTIN[k]->name;
}

double sinter_heat_param(const sinter_heat_model *hm, int k, double t)
{
    const double v =
        hm->schedule_count[k] == 0
            ? hm->param[k]
            : sinter_interpolate(hm->schedule_count[k], hm->schedule_t[k], hm->schedule_v[k], t);
    if (hm->path == NULL || (k != hm->path_key[0] && k != hm->path_key[1] && k != hm->path_key[2]))
        return v;
    double xy[2], level;
    sinter_scan_path_at(hm->path, t, xy, &level);
    return k == hm->path_key[0] ? xy[0] : k == hm->path_key[1] ? xy[1] : v * level;
}

/* The index of parameter `key` of hm's model, or -1. */
static int param_index(const sinter_heat_model *hm, const char *key)
{
    for (int p = 0; p < SINTER_HEAT_MAX_PARAMS && hm->ops->keys[p] != NULL; ++p)
        if (strcmp(hm->ops->keys[p], key) == 0)
            return p;
    return -1;
}

double sinter_heat_axis_travel(const sinter_heat_model *hm, double t, double h)
{
    const int kx = param_index(hm, "x"), ky = param_index(hm, "y");
    if (kx < 0 || ky < 0)
        return 0.0;
    return hypot(sinter_heat_param(hm, kx, t + h) - sinter_heat_param(hm, kx, t),
                 sinter_heat_param(hm, ky, t + h) - sinter_heat_param(hm, ky, t));
}

sinter_status sinter_heat_model_set_scan_path(sinter_heat_model *hm, size_t n, const double *points,
                                              double start_time)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    const char *func = "sinter_heat_model_set_scan_path";
    const int x = param_index(hm, "x"), y = param_index(hm, "y");
    int power = param_index(hm, "power");
    if (power < 0)
        power = param_index(hm, "intensity");
    if (x < 0 || y < 0 || power < 0)
        return sinter_fail(hm->ctx, SINTER_ERR_INVALID,
                           "%s: heat model '%s' has no beam to move (a scan path drives the "
                           "\"x\", \"y\" and \"power\" or \"intensity\" of \"beam\", \"laser\" and "
                           "\"nozzle\")",
                           func, hm->name);
    sinter_scan_path *path = NULL;
    if (n > 0) {
        SINTER_CHECK_NULL(hm->ctx, points);
        sinter_status st = sinter_scan_path_create(hm->ctx, n, points, start_time, &path, func);
        if (st != SINTER_OK)
            return st;
    }
    sinter_scan_path_destroy(hm->ctx, hm->path);
    hm->path = path;
    hm->path_key[0] = x;
    hm->path_key[1] = y;
    hm->path_key[2] = power;
    return SINTER_OK;
}

sinter_status sinter_heat_model_scan_end(const sinter_heat_model *hm, double *end_time)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(hm->ctx, end_time);
    if (hm->path == NULL)
        return sinter_fail(hm->ctx, SINTER_ERR_NOT_FOUND,
                           "sinter_heat_model_scan_end: heat model '%s' has no scan path",
                           hm->name);
    *end_time = hm->path->t[hm->path->vertices - 1];
    return SINTER_OK;
}

sinter_status sinter_scan_hatch(sinter_ctx *ctx, const double lo[2], const double hi[2],
                                double spacing, double angle, double speed, double jump_speed,
                                int serpentine, double *points, size_t capacity, size_t *count)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, lo);
    SINTER_CHECK_NULL(ctx, hi);
    SINTER_CHECK_NULL(ctx, count);
    return sinter_scan_hatch_build(ctx, lo, hi, spacing, angle, speed, jump_speed, serpentine,
                                   points, points != NULL ? capacity : 0, count);
}

sinter_status sinter_heat_model_create(sinter_heat_model **out, sinter_ctx *ctx, const char *name)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, name);
    const size_t n = sizeof(BUILTIN) / sizeof(BUILTIN[0]);
    for (size_t k = 0; k < n; ++k) {
        if (strcmp(BUILTIN[k]->name, name) != 0)
            continue;
        sinter_heat_model *hm = sinter_calloc(ctx, 1, sizeof(*hm));
        if (hm == NULL)
            return sinter_last_status(ctx);
        hm->ctx = ctx;
        hm->ops = BUILTIN[k];
        strncpy(hm->name, name, sizeof(hm->name) - 1);
        for (int p = 0; p < SINTER_HEAT_MAX_PARAMS && hm->ops->keys[p] != NULL; ++p)
            hm->param[p] = hm->ops->defaults[p];
        *out = hm;
        return SINTER_OK;
    }
    char known[256];
    sinter_join_names(known, sizeof(known), n, builtin_name);
    return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                       "sinter_heat_model_create: no heat model is called '%s' (known: %s)", name,
                       known);
}

sinter_status sinter_heat_model_create_host(sinter_heat_model **out, sinter_ctx *ctx,
                                            const char *name,
                                            const sinter_heat_callbacks *callbacks, void *user)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, callbacks);
    if (callbacks->struct_size != sizeof(sinter_heat_callbacks))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "sinter_heat_model_create_host: struct_size is %zu, expected %zu",
                           callbacks->struct_size, sizeof(sinter_heat_callbacks));
    if (callbacks->power == NULL)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_heat_model_create_host: the power callback is NULL");
    sinter_heat_model *hm = sinter_calloc(ctx, 1, sizeof(*hm));
    if (hm == NULL)
        return sinter_last_status(ctx);
    hm->ctx = ctx;
    hm->host = *callbacks;
    hm->user = user;
    strncpy(hm->name, name ? name : "host", sizeof(hm->name) - 1);
    hm->host_ops.name = hm->name;
    hm->host_ops.conduction = 0;
    hm->host_ops.keys[0] = NULL;
    hm->host_ops.eval = sinter_heat_host_eval;
    hm->host_ops.reads_geometry = sinter_heat_host_reads_geometry;
    hm->ops = &hm->host_ops;
    *out = hm;
    return SINTER_OK;
}

void sinter_heat_model_destroy(sinter_heat_model *hm)
{
    if (hm == NULL)
        return;
    if (hm->ops == &hm->host_ops && hm->host.destroy_user != NULL)
        hm->host.destroy_user(hm->user);
    for (int k = 0; k < SINTER_HEAT_MAX_PARAMS; ++k) {
        sinter_free(hm->ctx, hm->schedule_t[k]);
        sinter_free(hm->ctx, hm->schedule_v[k]);
    }
    sinter_scan_path_destroy(hm->ctx, hm->path);
    sinter_free(hm->ctx, hm);
}

const char *sinter_heat_model_name(const sinter_heat_model *hm)
{
    return hm == NULL ? "" : hm->name;
}

static int find_key(const sinter_heat_model *hm, const char *key)
{
    return sinter_find_key(hm->ops->keys, SINTER_HEAT_MAX_PARAMS, key);
}

static sinter_status key_index(const sinter_heat_model *hm, const char *key, int *k)
{
    SINTER_CHECK_NULL(hm->ctx, key);
    *k = find_key(hm, key);
    if (*k < 0)
        return sinter_unknown_key(hm->ctx, "heat model", hm->name, key, hm->ops->keys,
                                  SINTER_HEAT_MAX_PARAMS);
    return SINTER_OK;
}

sinter_status sinter_heat_model_set(sinter_heat_model *hm, const char *key, double value)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    int k = -1;
    sinter_status st = key_index(hm, key, &k);
    if (st != SINTER_OK)
        return st;
    if (!isfinite(value))
        return sinter_fail(hm->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': parameter '%s' = %g must be finite", hm->name, key,
                           value);
    hm->param[k] = value;
    return SINTER_OK;
}

sinter_status sinter_heat_model_get(const sinter_heat_model *hm, const char *key, double *value)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(hm->ctx, value);
    int k = -1;
    sinter_status st = key_index(hm, key, &k);
    if (st == SINTER_OK)
        *value = hm->param[k];
    return st;
}

sinter_status sinter_heat_model_output(const sinter_heat_model *hm, const char *name, double *value)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(hm->ctx, name);
    SINTER_CHECK_NULL(hm->ctx, value);
    const char *const *names = hm->ops == &sinter_heat_beam ? sinter_heat_beam_outputs : NULL;
    for (int k = 0; names != NULL && k < SINTER_HEAT_MAX_OUTPUTS && names[k] != NULL; ++k)
        if (strcmp(names[k], name) == 0) {
            *value = hm->output[k];
            return SINTER_OK;
        }
    return sinter_fail(hm->ctx, SINTER_ERR_NOT_FOUND, "heat model '%s' has no output '%s'",
                       hm->name, name);
}

sinter_status sinter_heat_model_set_schedule(sinter_heat_model *hm, const char *key, size_t n,
                                             const double *times, const double *values)
{
    if (hm == NULL)
        return SINTER_ERR_NULL;
    int k = -1;
    sinter_status st = key_index(hm, key, &k);
    if (st != SINTER_OK)
        return st;
    SINTER_CHECK_NULL(hm->ctx, times);
    SINTER_CHECK_NULL(hm->ctx, values);
    if (n < 1)
        return sinter_fail(hm->ctx, SINTER_ERR_INVALID,
                           "sinter_heat_model_set_schedule: a schedule needs at least one point");
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(times[i]) || !isfinite(values[i]) || (i > 0 && !(times[i] > times[i - 1])))
            return sinter_fail(hm->ctx, SINTER_ERR_INVALID,
                               "sinter_heat_model_set_schedule: point %zu of '%s' is not finite "
                               "or its time does not increase",
                               i, key);
    double *t = NULL, *v = NULL;
    if (sinter_copy_table(hm->ctx, n, times, values, &t, &v) != SINTER_OK)
        return SINTER_ERR_NOMEM;
    sinter_free(hm->ctx, hm->schedule_t[k]);
    sinter_free(hm->ctx, hm->schedule_v[k]);
    hm->schedule_t[k] = t;
    hm->schedule_v[k] = v;
    hm->schedule_count[k] = n;
    return SINTER_OK;
}
