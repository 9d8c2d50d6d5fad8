/*
 * Wall kinds beyond the infinite plane (rectangles, discs, cylinders), their spin and the
 * force servo, against closed forms and balances (docs/validation.md: walls).
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "scene_support.h"

static const double PI = 3.14159265358979323846;
static const double R = 1e-3, E = 1e7, NU = 0.3, RHO = 2500.0, G = 9.81;
static const double E_WALL = 1e13; /* a rigid wall */

/* Resting overlap of a sphere of weight w on a rigid wall (seed 003 eq. 2, r* = R). */
static double resting_overlap(double w)
{
    const double estar = 1.0 / ((1 - NU * NU) / E + (1 - NU * NU) / E_WALL);
    return pow(3.0 * w / (4.0 * estar * sqrt(R)), 2.0 / 3.0);
}

static void open_rigid(scene *s, double xi, double mu, int gravity)
{
    scene_init(s);
    scene_material(s, E, NU, RHO, xi, mu);
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_YOUNGS_MODULUS, E_WALL));
    scene_open(s, "hertz_mindlin", gravity);
}

/*
 * A sphere at rest at the bottom of a horizontal cylinder (inside) and on a disc: the wall
 * carries its weight (critically damped, 30 periods: e^-100 of the start left, 1e-6 relative
 * as the plane's test), and the overlap is Hertz's with the wall as a plane at the contact
 * (r* = R: the law's treatment of every kind, stated in sinter.h).
 */
static void test_sphere_rests_in_cylinder_and_on_disc(void **state)
{
    (void)state;
    for (int kind = 0; kind < 2; ++kind) {
        scene s;
        open_rigid(&s, 1.0, 0.3, 1);
        const double rc = 5.0 * R, origin[3] = {0, 0, 0};
        if (kind == 0) {
            const double axis[3] = {1, 0, 0};
            OK(sinter_walls_add_cylinder(s.walls, origin, axis, rc, HUGE_VAL, 1, s.wall_mat, NULL));
            scene_add(&s, 0, 0, -(rc - R) + 1e-6, R);
        } else {
            const double up[3] = {0, 0, 1};
            OK(sinter_walls_add_disc(s.walls, origin, up, 2.0 * R, s.wall_mat, NULL));
            scene_add(&s, 0.5 * R, 0, R + 1e-6, R);
        }
        OK(sinter_stepper_set_dt(s.st, 1e-6));
        OK(sinter_stepper_advance(s.st, 0.03));
        const double m = get1(&s, SINTER_FIELD_MASS, 0), w = m * G;
        double f[3], x[3];
        OK(sinter_walls_get_force(s.walls, 0, f));
        get3(&s, SINTER_FIELD_POSITION, 0, x);
        const double delta = resting_overlap(w);
        const double got = kind == 0 ? -(x[2] + rc - R) : R - x[2];
        print_message("%s: wall force %.10e N (weight %.10e N), overlap %.6e m (Hertz %.6e m)\n",
                      kind == 0 ? "cylinder" : "disc", -f[2], w, got, delta);
        assert_close(-f[2], w, 1e-6 * w);
        assert_close(f[0], 0.0, 1e-9 * w);
        assert_close(f[1], 0.0, 1e-9 * w);
        assert_close(got, delta, 1e-6 * delta);
        scene_close(&s);
    }
}

/*
 * Beyond a finite plane's edge: a sphere whose centre is more than its radius beyond a
 * rectangle's edge falls freely past it (z = z0 - g t^2 / 2, no force on the wall); one that
 * overhangs the edge touches the edge, along the line from the edge to its centre, with the
 * overlap R - distance (the force's direction at 45 degrees to round-off); so does one beyond
 * a finite cylinder's end with its rim circle.
 */
