/*
 * Heat conduction through contacts (seed 003 eq. 32-35, seed 000 eq. 33-34).
 *
 * Particle-particle, "area" = 0: Q_ij = G (theta_j - theta_i) with G = k_ij A_ij / d_ij,
 * d_ij = |x_j - x_i|, A_ij = pi a_ij^2 from the contact list (eq. 34) and
 * (r_i + r_j) / k_ij = r_i / k_i + r_j / k_j (eq. 35), written as
 * k_ij = k_i k_j (r_i + r_j) / (r_i k_j + r_j k_i) so that k = 0 on either side gives G = 0.
 *
 * "area" = 1 is LIGGGHTS' `contact_area projection` exactly, as in fix heat/gran/conduction
 * (LIGGGHTS-PUBLIC 3.8.0): G = 4 k_i k_j / (k_i + k_j) sqrt(A) with A = pi max(r_i, r_j)^2,
 * i.e. G = 2 sqrt(pi) k r for equal spheres, independent of the overlap (the peer benchmark's
 * canonical conductance). Note: LIGGGHTS projects the LARGER sphere and uses the harmonic mean
 * of the conductivities, not eq. 35; for equal radii both readings coincide.
 *
 * "area" = 2: the constriction conductance G = 4 a k_i k_j / (k_i + k_j) of two bodies meeting
 * in a circle of radius a (Batchelor & O'Brien 1977; 2 k a for equal conductivities). "radius"
 * = 1 takes Hertz's contact radius a^2 = r* delta for laws 0 and 2 instead of eq. 34's;
 * "resistance" R'' [m^2 K/W] > 0 puts an interface resistance in series over the contact
 * area, 1/G = 1/G_law + R''/A (seed 003 eq. 35's optional t_mat/k_mat); "gas_conductivity"
 * k_g > 0 adds the gas lens around each contact in parallel (gas_gap.h, with "gas_gap" and
 * "gas_radius"), and "gas_reach" > 0 the same lens between the pairs apart by less than
 * gas_reach min(r_i, r_j) (gas_gap.c, over the stepper's candidate pairs). Those options run in
 * conduction_eval's own loop (loop_pp_general); the default laws keep their ranges' loops.
 *
 * Particle-wall (when "walls" = 1): the wall is a fixed-temperature reservoir at
 * wall->temperature, k_iw = 2 k_i k_w / (k_i + k_w) (eq. 35 with the wall taken as a body of
 * the particle's size; k_w = 0 gives an adiabatic wall). "wall_reading" chooses the contact
 * area A and distance d of G = k_iw A / d: 0 eq. 34's circle pi (r^2 - s^2) over the
 * centre-to-plane distance s; 1 (the default, decided on seed 003 Fig. 5: docs/validation.md)
 * Hertz's area pi r delta (r* = r_i at a wall) over s; 2 eq. 34's circle over the distance 2 s
 * to the mirror particle. "area" = 1: LIGGGHTS' wall formula
 * 4 k_p k_w / (k_p + k_w) sqrt(pi r_i^2) with k_w the wall material's conductivity, as in
 * LIGGGHTS (a wall with k_w = 0 is adiabatic; k_w = k_p gives G = 2 sqrt(pi) k_i r_i).
 * "area" = 2: 4 a k_i k_w / (k_i + k_w) with a from the reading's area. Then each wall's own
 * thermal mode (sinter_walls_set_thermal): adiabatic, a specific resistance in series, a heat
 * transfer coefficient h alone (G = h A), or imposed (no conductance here: the stepper sets the
 * touching particles to the wall's temperature, stepper/thermal.c).
 * A particle whose centre is on or behind the plane (d <= 0, not a physical state) does not
 * conduct with "area" = 0.
 *
 * Explicit use (e->g_pp == NULL): Q is added to particle i and subtracted from particle j
 * exactly, so sum m C theta is conserved to round-off. Implicit use: G is added to g_pp[k] /
 * g_pw[k] instead and nothing is added to e->heat.
 */
#include <math.h>
#include <string.h>

#include "conduction_ranges.h"
#include "contact/chunks.h"
#include "core/ranges_run.h"
#include "gas_gap.h"
#include "heat_model.h"
#include "particles/particles.h"
#include "walls/walls.h"

