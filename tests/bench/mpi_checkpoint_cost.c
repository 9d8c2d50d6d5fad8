/*
 * What a portable checkpoint through MPI-IO costs (issue 44, sinter_mpi_checkpoint_write /
 * _read): the settled bed of migrate_cost.c (m x m x m Hertz-Mindlin spheres with rolling
 * resistance on a floor, 200 steps), split over the ranks in x slabs (a brick), written into
 * one file by every rank, read back on every rank into the same slabs, and read on rank 0 alone
 * (the whole bed), against the mean wall time of 20 explicit steps of the whole bed measured
 * in the same run on every rank at once (a ratio, so that the machine's speed cancels; each
 * rank steps the whole bed, so the ranks share the cores as a decomposed run's would not).
 * Also the file's bytes per particle. Usage:
 *   mpiexec -n NP --oversubscribe build/bin/mpi_checkpoint_cost [m] (40: 64 000 spheres)
 *   [repeats] (3) [dir] (/tmp).
 */
#define _POSIX_C_SOURCE 199309L
#define BENCH_NAME "mpi_checkpoint_cost"
#include "bench_support.h"

#include <stdint.h>

#include "sinter_mpi.h"

typedef struct bed {
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_stepper *st;
    sinter_force_model *hm, *gravity;
} bed;

static void bed_open(bed *b, sinter_material *mat)
{
    const double r = 5e-4, p[3] = {0, 0, -r}, up[3] = {0, 0, 1};
    CHECK(sinter_particles_create(&b->ps, g_ctx));
    CHECK(sinter_particles_set_material(b->ps, 0, mat));
    CHECK(sinter_walls_create(&b->walls, g_ctx));
    CHECK(sinter_walls_add_plane(b->walls, p, up, mat, NULL));
    CHECK(sinter_stepper_create(&b->st, g_ctx, SINTER_STEPPER_EXPLICIT, b->ps, b->walls));
    CHECK(sinter_stepper_set_option(b->st, "thread_choice", 0));
    CHECK(sinter_force_model_create(&b->hm, g_ctx, "hertz_mindlin"));
    CHECK(sinter_force_model_set(b->hm, "rolling", 1.0));
    CHECK(sinter_force_model_create(&b->gravity, g_ctx, "gravity"));
    CHECK(sinter_stepper_add_force(b->st, b->hm));
    CHECK(sinter_stepper_add_force(b->st, b->gravity));
    CHECK(sinter_stepper_set_dt(b->st, 2e-6));
}

static void bed_close(bed *b)
{
    sinter_stepper_destroy(b->st);
    sinter_force_model_destroy(b->hm);
    sinter_force_model_destroy(b->gravity);
    sinter_walls_destroy(b->walls);
    sinter_particles_destroy(b->ps);
}

