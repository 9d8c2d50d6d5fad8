/*
 * K u = f over an assembly of bonded links (seed 001 eq. 40, sec. 3.3): SUNDIALS PCG with a
 * block symmetric Gauss-Seidel (SSOR) preconditioner, 6x6 blocks, one per particle, applied by
 * Eisenstat's trick (bonded/block_ssor.h): PCG runs on the transformed system
 * E^-1 K E^-T x^ = E^-1 f, whose product costs two triangular sweeps, about one product with
 * K, and takes about half the iterations of block-Jacobi (tests/bench/RESULTS.md, session 14).
 * Everything goes through the shared PCG wrapper of src/core/pcg.h.
 *
 * Constrained DOFs (the principal-plane conditions of sec. 3.3, or a clamp) are removed by
 * projection: the operator is P K P + (I - P) and the right-hand side P f, with P zeroing the
 * constrained DOFs, so the system stays symmetric positive (semi-)definite. A free DOF with no
 * stiffness at all (a particle without links) is treated as constrained. Zero-energy modes that
 * the plane conditions leave (the rigid motions of spheres linked only to each other) do not
 * hinder convergence, the loads having no component on them, but the solution may carry any
 * amount of them, which depends on the start and the preconditioner: the quasi-static stepper
 * removes it (stepper/qs_floating.c).
 *
 * The stopping test is on the original system, |f - K u| <= rtol |f|: PCG's own test sees the
 * transformed residual E^-1 (f - K u), so its target is set from the ratio of the two norms,
 * the true residual checked after the solve, and PCG continued with a tighter target until the
 * true test holds.
 */
#include <math.h>
#include <string.h>

#include "core/pcg.h"

#include "bonded/beam.h"
#include "bonded/block_ssor.h"
#include "bonded/domain_order.h"
#include "core/two_parts.h"

/* Rounds of "PCG, then the true residual" before the solve gives up. */
#define BONDED_SOLVE_ROUNDS 6
/* The largest relative residual taken for a rounding floor: about the unit round-off times a
 * condition number of 1e10, far beyond any packing's (stiffness ratios of 1e3-1e6). */
#define ROUNDING_FLOOR 1e-6
/* PCG's first target on the transformed residual, in units of rtol |E^-1 f| (below). */
#define FIRST_TARGET_FACTOR 2.0

struct sinter_bonded_solver {
    sinter_ctx *ctx;
    sinter_pcg *pcg;
    sinter_block_ssor matrix;
    /* The matrix, mask and vectors below are in the order of bonded/domain_order.h (two
     * domains and their separator: the sweeps on two threads); f and u in the caller's. */
    sinter_domain_order order;
    unsigned char *mask;     /* 1: constrained (user-fixed or without stiffness) */
    uint32_t *lower, *upper; /* per link: its particles, lower first */
    double *residual;        /* 6 per particle */
    double *load, *displacement; /* f and u, 6 per particle */
    size_t mask_capacity, lower_capacity, upper_capacity, residual_capacity, load_capacity,
        displacement_capacity;
};

void sinter_bonded_solver_destroy(sinter_bonded_solver *solver)
{
    if (solver == NULL)
        return;
    sinter_pcg_free(solver->pcg);
    sinter_block_ssor_release(&solver->matrix);
    sinter_domain_order_release(&solver->order);
    sinter_free(solver->ctx, solver->mask);
    sinter_free(solver->ctx, solver->lower);
    sinter_free(solver->ctx, solver->upper);
    sinter_free(solver->ctx, solver->residual);
    sinter_free(solver->ctx, solver->load);
    sinter_free(solver->ctx, solver->displacement);
    sinter_free(solver->ctx, solver);
}

sinter_status sinter_bonded_solver_create(sinter_bonded_solver **out, sinter_ctx *ctx)
{
    SINTER_CHECK_NULL(ctx, out);
    *out = NULL;
    sinter_bonded_solver *s = sinter_calloc(ctx, 1, sizeof(*s));
    if (s == NULL)
        return SINTER_ERR_NOMEM;
    s->ctx = ctx;
    s->matrix.ctx = ctx;
    s->order.ctx = ctx;
    *out = s;
    return SINTER_OK;
}

