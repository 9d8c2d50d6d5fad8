/*
 * Triangle-mesh walls read from STL against the analytic kinds they approximate: a
 * triangulated plane against the plane (rolling and sliding, the tangential history carried
 * across triangles), a triangulated die against the cylinder (the offset of its facets), a
 * triangulated square's edges and corners against the rectangle's; force and moment balance;
 * ASCII and binary files alike; bad files refused (docs/validation.md: walls).
 */
#define _POSIX_C_SOURCE 200809L /* mkstemp */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "scene_support.h"
#include "io/vtp.h"
#include "walls/mesh/mesh.h"

static const double PI = 3.14159265358979323846;
static const double R = 1e-3, E = 1e7, NU = 0.3, RHO = 2500.0, G = 9.81;
static const double E_WALL = 1e13; /* a rigid wall */

static void open_rigid(scene *s, double xi, double mu, int gravity)
{
    scene_init(s);
    scene_material(s, E, NU, RHO, xi, mu);
    OK(sinter_material_set(s->wall_mat, SINTER_MAT_YOUNGS_MODULUS, E_WALL));
    scene_open(s, "hertz_mindlin", gravity);
}

/* An STL file of n facets (9 coordinates each, counter-clockwise from the front), ASCII or
 * binary, at a temporary path (path: 64 chars); normals written from the winding, or zero. */
static void write_stl(char *path, const double *v, size_t n, int binary)
{
    snprintf(path, 64, "/tmp/sinter_meshXXXXXX");
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, binary ? "wb" : "w");
    assert_non_null(f);
    if (!binary)
        fprintf(f, "solid\n"); /* no name: the first facet on the next line */
    else {
        char header[80] = "binary test mesh";
        fwrite(header, 1, 80, f);
        const uint32_t count = (uint32_t)n;
        const unsigned char c[4] = {(unsigned char)count, (unsigned char)(count >> 8),
                                    (unsigned char)(count >> 16), (unsigned char)(count >> 24)};
        fwrite(c, 1, 4, f);
    }
    for (size_t k = 0; k < n; ++k) {
        const double *a = v + 9 * k, *b = a + 3, *c = a + 6;
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double nn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                        u[0] * w[1] - u[1] * w[0]};
        const double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        for (int d = 0; d < 3; ++d)
            nn[d] /= l;
        if (!binary) {
            fprintf(f, "  facet normal %.9g %.9g %.9g\n    outer loop\n", nn[0], nn[1], nn[2]);
            for (int p = 0; p < 3; ++p)
                fprintf(f, "      vertex %.17g %.17g %.17g\n", a[3 * p], a[3 * p + 1],
                        a[3 * p + 2]);
            fprintf(f, "    endloop\n  endfacet\n");
        } else {
            float rec[12];
            for (int d = 0; d < 3; ++d)
                rec[d] = (float)nn[d];
            for (int d = 0; d < 9; ++d)
                rec[3 + d] = (float)a[d];
            fwrite(rec, sizeof(float), 12, f); /* little-endian hosts (x86, arm64) */
            const unsigned char attr[2] = {0, 0};
            fwrite(attr, 1, 2, f);
        }
    }
    if (!binary)
        fprintf(f, "endsolid test\n");
    fclose(f);
}

/* A square grid of n x n cells of unit side in the plane z = 0, from (0, 0), each split along
 * a diagonal (alternating), normals +z: 2 n^2 facets into v. */
