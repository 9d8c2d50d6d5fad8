/*
 * A packed bed in a triangulated die against the same bed in the analytic cylinder (issue 38:
 * the mesh costs at most 1.3 times the cylinder). Spheres of radius 0.5 mm on a jittered
 * lattice in a die of radius 6 mm (Hertz-Mindlin, gravity, a disc floor) settle for `steps`
 * steps; each seed runs the cylinder, then the mesh (a tube of `facets` facets around, rings
 * about as tall as wide, particles inside: its normals flipped), one thread, and prints both
 * times, their ratio and the die's radial reaction (the sum of |f| in the plane normal to the
 * axis), which the facets' offset from the circle, Rc (1 - cos(pi / facets)), changes a little.
 * Times are the steps' CPU time (the process's, one thread), so that other work on the host
 * counts less; the radial forces print all their digits (a change of the search that is to
 * keep every bit can be checked against an earlier library).
 *
 *   mesh_bench [particles=2000] [steps=4000] [facets=48] [seeds=3] [reach=0 m] [only=0]
 * (only: 1 runs the cylinder alone, 2 the mesh alone, for a profiler)
 */
#define _POSIX_C_SOURCE 200809L
#define BENCH_NAME "mesh_bench"
#include <math.h>
#include <stdint.h>
#include <unistd.h>

#include "bench_support.h"

static const double PI = 3.14159265358979323846;
static const double R = 0.5e-3, RC = 6e-3;
static double reach = 0.0; /* the mesh's, argument 5 [m] (0: exact everywhere) */

/* A binary STL tube: radius rc about z from 0 to height, `facets` around, outward normals. */
static void write_tube(const char *path, int facets, double rc, double height)
{
    const double width = 2.0 * PI * rc / facets;
    const int rings = (int)ceil(height / width);
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    char header[80] = "mesh_bench tube";
    fwrite(header, 1, 80, f);
    const uint32_t count = (uint32_t)(2 * facets * rings);
    const unsigned char c[4] = {(unsigned char)count, (unsigned char)(count >> 8),
                                (unsigned char)(count >> 16), (unsigned char)(count >> 24)};
    fwrite(c, 1, 4, f);
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < facets; ++i) {
            const double p0 = 2 * PI * i / facets, p1 = 2 * PI * (i + 1) / facets;
            const double z0 = height * j / rings, z1 = height * (j + 1) / rings;
            const float a[3] = {(float)(rc * cos(p0)), (float)(rc * sin(p0)), (float)z0};
            const float b[3] = {(float)(rc * cos(p1)), (float)(rc * sin(p1)), (float)z0};
            const float d[3] = {(float)(rc * cos(p1)), (float)(rc * sin(p1)), (float)z1};
            const float e[3] = {(float)(rc * cos(p0)), (float)(rc * sin(p0)), (float)z1};
            const float *tri[2][3] = {{a, b, d}, {a, d, e}}; /* outward */
            for (int t = 0; t < 2; ++t) {
                const float zero[3] = {0, 0, 0};
                fwrite(zero, sizeof(float), 3, f);
                for (int v = 0; v < 3; ++v)
                    fwrite(tri[t][v], sizeof(float), 3, f);
                const unsigned char attr[2] = {0, 0};
                fwrite(attr, 1, 2, f);
            }
        }
    fclose(f);
}

