/* Stage adaptive: selective and adaptive supersampling (seed 003: the integer activity mask of
 * src/pattern/adaptive_mask.c with Mitchell's contrast, the --mode adaptive passes of src/recon/adaptive.c) at the
 * edges: Imax + Imin = 0, all-black and all-white frames, one bright pixel, radiance 1e6, Inf/NaN colour
 * references, 1x1 and odd-size images, the presample's texture footprint at grazing, huge and degenerate texture
 * coordinates. References: Mitchell's contrast and the Fig. 4 subpixel rule evaluated here in double (non-finite
 * values left out, as documented), Morton order computed here by bit interleaving, the full mode at 1 and 16 spp
 * (what adaptive equals with no and with every subpixel active), the contrast's scale invariance (radiance x 1e6
 * gives the same mask) and the texels' range decoded here in double (a filter's weights are convex). */
#include <math.h>
#include <stdlib.h>

#include "hz/adaptive.h"
#include "hz/hash.h"
#include "stab_util.h"

static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bitsf(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Mitchell's contrast of n values in double: negatives count as 0, NaN/Inf are left out; -1 when fewer than two
 * values are left (never active). */
static double ref_contrast(const uint32_t *bits, uint32_t n)
{
    double mx = -1, mn = INFINITY;
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        float f = bitsf(bits[i]);
        if (!isfinite(f))
            continue;
        double v = f > 0 ? f : 0;
        mx = fmax(mx, v), mn = fmin(mn, v);
        k++;
    }
    if (k < 2)
        return -1;
    return mx + mn == 0 ? 0 : (mx - mn) / (mx + mn);
}

/* A random binary32 pattern: any exponent (subnormals to the largest finite), sometimes negative, 0, -0, Inf,
 * NaN. */
static uint32_t rnd_value(uint32_t *st)
{
    *st = hz_hash32(*st + 0x9e3779b9u);
    uint32_t h = *st;
    switch (h & 15u) {
    case 0: return 0;
    case 1: return 0x80000000u;
    case 2: return 0x7f800000u;
    case 3: return 0x7fc00001u;
    case 4: return 0xff800000u;
    case 5: return fbits(-(float)(h >> 8));
    case 6: return h >> 9;                                          /* subnormal */
    case 7: case 8: return fbits(0.5f + (float)(h >> 8) * (1.0f / 16777216.0f)); /* close values */
    default: return (h >> 1) & 0x7f7fffffu;                         /* finite positive, any exponent */
    }
}

/* Imax + Imin = 0 and the contrast over random value sets: hz_amask_contrast_q16 within one unit of
 * floor(65536 C) in double, hz_amask_contrast_at_least agreeing with C >= thr wherever C is not within 2^-20 of
 * the threshold. */
static void c_contrast(stab_result_t *r)
{
    const uint32_t zeros[][4] = { { 0, 0, 0, 0 }, { 0, 0x80000000u, 0, 0x80000000u }, { fbits(-1.0f), fbits(-5e30f),
                                                                                       0, 0x80000000u } };
    for (int i = 0; i < 3; i++) {
        bool usable = false;
        uint32_t c = hz_amask_contrast_q16(zeros[i], 4, &usable);
        STAB_CHECK(r, c == 0 && usable, "Imax + Imin = 0 (set %d): C = %u (usable %d), want 0", i, c, usable);
        STAB_CHECK(r, hz_amask_contrast_at_least(zeros[i], 4, 0) && !hz_amask_contrast_at_least(zeros[i], 4, 1),
                   "Imax + Imin = 0 (set %d): active at tau > 0 or not at tau = 0", i);
    }
    const uint32_t tiny[2] = { 0, 1 }; /* 0 and the smallest subnormal: full contrast */
    STAB_CHECK(r, hz_amask_contrast_q16(tiny, 2, NULL) == 65536u, "C(0, 2^-149) = %u, want 65536",
               hz_amask_contrast_q16(tiny, 2, NULL));
    uint32_t st = 3;
    uint64_t sets = 0, unusable = 0, near = 0;
    double e = 0;
    for (uint32_t s = 0; s < (r->full ? 2000000u : 200000u); s++) {
        uint32_t v[4], n = 2 + s % 3;
        for (uint32_t i = 0; i < n; i++)
            v[i] = rnd_value(&st);
        bool usable;
        uint32_t c = hz_amask_contrast_q16(v, n, &usable);
        double want = ref_contrast(v, n);
        STAB_CHECK(r, usable == (want >= 0), "set %u: usable %d, the reference says %d", s, usable, want >= 0);
        if (want < 0) {
            unusable++;
            st = hz_hash32(st);
            STAB_CHECK(r, !hz_amask_contrast_at_least(v, n, 0), "set %u without two finite values activates", s);
            continue;
        }
        double q = floor(65536.0 * want);
        stab_error(r, fabs((double)c - q));
        e = fmax(e, fabs((double)c - q));
        STAB_CHECK(r, fabs((double)c - q) <= 1.0, "set %u: C = %u, want %.0f", s, c, q);
        st = hz_hash32(st);
        uint32_t thr = st % 65540u;
        if (fabs(65536.0 * want - thr) < 65536.0 / 1048576.0) {
            near++;
            continue;
        }
        STAB_CHECK(r, hz_amask_contrast_at_least(v, n, thr) == (65536.0 * want >= thr),
                   "set %u: at_least(%u) = %d, C = %.9f", s, thr, !(65536.0 * want >= thr), want);
        sets++;
    }
    stab_note(r, "Imax + Imin = 0: C = 0 (active only at tau 0); %llu random sets: C within %.0f unit of Q16; %llu "
                 "without two finite values never active; %llu near ties skipped", (unsigned long long)sets, e,
              (unsigned long long)unusable, (unsigned long long)near);
    r->status = HZ_OK;
}

