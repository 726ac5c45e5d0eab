/* Procedural meshes (see hz/meshgen.h). */
#include "hz/meshgen.h"

#include "hz/hash.h"
#include "hz/vmath.h"

static hz_status_t alloc_mesh(hz_mesh_t *m, hz_arena_t *a, uint64_t verts, uint64_t tris, hz_error_t *err)
{
    if (verts > 0xFFFFFFFFu || tris > HZ_ACCEL_MAX_TRIS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "meshgen: %llu vertices / %llu triangles are too many",
                            (unsigned long long)verts, (unsigned long long)tris);
    hz_arena_mark_t m0 = hz_arena_mark(a);
    m->pos = hz_arena_alloc_array(a, (size_t)verts * 4u, sizeof(float), 16);
    m->tri = hz_arena_alloc_array(a, (size_t)tris * 3u, sizeof(uint32_t), 16);
    if ((verts && !m->pos) || (tris && !m->tri)) {
        hz_arena_error(a, err);
        hz_arena_reset(a, m0);
        return HZ_E_NO_MEMORY;
    }
    m->vertex_count = (uint32_t)verts;
    m->tri_count = (uint32_t)tris;
    m->tri_flags = 0;
    return HZ_OK;
}

static void set_v(hz_mesh_t *m, uint32_t i, float x, float y, float z)
{
    m->pos[4u * i + 0] = x;
    m->pos[4u * i + 1] = y;
    m->pos[4u * i + 2] = z;
    m->pos[4u * i + 3] = 0.0f;
}

static void set_t(hz_mesh_t *m, uint32_t i, uint32_t a, uint32_t b, uint32_t c)
{
    m->tri[3u * i + 0] = a;
    m->tri[3u * i + 1] = b;
    m->tri[3u * i + 2] = c;
}

hz_status_t hz_meshgen_sphere(hz_mesh_t *m, hz_arena_t *a, uint32_t stacks, uint32_t slices, float radius,
                              hz_error_t *err)
{
    if (stacks < 2 || slices < 3 || stacks > 16384 || slices > 16384)
        return hz_error_set(err, HZ_E_INVALID_ARG, "meshgen sphere: stacks %u (2..16384), slices %u (3..16384)",
                            stacks, slices);
    uint64_t verts = 2u + (uint64_t)(stacks - 1) * slices;
    uint64_t tris = 2u * (uint64_t)slices * (stacks - 1);
    hz_status_t s = alloc_mesh(m, a, verts, tris, err);
    if (s != HZ_OK)
        return s;
    set_v(m, 0, 0.0f, radius, 0.0f);
    set_v(m, 1, 0.0f, -radius, 0.0f);
    for (uint32_t i = 1; i < stacks; i++) {
        float th = HZ_PI * (float)i / (float)stacks, st, ct;
        hz_sincosf(th, &st, &ct);
        for (uint32_t j = 0; j < slices; j++) {
            float ph = 2.0f * HZ_PI * (float)j / (float)slices, sp, cp;
            hz_sincosf(ph, &sp, &cp);
            set_v(m, 2u + (i - 1) * slices + j, radius * st * cp, radius * ct, radius * st * sp);
        }
    }
    uint32_t t = 0;
    for (uint32_t j = 0; j < slices; j++) {
        uint32_t j1 = (j + 1) % slices;
        /* outward winding: (v1 - v0) x (v2 - v0) points away from the centre */
        set_t(m, t++, 0, 2u + j1, 2u + j);
        uint32_t last = 2u + (stacks - 2) * slices;
        set_t(m, t++, 1, last + j, last + j1);
    }
    for (uint32_t i = 1; i + 1 < stacks; i++) {
        uint32_t r0 = 2u + (i - 1) * slices, r1 = r0 + slices;
        for (uint32_t j = 0; j < slices; j++) {
            uint32_t j1 = (j + 1) % slices;
            set_t(m, t++, r0 + j, r0 + j1, r1 + j1);
            set_t(m, t++, r0 + j, r1 + j1, r1 + j);
        }
    }
    return HZ_OK;
}

