/*
 * et_metrics.h — full-reference image error: MSE/PSNR and SSIM (FLIP is in et_flip.h), plus the frame averaging the
 * display-integrated error needs. Hosted C99 (libm), used by errtime and its tests.
 *
 * Contract (every function compares a test image against a reference of the same size; a size mismatch is
 * HZ_E_INVALID_ARG):
 *  - What is compared is what a display shows: linear values are clamped to [0, 1] (NaN -> 0) first.
 *  - hz_mse: mean squared error over all pixels and the three channels, twice:
 *      srgb8   on the 8-bit sRGB codes (hz_srgb8_encode, exact rounding), code units (0..255);
 *      linear  on the clamped linear values (0..1).
 *    hz_psnr(mse, peak) = 10 log10(peak^2 / mse) dB, +INFINITY when mse == 0 (identical images; reports print
 *    "inf"). errtime's headline PSNR is the sRGB 8-bit one: hz_psnr(mse.srgb8, 255).
 *  - hz_ssim: mean SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luma: Y' = 0.2126 R + 0.7152 G + 0.0722 B of
 *    the 8-bit sRGB codes (BT.709 luma coefficients on gamma-encoded values; unrounded, dynamic range
 *    L = 255); 11x11 Gaussian window, sigma 1.5, normalised to sum 1; K1 = 0.01, K2 = 0.03, C1 = (K1 L)^2,
 *    C2 = (K2 L)^2; sigma^2 = E[x^2] - mu^2; the mean over every window lying fully inside the image (as in
 *    the authors' ssim_index.m, 'valid' filtering, no downsampling). Both sides must be at least 11 pixels
 *    (else HZ_E_INVALID_ARG). Computed in double; memory O(width) from the scratch arena.
 *  - hz_image_mean: the per-value mean of k images (linear light), used for the display-integrated error
 *    (the mean of the last k displayed frames against the mean of the k references shown at the same
 *    instants).
 *  - Scratch comes from the given arena and is released before returning (the arena ends where it started).
 */
#ifndef HZ_ERRTIME_METRICS_H
#define HZ_ERRTIME_METRICS_H

#include <stddef.h>

#include "hz/arena.h"
#include "hz/image.h"
#include "hz/status.h"

typedef struct hz_mse {
    double srgb8;  /* code units squared */
    double linear; /* linear units squared */
} hz_mse_t;

hz_status_t hz_mse(const hz_image_t *ref, const hz_image_t *test, hz_mse_t *out, hz_error_t *err);
double hz_psnr(double mse, double peak);

#define HZ_SSIM_WINDOW 11
size_t hz_ssim_scratch_bytes(uint32_t width, uint32_t height);
hz_status_t hz_ssim(const hz_image_t *ref, const hz_image_t *test, hz_arena_t *scratch, double *ssim,
                    hz_error_t *err);

/* out = mean of frames[0..k) (all of out's size). */
hz_status_t hz_image_mean(hz_image_t *out, const hz_image_t *const *frames, unsigned k, hz_error_t *err);

#endif
