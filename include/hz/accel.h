/*
 * hz/accel.h — ray/triangle acceleration: one interface over the native BVH (src/accel/) and Embree
 * (port/embree/, host builds only).
 *
 * Contract
 *  Geometry. An accel is built from an hz_accel_geom_t view: float4 positions (x, y, z, unused; 16-byte
 *  aligned), u32 triangle indices, optional per-triangle flags. The view's arrays must stay alive and in place
 *  for the life of the accel: refit re-reads `pos` (animation writes new positions into the same array).
 *  Building validates the view (alignment, counts, every index < vertex_count; error names the triangle).
 *  Triangles with non-finite vertices, or with a coordinate beyond +-HZ_ACCEL_MAX_COORD, are kept out of the
 *  structure (never hit) and counted in info.tri_skipped (refit treats a triangle moved there the same way):
 *  beyond that range the watertight test's products (cubes of coordinate differences) would overflow to
 *  infinite or NaN distances. Rays should start within the same range.
 *  Degenerate triangles (zero area) never report a hit.
 *
 *  Memory. The native build takes every byte from the arena passed in (the board's accel arena): the build's
 *  scratch is released before it returns, the structure stays. hz_accel_bytes_bound(n, cfg) gives upper bounds
 *  for the peak (what the arena must have free to build n triangles) and for what stays, so a memory plan can
 *  refuse a scene up front (hz_accel_plan_check prints both byte counts). A build the arena cannot hold fails
 *  with HZ_E_NO_MEMORY naming needed and available bytes, and leaves the arena as it found it. Embree
 *  allocates on its own; its memory monitor charges every byte against the same arena's free space (and
 *  refuses past it), and info.bytes reports Embree's figure.
 *
 *  Rays. hz_ray_t/hz_hit_t and the 4- and 8-wide SoA packets have exactly the layout of Embree 3's
 *  RTCRay/RTCHit, RTCRay4/RTCHit4, RTCRay8/RTCHit8 (fields renamed to house style: ng_x = Ng_x,
 *  prim_id = primID, geom_id = geomID, inst_id = instID), so the Embree backend passes them through without
 *  copying (port/embree checks the offsets at compile time). Packets: 16-byte (4) / 32-byte (8) aligned;
 *  `valid[i]` is -1 for an active lane and 0 for one left untouched. Rays must have finite origin and finite,
 *  non-zero direction (need not be normalised) and 0 <= tnear <= tfar; zero direction components are fine
 *  (a direction so short that a hit's t would not be a finite float, e.g. 1e-45, misses).
 *  Rays that break this never crash or loop: they miss.
 *  - intersect: finds the closest hit with t in [tnear, tfar] (both ends included). On a hit it writes
 *    ray.tfar = t, hit.u/v (barycentrics of vertices 1 and 2: P = (1-u-v) v0 + u v1 + v v2), hit.ng_* (the
 *    unnormalised geometric normal (v1 - v0) x (v2 - v0)), prim_id (the triangle index), geom_id = 0,
 *    inst_id[0] = HZ_ACCEL_INVALID_ID. On a miss the ray and hit are left untouched, so set
 *    hit.geom_id = HZ_ACCEL_INVALID_ID before the call (as with Embree).
 *    Native results do not depend on traversal order or kernel: hits at equal t go to the lower prim_id, and
 *    the scalar, AVX2 and NEON kernels return bit-identical t, u, v, ng and prim_id.
 *  - occluded: true when any hit with t in [tnear, tfar] exists; then ray.tfar = -inf, else untouched.
 *  - Hits are watertight (Woop, Benthin, Wald 2013): a ray through a shared edge or vertex of a closed,
 *    consistently indexed mesh hits at least one of the triangles there. Both faces hit (no culling).
 *  - time, mask, flags and id are carried for the renderer; id reaches the any-hit callback, time selects the
 *    geometry's pose when it has time keys (see Motion; static geometry ignores it), mask is ignored (as in
 *    Debian's Embree).
 *
 *  Any-hit. Triangles with HZ_ACCEL_TRI_ANYHIT in geom.tri_flags do not hit by themselves: every candidate
 *  hit on one (t in range, closer than the best so far for intersect) is offered to ctx->anyhit, which returns
 *  true to accept it. It may be called more than once for the same triangle and ray, and for candidates that
 *  a closer hit later replaces, in any order: decide from the arguments only. Without a callback such
 *  triangles are opaque.
 *
 *  Tiles (large packets). hz_accel_intersect8n / occluded8n (and the 4-lane forms) take n consecutive packets
 *  in one call: a screen tile's camera rays (the 8 packets of 4x2 pixels of an 8x8-pixel tile, say), or one
 *  tile's shadow rays towards one light. With HZ_ACCEL_COHERENT the native backend traces up to 256 of these rays
 *  as one packet (one interval test per node for all of them, active-ray ranges, rays grouped by direction
 *  octant; shadow rays sharing their light end bounded from that end), which is its fastest form for coherent
 *  rays; the results are those of the one-packet calls, bit for bit. Embree runs them packet by packet. Packets
 *  are aligned as single ones; any n (larger calls go in slices of 256 rays).
 *
 *  Context. hz_accel_ctx_t is per query (or per thread, reused): flags (HZ_ACCEL_COHERENT when the rays of a
 *  packet are coherent, e.g. primary rays of a pixel tile), the any-hit callback, a kernel override for tests
 *  and benchmarks, and a statistics sink. Statistics (rays, nodes visited, triangles tested) are counted only
 *  when the board sets HZ_FEATURE_STATS to 1; otherwise the code is compiled out and the sink stays zero.
 *  Embree does not report them.
 *
 *  Threads. Queries only read the accel: any number of threads may query at once, each with its own ctx.
 *  Build, refit and release need exclusive access.
 *
 *  Parallel build. The core starts no threads: a port with a pool passes cfg.run (a task hook in the style of
 *  Embree's task system: "run these N independent items") and the native build uses it for the binning of large
 *  nodes (chunks of references, merged in chunk order: box minima/maxima and integer counts combine exactly)
 *  and for the subtrees below the top levels (at most max(4096, n / 64) references each, a rule on the triangle
 *  count only), each with pre-assigned ranges of references, nodes and leaf slots and up to 4x its proportional
 *  share of the replication budget; if the subtrees together went over the budget, the build is redone by the
 *  serial builder (still binning on the pool). Builds without a hook take the same steps in turn, so the
 *  structure is byte for byte the same for every thread count and any order in which run executes items. The
 *  hooks (run, progress) are used during hz_accel_build_native only: refit's rebuilds run serially, silently.
 *
 *  Motion (seed 002, Grünschloß et al. 2011; interface in the motion-blur note shared with the renderer).
 *  Geometry with time_keys K >= 2 has key k at normalised time k / (K - 1); between keys vertices move
 *  linearly: the triangle a ray meets is, per vertex, hz_accel_lerp_key(key s, key s + 1, f) with (s, f) =
 *  hz_accel_time_segment(ray.time, K). ray.time outside [0, 1] is clamped, NaN means 0; static geometry (K <= 1)
 *  ignores ray.time and runs exactly today's code. The hit's t, u, v, ng are those of the triangle at the ray's
 *  time, bit-identical across kernels and ISAs as for static geometry. cfg.blur picks the motion BVH (MSBVH,
 *  interpolated or swept); the native backend's nodes then carry a box per key and every lane interpolates
 *  them at its own time (one packet may mix times: packets of moving geometry go lane by lane through the
 *  single-ray SIMD kernel). The topology is built on the positions at time 0.5. A triangle with a non-finite
 *  coordinate at any key never hits.
 *  Conservative in floating point, why: box and vertex interpolation use the same two products and one sum
 *  (no FMA), and round-to-nearest is monotone, so if box_s <= p_s and box_s+1 <= p_s+1 per coordinate then
 *  lerp(box) <= lerp(p) exactly in floats; interpolated and swept boxes are bounds of whole triangles at the
 *  keys, so they contain every lerped vertex (and so the triangle) exactly, with no margin. The MSBVH's leaf
 *  boxes bound polygons computed in floats (clipping at the midpoint, barycentric transfer to the keys), so each
 *  side of a leaf's key-k box is widened by delta_k = 2^-14 * e_k + 2^-18 * m_k (e_k: largest extent, m_k:
 *  largest absolute coordinate of the triangle at key k) and then cut to the triangle's own key-k box widened
 *  by delta_k; the midpoint clip (and a refit's clips at the previous first and last keys, against the leaf's
 *  boxes there) runs against the leaf box widened likewise. The rounding it covers: the clip's
 *  barycentric vertices are off the exact polygon by a few ulps of 1 (at most ~2^-21 of the triangle at key
 *  k after transfer, 2^-14 is a 128x allowance), the transfer b0 v0 + b1 v1 + b2 v2 and the lerp of a box against
 *  the lerp of a point each add at most ~8 ulps of the coordinates' magnitude (2^-20; 2^-18 is 4x that), and
 *  the clip planes widened by delta_mid make pieces of adjacent leaves overlap rather than leave slivers. A
 *  triangle seen through several leaves is covered by the union of their pieces (after a refit too: each new
 *  piece contains the previous one). hzrt accel --motion-check
 *  proves it against brute force (0 misses, 0 mismatches) on scenes and extreme procedural motions.
 *
 *  Motion segments per node (seed 002 section 6.3; cfg.segments = HZ_ACCEL_SEGMENTS_PER_NODE, the default). With
 *  K = 2^M + 1 keys, a node keeps its children's boxes at 2^m + 1 of them (every 2^(M - m)-th key, m <= M),
 *  the fewest whose piecewise-linear boxes, resampled at every key, add at most 1/32 to the children's summed
 *  key-box areas; a node over content that moves linearly keeps one segment, over a turn or a sway more. Levels
 *  are chosen at each build (a refit keeps them). A ray at time t reads a level-m node with segment
 *  seg >> (M - m) and weight t * 2^m - that segment (both exact in floats). Why it stays conservative: each
 *  level-m bound is fitted, in exact arithmetic, below (above) its content at every key (the children's boxes
 *  or the leaf's key boxes, which are linear in between, so below them at every t) and then moved out by
 *  2^-17 of the largest coordinate of the node's content; evaluating a lerp in floats errs by at most ~4 ulps
 *  of its operands, so a node's float box contains its children's exact boxes and, down the tree, the leaf's
 *  key boxes as the contract above evaluates them (2^-17 is 32x the 2^-22 the two evaluations need). Every
 *  kernel evaluates the same products and sum, so hits stay bit-identical across kernels and to the trees that
 *  keep every key (boxes decide only what is visited, not what is hit). EVERY_KEY keeps today's node boxes
 *  exactly, and K = 2 has one level only.
 *
 *  Rigid instances (seed 002 section 3.2). A motion view may name up to HZ_ACCEL_MAX_INSTANCES ranges of its
 *  triangles that move rigidly (hz_accel_instance_t: object-space positions and an affine matrix per key). With
 *  cfg.rigid = HZ_ACCEL_RIGID_INSTANCE (default) the native backend builds a static BVH per instance over its
 *  object-space positions, once, and one BVH (motion, or static when static_rest) over the other triangles.
 *  The triangle a ray meets in an instance is the object-space triangle under M(t): each matrix element
 *  interpolated with hz_accel_time_segment and hz_accel_lerp_key, the ray moved into object space by M(t)'s
 *  inverse (same t); hit.ng is the world triangle's (v1 - v0) x (v2 - v0) (the object normal times the cofactor
 *  matrix), u and v as in object space, prim_id the view's index. For the same keys this is the triangle of the
 *  interpolated posed vertices up to rounding, so results with instances are bit-identical across kernels and
 *  ISAs and to hz_accel_brute_intersect1 (which moves rays into instances the same way), not to a build without
 *  them. Where M(t) is singular or not finite the ray passes the instance. Any-hit callbacks get the view's
 *  triangle index and the world-space side. Refit re-reads the matrices (and refits the other triangles); the
 *  instances' trees never change. cfg.rigid = HZ_ACCEL_RIGID_REFIT and the Embree backend ignore the instances
 *  (their triangles move with pos_keys like any other). The statistics count each ray once.
 *
 *  Layout note: the native node's child words reserve a "motion node" type (src/accel/bvh.h); the motion BVH
 *  instead stores a whole tree's key boxes beside the nodes (see src/accel/msbvh.h), so static nodes are
 *  unchanged.
 */
