/*
 * The contact-area-scaled power law of seed 000 sec. 2.1-2.3:
 *  - contact (eq. 2-4): f_i = -K_p |E_ij|^p_p n_ij A_ij, E_ij = (d - (R_i + R_j)) / (R_i + R_j)
 *    (eq. 3), n_ij from i to j (eq. 4), A_ij = pi a^2 from eq. 7-12 (the contact list);
 *  - sliding friction (eq. 5-6): mu_d |f_con| against the relative tangential velocity;
 *  - wall contact (eq. 13-17): f_i = -K_w |E_iw|^p_w n_iw A_i with E_iw = (s - R_i) / R_i, s the
 *    centre-plane distance (eq. 14 written for any plane), plus sliding friction;
 *  - adhesive bonds (eq. 18-19), read as below.
 *
 * Pair values: K, p and E* of two materials (or particle and wall) are arithmetic means; mu_d is
 * the geometric mean (as in hertz_mindlin.c: a frictionless wall gives no friction).
 * Thermal softening (sec. 2.2 remark, sec. 7): K_p is multiplied by the mean of the two
 * particles' modulus scales, K_w by the particle's (the wall keeps its reference stiffness).
 * K_b is not softened: bonding is what heating promotes.
 *
 * Friction direction: eq. 6 and 17 use the centre velocities; since the friction force here
 * also exerts moments b x f (b_i = L_i n, b_j = -(d - L_i) n), the relative velocity is taken
 * at the contact point, u = (v_i + w_i x b_i) - (v_j + w_j x b_j) (the wall moves with u_w),
 * which is eq. 6 / 17 for non-spinning particles; only its tangential part u_t counts. Below
 * |u_t| <= 1e-12 (|v_i + w_i x b_i| + |v_j + w_j x b_j|), i.e. round-off of the velocities
 * involved, the direction is undefined and no friction is applied.
 *
 * Bonds (eq. 18-19). Reading: a bond is a persistent state of a particle pair. It is activated
 * in any evaluation that finds the pair with E_ij <= 0 and |E_ij| >= E* (eq. 19's criterion),
 * and from then on, for as long as the pair overlaps (eq. 18: d < R_i + R_j), it adds
 * f_i = +K_b |E_ij|^p_b n_ij A_ij (eq. 19 without the minus of eq. 2: towards j, attractive;
 * j gets the opposite), also after |E_ij| has dropped below E* again. When the contact ends
 * (E_ij > 0, the third case of sec. 2.3) the bond is broken; a new one needs a new
 * interpenetration past E*. The force vanishes continuously as the contact opens (|E| and A go
 * to 0): the bond lowers the repulsion and so the springback (sec. 7.2, phase 3). K_b = 0 (the
 * default) disables the force. History: 1 double per particle pair, 1.0 = bonded; activation
 * is trial history, committed only when the step is accepted.
 */
#include <math.h>

#include "force_model.h"
#include "vec3.h"

/* Model parameters (keys of sinter_force_power_law). */
enum { PARAM_BOND_STRENGTH = 0, PARAM_BOND_SOFTENING = 1 };

/* Relative tangential speed below which friction has no direction, relative to the speeds. */
static const double SLIP_EPS = 1e-12;

static double scale_of(const sinter_force_eval *e, size_t i)
{
    return e->modulus_scale ? e->modulus_scale[i] : 1.0;
}

static double geometric_mean(const sinter_material *a, const sinter_material *b,
                             sinter_material_param p)
{
    return sqrt(a->value[p] * b->value[p]);
}

static double mean(const sinter_material *a, const sinter_material *b, sinter_material_param p)
{
    return 0.5 * (a->value[p] + b->value[p]);
}

/* |E|^p of eq. 2, 13 and 19. Seed 000's exponents are whole or half numbers (2 in its press
 * scene): products and a square root give them within an ulp of pow, at a fraction of its cost
 * (pow was a fifth of the press scene's run); other exponents go to pow. */
static inline double power_of(double x, double p)
{
    if (p == 2.0)
        return x * x;
    if (p == 1.0)
        return x;
    if (p == 3.0)
        return x * x * x;
    if (p == 1.5)
        return x * sqrt(x);
    return pow(x, p);
}