/* ---- the mask of a frame against the Fig. 4 rule in double ---- */

typedef struct frame {
    uint32_t w, h;
    hz_amask_px_t *px; /* w * h, every attribute equal: the colour decides */
} frame_t;

static const hz_amask_px_t *at(const frame_t *f, int x, int y)
{
    x = x < 0 ? 0 : x >= (int)f->w ? (int)f->w - 1 : x; /* the image edge replicates */
    y = y < 0 ? 0 : y >= (int)f->h ? (int)f->h - 1 : y;
    return &f->px[(size_t)y * f->w + (size_t)x];
}

static const double factor[3] = { 1.36, 1.02, 2.04 }; /* Mitchell's, per channel */

/* Reference mask bit q of pixel (x, y) at tau (Q16), or -1 when a channel's contrast lies within 1e-6 of its
 * threshold (a tie the double cannot settle). */
static int ref_bit(const frame_t *f, int x, int y, uint32_t q, uint32_t tau)
{
    int out = 0;
    for (int ch = 0; ch < 3; ch++) {
        uint32_t v[4];
        v[0] = at(f, x, y)->rgb[ch];
        for (int k = 0; k < 3; k++)
            v[1 + k] = at(f, x + hz_amask_neighbours[q][k][0], y + hz_amask_neighbours[q][k][1])->rgb[ch];
        double c = ref_contrast(v, 4);
        if (c < 0)
            continue;
        /* the factor and the product with tau rounded to Q16, as documented */
        double thr = (double)(uint32_t)(((uint64_t)(uint32_t)floor(factor[ch] * 65536.0 + 0.5) * tau + 32768u) >> 16) /
                     65536.0;
        if (fabs(c - thr) < 1e-6)
            return -1;
        out |= c >= thr;
    }
    return out;
}

/* Runs hz_amask_block over the frame (window with a replicated border) and compares every subpixel with the
 * reference; returns the active count. */
static uint32_t check_frame(stab_result_t *r, const frame_t *f, const hz_amask_config_t *cfg, uint8_t *mask)
{
    uint32_t sw = f->w + 2, sh = f->h + 2;
    hz_amask_px_t *win = malloc(sizeof *win * sw * sh);
    if (!win) {
        stab_failf(r, __FILE__, __LINE__, "malloc");
        return 0;
    }
    for (uint32_t y = 0; y < sh; y++)
        for (uint32_t x = 0; x < sw; x++)
            win[(size_t)y * sw + x] = *at(f, (int)x - 1, (int)y - 1);
    uint32_t n = hz_amask_block(cfg, win, sw, f->w, f->h, mask, f->w), count = 0, ties = 0;
    for (uint32_t y = 0; y < f->h; y++)
        for (uint32_t x = 0; x < f->w; x++) {
            uint8_t m = mask[(size_t)y * f->w + x];
            if (m > 15u) {
                stab_failf(r, __FILE__, __LINE__, "mask %u at (%u, %u)", m, x, y);
                free(win);
                return 0;
            }
            count += hz_amask_count(m);
            for (uint32_t q = 0; q < 4; q++) {
                int want = ref_bit(f, (int)x, (int)y, q, cfg->tau[HZ_TAU_COL]);
                ties += want < 0;
                if (want >= 0 && want != (int)((m >> q) & 1u)) {
                    stab_failf(r, __FILE__, __LINE__, "%ux%u frame: subpixel %u of (%u, %u) is %d, Mitchell in double "
                               "says %d", f->w, f->h, q, x, y, (m >> q) & 1, want);
                    free(win);
                    return 0;
                }
            }
        }
    free(win);
    if (n != count)
        stab_failf(r, __FILE__, __LINE__, "hz_amask_block counts %u active, the mask has %u", n, count);
    (void)ties;
    return count;
}

static void frame_fill(frame_t *f, uint32_t w, uint32_t h, float v)
{
    f->w = w, f->h = h;
    f->px = calloc((size_t)w * h, sizeof *f->px);
    if (!f->px)
        abort();
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int c = 0; c < 3; c++)
            f->px[i].rgb[c] = fbits(v);
        f->px[i].hit[0].object = 7, f->px[i].hit[0].n[2] = 127, f->px[i].hit[0].flags = HZ_AMASK_HIT;
        f->px[i].hit[1].object = 0xffff;
    }
}

