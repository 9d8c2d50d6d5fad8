/*
 * Triangle-mesh walls turning about an axis (sinter_walls_set_rotation, issue 38): a sphere
 * on a turning triangulated square against the same sphere on the analytic turning rectangle,
 * a sphere struck by a turning paddle against the elastic contact's momentum, the wall's
 * reaction moment about the axis against the sphere's angular momentum, bad input refused.
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "scene_support.h"
#include "walls/walls.h"

static const double PI = 3.14159265358979323846;
static const double R = 1e-3, E = 1e7, NU = 0.3, RHO = 2500.0;
static const double E_WALL = 1e13; /* a rigid wall */

static void open_rigid(scene *s, double xi, double mu, int gravity)
{
    scene_init(s);
    scene_material(s, E, NU, RHO, xi, mu);
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_YOUNGS_MODULUS, E_WALL));
    scene_open(s, "hertz_mindlin", gravity);
}

/* An ASCII STL file of n facets (9 coordinates each, counter-clockwise from the front) at a
 * temporary path (64 chars). */
static void write_stl(char *path, const double *v, size_t n)
{
    snprintf(path, 64, "/tmp/sinter_meshrotXXXXXX");
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fprintf(f, "solid rot\n");
    for (size_t k = 0; k < n; ++k) {
        fprintf(f, "  facet normal 0 0 0\n    outer loop\n");
        for (int p = 0; p < 3; ++p)
            fprintf(f, "      vertex %.17g %.17g %.17g\n", v[9 * k + 3 * p], v[9 * k + 3 * p + 1],
                    v[9 * k + 3 * p + 2]);
        fprintf(f, "    endloop\n  endfacet\n");
    }
    fprintf(f, "endsolid rot\n");
    fclose(f);
}

/* A square grid of n x n unit cells in the plane z = 0 centred on the origin, each split
 * along a diagonal (alternating), normals +z: 2 n^2 facets into v. */
static size_t grid_square(int n, double *v)
{
    size_t k = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x0 = i - 0.5 * n, x1 = x0 + 1, y0 = j - 0.5 * n, y1 = y0 + 1;
            const double q[4][3] = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
            const int t[2][3] = {{0, 1, 2}, {0, 2, 3}}, s[2][3] = {{0, 1, 3}, {1, 2, 3}};
            const int(*tt)[3] = (i + j) % 2 ? t : s;
            for (int f = 0; f < 2; ++f, ++k)
                for (int p = 0; p < 3; ++p)
                    for (int d = 0; d < 3; ++d)
                        v[9 * k + 3 * p + d] = q[tt[f][p]][d];
        }
    return k;
}

/* A sphere dropped at rest off the axis onto a square of side 20 mm turning at 20 rad/s
 * about z (wall 0 of s): the turntable drags it. Trajectory (x, y, z, vx, vy) at 60 times
 * (every 2 ms) and the wall's force and moment into out (5 * 60 + 6). */
#define SAMPLES 60
static void turntable(scene *s, double *out)
{
    scene_add(s, 4e-3, 1.5e-3, R - 1e-7, R);
    OK(sinter_stepper_set_dt(s->st, 1e-6));
    for (int k = 0; k < SAMPLES; ++k) {
        OK(sinter_stepper_advance(s->st, 2e-3 * (k + 1)));
        double x[3], u[3];
        get3(s, SINTER_FIELD_POSITION, 0, x);
        get3(s, SINTER_FIELD_VELOCITY, 0, u);
        out[5 * k] = x[0], out[5 * k + 1] = x[1], out[5 * k + 2] = x[2];
        out[5 * k + 3] = u[0], out[5 * k + 4] = u[1];
    }
    OK(sinter_walls_get_force(s->walls, 0, out + 5 * SAMPLES));
    OK(sinter_walls_get_moment(s->walls, 0, out + 5 * SAMPLES + 3));
}

