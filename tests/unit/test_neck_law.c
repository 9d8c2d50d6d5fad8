/*
 * Pair laws of the quasi-static stepper other than the 7DOF model (issue 42):
 *  - the classic grain-boundary diffusion law (src/neck/gb_law.c) against its closed forms:
 *    the neck growth integral at constant temperature (a series), the free pair's approach
 *    rate, and the temperature integral along a ramp;
 *  - two copper spheres in the stepper shrink by exactly the law's free approach;
 *  - a host re-implementation of the law (sinter_stepper_set_neck_law) gives the built-in's
 *    packing to round-off.
 */
#include <math.h>
#include <string.h>

#include "scene_support.h"
#include "sinter_submodel.h"
#include "neck/neck.h"

#define PI 3.14159265358979323846
#define KB 1.380649e-23
#define GAS 8.314462618

/* Copper of seed 001 table 2 (the material defaults). */
static void copper_phase(sinter_neck_phase *p)
{
    memset(p, 0, sizeof(*p));
    p->atomic_volume = 1.18e-29;
    p->surface_energy = 1.78;
    p->grain_boundary_energy = 0.55;
    p->grain_boundary_thickness = 0.69e-9;
    p->boundary_d0 = 2.7e11;
    p->boundary_q = 500e3;
}

/* integral_{a0}^{a1} a^5 / (B + S a) da in closed form: the series
 * R*^5 sum_k (-S)^k / b^(k+1) (u1^(6+k) - u0^(6+k)) / (6+k), u = a / R*, b = B / R*
 * (convergent for S u / b < 1; 400 terms reach round-off for S u / b <= 0.6). */
static double series_integral(double rstar, double b_len, double s, double a0, double a1)
{
    const double b = b_len / rstar, u0 = a0 / rstar, u1 = a1 / rstar;
    double sum = 0.0, coef = 1.0 / b, p0 = pow(u0, 6), p1 = pow(u1, 6);
    for (int k = 0; k < 400; ++k) {
        sum += coef * (p1 - p0) / (6.0 + k);
        coef *= -s / b;
        p0 *= u0;
        p1 *= u1;
    }
    return pow(rstar, 5) * sum;
}

static void test_growth_and_rate_closed_form(void **state)
{
    (void)state;
    sinter_neck_phase p;
    copper_phase(&p);
    sinter_neck_material m;
    memset(&m, 0, sizeof(m));
    m.phase[0] = p;
    const double T = 1293.0, r = 25e-6, rstar = 0.5 * r;
    /* Delta_b = Omega delta_gb D_gb / (k T) */
    const double dgb = 2.7e11 * exp(-500e3 / (GAS * T));
    const double delta_b = 1.18e-29 * 0.69e-9 * dgb / (KB * T);
    assert_close(sinter_gb_law_diffusion(&p, T), delta_b, 1e-14 * delta_b);
    const double c = 0.55 / (2.0 * 1.78), B = 4.0 * rstar * (1.0 - c), S = sqrt(1.0 - c * c);
    const double times[1] = {0.0}, temps[1] = {T};
    const sinter_neck_schedule sched = {1, times, temps};
    const double a0 = 0.01 * r;
    const double t_out[3] = {10.0, 1000.0, 20000.0};
    for (int k = 0; k < 3; ++k) {
        double a = a0;
        OK(sinter_gb_law_advance(&m, &sched, r, r, 0.0, t_out[k], &a));
        /* the growth law integrated: int a^5/(B + S a) da = 16 R* gamma_s Delta_b t; the
         * tolerance is the 8-point rule's (1e-10) and the Newton stop (1e-15) */
        const double lhs = series_integral(rstar, B, S, a0, a);
        const double rhs = 16.0 * rstar * 1.78 * delta_b * t_out[k];
        print_message("t = %g s: a/R = %.6f, integral %.12e, 16 R* gamma Delta_b t %.12e\n",
                      t_out[k], a / r, lhs, rhs);
        assert_close(lhs, rhs, 1e-9 * rhs);
        /* the free pair's approach rate d(delta)/dt = 8 Delta_b F_s / (pi a^4), against the
         * central difference of delta(t) = (a(t)^2 - a0^2) / (4 R*): 1e-6 relative (the
         * difference's truncation, h = 1e-3 t) */
        const double h = 1e-3 * t_out[k];
        double am = a0, ap = a0;
        OK(sinter_gb_law_advance(&m, &sched, r, r, 0.0, t_out[k] - h, &am));
        OK(sinter_gb_law_advance(&m, &sched, r, r, 0.0, t_out[k] + h, &ap));
        const double rate = ((ap * ap - am * am) / (4.0 * rstar)) / (2.0 * h);
        const double fs = PI * 1.78 * (B + S * a);
        const double closed = 8.0 * delta_b * fs / (PI * a * a * a * a);
        assert_close(sinter_gb_law_approach_rate(&p, T, rstar, a), closed, 1e-13 * closed);
        assert_close(rate, closed, 1e-6 * closed);
    }
    /* a ramp 900 K -> 1293 K over 500 s: the law's temperature integral against a fine
     * trapezoid (2e5 panels, relative error ~1e-10) through the same closed form */
    const double rt[2] = {0.0, 500.0}, rT[2] = {900.0, 1293.0};
    const sinter_neck_schedule ramp = {2, rt, rT};
    double a = a0;
    OK(sinter_gb_law_advance(&m, &ramp, r, r, 0.0, 700.0, &a));
    double theta = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double ta = 500.0 * i / n, tb = 500.0 * (i + 1) / n;
        theta += 0.5 * (tb - ta) *
                 (sinter_gb_law_diffusion(&p, 900.0 + 393.0 * ta / 500.0) +
                  sinter_gb_law_diffusion(&p, 900.0 + 393.0 * tb / 500.0));
    }
    theta += 200.0 * delta_b;
    const double rhs = 16.0 * rstar * 1.78 * theta;
    assert_close(series_integral(rstar, B, S, a0, a), rhs, 1e-8 * rhs);
}

