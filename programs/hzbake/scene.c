/* The baker's in-memory scene: objects appended by the importers, vertex welding, sidecar overrides, and the
 * final .hzb image (see bake.h and scene.h). */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hz/accel.h" /* HZ_ACCEL_MAX_COORD */
#include "hz/hzb_write.h"

#define HZ_BAKE_PI 3.14159265358979323846

void hz_bake_scene_init(hz_bake_scene_t *s, const char *model)
{
    memset(s, 0, sizeof *s);
    hz_bake_vec_init(&s->pos, 16);
    hz_bake_vec_init(&s->nrm, 16);
    hz_bake_vec_init(&s->uv, 8);
    hz_bake_vec_init(&s->tri, 12);
    hz_bake_vec_init(&s->info, 4);
    hz_bake_vec_init(&s->mats, sizeof(hz_bake_material_t));
    hz_bake_vec_init(&s->texs, sizeof(hz_bake_texture_t));
    hz_bake_vec_init(&s->texels, 4);
    hz_bake_vec_init(&s->objs, sizeof(hz_bake_object_t));
    hz_bake_vec_init(&s->rkeys, sizeof(hz_hzb_rigid_key_t));
    hz_bake_vec_init(&s->vkeys, 16);
    hz_bake_vec_init(&s->vkey_nrm, 16);
    hz_bake_vec_init(&s->lights, sizeof(hz_hzb_light_t));
    hz_bake_vec_init(&s->cams, sizeof(hz_hzb_camera_key_t));
    hz_bake_vec_init(&s->joints, sizeof(hz_hzb_joint_t));
    hz_bake_vec_init(&s->joint_src, sizeof(const void *));
    hz_bake_vec_init(&s->binds, sizeof(hz_hzb_skin_bind_t));
    hz_bake_vec_init(&s->weights, sizeof(hz_hzb_skin_weight_t));
    snprintf(s->model, sizeof s->model, "%s", model);
}

void hz_bake_scene_free(hz_bake_scene_t *s)
{
    hz_bake_vec_t *all[] = { &s->pos,    &s->nrm,  &s->uv,    &s->tri,   &s->info,     &s->mats,   &s->texs,
                             &s->texels, &s->objs, &s->rkeys, &s->vkeys, &s->vkey_nrm, &s->lights, &s->cams,
                             &s->joints, &s->joint_src, &s->binds, &s->weights };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        hz_bake_vec_free(all[i]);
}

uint32_t hz_bake_object_begin(hz_bake_scene_t *s, const char *name, const char *mesh_name)
{
    hz_bake_object_t *o = hz_bake_vec_push(&s->objs, 1);
    snprintf(o->name, sizeof o->name, "%s", name);
    snprintf(o->mesh_name, sizeof o->mesh_name, "%s", mesh_name ? mesh_name : "");
    hz_bake_set_name(o->o.name, name);
    o->o.first_triangle = (uint32_t)s->tri.len;
    o->o.first_vertex = (uint32_t)s->pos.len;
    return (uint32_t)s->objs.len - 1;
}

uint32_t hz_bake_add_vertices(hz_bake_scene_t *s, uint32_t n)
{
    uint32_t first = (uint32_t)s->pos.len;
    hz_bake_vec_push(&s->pos, n);
    hz_bake_vec_push(&s->nrm, n);
    hz_bake_vec_push(&s->uv, n);
    return first;
}

void hz_bake_add_triangle(hz_bake_scene_t *s, uint32_t a, uint32_t b, uint32_t c, uint32_t mat)
{
    uint32_t *t = hz_bake_vec_push(&s->tri, 1);
    t[0] = a, t[1] = b, t[2] = c;
    *(uint32_t *)hz_bake_vec_push(&s->info, 1) = (mat & 0xffffu) | (uint32_t)(s->objs.len - 1) << 16;
}

/* ---- welding ---- */

typedef struct wkey {
    float f[8]; /* position xyz, normal xyz, uv */
} wkey_t;

