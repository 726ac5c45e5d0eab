/* Runtime skinning (hz/skin.h, HZ_MOTION_SKIN in hz/hzb.h): the board's SIMD blend against its scalar twin and
 * both against a double-precision oracle written here; a hand-made skinned scene whose poses are known in closed
 * form (a joint turning 90 degrees about z); version 1 files still load and cannot carry skinning; and corrupt
 * skinning sections, each refused with the right status and a message naming the problem. */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/crc32.h"
#include "hz/hzb_write.h"
#include "hz/scene.h"
#include "hzb_reseal.h"
#include "hz/skin.h"

#define N 1003 /* odd: no lane count divides it */
#define BINDS 7

static float mats[BINDS * HZ_SKIN_MAT_FLOATS] HZ_ALIGNED(64);
static float rest_pos[N * 4] HZ_ALIGNED(64), rest_nrm[N * 4] HZ_ALIGNED(64);
static float pos_a[N * 4] HZ_ALIGNED(64), nrm_a[N * 4] HZ_ALIGNED(64);
static float pos_b[N * 4] HZ_ALIGNED(64), nrm_b[N * 4] HZ_ALIGNED(64);
static hz_hzb_skin_weight_t weights[N];

static uint32_t rng = 12345u;
static float frand(float lo, float hi)
{
    rng = rng * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)(rng >> 8) / 16777216.0f;
}

static void random_input(void)
{
    for (int b = 0; b < BINDS; b++) {
        float *m = mats + b * HZ_SKIN_MAT_FLOATS;
        for (int c = 0; c < 4; c++) {
            for (int r = 0; r < 3; r++)
                m[c * 4 + r] = c == 3 ? frand(-5.0f, 5.0f) : (c == r ? 1.0f : 0.0f) + frand(-0.6f, 0.6f);
            m[c * 4 + 3] = 0.0f;
        }
    }
    for (int i = 0; i < N; i++) {
        for (int c = 0; c < 3; c++) {
            rest_pos[i * 4 + c] = frand(-3.0f, 3.0f);
            rest_nrm[i * 4 + c] = frand(-1.0f, 1.0f);
        }
        rest_pos[i * 4 + 3] = rest_nrm[i * 4 + 3] = 0.0f;
        float l = sqrtf(rest_nrm[i * 4] * rest_nrm[i * 4] + rest_nrm[i * 4 + 1] * rest_nrm[i * 4 + 1] +
                        rest_nrm[i * 4 + 2] * rest_nrm[i * 4 + 2]);
        for (int c = 0; c < 3; c++)
            rest_nrm[i * 4 + c] /= l;
        /* 1 to 4 influences, unorm16 summing to 65535. */
        int k = 1 + i % 4;
        uint32_t left = 65535;
        memset(&weights[i], 0, sizeof weights[i]);
        for (int j = 0; j < k; j++) {
            weights[i].bind[j] = (uint16_t)((i * 3 + j * 5) % BINDS);
            uint32_t w = j + 1 == k ? left : (uint32_t)frand(0.0f, (float)left);
            weights[i].weight[j] = (uint16_t)w;
            left -= w;
        }
    }
}

