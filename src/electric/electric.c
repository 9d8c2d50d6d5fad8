/*
 * Electric submodels: creation by name, parameters, and the one internal entry point the
 * stepper calls (seed 000 sec. 5). The models themselves are in averaged.c and network.c.
 */
#include <math.h>
#include <string.h>

#include "electric.h"
#include "core/pcg.h"

typedef struct electric_builtin {
    const char *name;
    int kind;
    double tolerance; /* default */
} electric_builtin;

static const electric_builtin BUILTIN[] = {
    {"averaged", SINTER_ELECTRIC_AVERAGED, 1e-6},
    {"network", SINTER_ELECTRIC_NETWORK, 1e-10},
};

static const double DEFAULT_MAX_ITERATIONS = 10000.0;

void *sinter_electric_reserve(sinter_ctx *ctx, void *ptr, size_t *capacity, size_t count,
                              size_t size)
{
    return sinter_grow(ctx, &ptr, capacity, count, size) == SINTER_OK ? ptr : NULL;
}

sinter_status sinter_electric_model_create(sinter_electric_model **out, sinter_ctx *ctx,
                                           const char *name)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    SINTER_CHECK_NULL(ctx, name);
    const size_t n = sizeof(BUILTIN) / sizeof(BUILTIN[0]);
    for (size_t k = 0; k < n; ++k) {
        if (strcmp(BUILTIN[k].name, name) != 0)
            continue;
        sinter_electric_model *em = sinter_calloc(ctx, 1, sizeof(*em));
        if (em == NULL)
            return sinter_last_status(ctx);
        em->ctx = ctx;
        em->kind = BUILTIN[k].kind;
        strncpy(em->name, BUILTIN[k].name, sizeof(em->name) - 1);
        em->tolerance = BUILTIN[k].tolerance;
        em->max_iterations = DEFAULT_MAX_ITERATIONS;
        em->theta_ref = 293.15;
        *out = em;
        return SINTER_OK;
    }
    return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                       "sinter_electric_model_create: no electric model is called '%s' (known: "
                       "averaged, network)",
                       name);
}

void sinter_electric_model_destroy(sinter_electric_model *em)
{
    if (em == NULL)
        return;
    sinter_ctx *ctx = em->ctx;
    if (em->host.struct_size != 0 && em->host.destroy_user != NULL)
        em->host.destroy_user(em->host_user);
    sinter_free(ctx, em->host_g);
    sinter_free(ctx, em->host_power);
    sinter_free(ctx, em->host_share);
    sinter_free(ctx, em->host_sigma);
    sinter_free(ctx, em->host_radius);
    sinter_free(ctx, em->host_walls);
    sinter_free(ctx, em->edge_contact);
    sinter_free(ctx, em->sigma_table);
    sinter_pcg_free(em->pcg);
    sinter_free(ctx, em->potential);
    sinter_free(ctx, em->label);
    sinter_free(ctx, em->wall_words);
    sinter_free(ctx, em->wall_sums);
    sinter_free(ctx, em->repro_edge);
    sinter_free(ctx, em->repro_start);
    sinter_free(ctx, em->repro_a);
    sinter_free(ctx, em->repro_b);
    em->across.ctx = ctx;
    sinter_domain_solve_free(&em->across);
    sinter_free(ctx, em->adj_start);
    sinter_free(ctx, em->adj_other);
    sinter_free(ctx, em->adj_area);
    sinter_free(ctx, em->wall_sum);
    sinter_free(ctx, em->wall_area);
    sinter_free(ctx, em->queue);
    sinter_free(ctx, em->state);
    sinter_free(ctx, em->averaged_rows);
    sinter_free(ctx, em->edge_a);
    sinter_free(ctx, em->edge_b);
    sinter_free(ctx, em->edge_g);
    sinter_free(ctx, em->parent);
    sinter_free(ctx, em->net);
    sinter_free(ctx, em->scale);
    sinter_free(ctx, em->pin);
    sinter_free(ctx, em->diag);
    sinter_free(ctx, em->free_a);
    sinter_free(ctx, em->free_b);
    sinter_free(ctx, em->free_g);
    sinter_free(ctx, em->dissipation);
    sinter_free(ctx, em->wall_mode);
    sinter_free(ctx, em->wall_value);
    sinter_free(ctx, em->warm_id);
    sinter_free(ctx, em->warm_pairs);
    sinter_free(ctx, em->warm_moved);
    sinter_free(ctx, em);
}

