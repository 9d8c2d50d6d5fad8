/*
 * A domain installed as a stepper's collective operations (libsinter_mpi, issue 44): the
 * callback table of sinter_domain.h over MPI. reduce and exscan are the domain's (reduce.c);
 * redistribute is a visible pipeline of its own: balance (optional), the neighbourhood graph
 * (neighbours.c), migration (migrate.c), ghosts (halo.c); halo is halo.c's.
 */
#include <stdlib.h>
#include <string.h>

#include "mpi/attach.h"
#include "mpi/domain.h"

int sinter_mpi_agree(sinter_mpi_attachment *a, int flag)
{
    int all = 1;
    const double t0 = MPI_Wtime();
    const int rc = MPI_Allreduce(&flag, &all, 1, MPI_INT, MPI_MAX, a->d->comm);
    a->d->stats.seconds_comm += MPI_Wtime() - t0;
    a->d->stats.reductions++;
    a->d->stats.reduce_bytes += sizeof(int);
    return rc == MPI_SUCCESS ? all : 1;
}

static int att_reduce(void *values, size_t count, int type, int op, void *user)
{
    const sinter_mpi_attachment *a = user;
    return a->d != NULL ? sinter_mpi_reduce(values, count, type, op, a->d) : -1;
}

static int att_exscan(uint64_t value, uint64_t *before, uint64_t *total, void *user)
{
    const sinter_mpi_attachment *a = user;
    return a->d != NULL ? sinter_mpi_exscan(value, before, total, a->d) : -1;
}

/* With SINTER_MPI_ATTACH_BALANCE: bisect anew above the threshold (one load per particle). */
static int balance(sinter_mpi_attachment *a, int *changed)
{
    size_t n = 0;
    const double *x = NULL;
    *changed = 0;
    int bad = sinter_particles_owned_count(a->ps, &n) != SINTER_OK;
    bad |= !bad && n > 0 &&
           sinter_particles_view_read(a->ps, SINTER_FIELD_POSITION, (const void **)&x, NULL,
                                      NULL) != SINTER_OK;
    static const double none[3] = {0.0, 0.0, 0.0};
    /* (a rank that failed still takes part, with no points, and then says so) */
    const sinter_status s =
        sinter_mpi_balance(a->d, bad || n == 0 ? none : x, NULL, bad ? 0 : n, NULL, changed);
    if (x != NULL)
        sinter_particles_release(a->ps, SINTER_FIELD_POSITION);
    return sinter_mpi_agree(a, bad || s != SINTER_OK) ? -1 : 0;
}

/* The owned counts' largest over their mean (a statistic: one MPI_Allgather). */
static void measure_imbalance(sinter_mpi_attachment *a)
{
    sinter_mpi_domain *d = a->d;
    size_t n = 0;
    sinter_particles_owned_count(a->ps, &n);
    a->stats.owned = n;
    uint64_t *all = malloc((size_t)d->size * sizeof(uint64_t)), mine = n;
    const double t0 = MPI_Wtime();
    /* (a rank without memory sends its count all the same; its statistic stays unmeasured) */
    uint64_t scratch[1];
    const int rc = MPI_Allgather(&mine, 1, MPI_UINT64_T, all != NULL ? all : scratch,
                                 all != NULL ? 1 : 0, MPI_UINT64_T, d->comm);
    a->stats.seconds_comm += MPI_Wtime() - t0;
    if (rc == MPI_SUCCESS && all != NULL) {
        uint64_t top = 0, sum = 0;
        for (int r = 0; r < d->size; ++r) {
            top = all[r] > top ? all[r] : top;
            sum += all[r];
        }
        a->stats.imbalance = sum > 0 ? (double)top * d->size / (double)sum : 1.0;
    }
    free(all);
}

