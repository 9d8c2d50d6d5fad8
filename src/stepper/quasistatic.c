/* Quasi-static sintering stepper (seed 001 sec. 2-3, fig. 6-7); see quasistatic.h. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stepper/quasistatic.h"
#include "stepper/qs_domain.h"
#include "stepper/qs_floating.h"
#include "stepper/qs_repro.h"
#include "stepper/qs_struct.h"
#include "stepper/stepper.h"
#include "particles/particles.h"
#include "contact/neighbors.h"

#define QS_PI 3.14159265358979323846

void sinter_qs_options_default(sinter_qs_options *opt)
{
    /* Strategy 3 with its whole-run setting (issue 45, tests/bench/RESULTS.md): young necks
     * each on their own CVODE steps, grown ones by strategy 2's RK4, the global step by the
     * links' strain with 1 % of them allowed above max_strain */
    opt->strategy = 3;
    opt->dt_initial = 1e-6;
    opt->dt_min = 1e-12;
    opt->dt_max = 10.0; /* docs/7dof.md §5: the seed's maximum global step */
    opt->alpha = 1.5;
    opt->error_limit = 1.0;
    opt->grow_fraction = 0.05;
    opt->shrink_fraction = 0.15;
    opt->contact_tolerance = 1e-9;
    opt->plane_tolerance = 1e-6;
    /* PCG residual of each step's K u = f relative to |f|: 1e-7 moves the copper packing's
     * shrinkage at 5000 s by 1.3e-8 relative to 1e-10 (the mechanical discretization error is
     * 3e-4) for 30 % less CPU (tests/bench/RESULTS.md, session 3) */
    opt->solve_rtol = 1e-7;
    opt->rtol = 1e-6;
    opt->epsilon = 0.01;
    opt->h0_ratio = 1.5;
    opt->max_strain = 7e-5;
    opt->strain_fraction = 0.01;
    opt->grown_rk4 = 1.0;
    opt->young_pairs = 1.0;
    opt->new_contacts = 1.0;
    opt->validity = 1.0;
    opt->neck_stiffness = 0.0;
    opt->neck_law = 0.0;
    opt->cell_strain = 1.0;
    memset(&opt->host_law, 0, sizeof(opt->host_law));
    opt->host_law_user = NULL;
}

double sinter_qs_section_scale(const sinter_qs_options *opt, const sinter_qs_link *l)
{
    if (opt->neck_stiffness == 0.0)
        return 1.0;
    const double ratio = l->neck.y[SINTER_NECK_X] / l->rm;
    return ratio * ratio;
}

/* The option table: key, offset of the double (or -1 for strategy), lower and upper bound, and
 * whether the lower bound is open. */
typedef struct qs_key {
    const char *key;
    size_t offset;
    double lo, hi;
    int open_lo;
} qs_key;

#define QS_KEY(name, field, lo, hi, open)                                                          \
    {                                                                                              \
        name, offsetof(sinter_qs_options, field), lo, hi, open                                     \
    }
static const qs_key qs_keys[] = {
    QS_KEY("qs_dt_min", dt_min, 0.0, INFINITY, 1),
    QS_KEY("qs_dt_max", dt_max, 0.0, INFINITY, 1),
    QS_KEY("qs_alpha", alpha, 1.0, 100.0, 1),
    QS_KEY("qs_error_limit", error_limit, 0.0, INFINITY, 1),
    QS_KEY("qs_grow_fraction", grow_fraction, 0.0, 1.0, 0),
    QS_KEY("qs_shrink_fraction", shrink_fraction, 0.0, 1.0, 0),
    QS_KEY("qs_contact_tolerance", contact_tolerance, 0.0, 1.0, 0),
    QS_KEY("qs_plane_tolerance", plane_tolerance, 0.0, 1.0, 0),
    QS_KEY("qs_solve_rtol", solve_rtol, 0.0, 1.0, 1),
    QS_KEY("qs_rtol", rtol, 0.0, 1.0, 1),
    QS_KEY("qs_epsilon", epsilon, 0.0, 0.5, 1),
    QS_KEY("qs_h0_ratio", h0_ratio, 1.0, 2.0, 1),
    QS_KEY("qs_max_strain", max_strain, 0.0, 1.0, 1),
    QS_KEY("qs_strain_fraction", strain_fraction, 0.0, 1.0, 0),
    QS_KEY("qs_grown_rk4", grown_rk4, 0.0, 1.0, 0),
    QS_KEY("qs_young_pairs", young_pairs, 0.0, 1.0, 0),
    QS_KEY("qs_new_contacts", new_contacts, 0.0, 1.0, 0),
    QS_KEY("qs_validity", validity, 0.0, 2.0, 0),
    QS_KEY("qs_neck_stiffness", neck_stiffness, 0.0, 1.0, 0),
    QS_KEY("qs_neck_law", neck_law, 0.0, 2.0, 0),
    QS_KEY("qs_cell_strain", cell_strain, 0.0, 1.0, 0),
};

/* SINTER_ERR_NOT_FOUND with the list of keys. */
static sinter_status unknown_key(sinter_ctx *ctx, const char *key)
{
    char list[640] = "qs_strategy";
    size_t len = strlen(list);
    for (size_t k = 0; k < sizeof(qs_keys) / sizeof(qs_keys[0]) && len < sizeof(list); ++k)
        len += (size_t)snprintf(list + len, sizeof(list) - len, ", %s", qs_keys[k].key);
    return sinter_fail(ctx, SINTER_ERR_NOT_FOUND,
                       "the quasi-static stepper has no option '%s' (options: %s)", key, list);
}

sinter_status sinter_qs_option_set(sinter_qs_options *opt, sinter_ctx *ctx, const char *key,
                                   double value)
{
    if (strcmp(key, "qs_strategy") == 0) {
        if (value != 1.0 && value != 2.0 && value != 3.0)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "qs_strategy = %g: expected 1 (global RK4 step), 2 (per-pair "
                               "sub-steps) or 3 (CVODE batch)",
                               value);
        opt->strategy = (int)value;
        return SINTER_OK;
    }
    for (size_t k = 0; k < sizeof(qs_keys) / sizeof(qs_keys[0]); ++k) {
        const qs_key *q = &qs_keys[k];
        if (strcmp(key, q->key) != 0)
            continue;
        if (!(value <= q->hi && (q->open_lo ? value > q->lo : value >= q->lo)))
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s = %g is outside %s%g, %g]", key, value,
                               q->open_lo ? "(" : "[", q->lo, q->hi);
        if (!isfinite(value))
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s = %g: the value must be finite", key,
                               value);
        if (q->offset == offsetof(sinter_qs_options, validity) && value != floor(value))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s = %g: expected 0 (off), 1 (warn) or 2 (error)", key, value);
        if (q->offset == offsetof(sinter_qs_options, neck_law) && value != floor(value))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s = %g: expected 0 (the 7DOF model), 1 (grain-boundary "
                               "diffusion law) or 2 (host law)",
                               key, value);
        if ((q->offset == offsetof(sinter_qs_options, dt_min) && value > opt->dt_max) ||
            (q->offset == offsetof(sinter_qs_options, dt_max) && value < opt->dt_min))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s = %g would leave qs_dt_min above qs_dt_max (now %g and %g s)",
                               key, value, opt->dt_min, opt->dt_max);
        *(double *)((char *)opt + q->offset) = value;
        return SINTER_OK;
    }
    return unknown_key(ctx, key);
}

sinter_status sinter_qs_option_get(const sinter_qs_options *opt, sinter_ctx *ctx, const char *key,
                                   double *value)
{
    if (strcmp(key, "qs_strategy") == 0) {
        *value = opt->strategy;
        return SINTER_OK;
    }
    for (size_t k = 0; k < sizeof(qs_keys) / sizeof(qs_keys[0]); ++k)
        if (strcmp(key, qs_keys[k].key) == 0) {
            *value = *(const double *)((const char *)opt + qs_keys[k].offset);
            return SINTER_OK;
        }
    return unknown_key(ctx, key);
}

sinter_status sinter_qs_create(sinter_qs **out, sinter_ctx *ctx, const sinter_qs_options *opt)
{
    SINTER_CHECK_NULL(ctx, out);
    *out = NULL;
    sinter_qs *qs = sinter_calloc(ctx, 1, sizeof(*qs));
    if (qs == NULL)
        return SINTER_ERR_NOMEM;
    qs->ctx = ctx;
    if (opt != NULL)
        qs->opt = *opt;
    else
        sinter_qs_options_default(&qs->opt);
    const sinter_qs_options *o = &qs->opt;
    if (o->strategy < 1 || o->strategy > 3 || !(o->max_strain > 0.0) || !(o->alpha > 1.0) ||
        !(o->dt_min > 0.0) || !(o->dt_initial >= o->dt_min) || !(o->dt_max >= o->dt_initial) ||
        !(o->error_limit > 0.0) || !(o->rtol > 0.0) || !(o->solve_rtol > 0.0)) {
        const sinter_status bad =
            sinter_fail(ctx, SINTER_ERR_INVALID,
                        "quasi-static stepper: invalid options (strategy %d, alpha %g, dt %g in "
                        "[%g, %g])",
                        o->strategy, o->alpha, o->dt_initial, o->dt_min, o->dt_max);
        sinter_free(ctx, qs);
        return bad;
    }
    qs->dt_next = o->dt_initial;
    sinter_status s = sinter_bonded_solver_create(&qs->solver, ctx);
    if (s != SINTER_OK) {
        sinter_free(ctx, qs);
        return s;
    }
    *out = qs;
    return SINTER_OK;
}

