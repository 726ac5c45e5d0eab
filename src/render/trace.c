/* Tracing and Whitted shading of one tile batch (see render_internal.h for the work organisation). */
#include "hz/dither.h"
#include "hz/image.h"
#include "hz/posekeys.h"
#include "shade.h"
#include "render_internal.h"


typedef struct hitrec {
    float t, u, v;
    uint32_t prim; /* HZ_ACCEL_INVALID_ID on a miss */
} hitrec_t;

/* ray id seen by the any-hit callback: the slot and whether the ray is a primary one (marks alpha_touched), or
 * for shadow rays the lane and ID_SHADOW (blended surfaces then composite into the lane's transmittance). */
#define ID_PRIMARY 0x10000u
#define ID_SHADOW 0x20000u /* shadow ray; the low bits are its packet lane */
#define ID_DITHER 0x40000u        /* camera-path ray taking the stochastic transparency decision (transp.c) */
#define ID_SHADOW_DITHER 0x80000u /* rr_shadows: shadow ray of a stochastic fragment, blended occluders by roulette */
#define SHADOW_GATHER (4u * HZ_RENDER_LANES) /* how deep take_shadows looks for a packet towards one light */

/* ---- packets ---- */

typedef char shade_lanes_match[HZ_SHADE_LANES == HZ_RENDER_LANES ? 1 : -1]; /* one packet, one shading call */

#if HZ_RENDER_LANES == 8
typedef hz_rayhit8_t packet_t;
typedef hz_ray8_t shadow_packet_t;
#define INTERSECT hz_accel_intersect8
#define INTERSECT_N hz_accel_intersect8n
#define OCCLUDED hz_accel_occluded8
#else
typedef hz_rayhit4_t packet_t;
typedef hz_ray4_t shadow_packet_t;
#define INTERSECT hz_accel_intersect4
#define INTERSECT_N hz_accel_intersect4n
#define OCCLUDED hz_accel_occluded4
#endif

/* A packet of up to HZ_RENDER_LANES jobs (lanes past n off), unbounded rays. */
static void fill_packet(packet_t *p, int32_t *valid, const ray_job_t *jobs, uint32_t n)
{
    for (uint32_t i = 0; i < HZ_RENDER_LANES; i++) {
        const ray_job_t *j = &jobs[i < n ? i : 0];
        valid[i] = i < n ? -1 : 0;
        p->ray.org_x[i] = j->o[0], p->ray.org_y[i] = j->o[1], p->ray.org_z[i] = j->o[2];
        p->ray.dir_x[i] = j->d[0], p->ray.dir_y[i] = j->d[1], p->ray.dir_z[i] = j->d[2];
        p->ray.tnear[i] = 0.0f;
        p->ray.tfar[i] = __builtin_inff();
        p->ray.time[i] = j->time;
        p->ray.mask[i] = 0xffffffffu;
        p->ray.id[i] = j->slot | (j->gslot == GSLOT_PRIMARY ? ID_PRIMARY : 0u) | (j->dither ? ID_DITHER : 0u);
        p->ray.flags[i] = 0;
        p->hit.geom_id[i] = HZ_ACCEL_INVALID_ID;
        p->hit.prim_id[i] = HZ_ACCEL_INVALID_ID;
    }
}

static void read_hits(const packet_t *p, uint32_t n, hitrec_t *out)
{
    for (uint32_t i = 0; i < n; i++) {
        out[i].prim = p->hit.geom_id[i] == HZ_ACCEL_INVALID_ID ? HZ_ACCEL_INVALID_ID : p->hit.prim_id[i];
        out[i].t = p->ray.tfar[i];
        out[i].u = p->hit.u[i];
        out[i].v = p->hit.v[i];
    }
}

/* Closest hits of up to HZ_RENDER_LANES jobs (unbounded rays). The packets come off the
 * queue of one camera packet's descendants (drain): continuation rays keep their camera rays' directions and
 * lie along their lines, a flat mirror turns a packet into the packet of a mirrored camera. They go as coherent
 * packets: the tile traversal takes lanes that part from the others on alone (a curved mirror's). Against single
 * rays: runs with exact or hybrid transparency 15-25% faster, mirror scenes even (doc/accel.md). */
static void intersect_jobs(hz_worker_t *w, const ray_job_t *jobs, uint32_t n, hitrec_t *out)
{
    packet_t p;
    int32_t valid[HZ_RENDER_LANES] HZ_ALIGNED(32);
    fill_packet(&p, valid, jobs, n);
    w->ctx.flags = HZ_ACCEL_COHERENT;
    INTERSECT(valid, w->r->accel, &w->ctx, &p);
    read_hits(&p, n, out);
}

#define BATCH_PACKETS (HZ_TILE_PIXELS / HZ_RENDER_LANES)

/* Closest hits of a batch's camera rays, n[q] jobs in packet q (jobs[q * HZ_RENDER_LANES ..]), all in one call:
 * the accel traces them as one coherent tile. */
static void intersect_batch(hz_worker_t *w, const ray_job_t *jobs, const uint32_t *n, hitrec_t *out)
{
    packet_t p[BATCH_PACKETS];
    int32_t valid[HZ_TILE_PIXELS] HZ_ALIGNED(32);
    for (uint32_t q = 0; q < BATCH_PACKETS; q++)
        fill_packet(&p[q], valid + q * HZ_RENDER_LANES, jobs + q * HZ_RENDER_LANES, n[q]);
    w->ctx.flags = HZ_ACCEL_COHERENT;
    INTERSECT_N(valid, w->r->accel, &w->ctx, p, BATCH_PACKETS);
    for (uint32_t q = 0; q < BATCH_PACKETS; q++)
        read_hits(&p[q], n[q], out + q * HZ_RENDER_LANES);
}

/* ---- surfaces ---- */

typedef struct surface {
    hz_vec3_t p, ng, ns;    /* ng and ns face the side the ray came from; unit length */
    float tu, tv;           /* texture coordinates */
    uint32_t prim;
    const hz_material_t *m;
    uint16_t object;
    float albedo[3];
    float alpha;            /* opacity of a blended surface, 1 otherwise */
    bool textured;
} surface_t;

static hz_vec3_t vtx(const float *arr, uint32_t i)
{
    return hz_v3(arr[(size_t)i * 4], arr[(size_t)i * 4 + 1], arr[(size_t)i * 4 + 2]);
}

static hz_vec3_t bary(hz_vec3_t a, hz_vec3_t b, hz_vec3_t c, float u, float v)
{
    float w = 1.0f - u - v;
    return hz_v3(w * a.x + u * b.x + v * c.x, w * a.y + u * b.y + v * c.y, w * a.z + u * b.z + v * c.z);
}

/* Lane i of a packet's surfaces (src/render/shade.h) with the hit's material. */
static void surface_from(const struct hz_renderer *r, const hitrec_t *h, const hz_shade_out_t *o, uint32_t i,
                         surface_t *sf)
{
    const hz_scene_t *s = r->scene;
    sf->prim = h->prim;
    sf->p = hz_v3(o->px[i], o->py[i], o->pz[i]);
    sf->ng = hz_v3(o->ngx[i], o->ngy[i], o->ngz[i]);
    sf->ns = hz_v3(o->nsx[i], o->nsy[i], o->nsz[i]);
    sf->tu = o->tu[i], sf->tv = o->tv[i];
    sf->m = &s->materials[s->tri_info[h->prim] & 0xffffu];
    sf->object = (uint16_t)(s->tri_info[h->prim] >> 16);
    sf->albedo[0] = o->albedo[0][i], sf->albedo[1] = o->albedo[1][i], sf->albedo[2] = o->albedo[2][i];
    sf->alpha = o->alpha[i];
    sf->textured = o->textured[i] != 0;
}