static size_t grid_plane(int n, double *v)
{
    size_t k = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x0 = i, x1 = i + 1, y0 = j, y1 = j + 1;
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

/* A sphere launched at (vx, 0, 0) without spin onto the plane z = 0 (wall 0 of s already
 * added), with gravity and friction: it slides, then rolls. Trajectory (x, z, vx, wy) at 40
 * times and the wall's force into out (4 * 40 + 3). */
static void launch(scene *s, double *out)
{
    scene_add(s, 3.3e-3, 4.6e-3, R - 1e-7, R);
    const double v[3] = {0.2, 0.08, 0};
    set3(s, SINTER_FIELD_VELOCITY, 0, v);
    OK(sinter_stepper_set_dt(s->st, 1e-6));
    for (int k = 0; k < 40; ++k) {
        OK(sinter_stepper_advance(s->st, 1e-3 * (k + 1))); /* to that time */
        double x[3], u[3], w[3];
        get3(s, SINTER_FIELD_POSITION, 0, x);
        get3(s, SINTER_FIELD_VELOCITY, 0, u);
        get3(s, SINTER_FIELD_SPIN, 0, w);
        out[4 * k] = x[0], out[4 * k + 1] = x[2], out[4 * k + 2] = u[0], out[4 * k + 3] = w[1];
    }
    OK(sinter_walls_get_force(s->walls, 0, out + 160));
}

/*
 * A sphere sliding, then rolling across a plane of 3200 triangles (0.5 mm squares: it crosses
 * some fifty of them, over edges and vertices) follows the analytic plane's
 * trajectory: its vertices lie in z = 0 exactly, so each face's distance and normal are the
 * plane's bits and the trajectory is the same to round-off (1e-12 of the distance travelled;
 * the history, the tangential spring, is carried across triangles: one contact per (particle,
 * mesh), and a spring restarted at each crossing would leave the sphere sliding longer: its
 * angular velocity is checked to 1e-9). ASCII and binary files give the same bits.
 */
static void test_triangulated_plane_as_plane(void **state)
{
    (void)state;
    double ref[163], got[163];
    scene s;
    open_rigid(&s, 0.3, 0.3, 1);
    const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    OK(sinter_walls_add_plane(s.walls, o, up, s.wall_mat, NULL));
    launch(&s, ref);
    scene_close(&s);
    const int n = 40;
    double *v = malloc(9 * 2 * (size_t)(n * n) * sizeof(double));
    const size_t nf = grid_plane(n, v);
    double first[163];
    for (int binary = 0; binary < 2; ++binary) {
        char path[64];
        write_stl(path, v, nf, binary);
        open_rigid(&s, 0.3, 0.3, 1);
        const double rot[3] = {0, 0, 0}, shift[3] = {-4e-3, -4e-3, 0};
        size_t k = 9;
        OK(sinter_walls_add_mesh(s.walls, path, 0.5e-3, rot, shift, 0, 0.0, s.wall_mat, &k));
        assert_int_equal(k, 0);
        int kind = -1;
        OK(sinter_walls_get_kind(s.walls, 0, &kind));
        assert_int_equal(kind, SINTER_WALL_MESH);
        launch(&s, got);
        scene_close(&s);
        unlink(path);
        double worst = 0.0;
        for (int k2 = 0; k2 < 40; ++k2) {
            assert_close(got[4 * k2], ref[4 * k2], 1e-12 * fabs(ref[4 * k2]));
            assert_close(got[4 * k2 + 1], ref[4 * k2 + 1], 1e-12 * R);
            assert_close(got[4 * k2 + 2], ref[4 * k2 + 2], 1e-9 * fabs(ref[4 * k2 + 2]));
            assert_close(got[4 * k2 + 3], ref[4 * k2 + 3], 1e-9 * fabs(ref[4 * k2 + 3]) + 1e-9);
            worst = fmax(worst, fabs(got[4 * k2] - ref[4 * k2]));
        }
        for (int d = 0; d < 3; ++d)
            assert_close(got[160 + d], ref[160 + d], 1e-12 * fabs(ref[162]));
        print_message("%s: x %.9e m (plane %.9e), wy %.6e rad/s (plane %.6e), worst |dx| %.2e m\n",
                      binary ? "binary" : "ascii", got[156], ref[156], got[159], ref[159], worst);
        if (binary == 0)
            memcpy(first, got, sizeof(first));
        else
            for (int k2 = 0; k2 < 163; ++k2)
                assert_true(first[k2] == got[k2]); /* the same mesh from both files */
    }
    /* the sphere went from sliding to rolling: v = R w at the end (to 5e-3: the tangential
     * spring's ringing) */
    assert_close(ref[158], R * ref[159], 5e-3 * fabs(ref[158]));
    free(v);
}

/* A die of nf facets of radius rc about the x axis from -L to L, outward normals (flip them
 * to hold particles inside), a vertex ring at angle pi/nf off the bottom so that a facet's
 * middle is at the bottom. */
static size_t tube(int nf, double rc, double len, double *v)
{
    size_t k = 0;
    for (int i = 0; i < nf; ++i) {
        const double p0 = -PI / 2 + PI / nf + 2 * PI * i / nf, p1 = p0 + 2 * PI / nf;
        const double a[3] = {-len, rc * cos(p0), rc * sin(p0)},
                     b[3] = {len, rc * cos(p0), rc * sin(p0)};
        const double c[3] = {len, rc * cos(p1), rc * sin(p1)},
                     d[3] = {-len, rc * cos(p1), rc * sin(p1)};
        const double *q[2][3] = {{a, c, b},
                                 {a, d, c}}; /* outward: counter-clockwise from outside */
        for (int f = 0; f < 2; ++f, ++k)
            for (int p = 0; p < 3; ++p)
                for (int e = 0; e < 3; ++e)
                    v[9 * k + 3 * p + e] = q[f][p][e];
    }
    return k;
}

/*
 * A sphere resting at the bottom of a triangulated die (64 facets around, the ends open)
 * against the same sphere in the analytic cylinder: the wall carries its weight (1e-6, as the
 * cylinder's test) and the sphere sits lower by the facet's offset from the circle, rc (1 -
 * cos(pi / 64)) (the tolerance the facet size sets: 1.2e-3 rc here), to 1e-6 of the overlap.
 */
static void test_sphere_rests_in_triangulated_die(void **state)
{
    (void)state;
    const double rc = 5.0 * R;
    const int nf = 64;
    double z[2], f[2][3];
    double *v = malloc(9 * 2 * (size_t)nf * sizeof(double));
    const size_t n = tube(nf, 1.0, 2.0, v);
    char path[64];
    write_stl(path, v, n, 0);
    for (int kind = 0; kind < 2; ++kind) {
        scene s;
        open_rigid(&s, 1.0, 0.3, 1);
        const double o[3] = {0, 0, 0}, axis[3] = {1, 0, 0};
        if (kind == 0)
            OK(sinter_walls_add_cylinder(s.walls, o, axis, rc, HUGE_VAL, 1, s.wall_mat, NULL));
        else
            OK(sinter_walls_add_mesh(s.walls, path, rc, o, o, 1, 0.0, s.wall_mat, NULL));
        scene_add(&s, 0, 0, -(rc - R) + 1e-6, R);
        OK(sinter_stepper_set_dt(s.st, 1e-6));
        OK(sinter_stepper_advance(s.st, 0.03));
        double x[3];
        get3(&s, SINTER_FIELD_POSITION, 0, x);
        OK(sinter_walls_get_force(s.walls, 0, f[kind]));
        z[kind] = x[2];
        const double w = get1(&s, SINTER_FIELD_MASS, 0) * G;
        assert_close(-f[kind][2], w, 1e-6 * w);
        assert_close(f[kind][1], 0.0, 1e-9 * w);
        scene_close(&s);
    }
    unlink(path);
    const double offset = rc * (1.0 - cos(PI / nf)), overlap = z[0] + rc - R;
    print_message("die: z %.9e m (cylinder %.9e m), offset %.6e m (facets %.6e m)\n", z[1], z[0],
                  z[1] - z[0], offset);
    assert_close(z[1] - z[0], offset, 1e-6 * fabs(overlap));
    free(v);
}

/*
 * Edges and vertices: a triangulated square (8 facets, open edges) touched beyond its edge and
 * beyond its corner gives the force of the rectangle of the same size, whose edges are rims
 * as the mesh's open edges are (the same closest point and normal), to 1e-12 of the force.
 */
static void test_edges_and_corners_as_rectangle(void **state)
{
    (void)state;
    double *v = malloc(9 * 8 * sizeof(double));
    const size_t n = grid_plane(2, v);
    char path[64];
    write_stl(path, v, n, 1);
    const double off = 0.6 * R, a = 2.0 * R;
    const double at[2][3] = {{a + off, 0.3 * R, off}, {a + off, a + off, 0.5 * off}};
    for (int c = 0; c < 2; ++c) {
        double fp[2][3];
        for (int kind = 0; kind < 2; ++kind) {
            scene s;
            open_rigid(&s, 0.0, 0.3, 0);
            const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, ex[3] = {1, 0, 0};
            const double shift[3] = {-a, -a, 0};
            if (kind == 0)
                OK(sinter_walls_add_rectangle(s.walls, o, up, ex, a, a, s.wall_mat, NULL));
            else
                OK(sinter_walls_add_mesh(s.walls, path, a, o, shift, 0, 0.0, s.wall_mat, NULL));
            scene_add(&s, at[c][0], at[c][1], at[c][2], R);
            OK(sinter_stepper_evaluate(s.st));
            get3(&s, SINTER_FIELD_FORCE, 0, fp[kind]);
            scene_close(&s);
        }
        const double f = sqrt(fp[0][0] * fp[0][0] + fp[0][1] * fp[0][1] + fp[0][2] * fp[0][2]);
        print_message("%s: mesh (%.6e, %.6e, %.6e) N, rectangle (%.6e, %.6e, %.6e) N\n",
                      c ? "corner" : "edge", fp[1][0], fp[1][1], fp[1][2], fp[0][0], fp[0][1],
                      fp[0][2]);
        assert_true(f > 0.0);
        for (int d = 0; d < 3; ++d)
            assert_close(fp[1][d], fp[0][d], 1e-12 * f);
    }
    unlink(path);
    free(v);
}

/*
 * Force and moment balance on a mesh: four spheres inside a triangulated die (64 facets, moved
 * off the origin), moving and spinning, with rolling resistance, touching its faces (one at a
 * facet's edge line): the wall's reaction equals minus the sum of the particles' forces, its
 * moment about its point minus the sum of (x_i - p) x F_i + T_i, to round-off (1e-12), as for
 * the analytic kinds (test_wall_kinds.c).
 */
static void test_mesh_force_and_moment_balance(void **state)
{
    (void)state;
    const int nf = 64;
    double *v = malloc(9 * 2 * (size_t)nf * sizeof(double));
    const size_t n = tube(nf, 1.0, 20.0, v);
    char path[64];
    write_stl(path, v, n, 1);
    scene s;
    open_rigid(&s, 0.3, 0.4, 0);
    OK(sinter_material_set(s.mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_ROLLING_FRICTION, 0.05));
    OK(sinter_material_set(s.wall_mat, SINTER_MAT_YOUNGS_MODULUS, E));
    const double p[3] = {1e-4, -2e-4, 3e-4}, o[3] = {0, 0, 0};
    OK(sinter_walls_add_mesh(s.walls, path, 6 * R, o, p, 1, 0.0, s.wall_mat, NULL));
    unlink(path);
    /* (axial, radial, angle from -z towards +y): the first on a facet's edge line */
    const double at[4][3] = {{0, 5.002 * R, PI / nf},
                             {3 * R, 5.003 * R, PI},
                             {-4 * R, 5.005 * R, 1.0},
                             {8 * R, 5.004 * R, -PI / 2}};
    const double vel[3] = {0.01, -0.02, 0.0};
    for (int i = 0; i < 4; ++i) {
        const double phi = -PI / 2 + at[i][2];
        scene_add(&s, p[0] + at[i][0], p[1] + at[i][1] * cos(phi), p[2] + at[i][1] * sin(phi), R);
        const double w[3] = {10.0 * i, -5.0, 3.0};
        set3(&s, SINTER_FIELD_SPIN, (size_t)i, w);
        set3(&s, SINTER_FIELD_VELOCITY, (size_t)i, vel);
    }
    OK(sinter_stepper_set_dt(s.st, 1e-7));
    OK(sinter_stepper_advance(s.st, 2e-6)); /* tangential springs loaded */
    OK(sinter_stepper_evaluate(s.st));
    double f[3], m[3], wp[3], sum_f[3] = {0, 0, 0}, sum_m[3] = {0, 0, 0}, fmax = 0.0;
    OK(sinter_walls_get_force(s.walls, 0, f));
    OK(sinter_walls_get_moment(s.walls, 0, m));
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
        }
    }
    print_message("mesh: %llu contacts; reaction (%.6e, %.6e, %.6e) N, moment (%.6e, %.6e, "
                  "%.6e) N m\n",
                  (unsigned long long)stats.wall_contacts, f[0], f[1], f[2], m[0], m[1], m[2]);
    assert_int_equal(stats.wall_contacts, 4);
    assert_true(fmax > 0.0);
    for (int d = 0; d < 3; ++d) {
        assert_close(f[d], -sum_f[d], 1e-12 * fmax);
        assert_close(m[d], -sum_m[d], 1e-12 * fmax * 10 * R);
    }
    scene_close(&s);
    free(v);
}

