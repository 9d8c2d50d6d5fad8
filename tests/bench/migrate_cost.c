/*
 * What moving particles between steppers costs (issue 43, sinter_stepper_export / _import):
 * a settled bed of N Hertz-Mindlin spheres with rolling resistance (an m x m x m lattice at
 * 0.999 diameters, jittered, on a floor under gravity, 200 steps) exports half its particles
 * (every other index, remove = 1) and imports them back, against the mean of 20 explicit
 * steps of the same bed measured in the same run (a ratio, so that the machine's speed
 * cancels). Also the stream's bytes per particle, and the steps after the round trip, whose
 * imported half sits at the end of the arrays, before and after a spatial sort. Then the
 * removal of half the bed after its export (a host with several destinations): by a second
 * export with removal against sinter_stepper_remove, same run. Usage: migrate_cost [m]
 * (default 40: 64 000 spheres) [repeats] (default 3).
 */
#define _POSIX_C_SOURCE 199309L
#define BENCH_NAME "migrate_cost"
#include "bench_support.h"

#include <stdint.h>

static double jitter(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0 - 0.5;
}

int main(int argc, char **argv)
{
    const size_t m = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 40;
    const int repeats = argc > 2 ? atoi(argv[2]) : 3;
    if (m == 0 || repeats <= 0)
        return 1;
    const size_t n = m * m * m;
    const double r = 5e-4, pitch = 2 * r * 0.999;
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    CHECK(sinter_ctx_set_threads(g_ctx, 1));
    sinter_material *mat = NULL;
    CHECK(sinter_material_create(&mat, g_ctx, "glass"));
    CHECK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    CHECK(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500));
    CHECK(sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_STATIC, 0.4));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DYNAMIC, 0.4));
    CHECK(sinter_material_set(mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    sinter_particles *ps[2];
    sinter_walls *walls[2];
    sinter_stepper *st[2];
    sinter_force_model *hm[2], *gravity[2];
    for (int k = 0; k < 2; ++k) {
        CHECK(sinter_particles_create(&ps[k], g_ctx));
        CHECK(sinter_particles_set_material(ps[k], 0, mat));
        CHECK(sinter_walls_create(&walls[k], g_ctx));
        const double p[3] = {0, 0, -r}, up[3] = {0, 0, 1};
        CHECK(sinter_walls_add_plane(walls[k], p, up, mat, NULL));
        CHECK(sinter_stepper_create(&st[k], g_ctx, SINTER_STEPPER_EXPLICIT, ps[k], walls[k]));
        CHECK(sinter_stepper_set_option(st[k], "thread_choice", 0));
        CHECK(sinter_force_model_create(&hm[k], g_ctx, "hertz_mindlin"));
        CHECK(sinter_force_model_set(hm[k], "rolling", 1.0));
        CHECK(sinter_force_model_create(&gravity[k], g_ctx, "gravity"));
        CHECK(sinter_stepper_add_force(st[k], hm[k]));
        CHECK(sinter_stepper_add_force(st[k], gravity[k]));
        CHECK(sinter_stepper_set_dt(st[k], 2e-6));
    }
    double *x = malloc(3 * n * sizeof(double)), *rad = malloc(n * sizeof(double));
    size_t *half = malloc((n / 2 + 1) * sizeof(size_t)), *all = malloc(n * sizeof(size_t));
    if (x == NULL || rad == NULL || half == NULL || all == NULL)
        return 1;
    uint64_t seed = 7;
    for (size_t k = 0; k < n; ++k) {
        x[3 * k] = pitch * (double)(k % m) + 1e-6 * jitter(&seed);
        x[3 * k + 1] = pitch * (double)((k / m) % m) + 1e-6 * jitter(&seed);
        x[3 * k + 2] = pitch * (double)(k / (m * m));
        rad[k] = r;
        all[k] = k;
    }
    CHECK(sinter_particles_add(ps[0], n, x, rad, 0, 300.0, NULL));
    CHECK(sinter_stepper_step(st[0], 200));
    double t0 = cpu_seconds();
    CHECK(sinter_stepper_step(st[0], 20));
    const double step = (cpu_seconds() - t0) / 20.0; /* the bed before any migration */
    printf("migrate_cost: %zu spheres, one step %.5f s (mean of 20), %d repeats\n", n, step,
           repeats);
    for (int rep = 0; rep < repeats; ++rep) {
        size_t count = 0, bytes = 0, written = 0, half_n = 0, back_n = 0;
        CHECK(sinter_particles_count(ps[0], &count));
        for (size_t i = 0; i < count; i += 2)
            half[half_n++] = i;
        t0 = cpu_seconds();
        CHECK(sinter_stepper_export_size(st[0], half_n, half, &bytes));
        const size_t out_bytes = bytes;
        unsigned char *buf = malloc(bytes);
        if (buf == NULL)
            return 1;
        CHECK(sinter_stepper_export(st[0], half_n, half, buf, bytes, &written, 1));
        const double out = cpu_seconds() - t0;
        t0 = cpu_seconds();
        CHECK(sinter_stepper_import(st[1], buf, written, &back_n));
        const double in = cpu_seconds() - t0;
        free(buf);
        /* and back, so that the next repeat starts from the whole bed */
        CHECK(sinter_stepper_export_size(st[1], back_n, all, &bytes));
        buf = malloc(bytes);
        if (buf == NULL)
            return 1;
        CHECK(sinter_stepper_export(st[1], back_n, all, buf, bytes, &written, 1));
        CHECK(sinter_stepper_import(st[0], buf, written, NULL));
        free(buf);
        t0 = cpu_seconds();
        CHECK(sinter_stepper_step(st[0], 20)); /* the first rebuilds the lists */
        const double after = (cpu_seconds() - t0) / 20.0;
        /* the imported half sits at the end in memory: sorted by position again */
        CHECK(sinter_particles_sort_spatial(ps[0]));
        CHECK(sinter_stepper_step(st[0], 1)); /* the lists rebuilt for the sorted order */
        t0 = cpu_seconds();
        CHECK(sinter_stepper_step(st[0], 20));
        const double sorted = (cpu_seconds() - t0) / 20.0;
        printf("repeat %d: export of %zu (remove) %.4f s = %.2f steps, import %.4f s = %.2f "
               "steps; %.0f bytes per particle; a step after the round trip %.2f steps, after "
               "a spatial sort %.2f\n",
               rep, half_n, out, out / step, in, in / step, (double)out_bytes / (double)half_n,
               after / step, sorted / step);
    }
    /* A host with several destinations exports each one's leavers without removal, then
     * removes them all: once by a second export with removal (its records thrown away, as
     * before), once by sinter_stepper_remove. Both on the same bed, in alternating order, the
     * half put back (imported) and one step taken (the lists rebuilt) after each. */
    double sum_old = 0.0, sum_new = 0.0, min_old = 1e300, max_old = 0.0, min_new = 1e300,
           max_new = 0.0;
    for (int rep = 0; rep < 2 * repeats; ++rep) {
        const int second_export = (rep % 2) == (rep / 2) % 2;
        size_t count = 0, bytes = 0, written = 0, half_n = 0;
        CHECK(sinter_particles_count(ps[0], &count));
        for (size_t i = 0; i < count; i += 2)
            half[half_n++] = i;
        CHECK(sinter_stepper_export_size(st[0], half_n, half, &bytes));
        unsigned char *buf = malloc(bytes), *scratch = malloc(bytes);
        if (buf == NULL || scratch == NULL)
            return 1;
        CHECK(sinter_stepper_export(st[0], half_n, half, buf, bytes, &written, 0));
        t0 = cpu_seconds();
        if (second_export) {
            size_t b2 = 0, w2 = 0;
            CHECK(sinter_stepper_export_size(st[0], half_n, half, &b2));
            CHECK(sinter_stepper_export(st[0], half_n, half, scratch, b2, &w2, 1));
        } else {
            CHECK(sinter_stepper_remove(st[0], half_n, half));
        }
        const double removal = cpu_seconds() - t0;
        CHECK(sinter_stepper_import(st[0], buf, written, NULL));
        free(buf);
        free(scratch);
        CHECK(sinter_stepper_step(st[0], 1));
        double *sum = second_export ? &sum_old : &sum_new;
        double *lo = second_export ? &min_old : &min_new, *hi = second_export ? &max_old : &max_new;
        *sum += removal;
        *lo = removal < *lo ? removal : *lo;
        *hi = removal > *hi ? removal : *hi;
    }
    printf("removal of %zu leavers after their export: by a second export %.4f s (%.4f-%.4f) = "
           "%.2f steps, by sinter_stepper_remove %.4f s (%.4f-%.4f) = %.2f steps; ratio %.3f "
           "(means of %d each)\n",
           (n + 1) / 2, sum_old / repeats, min_old, max_old, sum_old / repeats / step,
           sum_new / repeats, min_new, max_new, sum_new / repeats / step, sum_new / sum_old,
           repeats);
    for (int k = 0; k < 2; ++k) {
        sinter_stepper_destroy(st[k]);
        sinter_force_model_destroy(hm[k]);
        sinter_force_model_destroy(gravity[k]);
        sinter_walls_destroy(walls[k]);
        sinter_particles_destroy(ps[k]);
    }
    sinter_material_destroy(mat);
    sinter_ctx_destroy(g_ctx);
    free(x);
    free(rad);
    free(half);
    free(all);
    return 0;
}
