/*
 * The Cartesian brick (libsinter_mpi, issue 44): g0 x g1 x g2 equal boxes over the global box,
 * numbered as MPI_Cart_create numbers a grid's ranks, (i0 g1 + i1) g2 + i2. Static: its balance
 * is whatever the particles' spread gives (sinter_mpi_decomp_rebalance replaces it by RCB).
 */
#include <math.h>
#include <string.h>

#include "mpi/decomp.h"

/* The grid with the smallest total area of cut planes, (g_a - 1) times the box's section normal
 * to a (so that the ghosts' shells, proportional to that area, are the thinnest); ties go to
 * the larger count on the earlier axis, as MPI_Dims_create orders its dimensions. Axes given
 * non-zero are kept. 0 when no grid fits. */
static int choose_grid(int parts, const int given[3], const double lo[3], const double hi[3],
                       int grid[3])
{
    const double len[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    const double section[3] = {len[1] * len[2], len[0] * len[2], len[0] * len[1]};
    double best = INFINITY;
    for (int g0 = parts; g0 >= 1; --g0) {
        if (parts % g0 != 0 || (given[0] != 0 && given[0] != g0))
            continue;
        for (int g1 = parts / g0; g1 >= 1; --g1) {
            const int g2 = parts / g0 / g1;
            if ((parts / g0) % g1 != 0 || (given[1] != 0 && given[1] != g1) ||
                (given[2] != 0 && given[2] != g2))
                continue;
            const double area =
                (g0 - 1) * section[0] + (g1 - 1) * section[1] + (g2 - 1) * section[2];
            if (area < best) {
                best = area;
                grid[0] = g0;
                grid[1] = g1;
                grid[2] = g2;
            }
        }
    }
    return best < INFINITY;
}

sinter_status sinter_mpi_decomp_brick(sinter_mpi_decomp **out, int parts, const int grid[3],
                                      const double lo[3], const double hi[3])
{
    if (out == NULL || lo == NULL || hi == NULL)
        return SINTER_ERR_NULL;
    *out = NULL;
    const int none[3] = {0, 0, 0};
    const int *given = grid != NULL ? grid : none;
    if (parts < 1 || !sinter_mpi_box_valid(lo, hi) || given[0] < 0 || given[1] < 0 || given[2] < 0)
        return SINTER_ERR_INVALID;
    int g[3];
    if (!choose_grid(parts, given, lo, hi, g))
        return SINTER_ERR_INVALID;
    sinter_mpi_decomp *d = NULL;
    sinter_status st = sinter_mpi_decomp_alloc(&d, SINTER_MPI_DECOMP_BRICK, parts, lo, hi);
    if (st != SINTER_OK)
        return st;
    memcpy(d->grid, g, sizeof g);
    double *plane = d->plane_store;
    for (int a = 0; a < 3; ++a) {
        d->planes[a] = plane;
        for (int i = 0; i <= g[a]; ++i)
            plane[i] = i == g[a] ? hi[a] : lo[a] + (hi[a] - lo[a]) * i / g[a];
        plane += g[a] + 1;
    }
    for (int i0 = 0; i0 < g[0]; ++i0)
        for (int i1 = 0; i1 < g[1]; ++i1)
            for (int i2 = 0; i2 < g[2]; ++i2) {
                const int i[3] = {i0, i1, i2};
                double *box = d->box + 6 * (size_t)((i0 * g[1] + i1) * g[2] + i2);
                for (int a = 0; a < 3; ++a) {
                    box[a] = d->planes[a][i[a]];
                    box[3 + a] = d->planes[a][i[a] + 1];
                }
            }
    *out = d;
    return SINTER_OK;
}
