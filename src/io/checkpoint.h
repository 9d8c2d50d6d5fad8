/* Checkpoints with a host section: the scene runner stores its program beside the stepper. */
#ifndef SINTER_IO_CHECKPOINT_H
#define SINTER_IO_CHECKPOINT_H

#include "sinter.h"

/* What the stepper part of a checkpoint holds, shown to the host's check. */
typedef struct sinter_checkpoint_facts {
    double time; /* [s] */
    double dt;   /* the step it proposes next [s] */
    size_t particles;
    size_t walls;
    unsigned version; /* format version */
} sinter_checkpoint_facts;

/*
 * The host's check of its section (`data`, `bytes`; NULL and 0 when the file has none), called
 * when the whole file has been verified and before anything changes: a status other than
 * SINTER_OK (with its message set) refuses the file and nothing is changed. `data` is valid
 * only during the call.
 */
typedef sinter_status (*sinter_checkpoint_host_fn)(void *user, const void *data, size_t bytes,
                                                   const sinter_checkpoint_facts *facts);

/* sinter_checkpoint_write with `host_bytes` bytes of the host's own after the stepper's state. */
sinter_status sinter_checkpoint_write_with(const sinter_stepper *st, const char *path,
                                           const void *host, size_t host_bytes);

/* sinter_checkpoint_read that hands the host's section to `host_check` (may be NULL). */
sinter_status sinter_checkpoint_read_with(sinter_stepper *st, const char *path,
                                          sinter_checkpoint_host_fn host_check, void *user);

#endif
