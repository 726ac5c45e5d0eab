/* Writes a long skinned test model as glTF 2.0 (.gltf JSON + .bin): a ring of swaying tentacles on one skeleton,
 * the stand-in for a large public skinned model (about 60k triangles, tens of joints, tens of seconds of
 * animation) in runtime-skinning tests and figures. Host tool; `make scenes` runs it and bakes the result with
 * programs/hzbake/scenes/tentacles.hzs.
 *
 *     skinned_gltf OUT_DIR [TENTACLES JOINTS SECONDS]
 *         writes OUT_DIR/tentacles.gltf and OUT_DIR/tentacles.bin (each via a temp file and rename);
 *         defaults 6 tentacles x 8 joints (48 joints), 35 s
 *
 * Each tentacle is its own mesh (one node each, all skinned by the one skin, as a character's body parts are):
 * a tapered tube of SIDES x RINGS quads along a chain of JOINTS joints standing on the ground plane. Every
 * vertex is weighted to the two joints around its height (linear falloff), so no vertex has more than 2
 * influences. Each joint rotates about a horizontal axis by a sum of two sines (periods 3.1 s and 7.3 s, phase
 * along the chain) sampled at KEY_RATE keys per second (LINEAR rotation samplers), so the motion never repeats
 * inside the animation. The scene is the same on every machine (no randomness). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GEN_PROG "skinned_gltf"
#define GEN_EXIT 74
#include "gltfio.h"

#define SIDES 16
#define RINGS 321 /* 320 segments per tentacle: 16 * 320 * 2 = 10240 triangles */
#define KEY_RATE 10
#define HEIGHT 2.0
#define RADIUS 0.12
#define RING_R 0.9 /* tentacle bases on a circle of this radius */
#define PI 3.14159265358979323846

static void *xmalloc(size_t n)
{
    void *p = malloc(n);
    if (!p) {
        fprintf(stderr, "skinned_gltf: out of memory\n");
        exit(70);
    }
    return p;
}