static double jitter(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0 - 0.5;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const size_t m = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 40;
    const int repeats = argc > 2 ? atoi(argv[2]) : 3;
    const char *dir = argc > 3 ? argv[3] : "/tmp";
    if (m == 0 || repeats <= 0)
        return 1;
    char path[4096];
    snprintf(path, sizeof path, "%s/mpi_checkpoint_cost_np%d.bin", dir, size);
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
    double *x = malloc(3 * n * sizeof(double)), *rad = malloc(n * sizeof(double));
    size_t *others = malloc(n * sizeof(size_t));
    int *owner = malloc(n * sizeof(int));
    if (x == NULL || rad == NULL || others == NULL || owner == NULL)
        return 1;
    uint64_t seed = 7;
    for (size_t k = 0; k < n; ++k) {
        x[3 * k] = pitch * (double)(k % m) + 1e-6 * jitter(&seed);
        x[3 * k + 1] = pitch * (double)((k / m) % m) + 1e-6 * jitter(&seed);
        x[3 * k + 2] = pitch * (double)(k / (m * m));
        rad[k] = r;
    }
    bed full;
    bed_open(&full, mat);
    CHECK(sinter_particles_add(full.ps, n, x, rad, 0, 300.0, NULL));
    CHECK(sinter_stepper_step(full.st, 200));
    MPI_Barrier(MPI_COMM_WORLD);
    double t0 = now();
    CHECK(sinter_stepper_step(full.st, 20));
    double step = (now() - t0) / 20.0;
    MPI_Allreduce(MPI_IN_PLACE, &step, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    /* x slabs over the bed's box */
    const double lo[3] = {-r, -r, -r}, hi[3] = {pitch * (double)m, pitch * (double)m, 1.0};
    const int grid[3] = {size, 1, 1};
    sinter_mpi_decomp *slabs = NULL, *one = NULL;
    CHECK(sinter_mpi_decomp_brick(&slabs, size, grid, lo, hi));
    CHECK(sinter_mpi_decomp_brick(&one, 1, NULL, lo, hi));
    const double *xs = NULL;
    CHECK(
        sinter_particles_view_read(full.ps, SINTER_FIELD_POSITION, (const void **)&xs, NULL, NULL));
    CHECK(sinter_mpi_decomp_owners(slabs, xs, n, owner));
    CHECK(sinter_particles_release(full.ps, SINTER_FIELD_POSITION));
    size_t leave = 0, bytes = 0, written = 0;
    for (size_t i = 0; i < n; ++i)
        if (owner[i] != rank)
            others[leave++] = i;
    CHECK(sinter_stepper_export_size(full.st, leave, others, &bytes));
    unsigned char *scratch = malloc(bytes + 1);
    CHECK(sinter_stepper_export(full.st, leave, others, scratch, bytes, &written, 1));
    free(scratch);
    if (rank == 0)
        printf("mpi_checkpoint_cost: %zu spheres on %d ranks (x slabs), one step of the whole "
               "bed %.5f s (mean of 20, the slowest rank), %d repeats\n",
               n, size, step, repeats);
    for (int rep = 0; rep < repeats; ++rep) {
        MPI_Barrier(MPI_COMM_WORLD);
        t0 = now();
        CHECK(sinter_mpi_checkpoint_write(full.st, full.ps, MPI_COMM_WORLD, path));
        MPI_Barrier(MPI_COMM_WORLD);
        const double write = now() - t0;
        bed back;
        bed_open(&back, mat);
        size_t count = 0, total = 0;
        MPI_Barrier(MPI_COMM_WORLD);
        t0 = now();
        CHECK(sinter_mpi_checkpoint_read(back.st, back.ps, MPI_COMM_WORLD, path, slabs, &count));
        MPI_Barrier(MPI_COMM_WORLD);
        const double read = now() - t0;
        MPI_Allreduce(&count, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
        bed_close(&back);
        double read_one = 0.0;
        long file_bytes = 0;
        if (rank == 0) {
            bed alone;
            bed_open(&alone, mat);
            t0 = now();
            CHECK(sinter_mpi_checkpoint_read(alone.st, alone.ps, MPI_COMM_SELF, path, one, &count));
            read_one = now() - t0;
            bed_close(&alone);
            FILE *f = fopen(path, "rb");
            if (f != NULL && fseek(f, 0, SEEK_END) == 0)
                file_bytes = ftell(f);
            if (f != NULL)
                fclose(f);
            if (total != n || count != n) {
                fprintf(stderr, "mpi_checkpoint_cost: read back %zu and %zu of %zu\n", total, count,
                        n);
                MPI_Abort(MPI_COMM_WORLD, 1);
            }
            printf("repeat %d: file %.1f MB (%.0f bytes per particle); write %.4f s = %.2f "
                   "steps; read on %d ranks %.4f s = %.2f steps; read on 1 rank %.4f s = %.2f "
                   "steps\n",
                   rep, 1e-6 * (double)file_bytes, (double)file_bytes / (double)n, write,
                   write / step, size, read, read / step, read_one, read_one / step);
        }
        MPI_Barrier(MPI_COMM_WORLD);
    }
    if (rank == 0)
        remove(path);
    sinter_mpi_decomp_destroy(slabs);
    sinter_mpi_decomp_destroy(one);
    bed_close(&full);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(g_ctx);
    free(x);
    free(rad);
    free(others);
    free(owner);
    MPI_Finalize();
    return 0;
}
