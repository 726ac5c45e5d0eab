/* Overlapped frames (hz_render_overlap_units, port/linux/render_run.c): tdense and TAA frames whose resolve
 * units start while other rows are still being traced must be the frames of the two passes run one after the
 * other (opts.serial_passes), bit for bit, on any number of threads, frame after frame (history, windows,
 * flags and next orderings included). More pool threads than CPUs shuffle which thread runs what. The rows a
 * unit waits for are also checked against the pixels its resolve reads, worked out here from the image
 * geometry.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "hz/tdense.h"
#include "render_fixture.h"

#define W 75
#define H 45
#define FRAMES 10

typedef struct frame_state {
    float rgb[W * H * 3];
    uint8_t flags[W * H];
    uint8_t next_orders[W * H];
} frame_state_t;

static frame_state_t ref[FRAMES];

typedef struct run {
    const char *scene; /* file in $HZ_SCENES_DIR, or "builtin" */
    hz_render_mode_t mode;
    hz_transp_t transparency;
} run_t;

static void keep(frame_state_t *st, const rfix_t *f)
{
    memcpy(st->rgb, hz_render_output(f->r)->rgb, sizeof st->rgb);
    const hz_tdense_t *td = hz_render_tdense(f->r);
    memset(st->flags, 0, sizeof st->flags);
    memset(st->next_orders, 0, sizeof st->next_orders);
    if (td) {
        memcpy(st->flags, td->flags, (size_t)W * H);
        memcpy(st->next_orders, td->next_orders, (size_t)td->tiles_x * td->tiles_y);
    }
}

/* Renders FRAMES frames from t = 0.5 s at 60 Hz; serial: the reference (kept), else compared with it. */
static void render(const run_t *run, bool serial, int threads)
{
    rfix_t f;
    hz_error_t err;
    if (rfix_open_named(&f, run->scene, &err) != HZ_OK)
        fail_msg("%s: %s", run->scene, err.msg);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = run->mode, o.transparency = run->transparency;
    o.serial_passes = serial;
    if (rfix_renderer(&f, &o, threads, &err) != HZ_OK)
        fail_msg("%s: %s", run->scene, err.msg);
    uint32_t rows, items;
    uint32_t units = hz_render_overlap_units(f.r, &rows, &items);
    assert_true(serial ? units == 0 : units > 0);
    static frame_state_t now;
    for (uint32_t i = 0; i < FRAMES; i++) {
        if (rfix_frame(&f, i, 0.5f + (float)i / 60.0f, &err) != HZ_OK)
            fail_msg("%s frame %u: %s", run->scene, i, err.msg);
        if (serial) {
            keep(&ref[i], &f);
            continue;
        }
        keep(&now, &f);
        for (size_t k = 0; k < (size_t)W * H * 3; k++) {
            uint32_t a, b;
            memcpy(&a, &ref[i].rgb[k], 4);
            memcpy(&b, &now.rgb[k], 4);
            if (a != b)
                fail_msg("%s %s, %d threads, frame %u pixel (%zu, %zu) channel %zu: overlapped %08x, serial %08x",
                         run->scene, hz_render_mode_name(run->mode), threads, i, k / 3 % W, k / 3 / W, k % 3, b,
                         a);
        }
        assert_memory_equal(ref[i].flags, now.flags, sizeof now.flags);
        assert_memory_equal(ref[i].next_orders, now.next_orders, sizeof now.next_orders);
    }
    rfix_close(&f);
}

static void test_overlapped_frames_match_serial_passes(void **state)
{
    (void)state;
    static const run_t runs[] = {
        { "builtin", HZ_MODE_TDENSE, HZ_TRANSP_EXACT },
        { "builtin", HZ_MODE_TAA, HZ_TRANSP_EXACT },
        { "CesiumMan-small.hzb", HZ_MODE_TDENSE, HZ_TRANSP_EXACT },
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_TAA, HZ_TRANSP_STD },   /* 7x7 windows */
        { "AlphaBlendModeTest-small.hzb", HZ_MODE_TDENSE, HZ_TRANSP_STD },
    };
    static const int threads[] = { 1, 2, 3, 6 };
    for (size_t i = 0; i < HZ_ARRAY_LEN(runs); i++) {
        render(&runs[i], true, 1);
        for (size_t t = 0; t < HZ_ARRAY_LEN(threads); t++)
            render(&runs[i], false, threads[t]);
    }
}

