/* Writes the crossing-transparency scene as glTF 2.0 (.gltf JSON + .bin): blended panes and clouds of blended
 * confetti that move through each other in front of a striped wall, the moving counterpart of seed 004's still
 * tests (its fight scene, Figs. 8 and 11: transparent objects whose depth order changes while they move). Host
 * tool; `make scenes` runs it and bakes the result with programs/hzbake/scenes/crossing.hzs.
 *
 *     crossing_gltf OUT_DIR     writes OUT_DIR/crossing.gltf and OUT_DIR/crossing.bin (via temp files + rename)
 *
 * Opaque: a floor and a wall of alternating light and dark stripes (the contrast behind the blended layers makes
 * their errors visible). Blended (alphaMode BLEND, alpha from baseColorFactor): PANES panes 1.4 x 1.1 units, each
 * its own node, sliding sideways and turning about the vertical by up to 40 degrees with their own periods, 0.2
 * units apart in depth, so that they cut through each other and the order of the layers along a ray changes
 * across a pane and over time; CLOUDS clouds of CONFETTI small quads each (every quad its own connected group,
 * so it takes its own dither map), each cloud a node circling through the panes. LINEAR keys at KEY_RATE per
 * second over SECONDS. No randomness: the scene is the same on every machine. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GEN_PROG "crossing_gltf"
#define GEN_EXIT 74
#include "gltfio.h"

#define PANES 6
#define CLOUDS 3
#define CONFETTI 160
#define STRIPES 10
#define KEY_RATE 20
#define SECONDS 12.0
#define PI 3.14159265358979323846

/* Meshes as the glTF lists them: position, normal and index accessors and a material. */
typedef struct mesh {
    int pos, nrm, idx, mat;
} mesh_t;

static float vbuf[4 * CONFETTI * 3], nbuf[4 * CONFETTI * 3];
static uint32_t ibuf[6 * CONFETTI];
static int nv, ni;

/* Appends the quad c + s*u + t*v, s, t in [-1, 1], facing n = u x v. */
static void quad(const double c[3], const double u[3], const double v[3])
{
    double n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] };
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    static const int st[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    for (int k = 0; k < 4; k++) {
        for (int a = 0; a < 3; a++) {
            vbuf[(nv + k) * 3 + a] = (float)(c[a] + st[k][0] * u[a] + st[k][1] * v[a]);
            nbuf[(nv + k) * 3 + a] = (float)(n[a] / l);
        }
    }
    static const int tri[6] = { 0, 1, 2, 0, 2, 3 };
    for (int k = 0; k < 6; k++)
        ibuf[ni++] = (uint32_t)(nv + tri[k]);
    nv += 4;
}

/* The quads appended since the last call as one mesh of material `mat`. */
static mesh_t flush(int mat)
{
    float mn[3] = { 1e30f, 1e30f, 1e30f }, mx[3] = { -1e30f, -1e30f, -1e30f };
    for (int i = 0; i < nv; i++)
        for (int a = 0; a < 3; a++)
            mn[a] = fminf(mn[a], vbuf[i * 3 + a]), mx[a] = fmaxf(mx[a], vbuf[i * 3 + a]);
    mesh_t m = { gltf_accessor(vbuf, sizeof(float) * 3 * (size_t)nv, nv, "VEC3", 5126, 1, mn, mx),
                 gltf_accessor(nbuf, sizeof(float) * 3 * (size_t)nv, nv, "VEC3", 5126, 1, NULL, NULL),
                 gltf_accessor(ibuf, sizeof(uint32_t) * (size_t)ni, ni, "SCALAR", 5125, 2, NULL, NULL), mat };
    nv = ni = 0;
    return m;
}

