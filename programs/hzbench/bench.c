/*
 * hzbench — `make bench`: measures hzrt's kernels side by side in one run and prints a table (+ CSV, and with
 * --md the same figures as Markdown tables: bench_md.h).
 *
 * Every figure in a group is measured in the same process, interleaved round by round, so a shared, noisy
 * machine slows all of them alike and the ratios stay meaningful; absolute times do not transfer between
 * machines. Each figure is the median of the rounds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_adaptive.h"
#include "bench_fit.h"
#include "bench_md.h"
#include "bench_realtime.h"
#include "bench_blur.h"
#include "bench_tdense.h"
#include "bench_util.h"
#include "cli.h"
#include "clock.h"
#include "fileio.h"
#include "hz/hz.h"
#include "hz/crc32.h"
#include "hz/image.h"
#include "hz/tileorder.h"
#include "opttab.h"
#include "pools.h"

#include "bench_accel.h"
#include "bench_transp.h"
#include "bench_motion.h"

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

/* CRC-32 over a 1 MiB buffer (the loader checks every section of a scene file with it). */
static double bench_crc32(uint32_t n)
{
    static uint8_t buf[1 << 20];
    for (size_t i = 0; i < sizeof buf; i++)
        buf[i] = (uint8_t)(i * 131u + 7u);
    int64_t t0 = hz_clock_ns();
    uint32_t crc = 0;
    for (uint32_t done = 0; done < n; done += (uint32_t)sizeof buf)
        crc = hz_crc32(crc, buf, sizeof buf);
    sink += crc;
    return n / ((hz_clock_ns() - t0) * 1e-9);
}

/* ĝ with the paper's full rule (length fraction, CORDIC angle, random band) on motions of up to 8 px in every
 * direction: what each tile of a moving image costs once every four frames. */