/* A tube of nf facets around and nr rings along x from -len to len, radius rc, outward
 * normals: 2 nf nr facets into v. */
static size_t ringed_tube(int nf, int nr, double rc, double len, double *v)
{
    size_t k = 0;
    for (int j = 0; j < nr; ++j)
        for (int i = 0; i < nf; ++i) {
            const double p0 = 2 * PI * i / nf, p1 = 2 * PI * (i + 1) / nf;
            const double x0 = -len + 2 * len * j / nr, x1 = -len + 2 * len * (j + 1) / nr;
            const double a[3] = {x0, rc * cos(p0), rc * sin(p0)},
                         b[3] = {x1, rc * cos(p0), rc * sin(p0)};
            const double c[3] = {x1, rc * cos(p1), rc * sin(p1)},
                         d[3] = {x0, rc * cos(p1), rc * sin(p1)};
            const double *q[2][3] = {{a, c, b}, {a, d, c}};
            for (int f = 0; f < 2; ++f, ++k)
                for (int p = 0; p < 3; ++p)
                    for (int e = 0; e < 3; ++e)
                        v[9 * k + 3 * p + e] = q[f][p][e];
        }
    return k;
}

/* The search from a hint (the triangle of the last step's closest point, kept per contact and
 * per neighbour candidate) against the search without: the same bits of distance and normal,
 * and the same triangle, and the neighbour list's verdict (sinter_mesh_within), and points
 * moved inside and outside a certificate (sinter_mesh_closest_certified), from every hint
 * (the answer's, its index neighbours, the first and last triangles, a random one, none, one past
 * the mesh), for points all around two meshes: a triangulated plane with points above its edges and
 * vertices (exact ties between coplanar triangles, where the order of the search decides) and a
 * ringed die, inside, outside and behind, with the reach unlimited and short (lower bounds beyond
 * it). */
