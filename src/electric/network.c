/*
 * The "network" electric model: Kirchhoff's current law on the contact network.
 *
 * Seed 000 eq. 39 (steady charge conservation, div J = 0) is imposed exactly on a resistor
 * network instead of through the radial-flow simplification of eq. 41-42 used by "averaged.c".
 *
 * Nodes: the n particles (unknown potentials phi_i) and the walls (node n + w).
 * Edges (resistors):
 *  - a particle pair in contact: G_ij = sigma_ij A_ij / d_ij with A_ij = pi a_ij^2 of the
 *    contact list, d_ij the centre distance and (r_i + r_j) / sigma_ij = r_i / sigma_i +
 *    r_j / sigma_j, the harmonic rule of seed 003 eq. 35 (as heat conduction does), written as
 *    sigma_i sigma_j (r_i + r_j) / (r_i sigma_j + r_j sigma_i) so that a non-conducting side
 *    gives G = 0;
 *  - a particle touching a non-neutral wall: G = sigma_i A / d with the particle's own
 *    conductivity and d its centre-to-plane distance (as heat conduction's wall contact).
 *   Neutral walls are insulators: their contacts are not edges.
 * Boundary conditions:
 *  - SINTER_WALL_POTENTIAL: the wall node is held at its potential (Dirichlet);
 *  - SINTER_WALL_CURRENT: the wall is an equipotential electrode whose potential V_w is an
 *    unknown and which injects its total current J_ext: sum_i G_iw (V_w - phi_i) = J_ext
 *    (> 0 into the particles). The split of J_ext among the particles touching the wall is thus
 *    decided by the network (more goes where the path is more conductive).
 * Equations: for every free node p, sum_q G_pq (phi_p - phi_q) = s_p (s = J_ext for a current
 * wall, 0 for a particle): a symmetric weighted graph Laplacian.
 * Clusters (connected through particle contacts and current walls; a potential wall fixes its
 * neighbours' potential scale and so does not join them):
 *  - touching a potential wall: solved (symmetric positive definite);
 *  - otherwise, with current walls whose net current is zero (to 1e-9 of sum |J_ext|): solved
 *    with one current wall pinned at 0 V (potentials are defined up to a constant; currents are
 *    not affected);
 *  - otherwise the circuit is open (no return path: a single electrode touching the powder, or
 *    currents that do not balance): the cluster carries no current and a warning is logged;
 *  - clusters touching no driven wall carry no current.
 * Solution: SUNDIALS PCG with a matrix-free operator and a Jacobi preconditioner (the pattern of
 * stepper/thermal.c); pinned nodes are identity rows that keep their value exactly; stopping test
 * ||b - A phi||_2 <= tolerance ||b||_2 over the free rows, started from the potentials of the
 * model's last solve when it had as many nodes (a stepper's last step: a close start, a sixth of
 * the iterations over the press scene; moved with the particles by id after a reordering:
 * warm_ids.c), from phi = 0 otherwise; the test, and so the accuracy,
 * is the same either way. Checkpoints keep these potentials, so a restart continues bit for bit
 * (sinter_electric_warm_potentials).
 * Output: the current through contact (p, q) is I = G_pq (phi_p - phi_q); a particle's current is
 * half the sum of |I| over its conducting contacts (wall contacts included), i.e. what flows
 * through it: in a chain, the chain's current; at an electrode, what it receives from the wall.
 *
 * Periodic boundaries (issue 38; ghosts/ghosts.h): the unknowns are the owned particles only
 * (nodes 0 .. owned - 1, walls after them); a contact with an image (a ghost row) is an edge to
 * the image's owner, whose potential the image has, so a pair across a periodic face is one
 * resistor between the two owners and its Joule power goes to them. A periodic axis carries no
 * imposed potential drop (the potential is periodic along it: a drop across the cell would be a
 * jump at the face, which no resistor can carry); electrodes are walls across a non-periodic
 * axis, and the periodic axes are the transverse ones of an infinite slab between them.
 */
#include <math.h>
#include <string.h>

#include "core/pcg.h"
#include "domain/exact_reduce.h"
#include "electric.h"

static const uint32_t NO_NODE = UINT32_MAX;

/* The owned particles of ps: the particle nodes (the rows after them are images). */
static inline size_t owned_count(const sinter_particles *ps)
{
    return ps->count - ps->ghost_count;
}

/* The node of particle row j: the row itself, or an image's owner (em->ghost_owner). */
static inline uint32_t node_of(const sinter_electric_model *em, size_t owned, uint32_t j)
{
    return j < owned ? j : em->ghost_owner[j - owned];
}

/*
 * The reproducible mode (em->reproducible, issue 43): a particle's row adds its terms in the
 * order of the pair list, which the mode sorts by ids, so that its bits do not depend on the
 * decomposition; a free current wall's row gathers the edges of every subdomain, so its
 * diagonal and its products are exact sums over them (domain/exact_reduce.h), without domain
 * operations too (the same bits). The first subdomain (or the only one) adds the diagonal term.
 * Free edges to walls grouped by wall: wall w's are repro_edge[repro_start[w] ..
 * repro_start[w + 1]).
 */
static sinter_status repro_group(sinter_electric_model *em, size_t n, size_t nw)
{
    SINTER_ELECTRIC_RESERVE(em, repro_start, nw + 2);
    SINTER_ELECTRIC_RESERVE(em, repro_edge, em->free_edges + 1);
    size_t *start = em->repro_start;
    memset(start, 0, (nw + 2) * sizeof(size_t));
    for (size_t e = 0; e < em->free_edges; ++e)
        if (em->free_b[e] >= n && em->free_b[e] < n + nw)
            start[em->free_b[e] - n + 2]++;
    for (size_t w = 0; w < nw; ++w)
        start[w + 2] += start[w + 1];
    for (size_t e = 0; e < em->free_edges; ++e)
        if (em->free_b[e] >= n && em->free_b[e] < n + nw)
            em->repro_edge[start[em->free_b[e] - n + 1]++] = (uint32_t)e;
    return SINTER_OK;
}

