/*
 * imageio.h — image files for the Linux port: PNG (libpng), PPM (P6/P5), PFM (PF/Pf) and a streaming Y4M video
 * writer. These are hzrt's file sinks and the errtime tool's inputs and cache.
 *
 * Contract:
 *  - Images are hz_image_t (linear-light RGB floats, top row first; include/hz/image.h). 8- and 16-bit files
 *    (PNG, PPM) hold sRGB-encoded codes: readers decode them to linear light (8-bit exactly through the
 *    hz_srgb8 table), writers encode with hz_srgb8_encode (exact rounding, clamped, NaN -> 0). PFM holds linear
 *    floats as they are (NaN and Inf included), so it is the lossless format (the errtime reference cache).
 *  - Readers validate before they allocate: magic, header syntax, dimensions (1..HZ_IMAGE_MAX_DIM each), sample
 *    depth, and that the file holds all the pixel data. Errors name the file and the reason, with distinct codes:
 *      HZ_E_IO          cannot open or read (missing file, a directory, read error)
 *      HZ_E_FORMAT      wrong magic, malformed header, truncated data
 *      HZ_E_CORRUPT     a PNG checksum (CRC) does not match
 *      HZ_E_RANGE       a dimension is 0 or larger than HZ_IMAGE_MAX_DIM ("absurd size")
 *      HZ_E_UNSUPPORTED a valid variant this reader does not take (ASCII PPM, PAM), or PNG without libpng
 *      HZ_E_NO_MEMORY   the arena cannot hold the image (bytes needed vs available)
 *    Pixels come from the caller's arena; temporary rows come from it too and are released before returning,
 *    so on success the arena holds exactly the image, and on failure it is back where it was.
 *  - PNG input: any bit depth and colour type; palette, grey and tRNS are expanded to RGB and alpha is dropped
 *    (as NVIDIA's FLIP tool does); gAMA/iCCP chunks are ignored (the data is taken as sRGB). PNG output: 8-bit
 *    RGB with an sRGB chunk. PPM: maxval 1..65535 (samples scaled to [0, 1], then sRGB-decoded); output P6 8-bit.
 *    PFM: either byte order on input (the sign of the scale), rows stored bottom to top as the format says;
 *    output little-endian ("-1.0"), colour ("PF").
 *  - Writers go through fileio.h: a temporary file renamed into place when complete, so a failed write leaves
 *    no partial file and an existing file untouched.
 *  - Y4M: `hz_y4m_open` writes the stream header, each `hz_y4m_write` one frame ("FRAME" + planes),
 *    `hz_y4m_close` commits (renames) the file; `hz_y4m_abort` discards it. Output is 8-bit, C444 or C420jpeg
 *    (4:2:0, chroma sited at the centre of each 2x2 block: the JPEG/MPEG-1 siting; odd sizes round the chroma
 *    planes up). R'G'B' are the sRGB codes a PNG of the frame would hold, divided by 255 (no other transfer
 *    function is applied). With the matrix's Kr, Kb (BT.601: 0.299, 0.114; BT.709: 0.2126, 0.0722):
 *        Y' = Kr R' + (1 - Kr - Kb) G' + Kb B',  Pb = (B' - Y') / (2 (1 - Kb)),  Pr = (R' - Y') / (2 (1 - Kr))
 *      full range (JFIF, H.273 full): Y = round(255 Y'),      Cb = round(128 + 255 Pb), Cr = round(128 + 255 Pr)
 *      limited (studio) range:        Y = round(16 + 219 Y'), Cb = round(128 + 224 Pb), Cr = round(128 + 224 Pr)
 *    clamped to 0..255; 4:2:0 averages Pb, Pr over the 2x2 block before rounding. The header says the range
 *    (XCOLORRANGE=FULL|LIMITED, read by ffmpeg); Y4M cannot say the matrix, so tell the player:
 *      ffmpeg -colorspace bt709 -i f.y4m ...   (or bt470bg for BT.601; BT.601 is what ffmpeg assumes otherwise)
 *    The stream allocates its row buffers at open; writing frames allocates nothing.
 */