/* Friction of eq. 5-6 / 16-17: adds mu_d fn_abs along -u_t to f (u = relative contact-point
 * velocity, i minus j; the threshold speed = |u_i| + |u_j|, given by its two parts' squares:
 * their square roots are taken only when |u_t| is near the threshold, the same test). */
static void add_friction(const double n[3], const double u[3], double ui2, double uj2, double mu_d,
                         double fn_abs, double f[3])
{
    if (mu_d * fn_abs == 0.0)
        return;
    const double un = v3_dot(u, n);
    const double ut[3] = {u[0] - un * n[0], u[1] - un * n[1], u[2] - un * n[2]};
    const double ut2 = v3_dot(ut, ut), ut_len = sqrt(ut2);
    /* (|u_i| + |u_j|)^2 <= 2 (|u_i|^2 + |u_j|^2), with a margin of 1e-6 for the rounding of
     * both sides (|u_t|^2 scaled up rather than the speeds down, which could underflow): above
     * it the exact test holds for sure. */
    if (!(ut2 * (1.0 / (SLIP_EPS * SLIP_EPS)) > 2.000001 * (ui2 + uj2)) &&
        !(ut_len > SLIP_EPS * (sqrt(ui2) + sqrt(uj2))))
        return;
    const double s = -mu_d * fn_abs / ut_len; /* t = -u_t / |u_t|, eq. 6 and 17 */
    for (int d = 0; d < 3; ++d)
        f[d] += s * ut[d];
}

/* The parameters of a material pair (means as in the header), kept while consecutive contacts
 * have the same pair: the same values, without the square root and the lookups each time. */
typedef struct pair_params {
    const sinter_material *a, *b;
    double stiffness, exponent, critical_strain, bond_stiffness, bond_exponent, friction;
} pair_params;

static void pp_params(const sinter_material *mi, const sinter_material *mj, pair_params *q)
{
    if (q->a == mi && q->b == mj)
        return;
    q->a = mi;
    q->b = mj;
    q->stiffness = mean(mi, mj, SINTER_MAT_CONTACT_STIFFNESS);
    q->exponent = mean(mi, mj, SINTER_MAT_CONTACT_EXPONENT);
    q->critical_strain = mean(mi, mj, SINTER_MAT_BOND_CRITICAL_STRAIN);
    q->bond_stiffness = mean(mi, mj, SINTER_MAT_BOND_STIFFNESS);
    q->bond_exponent = mean(mi, mj, SINTER_MAT_BOND_EXPONENT);
    q->friction = geometric_mean(mi, mj, SINTER_MAT_FRICTION_DYNAMIC);
}

static void pw_params(const sinter_material *mi, const sinter_material *mw, pair_params *q)
{
    if (q->a == mi && q->b == mw)
        return;
    q->a = mi;
    q->b = mw;
    q->stiffness = mean(mi, mw, SINTER_MAT_WALL_STIFFNESS);
    q->exponent = mean(mi, mw, SINTER_MAT_WALL_EXPONENT);
    q->friction = geometric_mean(mi, mw, SINTER_MAT_FRICTION_DYNAMIC);
}

/* Contact k's normal force (f_bond - f_con) n on i (minus on j), the friction of eq. 5-6 at the
 * contact points x_i + b_i and x_j + b_j, and their moments about the centres. */
static inline void apply_pp(const sinter_force_eval *e, size_t k, uint32_t i, uint32_t j,
                            double f_con, double f_bond, double friction)
{
    const sinter_contact_list *c = e->pp;
    const double *v = e->ps->v, *w = e->ps->w;
    const double *n = c->n + 3 * k;
    double f[3];
    for (int d = 0; d < 3; ++d)
        f[d] = (f_bond - f_con) * n[d]; /* eq. 2 and 19, force on i */
    const double li = c->branch[k], lj = c->dist[k] - li;
    const double bi[3] = {li * n[0], li * n[1], li * n[2]};
    const double bj[3] = {-lj * n[0], -lj * n[1], -lj * n[2]};
    double ui[3], uj[3], u[3];
    v3_cross(w + 3 * i, bi, ui);
    v3_cross(w + 3 * j, bj, uj);
    for (int d = 0; d < 3; ++d) {
        ui[d] += v[3 * i + d];
        uj[d] += v[3 * j + d];
        u[d] = ui[d] - uj[d];
    }
    add_friction(n, u, v3_dot(ui, ui), v3_dot(uj, uj), friction, f_con, f);
    /* Moments about the centres: b_i x f on i, b_j x (-f) on j. */
    const double fj[3] = {-f[0], -f[1], -f[2]};
    double ti[3], tj[3];
    v3_cross(bi, f, ti);
    v3_cross(bj, fj, tj);
    for (int d = 0; d < 3; ++d) {
        e->force[3 * i + d] += f[d];
        e->force[3 * j + d] -= f[d];
        e->torque[3 * i + d] += ti[d];
        e->torque[3 * j + d] += tj[d];
    }
}