static void cfg_col(hz_amask_config_t *c, float tau_col)
{
    hz_amask_config_default(c);
    c->tau[HZ_TAU_COL] = (uint32_t)(tau_col * 65536.0f + 0.5f);
}

/* All-black, all-white and all-1e6 frames: no subpixel active at the default threshold; every subpixel at tau = 0
 * (C = 0 >= 0, as the paper says); none at tau = 1. */
static void c_flat_frames(stab_result_t *r)
{
    const float vals[4] = { 0.0f, 1.0f, 1e6f, 3e38f };
    const float taus[3] = { 0.6f, 0.0f, 1.0f };
    static uint8_t mask[9 * 7];
    for (int v = 0; v < 4; v++)
        for (int t = 0; t < 3; t++) {
            frame_t f;
            frame_fill(&f, 9, 7, vals[v]);
            hz_amask_config_t c;
            cfg_col(&c, taus[t]);
            uint32_t n = check_frame(r, &f, &c, mask);
            STAB_BAIL(r);
            uint32_t want = taus[t] == 0.0f ? 4u * 9u * 7u : 0u;
            STAB_CHECK(r, n == want, "flat %g at tau %g: %u active, want %u", (double)vals[v], (double)taus[t], n,
                       want);
            free(f.px);
        }
    r->status = HZ_OK;
    stab_note(r, "black; white; 1e6; 3e38 frames at tau 0.6 / 0 / 1: 0 / all / 0 active = Mitchell in double");
}

/* One pixel of 1e6 (then 3e38, +Inf, NaN, a negative value) in a frame of 0.1: the active subpixels are exactly
 * those whose Fig. 4 neighbourhood holds it (finite) and none (non-finite: left out, never active). */
static void c_one_bright_pixel(stab_result_t *r)
{
    const float vals[5] = { 1e6f, 3e38f, INFINITY, NAN, -1e6f };
    static uint8_t mask[9 * 7];
    uint32_t counts[5];
    for (int v = 0; v < 5; v++) {
        frame_t f;
        frame_fill(&f, 9, 7, 0.1f);
        for (int c = 0; c < 3; c++)
            f.px[3 * 9 + 4].rgb[c] = fbits(vals[v]);
        hz_amask_config_t cfg;
        cfg_col(&cfg, 0.6f);
        counts[v] = check_frame(r, &f, &cfg, mask);
        STAB_BAIL(r);
        free(f.px);
    }
    /* finite bright: its own 4 subpixels and the 12 of the 8 neighbours that face it (3 edge pairs x 2 + 4 corners
     * x 1 + ...): counted by the reference above; non-finite: none */
    STAB_CHECK(r, counts[0] > 4 && counts[0] == counts[1], "bright pixel: %u / %u active", counts[0], counts[1]);
    STAB_CHECK(r, counts[2] == 0 && counts[3] == 0, "Inf / NaN pixel activated %u / %u subpixels", counts[2],
               counts[3]);
    r->status = HZ_OK;
    stab_note(r, "1e6 and 3e38: %u active = Mitchell in double; Inf and NaN: 0; negative (as 0): %u", counts[0],
              counts[4]);
}

/* Random colours (any exponent, Inf, NaN, negatives) in 1x1, 1x9, 3x1, 7x5 and 33x17 frames against the double
 * reference at three thresholds; then hz_amask_pack over odd tiles: every active subpixel once, in Morton order
 * (interleaved here), tiles past 16 refused (0). */
static uint32_t interleave(uint32_t x, uint32_t y)
{
    uint32_t m = 0;
    for (uint32_t b = 0; b < 16; b++)
        m |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return m;
}