static void test_simd_matches_scalar_and_oracle(void **state)
{
    (void)state;
    random_input();
    print_message("blend path: %s\n", hz_skin_blend_path());
#if defined(HZ_BOARD_SIMD_AVX2)
    assert_string_equal(hz_skin_blend_path(), "avx2");
#elif defined(HZ_BOARD_SIMD_NEON)
    assert_string_equal(hz_skin_blend_path(), "neon");
#endif
    hz_skin_blend(mats, weights, rest_pos, rest_nrm, N, pos_a, nrm_a);
    hz_skin_blend_scalar(mats, weights, rest_pos, rest_nrm, N, pos_b, nrm_b);
    double worst_simd = 0, worst_oracle = 0;
    for (int i = 0; i < N; i++) {
        /* Oracle: sum_k w_k (M_k p) in double, normal normalised. */
        double p[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 };
        for (int k = 0; k < 4; k++) {
            double w = weights[i].weight[k] / 65535.0;
            const float *m = mats + weights[i].bind[k] * HZ_SKIN_MAT_FLOATS;
            for (int r = 0; r < 3; r++) {
                p[r] += w * ((double)m[r] * rest_pos[i * 4] + (double)m[4 + r] * rest_pos[i * 4 + 1] +
                             (double)m[8 + r] * rest_pos[i * 4 + 2] + m[12 + r]);
                n[r] += w * ((double)m[r] * rest_nrm[i * 4] + (double)m[4 + r] * rest_nrm[i * 4 + 1] +
                             (double)m[8 + r] * rest_nrm[i * 4 + 2]);
            }
        }
        double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int r = 0; r < 3; r++) {
            worst_simd = fmax(worst_simd, fabs((double)pos_a[i * 4 + r] - pos_b[i * 4 + r]));
            worst_simd = fmax(worst_simd, fabs((double)nrm_a[i * 4 + r] - nrm_b[i * 4 + r]));
            worst_oracle = fmax(worst_oracle, fabs(pos_b[i * 4 + r] - p[r]));
            worst_oracle = fmax(worst_oracle, fabs(nrm_b[i * 4 + r] - n[r] / nl));
        }
        assert_true(pos_a[i * 4 + 3] == 0.0f && nrm_a[i * 4 + 3] == 0.0f);
        assert_true(pos_b[i * 4 + 3] == 0.0f && nrm_b[i * 4 + 3] == 0.0f);
    }
    print_message("max |simd - scalar| %.3g, max |scalar - oracle| %.3g (coordinates up to ~20)\n", worst_simd,
                  worst_oracle);
    /* Float rounding of ~20 products of magnitude <= 20: a few ulps of 20 (2^-19 = 1.9e-6 each). */
    assert_true(worst_simd < 1e-5);
    assert_true(worst_oracle < 1e-5);
    /* Without normals only positions are written. */
    memset(nrm_a, 0x55, sizeof nrm_a);
    hz_skin_blend(mats, weights, rest_pos, NULL, N, pos_a, nrm_a);
    assert_true(nrm_a[0] != 0.0f);
}

/* ---- a hand-made skinned scene ---- */

/* Object 0 (skinned): joint 0 never moves, joint 1 turns from 0 to 90 degrees about z between t = 0 and 1 s.
 * v0 = (1,0,0) follows joint 1, v1 = (0,1,0) joint 0, v2 = (2,0,0) half each. Object 1: a static triangle. */
typedef struct skin_scene {
    float pos[6 * 4], nrm[6 * 4];
    uint32_t tri[2 * 3], info[2];
    hz_hzb_material_t mat;
    hz_hzb_object_t obj[2];
    hz_hzb_rigid_key_t keys[3];
    hz_hzb_joint_t joints[2];
    hz_hzb_skin_bind_t binds[2];
    hz_hzb_skin_weight_t w[6];
    hz_hzb_source_t src;
} skin_scene_t;

static uint8_t image[1 << 16] HZ_ALIGNED(64);
static uint8_t arena_mem[1 << 16] HZ_ALIGNED(64);
static size_t image_size;

static void unit_key(hz_hzb_rigid_key_t *k, float time, float angle_z)
{
    memset(k, 0, sizeof *k);
    k->time = time;
    k->rotation[2] = sinf(angle_z / 2), k->rotation[3] = cosf(angle_z / 2);
    k->scale[0] = k->scale[1] = k->scale[2] = 1.0f;
}