#ifndef HZ_ACCEL_H
#define HZ_ACCEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hz/arena.h"
#include "hz/base.h"
#include "hz/config.h"
#include "hz/status.h"
#include "hz/vmath.h"

#define HZ_ACCEL_INVALID_ID 0xFFFFFFFFu
/* tri_flags bit 0: the any-hit callback decides hits on this triangle (alpha cutouts, blended surfaces). */
#define HZ_ACCEL_TRI_ANYHIT 0x01u
/* Largest coordinate magnitude a triangle may have (2^36, about 6.9e10; see "Geometry" above). The scene
 * loader refuses positions beyond it. */
#define HZ_ACCEL_MAX_COORD 68719476736.0f
/* The largest split_budget: 4 extra references per triangle (seed 002's MSBVHs replicate up to 2.5x). */
#define HZ_ACCEL_SPLIT_BUDGET_MAX 4.0f
/* tri_flags bit 1: the triangle is not in this structure (never hit, not counted as skipped). The native
 * backend sets it on its own copy of the flags for the triangles its rigid instances hold (see "Rigid
 * instances"); a view may set it too. */
#define HZ_ACCEL_TRI_LEFT_OUT 0x02u
/* Most rigid instances one view carries (see "Rigid instances"): their top level is a list. */
#define HZ_ACCEL_MAX_INSTANCES 16
/* Most triangles one accel takes (the native leaf encoding's limit). */
#define HZ_ACCEL_MAX_TRIS (1u << 25)

