/*
 * libFuzzer target for the CSV edge reader (src/timing/ecsv.c), what `hzrt latency --source csv:FILE` reads.
 * The checks are those of fuzz_trace.h: two reads in different chunkings agree, refusals say where, edges are
 * well formed, and the v-sync model answers every rising edge.
 */
#include "fuzz_trace.h"

static fuzz_edges_t whole, chunked;

static hz_status_t read_csv(const uint8_t *data, size_t size, size_t chunk, fuzz_edges_t *e, hz_error_t *err)
{
    static hz_ecsv_t p;
    fuzz_edges_reset(e);
    hz_error_clear(err);
    hz_ecsv_init(&p);
    hz_status_t s = HZ_OK;
    for (size_t i = 0; s == HZ_OK && i < size; i += chunk)
        s = hz_ecsv_feed(&p, (const char *)data + i, size - i < chunk ? size - i : chunk, fuzz_edge, e, err);
    if (s == HZ_OK)
        s = hz_ecsv_finish(&p, fuzz_edge, e, err);
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hz_error_t e1, e2;
    hz_status_t s1 = read_csv(data, size, size ? size : 1, &whole, &e1);
    fuzz_check_refusal(s1, &e1);
    hz_status_t s2 = read_csv(data, size, fuzz_chunk(data, size), &chunked, &e2);
    fuzz_check_same(s1, &e1, &whole, s2, &e2, &chunked);
    fuzz_vsync(&whole);
    return 0;
}
