/* .hzb validation and loading (see hz/scene.h for the contract, hz/hzb.h for the format). Every check runs
 * before the data it guards is used; every size computation is done in 64 bits with explicit overflow checks.
 * Nothing here depends on the data being trustworthy. */
#include "hz/accel.h" /* HZ_ACCEL_MAX_COORD: positions the accel can trace */
#include "hz/crc32.h"
#include "hz/skin.h"
#include "scene_internal.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the .hzb loader uses the little-endian file in place: big-endian targets need a byte-swapping loader"
#endif

typedef struct view {
    const uint8_t *base;
    size_t size;
    hz_hzb_header_t h;
    const hz_hzb_section_t *sec[HZ_SEC_ID_MAX + 1]; /* by id; NULL when absent */
    uint64_t count[HZ_SEC_ID_MAX + 1];              /* elements per section */
    hz_error_t *err;
} view_t;

static hz_status_t fail(view_t *v, hz_status_t code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    hz_error_vset(v->err, code, fmt, ap);
    va_end(ap);
    return code;
}

static const void *sec_data(const view_t *v, uint32_t id)
{
    return v->sec[id] ? v->base + v->sec[id]->offset : NULL;
}

static int finite3(const float *f)
{
    return hz_isfinitef(f[0]) && hz_isfinitef(f[1]) && hz_isfinitef(f[2]);
}

static int name_ok(const uint8_t *name)
{
    for (uint32_t i = 0; i < HZ_HZB_NAME_BYTES; i++)
        if (name[i] == 0)
            return 1;
    return 0;
}

static int all_zero(const void *p, size_t n)
{
    const uint8_t *b = (const uint8_t *)p;
    for (size_t i = 0; i < n; i++)
        if (b[i])
            return 0;
    return 1;
}

static int in_unit(float x)
{
    return x >= 0.0f && x <= 1.0f; /* false for NaN */
}

/* ---- header and section table ---- */

static hz_status_t check_header(view_t *v)
{
    if (v->size < sizeof(hz_hzb_header_t))
        return fail(v, HZ_E_FORMAT, "truncated: %zu bytes, a .hzb header alone has %zu", v->size,
                    sizeof(hz_hzb_header_t));
    hz_memcpy(&v->h, v->base, sizeof v->h);
    const hz_hzb_header_t *h = &v->h;
    if (!(h->magic[0] == 'H' && h->magic[1] == 'Z' && h->magic[2] == 'B' && h->magic[3] == 0 &&
          h->magic[4] == '\r' && h->magic[5] == '\n' && h->magic[6] == 0x1a && h->magic[7] == '\n'))
        return fail(v, HZ_E_FORMAT, "not a .hzb file (bad magic)");
    if (h->version < HZ_HZB_VERSION_MIN || h->version > HZ_HZB_VERSION)
        return fail(v, HZ_E_VERSION, "format version %u, this build reads versions %u to %u", h->version,
                    HZ_HZB_VERSION_MIN, HZ_HZB_VERSION);
    if (h->header_bytes != sizeof(hz_hzb_header_t))
        return fail(v, HZ_E_FORMAT, "header size %u, expected %zu", h->header_bytes, sizeof(hz_hzb_header_t));
    uint32_t crc = hz_crc32(0, v->base, offsetof(hz_hzb_header_t, header_crc));
    if (crc != h->header_crc)
        return fail(v, HZ_E_CORRUPT, "header CRC mismatch (stored %08x, computed %08x)", h->header_crc, crc);
    if (h->file_bytes != (uint64_t)v->size)
        return fail(v, HZ_E_FORMAT, "%s: the header says %llu bytes, the buffer has %zu",
                    h->file_bytes > (uint64_t)v->size ? "truncated" : "trailing bytes",
                    (unsigned long long)h->file_bytes, v->size);
    if (h->section_count > HZ_SEC_ID_MAX)
        return fail(v, HZ_E_FORMAT, "%u sections, at most %u exist", h->section_count, HZ_SEC_ID_MAX);
    if (h->features & ~HZ_FEAT_ALL)
        return fail(v, HZ_E_FORMAT, "unknown feature bits %08x", h->features & ~HZ_FEAT_ALL);
    if (h->triangle_count == 0 || h->vertex_count < 3)
        return fail(v, HZ_E_FORMAT, "no geometry (%u vertices, %u triangles)", h->vertex_count, h->triangle_count);
    if (h->material_count == 0 || h->material_count > 65536)
        return fail(v, HZ_E_RANGE, "material count %u outside [1, 65536]", h->material_count);
    if (h->object_count == 0 || h->object_count > 65536)
        return fail(v, HZ_E_RANGE, "object count %u outside [1, 65536]", h->object_count);
    if (!finite3(h->bounds_min) || !finite3(h->bounds_max) || h->bounds_min[0] > h->bounds_max[0] ||
        h->bounds_min[1] > h->bounds_max[1] || h->bounds_min[2] > h->bounds_max[2])
        return fail(v, HZ_E_FORMAT, "header bounds are not finite or inverted");
    if (!(h->duration >= 0.0f) || !hz_isfinitef(h->duration))
        return fail(v, HZ_E_RANGE, "duration is negative or not finite");
    if (!finite3(h->background) || !finite3(h->ambient) || h->background[0] < 0 || h->background[1] < 0 ||
        h->background[2] < 0 || h->ambient[0] < 0 || h->ambient[1] < 0 || h->ambient[2] < 0)
        return fail(v, HZ_E_RANGE, "background or ambient colour is negative or not finite");
    if (!(h->camera_fov_y >= 0.0f && h->camera_fov_y < HZ_PI))
        return fail(v, HZ_E_RANGE, "default field of view outside [0, pi)");
    if (h->camera_flags & ~1u)
        return fail(v, HZ_E_FORMAT, "unknown camera flags %08x", h->camera_flags);
    if (!name_ok(h->name) || !all_zero(h->reserved, sizeof h->reserved))
        return fail(v, HZ_E_FORMAT, "header name not terminated or reserved fields not zero");
    if (h->version < 2 && (h->joint_count || h->skin_bind_count))
        return fail(v, HZ_E_FORMAT, "a version %u header with skinning counts (words 164..171 are reserved there)",
                    h->version);
    return HZ_OK;
}

