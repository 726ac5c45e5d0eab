/*
 * tools/gen/vac.h — void-and-cluster blue-noise mask (Ulichney, "The void-and-cluster method for dither array
 * generation", SPIE 1993), the generator behind hz_dither_blue64 (hz/dither.h). Header-only so that the
 * generator (tools/gen/dither_tables.c) and the test that regenerates the committed table
 * (test/unit/test_dither.c) run the same code.
 *
 * Contract: vac_generate(rank) fills rank[y * VAC_N + x] with a permutation of 0..VAC_N^2-1. Toroidal
 * Gaussian filter exp(-r^2 / (2 sigma^2)), sigma = VAC_SIGMA, quantised to integers (VAC_SCALE = 1) so that
 * energies are exact sums and every argmin/argmax (ties: lowest index) is the same on every machine. The initial
 * pattern is VAC_N^2 / 10 pixels drawn by a fixed xorshift32 sequence; phase 0 moves the tightest cluster into
 * the largest void until the two coincide; phase 1 ranks the prototype's ones by removing tightest clusters;
 * phases 2 and 3 insert into the largest void until the mask is full (the tightest cluster of zeros is the
 * largest void of ones, since a pixel's zero energy is the kernel total minus its one energy).
 */
#ifndef HZ_TOOLS_VAC_H
#define HZ_TOOLS_VAC_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#define VAC_N 64
#define VAC_PIX (VAC_N * VAC_N)
#define VAC_SIGMA 1.5
#define VAC_SCALE 65536.0

static uint32_t vac_kernel[VAC_PIX]; /* by (dy & 63) * 64 + (dx & 63) */

static void vac_build_kernel(void)
{
    for (int dy = 0; dy < VAC_N; dy++)
        for (int dx = 0; dx < VAC_N; dx++) {
            int ex = dx < VAC_N - dx ? dx : VAC_N - dx, ey = dy < VAC_N - dy ? dy : VAC_N - dy;
            double g = exp(-(double)(ex * ex + ey * ey) / (2.0 * VAC_SIGMA * VAC_SIGMA));
            vac_kernel[dy * VAC_N + dx] = (uint32_t)floor(g * VAC_SCALE + 0.5);
        }
}

static void vac_splat(uint32_t *energy, int p, int sign)
{
    int px = p % VAC_N, py = p / VAC_N;
    for (int y = 0; y < VAC_N; y++) {
        const uint32_t *k = &vac_kernel[((y - py) & (VAC_N - 1)) * VAC_N];
        uint32_t *e = &energy[y * VAC_N];
        for (int x = 0; x < VAC_N; x++) {
            uint32_t v = k[(x - px) & (VAC_N - 1)];
            e[x] = sign > 0 ? e[x] + v : e[x] - v;
        }
    }
}

/* Tightest cluster (want = 1: highest energy among ones) or largest void (want = 0: lowest among zeros). */
static int vac_find(const uint32_t *energy, const uint8_t *bits, int want)
{
    int best = -1;
    for (int p = 0; p < VAC_PIX; p++) {
        if (bits[p] != want)
            continue;
        if (best < 0 || (want ? energy[p] > energy[best] : energy[p] < energy[best]))
            best = p;
    }
    return best;
}

static void vac_generate(uint16_t *rank)
{
    static uint8_t proto[VAC_PIX], bits[VAC_PIX];
    static uint32_t eproto[VAC_PIX], energy[VAC_PIX];
    vac_build_kernel();
    memset(proto, 0, sizeof proto);
    memset(eproto, 0, sizeof eproto);
    uint32_t s = 0x2545f491u;
    int ones = 0;
    while (ones < VAC_PIX / 10) {
        s ^= s << 13, s ^= s >> 17, s ^= s << 5;
        int p = (int)(s % VAC_PIX);
        if (!proto[p]) {
            proto[p] = 1, ones++;
            vac_splat(eproto, p, 1);
        }
    }
    /* Phase 0: the prototype binary pattern. */
    for (int it = 0; it < 4 * VAC_PIX; it++) {
        int c = vac_find(eproto, proto, 1);
        proto[c] = 0;
        vac_splat(eproto, c, -1);
        int v = vac_find(eproto, proto, 0);
        proto[v] = 1;
        vac_splat(eproto, v, 1);
        if (v == c)
            break;
    }
    /* Phase 1: rank the prototype's ones, tightest cluster last removed = lowest rank. */
    memcpy(bits, proto, sizeof bits);
    memcpy(energy, eproto, sizeof energy);
    for (int r = ones - 1; r >= 0; r--) {
        int c = vac_find(energy, bits, 1);
        bits[c] = 0;
        vac_splat(energy, c, -1);
        rank[c] = (uint16_t)r;
    }
    /* Phases 2 and 3: fill the largest voids. */
    memcpy(bits, proto, sizeof bits);
    memcpy(energy, eproto, sizeof energy);
    for (int r = ones; r < VAC_PIX; r++) {
        int v = vac_find(energy, bits, 0);
        bits[v] = 1;
        vac_splat(energy, v, 1);
        rank[v] = (uint16_t)r;
    }
}

#endif
