/* Pose keys (hz/posekeys.h) on the built-in scene: hz_scene_pose_at gives what hz_scene_animate gives at the same
 * time and leaves the scene alone, keys hold the poses at the interval's ends and evenly in between, the key
 * count follows the motion (worked out by hand from the scene's parameters), rigid objects become instances whose
 * matrices reproduce the posed keys, and bad requests are refused. */
#include "hz_test.h"

#include <math.h>
#include <string.h>

#include "hz/builtin.h"
#include "hz/posekeys.h"
#include "hz/scene.h"

static uint8_t image_mem[4 << 20] HZ_ALIGNED(64);
static uint8_t scratch_mem[8 << 20] HZ_ALIGNED(64);
static uint8_t state_mem[1 << 20] HZ_ALIGNED(64);
static uint8_t keys_mem[8 << 20] HZ_ALIGNED(64);
static float copy_pos[1 << 17] HZ_ALIGNED(64), copy_nrm[1 << 17] HZ_ALIGNED(64);

static hz_arena_t images, scratch, st, karena;
static hz_scene_t sc;

static int setup(void **state)
{
    (void)state;
    hz_arena_init(&images, "images", image_mem, sizeof image_mem);
    hz_arena_init(&scratch, "scratch", scratch_mem, sizeof scratch_mem);
    hz_arena_init(&st, "scene", state_mem, sizeof state_mem);
    hz_arena_init(&karena, "keys", keys_mem, sizeof keys_mem);
    const void *img;
    size_t size;
    hz_error_t err;
    if (hz_builtin_scene_image(&images, &scratch, &img, &size, &err) != HZ_OK ||
        hz_scene_load(&sc, img, size, &st, &err) != HZ_OK) {
        print_error("builtin: %s\n", err.msg);
        return -1;
    }
    return (size_t)sc.vertex_count * 4 <= sizeof copy_pos / sizeof copy_pos[0] ? 0 : -1;
}

static void test_pose_at_matches_animate_and_mutates_nothing(void **state)
{
    (void)state;
    size_t n = (size_t)sc.vertex_count * 4;
    hz_scene_animate(&sc, 2.0f);
    float before[8];
    memcpy(before, sc.pos, sizeof before);
    memcpy(copy_pos, sc.pos, n * sizeof(float));
    memcpy(copy_nrm, sc.nrm, n * sizeof(float));
    /* Pose at 2 + 0.75 into copies: the scene's own arrays and time stay. */
    hz_scene_pose_at(&sc, 2.0f, 0.75f, copy_pos, copy_nrm);
    assert_true(sc.time == 2.0f);
    assert_memory_equal(before, sc.pos, sizeof before);
    hz_scene_animate(&sc, 2.75f);
    assert_memory_equal(copy_pos, sc.pos, n * sizeof(float));
    assert_memory_equal(copy_nrm, sc.nrm, n * sizeof(float));
}

static void test_count_follows_motion(void **state)
{
    (void)state;
    /* Built-in scene: spin pi/2 rad/s, oscillation 0.25 Hz (phase pi/2 rad/s), flag vertex keys at 30/s
     * (FLAG_RATE). Segments needed over I seconds: max(pi/2 I / 0.1, pi/2 I / 0.1, 30 I), at least 1. */
    assert_int_equal(hz_posekeys_count(&sc, 1.0f / 240.0f), 2); /* max(0.065, 0.125) -> 1 segment */
    assert_int_equal(hz_posekeys_count(&sc, 0.05f), 3);         /* max(0.785, 1.5) -> 2 */
    assert_int_equal(hz_posekeys_count(&sc, 0.1f), 5);          /* max(1.57, 3) -> 4 */
    assert_int_equal(hz_posekeys_count(&sc, 0.2f), 9);          /* max(3.14, 6) -> 8 */
    assert_int_equal(hz_posekeys_count(&sc, 5.0f), 9);          /* capped at 8 segments */
    assert_int_equal(hz_posekeys_bytes(&sc, 1), 0);
    assert_true(hz_posekeys_bytes(&sc, 3) >= 3u * 2u * sc.vertex_count * 16u);
}