static void test_beyond_the_edge(void **state)
{
    (void)state;
    scene s;
    open_rigid(&s, 0.5, 0.3, 1);
    const double c[3] = {0, 0, 0}, up[3] = {0, 0, 1}, ex[3] = {1, 0, 0}, a = 2.0 * R;
    OK(sinter_walls_add_rectangle(s.walls, c, up, ex, a, a, s.wall_mat, NULL));
    const double z0 = 0.5 * R;
    scene_add(&s, a + 1.001 * R, 0, z0, R);  /* beyond the edge in x */
    scene_add(&s, 0, -a - 1.001 * R, z0, R); /* beyond the edge in y */
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    const double t = 2e-3;
    OK(sinter_stepper_advance(s.st, t));
    double x0[3], x1[3], f[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x0);
    get3(&s, SINTER_FIELD_POSITION, 1, x1);
    OK(sinter_walls_get_force(s.walls, 0, f));
    const double z = z0 - 0.5 * G * t * t;
    assert_close(x0[2], z, 1e-12);
    assert_close(x1[2], z, 1e-12);
    assert_true(f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0);
    scene_close(&s);

    /* the edge contact, without gravity: one evaluation */
    open_rigid(&s, 0.0, 0.3, 0);
    OK(sinter_walls_add_rectangle(s.walls, c, up, ex, a, a, s.wall_mat, NULL));
    const double off = 0.6 * R; /* beyond the edge and above the plane: distance 0.849 R */
    scene_add(&s, a + off, 0, off, R);
    OK(sinter_stepper_evaluate(s.st));
    double fp[3];
    get3(&s, SINTER_FIELD_FORCE, 0, fp);
    const double overlap = R - sqrt(2.0) * off;
    const double estar = 1.0 / ((1 - NU * NU) / E + (1 - NU * NU) / E_WALL);
    const double fn = 4.0 / 3.0 * estar * sqrt(R * overlap) * overlap;
    print_message("edge contact: force (%.6e, %.6e, %.6e) N, Hertz %.6e N at 45 degrees\n", fp[0],
                  fp[1], fp[2], fn);
    assert_close(fp[0], fn / sqrt(2.0), 1e-12 * fn);
    assert_close(fp[2], fn / sqrt(2.0), 1e-12 * fn);
    assert_close(fp[1], 0.0, 1e-15);
    scene_close(&s);

    /* a finite cylinder's rim: inside a die of radius 5 R and half length 2 R along z, a sphere
     * 0.6 R inside the wall and 0.6 R beyond the end meets the rim circle at 45 degrees */
    open_rigid(&s, 0.0, 0.3, 0);
    const double axis[3] = {0, 0, 1};
    OK(sinter_walls_add_cylinder(s.walls, c, axis, 5 * R, 2 * R, 1, s.wall_mat, NULL));
    scene_add(&s, 5 * R - off, 0, 2 * R + off, R);
    OK(sinter_stepper_evaluate(s.st));
    get3(&s, SINTER_FIELD_FORCE, 0, fp);
    print_message("rim contact: force (%.6e, %.6e, %.6e) N\n", fp[0], fp[1], fp[2]);
    assert_close(fp[0], -fn / sqrt(2.0), 1e-12 * fn); /* towards the axis */
    assert_close(fp[2], fn / sqrt(2.0), 1e-12 * fn);  /* out of the end */
    assert_close(fp[1], 0.0, 1e-15);
    scene_close(&s);
}

/* The slip velocity of particle 0 at its contact with wall 0 (normal nw from the wall towards
 * the centre), relative to the wall's surface velocity u_s there: v + w x (-R nw) - u_s. */
static double slip(scene *s, const double nw[3], const double us[3])
{
    double v[3], w[3];
    get3(s, SINTER_FIELD_VELOCITY, 0, v);
    get3(s, SINTER_FIELD_SPIN, 0, w);
    const double b[3] = {-R * nw[0], -R * nw[1], -R * nw[2]};
    const double wb[3] = {w[1] * b[2] - w[2] * b[1], w[2] * b[0] - w[0] * b[2],
                          w[0] * b[1] - w[1] * b[0]};
    double s2 = 0.0;
    for (int d = 0; d < 3; ++d)
        s2 += (v[d] + wb[d] - us[d]) * (v[d] + wb[d] - us[d]);
    return sqrt(s2);
}

/*
 * A spinning wall's surface velocity enters the friction law. (a) A sphere inside a vertical
 * cylinder spinning at omega, without gravity, launched along the wall at half the surface
 * speed: the centrifugal push gives friction, which drives the sphere until it rolls on the
 * moving surface without slip: the slip velocity at the contact falls below 1 % of the
 * surface speed omega R_c (the tangential spring's ringing leaves ~0.1 %; against a wall
 * taken at rest the slip would stay of the order of the surface speed). (b) A
 * sphere at rest on a disc turning at omega (a turntable): it is dragged into rolling
 * without slip, after which its velocity turns at 2/7 omega (the rolling ball on a turntable:
 * m dv/dt = f, I dw/dt = b x f and the no-slip constraint give dv/dt = 2/7 omega z x v), to
 * 1 %.
 */
static void test_spinning_walls_drive_by_friction(void **state)
{
    (void)state;
    const double omega = 100.0, rc = 5.0 * R;
    scene s;
    open_rigid(&s, 0.5, 0.3, 0);
    const double origin[3] = {0, 0, 0}, axis[3] = {0, 0, 1};
    OK(sinter_walls_add_cylinder(s.walls, origin, axis, rc, HUGE_VAL, 1, s.wall_mat, NULL));
    OK(sinter_walls_set_spin(s.walls, 0, omega));
    scene_add(&s, rc - R, 0, 0, R);
    const double v0[3] = {0, 0.5 * omega * rc, 0};
    set3(&s, SINTER_FIELD_VELOCITY, 0, v0);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    OK(sinter_stepper_advance(s.st, 0.05));
    double x[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    const double rho = sqrt(x[0] * x[0] + x[1] * x[1]);
    const double nw[3] = {-x[0] / rho, -x[1] / rho, 0.0}; /* inside: towards the axis */
    const double us[3] = {-omega * rc * x[1] / rho, omega * rc * x[0] / rho, 0.0};
    const double sl = slip(&s, nw, us);
    print_message("cylinder: slip %.3e m/s against the surface speed %.3f m/s\n", sl, omega * rc);
    assert_true(sl < 1e-2 * omega * rc);
    scene_close(&s);

    /* (b) the turntable */
    open_rigid(&s, 1.0, 0.5, 1);
    OK(sinter_material_set(s.mat, SINTER_MAT_FRICTION_DAMPING_RATIO, 1.0));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_FRICTION_DAMPING_RATIO, 1.0));
    const double up[3] = {0, 0, 1}, spin = 20.0;
    OK(sinter_walls_add_disc(s.walls, origin, up, 0.5, s.wall_mat, NULL));
    OK(sinter_walls_set_spin(s.walls, 0, spin));
    scene_add(&s, 0.01, 0, R - resting_overlap(4.0 / 3.0 * PI * R * R * R * RHO * G), R);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    OK(sinter_stepper_advance(s.st, 0.03)); /* dragged into rolling (~12 ms at mu g) */
    double va[3], vb[3], xa[3];
    get3(&s, SINTER_FIELD_VELOCITY, 0, va);
    get3(&s, SINTER_FIELD_POSITION, 0, xa);
    const double surface[3] = {-spin * xa[1], spin * xa[0], 0.0}, n_up[3] = {0, 0, 1};
    const double sl_disc = slip(&s, n_up, surface);
    const double t_turn = 0.1;
    OK(sinter_stepper_advance(s.st, 0.03 + t_turn));
    get3(&s, SINTER_FIELD_VELOCITY, 0, vb);
    const double turned = atan2(va[0] * vb[1] - va[1] * vb[0], va[0] * vb[0] + va[1] * vb[1]);
    print_message("turntable: slip %.3e m/s (surface %.3f m/s); velocity turned %.5f rad, 2/7 "
                  "omega t = %.5f rad\n",
                  sl_disc, spin * 0.01, turned, 2.0 / 7.0 * spin * t_turn);
    assert_true(sl_disc < 1e-2 * spin * 0.01);
    assert_close(turned, 2.0 / 7.0 * spin * t_turn, 0.01 * 2.0 / 7.0 * spin * t_turn);
    scene_close(&s);
}

