/* Particle sets: add/remove/reserve, mass from density, views and locks, validation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"

static const double PI = 3.14159265358979323846;

typedef struct fixture {
    sinter_ctx *ctx;
    sinter_material *mat;
    sinter_particles *ps;
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof(f));
    if (sinter_ctx_create(&f.ctx, NULL) != SINTER_OK ||
        sinter_material_create(&f.mat, f.ctx, "glass") != SINTER_OK ||
        sinter_material_set(f.mat, SINTER_MAT_DENSITY, 2500.0) != SINTER_OK ||
        sinter_particles_create(&f.ps, f.ctx) != SINTER_OK ||
        sinter_particles_set_material(f.ps, 0, f.mat) != SINTER_OK)
        return -1;
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    sinter_particles_destroy(f->ps);
    sinter_material_destroy(f->mat);
    sinter_ctx_destroy(f->ctx);
    return 0;
}

/* Read views of the ids and positions (released by release_ids_positions). */
static void view_ids_positions(fixture *f, const uint64_t **id, const double **x)
{
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_ID, (const void **)id, NULL, NULL),
        SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_POSITION, (const void **)x, NULL, NULL),
        SINTER_OK);
}

static void release_ids_positions(fixture *f)
{
    sinter_particles_release(f->ps, SINTER_FIELD_ID);
    sinter_particles_release(f->ps, SINTER_FIELD_POSITION);
}

static void add_line(fixture *f, size_t n, double r)
{
    double pos[3 * 8], rad[8];
    assert_true(n <= 8);
    for (size_t k = 0; k < n; ++k) {
        pos[3 * k] = 3.0 * r * (double)k;
        pos[3 * k + 1] = 0.0;
        pos[3 * k + 2] = 0.0;
        rad[k] = r;
    }
    assert_int_equal(sinter_particles_add(f->ps, n, pos, rad, 0, 300.0, NULL), SINTER_OK);
}

static void test_add_sets_mass_and_inertia(void **state)
{
    fixture *f = *state;
    add_line(f, 3, 1e-3);
    size_t count = 0;
    assert_int_equal(sinter_particles_count(f->ps, &count), SINTER_OK);
    assert_int_equal(count, 3);
    const double *mass = NULL, *inertia = NULL, *temp = NULL;
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_MASS, (const void **)&mass, NULL, NULL),
        SINTER_OK);
    assert_int_equal(sinter_particles_view_read(f->ps, SINTER_FIELD_INERTIA,
                                                (const void **)&inertia, NULL, NULL),
                     SINTER_OK);
    assert_int_equal(sinter_particles_view_read(f->ps, SINTER_FIELD_TEMPERATURE,
                                                (const void **)&temp, NULL, NULL),
                     SINTER_OK);
    /* m = rho 4/3 pi r^3, j = 2/5 m r^2 (seed 003 sec. 2), to round-off. */
    const double m = 2500.0 * 4.0 / 3.0 * PI * 1e-9;
    for (int i = 0; i < 3; ++i) {
        assert_close(mass[i], m, 1e-15 * m);
        assert_close(inertia[i], 0.4 * m * 1e-6, 1e-15 * m * 1e-6);
        assert_close(temp[i], 300.0, 0.0);
    }
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_MASS), SINTER_OK);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_INERTIA), SINTER_OK);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_TEMPERATURE), SINTER_OK);
    /* Replacing the material recomputes the mass. */
    assert_int_equal(sinter_material_set(f->mat, SINTER_MAT_DENSITY, 5000.0), SINTER_OK);
    assert_int_equal(sinter_particles_set_material(f->ps, 0, f->mat), SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_MASS, (const void **)&mass, NULL, NULL),
        SINTER_OK);
    assert_close(mass[2], 2.0 * m, 1e-15 * m);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_MASS), SINTER_OK);
}

