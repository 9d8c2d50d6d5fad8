/* Particle sets: struct-of-arrays storage, materials, views and validation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "particles.h"

static const double PI = 3.14159265358979323846;

typedef struct field_spec {
    const char *name;
    const char *unit;
    sinter_dtype dtype;
    size_t components;
    size_t elem_size;
    int writable;
} field_spec;

/* Indexed by sinter_field; order must follow the enum in sinter.h. */
static const field_spec FIELDS[SINTER_FIELD_COUNT_] = {
    {"position", "m", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"velocity", "m/s", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"spin", "rad/s", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"rotation", "1", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"radius", "m", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"mass", "kg", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"inertia", "kg m^2", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"temperature", "K", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"current", "A", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"force", "N", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"torque", "N m", SINTER_DTYPE_DOUBLE, 3, sizeof(double), 1},
    {"heat", "W", SINTER_DTYPE_DOUBLE, 1, sizeof(double), 1},
    {"material", "1", SINTER_DTYPE_INT32, 1, sizeof(int32_t), 1},
    {"flags", "1", SINTER_DTYPE_UINT32, 1, sizeof(uint32_t), 1},
    {"id", "1", SINTER_DTYPE_UINT64, 1, sizeof(uint64_t), 0},
};

static void **field_slot(sinter_particles *ps, sinter_field f)
{
    switch (f) {
    case SINTER_FIELD_POSITION:
        return (void **)&ps->x;
    case SINTER_FIELD_VELOCITY:
        return (void **)&ps->v;
    case SINTER_FIELD_SPIN:
        return (void **)&ps->w;
    case SINTER_FIELD_ROTATION:
        return (void **)&ps->rot;
    case SINTER_FIELD_RADIUS:
        return (void **)&ps->radius;
    case SINTER_FIELD_MASS:
        return (void **)&ps->mass;
    case SINTER_FIELD_INERTIA:
        return (void **)&ps->inertia;
    case SINTER_FIELD_TEMPERATURE:
        return (void **)&ps->temperature;
    case SINTER_FIELD_CURRENT:
        return (void **)&ps->current;
    case SINTER_FIELD_FORCE:
        return (void **)&ps->force;
    case SINTER_FIELD_TORQUE:
        return (void **)&ps->torque;
    case SINTER_FIELD_HEAT:
        return (void **)&ps->heat;
    case SINTER_FIELD_MATERIAL:
        return (void **)&ps->material;
    case SINTER_FIELD_FLAGS:
        return (void **)&ps->flags;
    case SINTER_FIELD_ID:
        return (void **)&ps->id;
    default:
        return NULL;
    }
}

static int field_valid(int f)
{
    return f >= 0 && f < SINTER_FIELD_COUNT_;
}

sinter_status sinter_field_info(sinter_field field, const char **name, const char **unit,
                                sinter_dtype *dtype, size_t *components)
{
    if (!field_valid((int)field))
        return SINTER_ERR_RANGE;
    const field_spec *s = &FIELDS[field];
    if (name)
        *name = s->name;
    if (unit)
        *unit = s->unit;
    if (dtype)
        *dtype = s->dtype;
    if (components)
        *components = s->components;
    return SINTER_OK;
}

sinter_status sinter_particles_create(sinter_particles **out, sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    sinter_particles *ps = sinter_calloc(ctx, 1, sizeof(*ps));
    if (ps == NULL)
        return sinter_last_status(ctx);
    ps->ctx = ctx;
    ps->next_id = 0;
    *out = ps;
    return SINTER_OK;
}

void sinter_particles_destroy(sinter_particles *ps)
{
    if (ps == NULL)
        return;
    for (int f = 0; f < SINTER_FIELD_COUNT_; ++f)
        sinter_free(ps->ctx, *field_slot(ps, (sinter_field)f));
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m) {
        sinter_free(ps->ctx, ps->softening[m].temperature);
        sinter_free(ps->ctx, ps->softening[m].factor);
        sinter_material_props_free(ps->ctx, ps->props[m]);
    }
    sinter_id_index_free(ps->ctx, &ps->id_index);
    sinter_free(ps->ctx, ps);
}