/*
 * The planes' motions move the other kinds: a disc floor rising at a constant 10 mm/s carries
 * a sphere resting on it (in the floor's frame the same rest: after 0.2 s, 2 mm and twenty
 * neighbour-list skins, the overlap is Hertz's under the weight and the force the weight, to
 * 1e-6 as at rest), and a rectangle spinning at 5 pi rad/s has turned its edge by three
 * quarters of a turn about its normal at 0.3 s (to round-off).
 */
static void test_kinds_move_and_turn(void **state)
{
    (void)state;
    scene s;
    open_rigid(&s, 1.0, 0.3, 1);
    const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
    OK(sinter_walls_add_disc(s.walls, o, up, 2 * R, s.wall_mat, NULL));
    const double far[3] = {0, 0, -0.1};
    OK(sinter_walls_add_rectangle(s.walls, far, up, ex, R, 2 * R, s.wall_mat, NULL));
    const double u[3] = {0, 0, 0.01};
    OK(sinter_walls_set_velocity(s.walls, 0, u));
    OK(sinter_walls_set_spin(s.walls, 1, 5.0 * PI));
    const double w = 4.0 / 3.0 * PI * R * R * R * RHO * G, delta = resting_overlap(w);
    scene_add(&s, 0, 0, R - delta, R);
    OK(sinter_stepper_set_dt(s.st, 1e-6));
    OK(sinter_stepper_set_skin(s.st, 1e-4));
    OK(sinter_stepper_advance(s.st, 0.2));
    double x[3], f[3], edge[3];
    get3(&s, SINTER_FIELD_POSITION, 0, x);
    OK(sinter_walls_get_force(s.walls, 0, f));
    print_message("rising disc: overlap %.9e m (Hertz %.9e m), force %.9e N (weight %.9e N)\n",
                  0.002 + R - x[2], delta, -f[2], w);
    assert_close(0.002 + R - x[2], delta, 1e-6 * delta);
    assert_close(-f[2], w, 1e-6 * w);
    OK(sinter_stepper_advance(s.st, 0.3)); /* the spin from t = 0: 1.5 pi rad at 0.3 s */
    OK(sinter_walls_get_shape(s.walls, 1, NULL, edge, NULL));
    assert_close(edge[0], 0.0, 1e-12); /* (1, 0, 0) turned by 3/4 of a turn about z */
    assert_close(edge[1], -1.0, 1e-12);
    assert_close(edge[2], 0.0, 1e-12);
    scene_close(&s);
}

/*
 * Force and moment balance: spheres touching one wall only (no pair contacts), moving and
 * spinning, with rolling resistance: the wall's reaction equals minus the sum of the forces
 * on the particles, and its moment about its point p minus the sum of (x_i - p) x F_i + T_i
 * (each contact's moment about p is the particle's force's moment plus the torque it got
 * about its centre), to round-off; for a rectangle (face and edge contacts), a cylinder and a
 * disc, each spinning, and a plane (its moment asked for: sinter_walls_set_moment).
 */
