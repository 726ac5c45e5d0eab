/* Writes the dense smoke scene of seed 004's Emerald Square test into the unpacked Sponza folder: a cloud of
 * SMOKE_COUNT alpha-blended particle quads (soft round sprites, each its own object so that every particle picks
 * its own dither map) in the middle of the atrium, appended to a copy of sponza.obj. Host tool; `make scenes`
 * runs it and bakes the result with programs/hzbake/scenes/sponza-smoke.hzs (the light and the camera path through
 * the cloud).
 *
 *     smoke_scene SPONZA_DIR     reads sponza.obj and sponza.mtl there; writes sponza-smoke.obj,
 *                                sponza-smoke.mtl and smoke.tga (each via a temp file and rename)
 *     smoke_scene --column DIR   writes smoke-column.obj, smoke-column.mtl and smoke.tga into DIR: the same
 *                                particles as a dense rising column of COLUMN_COUNT over a ground plane (baked with
 *                                programs/hzbake/scenes/smoke-column.hzs: the camera circles it)
 *
 * The cloud is an ellipsoid centred at (0, 4.5, 0) with radii (10, 4, 4.2) (the atrium is about 30 x 15 x 11
 * units), particle centres uniform in it (about 13 per unit^3), quads 0.3 to 0.7 units wide with random
 * orientation, four grey materials of opacity 0.22 to 0.40 times the sprite's radial falloff: a ray along the
 * cloud crosses about 40 particles (visibility ~0.04 left), the sun's shadow rays about 15. Positions come from a
 * fixed xorshift sequence: the scene is the same on every machine. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GEN_PROG "smoke_scene"
#include "genio.h"

#define SMOKE_COUNT 12000
#define COLUMN_COUNT 6000
#define SPRITE 32

static uint32_t rng = 0x9e3779b9u;

static double uniform(void)
{
    rng ^= rng << 13, rng ^= rng >> 17, rng ^= rng << 5;
    return (double)(rng >> 8) / 16777216.0;
}

static void normalize(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int c = 0; c < 3; c++)
        v[c] /= l;
}

/* Uncompressed 32-bit TGA (stb_image reads it): white sprite, alpha (1 - r^2)^2 inside the unit circle. */
static void write_sprite(const char *path)
{
    char tmp[8192];
    FILE *f = gen_open_tmp(path, tmp, sizeof tmp);
    uint8_t h[18] = { 0 };
    h[2] = 2;
    h[12] = SPRITE, h[14] = SPRITE, h[16] = 32, h[17] = 8;
    fwrite(h, 1, sizeof h, f);
    for (int y = 0; y < SPRITE; y++)
        for (int x = 0; x < SPRITE; x++) {
            double dx = (x + 0.5) / SPRITE * 2.0 - 1.0, dy = (y + 0.5) / SPRITE * 2.0 - 1.0, r2 = dx * dx + dy * dy;
            double a = r2 < 1.0 ? (1.0 - r2) * (1.0 - r2) : 0.0;
            uint8_t px[4] = { 255, 255, 255, (uint8_t)lround(a * 255.0) };
            fwrite(px, 1, 4, f);
        }
    gen_finish(f, tmp, path);
}

static void copy_file(FILE *out, const char *path, long *v_count, long *vt_count, const char *mtllib)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        gen_fail("cannot open", path);
    char line[65536];
    while (fgets(line, sizeof line, in)) {
        if (v_count && !strncmp(line, "v ", 2))
            (*v_count)++;
        else if (vt_count && !strncmp(line, "vt ", 3))
            (*vt_count)++;
        if (mtllib && !strncmp(line, "mtllib ", 7))
            fprintf(out, "mtllib %s\n", mtllib);
        else
            fputs(line, out);
    }
    if (ferror(in))
        gen_fail("read error", path);
    fclose(in);
}

/* A random unit vector. */
static void random_dir(double n[3])
{
    double n2;
    do {
        for (int c = 0; c < 3; c++)
            n[c] = uniform() * 2.0 - 1.0;
        n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    } while (n2 > 1.0 || n2 < 1e-6);
    normalize(n);
}

/* One particle: a quad of half size 0.15 to 0.35 about c, randomly turned, its own group, one of the smoke materials.
 * *nv, *nvt: the OBJ's vertex and texture-coordinate counts so far. */
static void particle(FILE *o, int i, const double c[3], long *nv, long *nvt)
{
    double n[3];
    random_dir(n);
    /* Tangent frame: any vector not parallel to n. */
    double a[3] = { fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0 };
    double t[3] = { a[1] * n[2] - a[2] * n[1], a[2] * n[0] - a[0] * n[2], a[0] * n[1] - a[1] * n[0] };
    normalize(t);
    double b[3] = { n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0] };
    double half = 0.15 + 0.2 * uniform();
    int mat = (int)(uniform() * 4.0) & 3;
    fprintf(o, "g smoke_%05d\nusemtl smoke_%d\n", i, mat);
    static const double corner[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    for (int k = 0; k < 4; k++) {
        double u = corner[k][0] * half, v = corner[k][1] * half;
        fprintf(o, "v %.5f %.5f %.5f\n", c[0] + u * t[0] + v * b[0], c[1] + u * t[1] + v * b[1],
                c[2] + u * t[2] + v * b[2]);
    }
    for (int k = 0; k < 4; k++)
        fprintf(o, "vt %.1f %.1f\n", corner[k][0] * 0.5 + 0.5, corner[k][1] * 0.5 + 0.5);
    fprintf(o, "f %ld/%ld %ld/%ld %ld/%ld %ld/%ld\n", *nv + 1, *nvt + 1, *nv + 2, *nvt + 2, *nv + 3, *nvt + 3,
            *nv + 4, *nvt + 4);
    *nv += 4, *nvt += 4;
}

