/* Subcommands of the sinter command line kept outside sinter.c. */
#ifndef SINTER_CLI_H
#define SINTER_CLI_H

/* --log: print the library's messages to stderr, one a line, after the level's name. */
void cli_print_log(int level, const char *message, void *user);

/* sinter pair FILE... [-o DIR] [--quiet] (pair.c). */
int cli_pair(int argc, char **argv);

#ifdef SINTER_CLI_MPI
/* The MPI build: 1 when started by mpiexec (run_mpi.c). */
int cli_mpi_launched(void);
/* sinter run on the ranks of MPI_COMM_WORLD (run_mpi.c): MPI_Init to MPI_Finalize. */
int cli_run_mpi(int argc, char **argv);
#endif

#endif