/*
 * A sphere dropped onto a square of 1800 triangles (0.5 mm cells) turning at 20 rad/s about
 * its normal follows the sphere on the analytic rectangle turning at the same rate: dragged
 * from rest into rolling on the turning surface, over 0.12 s (2.4 rad of turn) it crosses
 * more than 5 mm of the mesh's frame, over a dozen cells (edges and vertices), the tangential
 * history carried across them. Both walls give the same surface velocity (sinter_wall_velocity_at,
 * the same bits); the mesh's distance is its face's in the turned frame, R^T (x - c), whose z row
 * differs from (0, 0, 1) by round-off (cos + (1 - cos) is 1 to an ulp): the trajectory agrees to
 * 1e-9 of the sphere's radius in position and of the surface speed in velocity (round-off grown
 * through 120000 steps of a stable, damped contact), the wall force and moment to 1e-6.
 */
static void test_turning_mesh_as_turning_rectangle(void **state)
{
    (void)state;
    const double omega = 20.0, o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
    double ref[5 * SAMPLES + 6], got[5 * SAMPLES + 6];
    scene s;
    open_rigid(&s, 0.5, 0.5, 1);
    OK(sinter_walls_add_rectangle(s.walls, o, up, ex, 10e-3, 10e-3, s.wall_mat, NULL));
    OK(sinter_walls_set_spin(s.walls, 0, omega));
    turntable(&s, ref);
    scene_close(&s);

    const int n = 30;
    double *v = malloc(9 * 2 * (size_t)(n * n) * sizeof(double));
    const size_t nf = grid_square(n, v);
    char path[64];
    write_stl(path, v, nf);
    open_rigid(&s, 0.5, 0.5, 1);
    const double rot[3] = {0, 0, 0};
    OK(sinter_walls_add_mesh(s.walls, path, 20e-3 / n, rot, o, 0, 0.0, s.wall_mat, NULL));
    unlink(path);
    OK(sinter_walls_set_rotation(s.walls, 0, o, up, omega));
    turntable(&s, got);
    scene_close(&s);
    free(v);
    const double us = omega * 4e-3; /* the surface speed under the sphere at the start */
    double worst_x = 0.0, worst_v = 0.0;
    for (int k = 0; k < SAMPLES; ++k) {
        for (int d = 0; d < 3; ++d)
            worst_x = fmax(worst_x, fabs(got[5 * k + d] - ref[5 * k + d]));
        for (int d = 3; d < 5; ++d)
            worst_v = fmax(worst_v, fabs(got[5 * k + d] - ref[5 * k + d]));
    }
    /* the end point in the mesh's frame: turned back by omega t */
    const double *end = got + 5 * (SAMPLES - 1), back = -omega * 2e-3 * SAMPLES;
    const double xm = cos(back) * end[0] - sin(back) * end[1];
    const double ym = sin(back) * end[0] + cos(back) * end[1];
    const double travel = hypot(xm - 4e-3, ym - 1.5e-3);
    print_message("turning mesh: end (%.9e, %.9e) m, rectangle (%.9e, %.9e) m, travelled %.3e m "
                  "over the mesh; worst |dx| %.2e m, |dv| %.2e m/s\n",
                  end[0], end[1], ref[5 * (SAMPLES - 1)], ref[5 * (SAMPLES - 1) + 1], travel,
                  worst_x, worst_v);
    assert_true(travel > 5e-3); /* over several cells of the mesh */
    assert_true(worst_x < 1e-9 * R);
    assert_true(worst_v < 1e-9 * us);
    for (int d = 0; d < 3; ++d) {
        const double *fr = ref + 5 * SAMPLES, *fg = got + 5 * SAMPLES;
        assert_close(fg[d], fr[d], 1e-6 * fabs(fr[2]));
        assert_close(fg[3 + d], fr[3 + d], 1e-6 * fabs(fr[2]) * 5e-3);
    }
}

typedef struct impulse_watch {
    scene *s;
    double dt, angular; /* the wall's moment about the axis summed over steps times dt [N m s] */
} impulse_watch;

