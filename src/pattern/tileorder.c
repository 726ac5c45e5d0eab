/* 2x2 tile orderings, their cycle classes and the ĝ(ℓf, α) choice (see hz/tileorder.h).
 * Integer-only: built with -mgeneral-regs-only and checked by check-integer on x86-64 and AArch64. */
#include "hz/tileorder.h"

#include <stdbool.h>

#include "hz/hash.h"

const int8_t hz_msaa4_jitter16[4][2] = { { -2, -6 }, { 6, -2 }, { -6, 2 }, { 2, 6 } };

/* The 24 permutations of {0,1,2,3} in lexicographic order, packed two bits per subframe (subframe s in bits
 * 2s..2s+1). Built by hand in order; test_tileorder checks the table against its own enumeration. */
#define PACK(a, b, c, d) (uint8_t)((a) | ((b) << 2) | ((c) << 4) | ((d) << 6))
const uint8_t hz_tileorder_packed[HZ_TILEORDER_COUNT] = {
    PACK(0, 1, 2, 3), PACK(0, 1, 3, 2), PACK(0, 2, 1, 3), PACK(0, 2, 3, 1), PACK(0, 3, 1, 2), PACK(0, 3, 2, 1),
    PACK(1, 0, 2, 3), PACK(1, 0, 3, 2), PACK(1, 2, 0, 3), PACK(1, 2, 3, 0), PACK(1, 3, 0, 2), PACK(1, 3, 2, 0),
    PACK(2, 0, 1, 3), PACK(2, 0, 3, 1), PACK(2, 1, 0, 3), PACK(2, 1, 3, 0), PACK(2, 3, 0, 1), PACK(2, 3, 1, 0),
    PACK(3, 0, 1, 2), PACK(3, 0, 2, 1), PACK(3, 1, 0, 2), PACK(3, 1, 2, 0), PACK(3, 2, 0, 1), PACK(3, 2, 1, 0),
};
#undef PACK

unsigned hz_tileorder_subframe(unsigned order, unsigned pixel)
{
    for (unsigned s = 0; s < 4; s++)
        if (hz_tileorder_pixel(order, s) == (pixel & 3u))
            return s;
    return 0; /* unreachable: every ordering is a permutation */
}

int hz_tileorder_index(const uint8_t seq[4])
{
    unsigned packed = 0, seen = 0;
    for (unsigned s = 0; s < 4; s++) {
        if (seq[s] > 3 || (seen & (1u << seq[s])))
            return -1;
        seen |= 1u << seq[s];
        packed |= (unsigned)seq[s] << (2u * s);
    }
    for (unsigned o = 0; o < HZ_TILEORDER_COUNT; o++)
        if (hz_tileorder_packed[o] == packed)
            return (int)o;
    return -1;
}

hz_tilecycle_t hz_tileorder_cycle(unsigned order)
{
    /* Classify the closed path by its steps: a step between pixels p and q is horizontal when p ^ q == 1
     * (same row), vertical when p ^ q == 2 (same column), diagonal when p ^ q == 3. A Hamiltonian cycle of the
     * 2x2 grid without a diagonal step is the square; one with diagonals has exactly two, plus two parallel
     * edges whose direction names the class. */
    unsigned horizontal = 0, diagonal = 0;
    for (unsigned s = 0; s < 4; s++) {
        unsigned step = hz_tileorder_pixel(order, s) ^ hz_tileorder_pixel(order, s + 1);
        horizontal += step == 1;
        diagonal += step == 3;
    }
    if (diagonal == 0)
        return HZ_TILECYCLE_SQUARE;
    return horizontal ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
}

unsigned hz_tileorder_of_cycle(hz_tilecycle_t cycle)
{
    switch (cycle) {
    case HZ_TILECYCLE_HOURGLASS:
        return HZ_TILEORDER_HOURGLASS;
    case HZ_TILECYCLE_BOWTIE:
        return HZ_TILEORDER_BOWTIE;
    case HZ_TILECYCLE_SQUARE:
    default:
        return HZ_TILEORDER_SQUARE;
    }
}

const char *hz_tilecycle_name(hz_tilecycle_t cycle)
{
    switch (cycle) {
    case HZ_TILECYCLE_HOURGLASS:
        return "hourglass";
    case HZ_TILECYCLE_BOWTIE:
        return "bowtie";
    case HZ_TILECYCLE_SQUARE:
    default:
        return "square";
    }
}

