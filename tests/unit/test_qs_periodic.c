#define _POSIX_C_SOURCE 200809L
/*
 * Periodic axes of the quasi-static stepper (issue 38, src/stepper/qs_periodic.c), through the
 * public API: copper spheres (R = 25 um, 1293 K, seed 001 table 2) sintering in a periodic cell
 * that follows the links' mean approach (qs_cell_strain, the default).
 *   - A pair that touches only across the face x = lo/hi sinters as the same pair on the
 *     principal planes with no periodic axis: its neck radius, approach and the cell's strain
 *     against the free pair's shrinkage, to round-off (1e-9 relative: for one link the cell's
 *     strain is the pair's approach over its length, eps = dl / l, the periodic rest of the
 *     solve is zero to round-off, so both runs integrate the same neck over the same steps and
 *     differ only in how the approach is summed: 1 - prod(1 - eps_k) against (d0 - d) / d0);
 *     and both against the two-particle model (sinter_neck_two_particles): neck ratio and
 *     shrinkage within 1e-6 relative, the necks' tolerance (rtol 1e-6 in both; measured 2e-8
 *     and 3e-8 at 1000 s: the stepper restarts the neck's integration at each global step).
 *   - A periodic 4 x 4 x 4 simple-cubic lattice with one sphere missing (the vacancy makes the
 *     solve's periodic rest non-zero), placed so that spheres straddle the faces, against the
 *     same lattice shifted by R / 2 so that none does. The odd x-layers sinter faster (3 times
 *     the grain-boundary diffusion), so the cell strains less along x than along y and z, and
 *     the vacancy's neighbours leave their affine places. Necks (1e-12 relative), the cell's
 *     lengths (1e-12) and the particles' relative positions (1e-12 R) agree to round-off, not
 *     bit for bit: the runs differ in the rounding of the absolute positions that the cell's
 *     affine move -eps (x - lo) and the wrapping act on (measured at 200 s: 8e-16 relative on
 *     the necks, 1.4e-14 R on the positions); the links, their ids and every order of the step
 *     are the same.
 *   - A checkpoint written at 40 s continues bit for bit (format 15: the cell and the links'
 *     images).
 *   - What is not supported is refused with a clear error.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene_support.h"

static const double R = 25e-6, T = 1293.0;

/* The context of the last stepper opened: its message goes with a failed call. */
static sinter_ctx *last_ctx;
#undef OK
#define OK(call)                                                                                   \
    do {                                                                                           \
        const sinter_status ok_ = (call);                                                          \
        if (ok_ != SINTER_OK)                                                                      \
            fail_msg("%s: %d, %s", #call, (int)ok_, sinter_last_error(last_ctx));                  \
    } while (0)

static void open_qs(scene *s)
{
    scene_init(s);
    last_ctx = s->ctx;
    scene_material(s, 72e9, 0.3, 8960, 0.0, 0.0); /* copper; neck data: the defaults */
    OK(sinter_particles_create(&s->ps, s->ctx));
    OK(sinter_particles_set_material(s->ps, 0, s->mat));
    OK(sinter_stepper_create(&s->st, s->ctx, SINTER_STEPPER_QUASISTATIC, s->ps, NULL));
}

static void add(scene *s, uint64_t id, double x, double y, double z)
{
    const double p[3] = {x, y, z}, r = R;
    OK(sinter_particles_add_with_ids(s->ps, 1, &id, p, &r, 0, T, NULL));
}

static sinter_sintering_stats stats_of(scene *s)
{
    sinter_sintering_stats st;
    memset(&st, 0, sizeof(st));
    st.struct_size = sizeof(st);
    OK(sinter_stepper_sintering_stats(s->st, &st));
    return st;
}

/* The links, sorted by their ids: neck radius and approach. */
typedef struct links {
    size_t m;
    uint64_t a[256], b[256];
    double neck[256], approach[256];
} links;

static void links_of(scene *s, links *out)
{
    memset(out, 0, sizeof(*out));
    sinter_snapshot *snap = NULL;
    OK(sinter_snapshot_create(&snap, s->st));
    OK(sinter_snapshot_counts(snap, NULL, NULL, &out->m, NULL));
    assert_true(out->m <= 256);
    const void *data = NULL;
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_A, &data, NULL, NULL, NULL));
    memcpy(out->a, data, out->m * sizeof(uint64_t));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_ID_B, &data, NULL, NULL, NULL));
    memcpy(out->b, data, out->m * sizeof(uint64_t));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_NECK_RADIUS, &data, NULL, NULL, NULL));
    memcpy(out->neck, data, out->m * sizeof(double));
    OK(sinter_snapshot_links(snap, SINTER_LINK_DATA_APPROACH, &data, NULL, NULL, NULL));
    memcpy(out->approach, data, out->m * sizeof(double));
    sinter_snapshot_destroy(snap);
}

