/*
 * A periodic green body for the quasi-static stepper's representative volume (issue 38,
 * examples/scenes/copper_rve.scene): copper_packing.scene's powder (radii uniform in
 * 25 um +- 10 %, Yade makeCloud's default of seed 001 sec. 3.2) jammed in a periodic cube,
 * written as "x y z r" lines [m] for a scene's [particles] method = file.
 *
 * Method: the spheres are placed at random in the cube at a tenth of the target solid fraction
 * and grown (every radius by one factor, the distribution kept) to the target while their
 * overlaps are pushed apart: each overlapping pair, through the nearest image, is moved apart
 * along its centre line by 0.8 of its overlap (a Jacobi relaxation of the harmonic overlap
 * energy, the frictionless soft-sphere jamming of O'Hern, Silbert, Liu and Nagel, Phys. Rev. E
 * 68, 011306, 2003). At the target the relaxation runs until the largest overlap stops
 * shrinking: above the jamming fraction (about 0.64-0.65 for this spread) the overlaps cannot
 * vanish, and the spheres are left touching with small overlaps, which the quasi-static
 * stepper's contact search turns into links.
 *
 * Usage: rve_pack SEED COUNT FRACTION FILE  (e.g. rve_pack 1 805 0.65 copper_rve.xyz)
 * Prints the cube's edge, the largest overlap and the touching pairs' coordination.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* splitmix64: a small, fixed random stream (the same file on every machine) */
static uint64_t state;
static double uniform(void)
{
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

typedef struct cells {
    int side;
    int *head, *next;
} cells;

static int cell_of(double x, double size, int side)
{
    int c = (int)floor(x / size);
    return ((c % side) + side) % side;
}

/* One sweep: every overlapping pair pushed apart by `share` of its overlap; returns the largest
 * overlap over the radius sum, and the count of touching pairs in *pairs. */
static double relax(size_t n, double *x, const double *r, double scale, double L, cells *g,
                    double share, double *dx, size_t *pairs)
{
    const int side = g->side;
    const double size = L / side;
    for (int c = 0; c < side * side * side; ++c)
        g->head[c] = -1;
    for (size_t i = 0; i < n; ++i) {
        const int c =
            (cell_of(x[3 * i], size, side) * side + cell_of(x[3 * i + 1], size, side)) * side +
            cell_of(x[3 * i + 2], size, side);
        g->next[i] = g->head[c];
        g->head[c] = (int)i;
    }
    memset(dx, 0, 3 * n * sizeof(double));
    double worst = 0.0;
    size_t touching = 0;
    for (size_t i = 0; i < n; ++i) {
        const int ci[3] = {cell_of(x[3 * i], size, side), cell_of(x[3 * i + 1], size, side),
                           cell_of(x[3 * i + 2], size, side)};
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b)
                for (int e = -1; e <= 1; ++e) {
                    const int c = ((((ci[0] + a) % side + side) % side) * side +
                                   (((ci[1] + b) % side + side) % side)) *
                                      side +
                                  (((ci[2] + e) % side + side) % side);
                    for (int j = g->head[c]; j >= 0; j = g->next[j]) {
                        if ((size_t)j <= i)
                            continue;
                        double v[3], d2 = 0.0;
                        for (int d = 0; d < 3; ++d) {
                            v[d] = x[3 * (size_t)j + d] - x[3 * i + d];
                            v[d] -= L * round(v[d] / L);
                            d2 += v[d] * v[d];
                        }
                        const double s = scale * (r[i] + r[j]);
                        if (d2 >= s * s)
                            continue;
                        ++touching;
                        const double dist = sqrt(d2), over = s - dist;
                        worst = fmax(worst, over / s);
                        const double push = 0.5 * share * over / fmax(dist, 1e-30);
                        for (int d = 0; d < 3; ++d) {
                            dx[3 * i + d] -= push * v[d];
                            dx[3 * (size_t)j + d] += push * v[d];
                        }
                    }
                }
    }
    for (size_t k = 0; k < 3 * n; ++k) {
        x[k] += dx[k];
        x[k] -= L * floor(x[k] / L);
        if (x[k] >= L) /* rounding of a value just below 0 */
            x[k] = 0.0;
    }
    *pairs = touching;
    return worst;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: rve_pack SEED COUNT FRACTION FILE\n");
        return 2;
    }
    state = strtoull(argv[1], NULL, 10) * 0x2545f4914f6cdd1dull + 1;
    const size_t n = (size_t)strtoul(argv[2], NULL, 10);
    const double fraction = strtod(argv[3], NULL);
    const double radius = 25e-6, spread = 2.5e-6; /* copper_packing.scene's */
    if (n < 2 || !(fraction > 0.0 && fraction < 0.74))
        return 2;
    double *x = malloc(3 * n * sizeof(double)), *dx = malloc(3 * n * sizeof(double));
    double *r = malloc(n * sizeof(double));
    double solid = 0.0, rmax = 0.0;
    for (size_t i = 0; i < n; ++i) {
        r[i] = radius + spread * (2.0 * uniform() - 1.0);
        solid += 4.0 / 3.0 * M_PI * r[i] * r[i] * r[i];
        rmax = fmax(rmax, r[i]);
    }
    const double L = cbrt(solid / fraction);
    for (size_t k = 0; k < 3 * n; ++k)
        x[k] = L * uniform();
    cells g;
    g.side = (int)floor(L / (2.0 * rmax * 1.01));
    if (g.side < 3)
        g.side = 3; /* every neighbour cell distinct */
    g.head = malloc((size_t)(g.side * g.side * g.side) * sizeof(int));
    g.next = malloc(n * sizeof(int));
    size_t pairs = 0;
    const int grow = 4000;
    for (int k = 0; k <= grow; ++k) { /* radius factor from 0.1^(1/3) to 1 */
        const double f = cbrt(0.1 + 0.9 * (double)k / grow);
        relax(n, x, r, f, L, &g, 0.8, dx, &pairs);
    }
    double worst = 0.0, previous = INFINITY;
    int sweeps = 0;
    for (; sweeps < 200000; ++sweeps) {
        worst = relax(n, x, r, 1.0, L, &g, 0.25, dx, &pairs);
        if (sweeps % 1000 == 999) {
            if (worst > 0.99 * previous || worst < 1e-6)
                break;
            previous = worst;
        }
    }
    FILE *f = fopen(argv[4], "w");
    if (f == NULL)
        return 1;
    fprintf(f, "# rve_pack %s %s %s: periodic cube [0, %.17g) m on each axis; x y z r [m]\n",
            argv[1], argv[2], argv[3], L);
    for (size_t i = 0; i < n; ++i)
        fprintf(f, "%.17g %.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2], r[i]);
    fclose(f);
    printf("cube edge %.17g m, solid fraction %g, %d sweeps after growing, largest overlap %.3e "
           "of the radius sum, %zu touching pairs (coordination %.3f)\n",
           L, fraction, sweeps + 1, worst, pairs, 2.0 * (double)pairs / (double)n);
    free(x);
    free(dx);
    free(r);
    free(g.head);
    free(g.next);
    return 0;
}
