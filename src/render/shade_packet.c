/* Packet surfaces (src/render/shade.h): the scalar twin, which is the renderer's per-hit surface code looping over the
 * lanes, and the per-lane helpers the SIMD kernels (shade_avx2.c, shade_neon.c over shade_kernel.h) share with it.
 * On scalar boards hz_shade_surfaces is the twin. */
#include "shade.h"

#include "terminator.h"
#include "shade_internal.h"

static hz_vec3_t vtx(const float *arr, uint32_t i)
{
    return hz_v3(arr[(size_t)i * 4], arr[(size_t)i * 4 + 1], arr[(size_t)i * 4 + 2]);
}

/* Triangle prim's vertices at a ray's time: the pose keys interpolated with motion blur, else the frame's. */
static void tri_at(const hz_shade_ctx_t *c, uint32_t prim, float time, hz_vec3_t p[3])
{
    const uint32_t *t = c->scene->tri + (size_t)prim * 3;
    for (int i = 0; i < 3; i++)
        p[i] = HZ_FEATURE_MOTION && c->keys ? hz_posekeys_lerp(c->keys, c->keys->pos, t[i], time)
                                            : vtx(c->scene->pos, t[i]);
}

static hz_vec3_t nrm_at(const hz_shade_ctx_t *c, uint32_t v, float time)
{
    return HZ_FEATURE_MOTION && c->keys && c->keys->nrm[0] ? hz_posekeys_lerp(c->keys, c->keys->nrm, v, time)
                                                           : vtx(c->scene->nrm, v);
}

static hz_vec3_t bary(hz_vec3_t a, hz_vec3_t b, hz_vec3_t c, float u, float v)
{
    float w = 1.0f - u - v;
    return hz_v3(w * a.x + u * b.x + v * c.x, w * a.y + u * b.y + v * c.y, w * a.z + u * b.z + v * c.z);
}

void hz_shade_fetch_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, float pos[9][HZ_SHADE_LANES],
                           float nrm[9][HZ_SHADE_LANES])
{
    const hz_scene_t *s = c->scene;
    for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
        if (!(mask >> i & 1u))
            continue;
        hz_vec3_t p[3];
        tri_at(c, in->prim[i], in->time[i], p);
        const uint32_t *t = s->tri + (size_t)in->prim[i] * 3;
        for (int k = 0; k < 3; k++) {
            pos[k * 3][i] = p[k].x, pos[k * 3 + 1][i] = p[k].y, pos[k * 3 + 2][i] = p[k].z;
            if (s->nrm) {
                hz_vec3_t n = nrm_at(c, t[k], in->time[i]);
                nrm[k * 3][i] = n.x, nrm[k * 3 + 1][i] = n.y, nrm[k * 3 + 2][i] = n.z;
            }
        }
    }
}

void hz_shade_lane_material(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t i, hz_shade_out_t *o,
                            hz_shade_lane_tex_t *lt)
{
    const hz_scene_t *s = c->scene;
    const hz_material_t *m = &s->materials[s->tri_info[in->prim[i]] & 0xffffu];
    o->albedo[0][i] = m->base_color[0], o->albedo[1][i] = m->base_color[1], o->albedo[2][i] = m->base_color[2];
    o->alpha[i] = 1.0f;
    o->textured[i] = 0;
    o->tu[i] = o->tv[i] = 0.0f;
    bool blend = m->alpha_mode == HZ_ALPHA_BLEND;
    if (blend)
        o->alpha[i] = m->alpha;
    lt->any = HZ_FEATURE_TEXTURES && c->textures && (m->base_texture >= 0 || (blend && m->alpha_texture >= 0));
    lt->base = m->base_texture >= 0 ? m->base_texture : -1;
    lt->base_alpha = blend && m->alpha_texture == m->base_texture;
    lt->alpha = blend && m->alpha_texture >= 0 && m->alpha_texture != m->base_texture ? m->alpha_texture : -1;
}

