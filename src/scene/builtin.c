/* The built-in scene (see hz/builtin.h): geometry, textures, motion, lights and camera made procedurally, then
 * serialised with the .hzb writer so that it meets exactly the checks a baked file meets. */
#include "hz/builtin.h"

#include "hz/hash.h"
#include "hz/hzb_write.h"
#include "scene_internal.h"

/* Capacities: generous upper bounds, checked on every append. */
#define MAX_VERTS 8192
#define MAX_TRIS 8192
#define MAX_OBJECTS 16
#define MAX_TEXELS (3 * 87382) /* three 256x256 textures with full mip chains */
#define FLAG_NX 16
#define FLAG_NY 10
#define FLAG_FRAMES 60
#define FLAG_RATE 30.0f

enum { MAT_FLOOR, MAT_WALL, MAT_CEILING, MAT_MIRROR, MAT_BOX, MAT_SPHERE, MAT_PEDESTAL, MAT_CUTOUT,
       MAT_PARTICLE0, MAT_PARTICLE1, MAT_PARTICLE2, MAT_PARTICLE3, MAT_FLAG, MAT_COUNT };
enum { TEX_CHECKER, TEX_BRICK, TEX_LEAVES, TEX_COUNT };

typedef struct builder {
    float *pos, *nrm, *uv;
    uint32_t *tri, *info;
    uint32_t nv, nt;
    hz_hzb_object_t objects[MAX_OBJECTS];
    uint32_t no;
    uint8_t *texels;
    uint32_t ntexels;
    hz_hzb_texture_t textures[TEX_COUNT];
    float *vkeys, *vkey_nrm;
    uint32_t nvkeys;
    int overflow;
} builder_t;

static uint32_t add_vertex(builder_t *b, hz_vec3_t p, hz_vec3_t n, float u, float v)
{
    if (b->nv >= MAX_VERTS) {
        b->overflow = 1;
        return 0;
    }
    uint32_t i = b->nv++;
    float *dp = b->pos + (size_t)i * 4, *dn = b->nrm + (size_t)i * 4;
    dp[0] = p.x, dp[1] = p.y, dp[2] = p.z, dp[3] = 0.0f;
    n = hz_v3_normalize(n);
    dn[0] = n.x, dn[1] = n.y, dn[2] = n.z, dn[3] = 0.0f;
    b->uv[i * 2] = u, b->uv[i * 2 + 1] = v;
    return i;
}

static void add_tri(builder_t *b, uint32_t a, uint32_t c, uint32_t d, uint32_t mat)
{
    if (b->nt >= MAX_TRIS || b->no == 0) {
        b->overflow = 1;
        return;
    }
    uint32_t t = b->nt++;
    b->tri[t * 3] = a, b->tri[t * 3 + 1] = c, b->tri[t * 3 + 2] = d;
    b->info[t] = mat | (b->no - 1) << 16;
}

static void begin_object(builder_t *b, const char *name)
{
    if (b->no >= MAX_OBJECTS) {
        b->overflow = 1;
        return;
    }
    hz_hzb_object_t *o = &b->objects[b->no++];
    hz_memset(o, 0, sizeof *o);
    for (uint32_t i = 0; i + 1 < HZ_HZB_NAME_BYTES && name[i]; i++)
        o->name[i] = (uint8_t)name[i];
    o->first_triangle = b->nt;
    o->first_vertex = b->nv;
}

static hz_hzb_object_t *end_object(builder_t *b)
{
    hz_hzb_object_t *o = &b->objects[b->no - 1];
    o->triangle_count = b->nt - o->first_triangle;
    o->vertex_count = b->nv - o->first_vertex;
    return o;
}

