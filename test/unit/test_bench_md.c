/* hzbench's Markdown tables (programs/hzbench/bench_md.h): a CSV read back as a table exactly, quoting and escaping,
 * alignment by column, row filters, the pivot, and each bad input refused by name with nothing written. The
 * expected tables are written out by hand from the CSVs here. */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* hzbench's own source, compiled into the test: the unit tests link the core, port and errtime libraries,
 * not hzbench's objects. */
#include "../../programs/hzbench/bench_md.c"

static char csv_path[512];

static void write_csv(const char *text)
{
    const char *dir = getenv("TMPDIR");
    snprintf(csv_path, sizeof csv_path, "%s/test_bench_md.%ld.csv", dir && *dir ? dir : "/tmp", (long)getpid());
    FILE *f = fopen(csv_path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* The table for the CSV at csv_path under spec, as a string (static buffer). */
static const char *md(const hz_bench_md_spec_t *spec, hz_status_t want, hz_error_t *err)
{
    static char out[4096];
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(hz_bench_md_csv(f, csv_path, spec, err), want);
    rewind(f);
    size_t n = fread(out, 1, sizeof out - 1, f);
    out[n] = '\0';
    fclose(f);
    return out;
}

static void test_plain_table(void **state)
{
    (void)state;
    hz_error_t err;
    /* A quoted field holding a comma and a doubled quote, a '|' to escape, CRLF line ends, a short row. */
    write_csv("group,kernel,median,unit\r\n"
              "core,\"srgb8 encode, exact \"\"table\"\"\",1295.6,Mvalues/s\r\n"
              "image,a|b,-3.5e2,ms\r\n"
              "pattern,short\r\n");
    const char *t = md(NULL, HZ_OK, &err);
    assert_string_equal(t, "| group | kernel | median | unit |\n"
                           "|---|---|---:|---|\n"
                           "| core | srgb8 encode, exact \"table\" | 1295.6 | Mvalues/s |\n"
                           "| image | a\\|b | -3.5e2 | ms |\n"
                           "| pattern | short |  |  |\n");
    remove(csv_path);
}

static void test_filter(void **state)
{
    (void)state;
    hz_error_t err;
    write_csv("group,name,value\ncore,a,1\ntdense,b,2\nblur,c,3\ncore,d,nan\n");
    static const char *const core[] = { "core", NULL }, *const two[] = { "tdense", "blur", NULL };
    hz_bench_md_spec_t in = { "group", core, false, NULL, NULL, NULL };
    assert_string_equal(md(&in, HZ_OK, &err), "| group | name | value |\n|---|---|---:|\n"
                                              "| core | a | 1 |\n| core | d | nan |\n");
    hz_bench_md_spec_t out = { "group", two, true, NULL, NULL, NULL };
    assert_string_equal(md(&out, HZ_OK, &err), "| group | name | value |\n|---|---|---:|\n"
                                               "| core | a | 1 |\n| core | d | nan |\n");
    static const char *const none[] = { "accel", NULL };
    hz_bench_md_spec_t empty = { "group", none, false, NULL, NULL, NULL };
    char want[600];
    snprintf(want, sizeof want, "(no rows in %s)\n", csv_path);
    assert_string_equal(md(&empty, HZ_OK, &err), want);
    remove(csv_path);
}

static void test_pivot(void **state)
{
    (void)state;
    hz_error_t err;
    /* Keys in order of first appearance, one column per method in order of first appearance; the cell of a
     * (key, method) pair that has no row stays empty; rows the filter drops take no part. */
    write_csv("scene,what,threads,method,value\n"
              "sponza,primary,2,native,10.5\n"
              "sponza,primary,2,embree,9.0\n"
              "sponza,shadow,2,native,20\n"
              "dragon,primary,2,embree,7\n"
              "dragon,primary,2,native,8\n"
              "dragon,build,1,native,0.5\n");
    static const char *const primary[] = { "primary", "shadow", NULL }, *const keys[] = { "scene", "what", NULL };
    hz_bench_md_spec_t spec = { "what", primary, false, keys, "method", "value" };
    assert_string_equal(md(&spec, HZ_OK, &err), "| scene | what | native | embree |\n"
                                                "|---|---|---:|---:|\n"
                                                "| sponza | primary | 10.5 | 9.0 |\n"
                                                "| sponza | shadow | 20 |  |\n"
                                                "| dragon | primary | 8 | 7 |\n");
    remove(csv_path);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    hz_error_t err;
    /* A file that is not there: i/o error naming it, nothing written. */
    snprintf(csv_path, sizeof csv_path, "test_bench_md.no-such-file.csv");
    assert_string_equal(md(NULL, HZ_E_IO, &err), "");
    assert_non_null(strstr(err.msg, "test_bench_md.no-such-file.csv"));
    /* A row with more fields than the header. */
    write_csv("a,b\n1,2\n1,2,3\n");
    assert_string_equal(md(NULL, HZ_E_FORMAT, &err), "");
    assert_non_null(strstr(err.msg, "row 3 has 3 fields, the header 2"));
    assert_non_null(strstr(err.msg, csv_path));
    /* A spec naming a column the header lacks: the filter, a key, the pivot's value. */
    write_csv("a,b\n1,2\n");
    static const char *const any[] = { "1", NULL }, *const keys[] = { "a", NULL }, *const bad_keys[] = { "z", NULL };
    hz_bench_md_spec_t where = { "nope", any, false, NULL, NULL, NULL };
    assert_string_equal(md(&where, HZ_E_FORMAT, &err), "");
    assert_non_null(strstr(err.msg, "no column 'nope'"));
    hz_bench_md_spec_t key = { NULL, NULL, false, bad_keys, "b", "b" };
    assert_string_equal(md(&key, HZ_E_FORMAT, &err), "");
    assert_non_null(strstr(err.msg, "no column 'z'"));
    hz_bench_md_spec_t value = { NULL, NULL, false, keys, "b", "missing" };
    assert_string_equal(md(&value, HZ_E_FORMAT, &err), "");
    assert_non_null(strstr(err.msg, "no column 'missing'"));
    /* An empty file has no header. */
    write_csv("");
    assert_string_equal(md(NULL, HZ_E_FORMAT, &err), "");
    assert_non_null(strstr(err.msg, "empty"));
    remove(csv_path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain_table),
        cmocka_unit_test(test_filter),
        cmocka_unit_test(test_pivot),
        cmocka_unit_test(test_bad_inputs),
    };
    return HZ_RUN(tests);
}
