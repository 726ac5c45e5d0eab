/*
 * The baker against the real scenes (`make scenes` output in $HZ_SCENES_DIR) and against bad inputs.
 *
 *  - triangle counts equal the publishers' (SOURCES.md), feature masks and materials are what each source means;
 *  - round trip: the geometry of every baked static/rigid scene equals the source as assimp reads it, compared
 *    as an order- and welding-independent hash of triangles (three corner positions each) computed here from
 *    assimp's own data, not from the baker's conversion; skinned and rigid motion is checked against joint and
 *    node transforms evaluated here from the animation keys; the furball's tubes against its strand points;
 *  - mip levels are linear-light box filters of the level above;
 *  - bad inputs (missing, unsupported, truncated, corrupt, NaN, crashing or hanging importer, bad sidecar)
 *    each give a message naming the file and the reason, their own exit status, and leave the output alone.
 *
 * Environment (set by `make test-host`): HZ_SCENES_DIR, HZ_BAKE (the baker), HZ_SCENES_SRC (../shared/scenes),
 * HZ_SCENES_UNPACK (the unpacked zips).
 */
#include "hz_test.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "hz/arena.h"
#include "hz/hzb.h"
#include "hz/scene.h"

/* ---- helpers ---- */

static const char *env(const char *name)
{
    const char *v = getenv(name);
    if (!v || !*v)
        fail_msg("%s is not set (run through `make test-host`)", name);
    return v;
}

static void *read_all(const char *path, size_t *size, int aligned)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        fail_msg("%s: %s", path, strerror(errno));
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *buf = NULL;
    if (aligned)
        assert_int_equal(posix_memalign(&buf, 64, (size_t)n + 1), 0);
    else
        buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    ((char *)buf)[n] = 0;
    *size = (size_t)n;
    return buf;
}

static void *gunzip_all(const char *path, size_t *size)
{
    gzFile g = gzopen(path, "rb");
    if (!g)
        fail_msg("%s: cannot open", path);
    size_t cap = 1 << 20, n = 0;
    char *buf = malloc(cap);
    int r;
    while ((r = gzread(g, buf + n, (unsigned)(cap - n))) > 0) {
        n += (size_t)r;
        if (n == cap)
            buf = realloc(buf, cap *= 2);
    }
    assert_true(r == 0);
    gzclose(g);
    *size = n;
    return buf;
}

typedef struct loaded {
    void *image, *state;
    size_t size;
    hz_scene_t s;
} loaded_t;

static void load(const char *name, loaded_t *l)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.hzb", env("HZ_SCENES_DIR"), name);
    l->image = read_all(path, &l->size, 1);
    hz_scene_plan_t plan;
    hz_error_t err;
    if (hz_scene_plan(l->image, l->size, &plan, &err) != HZ_OK)
        fail_msg("%s: %s", path, err.msg);
    assert_int_equal(posix_memalign(&l->state, 64, plan.arena_bytes + 64), 0);
    hz_arena_t a;
    hz_arena_init(&a, "scene", l->state, plan.arena_bytes + 64);
    if (hz_scene_load(&l->s, l->image, l->size, &a, &err) != HZ_OK)
        fail_msg("%s: %s", path, err.msg);
}

static void unload(loaded_t *l)
{
    free(l->image);
    free(l->state);
}

static const hz_material_t *material_named(const hz_scene_t *s, const char *name)
{
    for (uint32_t i = 0; i < s->material_count; i++)
        if (!strcmp((const char *)s->materials[i].name, name))
            return &s->materials[i];
    fail_msg("no material '%s'", name);
    return NULL;
}

/* ---- counts, masks, materials ---- */

typedef struct expect {
    const char *scene;
    uint32_t triangles;
    uint32_t features;
} expect_t;

#define F_CP HZ_FEAT_CAMERA_PATH
#define F_N HZ_FEAT_NORMALS
static const expect_t expected[] = {
    /* Publishers' counts (../shared/scenes/SOURCES.md). */
    { "conference", 331179, F_CP | F_N },
    { "sponza", 66450, HZ_FEAT_TEXTURES | F_CP | F_N },
    { "lost-empire", 224998, HZ_FEAT_CUTOUT | HZ_FEAT_TEXTURES | F_CP | F_N },
    { "dragon-res4", 11102, F_CP | F_N },
    { "dragon-res3", 47794, F_CP | F_N },
    { "dragon-res2", 202520, F_CP | F_N },
    { "dragon", 871414, F_CP | F_N },
    { "AlphaBlendModeTest", 61, HZ_FEAT_BLEND | HZ_FEAT_CUTOUT | HZ_FEAT_TEXTURES | F_CP | F_N },
    { "BoxAnimated", 254, HZ_FEAT_MOTION | F_N },
    { "CesiumMan", 4672, HZ_FEAT_MOTION | HZ_FEAT_SKINNING | HZ_FEAT_TEXTURES | F_CP | F_N },
    { "CesiumMan-keys", 4672, HZ_FEAT_MOTION | HZ_FEAT_SKINNING | HZ_FEAT_TEXTURES | F_CP | F_N },
    { "tentacles", 61440, HZ_FEAT_MOTION | HZ_FEAT_SKINNING | F_CP | F_N },
    { "pine", 527, HZ_FEAT_CUTOUT | HZ_FEAT_TEXTURES | F_CP | F_N },
    { "CornellBox-Original", 36, F_CP | F_N },
    { "CornellBox-Mirror", 36, HZ_FEAT_MIRROR | F_CP | F_N },
    /* 455,505 segments x 2 triangles x 3 sides (tube_sides in furball.hzs). */
    { "furball", 455505u * 6u, HZ_FEAT_MOTION | F_N },
};

static void test_triangle_counts_and_feature_masks(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++) {
        const expect_t *e = &expected[i];
        loaded_t l;
        load(e->scene, &l);
        char got[160], want[160];
        hz_scene_features_str(l.s.features, got, sizeof got);
        hz_scene_features_str(e->features, want, sizeof want);
        print_message("%-20s %9u triangles  %s\n", e->scene, l.s.triangle_count, got);
        if (l.s.triangle_count != e->triangles)
            fail_msg("%s: %u triangles, the publisher says %u", e->scene, l.s.triangle_count, e->triangles);
        if (l.s.features != e->features)
            fail_msg("%s: features '%s', expected '%s'", e->scene, got, want);
        /* The renderer relies on at least one point light and a camera in every shared scene. */
        if (l.s.light_count < 1 || l.s.camera_key_count < 1)
            fail_msg("%s: %u lights, %u camera keys", e->scene, l.s.light_count, l.s.camera_key_count);
        unload(&l);
    }
}

static void test_materials_mean_what_the_sources_say(void **state)
{
    (void)state;
    loaded_t l;
    load("AlphaBlendModeTest", &l);
    static const struct {
        const char *name;
        uint32_t mode;
        float cutoff;
    } modes[] = {
        { "MatOpaque", HZ_ALPHA_OPAQUE, 0.5f },  { "MatBlend", HZ_ALPHA_BLEND, 0.5f },
        { "MatCutoff25", HZ_ALPHA_MASK, 0.25f }, { "MatCutoffDefault", HZ_ALPHA_MASK, 0.5f },
        { "MatCutoff75", HZ_ALPHA_MASK, 0.75f },
    };
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        const hz_material_t *m = material_named(&l.s, modes[i].name);
        assert_int_equal(m->alpha_mode, modes[i].mode);
        assert_true(m->base_texture >= 0);
        if (modes[i].mode != HZ_ALPHA_OPAQUE) {
            assert_true(m->alpha_cutoff == modes[i].cutoff);
            assert_int_equal(m->alpha_texture, m->base_texture); /* glTF: alpha is the base colour's A */
            assert_true(l.s.textures[m->alpha_texture].flags & 1u);
        }
    }
    unload(&l);

    load("lost-empire", &l);
    const hz_material_t *leaves = material_named(&l.s, "Leaves"), *stone = material_named(&l.s, "Stone");
    assert_int_equal(leaves->alpha_mode, HZ_ALPHA_MASK);
    assert_int_equal(stone->alpha_mode, HZ_ALPHA_OPAQUE);
    assert_true(leaves->alpha_texture >= 0 && leaves->alpha_texture != leaves->base_texture);
    /* map_d lost_empire-Alpha.png is a grey mask with an opaque alpha channel: its grey became the alpha. */
    const hz_texture_t *at = &l.s.textures[leaves->alpha_texture];
    const uint8_t *tx = l.s.texels + (size_t)at->first_texel * 4;
    size_t zero = 0, full = 0;
    for (size_t i = 0; i < (size_t)at->width * at->height; i++)
        zero += tx[i * 4 + 3] == 0, full += tx[i * 4 + 3] == 255;
    assert_true(zero > 0 && full > 0 && (at->flags & 1u));
    assert_true(at->width <= 1024 && at->height <= 1024); /* texture_max */
    unload(&l);

    load("CornellBox-Mirror", &l);
    assert_true(material_named(&l.s, "tallBox")->mirror == 0.95f);
    unload(&l);
    load("CornellBox-Original", &l);
    for (uint32_t i = 0; i < l.s.material_count; i++)
        assert_true(l.s.materials[i].mirror == 0.0f);
    unload(&l);
    load("pine", &l);
    const hz_material_t *pine = material_named(&l.s, "SoftPine2");
    assert_int_equal(pine->alpha_mode, HZ_ALPHA_MASK);
    assert_int_equal(pine->alpha_texture, pine->base_texture);
    unload(&l);
}