/* Opacity of material m at a hit on prim: its alpha, times its alpha texture's at the hit's texture coordinates
 * when `textures` (colour not needed). */
static float hit_alpha(const hz_scene_t *s, const hz_material_t *m, uint32_t prim, float u, float v, bool textures)
{
    float a = m->alpha;
    if (textures && m->alpha_texture >= 0) {
        const uint32_t *t = s->tri + (size_t)prim * 3;
        const float *p = s->uv + (size_t)t[0] * 2, *q = s->uv + (size_t)t[1] * 2, *c = s->uv + (size_t)t[2] * 2;
        const float w = 1.0f - u - v;
        a *= hz_texture_alpha(s, m->alpha_texture, w * p[0] + u * q[0] + v * c[0], w * p[1] + u * q[1] + v * c[1]);
    }
    return a;
}

bool hz_render_anyhit(void *user, uint32_t prim, float u, float v, float t, uint32_t ray_id, int lane, unsigned back)
{
    (void)t;
    (void)lane;
    if (!HZ_FEATURE_TRANSPARENCY)
        return true; /* installed only in builds with transparency: the rest compiles out */
    hz_worker_t *w = (hz_worker_t *)user;
    const hz_scene_t *s = w->r->scene;
    const uint32_t mi = s->tri_info[prim] & 0xffffu;
    const hz_material_t *m = &s->materials[mi];
    if (m->alpha_mode == HZ_ALPHA_BLEND) {
        /* The common rejected layer: a threshold above the most opacity the material can have rejects it
         * without its texture (the decision is the same: it never falls as opacity grows); an untextured alpha
         * comes straight from the material; then integers only. */
        const uint32_t bound = w->r->blend_bound ? w->r->blend_bound[mi] : HZ_DITHER_ONE;
        const bool textures = HZ_FEATURE_TEXTURES && w->r->has_textures;
        if (ray_id & ID_DITHER) {
            if (hz_transp_rejects(w, prim, u, v, bound, ray_id & 0xffffu, back))
                return false;
            const float a = hit_alpha(s, m, prim, u, v, textures);
            return hz_transp_keep(w, prim, u, v, hz_transp_alpha_q16(a), ray_id & 0xffffu, back);
        }
        if (ray_id & ID_SHADOW_DITHER) {
            const uint32_t th = hz_transp_shadow_threshold(w, prim, u, v);
            return hz_dither_keep(bound, th) && hz_dither_keep(hz_transp_alpha_q16(hit_alpha(s, m, prim, u, v, textures)), th);
        }
        if (!(ray_id & ID_SHADOW))
            return true; /* camera and secondary rays stop at a blended surface and continue behind it */
        /* A shadow ray lets the layer's opacity through and goes on, counting each triangle once (spatial splits
         * put a triangle in several leaves): the lane's set of those met (hz_worker_t) says whether it has. */
        uint32_t ln = (ray_id & 0xffu) % HZ_RENDER_LANES;
        uint32_t *set = w->shadow_set[ln];
        uint32_t h = (prim * 0x9e3779b1u) >> (32 - HZ_RENDER_SHADOW_SET_BITS);
        for (; set[h]; h = (h + 1u) % HZ_RENDER_SHADOW_SET)
            if (set[h] == prim + 1u)
                return false;
        if (w->shadow_nprims[ln] == HZ_RENDER_MAX_LAYERS) {
            w->shadow_overflow[ln] = 1; /* past the layer cap with visibility left: ends as blocked */
            return true;
        }
        set[h] = prim + 1u;
        w->shadow_taken[ln][w->shadow_nprims[ln]++] = (uint8_t)h;
        w->shadow_vis[ln] *= 1.0f - hit_alpha(s, m, prim, u, v, textures);
        return !(w->shadow_vis[ln] >= w->r->f.opts.min_visibility); /* nothing left: as good as blocked */
    }
    if (m->alpha_mode != HZ_ALPHA_MASK)
        return true;
    if (ray_id & ID_PRIMARY)
        w->alpha_touched[(ray_id & 0xffffu) % HZ_TILE_PIXELS] = 1;
    return hit_alpha(s, m, prim, u, v, true) >= m->alpha_cutoff;
}

uint32_t hz_render_dither_decide(hz_renderer_t *r, const uint32_t *prims, const uint8_t *back, uint32_t n,
                                 uint8_t *keep)
{
    if (!HZ_FEATURE_TRANSPARENCY || !r->f.dither || r->thread_count < 1)
        return 0;
    hz_worker_t *w = r->workers_by_thread[0];
    hz_transp_cells(w);
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t slot = prims[i] % HZ_TILE_PIXELS;
        bool k = prims[i] < r->scene->triangle_count &&
                 hz_render_anyhit(w, prims[i], 0.25f, 0.25f, 1.0f, slot | ID_DITHER, 0, back[i] != 0);
        kept += k;
        if (keep)
            keep[i] = k;
    }
    return kept;
}

/* ---- queues ---- */

static void add_radiance(hz_worker_t *w, uint32_t slot, const float wt[3], const float L[3])
{
    float *dst = &w->b.radiance[slot * 3];
    dst[0] += wt[0] * L[0];
    dst[1] += wt[1] * L[1];
    dst[2] += wt[2] * L[2];
}

static void push_ray(hz_worker_t *w, const ray_job_t *j)
{
    if (w->stack_n >= w->stack_cap) {
        w->b.stats.queue_full++;
        return;
    }
    w->stack[w->stack_n++] = *j;
}

static void process_shadows(hz_worker_t *w);

static void push_shadow(hz_worker_t *w, const shadow_job_t *j)
{
    while (w->shadow_n >= w->shadow_cap)
        process_shadows(w); /* takes a packet off */
    w->shadows[w->shadow_n++] = *j;
}

static void count_blocked(hz_worker_t *w, uint32_t slot, uint8_t gslot)
{
    uint32_t px = w->b.pixel[slot];
    const hz_gbuffer_t *gb = &w->r->f.gb;
    uint8_t *c = gslot == GSLOT_PRIMARY ? gb->shadow : gslot == GSLOT_SECONDARY ? gb->shadow2 : NULL;
    if (c && c[px] < 255)
        c[px]++;
}

/* Takes a packet of jobs off the shadow queue: the newest job and the newest others towards the same light among
 * the SHADOW_GATHER newest (the rest keep their order), oldest first; jobs pushed hit by hit alternate between
 * the lights. Returns how many. A packet towards one light is coherent wherever its rays start (camera hits,
 * mirror hits, the layers behind blended surfaces): they end at one point of a point light, or run parallel
 * towards a directional one, so the traverser bounds them from that end. */
