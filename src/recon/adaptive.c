/* Selective and adaptive supersampling (seed 003): the presample's attribute map, the per-tile subpixel test
 * and the packed extra samples with their accumulation (see hz/adaptive.h; the mask is hz/adaptive_mask.h). */
#include "../render/mode.h"
#include "hz/adaptive.h"
#include "hz/hash.h"
#include "hz/vmath.h"

/* The mode's state: the presample (the colour reference and the output), the compact attribute map and the
 * activity mask of this frame. */
typedef struct adaptive_state {
    hz_image_t out;
    hz_amask_config_t cfg;
    hz_amask_hit_t *attr;      /* levels hits per pixel (primary, then the mirror hit where the scene has mirrors) */
    uint32_t levels;
    uint8_t *mask;             /* bit q: subpixel q active */
    float *pre;                /* bilinear only: the presample's colours (out is rewritten in pass 2) */
} adaptive_state_t;

void hz_adaptive_opts_default(hz_adaptive_opts_t *o)
{
    hz_memset(o, 0, sizeof *o);
    /* Table 2's caption; tau_alpha = tau_col = tau_pte = tau_ste = 0.6 */
    static const float tau[HZ_TAU_COUNT] = { 0.6f, 0.05f, 0.06f, 0.06f, 0.6f, 0.05f, 0.06f, 0.06f, 0.6f };
    for (int k = 0; k < HZ_TAU_COUNT; k++)
        o->tau[k] = tau[k];
    o->normal_angle_deg = 15.0f;
}

const char *hz_tau_name(hz_tau_t k)
{
    static const char *const names[HZ_TAU_COUNT] = { "col", "poid", "psn", "psc", "pte", "soid", "ssn", "ssc",
                                                     "ste" };
    return (unsigned)k < HZ_TAU_COUNT ? names[k] : "unknown";
}

/* cos of an angle in degrees in [0, 90], by its Taylor series (no libm in src/): |error| < 1e-7. */
static float cos_deg(float deg)
{
    float x = deg * 0.017453292519943295f, x2 = x * x, term = 1.0f, sum = 1.0f;
    for (int k = 1; k < 12; k++) {
        term *= -x2 / (float)((2 * k - 1) * (2 * k));
        sum += term;
    }
    return sum;
}

