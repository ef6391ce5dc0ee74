/* `firmament sun`: the sun's position and the day's sunrise, solar noon and sunset for a date, time
 * and place, as text or JSON.  Exit 0, or 2 with one line naming the problem. */
#ifndef FM_CLI_SUN_COMMAND_H
#define FM_CLI_SUN_COMMAND_H

#include <stdio.h>

/* argv[0] is "sun". */
int run_sun(int argc, char **argv);
/* The part of `firmament sun --help` after its usage line (usage.c): what it prints, the options. */
void sun_print_help(FILE *f);

#endif
