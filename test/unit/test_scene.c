/* Scene format: the built-in scene through writer + loader, animation, camera path, memory plan, and
 * hand-made invalid images that must each be refused with the right status and a message naming the problem. */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/builtin.h"
#include "hz/crc32.h"
#include "hz/hzb_write.h"
#include "hz/scene.h"

/* CRC of the built-in image, produced by this test on x86-64 (test_builtin_is_deterministic). */
#define HZ_BUILTIN_GOLDEN_CRC 0x82f8ae83u

static uint8_t image_mem[4 << 20] HZ_ALIGNED(64);
static uint8_t scratch_mem[8 << 20] HZ_ALIGNED(64);
static uint8_t state_mem[1 << 20] HZ_ALIGNED(64);
static uint8_t copy_mem[4 << 20] HZ_ALIGNED(64);

typedef struct fixture {
    hz_arena_t images, scratch, state;
    const uint8_t *image;
    size_t size;
} fixture_t;

static fixture_t fx;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&fx.images, "images", image_mem, sizeof image_mem);
    hz_arena_init(&fx.scratch, "scratch", scratch_mem, sizeof scratch_mem);
    hz_arena_init(&fx.state, "scene", state_mem, sizeof state_mem);
    hz_error_t err;
    const void *img;
    if (hz_builtin_scene_image(&fx.images, &fx.scratch, &img, &fx.size, &err) != HZ_OK) {
        print_error("builtin: %s\n", err.msg);
        return -1;
    }
    fx.image = img;
    return 0;
}

static void test_builtin_loads_with_every_feature(void **state)
{
    (void)state;
    hz_scene_t s;
    hz_error_t err;
    hz_arena_reset(&fx.state, 0);
    assert_int_equal(hz_scene_load(&s, fx.image, fx.size, &fx.state, &err), HZ_OK);
    uint32_t want = HZ_FEAT_MOTION | HZ_FEAT_BLEND | HZ_FEAT_CUTOUT | HZ_FEAT_MIRROR | HZ_FEAT_TEXTURES |
                    HZ_FEAT_INSTANCING | HZ_FEAT_CAMERA_PATH | HZ_FEAT_SKINNING | HZ_FEAT_NORMALS;
    assert_int_equal(s.features, want);
    assert_int_equal(s.light_count, 2);
    assert_true(s.triangle_count > 1000);
    assert_non_null(s.prev_pos);
    /* The scratch arena is given back; only the image stays. */
    assert_int_equal(fx.scratch.used, 0);
    assert_true(fx.state.used <= s.plan.arena_bytes);
    char buf[160];
    hz_scene_features_str(s.features, buf, sizeof buf);
    assert_string_equal(buf, "motion,blend,cutout,mirror,textures,instancing,camera-path,skinning,normals");
}

static void test_builtin_is_deterministic(void **state)
{
    (void)state;
    hz_arena_t a, sc;
    hz_arena_init(&a, "a", copy_mem, sizeof copy_mem);
    hz_arena_init(&sc, "s", scratch_mem, sizeof scratch_mem);
    const void *img;
    size_t size;
    assert_int_equal(hz_builtin_scene_image(&a, &sc, &img, &size, NULL), HZ_OK);
    assert_int_equal(size, fx.size);
    assert_memory_equal(img, fx.image, size);
    /* A golden CRC of the image: holds x86-64 and AArch64 (qemu) to the same bytes. */
    print_message("builtin image: %zu bytes, crc %08x\n", size, hz_crc32(0, img, size));
    assert_int_equal(hz_crc32(0, img, size), HZ_BUILTIN_GOLDEN_CRC);
}