sinter_status sinter_particles_count(const sinter_particles *ps, size_t *count)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, count);
    *count = ps->count;
    return SINTER_OK;
}

sinter_status sinter_particles_owned_count(const sinter_particles *ps, size_t *owned)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, owned);
    *owned = ps->count - ps->ghost_count;
    return SINTER_OK;
}

void sinter_particles_drop_ghosts(sinter_particles *ps)
{
    if (ps->ghost_count == 0)
        return;
    ps->count -= ps->ghost_count;
    ps->ghost_count = 0;
    ps->layout_generation++; /* (the owned particles, the population, did not change) */
}

sinter_status sinter_particles_capacity(const sinter_particles *ps, size_t *capacity)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, capacity);
    *capacity = ps->capacity;
    return SINTER_OK;
}

static sinter_status check_unlocked(const sinter_particles *ps, const char *func)
{
    if (ps->views_out > 0)
        return sinter_fail(ps->ctx, SINTER_ERR_BUSY,
                           "%s: %zu field view(s) of the particle set are still out; release "
                           "them before resizing",
                           func, ps->views_out);
    return SINTER_OK;
}

/* Grow every array to hold `capacity` particles; on failure the set is unchanged
 * (arrays that were already grown keep their data and are simply larger). */
static sinter_status grow(sinter_particles *ps, size_t capacity)
{
    if (capacity <= ps->capacity)
        return SINTER_OK;
    for (int f = 0; f < SINTER_FIELD_COUNT_; ++f) {
        void **slot = field_slot(ps, (sinter_field)f);
        const field_spec *s = &FIELDS[f];
        if (sinter_mul_overflows(capacity, s->components))
            return sinter_fail(ps->ctx, SINTER_ERR_OVERFLOW,
                               "particle capacity %zu overflows the %s array", capacity, s->name);
        void *p = sinter_realloc_array(ps->ctx, *slot, capacity * s->components, s->elem_size);
        if (p == NULL)
            return sinter_last_status(ps->ctx);
        *slot = p;
    }
    ps->capacity = capacity;
    return SINTER_OK;
}

sinter_status sinter_particles_reserve(sinter_particles *ps, size_t capacity)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_status st = check_unlocked(ps, "sinter_particles_reserve");
    if (st != SINTER_OK)
        return st;
    return grow(ps, capacity);
}

static void update_mass(sinter_particles *ps, size_t i)
{
    const double rho = sinter_particle_param(ps, i, SINTER_MAT_DENSITY);
    const double r = ps->radius[i];
    ps->mass[i] = rho * 4.0 / 3.0 * PI * r * r * r;
    ps->inertia[i] = 0.4 * ps->mass[i] * r * r; /* solid sphere, seed 003 sec. 2 */
}

sinter_status sinter_particles_set_material(sinter_particles *ps, int32_t id,
                                            const sinter_material *m)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, m);
    if (id < 0 || id >= SINTER_MAX_MATERIALS)
        return sinter_fail(ps->ctx, SINTER_ERR_RANGE,
                           "sinter_particles_set_material: material id %d is outside [0, %d]",
                           (int)id, SINTER_MAX_MATERIALS - 1);
    if (m->value[SINTER_MAT_LATENT_HEAT] > 0.0 && !(m->value[SINTER_MAT_MELTING_TEMPERATURE] > 0.0))
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "sinter_particles_set_material: material '%s': latent_heat = %g J/kg "
                           "needs a melting_temperature > 0",
                           m->name, m->value[SINTER_MAT_LATENT_HEAT]);
    ps->materials[id] = *m;
    ps->materials[id].ctx = ps->ctx;
    ps->material_used[id] = 1;
    ps->material_top = id >= ps->material_top ? id + 1 : ps->material_top;
    for (size_t i = 0; i < ps->count; ++i)
        if (ps->material[i] == id)
            update_mass(ps, i);
    ps->write_generation++; /* masses may have changed: steppers evaluate their forces again */
    /* its tables stay; its enthalpy follows the new heat capacity and latent heat */
    return sinter_particles_props_update(ps, id);
}

