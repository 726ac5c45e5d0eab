/* VCD and CSV trace readers: valid traces in any chunking, every malformed input a clear error. */
#include "hz_test.h"

#include <stdio.h>
#include <string.h>

#include "hz/hash.h"
#include "hz/traceio.h"
#include "hz_traces.h" /* the VCDs of test/traces as string arrays (test/traces/mkheader.sh) */

typedef struct edges {
    int64_t t[64];
    int level[64];
    int n;
    int stop_after; /* callback fails after this many (0: never) */
} edges_t;

static hz_status_t collect(void *ctx, int64_t t, int level, hz_error_t *err)
{
    edges_t *e = ctx;
    if (e->stop_after && e->n >= e->stop_after)
        return hz_error_set(err, HZ_E_NO_MEMORY, "edge buffer full");
    if (e->n < 64) {
        e->t[e->n] = t;
        e->level[e->n] = level;
    }
    e->n++;
    return HZ_OK;
}

static const char sigrok_vcd[] =
    "$date Mon Nov 20 10:00:00 2023 $end\n"
    "$version libsigrok 0.5.2 $end\n"
    "$comment\n  Acquisition with 2/8 channels at 24 MHz\n$end\n"
    "$timescale 1 ns $end\n"
    "$scope module libsigrok $end\n"
    "$var wire 1 ! D0 $end\n"
    "$var wire 1 \" VSYNC $end\n"
    "$upscope $end\n"
    "$enddefinitions $end\n"
    "#0 0! 0\"\n"
    "#1000 1\"\n"
    "#1500 1!\n"
    "#5000 0\"\n"
    "#16667000 1\"\n"
    "#16668000 0\"\n"
    "#33334000 x\"\n"
    "#33335000 1\"\n"
    "#33336000 b0 \"\n"
    "#40000000\n";

static hz_status_t parse_vcd(const char *text, size_t n, const char *signal, size_t chunk, edges_t *e,
                             hz_error_t *err)
{
    static hz_vcd_t p;
    memset(e, 0, sizeof *e);
    hz_status_t s = hz_vcd_init(&p, signal, err);
    for (size_t i = 0; s == HZ_OK && i < n; i += chunk)
        s = hz_vcd_feed(&p, text + i, n - i < chunk ? n - i : chunk, collect, e, err);
    if (s == HZ_OK)
        s = hz_vcd_finish(&p, collect, e, err);
    return s;
}

static void test_vcd_sigrok_trace(void **state)
{
    (void)state;
    edges_t e, e1;
    hz_error_t err;
    size_t n = strlen(sigrok_vcd);
    assert_int_equal(parse_vcd(sigrok_vcd, n, "VSYNC", n, &e, &err), HZ_OK);
    /* 0->1 at 1000, 1->0 at 5000, 0->1 at 16667000, 1->0 at 16668000; x and back to 1 is not an edge;
     * 1->0 (vector) at 33336000. */
    assert_int_equal(e.n, 5);
    int64_t want_t[] = { 1000, 5000, 16667000, 16668000, 33336000 };
    int want_l[] = { 1, 0, 1, 0, 0 };
    for (int i = 0; i < 5; i++) {
        assert_int_equal(e.t[i], want_t[i]);
        assert_int_equal(e.level[i], want_l[i]);
    }
    /* Byte-by-byte feeding gives the same edges. */
    assert_int_equal(parse_vcd(sigrok_vcd, n, "VSYNC", 1, &e1, &err), HZ_OK);
    assert_int_equal(e1.n, e.n);
    assert_memory_equal(e1.t, e.t, sizeof e.t);
    /* The other channel. */
    assert_int_equal(parse_vcd(sigrok_vcd, n, "D0", 7, &e, &err), HZ_OK);
    assert_int_equal(e.n, 1);
    assert_int_equal(e.t[0], 1500);
}

static void test_vcd_timescales(void **state)
{
    (void)state;
    const char *fmt = "$timescale %s $end $var wire 1 # v $end $enddefinitions $end #0 0# #3 1# #7 0#";
    struct { const char *ts; int64_t t1, t2; } cases[] = {
        { "1 ns", 3, 7 }, { "10ns", 30, 70 }, { "100 us", 300000, 700000 }, { "1 s", 3000000000ll, 7000000000ll },
        { "1 ps", 0, 0 }, { "100 ps", 0, 1 }, { "1 ms", 3000000, 7000000 },
    };
    char buf[256];
    edges_t e;
    hz_error_t err;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(buf, sizeof buf, fmt, cases[i].ts);
        assert_int_equal(parse_vcd(buf, strlen(buf), "", 5, &e, &err), HZ_OK);
        assert_int_equal(e.n, 2);
        assert_int_equal(e.t[0], cases[i].t1);
        assert_int_equal(e.t[1], cases[i].t2);
    }
}

