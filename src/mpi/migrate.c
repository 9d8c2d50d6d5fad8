/*
 * Migration (libsinter_mpi, issue 44): at a redistribution every owned particle whose centre
 * left this rank's part goes, with everything its stepper keeps for it (sinter_stepper_export's
 * record stream: fields, contact histories, links, warm starts), to the rank whose part holds
 * it. The streams travel in one MPI_Neighbor_alltoallv over the neighbourhood graph, or, when a
 * particle went farther than a neighbour (the first distribution, a decomposition replaced), in
 * one MPI_Alltoallv over the domain's communicator. The arrivals are imported from the ranks in
 * ascending order, each rank's leavers in their index order, as the thread transport of the
 * tests does, so that the two give the same particle order.
 *
 * Inside a staggered stepper's fixed-point attempt the stepper refuses removals and imports
 * (SINTER_ERR_STATE): the leavers then stay where they are, the exchange carries nothing from
 * this rank, and the stepper redistributes again at its next accepted state.
 *
 * Three agreements (one MPI_Allreduce of an int each) keep the ranks together: a rank that
 * fails locally (memory, an export) says so before the next exchange, and every rank returns
 * -1 at the same point, so none waits for a message that will not come.
 */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/attach.h"
#include "mpi/domain.h"

/* The leavers, their destinations and their streams, one per destination rank. */
typedef struct outbox {
    size_t owned, leaving;
    size_t *list;          /* leavers grouped by destination rank, each group in index order */
    int *dest;             /* per owned particle: its rank */
    size_t *bytes;         /* per rank: bytes of its stream */
    unsigned char *stream; /* the streams, rank after rank */
    size_t total;          /* bytes */
} outbox;

static void free_outbox(outbox *o)
{
    free(o->list);
    free(o->dest);
    free(o->bytes);
    free(o->stream);
}

/* Who leaves for where, and their streams (without removing them); 0 or -1. *far receives 1
 * when a leaver goes to a rank that is not a neighbour. */
static int pack(sinter_mpi_attachment *a, outbox *o, int *far)
{
    const sinter_mpi_domain *d = a->d;
    *far = 0;
    if (sinter_particles_owned_count(a->ps, &o->owned) != SINTER_OK)
        return -1;
    const size_t n = o->owned;
    o->list = malloc((n + 1) * sizeof(size_t));
    o->dest = malloc((n + 1) * sizeof(int));
    o->bytes = calloc((size_t)d->size, sizeof(size_t));
    if (o->list == NULL || o->dest == NULL || o->bytes == NULL)
        return -1;
    const double *x = NULL;
    if (n > 0) {
        if (sinter_particles_view_read(a->ps, SINTER_FIELD_POSITION, (const void **)&x, NULL,
                                       NULL) != SINTER_OK)
            return -1;
        const sinter_status s = sinter_mpi_decomp_owners(d->decomp, x, n, o->dest);
        sinter_particles_release(a->ps, SINTER_FIELD_POSITION);
        if (s != SINTER_OK)
            return -1;
    }
    /* group by destination (a counting pass per rank keeps each group in index order) */
    size_t *first = calloc((size_t)d->size + 1, sizeof(size_t));
    if (first == NULL)
        return -1;
    for (size_t i = 0; i < n; ++i)
        if (o->dest[i] != d->rank)
            first[o->dest[i] + 1]++;
    for (int r = 0; r < d->size; ++r)
        first[r + 1] += first[r];
    o->leaving = first[d->size];
    for (size_t i = 0; i < n; ++i)
        if (o->dest[i] != d->rank)
            o->list[first[o->dest[i]]++] = i;
    for (int r = d->size; r > 0; --r) /* (first[r] now holds the end of group r) */
        first[r] = first[r - 1];
    first[0] = 0;
    int bad = 0;
    /* Inside the staggered stepper's fixed-point attempt no particle may leave (a removal of
     * none says so, and has the stepper migrate at its next accepted state): they stay, and
     * only ghosts are made (sinter_domain.h). */
    if (o->leaving > 0) {
        const sinter_status s = sinter_stepper_remove(a->st, 0, o->list);
        if (s == SINTER_ERR_STATE) {
            o->leaving = 0;
            for (int r = 0; r <= d->size; ++r)
                first[r] = 0;
        }
        bad |= s != SINTER_OK && s != SINTER_ERR_STATE;
    }
    for (int r = 0; r < d->size && !bad; ++r) {
        const size_t m = first[r + 1] - first[r];
        if (m == 0)
            continue;
        int neighbour = 0;
        for (int k = 0; k < a->nbr_count; ++k)
            neighbour |= a->nbr[k] == r;
        *far |= !neighbour;
        bad |= sinter_stepper_export_size(a->st, m, o->list + first[r], &o->bytes[r]) != SINTER_OK;
        bad |= o->bytes[r] > INT_MAX;
        o->total += bad ? 0 : o->bytes[r];
    }
    bad |= o->total > INT_MAX;
    o->stream = bad ? NULL : malloc(o->total + 1);
    bad |= o->stream == NULL;
    size_t at = 0;
    for (int r = 0; r < d->size && !bad; ++r) {
        const size_t m = first[r + 1] - first[r];
        size_t written = 0;
        if (m == 0)
            continue;
        bad |= sinter_stepper_export(a->st, m, o->list + first[r], o->stream + at, o->bytes[r],
                                     &written, 0) != SINTER_OK;
        at += o->bytes[r];
    }
    free(first);
    return bad ? -1 : 0;
}