static void test_add_rejects_bad_values_unchanged(void **state)
{
    fixture *f = *state;
    add_line(f, 2, 1e-3);
    double pos[6] = {0, 0, 0, 1, NAN, 0};
    double rad[2] = {1e-3, 1e-3};
    assert_int_equal(sinter_particles_add(f->ps, 2, pos, rad, 0, 300.0, NULL), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f->ctx), "position.y"));
    assert_non_null(strstr(sinter_last_error(f->ctx), "particle 1"));
    pos[4] = 0.0;
    rad[1] = -0.002;
    assert_int_equal(sinter_particles_add(f->ps, 2, pos, rad, 0, 300.0, NULL), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f->ctx), "radius"));
    assert_non_null(strstr(sinter_last_error(f->ctx), "-0.002"));
    rad[1] = 1e-3;
    assert_int_equal(sinter_particles_add(f->ps, 2, pos, rad, 7, 300.0, NULL),
                     SINTER_ERR_NOT_FOUND);
    assert_int_equal(sinter_particles_add(f->ps, 2, pos, rad, 0, -1.0, NULL), SINTER_ERR_INVALID);
    assert_int_equal(sinter_particles_add(f->ps, 2, NULL, rad, 0, 300.0, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_add(f->ps, SIZE_MAX, pos, rad, 0, 300.0, NULL),
                     SINTER_ERR_OVERFLOW);
    size_t count = 0;
    sinter_particles_count(f->ps, &count);
    assert_int_equal(count, 2);
}

static void test_views_lock_resizing(void **state)
{
    fixture *f = *state;
    add_line(f, 4, 1e-3);
    double *x = NULL;
    size_t count = 0, comps = 0;
    assert_int_equal(
        sinter_particles_view(f->ps, SINTER_FIELD_POSITION, (void **)&x, &count, &comps),
        SINTER_OK);
    assert_int_equal(count, 4);
    assert_int_equal(comps, 3);
    x[3 * 3 + 2] = 0.5; /* writes go straight into the set */
    assert_int_equal(sinter_particles_reserve(f->ps, 1000), SINTER_ERR_BUSY);
    double p[3] = {0, 0, 1}, r = 1e-3;
    assert_int_equal(sinter_particles_add(f->ps, 1, p, &r, 0, 300.0, NULL), SINTER_ERR_BUSY);
    size_t idx = 0;
    assert_int_equal(sinter_particles_remove(f->ps, 1, &idx), SINTER_ERR_BUSY);
    size_t out = 0;
    assert_int_equal(sinter_particles_views_out(f->ps, &out), SINTER_OK);
    assert_int_equal(out, 1);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_POSITION), SINTER_OK);
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_POSITION), SINTER_ERR_STATE);
    assert_int_equal(sinter_particles_reserve(f->ps, 1000), SINTER_OK);
    size_t cap = 0;
    assert_int_equal(sinter_particles_capacity(f->ps, &cap), SINTER_OK);
    assert_true(cap >= 1000);
    const double *xr = NULL;
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_POSITION, (const void **)&xr, NULL, NULL),
        SINTER_OK);
    assert_close(xr[11], 0.5, 0.0); /* survives reallocation */
    assert_int_equal(sinter_particles_release(f->ps, SINTER_FIELD_POSITION), SINTER_OK);
    /* The id field is read-only. */
    void *ids = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_ID, &ids, NULL, NULL),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_particles_view(f->ps, (sinter_field)99, &ids, NULL, NULL),
                     SINTER_ERR_RANGE);
    assert_int_equal(sinter_particles_views_out(f->ps, &out), SINTER_OK);
    assert_int_equal(out, 0);
}

static void test_remove_keeps_order_and_ids(void **state)
{
    fixture *f = *state;
    add_line(f, 5, 1e-3);
    size_t doomed[2] = {3, 1};
    assert_int_equal(sinter_particles_remove(f->ps, 2, doomed), SINTER_OK);
    size_t count = 0;
    sinter_particles_count(f->ps, &count);
    assert_int_equal(count, 3);
    const uint64_t *id = NULL;
    const double *x = NULL;
    view_ids_positions(f, &id, &x);
    assert_int_equal(id[0], 0);
    assert_int_equal(id[1], 2);
    assert_int_equal(id[2], 4);
    assert_close(x[3 * 2], 12e-3, 1e-18);
    release_ids_positions(f);
    size_t index = 0;
    assert_int_equal(sinter_particles_find_id(f->ps, 4, &index), SINTER_OK);
    assert_int_equal(index, 2);
    assert_int_equal(sinter_particles_find_id(f->ps, 3, &index), SINTER_ERR_NOT_FOUND);
    /* Duplicate and out-of-range indices are refused without change. */
    size_t dup[2] = {0, 0};
    assert_int_equal(sinter_particles_remove(f->ps, 2, dup), SINTER_ERR_INVALID);
    size_t far = 3;
    assert_int_equal(sinter_particles_remove(f->ps, 1, &far), SINTER_ERR_RANGE);
    sinter_particles_count(f->ps, &count);
    assert_int_equal(count, 3);
}

