/*
 * peer_bench: libsinter's entry in the peer DEM benchmark (the same canonical scenes run by
 * LIGGGHTS, LAMMPS and Yade, kept outside this repository).
 *
 *   peer_bench --scene {scene} --xyz {xyz} --box {box} --steps {steps} --dt {dt} --heat {heat}
 *              [--stats]
 *
 * Runs the canonical scene of the peer README with the public API only and prints the lines
 * the harness (bench.py) parses, in the same form as the LIGGGHTS decks (liggghts/in.mech):
 *
 *   Loop time of <s> on 1 procs for <steps> steps with <N> atoms
 *   SANITY zmax_top=... zmean=... KEtrans=... KErot=... Zcontacts=...
 *   PROBE z1=... z2=...
 *
 * The geometry comes entirely from the .xyz ("x y z r" per line) and .box ("xlo xhi ylo yhi
 * zlo zhi") files written by gen_lattice.py, so the same program serves the mech, thermal and
 * calib scenes. --heat 1 adds the thermal scene's conduction: the "conduction" heat model
 * with LIGGGHTS' projection conductance (4 k1 k2/(k1+k2) sqrt(pi r^2) = 2 sqrt(pi) k r per
 * contact), k = 100 W/(m K), c_p = 100 J/(kg K), T0 = 300 K, the floor at 500 K with the
 * particles' conductivity and the side walls adiabatic (k = 0), explicit thermal update.
 * The total rotation vector (seed 003 eq. 45) is not integrated (stepper option "rotation"
 * 0), as LIGGGHTS' fix nve/sphere integrates no orientation either; --rotation 1 adds it.
 * --stats prints the stepper's phase times of the timed loop and the peak resident memory
 * (VmHWM) to stderr; --threads N sets the library's threads (default 1).
 *
 * --alternate K (with --threads N > 1) measures the N-thread speed-up on a host whose speed
 * drifts from minute to minute (RESULTS.md, issue 9, session 19): the timed loop runs in
 * blocks of K steps, by turns on one thread and on N (the order swapped every other pair),
 * and prints an ALTERNATE line with each side's time and the ratio; pairs of neighbouring
 * blocks see the same host minute, so a slow minute slows both sides. The library gives the
 * same bits on any thread count, so the run is the same simulation as one on either count.
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, CLOCK_MONOTONIC under -std=c11 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "peer_bench"
#include "bench_support.h"
#include "sinter.h"

static void usage(void)
{
    fprintf(stderr,
            "usage: peer_bench --scene S --xyz FILE --box FILE --steps N --dt DT "
            "--heat 0|1 [--stats] [--threads N] [--shuffle SEED] [--sort-interval K]\n"
            "       [--rotation 0|1] [--thread-choice -1|0] [--rolling MU_R] [--alternate K]\n"
            "       [--reproducible 0|1]\n"
            "  --shuffle: the particles in a random order in memory (as an unsorted host\n"
            "    would give them; the PROBE line then follows other particles)\n"
            "  --sort-interval: stepper option sort_interval (spatial sort every K steps)\n"
            "  --reproducible: stepper option reproducible (1: pairs in id order, sums on one\n"
            "    thread: the same bits for any order, thread count and decomposition)\n"
            "  --thread-choice: stepper option thread_choice (-1, the default, times\n"
            "    steps on the threads and on one and takes the faster; 0 always --threads)\n"
            "  --rotation: stepper option rotation (1 integrates the rotation vector;\n"
            "    default 0, as the peers)\n"
            "  --rolling: rolling resistance (seed 003 eq. 15-20) with coefficient MU_R\n"
            "    and rolling damping ratio 0.3 (default 0: the rolling model left out, as\n"
            "    the peer decks have none)\n"
            "  --alternate: blocks of K steps by turns on one thread and on --threads,\n"
            "    the ALTERNATE line gives each side's time and the speed-up\n"
            "  --alternate-option KEY: with --alternate K, blocks by turns with the stepper\n"
            "    option KEY at 0 and at 1 on --threads (e.g. energy_check: its cost, as the\n"
            "    ratio of the time with it on to the time without)\n");
    exit(1);
}

static int compare_doubles(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The timed loop in blocks of `block` steps by turns on one thread and on `threads` (one
 * first, then `threads` first, ...); prints the ALTERNATE line: each side's steps and time,
 * the ratio of their times per step, and the median and range of the block pairs' ratios. */