/* Positions by id (ids < n). */
static void positions_of(scene *s, size_t n, double *x)
{
    size_t count = 0;
    const uint64_t *id = NULL;
    const double *p = NULL;
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_ID, (const void **)&id, &count, NULL));
    OK(sinter_particles_view_read(s->ps, SINTER_FIELD_POSITION, (const void **)&p, NULL, NULL));
    for (size_t i = 0; i < count; ++i) {
        assert_true(id[i] < n);
        memcpy(x + 3 * id[i], p + 3 * i, 3 * sizeof(double));
    }
    OK(sinter_particles_release(s->ps, SINTER_FIELD_ID));
    OK(sinter_particles_release(s->ps, SINTER_FIELD_POSITION));
}

static void near_enough(double a, double b, double rel, double abs_tol)
{
    if (!(fabs(a - b) <= rel * fmax(fabs(a), fabs(b)) + abs_tol))
        fail_msg("%.17g and %.17g differ by %.3g (allowed %.3g relative + %.3g)", a, b, fabs(a - b),
                 rel, abs_tol);
}

/* ---- a pair across the face ----------------------------------------------------------------- */

static void test_pair_across_the_face(void **state)
{
    (void)state;
    const double t_end = 1000.0, L = 5.0 * R;
    scene per, free_pair;
    open_qs(&per);
    /* x periodic on [0, 5 R): A at 0.6 R, B at 3.6 R, whose image at -1.4 R touches A; their
     * direct distance 3 R does not touch. y and z: the principal planes, as the free pair's. */
    OK(sinter_stepper_set_periodic(per.st, 0, 0.0, L));
    add(&per, 0, 0.6 * R, R, R);
    add(&per, 1, 3.6 * R, R, R);
    open_qs(&free_pair);
    add(&free_pair, 0, R, R, R);
    add(&free_pair, 1, 3.0 * R, R, R);
    OK(sinter_stepper_advance(per.st, t_end));
    OK(sinter_stepper_advance(free_pair.st, t_end));
    links lp, lf;
    links_of(&per, &lp);
    links_of(&free_pair, &lf);
    assert_int_equal(lp.m, 1);
    assert_int_equal(lf.m, 1);
    near_enough(lp.neck[0], lf.neck[0], 1e-9, 0.0);
    near_enough(lp.approach[0], lf.approach[0], 1e-9, 0.0);
    const sinter_sintering_stats sp = stats_of(&per), sf = stats_of(&free_pair);
    int periodic = 0;
    double lo = 0.0, hi = 0.0;
    OK(sinter_stepper_get_periodic(per.st, 0, &periodic, &lo, &hi));
    assert_int_equal(periodic, 1);
    near_enough(sp.shrinkage[0], 1.0 - (hi - lo) / L, 1e-12, 0.0);
    print_message("pair across the face at %g s: neck %.10e m (free pair %.10e), cell strain "
                  "%.10e (free pair's shrinkage %.10e)\n",
                  t_end, lp.neck[0], lf.neck[0], sp.shrinkage[0], sf.shrinkage[0]);
    /* the two-particle model of the same spheres */
    sinter_neck_model *nm = NULL;
    OK(sinter_neck_model_create(&nm, per.ctx));
    const double times[1] = {0.0}, temps[1] = {T}, when = t_end;
    double x = 0.0, shrinkage = 0.0;
    OK(sinter_neck_two_particles(nm, per.mat, R, R, 1, times, temps, 1, &when, &x, &shrinkage,
                                 NULL));
    sinter_neck_model_destroy(nm);
    print_message("two-particle model: x/R %.10f (periodic %.10f), shrinkage %.10e\n", x / R,
                  lp.neck[0] / R, shrinkage);
    assert_true(sp.shrinkage[0] > 1e-3); /* it did sinter */
    near_enough(sp.shrinkage[0], sf.shrinkage[0], 1e-9, 0.0);
    near_enough(lp.neck[0] / R, x / R, 1e-6, 0.0);
    near_enough(sp.shrinkage[0], shrinkage, 1e-6, 0.0);
    scene_close(&per);
    scene_close(&free_pair);
}

