/*
 * An MPI host with its own decomposition (issue 44): libsinter driven through the domain
 * callbacks of sinter_domain.h with plain MPI calls, not through libsinter_mpi.
 *
 * The decomposition is the host's: slabs along y (rank r owns the particles whose centre lies
 * in the r-th of `size` equal slabs of [Y0, Y1); outside, the nearest slab), where
 * libsinter_mpi uses bricks or a recursive bisection. Its exchanges:
 *  - redistribute: migration (sinter_stepper_export of every leaver into one buffer ordered by
 *    destination, then one removal, MPI_Alltoallv of the record streams, sinter_stepper_import
 *    of each source's stream in ascending rank order); then ghosts: the ranks trade the y
 *    extents of their owned particles (MPI_Allgather) and every rank sends to every other the
 *    owned particles within sinter_stepper_ghost_cutoff of that extent (MPI_Alltoallv of fixed
 *    records); ghosts in ascending rank order, each rank's in its index order.
 *  - halo: the same send lists, rows packed and traded by MPI_Alltoallv; reverse rows added
 *    into their owners in ascending rank order, then zeroed.
 *  - reduce: integers and min/max by MPI_Allreduce (exact); sums of doubles by MPI_Allgather
 *    and a sum in rank order on every rank, so that every rank holds the same bits whatever
 *    MPI's reduction algorithm (not the same bits as another decomposition's sum).
 *  - exscan: MPI_Exscan and MPI_Allreduce.
 * What it guarantees: with the stepper option "reproducible" the final state (positions,
 * velocities, spins, temperatures, by id) is the same bits for any number of ranks and equals
 * libsinter_mpi's run of the same bed, because that mode makes the state independent of the
 * decomposition by itself (pairs in id order, each particle's sums on one thread, the walls'
 * reactions exact through two integer reductions a step): no double the host sums enters the
 * state. The heat model's energy and the statistics go through the double sums and may differ
 * in the last bits between decompositions. Local failures in a callback are agreed by an
 * MPI_Allreduce before it returns, so every rank gets SINTER_ERR_CALLBACK together.
 *
 * The bed: 288 spheres of 1 mm on a jiggled lattice (Hertz-Mindlin with friction, damping and
 * rolling resistance, gravity, conduction, five walls; a small skin, so a rebuild every few
 * steps and migration across the slab borders, which lie on columns of the lattice).
 *
 * Usage: mpiexec -n N example_mpi_host [--check]
 * Runs the bed for 150 steps of 2 us on the host's slabs and prints, on rank 0, the
 * migrations, ghosts and the wall force. With --check it also runs the bed through
 * sinter_mpi_attach (x slabs of a brick, reproducible mode) and exits non-zero unless the
 * final states sorted by id are equal bit for bit, every particle is owned once, the host's
 * halo works both ways on the last ghosts and, on more than one rank, particles migrated and
 * ghosts existed.
 */
#include <math.h>
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinter.h>
#include <sinter_domain.h>
#include <sinter_mpi.h>

enum { NX = 8, NY = 6, NZ = 6, N = NX * NY * NZ, NW = 5, STEPS = 150, ROW = 13 };
static const double R = 1e-3, A = 1.97e-3; /* radius and lattice spacing [m]: 1.5 % overlap */
static const double LX = R + A * (NX - 1) + 0.99 * R, LY = R + A * (NY - 1) + 0.99 * R; /* [m] */
/* the host's slabs along y: borders on columns of the lattice for 1, 2, 3 and 6 ranks */
static const double Y0 = R - A, Y1 = R + 5 * A;
/* libsinter_mpi's brick along x (the reference run) */
static const double X0 = R - 2 * A, X1 = R + 10 * A;
static const double DT = 2e-6; /* [s] */

/* ---- the host's transport --------------------------------------------------------------- */

/* One ghost as traded: id, x v w rot (12), radius, mass, inertia, temperature, material, flags. */
typedef struct ghost_rec {
    uint64_t id;
    double d[16];
    int32_t material;
    uint32_t flags;
} ghost_rec;

typedef struct host {
    MPI_Comm comm;
    int rank, size;
    sinter_particles *ps;
    int *scount, *sdispl, *rcount, *rdispl; /* per rank (items or bytes, by use) */
    size_t *send_idx;                       /* owned rows sent as ghosts, grouped by rank */
    int *send_n, *recv_n;                   /* per rank: rows sent, ghosts received */
    size_t n_send, n_ghosts;
    uint64_t migrated, ghosts_max;
} host;