void sinter_qs_destroy(sinter_qs *qs)
{
    if (qs == NULL)
        return;
    sinter_ctx *ctx = qs->ctx;
    sinter_bonded_solver_destroy(qs->solver);
    sinter_free(ctx, qs->links);
    sinter_free(ctx, qs->keys);
    sinter_free(ctx, qs->slot_id);
    sinter_free(ctx, qs->index_of_slot);
    sinter_free(ctx, qs->slot_of);
    sinter_free(ctx, qs->slot_x);
    sinter_free(ctx, qs->slot_r);
    sinter_free(ctx, qs->candidates);
    sinter_qs_near_free(ctx, &qs->near);
    sinter_free(ctx, qs->origins);
    sinter_free(ctx, qs->carried_id);
    sinter_free(ctx, qs->carried);
    sinter_free(ctx, qs->fixed);
    sinter_free(ctx, qs->f);
    sinter_free(ctx, qs->u);
    sinter_free(ctx, qs->saved);
    sinter_free(ctx, qs->saved_hint);
    sinter_free(ctx, qs->trial);
    sinter_free(ctx, qs->beams);
    sinter_free(ctx, qs->component);
    sinter_free(ctx, qs->component_held);
    sinter_free(ctx, qs->component_sums);
    sinter_neck_batch_destroy(qs->batch);
    sinter_neck_batch_destroy(qs->batch_young);
    sinter_neck_solver_destroy(qs->pair_solver);
    sinter_free(ctx, qs->batch_order);
    sinter_free(ctx, qs->batch_states);
    sinter_free(ctx, qs->batch_materials);
    sinter_free(ctx, qs->xi_affine);
    sinter_free(ctx, qs->image_pairs);
    sinter_free(ctx, qs->ext_x);
    sinter_free(ctx, qs->ext_r);
    sinter_free(ctx, qs->ext_owner);
    sinter_free(ctx, qs->ext_image);
    sinter_free(ctx, qs->dom.rows);
    sinter_free(ctx, qs);
}

const sinter_qs_link *sinter_qs_links(const sinter_qs *qs, size_t *n)
{
    *n = qs->count;
    return qs->links;
}

/* ---- neck advance: the seed's RK4 with step doubling (sec. 2.2, 3.3) ------------------- */

static const sinter_qs_material *material_of(const sinter_qs_particles *p, size_t i)
{
    return &p->materials[p->material != NULL ? p->material[i] : 0];
}

/* The coefficients at T(t) (seed 001 eq. 5); `previous` is reused when T is the same, as it is
 * at every step of a constant-temperature schedule. */
static void coeffs_at(const sinter_neck_material *m, const sinter_neck_schedule *s, double t,
                      const sinter_neck_coeffs *previous, sinter_neck_coeffs *c)
{
    const double temperature = sinter_neck_schedule_temperature(s, t);
    if (previous != NULL && previous->temperature == temperature)
        *c = *previous;
    else
        sinter_neck_coeffs_eval(m, sinter_neck_phase_at(m, temperature), temperature, c);
}

/* One classical RK4 step of the 7DOF system (seed 001 eq. 2-9) at the coefficients c, from y
 * with k1 = f(y) given. Returns 0, or -1 if a stage left the domain of spec §2.5 (out is not
 * checked). */
static int rk4_from(const sinter_neck_coeffs *c, double dt, const double y[SINTER_NECK_DOF],
                    const double k1[SINTER_NECK_DOF], double out[SINTER_NECK_DOF])
{
    double k[3][SINTER_NECK_DOF], stage[SINTER_NECK_DOF];
    static const double a[3] = {0.5, 0.5, 1.0};
    for (int r = 0; r < 3; ++r) {
        const double *from = r == 0 ? k1 : k[r - 1];
        for (int i = 0; i < SINTER_NECK_DOF; ++i)
            stage[i] = y[i] + a[r] * dt * from[i];
        if (sinter_neck_rhs(stage, c, k[r], NULL, NULL) != SINTER_NECK_VALID)
            return -1;
    }
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        out[i] = y[i] + dt / 6.0 * (k1[i] + 2.0 * k[0][i] + 2.0 * k[1][i] + k[2][i]);
    return 0;
}

/* *g = the geometry of y; 0 if y is inside the domain of spec §2.5, else -1. */
static int valid_geometry(const double y[SINTER_NECK_DOF], sinter_neck_geometry *g)
{
    return sinter_neck_geometry_eval(y, g) == 0 &&
                   sinter_neck_check_domain(y, g, NULL) == SINTER_NECK_VALID
               ? 0
               : -1;
}

/* A step of dt from y (its geometry g, valid) by two half steps into out (its geometry into
 * g_out); each RK4 step takes its coefficients at T(its middle). Returns the local error
 * (Richardson: |y_2 - y_1| / 15) in the neck error weights relative to eps_lim (<= 1:
 * accepted), or INFINITY if the step left the domain. The full step and the first half step
 * share f(y) when their temperatures are the same, and a checked state's geometry serves its
 * next stage: the same operations as three independent RK4 steps, so the same bits. */
static double pair_step(const sinter_qs *qs, const sinter_neck_material *m,
                        const sinter_neck_schedule *s, double t, double dt,
                        const double y[SINTER_NECK_DOF], const sinter_neck_geometry *g,
                        double out[SINTER_NECK_DOF], sinter_neck_geometry *g_out)
{
    double full[SINTER_NECK_DOF], half[SINTER_NECK_DOF], w[SINTER_NECK_DOF];
    double k_full[SINTER_NECK_DOF], k_first[SINTER_NECK_DOF], k_second[SINTER_NECK_DOF];
    sinter_neck_coeffs c_full, c_first, c_second;
    sinter_neck_geometry g_half, g_full;
    coeffs_at(m, s, t + 0.5 * dt, NULL, &c_full);
    coeffs_at(m, s, t + 0.5 * (0.5 * dt), &c_full, &c_first);
    coeffs_at(m, s, (t + 0.5 * dt) + 0.5 * (0.5 * dt), &c_first, &c_second);
    sinter_neck_rhs_at(y, g, &c_full, k_full, NULL);
    if (c_first.temperature == c_full.temperature)
        memcpy(k_first, k_full, sizeof(k_first));
    else
        sinter_neck_rhs_at(y, g, &c_first, k_first, NULL);
    if (rk4_from(&c_full, dt, y, k_full, full) != 0 || valid_geometry(full, &g_full) != 0 ||
        rk4_from(&c_first, 0.5 * dt, y, k_first, half) != 0 || valid_geometry(half, &g_half) != 0)
        return INFINITY;
    sinter_neck_rhs_at(half, &g_half, &c_second, k_second, NULL);
    if (rk4_from(&c_second, 0.5 * dt, half, k_second, out) != 0 || valid_geometry(out, g_out) != 0)
        return INFINITY;
    const double atol = 1e-14 * fmin(y[SINTER_NECK_RA], y[SINTER_NECK_RB]); /* spec §4 */
    sinter_neck_error_weights(y, qs->opt.rtol, atol, SINTER_NECK_SCALE_GEOMETRY, w);
    double err = 0.0;
    for (int i = 0; i < SINTER_NECK_DOF; ++i)
        err = fmax(err, fabs(out[i] - full[i]) / 15.0 * w[i]);
    return err / qs->opt.error_limit;
}

/* Strategy 2: advance one pair over [t, t + h] with its own sub-steps (hint in step_hint).
 * Returns 0, -1 when no sub-step above dt_min meets the tolerance, or -2 when even the smallest
 * sub-step left the model's domain of validity (docs/7dof.md §2.5). */
static int pair_advance(const sinter_qs *qs, sinter_qs_link *l, const sinter_neck_schedule *s,
                        double t, double h)
{
    const double alpha = qs->opt.alpha, t_end = t + h;
    double tau = l->neck.step_hint > 0.0 ? l->neck.step_hint : qs->opt.dt_min * 1e3;
    double tc = t, y[SINTER_NECK_DOF];
    memcpy(y, l->neck.y, sizeof(y));
    sinter_neck_geometry g;
    if (valid_geometry(y, &g) != 0)
        return -2;
    int substeps = 0, rejections = 0;
    while (tc < t_end) {
        const int last = tau >= t_end - tc;
        const double step = last ? t_end - tc : tau;
        double out[SINTER_NECK_DOF];
        sinter_neck_geometry g_out;
        const double err = pair_step(qs, &l->material, s, tc, step, y, &g, out, &g_out);
        if (!(err <= 1.0)) {
            tau = step / alpha; /* eq. 45 */
            ++rejections;
            if (tau < 1e-3 * qs->opt.dt_min)
                return isinf(err) ? -2 : -1;
            continue;
        }
        memcpy(y, out, sizeof(y));
        g = g_out;
        tc = last ? t_end : tc + step;
        ++substeps;
        if (err < 0.1) /* eq. 46-47 */
            tau = (last ? fmax(tau, step) : step) * alpha;
    }
    memcpy(l->neck.y, y, sizeof(y));
    l->neck.step_hint = tau;
    l->substepped = substeps > 1 || rejections > 0;
    return 0;
}

