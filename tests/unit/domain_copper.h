/*
 * The copper lattice of the quasi-static subdomain tests (test_qs_domain.c,
 * tests/mpi/test_mpi_qs.c): 8 x 3 x 3 spheres of R = 25 um (radii spread by up to 0.2 %, so
 * that the necks differ) on a 2R lattice, so that every neighbour pair overlaps and becomes a
 * link; seed 001 table 2 copper at 1293 K; ids a permutation of the places (a link's smaller
 * id lies on either side of a border). Slabs along x of [0, 16 R). What a run leaves is
 * collected into a copper_outcome: positions and rotations by id - 1, the links with their
 * necks and approaches, the sintering statistics. Everything is static inline: a file that
 * includes this uses what it needs.
 */
#ifndef SINTER_TEST_DOMAIN_COPPER_H
#define SINTER_TEST_DOMAIN_COPPER_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include <sinter.h>
#include <sinter_domain.h>

enum {
    COPPER_NX = 8,
    COPPER_NY = 3,
    COPPER_NZ = 3,
    COPPER_N = COPPER_NX * COPPER_NY * COPPER_NZ,
    COPPER_MAX_LINKS = 4 * COPPER_N,
    COPPER_SLOTS = 4 /* subdomains whose counts an outcome keeps */
};
#define COPPER_R 25e-6 /* the radius before the spread [m] */
#define COPPER_X0 0.0
#define COPPER_X1 (2.0 * COPPER_NX * COPPER_R)

/* Place p's centre and radius; `lifted`: the top layer 0.5 R off the layer below and off the
 * x and y planes (a link component that no plane holds). */
static inline void copper_place(size_t p, int lifted, double x[3], double *r)
{
    const size_t i = p / (COPPER_NY * COPPER_NZ), j = (p / COPPER_NZ) % COPPER_NY,
                 k = p % COPPER_NZ;
    x[0] = (1 + 2 * (double)i) * COPPER_R;
    x[1] = (1 + 2 * (double)j) * COPPER_R;
    x[2] = (1 + 2 * (double)k) * COPPER_R;
    if (lifted && k == COPPER_NZ - 1)
        for (size_t d = 0; d < 3; ++d)
            x[d] += 0.5 * COPPER_R;
    *r = COPPER_R * (1.0 + 2e-3 * (double)((p * 7919u) % 97u) / 96.0);
}

static inline uint64_t copper_id_of(size_t p)
{
    return 1 + (uint64_t)((p * 37u) % COPPER_N); /* 37 is prime to 72 */
}

/* The slab of `size` equal ones of [x0, x1) that holds x (the outer ones open outwards). */
static inline int copper_slab_of(double x, double x0, double x1, int size)
{
    const int r = (int)floor((x - x0) / ((x1 - x0) / size));
    return r < 0 ? 0 : r >= size ? size - 1 : r;
}

/* The copper material (neck data: the defaults, copper), a particle set of it and a
 * quasi-static stepper with `strategy`, the solve's target `rtol`, a skin of R / 2 and a
 * first global step of 1 ms. */
static inline sinter_status copper_setup(sinter_ctx *ctx, int strategy, double rtol,
                                         sinter_material **mat, sinter_particles **ps,
                                         sinter_stepper **st)
{
    sinter_status s = sinter_material_create(mat, ctx, "copper");
    if (s == SINTER_OK)
        s = sinter_material_set(*mat, SINTER_MAT_YOUNGS_MODULUS, 72e9);
    if (s == SINTER_OK)
        s = sinter_material_set(*mat, SINTER_MAT_POISSON_RATIO, 0.3);
    if (s == SINTER_OK)
        s = sinter_material_set(*mat, SINTER_MAT_DENSITY, 8960);
    if (s == SINTER_OK)
        s = sinter_particles_create(ps, ctx);
    if (s == SINTER_OK)
        s = sinter_particles_set_material(*ps, 0, *mat);
    if (s == SINTER_OK)
        s = sinter_stepper_create(st, ctx, SINTER_STEPPER_QUASISTATIC, *ps, NULL);
    if (s == SINTER_OK)
        s = sinter_stepper_set_option(*st, "qs_strategy", strategy);
    if (s == SINTER_OK)
        s = sinter_stepper_set_option(*st, "qs_solve_rtol", rtol);
    if (s == SINTER_OK)
        s = sinter_stepper_set_skin(*st, 0.5 * COPPER_R);
    if (s == SINTER_OK)
        s = sinter_stepper_set_dt(*st, 1e-3); /* the first global step [s] */
    return s;
}

