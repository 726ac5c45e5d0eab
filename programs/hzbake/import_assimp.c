/* OBJ, PLY and glTF import through assimp's C API (see scene.h).
 *
 * Every mesh instance (node x mesh) becomes one object. Its kind follows the source:
 *  - static: no node on its path to the root is animated: positions and normals are baked into world space
 *    (assimp's own matrix and vector functions, so tests can reproduce them bit for bit);
 *  - rigid: some node on its path is animated: positions stay in mesh space and the object's world transform is
 *    sampled into rigid keys (decomposed into T, R, S) at every source key time plus rigid_rate samples per
 *    second, so the runtime's linear interpolation follows nested animations and slerps closely;
 *  - skinned: the mesh has bones and the animation moves them. By default (sidecar `skinning = runtime`) the
 *    mesh keeps its bind pose and is skinned at run time (HZ_MOTION_SKIN): each bone becomes a bind (joint +
 *    offset matrix), each bone node a joint whose world transform is sampled at skin_rate (shared by all
 *    meshes), each vertex keeps its 4 largest weights. With `skinning = keys`: skin_rate frames per second of
 *    world positions and normals (per-vertex keys); frame 0 is also the rest geometry.
 * Triangles keep the source order; OBJ-style repeated vertices are welded. */
#include "scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/GltfMaterial.h>
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

typedef enum { FMT_OBJ, FMT_PLY, FMT_GLTF } fmt_t;

typedef struct ctx {
    hz_bake_scene_t *s;
    const hz_bake_sidecar_t *sc;
    const struct aiScene *ai;
    const struct aiAnimation *anim; /* NULL when the model has none */
    double tps;                     /* ticks per second of anim */
    fmt_t fmt;
    char dir[4096];
    uint32_t *mesh_uses;
    uint64_t skipped_faces;
    hz_error_t *err;
} ctx_t;

/* ---- materials ---- */

static float clamp01(float x)
{
    return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; /* NaN -> 0 */
}

static int texture_ref(ctx_t *c, const struct aiString *ref, int alpha_from_luma, const char *material)
{
    const char *r = ref->data;
    if (r[0] == '*') { /* embedded: "*N" */
        char *end;
        unsigned long n = strtoul(r + 1, &end, 10);
        if (*end || n >= c->ai->mNumTextures) {
            hz_bake_warn("%s: material '%s' names embedded texture '%s', which does not exist; it uses its colour",
                         c->s->model, material, r);
            return -1;
        }
        const struct aiTexture *t = c->ai->mTextures[n];
        if (t->mHeight != 0) {
            hz_bake_warn(
                "%s: embedded texture '%s' is stored uncompressed, which the baker does not read; material '%s' "
                "uses its colour",
                c->s->model, r, material);
            return -1;
        }
        char key[8192];
        snprintf(key, sizeof key, "%s#%s", c->s->model, r);
        return hz_bake_texture_from_memory(c->s, key, (const uint8_t *)t->pcData, t->mWidth, alpha_from_luma,
                                           c->sc->texture_max, material);
    }
    char path[8192];
    if (!hz_bake_resolve(c->dir, r, path, sizeof path))
        snprintf(path, sizeof path, "%s/%s", c->dir, r);
    return hz_bake_texture_get(c->s, path, alpha_from_luma, c->sc->texture_max, material);
}

static int first_texture(const struct aiMaterial *am, enum aiTextureType type, struct aiString *path)
{
    if (aiGetMaterialTextureCount(am, type) == 0)
        return 0;
    return aiGetMaterialTexture(am, type, 0, path, NULL, NULL, NULL, NULL, NULL, NULL) == aiReturn_SUCCESS &&
        path->length > 0;
}