/* Children per native BVH node and triangles per leaf block: the SIMD width of the board (scalar boards use 4,
 * so their nodes match the NEON layout). */
#if defined(HZ_SIMD_AVX2)
#define HZ_BVH_WIDTH 8
#else
#define HZ_BVH_WIDTH 4
#endif

/* ---- geometry view ---- */
/* Motion blur: most time keys per vertex (K = 2^m + 1 for m = 0..3, or 2). */
#define HZ_ACCEL_MAX_TIME_KEYS 9

typedef struct hz_accel_geom {
    const float *pos;         /* 4 floats per vertex (x, y, z, unused), 16-byte aligned */
    uint32_t vertex_count;
    const uint32_t *tri;      /* 3 vertex indices per triangle */
    uint32_t tri_count;
    const uint8_t *tri_flags; /* optional, NULL = all opaque; bit 0: HZ_ACCEL_TRI_ANYHIT */
    /* Motion blur (see "Motion" in the contract). 0 or 1: static, only `pos` is read. Else K = 2, 3, 5 or 9
     * keys: pos_keys[k] (k < K) holds the positions at normalised time k / (K - 1), same layout as `pos`; `pos`
     * must still be a valid array (the midpoint key by convention) for code that reads only it. */
    uint32_t time_keys;
    const float *pos_keys[HZ_ACCEL_MAX_TIME_KEYS];
    /* Rigid instances (see "Rigid instances"; only with time_keys >= 2): instance_count ranges of triangles whose
     * motion is rigid, ascending and disjoint. static_rest: the triangles outside them do not move (their
     * positions are equal at every key), so the native backend builds them as static geometry over `pos`. */
    uint32_t instance_count;
    const struct hz_accel_instance *instances;
    bool static_rest;
} hz_accel_geom_t;

