#define _POSIX_C_SOURCE 200809L
/*
 * libFuzzer harness of the scene-file reader: the input is written to a file
 * and loaded with sinter_scene_load. Whatever the bytes, the reader must
 * return a status (with a message), never crash, leak or hit undefined
 * behaviour. A scene that loads and is small is also stepped a few times and
 * its checkpoint written and read back (a checkpoint the library wrote must
 * always be readable).
 *
 * The directory holds "small.xyz" (4 spheres), so that "method = file" with
 * "file = small.xyz" reads something. Build and run: tests/fuzz/run.sh.
 */
#include "fuzz_support.h"

static char scene_path[128], checkpoint_path[128];

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *dir = fuzz_dir();
    snprintf(scene_path, sizeof(scene_path), "%s/in.scene", dir);
    snprintf(checkpoint_path, sizeof(checkpoint_path), "%s/out.ckpt", dir);
    char xyz[128];
    snprintf(xyz, sizeof(xyz), "%s/small.xyz", dir);
    static const char SMALL[] = "# x y z r [m]\n"
                                "0.001 0.001 0.001 0.0005\n"
                                "0.002 0.001 0.001 0.0005\n"
                                "0.001 0.002 0.0011 0.0005\n"
                                "0.002 0.002 0.002 0.0005\n";
    fuzz_write_file(xyz, (const uint8_t *)SMALL, sizeof(SMALL) - 1);
    return 0;
}

static void exercise(sinter_ctx *ctx, sinter_scene *scene)
{
    sinter_particles *ps = NULL;
    sinter_stepper *st = NULL;
    size_t n = 0;
    if (sinter_scene_get_particles(scene, &ps) != SINTER_OK ||
        sinter_scene_get_stepper(scene, &st) != SINTER_OK ||
        sinter_particles_count(ps, &n) != SINTER_OK)
        abort();
    if (n > 200)
        return;
    sinter_status s = sinter_stepper_step(st, 3);
    fuzz_check_error(ctx, s, "sinter_stepper_step");
    if (s != SINTER_OK)
        return;
    s = sinter_checkpoint_write(st, checkpoint_path);
    fuzz_check_error(ctx, s, "sinter_checkpoint_write");
    if (s == SINTER_OK && sinter_checkpoint_read(st, checkpoint_path) != SINTER_OK) {
        fprintf(stderr, "fuzz: a checkpoint just written is refused: %s\n", sinter_last_error(ctx));
        abort();
    }
    remove(checkpoint_path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 64 * 1024)
        return 0; /* scene files are small; keep the search there */
    fuzz_write_file(scene_path, data, size);
    fuzz_budget budget;
    sinter_ctx *ctx = fuzz_ctx(&budget);
    sinter_scene *scene = NULL;
    const sinter_status s = sinter_scene_load(&scene, ctx, scene_path);
    fuzz_check_error(ctx, s, "sinter_scene_load");
    if (s == SINTER_OK) {
        exercise(ctx, scene);
        sinter_scene_destroy(scene);
    } else if (scene != NULL) {
        fprintf(stderr, "fuzz: sinter_scene_load failed but set *out\n");
        abort();
    }
    fuzz_ctx_done(ctx, &budget);
    return 0;
}
