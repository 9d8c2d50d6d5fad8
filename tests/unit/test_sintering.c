/*
 * The quasi-static stepper through the public API: two copper spheres
 * (R = 25 um) at 1293 K reproduce the 7DOF pair model of 7dof.md sec. 6.2.
 */
#include <math.h>

#include "scene_support.h"

static void test_two_copper_particles_follow_the_pair_model(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const double r = 25e-6;
    scene_material(&s, 72e9, 0.3, 8960, 0.0, 0.0); /* copper: seed 001 table 2; neck data defaults */
    OK(sinter_particles_create(&s.ps, s.ctx));
    OK(sinter_particles_set_material(s.ps, 0, s.mat));
    OK(sinter_stepper_create(&s.st, s.ctx, SINTER_STEPPER_QUASISTATIC, s.ps, NULL));
    /* touching spheres; the first sits on the principal planes x = y = z = 0 */
    const double p[6] = {0, 0, 0, 2 * r, 0, 0}, rad[2] = {r, r};
    OK(sinter_particles_add(s.ps, 2, p, rad, 0, 1293.0, NULL));
    sinter_sintering_stats stats;
    memset(&stats, 0, sizeof(stats));
    stats.struct_size = sizeof(stats);
    assert_int_equal(sinter_stepper_sintering_stats(s.st, &stats), SINTER_ERR_STATE);
    OK(sinter_stepper_advance(s.st, 1000.0));
    OK(sinter_stepper_sintering_stats(s.st, &stats));
    double t = 0;
    OK(sinter_stepper_time(s.st, &t));
    print_message("t = %g s: %llu link, x/R = %.5f, shrinkage x %.5e (7dof.md 6.2: 0.2742, "
                  "1.029e-2)\n",
                  t, (unsigned long long)stats.links, stats.neck_ratio_mean, stats.shrinkage[0]);
    assert_close(t, 1000.0, 0.0);
    assert_int_equal(stats.links, 1);
    /* the pair model's values at 1000 s, within the regression's 0.5 % */
    assert_close(stats.neck_ratio_mean, 0.2742, 0.005 * 0.2742);
    assert_close(stats.shrinkage[0], 1.029e-2, 0.005 * 1.029e-2);
    assert_close(stats.coordination, 1.0, 0.0);
    stats.struct_size = 1;
    assert_int_equal(sinter_stepper_sintering_stats(s.st, &stats), SINTER_ERR_STRUCT_SIZE);
    scene_close(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_two_copper_particles_follow_the_pair_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