static sinter_status registered(const sinter_particles *ps, int32_t id, const char *func)
{
    if (id < 0 || id >= SINTER_MAX_MATERIALS || !ps->material_used[id])
        return sinter_fail(ps->ctx, SINTER_ERR_NOT_FOUND, "%s: material id %d is not registered",
                           func, (int)id);
    return SINTER_OK;
}

sinter_status sinter_particles_set_softening_curve(sinter_particles *ps, int32_t id, size_t n,
                                                   const double *temperatures,
                                                   const double *factors)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, temperatures);
    SINTER_CHECK_NULL(ps->ctx, factors);
    sinter_status st = registered(ps, id, __func__);
    if (st != SINTER_OK)
        return st;
    if (n < 1)
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID, "%s: the curve needs at least one point",
                           __func__);
    for (size_t k = 0; k < n; ++k)
        if (!isfinite(temperatures[k]) || !isfinite(factors[k]) || !(factors[k] > 0.0) ||
            (k > 0 && !(temperatures[k] > temperatures[k - 1])))
            return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                               "%s: point %zu (%g K, factor %g) is invalid: temperatures must "
                               "increase and factors be positive and finite",
                               __func__, k, temperatures[k], factors[k]);
    double *t = NULL, *f = NULL;
    if (sinter_copy_table(ps->ctx, n, temperatures, factors, &t, &f) != SINTER_OK)
        return SINTER_ERR_NOMEM;
    struct sinter_softening_curve *c = &ps->softening[id];
    sinter_free(ps->ctx, c->temperature);
    sinter_free(ps->ctx, c->factor);
    c->count = n;
    c->temperature = t;
    c->factor = f;
    ps->materials[id].value[SINTER_MAT_SOFTENING_LAW] = 3.0;
    return SINTER_OK;
}

sinter_status sinter_particles_set_softening_callback(sinter_particles *ps, int32_t id,
                                                      sinter_softening_fn fn, void *user)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, fn);
    sinter_status st = registered(ps, id, __func__);
    if (st != SINTER_OK)
        return st;
    ps->softening[id].fn = fn;
    ps->softening[id].user = user;
    ps->materials[id].value[SINTER_MAT_SOFTENING_LAW] = 4.0;
    return SINTER_OK;
}

sinter_status sinter_particles_get_material(const sinter_particles *ps, int32_t id,
                                            const sinter_material **m)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, m);
    if (id < 0 || id >= SINTER_MAX_MATERIALS || !ps->material_used[id])
        return sinter_fail(ps->ctx, SINTER_ERR_NOT_FOUND,
                           "sinter_particles_get_material: material id %d is not registered",
                           (int)id);
    *m = &ps->materials[id];
    return SINTER_OK;
}

static int id_compare(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Caller-chosen ids: none repeated among themselves or held by the set, none UINT64_MAX (kept
 * free so that next_id can pass every id). */
static sinter_status check_new_ids(sinter_particles *ps, size_t n, const uint64_t *ids,
                                   const char *func)
{
    sinter_ctx *ctx = ps->ctx;
    for (size_t k = 0; k < n; ++k)
        if (ids[k] == UINT64_MAX)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: the id of new particle %zu is 2^64 - 1, which is reserved",
                               func, k);
    sinter_status st = sinter_id_index_update(&ps->id_index, ps);
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < n; ++k) {
        const size_t held = sinter_id_index_find(&ps->id_index, ps, ids[k]);
        if (held != SIZE_MAX)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: id %llu of new particle %zu is held by particle %zu", func,
                               (unsigned long long)ids[k], k, held);
    }
    uint64_t *sorted = sinter_alloc(ctx, n * sizeof(uint64_t));
    if (sorted == NULL)
        return sinter_last_status(ctx);
    memcpy(sorted, ids, n * sizeof(uint64_t));
    qsort(sorted, n, sizeof(uint64_t), id_compare);
    for (size_t k = 1; k < n; ++k)
        if (sorted[k] == sorted[k - 1]) {
            const unsigned long long twice = (unsigned long long)sorted[k];
            sinter_free(ctx, sorted);
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: id %llu is given twice", func, twice);
        }
    sinter_free(ctx, sorted);
    return SINTER_OK;
}