/* ---- mip levels ---- */

static double lin(uint8_t b)
{
    double c = b / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static double enc(double x)
{
    double c = x <= 0.0031308 ? x * 12.92 : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return c * 255.0;
}

/* Level 1 of a texture whose level 0 is the decoded image is filtered from exactly the bytes stored, so it
 * must match to rounding (`exact`); deeper levels (and every level of a downscaled texture) are filtered by the
 * baker from unrounded float levels, so they may differ from a filter of the stored bytes by a few steps where
 * little alpha weights the colour. */
static void check_mips(const hz_scene_t *s, const hz_texture_t *t, int exact)
{
    const uint8_t *level = s->texels + (size_t)t->first_texel * 4;
    uint32_t w = t->width, h = t->height;
    for (uint32_t l = 1; l < t->levels; l++) {
        uint32_t nw = w > 1 ? w / 2 : 1, nh = h > 1 ? h / 2 : 1;
        const uint8_t *next = level + (size_t)w * h * 4;
        for (uint32_t y = 0; y < nh; y += (nh > 16 ? nh / 16 : 1))
            for (uint32_t x = 0; x < nw; x += (nw > 16 ? nw / 16 : 1)) {
                uint32_t xs[2] = { w > 1 ? 2 * x : 0, w > 1 ? 2 * x + 1 : 0 };
                uint32_t ys[2] = { h > 1 ? 2 * y : 0, h > 1 ? 2 * y + 1 : 0 };
                double a = 0, c[3] = { 0, 0, 0 };
                for (int j = 0; j < 2; j++)
                    for (int i = 0; i < 2; i++) {
                        const uint8_t *p = level + ((size_t)ys[j] * w + xs[i]) * 4;
                        a += p[3] / 255.0;
                        for (int k = 0; k < 3; k++)
                            c[k] += lin(p[k]) * p[3] / 255.0;
                    }
                const uint8_t *q = next + ((size_t)y * nw + x) * 4;
                double tol = exact && l == 1 ? 0.51 : 3.0;
                if (a > (exact && l == 1 ? 0.0 : 1.0))
                    for (int k = 0; k < 3; k++)
                        if (fabs(enc(c[k] / a) - q[k]) > tol)
                            fail_msg("texture %s level %u texel %u,%u channel %d: %u, expected %.1f",
                                     (const char *)t->name, l, x, y, k, q[k], enc(c[k] / a));
                if (fabs(a / 4 * 255.0 - q[3]) > tol)
                    fail_msg("texture %s level %u texel %u,%u alpha %u, expected %.1f", (const char *)t->name, l, x, y,
                             q[3], a / 4 * 255.0);
            }
        level = next;
        w = nw, h = nh;
    }
    assert_true(w == 1 && h == 1); /* full chains */
}

static void test_mip_levels_are_linear_box_filters(void **state)
{
    (void)state;
    static const char *const scenes[] = { "sponza", "pine", "AlphaBlendModeTest-small" };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        loaded_t l;
        load(scenes[i], &l);
        assert_true(l.s.texture_count > 0);
        for (uint32_t t = 0; t < l.s.texture_count; t++)
            check_mips(&l.s, &l.s.textures[t], strcmp(scenes[i], "AlphaBlendModeTest-small") != 0);
        if (!strcmp(scenes[i], "AlphaBlendModeTest-small"))
            for (uint32_t t = 0; t < l.s.texture_count; t++)
                assert_true(l.s.textures[t].width <= 16 && l.s.textures[t].height <= 16);
        unload(&l);
    }
}

/* ---- round trip: triangle hashes ---- */

typedef struct thash {
    uint64_t sum, mix;
    uint64_t count;
} thash_t;

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

static uint32_t fbits(float f)
{
    if (f == 0.0f)
        f = 0.0f; /* -0 */
    uint32_t b;
    memcpy(&b, &f, 4);
    return b;
}

static int corner_less(const uint32_t *a, const uint32_t *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k];
    return 0;
}

/* Adds one triangle: its corners sorted (independent of winding and vertex numbering), then hashed. */
static void hash_triangle(thash_t *h, const float *p0, const float *p1, const float *p2)
{
    uint32_t c[3][3];
    const float *p[3] = { p0, p1, p2 };
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            c[i][k] = fbits(p[i][k]);
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (corner_less(c[j], c[i])) {
                uint32_t t[3];
                memcpy(t, c[i], sizeof t);
                memcpy(c[i], c[j], sizeof t);
                memcpy(c[j], t, sizeof t);
            }
    uint64_t v = 0x9e3779b97f4a7c15ull;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            v = mix64(v ^ c[i][k]);
    h->sum += v;
    h->mix ^= mix64(v + 0x632be59bd9b4e019ull);
    h->count++;
}

typedef struct ai_ctx {
    const struct aiScene *ai;
    const struct aiAnimation *anim;
    thash_t *h;
} ai_ctx_t;

static int animated_path(const ai_ctx_t *c, const struct aiNode *n)
{
    for (; c->anim && n; n = n->mParent)
        for (unsigned i = 0; i < c->anim->mNumChannels; i++)
            if (!strcmp(c->anim->mChannels[i]->mNodeName.data, n->mName.data))
                return 1;
    return 0;
}

/* Static meshes: world positions (root first, parent * child, the order an importer naturally uses);
 * meshes under animated nodes: their own positions (the format's object space). */
static void hash_node(const ai_ctx_t *c, const struct aiNode *n, struct aiMatrix4x4 parent)
{
    struct aiMatrix4x4 g = parent;
    aiMultiplyMatrix4(&g, &n->mTransformation);
    int animated = animated_path(c, n);
    for (unsigned i = 0; i < n->mNumMeshes; i++) {
        const struct aiMesh *m = c->ai->mMeshes[n->mMeshes[i]];
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            if (m->mFaces[f].mNumIndices != 3)
                continue;
            float p[3][3];
            for (int k = 0; k < 3; k++) {
                struct aiVector3D v = m->mVertices[m->mFaces[f].mIndices[k]];
                if (!animated)
                    aiTransformVecByMatrix4(&v, &g);
                p[k][0] = v.x, p[k][1] = v.y, p[k][2] = v.z;
            }
            hash_triangle(c->h, p[0], p[1], p[2]);
        }
    }
    for (unsigned i = 0; i < n->mNumChildren; i++)
        hash_node(c, n->mChildren[i], g);
}

static const struct aiScene *import(const char *path)
{
    const struct aiScene *ai;
    if (strstr(path, ".gz")) {
        size_t size;
        void *data = gunzip_all(path, &size);
        ai = aiImportFileFromMemory(data, (unsigned)size, aiProcess_Triangulate, "ply");
        free(data);
    } else {
        ai = aiImportFile(path, aiProcess_Triangulate);
    }
    if (!ai)
        fail_msg("%s: %s", path, aiGetErrorString());
    return ai;
}

