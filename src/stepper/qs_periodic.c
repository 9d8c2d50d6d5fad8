/*
 * Periodic axes of the quasi-static stepper (issue 38): a representative volume without walls.
 *
 * The cell [lo, lo + L) along each periodic axis. A link across a face joins particle A to the
 * image of B at x_B + image L (integer image per axis, kept in the link), so the links, their
 * necks and the bonded solve see the image's shifted position; a link is still one record,
 * keyed by the two ids (the smaller one is A), and the solve's loads of the image are those of
 * B (a link names slots, not images: what acts on the image acts on B). No ghost particles are
 * needed: the quasi-static stepper owns its links, and the image only enters the link's vector.
 *
 * The cell's size (qs_cell_strain 1): each step the cell takes the homogeneous strain that the
 * links' free approaches ask for. With dl_k the approach the neck of link k makes over the step
 * (seed 001 eq. 13), l_k its centre vector (length l_k, unit n_k) and w_k its axial stiffness
 * (eq. 34a), the diagonal strain increment eps minimises
 *     sum_k w_k (dl_k - l_k sum_d eps_d n_kd^2)^2,
 * i.e. the links' mean approach weighted by their stiffness, which is also the strain at which
 * the mean axial stress of the links (Love-Weber: sigma_dd = 1/V sum_k F_k l_k n_kd^2,
 * Christoffersen, Mehrabadi and Nemat-Nasser 1981) vanishes if every link followed the cell
 * affinely (a Voigt estimate). The cell is therefore stress-free for the affine part of the
 * motion, as a body with no walls; what the packing's disorder leaves over is solved as the
 * periodic fluctuation u: K u = f - K u_affine (eq. 40), u a periodic field. For links that all
 * approach alike (a lattice, a pair) eps is their strain exactly and u vanishes. The cell keeps
 * its lower corner; each particle moves by -eps (x - lo) on top of u.
 *
 * Without qs_cell_strain the cell keeps its size (sintering constrained in those directions).
 * Axes that are not periodic keep the principal-plane conditions of sec. 3.3.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stepper/qs_struct.h"

sinter_status sinter_qs_set_cell(sinter_qs *qs, const int periodic[3], const double lo[3],
                                 const double hi[3])
{
    SINTER_CHECK_NULL(NULL, qs);
    SINTER_CHECK_NULL(qs->ctx, periodic);
    SINTER_CHECK_NULL(qs->ctx, lo);
    SINTER_CHECK_NULL(qs->ctx, hi);
    for (int d = 0; d < 3; ++d)
        if (periodic[d] && !(isfinite(lo[d]) && isfinite(hi[d]) && hi[d] > lo[d]))
            return sinter_fail(qs->ctx, SINTER_ERR_INVALID,
                               "quasi-static stepper: the periodic cell along axis %d is [%g, "
                               "%g) m; expected finite lo < hi",
                               d, lo[d], hi[d]);
    for (int d = 0; d < 3; ++d) {
        qs->periodic[d] = periodic[d] != 0;
        qs->cell_lo[d] = periodic[d] ? lo[d] : 0.0;
        qs->cell_len[d] = periodic[d] ? hi[d] - lo[d] : 0.0;
        if (!qs->cell_started || !periodic[d])
            qs->cell_len0[d] = qs->cell_len[d];
    }
    return SINTER_OK;
}

int sinter_qs_get_cell(const sinter_qs *qs, int periodic[3], double lo[3], double hi[3])
{
    for (int d = 0; d < 3; ++d) {
        periodic[d] = qs->periodic[d];
        lo[d] = qs->cell_lo[d];
        hi[d] = qs->cell_lo[d] + qs->cell_len[d];
    }
    return sinter_qs_periodic_on(qs);
}

/* The images of slot s within `cut` of a face: all combinations of -1, 0, +1 per periodic axis
 * (0 only on the others) but 0, 0, 0; written after the `*count` spheres already there. */
