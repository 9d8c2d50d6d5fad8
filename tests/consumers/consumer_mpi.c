/* A consumer of the installed libsinter_mpi (issue 44), built by CI with
 * `pkg-config --cflags --libs libsinter-mpi` and with CMake's find_package(libsinter COMPONENTS
 * mpi): the exact sum of 1 + 2 + ... over the ranks, and an RCB of one point per rank. */
#include <stdio.h>

#include <sinter_mpi.h>

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    sinter_mpi_options o;
    sinter_mpi_domain *d = NULL;
    int rc = 1;
    if (sinter_mpi_options_init(&o, sizeof o) == SINTER_OK &&
        sinter_mpi_domain_create(&d, MPI_COMM_WORLD, &o) == SINTER_OK) {
        int rank = 0, size = 0;
        sinter_mpi_domain_rank(d, &rank, &size);
        double value = rank + 1.0;
        const double point[3] = {(rank + 0.5) / size, 0.5, 0.5};
        int changed = 0;
        if (sinter_mpi_reduce(&value, 1, SINTER_MPI_F64, SINTER_MPI_SUM, d) == 0 &&
            value == size * (size + 1) / 2.0 &&
            sinter_mpi_balance(d, point, NULL, 1, NULL, &changed) == SINTER_OK) {
            if (rank == 0)
                printf("libsinter_mpi consumer on %d ranks: sum %.0f, %s\n", size, value,
                       changed ? "rebalanced" : "balanced");
            rc = 0;
        }
    }
    sinter_mpi_domain_destroy(d);
    MPI_Finalize();
    return rc;
}