enum {
    PARAM_AREA = 0,
    PARAM_WALLS = 1,
    PARAM_WALL_READING = 2,
    PARAM_RADIUS = 3,
    PARAM_RESISTANCE = 4,
    PARAM_GAS_CONDUCTIVITY = 5,
    PARAM_GAS_GAP = 6,
    PARAM_GAS_RADIUS = 7,
    PARAM_GAS_REACH = 8
};

/* "area": the pair law; "wall_reading": the particle-wall conductance's reading. */
enum { AREA_EQ34 = 0, AREA_PROJECTION = 1, AREA_CONSTRICTION = 2 };
enum { READING_PLANE = 0, READING_HERTZ = 1, READING_MIRROR = 2 };
/* For pw_run: every wall a reservoir under the projection or the plane reading (walls_plain),
 * so conductance_pw alone, with no wall's mode read. */
enum { READING_PLAIN = -1 };

static const double SQRT_PI = 1.77245385090551602730;
static const double PI = 3.14159265358979323846;

/* Conductance of one particle-particle contact. `projection` is constant per call. */
static inline double conductance_pp(int projection, double ki, double kj, double ri, double rj,
                                    double area, double dist)
{
    if (projection) {
        const double ks = ki + kj; /* LIGGGHTS: 4 k_i k_j / (k_i + k_j) sqrt(pi) r_max */
        return ks > 0.0 ? 4.0 * ki * kj / ks * SQRT_PI * (ri > rj ? ri : rj) : 0.0;
    }
    const double den = ri * kj + rj * ki;                             /* eq. 35 */
    return den > 0.0 ? ki * kj * (ri + rj) / den * area / dist : 0.0; /* eq. 32, 34 */
}

/* Conductance of one particle-wall contact. */
static inline double conductance_pw(int projection, double ki, double kw, double ri, double area,
                                    double dist)
{
    if (projection) /* LIGGGHTS' wall: 4 k_p k_w / (k_p + k_w) sqrt(pi r^2) */
        return ki + kw > 0.0 ? 4.0 * ki * kw / (ki + kw) * SQRT_PI * ri : 0.0;
    const double kiw = ki + kw > 0.0 ? 2.0 * ki * kw / (ki + kw) : 0.0; /* eq. 35, r_w = r_i */
    return dist > 0.0 ? kiw * area / dist : 0.0;                        /* eq. 32 */
}

/*
 * The general pair law ("area" 0 or 2 with "radius" and "resistance", or 1 with "resistance"):
 * the contact radius a^2 = A/pi of eq. 34 (hertz = 0) or Hertz's a^2 = r* delta (hertz = 1);
 * eq. 32-35 (area 0), the projection (1) or the constriction conductance of two half-spaces
 * through a circle of radius a, G = 4 a k_i k_j / (k_i + k_j) (Batchelor & O'Brien 1977: 2 k a
 * for equal conductivities; area 2); then an interface resistance R'' [m^2 K/W] in series over
 * the contact area: 1/G = 1/G_law + R''/A (seed 003 eq. 35's optional t/k term).
 */
typedef struct pp_law {
    int area, hertz;
    double resistance;
    double gas_k, gas_gap, gas_radius; /* the gas lens (gas_lens); gas_k 0: none */
} pp_law;

static double conductance_pp_general(const pp_law *L, double ki, double kj, double ri, double rj,
                                     double area, double dist, double delta)
{
    double a2 = L->area == AREA_PROJECTION ? 0.0 : area / PI;
    if (L->hertz)
        a2 = delta > 0.0 ? ri * rj / (ri + rj) * delta : 0.0;
    double g = 0.0, contact = PI * a2;
    if (L->area == AREA_PROJECTION) {
        const double rm = ri > rj ? ri : rj;
        g = conductance_pp(1, ki, kj, ri, rj, 0.0, 0.0);
        contact = PI * rm * rm;
    } else if (L->area == AREA_CONSTRICTION) {
        g = ki + kj > 0.0 && a2 > 0.0 ? 4.0 * sqrt(a2) * ki * kj / (ki + kj) : 0.0;
    } else {
        g = dist > 0.0 ? conductance_pp(0, ki, kj, ri, rj, contact, dist) : 0.0;
    }
    if (L->resistance > 0.0)
        g = g > 0.0 && contact > 0.0 ? 1.0 / (1.0 / g + L->resistance / contact) : 0.0;
    if (L->gas_k > 0.0) { /* in parallel with the solid contact (and its resistance) */
        const double rs = ri * rj / (ri + rj), rmin = ri < rj ? ri : rj;
        g += sinter_gas_lens(L->gas_k, L->gas_gap, L->gas_radius * rmin, rs, -delta, a2);
    }
    return g;
}

