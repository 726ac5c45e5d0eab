/*
 * hz/traceio.h — streaming readers for recorded v-sync traces: single-wire Value Change Dump files and CSV
 * files of edge timestamps. Both take input in chunks of any size, allocate nothing, are freestanding, and
 * hand each edge to a callback.
 *
 * VCD (IEEE 1364, as sigrok-cli and PulseView export it: `sigrok-cli -i capture.sr -O vcd`):
 *  - Follows one 1-bit signal: the one named `signal` (its $var reference name, e.g. "D3" or "vsync"), or,
 *    with signal "" , the only 1-bit $var of the file. Other signals' changes are skipped.
 *  - Identifier codes are any run of printable ASCII characters (33-126), '$' included, of 1 to 254
 *    characters (a value change is one token: the value and the code). Shapes read: any number of $var lines
 *    (wire/reg/..., 1-bit or wider; wider ones are skipped), $scope/$upscope nesting, $timescale as "1 us",
 *    "1us" or spread over lines, $dumpvars/$dumpall/$dumpon/$dumpoff blocks, "#t" lines followed by any
 *    number of changes on the same or following lines, scalar (0 1 x z), vector ("b1 id") and real
 *    ("r1.5 id") values; a vector's last bit is a 1-bit signal's level.
 *  - Reports each transition of that signal as an edge: 0->1 rising (level 1), 1->0 falling (level 0), at the
 *    time of the last #timestamp converted to ns with $timescale (1/10/100 s, ms, us, ns, ps, fs; sub-ns
 *    times are rounded to the nearest ns). The first known value, and changes from or to x/z, are not edges.
 *  - Errors name the line and the reason: no or a malformed $timescale, value changes before
 *    $enddefinitions, an unknown signal (the message lists the ones there are), several 1-bit signals and no
 *    choice, time going backwards, a time that overflows 64-bit nanoseconds, non-text bytes, a token over 255
 *    characters outside comments, a file that ends inside a $section. The edge callback may stop the parse
 *    by returning an error status, which is passed on.
 */
#ifndef HZ_TRACEIO_H
#define HZ_TRACEIO_H

#include <stddef.h>
#include <stdint.h>

#include "hz/status.h"

typedef hz_status_t (*hz_edge_fn)(void *ctx, int64_t t_ns, int level, hz_error_t *err);

#define HZ_VCD_TOKEN_MAX 256
#define HZ_VCD_NAMES_MAX 512

typedef struct hz_vcd {
    char want[64];
    char tok[HZ_VCD_TOKEN_MAX];
    size_t tok_len;
    int tok_long;          /* the current token outgrew tok (allowed inside skipped sections only) */
    uint64_t line, tok_line;
    int section;           /* which $keyword's body the tokens belong to (0: none) */
    int sec_arg;           /* tokens seen inside that section */
    char sec_kw[32];       /* its keyword, for messages */
    char sec_tok[4][HZ_VCD_TOKEN_MAX];
    int in_body;           /* after $enddefinitions */
    int64_t mul, div;      /* ns = ticks * mul / div */
    int have_timescale;
    char id[HZ_VCD_TOKEN_MAX]; /* identifier code of the followed signal */
    int have_id;
    int one_bit_vars;      /* 1-bit $vars seen */
    char names[HZ_VCD_NAMES_MAX]; /* their names, for messages */
    char first_id[HZ_VCD_TOKEN_MAX];
    int pending_vector;    /* a "b..." value waiting for its identifier */
    int vector_level;
    uint64_t ticks;
    int have_time;
    int level;             /* -1 unknown */
    uint64_t edges, changes;
} hz_vcd_t;

hz_status_t hz_vcd_init(hz_vcd_t *p, const char *signal, hz_error_t *err);
hz_status_t hz_vcd_feed(hz_vcd_t *p, const char *data, size_t n, hz_edge_fn edge, void *ctx, hz_error_t *err);
/* End of input: checks nothing was left open. */
hz_status_t hz_vcd_finish(hz_vcd_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err);

/*
 * CSV of edge timestamps (hzrt writes edges.csv in this format; spreadsheets and scripts can too):
 *  - '#' starts a comment line; blank lines are skipped; fields are separated by commas (spaces around
 *    fields are allowed); lines end in LF or CRLF and may be up to HZ_ECSV_LINE_MAX characters.
 *  - An optional header line names the columns: the time is `t_ns` (integer ns), `t_us` or `t_s` (decimal,
 *    up to 9 fraction digits for seconds); the level is `level` (0/1). Other columns are ignored.
 *  - Without a header the first column is t_ns and an optional second one the level. Without a level column
 *    every row is a rising (v-sync) edge.
 *  - Times must be >= 0 and non-decreasing. Errors name the line and the field (bytes that do not print as
 *    \xNN). A UTF-8 byte-order mark at the start of the file is skipped.
 */
#define HZ_ECSV_LINE_MAX 1024

typedef struct hz_ecsv {
    char line[HZ_ECSV_LINE_MAX + 1];
    size_t len;
    int too_long;
    uint64_t line_no;
    int header_done;
    int t_col, level_col;
    int t_unit_digits;     /* fraction digits to scale to ns: 0 ns, 3 us, 9 s */
    int64_t last_t;
    int have_last;
    uint64_t rows;
} hz_ecsv_t;

void hz_ecsv_init(hz_ecsv_t *p);
hz_status_t hz_ecsv_feed(hz_ecsv_t *p, const char *data, size_t n, hz_edge_fn edge, void *ctx, hz_error_t *err);
hz_status_t hz_ecsv_finish(hz_ecsv_t *p, hz_edge_fn edge, void *ctx, hz_error_t *err);

#endif /* HZ_TRACEIO_H */