/* Link order[k] (order NULL: k) advanced by pair_advance: UINT64_MAX, or the failure's key
 * (advance_pairs). */
static inline uint64_t advance_key(sinter_qs *qs, const size_t *order, size_t k,
                                   const sinter_neck_schedule *s, double t, double h)
{
    const int failed = pair_advance(qs, &qs->links[order != NULL ? order[k] : k], s, t, h);
    return failed == 0 ? UINT64_MAX : 2 * (uint64_t)k + (failed == -2 ? 1u : 0u);
}

/* Strategy 2 over the links order[0..m) (order NULL: every link, m = count), on the context's
 * threads (pairs of uneven cost: dynamic chunks). Returns UINT64_MAX, or for the failed pair of
 * lowest position k, 2 k + 1 if it left the model's domain and 2 k if it could not meet the
 * tolerance. */
static uint64_t advance_pairs(sinter_qs *qs, const size_t *order, size_t m,
                              const sinter_neck_schedule *s, double t, double h)
{
    const int threads = m < 64 ? 1 : sinter_threads(qs->ctx);
    uint64_t first = UINT64_MAX;
    if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 16) reduction(min : first)
        for (size_t k = 0; k < m; ++k) {
            const uint64_t key = advance_key(qs, order, k, s, t, h);
            first = key < first ? key : first;
        }
    } else { /* a region of one thread costs a team (core/ranges_run.h) */
        for (size_t k = 0; k < m; ++k) {
            const uint64_t key = advance_key(qs, order, k, s, t, h);
            first = key < first ? key : first;
        }
    }
    return first;
}

/* ---- links ------------------------------------------------------------------------------ */

int sinter_qs_key_compare(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/*
 * New touching pairs become links with a fresh neck at time t (sec. 3.3, docs/7dof.md §4). The
 * search runs over the particles in id order (qs_ids.c), so the pairs come in the order of
 * their ids, A the particle of the smaller id: the links are made, and oriented, the same way
 * whatever the caller's order.
 */
static sinter_status detect_contacts(sinter_qs *qs, const sinter_qs_particles *p, double t)
{
    const size_t n = p->count;
    const size_t before = qs->count;
    size_t found = 0;
    const double *slot_x = NULL, *slot_r = NULL;
    const int periodic = sinter_qs_periodic_on(qs);
    sinter_status found_status = sinter_qs_slot_geometry(qs, p, &slot_x, &slot_r);
    if (found_status == SINTER_OK && periodic) /* across the faces too (qs_periodic.c) */
        found_status = sinter_qs_periodic_pairs(qs, n, slot_x, slot_r, &found);
    else if (found_status == SINTER_OK)
        found_status = sinter_qs_touching_pairs_near(qs->ctx, &qs->near, n, slot_x, slot_r,
                                                     qs->opt.contact_tolerance, &qs->candidates,
                                                     &qs->candidates_capacity, &found, NULL);
    for (size_t k = 0; found_status == SINTER_ERR_INVALID && k < n; ++k) {
        const size_t i = qs->index_of_slot[k]; /* the search named a slot: name the particle */
        if (!isfinite(p->x[3 * i]) || !isfinite(p->x[3 * i + 1]) || !isfinite(p->x[3 * i + 2]))
            return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                               "quasi-static stepper: particle %zu (id %llu) has a non-finite "
                               "position (%g, %g, %g) m",
                               i, (unsigned long long)qs->slot_id[k], p->x[3 * i], p->x[3 * i + 1],
                               p->x[3 * i + 2]);
    }
    if (found_status != SINTER_OK)
        return found_status;
    for (size_t c = 0; c < found; ++c) {
        const sinter_qs_image_pair *q = periodic ? &qs->image_pairs[c] : NULL;
        const size_t sa = q != NULL ? q->sa : (size_t)(qs->candidates[c] / n);
        const size_t sb = q != NULL ? q->sb : (size_t)(qs->candidates[c] % n);
        const int32_t none[3] = {0, 0, 0};
        const int32_t *image = q != NULL ? q->image : none;
        const size_t a = qs->index_of_slot[sa], b = qs->index_of_slot[sb];
        double xb[3]; /* B, or its image across a periodic face */
        const double *xa = p->x + 3 * a;
        sinter_qs_image_of(qs, image, p->x + 3 * b, xb);
        const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
        const double dist2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        const sinter_qs_pair key = {qs->slot_id[sa], qs->slot_id[sb]};
        if (sinter_qs_domain_ghost(qs, a)) /* the subdomain of the smaller id owns the link */
            continue;
        if (before > 0 &&
            bsearch(&key, qs->keys, before, sizeof(sinter_qs_pair), sinter_qs_pair_compare))
            continue;
        sinter_status s = sinter_grow(qs->ctx, (void **)&qs->links, &qs->capacity, qs->count + 1,
                                      sizeof(sinter_qs_link));
        if (s == SINTER_OK)
            s = sinter_grow(qs->ctx, (void **)&qs->keys, &qs->keys_capacity, qs->count + 1,
                            sizeof(sinter_qs_pair));
        if (s != SINTER_OK)
            return s;
        sinter_qs_link *l = &qs->links[qs->count];
        memset(l, 0, sizeof(*l));
        const sinter_qs_material *ma = material_of(p, a), *mb = material_of(p, b);
        const double ra = p->radius[a], rb = p->radius[b];
        l->material = ma->neck; /* the neck data of A (one material per neck model) */
        l->youngs = 0.5 * (ma->youngs + mb->youngs);
        l->rm = 0.5 * (ra + rb); /* eq. 16 */
        if (sinter_neck_state_init(&l->neck, ra, rb, qs->opt.epsilon, qs->opt.h0_ratio, t) != 0 ||
            sinter_beam_init(&l->beam, (uint32_t)a, (uint32_t)b, xa, xb, l->neck.y[SINTER_NECK_LA],
                             l->neck.y[SINTER_NECK_LB], l->rm, ra + rb, l->youngs,
                             0.5 * (ma->poisson + mb->poisson)) != 0)
            return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                               "quasi-static stepper: cannot bond particles id %llu and id %llu "
                               "(radii %g, %g m, distance %g m)",
                               (unsigned long long)key.lo, (unsigned long long)key.hi, ra, rb,
                               sqrt(dist2));
        l->id_a = key.lo;
        l->id_b = key.hi;
        memcpy(l->image, image, sizeof(l->image));
        l->born = t;
        qs->keys[qs->count] = key;
        qs->count++;
    }
    if (qs->count > before)
        qsort(qs->keys, qs->count, sizeof(sinter_qs_pair), sinter_qs_pair_compare);
    return SINTER_OK;
}

static void extents(const sinter_qs_particles *p, double ext[3])
{
    for (int d = 0; d < 3; ++d) {
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < p->count; ++i) {
            lo = fmin(lo, p->x[3 * i + (size_t)d]);
            hi = fmax(hi, p->x[3 * i + (size_t)d]);
        }
        ext[d] = p->count > 0 ? hi - lo : 0.0;
    }
}

/* Sphere volume over the volume of the spheres' bounding box (the volumes summed in id order). */
static double box_density(const sinter_qs *qs, const sinter_qs_particles *p)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double volume = 0.0;
    for (size_t s = 0; s < p->count; ++s) {
        const size_t i = qs->index_of_slot[s];
        const double r = p->radius[i];
        volume += 4.0 / 3.0 * QS_PI * r * r * r;
        for (size_t d = 0; d < 3; ++d) {
            lo[d] = fmin(lo[d], p->x[3 * i + d] - r);
            hi[d] = fmax(hi[d], p->x[3 * i + d] + r);
        }
    }
    for (int d = 0; d < 3; ++d) /* a periodic axis: the cell's length */
        if (qs->periodic[d]) {
            lo[d] = 0.0;
            hi[d] = qs->cell_len[d];
        }
    if (qs->dom.repro) { /* the reproducible mode: the volume an exact sum (qs_repro.h), as
                          * sinter_qs_domain_start's over subdomains */
        int e = INT32_MIN;
        for (size_t i = 0; i < p->count; ++i) {
            const double r = p->radius[i], v = 4.0 / 3.0 * QS_PI * r * r * r;
            const int ev = sinter_repro_exponent(&v, 1, 1, NULL);
            e = ev > e ? ev : e;
        }
        sinter_repro_sum sum = {{0}, 0};
        for (size_t i = 0; i < p->count; ++i) {
            const double r = p->radius[i], v = 4.0 / 3.0 * QS_PI * r * r * r;
            sinter_repro_add(&sum, e, &v, 1, 1);
        }
        volume = sinter_repro_value(&sum, e);
    }
    return p->count > 0 ? volume / ((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])) : 0.0;
}