/* A fixed sequence in [0, 1) (Weyl: fractional parts of multiples of an irrational), for the confetti. */
static double weyl(int i, double a)
{
    double x = i * a;
    return x - floor(x);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: crossing_gltf OUT_DIR\n");
        return 64;
    }
    enum { M_FLOOR, M_LIGHT, M_DARK, M_PANE0, M_CLOUD0 = M_PANE0 + PANES, M_COUNT = M_CLOUD0 + CLOUDS };
    mesh_t mesh[3 + PANES + CLOUDS];
    int nm = 0;
    /* opaque: floor, then the wall's light and dark stripes */
    quad((const double[3]){ 0, 0, 0 }, (const double[3]){ 5, 0, 0 }, (const double[3]){ 0, 0, -4 });
    mesh[nm++] = flush(M_FLOOR);
    for (int shade = 0; shade < 2; shade++) {
        for (int s = shade; s < STRIPES; s += 2)
            quad((const double[3]){ -5 + 0.5 + s, 1.6, -2.5 }, (const double[3]){ 0.5, 0, 0 },
                 (const double[3]){ 0, 1.6, 0 });
        mesh[nm++] = flush(shade ? M_DARK : M_LIGHT);
    }
    /* panes, centred on their nodes */
    for (int p = 0; p < PANES; p++) {
        quad((const double[3]){ 0, 0, 0 }, (const double[3]){ 0.7, 0, 0 }, (const double[3]){ 0, 0.55, 0 });
        mesh[nm++] = flush(M_PANE0 + p);
    }
    /* confetti: quads of side 0.12 in a ball of radius 0.6 about their node, random orientations */
    for (int c = 0; c < CLOUDS; c++) {
        for (int q = 0; q < CONFETTI; q++) {
            int i = c * CONFETTI + q + 1;
            double r = 0.6 * cbrt(weyl(i, 0.7548776662466927)), th = acos(1 - 2 * weyl(i, 0.5698402909980532));
            double ph = 2 * PI * weyl(i, 0.6180339887498949);
            double ctr[3] = { r * sin(th) * cos(ph), r * cos(th), r * sin(th) * sin(ph) };
            double a = 2 * PI * weyl(i, 0.4142135623730950), b = acos(1 - 2 * weyl(i, 0.7320508075688772));
            double n[3] = { sin(b) * cos(a), cos(b), sin(b) * sin(a) };
            double t[3] = { fabs(n[1]) < 0.9 ? 0 : 1, fabs(n[1]) < 0.9 ? 1 : 0, 0 };
            double u[3] = { n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0] };
            double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            for (int k = 0; k < 3; k++)
                u[k] *= 0.06 / ul;
            double v[3] = { (n[1] * u[2] - n[2] * u[1]), (n[2] * u[0] - n[0] * u[2]), (n[0] * u[1] - n[1] * u[0]) };
            quad(ctr, u, v);
        }
        mesh[nm++] = flush(M_CLOUD0 + c);
    }
    /* animation: shared key times; per pane a translation and a rotation track, per cloud a translation */
    const int nk = (int)(SECONDS * KEY_RATE) + 1;
    float times[(int)(SECONDS * KEY_RATE) + 1], tr[3 * ((int)(SECONDS * KEY_RATE) + 1)],
        rot[4 * ((int)(SECONDS * KEY_RATE) + 1)];
    for (int k = 0; k < nk; k++)
        times[k] = (float)((double)k / KEY_RATE);
    const int acc_time = gltf_accessor_times(times, nk);
    int acc_tr[PANES + CLOUDS], acc_rot[PANES];
    for (int p = 0; p < PANES; p++) {
        const double period = 3.0 + 0.7 * p, turn = 4.1 + 0.9 * p, dir = p % 2 ? -1.0 : 1.0;
        for (int k = 0; k < nk; k++) {
            const double t = times[k];
            tr[3 * k + 0] = (float)(dir * 1.3 * sin(2 * PI * t / period + p));
            tr[3 * k + 1] = (float)(0.9 + 0.12 * p + 0.1 * sin(2 * PI * t / (period * 1.7)));
            tr[3 * k + 2] = (float)(-0.6 + 0.2 * p);
            const double ang = (40.0 * PI / 180.0) * sin(2 * PI * t / turn + 0.5 * p);
            rot[4 * k + 0] = 0.0f, rot[4 * k + 1] = (float)sin(ang / 2), rot[4 * k + 2] = 0.0f;
            rot[4 * k + 3] = (float)cos(ang / 2);
        }
        acc_tr[p] = gltf_accessor(tr, sizeof(float) * 3 * (size_t)nk, nk, "VEC3", 5126, 0, NULL, NULL);
        acc_rot[p] = gltf_accessor(rot, sizeof(float) * 4 * (size_t)nk, nk, "VEC4", 5126, 0, NULL, NULL);
    }
    for (int c = 0; c < CLOUDS; c++) {
        const double period = 5.0 + 1.3 * c, ph = 2 * PI * c / CLOUDS, dir = c % 2 ? -1.0 : 1.0;
        for (int k = 0; k < nk; k++) {
            const double a = dir * 2 * PI * times[k] / period + ph;
            tr[3 * k + 0] = (float)(1.6 * cos(a)), tr[3 * k + 1] = (float)(1.2 + 0.3 * c);
            tr[3 * k + 2] = (float)(0.9 * sin(a));
        }
        acc_tr[PANES + c] = gltf_accessor(tr, sizeof(float) * 3 * (size_t)nk, nk, "VEC3", 5126, 0, NULL, NULL);
    }

    char path[8192], tmp[8300];
    FILE *f = gltf_files(argv[1], "crossing", path, sizeof path, tmp, sizeof tmp);
    for (int i = 0; i < nm; i++)
        fprintf(f, "%d%s", i, i + 1 < nm ? "," : "");
    fprintf(f, "]}],\n\"nodes\":[\n");
    static const char *const role[3] = { "floor", "wall-light", "wall-dark" };
    for (int i = 0; i < nm; i++) {
        if (i < 3)
            fprintf(f, "{\"name\":\"%s\",\"mesh\":%d}", role[i], i);
        else if (i < 3 + PANES)
            fprintf(f, "{\"name\":\"pane%d\",\"mesh\":%d}", i - 3, i);
        else
            fprintf(f, "{\"name\":\"cloud%d\",\"mesh\":%d}", i - 3 - PANES, i);
        fprintf(f, "%s\n", i + 1 < nm ? "," : "");
    }
    /* materials: floor, light and dark stripes opaque; panes and clouds blended */
    static const float pane_rgba[PANES][4] = { { 0.9f, 0.2f, 0.15f, 0.45f }, { 0.2f, 0.75f, 0.25f, 0.4f },
                                               { 0.2f, 0.35f, 0.95f, 0.5f }, { 0.95f, 0.85f, 0.2f, 0.35f },
                                               { 0.2f, 0.85f, 0.9f, 0.4f },  { 0.85f, 0.3f, 0.85f, 0.55f } };
    static const float cloud_rgba[CLOUDS][4] = { { 1.0f, 0.6f, 0.2f, 0.6f }, { 0.9f, 0.9f, 0.95f, 0.5f },
                                                 { 0.3f, 0.9f, 0.5f, 0.6f } };
    fprintf(f, "],\n\"materials\":[\n");
    fprintf(f, "{\"name\":\"floor\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.55,0.55,0.5,1],"
               "\"metallicFactor\":0,\"roughnessFactor\":0.9}},\n");
    fprintf(f, "{\"name\":\"light\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.9,0.88,0.82,1],"
               "\"metallicFactor\":0,\"roughnessFactor\":0.9}},\n");
    fprintf(f, "{\"name\":\"dark\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.08,0.1,0.18,1],"
               "\"metallicFactor\":0,\"roughnessFactor\":0.9}},\n");
    for (int p = 0; p < PANES + CLOUDS; p++) {
        const float *c = p < PANES ? pane_rgba[p] : cloud_rgba[p - PANES];
        fprintf(f, "{\"name\":\"%s%d\",\"alphaMode\":\"BLEND\",\"doubleSided\":true,\"pbrMetallicRoughness\":{"
                   "\"baseColorFactor\":[%.3g,%.3g,%.3g,%.3g],\"metallicFactor\":0,\"roughnessFactor\":0.6}}%s\n",
                p < PANES ? "pane" : "cloud", p < PANES ? p : p - PANES, c[0], c[1], c[2], c[3],
                p + 1 < PANES + CLOUDS ? "," : "");
    }
    fprintf(f, "],\n\"meshes\":[\n");
    for (int i = 0; i < nm; i++)
        fprintf(f, "{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d},\"indices\":%d,"
                   "\"material\":%d}]}%s\n",
                mesh[i].pos, mesh[i].nrm, mesh[i].idx, mesh[i].mat, i + 1 < nm ? "," : "");
    fprintf(f, "],\n\"animations\":[{\"name\":\"crossing\",\"samplers\":[");
    int ns = 0;
    for (int p = 0; p < PANES + CLOUDS; p++) {
        fprintf(f, "%s{\"input\":%d,\"output\":%d,\"interpolation\":\"LINEAR\"}", ns++ ? "," : "", acc_time,
                acc_tr[p]);
        if (p < PANES)
            fprintf(f, ",{\"input\":%d,\"output\":%d,\"interpolation\":\"LINEAR\"}", acc_time, acc_rot[p]), ns++;
    }
    fprintf(f, "],\n\"channels\":[");
    ns = 0;
    for (int p = 0; p < PANES + CLOUDS; p++) {
        fprintf(f, "%s{\"sampler\":%d,\"target\":{\"node\":%d,\"path\":\"translation\"}}", ns ? "," : "", ns,
                3 + p);
        ns++;
        if (p < PANES) {
            fprintf(f, ",{\"sampler\":%d,\"target\":{\"node\":%d,\"path\":\"rotation\"}}", ns, 3 + p);
            ns++;
        }
    }
    fprintf(f, "]}],\n\"accessors\":[%s],\n\"bufferViews\":[%s],\n", gltf_acc_json, gltf_view_json);
    fprintf(f, "\"buffers\":[{\"uri\":\"crossing.bin\",\"byteLength\":%zu}]}\n", gltf_bin_len);
    gen_finish(f, tmp, path);
    printf("crossing_gltf: %s: %d panes, %d clouds of %d quads, %d keys over %.3g s\n", path, PANES, CLOUDS,
           CONFETTI, nk, SECONDS);
    gltf_free();
    return 0;
}
