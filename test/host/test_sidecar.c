/* Sidecar parser (programs/hzbake/sidecar.c): a complete valid sidecar reads back exactly, and each kind of mistake
 * is refused with "FILE:LINE: reason", the right line and the right status. */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sidecar.h"

static hz_status_t parse(hz_bake_sidecar_t *sc, const char *text, hz_error_t *err)
{
    hz_bake_sidecar_defaults(sc);
    hz_error_clear(err);
    return hz_bake_sidecar_parse(sc, "t.hzs", text, strlen(text), err);
}

static void test_full_sidecar_reads_back(void **state)
{
    (void)state;
    const char *text = "# comment line\n"
                       "name = My Scene   # trailing comment\n"
                       "background = 0.1 0.2 0.3\n"
                       "ambient = 0 0 0.5\n"
                       "duration = 8\n"
                       "camera_loop = yes\n"
                       "texture_max = 256\n"
                       "tube_sides = 5\n"
                       "light = position 1 2 3 color 4 5 6\n"
                       "light = color 1 1 1 position -1 -2 -3 falloff none\n"
                       "camera = 0 eye 0 1 5 target 0 1 0\n"
                       "camera = 2.5 eye 1 1 5 target 0 1 0 up 0 0 1 fov 30\n"
                       "fov = 50\n"
                       "\n"
                       "[material \"tall Box\"]\n"
                       "mirror = 0.95\n"
                       "alpha_mode = blend\n"
                       "alpha = 0.25\n"
                       "[material leaf*]\n"
                       "alpha_mode = mask\n"
                       "alpha_cutoff = 0.3\n"
                       "[object fur]\n"
                       "motion = spin\n"
                       "pivot = center\n"
                       "axis = 0 2 0\n"
                       "speed = 15\n"
                       "[object box]\n"
                       "motion = keys\n"
                       "key = 0 translate 0 0 0\n"
                       "key = 1 translate 0 1 0 rotate 0 1 0 90 scale 2\n"
                       "key = 2 scale 1 2 3\n"
                       "[scene]\n"
                       "smooth_angle = 30\n";
    hz_bake_sidecar_t sc;
    hz_error_t err;
    assert_int_equal(parse(&sc, text, &err), HZ_OK);
    assert_string_equal(sc.name, "My Scene");
    assert_true(sc.background[2] == 0.3f && sc.ambient[2] == 0.5f && sc.duration == 8.0f && sc.camera_loop);
    assert_int_equal(sc.texture_max, 256);
    assert_int_equal(sc.tube_sides, 5);
    assert_true(sc.smooth_angle_deg == 30.0f);
    assert_int_equal(sc.lights.len, 2);
    const hz_hzb_light_t *l = HZ_BAKE_AT(sc.lights, hz_hzb_light_t, 1);
    assert_true(l->position[0] == -1.0f && l->color[0] == 1.0f && l->falloff == HZ_FALLOFF_NONE);
    assert_int_equal(HZ_BAKE_AT(sc.lights, hz_hzb_light_t, 0)->falloff, HZ_FALLOFF_INV_SQUARE);
    assert_int_equal(sc.cameras.len, 2);
    const hz_bake_sc_camera_t *c0 = HZ_BAKE_AT(sc.cameras, hz_bake_sc_camera_t, 0),
                              *c1 = HZ_BAKE_AT(sc.cameras, hz_bake_sc_camera_t, 1);
    /* A key without fov takes the scene's fov even when `fov =` comes later in the file. */
    assert_true(c0->key.fov_y > 0.8726f && c0->key.fov_y < 0.8728f); /* 50 degrees */
    assert_true(c1->key.fov_y > 0.5235f && c1->key.fov_y < 0.5237f); /* 30 degrees */
    assert_true(c0->key.up[1] == 1.0f && c1->key.up[2] == 1.0f && c1->key.time == 2.5f);
    assert_int_equal(sc.materials.len, 2);
    const hz_bake_sc_material_t *m0 = HZ_BAKE_AT(sc.materials, hz_bake_sc_material_t, 0);
    assert_string_equal(m0->pattern, "tall Box");
    assert_true(m0->mirror == 0.95f && m0->alpha == 0.25f && m0->alpha_mode == HZ_ALPHA_BLEND);
    assert_int_equal(m0->set, HZ_BAKE_SC_MIRROR | HZ_BAKE_SC_ALPHA_MODE | HZ_BAKE_SC_ALPHA);
    assert_int_equal(sc.objects.len, 2);
    const hz_bake_sc_object_t *o0 = HZ_BAKE_AT(sc.objects, hz_bake_sc_object_t, 0),
                              *o1 = HZ_BAKE_AT(sc.objects, hz_bake_sc_object_t, 1);
    assert_int_equal(o0->motion, HZ_MOTION_SPIN);
    assert_true(o0->pivot_center && o0->axis[1] == 2.0f && o0->speed_deg == 15.0f);
    assert_int_equal(o1->motion, HZ_MOTION_RIGID);
    assert_int_equal(o1->keys.len, 3);
    const hz_bake_sc_key_t *k1 = HZ_BAKE_AT(o1->keys, hz_bake_sc_key_t, 1),
                           *k2 = HZ_BAKE_AT(o1->keys, hz_bake_sc_key_t, 2);
    assert_true(k1->translate[1] == 1.0f && k1->angle_deg == 90.0f && k1->scale[2] == 2.0f);
    assert_true(k2->scale[0] == 1.0f && k2->scale[1] == 2.0f && k2->scale[2] == 3.0f);
    hz_bake_sidecar_free(&sc);
}

