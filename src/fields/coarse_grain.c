/*
 * Coarse graining (fields/coarse_grain.h): the particles' mass, volume, temperature and
 * momentum smeared by a kernel W onto a grid, and the stress of their contacts along the
 * contacts' branch lines (Goldhirsch 2010, the density, momentum and stress fields of sec. 2;
 * Weinhart et al. 2012 for the wall contacts, whose branch runs from the centre to the contact
 * point; docs/models.md).
 *
 * W is a Gaussian of standard deviation w cut at c = cutoff * w and normalised over the ball
 * of radius c, so that its integral over space is exactly 1 and each particle's mass (each
 * contact's virial) is conserved by the fields.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/id_row.h"
#include "fields/coarse_grain.h"
#include "particles/particles.h"

/* Points of the Gauss-Legendre rule on each piece of a branch line (no longer than w). */
enum { LINE_NODES = 3 };

static const double PI = 3.14159265358979323846;
static const double SQRT2 = 1.41421356237309504880;

sinter_status sinter_coarse_options_init(sinter_coarse_options *options, size_t struct_size)
{
    if (options == NULL)
        return SINTER_ERR_NULL;
    if (struct_size != sizeof(sinter_coarse_options))
        return SINTER_ERR_STRUCT_SIZE;
    memset(options, 0, sizeof(*options));
    options->struct_size = struct_size;
    for (int d = 0; d < 3; ++d) {
        options->spacing[d] = 1e-3;
        options->points[d] = 1;
    }
    options->width = 1e-3;
    options->cutoff = 3.0;
    return SINTER_OK;
}

static const struct {
    const char *name, *unit;
    size_t components;
} QUANTITY[SINTER_COARSE_COUNT_] = {{"solid_fraction", "1", 1},
                                    {"density", "kg/m^3", 1},
                                    {"temperature", "K", 1},
                                    {"velocity", "m/s", 3},
                                    {"stress", "Pa", 9}};

sinter_status sinter_coarse_quantity_info(sinter_coarse_quantity quantity, const char **name,
                                          const char **unit, size_t *components)
{
    if ((int)quantity < 0 || quantity >= SINTER_COARSE_COUNT_)
        return SINTER_ERR_RANGE;
    if (name != NULL)
        *name = QUANTITY[quantity].name;
    if (unit != NULL)
        *unit = QUANTITY[quantity].unit;
    if (components != NULL)
        *components = QUANTITY[quantity].components;
    return SINTER_OK;
}

/* Most grid points (9 doubles each must be addressable). */
static const double MAX_POINTS = 1e9;

sinter_status sinter_coarse_check(sinter_ctx *ctx, const char *fn, const sinter_coarse_options *o)
{
    if (o->struct_size != sizeof(*o))
        return sinter_fail(ctx, SINTER_ERR_STRUCT_SIZE,
                           "%s: options.struct_size is %zu, expected %zu", fn, o->struct_size,
                           sizeof(*o));
    double points = 1.0;
    for (int d = 0; d < 3; ++d) {
        if (!isfinite(o->origin[d]) || !(o->spacing[d] > 0) || !isfinite(o->spacing[d]))
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: need a finite origin and spacing > 0 m along axis %d", fn, d);
        if (o->points[d] < 1)
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: need points >= 1 along axis %d", fn,
                               d);
        points *= (double)o->points[d];
    }
    if (points > MAX_POINTS)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: %g grid points, at most %g", fn, points,
                           MAX_POINTS);
    if (!(o->width > 0) || !isfinite(o->width))
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: need a kernel width > 0 m", fn);
    if (!(o->cutoff >= 1.0 && o->cutoff <= 10.0))
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: need 1 <= cutoff <= 10 (widths)", fn);
    return SINTER_OK;
}