/* ---- a lattice across the faces against the same lattice shifted ---------------------------- */

enum { SIDE = 4, LATTICE = SIDE * SIDE * SIDE, VACANCY = 21 };

/* The lattice with its first sphere at offset + R on each axis, in the periodic cell
 * [0, 2 SIDE R)^3; sphere VACANCY left out. */
static void open_lattice(scene *s, double offset)
{
    open_qs(s);
    /* the odd x-layers of a faster-sintering copper (3 times the grain-boundary diffusion):
     * their links along y and z approach faster than the even layers', so the vacancy's
     * neighbours are pulled off their affine places */
    sinter_material *fast = NULL;
    OK(sinter_material_clone(&fast, s->mat));
    double dgb = 0.0;
    OK(sinter_material_get(s->mat, SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, &dgb));
    OK(sinter_material_set(fast, SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR, 3.0 * dgb));
    OK(sinter_particles_set_material(s->ps, 1, fast));
    sinter_material_destroy(fast);
    for (int d = 0; d < 3; ++d)
        OK(sinter_stepper_set_periodic(s->st, d, 0.0, 2.0 * SIDE * R));
    uint64_t id = 0;
    for (int i = 0; i < SIDE; ++i)
        for (int j = 0; j < SIDE; ++j)
            for (int k = 0; k < SIDE; ++k, ++id)
                if (id != VACANCY) {
                    const double p[3] = {(1 + 2 * i) * R + offset, (1 + 2 * j) * R + offset,
                                         (1 + 2 * k) * R + offset};
                    const double r = R;
                    OK(sinter_particles_add_with_ids(s->ps, 1, &id, p, &r, i % 2, T, NULL));
                }
}

/* The vector from particle 0 to particle `i`, by the nearest image in the cell of lengths L. */
static void relative(const double *x, size_t i, const double L[3], double out[3])
{
    for (int d = 0; d < 3; ++d) {
        const double v = x[3 * i + (size_t)d] - x[(size_t)d];
        out[d] = v - L[d] * round(v / L[d]);
    }
}

