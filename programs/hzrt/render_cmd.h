/*
 * render_cmd.h — the `hzrt render` and `hzrt show` subcommands (see their --help): a scene through the one frame
 * loop, to files (render's default) or to the board's display locked to its v-sync (show's default: the board's
 * scene in the board's mode, with the latency report).
 *
 * Contract: returns the process exit status: 0, HZ_EXIT_USAGE for a bad command line, or 64 + the hz status
 * code of a run-time failure (after printing the reason, naming the input). Outputs go through temp file +
 * rename, so a failed run leaves no partial file.
 */
#ifndef HZ_PORT_RENDER_CMD_H
#define HZ_PORT_RENDER_CMD_H

int hz_cmd_render(int argc, char **argv);
int hz_cmd_show(int argc, char **argv);

#endif