typedef struct bad {
    const char *text;
    int line; /* expected line in "t.hzs:LINE:"; 0: no line (a whole-file check) */
    hz_status_t code;
    const char *reason; /* a fragment the message must contain */
} bad_t;

static const bad_t bad_cases[] = {
    { "name = a\nfoo = 1\n", 2, HZ_E_FORMAT, "unknown key 'foo'" },
    { "duration = 1\nduration = 2\n", 2, HZ_E_FORMAT, "given twice" },
    { "duration = abc\n", 1, HZ_E_FORMAT, "not a number" },
    { "duration = nan\n", 1, HZ_E_FORMAT, "not a number" },
    { "duration = inf\n", 1, HZ_E_FORMAT, "not a number" },
    { "duration = 0x10\n", 1, HZ_E_FORMAT, "not a number" },
    { "duration = -1\n", 1, HZ_E_RANGE, "outside" },
    { "\n\n[material a]\nmirror = 1.5\n", 4, HZ_E_RANGE, "outside [0, 1]" },
    { "background = 1 2\n", 1, HZ_E_FORMAT, "three numbers" },
    { "texture_max = 1.5\n", 1, HZ_E_FORMAT, "not an integer" },
    { "texture_max = 0\n", 1, HZ_E_RANGE, "outside" },
    { "name = a\ntube_sides = 2\n", 2, HZ_E_RANGE, "tube_sides = 2" }, /* with its line */
    /* a section NAME given twice: the later section would silently take over the earlier one */
    { "[object a]\nmotion = none\n[object a]\nmotion = none\n", 3, HZ_E_FORMAT, "repeats the section of line 1" },
    { "[material m]\nmirror = 1\n\n[material m]\nalpha = 0.5\n", 4, HZ_E_FORMAT, "repeats the section of line 1" },
    { "camera_loop = maybe\n", 1, HZ_E_FORMAT, "yes or no" },
    { "camera_loop = yes\n", 0, HZ_E_FORMAT, "needs a duration" },
    { "duration = 4\ncamera_loop = yes\ncamera = 4 eye 0 0 1 target 0 0 0\n", 3, HZ_E_RANGE, "below the duration" },
    { "camera = 1 eye 0 0 1 target 0 0 0\ncamera = 1 eye 0 0 2 target 0 0 0\n", 2, HZ_E_RANGE, "does not follow" },
    { "camera = 0 eye 0 0 1\n", 1, HZ_E_FORMAT, "'eye' and 'target' are required" },
    { "camera = 0 eye 1 1 1 target 1 1 1\n", 1, HZ_E_RANGE, "coincide" },
    { "camera = 0 eye 0 0 1 target 0 0 0 up 0 0 0\n", 1, HZ_E_RANGE, "up is zero" },
    { "camera = 0 eye 0 0 1 target 0 0 0 fov 180\n", 1, HZ_E_RANGE, "outside" },
    { "camera = 0 eye 0 0 1 target 0 0 0 zoom 2\n", 1, HZ_E_FORMAT, "unexpected 'zoom'" },
    { "light = position 1 2 3\n", 1, HZ_E_FORMAT, "position X Y Z color R G B" },
    { "light = position 1 2 3 color 1 1 -1\n", 1, HZ_E_RANGE, "outside" },
    { "light = position 1 2 3 color 1 1 1 falloff linear\n", 1, HZ_E_FORMAT, "falloff 'linear'" },
    { "[material a]\nlight = position 0 0 0 color 1 1 1\n", 2, HZ_E_FORMAT, "belongs in the [scene] part" },
    { "mirror = 0.5\n", 1, HZ_E_FORMAT, "belongs in a [material] section" },
    { "[object a]\nmirror = 0.5\n", 2, HZ_E_FORMAT, "belongs in a [material] section" },
    { "[object a]\nmotion = spin\naxis = 0 1 0\n", 1, HZ_E_FORMAT, "needs 'axis' and 'speed'" },
    { "[object a]\nmotion = spin\naxis = 0 0 0\nspeed = 1\n", 1, HZ_E_RANGE, "spin axis is zero" },
    { "[object a]\naxis = 0 1 0\n", 1, HZ_E_FORMAT, "without 'motion" },
    { "[object a]\nmotion = keys\n[object b]\n", 1, HZ_E_FORMAT, "at least one 'key" },
    { "[object a]\nmotion = oscillate\namplitude = 0 1 0\nfrequency = 1\nspeed = 2\n", 1, HZ_E_FORMAT,
      "spin parameters" },
    { "[object a]\nmotion = keys\nkey = 1 translate 0 0 0\nkey = 0.5 translate 0 0 0\n", 4, HZ_E_RANGE,
      "does not follow" },
    { "[object a]\nmotion = keys\nkey = 0 rotate 0 0 0 45\n", 3, HZ_E_RANGE, "rotation axis is zero" },
    { "[object a]\nmotion = wobble\n", 2, HZ_E_FORMAT, "none, spin, oscillate, keys or sway" },
    { "[object a]\nmotion = sway\namplitude = 0 1 0\n", 1, HZ_E_FORMAT, "sway needs 'amplitude' and 'frequency'" },
    { "[object a]\nmotion = sway\namplitude = 0 1 0\nfrequency = 1\nspeed = 2\n", 1, HZ_E_FORMAT,
      "pivot, amplitude and frequency only" },
    { "[material a\n", 1, HZ_E_FORMAT, "end with ']'" },
    { "[material two words]\n", 1, HZ_E_FORMAT, "\"like this\"" },
    { "[material]\n", 1, HZ_E_FORMAT, "name is missing" },
    { "[lamp x]\n", 1, HZ_E_FORMAT, "unknown section" },
    { "[scene x]\n", 1, HZ_E_FORMAT, "takes no name" },
    { "just words\n", 1, HZ_E_FORMAT, "expected 'key = value'" },
    { "Name = x\n", 1, HZ_E_FORMAT, "not a key" },
    { " = 1\n", 1, HZ_E_FORMAT, "missing key" },
    { "name =\n", 1, HZ_E_FORMAT, "missing value" },
    { "name = 0123456789012345678901234567890123\n", 1, HZ_E_RANGE, "longer than 31" },
};

