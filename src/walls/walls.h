/* Private layout of a wall set: planes with prescribed translation. */
#ifndef SINTER_WALLS_H
#define SINTER_WALLS_H

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
    double force[3]; /* reaction: force the particles exert on the wall [N] */
    char line_gap[64];
} sinter_wall;

/* Signed distance [m] of point x from the plane of wall w, positive on the particles' side
 * (the one arithmetic every search and check uses, so that their verdicts agree). */
static inline double sinter_wall_distance(const sinter_wall *w, const double *x)
{
    return (x[0] - w->p[0]) * w->n[0] + (x[1] - w->p[1]) * w->n[1] + (x[2] - w->p[2]) * w->n[2];
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

/* The electric drive (electric_drive.c): the wall's value at time t [s], and its schedule
 * freed. */
double sinter_wall_drive_value(const sinter_wall *w, double t);
void sinter_wall_drive_free(sinter_walls *walls, sinter_wall *w);

#endif
