/*
 * opttab.h — command-line options from tables, for every program (hzrt's commands, hzbake, hzbench, hzerrtime).
 * Each entry knows its option's name (and short alias), value kind and limits, its help line and, for hzrt's
 * commands, where it acts (optwhere.h). One parser checks a value against its entry, one loop reads a program's
 * command line from its table, and one printer writes the help text from the entries, limits included: the help
 * cannot drift from what is checked.
 *
 * Contract:
 *  - hz_opt_find() returns the entry named argv[i], by its name or its alias (NULL: not in the table).
 *  - hz_opt_value() checks the value (NULL for a flag) against the entry: an integer or number in [lo, hi] (lo
 *    excluded with lo_open), a size WxH with both sides in [lo, hi], one of the words, or any non-empty text; a
 *    bad value prints why, naming the option (and the command, when cmd is not NULL), and returns false.
 *  - hz_opt_parse() reads a program's whole command line (argv[1..argc)) from its table: an entry's value is
 *    the next argument; each checked option goes to take() in command-line order; an entry with id
 *    HZ_OPT_ID_HELP prints the help (hz_opt_help) to stdout. Arguments not starting with '-' (and "-" itself)
 *    are operands, up to max_operands. Returns 0 (parsed; *nops operands in ops), HZ_OPT_DONE (help printed,
 *    or take() finished the program's work: exit 0), or an exit status: HZ_EXIT_USAGE (2) for an unknown option,
 *    a missing value, a value outside the entry's limits or too many operands, each printed with the option
 *    and the reason; take()'s own non-zero status as it returned it.
 *  - hz_opt_help() prints the synopsis, then "  -a, --name ARG  help [lo..hi]" for every entry under the
 *    entries' section headings, then the epilogue.
 */
#ifndef HZ_PROGRAMS_OPTTAB_H
#define HZ_PROGRAMS_OPTTAB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef enum hz_opt_kind {
    HZ_OPT_FLAG,   /* no value */
    HZ_OPT_INT,    /* a decimal integer in [lo, hi] */
    HZ_OPT_REAL,   /* a finite number in [lo, hi] ((lo, hi] with lo_open) */
    HZ_OPT_SIZE,   /* WxH, both in [lo, hi] */
    HZ_OPT_WORD,   /* one of words */
    HZ_OPT_TEXT,   /* non-empty text, checked by the command (a spec, a time, a list, a path) */
} hz_opt_kind_t;

/* Flags. */
#define HZ_OF_IMAGE (1u << 0)  /* changes the image: recorded in summary.json's settings */
#define HZ_OF_OUTPUT (1u << 1) /* the value is an output file */

/* The id of a program's --help entry (hz_opt_parse prints the help for it). */
#define HZ_OPT_ID_HELP (-1)
/* hz_opt_parse: the program is done (help printed, --version, --list): exit 0. */
#define HZ_OPT_DONE (-1)

typedef struct hz_opt {
    const char *name, *arg;   /* arg NULL: a flag */
    hz_opt_kind_t kind;
    double lo, hi;
    bool lo_open;
    const char *const *words; /* HZ_OPT_WORD: NULL-terminated */
    unsigned modes;           /* hzrt: render modes (1 << hz_render_mode_t) it acts in; 0: every mode */
    unsigned where;           /* hzrt: HZ_OW_* (optwhere.h); 0: anywhere */
    unsigned cmds;            /* hzrt: HZ_OC_*; 0: every command */
    unsigned flags;           /* HZ_OF_* */
    int id;                   /* the owner's */
    /* For tests that walk the table: a valid value that differs from the default (flags: NULL), and the
     * options a run with it needs besides (NULL: none), space-separated. */
    const char *sample, *needs;
    const char *help;
    const char *section;      /* the help prints it as a heading before this entry (NULL: none) */
    const char *noun;         /* HZ_OPT_REAL: what a value is, for messages ("an angle"; NULL: "a number") */
    const char *alias;        /* a short form ("-s"; NULL: none) */
} hz_opt_t;

typedef struct hz_opt_val {
    long n;        /* HZ_OPT_INT */
    double x;      /* HZ_OPT_REAL */
    int w, h;      /* HZ_OPT_SIZE; w: HZ_OPT_WORD's index */
    const char *s; /* the text as given */
} hz_opt_val_t;

/* A program's command line. */
typedef struct hz_opt_prog {
    const char *name;     /* "hzbake": "try hzbake --help" */
    const hz_opt_t *table;
    size_t n;
    const char *synopsis; /* printed before the options: usage lines and what the program does */
    const char *epilogue; /* after them (NULL: none) */
    int max_operands;     /* arguments that are not options */
} hz_opt_prog_t;

/* Applies one checked option; returns 0, HZ_OPT_DONE, or an exit status that ends the parse. */
typedef int (*hz_opt_take_fn)(void *ctx, const hz_opt_t *o, const hz_opt_val_t *v);

const hz_opt_t *hz_opt_find(const hz_opt_t *t, size_t n, const char *name);
bool hz_opt_value(const hz_opt_t *o, const char *cmd, const char *v, hz_opt_val_t *out);
int hz_opt_parse(const hz_opt_prog_t *p, int argc, char **argv, hz_opt_take_fn take, void *ctx, const char **ops,
                 int *nops);
void hz_opt_help(FILE *f, const hz_opt_prog_t *p);

/* One entry of a help text, `note` (NULL: none) after its help and limits in parentheses ("only ..."); wide: the
 * table has aliases, so an entry without one is indented to line up; col: the column the help text starts in
 * (hzrt's commands: 24). */
void hz_opt_print_entry(FILE *f, const hz_opt_t *o, const char *note, bool wide, int col);

#endif
