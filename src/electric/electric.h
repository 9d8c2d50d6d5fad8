/*
 * Private interface of the electric submodels: steady current through the contact graph
 * (seed 000 sec. 5, eq. 38-44). The public handle is created by name in electric.c; a stepper
 * calls sinter_electric_solve() once per evaluation, after the contact lists are up to date.
 *
 * The two built-in models differ in what they conserve:
 *  - "averaged" (averaged.c) is the seed's model: a current MAGNITUDE imposed by the walls and
 *    propagated through the packing by contact-area-weighted averaging (eq. 42-43). It is a
 *    smoothing of the wall values, not a conservation law: in a chain the magnitude varies
 *    linearly between two walls of different J_ext (remark 4), and a branch does not split the
 *    current.
 *  - "network" (network.c) treats every contact as a resistor and solves Kirchhoff's current
 *    law per particle (charge conservation, eq. 39, exactly): a chain carries one current,
 *    parallel paths split it by conductance.
 */
#ifndef SINTER_ELECTRIC_H
#define SINTER_ELECTRIC_H

#include "sinter_submodel.h"
#include "contact/contacts.h"
#include "domain/solve.h"
#include "particles/particles.h"
#include "walls/walls.h"

typedef enum sinter_electric_kind {
    SINTER_ELECTRIC_AVERAGED = 0,
    SINTER_ELECTRIC_NETWORK = 1
} sinter_electric_kind;

/* SUNDIALS PCG objects of the network model (network.c). */

struct sinter_electric_model {
    sinter_ctx *ctx;
    int kind; /* sinter_electric_kind */
    char name[16];
    double tolerance;      /* relative, see sinter.h */
    double max_iterations; /* sweeps (averaged) or PCG iterations (network), integral */

    /* Results of the last solve, for inspection (tests, diagnostics). */
    size_t last_iterations;
    size_t node_count;    /* network: particles then walls; 0 after an averaged solve */
    double *potential;    /* network: node potentials [V] (node n + w is wall w) */
    size_t open_clusters; /* network: clusters left without current (open circuit) */
    size_t warm_nodes;    /* network: nodes of the last solve, whose potentials start the next
                             (0: none; see network.c) */
    /* network: the ids of the last solve's particle nodes, warm_id_count of them (0: unknown,
     * the potentials were restored by row), and the scratch that moves the warm start to the
     * particles' new rows after a reordering (warm_ids.c) */
    uint64_t *warm_id, *warm_pairs;
    double *warm_moved;
    size_t warm_id_count, warm_id_capacity, warm_pairs_capacity, warm_moved_capacity;
    /* network: the power of the last solve (network.c): delivered by the driven walls, and
     * dissipated in the contacts, per particle (its share) and in all [W] */
    double supplied_power, dissipated_power;
    double *dissipation; /* per particle, dissipation_count of them (0: none yet) */
    size_t dissipation_count, dissipation_capacity;
    /* network: each wall's mode and value in the solve under way (a compliance limit may
     * switch a wall: network.c) */
    int *wall_mode;
    double *wall_value;
    size_t wall_mode_capacity, wall_value_capacity;
    /* network: the conductivities follow seed 000 eq. 50's temperature term (network.c) */
    double sigmoid, theta_ref, k1, gamma1;
    /* network: host conductance law and Joule split (host.c; struct_size 0: none), the heat a
     * host split gave the electrodes in the last solve [W], and their scratch: per contact
     * (particle-particle first, then particle-wall) the conductance, power and share, per
     * particle the conductivity, the contact radii, the view's wall arrays */
    sinter_electric_callbacks host;
    void *host_user;
    double electrode_heat;
    double *host_g, *host_power, *host_share, *host_sigma, *host_radius, *host_walls;
    size_t host_g_capacity, host_power_capacity, host_share_capacity, host_sigma_capacity;
    size_t host_radius_capacity, host_walls_capacity;
    uint32_t *edge_contact; /* network: the contact of each edge (pp index, or pp count + pw) */
    /* network: the owner of each image row of the solve under way (periodic boundaries:
     * ghosts/ghosts.h), or NULL without images */
    const uint32_t *ghost_owner;
    size_t edge_contact_capacity;
    /* network: sigma(theta) of each particle when a material tabulates it (issue 39) */
    double *sigma_table;
    size_t sigma_table_capacity;