/*
 * Conductance of particle-wall contact (wall w) under the model's pair law `area` and wall
 * reading: the contact area A and distance d are eq. 34's circle and the centre-plane distance
 * s (READING_PLANE), Hertz's A = pi r delta over s (READING_HERTZ: r* = r, a^2 = r delta), or
 * eq. 34's circle over the distance 2 s to the mirror particle (READING_MIRROR); the law is
 * k_iw A / d (area 0), the projection (1, which reads neither) or the constriction
 * 4 a k_i k_w / (k_i + k_w) (2, which reads no distance). Then the wall's own condition:
 * reservoir (that G), adiabatic or imposed (0: the stepper sets an imposed wall's particles),
 * a specific resistance R'' in series (1/G = 1/G_law + R''/A) or a transfer coefficient alone
 * (G = h A; with the projection, A = pi r^2).
 */
static inline double conductance_wall(int area_law, int reading, const sinter_wall *w, double ki,
                                      double kw, double ri, double area, double dist, double delta)
{
    const int mode = w->thermal_mode;
    if (mode == SINTER_WALL_RESERVOIR &&
        (area_law == AREA_PROJECTION || (area_law == AREA_EQ34 && reading == READING_PLANE)))
        return conductance_pw(area_law == AREA_PROJECTION, ki, kw, ri, area, dist); /* 0.x */
    if (mode == SINTER_WALL_ADIABATIC || mode == SINTER_WALL_IMPOSED)
        return 0.0;
    double contact = area, d = dist;
    if (reading == READING_HERTZ)
        contact = delta > 0.0 ? PI * ri * delta : 0.0;
    else if (reading == READING_MIRROR)
        d = 2.0 * dist;
    if (area_law == AREA_PROJECTION)
        contact = PI * ri * ri;
    if (mode == SINTER_WALL_TRANSFER)
        return w->thermal_value * contact;
    double g;
    if (area_law == AREA_CONSTRICTION)
        g = ki + kw > 0.0 && contact > 0.0 ? 4.0 * sqrt(contact / PI) * ki * kw / (ki + kw) : 0.0;
    else
        g = conductance_pw(area_law == AREA_PROJECTION, ki, kw, ri, contact, d);
    if (mode == SINTER_WALL_RESISTANCE && w->thermal_value > 0.0)
        g = g > 0.0 && contact > 0.0 ? 1.0 / (1.0 / g + w->thermal_value / contact) : 0.0;
    return g;
}

/* Conductivity of every material, read once per evaluation (those above the registered ids
 * are 0, as an unregistered material's values are, without reading them). */
static void conductivities(const sinter_particles *ps, double k[SINTER_MAX_MATERIALS])
{
    const int top = ps->material_top;
    for (int m = 0; m < top; ++m)
        k[m] = ps->materials[m].value[SINTER_MAT_THERMAL_CONDUCTIVITY];
    memset(k + top, 0, (size_t)(SINTER_MAX_MATERIALS - top) * sizeof(double));
}

/* Conductance of particle-particle contact q. */
static inline double contact_g(const sinter_heat_eval *e, const double *kmat, int projection,
                               size_t q)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const uint32_t i = c->i[q], j = c->j[q];
    /* the projection law reads no geometry (the list may be lean: conduction_reads_geometry) */
    return conductance_pp(projection, kmat[ps->material[i]], kmat[ps->material[j]], ps->radius[i],
                          ps->radius[j], projection ? 0.0 : c->area[q],
                          projection ? 0.0 : c->dist[q]);
}

