/* host-tool — not a board: the settings the host tools (programs/hzbake, its tests, the loader fuzzer) compile the
 * core with. They run on the build machine, take no display and allocate their own memory, so only the
 * required macros are set; the arenas here are never instantiated. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "host-tool"

#define HZ_DISPLAY_WIDTH 640
#define HZ_DISPLAY_HEIGHT 360
#define HZ_DISPLAY_HZ 60
#define HZ_DISPLAY_DEVICE "file"

#define HZ_ARENA_SCENE_BYTES (64ull << 20)
#define HZ_ARENA_ACCEL_BYTES (64ull << 20)
#define HZ_ARENA_FRAME_BYTES (64ull << 20)
#define HZ_ARENA_THREAD_BYTES (1ull << 20)
#define HZ_MAX_THREADS 1

#define HZ_VSYNC_SOURCE HZ_VSYNC_SIM
#define HZ_VSYNC_GPIO_CHIP ""
#define HZ_VSYNC_GPIO_LINE -1

#define HZ_FEATURE_TEXTURES 1
#define HZ_FEATURE_MIRRORS 1
#define HZ_FEATURE_TRANSPARENCY 1
#define HZ_FEATURE_MOTION 1
#define HZ_ARENA_POISON 1

#endif
