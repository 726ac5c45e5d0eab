/*
 * tools/gen/gltfio.h — the glTF 2.0 buffers of the scene generators (host tools): one binary buffer built in
 * memory, and one buffer view per accessor, their JSON collected as text for the generator to print.
 *
 * Contract: gltf_accessor() appends `bytes` of data 4-byte aligned to the buffer and adds a view and an accessor
 * of `count` elements of `type` ("SCALAR", "VEC3", ...) and component type `ctype` (5126 float, 5123 u16, 5125
 * u32); target 1 = vertex attributes, 2 = indices, 0 = none; mn/mx (3 floats, may be NULL) the position bounds.
 * It returns the accessor's index. gltf_accessor_range() does the same for animation inputs (one float each: the
 * min and max glTF requires). gltf_acc_json / gltf_view_json hold the JSON arrays' contents, gltf_bin / gltf_bin_len
 * the buffer. Out of memory exits with status 70 after a message naming GEN_PROG (define it before including).
 * gltf_files() writes OUT_DIR/NAME.bin from the buffer and opens OUT_DIR/NAME.gltf (a temporary, into `tmp`,
 * until gen_finish) with its asset line and the scene's first words written, for the generator to go on.
 */
#ifndef HZ_GEN_GLTFIO_H
#define HZ_GEN_GLTFIO_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genio.h"

static unsigned char *gltf_bin;
static size_t gltf_bin_len, gltf_bin_cap;
static char *gltf_acc_json, *gltf_view_json;
static size_t gltf_acc_len, gltf_view_len;
static int gltf_acc_count;

static void *gltf_xrealloc(void *p, size_t n)
{
    p = realloc(p, n);
    if (!p) {
        fprintf(stderr, "%s: out of memory\n", GEN_PROG);
        exit(70);
    }
    return p;
}

static size_t gltf_bin_put(const void *p, size_t n)
{
    while (gltf_bin_len % 4)
        gltf_bin_len++;
    if (gltf_bin_len + n > gltf_bin_cap) {
        gltf_bin_cap = (gltf_bin_len + n) * 2;
        gltf_bin = gltf_xrealloc(gltf_bin, gltf_bin_cap);
    }
    size_t at = gltf_bin_len;
    memcpy(gltf_bin + at, p, n);
    gltf_bin_len += n;
    return at;
}

static void gltf_append(char **buf, size_t *len, const char *text)
{
    size_t n = strlen(text);
    *buf = gltf_xrealloc(*buf, *len + n + 1);
    memcpy(*buf + *len, text, n + 1);
    *len += n;
}

static int gltf_accessor(const void *data, size_t bytes, int count, const char *type, int ctype, int target,
                         const float *mn, const float *mx)
{
    size_t off = gltf_bin_put(data, bytes);
    char t[512];
    snprintf(t, sizeof t, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu%s}", gltf_acc_count ? "," : "",
             off, bytes, target == 1 ? ",\"target\":34962" : target == 2 ? ",\"target\":34963" : "");
    gltf_append(&gltf_view_json, &gltf_view_len, t);
    char range[256] = "";
    if (mn)
        snprintf(range, sizeof range, ",\"min\":[%.6g,%.6g,%.6g],\"max\":[%.6g,%.6g,%.6g]", mn[0], mn[1], mn[2],
                 mx[0], mx[1], mx[2]);
    snprintf(t, sizeof t, "%s{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"%s\"%s}",
             gltf_acc_count ? "," : "", gltf_acc_count, ctype, count, type, range);
    gltf_append(&gltf_acc_json, &gltf_acc_len, t);
    return gltf_acc_count++;
}

/* An animation input: `count` ascending times, with the min and max glTF requires on it. */
static int gltf_accessor_times(const float *times, int count)
{
    int a = gltf_accessor(times, sizeof(float) * (size_t)count, count, "SCALAR", 5126, 0, NULL, NULL);
    char mm[128];
    gltf_acc_len -= 1; /* reopen the accessor's object: drop its closing brace */
    snprintf(mm, sizeof mm, ",\"min\":[%.9g],\"max\":[%.9g]}", times[0], times[count - 1]);
    gltf_append(&gltf_acc_json, &gltf_acc_len, mm);
    return a;
}

static FILE *gltf_files(const char *dir, const char *name, char *path, size_t psize, char *tmp, size_t tsize)
{
    snprintf(path, psize, "%s/%s.bin", dir, name);
    FILE *f = gen_open_tmp(path, tmp, tsize);
    fwrite(gltf_bin, 1, gltf_bin_len, f);
    gen_finish(f, tmp, path);
    snprintf(path, psize, "%s/%s.gltf", dir, name);
    f = gen_open_tmp(path, tmp, tsize);
    fprintf(f, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"hzrt tools/gen/%s\"},\n", GEN_PROG);
    fprintf(f, "\"scene\":0,\"scenes\":[{\"nodes\":[");
    return f;
}

static void gltf_free(void)
{
    free(gltf_bin), free(gltf_acc_json), free(gltf_view_json);
    gltf_bin = NULL, gltf_acc_json = gltf_view_json = NULL;
}

#endif /* HZ_GEN_GLTFIO_H */
