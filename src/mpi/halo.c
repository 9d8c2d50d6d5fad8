/*
 * Ghosts and their exchange (libsinter_mpi, issue 44). At a redistribution every rank sends to
 * each neighbour its owned particles within the ghost cut-off of the bounding box of that
 * neighbour's owned particles (one MPI_Neighbor_alltoallv of fixed records), and takes what it
 * receives as its ghosts, in ascending rank order, each rank's in its index order. Between two
 * redistributions the ghost list is fixed, so a halo is one MPI_Neighbor_alltoallv of rows:
 * forward, the owners' rows into the ghost rows (received in place); reverse, the ghost rows back
 * to their owners, added there in ascending rank order (the order of the thread transport of the
 * tests), then zeroed.
 */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpi/attach.h"
#include "mpi/domain.h"

/* The squared distance from point x to a box. */
static double point_gap2(const double x[3], const double lo[3], const double hi[3])
{
    double s = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double g = lo[a] - x[a] > 0.0   ? lo[a] - x[a]
                         : x[a] - hi[a] > 0.0 ? x[a] - hi[a]
                                              : 0.0;
        s += g * g;
    }
    return s;
}

/* The owned fields a ghost record carries (views held while packing). */
typedef struct fields {
    const uint64_t *id;
    const double *x, *v, *w, *rot, *r, *m, *inertia, *temp;
    const int32_t *material;
    const uint32_t *flags;
} fields;

static const sinter_field FIELD_LIST[11] = {
    SINTER_FIELD_ID,          SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,
    SINTER_FIELD_ROTATION,    SINTER_FIELD_RADIUS,   SINTER_FIELD_MASS,     SINTER_FIELD_INERTIA,
    SINTER_FIELD_TEMPERATURE, SINTER_FIELD_MATERIAL, SINTER_FIELD_FLAGS};

static int view_fields(const sinter_particles *ps, fields *f, int *held)
{
    const void **slot[11] = {
        (const void **)&f->id,       (const void **)&f->x,       (const void **)&f->v,
        (const void **)&f->w,        (const void **)&f->rot,     (const void **)&f->r,
        (const void **)&f->m,        (const void **)&f->inertia, (const void **)&f->temp,
        (const void **)&f->material, (const void **)&f->flags};
    for (*held = 0; *held < 11; ++*held)
        if (sinter_particles_view_read(ps, FIELD_LIST[*held], slot[*held], NULL, NULL) != SINTER_OK)
            return -1;
    return 0;
}

static void release_fields(const sinter_particles *ps, int held)
{
    for (int k = 0; k < held; ++k)
        sinter_particles_release(ps, FIELD_LIST[k]);
}

/* Ghost record of owned particle i. */
static void pack_record(const fields *f, size_t i, unsigned char *out)
{
    memcpy(out, f->id + i, 8);
    memcpy(out + 8, f->x + 3 * i, 24);
    memcpy(out + 32, f->v + 3 * i, 24);
    memcpy(out + 56, f->w + 3 * i, 24);
    memcpy(out + 80, f->rot + 3 * i, 24);
    memcpy(out + 104, f->r + i, 8);
    memcpy(out + 112, f->m + i, 8);
    memcpy(out + 120, f->inertia + i, 8);
    memcpy(out + 128, f->temp + i, 8);
    memcpy(out + 136, f->material + i, 4);
    memcpy(out + 140, f->flags + i, 4);
}

/* The received records as the arrays of sinter_ghost_fields (one allocation). */
static int unpack(const unsigned char *in, size_t n, const sinter_mpi_attachment *a, void **block,
                  sinter_ghost_fields *g)
{
    unsigned char *b = malloc(n * (8 + 16 * 8 + 4 + 4 + 4) + 8);
    *block = b;
    if (b == NULL)
        return -1;
    uint64_t *id = (uint64_t *)b;
    double *x = (double *)(b + 8 * n), *v = x + 3 * n, *w = v + 3 * n, *rot = w + 3 * n,
           *r = rot + 3 * n, *m = r + n, *inertia = m + n, *temp = inertia + n;
    int32_t *material = (int32_t *)(temp + n), *owner = material + n;
    uint32_t *flags = (uint32_t *)(owner + n);
    for (size_t i = 0; i < n; ++i) {
        const unsigned char *p = in + SINTER_MPI_GHOST_RECORD * i;
        memcpy(id + i, p, 8);
        memcpy(x + 3 * i, p + 8, 24);
        memcpy(v + 3 * i, p + 32, 24);
        memcpy(w + 3 * i, p + 56, 24);
        memcpy(rot + 3 * i, p + 80, 24);
        memcpy(r + i, p + 104, 8);
        memcpy(m + i, p + 112, 8);
        memcpy(inertia + i, p + 120, 8);
        memcpy(temp + i, p + 128, 8);
        memcpy(material + i, p + 136, 4);
        memcpy(flags + i, p + 140, 4);
    }
    for (int k = 0, i = 0; k < a->nbr_count; ++k)
        for (int j = 0; j < a->recv_count[k]; ++j)
            owner[i++] = a->nbr[k];
    *g = (sinter_ghost_fields){.struct_size = sizeof(sinter_ghost_fields),
                               .count = n,
                               .id = id,
                               .position = x,
                               .velocity = v,
                               .spin = w,
                               .rotation = rot,
                               .radius = r,
                               .mass = m,
                               .inertia = inertia,
                               .temperature = temp,
                               .material = material,
                               .flags = flags,
                               .owner = owner};
    return 0;
}