/* Add the spheres whose x - shift lies in slab `rank` of `size` (size 0: every one). */
static inline sinter_status copper_add(sinter_particles *ps, int rank, int size, double shift,
                                       int lifted)
{
    sinter_status s = SINTER_OK;
    for (size_t p = 0; p < COPPER_N && s == SINTER_OK; ++p) {
        double x[3], r;
        copper_place(p, lifted, x, &r);
        if (size > 0 && copper_slab_of(x[0] - shift, COPPER_X0, COPPER_X1, size) != rank)
            continue;
        const uint64_t id = copper_id_of(p);
        s = sinter_particles_add_with_ids(ps, 1, &id, x, &r, 0, 1293.0, NULL);
    }
    return s;
}

typedef struct copper_outcome {
    double x[3 * COPPER_N], rot[3 * COPPER_N]; /* by id - 1 */
    int seen[COPPER_N];
    size_t links;
    uint64_t link_a[COPPER_MAX_LINKS], link_b[COPPER_MAX_LINKS];
    double neck[COPPER_MAX_LINKS], approach[COPPER_MAX_LINKS];
    double stats[11];
    uint64_t steps;
    size_t owned[COPPER_SLOTS], ghosts[COPPER_SLOTS]; /* by slot */
} copper_outcome;

/* The collective statistics of the run (every subdomain calls it), into `ss`. */
static inline sinter_status copper_sintering_stats(sinter_stepper *st, sinter_sintering_stats *ss)
{
    memset(ss, 0, sizeof(*ss));
    ss->struct_size = sizeof(*ss);
    return sinter_stepper_sintering_stats(st, ss);
}

/* This subdomain's owned particles, its links and `ss` into `o` (not collective: a caller
 * with threads holds a lock), its counts into slot `slot`; 0, or the line that failed. */
static inline int copper_collect(copper_outcome *o, size_t slot, sinter_particles *ps,
                                 sinter_stepper *st, const sinter_sintering_stats *ss)
{
    size_t owned = 0, count = 0;
    const uint64_t *id = NULL;
    const double *x = NULL, *rot = NULL;
    sinter_snapshot *snap = NULL;
    sinter_stepper_stats stats;
    stats.struct_size = sizeof(stats);
    if (sinter_stepper_get_stats(st, &stats) != SINTER_OK ||
        sinter_particles_owned_count(ps, &owned) != SINTER_OK ||
        sinter_particles_count(ps, &count) != SINTER_OK ||
        sinter_snapshot_create(&snap, st) != SINTER_OK)
        return __LINE__;
    int failed = 0;
    o->owned[slot] = owned;
    o->ghosts[slot] = count - owned;
    if (sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&id, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ||
        sinter_particles_view_read(ps, SINTER_FIELD_ROTATION, (const void **)&rot, NULL, NULL))
        failed = __LINE__;
    for (size_t i = 0; i < owned && id != NULL && x != NULL && rot != NULL; ++i) {
        const size_t k = (size_t)id[i] - 1;
        memcpy(o->x + 3 * k, x + 3 * i, 24);
        memcpy(o->rot + 3 * k, rot + 3 * i, 24);
        o->seen[k]++;
    }
    sinter_particles_release(ps, SINTER_FIELD_ID);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    sinter_particles_release(ps, SINTER_FIELD_ROTATION);
    size_t m = 0;
    const void *a = NULL, *b = NULL, *neck = NULL, *appr = NULL;
    if (sinter_snapshot_counts(snap, NULL, NULL, &m, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &a, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &b, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &neck, NULL, NULL, NULL) ||
        sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &appr, NULL, NULL, NULL) ||
        o->links + m > COPPER_MAX_LINKS)
        failed = __LINE__;
    for (size_t k = 0; k < m && !failed; ++k, ++o->links) {
        o->link_a[o->links] = ((const uint64_t *)a)[k];
        o->link_b[o->links] = ((const uint64_t *)b)[k];
        o->neck[o->links] = ((const double *)neck)[k];
        o->approach[o->links] = ((const double *)appr)[k];
    }
    sinter_snapshot_destroy(snap);
    const double v[11] = {ss->neck_mean,
                          ss->neck_min,
                          ss->neck_max,
                          ss->neck_ratio_mean,
                          ss->shrinkage[0],
                          ss->shrinkage[1],
                          ss->shrinkage[2],
                          ss->relative_density,
                          ss->coordination,
                          (double)ss->links,
                          (double)ss->pcg_iterations};
    memcpy(o->stats, v, sizeof(v)); /* the same on every subdomain */
    o->steps = stats.steps;
    return failed;
}

/* The largest |a - b| over the largest |a|, n values. */
static inline double copper_rel_diff(const double *a, const double *b, size_t n)
{
    double worst = 0.0, scale = 0.0;
    for (size_t i = 0; i < n; ++i)
        scale = fmax(scale, fabs(a[i]));
    for (size_t i = 0; i < n; ++i)
        worst = fmax(worst, fabs(a[i] - b[i]));
    return scale > 0.0 ? worst / scale : worst;
}

#endif
