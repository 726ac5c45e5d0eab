/* Object animation and the camera path (see hz/scene.h, hz/hzb.h for the motion model). */
#include "hz/skin.h"
#include "scene_internal.h"

float hz_scene_wrap_time(float t, float period)
{
    if (!(period > 0.0f) || !hz_isfinitef(t))
        return hz_isfinitef(t) ? t : 0.0f;
    float w = t - period * hz_floorf(t / period);
    return w >= period || w < 0.0f ? 0.0f : w; /* rounding can land exactly on period */
}

hz_mat4_t hz_quat_matrix(const float q[4])
{
    float x = q[0], y = q[1], z = q[2], w = q[3];
    hz_mat4_t m = hz_mat4_identity();
    m.m[0] = 1 - 2 * (y * y + z * z);
    m.m[1] = 2 * (x * y + z * w);
    m.m[2] = 2 * (x * z - y * w);
    m.m[4] = 2 * (x * y - z * w);
    m.m[5] = 1 - 2 * (x * x + z * z);
    m.m[6] = 2 * (y * z + x * w);
    m.m[8] = 2 * (x * z + y * w);
    m.m[9] = 2 * (y * z - x * w);
    m.m[10] = 1 - 2 * (x * x + y * y);
    return m;
}

static hz_mat4_t trs(const float t[3], const float q[4], const float s[3])
{
    hz_mat4_t r = hz_quat_matrix(q);
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            r.m[c * 4 + row] *= s[c];
    r.m[12] = t[0];
    r.m[13] = t[1];
    r.m[14] = t[2];
    return r;
}

hz_mat4_t hz_rigid_keys_matrix(const hz_hzb_rigid_key_t *k, uint32_t n, float t)
{
    if (n == 1 || t <= k[0].time)
        return trs(k[0].translation, k[0].rotation, k[0].scale);
    if (t >= k[n - 1].time)
        return trs(k[n - 1].translation, k[n - 1].rotation, k[n - 1].scale);
    /* Last key with time <= t (keys are strictly increasing: validated at load). */
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (k[mid].time <= t)
            lo = mid;
        else
            hi = mid;
    }
    const hz_hzb_rigid_key_t *a = &k[lo], *b = &k[hi];
    float w = (t - a->time) / (b->time - a->time);
    float tr[3], sc[3], q[4];
    for (int i = 0; i < 3; i++) {
        tr[i] = a->translation[i] + (b->translation[i] - a->translation[i]) * w;
        sc[i] = a->scale[i] + (b->scale[i] - a->scale[i]) * w;
    }
    /* Normalised lerp on the shorter arc: monotonic, cheap, and close to slerp for dense glTF keys. */
    float d = a->rotation[0] * b->rotation[0] + a->rotation[1] * b->rotation[1] + a->rotation[2] * b->rotation[2] +
              a->rotation[3] * b->rotation[3];
    float sgn = d < 0.0f ? -1.0f : 1.0f;
    float len2 = 0.0f;
    for (int i = 0; i < 4; i++) {
        q[i] = a->rotation[i] * (1.0f - w) + sgn * b->rotation[i] * w;
        len2 += q[i] * q[i];
    }
    float inv = len2 > 0.0f ? 1.0f / hz_sqrtf(len2) : 1.0f;
    for (int i = 0; i < 4; i++)
        q[i] *= inv;
    return trs(tr, q, sc);
}

