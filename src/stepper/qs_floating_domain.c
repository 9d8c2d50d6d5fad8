/*
 * The rigid motion the bonded solve leaves undetermined, removed on a subdomain of a
 * decomposed body (issue 43; the serial rule and its reasons: qs_floating.c).
 *
 * A component of the link graph may run through several subdomains, and a link lives only on
 * the subdomain of its smaller id: the subdomain owning the larger end may not know it. Each
 * subdomain joins its slots over its beams (owned and ghost ends), labels each local component
 * with the smallest id among its members and marks the axes its owned members' planes hold
 * and whether it has a link. Labels and marks then spread by rounds until no subdomain changes
 * one (the electric network's cluster labels do the same, network_domain.c): a forward halo
 * gives each ghost its owner's; a reverse halo gives each owner its ghosts' (the marks added,
 * so any mark; a label only from the copies below the owner's, their mean, as a halo can only
 * add). Labels only decrease and never below their component's smallest id, which its own
 * member keeps: the rounds end with every member labelled by that id, as on one domain.
 * The free components' labels are then listed in increasing order (one minimum reduction
 * each), and their counts, centroids and rotations summed over every subdomain's owned
 * members (one sum reduction; after the rotations are removed, one more for the displacements
 * left). Ghosts are moved as their owners, from the same sums. The sums' order differs from
 * one domain's: the result equals it to round-off.
 */
#include <math.h>
#include <string.h>

#include "stepper/qs_domain.h"
#include "stepper/qs_floating.h"
#include "stepper/qs_repro.h"
#include "stepper/qs_struct.h"

static uint32_t find_root(uint32_t *root, uint32_t i)
{
    while (root[i] != i) {
        root[i] = root[root[i]]; /* path halving */
        i = root[i];
    }
    return i;
}

/* the marks: bits 0-2 a plane holds x, y, z; bit 7 linked (as qs_floating.c) */
static const unsigned char MARK[4] = {1, 2, 4, 0x80};

enum { W = 6 }; /* a reverse row: copies below, their labels' sum, the four marks */

/* One round of spreading: 1 when a label or mark changed here. */
static sinter_status round_trip(sinter_qs *qs, size_t n, uint32_t *root, double *label,
                                unsigned char *held, double *rows, int *changed)
{
    const size_t owned = qs->dom.owned;
    *changed = 0;
    for (size_t i = 0; i < n; ++i) { /* forward: the owners' labels and marks */
        const uint32_t r = find_root(root, qs->slot_of[i]);
        rows[W * i] = label[r];
        rows[W * i + 1] = held[r];
    }
    sinter_status st = sinter_qs_domain_forward_index(qs, rows, W);
    if (st != SINTER_OK)
        return st;
    for (size_t i = owned; i < n; ++i) {
        const uint32_t r = find_root(root, qs->slot_of[i]);
        const unsigned char h = (unsigned char)rows[W * i + 1];
        if (rows[W * i] < label[r]) {
            label[r] = rows[W * i];
            *changed = 1;
        }
        if ((held[r] | h) != held[r]) {
            held[r] |= h;
            *changed = 1;
        }
    }
    /* reverse: the ghosts' labels below their owners' (rows[W i]: the owner's) and marks */
    for (size_t i = 0; i < n; ++i) {
        double *row = rows + W * i;
        const double owner = row[0];
        memset(row, 0, W * sizeof(double));
        if (i < owned)
            continue;
        const uint32_t r = find_root(root, qs->slot_of[i]);
        if (label[r] < owner) {
            row[0] = 1.0;
            row[1] = label[r];
        }
        for (int b = 0; b < 4; ++b)
            row[2 + b] = (held[r] & MARK[b]) ? 1.0 : 0.0;
    }
    if ((st = sinter_qs_domain_reverse_index(qs, rows, W)) != SINTER_OK)
        return st;
    for (size_t i = 0; i < owned; ++i) {
        const double *row = rows + W * i;
        const uint32_t r = find_root(root, qs->slot_of[i]);
        if (row[0] > 0.0) {
            const double mean = fmin(row[1] / row[0], label[r]);
            if (mean < label[r]) {
                label[r] = mean;
                *changed = 1;
            }
        }
        for (int b = 0; b < 4; ++b)
            if (row[2 + b] > 0.0 && !(held[r] & MARK[b])) {
                held[r] |= MARK[b];
                *changed = 1;
            }
    }
    return SINTER_OK;
}

enum { SUMS = 7 }; /* per free component: count, centroid sum (3), rotation sum (3) */

/* the index of label in the increasing list of k free labels (k: absent) */
static size_t find_label(const double *list, size_t k, double label)
{
    size_t lo = 0, hi = k;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (list[mid] < label)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < k && list[lo] == label ? lo : k;
}

/* The reproducible mode (qs_repro.h): out[c width + j] = the exact sum over every subdomain of
 * terms[i width + j] over the members i < count with comp[i] = c (< k; k: none). Collective. */