static int slab_of(const host *h, double y)
{
    const double r = floor((y - Y0) / (Y1 - Y0) * h->size);
    return r < 0.0 ? 0 : r >= h->size ? h->size - 1 : (int)r;
}

/* Every rank learns whether any failed (one MPI_Allreduce): the callbacks' common verdict. */
static int agree(const host *h, int bad)
{
    int any = 0;
    MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, h->comm);
    return any ? -1 : 0;
}

static int h_reduce(void *values, size_t count, int type, int op, void *user)
{
    host *h = user;
    if (type == SINTER_REDUCE_F64 && op == SINTER_REDUCE_SUM) {
        double *all = malloc(count * (size_t)h->size * sizeof(double) + 1);
        int bad = all == NULL;
        if (agree(h, bad)) {
            free(all);
            return -1;
        }
        MPI_Allgather(values, (int)count, MPI_DOUBLE, all, (int)count, MPI_DOUBLE, h->comm);
        for (size_t k = 0; k < count; ++k) { /* in rank order: the same bits on every rank */
            double s = 0.0;
            for (int r = 0; r < h->size; ++r)
                s += all[(size_t)r * count + k];
            ((double *)values)[k] = s;
        }
        free(all);
        return 0;
    }
    const MPI_Datatype t = type == SINTER_REDUCE_F64   ? MPI_DOUBLE
                           : type == SINTER_REDUCE_I64 ? MPI_INT64_T
                                                       : MPI_UINT64_T;
    const MPI_Op o = op == SINTER_REDUCE_SUM   ? MPI_SUM
                     : op == SINTER_REDUCE_MIN ? MPI_MIN
                                               : MPI_MAX;
    return MPI_Allreduce(MPI_IN_PLACE, values, (int)count, t, o, h->comm) == MPI_SUCCESS ? 0 : -1;
}

static int h_exscan(uint64_t value, uint64_t *before, uint64_t *total, void *user)
{
    host *h = user;
    uint64_t b = 0;
    MPI_Exscan(&value, &b, 1, MPI_UINT64_T, MPI_SUM, h->comm);
    *before = h->rank == 0 ? 0 : b; /* (undefined on rank 0) */
    MPI_Allreduce(&value, total, 1, MPI_UINT64_T, MPI_SUM, h->comm);
    return 0;
}

static void displs(const int *count, int *displ, int size)
{
    displ[0] = 0;
    for (int r = 1; r < size; ++r)
        displ[r] = displ[r - 1] + count[r - 1];
}

static int h_halo(const sinter_halo *hl, void *user)
{
    host *h = user;
    const size_t w = hl->width;
    int bad = hl->ghosts != h->n_ghosts;
    double *sbuf = malloc((h->n_send + h->n_ghosts) * w * sizeof(double) + 1);
    double *rbuf = malloc((h->n_send + h->n_ghosts) * w * sizeof(double) + 1);
    bad |= sbuf == NULL || rbuf == NULL;
    if (agree(h, bad)) {
        free(sbuf);
        free(rbuf);
        return -1;
    }
    const int fwd = hl->direction == SINTER_HALO_FORWARD;
    /* forward: my send rows go out, ghost rows come in; reverse: the other way round */
    for (int r = 0; r < h->size; ++r) {
        h->scount[r] = (fwd ? h->send_n[r] : h->recv_n[r]) * (int)w;
        h->rcount[r] = (fwd ? h->recv_n[r] : h->send_n[r]) * (int)w;
    }
    displs(h->scount, h->sdispl, h->size);
    displs(h->rcount, h->rdispl, h->size);
    if (fwd)
        for (size_t k = 0; k < h->n_send; ++k)
            memcpy(sbuf + k * w, hl->data + h->send_idx[k] * w, w * sizeof(double));
    else
        memcpy(sbuf, hl->data + hl->owned * w, h->n_ghosts * w * sizeof(double));
    MPI_Alltoallv(sbuf, h->scount, h->sdispl, MPI_DOUBLE, rbuf, h->rcount, h->rdispl, MPI_DOUBLE,
                  h->comm);
    if (fwd) {
        memcpy(hl->data + hl->owned * w, rbuf, h->n_ghosts * w * sizeof(double));
    } else { /* in ascending rank order (the send list is grouped by rank) */
        for (size_t k = 0; k < h->n_send; ++k)
            for (size_t c = 0; c < w; ++c)
                hl->data[h->send_idx[k] * w + c] += rbuf[k * w + c];
        memset(hl->data + hl->owned * w, 0, h->n_ghosts * w * sizeof(double));
    }
    free(sbuf);
    free(rbuf);
    return 0;
}