static void test_each_mistake_is_refused_with_its_line(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        const bad_t *b = &bad_cases[i];
        hz_bake_sidecar_t sc;
        hz_error_t err;
        hz_status_t s = parse(&sc, b->text, &err);
        char prefix[32];
        if (b->line)
            snprintf(prefix, sizeof prefix, "t.hzs:%d: ", b->line);
        else
            snprintf(prefix, sizeof prefix, "t.hzs: ");
        if (s != b->code || strncmp(err.msg, prefix, strlen(prefix)) != 0 || !strstr(err.msg, b->reason))
            fail_msg("case %zu (%s): got status %d, message '%s'; want %d, '%s...%s'", i, b->text, s, err.msg, b->code,
                     prefix, b->reason);
        hz_bake_sidecar_free(&sc);
    }
}

static void test_binary_and_long_lines_are_refused(void **state)
{
    (void)state;
    hz_bake_sidecar_t sc;
    hz_error_t err;
    static const char nul[] = "name = a\nduration = 1\0\n";
    hz_bake_sidecar_defaults(&sc);
    assert_int_equal(hz_bake_sidecar_parse(&sc, "t.hzs", nul, sizeof nul - 1, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "t.hzs:2: NUL byte"));
    hz_bake_sidecar_free(&sc);
    char *longline = malloc(10000);
    memset(longline, 'a', 9999);
    longline[9999] = 0;
    assert_int_equal(parse(&sc, longline, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "t.hzs:1: line longer"));
    hz_bake_sidecar_free(&sc);
    free(longline);
}

