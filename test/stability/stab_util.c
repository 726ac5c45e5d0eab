/* Shared pieces of the stability cases (see stab_util.h). */
#include "stab_util.h"

#include <stdio.h>
#include <stdlib.h>

#include "hz/hash.h"

#include "hz/hzb_write.h"
#include "hz/meshgen.h"
#include "blur_setup.h"
#include "render_run.h"

static void *grow(void *p, uint32_t *cap, uint32_t need, size_t elem)
{
    if (need <= *cap)
        return p;
    uint32_t c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void *q = realloc(p, (size_t)c * elem);
    if (!q)
        abort();
    *cap = c;
    return q;
}

void su_begin(su_scene_t *b)
{
    memset(b, 0, sizeof *b);
    b->fov_y = 1.0f;
    b->ambient[0] = b->ambient[1] = b->ambient[2] = 0.1f;
}

uint32_t su_material_alpha(su_scene_t *b, float r, float g, float bl, float alpha, uint32_t mode)
{
    hz_hzb_material_t *m = &b->mat[b->nmat];
    memset(m, 0, sizeof *m);
    m->base_color[0] = r, m->base_color[1] = g, m->base_color[2] = bl;
    m->alpha = alpha;
    m->alpha_cutoff = 0.5f;
    m->alpha_mode = mode;
    m->base_texture = m->alpha_texture = -1;
    return b->nmat++;
}

uint32_t su_material(su_scene_t *b, float r, float g, float bl)
{
    return su_material_alpha(b, r, g, bl, 1.0f, HZ_ALPHA_OPAQUE);
}

uint32_t su_vertex(su_scene_t *b, float x, float y, float z)
{
    b->pos = grow(b->pos, &b->cap_v, b->nv + 1, 4 * sizeof(float));
    float *p = b->pos + 4 * (size_t)b->nv;
    p[0] = x, p[1] = y, p[2] = z, p[3] = 0.0f;
    b->uv = grow(b->uv, &b->cap_uv, b->nv + 1, 2 * sizeof(float));
    b->uv[2 * (size_t)b->nv] = b->uv[2 * (size_t)b->nv + 1] = 0.0f;
    return b->nv++;
}

void su_uv(su_scene_t *b, uint32_t v, float u, float t)
{
    b->uv[2 * (size_t)v] = u, b->uv[2 * (size_t)v + 1] = t;
}

uint32_t su_texture(su_scene_t *b, const uint8_t *rgba, uint32_t w, uint32_t h, uint32_t levels)
{
    hz_hzb_texture_t *t = &b->tex[b->ntex];
    memset(t, 0, sizeof *t);
    t->width = w, t->height = h, t->levels = levels, t->first_texel = b->ntexel;
    snprintf((char *)t->name, sizeof t->name, "stability%u", b->ntex);
    uint32_t lw = w, lh = h, pw = w, ph = h; /* this level's size and the previous one's */
    for (uint32_t l = 0; l < levels; l++) {
        b->texels = grow(b->texels, &b->cap_texel, b->ntexel + lw * lh, 4);
        uint8_t *dst = b->texels + 4 * (size_t)b->ntexel;
        const uint8_t *src = dst - 4 * (size_t)pw * ph;
        if (l == 0)
            memcpy(dst, rgba, 4 * (size_t)w * h);
        for (uint32_t y = 0; l && y < lh; y++)
            for (uint32_t x = 0; x < lw; x++) {
                const uint32_t x0 = 2 * x < pw ? 2 * x : pw - 1, y0 = 2 * y < ph ? 2 * y : ph - 1;
                const uint32_t x1 = x0 + 1 < pw ? x0 + 1 : x0, y1 = y0 + 1 < ph ? y0 + 1 : y0;
                for (int c = 0; c < 4; c++) {
                    const uint32_t sum = src[4 * ((size_t)y0 * pw + x0) + c] + src[4 * ((size_t)y0 * pw + x1) + c] +
                                         src[4 * ((size_t)y1 * pw + x0) + c] + src[4 * ((size_t)y1 * pw + x1) + c];
                    dst[4 * ((size_t)y * lw + x) + c] = (uint8_t)((sum + 2) / 4);
                }
            }
        for (size_t i = 0; i < (size_t)lw * lh; i++)
            if (dst[4 * i + 3] < 255)
                t->flags |= 1u;
        b->ntexel += lw * lh;
        t->texel_count += lw * lh;
        pw = lw, ph = lh;
        lw = lw > 1 ? lw / 2 : 1, lh = lh > 1 ? lh / 2 : 1;
    }
    return b->ntex++;
}