/* Choose the owned rows each neighbour receives and pack their records; 0 or -1. */
static int select_ghosts(sinter_mpi_attachment *a, double cutoff, unsigned char **records,
                         size_t *sent)
{
    size_t n = 0;
    *records = NULL;
    *sent = 0;
    if (sinter_particles_owned_count(a->ps, &n) != SINTER_OK)
        return -1;
    fields f;
    int held = 0, bad = n > 0 && view_fields(a->ps, &f, &held) != 0;
    size_t count = 0;
    for (int k = 0; k < a->nbr_count && !bad; ++k) {
        const double *lo = a->nbr_box + 6 * k, *hi = lo + 3;
        size_t mine = 0;
        for (size_t i = 0; i < n && !bad; ++i) {
            if (point_gap2(f.x + 3 * i, lo, hi) > cutoff * cutoff)
                continue;
            if (count + 1 > a->send_capacity) {
                const size_t c = 2 * count + 64;
                size_t *g = realloc(a->send_index, c * sizeof(size_t));
                bad = g == NULL;
                a->send_index = g != NULL ? g : a->send_index;
                a->send_capacity = g != NULL ? c : a->send_capacity;
                if (bad)
                    break;
            }
            a->send_index[count++] = i;
            ++mine;
        }
        bad |= mine > INT_MAX / SINTER_MPI_GHOST_RECORD;
        a->send_count[k] = (int)mine;
    }
    *records = bad ? NULL : malloc(count * SINTER_MPI_GHOST_RECORD + 1);
    bad |= *records == NULL;
    for (size_t j = 0; j < count && !bad; ++j)
        pack_record(&f, a->send_index[j], *records + SINTER_MPI_GHOST_RECORD * j);
    release_fields(a->ps, held);
    *sent = count;
    return bad ? -1 : 0;
}

/* The neighbours' bounding boxes of their owned particles (an empty one: lo > hi), so that
 * a rank sends only the particles within the cut-off of another's particles, not of its
 * whole part: fewer ghosts, and the ghosts the thread transport of the tests takes. */