/* sinter_particles_add and _add_with_ids (ids NULL: the set's own ids from next_id; otherwise
 * checked by check_new_ids before anything changes). */
static sinter_status add_particles(sinter_particles *ps, size_t n, const uint64_t *ids,
                                   const double *positions, const double *radii,
                                   int32_t material_id, double temperature, size_t *first_index,
                                   const char *func)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    sinter_status st = check_unlocked(ps, func);
    if (st != SINTER_OK)
        return st;
    sinter_particles_drop_ghosts(ps); /* owned particles stay first; ghosts come back at the
                                       * next neighbour build */
    if (n == 0) {
        if (first_index)
            *first_index = ps->count;
        return SINTER_OK;
    }
    SINTER_CHECK_NULL(ctx, positions);
    SINTER_CHECK_NULL(ctx, radii);
    if (ids != NULL && (st = check_new_ids(ps, n, ids, func)) != SINTER_OK)
        return st;
    if (material_id < 0 || material_id >= SINTER_MAX_MATERIALS || !ps->material_used[material_id])
        return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                           "%s: material id %d is not registered; call "
                           "sinter_particles_set_material first",
                           func, (int)material_id);
    if (!isfinite(temperature) || temperature <= 0.0)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: temperature %g K must be positive and finite", func, temperature);
    if (n > SIZE_MAX - ps->count || sinter_mul_overflows(n, 3))
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW, "%s: adding %zu particles to %zu overflows",
                           func, n, ps->count);
    if (ids == NULL && ps->next_id > UINT64_MAX - 1 - n)
        return sinter_fail(ctx, SINTER_ERR_OVERFLOW,
                           "%s: the set's next id %llu leaves no room for %zu more ids", func,
                           (unsigned long long)ps->next_id, n);
    static const char *axis[3] = {"x", "y", "z"};
    const double rho = ps->materials[material_id].value[SINTER_MAT_DENSITY];
    for (size_t k = 0; k < n; ++k) {
        for (int d = 0; d < 3; ++d)
            if (!isfinite(positions[3 * k + d]))
                return sinter_fail(ctx, SINTER_ERR_INVALID,
                                   "%s: position.%s of new particle %zu is %g; "
                                   "positions must be finite",
                                   func, axis[d], k, positions[3 * k + d]);
        if (!isfinite(radii[k]) || radii[k] <= 0.0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: radius of new particle %zu is %g m; radii "
                               "must be positive and finite",
                               func, k, radii[k]);
        /* The mass and inertia follow from the radius: they must be representable too. */
        const double r = radii[k], mass = rho * 4.0 / 3.0 * PI * r * r * r;
        if (!isfinite(0.4 * mass * r * r) || !(0.4 * mass * r * r > 0.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: radius of new particle %zu is %g m; its "
                               "mass %g kg or moment of inertia %g kg m^2 is not a positive "
                               "finite number",
                               func, k, r, mass, 0.4 * mass * r * r);
    }
    size_t need = ps->count + n;
    if (need > ps->capacity) {
        size_t cap = ps->capacity < 16 ? 16 : ps->capacity;
        while (cap < need)
            cap = cap > SIZE_MAX / 2 ? need : cap * 2;
        st = grow(ps, cap);
        if (st != SINTER_OK)
            return st;
    }
    const size_t first = ps->count;
    for (size_t k = 0; k < n; ++k) {
        const size_t i = first + k;
        for (int d = 0; d < 3; ++d) {
            ps->x[3 * i + d] = positions[3 * k + d];
            ps->v[3 * i + d] = 0.0;
            ps->w[3 * i + d] = 0.0;
            ps->rot[3 * i + d] = 0.0;
            ps->force[3 * i + d] = 0.0;
            ps->torque[3 * i + d] = 0.0;
        }
        ps->radius[i] = radii[k];
        ps->material[i] = material_id;
        ps->temperature[i] = temperature;
        ps->current[i] = 0.0;
        ps->heat[i] = 0.0;
        ps->flags[i] = 0;
        ps->id[i] = ids != NULL ? ids[k] : ps->next_id++;
        if (ids != NULL && ids[k] >= ps->next_id)
            ps->next_id = ids[k] + 1; /* ids[k] < UINT64_MAX: check_new_ids */
        update_mass(ps, i);
    }
    ps->count = need;
    ps->layout_generation++;
    ps->population_generation++;
    if (first_index)
        *first_index = first;
    return SINTER_OK;
}

