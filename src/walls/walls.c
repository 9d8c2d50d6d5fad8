/* Walls: rigid planes with prescribed motion and their reaction forces. */
#include <math.h>
#include <string.h>

#include "core/stream_store.h"
#include "walls.h"

sinter_status sinter_walls_create(sinter_walls **out, sinter_ctx *ctx)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out);
    sinter_walls *w = sinter_calloc(ctx, 1, sizeof(*w));
    if (w == NULL)
        return sinter_last_status(ctx);
    w->ctx = ctx;
    *out = w;
    return SINTER_OK;
}

static void clear_temperature_schedule(sinter_walls *walls, sinter_wall *w)
{
    sinter_free(walls->ctx, w->temperature_t);
    sinter_free(walls->ctx, w->temperature_v);
    w->temperature_t = w->temperature_v = NULL;
    w->temperature_count = 0;
}

static void clear_schedule(sinter_walls *walls, sinter_wall *w)
{
    sinter_free(walls->ctx, w->schedule_t);
    sinter_free(walls->ctx, w->schedule_d);
    w->schedule_t = w->schedule_d = NULL;
    w->schedule_count = 0;
}

void sinter_walls_destroy(sinter_walls *walls)
{
    if (walls == NULL)
        return;
    for (size_t k = 0; k < walls->count; ++k) {
        clear_schedule(walls, &walls->wall[k]);
        clear_temperature_schedule(walls, &walls->wall[k]);
        sinter_wall_drive_free(walls, &walls->wall[k]);
        sinter_wall_servo_free(walls, &walls->wall[k]);
        sinter_wall_mesh_free(walls, &walls->wall[k]);
    }
    sinter_free(walls->ctx, walls->wall);
    sinter_free(walls->ctx, walls);
}

sinter_status sinter_walls_count(const sinter_walls *walls, size_t *count)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(walls->ctx, count);
    *count = walls->count;
    return SINTER_OK;
}

static int finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* v / |v| into unit, scaled by the largest component first so that neither 1e200 (whose
 * square overflows) nor 1e-200 (whose square underflows) is lost; 0 for the zero vector. */
static int unit_vector(const double v[3], double unit[3])
{
    const double scale = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(scale > 0.0))
        return 0;
    const double s[3] = {v[0] / scale, v[1] / scale, v[2] / scale};
    const double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int d = 0; d < 3; ++d)
        unit[d] = s[d] / len;
    return 1;
}

sinter_status sinter_walls_add_plane(sinter_walls *walls, const double point[3],
                                     const double normal[3], const sinter_material *material,
                                     size_t *index)
{
    if (walls == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = walls->ctx;
    SINTER_CHECK_NULL(ctx, point);
    SINTER_CHECK_NULL(ctx, normal);
    SINTER_CHECK_NULL(ctx, material);
    if (!finite3(point) || !finite3(normal))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_plane: point (%g, %g, %g) and normal (%g, %g, %g) "
                           "must be finite",
                           point[0], point[1], point[2], normal[0], normal[1], normal[2]);
    double unit[3];
    if (!unit_vector(normal, unit))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_walls_add_plane: the normal is the zero vector");
    if (walls->count == walls->capacity) {
        size_t cap = walls->capacity ? 2 * walls->capacity : 8;
        sinter_wall *grown = sinter_realloc_array(ctx, walls->wall, cap, sizeof(sinter_wall));
        if (grown == NULL)
            return sinter_last_status(ctx);
        walls->wall = grown;
        walls->capacity = cap;
    }
    sinter_wall *w = &walls->wall[walls->count];
    memset(w, 0, sizeof(*w));
    for (int d = 0; d < 3; ++d) {
        w->p0[d] = w->p[d] = point[d];
        w->n[d] = unit[d];
    }
    sinter_wall_frame(w); /* axis and edges: a spin's axis, a drawing's frame */
    w->temperature = 293.15;
    w->motion = SINTER_WALL_FIXED;
    w->material = *material;
    w->material.ctx = ctx;
    if (index)
        *index = walls->count;
    walls->count++;
    return SINTER_OK;
}

sinter_status sinter_wall_get(const sinter_walls *walls, size_t k, const char *func,
                              sinter_wall **w)
{
    if (k >= walls->count)
        return sinter_fail(walls->ctx, SINTER_ERR_RANGE, "%s: wall %zu does not exist (%zu walls)",
                           func, k, walls->count);
    *w = &walls->wall[k];
    return SINTER_OK;
}

