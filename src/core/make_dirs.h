/*
 * Create a directory and any missing parents (like mkdir -p): shared by the scene runner
 * (io/scene_run.c) and the MPI command-line runner (cli/run_mpi.c, which sees only the shared
 * library's public API), hence header-only.
 */
#ifndef SINTER_CORE_MAKE_DIRS_H
#define SINTER_CORE_MAKE_DIRS_H

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

/* Returns 0 when `path` exists or was made; -1 when it is empty or longer than `size` - 1;
 * 1 when a mkdir failed: then `partial` holds the directory that could not be made and errno
 * says why. `partial` is scratch of `size` bytes. */
static inline int sinter_make_dirs(const char *path, char *partial, size_t size)
{
    const size_t len = strlen(path);
    if (len == 0 || len >= size)
        return -1;
    memcpy(partial, path, len + 1);
    for (size_t k = 1; k <= len; ++k) {
        if (partial[k] != '/' && partial[k] != '\0')
            continue;
        const char keep = partial[k];
        partial[k] = '\0';
        if (mkdir(partial, 0777) != 0 && errno != EEXIST)
            return 1;
        partial[k] = keep;
    }
    return 0;
}

#endif
