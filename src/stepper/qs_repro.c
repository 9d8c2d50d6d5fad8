/* The quasi-static stepper's exact sums in the reproducible mode (qs_repro.h, issue 43). */
#include <string.h>

#include "domain/domain.h"
#include "stepper/qs_domain.h"
#include "stepper/qs_repro.h"

static int reduce_i64(int64_t *values, size_t count, int op, void *user)
{
    sinter_qs *qs = user;
    return sinter_domain_reduce(qs->ctx, qs->dom.d, values, count, SINTER_REDUCE_I64,
                                op == SINTER_REPRO_MAX ? SINTER_REDUCE_MAX : SINTER_REDUCE_SUM) !=
           SINTER_OK;
}

static int reverse_rows(double *rows, size_t width, void *user)
{
    return sinter_qs_domain_reverse_index(user, rows, width) != SINTER_OK;
}

sinter_repro_reduce_fn sinter_qs_repro_reduce(const sinter_qs *qs)
{
    return qs->dom.on ? reduce_i64 : NULL;
}

sinter_repro_reverse_fn sinter_qs_repro_reverse(const sinter_qs *qs)
{
    return qs->dom.on && qs->dom.ghosts > 0 ? reverse_rows : NULL;
}

sinter_status sinter_qs_repro_series(sinter_qs *qs, const double *terms, size_t n, size_t count,
                                     double *out)
{
    if (sinter_repro_series(terms, n, count, sinter_qs_repro_reduce(qs), qs, out) != 0)
        return sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                           "quasi-static stepper: an exact sum's reduction failed");
    return SINTER_OK;
}

sinter_status sinter_qs_repro_loads(sinter_qs *qs, size_t n, const double *fn, double *f)
{
    const size_t m = qs->count, width = 3; /* forces only: the sintering loads are axial */
    double *terms = sinter_alloc(qs->ctx, (2 * width * m + 1) * sizeof(double));
    double *out = sinter_alloc(qs->ctx, (width * n + 1) * sizeof(double));
    uint32_t *row = sinter_alloc(qs->ctx, (2 * m + 1) * sizeof(uint32_t));
    void *work = sinter_alloc(qs->ctx, sinter_repro_rows_bytes(n, width) + 1);
    sinter_status st =
        terms == NULL || out == NULL || row == NULL || work == NULL ? SINTER_ERR_NOMEM : SINTER_OK;
    if ((st = sinter_qs_domain_agree(qs, st)) == SINTER_OK) {
        for (size_t k = 0; k < m; ++k) { /* rows by index: owned, then ghosts */
            const sinter_qs_link *l = &qs->links[k];
            row[2 * k] = l->beam.a;
            row[2 * k + 1] = l->beam.b;
            for (size_t d = 0; d < 3; ++d) {
                terms[2 * width * k + d] = fn[k] * l->beam.axis[d];
                terms[2 * width * k + width + d] = -(fn[k] * l->beam.axis[d]);
            }
        }
        const size_t owned = qs->dom.on ? qs->dom.owned : n;
        if (sinter_repro_rows(n, owned, width, row, terms, 2 * m, sinter_qs_repro_reduce(qs),
                              sinter_qs_repro_reverse(qs), qs, work, out) != 0)
            st = sinter_fail(qs->ctx, SINTER_ERR_CALLBACK,
                             "quasi-static stepper: an exchange of the exact loads failed");
        else
            for (size_t i = 0; i < n; ++i) {
                double *fi = f + 6 * (size_t)qs->slot_of[i];
                memset(fi, 0, 6 * sizeof(double));
                memcpy(fi, out + width * i, width * sizeof(double));
            }
    }
    sinter_free(qs->ctx, terms);
    sinter_free(qs->ctx, out);
    sinter_free(qs->ctx, row);
    sinter_free(qs->ctx, work);
    return st;
}
