#define _POSIX_C_SOURCE 200809L
/*
 * The plot of a run (series.svg): its panels chosen by the series' column names, so that the
 * same plot is drawn at the end of a run and afterwards from the CSV of any run, finished or
 * not (sinter_plot_run, `sinter plot DIR`).
 *
 * A sintering run (a "shrinkage x" column): shrinkage per axis, mean neck ratio, relative
 * density, mean temperature. Otherwise: volume fraction; mean and max temperature; the wall
 * forces (columns "<wall> force" in N); the particle currents; kinetic energy. A series with
 * none of these names: one panel per column, eight at most.
 *
 * Any CSV a run writes, its columns chosen by name (sinter_plot_csv, `sinter plot DIR --panel
 * NAMES`): the seed's diagnostics such as the time step's history (seed 001 Fig. 12) or a
 * lamina profile (Fig. 10).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/path.h"
#include "io/run_plot.h"

enum { MAX_PANELS = 8 };

typedef struct layout {
    size_t panels, count, capacity;
    size_t start[MAX_PANELS + 1];
    size_t *columns;
} layout;

static ptrdiff_t column_named(const sinter_series *s, const char *name)
{
    for (size_t k = 0; k < s->columns; ++k)
        if (strcmp(s->names[k], name) == 0)
            return (ptrdiff_t)k;
    return -1;
}

/* A panel of the named columns that exist (none: no panel). */
static void panel_of(layout *l, const sinter_series *s, const char *const *names, size_t n)
{
    if (l->panels == MAX_PANELS)
        return;
    const size_t before = l->count;
    for (size_t k = 0; k < n; ++k) {
        const ptrdiff_t c = column_named(s, names[k]);
        if (c >= 0)
            l->columns[l->count++] = (size_t)c;
    }
    if (l->count > before)
        l->start[++l->panels] = l->count;
}

static int is_wall_force(const sinter_series *s, size_t k)
{
    const size_t n = strlen(s->names[k]), suffix = strlen(" force");
    return n > suffix && strcmp(s->names[k] + n - suffix, " force") == 0 &&
           strcmp(s->units[k], "N") == 0;
}

static void choose(layout *l, const sinter_series *s)
{
    l->panels = l->count = 0;
    l->start[0] = 0;
    if (column_named(s, "shrinkage x") >= 0) {
        /* with the two-particle reference where the run has it (seed 001 Figs. 11, 19) */
        static const char *const shrinkage[] = {"shrinkage x", "shrinkage y", "shrinkage z",
                                                "two-particle shrinkage"};
        static const char *const ratio[] = {"neck ratio mean", "two-particle neck ratio"},
                                 *const density[] = {"relative density"};
        static const char *const temperature[] = {"mean temperature"};
        panel_of(l, s, shrinkage, 4);
        panel_of(l, s, ratio, 2);
        panel_of(l, s, density, 1);
        panel_of(l, s, temperature, 1);
        return;
    }
    static const char *const fraction[] = {"volume fraction", "solid fraction"};
    static const char *const temperatures[] = {"mean temperature", "max temperature"};
    static const char *const currents[] = {"mean particle current", "max particle current"};
    static const char *const energy[] = {"kinetic energy"};
    panel_of(l, s, fraction, 2);
    panel_of(l, s, temperatures, 2);
    const size_t before = l->count;
    for (size_t k = 0; k < s->columns; ++k)
        if (is_wall_force(s, k))
            l->columns[l->count++] = k;
    if (l->count > before)
        l->start[++l->panels] = l->count;
    panel_of(l, s, currents, 2);
    panel_of(l, s, energy, 1);
    if (l->panels > 0)
        return;
    for (size_t k = 1; k < s->columns && l->panels < MAX_PANELS; ++k) {
        l->columns[l->count++] = k;
        l->start[++l->panels] = l->count;
    }
}

sinter_status sinter_plot_series(const sinter_series *s, const char *path, const char *title)
{
    layout l;
    memset(&l, 0, sizeof(l));
    l.columns = sinter_calloc(s->ctx, s->columns + MAX_PANELS, sizeof(size_t));
    if (l.columns == NULL)
        return sinter_last_status(s->ctx);
    choose(&l, s);
    sinter_status st =
        l.panels == 0 ? sinter_fail(s->ctx, SINTER_ERR_INVALID,
                                    "cannot plot '%s': the series has no column besides time", path)
                      : sinter_series_write_svg(s, path, title, 0, l.panels, l.start, l.columns);
    sinter_free(s->ctx, l.columns);
    return st;
}