static void c_odd_sizes(stab_result_t *r)
{
    const uint32_t sizes[][2] = { { 1, 1 }, { 1, 9 }, { 3, 1 }, { 7, 5 }, { 33, 17 }, { 16, 16 } };
    const float taus[3] = { 0.6f, 0.05f, 0.0f };
    static uint8_t mask[33 * 17];
    uint32_t st = 9, total = 0;
    for (size_t s = 0; s < 6; s++)
        for (int t = 0; t < 3; t++) {
            frame_t f;
            frame_fill(&f, sizes[s][0], sizes[s][1], 0.0f);
            for (size_t i = 0; i < (size_t)f.w * f.h; i++)
                for (int c = 0; c < 3; c++)
                    f.px[i].rgb[c] = (i + (size_t)c) % 3 ? rnd_value(&st) : fbits(0.25f);
            hz_amask_config_t cfg;
            cfg_col(&cfg, taus[t]);
            total += check_frame(r, &f, &cfg, mask);
            STAB_BAIL(r);
            if (f.w <= HZ_AMASK_MAX_TILE && f.h <= HZ_AMASK_MAX_TILE) {
                static uint16_t list[4 * 16 * 16];
                uint32_t n = hz_amask_pack(mask, f.w, f.w, f.h, list), want = 0, last = 0;
                for (size_t i = 0; i < (size_t)f.w * f.h; i++)
                    want += hz_amask_count(mask[i]);
                STAB_CHECK(r, n == want, "%ux%u: packed %u of %u active subpixels", f.w, f.h, n, want);
                for (uint32_t i = 0; i < n; i++) {
                    uint32_t pix = list[i] >> 2, q = list[i] & 3u, x = pix % f.w, y = pix / f.w;
                    STAB_CHECK(r, pix < f.w * f.h && (mask[pix] >> q & 1u), "%ux%u: entry %u is not active", f.w,
                               f.h, i);
                    uint32_t code = interleave(2 * x + (q & 1u), 2 * y + (q >> 1));
                    STAB_CHECK(r, i == 0 || code > last, "%ux%u: entry %u out of Morton order", f.w, f.h, i);
                    last = code;
                }
            }
            free(f.px);
        }
    static uint8_t big[17 * 17];
    memset(big, 15, sizeof big);
    static uint16_t list[4 * 17 * 17];
    STAB_CHECK(r, hz_amask_pack(big, 17, 17, 17, list) == 0, "a 17x17 tile was packed");
    r->status = HZ_OK;
    stab_note(r, "1x1 to 33x17 random frames at tau 0.6 / 0.05 / 0: %u active = Mitchell in double; packing "
                 "Morton-ordered; 17x17 refused", total);
}

/* Quantised normals at the int8 ends (-128, 127, the zero vector of a miss) and random ones: the primary normal
 * class disagrees exactly when the angle exceeds the agreeing angle (double reference), two misses agree, a miss
 * and a hit do not; at cos 0 (90 degrees) only obtuse pairs differ. */
static void c_normals_extreme(stab_result_t *r)
{
    static const int8_t ends[6] = { -128, -127, 0, 1, 126, 127 };
    uint32_t st = 21;
    uint64_t pairs = 0, ties = 0;
    for (int cfgk = 0; cfgk < 2; cfgk++) {
        hz_amask_config_t c;
        hz_amask_config_default(&c);
        if (cfgk)
            c.normal_cos = 0;
        const double cosv = c.normal_cos / 32768.0;
        for (uint32_t i = 0; i < 216 * 216 + 20000; i++) {
            hz_amask_px_t p, q;
            memset(&p, 0, sizeof p), memset(&q, 0, sizeof q);
            p.hit[1].object = q.hit[1].object = 0xffff;
            for (int k = 0; k < 3; k++) {
                st = hz_hash32(st);
                p.hit[0].n[k] = i < 216 * 216 ? ends[(i / (k == 0 ? 1 : k == 1 ? 6 : 36)) % 6] : (int8_t)(st & 0xff);
                q.hit[0].n[k] = i < 216 * 216 ? ends[(i / (216 * (k == 0 ? 1 : k == 1 ? 6 : 36))) % 6]
                                              : (int8_t)(st >> 8);
            }
            const hz_amask_px_t *nb[3] = { &q, &q, &q };
            uint32_t bits = hz_amask_disagree(&c, &p, nb, NULL) & HZ_AMASK_BIT(HZ_TAU_PSN);
            double aa = 0, bb = 0, dot = 0;
            for (int k = 0; k < 3; k++)
                aa += (double)p.hit[0].n[k] * p.hit[0].n[k], bb += (double)q.hit[0].n[k] * q.hit[0].n[k],
                    dot += (double)p.hit[0].n[k] * q.hit[0].n[k];
            bool want;
            if (aa == 0 || bb == 0)
                want = aa != bb;
            else {
                double lim = cosv * sqrt(aa) * sqrt(bb);
                if (fabs(dot - lim) <= 1e-9 * sqrt(aa * bb)) {
                    ties++;
                    continue;
                }
                want = dot < lim;
            }
            STAB_CHECK(r, (bits != 0) == want, "normals (%d %d %d) and (%d %d %d) at cos %.5f: differ %d, want %d",
                       p.hit[0].n[0], p.hit[0].n[1], p.hit[0].n[2], q.hit[0].n[0], q.hit[0].n[1], q.hit[0].n[2],
                       cosv, bits != 0, want);
            pairs++;
        }
    }
    r->status = HZ_OK;
    stab_note(r, "%llu normal pairs (int8 ends and random) at 15 and 90 degrees = double angle test; %llu ties",
              (unsigned long long)pairs, (unsigned long long)ties);
}

/* ---- --mode adaptive renders ---- */

#define RW 33
#define RH 17

static void room_scene(su_scene_t *b, float power, float ambient)
{
    su_begin(b);
    su_room(b, 1.0f);
    b->light[0].color[0] = b->light[0].color[1] = b->light[0].color[2] = power;
    b->ambient[0] = b->ambient[1] = b->ambient[2] = ambient;
    const float eye[3] = { 0.3f, 1.2f, 4 }, target[3] = { 0, 1, 0 };
    su_camera(b, 0, eye, target, 1.0f);
}

