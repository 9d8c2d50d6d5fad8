/* Private layout of a wall set: walls of several kinds (wall_shapes.c) with prescribed
 * translation, a spin about their axis, or a force servo (servo.c). */
#ifndef SINTER_WALLS_H
#define SINTER_WALLS_H

#include <math.h>

#include "core/core.h"
#include "particles/material.h"

typedef struct sinter_wall {
    /* Read by every search and contact law on every thread, and written only when they change
     * (sinter_walls_move), so that each core keeps its copy of these lines: a store, even of
     * the same value, would make every other core fetch them again (issue 9). */
    double n[3];              /* unit normal into the particle region */
    double p[3];              /* point at the current time [m] */
    double u[3];              /* velocity at the current time [m/s] */
    double temperature;       /* [K], at the current time */
    int kind;                 /* sinter_wall_kind (0 = plane: add_plane zeroes a wall) */
    int inside;               /* cylinder: 1 particles inside, 0 outside */
    int moment_wanted;        /* 1: the laws sum its reaction moment (sinter_walls_set_moment) */
    double axis[3];           /* unit axis: the normal of a planar kind, a cylinder's axis */
    double e1[3], e2[3];      /* rectangle: unit edge directions at the current time */
    double half[2];           /* rectangle: half lengths along e1, e2 [m] */
    double radius;            /* disc, cylinder: radius [m] */
    double half_length;       /* cylinder: its surface's reach from p along the axis [m] */
    struct sinter_mesh *mesh; /* triangle mesh (walls/mesh/): its triangles placed at p0 */
    double spin;              /* angular velocity about axis through p [rad/s] */
    double angle;             /* spin angle at the current time [rad] */
    int turns;                /* mesh: 1 when its triangles turn with the spin about axis through
                                 p (sinter_walls_set_rotation; mesh_rotation.c) */
    double rot[9];            /* a mesh that turns: R(angle) about axis, row-major */
    double turn_reach;        /* a mesh that turns: largest distance of a vertex from p [m] */
    double e1_0[3];           /* rectangle: e1 at angle 0 */
    double p0[3];             /* point of the plane at t = 0 [m] */
    size_t temperature_count; /* > 0: temperature follows (temperature_t, temperature_v) */
    double *temperature_t;
    double *temperature_v;
    int motion;          /* sinter_wall_motion */
    double motion_start; /* [s] */
    double velocity[3];  /* SINTER_WALL_VELOCITY */
    double amplitude[3]; /* SINTER_WALL_SINE */
    double omega;
    size_t schedule_count; /* SINTER_WALL_SCHEDULE */
    double *schedule_t;
    double *schedule_d; /* 3 per point */
    sinter_wall_motion_fn callback;
    void *callback_user;
    sinter_material material;
    int electric_mode;     /* sinter_wall_electric_mode (0 = neutral: add_plane zeroes a wall) */
    double electric_value; /* at the current time: CURRENT: J_ext [A]; POTENTIAL: [V]; NEUTRAL:
                              0 (electric_drive.c) */
    double electric_set;   /* the value set (sinter_walls_set_electric) */
    size_t electric_count; /* > 0: the value follows (electric_t, electric_v) instead */
    double *electric_t;
    double *electric_v;
    double pulse_on, pulse_off; /* pulsed drive: on for pulse_on, off for pulse_off [s] */
    double electric_limit;      /* compliance: the largest |V| of a current electrode or |I| of
                                   a potential one (network model); 0: none */
    int thermal_mode;     /* sinter_wall_thermal_mode (0 = reservoir: add_plane zeroes a wall) */
    double thermal_value; /* RESISTANCE: R'' [m^2 K/W]; TRANSFER: h [W/(m^2 K)]; others 0 */
    /* Written at every step's commit: last, and a cache line away from the next wall's first
     * fields (the array of walls is not line-aligned). */
    double force[3];       /* reaction: force the particles exert on the wall [N] */
    double moment[3];      /* reaction moment about p [N m] */
    double force_local[3]; /* this subdomain's share of force (include/sinter_domain.h) [N] */
    /* force servo (servo.c): state changed at each commit */
    int servo;          /* 1: the wall's motion along its axis is the servo's */
    size_t servo_count; /* target force schedule (servo_t [s], servo_f [N]) */
    double *servo_t, *servo_f;
    double servo_kp;   /* [m/(s N)] */
    double servo_ki;   /* [m/(s^2 N)] */
    double servo_vmax; /* [m/s] */
    double servo_time; /* time of the committed state [s] */
    double servo_disp; /* displacement along the axis at servo_time [m] */
    double servo_v;    /* velocity along the axis from servo_time on [m/s] */
    double servo_int;  /* integral of the force error [N s] */
    char line_gap[64];
} sinter_wall;