static hz_status_t check_table(view_t *v)
{
    uint64_t table_end = sizeof(hz_hzb_header_t) + (uint64_t)v->h.section_count * sizeof(hz_hzb_section_t);
    if (table_end > v->size)
        return fail(v, HZ_E_FORMAT, "truncated section table (%u entries)", v->h.section_count);
    const hz_hzb_section_t *t = (const hz_hzb_section_t *)(v->base + sizeof(hz_hzb_header_t));
    for (uint32_t i = 0; i < v->h.section_count; i++) {
        const hz_hzb_section_t *e = &t[i];
        uint32_t elem = hz_hzb_elem_bytes(e->id);
        if (elem == 0)
            return fail(v, HZ_E_FORMAT, "section table entry %u: unknown section id %u", i, e->id);
        const char *name = hz_hzb_section_name(e->id);
        if (v->h.version < 2 && e->id >= HZ_SEC_JOINTS)
            return fail(v, HZ_E_FORMAT, "section '%s' needs format version 2, the file says version %u", name,
                        v->h.version);
        if (v->sec[e->id])
            return fail(v, HZ_E_FORMAT, "section '%s' appears twice", name);
        if (e->elem_bytes != elem)
            return fail(v, HZ_E_FORMAT, "section '%s': element size %u, expected %u", name, e->elem_bytes, elem);
        if (e->reserved != 0)
            return fail(v, HZ_E_FORMAT, "section '%s': reserved field not zero", name);
        if (e->offset % HZ_HZB_ALIGN != 0 || e->offset < table_end)
            return fail(v, HZ_E_FORMAT, "section '%s': offset %llu is misaligned or inside the header", name,
                        (unsigned long long)e->offset);
        if (e->offset > v->size || e->size > v->size - e->offset)
            return fail(v, HZ_E_FORMAT, "section '%s': bytes %llu..%llu lie outside the %zu-byte file", name,
                        (unsigned long long)e->offset, (unsigned long long)e->offset + e->size, v->size);
        if (e->size == 0 || e->size % elem != 0)
            return fail(v, HZ_E_FORMAT, "section '%s': size %llu is not a positive multiple of %u", name,
                        (unsigned long long)e->size, elem);
        v->sec[e->id] = e;
        v->count[e->id] = e->size / elem;
    }
    /* No two sections share bytes. */
    for (uint32_t a = 1; a <= HZ_SEC_ID_MAX; a++)
        for (uint32_t b = a + 1; b <= HZ_SEC_ID_MAX; b++) {
            const hz_hzb_section_t *x = v->sec[a], *y = v->sec[b];
            if (x && y && x->offset < y->offset + y->size && y->offset < x->offset + x->size)
                return fail(v, HZ_E_FORMAT, "sections '%s' and '%s' overlap", hz_hzb_section_name(a),
                            hz_hzb_section_name(b));
        }
    for (uint32_t id = 1; id <= HZ_SEC_ID_MAX; id++) {
        const hz_hzb_section_t *e = v->sec[id];
        if (!e)
            continue;
        uint32_t crc = hz_crc32(0, v->base + e->offset, (size_t)e->size);
        if (crc != e->crc32)
            return fail(v, HZ_E_CORRUPT, "section '%s': CRC mismatch (stored %08x, computed %08x)",
                        hz_hzb_section_name(id), e->crc32, crc);
    }
    return HZ_OK;
}

/* A section's element count must match the header's count; absent iff the count is zero (or optional). */
static hz_status_t expect_count(view_t *v, uint32_t id, uint64_t want, int optional)
{
    const char *name = hz_hzb_section_name(id);
    if (!v->sec[id]) {
        if (want == 0 || optional)
            return HZ_OK;
        return fail(v, HZ_E_FORMAT, "section '%s' is missing (%llu elements expected)", name,
                    (unsigned long long)want);
    }
    if (v->count[id] != want)
        return fail(v, HZ_E_FORMAT, "section '%s' has %llu elements, the header says %llu", name,
                    (unsigned long long)v->count[id], (unsigned long long)want);
    return HZ_OK;
}