#ifndef HZ_PORT_IMAGEIO_H
#define HZ_PORT_IMAGEIO_H

#include <stdbool.h>
#include <stdint.h>

#include "fileio.h"
#include "hz/arena.h"
#include "hz/image.h"
#include "hz/status.h"

/* True when this build has libpng (the Makefile enables it where the target toolchain links -lpng). */
bool hz_png_supported(void);

hz_status_t hz_png_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err);
hz_status_t hz_png_write(const char *path, const hz_image_t *img, hz_error_t *err);
/* PNG and PPM of 8-bit sRGB codes (RGB24 rows of `stride` bytes): the same file as writing the linear image
 * they encode. */
hz_status_t hz_png_write_rgb8(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err);
hz_status_t hz_ppm_write_rgb8(const char *path, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err);

hz_status_t hz_ppm_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err);
hz_status_t hz_ppm_write(const char *path, const hz_image_t *img, hz_error_t *err);

hz_status_t hz_pfm_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err);
hz_status_t hz_pfm_write(const char *path, const hz_image_t *img, hz_error_t *err);

/* By content (PNG signature, "P6"/"P5", "PF"/"Pf"); an unknown magic is HZ_E_FORMAT. */
hz_status_t hz_image_read(const char *path, hz_arena_t *arena, hz_image_t *img, hz_error_t *err);
/* By extension (.png, .ppm, .pfm; case-insensitive); another extension is HZ_E_INVALID_ARG. */
hz_status_t hz_image_write(const char *path, const hz_image_t *img, hz_error_t *err);

typedef enum hz_y4m_chroma { HZ_Y4M_C444 = 0, HZ_Y4M_C420JPEG } hz_y4m_chroma_t;
typedef enum hz_y4m_matrix { HZ_Y4M_BT601 = 0, HZ_Y4M_BT709 } hz_y4m_matrix_t;

typedef struct hz_y4m_opts {
    hz_y4m_chroma_t chroma;
    hz_y4m_matrix_t matrix;
    bool full_range;
    uint32_t fps_num, fps_den; /* frame rate as a fraction, e.g. 240/1 */
} hz_y4m_opts_t;

typedef struct hz_y4m {
    hz_out_t out;
    hz_y4m_opts_t opts;
    uint32_t width, height, cw, ch; /* luma and chroma plane sizes */
    uint8_t *y, *cb, *cr;            /* planes, allocated at open */
    float *pb, *pr;                  /* one row pair of unquantised chroma (4:2:0) */
    uint8_t *row;                    /* one row of 8-bit codes */
    uint64_t frames;
} hz_y4m_t;

hz_status_t hz_y4m_open(hz_y4m_t *y4m, const char *path, uint32_t width, uint32_t height, const hz_y4m_opts_t *opts,
                        hz_error_t *err);
/* frame must be width x height. */
hz_status_t hz_y4m_write(hz_y4m_t *y4m, const hz_image_t *frame, hz_error_t *err);
/* The same frame as its 8-bit sRGB codes (RGB24 rows of `stride` bytes): the same bytes as hz_y4m_write of the
 * linear frame they encode. */
hz_status_t hz_y4m_write_rgb8(hz_y4m_t *y4m, const uint8_t *rgb, uint32_t w, uint32_t h, size_t stride,
                              hz_error_t *err);
hz_status_t hz_y4m_close(hz_y4m_t *y4m, hz_error_t *err);
void hz_y4m_abort(hz_y4m_t *y4m);

/* The conversion the writer uses, for one pixel of sRGB codes (exposed for tests and for other sinks). */
void hz_y4m_rgb_to_ycbcr(const hz_y4m_opts_t *opts, uint8_t r, uint8_t g, uint8_t b, uint8_t ycc[3]);

#endif