static void make_key(const hz_bake_scene_t *s, uint32_t v, wkey_t *k)
{
    const float *p = HZ_BAKE_AT(s->pos, float, (size_t)v * 4), *n = HZ_BAKE_AT(s->nrm, float, (size_t)v * 4);
    const float *uv = HZ_BAKE_AT(s->uv, float, (size_t)v * 2);
    float f[8] = { p[0], p[1], p[2], n[0], n[1], n[2], uv[0], uv[1] };
    for (int i = 0; i < 8; i++)
        k->f[i] = f[i] == 0.0f ? 0.0f : f[i]; /* -0 == +0 */
}

static uint64_t key_hash(const wkey_t *k)
{
    uint64_t h = 1469598103934665603ull;
    const uint8_t *b = (const uint8_t *)k->f;
    for (size_t i = 0; i < sizeof k->f; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h ^ (h >> 29);
}

/* Merges vertices [first, end) with identical keys; rewrites triangles [tfirst, tend). */
static void weld(hz_bake_scene_t *s, uint32_t first, uint32_t tfirst)
{
    uint32_t n = (uint32_t)s->pos.len - first;
    if (n < 2)
        return;
    size_t cap = 16;
    while (cap < (size_t)n * 2)
        cap *= 2;
    uint32_t *table = hz_bake_xmalloc(cap * sizeof(uint32_t)); /* new index + 1, 0 = empty */
    memset(table, 0, cap * sizeof(uint32_t));
    wkey_t *keys = hz_bake_xmalloc((size_t)n * sizeof(wkey_t)); /* keys of the kept vertices, by new index */
    uint32_t *remap = hz_bake_xmalloc((size_t)n * sizeof(uint32_t));
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        wkey_t k;
        make_key(s, first + i, &k);
        size_t h = (size_t)key_hash(&k) & (cap - 1);
        for (;;) {
            if (table[h] == 0) {
                table[h] = kept + 1;
                keys[kept] = k;
                /* Move the vertex down to its new slot (new index <= old index, so nothing is overwritten
                 * before it is read). */
                if (kept != i) {
                    memcpy(HZ_BAKE_AT(s->pos, float, (size_t)(first + kept) * 4),
                           HZ_BAKE_AT(s->pos, float, (size_t)(first + i) * 4), 16);
                    memcpy(HZ_BAKE_AT(s->nrm, float, (size_t)(first + kept) * 4),
                           HZ_BAKE_AT(s->nrm, float, (size_t)(first + i) * 4), 16);
                    memcpy(HZ_BAKE_AT(s->uv, float, (size_t)(first + kept) * 2),
                           HZ_BAKE_AT(s->uv, float, (size_t)(first + i) * 2), 8);
                }
                remap[i] = kept++;
                break;
            }
            if (!memcmp(&keys[table[h] - 1], &k, sizeof k)) {
                remap[i] = table[h] - 1;
                break;
            }
            h = (h + 1) & (cap - 1);
        }
    }
    uint32_t *t = HZ_BAKE_AT(s->tri, uint32_t, (size_t)tfirst * 3);
    size_t nt = s->tri.len - tfirst;
    for (size_t i = 0; i < nt * 3; i++)
        t[i] = first + remap[t[i] - first];
    s->pos.len = s->nrm.len = s->uv.len = first + kept;
    free(table);
    free(keys);
    free(remap);
}

static int finite_n(const float *f, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(f[i]))
            return 0;
    return 1;
}