static void hash_source(const char *path, thash_t *h)
{
    const struct aiScene *ai = import(path);
    ai_ctx_t c = { ai, ai->mNumAnimations ? ai->mAnimations[0] : NULL, h };
    struct aiMatrix4x4 id;
    aiIdentityMatrix4(&id);
    /* The root's matrix starts the chain: identity * root is root, bit for bit. */
    hash_node(&c, ai->mRootNode, id);
    aiReleaseImport(ai);
}

static void hash_baked(const hz_scene_t *s, thash_t *h)
{
    for (uint32_t t = 0; t < s->triangle_count; t++) {
        const uint32_t *i = s->tri + (size_t)t * 3;
        hash_triangle(h, s->rest_pos + (size_t)i[0] * 4, s->rest_pos + (size_t)i[1] * 4,
                      s->rest_pos + (size_t)i[2] * 4);
    }
}

static void source_path(char *out, size_t size, const char *where, const char *rel)
{
    snprintf(out, size, "%s/%s", env(where), rel);
}

static void test_round_trip_geometry_equals_source(void **state)
{
    (void)state;
    static const struct {
        const char *scene, *where, *model;
    } cases[] = {
        { "CornellBox-Original", "HZ_SCENES_UNPACK", "CornellBox/CornellBox-Original.obj" },
        { "CornellBox-Mirror", "HZ_SCENES_UNPACK", "CornellBox/CornellBox-Mirror.obj" },
        { "conference", "HZ_SCENES_UNPACK", "conference/conference.obj" },
        { "sponza", "HZ_SCENES_UNPACK", "sponza/sponza.obj" },
        { "lost-empire", "HZ_SCENES_UNPACK", "lost-empire/lost_empire.obj" },
        { "pine", "HZ_SCENES_UNPACK", "pine/scrubPine.obj" },
        { "dragon-res4", "HZ_SCENES_SRC", "dragon/dragon_vrip_res4.ply.gz" },
        { "dragon-res2", "HZ_SCENES_SRC", "dragon/dragon_vrip_res2.ply.gz" },
        { "AlphaBlendModeTest", "HZ_SCENES_SRC", "gltf/AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf" },
        { "BoxAnimated", "HZ_SCENES_SRC", "gltf/BoxAnimated/glTF/BoxAnimated.gltf" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char path[4096];
        source_path(path, sizeof path, cases[i].where, cases[i].model);
        thash_t src = { 0, 0, 0 }, baked = { 0, 0, 0 };
        hash_source(path, &src);
        loaded_t l;
        load(cases[i].scene, &l);
        hash_baked(&l.s, &baked);
        print_message("%-20s %9llu triangles  source %016llx%016llx  baked %016llx%016llx\n", cases[i].scene,
                      (unsigned long long)baked.count, (unsigned long long)src.sum, (unsigned long long)src.mix,
                      (unsigned long long)baked.sum, (unsigned long long)baked.mix);
        if (src.count != baked.count || src.sum != baked.sum || src.mix != baked.mix)
            fail_msg("%s: baked geometry differs from %s (%llu vs %llu triangles)", cases[i].scene, path,
                     (unsigned long long)baked.count, (unsigned long long)src.count);
        unload(&l);
    }
}

/* ---- motion against independently evaluated animation ---- */

static const struct aiNodeAnim *channel_of(const struct aiAnimation *a, const struct aiNode *n)
{
    for (unsigned i = 0; i < a->mNumChannels; i++)
        if (!strcmp(a->mChannels[i]->mNodeName.data, n->mName.data))
            return a->mChannels[i];
    return NULL;
}

/* The key value at `ticks`: the first/last key outside the key range, else a key at exactly that time (the
 * tests pick such times, so no interpolation is needed here). */
static int vec_key(const struct aiVectorKey *k, unsigned n, double ticks, struct aiVector3D *out)
{
    if (ticks <= k[0].mTime) {
        *out = k[0].mValue;
        return 1;
    }
    if (ticks >= k[n - 1].mTime) {
        *out = k[n - 1].mValue;
        return 1;
    }
    for (unsigned i = 0; i < n; i++)
        if (fabs(k[i].mTime - ticks) < 1e-3) {
            *out = k[i].mValue;
            return 1;
        }
    return 0;
}

static int quat_key(const struct aiQuatKey *k, unsigned n, double ticks, struct aiQuaternion *out)
{
    if (ticks <= k[0].mTime) {
        *out = k[0].mValue;
        return 1;
    }
    if (ticks >= k[n - 1].mTime) {
        *out = k[n - 1].mValue;
        return 1;
    }
    for (unsigned i = 0; i < n; i++)
        if (fabs(k[i].mTime - ticks) < 1e-3) {
            *out = k[i].mValue;
            return 1;
        }
    return 0;
}

static void world_at(const struct aiAnimation *a, const struct aiNode *n, double ticks, double m[16])
{
    struct aiMatrix4x4 local = n->mTransformation;
    const struct aiNodeAnim *ch = channel_of(a, n);
    if (ch) {
        struct aiVector3D t = { 0, 0, 0 }, s = { 1, 1, 1 };
        struct aiQuaternion r = { 1, 0, 0, 0 };
        assert_true(ch->mNumPositionKeys && ch->mNumRotationKeys && ch->mNumScalingKeys);
        assert_true(vec_key(ch->mPositionKeys, ch->mNumPositionKeys, ticks, &t));
        assert_true(quat_key(ch->mRotationKeys, ch->mNumRotationKeys, ticks, &r));
        assert_true(vec_key(ch->mScalingKeys, ch->mNumScalingKeys, ticks, &s));
        aiMatrix4FromScalingQuaternionPosition(&local, &s, &r, &t);
    }
    double l[16];
    const float *f = &local.a1; /* row-major a1..d4 */
    for (int i = 0; i < 16; i++)
        l[i] = f[i];
    if (!n->mParent) {
        memcpy(m, l, sizeof l);
        return;
    }
    double p[16];
    world_at(a, n->mParent, ticks, p);
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double v = 0;
            for (int k = 0; k < 4; k++)
                v += p[r * 4 + k] * l[k * 4 + c];
            m[r * 4 + c] = v;
        }
}

static void xform(const double m[16], const struct aiVector3D *v, double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m[r * 4] * v->x + m[r * 4 + 1] * v->y + m[r * 4 + 2] * v->z + m[r * 4 + 3];
}

static const struct aiNode *node_named(const struct aiNode *n, const char *name)
{
    if (!strcmp(n->mName.data, name))
        return n;
    for (unsigned i = 0; i < n->mNumChildren; i++) {
        const struct aiNode *f = node_named(n->mChildren[i], name);
        if (f)
            return f;
    }
    return NULL;
}

/* Skinned vertices of CesiumMan at its frames 0 and 30 (t = 0 and 1 s, where the source has keys), computed
 * here in double precision from assimp's bones and node animation, against the baked scene `name`: per-vertex
 * keys (CesiumMan-keys: the key frames themselves) or runtime skinning (CesiumMan: the scene animated to t). */