static void test_animation_moves_only_moving_objects(void **state)
{
    (void)state;
    hz_scene_t s;
    hz_arena_reset(&fx.state, 0);
    assert_int_equal(hz_scene_load(&s, fx.image, fx.size, &fx.state, NULL), HZ_OK);
    /* At t = 0 the posed state equals the baked rest positions for world-space objects. */
    hz_scene_animate(&s, 0.5f);
    for (uint32_t i = 0; i < s.object_count; i++) {
        const hz_object_t *o = &s.objects[i];
        int changed = 0;
        for (uint32_t v = o->first_vertex; v < o->first_vertex + o->vertex_count; v++)
            for (int c = 0; c < 3; c++) {
                float now = s.pos[v * 4 + c], before = s.prev_pos[v * 4 + c];
                assert_true(isfinite(now));
                changed |= now != before;
                if (o->motion == HZ_MOTION_NONE)
                    assert_true(now == s.rest_pos[v * 4 + c]);
            }
        assert_int_equal(changed, o->motion != HZ_MOTION_NONE);
    }
    /* prev holds the previous call's state. */
    float keep[64];
    memcpy(keep, s.pos + s.objects[3].first_vertex * 4, sizeof keep);
    hz_scene_animate(&s, 0.75f);
    assert_memory_equal(keep, s.prev_pos + s.objects[3].first_vertex * 4, sizeof keep);
    /* Motion loops with the scene's duration (8 s): t and t + 8 give the same pose. */
    hz_scene_animate(&s, 1.25f);
    float a[64];
    memcpy(a, s.pos + s.objects[7].first_vertex * 4, sizeof a);
    hz_scene_animate(&s, 9.25f);
    for (int i = 0; i < 64; i++)
        assert_true(fabsf(a[i] - s.pos[s.objects[7].first_vertex * 4 + i]) < 1e-4f);
    /* Spinning keeps the box's size: rigid motion preserves distances. */
    const float *p = s.pos + s.objects[3].first_vertex * 4;
    const float *r = s.rest_pos + s.objects[3].first_vertex * 4;
    float d_now = hypotf(hypotf(p[0] - p[4], p[1] - p[5]), p[2] - p[6]);
    float d_rest = hypotf(hypotf(r[0] - r[4], r[1] - r[5]), r[2] - r[6]);
    assert_true(fabsf(d_now - d_rest) < 1e-5f);
    /* Normals stay unit length. */
    for (uint32_t v = 0; v < s.vertex_count; v++) {
        float l = hypotf(hypotf(s.nrm[v * 4], s.nrm[v * 4 + 1]), s.nrm[v * 4 + 2]);
        assert_true(fabsf(l - 1.0f) < 1e-4f);
    }
}

static void test_camera_path(void **state)
{
    (void)state;
    hz_scene_t s;
    hz_arena_reset(&fx.state, 0);
    assert_int_equal(hz_scene_load(&s, fx.image, fx.size, &fx.state, NULL), HZ_OK);
    hz_camera_t c0 = hz_scene_camera(&s, 0.0f);
    assert_true(c0.eye.x == s.camera_keys[0].eye[0] && c0.eye.z == s.camera_keys[0].eye[2]);
    /* Passes through the keys, loops with the duration, stays smooth in between. */
    hz_camera_t c2 = hz_scene_camera(&s, 2.0f);
    assert_true(fabsf(c2.eye.y - s.camera_keys[1].eye[1]) < 1e-5f);
    hz_camera_t c8 = hz_scene_camera(&s, 8.0f);
    assert_true(fabsf(c8.eye.x - c0.eye.x) < 1e-5f);
    hz_vec3_t prev = hz_scene_camera(&s, 0.0f).eye;
    for (float t = 0.01f; t < 16.0f; t += 0.01f) {
        hz_camera_t c = hz_scene_camera(&s, t);
        float step = hz_v3_len(hz_v3_sub(c.eye, prev));
        assert_true(step < 0.05f); /* no jumps, including across the loop point */
        assert_true(c.fov_y > 0.5f && c.fov_y < 1.5f);
        prev = c.eye;
    }
}