/* The process's CPU time [s] (one thread: the steps' own, whatever else the host runs). */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One run: CPU seconds of the steps, and the die's radial reaction [N]. */
static double run(int mesh, const char *path, size_t n, int steps, unsigned seed, double *radial)
{
    sinter_ctx *ctx = NULL;
    CHECK(sinter_ctx_create(&ctx, NULL));
    g_ctx = ctx;
    CHECK(sinter_ctx_set_threads(ctx, 1));
    sinter_material *mat = NULL, *wall = NULL;
    CHECK(sinter_material_create(&mat, ctx, "powder"));
    CHECK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    CHECK(sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500.0));
    CHECK(sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, 0.5));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_STATIC, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DYNAMIC, 0.3));
    CHECK(sinter_material_clone(&wall, mat));
    sinter_particles *ps = NULL;
    CHECK(sinter_particles_create(&ps, ctx));
    CHECK(sinter_particles_set_material(ps, 0, mat));
    /* a jittered lattice of spacing 2.2 R inside the die, layer after layer */
    srand(seed);
    const double a = 2.2 * R;
    size_t placed = 0;
    for (int layer = 0; placed < n; ++layer)
        for (int i = -20; i <= 20 && placed < n; ++i)
            for (int j = -20; j <= 20 && placed < n; ++j) {
                const double x = i * a, y = j * a;
                if (sqrt(x * x + y * y) > RC - 1.3 * R)
                    continue;
                const double jit = 0.05 * R;
                const double p[3] = {x + jit * (2.0 * rand() / RAND_MAX - 1.0),
                                     y + jit * (2.0 * rand() / RAND_MAX - 1.0),
                                     1.2 * R + layer * a};
                const double r = R;
                CHECK(sinter_particles_add(ps, 1, p, &r, 0, 300.0, NULL));
                ++placed;
            }
    sinter_walls *walls = NULL;
    CHECK(sinter_walls_create(&walls, ctx));
    const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    size_t die = 0;
    if (mesh)
        CHECK(sinter_walls_add_mesh(walls, path, 1.0, o, o, 1, reach, wall, &die));
    else
        CHECK(sinter_walls_add_cylinder(walls, o, up, RC, HUGE_VAL, 1, wall, &die));
    CHECK(sinter_walls_add_disc(walls, o, up, 2.0 * RC, wall, NULL));
    sinter_stepper *st = NULL;
    CHECK(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    CHECK(sinter_stepper_set_option(st, "thread_choice", 0));
    sinter_force_model *hm = NULL, *g = NULL;
    CHECK(sinter_force_model_create(&hm, ctx, "hertz_mindlin"));
    CHECK(sinter_force_model_create(&g, ctx, "gravity"));
    CHECK(sinter_stepper_add_force(st, hm));
    CHECK(sinter_stepper_add_force(st, g));
    const double dt = 2e-6;
    CHECK(sinter_stepper_set_dt(st, dt));
    const double t0 = cpu_now();
    CHECK(sinter_stepper_advance(st, steps * dt));
    const double seconds = cpu_now() - t0;
    double f[3];
    CHECK(sinter_walls_get_force(walls, die, f));
    *radial = sqrt(f[0] * f[0] + f[1] * f[1]);
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(g);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_material_destroy(wall);
    sinter_ctx_destroy(ctx);
    return seconds;
}

int main(int argc, char **argv)
{
    const size_t n = argc > 1 ? (size_t)atol(argv[1]) : 2000;
    const int steps = argc > 2 ? atoi(argv[2]) : 4000;
    const int facets = argc > 3 ? atoi(argv[3]) : 48;
    const int seeds = argc > 4 ? atoi(argv[4]) : 3;
    reach = argc > 5 ? atof(argv[5]) : 0.0;
    const int only = argc > 6 ? atoi(argv[6]) : 0; /* 1: the cylinder only, 2: the mesh only */
    char path[64] = "/tmp/mesh_benchXXXXXX";
    const int fd = mkstemp(path);
    if (fd < 0)
        return 1;
    close(fd);
    const double height = 2.2 * R * (double)n / (PI * RC * RC / (2.2 * R * 2.2 * R)) + 4.0 * R;
    write_tube(path, facets, RC, height);
    printf("# %zu particles, %d steps, %d facets around (offset %.3e m), tube height %.3e m\n", n,
           steps, facets, RC * (1.0 - cos(PI / facets)), height);
    printf("# seed  cylinder_s  mesh_s  ratio  radial_cyl_N  radial_mesh_N\n");
    double sum = 0.0, sum2 = 0.0;
    for (int s = 0; s < seeds; ++s) {
        double fc = 0.0, fm = 0.0;
        const double tc = only == 2 ? 1.0 : run(0, path, n, steps, 1u + (unsigned)s, &fc);
        const double tm = only == 1 ? 1.0 : run(1, path, n, steps, 1u + (unsigned)s, &fm);
        printf("%d  %.3f  %.3f  %.3f  %.17e  %.17e\n", s + 1, tc, tm, tm / tc, fc, fm);
        sum += tm / tc;
        sum2 += (tm / tc) * (tm / tc);
    }
    const double mean = sum / seeds,
                 sd = seeds > 1 ? sqrt(fmax(sum2 / seeds - mean * mean, 0.0) * seeds / (seeds - 1))
                                : 0.0;
    printf("# mesh / cylinder time: %.3f +- %.3f (mean +- standard deviation over %d seeds)\n",
           mean, sd, seeds);
    unlink(path);
    return 0;
}
