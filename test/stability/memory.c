/* Stage memory: the fixed-memory promise at its edge. Every consumer is given an arena of exactly what it
 * reports needing (it must succeed) and one byte less (it must refuse with HZ_E_NO_MEMORY, a message naming
 * the arena and both byte counts, and leave the arena as it found it). */
#include <stdlib.h>
#include <unistd.h>

#include "hz/image.h"
#include "hz/meshgen.h"
#include "hz/tdense.h"
#include "scenefile.h"
#include "stab_util.h"

static void *abuf(size_t n)
{
    void *p = NULL;
    return posix_memalign(&p, 64, n ? n : 64) == 0 ? p : NULL;
}

/* "needs N bytes" and "has M" both in the message */
static void check_counts(stab_result_t *r, const hz_error_t *err, size_t need, size_t have)
{
    char a[48], b[48];
    snprintf(a, sizeof a, "%zu", need);
    snprintf(b, sizeof b, "%zu", have);
    STAB_CHECK(r, strstr(err->msg, a) && strstr(err->msg, b), "message '%s' lacks %s and %s", err->msg, a, b);
}

static void c_arena_exactly_full(stab_result_t *r)
{
    enum { CAP = 4096 };
    uint8_t *buf = abuf(CAP);
    hz_arena_t a;
    hz_error_t err;
    STAB_OK(r, hz_arena_init(&a, "test", buf, CAP), &err);
    void *p = hz_arena_alloc(&a, CAP, 1);
    STAB_CHECK(r, p == buf && a.used == CAP && hz_arena_available(&a, 1) == 0, "a request of the whole arena");
    void *z = hz_arena_alloc(&a, 0, 1);
    STAB_CHECK(r, z != NULL && a.used == CAP, "a zero-size request in a full arena");
    void *q = hz_arena_alloc(&a, 1, 1);
    STAB_CHECK(r, q == NULL && a.used == CAP, "one byte more was granted");
    hz_status_t s = hz_arena_error(&a, &err);
    STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "arena 'test'");
    check_counts(r, &err, 1, 0);
    free(buf);
}

static void c_arena_one_short(stab_result_t *r)
{
    enum { CAP = 4096 };
    uint8_t *buf = abuf(CAP);
    hz_arena_t a;
    hz_error_t err;
    STAB_OK(r, hz_arena_init(&a, "test", buf, CAP), &err);
    STAB_CHECK(r, hz_arena_alloc(&a, CAP + 1, 1) == NULL && a.used == 0, "cap + 1 granted or arena changed");
    hz_status_t s = hz_arena_error(&a, &err);
    STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "arena 'test'");
    check_counts(r, &err, CAP + 1, CAP);
    /* alignment padding counts: 1 byte, then 4095 at alignment 64 needs 63 + 4095 */
    STAB_CHECK(r, hz_arena_alloc(&a, 1, 1) != NULL, "1 byte");
    STAB_CHECK(r, hz_arena_alloc(&a, CAP - 1, 64) == NULL && a.used == 1, "padding not counted");
    s = hz_arena_error(&a, &err);
    check_counts(r, &err, 63 + CAP - 1, CAP - 1);
    STAB_BAIL(r);
    /* sizes that wrap */
    STAB_CHECK(r, hz_arena_alloc(&a, SIZE_MAX, 16) == NULL && a.used == 1, "SIZE_MAX granted");
    STAB_CHECK(r, hz_arena_alloc_array(&a, SIZE_MAX / 2, 3, 16) == NULL, "overflowing array granted");
    s = hz_arena_error(&a, &err);
    STAB_CHECK(r, s == HZ_E_OVERFLOW, "count * size overflow reported as %s", hz_status_str(s));
    stab_note(r, "cap + 1; padding; SIZE_MAX; overflowing count: refused, arena unchanged");
}

/* An animated scene's state: plan.arena_bytes exactly fits, one byte less is refused. */
static void c_scene_state_exact(stab_result_t *r)
{
    su_scene_t b;
    su_begin(&b);
    su_room(&b, 1.0f);
    b.obj[1].motion = HZ_MOTION_SPIN, b.obj[1].params[4] = 1, b.obj[1].params[6] = 1;
    const void *img;
    size_t n;
    hz_error_t err;
    STAB_OK(r, su_image(&b, &img, &n, &err), &err);
    hz_scene_plan_t plan;
    STAB_OK(r, hz_scene_plan(img, n, &plan, &err), &err);
    STAB_CHECK(r, plan.arena_bytes > 0, "an animated scene needs no state");
    for (int shortby = 0; shortby < 2; shortby++) {
        size_t cap = plan.arena_bytes - (size_t)shortby;
        uint8_t *buf = abuf(cap);
        hz_arena_t a;
        STAB_OK(r, hz_arena_init(&a, "scene", buf, cap), &err);
        hz_scene_t sc;
        hz_status_t s = hz_scene_load(&sc, img, n, &a, &err);
        if (!shortby) {
            STAB_CHECK(r, s == HZ_OK, "exactly %zu bytes refused: %s", cap, err.msg);
            STAB_CHECK(r, a.used <= cap, "used %zu of the %zu planned", a.used, cap);
        } else {
            STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "arena 'scene'");
            STAB_CHECK(r, a.used == 0, "a refused load kept %zu bytes", a.used);
        }
        free(buf);
    }
    stab_note(r, "plan %zu bytes: exact fits; one short refused", plan.arena_bytes);
}