static hz_status_t check_counts(view_t *v)
{
    const hz_hzb_header_t *h = &v->h;
    hz_status_t s;
    if ((s = expect_count(v, HZ_SEC_POSITIONS, h->vertex_count, 0)) ||
        (s = expect_count(v, HZ_SEC_NORMALS, h->vertex_count, 1)) ||
        (s = expect_count(v, HZ_SEC_UVS, h->vertex_count, 1)) ||
        (s = expect_count(v, HZ_SEC_TRIANGLES, h->triangle_count, 0)) ||
        (s = expect_count(v, HZ_SEC_TRI_INFO, h->triangle_count, 0)) ||
        (s = expect_count(v, HZ_SEC_MATERIALS, h->material_count, 0)) ||
        (s = expect_count(v, HZ_SEC_TEXTURES, h->texture_count, 0)) ||
        (s = expect_count(v, HZ_SEC_TEXELS, h->texel_count, 0)) ||
        (s = expect_count(v, HZ_SEC_OBJECTS, h->object_count, 0)) ||
        (s = expect_count(v, HZ_SEC_RIGID_KEYS, h->rigid_key_count, 0)) ||
        (s = expect_count(v, HZ_SEC_VERTEX_KEYS, h->vertex_key_count, 0)) ||
        (s = expect_count(v, HZ_SEC_VERTEX_KEY_NORMALS, h->vertex_key_count, 1)) ||
        (s = expect_count(v, HZ_SEC_LIGHTS, h->light_count, 0)) ||
        (s = expect_count(v, HZ_SEC_CAMERA_KEYS, h->camera_key_count, 0)) ||
        (s = expect_count(v, HZ_SEC_JOINTS, h->joint_count, 0)) ||
        (s = expect_count(v, HZ_SEC_SKIN_BINDS, h->skin_bind_count, 0)) ||
        (s = expect_count(v, HZ_SEC_SKIN_WEIGHTS, h->vertex_count, 1)))
        return s;
    return HZ_OK;
}

/* ---- content ---- */

static hz_status_t check_float4s(view_t *v, uint32_t id, int unit_length)
{
    const float *f = (const float *)sec_data(v, id);
    uint64_t n = v->count[id];
    for (uint64_t i = 0; i < n; i++, f += 4) {
        if (!finite3(f) || f[3] != 0.0f)
            return fail(v, HZ_E_RANGE, "section '%s': element %llu is not finite or its w is not 0",
                        hz_hzb_section_name(id), (unsigned long long)i);
        if (!unit_length && !(hz_absf(f[0]) <= HZ_ACCEL_MAX_COORD && hz_absf(f[1]) <= HZ_ACCEL_MAX_COORD &&
                              hz_absf(f[2]) <= HZ_ACCEL_MAX_COORD))
            return fail(v, HZ_E_RANGE, "section '%s': element %llu has a coordinate beyond +-2^36 (the accel's range)",
                        hz_hzb_section_name(id), (unsigned long long)i);
        if (unit_length && f[0] * f[0] + f[1] * f[1] + f[2] * f[2] > 1.0201f)
            return fail(v, HZ_E_RANGE, "section '%s': element %llu is longer than 1", hz_hzb_section_name(id),
                        (unsigned long long)i);
    }
    return HZ_OK;
}

static hz_status_t check_materials(view_t *v)
{
    const hz_hzb_material_t *m = (const hz_hzb_material_t *)sec_data(v, HZ_SEC_MATERIALS);
    for (uint32_t i = 0; i < v->h.material_count; i++, m++) {
        if (!in_unit(m->base_color[0]) || !in_unit(m->base_color[1]) || !in_unit(m->base_color[2]) ||
            !in_unit(m->alpha) || !in_unit(m->alpha_cutoff) || !in_unit(m->mirror))
            return fail(v, HZ_E_RANGE, "material %u: colour, alpha, cutoff or mirror outside [0, 1]", i);
        if (m->alpha_mode > HZ_ALPHA_BLEND)
            return fail(v, HZ_E_RANGE, "material %u: unknown alpha mode %u", i, m->alpha_mode);
        int32_t tc = (int32_t)v->h.texture_count;
        if (m->base_texture < -1 || m->base_texture >= tc || m->alpha_texture < -1 || m->alpha_texture >= tc)
            return fail(v, HZ_E_RANGE, "material %u: texture index %d / %d outside [-1, %d)", i, m->base_texture,
                        m->alpha_texture, tc);
        if ((m->base_texture >= 0 || m->alpha_texture >= 0) && !v->sec[HZ_SEC_UVS])
            return fail(v, HZ_E_FORMAT, "material %u uses a texture but the scene has no UVs", i);
        if (m->flags || !name_ok(m->name) || !all_zero(m->reserved, sizeof m->reserved))
            return fail(v, HZ_E_FORMAT, "material %u: name not terminated or reserved fields not zero", i);
    }
    return HZ_OK;
}