/* Two copper spheres (R = 25 um) at 1293 K under the law: the packing's shrinkage is the
 * free pair's approach over the centre distance, (a^2 - a0^2) / (4 R*) / (2 R), and the neck
 * the law's a, to the network solve's tolerance (PCG 1e-7). */
static void test_two_spheres_follow_the_law(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double r = 25e-6;
    scene_material(&s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, NULL));
    OK(sinter_stepper_set_option(s.st, "qs_neck_law", 1));
    assert_int_equal(sinter_stepper_set_option(s.st, "qs_neck_law", 1.5), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_option(s.st, "qs_neck_law", 3), SINTER_ERR_INVALID);
    const double pos[6] = {0, 0, 0, 2 * r, 0, 0}, rad[2] = {r, r};
    OK(sinter_particles_add(s.ps, 2, pos, rad, 0, 1293.0, NULL));
    OK(sinter_stepper_advance(s.st, 1000.0));
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_sintering_stats(s.st, &stats));
    sinter_neck_phase p;
    copper_phase(&p);
    sinter_neck_material m;
    memset(&m, 0, sizeof(m));
    m.phase[0] = p;
    const double times[1] = {0.0}, temps[1] = {1293.0};
    const sinter_neck_schedule sched = {1, times, temps};
    double a = 0.01 * r;
    OK(sinter_gb_law_advance(&m, &sched, r, r, 0.0, 1000.0, &a));
    const double shrink = (a * a - 1e-4 * r * r) / (4.0 * 0.5 * r) / (2.0 * r);
    print_message("grain-boundary law, 1000 s at 1293 K: x/R %.6f (law %.6f), shrinkage %.6e "
                  "(law %.6e)\n",
                  stats.neck_ratio_mean, a / r, stats.shrinkage[0], shrink);
    assert_close(stats.neck_ratio_mean, a / r, 1e-10 * a / r);
    assert_close(stats.shrinkage[0], shrink, 1e-6 * shrink);
    scene_close(&s);
}

/* ---- the law again as a host law, written from its equations --------------------------- */

typedef struct host_data {
    double omega, gamma_s, gamma_gb, thickness, d0, q; /* one material (id 0) */
    int calls;
} host_data;

static double host_temperature(const sinter_neck_law_batch *b, double t)
{
    const size_t n = b->schedule_count;
    const double *x = b->schedule_time, *v = b->schedule_temperature;
    if (t <= x[0])
        return v[0];
    if (t >= x[n - 1])
        return v[n - 1];
    size_t k = 0;
    while (t > x[k + 1])
        ++k;
    return v[k] + (v[k + 1] - v[k]) * ((t - x[k]) / (x[k + 1] - x[k]));
}

