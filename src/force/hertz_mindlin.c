/*
 * Hertz normal contact with viscous damping (seed 003 eq. 2-6), Mindlin
 * stick-slip friction with an accumulated tangential spring and Coulomb
 * return (eq. 7-14) and rolling resistance as a spring-damper-slider
 * (eq. 15-20). Walls are particles of infinite radius, mass and inertia
 * (seed 003 remark 1).
 *
 * Sign conventions: n points from i to j; u = (velocity of i's contact point)
 * - (velocity of j's contact point). The tangential spring Delta x integrates
 * the tangential part of u (eq. 10, 12) and the friction force on i is
 * -k_t Delta x - d_fric u_t (eq. 7); on slip it is scaled back to the Coulomb
 * limit mu_d |f_con| and the spring is reset consistently (eq. 13).
 *
 * Pair properties: E* and G* from eq. 3 and 9; damping rates of two different
 * materials are averaged arithmetically, friction and rolling coefficients
 * geometrically (a frictionless wall gives no friction).
 *
 * History per contact: Delta x (3 doubles), and Delta theta (3 doubles) when the
 * model's "rolling" parameter is non-zero at the time it is added to a stepper.
 */
#include <math.h>

#include "force_model.h"
#include "vec3.h"

enum { PARAM_ROLLING = 0 };

/* Material data of one side of a contact. */
typedef struct side {
    double compliance;       /* (1 - nu^2) / E  [1/Pa] */
    double shear_compliance; /* 1 / G  [1/Pa], G = E / (2 (1 + nu)) */
    double xi, mu_s, mu_d, xi_f, mu_r, xi_r;
} side;

/* Constants of a pair of materials (eq. 3, 9 and the averaged coefficients). */
typedef struct pair_consts {
    double estar, gstar;
    double sqrt_2estar, sqrt_8gstar; /* for the damping constants, eq. 6 and 11 */
    double xi, mu_s2, mu_d, xi_f, mu_r, xi_r; /* mu_s2 = mu_s^2 (squared comparisons) */
} pair_consts;

/* Per-contact quantities that depend on the two bodies. */
typedef struct pair_props {
    const pair_consts *c;
    double rstar, mstar, jstar;
} pair_props;

static void side_from_material(const sinter_material *m, double scale, side *s)
{
    const double e = m->value[SINTER_MAT_YOUNGS_MODULUS] * scale;
    const double nu = m->value[SINTER_MAT_POISSON_RATIO];
    s->compliance = (1.0 - nu * nu) / e;
    s->shear_compliance = 2.0 * (1.0 + nu) / e;
    s->xi = m->value[SINTER_MAT_DAMPING_RATIO];
    s->mu_s = m->value[SINTER_MAT_FRICTION_STATIC];
    s->mu_d = m->value[SINTER_MAT_FRICTION_DYNAMIC];
    s->xi_f = m->value[SINTER_MAT_FRICTION_DAMPING_RATIO];
    s->mu_r = m->value[SINTER_MAT_ROLLING_FRICTION];
    s->xi_r = m->value[SINTER_MAT_ROLLING_DAMPING_RATIO];
}

static void mix(const side *a, const side *b, pair_consts *p)
{
    p->estar = 1.0 / (a->compliance + b->compliance);             /* eq. 3 */
    p->gstar = 1.0 / (a->shear_compliance + b->shear_compliance); /* eq. 9 */
    p->sqrt_2estar = sqrt(2.0 * p->estar);
    p->sqrt_8gstar = sqrt(8.0 * p->gstar);
    /* Damping rates: arithmetic mean. Friction and rolling coefficients: geometric mean, so
     * that a frictionless wall (mu = 0, as in seed 003 sec. 5.2-5.3) gives no friction. */
    p->xi = 0.5 * (a->xi + b->xi);
    p->mu_s2 = a->mu_s * b->mu_s;
    p->mu_d = sqrt(a->mu_d * b->mu_d);
    p->xi_f = 0.5 * (a->xi_f + b->xi_f);
    p->mu_r = sqrt(a->mu_r * b->mu_r);
    p->xi_r = 0.5 * (a->xi_r + b->xi_r);
}

/*
 * The contact law for one contact. Inputs: geometry, u (relative velocity of
 * the contact points, i minus j), w_rel = w_i - w_j, pair properties.
 * Outputs: force on i, rolling moment on i, trial history.
 * Note r*^(1/4) delta^(1/4) = sqrt(sqrt(r* delta)), so eq. 6 and 11 need one root.
 */