void su_tri(su_scene_t *b, uint32_t v0, uint32_t v1, uint32_t v2, uint32_t mat)
{
    uint32_t cap = b->cap_t;
    b->tri = grow(b->tri, &cap, b->nt + 1, 3 * sizeof(uint32_t));
    b->info = grow(b->info, &b->cap_t, b->nt + 1, sizeof(uint32_t));
    b->tri[3 * (size_t)b->nt] = v0, b->tri[3 * (size_t)b->nt + 1] = v1, b->tri[3 * (size_t)b->nt + 2] = v2;
    b->info[b->nt] = mat | (b->nobj << 16);
    b->nt++;
}

void su_quad(su_scene_t *b, const float p0[3], const float p1[3], const float p2[3], const float p3[3],
             uint32_t mat)
{
    uint32_t a = su_vertex(b, p0[0], p0[1], p0[2]), c = su_vertex(b, p1[0], p1[1], p1[2]);
    uint32_t d = su_vertex(b, p2[0], p2[1], p2[2]), e = su_vertex(b, p3[0], p3[1], p3[2]);
    su_tri(b, a, c, d, mat);
    su_tri(b, a, d, e, mat);
}

hz_hzb_object_t *su_object(su_scene_t *b)
{
    hz_hzb_object_t *o = &b->obj[b->nobj++];
    memset(o, 0, sizeof *o);
    o->first_triangle = b->obj_first_t, o->triangle_count = b->nt - b->obj_first_t;
    o->first_vertex = b->obj_first_v, o->vertex_count = b->nv - b->obj_first_v;
    b->obj_first_t = b->nt, b->obj_first_v = b->nv;
    return o;
}

void su_light(su_scene_t *b, float x, float y, float z, float power)
{
    hz_hzb_light_t *l = &b->light[b->nlight++];
    memset(l, 0, sizeof *l);
    l->position[0] = x, l->position[1] = y, l->position[2] = z;
    l->color[0] = l->color[1] = l->color[2] = power;
}

void su_camera(su_scene_t *b, float t, const float eye[3], const float target[3], float fov_y)
{
    hz_hzb_camera_key_t *k = &b->cam[b->ncam++];
    memset(k, 0, sizeof *k);
    k->time = t;
    memcpy(k->eye, eye, sizeof k->eye);
    memcpy(k->target, target, sizeof k->target);
    k->up[1] = 1.0f;
    k->fov_y = fov_y;
}

hz_status_t su_image(const su_scene_t *b, const void **img, size_t *size, hz_error_t *err)
{
    hz_hzb_source_t src;
    memset(&src, 0, sizeof src);
    src.name = "stability";
    src.vertex_count = b->nv, src.positions = b->pos;
    src.triangle_count = b->nt, src.triangles = b->tri, src.tri_info = b->info;
    src.material_count = b->nmat, src.materials = b->mat;
    if (b->ntex) {
        src.uvs = b->uv;
        src.texture_count = b->ntex, src.textures = b->tex;
        src.texel_count = b->ntexel, src.texels = b->texels;
    }
    src.object_count = b->nobj, src.objects = b->obj;
    src.light_count = b->nlight, src.lights = b->nlight ? b->light : NULL;
    src.camera_key_count = b->ncam, src.camera_keys = b->ncam ? b->cam : NULL;
    src.rigid_key_count = b->nrkey, src.rigid_keys = b->nrkey ? b->rkey : NULL;
    src.vertex_key_count = b->nvkeys, src.vertex_keys = b->vkeys;
    src.duration = b->duration;
    memcpy(src.background, b->background, sizeof src.background);
    memcpy(src.ambient, b->ambient, sizeof src.ambient);
    src.camera_fov_y = b->fov_y;
    src.camera_flags = b->camera_flags;
    size_t n = hz_hzb_write_size(&src);
    hz_pools_t *p = hz_pools_get();
    void *buf = hz_arena_alloc(&p->scene, n, 64);
    if (!buf)
        return hz_arena_error(&p->scene, err);
    hz_status_t s = hz_hzb_write(&src, buf, n, size, err);
    *img = buf;
    return s;
}

