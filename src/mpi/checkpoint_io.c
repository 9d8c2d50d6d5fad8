/*
 * Portable checkpoints through MPI-IO (libsinter_mpi, issue 44): one file written by every rank
 * at once and read back by any number of ranks. Only libsinter's public API is used: the
 * stepper's global part (sinter_stepper_save_global) and the record streams of its particles
 * (sinter_stepper_export), which restart a stepper set up alike from records in any order and
 * any number of pieces.
 *
 * File (host byte order, checked by a marker; u64 fields unaligned):
 *   header:  "SINTMPCK", u32 version, u32 marker 0x01020304, u64 pieces R (the writers),
 *            u64 header bytes H = 72 + 32 R, u64 global part's offset (= H), its bytes G and
 *            its FNV-1a checksum, u64 file bytes;
 *            per piece: u64 offset, bytes, particles, FNV-1a checksum;
 *            u64 FNV-1a checksum of the header's bytes before it;
 *   the global part (rank 0's), then piece 0 (rank 0's record stream), piece 1, ... piece R-1,
 *   each at the exclusive prefix sum of the sizes before it.
 * Rank 0 writes the header, the global part and its piece as one block; every rank writes its
 * piece with MPI_File_write_at_all.
 *
 * Reading on N ranks: rank 0 reads and checks the header and the global part and broadcasts
 * them; the pieces are dealt to the readers in contiguous runs of about T/N bytes (T the pieces'
 * total; a piece is read whole, by the reader whose share holds its middle byte) and read with
 * MPI_File_read_at_all; each reader checks its pieces' checksums. Only when every rank found its
 * bytes sound does any rank change its stepper: it loads the global part, imports its pieces,
 * and sends each particle to the rank whose part of the decomposition holds its centre
 * (send_to_owners.c). A failure anywhere after that takes every particle out again and puts the
 * stepper's own global part back, on every rank.
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/fnv1a.h"
#include "mpi/agree.h"
#include "mpi/send_to_owners.h"
#include "sinter_mpi.h"

#define CKPT_VERSION 1u
#define CKPT_FIXED 64              /* the header before the piece table */
#define CKPT_PIECE 32              /* one piece's entry */
#define IO_CHUNK ((size_t)1 << 30) /* bytes per collective call (its count is an int) */
static const char MAGIC[8] = {'S', 'I', 'N', 'T', 'M', 'P', 'C', 'K'};

static size_t header_bytes(uint64_t pieces)
{
    return CKPT_FIXED + CKPT_PIECE * (size_t)pieces + 8;
}

static void put_u64(unsigned char *at, uint64_t v)
{
    memcpy(at, &v, 8);
}

static uint64_t get_u64(const unsigned char *at)
{
    uint64_t v;
    memcpy(&v, at, 8);
    return v;
}

/* A duplicate of comm whose errors are returned (the caller's is not touched). */
static int dup_comm(MPI_Comm comm, MPI_Comm *out)
{
    if (MPI_Comm_dup(comm, out) != MPI_SUCCESS)
        return SINTER_ERR_IO;
    MPI_Comm_set_errhandler(*out, MPI_ERRORS_RETURN);
    return SINTER_OK;
}

/* Collective read or write of `bytes` at `offset` in `rounds` calls of at most IO_CHUNK bytes
 * (every rank makes the same number of calls; a rank with nothing left passes 0 bytes). */
static int io_all(MPI_File fh, uint64_t offset, unsigned char *buf, size_t bytes, size_t rounds,
                  int write)
{
    int s = SINTER_OK;
    unsigned char none = 0;
    for (size_t k = 0; k < rounds; ++k) {
        const size_t at = k * IO_CHUNK;
        const size_t n = at < bytes ? (bytes - at < IO_CHUNK ? bytes - at : IO_CHUNK) : 0;
        unsigned char *p = n > 0 ? buf + at : &none;
        MPI_Status status;
        const int rc =
            write
                ? MPI_File_write_at_all(fh, (MPI_Offset)(offset + at), p, (int)n, MPI_BYTE, &status)
                : MPI_File_read_at_all(fh, (MPI_Offset)(offset + at), p, (int)n, MPI_BYTE, &status);
        int got = 0;
        if (rc != MPI_SUCCESS)
            s = SINTER_ERR_IO;
        else if (MPI_Get_count(&status, MPI_BYTE, &got) != MPI_SUCCESS || (size_t)got != n)
            s = write ? SINTER_ERR_IO : SINTER_ERR_CORRUPT; /* a short read: truncated */
    }
    return s;
}