/* The free walls' rows as exact sums: of z = A v (vv not NULL: the diagonal term and each
 * edge's -g v_a) or of the diagonal (vv NULL: each edge's g), into out[n + w]. */
static void repro_wall_rows(sinter_electric_model *em, const double *vv, double *out, size_t n,
                            size_t nw)
{
    const size_t *start = em->repro_start;
    double *ta = em->repro_a, *tb = em->repro_b;
    for (size_t w0 = 0; w0 < nw; w0 += SINTER_REPRO_BATCH) {
        const size_t m = nw - w0 < SINTER_REPRO_BATCH ? nw - w0 : SINTER_REPRO_BATCH;
        const double *a[SINTER_REPRO_BATCH], *b[SINTER_REPRO_BATCH];
        size_t count[SINTER_REPRO_BATCH], pos = 0;
        double sum[SINTER_REPRO_BATCH];
        for (size_t c = 0; c < m; ++c) {
            const size_t w = w0 + c, first = pos;
            a[c] = ta + pos;
            b[c] = tb + pos;
            if (em->state[n + w] & NODE_FREE) {
                if (vv != NULL && em->rank == 0) {
                    ta[pos] = em->diag[n + w];
                    tb[pos++] = vv[n + w];
                }
                for (size_t k = start[w]; k < start[w + 1]; ++k) {
                    const uint32_t e = em->repro_edge[k];
                    ta[pos] = vv != NULL ? -em->free_g[e] : em->free_g[e];
                    tb[pos++] = vv != NULL ? vv[em->free_a[e]] : 1.0;
                }
            }
            count[c] = pos - first;
        }
        if (em->across.failed ||
            sinter_domain_exact_sums(em->ctx, em->domain, m, a, b, count, sum) != SINTER_OK) {
            em->across.failed = 1;
            memset(sum, 0, sizeof(sum));
        }
        for (size_t c = 0; c < m; ++c)
            if (em->state[n + w0 + c] & NODE_FREE)
                out[n + w0 + c] = sum[c];
    }
}

/* z = A v: Jacobi diagonal times v minus the couplings between free nodes (a coupling to a
 * pinned node lives in the right-hand side). */
static void apply_operator(const double *vv, double *zz, void *data)
{
    sinter_electric_model *em = data;
    const uint32_t *fa = em->free_a, *fb = em->free_b;
    const double *fg = em->free_g;
    for (size_t p = 0; p < em->pcg_nodes; ++p)
        zz[p] = em->diag[p] * vv[p];
    for (size_t e = 0; e < em->free_edges; ++e) {
        const uint32_t a = fa[e], b = fb[e];
        zz[a] -= fg[e] * vv[b];
        zz[b] -= fg[e] * vv[a];
    }
    if (em->reproducible && em->across_walls_free)
        repro_wall_rows(em, vv, zz, em->across_owned, em->across_nodes - em->across_owned);
}

/*
 * The product across subdomains (domain/solve.h): the ghosts' values through the forward
 * halo; a free current wall's row summed over the subdomains (the diagonal term on the first
 * only, which on one subdomain makes the operations those of apply_operator).
 */
static void apply_operator_across(const double *vv, double *zz, void *data)
{
    sinter_electric_model *em = data;
    const size_t n = em->across_owned, nodes = em->across_nodes, nw = nodes - n;
    sinter_domain_solve_forward(&em->across, vv);
    const double *ghost = em->across.rows; /* node nodes + k is row n + k */
    const uint32_t *fa = em->free_a, *fb = em->free_b;
    const double *fg = em->free_g;
    for (size_t p = 0; p < em->pcg_nodes; ++p)
        zz[p] = p >= n && p < nodes && (em->state[p] & NODE_FREE) && em->rank != 0
                    ? 0.0
                    : em->diag[p] * vv[p];
    for (size_t e = 0; e < em->free_edges; ++e) {
        const uint32_t a = fa[e], b = fb[e];
        zz[a] -= fg[e] * (b < nodes ? vv[b] : ghost[b - nw]);
        if (b < nodes)
            zz[b] -= fg[e] * vv[a];
    }
    if (!em->across_walls_free)
        return;
    if (em->reproducible) {
        repro_wall_rows(em, vv, zz, n, nw);
        return;
    }
    double *sum = em->wall_sums;
    for (size_t w = 0; w < nw; ++w)
        sum[w] = em->state[n + w] & NODE_FREE ? zz[n + w] : 0.0;
    if (!em->across.failed && sinter_domain_reduce(em->ctx, em->domain, sum, nw, SINTER_REDUCE_F64,
                                                   SINTER_REDUCE_SUM) != SINTER_OK)
        em->across.failed = 1;
    for (size_t w = 0; w < nw; ++w)
        if (em->state[n + w] & NODE_FREE)
            zz[n + w] = sum[w];
}

/* Jacobi preconditioner: z = r / diag. */
static void precondition(const double *rr, double *zz, void *data)
{
    const sinter_electric_model *em = data;
    for (size_t p = 0; p < em->pcg_nodes; ++p)
        zz[p] = rr[p] / em->diag[p];
}

static uint32_t find_root(uint32_t *parent, uint32_t p)
{
    return sinter_network_root(parent, p);
}

static void unite(uint32_t *parent, uint32_t a, uint32_t b)
{
    sinter_network_unite(parent, a, b);
}

/*
 * A particle's conductivity [S/m]: its material's sigma_0, times seed 000 eq. 50's temperature
 * term 1 + k1 s(gamma1 (theta - theta_ref)), s(x) = 1 / (1 + e^-x), when "sigmoid" = 1 (the
 * field term of eq. 50 would make the network nonlinear in its own solution and is left to the
 * "joule" model's eq. 35 reading). 0 with *bad set when eq. 50 gives no positive value.
 */
