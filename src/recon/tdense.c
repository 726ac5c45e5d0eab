/* Temporally dense reconstruction (see hz/tdense.h): per-tile sample placement, the static moving window, the
 * dynamic reproject-and-clamp path, and the once-per-cycle choice of tile orderings. */
#include "hz/tdense.h"

#include "hz/pack.h"
#include "hz/vmath.h"
#include "tdense_internal.h"

/* Window slots per pixel: one RGB9E5 sample per MSAA position (16 bytes: four pixels per cache line). */
#define WIN 4u

hz_tdense_config_t hz_tdense_config_default(uint32_t width, uint32_t height)
{
    hz_tdense_config_t c;
    c.width = width;
    c.height = height;
    c.rule = HZ_GHAT_FULL;
    c.seed = 0;
    c.reflect_mv = true;
    c.gamma = 1.0f;
    c.motion = true;
    return c;
}

void hz_tdense_layout(hz_tdense_t *td, const hz_tdense_config_t *cfg, hz_memplan_t *p)
{
    const size_t px = (size_t)cfg->width * cfg->height;
    const uint32_t tx = (cfg->width + 1) / 2, ty = (cfg->height + 1) / 2;
    const size_t padded = (size_t)tx * ty + 2 * HZ_TDENSE_TILE_PAD;
    hz_memplan_part(p, HZ_TDENSE_PART_STATE);
    uint8_t *orders = hz_memplan_alloc(p, padded), *next_orders = hz_memplan_alloc(p, padded);
    float *planes[3];
    for (int k = 0; k < 3; k++)
        planes[k] = hz_memplan_array(p, padded, sizeof(float));
    uint8_t *jitter = hz_memplan_alloc(p, padded);
    /* the pointers skip the front padding (NULL, when counting, stays NULL) */
    td->orders = orders ? orders + HZ_TDENSE_TILE_PAD : NULL;
    td->next_orders = next_orders ? next_orders + HZ_TDENSE_TILE_PAD : NULL;
    for (int k = 0; k < 3; k++)
        td->sub_rgb[k] = planes[k] ? planes[k] + HZ_TDENSE_TILE_PAD : NULL;
    td->sub_jitter = jitter ? (int8_t *)jitter + HZ_TDENSE_TILE_PAD : NULL;
    /* a still scene under a still camera keeps no motion */
    td->mv = cfg->motion ? hz_memplan_array(p, px * 2, sizeof(uint16_t)) : NULL;
    td->window = hz_memplan_array(p, px * WIN, sizeof(uint32_t));
    td->flags = hz_memplan_alloc(p, px);
    td->hist[0] = hz_memplan_array(p, 3 * px + HZ_TDENSE_HIST_PAD, sizeof(uint16_t));
    td->hist[1] = hz_memplan_array(p, 3 * px + HZ_TDENSE_HIST_PAD, sizeof(uint16_t));
    hz_memplan_part(p, HZ_TDENSE_PART_DISPLAY);
    td->out.rgb = hz_memplan_array(p, px * 3, sizeof(float));
    hz_memplan_part(p, HZ_TDENSE_PART_STATE);
    td->cfg = *cfg;
    td->tiles_x = tx;
    td->tiles_y = ty;
    td->out.width = cfg->width;
    td->out.height = cfg->height;
}

size_t hz_tdense_bytes(uint32_t width, uint32_t height)
{
    return hz_tdense_plan(width, height, true, NULL);
}

size_t hz_tdense_plan(uint32_t width, uint32_t height, bool motion, size_t *display_bytes)
{
    size_t dummy;
    if (hz_image_check_size(width, height, &dummy, NULL) != HZ_OK)
        return 0;
    hz_tdense_t td;
    hz_tdense_config_t cfg = hz_tdense_config_default(width, height);
    cfg.motion = motion;
    hz_memplan_t p;
    hz_memplan_count(&p);
    hz_tdense_layout(&td, &cfg, &p);
    if (display_bytes)
        *display_bytes = p.part[HZ_TDENSE_PART_DISPLAY];
    return p.bytes;
}

hz_status_t hz_tdense_check(const hz_tdense_config_t *cfg, hz_error_t *err)
{
    size_t bytes;
    hz_status_t st = hz_image_check_size(cfg->width, cfg->height, &bytes, err);
    if (st != HZ_OK)
        return st;
    if ((unsigned)cfg->rule >= HZ_GHAT_RULE_COUNT)
        return hz_error_set(err, HZ_E_INVALID_ARG, "tdense: unknown ordering rule %d", (int)cfg->rule);
    if (!(cfg->gamma >= 0.0f && cfg->gamma <= 100.0f))
        return hz_error_set(err, HZ_E_INVALID_ARG, "tdense: variance box gamma must lie in [0, 100]");
    return HZ_OK;
}

