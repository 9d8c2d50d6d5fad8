/*
 * External heating by a ray-traced beam ("beam"): any direction, a top-hat or Gaussian
 * profile, absorption along each ray through the particles it crosses, with shadowing, so
 * that the power absorbed by the particles plus the power that leaves past the last one is
 * the beam's power.
 *
 * The beam: the axis through ("x", "y", "z") along ("dx", "dy", "dz") (normalised here), total
 * power "power" P [W], radius "radius" R [m]. Profile ("profile"): 0 top hat, I uniform over
 * the disc of radius R; 1 Gaussian I(rho) proportional to exp(-2 rho^2 / R^2) (R the 1/e^2
 * radius), truncated at 2 R (1 - e^-8 = 99.97 % of an untruncated beam's power; the rays
 * carry all of P). The cross-section is cut into a square grid of "rays" x "rays" cells over
 * the disc's bounding square; each cell whose centre is inside the disc is one ray, starting
 * in the plane through the axis point normal to the direction, with the power
 * P I(rho_k) / sum_k I(rho_k) (so the rays carry exactly P).
 *
 * Along a ray: the spheres it crosses in front of its start, in the order it enters them
 * (ties by particle index; by id across subdomains); a sphere of absorptance a (its material's)
 * crossed along a chord L absorbs the fraction a (1 - exp(-mu L)) of the power that reaches it, mu
 * = "attenuation" [1/m] (the default 1e9 makes particles opaque: the fraction a); the rest goes on
 * along the ray (what a sphere does not absorb is read as scattered forward). Whatever is left
 * after the last sphere is transmitted. Overlapping spheres are crossed each along its whole chord.
 * Walls absorb nothing.
 *
 * Outputs of the last evaluation (sinter_heat_model_output): "absorbed" and "transmitted"
 * [W] (their sum is P to round-off), "lit" (the number of particles that absorbed power) and
 * "lit_temperature" (their mean temperature [K], 0 when none). Each particle that absorbed power
 * is marked SINTER_PARTICLE_LIT (never cleared), as by the laser and nozzle (beam.c).
 *
 * Cost: one pass over the particles for the candidates (centre within R_beam + r of the axis,
 * in front of the start), then rays x candidates ray-sphere tests, on one thread (the sums in
 * one fixed order: the same bits on any thread count).
 *
 * Across subdomains (issue 43): a ray's shadows cross borders, so every subdomain gathers
 * every subdomain's candidates (sinter_domain_allgather: 7 doubles each, three collective
 * calls an evaluation), orders them by id and traces every ray through all of them; each
 * keeps the power of its owned particles. Every subdomain traces the same candidates in the
 * same order, so the powers and the outputs are the bits of one domain whose particles'
 * indices follow their ids (a scene's), whatever the decomposition.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "domain/domain.h"
#include "heat_model.h"
#include "particles/particles.h"

enum { B_X = 0, B_Y, B_Z, B_DX, B_DY, B_DZ, B_RADIUS, B_POWER, B_PROFILE, B_ATTENUATION, B_RAYS };

typedef struct hit {
    double t, chord;
    size_t q; /* the candidate */
} hit;

/* A candidate's record: x, y, z, r, absorptance, temperature, id (its bits). */
enum { CW = 7 };

/* The candidates the rays are traced through: this subdomain's, or every subdomain's
 * (this one's from record `first`). */
typedef struct candidates {
    double *row; /* CW doubles each */
    size_t count, first;
} candidates;

static uint64_t id_of(const candidates *cs, size_t q)
{
    uint64_t id;
    memcpy(&id, cs->row + CW * q + 6, sizeof(id));
    return id;
}

typedef struct keyed {
    uint64_t id;
    size_t q;
} keyed;

static int by_id(const void *a, const void *b)
{
    const uint64_t x = ((const keyed *)a)->id, y = ((const keyed *)b)->id;
    return (x > y) - (x < y);
}

/* order[] = the candidates in ascending id (ids are unique across subdomains). */
static sinter_status sort_by_id(sinter_ctx *ctx, const candidates *cs, size_t *order)
{
    keyed *k = sinter_alloc(ctx, (cs->count + 1) * sizeof(keyed));
    if (k == NULL)
        return SINTER_ERR_NOMEM;
    for (size_t q = 0; q < cs->count; ++q)
        k[q] = (keyed){id_of(cs, q), q};
    qsort(k, cs->count, sizeof(keyed), by_id);
    for (size_t q = 0; q < cs->count; ++q)
        order[q] = k[q].q;
    sinter_free(ctx, k);
    return SINTER_OK;
}