static void build(skin_scene_t *s)
{
    memset(s, 0, sizeof *s);
    static const float p[6][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 2, 0, 0 }, { 5, 5, 5 }, { 6, 5, 5 }, { 5, 6, 5 } };
    for (int v = 0; v < 6; v++) {
        memcpy(s->pos + v * 4, p[v], sizeof p[v]);
        s->nrm[v * 4 + 2] = 1.0f;
    }
    s->nrm[0 * 4 + 2] = 0.0f, s->nrm[0 * 4 + 0] = 1.0f; /* v0's normal along x: it turns with joint 1 */
    s->tri[0] = 0, s->tri[1] = 1, s->tri[2] = 2, s->tri[3] = 3, s->tri[4] = 4, s->tri[5] = 5;
    s->info[0] = 0, s->info[1] = 1u << 16;
    s->mat.base_color[0] = s->mat.base_color[1] = s->mat.base_color[2] = 0.5f;
    s->mat.alpha = 1.0f, s->mat.base_texture = s->mat.alpha_texture = -1;
    s->obj[0].triangle_count = 1, s->obj[0].vertex_count = 3, s->obj[0].motion = HZ_MOTION_SKIN;
    s->obj[0].key_first = 0, s->obj[0].key_count = 2;
    s->obj[1].first_triangle = 1, s->obj[1].triangle_count = 1, s->obj[1].first_vertex = 3;
    s->obj[1].vertex_count = 3;
    unit_key(&s->keys[0], 0.0f, 0.0f);
    unit_key(&s->keys[1], 0.0f, 0.0f);
    unit_key(&s->keys[2], 1.0f, (float)HZ_PI / 2);
    s->joints[0].key_first = 0, s->joints[0].key_count = 1;
    s->joints[1].key_first = 1, s->joints[1].key_count = 2;
    for (int b = 0; b < 2; b++) {
        s->binds[b].joint = (uint32_t)b;
        s->binds[b].inv_bind[0] = s->binds[b].inv_bind[4] = s->binds[b].inv_bind[8] = 1.0f;
    }
    s->w[0].bind[0] = 1, s->w[0].weight[0] = 65535;
    s->w[1].bind[0] = 0, s->w[1].weight[0] = 65535;
    s->w[2].bind[0] = 0, s->w[2].weight[0] = 32768, s->w[2].bind[1] = 1, s->w[2].weight[1] = 32767;
    hz_hzb_source_t *src = &s->src;
    src->name = "skin";
    src->vertex_count = 6, src->positions = s->pos, src->normals = s->nrm;
    src->triangle_count = 2, src->triangles = s->tri, src->tri_info = s->info;
    src->material_count = 1, src->materials = &s->mat;
    src->object_count = 2, src->objects = s->obj;
    src->rigid_key_count = 3, src->rigid_keys = s->keys;
    src->joint_count = 2, src->joints = s->joints;
    src->skin_bind_count = 2, src->skin_binds = s->binds;
    src->skin_weights = s->w;
}

static hz_status_t write_image(const skin_scene_t *s)
{
    hz_error_t err;
    return hz_hzb_write(&s->src, image, sizeof image, &image_size, &err);
}

static void near3(const float *got, float x, float y, float z)
{
    if (!(fabsf(got[0] - x) < 1e-4f && fabsf(got[1] - y) < 1e-4f && fabsf(got[2] - z) < 1e-4f))
        fail_msg("got (%g %g %g), want (%g %g %g)", (double)got[0], (double)got[1], (double)got[2], (double)x,
                 (double)y, (double)z);
}

