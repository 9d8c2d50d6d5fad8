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
 *
 * "no_tension" (default 0, eq. 2 as printed): 1 clamps the normal force at zero, f_n =
 * max(f_n, 0), before the friction and rolling limits read it. The pair blocks of each
 * setting are a function of their own (hertz_blocks.inc, included twice), so the default's
 * is the same machine code as before the option existed.
 */
#include <math.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "contact/chunks.h"
#include "core/clones.h"
#include "core/ranges_run.h"
#include "core/stream_store.h"
#include "force_model.h"
#include "vec3.h"

enum { PARAM_ROLLING = 0, PARAM_NO_TENSION = 1 };

/* Material data of one side of a contact. */
typedef struct side {
    double compliance;       /* (1 - nu^2) / E  [1/Pa] */
    double shear_compliance; /* 1 / G  [1/Pa], G = E / (2 (1 + nu)) */
    double xi, mu_s, mu_d, xi_f, mu_r, xi_r;
} side;

/* Constants of a pair of materials (eq. 3, 9 and the averaged coefficients), with the
 * per-contact prefactors folded in once per pair of materials. */
typedef struct pair_consts {
    double estar, gstar;
    double sqrt_2estar, sqrt_8gstar; /* for the damping constants, eq. 6 and 11 */
    double xi, mu_s2, mu_d, xi_f, mu_r, xi_r; /* mu_s2 = mu_s^2 (squared comparisons) */
    double kn_pre;   /* 4/3 E*            (eq. 2: f = kn_pre sqrt(r* delta) delta) */
    double kt_pre;   /* 8 G*              (eq. 9: k_t = kt_pre sqrt(r* delta)) */
    double dn_pre;   /* 2 xi sqrt(2 E*)   (eq. 6: d = dn_pre sqrt(m*) (r* delta)^(1/4)) */
    double dt_pre;   /* 2 xi_f sqrt(8 G*) (eq. 11) */
    double dr_pre;   /* 2 xi_r sqrt(8 G*) (eq. 20) */
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
    p->kn_pre = 4.0 / 3.0 * p->estar;
    p->kt_pre = 8.0 * p->gstar;
    p->dn_pre = 2.0 * p->xi * p->sqrt_2estar;
    p->dt_pre = 2.0 * p->xi_f * p->sqrt_8gstar;
    p->dr_pre = 2.0 * p->xi_r * p->sqrt_8gstar;
}

/* The per-contact law is inlined into each specialised loop (rolling on/off, one or many
 * pairs of materials), so no loop carries a branch for a submodel the scene did not enable. */
#if defined(__GNUC__)
#define HM_INLINE static inline __attribute__((always_inline))
#else
#define HM_INLINE static inline
#endif

/* The two roots of a contact: sqrt_rd = sqrt(r* delta) and sm = sqrt(m* sqrt_rd) =
 * sqrt(m*) (r* delta)^(1/4). */
HM_INLINE void roots(double rstar, double mstar, double delta, double *sqrt_rd, double *sm)
{
    const double s = sqrt(rstar * delta);
    *sqrt_rd = s;
    *sm = sqrt(mstar * s);
}

/*
 * The contact law for one contact. Inputs: geometry, u (relative velocity of
 * the contact points, i minus j), w_rel = w_i - w_j, pair properties.
 * Outputs: force on i, rolling moment on i, trial history.
 * Two roots serve eq. 2, 6, 9 and 11, given by the caller (see roots()).
 */
HM_INLINE void contact_law(const pair_props *p, const double n[3], double delta,
                           double sqrt_rd, double sm, const double u[3], const double w_rel[3],
                           double dt, const double *hist, double *trial, int rolling,
                           int no_tension, double f[3], double m_roll[3], double *power)