/* Renders one frame; out (w * h * 3) and mask (w * h) get the output and the adaptive mask (mode adaptive). */
static void render1(stab_result_t *r, const su_scene_t *b, hz_render_opts_t *o, float *out, uint8_t *mask,
                    uint64_t *active)
{
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open(&s, b, o, &err), &err);
    STAB_OK(r, su_render_frame(&s, 0, 0.0f, &err), &err);
    su_render_check(r, &s);
    STAB_BAIL(r);
    size_t n = (size_t)o->width * o->height;
    memcpy(out, hz_render_output(s.r)->rgb, sizeof(float) * 3 * n);
    if (mask) {
        const uint8_t *m = hz_render_adaptive_mask(s.r);
        STAB_CHECK(r, m != NULL, "no adaptive mask");
        memcpy(mask, m, n);
        hz_render_stats_t last;
        hz_render_frame_stats(s.r, &last, NULL);
        uint64_t c = 0;
        for (size_t i = 0; i < n; i++)
            c += hz_amask_count(m[i]);
        STAB_CHECK(r, c == last.active_subpixels && last.extra_rays == 4 * c,
                   "mask counts %llu active, stats %llu (extra rays %llu)", (unsigned long long)c,
                   (unsigned long long)last.active_subpixels, (unsigned long long)last.extra_rays);
        *active = c;
    }
    su_render_close(&s);
}

static double rel_diff(const float *a, const float *b, size_t n)
{
    double e = 0;
    for (size_t i = 0; i < n; i++)
        e = fmax(e, fabs((double)a[i] - b[i]) / fmax(fabs((double)b[i]), 1e-6));
    return e;
}

/* 1x1, 7x5 and 33x17 adaptive renders of the room: with every threshold at 1 (nothing active) bit-identical to
 * the full mode at 1 spp; with every threshold at 0 (every subpixel active) the full mode at 16 spp (within
 * 1e-5: the weights sum in another order). */
static void c_render_sizes(stab_result_t *r)
{
    const uint32_t sizes[3][2] = { { 1, 1 }, { 7, 5 }, { RW, RH } };
    static float a[RW * RH * 3], f[RW * RH * 3];
    static uint8_t mask[RW * RH];
    su_scene_t b;
    room_scene(&b, 20.0f, 0.1f);
    double e16 = 0;
    uint64_t act_default = 0;
    for (int s = 0; s < 3; s++) {
        const size_t n = (size_t)sizes[s][0] * sizes[s][1];
        for (int k = 0; k < 3; k++) {
            hz_render_opts_t o;
            hz_render_opts_default(&o);
            o.width = sizes[s][0], o.height = sizes[s][1], o.mode = HZ_MODE_ADAPTIVE;
            for (int t = 0; t < HZ_TAU_COUNT && k < 2; t++)
                o.adaptive.tau[t] = k == 0 ? 1.0f : 0.0f;
            uint64_t act = 0;
            render1(r, &b, &o, a, mask, &act);
            STAB_BAIL(r);
            if (k == 2) {
                act_default += act;
                continue;
            }
            STAB_CHECK(r, act == (k == 0 ? 0 : 4 * n), "%ux%u, thresholds %d: %llu active", sizes[s][0],
                       sizes[s][1], k == 0 ? 1 : 0, (unsigned long long)act);
            hz_render_opts_t of;
            hz_render_opts_default(&of);
            of.width = o.width, of.height = o.height, of.mode = HZ_MODE_FULL, of.spp = k == 0 ? 1 : 16;
            render1(r, &b, &of, f, NULL, NULL);
            STAB_BAIL(r);
            if (k == 0)
                STAB_CHECK(r, memcmp(a, f, sizeof(float) * 3 * n) == 0, "%ux%u: nothing active differs from 1 spp",
                           o.width, o.height);
            else {
                double e = rel_diff(a, f, 3 * n);
                e16 = fmax(e16, e);
                STAB_CHECK(r, e <= 1e-5, "%ux%u: everything active differs from 16 spp by %g", o.width, o.height, e);
            }
        }
    }
    stab_error(r, e16);
    stab_note(r, "1x1; 7x5; 33x17: tau 1 = 1 spp bit for bit; tau 0 = 16 spp within %.2g; default %llu active", e16,
              (unsigned long long)act_default);
}

/* All-black (no light power, no ambient, black background) and all-white (ambient 1 on albedo 1 filling the view)
 * renders: no subpixel active at the default thresholds, output all 0 / all 1. */