static size_t rounds_of(size_t bytes)
{
    return (bytes + IO_CHUNK - 1) / IO_CHUNK;
}

sinter_status sinter_mpi_checkpoint_write(sinter_stepper *stepper, sinter_particles *particles,
                                          MPI_Comm comm_in, const char *path)
{
    if (comm_in == MPI_COMM_NULL || path == NULL)
        return SINTER_ERR_NULL;
    MPI_Comm comm;
    if (dup_comm(comm_in, &comm) != SINTER_OK)
        return SINTER_ERR_IO;
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    int s = stepper == NULL || particles == NULL ? SINTER_ERR_NULL : SINTER_OK;
    size_t owned = 0, global = 0, piece = 0;
    if (s == SINTER_OK)
        s = sinter_particles_owned_count(particles, &owned);
    size_t *idx = s == SINTER_OK ? malloc((owned + 1) * sizeof(size_t)) : NULL;
    if (s == SINTER_OK && idx == NULL)
        s = SINTER_ERR_NOMEM;
    for (size_t i = 0; s == SINTER_OK && i < owned; ++i)
        idx[i] = i;
    if (s == SINTER_OK && rank == 0)
        s = sinter_stepper_save_global(stepper, NULL, 0, &global);
    if (s == SINTER_OK)
        s = sinter_stepper_export_size(stepper, owned, idx, &piece);
    /* rank 0's block: header, global part, its piece */
    const size_t head = rank == 0 ? header_bytes((uint64_t)size) : 0, lead = head + global;
    unsigned char *buf = s == SINTER_OK ? calloc(lead + piece + 1, 1) : NULL;
    uint64_t *table = rank == 0 ? malloc(4 * (size_t)size * sizeof(uint64_t)) : NULL;
    if (s == SINTER_OK && (buf == NULL || (rank == 0 && table == NULL)))
        s = SINTER_ERR_NOMEM;
    size_t written = 0;
    if (s == SINTER_OK && rank == 0)
        s = sinter_stepper_save_global(stepper, buf + head, global, &global);
    if (s == SINTER_OK)
        s = sinter_stepper_export(stepper, owned, idx, buf + lead, piece, &written, 0);
    free(idx);
    s = sinter_mpi_agree(comm, s);
    /* where each piece goes: the exclusive prefix sum of the blocks before it */
    uint64_t block = lead + piece, before = 0;
    if (s == SINTER_OK &&
        MPI_Exscan(&block, &before, 1, MPI_UINT64_T, MPI_SUM, comm) != MPI_SUCCESS)
        s = SINTER_ERR_IO;
    if (rank == 0)
        before = 0; /* MPI_Exscan leaves rank 0's undefined */
    const uint64_t entry[4] = {
        before + lead, piece, owned,
        sinter_fnv1a(SINTER_FNV1A_START, buf != NULL ? buf + lead : NULL, buf != NULL ? piece : 0)};
    if (s == SINTER_OK &&
        MPI_Gather(entry, 4, MPI_UINT64_T, table, 4, MPI_UINT64_T, 0, comm) != MPI_SUCCESS)
        s = SINTER_ERR_IO;
    if (s == SINTER_OK && rank == 0) {
        memcpy(buf, MAGIC, 8);
        const uint32_t version = CKPT_VERSION, marker = 0x01020304u;
        memcpy(buf + 8, &version, 4);
        memcpy(buf + 12, &marker, 4);
        put_u64(buf + 16, (uint64_t)size);
        put_u64(buf + 24, head);
        put_u64(buf + 32, head);
        put_u64(buf + 40, global);
        put_u64(buf + 48, sinter_fnv1a(SINTER_FNV1A_START, buf + head, global));
        put_u64(buf + 56, table[4 * (size - 1)] + table[4 * (size - 1) + 1]);
        for (size_t k = 0; k < 4 * (size_t)size; ++k)
            put_u64(buf + CKPT_FIXED + 8 * k, table[k]);
        put_u64(buf + head - 8, sinter_fnv1a(SINTER_FNV1A_START, buf, head - 8));
    }
    free(table);
    s = sinter_mpi_agree(comm, s);
    MPI_File fh = MPI_FILE_NULL;
    if (s == SINTER_OK) {
        const int rc =
            MPI_File_open(comm, path, MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
        s = sinter_mpi_agree(comm, rc == MPI_SUCCESS ? SINTER_OK : SINTER_ERR_IO);
        if (s != SINTER_OK && fh != MPI_FILE_NULL)
            MPI_File_close(&fh);
    }
    if (s == SINTER_OK) {
        /* a longer file of the same name loses its tail */
        if (MPI_File_set_size(fh, 0) != MPI_SUCCESS)
            s = SINTER_ERR_IO;
        uint64_t rounds = rounds_of(lead + piece);
        if (MPI_Allreduce(MPI_IN_PLACE, &rounds, 1, MPI_UINT64_T, MPI_MAX, comm) != MPI_SUCCESS)
            s = SINTER_ERR_IO;
        else if (io_all(fh, before, buf, lead + piece, (size_t)rounds, 1) != SINTER_OK)
            s = SINTER_ERR_IO;
        if (MPI_File_close(&fh) != MPI_SUCCESS)
            s = SINTER_ERR_IO;
        s = sinter_mpi_agree(comm, s);
    }
    free(buf);
    MPI_Comm_free(&comm);
    return s;
}

/* ---- reading ---- */

/* Rank 0: read and check the header and the global part into *out (*bytes). */
static int read_header(MPI_File fh, unsigned char **out, size_t *bytes)
{
    *out = NULL;
    *bytes = 0;
    MPI_Offset file = 0;
    if (MPI_File_get_size(fh, &file) != MPI_SUCCESS)
        return SINTER_ERR_IO;
    unsigned char fixed[CKPT_FIXED];
    MPI_Status status;
    int got = 0;
    if (file < CKPT_FIXED)
        return SINTER_ERR_CORRUPT;
    if (MPI_File_read_at(fh, 0, fixed, CKPT_FIXED, MPI_BYTE, &status) != MPI_SUCCESS ||
        MPI_Get_count(&status, MPI_BYTE, &got) != MPI_SUCCESS || got != CKPT_FIXED)
        return SINTER_ERR_IO;
    uint32_t version = 0, marker = 0;
    memcpy(&version, fixed + 8, 4);
    memcpy(&marker, fixed + 12, 4);
    const uint64_t size = (uint64_t)file, pieces = get_u64(fixed + 16);
    if (memcmp(fixed, MAGIC, 8) != 0 || version != CKPT_VERSION || marker != 0x01020304u ||
        pieces < 1 || pieces > (size - CKPT_FIXED) / CKPT_PIECE)
        return SINTER_ERR_CORRUPT;
    const uint64_t head = header_bytes(pieces), global = get_u64(fixed + 40);
    if (get_u64(fixed + 24) != head || get_u64(fixed + 32) != head || head > size ||
        global > size - head || head + global > INT_MAX || get_u64(fixed + 56) != size)
        return SINTER_ERR_CORRUPT;
    unsigned char *buf = malloc(head + global);
    if (buf == NULL)
        return SINTER_ERR_NOMEM;
    if (MPI_File_read_at(fh, 0, buf, (int)(head + global), MPI_BYTE, &status) != MPI_SUCCESS ||
        MPI_Get_count(&status, MPI_BYTE, &got) != MPI_SUCCESS || (uint64_t)got != head + global) {
        free(buf);
        return SINTER_ERR_IO;
    }
    int s = SINTER_OK;
    if (get_u64(buf + head - 8) != sinter_fnv1a(SINTER_FNV1A_START, buf, head - 8) ||
        get_u64(buf + 48) != sinter_fnv1a(SINTER_FNV1A_START, buf + head, global))
        s = SINTER_ERR_CORRUPT;
    /* the pieces follow one another to the end of the file */
    uint64_t at = head + global;
    for (uint64_t p = 0; p < pieces && s == SINTER_OK; ++p) {
        const unsigned char *e = buf + CKPT_FIXED + CKPT_PIECE * p;
        if (get_u64(e) != at || get_u64(e + 8) > size - at)
            s = SINTER_ERR_CORRUPT;
        at += get_u64(e + 8);
    }
    if (s == SINTER_OK && at != size)
        s = SINTER_ERR_CORRUPT;
    if (s != SINTER_OK) {
        free(buf);
        return s;
    }
    *out = buf;
    *bytes = head + global;
    return SINTER_OK;
}

/* The reader of each piece: contiguous runs of pieces, about the same bytes per reader. */
static void deal(const unsigned char *head, uint64_t pieces, int readers, int *reader)
{
    const unsigned char *t = head + CKPT_FIXED;
    const uint64_t first = get_u64(t), end = get_u64(t + CKPT_PIECE * (pieces - 1)) +
                                             get_u64(t + CKPT_PIECE * (pieces - 1) + 8);
    const double total = (double)(end - first);
    for (uint64_t p = 0; p < pieces; ++p) {
        const double middle = (double)(get_u64(t + CKPT_PIECE * p) - first) +
                              0.5 * (double)get_u64(t + CKPT_PIECE * p + 8);
        const double r = total > 0.0 ? floor(middle / total * readers) : 0.0;
        reader[p] = r < readers - 1 ? (int)r : readers - 1;
    }
}

/* Every owned particle out (with its histories and links) and the stepper's own global part
 * back: the state before a failed read. */
static void undo(sinter_stepper *st, sinter_particles *ps, const unsigned char *backup,
                 size_t backup_bytes)
{
    size_t n = 0, bytes = 0, written = 0;
    if (sinter_particles_owned_count(ps, &n) == SINTER_OK && n > 0) {
        size_t *idx = malloc(n * sizeof(size_t));
        for (size_t i = 0; idx != NULL && i < n; ++i)
            idx[i] = i;
        unsigned char *scratch = NULL;
        if (idx != NULL && sinter_stepper_export_size(st, n, idx, &bytes) == SINTER_OK &&
            (scratch = malloc(bytes)) != NULL)
            sinter_stepper_export(st, n, idx, scratch, bytes, &written, 1);
        free(scratch);
        free(idx);
    }
    sinter_stepper_load_global(st, backup, backup_bytes);
}

sinter_status sinter_mpi_checkpoint_read(sinter_stepper *stepper, sinter_particles *particles,
                                         MPI_Comm comm_in, const char *path,
                                         const sinter_mpi_decomp *decomp, size_t *count)
{
    if (comm_in == MPI_COMM_NULL || path == NULL)
        return SINTER_ERR_NULL;
    MPI_Comm comm;
    if (dup_comm(comm_in, &comm) != SINTER_OK)
        return SINTER_ERR_IO;
    int rank = 0, size = 0, parts = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    int s = stepper == NULL || particles == NULL || decomp == NULL ? SINTER_ERR_NULL : SINTER_OK;
    if (s == SINTER_OK)
        s = sinter_mpi_decomp_info(decomp, NULL, &parts);
    if (s == SINTER_OK && parts != size)
        s = SINTER_ERR_INVALID;
    size_t held = 0, backup_bytes = 0;
    if (s == SINTER_OK)
        s = sinter_particles_count(particles, &held);
    if (s == SINTER_OK && held > 0)
        s = SINTER_ERR_STATE;
    /* the stepper's own global part, put back if the read fails after it changed anything */
    unsigned char *backup = NULL;
    if (s == SINTER_OK)
        s = sinter_stepper_save_global(stepper, NULL, 0, &backup_bytes);
    if (s == SINTER_OK && (backup = malloc(backup_bytes)) == NULL)
        s = SINTER_ERR_NOMEM;
    if (s == SINTER_OK)
        s = sinter_stepper_save_global(stepper, backup, backup_bytes, &backup_bytes);
    s = sinter_mpi_agree(comm, s);
    MPI_File fh = MPI_FILE_NULL;
    if (s == SINTER_OK) {
        const int rc = MPI_File_open(comm, path, MPI_MODE_RDONLY, MPI_INFO_NULL, &fh);
        s = sinter_mpi_agree(comm, rc == MPI_SUCCESS ? SINTER_OK : SINTER_ERR_IO);
        if (s != SINTER_OK && fh != MPI_FILE_NULL)
            MPI_File_close(&fh);
    }
    /* the header and the global part: read and checked by rank 0, broadcast */
    unsigned char *head = NULL;
    size_t head_bytes = 0;
    if (s == SINTER_OK) {
        int64_t told[2] = {SINTER_OK, 0};
        if (rank == 0) {
            told[0] = read_header(fh, &head, &head_bytes);
            told[1] = (int64_t)head_bytes;
        }
        if (MPI_Bcast(told, 2, MPI_INT64_T, 0, comm) != MPI_SUCCESS)
            told[0] = SINTER_ERR_IO;
        s = (int)told[0];
        head_bytes = (size_t)told[1];
        if (s == SINTER_OK && rank != 0 && (head = malloc(head_bytes)) == NULL)
            s = SINTER_ERR_NOMEM;
        s = sinter_mpi_agree(comm, s);
        if (s == SINTER_OK && MPI_Bcast(head, (int)head_bytes, MPI_BYTE, 0, comm) != MPI_SUCCESS)
            s = SINTER_ERR_IO;
        s = sinter_mpi_agree(comm, s);
    }
    /* this rank's run of pieces, read collectively and checked */
    const uint64_t pieces = s == SINTER_OK ? get_u64(head + 16) : 0;
    int *reader = s == SINTER_OK ? malloc(pieces * sizeof(int)) : NULL;
    unsigned char *mine = NULL;
    uint64_t from = 0, to = 0, first = 0, last = 0; /* bytes [from, to), pieces [first, last) */
    if (s == SINTER_OK) {
        const unsigned char *t = head + CKPT_FIXED;
        if (reader == NULL)
            s = SINTER_ERR_NOMEM;
        else
            deal(head, pieces, size, reader);
        size_t rounds = 0, bytes = 0;
        for (uint64_t p = 0; p < pieces && s == SINTER_OK; ++p) {
            if (reader[p] < rank)
                first = p + 1;
            if (reader[p] <= rank)
                last = p + 1;
        }
        for (int r = 0; r < size && s == SINTER_OK; ++r) { /* every reader's calls */
            uint64_t a = UINT64_MAX, b = 0;
            for (uint64_t p = 0; p < pieces; ++p)
                if (reader[p] == r) {
                    a = a < get_u64(t + CKPT_PIECE * p) ? a : get_u64(t + CKPT_PIECE * p);
                    b = get_u64(t + CKPT_PIECE * p) + get_u64(t + CKPT_PIECE * p + 8);
                }
            const size_t n = b > a ? (size_t)(b - a) : 0;
            rounds = rounds_of(n) > rounds ? rounds_of(n) : rounds;
            if (r == rank) {
                from = a == UINT64_MAX ? 0 : a;
                to = a == UINT64_MAX ? 0 : b;
                bytes = n;
            }
        }
        if (s == SINTER_OK && (mine = malloc(bytes + 1)) == NULL)
            s = SINTER_ERR_NOMEM;
        s = sinter_mpi_agree(comm, s);
        if (s == SINTER_OK)
            s = io_all(fh, from, mine, (size_t)(to - from), rounds, 0);
        for (uint64_t p = first; p < last && s == SINTER_OK; ++p) {
            const unsigned char *e = t + CKPT_PIECE * p;
            if (get_u64(e + 24) !=
                sinter_fnv1a(SINTER_FNV1A_START, mine + (get_u64(e) - from), get_u64(e + 8)))
                s = SINTER_ERR_CORRUPT;
        }
        s = sinter_mpi_agree(comm, s);
    }
    if (fh != MPI_FILE_NULL) { /* open on every rank: closed collectively */
        if (MPI_File_close(&fh) != MPI_SUCCESS && s == SINTER_OK)
            s = SINTER_ERR_IO;
        s = sinter_mpi_agree(comm, s);
    }
    /* every rank's bytes are sound: the stepper changes from here on */
    int changed = 0;
    if (s == SINTER_OK) {
        changed = 1;
        const size_t global_at = header_bytes(pieces);
        s = sinter_stepper_load_global(stepper, head + global_at, get_u64(head + 40));
        for (uint64_t p = first; p < last && s == SINTER_OK; ++p) {
            const unsigned char *e = head + CKPT_FIXED + CKPT_PIECE * p;
            size_t got = 0;
            s = sinter_stepper_import(stepper, mine + (get_u64(e) - from), get_u64(e + 8), &got);
            if (s == SINTER_OK && got != get_u64(e + 16))
                s = SINTER_ERR_CORRUPT;
        }
        s = sinter_mpi_agree(comm, s);
    }
    free(mine);
    if (s == SINTER_OK)
        s = sinter_mpi_send_to_owners(stepper, particles, comm, decomp);
    if (s != SINTER_OK && changed)
        undo(stepper, particles, backup, backup_bytes);
    if (s == SINTER_OK && count != NULL)
        s = sinter_particles_owned_count(particles, count);
    free(reader);
    free(head);
    free(backup);
    MPI_Comm_free(&comm);
    return s;
}