static void add_material(ctx_t *c, const struct aiMaterial *am, unsigned index)
{
    hz_bake_material_t *m = hz_bake_vec_push(&c->s->mats, 1);
    struct aiString name;
    if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS && name.length)
        hz_bake_strcpy(m->name, sizeof m->name, name.data);
    else
        snprintf(m->name, sizeof m->name, "material%u", index);
    hz_bake_set_name(m->m.name, m->name);
    m->m.alpha = 1.0f;
    m->m.alpha_cutoff = 0.5f;
    m->m.alpha_mode = HZ_ALPHA_OPAQUE;
    m->m.base_texture = m->m.alpha_texture = -1;

    struct aiColor4D col = { 0.8f, 0.8f, 0.8f, 1.0f };
    int have_base = c->fmt == FMT_GLTF && aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &col) == aiReturn_SUCCESS;
    if (!have_base && aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &col) != aiReturn_SUCCESS)
        col.r = col.g = col.b = 0.8f, col.a = 1.0f;
    m->m.base_color[0] = clamp01(col.r), m->m.base_color[1] = clamp01(col.g), m->m.base_color[2] = clamp01(col.b);
    memcpy(m->source_color, m->m.base_color, sizeof m->source_color);

    struct aiString tex;
    int base = -1;
    if ((c->fmt == FMT_GLTF && first_texture(am, aiTextureType_BASE_COLOR, &tex)) ||
        first_texture(am, aiTextureType_DIFFUSE, &tex)) {
        base = texture_ref(c, &tex, 0, m->name);
    }
    if (base >= 0) {
        m->m.base_texture = base;
        /* OBJ: map_Kd gives the colour (Kd is what exporters write as its average, and the fallback when the
         * texture is missing); glTF: baseColorFactor multiplies the texture, as the spec says. */
        if (c->fmt == FMT_OBJ)
            m->m.base_color[0] = m->m.base_color[1] = m->m.base_color[2] = 1.0f;
    }
    int base_has_alpha = base >= 0 && (HZ_BAKE_AT(c->s->texs, hz_bake_texture_t, base)->t.flags & 1u);

    if (c->fmt == FMT_GLTF) {
        struct aiString mode;
        float cutoff = 0.5f;
        m->m.alpha = clamp01(col.a);
        aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_ALPHACUTOFF, &cutoff, NULL);
        m->m.alpha_cutoff = clamp01(cutoff);
        if (aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS) {
            if (!strcmp(mode.data, "MASK"))
                m->m.alpha_mode = HZ_ALPHA_MASK;
            else if (!strcmp(mode.data, "BLEND"))
                m->m.alpha_mode = HZ_ALPHA_BLEND;
            else if (strcmp(mode.data, "OPAQUE"))
                hz_bake_warn("%s: material '%s' has unknown alphaMode '%s'; treated as OPAQUE", c->s->model, m->name,
                             mode.data);
        }
        if (m->m.alpha_mode != HZ_ALPHA_OPAQUE)
            m->m.alpha_texture = base;
        if (m->m.alpha_mode == HZ_ALPHA_MASK && base < 0 && aiGetMaterialTextureCount(am, aiTextureType_BASE_COLOR))
            m->m.alpha_mode = HZ_ALPHA_OPAQUE; /* its cutout texture is missing (warned): nothing to cut */
    } else if (c->fmt == FMT_OBJ) {
        float d = 1.0f;
        aiGetMaterialFloatArray(am, AI_MATKEY_OPACITY, &d, NULL);
        m->m.alpha = clamp01(d);
        int amap = -1;
        if (first_texture(am, aiTextureType_OPACITY, &tex)) {
            amap = texture_ref(c, &tex, 1, m->name); /* map_d: a scalar map, grey when it has no alpha */
        }
        if (amap >= 0) {
            m->m.alpha_mode = HZ_ALPHA_MASK;
            m->m.alpha_texture = amap;
        } else if (m->m.alpha < 1.0f) {
            m->m.alpha_mode = HZ_ALPHA_BLEND;
            m->m.alpha_texture = base_has_alpha ? base : -1;
        } else if (base_has_alpha) {
            /* An RGBA map_Kd with transparent texels and no map_d: the usual way to ship foliage cutouts. */
            m->m.alpha_mode = HZ_ALPHA_MASK;
            m->m.alpha_texture = base;
        }
        /* illum 3 (reflection, ray traced), 5 (Fresnel mirror) and 8 (reflection): a mirror of strength Ks. */
        int illum = 0;
        unsigned one = 1;
        struct aiColor4D ks = { 0, 0, 0, 1 };
        int have_illum = aiGetMaterialIntegerArray(am, "$mat.illum", 0, 0, &illum, &one) == aiReturn_SUCCESS;
        if (have_illum && (illum == 3 || illum == 5 || illum == 8) &&
            aiGetMaterialColor(am, AI_MATKEY_COLOR_SPECULAR, &ks) == aiReturn_SUCCESS)
            m->m.mirror = clamp01(fmaxf(ks.r, fmaxf(ks.g, ks.b)));
        /* Glass: illum 4, 6, 7 or 9 (transparency on) with no d < 1 and no map_d. Its transmission filter Tf
         * becomes opacity, alpha = 1 - mean(Tf), blended: the renderer has no refraction, so glass shows what is
         * behind it dimmed by its opacity instead of opaque black (what Kd 0 alone would give). */
        struct aiColor4D tf = { 0, 0, 0, 1 };
        if (have_illum && (illum == 4 || illum == 6 || illum == 7 || illum == 9) && m->m.alpha_mode == HZ_ALPHA_OPAQUE &&
            aiGetMaterialColor(am, AI_MATKEY_COLOR_TRANSPARENT, &tf) == aiReturn_SUCCESS) {
            float t = clamp01((tf.r + tf.g + tf.b) / 3.0f);
            if (t > 0.0f) {
                m->m.alpha = 1.0f - t;
                m->m.alpha_mode = HZ_ALPHA_BLEND;
                m->m.alpha_texture = base_has_alpha ? base : -1;
            }
            hz_bake_warn("%s: material '%s' is glass (illum %d, Tf %.3g %.3g %.3g): baked as %s%.3g (no "
                         "refraction; a sidecar [material] section can override it)",
                         c->s->model, m->name, illum, (double)tf.r, (double)tf.g, (double)tf.b,
                         t > 0.0f ? "a blended surface of alpha " : "opaque, its Tf transmits nothing: alpha ",
                         (double)m->m.alpha);
        }
        /* Bump and normal maps are not baked: said once per material (a model names them per material). */
        if (first_texture(am, aiTextureType_HEIGHT, &tex) || first_texture(am, aiTextureType_NORMALS, &tex))
            hz_bake_progress("material '%s': bump map '%s' is not baked (no bump mapping)", m->name, tex.data);
    }
}

/* ---- node transforms and animation ---- */

static const struct aiNodeAnim *channel(const ctx_t *c, const struct aiNode *n)
{
    if (!c->anim)
        return NULL;
    for (unsigned i = 0; i < c->anim->mNumChannels; i++)
        if (!strcmp(c->anim->mChannels[i]->mNodeName.data, n->mName.data))
            return c->anim->mChannels[i];
    return NULL;
}

static int path_animated(const ctx_t *c, const struct aiNode *n)
{
    for (; n; n = n->mParent)
        if (channel(c, n))
            return 1;
    return 0;
}

static void vec_at(const struct aiVectorKey *k, unsigned n, double t, struct aiVector3D *out)
{
    if (n == 1 || t <= k[0].mTime) {
        *out = k[0].mValue;
        return;
    }
    if (t >= k[n - 1].mTime) {
        *out = k[n - 1].mValue;
        return;
    }
    unsigned i = 0;
    while (i + 1 < n && k[i + 1].mTime <= t)
        i++;
    double span = k[i + 1].mTime - k[i].mTime;
    float w = span > 0 ? (float)((t - k[i].mTime) / span) : 0.0f;
    out->x = k[i].mValue.x + (k[i + 1].mValue.x - k[i].mValue.x) * w;
    out->y = k[i].mValue.y + (k[i + 1].mValue.y - k[i].mValue.y) * w;
    out->z = k[i].mValue.z + (k[i + 1].mValue.z - k[i].mValue.z) * w;
}

static void quat_at(const struct aiQuatKey *k, unsigned n, double t, struct aiQuaternion *out)
{
    if (n == 1 || t <= k[0].mTime) {
        *out = k[0].mValue;
        return;
    }
    if (t >= k[n - 1].mTime) {
        *out = k[n - 1].mValue;
        return;
    }
    unsigned i = 0;
    while (i + 1 < n && k[i + 1].mTime <= t)
        i++;
    double span = k[i + 1].mTime - k[i].mTime;
    float w = span > 0 ? (float)((t - k[i].mTime) / span) : 0.0f;
    aiQuaternionInterpolate(out, &k[i].mValue, &k[i + 1].mValue, w);
    aiQuaternionNormalize(out);
}

static void local_at(const ctx_t *c, const struct aiNode *n, double ticks, struct aiMatrix4x4 *m)
{
    const struct aiNodeAnim *ch = channel(c, n);
    if (!ch) {
        *m = n->mTransformation;
        return;
    }
    /* A channel without keys of one kind keeps the node's own value for it. */
    struct aiVector3D s0, t0;
    struct aiQuaternion r0;
    aiDecomposeMatrix(&n->mTransformation, &s0, &r0, &t0);
    struct aiVector3D t = t0, s = s0;
    struct aiQuaternion r = r0;
    if (ch->mNumPositionKeys)
        vec_at(ch->mPositionKeys, ch->mNumPositionKeys, ticks, &t);
    if (ch->mNumRotationKeys)
        quat_at(ch->mRotationKeys, ch->mNumRotationKeys, ticks, &r);
    if (ch->mNumScalingKeys)
        vec_at(ch->mScalingKeys, ch->mNumScalingKeys, ticks, &s);
    aiMatrix4FromScalingQuaternionPosition(m, &s, &r, &t);
}

