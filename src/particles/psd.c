/*
 * Powder size distributions (issue 38): the quantiles (D10, D50, D90) of a particle set, by
 * number or by volume, and the reader of a tabulated cumulative distribution from a CSV file.
 * The sampling lives with the packer (packing.c).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/text_file.h"
#include "particles.h"

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

sinter_status sinter_particles_size_quantiles(const sinter_particles *particles, size_t first,
                                              size_t count, int basis, size_t nfractions,
                                              const double *fractions, double *diameters)
{
    static const char *func = "sinter_particles_size_quantiles";
    if (particles == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = particles->ctx;
    if (nfractions > 0) {
        SINTER_CHECK_NULL(ctx, fractions);
        SINTER_CHECK_NULL(ctx, diameters);
    }
    if (count == 0 || first > particles->count || count > particles->count - first)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: particles %zu .. %zu + %zu are not a non-empty range of the %zu "
                           "in the set",
                           func, first, first, count, particles->count);
    if (basis != SINTER_SIZE_BY_NUMBER && basis != SINTER_SIZE_BY_VOLUME)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: basis = %d is not a sinter_size_basis",
                           func, basis);
    for (size_t k = 0; k < nfractions; ++k)
        if (!(fractions[k] >= 0.0 && fractions[k] <= 1.0))
            return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: fractions[%zu] = %g is outside [0, 1]",
                               func, k, fractions[k]);
    double *d = sinter_realloc_array(ctx, NULL, count, sizeof(double));
    if (d == NULL)
        return sinter_last_status(ctx);
    for (size_t i = 0; i < count; ++i)
        d[i] = 2.0 * particles->radius[first + i];
    qsort(d, count, sizeof(double), compare_double);
    double total = 0.0;
    for (size_t i = 0; i < count; ++i)
        total += basis == SINTER_SIZE_BY_VOLUME ? d[i] * d[i] * d[i] : 1.0;
    for (size_t k = 0; k < nfractions; ++k) {
        /* the smallest d[i] whose cumulative weight reaches the fraction */
        const double target = fractions[k] * total;
        double sum = 0.0;
        size_t i = 0;
        for (; i + 1 < count; ++i) {
            sum += basis == SINTER_SIZE_BY_VOLUME ? d[i] * d[i] * d[i] : 1.0;
            if (sum >= target)
                break;
        }
        diameters[k] = d[i];
    }
    sinter_free(ctx, d);
    return SINTER_OK;
}

/* ---- CSV tables ------------------------------------------------------------------- */

/* Relative tolerance on the last cumulative value (1 or 100 %): within it, normalised. */
#define PSD_NORMALISATION_TOLERANCE 0.01

typedef struct psd_reader {
    sinter_ctx *ctx;
    const char *path;
    double unit, full; /* full scale: 1 or 100 */
    double *d, *q;
    size_t capacity, rows;
    double last_d, last_q;
    int last_line, header_allowed;
} psd_reader;

/* Two numbers separated by a comma, semicolon, tab or spaces, nothing after: 1, else 0. */
static int parse_row(char *text, double *a, double *b)
{
    for (char *c = text; *c; ++c)
        if (*c == ',' || *c == ';' || *c == '\t' || *c == '\r')
            *c = ' ';
    char *end = NULL;
    *a = strtod(text, &end);
    if (end == text)
        return 0;
    char *next = end;
    *b = strtod(next, &end);
    if (end == next)
        return 0;
    while (*end == ' ')
        ++end;
    return *end == '\0';
}

