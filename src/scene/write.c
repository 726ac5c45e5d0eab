/* .hzb serialisation (see hz/hzb_write.h). */
#include "hz/hzb_write.h"

#include "hz/crc32.h"
#include "hz/skin.h"
#include "scene_internal.h"

typedef struct sec {
    uint32_t id;
    const void *data;
    uint64_t count;
} sec_t;

static uint32_t collect(const hz_hzb_source_t *s, sec_t out[HZ_SEC_ID_MAX])
{
    const sec_t all[] = {
        { HZ_SEC_POSITIONS, s->positions, s->vertex_count },
        { HZ_SEC_NORMALS, s->normals, s->normals ? s->vertex_count : 0 },
        { HZ_SEC_UVS, s->uvs, s->uvs ? s->vertex_count : 0 },
        { HZ_SEC_TRIANGLES, s->triangles, s->triangle_count },
        { HZ_SEC_TRI_INFO, s->tri_info, s->triangle_count },
        { HZ_SEC_MATERIALS, s->materials, s->material_count },
        { HZ_SEC_TEXTURES, s->textures, s->texture_count },
        { HZ_SEC_TEXELS, s->texels, s->texel_count },
        { HZ_SEC_OBJECTS, s->objects, s->object_count },
        { HZ_SEC_RIGID_KEYS, s->rigid_keys, s->rigid_key_count },
        { HZ_SEC_VERTEX_KEYS, s->vertex_keys, s->vertex_key_count },
        { HZ_SEC_VERTEX_KEY_NORMALS, s->vertex_key_normals, s->vertex_key_normals ? s->vertex_key_count : 0 },
        { HZ_SEC_LIGHTS, s->lights, s->light_count },
        { HZ_SEC_CAMERA_KEYS, s->camera_keys, s->camera_key_count },
        { HZ_SEC_JOINTS, s->joints, s->joint_count },
        { HZ_SEC_SKIN_BINDS, s->skin_binds, s->skin_bind_count },
        { HZ_SEC_SKIN_WEIGHTS, s->skin_weights, s->skin_weights ? s->vertex_count : 0 },
    };
    uint32_t n = 0;
    for (size_t i = 0; i < HZ_ARRAY_LEN(all); i++)
        if (all[i].count && all[i].data)
            out[n++] = all[i];
    return n;
}

/* Adds b to *a; returns 0 on overflow. */
static int add_size(uint64_t *a, uint64_t b)
{
    if (*a > UINT64_MAX - b)
        return 0;
    *a += b;
    return 1;
}

static uint64_t layout(const sec_t *secs, uint32_t n, uint64_t *offsets)
{
    uint64_t at = sizeof(hz_hzb_header_t) + (uint64_t)n * sizeof(hz_hzb_section_t);
    for (uint32_t i = 0; i < n; i++) {
        uint64_t elem = hz_hzb_elem_bytes(secs[i].id);
        if (secs[i].count > UINT64_MAX / elem)
            return 0;
        at = (at + HZ_HZB_ALIGN - 1) & ~(uint64_t)(HZ_HZB_ALIGN - 1);
        offsets[i] = at;
        if (!add_size(&at, secs[i].count * elem))
            return 0;
    }
    return at;
}

size_t hz_hzb_write_size(const hz_hzb_source_t *src)
{
    sec_t secs[HZ_SEC_ID_MAX];
    uint64_t offsets[HZ_SEC_ID_MAX];
    uint64_t total = layout(secs, collect(src, secs), offsets);
    return total > (uint64_t)SIZE_MAX ? 0 : (size_t)total;
}