static void test_hint_changes_no_bit(void **state)
{
    (void)state;
    sinter_ctx *ctx = NULL;
    OK(sinter_ctx_create(&ctx, NULL));
    double *v = malloc(9 * 2 * 16 * 24 * sizeof(double));
    for (int which = 0; which < 2; ++which) {
        const size_t nf = which == 0 ? grid_plane(8, v) : ringed_tube(16, 12, 1.0, 2.0, v);
        char path[64];
        write_stl(path, v, nf, 1);
        sinter_stl stl;
        OK(sinter_stl_read(ctx, path, &stl));
        unlink(path);
        for (int r = 0; r < 2; ++r) {
            const double o[3] = {0, 0, 0}, reach = r == 0 ? 0.0 : 0.3;
            sinter_mesh *m = NULL;
            OK(sinter_mesh_build(ctx, &stl, "test", 1.0, o, o, 0, reach, &m));
            srand(7u + (unsigned)(2 * which + r));
            size_t checked = 0, bounded = 0, within_checked = 0, taken_front = 0, certified = 0;
            for (int k = 0; k < 4000; ++k) {
                double x[3];
                for (int d = 0; d < 3; ++d)
                    x[d] = (double)rand() / RAND_MAX;
                if (which == 0) { /* over [-1, 9]^2, z in [-0.5, 1.5]; a third on grid lines */
                    x[0] = -1.0 + 10.0 * x[0], x[1] = -1.0 + 10.0 * x[1], x[2] = 2 * x[2] - 0.5;
                    if (k % 3 == 1)
                        x[0] = floor(x[0] * 2.0) / 2.0;
                    if (k % 3 == 2)
                        x[0] = floor(x[0]), x[1] = floor(x[1]);
                } else { /* radius 0 to 1.6, along x past the ends */
                    const double rho = 1.6 * x[1], phi = 2 * PI * x[2];
                    x[0] = -2.5 + 5.0 * x[0], x[1] = rho * cos(phi), x[2] = rho * sin(phi);
                }
                double n0[3];
                const double d0 = sinter_mesh_closest(m, x, n0);
                uint32_t truth = UINT32_MAX;
                double n1[3];
                const double d1 = sinter_mesh_closest_hinted(m, x, n1, &truth);
                assert_memory_equal(&d0, &d1, sizeof(double));
                assert_memory_equal(n0, n1, sizeof(n0));
                const uint32_t nt = (uint32_t)m->nt;
                const uint32_t hints[8] = {
                    truth, truth + 1, truth - 1, 0, nt - 1, UINT32_MAX, (uint32_t)rand() % nt,
                    nt + 7};
                for (int h = 0; h < 8; ++h) {
                    uint32_t hint = hints[h];
                    double n[3];
                    const double d = sinter_mesh_closest_hinted(m, x, n, &hint);
                    assert_memory_equal(&d, &d0, sizeof(double));
                    assert_memory_equal(n, n0, sizeof(n0));
                    if (truth != UINT32_MAX)
                        assert_int_equal(hint, truth);
                    /* the neighbour list's verdict by the search ended at the bound: the
                     * full search's, but for a point farther behind the mesh than the bound
                     * and in front of its hint's plane (taken as in front, stated) */
                    for (int b = 0; b < 3; ++b) {
                        const double bound = b == 0 ? 0.05 : b == 1 ? 0.2 : 0.5;
                        uint32_t hint2 = hints[h];
                        const int within = sinter_mesh_within(m, x, bound, &hint2);
                        if (within != (d0 < bound)) {
                            assert_true(d0 <= -bound && within == 0);
                            taken_front++;
                        }
                        within_checked++;
                    }
                }
                /* a certificate from the search at x, then points moved from x by 0.5, 0.99
                 * and 1.5 of its radius: the same bits as the search without */
                double cert[4] = {0, 0, 0, -1}, nc[3];
                uint32_t hc = UINT32_MAX;
                const double dc = sinter_mesh_closest_certified(m, x, nc, &hc, cert);
                assert_memory_equal(&dc, &d0, sizeof(double));
                assert_memory_equal(nc, n0, sizeof(n0));
                for (int f = 0; f < 3 && cert[3] > 0.0; ++f) {
                    double u[3], y[3], ny[3], nz[3], ce[4];
                    for (int d = 0; d < 3; ++d)
                        u[d] = (double)rand() / RAND_MAX - 0.5;
                    const double lu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) + 1e-300;
                    const double step = (f == 0 ? 0.5 : f == 1 ? 0.99 : 1.5) * cert[3] / lu;
                    for (int d = 0; d < 3; ++d)
                        y[d] = x[d] + step * u[d];
                    memcpy(ce, cert, sizeof(ce));
                    uint32_t hy = hc;
                    const double dy = sinter_mesh_closest(m, y, ny);
                    const double dz = sinter_mesh_closest_certified(m, y, nz, &hy, ce);
                    assert_memory_equal(&dy, &dz, sizeof(double));
                    assert_memory_equal(ny, nz, sizeof(ny));
                    certified += f < 2;
                }
                checked += truth != UINT32_MAX;
                bounded += truth == UINT32_MAX;
            }
            print_message("%s, reach %g: %zu points exact, %zu beyond the reach (lower bounds); "
                          "%zu verdicts within a bound, %zu far behind taken as in front; %zu "
                          "points moved within a certificate\n",
                          which ? "die" : "plane", reach, checked, bounded, within_checked,
                          taken_front, certified);
            assert_true(certified > 1000);
            assert_true(checked > 1000);
            sinter_mesh_destroy(ctx, m);
        }
        sinter_stl_free(ctx, &stl);
    }
    free(v);
    sinter_ctx_destroy(ctx);
}