/* The seed's bonds (history width 1). */
static void eval_pp(const sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *r = ps->radius;
    const double *hist = e->hist_pp->committed;
    double *trial = e->hist_pp->trial;
    pair_params q = {NULL, NULL, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        pp_params(&ps->materials[ps->material[i]], &ps->materials[ps->material[j]], &q);
        const double strain = c->delta[k] / (r[i] + r[j]); /* |E_ij|, eq. 3 (E_ij = -strain) */
        const double area = c->area[k];                    /* A_ij, eq. 11-12 */
        /* Contact, eq. 2: magnitude K_p |E|^p_p A, repulsive (-n on i). */
        const double kp = q.stiffness * 0.5 * (scale_of(e, i) + scale_of(e, j));
        const double f_con = kp * power_of(strain, q.exponent) * area;
        /* Bond, eq. 18-19: active if committed, or activated now by |E| >= E*. */
        const int bonded = hist[c->pair[k]] != 0.0 || strain >= q.critical_strain;
        trial[k] = bonded ? 1.0 : 0.0;
        const double f_bond = bonded && q.bond_stiffness > 0.0
                                  ? q.bond_stiffness * power_of(strain, q.bond_exponent) * area
                                  : 0.0;
        apply_pp(e, k, i, j, f_con, f_bond, q.friction);
    }
}

/* 1 for the side that counts a pair's broken bond: with subdomains (domain.h) a pair across a
 * border is evaluated on both ranks and breaks on both (its history is equal there), so only
 * the rank that owns the smaller id counts it; serially every pair counts. */
static int counts_once(const sinter_particles *ps, uint32_t i, uint32_t j)
{
    const size_t owned = ps->count - ps->ghost_count;
    return (ps->id[i] < ps->id[j] ? i : j) < owned;
}

/* Bonds that hold (bond_strength > 0; history width 2: the bond flag and the bond's area A_b,
 * the largest contact area the bonded pair reached). Overlapping pairs: eq. 2, 5-6 and 18-19
 * as in eval_pp. A bonded pair apart (E_ij > 0: the search keeps it, sinter_contact_list.held)
 * carries the seed's bond law continued into tension, f_i = +k_b E_ij^p_b A_b n_ij towards j,
 * k_b = K_b (times the pair's mean modulus scale with bond_softening), which is 0 at E_ij = 0
 * as eq. 19 is; the bond breaks (for good) in the first evaluation where the tensile stress
 * k_b E_ij^p_b exceeds bond_strength. */
static void eval_pp_hold(const sinter_force_model *fm, sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *r = ps->radius;
    const double *hist = e->hist_pp->committed;
    double *trial = e->hist_pp->trial;
    const double strength = fm->param[PARAM_BOND_STRENGTH];
    const int soften = fm->param[PARAM_BOND_SOFTENING] != 0.0;
    pair_params q = {NULL, NULL, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    uint64_t broken = 0;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        pp_params(&ps->materials[ps->material[i]], &ps->materials[ps->material[j]], &q);
        const double *held = hist + 2 * (size_t)c->pair[k];
        double *out = trial + 2 * k;
        const double strain = c->delta[k] / (r[i] + r[j]); /* |E_ij| in compression */
        const double s_ij = 0.5 * (scale_of(e, i) + scale_of(e, j));
        if (strain <= 0.0) { /* apart or just touching: only a committed bond keeps it here */
            const double kb = q.bond_stiffness * (soften ? s_ij : 1.0);
            const double stress = kb * power_of(-strain, q.bond_exponent);
            if (held[0] == 0.0 || stress > strength) {
                broken += held[0] != 0.0 && counts_once(ps, i, j);
                out[0] = out[1] = 0.0;
                continue;
            }
            out[0] = 1.0;
            out[1] = held[1];
            apply_pp(e, k, i, j, 0.0, stress * held[1], q.friction);
            continue;
        }
        const double area = c->area[k];
        const double f_con = q.stiffness * s_ij * power_of(strain, q.exponent) * area;
        const int bonded = held[0] != 0.0 || strain >= q.critical_strain;
        out[0] = bonded ? 1.0 : 0.0;
        out[1] = bonded ? (area > held[1] ? area : held[1]) : 0.0;
        const double f_bond = bonded && q.bond_stiffness > 0.0
                                  ? q.bond_stiffness * power_of(strain, q.bond_exponent) * area
                                  : 0.0;
        apply_pp(e, k, i, j, f_con, f_bond, q.friction);
    }
    e->bonds_broken = broken;
}