static inline __attribute__((always_inline)) double
conductivity_from(const sinter_electric_model *em, const sinter_particles *ps, size_t i, int *bad,
                  double sigma0)
{
    if (em->sigmoid == 0.0)
        return sigma0;
    const double x = em->gamma1 * (ps->temperature[i] - em->theta_ref);
    const double sigma = sigma0 * (1.0 + em->k1 / (1.0 + exp(-x)));
    if (sigma0 > 0.0 && !(sigma > 0.0 && isfinite(sigma)))
        *bad = 1;
    return sigma;
}

/* sigma_0 is the material's, or sigma(theta) from `table` (tabulated_sigma) when not NULL. */
static inline __attribute__((always_inline)) double conductivity(const sinter_electric_model *em,
                                                                 const sinter_particles *ps,
                                                                 size_t i, int *bad,
                                                                 const double *table)
{
    return conductivity_from(
        em, ps, i, bad,
        table != NULL ? table[i] : sinter_particle_param(ps, i, SINTER_MAT_ELECTRIC_CONDUCTIVITY));
}

/* sigma(theta) of every particle into em->sigma_table when a material tabulates it (issue 39),
 * *table NULL otherwise (the materials' constants, read where they are needed). */
static sinter_status tabulated_sigma(sinter_electric_model *em, const sinter_particles *ps,
                                     const double **table)
{
    *table = NULL;
    if (!ps->tabulated[SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY])
        return SINTER_OK;
    SINTER_ELECTRIC_RESERVE(em, sigma_table, ps->count + 1);
    for (size_t i = 0; i < ps->count; ++i)
        em->sigma_table[i] = sinter_particle_property_tabulated(
            ps, i, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY, SINTER_MAT_ELECTRIC_CONDUCTIVITY);
    *table = em->sigma_table;
    return SINTER_OK;
}

double sinter_electric_contact_conductance(const sinter_electric_model *em,
                                           const sinter_particles *ps, uint32_t i, uint32_t j,
                                           int wall, double area, double dist)
{
    if (em->host.conductance != NULL)
        return NAN;
    int bad = 0;
    const double si =
        conductivity_from(em, ps, i, &bad,
                          sinter_particle_property(ps, i, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY,
                                                   SINTER_MAT_ELECTRIC_CONDUCTIVITY));
    double g = 0.0;
    if (wall) {
        g = dist > 0.0 ? si * area / dist : 0.0;
    } else {
        const double *r = ps->radius;
        const double sj =
            conductivity_from(em, ps, j, &bad,
                              sinter_particle_property(ps, j, SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY,
                                                       SINTER_MAT_ELECTRIC_CONDUCTIVITY));
        const double den = r[i] * sj + r[j] * si; /* seed 003 eq. 35, as build_edges */
        g = den > 0.0 && dist > 0.0 ? si * sj * (r[i] + r[j]) / den * area / dist : 0.0;
    }
    return g > 0.0 && isfinite(g) ? g : 0.0;
}

/* Conducting edges of a host conductance law (host.c): the contacts with g > 0 (a contact with
 * a neutral wall is none), in contact order. */
static sinter_status host_edges(sinter_electric_model *em, sinter_particles *ps,
                                const sinter_walls *walls, const sinter_contact_list *pp,
                                const sinter_contact_list *pw, const double *tab, int *bad)
{
    const size_t rows = ps->count, n = owned_count(ps);
    SINTER_ELECTRIC_RESERVE(em, host_sigma, rows + 1);
    SINTER_ELECTRIC_RESERVE(em, host_g, pp->count + pw->count + 1);
    for (size_t i = 0; i < rows; ++i)
        em->host_sigma[i] = conductivity(em, ps, i, bad, tab);
    if (*bad)
        return SINTER_OK; /* reported by the caller */
    sinter_status s =
        sinter_electric_host_conductance(em, ps, walls, pp, pw, em->host_sigma, em->host_g);
    if (s != SINTER_OK)
        return s;
    size_t count = 0;
    for (size_t k = 0; k < pp->count + pw->count; ++k) {
        const int wall = k >= pp->count;
        const size_t q = wall ? k - pp->count : k;
        const uint32_t b = wall ? (uint32_t)(n + pw->j[q]) : node_of(em, n, pp->j[q]);
        if ((wall && em->wall_mode[pw->j[q]] == SINTER_WALL_NEUTRAL) || !(em->host_g[k] > 0.0))
            continue;
        em->edge_a[count] = wall ? pw->i[q] : pp->i[q];
        em->edge_b[count] = b;
        em->edge_g[count] = em->host_g[k];
        em->edge_contact[count++] = (uint32_t)k;
    }
    em->edge_count = count;
    return SINTER_OK;
}

/* Across subdomains (em->domain): the node of particle row j, owned or the ghost row n + k,
 * whose node is n + nw + k (after the walls; its potential comes through the halo). */
static inline uint32_t far_node(size_t n, size_t nw, uint32_t j)
{
    return j < n ? j : (uint32_t)(j + nw);
}

