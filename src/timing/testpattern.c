/* The synthetic frame source (see hz/framesrc.h). */
#include "hz/framesrc.h"

#include "hz/hash.h"

void hz_testpattern_draw(uint8_t *rgb, size_t stride, int w, int h, uint64_t id)
{
    uint32_t f = (uint32_t)id;
    int bar_x = (int)((id * 8u) % (uint64_t)w), bar_y = (int)((id * 4u) % (uint64_t)h);
    uint8_t blue_base = (uint8_t)(f * 3u);
    for (int y = 0; y < h; y++) {
        uint8_t *p = rgb + (size_t)y * stride;
        uint8_t g = (uint8_t)((y * 255) / (h > 1 ? h - 1 : 1));
        int on_hbar = y >= bar_y && y < bar_y + 4;
        uint32_t cell_row = hz_hash2((uint32_t)(y >> 3), f >> 4);
        for (int x = 0; x < w; x++, p += 3) {
            if (on_hbar || (x >= bar_x && x < bar_x + 8)) {
                p[0] = p[1] = p[2] = (uint8_t)(on_hbar ? 255 : 32);
                continue;
            }
            uint32_t cell = hz_hash32(cell_row ^ (uint32_t)(x >> 3) * 0x9e3779b9u);
            p[0] = (uint8_t)((x * 255) / (w > 1 ? w - 1 : 1));
            p[1] = g;
            p[2] = (uint8_t)(blue_base + (cell & 0x3fu));
        }
    }
}

static hz_status_t render_pattern(void *ctx, const hz_frame_req_t *req, hz_rgb8_image_t *out, hz_error_t *err)
{
    (void)ctx;
    (void)err;
    hz_testpattern_draw(out->rgb, out->stride, out->w, out->h, req->id);
    return HZ_OK;
}

hz_framesrc_t hz_framesrc_testpattern(void)
{
    hz_framesrc_t s;
    s.name = "test pattern";
    s.ctx = 0;
    s.render = render_pattern;
    s.levels = 0;
    return s;
}
