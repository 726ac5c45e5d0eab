/*
 * libFuzzer target for the command-line option parsers: the tables of programs/opt/opttab.c, the render options
 * (renderopts.c: hz_ropts_take, hz_ropts_check) and the frame loop's options (showopts.c: hz_sopts_take,
 * hz_sopts_check), through the commands' own entry points (hz_cmd_render, hz_cmd_show, hz_cmd_latency), so the
 * combination checks of show.c (--render-model, --guard, --latch, the marker's layout, ...) run too. With
 * hz_show_check_only set a command returns once its command line is checked: nothing is rendered, opened or
 * written.
 *
 * Input: arguments separated by NUL or newline. When the first one is "render", "show" or "latency" it names the
 * command; otherwise the first byte picks one and every argument is an option. Each argument lives in a buffer
 * of its own size, so a read past its NUL is an ASan report.
 *
 * Checks beyond the sanitizers: the exit status of a checked command line is 0 or 2 (a usage error), never a
 * run-time failure; the same command line checked twice gets the same status (the commands' state is reset).
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "latency.h"
#include "render_cmd.h"
#include "show.h"

#define MAX_ARGS 256

typedef int (*cmd_fn)(int, char **);

static int run(cmd_fn fn, int argc, char **argv)
{
    /* argv as a command may leave it (none reorders today; a copy keeps the check honest if one ever does) */
    char *copy[MAX_ARGS + 2];
    memcpy(copy, argv, (size_t)(argc + 1) * sizeof *argv);
    return fn(argc, copy);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const struct { const char *name; cmd_fn fn; } cmds[] = {
        { "render", hz_cmd_render }, { "show", hz_cmd_show }, { "latency", hz_cmd_latency },
    };
    hz_cli_prog = "hzrt";
    hz_show_check_only = true;
    if (size == 0)
        return 0;
    char *argv[MAX_ARGS + 2];
    int argc = 1;
    argv[0] = NULL;
    for (size_t i = 0; i <= size && argc <= MAX_ARGS;) {
        size_t j = i;
        while (j < size && data[j] != 0 && data[j] != '\n')
            j++;
        char *a = malloc(j - i + 1);
        if (!a)
            abort();
        memcpy(a, data + i, j - i);
        a[j - i] = 0;
        argv[argc++] = a;
        i = j + 1;
    }
    argv[argc] = NULL;
    size_t c = data[0] % 3;
    int first = 1;
    for (size_t k = 0; k < 3; k++)
        if (!strcmp(argv[1], cmds[k].name))
            c = k, first = 2;
    /* argv[first - 1] becomes the command's argv[0] */
    char *name = argv[first - 1];
    argv[first - 1] = (char *)cmds[c].name;
    int n = argc - (first - 1);
    int rc1 = run(cmds[c].fn, n, argv + first - 1);
    int rc2 = run(cmds[c].fn, n, argv + first - 1);
    if (rc1 != 0 && rc1 != HZ_EXIT_USAGE) {
        fprintf(stderr, "fuzz_opts: %s: a command line checked without running exited %d\n", cmds[c].name, rc1);
        abort();
    }
    if (rc1 != rc2) {
        fprintf(stderr, "fuzz_opts: %s: the same command line exited %d, then %d\n", cmds[c].name, rc1, rc2);
        abort();
    }
    argv[first - 1] = name;
    for (int k = 1; k < argc; k++)
        free(argv[k]);
    return 0;
}
