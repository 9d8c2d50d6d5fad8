/*
 * Id lookups (issue 43, M0): sinter_particles_find_id on a set of N particles with scattered
 * caller-chosen ids, 10^6 lookups in a random order, against the linear scan it replaced
 * (timed on fewer lookups and scaled). Usage: id_lookup [N] (default 1 000 000).
 */
#define _POSIX_C_SOURCE 199309L
#define BENCH_NAME "id_lookup"
#include "bench_support.h"

#include <stdint.h>

static uint64_t next_random(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

int main(int argc, char **argv)
{
    const size_t n = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 1000000;
    if (n == 0)
        return 1;
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    sinter_material *m = NULL;
    sinter_particles *ps = NULL;
    CHECK(sinter_material_create(&m, g_ctx, "lookup"));
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, m));
    double *x = malloc(3 * n * sizeof(double)), *r = malloc(n * sizeof(double));
    uint64_t *ids = malloc(n * sizeof(uint64_t)), seed = 88172645463325252ULL;
    if (x == NULL || r == NULL || ids == NULL)
        return 1;
    for (size_t k = 0; k < n; ++k) {
        x[3 * k] = 1e-3 * (double)k;
        x[3 * k + 1] = x[3 * k + 2] = 0.0;
        r[k] = 4e-4;
        ids[k] = ((uint64_t)k << 20) | (next_random(&seed) & 0xfffff); /* unique, scattered */
    }
    CHECK(sinter_particles_add_with_ids(ps, n, ids, x, r, 0, 300.0, NULL));
    const size_t lookups = 1000000;
    size_t index = 0, sum = 0;
    double t0 = cpu_seconds();
    CHECK(sinter_particles_find_id(ps, ids[0], &index)); /* builds the index */
    const double build = cpu_seconds() - t0;
    t0 = cpu_seconds();
    for (size_t k = 0; k < lookups; ++k) {
        CHECK(sinter_particles_find_id(ps, ids[next_random(&seed) % n], &index));
        sum += index;
    }
    const double hashed = cpu_seconds() - t0;
    /* the linear scan of before, on 200 lookups */
    const size_t scans = 200;
    t0 = cpu_seconds();
    for (size_t k = 0; k < scans; ++k) {
        const uint64_t want = ids[next_random(&seed) % n];
        for (size_t i = 0; i < n; ++i)
            if (ids[i] == want) {
                sum += i;
                break;
            }
    }
    const double scan = (cpu_seconds() - t0) * (double)lookups / (double)scans;
    printf("N = %zu: index built in %.4f s; 10^6 lookups %.4f s (%.1f ns each); a linear scan "
           "would take %.1f s (%.0fx)  [checksum %zu]\n",
           n, build, hashed, 1e9 * hashed / (double)lookups, scan, scan / hashed, sum % 7);
    free(ids);
    free(r);
    free(x);
    sinter_particles_destroy(ps);
    sinter_material_destroy(m);
    sinter_ctx_destroy(g_ctx);
    return 0;
}