static void test_force_and_moment_balance(void **state)
{
    (void)state;
    for (int kind = 0; kind < 4; ++kind) {
        scene s;
        open_rigid(&s, 0.3, 0.4, 0);
        OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
        OK(sinter_material_set(s.wall_mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
        OK(sinter_material_set(s.wall_mat, SINTER_MAT_YOUNGS_MODULUS, E));
        const double p[3] = {1e-4, -2e-4, 3e-4}, up[3] = {0, 0, 1}, ex[3] = {1, 1, 0};
        const double tilt[3] = {0.1, 0.2, 1.0};
        if (kind == 0)
            OK(sinter_walls_add_rectangle(s.walls, p, up, ex, 3 * R, 2 * R, s.wall_mat, NULL));
        else if (kind == 1)
            OK(sinter_walls_add_cylinder(s.walls, p, tilt, 6 * R, 20 * R, 1, s.wall_mat, NULL));
        else if (kind == 2)
            OK(sinter_walls_add_disc(s.walls, p, tilt, 4 * R, s.wall_mat, NULL));
        else /* a plane: its moment asked for (off by default) */
            OK(sinter_walls_add_plane(s.walls, p, tilt, s.wall_mat, NULL));
        if (kind == 3)
            OK(sinter_walls_set_moment(s.walls, 0, 1));
        double a[3], e1[3], e2[3];
        OK(sinter_walls_get_shape(s.walls, 0, a, e1, NULL));
        e2[0] = a[1] * e1[2] - a[2] * e1[1];
        e2[1] = a[2] * e1[0] - a[0] * e1[2];
        e2[2] = a[0] * e1[1] - a[1] * e1[0];
        /* (along e1, along e2, along a) of each centre: planar kinds three on the face at
         * 0.5 % to 1 % overlap and one 0.7 R beyond an edge and above the face (distance
         * 0.99 R); the cylinder four at 0.2 % to 0.5 % overlap around and along it */
        const double planar[4][3] = {
            {0, 0, 0.995 * R},
            {R, -R, 0.99 * R},
            {(kind == 0 ? 3.7 : 4.7) * R, 0, (kind == 3 ? 0.996 : 0.7) * R},
            {-R, 0.5 * R, 0.993 * R}};
        const double c = cos(1.0), sn = sin(1.0);
        const double tube[4][3] = {{5.002 * R, 0, 0},
                                   {-5.003 * R, 0, 3 * R},
                                   {5.005 * R * c, 5.005 * R * sn, -4 * R},
                                   {0, -5.004 * R, 8 * R}};
        double x[4][3];
        for (int i = 0; i < 4; ++i)
            for (int d = 0; d < 3; ++d) {
                const double *o = kind == 1 ? tube[i] : planar[i];
                x[i][d] = p[d] + o[0] * e1[d] + o[1] * e2[d] + o[2] * a[d];
            }
        if (kind < 3)
            OK(sinter_walls_set_spin(s.walls, 0, 30.0));
        const double vel[3] = {0.01, -0.02, 0.0};
        for (int i = 0; i < 4; ++i) {
            scene_add(&s, x[i][0], x[i][1], x[i][2], R);
            const double w[3] = {10.0 * i, -5.0, 3.0};
            set3(&s, SINTER_FIELD_SPIN, (size_t)i, w);
            set3(&s, SINTER_FIELD_VELOCITY, (size_t)i, vel);
        }
        OK(sinter_stepper_set_dt(s.st, 1e-7));
        OK(sinter_stepper_advance(s.st, 2e-6)); /* tangential springs loaded */
        OK(sinter_stepper_evaluate(s.st));
        double f[3], m[3], sum_f[3] = {0, 0, 0}, sum_m[3] = {0, 0, 0}, fmax = 0.0, mmax = 0.0;
        OK(sinter_walls_get_force(s.walls, 0, f));
        OK(sinter_walls_get_moment(s.walls, 0, m));
        double wp[3];
        OK(sinter_walls_get_state(s.walls, 0, wp, NULL));
        sinter_stepper_stats stats;
        memset(&stats, 0, sizeof(stats));
        stats.struct_size = sizeof(stats);
        OK(sinter_stepper_get_stats(s.st, &stats));
        for (size_t i = 0; i < 4; ++i) {
            double fi[3], ti[3], xi[3];
            get3(&s, SINTER_FIELD_FORCE, i, fi);
            get3(&s, SINTER_FIELD_TORQUE, i, ti);
            get3(&s, SINTER_FIELD_POSITION, i, xi);
            const double r[3] = {xi[0] - wp[0], xi[1] - wp[1], xi[2] - wp[2]};
            const double rf[3] = {r[1] * fi[2] - r[2] * fi[1], r[2] * fi[0] - r[0] * fi[2],
                                  r[0] * fi[1] - r[1] * fi[0]};
            for (int d = 0; d < 3; ++d) {
                sum_f[d] += fi[d];
                sum_m[d] += rf[d] + ti[d];
                fmax = fmax > fabs(fi[d]) ? fmax : fabs(fi[d]);
                mmax = fmax * 10 * R;
            }
        }
        print_message("kind %d: %llu contacts; reaction (%.6e, %.6e, %.6e) N, moment (%.6e, "
                      "%.6e, %.6e) N m\n",
                      kind, (unsigned long long)stats.wall_contacts, f[0], f[1], f[2], m[0], m[1],
                      m[2]);
        assert_int_equal(stats.wall_contacts, 4);
        for (int d = 0; d < 3; ++d) {
            assert_close(f[d], -sum_f[d], 1e-12 * fmax);
            assert_close(m[d], -sum_m[d], 1e-12 * mmax);
        }
        assert_true(fmax > 0.0);
        scene_close(&s);
    }
}

/* A triangulated rectangle [-2R, 4R] x [-3R, 2R] at height z, its normal up, as an ASCII STL
 * file at a temporary path (64 chars); its diagonal passes the origin's foot at y = -4R/3. */
static void write_square_stl(char *path, double z)
{
    snprintf(path, 64, "/tmp/sinter_kindsXXXXXX");
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    const double c[4][2] = {{-2 * R, -3 * R}, {4 * R, -3 * R}, {4 * R, 2 * R}, {-2 * R, 2 * R}};
    const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    fprintf(f, "solid square\n");
    for (int t = 0; t < 2; ++t) {
        fprintf(f, " facet normal 0 0 1\n  outer loop\n");
        for (int v = 0; v < 3; ++v)
            fprintf(f, "   vertex %.17g %.17g %.17g\n", c[tri[t][v]][0], c[tri[t][v]][1], z);
        fprintf(f, "  endloop\n endfacet\n");
    }
    fprintf(f, "endsolid square\n");
    fclose(f);
}

static const double PL_KW = 1e7; /* power_law's wall compliance constant K_w [Pa] */

/* One evaluation of a sphere between a wall of `kind` below it (its closest point straight
 * below the centre, 0.99 R away) and a plane above (0.99 R away), with Hertz-Mindlin with
 * rolling (or the power-law contact: `model`), conduction (walls at 400 K and 500 K, the sphere
 * at 300 K), the electric network (the lower wall at 1 V, the upper at 0 V) and Joule heating:
 * the sphere's force, heat power and current into out (7 values). */

static void between_walls(int kind, const char *model, double out[7])
{
    scene s;
    scene_init(&s);
    scene_material(&s, E, NU, RHO, 0.3, 0.4);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s.mat, SINTER_MAT_WALL_STIFFNESS, PL_KW)); /* power_law's eq. 13 */
    OK(sinter_material_set(s.mat, SINTER_MAT_WALL_EXPONENT, 1.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_THERMAL_CONDUCTIVITY, 60.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_HEAT_CAPACITY, 100.0));
    OK(sinter_material_set(s.mat, SINTER_MAT_ELECTRIC_CONDUCTIVITY, 1e6));
    sinter_material_destroy(s.wall_mat);
    OK(sinter_material_clone(&s.wall_mat, s.mat));
    scene_open(&s, model, 0);
    const double below[3] = {0, 0, -0.99 * R}, up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
    if (kind == SINTER_WALL_PLANE)
        OK(sinter_walls_add_plane(s.walls, below, up, s.wall_mat, NULL));
    else if (kind == SINTER_WALL_RECTANGLE)
        OK(sinter_walls_add_rectangle(s.walls, below, up, ex, 3 * R, 2 * R, s.wall_mat, NULL));
    else if (kind == SINTER_WALL_DISC)
        OK(sinter_walls_add_disc(s.walls, below, up, 3 * R, s.wall_mat, NULL));
    else if (kind == SINTER_WALL_MESH) {
        char path[64];
        const double o[3] = {0, 0, 0};
        write_square_stl(path, below[2]);
        OK(sinter_walls_add_mesh(s.walls, path, 1.0, o, o, 0, 0.0, s.wall_mat, NULL));
        unlink(path);
    } else {
        const double axis_point[3] = {0, 0, 4.01 * R};
        OK(sinter_walls_add_cylinder(s.walls, axis_point, ex, 5 * R, HUGE_VAL, 1, s.wall_mat,
                                     NULL));
    }
    const double above[3] = {0, 0, 0.99 * R}, down[3] = {0, 0, -1};
    OK(sinter_walls_add_plane(s.walls, above, down, s.wall_mat, NULL));
    OK(sinter_walls_set_temperature(s.walls, 0, 400.0));
    OK(sinter_walls_set_temperature(s.walls, 1, 500.0));
    OK(sinter_walls_set_electric(s.walls, 0, SINTER_WALL_POTENTIAL, 1.0));
    OK(sinter_walls_set_electric(s.walls, 1, SINTER_WALL_POTENTIAL, 0.0));
    scene_add(&s, 0, 0, 0, R);
    const double v[3] = {0.02, 0.0, 0.0}, w[3] = {5.0, -3.0, 1.0}; /* along the axis */
    set3(&s, SINTER_FIELD_VELOCITY, 0, v);
    set3(&s, SINTER_FIELD_SPIN, 0, w);
    double *theta = NULL;
    OK(sinter_particles_view(s.ps, SINTER_FIELD_TEMPERATURE, (void **)&theta, NULL, NULL));
    theta[0] = 300.0;
    OK(sinter_particles_release(s.ps, SINTER_FIELD_TEMPERATURE));
    sinter_heat_model *cond = NULL, *joule = NULL;
    sinter_electric_model *net = NULL;
    OK(sinter_heat_model_create(&cond, s.ctx, "conduction"));
    OK(sinter_heat_model_create(&joule, s.ctx, "joule"));
    OK(sinter_electric_model_create(&net, s.ctx, "network"));
    OK(sinter_stepper_add_heat(s.st, cond));
    OK(sinter_stepper_add_heat(s.st, joule));
    OK(sinter_stepper_set_electric(s.st, net));
    OK(sinter_stepper_set_dt(s.st, 1e-7));
    OK(sinter_stepper_step(s.st, 3)); /* the tangential and rolling springs loaded */
    OK(sinter_stepper_evaluate(s.st));
    get3(&s, SINTER_FIELD_FORCE, 0, out);
    get3(&s, SINTER_FIELD_TORQUE, 0, out + 3);
    out[6] = get1(&s, SINTER_FIELD_HEAT, 0);
    const double current = get1(&s, SINTER_FIELD_CURRENT, 0);
    print_message("%s, kind %d: force (%.9e, %.9e, %.9e) N, heat %.9e W, current %.9e A\n", model,
                  kind, out[0], out[1], out[2], out[6], current);
    assert_true(current > 0.0 && out[6] != 0.0 && out[0] != 0.0);
    sinter_stepper_destroy(s.st);
    s.st = NULL;
    sinter_heat_model_destroy(cond);
    sinter_heat_model_destroy(joule);
    sinter_electric_model_destroy(net);
    scene_close(&s);
}