const char *hz_ghat_rule_name(hz_ghat_rule_t rule)
{
    static const char *const names[HZ_GHAT_RULE_COUNT] = { "full", "dominant", "shear-up", "shear-down",
                                                           "hourglass", "bowtie" };
    return (unsigned)rule < HZ_GHAT_RULE_COUNT ? names[rule] : NULL;
}

/* |v| as an unsigned value; exact for INT32_MIN (2^31). */
static uint32_t uabs32(int32_t v)
{
    return v < 0 ? 0u - (uint32_t)v : (uint32_t)v;
}

/* floor(v / 2^s) for signed v without relying on the implementation-defined shift of negative values, and
 * without a branch: for v < 0 it is ~(~v >> s) (int64_t is two's complement by definition). */
static int64_t floor_shift(int64_t v, unsigned s)
{
    const int64_t neg = -(int64_t)(v < 0);
    return (int64_t)((uint64_t)(v ^ neg) >> s) ^ neg;
}

/* round(atan(2^-i) / (π/2) * 2^38): CORDIC micro-rotation angles in 2^-8 HZ_QANGLE units (8 guard bits keep
 * the 34 rounded entries from adding up to more than a fraction of a unit). tools/gen/tileorder_golden.py
 * recomputes them from libm for the golden hash that test_tileorder checks. One list gives the table and its
 * sum (what all the steps together can turn). */
#define CORDIC_STEPS 34
#define CORDIC_GUARD 8
#define CORDIC_ATAN(X)                                                                                          \
    X(137438953472u) X(81134951838u) X(42869480287u) X(21761217566u) X(10922836750u) X(5466743129u)            \
    X(2734038620u) X(1367102738u) X(683561799u) X(341782203u) X(170891265u) X(85445653u) X(42722829u)         \
    X(21361415u) X(10680707u) X(5340354u) X(2670177u) X(1335088u) X(667544u) X(333772u) X(166886u) X(83443u)  \
    X(41722u) X(20861u) X(10430u) X(5215u) X(2608u) X(1304u) X(652u) X(326u) X(163u) X(81u) X(41u) X(20u)
#define CORDIC_ENTRY(v) v,
#define CORDIC_PLUS(v) +v
static const uint64_t cordic_atan[CORDIC_STEPS] = { CORDIC_ATAN(CORDIC_ENTRY) };
#define CORDIC_ATAN_TOTAL ((int64_t)(0 CORDIC_ATAN(CORDIC_PLUS)))

/* z (2^-8 units, CORDIC_GUARD) as the angle it rounds to, clamped to [0, π/2]. Non-decreasing in z. */
static hz_qangle_t angle_of_z(int64_t z)
{
    const int64_t right = (int64_t)HZ_QANGLE_RIGHT << CORDIC_GUARD;
    z = z < 0 ? 0 : z > right ? right : z;
    return (hz_qangle_t)((z + (1 << (CORDIC_GUARD - 1))) >> CORDIC_GUARD);
}

/* Vectoring CORDIC: rotate (x, y) onto the x axis by ±atan(2^-i), summing the rotations in z. */
typedef struct cordic {
    int64_t x, y, z;
} cordic_t;

/* ax, ay > 0. The larger input is scaled up to bit 60: the gain (about 1.65) keeps x below 2^62, and 34 steps
 * leave a residual below a tenth of a unit. */
static void cordic_start(cordic_t *c, uint32_t ax, uint32_t ay)
{
    uint32_t big = ax > ay ? ax : ay;
    unsigned shift = 60u - (31u - (unsigned)hz_clz32(big));
    c->x = (int64_t)((uint64_t)ax << shift);
    c->y = (int64_t)((uint64_t)ay << shift);
    c->z = 0;
}

static void cordic_step(cordic_t *c, unsigned i)
{
    /* the rotation's direction follows y's sign, which flips unpredictably: conditional negation by a mask
     * (-1 below zero: (v ^ -1) - (-1) = -v) instead of a branch */
    const int64_t neg = -(int64_t)(c->y < 0);
    const int64_t dx = floor_shift(c->y, i), dy = floor_shift(c->x, i);
    c->x += (dx ^ neg) - neg;
    c->y -= (dy ^ neg) - neg;
    c->z += ((int64_t)cordic_atan[i] ^ neg) - neg;
}