/* Conducting edges of the contact lists (G > 0), and the ELECTRIFIED flags. */
static sinter_status build_edges(sinter_electric_model *em, sinter_particles *ps,
                                 const sinter_walls *walls, const sinter_contact_list *pp,
                                 const sinter_contact_list *pw)
{
    const size_t n = owned_count(ps), m = pp->count + pw->count;
    const size_t nw = walls != NULL ? walls->count : 0;
    SINTER_ELECTRIC_RESERVE(em, edge_a, m + 1);
    SINTER_ELECTRIC_RESERVE(em, edge_b, m + 1);
    SINTER_ELECTRIC_RESERVE(em, edge_g, m + 1);
    SINTER_ELECTRIC_RESERVE(em, edge_contact, m + 1);
    size_t count = 0;
    const double *r = ps->radius;
    const double *tab = NULL;
    const sinter_status ts = tabulated_sigma(em, ps, &tab);
    if (ts != SINTER_OK)
        return ts;
    int bad = 0;
    for (size_t k = 0; k < pp->count && em->host.conductance == NULL; ++k) {
        const uint32_t i = pp->i[k], j = pp->j[k];
        const double si = conductivity(em, ps, i, &bad, tab),
                     sj = conductivity(em, ps, j, &bad, tab);
        const double den = r[i] * sj + r[j] * si; /* seed 003 eq. 35 */
        const double g = den > 0.0 && pp->dist[k] > 0.0
                             ? si * sj * (r[i] + r[j]) / den * pp->area[k] / pp->dist[k]
                             : 0.0;
        if (g > 0.0 && isfinite(g)) {
            em->edge_a[count] = i; /* (the smaller id's end: owned) */
            em->edge_b[count] = em->domain == NULL ? node_of(em, n, j) : far_node(n, nw, j);
            if (em->domain != NULL && i >= n) { /* a ghost's pair: its owned end first */
                em->edge_a[count] = j;
                em->edge_b[count] = far_node(n, nw, i);
            }
            em->edge_contact[count] = (uint32_t)k;
            em->edge_g[count++] = g;
        }
    }
    for (size_t i = 0; i < ps->count; ++i)
        ps->flags[i] &= ~(uint32_t)SINTER_PARTICLE_ELECTRIFIED;
    for (size_t k = 0; k < pw->count; ++k) {
        const uint32_t i = pw->i[k], w = pw->j[k];
        if (em->wall_mode[w] == SINTER_WALL_NEUTRAL)
            continue;
        ps->flags[i] |= (uint32_t)SINTER_PARTICLE_ELECTRIFIED;
        if (em->host.conductance != NULL)
            continue;
        const double si = conductivity(em, ps, i, &bad, tab);
        const double g = pw->dist[k] > 0.0 ? si * pw->area[k] / pw->dist[k] : 0.0;
        if (g > 0.0 && isfinite(g)) {
            em->edge_a[count] = i;
            em->edge_b[count] = (uint32_t)(n + w);
            em->edge_contact[count] = (uint32_t)(pp->count + k);
            em->edge_g[count++] = g;
        }
    }
    em->edge_count = count;
    if (em->host.conductance != NULL) {
        const sinter_status s = host_edges(em, ps, walls, pp, pw, tab, &bad);
        if (s != SINTER_OK)
            return s;
    }
    if (bad)
        return sinter_fail(em->ctx, SINTER_ERR_DOMAIN,
                           "electric model '%s': seed 000 eq. 50 (k1 = %g, gamma1 = %g 1/K, "
                           "theta_ref = %g K) gives a conductivity <= 0 at a particle's "
                           "temperature; it must stay positive",
                           em->name, em->k1, em->gamma1, em->theta_ref);
    return SINTER_OK;
}

/*
 * The power of the solution with a host Joule split (host.c): each edge's G (phi_a - phi_b)^2
 * goes as share to particle a and the rest to b, a particle or an electrode (whose part leaves
 * the powder: em->electrode_heat). Supplied power as in account_power.
 */
static sinter_status host_split_power(sinter_electric_model *em, sinter_particles *ps,
                                      const sinter_walls *walls, const sinter_contact_list *pp,
                                      const sinter_contact_list *pw)
{
    const size_t n = owned_count(ps), m = pp->count + pw->count;
    SINTER_ELECTRIC_RESERVE(em, host_power, m + 1);
    SINTER_ELECTRIC_RESERVE(em, host_share, m + 1);
    const double *phi = em->potential;
    memset(em->host_power, 0, m * sizeof(double));
    for (size_t e = 0; e < em->edge_count; ++e) {
        const double drop = phi[em->edge_a[e]] - phi[em->edge_b[e]];
        em->host_power[em->edge_contact[e]] = em->edge_g[e] * drop * drop;
    }
    sinter_status s =
        sinter_electric_host_split(em, ps, walls, pp, pw, em->host_power, em->host_share);
    if (s != SINTER_OK)
        return s;
    double *p = em->dissipation, dissipated = 0.0, supplied = 0.0, electrodes = 0.0;
    memset(p, 0, ps->count * sizeof(double)); /* (images: 0, their owners have it) */
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t a = em->edge_a[e], b = em->edge_b[e], k = em->edge_contact[e];
        const double power = em->host_power[k], share = em->host_share[k];
        dissipated += power;
        p[a] += share * power;
        if (b < n) {
            p[b] += (1.0 - share) * power;
        } else {
            electrodes += (1.0 - share) * power;
            supplied += phi[b] * em->edge_g[e] * (phi[b] - phi[a]);
        }
    }
    em->dissipation_count = ps->count;
    em->dissipated_power = dissipated;
    em->supplied_power = supplied;
    em->electrode_heat = electrodes;
    return SINTER_OK;
}

/* The reproducible mode: the supplied and dissipated powers as exact sums of the edges' terms
 * (account_power's) over every subdomain. */
static sinter_status repro_powers(sinter_electric_model *em, size_t nodes)
{
    const double *phi = em->potential;
    double *dis = em->repro_a, *sup = em->repro_b;
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t a = em->edge_a[e], b = em->edge_b[e];
        const double drop = phi[a] - phi[b], power = em->edge_g[e] * drop * drop;
        dis[e] = b < nodes ? power : 0.5 * power;
        sup[e] =
            b >= nodes || b < em->across_owned ? 0.0 : phi[b] * em->edge_g[e] * (phi[b] - phi[a]);
    }
    const double *terms[2] = {sup, dis}, *none[2] = {NULL, NULL};
    const size_t count[2] = {em->edge_count, em->edge_count};
    double total[2] = {0.0, 0.0};
    const sinter_status s =
        sinter_domain_exact_sums(em->ctx, em->domain, 2, terms, none, count, total);
    em->supplied_power = total[0];
    em->dissipated_power = total[1];
    return s;
}