hz_status_t hz_adaptive_config(const hz_adaptive_opts_t *o, hz_amask_config_t *c, hz_error_t *err)
{
    hz_amask_config_default(c);
    for (int k = 0; k < HZ_TAU_COUNT; k++) {
        float t = o->tau[k];
        if (!(t >= 0.0f && t <= 1.0f))
            return hz_error_set(err, HZ_E_INVALID_ARG, "adaptive threshold tau-%s must lie in [0, 1]",
                                hz_tau_name((hz_tau_t)k));
        c->tau[k] = (uint32_t)(t * 65536.0f + 0.5f);
    }
    if (!(o->normal_angle_deg >= 0.0f && o->normal_angle_deg <= 90.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "adaptive normal angle must lie in [0, 90] degrees");
    c->normal_cos = (int32_t)(cos_deg(o->normal_angle_deg) * 32768.0f + 0.5f);
    if (o->focus_count > HZ_AMASK_MAX_FOCUS)
        return hz_error_set(err, HZ_E_INVALID_ARG, "adaptive focus list: %u objects, at most %u", o->focus_count,
                            HZ_AMASK_MAX_FOCUS);
    /* sorted, without duplicates (insertion sort: at most 64) */
    c->focus_count = 0;
    for (uint32_t i = 0; i < o->focus_count; i++) {
        uint16_t v = o->focus[i];
        uint32_t j = c->focus_count;
        bool dup = false;
        for (uint32_t k = 0; k < c->focus_count; k++)
            dup = dup || c->focus[k] == v;
        if (dup)
            continue;
        while (j > 0 && c->focus[j - 1] > v) {
            c->focus[j] = c->focus[j - 1];
            j--;
        }
        c->focus[j] = v;
        c->focus_count++;
    }
    return HZ_OK;
}

void hz_adaptive_weights(uint32_t active, float *centre, float *sample)
{
    active = active > 4u ? 4u : active;
    *centre = (float)(4u - active) * 0.25f;
    *sample = 1.0f / 16.0f;
}

uint32_t hz_adaptive_attr_bytes_per_pixel(int mirrors)
{
    return (uint32_t)sizeof(hz_amask_hit_t) * (mirrors ? 2u : 1u);
}

size_t hz_adaptive_frame_bytes(uint32_t width, uint32_t height, int mirrors)
{
    size_t px = (size_t)width * height;
    return hz_align_up(px * hz_adaptive_attr_bytes_per_pixel(mirrors), 64) + 64 + hz_align_up(px, 64) + 64;
}

static void ad_layout(void *state, const hz_render_frame_t *f, hz_memplan_t *p)
{
    adaptive_state_t *a = state;
    const size_t px = (size_t)f->opts.width * f->opts.height;
    a->out.width = f->opts.width, a->out.height = f->opts.height;
    hz_memplan_part(p, HZ_PART_DISPLAY);
    a->out.rgb = hz_memplan_array(p, px, 12);
    hz_memplan_part(p, HZ_PART_STATE);
    a->levels = f->has_mirrors ? 2u : 1u;
    a->attr = hz_memplan_array(p, px * a->levels, sizeof(hz_amask_hit_t));
    a->mask = hz_memplan_alloc(p, px);
    a->pre = f->opts.adaptive.bilinear ? hz_memplan_array(p, px, 12) : NULL;
}

static hz_status_t ad_init(void *state, const hz_render_frame_t *f, hz_error_t *err)
{
    adaptive_state_t *a = state;
    hz_status_t s = hz_adaptive_config(&f->opts.adaptive, &a->cfg, err);
    if (s != HZ_OK)
        return s;
    const size_t px = (size_t)f->opts.width * f->opts.height;
    hz_memset(a->out.rgb, 0, px * 12);
    hz_memset(a->mask, 0, px);
    return HZ_OK;
}

/* ---- pass 0: the attribute map ---- */

static int8_t snorm8(float v)
{
    if (!(v > -1.0f))
        return v <= -1.0f ? -127 : 0; /* NaN: no direction */
    if (v >= 1.0f)
        return 127;
    float s = v * 127.0f;
    return (int8_t)(int32_t)(s >= 0.0f ? s + 0.5f : s - 0.5f);
}

static void pack_hit(hz_amask_hit_t *h, uint16_t object, const float *n, uint8_t shadow, uint8_t flags)
{
    h->object = object;
    for (int c = 0; c < 3; c++)
        h->n[c] = snorm8(n[c]);
    h->shadow = shadow;
    h->flags = (uint8_t)(((flags & HZ_GB_HIT) ? HZ_AMASK_HIT : 0u) | ((flags & HZ_GB_TEXTURED) ? HZ_AMASK_TEXTURED : 0u));
    h->pad = 0;
}

static void keep_attrs(adaptive_state_t *a, const hz_render_frame_t *f, const hz_batch_t *b)
{
    const hz_gbuffer_t *gb = &f->gb;
    for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
        uint32_t px = b->pixel[slot];
        if (px == UINT32_MAX)
            continue;
        hz_amask_hit_t *h = &a->attr[(size_t)px * a->levels];
        pack_hit(&h[0], gb->object[px], gb->normal + (size_t)px * 3, gb->shadow[px], gb->flags[px]);
        if (a->levels == 2)
            pack_hit(&h[1], gb->object2[px], gb->normal2 + (size_t)px * 3, gb->shadow2[px], gb->flags2[px]);
    }
}

/* ---- pass 1: the subpixel test ---- */

static void tile_rect(const hz_render_frame_t *f, uint32_t tile, uint32_t *x0, uint32_t *y0, uint32_t *tw,
                      uint32_t *th)
{
    *x0 = (tile % f->tiles_x) * HZ_RENDER_TILE;
    *y0 = (tile / f->tiles_x) * HZ_RENDER_TILE;
    *tw = f->opts.width - *x0 < HZ_RENDER_TILE ? f->opts.width - *x0 : HZ_RENDER_TILE;
    *th = f->opts.height - *y0 < HZ_RENDER_TILE ? f->opts.height - *y0 : HZ_RENDER_TILE;
}

static void test_tile(adaptive_state_t *a, const hz_render_frame_t *f, uint32_t tile)
{
    enum { S = HZ_RENDER_TILE + 2 };
    hz_amask_px_t win[S * S];
    uint32_t x0, y0, tw, th;
    tile_rect(f, tile, &x0, &y0, &tw, &th);
    const int32_t W = (int32_t)f->opts.width, H = (int32_t)f->opts.height;
    for (uint32_t wy = 0; wy < th + 2; wy++)
        for (uint32_t wx = 0; wx < tw + 2; wx++) {
            int32_t x = (int32_t)(x0 + wx) - 1, y = (int32_t)(y0 + wy) - 1;
            x = x < 0 ? 0 : x >= W ? W - 1 : x; /* the image edge replicates */
            y = y < 0 ? 0 : y >= H ? H - 1 : y;
            size_t px = (size_t)y * (size_t)W + (size_t)x;
            hz_amask_px_t *p = &win[wy * S + wx];
            hz_memcpy(p->rgb, a->out.rgb + px * 3, sizeof p->rgb); /* the bits of the colour reference */
            hz_memcpy(&p->hit[0], &a->attr[px * a->levels], sizeof(hz_amask_hit_t));
            if (a->levels == 2) {
                hz_memcpy(&p->hit[1], &a->attr[px * 2 + 1], sizeof(hz_amask_hit_t));
            } else {
                hz_memset(&p->hit[1], 0, sizeof(hz_amask_hit_t));
                p->hit[1].object = HZ_GB_NO_OBJECT;
            }
        }
    hz_amask_block(&a->cfg, win, S, tw, th, a->mask + (size_t)y0 * f->opts.width + x0, f->opts.width);
    if (a->pre) /* every tile's copy is made before pass 2 rewrites any pixel of out */
        for (uint32_t y = 0; y < th; y++) {
            size_t row = ((size_t)(y0 + y) * f->opts.width + x0) * 3;
            hz_memcpy(a->pre + row, a->out.rgb + row, (size_t)tw * 12);
        }
}