/* (power: NULL where the force is wanted; hertz_mindlin_dissipation's 2 values) */
{
    const pair_consts *c = p->c;
    /* Normal: eq. 2 and 6. delta_dot = -(u_j - u_i).n = u.n with u = u_i - u_j. */
    const double un = v3_dot(u, n);
    const double fn0 = c->kn_pre * sqrt_rd * delta + c->dn_pre * sm * un; /* repulsive > 0 */
    const double fn = no_tension && !(fn0 > 0.0) ? 0.0 : fn0; /* "no_tension": f_n >= 0 */
    const double fabs_n = fabs(fn);

    /* Tangential: eq. 7-13. */
    const double ut[3] = {u[0] - un * n[0], u[1] - un * n[1], u[2] - un * n[2]};
    const double kt = c->kt_pre * sqrt_rd;
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
    const double d_fric = c->dt_pre * sm;
    double ft[3];
    for (int d = 0; d < 3; ++d)
        ft[d] = -kt * sx[d] - d_fric * ut[d];
    const double ft2 = v3_dot(ft, ft);
    const int slipping = ft2 > c->mu_s2 * fabs_n * fabs_n && ft2 > 0.0;
    if (slipping) {
        /* Slip (eq. 8): Coulomb force along the trial direction; spring from eq. 13. */
        const double scale = c->mu_d * fabs_n / sqrt(ft2);
        const double inv_kt = kt > 0.0 ? 1.0 / kt : 0.0;
        for (int d = 0; d < 3; ++d) {
            ft[d] *= scale;
            sx[d] = kt > 0.0 ? -(ft[d] + d_fric * ut[d]) * inv_kt : 0.0;
        }
    }
    for (int d = 0; d < 3; ++d) {
        f[d] = ft[d] - fn * n[d];
        trial[d] = sx[d];
    }
    if (power != NULL) { /* hertz_mindlin_dissipation: the normal damper, the sliding */
        power[0] = (fn - c->kn_pre * sqrt_rd * delta) * un;
        power[1] = slipping ? fabs(v3_dot(ft, ut)) : 0.0;
    }

    /* Rolling resistance: eq. 15-20. */
    if (rolling) {
        double th[3] = {hist[3] + w_rel[0] * dt, hist[4] + w_rel[1] * dt, hist[5] + w_rel[2] * dt};
        const double kr = kt * p->rstar * p->rstar;
        /* d_rol = 2 xi_r sqrt(8 G* J*) r* (r* delta)^(1/4) = dr_pre sqrt(J* s) r* */
        const double d_rol = c->dr_pre * sqrt(p->jstar * sqrt_rd) * p->rstar;
        double mr[3];
        for (int d = 0; d < 3; ++d)
            mr[d] = -kr * th[d] - d_rol * w_rel[d];
        const double mr_len = v3_norm(mr), limit = c->mu_r * p->rstar * fabs_n;
        if (mr_len > limit && mr_len > 0.0) {
            const double scale = limit / mr_len;
            const double inv_kr = kr > 0.0 ? 1.0 / kr : 0.0;
            for (int d = 0; d < 3; ++d) {
                mr[d] *= scale;
                th[d] = kr > 0.0 ? -(mr[d] + d_rol * w_rel[d]) * inv_kr : 0.0;
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
    /* 1 if a material in use has a rolling coefficient mu_r > 0: without one, every pair's
     * and wall's mu_r (a geometric mean) is 0 and the rolling moment is 0 (eq. 17) */
    int any_rolling;
    int index[SINTER_MAX_MATERIALS]; /* material id -> row of the table, or -1 */
    int rows;
    side sides[MAX_TABLE];
    pair_consts table[MAX_TABLE * MAX_TABLE];
    int no_tension; /* the model's "no_tension": the normal force never pulls (f_n >= 0) */
} constants;

static void build_constants(const sinter_force_eval *e, constants *k)
{
    const sinter_particles *ps = e->ps;
    k->softening = e->modulus_scale != NULL;
    k->any_rolling = 0;
    k->no_tension = 0;
    k->rows = 0;
    for (int m = 0; m < SINTER_MAX_MATERIALS; ++m)
        k->index[m] = -1;
    for (int m = 0; m < ps->material_top; ++m) {
        if (ps->material_used[m] && ps->materials[m].value[SINTER_MAT_ROLLING_FRICTION] > 0.0)
            k->any_rolling = 1;
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

/* Constants of particles i and j: `single` when one entry serves every pair (one material in
 * use, no softening), else from the table, or mixed into `scratch`. */
HM_INLINE const pair_consts *pair_of(const constants *k, const sinter_force_eval *e, size_t i,
                                     size_t j, const pair_consts *single, pair_consts *scratch)
{
    if (single != NULL)
        return single;
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

/* Contacts per block of the blocked law: 16 gives the chain of roots and divisions of each
 * contact (geometry, eq. 2, 6) four independent AVX2 vectors to overlap; 8 was 2-3 % slower in
 * the force phase on the 64k packed bed, 32 no better (issue 9). */
enum { BLOCK = 16 };

/*
 * Blocked law, with or without rolling resistance, for any mix of materials: contacts are taken
 * BLOCK at a time, their inputs gathered into short arrays, the arithmetic done in one
 * branch-free loop over the block (selects instead of branches, so the compiler vectorises
 * it, and with a wider instruction set chosen at run time where the CPU has one), and the
 * results written back. The same operations in the same order as contact_law, on every
 * path, so every path gives the same bits (no contraction into FMA: ISO C mode).
 */
typedef struct blk {
    double nx[BLOCK], ny[BLOCK], nz[BLOCK], delta[BLOCK], li[BLOCK], lj[BLOCK];
    double ri[BLOCK], rj[BLOCK], mi[BLOCK], mj[BLOCK];
    double dvx[BLOCK], dvy[BLOCK], dvz[BLOCK];
    double wix[BLOCK], wiy[BLOCK], wiz[BLOCK], wjx[BLOCK], wjy[BLOCK], wjz[BLOCK];
    double hx[BLOCK], hy[BLOCK], hz[BLOCK];
    double kn[BLOCK], dn[BLOCK], kt[BLOCK], dtp[BLOCK], mus2[BLOCK], mud[BLOCK];
    double apart[BLOCK]; /* lean lists: 1 where the pair no longer touches (skipped) */
    /* rolling resistance: I + m r^2 of i and j (eq. 18), the rolling spring Delta theta, the
     * constants dr_pre and mu_r (gathered without `single`) */
    double ii[BLOCK], ij[BLOCK], hrx[BLOCK], hry[BLOCK], hrz[BLOCK], drp[BLOCK], mur[BLOCK];
    /* results: force on i, moments on i and j, spring */
    double fx[BLOCK], fy[BLOCK], fz[BLOCK], tix[BLOCK], tiy[BLOCK], tiz[BLOCK];
    double tjx[BLOCK], tjy[BLOCK], tjz[BLOCK], sx[BLOCK], sy[BLOCK], sz[BLOCK];
    double thx[BLOCK], thy[BLOCK], thz[BLOCK]; /* rolling: the new rolling spring */
    double mrx[BLOCK], mry[BLOCK], mrz[BLOCK]; /* rolling: the rolling moment on i */
} blk;

HM_INLINE void blk_gather(const sinter_force_eval *e, const constants *k,
                          const pair_consts *single, size_t q0, size_t nb, int lean, int rolling,
                          blk *b)
/* (with `single`, the constants are not gathered: blk_law reads them from it; with `lean`,
 * nx, ny, nz take the centre difference x_j - x_i and blk_geometry forms the geometry) */
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *mass = ps->mass, *x = ps->x;
    const double *inertia = ps->inertia;
    const double *hist = e->hist_pp->committed;
    const size_t width = e->hist_pp->width;
    for (size_t a = 0; a < BLOCK; ++a) {
        /* lanes past the end repeat the last contact; their results are not used */
        const size_t q = q0 + (a < nb ? a : nb - 1);
        const uint32_t i = c->i[q], j = c->j[q];
        const double *h = hist + width * c->pair[q];
        if (lean) {
            b->nx[a] = x[3 * j] - x[3 * i];
            b->ny[a] = x[3 * j + 1] - x[3 * i + 1];
            b->nz[a] = x[3 * j + 2] - x[3 * i + 2];
        } else {
            const double *n = c->n + 3 * q;
            b->nx[a] = n[0], b->ny[a] = n[1], b->nz[a] = n[2];
            b->delta[a] = c->delta[q];
            b->li[a] = c->branch[q];
            b->lj[a] = c->dist[q] - c->branch[q];
        }
        b->ri[a] = r[i], b->rj[a] = r[j], b->mi[a] = mass[i], b->mj[a] = mass[j];
        b->dvx[a] = v[3 * i] - v[3 * j];
        b->dvy[a] = v[3 * i + 1] - v[3 * j + 1];
        b->dvz[a] = v[3 * i + 2] - v[3 * j + 2];
        b->wix[a] = w[3 * i], b->wiy[a] = w[3 * i + 1], b->wiz[a] = w[3 * i + 2];
        b->wjx[a] = w[3 * j], b->wjy[a] = w[3 * j + 1], b->wjz[a] = w[3 * j + 2];
        b->hx[a] = h[0], b->hy[a] = h[1], b->hz[a] = h[2];
        if (rolling) {
            b->ii[a] = inertia[i] + mass[i] * r[i] * r[i];
            b->ij[a] = inertia[j] + mass[j] * r[j] * r[j];
            b->hrx[a] = h[3], b->hry[a] = h[4], b->hrz[a] = h[5];
        }
        if (single == NULL) {
            pair_consts scratch;
            const pair_consts *pc = pair_of(k, e, i, j, NULL, &scratch);
            b->kn[a] = pc->kn_pre, b->dn[a] = pc->dn_pre, b->kt[a] = pc->kt_pre;
            b->dtp[a] = pc->dt_pre, b->mus2[a] = pc->mu_s2, b->mud[a] = pc->mu_d;
            if (rolling)
                b->drp[a] = pc->dr_pre, b->mur[a] = pc->mu_r;
        }
    }
}

/* A lean list's geometry from the gathered centre differences, lane by lane: the contact
 * list's own formula (sinter_pp_geometry), so the same bits as a list that carries it; and
 * the search's test of each pair (contacts.c, touching: the same arithmetic), which an
 * unconfirmed list needs (sinter_contacts_find_pp_deferred). */
HM_INLINE void blk_geometry(blk *restrict b)
{
    for (int a = 0; a < BLOCK; ++a) {
        const double ex = b->nx[a], ey = b->ny[a], ez = b->nz[a], rs = b->ri[a] + b->rj[a];
        const double d2 = ex * ex + ey * ey + ez * ez;
        b->apart[a] = ((d2 < rs * rs) & (d2 != 0.0)) ? 0.0 : 1.0;
        const sinter_pp_geom g =
            sinter_pp_geometry(b->nx[a], b->ny[a], b->nz[a], b->ri[a], b->rj[a]);
        b->nx[a] = g.nx, b->ny[a] = g.ny, b->nz[a] = g.nz;
        b->delta[a] = g.delta;
        b->li[a] = g.li;
        b->lj[a] = g.d - g.li;
    }
}

/*
 * A slider's return to its limit (eq. 13 for friction, eq. 17 for rolling), one lane: where
 * `slipping`, the trial value (vx, vy, vz) = -k s - d u scaled by `scale` to the limit, and the
 * spring s that gives it, -(g + d u) / k (0 where k = 0); elsewhere both kept. The same
 * operations as contact_law's.
 */
HM_INLINE void slider_return(int slipping, double scale, double k, double d, double ux, double uy,
                             double uz, double *vx, double *vy, double *vz, double *sx,
                             double *sy, double *sz)
{
    const int stiff = k > 0.0;
    const double inv_k = 1.0 / k; /* used only where k > 0 */
    const double gx = *vx * scale, gy = *vy * scale, gz = *vz * scale;
    const double qx = stiff ? -(gx + d * ux) * inv_k : 0.0;
    const double qy = stiff ? -(gy + d * uy) * inv_k : 0.0;
    const double qz = stiff ? -(gz + d * uz) * inv_k : 0.0;
    *vx = slipping ? gx : *vx;
    *vy = slipping ? gy : *vy;
    *vz = slipping ? gz : *vz;
    *sx = slipping ? qx : *sx;
    *sy = slipping ? qy : *sy;
    *sz = slipping ? qz : *sz;
}

/*
 * contact_law with the contact points' kinematics and the moments, lane by lane, in three
 * loops (five with `rolling`): the rare cases (a spring turned by more than ~1e-2 rad, Coulomb
 * slip, the rolling slider's limit) need a root and divisions that the common case does not,
 * so their loops run only for a block where some lane needs them; a lane that does not keeps
 * its values, as in contact_law.
 */
HM_INLINE void blk_law(blk *restrict b, double dt, const pair_consts *single, int rolling,
                       int no_tension)
{
    /* one pair of materials: the constants are the same in every lane */
#define HM_C(field, lane) (single != NULL ? single->field : b->lane[a])
    double utx[BLOCK], uty[BLOCK], utz[BLOCK], fn[BLOCK], fabs_n[BLOCK], kt[BLOCK];
    double dfric[BLOCK], ftx[BLOCK], fty[BLOCK], ftz[BLOCK], ft2[BLOCK], big_x[BLOCK];
    double slip[BLOCK]; /* 1 where the Coulomb limit is exceeded */
    double rstars[BLOCK], sqrt_rds[BLOCK]; /* for the rolling law */
    for (int a = 0; a < BLOCK; ++a) {
        const double nx = b->nx[a], ny = b->ny[a], nz = b->nz[a], li = b->li[a], lj = b->lj[a];
        const double rstar = b->ri[a] * b->rj[a] / (b->ri[a] + b->rj[a]);
        const double mstar = b->mi[a] * b->mj[a] / (b->mi[a] + b->mj[a]);
        const double sqrt_rd = sqrt(rstar * b->delta[a]);
        rstars[a] = rstar, sqrt_rds[a] = sqrt_rd;
        const double sm = sqrt(mstar * sqrt_rd);
        /* u = v_i - v_j + (L_i w_i + L_j w_j) x n */
        const double wsx = li * b->wix[a] + lj * b->wjx[a], wsy = li * b->wiy[a] + lj * b->wjy[a],
                     wsz = li * b->wiz[a] + lj * b->wjz[a];
        const double ux = b->dvx[a] + (wsy * nz - wsz * ny);
        const double uy = b->dvy[a] + (wsz * nx - wsx * nz);
        const double uz = b->dvz[a] + (wsx * ny - wsy * nx);
        const double un = ux * nx + uy * ny + uz * nz;
        fn[a] = HM_C(kn_pre, kn) * sqrt_rd * b->delta[a] + HM_C(dn_pre, dn) * sm * un;
        if (no_tension) /* a constant of each body: the default's has no such line */
            fn[a] = fn[a] > 0.0 ? fn[a] : 0.0;
        fabs_n[a] = fabs(fn[a]);
        utx[a] = ux - un * nx, uty[a] = uy - un * ny, utz[a] = uz - un * nz;
        kt[a] = HM_C(kt_pre, kt) * sqrt_rd;
        dfric[a] = HM_C(dt_pre, dtp) * sm;
        double sx = b->hx[a], sy = b->hy[a], sz = b->hz[a];
        /* spring turned into the tangent plane, its length kept (contact_law) */
        const double sn = sx * nx + sy * ny + sz * nz;
        const double px = sx - sn * nx, py = sy - sn * ny, pz = sz - sn * nz;
        const double len1_2 = px * px + py * py + pz * pz;
        const double x = sn * sn / len1_2;
        const int turn = sn != 0.0, rescale = turn & (len1_2 > 0.0);
        /* x 1.0 is exact: no rescale keeps the value's bits; x >= 1e-4 is fixed below */
        const double scl = rescale ? 1.0 + x * (0.5 - 0.125 * x) : 1.0;
        big_x[a] = (rescale & !(x < 1e-4)) ? x : 0.0;
        b->sx[a] = (turn ? px : sx) * scl; /* the turned spring, before the increment */
        b->sy[a] = (turn ? py : sy) * scl;
        b->sz[a] = (turn ? pz : sz) * scl;
        b->hx[a] = turn ? px : sx; /* kept for the rare rescale */
        b->hy[a] = turn ? py : sy;
        b->hz[a] = turn ? pz : sz;
    }
    int rare = 0;
    for (int a = 0; a < BLOCK; ++a)
        rare |= big_x[a] != 0.0;
    if (rare)
        for (int a = 0; a < BLOCK; ++a) {
            const double root = sqrt(1.0 + big_x[a]);
            const int use = big_x[a] != 0.0;
            b->sx[a] = use ? b->hx[a] * root : b->sx[a];
            b->sy[a] = use ? b->hy[a] * root : b->sy[a];
            b->sz[a] = use ? b->hz[a] * root : b->sz[a];
        }
    for (int a = 0; a < BLOCK; ++a) {
        const double sx = b->sx[a] + utx[a] * dt, sy = b->sy[a] + uty[a] * dt,
                     sz = b->sz[a] + utz[a] * dt;
        b->sx[a] = sx, b->sy[a] = sy, b->sz[a] = sz;
        ftx[a] = -kt[a] * sx - dfric[a] * utx[a];
        fty[a] = -kt[a] * sy - dfric[a] * uty[a];
        ftz[a] = -kt[a] * sz - dfric[a] * utz[a];
        ft2[a] = ftx[a] * ftx[a] + fty[a] * fty[a] + ftz[a] * ftz[a];
        slip[a] = ((ft2[a] > HM_C(mu_s2, mus2) * fabs_n[a] * fabs_n[a]) & (ft2[a] > 0.0)) ? 1.0 : 0.0;
    }
    int slips = 0;
    for (int a = 0; a < BLOCK; ++a)
        slips |= slip[a] != 0.0;
    if (slips) /* Slip (eq. 8, 13) */
        for (int a = 0; a < BLOCK; ++a)
            slider_return(slip[a] != 0.0, HM_C(mu_d, mud) * fabs_n[a] / sqrt(ft2[a]), kt[a],
                          dfric[a], utx[a], uty[a], utz[a], &ftx[a], &fty[a], &ftz[a], &b->sx[a],
                          &b->sy[a], &b->sz[a]);
    /* Rolling resistance (eq. 15-20): the moment on i, mr (-mr on j), and the new spring */
    double *restrict mrx = b->mrx, *restrict mry = b->mry, *restrict mrz = b->mrz;
    if (rolling) {
        double wrx[BLOCK], wry[BLOCK], wrz[BLOCK], kr[BLOCK], drol[BLOCK], mlen[BLOCK];
        double lim[BLOCK], rslip[BLOCK];
        for (int a = 0; a < BLOCK; ++a) {
            const double rstar = rstars[a];
            const double jstar = 1.0 / (1.0 / b->ii[a] + 1.0 / b->ij[a]); /* eq. 18 */
            wrx[a] = b->wix[a] - b->wjx[a], wry[a] = b->wiy[a] - b->wjy[a];
            wrz[a] = b->wiz[a] - b->wjz[a];
            const double thx = b->hrx[a] + wrx[a] * dt, thy = b->hry[a] + wry[a] * dt,
                         thz = b->hrz[a] + wrz[a] * dt;
            kr[a] = kt[a] * rstar * rstar;
            /* d_rol = 2 xi_r sqrt(8 G* J*) r* (r* delta)^(1/4) = dr_pre sqrt(J* s) r* */
            drol[a] = HM_C(dr_pre, drp) * sqrt(jstar * sqrt_rds[a]) * rstar;
            mrx[a] = -kr[a] * thx - drol[a] * wrx[a];
            mry[a] = -kr[a] * thy - drol[a] * wry[a];
            mrz[a] = -kr[a] * thz - drol[a] * wrz[a];
            b->thx[a] = thx, b->thy[a] = thy, b->thz[a] = thz;
            mlen[a] = sqrt(mrx[a] * mrx[a] + mry[a] * mry[a] + mrz[a] * mrz[a]);
            lim[a] = HM_C(mu_r, mur) * rstar * fabs_n[a];
            rslip[a] = ((mlen[a] > lim[a]) & (mlen[a] > 0.0)) ? 1.0 : 0.0;
        }
        int rolls = 0;
        for (int a = 0; a < BLOCK; ++a)
            rolls |= rslip[a] != 0.0;
        if (rolls) /* the slider's limit mu_r r* |f_n| (eq. 17) */
            for (int a = 0; a < BLOCK; ++a)
                slider_return(rslip[a] != 0.0, lim[a] / mlen[a], kr[a], drol[a], wrx[a], wry[a],
                              wrz[a], &mrx[a], &mry[a], &mrz[a], &b->thx[a], &b->thy[a],
                              &b->thz[a]);
    }
    for (int a = 0; a < BLOCK; ++a) {
        const double nx = b->nx[a], ny = b->ny[a], nz = b->nz[a];
        const double fx = ftx[a] - fn[a] * nx, fy = fty[a] - fn[a] * ny, fz = ftz[a] - fn[a] * nz;
        b->fx[a] = fx, b->fy[a] = fy, b->fz[a] = fz;
        /* moments (eq. 14): L_i (n x f) on i, L_j (n x f) on j; rolling: + mr on i, - mr on j */
        const double mx = ny * fz - nz * fy, my = nz * fx - nx * fz, mz = nx * fy - ny * fx;
        if (rolling) {
            b->tix[a] = b->li[a] * mx + mrx[a], b->tiy[a] = b->li[a] * my + mry[a];
            b->tiz[a] = b->li[a] * mz + mrz[a];
            b->tjx[a] = b->lj[a] * mx - mrx[a], b->tjy[a] = b->lj[a] * my - mry[a];
            b->tjz[a] = b->lj[a] * mz - mrz[a];
        } else {
            b->tix[a] = b->li[a] * mx, b->tiy[a] = b->li[a] * my, b->tiz[a] = b->li[a] * mz;
            b->tjx[a] = b->lj[a] * mx, b->tjy[a] = b->lj[a] * my, b->tjz[a] = b->lj[a] * mz;
        }
    }
#undef HM_C
}

#define PP_BLOCKS pp_blocks_printed
#define PP_NO_TENSION 0
#include "hertz_blocks.inc"
#undef PP_BLOCKS
#undef PP_NO_TENSION
#define PP_BLOCKS pp_blocks_clamped
#define PP_NO_TENSION 1
#include "hertz_blocks.inc"
#undef PP_BLOCKS
#undef PP_NO_TENSION

/* The default's blocks (the law as printed) or the clamped law's ("no_tension"). */
HM_INLINE size_t pp_blocks(const sinter_force_eval *e, const constants *k,
                           const pair_consts *single, int rolling, size_t lo, size_t hi,
                           const sinter_chunks *ch, int s, uint32_t *bq, double *bout,
                           double *bmr, uint32_t *reach, size_t *ended)
{
    if (k->no_tension)
        return pp_blocks_clamped(e, k, single, rolling, lo, hi, ch, s, bq, bout, bmr, reach,
                                 ended);
    return pp_blocks_printed(e, k, single, rolling, lo, hi, ch, s, bq, bout, bmr, reach, ended);
}

/* Wall contacts: constants per (wall, material row) built once when they fit here. */
enum { MAX_WALL_TABLE = 64, MAX_THREADED_WALLS = 16 };

/*
 * The wall contacts' work for one evaluation: the constants, and the runs of the list that
 * never split a particle's contacts, by preference those of the pair partition's particle
 * ranges (chunks.h, sinter_chunks_wall_plan: each thread the particles it added the pair
 * forces into, at any size); each run sums its own wall reactions into `partial`, added to
 * the walls' in run order afterwards. The runs depend on the lists only: the same bits for
 * any thread count.
 */
typedef struct wall_job {
    size_t nw;
    int cached;
    pair_consts table[MAX_WALL_TABLE];
    int plain;   /* no wall spins or wants its moment (pw_range: wall_moment NULL) */
    int runs;    /* 0: one pass over the list, on one thread */
    int aligned; /* the runs are the pair partition's ranges */
    size_t qlo[SINTER_CHUNKS_MAX + 1];
    double partial[SINTER_CHUNKS_MAX][6 * MAX_THREADED_WALLS]; /* forces, then moments */
} wall_job;

static void plan_walls(const sinter_force_eval *e, const constants *k, wall_job *job)
{
    const sinter_contact_list *c = e->pw;
    const size_t nw = e->walls->count;
    job->nw = nw;
    job->cached = !k->softening && k->rows > 0 && nw * (size_t)k->rows <= MAX_WALL_TABLE;
    if (job->cached)
        for (size_t wall_index = 0; wall_index < nw; ++wall_index) {
            side sw;
            side_from_material(&e->walls->wall[wall_index].material, 1.0, &sw);
            for (int a = 0; a < k->rows; ++a)
                mix(&k->sides[a], &sw, &job->table[wall_index * (size_t)k->rows + (size_t)a]);
        }
    job->plain = 1;
    for (size_t wall_index = 0; wall_index < nw; ++wall_index)
        job->plain &=
            e->walls->wall[wall_index].spin == 0.0 && !e->walls->wall[wall_index].moment_wanted;
    job->runs = sinter_chunks_wall_plan(&e->pp->chunks, c, job->qlo, &job->aligned);
    if (nw > MAX_THREADED_WALLS)
        job->runs = job->aligned = 0;
}

static void pw_run(const sinter_force_eval *e, const constants *k, wall_job *job, int s,
                   int rolling);

/* Force of contact q (out, from pp_blocks) with the moments L (n x f) formed again as
 * blk_law forms them, and the rolling moment mr (NULL: none): added to particle p, first or
 * second of the contact. A lean list's geometry is formed again as blk_geometry forms it. */
static inline void add_from_force(const sinter_contact_list *c, const sinter_particles *ps,
                                  size_t q, const double *o, const double *mr, int first,
                                  double f[3], double t[3])
{
    double n[3], li, lj;
    if (c->geometry) {
        n[0] = c->n[3 * q], n[1] = c->n[3 * q + 1], n[2] = c->n[3 * q + 2];
        li = c->branch[q];
        lj = c->dist[q] - c->branch[q];
    } else {
        const double *x = ps->x, *r = ps->radius;
        const uint32_t i = c->i[q], j = c->j[q];
        const sinter_pp_geom g =
            sinter_pp_geometry(x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                               x[3 * j + 2] - x[3 * i + 2], r[i], r[j]);
        n[0] = g.nx, n[1] = g.ny, n[2] = g.nz;
        li = g.li;
        lj = g.d - g.li;
    }
    const double m[3] = {n[1] * o[2] - n[2] * o[1], n[2] * o[0] - n[0] * o[2],
                         n[0] * o[1] - n[1] * o[0]};
    const double l = first ? li : lj;
    for (int d = 0; d < 3; ++d) {
        f[d] = first ? f[d] + o[d] : f[d] - o[d];
        if (mr == NULL)
            t[d] += l * m[d];
        else /* with the rolling moment, + mr on i and - mr on j, as blk_law adds it */
            t[d] += first ? l * m[d] + mr[d] : l * m[d] - mr[d];
    }
}

/* One evaluation of a partitioned list (pp_chunked): what each range's passes read and
 * write. */
typedef struct law_job {
    const sinter_force_eval *e;
    const constants *k;
    const pair_consts *single;
    int rolling, final;
    wall_job *walls;
    const sinter_chunks *ch;
    uint32_t *bq; /* boundary contacts, at each range's own contact offset */
    double *bout; /* their forces, 3 each */
    double *bmr;  /* their rolling moments, 3 each (rolling only) */
    size_t boundary[SINTER_CHUNKS_MAX], first_ended[SINTER_CHUNKS_MAX];
    uint32_t reach[SINTER_CHUNKS_MAX];
    sinter_range_flags interior_done;
} law_job;

/* Range s's interior pass: its interior contacts added, its boundary contacts kept in list
 * order; then marked done (without waiting for anything), and with `final`
 * e->range_interior_done. */
static void range_interior(law_job *j, int s)
{
    const sinter_chunks *ch = j->ch;
    const size_t q = ch->qlo[s];
    j->first_ended[s] = SIZE_MAX;
    j->boundary[s] = pp_blocks(j->e, j->k, j->single, j->rolling, q, ch->qlo[s + 1], ch, s,
                               j->bq + q, j->bout + 3 * q, j->rolling ? j->bmr + 3 * q : NULL,
                               &j->reach[s], &j->first_ended[s]);
    sinter_range_flags_set(&j->interior_done, s);
    if (j->final && j->e->range_interior_done != NULL)
        j->e->range_interior_done(j->e->range_user, s);
}

/*
 * Range r's particles made final: the boundary contacts, in list order, by the range that
 * holds each particle (a particle receives them in the order one pass over the list gives,
 * and no two ranges add into the same particle), then the range's wall contacts (`walls`:
 * runs aligned with the ranges), as in two evaluations one after the other, then
 * e->range_final (`final`). Waits for the interior pass of ranges 0 .. r only, not for a
 * barrier: theirs are the only boundary contacts that reach r (a contact's smaller particle
 * index is in its range), and their interior passes are the only other ones that read or
 * write r's particles (which range_final may then write).
 */
static void range_rest(law_job *j, int r)
{
    const sinter_force_eval *e = j->e;
    const sinter_contact_list *c = e->pp;
    const sinter_chunks *ch = j->ch;
    double *force = e->force, *torque = e->torque;
    const size_t lo = ch->plo[r], hi = ch->plo[r + 1];
    sinter_range_flags_wait_below(&j->interior_done, r + 1);
    /* a range's contacts have their smaller particle index in it: later ranges touch none of
     * r's; nor do those whose boundary contacts reach no index of r */
    for (int s = 0; s <= r; ++s) {
        if (j->reach[s] <= lo)
            continue;
        for (size_t b = ch->qlo[s]; b < ch->qlo[s] + j->boundary[s]; ++b) {
            const size_t q = j->bq[b];
            const uint32_t ij[2] = {c->i[q], c->j[q]};
            for (int end = 0; end < 2; ++end) {
                const uint32_t p = ij[end];
                if (p < lo || p >= hi)
                    continue;
                double f[3] = {force[3 * p], force[3 * p + 1], force[3 * p + 2]};
                double t[3] = {torque[3 * p], torque[3 * p + 1], torque[3 * p + 2]};
                add_from_force(c, e->ps, q, j->bout + 3 * b, j->rolling ? j->bmr + 3 * b : NULL,
                               end == 0, f, t);
                for (int d = 0; d < 3; ++d)
                    force[3 * p + d] = f[d], torque[3 * p + d] = t[d];
            }
        }
    }
    if (j->walls != NULL)
        pw_run(e, j->k, j->walls, r, j->rolling);
    if (j->final) /* r's interior and boundary contacts and walls are all in */
        e->range_final(e->range_user, r, lo, hi);
}

/* The two passes of pp_chunked, for sinter_ranges_run_two_passes. */
static void interior_of(void *job, int s)
{
    range_interior(job, s);
}

static void rest_of(void *job, int r)
{
    range_rest(job, r);
}

/*
 * A partitioned list (contact/chunks.h): the ranges of a fixed partition in parallel, each
 * adding its interior contacts, then the boundary contacts in list order. The partition
 * depends on the list only, and each range's sums do not depend on the thread that makes
 * them, so any number of threads (one too) gives the same bits. With `final`,
 * e->range_final for each range at the end of the region.
 *
 * Which thread runs a range: with as many ranges as threads (a list under about 64k pairs),
 * range r is thread r's in both loops (the static schedule; on one thread too), as it is in
 * the integrator's passes, so that a range's lines stay on one core. With more ranges than
 * threads they go to whichever thread is free (dynamic schedule): on the project's VMs one
 * core is often slower than the other for seconds, and the faster one then takes more ranges
 * (RESULTS.md, issue 9, session 19: 512k bed, law 10-15 % shorter on two threads). No wait
 * can hang: a thread reaches the second loop only after the first has handed out every
 * range, and an interior pass waits for nothing.
 */
static sinter_status pp_chunked(const sinter_force_eval *e, const constants *k,
                                const pair_consts *single, int rolling, size_t *ended,
                                wall_job *walls, int final)
{
    const sinter_contact_list *c = e->pp;
    const int threads = sinter_threads(e->ctx);
    const sinter_chunks ch = c->chunks;
    law_job job = {.e = e,
                   .k = k,
                   .single = single,
                   .rolling = rolling,
                   .final = final,
                   .walls = walls,
                   .ch = &ch};
    /* room for every contact to be a boundary one (the list's scratch), and for their rolling
     * moments */
    job.bout = c->chunk_scratch;
    job.bq = (uint32_t *)(job.bout + 3 * c->count);
    if (rolling) {
        job.bmr = sinter_alloc(e->ctx, (3 * c->count + 1) * sizeof(double));
        if (job.bmr == NULL)
            return SINTER_ERR_NOMEM;
    }
    sinter_range_flags_clear(&job.interior_done, ch.count);
    sinter_ranges_run_two_passes(threads, ch.count, interior_of, rest_of, &job);
    for (int s = 0; s < ch.count; ++s)
        *ended = job.first_ended[s] < *ended ? job.first_ended[s] : *ended;
    sinter_free(e->ctx, job.bmr);
    return SINTER_OK;
}

/* Pair contacts; with `walls` (a partitioned list, wall runs aligned with its ranges) the wall
 * contacts too, in the same parallel region (pp_chunked). */
static sinter_status eval_pp(const sinter_force_eval *e, const constants *k, int rolling,
                             size_t *ended, wall_job *walls, int final)
{
    const sinter_contact_list *c = e->pp;
    const pair_consts *single = !k->softening && k->rows == 1 ? &k->table[0] : NULL;
    if (c->chunks.count > 0)
        return pp_chunked(e, k, single, rolling, ended, walls, final);
    /* Without a partition (a list of fewer than 2048 pairs): one thread, in list order. */
    (void)pp_blocks(e, k, single, rolling, 0, c->count, NULL, 0, NULL, NULL, NULL, NULL, ended);
    return SINTER_OK;
}

/* Wall contacts [lo, hi) in list order: forces and moments into the particles, reactions into
 * wall_force and wall_moment (3 per wall; moments NULL: not wanted). The wall's velocity is
 * its surface's at the contact point (its spin: sinter_wall_velocity_at). */
HM_INLINE void pw_range(const sinter_force_eval *e, const constants *k, const pair_consts *table,
                        int cached, int rolling, size_t lo, size_t hi, double *wall_force,
                        double *wall_moment, int no_tension, double *reaction)
/* (wall_moment NULL where called: no wall spins or wants its moment, and the loop tests
 * neither; reaction: sinter_force_eval.pw_reaction, NULL (a constant) on the plain path) */
{
    const sinter_particles *ps = e->ps;
    const double *x = ps->x;
    const sinter_contact_list *c = e->pw;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *mass = ps->mass,
                 *inertia = ps->inertia;
    const size_t width = e->hist_pw->width;
    const double *hist = e->hist_pw->committed;
    double *trial = e->hist_pw->trial;
    for (size_t q = lo; q < hi; ++q) {
        const uint32_t i = c->i[q], wall_index = c->j[q];
        const sinter_wall *wall = &e->walls->wall[wall_index];
        const double *n = c->n + 3 * q;
        const double li = c->branch[q];
        pair_consts consts;
        const int row = k->index[ps->material[i]];
        const pair_consts *pc = &consts;
        if (cached && row >= 0) {
            pc = &table[wall_index * (size_t)k->rows + (size_t)row];
        } else {
            side si, sw;
            side_from_material(&ps->materials[ps->material[i]],
                               k->softening ? e->modulus_scale[i] : 1.0, &si);
            side_from_material(&wall->material, 1.0, &sw);
            mix(&si, &sw, &consts);
        }
        pair_props p = {pc, r[i], mass[i], inertia[i] + mass[i] * r[i] * r[i]};
        const double bi[3] = {li * n[0], li * n[1], li * n[2]};
        double wi_b[3];
        v3_cross(w + 3 * i, bi, wi_b);
        const double *uw = wall->u;
        double spun[3];
        if (wall_moment != NULL && wall->spin != 0.0) {
            const double at[3] = {x[3 * i] + bi[0], x[3 * i + 1] + bi[1], x[3 * i + 2] + bi[2]};
            sinter_wall_velocity_at(wall, at, spun);
            uw = spun;
        }
        double u[3];
        for (int d = 0; d < 3; ++d)
            u[d] = v[3 * i + d] + wi_b[d] - uw[d];
        double f[3], mr[3], ti[3], sqrt_rd, sm;
        roots(p.rstar, p.mstar, c->delta[q], &sqrt_rd, &sm);
        contact_law(&p, n, c->delta[q], sqrt_rd, sm, u, w + 3 * i, e->dt,
                    hist + width * (size_t)c->pair[q],
                    trial + width * (e->hist_pw->by_pair ? (size_t)c->pair[q] : q), rolling,
                    no_tension, f, mr, NULL);
        if (!rolling && width == 6) /* a rolling spring no material uses: held at zero */
            for (int d = 3; d < 6; ++d)
                trial[width * (e->hist_pw->by_pair ? (size_t)c->pair[q] : q) + (size_t)d] = 0.0;
        v3_cross(bi, f, ti);
        for (int d = 0; d < 3; ++d) {
            e->force[3 * i + d] += f[d];
            e->torque[3 * i + d] += ti[d] + mr[d];
            wall_force[3 * wall_index + d] -= f[d];
        }
        if (reaction != NULL) /* (the reproducible mode: each contact's own) */
            for (int d = 0; d < 3; ++d)
                reaction[6 * q + (size_t)d] -= f[d];
        if (wall_moment != NULL && wall->moment_wanted) {
            const double at[3] = {x[3 * i] + bi[0], x[3 * i + 1] + bi[1], x[3 * i + 2] + bi[2]};
            sinter_wall_add_moment(wall, at, f, mr, wall_moment + 3 * wall_index);
            if (reaction != NULL)
                sinter_wall_add_moment(wall, at, f, mr, reaction + 6 * q + 3);
        }
    }
}

/* pw_range with no moments (NULL, a constant: no wall spins or wants its moment). */
static void pw_plain(const sinter_force_eval *e, const constants *k, const wall_job *job,
                     int rolling, size_t lo, size_t hi, double *wall_force)
{
    if (k->no_tension)
        pw_range(e, k, job->table, job->cached, rolling, lo, hi, wall_force, NULL, 1, NULL);
    else if (rolling)
        pw_range(e, k, job->table, job->cached, 1, lo, hi, wall_force, NULL, 0, NULL);
    else
        pw_range(e, k, job->table, job->cached, 0, lo, hi, wall_force, NULL, 0, NULL);
}

/* Run s of a wall job, its reactions into the run's partial sums. */
static void pw_run(const sinter_force_eval *e, const constants *k, wall_job *job, int s,
                   int rolling)
{
    for (size_t d = 0; d < 6 * job->nw; ++d)
        job->partial[s][d] = 0.0;
    const size_t lo = job->qlo[s], hi = job->qlo[s + 1];
    double *wf = job->partial[s], *wm = e->wall_moment ? wf + 3 * job->nw : NULL;
    double *re = e->pw_reaction; /* (the reproducible mode: the general loop) */
    if (job->plain && re == NULL) /* the planes' loop without a spin's or a moment's test */
        pw_plain(e, k, job, rolling, lo, hi, wf);
    else if (k->no_tension)
        pw_range(e, k, job->table, job->cached, rolling, lo, hi, wf, wm, 1, re);
    else if (rolling)
        pw_range(e, k, job->table, job->cached, 1, lo, hi, wf, wm, 0, re);
    else
        pw_range(e, k, job->table, job->cached, 0, lo, hi, wf, wm, 0, re);
}

/* The wall contacts by the job's plan (plan_walls); `done`: its runs were evaluated already
 * (with the pair contacts), only their reactions are left to add. */
static void eval_pw(const sinter_force_eval *e, const constants *k, int rolling, wall_job *job,
                    int done)
{
    const sinter_contact_list *c = e->pw;
    const int runs = job->runs;
    if (runs == 0) {
        double *wf = e->wall_force, *wm = e->wall_moment, *re = e->pw_reaction;
        if (job->plain && re == NULL)
            pw_plain(e, k, job, rolling, 0, c->count, wf);
        else if (k->no_tension)
            pw_range(e, k, job->table, job->cached, rolling, 0, c->count, wf, wm, 1, re);
        else if (rolling)
            pw_range(e, k, job->table, job->cached, 1, 0, c->count, wf, wm, 0, re);
        else
            pw_range(e, k, job->table, job->cached, 0, 0, c->count, wf, wm, 0, re);
        return;
    }
    if (!done) {
        const int threads = sinter_threads(e->ctx), team = threads < runs ? threads : runs;
        if (team > 1) {
#pragma omp parallel for num_threads(team) schedule(static)
            for (int s = 0; s < runs; ++s)
                pw_run(e, k, job, s, rolling);
        } else { /* a region of one thread costs a team (core/ranges_run.h) */
            for (int s = 0; s < runs; ++s)
                pw_run(e, k, job, s, rolling);
        }
    }
    for (int s = 0; s < runs; ++s) {
        for (size_t d = 0; d < 3 * job->nw; ++d)
            e->wall_force[d] += job->partial[s][d];
        for (size_t d = 0; e->wall_moment != NULL && d < 3 * job->nw; ++d)
            e->wall_moment[d] += job->partial[s][3 * job->nw + d];
    }
}

static sinter_status hertz_mindlin_eval(const sinter_force_model *fm, sinter_force_eval *e)
{
    /* Trial history by pair (see sinter_history_by_pair): committed by a swap, not a copy. */
    sinter_status hs = sinter_history_by_pair(e->ctx, e->hist_pp, e->pp);
    if (hs == SINTER_OK && e->walls != NULL)
        hs = sinter_history_by_pair(e->ctx, e->hist_pw, e->pw);
    if (hs != SINTER_OK)
        return hs;
    /* Rolling needs the 6-wide history chosen when the model was added to the stepper, and a
     * material in use with rolling friction: without one the rolling moment is 0 (mu_r = 0 is
     * the slip limit of eq. 17) and the blocked law without rolling serves (the rolling spring
     * is then held at zero, as in a new contact) */
    constants k;
    build_constants(e, &k);
    k.no_tension = fm->param[PARAM_NO_TENSION] != 0.0;
    const int rolling = fm->param[PARAM_ROLLING] != 0.0 && e->hist_pp->width == 6 && k.any_rolling;
    e->pp_ended = SIZE_MAX;
    /* the wall contacts with the pair contacts, in one parallel region, when their runs are
     * the pair partition's ranges (one fork and join fewer per step: a 1k bed's step takes
     * 60-75 us on two threads, each region 1-2 us) */
    wall_job walls;
    if (e->walls != NULL)
        plan_walls(e, &k, &walls);
    const int with_pairs = e->walls != NULL && walls.aligned; /* aligned: partitioned */
    /* the forces are final by ranges in pp_chunked's region when every wall contact is
     * evaluated there too (eval_pp takes it on a partitioned list) */
    const int final =
        e->range_final != NULL && e->pp->chunks.count > 0 && (e->walls == NULL || with_pairs);
    sinter_status st = eval_pp(e, &k, rolling, &e->pp_ended, with_pairs ? &walls : NULL, final);
    e->ranges_final = final && st == SINTER_OK;
    if (st == SINTER_OK && e->walls != NULL)
        eval_pw(e, &k, rolling, &walls, with_pairs);
    return st;
}

/*
 * The power each contact dissipates in the state of the last evaluation (issue 40: heat from
 * friction and inelastic impacts, heat/dissipation.c), into power[2 i] (the normal damper) and
 * power[2 i + 1] (Coulomb sliding), added: the law is evaluated again from the committed
 * history, as the evaluation did (contact_law), and gives
 *   normal: (f_n - f_elastic) delta_dot, f_elastic = 4/3 E* sqrt(r* delta) delta (eq. 2): the
 *     damper's force times the overlap rate, >= 0 (with "no_tension" the clamped force's
 *     difference from the elastic one, again >= 0);
 *   sliding: |f_t . u_t| where the contact slips (eq. 8), the Coulomb force times the slip
 *     velocity of the contact points (the usual DEM convention; the tangential damper while
 *     sticking, the springs' stored energy and the rolling slider are not counted).
 * A pair contact gives half to each particle, a wall contact all to its particle. Needs the
 * pair list's geometry (sinter_contacts_geometry) and a confirmed list.
 */
static sinter_status hertz_mindlin_dissipation(const sinter_force_model *fm,
                                               const sinter_force_eval *e, double *power)
{
    constants k;
    build_constants(e, &k);
    const int no_tension = fm->param[PARAM_NO_TENSION] != 0.0;
    const sinter_particles *ps = e->ps;
    const double *v = ps->v, *w = ps->w, *r = ps->radius, *mass = ps->mass;
    const double *inertia = ps->inertia;
    const sinter_contact_list *c = e->pp;
    double trial[6], f[3], mr[3], pw2[2];
    for (size_t q = 0; q < c->count && c->geometry; ++q) {
        const uint32_t i = c->i[q], j = c->j[q];
        const double *n = c->n + 3 * q, li = c->branch[q], lj = c->dist[q] - c->branch[q];
        pair_consts scratch;
        const pair_consts *pc = pair_of(&k, e, i, j, NULL, &scratch);
        const double ii = inertia[i] + mass[i] * r[i] * r[i];
        const double ij = inertia[j] + mass[j] * r[j] * r[j];
        const pair_props p = {pc, r[i] * r[j] / (r[i] + r[j]),
                              mass[i] * mass[j] / (mass[i] + mass[j]), 1.0 / (1.0 / ii + 1.0 / ij)};
        double ws[3], wsn[3], u[3], wrel[3], sqrt_rd, sm;
        for (int d = 0; d < 3; ++d) {
            ws[d] = li * w[3 * i + d] + lj * w[3 * j + d];
            wrel[d] = w[3 * i + d] - w[3 * j + d];
        }
        v3_cross(ws, n, wsn);
        for (int d = 0; d < 3; ++d)
            u[d] = v[3 * i + d] - v[3 * j + d] + wsn[d];
        roots(p.rstar, p.mstar, c->delta[q], &sqrt_rd, &sm);
        contact_law(&p, n, c->delta[q], sqrt_rd, sm, u, wrel, e->dt,
                    e->hist_pp->committed + e->hist_pp->width * (size_t)c->pair[q], trial, 0,
                    no_tension, f, mr, pw2);
        for (int d = 0; d < 2; ++d) {
            power[2 * (size_t)i + (size_t)d] += 0.5 * pw2[d];
            power[2 * (size_t)j + (size_t)d] += 0.5 * pw2[d];
        }
    }
    const sinter_contact_list *cw = e->pw;
    for (size_t q = 0; e->walls != NULL && q < cw->count; ++q) {
        const uint32_t i = cw->i[q];
        const sinter_wall *wall = &e->walls->wall[cw->j[q]];
        const double *n = cw->n + 3 * q, li = cw->branch[q];
        side si, sw;
        side_from_material(&ps->materials[ps->material[i]], k.softening ? e->modulus_scale[i] : 1.0,
                           &si);
        side_from_material(&wall->material, 1.0, &sw);
        pair_consts pc;
        mix(&si, &sw, &pc);
        const pair_props p = {&pc, r[i], mass[i], inertia[i] + mass[i] * r[i] * r[i]};
        const double bi[3] = {li * n[0], li * n[1], li * n[2]};
        double wi_b[3], uw[3], u[3], sqrt_rd, sm;
        v3_cross(w + 3 * i, bi, wi_b);
        if (wall->spin != 0.0) {
            const double at[3] = {ps->x[3 * i] + bi[0], ps->x[3 * i + 1] + bi[1],
                                  ps->x[3 * i + 2] + bi[2]};
            sinter_wall_velocity_at(wall, at, uw);
        } else {
            uw[0] = wall->u[0], uw[1] = wall->u[1], uw[2] = wall->u[2];
        }
        for (int d = 0; d < 3; ++d)
            u[d] = v[3 * i + d] + wi_b[d] - uw[d];
        roots(p.rstar, p.mstar, cw->delta[q], &sqrt_rd, &sm);
        contact_law(&p, n, cw->delta[q], sqrt_rd, sm, u, w + 3 * i, e->dt,
                    e->hist_pw->committed + e->hist_pw->width * (size_t)cw->pair[q], trial, 0,
                    no_tension, f, mr, pw2);
        power[2 * (size_t)i] += pw2[0];
        power[2 * (size_t)i + 1] += pw2[1];
    }
    return SINTER_OK;
}

/* Delta x (3) always; Delta theta (3) only with rolling resistance. */
static size_t hertz_mindlin_history(const sinter_force_model *fm, int wall)
{
    (void)wall;
    return fm->param[PARAM_ROLLING] != 0.0 ? 6 : 3;
}

/* The blocked law forms the geometry from the centres (blk_geometry) ... */
static int hertz_mindlin_reads_geometry(const sinter_force_model *fm, size_t width)
{
    (void)fm;
    (void)width;
    return 0;
}

/* ... and tests each contact as the search does, skipping ended ones. */
static int hertz_mindlin_confirms_contacts(const sinter_force_model *fm, size_t width)
{
    (void)fm;
    (void)width;
    return 1;
}

const sinter_force_ops sinter_force_hertz_mindlin = {
    .name = "hertz_mindlin",
    .history_pp = 6,
    .history_pw = 6,
    .uses_contacts = 1,
    .keys = {"rolling", "no_tension", NULL},
    .defaults = {1.0, 0.0},
    .eval = hertz_mindlin_eval,
    .history_width = hertz_mindlin_history,
    .reads_geometry = hertz_mindlin_reads_geometry,
    .confirms_contacts = hertz_mindlin_confirms_contacts,
    .dissipation = hertz_mindlin_dissipation,
};