static hz_status_t check_textures(view_t *v)
{
    const hz_hzb_texture_t *t = (const hz_hzb_texture_t *)sec_data(v, HZ_SEC_TEXTURES);
    for (uint32_t i = 0; i < v->h.texture_count; i++, t++) {
        if (t->width < 1 || t->width > 16384 || t->height < 1 || t->height > 16384)
            return fail(v, HZ_E_RANGE, "texture %u: size %ux%u outside [1, 16384]", i, t->width, t->height);
        uint32_t full = 1, w = t->width, h = t->height;
        while (w > 1 || h > 1) {
            w = w > 1 ? w / 2 : 1;
            h = h > 1 ? h / 2 : 1;
            full++;
        }
        if (t->levels < 1 || t->levels > full)
            return fail(v, HZ_E_RANGE, "texture %u: %u mip levels, a %ux%u image has 1..%u", i, t->levels,
                        t->width, t->height, full);
        uint64_t texels = 0;
        w = t->width, h = t->height;
        for (uint32_t l = 0; l < t->levels; l++) {
            texels += (uint64_t)w * h;
            w = w > 1 ? w / 2 : 1;
            h = h > 1 ? h / 2 : 1;
        }
        if (texels != t->texel_count)
            return fail(v, HZ_E_FORMAT, "texture %u: texel count %u, its levels need %llu", i, t->texel_count,
                        (unsigned long long)texels);
        if ((uint64_t)t->first_texel + t->texel_count > v->h.texel_count)
            return fail(v, HZ_E_RANGE, "texture %u: texels %u..%llu outside the %u in 'texels'", i,
                        t->first_texel, (unsigned long long)t->first_texel + t->texel_count, v->h.texel_count);
        if (t->flags & ~1u || !name_ok(t->name) || !all_zero(t->reserved, sizeof t->reserved))
            return fail(v, HZ_E_FORMAT, "texture %u: unknown flags, name not terminated or reserved not zero", i);
    }
    return HZ_OK;
}

/* Rigid keys key_first..+key_count of `what` (an object or a joint) `idx`. */
static hz_status_t check_key_range(view_t *v, const char *what, uint32_t idx, uint32_t key_first, uint32_t key_count)
{
    const hz_hzb_rigid_key_t *k = (const hz_hzb_rigid_key_t *)sec_data(v, HZ_SEC_RIGID_KEYS);
    if (key_count == 0 || (uint64_t)key_first + key_count > v->h.rigid_key_count)
        return fail(v, HZ_E_RANGE, "%s %u: rigid keys %u..%llu outside the %u in 'rigid_keys'", what, idx,
                    key_first, (unsigned long long)key_first + key_count, v->h.rigid_key_count);
    for (uint32_t i = 0; i < key_count; i++) {
        const hz_hzb_rigid_key_t *e = &k[key_first + i];
        float q2 = e->rotation[0] * e->rotation[0] + e->rotation[1] * e->rotation[1] +
                   e->rotation[2] * e->rotation[2] + e->rotation[3] * e->rotation[3];
        if (!hz_isfinitef(e->time) || !finite3(e->translation) || !finite3(e->scale) || !(q2 > 0.998f) ||
            !(q2 < 1.002f) || e->reserved != 0.0f)
            return fail(v, HZ_E_RANGE, "%s %u: rigid key %u is not finite or its rotation is not unit", what, idx, i);
        if (i > 0 && !(e->time > k[key_first + i - 1].time))
            return fail(v, HZ_E_RANGE, "%s %u: rigid key times do not increase at key %u", what, idx, i);
    }
    return HZ_OK;
}

static hz_status_t check_rigid_keys(view_t *v, uint32_t obj, const hz_hzb_object_t *o)
{
    return check_key_range(v, "object", obj, o->key_first, o->key_count);
}

/* ---- runtime skinning (format version 2) ---- */

static hz_status_t check_joints_binds(view_t *v)
{
    const hz_hzb_joint_t *j = (const hz_hzb_joint_t *)sec_data(v, HZ_SEC_JOINTS);
    for (uint32_t i = 0; i < v->h.joint_count; i++, j++) {
        if (!name_ok(j->name) || !all_zero(j->reserved, sizeof j->reserved))
            return fail(v, HZ_E_FORMAT, "joint %u: name not terminated or reserved fields not zero", i);
        hz_status_t s = check_key_range(v, "joint", i, j->key_first, j->key_count);
        if (s)
            return s;
    }
    const hz_hzb_skin_bind_t *b = (const hz_hzb_skin_bind_t *)sec_data(v, HZ_SEC_SKIN_BINDS);
    for (uint32_t i = 0; i < v->h.skin_bind_count; i++, b++) {
        if (b->joint >= v->h.joint_count)
            return fail(v, HZ_E_RANGE, "skin bind %u: joint %u, the scene has %u", i, b->joint, v->h.joint_count);
        if (!all_zero(b->reserved, sizeof b->reserved))
            return fail(v, HZ_E_FORMAT, "skin bind %u: reserved fields not zero", i);
        for (int c = 0; c < 12; c++)
            if (!hz_isfinitef(b->inv_bind[c]) || hz_absf(b->inv_bind[c]) > HZ_ACCEL_MAX_COORD)
                return fail(v, HZ_E_RANGE, "skin bind %u: inverse bind matrix element %d is not finite or beyond "
                            "+-2^36", i, c);
    }
    return HZ_OK;
}