int hz_object_matrix(const hz_hzb_object_t *o, const hz_hzb_rigid_key_t *keys, float t, hz_mat4_t *m)
{
    switch (o->motion) {
    case HZ_MOTION_RIGID:
        *m = hz_rigid_keys_matrix(keys + o->key_first, o->key_count, t);
        return 1;
    case HZ_MOTION_SPIN: {
        hz_vec3_t pivot = hz_v3(o->params[0], o->params[1], o->params[2]);
        hz_mat4_t to = hz_mat4_translate(pivot);
        hz_mat4_t from = hz_mat4_translate(hz_v3_neg(pivot));
        hz_mat4_t rot = hz_mat4_rotate(hz_v3(o->params[3], o->params[4], o->params[5]), o->params[6] * t);
        hz_mat4_t tmp = hz_mat4_mul(&rot, &from);
        *m = hz_mat4_mul(&to, &tmp);
        return 1;
    }
    case HZ_MOTION_OSCILLATE: {
        float s = hz_sinf(2.0f * HZ_PI * o->params[3] * t + o->params[4]);
        *m = hz_mat4_translate(hz_v3(o->params[0] * s, o->params[1] * s, o->params[2] * s));
        return 1;
    }
    default:
        *m = hz_mat4_identity();
        return 0;
    }
}

void hz_object_vertex_frames(const hz_hzb_object_t *o, float t, uint32_t *f0, uint32_t *f1, float *w)
{
    uint32_t n = o->key_count;
    float f = t * o->key_rate;
    if (!(f >= 0.0f) || !hz_isfinitef(f))
        f = 0.0f;
    /* Wrap in float before converting: f can exceed the uint32 range over long runs. */
    float period = (float)n;
    f = hz_scene_wrap_time(f, period);
    uint32_t i = (uint32_t)f;
    if (i >= n)
        i = n - 1;
    *f0 = i;
    *f1 = i + 1 < n ? i + 1 : 0;
    *w = n > 1 ? f - (float)i : 0.0f;
}

/* HZ_MOTION_SWAY (hz/hzb.h): rest position plus a h^2 sin(w t + pi (u.x + u.y + u.z)); rest normals. */
static void sway_object(const hz_scene_t *s, const hz_hzb_object_t *o, float t, float *pos, float *nrm)
{
    const float *c = o->params, *a = o->params + 3, w = o->params[6], r0 = o->params[7];
    for (uint32_t i = o->first_vertex; i < o->first_vertex + o->vertex_count; i++) {
        const float *r = s->rest_pos + (size_t)i * 4;
        float dx = r[0] - c[0], dy = r[1] - c[1], dz = r[2] - c[2];
        float len = hz_sqrtf(dx * dx + dy * dy + dz * dz), h = len > r0 ? len - r0 : 0.0f;
        float u = len > 0.0f ? (dx + dy + dz) / len : 0.0f;
        float k = h * h * hz_sinf(w * t + HZ_PI * u);
        float *dst = pos + (size_t)i * 4;
        dst[0] = r[0] + a[0] * k, dst[1] = r[1] + a[1] * k, dst[2] = r[2] + a[2] * k, dst[3] = 0.0f;
        if (nrm)
            hz_memcpy(nrm + (size_t)i * 4, s->rest_nrm + (size_t)i * 4, 4 * sizeof(float));
    }
}