hz_status_t su_load(const su_scene_t *b, hz_scene_t *scene, hz_error_t *err)
{
    const void *img;
    size_t n;
    hz_status_t s = su_image(b, &img, &n, err);
    if (s != HZ_OK)
        return s;
    return hz_scene_load(scene, img, n, &hz_pools_get()->scene, err);
}

/* The pools' marks (for su_render_close) and the scene. */
static hz_status_t open_scene(su_render_t *s, const su_scene_t *b, const hz_render_opts_t *o, hz_error_t *err)
{
    memset(s, 0, sizeof *s);
    s->opts = *o;
    hz_pools_t *p = hz_pools_get();
    s->marks[0] = hz_arena_mark(&p->scene), s->marks[1] = hz_arena_mark(&p->accel);
    s->marks[2] = hz_arena_mark(&p->frame), s->marks[3] = hz_arena_mark(&p->thread[0]);
    return su_load(b, &s->scene, err);
}

hz_status_t su_render_open(su_render_t *s, const su_scene_t *b, const hz_render_opts_t *o, hz_error_t *err)
{
    hz_status_t st = open_scene(s, b, o, err);
    if (st != HZ_OK)
        return st;
    hz_pools_t *p = hz_pools_get();
    hz_accel_geom_t g;
    if ((st = hz_accel_geom_from_scene(&g, &s->scene, &p->accel, err)) != HZ_OK ||
        (st = hz_accel_build_native(&s->accel, &g, NULL, &p->accel, err)) != HZ_OK)
        return st;
    return hz_render_create(&s->r, &s->scene, s->accel, o, &p->frame, p->thread, 1, err);
}

void su_render_close(su_render_t *s)
{
    hz_pools_t *p = hz_pools_get();
    hz_arena_reset(&p->thread[0], s->marks[3]);
    hz_arena_reset(&p->frame, s->marks[2]);
    hz_arena_reset(&p->accel, s->marks[1]);
    hz_arena_reset(&p->scene, s->marks[0]);
}

hz_status_t su_render_open_blur(su_render_t *s, const su_scene_t *b, const hz_render_opts_t *o,
                                hz_accel_blur_t blur, hz_error_t *err)
{
    hz_status_t st = open_scene(s, b, o, err);
    if (st != HZ_OK)
        return st;
    hz_pools_t *p = hz_pools_get();
    if ((st = hz_blur_build(&s->scene, &s->opts, HZ_ACCEL_NATIVE, blur, p, &s->keys, &s->accel, err)) != HZ_OK)
        return st;
    return hz_render_create(&s->r, &s->scene, s->accel, &s->opts, &p->frame, p->thread, 1, err);
}

static void su_frame_stats(su_render_t *s);

hz_status_t su_render_frame_ns(su_render_t *s, uint64_t index, hz_time_ns_t t, hz_error_t *err)
{
    hz_status_t st = hz_render_run_frame_ns(s->r, index, t, err);
    su_frame_stats(s);
    return st;
}

hz_status_t su_render_frame(su_render_t *s, uint64_t index, float t, hz_error_t *err)
{
    hz_status_t st = hz_render_run_frame(s->r, index, t, err);
    su_frame_stats(s);
    return st;
}

static void su_frame_stats(su_render_t *s)
{
    hz_render_stats_t last;
    hz_render_frame_stats(s->r, &last, NULL);
    s->nonfinite_stat += last.nonfinite;
    s->queue_full += last.queue_full;
    s->layer_cap += last.layer_cap;
}