static void expect_vcd_error(const char *text, const char *signal, const char *needle)
{
    edges_t e;
    hz_error_t err;
    hz_status_t s = parse_vcd(text, strlen(text), signal, 3, &e, &err);
    if (s == HZ_OK || !strstr(err.msg, needle))
        fail_msg("input <%s>: status %d, message '%s', expected '%s'", text, s, s ? err.msg : "", needle);
}

static void test_vcd_errors(void **state)
{
    (void)state;
    const char *head = "$timescale 1 ns $end $var wire 1 ! a $end $var wire 1 \" b $end $enddefinitions $end ";
    char buf[1024];
    expect_vcd_error("", "", "no $enddefinitions");
    expect_vcd_error("hello world", "", "line 1: value change before $enddefinitions: 'hello'");
    expect_vcd_error("$var wire 1 ! a $end $enddefinitions $end", "", "no $timescale");
    expect_vcd_error("$timescale 3 ns $end", "", "multiplier must be 1, 10 or 100");
    expect_vcd_error("$timescale 1 hz $end", "", "unit must be s, ms, us, ns, ps or fs");
    expect_vcd_error("$timescale 1 ns $end $var wire 1 ! a $end\n$var wire 1 \" b $end $enddefinitions $end", "",
                     "2 1-bit signals (a, b): name the v-sync one");
    expect_vcd_error("$timescale 1 ns $end $var wire 8 ! bus $end $enddefinitions $end", "",
                     "declares no 1-bit signal");
    snprintf(buf, sizeof buf, "%s", head);
    expect_vcd_error(buf, "vsync", "no 1-bit signal named 'vsync' (the file has: a, b)");
    snprintf(buf, sizeof buf, "%s#10 1!\n#5 0!", head);
    expect_vcd_error(buf, "a", "line 2: time goes backwards at '#5'");
    snprintf(buf, sizeof buf, "%s#99999999999999999999", head);
    expect_vcd_error(buf, "a", "bad timestamp");
    expect_vcd_error("$timescale 1 s $end $var wire 1 ! a $end $enddefinitions $end #9300000000000000000", "",
                     "does not fit 64-bit nanoseconds");
    snprintf(buf, sizeof buf, "%s#1 1!\n#2 ?!", head);
    expect_vcd_error(buf, "a", "line 2: not a value change or #time: '?!'");
    snprintf(buf, sizeof buf, "%s#1 1", head);
    expect_vcd_error(buf, "a", "value change without an identifier");
    expect_vcd_error("$timescale 1 ns $end $var wire 1 ! a", "", "ends inside $var (missing $end)");
    expect_vcd_error("$comment never closed", "", "ends inside $comment");
    expect_vcd_error("$timescale 1 ns $var wire 1 ! a $end", "", "'$var' inside $timescale (missing $end?)");
    expect_vcd_error("$end", "", "$end without a section");
    snprintf(buf, sizeof buf, "%s#1 1!\x01", head);
    expect_vcd_error(buf, "a", "byte 0x01 is not VCD text");
    snprintf(buf, sizeof buf, "%s$var wire 1 # c $end", head);
    expect_vcd_error(buf, "a", "declaration after $enddefinitions");
    snprintf(buf, sizeof buf, "%s#1 b1", head);
    expect_vcd_error(buf, "a", "vector value without its identifier");
    /* A long token outside a comment: refused; inside a comment: fine. */
    char longtok[301];
    memset(longtok, 'x', 300);
    longtok[300] = '\0';
    snprintf(buf, sizeof buf, "%s#1 %s", head, longtok);
    expect_vcd_error(buf, "a", "token longer than 255 characters");
    snprintf(buf, sizeof buf,
             "$comment %s \xc3\xa9 $end $timescale 1 ns $end $var wire 1 ! a $end $enddefinitions $end", longtok);
    edges_t e;
    hz_error_t err;
    assert_int_equal(parse_vcd(buf, strlen(buf), "", 16, &e, &err), HZ_OK);
    /* The callback can stop the parse; its status comes back. */
    snprintf(buf, sizeof buf, "%s#1 1! #2 0! #3 1! #4 0!\n", head);
    static hz_vcd_t p;
    memset(&e, 0, sizeof e);
    e.stop_after = 2;
    assert_int_equal(hz_vcd_init(&p, "a", &err), HZ_OK);
    assert_int_equal(hz_vcd_feed(&p, buf, strlen(buf), collect, &e, &err), HZ_E_NO_MEMORY);
    assert_string_equal(err.msg, "edge buffer full");
}