static void eval_pw(const sinter_force_eval *e)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pw;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *x = ps->x;
    pair_params q = {NULL, NULL, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], wall_index = c->j[k];
        const sinter_wall *wall = &e->walls->wall[wall_index];
        pw_params(&ps->materials[ps->material[i]], &wall->material, &q);
        const double *n = c->n + 3 * k;           /* from the particle towards the wall, eq. 15 */
        const double strain = c->delta[k] / r[i]; /* |E_iw|, eq. 14 with the plane distance */
        /* Wall contact, eq. 13: magnitude K_w |E_iw|^p_w A_i, away from the wall. */
        const double kw = q.stiffness * scale_of(e, i);
        const double f_con = kw * power_of(strain, q.exponent) * c->area[k];
        double f[3];
        for (int d = 0; d < 3; ++d)
            f[d] = -f_con * n[d];
        /* Continuous sliding friction against the wall's velocity, eq. 16-17. */
        const double li = c->branch[k];
        const double bi[3] = {li * n[0], li * n[1], li * n[2]};
        const double at[3] = {x[3 * i] + bi[0], x[3 * i + 1] + bi[1], x[3 * i + 2] + bi[2]};
        const double *uw = wall->u;
        double spun[3];
        if (wall->spin != 0.0) { /* the surface's velocity at the contact point */
            sinter_wall_velocity_at(wall, at, spun);
            uw = spun;
        }
        double ui[3], u[3];
        v3_cross(w + 3 * i, bi, ui);
        for (int d = 0; d < 3; ++d) {
            ui[d] += v[3 * i + d];
            u[d] = ui[d] - uw[d];
        }
        add_friction(n, u, v3_dot(ui, ui), v3_dot(uw, uw), q.friction, f_con, f);
        double ti[3];
        v3_cross(bi, f, ti);
        for (int d = 0; d < 3; ++d) {
            e->force[3 * i + d] += f[d];
            e->torque[3 * i + d] += ti[d];
            e->wall_force[3 * wall_index + d] -= f[d]; /* reaction on the wall */
        }
        if (e->pw_reaction != NULL) /* (the reproducible mode: each contact's own) */
            for (int d = 0; d < 3; ++d)
                e->pw_reaction[6 * k + (size_t)d] -= f[d];
        if (e->wall_moment != NULL && wall->moment_wanted)
            sinter_wall_add_moment(wall, at, f, NULL, e->wall_moment + 3 * wall_index);
        if (e->pw_reaction != NULL && e->wall_moment != NULL && wall->moment_wanted)
            sinter_wall_add_moment(wall, at, f, NULL, e->pw_reaction + 6 * k + 3);
    }
}

static sinter_status power_law_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    if (fm->param[PARAM_BOND_STRENGTH] > 0.0)
        eval_pp_hold(fm, e);
    else
        eval_pp(e);
    if (e->walls != NULL)
        eval_pw(e);
    return SINTER_OK;
}

static size_t power_law_history(const sinter_force_model *fm, int wall)
{
    return wall ? 0 : fm->param[PARAM_BOND_STRENGTH] > 0.0 ? 2 : 1;
}

static int power_law_holds(const sinter_force_model *fm)
{
    return fm->param[PARAM_BOND_STRENGTH] > 0.0;
}

const sinter_force_ops sinter_force_power_law = {.name = "power_law",
                                                 .history_pp = 1,
                                                 .uses_contacts = 1,
                                                 .keys = {"bond_strength", "bond_softening", NULL},
                                                 .defaults = {0.0, 0.0},
                                                 .eval = power_law_eval,
                                                 .history_width = power_law_history,
                                                 .holds_pairs = power_law_holds};