/* A 4 x 4 x 4 lattice added in a scrambled order comes out in cell order (z slowest, x
 * fastest), each id still at its own position; bad input moves nothing. */
static void test_sort_spatial(void **state)
{
    fixture *f = *state;
    enum { N = 64 };
    const double r = 1e-3, a = 2.5e-3;
    double pos[3 * N], rad[N];
    for (size_t k = 0; k < N; ++k) {
        const size_t c = (k * 37) % N; /* 37 is prime to 64: a permutation of the cells */
        pos[3 * k] = a * (double)(c % 4);
        pos[3 * k + 1] = a * (double)((c / 4) % 4);
        pos[3 * k + 2] = a * (double)(c / 16);
        rad[k] = r;
    }
    assert_int_equal(sinter_particles_add(f->ps, N, pos, rad, 0, 300.0, NULL), SINTER_OK);
    assert_int_equal(sinter_particles_sort_spatial(f->ps), SINTER_OK);
    const uint64_t *id = NULL;
    const double *x = NULL;
    view_ids_positions(f, &id, &x);
    for (size_t i = 0; i < N; ++i) {
        /* index i holds lattice cell i (cells of one diameter, 2 mm, one sphere per cell) */
        assert_close(x[3 * i], a * (double)(i % 4), 1e-15);
        assert_close(x[3 * i + 1], a * (double)((i / 4) % 4), 1e-15);
        assert_close(x[3 * i + 2], a * (double)(i / 16), 1e-15);
        /* and the particle with that id is the one added there */
        for (int d = 0; d < 3; ++d)
            assert_true(x[3 * i + d] == pos[3 * id[i] + d]);
    }
    /* a view out: refused (BUSY), nothing moves */
    assert_int_equal(sinter_particles_sort_spatial(f->ps), SINTER_ERR_BUSY);
    release_ids_positions(f);
    /* a position that is not finite: refused, naming the particle, nothing moves */
    double *wx = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_POSITION, (void **)&wx, NULL, NULL),
                     SINTER_OK);
    wx[3 * 5 + 1] = NAN;
    sinter_particles_release(f->ps, SINTER_FIELD_POSITION);
    assert_int_equal(sinter_particles_sort_spatial(f->ps), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f->ctx), "particle 5"));
    size_t index = 0;
    assert_int_equal(sinter_particles_find_id(f->ps, 0, &index), SINTER_OK);
    assert_int_equal(index, 0); /* cell 0 held id 0 (k = 0) */
    assert_int_equal(sinter_particles_sort_spatial(NULL), SINTER_ERR_NULL);
}

/* Caller-chosen ids (issue 43): kept, found in O(1) after adds, sorts and removals; repeats,
 * ids the set holds and the reserved 2^64 - 1 are refused with nothing added; the set's own
 * counter continues above the largest. */