/* One rigid instance: triangles [tri_first, tri_first + tri_count) of the view, whose vertices are
 * obj_pos (float4 per vertex, the view's vertex indices, 16-byte aligned) moved by an affine map per key:
 * xform[k] (12 floats, 3 rows of 4, row-major: world = A p + b with A the 3x3 left part, b the last column).
 * The arrays must stay alive and in place while the accel lives; refit re-reads xform. */
typedef struct hz_accel_instance {
    uint32_t tri_first, tri_count;
    const float *obj_pos;
    const float *xform[HZ_ACCEL_MAX_TIME_KEYS];
} hz_accel_instance_t;

/* Zeroes a view (static, no keys, no instances): initialise with this before filling fields, so new fields get
 * defaults. */
HZ_INLINE void hz_accel_geom_init(hz_accel_geom_t *g)
{
    g->pos = 0;
    g->vertex_count = 0;
    g->tri = 0;
    g->tri_count = 0;
    g->tri_flags = 0;
    g->time_keys = 0;
    for (int k = 0; k < HZ_ACCEL_MAX_TIME_KEYS; k++)
        g->pos_keys[k] = 0;
    g->instance_count = 0;
    g->instances = 0;
    g->static_rest = false;
}

/* The motion segment of ray time `time` for K >= 2 keys: the key pair (*seg, *seg + 1) and the weight f of key
 * *seg + 1 in [0, 1]. time is clamped to [0, 1], NaN counts as 0. Exact: time * (K - 1) has no rounding for K - 1
 * a power of two. Every kernel, the brute-force check and the renderer's shading use exactly this and
 * hz_accel_lerp_key, so the triangle a ray hits is the triangle the renderer shades. */
HZ_INLINE void hz_accel_time_segment(float time, uint32_t keys, uint32_t *seg, float *f)
{
    float t = time >= 0.0f ? (time <= 1.0f ? time : 1.0f) : 0.0f; /* NaN fails both: 0 */
    float x = t * (float)(keys - 1u);
    uint32_t s = (uint32_t)x;
    if (s > keys - 2u)
        s = keys - 2u;
    *seg = s;
    *f = x - (float)s;
}

/* Position at weight f between keys a (f = 0) and b (f = 1): (1 - f) * a + f * b with separate products (no
 * fused multiply-add: src/ is built with -ffp-contract=off), so keys are reproduced exactly at f = 0 and 1 and
 * the rounding is monotone in a and b (the bounding argument of the contract's "Motion" relies on it). */
HZ_INLINE float hz_accel_lerp_key(float a, float b, float f)
{
    const float g = 1.0f - f;
    return g * a + f * b;
}

/* ---- rays and hits: Embree 3 layouts ---- */
typedef struct HZ_ALIGNED(16) hz_ray {
    float org_x, org_y, org_z, tnear;
    float dir_x, dir_y, dir_z, time;
    float tfar;
    uint32_t mask, id, flags;
} hz_ray_t;

typedef struct HZ_ALIGNED(16) hz_hit {
    float ng_x, ng_y, ng_z;
    float u, v;
    uint32_t prim_id, geom_id, inst_id[1];
} hz_hit_t;

typedef struct hz_rayhit {
    hz_ray_t ray;
    hz_hit_t hit;
} hz_rayhit_t;

typedef struct HZ_ALIGNED(16) hz_ray4 {
    float org_x[4], org_y[4], org_z[4], tnear[4];
    float dir_x[4], dir_y[4], dir_z[4], time[4];
    float tfar[4];
    uint32_t mask[4], id[4], flags[4];
} hz_ray4_t;

typedef struct HZ_ALIGNED(16) hz_hit4 {
    float ng_x[4], ng_y[4], ng_z[4];
    float u[4], v[4];
    uint32_t prim_id[4], geom_id[4], inst_id[1][4];
} hz_hit4_t;

typedef struct hz_rayhit4 {
    hz_ray4_t ray;
    hz_hit4_t hit;
} hz_rayhit4_t;

typedef struct HZ_ALIGNED(32) hz_ray8 {
    float org_x[8], org_y[8], org_z[8], tnear[8];
    float dir_x[8], dir_y[8], dir_z[8], time[8];
    float tfar[8];
    uint32_t mask[8], id[8], flags[8];
} hz_ray8_t;

typedef struct HZ_ALIGNED(32) hz_hit8 {
    float ng_x[8], ng_y[8], ng_z[8];
    float u[8], v[8];
    uint32_t prim_id[8], geom_id[8], inst_id[1][8];
} hz_hit8_t;