/* The CORDIC of hz_tileorder_angle for ax, ay > 0, ax != ay. */
static hz_qangle_t cordic_angle(uint32_t ax, uint32_t ay)
{
    cordic_t c;
    cordic_start(&c, ax, ay);
    for (unsigned i = 0; i < CORDIC_STEPS; i++)
        cordic_step(&c, i);
    return angle_of_z(c.z);
}

hz_qangle_t hz_tileorder_angle(hz_q16_t mx, hz_q16_t my)
{
    uint32_t ax = uabs32(mx), ay = uabs32(my);
    if (ay == 0)
        return 0;
    if (ax == 0)
        return HZ_QANGLE_RIGHT;
    if (ax == ay)
        return HZ_QANGLE_DIAG;
    return cordic_angle(ax, ay);
}

/* floor(sqrt(x)), exact: hz_isqrt_u64's digit-by-digit method, started at the highest non-zero base-4 digit
 * instead of at 2^62 (half the steps for the motions of a few pixels that matter here). */
static uint32_t isqrt_fast(uint64_t x)
{
    if (x == 0)
        return 0;
    uint64_t res = 0, bit = (uint64_t)1 << ((63u - (unsigned)__builtin_clzll(x)) & ~1u);
    while (bit) { /* each digit's test is a coin toss for the branch predictor: masks instead */
        const uint64_t t = res + bit, take = 0u - (uint64_t)(x >= t);
        x -= t & take;
        res = (res >> 1) + (bit & take);
        bit >>= 2;
    }
    return (uint32_t)res;
}

hz_q16_t hz_tileorder_length_frac(hz_q16_t mx, hz_q16_t my)
{
    /* |m|^2 in Q32.32: each square is at most 2^62, so the sum fits in 64 bits; its integer square root is
     * |m| in Q16.16 rounded down (up to 2^31.5, so only the fraction is returned). */
    uint64_t ax = uabs32(mx), ay = uabs32(my);
    if (ax == 0 || ay == 0) /* on an axis the length is exact without a root (and static tiles are common) */
        return (hz_q16_t)((ax | ay) & (uint32_t)(HZ_Q16_ONE - 1));
    uint32_t len = isqrt_fast(ax * ax + ay * ay);
    return (hz_q16_t)(len & (uint32_t)(HZ_Q16_ONE - 1));
}

#define Q_QUARTER (HZ_Q16_ONE / 4)
#define Q_THREE_QUARTERS (3 * HZ_Q16_ONE / 4)

/* Eq. 4: horizontal motion. */
static hz_tilecycle_t rule_horizontal(hz_q16_t lf)
{
    return lf > Q_QUARTER && lf < Q_THREE_QUARTERS ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
}

/* Eq. 5: vertical motion (the complement of Eq. 4). */
static hz_tilecycle_t rule_vertical(hz_q16_t lf)
{
    return lf > Q_QUARTER && lf < Q_THREE_QUARTERS ? HZ_TILECYCLE_BOWTIE : HZ_TILECYCLE_HOURGLASS;
}

/* The continuous transitions of Fig. 10 (middle): the hourglass band (0.25, 0.75) of Eq. 4 slides by
 * t/2 = α / π, up (up != 0) or down, reaching Eq. 5's band at α = π/2. */
static hz_tilecycle_t rule_shear(hz_q16_t lf, hz_qangle_t a, int up)
{
    uint32_t half_t = a >> 15; /* (α / 2^30) / 2 in Q16.16: at most 0.5 */
    uint32_t u = (up ? (uint32_t)lf - half_t : (uint32_t)lf + half_t) & (uint32_t)(HZ_Q16_ONE - 1);
    return u > (uint32_t)Q_QUARTER && u < (uint32_t)Q_THREE_QUARTERS ? HZ_TILECYCLE_HOURGLASS
                                                                    : HZ_TILECYCLE_BOWTIE;
}

hz_tilecycle_t hz_tileorder_ghat_polar(hz_q16_t lf, hz_qangle_t a, uint32_t rnd, hz_ghat_rule_t rule)
{
    switch (rule) {
    case HZ_GHAT_HOURGLASS:
        return HZ_TILECYCLE_HOURGLASS;
    case HZ_GHAT_BOWTIE:
        return HZ_TILECYCLE_BOWTIE;
    case HZ_GHAT_DOMINANT:
        return a <= HZ_QANGLE_DIAG ? rule_horizontal(lf) : rule_vertical(lf);
    case HZ_GHAT_SHEAR_UP:
        return rule_shear(lf, a, 1);
    case HZ_GHAT_SHEAR_DOWN:
        return rule_shear(lf, a, 0);
    case HZ_GHAT_FULL:
    default:
        if (a <= HZ_QANGLE_DIAG - HZ_QANGLE_GAMMA)
            return rule_shear(lf, a, 1);
        if (a >= HZ_QANGLE_DIAG + HZ_QANGLE_GAMMA)
            return rule_shear(lf, a, 0);
        return (rnd >> 31) ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
    }
}