/* Particles touching a principal plane Oyz, Oxz, Oxy stay on it (sec. 3.3); per slot. */
static sinter_status setup(sinter_qs *qs, const sinter_qs_particles *p)
{
    const size_t n = p->count;
    sinter_status s = sinter_grow(qs->ctx, (void **)&qs->fixed, &qs->fixed_capacity, 6 * n + 1, 1);
    if (s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->f, &qs->f_capacity, 6 * n + 1, sizeof(double));
    if (s == SINTER_OK)
        s = sinter_grow(qs->ctx, (void **)&qs->u, &qs->u_capacity, 6 * n + 1, sizeof(double));
    if (s != SINTER_OK)
        return s;
    memset(qs->fixed, 0, 6 * n);
    for (size_t k = 0; k < n; ++k) {
        const size_t i = qs->index_of_slot[k];
        for (size_t d = 0; d < 3; ++d)
            qs->fixed[6 * k + d] =
                (unsigned char)(!qs->periodic[d] && p->x[3 * i + d] - p->radius[i] <
                                                        qs->opt.plane_tolerance * p->radius[i]);
    }
    if (qs->particles == 0) { /* the first setup only (not after a remap) */
        extents(p, qs->extent0);
        if ((s = sinter_grow(qs->ctx, (void **)&qs->origins, &qs->origin_capacity, n + 1,
                             sizeof(sinter_qs_origin))) != SINTER_OK)
            return s;
        for (size_t k = 0; k < n; ++k) { /* in id order, as the slots */
            qs->origins[k].id = qs->slot_id[k];
            memcpy(qs->origins[k].x, p->x + 3 * (size_t)qs->index_of_slot[k],
                   sizeof(qs->origins[k].x));
        }
        qs->origin_count = n;
        qs->density0 = box_density(qs, p);
        for (int d = 0; d < 3; ++d) /* the reference of the cell's strain */
            qs->cell_len0[d] = qs->cell_len[d];
        qs->cell_started = 1;
    }
    qs->particles = n;
    qs->u_step = 0.0; /* u no longer matches the particles */
    return SINTER_OK;
}

/* Periodic axes: every particle in the cell when the links are searched afresh (the search
 * makes images only of particles near a face, qs_periodic.c). */
static sinter_status inside_cell(const sinter_qs *qs, const sinter_qs_particles *p)
{
    for (size_t s = 0; s < p->count; ++s) {
        const size_t i = qs->index_of_slot[s];
        for (int d = 0; d < 3; ++d) {
            const double x = p->x[3 * i + (size_t)d];
            if (qs->periodic[d] && !(x >= qs->cell_lo[d] && x < qs->cell_lo[d] + qs->cell_len[d]))
                return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                                   "quasi-static stepper: particle id %llu is at %g m along axis "
                                   "%d, outside the periodic cell [%g, %g) m; place every "
                                   "particle in the cell",
                                   (unsigned long long)qs->slot_id[s], x, d, qs->cell_lo[d],
                                   qs->cell_lo[d] + qs->cell_len[d]);
        }
    }
    return SINTER_OK;
}

/* ---- the global step ---------------------------------------------------------------------- */

/* Strategy 1: one step h for all pairs, the whole step rejected while any pair misses the
 * tolerance (eq. 45); *grow when every pair is within 0.1 of it (eq. 46). */
static sinter_status advance_global(sinter_qs *qs, const sinter_neck_schedule *s, double t,
                                    double *h, int *grow)
{
    const size_t m = qs->count;
    sinter_status st =
        sinter_grow(qs->ctx, (void **)&qs->trial, &qs->trial_capacity, m + 1, sizeof(*qs->trial));
    if (st != SINTER_OK)
        return st;
    for (;;) {
        double worst = 0.0;
        for (size_t k = 0; k < m && worst <= 1.0; ++k) {
            sinter_neck_geometry g, g_out;
            const double *y = qs->links[k].neck.y;
            worst = valid_geometry(y, &g) != 0
                        ? INFINITY
                        : fmax(worst, pair_step(qs, &qs->links[k].material, s, t, *h, y, &g,
                                                qs->trial[k], &g_out));
        }
        if (worst <= 1.0) {
            for (size_t k = 0; k < m; ++k)
                memcpy(qs->links[k].neck.y, qs->trial[k], sizeof(qs->trial[k]));
            *grow = worst < 0.1;
            return SINTER_OK;
        }
        qs->rejected++;
        *h /= qs->opt.alpha;
        if (*h < qs->opt.dt_min)
            return sinter_fail(qs->ctx, SINTER_ERR_NOT_CONVERGED,
                               "quasi-static stepper (strategy 1): no step above %g s meets the "
                               "neck tolerance at t = %g s",
                               qs->opt.dt_min, t);
    }
}

/* Strategy 3: every pair in one CVODE system over [t, t + h] (neck/batch.c). */
/* Necks below this neck ratio x / min(R_A, R_B) are young (seeded at 0.01, docs/7dof.md §4). */
#define QS_YOUNG_NECK_RATIO 0.05

/* One CVODE batch over pairs order[0..count) (indices into links), states written back. */
static sinter_status advance_group(sinter_qs *qs, sinter_neck_batch *batch, const size_t *order,
                                   size_t count, const sinter_neck_schedule *s, double t, double h,
                                   sinter_neck_counters *counters)
{
    if (count == 0)
        return SINTER_OK;
    for (size_t k = 0; k < count; ++k) {
        qs->batch_states[k] = qs->links[order[k]].neck;
        qs->batch_states[k].time = t;
        qs->batch_materials[k] = &qs->links[order[k]].material;
    }
    sinter_neck_tolerances tol;
    sinter_neck_tolerances_default(&tol);
    tol.rtol = qs->opt.rtol;
    sinter_status st = sinter_neck_batch_advance(batch, count, qs->batch_states,
                                                 qs->batch_materials, s, t + h, &tol, counters);
    const size_t bad = sinter_neck_batch_failed_pair(batch);
    if (st != SINTER_OK && bad < count) {
        char detail[SINTER_ERROR_TEXT_SIZE];
        snprintf(detail, sizeof(detail), "%s", sinter_last_error(qs->ctx));
        return sinter_fail(qs->ctx, st,
                           "quasi-static stepper (strategy 3), step from t = %.9g s: the neck of "
                           "particles id %llu and id %llu failed; the state at t is kept: %s",
                           t, (unsigned long long)qs->links[order[bad]].id_a,
                           (unsigned long long)qs->links[order[bad]].id_b, detail);
    }
    if (st != SINTER_OK)
        return st;
    for (size_t k = 0; k < count; ++k) {
        sinter_neck_state *n = &qs->links[order[k]].neck;
        memcpy(n->y, qs->batch_states[k].y, sizeof(n->y));
        n->step_hint = qs->batch_states[k].step_hint;
    }
    return SINTER_OK;
}

/*
 * Strategy 3 with young_pairs: each young neck in CVODE on its own steps (cvode_driver.c, dense
 * 7x7 Newton matrix). In one batch the shared step follows whichever neck is in its stiffest
 * transient at each moment; necks of different radii pass their transients at different
 * times, so the shared step stays short for all (the titanium packing at 793 K: about 6000
 * batch steps over the first 1e-4 s, tests/bench/RESULTS.md, issue 45).
 */
static sinter_status advance_young_pairs(sinter_qs *qs, const size_t *order, size_t count,
                                         const sinter_neck_schedule *s, double t, double h)
{
    if (count == 0)
        return SINTER_OK;
    sinter_status st = SINTER_OK;
    if (qs->pair_solver == NULL &&
        (st = sinter_neck_solver_create(&qs->pair_solver, qs->ctx)) != SINTER_OK)
        return st;
    sinter_neck_tolerances tol;
    sinter_neck_tolerances_default(&tol);
    tol.rtol = qs->opt.rtol;
    for (size_t k = 0; k < count; ++k) {
        sinter_qs_link *l = &qs->links[order[k]];
        sinter_neck_state state = l->neck;
        state.time = t;
        st = sinter_neck_advance_pair(qs->pair_solver, &state, &l->material, s, t + h, &tol, NULL,
                                      &qs->batch_counters[0]);
        if (st != SINTER_OK) {
            char detail[SINTER_ERROR_TEXT_SIZE];
            snprintf(detail, sizeof(detail), "%s", sinter_last_error(qs->ctx));
            return sinter_fail(qs->ctx, st,
                               "quasi-static stepper (strategy 3), step from t = %.9g s: the neck "
                               "of particles id %llu and id %llu failed; the state at t is kept: "
                               "%s",
                               t, (unsigned long long)l->id_a, (unsigned long long)l->id_b, detail);
        }
        memcpy(l->neck.y, state.y, sizeof(l->neck.y));
        l->neck.step_hint = state.step_hint;
    }
    return SINTER_OK;
}