hz_status_t hz_meshgen_cube_sphere(hz_mesh_t *m, hz_arena_t *a, uint32_t n, float radius, bool round,
                                   hz_error_t *err)
{
    if (n < 1 || n > 1024)
        return hz_error_set(err, HZ_E_INVALID_ARG, "meshgen cube_sphere: n %u (1..1024)", n);
    const uint32_t L = n + 1;
    uint64_t verts = (uint64_t)L * L * L - (uint64_t)(L - 2) * (L - 2) * (L - 2);
    uint64_t tris = 12u * (uint64_t)n * n;
    hz_arena_mark_t m0 = hz_arena_mark(a);
    uint32_t *lattice = hz_arena_alloc_array(a, (size_t)L * L * L, sizeof(uint32_t), 16);
    if (!lattice) {
        hz_arena_error(a, err);
        return HZ_E_NO_MEMORY;
    }
    hz_status_t s = alloc_mesh(m, a, verts, tris, err);
    if (s != HZ_OK) {
        hz_arena_reset(a, m0);
        return s;
    }
    uint32_t v = 0;
    for (uint32_t z = 0; z < L; z++)
        for (uint32_t y = 0; y < L; y++)
            for (uint32_t x = 0; x < L; x++) {
                bool surface = x == 0 || y == 0 || z == 0 || x == n || y == n || z == n;
                uint32_t idx = (z * L + y) * L + x;
                lattice[idx] = HZ_ACCEL_INVALID_ID;
                if (!surface)
                    continue;
                float p[3] = { 2.0f * (float)x / (float)n - 1.0f, 2.0f * (float)y / (float)n - 1.0f,
                               2.0f * (float)z / (float)n - 1.0f };
                float sc = radius;
                if (round)
                    sc = radius / hz_sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                set_v(m, v, p[0] * sc, p[1] * sc, p[2] * sc);
                lattice[idx] = v++;
            }
    /* Six faces: axis k fixed at 0 or n; (u, w) walk the other two axes with outward winding. */
    uint32_t t = 0;
    for (int k = 0; k < 3; k++)
        for (int side = 0; side < 2; side++) {
            int ku = (k + 1) % 3, kw = (k + 2) % 3;
            for (uint32_t i = 0; i < n; i++)
                for (uint32_t j = 0; j < n; j++) {
                    uint32_t q[4];
                    const uint32_t du[4] = { 0, 1, 1, 0 }, dw[4] = { 0, 0, 1, 1 };
                    for (int c = 0; c < 4; c++) {
                        uint32_t coord[3];
                        coord[k] = side ? n : 0;
                        coord[ku] = i + du[c];
                        coord[kw] = j + dw[c];
                        q[c] = lattice[(coord[2] * L + coord[1]) * L + coord[0]];
                    }
                    /* (u, w) is right-handed around +k: counter-clockwise seen from +k outside */
                    if (side) {
                        set_t(m, t++, q[0], q[1], q[2]);
                        set_t(m, t++, q[0], q[2], q[3]);
                    } else {
                        set_t(m, t++, q[0], q[2], q[1]);
                        set_t(m, t++, q[0], q[3], q[2]);
                    }
                }
        }
    return HZ_OK;
}

static float unit(hz_rng_t *r)
{
    return hz_u32_to_unit(hz_rng_u32(r));
}