/*
 * Every submodel that meets walls reads a wall contact's geometry (overlap, distance, normal,
 * area) from the contact list, which every kind fills the same way: a sphere whose closest
 * wall point lies at the same distance and direction gets the same force and torque
 * (Hertz-Mindlin with friction history and rolling resistance; the power-law contact's wall
 * law, seed 000 eq. 13-17, with its continuous sliding friction), heat power (conduction from
 * both walls, Joule heating of the network's current) from a rectangle's face, a disc's face
 * a cylinder's inside and a triangle mesh's face as from a plane, to round-off (1e-12 of the
 * normal force, whose two walls' parts cancel: the distances come out of different
 * arithmetic, R_c - rho against a dot product; for the power law on the cylinder 1e-9: its
 * contact area pi (R^2 - s^2) at s = 0.99 R magnifies the distance's round-off a hundredfold,
 * and its friction's lateral part came out 1.8e-10 of the normal force from the plane's,
 * more than that alone explains: measured, not derived). The sphere moves along the cylinder's axis
 * only, so that its curvature does not turn the contact within the three steps.
 */
static void test_submodels_alike_on_every_kind(void **state)
{
    (void)state;
    static const char *const models[] = {"hertz_mindlin", "power_law"};
    for (int m = 0; m < 2; ++m) {
        double plane[7];
        between_walls(SINTER_WALL_PLANE, models[m], plane);
        const int kinds[] = {SINTER_WALL_RECTANGLE, SINTER_WALL_DISC, SINTER_WALL_CYLINDER,
                             SINTER_WALL_MESH};
        /* the scale: each wall's normal force (they cancel in the sum): Hertz at 0.01 R, or
         * eq. 13's K_w (delta / R) A with A = pi (R^2 - s^2) at s = 0.99 R */
        const double estar = E / (2.0 * (1.0 - NU * NU)), delta = 0.01 * R;
        const double fn = m == 0 ? 4.0 / 3.0 * estar * sqrt(R * delta) * delta
                                 : PL_KW * 0.01 * PI * (1.0 - 0.99 * 0.99) * R * R;
        for (size_t k = 0; k < sizeof(kinds) / sizeof(kinds[0]); ++k) {
            const int kind = kinds[k];
            const double tol = m == 1 && kind == SINTER_WALL_CYLINDER ? 1e-9 : 1e-12;
            double got[7];
            between_walls(kind, models[m], got);
            for (int d = 0; d < 3; ++d) {
                assert_close(got[d], plane[d], tol * fn);
                assert_close(got[3 + d], plane[3 + d], tol * fn * R);
            }
            assert_close(got[6], plane[6], 1e-12 * fabs(plane[6]));
        }
    }
}