/* ---- a tiny hand-made scene for targeted corruption ---- */

static float tiny_pos[4][4] = { { 0, 0, 0, 0 }, { 1, 0, 0, 0 }, { 0, 1, 0, 0 }, { 1, 1, 0, 0 } };
static uint32_t tiny_tri[2][3] = { { 0, 1, 2 }, { 1, 3, 2 } };
static uint32_t tiny_info[2] = { 0, 0 };

static hz_hzb_material_t tiny_mat(void)
{
    hz_hzb_material_t m;
    memset(&m, 0, sizeof m);
    m.base_color[0] = m.base_color[1] = m.base_color[2] = 0.5f;
    m.alpha = 1.0f;
    m.base_texture = m.alpha_texture = -1;
    return m;
}

static hz_hzb_object_t tiny_obj(void)
{
    hz_hzb_object_t o;
    memset(&o, 0, sizeof o);
    o.triangle_count = 2;
    o.vertex_count = 4;
    return o;
}

static size_t write_tiny(uint8_t *out, size_t cap, const hz_hzb_material_t *mat, const hz_hzb_object_t *obj)
{
    hz_hzb_source_t src;
    memset(&src, 0, sizeof src);
    src.name = "tiny";
    src.vertex_count = 4, src.positions = &tiny_pos[0][0];
    src.triangle_count = 2, src.triangles = &tiny_tri[0][0], src.tri_info = tiny_info;
    src.material_count = 1, src.materials = mat;
    src.object_count = 1, src.objects = obj;
    size_t n = 0;
    assert_int_equal(hz_hzb_write(&src, out, cap, &n, NULL), HZ_OK);
    assert_int_equal(n, hz_hzb_write_size(&src));
    return n;
}

static uint8_t tiny_buf[4096] HZ_ALIGNED(64);

/* Re-seals a modified image: section CRCs and the header CRC, so that the deeper checks are reached. */
static void reseal(uint8_t *img)
{
    hz_hzb_header_t h;
    memcpy(&h, img, sizeof h);
    for (uint32_t i = 0; i < h.section_count && i < HZ_SEC_ID_MAX; i++) {
        hz_hzb_section_t e;
        memcpy(&e, img + sizeof h + i * sizeof e, sizeof e);
        if (e.offset + e.size <= h.file_bytes) {
            e.crc32 = hz_crc32(0, img + e.offset, (size_t)e.size);
            memcpy(img + sizeof h + i * sizeof e, &e, sizeof e);
        }
    }
    h.header_crc = hz_crc32(0, &h, offsetof(hz_hzb_header_t, header_crc));
    memcpy(img, &h, sizeof h);
}

static hz_hzb_section_t *section(uint8_t *img, uint32_t id)
{
    hz_hzb_header_t *h = (hz_hzb_header_t *)img;
    for (uint32_t i = 0; i < h->section_count; i++) {
        hz_hzb_section_t *e = (hz_hzb_section_t *)(img + sizeof *h + i * sizeof *e);
        if (e->id == id)
            return e;
    }
    return NULL;
}

#define EXPECT_REFUSED(size, code, needle)                                                                  \
    do {                                                                                                    \
        hz_error_t err_;                                                                                    \
        hz_status_t s_ = hz_scene_plan(tiny_buf, (size), NULL, &err_);                                      \
        if (s_ != (code) || !strstr(err_.msg, (needle)))                                                    \
            print_error("got %s: '%s'\n", hz_status_str(s_), err_.msg);                                     \
        assert_int_equal(s_, (code));                                                                       \
        assert_non_null(strstr(err_.msg, (needle)));                                                        \
    } while (0)