static void check_skinning(const char *name, int runtime)
{
    char path[4096];
    source_path(path, sizeof path, "HZ_SCENES_SRC", "gltf/CesiumMan/glTF/CesiumMan.gltf");
    const struct aiScene *ai = import(path);
    assert_int_equal(ai->mNumMeshes, 1);
    const struct aiMesh *mesh = ai->mMeshes[0];
    const struct aiAnimation *a = ai->mAnimations[0];
    loaded_t l;
    load(name, &l);
    assert_int_equal(l.s.object_count, 1);
    const hz_object_t *o = &l.s.objects[0];
    assert_int_equal(o->vertex_count, mesh->mNumVertices); /* skinned meshes keep the source's vertices */
    if (runtime) {
        assert_int_equal(o->motion, HZ_MOTION_SKIN);
        assert_int_equal(o->key_count, mesh->mNumBones); /* every vertex is weighted: no bind for the node */
        assert_int_equal(l.s.header->joint_count, mesh->mNumBones);
        assert_int_equal(l.s.header->vertex_key_count, 0);
    } else {
        assert_int_equal(o->motion, HZ_MOTION_VERTEX);
        assert_true(o->key_rate == 30.0f);
        assert_int_equal(o->key_count, 60); /* 2 s at 30 frames/s */
    }
    /* Frame 0 (t = 0) and frame 30 (t = 1 s, where the source has keys): skin every vertex here. */
    static const uint32_t frames[] = { 0, 30 };
    double worst = 0;
    for (size_t fi = 0; fi < 2; fi++) {
        double ticks = frames[fi] / 30.0 * (a->mTicksPerSecond > 0 ? a->mTicksPerSecond : 25.0);
        double(*bm)[16] = calloc(mesh->mNumBones, sizeof *bm);
        for (unsigned b = 0; b < mesh->mNumBones; b++) {
            const struct aiNode *bn = node_named(ai->mRootNode, mesh->mBones[b]->mName.data);
            assert_non_null(bn);
            double g[16], off[16];
            world_at(a, bn, ticks, g);
            const float *f = &mesh->mBones[b]->mOffsetMatrix.a1;
            for (int i = 0; i < 16; i++)
                off[i] = f[i];
            for (int r = 0; r < 4; r++)
                for (int c = 0; c < 4; c++) {
                    double v = 0;
                    for (int k = 0; k < 4; k++)
                        v += g[r * 4 + k] * off[k * 4 + c];
                    bm[b][r * 4 + c] = v;
                }
        }
        double *acc = calloc((size_t)mesh->mNumVertices * 4, sizeof(double));
        for (unsigned b = 0; b < mesh->mNumBones; b++)
            for (unsigned w = 0; w < mesh->mBones[b]->mNumWeights; w++) {
                const struct aiVertexWeight *vw = &mesh->mBones[b]->mWeights[w];
                double p[3];
                xform(bm[b], &mesh->mVertices[vw->mVertexId], p);
                for (int k = 0; k < 3; k++)
                    acc[vw->mVertexId * 4 + k] += vw->mWeight * p[k];
                acc[vw->mVertexId * 4 + 3] += vw->mWeight;
            }
        const float *baked;
        if (runtime) {
            hz_scene_animate(&l.s, (float)frames[fi] / 30.0f);
            baked = l.s.pos + (size_t)o->first_vertex * 4;
        } else {
            baked = fi == 0 ? l.s.rest_pos + (size_t)o->first_vertex * 4
                            : l.s.vertex_keys + ((size_t)o->key_first + (size_t)frames[fi] * o->vertex_count) * 4;
        }
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            assert_true(acc[v * 4 + 3] > 0);
            for (int k = 0; k < 3; k++)
                worst = fmax(worst, fabs(acc[v * 4 + k] / acc[v * 4 + 3] - baked[v * 4 + k]));
        }
        free(acc);
        free(bm);
    }
    print_message("%s: largest skinning difference %.3g (figure is 1.44 units tall)\n", name, worst);
    assert_true(worst < 1e-4);
    unload(&l);
    aiReleaseImport(ai);
}

static void test_skinning_matches_joint_transforms(void **state)
{
    (void)state;
    check_skinning("CesiumMan-keys", 0);
    check_skinning("CesiumMan", 1);
}

static void test_rigid_keys_follow_node_animation(void **state)
{
    (void)state;
    char path[4096];
    source_path(path, sizeof path, "HZ_SCENES_SRC", "gltf/BoxAnimated/glTF/BoxAnimated.gltf");
    const struct aiScene *ai = import(path);
    const struct aiAnimation *a = ai->mAnimations[0];
    loaded_t l;
    load("BoxAnimated", &l);
    int checked = 0;
    /* Times where every channel has a key (or is past its last one). */
    static const double seconds[] = { 0.0, 1.25, 2.5, 3.70833 };
    for (unsigned mi = 0; mi < ai->mNumMeshes; mi++) {
        const struct aiMesh *mesh = ai->mMeshes[mi];
        uint32_t oi = l.s.object_count;
        for (uint32_t i = 0; i < l.s.object_count; i++)
            if (l.s.objects[i].vertex_count &&
                !strcmp((const char *)l.s.objects[i].name, mi == 0 ? "nodes[3]" : "nodes[2]"))
                oi = i;
        assert_true(oi < l.s.object_count);
        const hz_object_t *o = &l.s.objects[oi];
        const struct aiNode *node = node_named(ai->mRootNode, (const char *)o->name);
        assert_non_null(node);
        assert_int_equal(o->motion, mi == 0 ? HZ_MOTION_NONE : HZ_MOTION_RIGID);
        for (size_t ti = 0; ti < sizeof seconds / sizeof seconds[0]; ti++) {
            hz_scene_animate(&l.s, (float)seconds[ti]);
            double g[16];
            world_at(a, node, seconds[ti] * a->mTicksPerSecond, g);
            /* Each source vertex must be at some baked vertex of the object (welding merges duplicates). */
            double worst = 0;
            for (unsigned v = 0; v < mesh->mNumVertices; v++) {
                double p[3], best = INFINITY;
                xform(g, &mesh->mVertices[v], p);
                for (uint32_t b = 0; b < o->vertex_count; b++) {
                    const float *q = l.s.pos + (size_t)(o->first_vertex + b) * 4;
                    double d = fabs(p[0] - q[0]) + fabs(p[1] - q[1]) + fabs(p[2] - q[2]);
                    best = fmin(best, d);
                }
                worst = fmax(worst, best);
            }
            if (worst > 1e-4)
                fail_msg("BoxAnimated %s at %.3f s: a vertex is %.3g from where the animation puts it",
                         (const char *)o->name, seconds[ti], worst);
            checked++;
        }
    }
    assert_int_equal(checked, 8);
    unload(&l);
    aiReleaseImport(ai);
}

static void test_furball_tubes_surround_the_strands(void **state)
{
    (void)state;
    char path[4096];
    source_path(path, sizeof path, "HZ_SCENES_SRC", "furball/furBall_A.bin.gz");
    size_t size;
    uint8_t *bin = gunzip_all(path, &size);
    /* Layout from furBall_A.xml (SOURCES.md): 455,505 uint32 indices at 0, float4 points at 1,822,020. */
    const uint32_t nidx = 455505, npts = 485872;
    assert_true(size >= 1822020u + (size_t)npts * 16);
    const uint32_t *idx = (const uint32_t *)bin;
    const float *pts = (const float *)(bin + 1822020);
    loaded_t l;
    load("furball", &l);
    const uint32_t ring = 3;
    uint32_t v = 0, strands = 0;
    double worst_c = 0, worst_r = 0;
    for (uint32_t k = 0; k < nidx;) {
        uint32_t e = k + 1;
        while (e < nidx && idx[e] == idx[e - 1] + 1)
            e++;
        for (uint32_t p = idx[k]; p <= idx[e - 1] + 1; p++, v += ring) {
            assert_true(v + ring <= l.s.vertex_count);
            const float *c = pts + (size_t)p * 4;
            double mean[3] = { 0, 0, 0 };
            for (uint32_t j = 0; j < ring; j++) {
                const float *q = l.s.rest_pos + (size_t)(v + j) * 4;
                double d = sqrt(pow(q[0] - c[0], 2) + pow(q[1] - c[1], 2) + pow(q[2] - c[2], 2));
                worst_r = fmax(worst_r, fabs(d - c[3]));
                for (int x = 0; x < 3; x++)
                    mean[x] += q[x] / ring;
            }
            for (int x = 0; x < 3; x++)
                worst_c = fmax(worst_c, fabs(mean[x] - c[x]));
        }
        strands++;
        k = e;
    }
    print_message("furball: %u strands, %u ring vertices; ring centre off by %.3g, radius off by %.3g\n", strands, v,
                  worst_c, worst_r);
    assert_int_equal(strands, 30367);
    assert_int_equal(v, l.s.vertex_count);
    assert_true(worst_c < 1e-5 && worst_r < 1e-5);
    assert_int_equal(l.s.objects[0].motion, HZ_MOTION_SPIN);
    unload(&l);
    free(bin);
}

/* ---- bad inputs ---- */

static char tmpdir[64];

typedef struct run {
    int status;     /* exit status, or 128 + signal */
    char out[8192]; /* stdout + stderr */
} run_t;

