/*
 * Portable checkpoints through MPI-IO (issue 44), under mpiexec:
 *  - written on every rank, each holding a share of a settled cloud (64 Hertz-Mindlin spheres
 *    with rolling resistance in a box: springs between particles and with the walls), read
 *    back on 2 ranks (a recursive bisection) and on 1 rank: the union of the particles, sorted
 *    by id, equals what was written bit for bit, every field and every contact history entry;
 *    each reader holds exactly the particles whose centres lie in its part;
 *  - on one rank, a run that writes at step 2500 and restarts from the file continues bit for
 *    bit with the uninterrupted run (500 more steps: every field of every particle, the time).
 *    The run sorts its particles every 500 steps (option sort_interval), so that the uninterrupted
 *    run, too, builds its neighbour lists afresh at step 2501, in the order the restart has;
 *    at another step the restart continues as the run reordered would (its lists are new);
 *  - a damaged file (a byte of the last piece flipped, a byte of the header's table, the file
 *    cut short), a foreign file and a missing one are refused on every rank with the same
 *    status, and the stepper is unchanged: no particle, time 0 (a stepper of other force
 *    models, a decomposition of another number of parts, and a set without the records'
 *    material on the last rank only, found after the others imported their pieces, as well);
 *    the sound file then reads.
 * The record streams are compared in a canonical form: each record's fixed part, and the set of
 * its history entries, sorted (a stepper lists them in the order it found them, which differs
 * between a built pair list and one staged by an import) and byte-identical copies counted once
 * (an import stages a contact between two arriving particles from both their records, and an
 * export before the next step lists both copies). The stream's layout is the one documented
 * in src/stepper/migrate.c (format 3; its layout is format 2's).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_check.h"

#include "sinter_mpi.h"

#define OK(call) CHECK((call) == SINTER_OK)

enum { CLOUD = 64 };

static int rank, size;
static const double LO[3] = {-1.1e-3, -1.1e-3, -1.1e-3}, HI[3] = {7.3e-3, 7.3e-3, 9e-3};

typedef struct scene {
    sinter_ctx *ctx;
    sinter_material *mat, *wall_mat;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_stepper *st;
    sinter_force_model *contact, *gravity;
} scene;

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* The cloud of tests/unit/test_migrate.c: Hertz-Mindlin with rolling resistance, gravity (or
 * none), a floor and four side walls of a box of 8.2 mm; the particles' material 0 registered
 * (or not: a set that cannot take the records). */
static void scene_open_as(scene *s, int gravity, int material)
{
    memset(s, 0, sizeof *s);
    OK(sinter_ctx_create(&s->ctx, NULL));
    OK(sinter_material_create(&s->mat, s->ctx, "particles"));
    const sinter_material_param prop[6] = {SINTER_MAT_YOUNGS_MODULUS,  SINTER_MAT_POISSON_RATIO,
                                           SINTER_MAT_DENSITY,         SINTER_MAT_DAMPING_RATIO,
                                           SINTER_MAT_FRICTION_STATIC, SINTER_MAT_FRICTION_DYNAMIC};
    const double value[6] = {1e6, 0.3, 2500, 0.3, 0.4, 0.4};
    for (int k = 0; k < 6; ++k)
        OK(sinter_material_set(s->mat, prop[k], value[k]));
    OK(sinter_material_set(s->mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_clone(&s->wall_mat, s->mat));
    OK(sinter_particles_create(&s->ps, s->ctx));
    if (material)
        OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_walls_create(&s->walls, s->ctx));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_EXPLICIT, s->ps, s->walls));
    OK(sinter_stepper_set_option(s->st, "thread_choice", 0));
    OK(sinter_force_model_create(&s->contact, s->ctx, "hertz_mindlin"));
    OK(sinter_stepper_add_force(s->st, s->contact));
    OK(sinter_force_model_set(s->contact, "rolling", 1.0));
    if (gravity) {
        OK(sinter_force_model_create(&s->gravity, s->ctx, "gravity"));
        OK(sinter_stepper_add_force(s->st, s->gravity));
    }
    OK(sinter_stepper_set_dt(s->st, 2e-5));
    const double floor_p[3] = {0, 0, -0.001}, floor_n[3] = {0, 0, 1};
    OK(sinter_walls_add_plane(s->walls, floor_p, floor_n, s->wall_mat, NULL));
    for (int d = 0; d < 2; ++d)
        for (int side = 0; side < 2; ++side) {
            double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
            p[d] = side ? 7.2e-3 : -1.05e-3;
            n[d] = side ? -1.0 : 1.0;
            OK(sinter_walls_add_plane(s->walls, p, n, s->wall_mat, NULL));
        }
}