/* A read view of field f of the set (released by the caller when *held), or NULL. */
static const void *field(const sinter_particles *ps, sinter_field f, int *held)
{
    const void *a = NULL;
    *held = sinter_particles_view_read(ps, f, &a, NULL, NULL) == SINTER_OK;
    return a;
}

static const sinter_field FIELDS[] = {
    SINTER_FIELD_ID,          SINTER_FIELD_POSITION, SINTER_FIELD_VELOCITY, SINTER_FIELD_SPIN,
    SINTER_FIELD_ROTATION,    SINTER_FIELD_RADIUS,   SINTER_FIELD_MASS,     SINTER_FIELD_INERTIA,
    SINTER_FIELD_TEMPERATURE, SINTER_FIELD_MATERIAL, SINTER_FIELD_FLAGS};
enum { NF = sizeof(FIELDS) / sizeof(FIELDS[0]) };

/* Migration: every owned particle whose centre left this rank's slab goes to the slab's rank. */
static int migrate(host *h, sinter_stepper *st)
{
    size_t n = 0;
    int bad = sinter_particles_owned_count(h->ps, &n) != SINTER_OK;
    size_t *list = malloc((n + 1) * sizeof(size_t));
    int *dest = malloc((n + 1) * sizeof(int));
    unsigned char *sbuf = NULL, *rbuf = NULL;
    size_t leaving = 0, total = 0;
    bad |= list == NULL || dest == NULL;
    int held = 0;
    const double *x = bad ? NULL : field(h->ps, SINTER_FIELD_POSITION, &held);
    bad |= !held || (x == NULL && n > 0);
    for (size_t i = 0; i < n && !bad; ++i)
        dest[i] = slab_of(h, x[3 * i + 1]);
    if (held)
        sinter_particles_release(h->ps, SINTER_FIELD_POSITION);
    for (int r = 0; r < h->size; ++r)
        h->scount[r] = 0;
    /* every leaver exported (remove = 0) before the one removal, grouped by destination */
    for (int r = 0; r < h->size && !bad; ++r) {
        size_t m = 0, bytes = 0, written = 0;
        for (size_t i = 0; r != h->rank && i < n; ++i)
            if (dest[i] == r)
                list[leaving + m++] = i;
        if (m == 0)
            continue;
        bad |= sinter_stepper_export_size(st, m, list + leaving, &bytes) != SINTER_OK;
        unsigned char *g = bad ? NULL : realloc(sbuf, total + bytes);
        bad |= g == NULL;
        if (bad)
            break;
        sbuf = g;
        bad |= sinter_stepper_export(st, m, list + leaving, sbuf + total, bytes, &written, 0) !=
               SINTER_OK;
        h->scount[r] = (int)written;
        total += written;
        leaving += m;
    }
    if (!bad && leaving > 0) {
        size_t bytes = 0, written = 0;
        bad = sinter_stepper_export_size(st, leaving, list, &bytes) != SINTER_OK;
        void *scratch = bad ? NULL : malloc(bytes);
        bad = bad || scratch == NULL ||
              sinter_stepper_export(st, leaving, list, scratch, bytes, &written, 1) != SINTER_OK;
        free(scratch);
    }
    free(list);
    free(dest);
    if (agree(h, bad)) {
        free(sbuf);
        return -1;
    }
    h->migrated += leaving;
    MPI_Alltoall(h->scount, 1, MPI_INT, h->rcount, 1, MPI_INT, h->comm);
    displs(h->scount, h->sdispl, h->size);
    displs(h->rcount, h->rdispl, h->size);
    const size_t in = (size_t)h->rdispl[h->size - 1] + (size_t)h->rcount[h->size - 1];
    rbuf = malloc(in + 1);
    bad = rbuf == NULL;
    if (agree(h, bad)) {
        free(sbuf);
        return -1;
    }
    MPI_Alltoallv(sbuf, h->scount, h->sdispl, MPI_BYTE, rbuf, h->rcount, h->rdispl, MPI_BYTE,
                  h->comm);
    for (int r = 0; r < h->size && !bad; ++r) /* arrivals in ascending rank order */
        if (h->rcount[r] > 0)
            bad |= sinter_stepper_import(st, rbuf + h->rdispl[r], (size_t)h->rcount[r], NULL) !=
                   SINTER_OK;
    free(sbuf);
    free(rbuf);
    return agree(h, bad);
}