bool hz_shade_footprint_lane(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t i, const hz_vec3_t p[3],
                             float g[4])
{
    const hz_shade_footprint_t *fp = c->footprint;
    const hz_scene_t *s = c->scene;
    if (!HZ_FEATURE_TEXTURES || !fp || !s->uv || !(in->eye_dist[i] > 0.0f))
        return false;
    /* Igehy's transfer of a ray differential to the hit plane: for a direction step e of the unnormalised
     * direction D (|D| along fwd is 1), the hit moves by tq (e - d (e.N) / (d.N)), tq the hit's depth along fwd;
     * barycentric coordinates of that move through the dual edges N x e1 and e2 x N. */
    hz_vec3_t e1 = hz_v3_sub(p[1], p[0]), e2 = hz_v3_sub(p[2], p[0]);
    hz_vec3_t n = hz_v3_cross(e1, e2);
    hz_vec3_t d = hz_v3(in->dx[i], in->dy[i], in->dz[i]);
    float nn = hz_v3_dot(n, n), dn = hz_v3_dot(d, n);
    float tq = in->eye_dist[i] * hz_v3_dot(d, hz_v3(fp->f[0], fp->f[1], fp->f[2]));
    hz_vec3_t b1 = hz_v3_cross(e2, n), b2 = hz_v3_cross(n, e1);
    const uint32_t *t = s->tri + (size_t)in->prim[i] * 3;
    const float *ua = s->uv + (size_t)t[0] * 2, *ub = s->uv + (size_t)t[1] * 2, *uc = s->uv + (size_t)t[2] * 2;
    float du1 = ub[0] - ua[0], dv1 = ub[1] - ua[1], du2 = uc[0] - ua[0], dv2 = uc[1] - ua[1];
    for (int axis = 0; axis < 2; axis++) {
        const float *ev = axis ? fp->ey : fp->ex;
        hz_vec3_t e = hz_v3(ev[0], ev[1], ev[2]);
        float k = hz_v3_dot(e, n) / dn;
        hz_vec3_t a = hz_v3_scale(hz_v3_sub(e, hz_v3_scale(d, k)), tq);
        float beta = hz_v3_dot(a, b1) / nn, gamma = hz_v3_dot(a, b2) / nn;
        g[axis] = beta * du1 + gamma * du2;
        g[2 + axis] = beta * dv1 + gamma * dv2;
    }
    return hz_isfinitef(g[0]) && hz_isfinitef(g[1]) && hz_isfinitef(g[2]) && hz_isfinitef(g[3]);
}

static void sample_taps(const hz_scene_t *s, int32_t tex, float tu, float tv, float lod, const float g[4],
                        float rgba[4])
{
    float su[HZ_SHADE_TAPS], sv[HZ_SHADE_TAPS];
    bool finite = hz_isfinitef(tu) && hz_isfinitef(tv);
    for (uint32_t k = 0; k < HZ_SHADE_TAPS; k++) {
        float ox = hz_shade_tap_offset(k % HZ_SHADE_TAP_SIDE), oy = hz_shade_tap_offset(k / HZ_SHADE_TAP_SIDE);
        su[k] = tu + (ox * g[0] + oy * g[1]);
        sv[k] = tv + (ox * g[2] + oy * g[3]);
        finite = finite && hz_isfinitef(su[k]) && hz_isfinitef(sv[k]);
    }
    if (!finite) {
        hz_texture_sample(s, tex, tu, tv, lod, rgba);
        return;
    }
    float acc[4] = { 0.0f, 0.0f, 0.0f, 0.0f }, px[4];
    for (uint32_t k = 0; k < HZ_SHADE_TAPS; k++) {
        hz_texture_sample(s, tex, su[k], sv[k], lod, px);
        for (int ch = 0; ch < 4; ch++)
            acc[ch] = k ? acc[ch] + px[ch] : px[ch];
    }
    for (int ch = 0; ch < 4; ch++)
        rgba[ch] = acc[ch] * (1.0f / (float)HZ_SHADE_TAPS);
}

void hz_shade_sample_lane(const hz_scene_t *s, int32_t tex, float tu, float tv, float lod_base, const float *g,
                          float rgba[4])
{
    const hz_texture_t *tx = &s->textures[tex];
    const float lod = lod_base + 0.5f * hz_log2_approx((float)tx->width * (float)tx->height);
    if (g)
        sample_taps(s, tex, tu, tv, lod, g, rgba);
    else
        hz_texture_sample(s, tex, tu, tv, lod, rgba);
}