/* The accel build's peak: an arena of exactly the peak the build reported builds again; one byte less is
 * refused with the arena left empty. */
static void c_accel_build_exact(stab_result_t *r)
{
    hz_error_t err;
    hz_mesh_t m;
    STAB_OK(r, hz_meshgen_sphere(&m, &hz_pools_get()->scene, 24, 48, 1.0f, &err), &err);
    hz_accel_geom_t g = hz_meshgen_geom(&m);
    size_t peak = 0;
    for (int pass = 0; pass < 3; pass++) {
        size_t cap = pass == 0 ? (size_t)64 << 20 : peak - (size_t)(pass - 1);
        uint8_t *buf = abuf(cap);
        hz_arena_t a;
        STAB_OK(r, hz_arena_init(&a, "accel", buf, cap), &err);
        hz_accel_t *acc;
        hz_status_t s = hz_accel_build_native(&acc, &g, NULL, &a, &err);
        if (pass == 0) {
            STAB_CHECK(r, s == HZ_OK, "build: %s", err.msg);
            peak = a.high_water;
            STAB_CHECK(r, peak <= hz_accel_bytes_bound(m.tri_count, NULL).peak, "peak %zu beyond its bound", peak);
        } else if (pass == 1) {
            STAB_CHECK(r, s == HZ_OK, "an arena of exactly the peak (%zu) refused: %s", cap, err.msg);
        } else {
            STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "accel");
            STAB_CHECK(r, a.used == 0, "a refused build kept %zu bytes", a.used);
        }
        free(buf);
    }
    stab_note(r, "%u triangles: peak %zu bytes fits exactly; one short refused; arena left empty", m.tri_count,
              peak);
}

/* The renderer: hz_render_plan's frame_bytes exactly fit, one byte less is refused naming both counts. */
static void c_render_create_exact(stab_result_t *r)
{
    su_scene_t b;
    su_begin(&b);
    su_room(&b, 1.0f);
    const float eye[3] = { 0, 1.5f, 6 }, target[3] = { 0, 1.2f, 0 };
    su_camera(&b, 0, eye, target, 1.0f);
    hz_scene_t sc;
    hz_error_t err;
    STAB_OK(r, su_load(&b, &sc, &err), &err);
    hz_accel_geom_t g;
    hz_accel_t *acc;
    hz_pools_t *p = hz_pools_get();
    STAB_OK(r, hz_accel_geom_from_scene(&g, &sc, &p->accel, &err), &err);
    STAB_OK(r, hz_accel_build_native(&acc, &g, NULL, &p->accel, &err), &err);
    static const hz_render_mode_t modes[3] = { HZ_MODE_FULL, HZ_MODE_TAA, HZ_MODE_TDENSE };
    for (int k = 0; k < 3; k++) {
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = 37, o.height = 23, o.mode = modes[k];
        hz_render_plan_t plan;
        STAB_OK(r, hz_render_plan(&sc, &o, &plan, &err), &err);
        for (int shortby = 0; shortby < 2; shortby++) {
            size_t cap = plan.frame_bytes - (size_t)shortby;
            uint8_t *buf = abuf(cap);
            hz_arena_t a;
            STAB_OK(r, hz_arena_init(&a, "frame", buf, cap), &err);
            hz_renderer_t *rr;
            hz_arena_mark_t tm = hz_arena_mark(&p->thread[0]);
            hz_status_t s = hz_render_create(&rr, &sc, acc, &o, &a, p->thread, 1, &err);
            if (!shortby) {
                STAB_CHECK(r, s == HZ_OK, "%s: exactly %zu bytes refused: %s", hz_render_mode_name(o.mode), cap,
                           err.msg);
                STAB_OK(r, hz_render_begin_frame(rr, 0, 0.0f, &err), &err);
            } else {
                STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "arena 'frame'");
                check_counts(r, &err, cap + 1, cap);
                STAB_CHECK(r, a.used == 0, "a refused renderer kept %zu bytes", a.used);
            }
            hz_arena_reset(&p->thread[0], tm);
            free(buf);
        }
    }
    r->note[0] = 0;
    stab_note(r, "full/TAA/tdense at 37x23: planned frame bytes fit exactly; one short refused with both counts");
}