/* Ghosts: to every other rank, the owned particles within the cut-off of its y extent. */
static int make_ghosts(host *h, sinter_stepper *st)
{
    size_t n = 0;
    double cutoff = 0.0;
    int bad = sinter_particles_owned_count(h->ps, &n) != SINTER_OK ||
              sinter_stepper_ghost_cutoff(st, &cutoff) != SINTER_OK;
    const void *f[NF] = {NULL};
    int held[NF] = {0};
    for (int k = 0; k < NF && !bad; ++k) {
        f[k] = field(h->ps, FIELDS[k], &held[k]);
        bad |= !held[k] || (f[k] == NULL && n > 0);
    }
    const double *x = f[1];
    double ext[2] = {INFINITY, -INFINITY}; /* my owned particles' extent along y [m] */
    for (size_t i = 0; i < n && !bad; ++i) {
        ext[0] = fmin(ext[0], x[3 * i + 1]);
        ext[1] = fmax(ext[1], x[3 * i + 1]);
    }
    double *all = malloc(2 * (size_t)h->size * sizeof(double));
    size_t *idx = realloc(h->send_idx, ((size_t)h->size * n + 1) * sizeof(size_t));
    h->send_idx = idx != NULL ? idx : h->send_idx;
    bad |= all == NULL || idx == NULL;
    if (agree(h, bad))
        goto fail;
    MPI_Allgather(ext, 2, MPI_DOUBLE, all, 2, MPI_DOUBLE, h->comm);
    h->n_send = 0;
    for (int r = 0; r < h->size; ++r) {
        h->send_n[r] = 0;
        for (size_t i = 0; r != h->rank && i < n; ++i)
            if (x[3 * i + 1] >= all[2 * r] - cutoff && x[3 * i + 1] <= all[2 * r + 1] + cutoff) {
                h->send_idx[h->n_send++] = i;
                h->send_n[r]++;
            }
    }
    ghost_rec *srec = malloc((h->n_send + 1) * sizeof(ghost_rec));
    bad = srec == NULL;
    for (size_t k = 0; k < h->n_send && !bad; ++k) {
        const size_t i = h->send_idx[k];
        ghost_rec *g = &srec[k];
        memset(g, 0, sizeof(*g));
        g->id = ((const uint64_t *)f[0])[i];
        for (int c = 0; c < 3; ++c) {
            g->d[c] = x[3 * i + c];
            g->d[3 + c] = ((const double *)f[2])[3 * i + c];
            g->d[6 + c] = ((const double *)f[3])[3 * i + c];
            g->d[9 + c] = ((const double *)f[4])[3 * i + c];
        }
        for (int c = 0; c < 4; ++c)
            g->d[12 + c] = ((const double *)f[5 + c])[i];
        g->material = ((const int32_t *)f[9])[i];
        g->flags = ((const uint32_t *)f[10])[i];
    }
    for (int k = 0; k < NF; ++k)
        if (held[k])
            sinter_particles_release(h->ps, FIELDS[k]);
    memset(held, 0, sizeof(held));
    if (agree(h, bad)) {
        free(srec);
        goto fail;
    }
    MPI_Alltoall(h->send_n, 1, MPI_INT, h->recv_n, 1, MPI_INT, h->comm);
    h->n_ghosts = 0;
    for (int r = 0; r < h->size; ++r) {
        h->scount[r] = h->send_n[r] * (int)sizeof(ghost_rec);
        h->rcount[r] = h->recv_n[r] * (int)sizeof(ghost_rec);
        h->n_ghosts += (size_t)h->recv_n[r];
    }
    displs(h->scount, h->sdispl, h->size);
    displs(h->rcount, h->rdispl, h->size);
    const size_t g = h->n_ghosts;
    ghost_rec *rrec = malloc((g + 1) * sizeof(ghost_rec));
    double *d = malloc((16 * g + 1) * sizeof(double));
    uint64_t *id = malloc((g + 1) * sizeof(uint64_t));
    int32_t *mat = malloc((g + 1) * sizeof(int32_t)), *owner = malloc((g + 1) * sizeof(int32_t));
    uint32_t *flags = malloc((g + 1) * sizeof(uint32_t));
    bad = !rrec || !d || !id || !mat || !owner || !flags;
    if (!agree(h, bad)) {
        MPI_Alltoallv(srec, h->scount, h->sdispl, MPI_BYTE, rrec, h->rcount, h->rdispl, MPI_BYTE,
                      h->comm);
        /* struct of arrays: x v w rot as 3 per ghost, then the scalars, 1 per ghost */
        for (int r = 0, k = 0; r < h->size; ++r)
            for (int j = 0; j < h->recv_n[r]; ++j, ++k) {
                id[k] = rrec[k].id;
                for (int c = 0; c < 4; ++c)
                    memcpy(d + 3 * g * (size_t)c + 3 * (size_t)k, rrec[k].d + 3 * c, 24);
                for (int c = 0; c < 4; ++c)
                    d[12 * g + (size_t)c * g + (size_t)k] = rrec[k].d[12 + c];
                mat[k] = rrec[k].material;
                flags[k] = rrec[k].flags;
                owner[k] = r;
            }
        const sinter_ghost_fields gf = {.struct_size = sizeof(gf),
                                        .count = g,
                                        .id = id,
                                        .position = d,
                                        .velocity = d + 3 * g,
                                        .spin = d + 6 * g,
                                        .rotation = d + 9 * g,
                                        .radius = d + 12 * g,
                                        .mass = d + 13 * g,
                                        .inertia = d + 14 * g,
                                        .temperature = d + 15 * g,
                                        .material = mat,
                                        .flags = flags,
                                        .owner = owner};
        bad = sinter_particles_set_ghosts(h->ps, &gf) != SINTER_OK;
        bad = agree(h, bad) != 0;
    } else {
        bad = 1;
    }
    h->ghosts_max = g > h->ghosts_max ? g : h->ghosts_max;
    free(srec);
    free(rrec);
    free(d);
    free(id);
    free(mat);
    free(owner);
    free(flags);
    free(all);
    return bad ? -1 : 0;
fail:
    for (int k = 0; k < NF; ++k)
        if (held[k])
            sinter_particles_release(h->ps, FIELDS[k]);
    free(all);
    return -1;
}

