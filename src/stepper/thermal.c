/* Heat in the stepper: evaluation, explicit and implicit update, softening. */
#include <math.h>
#include <string.h>

#include "contact/chunks.h"
#include "contact/particle_pass.h"
#include "core/pcg.h"
#include "domain/exact_reduce.h"
#include "domain/solve.h"
#include "electric/electric.h"
#include "sanity.h"
#include "stepper.h"

struct sinter_thermal_solver {
    sinter_pcg *pcg;
    /* operator data for one solve */
    const sinter_stepper *st;
    const double *diag;
    double *diag_storage;
    size_t diag_capacity;
    /* across subdomains (domain/solve.h): the ghosts' values and the reductions */
    sinter_domain_solve across;
};

static void solver_free(sinter_ctx *ctx, sinter_thermal_solver *s)
{
    if (s == NULL)
        return;
    sinter_pcg_free(s->pcg);
    sinter_free(ctx, s->diag_storage);
    sinter_domain_solve_free(&s->across);
    sinter_free(ctx, s);
}

void sinter_thermal_free(sinter_ctx *ctx, sinter_thermal *th)
{
    sinter_free(ctx, th->slots);
    sinter_free(ctx, th->g_pp);
    sinter_free(ctx, th->g_pw);
    sinter_free(ctx, th->modulus_scale);
    sinter_free(ctx, th->theta_backup);
    sinter_free(ctx, th->law_scratch);
    sinter_free(ctx, th->conductivity);
    solver_free(ctx, th->solver);
    memset(th, 0, sizeof(*th));
}

/* ---- softening ------------------------------------------------------------ */

/* E(theta)/E_0 of particle i (seed 000 sec. 7; seed 003 eq. 42; curve; host callback). */
static double softening_factor(const sinter_particles *ps, size_t i)
{
    const int32_t id = ps->material[i];
    const double *v = ps->materials[id].value, theta = ps->temperature[i];
    const double floor = v[SINTER_MAT_SOFTENING_FLOOR], ts = v[SINTER_MAT_SOFTENING_TEMPERATURE];
    const struct sinter_softening_curve *c = &ps->softening[id];
    double s = 1.0;
    switch ((int)v[SINTER_MAT_SOFTENING_LAW]) {
    case 1: /* K = max(K_0 (1 - theta/theta*), K_lim) */
        s = 1.0 - theta / ts;
        break;
    case 2: /* E = min(E_0, E_0 exp(c (1 - theta/theta*))) */
        s = fmin(1.0, exp(v[SINTER_MAT_SOFTENING_RATE] * (1.0 - theta / ts)));
        break;
    case 3: /* tabulated curve */
        if (c->count == 0)
            return 1.0;
        s = sinter_interpolate(c->count, c->temperature, c->factor, theta);
        break;
    case 4: /* host callback: validated by the caller */
        return c->fn != NULL ? c->fn(theta, c->user) : 1.0;
    default:
        return 1.0;
    }
    return fmax(s, floor);
}

/* The factors of particles [lo, hi) and the first one that is not positive and finite. */
typedef struct softening_job {
    const sinter_particles *ps;
    double *scale;
    size_t bad[SINTER_CHUNKS_MAX]; /* per range: the first bad particle, or SIZE_MAX */
} softening_job;

static void softening_range(void *data, int range, size_t lo, size_t hi)
{
    softening_job *job = data;
    job->bad[range] = SIZE_MAX;
    for (size_t i = lo; i < hi; ++i) {
        const double f = softening_factor(job->ps, i);
        if (!(f > 0.0) || !isfinite(f)) {
            job->bad[range] = i;
            return;
        }
        job->scale[i] = f;
    }
}

