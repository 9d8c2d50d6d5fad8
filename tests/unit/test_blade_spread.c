/*
 * Spreading a powder layer with a blade (issue 38): a blade, a closed thin box read as a
 * triangle mesh (a closed surface has an outside everywhere, so powder that passes under the
 * blade and piles up behind it meets the blade's back face, not the half-space behind a one-sided
 * rectangle), lifted to a gap g above the build plate and moved along x by a displacement
 * schedule, spreads a heap of spheres. Behind the blade no sphere may reach above the gap by
 * more than a contact's overlap: the layer's top is bounded by g (plus 1 % of a radius for the
 * overlap of a soft contact with the blade's bottom face). Spheres are
 * neither lost nor made, the blade pushes the heap along +x (its reaction along -x), and the
 * layer covers the plate behind the blade.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "scene_support.h"

#define R 1e-4     /* sphere radius [m] */
#define GAP 5e-4   /* blade gap above the plate [m]: 2.5 diameters */
#define WIDTH 1e-3 /* between the side walls [m] */

/* The blade: a box x in [-0.2, 0] mm, y across the bed and beyond, z in [0, 2] mm, with
 * outward normals (counter-clockwise seen from outside), as an ASCII STL in mm. */
static void write_blade(char *path)
{
    snprintf(path, 64, "/tmp/sinter_bladeXXXXXX");
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    const double x[2] = {-0.2, 0.0}, y[2] = {-0.5, 1.5}, z[2] = {0.0, 2.0};
#define V(i, j, k)                                                                                 \
    {                                                                                              \
        x[i], y[j], z[k]                                                                           \
    }
    const double quads[6][4][3] = {
        {V(0, 0, 0), V(0, 0, 1), V(0, 1, 1), V(0, 1, 0)}, /* -x */
        {V(1, 0, 0), V(1, 1, 0), V(1, 1, 1), V(1, 0, 1)}, /* +x */
        {V(0, 0, 0), V(1, 0, 0), V(1, 0, 1), V(0, 0, 1)}, /* -y */
        {V(0, 1, 0), V(0, 1, 1), V(1, 1, 1), V(1, 1, 0)}, /* +y */
        {V(0, 0, 0), V(0, 1, 0), V(1, 1, 0), V(1, 0, 0)}, /* -z */
        {V(0, 0, 1), V(1, 0, 1), V(1, 1, 1), V(0, 1, 1)}, /* +z */
    };
#undef V
    fprintf(f, "solid blade\n");
    for (int q = 0; q < 6; ++q)
        for (int t = 0; t < 2; ++t) {
            const int idx[3] = {0, t + 1, t + 2};
            fprintf(f, "facet normal 0 0 0\nouter loop\n");
            for (int p = 0; p < 3; ++p)
                fprintf(f, "vertex %g %g %g\n", quads[q][idx[p]][0], quads[q][idx[p]][1],
                        quads[q][idx[p]][2]);
            fprintf(f, "endloop\nendfacet\n");
        }
    fprintf(f, "endsolid blade\n");
    fclose(f);
}

static void test_blade_leaves_a_layer_below_the_gap(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 1e7, 0.3, 2500.0, 0.5, 0.3);
    scene_open(&s, "hertz_mindlin", 1);
    scene_floor(&s, 0.0); /* the build plate */
    const double o[3] = {0, 0, 0}, ny[3] = {0, 1, 0}, nyh[3] = {0, -1, 0}, pyh[3] = {0, WIDTH, 0};
    OK(sinter_walls_add_plane(s.walls, o, ny, s.wall_mat, NULL));
    OK(sinter_walls_add_plane(s.walls, pyh, nyh, s.wall_mat, NULL));
    char path[64];
    write_blade(path);
    size_t blade = 0;
    OK(sinter_walls_add_mesh(s.walls, path, 1e-3, o, o, 0, 0.0, s.wall_mat, &blade));
    remove(path);
    /* held on the plate while the heap settles, lifted to the gap, then 2 mm along x */
    const double times[4] = {0.0, 0.02, 0.021, 0.041};
    const double disp[12] = {0, 0, 0, 0, 0, 0, 0, 0, GAP, 2e-3, 0, GAP};
    OK(sinter_walls_set_schedule(s.walls, blade, 4, times, disp));
    sinter_packing_options p;
    OK(sinter_packing_options_init(&p, sizeof(p)));
    p.radius_mean = R;
    p.seed = 3;
    const double lo[3] = {1e-5, 0, 0}, hi[3] = {1.2e-3, WIDTH, 2e-3};
    for (int d = 0; d < 3; ++d) {
        p.box_min[d] = lo[d];
        p.box_max[d] = hi[d];
    }
    size_t n = 0;
    OK(sinter_pack_random(s.ps, &p, 150, &n));
    assert_int_equal(n, 150);
    OK(sinter_stepper_set_dt(s.st, 2e-6));
    double pushed = 0.0;
    for (int k = 1; k <= 45; ++k) {
        OK(sinter_stepper_advance(s.st, 1e-3 * k));
        double f[3];
        OK(sinter_walls_get_force(s.walls, blade, f));
        if (k > 25)
            pushed = fmin(pushed, -f[0]); /* the push it exerts: +x on the powder */
    }
    size_t count = 0;
    OK(sinter_particles_count(s.ps, &count));
    assert_int_equal(count, 150);
    double point[3], velocity[3];
    OK(sinter_walls_get_state(s.walls, blade, point, velocity));
    const double blade_x = point[0] - 2e-4; /* its back face */
    const double *x = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    size_t behind = 0, ahead = 0;
    double top = 0.0;
    for (size_t i = 0; i < count; ++i) {
        if (x[3 * i] < blade_x - R) {
            ++behind;
            top = fmax(top, x[3 * i + 2] + R);
        } else
            ++ahead;
    }
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    print_message("blade at x = %.4g m: %zu spheres behind it (layer top %.4g m, gap %.4g m), "
                  "%zu ahead; blade force along x %.3g N\n",
                  point[0], behind, top, GAP, ahead, pushed);
    assert_true(top <= GAP + 0.01 * R);
    assert_true(behind >= 30); /* a layer, not a bare plate: 2 mm x 1 mm at 2.5 diameters */
    assert_true(ahead > 0);    /* the rest is still pushed along */
    assert_true(pushed < 0.0); /* the powder pushes back on the blade: -x */
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blade_leaves_a_layer_below_the_gap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