static int h_redistribute(sinter_stepper *st, void *user)
{
    host *h = user;
    if (migrate(h, st) != 0)
        return -1;
    return make_ghosts(h, st);
}

static int host_init(host *h, MPI_Comm comm, sinter_particles *ps)
{
    memset(h, 0, sizeof(*h));
    h->comm = comm;
    h->ps = ps;
    MPI_Comm_rank(comm, &h->rank);
    MPI_Comm_size(comm, &h->size);
    const size_t s = (size_t)h->size;
    h->scount = calloc(s, sizeof(int));
    h->sdispl = calloc(s, sizeof(int));
    h->rcount = calloc(s, sizeof(int));
    h->rdispl = calloc(s, sizeof(int));
    h->send_n = calloc(s, sizeof(int));
    h->recv_n = calloc(s, sizeof(int));
    return h->scount && h->sdispl && h->rcount && h->rdispl && h->send_n && h->recv_n ? 0 : -1;
}

static void host_free(host *h)
{
    free(h->scount);
    free(h->sdispl);
    free(h->rcount);
    free(h->rdispl);
    free(h->send_n);
    free(h->recv_n);
    free(h->send_idx);
}

/* The halo in both directions on the last rebuild's ghosts (the explicit step uses the forward
 * one only): forward, a column holding each owned row's id must bring every ghost row its own
 * id; reverse, ghost rows of 1 must add to the owners, over all ranks, as many as there are
 * ghosts, and leave the ghost rows zero. Collective; returns the errors over all ranks. */
static int check_halo(host *h)
{
    size_t owned = 0, count = 0;
    int errors = 0, held = 0;
    if (sinter_particles_owned_count(h->ps, &owned) != SINTER_OK ||
        sinter_particles_count(h->ps, &count) != SINTER_OK)
        errors++;
    const uint64_t *id = errors ? NULL : field(h->ps, SINTER_FIELD_ID, &held);
    double *data = calloc(2 * count + 2, sizeof(double));
    errors += !held || data == NULL || (id == NULL && count > 0);
    if (agree(h, errors)) {
        if (held)
            sinter_particles_release(h->ps, SINTER_FIELD_ID);
        free(data);
        return 1;
    }
    for (size_t i = 0; i < owned; ++i)
        data[2 * i + 1] = (double)id[i];
    sinter_halo hl = {.struct_size = sizeof(hl),
                      .direction = SINTER_HALO_FORWARD,
                      .width = 2,
                      .data = data,
                      .id = id,
                      .owned = owned,
                      .ghosts = count - owned};
    errors += h_halo(&hl, h) != 0;
    for (size_t i = owned; i < count; ++i)
        errors += data[2 * i + 1] != (double)id[i];
    for (size_t i = 0; i < count; ++i)
        data[2 * i] = i < owned ? 0.0 : 1.0;
    hl.direction = SINTER_HALO_REVERSE;
    errors += h_halo(&hl, h) != 0;
    uint64_t sums[2] = {0, count - owned}; /* ghosts counted by their owners, and held */
    for (size_t i = 0; i < count; ++i)
        if (i < owned)
            sums[0] += (uint64_t)data[2 * i];
        else
            errors += data[2 * i] != 0.0;
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_UINT64_T, MPI_SUM, h->comm);
    errors += sums[0] != sums[1];
    sinter_particles_release(h->ps, SINTER_FIELD_ID);
    free(data);
    int all = 0;
    MPI_Allreduce(&errors, &all, 1, MPI_INT, MPI_SUM, h->comm);
    return all;
}