    /* Scratch reused across solves (grown on demand, never shrunk). */
    size_t potential_capacity;
    uint32_t *adj_start; /* averaged: CSR offsets, n + 1 */
    size_t adj_start_capacity;
    uint32_t *adj_other; /* averaged: neighbour of each CSR entry */
    double *adj_area;    /* averaged: contact area of each CSR entry [m^2] */
    size_t adj_other_capacity, adj_area_capacity;
    double *wall_sum;  /* averaged: sum A |J_ext| over current-wall contacts, per particle */
    double *wall_area; /* averaged: sum A over current-wall contacts, per particle */
    size_t wall_sum_capacity, wall_area_capacity;
    uint32_t *queue; /* averaged: breadth-first search */
    size_t queue_capacity;
    unsigned char *state; /* averaged: per particle; network: per node */
    size_t state_capacity;
    /* averaged, on one subdomain of a decomposed run (domain/domain.h; NULL: the whole body):
     * the host's collective operations, and a row per particle for their halos */
    struct sinter_domain *averaged_domain;
    /* averaged: 1 in the stepper's reproducible mode (set by the stepper before each solve):
     * Jacobi sweeps with exact sums, the same bits for any decomposition (averaged.c) */
    int reproducible;
    double *averaged_rows;
    size_t averaged_rows_capacity;
    uint32_t *edge_a, *edge_b; /* network: conducting edges between nodes */
    double *edge_g;            /* network: their conductances [S] */
    size_t edge_a_capacity, edge_b_capacity, edge_g_capacity;
    uint32_t *parent; /* network: union-find over nodes */
    size_t parent_capacity;
    double *net, *scale; /* network: per cluster root: net injected current, sum |J_ext| [A] */
    size_t net_capacity, scale_capacity;
    uint32_t *pin; /* network: per cluster root: node pinned at 0 V, or UINT32_MAX */
    size_t pin_capacity;
    double *diag; /* network: Jacobi diagonal */
    size_t diag_capacity;
    /* network: the edges between two free nodes, in edge order: the PCG operator's couplings,
     * so that its loop reads no node state (the press scene's main cost) */
    uint32_t *free_a, *free_b;
    double *free_g;
    size_t free_a_capacity, free_b_capacity, free_g_capacity, free_edges;
    size_t edge_count;
    struct sinter_pcg *pcg; /* network model: the PCG solver (core/pcg.h) */
    size_t pcg_nodes;       /* unknowns of the solve under way */
    /* network across subdomains (network_domain.c; NULL: one domain): the host's operations
     * for the solve under way (set by the stepper), the ghosts' values and reductions, the
     * clusters' global labels per node, and the walls' reduced words */
    sinter_domain *domain;
    sinter_domain_solve across;
    uint64_t *label;
    size_t label_capacity;
    uint64_t *wall_words;
    size_t wall_words_capacity;
    double *wall_sums; /* per wall, summed over the subdomains */
    size_t wall_sums_capacity;
    long rank;                         /* this subdomain's number in the solve under way */
    size_t across_owned, across_nodes; /* its owned particles and nodes (+ walls) */
    int across_walls_free;             /* a current wall's potential is an unknown */
    /* network in the reproducible mode (em->reproducible, issue 43): a free current wall's
     * row, diagonal and the norms are exact sums over every subdomain (network.c); the free
     * edges to walls grouped by wall (repro_start[w] .. repro_start[w + 1] in repro_edge), and
     * the terms of one product */
    uint32_t *repro_edge;
    size_t repro_edge_capacity;
    size_t *repro_start;
    size_t repro_start_capacity;
    double *repro_a, *repro_b;
    size_t repro_a_capacity, repro_b_capacity;
};

/*
 * Solve the model on the current contact state: write ps->current [A] for every particle and
 * set SINTER_PARTICLE_ELECTRIFIED on the particles touching a driven wall (cleared on the
 * others). `walls` may be NULL only when pw is empty. With periodic images (ps->ghost_count
 * rows after the owned particles, ghosts/ghosts.h) sinter_electric_solve_images, whose
 * `ghost_owner` names each image's owner:
 * the network's unknowns are the owned particles, an image stands for its owner (network.c);
 * the averaged model refuses images. *iterations (may be NULL) receives the
 * sweeps or PCG iterations of this solve. Errors: SINTER_ERR_NULL, SINTER_ERR_INVALID (a model
 * cannot use a wall's mode), SINTER_ERR_NOT_CONVERGED (the currents of the last iterate are
 * kept), SINTER_ERR_NOMEM.
 */
sinter_status sinter_electric_solve(sinter_electric_model *em, sinter_particles *ps,
                                    const sinter_walls *walls, const sinter_contact_list *pp,
                                    const sinter_contact_list *pw, size_t *iterations);
sinter_status sinter_electric_solve_images(sinter_electric_model *em, sinter_particles *ps,
                                           const sinter_walls *walls, const sinter_contact_list *pp,
                                           const sinter_contact_list *pw,
                                           const uint32_t *ghost_owner, size_t *iterations);

/* The Joule power each particle receives from the last network solve [W] (n values, 0 on
 * images: their owners have it), or NULL when the model is not a network or its last solve
 * was not over n particles. */
const double *sinter_electric_dissipation(const sinter_electric_model *em, size_t n);

/* The network's per-node state bits (a cluster's bits live on its union-find root). */
enum {
    NODE_FREE = 1,
    CLUSTER_GROUND = 2,
    CLUSTER_CURRENT = 4,
    CLUSTER_PARTICLE = 8,
    CLUSTER_SOLVED = 16,
    CLUSTER_UNLIMITED = 32 /* holds a current wall without a compliance limit */
};