typedef struct hz_rayhit8 {
    hz_ray8_t ray;
    hz_hit8_t hit;
} hz_rayhit8_t;

/* ---- query context ---- */

/* Decides a candidate hit on an HZ_ACCEL_TRI_ANYHIT triangle: true accepts it. ray_id is the ray's id field,
 * lane its lane in the packet (0 for single rays), back the side the ray meets: 1 when its direction runs along
 * the geometric normal (v1 - v0) x (v2 - v0) (the back face of a counter-clockwise triangle), 0 against it; it
 * comes from the intersection test's own determinant sign, so it costs nothing and agrees with the hit. Called
 * from the querying thread. */
typedef bool (*hz_accel_anyhit_fn)(void *user, uint32_t prim_id, float u, float v, float t, uint32_t ray_id,
                                   int lane, unsigned back);

typedef struct hz_accel_stats {
    uint64_t rays;         /* rays (active lanes) queried */
    uint64_t nodes;        /* wide nodes visited (box tests of all children of one node count once) */
    uint64_t tris;         /* ray/triangle tests (per ray and triangle) */
    uint64_t anyhit_calls; /* calls of the any-hit callback */
    /* Per-ray maxima over the queries that used this sink (HZ_FEATURE_STATS): the most wide nodes one ray
     * visited and the most triangles one ray tested (a packet lane counts as one ray; the frustum packet, which
     * visits nodes for the whole packet, charges each active lane the packet's counts). */
    uint32_t ray_nodes_max, ray_tris_max;
} hz_accel_stats_t;

/* Native kernel choice. AUTO takes the fastest measured form for the packet's coherence (doc/accel.md):
 * coherent packets and tiles: the packet traversal; incoherent rays: single rays against wide nodes. */
typedef enum hz_accel_kernel {
    HZ_ACCEL_KERNEL_AUTO = 0,
    HZ_ACCEL_KERNEL_SCALAR,      /* the scalar reference, one ray at a time */
    HZ_ACCEL_KERNEL_SIMD_SINGLE, /* one ray against all children of a wide node at once (AVX2 / NEON) */
    HZ_ACCEL_KERNEL_SIMD_PACKET, /* a packet or tile through one interval test per node (coherent rays) */
    HZ_ACCEL_KERNEL_SIMD_MASKED, /* runs as SIMD_SINGLE (the masked packet, per-lane box tests with lane-mask
                                    compaction, was slower than single rays on every scene and is gone) */
    HZ_ACCEL_KERNEL_COUNT
} hz_accel_kernel_t;

#define HZ_ACCEL_COHERENT 0x1u /* ctx.flags: the packet's rays are coherent */

typedef struct hz_accel_ctx {
    uint32_t flags;           /* HZ_ACCEL_COHERENT */
    hz_accel_kernel_t kernel; /* native backend only; AUTO unless testing or benchmarking */
    hz_accel_anyhit_fn anyhit;
    void *user;
    hz_accel_stats_t *stats;  /* may be NULL; accumulated only when HZ_FEATURE_STATS */
} hz_accel_ctx_t;

HZ_INLINE void hz_accel_ctx_init(hz_accel_ctx_t *c)
{
    c->flags = 0;
    c->kernel = HZ_ACCEL_KERNEL_AUTO;
    c->anyhit = 0;
    c->user = 0;
    c->stats = 0;
}

/* ---- build ---- */
typedef enum hz_accel_backend { HZ_ACCEL_NATIVE = 0, HZ_ACCEL_EMBREE = 1 } hz_accel_backend_t;

/* Which motion-blur BVH the native backend builds for geometry with time_keys >= 2 (seed 002):
 *  MSBVH:  SBVH topology at the midpoint time, node boxes at every key from the leaves' triangles clipped to
 *          the leaf's midpoint box and carried to each key by barycentrics (Grünschloß et al. 2011, 3.1);
 *  INTERP: the classic interpolated BVH: the same builder without spatial splits, boxes at every key from whole
 *          triangles;
 *  SWEPT:  a static BVH over swept boxes (each triangle's box is the union over all keys), no box interpolation.
 * Static geometry ignores the choice. */
typedef enum hz_accel_blur {
    HZ_ACCEL_BLUR_MSBVH = 0,
    HZ_ACCEL_BLUR_INTERP,
    HZ_ACCEL_BLUR_SWEPT,
    HZ_ACCEL_BLUR_COUNT
} hz_accel_blur_t;

const char *hz_accel_blur_name(hz_accel_blur_t b); /* "msbvh", "interp", "swept" */
/* Parses "msbvh" | "interp" | "swept"; false (and *out untouched) for anything else. */
bool hz_accel_blur_parse(const char *s, hz_accel_blur_t *out);

/* What the native backend does with a view's rigid instances (see "Rigid instances"):
 *  INSTANCE: each keeps a static BVH in object space, built once; rays move into it at their time (default);
 *  REFIT:    the instances are ignored: their triangles are motion geometry like any other (refit per frame). */
typedef enum hz_accel_rigid {
    HZ_ACCEL_RIGID_INSTANCE = 0,
    HZ_ACCEL_RIGID_REFIT,
    HZ_ACCEL_RIGID_COUNT
} hz_accel_rigid_t;