static inline void contact_law(const pair_props *p, const double n[3], double delta,
                               const double u[3], const double w_rel[3], double dt,
                               const double *hist, double *trial, int rolling, double f[3],
                               double m_roll[3])
{
    const pair_consts *c = p->c;
    const double sqrt_rd = sqrt(p->rstar * delta);
    const double rd_q = sqrt(sqrt_rd);    /* (r* delta)^(1/4) */
    const double sqrt_m = sqrt(p->mstar);
    /* Normal: eq. 2 and 6. delta_dot = -(u_j - u_i).n = u.n with u = u_i - u_j. */
    const double un = v3_dot(u, n);
    const double d_con = 2.0 * c->xi * c->sqrt_2estar * sqrt_m * rd_q;
    const double fn = 4.0 / 3.0 * c->estar * sqrt_rd * delta + d_con * un; /* repulsive > 0 */
    const double fabs_n = fabs(fn);
    for (int d = 0; d < 3; ++d)
        f[d] = -fn * n[d];

    /* Tangential: eq. 7-13. */
    const double ut[3] = {u[0] - un * n[0], u[1] - un * n[1], u[2] - un * n[2]};
    const double kt = 8.0 * c->gstar * sqrt_rd;
    double sx[3] = {hist[0], hist[1], hist[2]};
    /* Keep the accumulated spring in the current tangent plane (rotate, keep length). */
    const double sn = v3_dot(sx, n);
    if (sn != 0.0) {
        for (int d = 0; d < 3; ++d)
            sx[d] -= sn * n[d];
        const double len1_2 = v3_dot(sx, sx);
        if (len1_2 > 0.0) {
            /* rescale by sqrt(1 + x), x = sn^2 / |sx|^2: the normal turns by ~1e-4 rad per
             * step, so a two-term series is exact to round-off for x < 1e-4 */
            const double x = sn * sn / len1_2;
            const double s = x < 1e-4 ? 1.0 + x * (0.5 - 0.125 * x) : sqrt(1.0 + x);
            for (int d = 0; d < 3; ++d)
                sx[d] *= s;
        }
    }
    for (int d = 0; d < 3; ++d)
        sx[d] += ut[d] * dt; /* eq. 10, 12 */
    const double d_fric = 2.0 * c->xi_f * c->sqrt_8gstar * sqrt_m * rd_q;
    double ft[3];
    for (int d = 0; d < 3; ++d)
        ft[d] = -kt * sx[d] - d_fric * ut[d];
    const double ft2 = v3_dot(ft, ft);
    if (ft2 > c->mu_s2 * fabs_n * fabs_n && ft2 > 0.0) {
        /* Slip (eq. 8): Coulomb force along the trial direction; spring from eq. 13. */
        const double scale = c->mu_d * fabs_n / sqrt(ft2);
        for (int d = 0; d < 3; ++d) {
            ft[d] *= scale;
            sx[d] = kt > 0.0 ? -(ft[d] + d_fric * ut[d]) / kt : 0.0;
        }
    }
    for (int d = 0; d < 3; ++d) {
        f[d] += ft[d];
        trial[d] = sx[d];
    }

    /* Rolling resistance: eq. 15-20. */
    if (rolling) {
        double th[3] = {hist[3] + w_rel[0] * dt, hist[4] + w_rel[1] * dt, hist[5] + w_rel[2] * dt};
        const double kr = kt * p->rstar * p->rstar;
        const double d_rol = 2.0 * c->xi_r * c->sqrt_8gstar * sqrt(p->jstar) * p->rstar * rd_q;
        double mr[3];
        for (int d = 0; d < 3; ++d)
            mr[d] = -kr * th[d] - d_rol * w_rel[d];
        const double mr_len = v3_norm(mr), limit = c->mu_r * p->rstar * fabs_n;
        if (mr_len > limit && mr_len > 0.0) {
            const double scale = limit / mr_len;
            for (int d = 0; d < 3; ++d) {
                mr[d] *= scale;
                th[d] = kr > 0.0 ? -(mr[d] + d_rol * w_rel[d]) / kr : 0.0;
            }
        }
        for (int d = 0; d < 3; ++d) {
            m_roll[d] = mr[d];
            trial[3 + d] = th[d];
        }
    } else {
        m_roll[0] = m_roll[1] = m_roll[2] = 0.0;
    }
}

/*
 * Pair constants of the materials in use, built once per evaluation. With
 * thermal softening E depends on each particle's temperature, and the
 * constants are mixed per contact instead.
 */
enum { MAX_TABLE = 8 };

typedef struct constants {
    int softening;
    int index[SINTER_MAX_MATERIALS]; /* material id -> row of the table, or -1 */
    int rows;
    side sides[MAX_TABLE];
    pair_consts table[MAX_TABLE * MAX_TABLE];
} constants;