/*
 * Strategy 3: the pairs in CVODE batches over [t, t + h] (neck/batch.c), grouped by age: a
 * batch shares one step, which follows its most demanding neck, and a neck seeded at
 * x = 0.01 R starts on steps of about 1e-12 s (docs/7dof.md §4). In one batch every new contact
 * would restart all necks on such steps; the young necks (ratio below QS_YOUNG_NECK_RATIO)
 * are therefore integrated in a batch of their own.
 */
static sinter_status advance_batch(sinter_qs *qs, const sinter_neck_schedule *s, double t, double h)
{
    const size_t m = qs->count;
    if (m == 0)
        return SINTER_OK;
    sinter_status st = SINTER_OK;
    if (qs->batch == NULL && (st = sinter_neck_batch_create(&qs->batch, qs->ctx)) != SINTER_OK)
        return st;
    if (qs->batch_young == NULL &&
        (st = sinter_neck_batch_create(&qs->batch_young, qs->ctx)) != SINTER_OK)
        return st;
    st = sinter_grow(qs->ctx, (void **)&qs->batch_states, &qs->batch_states_capacity, m,
                     sizeof(sinter_neck_state));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->batch_materials, &qs->batch_materials_capacity, m,
                         sizeof(*qs->batch_materials));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->batch_order, &qs->batch_order_capacity, m,
                         sizeof(size_t));
    if (st != SINTER_OK)
        return st;
    size_t young = 0, mature = m;
    for (size_t k = 0; k < m; ++k) {
        const double *y = qs->links[k].neck.y;
        const double ratio = y[SINTER_NECK_X] / fmin(y[SINTER_NECK_RA], y[SINTER_NECK_RB]);
        if (ratio < QS_YOUNG_NECK_RATIO)
            qs->batch_order[young++] = k;
        else
            qs->batch_order[--mature] = k;
    }
    /* the reproducible mode: no CVODE system spans links (its error norm would mix the links of
     * one subdomain only), every neck on its own steps (qs_repro.h) */
    if (qs->dom.repro && qs->opt.grown_rk4 == 0.0)
        st = advance_young_pairs(qs, qs->batch_order, m, s, t, h);
    else if (qs->opt.young_pairs != 0.0 || qs->dom.repro)
        st = advance_young_pairs(qs, qs->batch_order, young, s, t, h);
    else
        st = advance_group(qs, qs->batch_young, qs->batch_order, young, s, t, h,
                           &qs->batch_counters[0]);
    if (st == SINTER_OK && qs->opt.grown_rk4 != 0.0) {
        const uint64_t failed = advance_pairs(qs, qs->batch_order + young, m - young, s, t, h);
        if (failed != UINT64_MAX) {
            const sinter_qs_link *l = &qs->links[qs->batch_order[young + (size_t)(failed >> 1)]];
            st = sinter_fail(qs->ctx, (failed & 1u) ? SINTER_ERR_DOMAIN : SINTER_ERR_NOT_CONVERGED,
                             "quasi-static stepper (strategy 3, grown necks by RK4): the neck "
                             "of particles id %llu and id %llu failed from t = %.9g s; the "
                             "state at t is kept",
                             (unsigned long long)l->id_a, (unsigned long long)l->id_b, t);
        }
    } else if (st == SINTER_OK && !qs->dom.repro)
        st = advance_group(qs, qs->batch, qs->batch_order + young, m - young, s, t, h,
                           &qs->batch_counters[1]);
    if (st != SINTER_OK) /* the young group may have moved: every neck back to t */
        for (size_t k = 0; k < m; ++k)
            memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
    return st;
}

/* With domain operations the status of a stage as every subdomain agrees it; a failure
 * anywhere puts this subdomain's necks back at t as well (and their step hints, strategy 2). */
static sinter_status agree_necks(sinter_qs *qs, sinter_status st, int hints)
{
    if (!qs->dom.on)
        return st;
    const sinter_status agreed = sinter_qs_domain_agree(qs, st);
    for (size_t k = 0; agreed != SINTER_OK && k < qs->count; ++k) {
        memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
        if (hints)
            qs->links[k].neck.step_hint = qs->saved_hint[k];
    }
    return agreed;
}