/*
 * A packed bed in a triangulated die against the same bed in the analytic cylinder: six
 * layers of 26 spheres (a ring of 16 pressed 0.05 R into the wall, an inner ring of 9, one on
 * the axis; the layers 1.98 R apart and touching each other; each layer's ring turned by
 * another angle so that spheres meet facets' middles, edges and vertices), the forces
 * evaluated at rest with no die, the cylinder of radius Rc, the mesh of 48 facets around
 * (rings as tall as wide) inscribed in it, and the cylinder through the facets' middles,
 * Rc cos(pi / 48). The wall's force on each sphere (its force less the no-die force: the pair
 * forces are the same) lies between the two cylinders' (the facets lie between the circles:
 * the overlap grows by at most the facets' offset Rc (1 - cos(pi / 48)), 1.29e-2 R here) and
 * turns from the radial by at most pi / 48; the die's reaction balances the spheres' forces.
 */
static void test_packed_bed_in_triangulated_die(void **state)
{
    (void)state;
    const double rc = 6.0 * R, len = 8.0 * R, delta = 0.05 * R;
    const int nf = 48, nr = (int)ceil(2.0 * len / (2.0 * PI * rc / nf)), layers = 6;
    double *v = malloc(9 * 2 * (size_t)(nf * nr) * sizeof(double));
    const size_t nt = ringed_tube(nf, nr, rc, len, v);
    char path[64];
    write_stl(path, v, nt, 1);
    free(v);
    const double rin = rc * cos(PI / nf);
    size_t n = 0;
    double *f[4] = {NULL, NULL, NULL, NULL}, reaction[3] = {0, 0, 0};
    double(*x)[3] = NULL;
    for (int kind = 0; kind < 4; ++kind) { /* none, cylinder rc, mesh, cylinder rin */
        scene s;
        open_rigid(&s, 0.3, 0.3, 0);
        const double o[3] = {0, 0, 0}, axis[3] = {1, 0, 0};
        if (kind == 1 || kind == 3)
            OK(sinter_walls_add_cylinder(s.walls, o, axis, kind == 1 ? rc : rin, HUGE_VAL, 1,
                                         s.wall_mat, NULL));
        if (kind == 2)
            OK(sinter_walls_add_mesh(s.walls, path, 1.0, o, o, 1, 0.0, s.wall_mat, NULL));
        for (int l = 0; l < layers; ++l) {
            const double ax = (l - 0.5 * (layers - 1)) * 1.98 * R, turn = 0.37 * l;
            for (int i = 0; i < 16; ++i) {
                const double phi = turn + 2 * PI * i / 16, rho = rc - R + delta;
                scene_add(&s, ax, rho * cos(phi), rho * sin(phi), R);
            }
            for (int i = 0; i < 9; ++i) {
                const double phi = -turn + 2 * PI * i / 9, rho = 3.05 * R;
                scene_add(&s, ax, rho * cos(phi), rho * sin(phi), R);
            }
            scene_add(&s, ax, 0, 0, R);
        }
        OK(sinter_particles_count(s.ps, &n));
        f[kind] = malloc(3 * n * sizeof(double));
        if (x == NULL)
            x = malloc(n * sizeof(*x));
        OK(sinter_stepper_evaluate(s.st));
        for (size_t i = 0; i < n; ++i) {
            get3(&s, SINTER_FIELD_FORCE, i, f[kind] + 3 * i);
            get3(&s, SINTER_FIELD_POSITION, i, x[i]);
        }
        if (kind == 2)
            OK(sinter_walls_get_force(s.walls, 0, reaction));
        scene_close(&s);
    }
    unlink(path);
    double push[3] = {0, 0, 0}, sum[3] = {0, 0, 0}, worst_turn = 0.0;
    size_t touching = 0;
    for (size_t i = 0; i < n; ++i) {
        const double rho = hypot(x[i][1], x[i][2]), at = rho > 0.0 ? rho : 1.0;
        const double in[3] = {0, -x[i][1] / at, -x[i][2] / at}; /* towards the axis */
        double p[3], w[3][3];
        for (int kind = 1; kind < 4; ++kind) {
            double *wk = w[kind - 1];
            for (int d = 0; d < 3; ++d)
                wk[d] = f[kind][3 * i + d] - f[0][3 * i + d];
            p[kind - 1] = wk[0] * in[0] + wk[1] * in[1] + wk[2] * in[2];
            push[kind - 1] += p[kind - 1];
        }
        for (int d = 0; d < 3; ++d)
            sum[d] += w[1][d];
        const double scale = fabs(f[0][3 * i]) + fabs(f[0][3 * i + 1]) + fabs(f[0][3 * i + 2]) +
                             fabs(p[2]); /* the round-off of the subtraction */
        if (rho < rc - 2.0 * R) {        /* inner spheres: no wall force */
            for (int kind = 0; kind < 3; ++kind)
                for (int d = 0; d < 3; ++d)
                    assert_true(fabs(w[kind][d]) <= 1e-12 * scale);
            continue;
        }
        ++touching;
        const double mag = sqrt(w[1][0] * w[1][0] + w[1][1] * w[1][1] + w[1][2] * w[1][2]);
        assert_true(p[0] > 0.0);
        assert_true(p[0] <= mag * (1.0 + 1e-12) + 1e-12 * scale); /* cylinder rc <= mesh */
        assert_true(mag <= p[2] * (1.0 + 1e-12) + 1e-12 * scale); /* mesh <= cylinder rin */
        const double turned = acos(fmin(p[1] / mag, 1.0));
        worst_turn = fmax(worst_turn, turned);
        /* 1e-6 rad: acos near 1 of a ratio with round-off (at a facets' edge the turn is
         * pi / nf exactly, a face's normal); a wrong facet's would be off by pi / nf more */
        assert_true(turned <= PI / nf + 1e-6);
    }
    print_message("bed: %zu of %zu spheres on the die; radial push %.6e N (cylinder Rc %.6e, "
                  "cylinder Rc cos(pi/%d) %.6e), normals turned by at most %.3e rad (pi/%d = "
                  "%.3e)\n",
                  touching, n, push[1], push[0], nf, push[2], worst_turn, nf, PI / nf);
    assert_int_equal(touching, 16 * layers);
    assert_true(push[0] <= push[1] && push[1] <= push[2]);
    for (int d = 0; d < 3; ++d)
        assert_close(reaction[d], -sum[d], 1e-12 * push[1]);
    for (int kind = 0; kind < 4; ++kind)
        free(f[kind]);
    free(x);
}