int main(int argc, char **argv)
{
    if (argc != 2 && argc != 5) {
        fprintf(stderr, "usage: skinned_gltf OUT_DIR [TENTACLES JOINTS SECONDS]\n");
        return 64;
    }
    int nt = 6, nj = 8;
    double seconds = 35.0;
    if (argc == 5) {
        nt = atoi(argv[2]), nj = atoi(argv[3]), seconds = atof(argv[4]);
        if (nt < 1 || nt > 64 || nj < 2 || nj > 64 || !(seconds > 0 && seconds <= 3600)) {
            fprintf(stderr, "skinned_gltf: TENTACLES in 1..64, JOINTS in 2..64, SECONDS in (0, 3600]\n");
            return 64;
        }
    }
    const double seg = HEIGHT / nj; /* joint spacing */
    const int nv = SIDES * RINGS, ntri = SIDES * (RINGS - 1) * 2;
    int mesh_pos[64], mesh_nrm[64], mesh_jnt[64], mesh_wgt[64], mesh_idx[64];
    float *pos = xmalloc(sizeof(float) * 3 * nv), *nrm = xmalloc(sizeof(float) * 3 * nv);
    float *wgt = xmalloc(sizeof(float) * 4 * nv);
    uint16_t *jnt = xmalloc(sizeof(uint16_t) * 4 * nv);
    uint32_t *idx = xmalloc(sizeof(uint32_t) * 3 * ntri);
    for (int t = 0; t < nt; t++) {
        double bx = RING_R * cos(2 * PI * t / nt), bz = RING_R * sin(2 * PI * t / nt);
        float mn[3] = { 1e30f, 1e30f, 1e30f }, mx[3] = { -1e30f, -1e30f, -1e30f };
        for (int r = 0; r < RINGS; r++) {
            double h = HEIGHT * r / (RINGS - 1), rad = RADIUS * (1.0 - 0.85 * h / HEIGHT);
            double s = h / seg;
            int j0 = (int)floor(s);
            double f = s - j0;
            if (j0 >= nj - 1)
                j0 = nj - 1, f = 0.0;
            for (int k = 0; k < SIDES; k++) {
                int v = r * SIDES + k;
                double a = 2 * PI * k / SIDES;
                double p[3] = { bx + rad * cos(a), h, bz + rad * sin(a) };
                for (int c = 0; c < 3; c++) {
                    pos[v * 3 + c] = (float)p[c];
                    mn[c] = fminf(mn[c], (float)p[c]), mx[c] = fmaxf(mx[c], (float)p[c]);
                }
                nrm[v * 3 + 0] = (float)cos(a), nrm[v * 3 + 1] = 0.0f, nrm[v * 3 + 2] = (float)sin(a);
                int g0 = t * nj + j0, g1 = t * nj + (j0 + 1 < nj ? j0 + 1 : j0);
                jnt[v * 4 + 0] = (uint16_t)g0, jnt[v * 4 + 1] = (uint16_t)g1, jnt[v * 4 + 2] = 0,
                jnt[v * 4 + 3] = 0;
                wgt[v * 4 + 0] = (float)(1.0 - f), wgt[v * 4 + 1] = (float)f, wgt[v * 4 + 2] = 0.0f,
                wgt[v * 4 + 3] = 0.0f;
            }
        }
        int n = 0;
        for (int r = 0; r + 1 < RINGS; r++)
            for (int k = 0; k < SIDES; k++) {
                uint32_t a = (uint32_t)(r * SIDES + k), b = (uint32_t)(r * SIDES + (k + 1) % SIDES);
                uint32_t c = a + SIDES, d = b + SIDES;
                idx[n++] = a, idx[n++] = c, idx[n++] = b; /* outward facing, counter-clockwise */
                idx[n++] = b, idx[n++] = c, idx[n++] = d;
            }
        mesh_pos[t] = gltf_accessor(pos, sizeof(float) * 3 * nv, nv, "VEC3", 5126, 1, mn, mx);
        mesh_nrm[t] = gltf_accessor(nrm, sizeof(float) * 3 * nv, nv, "VEC3", 5126, 1, NULL, NULL);
        mesh_jnt[t] = gltf_accessor(jnt, sizeof(uint16_t) * 4 * nv, nv, "VEC4", 5123, 1, NULL, NULL);
        mesh_wgt[t] = gltf_accessor(wgt, sizeof(float) * 4 * nv, nv, "VEC4", 5126, 1, NULL, NULL);
        mesh_idx[t] = gltf_accessor(idx, sizeof(uint32_t) * 3 * ntri, ntri * 3, "SCALAR", 5125, 2, NULL, NULL);
    }
    /* Inverse bind matrices: joint j of tentacle t sits at (bx, j * seg, bz) in the bind pose (no rotation). */
    int njt = nt * nj;
    float *ibm = xmalloc(sizeof(float) * 16 * njt);
    for (int t = 0; t < nt; t++)
        for (int j = 0; j < nj; j++) {
            float *m = ibm + (t * nj + j) * 16;
            memset(m, 0, sizeof(float) * 16);
            m[0] = m[5] = m[10] = m[15] = 1.0f;
            m[12] = (float)(-RING_R * cos(2 * PI * t / nt));
            m[13] = (float)(-j * seg);
            m[14] = (float)(-RING_R * sin(2 * PI * t / nt));
        }
    int acc_ibm = gltf_accessor(ibm, sizeof(float) * 16 * njt, njt, "MAT4", 5126, 0, NULL, NULL);
    /* Animation: shared key times, one rotation track per joint. */
    int nk = (int)ceil(seconds * KEY_RATE) + 1;
    float *times = xmalloc(sizeof(float) * nk), *rot = xmalloc(sizeof(float) * 4 * nk);
    for (int k = 0; k < nk; k++)
        times[k] = (float)(k == nk - 1 ? seconds : (double)k / KEY_RATE);
    int acc_time = gltf_accessor_times(times, nk);
    int *acc_rot = xmalloc(sizeof(int) * njt);
    for (int t = 0; t < nt; t++)
        for (int j = 0; j < nj; j++) {
            double axis_a = 2 * PI * t / nt + PI / 2; /* sway tangentially to the ring */
            double ax = cos(axis_a), az = sin(axis_a);
            for (int k = 0; k < nk; k++) {
                double tt = times[k];
                double ang = 0.22 * sin(2 * PI * tt / 3.1 + 0.6 * j + t) + 0.12 * sin(2 * PI * tt / 7.3 - 0.4 * j);
                if (j == 0)
                    ang *= 0.3; /* the root barely moves */
                double sn = sin(ang / 2);
                rot[k * 4 + 0] = (float)(ax * sn), rot[k * 4 + 1] = 0.0f, rot[k * 4 + 2] = (float)(az * sn),
                rot[k * 4 + 3] = (float)cos(ang / 2);
            }
            acc_rot[t * nj + j] = gltf_accessor(rot, sizeof(float) * 4 * nk, nk, "VEC4", 5126, 0, NULL, NULL);
        }

    char path[8192], tmp[8300];
    FILE *f = gltf_files(argv[1], "tentacles", path, sizeof path, tmp, sizeof tmp);
    /* Nodes: joints first (tentacle t's chain is t*nj .. t*nj+nj-1), then one mesh node per tentacle. */
    for (int t = 0; t < nt; t++)
        fprintf(f, "%d,", t * nj);
    for (int t = 0; t < nt; t++)
        fprintf(f, "%d%s", njt + t, t + 1 < nt ? "," : "");
    fprintf(f, "]}],\n\"nodes\":[\n");
    for (int t = 0; t < nt; t++)
        for (int j = 0; j < nj; j++) {
            double tx = j == 0 ? RING_R * cos(2 * PI * t / nt) : 0.0, tz = j == 0 ? RING_R * sin(2 * PI * t / nt) : 0.0;
            fprintf(f, "{\"name\":\"t%d_j%d\",\"translation\":[%.9g,%.9g,%.9g]", t, j, tx, j == 0 ? 0.0 : seg, tz);
            if (j + 1 < nj)
                fprintf(f, ",\"children\":[%d]", t * nj + j + 1);
            fprintf(f, "},\n");
        }
    for (int t = 0; t < nt; t++)
        fprintf(f, "{\"name\":\"tentacle%d\",\"mesh\":%d,\"skin\":0}%s\n", t, t, t + 1 < nt ? "," : "");
    fprintf(f, "],\n\"skins\":[{\"inverseBindMatrices\":%d,\"joints\":[", acc_ibm);
    for (int j = 0; j < njt; j++)
        fprintf(f, "%d%s", j, j + 1 < njt ? "," : "");
    fprintf(f, "]}],\n\"materials\":[{\"name\":\"skin\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.45,0.3,1],"
               "\"metallicFactor\":0,\"roughnessFactor\":0.8}}],\n\"meshes\":[\n");
    for (int t = 0; t < nt; t++)
        fprintf(f, "{\"name\":\"tentacle%d\",\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,"
                   "\"JOINTS_0\":%d,\"WEIGHTS_0\":%d},\"indices\":%d,\"material\":0}]}%s\n",
                t, mesh_pos[t], mesh_nrm[t], mesh_jnt[t], mesh_wgt[t], mesh_idx[t], t + 1 < nt ? "," : "");
    fprintf(f, "],\n\"animations\":[{\"name\":\"sway\",\"samplers\":[");
    for (int j = 0; j < njt; j++)
        fprintf(f, "{\"input\":%d,\"output\":%d,\"interpolation\":\"LINEAR\"}%s", acc_time, acc_rot[j],
                j + 1 < njt ? "," : "");
    fprintf(f, "],\n\"channels\":[");
    for (int j = 0; j < njt; j++)
        fprintf(f, "{\"sampler\":%d,\"target\":{\"node\":%d,\"path\":\"rotation\"}}%s", j, j, j + 1 < njt ? "," : "");
    fprintf(f, "]}],\n\"accessors\":[%s],\n\"bufferViews\":[%s],\n", gltf_acc_json, gltf_view_json);
    fprintf(f, "\"buffers\":[{\"uri\":\"tentacles.bin\",\"byteLength\":%zu}]}\n", gltf_bin_len);
    gen_finish(f, tmp, path);
    printf("skinned_gltf: %s: %d meshes, %d triangles, %d joints, %d keys per joint over %.3g s\n", path, nt,
           nt * ntri, njt, nk, seconds);
    free(pos), free(nrm), free(wgt), free(jnt), free(idx), free(ibm), free(times), free(rot), free(acc_rot);
    gltf_free();
    return 0;
}