sinter_status sinter_particles_add(sinter_particles *ps, size_t n, const double *positions,
                                   const double *radii, int32_t material_id, double temperature,
                                   size_t *first_index)
{
    return add_particles(ps, n, NULL, positions, radii, material_id, temperature, first_index,
                         "sinter_particles_add");
}

sinter_status sinter_particles_add_with_ids(sinter_particles *ps, size_t n, const uint64_t *ids,
                                            const double *positions, const double *radii,
                                            int32_t material_id, double temperature,
                                            size_t *first_index)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    if (n > 0)
        SINTER_CHECK_NULL(ps->ctx, ids);
    return add_particles(ps, n, ids, positions, radii, material_id, temperature, first_index,
                         "sinter_particles_add_with_ids");
}

sinter_status sinter_particles_set_ghost_rows(sinter_particles *ps, size_t n, const uint32_t *owner,
                                              const double *shift)
{
    sinter_particles_drop_ghosts(ps);
    return sinter_particles_append_ghost_rows(ps, n, owner, shift);
}

sinter_status sinter_particles_append_ghost_rows(sinter_particles *ps, size_t n,
                                                 const uint32_t *owner, const double *shift)
{
    const size_t owned = ps->count; /* (rows before the new ones: owned and ghosts) */
    if (n == 0)
        return SINTER_OK;
    if (owned + n > ps->capacity) {
        const sinter_status st = grow(ps, owned + n + (owned + n) / 4);
        if (st != SINTER_OK)
            return st;
    }
    for (int f = 0; f < SINTER_FIELD_COUNT_; ++f) {
        const field_spec *s = &FIELDS[f];
        char *base = *field_slot(ps, (sinter_field)f);
        const size_t bytes = s->components * s->elem_size;
        for (size_t k = 0; k < n; ++k)
            memcpy(base + (owned + k) * bytes, base + (size_t)owner[k] * bytes, bytes);
    }
    for (size_t k = 0; k < n; ++k) {
        const size_t g = owned + k;
        for (int d = 0; d < 3; ++d) {
            ps->x[3 * g + d] += shift[3 * k + d];
            ps->force[3 * g + d] = ps->torque[3 * g + d] = 0.0;
        }
        ps->heat[g] = 0.0;
    }
    ps->count = owned + n;
    ps->ghost_count += n;
    ps->layout_generation++; /* (the owned particles, the population, did not change) */
    return SINTER_OK;
}

sinter_status sinter_particles_make_ghost_rows(sinter_particles *ps, size_t n)
{
    sinter_status st = check_unlocked(ps, "sinter_particles_set_ghosts");
    if (st != SINTER_OK)
        return st;
    sinter_particles_drop_ghosts(ps);
    const size_t owned = ps->count;
    if (n == 0)
        return SINTER_OK;
    if (owned + n > ps->capacity && (st = grow(ps, owned + n + (owned + n) / 4)) != SINTER_OK)
        return st;
    memset(ps->force + 3 * owned, 0, 3 * n * sizeof(double));
    memset(ps->torque + 3 * owned, 0, 3 * n * sizeof(double));
    memset(ps->heat + owned, 0, n * sizeof(double));
    memset(ps->current + owned, 0, n * sizeof(double));
    ps->count = owned + n;
    ps->ghost_count = n;
    ps->layout_generation++; /* (the owned particles, the population, did not change) */
    return SINTER_OK;
}

