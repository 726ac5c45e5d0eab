/* x86-kiosk — 1280x800 at 120 Hz on fbdev, v-sync from FBIO_WAITFORVSYNC (see board.mk). */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "x86-kiosk"

#define HZ_DISPLAY_WIDTH 1280
#define HZ_DISPLAY_HEIGHT 800
#define HZ_DISPLAY_HZ 120
#define HZ_DISPLAY_DEVICE "/dev/fb0"

#define HZ_ARENA_SCENE_BYTES (256ull << 20)
#define HZ_ARENA_ACCEL_BYTES (512ull << 20)
/* Frame arena from `hzrt info` at 1280x800 (tdense, the default mode): builtin 94.5 MiB (96.8 B/px),
 * Conference 71.0 MiB (72.8 B/px), Conference's accel build at most 136 MiB. */
#define HZ_ARENA_FRAME_BYTES (128ull << 20)
#define HZ_ARENA_THREAD_BYTES (8ull << 20)
#define HZ_MAX_THREADS 16

#define HZ_VSYNC_SOURCE HZ_VSYNC_FBDEV
#define HZ_VSYNC_GPIO_CHIP ""
#define HZ_VSYNC_GPIO_LINE -1

#define HZ_FEATURE_TEXTURES 1
#define HZ_FEATURE_MIRRORS 1
#define HZ_FEATURE_TRANSPARENCY 1
#define HZ_FEATURE_MOTION 1

#endif