hz_status_t hz_tdense_init(hz_tdense_t *td, const hz_tdense_config_t *cfg, hz_arena_t *arena, hz_error_t *err)
{
    hz_memset(td, 0, sizeof *td);
    hz_status_t st = hz_tdense_check(cfg, err);
    if (st != HZ_OK)
        return st;
    size_t need = hz_tdense_plan(cfg->width, cfg->height, cfg->motion, NULL), have = hz_memplan_room(arena);
    if (need > have)
        return hz_error_set(err, HZ_E_NO_MEMORY,
                            "tdense %ux%u: arena '%s' needs %zu bytes, has %zu", (unsigned)cfg->width,
                            (unsigned)cfg->height, arena->name ? arena->name : "?", need, have);
    hz_arena_mark_t mark = hz_arena_mark(arena);
    hz_memplan_t p;
    hz_memplan_take(&p, arena);
    hz_tdense_layout(td, cfg, &p);
    if (p.refused) {
        /* The count above is an upper bound, so this is a bug in the layout. */
        hz_arena_reset(arena, mark);
        hz_memset(td, 0, sizeof *td);
        return hz_error_set(err, HZ_E_INTERNAL, "tdense: arena '%s' refused memory its plan said was there",
                            arena->name ? arena->name : "?");
    }
    hz_tdense_reset(td);
    return HZ_OK;
}

void hz_tdense_reset(hz_tdense_t *td)
{
    size_t px = (size_t)td->cfg.width * td->cfg.height, tiles = (size_t)td->tiles_x * td->tiles_y;
    unsigned first = hz_tileorder_of_cycle(hz_tileorder_ghat(0, 0, 0, td->cfg.rule));
    const size_t padded = tiles + 2 * HZ_TDENSE_TILE_PAD;
    hz_memset(td->orders - HZ_TDENSE_TILE_PAD, (int)first, padded);
    hz_memset(td->next_orders - HZ_TDENSE_TILE_PAD, (int)first, padded);
    for (int k = 0; k < 3; k++)
        hz_memset(td->sub_rgb[k] - HZ_TDENSE_TILE_PAD, 0, padded * sizeof(float));
    hz_memset(td->sub_jitter - HZ_TDENSE_TILE_PAD, -1, padded);
    if (td->mv)
        hz_memset(td->mv, 0, px * 2 * sizeof(uint16_t));
    hz_memset(td->window, 0, px * WIN * sizeof(uint32_t));
    hz_memset(td->flags, 0, px);
    hz_memset(td->hist[0], 0, (3 * px + HZ_TDENSE_HIST_PAD) * sizeof(uint16_t)); /* half code 0 is black */
    hz_memset(td->hist[1], 0, (3 * px + HZ_TDENSE_HIST_PAD) * sizeof(uint16_t));
    hz_memset(td->out.rgb, 0, px * 3 * sizeof(float));
    td->frame = 0;
    td->camera_moved = false;
    td->in_frame = false;
}

void hz_tdense_begin_frame(hz_tdense_t *td, bool camera_moved)
{
    td->camera_moved = camera_moved;
    td->in_frame = true;
}

bool hz_tdense_tile_sample(const hz_tdense_t *td, uint32_t tx, uint32_t ty, uint32_t *px, uint32_t *py,
                           float jitter[2], int *msaa)
{
    return hz_tdense_sample_at(td, tx, ty, px, py, jitter, msaa);
}

static float sanitise_motion(float v)
{
    if (hz_isnanf(v))
        return 0.0f;
    return hz_clampf(v, -HZ_TDENSE_MAX_MOTION, HZ_TDENSE_MAX_MOTION);
}

void hz_tdense_put(hz_tdense_t *td, uint32_t tx, uint32_t ty, const float rgb[3], const float mv[2],
                   const float *mv_reflect)
{
    uint32_t px, py;
    if (!hz_tdense_tile_pixel(td, tx, ty, &px, &py))
        return;
    const size_t p = (size_t)py * td->cfg.width + px;
    hz_tdense_put_sample(td, (size_t)ty * td->tiles_x + tx, p, hz_tdense_trace_msaa(td, p), rgb, mv, mv_reflect);
}

