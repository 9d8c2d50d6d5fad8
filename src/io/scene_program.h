/*
 * Where a scene's run stands (io/scene_run.c): its phase (pouring or the main run), the time
 * origins the set-up fixed (the pour's start and end, the run's end), the output schedule and
 * what was written. It travels in the scene's checkpoints (io/scene_program.c) beside the
 * stepper's state, so that a restart continues the program instead of repeating its set-up.
 */
#ifndef SINTER_IO_SCENE_PROGRAM_H
#define SINTER_IO_SCENE_PROGRAM_H

#include <stdint.h>

#include "core/core.h"

enum {
    SCENE_PHASE_NONE = 0, /* not started: the set-up (compaction, the first sample) is to come */
    SCENE_PHASE_POUR = 1, /* pouring to rest, every wall held */
    SCENE_PHASE_MAIN = 2  /* the run to origin + the scene's end time */
};

typedef struct scene_program {
    int phase;
    double pour_start;      /* [s] */
    double origin;          /* the time origin of the wall motions, the furnace and the end
                               time: a pour's end, else 0 [s] */
    double next_output;     /* the next sample's time [s] */
    double next_checkpoint; /* [s] */
    uint64_t rows;          /* series rows written */
    uint64_t frames;        /* VTU frames written, their times in frame_times */
    double *frame_times;
    size_t frame_capacity;
} scene_program;

/* Record a frame's time. Errors: SINTER_ERR_NOMEM. */
sinter_status scene_program_add_frame(sinter_ctx *ctx, scene_program *p, double time);

void scene_program_free(sinter_ctx *ctx, scene_program *p);

#endif