hz_status_t hz_bake_object_end(hz_bake_scene_t *s, int has_normals, int weld_vertices, hz_error_t *err)
{
    hz_bake_object_t *o = HZ_BAKE_AT(s->objs, hz_bake_object_t, s->objs.len - 1);
    uint32_t first = o->o.first_vertex, n = (uint32_t)s->pos.len - first;
    for (uint32_t i = 0; i < n; i++) {
        float *p = HZ_BAKE_AT(s->pos, float, (size_t)(first + i) * 4);
        float *nr = HZ_BAKE_AT(s->nrm, float, (size_t)(first + i) * 4);
        const float *uv = HZ_BAKE_AT(s->uv, float, (size_t)(first + i) * 2);
        if (!finite_n(p, 3)) {
            char xyz[3][24];
            return hz_bake_err(err, HZ_E_RANGE, "%s: object '%s': vertex %u has a non-finite position (%s %s %s)",
                               s->model, o->name, i, hz_bake_num(xyz[0], 24, p[0]), hz_bake_num(xyz[1], 24, p[1]),
                               hz_bake_num(xyz[2], 24, p[2]));
        }
        if (!finite_n(uv, 2))
            return hz_bake_err(err, HZ_E_RANGE, "%s: object '%s': vertex %u has a non-finite texture coordinate",
                               s->model, o->name, i);
        p[3] = 0.0f;
        nr[3] = 0.0f;
        if (!has_normals) {
            nr[0] = nr[1] = nr[2] = 0.0f;
            continue;
        }
        double len = sqrt((double)nr[0] * nr[0] + (double)nr[1] * nr[1] + (double)nr[2] * nr[2]);
        if (!isfinite(len) || len < 1e-20) {
            nr[0] = nr[1] = nr[2] = 0.0f; /* repaired from the faces in hz_bake_scene_finish */
        } else {
            for (int c = 0; c < 3; c++)
                nr[c] = (float)(nr[c] / len);
        }
    }
    o->has_normals = has_normals;
    if (weld_vertices)
        weld(s, first, o->o.first_triangle);
    o = HZ_BAKE_AT(s->objs, hz_bake_object_t, s->objs.len - 1);
    o->o.vertex_count = (uint32_t)s->pos.len - first;
    o->o.triangle_count = (uint32_t)s->tri.len - o->o.first_triangle;
    if (s->pos.len > UINT32_MAX || s->tri.len > UINT32_MAX)
        return hz_bake_err(err, HZ_E_OVERFLOW, "%s: more than 2^32 vertices or triangles", s->model);
    return HZ_OK;
}

/* ---- finishing ---- */

/* Area-weighted vertex normals from the faces, for vertices whose normal is zero (missing or degenerate in the
 * source); a vertex of degenerate faces only gets +Y. */
static void repair_normals(hz_bake_scene_t *s)
{
    size_t nv = s->pos.len;
    uint8_t *fix = hz_bake_xcalloc(nv, 1);
    size_t need = 0;
    for (size_t v = 0; v < nv; v++) {
        const float *n = HZ_BAKE_AT(s->nrm, float, v * 4);
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f)
            fix[v] = 1, need++;
    }
    if (need) {
        double *acc = hz_bake_xcalloc(nv * 3, sizeof(double));
        for (size_t t = 0; t < s->tri.len; t++) {
            const uint32_t *i = HZ_BAKE_AT(s->tri, uint32_t, t * 3);
            if (!fix[i[0]] && !fix[i[1]] && !fix[i[2]])
                continue;
            const float *a = HZ_BAKE_AT(s->pos, float, (size_t)i[0] * 4),
                        *b = HZ_BAKE_AT(s->pos, float, (size_t)i[1] * 4),
                        *c = HZ_BAKE_AT(s->pos, float, (size_t)i[2] * 4);
            double e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
            double fn[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0] };
            for (int k = 0; k < 3; k++)
                if (fix[i[k]])
                    for (int c3 = 0; c3 < 3; c3++)
                        acc[(size_t)i[k] * 3 + c3] += fn[c3];
        }
        for (size_t v = 0; v < nv; v++) {
            if (!fix[v])
                continue;
            double *a = acc + v * 3;
            double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            float *n = HZ_BAKE_AT(s->nrm, float, v * 4);
            if (len > 0 && isfinite(len))
                n[0] = (float)(a[0] / len), n[1] = (float)(a[1] / len), n[2] = (float)(a[2] / len);
            else
                n[0] = 0.0f, n[1] = 1.0f, n[2] = 0.0f;
        }
        free(acc);
    }
    free(fix);
}

static void object_center(const hz_bake_scene_t *s, const hz_bake_object_t *o, float c[3])
{
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t v = 0; v < o->o.vertex_count; v++) {
        const float *p = HZ_BAKE_AT(s->pos, float, (size_t)(o->o.first_vertex + v) * 4);
        for (int k = 0; k < 3; k++)
            lo[k] = fminf(lo[k], p[k]), hi[k] = fmaxf(hi[k], p[k]);
    }
    for (int k = 0; k < 3; k++)
        c[k] = o->o.vertex_count ? 0.5f * (lo[k] + hi[k]) : 0.0f;
}

