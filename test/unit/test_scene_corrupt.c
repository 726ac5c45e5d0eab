/*
 * Deterministic corruption of whole scene images: every section and the header are flipped and truncated, and
 * the loader must answer each with a clean error (never a crash, an out-of-bounds read — ASan/UBSan builds
 * check that — or a hang). A second pass re-seals the CRCs after each flip so the corrupted value reaches the
 * deep checks: then the loader may accept (a benign byte such as a texel) but must never misbehave, and what
 * it accepts must be a scene whose indices are all in range.
 *
 * Images: the built-in scene always; real baked scenes from $HZ_SCENES_DIR when the list below names them
 * (they are produced by `make scenes`, which `make test` runs first).
 * hz-test: no-vm (heavy under system emulation, runs under qemu-user)
 */
#include "hz_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hz/builtin.h"
#include "hz/crc32.h"
#include "hz/scene.h"
#include "hzb_reseal.h"

static uint8_t image_mem[64 << 20] HZ_ALIGNED(64);
static uint8_t work_mem[64 << 20] HZ_ALIGNED(64);
static uint8_t scratch_mem[8 << 20] HZ_ALIGNED(64);
static uint8_t state_mem[64 << 20] HZ_ALIGNED(64);

/* Every index of an accepted scene must be in range: the loader's promise to the renderer. */
static void assert_consistent(const hz_scene_t *s)
{
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        for (int c = 0; c < 3; c++)
            assert_true(s->tri[t * 3 + c] < s->vertex_count);
        assert_true(hz_scene_tri_material(s, t) < s->material_count);
        assert_true(hz_scene_tri_object(s, t) < s->object_count);
    }
}

typedef struct stats {
    unsigned refused, accepted;
} stats_t;

static void try_load(const uint8_t *img, size_t size, stats_t *st, int must_refuse)
{
    hz_arena_t a;
    hz_arena_init(&a, "scene", state_mem, sizeof state_mem);
    hz_scene_t s;
    hz_error_t err;
    hz_error_clear(&err);
    hz_status_t r = hz_scene_load(&s, img, size, &a, &err);
    if (r == HZ_OK) {
        if (must_refuse)
            fail_msg("a corrupted image was accepted");
        assert_consistent(&s);
        hz_scene_animate(&s, 0.37f); /* animation must stay in bounds too */
        st->accepted++;
    } else {
        assert_true(err.code == r && strlen(err.msg) > 0); /* a clean error says why */
        st->refused++;
    }
}

static void corrupt_image(const char *label, const uint8_t *img, size_t size)
{
    hz_hzb_header_t h;
    memcpy(&h, img, sizeof h);
    stats_t st = { 0, 0 };
    /* Regions: the header, the section table, and each section. Positions within each: first, last and a
     * few in between. */
    uint64_t starts[HZ_SEC_ID_MAX + 2], sizes[HZ_SEC_ID_MAX + 2];
    uint32_t nreg = 0;
    starts[nreg] = 0, sizes[nreg++] = sizeof h;
    starts[nreg] = sizeof h, sizes[nreg++] = (uint64_t)h.section_count * sizeof(hz_hzb_section_t);
    for (uint32_t i = 0; i < h.section_count; i++) {
        hz_hzb_section_t e;
        memcpy(&e, img + sizeof h + i * sizeof e, sizeof e);
        starts[nreg] = e.offset, sizes[nreg++] = e.size;
    }
    for (uint32_t r = 0; r < nreg; r++) {
        for (int k = 0; k < 9; k++) {
            uint64_t at = starts[r] + (k == 8 ? sizes[r] - 1 : sizes[r] * (uint64_t)k / 8);
            for (int bit = 0; bit < 8; bit += 3) {
                memcpy(work_mem, img, size);
                work_mem[at] ^= (uint8_t)(1u << bit);
                try_load(work_mem, size, &st, 1); /* CRCs catch every single flip */
                reseal(work_mem, size);
                try_load(work_mem, size, &st, 0); /* past the CRCs: accepted or refused, never unsafe */
            }
            /* Whole words set to extreme values, resealed. */
            static const uint32_t extremes[] = { 0xffffffffu, 0x80000000u, 0x7fc00000u /* NaN */, 0x7f800000u };
            for (size_t x = 0; x < HZ_ARRAY_LEN(extremes); x++) {
                uint64_t w = (at & ~(uint64_t)3);
                if (w + 4 > size)
                    continue;
                memcpy(work_mem, img, size);
                memcpy(work_mem + w, &extremes[x], 4);
                reseal(work_mem, size);
                try_load(work_mem, size, &st, 0);
            }
        }
        /* Truncation inside this region (and at its end). */
        uint64_t cuts[3] = { starts[r], starts[r] + sizes[r] / 2, starts[r] + sizes[r] };
        for (int c = 0; c < 3; c++)
            if (cuts[c] < size) {
                memcpy(work_mem, img, (size_t)cuts[c]);
                try_load(work_mem, (size_t)cuts[c], &st, 1);
            }
    }
    print_message("%s: %u corrupted images refused, %u benign ones accepted\n", label, st.refused, st.accepted);
    assert_true(st.refused > 10 * nreg);
}

static void test_builtin_corruptions(void **state)
{
    (void)state;
    hz_arena_t images, scratch;
    hz_arena_init(&images, "images", image_mem, sizeof image_mem);
    hz_arena_init(&scratch, "scratch", scratch_mem, sizeof scratch_mem);
    const void *img;
    size_t size;
    assert_int_equal(hz_builtin_scene_image(&images, &scratch, &img, &size, NULL), HZ_OK);
    corrupt_image("builtin", img, size);
}

/* Real baked scenes small enough to corrupt exhaustively in seconds; bigger ones are covered by the fuzzer.
 * Together they hold every section type: BoxAnimated has rigid keys; CesiumMan-small (CesiumMan with 16-texel
 * textures and two skinning frames) has UVs, textures, texels, vertex keys and key normals; CesiumMan-skin-small
 * (the same, skinned at run time) has joints, skin binds and skin weights; all have positions, normals,
 * triangles, tri_info, materials, objects, lights and camera keys. */
static const char *const real_scenes[] = { "BoxAnimated.hzb", "CesiumMan-small.hzb", "CesiumMan-skin-small.hzb",
                                           NULL };

static void test_real_scene_corruptions(void **state)
{
    (void)state;
    const char *dir = getenv("HZ_SCENES_DIR");
    for (size_t i = 0; real_scenes[i]; i++) {
        char path[4096];
        assert_non_null(dir);
        snprintf(path, sizeof path, "%s/%s", dir, real_scenes[i]);
        FILE *f = fopen(path, "rb");
        if (!f)
            fail_msg("%s: missing (make scenes bakes it)", path);
        size_t n = fread(image_mem, 1, sizeof image_mem, f);
        fclose(f);
        corrupt_image(real_scenes[i], image_mem, n);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builtin_corruptions),
        cmocka_unit_test(test_real_scene_corruptions),
    };
    return HZ_RUN(tests);
}
