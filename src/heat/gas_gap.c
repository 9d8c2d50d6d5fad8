/*
 * Gas conduction between spheres apart (issue 40): the lens of gas_gap.h over the candidate
 * pairs within the model's reach. The candidate list holds every such pair because the stepper
 * widens its neighbour search by the reach (contact/neighbors.h, "reach").
 */
#include "gas_gap.h"

#include "contact/neighbors.h"
#include "particles/particles.h"

void sinter_gas_near_pairs(const sinter_heat_eval *e, const sinter_gas_law *law)
{
    const sinter_pair_list *p = e->pairs;
    if (p == NULL || !(law->k > 0.0) || !(law->reach > 0.0))
        return;
    const sinter_particles *ps = e->ps;
    const double *x = ps->x, *r = ps->radius, *theta = ps->temperature;
    for (size_t k = 0; k < p->count; ++k) {
        const uint32_t i = p->i[k], j = p->j[k];
        const double ex = x[3 * j] - x[3 * i], ey = x[3 * j + 1] - x[3 * i + 1],
                     ez = x[3 * j + 2] - x[3 * i + 2];
        const double d2 = ex * ex + ey * ey + ez * ez, rs = r[i] + r[j];
        if (d2 < rs * rs) /* a contact (the search's test): the contact list's lens */
            continue;
        const double rmin = r[i] < r[j] ? r[i] : r[j], h = sqrt(d2) - rs;
        if (!(h < law->reach * rmin))
            continue;
        const double g =
            sinter_gas_lens(law->k, law->gap, law->radius * rmin, r[i] * r[j] / rs, h, 0.0);
        const double q = g * (theta[j] - theta[i]);
        e->heat[i] += q;
        e->heat[j] -= q;
    }
}