sinter_status sinter_walls_set_material(sinter_walls *walls, size_t k,
                                        const sinter_material *material)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, material);
    w->material = *material;
    w->material.ctx = walls->ctx;
    return SINTER_OK;
}

sinter_status sinter_walls_set_velocity(sinter_walls *walls, size_t k, const double velocity[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, velocity);
    if (!finite3(velocity))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_velocity: velocity of wall %zu must be finite", k);
    clear_schedule(walls, w);
    memcpy(w->velocity, velocity, sizeof(w->velocity));
    w->motion = SINTER_WALL_VELOCITY;
    w->servo = 0;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_set_schedule(sinter_walls *walls, size_t k, size_t n,
                                        const double *times, const double *displacements)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, times);
    SINTER_CHECK_NULL(walls->ctx, displacements);
    if (n < 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_schedule: a schedule needs at least one point");
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(times[i]) || !finite3(displacements + 3 * i))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_set_schedule: point %zu of wall %zu is not finite", i,
                               k);
        if (i > 0 && !(times[i] > times[i - 1]))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_set_schedule: times must increase strictly, but "
                               "t[%zu] = %g s follows t[%zu] = %g s",
                               i, times[i], i - 1, times[i - 1]);
    }
    double *t = sinter_calloc(walls->ctx, n, sizeof(double));
    double *d = sinter_calloc(walls->ctx, 3 * n, sizeof(double));
    if (t == NULL || d == NULL) {
        sinter_free(walls->ctx, t);
        sinter_free(walls->ctx, d);
        return SINTER_ERR_NOMEM;
    }
    memcpy(t, times, n * sizeof(double));
    memcpy(d, displacements, 3 * n * sizeof(double));
    clear_schedule(walls, w);
    w->schedule_t = t;
    w->schedule_d = d;
    w->schedule_count = n;
    w->motion = SINTER_WALL_SCHEDULE;
    w->servo = 0;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_set_sine(sinter_walls *walls, size_t k, const double amplitude[3],
                                    double omega)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, amplitude);
    if (!finite3(amplitude) || !isfinite(omega) || omega < 0.0)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_sine: amplitude must be finite and omega = %g rad/s "
                           "finite and >= 0",
                           omega);
    clear_schedule(walls, w);
    memcpy(w->amplitude, amplitude, sizeof(w->amplitude));
    w->omega = omega;
    w->motion = SINTER_WALL_SINE;
    w->servo = 0;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_set_callback(sinter_walls *walls, size_t k, sinter_wall_motion_fn fn,
                                        void *user)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, fn);
    /* tried at the current time first: a callback that fails leaves the wall as it was */
    const sinter_wall_motion_fn old_fn = w->callback;
    void *const old_user = w->callback_user;
    const int old_motion = w->motion, old_servo = w->servo;
    w->callback = fn;
    w->callback_user = user;
    w->motion = SINTER_WALL_CALLBACK;
    w->servo = 0;
    const sinter_status s = sinter_walls_move(walls, walls->time);
    if (s != SINTER_OK) {
        w->callback = old_fn;
        w->callback_user = old_user;
        w->motion = old_motion;
        w->servo = old_servo;
        return s;
    }
    clear_schedule(walls, w);
    return SINTER_OK;
}

sinter_status sinter_walls_set_motion_start(sinter_walls *walls, size_t k, double start)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (isnan(start) || start == -HUGE_VAL)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_motion_start: start %g s of wall %zu must be finite "
                           "(or HUGE_VAL to hold the wall until further notice)",
                           start, k);
    w->motion_start = start;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_set_temperature(sinter_walls *walls, size_t k, double temperature)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (!isfinite(temperature) || temperature <= 0.0)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_temperature: temperature %g K of wall %zu must be "
                           "positive and finite",
                           temperature, k);
    clear_temperature_schedule(walls, w);
    w->temperature = temperature;
    return SINTER_OK;
}

sinter_status sinter_walls_set_electric(sinter_walls *walls, size_t k, int mode, double value)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (mode != SINTER_WALL_NEUTRAL && mode != SINTER_WALL_CURRENT && mode != SINTER_WALL_POTENTIAL)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_electric: mode %d of wall %zu is not one of "
                           "SINTER_WALL_NEUTRAL (0), SINTER_WALL_CURRENT (1), "
                           "SINTER_WALL_POTENTIAL (2)",
                           mode, k);
    if (!isfinite(value))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_electric: value %g of wall %zu must be finite "
                           "(a current [A] or a potential [V])",
                           value, k);
    w->electric_mode = mode;
    w->electric_set = mode == SINTER_WALL_NEUTRAL ? 0.0 : value;
    w->electric_value = sinter_wall_drive_value(w, walls->time);
    return SINTER_OK;
}

