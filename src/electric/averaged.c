/*
 * The "averaged" electric model of seed 000 sec. 5 (eq. 40-44).
 *
 * Charge conservation written per particle with radial flow (eq. 40-41) gives
 * sum_j (J_i - J_j) A_ij = 0, i.e. eq. 42: J_i = sum_j J_j A_ij / sum_j A_ij, the
 * contact-area-weighted average of the neighbours' current magnitudes. Boundary condition
 * (remark 2, Figure 5): a particle touching a current wall is "fully electrified" and takes the
 * wall's |J_ext|; if it touches several current walls, the contact-area-weighted mean of their
 * magnitudes. Neutral walls do not take part (their contacts are neither sources nor
 * neighbours). Remark 4: in a chain with equal contact areas J_i = (J_+ + J_-) / 2, so the
 * magnitudes vary linearly between two electrified ends (eq. 44).
 *
 * Solution (eq. 43, sec. 5.2): Gauss-Seidel sweeps "through the system, particle by particle,
 * updating the variables as it progresses", in index order, each particle using the newest
 * values of its neighbours. After sweep K the normalised change (the seed's error measure of
 * sec. 3.1 step 4) Z_K = sum_i |J_i^K - J_i^(K-1)| / sum_i |J_i^K| is compared with
 * "tolerance"; the sweep count is reported. Note that this bounds the last change, not the
 * error: for a slowly contracting sweep (a long chain) the error is about Z_K / (1 - rho) with
 * rho the contraction factor of a sweep.
 *
 * Start: the particles' current field (the previous solution, which makes repeated solves in a
 * stepper cheap); particles that cannot be reached from an electrified one through contacts get
 * 0 and are not swept (otherwise they would keep a stale value forever).
 *
 * This is a magnitude smoothing, not Kirchhoff's law: a branch does not split the current and
 * the total current is not conserved (see network.c for that).
 *
 * On one subdomain of a decomposed run (em->averaged_domain, domain/domain.h) the unknowns are
 * the owned particles; a ghost's current is its owner's, brought by a forward halo. The
 * search for connected particles goes on in rounds: the reached marks of the owners go to
 * their ghosts (a halo), the search goes on from the ghosts newly reached, until a round
 * reaches no owned particle anywhere (a reduction). A sweep is Gauss-Seidel within the
 * subdomain and Jacobi across its border: it sweeps the owned particles in index order with
 * the ghosts' currents of the last halo, then the change and the norm are summed over every
 * subdomain and the ghosts take the new currents. The fixed point is eq. 42's, the same as on
 * one domain; the iterates differ, by less than the tolerance. Every decision comes from the
 * reduced values, so every subdomain sweeps as often. On one subdomain the sweep is the
 * whole body's, the same bits.
 *
 * The stepper's reproducible mode (em->reproducible, issue 43): the sweeps are Jacobi's
 * everywhere, each particle's new current from its neighbours' of the last sweep, so that a
 * sweep's result does not depend on which particles a subdomain holds or in which order; a
 * particle's neighbours come in the order of its contacts, which the mode sorts by ids, and
 * the change and the norm of the stopping test are exact sums (domain/exact_reduce.h). The same
 * bits for any decomposition and memory order. Jacobi's contraction for this averaging is rho
 * where Gauss-Seidel's is about rho^2: from a cold start it takes about 1.7 times the sweeps
 * (253 against 146 in a press's first step, tests/bench/RESULTS.md), about as many once the
 * currents are warm.
 */
#include <math.h>
#include <string.h>

#include "domain/domain.h"
#include "domain/exact_reduce.h"
#include "electric.h"

enum { UNREACHED = 0, ELECTRIFIED = 1, FREE = 2 };