static hz_status_t check_skin_object(view_t *v, uint32_t obj, const hz_hzb_object_t *o)
{
    if (o->key_count == 0 || o->key_count > 65536u || (uint64_t)o->key_first + o->key_count > v->h.skin_bind_count)
        return fail(v, HZ_E_RANGE, "object %u: skin binds %u..%llu outside the %u in 'skin_binds' (or more than "
                    "65536)", obj, o->key_first, (unsigned long long)o->key_first + o->key_count, v->h.skin_bind_count);
    if (!v->sec[HZ_SEC_SKIN_WEIGHTS])
        return fail(v, HZ_E_FORMAT, "object %u is skinned but section 'skin_weights' is missing", obj);
    return HZ_OK;
}

/* Weights: inside a SKIN object every vertex names binds of its object and its weights sum to 65535 (so the
 * blend needs no division); elsewhere they are zero. Runs after check_objects (ranges are valid). */
static hz_status_t check_skin_weights(view_t *v)
{
    const hz_hzb_skin_weight_t *w = (const hz_hzb_skin_weight_t *)sec_data(v, HZ_SEC_SKIN_WEIGHTS);
    const hz_hzb_object_t *o = (const hz_hzb_object_t *)sec_data(v, HZ_SEC_OBJECTS);
    int any_skin = 0;
    for (uint32_t i = 0; i < v->h.object_count; i++)
        any_skin |= o[i].motion == HZ_MOTION_SKIN;
    if (!w) /* check_skin_object refused skinned objects without weights */
        return HZ_OK;
    if (!any_skin)
        return fail(v, HZ_E_FORMAT, "section 'skin_weights' is present but no object is skinned");
    for (uint32_t i = 0; i < v->h.object_count; i++) {
        int skin = o[i].motion == HZ_MOTION_SKIN;
        for (uint32_t k = o[i].first_vertex; k < o[i].first_vertex + o[i].vertex_count; k++) {
            const hz_hzb_skin_weight_t *e = &w[k];
            uint32_t sum = 0;
            for (int c = 0; c < 4; c++) {
                sum += e->weight[c];
                if (skin && e->bind[c] >= o[i].key_count)
                    return fail(v, HZ_E_RANGE, "skin weights of vertex %u: bind %u, its object %u has %u", k,
                                e->bind[c], i, o[i].key_count);
                if (!skin && (e->bind[c] || e->weight[c]))
                    return fail(v, HZ_E_FORMAT, "skin weights of vertex %u are not zero, its object %u is not "
                                "skinned", k, i);
            }
            if (skin && sum != 65535u)
                return fail(v, HZ_E_RANGE, "skin weights of vertex %u sum to %u, not 65535", k, sum);
        }
    }
    return HZ_OK;
}

static hz_status_t check_objects(view_t *v)
{
    const hz_hzb_object_t *o = (const hz_hzb_object_t *)sec_data(v, HZ_SEC_OBJECTS);
    uint64_t next_tri = 0, next_vert = 0;
    for (uint32_t i = 0; i < v->h.object_count; i++, o++) {
        if (!name_ok(o->name))
            return fail(v, HZ_E_FORMAT, "object %u: name not terminated", i);
        /* Objects partition triangles and vertices in order: this makes "object owns its range" checkable in
         * one pass and lets animation rewrite one contiguous range. */
        if (o->first_triangle != next_tri || o->first_vertex != next_vert)
            return fail(v, HZ_E_FORMAT, "object %u: ranges must follow the previous object's (triangle %llu, "
                        "vertex %llu)", i, (unsigned long long)next_tri, (unsigned long long)next_vert);
        next_tri += o->triangle_count;
        next_vert += o->vertex_count;
        if (next_tri > v->h.triangle_count || next_vert > v->h.vertex_count)
            return fail(v, HZ_E_RANGE, "object %u: ranges run past the scene's %u triangles / %u vertices", i,
                        v->h.triangle_count, v->h.vertex_count);
        for (int p = 0; p < 8; p++)
            if (!hz_isfinitef(o->params[p]))
                return fail(v, HZ_E_RANGE, "object %u: motion parameter %d is not finite", i, p);
        hz_status_t s;
        switch (o->motion) {
        case HZ_MOTION_NONE:
            break;
        case HZ_MOTION_RIGID:
            if ((s = check_rigid_keys(v, i, o)))
                return s;
            break;
        case HZ_MOTION_VERTEX: {
            uint64_t need = (uint64_t)o->key_count * o->vertex_count;
            if (o->key_count == 0 || o->vertex_count == 0 || !(o->key_rate > 0.0f) || !hz_isfinitef(o->key_rate) ||
                (uint64_t)o->key_first + need > v->h.vertex_key_count)
                return fail(v, HZ_E_RANGE, "object %u: %u vertex-key frames of %u vertices from %u do not fit the "
                            "%u keys (or the rate is not positive)", i, o->key_count, o->vertex_count,
                            o->key_first, v->h.vertex_key_count);
            if (v->sec[HZ_SEC_NORMALS] && !v->sec[HZ_SEC_VERTEX_KEY_NORMALS])
                return fail(v, HZ_E_FORMAT, "object %u: per-vertex keys without key normals in a scene with normals",
                            i);
            break;
        }
        case HZ_MOTION_SPIN:
            if (o->params[3] == 0.0f && o->params[4] == 0.0f && o->params[5] == 0.0f)
                return fail(v, HZ_E_RANGE, "object %u: spin axis is zero", i);
            break;
        case HZ_MOTION_OSCILLATE:
            if (o->params[3] < 0.0f)
                return fail(v, HZ_E_RANGE, "object %u: oscillation frequency is negative", i);
            break;
        case HZ_MOTION_SWAY:
            if (o->params[7] < 0.0f)
                return fail(v, HZ_E_RANGE, "object %u: sway root radius is negative", i);
            break;
        case HZ_MOTION_SKIN:
            if ((s = check_skin_object(v, i, o)))
                return s;
            break;
        default:
            return fail(v, HZ_E_RANGE, "object %u: unknown motion kind %u", i, o->motion);
        }
    }
    if (next_tri != v->h.triangle_count || next_vert != v->h.vertex_count)
        return fail(v, HZ_E_FORMAT, "objects cover %llu of %u triangles and %llu of %u vertices",
                    (unsigned long long)next_tri, v->h.triangle_count, (unsigned long long)next_vert,
                    v->h.vertex_count);
    return HZ_OK;
}