static sinter_status exact_sums(sinter_qs *qs, const size_t *comp, const double *terms,
                                size_t count, size_t k, size_t width, double *out)
{
    const size_t v = k * width;
    int64_t *e = sinter_alloc(qs->ctx, (v + 1) * sizeof(int64_t));
    sinter_repro_sum *sum = sinter_calloc(qs->ctx, v + 1, sizeof(sinter_repro_sum));
    sinter_status st =
        sinter_qs_domain_agree(qs, e == NULL || sum == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
    if (st == SINTER_OK) {
        for (size_t q = 0; q < v; ++q)
            e[q] = INT32_MIN;
        for (size_t i = 0; i < count; ++i)
            for (size_t j = 0; j < width && comp[i] < k; ++j) {
                const int ej = sinter_repro_exponent(terms + width * i + j, 1, 1, NULL);
                int64_t *eq = e + width * comp[i] + j;
                *eq = ej > *eq ? ej : *eq;
            }
        const sinter_repro_reduce_fn reduce = sinter_qs_repro_reduce(qs);
        if (reduce != NULL && reduce(e, v, SINTER_REPRO_MAX, qs) != 0)
            st = sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                             "quasi-static stepper: an exact sum's reduction failed");
        for (size_t i = 0; i < count && st == SINTER_OK; ++i)
            for (size_t j = 0; j < width && comp[i] < k; ++j) {
                const size_t q = width * comp[i] + j;
                sinter_repro_add(&sum[q], (int)e[q], terms + width * i + j, 1, 1);
            }
        if (st == SINTER_OK && sinter_repro_totals(sum, e, v, reduce, qs, out) != 0)
            st = sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                             "quasi-static stepper: an exact sum's reduction failed");
    }
    sinter_free(qs->ctx, e);
    sinter_free(qs->ctx, sum);
    return st;
}