sinter_status sinter_qs_step(sinter_qs *qs, const sinter_qs_particles *p,
                             const sinter_neck_schedule *schedule, double t, double h,
                             double *taken)
{
    SINTER_CHECK_NULL(NULL, qs);
    SINTER_CHECK_NULL(qs->ctx, p);
    SINTER_CHECK_NULL(qs->ctx, schedule);
    if (!(h > 0.0) || !isfinite(h))
        return sinter_fail(qs->ctx, SINTER_ERR_INVALID, "quasi-static stepper: step %g s", h);
    const size_t n = p->count;
    sinter_status st = sinter_qs_follow_ids(qs, p); /* the slots of p's particles (qs_ids.c) */
    const int fresh = st == SINTER_OK && qs->particles != n;
    if (fresh && sinter_qs_periodic_on(qs))
        st = inside_cell(qs, p);
    if (fresh && st == SINTER_OK)
        st = setup(qs, p);
    /* with domain operations (qs_domain.h) the stages below agree their status, and the
     * first step's extents and green density are those of every subdomain */
    if ((st = sinter_qs_domain_agree(qs, st)) != SINTER_OK)
        return st;
    if (qs->dom.on && !qs->dom.started)
        st = sinter_qs_domain_start(qs, p);
    if (fresh && st == SINTER_OK)
        st = detect_contacts(qs, p, t);
    const size_t m = qs->count;
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->saved, &qs->saved_capacity, m + 1,
                         sizeof(*qs->saved));
    if ((st = sinter_qs_domain_agree(qs, st)) != SINTER_OK)
        return st;
    for (size_t k = 0; k < m; ++k)
        memcpy(qs->saved[k], qs->links[k].neck.y, sizeof(qs->saved[k]));

    /* 1. the necks (sec. 3.3, fig. 7) */
    const double alpha = qs->opt.alpha;
    double next = h;
    if (qs->opt.strategy == 3 || qs->opt.neck_law != 0.0) {
        st = qs->opt.neck_law != 0.0 ? sinter_qs_advance_law(qs, p, schedule, t, h)
                                     : advance_batch(qs, schedule, t, h);
        if ((st = agree_necks(qs, st, 0)) != SINTER_OK)
            return st;
        uint64_t above[2] = {0, m}; /* links whose approach of the step / L0 reached max_strain */
        for (size_t k = 0; k < m; ++k) {
            const double *y = qs->links[k].neck.y;
            const double dl = qs->saved[k][SINTER_NECK_LA] - y[SINTER_NECK_LA] +
                              qs->saved[k][SINTER_NECK_LB] - y[SINTER_NECK_LB];
            above[0] += fabs(dl) >= qs->opt.max_strain * qs->links[k].neck.center_distance0;
        }
        if ((st = sinter_qs_domain_reduce(qs, above, 2, SINTER_REDUCE_U64, SINTER_REDUCE_SUM)) !=
            SINTER_OK) /* (over every subdomain's links) */
            return st;
        /* strain_fraction 0: grow only while no link reached max_strain */
        next =
            (double)above[0] <= qs->opt.strain_fraction * (double)above[1] ? h * alpha : h / alpha;
    } else if (qs->opt.strategy == 1) {
        int grow = 0;
        if ((st = advance_global(qs, schedule, t, &h, &grow)) != SINTER_OK)
            return st;
        next = grow ? h * alpha : h; /* eq. 47 */
    } else {
        /* Every pair on its own (the pairs share nothing), on the context's threads; a failure
         * reports the pair of lowest index and puts every neck back at t, hints included, so
         * the state and the message do not depend on the thread count. */
        st = sinter_grow(qs->ctx, (void **)&qs->saved_hint, &qs->saved_hint_capacity, m + 1,
                         sizeof(double));
        if ((st = sinter_qs_domain_agree(qs, st)) != SINTER_OK)
            return st;
        for (size_t k = 0; k < m; ++k)
            qs->saved_hint[k] = qs->links[k].neck.step_hint;
        const uint64_t first_failed = advance_pairs(qs, NULL, m, schedule, t, h);
        if (first_failed == UINT64_MAX && (st = agree_necks(qs, SINTER_OK, 1)) != SINTER_OK)
            return st; /* (another subdomain's neck failed) */
        if (first_failed != UINT64_MAX) {
            const size_t k = (size_t)(first_failed >> 1);
            const int outside = (int)(first_failed & 1u);
            for (size_t j = 0; j < m; ++j) {
                memcpy(qs->links[j].neck.y, qs->saved[j], sizeof(qs->saved[j]));
                qs->links[j].neck.step_hint = qs->saved_hint[j];
            }
            const sinter_qs_link *l = &qs->links[k];
            st = sinter_fail(qs->ctx, outside ? SINTER_ERR_DOMAIN : SINTER_ERR_NOT_CONVERGED,
                             "quasi-static stepper (strategy 2): the neck of particles id "
                             "%llu and id %llu (neck radius %g m, x/R %g) %s from t = %.9g s "
                             "(sub-steps down to %g s tried); the state at t is kept",
                             (unsigned long long)l->id_a, (unsigned long long)l->id_b,
                             l->neck.y[SINTER_NECK_X],
                             l->neck.y[SINTER_NECK_X] /
                                 fmin(l->neck.y[SINTER_NECK_RA], l->neck.y[SINTER_NECK_RB]),
                             outside ? "leaves the 7DOF model's domain of validity "
                                       "(7dof.md sec. 2.5)"
                                     : "cannot meet the neck tolerance",
                             t, 1e-3 * qs->opt.dt_min);
            return agree_necks(qs, st, 1);
        }
        uint64_t sub[2] = {0, m};
        for (size_t k = 0; k < m; ++k)
            sub[0] += (uint64_t)qs->links[k].substepped;
        if ((st = sinter_qs_domain_reduce(qs, sub, 2, SINTER_REDUCE_U64, SINTER_REDUCE_SUM)) !=
            SINTER_OK) /* (over every subdomain's links) */
            return st;
        qs->substepped += sub[0]; /* (every subdomain's: the same count on each) */
        const double fraction = sub[1] > 0 ? (double)sub[0] / (double)sub[1] : 0.0;
        if (fraction < qs->opt.grow_fraction)
            next = h * alpha;
        else if (fraction > qs->opt.shrink_fraction)
            next = h / alpha;
    }
    next = fmin(fmax(next, qs->opt.dt_min), qs->opt.dt_max);

    /* 2. sintering forces of the step's approach (eq. 13, 17), incremental form; f, u and the
     * solve are per slot, each particle's loads summed in link order */
    double *f = qs->f, *u = qs->u;
    const uint32_t *slot = qs->slot_of;
    memset(f, 0, 6 * n * sizeof(double));
    double *fn_repro = NULL; /* the reproducible mode: each link's force, then exact row sums */
    if (qs->dom.repro) {
        fn_repro = sinter_alloc(qs->ctx, (m + 1) * sizeof(double));
        if ((st = agree_necks(qs, fn_repro == NULL ? SINTER_ERR_NOMEM : SINTER_OK, 0)) !=
            SINTER_OK) {
            if (!qs->dom.on)
                for (size_t k = 0; k < m; ++k)
                    memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
            return st;
        }
    }
    for (size_t k = 0; k < m; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const double dl = (qs->saved[k][SINTER_NECK_LA] - l->neck.y[SINTER_NECK_LA]) +
                          (qs->saved[k][SINTER_NECK_LB] - l->neck.y[SINTER_NECK_LB]);
        /* the same section as the link's stiffness below: a free pair approaches by dl */
        const double fn =
            sinter_sintering_force(l->youngs, l->rm, dl) * sinter_qs_section_scale(&qs->opt, l);
        if (fn_repro != NULL) {
            fn_repro[k] = fn;
            continue;
        }
        for (size_t d = 0; d < 3; ++d) {
            f[6 * (size_t)slot[l->beam.a] + d] += fn * l->beam.axis[d];
            f[6 * (size_t)slot[l->beam.b] + d] -= fn * l->beam.axis[d];
        }
    }
    /* with domain operations: the loads on ghost ends added into their owners (qs_domain.h) */
    if (fn_repro != NULL) {
        st = sinter_qs_repro_loads(qs, n, fn_repro, f);
        sinter_free(qs->ctx, fn_repro);
    } else
        st = sinter_qs_domain_reverse(qs, f, 6);
    if ((st = agree_necks(qs, st, 0)) != SINTER_OK) {
        if (!qs->dom.on) /* (agree_necks restores the necks with domain operations only) */
            for (size_t k = 0; k < m; ++k)
                memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
        return st;
    }

    /* periodic axes: the cell's strain from the links' approaches, its loads off f (the
     * solve's u is then the periodic rest; qs_periodic.c) */
    const int periodic = sinter_qs_periodic_on(qs);
    if (periodic && (st = sinter_qs_cell_strain(qs, p, f)) != SINTER_OK) {
        for (size_t k = 0; k < m; ++k)
            memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
        return st;
    }

    /* 3. K u = f (eq. 40) under the principal-plane conditions */
    int iterations = 0;
    st = sinter_grow(qs->ctx, (void **)&qs->beams, &qs->beams_capacity, m + 1, sizeof(sinter_beam));
    st = sinter_qs_domain_agree(qs, st);
    if (st == SINTER_OK) {
        for (size_t k = 0; k < m; ++k) {
            qs->beams[k] = qs->links[k].beam;
            qs->beams[k].a = slot[qs->links[k].beam.a];
            qs->beams[k].b = slot[qs->links[k].beam.b];
            /* qs_neck_stiffness: A = pi x^2, I and J ~ x^4 instead of eq. 36's R_m */
            const double a = sinter_qs_section_scale(&qs->opt, &qs->links[k]);
            qs->beams[k].k_axial *= a;
            qs->beams[k].k_shear *= a;
            qs->beams[k].k_bend *= a * a;
            qs->beams[k].k_torsion *= a * a;
        }
        /* start from the last step's displacements scaled to this step (u ~ h) */
        double *guess = NULL;
        if (qs->u_step > 0.0) {
            const double scale = h / qs->u_step;
            for (size_t i = 0; i < 6 * n; ++i)
                u[i] *= scale;
            guess = u;
        }
        if (qs->dom.split ||
            qs->dom.repro) { /* over the subdomains (bonded/solve_split.h),
                              * and the free motion of components across them
                              * (qs_floating_domain.c); the reproducible mode's arithmetic on
                              * one subdomain and without domain operations too */
            st = sinter_qs_domain_solve(qs, n, f, guess, u, &iterations);
            st = sinter_qs_domain_remove_free_motion(qs, p, u, st);
        } else {
            st = sinter_bonded_solve_from(qs->solver, n, qs->beams, m, qs->fixed, f, guess, u,
                                          qs->opt.solve_rtol, &iterations);
            if (st == SINTER_OK) /* the rigid motion K leaves free: none (qs_floating.c) */
                st = sinter_qs_remove_free_motion(qs, p, u);
        }
        st = sinter_qs_domain_agree(qs, st);
        qs->u_step = st == SINTER_OK ? h : 0.0;
    }
    if (st != SINTER_OK) {
        for (size_t k = 0; k < m; ++k)
            memcpy(qs->links[k].neck.y, qs->saved[k], sizeof(qs->saved[k]));
        return st;
    }
    qs->pcg_iterations += (uint64_t)iterations;

    /* The new centres of every link must stay apart and finite; checked before anything moves,
     * so that a failure keeps the state at t. */
    for (size_t k = 0; k < m && st == SINTER_OK; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const size_t a = l->beam.a, b = l->beam.b, sa = slot[a], sb = slot[b];
        double d2 = 0.0;
        for (size_t d = 0; d < 3 && !periodic; ++d) {
            const double dd = (p->x[3 * b + d] + u[6 * sb + d]) - (p->x[3 * a + d] + u[6 * sa + d]);
            d2 += dd * dd;
        }
        if (periodic)
            d2 = sinter_qs_cell_distance2(qs, p, k, u);
        if (!(d2 > 0.0) || !isfinite(d2)) {
            st = sinter_fail(qs->ctx, SINTER_ERR_DOMAIN,
                             "quasi-static stepper: the step from t = %.9g s to %.9g s would "
                             "put particles id %llu and id %llu at a centre distance of %g m; "
                             "the state at t is kept",
                             t, t + h, (unsigned long long)l->id_a, (unsigned long long)l->id_b,
                             sqrt(d2));
        }
    }
    if ((st = agree_necks(qs, st, 0)) != SINTER_OK) {
        for (size_t j = 0; j < m; ++j)
            memcpy(qs->links[j].neck.y, qs->saved[j], sizeof(qs->saved[j]));
        qs->u_step = 0.0;
        return st;
    }

    /* 4. move and turn the particles; share the link compression between y4 and y7 */
    if (periodic) /* the cell's strain first: it acts on the positions at t */
        sinter_qs_cell_move(qs, p);
    for (size_t i = 0; i < n; ++i) {
        const double *ui = u + 6 * (size_t)slot[i];
        for (size_t d = 0; d < 3; ++d)
            p->x[3 * i + d] += ui[d];
        if (p->rot != NULL)
            sinter_compose_rotation(p->rot + 3 * i, ui + 3);
    }
    if (periodic) /* back into the cell, the links' images following */
        sinter_qs_cell_wrap(qs, p);
    for (size_t k = 0; k < m; ++k) {
        sinter_qs_link *l = &qs->links[k];
        const size_t a = l->beam.a, b = l->beam.b, sa = slot[a], sb = slot[b];
        double xi = 0.0; /* eq. 41, positive when the centres approach */
        for (size_t d = 0; d < 3; ++d)
            xi += (u[6 * sa + d] - u[6 * sb + d]) * l->beam.axis[d];
        if (periodic)
            xi += qs->xi_affine[k]; /* the cell's share */
        const double y4p = qs->saved[k][SINTER_NECK_LA], y7p = qs->saved[k][SINTER_NECK_LB];
        const double d4 = y4p - l->neck.y[SINTER_NECK_LA]; /* eq. 43a */
        const double d7 = y7p - l->neck.y[SINTER_NECK_LB]; /* eq. 43b */
        const double share = d4 + d7 != 0.0 ? d4 / (d4 + d7) : 0.5;
        /* eq. 42 with the approach subtracted: the 7DOF approach d4 + d7 must give back y_i
         * when the packing lets the pair shrink freely (xi = d4 + d7). */
        l->neck.y[SINTER_NECK_LA] = y4p - share * xi;
        l->neck.y[SINTER_NECK_LB] = y7p - (1.0 - share) * xi;
        l->neck.last_dy4 = d4;
        l->neck.last_dy7 = d7;
        l->neck.time = t + h;
        double xb[3];
        sinter_qs_image_of(qs, l->image, p->x + 3 * b, xb);
        if (sinter_beam_update(&l->beam, p->x + 3 * a, xb, l->neck.y[SINTER_NECK_LA],
                               l->neck.y[SINTER_NECK_LB]) != 0)
            return sinter_fail(qs->ctx, SINTER_ERR_DOMAIN,
                               "quasi-static stepper: particles id %llu and id %llu coincide at "
                               "t = %g s",
                               (unsigned long long)l->id_a, (unsigned long long)l->id_b,
                               t + h); /* excluded by the check above */
    }

    /* 5. new contacts */
    if (qs->opt.new_contacts != 0.0)
        st = detect_contacts(qs, p, t + h);
    if ((st = sinter_qs_domain_agree(qs, st)) != SINTER_OK)
        return st;
    qs->steps++;
    qs->dt_next = next;
    if (taken)
        *taken = h;
    return sinter_qs_check_validity(qs, p, t + h); /* (collective with domain operations) */
}