/* The kernel and the grid it is sampled on. */
typedef struct kernel {
    const sinter_coarse_options *o;
    double reach;      /* c = cutoff w [m] */
    double inv_two_w2; /* 1 / (2 w^2) */
    double scale;      /* 1 / the Gaussian's integral over the ball of radius c */
    /* per axis, for the grid lines in reach of a point: the squared distance and the factor
     * exp(-d^2 / 2 w^2) of the separable Gaussian (owned; `span` entries each) */
    double *d2[3], *factor[3];
    size_t span[3];
} kernel;

static void kernel_free(sinter_ctx *ctx, kernel *k)
{
    for (int d = 0; d < 3; ++d) {
        sinter_free(ctx, k->d2[d]);
        sinter_free(ctx, k->factor[d]);
    }
}

static sinter_status kernel_make(sinter_ctx *ctx, const sinter_coarse_options *o, kernel *k)
{
    const double c = o->cutoff, w = o->width;
    memset(k, 0, sizeof(*k));
    k->o = o;
    k->reach = c * w;
    k->inv_two_w2 = 1.0 / (2.0 * w * w);
    /* integral of exp(-r^2 / 2 w^2) over |r| < c w:
     * (2 pi w^2)^(3/2) [erf(c / sqrt 2) - sqrt(2 / pi) c exp(-c^2 / 2)] */
    const double whole = pow(2.0 * PI * w * w, 1.5);
    k->scale = 1.0 / (whole * (erf(c / SQRT2) - sqrt(2.0 / PI) * c * exp(-0.5 * c * c)));
    for (int d = 0; d < 3; ++d) {
        const double lines = 2.0 * ceil(k->reach / o->spacing[d]) + 3.0;
        k->span[d] = lines < (double)o->points[d] ? (size_t)lines : o->points[d];
        k->d2[d] = sinter_calloc(ctx, k->span[d], sizeof(double));
        k->factor[d] = sinter_calloc(ctx, k->span[d], sizeof(double));
        if (k->d2[d] == NULL || k->factor[d] == NULL) {
            kernel_free(ctx, k);
            return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_coarse_grain: out of memory");
        }
    }
    return SINTER_OK;
}

/* The grid indices lo..hi (inclusive; lo > hi: none) within the kernel's reach of p along d. */
static void reach_range(const kernel *k, const double p[3], int d, long *lo, long *hi)
{
    const sinter_coarse_options *o = k->o;
    const double a = (p[d] - k->reach - o->origin[d]) / o->spacing[d];
    const double b = (p[d] + k->reach - o->origin[d]) / o->spacing[d];
    const double top = (double)o->points[d] - 1.0;
    *lo = a <= 0 ? 0 : (a > top ? (long)o->points[d] : (long)ceil(a));
    *hi = b >= top ? (long)top : (b < 0 ? -1 : (long)floor(b));
}

/*
 * Add value[c] * weight * W(g - p) to acc[point * n + c] at every grid point g in reach of p.
 */
static void scatter(const kernel *k, const double p[3], double weight, const double *value,
                    size_t n, double *acc)
{
    const sinter_coarse_options *o = k->o;
    long lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        reach_range(k, p, d, &lo[d], &hi[d]);
        if (lo[d] > hi[d])
            return;
        /* the Gaussian is separable: one exp per grid line, not per point */
        for (long g = lo[d]; g <= hi[d] && (size_t)(g - lo[d]) < k->span[d]; ++g) {
            const double delta = o->origin[d] + (double)g * o->spacing[d] - p[d];
            k->d2[d][g - lo[d]] = delta * delta;
            k->factor[d][g - lo[d]] = exp(-delta * delta * k->inv_two_w2);
        }
        if ((size_t)(hi[d] - lo[d]) >= k->span[d]) /* (not reached: span covers the reach) */
            hi[d] = lo[d] + (long)k->span[d] - 1;
    }
    const double r2max = k->reach * k->reach, scaled = weight * k->scale;
    for (long kz = lo[2]; kz <= hi[2]; ++kz) {
        const double dz2 = k->d2[2][kz - lo[2]], fz = scaled * k->factor[2][kz - lo[2]];
        for (long ky = lo[1]; ky <= hi[1]; ++ky) {
            const double dyz2 = dz2 + k->d2[1][ky - lo[1]];
            const double fyz = fz * k->factor[1][ky - lo[1]];
            if (dyz2 > r2max)
                continue;
            const size_t row = ((size_t)kz * o->points[1] + (size_t)ky) * o->points[0];
            for (long kx = lo[0]; kx <= hi[0]; ++kx) {
                if (dyz2 + k->d2[0][kx - lo[0]] > r2max)
                    continue;
                const double wk = fyz * k->factor[0][kx - lo[0]];
                double *q = acc + (row + (size_t)kx) * n;
                for (size_t c = 0; c < n; ++c)
                    q[c] += wk * value[c];
            }
        }
    }
}

