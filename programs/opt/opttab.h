/*
 * opttab.h — command-line options from tables. Each entry knows its option's value kind and limits, the render
 * modes it acts in, the v-sync sources, sinks and frames it acts with, the commands that take it, whether it
 * changes the image, and its help line. One parser checks a value against its entry, one check refuses an option
 * given where it would do nothing, and one printer writes the help text from the entries, limits and
 * applicability included: the help cannot drift from what is checked.
 *
 * Contract:
 *  - hz_opt_find() returns the entry named argv[i] (NULL: not in the table). hz_opt_value() checks the value
 *    (NULL for a flag) against the entry: an integer or number in [lo, hi] (lo excluded with lo_open), a size
 *    WxH with both sides in [lo, hi], one of the words, or any non-empty text; a bad value prints why, naming
 *    the option and the command, and returns false.
 *  - Applicability: `where` holds bits of four groups (source, sink, frames, clock); in a group where the entry
 *    has no bit it acts with anything. hz_opt_acts() says whether an entry acts in a run described by bits of
 *    every group; hz_opt_refuse_idle() prints why it does not ("--jitter-us does nothing with --source gpio: it
 *    acts with --source sim") and returns HZ_EXIT_USAGE.
 *  - hz_opt_usage() prints the entries a command takes: "  --name ARG  help [lo..hi] (only ...)", under the
 *    entries' section headings.
 */
#ifndef HZ_PORT_OPTTAB_H
#define HZ_PORT_OPTTAB_H

#include <stdbool.h>
#include <stdio.h>

typedef enum hz_opt_kind {
    HZ_OPT_FLAG,   /* no value */
    HZ_OPT_INT,    /* a decimal integer in [lo, hi] */
    HZ_OPT_REAL,   /* a finite number in [lo, hi] ((lo, hi] with lo_open) */
    HZ_OPT_SIZE,   /* WxH, both in [lo, hi] */
    HZ_OPT_WORD,   /* one of words */
    HZ_OPT_TEXT,   /* non-empty text, checked by the command (a spec, a time, a list, a path) */
} hz_opt_kind_t;

/* Where an option acts. Sources: */
#define HZ_OW_OFFLINE (1u << 0)
#define HZ_OW_SIM (1u << 1)
#define HZ_OW_GPIO (1u << 2)
#define HZ_OW_FBDEV_SRC (1u << 3)
#define HZ_OW_DRM_SRC (1u << 4)
#define HZ_OW_V4L2_SRC (1u << 5)
#define HZ_OW_VCD (1u << 6)
#define HZ_OW_CSV (1u << 7)
#define HZ_OW_SOURCES 0xffu
#define HZ_OW_DISPLAY_SOURCES (HZ_OW_SOURCES & ~HZ_OW_OFFLINE)
/* sinks (`display` is the board's drm or fbdev): */
#define HZ_OW_FILES (1u << 8)
#define HZ_OW_NONE (1u << 9)
#define HZ_OW_DRM (1u << 10)
#define HZ_OW_FBDEV (1u << 11)
#define HZ_OW_V4L2 (1u << 12)
#define HZ_OW_SINKS 0x1f00u
#define HZ_OW_DEVICE_SINKS (HZ_OW_DRM | HZ_OW_FBDEV | HZ_OW_V4L2)
/* frames: */
#define HZ_OW_PATTERN (1u << 13)
#define HZ_OW_SCENE (1u << 14)
#define HZ_OW_EDGES (1u << 15)
#define HZ_OW_FRAMES (HZ_OW_PATTERN | HZ_OW_SCENE)
#define HZ_OW_WHAT 0xe000u
/* clock: */
#define HZ_OW_REAL (1u << 16)
#define HZ_OW_VIRTUAL (1u << 17)
#define HZ_OW_CLOCK 0x30000u

/* Commands (0 in an entry: every command). */
#define HZ_OC_RENDER (1u << 0)
#define HZ_OC_SHOW (1u << 1)
#define HZ_OC_LATENCY (1u << 2)

/* Flags. */
#define HZ_OF_IMAGE (1u << 0)  /* changes the image: recorded in summary.json's settings */
#define HZ_OF_OUTPUT (1u << 1) /* the value is an output file */

typedef struct hz_opt {
    const char *name, *arg;   /* arg NULL: a flag */
    hz_opt_kind_t kind;
    double lo, hi;
    bool lo_open;
    const char *const *words; /* HZ_OPT_WORD: NULL-terminated */
    unsigned modes;           /* render modes (1 << hz_render_mode_t) it acts in; 0: every mode */
    unsigned where;           /* HZ_OW_* */
    unsigned cmds;            /* HZ_OC_*; 0: every command */
    unsigned flags;           /* HZ_OF_* */
    int id;                   /* the owner's */
    /* For tests that walk the table: a valid value that differs from the default (flags: NULL), and the
     * options a run with it needs besides (NULL: none), space-separated. */
    const char *sample, *needs;
    const char *help;
    const char *section;      /* the help prints it as a heading before this entry (NULL: none) */
    const char *noun;         /* HZ_OPT_REAL: what a value is, for messages ("an angle"; NULL: "a number") */
} hz_opt_t;

typedef struct hz_opt_val {
    long n;        /* HZ_OPT_INT */
    double x;      /* HZ_OPT_REAL */
    int w, h;      /* HZ_OPT_SIZE; w: HZ_OPT_WORD's index */
    const char *s; /* the text as given */
} hz_opt_val_t;

const hz_opt_t *hz_opt_find(const hz_opt_t *t, size_t n, const char *name);
bool hz_opt_value(const hz_opt_t *o, const char *cmd, const char *v, hz_opt_val_t *out);
bool hz_opt_acts(const hz_opt_t *o, unsigned run_where);
int hz_opt_refuse_idle(const hz_opt_t *o, const char *cmd, unsigned run_where);
/* "full, taa or tdense" for a mode mask. */
const char *hz_opt_modes_str(char *buf, size_t cap, unsigned modes);
/* fixed: groups (HZ_OW_SOURCES, ...) the command fixes, left out of the annotations (render always draws a
 * scene). */
void hz_opt_usage(FILE *f, const hz_opt_t *t, size_t n, unsigned cmd, unsigned fixed);

#endif