/* World transform at `ticks` (static nodes use their own matrices). */
static void global_at(const ctx_t *c, const struct aiNode *n, double ticks, struct aiMatrix4x4 *m)
{
    struct aiMatrix4x4 local;
    local_at(c, n, ticks, &local);
    if (!n->mParent) {
        *m = local;
        return;
    }
    global_at(c, n->mParent, ticks, m);
    aiMultiplyMatrix4(m, &local); /* m = parent * local */
}

static void global_static(const struct aiNode *n, struct aiMatrix4x4 *m)
{
    if (!n->mParent) {
        *m = n->mTransformation;
        return;
    }
    global_static(n->mParent, m);
    aiMultiplyMatrix4(m, &n->mTransformation);
}

static const struct aiNode *find_node(const struct aiNode *n, const char *name)
{
    if (!strcmp(n->mName.data, name))
        return n;
    for (unsigned i = 0; i < n->mNumChildren; i++) {
        const struct aiNode *f = find_node(n->mChildren[i], name);
        if (f)
            return f;
    }
    return NULL;
}

/* Normal matrix (inverse transpose of the upper 3x3) of m. */
static void normal_matrix(const struct aiMatrix4x4 *m, struct aiMatrix3x3 *nm)
{
    aiMatrix3FromMatrix4(nm, m);
    aiMatrix3Inverse(nm);
    aiTransposeMatrix3(nm);
}

static double det3(const struct aiMatrix4x4 *m)
{
    return (double)m->a1 * ((double)m->b2 * m->c3 - (double)m->b3 * m->c2) -
        (double)m->a2 * ((double)m->b1 * m->c3 - (double)m->b3 * m->c1) +
        (double)m->a3 * ((double)m->b1 * m->c2 - (double)m->b2 * m->c1);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* ---- meshes ---- */

/* Appends matrix g as a rigid key at `time` (T, R, S decomposed; the quaternion's sign continues prev_q's so
 * interpolation takes the short way); *worst grows to the relative error of T R S against g (shear the keys
 * cannot hold). Returns 1 for a degenerate matrix (nothing appended). */
static int push_matrix_key(ctx_t *c, const struct aiMatrix4x4 *g, float time, float prev_q[4], double *worst)
{
    struct aiMatrix4x4 back;
    struct aiVector3D s, t;
    struct aiQuaternion r;
    aiDecomposeMatrix(g, &s, &r, &t);
    double ql = sqrt((double)r.x * r.x + (double)r.y * r.y + (double)r.z * r.z + (double)r.w * r.w);
    if (!(ql > 0) || !isfinite(ql) || !isfinite(t.x + t.y + t.z) || !isfinite(s.x + s.y + s.z))
        return 1;
    float q[4] = { (float)(r.x / ql), (float)(r.y / ql), (float)(r.z / ql), (float)(r.w / ql) };
    if (q[0] * prev_q[0] + q[1] * prev_q[1] + q[2] * prev_q[2] + q[3] * prev_q[3] < 0)
        for (int k = 0; k < 4; k++)
            q[k] = -q[k];
    memcpy(prev_q, q, 4 * sizeof(float));
    struct aiQuaternion rq = { q[3], q[0], q[1], q[2] };
    aiMatrix4FromScalingQuaternionPosition(&back, &s, &rq, &t);
    const float *a = &g->a1, *b = &back.a1;
    for (int k = 0; k < 16; k++)
        *worst = fmax(*worst, fabs((double)a[k] - b[k]) / (1.0 + fabs((double)a[k])));
    hz_hzb_rigid_key_t *key = hz_bake_vec_push(&c->s->rkeys, 1);
    key->time = time;
    key->translation[0] = t.x, key->translation[1] = t.y, key->translation[2] = t.z;
    memcpy(key->rotation, q, sizeof q);
    key->scale[0] = s.x, key->scale[1] = s.y, key->scale[2] = s.z;
    return 0;
}

#define RIGID_SAMPLES_MAX 1000000u /* per object; what joint keys are capped at */

static hz_status_t rigid_keys(ctx_t *c, const struct aiNode *node, hz_bake_object_t *o)
{
    hz_bake_vec_t times;
    hz_bake_vec_init(&times, sizeof(double));
    double dur = c->anim->mDuration;
    for (const struct aiNode *n = node; n; n = n->mParent) {
        const struct aiNodeAnim *ch = channel(c, n);
        if (!ch)
            continue;
        for (unsigned i = 0; i < ch->mNumPositionKeys; i++)
            *(double *)hz_bake_vec_push(&times, 1) = ch->mPositionKeys[i].mTime;
        for (unsigned i = 0; i < ch->mNumRotationKeys; i++)
            *(double *)hz_bake_vec_push(&times, 1) = ch->mRotationKeys[i].mTime;
        for (unsigned i = 0; i < ch->mNumScalingKeys; i++)
            *(double *)hz_bake_vec_push(&times, 1) = ch->mScalingKeys[i].mTime;
    }
    double step = c->tps / c->sc->rigid_rate;
    /* The samples are (duration / step) + 1: a long animation or a high rigid_rate could ask for billions (the
     * import fuzzer's glb asked for 512 million, 4 GiB of sample times). */
    if (step > 0 && !(dur / step < RIGID_SAMPLES_MAX)) {
        hz_bake_vec_free(&times);
        return hz_bake_err(c->err, HZ_E_RANGE,
                           "%s: object '%s': its %.6g s animation at rigid_rate %g keys/s needs more than %u rigid "
                           "keys; lower rigid_rate in the sidecar or shorten the animation",
                           c->s->model, o->name, dur / c->tps, (double)c->sc->rigid_rate, RIGID_SAMPLES_MAX);
    }
    for (double t = 0; t <= dur && step > 0; t += step)
        *(double *)hz_bake_vec_push(&times, 1) = t;
    double *tv = times.data;
    qsort(tv, times.len, sizeof(double), cmp_double);
    o->o.motion = HZ_MOTION_RIGID;
    o->o.key_first = (uint32_t)c->s->rkeys.len;
    float prev_time = -INFINITY;
    float prev_q[4] = { 0, 0, 0, 1 };
    double worst = 0;
    for (size_t i = 0; i < times.len; i++) {
        if (!isfinite(tv[i]) || tv[i] < 0)
            continue;
        float time = (float)(tv[i] / c->tps);
        if (!(time > prev_time + 1e-6f))
            continue; /* duplicates, and keys too close to be strictly increasing in float */
        struct aiMatrix4x4 g;
        global_at(c, node, tv[i], &g);
        if (push_matrix_key(c, &g, time, prev_q, &worst)) {
            hz_bake_vec_free(&times);
            return hz_bake_err(c->err, HZ_E_RANGE, "%s: object '%s': its transform at %g s is degenerate", c->s->model,
                               o->name, (double)time);
        }
        prev_time = time;
    }
    hz_bake_vec_free(&times);
    o->o.key_count = (uint32_t)c->s->rkeys.len - o->o.key_first;
    if (worst > 1e-3)
        hz_bake_warn("%s: object '%s': its animated transform has shear the rigid keys cannot hold (error %.2g)",
                     c->s->model, o->name, worst);
    return HZ_OK;
}

typedef struct influence {
    uint32_t bone;
    float weight;
} influence_t;

/* Skinned positions and normals of every vertex at `ticks` (world space). */
static void skin_pose(ctx_t *c, const struct aiNode *node, const struct aiMesh *mesh, const struct aiNode **bones,
                      const uint32_t *inf_first, const influence_t *inf, double ticks, float *pos, float *nrm)
{
    struct aiMatrix4x4 *bm = hz_bake_xmalloc(sizeof *bm * (mesh->mNumBones + 1u));
    for (unsigned b = 0; b < mesh->mNumBones; b++) {
        global_at(c, bones[b], ticks, &bm[b]);
        aiMultiplyMatrix4(&bm[b], &mesh->mBones[b]->mOffsetMatrix);
    }
    global_at(c, node, ticks, &bm[mesh->mNumBones]); /* vertices without weights follow their node */
    for (unsigned v = 0; v < mesh->mNumVertices; v++) {
        double p[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 }, wsum = 0;
        uint32_t k0 = inf_first[v], k1 = inf_first[v + 1];
        influence_t self = { mesh->mNumBones, 1.0f };
        const influence_t *list = k1 > k0 ? inf + k0 : &self;
        uint32_t count = k1 > k0 ? k1 - k0 : 1;
        const struct aiVector3D *sp = &mesh->mVertices[v];
        const struct aiVector3D *sn = mesh->mNormals ? &mesh->mNormals[v] : NULL;
        for (uint32_t k = 0; k < count; k++) {
            const struct aiMatrix4x4 *m = &bm[list[k].bone];
            double w = list[k].weight;
            wsum += w;
            p[0] += w * ((double)m->a1 * sp->x + (double)m->a2 * sp->y + (double)m->a3 * sp->z + m->a4);
            p[1] += w * ((double)m->b1 * sp->x + (double)m->b2 * sp->y + (double)m->b3 * sp->z + m->b4);
            p[2] += w * ((double)m->c1 * sp->x + (double)m->c2 * sp->y + (double)m->c3 * sp->z + m->c4);
            if (sn) {
                n[0] += w * ((double)m->a1 * sn->x + (double)m->a2 * sn->y + (double)m->a3 * sn->z);
                n[1] += w * ((double)m->b1 * sn->x + (double)m->b2 * sn->y + (double)m->b3 * sn->z);
                n[2] += w * ((double)m->c1 * sn->x + (double)m->c2 * sn->y + (double)m->c3 * sn->z);
            }
        }
        if (!(wsum > 0))
            wsum = 1;
        for (int k = 0; k < 3; k++)
            pos[v * 4 + k] = (float)(p[k] / wsum);
        pos[v * 4 + 3] = 0.0f;
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++)
            nrm[v * 4 + k] = len > 0 && isfinite(len) ? (float)(n[k] / len) : 0.0f;
        nrm[v * 4 + 3] = 0.0f;
    }
    free(bm);
}