sinter_status sinter_thermal_softening(sinter_stepper *st, const double **scale)
{
    const sinter_particles *ps = st->ps;
    int any = 0, host = 0;
    for (int m = 0; m < ps->material_top; ++m) {
        const double law = ps->materials[m].value[SINTER_MAT_SOFTENING_LAW];
        any |= ps->material_used[m] && law != 0.0;
        host |= ps->material_used[m] && law == 4.0;
    }
    st->thermal.softening = any;
    *scale = NULL;
    if (!any)
        return SINTER_OK;
    sinter_thermal *th = &st->thermal;
    sinter_status s = sinter_grow(st->ctx, (void **)&th->modulus_scale, &th->scale_capacity,
                                  ps->count + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    /* on the contact law's particle ranges; a host's softening callback on one thread, as the
     * other callbacks */
    softening_job job = {ps, th->modulus_scale, {0}};
    const int ranges =
        sinter_particle_pass(st->ctx, host ? NULL : &st->pp, ps->count, softening_range, &job);
    for (int k = 0; k < ranges; ++k)
        if (job.bad[k] != SIZE_MAX) {
            const size_t i = job.bad[k];
            return sinter_fail(st->ctx, SINTER_ERR_CALLBACK,
                               "the softening law of material %d gave E/E_0 = %g for particle %zu "
                               "at %g K; it must be positive and finite",
                               (int)ps->material[i], softening_factor(ps, i), i,
                               ps->temperature[i]);
        }
    *scale = th->modulus_scale;
    return SINTER_OK;
}

/* ---- evaluation ----------------------------------------------------------- */

/* The explicit evaluation's inputs (the implicit one adds g_pp and g_pw). */
static sinter_heat_eval explicit_eval(sinter_stepper *st)
{
    sinter_heat_eval e;
    memset(&e, 0, sizeof(e));
    e.ctx = st->ctx;
    e.ps = st->ps;
    e.walls = st->walls;
    e.pp = &st->pp;
    e.pw = &st->pw;
    e.time = st->time;
    e.heat = st->ps->heat;
    e.view = &st->view;
    e.joule_dissipation = sinter_electric_dissipation(st->electric, st->ps->count);
    /* the gas between pairs apart (gas_gap.h) reads the candidate pairs of this layout */
    e.pairs =
        st->nb.built && st->nb.layout_generation == st->ps->layout_generation ? &st->nb.pp : NULL;
    e.dissipation = st->dissipation_valid ? st->dissipation : NULL; /* heat/dissipation.c */
    e.flags = st->ps->flags; /* the beams' SINTER_PARTICLE_LIT */
    /* periodic images: sources act on the owned particles only (heat_model.h) */
    e.owned = st->ps->count - st->ps->ghost_count;
    e.ghost_owner = st->ps->ghost_count > 0 ? st->ghosts.owner : NULL;
    /* other subdomains' ghosts and collective calls (not for a local estimate) */
    e.domain = st->domain.on && !st->thermal.local_eval ? &st->domain : NULL;
    return e;
}

int sinter_thermal_collective(const sinter_stepper *st)
{
    for (size_t k = 0; st->domain.on && k < st->thermal.count; ++k) {
        const sinter_heat_ops *ops = st->thermal.slots[k].model->ops;
        if (ops == &sinter_heat_laser || ops == &sinter_heat_nozzle || ops == &sinter_heat_beam)
            return 1;
    }
    return 0;
}

sinter_status sinter_thermal_conductivities(sinter_stepper *st, const double **k)
{
    sinter_thermal *th = &st->thermal;
    const sinter_particles *ps = st->ps;
    *k = NULL;
    if (!ps->tabulated[SINTER_PROPERTY_THERMAL_CONDUCTIVITY])
        return SINTER_OK;
    sinter_status s = sinter_grow(st->ctx, (void **)&th->conductivity, &th->conductivity_capacity,
                                  ps->count + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    for (size_t i = 0; i < ps->count; ++i)
        th->conductivity[i] = sinter_particle_property(ps, i, SINTER_PROPERTY_THERMAL_CONDUCTIVITY,
                                                       SINTER_MAT_THERMAL_CONDUCTIVITY);
    *k = th->conductivity;
    return SINTER_OK;
}

int sinter_thermal_law_begin(sinter_stepper *st)
{
    sinter_thermal *th = &st->thermal;
    th->first_in_law = 0;
    /* k(theta) tables: conduction_eval's general loops, after the law */
    if (st->ps->tabulated[SINTER_PROPERTY_THERMAL_CONDUCTIVITY])
        return 0;
    /* on one thread there is no fork to save nor wait to fill, and the interleaved passes
     * measured 1-2 % slower (RESULTS.md, issue 9, session 20) */
    if (th->count == 0 || th->scheme != SINTER_THERMAL_EXPLICIT ||
        th->slots[0].model->ops != &sinter_heat_conduction || st->pp.chunks.count == 0 ||
        sinter_threads(st->ctx) < 2)
        return 0;
    if (sinter_grow(st->ctx, &th->law_scratch, &th->law_scratch_capacity,
                    sinter_conduction_ranges_scratch(st->pp.count), 1) != SINTER_OK) {
        sinter_clear_error(st->ctx); /* no room: evaluated after the law, as before */
        return 0;
    }
    const sinter_heat_eval e = explicit_eval(st);
    if (!sinter_conduction_ranges_begin(th->slots[0].model, &e, th->law_scratch, &th->law_job) ||
        th->law_job.walls_left)
        return 0;
    if (!th->heat_zeroed && st->ps->count > 0) /* the drift zeroes it on the threads when it can */
        memset(st->ps->heat, 0, st->ps->count * sizeof(double));
    th->heat_zeroed = 1;
    return 1;
}

void sinter_thermal_law_interior(void *stepper, int range)
{
    sinter_conduction_range_interior(&((sinter_stepper *)stepper)->thermal.law_job, range);
}

void sinter_thermal_law_rest(sinter_stepper *st, int range)
{
    sinter_conduction_range_rest(&st->thermal.law_job, range);
}

void sinter_thermal_law_end(sinter_stepper *st, int ran)
{
    st->thermal.first_in_law = ran;
    st->thermal.law_evaluations += (uint64_t)ran;
}

sinter_status sinter_thermal_eval(sinter_stepper *st)
{
    sinter_thermal *th = &st->thermal;
    sinter_particles *ps = st->ps;
    const size_t n = ps->count;
    if (!th->heat_zeroed && n > 0) /* (an empty set has no arrays) */
        memset(ps->heat, 0, n * sizeof(double));
    th->heat_zeroed = 0;
    const int first_done = th->first_in_law;
    th->first_in_law = 0;
    if (th->count == 0)
        return SINTER_OK;
    for (size_t k = 0; k < th->count; ++k)
        if (sinter_heat_reads_geometry(th->slots[k].model, st->time))
            sinter_contacts_geometry(st->ctx, &st->pp, ps); /* a lean list gets it here */
    sinter_heat_eval e = explicit_eval(st);
    sinter_status ks = sinter_thermal_conductivities(st, &e.conductivity);
    if (ks != SINTER_OK)
        return ks;
    if (th->scheme == SINTER_THERMAL_IMPLICIT) {
        sinter_status s = sinter_grow(st->ctx, (void **)&th->g_pp, &th->g_pp_capacity,
                                      st->pp.count + 1, sizeof(double));
        if (s == SINTER_OK)
            s = sinter_grow(st->ctx, (void **)&th->g_pw, &th->g_pw_capacity, st->pw.count + 1,
                            sizeof(double));
        if (s != SINTER_OK)
            return s;
        memset(th->g_pp, 0, st->pp.count * sizeof(double));
        memset(th->g_pw, 0, st->pw.count * sizeof(double));
        e.g_pp = th->g_pp;
        e.g_pw = th->g_pw;
    }
    double before = 0.0;
    for (size_t k = 0; k < th->count; ++k) {
        sinter_heat_slot *slot = &th->slots[k];
        /* the first model may have been summed in the law's region (sinter_thermal_law_begin) */
        sinter_status s =
            k == 0 && first_done ? SINTER_OK : slot->model->ops->eval(slot->model, &e);
        if (s != SINTER_OK)
            return s;
        /* four partial sums: the dependent additions of one would take longer than the
         * submodel at a million particles */
        double part[4] = {0.0, 0.0, 0.0, 0.0};
        /* (with ghosts of other subdomains, this subdomain's share: its owned particles) */
        const size_t m = st->domain.on ? n - ps->ghost_count : n;
        size_t i = 0;
        for (; i + 4 <= m; i += 4)
            for (int a = 0; a < 4; ++a)
                part[a] += ps->heat[i + (size_t)a];
        for (; i < m; ++i)
            part[0] += ps->heat[i];
        const double after = (part[0] + part[1]) + (part[2] + part[3]);
        slot->power = after - before;
        before = after;
    }
    return SINTER_OK;
}

/* ---- update --------------------------------------------------------------- */

static sinter_status backup(sinter_stepper *st)
{
    sinter_thermal *th = &st->thermal;
    const size_t n = st->ps->count;
    sinter_status s = sinter_grow(st->ctx, (void **)&th->theta_backup, &th->backup_capacity, n + 1,
                                  sizeof(double));
    if (s == SINTER_OK && n > 0)
        memcpy(th->theta_backup, st->ps->temperature, n * sizeof(double));
    return s;
}

void sinter_thermal_rollback(sinter_stepper *st)
{
    if (st->thermal.count == 0)
        return;
    if (st->ps->count > 0)
        memcpy(st->ps->temperature, st->thermal.theta_backup, st->ps->count * sizeof(double));
    /* energies: the rejected step's contribution is taken back */
    for (size_t k = 0; k < st->thermal.count; ++k) {
        st->thermal.slots[k].energy -= st->thermal.slots[k].applied;
        st->thermal.slots[k].applied = 0.0;
    }
}

static int fixed(const sinter_particles *ps, size_t i)
{
    return (ps->flags[i] & SINTER_PARTICLE_FIXED_TEMPERATURE) != 0;
}

/* The unknown of particle row j: the row, or an image's owner (periodic boundaries, issue 38:
 * the unknowns are the owned particles, rows [0, owned); ghosts/ghosts.h). */
static inline uint32_t owner_of(const sinter_stepper *st, size_t owned, uint32_t j)
{
    return j < owned ? j : st->ghosts.owner[j - owned];
}

/* z = A v for backward Euler: A = diag(m C / h + sum G) - G couplings (free rows only); a
 * contact with an image couples to the image's owner. */
static void apply_operator(const double *vv, double *zz, void *data)
{
    const sinter_thermal_solver *s = data;
    const sinter_stepper *st = s->st;
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    for (size_t i = 0; i < owned; ++i)
        zz[i] = s->diag[i] * vv[i];
    const sinter_contact_list *c = &st->pp;
    const double *g = st->thermal.g_pp;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = owner_of(st, owned, c->j[k]);
        if (fixed(ps, i) || fixed(ps, j))
            continue; /* coupling to a fixed temperature lives in the right-hand side */
        zz[i] -= g[k] * vv[j];
        zz[j] -= g[k] * vv[i];
    }
}

/* The same product across subdomains (domain/solve.h): the owned rows only, a ghost's value
 * from its owner through the forward halo; a pair with a ghost end adds to its owned end. */
static void apply_operator_across(const double *vv, double *zz, void *data)
{
    sinter_thermal_solver *s = data;
    const sinter_stepper *st = s->st;
    const sinter_particles *ps = st->ps;
    const size_t owned = ps->count - ps->ghost_count;
    sinter_domain_solve_forward(&s->across, vv);
    const double *v = s->across.rows;
    for (size_t i = 0; i < owned; ++i)
        zz[i] = s->diag[i] * v[i];
    if (owned == 0) /* (the placeholder unknown of an empty subdomain: the identity) */
        zz[0] = vv[0];
    const sinter_contact_list *c = &st->pp;
    const double *g = st->thermal.g_pp;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        if (fixed(ps, i) || fixed(ps, j))
            continue;
        if (i < owned)
            zz[i] -= g[k] * v[j];
        if (j < owned)
            zz[j] -= g[k] * v[i];
    }
}

