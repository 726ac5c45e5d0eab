/* host-sim — host simulation build (see board.mk). Large arenas: the host renders the big reference scenes
 * (Conference 331k, dragon 871k triangles) and 256-spp references. The buffers are zero-initialised statics
 * in .bss, so untouched capacity costs address space, not RAM. */
#ifndef HZ_BOARD_H
#define HZ_BOARD_H

#define HZ_BOARD_NAME "host-sim"

#define HZ_DISPLAY_WIDTH 1280
#define HZ_DISPLAY_HEIGHT 720
#define HZ_DISPLAY_HZ 240
#define HZ_DISPLAY_DEVICE "file" /* frames go to file sinks (PNG/PPM/PFM/Y4M) */
#define HZ_DISPLAY_SINK "none"   /* `hzrt show`: the simulated display shows nothing (its report says how it went) */

#define HZ_ARENA_SCENE_BYTES (512ull << 20)
/* The furball's motion BVH in make bench's blur group (2.7M triangles) has a bound of 4.35 GiB (hzbench
 * --check-fit); untouched bss pages cost nothing. */
#define HZ_ARENA_ACCEL_BYTES (5120ull << 20)
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

#endif