/* A recorded sigrok-cli export (test/traces/README.md), fed line by line as read from the file. */
static hz_status_t parse_lines(const char *const *lines, size_t n, const char *signal, edges_t *e, hz_error_t *err)
{
    static hz_vcd_t p;
    memset(e, 0, sizeof *e);
    hz_status_t s = hz_vcd_init(&p, signal, err);
    for (size_t i = 0; s == HZ_OK && i < n; i++)
        s = hz_vcd_feed(&p, lines[i], strlen(lines[i]), collect, e, err);
    if (s == HZ_OK)
        s = hz_vcd_finish(&p, collect, e, err);
    return s;
}

static void test_vcd_sigrok_demo_exports(void **state)
{
    (void)state;
    /* Edge counts and first/last edges per channel from an independent reader (a Python split-and-compare of
     * the same files, written for this test). D3's identifier code is '$'. D7 never changes in the demo. */
    typedef struct { const char *ch; int n; int64_t t0; int l0; } chan_t;
    static const chan_t k200[] = {
        { "D0", 500, 5000, 0 }, { "D1", 749, 5000, 1 }, { "D2", 623, 5000, 1 }, { "D3", 562, 5000, 0 },
        { "D4", 686, 20000, 0 }, { "D5", 687, 5000, 1 }, { "D6", 562, 5000, 0 }, { "D7", 0, 0, 0 },
    }, k1[] = {
        { "D0", 1000, 1000000, 0 }, { "D1", 1501, 1000000, 1 }, { "D2", 1249, 1000000, 1 },
        { "D3", 1126, 1000000, 0 }, { "D4", 1376, 4000000, 0 }, { "D5", 1377, 1000000, 1 },
        { "D6", 1126, 1000000, 0 }, { "D7", 0, 0, 0 },
    };
    edges_t e;
    hz_error_t err;
    for (int f = 0; f < 2; f++)
        for (int c = 0; c < 8; c++) {
            const char *const *lines = f ? hz_trace_sigrok_demo_1k_vcd : hz_trace_sigrok_demo_200k_vcd;
            size_t n = f ? sizeof hz_trace_sigrok_demo_1k_vcd / sizeof lines[0]
                         : sizeof hz_trace_sigrok_demo_200k_vcd / sizeof lines[0];
            const chan_t *k = f ? &k1[c] : &k200[c];
            hz_status_t s = parse_lines(lines, n, k->ch, &e, &err);
            if (s != HZ_OK)
                fail_msg("%s channel %s: %s", f ? "1k" : "200k", k->ch, err.msg);
            assert_int_equal(e.n, k->n);
            if (k->n) {
                assert_int_equal(e.t[0], k->t0);
                assert_int_equal(e.level[0], k->l0);
            }
        }
    /* Without --signal the file's eight 1-bit signals are listed. */
    assert_int_equal(parse_lines(hz_trace_sigrok_demo_1k_vcd,
                                 sizeof hz_trace_sigrok_demo_1k_vcd / sizeof hz_trace_sigrok_demo_1k_vcd[0], "",
                                 &e, &err),
                     HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "8 1-bit signals (D0, D1, D2, D3, D4, D5, D6, D7): name the v-sync one"));
}

static hz_status_t keep_last(void *ctx, int64_t t, int level, hz_error_t *err)
{
    (void)level;
    (void)err;
    *(int64_t *)ctx = t;
    return HZ_OK;
}