/* Jacobi preconditioner: z = r / diag. */
static void precondition(const double *rr, double *zz, void *data)
{
    const sinter_thermal_solver *s = data;
    for (size_t i = 0; i < s->st->ps->count - s->st->ps->ghost_count; ++i)
        zz[i] = rr[i] / s->diag[i];
}

/* The solver for n unknowns here, of `total` over every subdomain (the iteration limit,
 * the same everywhere). */
static sinter_status ensure_solver(sinter_stepper *st, size_t n, size_t total)
{
    sinter_thermal *th = &st->thermal;
    if (th->solver == NULL) {
        th->solver = sinter_calloc(st->ctx, 1, sizeof(*th->solver));
        if (th->solver == NULL)
            return SINTER_ERR_NOMEM;
    }
    return sinter_pcg_reserve(st->ctx, &th->solver->pcg, n,
                              (int)(total < 1000        ? 1000
                                    : total > INT32_MAX ? INT32_MAX
                                                        : total));
}

/* The temperatures of the solution x of the owned particles [0, n), and the power applied. */
static void apply_solution(sinter_stepper *st, double h, const double *x, size_t n)
{
    sinter_particles *ps = st->ps;
    const double *theta = ps->temperature;
    for (size_t i = 0; i < n; ++i) {
        if (fixed(ps, i))
            continue;
        const double mc = ps->mass[i] * sinter_particle_heat_capacity(ps, i, theta[i]);
        ps->heat[i] = mc * (x[i] - theta[i]) / h; /* the power actually applied */
        const sinter_enthalpy *H = sinter_particle_enthalpy(ps, i);
        /* with C(theta) or latent heat the energy mc (x - theta) goes into the enthalpy */
        ps->temperature[i] = H == NULL
                                 ? x[i]
                                 : sinter_enthalpy_inverse(H, sinter_enthalpy_at(H, theta[i]) +
                                                                  ps->heat[i] * h / ps->mass[i]);
    }
}