static sinter_status psd_line(void *user, int line, char *text)
{
    psd_reader *r = user;
    char *hash = strchr(text, '#');
    if (hash)
        *hash = '\0';
    const char *c = text;
    while (*c == ' ' || *c == '\t' || *c == '\r')
        ++c;
    if (*c == '\0')
        return SINTER_OK;
    char copy[512];
    snprintf(copy, sizeof(copy), "%s", c);
    double size, value;
    if (!parse_row(copy, &size, &value)) {
        if (r->header_allowed) {
            r->header_allowed = 0;
            return SINTER_OK;
        }
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: expected 'diameter, cumulative' (two numbers), got '%.40s'",
                           r->path, line, c);
    }
    r->header_allowed = 0;
    const double d = size * r->unit;
    if (!isfinite(d) || !(d > 0.0))
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: diameter %g must be positive and finite (a size cannot be "
                           "negative or zero)",
                           r->path, line, size);
    if (!isfinite(value) || value < 0.0 || value > r->full * (1.0 + PSD_NORMALISATION_TOLERANCE))
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: cumulative value %g must be in [0, %g]", r->path, line, value,
                           r->full);
    if (r->rows > 0 && !(d > r->last_d))
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: diameter %g is not larger than the one on line %d; the table "
                           "must list increasing sizes",
                           r->path, line, size, r->last_line);
    if (r->rows > 0 && value < r->last_q)
        return sinter_fail(r->ctx, SINTER_ERR_PARSE,
                           "%s:%d: cumulative value %g is below %g on line %d; a cumulative "
                           "distribution never decreases",
                           r->path, line, value, r->last_q, r->last_line);
    if (r->capacity > 0) {
        if (r->rows == r->capacity)
            return sinter_fail(r->ctx, SINTER_ERR_INVALID,
                               "sinter_psd_read_csv: '%s' has more than capacity = %zu rows",
                               r->path, r->capacity);
        r->d[r->rows] = d;
        r->q[r->rows] = value / r->full;
    }
    r->rows++;
    r->last_d = d;
    r->last_q = value;
    r->last_line = line;
    return SINTER_OK;
}

sinter_status sinter_psd_read_csv(sinter_ctx *ctx, const char *path, double unit, int percent,
                                  double *diameter, double *cumulative, size_t capacity,
                                  size_t *count)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, path);
    SINTER_CHECK_NULL(ctx, count);
    *count = 0;
    if (capacity > 0) {
        SINTER_CHECK_NULL(ctx, diameter);
        SINTER_CHECK_NULL(ctx, cumulative);
    }
    if (!isfinite(unit) || !(unit > 0.0))
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_psd_read_csv: unit = %g m must be positive and finite", unit);
    if (percent != 0 && percent != 1)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "sinter_psd_read_csv: percent = %d is not 0 or 1", percent);
    psd_reader r;
    memset(&r, 0, sizeof(r));
    r.ctx = ctx;
    r.path = path;
    r.unit = unit;
    r.full = percent ? 100.0 : 1.0;
    r.d = diameter;
    r.q = cumulative;
    r.capacity = capacity;
    r.header_allowed = 1;
    FILE *f = NULL;
    sinter_status st = sinter_text_open(ctx, "", "size distribution file", path, &f);
    if (st != SINTER_OK)
        return st;
    char buf[512];
    st = sinter_text_each_line(ctx, f, path, "a size distribution", buf, sizeof(buf), psd_line, &r);
    fclose(f);
    if (st != SINTER_OK)
        return st;
    if (r.rows == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: no 'diameter, cumulative' rows", path);
    if (!(fabs(r.last_q - r.full) <= PSD_NORMALISATION_TOLERANCE * r.full))
        return sinter_fail(ctx, SINTER_ERR_PARSE,
                           "%s:%d: the last cumulative value is %g, not %g within 1 %%: the "
                           "table is not normalised (is it a density, or %s?)",
                           path, r.last_line, r.last_q, r.full,
                           percent ? "a fraction" : "in percent");
    if (capacity > 0) /* normalise: the table ends at exactly 1 */
        for (size_t i = 0; i < r.rows; ++i)
            cumulative[i] /= r.last_q / r.full;
    *count = r.rows;
    return SINTER_OK;
}