static double bench_ghat(uint32_t n)
{
    hz_rng_t r;
    hz_rng_seed(&r, 9, 9);
    enum { M = 4096 };
    static hz_q16_t mv[2 * M];
    for (uint32_t i = 0; i < 2 * M; i++)
        mv[i] = (hz_q16_t)(hz_rng_u32(&r) & 0xfffffu) - (hz_q16_t)0x80000; /* [-8, 8) px in Q16.16 */
    int64_t t0 = hz_clock_ns();
    uint32_t acc = 0;
    for (uint32_t i = 0; i < n; i++)
        acc += (uint32_t)hz_tileorder_ghat(mv[2 * (i % M)], mv[2 * (i % M) + 1], hz_hash32(i), HZ_GHAT_FULL);
    sink += acc;
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

/* --md without a group's CSV path: the CSV goes next to the Markdown file, named after the group. */
static const char *csv_beside(const char *given, const char *md, const char *name, char *buf, size_t size)
{
    if (given || !md)
        return given;
    const char *slash = strrchr(md, '/');
    snprintf(buf, size, "%.*s%s.csv", slash ? (int)(slash - md + 1) : 0, md, name);
    return buf;
}

typedef struct md_section {
    bool ran;
    const char *title;  /* "## title" */
    char what[640];     /* what the table measures, how */
    const char *csv;
    hz_bench_md_spec_t spec[4];
    const char *sub[4]; /* a heading per table when a section has several */
    int tables;
} md_section_t;

/* The Markdown report: the command, then one section per group that ran, each table read back from its CSV. */
static int write_md(const char *path, int argc, char **argv, const md_section_t *sec, int n)
{
    hz_out_t out;
    hz_error_t err;
    if (hz_out_open(&out, path, &err) != HZ_OK)
        return hz_cli_report(&err);
    fputs("# hzbench\n\n`hzbench", out.f);
    for (int i = 1; i < argc; i++)
        fprintf(out.f, " %s", argv[i]);
    fputs("`: every figure of a group comes from one run, its rounds interleaved, so ratios within a group are the "
          "result; absolute times depend on the machine and its load.\n", out.f);
    for (int k = 0; k < n; k++) {
        if (!sec[k].ran)
            continue;
        fprintf(out.f, "\n## %s\n\n%s (`%s`)\n", sec[k].title, sec[k].what, sec[k].csv);
        for (int t = 0; t < sec[k].tables; t++) {
            fputc('\n', out.f);
            if (sec[k].sub[t])
                fprintf(out.f, "%s\n\n", sec[k].sub[t]);
            if (hz_bench_md_csv(out.f, sec[k].csv, &sec[k].spec[t], &err) != HZ_OK) {
                hz_out_abort(&out);
                return hz_cli_report(&err);
            }
        }
    }
    if (hz_out_commit(&out, &err) != HZ_OK)
        return hz_cli_report(&err);
    printf("wrote %s\n", path);
    return 0;
}

/* The per-frame time curve along a smoke scene's path, every method (seed 004, Fig. 12): next to the
 * transparency CSV X.csv, X-frames.csv (frame, t_s, then one column of ms per method) and X-frames.svg for the
 * group's first scene (sponza-smoke), X-<scene>-frames.csv and .svg for the others. */
static hz_status_t write_curve(const char *csv, const char *scene, const hz_bench_transp_row_t *rows, int n,
                               hz_error_t *err)
{
    const bool first = !strcmp(scene, hz_bench_transp_scenes[0][0]);
    char base[4096], path[4200];
    size_t len = strlen(csv);
    if (len >= sizeof base)
        return hz_error_set(err, HZ_E_INVALID_ARG, "--transparency-csv: path too long");
    memcpy(base, csv, len + 1);
    if (len > 4 && !strcmp(base + len - 4, ".csv"))
        base[len - 4] = 0;
    hz_out_t out;
    snprintf(path, sizeof path, "%s%s%s-frames.csv", base, first ? "" : "-", first ? "" : scene);
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    fprintf(out.f, "frame,t_s");
    for (int k = 0; k < n; k++)
        fprintf(out.f, ",%s", rows[k].method);
    fprintf(out.f, "\n");
    double hi = 0.0;
    for (uint32_t i = 0; i < rows[0].frames; i++) {
        fprintf(out.f, "%u,%.3f", i, rows[0].t_s[i]);
        for (int k = 0; k < n; k++) {
            fprintf(out.f, ",%.3f", rows[k].frame_ms[i]);
            hi = rows[k].frame_ms[i] > hi ? rows[k].frame_ms[i] : hi;
        }
        fprintf(out.f, "\n");
    }
    if ((s = hz_out_commit(&out, err)) != HZ_OK)
        return s;
    printf("wrote %s\n", path);
    snprintf(path, sizeof path, "%s%s%s-frames.svg", base, first ? "" : "-", first ? "" : scene);
    if ((s = hz_out_open(&out, path, err)) != HZ_OK)
        return s;
    static const char *const colour[] = { "#000000", "#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                          "#8c564b", "#e377c2", "#ff7f0e" };
    const int W = 720, H = 400, L = 60, R = 170, T = 20, B = 40;
    const uint32_t nf = rows[0].frames;
    double tmax = nf > 1 ? rows[0].t_s[nf - 1] : 1.0;
    tmax = tmax > 0.0 ? tmax : 1.0;
    hi = hi > 0.0 ? hi * 1.05 : 1.0;
    fprintf(out.f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
                   "font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            W, H, W, H);
    fprintf(out.f, "<text x=\"%d\" y=\"14\">frame time along %s's camera path (ms, min over rounds)</text>\n", L,
            scene);
    fprintf(out.f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, H - B, W - R, H - B);
    fprintf(out.f, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T, L, H - B);
    for (int g = 0; g <= 4; g++) {
        double v = hi * g / 4.0;
        int y = H - B - (int)((H - B - T) * g / 4.0);
        fprintf(out.f, "<text x=\"%d\" y=\"%d\" text-anchor=\"end\">%.0f</text>\n", L - 4, y + 4, v);
        double tv = tmax * g / 4.0;
        int x = L + (int)((W - R - L) * g / 4.0);
        fprintf(out.f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%.1f s</text>\n", x, H - B + 16, tv);
    }
    for (int k = 0; k < n; k++) {
        const char *c = colour[k % 8];
        fprintf(out.f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"1.5\" points=\"", c);
        for (uint32_t i = 0; i < nf; i++)
            fprintf(out.f, "%.1f,%.1f ", L + (W - R - L) * rows[k].t_s[i] / tmax,
                    H - B - (H - B - T) * rows[k].frame_ms[i] / hi);
        fprintf(out.f, "\"/>\n<text x=\"%d\" y=\"%d\" fill=\"%s\">%s</text>\n", W - R + 8, T + 14 * (k + 1), c,
                rows[k].method);
    }
    fprintf(out.f, "</svg>\n");
    if ((s = hz_out_commit(&out, err)) != HZ_OK)
        return s;
    printf("wrote %s\n", path);
    return HZ_OK;
}

#define STR_(x) #x
#define STR(x) STR_(x)

/* The command line (opttab.h): the help is printed from this table. */
enum { B_ONLY, B_CSV, B_MD, B_SCENES, B_ROUNDS, B_THREADS, B_RT_CSV, B_RT_SIZE, B_RT_FRAMES, B_RT_TWIN, B_RT_SCALING,
       B_TD_SIZE, B_FRAMES, B_TP_CSV, B_TP_SIZE, B_TP_FRAMES, B_AD_CSV, B_AD_SIZE, B_SHUTTER, B_BLUR_SIZE, B_ACCEL_CSV, B_SCENE,
       B_SIZE, B_EMBREE, B_MO_CSV, B_MO_SCENE, B_MO_SIZE, B_MO_INTERVAL, B_MO_BUDGET, B_MO_SWEEP, B_MO_LEAF, B_CHECK_FIT };

static const char *const group_words[] = { "kernels", "accel", "tdense", "transparency", "adaptive", "blur", "motion",
                                           "realtime", NULL };

static const hz_opt_t options[] = {
    { .name = "--help", .alias = "-h", .kind = HZ_OPT_FLAG, .id = HZ_OPT_ID_HELP, .help = "this text" },
    { .name = "--only", .arg = "G", .kind = HZ_OPT_WORD, .words = group_words, .id = B_ONLY,
      .help = "run only this group (kernels, accel, tdense, transparency, adaptive, blur, motion or realtime); "
              "repeat for more; default every group" },
    { .name = "--check-fit", .kind = HZ_OPT_FLAG, .id = B_CHECK_FIT,
      .help = "measure nothing: check that every scene of the groups fits the board's arenas as the group uses it "
              "(its native build's bound, its renderers' plans, its pose keys) and exit 66 if one does not" },
    { .name = "--csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_CSV, .help = "the kernels' table as CSV" },
    { .name = "--md", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_MD,
      .help = "also every group's table in Markdown (a group without its --*-csv writes its CSV next to FILE: "
              "bench.csv, accel.csv, transparency.csv, adaptive.csv, motion.csv, realtime.csv)" },
    { .name = "--scenes", .arg = "DIR", .kind = HZ_OPT_TEXT, .id = B_SCENES,
      .help = "the baked scenes (default $HZ_SCENES_DIR or build/scenes; `make scenes` bakes them)" },
    { .name = "--rounds", .arg = "N", .kind = HZ_OPT_INT, .lo = 1,
      .hi = HZ_BENCH_TDENSE_MAX_ROUNDS < 15 ? HZ_BENCH_TDENSE_MAX_ROUNDS : 15, .id = B_ROUNDS,
      .help = "rounds of the scene groups (default 5; realtime takes at most " STR(HZ_BENCH_REALTIME_MAX_ROUNDS) ")" },
    { .name = "--threads", .arg = "N", .kind = HZ_OPT_INT, .lo = 0, .hi = HZ_MAX_THREADS, .id = B_THREADS,
      .help = "pool size (0: every CPU; adaptive and realtime default to 2)" },
    { .section = "realtime", .name = "--realtime-csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_RT_CSV,
      .help = "its table as CSV" },
    { .name = "--realtime-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 16, .hi = 8192, .id = B_RT_SIZE,
      .help = "frame size (default 640x360)" },
    { .name = "--realtime-frames", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = HZ_BENCH_REALTIME_MAX_FRAMES,
      .id = B_RT_FRAMES, .help = "timed frames (default 96)" },
    { .name = "--realtime-shading-twin", .kind = HZ_OPT_FLAG, .id = B_RT_TWIN,
      .help = "tdense with the packet shading against its scalar twin instead of tdense and TAA" },
    { .name = "--realtime-scaling", .kind = HZ_OPT_FLAG, .id = B_RT_SCALING,
      .help = "the table again on 1 thread, and each row's speedup and efficiency" },
    { .section = "tdense", .name = "--tdense-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 16, .hi = 8192,
      .id = B_TD_SIZE, .help = "frame size (default 640x360)" },
    { .name = "--frames", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = 1000, .id = B_FRAMES,
      .help = "timed frames (default 12)" },
    { .section = "transparency", .name = "--transparency-csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_TP_CSV,
      .help = "its table as CSV" },
    { .name = "--transparency-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 8, .hi = 8192, .id = B_TP_SIZE,
      .help = "frame size (default 192x108)" },
    { .name = "--transparency-frames", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = HZ_BENCH_TRANSP_MAX_FRAMES,
      .id = B_TP_FRAMES, .help = "frames along the camera path (default 24)" },
    { .section = "adaptive", .name = "--adaptive-csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_AD_CSV,
      .help = "its table as CSV" },
    { .name = "--adaptive-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 8, .hi = 8192, .id = B_AD_SIZE,
      .help = "frame size (default 640x360; seed 003 measured at 1024x1024)" },
    { .section = "blur", .name = "--shutter", .arg = "S", .kind = HZ_OPT_REAL, .lo = 0, .hi = 1, .lo_open = true,
      .noun = "a fraction", .id = B_SHUTTER, .help = "the shutter's share of the frame interval (default 1)" },
    { .name = "--blur-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 16, .hi = 8192, .id = B_BLUR_SIZE,
      .help = "frame size (default 320x180)" },
    { .section = "accel", .name = "--accel-csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_ACCEL_CSV,
      .help = "its table as CSV" },
    { .name = "--scene", .arg = "NAME", .kind = HZ_OPT_TEXT, .id = B_SCENE,
      .help = "a baked scene to measure; repeat for more (at most " STR(HZ_BENCH_MAX_SCENES) "; default conference "
              "sponza lost-empire furball dragon-res4 dragon-res3 dragon-res2 dragon)" },
    { .name = "--size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 8, .hi = 8192, .id = B_SIZE,
      .help = "the primary rays (default 1024x1024)" },
    { .name = "--embree-config", .arg = "S", .kind = HZ_OPT_TEXT, .id = B_EMBREE, .help = "Embree's device config" },
    { .section = "motion", .name = "--motion-csv", .arg = "FILE", .kind = HZ_OPT_TEXT, .id = B_MO_CSV,
      .help = "its table as CSV" },
    { .name = "--motion-scene", .arg = "NAME", .kind = HZ_OPT_TEXT, .id = B_MO_SCENE,
      .help = "a baked scene to measure; repeat for more (at most " STR(HZ_BENCH_MOTION_MAX_SCENES) "; default the "
              "moving hairball, the rotated Sponza and the swaying furball)" },
    { .name = "--motion-size", .arg = "WxH", .kind = HZ_OPT_SIZE, .lo = 8, .hi = 8192, .id = B_MO_SIZE,
      .help = "frame size (default 512x512)" },
    { .name = "--motion-interval", .arg = "S", .kind = HZ_OPT_REAL, .lo = 0, .hi = 10, .lo_open = true,
      .noun = "a number of seconds", .id = B_MO_INTERVAL, .help = "the shutter interval (default 1/24 s)" },
    { .name = "--motion-budget", .arg = "B", .kind = HZ_OPT_REAL, .lo = 0, .hi = HZ_ACCEL_SPLIT_BUDGET_MAX,
      .noun = "a fraction of the triangles", .id = B_MO_BUDGET,
      .help = "an MSBVH split budget to measure; repeat for more (at most " STR(HZ_BENCH_MOTION_MAX_BUDGETS) "; "
              "default 0.25 0.5 1 4, the largest standing for unbounded where it stops no split)" },
    { .name = "--motion-leaf", .arg = "N", .kind = HZ_OPT_INT, .lo = 1, .hi = HZ_BVH_WIDTH, .id = B_MO_LEAF,
      .help = "triangles per leaf of every native motion BVH (default " STR(HZ_BVH_WIDTH) ", the SIMD width; seed "
              "002's trees held about 3 to 4)" },
    { .name = "--motion-sweep", .arg = "NAME", .kind = HZ_OPT_TEXT, .id = B_MO_SWEEP,
      .help = "the scene of the leaf sizes (msbvh and interp with leaves of 2, 4 and the default number of "
              "triangles) and of the motion-size sweep: its shutter interval scaled 1/8x to 8x, intersections of the "
              "msbvh (largest budget) and the swept BVH against the interpolated one over motion per triangle size "
              "(default the hairball when it is measured; none: neither)" },
};

static const hz_opt_prog_t program = {
    .name = "hzbench",
    .table = options,
    .n = sizeof options / sizeof options[0],
    .synopsis =
        "usage: hzbench [options]\n"
        "\nMeasures hzrt's kernels side by side and prints medians of interleaved rounds, in these groups\n"
        "(all by default, or those --only names):\n"
        "  kernels  core kernels (" STR(ROUNDS) " rounds)\n"
        "  tdense   displayed-frame time of tdense against full-frame 1 spp + TAA on the built-in scene\n"
        "           and sponza/conference\n"
        "  transparency  per-frame time along the camera paths of sponza-smoke and smoke-column of exact, rr,\n"
        "           std, dtaa and hybrid:0.25/0.5/0.75 with TAA (min over 3 rounds)\n"
        "  realtime tdense and TAA on 2 threads (or --threads) on the built-in scene, Sponza and Conference,\n"
        "           frames from t = 1 s: p50/p99 ms, begin/trace/shade/resolve, the same rays through Embree\n"
        "           alone (8-ray packets, no shading) and overhead = p50 / that; with --realtime-scaling the\n"
        "           speedup over 1 thread and efficiency = p50 on 1 thread / (threads x p50) (the goal is\n"
        "           >= 85% at 16 threads)\n"
        "  adaptive fixed 9 spp against --mode adaptive (tau 0.3, 0.6, 1, and 1 focused on the objects at\n"
        "           the centre of the view) at 640x360 (or --adaptive-size) on 2 threads (or --threads):\n"
        "           presample / test / extra ms, live lanes per packet, PSNR vs 256 spp, also over the focus\n"
        "           objects' pixels\n"
        "  blur     motion blur in tdense: one MSBVH key interval and refit per 4-subframe cycle against\n"
        "           posing and refitting every subframe, on the built-in scene, sponza-rotated and furball-sway\n"
        "  accel    native BVH against Embree on the baked scenes\n"
        "  motion   motion-blur BVHs (seed 002: msbvh, interp, swept) against Embree's motion blur\n"
        "\noptions (a group's own under its name):\n",
};

typedef struct args {
    const char *csv_path, *md_path, *realtime_csv, *transp_csv;
    bool core, accel, tdense, transp, adaptive, blur, motion, realtime, only_given, realtime_scaling, check_fit;
    hz_bench_realtime_opts_t rt;
    hz_bench_transp_opts_t tp;
    hz_bench_adaptive_opts_t ad;
    hz_bench_blur_opts_t bo;
    hz_bench_accel_opts_t ao;
    hz_bench_motion_opts_t mo;
    hz_bench_tdense_opts_t td;
} args_t;

static int take(void *ctx, const hz_opt_t *o, const hz_opt_val_t *v)
{
    args_t *a = ctx;
    switch (o->id) {
    case B_ONLY: {
        if (!a->only_given)
            a->core = a->accel = a->tdense = a->transp = a->adaptive = a->blur = a->motion = a->realtime = false;
        a->only_given = true;
        bool *group[] = { &a->core, &a->accel, &a->tdense, &a->transp, &a->adaptive, &a->blur, &a->motion,
                          &a->realtime };
        *group[v->w] = true;
        break;
    }
    case B_CSV: a->csv_path = v->s; break;
    case B_CHECK_FIT: a->check_fit = true; break;
    case B_MD: a->md_path = v->s; break;
    case B_SCENES:
        a->ao.scenes_dir = a->td.scenes_dir = a->tp.scenes_dir = a->ad.scenes_dir = a->bo.scenes_dir =
            a->mo.scenes_dir = a->rt.scenes_dir = v->s;
        break;
    case B_ROUNDS:
        a->ao.rounds = a->td.rounds = a->tp.rounds = a->ad.rounds = a->bo.rounds = a->mo.rounds = (int)v->n;
        a->rt.rounds = v->n < HZ_BENCH_REALTIME_MAX_ROUNDS ? (int)v->n : HZ_BENCH_REALTIME_MAX_ROUNDS;
        break;
    case B_THREADS:
        a->ao.threads = a->td.threads = a->tp.threads = a->bo.threads = (int)v->n;
        a->ad.threads = a->rt.threads = v->n ? (int)v->n : 2;
        break;
    case B_RT_CSV: a->realtime_csv = v->s; break;
    case B_RT_SIZE: a->rt.width = (uint32_t)v->w, a->rt.height = (uint32_t)v->h; break;
    case B_RT_FRAMES: a->rt.frames = (uint32_t)v->n; break;
    case B_RT_TWIN: a->rt.compare_shading = true; break;
    case B_RT_SCALING: a->realtime_scaling = true; break;
    case B_TD_SIZE: a->td.width = (uint32_t)v->w, a->td.height = (uint32_t)v->h; break;
    case B_FRAMES: a->td.frames = (uint32_t)v->n; break;
    case B_TP_CSV: a->transp_csv = v->s; break;
    case B_TP_SIZE: a->tp.width = (uint32_t)v->w, a->tp.height = (uint32_t)v->h; break;
    case B_TP_FRAMES: a->tp.frames = (uint32_t)v->n; break;
    case B_AD_CSV: a->ad.csv_path = v->s; break;
    case B_AD_SIZE: a->ad.width = (uint32_t)v->w, a->ad.height = (uint32_t)v->h; break;
    case B_SHUTTER: a->bo.shutter = (float)v->x; break;
    case B_BLUR_SIZE: a->bo.width = (uint32_t)v->w, a->bo.height = (uint32_t)v->h; break;
    case B_ACCEL_CSV: a->ao.csv_path = v->s; break;
    case B_SCENE:
        if (a->ao.scene_count == HZ_BENCH_MAX_SCENES) {
            hz_cli_error("--scene: at most %d scenes", HZ_BENCH_MAX_SCENES);
            return HZ_EXIT_USAGE;
        }
        a->ao.scenes[a->ao.scene_count++] = v->s;
        break;
    case B_SIZE: a->ao.width = (uint32_t)v->w, a->ao.height = (uint32_t)v->h; break;
    case B_EMBREE: a->ao.embree_config = v->s; break;
    case B_MO_CSV: a->mo.csv_path = v->s; break;
    case B_MO_SCENE:
        if (a->mo.scene_count == HZ_BENCH_MOTION_MAX_SCENES) {
            hz_cli_error("--motion-scene: at most %d scenes", HZ_BENCH_MOTION_MAX_SCENES);
            return HZ_EXIT_USAGE;
        }
        a->mo.scenes[a->mo.scene_count++] = v->s;
        break;
    case B_MO_SIZE: a->mo.width = (uint32_t)v->w, a->mo.height = (uint32_t)v->h; break;
    case B_MO_INTERVAL: a->mo.interval = (float)v->x; break;
    case B_MO_SWEEP: a->mo.sweep_scene = v->s; break;
    case B_MO_LEAF: a->mo.leaf_max = (uint32_t)v->n; break;
    case B_MO_BUDGET:
        if (a->mo.budget_count == HZ_BENCH_MOTION_MAX_BUDGETS) {
            hz_cli_error("--motion-budget: at most %d budgets", HZ_BENCH_MOTION_MAX_BUDGETS);
            return HZ_EXIT_USAGE;
        }
        a->mo.budgets[a->mo.budget_count++] = (float)v->x;
        break;
    }
    return 0;
}

/* --check-fit (bench_fit.h): each selected group's scenes against the board's arenas, nothing measured. */
static int check_fit(const args_t *a)
{
    hz_bench_fit_t fit = { a->td.scenes_dir, 0, 0 };
    if (!fit.scenes_dir)
        fit.scenes_dir = getenv("HZ_SCENES_DIR") ? getenv("HZ_SCENES_DIR") : "build/scenes";
    printf("fit: the scenes of every group against board %s's arenas (%s)\n", HZ_BOARD_NAME, fit.scenes_dir);
    printf("fit: native builds by their bound; Embree's builds take what they need from the accel arena's free bytes "
           "as they build (not bounded beforehand, not checked here)\n");
    if (a->accel)
        hz_bench_accel_fit(&a->ao, &fit);
    if (a->tdense)
        hz_bench_tdense_fit(&a->td, &fit);
    if (a->transp)
        hz_bench_transp_fit(&a->tp, &fit);
    if (a->adaptive)
        hz_bench_adaptive_fit(&a->ad, &fit);
    if (a->blur)
        hz_bench_blur_fit(&a->bo, &fit);
    if (a->motion)
        hz_bench_motion_fit(&a->mo, &fit);
    if (a->realtime)
        hz_bench_realtime_fit(&a->rt, &fit);
    printf("fit: %d checks, %d do not fit\n", fit.checked, fit.failed);
    if (fit.failed)
        hz_cli_error("%d of %d checks fail on board %s's arenas (the lines marked above)", fit.failed, fit.checked,
                     HZ_BOARD_NAME);
    return fit.failed ? hz_status_exit_code(HZ_E_NO_MEMORY) : 0;
}

int main(int argc, char **argv)
{
    hz_cli_prog = "hzbench";
    static args_t a = { .core = true, .accel = true, .tdense = true, .transp = true, .adaptive = true,
                        .blur = true, .motion = true, .realtime = true,
                        .rt = { NULL, 640, 360, 2, 3, 8, 96, 1.0f, 240, false, false },
                        .tp = { .width = 192, .height = 108, .rounds = 3, .frames = 24 },
                        .ad = { NULL, NULL, 640, 360, 2, 5, 1, 3, 1.0f, 256, false },
                        .bo = { NULL, 320, 180, 0, 5, 4, 12, 1.0f, 1.0f, 240, HZ_ACCEL_BLUR_MSBVH, false },
                        .td = { NULL, 640, 360, 0, 5, 4, 12, 1.0f, 240, false } };
    int nops = 0;
    int rc = hz_opt_parse(&program, argc, argv, take, &a, NULL, &nops);
    if (rc)
        return rc == HZ_OPT_DONE ? 0 : rc;
    if (!hz_pools_get()) { /* every group measures in the board's arenas */
        hz_error_t err;
        hz_pools_error(&err, "board");
        return hz_cli_report(&err);
    }
    if (a.check_fit)
        return check_fit(&a);
    const char *csv_path = a.csv_path, *md_path = a.md_path, *realtime_csv = a.realtime_csv;
    const char *transp_csv = a.transp_csv;
    bool core = a.core, accel = a.accel, tdense = a.tdense, transp = a.transp, adaptive = a.adaptive, blur = a.blur;
    bool motion = a.motion, realtime = a.realtime, realtime_scaling = a.realtime_scaling;
    hz_bench_realtime_opts_t rt = a.rt;
    hz_bench_transp_opts_t tp = a.tp;
    hz_bench_adaptive_opts_t ad = a.ad;
    hz_bench_blur_opts_t bo = a.bo;
    hz_bench_accel_opts_t ao = a.ao;
    hz_bench_motion_opts_t mo = a.mo;
    hz_bench_tdense_opts_t td = a.td;
    char csv_buf[6][4200];
    csv_path = csv_beside(csv_path, md_path, "bench", csv_buf[0], sizeof csv_buf[0]);
    ao.csv_path = csv_beside(ao.csv_path, md_path, "accel", csv_buf[1], sizeof csv_buf[1]);
    transp_csv = csv_beside(transp_csv, md_path, "transparency", csv_buf[2], sizeof csv_buf[2]);
    ad.csv_path = csv_beside(ad.csv_path, md_path, "adaptive", csv_buf[3], sizeof csv_buf[3]);
    mo.csv_path = csv_beside(mo.csv_path, md_path, "motion", csv_buf[4], sizeof csv_buf[4]);
    realtime_csv = csv_beside(realtime_csv, md_path, "realtime", csv_buf[5], sizeof csv_buf[5]);
    row_t rows[] = {
        { "core", "hash32 (murmur3 fmix)", "Mops/s", { 0 }, 0 },
        { "core", "hash_pcg", "Mops/s", { 0 }, 0 },
        { "core", "rng_u32 (pcg32)", "Mops/s", { 0 }, 0 },
        { "core", "arena_alloc 48 B", "Mops/s", { 0 }, 0 },
        { "core", "crc32 (slicing by 8)", "MB/s", { 0 }, 0 },
        { "image", "srgb8 encode, exact table", "Mvalues/s", { 0 }, 0 },
        { "image", "srgb8 encode, powf formula", "Mvalues/s", { 0 }, 0 },
        { "pattern", "tile ordering (full ghat)", "Mtiles/s", { 0 }, 0 },
    };
    double (*fns[])(uint32_t) = { bench_hash, bench_hash_pcg, bench_rng, bench_arena, bench_crc32, bench_srgb8_table,
                                  bench_srgb8_powf, bench_ghat };
    size_t nrows = core ? HZ_ARRAY_LEN(rows) : 0;
    const uint32_t n = 1u << 24;
    for (int r = 0; r < ROUNDS; r++)
        for (size_t k = 0; k < nrows; k++)
            rows[k].per_sec[r] = fns[k](n) * 1e-6;
    if (nrows)
        printf("%-8s %-28s %12s %s\n", "group", "kernel", "median", "unit");
    for (size_t k = 0; k < nrows; k++) {
        qsort(rows[k].per_sec, ROUNDS, sizeof(double), cmp_double);
        rows[k].median = rows[k].per_sec[ROUNDS / 2];
        printf("%-8s %-28s %12.1f %s\n", rows[k].group, rows[k].name, rows[k].median, rows[k].unit);
    }

    hz_bench_tdense_row_t trows[8];
    int nt = 0;
    if (tdense) {
        hz_error_t err;
        td.progress = hz_cli_stderr_is_tty();
        td.threads = hz_bench_threads(td.threads);
        printf("\ntdense vs full-frame 1 spp + TAA: %ux%u, %d threads, %u frames after %u from t = %.1f s at %u Hz, "
               "median of %d rounds\n", td.width, td.height, td.threads, td.frames, td.warm, td.start, td.hz,
               td.rounds);
        nt = hz_bench_tdense(&td, trows, 8, &err);
        if (nt < 0)
            return hz_cli_report(&err);
        printf("%-12s %12s %12s %8s %15s %14s %14s\n", "scene", "tdense ms", "taa ms", "ratio", "ratio min..max",
               "tdense rays", "taa rays");
        for (int k = 0; k < nt; k++)
            printf("%-12s %12.2f %12.2f %7.2fx %7.2f..%-7.2f %14.0f %14.0f\n", trows[k].scene, trows[k].tdense_ms,
                   trows[k].taa_ms, trows[k].ratio, trows[k].ratio_min, trows[k].ratio_max, trows[k].tdense_rays,
                   trows[k].taa_rays);
        printf("parts of a frame, ms (begin: animation + refit + camera; trace pass; resolve pass):\n");
        printf("%-12s %8s %8s %8s   %8s %8s %8s   %s\n", "scene", "td begin", "trace", "resolve", "taa begin",
               "trace", "resolve", "trace ratio");
        for (int k = 0; k < nt; k++) {
            const hz_bench_tdense_row_t *t = &trows[k];
            printf("%-12s %8.2f %8.2f %8.2f   %8.2f %8.2f %8.2f   %.2fx\n", t->scene, t->part_ms[0][0],
                   t->part_ms[0][1], t->part_ms[0][2], t->part_ms[1][0], t->part_ms[1][1], t->part_ms[1][2],
                   t->part_ms[1][1] / t->part_ms[0][1]);
        }
        printf("(seed 001 reports about 3.5x at 1920x1080 on an RTX 2080 Ti)\n");
    }
    if (transp) {
        hz_error_t err;
        static hz_bench_transp_row_t prow[HZ_BENCH_TRANSP_SCENES * HZ_BENCH_TRANSP_METHODS];
        int np = 0, per[HZ_BENCH_TRANSP_SCENES] = { 0 };
        tp.progress = hz_cli_stderr_is_tty();
        if (tp.threads == 0) {
            long c = sysconf(_SC_NPROCESSORS_ONLN);
            tp.threads = c < 1 ? 1 : c > HZ_MAX_THREADS ? HZ_MAX_THREADS : (int)c;
        }
        for (int sc = 0; sc < HZ_BENCH_TRANSP_SCENES; sc++) {
            hz_bench_transp_row_t *rows = prow + np;
            tp.scene = hz_bench_transp_scenes[sc];
            printf("\ntransparency (seed 004) on %s with TAA: %ux%u, %d threads, %u frames along the camera path, "
                   "min of %d rounds per frame\n", tp.scene[0], tp.width, tp.height, tp.threads, tp.frames, tp.rounds);
            const int n = hz_bench_transp(&tp, rows, &err);
            if (n < 0)
                return hz_cli_report(&err);
            per[sc] = n, np += n;
            if (n == 0)
                continue;
            printf("%-16s %10s %10s %8s %14s %12s %12s\n", "method", "p50 ms", "p99 ms", "p99/p50", "rays/frame",
                   "exact/p50", "exact/p99");
            for (int k = 0; k < n; k++)
                printf("%-16s %10.2f %10.2f %8.3f %14.0f %11.2fx %11.2fx\n", rows[k].method, rows[k].p50_ms,
                       rows[k].p99_ms, rows[k].p99_ms / rows[k].p50_ms, rows[k].rays_per_frame,
                       rows[0].p50_ms / rows[k].p50_ms, rows[0].p99_ms / rows[k].p99_ms);
            printf("(goal, seed 004: std >= 3x exact at p50, std p99/p50 <= 1.15)\n");
            printf("%-12s %16s %10s   (the any-hit decision on every blended triangle, both sides, after the last "
                   "frame)\n", "method", "ns/rejected layer", "rejected");
            for (int k = 0; k < n; k++)
                if (rows[k].reject_share > 0.0)
                    printf("%-12s %16.1f %9.0f%%\n", rows[k].method, rows[k].reject_ns, 100.0 * rows[k].reject_share);
        }
        if (np > 0) {
            double lns = 0.0, lsh = 0.0;
            if (hz_bench_transp_layers("builtin", HZ_TRANSP_STD, tp.width, tp.height, &lns, &lsh, &err) != HZ_OK)
                return hz_cli_report(&err);
            printf("%-12s %16.1f %9.0f%%   (the built-in scene's untextured particles: alpha from the material)\n",
                   "std builtin", lns, 100.0 * lsh);
        }
        if (transp_csv && np > 0) {
            hz_out_t out;
            if (hz_out_open(&out, transp_csv, &err) != HZ_OK)
                return hz_cli_report(&err);
            fprintf(out.f, "scene,method,frames,p50_ms,p99_ms,rays_per_frame,reject_ns,reject_share\n");
            for (int k = 0; k < np; k++)
                fprintf(out.f, "%s,%s,%u,%.3f,%.3f,%.0f,%.2f,%.4f\n", prow[k].scene, prow[k].method, prow[k].frames,
                        prow[k].p50_ms, prow[k].p99_ms, prow[k].rays_per_frame, prow[k].reject_ns,
                        prow[k].reject_share);
            if (hz_out_commit(&out, &err) != HZ_OK)
                return hz_cli_report(&err);
            printf("wrote %s\n", transp_csv);
            for (int sc = 0, k = 0; sc < HZ_BENCH_TRANSP_SCENES; k += per[sc++])
                if (per[sc] > 0 &&
                    write_curve(transp_csv, hz_bench_transp_scenes[sc][0], prow + k, per[sc], &err) != HZ_OK)
                    return hz_cli_report(&err);
        }
    }
    hz_bench_blur_row_t brows[4];
    int nb = 0;
    if (blur) {
        hz_error_t err;
        bo.progress = hz_cli_stderr_is_tty();
        bo.threads = hz_bench_threads(bo.threads);
        printf("\nmotion blur in tdense, shutter %.2f: one key interval per 4-subframe cycle vs per subframe (%s); "
               "%ux%u, %d threads, %u frames after %u from t = %.1f s at %u Hz, median of %d rounds\n",
               (double)bo.shutter, hz_accel_blur_name(bo.blur), bo.width, bo.height, bo.threads, bo.frames, bo.warm,
               (double)bo.start, bo.hz, bo.rounds);
        nb = hz_bench_blur(&bo, brows, 4, &err);
        if (nb < 0)
            return hz_cli_report(&err);
        printf("%-14s %3s %10s %10s %7s %11s %11s %11s %11s %9s\n", "scene", "K", "cycle ms", "subfr ms",
               "ratio", "cycle begin", "subfr begin", "cycle trace", "subfr trace", "refits/f");
        for (int k = 0; k < nb; k++) {
            const hz_bench_blur_row_t *b = &brows[k];
            printf("%-14s %3u %10.2f %10.2f %6.2fx %11.2f %11.2f %11.2f %11.2f %4.2f/%4.2f\n", b->scene, b->time_keys,
                   b->ms[0], b->ms[1], b->ratio, b->begin_ms[0], b->begin_ms[1], b->trace_ms[0], b->trace_ms[1],
                   b->refits[0], b->refits[1]);
        }
    }
    if (csv_path) {
        hz_out_t out;
        hz_error_t err;
        if (hz_out_open(&out, csv_path, &err) != HZ_OK)
            return hz_cli_report(&err);
        fprintf(out.f, "group,kernel,median,min,max,unit\n");
        for (size_t k = 0; k < nrows; k++) /* quoted: some kernel names hold a comma */
            fprintf(out.f, "%s,\"%s\",%.3f,%.3f,%.3f,%s\n", rows[k].group, rows[k].name, rows[k].median,
                    rows[k].per_sec[0], rows[k].per_sec[ROUNDS - 1], rows[k].unit);
        for (int k = 0; k < nt; k++) {
            fprintf(out.f, "tdense,%s %ux%u tdense,%.3f,,,ms/frame\n", trows[k].scene, td.width, td.height,
                    trows[k].tdense_ms);
            fprintf(out.f, "tdense,%s %ux%u full 1 spp + taa,%.3f,,,ms/frame\n", trows[k].scene, td.width,
                    td.height, trows[k].taa_ms);
            fprintf(out.f, "tdense,%s %ux%u taa/tdense,%.3f,%.3f,%.3f,ratio\n", trows[k].scene, td.width, td.height,
                    trows[k].ratio, trows[k].ratio_min, trows[k].ratio_max);
            static const char *const part[3] = { "begin_frame", "trace pass", "resolve pass" };
            for (int m = 0; m < 2; m++)
                for (int q = 0; q < 3; q++)
                    fprintf(out.f, "tdense,%s %ux%u %s %s,%.3f,,,ms/frame\n", trows[k].scene, td.width, td.height,
                            m ? "full 1 spp + taa" : "tdense", part[q], trows[k].part_ms[m][q]);
        }
        for (int k = 0; k < nb; k++) {
            static const char *const how[2] = { "keys per cycle", "keys per subframe" };
            for (int m = 0; m < 2; m++) {
                fprintf(out.f, "blur,%s %ux%u tdense %s,%.3f,,,ms/frame\n", brows[k].scene, bo.width, bo.height,
                        how[m], brows[k].ms[m]);
                fprintf(out.f, "blur,%s %ux%u tdense %s begin_frame,%.3f,,,ms/frame\n", brows[k].scene, bo.width,
                        bo.height, how[m], brows[k].begin_ms[m]);
                fprintf(out.f, "blur,%s %ux%u tdense %s trace pass,%.3f,,,ms/frame\n", brows[k].scene, bo.width,
                        bo.height, how[m], brows[k].trace_ms[m]);
            }
            fprintf(out.f, "blur,%s %ux%u per subframe/per cycle,%.3f,,,ratio\n", brows[k].scene, bo.width,
                    bo.height, brows[k].ratio);
        }
        if (hz_out_commit(&out, &err) != HZ_OK)
            return hz_cli_report(&err);
        printf("wrote %s\n", csv_path);
    }
    if (realtime) {
        hz_error_t err;
        hz_bench_realtime_row_t rrows[6];
        rt.progress = hz_cli_stderr_is_tty();
        printf("\nreal time: %ux%u, %d threads, %u frames after %u from t = %.1f s at %u Hz, %d rounds; budget %.2f ms "
               "per frame at %u Hz\n", rt.width, rt.height, rt.threads, rt.frames, rt.warm, (double)rt.start, rt.hz,
               rt.rounds, 1000.0 / rt.hz, rt.hz);
        int nr = hz_bench_realtime(&rt, rrows, 6, &err);
        if (nr < 0)
            return hz_cli_report(&err);
        const int mw = rt.compare_shading ? 13 : 6;
        printf("%-11s %-*s %8s %8s %7s %7s %7s %8s %9s %8s %9s %9s %9s\n", "scene", mw, "mode", "p50 ms", "p99 ms",
               "begin", "trace", "shade", "resolve", "embree ms", "overhead", "primary", "shadow", "secondary");
        for (int k = 0; k < nr; k++) {
            const hz_bench_realtime_row_t *w = &rrows[k];
            printf("%-11s %-*s %8.2f %8.2f %7.2f %7.2f %7.2f %8.2f %9.2f %8.2f %9.0f %9.0f %9.0f\n", w->scene, mw,
                   w->mode, w->p50_ms, w->p99_ms, w->begin_ms, w->trace_ms, w->shade_ms, w->resolve_ms, w->embree_trace_ms,
                   w->overhead, w->primary, w->shadow, w->secondary);
        }
        for (int k = 0; rt.compare_shading && k + 1 < nr; k += 2)
            printf("%-11s scalar twin / packet shading: shade %.2fx, p50 %.2fx\n", rrows[k].scene,
                   rrows[k + 1].shade_ms / rrows[k].shade_ms, rrows[k + 1].p50_ms / rrows[k].p50_ms);
        for (int k = 0; !rt.compare_shading && k + 1 < nr; k += 2)
            printf("%-11s TAA / tdense p50 %.2fx; tdense p99 %.2f ms against the %.2f ms budget (%.1fx over)\n",
                   rrows[k].scene, rrows[k + 1].p50_ms / rrows[k].p50_ms, rrows[k].p99_ms, 1000.0 / rt.hz,
                   rrows[k].p99_ms * rt.hz / 1000.0);
        for (int k = 0; k < nr; k++)
            printf("%-11s %-6s resolve %.2f ms in SIMD lanes, %.2f ms with its scalar twin (%.2fx)\n", rrows[k].scene,
                   rrows[k].mode, rrows[k].resolve_ms, rrows[k].resolve_scalar_ms,
                   rrows[k].resolve_scalar_ms / rrows[k].resolve_ms);
        for (int k = 0; k < nr; k++)
            printf("%-11s %-6s p50 %.2f ms with trace and resolve overlapped, %.2f ms with a barrier between them "
                   "(%.2fx)\n", rrows[k].scene, rrows[k].mode, rrows[k].p50_ms, rrows[k].serial_p50_ms,
                   rrows[k].serial_p50_ms / rrows[k].p50_ms);
        printf("(goals: Sponza tdense p99 <= 4.17 ms on 2 cores, overhead <= 1.5, TAA / tdense >= 3.7x)\n");
        if (realtime_csv && nr > 0) {
            hz_out_t out;
            if (hz_out_open(&out, realtime_csv, &err) != HZ_OK)
                return hz_cli_report(&err);
            fprintf(out.f, "scene,threads,mode,p50_ms,p99_ms,begin_ms,trace_ms,shade_ms,resolve_ms,embree_trace_ms,"
                           "overhead\n");
            for (int k = 0; k < nr; k++) {
                const hz_bench_realtime_row_t *w = &rrows[k];
                fprintf(out.f, "%s,%d,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,", w->scene, w->threads, w->mode, w->p50_ms,
                        w->p99_ms, w->begin_ms, w->trace_ms, w->shade_ms, w->resolve_ms);
                if (isnan(w->embree_trace_ms))
                    fprintf(out.f, ",\n");
                else
                    fprintf(out.f, "%.3f,%.3f\n", w->embree_trace_ms, w->overhead);
            }
            if (hz_out_commit(&out, &err) != HZ_OK)
                return hz_cli_report(&err);
            printf("wrote %s\n", realtime_csv);
        }
        if (realtime_scaling && !rt.compare_shading && rt.threads > 1) {
            hz_bench_realtime_opts_t one = rt;
            hz_bench_realtime_row_t srows[6];
            one.threads = 1;
            printf("\nscaling: the same table on 1 thread against %d threads\n", rt.threads);
            int ns = hz_bench_realtime(&one, srows, 6, &err);
            if (ns < 0)
                return hz_cli_report(&err);
            for (int k = 0; k < ns && k < nr; k++)
                printf("%-11s %-6s p50 %.2f ms on 1 thread, %.2f ms on %d: speedup %.2fx, efficiency %.0f%%\n",
                       srows[k].scene, srows[k].mode, srows[k].p50_ms, rrows[k].p50_ms, rt.threads,
                       srows[k].p50_ms / rrows[k].p50_ms, 100.0 * srows[k].p50_ms / (rt.threads * rrows[k].p50_ms));
        } else if (realtime_scaling) {
            printf("--realtime-scaling: needs the table on 2 threads or more (--threads), without "
                   "--realtime-shading-twin\n");
        }
    }
    if (adaptive) {
        hz_error_t err;
        hz_bench_adaptive_row_t arows[HZ_BENCH_ADAPTIVE_MAX_ROWS];
        ad.progress = hz_cli_stderr_is_tty();
        printf("\nadaptive supersampling vs fixed 9 spp: %ux%u, %d threads, %u frames after %u at t = %.1f s, median of "
               "%d rounds; PSNR against %u spp\n", ad.width, ad.height, ad.threads, ad.frames, ad.warm, ad.t,
               ad.rounds, ad.ref_spp);
        int na = hz_bench_adaptive(&ad, arows, HZ_BENCH_ADAPTIVE_MAX_ROWS, &err);
        if (na < 0)
            return hz_cli_report(&err);
        printf("%-18s %-14s %5s %9s %9s %8s %9s %8s %7s %9s %8s %9s\n", "scene", "method", "tau", "ms", "presample",
               "test", "extra", "rays/px", "lanes", "PSNR dB", "vs 9spp", "focus dB");
        for (int k = 0; k < na; k++) {
            const hz_bench_adaptive_row_t *a = &arows[k];
            const hz_bench_adaptive_row_t *f9 = &arows[k - k % HZ_BENCH_ADAPTIVE_METHODS];
            if (k % HZ_BENCH_ADAPTIVE_METHODS == 0) {
                printf("%s focus objects:", a->scene);
                for (uint32_t i = 0; i < a->focus_count; i++)
                    printf("%s%u", i ? "," : " ", (unsigned)a->focus[i]);
                if (a->focus_count)
                    printf(" (%.1f%% of the frame)\n", 100.0 * a->focus_share);
                else
                    printf(" none (the centre of the frame shows only background): no focused row\n");
            }
            if (isnan(a->ms))
                continue;
            if (isnan(a->tau))
                printf("%-18s %-14s %5s %9.2f %9.2f %8s %9s %8.3f %7s %9.2f %8s %9.2f\n", a->scene, a->method, "",
                       a->ms, a->pass_ms[0], "", "", a->rays_per_pixel, "", a->psnr_srgb8_db, "1.00x",
                       a->focus_psnr_srgb8_db);
            else
                printf("%-18s %-14s %5.2f %9.2f %9.2f %8.2f %9.2f %8.3f %7.2f %9.2f %7.2fx %9.2f\n", a->scene,
                       a->method, a->tau, a->ms, a->pass_ms[0], a->pass_ms[1], a->pass_ms[2], a->rays_per_pixel,
                       a->lanes_per_packet, a->psnr_srgb8_db, a->ms / f9->ms, a->focus_psnr_srgb8_db);
        }
        printf("(vs 9spp: time against fixed 9 spp in the same run; seed 003 reports 2-3x faster at 1024x1024 on a "
               "GTX 280, 2.7x its fixed 9 spp's frame rate focused on one character; focus dB: PSNR over the pixels "
               "that show the focus objects)\n");
        if (ad.csv_path)
            printf("wrote %s\n", ad.csv_path);
    }
    bool motion_swept = false;
    int status = accel ? hz_bench_accel(&ao) : 0;
    if (status == 0 && motion)
        status = hz_bench_motion(&mo, &motion_swept);
    if (status != 0 || !md_path)
        return status;

    /* What each table measures: the group's settings as this run used them. */
    static const char *const core_groups[] = { "tdense", "blur", NULL }, *const tdense_group[] = { "tdense", NULL },
                             *const blur_group[] = { "blur", NULL }, *const primary[] = { "primary", NULL },
                             *const shadow[] = { "shadow", NULL }, *const diffuse[] = { "diffuse", NULL },
                             *const rays[] = { "primary", "shadow", "diffuse", NULL },
                             *const accel_keys[] = { "scene", "triangles", "threads", NULL },
                             *const other_keys[] = { "scene", "triangles", "what", "threads", NULL };
    md_section_t sec[10];
    memset(sec, 0, sizeof sec);
    sec[0] = (md_section_t){ core && nrows > 0, "Kernels", "", csv_path, { { "group", core_groups, true, 0, 0, 0 } },
                             { 0 }, 1 };
    snprintf(sec[0].what, sizeof sec[0].what, "Core kernels, throughput as the median of %d rounds: hashing, the "
             "arena, CRC-32, sRGB encoding (the exact table against the powf formula), the tdense tile ordering "
             "(hzbench --only kernels)", ROUNDS);
    sec[1] = (md_section_t){ tdense && nt > 0, "Temporally dense rendering (seed 001)", "", csv_path,
                             { { "group", tdense_group, false, 0, 0, 0 } }, { 0 }, 1 };
    snprintf(sec[1].what, sizeof sec[1].what, "Displayed-frame time of tdense against full-frame 1 spp + TAA on the "
             "same scene, %ux%u, %d threads, %u frames after %u from t = %.1f s at %u Hz, median of %d rounds "
             "interleaved; the ratio TAA / tdense per round (median, min, max) and each mode's begin_frame "
             "(animation, refit, camera), trace pass and resolve pass (hzbench --only tdense)", td.width, td.height,
             td.threads, td.frames, td.warm, (double)td.start, td.hz, td.rounds);
    sec[2] = (md_section_t){ transp && transp_csv, "Transparency (seed 004)", "", transp_csv, { { 0 } }, { 0 }, 1 };
    snprintf(sec[2].what, sizeof sec[2].what, "Per-frame time along the camera paths of sponza-smoke (flown into and "
             "through the cloud) and smoke-column (circled at a constant distance) with TAA, %ux%u, %d "
             "threads, %u frames, the minimum of %d interleaved rounds per frame, for every --transparency method: "
             "p50 and p99 ms and rays per frame; the seed's goal is std >= 3x exact at p50 and p99/p50 <= 1.15 "
             "(hzbench --only transparency)", tp.width, tp.height, tp.threads, tp.frames, tp.rounds);
    sec[3] = (md_section_t){ blur && nb > 0, "Motion blur in tdense (seed 002)", "", csv_path,
                             { { "group", blur_group, false, 0, 0, 0 } }, { 0 }, 1 };
    snprintf(sec[3].what, sizeof sec[3].what, "tdense with the shutter open (%.2f), one motion-BVH key interval and "
             "refit per 4-subframe cycle against posing and refitting every subframe: ms per displayed frame, its "
             "begin_frame and trace pass, %ux%u, %d threads, median of %d rounds (hzbench --only blur)",
             (double)bo.shutter, bo.width, bo.height, bo.threads, bo.rounds);
    sec[4] = (md_section_t){ realtime && realtime_csv, "Real time: where a frame's time goes", "", realtime_csv,
                             { { 0 } }, { 0 }, 1 };
    snprintf(sec[4].what, sizeof sec[4].what, "tdense and TAA at %ux%u on %d threads, %u frames from t = %.1f s at "
             "%u Hz, %d rounds: p50 and p99 ms per frame; begin, trace (time inside accel calls), shade (the rest "
             "of the trace pass) and resolve ms; the same frame's rays through Embree alone; overhead = p50 / that "
             "(hzbench --only realtime)", rt.width, rt.height, rt.threads, rt.frames, (double)rt.start, rt.hz,
             rt.rounds);
    sec[5] = (md_section_t){ adaptive && ad.csv_path, "Adaptive supersampling (seed 003)", "", ad.csv_path, { { 0 } },
                             { 0 }, 1 };
    snprintf(sec[5].what, sizeof sec[5].what, "Fixed 9 spp against --mode adaptive at several tau and at tau 1 "
             "focused on the objects at the centre of the view, %ux%u, %d threads, one frame at t = %.1f s, median "
             "of %d interleaved rounds: ms split into presample, subpixel test and extra samples, camera rays per "
             "pixel, live lanes per extra packet, PSNR (sRGB 8-bit) against %u spp over the frame and over the focus "
             "objects' pixels (hzbench --only adaptive)", ad.width, ad.height, ad.threads, (double)ad.t, ad.rounds,
             ad.ref_spp);
    sec[6] = (md_section_t){ accel && ao.csv_path, "Ray queries: native BVH against Embree", "", ao.csv_path,
                             { { "what", primary, false, accel_keys, "method", "value" },
                               { "what", shadow, false, accel_keys, "method", "value" },
                               { "what", diffuse, false, accel_keys, "method", "value" },
                               { "what", rays, true, other_keys, "method", "value" } },
                             { "Primary rays, Mrays/s (ratios: best native SIMD over Embree's best):",
                               "Shadow rays, Mrays/s:", "Diffuse bounces, Mrays/s:",
                               "Builds (s; ratios native over Embree), bytes per triangle, agreement with Embree (%):" },
                             4 };
    snprintf(sec[6].what, sizeof sec[6].what, "Per scene: Mrays/s of primary rays from the scene's camera, shadow "
             "rays to its first light and cosine-weighted diffuse bounces, for every native kernel and Embree "
             "call, on one thread and on the pool (medians of interleaved rounds); build times, bytes per "
             "triangle and the agreement of native and Embree hits (hzbench --only accel)");
    sec[7] = (md_section_t){ motion && mo.csv_path, "Motion-blur BVHs (seed 002)", "", mo.csv_path, { { 0 } }, { 0 },
                             1 };
    snprintf(sec[7].what, sizeof sec[7].what, "The seed's Table 1 per scene and BVH (msbvh, interp, swept, Embree's "
             "motion blur): references, nodes, spatial splits, SAH cost, intersections and traversal steps per ray "
             "(max / average), render ms of a frame of one primary and one shadow or ambient-occlusion ray per pixel "
             "at its own time, build and refit ms, bytes per triangle, Mrays/s, the MSBVH at several split budgets "
             "(hzbench --only motion)");
    char sweep_csv[4096] = "";
    if (motion_swept)
        hz_bench_csv_beside(mo.csv_path, "sweep", sweep_csv, sizeof sweep_csv);
    sec[8] = (md_section_t){ motion_swept, "Motion size (seed 002)", "",
                             sweep_csv, { { 0 } }, { 0 }, 1 };
    snprintf(sec[8].what, sizeof sec[8].what, "The motion-size sweep: one scene's shutter interval scaled from 1/8x to "
             "8x; per interval the keys, how far triangles move over it against their size (median and mean over "
             "triangles), and per BVH and secondary ray the intersections per ray, average and max, the average as "
             "%% of the interpolated BVH, SAH cost and references (hzbench --only motion --motion-sweep)");
    char leaf_csv[4096] = "";
    if (motion_swept)
        hz_bench_csv_beside(mo.csv_path, "leaf", leaf_csv, sizeof leaf_csv);
    sec[9] = (md_section_t){ motion_swept, "Leaf size (seed 002)", "", leaf_csv, { { 0 } }, { 0 }, 1 };
    snprintf(sec[9].what, sizeof sec[9].what, "The sweep scene's MSBVH (budget 1 and the largest) and interpolated BVH "
             "with leaves of at most 2, 4 and the default number of triangles (the seed's trees held about 3.8): "
             "references, nodes, bytes per triangle, intersections per ray (average, max, %% of the interpolated "
             "BVH with the same leaves), traversal steps, render ms and its ratio to that BVH's, interleaved with it "
             "(hzbench --only motion)");
    return write_md(md_path, argc, argv, sec, 10);
}