/* The projection law's factor 4 k_i k_j / (k_i + k_j) sqrt(pi) when one material is in use
 * (then G = factor r_max, the same bits as conductance_pp), else -1. */
static double projection_factor(const sinter_particles *ps, const double *kmat)
{
    int used = -1;
    for (int m = 0; m < ps->material_top; ++m)
        if (ps->material_used[m]) {
            if (used >= 0)
                return -1.0;
            used = m;
        }
    if (used < 0)
        return -1.0;
    const double k = kmat[used], ks = k + k;
    return ks > 0.0 ? 4.0 * k * k / ks * SQRT_PI : 0.0;
}

/* Range s of a partitioned list: interior contacts into heat, boundary ones stored, *reach
 * 1 + the largest particle index among them (0: none); returns their number. With `factor`
 * >= 0 (projection_factor) the conductance is factor r_max. With `skip_ended` (an
 * unconfirmed list, read in the law's region after the law's pass over range s) the contacts
 * the law marked ended are left out, as sinter_contacts_confirm then drops them: the same
 * sums as over the confirmed list. */
static inline __attribute__((always_inline)) size_t
pp_range(const sinter_heat_eval *e, const double *kmat, int projection, double factor,
         int skip_ended, const sinter_chunks *ch, int s, double *restrict heat,
         uint32_t *restrict bq, double *restrict bpower, uint32_t *reach)
{
    const sinter_contact_list *c = e->pp;
    const double *restrict theta = e->ps->temperature;
    const uint32_t *restrict ci = c->i, *restrict cj = c->j;
    const uint8_t *restrict ended = c->ended;
    size_t kept = 0;
    uint32_t top = 0;
    const double *restrict r = e->ps->radius;
    for (size_t k = ch->qlo[s]; k < ch->qlo[s + 1]; ++k) {
        if (skip_ended && ended[k]) /* a contact the law found ended (not yet dropped) */
            continue;
        const uint32_t i = ci[k], j = cj[k];
        const double g = factor >= 0.0 ? factor * (r[i] > r[j] ? r[i] : r[j])
                                       : contact_g(e, kmat, projection, k);
        const double q = g * (theta[j] - theta[i]); /* eq. 32 */
        if (sinter_chunks_interior(ch, s, i, j)) {
            heat[i] += q;
            heat[j] -= q;
        } else { /* a boundary contact: its particles may be another range's, not touched here */
            bq[kept] = (uint32_t)k;
            bpower[kept++] = q;
            top = sinter_chunks_reach(top, i, j);
        }
    }
    *reach = top;
    return kept;
}

/* Wall contacts [lo, hi) (eq. 32, the wall side at the wall's temperature): their
 * conductances into g_pw when implicit, else their powers into heat. */
static inline __attribute__((always_inline)) void pw_run(const sinter_heat_eval *e,
                                                         const double *kmat, int area_law,
                                                         int reading, int implicit, size_t lo,
                                                         size_t hi)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pw;
    const double *r = ps->radius, *theta = ps->temperature;
    for (size_t k = lo; k < hi; ++k) {
        const uint32_t i = c->i[k];
        const sinter_wall *wall = &e->walls->wall[c->j[k]];
        const double kw = wall->material.value[SINTER_MAT_THERMAL_CONDUCTIVITY];
        const double ki = sinter_heat_conductivity(e, kmat, i);
        const double g =
            reading == READING_PLAIN
                ? conductance_pw(area_law == AREA_PROJECTION, ki, kw, r[i], c->area[k], c->dist[k])
                : conductance_wall(area_law, reading, wall, ki, kw, r[i], c->area[k], c->dist[k],
                                   c->delta[k]);
        if (implicit)
            e->g_pw[k] += g;
        else
            e->heat[i] += g * (wall->temperature - theta[i]); /* eq. 32 */
    }
}

/* Range r's boundary contacts (those of ranges 0 .. r that reach it, in list order), then,
 * with `wq`, its wall contacts: after the interior passes of ranges 0 .. r (all_ranges). */