/* CSR adjacency of the particle-particle contacts, weighted by contact area. */
static sinter_status build_adjacency(sinter_electric_model *em, size_t n,
                                     const sinter_contact_list *pp)
{
    SINTER_ELECTRIC_RESERVE(em, adj_start, n + 1);
    SINTER_ELECTRIC_RESERVE(em, adj_other, 2 * pp->count + 1);
    SINTER_ELECTRIC_RESERVE(em, adj_area, 2 * pp->count + 1);
    uint32_t *start = em->adj_start;
    memset(start, 0, (n + 1) * sizeof(uint32_t));
    for (size_t k = 0; k < pp->count; ++k) {
        start[pp->i[k] + 1]++;
        start[pp->j[k] + 1]++;
    }
    for (size_t i = 0; i < n; ++i)
        start[i + 1] += start[i];
    /* fill with start[i] as the running cursor, then shift back */
    for (size_t k = 0; k < pp->count; ++k) {
        const uint32_t i = pp->i[k], j = pp->j[k];
        em->adj_other[start[i]] = j;
        em->adj_area[start[i]++] = pp->area[k];
        em->adj_other[start[j]] = i;
        em->adj_area[start[j]++] = pp->area[k];
    }
    for (size_t i = n; i > 0; --i)
        start[i] = start[i - 1];
    start[0] = 0;
    return SINTER_OK;
}

/* The search from the queue's entries [head, *tail): every unreached neighbour becomes FREE,
 * keeps its current as the warm start when it is usable (else 0) and joins the queue. Returns
 * how many of them are owned (rows below `owned`). */
static size_t search(sinter_electric_model *em, sinter_particles *ps, size_t head, size_t *tail,
                     size_t owned)
{
    unsigned char *state = em->state;
    const uint32_t *start = em->adj_start, *other = em->adj_other;
    size_t reached = 0;
    while (head < *tail) {
        const uint32_t i = em->queue[head++];
        for (uint32_t e = start[i]; e < start[i + 1]; ++e) {
            const uint32_t j = other[e];
            if (state[j] != UNREACHED)
                continue;
            state[j] = FREE;
            if (!isfinite(ps->current[j]))
                ps->current[j] = 0.0;
            em->queue[(*tail)++] = j;
            reached += j < owned;
        }
    }
    return reached;
}

/* The owners' values of `v` (one per particle) into their ghosts (a forward halo). */
static sinter_status to_ghosts(sinter_electric_model *em, const sinter_particles *ps, double *v)
{
    const size_t n = ps->count, owned = n - ps->ghost_count;
    double *rows = em->averaged_rows;
    if (owned > 0)
        memcpy(rows, v, owned * sizeof(double));
    const sinter_status s = sinter_domain_forward_rows(em->ctx, em->averaged_domain, ps, rows, 1);
    if (s == SINTER_OK && n > owned)
        memcpy(v + owned, rows + owned, (n - owned) * sizeof(double));
    return s;
}

/* The search for particles connected to an electrified one, across subdomains (see the top of
 * the file): rounds of a halo of the marks and the search from the ghosts they reached, until
 * one reaches no owned particle anywhere. `tail` is the queue's length after the local search. */
static sinter_status search_across(sinter_electric_model *em, sinter_particles *ps, size_t tail)
{
    const size_t n = ps->count, owned = n - ps->ghost_count;
    unsigned char *state = em->state;
    double *mark = em->wall_sum; /* (scratch: the wall sums are read) */
    for (;;) {
        for (size_t i = 0; i < owned; ++i)
            mark[i] = (double)state[i];
        sinter_status s = to_ghosts(em, ps, mark);
        if (s != SINTER_OK)
            return s;
        size_t head = tail;
        for (size_t g = owned; g < n; ++g) {
            const unsigned char remote = (unsigned char)mark[g];
            ps->flags[g] &= ~(uint32_t)SINTER_PARTICLE_ELECTRIFIED;
            if (remote == ELECTRIFIED)
                ps->flags[g] |= (uint32_t)SINTER_PARTICLE_ELECTRIFIED;
            if (remote != UNREACHED && state[g] == UNREACHED)
                em->queue[tail++] = (uint32_t)g;
            state[g] = remote;
        }
        double reached = (double)search(em, ps, head, &tail, owned); /* owned ones, this round */
        if ((s = sinter_domain_sum(em->ctx, em->averaged_domain, &reached, 1)) != SINTER_OK)
            return s;
        if (reached == 0.0)
            return SINTER_OK;
        tail = 0; /* (the queue only grows within a round) */
    }
}