/* The presample's colour c at (x, y) in pixel units (pixel centres at integers + 0.5), interpolated bilinearly
 * between the four nearest centres; the image edge replicates. */
static void bilinear_at(const adaptive_state_t *a, uint32_t w, uint32_t h, float x, float y, float c[3])
{
    float fx = x - 0.5f, fy = y - 0.5f;
    int32_t ix = (int32_t)(fx < 0.0f ? -1.0f : fx), iy = (int32_t)(fy < 0.0f ? -1.0f : fy);
    float tx = fx - (float)ix, ty = fy - (float)iy;
    int32_t xs[2] = { ix, ix + 1 }, ys[2] = { iy, iy + 1 };
    for (int k = 0; k < 2; k++) {
        xs[k] = xs[k] < 0 ? 0 : xs[k] >= (int32_t)w ? (int32_t)w - 1 : xs[k];
        ys[k] = ys[k] < 0 ? 0 : ys[k] >= (int32_t)h ? (int32_t)h - 1 : ys[k];
    }
    const float *p00 = a->pre + ((size_t)ys[0] * w + (size_t)xs[0]) * 3, *p10 = a->pre + ((size_t)ys[0] * w + (size_t)xs[1]) * 3;
    const float *p01 = a->pre + ((size_t)ys[1] * w + (size_t)xs[0]) * 3, *p11 = a->pre + ((size_t)ys[1] * w + (size_t)xs[1]) * 3;
    for (int ch = 0; ch < 3; ch++) {
        float top = p00[ch] + (p10[ch] - p00[ch]) * tx, bottom = p01[ch] + (p11[ch] - p01[ch]) * tx;
        c[ch] = top + (bottom - top) * ty;
    }
}

/* ---- pass 2: extra samples ---- */

