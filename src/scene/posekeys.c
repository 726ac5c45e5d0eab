/* The scene's pose at a shutter interval's key times (see hz/posekeys.h). */
#include "hz/posekeys.h"

#include "scene_internal.h"

/* Segments n rigid keys need over interval_s seconds: the fastest rotation between two keys (angle <=
 * pi * |qa - qb| on the shorter arc: the chord bounds the arc, no trigonometry needed) and the shortest key
 * interval (one knot per segment at most). */
static float key_segments(const hz_hzb_rigid_key_t *k, uint32_t n, float interval_s)
{
    const float per = HZ_POSEKEYS_SEGMENT_RAD;
    float need = 0.0f;
    for (uint32_t i = 0; i + 1 < n; i++) {
        float dt = k[i + 1].time - k[i].time, d = 0.0f, dm = 0.0f;
        for (int c = 0; c < 4; c++) {
            float a = k[i].rotation[c] - k[i + 1].rotation[c], b = k[i].rotation[c] + k[i + 1].rotation[c];
            d += a * a, dm += b * b;
        }
        float angle = HZ_PI * hz_sqrtf(hz_minf(d, dm));
        if (dt > 0.0f)
            need = hz_maxf(need, hz_maxf(angle / dt * interval_s / per, interval_s / dt));
    }
    return need;
}

/* Segments object o needs over interval_s seconds (at least 1; may exceed 8, the caller caps). */
static float object_segments(const hz_scene_t *s, const hz_hzb_object_t *o, float interval_s)
{
    const float per = HZ_POSEKEYS_SEGMENT_RAD;
    switch (o->motion) {
    case HZ_MOTION_SPIN:
        return hz_absf(o->params[6]) * interval_s / per;
    case HZ_MOTION_OSCILLATE:
        return 2.0f * HZ_PI * hz_absf(o->params[3]) * interval_s / per;
    case HZ_MOTION_SWAY:
        return hz_absf(o->params[6]) * interval_s / per;
    case HZ_MOTION_VERTEX:
        return o->key_rate * interval_s;
    case HZ_MOTION_RIGID:
        return key_segments(s->rigid_keys + o->key_first, o->key_count, interval_s);
    case HZ_MOTION_SKIN: {
        /* The fastest joint's (joints shared by many binds are visited once per bind: cheap, at plan time). */
        float need = 0.0f;
        for (uint32_t i = 0; i < o->key_count; i++) {
            const hz_hzb_joint_t *j = &s->joints[s->skin_binds[o->key_first + i].joint];
            need = hz_maxf(need, key_segments(s->rigid_keys + j->key_first, j->key_count, interval_s));
        }
        return need;
    }
    default:
        return 0.0f;
    }
}

uint32_t hz_posekeys_count(const hz_scene_t *s, float interval_s)
{
    if (!s->prev_pos)
        return 1; /* nothing moves */
    float need = 1.0f;
    for (uint32_t i = 0; i < s->object_count; i++)
        need = hz_maxf(need, object_segments(s, &s->objects[i], hz_absf(interval_s)));
    uint32_t n = 1;
    while (n < 8 && (float)n < need)
        n *= 2;
    return n + 1;
}

static bool valid_count(uint32_t k)
{
    return k == 2 || k == 3 || k == 5 || k == 9;
}

size_t hz_posekeys_bytes(const hz_scene_t *s, uint32_t count)
{
    if (count < 2)
        return 0;
    size_t one = hz_align_up((size_t)s->vertex_count * 16u, 64) + 64;
    return (size_t)count * one * (s->nrm ? 2u : 1u);
}

static bool rigid_motion(uint32_t m)
{
    return m == HZ_MOTION_RIGID || m == HZ_MOTION_SPIN || m == HZ_MOTION_OSCILLATE;
}

static bool same_motion(const hz_hzb_object_t *a, const hz_hzb_object_t *b)
{
    if (a->motion != b->motion || a->key_first != b->key_first || a->key_count != b->key_count)
        return false;
    for (int i = 0; i < 8; i++)
        if (a->params[i] != b->params[i])
            return false;
    return true;
}