static int watch_moment(const sinter_stepper *st, double t, void *user)
{
    (void)st;
    (void)t;
    impulse_watch *w = user;
    double m[3];
    OK(sinter_walls_get_moment(w->s->walls, 0, m));
    w->angular += m[2] * w->dt;
    return 0;
}

/*
 * A paddle (a 10 mm x 10 mm square of 800 triangles in the plane y = 0, from the axis out
 * to x = 10 mm) turning at omega = 20 rad/s about z strikes a sphere at rest 6 mm from the
 * axis, without friction or damping: the elastic normal contact reverses the relative normal
 * velocity, so the sphere leaves at 2 omega r (r = 6 mm: the contact point's distance from
 * the axis) along the paddle's normal. The paddle turns by omega t_c ~ 4e-3 rad during the
 * ~0.2 ms contact, so the impulse's direction and the contact point's speed shift by that
 * order: the speed is checked to 1 %, its direction to 0.01 rad. The wall's reaction moment
 * about the axis, summed over the steps (dt = 1e-7 s), is minus the sphere's angular momentum
 * about the axis m (x v_y - y v_x) gained (the only force on it is the paddle's; its spin
 * stays zero): to 1e-6 (each step's kick is its force times dt and the moment is summed
 * from the same forces at the same contact points, so only the step rule's remainder at the
 * contact's ends and round-off over ~2000 steps are left; measured ~1e-10).
 */