void su_render_check(stab_result_t *r, su_render_t *s)
{
    const hz_image_t *img = hz_render_output(s->r);
    size_t n = hz_image_pixels(img);
    uint64_t before = r->nonfinite;
    stab_count_nonfinite(r, img->rgb, 3 * n);
    if (r->nonfinite != before)
        stab_note(r, "%llu non-finite output values", (unsigned long long)(r->nonfinite - before));
    for (size_t i = 0; i < 3 * n; i++)
        if (img->rgb[i] < 0.0f) {
            stab_failf(r, __FILE__, __LINE__, "negative radiance %g at value %zu", (double)img->rgb[i], i);
            break;
        }
    const hz_gbuffer_t *gb = hz_render_gbuffer(s->r);
    if (gb->mv && stab_count_nonfinite(r, gb->mv, 2 * n))
        stab_note(r, "non-finite motion vectors");
    if (gb->mv_reflect && stab_count_nonfinite(r, gb->mv_reflect, 2 * n))
        stab_note(r, "non-finite reflected motion vectors");
    if (gb->normal && stab_count_nonfinite(r, gb->normal, 3 * n))
        stab_note(r, "non-finite normals");
    if (gb->depth) {
        uint64_t bad = 0;
        for (size_t i = 0; i < n; i++)
            bad += !(gb->depth[i] >= 0.0f); /* NaN or negative; +inf marks a miss */
        if (bad)
            stab_note(r, "%llu depth values NaN or negative (mode %s)", (unsigned long long)bad,
                      hz_render_mode_name(s->opts.mode));
        r->nonfinite += bad;
    }
    r->nonfinite += s->nonfinite_stat;
    if (s->nonfinite_stat)
        stab_note(r, "renderer replaced %llu non-finite values", (unsigned long long)s->nonfinite_stat);
    if (s->queue_full)
        stab_failf(r, __FILE__, __LINE__, "%llu rays dropped: queue full", (unsigned long long)s->queue_full);
}

hz_status_t su_accel(hz_accel_t **a, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt,
                     hz_error_t *err)
{
    hz_pools_t *p = hz_pools_get();
    float *pp = hz_arena_alloc(&p->scene, (size_t)nv * 4 * sizeof(float) + 16, 64);
    uint32_t *tt = hz_arena_alloc(&p->scene, (size_t)nt * 3 * sizeof(uint32_t) + 4, 64);
    if (!pp || !tt)
        return hz_arena_error(&p->scene, err);
    memcpy(pp, pos, (size_t)nv * 4 * sizeof(float));
    memcpy(tt, tri, (size_t)nt * 3 * sizeof(uint32_t));
    hz_accel_geom_t g = { .pos = pp, .vertex_count = nv, .tri = tt, .tri_count = nt };
    return hz_accel_build_native(a, &g, NULL, &p->accel, err);
}

void su_ray(hz_rayhit_t *rh, double ox, double oy, double oz, double dx, double dy, double dz)
{
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = (float)ox, rh->ray.org_y = (float)oy, rh->ray.org_z = (float)oz;
    rh->ray.dir_x = (float)dx, rh->ray.dir_y = (float)dy, rh->ray.dir_z = (float)dz;
    rh->ray.tnear = 0.0f;
    rh->ray.tfar = INFINITY;
    rh->ray.mask = 0xFFFFFFFFu;
    rh->hit.geom_id = rh->hit.prim_id = rh->hit.inst_id[0] = HZ_ACCEL_INVALID_ID;
}