const char *hz_accel_rigid_name(hz_accel_rigid_t r); /* "instance", "refit" */
/* Parses "instance" | "refit"; false (and *out untouched) for anything else. */
bool hz_accel_rigid_parse(const char *s, hz_accel_rigid_t *out);

/* How many motion segments the native motion BVH's nodes keep (see "Motion segments per node"):
 *  PER_NODE:  each node 2^m of them (m <= log2(K - 1)), as few as its content's motion needs (default);
 *  EVERY_KEY: every node a box set at every one of the view's K keys. */
typedef enum hz_accel_segments {
    HZ_ACCEL_SEGMENTS_PER_NODE = 0,
    HZ_ACCEL_SEGMENTS_EVERY_KEY,
    HZ_ACCEL_SEGMENTS_COUNT
} hz_accel_segments_t;

const char *hz_accel_segments_name(hz_accel_segments_t s); /* "per-node", "every-key" */
/* Parses "per-node" | "every-key"; false (and *out untouched) for anything else. */
bool hz_accel_segments_parse(const char *s, hz_accel_segments_t *out);

typedef struct hz_accel_config {
    /* native */
    uint32_t leaf_max;     /* triangles per leaf, 1..HZ_BVH_WIDTH (default HZ_BVH_WIDTH) */
    bool spatial_splits;   /* SBVH (Stich et al. 2009); false gives a plain binned-SAH BVH */
    float split_alpha;     /* try spatial splits where children overlap > alpha * root area (1e-5) */
    float split_budget;    /* extra references allowed, as a fraction of the triangle count (0.25; at most
                              HZ_ACCEL_SPLIT_BUDGET_MAX, more is taken as that; the memory bound counts it) */
    /* Embree */
    bool robust;           /* RTC_SCENE_FLAG_ROBUST (watertight, slower) */
    int quality;           /* 0 low, 1 medium (default), 2 high (Embree's own spatial splits) */
    /* Progress of a native build, for the port to show (the core has no I/O); NULL (default) for none. Called
     * on the building thread with the fraction done in [0, 1], at most about 300 times, the last time with 1. */
    void (*progress)(void *user, float done);
    void *progress_user;
    /* motion blur (native; Embree builds its own motion BVH) */
    hz_accel_blur_t blur;     /* HZ_ACCEL_BLUR_MSBVH */
    float rebuild_sah_growth; /* refit rebuilds when the SAH cost grew by more than this fraction (0.30) */
    hz_accel_rigid_t rigid;   /* HZ_ACCEL_RIGID_INSTANCE */
    hz_accel_segments_t segments; /* HZ_ACCEL_SEGMENTS_PER_NODE */
    /* Parallel native build (see "Parallel build" in the contract); NULL (default) builds on the calling thread.
     * run(run_user, fn, ctx, items) must call fn(ctx, item) exactly once for every item in [0, items), in any
     * order and on any threads, and return when every call has returned; it is called only from the building
     * thread, never from inside fn. run_threads: how many threads run uses (a hint: <= 1 builds serially). */
    void (*run)(void *run_user, void (*fn)(void *ctx, uint32_t item), void *ctx, uint32_t items);
    void *run_user;
    uint32_t run_threads;
} hz_accel_config_t;

void hz_accel_config_default(hz_accel_config_t *cfg);

/* Bytes of the accel arena a native build of tri_count triangles with cfg needs at most: `peak` must be free
 * when the build starts, `kept` stays allocated after it. Guaranteed bounds (the builder enforces the
 * replication budget); typical builds use a third to a half. Saturates at SIZE_MAX. */
typedef struct hz_accel_bytes {
    size_t peak;
    size_t kept;
} hz_accel_bytes_t;

hz_accel_bytes_t hz_accel_bytes_bound(uint32_t tri_count, const hz_accel_config_t *cfg);

/* The same bounds for a geometry view, motion included (time_keys >= 2: the key copies of the triangles, the
 * node boxes per key, the MSBVH's pieces, and the build's scratch; static views give hz_accel_bytes_bound). A
 * refit that decides to rebuild needs `peak` bytes free above the accel (it builds the new tree before it
 * drops the old one); without them it only refits. */
hz_accel_bytes_t hz_accel_bytes_bound_geom(const hz_accel_geom_t *g, const hz_accel_config_t *cfg);

/* HZ_OK if a native build of tri_count triangles surely fits in `available` bytes, else HZ_E_NO_MEMORY with
 * "accel: <n> triangles need up to <peak> bytes to build, arena '<name>' has <available>". The _geom form
 * checks a view with motion. */
hz_status_t hz_accel_plan_check(uint32_t tri_count, const hz_accel_config_t *cfg, const hz_arena_t *arena,
                                hz_error_t *err);
hz_status_t hz_accel_plan_check_geom(const hz_accel_geom_t *g, const hz_accel_config_t *cfg, const hz_arena_t *arena,
                                     hz_error_t *err);