/* The outcome of the PCG solve (return code rc): a failure, or the iterations counted and the
 * solution x of the n owned particles taken. */
static sinter_status take_solution(sinter_stepper *st, double h, const double *x, size_t n, int rc,
                                   int iterations, double residual)
{
    if (rc != 0)
        return sinter_fail(st->ctx, SINTER_ERR_NOT_CONVERGED,
                           "implicit conduction: PCG returned %d after %d iterations at t = %g s "
                           "(residual %g)",
                           rc, iterations, st->time, residual);
    st->stats_thermal_iterations += (uint64_t)iterations;
    apply_solution(st, h, x, n);
    return SINTER_OK;
}

/*
 * The backward-Euler system of the owned particles, rows [0, n): diag, b and the start x (the
 * temperatures at t); returns this side's |b|^2. `across`: a pair's end at a row >= n is a ghost
 * of another subdomain, whose row is assembled there; else an end is the unknown of its row or
 * of an image's owner (owner_of). The same operations in the same order either way.
 */
static double assemble(sinter_stepper *st, double h, size_t n, int across, double *diag, double *b,
                       double *x)
{
    const sinter_particles *ps = st->ps;
    const sinter_thermal *th = &st->thermal;
    const double *theta = ps->temperature;
    for (size_t i = 0; i < n; ++i) {
        /* C(theta) at the step's start (linearised backward Euler; the energy is kept exact
         * below through the enthalpy) */
        const double mc = ps->mass[i] * sinter_particle_heat_capacity(ps, i, theta[i]);
        diag[i] = fixed(ps, i) ? 1.0 : mc / h;
        b[i] = fixed(ps, i) ? theta[i] : mc / h * theta[i] + ps->heat[i];
        x[i] = theta[i];
    }
    const sinter_contact_list *c = &st->pp;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = across ? c->j[k] : owner_of(st, n, c->j[k]);
        const double g = th->g_pp[k];
        if ((!across || i < n) && !fixed(ps, i)) {
            diag[i] += g;
            if (fixed(ps, j))
                b[i] += g * theta[j];
        }
        if ((!across || j < n) && !fixed(ps, j)) {
            diag[j] += g;
            if (fixed(ps, i))
                b[j] += g * theta[i];
        }
    }
    c = &st->pw;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k];
        if ((across && i >= n) || fixed(ps, i))
            continue;
        diag[i] += th->g_pw[k];
        b[i] += th->g_pw[k] * st->walls->wall[c->j[k]].temperature;
    }
    double bnorm = 0.0;
    for (size_t i = 0; i < n; ++i)
        bnorm += b[i] * b[i];
    return bnorm;
}

