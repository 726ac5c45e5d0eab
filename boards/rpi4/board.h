/* rpi4 — Raspberry Pi 4 Model B, 800x480 RGB666 DPI panel at 60 Hz, v-sync captured on GPIO26 (header pin 37)
 * from the DPI VSYNC output on GPIO2 (header pin 3). Wiring and config.txt in README.md. Arenas sized for the
 * 2 GiB model with room left for the OS. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "rpi4"

#define HZ_DISPLAY_WIDTH 800
#define HZ_DISPLAY_HEIGHT 480
#define HZ_DISPLAY_HZ 60
#define HZ_DISPLAY_DEVICE "/dev/fb0" /* the fbdev fallback */
#define HZ_DISPLAY_SINK "drm"        /* DRM/KMS first (legacy fbdev emulation is gone on current Pi OS) */

#define HZ_ARENA_SCENE_BYTES (96ull << 20)
#define HZ_ARENA_ACCEL_BYTES (160ull << 20)
/* Frame arena from `hzrt info` at 800x480 (tdense, the default mode): builtin 35.4 MiB (mirrors and motion:
 * 96.8 B/px), Sponza 26.6 MiB (72.8 B/px); TAA needs less, full mode 23.4 MiB. */
#define HZ_ARENA_FRAME_BYTES (40ull << 20)
#define HZ_ARENA_THREAD_BYTES (4ull << 20)
#define HZ_MAX_THREADS 4

#define HZ_VSYNC_SOURCE HZ_VSYNC_GPIO
/* By label, not number: the header's controller has been gpiochip0 on some kernels and not on others. */
#define HZ_VSYNC_GPIO_CHIP "pinctrl-bcm2711"
#define HZ_VSYNC_GPIO_LINE 26

#define HZ_FEATURE_TEXTURES 1
#define HZ_FEATURE_MIRRORS 1
#define HZ_FEATURE_TRANSPARENCY 1
#define HZ_FEATURE_MOTION 1

#endif
