/*
 * The rigid motion the bonded solve leaves undetermined (quasi-static stepper, seed 001
 * sec. 3.3).
 *
 * The principal-plane conditions hold a packing's main network, but spheres linked only to each
 * other (the titanium packing has four such pairs among 3619 spheres) form a component of the
 * link graph whose rigid translations K does not resist at all, and whose rigid rotations it
 * resists only through L_A0 + L_B0 - |x_B - x_A| (about zero, eq. 25). Their loads balance, so
 * K u = f holds whatever rigid motion they get; which one a solve returns depends on its start
 * and its preconditioner (block-Jacobi and block-SSOR put the four pairs in different places,
 * which moved the titanium packing's shrinkage by 1e-3; tests/bench/RESULTS.md, session 14).
 *
 * This takes the one without rigid motion: in a component no plane holds along an axis, the
 * mean displacement along that axis is removed; about an axis whose two perpendicular
 * directions no plane holds, the mean rotation is removed with the displacement it gives about
 * the component's centroid. A component held on every axis (the main network) is not touched.
 *
 * Everything runs per slot (the id order of qs_ids.c) over the step's beams, which name slots:
 * the components, their roots (the smallest slot) and the order of their sums follow the ids.
 */
#include <string.h>

#include "stepper/qs_floating.h"
#include "stepper/qs_struct.h"

static uint32_t find_root(uint32_t *root, uint32_t i)
{
    while (root[i] != i) {
        root[i] = root[root[i]]; /* path halving */
        i = root[i];
    }
    return i;
}

enum { SUMS = 10 }; /* per component: count, centroid sum (3), rotation sum (3), u sum (3) */

sinter_status sinter_qs_remove_free_motion(sinter_qs *qs, const sinter_qs_particles *p, double *u)
{
    const size_t n = p->count, m = qs->count;
    if (n == 0 || m == 0)
        return SINTER_OK;
    sinter_status st = sinter_grow(qs->ctx, (void **)&qs->component, &qs->component_capacity, n + 1,
                                   sizeof(uint32_t));
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->component_held, &qs->component_held_capacity, n + 1,
                         1);
    if (st == SINTER_OK)
        st = sinter_grow(qs->ctx, (void **)&qs->component_sums, &qs->component_sums_capacity,
                         SUMS * n + 1, sizeof(double));
    if (st != SINTER_OK)
        return st;
    uint32_t *root = qs->component;
    unsigned char *held = qs->component_held; /* bits 0-2: a plane holds x, y, z; bit 7: linked */
    double *sums = qs->component_sums;
    const uint32_t *index = qs->index_of_slot; /* the caller's index of a slot */
    const sinter_beam *beams = qs->beams;      /* the step's beams, a and b their slots */
    for (size_t i = 0; i < n; ++i)
        root[i] = (uint32_t)i;
    memset(held, 0, n);
    for (size_t k = 0; k < m; ++k) {
        const uint32_t a = find_root(root, beams[k].a);
        const uint32_t b = find_root(root, beams[k].b);
        if (a != b) /* the lower slot is the root: the same components whatever the order */
            root[a > b ? a : b] = a > b ? b : a;
        held[beams[k].a] |= 0x80;
        held[beams[k].b] |= 0x80;
    }
    int any_free = 0;
    for (size_t i = 0; i < n; ++i) { /* roots' held bits: their components' */
        const uint32_t r = find_root(root, (uint32_t)i);
        for (int d = 0; d < 3; ++d)
            if (qs->fixed[6 * i + (size_t)d])
                held[r] |= (unsigned char)(1u << d);
    }
    for (size_t i = 0; i < n; ++i)
        if (root[i] == i && (held[i] & 0x80) && (held[i] & 7) != 7)
            any_free = 1;
    if (!any_free)
        return SINTER_OK;

    /* centroid and mean rotation of each free component */
    memset(sums, 0, SUMS * n * sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        if (!(held[i] & 0x80))
            continue;
        double *s = sums + SUMS * (size_t)root[i];
        s[0] += 1.0;
        for (size_t d = 0; d < 3; ++d) {
            s[1 + d] += p->x[3 * (size_t)index[i] + d];
            s[4 + d] += u[6 * i + 3 + d];
        }
    }
    /* remove the free rotations, summing the displacements left */
    for (size_t i = 0; i < n; ++i) {
        if (!(held[i] & 0x80))
            continue;
        const size_t r = root[i];
        double *s = sums + SUMS * r;
        /* a periodic axis holds the rotations that would turn it (a network across its faces
         * cannot turn), not the translations along it (qs_periodic.c) */
        const unsigned char h = (unsigned char)(held[r] | qs->periodic[0] | qs->periodic[1] << 1 |
                                                qs->periodic[2] << 2);
        double w[3], arm[3];
        for (int k = 0; k < 3; ++k) {
            const int free_about_k = !(h & (1u << ((k + 1) % 3))) && !(h & (1u << ((k + 2) % 3)));
            w[k] = free_about_k ? s[4 + k] / s[0] : 0.0;
            arm[k] = p->x[3 * (size_t)index[i] + (size_t)k] - s[1 + k] / s[0];
        }
        const double turn[3] = {w[1] * arm[2] - w[2] * arm[1], w[2] * arm[0] - w[0] * arm[2],
                                w[0] * arm[1] - w[1] * arm[0]};
        for (size_t d = 0; d < 3; ++d) {
            u[6 * i + d] -= turn[d];
            u[6 * i + 3 + d] -= w[d];
            s[7 + d] += u[6 * i + d];
        }
    }
    /* then the free translations */
    for (size_t i = 0; i < n; ++i) {
        if (!(held[i] & 0x80))
            continue;
        const size_t r = root[i];
        const double *s = sums + SUMS * r;
        for (size_t d = 0; d < 3; ++d)
            if (!(held[r] & (1u << d)))
                u[6 * i + d] -= s[7 + d] / s[0];
    }
    return SINTER_OK;
}
