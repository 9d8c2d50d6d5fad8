/*
 * Particles sent to the ranks whose parts hold them (libsinter_mpi, issue 44): each rank
 * exports (with removal) the particles that lie in another rank's part, one record stream per
 * destination, and imports what the others send it. Only libsinter's public API is used: the
 * records carry every field and contact history, so the particles continue on their new
 * rank as they would have on the old one (include/sinter.h, sinter_stepper_export).
 *
 * A stream goes through MPI_Alltoallv, whose counts and displacements are ints: a rank sends
 * and receives at most INT_MAX bytes in one exchange (about 3 million particles of 620 bytes);
 * more is refused with SINTER_ERR_RANGE on every rank.
 */
#include "mpi/send_to_owners.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/agree.h"

/* The positions of the n owned particles, copied (the view is released before any export). */
static int owned_positions(sinter_particles *ps, size_t n, double **x)
{
    *x = NULL;
    if (n == 0)
        return SINTER_OK;
    const void *view = NULL;
    int s = sinter_particles_view_read(ps, SINTER_FIELD_POSITION, &view, NULL, NULL);
    if (s != SINTER_OK)
        return s;
    *x = malloc(3 * n * sizeof(double));
    if (*x != NULL)
        memcpy(*x, view, 3 * n * sizeof(double));
    s = sinter_particles_release(ps, SINTER_FIELD_POSITION);
    return *x == NULL ? SINTER_ERR_NOMEM : s;
}

/* Export (with removal) the particles of original index i with owner[i] == dest, appending
 * their stream to *buf (of *used bytes, *cap allocated). removed[i] marks the particles that
 * left already: the set keeps the others' order, so the current index of i is i less the
 * removed particles before it. */
static int export_to(sinter_stepper *st, const int *owner, unsigned char *removed, size_t n,
                     int dest, size_t *idx, unsigned char **buf, size_t *used, size_t *cap,
                     size_t *bytes)
{
    size_t m = 0, gone = 0;
    for (size_t i = 0; i < n; ++i) {
        if (owner[i] == dest)
            idx[m++] = i - gone;
        gone += removed[i];
    }
    *bytes = 0;
    if (m == 0)
        return SINTER_OK;
    size_t need = 0, written = 0;
    int s = sinter_stepper_export_size(st, m, idx, &need);
    if (s != SINTER_OK)
        return s;
    if (*used + need > *cap) {
        const size_t grown = *used + need > 2 * *cap ? *used + need : 2 * *cap;
        unsigned char *p = realloc(*buf, grown);
        if (p == NULL)
            return SINTER_ERR_NOMEM;
        *buf = p;
        *cap = grown;
    }
    s = sinter_stepper_export(st, m, idx, *buf + *used, need, &written, 1);
    if (s != SINTER_OK)
        return s;
    for (size_t i = 0; i < n; ++i)
        removed[i] |= owner[i] == dest;
    *used += written;
    *bytes = written;
    return SINTER_OK;
}

int sinter_mpi_send_to_owners(sinter_stepper *st, sinter_particles *ps, MPI_Comm comm,
                              const sinter_mpi_decomp *decomp)
{
    int rank = 0, size = 0, parts = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    size_t n = 0;
    int s = sinter_mpi_decomp_info(decomp, NULL, &parts);
    if (s == SINTER_OK && parts != size)
        s = SINTER_ERR_INVALID;
    if (s == SINTER_OK)
        s = sinter_particles_owned_count(ps, &n);
    double *x = NULL;
    if (s == SINTER_OK)
        s = owned_positions(ps, n, &x);
    int *owner = malloc((n + 1) * sizeof(int));
    unsigned char *removed = calloc(n + 1, 1);
    size_t *idx = malloc((n + 1) * sizeof(size_t));
    uint64_t *sizes = calloc(2 * (size_t)size, sizeof(uint64_t)); /* sent, then received */
    int *counts = malloc(4 * (size_t)size * sizeof(int));
    if (s == SINTER_OK &&
        (owner == NULL || removed == NULL || idx == NULL || sizes == NULL || counts == NULL))
        s = SINTER_ERR_NOMEM;
    if (s == SINTER_OK && n > 0)
        s = sinter_mpi_decomp_owners(decomp, x, n, owner);
    free(x);
    unsigned char *send = NULL, *recv = NULL;
    size_t used = 0, cap = 0;
    for (int d = 0; d < size && s == SINTER_OK; ++d) {
        size_t bytes = 0;
        if (d != rank)
            s = export_to(st, owner, removed, n, d, idx, &send, &used, &cap, &bytes);
        sizes[d] = bytes;
    }
    s = sinter_mpi_agree(comm, s);
    if (s == SINTER_OK &&
        MPI_Alltoall(sizes, 1, MPI_UINT64_T, sizes + size, 1, MPI_UINT64_T, comm) != MPI_SUCCESS)
        s = SINTER_ERR_IO;
    s = sinter_mpi_agree(comm, s);
    /* int counts and displacements for MPI_Alltoallv */
    size_t received = 0;
    if (s == SINTER_OK) {
        uint64_t sent_at = 0, recv_at = 0;
        for (int r = 0; r < size; ++r) {
            if (sizes[r] > INT_MAX || sizes[size + r] > INT_MAX || sent_at > INT_MAX ||
                recv_at > INT_MAX)
                s = SINTER_ERR_RANGE;
            counts[r] = (int)sizes[r];
            counts[size + r] = (int)sent_at;
            counts[2 * size + r] = (int)sizes[size + r];
            counts[3 * size + r] = (int)recv_at;
            sent_at += sizes[r];
            recv_at += sizes[size + r];
        }
        received = (size_t)recv_at;
        if (s == SINTER_OK && (recv = malloc(received + 1)) == NULL)
            s = SINTER_ERR_NOMEM;
    }
    s = sinter_mpi_agree(comm, s);
    unsigned char none = 0;
    if (s == SINTER_OK &&
        MPI_Alltoallv(send != NULL ? send : &none, counts, counts + size, MPI_BYTE, recv,
                      counts + 2 * size, counts + 3 * size, MPI_BYTE, comm) != MPI_SUCCESS)
        s = SINTER_ERR_IO;
    free(send);
    /* arrivals in ascending rank order of their senders */
    for (int r = 0; r < size && s == SINTER_OK; ++r)
        if (counts[2 * size + r] > 0)
            s = sinter_stepper_import(st, recv + counts[3 * size + r], (size_t)counts[2 * size + r],
                                      NULL);
    s = sinter_mpi_agree(comm, s);
    free(recv);
    free(owner);
    free(removed);
    free(idx);
    free(sizes);
    free(counts);
    return s;
}