/* The reproducible mode's sweeps (see the top of the file): Jacobi over the owned particles
 * [0, owned), the change and the norm summed exactly over every subdomain, the ghosts taking
 * the new currents after each sweep. Scratch: the wall sums (read before). */
static sinter_status jacobi_sweeps(sinter_electric_model *em, sinter_particles *ps, size_t owned)
{
    sinter_domain *dom = em->averaged_domain;
    const unsigned char *state = em->state;
    const uint32_t *start = em->adj_start, *other = em->adj_other;
    const double *area = em->adj_area;
    double *J = ps->current, *next = em->wall_area, *change = em->wall_sum;
    const size_t max_sweeps = (size_t)em->max_iterations;
    double sums[2] = {0.0, 0.0}; /* change, norm */
    for (size_t sweep = 1; sweep <= max_sweeps; ++sweep) {
        for (size_t i = 0; i < owned; ++i) {
            next[i] = J[i];
            change[i] = 0.0;
            if (state[i] != FREE)
                continue;
            double sum_ja = 0.0, sum_a = 0.0;
            for (uint32_t e = start[i]; e < start[i + 1]; ++e) {
                sum_ja += J[other[e]] * area[e];
                sum_a += area[e];
            }
            next[i] = sum_ja / sum_a; /* eq. 43 with the last sweep's neighbours */
            change[i] = fabs(next[i] - J[i]);
        }
        if (owned > 0)
            memcpy(J, next, owned * sizeof(double));
        for (size_t i = 0; i < owned; ++i)
            next[i] = fabs(J[i]); /* (the norm's terms: 0 where unreached) */
        const double *terms[2] = {change, next};
        const size_t len[2] = {owned, owned};
        sinter_status s = sinter_domain_exact_sums(em->ctx, dom, 2, terms, NULL, len, sums);
        if (s != SINTER_OK)
            return s;
        if (dom != NULL && (s = to_ghosts(em, ps, J)) != SINTER_OK)
            return s;
        em->last_iterations = sweep;
        if (sums[0] <= em->tolerance * sums[1])
            return SINTER_OK;
    }
    return sinter_fail(em->ctx, SINTER_ERR_NOT_CONVERGED,
                       "electric model 'averaged': no convergence in %zu Jacobi sweeps (the "
                       "stepper's reproducible mode; normalised change %g > tolerance %g); raise "
                       "'max_iterations' or 'tolerance'",
                       max_sweeps, sums[1] > 0.0 ? sums[0] / sums[1] : sums[0], em->tolerance);
}