sinter_status sinter_qs_domain_remove_free_motion(sinter_qs *qs, const sinter_qs_particles *p,
                                                  double *u, sinter_status st)
{
    /* every subdomain takes part in every exchange; a failure is agreed first */
    const size_t n = p->count, m = qs->count, owned = qs->dom.owned;
    uint32_t *root = NULL;
    unsigned char *held = NULL;
    double *label = NULL, *rows = NULL, *list = NULL, *sums = NULL, *terms = NULL;
    size_t *comp = NULL; /* the reproducible mode's exact sums */
    if (st == SINTER_OK) {
        root = sinter_alloc(qs->ctx, (n + 1) * sizeof(uint32_t));
        held = sinter_alloc(qs->ctx, n + 1);
        label = sinter_alloc(qs->ctx, (n + 1) * sizeof(double));
        rows = sinter_alloc(qs->ctx, (W * n + 1) * sizeof(double));
        if (root == NULL || held == NULL || label == NULL || rows == NULL)
            st = SINTER_ERR_NOMEM;
    }
    st = sinter_qs_domain_agree(qs, st);
    if (st != SINTER_OK)
        goto out;

    for (size_t s = 0; s < n; ++s) {
        root[s] = (uint32_t)s;
        held[s] = 0;
        label[s] = INFINITY;
    }
    for (size_t k = 0; k < m; ++k) {
        const uint32_t a = find_root(root, qs->beams[k].a);
        const uint32_t b = find_root(root, qs->beams[k].b);
        if (a != b)
            root[a > b ? a : b] = a > b ? b : a;
        held[qs->beams[k].a] |= 0x80;
        held[qs->beams[k].b] |= 0x80;
    }
    for (size_t s = 0; s < n; ++s) { /* ids and planes (of the owned members) to the roots */
        const uint32_t r = find_root(root, (uint32_t)s);
        const size_t i = qs->index_of_slot[s];
        label[r] = fmin(label[r], (double)qs->dom.id[i]);
        held[r] |= held[s] & 0x80;
        for (int d = 0; d < 3 && i < owned; ++d)
            if (qs->fixed[6 * s + (size_t)d])
                held[r] |= (unsigned char)(1u << d);
    }
    for (;;) {
        int changed = 0;
        if ((st = round_trip(qs, n, root, label, held, rows, &changed)) != SINTER_OK)
            goto out;
        double any = changed;
        st = sinter_qs_domain_reduce(qs, &any, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
        if (st != SINTER_OK)
            goto out;
        if (any == 0.0)
            break;
    }

    /* the free components' labels, in increasing order */
    size_t k = 0, capacity = 0;
    for (double last = -INFINITY;;) {
        double next = INFINITY;
        for (size_t s = 0; s < n; ++s)
            if (root[s] == s && (held[s] & 0x80) && (held[s] & 7) != 7 && label[s] > last)
                next = fmin(next, label[s]);
        st = sinter_qs_domain_reduce(qs, &next, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MIN);
        if (st == SINTER_OK && isfinite(next) && k == capacity)
            st = sinter_grow(qs->ctx, (void **)&list, &capacity, 2 * capacity + 8, sizeof(double));
        st = sinter_qs_domain_agree(qs, st);
        if (st != SINTER_OK)
            goto out;
        if (!isfinite(next))
            break;
        list[k++] = last = next;
    }
    if (k == 0)
        goto out;

    sums = sinter_alloc(qs->ctx, ((SUMS + 3) * k + 1) * sizeof(double));
    if (qs->dom.repro) { /* per owned member: its component and terms (exact_sums) */
        comp = sinter_alloc(qs->ctx, (owned + 1) * sizeof(size_t));
        terms = sinter_alloc(qs->ctx, (SUMS * owned + 1) * sizeof(double));
    }
    st = sinter_qs_domain_agree(
        qs, sums == NULL || (qs->dom.repro && (comp == NULL || terms == NULL)) ? SINTER_ERR_NOMEM
                                                                               : SINTER_OK);
    if (st != SINTER_OK)
        goto out;
    memset(sums, 0, SUMS * k * sizeof(double));
    for (size_t i = 0; i < owned; ++i) { /* centroid and mean rotation, owned members */
        const size_t s = qs->slot_of[i];
        const size_t c = find_label(list, k, label[find_root(root, (uint32_t)s)]);
        if (comp != NULL) {
            comp[i] = c;
            double *t = terms + SUMS * i;
            t[0] = 1.0;
            for (size_t d = 0; d < 3; ++d) {
                t[1 + d] = p->x[3 * i + d];
                t[4 + d] = u[6 * s + 3 + d];
            }
        }
        if (c == k)
            continue;
        double *sc = sums + SUMS * c;
        sc[0] += 1.0;
        for (size_t d = 0; d < 3; ++d) {
            sc[1 + d] += p->x[3 * i + d];
            sc[4 + d] += u[6 * s + 3 + d];
        }
    }
    st = comp != NULL
             ? exact_sums(qs, comp, terms, owned, k, SUMS, sums)
             : sinter_qs_domain_reduce(qs, sums, SUMS * k, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (st != SINTER_OK)
        goto out;
    double *left = sums + SUMS * k; /* the displacements left after the rotations */
    memset(left, 0, 3 * k * sizeof(double));
    const unsigned char per =
        (unsigned char)(qs->periodic[0] | qs->periodic[1] << 1 | qs->periodic[2] << 2);
    for (size_t s = 0; s < n; ++s) { /* the rotations, ghosts too */
        const uint32_t r = find_root(root, (uint32_t)s);
        const size_t c = find_label(list, k, label[r]);
        if (c == k)
            continue;
        const double *sc = sums + SUMS * c;
        const size_t i = qs->index_of_slot[s];
        const unsigned char h = (unsigned char)(held[r] | per); /* (as qs_floating.c) */
        double w[3], arm[3];
        for (int a = 0; a < 3; ++a) {
            const int free_about = !(h & (1u << ((a + 1) % 3))) && !(h & (1u << ((a + 2) % 3)));
            w[a] = free_about ? sc[4 + a] / sc[0] : 0.0;
            arm[a] = p->x[3 * i + (size_t)a] - sc[1 + a] / sc[0];
        }
        const double turn[3] = {w[1] * arm[2] - w[2] * arm[1], w[2] * arm[0] - w[0] * arm[2],
                                w[0] * arm[1] - w[1] * arm[0]};
        for (size_t d = 0; d < 3; ++d) {
            u[6 * s + d] -= turn[d];
            u[6 * s + 3 + d] -= w[d];
            if (i < owned)
                left[3 * c + d] += u[6 * s + d];
            if (i < owned && comp != NULL)
                terms[3 * i + d] = u[6 * s + d]; /* (the first sums' terms are spent) */
        }
    }
    st = comp != NULL
             ? exact_sums(qs, comp, terms, owned, k, 3, left)
             : sinter_qs_domain_reduce(qs, left, 3 * k, SINTER_REDUCE_F64, SINTER_REDUCE_SUM);
    if (st != SINTER_OK)
        goto out;
    for (size_t s = 0; s < n; ++s) { /* then the translations */
        const uint32_t r = find_root(root, (uint32_t)s);
        const size_t c = find_label(list, k, label[r]);
        if (c == k)
            continue;
        for (size_t d = 0; d < 3; ++d)
            if (!(held[r] & (1u << d)))
                u[6 * s + d] -= left[3 * c + d] / sums[SUMS * c];
    }
out:
    sinter_free(qs->ctx, root);
    sinter_free(qs->ctx, held);
    sinter_free(qs->ctx, label);
    sinter_free(qs->ctx, rows);
    sinter_free(qs->ctx, list);
    sinter_free(qs->ctx, sums);
    sinter_free(qs->ctx, comp);
    sinter_free(qs->ctx, terms);
    return st;
}