static void test_tiny_round_trip(void **state)
{
    (void)state;
    hz_hzb_material_t m = tiny_mat();
    hz_hzb_object_t o = tiny_obj();
    size_t n = write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    hz_scene_t s;
    hz_arena_t none;
    hz_arena_init(&none, "scene", NULL, 0); /* a static scene needs no arena memory at all */
    assert_int_equal(hz_scene_load(&s, tiny_buf, n, &none, NULL), HZ_OK);
    assert_int_equal(s.features, 0);
    assert_memory_equal(s.pos, tiny_pos, sizeof tiny_pos);
    assert_memory_equal(s.tri, tiny_tri, sizeof tiny_tri);
    assert_null(s.prev_pos);
    assert_int_equal(s.plan.arena_bytes, 0);
    /* A buffer that is too small for the writer is refused, nothing written past it. */
    uint8_t small[300] HZ_ALIGNED(64);
    memset(small, 0x77, sizeof small);
    hz_hzb_source_t src;
    memset(&src, 0, sizeof src);
    src.vertex_count = 4, src.positions = &tiny_pos[0][0];
    src.triangle_count = 2, src.triangles = &tiny_tri[0][0], src.tri_info = tiny_info;
    src.material_count = 1, src.materials = &m, src.object_count = 1, src.objects = &o;
    assert_int_equal(hz_hzb_write(&src, small, 200, NULL, NULL), HZ_E_NO_MEMORY);
    for (size_t i = 0; i < sizeof small; i++)
        assert_int_equal(small[i], 0x77);
}

static void test_refuses_bad_headers(void **state)
{
    (void)state;
    hz_hzb_material_t m = tiny_mat();
    hz_hzb_object_t o = tiny_obj();
    size_t n = write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    hz_hzb_header_t *h = (hz_hzb_header_t *)tiny_buf;

    tiny_buf[0] = 'X';
    EXPECT_REFUSED(n, HZ_E_FORMAT, "bad magic");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    h->version = 3;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_VERSION, "version 3");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    h->vertex_count ^= 1; /* not resealed */
    EXPECT_REFUSED(n, HZ_E_CORRUPT, "header CRC");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    EXPECT_REFUSED(n - 1, HZ_E_FORMAT, "truncated");
    EXPECT_REFUSED(100, HZ_E_FORMAT, "truncated");
    EXPECT_REFUSED(0, HZ_E_FORMAT, "truncated");
    /* Counts that would overflow 32-bit size arithmetic. */
    h->vertex_count = 0xffffffffu;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "section 'positions' has 4 elements");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    h->section_count = 0x40000000u;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "sections");
    /* An unaligned buffer is refused before anything is read. */
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    hz_error_t err;
    assert_int_equal(hz_scene_plan(tiny_buf + 4, n - 4, NULL, &err), HZ_E_INVALID_ARG);
}

static void test_refuses_bad_sections(void **state)
{
    (void)state;
    hz_hzb_material_t m = tiny_mat();
    hz_hzb_object_t o = tiny_obj();
    size_t n = write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);

    /* Section points past the end of the file (offset + size overflows 64 bits, too). */
    hz_hzb_section_t *e = section(tiny_buf, HZ_SEC_TRIANGLES);
    e->offset = 0xffffffffffffffc0ull;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "outside");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    e = section(tiny_buf, HZ_SEC_TRIANGLES);
    e->offset = section(tiny_buf, HZ_SEC_POSITIONS)->offset;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "overlap");
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    section(tiny_buf, HZ_SEC_TRIANGLES)->id = 99;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "unknown section id 99");
    /* A flipped data byte without resealing: CRC. */
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    tiny_buf[section(tiny_buf, HZ_SEC_POSITIONS)->offset + 5] ^= 0x10;
    EXPECT_REFUSED(n, HZ_E_CORRUPT, "'positions': CRC");
}

