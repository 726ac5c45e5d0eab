/* Temporally dense rendering through the renderer (HZ_MODE_TDENSE): one primary ray per 2x2 tile per frame;
 * under a still camera every static pixel holds its four jittered samples after 16 frames and the image is the
 * 4-spp full-frame render at the same 4x MSAA positions (within float rounding); reflected motion vectors
 * keep a static mirror that shows a moving object from being averaged; bit-identical output for any thread
 * count. */
#include "hz_test.h"

#include <unistd.h>

#include "fileio.h"
#include "hz/hzb_write.h"
#include "hz/tdense.h"
#include "render_fixture.h"

/* A still room: back wall, floor, a box, a mirror on the back wall; `spin` adds a quad spinning between the
 * camera and the mirror (seen in it). Object ids: 0 wall + floor, 1 box, 2 mirror, 3 spinner. */
static const char *write_room(char *path, size_t size, int spin)
{
    static float pos[24][4] = {
        { -4, -2, -3, 0 }, { 4, -2, -3, 0 }, { 4, 3, -3, 0 }, { -4, 3, -3, 0 },         /* wall */
        { -4, -2, -3, 0 }, { 4, -2, -3, 0 }, { 4, -2, 3, 0 }, { -4, -2, 3, 0 },         /* floor */
        { -0.3f, -2, -1, 0 }, { 1.2f, -2, -1.4f, 0 }, { 1.2f, 0.4f, -1.4f, 0 }, { -0.3f, 0.4f, -1, 0 }, /* box */
        { -3.5f, -1.5f, -2.9f, 0 }, { -0.5f, -1.5f, -2.9f, 0 }, { -0.5f, 2, -2.9f, 0 }, { -3.5f, 2, -2.9f, 0 }, /* mirror */
        { -2.3f, -0.6f, 2, 0 }, { -0.7f, -0.6f, 2, 0 }, { -0.7f, 1.0f, 2, 0 }, { -2.3f, 1.0f, 2, 0 }, /* spinner */
        { 0, 0, 0, 0 }, { 0, 0, 0, 0 }, { 0, 0, 0, 0 }, { 0, 0, 0, 0 },
    };
    static uint32_t tri[10][3] = { { 0, 1, 2 },    { 0, 2, 3 },    { 4, 6, 5 },    { 4, 7, 6 },    { 8, 9, 10 },
                                   { 8, 10, 11 },  { 12, 13, 14 }, { 12, 14, 15 }, { 16, 17, 18 }, { 16, 18, 19 } };
    static uint32_t info[10] = { 0, 0, 1, 1, 2 | 1u << 16, 2 | 1u << 16, 3 | 2u << 16, 3 | 2u << 16,
                                 4 | 3u << 16, 4 | 3u << 16 };
    hz_hzb_material_t m[5];
    memset(m, 0, sizeof m);
    const float col[5][3] = { { 0.7f, 0.7f, 0.65f }, { 0.2f, 0.35f, 0.6f }, { 0.8f, 0.3f, 0.1f }, { 0.9f, 0.9f, 0.9f },
                              { 0.1f, 0.8f, 0.2f } };
    for (int i = 0; i < 5; i++) {
        memcpy(m[i].base_color, col[i], sizeof col[i]);
        m[i].alpha = 1.0f;
        m[i].base_texture = m[i].alpha_texture = -1;
    }
    m[3].mirror = 0.9f;
    hz_hzb_object_t o[4];
    memset(o, 0, sizeof o);
    o[0].triangle_count = 4, o[0].vertex_count = 8;
    o[1].first_triangle = 4, o[1].triangle_count = 2, o[1].first_vertex = 8, o[1].vertex_count = 4;
    o[2].first_triangle = 6, o[2].triangle_count = 2, o[2].first_vertex = 12, o[2].vertex_count = 4;
    o[3].first_triangle = 8, o[3].triangle_count = 2, o[3].first_vertex = 16, o[3].vertex_count = 4;
    if (spin) {
        o[3].motion = HZ_MOTION_SPIN;
        o[3].params[0] = -1.5f, o[3].params[1] = 0.2f, o[3].params[2] = 2.0f; /* pivot: the quad's centre */
        o[3].params[5] = 1.0f; /* about z */
        o[3].params[6] = 3.0f; /* rad/s */
    }
    hz_hzb_light_t l;
    memset(&l, 0, sizeof l);
    l.position[0] = 1.0f, l.position[1] = 2.5f, l.position[2] = 2.0f;
    l.color[0] = l.color[1] = l.color[2] = 25.0f;
    hz_hzb_camera_key_t k;
    memset(&k, 0, sizeof k);
    k.eye[0] = 0.5f, k.eye[1] = 0.3f, k.eye[2] = 6.0f, k.up[1] = 1.0f, k.fov_y = 0.9f;
    k.target[0] = -0.5f, k.target[2] = -1.0f;
    hz_hzb_source_t src;
    memset(&src, 0, sizeof src);
    src.vertex_count = spin ? 20 : 16, src.positions = &pos[0][0];
    src.triangle_count = spin ? 10 : 8, src.triangles = &tri[0][0], src.tri_info = info;
    src.material_count = 5, src.materials = m, src.object_count = spin ? 4 : 3, src.objects = o;
    src.light_count = 1, src.lights = &l, src.camera_key_count = 1, src.camera_keys = &k;
    src.ambient[0] = src.ambient[1] = src.ambient[2] = 0.05f;
    src.background[2] = 0.2f;
    static uint8_t img[16384] HZ_ALIGNED(64);
    size_t n;
    hz_error_t err;
    if (hz_hzb_write(&src, img, sizeof img, &n, &err) != HZ_OK)
        fail_msg("write: %s", err.msg);
    snprintf(path, size, "/tmp/hz-test-room-%d-%d.hzb", spin, (int)getpid());
    assert_int_equal(hz_file_write_atomic(path, img, n, NULL), HZ_OK);
    return path;
}