sinter_status sinter_walls_set_thermal(sinter_walls *walls, size_t k, int mode, double value)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (mode < SINTER_WALL_RESERVOIR || mode > SINTER_WALL_IMPOSED)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_thermal: mode %d of wall %zu is not one of "
                           "SINTER_WALL_RESERVOIR (0), SINTER_WALL_ADIABATIC (1), "
                           "SINTER_WALL_RESISTANCE (2), SINTER_WALL_TRANSFER (3), "
                           "SINTER_WALL_IMPOSED (4)",
                           mode, k);
    const int valued = mode == SINTER_WALL_RESISTANCE || mode == SINTER_WALL_TRANSFER;
    if (valued && !(value >= 0.0 && value < INFINITY))
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_thermal: value %g of wall %zu must be finite and "
                           ">= 0 (a specific contact resistance [m^2 K/W] or a heat transfer "
                           "coefficient [W/(m^2 K)])",
                           value, k);
    w->thermal_mode = mode;
    w->thermal_value = valued ? value : 0.0;
    return SINTER_OK;
}

sinter_status sinter_walls_set_temperature_schedule(sinter_walls *walls, size_t k, size_t n,
                                                    const double *times, const double *temperatures)
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, times);
    SINTER_CHECK_NULL(walls->ctx, temperatures);
    if (n < 1)
        return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                           "sinter_walls_set_temperature_schedule: a schedule needs a point");
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(times[i]) || !(temperatures[i] > 0.0) || !isfinite(temperatures[i]) ||
            (i > 0 && !(times[i] > times[i - 1])))
            return sinter_fail(walls->ctx, SINTER_ERR_INVALID,
                               "sinter_walls_set_temperature_schedule: point %zu of wall %zu "
                               "(t = %g s, T = %g K) is invalid: times must increase and "
                               "temperatures be positive",
                               i, k, times[i], temperatures[i]);
    double *t = NULL, *v = NULL;
    if (sinter_copy_table(walls->ctx, n, times, temperatures, &t, &v) != SINTER_OK)
        return SINTER_ERR_NOMEM;
    clear_temperature_schedule(walls, w);
    w->temperature_t = t;
    w->temperature_v = v;
    w->temperature_count = n;
    return sinter_walls_move(walls, walls->time);
}