hz_status_t hz_meshgen_soup(hz_mesh_t *m, hz_arena_t *a, uint32_t count, float extent, float size, uint64_t seed,
                            hz_error_t *err)
{
    if (count == 0 || !(extent > 0.0f) || !(size > 0.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "meshgen soup: count, extent and size must be positive");
    hz_status_t s = alloc_mesh(m, a, 3u * (uint64_t)count, count, err);
    if (s != HZ_OK)
        return s;
    hz_rng_t r;
    hz_rng_seed(&r, seed, 7);
    for (uint32_t i = 0; i < count; i++) {
        float c[3];
        for (int k = 0; k < 3; k++)
            c[k] = (2.0f * unit(&r) - 1.0f) * extent;
        for (uint32_t v = 0; v < 3; v++) {
            float p[3]; /* one draw per statement: argument evaluation order is unspecified */
            for (int k = 0; k < 3; k++)
                p[k] = c[k] + (unit(&r) - 0.5f) * size;
            set_v(m, 3u * i + v, p[0], p[1], p[2]);
        }
        set_t(m, i, 3u * i, 3u * i + 1, 3u * i + 2);
    }
    return HZ_OK;
}

hz_status_t hz_meshgen_append_degenerates(hz_mesh_t *m, hz_arena_t *a, uint32_t count, uint64_t seed,
                                          hz_error_t *err)
{
    hz_mesh_t o = *m;
    float lo[3] = { -1, -1, -1 }, hi[3] = { 1, 1, 1 };
    for (uint32_t i = 0; i < o.vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float p = o.pos[4u * i + (uint32_t)k];
            if (i == 0 || p < lo[k])
                lo[k] = p;
            if (i == 0 || p > hi[k])
                hi[k] = p;
        }
    hz_status_t s = alloc_mesh(m, a, (uint64_t)o.vertex_count + 3u * (uint64_t)count,
                               (uint64_t)o.tri_count + count, err);
    if (s != HZ_OK) {
        *m = o;
        return s;
    }
    hz_memcpy(m->pos, o.pos, (size_t)o.vertex_count * 4u * sizeof(float));
    hz_memcpy(m->tri, o.tri, (size_t)o.tri_count * 3u * sizeof(uint32_t));
    hz_rng_t r;
    hz_rng_seed(&r, seed, 11);
    uint32_t v = o.vertex_count, t = o.tri_count;
    for (uint32_t i = 0; i < count; i++) {
        float p[3], d[3];
        for (int k = 0; k < 3; k++) {
            p[k] = lo[k] + (hi[k] - lo[k]) * unit(&r);
            d[k] = (unit(&r) - 0.5f) * (hi[k] - lo[k]) * 0.1f;
        }
        switch (i % 3) {
        case 0: /* repeated index */
            set_v(m, v, p[0], p[1], p[2]);
            set_v(m, v + 1, p[0] + d[0], p[1] + d[1], p[2] + d[2]);
            set_v(m, v + 2, p[0], p[1], p[2]);
            set_t(m, t++, v, v + 1, v);
            break;
        case 1: /* three equal points */
            for (uint32_t q = 0; q < 3; q++)
                set_v(m, v + q, p[0], p[1], p[2]);
            set_t(m, t++, v, v + 1, v + 2);
            break;
        default: /* collinear */
            for (uint32_t q = 0; q < 3; q++)
                set_v(m, v + q, p[0] + d[0] * (float)q, p[1] + d[1] * (float)q, p[2] + d[2] * (float)q);
            set_t(m, t++, v, v + 1, v + 2);
            break;
        }
        v += 3;
    }
    return HZ_OK;
}

void hz_meshgen_transform(hz_mesh_t *m, float scale, hz_vec3_t offset)
{
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        m->pos[4u * i + 0] = m->pos[4u * i + 0] * scale + offset.x;
        m->pos[4u * i + 1] = m->pos[4u * i + 1] * scale + offset.y;
        m->pos[4u * i + 2] = m->pos[4u * i + 2] * scale + offset.z;
    }
}

hz_accel_geom_t hz_meshgen_geom(const hz_mesh_t *m)
{
    hz_accel_geom_t g;
    hz_accel_geom_init(&g);
    g.pos = m->pos;
    g.vertex_count = m->vertex_count;
    g.tri = m->tri;
    g.tri_count = m->tri_count;
    g.tri_flags = m->tri_flags;
    return g;
}

/* ---- motion keys ---- */
static const char *const motion_names[HZ_MESHGEN_MOTION_COUNT] = { "sway", "rotate", "cross", "collapse", "rot180" };

const char *hz_meshgen_motion_name(hz_meshgen_motion_kind_t k)
{
    return (unsigned)k < HZ_MESHGEN_MOTION_COUNT ? motion_names[k] : "unknown";
}

bool hz_meshgen_motion_parse(const char *s, hz_meshgen_motion_kind_t *out)
{
    for (int i = 0; s && i < HZ_MESHGEN_MOTION_COUNT; i++) {
        const char *a = s, *b = motion_names[i];
        while (*a && *a == *b)
            a++, b++;
        if (*a == *b) {
            *out = (hz_meshgen_motion_kind_t)i;
            return true;
        }
    }
    return false;
}