/*
 * The power of the solution (Joule's law on each resistor, P = G (phi_a - phi_b)^2): a
 * particle-particle contact gives half its power to each particle, a particle-wall contact all
 * of it to the particle (the electrode is a reservoir that takes no heat from the powder). The
 * driven walls deliver sum_w phi_w I_w, I_w the current from wall w into the powder; by
 * Tellegen's theorem the two are equal to the accuracy of the solve.
 */
static sinter_status account_power(sinter_electric_model *em, sinter_particles *ps,
                                   const sinter_walls *walls, const sinter_contact_list *pp,
                                   const sinter_contact_list *pw)
{
    const size_t n = owned_count(ps);
    SINTER_ELECTRIC_RESERVE(em, dissipation, ps->count + 1);
    em->electrode_heat = 0.0;
    if (em->host.joule_split != NULL)
        return host_split_power(em, ps, walls, pp, pw);
    const double *phi = em->potential;
    double *p = em->dissipation, dissipated = 0.0, supplied = 0.0;
    memset(p, 0, ps->count * sizeof(double)); /* (images: 0, their owners have it) */
    const size_t nodes = n + (walls != NULL ? walls->count : 0);
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t a = em->edge_a[e], b = em->edge_b[e];
        const double drop = phi[a] - phi[b], power = em->edge_g[e] * drop * drop;
        /* (a pair with a ghost of another subdomain: half here, half on its owner's side) */
        dissipated += b < nodes ? power : 0.5 * power;
        if (b < n) {
            p[a] += 0.5 * power;
            p[b] += 0.5 * power;
        } else if (b >= nodes) {
            p[a] += 0.5 * power;
        } else {
            p[a] += power;
            supplied += phi[b] * em->edge_g[e] * (phi[b] - phi[a]);
        }
    }
    em->dissipation_count = ps->count;
    em->dissipated_power = dissipated;
    em->supplied_power = supplied;
    if (em->reproducible) /* the two sums exact over every subdomain */
        return repro_powers(em, nodes);
    if (em->domain == NULL)
        return SINTER_OK;
    double total[2] = {supplied, dissipated}; /* over every subdomain */
    const sinter_status s =
        sinter_domain_reduce(em->ctx, em->domain, total, 2, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    em->supplied_power = total[0];
    em->dissipated_power = total[1];
    return s;
}

/* Clusters, their boundary conditions, and which nodes are free (state bits). */
static void classify_nodes(sinter_electric_model *em, const sinter_walls *walls, size_t n,
                           size_t nw)
{
    const size_t nodes = n + nw;
    uint32_t *parent = em->parent;
    unsigned char *state = em->state;
    for (size_t p = 0; p < nodes; ++p) {
        parent[p] = (uint32_t)p;
        state[p] = 0;
        em->net[p] = em->scale[p] = 0.0;
        em->pin[p] = NO_NODE;
    }
    /* A potential wall does not join clusters: its potential is fixed. */
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t b = em->edge_b[e];
        if (b < n || em->wall_mode[b - n] == SINTER_WALL_CURRENT)
            unite(parent, em->edge_a[e], b);
    }
    for (size_t p = 0; p < n; ++p)
        state[find_root(parent, (uint32_t)p)] |= CLUSTER_PARTICLE;
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t b = em->edge_b[e];
        if (b >= n && em->wall_mode[b - n] == SINTER_WALL_POTENTIAL)
            state[find_root(parent, em->edge_a[e])] |= CLUSTER_GROUND;
    }
    for (size_t w = 0; w < nw; ++w) {
        if (em->wall_mode[w] != SINTER_WALL_CURRENT)
            continue;
        const uint32_t root = find_root(parent, (uint32_t)(n + w));
        state[root] |= CLUSTER_CURRENT;
        if (!(walls->wall[w].electric_limit > 0.0))
            state[root] |= CLUSTER_UNLIMITED;
        em->net[root] += em->wall_value[w];
        em->scale[root] += fabs(em->wall_value[w]);
        if (em->pin[root] == NO_NODE)
            em->pin[root] = (uint32_t)(n + w);
    }
    for (size_t p = 0; p < nodes; ++p) {
        if (parent[p] != p)
            continue;
        const unsigned char c = state[p];
        if (c & CLUSTER_GROUND)
            state[p] |= CLUSTER_SOLVED; /* no pin: the potential walls fix the level */
        else if ((c & CLUSTER_CURRENT) && fabs(em->net[p]) <= 1e-9 * em->scale[p])
            state[p] |= CLUSTER_SOLVED; /* balanced electrodes: pin one at 0 V */
        else if ((c & CLUSTER_CURRENT) && (c & CLUSTER_PARTICLE) && (c & CLUSTER_UNLIMITED))
            em->open_clusters++; /* a supply with a limit sits at it: an expected state */
    }
    for (size_t p = 0; p < nodes; ++p) {
        const uint32_t root = find_root(parent, (uint32_t)p);
        if (!(state[root] & CLUSTER_SOLVED))
            continue;
        if (p >= n && em->wall_mode[p - n] != SINTER_WALL_CURRENT)
            continue; /* potential and neutral walls are singletons, never free */
        if ((state[root] & CLUSTER_GROUND) || em->pin[root] != p)
            state[p] |= NODE_FREE;
    }
}

/* Across subdomains: the diagonal of each free current wall summed over the subdomains (each
 * holds its particles' edges to it), and whether there is such a wall. */
