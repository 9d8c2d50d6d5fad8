/* Private layout of a scene built from a scene file. */
#ifndef SINTER_SCENE_H
#define SINTER_SCENE_H

#include "io/scene_program.h"
#include "io/path.h"
#include "io/vtk_arrays.h"
#include "stepper/stepper.h"

#define SCENE_MAX_MATERIALS 32
#define SCENE_MAX_WALLS 64
#define SCENE_MAX_FORCES 16
#define SCENE_MAX_TEMPERATURE_BINS 100 /* [output] temperature_bins: most bins */
#define SCENE_MAX_TRACKED 8            /* [output] track: most particles followed in series.csv */
#define SCENE_NAME 64                  /* bytes of a name with its NUL; longer names are refused */
#define SCENE_NAME_TEXT "63"           /* SCENE_NAME - 1, for messages */

struct sinter_scene {
    sinter_ctx *ctx;
    char name[SCENE_NAME];
    char directory[SINTER_PATH_SIZE]; /* of the scene file, for relative paths */
    sinter_material *materials[SCENE_MAX_MATERIALS];
    char material_names[SCENE_MAX_MATERIALS][SCENE_NAME];
    size_t material_count;
    int32_t insert_materials[SCENE_MAX_MATERIALS]; /* [insert] materials = ...: the mixture's */
    size_t insert_mixture;                         /* their count (0: one material) */
    sinter_particles *ps;
    sinter_walls *walls;
    char wall_names[SCENE_MAX_WALLS][SCENE_NAME];
    sinter_force_model *forces[SCENE_MAX_FORCES];
    size_t force_count;
    sinter_heat_model *heats[SCENE_MAX_FORCES];
    size_t heat_count;
    sinter_electric_model *electric;
    sinter_stepper *st;
    double end_time;
    /* pour before the run */
    int pour;
    double pour_ke, pour_t_min, pour_t_max;
    /* triaxial compaction before the run (after the pour), [compact] */
    int compact;
    sinter_compaction_options compact_options;
    /* output */
    double output_interval;
    int write_vtu, write_csv, write_plot;
    int vtu_binary;   /* frames' arrays as inline base64 binary (1, the default) or ascii */
    int vtu_single;   /* [output] vtu_precision = single: floating-point arrays as Float32 */
    int vtu_appended; /* vtu_format = appended: binary arrays as raw appended data */
    /* beside each frame: the contacts (links) and the walls as .vtp (io/scene_frames.h) */
    int write_contacts, write_walls;
    /* histograms of the coordination number and the neck ratio in series.csv (scene_run.c) */
    int write_distributions;
    /* particles followed in series.csv by their persistent ids (io/scene_track.h) */
    uint64_t track_ids[SCENE_MAX_TRACKED];
    size_t track_count;
    /* [output] temperature_bins = lo hi n: a histogram of the particles' temperatures in
     * series.csv (scene_run.c); n = 0: none */
    double temperature_low, temperature_high;
    size_t temperature_bins;
    /* the two-particle reference's columns (io/scene_pair_reference.h) */
    int pair_reference;
    /* [fields]: coarse-grained fields (.vti) and lamina profiles (CSV) with each frame
     * (io/scene_frames.h, issue 37) */
    int fields;                                         /* a [fields] section */
    int fields_grid;                                    /* write frames/fields_NNNNN.vti */
    double fields_width, fields_cutoff, fields_spacing; /* [m], [1], [m] */
    int fields_box; /* box_min and box_max given (else the box of scene_frames.c) */
    double fields_lo[3], fields_hi[3];
    unsigned profile_axes; /* bit d: the laminae along axis d */
    double laminae;        /* laminae per profile */
    /* [output] solid_box: the series' solid fraction in this box instead of the walls' (issue
     * 38: a powder layer's packing density) */
    int solid_box;
    double solid_lo[3], solid_hi[3];
    double checkpoint_interval;
    /* where the run stands (io/scene_program.h); restored by sinter_scene_restart */
    scene_program program;
    double furnace_shift; /* how far the stepper's furnace has been delayed (the origin) [s] */
    double max_frames;    /* most records (series rows, VTU frames) the run may write */
};

/* Set the parameters of a [material NAME] section's lines on `m` (each "key = value" a
 * sinter_material_param key), labelling errors "file:line" (also used by io/pair.c). */
struct scene_text;
struct scene_section;
sinter_status scene_material_read(struct scene_text *t, struct scene_section *s,
                                  sinter_material *m);

/* The material named by a section's "material" key: its index into *id (scene.c). */
sinter_status scene_material_ref(struct scene_text *t, sinter_scene *sc, struct scene_section *s,
                                 int *id);

/* A section's size distribution keys (distribution `dist`, radius, spread, radius_min,
 * radius_max, gsd, table...) into o; a table's arrays into *d and *q (free both, also on
 * error). Shared by [particles] method = random, [insert] and [size NAME] (scene.c). */
sinter_status scene_read_distribution(struct scene_text *t, sinter_scene *sc,
                                      struct scene_section *s, sinter_packing_options *o,
                                      const char *dist, double radius, double **d, double **q);

/* A section's mixture, materials = A B ... with mass_fractions = f_A f_B ... (scene.c): the
 * ids into mat[], the fractions into a new array (*fractions, free it), their count. */
sinter_status scene_read_mixture(struct scene_text *t, sinter_scene *sc, struct scene_section *s,
                                 int32_t mat[SCENE_MAX_MATERIALS], double **fractions,
                                 size_t *count);

/* A mixture's sizes = NAME ... (one [size NAME] section per material, in the order of
 * `materials`), each read into sizes[k] (count of them, filled by sinter_packing_options_init);
 * the tables' arrays into tables[2 k], tables[2 k + 1] (all 2 count set; free each, also on
 * error) (scene.c). */
sinter_status scene_read_sizes(struct scene_text *t, sinter_scene *sc, struct scene_section *s,
                               size_t count, sinter_packing_options *sizes, double **tables);

/* The format bits of the frames' writers (io/vtk_arrays.h) the scene asks for. */
static inline int scene_vtk_format(const sinter_scene *sc)
{
    return (sc->vtu_binary ? SINTER_VTK_BINARY : 0) | (sc->vtu_single ? SINTER_VTK_FLOAT32 : 0);
}

/* Default of [output] max_frames. */
#define SCENE_MAX_FRAMES 1e6

/*
 * The output plan of a run of end_time after a pour of at most pour_time [s] (0: none),
 * recording every interval: SINTER_ERR_INVALID when t + interval == t at the last time
 * (the run would never end) or when it would record more than max_frames times.
 */
sinter_status sinter_scene_check_output(sinter_ctx *ctx, double end_time, double pour_time,
                                        double interval, double max_frames);

#endif