/* Signed distance [m] of point x from the plane of wall w, positive on the particles' side. */
static inline double sinter_plane_distance(const sinter_wall *w, const double *x)
{
    return (x[0] - w->p[0]) * w->n[0] + (x[1] - w->p[1]) * w->n[1] + (x[2] - w->p[2]) * w->n[2];
}

/* The other kinds (wall_shapes.c): distance s [m] of centre x from the wall's closest point,
 * positive on the particles' side, and the unit normal n from that point towards x (may be
 * NULL). */
double sinter_wall_shape_contact(const sinter_wall *w, const double *x, double *n);

/* The triangle-mesh kind (walls/mesh/mesh_wall.c): as sinter_wall_shape_contact, and its
 * mesh released. */
double sinter_wall_mesh_contact(const sinter_wall *w, const double *x, double *n);

/* As sinter_wall_shape_contact, for a mesh started from triangle *hint and *hint set to the
 * triangle of the closest point (sinter_mesh_closest_hinted: the same bits with any hint);
 * the other kinds ignore it. */
double sinter_wall_contact_hinted(const sinter_wall *w, const double *x, double *n, uint32_t *hint);
/* sinter_wall_contact_hinted with a certificate per contact (cert[4], cert[3] <= 0: none;
 * sinter_mesh_closest_certified): the same bits, a search only when the sphere left it. */
double sinter_wall_contact_certified(const sinter_wall *w, const double *x, double *n,
                                     uint32_t *hint, double cert[4]);
/* A mesh wall (w->kind SINTER_WALL_MESH): 1 if the signed distance of x is below `bound` [m],
 * the search ending at the bound (sinter_mesh_within; the neighbour list's verdict). */
int sinter_wall_mesh_within(const sinter_wall *w, const double *x, double bound, uint32_t *hint);
void sinter_wall_mesh_free(sinter_walls *walls, sinter_wall *w);

/* A drawing of a mesh wall (mesh_wall.c): its triangle count, and when points is not NULL its
 * triangles where the wall's motion has carried them (9 doubles each [m]) and their unit
 * normals into the particles (3 each, may be NULL). */
size_t sinter_wall_mesh_draw(const sinter_wall *w, double *points, double *normals);

/* Signed distance [m] of centre x from wall w, positive on the particles' side (the one
 * arithmetic every search and check uses, so that their verdicts agree); a plane's is the
 * plane's, inline. */
static inline double sinter_wall_distance(const sinter_wall *w, const double *x)
{
    if (w->kind == 0)
        return sinter_plane_distance(w, x);
    return sinter_wall_shape_contact(w, x, NULL);
}

/* Velocity [m/s] of wall w's surface at point c: its translation, plus its spin about the
 * axis through p (omega a x (c - p)). */
static inline void sinter_wall_velocity_at(const sinter_wall *w, const double *c, double *u)
{
    u[0] = w->u[0], u[1] = w->u[1], u[2] = w->u[2];
    if (w->spin != 0.0) {
        const double r[3] = {c[0] - w->p[0], c[1] - w->p[1], c[2] - w->p[2]};
        const double *a = w->axis, s = w->spin;
        u[0] += s * (a[1] * r[2] - a[2] * r[1]);
        u[1] += s * (a[2] * r[0] - a[0] * r[2]);
        u[2] += s * (a[0] * r[1] - a[1] * r[0]);
    }
}

/* The reaction of one contact added to wall w's moment about its point p: particle-side force
 * f [N] at contact point c, with the rolling moment mr [N m] (NULL: none) the particle got:
 * the wall gets -(c - p) x f - mr. */
static inline void sinter_wall_add_moment(const sinter_wall *w, const double *c, const double *f,
                                          const double *mr, double *moment)
{
    const double r[3] = {c[0] - w->p[0], c[1] - w->p[1], c[2] - w->p[2]};
    moment[0] -= r[1] * f[2] - r[2] * f[1];
    moment[1] -= r[2] * f[0] - r[0] * f[2];
    moment[2] -= r[0] * f[1] - r[1] * f[0];
    if (mr != NULL)
        for (int d = 0; d < 3; ++d)
            moment[d] -= mr[d];
}