static void test_paddle_strikes_sphere(void **state)
{
    (void)state;
    const int n = 20;
    double *v = malloc(9 * 2 * (size_t)(n * n) * sizeof(double));
    const size_t nf = grid_square(n, v);
    char path[64];
    write_stl(path, v, nf);
    free(v);
    scene s;
    open_rigid(&s, 0.0, 0.0, 0);
    /* the square turned by -90 degrees about x: (x, y, 0) -> (x, 0, -y), normal +y; its
     * inner edge on the axis */
    const double rot[3] = {-PI / 2, 0, 0}, shift[3] = {5e-3, 0, 0};
    OK(sinter_walls_add_mesh(s.walls, path, 0.5e-3, rot, shift, 0, 0.0, s.wall_mat, NULL));
    unlink(path);
    const double o[3] = {0, 0, 0}, z[3] = {0, 0, 2.5}, omega = 20.0, r0 = 6e-3;
    OK(sinter_walls_set_rotation(s.walls, 0, o, z, omega));
    scene_add(&s, r0, R + 2e-5, 0, R);
    const double dt = 1e-7;
    OK(sinter_stepper_set_dt(s.st, dt));
    impulse_watch w = {&s, dt, 0.0};
    OK(sinter_stepper_set_observer(s.st, watch_moment, &w));
    OK(sinter_stepper_advance(s.st, 1e-3));
    double x[3], u[3], spin[3], f[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    get3(&s, SINTER_FIELD_VELOCITY, 0, u);
    get3(&s, SINTER_FIELD_SPIN, 0, spin);
    OK(sinter_walls_get_force(s.walls, 0, f));
    const double mass = 4.0 / 3.0 * PI * R * R * R * RHO;
    const double speed = hypot(u[0], u[1]), expect = 2.0 * omega * r0;
    const double lz = mass * (x[0] * u[1] - x[1] * u[0]);
    print_message("paddle: sphere leaves at (%.6e, %.6e, %.1e) m/s, %.6e m/s (2 omega r %.6e); "
                  "L_z %.9e N m s, wall's moment impulse %.9e N m s\n",
                  u[0], u[1], u[2], speed, expect, lz, w.angular);
    assert_true(f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0); /* gone: no contact left */
    assert_close(speed, expect, 1e-2 * expect);
    assert_close(atan2(-u[0], u[1]), 0.0, 1e-2); /* along the paddle's normal, near +y */
    assert_close(u[2], 0.0, 1e-12 * expect);
    for (int d = 0; d < 3; ++d)
        assert_close(spin[d], 0.0, 1e-9 * expect / R);
    assert_true(lz > 0.0);
    assert_close(w.angular, -lz, 1e-6 * lz);
    OK(sinter_stepper_set_observer(s.st, NULL, NULL));
    scene_close(&s);
}

/*
 * The turned geometry: a 2 mm square of 8 triangles in z = 0 turned about the x axis through
 * the origin at pi/2 rad/s, at t = 1 s a quarter turn: (x, y, 0) -> (x, 0, y), its normal
 * (0, 0, 1) -> (0, -1, 0). Its drawing has each file vertex so turned, the distance of a point
 * in front of it is its offset along -y with that normal, and the neighbour list's measure of
 * the wall's travel is at least the farthest vertex's arc, sqrt(2) mm pi/2 (all to 1e-15 m:
 * cos(pi/2) is 6e-17, not 0).
 */
static void test_turned_mesh_geometry(void **state)
{
    (void)state;
    double v[72];
    const size_t nf = grid_square(2, v);
    char path[64];
    write_stl(path, v, nf);
    scene s;
    open_rigid(&s, 0.3, 0.3, 0);
    const double o[3] = {0, 0, 0}, ex[3] = {1, 0, 0};
    OK(sinter_walls_add_mesh(s.walls, path, 1e-3, o, o, 0, 0.0, s.wall_mat, NULL));
    unlink(path);
    OK(sinter_walls_set_rotation(s.walls, 0, o, ex, PI / 2));
    const sinter_wall *w = &s.walls->wall[0];
    double ref[4];
    sinter_wall_reference(w, ref);
    OK(sinter_walls_move(s.walls, 1.0));
    double points[72], normals[24];
    assert_int_equal(sinter_wall_mesh_draw(w, points, normals), 8);
    for (size_t k = 0; k < 24; ++k) {
        const double want[3] = {1e-3 * v[3 * k], 0.0, 1e-3 * v[3 * k + 1]};
        for (int d = 0; d < 3; ++d)
            assert_close(points[3 * k + d], want[d], 1e-15);
    }
    for (size_t t = 0; t < 8; ++t)
        for (int d = 0; d < 3; ++d)
            assert_close(normals[3 * t + d], d == 1 ? -1.0 : 0.0, 1e-15);
    const double x[3] = {0.2e-3, -0.4e-3, 0.5e-3};
    double n[3];
    const double dist = sinter_wall_distance(w, x);
    assert_close(dist, 0.4e-3, 1e-15);
    uint32_t hint = UINT32_MAX;
    assert_true(sinter_wall_contact_hinted(w, x, n, &hint) == dist);
    for (int d = 0; d < 3; ++d)
        assert_close(n[d], d == 1 ? -1.0 : 0.0, 1e-15);
    assert_true(sinter_wall_mesh_within(w, x, 0.5e-3, &hint) == 1);
    assert_true(sinter_wall_mesh_within(w, x, 0.3e-3, &hint) == 0);
    assert_true(sinter_wall_moved(w, ref) >= sqrt(2.0) * 1e-3 * PI / 2 * (1 - 1e-15));
    scene_close(&s);
}

/* A turning square mesh (as in test_turning_mesh_as_turning_rectangle) with a sphere dragged
 * on it, at dt = 1e-6 s to 10 ms. */
static void open_turntable(scene *s, const char *stl)
{
    open_rigid(s, 0.5, 0.5, 1);
    const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    OK(sinter_walls_add_mesh(s->walls, stl, 20e-3 / 30, o, o, 0, 0.0, s->wall_mat, NULL));
    OK(sinter_walls_set_rotation(s->walls, 0, o, up, 20.0));
    scene_add(s, 4e-3, 1.5e-3, R - 1e-7, R);
    OK(sinter_stepper_set_dt(s->st, 1e-6));
}

/* A run restarted from a checkpoint at 10 ms of a sphere on a turning mesh continues with
 * the same bits to 20 ms (the angle comes from the time, the neighbour list's reference
 * angle from the checkpoint): position, velocity, spin and the wall's force and moment. */
static void test_turning_mesh_restarts_bit_for_bit(void **state)
{
    (void)state;
    double *v = malloc(9 * 2 * 900 * sizeof(double));
    const size_t nf = grid_square(30, v);
    char stl[64];
    write_stl(stl, v, nf);
    free(v);
    char path[] = "/tmp/sinter_meshrot_ckpt_XXXXXX";
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    scene a, b;
    open_turntable(&a, stl);
    OK(sinter_stepper_advance(a.st, 0.01));
    OK(sinter_checkpoint_write(a.st, path));
    OK(sinter_stepper_advance(a.st, 0.02));
    open_turntable(&b, stl);
    OK(sinter_checkpoint_read(b.st, path));
    OK(sinter_stepper_advance(b.st, 0.02));
    remove(path);
    unlink(stl);
    const sinter_field fields[3] = {SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY,
                                    SINTER_FIELD_SPIN};
    for (int f = 0; f < 3; ++f) {
        double xa[3], xb[3];
        get3(&a, fields[f], 0, xa);
        get3(&b, fields[f], 0, xb);
        assert_memory_equal(xa, xb, sizeof(xa));
    }
    double fa[3], fb[3], ma[3], mb[3];
    OK(sinter_walls_get_force(a.walls, 0, fa));
    OK(sinter_walls_get_force(b.walls, 0, fb));
    assert_memory_equal(fa, fb, sizeof(fa));
    assert_true(fa[2] != 0.0); /* still touching */
    OK(sinter_walls_get_moment(a.walls, 0, ma));
    OK(sinter_walls_get_moment(b.walls, 0, mb));
    assert_memory_equal(ma, mb, sizeof(ma));
    scene_close(&a);
    scene_close(&b);
}

/* Bad input refused, and the wall unchanged: a zero axis, a non-finite point, axis or rate,
 * a wall that is not a mesh, a wall that does not exist, NULL arrays. */
static void test_bad_rotation_refused(void **state)
{
    (void)state;
    double *v = malloc(9 * 2 * 4 * sizeof(double));
    const size_t nf = grid_square(2, v);
    char path[64];
    write_stl(path, v, nf);
    free(v);
    scene s;
    open_rigid(&s, 0.3, 0.3, 0);
    const double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, zero[3] = {0, 0, 0};
    OK(sinter_walls_add_mesh(s.walls, path, 1e-3, o, o, 0, 0.0, s.wall_mat, NULL));
    unlink(path);
    OK(sinter_walls_add_plane(s.walls, o, z, s.wall_mat, NULL));
    const double bad[3] = {0, NAN, 0}, inf[3] = {INFINITY, 0, 0};
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, o, zero, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, bad, z, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, o, inf, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, o, z, NAN), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, o, z, -INFINITY), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 1, o, z, 1.0), SINTER_ERR_INVALID);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 2, o, z, 1.0), SINTER_ERR_RANGE);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, NULL, z, 1.0), SINTER_ERR_NULL);
    assert_int_equal(sinter_walls_set_rotation(s.walls, 0, o, NULL, 1.0), SINTER_ERR_NULL);
    assert_int_equal(sinter_walls_set_rotation(NULL, 0, o, z, 1.0), SINTER_ERR_NULL);
    double axis[3];
    OK(sinter_walls_get_shape(s.walls, 0, axis, NULL, NULL));
    assert_true(axis[0] == 0.0 && axis[1] == 0.0 && axis[2] == 1.0); /* unchanged */
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_turning_mesh_as_turning_rectangle),
        cmocka_unit_test(test_paddle_strikes_sphere),
        cmocka_unit_test(test_turned_mesh_geometry),
        cmocka_unit_test(test_turning_mesh_restarts_bit_for_bit),
        cmocka_unit_test(test_bad_rotation_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
