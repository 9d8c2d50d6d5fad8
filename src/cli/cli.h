/* Subcommands of the sinter command line kept outside sinter.c. */
#ifndef SINTER_CLI_H
#define SINTER_CLI_H

/* --log: print the library's messages to stderr, one a line, after the level's name. */
void cli_print_log(int level, const char *message, void *user);

/* sinter pair FILE... [-o DIR] [--quiet] (pair.c). */
int cli_pair(int argc, char **argv);

#endif