/* How far wall w may have come towards any particle since ref (4 doubles written by
 * sinter_wall_reference), for the neighbour list's skin [m]. */
static inline double sinter_wall_moved(const sinter_wall *w, const double *ref)
{
    if (w->kind == 0)
        return fabs(w->n[0] * w->p[0] + w->n[1] * w->p[1] + w->n[2] * w->p[2] - ref[0]);
    const double d[3] = {w->p[0] - ref[0], w->p[1] - ref[1], w->p[2] - ref[2]};
    double moved = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (w->kind == SINTER_WALL_RECTANGLE) /* a turn moves a corner by at most arc length */
        moved += sqrt(w->half[0] * w->half[0] + w->half[1] * w->half[1]) * fabs(w->angle - ref[3]);
    if (w->turns) /* a turning mesh: a vertex moves by at most its distance times the angle */
        moved += w->turn_reach * fabs(w->angle - ref[3]);
    return moved;
}

/* The reference (4 doubles) sinter_wall_moved measures from: a plane's n . p, else the point
 * and the spin angle. */
static inline void sinter_wall_reference(const sinter_wall *w, double *ref)
{
    if (w->kind == 0) {
        ref[0] = w->n[0] * w->p[0] + w->n[1] * w->p[1] + w->n[2] * w->p[2];
        ref[1] = ref[2] = ref[3] = 0.0;
        return;
    }
    ref[0] = w->p[0], ref[1] = w->p[1], ref[2] = w->p[2], ref[3] = w->angle;
}

struct sinter_walls {
    sinter_ctx *ctx;
    size_t count;
    size_t capacity;
    sinter_wall *wall;
    /* written at every step, and a cache line away from the fields above, which every thread
     * reads in its searches and laws (sinter_wall) */
    char line_gap[64];
    double time; /* time of the current p and u */
};

/* Move every wall to time t (sets p and u). Errors: SINTER_ERR_CALLBACK. */
sinter_status sinter_walls_move(sinter_walls *walls, double t);

/* Wall k, or SINTER_ERR_RANGE naming `func`. */
sinter_status sinter_wall_get(const sinter_walls *walls, size_t k, const char *func,
                              sinter_wall **w);

/* In a public function: NULL walls return SINTER_ERR_NULL, a wall k that does not exist
 * SINTER_ERR_RANGE naming the function; otherwise w is wall k. */
#define GET_WALL(walls, k, w)                                                                      \
    do {                                                                                           \
        if ((walls) == NULL)                                                                       \
            return SINTER_ERR_NULL;                                                                \
        sinter_status st_ = sinter_wall_get((walls), (k), __func__, &(w));                         \
        if (st_ != SINTER_OK)                                                                      \
            return st_;                                                                            \
    } while (0)

/* Wall w's axis (its normal) and a frame of unit edges e1, e2 normal to it (wall_shapes.c). */
void sinter_wall_frame(sinter_wall *w);

/* A drawing of a wall that is not a plane (wall_shapes.c): its polygons' points (at most
 * 4 * SINTER_WALL_OUTLINE_SEGMENTS), each polygon's point count in sizes and its normal into
 * the particles; an infinite cylinder over the box [lo, hi]; a mesh none (sinter_wall_mesh_draw
 * draws it). Returns the polygon count. */
#define SINTER_WALL_OUTLINE_SEGMENTS 32
int sinter_wall_outline(const sinter_wall *w, const double lo[3], const double hi[3],
                        double (*points)[3], int *sizes, double (*normals)[3]);

/* The force servo (servo.c): its displacement and velocity along the axis at time t, its
 * controller advanced to the committed reaction at time t, its schedule freed. */
void sinter_wall_servo_at(const sinter_wall *w, double t, double *disp, double *vel);
void sinter_walls_servo_commit(sinter_walls *walls, double t);
void sinter_wall_servo_free(sinter_walls *walls, sinter_wall *w);

/* R(angle) about unit axis a (Rodrigues), row-major, into rot (mesh_rotation.c). */
void sinter_wall_rotation_matrix(const double *a, double angle, double *rot);

/* The electric drive (electric_drive.c): the wall's value at time t [s], and its schedule
 * freed. */
double sinter_wall_drive_value(const sinter_wall *w, double t);
void sinter_wall_drive_free(sinter_walls *walls, sinter_wall *w);

#endif