void hz_tdense_put_sample(hz_tdense_t *td, size_t t, size_t p, int msaa, const float rgb[3], const float mv[2],
                          const float *mv_reflect)
{
    td->sub_rgb[0][t] = rgb[0];
    td->sub_rgb[1][t] = rgb[1];
    td->sub_rgb[2][t] = rgb[2];
    td->sub_jitter[t] = (int8_t)msaa;
    const float *m = (mv_reflect && td->cfg.reflect_mv) ? mv_reflect : mv;
    if (td->mv) {
#ifdef HZ_TDENSE_LANES
        const uint32_t code = hz_tdense_motion_code_lanes(m[0], m[1]);
#else
        const uint32_t code = hz_tdense_motion_code(m[0], m[1]);
#endif
        td->mv[2 * p + 0] = (uint16_t)(code & 0xffffu);
        td->mv[2 * p + 1] = (uint16_t)(code >> 16);
    }
}

uint32_t hz_tdense_motion_code(float x, float y)
{
    return (uint32_t)hz_half_pack_signed(sanitise_motion(x)) | (uint32_t)hz_half_pack_signed(sanitise_motion(y)) << 16;
}

/* Whether pixel (x, y) is the one its tile traced this frame (then *tile is its tile index). */
HZ_INLINE bool is_new(const hz_tdense_t *td, uint32_t x, uint32_t y, unsigned subframe, size_t *tile)
{
    size_t t = (size_t)(y >> 1) * td->tiles_x + (x >> 1);
    *tile = t;
    return hz_tileorder_pixel(td->orders[t], subframe) == (((y & 1u) << 1) | (x & 1u));
}

typedef hz_tdense_motion_t motion_t;

/* The longer of a and b; a wins ties, so the scan order decides (and no split of the work can change it). */
HZ_INLINE motion_t longer(motion_t a, motion_t b)
{
    return b.l2 > a.l2 ? b : a;
}

HZ_INLINE motion_t motion_at(const uint16_t *mv, size_t p)
{
    motion_t m = { 0.0f, 0.0f, 0.0f };
    if (mv) {
        m.x = hz_half_unpack(mv[2 * p]), m.y = hz_half_unpack(mv[2 * p + 1]);
        m.l2 = m.x * m.x + m.y * m.y;
    }
    return m;
}

/* Longest motion vector among the pixels [x0, x1] x [y0, y1] (clamped to the image), scanned row by row. */
static motion_t longest_in(const hz_tdense_t *td, int x0, int y0, int x1, int y1)
{
    int w = (int)td->cfg.width, h = (int)td->cfg.height;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= w ? w - 1 : x1;
    y1 = y1 >= h ? h - 1 : y1;
    motion_t best = { 0.0f, 0.0f, 0.0f };
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            best = longer(best, motion_at(td->mv, (size_t)y * (size_t)w + (size_t)x));
    return best;
}

/* Pixel p of a history frame (planes of px half codes) into c, and c into it. */
static void hist_read(const uint16_t *hist, size_t px, size_t p, float c[3])
{
    for (int k = 0; k < 3; k++)
        c[k] = hz_half_unpack(hist[(size_t)k * px + p]);
}

static void hist_write(uint16_t *hist, size_t px, size_t p, const float c[3])
{
    for (int k = 0; k < 3; k++)
        hist[(size_t)k * px + p] = hz_half_pack(c[k]);
}

/* Bilinear fetch of the previous frame (half-float planes, w x h) at continuous pixel coordinates (pixel centres
 * on integers), clamped to the image edge (so the coordinates are non-negative and truncation is the floor). */
static void fetch_bilinear(const uint16_t *img, uint32_t w, uint32_t h, float sx, float sy, float out[3])
{
    sx = hz_clampf(sx, 0.0f, (float)w - 1.0f);
    sy = hz_clampf(sy, 0.0f, (float)h - 1.0f);
    uint32_t x0 = (uint32_t)sx, y0 = (uint32_t)sy;
    float fx = sx - (float)x0, fy = sy - (float)y0;
    uint32_t x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    float a[3], b[3], c[3], d[3];
    const size_t px = (size_t)w * h;
    hist_read(img, px, (size_t)y0 * w + x0, a);
    hist_read(img, px, (size_t)y0 * w + x1, b);
    hist_read(img, px, (size_t)y1 * w + x0, c);
    hist_read(img, px, (size_t)y1 * w + x1, d);
    for (int k = 0; k < 3; k++) {
        float top = a[k] + (b[k] - a[k]) * fx;
        float bot = c[k] + (d[k] - c[k]) * fx;
        out[k] = top + (bot - top) * fy;
    }
}