/* What a build produced (filled by the backend; times are measured by the caller, src/ has no clock). */
typedef struct hz_accel_info {
    const char *backend;     /* "native-avx2", "native-neon", "native-scalar", "embree" */
    uint32_t tri_count;      /* triangles in the view */
    uint32_t tri_skipped;    /* triangles left out (non-finite vertices) */
    uint32_t ref_count;      /* triangle references after spatial splits (native) */
    uint32_t spatial_splits; /* nodes split spatially (native) */
    uint32_t budget_stops;   /* spatial split searches skipped and straddling references kept whole because the
                                replication budget was spent (native): 0 means the budget never bound, the tree
                                is the one the overlap threshold alone gives */
    uint32_t tasks_rebuilt;  /* parallel-build tasks built a second time because the first pass went over the
                                replication budget (native) */
    uint32_t node_count;     /* wide nodes (native) */
    uint32_t leaf_count;
    uint32_t block_count;    /* triangle blocks of HZ_BVH_WIDTH slots */
    uint32_t depth;          /* deepest wide-node level */
    float sah_cost;          /* SAH cost of the binary tree, relative to the root box (native); with motion: of
                                the wide tree with its boxes averaged over the keys, as of the last build/refit */
    size_t bytes;            /* bytes the built structure holds */
    size_t bytes_peak;       /* most bytes held during the build */
    /* motion blur */
    uint32_t time_keys;      /* K of the geometry (0 = static) */
    hz_accel_blur_t blur;    /* the motion BVH built (meaningful when time_keys >= 2) */
    float sah_built;         /* sah_cost right after the last (re)build: refit compares against it */
    uint32_t refits;         /* refits since the first build (each re-reads the keys) */
    uint32_t rebuilds;       /* refits that rebuilt because sah_cost > sah_built * (1 + rebuild_sah_growth) */
    uint64_t key_sets;       /* box sets the nodes hold, one per node and key it keeps: node_count * K with
                                every key, down to node_count * 2 when no node needs more than one segment */
    /* rigid instances (native, cfg.rigid = INSTANCE): the figures above sum the instances' object-space BVHs
     * and the BVH of the other triangles; sah_cost is the latter's (0 when every triangle is in an instance) */
    uint32_t instances;      /* instances built (0: none) */
    uint32_t instance_tris;  /* triangles they hold */
} hz_accel_info_t;

typedef struct hz_accel hz_accel_t;

/* Backend operations: the native backend's live in src/accel, Embree's in port/embree. */
typedef struct hz_accel_ops {
    void (*intersect1)(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit_t *rh);
    void (*occluded1)(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray_t *r);
    void (*intersect4)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh);
    void (*occluded4)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r);
    void (*intersect8)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh);
    void (*occluded8)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r);
    hz_status_t (*refit)(hz_accel_t *a, hz_error_t *err);
    void (*release)(hz_accel_t *a);
    /* Large packets (see "Tiles"); NULL: the wrappers below call the one-packet forms packet by packet. */
    void (*intersect8n)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit8_t *rh,
                        uint32_t n);
    void (*occluded8n)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r, uint32_t n);
    void (*intersect4n)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit4_t *rh,
                        uint32_t n);
    void (*occluded4n)(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r, uint32_t n);
} hz_accel_ops_t;

struct hz_accel {
    const hz_accel_ops_t *ops;
    hz_accel_backend_t backend;
    hz_accel_geom_t geom;
    hz_accel_info_t info;
    void *impl; /* backend data */
};

/* The view of a loaded scene: its current positions (animation writes them in place, so refit sees them) and
 * indices; triangles whose material is alpha-tested or blended get HZ_ACCEL_TRI_ANYHIT, in a flag array taken
 * from `arena` (only when the scene has such materials; tri_flags stays NULL otherwise). */
struct hz_scene;
hz_status_t hz_accel_geom_from_scene(hz_accel_geom_t *g, const struct hz_scene *scene, hz_arena_t *arena,
                                     hz_error_t *err);

/* Validates geom (HZ_E_INVALID_ARG / HZ_E_RANGE naming the field or triangle); shared by both backends. With
 * motion: time_keys in {0, 1, 2, 3, 5, 9}, every key array present and 16-byte aligned. */
hz_status_t hz_accel_geom_check(const hz_accel_geom_t *g, hz_error_t *err);

/* Native build ("commit"): all memory from `arena` (cfg may be NULL for defaults). *out points into the
 * arena; nothing needs releasing, the arena owner resets it. With motion (time_keys >= 2) the accel keeps
 * `arena` for rebuilds on refit: allocate nothing else from it after the build, or refit only refits. */
hz_status_t hz_accel_build_native(hz_accel_t **out, const hz_accel_geom_t *g, const hz_accel_config_t *cfg,
                                  hz_arena_t *arena, hz_error_t *err);

/* Recomputes boxes (and the native backend's triangle copies) after the renderer moved vertices in geom.pos
 * (or, with motion, rewrote geom.pos_keys for a new shutter interval: the MSBVH re-clips its leaves); the
 * topology stays. Cheaper than a build, but rays slow down as the motion grows: with motion the native backend
 * rebuilds (in the same arena, the same bytes bound) when the SAH cost grew past cfg.rebuild_sah_growth, and
 * counts refits and rebuilds in info. */