su_ref_t su_ref_intersect(const float *pos, const uint32_t *tri, uint32_t nt, const hz_rayhit_t *rh)
{
    su_ref_t best = { -1, -1.0, 0.0, INFINITY };
    double o[3] = { rh->ray.org_x, rh->ray.org_y, rh->ray.org_z };
    double d[3] = { rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z };
    double second = INFINITY;
    for (uint32_t t = 0; t < nt; t++) {
        const float *p0 = pos + 4 * (size_t)tri[3 * (size_t)t], *p1 = pos + 4 * (size_t)tri[3 * (size_t)t + 1],
                    *p2 = pos + 4 * (size_t)tri[3 * (size_t)t + 2];
        double e1[3], e2[3], s[3], pv[3], qv[3];
        for (int k = 0; k < 3; k++)
            e1[k] = (double)p1[k] - p0[k], e2[k] = (double)p2[k] - p0[k], s[k] = o[k] - p0[k];
        pv[0] = d[1] * e2[2] - d[2] * e2[1], pv[1] = d[2] * e2[0] - d[0] * e2[2], pv[2] = d[0] * e2[1] - d[1] * e2[0];
        double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (det == 0.0 || !isfinite(det))
            continue;
        double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
        qv[0] = s[1] * e1[2] - s[2] * e1[1], qv[1] = s[2] * e1[0] - s[0] * e1[2], qv[2] = s[0] * e1[1] - s[1] * e1[0];
        double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
        double tt = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
        double m = fmin(u, fmin(v, 1.0 - u - v));
        if (m < 0.0 || !(tt >= rh->ray.tnear) || !(tt <= rh->ray.tfar))
            continue;
        if (best.prim < 0 || tt < best.t) {
            second = best.prim < 0 ? INFINITY : best.t;
            best.prim = (int32_t)t, best.t = tt, best.edge_margin = m;
        } else if (tt < second)
            second = tt;
    }
    if (best.prim >= 0)
        best.t_gap = isinf(second) ? INFINITY : (second - best.t) / fmax(fabs(best.t), 1e-300);
    return best;
}

double su_relerr(double a, double b, double floor_)
{
    return fabs(a - b) / fmax(fabs(b), floor_);
}

static void pack(hz_rayhit8_t *P8, hz_rayhit4_t *P4, int i, const hz_rayhit_t *r)
{
#define SU_PUT(P)                                                                                                 \
    do {                                                                                                          \
        (P)->ray.org_x[i] = r->ray.org_x, (P)->ray.org_y[i] = r->ray.org_y, (P)->ray.org_z[i] = r->ray.org_z;     \
        (P)->ray.tnear[i] = r->ray.tnear, (P)->ray.dir_x[i] = r->ray.dir_x, (P)->ray.dir_y[i] = r->ray.dir_y;     \
        (P)->ray.dir_z[i] = r->ray.dir_z, (P)->ray.time[i] = r->ray.time, (P)->ray.tfar[i] = r->ray.tfar;         \
        (P)->ray.mask[i] = r->ray.mask, (P)->ray.id[i] = r->ray.id, (P)->ray.flags[i] = r->ray.flags;             \
        (P)->hit.ng_x[i] = r->hit.ng_x, (P)->hit.ng_y[i] = r->hit.ng_y, (P)->hit.ng_z[i] = r->hit.ng_z;           \
        (P)->hit.u[i] = r->hit.u, (P)->hit.v[i] = r->hit.v, (P)->hit.prim_id[i] = r->hit.prim_id;                 \
        (P)->hit.geom_id[i] = r->hit.geom_id, (P)->hit.inst_id[0][i] = r->hit.inst_id[0];                         \
    } while (0)
    if (P8)
        SU_PUT(P8);
    else
        SU_PUT(P4);
}

static void unpack(const hz_rayhit8_t *P8, const hz_rayhit4_t *P4, int i, hz_rayhit_t *o)
{
#define SU_GET(P)                                                                                                 \
    do {                                                                                                          \
        o->ray.tfar = (P)->ray.tfar[i];                                                                           \
        o->hit.ng_x = (P)->hit.ng_x[i], o->hit.ng_y = (P)->hit.ng_y[i], o->hit.ng_z = (P)->hit.ng_z[i];           \
        o->hit.u = (P)->hit.u[i], o->hit.v = (P)->hit.v[i], o->hit.prim_id = (P)->hit.prim_id[i];                 \
        o->hit.geom_id = (P)->hit.geom_id[i], o->hit.inst_id[0] = (P)->hit.inst_id[0][i];                         \
    } while (0)
    if (P8)
        SU_GET(P8);
    else
        SU_GET(P4);
}

static bool same_hit(const hz_rayhit_t *a, const hz_rayhit_t *b)
{
    return memcmp(&a->ray.tfar, &b->ray.tfar, sizeof a->ray.tfar) == 0 && memcmp(&a->hit, &b->hit, sizeof a->hit) == 0;
}