/*
 * The reproducible mode (issue 43): |b|^2 as an exact sum over every subdomain (d NULL: this
 * part's), the same bits for any split. The rows' own terms already come in an order fixed by
 * the ids (the sorted pair list), and the PCG's dot products are exact sums too
 * (sinter_domain_solve_exact_dot), so that the solve is the same bits without domain operations
 * and on any number of subdomains.
 */
static sinter_status repro_norm(sinter_stepper *st, sinter_domain *d, const double *b, size_t n,
                                double *bnorm)
{
    return sinter_domain_exact_sums(st->ctx, d, 1, &b, &b, &n, bnorm);
}

/*
 * Backward Euler across subdomains (domain/solve.h): the owned particles' rows, the pairs with
 * a ghost end assembled on this side for their owned end (the other side assembles its own),
 * the ghosts' temperatures those of their owners at t (the halo after the last accepted
 * step). The same operations in the same order as implicit_update on one subdomain.
 */
static sinter_status implicit_update_across(sinter_stepper *st, double h)
{
    sinter_particles *ps = st->ps;
    sinter_thermal *th = &st->thermal;
    sinter_domain *d = &st->domain;
    const size_t n = ps->count - ps->ghost_count, rows = n > 0 ? n : 1;
    uint64_t total = n;
    sinter_status s =
        sinter_domain_reduce(st->ctx, d, &total, 1, SINTER_REDUCE_U64, SINTER_REDUCE_SUM);
    if (s == SINTER_OK)
        s = ensure_solver(st, rows, (size_t)total);
    sinter_thermal_solver *sv = th->solver;
    if (s == SINTER_OK) {
        sv->across =
            (sinter_domain_solve){st->ctx, d, ps, sv->across.rows, sv->across.rows_capacity, 0};
        s = sinter_domain_solve_reserve(&sv->across, 1);
    }
    if (s == SINTER_OK)
        s = sinter_grow(st->ctx, (void **)&sv->diag_storage, &sv->diag_capacity, rows + 1,
                        sizeof(double));
    if ((s = sinter_domain_agree(st->ctx, d, s)) != SINTER_OK)
        return s;
    double *diag = sv->diag_storage, *b = sinter_pcg_rhs(sv->pcg),
           *x = sinter_pcg_solution(sv->pcg);
    diag[0] = 1.0; /* an empty subdomain's placeholder unknown: 1 x = 0 */
    b[0] = x[0] = 0.0;
    sv->st = st;
    sv->diag = diag;
    double bnorm = assemble(st, h, n, 1, diag, b, x);
    if (st->reproducible) /* |b|^2 and every dot product exact sums (repro_norm) */
        s = repro_norm(st, d, b, n, &bnorm);
    else
        s = sinter_domain_reduce(st->ctx, d, &bnorm, 1, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (s != SINTER_OK)
        return s;
    const double tol = 1e-13 * sqrt(bnorm) + 1e-300;
    int iterations = 0;
    double residual = 0.0;
    sinter_pcg_set_sum(sv->pcg, sinter_domain_solve_sum, &sv->across, n);
    if (st->reproducible)
        sinter_pcg_set_dot(sv->pcg, sinter_domain_solve_exact_dot, &sv->across, n);
    const int rc = sinter_pcg_solve(sv->pcg, apply_operator_across, precondition, sv, tol,
                                    &iterations, &residual);
    sinter_pcg_set_sum(sv->pcg, NULL, NULL, 0);
    sinter_pcg_set_dot(sv->pcg, NULL, NULL, 0);
    if (sv->across.failed)
        return sinter_last_status(st->ctx);
    /* (every subdomain: the same reduced residuals) */
    return take_solution(st, h, x, n, rc, iterations, residual);
}

static sinter_status implicit_update(sinter_stepper *st, double h)
{
    if (st->domain.on)
        return implicit_update_across(st, h);
    sinter_particles *ps = st->ps;
    sinter_thermal *th = &st->thermal;
    const size_t n = ps->count - ps->ghost_count; /* the owned particles: the unknowns */
    sinter_status s = ensure_solver(st, n, n);
    if (s != SINTER_OK)
        return s;
    sinter_thermal_solver *sv = th->solver;
    s = sinter_grow(st->ctx, (void **)&sv->diag_storage, &sv->diag_capacity, n + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    double *diag = sv->diag_storage, *b = sinter_pcg_rhs(sv->pcg),
           *x = sinter_pcg_solution(sv->pcg);
    sv->st = st;
    sv->diag = diag;
    double bnorm = assemble(st, h, n, 0, diag, b, x);
    if (st->reproducible) { /* the decomposed run's exact sums, on this part alone */
        sv->across =
            (sinter_domain_solve){st->ctx, NULL, ps, sv->across.rows, sv->across.rows_capacity, 0};
        if ((s = repro_norm(st, NULL, b, n, &bnorm)) != SINTER_OK)
            return s;
        sinter_pcg_set_dot(sv->pcg, sinter_domain_solve_exact_dot, &sv->across, n);
    }
    const double tol = 1e-13 * sqrt(bnorm) + 1e-300;
    int iterations = 0;
    double residual = 0.0;
    const int rc =
        sinter_pcg_solve(sv->pcg, apply_operator, precondition, sv, tol, &iterations, &residual);
    sinter_pcg_set_dot(sv->pcg, NULL, NULL, 0);
    if (st->reproducible && sv->across.failed)
        return sinter_last_status(st->ctx);
    return take_solution(st, h, x, n, rc, iterations, residual);
}

static sinter_status thermal_booked(sinter_stepper *st, double h);

/*
 * Walls with SINTER_WALL_IMPOSED (seed 000 Fig. 5, remark 2): after a thermal update each
 * particle touching one (in the contact list the update's powers came from) takes its
 * temperature, fixed-temperature particles aside; the heat this takes, sum m C (theta_w -
 * theta), is booked to the first "conduction" model (its power over the step h), else to none.
 */
static void impose_wall_temperatures(sinter_stepper *st, double h)
{
    const sinter_walls *walls = st->walls;
    if (walls == NULL || st->pw.count == 0)
        return;
    int any = 0;
    for (size_t w = 0; w < walls->count; ++w)
        any |= walls->wall[w].thermal_mode == SINTER_WALL_IMPOSED;
    if (!any)
        return;
    sinter_particles *ps = st->ps;
    double energy = 0.0;
    for (size_t k = 0; k < st->pw.count; ++k) {
        const uint32_t i = st->pw.i[k];
        const sinter_wall *wall = &walls->wall[st->pw.j[k]];
        if (wall->thermal_mode != SINTER_WALL_IMPOSED || fixed(ps, i))
            continue;
        const sinter_enthalpy *H = sinter_particle_enthalpy(ps, i);
        if (H != NULL) {
            energy += ps->mass[i] * (sinter_enthalpy_at(H, wall->temperature) -
                                     sinter_enthalpy_at(H, ps->temperature[i]));
        } else {
            const double mc = ps->mass[i] * sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY);
            energy += mc * (wall->temperature - ps->temperature[i]);
        }
        ps->temperature[i] = wall->temperature;
    }
    for (size_t k = 0; k < st->thermal.count; ++k)
        if (st->thermal.slots[k].model->ops == &sinter_heat_conduction) {
            st->thermal.slots[k].power += energy / h;
            break;
        }
}

/* The saved temperatures' room, for the explicit update. */
sinter_status sinter_thermal_explicit_begin(sinter_stepper *st)
{
    sinter_thermal *th = &st->thermal;
    th->hot_checked = 0;
    return sinter_grow(st->ctx, (void **)&th->theta_backup, &th->backup_capacity, st->ps->count + 1,
                       sizeof(double));
}

/* The explicit update of [lo, hi) when a material's temperature advances through its enthalpy:
 * H(theta_1) = H(theta_0) + h Q / m (seed 003 eq. 46 written for H); the others as usual. */
static void enthalpy_range(sinter_stepper *st, double h, size_t lo, size_t hi, size_t *bad,
                           size_t *hot)
{
    sinter_particles *ps = st->ps;
    double *restrict saved = st->thermal.theta_backup, *restrict temp = ps->temperature;
    for (size_t i = lo; i < hi; ++i) {
        const double t0 = temp[i];
        saved[i] = t0;
        if (fixed(ps, i))
            continue;
        const sinter_enthalpy *H = sinter_particle_enthalpy(ps, i);
        double t1;
        if (H == NULL) {
            const double mc = ps->mass[i] * sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY);
            t1 = t0 + h * ps->heat[i] / mc;
        } else {
            t1 = sinter_enthalpy_inverse(H,
                                         sinter_enthalpy_at(H, t0) + h * ps->heat[i] / ps->mass[i]);
        }
        temp[i] = t1;
        if (!(t1 > 0.0 && t1 < INFINITY) && i < *bad)
            *bad = i;
        if (!(t1 <= SINTER_SANITY_MAX_TEMPERATURE) && i < *hot)
            *hot = i;
    }
}