/* z = K^ v, the transformed operator. */
static void apply_transformed(const double *v, double *z, void *data)
{
    const sinter_bonded_solver *s = data;
    sinter_block_ssor_transformed(&s->matrix, v, z);
}

/* z = D r: the transformed system's preconditioner solve (its preconditioner is D^-1). */
static void precondition_transformed(const double *r, double *z, void *data)
{
    const sinter_bonded_solver *s = data;
    sinter_block_ssor_diag_multiply(&s->matrix, r, z);
}

static sinter_status prepare(sinter_bonded_solver *s, size_t n, size_t count)
{
    const size_t dofs = 6 * n;
    sinter_status st = sinter_grow(s->ctx, (void **)&s->mask, &s->mask_capacity, dofs + 1, 1);
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->residual, &s->residual_capacity, dofs + 1,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->load, &s->load_capacity, dofs + 1, sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->displacement, &s->displacement_capacity, dofs + 1,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->lower, &s->lower_capacity, count + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(s->ctx, (void **)&s->upper, &s->upper_capacity, count + 1,
                         sizeof(uint32_t));
    if (st != SINTER_OK)
        return st;
    const int maxl = (int)(2 * dofs < 1000 ? 1000 : 2 * dofs);
    return sinter_pcg_reserve(s->ctx, &s->pcg, dofs, maxl);
}

/* The stiffness blocks of one thread's share (sinter_two_parts over block_ssor.h's domains):
 * part 1 owns B's particles, part 0 A's and S's. Each owner writes the coupling blocks of its
 * rows and sums the diagonal blocks of its particles, each over its links in block order, as
 * one thread would: part 1 takes B's rows, whose blocks touch only B and S (S's share left to
 * part 0); part 0 A's rows, then the blocks from B's rows into S (their stiffness computed a
 * second time, for S), then S's rows. */
typedef struct assembly {
    sinter_block_ssor *m;
    const sinter_beam *links;
    const uint32_t *place;
} assembly;

static int owns(const sinter_block_ssor *m, int which, size_t p)
{
    return (p >= m->split_a && p < m->split_b) == which;
}

static void stiffness_block(const assembly *w, int which, size_t e, int coupling)
{
    sinter_block_ssor *m = w->m;
    const sinter_beam *l = &w->links[m->link_of[e]];
    double ke[144];
    sinter_beam_stiffness(l, ke);
    const size_t a = w->place[l->a], b = w->place[l->b];
    const int add_a = owns(m, which, a), add_b = owns(m, which, b), a_first = a < b;
    double *u = m->upper_rows + 36 * e;
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) {
            if (add_a)
                m->diag[36 * a + (size_t)(6 * r + c)] += ke[12 * r + c];
            if (add_b)
                m->diag[36 * b + (size_t)(6 * r + c)] += ke[12 * (r + 6) + c + 6];
            /* U_pq, p the lower particle: K_AB if A is the lower one, else K_BA */
            if (coupling)
                u[6 * r + c] = a_first ? ke[12 * r + c + 6] : ke[12 * (r + 6) + c];
        }
}

static void assemble_part(void *data, int which)
{
    const assembly *w = data;
    const sinter_block_ssor *m = w->m;
    const size_t *row = m->row_start;
    if (which) {
        for (size_t e = row[m->split_a]; e < row[m->split_b]; ++e)
            stiffness_block(w, 1, e, 1);
        return;
    }
    for (size_t e = 0; e < row[m->split_a]; ++e)
        stiffness_block(w, 0, e, 1);
    for (size_t p = m->split_a; p < m->split_b; ++p)
        for (size_t e = m->row_cross[p]; e < row[p + 1]; ++e)
            stiffness_block(w, 0, e, 0);
    for (size_t e = row[m->split_b]; e < row[m->n]; ++e)
        stiffness_block(w, 0, e, 1);
}

/* The caller's index of unknown i of the domains' order. */
static size_t caller_dof(const sinter_domain_order *o, size_t i)
{
    return 6 * (size_t)o->old_of_new[i / 6] + i % 6;
}