HZ_INLINE hz_status_t hz_accel_refit(hz_accel_t *a, hz_error_t *err) { return a->ops->refit(a, err); }
/* Gives back what the backend holds outside arenas (Embree's device and scene). */
HZ_INLINE void hz_accel_release(hz_accel_t *a)
{
    if (a && a->ops->release)
        a->ops->release(a);
}

/* ---- queries (argument order as in Embree: valid, accel, ctx, rays); ctx may be NULL ---- */
HZ_INLINE void hz_accel_intersect1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_rayhit_t *rh)
{
    a->ops->intersect1(a, ctx, rh);
}
HZ_INLINE void hz_accel_occluded1(const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray_t *r)
{
    a->ops->occluded1(a, ctx, r);
}
HZ_INLINE void hz_accel_intersect4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx,
                                   hz_rayhit4_t *rh)
{
    a->ops->intersect4(valid, a, ctx, rh);
}
HZ_INLINE void hz_accel_occluded4(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r)
{
    a->ops->occluded4(valid, a, ctx, r);
}
HZ_INLINE void hz_accel_intersect8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx,
                                   hz_rayhit8_t *rh)
{
    a->ops->intersect8(valid, a, ctx, rh);
}
HZ_INLINE void hz_accel_occluded8(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r)
{
    a->ops->occluded8(valid, a, ctx, r);
}

/* Tiles: n consecutive packets (valid: 8 n or 4 n words, lane i of packet p at valid[8 p + i]) in one call.
 * The results are exactly those of n calls of hz_accel_intersect8 / occluded8 (4) on the same packets. */
HZ_INLINE void hz_accel_intersect8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx,
                                    hz_rayhit8_t *rh, uint32_t n)
{
    if (a->ops->intersect8n) {
        a->ops->intersect8n(valid, a, ctx, rh, n);
        return;
    }
    for (uint32_t p = 0; p < n; p++)
        a->ops->intersect8(valid + 8u * (size_t)p, a, ctx, rh + p);
}
HZ_INLINE void hz_accel_occluded8n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray8_t *r,
                                   uint32_t n)
{
    if (a->ops->occluded8n) {
        a->ops->occluded8n(valid, a, ctx, r, n);
        return;
    }
    for (uint32_t p = 0; p < n; p++)
        a->ops->occluded8(valid + 8u * (size_t)p, a, ctx, r + p);
}
HZ_INLINE void hz_accel_intersect4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx,
                                    hz_rayhit4_t *rh, uint32_t n)
{
    if (a->ops->intersect4n) {
        a->ops->intersect4n(valid, a, ctx, rh, n);
        return;
    }
    for (uint32_t p = 0; p < n; p++)
        a->ops->intersect4(valid + 4u * (size_t)p, a, ctx, rh + p);
}
HZ_INLINE void hz_accel_occluded4n(const int32_t *valid, const hz_accel_t *a, hz_accel_ctx_t *ctx, hz_ray4_t *r,
                                   uint32_t n)
{
    if (a->ops->occluded4n) {
        a->ops->occluded4n(valid, a, ctx, r, n);
        return;
    }
    for (uint32_t p = 0; p < n; p++)
        a->ops->occluded4(valid + 4u * (size_t)p, a, ctx, r + p);
}

/* The reference for tests and `hzrt accel --motion-check`: the closest hit of rh over every triangle of g at
 * rh->ray.time (hz_accel_time_segment + hz_accel_lerp_key per vertex), with the native kernels' watertight test
 * and tie rule but no hierarchy: O(triangles) per ray. Triangles with a non-finite coordinate (at any key)
 * never hit. Writes rh as hz_accel_intersect1 does; any-hit flags are ignored (every triangle opaque). A view
 * with rigid instances is taken as the default configuration builds it (see "Rigid instances"; the other
 * triangles over pos when static_rest): to check a REFIT build, pass the view without its instances. */
void hz_accel_brute_intersect1(const hz_accel_geom_t *g, hz_rayhit_t *rh);

/* Whether the native build of this board has a SIMD form of `kernel` (SCALAR and AUTO always). */
bool hz_accel_kernel_available(hz_accel_kernel_t kernel);
const char *hz_accel_kernel_name(hz_accel_kernel_t kernel);

/* ---- secondary-ray origins ---- */

/* Offsets a hit point p along the geometric normal n (need not be normalised, must face the side the new ray
 * leaves from: flip it for rays into the surface) so that a ray started there does not hit the surface it
 * left (Wächter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6):
 * away from the origin the point moves by 256 float ulps per unit of normal component; where a component is
 * within scale/32 of 0 it moves by scale/65536 instead. `scale` is the scene's size (the largest absolute
 * coordinate of its bounds): with scale = 1 these are the chapter's constants, and scaling them with the scene
 * keeps the method robust from scenes of 1e-6 to 1e6 units. scale <= 0 (or not finite) means 1. Use the new
 * ray with tnear = 0. */
hz_vec3_t hz_accel_offset_origin(hz_vec3_t p, hz_vec3_t n, float scale);

#endif /* HZ_ACCEL_H */