static void add_images(sinter_qs *qs, size_t s, const double *x, const double *r, double cut,
                       size_t *count)
{
    int lo_side[3], hi_side[3];
    for (int d = 0; d < 3; ++d) {
        const double rel = x[3 * s + (size_t)d] - qs->cell_lo[d];
        lo_side[d] = qs->periodic[d] && rel < cut;                   /* image at +L */
        hi_side[d] = qs->periodic[d] && rel > qs->cell_len[d] - cut; /* image at -L */
    }
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k) {
                const int o[3] = {i, j, k};
                int ok = i != 0 || j != 0 || k != 0;
                for (int d = 0; d < 3 && ok; ++d)
                    ok = o[d] == 0 || (o[d] > 0 ? lo_side[d] : hi_side[d]);
                if (!ok)
                    continue;
                const size_t e = *count;
                for (int d = 0; d < 3; ++d) {
                    qs->ext_x[3 * e + (size_t)d] =
                        x[3 * s + (size_t)d] + (double)o[d] * qs->cell_len[d];
                    qs->ext_image[3 * e + (size_t)d] = o[d];
                }
                qs->ext_r[e] = r[s];
                qs->ext_owner[e] = (uint32_t)s;
                ++*count;
            }
}

static int image_pair_compare(const void *pa, const void *pb)
{
    const sinter_qs_image_pair *a = pa, *b = pb;
    if (a->sa != b->sa)
        return a->sa < b->sa ? -1 : 1;
    if (a->sb != b->sb)
        return a->sb < b->sb ? -1 : 1;
    for (int d = 0; d < 3; ++d)
        if (a->image[d] != b->image[d])
            return a->image[d] < b->image[d] ? -1 : 1;
    return 0;
}

sinter_status sinter_qs_periodic_pairs(sinter_qs *qs, size_t n, const double *x, const double *r,
                                       size_t *count)
{
    *count = 0;
    double r_max = 0.0;
    for (size_t s = 0; s < n; ++s)
        r_max = fmax(r_max, r[s]);
    /* the farthest two touching centres; an image is needed within it of a face */
    const double cut = 2.0 * r_max * (1.0 + qs->opt.contact_tolerance);
    for (int d = 0; d < 3; ++d)
        if (qs->periodic[d] && !(qs->cell_len[d] > 2.0 * cut))
            return sinter_fail(qs->ctx, SINTER_ERR_UNSUPPORTED,
                               "quasi-static stepper: the periodic cell along axis %d is %g m "
                               "long, not above twice the touching distance of the largest "
                               "spheres (%g m): a pair could touch through two images",
                               d, qs->cell_len[d], cut);
    /* at most 26 images of a sphere; grown as needed */
    size_t total = n;
    for (size_t s = 0; s < n; ++s) {
        int sides = 1;
        for (int d = 0; d < 3; ++d) {
            const double rel = x[3 * s + (size_t)d] - qs->cell_lo[d];
            if (qs->periodic[d] && (rel < cut || rel > qs->cell_len[d] - cut))
                sides *= (rel < cut && rel > qs->cell_len[d] - cut) ? 3 : 2;
        }
        total += (size_t)(sides - 1);
    }
    sinter_status st = sinter_grow(qs->ctx, (void **)&qs->ext_x, &qs->ext_x_capacity, 3 * total + 1,
                                   sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->ext_r, &qs->ext_r_capacity, total + 1,
                         sizeof(double));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->ext_owner, &qs->ext_owner_capacity, total + 1,
                         sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->ext_image, &qs->ext_image_capacity, 3 * total + 3,
                         sizeof(int32_t));
    if (st != SINTER_OK)
        return st;
    memcpy(qs->ext_x, x, 3 * n * sizeof(double));
    memcpy(qs->ext_r, r, n * sizeof(double));
    size_t e = n;
    for (size_t s = 0; s < n; ++s)
        add_images(qs, s, x, r, cut, &e);
    size_t found = 0;
    st = sinter_qs_touching_pairs(qs->ctx, e, qs->ext_x, qs->ext_r, qs->opt.contact_tolerance, 0.0,
                                  &qs->candidates, &qs->candidates_capacity, &found);
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->image_pairs, &qs->image_pairs_capacity, found + 1,
                         sizeof(sinter_qs_image_pair));
    if (st != SINTER_OK)
        return st;
    size_t m = 0;
    for (size_t c = 0; c < found; ++c) {
        const size_t a = (size_t)(qs->candidates[c] / e), b = (size_t)(qs->candidates[c] % e);
        if (a >= n)
            continue; /* two images: the pair of their owners is found between owned spheres */
        sinter_qs_image_pair q;
        memset(&q, 0, sizeof(q));
        if (b < n) {
            q.sa = (uint32_t)a;
            q.sb = (uint32_t)b;
        } else {
            const uint32_t o = qs->ext_owner[b];
            const int32_t *img = qs->ext_image + 3 * b;
            if (o == a)
                continue;           /* its own image: excluded by the cell's length */
            const int flip = o < a; /* A the smaller slot (id): B seen from A at -image */
            q.sa = flip ? o : (uint32_t)a;
            q.sb = flip ? (uint32_t)a : o;
            for (int d = 0; d < 3; ++d)
                q.image[d] = flip ? -img[d] : img[d];
        }
        qs->image_pairs[m++] = q;
    }
    /* a pair across a face is found from both ends (each near its face): once */
    qsort(qs->image_pairs, m, sizeof(sinter_qs_image_pair), image_pair_compare);
    size_t kept = 0;
    for (size_t c = 0; c < m; ++c)
        if (kept == 0 || image_pair_compare(&qs->image_pairs[kept - 1], &qs->image_pairs[c]) != 0)
            qs->image_pairs[kept++] = qs->image_pairs[c];
    *count = kept;
    return SINTER_OK;
}