static void build_constants(const sinter_force_eval *e, constants *k)
{
    const sinter_particles *ps = e->ps;
    k->softening = e->modulus_scale != NULL;
    k->rows = 0;
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m) {
        k->index[m] = -1;
        if (ps->material_used[m] && k->rows < MAX_TABLE) {
            k->index[m] = k->rows;
            side_from_material(&ps->materials[m], 1.0, &k->sides[k->rows]);
            k->rows++;
        }
    }
    for (int a = 0; a < k->rows; ++a)
        for (int b = 0; b < k->rows; ++b)
            mix(&k->sides[a], &k->sides[b], &k->table[a * MAX_TABLE + b]);
}

/* Constants of particles i and j: from the table, or mixed into `scratch`. */
static inline const pair_consts *pair_of(const constants *k, const sinter_force_eval *e, size_t i,
                                         size_t j, pair_consts *scratch)
{
    const sinter_particles *ps = e->ps;
    const int a = k->index[ps->material[i]], b = k->index[ps->material[j]];
    if (!k->softening && a >= 0 && b >= 0)
        return &k->table[a * MAX_TABLE + b];
    side si, sj;
    side_from_material(&ps->materials[ps->material[i]], k->softening ? e->modulus_scale[i] : 1.0,
                       &si);
    side_from_material(&ps->materials[ps->material[j]], k->softening ? e->modulus_scale[j] : 1.0,
                       &sj);
    mix(&si, &sj, scratch);
    return scratch;
}

/* The law for particle-particle contact q: force on i, moments on i and j, trial history. */
static inline void pp_contact(const sinter_force_eval *e, const constants *k, int rolling,
                              size_t q, double f[3], double ti_total[3], double tj_total[3])
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *mass = ps->mass,
                 *inertia = ps->inertia;
    const size_t width = e->hist_pp->width;
    const uint32_t i = c->i[q], j = c->j[q];
    const double *n = c->n + 3 * q;
    const double li = c->branch[q], lj = c->dist[q] - li;
    pair_consts scratch;
    pair_props p;
    p.c = pair_of(k, e, i, j, &scratch);
    p.rstar = r[i] * r[j] / (r[i] + r[j]);
    p.mstar = mass[i] * mass[j] / (mass[i] + mass[j]);
    p.jstar = rolling ? 1.0 / (1.0 / (inertia[i] + mass[i] * r[i] * r[i]) +
                               1.0 / (inertia[j] + mass[j] * r[j] * r[j])) /* eq. 18 */
                      : 0.0;
    /* Contact-point velocities: v + w x b, with b_i = L_i n and b_j = -L_j n. */
    const double bi[3] = {li * n[0], li * n[1], li * n[2]};
    const double bj[3] = {-lj * n[0], -lj * n[1], -lj * n[2]};
    double wi_b[3], wj_b[3];
    v3_cross(w + 3 * i, bi, wi_b);
    v3_cross(w + 3 * j, bj, wj_b);
    double u[3], w_rel[3];
    for (int d = 0; d < 3; ++d) {
        u[d] = v[3 * i + d] + wi_b[d] - v[3 * j + d] - wj_b[d];
        w_rel[d] = w[3 * i + d] - w[3 * j + d];
    }
    double mr[3];
    contact_law(&p, n, c->delta[q], u, w_rel, e->dt, e->hist_pp->committed + width * c->pair[q],
                e->hist_pp->trial + width * q, rolling, f, mr);
    double ti[3], tj[3];
    v3_cross(bi, f, ti); /* moment of f on i about its centre (eq. 14) */
    const double fj[3] = {-f[0], -f[1], -f[2]};
    v3_cross(bj, fj, tj);
    for (int d = 0; d < 3; ++d) {
        ti_total[d] = ti[d] + mr[d];
        tj_total[d] = tj[d] - mr[d];
    }
}