static void test_known_poses(void **state)
{
    (void)state;
    skin_scene_t s;
    build(&s);
    assert_int_equal(write_image(&s), HZ_OK);
    hz_arena_t a;
    hz_arena_init(&a, "scene", arena_mem, sizeof arena_mem);
    hz_scene_t sc;
    hz_error_t err;
    if (hz_scene_load(&sc, image, image_size, &a, &err) != HZ_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(sc.header->version, HZ_HZB_VERSION);
    assert_true(sc.features & HZ_FEAT_SKINNING);
    assert_int_equal(sc.plan.skin_bytes, 2 * HZ_SKIN_MAT_BYTES + HZ_HZB_ALIGN);
    assert_true(a.used <= sc.plan.arena_bytes);
    near3(sc.pos + 0, 1, 0, 0); /* t = 0: the bind pose */
    hz_scene_animate(&sc, 1.0f);
    near3(sc.pos + 0, 0, 1, 0);
    near3(sc.nrm + 0, 0, 1, 0);
    near3(sc.pos + 4, 0, 1, 0);
    near3(sc.pos + 8, 1.0f + 1.0f / 65535.0f, 1.0f - 1.0f / 65535.0f, 0); /* 32768/65535 of (2,0,0) + 32767/65535 of (0,2,0) */
    near3(sc.prev_pos + 0, 1, 0, 0);
    near3(sc.pos + 12, 5, 5, 5); /* the static object is untouched */
    hz_scene_animate(&sc, 0.5f); /* nlerp halfway between 0 and 90 degrees is 45 degrees */
    near3(sc.pos + 0, sqrtf(0.5f), sqrtf(0.5f), 0);
    hz_scene_animate(&sc, 7.0f); /* no loop: holds after the last key */
    near3(sc.pos + 0, 0, 1, 0);
    /* pose_at writes the same pose into other arrays and changes nothing in the scene. */
    float p2[6 * 4], n2[6 * 4];
    memset(p2, 0, sizeof p2);
    hz_scene_pose_at(&sc, 0.25f, 0.25f, p2, n2);
    near3(p2 + 0, sqrtf(0.5f), sqrtf(0.5f), 0);
    near3(sc.pos + 0, 0, 1, 0);
}

/* ---- versions ---- */

static hz_status_t plan(hz_error_t *err)
{
    return hz_scene_plan(image, image_size, NULL, err);
}

#define EXPECT(code, needle)                                                                                \
    do {                                                                                                    \
        hz_error_t err_;                                                                                    \
        hz_status_t s_ = plan(&err_);                                                                       \
        if (s_ != (code) || !strstr(err_.msg, (needle)))                                                    \
            print_error("got %s: '%s', want '%s'\n", hz_status_str(s_), s_ ? err_.msg : "", (needle));      \
        assert_int_equal(s_, (code));                                                                       \
        assert_non_null(strstr(err_.msg, (needle)));                                                        \
    } while (0)

static void set_version(uint32_t v)
{
    hz_hzb_header_t *h = (hz_hzb_header_t *)image;
    h->version = v;
    reseal(image, image_size);
}

static void test_version_1_loads_without_skinning(void **state)
{
    (void)state;
    skin_scene_t s;
    build(&s);
    s.obj[0].motion = HZ_MOTION_NONE, s.obj[0].key_count = 0;
    s.src.joint_count = 0, s.src.joints = NULL, s.src.skin_bind_count = 0, s.src.skin_binds = NULL;
    s.src.skin_weights = NULL, s.src.rigid_key_count = 0, s.src.rigid_keys = NULL;
    assert_int_equal(write_image(&s), HZ_OK);
    set_version(1);
    hz_error_t err;
    assert_int_equal(plan(&err), HZ_OK); /* a version 1 file, as the old baker wrote it */
    set_version(0);
    EXPECT(HZ_E_VERSION, "versions 1 to 2");
    /* A version 1 file cannot carry version 2 sections or counts. */
    build(&s);
    assert_int_equal(write_image(&s), HZ_OK);
    set_version(1);
    EXPECT(HZ_E_FORMAT, "version 1 header with skinning counts");
}

/* ---- corrupt skinning sections ---- */

static void *section(uint32_t id)
{
    hz_hzb_header_t h;
    memcpy(&h, image, sizeof h);
    for (uint32_t i = 0; i < h.section_count; i++) {
        hz_hzb_section_t e;
        memcpy(&e, image + sizeof h + i * sizeof e, sizeof e);
        if (e.id == id)
            return image + e.offset;
    }
    fail_msg("no section %u", id);
    return NULL;
}

static void test_corrupt_skin_sections(void **state)
{
    (void)state;
    skin_scene_t s;
    hz_error_t err;
    build(&s);
    assert_int_equal(write_image(&s), HZ_OK);
    assert_int_equal(plan(&err), HZ_OK);

#define CASE(patch, code, needle)                                                                           \
    do {                                                                                                    \
        assert_int_equal(write_image(&s), HZ_OK);                                                           \
        patch;                                                                                              \
        reseal(image, image_size);                                                                          \
        EXPECT(code, needle);                                                                               \
    } while (0)
    hz_hzb_joint_t *j;
    hz_hzb_skin_bind_t *b;
    hz_hzb_skin_weight_t *w;
    hz_hzb_object_t *o;
    CASE((b = section(HZ_SEC_SKIN_BINDS), b[1].joint = 2), HZ_E_RANGE, "skin bind 1: joint 2, the scene has 2");
    CASE((b = section(HZ_SEC_SKIN_BINDS), b[0].reserved[1] = 1), HZ_E_FORMAT, "skin bind 0: reserved");
    CASE((b = section(HZ_SEC_SKIN_BINDS), b[0].inv_bind[5] = NAN), HZ_E_RANGE, "inverse bind matrix element 5");
    CASE((b = section(HZ_SEC_SKIN_BINDS), b[0].inv_bind[9] = 1e12f), HZ_E_RANGE, "beyond");
    CASE((j = section(HZ_SEC_JOINTS), j[1].key_count = 3), HZ_E_RANGE, "joint 1: rigid keys 1..4 outside the 3");
    CASE((j = section(HZ_SEC_JOINTS), j[1].key_count = 0), HZ_E_RANGE, "joint 1: rigid keys");
    CASE((j = section(HZ_SEC_JOINTS), memset(j[0].name, 'x', sizeof j[0].name)), HZ_E_FORMAT,
         "joint 0: name not terminated");
    CASE((j = section(HZ_SEC_JOINTS), j[0].reserved[0] = 7), HZ_E_FORMAT, "joint 0: name not terminated or reserved");
    CASE((w = section(HZ_SEC_SKIN_WEIGHTS), w[0].weight[0] = 65534), HZ_E_RANGE,
         "skin weights of vertex 0 sum to 65534, not 65535");
    CASE((w = section(HZ_SEC_SKIN_WEIGHTS), w[2].bind[1] = 2), HZ_E_RANGE,
         "skin weights of vertex 2: bind 2, its object 0 has 2");
    CASE((w = section(HZ_SEC_SKIN_WEIGHTS), w[4].weight[0] = 1), HZ_E_FORMAT,
         "skin weights of vertex 4 are not zero, its object 1 is not skinned");
    CASE((o = section(HZ_SEC_OBJECTS), o[0].key_count = 3), HZ_E_RANGE, "object 0: skin binds 0..3 outside the 2");
    CASE((o = section(HZ_SEC_OBJECTS), o[0].key_count = 0), HZ_E_RANGE, "object 0: skin binds");
    CASE((o = section(HZ_SEC_OBJECTS), o[0].motion = 7), HZ_E_RANGE, "unknown motion kind 7");
    /* A key of joint 1 that is not a unit rotation. */
    {
        hz_hzb_rigid_key_t *k;
        CASE((k = section(HZ_SEC_RIGID_KEYS), k[2].rotation[3] = 3.0f), HZ_E_RANGE,
             "joint 1: rigid key 1 is not finite or its rotation is not unit");
        CASE((k = section(HZ_SEC_RIGID_KEYS), k[2].time = 0.0f), HZ_E_RANGE,
             "joint 1: rigid key times do not increase at key 1");
    }
    /* Header counts against the sections. */
    CASE(((hz_hzb_header_t *)image)->joint_count = 3, HZ_E_FORMAT, "section 'joints' has 2 elements, the header says 3");
    CASE(((hz_hzb_header_t *)image)->skin_bind_count = 1, HZ_E_FORMAT, "'skin_binds' has 2 elements");
#undef CASE
    /* Sections that must come together. */
    s.src.skin_weights = NULL;
    assert_int_equal(write_image(&s), HZ_OK);
    EXPECT(HZ_E_FORMAT, "object 0 is skinned but section 'skin_weights' is missing");
    build(&s);
    s.obj[0].motion = HZ_MOTION_NONE;
    s.obj[0].key_count = 0;
    assert_int_equal(write_image(&s), HZ_OK);
    EXPECT(HZ_E_FORMAT, "section 'skin_weights' is present but no object is skinned");
    build(&s);
    s.src.joint_count = 0, s.src.joints = NULL;
    assert_int_equal(write_image(&s), HZ_OK);
    EXPECT(HZ_E_RANGE, "skin bind 0: joint 0, the scene has 0");
    /* Truncated anywhere inside the skinning sections: refused, never read past the end. */
    build(&s);
    assert_int_equal(write_image(&s), HZ_OK);
    size_t full = image_size;
    for (size_t cut = full - 1; cut > full - 400; cut -= 13) {
        image_size = cut;
        assert_int_not_equal(plan(&err), HZ_OK);
    }
    image_size = full;
}

/* The arena must hold the joint matrices too: one byte less than the plan is refused up front. */
static void test_arena_plan_includes_joint_matrices(void **state)
{
    (void)state;
    skin_scene_t s;
    build(&s);
    assert_int_equal(write_image(&s), HZ_OK);
    hz_scene_plan_t p;
    hz_error_t err;
    assert_int_equal(hz_scene_plan(image, image_size, &p, &err), HZ_OK);
    hz_arena_t a;
    hz_arena_init(&a, "scene", arena_mem, p.arena_bytes - 1);
    hz_scene_t sc;
    assert_int_equal(hz_scene_load(&sc, image, image_size, &a, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "arena 'scene'"));
    hz_arena_init(&a, "scene", arena_mem, p.arena_bytes);
    assert_int_equal(hz_scene_load(&sc, image, image_size, &a, &err), HZ_OK);
    assert_non_null(sc.skin_mats);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_simd_matches_scalar_and_oracle),
        cmocka_unit_test(test_known_poses),
        cmocka_unit_test(test_version_1_loads_without_skinning),
        cmocka_unit_test(test_corrupt_skin_sections),
        cmocka_unit_test(test_arena_plan_includes_joint_matrices),
    };
    return HZ_RUN(tests);
}