sinter_status sinter_electric_solve_averaged(sinter_electric_model *em, sinter_particles *ps,
                                             const sinter_walls *walls,
                                             const sinter_contact_list *pp,
                                             const sinter_contact_list *pw)
{
    const size_t n = ps->count;
    const size_t nw = walls != NULL ? walls->count : 0;
    for (size_t w = 0; w < nw; ++w)
        if (walls->wall[w].electric_mode == SINTER_WALL_POTENTIAL)
            return sinter_fail(em->ctx, SINTER_ERR_INVALID,
                               "electric model 'averaged': wall %zu is held at a potential, "
                               "which this model (seed 000 eq. 42, currents only) cannot use; "
                               "give it a current (SINTER_WALL_CURRENT) or use the 'network' "
                               "model",
                               w);
    SINTER_ELECTRIC_RESERVE(em, wall_sum, n + 1);
    SINTER_ELECTRIC_RESERVE(em, wall_area, n + 1);
    SINTER_ELECTRIC_RESERVE(em, state, n + 1);
    SINTER_ELECTRIC_RESERVE(em, queue, n + 1);
    sinter_domain *dom = em->averaged_domain;
    const size_t owned = dom != NULL ? n - ps->ghost_count : n;
    if (dom != NULL) /* (the search across borders: up to n after the local search) */
    {
        SINTER_ELECTRIC_RESERVE(em, averaged_rows, n + 1);
        SINTER_ELECTRIC_RESERVE(em, queue, 2 * n + 1);
    }
    sinter_status s = build_adjacency(em, n, pp);
    if (s != SINTER_OK)
        return s;
    double *wall_sum = em->wall_sum, *wall_area = em->wall_area, *J = ps->current;
    unsigned char *state = em->state;
    memset(wall_sum, 0, n * sizeof(double));
    memset(wall_area, 0, n * sizeof(double));
    memset(state, UNREACHED, n);

    /* Remark 2: particles touching a current wall take its magnitude. */
    for (size_t k = 0; k < pw->count; ++k) {
        const sinter_wall *w = &walls->wall[pw->j[k]];
        if (w->electric_mode != SINTER_WALL_CURRENT)
            continue;
        const uint32_t i = pw->i[k];
        wall_sum[i] += pw->area[k] * fabs(w->electric_value);
        wall_area[i] += pw->area[k];
    }
    size_t head = 0, tail = 0;
    for (size_t i = 0; i < n; ++i) {
        ps->flags[i] &= ~(uint32_t)SINTER_PARTICLE_ELECTRIFIED;
        if (wall_area[i] > 0.0) {
            ps->flags[i] |= (uint32_t)SINTER_PARTICLE_ELECTRIFIED;
            state[i] = ELECTRIFIED;
            J[i] = wall_sum[i] / wall_area[i];
            em->queue[tail++] = (uint32_t)i;
        }
    }
    /* Particles connected to an electrified one; the others carry nothing. */
    const uint32_t *start = em->adj_start, *other = em->adj_other;
    const double *area = em->adj_area;
    size_t free_count = search(em, ps, head, &tail, owned); /* (owned = n on one domain) */
    if (dom != NULL) { /* across the subdomains' borders; the free particles counted again */
        if ((s = search_across(em, ps, tail)) != SINTER_OK)
            return s;
        double count = 0.0;
        for (size_t i = 0; i < owned; ++i)
            count += state[i] == FREE;
        if ((s = sinter_domain_sum(em->ctx, dom, &count, 1)) != SINTER_OK)
            return s;
        free_count = (size_t)count;
    }
    for (size_t i = 0; i < owned; ++i)
        if (state[i] == UNREACHED)
            J[i] = 0.0;
    if (dom != NULL && (s = to_ghosts(em, ps, J)) != SINTER_OK) /* the ghosts' start */
        return s;
    if (free_count == 0)
        return SINTER_OK; /* every connected particle is electrified: nothing to iterate */
    if (em->reproducible)
        return jacobi_sweeps(em, ps, owned);

    /* Eq. 43, Gauss-Seidel in index order; Z_K of sec. 3.1 step 4 as the stopping test. */
    const size_t max_sweeps = (size_t)em->max_iterations;
    double change = 0.0, norm = 0.0;
    for (size_t sweep = 1; sweep <= max_sweeps; ++sweep) {
        change = 0.0;
        norm = 0.0;
        for (size_t i = 0; i < owned; ++i) {
            if (state[i] == UNREACHED)
                continue;
            if (state[i] == FREE) {
                double sum_ja = 0.0, sum_a = 0.0;
                for (uint32_t e = start[i]; e < start[i + 1]; ++e) {
                    sum_ja += J[other[e]] * area[e];
                    sum_a += area[e];
                }
                const double next = sum_ja / sum_a; /* eq. 43; sum_a > 0: i has a neighbour */
                change += fabs(next - J[i]);
                J[i] = next;
            }
            norm += fabs(J[i]);
        }
        if (dom != NULL) { /* over every subdomain; the ghosts take the new currents */
            double v[2] = {change, norm};
            if ((s = sinter_domain_sum(em->ctx, dom, v, 2)) != SINTER_OK ||
                (s = to_ghosts(em, ps, J)) != SINTER_OK)
                return s;
            change = v[0];
            norm = v[1];
        }
        em->last_iterations = sweep;
        if (change <= em->tolerance * norm)
            return SINTER_OK;
    }
    return sinter_fail(em->ctx, SINTER_ERR_NOT_CONVERGED,
                       "electric model 'averaged': no convergence in %zu Gauss-Seidel sweeps "
                       "(normalised change %g > tolerance %g); raise 'max_iterations' or "
                       "'tolerance'",
                       max_sweeps, norm > 0.0 ? change / norm : change, em->tolerance);
}