static void test_unmatched_sections_are_named(void **state)
{
    (void)state;
    hz_bake_sidecar_t sc;
    hz_error_t err;
    assert_int_equal(parse(&sc, "[material wall*]\nmirror = 1\n\n[object Boxx]\nmotion = none\n", &err), HZ_OK);
    hz_bake_scene_t s;
    hz_bake_scene_init(&s, "m.obj");
    hz_bake_material_t *m = hz_bake_vec_push(&s.mats, 1);
    snprintf(m->name, sizeof m->name, "wallLeft");
    hz_bake_object_t *o = hz_bake_vec_push(&s.objs, 1);
    snprintf(o->name, sizeof o->name, "Box");
    /* Matching is the caller's (scene.c); here: the material matched, the object did not. */
    assert_true(hz_bake_sidecar_match("wall*", "wallLeft"));
    assert_false(hz_bake_sidecar_match("Boxx", "Box"));
    HZ_BAKE_AT(sc.materials, hz_bake_sc_material_t, 0)->matched = 1;
    assert_int_equal(hz_bake_sidecar_unmatched(&sc, &s, &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "t.hzs:4: [object \"Boxx\"] matches no object of the model ('Box')"));
    HZ_BAKE_AT(sc.objects, hz_bake_sc_object_t, 0)->matched = 1;
    assert_int_equal(hz_bake_sidecar_unmatched(&sc, &s, &err), HZ_OK);
    hz_bake_scene_free(&s);
    hz_bake_sidecar_free(&sc);
}

/* A byte-order mark at the start (Windows editors write one) is not text; one elsewhere is refused by name, its
 * bytes shown. */
static void test_byte_order_mark(void **state)
{
    (void)state;
    hz_bake_sidecar_t sc;
    hz_error_t err;
    assert_int_equal(parse(&sc, "\xef\xbb\xbflight = position 1 2 3 color 4 5 6\nfov = 40\n", &err), HZ_OK);
    assert_int_equal((int)sc.lights.len, 1);
    hz_bake_sidecar_free(&sc);
    assert_int_equal(parse(&sc, "fov = 40\n\xef\xbb\xbflight = position 1 2 3 color 4 5 6\n", &err), HZ_E_FORMAT);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "t.hzs:2:"));
    assert_non_null(strstr(err.msg, "'\\xef\\xbb\\xbflight' is not a key"));
    assert_non_null(strstr(err.msg, "byte-order mark"));
    hz_bake_sidecar_free(&sc);
    assert_int_equal(parse(&sc, "f\xc2\xa0ov = 40\n", &err), HZ_E_FORMAT);
    assert_non_null(strstr(err.msg, "'f\\xc2\\xa0ov' is not a key"));
    hz_bake_sidecar_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_sidecar_reads_back),
        cmocka_unit_test(test_each_mistake_is_refused_with_its_line),
        cmocka_unit_test(test_binary_and_long_lines_are_refused),
        cmocka_unit_test(test_unmatched_sections_are_named),
        cmocka_unit_test(test_byte_order_mark),
    };
    return HZ_RUN(tests);
}
