/* Embree furball import (see scene.h): an XML scene with one <RoundLineSegments> element whose <indices> and
 * <positions> name byte ranges of a binary file beside it (the XML's name with .bin, or .bin.gz as Debian
 * ships it). indices[k] is the first point of segment k (segment = points i, i + 1); positions are float4
 * (x, y, z, radius). A strand is a run of segments whose indices follow each other.
 *
 * Each strand point becomes a ring of tube_sides vertices around the strand (a parallel-transported frame, so
 * rings do not twist), each segment 2 * tube_sides triangles; tube_sides = 1 makes a flat ribbon (2 vertices
 * per point, 2 triangles per segment). Vertex order: strands in file order, rings in point order, ring
 * vertices by angle; tests rely on it to check the tubes against the strand points. */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HZ_BAKE_PI 3.14159265358979323846

/* Finds `<tag ` and reads attribute `attr="N"` inside it. */
static int xml_attr(const char *xml, const char *tag, const char *attr, unsigned long long *out)
{
    char open[64];
    snprintf(open, sizeof open, "<%s", tag);
    const char *t = strstr(xml, open);
    while (t && !(t[strlen(open)] == ' ' || t[strlen(open)] == '\t' || t[strlen(open)] == '\n'))
        t = strstr(t + 1, open);
    if (!t)
        return 0;
    const char *end = strchr(t, '>');
    char key[64];
    snprintf(key, sizeof key, "%s=\"", attr);
    const char *a = strstr(t, key);
    if (!a || (end && a > end))
        return 0;
    a += strlen(key);
    char *stop;
    unsigned long long v = strtoull(a, &stop, 10);
    if (stop == a || *stop != '"')
        return 0;
    *out = v;
    return 1;
}

