/* [fields] over the ranks (run_mpi_fields.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mpi.h>
#include <sinter_domain.h>

#include "run_mpi_fields.h"
#include "trim_line.h"

enum { LINE_SIZE = 1024, PATH_SIZE = 4096 };

/* Up to three numbers separated by blanks, commas or semicolons (the scene parser's form). */
static void numbers(const char *text, double *out, int n)
{
    const char *p = text;
    for (int k = 0; k < n; ++k) {
        while (*p == ' ' || *p == '\t' || *p == ',' || *p == ';')
            ++p;
        char *end = NULL;
        out[k] = strtod(p, &end);
        p = end;
    }
}

static int yes(const char *value)
{
    return strcmp(value, "no") != 0 && strcmp(value, "false") != 0 && strcmp(value, "0") != 0;
}

void run_mpi_fields_read(const char *path, run_mpi_fields *f)
{
    memset(f, 0, sizeof(*f));
    f->grid = f->frames = 1;
    f->flags = 1; /* binary arrays by default, as the scene's frames */
    f->cutoff = 3.0;
    f->laminae = 20.0;
    int spacing = 0, have_lo = 0, have_hi = 0;
    FILE *fp = fopen(path, "r");
    if (fp == NULL)
        return;
    char line[LINE_SIZE], section[LINE_SIZE] = "";
    while (fgets(line, sizeof(line), fp) != NULL) {
        char *hash = strchr(line, '#');
        if (hash != NULL)
            *hash = '\0';
        trim(line);
        if (line[0] == '[') {
            char *end = strchr(line, ']');
            if (end != NULL) {
                *end = '\0';
                snprintf(section, sizeof(section), "%s", line + 1);
                trim(section);
                f->on |= strcmp(section, "fields") == 0;
            }
            continue;
        }
        char *eq = strchr(line, '=');
        if (eq == NULL)
            continue;
        *eq = '\0';
        char *key = line, *value = eq + 1;
        trim(key);
        trim(value);
        if (strcmp(section, "fields") == 0) {
            if (strcmp(key, "width") == 0)
                f->width = strtod(value, NULL);
            else if (strcmp(key, "spacing") == 0) {
                f->spacing = strtod(value, NULL);
                spacing = 1;
            } else if (strcmp(key, "cutoff") == 0)
                f->cutoff = strtod(value, NULL);
            else if (strcmp(key, "laminae") == 0)
                f->laminae = strtod(value, NULL);
            else if (strcmp(key, "grid") == 0)
                f->grid = yes(value);
            else if (strcmp(key, "box_min") == 0) {
                numbers(value, f->lo, 3);
                have_lo = 1;
            } else if (strcmp(key, "box_max") == 0) {
                numbers(value, f->hi, 3);
                have_hi = 1;
            } else if (strcmp(key, "profiles") == 0 && strcmp(value, "none") != 0)
                for (const char *c = value; *c >= 'x' && *c <= 'z'; ++c)
                    f->profiles |= 1u << (*c - 'x');
        } else if (strcmp(section, "output") == 0) {
            if (strcmp(key, "vtu") == 0)
                f->frames = yes(value);
            else if (strcmp(key, "vtu_format") == 0) {
                f->flags = (f->flags & ~1) | (strcmp(value, "ascii") != 0 ? 1 : 0);
                f->appended = strcmp(value, "appended") == 0;
            } else if (strcmp(key, "vtu_precision") == 0)
                f->flags = (f->flags & ~2) | (strcmp(value, "single") == 0 ? 2 : 0);
        } else if (strcmp(section, "stepper") == 0) {
            if (strcmp(key, "domain_min") == 0) {
                numbers(value, f->domain_lo, 3);
                f->domain |= 1;
            } else if (strcmp(key, "domain_max") == 0) {
                numbers(value, f->domain_hi, 3);
                f->domain |= 2;
            }
        }
    }
    fclose(fp);
    if (!spacing)
        f->spacing = f->width;
    f->box = have_lo && have_hi;
    f->domain = f->domain == 3;
}

/* The owned particles' bounding box over every rank (scene_frames.c's particle_box: a unit box
 * about the origin without particles); min and max are exact in any order. */