static void apply_material(hz_bake_material_t *m, const hz_bake_sc_material_t *sm)
{
    if (sm->set & HZ_BAKE_SC_COLOR)
        memcpy(m->m.base_color, sm->color, sizeof sm->color);
    if (sm->set & HZ_BAKE_SC_ALPHA)
        m->m.alpha = sm->alpha;
    if (sm->set & HZ_BAKE_SC_ALPHA_CUTOFF)
        m->m.alpha_cutoff = sm->alpha_cutoff;
    if (sm->set & HZ_BAKE_SC_MIRROR)
        m->m.mirror = sm->mirror;
    if (sm->set & HZ_BAKE_SC_ALPHA_MODE) {
        m->m.alpha_mode = sm->alpha_mode;
        /* Cutouts and blending read the base texture's alpha unless the model named an alpha map. */
        if (sm->alpha_mode != HZ_ALPHA_OPAQUE && m->m.alpha_texture < 0)
            m->m.alpha_texture = m->m.base_texture;
    }
}

static void quat_axis_angle(const float axis[3], float deg, float q[4])
{
    double len = sqrt((double)axis[0] * axis[0] + (double)axis[1] * axis[1] + (double)axis[2] * axis[2]);
    double half = 0.5 * deg * HZ_BAKE_PI / 180.0, sn = sin(half) / len;
    q[0] = (float)(axis[0] * sn), q[1] = (float)(axis[1] * sn), q[2] = (float)(axis[2] * sn), q[3] = (float)cos(half);
}

static hz_status_t apply_object(hz_bake_scene_t *s, hz_bake_object_t *o, const hz_bake_sc_object_t *so,
                                const char *sidecar, hz_error_t *err)
{
    if (o->o.motion != HZ_MOTION_NONE)
        return hz_bake_err(err, HZ_E_FORMAT,
                           "%s:%d: object '%s' is already animated by the model; a sidecar motion "
                           "cannot replace it",
                           sidecar, so->line, o->name);
    hz_hzb_object_t *ob = &o->o;
    memset(ob->params, 0, sizeof ob->params);
    ob->motion = so->motion;
    if (so->motion == HZ_MOTION_SPIN) {
        float c[3];
        if (so->pivot_center)
            object_center(s, o, c);
        else
            memcpy(c, so->pivot, sizeof c);
        double len = sqrt((double)so->axis[0] * so->axis[0] + (double)so->axis[1] * so->axis[1] +
                          (double)so->axis[2] * so->axis[2]);
        for (int k = 0; k < 3; k++) {
            ob->params[k] = c[k];
            ob->params[3 + k] = (float)(so->axis[k] / len);
        }
        ob->params[6] = (float)(so->speed_deg * HZ_BAKE_PI / 180.0);
    } else if (so->motion == HZ_MOTION_OSCILLATE) {
        for (int k = 0; k < 3; k++)
            ob->params[k] = so->amplitude[k];
        ob->params[3] = so->frequency;
        ob->params[4] = (float)(so->phase_deg * HZ_BAKE_PI / 180.0);
    } else if (so->motion == HZ_MOTION_SWAY) {
        /* Centre (pivot or the object's centre), amplitude, angular frequency and the root radius: the nearest
         * vertex's distance from the centre, so strands are rooted where the surface begins (hz/hzb.h). */
        float c[3];
        if (so->pivot_center)
            object_center(s, o, c);
        else
            memcpy(c, so->pivot, sizeof c);
        double r0 = INFINITY;
        for (uint32_t v = 0; v < o->o.vertex_count; v++) {
            const float *p = HZ_BAKE_AT(s->pos, float, (size_t)(o->o.first_vertex + v) * 4);
            double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
            r0 = fmin(r0, sqrt(dx * dx + dy * dy + dz * dz));
        }
        for (int k = 0; k < 3; k++) {
            ob->params[k] = c[k];
            ob->params[3 + k] = so->amplitude[k];
        }
        ob->params[6] = (float)(2.0 * HZ_BAKE_PI * so->frequency);
        ob->params[7] = o->o.vertex_count ? (float)r0 : 0.0f;
    } else if (so->motion == HZ_MOTION_RIGID) {
        /* Object space = the baked world positions: keys move the object from where the model put it. */
        ob->key_first = (uint32_t)s->rkeys.len;
        ob->key_count = (uint32_t)so->keys.len;
        for (size_t i = 0; i < so->keys.len; i++) {
            const hz_bake_sc_key_t *k = HZ_BAKE_AT(so->keys, hz_bake_sc_key_t, i);
            hz_hzb_rigid_key_t *r = hz_bake_vec_push(&s->rkeys, 1);
            r->time = k->time;
            memcpy(r->translation, k->translate, sizeof r->translation);
            quat_axis_angle(k->axis, k->angle_deg, r->rotation);
            memcpy(r->scale, k->scale, sizeof r->scale);
        }
    }
    return HZ_OK;
}

