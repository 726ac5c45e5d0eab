/* ĝ for the tdense resolve's end of cycle (tdense_internal.h): the decision of hz_tileorder_ghat, taken in
 * double precision where the result is certain and by the exact integer code (src/pattern/tileorder.c) where it
 * is not.
 *
 * Why: the exact code turns a CORDIC until the angle's remaining range decides, and takes an integer square
 * root: about a quarter of the whole resolve's time on a moving camera, all of it in the cycle's last frame (a
 * 640x360 frame has 57,600 tiles). The decision depends on two numbers: the angle α = atan2(|my|, |mx|) against
 * the random band's edges π/4 ± π/40, and u = frac(|m| ∓ α/π) against (1/4, 3/4). The exact code reads them as
 *   a = the CORDIC angle in units of 2^-30 quarter turns, rounded (within one unit of the true angle: its
 *       residual and table roundings are fractions of a unit),
 *   r = floor(|m| 2^16), h = a >> 15, u = (r ∓ h) mod 2^16 (units of 2^-16),
 * so the double-precision A (the angle in the same units, from a short series: within 3,900 units of a) and
 * U = |m| 2^16 ∓ A / 2^15 (within 3 units of r ∓ h: each floor loses less than one unit, the angle's error
 * a 2^15th of its own) fall on the same side of every edge where A is more than ANGLE_MARGIN units from the
 * random band's edges and U more than U_MARGIN units from 2^14 and 3 * 2^14 (mod 2^16): the same decision.
 * Elsewhere (about 4 in 10,000 ordinary motions) the exact code decides. The rules other than the full one
 * and the two shears, and motion along an axis, go to the exact code as they are (they need no angle). */
#include "hz/tileorder.h"
#include "tdense_internal.h"

#define ANGLE_MARGIN 16384.0 /* units of 2^-30 quarter turns (2.4e-5 rad): atan_small's error is under 3,900 */
#define U_MARGIN 8.0      /* units of 2^-16 px: the readings differ by less than 3 */

/* atan(s) for |s| <= tan(π/8) = 0.4143: the alternating series s - s^3/3 + ... + s^9/9, whose error is below
 * the first term left out, 0.4143^11 / 11 < 5.7e-6 rad (3,900 angle units: ANGLE_MARGIN is 4x that, and the
 * length's reading moves by a 2^15th of it, 0.12 units). Short, because it is on the critical path per tile. */
static double atan_small(double s)
{
    const double z = s * s;
    return s * (1.0 - z * (1.0 / 3.0 - z * (1.0 / 5.0 - z * (1.0 / 7.0 - z * (1.0 / 9.0)))));
}

/* α = atan2(ay, ax) in [0, π/2] for ax, ay > 0, in one division: near the axes from the smaller ratio, else
 * as π/4 + atan((ay - ax) / (ay + ax)); each argument within tan(π/8). */
static double angle_of(double ax, double ay)
{
    static const double tan_pi_8 = 0.41421356237309504880, pi_4 = 0.78539816339744830962;
    if (ay <= tan_pi_8 * ax)
        return atan_small(ay / ax);
    if (ax <= tan_pi_8 * ay)
        return 2.0 * pi_4 - atan_small(ax / ay);
    return pi_4 + atan_small((ay - ax) / (ay + ax));
}

/* Whether x lies within margin of the band edge e. */
static int near(double x, double e, double margin)
{
    return x > e - margin && x < e + margin;
}

int hz_tdense_ghat_certain(hz_q16_t mx, hz_q16_t my, hz_ghat_rule_t rule)
{
    if (rule != HZ_GHAT_FULL && rule != HZ_GHAT_SHEAR_UP && rule != HZ_GHAT_SHEAR_DOWN)
        return -1;
    if (mx == 0 || my == 0)
        return -1; /* the exact code's axis branch is cheap */
    /* |mx|, |my| as doubles: exact (at most 2^31) */
    const double ax = mx < 0 ? -(double)mx : (double)mx, ay = my < 0 ? -(double)my : (double)my;
    static const double units = 683565275.57643158978; /* 2^30 / (π / 2) */
    const double angle = angle_of(ax, ay);
    const double A = angle * units;
    const double lo = (double)(HZ_QANGLE_DIAG - HZ_QANGLE_GAMMA), hi = (double)(HZ_QANGLE_DIAG + HZ_QANGLE_GAMMA);
    int up;
    if (rule == HZ_GHAT_SHEAR_UP) {
        up = 1;
    } else if (rule == HZ_GHAT_SHEAR_DOWN) {
        up = 0;
    } else {
        if (near(A, lo, ANGLE_MARGIN) || near(A, hi, ANGLE_MARGIN))
            return -1;
        if (A > lo && A < hi)
            return HZ_TDENSE_GHAT_RANDOM;
        up = A <= lo;
    }
    /* |m| 2^16 = sqrt(ax^2 + ay^2) (Q16 inputs): the sum is exact in double below 2^53, and at most 2^63 here,
     * where its rounding is far below a unit of the root */
    const double len = __builtin_sqrt(ax * ax + ay * ay);
    const double h = A * (1.0 / 32768.0);
    /* U mod 2^16 in [0, 2^16): U + 2^17 is positive (h <= 2^15 + 1), so the truncation is the floor */
    const double U = (up ? len - h : len + h) + 131072.0;
    const double whole = (double)(int64_t)(U * (1.0 / 65536.0)) * 65536.0;
    const double p = U - whole;
    if (near(p, 16384.0, U_MARGIN) || near(p, 49152.0, U_MARGIN))
        return -1; /* (near 0 or 2^16 both readings are outside the band, whichever side of the wrap) */
    return p > 16384.0 && p < 49152.0 ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
}

hz_tilecycle_t hz_tdense_ghat(hz_q16_t mx, hz_q16_t my, uint32_t tx, uint32_t ty, uint32_t key, hz_ghat_rule_t rule)
{
    const int d = hz_tdense_ghat_certain(mx, my, rule);
    if (d == HZ_TDENSE_GHAT_RANDOM)
        return (hz_tileorder_tile_random_keyed(tx, ty, key) >> 31) ? HZ_TILECYCLE_HOURGLASS : HZ_TILECYCLE_BOWTIE;
    if (d >= 0)
        return (hz_tilecycle_t)d;
    return hz_tileorder_ghat(mx, my, hz_tileorder_tile_random_keyed(tx, ty, key), rule);
}