static inline __attribute__((always_inline)) void
range_rest(const sinter_heat_eval *e, const double *kmat, int projection, const sinter_chunks *ch,
           int r, double *heat, const uint32_t *bq, const double *bpower, const size_t *boundary,
           const uint32_t *reach, const size_t *wq, int reading)
{
    const sinter_contact_list *c = e->pp;
    const size_t lo = ch->plo[r], hi = ch->plo[r + 1];
    for (int s = 0; s <= r; ++s) {
        if (reach[s] <= lo) /* no boundary contact of range s reaches r */
            continue;
        for (size_t b = ch->qlo[s]; b < ch->qlo[s] + boundary[s]; ++b) {
            const uint32_t i = c->i[bq[b]], j = c->j[bq[b]];
            if (i >= lo && i < hi)
                heat[i] += bpower[b];
            if (j >= lo && j < hi)
                heat[j] -= bpower[b];
        }
    }
    const int law = projection ? AREA_PROJECTION : AREA_EQ34;
    if (wq != NULL && reading == READING_PLAIN)
        pw_run(e, kmat, law, READING_PLAIN, 0, wq[r], wq[r + 1]);
    else if (wq != NULL)
        pw_run(e, kmat, law, reading, 0, wq[r], wq[r + 1]);
}

/* The conductance laws of a partitioned evaluation, each its own loop (constants inlined, so
 * that none tests them): eq. 34's area, the projection, the projection with one material. */
enum law { LAW_AREA = 0, LAW_PROJECTION = 1, LAW_FACTOR = 2 };

/* READING_PLAIN when every wall is a reservoir and the law reads the walls as before the
 * readings existed (the projection, or eq. 34's circle over s), else `reading`. */
static int walls_plain(const sinter_heat_eval *e, int area_law, int reading)
{
    if (e->walls == NULL ||
        !(area_law == AREA_PROJECTION || (area_law == AREA_EQ34 && reading == READING_PLANE)))
        return reading;
    for (size_t w = 0; w < e->walls->count; ++w)
        if (e->walls->wall[w].thermal_mode != SINTER_WALL_RESERVOIR)
            return reading;
    return READING_PLAIN;
}

int sinter_conduction_ranges_begin(const sinter_heat_model *hm, const sinter_heat_eval *e,
                                   void *scratch, sinter_conduction_ranges *j)
{
    const sinter_contact_list *c = e->pp;
    if (hm->ops != &sinter_heat_conduction || e->g_pp != NULL || c->chunks.count == 0 ||
        e->conductivity != NULL) /* k(theta) tables: the general loops */
        return 0;
    const double area = sinter_heat_param(hm, PARAM_AREA, e->time);
    if (area != 0.0 && area != 1.0) /* conduction_eval reports it */
        return 0;
    const int projection = area == 1.0;
    if (!projection && !c->geometry) /* the area and distance of a lean list are not formed */
        return 0;
    /* the general pair law (radius, resistance) runs in conduction_eval's own loops */
    if (sinter_heat_param(hm, PARAM_RADIUS, e->time) != 0.0 ||
        sinter_heat_param(hm, PARAM_RESISTANCE, e->time) != 0.0 ||
        sinter_heat_param(hm, PARAM_GAS_CONDUCTIVITY, e->time) != 0.0)
        return 0;
    const double reading = sinter_heat_param(hm, PARAM_WALL_READING, e->time);
    if (reading != READING_PLANE && reading != READING_HERTZ && reading != READING_MIRROR)
        return 0;
    j->reading = walls_plain(e, projection ? AREA_PROJECTION : AREA_EQ34, (int)reading);
    const int walls =
        sinter_heat_param(hm, PARAM_WALLS, e->time) != 0.0 && e->walls != NULL && e->pw != NULL;
    j->walls = walls && sinter_chunks_wall_runs(&c->chunks, e->pw, j->wq) > 0;
    j->walls_left = walls && !j->walls;
    j->e = *e;
    conductivities(e->ps, j->kmat);
    j->factor = projection ? projection_factor(e->ps, j->kmat) : -1.0;
    j->law = !projection ? LAW_AREA : j->factor >= 0.0 ? LAW_FACTOR : LAW_PROJECTION;
    j->ch = c->chunks;
    j->skip_ended = c->unconfirmed;
    j->bpower = scratch;
    j->bq = (uint32_t *)(j->bpower + c->count);
    sinter_range_flags_clear(&j->interior_done, j->ch.count);
    return 1;
}