/* A packed, jittered lattice of 15^3 spheres (r = 0.5 mm) on a spinning disc floor in a box of
 * four planes whose moments are summed (over a thousand wall contacts: the threaded wall
 * path), on `threads` threads for 30 steps: positions, then each wall's force and moment, into
 * out (3 n + 30). */
static void packed_box(int threads, double *out)
{
    enum { M = 15, N = M * M * M };
    scene s;
    scene_init(&s);
    OK(sinter_ctx_set_threads(s.ctx, threads));
    scene_material(&s, 1e7, 0.3, 2500, 0.2, 0.3);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    scene_open(&s, "hertz_mindlin", 1);
    const double r = 0.5e-3, a = 2 * r * 0.999, side = M * a;
    const double centre[3] = {0.5 * side, 0.5 * side, 0}, up[3] = {0, 0, 1};
    OK(sinter_walls_add_disc(s.walls, centre, up, side, s.wall_mat, NULL));
    OK(sinter_walls_set_spin(s.walls, 0, 5.0));
    const double wp[4][3] = {{0, 0, 0}, {side, 0, 0}, {0, 0, 0}, {0, side, 0}};
    const double wn[4][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (size_t k = 0; k < 4; ++k) {
        OK(sinter_walls_add_plane(s.walls, wp[k], wn[k], s.wall_mat, NULL));
        OK(sinter_walls_set_moment(s.walls, k + 1, 1));
    }
    uint64_t seed = 5;
    for (int k = 0; k < M; ++k)
        for (int j = 0; j < M; ++j)
            for (int i = 0; i < M; ++i) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                const double dx = 1e-6 * (double)(seed >> 11) / 9007199254740992.0;
                scene_add(&s, (i + 0.5) * a + dx, (j + 0.5) * a, (k + 0.5) * a, r);
            }
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    OK(sinter_stepper_step(s.st, 30));
    sinter_stepper_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_get_stats(s.st, &stats));
    assert_true(stats.wall_contacts > 1024);
    const double *x = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    memcpy(out, x, 3 * N * sizeof(double));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    for (size_t k = 0; k < 5; ++k) {
        OK(sinter_walls_get_force(s.walls, k, out + 3 * N + 6 * k));
        OK(sinter_walls_get_moment(s.walls, k, out + 3 * N + 6 * k + 3));
    }
    scene_close(&s);
}