/* Writes the state of object `o` at time t into pos/nrm (full-size arrays indexed by vertex; nrm may be NULL). */
static void animate_object(const hz_scene_t *s, const hz_hzb_object_t *o, float t, float *pos, float *nrm)
{
    uint32_t v0 = o->first_vertex, vn = o->vertex_count;
    if (o->motion == HZ_MOTION_VERTEX) {
        uint32_t f0, f1;
        float w;
        hz_object_vertex_frames(o, t, &f0, &f1, &w);
        const float *a = s->vertex_keys + ((size_t)o->key_first + (size_t)f0 * vn) * 4;
        const float *b = s->vertex_keys + ((size_t)o->key_first + (size_t)f1 * vn) * 4;
        for (uint32_t i = 0; i < vn; i++)
            for (int c = 0; c < 4; c++)
                pos[(size_t)(v0 + i) * 4 + c] = a[i * 4 + c] + (b[i * 4 + c] - a[i * 4 + c]) * w;
        if (nrm && s->vertex_key_normals) {
            const float *na = s->vertex_key_normals + ((size_t)o->key_first + (size_t)f0 * vn) * 4;
            const float *nb = s->vertex_key_normals + ((size_t)o->key_first + (size_t)f1 * vn) * 4;
            for (uint32_t i = 0; i < vn; i++) {
                hz_vec3_t n = hz_v3_lerp(hz_v3(na[i * 4], na[i * 4 + 1], na[i * 4 + 2]),
                                         hz_v3(nb[i * 4], nb[i * 4 + 1], nb[i * 4 + 2]), w);
                n = hz_v3_normalize(n);
                float *dst = nrm + (size_t)(v0 + i) * 4;
                dst[0] = n.x, dst[1] = n.y, dst[2] = n.z, dst[3] = 0.0f;
            }
        }
        return;
    }
    if (o->motion == HZ_MOTION_SWAY) {
        sway_object(s, o, t, pos, nrm);
        return;
    }
    if (o->motion == HZ_MOTION_SKIN) {
        /* skin_mats is the scene's scratch (planned for the largest object): the pose is a pure function of t,
         * the matrices only pass through it. */
        hz_skin_matrices(o, s->skin_binds, s->joints, s->rigid_keys, t, s->skin_mats);
        hz_skin_blend(s->skin_mats, s->skin_weights + v0, s->rest_pos + (size_t)v0 * 4,
                      nrm ? s->rest_nrm + (size_t)v0 * 4 : NULL, vn, pos + (size_t)v0 * 4,
                      nrm ? nrm + (size_t)v0 * 4 : NULL);
        return;
    }
    hz_mat4_t m, inv, nm;
    if (!hz_object_matrix(o, s->rigid_keys, t, &m))
        return;
    /* Normals transform by the inverse transpose; a degenerate (zero-scale) key keeps the rest normals. */
    int have_nm = nrm && hz_mat4_inverse(&m, &inv) == HZ_OK;
    if (have_nm)
        nm = hz_mat4_transpose(&inv);
    for (uint32_t i = 0; i < vn; i++) {
        const float *r = s->rest_pos + (size_t)(v0 + i) * 4;
        hz_vec3_t p = hz_mat4_mul_point(&m, hz_v3(r[0], r[1], r[2]));
        float *dst = pos + (size_t)(v0 + i) * 4;
        dst[0] = p.x, dst[1] = p.y, dst[2] = p.z, dst[3] = 0.0f;
        if (nrm) {
            const float *rn = s->rest_nrm + (size_t)(v0 + i) * 4;
            hz_vec3_t n = hz_v3(rn[0], rn[1], rn[2]);
            if (have_nm)
                n = hz_v3_normalize(hz_mat4_mul_dir(&nm, n));
            float *dn = nrm + (size_t)(v0 + i) * 4;
            dn[0] = n.x, dn[1] = n.y, dn[2] = n.z, dn[3] = 0.0f;
        }
    }
}

/* Time of object o at scene time t, as float seconds small enough to keep float's precision: inside the scene's
 * loop when it has one; otherwise inside the object's own period (spin: one turn, oscillate: one cycle, vertex
 * keys: the key range), or clamped after the last rigid key (the pose stays there). */
static float object_time(const hz_scene_t *s, const hz_hzb_object_t *o, hz_time_ns_t t, float duration)
{
    const hz_hzb_rigid_key_t *keys = s->rigid_keys;
    if (duration > 0.0f)
        return hz_time_wrap_s(t, duration);
    switch (o->motion) {
    case HZ_MOTION_SPIN:
    case HZ_MOTION_SWAY: /* both: angular frequency in params[6] */
        return o->params[6] != 0.0f ? hz_time_wrap_s(t, 2.0 * HZ_PI / hz_absf(o->params[6])) : 0.0f;
    case HZ_MOTION_OSCILLATE:
        return o->params[3] != 0.0f ? hz_time_wrap_s(t, 1.0 / hz_absf(o->params[3])) : 0.0f;
    case HZ_MOTION_VERTEX:
        return o->key_rate > 0.0f ? hz_time_wrap_s(t, (double)o->key_count / o->key_rate) : 0.0f;
    case HZ_MOTION_RIGID: {
        float last = keys[o->key_first + o->key_count - 1].time;
        return t >= hz_time_from_s(last) ? last : hz_time_wrap_s(t, 0.0);
    }
    case HZ_MOTION_SKIN: {
        float last = hz_skin_last_key_time(o, s->skin_binds, s->joints, keys);
        return t >= hz_time_from_s(last) ? last : hz_time_wrap_s(t, 0.0);
    }
    default:
        return 0.0f;
    }
}