/* tdense state: hz_tdense_bytes (an upper bound including worst-case padding) fits; an arena one byte short of
 * what init then took is refused and keeps nothing. */
static void c_tdense_init_exact(stab_result_t *r)
{
    hz_tdense_config_t c = hz_tdense_config_default(33, 17);
    size_t need = hz_tdense_bytes(33, 17), used = 0;
    hz_error_t err;
    for (int pass = 0; pass < 2; pass++) {
        size_t cap = pass ? used - 1 : need;
        uint8_t *buf = abuf(cap);
        hz_arena_t a;
        STAB_OK(r, hz_arena_init(&a, "frame", buf, cap), &err);
        hz_tdense_t td;
        hz_status_t s = hz_tdense_init(&td, &c, &a, &err);
        if (!pass) {
            STAB_CHECK(r, s == HZ_OK, "exactly %zu bytes refused: %s", cap, err.msg);
            used = a.used;
        } else {
            STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "frame");
            STAB_CHECK(r, a.used == 0, "a refused init kept %zu bytes", a.used);
        }
        free(buf);
    }
    STAB_CHECK(r, hz_tdense_bytes(0, 5) == 0 && hz_tdense_bytes(HZ_IMAGE_MAX_DIM + 1, 1) == 0, "invalid sizes");
    stab_note(r, "33x17: bound %zu bytes fits (took %zu); %zu refused", need, used, used - 1);
}

static void c_image_alloc_exact(stab_result_t *r)
{
    size_t need;
    hz_error_t err;
    STAB_OK(r, hz_image_check_size(4096, 16, &need, &err), &err);
    for (int shortby = 0; shortby < 2; shortby++) {
        size_t cap = need - (size_t)shortby;
        uint8_t *buf = abuf(cap);
        hz_arena_t a;
        STAB_OK(r, hz_arena_init(&a, "frame", buf, cap), &err);
        hz_image_t img;
        hz_status_t s = hz_image_alloc(&img, &a, 4096, 16, &err);
        if (!shortby)
            STAB_CHECK(r, s == HZ_OK, "exactly %zu bytes refused", cap);
        else {
            STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, "arena 'frame'");
            STAB_CHECK(r, img.rgb == NULL && img.width == 0, "a refused image is not zeroed");
        }
        free(buf);
    }
    stab_note(r, "4096x16: %zu bytes fit exactly; one short refused", need);
}

/* A scene file one byte larger than the scene arena's free space: refused naming the file and both counts. */
static void c_scenefile_too_big(stab_result_t *r)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/hzstab-big-%d.bin", (int)getpid());
    enum { N = 10000 };
    FILE *f = fopen(path, "wb");
    static uint8_t junk[N];
    STAB_CHECK(r, f && fwrite(junk, 1, N, f) == N, "cannot write %s", path);
    fclose(f);
    hz_error_t err;
    for (int shortby = 0; shortby < 2; shortby++) {
        size_t cap = N - (size_t)shortby;
        uint8_t *buf = abuf(cap);
        hz_arena_t a;
        STAB_OK(r, hz_arena_init(&a, "scene", buf, cap), &err);
        const void *data;
        size_t size;
        hz_status_t s = hz_scenefile_read(path, &a, &data, &size, &err);
        if (!shortby)
            STAB_CHECK(r, s == HZ_OK && size == N, "exactly %zu bytes refused: %s", cap, err.msg);
        else {
            STAB_REFUSED(r, s, HZ_E_NO_MEMORY, &err, path);
            check_counts(r, &err, N, cap);
            STAB_CHECK(r, a.used == 0, "a refused read kept %zu bytes", a.used);
        }
        free(buf);
    }
    remove(path);
}

static const stab_case_t cases[] = {
    { "arena_exactly_full", "a request of the whole arena fits; one byte more refused naming the arena",
      c_arena_exactly_full, 0 },
    { "arena_one_short", "cap + 1; alignment padding; SIZE_MAX; overflowing count: refused; arena unchanged",
      c_arena_one_short, 0 },
    { "scene_state_exact", "animated scene state: planned bytes fit exactly; one short refused",
      c_scene_state_exact, 0 },
    { "accel_build_exact", "accel build peak fits exactly; one short refused; arena left empty",
      c_accel_build_exact, 0 },
    { "render_create_exact", "renderer frame bytes (full/TAA/tdense) fit exactly; one short refused",
      c_render_create_exact, 0 },
    { "tdense_init_exact", "tdense state: its bound fits; one byte short of what it takes refused; keeps nothing", c_tdense_init_exact, 0 },
    { "image_alloc_exact", "4096x16 image fits exactly; one short refused; image zeroed", c_image_alloc_exact, 0 },
    { "scenefile_too_big", "scene file one byte over the arena: refused naming the file and counts",
      c_scenefile_too_big, 0 },
};
STAB_STAGE(memory, cases);