/* x_B's image - x_A of link l (positions at t). */
static void link_vector(const sinter_qs *qs, const sinter_qs_particles *p, const sinter_qs_link *l,
                        double v[3])
{
    double xb[3];
    sinter_qs_image_of(qs, l->image, p->x + 3 * (size_t)l->beam.b, xb);
    for (int d = 0; d < 3; ++d)
        v[d] = xb[d] - p->x[3 * (size_t)l->beam.a + (size_t)d];
}

/* Solve the active rows of A eps = b (3 x 3, symmetric) by elimination; an axis whose pivot
 * vanishes (no link has a component along it) gets eps 0. */
static void solve3(double a[3][3], double b[3], const int active[3], double eps[3])
{
    int on[3];
    double diag[3];
    for (int d = 0; d < 3; ++d) {
        on[d] = active[d] && a[d][d] > 0.0;
        diag[d] = a[d][d];
        eps[d] = 0.0;
    }
    for (int p = 0; p < 3; ++p) {
        if (!on[p])
            continue;
        if (!(a[p][p] > 1e-12 * diag[p])) { /* dependent on the axes before it */
            on[p] = 0;
            continue;
        }
        for (int q = p + 1; q < 3; ++q) {
            if (!on[q])
                continue;
            const double f = a[q][p] / a[p][p];
            for (int c = p; c < 3; ++c)
                a[q][c] -= f * a[p][c];
            b[q] -= f * b[p];
        }
    }
    for (int p = 2; p >= 0; --p) {
        if (!on[p])
            continue;
        double s = b[p];
        for (int c = p + 1; c < 3; ++c)
            if (on[c])
                s -= a[p][c] * eps[c];
        eps[p] = s / a[p][p];
    }
}