sinter_status sinter_walls_get_state(const sinter_walls *walls, size_t k, double point[3],
                                     double velocity[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    if (point)
        memcpy(point, w->p, sizeof(w->p));
    if (velocity)
        memcpy(velocity, w->u, sizeof(w->u));
    return SINTER_OK;
}

sinter_status sinter_walls_get_normal(const sinter_walls *walls, size_t k, double normal[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, normal);
    memcpy(normal, w->n, sizeof(w->n));
    return SINTER_OK;
}

sinter_status sinter_walls_get_force(const sinter_walls *walls, size_t k, double force[3])
{
    sinter_wall *w = NULL;
    GET_WALL(walls, k, w);
    SINTER_CHECK_NULL(walls->ctx, force);
    memcpy(force, w->force, sizeof(w->force));
    return SINTER_OK;
}

/* Displacement and velocity of a piecewise-linear schedule at time t. */
static void schedule_at(const sinter_wall *w, double t, double disp[3], double vel[3])
{
    const size_t n = w->schedule_count;
    const double *ts = w->schedule_t, *ds = w->schedule_d;
    if (n == 1 || t <= ts[0] || t >= ts[n - 1]) {
        const size_t end = (n == 1 || t <= ts[0]) ? 0 : n - 1;
        for (int d = 0; d < 3; ++d) {
            disp[d] = ds[3 * end + d];
            vel[d] = 0.0;
        }
        return;
    }
    size_t lo = 0, hi = n - 1; /* ts[lo] <= t < ts[hi] */
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (ts[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const double span = ts[hi] - ts[lo], f = (t - ts[lo]) / span;
    for (int d = 0; d < 3; ++d) {
        const double slope = (ds[3 * hi + d] - ds[3 * lo + d]) / span;
        disp[d] = ds[3 * lo + d] + f * (ds[3 * hi + d] - ds[3 * lo + d]);
        vel[d] = slope;
    }
}

sinter_status sinter_walls_move(sinter_walls *walls, double t)
{
    for (size_t k = 0; k < walls->count; ++k) {
        sinter_wall *w = &walls->wall[k];
        double disp[3] = {0, 0, 0}, vel[3] = {0, 0, 0};
        const double t_wall = t - w->motion_start; /* time since the motion started */
        /* before its start a wall rests (a schedule holds its first point) */
        switch ((t_wall < 0.0 && w->motion != SINTER_WALL_SCHEDULE) ? SINTER_WALL_FIXED
                                                                    : w->motion) {
        case SINTER_WALL_VELOCITY:
            for (int d = 0; d < 3; ++d) {
                disp[d] = w->velocity[d] * t_wall;
                vel[d] = w->velocity[d];
            }
            break;
        case SINTER_WALL_SCHEDULE:
            schedule_at(w, t_wall, disp, vel);
            break;
        case SINTER_WALL_SINE: {
            const double s = sin(w->omega * t_wall), c = cos(w->omega * t_wall);
            for (int d = 0; d < 3; ++d) {
                disp[d] = w->amplitude[d] * s;
                vel[d] = w->amplitude[d] * w->omega * c;
            }
            break;
        }
        case SINTER_WALL_CALLBACK:
            if (w->callback(t_wall, disp, vel, w->callback_user) != 0)
                return sinter_fail(walls->ctx, SINTER_ERR_CALLBACK,
                                   "the motion callback of wall %zu failed at t = %g s", k, t);
            if (!finite3(disp) || !finite3(vel))
                return sinter_fail(walls->ctx, SINTER_ERR_CALLBACK,
                                   "the motion callback of wall %zu gave a non-finite "
                                   "displacement or velocity at t = %g s",
                                   k, t);
            break;
        default:
            break;
        }
        /* written only where the bits change (a wall at rest: never; sinter_wall) */
        double p[3];
        for (int d = 0; d < 3; ++d)
            p[d] = w->p0[d] + disp[d];
        if (w->servo) { /* along the axis, by the controller's committed state (servo.c) */
            double sd = 0.0, sv = 0.0;
            sinter_wall_servo_at(w, t, &sd, &sv);
            for (int d = 0; d < 3; ++d) {
                p[d] += sd * w->axis[d];
                vel[d] += sv * w->axis[d];
            }
        }
        sinter_put_changed(w->p, p, sizeof(p));
        sinter_put_changed(w->u, vel, sizeof(vel));
        if (w->spin != 0.0) { /* the spin's angle since the motion's start; a rectangle turns */
            const double angle = t_wall > 0.0 ? w->spin * t_wall : 0.0;
            sinter_put_changed(&w->angle, &angle, sizeof(angle));
            if (w->kind == SINTER_WALL_RECTANGLE) {
                const double c = cos(angle), s = sin(angle), *a = w->axis, *e = w->e1_0;
                const double ax_e[3] = {a[1] * e[2] - a[2] * e[1], a[2] * e[0] - a[0] * e[2],
                                        a[0] * e[1] - a[1] * e[0]};
                double e1[3], e2[3];
                for (int d = 0; d < 3; ++d)
                    e1[d] = c * e[d] + s * ax_e[d];
                e2[0] = a[1] * e1[2] - a[2] * e1[1];
                e2[1] = a[2] * e1[0] - a[0] * e1[2];
                e2[2] = a[0] * e1[1] - a[1] * e1[0];
                sinter_put_changed(w->e1, e1, sizeof(e1));
                sinter_put_changed(w->e2, e2, sizeof(e2));
            } else if (w->turns) { /* a mesh turned about its axis (mesh_rotation.c) */
                double rot[9];
                sinter_wall_rotation_matrix(w->axis, angle, rot);
                sinter_put_changed(w->rot, rot, sizeof(rot));
            }
        }
        if (w->temperature_count > 0) {
            const double temperature =
                sinter_interpolate(w->temperature_count, w->temperature_t, w->temperature_v, t);
            sinter_put_changed(&w->temperature, &temperature, sizeof(temperature));
        }
        if (w->electric_count > 0 || w->pulse_off > 0.0) {
            const double value = sinter_wall_drive_value(w, t);
            sinter_put_changed(&w->electric_value, &value, sizeof(value));
        }
    }
    walls->time = t;
    return SINTER_OK;
}
