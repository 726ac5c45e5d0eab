/* The 64-bit scene clock (hz/scenetime.h): exact wrapping at any time, and animation that keeps moving after a
 * million seconds (`hzrt render --start 1e6`) and after 30 days of the frame loop's scene source (`hzrt latency
 * --render scene`). The oracle is the built-in scene's 8 s loop: a frame at t + k * 8 s must be the frame at t,
 * byte for byte, and consecutive frames must differ as they do at the start.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <stdlib.h>
#include <string.h>

#include "hz/scenetime.h"
#include "render_fixture.h"
#include "scenesrc.h"

static void test_wrap_exact(void **state)
{
    (void)state;
    const hz_time_ns_t day = 86400 * HZ_NS_PER_S;
    assert_true(hz_time_wrap_s(30 * day + 250000000, 8.0) == 0.25f);
    assert_true(hz_time_wrap_s(-250000000, 8.0) == 7.75f);
    assert_true(hz_time_wrap_s(INT64_MAX, 8.0) >= 0.0f && hz_time_wrap_s(INT64_MAX, 8.0) < 8.0f);
    assert_true(hz_time_wrap_s(INT64_MIN, 8.0) >= 0.0f && hz_time_wrap_s(INT64_MIN, 8.0) < 8.0f);
    assert_true(hz_time_wrap_s(1500000000, 0.0) == 1.5f); /* no loop */
    assert_true(hz_time_wrap_s(8 * HZ_NS_PER_S - 1, 8.0) < 8.0f); /* never the period itself */
    assert_true(hz_time_from_s(1e6) == 1000000 * HZ_NS_PER_S);
    assert_true(hz_time_from_s(0.5) == 500000000);
    assert_true(hz_time_from_s(1e30) == INT64_MAX && hz_time_from_s(-1e30) == INT64_MIN);
    /* Frame times of a 240 Hz display: exact at every second boundary, strictly increasing. */
    assert_true(hz_time_of_frame(0, 240, 240) == HZ_NS_PER_S);
    assert_true(hz_time_of_frame(7, 240u * 86400u * 30u, 240) == 7 + 30 * day);
    for (uint64_t n = 0; n < 1000; n++)
        assert_true(hz_time_of_frame(0, n + 1, 240) > hz_time_of_frame(0, n, 240));
}

enum { W = 64, H = 36, N = 6 };

/* N consecutive full-mode frames of the built-in scene at a 240 Hz display from scene time start. */
static void render_run(rfix_t *f, hz_time_ns_t start, float *out)
{
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H;
    hz_error_t err;
    if (rfix_renderer(f, &o, 2, &err) != HZ_OK)
        fail_msg("renderer: %s", err.msg);
    for (uint32_t k = 0; k < N; k++) {
        if (hz_render_run_frame_ns(f->r, k, hz_time_of_frame(start, k, 240), &err) != HZ_OK)
            fail_msg("frame: %s", err.msg);
        memcpy(out + (size_t)k * W * H * 3, hz_render_output(f->r)->rgb, (size_t)W * H * 3 * sizeof(float));
    }
}

static int consecutive_equal(const float *frames)
{
    int same = 0;
    for (int k = 1; k < N; k++)
        same += !memcmp(frames + (size_t)(k - 1) * W * H * 3, frames + (size_t)k * W * H * 3,
                        (size_t)W * H * 3 * sizeof(float));
    return same;
}

static void test_render_after_a_million_seconds(void **state)
{
    (void)state;
    static float a[N * W * H * 3], b[N * W * H * 3], c[N * W * H * 3];
    rfix_t f;
    hz_error_t err;
    if (rfix_open(&f, "builtin", HZ_ACCEL_NATIVE, &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    assert_true(f.scene.header->duration == 8.0f); /* the oracle below needs the 8 s loop */
    render_run(&f, hz_time_from_s(0.5), a);
    render_run(&f, hz_time_from_s(1e6 + 0.5), b); /* 1e6 s is 125000 loops */
    render_run(&f, hz_time_from_s(1e6 + 0.5 + 1.0 / 480.0), c); /* half a frame later */
    assert_int_equal(consecutive_equal(a), 0);
    assert_int_equal(consecutive_equal(b), 0); /* with a float clock 8 of 9 repeated here */
    assert_memory_equal(a, b, sizeof a);
    assert_true(memcmp(b, c, sizeof b) != 0);
    rfix_close(&f);
}

static void test_latency_source_after_30_days(void **state)
{
    (void)state;
    hz_framesrc_t src;
    hz_error_t err;
    if (hz_scenesrc_open_simple(&src, "builtin", W, H, 1, 0, HZ_MODE_FULL, &err) != HZ_OK)
        fail_msg("scene source: %s", err.msg);
    size_t bytes = (size_t)W * H * 3;
    uint8_t *img = malloc(bytes * (N + 1)), *early = malloc(bytes * N);
    assert_non_null(img);
    assert_non_null(early);
    const int64_t period = 4166667, d0 = 123456789; /* 240 Hz; the loop's clock starts anywhere */
    const int64_t month = 30ll * 86400 * HZ_NS_PER_S; /* 324000 loops of the 8 s scene */
    hz_frame_req_t req = { 0, d0, period, 0, 0 };
    for (int k = 0; k < N; k++) { /* the first frame fixes scene time 0 */
        hz_rgb8_image_t out = { early + k * bytes, W, H, (size_t)W * 3 };
        req.id = (uint64_t)k, req.display_ns = d0 + k * period;
        assert_int_equal(src.render(src.ctx, &req, &out, &err), HZ_OK);
    }
    for (int k = 0; k < N; k++) {
        hz_rgb8_image_t out = { img + k * bytes, W, H, (size_t)W * 3 };
        req.id = (uint64_t)(N + k), req.display_ns = d0 + month + k * period;
        assert_int_equal(src.render(src.ctx, &req, &out, &err), HZ_OK);
    }
    for (int k = 1; k < N; k++)
        assert_true(memcmp(img + (k - 1) * bytes, img + k * bytes, bytes) != 0); /* still animating */
    assert_memory_equal(img, early, bytes * N); /* and exactly where the loop says */
    free(img);
    free(early);
}

int main(void)
{
    (void)rfix_frame; /* the fixture's float-time helper: this test drives the ns clock itself */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wrap_exact),
        cmocka_unit_test(test_render_after_a_million_seconds),
        cmocka_unit_test(test_latency_source_after_30_days),
    };
    return HZ_RUN(tests);
}