static void bake(run_t *r, const char *hook, const char *const *args)
{
    char log[128];
    snprintf(log, sizeof log, "%s/log", tmpdir);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, 1);
        dup2(fd, 2);
        if (hook)
            setenv("HZ_BAKE_TEST_CRASH", hook, 1);
        else
            unsetenv("HZ_BAKE_TEST_CRASH");
        const char *argv[16];
        int n = 0;
        argv[n++] = env("HZ_BAKE");
        for (; args[n - 1] && n < 15; n++)
            argv[n] = args[n - 1];
        argv[n] = NULL;
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int st;
    waitpid(pid, &st, 0);
    r->status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    size_t n;
    char *text = read_all(log, &n, 0);
    snprintf(r->out, sizeof r->out, "%s", text);
    free(text);
}

static void put(const char *name, const void *data, size_t size)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
}

static void put_text(const char *name, const char *text)
{
    put(name, text, strlen(text));
}

static void copy_prefix(const char *src, const char *name, size_t keep)
{
    size_t n;
    char *data = read_all(src, &n, 0);
    put(name, data, keep < n ? keep : n);
    free(data);
}

/* The output must be exactly as before the failed bake, and no temporary file may be left behind. */
static void assert_output_untouched(void)
{
    char path[256];
    snprintf(path, sizeof path, "%s/out.hzb", tmpdir);
    size_t n;
    char *data = read_all(path, &n, 0);
    assert_string_equal(data, "previous output");
    free(data);
    char cmd[256];
    snprintf(cmd, sizeof cmd, "ls %s | grep -c '\\.tmp\\.' >/dev/null", tmpdir);
    assert_int_not_equal(system(cmd), 0);
}

typedef struct bad_case {
    const char *what;
    const char *hook;
    const char *args[6]; /* relative names are in tmpdir; "OUT" is out.hzb */
    int status;
    int status2;         /* another acceptable status (0: none) */
    const char *says[3]; /* fragments the message must contain */
} bad_case_t;

static void test_bad_inputs_get_clear_errors_and_distinct_statuses(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-test.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    char p[4096];
    /* Inputs. */
    put_text("junk.xyz", "this is not a model\n");
    put_text("empty.obj", "");
    put_text("oob.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
    put_text("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    put_text("far.obj", "o far\nv 0 0 0\nv 1e12 0 0\nv 0 1 0\nf 1 2 3\n");
    put_text("point.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\nf 3 2 1\n"); /* welded into one vertex */
    put_text("tex.obj",
             "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl red\nf 1/1 2/2 3/3\n");
    put_text("tex.mtl", "newmtl red\nKd 0.8 0.1 0.1\nmap_Kd missing.png\n");
    put_text("ok.hzs", "light = position 0 1 1 color 1 1 1\ncamera = 0 eye 0 0 3 target 0 0 0\n");
    put_text("bad.hzs", "light = position 0 1 1 color 1 1 1\n\nmirror = 2\n");
    put_text("typo.hzs", "[material blue]\nmirror = 0.5\n");
    source_path(p, sizeof p, "HZ_SCENES_SRC", "dragon/dragon_vrip_res4.ply.gz");
    copy_prefix(p, "cut.ply.gz", 60000);
    size_t plen;
    char *ply = gunzip_all(p, &plen);
    put("cut.ply", ply, 30000); /* header + part of the vertices: assimp 5.2 aborts on this */
    put("headcut.ply", ply, 120); /* cut inside the header: assimp 5.2 loops forever on this */
    memcpy(ply + 60, "\0", 1);   /* a NUL in the header (the import fuzzer's lib-1f28d697d72ea06b): the same */
    put("headnul.ply", ply, 30000);
    free(ply);
    source_path(p, sizeof p, "HZ_SCENES_SRC", "gltf/BoxAnimated/glTF/BoxAnimated.gltf");
    copy_prefix(p, "box.gltf", SIZE_MAX);
    source_path(p, sizeof p, "HZ_SCENES_SRC", "gltf/BoxAnimated/glTF/BoxAnimated0.bin");
    copy_prefix(p, "BoxAnimated0.bin", 3000);
    /* A triangle whose translation is animated over 1e9 s: 3e10 rigid keys at the default rigid_rate (the import
     * fuzzer's glb asked for 512 million: 4 GiB of sample times). */
    put_text("longanim.gltf",
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"name\":\"tri\",\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
             "\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}],"
             "\"samplers\":[{\"input\":1,\"output\":2}]}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":2,"
             "\"type\":\"SCALAR\",\"min\":[0],\"max\":[1e9]},{\"bufferView\":2,\"componentType\":5126,\"count\":2,"
             "\"type\":\"VEC3\"}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
             "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":8},{\"buffer\":0,\"byteOffset\":44,\"byteLength\":24}],"
             "\"buffers\":[{\"byteLength\":68,\"uri\":\"longanim.bin\"}]}");
    static const float longanim[17] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1e9f, 0, 0, 0, 5, 0, 0 };
    put("longanim.bin", longanim, sizeof longanim);
    put_text("fur.xml",
             "<scene><RoundLineSegments><indices ofs=\"0\" size=\"2\"/>"
             "<positions ofs=\"8\" size=\"2\"/></RoundLineSegments></scene>");
    static const uint32_t fur_idx[2] = { 0, 7 }; /* segment 1 starts at point 7 of 2 */
    uint8_t fur[8 + 32];
    memcpy(fur, fur_idx, 8);
    memset(fur + 8, 0, 32);
    put("fur.bin", fur, sizeof fur);

    const char *cornell = NULL;
    char cb[4096];
    source_path(cb, sizeof cb, "HZ_SCENES_UNPACK", "CornellBox/CornellBox-Original.obj");
    cornell = cb;

    const bad_case_t cases[] = {
        { "missing model", NULL, { "nothere.obj", "OUT" }, 73, 0, { "nothere.obj", "no such file" } },
        { "unsupported format", NULL, { "junk.xyz", "OUT" }, 72, 0, { "junk.xyz", "unsupported model format" } },
        { "empty OBJ", NULL, { "empty.obj", "OUT" }, 68, 0, { "empty.obj", "assimp cannot import" } },
        { "OBJ index out of range", NULL, { "oob.obj", "OUT" }, 68, 0, { "oob.obj", "out of range" } },
        { "NaN vertex", NULL, { "nan.obj", "OUT" }, 71, 0, { "nan.obj", "non-finite position" } },
        /* The import fuzzer's regress-glb-vertex-beyond-2-36 (test/fuzz/corpus/import): a vertex the renderer
         * cannot trace was baked, and only the check of the finished image refused it, naming no vertex. */
        { "vertex beyond +-2^36", NULL, { "far.obj", "OUT" }, 71, 0, { "far.obj", "object 'far': vertex 1", "2^36" } },
        /* The import fuzzer's regress-ply-one-vertex: a PLY whose 89 faces all met in one vertex was baked into an
         * image the runtime refuses (it needs 3 vertices), and only that check said so. */
        { "all triangles in one point", NULL, { "point.obj", "OUT" }, 68, 0,
          { "point.obj", "2 triangles have only 1 distinct vertices" } },
        { "truncated .ply.gz", NULL, { "cut.ply.gz", "OUT" }, 68, 0, { "cut.ply.gz", "gzip" } },
        /* assimp 5.2.5 aborts in an assertion on this file: the child's crash becomes status 76. A fixed
         * assimp may refuse it cleanly instead (68); either way the baker survives and names the file. */
        { "truncated PLY", NULL, { "cut.ply", "OUT" }, 76, 68, { "cut.ply" } },
        /* Refused before assimp sees them; --timeout makes a regression fail fast instead of waiting 600 s. */
        { "PLY cut in its header", NULL, { "--timeout", "1", "headcut.ply", "OUT" }, 68, 0,
          { "headcut.ply", "no end_header line" } },
        { "NUL in a PLY header", NULL, { "--timeout", "1", "headnul.ply", "OUT" }, 68, 0,
          { "headnul.ply", "line 4 of the PLY header holds the control byte 0x00" } },
        { "truncated glTF buffer", NULL, { "box.gltf", "OUT" }, 68, 0, { "box.gltf", "byteLength" } },
        { "animation needing 3e10 keys", NULL, { "--timeout", "1", "longanim.gltf", "OUT" }, 71, 0,
          { "longanim.gltf", "object 'tri'", "more than 1000000 rigid keys" } },
        { "furball index out of range",
          NULL,
          { "fur.xml", "OUT" },
          68,
          0,
          { "fur.bin", "segment 1 starts at point 7 of 2" } },
        { "importer abort",
          "abort",
          { "-s", "ok.hzs", cornell, "OUT" },
          76,
          0,
          { "CornellBox-Original.obj", "importer crashed (abort" } },
        { "importer segfault",
          "segv",
          { "-s", "ok.hzs", cornell, "OUT" },
          76,
          0,
          { "CornellBox-Original.obj", "importer crashed" } }, /* ASan builds catch SIGSEGV and exit(1) */
        { "importer hangs",
          "hang",
          { "--timeout", "1", cornell, "OUT" },
          75,
          0,
          { "CornellBox-Original.obj", "longer than 1 s" } },
        { "bad sidecar value",
          NULL,
          { "-s", "bad.hzs", cornell, "OUT" },
          68,
          0,
          { "bad.hzs:3:", "belongs in a [material] section" } },
        { "sidecar names no material",
          NULL,
          { "-s", "typo.hzs", cornell, "OUT" },
          68,
          0,
          { "typo.hzs:1:", "matches no material" } },
        { "missing sidecar", NULL, { "-s", "nope.hzs", cornell, "OUT" }, 73, 0, { "nope.hzs" } },
        { "bad command line", NULL, { "--texture-max", "0", cornell, "OUT" }, 2, 0, { "--texture-max" } },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case_t *c = &cases[i];
        put_text("out.hzb", "previous output");
        char bufs[6][4096];
        const char *args[7];
        size_t n = 0;
        for (; n < 6 && c->args[n]; n++) {
            const char *a = c->args[n];
            if (!strcmp(a, "OUT"))
                snprintf(bufs[n], sizeof bufs[n], "%s/out.hzb", tmpdir);
            else if (a[0] != '-' && a[0] != '/' && strcmp(a, "1") && strcmp(a, "0"))
                snprintf(bufs[n], sizeof bufs[n], "%s/%s", tmpdir, a);
            else
                snprintf(bufs[n], sizeof bufs[n], "%s", a);
            args[n] = bufs[n];
        }
        args[n] = NULL;
        run_t r;
        bake(&r, c->hook, args);
        int ok = r.status == c->status || (c->status2 && r.status == c->status2);
        for (int k = 0; k < 3 && c->says[k]; k++)
            ok = ok && strstr(r.out, c->says[k]) != NULL;
        print_message("%-28s exit %3d: %s", c->what, r.status, r.out);
        if (!ok)
            fail_msg("%s: exit %d (want %d), output: %s", c->what, r.status, c->status, r.out);
        assert_output_untouched();
    }

    /* A missing texture is a warning: the bake succeeds and the material keeps its colour (Kd). */
    char out[256], tex[256];
    snprintf(out, sizeof out, "%s/out.hzb", tmpdir);
    snprintf(tex, sizeof tex, "%s/tex.obj", tmpdir);
    const char *args[] = { "-q", tex, out, NULL };
    run_t r;
    bake(&r, NULL, args);
    print_message("%-28s exit %3d: %s", "missing texture", r.status, r.out);
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "warning"));
    assert_non_null(strstr(r.out, "missing.png"));
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_plan_t plan;
    assert_int_equal(hz_scene_plan(img, size, &plan, NULL), HZ_OK);
    hz_scene_t s;
    assert_int_equal(hz_scene_load(&s, img, size, NULL, NULL), HZ_OK);
    const hz_material_t *red = material_named(&s, "red");
    assert_int_equal(red->base_texture, -1);
    assert_true(red->base_color[0] == 0.8f && red->base_color[1] == 0.1f && red->base_color[2] == 0.1f);
    free(img);

    /* --info on a good and on a damaged image. */
    char scene[4096];
    snprintf(scene, sizeof scene, "%s/CornellBox-Mirror.hzb", env("HZ_SCENES_DIR"));
    const char *info[] = { "--info", scene, NULL };
    bake(&r, NULL, info);
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "mirror"));
    assert_non_null(strstr(r.out, "memory plan"));
    void *bytes = read_all(scene, &size, 0);
    ((uint8_t *)bytes)[size - 1] ^= 0x40; /* inside the last section: a CRC mismatch */
    put("damaged.hzb", bytes, size);
    free(bytes);
    snprintf(scene, sizeof scene, "%s/damaged.hzb", tmpdir);
    bake(&r, NULL, info);
    print_message("%-28s exit %3d: %s", "--info damaged image", r.status, r.out);
    assert_int_equal(r.status, 70);
    assert_non_null(strstr(r.out, "damaged.hzb"));
    assert_non_null(strstr(r.out, "CRC mismatch"));

    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* ---- procedural motion from a sidecar ---- */