static void test_keys_span_the_interval(void **state)
{
    (void)state;
    hz_posekeys_t k;
    hz_error_t err;
    hz_arena_reset(&karena, 0);
    assert_int_equal(hz_posekeys_init(&k, &sc, 5, &karena, &err), HZ_OK);
    assert_int_equal(k.count, 5);
    hz_posekeys_eval(&k, &sc, 1.0f, -0.1f, 0.3f);
    size_t n = (size_t)sc.vertex_count * 4;
    for (uint32_t i = 0; i < 5; i++) {
        float dt = i == 4 ? 0.3f : -0.1f + 0.4f * ((float)i / 4.0f);
        hz_scene_animate_ns(&sc, hz_time_from_s(1.0) + hz_time_from_s(dt)); /* t + dt, summed in ns */
        assert_memory_equal(k.pos[i], sc.pos, n * sizeof(float));
        assert_memory_equal(k.nrm[i], sc.nrm, n * sizeof(float));
    }
    /* Interpolation reproduces the keys at their times, clamps outside [0, 1], takes NaN as 0. */
    uint32_t v = sc.objects[0].first_vertex;
    for (uint32_t o = 0; o < sc.object_count; o++)
        if (sc.objects[o].motion == HZ_MOTION_SPIN)
            v = sc.objects[o].first_vertex;
    hz_vec3_t a = hz_posekeys_lerp(&k, k.pos, v, 0.25f), b = hz_posekeys_lerp(&k, k.pos, v, 1.0f);
    assert_true(a.x == k.pos[1][v * 4] && a.y == k.pos[1][v * 4 + 1] && a.z == k.pos[1][v * 4 + 2]);
    assert_true(b.x == k.pos[4][v * 4] && b.z == k.pos[4][v * 4 + 2]);
    hz_vec3_t c = hz_posekeys_lerp(&k, k.pos, v, NAN), d = hz_posekeys_lerp(&k, k.pos, v, 7.0f);
    assert_true(c.x == k.pos[0][v * 4] && d.x == k.pos[4][v * 4]);
    hz_vec3_t m = hz_posekeys_lerp(&k, k.pos, v, 0.125f); /* half-way between keys 0 and 1 */
    assert_true(fabsf(m.x - 0.5f * (k.pos[0][v * 4] + k.pos[1][v * 4])) < 1e-5f);
    /* Geometry view: K keys, pos = the middle one. */
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    hz_posekeys_geom(&k, &g);
    assert_int_equal(g.time_keys, 5);
    assert_ptr_equal(g.pos, k.pos[2]);
    assert_ptr_equal(g.pos_keys[4], k.pos[4]);
    assert_null(g.pos_keys[5]);
}

/* Rigid instances: every rigidly moving object of the built-in scene lies in exactly one instance, nothing else
 * does, and each instance's matrix at each key moves its rest positions onto that key's posed positions (which
 * hz_scene_pose_at computes on its own, vertex by vertex). The flag moves by vertex keys: the rest moves. */
static void test_rigid_instances(void **state)
{
    (void)state;
    hz_posekeys_t k;
    hz_error_t err;
    hz_arena_reset(&karena, 0);
    assert_int_equal(hz_posekeys_init(&k, &sc, 3, &karena, &err), HZ_OK);
    hz_posekeys_eval(&k, &sc, 1.5f, -0.2f, 0.2f);
    uint32_t rigid = 0;
    for (uint32_t o = 0; o < sc.object_count; o++) {
        const hz_hzb_object_t *ob = &sc.objects[o];
        const bool is_rigid = ob->motion == HZ_MOTION_SPIN || ob->motion == HZ_MOTION_OSCILLATE ||
                              ob->motion == HZ_MOTION_RIGID;
        rigid += is_rigid && ob->triangle_count;
        uint32_t in = 0;
        for (uint32_t i = 0; i < k.instance_count; i++)
            in += ob->first_triangle >= k.inst[i].tri_first &&
                  ob->first_triangle + ob->triangle_count <= k.inst[i].tri_first + k.inst[i].tri_count;
        assert_int_equal(in, is_rigid && ob->triangle_count ? 1u : 0u);
    }
    assert_true(rigid >= 2); /* a spinning and an oscillating object */
    assert_true(k.instance_count >= 2 && k.instance_count <= rigid);
    assert_false(k.static_rest);
    for (uint32_t i = 0; i < k.instance_count; i++)
        for (uint32_t key = 0; key < 3; key++) {
            const float *m = k.inst[i].xform[key];
            assert_ptr_equal(m, k.xform[i][key]);
            for (uint32_t t = k.inst[i].tri_first; t < k.inst[i].tri_first + k.inst[i].tri_count; t++)
                for (int c = 0; c < 3; c++) {
                    const uint32_t v = sc.tri[3u * t + (uint32_t)c];
                    const float *p = k.inst[i].obj_pos + 4u * v, *q = k.pos[key] + 4u * v;
                    for (int r = 0; r < 3; r++) {
                        const float x = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
                        assert_true(fabsf(x - q[r]) <= 1e-5f * (1.0f + fabsf(q[r])));
                    }
                }
        }
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    hz_posekeys_geom(&k, &g);
    assert_int_equal(g.instance_count, k.instance_count);
    assert_ptr_equal(g.instances, k.inst);
    assert_false(g.static_rest);
}

static void test_refusals(void **state)
{
    (void)state;
    hz_posekeys_t k;
    hz_error_t err;
    hz_arena_reset(&karena, 0);
    assert_int_equal(hz_posekeys_init(&k, &sc, 4, &karena, &err), HZ_E_INVALID_ARG);
    assert_non_null(strstr(err.msg, "4 time keys"));
    static uint8_t small[4096] HZ_ALIGNED(64);
    hz_arena_t a;
    hz_arena_init(&a, "tiny", small, sizeof small);
    assert_int_equal(hz_posekeys_init(&k, &sc, 2, &a, &err), HZ_E_NO_MEMORY);
    assert_non_null(strstr(err.msg, "tiny"));
    assert_int_equal(a.used, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_at_matches_animate_and_mutates_nothing),
        cmocka_unit_test(test_count_follows_motion),
        cmocka_unit_test(test_keys_span_the_interval),
        cmocka_unit_test(test_rigid_instances),
        cmocka_unit_test(test_refusals),
    };
    return HZ_RUN_GROUP(tests, setup, NULL);
}
