/* Writes a moving hairball as glTF 2.0 (.gltf JSON + .bin): seed 002's test scene for the motion-blur BVHs (its
 * Fig. 1 and Table 1: a ball of thin strands, 348K triangles, whose strands move past each other within a
 * shutter interval). Host tool; `make scenes` runs it and bakes the result with
 * programs/hzbake/scenes/hairball.hzs.
 *
 *     hairball_gltf OUT_DIR     writes OUT_DIR/hairball.gltf and OUT_DIR/hairball.bin (via temp files + rename)
 *
 * STRANDS strands grow from a sphere of radius ROOT_R as curly random walks of SEGMENTS segments (each step
 * mostly outward, partly along a direction that turns every step), each a three-sided tube of radius TUBE_R:
 * 6 triangles per segment, STRANDS * SEGMENTS * 6 = 348,000 triangles, long and thin (0.145 by 0.007 units) as
 * the paper's replication of 2.5x suggests its were. Strand i belongs to group i % GROUPS, and each group is its
 * own mesh on its own node that turns about the ball's centre, back and forth by up to SWING radians about an
 * axis of its own with a period and phase of its own: neighbouring strands belong to different groups, so they
 * cross each other. At radius 1 a strand tip moves up to SWING * 2 pi / PERIOD units per second, about 0.08
 * units in a 1/24 s shutter: about three times the strand spacing at the surface (0.03) and ten times a
 * strand's width. Rotations are LINEAR keys at KEY_RATE per second over SECONDS. No
 * randomness: the scene is the same on every machine. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GEN_PROG "hairball_gltf"
#define GEN_EXIT 74
#include "gltfio.h"

#define STRANDS 14500
#define SEGMENTS 4
#define GROUPS 64
#define ROOT_R 0.45
#define STEP 0.145
#define TUBE_R 0.004
#define SWING 0.3
#define PERIOD 1.0
#define KEY_RATE 48
#define SECONDS 4
#define N_KEYS (SECONDS * KEY_RATE + 1)
#define PI 3.14159265358979323846

#define PER_GROUP ((STRANDS + GROUPS - 1) / GROUPS)
static float vbuf[PER_GROUP * (SEGMENTS + 1) * 3 * 3], nbuf[PER_GROUP * (SEGMENTS + 1) * 3 * 3];
static uint32_t ibuf[PER_GROUP * SEGMENTS * 6 * 3];
static float key_times[N_KEYS], rot[4 * N_KEYS];
static int nv, ni;

/* A fixed sequence in [0, 1) (Weyl: fractional parts of multiples of an irrational). */
static double weyl(long i, double a)
{
    double x = (double)i * a;
    return x - floor(x);
}

static void normalize(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] /= l;
}

static void cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}

/* A unit vector from two numbers in [0, 1). */
static void sphere_dir(double u, double v, double *d)
{
    double z = 1 - 2 * u, r = sqrt(1 - z * z), ph = 2 * PI * v;
    d[0] = r * cos(ph), d[1] = z, d[2] = r * sin(ph);
}

