/*
 * mpi_packed_bed: the 64 000-sphere packed bed of the peer benchmark (peer_bench.c's thermal
 * scene: an n x n x n simple-cubic lattice of r = 0.5 mm spheres at spacing s = 2r (1 - 1e-3),
 * 1 um overlap per contact, five walls, gravity, Hertz-Mindlin with LIGGGHTS' damping, optional
 * conduction) run through libsinter_mpi (sinter_mpi_attach) on however many ranks mpiexec
 * gives it (issue 44, "Tests and measurements": speed and communication volume).
 *
 *   mpiexec -n NP build/bin/mpi_packed_bed [--n 40] [--steps 200] [--heat 1] [--dt 1e-5]
 *                                          [--grid GX GY GZ] [--balance 0|1] [--tall F]
 *                                          [--skin 1e-4]
 *
 * Every rank builds the same lattice and keeps the spheres whose centres its part of a brick
 * over the bed's box [0, n s]^3 holds (sinter_mpi_decomp_owners; --grid fixes the ranks per
 * axis, default: the brick of least cut area). step(0) (the first distribution, neighbour
 * build and forces) is left out of the timing, as in peer_bench. --tall F makes the domain's
 * box F times the bed's height and (without --grid) z slabs: the bed in the bottom 1/F of the
 * box, as after a pour, for the imbalance of the static brick and of --balance 1 (a bisection
 * at the first rebuild); --skin sets the neighbour-list skin (a small one makes rebuilds in the
 * resting bed, for the rebuild traffic). Rank 0 prints:
 *
 *   TIME   wall and CPU seconds per step (CPU: summed over the ranks, and the largest rank's;
 *          Open MPI ranks that wait in a collective spin, so CPU time includes waiting), the
 *          microseconds per particle-step, the largest rank's own work (the stepper's
 *          neighbour, force and integration phases, wall time) and the load average before
 *          and after;
 *   COMM   per step of the timed loop: halos, bytes sent and messages (summed over the ranks),
 *          ghosts (sum and largest), owned (smallest and largest), migrations, redistributions,
 *          imbalance, the seconds in exchanges and reductions (largest rank), the reductions
 *          per step and the bytes of the first distribution (the one-off rebuild traffic);
 *   MODEL  the ghosts predicted from the geometry (each cut plane of area A within the bed
 *          gives 2 A c / s^3 ghosts in the continuum estimate, c the ghost cut-off, and
 *          2 floor(c/s) lattice layers of A / s^2 spheres on this lattice; the area from the
 *          parts' boxes, a brick's or a bisection's) and the halo bytes per step they
 *          imply (halos per step x 13 doubles x ghosts; the explicit step has no reverse halo);
 *   SANITY the peer benchmark's mean height, contacts per sphere and mean temperature, summed
 *          over the ranks (to compare the decomposed run with np 1).
 */
#define _POSIX_C_SOURCE 200809L
#define BENCH_NAME "mpi_packed_bed"
#include "bench_support.h"

#include <math.h>
#include <stdint.h>

#include "sinter_domain.h"
#include "sinter_mpi.h"

static void load_average(double out[1])
{
    FILE *f = fopen("/proc/loadavg", "r");
    out[0] = -1.0;
    if (f != NULL) {
        if (fscanf(f, "%lf", out) != 1)
            out[0] = -1.0;
        fclose(f);
    }
}