static int particle_box(sinter_particles *ps, sinter_mpi_domain *domain, double lo[3], double hi[3],
                        double *count)
{
    const double *x = NULL, *rad = NULL;
    size_t owned = 0;
    int ok = sinter_particles_owned_count(ps, &owned) == SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL) ==
                 SINTER_OK &&
             sinter_particles_view_read(ps, SINTER_FIELD_RADIUS, (const void **)&rad, NULL, NULL) ==
                 SINTER_OK;
    /* -lo and hi, each a max */
    double box[6] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; ok && i < owned; ++i)
        for (int d = 0; d < 3; ++d) {
            box[d] = fmax(box[d], -(x[3 * i + (size_t)d] - rad[i]));
            box[3 + d] = fmax(box[3 + d], x[3 * i + (size_t)d] + rad[i]);
        }
    if (x != NULL)
        sinter_particles_release(ps, SINTER_FIELD_POSITION);
    if (rad != NULL)
        sinter_particles_release(ps, SINTER_FIELD_RADIUS);
    double n = ok ? (double)owned : -1.0;
    ok = sinter_mpi_reduce(box, 6, SINTER_MPI_F64, SINTER_MPI_MAX, domain) == 0 && ok;
    ok = sinter_mpi_reduce(&n, 1, SINTER_MPI_F64, SINTER_MPI_SUM, domain) == 0 && ok;
    *count = n;
    for (int d = 0; d < 3; ++d) {
        lo[d] = n > 0 ? -box[d] : -0.5;
        hi[d] = n > 0 ? box[3 + d] : 0.5;
    }
    return ok;
}

/* The grid (scene_frames.c's field_grid): box_min..box_max, else the stepper's domain, else
 * the particles' box grown by a tenth of its diagonal, at the scene's spacing. */
static void field_grid(const run_mpi_fields *f, const double plo[3], const double phi[3], double n,
                       sinter_coarse_options *o)
{
    double lo[3], hi[3];
    (void)sinter_coarse_options_init(o, sizeof(*o));
    double diagonal = 0.0;
    for (int d = 0; d < 3; ++d)
        diagonal += n > 0 ? (phi[d] - plo[d]) * (phi[d] - plo[d]) : 0.0;
    const double grow = n > 0 ? 0.1 * sqrt(diagonal) : 1.0;
    for (int d = 0; d < 3; ++d) {
        lo[d] = f->box ? f->lo[d] : f->domain ? f->domain_lo[d] : n > 0 ? plo[d] - grow : -grow;
        hi[d] = f->box ? f->hi[d] : f->domain ? f->domain_hi[d] : n > 0 ? phi[d] + grow : grow;
    }
    for (int d = 0; d < 3; ++d) {
        const double cells = floor((hi[d] - lo[d]) / f->spacing * (1 + 1e-12));
        o->origin[d] = lo[d];
        o->spacing[d] = f->spacing;
        o->points[d] = cells >= 0 && cells < 1e9 ? (size_t)cells + 1 : (size_t)1e9;
    }
    o->width = f->width;
    o->cutoff = f->cutoff;
}

/* The worst of every rank's status (0 or -1). */
static int agree(int ok)
{
    int status = ok ? 0 : -1, worst = status;
    MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return worst == 0;
}

static void out_double(FILE *fp, double value)
{
    if (isnan(value))
        fputs("nan", fp);
    else if (isinf(value))
        fputs(value > 0.0 ? "inf" : "-inf", fp);
    else
        fprintf(fp, "%.17g", value);
}

/* frames/profile_<axis>_NNNNN.csv (scene_frames.c's write_profile): the laminae's sums over
 * the ranks, their ratios on rank 0. */