static hz_status_t check_triangles(view_t *v)
{
    const uint32_t *tri = (const uint32_t *)sec_data(v, HZ_SEC_TRIANGLES);
    const uint32_t *info = (const uint32_t *)sec_data(v, HZ_SEC_TRI_INFO);
    const hz_hzb_object_t *objects = (const hz_hzb_object_t *)sec_data(v, HZ_SEC_OBJECTS);
    for (uint32_t t = 0; t < v->h.triangle_count; t++) {
        uint32_t mat = info[t] & 0xffffu, obj = info[t] >> 16;
        if (mat >= v->h.material_count || obj >= v->h.object_count)
            return fail(v, HZ_E_RANGE, "triangle %u: material %u / object %u out of range (%u / %u)", t, mat, obj,
                        v->h.material_count, v->h.object_count);
        const hz_hzb_object_t *o = &objects[obj];
        if (t < o->first_triangle || t - o->first_triangle >= o->triangle_count)
            return fail(v, HZ_E_RANGE, "triangle %u lies outside the range of its object %u", t, obj);
        for (int c = 0; c < 3; c++) {
            uint32_t idx = tri[(size_t)t * 3 + c];
            if (idx >= v->h.vertex_count)
                return fail(v, HZ_E_RANGE, "triangle %u: vertex index %u >= vertex count %u", t, idx,
                            v->h.vertex_count);
            if (idx < o->first_vertex || idx - o->first_vertex >= o->vertex_count)
                return fail(v, HZ_E_RANGE, "triangle %u: vertex %u is not a vertex of its object %u", t, idx, obj);
        }
    }
    return HZ_OK;
}

static hz_status_t check_lights_camera(view_t *v)
{
    const hz_hzb_light_t *l = (const hz_hzb_light_t *)sec_data(v, HZ_SEC_LIGHTS);
    for (uint32_t i = 0; i < v->h.light_count; i++, l++)
        if (!finite3(l->position) || !finite3(l->color) || l->color[0] < 0 || l->color[1] < 0 ||
            l->color[2] < 0 || l->falloff > HZ_FALLOFF_NONE || l->reserved)
            return fail(v, HZ_E_RANGE, "light %u: position/colour not finite, negative colour or bad falloff", i);
    const hz_hzb_camera_key_t *k = (const hz_hzb_camera_key_t *)sec_data(v, HZ_SEC_CAMERA_KEYS);
    for (uint32_t i = 0; i < v->h.camera_key_count; i++) {
        const hz_hzb_camera_key_t *e = &k[i];
        if (!hz_isfinitef(e->time) || !finite3(e->eye) || !finite3(e->target) || !finite3(e->up) ||
            !(e->fov_y > 0.0f && e->fov_y < HZ_PI) || e->reserved != 0.0f)
            return fail(v, HZ_E_RANGE, "camera key %u: not finite or field of view outside (0, pi)", i);
        if (e->eye[0] == e->target[0] && e->eye[1] == e->target[1] && e->eye[2] == e->target[2])
            return fail(v, HZ_E_RANGE, "camera key %u: eye and target coincide", i);
        if (e->up[0] == 0.0f && e->up[1] == 0.0f && e->up[2] == 0.0f)
            return fail(v, HZ_E_RANGE, "camera key %u: up vector is zero", i);
        if (i > 0 && !(e->time > k[i - 1].time))
            return fail(v, HZ_E_RANGE, "camera key times do not increase at key %u", i);
    }
    return HZ_OK;
}

