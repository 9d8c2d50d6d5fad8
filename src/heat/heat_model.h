/* Private interface of heat submodels (built-in and host). */
#ifndef SINTER_HEAT_MODEL_H
#define SINTER_HEAT_MODEL_H

#include "sinter_submodel.h"
#include "contact/contacts.h"

#define SINTER_HEAT_MAX_PARAMS 16
#define SINTER_HEAT_MAX_OUTPUTS 4

/* Everything one evaluation of one heat model reads and writes. */
typedef struct sinter_heat_eval {
    sinter_ctx *ctx;
    const sinter_particles *ps;
    const sinter_walls *walls;     /* may be NULL */
    const sinter_contact_list *pp; /* particle-particle contacts */
    const sinter_contact_list *pw; /* particle-wall contacts */
    double time;                   /* [s] */
    double *heat;                  /* power into each particle [W], accumulated */
    /*
     * Implicit conduction: when g_pp is not NULL, a conduction model adds its
     * conductance G [W/K] per contact to g_pp / g_pw (the wall side held at
     * the wall's temperature) INSTEAD of adding conduction power to `heat`.
     */
    double *g_pp;
    double *g_pw;
    const sinter_state_view *view; /* for host callbacks */
    /* the Joule power each particle received from the last network electric solve [W] (the
     * "joule" model's energy-consistent source), or NULL without a network model */
    const double *joule_dissipation;
    /* k(theta) of each particle [W/(m K)] when a material has a conductivity table
     * (particles/property_table.h), else NULL: the materials' constants */
    const double *conductivity;
    /* the particle-particle candidate pairs the contacts were found among (the neighbour
     * search's, widened by the gas reach: gas_gap.h), or NULL */
    const struct sinter_pair_list *pairs;
    /* the power the contacts dissipated in the force evaluation of this state [W], 2 per
     * particle (normal damping, sliding: sinter_force_ops.dissipation), or NULL */
    const double *dissipation;
    /* the particles' flags, on which the beam models set SINTER_PARTICLE_LIT for each particle
     * they give power to (beam.c, beam_rays.c), or NULL: they mark nothing */
    uint32_t *flags;
    /* Periodic boundaries (ghosts/ghosts.h): rows [0, owned) are the owned particles, and row
     * owned + k is an image (ghost) of particle ghost_owner[k]; ghost_owner is NULL without
     * images (then owned is not read: every row is owned). A source of one particle
     * (radiation, convection, the beams, eq. 35's Joule heat) acts on owned rows only, so that
     * an image does not count it a second time (issue 38); a pair term uses every row, and the
     * stepper adds what it put on an image to the image's owner (the reverse halo). */
    size_t owned;
    const uint32_t *ghost_owner;
    /* Across subdomains (issue 43, domain/domain.h): the host's collective operations, or NULL.
     * Rows [owned, count) are then ghosts of other subdomains' particles (ghost_owner NULL):
     * sources act on the owned rows, and a model that needs other particles than a pair's
     * (the beams' top surface and shadows) gets them through the domain (collective: every
     * subdomain evaluates the same models at the same states). */
    struct sinter_domain *domain;
} sinter_heat_eval;

/* The rows a source of one particle acts on: the owned particles (see owned above). */
static inline size_t sinter_heat_owned(const sinter_heat_eval *e)
{
    return e->ghost_owner != NULL || e->domain != NULL ? e->owned : e->ps->count;
}

/* The conductivity of particle i in evaluation e: k(theta_i) when tabulated, else its
 * material's entry of kmat. */
static inline double sinter_heat_conductivity(const sinter_heat_eval *e, const double *kmat,
                                              size_t i)
{
    return e->conductivity != NULL ? e->conductivity[i] : kmat[e->ps->material[i]];
}

typedef struct sinter_heat_ops {
    const char *name;
    int conduction; /* 1: linear in temperatures through contact conductances (eval honours g_pp) */
    const char *keys[SINTER_HEAT_MAX_PARAMS]; /* parameters, NULL-terminated */
    double defaults[SINTER_HEAT_MAX_PARAMS];
    sinter_status (*eval)(const sinter_heat_model *hm, sinter_heat_eval *e);
    /* 1 if an evaluation at time t reads the geometry (n, delta, dist, area, branch) of
     * e->pp; NULL: it reads no contact geometry. A model reading it must set this. */
    int (*reads_geometry)(const sinter_heat_model *hm, double t);
} sinter_heat_ops;

struct sinter_heat_model {
    sinter_ctx *ctx;
    const sinter_heat_ops *ops;
    char name[64];
    double param[SINTER_HEAT_MAX_PARAMS];
    size_t schedule_count[SINTER_HEAT_MAX_PARAMS]; /* 0: constant */
    double *schedule_t[SINTER_HEAT_MAX_PARAMS];
    double *schedule_v[SINTER_HEAT_MAX_PARAMS];
    sinter_heat_callbacks host;
    void *user;
    sinter_heat_ops host_ops;
    double output[SINTER_HEAT_MAX_OUTPUTS]; /* written by each evaluation (ops->outputs) */
    /* a scan path (scan_path.h) driving the parameters path_key[0..2] (x, y, the power), or NULL */
    struct sinter_scan_path *path;
    int path_key[3];
};

/* Value of parameter k at time t (its schedule if it has one; a scan path's position for the
 * axis point, and the power times the path's level). */
double sinter_heat_param(const sinter_heat_model *hm, int k, double t);

/* How far the axis point (parameters "x" and "y": the laser, the nozzle, the beam) of hm moves
 * from t to t + h [m]: the chord of its schedules or scan path over the interval; 0 for a model
 * without an axis point. */
double sinter_heat_axis_travel(const sinter_heat_model *hm, double t, double h);

/* Built-in models, one file each. */
extern const sinter_heat_ops sinter_heat_conduction;
extern const sinter_heat_ops sinter_heat_convection;
extern const sinter_heat_ops sinter_heat_radiation;
extern const sinter_heat_ops sinter_heat_nozzle;
extern const sinter_heat_ops sinter_heat_laser;
extern const sinter_heat_ops sinter_heat_joule;
extern const sinter_heat_ops sinter_heat_beam;
extern const sinter_heat_ops sinter_heat_dissipation;
/* Names of "beam"'s outputs (sinter_heat_model.output, sinter_heat_model_output), NULL-ended. */
extern const char *const sinter_heat_beam_outputs[SINTER_HEAT_MAX_OUTPUTS + 1];

/* Host model evaluation (host.c). */
sinter_status sinter_heat_host_eval(const sinter_heat_model *hm, sinter_heat_eval *e);
int sinter_heat_host_reads_geometry(const sinter_heat_model *hm, double t); /* 1: contact radii */

/* 1 if an evaluation of hm at time t reads the contact list's geometry. */
static inline int sinter_heat_reads_geometry(const sinter_heat_model *hm, double t)
{
    return hm->ops->reads_geometry != NULL && hm->ops->reads_geometry(hm, t);
}

#endif