static void open_room(rfix_t *f, int spin)
{
    char path[256];
    hz_error_t err;
    write_room(path, sizeof path, spin);
    if (rfix_open(f, path, HZ_ACCEL_NATIVE, &err) != HZ_OK)
        fail_msg("open: %s", err.msg);
    unlink(path);
}

static void renderer(rfix_t *f, const hz_render_opts_t *o, int threads)
{
    hz_error_t err;
    if (rfix_renderer(f, o, threads, &err) != HZ_OK)
        fail_msg("renderer: %s", err.msg);
}

static void frame(rfix_t *f, uint64_t i, float t)
{
    hz_error_t err;
    if (rfix_frame(f, i, t, &err) != HZ_OK)
        fail_msg("frame %u: %s", (unsigned)i, err.msg);
}

static float *copy_image(const hz_image_t *img)
{
    size_t n = hz_image_pixels(img) * 3 * sizeof(float);
    float *c = malloc(n);
    assert_non_null(c);
    memcpy(c, img->rgb, n);
    return c;
}

static void test_static_camera_converges_to_msaa4(void **state)
{
    (void)state;
    const uint32_t W = 96, H = 64;
    rfix_t f;
    open_room(&f, 0);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = HZ_MODE_TDENSE;
    renderer(&f, &o, 2);
    hz_render_stats_t last;
    for (uint32_t i = 0; i < 16; i++) {
        frame(&f, i, 0.25f + (float)i / 240.0f);
        hz_render_frame_stats(f.r, &last, NULL);
        assert_int_equal(last.primary_rays, (W / 2) * (H / 2)); /* one per 2x2 tile */
    }
    const hz_tdense_t *td = hz_render_tdense(f.r);
    assert_non_null(td);
    for (size_t p = 0; p < (size_t)W * H; p++)
        assert_int_equal(td->flags[p] & (HZ_TDENSE_SAMPLES | HZ_TDENSE_DYNAMIC), HZ_TDENSE_SAMPLES);
    float *dense = copy_image(hz_render_output(f.r));

    o.mode = HZ_MODE_FULL, o.spp = 4, o.msaa4 = true;
    renderer(&f, &o, 2);
    frame(&f, 0, 0.25f);
    const hz_image_t *full = hz_render_output(f.r);
    /* The same four positions, summed in a different order (per sample vs. per contribution): equal within
     * float rounding plus the window's RGB9E5 rounding of each sample: at most half a step of the sample's
     * largest channel, 2^-9 of it, and the largest channel of any of the four samples is at most 4 times the
     * pixel's channel sum (r + g + b) (hz/pack.h); a pixel not traced in the last frame shows that average as
     * kept in RGB9E5, half a step of its largest channel more. */
    double worst = 0.0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        const float *fp = full->rgb + i / 3 * 3;
        double d = fabs((double)dense[i] - full->rgb[i]),
               tol = 4e-6 * fmax(1.0, fabs(full->rgb[i])) + ldexp((double)fp[0] + fp[1] + fp[2], -8);
        if (d > tol)
            fail_msg("value %zu (pixel %zu): tdense %.9g, full 4-spp MSAA %.9g", i, i / 3, dense[i], full->rgb[i]);
        worst = fmax(worst, d);
    }
    print_message("largest difference %.3g\n", worst);
    /* And the comparison can fail: the stratified 4-spp render is a different image. */
    o.msaa4 = false;
    renderer(&f, &o, 2);
    frame(&f, 0, 0.25f);
    size_t differ = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++)
        differ += fabs((double)dense[i] - hz_render_output(f.r)->rgb[i]) > 1e-4;
    assert_true(differ > 100);
    free(dense);
    rfix_close(&f);
}