/* A grid of nu x nv quads spanning origin + [0,1] du + [0,1] dv, facing along du x dv; uv = position / tile. */
static void add_grid(builder_t *b, hz_vec3_t origin, hz_vec3_t du, hz_vec3_t dv, int nu, int nv, float tile,
                     uint32_t mat)
{
    hz_vec3_t n = hz_v3_cross(du, dv);
    uint32_t base = b->nv;
    float lu = hz_v3_len(du), lv = hz_v3_len(dv);
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            float s = (float)i / nu, t = (float)j / nv;
            hz_vec3_t p = hz_v3_add(origin, hz_v3_add(hz_v3_scale(du, s), hz_v3_scale(dv, t)));
            add_vertex(b, p, n, s * lu / tile, t * lv / tile);
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = base + (uint32_t)(j * (nu + 1) + i);
            add_tri(b, a, a + 1, a + (uint32_t)nu + 2, mat);
            add_tri(b, a, a + (uint32_t)nu + 2, a + (uint32_t)nu + 1, mat);
        }
}

static void add_box(builder_t *b, hz_vec3_t c, hz_vec3_t h, uint32_t mat)
{
    /* Six faces, each with its own vertices so normals stay flat. */
    const hz_vec3_t axes[3] = { hz_v3(1, 0, 0), hz_v3(0, 1, 0), hz_v3(0, 0, 1) };
    for (int a = 0; a < 3; a++)
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            hz_vec3_t n = hz_v3_scale(axes[a], (float)sgn);
            hz_vec3_t u = axes[(a + 1) % 3], v = axes[(a + 2) % 3];
            if (sgn < 0) {
                hz_vec3_t t = u;
                u = v, v = t;
            }
            hz_vec3_t hu = hz_v3_mul(u, h), hv = hz_v3_mul(v, h), hn = hz_v3_mul(n, h);
            hz_vec3_t o = hz_v3_sub(hz_v3_sub(hz_v3_add(c, hn), hu), hv);
            add_grid(b, o, hz_v3_scale(hu, 2.0f), hz_v3_scale(hv, 2.0f), 1, 1, 1.0f, mat);
        }
}

static void add_sphere(builder_t *b, hz_vec3_t c, float r, int seg, int rings, uint32_t mat)
{
    uint32_t base = b->nv;
    for (int j = 0; j <= rings; j++) {
        float th = HZ_PI * (float)j / rings;
        float st, ct;
        hz_sincosf(th, &st, &ct);
        for (int i = 0; i <= seg; i++) {
            float ph = 2.0f * HZ_PI * (float)i / seg;
            float sp, cp;
            hz_sincosf(ph, &sp, &cp);
            hz_vec3_t n = hz_v3(st * cp, ct, st * sp);
            add_vertex(b, hz_v3_add(c, hz_v3_scale(n, r)), n, (float)i / seg, (float)j / rings);
        }
    }
    for (int j = 0; j < rings; j++)
        for (int i = 0; i < seg; i++) {
            uint32_t a = base + (uint32_t)(j * (seg + 1) + i), d = a + (uint32_t)seg + 1;
            if (j > 0)
                add_tri(b, a, a + 1, d, mat);
            if (j < rings - 1)
                add_tri(b, a + 1, d + 1, d, mat);
        }
}

static void add_octahedron(builder_t *b, hz_vec3_t c, float r, uint32_t mat)
{
    static const int8_t dirs[6][3] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 }, { 0, 0, -1 } };
    static const uint8_t faces[8][3] = { { 0, 2, 4 }, { 4, 2, 1 }, { 1, 2, 5 }, { 5, 2, 0 },
                                         { 4, 3, 0 }, { 1, 3, 4 }, { 5, 3, 1 }, { 0, 3, 5 } };
    uint32_t base = b->nv;
    for (int i = 0; i < 6; i++) {
        hz_vec3_t n = hz_v3(dirs[i][0], dirs[i][1], dirs[i][2]);
        add_vertex(b, hz_v3_add(c, hz_v3_scale(n, r)), n, 0.5f, 0.5f);
    }
    for (int f = 0; f < 8; f++)
        add_tri(b, base + faces[f][0], base + faces[f][1], base + faces[f][2], mat);
}

/* ---- textures (sRGB RGBA8, full mip chains) ---- */