static void scene_open(scene *s, int gravity)
{
    scene_open_as(s, gravity, 1);
}

static void scene_close(scene *s)
{
    sinter_stepper_destroy(s->st);
    sinter_force_model_destroy(s->contact);
    sinter_force_model_destroy(s->gravity);
    sinter_walls_destroy(s->walls);
    sinter_particles_destroy(s->ps);
    sinter_material_destroy(s->mat);
    sinter_material_destroy(s->wall_mat);
    sinter_ctx_destroy(s->ctx);
}

/* A jittered 4 x 4 x 4 lattice with random velocities, settled for 2500 steps (50 ms). */
static void fill_and_settle(scene *s)
{
    uint64_t seed = 11;
    const double spacing = 2.05e-3;
    double x[3 * CLOUD], r[CLOUD];
    for (size_t k = 0; k < CLOUD; ++k) {
        x[3 * k] = spacing * (double)(k % 4);
        x[3 * k + 1] = spacing * (double)((k / 4) % 4);
        x[3 * k + 2] = spacing * (double)(k / 16);
        r[k] = 1e-3 * (0.8 + 0.2 * lcg(&seed));
    }
    OK(sinter_particles_add(s->ps, CLOUD, x, r, 0, 300.0, NULL));
    double *v = NULL;
    OK(sinter_particles_view(s->ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
    for (size_t k = 0; v != NULL && k < 3 * CLOUD; ++k)
        v[k] = lcg(&seed) - 0.5;
    OK(sinter_particles_release(s->ps, SINTER_FIELD_VELOCITY));
    OK(sinter_stepper_step(s->st, 2500));
}

/* The record stream of every owned particle (malloc'd; *bytes). */
static unsigned char *export_all(scene *s, size_t *bytes, int remove)
{
    size_t n = 0, written = 0;
    OK(sinter_particles_owned_count(s->ps, &n));
    size_t *idx = malloc((n + 1) * sizeof *idx);
    for (size_t i = 0; idx != NULL && i < n; ++i)
        idx[i] = i;
    *bytes = 0;
    OK(sinter_stepper_export_size(s->st, n, idx, bytes));
    unsigned char *buf = malloc(*bytes + 1);
    CHECK(buf != NULL && idx != NULL);
    OK(sinter_stepper_export(s->st, n, idx, buf, *bytes, &written, remove));
    CHECK(written == *bytes);
    free(idx);
    return buf;
}

/* Keep this rank's share of the particles: the ids equal to its rank modulo the ranks (the
 * others exported with removal, so the kept ones hold their springs with them as well). */
static void keep_share(scene *s)
{
    const uint64_t *id = NULL;
    size_t others[CLOUD], m = 0, bytes = 0, written = 0, n = 0;
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_ID, (const void **)&id, &n, NULL));
    for (size_t i = 0; id != NULL && i < n && i < CLOUD; ++i)
        if (id[i] % (uint64_t)size != (uint64_t)rank)
            others[m++] = i;
    OK(sinter_particles_release(s->ps, SINTER_FIELD_ID));
    OK(sinter_stepper_export_size(s->st, m, others, &bytes));
    unsigned char *scratch = malloc(bytes + 1);
    CHECK(scratch != NULL);
    OK(sinter_stepper_export(s->st, m, others, scratch, bytes, &written, 1));
    free(scratch);
}

/* ---- the canonical form of record streams ---- */

typedef struct record {
    uint64_t id;
    unsigned char *blob; /* the fixed part, then per section its count and sorted entries */
    size_t bytes;
} record;

static size_t entry_bytes; /* qsort's comparator's width */

static int entry_order(const void *a, const void *b)
{
    return memcmp(a, b, entry_bytes);
}

static int record_order(const void *a, const void *b)
{
    const record *p = a, *q = b;
    return (p->id > q->id) - (p->id < q->id);
}

static uint64_t u64_at(const unsigned char *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}

/* Append the records of one stream to *recs (*n); *pp_entries counts particle-particle
 * history entries (each listed by each end it travels with). 0 when the stream is malformed. */