sinter_status sinter_qs_run(sinter_qs *qs, const sinter_qs_particles *p,
                            const sinter_neck_schedule *schedule, double t0, double t1)
{
    double t = t0;
    while (t < t1) {
        const double remaining = t1 - t;
        double h = fmin(qs->dt_next, remaining), taken = 0.0;
        const int last = h >= remaining * (1.0 - 1e-12);
        const sinter_status s = sinter_qs_step(qs, p, schedule, t, last ? remaining : h, &taken);
        if (s != SINTER_OK)
            return s;
        t = last && taken == remaining ? t1 : t + taken;
    }
    return SINTER_OK;
}

/*
 * Shrinkage along x, y, z: the homogeneous strain of the packing, i.e. minus the least-squares
 * slope of each particle's displacement against its initial position along that axis, over the
 * particles that carry at least one link (a rattler without links does not move with the
 * packing, and one at the edge would pin an extent-based measure). For two linked spheres it is
 * the pair's centre approach over its initial distance (seed 001 eq. 13). Falls back to the
 * extent of all centres when the link counts cannot be allocated. The sums run in id order
 * (qs_ids.c) when the stepper's map is that of p.
 */
static void shrinkage(const sinter_qs *qs, const sinter_qs_particles *p, double out[3])
{
    const size_t n = p->count;
    unsigned char *linked = n > 0 ? sinter_calloc(qs->ctx, n, 1) : NULL;
    if (!qs->dom.on && (linked == NULL || qs->origin_count == 0)) {
        sinter_free(qs->ctx, linked);
        double ext[3];
        extents(p, ext);
        for (int d = 0; d < 3; ++d)
            out[d] = qs->extent0[d] > 0.0 ? 1.0 - ext[d] / qs->extent0[d] : 0.0;
        return;
    }
    for (size_t k = 0; k < qs->count && linked != NULL; ++k)
        linked[qs->links[k].beam.a] = linked[qs->links[k].beam.b] = 1;
    /* with domain operations: a ghost's marks to its owner (every subdomain reduces alike, an
     * allocation failure only loses this subdomain's share) */
    sinter_qs *q = (sinter_qs *)qs; /* (the halo counts calls in the domain only) */
    if (qs->dom.on && sinter_qs_domain_linked(q, linked != NULL ? n : 0, linked) != SINTER_OK)
        memset(linked, 0, linked != NULL ? n : 0);
    double sum0[3] = {0, 0, 0}, sumu[3] = {0, 0, 0}, s00[3] = {0, 0, 0}, s0u[3] = {0, 0, 0};
    double m = 0.0;
    const int by_slot = qs->slots_valid && qs->slots == n;
    /* the reproducible mode: the terms kept, series j at terms + j n (zero where none) */
    double *terms = qs->dom.repro ? sinter_calloc(qs->ctx, 12 * n + 1, sizeof(double)) : NULL;
    if (qs->dom.repro &&
        sinter_qs_domain_agree(q, terms == NULL ? SINTER_ERR_NOMEM : SINTER_OK) != SINTER_OK) {
        sinter_free(qs->ctx, terms);
        terms = NULL; /* (every subdomain: the sums of doubles below) */
    }
    for (size_t s = 0; s < n && linked != NULL; ++s) {
        const size_t i = by_slot ? qs->index_of_slot[s] : s;
        if (!linked[i])
            continue;
        const uint64_t id = p->id != NULL ? p->id[i] : (uint64_t)i;
        const sinter_qs_origin *o = bsearch(&id, qs->origins, qs->origin_count,
                                            sizeof(sinter_qs_origin), sinter_qs_key_compare);
        if (o == NULL)
            continue; /* added after the start: no reference */
        m += 1.0;
        for (int d = 0; d < 3; ++d) {
            const double x0 = o->x[d], u = p->x[3 * i + (size_t)d] - x0;
            sum0[d] += x0;
            sumu[d] += u;
            s00[d] += x0 * x0;
            s0u[d] += x0 * u;
            if (terms != NULL) {
                terms[(size_t)d * n + s] = x0;
                terms[(size_t)(3 + d) * n + s] = u;
                terms[(size_t)(6 + d) * n + s] = x0 * x0;
                terms[(size_t)(9 + d) * n + s] = x0 * u;
            }
        }
    }
    sinter_free(qs->ctx, linked);
    if (qs->dom.on) {
        double v[13];
        memcpy(v, sum0, sizeof(sum0));
        memcpy(v + 3, sumu, sizeof(sumu));
        memcpy(v + 6, s00, sizeof(s00));
        memcpy(v + 9, s0u, sizeof(s0u));
        v[12] = m;
        if (sinter_qs_domain_reduce(q, v, 13, SINTER_REDUCE_F64, SINTER_REDUCE_SUM) == SINTER_OK) {
            memcpy(sum0, v, sizeof(sum0));
            memcpy(sumu, v + 3, sizeof(sumu));
            memcpy(s00, v + 6, sizeof(s00));
            memcpy(s0u, v + 9, sizeof(s0u));
            m = v[12];
        }
    }
    if (terms != NULL) { /* the reproducible mode: the twelve sums exact (qs_repro.h) */
        double v[12];
        if (sinter_qs_repro_series(q, terms, n, 12, v) == SINTER_OK) {
            memcpy(sum0, v, sizeof(sum0));
            memcpy(sumu, v + 3, sizeof(sumu));
            memcpy(s00, v + 6, sizeof(s00));
            memcpy(s0u, v + 9, sizeof(s0u));
        }
        sinter_free(qs->ctx, terms);
    }
    for (int d = 0; d < 3; ++d) {
        const double var = m > 0.0 ? s00[d] - sum0[d] * sum0[d] / m : 0.0;
        const double cov = m > 0.0 ? s0u[d] - sum0[d] * sumu[d] / m : 0.0;
        out[d] = var > 0.0 ? -cov / var : 0.0;
        if (qs->periodic[d]) /* a periodic axis: the cell's strain (qs_periodic.c) */
            out[d] = 1.0 - qs->cell_len[d] / qs->cell_len0[d];
    }
}