/*
 * The stress of one contact: -f (x) b times the integral of W along the line from p0 (the
 * centre of the particle the force f acts on) to p1 = p0 - b (the other centre or the contact
 * point): Goldhirsch 2010's contact stress, with Weinhart et al. 2012's b = r_i - c_ik for a
 * wall contact.
 * The line is cut into pieces no longer than w, each integrated by Gauss-Legendre.
 */
static void scatter_contact(const kernel *k, const double p0[3], const double f[3],
                            const double b[3], double *stress)
{
    static const double node[LINE_NODES] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
    static const double weight[LINE_NODES] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    double tensor[9];
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
            tensor[3 * a + c] = -f[a] * b[c];
    const double length = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    const double pieces = fmax(1.0, ceil(length / k->o->width));
    const size_t m = pieces < 1e6 ? (size_t)pieces : 1000000;
    for (size_t s = 0; s < m; ++s)
        for (int q = 0; q < LINE_NODES; ++q) {
            /* fraction of the way from p0 to p1, and the node's share of the unit integral */
            const double t = ((double)s + 0.5 + 0.5 * node[q]) / (double)m;
            const double p[3] = {p0[0] - t * b[0], p0[1] - t * b[1], p0[2] - t * b[2]};
            scatter(k, p, 0.5 * weight[q] / (double)m, tensor, 9, stress);
        }
}