/* 1 if particle p has a constrained DOF. */
static int any_constrained(const unsigned char *mask, size_t p)
{
    const unsigned char *d = mask + 6 * p;
    return d[0] | d[1] | d[2] | d[3] | d[4] | d[5];
}

/* The blocks of P K P + I - P (eq. 40) in the domains' order: each link's 12x12 stiffness adds
 * its AA and BB blocks to the diagonal and gives its coupling block; constrained rows and
 * columns become those of the identity. */
static sinter_status assemble(sinter_bonded_solver *s, size_t n, const sinter_beam *links,
                              size_t count, const unsigned char *fixed)
{
    const size_t dofs = 6 * n;
    for (size_t k = 0; k < count; ++k) {
        if (links[k].a >= n || links[k].b >= n || links[k].a == links[k].b)
            return sinter_fail(s->ctx, SINTER_ERR_INVALID,
                               "bonded solve: link %zu joins particles %u and %u of %zu", k,
                               (unsigned)links[k].a, (unsigned)links[k].b, n);
        const int a_first = links[k].a < links[k].b;
        s->lower[k] = a_first ? links[k].a : links[k].b;
        s->upper[k] = a_first ? links[k].b : links[k].a;
    }
    sinter_domain_order *o = &s->order;
    sinter_status st = sinter_domain_order_make(o, n, s->lower, s->upper, count);
    if (st != SINTER_OK)
        return st;
    const uint32_t *place = o->new_of_old;
    for (size_t k = 0; k < count; ++k) {
        const uint32_t a = place[links[k].a], b = place[links[k].b];
        s->lower[k] = a < b ? a : b;
        s->upper[k] = a < b ? b : a;
    }
    sinter_block_ssor *m = &s->matrix;
    st = sinter_block_ssor_layout(m, n, s->lower, s->upper, count, o->split_a, o->split_b);
    if (st != SINTER_OK)
        return st;
    memset(m->diag, 0, 36 * n * sizeof(double));
    const size_t blocks = m->row_start[n + 1];
    assembly w = {m, links, place};
    sinter_two_parts(sinter_block_ssor_threads(m), assemble_part, &w);
    for (size_t i = 0; i < dofs; ++i) {
        const double diag = m->diag[36 * (i / 6) + 7 * (i % 6)];
        s->mask[i] = (unsigned char)((fixed != NULL && fixed[caller_dof(o, i)]) || !(diag > 0.0));
    }
    for (size_t p = 0; p < n; ++p) {
        double *blk = m->diag + 36 * p;
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                if (s->mask[6 * p + (size_t)r] || s->mask[6 * p + (size_t)c])
                    blk[6 * r + c] = r == c ? 1.0 : 0.0;
    }
    for (size_t e = 0; e < blocks; ++e) {
        const size_t p = s->lower[m->link_of[e]], q = m->column[e];
        if (!any_constrained(s->mask, p) && !any_constrained(s->mask, q))
            continue;
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 6; ++c)
                if (s->mask[6 * p + (size_t)r] || s->mask[6 * q + (size_t)c])
                    m->upper_rows[36 * e + (size_t)(6 * r + c)] = 0.0;
    }
    size_t singular = 0;
    if (sinter_block_ssor_finish(m, &singular) != 0)
        return sinter_fail(s->ctx, SINTER_ERR_NOT_CONVERGED,
                           "bonded solve: the stiffness block of particle %u is singular",
                           (unsigned)o->old_of_new[singular]);
    return SINTER_OK;
}

static double norm2(const double *v, size_t n)
{
    return sqrt(sinter_pcg_dot(v, v, n));
}

sinter_status sinter_bonded_solve(sinter_bonded_solver *solver, size_t n, const sinter_beam *links,
                                  size_t count, const unsigned char *fixed, const double *f,
                                  double *u, double rtol, int *iterations)
{
    return sinter_bonded_solve_from(solver, n, links, count, fixed, f, NULL, u, rtol, iterations);
}