static uint32_t take_shadows(hz_worker_t *w, shadow_job_t *jobs)
{
    const uint32_t top = w->shadow_n, lo = top > SHADOW_GATHER ? top - SHADOW_GATHER : 0;
    const uint8_t light = w->shadows[top - 1].light;
    uint32_t start = top, found = 0;
    for (uint32_t i = top; i-- > lo && found < HZ_RENDER_LANES;)
        if (w->shadows[i].light == light)
            found++, start = i;
    uint32_t n = 0, d = start;
    for (uint32_t i = start; i < top; i++) {
        if (w->shadows[i].light == light) {
            jobs[n++] = w->shadows[i];
        } else {
            w->shadows[d++] = w->shadows[i];
        }
    }
    w->shadow_n = d;
    return n;
}

/* One shadow packet of n rays (lanes past n off), set up in p but for the per-lane state set here: occlusion with
 * early exit; blended surfaces composite into the lane's transmittance in the any-hit callback, in whatever
 * order the traversal meets them (the order moves only the product's last bits), each triangle once, up to the
 * layer cap. Lane i's transmittance times wt[i] goes to its slot, or a blocked ray counts into its pixel. */
static void trace_shadow_packet(hz_worker_t *w, shadow_packet_t *p, int32_t *valid, uint32_t n, const uint16_t *slot,
                                const uint8_t *gslot, const float (*wt)[3])
{
    w->b.stats.shadow_rays += n;
    w->ctx.flags = HZ_ACCEL_COHERENT;
    for (uint32_t i = 0; i < HZ_RENDER_LANES; i++) {
        valid[i] = i < n ? -1 : 0;
        p->tnear[i] = 0.0f;
        p->mask[i] = 0xffffffffu;
        p->flags[i] = 0;
        w->shadow_vis[i] = 1.0f;
        for (uint32_t k = 0; k < w->shadow_nprims[i]; k++) /* the set is empty otherwise (workers start zeroed) */
            w->shadow_set[i][w->shadow_taken[i][k]] = 0;
        w->shadow_nprims[i] = 0;
        w->shadow_overflow[i] = 0;
    }
    OCCLUDED(valid, w->r->accel, &w->ctx, p);
    for (uint32_t i = 0; i < n; i++) {
        if (p->tfar[i] < 0.0f) { /* -inf: blocked, nothing left after the layers, or past the layer cap */
            w->b.stats.layer_cap += w->shadow_overflow[i];
            count_blocked(w, slot[i], gslot[i]);
        } else {
            const float v = w->shadow_vis[i];
            add_radiance(w, slot[i], wt[i], (const float[3]){ v, v, v });
        }
    }
}

static void process_shadows(hz_worker_t *w)
{
    if (w->shadow_n == 0)
        return;
    shadow_job_t jobs[HZ_RENDER_LANES];
    uint32_t n = take_shadows(w, jobs);
    shadow_packet_t p;
    int32_t valid[HZ_RENDER_LANES] HZ_ALIGNED(32);
    uint16_t slot[HZ_RENDER_LANES];
    uint8_t gslot[HZ_RENDER_LANES];
    float wt[HZ_RENDER_LANES][3];
    for (uint32_t i = 0; i < HZ_RENDER_LANES; i++) {
        const shadow_job_t *j = &jobs[i < n ? i : 0];
        p.org_x[i] = j->o[0], p.org_y[i] = j->o[1], p.org_z[i] = j->o[2];
        p.dir_x[i] = j->d[0], p.dir_y[i] = j->d[1], p.dir_z[i] = j->d[2];
        p.tfar[i] = j->tmax;
        p.time[i] = j->time;
        p.id[i] = i | ID_SHADOW | (j->dither ? ID_SHADOW_DITHER : 0u);
        slot[i] = j->slot, gslot[i] = j->gslot;
        wt[i][0] = j->w[0], wt[i][1] = j->w[1], wt[i][2] = j->w[2];
    }
    trace_shadow_packet(w, &p, valid, n, slot, gslot, (const float(*)[3])wt);
}

/* Queues the shadow ray of job j's hit (kernel lane `lane` of sl) towards light l, adding wt times its
 * transmittance to the job's slot; dither: the ray takes the roulette through blended occluders. */
static void push_cast(hz_worker_t *w, const ray_job_t *j, const hz_shade_light_t *sl, uint32_t lane, uint32_t l,
                      const float wt[3], bool dither)
{
    shadow_job_t sj;
    sj.o[0] = sl->ox[lane], sj.o[1] = sl->oy[lane], sj.o[2] = sl->oz[lane];
    sj.d[0] = sl->dx[lane], sj.d[1] = sl->dy[lane], sj.d[2] = sl->dz[lane];
    sj.tmax = sl->tmax[lane];
    sj.w[0] = wt[0], sj.w[1] = wt[1], sj.w[2] = wt[2];
    sj.time = j->time;
    sj.slot = j->slot;
    sj.gslot = j->gslot;
    sj.light = (uint8_t)l;
    sj.dither = dither;
    push_shadow(w, &sj);
}

/* The shadow rays of one packet's hits towards its first HZ_SHADE_LIGHTS lights, kept in the shading kernel's
 * lanes (hz_shade_out_t.light) instead of the queue: bit i of mask[l], lane i's ray towards light l, weighted
 * wt[l][0..2][i]. */
typedef struct casts {
    uint32_t mask[HZ_SHADE_LIGHTS], dither[HZ_SHADE_LIGHTS];
    float wt[HZ_SHADE_LIGHTS][3][HZ_RENDER_LANES];
} casts_t;

/* A packet's casts after its hits are shaded. Where the queues are empty they are traced straight from the
 * kernel's lanes, in the order the queue would have taken them, so that each slot sums the same terms in the same
 * order: with at most HZ_SHADE_LIGHTS rays per hit, all of them lie within SHADOW_GATHER of the top, so
 * take_shadows takes, light after light, every ray towards the light of the newest ray left (the rays were
 * pushed hit by hit, lights in order). Otherwise they join the queue in that push order. */
