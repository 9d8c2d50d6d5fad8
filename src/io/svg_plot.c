/* SVG plots of a time series: panels stacked vertically that share the x column. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "io/series.h"

/* Geometry [px] and text metrics. */
#define SVG_WIDTH 800.0
#define PLOT_HEIGHT 196.0
#define FONT 12.0      /* axis labels and legend */
#define TICK_FONT 11.0 /* tick labels */
#define TITLE_FONT 16.0
#define CHAR_EM 0.6 /* generous estimate of a sans-serif character's advance [em] */
#define LEGEND_LINE 18.0
#define COORD_LIMIT 1e5 /* coordinates are clamped to +-COORD_LIMIT */

static const char *const PALETTE[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                      "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
#define PALETTE_SIZE (sizeof(PALETTE) / sizeof(PALETTE[0]))

typedef struct axis {
    double lo, hi; /* range shown */
    double first;  /* first tick */
    double step;   /* tick spacing */
    size_t ticks;  /* ticks at first + k step, k < ticks */
    int precision; /* %.*g precision that tells neighbouring tick labels apart */
} axis;

typedef struct panel {
    size_t first, count; /* entries of panel_columns */
    axis y;
    size_t legend_lines;
    double top; /* top edge of the plot area */
} panel;

typedef struct plot {
    const sinter_series *s;
    FILE *fp;
    size_t x_column;
    const size_t *columns; /* panel_columns */
    axis x;
    double left, width; /* plot area, horizontally */
    char *text;         /* scratch for labels */
} plot;

/* ---- text --------------------------------------------------------------------------------- */

static size_t utf8_chars(const char *text, size_t bytes)
{
    size_t n = 0;
    for (size_t i = 0; i < bytes; ++i)
        n += ((unsigned char)text[i] & 0xC0) != 0x80;
    return n;
}

static double text_width(const char *text, double font)
{
    return (double)utf8_chars(text, strlen(text)) * font * CHAR_EM;
}

/* Write <text ...attrs>text</text>, cut with an ellipsis to fit max_px. */
static void write_text(FILE *fp, double x, double y, const char *attrs, const char *text,
                       double font, double max_px)
{
    size_t bytes = strlen(text);
    int cut = 0;
    if (text_width(text, font) > max_px) {
        const double fit = floor(max_px / (font * CHAR_EM)) - 1.0;
        const size_t keep = fit > 0.0 ? (size_t)fit : 0;
        size_t chars = 0, i = 0;
        for (; i < bytes; ++i) {
            if (((unsigned char)text[i] & 0xC0) != 0x80 && chars++ == keep)
                break;
        }
        bytes = i;
        cut = 1;
    }
    fprintf(fp, "<text x=\"%.1f\" y=\"%.1f\"%s>", x, y, attrs);
    sinter_out_xml_n(fp, text, bytes);
    fputs(cut ? "\xE2\x80\xA6</text>\n" : "</text>\n", fp); /* U+2026 ellipsis */
}

/* "name [unit]", or "name" when the unit is empty, into buf. */
static void column_label(const sinter_series *s, size_t c, char *buf)
{
    strcpy(buf, s->names[c]);
    if (s->units[c][0] != '\0') {
        strcat(buf, " [");
        strcat(buf, s->units[c]);
        strcat(buf, "]");
    }
}

/* Bytes column_label needs, without the terminator. */
static size_t column_label_size(const sinter_series *s, size_t c)
{
    return strlen(s->names[c]) + strlen(s->units[c]) + 3;
}

/* y-axis label of a panel: "a, b [unit]" when every column shares a unit, else "a [u], b [v]". */
static void panel_label(const plot *p, const panel *pn, char *buf)
{
    const sinter_series *s = p->s;
    const char *unit = s->units[p->columns[pn->first]];
    int shared = unit[0] != '\0';
    for (size_t k = 1; k < pn->count && shared; ++k)
        shared = strcmp(s->units[p->columns[pn->first + k]], unit) == 0;
    buf[0] = '\0';
    for (size_t k = 0; k < pn->count; ++k) {
        const size_t c = p->columns[pn->first + k];
        if (k > 0)
            strcat(buf, ", ");
        if (shared)
            strcat(buf, s->names[c]);
        else
            column_label(s, c, buf + strlen(buf));
    }
    if (shared) {
        strcat(buf, " [");
        strcat(buf, unit);
        strcat(buf, "]");
    }
}

/* ---- axes --------------------------------------------------------------------------------- */

/* 1, 2 or 5 times a power of ten, the nearest to rough (> 0). */
static double nice_step(double rough)
{
    const double magnitude = pow(10.0, floor(log10(rough)));
    const double norm = rough / magnitude;
    return (norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0) * magnitude;
}

/*
 * Axis over the finite data range [min, max] (min > max: no data), widened by
 * `pad` of the range on both sides, with ticks at multiples of a 1-2-5 step
 * that gives about `target` intervals.
 */
static void make_axis(double min, double max, double target, double pad, axis *a)
{
    if (!(min <= max)) {
        min = 0.0;
        max = 1.0;
    }
    const double big = fmax(fabs(min), fabs(max));
    if (!(max - min > 1e-12 * big)) { /* constant data: centre a range on it */
        const double mid = 0.5 * min + 0.5 * max;
        const double half = mid != 0.0 ? 0.1 * fabs(mid) : 1.0;
        min = mid - half;
        max = mid + half;
    } else {
        const double margin = 2.0 * pad * (0.5 * max - 0.5 * min);
        min -= margin;
        max += margin;
    }
    const double step = nice_step(max / target - min / target);
    /* The tolerance keeps round-off in min / step from dropping a tick on the edge. */
    const double first = ceil(min / step - 1e-9), last = floor(max / step + 1e-9);
    a->lo = isfinite(min) ? min : -DBL_MAX;
    a->hi = isfinite(max) ? max : DBL_MAX;
    if (!(isfinite(first * step) && last - first >= 0.0 && last - first <= 1000.0)) {
        /* Only for data near the limits of double: one tick at the lower edge. */
        a->first = a->lo;
        a->step = 0.0;
        a->ticks = 1;
        a->precision = 6;
        return;
    }
    a->first = first * step;
    a->step = step;
    a->ticks = (size_t)(last - first) + 1;
    /* Enough digits to tell ticks apart, and to print integers below 1e6 without an exponent. */
    const int magnitude = (int)floor(log10(fmax(fabs(a->first), fabs(last * step)) + step));
    int digits = magnitude - (int)floor(log10(step)) + 1;
    if (magnitude < 6 && digits < magnitude + 1)
        digits = magnitude + 1;
    a->precision = digits < 1 ? 1 : digits > 17 ? 17 : digits;
}

static double tick_value(const axis *a, size_t k)
{
    const double v = a->first + (double)k * a->step;
    return fabs(v) < 1e-9 * a->step ? 0.0 : v;
}

/* %g text of tick k, with the exponent tidied: "1.5e+06" becomes "1.5e6", "2e-09" "2e-9". */
static void tick_label(const axis *a, size_t k, char *buf, size_t size)
{
    snprintf(buf, size, "%.*g", a->precision, tick_value(a, k));
    char *e = strchr(buf, 'e');
    if (e == NULL)
        return;
    char *digits = e + 1, *out = e + 1;
    if (*digits == '+' || *digits == '-')
        digits++;
    if (*out == '-')
        out++;
    while (*digits == '0' && digits[1] != '\0')
        digits++;
    memmove(out, digits, strlen(digits) + 1);
}

static double widest_tick_label(const axis *a)
{
    double widest = 0.0;
    char buf[48];
    for (size_t k = 0; k < a->ticks; ++k) {
        tick_label(a, k, buf, sizeof(buf));
        widest = fmax(widest, text_width(buf, TICK_FONT));
    }
    return widest;
}

/* Fraction of the axis at v (0 at lo, 1 at hi), without overflow. */
static double axis_fraction(const axis *a, double v)
{
    return (0.5 * v - 0.5 * a->lo) / (0.5 * a->hi - 0.5 * a->lo);
}

static double clamp_coord(double c)
{
    return !(c > -COORD_LIMIT) ? -COORD_LIMIT : c > COORD_LIMIT ? COORD_LIMIT : c;
}

/* Finite range of column c over the rows with a finite x. */
static void data_range(const plot *p, size_t c, double *min, double *max)
{
    const sinter_series *s = p->s;
    for (size_t r = 0; r < s->rows; ++r) {
        const double *row = s->values + r * s->columns;
        if (isfinite(row[p->x_column]) && isfinite(row[c])) {
            *min = fmin(*min, row[c]);
            *max = fmax(*max, row[c]);
        }
    }
}

/* ---- drawing ------------------------------------------------------------------------------ */

static double legend_entry_width(const plot *p, size_t c)
{
    column_label(p->s, c, p->text);
    return fmin(28.0 + text_width(p->text, FONT), p->width) + 18.0;
}

static size_t legend_lines(const plot *p, const panel *pn)
{
    size_t lines = 1;
    double x = 0.0;
    for (size_t k = 0; k < pn->count; ++k) {
        const double w = legend_entry_width(p, p->columns[pn->first + k]);
        if (x > 0.0 && x + w > p->width + 18.0) {
            lines++;
            x = 0.0;
        }
        x += w;
    }
    return lines;
}

static void draw_legend(const plot *p, const panel *pn)
{
    double x = 0.0, y = pn->top - (double)pn->legend_lines * LEGEND_LINE + 6.0;
    for (size_t k = 0; k < pn->count; ++k) {
        const size_t c = p->columns[pn->first + k];
        const double w = legend_entry_width(p, c);
        if (x > 0.0 && x + w > p->width + 18.0) {
            y += LEGEND_LINE;
            x = 0.0;
        }
        fprintf(p->fp,
                "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
                "stroke-width=\"2.5\"/>\n",
                p->left + x, y - 4.0, p->left + x + 22.0, y - 4.0, PALETTE[k % PALETTE_SIZE]);
        column_label(p->s, c, p->text);
        write_text(p->fp, p->left + x + 28.0, y, "", p->text, FONT, p->width - 28.0);
        x += w;
    }
}

static void draw_axes(const plot *p, const panel *pn)
{
    FILE *fp = p->fp;
    const double bottom = pn->top + PLOT_HEIGHT, right = p->left + p->width;
    char buf[48];
    fputs("<path fill=\"none\" stroke=\"#e4e4e4\" d=\"", fp);
    for (size_t k = 0; k < p->x.ticks; ++k)
        fprintf(fp, "M%.2f %.2fV%.2f",
                p->left + p->width * axis_fraction(&p->x, tick_value(&p->x, k)), pn->top, bottom);
    for (size_t k = 0; k < pn->y.ticks; ++k)
        fprintf(fp, "M%.2f %.2fH%.2f", p->left,
                bottom - PLOT_HEIGHT * axis_fraction(&pn->y, tick_value(&pn->y, k)), right);
    fputs("\"/>\n<path fill=\"none\" stroke=\"#000\" d=\"", fp);
    for (size_t k = 0; k < p->x.ticks; ++k)
        fprintf(fp, "M%.2f %.2fv5", p->left + p->width * axis_fraction(&p->x, tick_value(&p->x, k)),
                bottom);
    for (size_t k = 0; k < pn->y.ticks; ++k)
        fprintf(fp, "M%.2f %.2fh-5", p->left,
                bottom - PLOT_HEIGHT * axis_fraction(&pn->y, tick_value(&pn->y, k)));
    fprintf(fp, "\"/>\n<g font-size=\"%g\" fill=\"#222\" text-anchor=\"middle\">\n", TICK_FONT);
    for (size_t k = 0; k < p->x.ticks; ++k) {
        tick_label(&p->x, k, buf, sizeof(buf));
        fprintf(fp, "<text x=\"%.2f\" y=\"%.2f\">%s</text>\n",
                p->left + p->width * axis_fraction(&p->x, tick_value(&p->x, k)), bottom + 17.0,
                buf);
    }
    for (size_t k = 0; k < pn->y.ticks; ++k) {
        tick_label(&pn->y, k, buf, sizeof(buf));
        fprintf(fp, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">%s</text>\n", p->left - 8.0,
                bottom - PLOT_HEIGHT * axis_fraction(&pn->y, tick_value(&pn->y, k)) + 4.0, buf);
    }
    fputs("</g>\n", fp);
}

static void point_coords(const plot *p, const panel *pn, double x, double y, double *px, double *py)
{
    *px = clamp_coord(p->left + p->width * axis_fraction(&p->x, x));
    *py = clamp_coord(pn->top + PLOT_HEIGHT * (1.0 - axis_fraction(&pn->y, y)));
}

/* One polyline per run of finite points; a run of a single point is drawn as a dot. */
static void draw_column(const plot *p, const panel *pn, size_t c, const char *colour)
{
    FILE *fp = p->fp;
    const sinter_series *s = p->s;
    fprintf(fp, "<g fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" stroke-linejoin=\"round\">\n",
            colour);
    size_t run = 0;
    double first_x = 0.0, first_y = 0.0;
    for (size_t r = 0; r <= s->rows; ++r) {
        const double *row = r < s->rows ? s->values + r * s->columns : NULL;
        if (row != NULL && !isfinite(row[p->x_column]))
            continue; /* rows without x are skipped, not breaks */
        if (row != NULL && isfinite(row[c])) {
            double px, py;
            point_coords(p, pn, row[p->x_column], row[c], &px, &py);
            if (run == 0) {
                first_x = px;
                first_y = py;
            } else {
                if (run == 1)
                    fprintf(fp, "<polyline points=\"%.2f,%.2f", first_x, first_y);
                fputc(run % 8 == 0 ? '\n' : ' ', fp);
                fprintf(fp, "%.2f,%.2f", px, py);
            }
            run++;
            continue;
        }
        if (run == 1)
            fprintf(fp, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"2.5\" fill=\"%s\" stroke=\"none\"/>\n",
                    first_x, first_y, colour);
        else if (run > 1)
            fputs("\"/>\n", fp);
        run = 0;
    }
    fputs("</g>\n", fp);
}

static void draw_panel(const plot *p, const panel *pn)
{
    FILE *fp = p->fp;
    fputs("<g>\n", fp);
    draw_axes(p, pn);
    for (size_t k = 0; k < pn->count; ++k)
        draw_column(p, pn, p->columns[pn->first + k], PALETTE[k % PALETTE_SIZE]);
    fprintf(fp,
            "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"none\" "
            "stroke=\"#000\"/>\n",
            p->left, pn->top, p->width, PLOT_HEIGHT);
    draw_legend(p, pn);
    /* Rotated y-axis label, shrunk (then cut) to the height of the plot area. */
    panel_label(p, pn, p->text);
    const double cy = pn->top + 0.5 * PLOT_HEIGHT;
    const double font = text_width(p->text, FONT) <= PLOT_HEIGHT ? FONT : 10.0;
    char attrs[96];
    snprintf(attrs, sizeof(attrs),
             " text-anchor=\"middle\" font-size=\"%g\" transform=\"rotate(-90 18 %.2f)\"", font,
             cy);
    write_text(fp, 18.0, cy, attrs, p->text, font, PLOT_HEIGHT);
    fputs("</g>\n", fp);
}

/* ---- entry point -------------------------------------------------------------------------- */

static sinter_status check_panels(const sinter_series *s, size_t x_column, size_t panels,
                                  const size_t *panel_start, const size_t *panel_columns)
{
    static const char *const fn = "sinter_series_write_svg";
    sinter_ctx *ctx = s->ctx;
    if (x_column >= s->columns)
        return sinter_fail(ctx, SINTER_ERR_RANGE,
                           "%s: x_column %zu is out of range; the series has %zu columns", fn,
                           x_column, s->columns);
    if (panels == 0)
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: panels is 0; draw at least one panel", fn);
    SINTER_CHECK_NULL(ctx, panel_start);
    SINTER_CHECK_NULL(ctx, panel_columns);
    for (size_t k = 0; k < panels; ++k)
        if (panel_start[k + 1] <= panel_start[k])
            return sinter_fail(ctx, SINTER_ERR_INVALID,
                               "%s: panel %zu has no columns (panel_start[%zu] = %zu, "
                               "panel_start[%zu] = %zu)",
                               fn, k, k, panel_start[k], k + 1, panel_start[k + 1]);
    for (size_t k = 0; k < panels; ++k)
        for (size_t j = panel_start[k]; j < panel_start[k + 1]; ++j)
            if (panel_columns[j] >= s->columns)
                return sinter_fail(ctx, SINTER_ERR_RANGE,
                                   "%s: panel_columns[%zu] (panel %zu) is column %zu, out of "
                                   "range; the series has %zu columns",
                                   fn, j, k, panel_columns[j], s->columns);
    return SINTER_OK;
}

sinter_status sinter_series_write_svg(const sinter_series *s, const char *path, const char *title,
                                      size_t x_column, size_t panels, const size_t *panel_start,
                                      const size_t *panel_columns)
{
    if (s == NULL)
        return SINTER_ERR_NULL;
    sinter_ctx *ctx = s->ctx;
    SINTER_CHECK_NULL(ctx, path);
    if (path[0] == '\0')
        return sinter_fail(ctx, SINTER_ERR_INVALID, "sinter_series_write_svg: the path is empty");
    sinter_status st = check_panels(s, x_column, panels, panel_start, panel_columns);
    if (st != SINTER_OK)
        return st;

    /* Scratch text large enough for every label. */
    size_t text_size = column_label_size(s, x_column);
    for (size_t k = 0; k < panels; ++k) {
        size_t need = 0;
        for (size_t j = panel_start[k]; j < panel_start[k + 1]; ++j)
            need += column_label_size(s, panel_columns[j]) + 2;
        text_size = need > text_size ? need : text_size;
    }
    plot p = {.s = s, .x_column = x_column, .columns = panel_columns};
    panel *pns = sinter_calloc(ctx, panels, sizeof(panel));
    p.text = sinter_alloc(ctx, text_size + 1);
    if (pns == NULL || p.text == NULL) {
        sinter_free(ctx, pns);
        sinter_free(ctx, p.text);
        return sinter_last_status(ctx);
    }

    /* Axes: y per panel, then the left margin from the widest y tick label. */
    double widest = 0.0;
    for (size_t k = 0; k < panels; ++k) {
        panel *pn = &pns[k];
        pn->first = panel_start[k];
        pn->count = panel_start[k + 1] - panel_start[k];
        double min = INFINITY, max = -INFINITY;
        for (size_t j = 0; j < pn->count; ++j)
            data_range(&p, panel_columns[pn->first + j], &min, &max);
        make_axis(min, max, 5.0, 0.04, &pn->y);
        widest = fmax(widest, widest_tick_label(&pn->y));
    }
    p.left = fmax(64.0, 40.0 + widest);
    double xmin = INFINITY, xmax = -INFINITY;
    data_range(&p, x_column, &xmin, &xmax);
    /* Fewer x ticks until their labels fit side by side. */
    for (double target = 10.0; target >= 2.0; target -= 1.0) {
        make_axis(xmin, xmax, target, 0.0, &p.x);
        const double right = fmax(24.0, 0.5 * widest_tick_label(&p.x) + 8.0);
        p.width = SVG_WIDTH - p.left - right;
        const double spacing = p.width * axis_fraction(&p.x, p.x.lo + p.x.step);
        if (widest_tick_label(&p.x) + 20.0 <= spacing)
            break;
    }

    /* Vertical layout: title, then per panel a legend band, the plot area and the x ticks. */
    const int has_title = title != NULL && title[0] != '\0';
    double y = has_title ? 44.0 : 14.0;
    for (size_t k = 0; k < panels; ++k) {
        pns[k].legend_lines = legend_lines(&p, &pns[k]);
        pns[k].top = y + (double)pns[k].legend_lines * LEGEND_LINE + 6.0;
        y = pns[k].top + PLOT_HEIGHT + 40.0;
    }
    const double bottom = pns[panels - 1].top + PLOT_HEIGHT, height = bottom + 52.0;

    sinter_out_file out;
    st = sinter_out_open(&out, ctx, "sinter_series_write_svg", path);
    if (st == SINTER_OK) {
        p.fp = out.fp;
        fprintf(p.fp,
                "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
                "viewBox=\"0 0 %.0f %.0f\" font-family=\"DejaVu Sans, Arial, sans-serif\" "
                "font-size=\"%g\">\n"
                "<rect width=\"100%%\" height=\"100%%\" fill=\"#fff\"/>\n",
                SVG_WIDTH, height, SVG_WIDTH, height, FONT);
        if (has_title)
            write_text(p.fp, 0.5 * SVG_WIDTH, 28.0,
                       " text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\"", title,
                       TITLE_FONT, SVG_WIDTH - 20.0);
        for (size_t k = 0; k < panels; ++k)
            draw_panel(&p, &pns[k]);
        column_label(s, x_column, p.text);
        write_text(p.fp, p.left + 0.5 * p.width, bottom + 40.0, " text-anchor=\"middle\"", p.text,
                   FONT, p.width);
        fputs("</svg>\n", p.fp);
        st = sinter_out_close(&out, SINTER_OK);
    }
    sinter_free(ctx, pns);
    sinter_free(ctx, p.text);
    return st;
}
