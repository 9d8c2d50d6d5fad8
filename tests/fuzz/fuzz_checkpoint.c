#define _POSIX_C_SOURCE 200809L
/*
 * libFuzzer harness of the checkpoint reader. Every input is read into a
 * fresh small stepper (3 spheres, a floor and a side wall, Hertz-Mindlin and
 * gravity) with sinter_checkpoint_read:
 *  - as it is (the checksum guards the file), and
 *  - when it starts with the magic, again with its checksum recomputed, so
 *    that mutations reach the section parser instead of dying at the checksum.
 * A refused file must leave the stepper exactly as it was; an accepted one must
 * step, be written again and read back.
 *
 * SINTER_FUZZ_MAKE_CORPUS=DIR writes the seed corpus (valid checkpoints of the
 * fixture at a few times, and truncations) into DIR and exits; run.sh
 * documents the command.
 */
#include "fuzz_support.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct fixture {
    fuzz_budget budget;
    sinter_ctx *ctx;
    sinter_material *mat;
    sinter_particles *ps;
    sinter_walls *walls;
    sinter_force_model *contact, *gravity;
    sinter_stepper *st;
} fixture;

static char in_path[128], out_path[128];

#define CHECK(call)                                                                                \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            fprintf(stderr, "fuzz fixture: %s failed: %s\n", #call, sinter_last_error(f->ctx));    \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

static void fixture_open(fixture *f, uint64_t steps)
{
    memset(f, 0, sizeof(*f));
    f->ctx = fuzz_ctx(&f->budget);
    CHECK(sinter_material_create(&f->mat, f->ctx, "glass"));
    CHECK(sinter_material_set(f->mat, SINTER_MAT_YOUNGS_MODULUS, 1e7));
    CHECK(sinter_material_set(f->mat, SINTER_MAT_DAMPING_RATIO, 0.2));
    CHECK(sinter_particles_create(&f->ps, f->ctx));
    CHECK(sinter_particles_set_material(f->ps, 0, f->mat));
    const double x[9] = {0.0, 0.0, 0.00099, 0.0, 0.0, 0.00298, 0.00099, 0.003, 0.00099};
    const double r[3] = {0.001, 0.001, 0.001};
    CHECK(sinter_particles_add(f->ps, 3, x, r, 0, 300.0, NULL));
    CHECK(sinter_walls_create(&f->walls, f->ctx));
    const double p0[3] = {0, 0, 0}, n0[3] = {0, 0, 1}, p1[3] = {0, 0, 0}, n1[3] = {1, 0, 0};
    CHECK(sinter_walls_add_plane(f->walls, p0, n0, f->mat, NULL));
    CHECK(sinter_walls_add_plane(f->walls, p1, n1, f->mat, NULL));
    CHECK(sinter_force_model_create(&f->contact, f->ctx, "hertz_mindlin"));
    CHECK(sinter_force_model_create(&f->gravity, f->ctx, "gravity"));
    CHECK(sinter_stepper_create(&f->st, f->ctx, SINTER_STEPPER_EXPLICIT, f->ps, f->walls));
    CHECK(sinter_stepper_add_force(f->st, f->contact));
    CHECK(sinter_stepper_add_force(f->st, f->gravity));
    CHECK(sinter_stepper_set_dt(f->st, 1e-6));
    CHECK(sinter_stepper_step(f->st, steps));
}

static void fixture_close(fixture *f)
{
    sinter_stepper_destroy(f->st);
    sinter_force_model_destroy(f->contact);
    sinter_force_model_destroy(f->gravity);
    sinter_walls_destroy(f->walls);
    sinter_particles_destroy(f->ps);
    sinter_material_destroy(f->mat);
    fuzz_ctx_done(f->ctx, &f->budget);
}

/* FNV-1a over the stepper's visible state: time, count, every double field, walls. */
static uint64_t fingerprint(fixture *f)
{
    uint64_t h = 0xcbf29ce484222325ull;
#define MIX(ptr, bytes)                                                                            \
    do {                                                                                           \
        const unsigned char *p_ = (const unsigned char *)(ptr);                                    \
        for (size_t k_ = 0; k_ < (bytes); ++k_)                                                    \
            h = (h ^ p_[k_]) * 0x100000001b3ull;                                                   \
    } while (0)
    double t = 0;
    size_t n = 0;
    CHECK(sinter_stepper_time(f->st, &t));
    CHECK(sinter_particles_count(f->ps, &n));
    MIX(&t, sizeof(t));
    MIX(&n, sizeof(n));
    for (int field = 0; field <= (int)SINTER_FIELD_HEAT; ++field) {
        const double *a = NULL;
        size_t comps = 0;
        CHECK(sinter_particles_view_read(f->ps, (sinter_field)field, (const void **)&a, NULL,
                                         &comps));
        MIX(a, n * comps * sizeof(double));
        CHECK(sinter_particles_release(f->ps, (sinter_field)field));
    }
    for (size_t k = 0; k < 2; ++k) {
        double p[3], u[3], force[3];
        CHECK(sinter_walls_get_state(f->walls, k, p, u));
        CHECK(sinter_walls_get_force(f->walls, k, force));
        MIX(p, sizeof(p));
        MIX(u, sizeof(u));
        MIX(force, sizeof(force));
    }
#undef MIX
    return h;
}