void su_check_kernels(stab_result_t *r, const hz_accel_t *a, const hz_rayhit_t *rays, uint32_t n,
                      hz_rayhit_t *out)
{
    hz_accel_ctx_t ctx;
    hz_accel_ctx_init(&ctx);
    ctx.kernel = HZ_ACCEL_KERNEL_SCALAR;
    for (uint32_t i = 0; i < n; i++) {
        out[i] = rays[i];
        hz_accel_intersect1(a, &ctx, &out[i]);
        hz_ray_t o = rays[i].ray;
        hz_accel_occluded1(a, &ctx, &o);
        STAB_CHECK(r, (o.tfar == -INFINITY) == (out[i].hit.geom_id != HZ_ACCEL_INVALID_ID),
                   "scalar occlusion of ray %u disagrees with its closest hit", i);
        if (out[i].hit.geom_id != HZ_ACCEL_INVALID_ID) {
            const float v[6] = { out[i].ray.tfar, out[i].hit.u,    out[i].hit.v,
                                 out[i].hit.ng_x, out[i].hit.ng_y, out[i].hit.ng_z };
            stab_count_nonfinite(r, v, 6);
        }
    }
    for (int k = HZ_ACCEL_KERNEL_AUTO; k < HZ_ACCEL_KERNEL_COUNT; k++) {
        if (k == HZ_ACCEL_KERNEL_SCALAR || !hz_accel_kernel_available((hz_accel_kernel_t)k))
            continue;
        ctx.kernel = (hz_accel_kernel_t)k;
        for (int coherent = 0; coherent < 2; coherent++) {
            ctx.flags = coherent ? HZ_ACCEL_COHERENT : 0;
            for (uint32_t i = 0; i < n; i++) {
                hz_rayhit_t x = rays[i];
                hz_accel_intersect1(a, &ctx, &x);
                STAB_CHECK(r, same_hit(&x, &out[i]), "kernel %s single ray %u differs from scalar",
                           hz_accel_kernel_name(ctx.kernel), i);
                hz_ray_t o = rays[i].ray;
                hz_accel_occluded1(a, &ctx, &o);
                STAB_CHECK(r, (o.tfar == -INFINITY) == (out[i].hit.geom_id != HZ_ACCEL_INVALID_ID),
                           "kernel %s: occlusion of ray %u disagrees with the scalar closest hit",
                           hz_accel_kernel_name(ctx.kernel), i);
            }
            for (int pw = 4; pw <= 8; pw += 4)
                for (uint32_t p0 = 0; p0 < n; p0 += (uint32_t)pw) {
                    static hz_rayhit8_t P8 HZ_ALIGNED(32);
                    static hz_rayhit4_t P4 HZ_ALIGNED(16);
                    int32_t valid[8] HZ_ALIGNED(32);
                    for (int i = 0; i < pw; i++) {
                        uint32_t j = p0 + (uint32_t)i < n ? p0 + (uint32_t)i : p0;
                        valid[i] = p0 + (uint32_t)i < n ? -1 : 0;
                        pack(pw == 8 ? &P8 : NULL, &P4, i, &rays[j]);
                    }
                    if (pw == 8)
                        hz_accel_intersect8(valid, a, &ctx, &P8);
                    else
                        hz_accel_intersect4(valid, a, &ctx, &P4);
                    for (int i = 0; i < pw && p0 + (uint32_t)i < n; i++) {
                        hz_rayhit_t x = rays[p0 + (uint32_t)i];
                        unpack(pw == 8 ? &P8 : NULL, &P4, i, &x);
                        STAB_CHECK(r, same_hit(&x, &out[p0 + (uint32_t)i]),
                                   "kernel %s %s %d-wide packet ray %u differs from scalar",
                                   hz_accel_kernel_name(ctx.kernel), coherent ? "coherent" : "incoherent", pw,
                                   p0 + (uint32_t)i);
                    }
                }
        }
    }
}

double su_unit(hz_rng_t *g)
{
    return (double)hz_rng_u32(g) / 4294967296.0;
}