/* ---- the bed ---------------------------------------------------------------------------- */

static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static double BX[3 * N], BV[3 * N], BW[3 * N], BT[N];
static uint64_t BID[N];

static void make_bed(void)
{
    uint64_t seed = 43;
    for (int k = 0; k < N; ++k) {
        const int i = k % NX, j = (k / NX) % NY, l = k / (NX * NY);
        BX[3 * k] = R + A * i + 0.01 * R * (lcg(&seed) - 0.5);
        BX[3 * k + 1] = R + A * j + 0.01 * R * (lcg(&seed) - 0.5);
        BX[3 * k + 2] = 0.99 * R + A * l + 0.01 * R * (lcg(&seed) - 0.5);
        for (int d = 0; d < 3; ++d) {
            BV[3 * k + d] = 0.04 * (lcg(&seed) - 0.5);
            BW[3 * k + d] = 20.0 * (lcg(&seed) - 0.5);
        }
        BT[k] = 300.0 + 100.0 * lcg(&seed);
        BID[k] = 1 + (uint64_t)((k * 37) % N); /* ids in a permuted order */
    }
}

/* A run's result: its owned rows (id, then x v w rot temperature) and the walls' forces. */
typedef struct result {
    size_t n;
    double rows[N * (ROW + 1)];
    double wall[3 * NW];
    int ok;
    int halo_errors; /* check_halo's (the host's run) */
} result;

#define TRY(call)                                                                                  \
    do {                                                                                           \
        if ((call) != SINTER_OK) {                                                                 \
            fprintf(stderr, "line %d: %s\n", __LINE__, sinter_last_error(ctx));                    \
            goto done;                                                                             \
        }                                                                                          \
    } while (0)