/* The network's union-find over nodes: the root of p (path halving), and a union in which the
 * smaller index becomes the root. */
static inline uint32_t sinter_network_root(uint32_t *parent, uint32_t p)
{
    while (parent[p] != p) {
        parent[p] = parent[parent[p]]; /* path halving */
        p = parent[p];
    }
    return p;
}

static inline void sinter_network_unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = sinter_network_root(parent, a);
    b = sinter_network_root(parent, b);
    if (a != b)
        parent[a > b ? a : b] = a < b ? a : b;
}

/*
 * The network across subdomains (network_domain.c), with em->domain set: clusters found over
 * every subdomain (em->state of the nodes [0, owned + walls + ghosts)), and the wall nodes'
 * rows of an operator product summed over the subdomains.
 */
sinter_status sinter_network_classify_across(sinter_electric_model *em, const sinter_walls *walls,
                                             const sinter_particles *ps, size_t nw);

/* The two models (averaged.c, network.c); arguments are checked by sinter_electric_solve. */
sinter_status sinter_electric_solve_averaged(sinter_electric_model *em, sinter_particles *ps,
                                             const sinter_walls *walls,
                                             const sinter_contact_list *pp,
                                             const sinter_contact_list *pw);
sinter_status sinter_electric_solve_network(sinter_electric_model *em, sinter_particles *ps,
                                            const sinter_walls *walls,
                                            const sinter_contact_list *pp,
                                            const sinter_contact_list *pw);

/* Host callbacks (host.c), for the network model's solve: the conductances g of the contacts
 * of pp then pw from the particles' conductivities sigma, and the share of each contact's power
 * (power, same order) that goes to its particle i. Errors: SINTER_ERR_CALLBACK (a callback
 * returned non-zero), SINTER_ERR_DOMAIN (a value out of range), SINTER_ERR_NOMEM. */
sinter_status
sinter_electric_host_conductance(sinter_electric_model *em, const sinter_particles *ps,
                                 const sinter_walls *walls, const sinter_contact_list *pp,
                                 const sinter_contact_list *pw, const double *sigma, double *g);
sinter_status sinter_electric_host_split(sinter_electric_model *em, const sinter_particles *ps,
                                         const sinter_walls *walls, const sinter_contact_list *pp,
                                         const sinter_contact_list *pw, const double *power,
                                         double *share);

/* The conductance [S] build_edges gives a contact (particle i with particle j, or with a
 * non-neutral wall when `wall` is 1) of contact area `area` and centre (or centre-plane) distance
 * `dist`, eq. 50's term included; NaN under a host conductance law, 0 for an insulating one. For
 * reports of the last solve's contact currents (contact/snapshot.c). */
double sinter_electric_contact_conductance(const sinter_electric_model *em,
                                           const sinter_particles *ps, uint32_t i, uint32_t j,
                                           int wall, double area, double dist);

/* The network model's warm start (network.c): the potentials of its last solve, *nodes of
 * them (0 and NULL when the next solve starts from 0), for a checkpoint. */
const double *sinter_electric_warm_potentials(const sinter_electric_model *em, size_t *nodes);

/* Before a solve over n particle nodes (nodes in all): when the warm start is of that many
 * nodes and its particles' ids are known but sit in other rows now, move each potential to its
 * particle's row (a particle the last solve did not have: start from 0). After a solve: keep the
 * ids of its n particle rows. (warm_ids.c) Errors: SINTER_ERR_NOMEM. */
sinter_status sinter_electric_warm_follow(sinter_electric_model *em, const sinter_particles *ps,
                                          size_t n, size_t nodes);
sinter_status sinter_electric_warm_record_ids(sinter_electric_model *em, const sinter_particles *ps,
                                              size_t n);

/* Restore them from `phi`, nodes doubles at any alignment (a checkpoint's; nodes = 0 clears
 * them). Errors: SINTER_ERR_NOMEM. */
sinter_status sinter_electric_set_warm_potentials(sinter_electric_model *em, const void *phi,
                                                  size_t nodes);

/*
 * Storage for at least `count` elements of `size` bytes at `ptr` (contents kept, capacity in
 * elements updated): the grown block, `ptr` itself if it is large enough, or NULL when out of
 * memory (then `ptr` is untouched and the error is recorded on ctx).
 */
void *sinter_electric_reserve(sinter_ctx *ctx, void *ptr, size_t *capacity, size_t count,
                              size_t size);

/* Grow scratch field `field` of `em` (with its `field`_capacity) to `count` elements. */
#define SINTER_ELECTRIC_RESERVE(em, field, count)                                                  \
    do {                                                                                           \
        void *grown_ = sinter_electric_reserve((em)->ctx, (em)->field, &(em)->field##_capacity,    \
                                               (count), sizeof(*(em)->field));                     \
        if (grown_ == NULL)                                                                        \
            return sinter_last_status((em)->ctx);                                                  \
        (em)->field = grown_;                                                                      \
    } while (0)

#endif