/* ---- runtime skinning (HZ_MOTION_SKIN) ---- */

/* Index of node n's joint, created on first use: its world transform sampled at skin_rate over the animation
 * (one key when nothing on its path moves). Joints are shared by every mesh skinned to them. */
static hz_status_t joint_of(ctx_t *c, const struct aiNode *n, uint32_t *out)
{
    const void *const *src = c->s->joint_src.data;
    for (size_t i = 0; i < c->s->joint_src.len; i++)
        if (src[i] == (const void *)n) {
            *out = (uint32_t)i;
            return HZ_OK;
        }
    hz_hzb_joint_t *j = hz_bake_vec_push(&c->s->joints, 1);
    *(const void **)hz_bake_vec_push(&c->s->joint_src, 1) = n;
    hz_bake_set_name(j->name, n->mName.data);
    j->key_first = (uint32_t)c->s->rkeys.len;
    double dur_s = c->anim ? c->anim->mDuration / c->tps : 0.0;
    uint32_t frames = 1;
    if (c->anim && path_animated(c, n)) {
        double f = ceil(dur_s * c->sc->skin_rate - 1e-6);
        frames = f < 1 ? 1 : f > 1000000 ? 1000000 : (uint32_t)f;
    }
    float prev_q[4] = { 0, 0, 0, 1 }, prev_time = -INFINITY;
    double worst = 0;
    for (uint32_t f = 0; f <= frames; f++) {
        /* Frames at skin_rate, then the animation's end (a loop lands there exactly). */
        double t_s = f < frames ? (double)f / c->sc->skin_rate : dur_s;
        float time = (float)t_s;
        if (!(time > prev_time + 1e-6f) || (frames == 1 && f == 1))
            continue;
        struct aiMatrix4x4 g;
        global_at(c, n, t_s * c->tps, &g);
        if (push_matrix_key(c, &g, time, prev_q, &worst))
            return hz_bake_err(c->err, HZ_E_RANGE, "%s: joint '%s': its transform at %g s is degenerate", c->s->model,
                               n->mName.data, t_s);
        prev_time = time;
    }
    j = HZ_BAKE_AT(c->s->joints, hz_hzb_joint_t, c->s->joints.len - 1);
    j->key_count = (uint32_t)c->s->rkeys.len - j->key_first;
    if (worst > 1e-3)
        hz_bake_warn("%s: joint '%s': its animated transform has shear the joint keys cannot hold (error %.2g)",
                     c->s->model, n->mName.data, worst);
    *out = (uint32_t)(c->s->joints.len - 1);
    return HZ_OK;
}

static int cmp_influence(const void *a, const void *b)
{
    float x = ((const influence_t *)a)->weight, y = ((const influence_t *)b)->weight;
    return x > y ? -1 : x < y;
}

/* Binds (one per bone, plus the mesh's own node for vertices without weights) and per-vertex weights: the 4
 * largest influences, quantised to unorm16 summing to exactly 65535. */