static void test_add_with_ids(void **state)
{
    fixture *f = *state;
    const double pos[9] = {0.0, 0.0, 0.0, 3e-3, 0.0, 0.0, 6e-3, 0.0, 0.0};
    const double rad[3] = {1e-3, 1e-3, 1e-3};
    const uint64_t ids[3] = {10, 3, 7};
    size_t first = 99, index = 0, count = 0;
    assert_int_equal(sinter_particles_add_with_ids(f->ps, 3, ids, pos, rad, 0, 300.0, &first),
                     SINTER_OK);
    assert_int_equal(first, 0);
    assert_int_equal(sinter_particles_find_id(f->ps, 3, &index), SINTER_OK);
    assert_int_equal(index, 1);
    const uint64_t twice[2] = {20, 20}, held[2] = {21, 7}, reserved[1] = {UINT64_MAX};
    assert_int_equal(sinter_particles_add_with_ids(f->ps, 2, twice, pos, rad, 0, 300.0, NULL),
                     SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(f->ctx), "id 20 is given twice"));
    assert_int_equal(sinter_particles_add_with_ids(f->ps, 2, held, pos, rad, 0, 300.0, NULL),
                     SINTER_ERR_INVALID);
    assert_non_null(
        strstr(sinter_last_error(f->ctx), "id 7 of new particle 1 is held by particle 2"));
    assert_int_equal(sinter_particles_add_with_ids(f->ps, 1, reserved, pos, rad, 0, 300.0, NULL),
                     SINTER_ERR_INVALID);
    assert_int_equal(sinter_particles_add_with_ids(f->ps, 1, NULL, pos, rad, 0, 300.0, NULL),
                     SINTER_ERR_NULL);
    sinter_particles_count(f->ps, &count);
    assert_int_equal(count, 3);
    /* the counter continues above 10 */
    assert_int_equal(sinter_particles_add(f->ps, 1, pos, rad, 0, 300.0, NULL), SINTER_OK);
    assert_int_equal(sinter_particles_find_id(f->ps, 11, &index), SINTER_OK);
    assert_int_equal(index, 3);

    /* Many ids in a scrambled order, far apart (multiples of 2^40: a poor hash would pile
     * them into a few slots), found after adding, after a sort and after removing half. */
    enum { N = 5000 };
    double *xyz = malloc(3 * N * sizeof(double)), *r = malloc(N * sizeof(double));
    uint64_t *many = malloc(N * sizeof(uint64_t));
    assert_non_null(xyz);
    assert_non_null(r);
    assert_non_null(many);
    for (size_t k = 0; k < N; ++k) {
        const size_t c = (k * 2749) % N; /* 2749 is prime to 5000 */
        xyz[3 * k] = 3e-3 * (double)(c % 20);
        xyz[3 * k + 1] = 3e-3 * (double)((c / 20) % 25);
        xyz[3 * k + 2] = 3e-3 * (double)(c / 500) + 1.0;
        r[k] = 1e-3;
        many[k] = ((uint64_t)c + 100) << 40;
    }
    assert_int_equal(sinter_particles_add_with_ids(f->ps, N, many, xyz, r, 0, 300.0, &first),
                     SINTER_OK);
    assert_int_equal(first, 4);
    for (size_t k = 0; k < N; ++k) {
        assert_int_equal(sinter_particles_find_id(f->ps, many[k], &index), SINTER_OK);
        assert_int_equal(index, first + k);
    }
    assert_int_equal(sinter_particles_sort_spatial(f->ps), SINTER_OK);
    const uint64_t *id = NULL;
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_ID, (const void **)&id, &count, NULL),
        SINTER_OK);
    for (size_t i = 0; i < count; ++i) {
        assert_int_equal(sinter_particles_find_id(f->ps, id[i], &index), SINTER_OK);
        assert_int_equal(index, i);
    }
    sinter_particles_release(f->ps, SINTER_FIELD_ID);
    size_t *doomed = malloc(N / 2 * sizeof(size_t));
    assert_non_null(doomed);
    for (size_t k = 0; k < N / 2; ++k)
        doomed[k] = 2 * k;
    assert_int_equal(sinter_particles_remove(f->ps, N / 2, doomed), SINTER_OK);
    assert_int_equal(
        sinter_particles_view_read(f->ps, SINTER_FIELD_ID, (const void **)&id, &count, NULL),
        SINTER_OK);
    assert_int_equal(count, N + 4 - N / 2);
    for (size_t i = 0; i < count; ++i) {
        assert_int_equal(sinter_particles_find_id(f->ps, id[i], &index), SINTER_OK);
        assert_int_equal(index, i);
    }
    sinter_particles_release(f->ps, SINTER_FIELD_ID);
    /* every id ever given is found exactly when its particle remains; one never given is not */
    size_t found = 0;
    const uint64_t small[4] = {10, 3, 7, 11};
    for (size_t k = 0; k < N + 4; ++k) {
        size_t at = 0;
        found += sinter_particles_find_id(f->ps, k < N ? many[k] : small[k - N], &at) == SINTER_OK;
    }
    assert_int_equal(found, count);
    assert_int_equal(sinter_particles_find_id(f->ps, 12, &index), SINTER_ERR_NOT_FOUND);
    free(doomed);
    free(many);
    free(r);
    free(xyz);
}

static void test_validate_names_particle_and_field(void **state)
{
    fixture *f = *state;
    add_line(f, 4, 1e-3);
    assert_int_equal(sinter_particles_validate(f->ps, NULL), SINTER_OK);
    double *v = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL),
                     SINTER_OK);
    v[3 * 2 + 2] = INFINITY;
    sinter_particles_release(f->ps, SINTER_FIELD_VELOCITY);
    size_t bad = 0;
    assert_int_equal(sinter_particles_validate(f->ps, &bad), SINTER_ERR_INVALID);
    assert_int_equal(bad, 2);
    assert_non_null(strstr(sinter_last_error(f->ctx), "velocity.z of particle 2"));
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL),
                     SINTER_OK);
    v[3 * 2 + 2] = 0.0;
    sinter_particles_release(f->ps, SINTER_FIELD_VELOCITY);
    int32_t *mat = NULL;
    assert_int_equal(sinter_particles_view(f->ps, SINTER_FIELD_MATERIAL, (void **)&mat, NULL, NULL),
                     SINTER_OK);
    mat[3] = 42;
    sinter_particles_release(f->ps, SINTER_FIELD_MATERIAL);
    assert_int_equal(sinter_particles_validate(f->ps, &bad), SINTER_ERR_INVALID);
    assert_int_equal(bad, 3);
    assert_non_null(strstr(sinter_last_error(f->ctx), "material of particle 3"));
}