void sinter_thermal_explicit_range(sinter_stepper *st, double h, size_t lo, size_t hi, size_t *bad,
                                   size_t *hot)
{
    sinter_particles *ps = st->ps;
    double *restrict saved = st->thermal.theta_backup, *restrict temp = ps->temperature;
    size_t first_bad = hi, first_hot = hi;
    if (__builtin_expect(ps->enthalpy, 0)) { /* C(theta) or latent heat (property_table.h) */
        enthalpy_range(st, h, lo, hi, &first_bad, &first_hot);
    } else {
        for (size_t i = lo; i < hi; ++i) {
            const double t0 = temp[i];
            saved[i] = t0;
            if (fixed(ps, i))
                continue;
            const double mc = ps->mass[i] * sinter_particle_param(ps, i, SINTER_MAT_HEAT_CAPACITY);
            const double t1 = t0 + h * ps->heat[i] / mc;
            temp[i] = t1;
            if (!(t1 > 0.0 && t1 < INFINITY) && i < first_bad)
                first_bad = i;
            if (!(t1 <= SINTER_SANITY_MAX_TEMPERATURE) && i < first_hot)
                first_hot = i;
        }
    }
    *bad = first_bad;
    *hot = first_hot;
}

sinter_status sinter_thermal_explicit_end(sinter_stepper *st, double h, size_t bad, size_t hot)
{
    sinter_thermal *th = &st->thermal;
    sinter_particles *ps = st->ps;
    th->hot_checked = 1;
    th->hot = hot;
    if (bad < ps->count) {
        const double theta = ps->temperature[bad];
        memcpy(ps->temperature, th->theta_backup, ps->count * sizeof(double));
        double dt_stable = 0.0;
        sinter_stepper_stable_dt_thermal(st, &dt_stable);
        return sinter_fail(st->ctx, SINTER_ERR_UNSTABLE,
                           "explicit heat step at t = %g s rejected: the temperature of "
                           "particle %zu (id %llu) would become %g K; the step %g s exceeds "
                           "the explicit thermal limit %g s (use the implicit thermal "
                           "scheme or a smaller step)",
                           st->time, bad, (unsigned long long)ps->id[bad], theta, h, dt_stable);
    }
    impose_wall_temperatures(st, h);
    return thermal_booked(st, h);
}

sinter_status sinter_thermal_implicit_advance(sinter_stepper *st, double h)
{
    sinter_thermal *th = &st->thermal;
    th->hot_checked = 0;
    if (th->count == 0)
        return SINTER_OK;
    sinter_status s = backup(st);
    if (st->domain.on) /* (the solve is collective: every subdomain or none) */
        s = sinter_domain_agree(st->ctx, &st->domain, s);
    if (s == SINTER_OK)
        s = implicit_update(st, h);
    if (s == SINTER_OK)
        impose_wall_temperatures(st, h);
    return s == SINTER_OK ? thermal_booked(st, h) : s;
}

/* The energies of an update that succeeded booked, and its step kept. */
static sinter_status thermal_booked(sinter_stepper *st, double h)
{
    sinter_thermal *th = &st->thermal;
    for (size_t k = 0; k < th->count; ++k) {
        th->slots[k].applied = th->slots[k].power * h;
        th->slots[k].energy += th->slots[k].applied;
    }
    st->thermal_last_h = h;
    return SINTER_OK;
}