/* The rigid instances (see the contract): consecutive objects with the same rigid motion, or none at all. */
static void find_instances(hz_posekeys_t *k, const hz_scene_t *s)
{
    uint32_t n = 0;
    bool rest_moves = false, over = false;
    for (uint32_t i = 0; i < s->object_count; i++) {
        const hz_hzb_object_t *o = &s->objects[i];
        if (!rigid_motion(o->motion) || !o->triangle_count) {
            rest_moves = rest_moves || (o->motion != HZ_MOTION_NONE && o->triangle_count);
            continue;
        }
        hz_accel_instance_t *last = n ? &k->inst[n - 1u] : NULL;
        if (last && same_motion(&s->objects[k->inst_object[n - 1u]], o) &&
            last->tri_first + last->tri_count == o->first_triangle) {
            last->tri_count += o->triangle_count;
            continue;
        }
        if (n == HZ_ACCEL_MAX_INSTANCES) {
            over = true;
            break;
        }
        k->inst[n].tri_first = o->first_triangle;
        k->inst[n].tri_count = o->triangle_count;
        k->inst[n].obj_pos = s->rest_pos;
        for (uint32_t key = 0; key < HZ_ACCEL_MAX_TIME_KEYS; key++)
            k->inst[n].xform[key] = key < k->count ? k->xform[n][key] : NULL;
        k->inst_object[n] = i;
        n++;
    }
    k->instance_count = over ? 0u : n;
    k->static_rest = !over && !rest_moves;
}

hz_status_t hz_posekeys_init(hz_posekeys_t *k, const hz_scene_t *s, uint32_t count, hz_arena_t *arena,
                             hz_error_t *err)
{
    hz_memset(k, 0, sizeof *k);
    if (!valid_count(count))
        return hz_error_set(err, HZ_E_INVALID_ARG, "pose keys: %u time keys (must be 2, 3, 5 or 9)", count);
    size_t need = hz_posekeys_bytes(s, count), have = hz_arena_available(arena, 64);
    if (need > have)
        return hz_error_set(err, HZ_E_NO_MEMORY, "arena '%s': %u pose keys of %u vertices need %zu bytes, has %zu",
                            arena->name, count, s->vertex_count, need, have);
    hz_arena_mark_t mark = hz_arena_mark(arena);
    size_t bytes = (size_t)s->vertex_count * 16u;
    for (uint32_t i = 0; i < count; i++) {
        k->pos[i] = hz_arena_alloc(arena, bytes ? bytes : 16u, 64);
        k->nrm[i] = s->nrm ? hz_arena_alloc(arena, bytes ? bytes : 16u, 64) : NULL;
        if (!k->pos[i] || (s->nrm && !k->nrm[i])) {
            hz_arena_reset(arena, mark);
            hz_memset(k, 0, sizeof *k);
            return hz_arena_error(arena, err);
        }
        hz_memcpy(k->pos[i], s->pos, bytes);
        if (s->nrm)
            hz_memcpy(k->nrm[i], s->nrm, bytes);
    }
    k->count = count;
    k->vertex_count = s->vertex_count;
    find_instances(k, s);
    return HZ_OK;
}

void hz_posekeys_eval_ns(hz_posekeys_t *k, const hz_scene_t *s, hz_time_ns_t t, float lo, float hi)
{
    for (uint32_t i = 0; i < k->count; i++) {
        /* The ends exactly at lo and hi; in between lo + (hi - lo) i / (K - 1). */
        float dt = i + 1 == k->count ? hi : lo + (hi - lo) * ((float)i / (float)(k->count - 1u));
        hz_scene_pose_at_ns(s, t, dt, k->pos[i], k->nrm[i]);
        for (uint32_t j = 0; j < k->instance_count; j++)
            hz_scene_object_matrix_at_ns(s, k->inst_object[j], t, dt, k->xform[j][i]);
    }
    k->time = t, k->lo = lo, k->hi = hi;
    k->valid = true;
}

void hz_posekeys_eval(hz_posekeys_t *k, const hz_scene_t *s, float t, float lo, float hi)
{
    hz_posekeys_eval_ns(k, s, hz_time_from_s(t), lo, hi);
}

void hz_posekeys_geom(const hz_posekeys_t *k, hz_accel_geom_t *g)
{
    g->time_keys = k->count;
    for (uint32_t i = 0; i < HZ_ACCEL_MAX_TIME_KEYS; i++)
        g->pos_keys[i] = i < k->count ? k->pos[i] : NULL;
    g->pos = k->pos[(k->count - 1u) / 2u];
    g->instance_count = k->instance_count;
    g->instances = k->instance_count ? k->inst : NULL;
    g->static_rest = k->static_rest;
}