static int parse(const unsigned char *b, size_t bytes, record **recs, size_t *n, size_t *pp_entries)
{
    enum { FIXED = 8 + 8 * 37 + 4 + 4 + 8 + 8 };
    uint32_t version = 0;
    if (bytes < 48 || memcmp(b, "SINTERMG", 8) != 0)
        return 0;
    memcpy(&version, b + 8, 4);
    const uint64_t count = u64_at(b + 24), slots = u64_at(b + 32);
    if (version != 4 || u64_at(b + 16) != bytes || slots > 8)
        return 0;
    uint64_t width[17];
    for (uint64_t k = 0; k < slots; ++k) {
        width[2 * k] = u64_at(b + 40 + 80 * k + 64);
        width[2 * k + 1] = u64_at(b + 40 + 80 * k + 72);
    }
    const uint64_t link = u64_at(b + 40 + 80 * slots);
    size_t p = 48 + 80 * slots;
    record *grown = realloc(*recs, (*n + count) * sizeof(record));
    if (grown == NULL)
        return 0;
    *recs = grown;
    for (uint64_t r = 0; r < count; ++r) {
        record *rec = &(*recs)[(*n)++];
        rec->id = u64_at(b + p);
        rec->bytes = 0;
        rec->blob = malloc(bytes); /* more than it needs */
        if (rec->blob == NULL || p + FIXED > bytes)
            return 0;
        memcpy(rec->blob, b + p, FIXED);
        rec->bytes = FIXED;
        p += FIXED;
        for (uint64_t sec = 0; sec <= 2 * slots; ++sec) {
            const uint64_t c = u64_at(b + p);
            entry_bytes = sec == 2 * slots ? link : 16 + 8 * width[sec];
            p += 8;
            if (p + c * entry_bytes > bytes)
                return 0;
            unsigned char *list = rec->blob + rec->bytes + 8;
            memcpy(list, b + p, c * entry_bytes);
            qsort(list, c, entry_bytes, entry_order);
            uint64_t kept = 0; /* byte-identical copies of one entry count once */
            for (uint64_t e = 0; e < c; ++e)
                if (kept == 0 || memcmp(list + (kept - 1) * entry_bytes, list + e * entry_bytes,
                                        entry_bytes) != 0)
                    memmove(list + kept++ * entry_bytes, list + e * entry_bytes, entry_bytes);
            memcpy(rec->blob + rec->bytes, &kept, 8);
            rec->bytes += 8 + kept * entry_bytes;
            p += c * entry_bytes;
            if (sec == 0)
                *pp_entries += kept;
        }
        enum { QS_STATE = 88 }; /* format 4: the quasi-static state, after the links */
        if (p + QS_STATE > bytes)
            return 0;
        memcpy(rec->blob + rec->bytes, b + p, QS_STATE);
        rec->bytes += QS_STATE;
        p += QS_STATE;
    }
    return p + 8 == bytes;
}

static void records_free(record *recs, size_t n)
{
    for (size_t k = 0; k < n; ++k)
        free(recs[k].blob);
    free(recs);
}

/* The same particles with the same bits, by id. */
static int same_records(record *a, size_t na, record *b, size_t nb)
{
    if (na != nb)
        return 0;
    qsort(a, na, sizeof *a, record_order);
    qsort(b, nb, sizeof *b, record_order);
    for (size_t k = 0; k < na; ++k)
        if (a[k].id != b[k].id || a[k].bytes != b[k].bytes ||
            memcmp(a[k].blob, b[k].blob, a[k].bytes) != 0)
            return 0;
    return 1;
}

static void checkpoint_path(char *path, size_t cap, const char *dir, const char *what)
{
    snprintf(path, cap, "%s/mpi_checkpoint_%s_np%d.bin", dir, what, size);
}

/* ---- (a) written on every rank, read on 2 ranks and on 1 ---- */