/* The walls' moments are summed in a fixed order, as their forces: a packed box with a spinning
 * disc floor gives the same bits on one and on two threads, positions, forces and moments. */
static void test_moments_independent_of_threads(void **state)
{
    (void)state;
    enum { N = 15 * 15 * 15 };
    double *one = malloc((3 * N + 30) * sizeof(double)),
           *two = malloc((3 * N + 30) * sizeof(double));
    assert_non_null(one);
    assert_non_null(two);
    packed_box(1, one);
    packed_box(2, two);
    assert_memory_equal(one, two, (3 * N + 30) * sizeof(double));
    double m = 0.0;
    for (int k = 0; k < 30; ++k)
        m = fmax(m, fabs(one[3 * N + k]));
    assert_true(m > 0.0);
    free(one);
    free(two);
}

typedef struct servo_watch {
    scene *s;
    double target, peak;
} servo_watch;

static int watch_servo(const sinter_stepper *st, double t, void *user)
{
    (void)st;
    (void)t;
    servo_watch *w = user;
    double pushed = 0.0;
    OK(sinter_walls_get_servo(w->s->walls, 1, NULL, &pushed, NULL));
    w->peak = pushed > w->peak ? pushed : w->peak;
    return 0;
}

/* A packed column: 6 spheres stacked in a die (a cylinder of radius 1.05 R) on a disc floor,
 * a disc punch 10 um above the top sphere driven by a servo to `target` N. */
static void open_column(scene *s, double target, double kp, double ki, double vmax)
{
    open_rigid(s, 0.7, 0.3, 1);
    const double origin[3] = {0, 0, 0}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
    OK(sinter_walls_add_disc(s->walls, origin, up, 2 * R, s->wall_mat, NULL));
    const int n = 6;
    const double top[3] = {0, 0, 2 * R * n + 1e-5};
    OK(sinter_walls_add_disc(s->walls, top, down, 2 * R, s->wall_mat, NULL));
    OK(sinter_walls_add_cylinder(s->walls, origin, up, 1.05 * R, HUGE_VAL, 1, s->wall_mat, NULL));
    for (int i = 0; i < n; ++i)
        scene_add(s, 0.01 * R * (i % 2), 0, R + 2 * R * i, R);
    const double times[2] = {0.0, 1.0}, forces[2] = {target, target};
    OK(sinter_walls_set_servo(s->walls, 1, 2, times, forces, kp, ki, vmax));
    OK(sinter_stepper_set_dt(s->st, 1e-6));
}

/*
 * The force servo on a packed column reaches its target: from 10 um above the column, the
 * punch (vmax 10 mm/s, kp = 2 vmax / F: at its limit until half the force) presses until the
 * force on it is the target to 1e-3 after 60 ms (the loop's time constant 1 / (kp K) with
 * the column's stiffness K ~ 200 N/m is ~5 ms: 60 ms is twelve of them), and the force never
 * exceeds the target by more than 5 % on the way (its overshoot: the column's own vibration,
 * damped at 0.7 of critical, rides on a first-order approach).
 */
static void test_servo_reaches_target(void **state)
{
    (void)state;
    const double target = 0.02, vmax = 0.01;
    scene s;
    open_column(&s, target, 2.0 * vmax / target, 0.0, vmax);
    servo_watch w = {&s, target, 0.0};
    OK(sinter_stepper_set_observer(s.st, watch_servo, &w));
    OK(sinter_stepper_advance(s.st, 0.06));
    double got = 0.0, v = 0.0, tgt = 0.0;
    OK(sinter_walls_get_servo(s.walls, 1, &tgt, &got, &v));
    double floor_f[3];
    OK(sinter_walls_get_force(s.walls, 0, floor_f));
    print_message("servo: force %.6e N (target %.6e N), peak %.6e N, velocity %.3e m/s, floor "
                  "%.6e N\n",
                  got, tgt, w.peak, v, -floor_f[2]);
    assert_close(tgt, target, 0.0);
    assert_close(got, target, 1e-3 * target);
    assert_true(w.peak <= 1.05 * target);
    assert_true(w.peak > 0.9 * target);
    scene_close(&s);
}

/* A servo's state goes through a checkpoint: a run continued from one is the same to the bit
 * as the run that went on. */
static void test_servo_restarts_bit_for_bit(void **state)
{
    (void)state;
    const double target = 0.02, vmax = 0.01;
    char path[] = "/tmp/sinter_servo_XXXXXX";
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    scene a, b;
    open_column(&a, target, vmax / target, 0.5 * vmax / target, vmax);
    OK(sinter_walls_set_spin(a.walls, 2, 3.0));
    OK(sinter_stepper_advance(a.st, 0.004));
    OK(sinter_checkpoint_write(a.st, path));
    OK(sinter_stepper_advance(a.st, 0.008));
    open_column(&b, target, vmax / target, 0.5 * vmax / target, vmax);
    OK(sinter_walls_set_spin(b.walls, 2, 3.0));
    OK(sinter_checkpoint_read(b.st, path));
    OK(sinter_stepper_advance(b.st, 0.008));
    remove(path);
    for (size_t i = 0; i < 6; ++i) {
        double xa[3], xb[3];
        get3(&a, SINTER_FIELD_POSITION, i, xa);
        get3(&b, SINTER_FIELD_POSITION, i, xb);
        assert_memory_equal(xa, xb, sizeof(xa));
    }
    double pa[3], pb[3], ma[3], mb[3];
    OK(sinter_walls_get_state(a.walls, 1, pa, NULL));
    OK(sinter_walls_get_state(b.walls, 1, pb, NULL));
    assert_memory_equal(pa, pb, sizeof(pa));
    OK(sinter_walls_get_moment(a.walls, 2, ma));
    OK(sinter_walls_get_moment(b.walls, 2, mb));
    assert_memory_equal(ma, mb, sizeof(ma));
    scene_close(&a);
    scene_close(&b);
}