static int att_redistribute(sinter_stepper *st, void *user)
{
    sinter_mpi_attachment *a = user;
    if (a->d == NULL || st != a->st)
        return -1;
    a->stats.redistributions++;
    double cutoff = 0.0; /* the same on every rank (a reduced r_max) */
    if (sinter_stepper_ghost_cutoff(st, &cutoff) != SINTER_OK)
        return -1;
    int changed = 0;
    /* (a domain created as a bisection balances whatever the flags: its first bisection) */
    const int balancing = (a->flags & SINTER_MPI_ATTACH_BALANCE) ||
                          a->d->options.decomposition == SINTER_MPI_DECOMP_RCB;
    if (balancing && balance(a, &changed) != 0)
        return -1;
    if (sinter_mpi_neighbours(a, cutoff) != SINTER_OK)
        return -1;
    if (sinter_mpi_migrate(a, changed) != 0)
        return -1;
    /* (a failure of set_ghosts is this rank's alone: the statistic's collective comes first,
     * the status is then agreed by the stepper) */
    const int ghosts = sinter_mpi_make_ghosts(a, cutoff);
    measure_imbalance(a);
    return ghosts;
}

static void free_attachment(sinter_mpi_attachment *a)
{
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (a->graph != MPI_COMM_NULL && !finalized)
        MPI_Comm_free(&a->graph);
    free(a->nbr);
    free(a->nbr_box);
    free(a->send_index);
    free(a->send_count);
    free(a->recv_count);
    free(a->buffer);
    for (int k = 0; k < 4; ++k)
        free(a->counts[k]);
    free(a);
}

static void att_destroy(void *user)
{
    sinter_mpi_attachment *a = user;
    if (a->d != NULL && a->d->attached == a)
        a->d->attached = NULL;
    free_attachment(a);
}

sinter_status sinter_mpi_attach(sinter_mpi_domain *d, sinter_stepper *stepper,
                                sinter_particles *particles, int flags)
{
    if (d == NULL || stepper == NULL || particles == NULL)
        return SINTER_ERR_NULL;
    if ((flags & ~SINTER_MPI_ATTACH_BALANCE) != 0)
        return SINTER_ERR_INVALID;
    if (d->attached != NULL)
        return SINTER_ERR_STATE;
    sinter_mpi_attachment *a = calloc(1, sizeof *a);
    sinter_status s = a != NULL ? SINTER_OK : SINTER_ERR_NOMEM;
    if (a != NULL) {
        a->d = d;
        a->st = stepper;
        a->ps = particles;
        a->flags = flags;
        a->graph = MPI_COMM_NULL;
        a->stats.struct_size = sizeof a->stats;
        a->stats.imbalance = 1.0;
        const sinter_domain_ops ops = {.struct_size = sizeof(sinter_domain_ops),
                                       .reduce = att_reduce,
                                       .exscan = att_exscan,
                                       .halo = sinter_mpi_halo,
                                       .redistribute = att_redistribute,
                                       .destroy_user = att_destroy};
        a->ops = ops;
        d->attached = a; /* (before: a table it replaces may detach nothing of ours) */
        s = sinter_stepper_set_domain_ops(stepper, &ops, a);
        if (s != SINTER_OK) {
            d->attached = NULL;
            free_attachment(a);
        }
    }
    /* every rank learns of a failure anywhere (then the ops are removed again here) */
    int all = 0, bad = s != SINTER_OK;
    if (MPI_Allreduce(&bad, &all, 1, MPI_INT, MPI_MAX, d->comm) != MPI_SUCCESS)
        all = 1;
    if (all && s == SINTER_OK) {
        sinter_stepper_set_domain_ops(stepper, NULL, NULL); /* (calls att_destroy) */
        s = SINTER_ERR_IO;
    }
    return s;
}

sinter_status sinter_mpi_distribute(sinter_mpi_domain *d)
{
    if (d == NULL)
        return SINTER_ERR_NULL;
    if (d->attached == NULL)
        return SINTER_ERR_STATE;
    return sinter_mpi_migrate(d->attached, 1) == 0 ? SINTER_OK : SINTER_ERR_CALLBACK;
}

sinter_status sinter_mpi_get_exchange_stats(const sinter_mpi_domain *d,
                                            sinter_mpi_exchange_stats *stats)
{
    if (d == NULL || stats == NULL)
        return SINTER_ERR_NULL;
    if (stats->struct_size != sizeof *stats)
        return SINTER_ERR_STRUCT_SIZE;
    if (d->attached == NULL)
        return SINTER_ERR_STATE;
    *stats = d->attached->stats;
    return SINTER_OK;
}