/* Move particle `from` to slot `to` in every field. */
static void move_particle(sinter_particles *ps, size_t to, size_t from)
{
    for (int f = 0; f < SINTER_FIELD_COUNT_; ++f) {
        const field_spec *s = &FIELDS[f];
        char *base = *field_slot(ps, (sinter_field)f);
        const size_t bytes = s->components * s->elem_size;
        memmove(base + to * bytes, base + from * bytes, bytes);
    }
}

sinter_status sinter_particles_remove(sinter_particles *ps, size_t n, const size_t *indices)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    sinter_status st = check_unlocked(ps, "sinter_particles_remove");
    if (st != SINTER_OK || n == 0)
        return st;
    sinter_particles_drop_ghosts(ps); /* indices name owned particles */
    SINTER_CHECK_NULL(ctx, indices);
    unsigned char *doomed = sinter_calloc(ctx, ps->count ? ps->count : 1, 1);
    if (doomed == NULL)
        return sinter_last_status(ctx);
    for (size_t k = 0; k < n; ++k) {
        if (indices[k] >= ps->count || doomed[indices[k]]) {
            st = sinter_fail(ctx, indices[k] >= ps->count ? SINTER_ERR_RANGE : SINTER_ERR_INVALID,
                             "sinter_particles_remove: index %zu (entry %zu) is %s", indices[k], k,
                             indices[k] >= ps->count ? "out of range" : "listed twice");
            sinter_free(ctx, doomed);
            return st;
        }
        doomed[indices[k]] = 1;
    }
    size_t kept = 0;
    for (size_t i = 0; i < ps->count; ++i) {
        if (doomed[i])
            continue;
        if (kept != i)
            move_particle(ps, kept, i);
        ++kept;
    }
    ps->count = kept;
    ps->layout_generation++;
    ps->population_generation++;
    sinter_free(ctx, doomed);
    return SINTER_OK;
}

sinter_status sinter_particles_permute(sinter_particles *ps, const size_t *order)
{
    sinter_status st = check_unlocked(ps, "sinter_particles_permute");
    if (st != SINTER_OK)
        return st;
    const size_t n = ps->count;
    if (n == 0)
        return SINTER_OK;
    size_t max_bytes = 3 * sizeof(double);
    char *tmp = sinter_alloc(ps->ctx, n * max_bytes);
    if (tmp == NULL)
        return sinter_last_status(ps->ctx);
    for (int f = 0; f < SINTER_FIELD_COUNT_; ++f) {
        const field_spec *s = &FIELDS[f];
        char *base = *field_slot(ps, (sinter_field)f);
        const size_t bytes = s->components * s->elem_size;
        for (size_t k = 0; k < n; ++k)
            memcpy(tmp + k * bytes, base + order[k] * bytes, bytes);
        memcpy(base, tmp, n * bytes);
    }
    sinter_free(ps->ctx, tmp);
    ps->layout_generation++;
    return SINTER_OK;
}

static sinter_status borrow(const sinter_particles *ps, sinter_field field, int write, void **data,
                            size_t *count, size_t *components)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, data);
    if (!field_valid((int)field))
        return sinter_fail(ps->ctx, SINTER_ERR_RANGE, "particle field %d does not exist",
                           (int)field);
    if (write && !FIELDS[field].writable)
        return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                           "particle field '%s' is read-only; use sinter_particles_view_read",
                           FIELDS[field].name);
    /* Views are bookkeeping on a logically const object. */
    sinter_particles *mut = (sinter_particles *)ps;
    *data = *field_slot(mut, field);
    if (count)
        *count = ps->count;
    if (components)
        *components = FIELDS[field].components;
    mut->views_out++;
    mut->field_views[field]++;
    if (write)
        mut->write_generation++;
    return SINTER_OK;
}

sinter_status sinter_particles_view(sinter_particles *ps, sinter_field field, void **data,
                                    size_t *count, size_t *components)
{
    return borrow(ps, field, 1, data, count, components);
}