/* Mean and variance of the immediate neighbours of (x, y) that belong to this frame's subframe. Returns how
 * many there were. The 3x3 window around a pixel meets its own tile and, towards the side its position in the
 * tile faces, one tile across, one tile down or up, and one diagonally; each of those traced exactly one pixel,
 * so at most four candidates need checking, in a fixed order (the sums do not depend on how the work is split).
 * The own tile's pixel is always adjacent; the tile across is when its pixel lies in the column next to x (its
 * column parity differs from x's), the tile up or down when its row parity differs from y's, the diagonal when
 * both do. A tile's pixel may lie outside an odd-sized image (it traced nothing). (x, y) itself is never a
 * candidate: the caller asks only for pixels this subframe did not trace. */
static int newest_box(const hz_tdense_t *td, uint32_t x, uint32_t y, unsigned subframe, float mean[3],
                      float var[3])
{
    const uint32_t w = td->cfg.width, h = td->cfg.height, tw = td->tiles_x;
    const uint32_t tx = x >> 1, ty = y >> 1, px = x & 1u, py = y & 1u;
    /* tiles across and up/down; UINT32_MAX (outside) when that side has none */
    const uint32_t cx = px ? (tx + 1 < tw ? tx + 1 : UINT32_MAX) : (tx ? tx - 1 : UINT32_MAX);
    const uint32_t cy = py ? (ty + 1 < td->tiles_y ? ty + 1 : UINT32_MAX) : (ty ? ty - 1 : UINT32_MAX);
    const uint32_t ctx[4] = { tx, cx, tx, cx }, cty[4] = { ty, ty, cy, cy };
    float sum[3] = { 0, 0, 0 }, sq[3] = { 0, 0, 0 };
    int n = 0;
    for (int i = 0; i < 4; i++) {
        if (ctx[i] == UINT32_MAX || cty[i] == UINT32_MAX)
            continue;
        const size_t t = (size_t)cty[i] * tw + ctx[i];
        const unsigned pix = hz_tileorder_pixel(td->orders[t], subframe);
        const uint32_t nx = 2u * ctx[i] + (pix & 1u), ny = 2u * cty[i] + (pix >> 1);
        if (((i & 1) && (pix & 1u) == px) || ((i & 2) && (pix >> 1) == py) || nx >= w || ny >= h)
            continue;
        for (int k = 0; k < 3; k++) {
            const float c = td->sub_rgb[k][t];
            sum[k] += c;
            sq[k] += c * c;
        }
        n++;
    }
    float inv = n ? 1.0f / (float)n : 0.0f;
    for (int k = 0; k < 3; k++) {
        mean[k] = sum[k] * inv;
        float v = sq[k] * inv - mean[k] * mean[k];
        var[k] = v > 0.0f ? v : 0.0f;
    }
    return n;
}

/* Average of the window's samples in MSAA order (the order the 4-spp full-frame mode sums them in). */
static void window_average(const uint32_t *win, unsigned mask, float out[3])
{
    float s[3] = { 0.0f, 0.0f, 0.0f };
    unsigned n = 0;
    for (unsigned j = 0; j < 4; j++) {
        if (!(mask & (1u << j)))
            continue;
        float c[3];
        hz_rgb9e5_unpack(win[j], c);
        for (int k = 0; k < 3; k++)
            s[k] += c[k];
        n++;
    }
    for (int k = 0; k < 3; k++)
        out[k] = n == 4 ? s[k] * 0.25f : s[k] / (float)n;
}

HZ_INLINE void copy3(float *dst, const float *src)
{
    dst[0] = src[0];
    dst[1] = src[1];
    dst[2] = src[2];
}

/* One pixel of Fig. 3; m is the longest motion in its 3x3 neighbourhood. prev, cur: the previous frame and
 * the one written now (half-float history planes, ping-pong). */