/* The contacts' stress of the snapshot. */
static sinter_status contact_stress(const sinter_particles *ps, const sinter_snapshot *snap,
                                    const kernel *k, size_t owned, double *stress)
{
    sinter_ctx *ctx = ps->ctx;
    static const char *const fn = "sinter_coarse_grain";
    size_t pairs = 0, walls = 0;
    sinter_status st = sinter_snapshot_counts(snap, &pairs, &walls, NULL, NULL);
    const void *raw[5] = {NULL, NULL, NULL, NULL, NULL};
    static const sinter_contact_data WANT[5] = {
        SINTER_CONTACT_DATA_ID_A, SINTER_CONTACT_DATA_ID_B, SINTER_CONTACT_DATA_NORMAL,
        SINTER_CONTACT_DATA_OVERLAP, SINTER_CONTACT_DATA_NORMAL_FORCE};
    const void *tangential_raw = NULL;
    if (st == SINTER_OK && pairs + walls == 0)
        return SINTER_OK;
    for (int q = 0; q < 5 && st == SINTER_OK; ++q)
        st = sinter_snapshot_contacts(snap, WANT[q], &raw[q], NULL, NULL, NULL);
    if (st == SINTER_OK)
        st = sinter_snapshot_contacts(snap, SINTER_CONTACT_DATA_TANGENTIAL_FORCE, &tangential_raw,
                                      NULL, NULL, NULL);
    if (st != SINTER_OK)
        return sinter_fail(ctx, st, "%s: the snapshot's contacts cannot be read", fn);
    const uint64_t *id_a = raw[0], *id_b = raw[1];
    const double *n = raw[2], *delta = raw[3], *force = raw[4], *tangential = tangential_raw;
    const size_t np = ps->count;
    sinter_id_row *map = sinter_calloc(ctx, np ? np : 1, sizeof(*map));
    if (map == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "%s: out of memory", fn);
    for (size_t i = 0; i < np; ++i) {
        map[i].id = ps->id[i];
        map[i].index = i;
    }
    qsort(map, np, sizeof(*map), sinter_id_row_compare);
    for (size_t c = 0; c < pairs + walls; ++c) {
        const sinter_id_row key_a = {id_a[c], 0}, key_b = {c < pairs ? id_b[c] : 0, 0};
        const sinter_id_row *a =
            np ? bsearch(&key_a, map, np, sizeof(*map), sinter_id_row_compare) : NULL;
        const sinter_id_row *b =
            c < pairs && np ? bsearch(&key_b, map, np, sizeof(*map), sinter_id_row_compare) : a;
        if (a == NULL || b == NULL) {
            st = sinter_fail(ctx, SINTER_ERR_INVALID,
                             "%s: contact %zu's particles are not among the particles (a "
                             "snapshot of other particles?)",
                             fn, c);
            break;
        }
        const size_t i = a->index;
        /* a pair once over the subdomains: where its smaller id is owned (sinter_coarse_sums) */
        if ((c < pairs && id_b[c] < id_a[c] ? b->index : i) >= owned)
            continue;
        const double *nc = n + 3 * c;
        /* how far the other end lies along n: the other centre at r_a + r_b - delta, the
         * wall's contact point (on its plane) at r_a - delta */
        const double reach = ps->radius[i] - delta[c] + (c < pairs ? ps->radius[b->index] : 0.0);
        double f[3], branch[3];
        for (int d = 0; d < 3; ++d) {
            /* the force on a: the normal force (> 0 compressive) pushes it against n */
            f[d] = -force[c] * nc[d] + tangential[3 * c + (size_t)d];
            branch[d] = -reach * nc[d];
        }
        scatter_contact(k, ps->x + 3 * i, f, branch, stress);
    }
    sinter_free(ctx, map);
    return st;
}

void sinter_coarse_fields_free(sinter_ctx *ctx, sinter_coarse_fields *f)
{
    if (f == NULL)
        return;
    sinter_free(ctx, f->solid);
    sinter_free(ctx, f->density);
    sinter_free(ctx, f->temperature);
    sinter_free(ctx, f->velocity);
    sinter_free(ctx, f->stress);
    memset(f, 0, sizeof(*f));
}

sinter_status sinter_coarse_accumulate(const sinter_particles *ps, const sinter_snapshot *snap,
                                       const sinter_coarse_options *o, size_t owned, double *sums)
{
    const size_t points = o->points[0] * o->points[1] * o->points[2];
    kernel k;
    sinter_status st = kernel_make(ps->ctx, o, &k);
    if (st != SINTER_OK)
        return st;
    double *acc = sums, *stress = sums + SINTER_COARSE_PARTICLE_SUMS * points;
    for (size_t i = 0; i < owned && i < ps->count; ++i) {
        const double r = ps->radius[i], m = ps->mass[i], *v = ps->v + 3 * i;
        double value[SINTER_COARSE_PARTICLE_SUMS] = {
            4.0 / 3.0 * PI * r * r * r, m, m * ps->temperature[i], m * v[0], m * v[1], m * v[2]};
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c)
                value[6 + 3 * a + c] = m * v[a] * v[c];
        scatter(&k, ps->x + 3 * i, 1.0, value, SINTER_COARSE_PARTICLE_SUMS, acc);
    }
    st = snap != NULL ? contact_stress(ps, snap, &k, owned, stress) : SINTER_OK;
    kernel_free(ps->ctx, &k);
    return st;
}

