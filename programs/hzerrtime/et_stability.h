/*
 * et_stability.h — errtime's temporal-stability figure (seed 004's transparency methods): the mean absolute
 * frame-to-frame change of a still view, in 8-bit sRGB codes (0..255) as the display shows them.
 *
 * Contract: hz_et_stability renders warmup + frames + 1 frames of `seq` with method m, the camera label set to
 * "still" (et_render.c then renders every frame at scene time 0, so nothing in the scene moves), and reports the
 * mean over frames after the warm-up of the mean over pixels and channels of |code_i - code_(i-1)|: 0 for a
 * perfectly stable method; a stochastic method's residual flicker after its temporal filter. Everything comes
 * from `arena` and is given back before it returns. hz_et_write_stability_csv writes the rows (header
 * HZ_ET_STABILITY_CSV_HEADER) via temporary file + rename.
 */
#ifndef HZ_ERRTIME_STABILITY_H
#define HZ_ERRTIME_STABILITY_H

#include <stddef.h>
#include <stdint.h>

#include "errtime.h"

typedef struct hz_et_stab_row {
    char scene[64], method[48], knob[24];
    double value;
    uint32_t width, height, frames;
    double mean_abs_change; /* sRGB 8-bit codes per channel and frame */
} hz_et_stab_row_t;

#define HZ_ET_STABILITY_CSV_HEADER "scene,method,knob,value,width,height,frames,mean_abs_change_srgb8"

hz_status_t hz_et_stability(const hz_et_sequence_t *seq, const hz_et_method_t *m, uint32_t frames,
                            hz_arena_t *arena, hz_et_stab_row_t *row, hz_error_t *err);
hz_status_t hz_et_write_stability_csv(const char *path, const hz_et_stab_row_t *rows, size_t n, hz_error_t *err);

#endif