const char *sinter_electric_model_name(const sinter_electric_model *em)
{
    return em == NULL ? "" : em->name;
}

enum {
    KEY_TOLERANCE = 0,
    KEY_MAX_ITERATIONS,
    KEY_SIGMOID,
    KEY_THETA_REF,
    KEY_K1,
    KEY_GAMMA1,
    KEY_COUNT
};
static const char *const KEYS[KEY_COUNT] = {"tolerance", "max_iterations", "sigmoid", "theta_ref",
                                            "k1",        "gamma1"};

static sinter_status find_key(const sinter_electric_model *em, const char *key, int *k)
{
    SINTER_CHECK_NULL(em->ctx, key);
    for (*k = 0; *k < KEY_COUNT; ++*k)
        if (strcmp(KEYS[*k], key) == 0)
            return SINTER_OK;
    return sinter_fail(em->ctx, SINTER_ERR_NOT_FOUND,
                       "electric model '%s' has no parameter '%s' (known: tolerance, "
                       "max_iterations, sigmoid, theta_ref, k1, gamma1)",
                       em->name, key);
}

static double *value_of(sinter_electric_model *em, int k)
{
    double *const values[KEY_COUNT] = {
        &em->tolerance, &em->max_iterations, &em->sigmoid, &em->theta_ref, &em->k1, &em->gamma1};
    return values[k];
}

sinter_status sinter_electric_model_set(sinter_electric_model *em, const char *key, double value)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    int k = 0;
    sinter_status s = find_key(em, key, &k);
    if (s != SINTER_OK)
        return s;
    const char *why = NULL;
    if (k == KEY_TOLERANCE && !(value > 0.0 && value < 1.0))
        why = "must lie in (0, 1)";
    else if (k == KEY_MAX_ITERATIONS && !(value >= 1.0 && value <= 1e9 && value == floor(value)))
        why = "must be an integer in [1, 1e9]";
    else if (k == KEY_SIGMOID && value != 0.0 && value != 1.0)
        why = "must be 0 (constant conductivities) or 1 (seed 000 eq. 50's temperature term)";
    else if (k == KEY_THETA_REF && !(value > 0.0 && isfinite(value)))
        why = "must be a positive temperature [K]";
    else if ((k == KEY_K1 || k == KEY_GAMMA1) && !isfinite(value))
        why = "must be finite";
    else if (k >= KEY_SIGMOID && em->kind != SINTER_ELECTRIC_NETWORK)
        why = "is a parameter of the network model's conductances only";
    if (why != NULL)
        return sinter_fail(em->ctx, SINTER_ERR_INVALID, "electric model '%s': %s %g %s", em->name,
                           key, value, why);
    *value_of(em, k) = value;
    return SINTER_OK;
}

sinter_status sinter_electric_model_get(const sinter_electric_model *em, const char *key,
                                        double *value)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(em->ctx, value);
    int k = 0;
    sinter_status s = find_key(em, key, &k);
    if (s == SINTER_OK)
        *value = *value_of((sinter_electric_model *)em, k);
    return s;
}

sinter_status sinter_electric_model_power(const sinter_electric_model *em, double *supplied,
                                          double *dissipated)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(em->ctx, supplied);
    SINTER_CHECK_NULL(em->ctx, dissipated);
    if (em->kind != SINTER_ELECTRIC_NETWORK)
        return sinter_fail(em->ctx, SINTER_ERR_UNSUPPORTED,
                           "sinter_electric_model_power: the '%s' model propagates a current "
                           "magnitude without potentials; only 'network' has a power",
                           em->name);
    *supplied = em->supplied_power;
    *dissipated = em->dissipated_power;
    return SINTER_OK;
}