static void put_texel(uint8_t *t, uint32_t r, uint32_t g, uint32_t bl, uint32_t a)
{
    t[0] = (uint8_t)r, t[1] = (uint8_t)g, t[2] = (uint8_t)bl, t[3] = (uint8_t)a;
}

/* Level 0 from the pattern, the rest by 2x2 box filtering. The filter averages the stored sRGB bytes, not
 * linear values: for these procedural patterns the coarse levels come out slightly dark at high-contrast edges,
 * which only affects distant texels of the built-in scene. Alpha is averaged as stored (it is linear). */
static void add_texture(builder_t *b, uint32_t index, const char *name, uint32_t size, int pattern)
{
    hz_hzb_texture_t *t = &b->textures[index];
    hz_memset(t, 0, sizeof *t);
    for (uint32_t i = 0; i + 1 < HZ_HZB_NAME_BYTES && name[i]; i++)
        t->name[i] = (uint8_t)name[i];
    t->width = t->height = size;
    t->first_texel = b->ntexels;
    uint8_t *l0 = b->texels + (size_t)b->ntexels * 4;
    for (uint32_t y = 0; y < size; y++)
        for (uint32_t x = 0; x < size; x++) {
            uint8_t *p = l0 + ((size_t)y * size + x) * 4;
            if (pattern == TEX_CHECKER) {
                int on = ((x / 32) + (y / 32)) & 1;
                put_texel(p, on ? 210 : 60, on ? 205 : 62, on ? 195 : 70, 255);
            } else if (pattern == TEX_BRICK) {
                uint32_t row = y / 32, off = (row & 1) * 32;
                int mortar = (y % 32) < 3 || ((x + off) % 64) < 3;
                uint32_t shade = hz_hash2(((x + off) / 64) * 7 + row, 11) & 31;
                if (mortar)
                    put_texel(p, 180, 175, 165, 255);
                else
                    put_texel(p, 150 + shade, 70 + shade / 2, 50 + shade / 3, 255);
            } else {
                /* Leaves: discs on a transparent background, for the alpha-tested panel. */
                uint32_t cx = (x / 32) * 32 + 16, cy = (y / 32) * 32 + 16;
                int32_t dx = (int32_t)x - (int32_t)cx, dy = (int32_t)y - (int32_t)cy;
                uint32_t r2 = (uint32_t)(dx * dx + dy * dy);
                int in = r2 < 13u * 13u;
                put_texel(p, 60, 140 + (hz_hash2(x / 32, y / 32) & 63), 50, in ? 255 : 0);
                if (!in)
                    t->flags |= 1u;
            }
        }
    uint32_t w = size, count = size * size, levels = 1;
    const uint8_t *src = l0;
    while (w > 1) {
        uint32_t nw = w / 2;
        uint8_t *dst = (uint8_t *)src + (size_t)w * w * 4;
        for (uint32_t y = 0; y < nw; y++)
            for (uint32_t x = 0; x < nw; x++)
                for (int c = 0; c < 4; c++) {
                    uint32_t s = src[((2 * y) * w + 2 * x) * 4 + c] + src[((2 * y) * w + 2 * x + 1) * 4 + c] +
                                 src[((2 * y + 1) * w + 2 * x) * 4 + c] + src[((2 * y + 1) * w + 2 * x + 1) * 4 + c];
                    dst[((size_t)y * nw + x) * 4 + c] = (uint8_t)((s + 2) / 4);
                }
        src = dst;
        w = nw;
        count += w * w;
        levels++;
    }
    t->levels = levels;
    t->texel_count = count;
    b->ntexels += count;
}

/* ---- the waving flag: per-vertex keys ---- */

static hz_vec3_t flag_point(int i, int j, float t)
{
    const float width = 1.6f, height = 1.0f;
    float s = (float)i / FLAG_NX, v = (float)j / FLAG_NY;
    float wave = 0.12f * s * hz_sinf(2.0f * HZ_PI * (1.5f * t - 1.2f * s));
    /* Hangs from a pole at x = 3.6 near the right wall, in the plane x = const + wave, spanning z. */
    return hz_v3(3.6f + wave, 2.6f - height * v, -2.4f + width * s);
}