static void usage(void)
{
    fprintf(stderr, "usage: mpiexec -n NP mpi_packed_bed [--n 40] [--steps 200] [--heat 0|1] "
                    "[--dt 1e-5] [--grid GX GY GZ] [--balance 0|1] [--tall F] [--skin 1e-4]\n");
    MPI_Abort(MPI_COMM_WORLD, 1);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int n = 40, heat = 1, balance = 0, grid[3] = {0, 0, 0};
    double tall = 1.0; /* the domain's box: tall times the bed's height */
    unsigned long long steps = 200;
    double dt = 1e-5, skin = 1e-4;
    for (int a = 1; a < argc; ++a) {
        if (a + 1 >= argc)
            usage();
        if (strcmp(argv[a], "--n") == 0)
            n = atoi(argv[++a]);
        else if (strcmp(argv[a], "--steps") == 0)
            steps = strtoull(argv[++a], NULL, 10);
        else if (strcmp(argv[a], "--heat") == 0)
            heat = atoi(argv[++a]);
        else if (strcmp(argv[a], "--balance") == 0)
            balance = atoi(argv[++a]);
        else if (strcmp(argv[a], "--tall") == 0)
            tall = strtod(argv[++a], NULL);
        else if (strcmp(argv[a], "--skin") == 0)
            skin = strtod(argv[++a], NULL);
        else if (strcmp(argv[a], "--dt") == 0)
            dt = strtod(argv[++a], NULL);
        else if (strcmp(argv[a], "--grid") == 0 && a + 3 < argc) {
            for (int d = 0; d < 3; ++d)
                grid[d] = atoi(argv[++a]);
        } else
            usage();
    }
    if (n < 1 || steps == 0 || !(dt > 0.0) || !(tall >= 1.0) || !(skin > 0.0))
        usage();

    /* ---- the lattice of gen_lattice.py --scene thermal (peer benchmark) ---------------------- */
    const double r = 0.5e-3, d = 2 * r, s = d * (1 - 1e-3), L = n * s;
    const double box[6] = {0.0, L, 0.0, L, 0.0, L + 4 * d};
    const size_t total = (size_t)n * (size_t)n * (size_t)n;

    sinter_mpi_options o;
    CHECK(sinter_mpi_options_init(&o, sizeof o));
    const double lo[3] = {0, 0, 0}, hi[3] = {L, L, tall * L}; /* (the walls' box is taller) */
    if (tall > 1.0 && grid[0] == 0 && grid[1] == 0 && grid[2] == 0)
        grid[2] = size; /* z slabs: the bed in the bottom part(s), as after a pour */
    memcpy(o.grid, grid, sizeof grid);
    memcpy(o.lo, lo, sizeof lo);
    memcpy(o.hi, hi, sizeof hi);
    sinter_mpi_domain *dom = NULL;
    CHECK(sinter_mpi_domain_create(&dom, MPI_COMM_WORLD, &o));
    const sinter_mpi_decomp *decomp = NULL;
    CHECK(sinter_mpi_domain_decomp(dom, &decomp));
    int g[3] = {1, 1, 1};
    CHECK(sinter_mpi_decomp_grid(decomp, g));

    double *x = malloc(3 * total * sizeof(double)), *rad = malloc(total * sizeof(double));
    uint64_t *id = malloc(total * sizeof(uint64_t));
    int *owner = malloc(total * sizeof(int));
    if (x == NULL || rad == NULL || id == NULL || owner == NULL)
        MPI_Abort(MPI_COMM_WORLD, 1);
    for (size_t k = 0; k < total; ++k) {
        const size_t i = k % (size_t)n, j = (k / (size_t)n) % (size_t)n,
                     l = k / ((size_t)n * (size_t)n);
        x[3 * k] = ((double)i + 0.5) * s;
        x[3 * k + 1] = ((double)j + 0.5) * s;
        x[3 * k + 2] = ((double)l + 0.5) * s;
    }
    CHECK(sinter_mpi_decomp_owners(decomp, x, total, owner));
    size_t mine = 0;
    for (size_t k = 0; k < total; ++k)
        if (owner[k] == rank) {
            memmove(x + 3 * mine, x + 3 * k, 3 * sizeof(double));
            rad[mine] = r;
            id[mine++] = (uint64_t)k + 1;
        }

    /* the brick's imbalance as created (largest part over the mean), before any balancing */
    double imbalance_brick = (double)mine;
    MPI_Allreduce(MPI_IN_PLACE, &imbalance_brick, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    imbalance_brick *= (double)size / (double)total;

    /* ---- peer_bench's canonical material, walls and stepper (liggghts/in.mech) -------------- */
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    CHECK(sinter_ctx_set_threads(g_ctx, 1));
    double xi;
    CHECK(sinter_damping_ratio_from_restitution(0.5, &xi));
    sinter_material *mat, *adiabatic;
    CHECK(sinter_material_create(&mat, g_ctx, "canonical"));
    CHECK(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500.0));
    CHECK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    CHECK(sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, xi));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_STATIC, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DYNAMIC, 0.3));
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DAMPING_RATIO, xi));
    CHECK(sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 100.0));
    CHECK(sinter_material_set(mat, SINTER_MAT_HEAT_CAPACITY, 100.0));
    CHECK(sinter_material_clone(&adiabatic, mat));
    CHECK(sinter_material_set(adiabatic, SINTER_MAT_THERMAL_CONDUCTIVITY, 0.0));
    sinter_particles *ps;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, mat));
    if (mine > 0)
        CHECK(sinter_particles_add_with_ids(ps, mine, id, x, rad, 0, 300.0, NULL));
    free(x);
    free(rad);
    free(id);
    free(owner);
    sinter_walls *walls;
    CHECK(sinter_walls_create(&walls, g_ctx));
    const double planes[5][6] = {{0, 0, box[4], 0, 0, 1},
                                 {box[0], 0, 0, 1, 0, 0},
                                 {box[1], 0, 0, -1, 0, 0},
                                 {0, box[2], 0, 0, 1, 0},
                                 {0, box[3], 0, 0, -1, 0}};
    for (int k = 0; k < 5; ++k)
        CHECK(sinter_walls_add_plane(walls, planes[k], planes[k] + 3, k == 0 ? mat : adiabatic,
                                     NULL));
    CHECK(sinter_walls_set_temperature(walls, 0, 500.0));
    sinter_stepper *st;
    sinter_force_model *hm, *grav;
    sinter_heat_model *cond = NULL;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    CHECK(sinter_force_model_create(&hm, g_ctx, "hertz_mindlin"));
    CHECK(sinter_force_model_set(hm, "rolling", 0.0));
    CHECK(sinter_force_model_create(&grav, g_ctx, "gravity"));
    CHECK(sinter_force_model_set(grav, "gz", -9.81));
    CHECK(sinter_stepper_add_force(st, grav));
    CHECK(sinter_stepper_add_force(st, hm));
    CHECK(sinter_stepper_set_dt(st, dt));
    CHECK(sinter_stepper_set_skin(st, skin)); /* the peer's 1e-4 m by default */
    CHECK(sinter_stepper_set_option(st, "rotation", 0.0));
    CHECK(sinter_stepper_set_option(st, "thread_choice", 0.0));
    if (heat) {
        CHECK(sinter_heat_model_create(&cond, g_ctx, "conduction"));
        CHECK(sinter_heat_model_set(cond, "area", 1.0));
        CHECK(sinter_stepper_add_heat(st, cond));
    }
    CHECK(sinter_mpi_attach(dom, st, ps, balance ? SINTER_MPI_ATTACH_BALANCE : 0));

    /* ---- step(0) untimed, then the timed loop -------------------------------------------- */
    CHECK(sinter_stepper_step(st, 0));
    sinter_mpi_exchange_stats x0 = {.struct_size = sizeof x0}, x1 = x0;
    sinter_mpi_stats m0 = {.struct_size = sizeof m0}, m1 = m0;
    CHECK(sinter_mpi_get_exchange_stats(dom, &x0));
    CHECK(sinter_mpi_get_stats(dom, &m0));
    double cutoff = 0.0, load[2];
    CHECK(sinter_stepper_ghost_cutoff(st, &cutoff));
    load_average(load);
    sinter_stepper_stats p0 = {.struct_size = sizeof p0}, p1 = p0;
    CHECK(sinter_stepper_get_stats(st, &p0));
    MPI_Barrier(MPI_COMM_WORLD);
    const double t0 = now(), c0 = cpu_seconds();
    CHECK(sinter_stepper_step(st, steps));
    const double c1 = cpu_seconds();
    MPI_Barrier(MPI_COMM_WORLD);
    const double wall = now() - t0;
    load_average(load + 1);
    CHECK(sinter_mpi_get_exchange_stats(dom, &x1));
    CHECK(sinter_mpi_get_stats(dom, &m1));
    CHECK(sinter_stepper_get_stats(st, &p1));
    /* this rank's own work: the stepper's neighbour, force and integration phases (wall) */
    const double work = (p1.seconds_neighbor - p0.seconds_neighbor) +
                        (p1.seconds_force - p0.seconds_force) +
                        (p1.seconds_integrate - p0.seconds_integrate);

    /* ---- the counters over the ranks ------------------------------------------------------ */
    const double per = 1.0 / (double)steps;
    double sums[8] = {c1 - c0,
                      (double)(x1.bytes_sent - x0.bytes_sent),
                      (double)(x1.messages_sent - x0.messages_sent),
                      (double)x1.ghosts,
                      (double)(x1.migrated_out - x0.migrated_out),
                      (double)x0.bytes_sent,
                      (double)(m1.reduce_bytes - m0.reduce_bytes),
                      (double)x1.owned};
    double maxs[6] = {c1 - c0,
                      (double)x1.ghosts,
                      x1.seconds_comm - x0.seconds_comm,
                      m1.seconds_comm - m0.seconds_comm,
                      (double)x1.owned,
                      work};
    double mins[1] = {(double)x1.owned};
    MPI_Allreduce(MPI_IN_PLACE, sums, 8, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, maxs, 6, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, mins, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);

    /* ---- sanity values (peer_bench's), summed over the ranks ------------------------------ */
    const double *xs, *ms, *ts;
    const size_t owned = x1.owned;
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&xs, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_MASS, (const void **)&ms, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&ts, NULL, NULL));
    double san[3] = {0, 0, 0}; /* sum m z, sum m, sum T */
    for (size_t i = 0; i < owned; ++i) {
        san[0] += ms[i] * xs[3 * i + 2];
        san[1] += ms[i];
        san[2] += ts[i];
    }
    CHECK(sinter_particles_release(ps, SINTER_FIELD_POSITION));
    CHECK(sinter_particles_release(ps, SINTER_FIELD_MASS));
    CHECK(sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE));
    MPI_Allreduce(MPI_IN_PLACE, san, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    sinter_stepper_stats gs = {.struct_size = sizeof gs};
    CHECK(sinter_stepper_get_stats_global(st, &gs));

    /* ---- the model: ghosts from the geometry of the parts' faces inside the bed ----------- */
    /* Each face of a part's box that cuts the bed (the cube [0, L]^3) receives the spheres of
     * the far side within the cut-off c of its owned spheres: continuum A c / s^3, on this
     * lattice floor(c / s) layers of A / s^2 (the cut planes lie between layers; diagonal
     * neighbours add none, as s sqrt 2 > c). Counted from both sides, as the ghosts are. */
    CHECK(sinter_mpi_domain_decomp(dom, &decomp));
    double area = 0.0; /* both sides of every cut plane within the bed [m^2] */
    for (int part = 0; part < size; ++part) {
        double plo[3], phi[3];
        CHECK(sinter_mpi_decomp_box(decomp, part, plo, phi));
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            const double wb = fmin(phi[b], L) - fmax(plo[b], 0.0),
                         wc = fmin(phi[c], L) - fmax(plo[c], 0.0);
            if (wb <= 0.0 || wc <= 0.0)
                continue;
            area += (plo[a] > 1e-9 * L && plo[a] < L ? wb * wc : 0.0) +
                    (phi[a] > 0.0 && phi[a] < L * (1 - 1e-9) ? wb * wc : 0.0);
        }
    }
    const double ghosts_continuum = area * cutoff / (s * s * s),
                 ghosts_lattice = floor(cutoff / s) * area / (s * s);
    const double halos = (double)(x1.halos - x0.halos) * per;

    if (rank == 0) {
        printf("MPI_PACKED_BED np=%d N=%zu grid=%dx%dx%d tall=%g steps=%llu dt=%g heat=%d "
               "balance=%d cutoff=%.6g m imbalance_brick=%.4f rebalances=%llu\n",
               size, total, g[0], g[1], g[2], tall, steps, dt, heat, balance, cutoff,
               imbalance_brick, (unsigned long long)m1.rebalances);
        printf("TIME wall_per_step=%.6g s cpu_per_step_sum=%.6g s cpu_per_step_max_rank=%.6g s "
               "us_per_particle_step=%.6g (wall x np / N) work_per_step_max_rank=%.6g s "
               "load_before=%.2f load_after=%.2f\n",
               wall * per, sums[0] * per, maxs[0] * per, 1e6 * wall * per * size / (double)total,
               maxs[5] * per, load[0], load[1]);
        printf("COMM halos_per_step=%.3g bytes_sent_per_step=%.6g messages_per_step=%.4g "
               "ghosts_sum=%.0f ghosts_max=%.0f owned_min=%.0f owned_max=%.0f "
               "migrations=%.0f redistributions=%llu imbalance=%.4f comm_s_per_step_max=%.4g "
               "reduce_s_per_step_max=%.4g reductions_per_step=%.4g reduce_bytes_per_step=%.4g "
               "first_distribution_bytes=%.6g neighbours_rank0=%d\n",
               halos, sums[1] * per, sums[2] * per, sums[3], maxs[1], mins[0], maxs[4], sums[4],
               (unsigned long long)(x1.redistributions - x0.redistributions), x1.imbalance,
               maxs[2] * per, maxs[3] * per, (double)(m1.reductions - m0.reductions) * per,
               sums[6] * per / size, sums[5], x1.neighbours);
        printf("MODEL cut_area=%.6g m^2 ghosts_continuum=%.0f ghosts_lattice=%.0f "
               "halo_bytes_per_step_lattice=%.6g halo_bytes_per_step_continuum=%.6g "
               "(measured ghosts x 13 x 8 x halos: %.6g) rebuild_bytes_per_redistribution=%.6g "
               "(the bytes beyond the halos' at the final ghost count; model 144 x ghosts = %.6g "
               "plus the migrants' records)\n",
               area, ghosts_continuum, ghosts_lattice, halos * 13 * 8 * ghosts_lattice,
               halos * 13 * 8 * ghosts_continuum, halos * 13 * 8 * sums[3],
               x1.redistributions > x0.redistributions
                   ? (sums[1] - (double)(x1.halos - x0.halos) * 13 * 8 * sums[3]) /
                         (double)(x1.redistributions - x0.redistributions)
                   : 0.0,
               144.0 * sums[3]);
        printf("SANITY zmean=%.10g Zcontacts=%.10g Tmean=%.10g\n", san[0] / san[1],
               2.0 * (double)gs.contacts / (double)total, san[2] / (double)total);
    }
    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(cond);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(grav);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(adiabatic);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(g_ctx);
    sinter_mpi_domain_destroy(dom);
    MPI_Finalize();
    return 0;
}