static void test_lattice_straddling_the_faces_as_shifted_away(void **state)
{
    (void)state;
    const double t_end = 200.0;
    scene across, away;
    open_lattice(&across, -0.5 * R); /* spheres at 0.5 R, 2.5 R, ...: the first ones straddle lo */
    open_lattice(&away, 0.0);        /* at R, 3 R, ...: none crosses a face */
    OK(sinter_stepper_advance(across.st, t_end));
    OK(sinter_stepper_advance(away.st, t_end));
    links la, lw;
    links_of(&across, &la);
    links_of(&away, &lw);
    /* 3 per sphere, less the vacancy's 6 */
    assert_int_equal(la.m, 3 * LATTICE - 6);
    assert_int_equal(lw.m, la.m);
    double worst_neck = 0.0, worst_x = 0.0;
    for (size_t k = 0; k < la.m; ++k) {
        assert_true(la.a[k] == lw.a[k] && la.b[k] == lw.b[k]);
        near_enough(la.neck[k], lw.neck[k], 1e-12, 0.0);
        near_enough(la.approach[k], lw.approach[k], 1e-9, 1e-12 * R);
        worst_neck = fmax(worst_neck, fabs(la.neck[k] - lw.neck[k]) / lw.neck[k]);
    }
    /* the vacancy's layer (x index 1): its links along y do not all approach alike */
    double lo_app = INFINITY, hi_app = 0.0;
    for (size_t k = 0; k < la.m; ++k)
        if (la.a[k] / 16 == 1 && la.b[k] / 16 == 1 && la.b[k] - la.a[k] == 4) {
            lo_app = fmin(lo_app, la.approach[k]);
            hi_app = fmax(hi_app, la.approach[k]);
        }
    assert_true(hi_app - lo_app > 1e-3 * hi_app);
    double La[3], Lw[3];
    for (int d = 0; d < 3; ++d) {
        int p = 0;
        double lo = 0.0, hi = 0.0;
        OK(sinter_stepper_get_periodic(across.st, d, &p, &lo, &hi));
        La[d] = hi - lo;
        OK(sinter_stepper_get_periodic(away.st, d, &p, &lo, &hi));
        Lw[d] = hi - lo;
        near_enough(La[d], Lw[d], 1e-12, 0.0);
    }
    static double xa[3 * LATTICE], xw[3 * LATTICE];
    positions_of(&across, LATTICE, xa);
    positions_of(&away, LATTICE, xw);
    for (size_t i = 1; i < LATTICE; ++i) {
        if (i == VACANCY)
            continue;
        double va[3], vw[3];
        relative(xa, i, La, va);
        relative(xw, i, Lw, vw);
        for (int d = 0; d < 3; ++d) {
            near_enough(va[d], vw[d], 0.0, 1e-12 * R);
            worst_x = fmax(worst_x, fabs(va[d] - vw[d]) / R);
        }
    }
    const sinter_sintering_stats sa = stats_of(&across), sw = stats_of(&away);
    print_message("lattice at %g s: cell strain %.6e %.6e %.6e (shifted: %.6e), density %.6f; "
                  "largest differences: neck %.2e relative, relative positions %.2e R; the "
                  "vacancy layer's y links approach %.4e to %.4e m\n",
                  t_end, sa.shrinkage[0], sa.shrinkage[1], sa.shrinkage[2], sw.shrinkage[0],
                  sa.relative_density, worst_neck, worst_x, lo_app, hi_app);
    assert_true(sa.shrinkage[0] > 1e-3);
    /* the layers of x: y and z alike (the lattice is symmetric under their exchange), x not */
    near_enough(sa.shrinkage[1], sa.shrinkage[2], 1e-9, 0.0);
    assert_true(fabs(sa.shrinkage[0] - sa.shrinkage[1]) > 1e-3 * sa.shrinkage[1]);
    scene_close(&across);
    scene_close(&away);
}

/* ---- restart -------------------------------------------------------------------------------- */

static void test_restart_bit_for_bit(void **state)
{
    (void)state;
    char dir[] = "/tmp/sinter_qs_periodic_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[64];
    snprintf(path, sizeof(path), "%s/at40.bin", dir);
    scene straight, restarted;
    open_lattice(&straight, -0.5 * R);
    OK(sinter_stepper_advance(straight.st, 40.0));
    OK(sinter_checkpoint_write(straight.st, path));
    OK(sinter_stepper_advance(straight.st, 100.0));
    open_lattice(&restarted, -0.5 * R);
    OK(sinter_checkpoint_read(restarted.st, path));
    OK(sinter_stepper_advance(restarted.st, 100.0));
    static double xs[3 * LATTICE], xr[3 * LATTICE];
    positions_of(&straight, LATTICE, xs);
    positions_of(&restarted, LATTICE, xr);
    assert_memory_equal(xs, xr, sizeof(xs));
    links ls, lr;
    links_of(&straight, &ls);
    links_of(&restarted, &lr);
    assert_int_equal(ls.m, lr.m);
    assert_memory_equal(ls.neck, lr.neck, sizeof(ls.neck));
    assert_memory_equal(ls.approach, lr.approach, sizeof(ls.approach));
    for (int d = 0; d < 3; ++d) {
        int p1 = 0, p2 = 0;
        double lo1, hi1, lo2, hi2;
        OK(sinter_stepper_get_periodic(straight.st, d, &p1, &lo1, &hi1));
        OK(sinter_stepper_get_periodic(restarted.st, d, &p2, &lo2, &hi2));
        assert_int_equal(p1, p2);
        assert_memory_equal(&hi1, &hi2, sizeof(hi1));
    }
    const sinter_sintering_stats a = stats_of(&straight), b = stats_of(&restarted);
    assert_memory_equal(a.shrinkage, b.shrinkage, sizeof(a.shrinkage));
    scene_close(&straight);
    scene_close(&restarted);
    unlink(path);
    rmdir(dir);
}

