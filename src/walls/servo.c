/* Force servo of a wall (a punch driven to a target force or pressure): a PI controller on
 * the error between the target force and the force the particles press on the wall along its
 * axis, whose output is the wall's velocity along its axis, limited to +-vmax.
 *
 *   F(t)  = -force . a                      (the particles' push against the axis a)
 *   e     = F_target(t) - F
 *   v     = clamp(kp e + ki I, -vmax, vmax)  (along +a: towards the particles)
 *   dI/dt = e, held while v is at its limit and e would drive it further (anti-windup)
 *
 * The target schedule is timed from the wall's motion start (sinter_walls_set_motion_start),
 * before which the wall is held. The controller acts at each committed step
 * (sinter_walls_servo_commit): between commits the
 * wall moves at the velocity set at the last one, so that a rejected or repeated trial step
 * moves it the same way (the wall's position is a function of the committed state and t).
 * This is the discrete analogue of LIGGGHTS' servo walls (fix mesh/surface/stress/servo, a
 * PID on the force error with a velocity cap). */
#include <math.h>
#include <string.h>

#include "walls.h"

void sinter_wall_servo_at(const sinter_wall *w, double t, double *disp, double *vel)
{
    const double dt = t > w->servo_time ? t - w->servo_time : 0.0;
    *disp = w->servo_disp + w->servo_v * dt;
    *vel = w->servo_v;
}

/* The target force [N] at time t: its schedule timed from the motion's start, as motions are. */
static double servo_target(const sinter_wall *w, double t)
{
    return sinter_interpolate(w->servo_count, w->servo_t, w->servo_f, t - w->motion_start);
}

static double clamp(double v, double limit)
{
    return v > limit ? limit : v < -limit ? -limit : v;
}

void sinter_walls_servo_commit(sinter_walls *walls, double t)
{
    for (size_t k = 0; k < walls->count; ++k) {
        sinter_wall *w = &walls->wall[k];
        if (!w->servo)
            continue;
        const double dt = t > w->servo_time ? t - w->servo_time : 0.0;
        w->servo_disp += w->servo_v * dt;
        w->servo_time = t;
        if (t < w->motion_start) { /* held until its motion starts (a scene: after a pour) */
            w->servo_v = 0.0;
            continue;
        }
        const double target = servo_target(w, t);
        const double pushed =
            -(w->force[0] * w->axis[0] + w->force[1] * w->axis[1] + w->force[2] * w->axis[2]);
        const double e = target - pushed;
        const double integral = w->servo_int + e * dt;
        const double raw = w->servo_kp * e + w->servo_ki * integral;
        const double v = clamp(raw, w->servo_vmax);
        /* anti-windup: the integral grows only while the output is not held at its limit
         * in the error's direction */
        if (raw == v || (raw > v) != (e > 0.0))
            w->servo_int = integral;
        w->servo_v = v;
    }
}

void sinter_wall_servo_free(sinter_walls *walls, sinter_wall *w)
{
    sinter_free(walls->ctx, w->servo_t);
    sinter_free(walls->ctx, w->servo_f);
    w->servo_t = w->servo_f = NULL;
    w->servo_count = 0;
}

sinter_status sinter_walls_set_servo(sinter_walls *walls, size_t k, size_t n, const double *times,
                                     const double *forces, double kp, double ki, double vmax)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, times);
    SINTER_CHECK_NULL(walls->ctx, forces);
    if (w->kind == SINTER_WALL_CYLINDER)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_servo: wall %zu is a cylinder; a servo drives a "
                           "plane, rectangle or disc along its normal",
                           k);
    if (n < 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_servo: the target schedule of wall %zu needs a "
                           "point",
                           k);
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(times[i]) || !isfinite(forces[i]) || (i > 0 && !(times[i] > times[i - 1])))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_set_servo: point %zu of wall %zu (t = %g s, F = %g "
                               "N) is invalid: times must increase and forces be finite",
                               i, k, times[i], forces[i]);
    if (!(kp >= 0.0 && kp < INFINITY) || !(ki >= 0.0 && ki < INFINITY) || !(kp + ki > 0.0) ||
        !(vmax > 0.0 && vmax < INFINITY))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_servo: gains kp = %g m/(s N) and ki = %g m/(s^2 N) "
                           "of wall %zu must be finite, >= 0 and not both 0, and the velocity "
                           "limit %g m/s positive and finite",
                           kp, ki, k, vmax);
    double *t = NULL, *f = NULL;
    if (sinter_copy_table(walls->ctx, n, times, forces, &t, &f) != SINTER_OK)
        return SINTER_ERR_NOMEM;
    sinter_wall_servo_free(walls, w);
    /* the prescribed motion stops where it is: its displacement becomes the servo's start */
    memcpy(w->p0, w->p, sizeof(w->p0));
    memset(w->velocity, 0, sizeof(w->velocity));
    w->motion = SINTER_WALL_FIXED;
    w->servo_t = t;
    w->servo_f = f;
    w->servo_count = n;
    w->servo_kp = kp;
    w->servo_ki = ki;
    w->servo_vmax = vmax;
    w->servo_time = walls->time;
    w->servo_disp = w->servo_v = w->servo_int = 0.0;
    w->servo = 1;
    w->moment_wanted = 1;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_get_servo(const sinter_walls *walls, size_t k, double *target,
                                     double *pushed, double *velocity)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (!w->servo)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_get_servo: wall %zu has no servo", k);
    if (target)
        *target = servo_target(w, walls->time);
    if (pushed)
        *pushed = -(w->force[0] * w->axis[0] + w->force[1] * w->axis[1] + w->force[2] * w->axis[2]);
    if (velocity)
        *velocity = w->servo_v;
    return SINTER_OK;
}
