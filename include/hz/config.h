/*
 * hz/config.h — the one place where a board's settings enter the build.
 *
 * Contract: every translation unit that depends on the board includes this header (never board.h directly).
 * The Makefile puts boards/<BOARD>/ on the include path, so "board.h" is the chosen board's file. Every
 * required setting must be defined there; a missing one stops the build with an #error that names it.
 * Optional settings get their defaults here. Everything in this header is preprocessor-only, so integer-only
 * code (src/pattern/) may include it.
 */
#ifndef HZ_CONFIG_H
#define HZ_CONFIG_H

#include "board.h"

/* ---- required: identity and display ---- */
#ifndef HZ_BOARD_NAME
#error "board.h must define HZ_BOARD_NAME (a string naming the board)"
#endif
#ifndef HZ_DISPLAY_WIDTH
#error "board.h must define HZ_DISPLAY_WIDTH (panel width in pixels)"
#endif
#ifndef HZ_DISPLAY_HEIGHT
#error "board.h must define HZ_DISPLAY_HEIGHT (panel height in pixels)"
#endif
#ifndef HZ_DISPLAY_HZ
#error "board.h must define HZ_DISPLAY_HZ (panel refresh rate in Hz)"
#endif
#ifndef HZ_DISPLAY_DEVICE
#error "board.h must define HZ_DISPLAY_DEVICE (display node such as \"/dev/fb0\", or \"file\" for file sinks)"
#endif

/* ---- required: memory (bytes of each static arena; the port owns the buffers) ---- */
#ifndef HZ_ARENA_SCENE_BYTES
#error "board.h must define HZ_ARENA_SCENE_BYTES (geometry, materials, textures, animation)"
#endif
#ifndef HZ_ARENA_ACCEL_BYTES
#error "board.h must define HZ_ARENA_ACCEL_BYTES (acceleration structure and build scratch)"
#endif
#ifndef HZ_ARENA_FRAME_BYTES
#error "board.h must define HZ_ARENA_FRAME_BYTES (framebuffers, G-buffer, history)"
#endif
#ifndef HZ_ARENA_THREAD_BYTES
#error "board.h must define HZ_ARENA_THREAD_BYTES (per-thread scratch, one arena per worker)"
#endif
#ifndef HZ_MAX_THREADS
#error "board.h must define HZ_MAX_THREADS (worker threads the static pool can hold)"
#endif

/* ---- required: v-sync source ---- */
#define HZ_VSYNC_SIM 1    /* simulated display clock (host builds) */
#define HZ_VSYNC_GPIO 2   /* edge events on a GPIO input wired to the panel's VSYNC */
#define HZ_VSYNC_FBDEV 3  /* FBIO_WAITFORVSYNC on HZ_DISPLAY_DEVICE */
/* The display `--sink display` drives: "drm" (DRM/KMS, fbdev HZ_DISPLAY_DEVICE as fallback), "fbdev" or "none"
 * (a simulated display that shows nothing). */
#ifndef HZ_DISPLAY_SINK
#define HZ_DISPLAY_SINK "fbdev"
#endif
/* What `hzrt show` (the board's default command) shows on that display: a scene ("builtin" or a .hzb path on
 * the target) in a render mode (hz_render_mode_t). */
#ifndef HZ_DISPLAY_SCENE
#define HZ_DISPLAY_SCENE "builtin"
#endif
#ifndef HZ_DISPLAY_MODE
#define HZ_DISPLAY_MODE HZ_MODE_TDENSE
#endif
#ifndef HZ_VSYNC_SOURCE
#error "board.h must define HZ_VSYNC_SOURCE (HZ_VSYNC_SIM, HZ_VSYNC_GPIO or HZ_VSYNC_FBDEV)"
#endif
#ifndef HZ_VSYNC_GPIO_CHIP
#error "board.h must define HZ_VSYNC_GPIO_CHIP (gpiochip name, path or label; \"\" when unused)"
#endif
#ifndef HZ_VSYNC_GPIO_LINE
#error "board.h must define HZ_VSYNC_GPIO_LINE (line offset on that chip; -1 when unused)"
#endif

/* ---- required: features compiled in (1) or out (0) ---- */
#ifndef HZ_FEATURE_TEXTURES
#error "board.h must define HZ_FEATURE_TEXTURES (0 or 1)"
#endif
#ifndef HZ_FEATURE_MIRRORS
#error "board.h must define HZ_FEATURE_MIRRORS (0 or 1)"
#endif
#ifndef HZ_FEATURE_TRANSPARENCY
#error "board.h must define HZ_FEATURE_TRANSPARENCY (0 or 1: alpha cutouts and blended surfaces)"
#endif
#ifndef HZ_FEATURE_MOTION
#error "board.h must define HZ_FEATURE_MOTION (0 or 1: animated objects, motion vectors, motion blur)"
#endif

/* A build may leave out what its board has (make FEATURES_OFF="transparency motion", see doc/boards.md): the
 * Makefile passes -DHZ_FEATURE_OFF_<NAME>, which turns the board's 1 into 0. Nothing turns a board's 0 into 1. */
