/* Isolated dark pixels in lit areas of a dense scan (issue 18): the Stanford dragon at res2 (202,520 triangles),
 * 640x480, 1 sample at the pixel centres, camera key 0, with the native backend and (host builds) Embree.
 *
 * A speckle is a pixel on the dragon whose 8 neighbours are all on the dragon, whose luminance is below half
 * the median of its neighbours' while that median is lit (> 0.1, ambient alone gives 0.024), and at least 6
 * of the 8 neighbours are within 70% of the median (an isolated pixel, not a shadow edge). Measured with this
 * definition: 48 (native) and 50 (Embree) speckles before the fix; 17 / 18 once the baker's PLY vertex
 * normals are area-weighted (assimp's were one arbitrary adjacent face's normal); 10 / 11 with the
 * shadow-terminator skip as well (hz/terminator.h). The rest are grazing light on the scan's folds and true
 * occlusion. The limit, 14, fails either fix undone.
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include "render_fixture.h"

#define W 640
#define H 480
#define MAX_SPECKLES 14

static float lum(const hz_image_t *img, int x, int y)
{
    const float *p = img->rgb + ((size_t)y * W + (size_t)x) * 3;
    return (p[0] + p[1] + p[2]) / 3.0f;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static unsigned count_speckles(const hz_image_t *img, const hz_gbuffer_t *gb, unsigned *lit_pixels)
{
    unsigned n = 0;
    *lit_pixels = 0;
    for (int y = 1; y < H - 1; y++)
        for (int x = 1; x < W - 1; x++) {
            float nb[8];
            int k = 0, all_on = gb->object[y * W + x] != HZ_GB_NO_OBJECT;
            for (int dy = -1; dy <= 1 && all_on; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    if (!dx && !dy)
                        continue;
                    if (gb->object[(y + dy) * W + x + dx] == HZ_GB_NO_OBJECT)
                        all_on = 0;
                    nb[k++] = lum(img, x + dx, y + dy);
                }
            if (!all_on)
                continue;
            qsort(nb, 8, sizeof nb[0], cmp_float);
            float med = 0.5f * (nb[3] + nb[4]);
            if (!(med > 0.1f))
                continue;
            (*lit_pixels)++;
            int close = 0;
            for (int i = 0; i < 8; i++)
                close += nb[i] > 0.7f * med;
            if (lum(img, x, y) < 0.5f * med && close >= 6)
                n++;
        }
    return n;
}

static void check_backend(hz_accel_backend_t backend, const char *name)
{
    char p[4096];
    const char *scene = rfix_scene_path("dragon-res2.hzb", p, sizeof p);
    if (!scene)
        fail_msg("HZ_SCENES_DIR is not set (make test sets it)");
    rfix_t f;
    hz_error_t err;
    if (rfix_open(&f, scene, backend, &err) != HZ_OK)
        fail_msg("%s: %s", scene, err.msg);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = W, o.height = H, o.mode = HZ_MODE_FULL, o.spp = 1;
    if (rfix_renderer(&f, &o, 2, &err) != HZ_OK || rfix_frame(&f, 0, 0.0f, &err) != HZ_OK)
        fail_msg("%s: %s", scene, err.msg);
    unsigned lit;
    unsigned n = count_speckles(hz_render_output(f.r), hz_render_gbuffer(f.r), &lit);
    print_message("dragon-res2 %dx%d, %s: %u isolated dark pixels among %u lit dragon pixels (limit %d)\n", W, H,
                  name, n, lit, MAX_SPECKLES);
    assert_true(lit > 50000); /* the dragon fills the view: the count means something */
    assert_true(n <= MAX_SPECKLES);
    rfix_close(&f);
}

static void test_native_has_no_speckles(void **state)
{
    (void)state;
    check_backend(HZ_ACCEL_NATIVE, "native");
}

#if HZ_HAVE_EMBREE
static void test_embree_has_no_speckles(void **state)
{
    (void)state;
    check_backend(HZ_ACCEL_EMBREE, "embree");
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_native_has_no_speckles),
#if HZ_HAVE_EMBREE
        cmocka_unit_test(test_embree_has_no_speckles),
#endif
    };
    return HZ_RUN(tests);
}