static void test_refuses_bad_content(void **state)
{
    (void)state;
    hz_hzb_material_t m = tiny_mat();
    hz_hzb_object_t o = tiny_obj();
    size_t n = write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    uint8_t *tri = tiny_buf + section(tiny_buf, HZ_SEC_TRIANGLES)->offset;
    uint32_t bad = 4;
    memcpy(tri + 8, &bad, 4);
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_RANGE, "vertex index 4 >= vertex count 4");

    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    float nan = NAN;
    memcpy(tiny_buf + section(tiny_buf, HZ_SEC_POSITIONS)->offset + 20, &nan, 4);
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_RANGE, "'positions': element 1 is not finite");

    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    float inf = INFINITY;
    memcpy(tiny_buf + section(tiny_buf, HZ_SEC_POSITIONS)->offset + 32, &inf, 4);
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_RANGE, "not finite");

    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    uint32_t info = 1u << 16; /* object 1 of 1 */
    memcpy(tiny_buf + section(tiny_buf, HZ_SEC_TRI_INFO)->offset, &info, 4);
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_RANGE, "object 1 out of range");

    hz_hzb_material_t m2 = tiny_mat();
    m2.base_texture = 0; /* no textures exist */
    write_tiny(tiny_buf, sizeof tiny_buf, &m2, &o);
    EXPECT_REFUSED(n, HZ_E_RANGE, "texture index");
    m2 = tiny_mat();
    m2.mirror = 1.5f;
    write_tiny(tiny_buf, sizeof tiny_buf, &m2, &o);
    EXPECT_REFUSED(n, HZ_E_RANGE, "outside [0, 1]");

    hz_hzb_object_t o2 = tiny_obj();
    o2.triangle_count = 1; /* leaves a triangle without an object */
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o2);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "objects cover 1 of 2 triangles");
    o2 = tiny_obj();
    o2.motion = HZ_MOTION_SPIN; /* zero axis */
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o2);
    EXPECT_REFUSED(n, HZ_E_RANGE, "spin axis is zero");
    o2.params[4] = 1.0f;
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o2);
    /* NaN speed written into the image after the fact (the writer would have produced NaN bounds). */
    hz_hzb_object_t *po = (hz_hzb_object_t *)(tiny_buf + section(tiny_buf, HZ_SEC_OBJECTS)->offset);
    po->params[6] = NAN;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_RANGE, "motion parameter 6 is not finite");

    /* A feature mask that does not match the content. */
    write_tiny(tiny_buf, sizeof tiny_buf, &m, &o);
    ((hz_hzb_header_t *)tiny_buf)->features |= HZ_FEAT_MIRROR;
    reseal(tiny_buf);
    EXPECT_REFUSED(n, HZ_E_FORMAT, "feature mask says 'mirror', the content needs 'none'");
}

static void test_arena_refusal_names_both_counts(void **state)
{
    (void)state;
    static uint8_t small[4096] HZ_ALIGNED(64);
    hz_arena_t a;
    hz_arena_init(&a, "scene", small, sizeof small);
    hz_scene_t s;
    hz_error_t err;
    assert_int_equal(hz_scene_load(&s, fx.image, fx.size, &a, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "arena 'scene': needs "));
    assert_non_null(strstr(err.msg, "has 4096"));
    assert_int_equal(a.used, 0); /* nothing allocated on refusal */
    hz_scene_plan_t plan;
    assert_int_equal(hz_scene_plan(fx.image, fx.size, &plan, NULL), HZ_OK);
    assert_true(plan.arena_bytes > 4096);
    assert_int_equal(plan.animated_vertices, 24 + 561 + 187);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builtin_loads_with_every_feature),
        cmocka_unit_test(test_builtin_is_deterministic),
        cmocka_unit_test(test_animation_moves_only_moving_objects),
        cmocka_unit_test(test_camera_path),
        cmocka_unit_test(test_tiny_round_trip),
        cmocka_unit_test(test_refuses_bad_headers),
        cmocka_unit_test(test_refuses_bad_sections),
        cmocka_unit_test(test_refuses_bad_content),
        cmocka_unit_test(test_arena_refusal_names_both_counts),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