static void write_text(char *path, const char *text)
{
    snprintf(path, 64, "/tmp/sinter_meshXXXXXX");
    const int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
}

/*
 * The .vtp wall frame draws a mesh as its triangles where its motion has carried them: a
 * triangulated square of 8 facets (1 mm cells) moving up at 0.1 m/s, after 1 ms: 8 polygons
 * of 3 points each, every point 1e-4 m above the file's (to 1e-15 m), the facets' normals
 * (+z) as cell data.
 */
static void test_mesh_drawn_in_wall_frames(void **state)
{
    (void)state;
    double v[72];
    const size_t nf = grid_plane(2, v);
    char path[64];
    write_stl(path, v, nf, 0);
    scene s;
    open_rigid(&s, 0.3, 0.3, 0);
    const double o[3] = {0, 0, 0}, up[3] = {0, 0, 0.1};
    OK(sinter_walls_add_mesh(s.walls, path, 1e-3, o, o, 0, 0.0, s.wall_mat, NULL));
    unlink(path);
    OK(sinter_walls_set_velocity(s.walls, 0, up));
    scene_add(&s, 0, 0, 0.01, R); /* far from it */
    OK(sinter_stepper_set_dt(s.st, 1e-5));
    OK(sinter_stepper_advance(s.st, 1e-3));
    char out[64];
    write_text(out, "");
    const double lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
    OK(sinter_vtp_write_walls(s.ctx, out, s.walls, lo, hi, 0));
    scene_close(&s);
    FILE *f = fopen(out, "r");
    assert_non_null(f);
    static char text[1 << 16];
    const size_t len = fread(text, 1, sizeof(text) - 1, f);
    fclose(f);
    unlink(out);
    text[len] = '\0';
    assert_non_null(strstr(text, "NumberOfPoints=\"24\""));
    assert_non_null(strstr(text, "NumberOfPolys=\"8\""));
    const char *at = strstr(text, "Name=\"points\"");
    assert_non_null(at);
    at = strchr(at, '\n') + 1;
    for (size_t k = 0; k < 24; ++k) {
        char *end = NULL;
        double q[3];
        for (int d = 0; d < 3; ++d) {
            q[d] = strtod(at, &end);
            assert_true(end != at);
            at = end;
        }
        for (int d = 0; d < 3; ++d) /* the file's vertex (unit cells, scaled), moved up */
            assert_close(q[d], 1e-3 * v[3 * k + d] + (d == 2 ? 1e-4 : 0.0), 1e-15);
    }
    at = strstr(text, "Name=\"normal\"");
    assert_non_null(at);
    at = strchr(at, '\n') + 1;
    for (size_t k = 0; k < 8; ++k) {
        char *end = NULL;
        for (int d = 0; d < 3; ++d) {
            const double q = strtod(at, &end);
            assert_true(end != at);
            at = end;
            assert_close(q, d == 2 ? 1.0 : 0.0, 1e-15);
        }
    }
}