static void trim_ext(const char *path, char *out, size_t size)
{
    snprintf(out, size, "%s", hz_bake_basename(path));
    if (hz_bake_ends_with(out, ".gz"))
        out[strlen(out) - 3] = 0;
    char *dot = strrchr(out, '.');
    if (dot && dot != out)
        *dot = 0;
}

static int beyond(const float *p, int n)
{
    for (int i = 0; i < n; i++)
        if (!(fabsf(p[i]) <= HZ_ACCEL_MAX_COORD))
            return 1;
    return 0;
}

/* Coordinates the renderer cannot trace (beyond +-2^36) would make an image the runtime loader refuses; say
 * which object, vertex, frame or bone instead. */
static hz_status_t check_coordinate_range(const hz_bake_scene_t *s, hz_error_t *err)
{
    for (size_t i = 0; i < s->objs.len; i++) {
        const hz_bake_object_t *o = HZ_BAKE_AT(s->objs, hz_bake_object_t, i);
        for (uint32_t v = 0; v < o->o.vertex_count; v++) {
            const float *p = HZ_BAKE_AT(s->pos, float, (size_t)(o->o.first_vertex + v) * 4);
            if (beyond(p, 3))
                return hz_bake_err(err, HZ_E_RANGE,
                                   "%s: object '%s': vertex %u at (%g %g %g) lies beyond +-2^36 (%.3g), the largest "
                                   "coordinate hzrt traces",
                                   s->model, o->name, v, (double)p[0], (double)p[1], (double)p[2],
                                   (double)HZ_ACCEL_MAX_COORD);
        }
        if (o->o.motion == HZ_MOTION_VERTEX)
            for (uint64_t k = 0; k < (uint64_t)o->o.key_count * o->o.vertex_count; k++) {
                const float *p = HZ_BAKE_AT(s->vkeys, float, (size_t)(o->o.key_first + k) * 4);
                if (beyond(p, 3))
                    return hz_bake_err(err, HZ_E_RANGE,
                                       "%s: object '%s': vertex %llu in animation frame %llu moves to (%g %g %g), "
                                       "beyond +-2^36 (%.3g), the largest coordinate hzrt traces",
                                       s->model, o->name, (unsigned long long)(k % o->o.vertex_count),
                                       (unsigned long long)(k / o->o.vertex_count), (double)p[0], (double)p[1],
                                       (double)p[2], (double)HZ_ACCEL_MAX_COORD);
            }
    }
    for (size_t i = 0; i < s->binds.len; i++) {
        const hz_hzb_skin_bind_t *b = HZ_BAKE_AT(s->binds, hz_hzb_skin_bind_t, i);
        if (beyond(b->inv_bind, 12))
            return hz_bake_err(err, HZ_E_RANGE,
                               "%s: bone %zu (joint '%s') has an offset matrix element beyond +-2^36 (%.3g)", s->model,
                               i, (const char *)HZ_BAKE_AT(s->joints, hz_hzb_joint_t, b->joint)->name,
                               (double)HZ_ACCEL_MAX_COORD);
    }
    return HZ_OK;
}