static hz_status_t check_uvs(view_t *v)
{
    const float *uv = (const float *)sec_data(v, HZ_SEC_UVS);
    for (uint64_t i = 0; uv && i < v->count[HZ_SEC_UVS]; i++)
        if (!hz_isfinitef(uv[i * 2]) || !hz_isfinitef(uv[i * 2 + 1]))
            return fail(v, HZ_E_RANGE, "section 'uvs': element %llu is not finite", (unsigned long long)i);
    return HZ_OK;
}

static hz_status_t validate(view_t *v, hz_scene_plan_t *plan)
{
    hz_status_t s;
    if ((s = check_header(v)) || (s = check_table(v)) || (s = check_counts(v)))
        return s;
    if ((s = check_float4s(v, HZ_SEC_POSITIONS, 0)) || (s = check_float4s(v, HZ_SEC_NORMALS, 1)) ||
        (s = check_float4s(v, HZ_SEC_VERTEX_KEYS, 0)) || (s = check_float4s(v, HZ_SEC_VERTEX_KEY_NORMALS, 1)) ||
        (s = check_uvs(v)) || (s = check_textures(v)) || (s = check_materials(v)) || (s = check_objects(v)) ||
        (s = check_triangles(v)) || (s = check_lights_camera(v)) || (s = check_joints_binds(v)) ||
        (s = check_skin_weights(v)))
        return s;
    const hz_hzb_header_t *h = &v->h;
    uint32_t content = hz_hzb_content_features((const hz_hzb_material_t *)sec_data(v, HZ_SEC_MATERIALS),
                                               h->material_count,
                                               (const hz_hzb_object_t *)sec_data(v, HZ_SEC_OBJECTS),
                                               h->object_count, h->camera_key_count, v->sec[HZ_SEC_NORMALS] != NULL);
    if ((h->features & ~(uint32_t)HZ_FEAT_INSTANCING) != content) {
        char want[128], got[128];
        hz_scene_features_str(content, want, sizeof want);
        hz_scene_features_str(h->features & ~(uint32_t)HZ_FEAT_INSTANCING, got, sizeof got);
        return fail(v, HZ_E_FORMAT, "feature mask says '%s', the content needs '%s'", got, want);
    }
    plan->features = h->features;
    plan->file_bytes = v->size;
    plan->animated_vertices = 0;
    plan->arena_bytes = 0;
    plan->skin_bytes = 0;
    if (h->features & HZ_FEAT_MOTION) {
        const hz_hzb_object_t *o = (const hz_hzb_object_t *)sec_data(v, HZ_SEC_OBJECTS);
        uint32_t max_binds = 0;
        for (uint32_t i = 0; i < h->object_count; i++) {
            if (o[i].motion != HZ_MOTION_NONE)
                plan->animated_vertices += o[i].vertex_count;
            if (o[i].motion == HZ_MOTION_SKIN && o[i].key_count > max_binds)
                max_binds = o[i].key_count;
        }
        /* One matrix per bind of the largest skinned object (<= 65536 * 64 bytes): objects skin one by one. */
        if (max_binds)
            plan->skin_bytes = (size_t)max_binds * HZ_SKIN_MAT_BYTES + HZ_HZB_ALIGN;
        /* Current and previous positions (and normals): whole arrays, so the accel and the shader index them
         * like the static ones. vertex_count < 2^32, so this cannot overflow a 64-bit size_t; on 32-bit
         * targets the checks below catch it. */
        uint64_t arrays = v->sec[HZ_SEC_NORMALS] ? 4 : 2;
        uint64_t bytes = arrays * ((uint64_t)h->vertex_count * 16u + HZ_HZB_ALIGN);
        if (bytes > (uint64_t)SIZE_MAX)
            return fail(v, HZ_E_OVERFLOW, "animated state of %u vertices does not fit the address space",
                        h->vertex_count);
        if (bytes > (uint64_t)SIZE_MAX - plan->skin_bytes)
            return fail(v, HZ_E_OVERFLOW, "animated state of %u vertices does not fit the address space",
                        h->vertex_count);
        plan->arena_bytes = (size_t)bytes + plan->skin_bytes;
    }
    return HZ_OK;
}

static hz_status_t begin(view_t *v, const void *buf, size_t size, hz_error_t *err)
{
    hz_memset(v, 0, sizeof *v);
    v->base = (const uint8_t *)buf;
    v->size = size;
    v->err = err;
    if (!buf)
        return fail(v, HZ_E_INVALID_ARG, "no scene buffer");
    if ((uintptr_t)buf % HZ_HZB_ALIGN != 0)
        return fail(v, HZ_E_INVALID_ARG, "scene buffer is not %u-byte aligned", HZ_HZB_ALIGN);
    return HZ_OK;
}

hz_status_t hz_scene_plan(const void *buf, size_t size, hz_scene_plan_t *plan, hz_error_t *err)
{
    view_t v;
    hz_scene_plan_t p;
    hz_status_t s = begin(&v, buf, size, err);
    if (s == HZ_OK)
        s = validate(&v, &p);
    if (s == HZ_OK && plan)
        *plan = p;
    return s;
}