static const hz_object_t *object_with_material(const hz_scene_t *s, const char *material)
{
    for (uint32_t i = 0; i < s->object_count; i++) {
        const hz_object_t *o = &s->objects[i];
        if (o->triangle_count &&
            !strcmp((const char *)s->materials[hz_scene_tri_material(s, o->first_triangle)].name, material))
            return o;
    }
    fail_msg("no object with material '%s'", material);
    return NULL;
}

static void test_sidecar_motion_is_baked_and_animates(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-test.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    /* CornellBox-Original's OBJ groups are misplaced (the tall box is in group "shortBox"): sections also match
     * an object's material, so [object tallBox] finds the tall box. */
    put_text("motion.hzs",
             "light = position 0 1.8 0 color 5 5 5\n"
             "camera = 0 eye 0 1 4 target 0 1 0\n"
             "[object floor]\nmotion = spin\npivot = center\naxis = 0 2 0\nspeed = 90\n"
             "[object light]\nmotion = oscillate\namplitude = 0 0.1 0\nfrequency = 0.5\n"
             "[object tallBox]\nmotion = keys\nkey = 0\n"
             "key = 1 translate 0 0.5 0 rotate 0 1 0 90\n");
    char cb[4096], hzs[256], out[256];
    source_path(cb, sizeof cb, "HZ_SCENES_UNPACK", "CornellBox/CornellBox-Original.obj");
    snprintf(hzs, sizeof hzs, "%s/motion.hzs", tmpdir);
    snprintf(out, sizeof out, "%s/motion.hzb", tmpdir);
    const char *args[] = { "-q", "-s", hzs, cb, out, NULL };
    run_t r;
    bake(&r, NULL, args);
    if (r.status != 0)
        fail_msg("bake failed (%d): %s", r.status, r.out);
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_plan_t plan;
    assert_int_equal(hz_scene_plan(img, size, &plan, NULL), HZ_OK);
    assert_int_equal(plan.features, HZ_FEAT_MOTION | HZ_FEAT_NORMALS);
    void *mem = NULL;
    assert_int_equal(posix_memalign(&mem, 64, plan.arena_bytes + 64), 0);
    hz_arena_t arena;
    hz_arena_init(&arena, "scene", mem, plan.arena_bytes + 64);
    hz_scene_t s;
    assert_int_equal(hz_scene_load(&s, img, size, &arena, NULL), HZ_OK);
    const hz_object_t *floor = object_with_material(&s, "floor"), *light = object_with_material(&s, "light");
    const hz_object_t *tall = object_with_material(&s, "tallBox"), *shrt = object_with_material(&s, "shortBox");
    assert_int_equal(floor->motion, HZ_MOTION_SPIN);
    assert_int_equal(light->motion, HZ_MOTION_OSCILLATE);
    assert_int_equal(tall->motion, HZ_MOTION_RIGID);
    assert_int_equal(shrt->motion, HZ_MOTION_NONE);
    /* Spin: unit axis, radians per second, pivot at the floor's centre. */
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < floor->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], s.rest_pos[(size_t)(floor->first_vertex + v) * 4 + k]);
            hi[k] = fmax(hi[k], s.rest_pos[(size_t)(floor->first_vertex + v) * 4 + k]);
        }
    for (int k = 0; k < 3; k++)
        assert_true(fabs(floor->params[k] - 0.5 * (lo[k] + hi[k])) < 1e-6);
    assert_true(floor->params[3] == 0.0f && floor->params[4] == 1.0f && floor->params[5] == 0.0f);
    assert_true(fabs(floor->params[6] - 1.5707963267948966) < 1e-6);
    /* Keys: the second rotates 90 degrees about y and lifts by 0.5. */
    assert_int_equal(tall->key_count, 2);
    const hz_hzb_rigid_key_t *k1 = &s.rigid_keys[tall->key_first + 1];
    assert_true(k1->time == 1.0f && k1->translation[1] == 0.5f);
    assert_true(fabs(k1->rotation[1] - 0.7071067811865476) < 1e-6 && fabs(k1->rotation[3] - 0.7071067811865476) < 1e-6);
    /* Animate: at t = 1 the tall box is rotated (x, y, z) -> (z, y, -x) and lifted; at t = 0.5 the lamp is at
     * the top of its oscillation, sin(2 pi 0.5 0.5) = 1. */
    hz_scene_animate(&s, 1.0f);
    for (uint32_t v = 0; v < tall->vertex_count; v++) {
        const float *p = s.rest_pos + (size_t)(tall->first_vertex + v) * 4,
                    *q = s.pos + (size_t)(tall->first_vertex + v) * 4;
        assert_true(fabs(q[0] - p[2]) < 1e-5 && fabs(q[1] - (p[1] + 0.5)) < 1e-5 && fabs(q[2] + p[0]) < 1e-5);
    }
    hz_scene_animate(&s, 0.5f);
    for (uint32_t v = 0; v < light->vertex_count; v++) {
        const float *p = s.rest_pos + (size_t)(light->first_vertex + v) * 4,
                    *q = s.pos + (size_t)(light->first_vertex + v) * 4;
        assert_true(fabs(q[1] - (p[1] + 0.1)) < 1e-5 && q[0] == p[0] && q[2] == p[2]);
    }
    free(mem);
    free(img);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* ---- instancing ---- */

