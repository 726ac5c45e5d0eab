/* Known-bad board for the guard tests: HZ_DISPLAY_HZ is missing; hz/config.h must stop with an #error
 * that names it. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H
#define HZ_BOARD_NAME "bad"
#define HZ_DISPLAY_WIDTH 640
#define HZ_DISPLAY_HEIGHT 480
#define HZ_DISPLAY_DEVICE "file"
#define HZ_ARENA_SCENE_BYTES (1u << 20)
#define HZ_ARENA_ACCEL_BYTES (1u << 20)
#define HZ_ARENA_FRAME_BYTES (1u << 20)
#define HZ_ARENA_THREAD_BYTES (1u << 20)
#define HZ_MAX_THREADS 1
#define HZ_VSYNC_SOURCE HZ_VSYNC_SIM
#define HZ_VSYNC_GPIO_CHIP ""
#define HZ_VSYNC_GPIO_LINE -1
#define HZ_FEATURE_TEXTURES 0
#define HZ_FEATURE_MIRRORS 0
#define HZ_FEATURE_TRANSPARENCY 0
#define HZ_FEATURE_MOTION 0
#endif
