/* The commands of the executable and their usage, one row each: `firmament --help`, every
 * `firmament COMMAND --help` and the usage lines of the errors are all made from this table. */
#ifndef FM_CLI_USAGE_H
#define FM_CLI_USAGE_H

#include <stdio.h>

typedef struct command_usage {
    const char *name;            /* "sun", "batch plan" */
    const char *synopsis;        /* what follows "firmament NAME" on its usage line; NULL for a
                                    command of subcommands (their names, "plan|run|...") */
    const char *about;           /* a few words beside it in `firmament --help`, or NULL */
    const char *text;            /* the rest of its --help (what it does, its options), or NULL */
    void (*print_more)(FILE *f); /* the part of its --help made from another table, or NULL */
} command_usage;

extern const command_usage commands[];
extern const int command_count;

/* The row of `firmament NAME [SUB]` ("batch" and "plan": "batch plan"), or NULL for an unknown
 * NAME. */
const command_usage *command_find(const char *name, const char *sub);
/* Whether one of the arguments after the command asks for its help (--help or -h). */
int command_help_asked(int argc, char **argv);
/* `firmament NAME --help` on f. */
void command_print_help(FILE *f, const command_usage *c);
/* "usage: firmament NAME SYNOPSIS" on one line, for an error (a static buffer). */
const char *command_usage_line(const char *name);

#endif