static inline __attribute__((always_inline)) void
interior_pass(sinter_conduction_ranges *j, int s, int projection, double factor, int skip_ended)
{
    const size_t q = j->ch.qlo[s];
    j->boundary[s] = pp_range(&j->e, j->kmat, projection, factor, skip_ended, &j->ch, s, j->e.heat,
                              j->bq + q, j->bpower + q, &j->reach[s]);
    sinter_range_flags_set(&j->interior_done, s);
}

/* This file is compiled with its functions on 64-byte lines and its jump targets on 16 bytes
 * (CMakeLists.txt, SINTER_ALIGNED_SOURCES): the interior pass's speed depends on its loop's
 * place in the cache lines. Code moved from here to another file must take the flags along. */
void sinter_conduction_range_interior(sinter_conduction_ranges *j, int s)
{
    const int skip = j->skip_ended;
    if (j->law == LAW_FACTOR)
        skip ? interior_pass(j, s, 1, j->factor, 1) : interior_pass(j, s, 1, j->factor, 0);
    else if (j->law == LAW_PROJECTION)
        skip ? interior_pass(j, s, 1, -1.0, 1) : interior_pass(j, s, 1, -1.0, 0);
    else
        skip ? interior_pass(j, s, 0, -1.0, 1) : interior_pass(j, s, 0, -1.0, 0);
}

void sinter_conduction_range_rest(sinter_conduction_ranges *j, int r)
{
    sinter_range_flags_wait_below(&j->interior_done, r + 1);
    range_rest(&j->e, j->kmat, j->law != LAW_AREA, &j->ch, r, j->e.heat, j->bq, j->bpower,
               j->boundary, j->reach, j->walls ? j->wq : NULL, j->reading);
}

/* The two passes of all_ranges, for sinter_ranges_run_two_passes. */
static void interior_of(void *j, int s)
{
    sinter_conduction_range_interior(j, s);
}

static void rest_of(void *j, int r)
{
    sinter_conduction_range_rest(j, r);
}

/*
 * Explicit, on a partitioned list: the ranges in one parallel region of their own, each
 * adding its interior contacts' powers, then the boundary contacts in list order by the range
 * that holds each particle (a contact of range s touches ranges s and later only), so that
 * every particle receives them in the order of one pass over the list; then, when the model
 * conducts to the walls, each range's wall contacts. No barrier: range r waits for the
 * interior passes of ranges 0 .. r only (range_flags.h). Which thread runs a range: see
 * sinter_ranges_run_two_passes (core/ranges_run.h); the bits do not depend on it.
 */
static void all_ranges(sinter_conduction_ranges *j, int threads)
{
    sinter_ranges_run_two_passes(threads, j->ch.count, interior_of, rest_of, j);
}

/* Pair contacts, on a list without a partition or implicit (a partitioned list's explicit
 * sums are all_ranges'). */
static inline void loop_pp(const sinter_heat_eval *e, const double *kmat, int projection,
                           int implicit)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *theta = ps->temperature;
    const int threads = c->count < 4096 ? 1 : sinter_threads(e->ctx);
    if (implicit) {
        const long count = (long)c->count;
        if (threads > 1) {
#pragma omp parallel for num_threads(threads) schedule(static)
            for (long k = 0; k < count; ++k)
                e->g_pp[k] += contact_g(e, kmat, projection, (size_t)k);
        } else { /* a region of one thread costs a team (core/ranges_run.h) */
            for (long k = 0; k < count; ++k)
                e->g_pp[k] += contact_g(e, kmat, projection, (size_t)k);
        }
        return;
    }
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        const double q = contact_g(e, kmat, projection, k) * (theta[j] - theta[i]); /* eq. 32 */
        e->heat[i] += q;
        e->heat[j] -= q;
    }
}