static void cast_shadows(hz_worker_t *w, const casts_t *cs, const hz_shade_out_t *so, const ray_job_t *jobs,
                         uint32_t light_count)
{
    typedef char fits_the_window[HZ_SHADE_LIGHTS * HZ_RENDER_LANES <= SHADOW_GATHER ? 1 : -1];
    (void)sizeof(fits_the_window);
    if (w->shadow_n || w->stack_n) {
        for (uint32_t i = 0; i < HZ_RENDER_LANES; i++)
            for (uint32_t l = 0; l < light_count; l++)
                if (cs->mask[l] >> i & 1u)
                    push_cast(w, &jobs[i], &so->light[l], i, l,
                              (const float[3]){ cs->wt[l][0][i], cs->wt[l][1][i], cs->wt[l][2][i] },
                              (cs->dither[l] >> i & 1u) != 0);
        return;
    }
    uint32_t left = 0;
    for (uint32_t l = 0; l < light_count; l++)
        left |= (cs->mask[l] != 0) << l;
    while (left) {
        /* the light of the newest ray left: the highest lane, then the highest light */
        uint32_t pick = 0, key = 0;
        for (uint32_t l = 0; l < light_count; l++) {
            if (!(left >> l & 1u))
                continue;
            const uint32_t k = (31u - (uint32_t)__builtin_clz(cs->mask[l])) * HZ_SHADE_LIGHTS + l + 1u;
            if (k > key)
                key = k, pick = l;
        }
        left &= ~(1u << pick);
        const hz_shade_light_t *sl = &so->light[pick];
        shadow_packet_t p;
        int32_t valid[HZ_RENDER_LANES] HZ_ALIGNED(32);
        uint16_t slot[HZ_RENDER_LANES];
        uint8_t gslot[HZ_RENDER_LANES];
        float wt[HZ_RENDER_LANES][3];
        uint32_t n = 0, lane[HZ_RENDER_LANES];
        for (uint32_t m = cs->mask[pick]; m; m &= m - 1u)
            lane[n++] = (uint32_t)__builtin_ctz(m);
        for (uint32_t q = 0; q < n; q++) {
            const uint32_t i = lane[q];
            p.org_x[q] = sl->ox[i], p.org_y[q] = sl->oy[i], p.org_z[q] = sl->oz[i];
            p.dir_x[q] = sl->dx[i], p.dir_y[q] = sl->dy[i], p.dir_z[q] = sl->dz[i];
            p.tfar[q] = sl->tmax[i];
            p.time[q] = jobs[i].time;
            p.id[q] = q | ID_SHADOW | ((cs->dither[pick] >> i & 1u) ? ID_SHADOW_DITHER : 0u);
            slot[q] = jobs[i].slot, gslot[q] = jobs[i].gslot;
            wt[q][0] = cs->wt[pick][0][i], wt[q][1] = cs->wt[pick][1][i], wt[q][2] = cs->wt[pick][2][i];
        }
        for (uint32_t i = n; i < HZ_RENDER_LANES; i++) { /* off lanes repeat the first ray, as the queue's do */
            p.org_x[i] = p.org_x[0], p.org_y[i] = p.org_y[0], p.org_z[i] = p.org_z[0];
            p.dir_x[i] = p.dir_x[0], p.dir_y[i] = p.dir_y[0], p.dir_z[i] = p.dir_z[0];
            p.tfar[i] = p.tfar[0];
            p.time[i] = p.time[0];
            p.id[i] = i | ID_SHADOW | (p.id[0] & ID_SHADOW_DITHER);
        }
        trace_shadow_packet(w, &p, valid, n, slot, gslot, (const float(*)[3])wt);
    }
}

/* ---- shading ---- */

static void write_mv(float *mv, size_t px, float dx, float dy)
{
    mv[px * 2] = dx;
    mv[px * 2 + 1] = dy;
}

/* Motion of a world point that is at p now and was at pp one frame ago. */
HZ_INLINE void point_motion(const struct hz_renderer *r, hz_vec3_t p, hz_vec3_t pp, float out[2])
{
    hz_view_point_motion(&r->view, &r->prev_view, &p, &pp, out);
}

/* Motion of what lies infinitely far along direction d (the background). */
static void direction_motion(const struct hz_renderer *r, hz_vec3_t d, float out[2])
{
    point_motion(r, hz_v3_add(r->view.eye, d), hz_v3_add(r->prev_view.eye, d), out);
    /* Translation does not move the background: the two points differ only by the eye offset. */
}

HZ_INLINE hz_vec3_t prev_point(const struct hz_renderer *r, uint32_t prim, float u, float v, hz_vec3_t now)
{
    const hz_scene_t *s = r->scene;
    if (!s->prev_pos)
        return now;
    const uint32_t *t = s->tri + (size_t)prim * 3;
    return bary(vtx(s->prev_pos, t[0]), vtx(s->prev_pos, t[1]), vtx(s->prev_pos, t[2]), u, v);
}

/* The hit point (u, v) of prim at the frame's time. */
HZ_INLINE hz_vec3_t frame_point(const struct hz_renderer *r, uint32_t prim, float u, float v)
{
    const hz_scene_t *s = r->scene;
    const uint32_t *t = s->tri + (size_t)prim * 3;
    return bary(vtx(s->pos, t[0]), vtx(s->pos, t[1]), vtx(s->pos, t[2]), u, v);
}

static hz_vec3_t prev_normal(const struct hz_renderer *r, uint32_t prim)
{
    const hz_scene_t *s = r->scene;
    const float *pos = s->prev_pos ? s->prev_pos : s->pos;
    const uint32_t *t = s->tri + (size_t)prim * 3;
    hz_vec3_t p0 = vtx(pos, t[0]);
    return hz_v3_normalize(hz_v3_cross(hz_v3_sub(vtx(pos, t[1]), p0), hz_v3_sub(vtx(pos, t[2]), p0)));
}

static hz_vec3_t mirror_point(hz_vec3_t x, hz_vec3_t m, hz_vec3_t n)
{
    return hz_v3_sub(x, hz_v3_scale(n, 2.0f * hz_v3_dot(hz_v3_sub(x, m), n)));
}

/* The pixel's camera ray has no reflected hit: the secondary record says so. */
static void no_reflection(hz_gbuffer_t *gb, uint32_t px)
{
    gb->object2[px] = HZ_GB_NO_OBJECT;
    if (gb->normal2) {
        gb->normal2[px * 3] = gb->normal2[px * 3 + 1] = gb->normal2[px * 3 + 2] = 0.0f;
        gb->shadow2[px] = 0;
    }
    gb->flags2[px] = 0;
}

static void shade_miss(hz_worker_t *w, const ray_job_t *j)
{
    struct hz_renderer *r = w->r;
    const float *bg = r->scene->header->background;
    const float vis[3] = { bg[0] * j->vis, bg[1] * j->vis, bg[2] * j->vis };
    add_radiance(w, j->slot, j->w, vis);
    uint32_t px = w->b.pixel[j->slot];
    hz_gbuffer_t *gb = &r->f.gb;
    hz_vec3_t d = hz_v3(j->d[0], j->d[1], j->d[2]);
    if (j->gslot == GSLOT_PRIMARY) {
        if (gb->normal) { /* full and adaptive modes (hz_render_mode_keeps_surface) */
            gb->depth[px] = __builtin_inff();
            gb->normal[px * 3] = gb->normal[px * 3 + 1] = gb->normal[px * 3 + 2] = 0.0f;
            gb->shadow[px] = 0;
        }
        gb->object[px] = HZ_GB_NO_OBJECT;
        gb->flags[px] = w->alpha_touched[j->slot] ? HZ_GB_ALPHA : 0;
        if (gb->mv) {
            float mv[2];
            direction_motion(r, d, mv);
            write_mv(gb->mv, px, mv[0], mv[1]);
            if (gb->mv_reflect)
                write_mv(gb->mv_reflect, px, mv[0], mv[1]);
        }
    } else if (j->gslot == GSLOT_SECONDARY) {
        no_reflection(gb, px);
        /* The virtual image of a ray leaving the scene lies along the primary ray's line: the mirror's
         * reflected background moves like the background. */
        if (gb->mv_reflect) {
            gb->mv_reflect[px * 2] = gb->mv[px * 2];
            gb->mv_reflect[px * 2 + 1] = gb->mv[px * 2 + 1];
        }
    }
}

/* The G-buffer record of a camera ray's hit (gslot PRIMARY) at pixel px: depth and normal where the mode keeps
 * them, object, flags, motion vectors (hit_mv: NULL, or the packet's motion vectors,
 * hz_view_motion_lanes, x then y), and for a mirror the data of its reflected hit's motion vector. */