static hz_status_t runtime_skin(ctx_t *c, const struct aiNode *node, const struct aiMesh *mesh,
                                const struct aiNode **bones, const uint32_t *inf_first, influence_t *inf,
                                hz_bake_object_t *o, uint32_t first)
{
    unsigned nv = mesh->mNumVertices, nb = mesh->mNumBones;
    int need_self = 0;
    for (unsigned v = 0; v < nv; v++) {
        double sum = 0;
        for (uint32_t k = inf_first[v]; k < inf_first[v + 1]; k++)
            sum += inf[k].weight;
        need_self |= !(sum > 0);
    }
    if (nb + (unsigned)need_self > 65536u)
        return hz_bake_err(c->err, HZ_E_UNSUPPORTED, "%s: mesh '%s' has %u bones, runtime skinning takes 65536",
                           c->s->model, mesh->mName.data, nb);
    hz_bake_phase("skinning mesh '%s' at run time (%u vertices, %u bones)", mesh->mName.data, nv, nb);
    o->o.motion = HZ_MOTION_SKIN;
    o->o.key_first = (uint32_t)c->s->binds.len;
    o->o.key_count = nb + (unsigned)need_self;
    for (unsigned b = 0; b <= nb; b++) {
        if (b == nb && !need_self)
            break;
        uint32_t joint = 0;
        hz_status_t st = joint_of(c, b < nb ? bones[b] : node, &joint);
        if (st)
            return st;
        hz_hzb_skin_bind_t *e = hz_bake_vec_push(&c->s->binds, 1);
        e->joint = joint;
        if (b == nb) { /* identity: the vertex follows its node */
            e->inv_bind[0] = e->inv_bind[4] = e->inv_bind[8] = 1.0f;
            continue;
        }
        const struct aiMatrix4x4 *m = &mesh->mBones[b]->mOffsetMatrix;
        const float rows[3][4] = { { m->a1, m->a2, m->a3, m->a4 }, { m->b1, m->b2, m->b3, m->b4 },
                                   { m->c1, m->c2, m->c3, m->c4 } };
        for (int col = 0; col < 4; col++)
            for (int r = 0; r < 3; r++) {
                e->inv_bind[col * 3 + r] = rows[r][col];
                if (!isfinite(rows[r][col]))
                    return hz_bake_err(c->err, HZ_E_RANGE, "%s: mesh '%s': bone '%s' has a non-finite offset matrix",
                                       c->s->model, mesh->mName.data, mesh->mBones[b]->mName.data);
            }
    }
    if (c->s->weights.len < (size_t)first + nv)
        hz_bake_vec_push(&c->s->weights, (size_t)first + nv - c->s->weights.len);
    uint32_t dropped = 0;
    for (unsigned v = 0; v < nv; v++) {
        hz_hzb_skin_weight_t *w = HZ_BAKE_AT(c->s->weights, hz_hzb_skin_weight_t, (size_t)first + v);
        uint32_t k0 = inf_first[v], count = inf_first[v + 1] - k0;
        qsort(inf + k0, count, sizeof *inf, cmp_influence);
        while (count > 0 && !(inf[k0 + count - 1].weight > 0))
            count--; /* zero weights (glTF pads JOINTS_0/WEIGHTS_0 with them) are no influence */
        if (count > 4)
            dropped++, count = 4;
        double sum = 0;
        for (uint32_t k = 0; k < count; k++)
            sum += inf[k0 + k].weight;
        memset(w, 0, sizeof *w);
        if (!(sum > 0)) {
            w->bind[0] = (uint16_t)nb, w->weight[0] = 65535;
            continue;
        }
        uint32_t total = 0;
        for (uint32_t k = 0; k < count; k++) {
            w->bind[k] = (uint16_t)inf[k0 + k].bone;
            w->weight[k] = (uint16_t)floor(inf[k0 + k].weight / sum * 65535.0 + 0.5);
            total += w->weight[k];
        }
        /* Rounding leaves the sum within +-2 of 65535: the largest weight takes the difference. */
        w->weight[0] = (uint16_t)((int32_t)w->weight[0] + 65535 - (int32_t)total);
    }
    if (dropped)
        hz_bake_warn("%s: mesh '%s': %u vertices have more than 4 bone weights; the 4 largest are kept",
                     c->s->model, mesh->mName.data, dropped);
    return HZ_OK;
}

static hz_status_t skinned_mesh(ctx_t *c, const struct aiNode *node, const struct aiMesh *mesh, hz_bake_object_t **po,
                                uint32_t first, int animated)
{
    unsigned nv = mesh->mNumVertices;
    const struct aiNode **bones = hz_bake_xcalloc(mesh->mNumBones, sizeof *bones);
    uint32_t *inf_first = hz_bake_xcalloc((size_t)nv + 1, sizeof(uint32_t));
    size_t total = 0;
    for (unsigned b = 0; b < mesh->mNumBones; b++) {
        const struct aiBone *bone = mesh->mBones[b];
        bones[b] = find_node(c->ai->mRootNode, bone->mName.data);
        if (!bones[b]) {
            free(bones);
            free(inf_first);
            return hz_bake_err(c->err, HZ_E_FORMAT, "%s: mesh '%s': bone '%s' has no node", c->s->model,
                               mesh->mName.data, bone->mName.data);
        }
        for (unsigned w = 0; w < bone->mNumWeights; w++) {
            if (bone->mWeights[w].mVertexId >= nv) {
                free(bones);
                free(inf_first);
                return hz_bake_err(c->err, HZ_E_FORMAT, "%s: mesh '%s': bone '%s' weights vertex %u of %u", c->s->model,
                                   mesh->mName.data, bone->mName.data, bone->mWeights[w].mVertexId, nv);
            }
            inf_first[bone->mWeights[w].mVertexId + 1]++;
            total++;
        }
    }
    for (unsigned v = 0; v < nv; v++)
        inf_first[v + 1] += inf_first[v];
    influence_t *inf = hz_bake_xcalloc(total ? total : 1, sizeof *inf);
    uint32_t *fill = hz_bake_xcalloc(nv, sizeof(uint32_t));
    for (unsigned b = 0; b < mesh->mNumBones; b++)
        for (unsigned w = 0; w < mesh->mBones[b]->mNumWeights; w++) {
            const struct aiVertexWeight *vw = &mesh->mBones[b]->mWeights[w];
            influence_t *e = &inf[inf_first[vw->mVertexId] + fill[vw->mVertexId]++];
            e->bone = b;
            e->weight = isfinite(vw->mWeight) && vw->mWeight > 0 ? vw->mWeight : 0.0f;
        }
    free(fill);

    if (animated && c->sc->skinning == HZ_BAKE_SKINNING_RUNTIME) {
        hz_status_t rst = runtime_skin(c, node, mesh, bones, inf_first, inf, *po, first);
        free(inf);
        free(inf_first);
        free(bones);
        return rst;
    }
    double dur_s = c->anim ? c->anim->mDuration / c->tps : 0.0;
    uint32_t frames = 1;
    if (animated) {
        double f = ceil(dur_s * c->sc->skin_rate - 1e-6);
        frames = f < 1 ? 1 : f > 100000 ? 100000 : (uint32_t)f;
    }
    float *pos = hz_bake_xmalloc((size_t)nv * 16), *nrm = hz_bake_xmalloc((size_t)nv * 16);
    hz_status_t st = HZ_OK;
    hz_bake_phase("baking skinning of mesh '%s' (%u vertices, %u bones, %u frames)", mesh->mName.data, nv,
                  mesh->mNumBones, frames);
    for (uint32_t f = 0; f < frames && st == HZ_OK; f++) {
        double ticks = (double)f / c->sc->skin_rate * c->tps;
        skin_pose(c, node, mesh, bones, inf_first, inf, ticks, pos, nrm);
        for (size_t i = 0; i < (size_t)nv * 4; i++)
            if (!isfinite(pos[i]) || !isfinite(nrm[i])) {
                st = hz_bake_err(c->err, HZ_E_RANGE, "%s: mesh '%s': skinning gives a non-finite vertex at frame %u",
                                 c->s->model, mesh->mName.data, f);
                break;
            }
        if (f == 0) {
            memcpy(HZ_BAKE_AT(c->s->pos, float, (size_t)first * 4), pos, (size_t)nv * 16);
            memcpy(HZ_BAKE_AT(c->s->nrm, float, (size_t)first * 4), nrm, (size_t)nv * 16);
        }
        if (animated) {
            memcpy(hz_bake_vec_push(&c->s->vkeys, nv), pos, (size_t)nv * 16);
            memcpy(hz_bake_vec_push(&c->s->vkey_nrm, nv), nrm, (size_t)nv * 16);
        }
    }
    if (animated && st == HZ_OK) {
        hz_bake_object_t *o = *po;
        o->o.motion = HZ_MOTION_VERTEX;
        o->o.key_first = (uint32_t)(c->s->vkeys.len - (size_t)frames * nv);
        o->o.key_count = frames;
        o->o.key_rate = c->sc->skin_rate;
        if (c->s->vkeys.len > UINT32_MAX)
            st = hz_bake_err(c->err, HZ_E_OVERFLOW, "%s: more than 2^32 vertex keys", c->s->model);
    }
    free(pos);
    free(nrm);
    free(inf);
    free(inf_first);
    free(bones);
    return st;
}