hz_status_t hz_scene_load(hz_scene_t *scene, const void *buf, size_t size, hz_arena_t *arena, hz_error_t *err)
{
    view_t v;
    hz_scene_plan_t plan;
    hz_status_t s = begin(&v, buf, size, err);
    if (s == HZ_OK)
        s = validate(&v, &plan);
    if (s != HZ_OK)
        return s;
    if (plan.arena_bytes) {
        size_t have = arena ? hz_arena_available(arena, HZ_HZB_ALIGN) : 0;
        if (plan.arena_bytes > have)
            return fail(&v, HZ_E_NO_MEMORY, "arena '%s': needs %zu bytes, has %zu",
                        arena ? arena->name : "scene", plan.arena_bytes, have);
    }
    hz_scene_t *sc = scene;
    hz_memset(sc, 0, sizeof *sc);
    sc->header = (const hz_hzb_header_t *)buf;
    sc->features = plan.features;
    sc->vertex_count = v.h.vertex_count;
    sc->triangle_count = v.h.triangle_count;
    sc->material_count = v.h.material_count;
    sc->texture_count = v.h.texture_count;
    sc->object_count = v.h.object_count;
    sc->light_count = v.h.light_count;
    sc->camera_key_count = v.h.camera_key_count;
    sc->rest_pos = (const float *)sec_data(&v, HZ_SEC_POSITIONS);
    sc->rest_nrm = (const float *)sec_data(&v, HZ_SEC_NORMALS);
    sc->uv = (const float *)sec_data(&v, HZ_SEC_UVS);
    sc->tri = (const uint32_t *)sec_data(&v, HZ_SEC_TRIANGLES);
    sc->tri_info = (const uint32_t *)sec_data(&v, HZ_SEC_TRI_INFO);
    sc->materials = (const hz_material_t *)sec_data(&v, HZ_SEC_MATERIALS);
    sc->textures = (const hz_texture_t *)sec_data(&v, HZ_SEC_TEXTURES);
    sc->texels = (const uint8_t *)sec_data(&v, HZ_SEC_TEXELS);
    sc->objects = (const hz_object_t *)sec_data(&v, HZ_SEC_OBJECTS);
    sc->rigid_keys = (const hz_hzb_rigid_key_t *)sec_data(&v, HZ_SEC_RIGID_KEYS);
    sc->vertex_keys = (const float *)sec_data(&v, HZ_SEC_VERTEX_KEYS);
    sc->vertex_key_normals = (const float *)sec_data(&v, HZ_SEC_VERTEX_KEY_NORMALS);
    sc->lights = (const hz_light_t *)sec_data(&v, HZ_SEC_LIGHTS);
    sc->camera_keys = (const hz_hzb_camera_key_t *)sec_data(&v, HZ_SEC_CAMERA_KEYS);
    sc->joints = (const hz_hzb_joint_t *)sec_data(&v, HZ_SEC_JOINTS);
    sc->skin_binds = (const hz_hzb_skin_bind_t *)sec_data(&v, HZ_SEC_SKIN_BINDS);
    sc->skin_weights = (const hz_hzb_skin_weight_t *)sec_data(&v, HZ_SEC_SKIN_WEIGHTS);
    sc->plan = plan;
    /* Static data is used in place and never written: the casts below drop const only for the API's sake. */
    sc->pos = (float *)(uintptr_t)sc->rest_pos;
    sc->nrm = (float *)(uintptr_t)sc->rest_nrm;
    if (plan.arena_bytes) {
        size_t bytes = (size_t)v.h.vertex_count * 16u;
        sc->pos = hz_arena_alloc(arena, bytes, HZ_HZB_ALIGN);
        sc->prev_pos = hz_arena_alloc(arena, bytes, HZ_HZB_ALIGN);
        if (sc->rest_nrm) {
            sc->nrm = hz_arena_alloc(arena, bytes, HZ_HZB_ALIGN);
            sc->prev_nrm = hz_arena_alloc(arena, bytes, HZ_HZB_ALIGN);
        }
        if (plan.skin_bytes)
            sc->skin_mats = hz_arena_alloc(arena, plan.skin_bytes - HZ_HZB_ALIGN, HZ_HZB_ALIGN);
        if (!sc->pos || !sc->prev_pos || (sc->rest_nrm && (!sc->nrm || !sc->prev_nrm)) ||
            (plan.skin_bytes && !sc->skin_mats))
            return hz_arena_error(arena, err); /* cannot happen after the check above; kept as a guard */
        hz_memcpy(sc->pos, sc->rest_pos, bytes);
        if (sc->rest_nrm)
            hz_memcpy(sc->nrm, sc->rest_nrm, bytes);
        hz_scene_pose(sc, 0.0f);
        hz_memcpy(sc->prev_pos, sc->pos, bytes);
        if (sc->rest_nrm)
            hz_memcpy(sc->prev_nrm, sc->nrm, bytes);
    }
    return HZ_OK;
}