HZ_INLINE void primary_record(hz_worker_t *w, const ray_job_t *j, const hitrec_t *h, uint32_t px, hz_vec3_t p,
                             hz_vec3_t ns, uint16_t object, uint8_t flags, float mirror,
                             const float (*hit_mv)[HZ_SHADE_LANES], uint32_t lane)
{
    struct hz_renderer *r = w->r;
    const hz_scene_t *s = r->scene;
    hz_gbuffer_t *gb = &r->f.gb;
    if (gb->normal) { /* full and adaptive modes (hz_render_mode_keeps_surface) */
        gb->depth[px] = j->travelled + h->t;
        gb->normal[px * 3] = ns.x, gb->normal[px * 3 + 1] = ns.y, gb->normal[px * 3 + 2] = ns.z;
        gb->shadow[px] = 0;
    }
    gb->object[px] = object;
    gb->flags[px] = flags;
    if (!gb->mv)
        return;
    float mv[2];
    /* Motion vectors belong to the frame's time: with blur the hit is at the ray's time instead. hit_mv's come
     * with the packet (no vertex keys: pf is p); pp is needed then only for a mirror. */
    hz_vec3_t pf = p, pp = p;
    if (hit_mv) {
        mv[0] = hit_mv[0][lane], mv[1] = hit_mv[1][lane];
        if (mirror > 0.0f)
            pp = prev_point(r, h->prim, h->u, h->v, p);
    } else {
        pf = HZ_RENDER_KEYS(r) ? frame_point(r, h->prim, h->u, h->v) : p;
        pp = prev_point(r, h->prim, h->u, h->v, pf);
        point_motion(r, pf, pp, mv);
    }
    write_mv(gb->mv, px, mv[0], mv[1]);
    if (gb->mv_reflect)
        write_mv(gb->mv_reflect, px, mv[0], mv[1]); /* replaced by the reflected hit's, if any */
    if (mirror > 0.0f) {
        mirror_rec_t *mr = &w->mirror[j->slot];
        hz_vec3_t n = hz_v3_normalize(hz_v3_cross(hz_v3_sub(vtx(s->pos, s->tri[h->prim * 3 + 1]),
                                                            vtx(s->pos, s->tri[h->prim * 3])),
                                                  hz_v3_sub(vtx(s->pos, s->tri[h->prim * 3 + 2]),
                                                            vtx(s->pos, s->tri[h->prim * 3]))));
        hz_vec3_t np = prev_normal(r, h->prim);
        mr->p[0] = pf.x, mr->p[1] = pf.y, mr->p[2] = pf.z;
        mr->n[0] = n.x, mr->n[1] = n.y, mr->n[2] = n.z;
        mr->pp[0] = pp.x, mr->pp[1] = pp.y, mr->pp[2] = pp.z;
        mr->np[0] = np.x, mr->np[1] = np.y, mr->np[2] = np.z;
    }
}

/* hit_mv: NULL, or the packet's motion vectors of its hits (hz_view_motion_lanes), x then y. */
static void shade_hit(hz_worker_t *w, const ray_job_t *j, const hitrec_t *h, const hz_shade_ctx_t *c,
                      const hz_shade_out_t *so, uint32_t lane, const float (*hit_mv)[HZ_SHADE_LANES], casts_t *cs)
{
    struct hz_renderer *r = w->r;
    const hz_scene_t *s = r->scene;
    surface_t sf;
    surface_from(r, h, so, lane, &sf);
    const hz_material_t *m = sf.m;
    uint32_t px = w->b.pixel[j->slot];
    hz_gbuffer_t *gb = &r->f.gb;
    float mirror = HZ_FEATURE_MIRRORS && r->f.has_mirrors ? m->mirror : 0.0f;

    if (j->gslot == GSLOT_PRIMARY) {
        const uint8_t flags = (uint8_t)(HZ_GB_HIT | (sf.textured ? HZ_GB_TEXTURED : 0) |
                                        (mirror > 0.0f ? HZ_GB_MIRROR : 0) |
                                        (w->alpha_touched[j->slot] || m->alpha_mode != HZ_ALPHA_OPAQUE ? HZ_GB_ALPHA : 0));
        primary_record(w, j, h, px, sf.p, sf.ns, sf.object, flags, mirror, hit_mv, lane);
    } else if (j->gslot == GSLOT_SECONDARY) {
        gb->object2[px] = sf.object;
        if (gb->normal2) {
            gb->normal2[px * 3] = sf.ns.x, gb->normal2[px * 3 + 1] = sf.ns.y, gb->normal2[px * 3 + 2] = sf.ns.z;
            gb->shadow2[px] = 0;
        }
        gb->flags2[px] = (uint8_t)(HZ_GB_HIT | (sf.textured ? HZ_GB_TEXTURED : 0) | (mirror > 0.0f ? HZ_GB_MIRROR : 0) |
                                   (m->alpha_mode != HZ_ALPHA_OPAQUE ? HZ_GB_ALPHA : 0));
        if (gb->mv_reflect) {
            const mirror_rec_t *mr = &w->mirror[j->slot];
            hz_vec3_t pf = HZ_RENDER_KEYS(r) ? frame_point(r, h->prim, h->u, h->v) : sf.p;
            hz_vec3_t pp = prev_point(r, h->prim, h->u, h->v, pf);
            hz_vec3_t v = mirror_point(pf, hz_v3(mr->p[0], mr->p[1], mr->p[2]), hz_v3(mr->n[0], mr->n[1], mr->n[2]));
            hz_vec3_t vp = mirror_point(pp, hz_v3(mr->pp[0], mr->pp[1], mr->pp[2]),
                                        hz_v3(mr->np[0], mr->np[1], mr->np[2]));
            float mv[2];
            point_motion(r, v, vp, mv);
            write_mv(gb->mv_reflect, px, mv[0], mv[1]);
        }
    }

    /* Blended surface: it takes alpha of what reaches it; the rest continues behind it. A stochastic ray's
     * fragment survived its decision: opaque. */
    float a = !HZ_FEATURE_TRANSPARENCY || j->dither ? 1.0f : sf.alpha;
    float wc[3] = { j->w[0] * j->vis * a, j->w[1] * j->vis * a, j->w[2] * j->vis * a };
    if (a < 1.0f) {
        float vis = j->vis * (1.0f - a);
        if (!(vis >= r->f.opts.min_visibility)) {
            /* What is left is below the threshold: dropped, as the exact method prescribes. */
        } else if (j->layers + 1u >= HZ_RENDER_MAX_LAYERS) {
            w->b.stats.layer_cap++;
        } else {
            ray_job_t c = *j;
            hz_vec3_t o = hz_accel_offset_origin(sf.p, hz_v3_neg(sf.ng), r->offset_scale);
            c.o[0] = o.x, c.o[1] = o.y, c.o[2] = o.z;
            c.travelled = j->travelled + h->t;
            c.cone_w = j->cone_w + j->cone_s * h->t;
            c.vis = vis;
            c.layers = (uint16_t)(j->layers + 1u);
            c.gslot = GSLOT_NONE;
            /* hybrid: exact while the path's visibility is above X, then one stochastic ray */
            c.dither = HZ_FEATURE_TRANSPARENCY && r->f.dither && j->bounces == 0 && !(vis > r->f.opts.hybrid_x);
            push_ray(w, &c);
        }
    }
    if (!(wc[0] > 0.0f || wc[1] > 0.0f || wc[2] > 0.0f) && j->gslot == GSLOT_NONE)
        return;

    /* Direct light from every point light, through one shadow ray each. */
    float diffuse = 1.0f - mirror;
    float kd[3] = { wc[0] * diffuse * sf.albedo[0], wc[1] * diffuse * sf.albedo[1], wc[2] * diffuse * sf.albedo[2] };
    hz_vec3_t o_light = hz_v3(so->lox[lane], so->loy[lane], so->loz[lane]);
    for (uint32_t l = 0; l < r->light_count; l++) {
        const hz_light_t *lt = &r->lights[l];
        /* The packet computed the first lights for every lane; the rest come one lane at a time. */
        hz_shade_light_t one;
        const hz_shade_light_t *sl = l < HZ_SHADE_LIGHTS ? &so->light[l] : &one;
        bool lit = l < HZ_SHADE_LIGHTS ? (so->lit[l] >> lane & 1u) != 0 : hz_shade_light_lane(c, so, lane, l, &one);
        if (!lit) {
            if (j->gslot != GSLOT_NONE)
                count_blocked(w, j->slot, j->gslot);
            continue;
        }
        float k = sl->k[lane];
        const float wt[3] = { kd[0] * lt->color[0] * k, kd[1] * lt->color[1] * k, kd[2] * lt->color[2] * k };
        const bool rr = j->dither && r->f.opts.rr_shadows;
        if (cs) {
            cs->mask[l] |= 1u << lane;
            cs->dither[l] |= (uint32_t)rr << lane;
            for (int ch = 0; ch < 3; ch++)
                cs->wt[l][ch][lane] = wt[ch];
        } else {
            push_cast(w, j, sl, lane, l, wt, rr);
        }
    }
    const float *amb = s->header->ambient;
    float ka[3] = { kd[0] * amb[0], kd[1] * amb[1], kd[2] * amb[2] };
    add_radiance(w, j->slot, (const float[3]){ 1.0f, 1.0f, 1.0f }, ka);

    /* Mirror reflection. */
    if (mirror > 0.0f && j->bounces < r->f.opts.max_bounces) {
        hz_vec3_t d = hz_v3(j->d[0], j->d[1], j->d[2]);
        hz_vec3_t rd = hz_v3_sub(d, hz_v3_scale(sf.ns, 2.0f * hz_v3_dot(d, sf.ns)));
        if (!(hz_v3_dot(rd, sf.ng) > 0.0f))
            rd = hz_v3_sub(d, hz_v3_scale(sf.ng, 2.0f * hz_v3_dot(d, sf.ng)));
        rd = hz_v3_normalize(rd);
        ray_job_t c = *j;
        hz_vec3_t o = o_light;
        c.o[0] = o.x, c.o[1] = o.y, c.o[2] = o.z;
        c.d[0] = rd.x, c.d[1] = rd.y, c.d[2] = rd.z;
        c.w[0] = wc[0] * mirror, c.w[1] = wc[1] * mirror, c.w[2] = wc[2] * mirror;
        c.vis = 1.0f;
        c.travelled = j->travelled + h->t;
        c.cone_w = j->cone_w + j->cone_s * h->t;
        c.bounces = (uint8_t)(j->bounces + 1u);
        c.gslot = j->gslot == GSLOT_PRIMARY ? GSLOT_SECONDARY : GSLOT_NONE;
        c.dither = 0; /* reflections composite exactly */
        push_ray(w, &c);
    } else if (j->gslot == GSLOT_PRIMARY && r->f.gb.object2) {
        no_reflection(gb, px);
    }
}

