/*
 * hzbench — `make bench`: measures hzrt's kernels side by side in one run and prints a table (+ CSV).
 *
 * Every figure in a group is measured in the same process, interleaved round by round, so a shared, noisy
 * machine slows all of them alike and the ratios stay meaningful; absolute times do not transfer between
 * machines. Each figure is the median of the rounds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clock.h"
#include "fileio.h"
#include "hz/hz.h"
#include "hz/image.h"

#define ROUNDS 7

typedef struct row {
    const char *group, *name, *unit;
    double per_sec[ROUNDS];
    double median;
} row_t;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static volatile uint32_t sink;

static double bench_hash(uint32_t n)
{
    int64_t t0 = hz_clock_ns();
    uint32_t acc = 0;
    for (uint32_t i = 0; i < n; i++)
        acc += hz_hash32(i);
    sink = acc;
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

static double bench_hash_pcg(uint32_t n)
{
    int64_t t0 = hz_clock_ns();
    uint32_t acc = 0;
    for (uint32_t i = 0; i < n; i++)
        acc += hz_hash_pcg(i);
    sink = acc;
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

static double bench_rng(uint32_t n)
{
    hz_rng_t r;
    hz_rng_seed(&r, 1, 2);
    int64_t t0 = hz_clock_ns();
    uint32_t acc = 0;
    for (uint32_t i = 0; i < n; i++)
        acc += hz_rng_u32(&r);
    sink = acc;
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

static double bench_arena(uint32_t n)
{
    static uint8_t buf[1 << 20] HZ_ALIGNED(64);
    hz_arena_t a;
    hz_arena_init(&a, "bench", buf, sizeof buf);
    int64_t t0 = hz_clock_ns();
    for (uint32_t i = 0; i < n; i++) {
        void *p = hz_arena_alloc(&a, 48, 16);
        if (!p) {
            hz_arena_reset(&a, 0);
            p = hz_arena_alloc(&a, 48, 16);
        }
        sink += (uint32_t)(uintptr_t)p;
    }
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

/* Linear -> 8-bit sRGB over a 1 Mi-value buffer (3 values a pixel: 1080p is 6.2 M values a frame): the exact
 * table encoder next to the obvious powf formula (which is not even exactly rounded). */
static float *srgb_input(void)
{
    static float v[1 << 20];
    static int ready;
    if (!ready) {
        hz_rng_t r;
        hz_rng_seed(&r, 5, 5);
        for (size_t i = 0; i < HZ_ARRAY_LEN(v); i++)
            v[i] = (float)hz_rng_u32(&r) * 0x1p-32f * 1.1f;
        ready = 1;
    }
    return v;
}

static double bench_srgb8_table(uint32_t n)
{
    const float *v = srgb_input();
    static uint8_t out[1 << 20];
    int64_t t0 = hz_clock_ns();
    for (uint32_t done = 0; done < n; done += 1u << 20)
        hz_srgb8_encode_n(v, out, 1u << 20);
    sink += out[n & 0xfffff];
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

static double bench_srgb8_powf(uint32_t n)
{
    const float *v = srgb_input();
    static uint8_t out[1 << 20];
    int64_t t0 = hz_clock_ns();
    for (uint32_t done = 0; done < n; done += 1u << 20)
        for (size_t i = 0; i < (1u << 20); i++) {
            float x = v[i] > 0.0f ? (v[i] < 1.0f ? v[i] : 1.0f) : 0.0f;
            float e = x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
            out[i] = (uint8_t)(255.0f * e + 0.5f);
        }
    sink += out[n & 0xfffff];
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

int main(int argc, char **argv)
{
    hz_cli_prog = "hzbench";
    const char *csv_path = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--csv") && i + 1 < argc) {
            csv_path = argv[++i];
        } else if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            printf("usage: hzbench [--csv FILE]\n\nMeasures hzrt's kernels side by side and prints medians of %d "
                   "interleaved rounds.\n", ROUNDS);
            return 0;
        } else {
            hz_cli_error("unknown option '%s' (try --help)", argv[i]);
            return HZ_EXIT_USAGE;
        }
    }
    row_t rows[] = {
        { "core", "hash32 (murmur3 fmix)", "Mops/s", { 0 }, 0 },
        { "core", "hash_pcg", "Mops/s", { 0 }, 0 },
        { "core", "rng_u32 (pcg32)", "Mops/s", { 0 }, 0 },
        { "core", "arena_alloc 48 B", "Mops/s", { 0 }, 0 },
        { "image", "srgb8 encode, exact table", "Mvalues/s", { 0 }, 0 },
        { "image", "srgb8 encode, powf formula", "Mvalues/s", { 0 }, 0 },
    };
    double (*fns[])(uint32_t) = { bench_hash, bench_hash_pcg, bench_rng, bench_arena, bench_srgb8_table,
                                  bench_srgb8_powf };
    const uint32_t n = 1u << 24;
    for (int r = 0; r < ROUNDS; r++)
        for (size_t k = 0; k < HZ_ARRAY_LEN(rows); k++)
            rows[k].per_sec[r] = fns[k](n) * 1e-6;
    printf("%-8s %-28s %12s %s\n", "group", "kernel", "median", "unit");
    for (size_t k = 0; k < HZ_ARRAY_LEN(rows); k++) {
        qsort(rows[k].per_sec, ROUNDS, sizeof(double), cmp_double);
        rows[k].median = rows[k].per_sec[ROUNDS / 2];
        printf("%-8s %-28s %12.1f %s\n", rows[k].group, rows[k].name, rows[k].median, rows[k].unit);
    }
    if (csv_path) {
        hz_out_t out;
        hz_error_t err;
        if (hz_out_open(&out, csv_path, &err) != HZ_OK)
            return hz_cli_report(&err);
        fprintf(out.f, "group,kernel,median,min,max,unit\n");
        for (size_t k = 0; k < HZ_ARRAY_LEN(rows); k++)
            fprintf(out.f, "%s,%s,%.3f,%.3f,%.3f,%s\n", rows[k].group, rows[k].name, rows[k].median,
                    rows[k].per_sec[0], rows[k].per_sec[ROUNDS - 1], rows[k].unit);
        if (hz_out_commit(&out, &err) != HZ_OK)
            return hz_cli_report(&err);
        printf("wrote %s\n", csv_path);
    }
    return 0;
}