static sinter_status eval_pp(const sinter_force_eval *e, const constants *k, int rolling)
{
    const sinter_contact_list *c = e->pp;
    double *force = e->force, *torque = e->torque;
    /* The two-phase path pays only with enough contacts per particle (measured: with 0.37 per
     * particle it is slower than one thread); both paths give the same bits. */
    const int threads =
        c->count < 2048 || c->count < c->particle_count ? 1 : sinter_threads(e->ctx);
    if (threads <= 1) {
        for (size_t q = 0; q < c->count; ++q) {
            double f[3], ti[3], tj[3];
            pp_contact(e, k, rolling, q, f, ti, tj);
            const uint32_t i = c->i[q], j = c->j[q];
            for (int d = 0; d < 3; ++d) {
                force[3 * i + d] += f[d];
                force[3 * j + d] -= f[d];
                torque[3 * i + d] += ti[d];
                torque[3 * j + d] += tj[d];
            }
        }
        return SINTER_OK;
    }
    /*
     * Threads: (1) every contact's force and moments into a scratch array, in parallel;
     * (2) every particle sums its contacts in ascending contact order, in parallel. The sums
     * are done in the same order as the loop above, so the result does not depend on the
     * number of threads.
     */
    double *out = sinter_alloc(e->ctx, 9 * c->count * sizeof(double));
    if (out == NULL)
        return SINTER_ERR_NOMEM;
    const long count = (long)c->count;
#pragma omp parallel for num_threads(threads) schedule(static)
    for (long q = 0; q < count; ++q)
        pp_contact(e, k, rolling, (size_t)q, out + 9 * q, out + 9 * q + 3, out + 9 * q + 6);
    const long particles = (long)c->particle_count;
#pragma omp parallel for num_threads(threads) schedule(static)
    for (long p = 0; p < particles; ++p) {
        double f[3] = {force[3 * p], force[3 * p + 1], force[3 * p + 2]};
        double t[3] = {torque[3 * p], torque[3 * p + 1], torque[3 * p + 2]};
        for (uint32_t a = c->adj_start[p]; a < c->adj_start[p + 1]; ++a) {
            const uint32_t q = c->pair_to_contact[c->adj_pair[a]];
            if (q == SINTER_NO_PAIR)
                continue;
            const double *o = out + 9 * (size_t)q;
            const int first = c->i[q] == (uint32_t)p;
            for (int d = 0; d < 3; ++d) {
                f[d] = first ? f[d] + o[d] : f[d] - o[d];
                t[d] += first ? o[3 + d] : o[6 + d];
            }
        }
        for (int d = 0; d < 3; ++d) {
            force[3 * p + d] = f[d];
            torque[3 * p + d] = t[d];
        }
    }
    sinter_free(e->ctx, out);
    return SINTER_OK;
}

static sinter_status eval_pw(const sinter_force_eval *e, const constants *k, int rolling)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pw;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *mass = ps->mass,
                 *inertia = ps->inertia;
    const size_t width = e->hist_pw->width;
    const double *hist = e->hist_pw->committed;
    double *trial = e->hist_pw->trial;
    for (size_t q = 0; q < c->count; ++q) {
        const uint32_t i = c->i[q], wall_index = c->j[q];
        const sinter_wall *wall = &e->walls->wall[wall_index];
        const double *n = c->n + 3 * q;
        const double li = c->branch[q];
        side si, sw;
        side_from_material(&ps->materials[ps->material[i]],
                           k->softening ? e->modulus_scale[i] : 1.0, &si);
        side_from_material(&wall->material, 1.0, &sw);
        pair_consts consts;
        mix(&si, &sw, &consts);
        pair_props p = {&consts, r[i], mass[i], inertia[i] + mass[i] * r[i] * r[i]};
        const double bi[3] = {li * n[0], li * n[1], li * n[2]};
        double wi_b[3];
        v3_cross(w + 3 * i, bi, wi_b);
        double u[3];
        for (int d = 0; d < 3; ++d)
            u[d] = v[3 * i + d] + wi_b[d] - wall->u[d];
        double f[3], mr[3], ti[3];
        contact_law(&p, n, c->delta[q], u, w + 3 * i, e->dt, hist + width * (size_t)c->pair[q],
                    trial + width * q, rolling, f, mr);
        v3_cross(bi, f, ti);
        for (int d = 0; d < 3; ++d) {
            e->force[3 * i + d] += f[d];
            e->torque[3 * i + d] += ti[d] + mr[d];
            e->wall_force[3 * wall_index + d] -= f[d];
        }
    }
    return SINTER_OK;
}

static sinter_status hertz_mindlin_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    /* Rolling needs the 6-wide history chosen when the model was added to the stepper. */
    const int rolling = fm->param[PARAM_ROLLING] != 0.0 && e->hist_pp->width == 6;
    constants k;
    build_constants(e, &k);
    sinter_status st = rolling ? eval_pp(e, &k, 1) : eval_pp(e, &k, 0);
    if (st == SINTER_OK && e->walls != NULL)
        st = rolling ? eval_pw(e, &k, 1) : eval_pw(e, &k, 0);
    return st;
}

/* Delta x (3) always; Delta theta (3) only with rolling resistance. */
static size_t hertz_mindlin_history(const sinter_force_model *fm, int wall)
{
    (void)wall;
    return fm->param[PARAM_ROLLING] != 0.0 ? 6 : 3;
}

const sinter_force_ops sinter_force_hertz_mindlin = {
    .name = "hertz_mindlin",
    .history_pp = 6,
    .history_pw = 6,
    .uses_contacts = 1,
    .keys = {"rolling", NULL},
    .defaults = {1.0},
    .eval = hertz_mindlin_eval,
    .history_width = hertz_mindlin_history,
};