/* Pair contacts under the general law (conductance_pp_general), explicit or implicit. */
static void loop_pp_general(const sinter_heat_eval *e, const double *kmat, const pp_law *L,
                            int implicit)
{
    const sinter_particles *ps = e->ps;
    const sinter_contact_list *c = e->pp;
    const double *theta = ps->temperature, *r = ps->radius;
    /* the projection reads no geometry, the gas lens the overlap */
    const int geometry = L->area != AREA_PROJECTION || L->gas_k > 0.0;
    for (size_t k = 0; k < c->count; ++k) {
        const uint32_t i = c->i[k], j = c->j[k];
        if (c->unconfirmed && c->ended[k])
            continue;
        const double g = conductance_pp_general(
            L, sinter_heat_conductivity(e, kmat, i), sinter_heat_conductivity(e, kmat, j), r[i],
            r[j], geometry ? c->area[k] : 0.0, geometry ? c->dist[k] : 0.0,
            geometry ? c->delta[k] : 0.0);
        if (implicit) {
            e->g_pp[k] += g;
            continue;
        }
        const double q = g * (theta[j] - theta[i]); /* eq. 32 */
        e->heat[i] += q;
        e->heat[j] -= q;
    }
}

static inline void loop_pw(const sinter_heat_eval *e, const double *kmat, int area_law, int reading,
                           int implicit)
{
    const sinter_contact_list *c = e->pw;
    /* runs that never split a particle's contacts: those of the pair partition's particle
     * ranges (each thread its own particles), else the list's own (chunks.h) */
    size_t qlo[SINTER_CHUNKS_MAX + 1] = {0, c->count};
    int ranges = sinter_chunks_wall_plan(&e->pp->chunks, c, qlo, NULL);
    ranges = ranges > 0 ? ranges : 1;
    const int threads = ranges > 1 ? sinter_threads(e->ctx) : 1;
    if (threads == 1) { /* (a region of one thread costs a team's allocation: ranges_run.h) */
        for (int s = 0; s < ranges; ++s)
            if (reading == READING_PLAIN)
                pw_run(e, kmat, area_law, READING_PLAIN, implicit, qlo[s], qlo[s + 1]);
            else
                pw_run(e, kmat, area_law, reading, implicit, qlo[s], qlo[s + 1]);
        return;
    }
#pragma omp parallel for num_threads(threads < ranges ? threads : ranges) schedule(static)
    for (int s = 0; s < ranges; ++s)
        pw_run(e, kmat, area_law, reading, implicit, qlo[s], qlo[s + 1]);
}

