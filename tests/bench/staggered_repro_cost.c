/*
 * The staggered stepper's reproducible mode: its cost on one subdomain (issue 43). A lattice
 * press in the manner of examples/scenes/press_staggered.scene (the seed 000 power law, drag,
 * gravity, conduction, Joule heating, the averaged electric model between two current walls,
 * the top one moving down; adaptive steps), the press of tests/unit/
 * test_domain_staggered_repro.c made larger, run for a number of steps with the option
 * "reproducible" at 0 or 1, without domain operations. Measure instructions with callgrind at
 * two step counts and take the difference (the set-up cancels); the program prints what the
 * run counted (steps, rejections, fixed-point iterations, the electric model's sweeps), which
 * the two modes may do differently (Jacobi against Gauss-Seidel sweeps).
 *
 *   staggered_repro_cost --reproducible R --steps K [--scheme S] [--side M] [--layers L]
 *                        [--network 1]
 *
 * --network 1: the "network" electric model instead (1 A from the floor to the grounded top
 * wall, PCG tolerance 1e-10, as test_domain_staggered_repro.c's network press); the electric
 * count printed is then the PCG's iterations.
 *
 * RESULTS.md, "The staggered stepper's reproducible mode", has the figures and the command.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter.h>

#include "../unit/domain_press_models.h"

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

#define CHECK(call)                                                                                \
    do {                                                                                           \
        const sinter_status s_ = (call);                                                           \
        if (s_ != SINTER_OK) {                                                                     \
            fprintf(stderr, "%s failed: %s\n", #call, sinter_last_error(ctx));                     \
            return 1;                                                                              \
        }                                                                                          \
    } while (0)

int main(int argc, char **argv)
{
    int reproducible = 0, steps = 10, scheme = 1, side = 10, layers = 6, network = 0;
    for (int a = 1; a + 1 < argc; a += 2) {
        const int v = atoi(argv[a + 1]);
        if (strcmp(argv[a], "--reproducible") == 0)
            reproducible = v;
        else if (strcmp(argv[a], "--steps") == 0)
            steps = v;
        else if (strcmp(argv[a], "--scheme") == 0)
            scheme = v;
        else if (strcmp(argv[a], "--side") == 0)
            side = v;
        else if (strcmp(argv[a], "--layers") == 0)
            layers = v;
        else if (strcmp(argv[a], "--network") == 0)
            network = v;
        else {
            fprintf(stderr, "unknown option %s\n", argv[a]);
            return 2;
        }
    }
    const double R = 0.05, A = 0.099; /* radius and lattice spacing [m]: 1 % overlap */
    const double LX = R + A * (side - 1) + R, TOP = R + A * (layers - 1) + 0.99 * R;
    sinter_ctx *ctx = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    CHECK(sinter_ctx_set_threads(ctx, 1));
    sinter_material *mat = NULL;
    CHECK(domain_press_material(ctx, &mat));
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, ctx));
    CHECK(sinter_particles_set_material(ps, 0, mat));
    sinter_walls *walls = NULL;
    CHECK(domain_press_walls(ctx, mat, LX, LX, TOP, &walls));
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, ctx, SINTER_STEPPER_STAGGERED, ps, walls));
    domain_press_models models = {NULL, NULL, NULL, NULL, NULL, NULL};
    CHECK(domain_press_add_models(ctx, st, 1e-4, &models)); /* the scene's electric tolerance */
    sinter_electric_model *em = NULL;
    if (network) {
        CHECK(sinter_electric_model_create(&em, ctx, "network"));
        CHECK(sinter_electric_model_set(em, "tolerance", 1e-10));
        CHECK(sinter_stepper_set_electric(st, em));
        CHECK(sinter_walls_set_electric(walls, 0, SINTER_WALL_CURRENT, 1.0));
        CHECK(sinter_walls_set_electric(walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    }
    CHECK(sinter_stepper_set_option(st, "reproducible", reproducible));
    CHECK(sinter_stepper_set_option(st, "scheme", scheme));
    CHECK(sinter_stepper_set_dt(st, 0.005));
    CHECK(sinter_stepper_set_option(st, "dt_max", 0.005));
    CHECK(sinter_stepper_set_option(st, "dt_min", 1e-7));
    CHECK(sinter_stepper_set_option(st, "position_tolerance", 1e-6));
    CHECK(sinter_stepper_set_skin(st, 0.01));
    uint64_t seed = 28;
    const int n = side * side * layers;
    for (int k = 0; k < n; ++k) {
        const int i = k % side, j = (k / side) % side, l = k / (side * side);
        const double x[3] = {R + A * i + 0.002 * R * (lcg(&seed) - 0.5),
                             R + A * j + 0.002 * R * (lcg(&seed) - 0.5),
                             0.99 * R + A * l + 0.002 * R * (lcg(&seed) - 0.5)};
        double v[3];
        for (int d = 0; d < 3; ++d)
            v[d] = 0.01 * (lcg(&seed) - 0.5);
        const uint64_t id = 1 + (uint64_t)((k * 37) % n); /* (37 prime to the counts used) */
        size_t first = 0;
        CHECK(
            sinter_particles_add_with_ids(ps, 1, &id, x, &R, 0, 300.0 + 50.0 * lcg(&seed), &first));
        double *vel = NULL;
        CHECK(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&vel, NULL, NULL));
        memcpy(vel + 3 * first, v, sizeof(v));
        CHECK(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
    }
    for (int k = 0; k < steps; ++k)
        CHECK(sinter_stepper_step(st, 1));
    sinter_stepper_stats stats = {.struct_size = sizeof(stats)};
    CHECK(sinter_stepper_get_stats(st, &stats));
    uint64_t sweeps = 0;
    CHECK(sinter_stepper_electric_iterations(st, &sweeps));
    double t = 0.0;
    CHECK(sinter_stepper_time(st, &t));
    printf("particles %d network %d reproducible %d scheme %d: %llu steps, %llu rejected, %llu "
           "iterations, "
           "%llu evaluations, %llu builds, %llu electric sweeps, t = %.9g s\n",
           n, network, reproducible, scheme, (unsigned long long)stats.steps,
           (unsigned long long)stats.rejected, (unsigned long long)stats.iterations,
           (unsigned long long)stats.evaluations, (unsigned long long)stats.neighbor_builds,
           (unsigned long long)sweeps, t);
    sinter_stepper_destroy(st);
    domain_press_models_destroy(&models);
    sinter_electric_model_destroy(em);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
    return 0;
}