static hz_status_t mesh_instance(ctx_t *c, const struct aiNode *node, unsigned mesh_index)
{
    const struct aiMesh *mesh = c->ai->mMeshes[mesh_index];
    unsigned tris = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; f++)
        tris += mesh->mFaces[f].mNumIndices == 3;
    c->skipped_faces += mesh->mNumFaces - tris;
    if (tris == 0)
        return HZ_OK;
    if (mesh->mMaterialIndex >= c->s->mats.len)
        return hz_bake_err(c->err, HZ_E_FORMAT, "%s: mesh '%s' names material %u of %zu", c->s->model, mesh->mName.data,
                           mesh->mMaterialIndex, c->s->mats.len);
    const char *name = node->mName.length ? node->mName.data : mesh->mName.length ? mesh->mName.data : "object";
    int skinned = mesh->mNumBones > 0;
    int bones_animated = 0;
    for (unsigned b = 0; skinned && b < mesh->mNumBones; b++) {
        const struct aiNode *bn = find_node(c->ai->mRootNode, mesh->mBones[b]->mName.data);
        bones_animated |= bn && path_animated(c, bn);
    }
    int rigid = !skinned && path_animated(c, node);

    hz_bake_object_begin(c->s, name, mesh->mName.data);
    uint32_t nv = mesh->mNumVertices;
    uint32_t first = hz_bake_add_vertices(c->s, nv);
    struct aiMatrix4x4 g;
    struct aiMatrix3x3 nm;
    global_static(node, &g);
    normal_matrix(&g, &nm);
    int flip = !rigid && !skinned && det3(&g) < 0;
    for (uint32_t v = 0; v < nv; v++) {
        float *p = HZ_BAKE_AT(c->s->pos, float, (size_t)(first + v) * 4);
        float *n = HZ_BAKE_AT(c->s->nrm, float, (size_t)(first + v) * 4);
        struct aiVector3D q = mesh->mVertices[v];
        if (!isfinite(q.x) || !isfinite(q.y) || !isfinite(q.z)) { /* named as the model gives it, before transforms */
            char xyz[3][24];
            return hz_bake_err(c->err, HZ_E_RANGE, "%s: mesh '%s': vertex %u has a non-finite position in the model (%s %s %s)",
                               c->s->model, mesh->mName.data, v, hz_bake_num(xyz[0], 24, q.x),
                               hz_bake_num(xyz[1], 24, q.y), hz_bake_num(xyz[2], 24, q.z));
        }
        struct aiVector3D qn = { 0, 0, 0 };
        if (mesh->mNormals)
            qn = mesh->mNormals[v];
        if (!rigid && !skinned) {
            aiTransformVecByMatrix4(&q, &g);
            aiTransformVecByMatrix3(&qn, &nm);
        }
        p[0] = q.x, p[1] = q.y, p[2] = q.z;
        n[0] = qn.x, n[1] = qn.y, n[2] = qn.z;
        if (mesh->mTextureCoords[0]) {
            float *uv = HZ_BAKE_AT(c->s->uv, float, (size_t)(first + v) * 2);
            uv[0] = mesh->mTextureCoords[0][v].x;
            uv[1] = 1.0f - mesh->mTextureCoords[0][v].y; /* assimp's v points up; .hzb's down */
        }
    }
    if (mesh->mTextureCoords[0])
        c->s->any_uv = 1;
    for (unsigned f = 0; f < mesh->mNumFaces; f++) {
        const struct aiFace *face = &mesh->mFaces[f];
        if (face->mNumIndices != 3)
            continue;
        for (int k = 0; k < 3; k++)
            if (face->mIndices[k] >= nv)
                return hz_bake_err(c->err, HZ_E_FORMAT, "%s: mesh '%s': face %u uses vertex %u of %u", c->s->model,
                                   mesh->mName.data, f, face->mIndices[k], nv);
        uint32_t a = first + face->mIndices[0], b = first + face->mIndices[1], d = first + face->mIndices[2];
        if (flip)
            hz_bake_add_triangle(c->s, a, d, b, mesh->mMaterialIndex);
        else
            hz_bake_add_triangle(c->s, a, b, d, mesh->mMaterialIndex);
    }
    hz_bake_object_t *o = HZ_BAKE_AT(c->s->objs, hz_bake_object_t, c->s->objs.len - 1);
    hz_status_t st = HZ_OK;
    if (skinned) {
        st = skinned_mesh(c, node, mesh, &o, first, bones_animated);
        if (st)
            return st;
    }
    st = hz_bake_object_end(c->s, mesh->mNormals != NULL, !skinned, c->err);
    if (st)
        return st;
    o = HZ_BAKE_AT(c->s->objs, hz_bake_object_t, c->s->objs.len - 1);
    if (rigid)
        st = rigid_keys(c, node, o);
    return st;
}

static hz_status_t walk(ctx_t *c, const struct aiNode *node, unsigned depth)
{
    if (depth > 1000)
        return hz_bake_err(c->err, HZ_E_FORMAT, "%s: node hierarchy deeper than 1000", c->s->model);
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        if (node->mMeshes[i] >= c->ai->mNumMeshes)
            return hz_bake_err(c->err, HZ_E_FORMAT, "%s: node '%s' names mesh %u of %u", c->s->model, node->mName.data,
                               node->mMeshes[i], c->ai->mNumMeshes);
        hz_status_t st = mesh_instance(c, node, node->mMeshes[i]);
        if (st)
            return st;
    }
    for (unsigned i = 0; i < node->mNumChildren; i++) {
        hz_status_t st = walk(c, node->mChildren[i], depth + 1);
        if (st)
            return st;
    }
    return HZ_OK;
}