/* Trace rows (`tall` pixel rows each) holding pixel rows [y0, y1], clamped to the image. */
static void rows_of(int tall, int y0, int y1, uint32_t *lo, uint32_t *hi)
{
    y0 = y0 < 0 ? 0 : y0;
    y1 = y1 > H - 1 ? H - 1 : y1;
    *lo = (uint32_t)(y0 / tall);
    *hi = (uint32_t)(y1 / tall);
}

static void test_units_wait_for_the_rows_they_read(void **state)
{
    (void)state;
    static const hz_render_mode_t modes[] = { HZ_MODE_TDENSE, HZ_MODE_TAA, HZ_MODE_FULL, HZ_MODE_ADAPTIVE };
    for (size_t m = 0; m < HZ_ARRAY_LEN(modes); m++) {
        rfix_t f;
        hz_error_t err;
        assert_int_equal(rfix_open(&f, "builtin", HZ_ACCEL_NATIVE, &err), HZ_OK);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = W, o.height = H, o.mode = modes[m];
        if (rfix_renderer(&f, &o, 1, &err) != HZ_OK)
            fail_msg("renderer: %s", err.msg);
        /* a trace item is a render tile, or for tdense an area of 8x8 tdense tiles (2x2 pixels each), so that
         * its camera rays fill a batch */
        const int tall = modes[m] == HZ_MODE_TDENSE ? 2 * HZ_RENDER_TILE : HZ_RENDER_TILE;
        uint32_t rows, items, units = hz_render_overlap_units(f.r, &rows, &items);
        assert_int_equal(rows, (H + tall - 1) / tall);
        assert_int_equal(items, (W + tall - 1) / tall);
        assert_int_equal(hz_render_pass_items(f.r, 0), rows * items);
        if (modes[m] == HZ_MODE_FULL || modes[m] == HZ_MODE_ADAPTIVE) {
            assert_int_equal(units, 0); /* one pass, or three whose tests read more than their neighbours */
            rfix_close(&f);
            continue;
        }
        /* tdense: a unit per trace row; TAA: runs of tiles along the rows, the same number in every row */
        if (modes[m] == HZ_MODE_TDENSE)
            assert_int_equal(units, rows);
        else
            assert_true(units >= rows && units <= rows * items && units % rows == 0);
        const uint32_t per_row = units / rows;
        uint32_t last_lo = 0, last_hi = 0;
        for (uint32_t u = 0; u < units; u++) {
            uint32_t lo, hi, need_lo, need_hi;
            hz_render_overlap_needs(f.r, u, &lo, &hi);
            if (modes[m] == HZ_MODE_TDENSE) {
                /* tdense unit u: the tdense tile rows of trace row u, pixel rows 16u .. 16u + 15; their 3x3 motion
                 * and the newest-subframe box of the tile rows above and below reach two pixel rows further */
                int y0 = (int)u * tall;
                rows_of(tall, y0 - 2, y0 + tall - 1 + 2, &need_lo, &need_hi);
            } else {
                /* a run of TAA tiles: their pixel rows and the 7x7 window's 3 rows either side */
                int y0 = (int)(u / per_row) * tall;
                rows_of(tall, y0 - 3, y0 + tall - 1 + 3, &need_lo, &need_hi);
            }
            assert_true(lo <= need_lo && hi >= need_hi && hi < rows);
            assert_true(lo >= last_lo && hi >= last_hi); /* units can be handed out in order */
            last_lo = lo, last_hi = hi;
        }
        rfix_close(&f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_units_wait_for_the_rows_they_read),
        cmocka_unit_test(test_overlapped_frames_match_serial_passes),
    };
    return HZ_RUN(tests);
}
