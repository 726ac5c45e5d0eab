/*
 * et_flip.h — LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild, "FLIP: A Difference
 * Evaluator for Alternating Images", HPG 2020): a per-pixel perceptual error in [0, 1] for a test image against a
 * reference, as seen by an observer at a given number of pixels per degree of visual angle. Mean FLIP is errtime's
 * headline error.
 *
 * Contract:
 *  - Inputs are linear RGB images of the same size, clamped to [0, 1] (NaN -> 0) first, as the display shows them.
 *  - The pipeline (implemented from the paper, with the separable filters NVIDIA's reference has used since
 *    v1.2, whose results it matches to ~1e-6 in the mean; see test_flip):
 *      colour:  linear RGB -> XYZ (sRGB primaries, D65 white = RGB(1,1,1)) -> YCxCz; each channel filtered with
 *               the contrast sensitivity of the paper (spatial form a sqrt(pi/b) exp(-pi^2 x^2 / b), x in
 *               degrees; Y: a1 1, b1 0.0047; Cx: 1, 0.0053; Cz: 34.1, 0.04 plus 13.5, 0.025), kernels
 *               normalised to sum 1, radius ceil(3 sqrt(0.04 / (2 pi^2)) ppd), edges clamped; back to linear
 *               RGB, clamped to [0, 1]; CIELAB with the Hunt adjustment (a, b scaled by L/100); HyAB distance
 *               (|dL| + ||d(a,b)||) raised to qc = 0.7, remapped with pc = 0.4, pt = 0.95 against the distance
 *               cmax between Hunt-adjusted green and blue.
 *      feature: luminance Y/Yw of the unfiltered images; edges (first) and points (second derivative of a
 *               Gaussian, sd = 0.5 * 0.082 deg * ppd, radius ceil(3 sd), positive and negative weights each
 *               normalised to +-1); difference = max(|d edge|, |d point|) / sqrt(2), raised to qf = 0.5.
 *      error:   colour^(1 - feature).
 *  - ppd: pixels per degree; HZ_FLIP_DEFAULT_PPD is the paper's and the reference tool's default observer
 *    (0.7 m from a 0.7 m wide 3840-pixel display: 67.02 ppd).
 *  - map (optional, width * height floats, top row first) receives the per-pixel error; *mean gets its mean
 *    (accumulated in double).
 *  - Scratch: hz_flip_scratch_bytes(w, h) from the arena (about 64 bytes a pixel), released before returning.
 *    A size mismatch or bad ppd (not finite, <= 0 or > 1000) is HZ_E_INVALID_ARG.
 */
#ifndef HZ_ERRTIME_FLIP_H
#define HZ_ERRTIME_FLIP_H

#include <stddef.h>

#include "hz/arena.h"
#include "hz/image.h"
#include "hz/status.h"

/* ppd of an observer `distance_m` from a display `width_m` wide with `width_px` pixels (computed in float, the
 * way the reference tool computes its default). */
float hz_flip_ppd(float distance_m, float width_px, float width_m);
#define HZ_FLIP_DEFAULT_PPD hz_flip_ppd(0.7f, 3840.0f, 0.7f)

size_t hz_flip_scratch_bytes(uint32_t width, uint32_t height, float ppd);
hz_status_t hz_flip(const hz_image_t *ref, const hz_image_t *test, float ppd, hz_arena_t *scratch, float *map,
                    double *mean, hz_error_t *err);

#endif