static void test_reflected_motion_keeps_mirror_dynamic(void **state)
{
    (void)state;
    /* The mirror is still; the quad spinning in front of it is seen in it. With reflected motion vectors, the
     * mirror pixels that show the spinner are dynamic; without them they are averaged as static. */
    const uint32_t W = 96, H = 64;
    size_t dyn_mirror[2] = { 0, 0 }, mirror_px[2] = { 0, 0 };
    for (int reflect = 0; reflect < 2; reflect++) {
        rfix_t f;
        open_room(&f, 1);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = W, o.height = H, o.mode = HZ_MODE_TDENSE, o.tdense_reflect_mv = reflect != 0;
        renderer(&f, &o, 1);
        for (uint32_t i = 0; i < 8; i++)
            frame(&f, i, (float)i / 240.0f);
        const hz_tdense_t *td = hz_render_tdense(f.r);
        const hz_gbuffer_t *gb = hz_render_gbuffer(f.r);
        for (size_t p = 0; p < (size_t)W * H; p++) {
            if (gb->object[p] != 2 || !gb->object2 || gb->object2[p] != 3)
                continue; /* mirror pixels whose reflection hits the spinner */
            mirror_px[reflect]++;
            dyn_mirror[reflect] += (td->flags[p] & HZ_TDENSE_DYNAMIC) != 0;
        }
        rfix_close(&f);
    }
    print_message("mirror pixels showing the spinner: %zu / %zu dynamic without, %zu / %zu with reflected "
                  "motion\n", dyn_mirror[0], mirror_px[0], dyn_mirror[1], mirror_px[1]);
    assert_true(mirror_px[1] > 20);
    assert_true(dyn_mirror[1] >= mirror_px[1] * 9 / 10);
    assert_true(dyn_mirror[0] <= mirror_px[0] / 10);
}

static void test_threads_give_identical_bytes(void **state)
{
    (void)state;
    /* The built-in scene (camera path, moving objects, mirror, transparency): 1 and 2 threads. */
    const uint32_t W = 80, H = 46;
    float *img[2];
    uint8_t orders[2][40 * 23];
    for (int k = 0; k < 2; k++) {
        rfix_t f;
        hz_error_t err;
        assert_int_equal(rfix_open(&f, "builtin", HZ_ACCEL_NATIVE, &err), HZ_OK);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = W, o.height = H, o.mode = HZ_MODE_TDENSE;
        renderer(&f, &o, k + 1);
        for (uint32_t i = 0; i < 9; i++)
            frame(&f, i, 1.0f + (float)i / 240.0f);
        img[k] = copy_image(hz_render_output(f.r));
        memcpy(orders[k], hz_render_tdense(f.r)->orders, sizeof orders[k]);
        rfix_close(&f);
    }
    assert_memory_equal(img[0], img[1], (size_t)W * H * 3 * sizeof(float));
    assert_memory_equal(orders[0], orders[1], sizeof orders[0]);
    /* The camera moves: after a cycle the tiles chose both patterns. */
    size_t hg = 0;
    for (size_t t = 0; t < sizeof orders[0]; t++)
        hg += orders[0][t] == HZ_TILEORDER_HOURGLASS;
    assert_true(hg > 0 && hg < sizeof orders[0]);
    free(img[0]);
    free(img[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_camera_converges_to_msaa4),
        cmocka_unit_test(test_reflected_motion_keeps_mirror_dynamic),
        cmocka_unit_test(test_threads_give_identical_bytes),
    };
    return HZ_RUN(tests);
}