/* <float3 name="Kt">r g b</float3> */
static int xml_float3(const char *xml, const char *name, float out[3])
{
    char key[80];
    snprintf(key, sizeof key, "<float3 name=\"%s\">", name);
    const char *a = strstr(xml, key);
    if (!a)
        return 0;
    a += strlen(key);
    char *e1, *e2, *e3;
    double x = strtod(a, &e1), y = strtod(e1, &e2), z = strtod(e2, &e3);
    if (e1 == a || e2 == e1 || e3 == e2 || !isfinite(x + y + z))
        return 0;
    out[0] = (float)x, out[1] = (float)y, out[2] = (float)z;
    return 1;
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

/* Any unit vector perpendicular to t. */
static void perpendicular(const double t[3], double n[3])
{
    double a[3] = { 1, 0, 0 };
    if (fabs(t[0]) > 0.9)
        a[0] = 0, a[1] = 1;
    double d = a[0] * t[0] + a[1] * t[1] + a[2] * t[2];
    for (int k = 0; k < 3; k++)
        n[k] = a[k] - d * t[k];
    normalize3(n);
}

hz_status_t hz_bake_import_furball(hz_bake_scene_t *s, const char *path, const hz_bake_sidecar_t *sc, hz_error_t *err)
{
    uint8_t *xml;
    size_t xml_size;
    hz_bake_phase("reading strands and tessellating them into tubes");
    hz_status_t st = hz_bake_read_file(path, &xml, &xml_size, err);
    if (st)
        return st;
    const char *x = (const char *)xml;
    unsigned long long iofs, isize, pofs, psize;
    if (!strstr(x, "<RoundLineSegments>")) {
        free(xml);
        return hz_bake_err(err, HZ_E_UNSUPPORTED,
                           "%s: not an Embree RoundLineSegments scene (the only XML the baker "
                           "reads)",
                           path);
    }
    if (!xml_attr(x, "indices", "ofs", &iofs) || !xml_attr(x, "indices", "size", &isize) ||
        !xml_attr(x, "positions", "ofs", &pofs) || !xml_attr(x, "positions", "size", &psize)) {
        free(xml);
        return hz_bake_err(err, HZ_E_FORMAT, "%s: <indices ofs= size=/> or <positions ofs= size=/> missing", path);
    }
    float color[3] = { 0.64f, 0.456f, 0.256f };
    xml_float3(x, "Kt", color);
    free(xml);

    char bin[4096];
    size_t n = strlen(path);
    if (n < 4 || n + 4 >= sizeof bin)
        return hz_bake_err(err, HZ_E_INVALID_ARG, "%s: path too long", path);
    snprintf(bin, sizeof bin, "%.*s.bin", (int)(n - 4), path);
    uint8_t *data;
    size_t size;
    if (hz_bake_file_exists(bin)) {
        st = hz_bake_read_file(bin, &data, &size, err);
    } else {
        strcat(bin, ".gz");
        st = hz_bake_read_gzip(bin, &data, &size, err);
    }
    if (st)
        return st;
    if (isize == 0 || psize < 2 || isize > UINT32_MAX || psize > UINT32_MAX || iofs > size || isize * 4 > size - iofs ||
        pofs > size || psize * 16 > size - pofs || iofs % 4 || pofs % 4) {
        free(data);
        return hz_bake_err(err, HZ_E_FORMAT,
                           "%s: indices (%llu at byte %llu) or positions (%llu at byte %llu) do not "
                           "fit its %zu bytes (truncated?)",
                           bin, isize, iofs, psize, pofs, size);
    }
    const uint32_t *idx = (const uint32_t *)(data + iofs);
    const float *pts = (const float *)(data + pofs);
    for (unsigned long long k = 0; k < isize; k++)
        if ((unsigned long long)idx[k] + 1 >= psize) {
            st = hz_bake_err(err, HZ_E_FORMAT, "%s: segment %llu starts at point %u of %llu", bin, k, idx[k], psize);
            free(data);
            return st;
        }
    for (unsigned long long k = 0; k < psize; k++) {
        const float *p = pts + k * 4;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(p[3]) || p[3] < 0) {
            free(data);
            return hz_bake_err(err, HZ_E_RANGE, "%s: point %llu is not finite or has a negative radius", bin, k);
        }
    }

    uint32_t sides = sc->tube_sides;
    uint32_t ring = sides == 1 ? 2 : sides;
    uint32_t quads = sides == 1 ? 1 : sides;
    float rscale = sc->tube_radius_scale;
    /* Material and object. */
    hz_bake_material_t *m = hz_bake_vec_push(&s->mats, 1);
    snprintf(m->name, sizeof m->name, "Hair");
    hz_bake_set_name(m->m.name, m->name);
    memcpy(m->m.base_color, color, sizeof color);
    for (int k = 0; k < 3; k++)
        m->m.base_color[k] = fminf(fmaxf(m->m.base_color[k], 0.0f), 1.0f);
    memcpy(m->source_color, m->m.base_color, sizeof color);
    m->m.alpha = 1.0f;
    m->m.alpha_cutoff = 0.5f;
    m->m.base_texture = m->m.alpha_texture = -1;
    char name[256];
    snprintf(name, sizeof name, "%s", hz_bake_basename(path));
    char *dot = strrchr(name, '.');
    if (dot)
        *dot = 0;
    hz_bake_object_begin(s, name, "RoundLineSegments");

    uint64_t strands = 0, verts = 0;
    double t0 = hz_bake_now();
    for (unsigned long long k = 0; k < isize;) {
        /* Strand: segments k..e-1 with consecutive indices; points idx[k] .. idx[e-1] + 1. */
        unsigned long long e = k + 1;
        while (e < isize && idx[e] == idx[e - 1] + 1)
            e++;
        uint32_t p0 = idx[k], np = (uint32_t)(e - k) + 1;
        if ((uint64_t)verts + (uint64_t)np * ring > UINT32_MAX) {
            free(data);
            return hz_bake_err(err, HZ_E_OVERFLOW, "%s: the tubes need more than 2^32 vertices", path);
        }
        uint32_t base = hz_bake_add_vertices(s, np * ring);
        double nrm[3] = { 0, 0, 0 };
        for (uint32_t i = 0; i < np; i++) {
            const float *p = pts + (size_t)(p0 + i) * 4;
            const float *a = pts + (size_t)(p0 + (i > 0 ? i - 1 : 0)) * 4;
            const float *b = pts + (size_t)(p0 + (i + 1 < np ? i + 1 : np - 1)) * 4;
            double t[3] = { (double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2] };
            normalize3(t);
            if (i == 0) {
                perpendicular(t, nrm);
            } else {
                /* Parallel transport: remove the new tangent's component from the previous normal. */
                double d = nrm[0] * t[0] + nrm[1] * t[1] + nrm[2] * t[2];
                for (int c = 0; c < 3; c++)
                    nrm[c] -= d * t[c];
                double l = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
                if (l < 1e-6)
                    perpendicular(t, nrm);
                else
                    for (int c = 0; c < 3; c++)
                        nrm[c] /= l;
            }
            double bin3[3] = { t[1] * nrm[2] - t[2] * nrm[1], t[2] * nrm[0] - t[0] * nrm[2],
                               t[0] * nrm[1] - t[1] * nrm[0] };
            double r = (double)p[3] * rscale;
            for (uint32_t j = 0; j < ring; j++) {
                double dir[3], out[3];
                if (sides == 1) {
                    double sgn = j == 0 ? -1.0 : 1.0;
                    for (int c = 0; c < 3; c++)
                        dir[c] = sgn * bin3[c], out[c] = nrm[c];
                } else {
                    double ang = 2.0 * HZ_BAKE_PI * j / ring, cs = cos(ang), sn = sin(ang);
                    for (int c = 0; c < 3; c++)
                        dir[c] = cs * nrm[c] + sn * bin3[c], out[c] = dir[c];
                }
                float *v = HZ_BAKE_AT(s->pos, float, (size_t)(base + i * ring + j) * 4);
                float *vn = HZ_BAKE_AT(s->nrm, float, (size_t)(base + i * ring + j) * 4);
                for (int c = 0; c < 3; c++) {
                    v[c] = (float)(p[c] + r * dir[c]);
                    vn[c] = (float)out[c];
                }
            }
        }
        for (uint32_t i = 0; i + 1 < np; i++)
            for (uint32_t j = 0; j < quads; j++) {
                uint32_t j1 = (j + 1) % ring;
                uint32_t a = base + i * ring + j, b = base + i * ring + j1;
                uint32_t c = base + (i + 1) * ring + j1, d = base + (i + 1) * ring + j;
                /* Outward winding: ring angles grow from n towards t x n, so (a, b, c) faces out. */
                hz_bake_add_triangle(s, a, b, c, 0);
                hz_bake_add_triangle(s, a, c, d, 0);
            }
        verts += (uint64_t)np * ring;
        strands++;
        k = e;
    }
    free(data);
    hz_bake_progress("furball: %llu strands, %llu segments -> %zu triangles in %.2f s", (unsigned long long)strands,
                     isize, s->tri.len, hz_bake_now() - t0);
    return hz_bake_object_end(s, 1, 0, err);
}
