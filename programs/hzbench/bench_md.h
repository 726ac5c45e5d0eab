/*
 * bench_md.h — hzbench's Markdown tables: the CSVs a run wrote, read back and set as Markdown, so the printed
 * report, the CSV and the table in doc/results.md are one set of figures.
 *
 * Contract:
 *  - hz_bench_md_csv(f, path, spec, err) reads the CSV at path (a header line naming the columns, then one row per
 *    line; fields separated by commas, "..." quoting with "" for a quote, as RFC 4180) and appends it to f as one
 *    Markdown table. spec may be NULL (every row, every column). With spec->where, only rows whose `where` column
 *    is one of spec->in (a NULL-terminated list) are kept, or, with spec->not_in, none of them. With spec->keys (a
 *    NULL-terminated list of columns) the rows are pivoted: one table row per distinct combination of the key
 *    columns (in order of first appearance), one column per distinct value of spec->across (in order of first
 *    appearance), the cell holding spec->value of the row with that key and that value (the last one when several
 *    match; empty when none does). A column whose non-empty cells all read as numbers is right-aligned; '|' in a
 *    cell is escaped. A file that cannot be read, a row with more fields than the header, or a spec naming a
 *    column the header lacks is an error naming the file (HZ_E_IO, HZ_E_FORMAT); nothing is written then.
 *    A CSV with no rows left gives a line saying so instead of a table.
 *  - hz_bench_md_cell(f, s) writes s as the text of one table cell.
 */
#ifndef HZ_BENCH_MD_H
#define HZ_BENCH_MD_H

#include <stdbool.h>
#include <stdio.h>

#include "hz/status.h"

typedef struct hz_bench_md_spec {
    const char *where;          /* column to filter rows on, or NULL */
    const char *const *in;      /* NULL-terminated values of `where` kept (or dropped with not_in) */
    bool not_in;
    const char *const *keys;    /* pivot: NULL-terminated key columns, or NULL for no pivot */
    const char *across;         /* pivot: column whose values become the table's columns */
    const char *value;          /* pivot: column that fills the cells */
} hz_bench_md_spec_t;

hz_status_t hz_bench_md_csv(FILE *f, const char *path, const hz_bench_md_spec_t *spec, hz_error_t *err);
void hz_bench_md_cell(FILE *f, const char *s);

#endif