/* Of a packet's hits (bits of `hits_mask`), the camera rays' on surfaces that neither reflect nor let light
 * through where the ray takes no stochastic decision, as shade_hit shades them, the packet at once: their
 * G-buffer records, the lights' casts and the ambient term (up to HZ_SHADE_LIGHTS lights). The same operations in
 * the same order for every value, and camera rays have slots of their own, so the results are shade_hit's bits
 * (scalar_shading takes shade_hit). Returns the lanes it shaded. */
static uint32_t shade_camera_hits(hz_worker_t *w, const ray_job_t *jobs, const hitrec_t *hits,
                                  const hz_shade_out_t *so, uint32_t hits_mask,
                                  const float (*hit_mv)[HZ_SHADE_LANES], casts_t *cs)
{
    enum { L = HZ_RENDER_LANES };
    struct hz_renderer *r = w->r;
    const hz_scene_t *s = r->scene;
    /* The job fields and the factors the weights need, lane by lane; then the weights in whole-packet loops
     * without branches (the compiler makes them vector operations: the same IEEE operations in the same order
     * as the per-hit code, lanes the packet does not shade computed and left unread). */
    float jw[3][L] HZ_ALIGNED(32), jvis[L] HZ_ALIGNED(32), ja[L] HZ_ALIGNED(32), dif[L] HZ_ALIGNED(32);
    float kd[3][L] HZ_ALIGNED(32);
    uint32_t taken = 0, named = 0, rr = 0; /* lanes shaded here; those a G-buffer slot names; roulette casts */
    for (uint32_t i = 0; i < L; i++) {
        jw[0][i] = jw[1][i] = jw[2][i] = jvis[i] = ja[i] = dif[i] = 0.0f;
    }
    for (uint32_t m = hits_mask; m; m &= m - 1u) {
        const uint32_t i = (uint32_t)__builtin_ctz(m);
        const ray_job_t *j = &jobs[i];
        const uint32_t info = s->tri_info[hits[i].prim];
        const hz_material_t *mat = &s->materials[info & 0xffffu];
        const float mirror = HZ_FEATURE_MIRRORS && r->f.has_mirrors ? mat->mirror : 0.0f;
        const float a = !HZ_FEATURE_TRANSPARENCY || j->dither ? 1.0f : so->alpha[i];
        if (j->bounces || j->layers || mirror > 0.0f || a < 1.0f)
            continue; /* a reflection, a continuation ray, a mirror or a blended layer: shade_hit's */
        taken |= 1u << i;
        named |= (uint32_t)(j->gslot != GSLOT_NONE) << i;
        rr |= (uint32_t)(j->dither && r->f.opts.rr_shadows) << i;
        if (j->gslot == GSLOT_PRIMARY) {
            const uint8_t flags = (uint8_t)(HZ_GB_HIT | (so->textured[i] ? HZ_GB_TEXTURED : 0) |
                                            (w->alpha_touched[j->slot] || mat->alpha_mode != HZ_ALPHA_OPAQUE ? HZ_GB_ALPHA : 0));
            primary_record(w, j, &hits[i], w->b.pixel[j->slot], hz_v3(so->px[i], so->py[i], so->pz[i]),
                           hz_v3(so->nsx[i], so->nsy[i], so->nsz[i]), (uint16_t)(info >> 16), flags, mirror,
                           hit_mv, i);
            if (r->f.gb.object2)
                no_reflection(&r->f.gb, w->b.pixel[j->slot]);
        }
        jw[0][i] = j->w[0], jw[1][i] = j->w[1], jw[2][i] = j->w[2];
        jvis[i] = j->vis, ja[i] = a, dif[i] = 1.0f - mirror;
    }
    if (!taken)
        return 0;
    /* wc = w vis a, kd = wc (1 - mirror) albedo; lit where some wc > 0 or the ray names a G-buffer slot */
    uint32_t lit = named & taken;
    for (int ch = 0; ch < 3; ch++) {
        float wc[L] HZ_ALIGNED(32);
        for (uint32_t i = 0; i < L; i++) {
            wc[i] = jw[ch][i] * jvis[i] * ja[i];
            kd[ch][i] = wc[i] * dif[i] * so->albedo[ch][i];
        }
        for (uint32_t i = 0; i < L; i++)
            lit |= (uint32_t)(wc[i] > 0.0f) << i & taken;
    }
    const float *amb = s->header->ambient;
    for (uint32_t m = lit; m; m &= m - 1u) {
        const uint32_t i = (uint32_t)__builtin_ctz(m);
        const float ka[3] = { kd[0][i] * amb[0], kd[1][i] * amb[1], kd[2][i] * amb[2] };
        add_radiance(w, jobs[i].slot, (const float[3]){ 1.0f, 1.0f, 1.0f }, ka);
    }
    for (uint32_t l = 0; l < r->light_count; l++) {
        const float *col = r->lights[l].color, *k = so->light[l].k;
        const uint32_t cast = so->lit[l] & lit;
        /* unlit: a camera ray counts into its pixel's shadow count (modes that keep one) */
        for (uint32_t m = r->f.gb.shadow ? lit & ~cast : 0u; m; m &= m - 1u) {
            const uint32_t i = (uint32_t)__builtin_ctz(m);
            if (jobs[i].gslot != GSLOT_NONE)
                count_blocked(w, jobs[i].slot, jobs[i].gslot);
        }
        if (!cast)
            continue;
        cs->mask[l] |= cast;
        cs->dither[l] |= cast & rr;
        /* every lane: the lanes of `cast` are read; shade_hit, which runs after, writes its own */
        for (int ch = 0; ch < 3; ch++)
            for (uint32_t i = 0; i < L; i++)
                cs->wt[l][ch][i] = kd[ch][i] * col[ch] * k[i];
    }
    return taken;
}