static void flag_frame(builder_t *b, float t, float *pos, float *nrm)
{
    for (int j = 0; j <= FLAG_NY; j++)
        for (int i = 0; i <= FLAG_NX; i++) {
            hz_vec3_t p = flag_point(i, j, t);
            /* Normal from central differences of the analytic surface. */
            hz_vec3_t du = hz_v3_sub(flag_point(i + 1, j, t), flag_point(i - 1, j, t));
            hz_vec3_t dv = hz_v3_sub(flag_point(i, j + 1, t), flag_point(i, j - 1, t));
            hz_vec3_t n = hz_v3_normalize(hz_v3_cross(dv, du));
            size_t k = (size_t)(j * (FLAG_NX + 1) + i) * 4;
            pos[k] = p.x, pos[k + 1] = p.y, pos[k + 2] = p.z, pos[k + 3] = 0.0f;
            nrm[k] = n.x, nrm[k + 1] = n.y, nrm[k + 2] = n.z, nrm[k + 3] = 0.0f;
        }
    (void)b;
}

static void add_flag(builder_t *b)
{
    uint32_t base = b->nv;
    float pos[(FLAG_NX + 1) * (FLAG_NY + 1) * 4], nrm[(FLAG_NX + 1) * (FLAG_NY + 1) * 4];
    flag_frame(b, 0.0f, pos, nrm);
    for (int j = 0; j <= FLAG_NY; j++)
        for (int i = 0; i <= FLAG_NX; i++) {
            size_t k = (size_t)(j * (FLAG_NX + 1) + i) * 4;
            add_vertex(b, hz_v3(pos[k], pos[k + 1], pos[k + 2]), hz_v3(nrm[k], nrm[k + 1], nrm[k + 2]),
                       (float)i / FLAG_NX, (float)j / FLAG_NY);
        }
    for (int j = 0; j < FLAG_NY; j++)
        for (int i = 0; i < FLAG_NX; i++) {
            uint32_t a = base + (uint32_t)(j * (FLAG_NX + 1) + i);
            add_tri(b, a, a + FLAG_NX + 2, a + 1, MAT_FLAG);
            add_tri(b, a, a + FLAG_NX + 1, a + FLAG_NX + 2, MAT_FLAG);
        }
    uint32_t nverts = (FLAG_NX + 1) * (FLAG_NY + 1);
    for (int f = 0; f < FLAG_FRAMES; f++)
        flag_frame(b, (float)f / FLAG_RATE, b->vkeys + (size_t)f * nverts * 4, b->vkey_nrm + (size_t)f * nverts * 4);
    b->nvkeys = FLAG_FRAMES * nverts;
}

static hz_hzb_material_t material(const char *name, float r, float g, float bl)
{
    hz_hzb_material_t m;
    hz_memset(&m, 0, sizeof m);
    for (uint32_t i = 0; i + 1 < HZ_HZB_NAME_BYTES && name[i]; i++)
        m.name[i] = (uint8_t)name[i];
    m.base_color[0] = r, m.base_color[1] = g, m.base_color[2] = bl;
    m.alpha = 1.0f;
    m.alpha_cutoff = 0.5f;
    m.base_texture = -1;
    m.alpha_texture = -1;
    return m;
}

static hz_hzb_camera_key_t camera_key(float t, hz_vec3_t eye, hz_vec3_t target)
{
    hz_hzb_camera_key_t k;
    hz_memset(&k, 0, sizeof k);
    k.time = t;
    k.eye[0] = eye.x, k.eye[1] = eye.y, k.eye[2] = eye.z;
    k.target[0] = target.x, k.target[1] = target.y, k.target[2] = target.z;
    k.up[1] = 1.0f;
    k.fov_y = 60.0f * HZ_PI / 180.0f;
    return k;
}