static void test_vcd_sigrok_last_edges(void **state)
{
    (void)state;
    const char *ch[] = { "D0", "D3", "D6" };
    int64_t want[] = { 3996000000ll, 3996000000ll, 3997000000ll };
    static hz_vcd_t p;
    hz_error_t err;
    size_t n = sizeof hz_trace_sigrok_demo_1k_vcd / sizeof hz_trace_sigrok_demo_1k_vcd[0];
    for (int c = 0; c < 3; c++) {
        int64_t last = -1;
        assert_int_equal(hz_vcd_init(&p, ch[c], &err), HZ_OK);
        for (size_t i = 0; i < n; i++)
            assert_int_equal(hz_vcd_feed(&p, hz_trace_sigrok_demo_1k_vcd[i], strlen(hz_trace_sigrok_demo_1k_vcd[i]),
                                         keep_last, &last, &err),
                             HZ_OK);
        assert_int_equal(hz_vcd_finish(&p, keep_last, &last, &err), HZ_OK);
        assert_int_equal(last, want[c]);
    }
}

static void test_vcd_identifier_codes(void **state)
{
    (void)state;
    /* Codes of any printable characters and length: '$', '$end'-like prefixes, multi-character codes (sigrok
     * past 94 channels, GTKWave, Verilog simulators), a 200-character one; a vector value "b1 $"; $dumpvars
     * with initial values; a timescale spread over lines; several changes per #time, on separate lines. */
    char code[201];
    for (int i = 0; i < 200; i++)
        code[i] = (char)(33 + (i * 7) % 94);
    code[200] = '\0';
    for (int i = 0; i < 200; i++)
        if (code[i] == '$' && i == 0)
            code[i] = '%';
    static char buf[4096];
    snprintf(buf, sizeof buf,
             "$version Icarus $end\n$timescale\n\t10\n\tns\n$end\n$scope module top $end\n"
             "$var wire 1 $ D3 $end\n$var wire 1 $$ two $end\n$var reg 1 !! bang $end\n"
             "$var wire 8 $x bus $end\n$var wire 1 %s long $end\n$var wire 1 $endx tricky $end\n"
             "$scope module inner $end $var wire 1 a$b in [0] $end $upscope $end\n$upscope $end\n"
             "$enddefinitions $end\n#0\n$dumpvars\n0$\nb0 $$\n0!!\nb00000000 $x\n0%s\n0$endx\n0a$b\n$end\n"
             "#1 1$ 1$$\n1!!\nb10101010 $x\n#2\n0$\nb1 $$\n1%s\n1$endx\n1a$b\n#3 0!! 0%s 0$endx 0a$b\n",
             code, code, code, code);
    struct { const char *sig; int n; int64_t t0; } want[] = {
        { "D3", 2, 10 }, { "two", 1, 10 }, { "bang", 2, 10 }, { "long", 2, 20 }, { "tricky", 2, 20 },
        { "in", 2, 20 },
    };
    edges_t e;
    hz_error_t err;
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
        for (size_t chunk = 1; chunk <= 64; chunk *= 4) {
            hz_status_t s = parse_vcd(buf, strlen(buf), want[i].sig, chunk, &e, &err);
            if (s != HZ_OK)
                fail_msg("%s (chunks of %zu): %s", want[i].sig, chunk, err.msg);
            assert_int_equal(e.n, want[i].n);
            assert_int_equal(e.t[0], want[i].t0);
        }
    /* A code too long for a value-change token is refused with its reason, not truncated into a match. */
    char huge[300];
    memset(huge, 'q', 299);
    huge[299] = '\0';
    snprintf(buf, sizeof buf, "$timescale 1 ns $end $var wire 1 %s v $end $enddefinitions $end", huge);
    expect_vcd_error(buf, "v", "longer than 255 characters");
}

static hz_status_t parse_csv(const char *text, size_t chunk, edges_t *e, hz_error_t *err)
{
    static hz_ecsv_t p;
    memset(e, 0, sizeof *e);
    hz_ecsv_init(&p);
    size_t n = strlen(text);
    hz_status_t s = HZ_OK;
    for (size_t i = 0; s == HZ_OK && i < n; i += chunk)
        s = hz_ecsv_feed(&p, text + i, n - i < chunk ? n - i : chunk, collect, e, err);
    if (s == HZ_OK)
        s = hz_ecsv_finish(&p, collect, e, err);
    return s;
}

