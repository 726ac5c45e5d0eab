/* aarch64-generic — Cortex-A72-class AArch64 board with a 1280x720 60 Hz display (see board.mk). Arenas sized
 * for a 2 GiB board: the mid-size shared scenes (Sponza, Lost Empire) fit; Conference and the full dragon do
 * not and are refused at load with the byte counts. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "aarch64-generic"

#define HZ_DISPLAY_WIDTH 1280
#define HZ_DISPLAY_HEIGHT 720
#define HZ_DISPLAY_HZ 60
#define HZ_DISPLAY_DEVICE "/dev/fb0" /* the fbdev fallback */
#define HZ_DISPLAY_SINK "drm"        /* DRM/KMS first (legacy fbdev emulation is gone on current Pi OS) */

#define HZ_ARENA_SCENE_BYTES (96ull << 20)
#define HZ_ARENA_ACCEL_BYTES (160ull << 20)
/* Frame arena from `hzrt info` at 1280x720 (tdense, the default mode): builtin 85.0 MiB (96.8 B/px), Sponza
 * 64.0 MiB (72.8 B/px). */
#define HZ_ARENA_FRAME_BYTES (96ull << 20)
#define HZ_ARENA_THREAD_BYTES (4ull << 20)
#define HZ_MAX_THREADS 8

#define HZ_VSYNC_SOURCE HZ_VSYNC_GPIO
#define HZ_VSYNC_GPIO_CHIP "gpiochip0"
#define HZ_VSYNC_GPIO_LINE 3 /* the QEMU virt machine's PL061 line 3 is what the VM tests pulse */

#define HZ_FEATURE_TEXTURES 1
#define HZ_FEATURE_MIRRORS 1
#define HZ_FEATURE_TRANSPARENCY 1
#define HZ_FEATURE_MOTION 1
#define HZ_FEATURE_STATS 1
#define HZ_ARENA_POISON 1

#endif
