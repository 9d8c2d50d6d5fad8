/*
 * Per-particle export records keyed by id, as the reproducible-mode tests gather and compare
 * them (test_domain_repro.c, test_domain_staggered_repro.c, test_qs_domain_repro.c): each
 * owned particle's record (sinter_stepper_export without removal) stored at index id - 1,
 * compared by length and bytes, freed. Static inline, so that a test using a part of it does
 * not warn about the rest.
 */
#ifndef SINTER_DOMAIN_RECORDS_H
#define SINTER_DOMAIN_RECORDS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <sinter.h>

/* Each owned particle's record (remove = 0) into rec[id - 1] and len[id - 1], ids 1 to n; an
 * id out of range or met twice is SINTER_ERR_INVALID. The caller serialises concurrent calls
 * on the same arrays only if two subdomains may write the same slot (they may not when every
 * particle is owned once). */
static inline sinter_status domain_records_export_owned(sinter_stepper *st, sinter_particles *ps,
                                                        int n, unsigned char **rec, size_t *len)
{
    size_t owned = 0;
    const uint64_t *ids = NULL;
    sinter_status s = sinter_particles_owned_count(ps, &owned);
    if (s == SINTER_OK)
        s = sinter_particles_view_read(ps, SINTER_FIELD_ID, (const void **)&ids, NULL, NULL);
    uint64_t *id = malloc((owned + 1) * sizeof(uint64_t));
    if (s == SINTER_OK && id != NULL)
        memcpy(id, ids, owned * sizeof(uint64_t));
    if (ids != NULL)
        sinter_particles_release(ps, SINTER_FIELD_ID);
    for (size_t i = 0; i < owned && s == SINTER_OK && id != NULL; ++i) {
        size_t bytes = 0, written = 0;
        if ((s = sinter_stepper_export_size(st, 1, &i, &bytes)) != SINTER_OK)
            break;
        unsigned char *buf = malloc(bytes);
        if (buf == NULL || id[i] < 1 || id[i] > (uint64_t)n || rec[id[i] - 1] != NULL) {
            free(buf);
            s = SINTER_ERR_INVALID;
            break;
        }
        s = sinter_stepper_export(st, 1, &i, buf, bytes, &written, 0);
        rec[id[i] - 1] = buf;
        len[id[i] - 1] = written;
    }
    free(id);
    return id == NULL ? SINTER_ERR_NOMEM : s;
}

/* The number of the n records that differ between a and b (length or bytes). */
static inline int domain_records_differing(unsigned char *const *a, const size_t *a_len,
                                           unsigned char *const *b, const size_t *b_len, int n)
{
    int d = 0;
    for (int k = 0; k < n; ++k)
        d += a_len[k] != b_len[k] || memcmp(a[k], b[k], a_len[k]) != 0;
    return d;
}

/* Frees the n records (the caller clears the arrays). */
static inline void domain_records_free(unsigned char **rec, int n)
{
    for (int k = 0; k < n; ++k)
        free(rec[k]);
}

/* The documented restart's step for one record: imports it, and when its particle's centre
 * lies outside slab `rank` of `slabs` equal slabs over [x0, x1) along x (the first and last
 * slab extend outwards) takes it out again (export with removal); slabs 0 keeps every one. */
static inline sinter_status domain_records_import_in_slab(sinter_stepper *st, sinter_particles *ps,
                                                          const unsigned char *rec, size_t len,
                                                          int slabs, int rank, double x0, double x1)
{
    size_t first = 0, count = 0;
    sinter_status s = sinter_particles_count(ps, &first);
    if (s == SINTER_OK)
        s = sinter_stepper_import(st, rec, len, &count);
    const double *x = NULL;
    if (s == SINTER_OK)
        s = sinter_particles_view_read(ps, SINTER_FIELD_POSITION, (const void **)&x, NULL, NULL);
    if (s != SINTER_OK)
        return s;
    const double r = floor((x[3 * first] - x0) / (x1 - x0) * slabs);
    sinter_particles_release(ps, SINTER_FIELD_POSITION);
    if (slabs <= 0 || (r < 0.0 ? 0 : r >= slabs ? slabs - 1 : (int)r) == rank)
        return SINTER_OK;
    size_t bytes = 0, written = 0;
    unsigned char scratch[1];
    if ((s = sinter_stepper_export_size(st, 1, &first, &bytes)) != SINTER_OK)
        return s;
    unsigned char *buf = bytes > 1 ? malloc(bytes) : scratch;
    s = buf == NULL ? SINTER_ERR_NOMEM
                    : sinter_stepper_export(st, 1, &first, buf, bytes, &written, 1);
    if (buf != scratch)
        free(buf);
    return s;
}

/* The stepper's global part (sinter_stepper_save_global) into a new buffer *global of *len
 * bytes; *global NULL on failure. */
static inline sinter_status domain_records_save_global(sinter_stepper *st, unsigned char **global,
                                                       size_t *len)
{
    size_t bytes = 0;
    *global = NULL;
    *len = 0;
    sinter_status s = sinter_stepper_save_global(st, NULL, 0, &bytes);
    if (s != SINTER_OK)
        return s;
    unsigned char *buf = malloc(bytes + 1);
    if (buf == NULL)
        return SINTER_ERR_NOMEM;
    if ((s = sinter_stepper_save_global(st, buf, bytes, &bytes)) != SINTER_OK) {
        free(buf);
        return s;
    }
    *global = buf;
    *len = bytes;
    return SINTER_OK;
}

#endif
