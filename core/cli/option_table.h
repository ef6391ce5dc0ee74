/* The options of `firmament render`, one row each: the flag, where its value goes, its kind, its
 * range and unit, its default and its help.  getopt's long options, the usage text, the checks of
 * each value, the sky presets' keys and `firmament options --json` are all made from this table.
 * Numeric ranges are the library's (fm_param_range_of(field)) except for the few values the
 * library never sees (--exposure, --seed, --step), whose range is the row's own. */
#ifndef FM_CLI_OPTION_TABLE_H
#define FM_CLI_OPTION_TABLE_H

#include "args.h"

#include <stddef.h>
#include <stdio.h>

typedef enum option_kind {
    OPTION_NUMBER, /* a decimal, into a double */
    OPTION_WHOLE,  /* a whole number, into an int */
    OPTION_SEED,   /* a whole number, into a uint64_t */
    OPTION_CHOICE, /* one of the row's words, into an int (an enum) */
    OPTION_TEXT,   /* a name or a path, kept as given (a const char *) */
    OPTION_SWITCH, /* no value: sets an int to the row's set_to */
    OPTION_DATE,   /* YYYY-MM-DD, into sky.year, month, day */
    OPTION_TIME,   /* HH:MM[:SS] of the local day (args.c keeps the seconds) */
    OPTION_OFFSET, /* +-HH[:MM], into an int of minutes */
    OPTION_RATIO,  /* W:H or a positive number, into a double */
} option_kind;

/* What an option needs or affects besides its value (checked after all are read). */
enum {
    NEEDS_BUILTIN = 1 << 0,   /* about the built-in atmosphere: refused with --atmosphere */
    NEEDS_FISHEYE = 1 << 1,   /* refused unless --camera fisheye */
    NEEDS_PINHOLE = 1 << 2,   /* refused unless --camera pinhole */
    NEEDS_TIME = 1 << 3,      /* the solar position's inputs: refused without --time or --time-start */
    FROM_TIME = 1 << 4,       /* computed from --time unless given */
    FILE_ARG = 1 << 5,        /* a path written by the render: '--width' there is a forgotten path */
    NOT_PARSED = 1 << 6,      /* handled before parsing (--preset) or by main (--help) */
    BIOME_WORDS = 1 << 7,     /* its words are the biomes' names (presets/biomes/) */
    CLOUD_WORDS = 1 << 8,     /* its words are the cloud layers' names (presets/clouds/) */
};

typedef struct option_word {
    const char *word;
    int value;
} option_word;

typedef struct option_spec {
    const char *flag;          /* "sun-elevation" (a sky preset's key is this with '_' for '-') */
    char short_flag;           /* 'o', or 0 */
    const char *metavar;       /* "DEG"; NULL for a switch */
    option_kind kind;
    size_t offset;             /* of the value in struct options */
    const char *field;         /* the library's name of the value (its range and errors), or NULL */
    fm_param_range own_range;  /* the range of a number the library does not see (field NULL) */
    const option_word *words;  /* OPTION_CHOICE: the words, ended by {NULL, 0} */
    int set_to;                /* OPTION_SWITCH: the value it sets */
    int flags;                 /* NEEDS_..., FROM_TIME, ... */
    const char *group;         /* its heading in the usage */
    const char *help;          /* "%R" stands for the range, "%W" for the words "a | b | c" */
    const char *default_text;  /* the default when the value alone does not say it, or NULL */
} option_spec;

extern const option_spec option_specs[];
extern const int option_count;

/* The row of "--flag" / "flag", or NULL. */
const option_spec *option_find(const char *flag);
/* The row whose value the library calls field ("sun_elevation_deg"), or NULL. */
const option_spec *option_for_field(const char *field);
/* Its numeric range: the library's for its field, else its own; NULL for a value without one. */
const fm_param_range *option_range(const option_spec *o);
/* "[-90, 90] degrees" */
void option_format_range(const fm_param_range *r, char *out, size_t size);

/* The part of `firmament render --help` after the usage lines (usage.c): what it makes, and every
 * option from the table. */
void option_print_help(FILE *f);
/* `firmament options --json`: every option with its flag, preset key, kind, range, unit, default,
 * words and help. */
void option_print_json(FILE *f);

#endif