/* One triangle mesh used by two nodes (translated by -2 and +2 in x), with its buffer inline. */
static const char instanced_gltf[] =
    "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"name\":\"l"
    "eft\",\"mesh\":0,\"translation\":[-2,0,0]},{\"name\":\"right\",\"mesh\":0,\"translation\":[2,0,0]}],"
    "\"meshes\":[{\"name\":\"tri\",\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],\"b"
    "uffers\":[{\"byteLength\":44,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAA"
    "AAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=\"}],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLengt"
    "h\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":6}],\"accessors\":[{\"bufferView\":0,\"compon"
    "entType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"co"
    "mponentType\":5123,\"count\":3,\"type\":\"SCALAR\"}]}";

static void test_instanced_meshes_are_expanded(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-test.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    put_text("inst.gltf", instanced_gltf);
    char in[256], out[256];
    snprintf(in, sizeof in, "%s/inst.gltf", tmpdir);
    snprintf(out, sizeof out, "%s/inst.hzb", tmpdir);
    const char *args[] = { "-q", in, out, NULL };
    run_t r;
    bake(&r, NULL, args);
    if (r.status != 0)
        fail_msg("bake failed (%d): %s", r.status, r.out);
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_t s;
    assert_int_equal(hz_scene_load(&s, img, size, NULL, NULL), HZ_OK);
    assert_true(s.features & HZ_FEAT_INSTANCING);
    assert_int_equal(s.object_count, 2);
    assert_int_equal(s.triangle_count, 2);
    for (uint32_t o = 0; o < 2; o++) {
        const hz_object_t *ob = &s.objects[o];
        assert_string_equal((const char *)ob->name, o == 0 ? "left" : "right");
        assert_int_equal(ob->vertex_count, 3); /* each use owns its own copy of the vertices */
        float dx = o == 0 ? -2.0f : 2.0f;
        const uint32_t *t = s.tri + (size_t)ob->first_triangle * 3;
        static const float want[3][2] = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
        for (int k = 0; k < 3; k++) {
            const float *p = s.rest_pos + (size_t)t[k] * 4;
            assert_true(p[0] == want[k][0] + dx && p[1] == want[k][1] && p[2] == 0.0f);
        }
    }
    free(img);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* ---- normals of a scan ---- */

/* A PLY scan's vertex normals are the area-weighted mean of its faces' normals (an independent computation
 * here). assimp's generated normals on the shared vertices of a PLY were the normal of one arbitrary adjacent
 * face: on the dragon at res4, vertices up to 180 degrees off, the cause of dark single pixels (issue 18). */
static void test_scan_normals_follow_the_surface(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-scan.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    char ply[4096], out[256];
    source_path(ply, sizeof ply, "HZ_SCENES_SRC", "dragon/dragon_vrip_res4.ply.gz");
    snprintf(out, sizeof out, "%s/d.hzb", tmpdir);
    const char *args[] = { "-q", ply, out, NULL };
    run_t r;
    bake(&r, NULL, args);
    assert_int_equal(r.status, 0);
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_t s;
    assert_int_equal(hz_scene_load(&s, img, size, NULL, NULL), HZ_OK);
    assert_non_null(s.nrm);
    double *acc = calloc((size_t)s.vertex_count * 3, sizeof(double));
    assert_non_null(acc);
    for (uint32_t t = 0; t < s.triangle_count; t++) {
        const uint32_t *v = s.tri + (size_t)t * 3;
        const float *a = s.pos + (size_t)v[0] * 4, *b = s.pos + (size_t)v[1] * 4, *c = s.pos + (size_t)v[2] * 4;
        double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
        double n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++)
                acc[(size_t)v[k] * 3 + i] += n[i];
    }
    double worst = 0;
    uint32_t off5 = 0, checked = 0;
    for (uint32_t i = 0; i < s.vertex_count; i++) {
        const double *q = acc + (size_t)i * 3;
        double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        if (!(len > 1e-30))
            continue;
        const float *n = s.nrm + (size_t)i * 4;
        double d = (n[0] * q[0] + n[1] * q[1] + n[2] * q[2]) / len;
        double ang = acos(d > 1 ? 1 : d < -1 ? -1 : d) * 180.0 / 3.14159265358979;
        worst = ang > worst ? ang : worst;
        off5 += ang > 5.0;
        checked++;
    }
    print_message("dragon res4: %u vertices, largest angle to the area-weighted face normal %.3g deg, %u over 5 deg\n",
                  checked, worst, off5);
    assert_true(checked > 4000);
    assert_true(worst < 0.1); /* float rounding: 0.017 here */
    free(acc);
    free(img);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* ---- OBJ glass, bump maps, the help text ---- */

static int count_of(const char *hay, const char *needle)
{
    int n = 0;
    for (const char *p = strstr(hay, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

/* Glass (transparency illum modes, Tf, Kd 0, no d) becomes a blended surface of opacity 1 - mean(Tf), with a
 * warning per material; an opaque illum keeps Tf ignored; a bump map is said once per material with -v. */
static void test_obj_glass_and_bump_maps(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-glass.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    put_text("g.obj", "mtllib g.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl glass\nf 1 2 3\n"
                      "usemtl wall\nf 1 2 4\nusemtl tinted\nf 1 3 4\nusemtl dark\nf 2 3 4\n");
    put_text("g.mtl", "newmtl glass\nKd 0 0 0\nKs 0.3 0.3 0.3\nTf 0.8 0.8 0.8\nillum 4\nmap_bump b.png\n"
                      "bump b.png\n\nnewmtl wall\nKd 0.5 0.5 0.5\nTf 1 1 1\nillum 2\nmap_bump w.png\n\n"
                      "newmtl tinted\nKd 0 0 0\nTf 0.1 0.4 0.7\nd 0.5\nillum 7\n\n"
                      "newmtl dark\nKd 0 0 0\nTf 0 0 0\nillum 6\n");
    char obj[256], out[256];
    snprintf(obj, sizeof obj, "%s/g.obj", tmpdir);
    snprintf(out, sizeof out, "%s/g.hzb", tmpdir);
    const char *args[] = { "-v", obj, out, NULL };
    run_t r;
    bake(&r, NULL, args);
    print_message("%s", r.out);
    assert_int_equal(r.status, 0);
    assert_int_equal(count_of(r.out, "material 'glass' is glass (illum 4, Tf 0.8 0.8 0.8): baked as a blended "
                                     "surface of alpha 0.2"), 1);
    assert_int_equal(count_of(r.out, "material 'dark' is glass (illum 6, Tf 0 0 0): baked as opaque"), 1);
    assert_int_equal(count_of(r.out, "'wall' is glass"), 0);
    assert_int_equal(count_of(r.out, "'tinted' is glass"), 0); /* its d decides */
    assert_int_equal(count_of(r.out, "material 'glass': bump map 'b.png' is not baked"), 1);
    assert_int_equal(count_of(r.out, "material 'wall': bump map 'w.png' is not baked"), 1);
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_t s;
    assert_int_equal(hz_scene_load(&s, img, size, NULL, NULL), HZ_OK);
    const hz_material_t *glass = material_named(&s, "glass"), *wall = material_named(&s, "wall");
    const hz_material_t *tinted = material_named(&s, "tinted"), *dark = material_named(&s, "dark");
    assert_int_equal(glass->alpha_mode, HZ_ALPHA_BLEND);
    assert_true(fabsf(glass->alpha - 0.2f) < 1e-6f);
    assert_int_equal(wall->alpha_mode, HZ_ALPHA_OPAQUE);
    assert_int_equal(tinted->alpha_mode, HZ_ALPHA_BLEND);
    assert_true(tinted->alpha == 0.5f);
    assert_int_equal(dark->alpha_mode, HZ_ALPHA_OPAQUE);
    free(img);
    /* Without -v the bump maps are not mentioned; the glass warning stays. */
    const char *quiet[] = { obj, out, NULL };
    bake(&r, NULL, quiet);
    assert_int_equal(r.status, 0);
    assert_int_equal(count_of(r.out, "bump map"), 0);
    assert_int_equal(count_of(r.out, "is glass"), 2);
    /* Phases are named while the import child works: the skinning bake is not "importing". */
    char cm[4096], cms[4096];
    source_path(cm, sizeof cm, "HZ_SCENES_SRC", "gltf/CesiumMan/glTF/CesiumMan.gltf");
    snprintf(cms, sizeof cms, "programs/hzbake/scenes/CesiumMan-small.hzs"); /* tests run from the repository root */
    const char *skin[] = { "-s", cms, cm, out, NULL };
    setenv("HZ_PROGRESS", "all", 1);
    bake(&r, NULL, skin);
    unsetenv("HZ_PROGRESS");
    print_message("%s", r.out);
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "CesiumMan.gltf: baking skinning of mesh 'Cesium_Man' (3273 vertices, 19 bones"));
    assert_non_null(strstr(r.out, "CesiumMan.gltf: importing (assimp)"));
    /* The help text names every exit status the baker uses. */
    const char *help[] = { "--help", NULL };
    bake(&r, NULL, help);
    assert_int_equal(r.status, 0);
    static const char *const codes[] = { " 2 bad command line", "66 ", "67 ", "68 ", "70 ", "71 ", "72 ", "73 ",
                                         "75 ", "76 " };
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; i++)
        if (!strstr(r.out, codes[i]))
            fail_msg("hzbake --help does not list exit status '%s'", codes[i]);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* Writes `text` as tmpdir/keys.hzs; its path goes to path. */
static void write_sidecar(char *path, size_t size, const char *text)
{
    snprintf(path, size, "%s/keys.hzs", tmpdir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    assert_int_equal(fclose(f), 0);
}

/* A bake that no board can load (its scene arena need exceeds every board's) gets a warning naming the
 * largest board and what to change (skinned vertex keys: skin_rate); one that fits gets none. The board list is
 * replaced by a test hook so a small scene stands in for a huge one. */
static void test_warns_when_no_board_can_load_it(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-test.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    char model[4096], out[256];
    source_path(model, sizeof model, "HZ_SCENES_SRC", "gltf/CesiumMan/glTF/CesiumMan.gltf");
    snprintf(out, sizeof out, "%s/cm.hzb", tmpdir);
    char keys_sc[300];
    write_sidecar(keys_sc, sizeof keys_sc, "skinning = keys\n");
    const char *keys_args[] = { "-q", "-s", keys_sc, model, out, NULL };
    run_t r;
    setenv("HZ_BAKE_TEST_BOARDS", "big-board=4 small-board=2", 1);
    bake(&r, NULL, keys_args); /* per-vertex keys: 12 MB, most of it keys */
    assert_int_equal(r.status, 0); /* a warning, not an error: the file is written */
    if (!strstr(r.out, "no board can load it") || !strstr(r.out, "big-board, has 4 MiB") ||
        !strstr(r.out, "skin_rate 30") || !strstr(r.out, "skinning = runtime"))
        fail_msg("no or wrong warning: %s", r.out);
    const char *args[] = { "-q", model, out, NULL };
    bake(&r, NULL, args); /* skinned at run time: 5.9 MB, most of it the texture */
    assert_int_equal(r.status, 0);
    if (!strstr(r.out, "no board can load it") || !strstr(r.out, "lower texture_max") || strstr(r.out, "skin_rate"))
        fail_msg("no or wrong warning: %s", r.out);
    unsetenv("HZ_BAKE_TEST_BOARDS");
    bake(&r, NULL, args); /* the real boards: CesiumMan fits them all */
    assert_int_equal(r.status, 0);
    assert_null(strstr(r.out, "no board can load it"));
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

/* Bakes args (which write `out`) and returns the output's size. */
static long long bake_size(const char *const *args, const char *out)
{
    run_t r;
    bake(&r, NULL, args);
    if (r.status != 0)
        fail_msg("%s", r.out);
    struct stat st;
    assert_int_equal(stat(out, &st), 0);
    return (long long)st.st_size;
}

/* The long skinned model (tools/gen/skinned_gltf.c, written by `make scenes`: 61,440 triangles, 48 joints, 35 s)
 * bakes small with runtime skinning, the default; the old per-vertex keys are far larger even at 1 frame/s. */
static void test_long_skinned_model_bakes_small(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/hzbake-test.XXXXXX");
    assert_non_null(mkdtemp(tmpdir));
    char model[4096], out[256], sc[300];
    source_path(model, sizeof model, "HZ_SCENES_GEN", "tentacles/tentacles.gltf");
    snprintf(out, sizeof out, "%s/t.hzb", tmpdir);
    const char *args[] = { "-q", "-s", "programs/hzbake/scenes/tentacles.hzs", model, out, NULL };
    long long rt = bake_size(args, out);
    print_message("tentacles, skinned at run time: %lld bytes\n", rt);
    assert_true(rt < 20 << 20);
    size_t size;
    void *img = read_all(out, &size, 1);
    hz_scene_plan_t plan;
    hz_error_t err;
    assert_int_equal(hz_scene_plan(img, size, &plan, &err), HZ_OK);
    const hz_hzb_header_t *h = img;
    assert_int_equal(h->joint_count, 48);
    assert_int_equal(h->vertex_key_count, 0);
    assert_true(h->duration == 35.0f);
    free(img);
    write_sidecar(sc, sizeof sc, "skinning = keys\nskin_rate = 1\n");
    const char *keys[] = { "-q", "-s", sc, model, out, NULL };
    long long kb = bake_size(keys, out);
    print_message("tentacles, per-vertex keys at 1 frame/s: %lld bytes\n", kb);
    assert_true(kb > 4 * rt);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmpdir);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_triangle_counts_and_feature_masks),
        cmocka_unit_test(test_materials_mean_what_the_sources_say),
        cmocka_unit_test(test_mip_levels_are_linear_box_filters),
        cmocka_unit_test(test_round_trip_geometry_equals_source),
        cmocka_unit_test(test_skinning_matches_joint_transforms),
        cmocka_unit_test(test_rigid_keys_follow_node_animation),
        cmocka_unit_test(test_furball_tubes_surround_the_strands),
        cmocka_unit_test(test_bad_inputs_get_clear_errors_and_distinct_statuses),
        cmocka_unit_test(test_sidecar_motion_is_baked_and_animates),
        cmocka_unit_test(test_instanced_meshes_are_expanded),
        cmocka_unit_test(test_obj_glass_and_bump_maps),
        cmocka_unit_test(test_scan_normals_follow_the_surface),
        cmocka_unit_test(test_warns_when_no_board_can_load_it),
        cmocka_unit_test(test_long_skinned_model_bakes_small),
    };
    return HZ_RUN(tests);
}
