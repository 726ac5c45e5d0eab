/* Format helpers shared by the writer and the loader (see hz/hzb.h and scene_internal.h). */
#include "scene_internal.h"

uint32_t hz_hzb_elem_bytes(uint32_t id)
{
    switch (id) {
    case HZ_SEC_POSITIONS: return 16;
    case HZ_SEC_NORMALS: return 16;
    case HZ_SEC_UVS: return 8;
    case HZ_SEC_TRIANGLES: return 12;
    case HZ_SEC_TRI_INFO: return 4;
    case HZ_SEC_MATERIALS: return (uint32_t)sizeof(hz_hzb_material_t);
    case HZ_SEC_TEXTURES: return (uint32_t)sizeof(hz_hzb_texture_t);
    case HZ_SEC_TEXELS: return 4;
    case HZ_SEC_OBJECTS: return (uint32_t)sizeof(hz_hzb_object_t);
    case HZ_SEC_RIGID_KEYS: return (uint32_t)sizeof(hz_hzb_rigid_key_t);
    case HZ_SEC_VERTEX_KEYS: return 16;
    case HZ_SEC_VERTEX_KEY_NORMALS: return 16;
    case HZ_SEC_LIGHTS: return (uint32_t)sizeof(hz_hzb_light_t);
    case HZ_SEC_CAMERA_KEYS: return (uint32_t)sizeof(hz_hzb_camera_key_t);
    case HZ_SEC_JOINTS: return (uint32_t)sizeof(hz_hzb_joint_t);
    case HZ_SEC_SKIN_BINDS: return (uint32_t)sizeof(hz_hzb_skin_bind_t);
    case HZ_SEC_SKIN_WEIGHTS: return (uint32_t)sizeof(hz_hzb_skin_weight_t);
    default: return 0;
    }
}

const char *hz_hzb_section_name(uint32_t id)
{
    static const char *const names[HZ_SEC_ID_MAX + 1] = {
        "unknown", "positions", "normals", "uvs", "triangles", "tri_info", "materials", "textures", "texels",
        "objects", "rigid_keys", "vertex_keys", "vertex_key_normals", "lights", "camera_keys", "joints",
        "skin_binds", "skin_weights",
    };
    return id <= HZ_SEC_ID_MAX ? names[id] : "unknown";
}

uint32_t hz_hzb_content_features(const hz_hzb_material_t *materials, uint32_t material_count,
                                 const hz_hzb_object_t *objects, uint32_t object_count, uint32_t camera_key_count,
                                 int has_normals)
{
    uint32_t f = 0;
    for (uint32_t i = 0; i < material_count; i++) {
        const hz_hzb_material_t *m = &materials[i];
        if (m->alpha_mode == HZ_ALPHA_BLEND)
            f |= HZ_FEAT_BLEND;
        if (m->alpha_mode == HZ_ALPHA_MASK)
            f |= HZ_FEAT_CUTOUT;
        if (m->mirror > 0.0f)
            f |= HZ_FEAT_MIRROR;
        if (m->base_texture >= 0 || (m->alpha_mode != HZ_ALPHA_OPAQUE && m->alpha_texture >= 0))
            f |= HZ_FEAT_TEXTURES;
    }
    for (uint32_t i = 0; i < object_count; i++) {
        if (objects[i].motion != HZ_MOTION_NONE)
            f |= HZ_FEAT_MOTION;
        if (objects[i].motion == HZ_MOTION_VERTEX || objects[i].motion == HZ_MOTION_SKIN)
            f |= HZ_FEAT_SKINNING;
    }
    if (camera_key_count > 1)
        f |= HZ_FEAT_CAMERA_PATH;
    if (has_normals)
        f |= HZ_FEAT_NORMALS;
    return f;
}

void hz_scene_features_str(uint32_t features, char *buf, size_t size)
{
    static const char *const names[] = { "motion", "blend", "cutout", "mirror", "textures",
                                         "instancing", "camera-path", "skinning", "normals" };
    size_t n = 0;
    if (size == 0)
        return;
    buf[0] = '\0';
    for (unsigned i = 0; i < HZ_ARRAY_LEN(names); i++) {
        if (!(features & (1u << i)))
            continue;
        n += hz_fmt(buf + (n < size ? n : size - 1), n < size ? size - n : 1, "%s%s", n ? "," : "", names[i]);
    }
    if (n == 0)
        hz_fmt(buf, size, "none");
}