const double *sinter_electric_dissipation(const sinter_electric_model *em, size_t n)
{
    return em != NULL && em->kind == SINTER_ELECTRIC_NETWORK && em->dissipation_count == n && n > 0
               ? em->dissipation
               : NULL;
}

sinter_status sinter_electric_solve(sinter_electric_model *em, sinter_particles *ps,
                                    const sinter_walls *walls, const sinter_contact_list *pp,
                                    const sinter_contact_list *pw, size_t *iterations)
{
    return sinter_electric_solve_images(em, ps, walls, pp, pw, NULL, iterations);
}

sinter_status sinter_electric_solve_images(sinter_electric_model *em, sinter_particles *ps,
                                           const sinter_walls *walls, const sinter_contact_list *pp,
                                           const sinter_contact_list *pw,
                                           const uint32_t *ghost_owner, size_t *iterations)
{
    if (em == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(em->ctx, ps);
    SINTER_CHECK_NULL(em->ctx, pp);
    SINTER_CHECK_NULL(em->ctx, pw);
    if (iterations != NULL)
        *iterations = 0;
    const size_t nw = walls != NULL ? walls->count : 0;
    for (size_t k = 0; k < pw->count; ++k)
        if (pw->j[k] >= nw)
            return sinter_fail(em->ctx, SINTER_ERR_INVALID,
                               "electric model '%s': particle-wall contact %zu names wall %u but "
                               "there are %zu walls",
                               em->name, k, (unsigned)pw->j[k], nw);
    if ((uint64_t)ps->count + nw >= UINT32_MAX)
        return sinter_fail(em->ctx, SINTER_ERR_OVERFLOW,
                           "electric model '%s': %zu particles and %zu walls exceed the 32-bit "
                           "node index",
                           em->name, ps->count, nw);
    if (em->domain != NULL && (em->kind != SINTER_ELECTRIC_NETWORK || em->host.struct_size != 0))
        return sinter_fail(em->ctx, SINTER_ERR_UNSUPPORTED,
                           "electric model '%s': across subdomains only the 'network' model "
                           "without host callbacks",
                           em->name);
    const int subdomain = em->domain != NULL ||
                          (em->averaged_domain != NULL && em->kind == SINTER_ELECTRIC_AVERAGED);
    if (ps->ghost_count > 0 && !subdomain &&
        (ghost_owner == NULL || em->kind != SINTER_ELECTRIC_NETWORK))
        return sinter_fail(em->ctx, SINTER_ERR_UNSUPPORTED,
                           "electric model '%s': %zu periodic images need the 'network' model "
                           "and their owners",
                           em->name, ps->ghost_count);
    em->ghost_owner = ps->ghost_count > 0 && em->domain == NULL ? ghost_owner : NULL;
    em->last_iterations = 0;
    em->node_count = 0;
    em->open_clusters = 0;
    sinter_status s = em->kind == SINTER_ELECTRIC_AVERAGED
                          ? sinter_electric_solve_averaged(em, ps, walls, pp, pw)
                          : sinter_electric_solve_network(em, ps, walls, pp, pw);
    if (iterations != NULL)
        *iterations = em->last_iterations;
    return s;
}

const double *sinter_electric_warm_potentials(const sinter_electric_model *em, size_t *nodes)
{
    const int warm = em->kind == SINTER_ELECTRIC_NETWORK && em->warm_nodes > 0;
    *nodes = warm ? em->warm_nodes : 0;
    return warm ? em->potential : NULL;
}

sinter_status sinter_electric_set_warm_potentials(sinter_electric_model *em, const void *phi,
                                                  size_t nodes)
{
    em->warm_nodes = 0;
    em->warm_id_count = 0; /* by row: see warm_ids.c */
    if (nodes == 0 || em->kind != SINTER_ELECTRIC_NETWORK)
        return SINTER_OK;
    SINTER_ELECTRIC_RESERVE(em, potential, nodes + 1);
    memcpy(em->potential, phi, nodes * sizeof(double));
    em->warm_nodes = nodes;
    return SINTER_OK;
}