sinter_status sinter_particles_view_read(const sinter_particles *ps, sinter_field field,
                                         const void **data, size_t *count, size_t *components)
{
    void *p = NULL;
    if (data == NULL)
        return ps == NULL ? SINTER_ERR_NULL
                          : sinter_fail(ps->ctx, SINTER_ERR_NULL,
                                        "sinter_particles_view_read: argument 'data' is NULL");
    sinter_status st = borrow(ps, field, 0, &p, count, components);
    if (st == SINTER_OK)
        *data = p;
    return st;
}

sinter_status sinter_particles_release(const sinter_particles *ps, sinter_field field)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    if (!field_valid((int)field))
        return sinter_fail(ps->ctx, SINTER_ERR_RANGE, "particle field %d does not exist",
                           (int)field);
    sinter_particles *mut = (sinter_particles *)ps;
    if (mut->field_views[field] == 0)
        return sinter_fail(ps->ctx, SINTER_ERR_STATE,
                           "sinter_particles_release: no view of field '%s' is out",
                           FIELDS[field].name);
    mut->field_views[field]--;
    mut->views_out--;
    return SINTER_OK;
}

sinter_status sinter_particles_views_out(const sinter_particles *ps, size_t *views)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, views);
    *views = ps->views_out;
    return SINTER_OK;
}

static sinter_status bad_value(const sinter_particles *ps, size_t i, const char *field,
                               const char *component, double value, const char *rule,
                               size_t *bad_index)
{
    if (bad_index)
        *bad_index = i;
    return sinter_fail(ps->ctx, SINTER_ERR_INVALID, "%s%s of particle %zu (id %llu) is %g; %s",
                       field, component, i, (unsigned long long)ps->id[i], value, rule);
}

sinter_status sinter_particles_validate(const sinter_particles *ps, size_t *bad_index)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    static const char *axis[3] = {".x", ".y", ".z"};
    const struct {
        const char *name;
        const double *data;
    } vectors[4] = {
        {"position", ps->x}, {"velocity", ps->v}, {"spin", ps->w}, {"rotation", ps->rot}};
    const struct {
        const char *name;
        const char *unit;
        const double *data;
    } positives[4] = {{"radius", "m", ps->radius},
                      {"mass", "kg", ps->mass},
                      {"inertia", "kg m^2", ps->inertia},
                      {"temperature", "K", ps->temperature}};
    for (size_t i = 0; i < ps->count; ++i) {
        for (int f = 0; f < 4; ++f)
            for (int d = 0; d < 3; ++d)
                if (!isfinite(vectors[f].data[3 * i + d]))
                    return bad_value(ps, i, vectors[f].name, axis[d], vectors[f].data[3 * i + d],
                                     "it must be finite", bad_index);
        for (int f = 0; f < 4; ++f) {
            const double value = positives[f].data[i];
            if (!isfinite(value) || value <= 0.0)
                return bad_value(ps, i, positives[f].name, "", value,
                                 "it must be positive and finite", bad_index);
        }
        if (!isfinite(ps->current[i]))
            return bad_value(ps, i, "current", "", ps->current[i], "it must be finite", bad_index);
        const int32_t mat = ps->material[i];
        if (mat < 0 || mat >= SINTER_MAX_MATERIALS || !ps->material_used[mat]) {
            if (bad_index)
                *bad_index = i;
            return sinter_fail(ps->ctx, SINTER_ERR_INVALID,
                               "material of particle %zu (id %llu) is %d, which is not a "
                               "registered material id",
                               i, (unsigned long long)ps->id[i], (int)mat);
        }
    }
    return SINTER_OK;
}

sinter_status sinter_particles_find_id(const sinter_particles *ps, uint64_t id, size_t *index)
{
    if (ps == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ps->ctx, index);
    /* The index is bookkeeping on a logically const set (as the views are). */
    sinter_particles *mut = (sinter_particles *)ps;
    sinter_status st = sinter_id_index_update(&mut->id_index, ps);
    if (st != SINTER_OK)
        return st;
    const size_t i = sinter_id_index_find(&ps->id_index, ps, id);
    if (i == SIZE_MAX)
        return sinter_fail(ps->ctx, SINTER_ERR_NOT_FOUND, "no particle has id %llu",
                           (unsigned long long)id);
    *index = i;
    return SINTER_OK;
}