sinter_status sinter_coarse_fields_from_sums(sinter_ctx *ctx, size_t points, const double *sums,
                                             sinter_coarse_fields *out)
{
    memset(out, 0, sizeof(*out));
    out->points = points;
    out->solid = sinter_calloc(ctx, points, sizeof(double));
    out->density = sinter_calloc(ctx, points, sizeof(double));
    out->temperature = sinter_calloc(ctx, points, sizeof(double));
    out->velocity = sinter_calloc(ctx, points, 3 * sizeof(double));
    out->stress = sinter_calloc(ctx, points, 9 * sizeof(double));
    if (out->solid == NULL || out->density == NULL || out->temperature == NULL ||
        out->velocity == NULL || out->stress == NULL) {
        sinter_coarse_fields_free(ctx, out);
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_coarse_grain: out of memory");
    }
    const double *stress = sums + SINTER_COARSE_PARTICLE_SUMS * points;
    for (size_t p = 0; p < points; ++p) {
        const double *q = sums + SINTER_COARSE_PARTICLE_SUMS * p, rho = q[1];
        double *vel = out->velocity + 3 * p, *s = out->stress + 9 * p;
        out->solid[p] = q[0];
        out->density[p] = rho;
        out->temperature[p] = rho > 0 ? q[2] / rho : NAN;
        for (int a = 0; a < 3; ++a)
            vel[a] = rho > 0 ? q[3 + a] / rho : 0.0;
        /* the contacts' stress less the kinetic -sum m v' v' W with v' = v - V (Goldhirsch
         * 2010): -(sum m v v W - rho V V) */
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c)
                s[3 * a + c] = stress[9 * p + 3 * (size_t)a + (size_t)c] -
                               (q[6 + 3 * a + c] - rho * vel[a] * vel[c]);
    }
    return SINTER_OK;
}

sinter_status sinter_coarse_fields_compute(const sinter_particles *ps, const sinter_snapshot *snap,
                                           const sinter_coarse_options *o,
                                           sinter_coarse_fields *out)
{
    sinter_ctx *ctx = ps->ctx;
    memset(out, 0, sizeof(*out));
    const size_t points = o->points[0] * o->points[1] * o->points[2];
    double *sums = sinter_calloc(ctx, points, (SINTER_COARSE_PARTICLE_SUMS + 9) * sizeof(double));
    if (sums == NULL)
        return sinter_fail(ctx, SINTER_ERR_NOMEM, "sinter_coarse_grain: out of memory");
    sinter_status st = sinter_coarse_accumulate(ps, snap, o, ps->count, sums);
    if (st == SINTER_OK)
        st = sinter_coarse_fields_from_sums(ctx, points, sums, out);
    sinter_free(ctx, sums);
    return st;
}

sinter_status sinter_coarse_grain(const sinter_particles *ps, const sinter_snapshot *snapshot,
                                  const sinter_coarse_options *options,
                                  sinter_coarse_quantity quantity, double *out, size_t out_count)
{
    static const char *const fn = "sinter_coarse_grain";
    if (ps == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = ps->ctx;
    SINTER_CHECK_NULL(ctx, options);
    SINTER_CHECK_NULL(ctx, out);
    size_t components = 0;
    if (sinter_coarse_quantity_info(quantity, NULL, NULL, &components) != SINTER_OK)
        return sinter_fail(ctx, SINTER_ERR_RANGE, "%s: unknown quantity %d", fn, (int)quantity);
    sinter_status st = sinter_coarse_check(ctx, fn, options);
    if (st != SINTER_OK)
        return st;
    const size_t points = options->points[0] * options->points[1] * options->points[2];
    if (out_count != points * components)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: out_count is %zu, the grid's %zu points need %zu", fn, out_count,
                           points, points * components);
    sinter_coarse_fields f;
    st = sinter_coarse_fields_compute(ps, quantity == SINTER_COARSE_STRESS ? snapshot : NULL,
                                      options, &f);
    if (st != SINTER_OK)
        return st;
    const double *src[SINTER_COARSE_COUNT_] = {f.solid, f.density, f.temperature, f.velocity,
                                               f.stress};
    memcpy(out, src[quantity], points * components * sizeof(double));
    sinter_coarse_fields_free(ctx, &f);
    return SINTER_OK;
}