static void read_one(const uint8_t *data, size_t size)
{
    fixture fx, *f = &fx;
    fixture_open(f, 5);
    const uint64_t before = fingerprint(f);
    fuzz_write_file(in_path, data, size);
    sinter_status s = sinter_checkpoint_read(f->st, in_path);
    fuzz_check_error(f->ctx, s, "sinter_checkpoint_read");
    if (s != SINTER_OK) {
        if (fingerprint(f) != before) {
            fprintf(stderr, "fuzz: a refused checkpoint changed the stepper (%s)\n",
                    sinter_last_error(f->ctx));
            abort();
        }
    } else {
        s = sinter_stepper_step(f->st, 3);
        fuzz_check_error(f->ctx, s, "sinter_stepper_step");
        if (s == SINTER_OK) {
            s = sinter_checkpoint_write(f->st, out_path);
            fuzz_check_error(f->ctx, s, "sinter_checkpoint_write");
            if (s == SINTER_OK && sinter_checkpoint_read(f->st, out_path) != SINTER_OK) {
                fprintf(stderr, "fuzz: a checkpoint just written is refused: %s\n",
                        sinter_last_error(f->ctx));
                abort();
            }
        }
    }
    fixture_close(f);
}

static const char MAGIC[8] = {'S', 'I', 'N', 'T', 'E', 'R', 'C', 'K'};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 64 * 1024)
        return 0;
    read_one(data, size);
    if (size >= 24 && memcmp(data, MAGIC, sizeof(MAGIC)) == 0) {
        uint8_t *fixed = malloc(size);
        if (fixed == NULL)
            abort();
        memcpy(fixed, data, size);
        uint64_t h = 0xcbf29ce484222325ull;
        for (size_t k = 0; k < size - 8; ++k)
            h = (h ^ fixed[k]) * 0x100000001b3ull;
        if (memcmp(fixed + size - 8, &h, 8) != 0) {
            memcpy(fixed + size - 8, &h, 8);
            read_one(fixed, size);
        }
        free(fixed);
    }
    return 0;
}

/* Seed corpus: valid checkpoints after 0, 5 and 400 steps, and truncations of one. */
static void make_corpus(const char *dir)
{
    static const uint64_t steps[] = {0, 5, 400};
    char path[512];
    for (size_t k = 0; k < sizeof(steps) / sizeof(steps[0]); ++k) {
        fixture fx, *f = &fx;
        fixture_open(f, steps[k]);
        snprintf(path, sizeof(path), "%s/valid_step%llu.ckpt", dir, (unsigned long long)steps[k]);
        CHECK(sinter_checkpoint_write(f->st, path));
        fixture_close(f);
    }
    snprintf(path, sizeof(path), "%s/valid_step400.ckpt", dir);
    FILE *in = fopen(path, "rb");
    if (in == NULL)
        abort();
    static uint8_t buf[1 << 16];
    const size_t size = fread(buf, 1, sizeof(buf), in);
    fclose(in);
    const size_t cuts[] = {0, 8, 23, 24, 100, size / 2, size - 9, size - 8, size - 1};
    for (size_t k = 0; k < sizeof(cuts) / sizeof(cuts[0]); ++k) {
        snprintf(path, sizeof(path), "%s/truncated_%zu.ckpt", dir, cuts[k]);
        fuzz_write_file(path, buf, cuts[k]);
    }
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *dir = fuzz_dir();
    snprintf(in_path, sizeof(in_path), "%s/in.ckpt", dir);
    snprintf(out_path, sizeof(out_path), "%s/out.ckpt", dir);
    const char *corpus = getenv("SINTER_FUZZ_MAKE_CORPUS");
    if (corpus != NULL) {
        make_corpus(corpus);
        exit(0);
    }
    return 0;
}