static int exchange_boxes(sinter_mpi_attachment *a)
{
    double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    size_t n = 0;
    const double *x = NULL;
    int bad = sinter_particles_owned_count(a->ps, &n) != SINTER_OK;
    bad |= !bad && n > 0 &&
           sinter_particles_view_read(a->ps, SINTER_FIELD_POSITION, (const void **)&x, NULL,
                                      NULL) != SINTER_OK;
    for (size_t i = 0; i < n && x != NULL; ++i)
        for (int c = 0; c < 3; ++c) {
            box[c] = fmin(box[c], x[3 * i + c]);
            box[3 + c] = fmax(box[3 + c], x[3 * i + c]);
        }
    if (x != NULL)
        sinter_particles_release(a->ps, SINTER_FIELD_POSITION);
    const double t0 = MPI_Wtime();
    const int mpi = MPI_Neighbor_allgather(box, 6, MPI_DOUBLE, a->nbr_box, 6, MPI_DOUBLE, a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    a->stats.messages_sent += (uint64_t)a->nbr_count;
    a->stats.bytes_sent += (uint64_t)a->nbr_count * sizeof box;
    a->stats.bytes_received += (uint64_t)a->nbr_count * sizeof box;
    return bad || mpi != MPI_SUCCESS ? -1 : 0;
}

int sinter_mpi_make_ghosts(sinter_mpi_attachment *a, double cutoff)
{
    unsigned char *records = NULL, *inbox = NULL;
    size_t sent = 0, in = 0;
    int bad = exchange_boxes(a);
    bad |= !bad && select_ghosts(a, cutoff, &records, &sent);
    const int nn = a->nbr_count;
    int *sc = a->counts[0], *sd = a->counts[1], *rc = a->counts[2], *rd = a->counts[3];
    double t0 = MPI_Wtime();
    /* the counts travel whatever happened (a failed rank sends zeros), then it is agreed */
    for (int k = 0; k < nn; ++k)
        sc[k] = bad ? 0 : a->send_count[k];
    int mpi = MPI_Neighbor_alltoall(sc, 1, MPI_INT, a->recv_count, 1, MPI_INT, a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    bad |= mpi != MPI_SUCCESS;
    size_t at = 0;
    for (int k = 0; k < nn && !bad; ++k) {
        sc[k] = a->send_count[k] * SINTER_MPI_GHOST_RECORD;
        sd[k] = (int)at;
        at += (size_t)sc[k];
        rc[k] = a->recv_count[k] * SINTER_MPI_GHOST_RECORD;
        rd[k] = (int)(in * SINTER_MPI_GHOST_RECORD);
        in += (size_t)a->recv_count[k];
        bad |= at > INT_MAX || in * SINTER_MPI_GHOST_RECORD > INT_MAX;
    }
    inbox = bad ? NULL : malloc(in * SINTER_MPI_GHOST_RECORD + 1);
    bad |= inbox == NULL;
    if (sinter_mpi_agree(a, bad)) {
        free(records);
        free(inbox);
        a->ghosts = 0;
        return -1;
    }
    t0 = MPI_Wtime();
    mpi = MPI_Neighbor_alltoallv(records, sc, sd, MPI_BYTE, inbox, rc, rd, MPI_BYTE, a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    for (int k = 0; k < nn; ++k) {
        a->stats.messages_sent += (sc[k] > 0) + 1; /* (the count, then the records) */
        a->stats.bytes_sent += (uint64_t)sc[k] + sizeof(int);
        a->stats.bytes_received += (uint64_t)rc[k] + sizeof(int);
    }
    free(records);
    void *block = NULL;
    sinter_ghost_fields g;
    bad = mpi != MPI_SUCCESS || unpack(inbox, in, a, &block, &g) != 0 ||
          sinter_particles_set_ghosts(a->ps, &g) != SINTER_OK;
    free(block);
    free(inbox);
    a->ghosts = bad ? 0 : in;
    a->stats.ghosts = a->ghosts;
    (void)sent;
    return bad ? -1 : 0;
}

int sinter_mpi_halo(const sinter_halo *h, void *user)
{
    sinter_mpi_attachment *a = user;
    if (a == NULL || a->d == NULL || h == NULL)
        return -1;
    if (a->graph == MPI_COMM_NULL) /* before the first redistribution: no ghosts anywhere */
        return h->ghosts == 0 ? 0 : -1;
    if (h->ghosts != a->ghosts)
        return -1; /* (not reached through the library: its ghosts are the last redistribution's) */
    const size_t w = h->width;
    size_t sent = 0;
    for (int k = 0; k < a->nbr_count; ++k)
        sent += (size_t)a->send_count[k];
    if (sent * w > INT_MAX || h->ghosts * w > INT_MAX)
        return -1;
    if (sent * w > a->buffer_capacity) {
        double *g = realloc(a->buffer, sent * w * sizeof(double));
        if (g == NULL)
            return -1;
        a->buffer = g;
        a->buffer_capacity = sent * w;
    }
    const int forward = h->direction == SINTER_HALO_FORWARD;
    /* mine: the rows of my owned particles my neighbours hold; theirs: my ghost rows */
    int *mc = a->counts[0], *md = a->counts[1], *tc = a->counts[2], *td = a->counts[3];
    size_t at = 0, gt = 0;
    for (int k = 0; k < a->nbr_count; ++k) {
        mc[k] = (int)((size_t)a->send_count[k] * w);
        md[k] = (int)at;
        at += (size_t)mc[k];
        tc[k] = (int)((size_t)a->recv_count[k] * w);
        td[k] = (int)gt;
        gt += (size_t)tc[k];
    }
    double *ghost_rows = h->data + h->owned * w;
    if (forward)
        for (size_t j = 0; j < sent; ++j)
            memcpy(a->buffer + j * w, h->data + a->send_index[j] * w, w * sizeof(double));
    const double t0 = MPI_Wtime();
    const int mpi = forward ? MPI_Neighbor_alltoallv(a->buffer, mc, md, MPI_DOUBLE, ghost_rows, tc,
                                                     td, MPI_DOUBLE, a->graph)
                            : MPI_Neighbor_alltoallv(ghost_rows, tc, td, MPI_DOUBLE, a->buffer, mc,
                                                     md, MPI_DOUBLE, a->graph);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    a->stats.halos++;
    for (int k = 0; k < a->nbr_count; ++k) {
        const int out = forward ? mc[k] : tc[k], back = forward ? tc[k] : mc[k];
        a->stats.messages_sent += out > 0;
        a->stats.bytes_sent += (uint64_t)out * sizeof(double);
        a->stats.bytes_received += (uint64_t)back * sizeof(double);
    }
    if (mpi != MPI_SUCCESS)
        return -1;
    if (!forward) { /* added in ascending rank order, then the ghost rows zeroed */
        for (size_t j = 0; j < sent; ++j)
            for (size_t c = 0; c < w; ++c)
                h->data[a->send_index[j] * w + c] += a->buffer[j * w + c];
        if (h->ghosts > 0)
            memset(ghost_rows, 0, h->ghosts * w * sizeof(double));
    }
    return 0;
}