/* Eq. 4's band test on a length fraction: (0.25, 0.75) exclusive. */
static bool in_band(uint32_t frac16)
{
    return frac16 > (uint32_t)Q_QUARTER && frac16 < (uint32_t)Q_THREE_QUARTERS;
}

/* in_band((floor(sqrt(x)) - shift) mod 1) in Q16.16, with isqrt_fast's digits, stopping once the digits left
 * cannot change the answer: after the digit of 4^m, res is q 4^m with q the root's digits found so far, so the
 * root lies in [q 2^m, q 2^m + 2^m - 1]; when that range is under a quarter wide and both ends give the same
 * answer, every root in it does (the band and its outside are each wider than the range). */
static bool len_in_band(uint64_t x, uint32_t shift)
{
    if (x == 0)
        return in_band((0u - shift) & (uint32_t)(HZ_Q16_ONE - 1));
    unsigned m = (63u - (unsigned)__builtin_clzll(x)) >> 1;
    uint64_t res = 0, bit = (uint64_t)1 << (2u * m);
    for (;;) { /* each digit's test is a coin toss for the branch predictor: masks instead */
        const uint64_t t = res + bit, take = 0u - (uint64_t)(x >= t);
        x -= t & take;
        res = (res >> 1) + (bit & take);
        if (m == 0)
            return in_band(((uint32_t)res - shift) & (uint32_t)(HZ_Q16_ONE - 1));
        if (m <= 13u) {
            const uint32_t lo = (uint32_t)(res >> m) - shift, hi = lo + ((1u << m) - 1u);
            const bool a = in_band(lo & (uint32_t)(HZ_Q16_ONE - 1));
            if (a == in_band(hi & (uint32_t)(HZ_Q16_ONE - 1)))
                return a;
        }
        bit >>= 2;
        m--;
    }
}

/* Where an angle puts the shear rules (hz_tileorder_ghat_polar): the up shear, the down shear, or ĝ's random
 * band. Non-decreasing in a. */
enum { SIDE_UP, SIDE_RANDOM, SIDE_DOWN };
static int ghat_side(hz_qangle_t a, hz_ghat_rule_t rule)
{
    if (rule == HZ_GHAT_SHEAR_UP)
        return SIDE_UP;
    if (rule == HZ_GHAT_SHEAR_DOWN)
        return SIDE_DOWN;
    return a <= HZ_QANGLE_DIAG - HZ_QANGLE_GAMMA ? SIDE_UP : a >= HZ_QANGLE_DIAG + HZ_QANGLE_GAMMA ? SIDE_DOWN
                                                                                            : SIDE_RANDOM;
}

/* ĝ's decision (a tile cycle) when every angle in [lo, hi] gets the same one at length root r (Q16.16: |m|
 * rounded down), else -1. All on one side: the shear reads u = (r - (a >> 15)) mod 1 (up) or r + (a >> 15)
 * (down), which over [lo, hi] runs through a range as wide as the shifts differ; under a quarter wide, it
 * cannot cross the band (half wide) or its outside, so its two ends decide. *r_known says whether r holds the
 * root of x yet (taken only when a decision needs it). */
static int ghat_range(uint64_t x, uint32_t *r, bool *r_known, hz_qangle_t lo, hz_qangle_t hi, uint32_t rnd,
                      hz_ghat_rule_t rule)
{
    const int side = ghat_side(lo, rule);
    if (side != ghat_side(hi, rule))
        return -1;
    if (side == SIDE_RANDOM)
        return (rnd >> 31) ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
    const uint32_t h_lo = lo >> 15, h_hi = hi >> 15;
    if (h_hi - h_lo >= (uint32_t)Q_QUARTER)
        return -1;
    if (!*r_known) {
        *r = isqrt_fast(x);
        *r_known = true;
    }
    const uint32_t ua = side == SIDE_UP ? *r - h_hi : *r + h_lo, ub = side == SIDE_UP ? *r - h_lo : *r + h_hi;
    const bool a = in_band(ua & (uint32_t)(HZ_Q16_ONE - 1));
    if (a != in_band(ub & (uint32_t)(HZ_Q16_ONE - 1)))
        return -1;
    return a ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
}