static void extra_tile(adaptive_state_t *a, hz_render_frame_t *f, uint32_t tile, hz_batch_t *b)
{
    uint16_t list[4 * HZ_TILE_PIXELS];
    float acc[HZ_TILE_PIXELS * 3];
    float jitter[HZ_TILE_PIXELS][2], times[HZ_TILE_PIXELS];
    const bool blur = HZ_FEATURE_MOTION && f->blur;
    uint32_t x0, y0, tw, th;
    tile_rect(f, tile, &x0, &y0, &tw, &th);
    const uint32_t W = f->opts.width;
    const uint8_t *mask = a->mask + (size_t)y0 * W + x0;
    uint32_t n = hz_amask_pack(mask, W, tw, th, list);
    if (n == 0)
        return; /* every pixel keeps its centre colour */
    hz_memset(acc, 0, sizeof acc);
    /* 4 rays per active subpixel, HZ_TILE_PIXELS rays per batch; hz_trace_batch traces consecutive slots in
     * packets of HZ_RENDER_LANES, so only the tile's last packet can be partial. */
    const uint32_t rays = 4u * n;
    for (uint32_t first = 0; first < rays; first += HZ_TILE_PIXELS) {
        uint32_t count = rays - first < HZ_TILE_PIXELS ? rays - first : HZ_TILE_PIXELS;
        uint8_t owner[HZ_TILE_PIXELS];
        for (uint32_t slot = 0; slot < HZ_TILE_PIXELS; slot++) {
            if (slot >= count) {
                b->pixel[slot] = UINT32_MAX;
                continue;
            }
            uint32_t k = first + slot, e = list[k / 4u], s = k % 4u, q = e & 3u, p = e >> 2;
            uint32_t px = (y0 + p / tw) * W + x0 + p % tw;
            b->pixel[slot] = px;
            owner[slot] = (uint8_t)p;
            /* Stratum (cx, cy) of the pixel's 4x4 grid, jittered exactly as the full mode's 16 spp. */
            uint32_t cx = 2u * (q & 1u) + (s & 1u), cy = 2u * (q >> 1) + (s >> 1);
            uint32_t h = hz_hash3(px, cy * 4u + cx, f->opts.seed);
            jitter[slot][0] = ((float)cx + hz_u32_to_unit(h)) / 4.0f - 0.5f;
            jitter[slot][1] = ((float)cy + hz_u32_to_unit(hz_hash32(h))) / 4.0f - 0.5f;
            /* With motion blur every extra sample takes its own time: the stratum of its 4x4 cell among the
             * pixel's 16, as the full mode's 16 spp would (the presample took one time over the whole shutter). */
            if (blur)
                times[slot] = hz_render_sample_time(f, px, cy * 4u + cx, 16u);
        }
        hz_memset(b->radiance, 0, sizeof b->radiance);
        hz_render_trace(f, b, (const float(*)[2])jitter, blur ? times : NULL, false);
        for (uint32_t slot = 0; slot < count; slot++)
            for (int c = 0; c < 3; c++)
                acc[owner[slot] * 3u + (uint32_t)c] += b->radiance[slot * 3 + (uint32_t)c];
        b->stats.extra_packets += (count + HZ_RENDER_LANES - 1) / HZ_RENDER_LANES;
    }
    b->stats.extra_rays += rays;
    b->stats.active_subpixels += n;
    for (uint32_t p = 0; p < tw * th; p++) {
        const uint8_t bits = mask[(p / tw) * W + p % tw];
        uint32_t m = hz_amask_count(bits);
        if (m == 0)
            continue;
        float cw, sw;
        hz_adaptive_weights(m, &cw, &sw);
        const uint32_t x = x0 + p % tw, y = y0 + p / tw;
        float *dst = a->out.rgb + ((size_t)y * W + x) * 3;
        float inactive[3] = { dst[0] * cw, dst[1] * cw, dst[2] * cw };
        if (a->pre && m < 4) {
            /* each inactive subpixel q (bit q: x side q & 1, y side q >> 1) at its own centre */
            inactive[0] = inactive[1] = inactive[2] = 0.0f;
            for (uint32_t q = 0; q < 4; q++) {
                if (bits & (1u << q))
                    continue;
                float c[3];
                bilinear_at(a, W, f->opts.height, (float)x + 0.25f + 0.5f * (float)(q & 1u),
                            (float)y + 0.25f + 0.5f * (float)(q >> 1), c);
                for (int ch = 0; ch < 3; ch++)
                    inactive[ch] += 0.25f * c[ch];
            }
        }
        for (int c = 0; c < 3; c++) {
            float v = inactive[c] + acc[p * 3 + (uint32_t)c] * sw;
            if (!hz_isfinitef(v)) {
                b->stats.nonfinite++;
                v = 0.0f;
            }
            dst[c] = v > 0.0f ? v : 0.0f;
        }
    }
}

/* ---- the mode (mode.h) ---- */

static hz_status_t ad_check(const hz_render_opts_t *o, hz_error_t *err)
{
    /* Motion blur needs nothing of its own: the presample and every extra sample carry their own shutter time,
     * so the estimate converges to the blurred pixel; moving edges differ more between neighbours and get more
     * subpixels. */
    hz_amask_config_t c;
    return hz_adaptive_config(&o->adaptive, &c, err);
}

static uint32_t ad_items(const void *state, const hz_render_frame_t *f, uint32_t pass)
{
    (void)state, (void)pass;
    return f->tiles_x * f->tiles_y;
}

static void ad_run(void *state, hz_render_frame_t *f, uint32_t pass, uint32_t item, hz_batch_t *b)
{
    adaptive_state_t *a = state;
    if (pass == 0) {
        /* the presample: 1 spp at pixel centres, textures over the pixel where asked */
        hz_tile_sampling_t centres = { 1, NULL, false, 0, 0, f->opts.adaptive.footprint != 0 };
        hz_render_trace_tile(f, b, item, &centres, &a->out);
        keep_attrs(a, f, b);
    } else if (pass == 1) {
        test_tile(a, f, item);
    } else {
        extra_tile(a, f, item, b);
    }
}

static const hz_image_t *ad_output(const void *state)
{
    return &((const adaptive_state_t *)state)->out;
}

const hz_mode_ops_t hz_mode_adaptive = {
    .name = "adaptive",
    .flags = HZ_MODE_KEEPS_SURFACE,
    .state_bytes = sizeof(adaptive_state_t),
    .check = ad_check,
    .layout = ad_layout,
    .init = ad_init,
    .passes = 3,
    .pass_items = ad_items,
    .pass_run = ad_run,
    .output = ad_output,
};

const uint8_t *hz_render_adaptive_mask(const hz_renderer_t *r)
{
    const adaptive_state_t *a = hz_render_mode_state(r, &hz_mode_adaptive);
    return a ? a->mask : NULL;
}