/* ---- refusals ------------------------------------------------------------------------------- */

static void test_refusals(void **state)
{
    (void)state;
    scene s;
    /* a period under twice the touching distance: a pair could touch through two images */
    open_qs(&s);
    OK(sinter_stepper_set_periodic(s.st, 0, 0.0, 3.0 * R));
    add(&s, 0, R, R, R);
    add(&s, 1, 2.5 * R, R, R);
    assert_int_equal(sinter_stepper_step(s.st, 1), SINTER_ERR_UNSUPPORTED);
    assert_non_null(strstr(sinter_last_error(s.ctx), "two images"));
    scene_close(&s);
    /* a particle outside the cell */
    open_qs(&s);
    OK(sinter_stepper_set_periodic(s.st, 1, 0.0, 10.0 * R));
    add(&s, 0, R, R, R);
    add(&s, 1, 3.0 * R, -2.0 * R, R);
    assert_int_equal(sinter_stepper_step(s.st, 1), SINTER_ERR_INVALID);
    assert_non_null(strstr(sinter_last_error(s.ctx), "outside the periodic cell"));
    scene_close(&s);
    /* every kind takes periodic axes (the staggered one through images: test_periodic_models) */
    open_qs(&s);
    sinter_stepper *staggered = NULL;
    OK(sinter_stepper_create(&staggered, s.ctx, SINTER_STEPPER_STAGGERED, s.ps, NULL));
    OK(sinter_stepper_set_periodic(staggered, 0, 0.0, 10.0 * R));
    sinter_stepper_destroy(staggered);
    scene_close(&s);
    /* qs_cell_strain is 0 or 1 */
    open_qs(&s);
    assert_int_equal(sinter_stepper_set_option(s.st, "qs_cell_strain", 2.0), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_option(s.st, "qs_cell_strain", 0.0));
    scene_close(&s);
}

/* With qs_cell_strain 0 the cell keeps its size: a ring of three spheres around the x axis's
 * period (links A-B, B-C and C-A across the face) cannot shrink, its necks grow against the
 * links (constrained sintering), the centres stay 2 R apart (the three links are alike) and the
 * cell's strain stays 0. */
static void test_fixed_cell(void **state)
{
    (void)state;
    scene s;
    open_qs(&s);
    OK(sinter_stepper_set_option(s.st, "qs_cell_strain", 0.0));
    OK(sinter_stepper_set_periodic(s.st, 0, 0.0, 6.0 * R));
    add(&s, 0, R, R, R);
    add(&s, 1, 3.0 * R, R, R);
    add(&s, 2, 5.0 * R, R, R);
    OK(sinter_stepper_advance(s.st, 100.0));
    int p = 0;
    double lo = 0.0, hi = 0.0;
    OK(sinter_stepper_get_periodic(s.st, 0, &p, &lo, &hi));
    assert_true(hi - lo == 6.0 * R);
    const sinter_sintering_stats st = stats_of(&s);
    assert_int_equal(st.links, 3);
    assert_true(st.shrinkage[0] == 0.0);
    assert_true(st.neck_ratio_mean > 0.1); /* the necks grew */
    double x[9];
    positions_of(&s, 3, x);
    near_enough(x[3] - x[0], 2.0 * R, 1e-9, 0.0);
    near_enough(x[6] - x[3], 2.0 * R, 1e-9, 0.0);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pair_across_the_face),
        cmocka_unit_test(test_lattice_straddling_the_faces_as_shifted_away),
        cmocka_unit_test(test_restart_bit_for_bit),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_fixed_cell),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
