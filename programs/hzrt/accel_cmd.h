/*
 * accel_cmd.h — `hzrt accel SCENE`: builds the acceleration structure of a scene and reports it (build time,
 * memory per triangle, tree shape), after checking the accel arena's memory plan.
 *
 * Contract: returns the process exit status: 0, HZ_EXIT_USAGE for a bad command line, 64 + code for a failure
 * (a scene that does not load, or whose accel does not fit the board's accel arena: HZ_E_NO_MEMORY with both
 * byte counts). With --motion-check N it builds the native motion BVH (--blur-bvh) over the scene's animation
 * (or procedural keys), checks N random rays at random times against brute force and prints exactly
 * "motion-check: N rays, K misses, M mismatches" on stdout (progress on stderr); exit 1 when K or M is not 0.
 */
#ifndef HZ_PORT_ACCEL_CMD_H
#define HZ_PORT_ACCEL_CMD_H

int hz_cmd_accel(int argc, char **argv);

#endif
