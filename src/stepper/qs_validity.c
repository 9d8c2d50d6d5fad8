/*
 * The quasi-static stepper's validity guard (docs/7dof.md §2.6): after a step, the share of each
 * particle's surface its necks cover (the caps cut off by its links' neck planes, summed) against
 * SINTER_NECK_COVERAGE_LIMIT, where neighbouring necks are taken to meet, and the packing's
 * relative density against SINTER_NECK_DENSITY_LIMIT, the end of the model's domain (seed 001
 * sec. 4.2). Once per quantity: a warning (qs_validity = 1) or SINTER_ERR_DOMAIN (2).
 */
#include <math.h>
#include <stdio.h>

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

sinter_status sinter_qs_check_validity(sinter_qs *qs, const sinter_qs_particles *p, double t)
{
    if (qs->opt.validity <= 0.0 || (qs->warned_coverage && qs->warned_density) || p->count == 0)
        return SINTER_OK;
    char what[320];
    if (!qs->warned_coverage) {
        double *share = sinter_calloc(qs->ctx, p->count, sizeof(double));
        if (share == NULL)
            return SINTER_ERR_NOMEM;
        for (size_t k = 0; k < qs->count; ++k) {
            const sinter_qs_link *l = &qs->links[k];
            const double x = l->neck.y[SINTER_NECK_X];
            share[l->beam.a] += sinter_neck_cap_share(x / p->radius[l->beam.a]);
            share[l->beam.b] += sinter_neck_cap_share(x / p->radius[l->beam.b]);
        }
        /* the most covered particle, the smallest id on ties (the slots' order, qs_ids.c) */
        const int by_slot = qs->slots_valid && qs->slots == p->count;
        size_t worst = by_slot ? qs->index_of_slot[0] : 0;
        for (size_t s = 1; s < p->count; ++s) {
            const size_t i = by_slot ? qs->index_of_slot[s] : s;
            if (share[i] > share[worst])
                worst = i;
        }
        const double most = share[worst];
        sinter_free(qs->ctx, share);
        if (most > SINTER_NECK_COVERAGE_LIMIT) {
            size_t links = 0;
            double ratio = 0.0;
            for (size_t k = 0; k < qs->count; ++k) {
                const sinter_qs_link *l = &qs->links[k];
                if (l->beam.a == worst || l->beam.b == worst) {
                    ++links;
                    ratio = fmax(ratio, l->neck.y[SINTER_NECK_X] / p->radius[worst]);
                }
            }
            snprintf(what, sizeof(what),
                     "the necks impinge: the %zu necks of particle id %llu (largest x/R = %.4g) "
                     "cover %.4g of its surface, more than %g (docs/7dof.md section 2.6), at "
                     "t = %.6g s",
                     links, (unsigned long long)(p->id != NULL ? p->id[worst] : worst), ratio, most,
                     SINTER_NECK_COVERAGE_LIMIT, t);
            const sinter_status st = report(qs, &qs->warned_coverage, what);
            if (st != SINTER_OK)
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
