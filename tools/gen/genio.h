/*
 * tools/gen/genio.h — output files of the generators (host tools): written to PATH.tmp and renamed into place,
 * so a failed or interrupted run never leaves a half-written model for `make scenes` to bake.
 *
 * Contract: gen_open_tmp() creates PATH.tmp (tmp receives its name); gen_finish() closes it and renames it to
 * PATH, removing it on any error. Both exit with GEN_EXIT (default 1) after a message "PROG: PATH: what: reason"
 * on stderr, PROG being GEN_PROG (define both before including this header).
 */
#ifndef HZ_GEN_GENIO_H
#define HZ_GEN_GENIO_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GEN_PROG
#error "define GEN_PROG (the program's name for messages) before including genio.h"
#endif
#ifndef GEN_EXIT
#define GEN_EXIT 1
#endif

static void gen_fail(const char *what, const char *path)
{
    fprintf(stderr, "%s: %s: %s: %s\n", GEN_PROG, path, what, errno ? strerror(errno) : "failed");
    exit(GEN_EXIT);
}

static FILE *gen_open_tmp(const char *path, char *tmp, size_t size)
{
    if (snprintf(tmp, size, "%s.tmp", path) >= (int)size)
        gen_fail("path too long", path);
    FILE *f = fopen(tmp, "wb");
    if (!f)
        gen_fail("cannot create", tmp);
    return f;
}

static void gen_finish(FILE *f, const char *tmp, const char *path)
{
    if (ferror(f) || fclose(f) != 0 || rename(tmp, path) != 0) {
        remove(tmp);
        gen_fail("cannot write", path);
    }
}

#endif /* HZ_GEN_GENIO_H */