static void test_csv_forms(void **state)
{
    (void)state;
    edges_t e;
    hz_error_t err;
    assert_int_equal(parse_csv("# hzrt edges\n100\n200\n\n300", 2, &e, &err), HZ_OK);
    assert_int_equal(e.n, 3);
    assert_int_equal(e.t[2], 300);
    assert_int_equal(e.level[0], 1);
    assert_int_equal(parse_csv("100,1\r\n150,0\r\n", 1, &e, &err), HZ_OK);
    assert_int_equal(e.n, 2);
    assert_int_equal(e.level[1], 0);
    /* hzrt's own edges.csv: named columns, extra ones ignored. */
    assert_int_equal(parse_csv("t_ns,level,class,slot\n10,1,edge,0\n20,0,edge,0\n", 64, &e, &err), HZ_OK);
    assert_int_equal(e.n, 2);
    assert_int_equal(e.t[1], 20);
    assert_int_equal(parse_csv("index, T_S , level\n0, 1.5, 1\n1, 2.000000001 ,0\n2,3,1", 5, &e, &err), HZ_OK);
    assert_int_equal(e.n, 3);
    assert_int_equal(e.t[0], 1500000000);
    assert_int_equal(e.t[1], 2000000001);
    assert_int_equal(e.t[2], 3000000000ll);
    assert_int_equal(parse_csv("t_us\n16.667\n33.334\n", 3, &e, &err), HZ_OK);
    assert_int_equal(e.t[0], 16667);
}

static void expect_csv_error(const char *text, const char *needle)
{
    edges_t e;
    hz_error_t err;
    hz_status_t s = parse_csv(text, 4, &e, &err);
    if (s == HZ_OK || !strstr(err.msg, needle))
        fail_msg("input <%s>: status %d, message '%s', expected '%s'", text, s, s ? err.msg : "", needle);
}

static void test_csv_errors(void **state)
{
    (void)state;
    expect_csv_error("100\nabc\n", "line 2: time 'abc' is not a non-negative number of nanoseconds");
    expect_csv_error("100\n-5\n", "line 2: time '-5'");
    expect_csv_error("100\n50\n", "line 2: time 50 ns goes backwards (previous 100 ns)");
    expect_csv_error("100,2\n", "line 1: level must be 0 or 1");
    expect_csv_error("100,1\n200\n", "line 2: 1 field, the level column is missing");
    expect_csv_error("time,level\n1,1\n", "line 1: the header names no time column");
    expect_csv_error("t_s\n1.1234567891\n", "line 2: time '1.1234567891'");
    expect_csv_error("1\x02\n", "byte 0x02 is not CSV text");
    expect_csv_error("99999999999999999999\n", "not a non-negative number");
    char big[1200];
    memset(big, '1', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    expect_csv_error(big, "line 1: longer than 1024 characters");
}

static void test_fuzz_never_crashes(void **state)
{
    (void)state;
    /* Random mutations of valid traces: each parse ends with OK or an error message, never a crash (the
     * sanitizer build checks the bounds). */
    static char buf[sizeof sigrok_vcd + 64];
    hz_rng_t r;
    hz_rng_seed(&r, 99, 5);
    int errors = 0;
    for (int round = 0; round < 3000; round++) {
        size_t n = strlen(sigrok_vcd);
        memcpy(buf, sigrok_vcd, n);
        int muts = 1 + (int)hz_rng_below(&r, 6);
        for (int m = 0; m < muts; m++)
            buf[hz_rng_below(&r, (uint32_t)n)] = (char)hz_rng_below(&r, 256);
        n = hz_rng_below(&r, (uint32_t)n + 1); /* and cut it somewhere */
        edges_t e;
        hz_error_t err;
        hz_status_t s = parse_vcd(buf, n, round & 1 ? "VSYNC" : "", 1 + hz_rng_below(&r, 40), &e, &err);
        if (s != HZ_OK) {
            errors++;
            assert_true(strlen(err.msg) > 0);
        }
        s = parse_csv(buf, 1 + hz_rng_below(&r, 40), &e, &err);
        if (s != HZ_OK)
            assert_true(strlen(err.msg) > 0);
    }
    assert_true(errors > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vcd_sigrok_trace),
        cmocka_unit_test(test_vcd_timescales),
        cmocka_unit_test(test_vcd_errors),
        cmocka_unit_test(test_vcd_sigrok_demo_exports),
        cmocka_unit_test(test_vcd_sigrok_last_edges),
        cmocka_unit_test(test_vcd_identifier_codes),
        cmocka_unit_test(test_csv_forms),
        cmocka_unit_test(test_csv_errors),
        cmocka_unit_test(test_fuzz_never_crashes),
    };
    return HZ_RUN(tests);
}
