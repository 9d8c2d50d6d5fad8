/*
 * The files of a scene's frame beside the particles' .vtu ([output] contacts, walls; issue
 * 37): frames/contacts_NNNNN.vtp (frames/links_NNNNN.vtp for the quasi-static stepper) and
 * frames/walls_NNNNN.vtp, listed in the .pvd as parts 1 and 2 of the frame's timestep; with
 * a [fields] section the coarse-grained fields frames/fields_NNNNN.vti (part 3) and the
 * lamina profiles frames/profile_<axis>_NNNNN.csv (not in the .pvd).
 */
#ifndef SINTER_IO_SCENE_FRAMES_H
#define SINTER_IO_SCENE_FRAMES_H

#include "io/scene.h"

/* Most extra files of one frame. */
#define SCENE_FRAME_EXTRAS 3

/* Write frame `frame`'s extra files into out_dir/frames as the scene's options ask: the
 * contacts of a snapshot of the stepper (an empty file where its state is not evaluated yet,
 * such as before the first step) and the walls clipped to the stepper's domain, or without
 * one to the particles' bounding box grown by a tenth of its diagonal. */
sinter_status scene_frame_extras_write(const sinter_scene *sc, const char *out_dir, uint64_t frame);

/* The extra files of frame `frame` that are in out_dir: their paths relative to it (into
 * rel, up to SCENE_FRAME_EXTRAS) and their parts; returns their number. */
size_t scene_frame_extras_list(const sinter_scene *sc, const char *out_dir, uint64_t frame,
                               char rel[SCENE_FRAME_EXTRAS][64],
                               unsigned parts[SCENE_FRAME_EXTRAS]);

#endif