void hz_shade_levels_head(const hz_scene_t *s, int32_t tex, hz_shade_levels_t *lv)
{
    const hz_texture_t *tx = &s->textures[tex];
    lv->size_term = 0.5f * hz_log2_approx((float)tx->width * (float)tx->height);
    lv->top = (int32_t)tx->levels - 1; /* 1..32 levels (the loader checks them against the size) */
}

void hz_shade_levels_walk(const hz_scene_t *s, int32_t tex, int32_t upto, hz_shade_levels_t *lv)
{
    const hz_texture_t *tx = &s->textures[tex];
    lv->far = 0;
    size_t f = tx->first_texel;
    uint32_t lw = tx->width, lh = tx->height;
    for (int32_t l = 0; l <= upto && l < HZ_SHADE_MAX_LEVELS; l++) {
        /* hz_texture_level_first's walk, every level on the way kept */
        const bool far = f + (size_t)lw * lh > 0x7fffffffu;
        lv->far |= (uint32_t)far << l;
        lv->first[l] = far ? 0 : (int32_t)f;
        lv->w[l] = (int32_t)lw, lv->h[l] = (int32_t)lh;
        hz_texture_level_next(&f, &lw, &lh);
    }
}

/* One lane, exactly as the renderer shaded a hit before packets (the oracle of the SIMD kernels). */
static void lane_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t i, hz_shade_out_t *o)
{
    const hz_scene_t *s = c->scene;
    const uint32_t prim = in->prim[i];
    const float hu = in->u[i], hv = in->v[i];
    const uint32_t *t = s->tri + (size_t)prim * 3;
    hz_vec3_t pv[3];
    tri_at(c, prim, in->time[i], pv);
    hz_vec3_t p0 = pv[0], p1 = pv[1], p2 = pv[2];
    hz_vec3_t d = hz_v3(in->dx[i], in->dy[i], in->dz[i]);
    hz_vec3_t p = bary(p0, p1, p2, hu, hv);
    hz_vec3_t ng = hz_v3_cross(hz_v3_sub(p1, p0), hz_v3_sub(p2, p0));
    float area2 = hz_v3_len(ng);
    ng = hz_v3_normalize(ng);
    float flip = hz_v3_dot(ng, d) > 0.0f ? -1.0f : 1.0f;
    hz_vec3_t ngf = hz_v3_scale(ng, flip), ns = ngf;
    if (s->nrm) {
        hz_vec3_t n = hz_v3_normalize(
            bary(nrm_at(c, t[0], in->time[i]), nrm_at(c, t[1], in->time[i]), nrm_at(c, t[2], in->time[i]), hu, hv));
        n = hz_v3_scale(n, flip);
        /* Interpolated normals can point below the surface at grazing angles: keep the geometric one then. */
        if (hz_v3_dot(n, ngf) > 0.0f)
            ns = n;
    }
    o->px[i] = p.x, o->py[i] = p.y, o->pz[i] = p.z;
    o->ngx[i] = ngf.x, o->ngy[i] = ngf.y, o->ngz[i] = ngf.z;
    o->nsx[i] = ns.x, o->nsy[i] = ns.y, o->nsz[i] = ns.z;
    hz_shade_lane_tex_t lt;
    hz_shade_lane_material(c, in, i, o, &lt);
    if (!HZ_FEATURE_TEXTURES || !lt.any)
        return;
    const float *a = s->uv + (size_t)t[0] * 2, *b = s->uv + (size_t)t[1] * 2, *cc = s->uv + (size_t)t[2] * 2;
    float w = 1.0f - hu - hv;
    float tu = w * a[0] + hu * b[0] + hv * cc[0];
    float tv = w * a[1] + hu * b[1] + hv * cc[1];
    float cr = (b[0] - a[0]) * (cc[1] - a[1]) - (cc[0] - a[0]) * (b[1] - a[1]);
    float uv_area2 = hz_absf(cr);
    o->tu[i] = tu, o->tv[i] = tv;
    float cos = hz_absf(hz_v3_dot(ng, d));
    float width = in->cone_w[i] + in->cone_s[i] * in->t[i];
    float lod_base = 0.5f * hz_log2_approx(uv_area2 / area2) + hz_log2_approx(width) - hz_log2_approx(cos);
    float rgba[4], g[4];
    const bool foot = hz_shade_footprint_lane(c, in, i, pv, g);
    if (lt.base >= 0) {
        hz_shade_sample_lane(s, lt.base, tu, tv, lod_base, foot ? g : NULL, rgba);
        o->albedo[0][i] *= rgba[0], o->albedo[1][i] *= rgba[1], o->albedo[2][i] *= rgba[2];
        o->textured[i] = 1;
        if (lt.base_alpha)
            o->alpha[i] *= rgba[3];
    }
    if (lt.alpha >= 0) {
        hz_shade_sample_lane(s, lt.alpha, tu, tv, lod_base, foot ? g : NULL, rgba);
        o->alpha[i] *= rgba[3];
        o->textured[i] = 1;
    }
}