/* ĝ for off-axis motion (ax, ay > 0, ax != ay) under the full and shear rules: the CORDIC of hz_tileorder_angle,
 * stopped as soon as every angle its remaining steps can still reach (each step adds ±cordic_atan[i] to z, so
 * the steps after i move it by at most the sum of the entries after i) gets the same decision with the exact
 * length (ghat_range). So it decides as ĝ on the full angle does, in a few steps on typical motion; the
 * length's square root is taken only when a shear needs it. */
static hz_tilecycle_t ghat_off_axis(uint32_t ax, uint32_t ay, uint32_t rnd, hz_ghat_rule_t rule)
{
    enum { FIRST_CHECK = 2 }; /* before this the shifts' range is wider than a quarter anyway */
    const uint64_t x = (uint64_t)ax * ax + (uint64_t)ay * ay;
    uint32_t r = 0;
    bool r_known = false;
    cordic_t c;
    cordic_start(&c, ax, ay);
    int64_t rest = CORDIC_ATAN_TOTAL;
    for (unsigned i = 0; i + 1 < CORDIC_STEPS; i++) {
        cordic_step(&c, i);
        rest -= (int64_t)cordic_atan[i];
        if (i >= FIRST_CHECK) {
            const int d = ghat_range(x, &r, &r_known, angle_of_z(c.z - rest), angle_of_z(c.z + rest), rnd, rule);
            if (d >= 0)
                return (hz_tilecycle_t)d;
        }
    }
    /* the last step leaves nothing to turn: a single angle, which always decides */
    cordic_step(&c, CORDIC_STEPS - 1);
    const hz_qangle_t a = angle_of_z(c.z);
    return (hz_tilecycle_t)ghat_range(x, &r, &r_known, a, a, rnd, rule);
}

hz_tilecycle_t hz_tileorder_ghat(hz_q16_t mx, hz_q16_t my, uint32_t rnd, hz_ghat_rule_t rule)
{
    if (rule == HZ_GHAT_HOURGLASS)
        return HZ_TILECYCLE_HOURGLASS;
    if (rule == HZ_GHAT_BOWTIE)
        return HZ_TILECYCLE_BOWTIE;
    const uint32_t ax = uabs32(mx), ay = uabs32(my);
    if (my == 0)
        return rule_horizontal((hz_q16_t)(ax & (uint32_t)(HZ_Q16_ONE - 1))); /* on an axis |m| is exact */
    if (mx == 0)
        return rule_vertical((hz_q16_t)(ay & (uint32_t)(HZ_Q16_ONE - 1)));
    if (rule == HZ_GHAT_DOMINANT) { /* exact comparison rather than the rounded angle */
        const bool band = len_in_band((uint64_t)ax * ax + (uint64_t)ay * ay, 0u);
        return (ax >= ay) == band ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
    }
    return ghat_off_axis(ax, ay, rnd, rule);
}

uint32_t hz_tileorder_cycle_key(uint32_t cycle, uint32_t seed)
{
    return hz_hash2(cycle, seed);
}

uint32_t hz_tileorder_tile_random_keyed(uint32_t tx, uint32_t ty, uint32_t key)
{
    return hz_hash3(tx, ty, key);
}

uint32_t hz_tileorder_tile_random(uint32_t tx, uint32_t ty, uint32_t cycle, uint32_t seed)
{
    return hz_tileorder_tile_random_keyed(tx, ty, hz_tileorder_cycle_key(cycle, seed));
}

void hz_tileorder_choose(const hz_q16_t *motion, size_t tiles_x, size_t ty0, size_t ty1, uint32_t cycle,
                         uint32_t seed, hz_ghat_rule_t rule, uint8_t *orders)
{
    const uint32_t key = hz_tileorder_cycle_key(cycle, seed);
    for (size_t ty = ty0; ty < ty1; ty++) {
        for (size_t tx = 0; tx < tiles_x; tx++) {
            size_t i = ty * tiles_x + tx;
            uint32_t rnd = hz_tileorder_tile_random_keyed((uint32_t)tx, (uint32_t)ty, key);
            hz_tilecycle_t c = hz_tileorder_ghat(motion[2 * i], motion[2 * i + 1], rnd, rule);
            orders[i] = (uint8_t)hz_tileorder_of_cycle(c);
        }
    }
}