/* ---- the files assimp opens: never the output, and the ones that are missing named ---- */

typedef struct io_ctx {
    const char *model;
    char fallback[512]; /* OBJ: assimp tries MODEL.mtl when the named library is missing: not the model's word */
    char missing[4][512]; /* files the model names that could not be opened (a .mtl, a .bin) */
    int n_missing, more_missing;
} io_ctx_t;

static size_t io_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)(void *)f->UserData);
}

static size_t io_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0; /* the import reads only */
}

static size_t io_tell(struct aiFile *f)
{
    long at = ftell((FILE *)(void *)f->UserData);
    return at < 0 ? 0 : (size_t)at;
}

static size_t io_size(struct aiFile *f)
{
    FILE *fp = (FILE *)(void *)f->UserData;
    long at = ftell(fp), end = -1;
    if (at >= 0 && fseek(fp, 0, SEEK_END) == 0) {
        end = ftell(fp);
        fseek(fp, at, SEEK_SET);
    }
    return end < 0 ? 0 : (size_t)end;
}

static enum aiReturn io_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    return fseek((FILE *)(void *)f->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void io_flush(struct aiFile *f)
{
    (void)f;
}

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode)
{
    io_ctx_t *c = (io_ctx_t *)(void *)io->UserData;
    if (!hz_bake_input_ok(path))
        return NULL; /* the output: the bake fails after the import (hz_bake_input_clash) */
    FILE *fp = fopen(path, mode);
    if (!fp) {
        while (path[0] == '.' && path[1] == '/')
            path += 2; /* assimp asks for "./x.mtl" after "x.mtl" */
        int seen = !strcmp(path, c->model) || (c->n_missing && !strcmp(path, c->fallback));
        for (int i = 0; i < c->n_missing && !seen; i++)
            seen = !strcmp(c->missing[i], path);
        if (!seen && c->n_missing < 4)
            hz_bake_strcpy(c->missing[c->n_missing++], sizeof c->missing[0], path);
        else if (!seen)
            c->more_missing++;
        return NULL;
    }
    struct aiFile *f = hz_bake_xcalloc(1, sizeof *f);
    f->ReadProc = io_read;
    f->WriteProc = io_write;
    f->TellProc = io_tell;
    f->FileSizeProc = io_size;
    f->SeekProc = io_seek;
    f->FlushProc = io_flush;
    f->UserData = (aiUserData)(void *)fp;
    return f;
}

static void io_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (f) {
        fclose((FILE *)(void *)f->UserData);
        free(f);
    }
}

/* "'a.mtl'" or "'a.mtl', 'b.mtl' and 2 more" */
static void missing_list(const io_ctx_t *c, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < c->n_missing && n < cap; i++)
        n += (size_t)snprintf(buf + n, cap - n, "%s'%s'", i ? ", " : "", c->missing[i]);
    if (c->more_missing && n < cap)
        snprintf(buf + n, cap - n, " and %d more", c->more_missing);
}

static void count_uses(ctx_t *c, const struct aiNode *node, unsigned depth)
{
    if (depth > 1000)
        return;
    for (unsigned i = 0; i < node->mNumMeshes; i++)
        if (node->mMeshes[i] < c->ai->mNumMeshes)
            c->mesh_uses[node->mMeshes[i]]++;
    for (unsigned i = 0; i < node->mNumChildren; i++)
        count_uses(c, node->mChildren[i], depth + 1);
}

/* assimp 5.2's PLY reader loops forever on a header that ends without an end_header line (a cut file) or holds a
 * control byte before it (a damaged one), so the header is checked here first: "ply", then text lines (tabs,
 * and any byte from 0x20 up: comments may be UTF-8) up to end_header, within its first HEADER_MAX bytes. */
#define PLY_HEADER_MAX (1u << 20)

static hz_status_t check_ply_header(const char *path, const uint8_t *d, size_t n, hz_error_t *err)
{
    size_t lim = n < PLY_HEADER_MAX ? n : PLY_HEADER_MAX, at = 0, line = 1;
    if (n < 3 || (d[0] | 0x20) != 'p' || (d[1] | 0x20) != 'l' || (d[2] | 0x20) != 'y')
        return hz_bake_err(err, HZ_E_FORMAT, "%s: not a PLY file (it does not start with 'ply')", path);
    while (at < lim) {
        size_t e = at;
        while (e < lim && d[e] != '\n')
            e++;
        size_t len = e - at;
        while (len && (d[at + len - 1] == '\r' || d[at + len - 1] == ' ' || d[at + len - 1] == '\t'))
            len--;
        for (size_t i = at; i < at + len; i++)
            if (d[i] < 0x20 && d[i] != '\t')
                return hz_bake_err(err, HZ_E_FORMAT,
                                   "%s: line %zu of the PLY header holds the control byte 0x%02x (a damaged file?)",
                                   path, line, d[i]);
        if (len == 10 && !memcmp(d + at, "end_header", 10))
            return HZ_OK;
        at = e + 1;
        line++;
    }
    return hz_bake_err(err, HZ_E_FORMAT, "%s: the PLY header has no end_header line%s (a cut or damaged file?)", path,
                       n > PLY_HEADER_MAX ? " in its first MiB" : "");
}

/* The first PLY_HEADER_MAX bytes of a file, for check_ply_header. */
static hz_status_t check_ply_file(const char *path, hz_error_t *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return hz_bake_err(err, HZ_E_IO, "%s: cannot open: %s", path, strerror(errno));
    uint8_t *head = hz_bake_xmalloc(PLY_HEADER_MAX + 1);
    size_t n = fread(head, 1, PLY_HEADER_MAX + 1, f);
    int failed = ferror(f);
    fclose(f);
    hz_status_t st = failed ? hz_bake_err(err, HZ_E_IO, "%s: read failed", path) : check_ply_header(path, head, n, err);
    free(head);
    return st;
}