static void rot_y(const float *p, hz_vec3_t c, float ang, float *o)
{
    float sn, cs;
    hz_sincosf(ang, &sn, &cs);
    const float x = p[0] - c.x, z = p[2] - c.z;
    o[0] = c.x + cs * x + sn * z;
    o[1] = p[1];
    o[2] = c.z - sn * x + cs * z;
}

hz_status_t hz_meshgen_motion(hz_accel_geom_t *g, const float *pos, hz_meshgen_motion_kind_t kind, uint32_t keys,
                              hz_vec3_t center, float size, float turns, hz_arena_t *a)
{
    if (!(keys == 2u || keys == 3u || keys == 5u || keys == 9u) || (unsigned)kind >= HZ_MESHGEN_MOTION_COUNT ||
        (kind == HZ_MESHGEN_ROT180 && keys != 2u))
        return HZ_E_INVALID_ARG;
    const hz_arena_mark_t m0 = hz_arena_mark(a);
    const size_t n = (size_t)g->vertex_count;
    for (uint32_t k = 0; k < keys; k++) {
        float *d = hz_arena_alloc_array(a, 4u * n + 4u, sizeof(float), 16);
        if (!d) {
            hz_arena_reset(a, m0);
            return HZ_E_NO_MEMORY;
        }
        const float t = (float)k / (float)(keys - 1u);
        for (size_t i = 0; i < n; i++) {
            const float *p = pos + 4u * i;
            float *o = d + 4u * i;
            switch (kind) {
            case HZ_MESHGEN_SWAY: {
                const float ph = (p[0] + p[2]) * (6.2831853f / (size > 0.0f ? size : 1.0f)) + 6.2831853f * t;
                const float h = p[1] - center.y;
                const float amp = size * 0.02f * (h > 0.0f ? h / (size > 0.0f ? size : 1.0f) + 0.25f : 0.25f);
                o[0] = p[0] + amp * hz_sinf(ph);
                o[1] = p[1] + amp * 0.3f * hz_cosf(ph * 1.7f);
                o[2] = p[2] + amp * hz_cosf(ph);
                break;
            }
            case HZ_MESHGEN_ROTATE: rot_y(p, center, 6.2831853f * turns * t, o); break;
            case HZ_MESHGEN_ROT180: rot_y(p, center, 3.14159265f * t, o); break;
            case HZ_MESHGEN_CROSS: {
                const float s = (i & 1u) ? 0.5f : -0.5f;
                o[0] = p[0] + s * size * (2.0f * t - 1.0f);
                o[1] = p[1], o[2] = p[2];
                break;
            }
            default: /* COLLAPSE */
                o[0] = hz_accel_lerp_key(p[0], center.x, t);
                o[1] = hz_accel_lerp_key(p[1], center.y, t);
                o[2] = hz_accel_lerp_key(p[2], center.z, t);
                break;
            }
            o[3] = 0.0f;
        }
        g->pos_keys[k] = d;
    }
    for (uint32_t k = keys; k < HZ_ACCEL_MAX_TIME_KEYS; k++)
        g->pos_keys[k] = 0;
    g->time_keys = keys;
    g->pos = g->pos_keys[keys & 1u ? (keys - 1u) / 2u : 0u];
    return HZ_OK;
}

hz_vec3_t hz_meshgen_tri_point(const hz_accel_geom_t *g, uint32_t t, float time, float b1, float b2)
{
    uint32_t seg = 0;
    float f = 0.0f;
    const bool motion = g->time_keys >= 2u;
    if (motion)
        hz_accel_time_segment(time, g->time_keys, &seg, &f);
    const float w[3] = { 1.0f - b1 - b2, b1, b2 };
    float p[3] = { 0.0f, 0.0f, 0.0f };
    for (int v = 0; v < 3; v++)
        for (int c = 0; c < 3; c++) {
            const size_t vi = 4u * (size_t)g->tri[3u * (size_t)t + (uint32_t)v] + (size_t)c;
            p[c] += w[v] * (motion ? hz_accel_lerp_key(g->pos_keys[seg][vi], g->pos_keys[seg + 1u][vi], f) : g->pos[vi]);
        }
    return hz_v3(p[0], p[1], p[2]);
}