static void test_null_handles(void **state)
{
    (void)state;
    size_t n = 0;
    assert_int_equal(sinter_particles_count(NULL, &n), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_reserve(NULL, 1), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_add(NULL, 0, NULL, NULL, 0, 300.0, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_remove(NULL, 0, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_validate(NULL, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_release(NULL, SINTER_FIELD_MASS), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_set_material(NULL, 0, NULL), SINTER_ERR_NULL);
    assert_int_equal(sinter_particles_create(NULL, NULL), SINTER_ERR_NULL);
    sinter_particles_destroy(NULL);
    const char *name = NULL;
    size_t comps = 0;
    sinter_dtype dtype;
    assert_int_equal(sinter_field_info(SINTER_FIELD_ID, &name, NULL, &dtype, &comps), SINTER_OK);
    assert_string_equal(name, "id");
    assert_int_equal(dtype, SINTER_DTYPE_UINT64);
    assert_int_equal(sinter_field_info(SINTER_FIELD_COUNT_, &name, NULL, NULL, NULL),
                     SINTER_ERR_RANGE);
}

/* Every allocation of a build-up sequence is made to fail in turn: each failure
 * is reported as SINTER_ERR_NOMEM, nothing leaks, and the set stays usable. */
static void test_allocation_failure_injection(void **state)
{
    (void)state;
    int failures_seen = 0;
    for (long fail_after = 0; fail_after < 64; ++fail_after) {
        counting_allocator c = {0, 0, -1, 0};
        sinter_allocator a = counting_allocator_hook(&c);
        sinter_ctx *ctx = NULL;
        assert_int_equal(sinter_ctx_create(&ctx, &a), SINTER_OK);
        c.fail_after = fail_after;
        c.calls = 0;
        sinter_material *m = NULL;
        sinter_particles *ps = NULL;
        sinter_status st = sinter_material_create(&m, ctx, "m");
        if (st == SINTER_OK)
            st = sinter_particles_create(&ps, ctx);
        if (st == SINTER_OK)
            st = sinter_particles_set_material(ps, 0, m);
        double pos[3 * 40], rad[40];
        for (int k = 0; k < 40; ++k) {
            pos[3 * k] = k * 1e-2;
            pos[3 * k + 1] = pos[3 * k + 2] = 0.0;
            rad[k] = 1e-3;
        }
        size_t before = 0;
        if (st == SINTER_OK) {
            sinter_particles_count(ps, &before);
            st = sinter_particles_add(ps, 40, pos, rad, 0, 300.0, NULL);
            size_t after = 0;
            sinter_particles_count(ps, &after);
            if (st != SINTER_OK)
                assert_int_equal(after, before); /* nothing changed */
        }
        if (st == SINTER_OK) {
            size_t idx[2] = {0, 5};
            st = sinter_particles_remove(ps, 2, idx);
        }
        if (st != SINTER_OK) {
            assert_int_equal(st, SINTER_ERR_NOMEM);
            assert_int_equal(sinter_last_status(ctx), SINTER_ERR_NOMEM);
            failures_seen++;
        }
        sinter_particles_destroy(ps);
        sinter_material_destroy(m);
        sinter_ctx_destroy(ctx);
        assert_int_equal(c.allocations, c.frees);
        if (st == SINTER_OK)
            break;
    }
    assert_true(failures_seen >= 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_add_sets_mass_and_inertia, setup, teardown),
        cmocka_unit_test_setup_teardown(test_add_rejects_bad_values_unchanged, setup, teardown),
        cmocka_unit_test_setup_teardown(test_views_lock_resizing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_remove_keeps_order_and_ids, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sort_spatial, setup, teardown),
        cmocka_unit_test_setup_teardown(test_add_with_ids, setup, teardown),
        cmocka_unit_test_setup_teardown(test_validate_names_particle_and_field, setup, teardown),
        cmocka_unit_test(test_null_handles),
        cmocka_unit_test(test_allocation_failure_injection),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