/* Shades a packet's n jobs in order: their surfaces first, all lanes at once (src/render/shade.h), then job by job
 * what each adds (G-buffer, continuation and mirror rays, the light loop's shadow rays). */
static void shade_packet(hz_worker_t *w, const ray_job_t *jobs, const hitrec_t *hits, uint32_t n)
{
    const struct hz_renderer *r = w->r;
    hz_shade_in_t in;
    hz_shade_out_t out;
    /* Textures filtered over the pixel where the batch asks: the frame camera's pixel steps (with camera blur a
     * ray's own camera differs from it by the shutter's motion, a small change of a filter's width). */
    const bool foot = HZ_FEATURE_TEXTURES && w->b.footprint && r->has_textures;
    const hz_shade_ctx_t c = { r->scene,         HZ_RENDER_KEYS(r), HZ_FEATURE_TEXTURES && r->has_textures,
                               r->lights,        r->light_count,    r->offset_scale,
                               foot ? &r->footprint : NULL };
    uint32_t mask = 0, live = 0;
    for (uint32_t i = 0; i < n; i++)
        if (hits[i].prim != HZ_ACCEL_INVALID_ID) {
            if (!mask)
                live = i;
            mask |= 1u << i;
        }
    if (mask) {
        for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
            uint32_t k = mask >> i & 1u ? i : live; /* empty lanes repeat a live one: valid gathers */
            const ray_job_t *j = &jobs[k];
            in.prim[i] = hits[k].prim, in.u[i] = hits[k].u, in.v[i] = hits[k].v, in.t[i] = hits[k].t;
            in.dx[i] = j->d[0], in.dy[i] = j->d[1], in.dz[i] = j->d[2];
            in.time[i] = j->time, in.cone_w[i] = j->cone_w, in.cone_s[i] = j->cone_s;
            in.eye_dist[i] = foot && j->bounces == 0 ? j->travelled + hits[k].t : 0.0f; /* on the camera ray's line */
        }
        (r->f.opts.scalar_shading ? hz_shade_surfaces_scalar : hz_shade_surfaces)(&c, &in, mask, &out);
    }
    /* Primary hits get their motion vectors for the whole packet at once, from the hit point and, where the scene
     * moves, the same (u, v) on the previous pose (prev_point's point, gathered lane by lane); with vertex keys a
     * hit's frame point differs from its point, and the scalar twin (scalar_shading) keeps them per hit. */
    float hit_mv[2][HZ_SHADE_LANES] HZ_ALIGNED(32);
    uint32_t primary = 0; /* hit lanes of camera rays: the only ones that read hit_mv */
    for (uint32_t m = mask; m; m &= m - 1u)
        primary |= (uint32_t)(jobs[__builtin_ctz(m)].gslot == GSLOT_PRIMARY) << __builtin_ctz(m);
    const bool lanes_mv = primary && w->write_gbuffer && r->f.gb.mv && !HZ_RENDER_KEYS(r) &&
                          !r->f.opts.scalar_shading;
    if (lanes_mv) {
        const float *const p[3] = { out.px, out.py, out.pz };
        float prev[3][HZ_SHADE_LANES] HZ_ALIGNED(32);
        const float *const pp[3] = { prev[0], prev[1], prev[2] };
        if (r->scene->prev_pos) {
            for (uint32_t i = 0; i < HZ_SHADE_LANES; i++) {
                hz_vec3_t q = hz_v3(out.px[i], out.py[i], out.pz[i]);
                if (primary >> i & 1u)
                    q = prev_point(r, hits[i].prim, hits[i].u, hits[i].v, q);
                prev[0][i] = q.x, prev[1][i] = q.y, prev[2][i] = q.z;
            }
        }
        hz_view_motion_lanes(&r->view, &r->prev_view, p, r->scene->prev_pos ? pp : p, hit_mv[0], hit_mv[1]);
    }
    /* the shadow rays of up to HZ_SHADE_LIGHTS lights wait in the kernel's lanes (cast_shadows) */
    casts_t cs;
    const bool cast = r->light_count <= HZ_SHADE_LIGHTS && !r->f.opts.scalar_shading; /* the twin: the queue */
    uint32_t camera = 0; /* hits shade_camera_hits shaded */
    if (cast) {
        for (uint32_t l = 0; l < HZ_SHADE_LIGHTS; l++)
            cs.mask[l] = cs.dither[l] = 0;
        camera = shade_camera_hits(w, jobs, hits, &out, mask,
                                   lanes_mv ? (const float(*)[HZ_SHADE_LANES])hit_mv : NULL, &cs);
    }
    for (uint32_t i = 0; i < n; i++) {
        const ray_job_t *j = &jobs[i];
        if (hits[i].prim == HZ_ACCEL_INVALID_ID)
            shade_miss(w, j);
        else if (!(camera >> i & 1u))
            shade_hit(w, j, &hits[i], &c, &out, i,
                      lanes_mv && j->gslot == GSLOT_PRIMARY ? (const float(*)[HZ_SHADE_LANES])hit_mv : NULL,
                      cast ? &cs : NULL);
        if (j->dither && w->write_gbuffer && w->dither_touched[j->slot])
            w->r->f.gb.flags[w->b.pixel[j->slot]] |= HZ_GB_DITHER; /* the opacity mask TAA reads */
    }
    if (cast && mask)
        cast_shadows(w, &cs, &out, jobs, r->light_count);
}