static void alternate_threads(sinter_stepper *st, unsigned long long steps,
                              unsigned long long block, int threads, const char *option)
{
    double side[2] = {0.0, 0.0};
    unsigned long long done[2] = {0, 0}, pairs = 0;
    size_t nratio = 0;
    double *ratios = malloc((size_t)(steps / block / 2 + 2) * sizeof(double));
    if (ratios == NULL)
        exit(1);
    CHECK(sinter_stepper_set_option(st, "thread_choice", 0.0)); /* no choosing: the count given */
    for (unsigned long long k = 0; k < steps; ++pairs) {
        double pair[2] = {0.0, 0.0};
        unsigned long long taken[2] = {0, 0};
        for (int turn = 0; turn < 2 && k < steps; ++turn) {
            const int which = (int)(pairs % 2) ^ turn; /* 0: one thread, 1: `threads` */
            const unsigned long long m = steps - k < block ? steps - k : block;
            if (option != NULL) /* side 0: the option at 0, side 1: at 1 */
                CHECK(sinter_stepper_set_option(st, option, which ? 1.0 : 0.0));
            else
                CHECK(sinter_ctx_set_threads(g_ctx, which ? threads : 1));
            const double t = now();
            CHECK(sinter_stepper_step(st, m));
            pair[which] = now() - t;
            taken[which] = m;
            side[which] += pair[which];
            done[which] += m;
            k += m;
        }
        if (taken[0] == block && taken[1] == block) /* whole pairs only */
            ratios[nratio++] = pair[0] / pair[1];
    }
    qsort(ratios, nratio, sizeof(double), compare_doubles);
    const double median = nratio == 0  ? 0.0
                          : nratio % 2 ? ratios[nratio / 2]
                                       : 0.5 * (ratios[nratio / 2 - 1] + ratios[nratio / 2]);
    CHECK(sinter_ctx_set_threads(g_ctx, threads));
    printf("ALTERNATE %s%s block=%llu threads=%d one=%.6g s/%llu steps many=%.6g s/%llu steps "
           "speedup=%.4f pairs=%zu pair_median=%.4f pair_range=%.3f-%.3f\n",
           option != NULL ? "option=" : "", option != NULL ? option : "", block, threads, side[0],
           done[0], side[1], done[1], (side[0] / (double)done[0]) / (side[1] / (double)done[1]),
           nratio, median, nratio ? ratios[0] : 0.0, nratio ? ratios[nratio - 1] : 0.0);
    free(ratios);
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *xyz = NULL, *boxf = NULL;
    unsigned long long steps = 0;
    double dt = 0.0, rolling = 0.0;
    int heat = 0, stats = 0, threads = 1, rotation = 0, thread_choice = -1;
    unsigned long long shuffle = 0, sort_interval = 0, alternate = 0;
    const char *alternate_option = NULL;
    int reproducible = 0;
    for (int a = 1; a < argc; ++a) {
        const char *v = a + 1 < argc ? argv[a + 1] : NULL;
        if (strcmp(argv[a], "--stats") == 0) {
            stats = 1;
            continue;
        }
        if (v == NULL)
            usage();
        if (strcmp(argv[a], "--scene") == 0)
            scene = v;
        else if (strcmp(argv[a], "--xyz") == 0)
            xyz = v;
        else if (strcmp(argv[a], "--box") == 0)
            boxf = v;
        else if (strcmp(argv[a], "--steps") == 0)
            steps = strtoull(v, NULL, 10);
        else if (strcmp(argv[a], "--dt") == 0)
            dt = strtod(v, NULL);
        else if (strcmp(argv[a], "--heat") == 0)
            heat = atoi(v);
        else if (strcmp(argv[a], "--threads") == 0)
            threads = atoi(v);
        else if (strcmp(argv[a], "--shuffle") == 0)
            shuffle = strtoull(v, NULL, 10);
        else if (strcmp(argv[a], "--sort-interval") == 0)
            sort_interval = strtoull(v, NULL, 10);
        else if (strcmp(argv[a], "--rotation") == 0)
            rotation = atoi(v);
        else if (strcmp(argv[a], "--rolling") == 0)
            rolling = strtod(v, NULL);
        else if (strcmp(argv[a], "--reproducible") == 0)
            reproducible = atoi(v);
        else if (strcmp(argv[a], "--thread-choice") == 0)
            thread_choice = atoi(v);
        else if (strcmp(argv[a], "--alternate") == 0)
            alternate = strtoull(v, NULL, 10);
        else if (strcmp(argv[a], "--alternate-option") == 0)
            alternate_option = v;
        else
            usage();
        ++a;
    }
    if (scene == NULL || xyz == NULL || boxf == NULL || steps == 0 || !(dt > 0.0) ||
        (alternate > 0 && threads < 2 && alternate_option == NULL))
        usage();

    double box[6];
    const spheres read = read_spheres(xyz);
    double *pos = read.x, *rad = read.r;
    const size_t n = read.n;
    if (shuffle != 0) { /* Fisher-Yates with a 64-bit LCG */
        unsigned long long z = shuffle;
        for (size_t k = n; k > 1; --k) {
            z = z * 6364136223846793005ULL + 1442695040888963407ULL;
            const size_t j = (size_t)((z >> 11) % k);
            double t[4] = {pos[3 * (k - 1)], pos[3 * (k - 1) + 1], pos[3 * (k - 1) + 2],
                           rad[k - 1]};
            for (int d = 0; d < 3; ++d)
                pos[3 * (k - 1) + d] = pos[3 * j + d], pos[3 * j + d] = t[d];
            rad[k - 1] = rad[j], rad[j] = t[3];
        }
    }
    FILE *bf = fopen(boxf, "r");
    if (bf == NULL || fscanf(bf, "%lf %lf %lf %lf %lf %lf", &box[0], &box[1], &box[2], &box[3],
                             &box[4], &box[5]) != 6) {
        fprintf(stderr, "peer_bench: cannot read the box from %s\n", boxf);
        return 1;
    }
    fclose(bf);

    /* ---- canonical material (liggghts/in.mech: fix property/global m1..m4) ---------------- */
    CHECK(sinter_ctx_create(&g_ctx, NULL));
    /* 1 thread by default, like the peers' single serial rank; --threads N for scaling runs */
    CHECK(sinter_ctx_set_threads(g_ctx, threads));
    double xi;
    CHECK(sinter_damping_ratio_from_restitution(0.5, &xi)); /* e = 0.5 */
    sinter_material *mat;
    CHECK(sinter_material_create(&mat, g_ctx, "canonical"));
    CHECK(sinter_material_set(mat, SINTER_MAT_DENSITY, 2500.0));      /* rho, from the .lmp */
    CHECK(sinter_material_set(mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));  /* youngsModulus */
    CHECK(sinter_material_set(mat, SINTER_MAT_POISSON_RATIO, 0.3));   /* poissonsRatio */
    CHECK(sinter_material_set(mat, SINTER_MAT_DAMPING_RATIO, xi));    /* coefficientRestitution */
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_STATIC, 0.3)); /* coefficientFriction */
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DYNAMIC, 0.3));
    /* Tangential damping: the same ratio as the normal one. xi = sqrt(5/6)|beta(e)|, so the
     * library's d_t = 2 xi sqrt(8 G* m* sqrt(R* delta)) is LIGGGHTS' default gamma_t =
     * 2 sqrt(5/6) |beta| sqrt(S_t m*) (hertz tangential history, tangential damping on);
     * LAMMPS uses x_gamma_t = 1 on its Tsuji damping, Yade es = 0.5. */
    CHECK(sinter_material_set(mat, SINTER_MAT_FRICTION_DAMPING_RATIO, xi));
    CHECK(sinter_material_set(mat, SINTER_MAT_ROLLING_FRICTION, rolling)); /* none by default */
    CHECK(sinter_material_set(mat, SINTER_MAT_ROLLING_DAMPING_RATIO, rolling > 0.0 ? 0.3 : 0.0));
    CHECK(
        sinter_material_set(mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 100.0)); /* thermalConductivity */
    CHECK(sinter_material_set(mat, SINTER_MAT_HEAT_CAPACITY, 100.0));      /* thermalCapacity */
    sinter_material *adiabatic;                                            /* side walls */
    CHECK(sinter_material_clone(&adiabatic, mat));
    CHECK(sinter_material_set(adiabatic, SINTER_MAT_THERMAL_CONDUCTIVITY, 0.0));

    /* ---- particles: monodisperse r = 0.5 mm from the .xyz --------------------------------- */
    sinter_particles *ps;
    CHECK(sinter_particles_create(&ps, g_ctx));
    CHECK(sinter_particles_set_material(ps, 0, mat));
    CHECK(sinter_particles_add(ps, n, pos, rad, 0, 300.0, NULL));
    free(pos);
    free(rad);

    /* ---- five fixed walls, same material (fix wall/gran ... primitive type 1) ------------- */
    sinter_walls *walls;
    CHECK(sinter_walls_create(&walls, g_ctx));
    const double planes[5][6] = {
        {0, 0, box[4], 0, 0, 1},  /* zplane 0.0 (floor), normal +z */
        {box[0], 0, 0, 1, 0, 0},  /* xplane 0.0 */
        {box[1], 0, 0, -1, 0, 0}, /* xplane L */
        {0, box[2], 0, 0, 1, 0},  /* yplane 0.0 */
        {0, box[3], 0, 0, -1, 0}, /* yplane L */
    };
    for (int k = 0; k < 5; ++k)
        CHECK(sinter_walls_add_plane(walls, planes[k], planes[k] + 3, k == 0 ? mat : adiabatic,
                                     NULL));
    CHECK(sinter_walls_set_temperature(walls, 0, 500.0)); /* zplane 0.0 temperature 500 */

    /* ---- stepper: Hertz-Mindlin (pair_style gran model hertz tangential history) + gravity -- */
    sinter_stepper *st;
    sinter_force_model *hm, *grav;
    CHECK(sinter_stepper_create(&st, g_ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    CHECK(sinter_force_model_create(&hm, g_ctx, "hertz_mindlin"));
    CHECK(sinter_force_model_set(hm, "rolling", rolling > 0.0)); /* no rolling model by default */
    CHECK(sinter_force_model_create(&grav, g_ctx, "gravity"));
    CHECK(sinter_force_model_set(grav, "gz", -9.81)); /* fix gravity 9.81 vector 0 0 -1 */
    /* gravity first: the integrator then writes m g where it zeroes the force (no pass of
     * its own; the force sums start from m g instead of ending with it) */
    CHECK(sinter_stepper_add_force(st, grav));
    CHECK(sinter_stepper_add_force(st, hm));
    CHECK(sinter_stepper_set_dt(st, dt));     /* timestep ${dt} */
    CHECK(sinter_stepper_set_skin(st, 1e-4)); /* neighbor 1.0e-4 bin, check every step */
    if (sort_interval > 0)
        CHECK(sinter_stepper_set_option(st, "sort_interval", (double)sort_interval));
    CHECK(sinter_stepper_set_option(st, "rotation", (double)rotation));
    CHECK(sinter_stepper_set_option(st, "thread_choice", (double)thread_choice));
    CHECK(sinter_stepper_set_option(st, "reproducible", (double)reproducible));
    sinter_heat_model *cond = NULL;
    if (heat) {
        /* fix heat/gran/conduction ... contact_area projection */
        CHECK(sinter_heat_model_create(&cond, g_ctx, "conduction"));
        CHECK(sinter_heat_model_set(cond, "area", 1.0));
        CHECK(sinter_stepper_add_heat(st, cond));
    }

    /* Setup force evaluation outside the timing, like LAMMPS/LIGGGHTS' setup before "Loop
     * time": step(0) runs the stepper's prepare() (neighbour build, forces, history commit). */
    CHECK(sinter_stepper_step(st, 0));
    sinter_stepper_stats s0 = {.struct_size = sizeof(sinter_stepper_stats)}, s1 = s0;
    CHECK(sinter_stepper_get_stats(st, &s0));
    const double t0 = now();
    if (alternate > 0)
        alternate_threads(st, steps, alternate, threads, alternate_option);
    else
        CHECK(sinter_stepper_step(st, steps)); /* the timed stepping loop */
    const double loop = now() - t0;
    CHECK(sinter_stepper_get_stats(st, &s1));
    printf("Loop time of %.6g on 1 procs for %llu steps with %zu atoms\n", loop, steps, n);

    /* ---- sanity values, as the LIGGGHTS deck computes them -------------------------------- */
    const double *x, *v, *w, *m, *j, *r;
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_VELOCITY, (const void **)&v, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_SPIN, (const void **)&w, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_MASS, (const void **)&m, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_INERTIA, (const void **)&j, NULL, NULL));
    CHECK(sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&r, NULL, NULL));
    double zmax = -1e300, mz = 0, mtot = 0, ket = 0, ker = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *vi = v + 3 * i, *wi = w + 3 * i;
        if (x[3 * i + 2] + r[i] > zmax)
            zmax = x[3 * i + 2] + r[i]; /* bound(all,zmax) + 0.5e-3 */
        mz += m[i] * x[3 * i + 2];      /* xcm(all,z) */
        mtot += m[i];
        ket += 0.5 * m[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]); /* compute ke */
        ker += 0.5 * j[i] * (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]); /* erotate/sphere */
    }
    /* compute contact/atom summed over atoms / N = 2 * (sphere-sphere contacts) / N. */
    printf("SANITY zmax_top=%.10g zmean=%.10g KEtrans=%.10g KErot=%.10g Zcontacts=%.10g\n", zmax,
           mz / mtot, ket, ker, 2.0 * (double)s1.contacts / (double)n);
    /* z[1], z[2] of LAMMPS = particles 0 and 1 (same order as the .lmp). */
    printf("PROBE z1=%.17g z2=%.17g\n", x[2], n > 1 ? x[5] : x[2]);
    if (heat) {
        /* as the LIGGGHTS deck: Tbot over particles with z < 1 mm */
        const double *temp;
        CHECK(sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, (const void **)&temp, NULL,
                                         NULL));
        double tsum = 0, tmax = 0, tbot = 0;
        size_t nbot = 0;
        for (size_t i = 0; i < n; ++i) {
            tsum += temp[i];
            tmax = temp[i] > tmax ? temp[i] : tmax;
            if (x[3 * i + 2] < 1e-3) {
                tbot += temp[i];
                ++nbot;
            }
        }
        printf("THERMAL Tmean=%.10g Tbot=%.10g Tmax=%.10g\n", tsum / (double)n,
               nbot ? tbot / (double)nbot : 0.0, tmax);
        CHECK(sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE));
    }
    const sinter_field fields[] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY,
                                   SINTER_FIELD_SPIN,     SINTER_FIELD_MASS,
                                   SINTER_FIELD_INERTIA,  SINTER_FIELD_RADIUS};
    for (size_t k = 0; k < sizeof(fields) / sizeof(fields[0]); ++k)
        CHECK(sinter_particles_release(ps, fields[k]));

    if (stats) {
        /* Peak resident memory of the whole process (Linux), for the memory figures. */
        FILE *status = fopen("/proc/self/status", "r");
        char line[256];
        while (status != NULL && fgets(line, sizeof(line), status) != NULL)
            if (strncmp(line, "VmHWM:", 6) == 0)
                fprintf(stderr, "STATS peak_rss %s", line + 6);
        if (status != NULL)
            fclose(status);
        /* Phase times of the timed loop only (the setup evaluation is subtracted). */
        const double nb = s1.seconds_neighbor - s0.seconds_neighbor,
                     fo = s1.seconds_force - s0.seconds_force,
                     in = s1.seconds_integrate - s0.seconds_integrate,
                     tot = s1.seconds_total - s0.seconds_total, other = tot - nb - fo - in;
        fprintf(stderr,
                "STATS scene=%s N=%zu steps=%llu loop=%.4f s stepper_total=%.4f s "
                "neighbor_builds=%llu contacts=%llu wall_contacts=%llu\n"
                "STATS neighbor %.4f s (%.1f%%)  force %.4f s (%.1f%%)  integrate %.4f s "
                "(%.1f%%)  other %.4f s (%.1f%%)\n",
                scene, n, steps, loop, tot,
                (unsigned long long)(s1.neighbor_builds - s0.neighbor_builds),
                (unsigned long long)s1.contacts, (unsigned long long)s1.wall_contacts, nb,
                100 * nb / tot, fo, 100 * fo / tot, in, 100 * in / tot, other, 100 * other / tot);
    }

    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(cond);
    sinter_material_destroy(adiabatic);
    sinter_force_model_destroy(hm);
    sinter_force_model_destroy(grav);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(g_ctx);
    return 0;
}