hz_status_t hz_builtin_scene_image(hz_arena_t *image_arena, hz_arena_t *scratch, const void **image, size_t *size,
                                   hz_error_t *err)
{
    if (!image_arena || !scratch || !image || !size)
        return hz_error_set(err, HZ_E_INVALID_ARG, "built-in scene: missing argument");
    hz_arena_mark_t mark = hz_arena_mark(scratch);
    builder_t b;
    hz_memset(&b, 0, sizeof b);
    uint32_t flag_verts = (FLAG_NX + 1) * (FLAG_NY + 1);
    b.pos = hz_arena_alloc_array(scratch, MAX_VERTS, 16, 64);
    b.nrm = hz_arena_alloc_array(scratch, MAX_VERTS, 16, 64);
    b.uv = hz_arena_alloc_array(scratch, MAX_VERTS, 8, 64);
    b.tri = hz_arena_alloc_array(scratch, MAX_TRIS, 12, 64);
    b.info = hz_arena_alloc_array(scratch, MAX_TRIS, 4, 64);
    b.texels = hz_arena_alloc_array(scratch, MAX_TEXELS, 4, 64);
    b.vkeys = hz_arena_alloc_array(scratch, (size_t)FLAG_FRAMES * flag_verts, 16, 64);
    b.vkey_nrm = hz_arena_alloc_array(scratch, (size_t)FLAG_FRAMES * flag_verts, 16, 64);
    if (!b.pos || !b.nrm || !b.uv || !b.tri || !b.info || !b.texels || !b.vkeys || !b.vkey_nrm) {
        hz_status_t s = hz_arena_error(scratch, err);
        hz_error_prefix(err, "built-in scene");
        hz_arena_reset(scratch, mark);
        return s;
    }

    add_texture(&b, TEX_CHECKER, "checker", 256, TEX_CHECKER);
    add_texture(&b, TEX_BRICK, "brick", 256, TEX_BRICK);
    add_texture(&b, TEX_LEAVES, "leaves", 128, TEX_LEAVES);

    hz_hzb_material_t mats[MAT_COUNT];
    mats[MAT_FLOOR] = material("floor", 1.0f, 1.0f, 1.0f);
    mats[MAT_FLOOR].base_texture = TEX_CHECKER;
    mats[MAT_WALL] = material("wall", 1.0f, 1.0f, 1.0f);
    mats[MAT_WALL].base_texture = TEX_BRICK;
    mats[MAT_CEILING] = material("ceiling", 0.75f, 0.75f, 0.72f);
    mats[MAT_MIRROR] = material("mirror", 0.04f, 0.04f, 0.05f);
    mats[MAT_MIRROR].mirror = 0.9f;
    mats[MAT_BOX] = material("box", 0.75f, 0.22f, 0.12f);
    mats[MAT_SPHERE] = material("sphere", 0.15f, 0.45f, 0.8f);
    mats[MAT_SPHERE].mirror = 0.25f;
    mats[MAT_PEDESTAL] = material("pedestal", 0.6f, 0.6f, 0.6f);
    mats[MAT_CUTOUT] = material("leaves", 1.0f, 1.0f, 1.0f);
    mats[MAT_CUTOUT].base_texture = TEX_LEAVES;
    mats[MAT_CUTOUT].alpha_texture = TEX_LEAVES;
    mats[MAT_CUTOUT].alpha_mode = HZ_ALPHA_MASK;
    static const float particle_rgb[4][3] = { { 0.9f, 0.3f, 0.2f }, { 0.2f, 0.8f, 0.3f }, { 0.25f, 0.4f, 0.95f },
                                              { 0.95f, 0.85f, 0.2f } };
    for (int i = 0; i < 4; i++) {
        mats[MAT_PARTICLE0 + i] = material("particle", particle_rgb[i][0], particle_rgb[i][1], particle_rgb[i][2]);
        mats[MAT_PARTICLE0 + i].alpha_mode = HZ_ALPHA_BLEND;
        mats[MAT_PARTICLE0 + i].alpha = 0.35f;
    }
    mats[MAT_FLAG] = material("flag", 0.85f, 0.75f, 0.15f);

    /* Room 10 x 4 x 10, floor at y = 0. Walls face inward. */
    begin_object(&b, "room");
    add_grid(&b, hz_v3(-5, 0, 5), hz_v3(10, 0, 0), hz_v3(0, 0, -10), 8, 8, 2.0f, MAT_FLOOR);
    add_grid(&b, hz_v3(-5, 4, -5), hz_v3(10, 0, 0), hz_v3(0, 0, 10), 4, 4, 2.0f, MAT_CEILING);
    add_grid(&b, hz_v3(-5, 0, -5), hz_v3(10, 0, 0), hz_v3(0, 4, 0), 8, 4, 2.0f, MAT_WALL);  /* back, faces +z */
    add_grid(&b, hz_v3(5, 0, 5), hz_v3(-10, 0, 0), hz_v3(0, 4, 0), 8, 4, 2.0f, MAT_WALL);  /* front, faces -z */
    add_grid(&b, hz_v3(-5, 0, 5), hz_v3(0, 0, -10), hz_v3(0, 4, 0), 8, 4, 2.0f, MAT_WALL); /* left, faces +x */
    add_grid(&b, hz_v3(5, 0, -5), hz_v3(0, 0, 10), hz_v3(0, 4, 0), 8, 4, 2.0f, MAT_WALL);  /* right, faces -x */
    end_object(&b);

    begin_object(&b, "mirror");
    add_grid(&b, hz_v3(-2.0f, 0.6f, -4.95f), hz_v3(4.0f, 0, 0), hz_v3(0, 2.6f, 0), 1, 1, 1.0f, MAT_MIRROR);
    add_box(&b, hz_v3(0, 0.3f, -4.9f), hz_v3(2.2f, 0.3f, 0.08f), MAT_PEDESTAL);
    end_object(&b);

    begin_object(&b, "pedestal");
    add_box(&b, hz_v3(-1.2f, 0.4f, -1.0f), hz_v3(0.5f, 0.4f, 0.5f), MAT_PEDESTAL);
    end_object(&b);

    begin_object(&b, "spinning box");
    add_box(&b, hz_v3(-1.2f, 1.25f, -1.0f), hz_v3(0.35f, 0.35f, 0.35f), MAT_BOX);
    hz_hzb_object_t *spin = end_object(&b);
    spin->motion = HZ_MOTION_SPIN;
    spin->params[0] = -1.2f, spin->params[1] = 1.25f, spin->params[2] = -1.0f; /* pivot: the box centre */
    spin->params[3] = 0.3f, spin->params[4] = 1.0f, spin->params[5] = 0.2f;    /* tilted axis */
    spin->params[6] = HZ_PI / 2.0f;                                           /* a quarter turn per second */

    begin_object(&b, "bouncing sphere");
    add_sphere(&b, hz_v3(1.4f, 0.9f, -0.6f), 0.55f, 32, 16, MAT_SPHERE);
    hz_hzb_object_t *osc = end_object(&b);
    osc->motion = HZ_MOTION_OSCILLATE;
    osc->params[0] = 0.8f, osc->params[1] = 0.3f, osc->params[2] = 0.0f; /* amplitude */
    osc->params[3] = 0.25f;                                            /* Hz: 2 periods per 8 s loop */

    begin_object(&b, "leaf panel");
    add_grid(&b, hz_v3(-4.9f, 0.5f, 1.5f), hz_v3(0, 0, -3.0f), hz_v3(0, 2.4f, 0), 1, 1, 0.75f, MAT_CUTOUT);
    end_object(&b);

    /* 160 particles in a loose cloud: one octahedron mesh placed 160 times (instancing, expanded). */
    begin_object(&b, "particles");
    for (uint32_t i = 0; i < 160; i++) {
        uint32_t h = hz_hash2(i, 0x5eed);
        float x = -3.0f + 6.0f * hz_u32_to_unit(h);
        float y = 0.8f + 2.6f * hz_u32_to_unit(hz_hash32(h));
        float z = -3.5f + 5.0f * hz_u32_to_unit(hz_hash32(h ^ 0x9e3779b9u));
        float r = 0.06f + 0.08f * hz_u32_to_unit(hz_hash_pcg(h));
        add_octahedron(&b, hz_v3(x, y, z), r, MAT_PARTICLE0 + (i & 3));
    }
    end_object(&b);

    begin_object(&b, "flag");
    add_flag(&b);
    hz_hzb_object_t *flag = end_object(&b);
    flag->motion = HZ_MOTION_VERTEX;
    flag->key_first = 0;
    flag->key_count = FLAG_FRAMES;
    flag->key_rate = FLAG_RATE;

    if (b.overflow) {
        hz_arena_reset(scratch, mark);
        return hz_error_set(err, HZ_E_INTERNAL, "built-in scene: a builder capacity is too small");
    }

    hz_hzb_light_t lights[2];
    hz_memset(lights, 0, sizeof lights);
    lights[0].position[0] = -2.0f, lights[0].position[1] = 3.6f, lights[0].position[2] = 1.5f;
    lights[0].color[0] = 9.0f, lights[0].color[1] = 7.5f, lights[0].color[2] = 6.0f;
    lights[1].position[0] = 3.0f, lights[1].position[1] = 3.2f, lights[1].position[2] = -2.5f;
    lights[1].color[0] = 4.0f, lights[1].color[1] = 5.0f, lights[1].color[2] = 7.0f;

    hz_hzb_camera_key_t cams[4] = {
        camera_key(0.0f, hz_v3(-2.6f, 1.7f, 4.2f), hz_v3(0.4f, 1.2f, -3.0f)),
        camera_key(2.0f, hz_v3(0.0f, 2.3f, 4.4f), hz_v3(0.0f, 1.0f, -3.0f)),
        camera_key(4.0f, hz_v3(2.6f, 1.7f, 4.2f), hz_v3(-0.4f, 1.2f, -3.0f)),
        camera_key(6.0f, hz_v3(0.0f, 1.4f, 3.6f), hz_v3(0.0f, 1.4f, -3.0f)),
    };

    hz_hzb_source_t src;
    hz_memset(&src, 0, sizeof src);
    src.name = "builtin";
    src.vertex_count = b.nv, src.positions = b.pos, src.normals = b.nrm, src.uvs = b.uv;
    src.triangle_count = b.nt, src.triangles = b.tri, src.tri_info = b.info;
    src.material_count = MAT_COUNT, src.materials = mats;
    src.texture_count = TEX_COUNT, src.textures = b.textures;
    src.texel_count = b.ntexels, src.texels = b.texels;
    src.object_count = b.no, src.objects = b.objects;
    src.vertex_key_count = b.nvkeys, src.vertex_keys = b.vkeys, src.vertex_key_normals = b.vkey_nrm;
    src.light_count = 2, src.lights = lights;
    src.camera_key_count = 4, src.camera_keys = cams;
    src.duration = 8.0f;
    src.background[0] = 0.02f, src.background[1] = 0.03f, src.background[2] = 0.06f;
    src.ambient[0] = src.ambient[1] = src.ambient[2] = 0.03f;
    src.camera_fov_y = 60.0f * HZ_PI / 180.0f;
    src.camera_flags = 1u; /* the path loops */
    src.extra_features = HZ_FEAT_INSTANCING;

    size_t need = hz_hzb_write_size(&src);
    void *out = need ? hz_arena_alloc(image_arena, need, HZ_HZB_ALIGN) : NULL;
    hz_status_t s;
    if (!out) {
        s = hz_arena_error(image_arena, err);
        hz_error_prefix(err, "built-in scene");
    } else {
        s = hz_hzb_write(&src, out, need, size, err);
        if (s == HZ_OK)
            *image = out;
    }
    hz_arena_reset(scratch, mark);
    return s;
}
