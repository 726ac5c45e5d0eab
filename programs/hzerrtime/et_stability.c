/* errtime's still-view temporal stability (see et_stability.h). */
#include "et_stability.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"

hz_status_t hz_et_stability(const hz_et_sequence_t *seq, const hz_et_method_t *m, uint32_t frames,
                            hz_arena_t *arena, hz_et_stab_row_t *row, hz_error_t *err)
{
    hz_et_sequence_t still = *seq;
    still.camera = "still";
    hz_arena_mark_t mark = hz_arena_mark(arena);
    size_t px = (size_t)seq->width * seq->height;
    hz_image_t img;
    uint8_t *codes[2] = { hz_arena_alloc(arena, px * 3, 64), hz_arena_alloc(arena, px * 3, 64) };
    hz_status_t s = hz_image_alloc(&img, arena, seq->width, seq->height, err);
    if (s == HZ_OK && (!codes[0] || !codes[1]))
        s = hz_arena_error(arena, err);
    void *state = NULL;
    if (s == HZ_OK && m->begin)
        s = m->begin(m, &still, arena, &state, err);
    bool begun = s == HZ_OK;
    double sum = 0.0;
    uint32_t total = seq->warmup + frames + 1;
    for (uint32_t i = 0; i < total && s == HZ_OK; i++) {
        uint64_t rays;
        if ((s = m->render(state, i, &img, &rays, err)) != HZ_OK)
            break;
        hz_image_to_srgb8(&img, codes[i & 1]);
        if (i > seq->warmup) {
            uint64_t d = 0;
            for (size_t k = 0; k < px * 3; k++)
                d += (uint64_t)abs((int)codes[0][k] - (int)codes[1][k]);
            sum += (double)d / (double)(px * 3);
        }
    }
    if (begun && m->end)
        m->end(state);
    hz_arena_reset(arena, mark);
    if (s != HZ_OK)
        return s;
    memset(row, 0, sizeof *row);
    snprintf(row->scene, sizeof row->scene, "%s", seq->scene);
    snprintf(row->method, sizeof row->method, "%s", m->name);
    snprintf(row->knob, sizeof row->knob, "%s", m->knob);
    row->value = m->value;
    row->width = seq->width, row->height = seq->height, row->frames = frames;
    row->mean_abs_change = sum / frames;
    return HZ_OK;
}

hz_status_t hz_et_write_stability_csv(const char *path, const hz_et_stab_row_t *rows, size_t n, hz_error_t *err)
{
    hz_out_t out;
    hz_status_t s = hz_out_open(&out, path, err);
    if (s != HZ_OK)
        return s;
    fprintf(out.f, "%s\n", HZ_ET_STABILITY_CSV_HEADER);
    for (size_t i = 0; i < n; i++)
        fprintf(out.f, "%s,%s,%s,%g,%u,%u,%u,%.4f\n", rows[i].scene, rows[i].method, rows[i].knob, rows[i].value,
                rows[i].width, rows[i].height, rows[i].frames, rows[i].mean_abs_change);
    return hz_out_commit(&out, err);
}