/* Bad input: each refused with SINTER_ERR_INVALID and a message naming the problem. */
static void test_bad_wall_input(void **state)
{
    (void)state;
    scene s;
    open_rigid(&s, 0.5, 0.3, 0);
    const double o[3] = {0, 0, 0}, z[3] = {0, 0, 1}, zero[3] = {0, 0, 0};
    const double nan3[3] = {NAN, 0, 0};
    sinter_walls *w = s.walls;
    const char *msg = NULL;
#define REFUSED(call, fragment)                                                                    \
    do {                                                                                           \
        assert_int_equal((call), SINTER_ERR_INVALID);                                              \
        msg = sinter_last_error(s.ctx);                                                            \
        if (strstr(msg, fragment) == NULL)                                                         \
            fail_msg("'%s' lacks '%s'", msg, fragment);                                            \
    } while (0)
    REFUSED(sinter_walls_add_cylinder(w, o, z, 0.0, 1.0, 1, s.wall_mat, NULL), "radius 0 m");
    REFUSED(sinter_walls_add_cylinder(w, o, zero, 1.0, 1.0, 1, s.wall_mat, NULL), "zero vector");
    REFUSED(sinter_walls_add_cylinder(w, nan3, z, 1.0, 1.0, 1, s.wall_mat, NULL), "finite");
    REFUSED(sinter_walls_add_cylinder(w, o, z, NAN, 1.0, 1, s.wall_mat, NULL), "radius");
    REFUSED(sinter_walls_add_cylinder(w, o, z, 1.0, 0.0, 1, s.wall_mat, NULL), "half length");
    REFUSED(sinter_walls_add_cylinder(w, o, z, 1.0, 1.0, 2, s.wall_mat, NULL), "inside");
    REFUSED(sinter_walls_add_disc(w, o, z, -1.0, s.wall_mat, NULL), "radius -1 m");
    REFUSED(sinter_walls_add_disc(w, o, zero, 1.0, s.wall_mat, NULL), "zero vector");
    REFUSED(sinter_walls_add_rectangle(w, o, z, z, 1.0, 1.0, s.wall_mat, NULL),
            "not parallel to the normal");
    REFUSED(sinter_walls_add_rectangle(w, o, z, nan3, 1.0, 1.0, s.wall_mat, NULL), "edge");
    REFUSED(sinter_walls_add_rectangle(w, o, z, o, 0.0, 1.0, s.wall_mat, NULL), "half lengths");
    size_t count = 9;
    OK(sinter_walls_count(w, &count));
    assert_int_equal(count, 0); /* nothing was added */
    size_t k = 0;
    OK(sinter_walls_add_cylinder(w, o, z, 1.0, HUGE_VAL, 1, s.wall_mat, &k));
    REFUSED(sinter_walls_set_spin(w, k, NAN), "finite");
    const double t[2] = {0, 1}, f[2] = {1, 1}, tb[2] = {1, 0};
    REFUSED(sinter_walls_set_servo(w, k, 2, t, f, 1.0, 0.0, 1.0), "cylinder");
    OK(sinter_walls_add_disc(w, o, z, 1.0, s.wall_mat, &k));
    REFUSED(sinter_walls_set_servo(w, k, 2, t, f, 0.0, 0.0, 1.0), "not both 0");
    REFUSED(sinter_walls_set_servo(w, k, 2, t, f, 1.0, 0.0, 0.0), "velocity limit");
    REFUSED(sinter_walls_set_servo(w, k, 2, tb, f, 1.0, 0.0, 1.0), "times must increase");
    REFUSED(sinter_walls_get_servo(w, k, NULL, NULL, NULL), "no servo");
    REFUSED(sinter_walls_set_moment(w, k, 2), "must be 0 or 1");
    int kind = -1;
    OK(sinter_walls_get_kind(w, k, &kind));
    assert_int_equal(kind, SINTER_WALL_DISC);
#undef REFUSED
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_rests_in_cylinder_and_on_disc),
        cmocka_unit_test(test_beyond_the_edge),
        cmocka_unit_test(test_spinning_walls_drive_by_friction),
        cmocka_unit_test(test_kinds_move_and_turn),
        cmocka_unit_test(test_force_and_moment_balance),
        cmocka_unit_test(test_submodels_alike_on_every_kind),
        cmocka_unit_test(test_moments_independent_of_threads),
        cmocka_unit_test(test_servo_reaches_target),
        cmocka_unit_test(test_servo_restarts_bit_for_bit),
        cmocka_unit_test(test_bad_wall_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