sinter_status sinter_qs_cell_strain(sinter_qs *qs, const sinter_qs_particles *p, double *f)
{
    const size_t m = qs->count;
    sinter_status st = sinter_grow(qs->ctx, (void **)&qs->xi_affine, &qs->xi_affine_capacity, m + 1,
                                   sizeof(double));
    if (st != SINTER_OK)
        return st;
    double a[3][3] = {{0}}, b[3] = {0};
    for (size_t k = 0; k < m; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        const double dl = (qs->saved[k][SINTER_NECK_LA] - l->neck.y[SINTER_NECK_LA]) +
                          (qs->saved[k][SINTER_NECK_LB] - l->neck.y[SINTER_NECK_LB]);
        const double w = l->beam.k_axial * sinter_qs_section_scale(&qs->opt, l);
        double v[3];
        link_vector(qs, p, l, v);
        const double len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], len = sqrt(len2);
        /* l n_d^2 = v_d^2 / l; l^2 n_d^2 n_e^2 = v_d^2 v_e^2 / l^2 */
        for (int d = 0; d < 3; ++d) {
            b[d] += w * dl * v[d] * v[d] / len;
            for (int e = 0; e < 3; ++e)
                a[d][e] += w * v[d] * v[d] * v[e] * v[e] / len2;
        }
    }
    const int active[3] = {qs->periodic[0] && qs->opt.cell_strain != 0.0,
                           qs->periodic[1] && qs->opt.cell_strain != 0.0,
                           qs->periodic[2] && qs->opt.cell_strain != 0.0};
    solve3(a, b, active, qs->eps);
    const int any = qs->eps[0] != 0.0 || qs->eps[1] != 0.0 || qs->eps[2] != 0.0;
    for (size_t k = 0; k < m; ++k) {
        const sinter_qs_link *l = &qs->links[k];
        double v[3];
        link_vector(qs, p, l, v);
        /* the cell's approach of the link: (u_A - u_B') . e3 with u = -eps (x - lo) */
        double xi = 0.0;
        for (int d = 0; d < 3; ++d)
            xi += qs->eps[d] * v[d] * l->beam.axis[d];
        qs->xi_affine[k] = xi;
        if (!any)
            continue;
        /* the loads that hold that motion (eq. 40), off f: u stays the periodic rest */
        sinter_beam beam = l->beam;
        const double s = sinter_qs_section_scale(&qs->opt, l);
        beam.k_axial *= s;
        beam.k_shear *= s;
        beam.k_bend *= s * s;
        beam.k_torsion *= s * s;
        const double ya[6] = {0, 0, 0, 0, 0, 0};
        const double yb[6] = {-qs->eps[0] * v[0], -qs->eps[1] * v[1], -qs->eps[2] * v[2], 0, 0, 0};
        double pa[6] = {0, 0, 0, 0, 0, 0}, pb[6] = {0, 0, 0, 0, 0, 0};
        sinter_beam_apply(&beam, ya, yb, pa, pb);
        const size_t sa = qs->slot_of[l->beam.a], sb = qs->slot_of[l->beam.b];
        for (int d = 0; d < 6; ++d) {
            f[6 * sa + (size_t)d] -= pa[d];
            f[6 * sb + (size_t)d] -= pb[d];
        }
    }
    return SINTER_OK;
}

double sinter_qs_cell_distance2(const sinter_qs *qs, const sinter_qs_particles *p, size_t k,
                                const double *u)
{
    const sinter_qs_link *l = &qs->links[k];
    const size_t sa = qs->slot_of[l->beam.a], sb = qs->slot_of[l->beam.b];
    double v[3], d2 = 0.0;
    link_vector(qs, p, l, v);
    for (int d = 0; d < 3; ++d) {
        const double dd =
            v[d] * (1.0 - qs->eps[d]) + (u[6 * sb + (size_t)d] - u[6 * sa + (size_t)d]);
        d2 += dd * dd;
    }
    return d2;
}

void sinter_qs_cell_move(sinter_qs *qs, const sinter_qs_particles *p)
{
    for (int d = 0; d < 3; ++d) {
        if (!qs->periodic[d] || qs->eps[d] == 0.0)
            continue;
        for (size_t i = 0; i < p->count; ++i)
            p->x[3 * i + (size_t)d] -= qs->eps[d] * (p->x[3 * i + (size_t)d] - qs->cell_lo[d]);
        qs->cell_len[d] *= 1.0 - qs->eps[d];
    }
}

/* How many periods x lies above the cell (negative: below). */
static int32_t periods(const sinter_qs *qs, double x, int d)
{
    return (int32_t)floor((x - qs->cell_lo[d]) / qs->cell_len[d]);
}

void sinter_qs_cell_wrap(sinter_qs *qs, const sinter_qs_particles *p)
{
    for (size_t k = 0; k < qs->count; ++k) {
        sinter_qs_link *l = &qs->links[k];
        for (int d = 0; d < 3; ++d)
            if (qs->periodic[d]) /* x_B + image L - x_A unchanged */
                l->image[d] += periods(qs, p->x[3 * (size_t)l->beam.b + (size_t)d], d) -
                               periods(qs, p->x[3 * (size_t)l->beam.a + (size_t)d], d);
    }
    for (size_t i = 0; i < p->count; ++i)
        for (int d = 0; d < 3; ++d)
            if (qs->periodic[d]) {
                const int32_t w = periods(qs, p->x[3 * i + (size_t)d], d);
                if (w != 0)
                    p->x[3 * i + (size_t)d] -= (double)w * qs->cell_len[d];
            }
}