void hz_tdense_resolve_pixel(hz_tdense_t *td, uint32_t x, uint32_t y, unsigned subframe, motion_t m,
                             const uint16_t *prev, uint16_t *cur)
{
    float *out = hz_image_at(&td->out, x, y);
    size_t p = (size_t)y * td->cfg.width + x, t;
    const size_t px = (size_t)td->cfg.width * td->cfg.height;
    bool fresh = is_new(td, x, y, subframe, &t);
    unsigned f = td->flags[p];
    const float sample[3] = { td->sub_rgb[0][t], td->sub_rgb[1][t], td->sub_rgb[2][t] };
    float mean[3], var[3];
    if (!td->camera_moved && m.l2 == 0.0f) {
        /* Static. An old pixel's window has not changed since the previous frame, where the pixel was static
         * too (turning static empties nothing, and a dynamic pixel's window is empty): its output then was the
         * same average, or the previous output it kept, so it is copied. */
        f &= ~HZ_TDENSE_DYNAMIC;
        if (fresh) {
            int j = td->sub_jitter[t];
            if (j >= 0) {
                td->window[WIN * p + (unsigned)j] = hz_rgb9e5_pack(sample);
                f |= 1u << j;
                window_average(td->window + WIN * p, f & HZ_TDENSE_SAMPLES, out);
            } else {
                f &= ~HZ_TDENSE_SAMPLES; /* a centre sample starts no window: wait for a jittered one */
                copy3(out, sample);
            }
        } else if (f & HZ_TDENSE_SEEN) {
            /* The history being written is the one before the previous (ping-pong): if the previous frame
             * kept the value too, it is already there. */
            if (!(f & HZ_TDENSE_KEPT))
                for (int k = 0; k < 3; k++)
                    cur[(size_t)k * px + p] = prev[(size_t)k * px + p];
            hist_read(prev, px, p, out);
            td->flags[p] = (uint8_t)(f | HZ_TDENSE_KEPT);
            return;
        } else {
            newest_box(td, x, y, subframe, mean, var);
            copy3(out, mean);
        }
    } else {
        f = (f & ~HZ_TDENSE_SAMPLES) | HZ_TDENSE_DYNAMIC;
        if (fresh) {
            copy3(out, sample);
        } else {
            int n = newest_box(td, x, y, subframe, mean, var);
            if (!(f & HZ_TDENSE_SEEN)) {
                copy3(out, mean);
            } else {
                fetch_bilinear(prev, td->cfg.width, td->cfg.height, (float)x + m.x, (float)y + m.y, out);
                for (int k = 0; n && k < 3; k++) { /* clamp to mean ± γσ (branch-free: min/max) */
                    float half = td->cfg.gamma * hz_sqrtf(var[k]);
                    out[k] = hz_clampf(out[k], mean[k] - half, mean[k] + half);
                }
                /* A non-finite sample shows in the frame it was traced (a broken tracer must be visible), but
                 * the clamp lets NaN through and bilinear reprojection spreads it: old values that are not
                 * finite restart from the new samples' mean, so it dies out instead of drifting forever. */
                for (int k = 0; k < 3; k++)
                    if (!hz_isfinitef(out[k]))
                        out[k] = n ? mean[k] : 0.0f;
            }
        }
    }
    hist_write(cur, px, p, out);
    td->flags[p] = (uint8_t)((f | HZ_TDENSE_SEEN) & ~HZ_TDENSE_KEPT);
}

motion_t hz_tdense_column_motion(const uint16_t *r0, const uint16_t *r1, const uint16_t *r2, size_t x)
{
    return longer(longer(motion_at(r0, x), motion_at(r1, x)), motion_at(r2, x));
}

/* Pixel row y: the 3x3 longest motion slides along the row as three column maxima. */
static void resolve_row(hz_tdense_t *td, uint32_t y, unsigned subframe, const uint16_t *prev, uint16_t *cur)
{
    uint32_t w = td->cfg.width, h = td->cfg.height;
    const uint16_t *r0 = td->mv ? td->mv + 2 * (size_t)(y ? y - 1 : 0) * w : NULL;
    const uint16_t *r1 = td->mv ? td->mv + 2 * (size_t)y * w : NULL;
    const uint16_t *r2 = td->mv ? td->mv + 2 * (size_t)(y + 1 < h ? y + 1 : y) * w : NULL;
    motion_t col_prev, col_cur, col_next;
    col_cur = longer(longer(motion_at(r0, 0), motion_at(r1, 0)), motion_at(r2, 0));
    col_prev = col_cur;
    for (uint32_t x = 0; x < w; x++) {
        uint32_t xn = x + 1 < w ? x + 1 : x;
        col_next = longer(longer(motion_at(r0, xn), motion_at(r1, xn)), motion_at(r2, xn));
        motion_t m = longer(longer(col_prev, col_cur), col_next);
        hz_tdense_resolve_pixel(td, x, y, subframe, m, prev, cur);
        col_prev = col_cur;
        col_cur = col_next;
    }
}

typedef void (*row_fn_t)(hz_tdense_t *td, uint32_t y, unsigned subframe, const uint16_t *prev, uint16_t *cur);