static sinter_status sum_free_walls(sinter_electric_model *em, size_t n, size_t nw)
{
    SINTER_ELECTRIC_RESERVE(em, wall_sums, nw + 1);
    em->across_walls_free = 0;
    for (size_t w = 0; w < nw; ++w) {
        const int free = (em->state[n + w] & NODE_FREE) != 0;
        em->wall_sums[w] = free ? em->diag[n + w] : 0.0;
        em->across_walls_free |= free; /* (the same on every subdomain: the clusters are) */
    }
    if (!em->across_walls_free)
        return SINTER_OK;
    const sinter_status s = sinter_domain_reduce(em->ctx, em->domain, em->wall_sums, nw,
                                                 SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    for (size_t w = 0; w < nw && s == SINTER_OK; ++w)
        if (em->state[n + w] & NODE_FREE)
            em->diag[n + w] = em->wall_sums[w];
    return s;
}

/* One solve with the walls' effective modes and values (em->wall_mode, em->wall_value). */
static sinter_status solve_once(sinter_electric_model *em, sinter_particles *ps,
                                const sinter_walls *walls, const sinter_contact_list *pp,
                                const sinter_contact_list *pw)
{
    const size_t n = owned_count(ps), nw = walls != NULL ? walls->count : 0, nodes = n + nw;
    sinter_domain *dom = em->domain; /* across subdomains: ghosts after the walls */
    const size_t all = dom != NULL ? nodes + ps->ghost_count : nodes;
    if (dom != NULL || em->reproducible) /* (the mode's exact sums: their failure flag) */
        em->across =
            (sinter_domain_solve){em->ctx, dom, ps, em->across.rows, em->across.rows_capacity, 0};
    em->rank = 0;
    em->across_owned = n;
    em->across_nodes = nodes;
    em->across_walls_free = 0;
    em->open_clusters = 0;
    SINTER_ELECTRIC_RESERVE(em, parent, all + 1);
    SINTER_ELECTRIC_RESERVE(em, state, all + 1);
    SINTER_ELECTRIC_RESERVE(em, net, nodes + 1);
    SINTER_ELECTRIC_RESERVE(em, scale, nodes + 1);
    SINTER_ELECTRIC_RESERVE(em, pin, all + 1);
    SINTER_ELECTRIC_RESERVE(em, diag, nodes + 1);
    SINTER_ELECTRIC_RESERVE(em, potential, all + 1);
    SINTER_ELECTRIC_RESERVE(em, warm_id, n + 1); /* (so that keeping the ids cannot fail) */
    /* the last solve's potentials start this one if it had as many nodes (then cleared: an
     * error below leaves the next solve a start from 0); across subdomains only if every
     * subdomain's do (the wall nodes, copies on each, must start equal). After a reordering
     * the potentials first move to their particles' rows (warm_ids.c). */
    sinter_status s = sinter_electric_warm_follow(em, ps, n, nodes);
    int64_t warm = s == SINTER_OK && em->warm_nodes == nodes;
    em->warm_nodes = 0;
    em->dissipation_count = 0;
    em->supplied_power = em->dissipated_power = 0.0;
    if (dom != NULL) {
        const sinter_status r =
            sinter_domain_reduce(em->ctx, dom, &warm, 1, SINTER_REDUCE_I64, SINTER_REDUCE_MIN);
        s = s == SINTER_OK ? r : s;
    }
    if (s == SINTER_OK)
        s = build_edges(em, ps, walls, pp, pw);
    if (dom != NULL && (s = sinter_domain_agree(em->ctx, dom, s)) == SINTER_OK)
        s = sinter_network_classify_across(em, walls, ps, nw);
    if (s != SINTER_OK)
        return s;
    if (dom == NULL)
        classify_nodes(em, walls, n, nw);
    if (em->reproducible) { /* the exact sums' terms */
        SINTER_ELECTRIC_RESERVE(em, repro_a, em->edge_count + all + 1);
        SINTER_ELECTRIC_RESERVE(em, repro_b, em->edge_count + all + 1);
    }

    /* Right-hand side, diagonal and start: pinned rows are identities at their value. */
    double *phi = em->potential, *diag = em->diag, *rhs = em->net; /* net is no longer needed */
    const unsigned char *state = em->state;
    size_t free_count = 0;
    for (size_t p = 0; p < nodes; ++p) {
        const int wall_mode = p >= n ? em->wall_mode[p - n] : -1;
        const double wall_value = p >= n ? em->wall_value[p - n] : 0.0;
        if (state[p] & NODE_FREE) {
            free_count++;
            diag[p] = 0.0;
            phi[p] = warm && isfinite(phi[p]) ? phi[p] : 0.0;
            rhs[p] = wall_value; /* a free wall node is a current wall; a particle: 0 */
        } else {
            diag[p] = 1.0;
            phi[p] = wall_mode == SINTER_WALL_POTENTIAL ? wall_value : 0.0;
            rhs[p] = phi[p];
        }
    }
    for (size_t p = nodes; p < all; ++p)
        phi[p] = 0.0; /* the ghosts' potentials: from their owners after the solve */
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t a = em->edge_a[e], b = em->edge_b[e];
        const double g = em->edge_g[e];
        if (state[a] & NODE_FREE) {
            diag[a] += g;
            if (!(state[b] & NODE_FREE))
                rhs[a] += g * phi[b];
        }
        if (b < nodes && (state[b] & NODE_FREE)) { /* (a ghost's row is its owner's) */
            diag[b] += g;
            if (!(state[a] & NODE_FREE))
                rhs[b] += g * phi[a];
        }
    }
    double bnorm = 0.0;
    uint64_t free_total = free_count;
    if (dom != NULL) {
        if ((s = sinter_domain_rank(em->ctx, dom, &em->rank)) != SINTER_OK ||
            (s = sum_free_walls(em, n, nw)) != SINTER_OK)
            return s;
        /* the wall nodes are copies on every subdomain: counted by the first */
        const size_t counted = em->rank == 0 ? nodes : n;
        for (size_t p = 0; p < counted && !em->reproducible; ++p)
            if (state[p] & NODE_FREE)
                bnorm += rhs[p] * rhs[p];
        if ((!em->reproducible &&
             (s = sinter_domain_reduce(em->ctx, dom, &bnorm, 1, SINTER_REDUCE_F64,
                                       SINTER_REDUCE_SUM)) != SINTER_OK) ||
            (s = sinter_domain_reduce(em->ctx, dom, &free_total, 1, SINTER_REDUCE_U64,
                                      SINTER_REDUCE_SUM)) != SINTER_OK)
            return s;
    }
    if (em->reproducible) { /* |b|^2 an exact sum (the wall rows counted by the first) */
        const size_t counted = em->rank == 0 ? nodes : n;
        double *t = em->repro_a;
        for (size_t p = 0; p < counted; ++p)
            t[p] = state[p] & NODE_FREE ? rhs[p] : 0.0;
        const double *ta = t;
        if ((s = sinter_domain_exact_sums(em->ctx, dom, 1, &ta, &ta, &counted, &bnorm)) !=
            SINTER_OK)
            return s;
    } else if (dom == NULL) {
        for (size_t p = 0; p < nodes; ++p)
            if (state[p] & NODE_FREE)
                bnorm += rhs[p] * rhs[p];
    }
    bnorm = sqrt(bnorm);

    /* A zero right-hand side on an SPD system has the solution 0. */
    if (!(bnorm > 0.0))
        for (size_t p = 0; p < nodes; ++p)
            if (state[p] & NODE_FREE)
                phi[p] = 0.0;
    if (free_total > 0 && bnorm > 0.0) {
        SINTER_ELECTRIC_RESERVE(em, free_a, em->edge_count + 1);
        SINTER_ELECTRIC_RESERVE(em, free_b, em->edge_count + 1);
        SINTER_ELECTRIC_RESERVE(em, free_g, em->edge_count + 1);
        size_t kept = 0;
        for (size_t e = 0; e < em->edge_count; ++e) {
            const uint32_t a = em->edge_a[e], b = em->edge_b[e];
            if ((state[a] & NODE_FREE) && (state[b] & NODE_FREE)) {
                em->free_a[kept] = a;
                em->free_b[kept] = b;
                em->free_g[kept++] = em->edge_g[e];
            }
        }
        em->free_edges = kept;
        if (em->reproducible) { /* the free walls' diagonals as exact sums over the edges */
            for (size_t w = 0; w < nw; ++w)
                em->across_walls_free |= (state[n + w] & NODE_FREE) != 0;
            if ((s = repro_group(em, n, nw)) != SINTER_OK)
                return s;
            if (em->across_walls_free)
                repro_wall_rows(em, NULL, diag, n, nw);
            if (em->across.failed)
                return sinter_last_status(em->ctx);
        }
        const int maxl = (int)fmin(em->max_iterations, 2147483647.0);
        /* (an empty subdomain without walls solves 1 x = 0 as its part) */
        const size_t unknowns = nodes > 0 || dom == NULL ? nodes : 1;
        s = sinter_pcg_reserve(em->ctx, &em->pcg, unknowns, maxl);
        if (dom != NULL)
            s = sinter_domain_agree(em->ctx, dom, s);
        if (s != SINTER_OK)
            return s;
        if (unknowns > nodes) {
            diag[0] = 1.0;
            phi[0] = rhs[0] = 0.0;
        }
        em->pcg_nodes = unknowns;
        memcpy(sinter_pcg_solution(em->pcg), phi, unknowns * sizeof(double));
        memcpy(sinter_pcg_rhs(em->pcg), rhs, unknowns * sizeof(double));
        int iterations = 0;
        double res = 0.0;
        if (dom != NULL)
            sinter_pcg_set_sum(em->pcg, sinter_domain_solve_sum, &em->across,
                               em->rank == 0 ? nodes : n);
        if (em->reproducible) /* every dot product an exact sum, with or without domains */
            sinter_pcg_set_dot(em->pcg, sinter_domain_solve_exact_dot, &em->across,
                               em->rank == 0 ? nodes : n);
        const int rc =
            sinter_pcg_solve(em->pcg, dom != NULL ? apply_operator_across : apply_operator,
                             precondition, em, em->tolerance * bnorm, &iterations, &res);
        sinter_pcg_set_sum(em->pcg, NULL, NULL, 0);
        sinter_pcg_set_dot(em->pcg, NULL, NULL, 0);
        em->last_iterations = (size_t)iterations;
        memcpy(phi, sinter_pcg_solution(em->pcg), nodes * sizeof(double));
        if ((dom != NULL || em->reproducible) && em->across.failed)
            return sinter_last_status(em->ctx);
        if (rc != 0)
            return sinter_fail(em->ctx, SINTER_ERR_NOT_CONVERGED,
                               "electric model 'network': PCG returned %d after %zu iterations "
                               "(residual %g > tolerance %g x %g); raise 'max_iterations' or "
                               "'tolerance'",
                               rc, em->last_iterations, res, em->tolerance, bnorm);
    }
    em->node_count = nodes;
    if ((s = sinter_electric_warm_record_ids(em, ps, n)) != SINTER_OK)
        return s;
    em->warm_nodes = nodes;
    if (dom != NULL) { /* the ghosts' potentials, from their owners */
        sinter_domain_solve_forward(&em->across, phi);
        if (em->across.failed)
            return sinter_last_status(em->ctx);
        if (ps->ghost_count > 0)
            memcpy(phi + nodes, em->across.rows + n, ps->ghost_count * sizeof(double));
    }

    /* Contact currents I = G (phi_a - phi_b); a particle carries half the sum of |I|. */
    double *J = ps->current;
    memset(J, 0, n * sizeof(double));
    for (size_t e = 0; e < em->edge_count; ++e) {
        const uint32_t a = em->edge_a[e], b = em->edge_b[e];
        const double half = 0.5 * fabs(em->edge_g[e] * (phi[a] - phi[b]));
        J[a] += half;
        if (b < n)
            J[b] += half;
    }
    for (size_t k = 0; k < ps->ghost_count; ++k) /* an image carries its owner's current */
        J[n + k] = dom == NULL ? J[em->ghost_owner[k]] : 0.0; /* (a ghost's: its owner's side) */
    return account_power(em, ps, walls, pp, pw);
}