void hz_scene_pose_ns(hz_scene_t *s, hz_time_ns_t t)
{
    for (uint32_t i = 0; i < s->object_count; i++)
        if (s->objects[i].motion != HZ_MOTION_NONE)
            animate_object(s, &s->objects[i], object_time(s, &s->objects[i], t, s->header->duration),
                           s->pos, s->nrm);
    s->time = hz_time_wrap_s(t, s->header->duration);
    s->time_ns = t;
}

void hz_scene_pose(hz_scene_t *s, float t)
{
    hz_scene_pose_ns(s, hz_time_from_s(t));
}

void hz_scene_pose_at_ns(const hz_scene_t *s, hz_time_ns_t t, float dt, float *pos, float *nrm)
{
    hz_time_ns_t at = t + hz_time_from_s(dt);
    for (uint32_t i = 0; i < s->object_count; i++)
        if (s->objects[i].motion != HZ_MOTION_NONE)
            animate_object(s, &s->objects[i], object_time(s, &s->objects[i], at, s->header->duration),
                           pos, s->nrm ? nrm : NULL);
}

void hz_scene_object_matrix_at_ns(const hz_scene_t *s, uint32_t object, hz_time_ns_t t, float dt, float m[12])
{
    const hz_hzb_object_t *o = &s->objects[object];
    hz_mat4_t a;
    hz_object_matrix(o, s->rigid_keys, object_time(s, o, t + hz_time_from_s(dt), s->header->duration), &a);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++)
            m[4 * r + c] = a.m[4 * c + r]; /* hz_mat4_t is column-major */
}

void hz_scene_pose_at(const hz_scene_t *s, float t, float dt, float *pos, float *nrm)
{
    hz_scene_pose_at_ns(s, hz_time_from_s(t), dt, pos, nrm);
}

void hz_scene_animate(hz_scene_t *s, float t)
{
    hz_scene_animate_ns(s, hz_time_from_s(t));
}

void hz_scene_animate_ns(hz_scene_t *s, hz_time_ns_t t)
{
    if (!s->prev_pos)
        return; /* nothing moves */
    for (uint32_t i = 0; i < s->object_count; i++) {
        const hz_hzb_object_t *o = &s->objects[i];
        if (o->motion == HZ_MOTION_NONE)
            continue;
        size_t off = (size_t)o->first_vertex * 4, n = (size_t)o->vertex_count * 4;
        hz_memcpy(s->prev_pos + off, s->pos + off, n * sizeof(float));
        if (s->nrm)
            hz_memcpy(s->prev_nrm + off, s->nrm + off, n * sizeof(float));
    }
    hz_scene_pose_ns(s, t);
}

/* Uniform Catmull-Rom through p1..p2 with neighbours p0, p3. */
static hz_vec3_t catmull_rom(hz_vec3_t p0, hz_vec3_t p1, hz_vec3_t p2, hz_vec3_t p3, float u)
{
    float u2 = u * u, u3 = u2 * u;
    float a = -0.5f * u3 + u2 - 0.5f * u;
    float b = 1.5f * u3 - 2.5f * u2 + 1.0f;
    float c = -1.5f * u3 + 2.0f * u2 + 0.5f * u;
    float d = 0.5f * u3 - 0.5f * u2;
    return hz_v3(a * p0.x + b * p1.x + c * p2.x + d * p3.x, a * p0.y + b * p1.y + c * p2.y + d * p3.y,
                 a * p0.z + b * p1.z + c * p2.z + d * p3.z);
}