static void c_render_flat(stab_result_t *r)
{
    static float a[RW * RH * 3];
    static uint8_t mask[RW * RH];
    uint64_t act[2];
    for (int k = 0; k < 2; k++) {
        su_scene_t b;
        su_begin(&b);
        b.ambient[0] = b.ambient[1] = b.ambient[2] = (float)k;
        uint32_t m = su_material(&b, 1.0f, 1.0f, 1.0f);
        const float w0[3] = { -50, -50, 0 }, w1[3] = { 50, -50, 0 }, w2[3] = { 50, 50, 0 }, w3[3] = { -50, 50, 0 };
        su_quad(&b, w0, w1, w2, w3, m);
        su_object(&b);
        /* dark and behind every surface (no shadow rays): without lights the scene would get the default key light */
        su_light(&b, 0, 0, -100, 0.0f);
        const float eye[3] = { 0, 0, 5 }, target[3] = { 0, 0, 0 };
        su_camera(&b, 0, eye, target, 0.8f);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = RW, o.height = RH, o.mode = HZ_MODE_ADAPTIVE;
        render1(r, &b, &o, a, mask, &act[k]);
        STAB_BAIL(r);
        for (size_t i = 0; i < 3 * RW * RH; i++)
            stab_error(r, fabs(a[i] - (double)k));
        STAB_CHECK(r, act[k] == 0, "%s frame: %llu subpixels active", k ? "white" : "black",
                   (unsigned long long)act[k]);
    }
    STAB_CHECK(r, r->max_error <= 1e-6, "flat frames off their value by %g", r->max_error);
    stab_note(r, "black and white 33x17: 0 active; values exact within %.2g", r->max_error);
}

/* The room lit with radiance ~1e6 (light power x 1e6, no ambient): finite, and the same mask as at power 1
 * (Mitchell's contrast is scale-invariant) except where a contrast sits at its threshold (at most 1%); a light
 * of 3e38 (radiance near the float range) stays finite, and so does the room under a shutter (each
 * extra sample at its own time). */
static void c_render_bright(stab_result_t *r)
{
    static float a[RW * RH * 3];
    static uint8_t m1[RW * RH], m2[RW * RH];
    const float powers[3] = { 20.0f, 2e7f, 3e38f };
    uint64_t act[3];
    for (int k = 0; k < 3; k++) {
        su_scene_t b;
        room_scene(&b, powers[k], 0.0f);
        hz_render_opts_t o;
        hz_render_opts_default(&o);
        o.width = RW, o.height = RH, o.mode = HZ_MODE_ADAPTIVE;
        render1(r, &b, &o, a, k == 0 ? m1 : m2, &act[k]);
        STAB_BAIL(r);
        if (k == 1) {
            uint32_t diff = 0;
            for (size_t i = 0; i < RW * RH; i++)
                diff += m1[i] != m2[i];
            STAB_CHECK(r, diff * 100 <= RW * RH, "radiance x 1e6 changed the mask of %u of %u pixels", diff,
                       RW * RH);
            stab_note(r, "x 1e6: %u of %u pixel masks differ; %llu / %llu active", diff, RW * RH,
                      (unsigned long long)act[0], (unsigned long long)act[1]);
        }
    }
    STAB_CHECK(r, act[0] > 0, "the room has no active subpixel: the case tests nothing");
    su_scene_t b;
    room_scene(&b, 20.0f, 0.1f);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = RW, o.height = RH, o.mode = HZ_MODE_ADAPTIVE, o.shutter = 1.0f;
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open_blur(&s, &b, &o, HZ_ACCEL_BLUR_MSBVH, &err), &err);
    STAB_OK(r, su_render_frame(&s, 0, 0.5f, &err), &err);
    su_render_check(r, &s);
    hz_render_stats_t last;
    hz_render_frame_stats(s.r, &last, NULL);
    su_render_close(&s);
    STAB_BAIL(r);
    STAB_CHECK(r, last.extra_rays > 0, "the room under shutter 1 got no extra ray");
    stab_note(r, "3e38 light: finite; the room under shutter 1: finite, %llu extra rays",
              (unsigned long long)last.extra_rays);
}

