/* host-sim — host simulation build (see board.mk). Large arenas: the host renders the big reference scenes
 * (Conference 331k, dragon 871k triangles) and 256-spp references, and builds furball-sway's motion BVHs at its
 * 9 pose keys. The arenas are address space reserved without commitment (HZ_POOLS_RESERVE): capacity costs RAM
 * only once touched, and the program starts on machines with less RAM than the arenas' total. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "host-sim"

#define HZ_DISPLAY_WIDTH 1280
#define HZ_DISPLAY_HEIGHT 720
#define HZ_DISPLAY_HZ 240
#define HZ_DISPLAY_DEVICE "file" /* frames go to file sinks (PNG/PPM/PFM/Y4M) */
#define HZ_DISPLAY_SINK "none"   /* `hzrt show`: the simulated display shows nothing (its report says how it went) */

/* furball-sway (2.7M triangles) at its 9 pose keys in make bench's motion group: the scene and 400 MiB of keys;
 * its MSBVH at the unbounded split budget (4) has a bound of 29.75 GiB (hzbench --check-fit), a worst case
 * (references at five times the triangles) that the build stays far below. */
#define HZ_ARENA_SCENE_BYTES (1024ull << 20)
#define HZ_ARENA_ACCEL_BYTES (32768ull << 20)
#define HZ_ARENA_FRAME_BYTES (256ull << 20)
#define HZ_ARENA_THREAD_BYTES (8ull << 20)
#define HZ_MAX_THREADS 64

#define HZ_VSYNC_SOURCE HZ_VSYNC_SIM
#define HZ_VSYNC_GPIO_CHIP ""
#define HZ_VSYNC_GPIO_LINE -1

#define HZ_FEATURE_TEXTURES 1
#define HZ_FEATURE_MIRRORS 1
#define HZ_FEATURE_TRANSPARENCY 1
#define HZ_FEATURE_MOTION 1
#define HZ_FEATURE_STATS 1
#define HZ_ARENA_POISON 1
#define HZ_POOLS_RESERVE 1

#endif