/* The four grey smoke materials (the sprite's alpha times the opacity). */
static void smoke_materials(FILE *m)
{
    static const double grey[4] = { 0.78, 0.72, 0.85, 0.66 }, opacity[4] = { 0.22, 0.28, 0.34, 0.40 };
    for (int k = 0; k < 4; k++)
        fprintf(m, "\nnewmtl smoke_%d\n\tKd %.2f %.2f %.2f\n\td %.2f\n\tillum 1\n\tmap_Kd smoke.tga\n", k, grey[k],
                grey[k], grey[k] * 0.97, opacity[k]);
}

/* The column: particle centres uniform in a cone frustum about the vertical axis from y = 0.2 (radius 0.7) to
 * y = 7.2 (radius 1.5), about 215 particles per unit^3, so that a ray through the middle crosses about 60; a 24 x 24
 * ground quad below it. */
static int write_column(const char *dir)
{
    char obj[4096], mtl[4096], tga[4096], tmp[8192];
    snprintf(obj, sizeof obj, "%s/smoke-column.obj", dir);
    snprintf(mtl, sizeof mtl, "%s/smoke-column.mtl", dir);
    snprintf(tga, sizeof tga, "%s/smoke.tga", dir);
    write_sprite(tga);
    FILE *m = gen_open_tmp(mtl, tmp, sizeof tmp);
    fprintf(m, "newmtl ground\n\tKd 0.55 0.50 0.44\n\tillum 1\n");
    smoke_materials(m);
    gen_finish(m, tmp, mtl);
    FILE *o = gen_open_tmp(obj, tmp, sizeof tmp);
    fprintf(o, "# smoke column: %d particles over a ground quad (tools/gen/smoke_scene.c --column)\nmtllib "
               "smoke-column.mtl\ng ground\nusemtl ground\nv -12 0 -12\nv -12 0 12\nv 12 0 12\nv 12 0 -12\n"
               "vt 0 0\nvt 0 1\nvt 1 1\nvt 1 0\nf 1/1 2/2 3/3 4/4\n",
            COLUMN_COUNT);
    long nv = 4, nvt = 4;
    for (int i = 0; i < COLUMN_COUNT; i++) {
        double y, x, z, r;
        do { /* uniform in the frustum: rejection from its bounding box */
            y = uniform();
            x = uniform() * 2.0 - 1.0, z = uniform() * 2.0 - 1.0;
            r = (0.7 + 0.8 * y) / 1.5;
        } while (x * x + z * z > r * r);
        const double c[3] = { x * 1.5, 0.2 + 7.0 * y, z * 1.5 };
        particle(o, i, c, &nv, &nvt);
    }
    gen_finish(o, tmp, obj);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "--column"))
        return write_column(argv[2]);
    if (argc != 2) {
        fprintf(stderr, "usage: smoke_scene SPONZA_DIR | smoke_scene --column DIR\n");
        return 2;
    }
    const char *dir = argv[1];
    char src_obj[4096], src_mtl[4096], obj[4096], mtl[4096], tga[4096], tmp[8192];
    snprintf(src_obj, sizeof src_obj, "%s/sponza.obj", dir);
    snprintf(src_mtl, sizeof src_mtl, "%s/sponza.mtl", dir);
    snprintf(obj, sizeof obj, "%s/sponza-smoke.obj", dir);
    snprintf(mtl, sizeof mtl, "%s/sponza-smoke.mtl", dir);
    snprintf(tga, sizeof tga, "%s/smoke.tga", dir);
    write_sprite(tga);

    FILE *m = gen_open_tmp(mtl, tmp, sizeof tmp);
    copy_file(m, src_mtl, NULL, NULL, NULL);
    smoke_materials(m);
    gen_finish(m, tmp, mtl);

    FILE *o = gen_open_tmp(obj, tmp, sizeof tmp);
    long nv = 0, nvt = 0;
    copy_file(o, src_obj, &nv, &nvt, "sponza-smoke.mtl");
    fprintf(o, "\n# smoke: %d particles (tools/gen/smoke_scene.c)\n", SMOKE_COUNT);
    for (int i = 0; i < SMOKE_COUNT; i++) {
        double p[3], r2;
        do {
            for (int c = 0; c < 3; c++)
                p[c] = uniform() * 2.0 - 1.0;
            r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        } while (r2 > 1.0 || r2 < 1e-9);
        const double c[3] = { p[0] * 10.0, 4.5 + p[1] * 4.0, p[2] * 4.2 };
        particle(o, i, c, &nv, &nvt);
    }
    gen_finish(o, tmp, obj);
    return 0;
}