/* Bad files and arguments are refused with a message naming what is wrong; nothing added. */
static void test_bad_meshes_refused(void **state)
{
    (void)state;
    scene s;
    open_rigid(&s, 0.5, 0.3, 0);
    const double o[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 0};
    const char *msg = NULL;
#define REFUSED(code, call, fragment)                                                              \
    do {                                                                                           \
        assert_int_equal((call), (code));                                                          \
        msg = sinter_last_error(s.ctx);                                                            \
        if (strstr(msg, fragment) == NULL)                                                         \
            fail_msg("'%s' lacks '%s'", msg, fragment);                                            \
    } while (0)
    static const struct {
        const char *text, *fragment;
        sinter_status code;
    } bad[] = {
        {"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
         " vertex 2 0 0\n endloop\n endfacet\nendsolid\n",
         "facet 1 is degenerate", SINTER_ERR_INVALID},
        {"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
         " vertex 0 1 0\n endloop\n endfacet\n facet normal 0 0 1\n outer loop\n vertex 1 0 0\n"
         " vertex 0 1 0\n vertex 1 1 0\n endloop\n endfacet\nendsolid\n",
         "inconsistent normals", SINTER_ERR_INVALID},
        {"solid x\n facet normal 0 0 -1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
         " vertex 0 1 0\n endloop\n endfacet\nendsolid\n",
         "stored normal", SINTER_ERR_INVALID},
        {"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
         " vertex 0 1 0\n endloop\n endfacet\n facet normal 0 0 0\n outer loop\n vertex 0 0 0\n"
         " vertex 1 0 0\n vertex 0 0 1\n endloop\n endfacet\n facet normal 0 0 0\n outer loop\n"
         " vertex 1 0 0\n vertex 0 0 0\n vertex 0 0 -1\n endloop\n endfacet\nendsolid\n",
         "shared by 3 facets", SINTER_ERR_INVALID},
        {"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 zero 0\n",
         ":5: expected a finite number, got 'zero'", SINTER_ERR_PARSE},
        {"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n", "expected 'vertex'",
         SINTER_ERR_PARSE},
        {"solid x\nendsolid x\n", "has no facets", SINTER_ERR_PARSE},
        {"not an stl file", "neither ASCII", SINTER_ERR_PARSE},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); ++k) {
        char path[64];
        write_text(path, bad[k].text);
        REFUSED(bad[k].code,
                sinter_walls_add_mesh(s.walls, path, 1.0, o, o, 0, 0.0, s.wall_mat, NULL),
                bad[k].fragment);
        unlink(path);
    }
    REFUSED(
        SINTER_ERR_IO,
        sinter_walls_add_mesh(s.walls, "/nonexistent/x.stl", 1.0, o, o, 0, 0.0, s.wall_mat, NULL),
        "cannot open");
    char path[64];
    write_text(path, bad[0].text);
    REFUSED(SINTER_ERR_INVALID,
            sinter_walls_add_mesh(s.walls, path, 0.0, o, o, 0, 0.0, s.wall_mat, NULL), "scale");
    REFUSED(SINTER_ERR_INVALID,
            sinter_walls_add_mesh(s.walls, path, 1.0, nan3, o, 0, 0.0, s.wall_mat, NULL), "finite");
    REFUSED(SINTER_ERR_INVALID,
            sinter_walls_add_mesh(s.walls, path, 1.0, o, o, 2, 0.0, s.wall_mat, NULL), "flip");
    REFUSED(SINTER_ERR_INVALID,
            sinter_walls_add_mesh(s.walls, path, 1.0, o, o, 0, -1.0, s.wall_mat, NULL), "reach");
    assert_int_equal(sinter_walls_add_mesh(s.walls, NULL, 1.0, o, o, 0, 0.0, s.wall_mat, NULL),
                     SINTER_ERR_NULL);
    unlink(path);
    size_t count = 9;
    OK(sinter_walls_count(s.walls, &count));
    assert_int_equal(count, 0);
#undef REFUSED
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_triangulated_plane_as_plane),
        cmocka_unit_test(test_sphere_rests_in_triangulated_die),
        cmocka_unit_test(test_edges_and_corners_as_rectangle),
        cmocka_unit_test(test_mesh_force_and_moment_balance),
        cmocka_unit_test(test_hint_changes_no_bit),
        cmocka_unit_test(test_packed_bed_in_triangulated_die),
        cmocka_unit_test(test_mesh_drawn_in_wall_frames),
        cmocka_unit_test(test_bad_meshes_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