/* Bounds at t = 0 with object transforms applied (rigid objects store object-space positions). */
static void bounds_at_zero(const hz_hzb_source_t *s, float lo[3], float hi[3])
{
    for (int c = 0; c < 3; c++)
        lo[c] = FLT_MAX, hi[c] = -FLT_MAX;
    for (uint32_t o = 0; o < s->object_count; o++) {
        const hz_hzb_object_t *ob = &s->objects[o];
        hz_mat4_t m;
        int moved = ob->motion != HZ_MOTION_VERTEX && hz_object_matrix(ob, s->rigid_keys, 0.0f, &m);
        int skinned = ob->motion == HZ_MOTION_SKIN && s->skin_weights && s->skin_binds && s->joints;
        for (uint32_t v = ob->first_vertex; v < ob->first_vertex + ob->vertex_count && v < s->vertex_count; v++) {
            const float *p = s->positions + (size_t)v * 4;
            if (ob->motion == HZ_MOTION_VERTEX && s->vertex_keys) {
                uint32_t f0, f1;
                float w;
                hz_object_vertex_frames(ob, 0.0f, &f0, &f1, &w);
                p = s->vertex_keys + ((size_t)ob->key_first + (size_t)f0 * ob->vertex_count +
                                      (v - ob->first_vertex)) * 4;
            }
            hz_vec3_t q = hz_v3(p[0], p[1], p[2]);
            if (skinned)
                q = hz_skin_point(ob, s->skin_binds, s->skin_bind_count, s->joints, s->joint_count, s->rigid_keys,
                                  s->rigid_key_count, &s->skin_weights[v], q, 0.0f);
            else if (moved)
                q = hz_mat4_mul_point(&m, q);
            for (int c = 0; c < 3; c++) {
                float x = hz_v3_get(q, c);
                lo[c] = hz_minf(lo[c], x);
                hi[c] = hz_maxf(hi[c], x);
            }
        }
    }
    if (lo[0] > hi[0])
        for (int c = 0; c < 3; c++)
            lo[c] = hi[c] = 0.0f;
}

hz_status_t hz_hzb_write(const hz_hzb_source_t *src, void *out, size_t cap, size_t *written, hz_error_t *err)
{
    sec_t secs[HZ_SEC_ID_MAX];
    uint64_t offsets[HZ_SEC_ID_MAX];
    uint32_t n = collect(src, secs);
    uint64_t total = layout(secs, n, offsets);
    if (written)
        *written = 0;
    if (total == 0 || total > (uint64_t)SIZE_MAX)
        return hz_error_set(err, HZ_E_OVERFLOW, "scene too large for one .hzb image");
    if (total > cap)
        return hz_error_set(err, HZ_E_NO_MEMORY, "the .hzb image needs %llu bytes, the buffer has %zu",
                            (unsigned long long)total, cap);
    uint8_t *base = (uint8_t *)out;
    hz_memset(base, 0, (size_t)total);

    hz_hzb_header_t h;
    hz_memset(&h, 0, sizeof h);
    hz_memcpy(h.magic, HZ_HZB_MAGIC, 8);
    h.version = HZ_HZB_VERSION;
    h.header_bytes = sizeof h;
    h.file_bytes = total;
    h.section_count = n;
    h.features = hz_hzb_content_features(src->materials, src->material_count, src->objects, src->object_count,
                                         src->camera_key_count, src->normals != NULL) |
                 (src->extra_features & HZ_FEAT_INSTANCING);
    h.vertex_count = src->vertex_count;
    h.triangle_count = src->triangle_count;
    h.material_count = src->material_count;
    h.texture_count = src->texture_count;
    h.object_count = src->object_count;
    h.light_count = src->light_count;
    h.camera_key_count = src->camera_key_count;
    h.rigid_key_count = src->rigid_key_count;
    h.vertex_key_count = src->vertex_key_count;
    h.texel_count = src->texel_count;
    h.joint_count = src->joint_count;
    h.skin_bind_count = src->skin_bind_count;
    bounds_at_zero(src, h.bounds_min, h.bounds_max);
    h.duration = src->duration;
    for (int c = 0; c < 3; c++) {
        h.background[c] = src->background[c];
        h.ambient[c] = src->ambient[c];
    }
    h.camera_fov_y = src->camera_fov_y;
    h.camera_flags = src->camera_flags;
    if (src->name)
        for (uint32_t i = 0; i + 1 < HZ_HZB_NAME_BYTES && src->name[i]; i++)
            h.name[i] = (uint8_t)src->name[i];
    h.header_crc = hz_crc32(0, &h, offsetof(hz_hzb_header_t, header_crc));
    hz_memcpy(base, &h, sizeof h);

    for (uint32_t i = 0; i < n; i++) {
        uint32_t elem = hz_hzb_elem_bytes(secs[i].id);
        size_t size = (size_t)(secs[i].count * elem);
        hz_hzb_section_t e;
        hz_memset(&e, 0, sizeof e);
        e.id = secs[i].id;
        e.elem_bytes = elem;
        e.offset = offsets[i];
        e.size = size;
        hz_memcpy(base + offsets[i], secs[i].data, size);
        e.crc32 = hz_crc32(0, base + offsets[i], size);
        hz_memcpy(base + sizeof h + (size_t)i * sizeof e, &e, sizeof e);
    }
    if (written)
        *written = (size_t)total;
    return HZ_OK;
}