/* Everything queued: rays depth first in packets, shadow rays whenever a packet's worth is waiting. */
static void drain(hz_worker_t *w)
{
    ray_job_t jobs[HZ_RENDER_LANES];
    hitrec_t hits[HZ_RENDER_LANES];
    while (w->stack_n || w->shadow_n) {
        if (w->shadow_n >= HZ_RENDER_LANES || w->stack_n == 0) {
            process_shadows(w);
            continue;
        }
        uint32_t n = w->stack_n < HZ_RENDER_LANES ? w->stack_n : HZ_RENDER_LANES;
        w->stack_n -= n;
        for (uint32_t i = 0; i < n; i++)
            jobs[i] = w->stack[w->stack_n + i];
        w->b.stats.secondary_rays += n;
        intersect_jobs(w, jobs, n, hits);
        shade_packet(w, jobs, hits, n);
    }
}

/* Motion blur: the camera at shutter time t in [0, 1), between the two nearest of the shutter's views. */
static void view_at(const struct hz_renderer *r, float t, hz_view_t *v)
{
    float fs = t * (float)(HZ_RENDER_CAMERA_KEYS - 1);
    uint32_t i = (uint32_t)fs;
    if (i > HZ_RENDER_CAMERA_KEYS - 2)
        i = HZ_RENDER_CAMERA_KEYS - 2;
    float f = fs - (float)i;
    const hz_view_t *a = &r->cam_views[i], *b = &r->cam_views[i + 1];
    *v = *a;
    v->eye = hz_v3_lerp(a->eye, b->eye, f);
    v->fwd = hz_v3_lerp(a->fwd, b->fwd, f);
    v->right = hz_v3_lerp(a->right, b->right, f);
    v->up = hz_v3_lerp(a->up, b->up, f);
    v->spread = a->spread + (b->spread - a->spread) * f;
}

void hz_render_trace(hz_render_frame_t *f, hz_batch_t *b, const float (*jitter)[2], const float *times,
                     bool write_gbuffer)
{
    hz_worker_t *w = (hz_worker_t *)(void *)b; /* the batch is the worker's first member */
    struct hz_renderer *r = w->r;
    (void)f;
    const hz_view_t *v = &r->view;
    hz_view_t vt;
    ray_job_t jobs[HZ_TILE_PIXELS];
    hitrec_t hits[HZ_TILE_PIXELS];
    uint32_t count[BATCH_PACKETS];
    hz_memset(w->alpha_touched, 0, sizeof w->alpha_touched);
    hz_memset(w->dither_touched, 0, sizeof w->dither_touched);
    if (HZ_FEATURE_TRANSPARENCY && r->f.dither)
        hz_transp_cells(w);
    w->write_gbuffer = write_gbuffer;
    /* Stochastic from the first hit, unless hybrid's threshold lies below full visibility. */
    uint16_t dither = HZ_FEATURE_TRANSPARENCY && r->f.dither &&
                      (r->f.opts.transparency != HZ_TRANSP_HYBRID || !(1.0f > r->f.opts.hybrid_x));
    /* every camera ray of the batch first, traced as one tile; then packet by packet, shading and all it spawns
     * (the hits do not depend on the order, and the any-hit calls of camera rays touch their own slots only) */
    ray_job_t proto; /* what every camera ray shares */
    proto.o[0] = v->eye.x, proto.o[1] = v->eye.y, proto.o[2] = v->eye.z;
    proto.w[0] = proto.w[1] = proto.w[2] = 1.0f;
    proto.cone_w = 0.0f;
    proto.cone_s = v->spread;
    proto.travelled = 0.0f;
    proto.vis = 1.0f;
    proto.time = r->time;
    proto.gslot = write_gbuffer ? GSLOT_PRIMARY : GSLOT_NONE;
    proto.bounces = 0;
    proto.layers = 0;
    proto.dither = dither;
    const bool cam_blur = HZ_FEATURE_MOTION && times && r->cam_blur; /* each ray its own camera */
    const uint32_t width = v->width;
    for (uint32_t base = 0; base < HZ_TILE_PIXELS; base += HZ_RENDER_LANES) {
        uint32_t n = 0;
        float x[HZ_RENDER_LANES] HZ_ALIGNED(32), y[HZ_RENDER_LANES] HZ_ALIGNED(32);
        float dx[HZ_RENDER_LANES] HZ_ALIGNED(32), dy[HZ_RENDER_LANES] HZ_ALIGNED(32), dz[HZ_RENDER_LANES] HZ_ALIGNED(32);
        uint16_t slots[HZ_RENDER_LANES];
        for (uint32_t i = 0; i < HZ_RENDER_LANES; i++) {
            const uint32_t slot = base + i, px = w->b.pixel[slot];
            x[i] = y[i] = 0.5f; /* unused lanes */
            if (px == UINT32_MAX)
                continue;
            x[n] = (float)(px % width) + 0.5f + jitter[slot][0];
            y[n] = (float)(px / width) + 0.5f + jitter[slot][1];
            slots[n++] = (uint16_t)slot;
        }
        if (n && !cam_blur)
            hz_view_ray_dirs(v, x, y, dx, dy, dz);
        for (uint32_t q = 0; q < n; q++) {
            ray_job_t *j = &jobs[base + q];
            const uint32_t slot = slots[q];
            *j = proto;
            j->slot = (uint16_t)slot;
            if (times)
                j->time = r->tmap_a + times[slot] * r->tmap_b;
            if (cam_blur) {
                view_at(r, times[slot], &vt);
                const hz_vec3_t d = hz_view_ray_dir(&vt, x[q], y[q]);
                j->o[0] = vt.eye.x, j->o[1] = vt.eye.y, j->o[2] = vt.eye.z;
                j->d[0] = d.x, j->d[1] = d.y, j->d[2] = d.z;
                j->cone_s = vt.spread;
            } else {
                j->d[0] = dx[q], j->d[1] = dy[q], j->d[2] = dz[q];
            }
        }
        count[base / HZ_RENDER_LANES] = n;
    }
    intersect_batch(w, jobs, count, hits);
    for (uint32_t base = 0; base < HZ_TILE_PIXELS; base += HZ_RENDER_LANES) {
        const uint32_t n = count[base / HZ_RENDER_LANES];
        if (n == 0)
            continue;
        w->b.stats.primary_rays += n;
        shade_packet(w, jobs + base, hits + base, n);
        drain(w);
    }
}

void hz_tile_slots(const struct hz_renderer *r, uint32_t tile, uint32_t pixel[HZ_TILE_PIXELS])
{
    uint32_t tx = tile % r->f.tiles_x, ty = tile / r->f.tiles_x;
    /* Packets of 4x2 pixels (8 lanes) or 2x2 (4 lanes), row by row inside the tile. */
    const uint32_t pw = HZ_RENDER_LANES == 8 ? 4 : 2, ph = 2;
    const uint32_t per_row = HZ_RENDER_TILE / pw;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t packet = slot / HZ_RENDER_LANES, lane = slot % HZ_RENDER_LANES;
        uint32_t x = tx * HZ_RENDER_TILE + (packet % per_row) * pw + lane % pw;
        uint32_t y = ty * HZ_RENDER_TILE + (packet / per_row) * ph + lane / pw;
        pixel[slot] = x < r->f.opts.width && y < r->f.opts.height ? y * r->f.opts.width + x : UINT32_MAX;
    }
}