hz_status_t hz_bake_scene_finish(hz_bake_scene_t *s, hz_bake_sidecar_t *sc, hz_bake_image_t *img, hz_error_t *err)
{
    memset(img, 0, sizeof *img);
    if (s->tri.len == 0)
        return hz_bake_err(err, HZ_E_FORMAT, "%s: the model has no triangles to bake", s->model);
    if (s->pos.len < 3) /* the runtime refuses such a scene: every triangle is a point or a line */
        return hz_bake_err(err, HZ_E_FORMAT, "%s: the model's %zu triangles have only %zu distinct vertices", s->model,
                           s->tri.len, s->pos.len);
    if (s->objs.len > 65536)
        return hz_bake_err(err, HZ_E_RANGE, "%s: %zu objects, a .hzb holds at most 65536", s->model, s->objs.len);
    if (s->mats.len == 0) {
        hz_bake_material_t *m = hz_bake_vec_push(&s->mats, 1);
        snprintf(m->name, sizeof m->name, "default");
        hz_bake_set_name(m->m.name, m->name);
        m->m.base_color[0] = m->m.base_color[1] = m->m.base_color[2] = 0.8f;
        m->m.alpha = 1.0f;
        m->m.alpha_cutoff = 0.5f;
        m->m.base_texture = m->m.alpha_texture = -1;
    }
    if (s->mats.len > 65536)
        return hz_bake_err(err, HZ_E_RANGE, "%s: %zu materials, a .hzb holds at most 65536", s->model, s->mats.len);

    /* Sidecar: materials (every matching section in file order), then objects (the last matching section). */
    for (size_t i = 0; i < s->mats.len; i++) {
        hz_bake_material_t *m = HZ_BAKE_AT(s->mats, hz_bake_material_t, i);
        for (size_t j = 0; j < sc->materials.len; j++) {
            hz_bake_sc_material_t *sm = HZ_BAKE_AT(sc->materials, hz_bake_sc_material_t, j);
            if (hz_bake_sidecar_match(sm->pattern, m->name)) {
                apply_material(m, sm);
                sm->matched = 1;
            }
        }
    }
    for (size_t i = 0; i < s->objs.len; i++) {
        hz_bake_object_t *o = HZ_BAKE_AT(s->objs, hz_bake_object_t, i);
        hz_bake_sc_object_t *last = NULL;
        /* Objects also answer to their material's name: OBJ groups are often misplaced (CornellBox's tall box
         * sits in group "shortBox"), the material names what the geometry is. */
        const char *mat_name = NULL;
        if (o->o.triangle_count) {
            uint32_t mi = *HZ_BAKE_AT(s->info, uint32_t, o->o.first_triangle) & 0xffffu;
            if (mi < s->mats.len)
                mat_name = HZ_BAKE_AT(s->mats, hz_bake_material_t, mi)->name;
        }
        for (size_t j = 0; j < sc->objects.len; j++) {
            hz_bake_sc_object_t *so = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, j);
            if (hz_bake_sidecar_match(so->pattern, o->name) ||
                (o->mesh_name[0] && hz_bake_sidecar_match(so->pattern, o->mesh_name)) ||
                (mat_name && hz_bake_sidecar_match(so->pattern, mat_name))) {
                if (!so->matched)
                    so->matched = 1;
                last = so;
            }
        }
        if (last)
            last->matched = 2; /* it decides this object's motion */
        if (last && (last->motion != HZ_MOTION_NONE || o->o.motion != HZ_MOTION_NONE)) {
            hz_status_t st = apply_object(s, o, last, sc->path, err);
            if (st)
                return st;
        }
    }
    hz_status_t st = hz_bake_sidecar_unmatched(sc, s, err);
    if (st)
        return st;
    /* An object section that matches objects but decides none (a later section matches each of them) does
     * nothing: say which section takes over. */
    for (size_t j = 0; j < sc->objects.len; j++) {
        const hz_bake_sc_object_t *so = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, j);
        if (so->matched != 1)
            continue;
        for (size_t i = 0; i < s->objs.len; i++) {
            const hz_bake_object_t *o = HZ_BAKE_AT(s->objs, hz_bake_object_t, i);
            const hz_bake_sc_object_t *later = NULL;
            for (size_t k = j + 1; k < sc->objects.len; k++) {
                const hz_bake_sc_object_t *sk = HZ_BAKE_AT(sc->objects, hz_bake_sc_object_t, k);
                if (hz_bake_sidecar_match(sk->pattern, o->name) ||
                    (o->mesh_name[0] && hz_bake_sidecar_match(sk->pattern, o->mesh_name)))
                    later = sk;
            }
            if (later && (hz_bake_sidecar_match(so->pattern, o->name) ||
                          (o->mesh_name[0] && hz_bake_sidecar_match(so->pattern, o->mesh_name))))
                return hz_bake_err(err, HZ_E_FORMAT, "%s:%d: [object \"%s\"] does nothing: every object it matches "
                                   "takes a later section (object '%s': [object \"%s\"], line %d)", sc->path, so->line,
                                   so->pattern, o->name, later->pattern, later->line);
        }
        return hz_bake_err(err, HZ_E_FORMAT, "%s:%d: [object \"%s\"] does nothing: a later section takes every object "
                           "it matches", sc->path, so->line, so->pattern);
    }

    /* Textures need UVs. */
    if (!s->any_uv)
        for (size_t i = 0; i < s->mats.len; i++) {
            hz_bake_material_t *m = HZ_BAKE_AT(s->mats, hz_bake_material_t, i);
            if (m->m.base_texture >= 0 || m->m.alpha_texture >= 0) {
                hz_bake_warn("%s: material '%s' has a texture but the model has no texture coordinates; it uses its "
                             "colour instead",
                             s->model, m->name);
                if (m->m.base_texture >= 0)
                    memcpy(m->m.base_color, m->source_color, sizeof m->source_color);
                m->m.base_texture = m->m.alpha_texture = -1;
                if (m->m.alpha_mode == HZ_ALPHA_MASK)
                    m->m.alpha_mode = HZ_ALPHA_OPAQUE;
            }
        }
    for (size_t i = 0; i < s->mats.len; i++) {
        hz_bake_material_t *m = HZ_BAKE_AT(s->mats, hz_bake_material_t, i);
        if (m->m.alpha_mode == HZ_ALPHA_MASK && m->m.alpha_texture < 0 && m->m.alpha >= m->m.alpha_cutoff)
            hz_bake_warn("%s: material '%s' is a cutout without an alpha texture: nothing is cut", s->model, m->name);
    }

    int normals = sc->normals != HZ_BAKE_NORMALS_NONE;
    if (normals) {
        for (size_t i = 0; i < s->objs.len; i++) {
            hz_bake_object_t *o = HZ_BAKE_AT(s->objs, hz_bake_object_t, i);
            if (!o->has_normals)
                for (uint32_t v = 0; v < o->o.vertex_count; v++)
                    memset(HZ_BAKE_AT(s->nrm, float, (size_t)(o->o.first_vertex + v) * 4), 0, 16);
        }
        repair_normals(s);
    }

    st = check_coordinate_range(s, err);
    if (st)
        return st;

    /* Lights and camera. */
    for (size_t i = 0; i < sc->lights.len; i++)
        *(hz_hzb_light_t *)hz_bake_vec_push(&s->lights, 1) = *HZ_BAKE_AT(sc->lights, hz_hzb_light_t, i);
    for (size_t i = 0; i < sc->cameras.len; i++)
        *(hz_hzb_camera_key_t *)hz_bake_vec_push(&s->cams, 1) = HZ_BAKE_AT(sc->cameras, hz_bake_sc_camera_t, i)->key;
    if (s->lights.len == 0)
        hz_bake_warn("%s: the scene has no lights (add 'light = position X Y Z color R G B' to its sidecar)", s->model);

    hz_hzb_source_t src;
    memset(&src, 0, sizeof src);
    char name[256];
    if (sc->set & HZ_BAKE_SC_NAME)
        snprintf(name, sizeof name, "%s", sc->name);
    else
        trim_ext(s->model, name, sizeof name);
    uint8_t name_field[HZ_HZB_NAME_BYTES];
    hz_bake_set_name(name_field, name);
    memcpy(img->name, name_field, sizeof name_field);
    src.name = (const char *)img->name;
    src.vertex_count = (uint32_t)s->pos.len;
    src.positions = s->pos.data;
    src.normals = normals ? s->nrm.data : NULL;
    src.uvs = s->any_uv ? s->uv.data : NULL;
    src.triangle_count = (uint32_t)s->tri.len;
    src.triangles = s->tri.data;
    src.tri_info = s->info.data;
    /* Materials and textures: the .hzb structs are the first member of the baker's records. */
    hz_hzb_material_t *mats = hz_bake_xcalloc(s->mats.len, sizeof *mats);
    for (size_t i = 0; i < s->mats.len; i++)
        mats[i] = HZ_BAKE_AT(s->mats, hz_bake_material_t, i)->m;
    hz_hzb_texture_t *texs = hz_bake_xcalloc(s->texs.len, sizeof *texs);
    for (size_t i = 0; i < s->texs.len; i++)
        texs[i] = HZ_BAKE_AT(s->texs, hz_bake_texture_t, i)->t;
    hz_hzb_object_t *objs = hz_bake_xcalloc(s->objs.len, sizeof *objs);
    for (size_t i = 0; i < s->objs.len; i++)
        objs[i] = HZ_BAKE_AT(s->objs, hz_bake_object_t, i)->o;
    src.material_count = (uint32_t)s->mats.len;
    src.materials = mats;
    src.texture_count = (uint32_t)s->texs.len;
    src.textures = texs;
    src.texel_count = (uint32_t)s->texels.len;
    src.texels = s->texels.data;
    src.object_count = (uint32_t)s->objs.len;
    src.objects = objs;
    src.rigid_key_count = (uint32_t)s->rkeys.len;
    src.rigid_keys = s->rkeys.data;
    src.vertex_key_count = (uint32_t)s->vkeys.len;
    src.vertex_keys = s->vkeys.data;
    src.vertex_key_normals = normals && s->vkey_nrm.len == s->vkeys.len ? s->vkey_nrm.data : NULL;
    src.light_count = (uint32_t)s->lights.len;
    src.lights = s->lights.data;
    src.camera_key_count = (uint32_t)s->cams.len;
    src.camera_keys = s->cams.data;
    if (s->binds.len) {
        if (s->weights.len < s->pos.len)
            hz_bake_vec_push(&s->weights, s->pos.len - s->weights.len); /* zero: vertices of unskinned objects */
        src.joint_count = (uint32_t)s->joints.len;
        src.joints = s->joints.data;
        src.skin_bind_count = (uint32_t)s->binds.len;
        src.skin_binds = s->binds.data;
        src.skin_weights = s->weights.data;
    }
    src.duration = (sc->set & HZ_BAKE_SC_DURATION) ? sc->duration : s->anim_duration;
    memcpy(src.background, sc->background, sizeof src.background);
    memcpy(src.ambient, sc->ambient, sizeof src.ambient);
    src.camera_fov_y = (sc->set & HZ_BAKE_SC_FOV) ? sc->fov_deg * (float)(HZ_BAKE_PI / 180.0) : 0.0f;
    src.camera_flags = sc->camera_loop ? 1u : 0u;
    src.extra_features = s->extra_features;

    size_t size = hz_hzb_write_size(&src);
    if (size == 0)
        st = hz_bake_err(err, HZ_E_OVERFLOW, "%s: the scene is too large for one .hzb image", s->model);
    else {
        void *buf = NULL;
        if (posix_memalign(&buf, HZ_HZB_ALIGN, size) != 0)
            st = hz_bake_err(err, HZ_E_NO_MEMORY, "%s: cannot allocate %zu bytes for the image", s->model, size);
        else {
            hz_error_t werr;
            st = hz_hzb_write(&src, buf, size, &img->size, &werr);
            if (st) {
                hz_bake_err(err, st, "%s: %s", s->model, werr.msg);
                free(buf);
            } else {
                img->data = buf;
            }
        }
    }
    free(mats);
    free(texs);
    free(objs);
    return st;
}