/* The bed on this rank: with the host's slabs (d == NULL) or through libsinter_mpi (d). */
static void run_bed(MPI_Comm comm, sinter_mpi_domain *d, result *out, host *h)
{
    sinter_ctx *ctx = NULL;
    sinter_material *mat = NULL;
    sinter_particles *ps = NULL;
    sinter_walls *walls = NULL;
    sinter_stepper *st = NULL;
    sinter_force_model *gravity = NULL, *contact = NULL;
    sinter_heat_model *cond = NULL;
    const void *f[NF] = {NULL};
    int held[NF] = {0};
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    out->ok = 0;
    TRY(sinter_ctx_create(&ctx, NULL));
    TRY(sinter_ctx_set_threads(ctx, 1));
    TRY(sinter_material_create(&mat, ctx, "bed"));
    const struct {
        sinter_material_param p;
        double v;
    } props[] = {{SINTER_MAT_YOUNGS_MODULUS, 1e7},   {SINTER_MAT_POISSON_RATIO, 0.3},
                 {SINTER_MAT_DENSITY, 2500},         {SINTER_MAT_DAMPING_RATIO, 0.3},
                 {SINTER_MAT_FRICTION_STATIC, 0.5},  {SINTER_MAT_FRICTION_DYNAMIC, 0.5},
                 {SINTER_MAT_ROLLING_FRICTION, 0.1}, {SINTER_MAT_THERMAL_CONDUCTIVITY, 400},
                 {SINTER_MAT_HEAT_CAPACITY, 400}};
    for (size_t k = 0; k < sizeof(props) / sizeof(props[0]); ++k)
        TRY(sinter_material_set(mat, props[k].p, props[k].v));
    TRY(sinter_particles_create(&ps, ctx));
    TRY(sinter_particles_set_material(ps, 0, mat));
    TRY(sinter_walls_create(&walls, ctx));
    const double wp[NW][3] = {{0, 0, 0}, {0, 0, 0}, {LX, 0, 0}, {0, 0, 0}, {0, LY, 0}};
    const double wn[NW][3] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < NW; ++k)
        TRY(sinter_walls_add_plane(walls, wp[k], wn[k], mat, NULL));
    TRY(sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, walls));
    TRY(sinter_stepper_set_option(st, "reproducible", 1));
    TRY(sinter_force_model_create(&gravity, ctx, "gravity"));
    TRY(sinter_stepper_add_force(st, gravity));
    TRY(sinter_force_model_create(&contact, ctx, "hertz_mindlin"));
    TRY(sinter_stepper_add_force(st, contact));
    TRY(sinter_heat_model_create(&cond, ctx, "conduction"));
    TRY(sinter_stepper_add_heat(st, cond));
    if (d == NULL && host_init(h, comm, ps) != 0)
        goto done;
    const sinter_mpi_decomp *decomp = NULL;
    if (d != NULL)
        TRY(sinter_mpi_domain_decomp(d, &decomp));
    for (int k = 0; k < N; ++k) { /* every rank adds the particles of its own part */
        int part = 0;
        if (d != NULL)
            TRY(sinter_mpi_decomp_owners(decomp, BX + 3 * k, 1, &part));
        else
            part = slab_of(h, BX[3 * k + 1]);
        if (part != rank)
            continue;
        size_t first = 0;
        TRY(sinter_particles_add_with_ids(ps, 1, &BID[k], BX + 3 * k, &R, 0, BT[k], &first));
        double *v = NULL;
        TRY(sinter_particles_view(ps, SINTER_FIELD_VELOCITY, (void **)&v, NULL, NULL));
        memcpy(v + 3 * first, BV + 3 * k, 24);
        TRY(sinter_particles_release(ps, SINTER_FIELD_VELOCITY));
        TRY(sinter_particles_view(ps, SINTER_FIELD_SPIN, (void **)&v, NULL, NULL));
        memcpy(v + 3 * first, BW + 3 * k, 24);
        TRY(sinter_particles_release(ps, SINTER_FIELD_SPIN));
    }
    TRY(sinter_stepper_set_dt(st, DT));
    TRY(sinter_stepper_set_skin(st, 1e-5));
    if (d != NULL) {
        TRY(sinter_mpi_attach(d, st, ps, 0));
    } else {
        const sinter_domain_ops ops = {.struct_size = sizeof(ops),
                                       .reduce = h_reduce,
                                       .exscan = h_exscan,
                                       .halo = h_halo,
                                       .redistribute = h_redistribute,
                                       .destroy_user = NULL};
        TRY(sinter_stepper_set_domain_ops(st, &ops, h));
    }
    TRY(sinter_stepper_step(st, STEPS)); /* collective: the same status on every rank */
    if (d == NULL)
        out->halo_errors = check_halo(h);
    TRY(sinter_particles_owned_count(ps, &out->n));
    for (int k = 0; k < NF && out->n > 0; ++k)
        if ((f[k] = field(ps, FIELDS[k], &held[k])) == NULL)
            goto done;
    for (size_t i = 0; i < out->n; ++i) {
        double *row = out->rows + i * (ROW + 1);
        row[0] = (double)((const uint64_t *)f[0])[i]; /* ids < 2^53: exact */
        for (int c = 0; c < 4; ++c)
            memcpy(row + 1 + 3 * c, (const double *)f[1 + c] + 3 * i, 24);
        row[ROW] = ((const double *)f[8])[i];
    }
    for (int k = 0; k < NW; ++k)
        TRY(sinter_walls_get_force(walls, (size_t)k, out->wall + 3 * k));
    out->ok = 1;
done:
    for (int k = 0; k < NF; ++k)
        if (held[k])
            sinter_particles_release(ps, FIELDS[k]);
    if (st != NULL)
        sinter_stepper_set_domain_ops(st, NULL, NULL);
    sinter_stepper_destroy(st);
    sinter_force_model_destroy(gravity);
    sinter_force_model_destroy(contact);
    sinter_heat_model_destroy(cond);
    sinter_walls_destroy(walls);
    sinter_particles_destroy(ps);
    sinter_material_destroy(mat);
    sinter_ctx_destroy(ctx);
}

/* Rank 0 receives every rank's rows and files them by id - 1 into `state` (N rows of ROW);
 * seen[k] counts the owners of id k + 1. */