/* A random unit direction; every 8th has one zero component, every 16th two. */
void su_random_dir(hz_rng_t *g, uint32_t i, double d[3])
{
    double z = 2 * su_unit(g) - 1, ph = 6.283185307179586 * su_unit(g), s = sqrt(fmax(0, 1 - z * z));
    d[0] = s * cos(ph), d[1] = s * sin(ph), d[2] = z;
    if (i % 8 == 3)
        d[i / 8 % 3] = 0;
    if (i % 16 == 7)
        d[i / 16 % 3] = 0, d[(i / 16 + 1) % 3] = 0, d[(i / 16 + 2) % 3] = i & 32 ? -1 : 1;
    if (d[0] == 0 && d[1] == 0 && d[2] == 0)
        d[2] = 1;
}

/* Checks rays against a mesh: kernels agree, no non-finite hit, `closed`: every ray hits (leaks counted and
 * required 0), and hits agree in t with the double-precision oracle where the oracle's decision is clear. Hits
 * on triangles at or after `first_bad` (degenerate or non-finite ones) fail. */
void su_check_mesh(stab_result_t *r, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt,
                       const hz_rayhit_t *rays, uint32_t n, bool closed, uint32_t first_bad, double t_bound)
{
    hz_error_t err;
    hz_accel_t *a;
    STAB_OK(r, su_accel(&a, pos, nv, tri, nt, &err), &err);
    r->status = HZ_OK;
    hz_rayhit_t *out = malloc(sizeof *out * n);
    STAB_CHECK(r, out != NULL, "malloc");
    su_check_kernels(r, a, rays, n, out);
    if (r->fail[0])
        return;
    uint32_t leaks = 0, compared = 0, disagree = 0;
    for (uint32_t i = 0; i < n; i++) {
        bool hit = out[i].hit.geom_id != HZ_ACCEL_INVALID_ID;
        leaks += closed && !hit;
        STAB_CHECK(r, !hit || out[i].hit.prim_id < first_bad, "ray %u hit excluded triangle %u", i,
                   out[i].hit.prim_id);
        su_ref_t ref = su_ref_intersect(pos, tri, first_bad < nt ? first_bad : nt, &rays[i]);
        if (ref.prim < 0 || ref.edge_margin < 1e-4 || ref.t_gap < 1e-4)
            continue;
        compared++;
        if (!hit || out[i].hit.prim_id != (uint32_t)ref.prim) {
            disagree++;
            continue;
        }
        stab_error(r, su_relerr(out[i].ray.tfar, ref.t, 1e-300));
    }
    stab_note(r, "%u rays; %u leaks; %u clear hits vs double oracle; %u disagree; triangles %u (%u skipped)", n,
              leaks, compared, disagree, nt, a->info.tri_skipped);
    STAB_CHECK(r, leaks == 0, "%u of %u rays leaked through the closed mesh", leaks, n);
    STAB_CHECK(r, disagree == 0, "%u clear hits disagree with the oracle", disagree);
    STAB_CHECK(r, isnan(r->max_error) || r->max_error <= t_bound, "t relative error %g > %g", r->max_error, t_bound);
    free(out);
}

/* Rays from random points inside a sphere of radius `inner` around c. */
hz_rayhit_t *su_inside_rays(uint32_t n, const double c[3], double inner, uint64_t seed)
{
    hz_rayhit_t *rays = malloc(sizeof *rays * n);
    hz_rng_t g;
    hz_rng_seed(&g, seed, 7);
    for (uint32_t i = 0; i < n; i++) {
        double o[3], d[3];
        su_random_dir(&g, i, d);
        double rr = inner * cbrt(su_unit(&g)), od[3];
        su_random_dir(&g, i + 1, od);
        for (int k = 0; k < 3; k++)
            o[k] = c[k] + rr * od[k];
        su_ray(&rays[i], o[0], o[1], o[2], d[0], d[1], d[2]);
    }
    return rays;
}


