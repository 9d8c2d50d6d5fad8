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
 */
#include <stdio.h>
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
        static const char *const shrinkage[] = {"shrinkage x", "shrinkage y", "shrinkage z"};
        static const char *const ratio[] = {"neck ratio mean"}, *const density[] = {
                                                                    "relative density"};
        static const char *const temperature[] = {"mean temperature"};
        panel_of(l, s, shrinkage, 3);
        panel_of(l, s, ratio, 1);
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