sinter_status sinter_bonded_solve_from(sinter_bonded_solver *solver, size_t n,
                                       const sinter_beam *links, size_t count,
                                       const unsigned char *fixed, const double *f,
                                       const double *guess, double *u, double rtol, int *iterations)
{
    SINTER_CHECK_NULL(NULL, solver);
    sinter_bonded_solver *s = solver;
    if (iterations)
        *iterations = 0;
    if (n == 0)
        return SINTER_OK;
    if (n >= UINT32_MAX / 6 || count >= UINT32_MAX)
        return sinter_fail(s->ctx, SINTER_ERR_INVALID,
                           "bonded solve: %zu links of %zu particles, too many", count, n);
    sinter_status st = prepare(s, n, count);
    if (st == SINTER_OK)
        st = assemble(s, n, links, count, fixed);
    if (st != SINTER_OK)
        return st;
    const size_t dofs = 6 * n;
    const sinter_block_ssor *m = &s->matrix;
    double *b = sinter_pcg_rhs(s->pcg), *x = sinter_pcg_solution(s->pcg), *r = s->residual;
    /* f and u in the domains' order (the original unknowns: un) */
    double *fn = s->load, *un = s->displacement;
    for (size_t i = 0; i < dofs; ++i) {
        const size_t caller = caller_dof(&s->order, i);
        un[i] = s->mask[i] || guess == NULL ? 0.0 : guess[caller];
        fn[i] = s->mask[i] ? 0.0 : f[caller];
    }
    memcpy(b, fn, dofs * sizeof(double));
    const double norm = norm2(b, dofs), target = rtol * norm;
    if (norm == 0.0) {
        memset(u, 0, dofs * sizeof(double));
        return SINTER_OK;
    }
    /* b^ = E^-1 f, x^ = E^T u. PCG's first target: 2 rtol relative to |b^|. (On the copper
     * packing, rtol |b^| left the true residual at about 0.3 rtol |f|; with 2 rtol |b^| the
     * solves take 5 % fewer iterations and 12 of 1389 need a second round: RESULTS.md,
     * session 14.) */
    sinter_block_ssor_lower_solve(m, b);
    sinter_block_ssor_upper_multiply(m, un, x);
    /* PCG's vectors in the domains' parts, each on the thread that sweeps it */
    sinter_pcg_set_parts(s->pcg, 6 * m->split_a, 6 * m->split_b, sinter_block_ssor_threads(m));
    double target_hat = FIRST_TARGET_FACTOR * rtol * norm2(b, dofs), true_residual = HUGE_VAL,
           hat_residual = 0.0;
    int taken = 0, rc = 0, done = 0;
    for (int round = 0; round < BONDED_SOLVE_ROUNDS && !done; ++round) {
        int more = 0;
        rc = sinter_pcg_solve(s->pcg, apply_transformed, precondition_transformed, s, target_hat,
                              &more, &hat_residual);
        taken += more;
        memcpy(un, x, dofs * sizeof(double)); /* u = E^-T x^ */
        sinter_block_ssor_upper_solve(m, un);
        sinter_block_ssor_multiply(m, un, r);
        for (size_t i = 0; i < dofs; ++i)
            r[i] = fn[i] - r[i];
        const double last = true_residual;
        true_residual = norm2(r, dofs);
        if (rc < 0 || !isfinite(true_residual))
            break;
        /* Done at the target, or when PCG met its own and another round did not halve the
         * true residual: that is the rounding floor of K u (a target under it, as 1e-13 on a
         * stiff link, cannot be met by any number of iterations), if the floor is below
         * ROUNDING_FLOOR |f|. */
        done = true_residual <= target || (rc == 0 && round > 0 && true_residual > 0.5 * last &&
                                           true_residual <= ROUNDING_FLOOR * norm);
        /* the transformed residual is the true one times about hat/true: aim a bit under */
        target_hat =
            hat_residual > 0.0 ? 0.5 * target * hat_residual / true_residual : 0.5 * target_hat;
    }
    if (iterations)
        *iterations = taken;
    for (size_t i = 0; i < dofs; ++i) /* back in the caller's order */
        u[caller_dof(&s->order, i)] = s->mask[i] ? 0.0 : un[i];
    if (!done)
        return sinter_fail(s->ctx, SINTER_ERR_NOT_CONVERGED,
                           "bonded solve: PCG returned %d after %d iterations (residual %g, "
                           "|f| %g) over %zu DOFs",
                           rc, taken, true_residual, norm, dofs);
    return SINTER_OK;
}
