/*
 * libFuzzer target for the VCD trace reader (src/timing/vcd.c), what `hzrt latency --source vcd:FILE` reads.
 *
 * The signal to follow is "" (the file's only 1-bit signal) unless the input names one in a comment, which the
 * reader skips like any other: `$comment hzfuzz-signal NAME $end`. The checks are those of fuzz_trace.h: two
 * reads in different chunkings agree, refusals say where, edges are well formed, and the v-sync model answers
 * every rising edge.
 */
#include "fuzz_trace.h"

static fuzz_edges_t whole, chunked;

static hz_status_t read_vcd(const char *signal, const uint8_t *data, size_t size, size_t chunk, fuzz_edges_t *e,
                            hz_error_t *err)
{
    static hz_vcd_t p;
    fuzz_edges_reset(e);
    hz_error_clear(err);
    hz_status_t s = hz_vcd_init(&p, signal, err);
    for (size_t i = 0; s == HZ_OK && i < size; i += chunk)
        s = hz_vcd_feed(&p, (const char *)data + i, size - i < chunk ? size - i : chunk, fuzz_edge, e, err);
    if (s == HZ_OK)
        s = hz_vcd_finish(&p, fuzz_edge, e, err);
    return s;
}

/* The NAME of the first "hzfuzz-signal NAME", or "". */
static void signal_of(const uint8_t *data, size_t size, char *out, size_t cap)
{
    static const char key[] = "hzfuzz-signal ";
    const size_t k = sizeof key - 1;
    out[0] = '\0';
    for (size_t i = 0; i + k <= size; i++) {
        if (memcmp(data + i, key, k))
            continue;
        size_t n = 0;
        for (size_t j = i + k; j < size && n + 1 < cap && data[j] > ' ' && data[j] < 0x7f; j++)
            out[n++] = (char)data[j];
        out[n] = '\0';
        return;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char signal[80];
    signal_of(data, size, signal, sizeof signal);
    hz_error_t e1, e2;
    hz_status_t s1 = read_vcd(signal, data, size, size ? size : 1, &whole, &e1);
    if (s1 != HZ_OK && strlen(signal) >= sizeof ((hz_vcd_t *)0)->want) {
        if (e1.code != s1 || !e1.msg[0])
            abort(); /* a signal name too long for the reader is refused up front, with a message */
        return 0;
    }
    fuzz_check_refusal(s1, &e1);
    hz_status_t s2 = read_vcd(signal, data, size, fuzz_chunk(data, size), &chunked, &e2);
    fuzz_check_same(s1, &e1, &whole, s2, &e2, &chunked);
    fuzz_vsync(&whole);
    return 0;
}