/* Tile (tx, ty)'s motion for ĝ: the longest over its 4x4 block. With lanes (and motion), groups of tiles scan
 * their blocks together in the same order, with the same result (hz_tdense_block_motion_lanes); g keeps the
 * group's results (tx runs up from 0, so a group's first tile comes first). */
typedef struct block_cache {
#ifdef HZ_TDENSE_LANES
    float x[HZ_TDENSE_LANES], y[HZ_TDENSE_LANES];
#endif
    int dummy;
} block_cache_t;

static motion_t tile_motion(const hz_tdense_t *td, uint32_t tx, uint32_t ty, bool lanes, block_cache_t *g)
{
    motion_t m;
#ifdef HZ_TDENSE_LANES
    uint32_t k = tx % HZ_TDENSE_LANES;
    if (lanes && td->mv && tx - k + HZ_TDENSE_LANES <= td->tiles_x) {
        if (k == 0)
            hz_tdense_block_motion_lanes(td, ty, tx - k, g->x, g->y);
        m.x = g->x[k], m.y = g->y[k];
        m.l2 = 0.0f; /* not used by the caller */
        return m;
    }
#else
    (void)lanes;
    (void)g;
#endif
    m = longest_in(td, 2 * (int)tx - 1, 2 * (int)ty - 1, 2 * (int)tx + 2, 2 * (int)ty + 2);
    return m;
}

static void resolve_rows(hz_tdense_t *td, uint32_t ty0, uint32_t ty1, row_fn_t row)
{
    unsigned subframe = hz_tdense_subframe(td->frame);
    uint16_t *cur = td->hist[td->frame & 1u];
    const uint16_t *prev = td->hist[(td->frame + 1u) & 1u];
    uint32_t h = td->cfg.height;
    if (ty1 > td->tiles_y)
        ty1 = td->tiles_y;
    for (uint32_t ty = ty0; ty < ty1; ty++) {
        for (uint32_t y = 2 * ty; y < 2 * ty + 2 && y < h; y++)
            row(td, y, subframe, prev, cur);
        if (subframe == 3) {
            /* Last frame of the cycle: each tile's motion is the longest over the 3x3 neighbourhoods of its
             * pixels, i.e. the 4x4 block around it; ĝ picks the next cycle's ordering (as hz_tileorder_choose
             * does, a tile at a time, so no per-tile motion array is kept). */
            const uint32_t key = hz_tileorder_cycle_key(hz_tdense_cycle(td->frame) + 1u, td->cfg.seed);
            block_cache_t g;
            for (uint32_t tx = 0; tx < td->tiles_x; tx++) {
                motion_t m = tile_motion(td, tx, ty, row != resolve_row, &g);
                hz_tilecycle_t c = hz_tdense_ghat(hz_q16_from_float(m.x), hz_q16_from_float(m.y), tx, ty, key,
                                                  td->cfg.rule);
                td->next_orders[(size_t)ty * td->tiles_x + tx] = (uint8_t)hz_tileorder_of_cycle(c);
            }
        }
    }
}

void hz_tdense_resolve_rows_scalar(hz_tdense_t *td, uint32_t ty0, uint32_t ty1)
{
    resolve_rows(td, ty0, ty1, resolve_row);
}

#if defined(HZ_BOARD_SIMD_AVX2) || defined(HZ_BOARD_SIMD_NEON) /* the Makefile builds tdense_lanes.c then */
void hz_tdense_resolve_rows(hz_tdense_t *td, uint32_t ty0, uint32_t ty1)
{
    resolve_rows(td, ty0, ty1, hz_tdense_resolve_row_lanes);
}

const char *hz_tdense_resolve_path(void)
{
#if defined(HZ_BOARD_SIMD_AVX2)
    return "avx2";
#else
    return "neon";
#endif
}
#else
void hz_tdense_resolve_rows(hz_tdense_t *td, uint32_t ty0, uint32_t ty1)
{
    resolve_rows(td, ty0, ty1, resolve_row);
}

const char *hz_tdense_resolve_path(void)
{
    return "scalar";
}
#endif

void hz_tdense_end_frame(hz_tdense_t *td)
{
    if (hz_tdense_subframe(td->frame) == 3) {
        uint8_t *o = td->orders;
        td->orders = td->next_orders;
        td->next_orders = o;
    }
    td->frame++;
    td->in_frame = false;
}

const hz_image_t *hz_tdense_output(const hz_tdense_t *td)
{
    return &td->out;
}