static void test_read_on_fewer_ranks(const char *dir)
{
    char path[4096];
    checkpoint_path(path, sizeof path, dir, "spread");
    scene full;
    scene_open(&full, 1);
    fill_and_settle(&full);
    size_t ref_bytes = 0, ref_n = 0, pp = 0;
    unsigned char *ref = export_all(&full, &ref_bytes, 0);
    record *want = NULL;
    CHECK(parse(ref, ref_bytes, &want, &ref_n, &pp));
    free(ref);
    CHECK(ref_n == CLOUD);
    CHECK(pp >= 80); /* the springs the test is about: each listed by both ends */
    double x_all[3 * CLOUD], time = 0.0;
    const double *x = NULL;
    OK(sinter_particles_view_read(full.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    memcpy(x_all, x, sizeof x_all);
    OK(sinter_particles_release(full.ps, SINTER_FIELD_POSITION));
    OK(sinter_stepper_time(full.st, &time));
    keep_share(&full);
    size_t bytes = 0;
    OK(sinter_mpi_checkpoint_write(full.st, full.ps, MPI_COMM_WORLD, path));
    scene_close(&full);

    const int readers_of[2] = {size >= 2 ? 2 : 1, 1};
    for (int c = 0; c < (size >= 2 ? 2 : 1); ++c) {
        const int readers = readers_of[c];
        MPI_Comm comm = MPI_COMM_NULL;
        MPI_Comm_split(MPI_COMM_WORLD, rank < readers ? 0 : MPI_UNDEFINED, rank, &comm);
        if (comm == MPI_COMM_NULL)
            continue;
        scene r;
        scene_open(&r, 1);
        sinter_mpi_decomp *decomp = NULL;
        if (readers == 2)
            OK(sinter_mpi_decomp_rcb(&decomp, 2, LO, HI, x_all, NULL, CLOUD, NULL, NULL));
        else
            OK(sinter_mpi_decomp_brick(&decomp, 1, NULL, LO, HI));
        size_t count = 0;
        OK(sinter_mpi_checkpoint_read(r.st, r.ps, comm, path, decomp, &count));
        double t = -1.0;
        OK(sinter_stepper_time(r.st, &t));
        CHECK(memcmp(&t, &time, sizeof t) == 0);
        CHECK(readers == 1 ? count == CLOUD : count > 0 && count < CLOUD);
        /* every particle in this rank's part */
        int owner[CLOUD];
        OK(sinter_particles_view_read(r.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
        OK(sinter_mpi_decomp_owners(decomp, x, count, owner));
        OK(sinter_particles_release(r.ps, SINTER_FIELD_POSITION));
        for (size_t i = 0; i < count; ++i)
            CHECK(owner[i] == rank);
        /* the union on the first reader */
        unsigned char *mine = export_all(&r, &bytes, 0);
        int my_bytes = (int)bytes, all_bytes[2] = {0, 0}, at[2] = {0, 0};
        MPI_Gather(&my_bytes, 1, MPI_INT, all_bytes, 1, MPI_INT, 0, comm);
        at[1] = all_bytes[0];
        unsigned char *all = malloc((size_t)(all_bytes[0] + all_bytes[1]) + 1);
        MPI_Gatherv(mine, my_bytes, MPI_BYTE, all, all_bytes, at, MPI_BYTE, 0, comm);
        if (rank == 0) {
            record *got = NULL;
            size_t got_n = 0, got_pp = 0;
            for (int k = 0; k < readers; ++k)
                CHECK(parse(all + at[k], (size_t)all_bytes[k], &got, &got_n, &got_pp));
            const int same = same_records(got, got_n, want, ref_n) && got_pp == pp;
            CHECK(same);
            if (same)
                printf(
                    "written on %d ranks, read on %d: %zu particles, %zu history entries between "
                    "particles (by each end), the same bits\n",
                    size, readers, got_n, got_pp);
            records_free(got, got_n);
        }
        free(all);
        free(mine);
        sinter_mpi_decomp_destroy(decomp);
        scene_close(&r);
        MPI_Comm_free(&comm);
    }
    records_free(want, ref_n);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        remove(path);
}

/* ---- (b) one rank: a restart continues bit for bit ---- */

/* Every field of every particle in id order (x, v, w, rot, force, torque: 18; temperature,
 * heat). */
static void by_id(scene *s, double *out)
{
    const sinter_field vec[6] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,
                                 SINTER_FIELD_ROTATION, SINTER_FIELD_FORCE,    SINTER_FIELD_TORQUE};
    const sinter_field one[2] = {SINTER_FIELD_TEMPERATURE, SINTER_FIELD_HEAT};
    const uint64_t *id = NULL;
    size_t n = 0;
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_ID, (const void **)&id, &n, NULL));
    CHECK(n == CLOUD);
    for (int f = 0; f < 8; ++f) {
        const double *a = NULL;
        const sinter_field field = f < 6 ? vec[f] : one[f - 6];
        const size_t width = f < 6 ? 3 : 1, at = f < 6 ? 3 * (size_t)f : 12 + (size_t)f;
        OK(sinter_particles_view_read(s->ps, field, (const void **)&a, NULL, NULL));
        for (size_t i = 0; a != NULL && i < n && i < CLOUD; ++i)
            memcpy(out + 20 * (id[i] % CLOUD) + at, a + width * i, width * sizeof(double));
        OK(sinter_particles_release(s->ps, field));
    }
    OK(sinter_particles_release(s->ps, SINTER_FIELD_ID));
}

static void test_restart_continues(const char *dir)
{
    char path[4096];
    checkpoint_path(path, sizeof path, dir, "restart");
    scene a, b;
    scene_open(&a, 1);
    scene_open(&b, 1);
    OK(sinter_stepper_set_option(a.st, "sort_interval", 500));
    OK(sinter_stepper_set_option(b.st, "sort_interval", 500));
    fill_and_settle(&a);
    OK(sinter_mpi_checkpoint_write(a.st, a.ps, MPI_COMM_WORLD, path));
    sinter_mpi_decomp *decomp = NULL;
    OK(sinter_mpi_decomp_brick(&decomp, 1, NULL, LO, HI));
    size_t count = 0;
    OK(sinter_mpi_checkpoint_read(b.st, b.ps, MPI_COMM_WORLD, path, decomp, &count));
    CHECK(count == CLOUD);
    OK(sinter_stepper_step(a.st, 500));
    OK(sinter_stepper_step(b.st, 500));
    static double want[20 * CLOUD], got[20 * CLOUD];
    by_id(&a, want);
    by_id(&b, got);
    double ta = 0.0, tb = 1.0;
    OK(sinter_stepper_time(a.st, &ta));
    OK(sinter_stepper_time(b.st, &tb));
    const int same = memcmp(got, want, sizeof got) == 0 && memcmp(&ta, &tb, sizeof ta) == 0;
    CHECK(same);
    if (same)
        printf("restart at step 2500 on one rank: 500 steps later the same bits as the run without "
               "it (t = %.6f s)\n",
               tb);
    sinter_mpi_decomp_destroy(decomp);
    scene_close(&a);
    scene_close(&b);
    remove(path);
}

/* ---- (c) damaged and foreign files ---- */

/* Rank 0 changes the file (flip: XOR 1 into the byte at `at` from the end (at > 0) or from the
 * start (at <= 0); cut: drop the last bytes), the others wait. */
static void damage(const char *path, long at, long cut)
{
    if (rank == 0) {
        FILE *f = fopen(path, "r+b");
        CHECK(f != NULL);
        if (f != NULL) {
            fseek(f, 0, SEEK_END);
            const long end = ftell(f);
            const long where = at > 0 ? end - at : -at;
            if (cut == 0) {
                fseek(f, where, SEEK_SET);
                const int c = fgetc(f);
                fseek(f, where, SEEK_SET);
                fputc(c ^ 1, f);
                fclose(f);
            } else {
                unsigned char *buf = malloc((size_t)end);
                fseek(f, 0, SEEK_SET);
                CHECK(buf != NULL && fread(buf, 1, (size_t)end, f) == (size_t)end);
                fclose(f);
                f = fopen(path, "wb");
                CHECK(f != NULL && fwrite(buf, 1, (size_t)(end - cut), f) == (size_t)(end - cut));
                fclose(f);
                free(buf);
            }
        }
    }
    MPI_Barrier(MPI_COMM_WORLD);
}

/* A read that must be refused with `want` on every rank, the stepper unchanged. */
static void refused(scene *r, const char *path, const sinter_mpi_decomp *decomp, sinter_status want,
                    const char *what)
{
    const sinter_status got =
        sinter_mpi_checkpoint_read(r->st, r->ps, MPI_COMM_WORLD, path, decomp, NULL);
    CHECK(got == want);
    CHECK(same_on_every_rank(&got, sizeof got));
    size_t n = 1;
    double t = 1.0;
    OK(sinter_particles_count(r->ps, &n));
    OK(sinter_stepper_time(r->st, &t));
    CHECK(n == 0 && t == 0.0);
    if (rank == 0)
        printf("%s: refused on every rank (%s)\n", what, sinter_status_string(got));
}

static void test_damaged_files_refused(const char *dir)
{
    char path[4096], foreign[4096];
    checkpoint_path(path, sizeof path, dir, "damaged");
    checkpoint_path(foreign, sizeof foreign, dir, "foreign");
    scene w;
    scene_open(&w, 1);
    fill_and_settle(&w);
    keep_share(&w);
    /* argument errors: a NULL stepper on one rank is every rank's error */
    const sinter_status no_stepper =
        sinter_mpi_checkpoint_write(rank == size - 1 ? NULL : w.st, w.ps, MPI_COMM_WORLD, path);
    CHECK(no_stepper == SINTER_ERR_NULL);
    CHECK(sinter_mpi_checkpoint_write(w.st, w.ps, MPI_COMM_NULL, path) == SINTER_ERR_NULL);
    CHECK(sinter_mpi_checkpoint_read(w.st, w.ps, MPI_COMM_WORLD, NULL, NULL, NULL) ==
          SINTER_ERR_NULL);
    OK(sinter_mpi_checkpoint_write(w.st, w.ps, MPI_COMM_WORLD, path));
    scene_close(&w);
    scene r, other;
    scene_open(&r, 1);
    scene_open(&other, 0);
    sinter_mpi_decomp *decomp = NULL;
    OK(sinter_mpi_decomp_brick(&decomp, size, NULL, LO, HI));
    damage(path, 100, 0); /* in the last piece, read by the last rank only */
    refused(&r, path, decomp, SINTER_ERR_CORRUPT, "a byte of the last piece flipped");
    damage(path, 100, 0);
    damage(path, -(64 + 8), 0); /* the first piece's size in the table */
    refused(&r, path, decomp, SINTER_ERR_CORRUPT, "a byte of the header's table flipped");
    damage(path, -(64 + 8), 0);
    refused(&other, path, decomp, SINTER_ERR_INVALID, "a stepper of other force models");
    sinter_mpi_decomp *wrong = NULL; /* one part more than there are ranks */
    OK(sinter_mpi_decomp_brick(&wrong, size + 1, NULL, LO, HI));
    refused(&r, path, wrong, SINTER_ERR_INVALID, "a decomposition of another number of parts");
    sinter_mpi_decomp_destroy(wrong);
    /* the last rank's set lacks the material: its import is refused after every rank loaded
     * the global part (and the others imported their pieces), so every rank takes its
     * particles out again and puts its own global part back */
    scene lacking;
    scene_open_as(&lacking, 1, 0);
    refused(rank == size - 1 ? &lacking : &r, path, decomp, SINTER_ERR_INVALID,
            "a set without the records' material on the last rank");
    scene_close(&lacking);
    if (rank == 0) {
        FILE *f = fopen(foreign, "wb");
        CHECK(f != NULL);
        for (int k = 0; f != NULL && k < 64; ++k)
            fputs("not a checkpoint\n", f);
        if (f != NULL)
            fclose(f);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    refused(&r, foreign, decomp, SINTER_ERR_CORRUPT, "a foreign file");
    refused(&r, "/nonexistent/mpi_checkpoint.bin", decomp, SINTER_ERR_IO, "a missing file");
    /* the sound file reads: the refusals came from the damage */
    size_t count = 0, total = 0;
    OK(sinter_mpi_checkpoint_read(r.st, r.ps, MPI_COMM_WORLD, path, decomp, &count));
    MPI_Allreduce(&count, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    CHECK(total == CLOUD);
    damage(path, 0, 8); /* cut short */
    scene fresh;
    scene_open(&fresh, 1);
    refused(&fresh, path, decomp, SINTER_ERR_CORRUPT, "the file cut short by 8 bytes");
    scene_close(&fresh);
    sinter_mpi_decomp_destroy(decomp);
    scene_close(&r);
    scene_close(&other);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        remove(path);
        remove(foreign);
    }
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const char *dir = argc > 1 ? argv[1] : ".";
    test_read_on_fewer_ranks(dir);
    if (size == 1)
        test_restart_continues(dir);
    test_damaged_files_refused(dir);
    const int rc = mpi_check_finish("test_mpi_checkpoint");
    MPI_Finalize();
    return rc;
}
