/*
 * accel_cmd.h — `hzrt accel SCENE`: builds the acceleration structure of a scene and reports it (build time,
 * memory per triangle, tree shape), after checking the accel arena's memory plan.
 *
 * Contract: returns the process exit status: 0, HZ_EXIT_USAGE for a bad command line, 64 + code for a failure
 * (a scene that does not load, or whose accel does not fit the board's accel arena: HZ_E_NO_MEMORY with both
 * byte counts).
 */
#ifndef HZ_PORT_ACCEL_CMD_H
#define HZ_PORT_ACCEL_CMD_H

int hz_cmd_accel(int argc, char **argv);

#endif