hz_status_t hz_bake_import_assimp(hz_bake_scene_t *s, const char *path, const hz_bake_sidecar_t *sc, hz_error_t *err)
{
    ctx_t c;
    memset(&c, 0, sizeof c);
    c.s = s;
    c.sc = sc;
    c.err = err;
    int gz = hz_bake_ends_with(path, ".gz");
    if (hz_bake_ends_with(path, ".obj"))
        c.fmt = FMT_OBJ;
    else if (hz_bake_ends_with(path, ".ply") || hz_bake_ends_with(path, ".ply.gz"))
        c.fmt = FMT_PLY;
    else if (hz_bake_ends_with(path, ".gltf") || hz_bake_ends_with(path, ".glb"))
        c.fmt = FMT_GLTF;
    else
        return hz_bake_err(err, HZ_E_UNSUPPORTED, "%s: unsupported model format", path);
    hz_bake_dirname(path, c.dir, sizeof c.dir);

    unsigned flags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
    /* PLY meshes share their vertices, and assimp 5.2's smooth normals are wrong on shared vertices: each vertex
     * gets the normal of the last face that names it (within the crease angle of itself), an arbitrary
     * neighbour, so a scan's sliver triangles give vertex normals up to 180 degrees off the surface (the dragon at
     * res2: 669 vertices more than 60 degrees off the area-weighted mean of their faces) and dark single pixels
     * where they tilt away from a light. Their normals come from the baker's own area-weighted mean instead
     * (scene.c, as for missing normals); a scan is one smooth surface, so no crease angle is lost. */
    if (sc->normals != HZ_BAKE_NORMALS_NONE && c.fmt != FMT_PLY)
        flags |= aiProcess_GenSmoothNormals;
    struct aiPropertyStore *props = aiCreatePropertyStore();
    aiSetImportPropertyFloat(props, AI_CONFIG_PP_GSN_MAX_SMOOTHING_ANGLE, sc->smooth_angle_deg);
    double t0 = hz_bake_now();
    hz_bake_progress("importing %s", path);
    hz_bake_phase("importing (assimp)");
    const struct aiScene *ai;
    io_ctx_t ioc;
    memset(&ioc, 0, sizeof ioc);
    ioc.model = path;
    if (c.fmt == FMT_OBJ) {
        hz_bake_strcpy(ioc.fallback, sizeof ioc.fallback - 4, path);
        char *dot = strrchr(ioc.fallback, '.');
        if (dot)
            strcpy(dot, ".mtl");
    }
    struct aiFileIO io = { io_open, io_close, (aiUserData)(void *)&ioc };
    if (gz) {
        uint8_t *data;
        size_t size;
        hz_status_t st = hz_bake_read_gzip(path, &data, &size, err);
        if (st) {
            aiReleasePropertyStore(props);
            return st;
        }
        if (size > UINT32_MAX || (st = check_ply_header(path, data, size, err)) != HZ_OK) {
            free(data);
            aiReleasePropertyStore(props);
            return st ? st : hz_bake_err(err, HZ_E_UNSUPPORTED, "%s: more than 4 GiB uncompressed", path);
        }
        ai = aiImportFileFromMemoryWithProperties((const char *)data, (unsigned)size, flags, "ply", props);
        free(data);
    } else {
        if (!hz_bake_file_exists(path)) {
            aiReleasePropertyStore(props);
            return hz_bake_err(err, HZ_E_IO, "%s: no such file", path);
        }
        hz_status_t st = c.fmt == FMT_PLY ? check_ply_file(path, err) : HZ_OK;
        if (st) {
            aiReleasePropertyStore(props);
            return st;
        }
        ai = aiImportFileExWithProperties(path, flags, &io, props);
    }
    aiReleasePropertyStore(props);
    char missing[1200] = "";
    missing_list(&ioc, missing, sizeof missing);
    if (!ai) {
        const char *why = aiGetErrorString();
        if (!why || !*why)
            why = "unknown error";
        if (hz_bake_input_clash()[0])
            return hz_bake_err(err, HZ_E_INVALID_ARG, "%s: %s, a file the model reads, is the output too: baking "
                               "would replace it; choose another output path", path, hz_bake_input_clash());
        /* The extension is one assimp reads: "no suitable reader" means the file is not what it says (a glTF or
         * glb cut short fails the reader's own header test). */
        if (strstr(why, "No suitable reader"))
            return hz_bake_err(err, HZ_E_FORMAT, "%s: not a readable %s file (truncated or corrupt: no importer "
                               "recognises its content)", path, c.fmt == FMT_OBJ ? "OBJ" : c.fmt == FMT_PLY ? "PLY" : "glTF");
        return hz_bake_err(err, HZ_E_FORMAT, "%s: assimp cannot import it: %s%s%s", path, why,
                           missing[0] ? "; it names files that cannot be opened: " : "", missing);
    }
    if (missing[0] && !hz_bake_input_clash()[0])
        hz_bake_warn("%s: names %s, which cannot be opened (missing?): what %s define%s is left out (an OBJ's "
                     "materials get the default grey)", path, missing, ioc.n_missing + ioc.more_missing == 1 ? "it" : "they",
                     ioc.n_missing + ioc.more_missing == 1 ? "s" : "");
    hz_bake_progress("imported in %.2f s: %u meshes, %u materials, %u animations", hz_bake_now() - t0, ai->mNumMeshes,
                     ai->mNumMaterials, ai->mNumAnimations);
    hz_bake_phase("converting %u meshes and %u materials", ai->mNumMeshes, ai->mNumMaterials);
    c.ai = ai;
    hz_status_t st = HZ_OK;
    if ((ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !ai->mRootNode)
        st = hz_bake_err(err, HZ_E_FORMAT, "%s: assimp returned an incomplete scene", path);
    if (!st && ai->mNumAnimations) {
        if (sc->animation >= ai->mNumAnimations)
            st = hz_bake_err(err, HZ_E_RANGE, "%s: animation %u requested (sidecar), the model has %u", path,
                             sc->animation, ai->mNumAnimations);
        else {
            c.anim = ai->mAnimations[sc->animation];
            c.tps = c.anim->mTicksPerSecond > 0 ? c.anim->mTicksPerSecond : 25.0;
            if (!(c.anim->mDuration >= 0) || !isfinite(c.anim->mDuration))
                st = hz_bake_err(err, HZ_E_RANGE, "%s: animation duration is not a finite positive number", path);
            else
                s->anim_duration = (float)(c.anim->mDuration / c.tps);
        }
    } else if (!st && (sc->set & HZ_BAKE_SC_ANIMATION) && sc->animation > 0) {
        st = hz_bake_err(err, HZ_E_RANGE, "%s: animation %u requested (sidecar), the model has none", path,
                         sc->animation);
    }
    for (unsigned i = 0; !st && i < ai->mNumMaterials; i++)
        add_material(&c, ai->mMaterials[i], i);
    if (!st) {
        c.mesh_uses = hz_bake_xcalloc(ai->mNumMeshes ? ai->mNumMeshes : 1, sizeof(uint32_t));
        count_uses(&c, ai->mRootNode, 0);
        for (unsigned i = 0; i < ai->mNumMeshes; i++)
            if (c.mesh_uses[i] > 1)
                s->extra_features |= HZ_FEAT_INSTANCING; /* expanded: every use is its own object */
        st = walk(&c, ai->mRootNode, 0);
        free(c.mesh_uses);
    }
    if (!st && c.skipped_faces)
        hz_bake_warn("%s: %llu point/line primitives skipped (only triangles are baked)", path,
                     (unsigned long long)c.skipped_faces);
    aiReleaseImport(ai);
    return st;
}