/* Orthonormal e1, e2 perpendicular to the unit vector d. */
static void basis(const double d[3], double e1[3], double e2[3])
{
    /* the axis least aligned with d */
    const double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]);
    double a[3] = {0.0, 0.0, 0.0};
    if (ax <= ay && ax <= az)
        a[0] = 1.0;
    else if (ay <= az)
        a[1] = 1.0;
    else
        a[2] = 1.0;
    /* e1 = normalise(a - (a.d) d), e2 = d x e1 */
    const double ad = a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
    double n = 0.0;
    for (int k = 0; k < 3; ++k) {
        e1[k] = a[k] - ad * d[k];
        n += e1[k] * e1[k];
    }
    n = sqrt(n);
    for (int k = 0; k < 3; ++k)
        e1[k] /= n;
    e2[0] = d[1] * e1[2] - d[2] * e1[1];
    e2[1] = d[2] * e1[0] - d[0] * e1[2];
    e2[2] = d[0] * e1[1] - d[1] * e1[0];
}

static sinter_status beam_rays_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double t = e->time;
    const double p[3] = {sinter_heat_param(hm, B_X, t), sinter_heat_param(hm, B_Y, t),
                         sinter_heat_param(hm, B_Z, t)};
    double d[3] = {sinter_heat_param(hm, B_DX, t), sinter_heat_param(hm, B_DY, t),
                   sinter_heat_param(hm, B_DZ, t)};
    const double rb = sinter_heat_param(hm, B_RADIUS, t), power = sinter_heat_param(hm, B_POWER, t);
    const double profile = sinter_heat_param(hm, B_PROFILE, t);
    const double mu = sinter_heat_param(hm, B_ATTENUATION, t),
                 rays = sinter_heat_param(hm, B_RAYS, t);
    const double dn = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(dn > 0.0) || !(rb > 0.0) || !(power >= 0.0) || (profile != 0.0 && profile != 1.0) ||
        !(mu >= 0.0) || !(rays >= 1.0 && rays <= 4096.0) || rays != floor(rays))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s' at t = %g s: needs a non-zero direction (|d| = %g), "
                           "radius > 0 (%g m), power >= 0 (%g W), profile 0 or 1 (%g), "
                           "attenuation >= 0 (%g 1/m) and a whole number of rays in [1, 4096] (%g)",
                           hm->name, t, dn, rb, power, profile, mu, rays);
    sinter_heat_model *out = (sinter_heat_model *)hm; /* the outputs of this evaluation */
    memset(out->output, 0, sizeof(out->output));
    for (int k = 0; k < 3; ++k)
        d[k] /= dn;
    double e1[3], e2[3];
    basis(d, e1, e2);
    const int gauss = profile == 1.0;
    const double rs = gauss ? 2.0 * rb : rb; /* the sampled disc */
    const int n = (int)rays;
    const double h = 2.0 * rs / n;

    /* candidates: centres within rs + r of the axis, not wholly behind the start plane */
    const sinter_particles *ps = e->ps;
    const double *x = ps->x, *r = ps->radius;
    double *mine = sinter_alloc(e->ctx, (sinter_heat_owned(e) + 1) * CW * sizeof(double));
    size_t *where = sinter_alloc(e->ctx, (sinter_heat_owned(e) + 1) * sizeof(size_t));
    if (mine == NULL || where == NULL) {
        sinter_free(e->ctx, mine);
        mine = NULL;
    }
    size_t nc = 0; /* owned particles only: the beam crosses one periodic cell (heat_model.h) */
    for (size_t i = 0; mine != NULL && i < sinter_heat_owned(e); ++i) {
        const double c[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]};
        const double along = c[0] * d[0] + c[1] * d[1] + c[2] * d[2];
        const double a1 = c[0] * e1[0] + c[1] * e1[1] + c[2] * e1[2];
        const double a2 = c[0] * e2[0] + c[1] * e2[1] + c[2] * e2[2];
        const double reach = rs + r[i];
        if (along + r[i] > 0.0 && a1 * a1 + a2 * a2 <= reach * reach) {
            where[nc] = i; /* its row in this set */
            double *row = mine + CW * nc++;
            memcpy(row, x + 3 * i, 3 * sizeof(double));
            row[3] = r[i];
            row[4] = sinter_particle_param(ps, i, SINTER_MAT_ABSORPTANCE);
            row[5] = ps->temperature[i];
            const uint64_t id = ps->id[i];
            memcpy(row + 6, &id, sizeof(id));
        }
    }
    /* across subdomains every subdomain traces every candidate (the shadows cross borders) */
    candidates cs = {mine, nc, 0};
    sinter_status st = mine != NULL ? SINTER_OK : SINTER_ERR_NOMEM;
    if (e->domain != NULL) {
        st = sinter_domain_allgather(e->ctx, e->domain, st, mine, nc, CW, &cs.row, &cs.count,
                                     &cs.first);
        sinter_free(e->ctx, mine);
        mine = NULL;
    }
    if (st != SINTER_OK) {
        sinter_free(e->ctx, where);
        return st;
    }
    const size_t m = cs.count;
    /* the order of the candidates (ties along a ray): one domain's index order, or the ids
     * across subdomains (the same order while ids ascend with indices) */
    size_t *order = sinter_alloc(e->ctx, (m + 1) * sizeof(size_t));
    double *got = sinter_calloc(e->ctx, m + 1, sizeof(double));
    hit *hits = sinter_calloc(e->ctx, m + 1, sizeof(hit));
    st = order == NULL || got == NULL || hits == NULL ? SINTER_ERR_NOMEM : SINTER_OK;
    for (size_t q = 0; st == SINTER_OK && q < m; ++q)
        order[q] = q;
    if (st == SINTER_OK && e->domain != NULL)
        st = sort_by_id(e->ctx, &cs, order);
    if (st != SINTER_OK) {
        sinter_free(e->ctx, where);
        sinter_free(e->ctx, order);
        sinter_free(e->ctx, got);
        sinter_free(e->ctx, hits);
        sinter_free(e->ctx, cs.row);
        return SINTER_ERR_NOMEM;
    }
    /* the rays' weights: their sum first, so that the rays carry exactly P */
    double wsum = 0.0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double s1 = -rs + (a + 0.5) * h, s2 = -rs + (b + 0.5) * h;
            const double rho2 = s1 * s1 + s2 * s2;
            if (rho2 <= rs * rs)
                wsum += gauss ? exp(-2.0 * rho2 / (rb * rb)) : 1.0;
        }
    double absorbed = 0.0, transmitted = 0.0;
    for (int a = 0; a < n && wsum > 0.0; ++a)
        for (int b = 0; b < n; ++b) {
            const double s1 = -rs + (a + 0.5) * h, s2 = -rs + (b + 0.5) * h;
            const double rho2 = s1 * s1 + s2 * s2;
            if (rho2 > rs * rs)
                continue;
            double left = power * (gauss ? exp(-2.0 * rho2 / (rb * rb)) : 1.0) / wsum;
            const double o[3] = {p[0] + s1 * e1[0] + s2 * e2[0], p[1] + s1 * e1[1] + s2 * e2[1],
                                 p[2] + s1 * e1[2] + s2 * e2[2]};
            size_t nh = 0;
            for (size_t k = 0; k < m; ++k) {
                const size_t q = order[k];
                const double *c = cs.row + CW * q;
                const double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
                const double bb = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
                const double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - c[3] * c[3];
                const double disc = bb * bb - cc;
                if (!(disc > 0.0))
                    continue;
                const double root = sqrt(disc), t1 = -bb + root;
                if (!(t1 > 0.0))
                    continue;
                const double t0 = fmax(-bb - root, 0.0);
                /* insertion by entry, ties in the candidates' order */
                size_t at = nh++;
                while (at > 0 && hits[at - 1].t > t0) {
                    hits[at] = hits[at - 1];
                    --at;
                }
                hits[at] = (hit){t0, t1 - t0, q};
            }
            for (size_t k = 0; k < nh && left > 0.0; ++k) {
                const size_t q = hits[k].q;
                const double f = cs.row[CW * q + 4] * -expm1(-mu * hits[k].chord);
                const double dq = left * f;
                if (q >= cs.first && q < cs.first + nc) /* this subdomain's particle */
                    e->heat[where[q - cs.first]] += dq;
                got[q] += dq;
                absorbed += dq;
                left -= dq;
            }
            transmitted += left;
        }
    double lit = 0.0, lit_theta = 0.0;
    for (size_t k = 0; k < m; ++k) {
        const size_t q = order[k];
        if (got[q] > 0.0) {
            lit += 1.0;
            lit_theta += cs.row[CW * q + 5];
            if (e->flags != NULL && q >= cs.first && q < cs.first + nc) /* targeted (beam.c) */
                e->flags[where[q - cs.first]] |= (uint32_t)SINTER_PARTICLE_LIT;
        }
    }
    out->output[0] = absorbed;
    out->output[1] = wsum > 0.0 ? transmitted : power;
    out->output[2] = lit;
    out->output[3] = lit > 0.0 ? lit_theta / lit : 0.0;
    sinter_free(e->ctx, where);
    sinter_free(e->ctx, order);
    sinter_free(e->ctx, got);
    sinter_free(e->ctx, hits);
    sinter_free(e->ctx, cs.row);
    return SINTER_OK;
}

const char *const sinter_heat_beam_outputs[SINTER_HEAT_MAX_OUTPUTS + 1] = {
    "absorbed", "transmitted", "lit", "lit_temperature", NULL};

const sinter_heat_ops sinter_heat_beam = {
    "beam",
    0,
    {"x", "y", "z", "dx", "dy", "dz", "radius", "power", "profile", "attenuation", "rays", NULL},
    {0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 5e-3, 0.0, 0.0, 1e9, 32.0},
    beam_rays_eval,
    NULL};
