/*
 * optwhere.h — where hzrt's options act (opttab.h's tables for render, show and latency): the render modes an
 * entry acts in, the v-sync sources, sinks, frames and clock it acts with, and the commands that take it.
 *
 * Contract:
 *  - `where` holds bits of four groups (source, sink, frames, clock); in a group where the entry has no bit it
 *    acts with anything. hz_opt_acts() says whether an entry acts in a run described by bits of every group;
 *    hz_opt_refuse_idle() prints why it does not ("--jitter-us does nothing with --source gpio: it acts with
 *    --source sim") and returns HZ_EXIT_USAGE.
 *  - hz_opt_usage() prints the entries a command takes: "  --name ARG  help [lo..hi] (only ...)", under the
 *    entries' section headings; the "only" note names the modes and the groups the command does not fix.
 */
#ifndef HZ_PROGRAMS_OPTWHERE_H
#define HZ_PROGRAMS_OPTWHERE_H

#include "opttab.h"

/* Where an option acts. Sources: */
#define HZ_OW_OFFLINE (1u << 0)
#define HZ_OW_SIM (1u << 1)
#define HZ_OW_GPIO (1u << 2)
#define HZ_OW_FBDEV_SRC (1u << 3)
#define HZ_OW_DRM_SRC (1u << 4)
#define HZ_OW_V4L2_SRC (1u << 5)
#define HZ_OW_VCD (1u << 6)
#define HZ_OW_CSV (1u << 7)
#define HZ_OW_SOURCES 0xffu
#define HZ_OW_DISPLAY_SOURCES (HZ_OW_SOURCES & ~HZ_OW_OFFLINE)
/* sinks (`display` is the board's drm or fbdev): */
#define HZ_OW_FILES (1u << 8)
#define HZ_OW_NONE (1u << 9)
#define HZ_OW_DRM (1u << 10)
#define HZ_OW_FBDEV (1u << 11)
#define HZ_OW_V4L2 (1u << 12)
#define HZ_OW_SINKS 0x1f00u
#define HZ_OW_DEVICE_SINKS (HZ_OW_DRM | HZ_OW_FBDEV | HZ_OW_V4L2)
/* frames: */
#define HZ_OW_PATTERN (1u << 13)
#define HZ_OW_SCENE (1u << 14)
#define HZ_OW_EDGES (1u << 15)
#define HZ_OW_FRAMES (HZ_OW_PATTERN | HZ_OW_SCENE)
#define HZ_OW_WHAT 0xe000u
/* clock: */
#define HZ_OW_REAL (1u << 16)
#define HZ_OW_VIRTUAL (1u << 17)
#define HZ_OW_CLOCK 0x30000u

/* Commands (0 in an entry: every command). */
#define HZ_OC_RENDER (1u << 0)
#define HZ_OC_SHOW (1u << 1)
#define HZ_OC_LATENCY (1u << 2)

bool hz_opt_acts(const hz_opt_t *o, unsigned run_where);
int hz_opt_refuse_idle(const hz_opt_t *o, const char *cmd, unsigned run_where);
/* "full, taa or tdense" for a mode mask. */
const char *hz_opt_modes_str(char *buf, size_t cap, unsigned modes);
/* fixed: groups (HZ_OW_SOURCES, ...) the command fixes, left out of the annotations (render always draws a
 * scene). */
void hz_opt_usage(FILE *f, const hz_opt_t *t, size_t n, unsigned cmd, unsigned fixed);

#endif