static sinter_status conduction_eval(const sinter_heat_model *hm, sinter_heat_eval *e)
{
    const double area = sinter_heat_param(hm, PARAM_AREA, e->time);
    if (area != AREA_EQ34 && area != AREA_PROJECTION && area != AREA_CONSTRICTION)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'area' = %g must be 0 (eq. 34), 1 (projection) or "
                           "2 (constriction)",
                           hm->name, area);
    const double reading = sinter_heat_param(hm, PARAM_WALL_READING, e->time);
    if (reading != READING_PLANE && reading != READING_HERTZ && reading != READING_MIRROR)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'wall_reading' = %g must be 0 (centre-plane "
                           "distance), 1 (Hertz's area) or 2 (mirror particle)",
                           hm->name, reading);
    const double radius = sinter_heat_param(hm, PARAM_RADIUS, e->time);
    if (radius != 0.0 && radius != 1.0)
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'radius' = %g must be 0 (eq. 34) or 1 (Hertz)",
                           hm->name, radius);
    const double resistance = sinter_heat_param(hm, PARAM_RESISTANCE, e->time);
    if (!(resistance >= 0.0 && resistance < INFINITY))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'resistance' = %g m^2 K/W must be finite and >= 0",
                           hm->name, resistance);
    const double gas_k = sinter_heat_param(hm, PARAM_GAS_CONDUCTIVITY, e->time);
    const double gas_gap = sinter_heat_param(hm, PARAM_GAS_GAP, e->time);
    const double gas_radius = sinter_heat_param(hm, PARAM_GAS_RADIUS, e->time);
    const double gas_reach = sinter_heat_param(hm, PARAM_GAS_REACH, e->time);
    if (!(gas_k >= 0.0 && gas_k < INFINITY) || !(gas_gap > 0.0 && gas_gap < INFINITY) ||
        !(gas_radius > 0.0 && gas_radius <= 1.0) || !(gas_reach >= 0.0 && gas_reach <= 10.0))
        return sinter_fail(e->ctx, SINTER_ERR_INVALID,
                           "heat model '%s': 'gas_conductivity' = %g W/(m K) must be finite and "
                           ">= 0, 'gas_gap' = %g m finite and > 0, 'gas_radius' = %g in (0, 1], "
                           "'gas_reach' = %g in [0, 10]",
                           hm->name, gas_k, gas_gap, gas_radius, gas_reach);
    const int law = (int)area, proj = law == AREA_PROJECTION;
    const int wr = walls_plain(e, law, (int)reading);
    const int implicit = e->g_pp != NULL;
    const int walls =
        sinter_heat_param(hm, PARAM_WALLS, e->time) != 0.0 && e->walls != NULL && e->pw != NULL;
    double kmat[SINTER_MAX_MATERIALS];
    if (law == AREA_CONSTRICTION || radius != 0.0 || resistance != 0.0 || gas_k != 0.0 ||
        e->conductivity != NULL) {
        conductivities(e->ps, kmat);
        const pp_law L = {law, radius != 0.0, resistance, gas_k, gas_gap, gas_radius};
        loop_pp_general(e, kmat, &L, implicit);
        const sinter_gas_law gas = {gas_k, gas_gap, gas_radius, gas_reach};
        sinter_gas_near_pairs(e, &gas); /* the pairs apart (gas_reach > 0) */
        if (walls)
            loop_pw(e, kmat, law, wr, implicit);
        return SINTER_OK;
    }
    /* explicit on a partitioned list: by its ranges, in a parallel region of their own, with
     * the wall contacts when their runs align with the ranges (each by the thread of its
     * particle's range: one region fewer); the list's scratch holds the boundary contacts */
    sinter_conduction_ranges j;
    if (sinter_conduction_ranges_begin(hm, e, e->pp->chunk_scratch, &j)) {
        all_ranges(&j, sinter_threads(e->ctx));
        if (j.walls_left)
            proj ? loop_pw(e, j.kmat, 1, wr, 0) : loop_pw(e, j.kmat, 0, wr, 0);
        return SINTER_OK;
    }
    conductivities(e->ps, kmat);
    /* Constant switches resolved here so each loop is branch-free on them. */
    if (proj)
        implicit ? loop_pp(e, kmat, 1, 1) : loop_pp(e, kmat, 1, 0);
    else
        implicit ? loop_pp(e, kmat, 0, 1) : loop_pp(e, kmat, 0, 0);
    if (walls) {
        if (proj)
            implicit ? loop_pw(e, kmat, 1, wr, 1) : loop_pw(e, kmat, 1, wr, 0);
        else
            implicit ? loop_pw(e, kmat, 0, wr, 1) : loop_pw(e, kmat, 0, wr, 0);
    }
    return SINTER_OK;
}

double sinter_heat_gas_reach(const sinter_heat_model *hm, double t)
{
    if (hm->ops != &sinter_heat_conduction ||
        !(sinter_heat_param(hm, PARAM_GAS_CONDUCTIVITY, t) > 0.0))
        return 0.0;
    const double reach = sinter_heat_param(hm, PARAM_GAS_REACH, t);
    return reach > 0.0 && reach <= 10.0 ? reach : 0.0;
}

/* The projection law reads radii and temperatures only (the wall contacts, which always
 * carry their geometry, aside). */
static int conduction_reads_geometry(const sinter_heat_model *hm, double t)
{
    return sinter_heat_param(hm, PARAM_AREA, t) != 1.0 ||
           sinter_heat_param(hm, PARAM_GAS_CONDUCTIVITY, t) != 0.0;
}

const sinter_heat_ops sinter_heat_conduction = {
    "conduction",
    1,
    {"area", "walls", "wall_reading", "radius", "resistance", "gas_conductivity", "gas_gap",
     "gas_radius", "gas_reach", NULL},
    /* wall_reading 1: docs/validation.md, seed 003 sec. 5.1 */
    {0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1e-7, 0.5, 0.0},
    conduction_eval,
    conduction_reads_geometry};