void sinter_qs_stats_get(const sinter_qs *qs, const sinter_qs_particles *p, sinter_qs_stats *out)
{
    memset(out, 0, sizeof(*out));
    out->dt_next = qs->dt_next;
    out->particles = p->count;
    out->links = qs->count;
    out->steps = qs->steps;
    out->rejected = qs->rejected;
    out->pcg_iterations = qs->pcg_iterations;
    out->substepped_pairs = qs->substepped;
    out->neck_min = INFINITY;
    out->neck_max = 0.0;
    double links = (double)qs->count;
    for (size_t k = 0; k < qs->count; ++k) {
        const double *y = qs->links[k].neck.y;
        out->neck_mean += y[SINTER_NECK_X];
        out->neck_min = fmin(out->neck_min, y[SINTER_NECK_X]);
        out->neck_max = fmax(out->neck_max, y[SINTER_NECK_X]);
        out->neck_ratio_mean +=
            y[SINTER_NECK_X] / fmin(p->radius[qs->links[k].beam.a], p->radius[qs->links[k].beam.b]);
        out->time = qs->links[k].neck.time;
    }
    double exact[2] = {out->neck_mean, out->neck_ratio_mean};
    if (qs->dom.repro) { /* the reproducible mode: the two sums exact (qs_repro.h) */
        sinter_qs *q = (sinter_qs *)qs;
        const size_t m = qs->count;
        double *terms = sinter_alloc(qs->ctx, (2 * m + 1) * sizeof(double));
        for (size_t k = 0; k < m && terms != NULL; ++k) {
            const double *y = qs->links[k].neck.y;
            terms[k] = y[SINTER_NECK_X];
            terms[m + k] = y[SINTER_NECK_X] /
                           fmin(p->radius[qs->links[k].beam.a], p->radius[qs->links[k].beam.b]);
        }
        if (sinter_qs_domain_agree(q, terms == NULL ? SINTER_ERR_NOMEM : SINTER_OK) != SINTER_OK ||
            sinter_qs_repro_series(q, terms, m, 2, exact) != SINTER_OK)
            exact[0] = exact[1] = NAN;
        sinter_free(qs->ctx, terms);
    }
    if (qs->dom.on) { /* over every subdomain's links and owned particles (qs_domain.h) */
        sinter_qs *q = (sinter_qs *)qs; /* (the reductions count calls in the domain only) */
        double sums[4] = {out->neck_mean, out->neck_ratio_mean, links, (double)q->dom.owned};
        double lo = out->neck_min, hi[2] = {out->neck_max, out->time};
        if (sinter_qs_domain_reduce(q, sums, 4, SINTER_REDUCE_F64, SINTER_REDUCE_SUM) ==
                SINTER_OK &&
            sinter_qs_domain_reduce(q, &lo, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MIN) == SINTER_OK &&
            sinter_qs_domain_reduce(q, hi, 2, SINTER_REDUCE_F64, SINTER_REDUCE_MAX) == SINTER_OK) {
            out->neck_mean = sums[0];
            out->neck_ratio_mean = sums[1];
            links = sums[2];
            out->particles = (size_t)sums[3];
            out->neck_min = lo;
            out->neck_max = hi[0];
            out->time = hi[1];
            out->links = (size_t)links;
        }
    }
    if (qs->dom.repro) {
        out->neck_mean = exact[0];
        out->neck_ratio_mean = exact[1];
    }
    if (links > 0.0) {
        out->neck_mean /= links;
        out->neck_ratio_mean /= links;
    } else {
        out->neck_min = 0.0;
    }
    shrinkage(qs, p, out->shrinkage);
    /* The green density (sphere volume over the spheres' bounding box at the start) carried by
     * the homogeneous strain: a box that shrinks by s_d along each axis. */
    out->relative_density = qs->density0 / ((1.0 - out->shrinkage[0]) * (1.0 - out->shrinkage[1]) *
                                            (1.0 - out->shrinkage[2]));
    out->coordination =
        out->particles > 0 ? 2.0 * (double)out->links / (double)out->particles : 0.0;
}

/* ---- adapter to the stepper ---------------------------------------------------------------- */

sinter_status sinter_quasistatic_step(struct sinter_stepper *st, sinter_qs **qs,
                                      const sinter_qs_options *opt, double h, double *taken)
{
    sinter_particles *ps = st->ps;
    sinter_status s = SINTER_OK;
    if (*qs == NULL)
        s = sinter_qs_create(qs, st->ctx, opt);
    if (s == SINTER_OK && st->domain.on) /* (settings not yet supported across subdomains) */
        s = sinter_domain_check(st);
    /* with domain operations (qs_domain.h): the ghosts' state from their owners first */
    if (st->domain.on && (s = sinter_domain_agree(st->ctx, &st->domain, s)) == SINTER_OK)
        s = sinter_domain_forward(st->ctx, &st->domain, ps);
    if (s == SINTER_OK)
        s = sinter_qs_domain_bind(*qs, st);
    if (s != SINTER_OK)
        return s;
    /* a reordering (option sort_interval), addition or removal of particles is followed through
     * their ids (qs_ids.c); after particles were added or removed the plane conditions are
     * detected again even where the ids are those of the last step (an id removed and given
     * again: the links of that id stay, as for a particle that leaves and comes back) */
    if ((*qs)->population_known && (*qs)->population_generation != ps->population_generation &&
        !st->domain.on) /* (the ghosts are made again at each redistribution) */
        (*qs)->slots_valid = 0;
    const sinter_qs_particles ids_view = {ps->count,    ps->x,  ps->rot, ps->radius,
                                          ps->material, ps->id, NULL};
    s = sinter_qs_follow_ids(*qs, &ids_view);
    if ((s = sinter_qs_domain_agree(*qs, s)) != SINTER_OK)
        return s;
    /* the stepper's periodic axes (sinter_stepper_set_periodic): the cell is the core's once
     * it steps, and is written back after each step, so only a change by the host is taken */
    int per[3], cell_per[3];
    double cell_lo[3], cell_hi[3];
    sinter_qs_get_cell(*qs, cell_per, cell_lo, cell_hi);
    int changed = 0;
    for (int d = 0; d < 3; ++d) {
        per[d] = st->ghosts.periodic[d];
        changed |= per[d] != cell_per[d] ||
                   (per[d] && (st->ghosts.lo[d] != cell_lo[d] || st->ghosts.hi[d] != cell_hi[d]));
    }
    if (changed && (s = sinter_qs_set_cell(*qs, per, st->ghosts.lo, st->ghosts.hi)) != SINTER_OK)
        return s;
    (*qs)->layout_generation = ps->layout_generation;
    (*qs)->population_generation = ps->population_generation;
    (*qs)->population_known = 1;
    /* The materials in use (index = material id). */
    sinter_qs_material *mats = sinter_calloc(st->ctx, SINTER_MAX_MATERIALS, sizeof(*mats));
    if ((s = sinter_qs_domain_agree(*qs, mats == NULL ? SINTER_ERR_NOMEM : SINTER_OK)) !=
        SINTER_OK) {
        sinter_free(st->ctx, mats);
        return s;
    }
    for (int id = 0; id < SINTER_MAX_MATERIALS; ++id) {
        if (!ps->material_used[id])
            continue;
        sinter_neck_material_from(&ps->materials[id], &mats[id].neck);
        mats[id].youngs = ps->materials[id].value[SINTER_MAT_YOUNGS_MODULUS];
        mats[id].poisson = ps->materials[id].value[SINTER_MAT_POISSON_RATIO];
    }
    /* The furnace's T(t), or the mean particle temperature held over the step (summed in id
     * order; with domain operations over every subdomain's owned particles). */
    double mean[2] = {0.0, 0.0};
    for (size_t k = 0; k < ps->count; ++k) {
        const size_t i = (*qs)->index_of_slot[k];
        if (!sinter_qs_domain_ghost(*qs, i)) {
            mean[0] += ps->temperature[i];
            mean[1] += 1.0;
        }
    }
    if ((s = sinter_qs_domain_reduce(*qs, mean, 2, SINTER_REDUCE_F64, SINTER_REDUCE_SUM)) ==
            SINTER_OK &&
        (*qs)->dom.repro && st->furnace_count == 0) { /* the temperatures' exact sum */
        double *terms = sinter_alloc(st->ctx, (ps->count + 1) * sizeof(double));
        size_t k = 0;
        for (size_t i = 0; i < ps->count && terms != NULL; ++i)
            if (!sinter_qs_domain_ghost(*qs, i))
                terms[k++] = ps->temperature[i];
        s = sinter_qs_domain_agree(*qs, terms == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
        if (s == SINTER_OK)
            s = sinter_qs_repro_series(*qs, terms, k, 1, &mean[0]);
        sinter_free(st->ctx, terms);
    }
    if (s != SINTER_OK) {
        sinter_free(st->ctx, mats);
        return s;
    }
    double mean_temperature = mean[1] > 0.0 ? mean[0] / mean[1] : 0.0;
    const double times[1] = {st->time}, temps[1] = {mean_temperature};
    sinter_neck_schedule schedule = {1, times, temps};
    if (st->furnace_count > 0) {
        schedule.count = st->furnace_count;
        schedule.times = st->furnace;
        schedule.temperatures = st->furnace + st->furnace_count;
        mean_temperature = 1.0; /* the furnace's temperatures are checked positive */
    }
    const sinter_qs_particles view = {ps->count,    ps->x,  ps->rot, ps->radius,
                                      ps->material, ps->id, mats};
    double step = 0.0;
    if (!(mean_temperature > 0.0))
        s = sinter_fail(st->ctx, SINTER_ERR_INVALID,
                        "quasi-static stepper: the particles need a positive temperature");
    else
        s = sinter_qs_step(*qs, &view, &schedule, st->time, h, &step);
    sinter_free(st->ctx, mats);
    if (s != SINTER_OK)
        return s;
    if (sinter_qs_get_cell(*qs, cell_per, cell_lo, cell_hi)) /* the cell after the step */
        for (int d = 0; d < 3; ++d)
            if (cell_per[d])
                st->ghosts.hi[d] = cell_hi[d];
    *taken = step;
    st->time += step;
    st->dt = (*qs)->dt_next;
    st->stats.dt = st->dt;
    st->forces_current = 0;
    return SINTER_OK;
}