static hz_vec3_t v3_of(const float *f)
{
    return hz_v3(f[0], f[1], f[2]);
}

hz_camera_t hz_scene_camera(const hz_scene_t *s, float t)
{
    return hz_scene_camera_ns(s, hz_time_from_s(t));
}

hz_camera_t hz_scene_camera_ns(const hz_scene_t *s, hz_time_ns_t t_ns)
{
    hz_camera_t cam;
    uint32_t n = s->camera_key_count;
    const hz_hzb_camera_key_t *k = s->camera_keys;
    if (n == 0) {
        /* Frame the bounds from the front, slightly above. */
        const hz_hzb_header_t *h = s->header;
        hz_vec3_t lo = v3_of(h->bounds_min), hi = v3_of(h->bounds_max);
        hz_vec3_t c = hz_v3_scale(hz_v3_add(lo, hi), 0.5f);
        float radius = 0.5f * hz_v3_len(hz_v3_sub(hi, lo));
        cam.fov_y = h->camera_fov_y > 0.0f ? h->camera_fov_y : HZ_PI / 3.0f;
        float dist = radius / hz_tanf(0.5f * cam.fov_y) * 1.05f;
        if (!(dist > 0.0f))
            dist = 1.0f;
        cam.target = c;
        cam.eye = hz_v3_add(c, hz_v3_scale(hz_v3_normalize(hz_v3(0.0f, 0.35f, 1.0f)), dist));
        cam.up = hz_v3(0.0f, 1.0f, 0.0f);
        return cam;
    }
    int loop = (s->header->camera_flags & 1u) && s->header->duration > 0.0f;
    /* In the loop, or held at the last key after it (a float of the time since the start would lose precision
     * over long runs). */
    float t = loop ? hz_time_wrap_s(t_ns, s->header->duration)
                   : t_ns >= hz_time_from_s(k[n - 1].time) ? k[n - 1].time : hz_time_wrap_s(t_ns, 0.0);
    if (n == 1 || t <= k[0].time || (!loop && t >= k[n - 1].time)) {
        const hz_hzb_camera_key_t *e = (n == 1 || t <= k[0].time) ? &k[0] : &k[n - 1];
        cam.eye = v3_of(e->eye), cam.target = v3_of(e->target), cam.up = v3_of(e->up), cam.fov_y = e->fov_y;
        return cam;
    }
    uint32_t i1, i2;
    float u;
    if (t >= k[n - 1].time) {
        /* Looping: the segment from the last key back to the first, ending at time duration. */
        i1 = n - 1, i2 = 0;
        float span = s->header->duration - k[n - 1].time + k[0].time;
        u = span > 0.0f ? (t - k[n - 1].time) / span : 0.0f;
    } else {
        i1 = 0;
        while (i1 + 1 < n && k[i1 + 1].time <= t)
            i1++;
        i2 = i1 + 1;
        u = (t - k[i1].time) / (k[i2].time - k[i1].time);
    }
    uint32_t i0 = i1 > 0 ? i1 - 1 : (loop ? n - 1 : 0);
    uint32_t i3 = i2 + 1 < n ? i2 + 1 : (loop ? (i2 + 1) % n : i2);
    cam.eye = catmull_rom(v3_of(k[i0].eye), v3_of(k[i1].eye), v3_of(k[i2].eye), v3_of(k[i3].eye), u);
    cam.target = catmull_rom(v3_of(k[i0].target), v3_of(k[i1].target), v3_of(k[i2].target),
                             v3_of(k[i3].target), u);
    cam.up = hz_v3_normalize(hz_v3_lerp(v3_of(k[i1].up), v3_of(k[i2].up), u));
    cam.fov_y = k[i1].fov_y + (k[i2].fov_y - k[i1].fov_y) * u;
    return cam;
}