/* sRGB8 to linear in double, the standard's formula (the renderer decodes by a table). */
static double srgb_linear(uint8_t c)
{
    double v = c / 255.0;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

#define TEX_SIDE 64

/* A textured scene lit only by ambient 1 on albedo 1, so every pixel shows a convex combination of texels
 * (random between two colours, so that every level has detail): a floor receding to the horizon (grazing: the footprint's largest and most anisotropic), a wall whose
 * coordinates sit near 1e6 (texel steps of 1/16 in float), a quad whose four coordinates are one point (no
 * gradient) and a triangle whose coordinates span 1e-30 (gradients of 1e-30). lo and hi get each channel's
 * smallest and largest texel over every level, decoded here in double. */
static void textured_scene(su_scene_t *b, double lo[3], double hi[3])
{
    static uint8_t rgba[TEX_SIDE * TEX_SIDE * 4];
    static const uint8_t dark[3] = { 40, 25, 60 }, light[3] = { 210, 230, 190 };
    for (int y = 0; y < TEX_SIDE; y++)
        for (int x = 0; x < TEX_SIDE; x++)
            for (int c = 0; c < 4; c++)
                rgba[4 * (y * TEX_SIDE + x) + c] =
                    c == 3 ? 255
                           : (uint8_t)(dark[c] + hz_hash32((uint32_t)(4 * (y * TEX_SIDE + x) + c)) %
                                                     (uint32_t)(light[c] - dark[c] + 1));
    su_begin(b);
    b->ambient[0] = b->ambient[1] = b->ambient[2] = 1.0f;
    const uint32_t tex = su_texture(b, rgba, TEX_SIDE, TEX_SIDE, 7);
    for (int c = 0; c < 3; c++) {
        lo[c] = 1e30, hi[c] = -1e30;
        for (uint32_t i = 0; i < b->ntexel; i++) {
            lo[c] = fmin(lo[c], srgb_linear(b->texels[4 * i + c]));
            hi[c] = fmax(hi[c], srgb_linear(b->texels[4 * i + c]));
        }
    }
    /* the background between them, so that it is a value the bounds allow */
    b->background[0] = b->background[1] = b->background[2] = (float)((lo[1] + hi[1]) / 2);
    const uint32_t m = su_material(b, 1.0f, 1.0f, 1.0f);
    b->mat[m].base_texture = (int32_t)tex;
    const float f0[3] = { -60, 0, 5 }, f1[3] = { 60, 0, 5 }, f2[3] = { 60, 0, -400 }, f3[3] = { -60, 0, -400 };
    su_quad(b, f0, f1, f2, f3, m);
    const float fuv[4][2] = { { 0, 0 }, { 120, 0 }, { 120, 405 }, { 0, 405 } };
    for (uint32_t k = 0; k < 4; k++)
        su_uv(b, b->nv - 4 + k, fuv[k][0], fuv[k][1]);
    su_object(b);
    const float w0[3] = { 1, 0, -6 }, w1[3] = { 6, 0, -6 }, w2[3] = { 6, 4, -6 }, w3[3] = { 1, 4, -6 };
    su_quad(b, w0, w1, w2, w3, m);
    for (uint32_t k = 0; k < 4; k++)
        su_uv(b, b->nv - 4 + k, 1e6f + (float)(k == 1 || k == 2) * 3.0f, -1e6f + (float)(k >= 2) * 2.0f);
    su_object(b);
    const float q0[3] = { -3, 0.5f, -4 }, q1[3] = { -1, 0.5f, -4 }, q2[3] = { -1, 2, -4 }, q3[3] = { -3, 2, -4 };
    su_quad(b, q0, q1, q2, q3, m);
    for (uint32_t k = 0; k < 4; k++)
        su_uv(b, b->nv - 4 + k, 0.3f, 0.7f);
    su_object(b);
    const uint32_t a = su_vertex(b, -0.5f, 2.2f, -3), c = su_vertex(b, 0.5f, 2.2f, -3), d = su_vertex(b, 0, 3, -3);
    su_uv(b, a, 0.25f, 0.25f);
    su_uv(b, c, 0.25f + 1e-30f, 0.25f);
    su_uv(b, d, 0.25f, 0.25f + 1e-30f);
    su_tri(b, a, c, d, m);
    su_object(b);
    /* dark and behind every surface: without lights the scene would get the default key light */
    su_light(b, 0, -100, 0, 0.0f);
    const float eye[3] = { 0, 1.0f, 4 }, target[3] = { 0, 0.8f, -4 };
    su_camera(b, 0, eye, target, 1.0f);
}

/* Counts the values outside [lo, hi] (per channel, 1e-6 relative slack) into the error and returns them. */
static uint32_t out_of_bounds(stab_result_t *r, const float *img, size_t n, const double lo[3], const double hi[3])
{
    uint32_t bad = 0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            const double v = img[3 * i + c];
            const double e = fmax(lo[c] - v, v - hi[c]) / hi[c];
            stab_error(r, fmax(e, 0.0));
            bad += !(v >= lo[c] * (1 - 1e-6) && v <= hi[c] * (1 + 1e-6));
        }
    return bad;
}

/* --adaptive-footprint on textures at their extremes (textured_scene) at 1x1, 7x5 and 33x17: every value finite
 * and within the texels' range (the taps' weights are convex, so a value outside it is a wrong weight or a tap
 * that read past the texture); the footprint changes the presample at tau 1 (the case tests the path) and brings
 * it nearer the full mode's 16 spp than one sample at the hit (its purpose); at tau 0
 * the image is the full mode's 16 spp (within 1e-5, as without the footprint: the extra samples replace the
 * presample); under a shutter (the frame camera's footprint) finite and within the range too. */
