/* The plot of a run, its panels chosen by the column names (io/run_plot.c). */
#ifndef SINTER_IO_RUN_PLOT_H
#define SINTER_IO_RUN_PLOT_H

#include "io/series.h"

/* Draw `s` (column 0: time) into the SVG file `path` with the run's panels. */
sinter_status sinter_plot_series(const sinter_series *s, const char *path, const char *title);

#endif