#ifdef HZ_FEATURE_OFF_TEXTURES
#undef HZ_FEATURE_TEXTURES
#define HZ_FEATURE_TEXTURES 0
#endif
#ifdef HZ_FEATURE_OFF_MIRRORS
#undef HZ_FEATURE_MIRRORS
#define HZ_FEATURE_MIRRORS 0
#endif
#ifdef HZ_FEATURE_OFF_TRANSPARENCY
#undef HZ_FEATURE_TRANSPARENCY
#define HZ_FEATURE_TRANSPARENCY 0
#endif
#ifdef HZ_FEATURE_OFF_MOTION
#undef HZ_FEATURE_MOTION
#define HZ_FEATURE_MOTION 0
#endif
#if (HZ_FEATURE_TEXTURES != 0 && HZ_FEATURE_TEXTURES != 1) || (HZ_FEATURE_MIRRORS != 0 && HZ_FEATURE_MIRRORS != 1) || \
    (HZ_FEATURE_TRANSPARENCY != 0 && HZ_FEATURE_TRANSPARENCY != 1) || (HZ_FEATURE_MOTION != 0 && HZ_FEATURE_MOTION != 1)
#error "HZ_FEATURE_TEXTURES, _MIRRORS, _TRANSPARENCY and _MOTION must be 0 or 1"
#endif

/* ---- sanity of the values (catches typos such as a size in KiB) ---- */
#if HZ_DISPLAY_WIDTH < 16 || HZ_DISPLAY_HEIGHT < 16 || HZ_DISPLAY_WIDTH > 8192 || HZ_DISPLAY_HEIGHT > 8192
#error "HZ_DISPLAY_WIDTH/HEIGHT must lie in [16, 8192]"
#endif
#if HZ_DISPLAY_HZ < 1 || HZ_DISPLAY_HZ > 1000
#error "HZ_DISPLAY_HZ must lie in [1, 1000]"
#endif
#if HZ_MAX_THREADS < 1 || HZ_MAX_THREADS > 256
#error "HZ_MAX_THREADS must lie in [1, 256]"
#endif
#if HZ_VSYNC_SOURCE != HZ_VSYNC_SIM && HZ_VSYNC_SOURCE != HZ_VSYNC_GPIO && HZ_VSYNC_SOURCE != HZ_VSYNC_FBDEV
#error "HZ_VSYNC_SOURCE must be HZ_VSYNC_SIM, HZ_VSYNC_GPIO or HZ_VSYNC_FBDEV"
#endif

/* ---- optional settings ---- */
#ifndef HZ_FEATURE_STATS
#define HZ_FEATURE_STATS 0 /* per-query traversal counters (nodes visited, triangles tested) */
#endif
#ifndef HZ_ARENA_POISON
#define HZ_ARENA_POISON 0 /* fill memory released by hz_arena_reset with 0xA5 to expose use-after-reset */
#endif
#ifndef HZ_POOLS_RESERVE
#define HZ_POOLS_RESERVE 0 /* Linux port: arenas in one reservation of address space (mmap, MAP_NORESERVE) instead of
                            * .bss, for host builds whose arenas exceed a small machine's RAM and swap */
#endif
#ifndef HZ_VSYNC_GPIO_ACTIVE_LOW
#define HZ_VSYNC_GPIO_ACTIVE_LOW 0
#endif
#ifndef HZ_VSYNC_GPIO_EDGE
#define HZ_VSYNC_GPIO_EDGE 0 /* the edge that marks a refresh: 0 rising, 1 falling, 2 any (photodiode on the marker) */
#endif
#if HZ_VSYNC_GPIO_EDGE < 0 || HZ_VSYNC_GPIO_EDGE > 2
#error "HZ_VSYNC_GPIO_EDGE must be 0 (rising), 1 (falling) or 2 (any)"
#endif

/* ---- SIMD: derived from the compiler's ISA macros, which the board's flags set ---- */
#if defined(__AVX2__) && defined(__FMA__)
#define HZ_SIMD_AVX2 1
#define HZ_SIMD_LANES 8
#elif defined(__ARM_NEON) && defined(__aarch64__)
#define HZ_SIMD_NEON 1
#define HZ_SIMD_LANES 4
#else
#define HZ_SIMD_SCALAR 1
#define HZ_SIMD_LANES 1
#endif

/* The Makefile passes the board.mk's BOARD_SIMD choice; it must agree with the ISA flags. */
#if defined(HZ_BOARD_SIMD_AVX2) && !defined(HZ_SIMD_AVX2)
#error "board.mk selects BOARD_SIMD=avx2 but BOARD_CFLAGS do not enable AVX2 and FMA"
#endif
#if defined(HZ_BOARD_SIMD_NEON) && !defined(HZ_SIMD_NEON)
#error "board.mk selects BOARD_SIMD=neon but the target is not AArch64 with NEON"
#endif

#endif /* HZ_CONFIG_H */