static double host_delta_b(const host_data *d, double T)
{
    return d->omega * d->thickness * (d->d0 * exp(-d->q / (GAS * T))) / (KB * T);
}

static int host_advance(sinter_neck_law_batch *b, void *user)
{
    host_data *d = user;
    d->calls++;
    static const double gl4x[2] = {0.33998104358485626, 0.86113631159405258};
    static const double gl4w[2] = {0.65214515486254614, 0.34785484513745386};
    static const double gl8x[4] = {0.18343464249564981, 0.52553240991632899, 0.79666647741362674,
                                   0.96028985649753623};
    static const double gl8w[4] = {0.36268378337836198, 0.31370664587788729, 0.22238103445337447,
                                   0.10122853629037626};
    const double t1 = b->time + b->dt;
    for (size_t k = 0; k < b->count; ++k) {
        if (b->material[k] != 0)
            return -1;
        double *y = b->state + SINTER_NECK_LAW_STATE * k;
        const double ra = y[1], rb = y[4], rstar = ra * rb / (ra + rb), a0 = y[0];
        const double c = d->gamma_gb / (2.0 * d->gamma_s);
        const double B = 4.0 * rstar * (1.0 - c), S = sqrt((1.0 - c) * (1.0 + c));
        double t = b->time, a = a0;
        while (t < t1) {
            double next = t1; /* the next schedule point: T(t) is linear up to it */
            for (size_t i = 0; i < b->schedule_count; ++i)
                if (b->schedule_time[i] > t && b->schedule_time[i] < next)
                    next = b->schedule_time[i];
            const double span = fabs(host_temperature(b, next) - host_temperature(b, t));
            const double panels = fmin(fmax(ceil(span / 5.0), 1.0), 1e4);
            const double width = (next - t) / panels, half = 0.5 * width;
            double theta = 0.0;
            for (double j = 0.0; j < panels; j += 1.0) {
                const double mid = t + (j + 0.5) * width;
                for (int q = 0; q < 2; ++q)
                    theta += gl4w[q] * half *
                             (host_delta_b(d, host_temperature(b, mid - half * gl4x[q])) +
                              host_delta_b(d, host_temperature(b, mid + half * gl4x[q])));
            }
            const double target = 16.0 * rstar * d->gamma_s * theta;
            if (target > 0.0) {
                /* Newton in w = a^6 on int_{a}^{a1} a^5/(B + S a) = target */
                const double start = a;
                double w = a * a * a * a * a * a + 6.0 * B * target;
                for (int it = 0; it < 100; ++it) {
                    const double a1 = cbrt(sqrt(w)), m = 0.5 * (start + a1), h = 0.5 * (a1 - start);
                    double sum = 0.0;
                    for (int q = 0; q < 4; ++q)
                        for (int sg = -1; sg <= 1; sg += 2) {
                            const double u = m + sg * h * gl8x[q], u2 = u * u;
                            sum += gl8w[q] * u2 * u2 * u / (B + S * u);
                        }
                    const double next_w = w - (h * sum - target) * 6.0 * (B + S * a1);
                    const int done = !(fabs(next_w - w) > 4.0 * 2.220446049250313e-16 * w);
                    w = next_w;
                    if (done)
                        break;
                }
                a = cbrt(sqrt(w));
            }
            t = next;
        }
        const double approach = (a - a0) * (a + a0) / (4.0 * rstar);
        y[0] = a;
        y[3] -= approach * (rstar / ra);
        y[6] -= approach * (rstar / rb);
    }
    return 0;
}

static void destroy_host(void *user)
{
    ((host_data *)user)->calls = -1000000;
}

/* 8 copper spheres in a 2 x 2 x 2 block of touching pairs along x, y, z, heated
 * 900 K -> 1293 K over 300 s then held to 600 s: the same packing under the built-in law and
 * under its host re-implementation, every centre and neck within 1e-12 relative (round-off;
 * the loops are the same operations, up to the compiler's contraction). */