/* Appends strand s: its path and the three-sided tube around it. */
static void strand(long s)
{
    double p[3], dir[3], turn[3];
    sphere_dir(weyl(s + 1, 0.7548776662466927), weyl(s + 1, 0.5698402909980532), dir);
    for (int k = 0; k < 3; k++)
        p[k] = ROOT_R * dir[k];
    sphere_dir(weyl(s + 1, 0.4142135623730950), weyl(s + 1, 0.7320508075688772), turn);
    const int first = nv;
    for (int r = 0; r <= SEGMENTS; r++) {
        double out[3] = { p[0], p[1], p[2] }, t[3], a[3], b[3];
        normalize(out);
        for (int k = 0; k < 3; k++) /* the walk: mostly outward, partly along a slowly turning direction */
            t[k] = out[k] + 0.9 * turn[k];
        normalize(t);
        const double *ref = fabs(t[1]) < 0.9 ? (const double[3]){ 0, 1, 0 } : (const double[3]){ 1, 0, 0 };
        cross(t, ref, a);
        normalize(a);
        cross(t, a, b);
        for (int c = 0; c < 3; c++) {
            const double ang = 2 * PI * c / 3.0;
            for (int k = 0; k < 3; k++) {
                const double n = cos(ang) * a[k] + sin(ang) * b[k];
                vbuf[nv * 3 + k] = (float)(p[k] + TUBE_R * n);
                nbuf[nv * 3 + k] = (float)n;
            }
            nv++;
        }
        for (int k = 0; k < 3; k++)
            p[k] += STEP * t[k];
        /* the turning direction drifts: a curl of its own per strand */
        double w[3];
        sphere_dir(weyl(s * 16 + r + 7, 0.6180339887498949), weyl(s * 16 + r + 7, 0.3819660112501051), w);
        for (int k = 0; k < 3; k++)
            turn[k] += 0.5 * w[k];
        normalize(turn);
    }
    for (int r = 0; r < SEGMENTS; r++)
        for (int c = 0; c < 3; c++) {
            const uint32_t a0 = (uint32_t)(first + r * 3 + c), a1 = (uint32_t)(first + r * 3 + (c + 1) % 3);
            const uint32_t b0 = a0 + 3, b1 = a1 + 3;
            const uint32_t q[6] = { a0, a1, b1, a0, b1, b0 };
            memcpy(&ibuf[ni], q, sizeof q);
            ni += 6;
        }
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: hairball_gltf OUT_DIR\n");
        return 64;
    }
    int acc_pos[GROUPS], acc_nrm[GROUPS], acc_idx[GROUPS], acc_rot[GROUPS];
    long tris = 0;
    for (int gi = 0; gi < GROUPS; gi++) {
        nv = ni = 0;
        for (long s = gi; s < STRANDS; s += GROUPS)
            strand(s);
        float mn[3] = { 1e30f, 1e30f, 1e30f }, mx[3] = { -1e30f, -1e30f, -1e30f };
        for (int i = 0; i < nv; i++)
            for (int k = 0; k < 3; k++)
                mn[k] = fminf(mn[k], vbuf[i * 3 + k]), mx[k] = fmaxf(mx[k], vbuf[i * 3 + k]);
        acc_pos[gi] = gltf_accessor(vbuf, sizeof(float) * 3 * (size_t)nv, nv, "VEC3", 5126, 1, mn, mx);
        acc_nrm[gi] = gltf_accessor(nbuf, sizeof(float) * 3 * (size_t)nv, nv, "VEC3", 5126, 1, NULL, NULL);
        acc_idx[gi] = gltf_accessor(ibuf, sizeof(uint32_t) * (size_t)ni, ni, "SCALAR", 5125, 2, NULL, NULL);
        tris += ni / 3;
    }
    const int nk = N_KEYS;
    for (int k = 0; k < nk; k++)
        key_times[k] = (float)((double)k / KEY_RATE);
    const int acc_time = gltf_accessor_times(key_times, nk);
    for (int gi = 0; gi < GROUPS; gi++) {
        double axis[3];
        sphere_dir(weyl(gi + 1, 0.2360679774997897), weyl(gi + 1, 0.6457513110645906), axis);
        const double period = PERIOD * (0.8 + 0.4 * weyl(gi + 1, 0.1622776601683794));
        const double phase = 2 * PI * weyl(gi + 1, 0.3166247903554);
        for (int k = 0; k < nk; k++) {
            const double ang = SWING * sin(2 * PI * key_times[k] / period + phase);
            for (int c = 0; c < 3; c++)
                rot[4 * k + c] = (float)(axis[c] * sin(ang / 2));
            rot[4 * k + 3] = (float)cos(ang / 2);
        }
        acc_rot[gi] = gltf_accessor(rot, sizeof(float) * 4 * (size_t)nk, nk, "VEC4", 5126, 0, NULL, NULL);
    }

    char path[8192], tmp[8300];
    FILE *f = gltf_files(argv[1], "hairball", path, sizeof path, tmp, sizeof tmp);
    for (int i = 0; i < GROUPS; i++)
        fprintf(f, "%d%s", i, i + 1 < GROUPS ? "," : "");
    fprintf(f, "]}],\n\"nodes\":[\n");
    for (int i = 0; i < GROUPS; i++)
        fprintf(f, "{\"name\":\"hair%d\",\"mesh\":%d}%s\n", i, i, i + 1 < GROUPS ? "," : "");
    fprintf(f, "],\n\"materials\":[{\"name\":\"hair\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.55,0.4,0.25,1],"
               "\"metallicFactor\":0,\"roughnessFactor\":0.7}}],\n\"meshes\":[\n");
    for (int i = 0; i < GROUPS; i++)
        fprintf(f, "{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d},\"indices\":%d,"
                   "\"material\":0}]}%s\n",
                acc_pos[i], acc_nrm[i], acc_idx[i], i + 1 < GROUPS ? "," : "");
    fprintf(f, "],\n\"animations\":[{\"name\":\"swing\",\"samplers\":[");
    for (int i = 0; i < GROUPS; i++)
        fprintf(f, "%s{\"input\":%d,\"output\":%d,\"interpolation\":\"LINEAR\"}", i ? "," : "", acc_time, acc_rot[i]);
    fprintf(f, "],\n\"channels\":[");
    for (int i = 0; i < GROUPS; i++)
        fprintf(f, "%s{\"sampler\":%d,\"target\":{\"node\":%d,\"path\":\"rotation\"}}", i ? "," : "", i, i);
    fprintf(f, "]}],\n\"accessors\":[%s],\n\"bufferViews\":[%s],\n", gltf_acc_json, gltf_view_json);
    fprintf(f, "\"buffers\":[{\"uri\":\"hairball.bin\",\"byteLength\":%zu}]}\n", gltf_bin_len);
    gen_finish(f, tmp, path);
    printf("hairball_gltf: %s: %d strands of %d segments in %d groups, %ld triangles, %d keys over %d s\n", path,
           STRANDS, SEGMENTS, GROUPS, tris, nk, SECONDS);
    gltf_free();
    return 0;
}