void su_mesh(su_scene_t *b, const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nt, uint32_t mat,
             float scale, const float offset[3])
{
    uint32_t base = b->nv;
    for (uint32_t i = 0; i < nv; i++)
        su_vertex(b, pos[4 * i] * scale + offset[0], pos[4 * i + 1] * scale + offset[1],
                  pos[4 * i + 2] * scale + offset[2]);
    for (uint32_t t = 0; t < nt; t++)
        su_tri(b, base + tri[3 * t], base + tri[3 * t + 1], base + tri[3 * t + 2], mat);
}

void su_room(su_scene_t *b, float s)
{
    uint32_t grey = su_material(b, 0.7f, 0.7f, 0.7f), red = su_material(b, 0.8f, 0.2f, 0.1f);
    const float f0[3] = { -5 * s, 0, -5 * s }, f1[3] = { 5 * s, 0, -5 * s }, f2[3] = { 5 * s, 0, 5 * s },
                f3[3] = { -5 * s, 0, 5 * s };
    su_quad(b, f3, f2, f1, f0, grey);
    const float w0[3] = { -5 * s, 0, -5 * s }, w1[3] = { 5 * s, 0, -5 * s }, w2[3] = { 5 * s, 5 * s, -5 * s },
                w3[3] = { -5 * s, 5 * s, -5 * s };
    su_quad(b, w0, w1, w2, w3, grey);
    su_object(b);
    hz_mesh_t m;
    hz_arena_mark_t mk = hz_arena_mark(&hz_pools_get()->frame);
    if (hz_meshgen_sphere(&m, &hz_pools_get()->frame, 12, 24, 1.0f, NULL) == HZ_OK) {
        const float off[3] = { 0, 1.2f * s, 0 };
        su_mesh(b, m.pos, m.vertex_count, m.tri, m.tri_count, red, s, off);
        su_object(b);
    }
    hz_arena_reset(&hz_pools_get()->frame, mk);
    su_light(b, 1 * s, 4 * s, 3 * s, 20.0f * s * s);
}

void su_check_image(stab_result_t *r, const hz_image_t *img)
{
    stab_count_nonfinite(r, img->rgb, 3 * hz_image_pixels(img));
}

hz_hzb_object_t *su_wall_and_quad(su_scene_t *b, float size)
{
    su_begin(b);
    uint32_t m0 = su_material(b, 0.6f, 0.6f, 0.6f), m1 = su_material(b, 0.2f, 0.7f, 0.3f);
    const float w0[3] = { -8, -8, -3 }, w1[3] = { 8, -8, -3 }, w2[3] = { 8, 8, -3 }, w3[3] = { -8, 8, -3 };
    su_quad(b, w0, w1, w2, w3, m0);
    su_object(b);
    const float q0[3] = { -size, -size, 0 }, q1[3] = { size, -size, 0 }, q2[3] = { size, size, 0 },
                q3[3] = { -size, size, 0 };
    su_quad(b, q0, q1, q2, q3, m1);
    hz_hzb_object_t *o = su_object(b);
    su_light(b, 2, 3, 6, 60);
    const float eye[3] = { 0, 0, 6 }, target[3] = { 0, 0, 0 };
    su_camera(b, 0, eye, target, 1.0f);
    return o;
}

void su_wall_layer(su_scene_t *b, int layer_mode, float alpha)
{
    su_begin(b);
    uint32_t wall = su_material(b, 0.7f, 0.6f, 0.5f);
    const float w0[3] = { -4, -4, -1 }, w1[3] = { 4, -4, -1 }, w2[3] = { 4, 4, -1 }, w3[3] = { -4, 4, -1 };
    su_quad(b, w0, w1, w2, w3, wall);
    su_object(b);
    if (layer_mode >= 0) {
        uint32_t m = su_material_alpha(b, 0.2f, 0.4f, 0.9f, alpha, (uint32_t)layer_mode);
        const float q0[3] = { -4, -4, 0 }, q1[3] = { 4, -4, 0 }, q2[3] = { 4, 4, 0 }, q3[3] = { -4, 4, 0 };
        su_quad(b, q0, q1, q2, q3, m);
        su_object(b);
    }
    su_light(b, 0.5f, 0.5f, 2.0f, 8.0f);
    const float eye[3] = { 0, 0, 4 }, target[3] = { 0, 0, 0 };
    su_camera(b, 0, eye, target, 0.8f);
}