bool hz_shade_light_lane(const hz_shade_ctx_t *c, const hz_shade_out_t *o, uint32_t i, uint32_t l,
                         hz_shade_light_t *out)
{
    const hz_light_t *lt = &c->lights[l];
    const hz_vec3_t o_light = hz_v3(o->lox[i], o->loy[i], o->loz[i]);
    const hz_vec3_t ng = hz_v3(o->ngx[i], o->ngy[i], o->ngz[i]), ns = hz_v3(o->nsx[i], o->nsy[i], o->nsz[i]);
    hz_vec3_t L = hz_v3_sub(hz_v3(lt->position[0], lt->position[1], lt->position[2]), o_light);
    float dist2 = hz_v3_dot(L, L);
    float dist = hz_sqrtf(dist2);
    hz_vec3_t ld = dist > 0.0f ? hz_v3_scale(L, 1.0f / dist) : ns;
    float cs = hz_v3_dot(ns, ld);
    if (!(cs > 0.0f) || !(hz_v3_dot(ng, ld) > 0.0f) || !(dist > 0.0f))
        return false;
    float k = cs * HZ_SHADE_INV_PI * (lt->falloff == HZ_FALLOFF_INV_SQUARE ? 1.0f / dist2 : 1.0f);
    float so[3] = { o_light.x, o_light.y, o_light.z };
    float tmax = dist * (1.0f - 1e-4f);
    const float skip = o->skip[i];
    if (skip > 0.0f) {
        float k0 = hz_minf(skip, tmax);
        so[0] += ld.x * k0, so[1] += ld.y * k0, so[2] += ld.z * k0;
        tmax -= k0;
    }
    out->ox[i] = so[0], out->oy[i] = so[1], out->oz[i] = so[2];
    out->dx[i] = ld.x, out->dy[i] = ld.y, out->dz[i] = ld.z;
    out->tmax[i] = tmax;
    out->k[i] = k;
    return true;
}

void hz_shade_surfaces_scalar(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out)
{
    const uint32_t nl = c->light_count < HZ_SHADE_LIGHTS ? c->light_count : HZ_SHADE_LIGHTS;
    for (uint32_t l = 0; l < HZ_SHADE_LIGHTS; l++)
        out->lit[l] = 0;
    for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
        if (!(mask >> i & 1u))
            continue;
        lane_scalar(c, in, i, out);
        hz_vec3_t p = hz_v3(out->px[i], out->py[i], out->pz[i]), ng = hz_v3(out->ngx[i], out->ngy[i], out->ngz[i]);
        hz_vec3_t o = hz_accel_offset_origin(p, ng, c->offset_scale);
        out->lox[i] = o.x, out->loy[i] = o.y, out->loz[i] = o.z;
        out->skip[i] = hz_terminator_skip(c->scene, in->prim[i], ng); /* the facet's own curvature */
        for (uint32_t l = 0; l < nl; l++)
            out->lit[l] |= (hz_shade_light_lane(c, out, i, l, &out->light[l]) ? 1u : 0u) << i;
    }
}

#if !defined(HZ_BOARD_SIMD_AVX2) && !defined(HZ_BOARD_SIMD_NEON) /* the Makefile builds shade_<simd>.c then */
void hz_shade_surfaces(const hz_shade_ctx_t *c, const hz_shade_in_t *in, uint32_t mask, hz_shade_out_t *out)
{
    hz_shade_surfaces_scalar(c, in, mask, out);
}

const char *hz_shade_path(void)
{
    return "scalar";
}
#endif