/* The reproducible mode: the current from each wall into the powder as an exact sum over every
 * subdomain, into em->wall_sums. 0 on a failure. */
static int repro_wall_currents(sinter_electric_model *em, size_t nw, size_t n)
{
    const double *phi = em->potential;
    double *t = em->repro_a;
    for (size_t w0 = 0; w0 < nw; w0 += SINTER_REPRO_BATCH) {
        const size_t m = nw - w0 < SINTER_REPRO_BATCH ? nw - w0 : SINTER_REPRO_BATCH;
        const double *a[SINTER_REPRO_BATCH], *b[SINTER_REPRO_BATCH];
        size_t count[SINTER_REPRO_BATCH], pos = 0;
        for (size_t c = 0; c < m; ++c) {
            const size_t w = w0 + c, first = pos;
            a[c] = t + pos;
            b[c] = NULL;
            for (size_t e = 0; e < em->edge_count; ++e)
                if (em->edge_b[e] == n + w)
                    t[pos++] = em->edge_g[e] * (phi[n + w] - phi[em->edge_a[e]]);
            count[c] = pos - first;
        }
        if (sinter_domain_exact_sums(em->ctx, em->domain, m, a, b, count, em->wall_sums + w0) !=
            SINTER_OK)
            return 0;
    }
    return 1;
}