sinter_status sinter_plot_run(sinter_ctx *ctx, const char *out_dir, const char *title)
{
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, out_dir);
    char csv[SINTER_PATH_SIZE], svg[SINTER_PATH_SIZE];
    sinter_status st = sinter_path_join(ctx, csv, sizeof(csv), out_dir, "series.csv");
    if (st == SINTER_OK)
        st = sinter_path_join(ctx, svg, sizeof(svg), out_dir, "series.svg");
    if (st != SINTER_OK)
        return st;
    sinter_series *s = NULL;
    st = sinter_series_read_csv(&s, ctx, csv);
    if (st == SINTER_OK && s->rows == 0)
        st = sinter_fail(ctx, SINTER_ERR_STATE, "sinter_plot_run: '%s' has no sample yet", csv);
    if (st == SINTER_OK)
        st = sinter_plot_series(s, svg, title);
    sinter_series_destroy(s);
    return st;
}

/* The columns named in `names` (comma-separated) into l's next panel: each name exactly, or
 * else every column that starts with it. SINTER_ERR_INVALID when a name selects none. */
static sinter_status panel_named(sinter_ctx *ctx, layout *l, const sinter_series *s, size_t x,
                                 const char *names)
{
    static const char *const fn = "sinter_plot_csv";
    const size_t before = l->count;
    const char *p = names;
    for (;;) {
        const char *end = strchr(p, ',');
        size_t n = end != NULL ? (size_t)(end - p) : strlen(p);
        while (n > 0 && p[0] == ' ') /* spaces around a name are not part of it */
            ++p, --n;
        while (n > 0 && p[n - 1] == ' ')
            --n;
        /* the column of that name, else those that start with it */
        ptrdiff_t exact = -1;
        for (size_t k = 0; k < s->columns && exact < 0; ++k)
            if (k != x && strlen(s->names[k]) == n && strncmp(s->names[k], p, n) == 0)
                exact = (ptrdiff_t)k;
        size_t found = 0;
        for (size_t k = 0; k < s->columns && n > 0; ++k) {
            const int take =
                exact >= 0 ? k == (size_t)exact : k != x && strncmp(s->names[k], p, n) == 0;
            if (take && l->count < l->capacity) {
                l->columns[l->count++] = k;
                found++;
            }
        }
        if (!found)
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: no column is named or starts with '%.*s'", fn, (int)n, p);
        if (end == NULL)
            break;
        p = end + 1;
    }
    if (l->count > before)
        l->start[++l->panels] = l->count;
    return SINTER_OK;
}

sinter_status sinter_plot_csv(sinter_ctx *ctx, const char *csv_path, const char *svg_path,
                              const char *title, const char *x, const char *const *panels,
                              size_t panel_count)
{
    static const char *const fn = "sinter_plot_csv";
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, csv_path);
    SINTER_CHECK_NULL(ctx, svg_path);
    if (panel_count > 0)
        SINTER_CHECK_NULL(ctx, panels);
    if (panel_count > MAX_PANELS)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: %zu panels, at most %d", fn, panel_count,
                           MAX_PANELS);
    for (size_t k = 0; k < panel_count; ++k)
        if (panels[k] == NULL)
            return sinter_fail(ctx, SINTER_ERR_NULL, "%s: panels[%zu] is NULL", fn, k);
    sinter_series *s = NULL;
    sinter_status st = sinter_series_read_csv(&s, ctx, csv_path);
    if (st != SINTER_OK)
        return st;
    size_t xc = 0;
    if (x != NULL) {
        const ptrdiff_t c = column_named(s, x);
        if (c < 0)
            st = sinter_fail(ctx, SINTER_ERR_INVALID, "%s: '%s' has no column named '%s'", fn,
                             csv_path, x);
        xc = c < 0 ? 0 : (size_t)c;
    }
    if (st == SINTER_OK && s->rows == 0)
        st = sinter_fail(ctx, SINTER_ERR_STATE, "%s: '%s' has no row", fn, csv_path);
    layout l;
    memset(&l, 0, sizeof(l));
    l.capacity = st == SINTER_OK ? 4 * s->columns * MAX_PANELS + 1 : 0;
    l.columns = st == SINTER_OK ? sinter_calloc(ctx, l.capacity, sizeof(size_t)) : NULL;
    if (st == SINTER_OK && l.columns == NULL)
        st = sinter_last_status(ctx);
    for (size_t k = 0; st == SINTER_OK && k < panel_count; ++k)
        st = panel_named(ctx, &l, s, xc, panels[k]);
    for (size_t k = 0; st == SINTER_OK && panel_count == 0 && k < s->columns; ++k)
        if (k != xc && l.panels < MAX_PANELS) {
            l.columns[l.count++] = k;
            l.start[++l.panels] = l.count;
        }
    if (st == SINTER_OK && l.panels == 0)
        st = sinter_fail(ctx, SINTER_ERR_INVALID, "%s: '%s' has no column besides '%s'", fn,
                         csv_path, s->names[xc]);
    if (st == SINTER_OK)
        st = sinter_series_write_svg(s, svg_path, title, xc, l.panels, l.start, l.columns);
    sinter_free(ctx, l.columns);
    sinter_series_destroy(s);
    return st;
}
