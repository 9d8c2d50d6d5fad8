/*
 * The quasi-static stepper's validity guard (docs/7dof.md §2.6): after a step, the share of each
 * particle's surface its necks cover (the caps cut off by its links' neck planes, summed) against
 * SINTER_NECK_COVERAGE_LIMIT, where neighbouring necks are taken to meet, and the packing's
 * relative density against SINTER_NECK_DENSITY_LIMIT, the end of the model's domain (seed 001
 * sec. 4.2). Once per quantity: a warning (qs_validity = 1) or SINTER_ERR_DOMAIN (2).
 */
#include <math.h>
#include <stdio.h>

#include "stepper/qs_domain.h"
#include "stepper/qs_repro.h"
#include "stepper/qs_struct.h"
#include "stepper/quasistatic.h"

static sinter_status report(sinter_qs *qs, int *warned, const char *what)
{
    if (qs->opt.validity >= 2.0)
        return sinter_fail(qs->ctx, SINTER_ERR_DOMAIN, "quasi-static stepper: %s", what);
    *warned = 1;
    sinter_log(qs->ctx, SINTER_LOG_WARNING, "quasi-static stepper: %s", what);
    return SINTER_OK;
}

/* Each owned particle's covered share as an exact sum over every subdomain's links (the
 * reproducible mode, qs_repro.h); ghosts 0. Collective. */
static sinter_status exact_shares(sinter_qs *qs, const sinter_qs_particles *p, double *share)
{
    const size_t m = qs->count, n = p->count;
    double *terms = sinter_alloc(qs->ctx, (2 * m + 1) * sizeof(double));
    uint32_t *row = sinter_alloc(qs->ctx, (2 * m + 1) * sizeof(uint32_t));
    void *work = sinter_alloc(qs->ctx, sinter_repro_rows_bytes(n, 1) + 1);
    sinter_status st = sinter_qs_domain_agree(
        qs, terms == NULL || row == NULL || work == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
    if (st == SINTER_OK) {
        for (size_t k = 0; k < m; ++k) {
            const sinter_qs_link *l = &qs->links[k];
            const double x = l->neck.y[SINTER_NECK_X];
            row[2 * k] = l->beam.a;
            row[2 * k + 1] = l->beam.b;
            terms[2 * k] = sinter_neck_cap_share(x / p->radius[l->beam.a]);
            terms[2 * k + 1] = sinter_neck_cap_share(x / p->radius[l->beam.b]);
        }
        if (sinter_repro_rows(n, qs->dom.on ? qs->dom.owned : n, 1, row, terms, 2 * m,
                              sinter_qs_repro_reduce(qs), sinter_qs_repro_reverse(qs), qs, work,
                              share) != 0)
            st = sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                             "quasi-static stepper: an exchange of the necks' coverage failed");
    }
    sinter_free(qs->ctx, terms);
    sinter_free(qs->ctx, row);
    sinter_free(qs->ctx, work);
    return st;
}