/* Take the leavers out of the set (their streams are written: a removal without records). */
static int remove_leavers(sinter_mpi_attachment *a, const outbox *o)
{
    if (o->leaving == 0)
        return 0;
    return sinter_stepper_remove(a->st, o->leaving, o->list) != SINTER_OK ? -1 : 0;
}

int sinter_mpi_migrate(sinter_mpi_attachment *a, int everywhere)
{
    sinter_mpi_domain *d = a->d;
    outbox o;
    memset(&o, 0, sizeof o);
    int far = 0;
    /* the counts of the exchange, allocated before the ranks agree to go on */
    int *c = calloc(4 * (size_t)d->size + 4, sizeof(int));
    const int packed = c == NULL ? -1 : pack(a, &o, &far);
    /* 2: a rank failed; 1: a leaver goes beyond the neighbours */
    const int agreed = sinter_mpi_agree(a, packed != 0 ? 2 : far || everywhere ? 1 : 0);
    if (agreed == 2) {
        free(c);
        free_outbox(&o);
        return -1;
    }
    everywhere = agreed == 1 || a->graph == MPI_COMM_NULL;
    const int peers = everywhere ? d->size : a->nbr_count;
    /* send counts, send displacements, receive counts, receive displacements */
    int *sc = c, *sd = c + peers + 1, *rc = c + 2 * peers + 2, *rd = c + 3 * peers + 3;
    int bad = 0;
    size_t at = 0; /* the streams lie in rank order; a neighbour's starts where its rank's does */
    for (int r = 0, k = 0; r < d->size; ++r) {
        const int is_peer = everywhere ? 1 : (k < peers && a->nbr[k] == r);
        if (is_peer) {
            sc[k] = (int)o.bytes[r];
            sd[k] = (int)at;
            ++k;
        }
        at += o.bytes[r]; /* (at most o.total, below INT_MAX: checked in pack) */
    }
    double t0 = MPI_Wtime();
    int mpi = everywhere ? MPI_Alltoall(sc, 1, MPI_INT, rc, 1, MPI_INT, d->comm)
                         : MPI_Neighbor_alltoall(sc, 1, MPI_INT, rc, 1, MPI_INT, a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    bad |= mpi != MPI_SUCCESS;
    size_t in = 0;
    for (int k = 0; k < peers && !bad; ++k) {
        rd[k] = (int)in;
        in += (size_t)rc[k];
        bad |= in > INT_MAX;
    }
    unsigned char *inbox = bad ? NULL : malloc(in + 1);
    bad |= inbox == NULL;
    bad |= !bad && remove_leavers(a, &o) != 0;
    if (sinter_mpi_agree(a, bad)) {
        free(inbox);
        free(c);
        free_outbox(&o);
        return -1;
    }
    t0 = MPI_Wtime();
    mpi = everywhere ? MPI_Alltoallv(o.stream, sc, sd, MPI_BYTE, inbox, rc, rd, MPI_BYTE, d->comm)
                     : MPI_Neighbor_alltoallv(o.stream, sc, sd, MPI_BYTE, inbox, rc, rd, MPI_BYTE,
                                              a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    bad = mpi != MPI_SUCCESS;
    for (int k = 0; k < peers; ++k) {
        a->stats.messages_sent += sc[k] > 0;
        a->stats.bytes_sent += (uint64_t)sc[k] + (uint64_t)sizeof(int);
        a->stats.bytes_received += (uint64_t)rc[k] + (uint64_t)sizeof(int);
    }
    a->stats.global_migrations += (uint64_t)everywhere;
    a->stats.migrated_out += o.leaving;
    for (int k = 0; k < peers && !bad; ++k) { /* the arrivals, from the ranks in order */
        size_t count = 0;
        if (rc[k] > 0)
            bad |= sinter_stepper_import(a->st, inbox + rd[k], (size_t)rc[k], &count) != SINTER_OK;
        a->stats.migrated_in += count;
    }
    free(inbox);
    free(c);
    free_outbox(&o);
    return sinter_mpi_agree(a, bad) ? -1 : 0;
}