/* Across subdomains: the current from each wall into the powder, summed over the
 * subdomains, into em->wall_sums (collective when a wall has a limit). 0 on a failure. */
static int wall_currents_across(sinter_electric_model *em, const sinter_walls *walls, size_t n)
{
    int limited = 0;
    for (size_t w = 0; w < walls->count; ++w)
        limited |= walls->wall[w].electric_limit > 0.0;
    if (!limited)
        return 1;
    const double *phi = em->potential;
    double *sums = sinter_electric_reserve(em->ctx, em->wall_sums, &em->wall_sums_capacity,
                                           walls->count + 1, sizeof(double));
    if (sums == NULL)
        return 0;
    em->wall_sums = sums;
    if (em->reproducible) /* exact sums, with or without domain operations */
        return repro_wall_currents(em, walls->count, n);
    for (size_t w = 0; w < walls->count; ++w) {
        em->wall_sums[w] = 0.0;
        for (size_t e = 0; e < em->edge_count; ++e)
            if (em->edge_b[e] == n + w)
                em->wall_sums[w] += em->edge_g[e] * (phi[n + w] - phi[em->edge_a[e]]);
    }
    return sinter_domain_reduce(em->ctx, em->domain, em->wall_sums, walls->count, SINTER_REDUCE_F64,
                                SINTER_REDUCE_SUM) == SINTER_OK;
}

/*
 * Compliance (walls/electric_drive.c): a current electrode whose potential passes its limit is
 * held at the limit, a potential electrode whose current passes its limit carries the limit.
 * 1 if a wall changed its mode (solve again).
 */
static int apply_limits(sinter_electric_model *em, const sinter_walls *walls, size_t n)
{
    const double *phi = em->potential;
    int changed = 0;
    if ((em->domain != NULL || em->reproducible) && !wall_currents_across(em, walls, n))
        return 0; /* (a failed reduction: reported by the caller) */
    for (size_t w = 0; w < walls->count; ++w) {
        const double limit = walls->wall[w].electric_limit;
        if (!(limit > 0.0) || em->wall_mode[w] != walls->wall[w].electric_mode)
            continue; /* no limit, or already switched in this solve */
        if (em->wall_mode[w] == SINTER_WALL_CURRENT && fabs(phi[n + w]) > limit) {
            em->wall_mode[w] = SINTER_WALL_POTENTIAL;
            em->wall_value[w] = copysign(limit, phi[n + w]);
            changed = 1;
        } else if (em->wall_mode[w] == SINTER_WALL_POTENTIAL) {
            double current = 0.0; /* from the wall into the powder */
            for (size_t e = 0; e < em->edge_count && em->domain == NULL && !em->reproducible; ++e)
                if (em->edge_b[e] == n + w)
                    current += em->edge_g[e] * (phi[n + w] - phi[em->edge_a[e]]);
            if (em->domain != NULL || em->reproducible) /* (over every subdomain) */
                current = em->wall_sums[w];
            if (fabs(current) > limit) {
                em->wall_mode[w] = SINTER_WALL_CURRENT;
                em->wall_value[w] = copysign(limit, current);
                changed = 1;
            }
        }
    }
    return changed;
}

sinter_status sinter_electric_solve_network(sinter_electric_model *em, sinter_particles *ps,
                                            const sinter_walls *walls,
                                            const sinter_contact_list *pp,
                                            const sinter_contact_list *pw)
{
    const size_t nw = walls != NULL ? walls->count : 0;
    SINTER_ELECTRIC_RESERVE(em, wall_mode, nw + 1);
    SINTER_ELECTRIC_RESERVE(em, wall_value, nw + 1);
    for (size_t w = 0; w < nw; ++w) {
        em->wall_mode[w] = walls->wall[w].electric_mode;
        em->wall_value[w] = walls->wall[w].electric_value;
    }
    sinter_status s = solve_once(em, ps, walls, pp, pw);
    /* each wall changes its mode at most once: at most nw solves more */
    for (size_t pass = 0; s == SINTER_OK && pass < nw && apply_limits(em, walls, owned_count(ps));
         ++pass)
        s = solve_once(em, ps, walls, pp, pw);
    if (s == SINTER_OK && em->open_clusters > 0)
        sinter_log(em->ctx, SINTER_LOG_WARNING,
                   "electric model 'network': %zu cluster(s) of particles touch current walls "
                   "but no potential wall and the currents do not balance (open circuit); they "
                   "carry no current",
                   em->open_clusters);
    return s;
}