static void gather_by_id(MPI_Comm comm, const result *r, double *state, int *seen)
{
    int rank = 0, size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    const int mine = (int)(r->n * (ROW + 1));
    int *count = calloc((size_t)size, sizeof(int)), *displ = calloc((size_t)size, sizeof(int));
    MPI_Gather(&mine, 1, MPI_INT, count, 1, MPI_INT, 0, comm);
    if (rank == 0)
        displs(count, displ, size);
    const size_t total = rank == 0 ? (size_t)displ[size - 1] + (size_t)count[size - 1] : 0;
    double *all = malloc((total + 1) * sizeof(double));
    MPI_Gatherv(r->rows, mine, MPI_DOUBLE, all, count, displ, MPI_DOUBLE, 0, comm);
    memset(seen, 0, N * sizeof(int));
    for (size_t k = 0; rank == 0 && k < total; k += ROW + 1) {
        const size_t id = (size_t)all[k];
        if (id >= 1 && id <= N) {
            memcpy(state + (id - 1) * ROW, all + k + 1, ROW * sizeof(double));
            seen[id - 1]++;
        }
    }
    free(all);
    free(count);
    free(displ);
}

static result MINE, THEIRS;
static double S_HOST[N * ROW], S_MPI[N * ROW];
static int SEEN_HOST[N], SEEN_MPI[N];

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1, failures = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const int check = argc > 1 && strcmp(argv[1], "--check") == 0;
    make_bed();

    host h;
    run_bed(MPI_COMM_WORLD, NULL, &MINE, &h);
    uint64_t stats[2] = {h.migrated, h.ghosts_max}, sums[2] = {0, 0};
    MPI_Allreduce(stats, sums, 2, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    host_free(&h);
    gather_by_id(MPI_COMM_WORLD, &MINE, S_HOST, SEEN_HOST);
    int ok = MINE.ok, all_ok = 0;
    MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (rank == 0)
        printf("host (y slabs, %d ranks): %s; %llu migrations, up to %llu ghosts per rank summed; "
               "floor force %.9g N\n",
               size, all_ok ? "ran" : "FAILED", (unsigned long long)sums[0],
               (unsigned long long)sums[1], MINE.wall[2]);
    failures += !all_ok;

    if (check) {
        sinter_mpi_options o;
        sinter_mpi_options_init(&o, sizeof o);
        o.decomposition = SINTER_MPI_DECOMP_BRICK;
        const int grid[3] = {size, 1, 1};
        const double lo[3] = {X0, -A, -A}, hi[3] = {X1, LY + A, A * (NZ + 1)};
        memcpy(o.grid, grid, sizeof grid);
        memcpy(o.lo, lo, sizeof lo);
        memcpy(o.hi, hi, sizeof hi);
        sinter_mpi_domain *d = NULL;
        if (sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK) {
            run_bed(MPI_COMM_WORLD, d, &THEIRS, NULL);
            sinter_mpi_domain_destroy(d);
        }
        gather_by_id(MPI_COMM_WORLD, &THEIRS, S_MPI, SEEN_MPI);
        ok = THEIRS.ok;
        MPI_Allreduce(&ok, &all_ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        if (rank == 0) {
            int once = 1;
            for (int k = 0; k < N; ++k)
                once &= SEEN_HOST[k] == 1 && SEEN_MPI[k] == 1;
            const int same = memcmp(S_HOST, S_MPI, sizeof S_HOST) == 0;
            const int walls = memcmp(MINE.wall, THEIRS.wall, sizeof MINE.wall) == 0;
            const int moved = size == 1 || (sums[0] > 0 && sums[1] > 0);
            size_t differ = 0;
            for (size_t k = 0; k < N * ROW; ++k)
                differ += memcmp(S_HOST + k, S_MPI + k, sizeof(double)) != 0;
            printf("check against sinter_mpi_attach (x brick): %s; owned once %s, state %s "
                   "(%zu of %d doubles differ), wall forces %s, migrations and ghosts %s, "
                   "halo errors %d\n",
                   all_ok ? "ran" : "FAILED", once ? "yes" : "NO", same ? "same bits" : "DIFFER",
                   differ, N * ROW, walls ? "same bits" : "DIFFER", moved ? "yes" : "NO",
                   MINE.halo_errors);
            failures += !all_ok || !once || !same || !walls || !moved || MINE.halo_errors != 0;
        }
    }
    MPI_Bcast(&failures, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Finalize();
    return failures ? 1 : 0;
}