static void c_render_textured(stab_result_t *r)
{
    const uint32_t sizes[3][2] = { { 1, 1 }, { 7, 5 }, { RW, RH } };
    static float a[RW * RH * 3], f[RW * RH * 3], g[RW * RH * 3];
    static uint8_t mask[RW * RH];
    su_scene_t b;
    double lo[3], hi[3];
    textured_scene(&b, lo, hi);
    uint32_t bad = 0, changed = 0;
    double e16 = 0, err_fp = 0, err_one = 0; /* 33x17 at tau 1: distance to 16 spp with and without */
    for (int s = 0; s < 3; s++) {
        const size_t n = (size_t)sizes[s][0] * sizes[s][1];
        for (int k = 0; k < 3; k++) { /* tau 1 with and without the footprint, tau 0 with it */
            hz_render_opts_t o;
            hz_render_opts_default(&o);
            o.width = sizes[s][0], o.height = sizes[s][1], o.mode = HZ_MODE_ADAPTIVE;
            o.adaptive.footprint = k != 1;
            for (int t = 0; t < HZ_TAU_COUNT; t++)
                o.adaptive.tau[t] = k == 2 ? 0.0f : 1.0f;
            uint64_t act = 0;
            render1(r, &b, &o, k == 0 ? a : f, mask, &act);
            STAB_BAIL(r);
            bad += out_of_bounds(r, k == 0 ? a : f, n, lo, hi);
            if (k == 1) {
                hz_render_opts_t of;
                hz_render_opts_default(&of);
                of.width = o.width, of.height = o.height, of.mode = HZ_MODE_FULL, of.spp = 16;
                render1(r, &b, &of, g, NULL, NULL);
                STAB_BAIL(r);
                for (size_t i = 0; i < 3 * n; i++) {
                    changed += a[i] != f[i];
                    if (s == 2)
                        err_fp += fabs((double)a[i] - g[i]), err_one += fabs((double)f[i] - g[i]);
                }
            }
            if (k == 2) {
                double e = rel_diff(f, g, 3 * n);
                e16 = fmax(e16, e);
                STAB_CHECK(r, e <= 1e-5, "%ux%u: tau 0 with the footprint differs from 16 spp by %g", o.width,
                           o.height, e);
            }
        }
    }
    STAB_CHECK(r, bad == 0, "%u values outside the texels' range", bad);
    STAB_CHECK(r, changed > 0, "the footprint changed no value: the case tests nothing");
    /* the footprint's purpose: the presample nearer the supersampled pixel than one sample at the hit */
    STAB_CHECK(r, err_fp < err_one, "33x17 at tau 1: %g from 16 spp with the footprint, %g without", err_fp,
               err_one);
    hz_render_opts_t o;
    hz_render_opts_default(&o);
    o.width = RW, o.height = RH, o.mode = HZ_MODE_ADAPTIVE, o.shutter = 1.0f, o.adaptive.footprint = 1;
    su_render_t s;
    hz_error_t err;
    STAB_OK(r, su_render_open_blur(&s, &b, &o, HZ_ACCEL_BLUR_MSBVH, &err), &err);
    STAB_OK(r, su_render_frame(&s, 0, 0.5f, &err), &err);
    su_render_check(r, &s);
    memcpy(a, hz_render_output(s.r)->rgb, sizeof(float) * 3 * RW * RH);
    su_render_close(&s);
    STAB_BAIL(r);
    uint32_t bad_blur = out_of_bounds(r, a, RW * RH, lo, hi);
    STAB_CHECK(r, bad_blur == 0, "under shutter 1: %u values outside the texels' range", bad_blur);
    stab_note(r, "grazing, 1e6 and point coordinates: within the texels' range (worst %.2g over); the footprint "
              "changed %u values at tau 1 (absolute error from 16 spp %.3f, %.3f without); tau 0 = 16 spp within "
              "%.2g; finite under a shutter", r->max_error, changed, err_fp, err_one, e16);
}

static const stab_case_t cases[] = {
    { "amask_contrast", "Imax + Imin = 0: C = 0; random sets incl. subnormal/Inf/NaN = Mitchell in double",
      c_contrast, 0 },
    { "amask_flat_frames", "all-black/white/1e6 frames: no subpixel active (all at tau 0)", c_flat_frames, 0 },
    { "amask_one_bright_pixel", "one 1e6 pixel: active set = double reference; Inf/NaN pixel never active",
      c_one_bright_pixel, 0 },
    { "amask_odd_sizes", "1x1 to 33x17 random frames = double reference; packing in Morton order", c_odd_sizes,
      0 },
    { "amask_normals_extreme", "int8 normals at -128/127/0 and random: class disagrees = double angle test",
      c_normals_extreme, 0 },
    { "adaptive_render_sizes", "--mode adaptive 1x1/7x5/33x17: tau 1 = 1 spp exactly; tau 0 = 16 spp (1e-5)",
      c_render_sizes, 0 },
    { "adaptive_render_flat", "--mode adaptive on black and white frames: 0 active; exact values", c_render_flat,
      0 },
    { "adaptive_render_bright", "radiance 1e6: same mask (scale-invariant); 3e38 finite; finite under a shutter",
      c_render_bright, 0 },
    { "adaptive_render_textured",
      "--adaptive-footprint on grazing, 1e6 and point texture coordinates: within the texels' range; tau 0 = 16 spp",
      c_render_textured, 0 },
};
STAB_STAGE(adaptive, cases);
