/* Every particle's export record by id - 1 (sinter_stepper_export, remove = 0), for the tests
 * of the reproducible mode under mpiexec (issues 43 and 44): each rank exports its owned
 * particles' records, rank 0 of a communicator gathers them by id and compares them byte for
 * byte with another run's. Everything is static inline: a file that includes this uses what it
 * needs. */
#ifndef SINTER_TEST_MPI_RECORDS_H
#define SINTER_TEST_MPI_RECORDS_H

#include <mpi.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <sinter.h>

#include "../unit/domain_records.h"

enum { RECORDS_MAX = 256 }; /* the most particles of a test */

typedef struct records {
    unsigned char *rec[RECORDS_MAX];
    size_t len[RECORDS_MAX];
    int twice;             /* records of a particle already held (or of no particle of the test) */
    unsigned char *global; /* the global part (sinter_stepper_save_global), if saved */
    size_t global_len;
} records;

static inline void records_free(records *r)
{
    domain_records_free(r->rec, RECORDS_MAX);
    free(r->global);
    memset(r, 0, sizeof *r);
}

/* Each owned particle's record, by itself, into out by id (ids 1 to n). */
static inline sinter_status records_export(sinter_stepper *st, sinter_particles *ps, int n,
                                           records *out)
{
    if (n > RECORDS_MAX)
        return SINTER_ERR_INVALID;
    return domain_records_export_owned(st, ps, n, out->rec, out->len);
}

/* The stepper's global part into out. */
static inline sinter_status records_save_global(sinter_stepper *st, records *out)
{
    free(out->global);
    return domain_records_save_global(st, &out->global, &out->global_len);
}

/* Every rank's records of `comm` into `all` on its rank 0, by id (sorted so); collective. */
static inline int records_gather(const records *mine, records *all, int n, MPI_Comm comm)
{
    int rank = 0, size = 0, bad = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    size_t bytes = 0;
    for (int k = 0; k < n; ++k)
        bytes += mine->rec[k] != NULL ? 16 + mine->len[k] : 0;
    unsigned char *blob = malloc(bytes + 1), *at = blob;
    bad |= blob == NULL || bytes > (size_t)INT32_MAX;
    for (int k = 0; k < n && !bad; ++k) {
        if (mine->rec[k] == NULL)
            continue;
        const uint64_t head[2] = {(uint64_t)k + 1, mine->len[k]};
        memcpy(at, head, 16);
        memcpy(at + 16, mine->rec[k], mine->len[k]);
        at += 16 + mine->len[k];
    }
    const int count = bad ? 0 : (int)bytes;
    int *counts = calloc((size_t)size, sizeof(int)), *displs = calloc((size_t)size, sizeof(int));
    int c0 = 0, *cnt = counts != NULL ? counts : &c0;
    MPI_Gather(&count, 1, MPI_INT, rank == 0 ? cnt : NULL, 1, MPI_INT, 0, comm);
    size_t total = 0;
    for (int r = 0; r < size && rank == 0 && counts != NULL && displs != NULL; ++r) {
        displs[r] = (int)total;
        total += (size_t)counts[r];
    }
    unsigned char *every = rank == 0 ? malloc(total + 1) : NULL;
    bad |= rank == 0 && (every == NULL || counts == NULL || displs == NULL);
    MPI_Gatherv(blob, count, MPI_BYTE, every, counts, displs, MPI_BYTE, 0, comm);
    free(blob);
    free(counts);
    free(displs);
    if (rank != 0)
        return bad;
    records_free(all);
    for (size_t off = 0; every != NULL && off + 16 <= total;) {
        uint64_t head[2];
        memcpy(head, every + off, 16);
        off += 16;
        if (head[0] < 1 || head[0] > (uint64_t)n || all->rec[head[0] - 1] != NULL ||
            off + head[1] > total) {
            all->twice++;
            off += head[1];
            continue;
        }
        all->rec[head[0] - 1] = malloc(head[1] + 1);
        bad |= all->rec[head[0] - 1] == NULL;
        if (all->rec[head[0] - 1] != NULL)
            memcpy(all->rec[head[0] - 1], every + off, head[1]);
        all->len[head[0] - 1] = head[1];
        off += head[1];
    }
    free(every);
    return bad;
}

/* The particles (of ids 1 to n) whose records differ: missing, length or bytes. */
static inline int records_differing(const records *a, const records *b, int n)
{
    int d = 0;
    for (int k = 0; k < n; ++k)
        d += a->rec[k] == NULL || b->rec[k] == NULL || a->len[k] != b->len[k] ||
             memcmp(a->rec[k], b->rec[k], a->len[k]) != 0;
    return d + a->twice + b->twice;
}

static inline int records_same_global(const records *a, const records *b)
{
    return a->global != NULL && b->global != NULL && a->global_len == b->global_len &&
           memcmp(a->global, b->global, a->global_len) == 0;
}

#endif