static void run_block(int host, host_data *data, double *x_out, double *neck_out)
{
    scene s;
    scene_init(&s);
    scene_material(&s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, NULL));
    if (host) {
        sinter_neck_law_callbacks cb = {sizeof(cb), host_advance, destroy_host};
        cb.struct_size = 1;
        assert_int_equal(sinter_stepper_set_neck_law(s.st, &cb, data), SINTER_ERR_STRUCT_SIZE);
        cb.struct_size = sizeof(cb);
        OK(sinter_stepper_set_neck_law(s.st, &cb, data));
        double law = 0;
        OK(sinter_stepper_get_option(s.st, "qs_neck_law", &law));
        assert_true(law == 2.0);
    } else {
        OK(sinter_stepper_set_option(s.st, "qs_neck_law", 1));
    }
    const double r = 20e-6;
    double pos[24], rad[8];
    for (int i = 0; i < 8; ++i) {
        rad[i] = r;
        pos[3 * i] = (i & 1) ? 2 * r : 0;
        pos[3 * i + 1] = (i & 2) ? 2 * r : 0;
        pos[3 * i + 2] = (i & 4) ? 2 * r : 0;
    }
    OK(sinter_particles_add(s.ps, 8, pos, rad, 0, 900.0, NULL));
    const double ft[2] = {0.0, 300.0}, fT[2] = {900.0, 1293.0};
    OK(sinter_stepper_set_furnace(s.st, 2, ft, fT));
    OK(sinter_stepper_advance(s.st, 600.0));
    const double *x = NULL;
    OK(sinter_particles_view_read(s.ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL));
    memcpy(x_out, x, 24 * sizeof(double));
    OK(sinter_particles_release(s.ps, SINTER_FIELD_POSITION));
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    OK(sinter_stepper_sintering_stats(s.st, &stats));
    assert_int_equal(stats.links, 12);
    neck_out[0] = stats.neck_min;
    neck_out[1] = stats.neck_max;
    neck_out[2] = stats.shrinkage[0];
    scene_close(&s);
}

static void test_host_law_matches_builtin(void **state)
{
    (void)state;
    host_data d = {1.18e-29, 1.78, 0.55, 0.69e-9, 2.7e11, 500e3, 0};
    double xb[24], xh[24], nb[3], nh[3];
    run_block(0, NULL, xb, nb);
    run_block(1, &d, xh, nh);
    assert_int_equal(d.calls, -1000000); /* destroy_user ran once, with the stepper */
    print_message("block of 8: neck %.9e m (host %.9e), shrinkage %.9e (host %.9e)\n", nb[1], nh[1],
                  nb[2], nh[2]);
    assert_true(nb[2] > 1e-3); /* it sintered */
    for (int k = 0; k < 3; ++k)
        assert_close(nh[k], nb[k], 1e-12 * fabs(nb[k]));
    for (int i = 0; i < 24; ++i)
        assert_close(xh[i], xb[i], 1e-12 * 40e-6);
}

/* The API refuses what it cannot use. */
static void test_host_law_errors(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    scene_material(&s, 72e9, 0.3, 8960, 0.0, 0.0);
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, NULL));
    sinter_neck_law_callbacks cb = {sizeof(cb), NULL, NULL};
    assert_int_equal(sinter_stepper_set_neck_law(s.st, &cb, NULL), SINTER_ERR_INVALID);
    assert_int_equal(sinter_stepper_set_neck_law(NULL, &cb, NULL), SINTER_ERR_NULL);
    /* qs_neck_law 2 without a host law: the step is refused */
    OK(sinter_stepper_set_option(s.st, "qs_neck_law", 2));
    const double r = 25e-6, pos[6] = {0, 0, 0, 2 * r, 0, 0}, rad[2] = {r, r};
    OK(sinter_particles_add(s.ps, 2, pos, rad, 0, 1293.0, NULL));
    assert_int_equal(sinter_stepper_advance(s.st, 1.0), SINTER_ERR_INVALID);
    OK(sinter_stepper_set_neck_law(s.st, NULL, NULL));
    double law = -1;
    OK(sinter_stepper_get_option(s.st, "qs_neck_law", &law));
    assert_true(law == 0.0);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_growth_and_rate_closed_form),
        cmocka_unit_test(test_two_spheres_follow_the_law),
        cmocka_unit_test(test_host_law_matches_builtin),
        cmocka_unit_test(test_host_law_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