sinter_status sinter_qs_check_validity(sinter_qs *qs, const sinter_qs_particles *p, double t)
{
    /* with domain operations every decision below follows reduced values (qs_domain.h): a
     * particle's necks may lie on several subdomains */
    const int domain = qs->dom.on;
    if (qs->opt.validity <= 0.0 || (qs->warned_coverage && qs->warned_density) ||
        (p->count == 0 && !domain))
        return SINTER_OK;
    char what[320];
    if (!qs->warned_coverage) {
        double *share = sinter_calloc(qs->ctx, p->count + 1, sizeof(double));
        sinter_status st = sinter_qs_domain_agree(qs, share == NULL ? SINTER_ERR_NOMEM : SINTER_OK);
        if (st != SINTER_OK) {
            sinter_free(qs->ctx, share);
            return st;
        }
        if (qs->dom.repro) /* the reproducible mode: exact row sums (qs_repro.h) */
            st = exact_shares(qs, p, share);
        else {
            for (size_t k = 0; k < qs->count; ++k) {
                const sinter_qs_link *l = &qs->links[k];
                const double x = l->neck.y[SINTER_NECK_X];
                share[l->beam.a] += sinter_neck_cap_share(x / p->radius[l->beam.a]);
                share[l->beam.b] += sinter_neck_cap_share(x / p->radius[l->beam.b]);
            }
            st = sinter_qs_domain_reverse_index(qs, share, 1); /* (the ghosts' to owners) */
        }
        /* the most covered particle, the smallest id on ties (the slots' order, qs_ids.c) */
        const int by_slot = qs->slots_valid && qs->slots == p->count;
        size_t worst = SIZE_MAX;
        for (size_t s = 0; s < p->count; ++s) {
            const size_t i = by_slot ? qs->index_of_slot[s] : s;
            if (!sinter_qs_domain_ghost(qs, i) && (worst == SIZE_MAX || share[i] > share[worst]))
                worst = i;
        }
        double most = worst != SIZE_MAX ? share[worst] : 0.0;
        uint64_t worst_id = worst == SIZE_MAX ? UINT64_MAX : p->id != NULL ? p->id[worst] : worst;
        sinter_free(qs->ctx, share);
        if (domain && st == SINTER_OK) { /* over the subdomains: the largest share, its
                                            smallest id */
            const double mine = most;
            st = sinter_qs_domain_reduce(qs, &most, 1, SINTER_REDUCE_F64, SINTER_REDUCE_MAX);
            worst_id = worst != SIZE_MAX && mine == most ? worst_id : UINT64_MAX;
            if (st == SINTER_OK)
                st =
                    sinter_qs_domain_reduce(qs, &worst_id, 1, SINTER_REDUCE_U64, SINTER_REDUCE_MIN);
        }
        if (st != SINTER_OK)
            return st;
        if (most > SINTER_NECK_COVERAGE_LIMIT) {
            uint64_t links = 0;
            double ratio = 0.0;
            for (size_t k = 0; k < qs->count; ++k) {
                const sinter_qs_link *l = &qs->links[k];
                const int on_a = domain ? l->id_a == worst_id : l->beam.a == worst;
                const int on_b = domain ? l->id_b == worst_id : l->beam.b == worst;
                if (on_a || on_b) {
                    ++links;
                    ratio = fmax(ratio, l->neck.y[SINTER_NECK_X] /
                                            p->radius[on_a ? l->beam.a : l->beam.b]);
                }
            }
            if (domain && ((st = sinter_qs_domain_reduce(qs, &links, 1, SINTER_REDUCE_U64,
                                                         SINTER_REDUCE_SUM)) != SINTER_OK ||
                           (st = sinter_qs_domain_reduce(qs, &ratio, 1, SINTER_REDUCE_F64,
                                                         SINTER_REDUCE_MAX)) != SINTER_OK))
                return st;
            snprintf(what, sizeof(what),
                     "the necks impinge: the %llu necks of particle id %llu (largest x/R = %.4g) "
                     "cover %.4g of its surface, more than %g (docs/7dof.md section 2.6), at "
                     "t = %.6g s",
                     (unsigned long long)links, (unsigned long long)worst_id, ratio, most,
                     SINTER_NECK_COVERAGE_LIMIT, t);
            if ((st = report(qs, &qs->warned_coverage, what)) != SINTER_OK)
                return st;
        }
    }
    if (!qs->warned_density) {
        sinter_qs_stats stats;
        sinter_qs_stats_get(qs, p, &stats);
        if (stats.relative_density > SINTER_NECK_DENSITY_LIMIT) {
            snprintf(what, sizeof(what),
                     "the relative density %.4g passed %g, the end of the model's domain (seed "
                     "001 sec. 4.2, docs/7dof.md section 2.6), at t = %.6g s",
                     stats.relative_density, SINTER_NECK_DENSITY_LIMIT, t);
            return report(qs, &qs->warned_density, what);
        }
    }
    return SINTER_OK;
}