static int write_profile(const run_mpi_fields *f, sinter_particles *ps, sinter_mpi_domain *domain,
                         int rank, const char *out_dir, unsigned long long frame, int axis,
                         const double plo[3], const double phi[3])
{
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        lo[d] = f->box ? f->lo[d] : plo[d];
        hi[d] = f->box ? f->hi[d] : phi[d];
        if (!(hi[d] > lo[d])) /* one particle layer across a plane: give it width */
            hi[d] = lo[d] + 1.0;
    }
    const size_t n = (size_t)f->laminae;
    double *sums = calloc(2 * n, sizeof(double));
    if (!agree(sums != NULL)) {
        free(sums);
        return 0;
    }
    int ok = sinter_lamina_sums(ps, axis, lo, hi, n, sums) == SINTER_OK;
    ok = sinter_mpi_reduce(sums, 2 * n, SINTER_MPI_F64, SINTER_MPI_SUM, domain) == 0 && ok;
    if (ok && rank == 0) {
        char path[PATH_SIZE];
        snprintf(path, sizeof(path), "%s/frames/profile_%c_%05llu.csv", out_dir, 'x' + axis, frame);
        FILE *fp = fopen(path, "w");
        ok = fp != NULL;
        double section = 1.0;
        for (int d = 0; d < 3; ++d)
            if (d != axis)
                section *= hi[d] - lo[d];
        const double q = (hi[axis] - lo[axis]) / (double)n;
        if (fp != NULL) {
            fputs("position [m],solid_fraction [1],temperature [K]\n", fp);
            for (size_t s = 0; s < n; ++s) {
                out_double(fp, lo[axis] + ((double)s + 0.5) * q); /* lamina centre */
                fputc(',', fp);
                out_double(fp, sums[s] / (section * q)); /* seed 001 eq. 48 */
                fputc(',', fp);
                out_double(fp, sums[s] > 0 ? sums[n + s] / sums[s] : NAN);
                fputc('\n', fp);
            }
            ok = fclose(fp) == 0;
        }
    }
    free(sums);
    return ok;
}

/* frames/fields_NNNNN.vti: the grid's sums over the ranks, the fields formed on rank 0. */
static int write_grid(const run_mpi_fields *f, sinter_ctx *ctx, sinter_stepper *st,
                      sinter_particles *ps, sinter_mpi_domain *domain, int rank,
                      const char *out_dir, unsigned long long frame,
                      const sinter_coarse_options *grid)
{
    const size_t count =
        grid->points[0] * grid->points[1] * grid->points[2] * (size_t)SINTER_COARSE_SUMS;
    double *sums = calloc(count, sizeof(double));
    if (!agree(sums != NULL)) {
        free(sums);
        return 0;
    }
    /* a state not evaluated yet (the first sample) has no contacts: no snapshot, as serially */
    sinter_snapshot *snap = NULL;
    if (sinter_snapshot_create(&snap, st) != SINTER_OK)
        snap = NULL;
    int ok = sinter_coarse_sums(ps, snap, grid, sums, count) == SINTER_OK;
    sinter_snapshot_destroy(snap);
    ok = sinter_mpi_reduce(sums, count, SINTER_MPI_F64, SINTER_MPI_SUM, domain) == 0 && ok;
    if (ok && rank == 0) {
        char path[PATH_SIZE];
        snprintf(path, sizeof(path), "%s/frames/fields_%05llu.vti", out_dir, frame);
        ok = sinter_write_vti_sums(ctx, path, grid, sums, count, f->flags) == SINTER_OK;
    }
    free(sums);
    return ok;
}

int run_mpi_fields_write(const run_mpi_fields *f, sinter_ctx *ctx, sinter_stepper *st,
                         sinter_particles *ps, sinter_mpi_domain *domain, int rank,
                         const char *out_dir, unsigned long long frame)
{
    if (!f->on || !f->frames)
        return 1;
    double plo[3], phi[3], n = 0.0;
    int ok = particle_box(ps, domain, plo, phi, &n);
    if (ok && f->grid) {
        sinter_coarse_options grid;
        field_grid(f, plo, phi, n, &grid);
        ok = write_grid(f, ctx, st, ps, domain, rank, out_dir, frame, &grid);
    }
    for (int axis = 0; axis < 3; ++axis)
        if (f->profiles >> axis & 1u)
            ok = write_profile(f, ps, domain, rank, out_dir, frame, axis, plo, phi) && ok;
    return agree(ok);
}
