/* vec3/mat4 helpers and libm-free scalar functions (see hz/vmath.h). */
#include "hz/vmath.h"

/* Round to nearest integer (ties to even) for |v| < 2^51 without libm: adding 1.5 * 2^52 pushes the fraction
 * out of the mantissa. Needs strict double evaluation, which SSE2 (x86-64) and AArch64 both give. */
static double round_nearest(double v)
{
    const double shifter = 6755399441055744.0;
    volatile double t = v + shifter; /* volatile: keep the compiler from folding (v + s) - s into v */
    return t - shifter;
}

/* sin and cos on |r| <= pi/4 by their Taylor series; the truncation error is below 1e-11. */
static double sin_poly(double r)
{
    double r2 = r * r;
    return r * (1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 +
                    r2 * (-1.0 / 39916800))))));
}

static double cos_poly(double r)
{
    double r2 = r * r;
    return 1.0 + r2 * (-1.0 / 2 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 +
                    r2 * (-1.0 / 3628800 + r2 * (1.0 / 479001600))))));
}

void hz_sincosf(float x, float *s, float *c)
{
    if (!hz_isfinitef(x)) {
        float nan = __builtin_nanf("");
        if (s) *s = nan;
        if (c) *c = nan;
        return;
    }
    /* Cody-Waite reduction with pi/2 split into a 33-bit head and a tail (fdlibm's pio2_1, pio2_1t):
     * k * head is exact for |k| < 2^20, i.e. |x| < 1.6e6. Beyond that k * head rounds and r can be far outside
     * [-pi/4, pi/4] (about |x| * 2^-53: thousands at 1e20), where the polynomials leave [-1, 1] and overflow
     * float; so r is reduced again until it is in range (one pass below ~1e15, at most four for any float). The
     * angle is meaningless there, but the result stays on the unit circle. */
    const double two_over_pi = 6.36619772367581382433e-01;
    const double pio2_head = 1.57079632673412561417e+00;
    const double pio2_tail = 6.07710050650619224932e-11;
    double r = x;
    long q = 0;
    for (int pass = 0; pass < 8; pass++) {
        double k = round_nearest(r * two_over_pi);
        r = (r - k * pio2_head) - k * pio2_tail;
        /* The quadrant k mod 4. From 2^62 up a cast to long would overflow; every double that large is a
         * multiple of 1024, so its quadrant is 0. */
        q += (k < 0 ? -k : k) < 4611686018427387904.0 ? (long)k & 3 : 0;
        if (r >= -0.786 && r <= 0.786)
            break;
    }
    q &= 3;
    double sr = sin_poly(r), cr = cos_poly(r);
    double sv, cv;
    switch (q) {
    case 0: sv = sr; cv = cr; break;
    case 1: sv = cr; cv = -sr; break;
    case 2: sv = -sr; cv = -cr; break;
    default: sv = -cr; cv = sr; break;
    }
    if (s) *s = (float)sv;
    if (c) *c = (float)cv;
}

float hz_sinf(float x)
{
    float s;
    hz_sincosf(x, &s, 0);
    return s;
}

float hz_cosf(float x)
{
    float c;
    hz_sincosf(x, 0, &c);
    return c;
}

float hz_tanf(float x)
{
    float s, c;
    hz_sincosf(x, &s, &c);
    return s / c;
}


hz_vec3_t hz_v3_normalize_rescaled(hz_vec3_t a)
{
    /* Very large vectors overflow l2, tiny ones underflow it: rescale by the largest component. */
    float m = hz_maxf(hz_absf(a.x), hz_maxf(hz_absf(a.y), hz_absf(a.z)));
    if (!(m > 0.0f))
        return hz_v3(0.0f, 0.0f, 0.0f);
    a = hz_v3(a.x / m, a.y / m, a.z / m); /* divide: 1 / m overflows for subnormal m */
    return hz_v3_scale(a, 1.0f / hz_sqrtf(hz_v3_dot(a, a)));
}

hz_mat4_t hz_mat4_identity(void)
{
    hz_mat4_t r = { { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 } };
    return r;
}

hz_mat4_t hz_mat4_mul(const hz_mat4_t *a, const hz_mat4_t *b)
{
    hz_mat4_t r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++)
                s += a->m[k * 4 + row] * b->m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

hz_mat4_t hz_mat4_transpose(const hz_mat4_t *a)
{
    hz_mat4_t r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++)
            r.m[c * 4 + row] = a->m[row * 4 + c];
    return r;
}

hz_mat4_t hz_mat4_translate(hz_vec3_t t)
{
    hz_mat4_t r = hz_mat4_identity();
    r.m[12] = t.x;
    r.m[13] = t.y;
    r.m[14] = t.z;
    return r;
}

hz_mat4_t hz_mat4_scale(hz_vec3_t s)
{
    hz_mat4_t r = hz_mat4_identity();
    r.m[0] = s.x;
    r.m[5] = s.y;
    r.m[10] = s.z;
    return r;
}

hz_mat4_t hz_mat4_rotate(hz_vec3_t axis, float radians)
{
    hz_vec3_t u = hz_v3_normalize(axis);
    hz_mat4_t r = hz_mat4_identity();
    if (u.x == 0.0f && u.y == 0.0f && u.z == 0.0f)
        return r;
    float s, c;
    hz_sincosf(radians, &s, &c);
    float t = 1.0f - c;
    /* Rodrigues' formula, written column by column. */
    r.m[0] = t * u.x * u.x + c;
    r.m[1] = t * u.x * u.y + s * u.z;
    r.m[2] = t * u.x * u.z - s * u.y;
    r.m[4] = t * u.x * u.y - s * u.z;
    r.m[5] = t * u.y * u.y + c;
    r.m[6] = t * u.y * u.z + s * u.x;
    r.m[8] = t * u.x * u.z + s * u.y;
    r.m[9] = t * u.y * u.z - s * u.x;
    r.m[10] = t * u.z * u.z + c;
    return r;
}

hz_mat4_t hz_mat4_look_at(hz_vec3_t eye, hz_vec3_t target, hz_vec3_t up)
{
    hz_vec3_t f = hz_v3_normalize(hz_v3_sub(target, eye));
    if (f.x == 0.0f && f.y == 0.0f && f.z == 0.0f)
        f = hz_v3(0.0f, 0.0f, -1.0f);
    hz_vec3_t r = hz_v3_normalize(hz_v3_cross(f, up));
    if (r.x == 0.0f && r.y == 0.0f && r.z == 0.0f) {
        /* up parallel to f: use the world axis least aligned with f. */
        float ax = hz_absf(f.x), ay = hz_absf(f.y), az = hz_absf(f.z);
        hz_vec3_t alt = ax <= ay && ax <= az ? hz_v3(1, 0, 0) : ay <= az ? hz_v3(0, 1, 0) : hz_v3(0, 0, 1);
        r = hz_v3_normalize(hz_v3_cross(f, alt));
    }
    hz_vec3_t u = hz_v3_cross(r, f);
    hz_mat4_t m = hz_mat4_identity();
    m.m[0] = r.x; m.m[1] = r.y; m.m[2] = r.z;
    m.m[4] = u.x; m.m[5] = u.y; m.m[6] = u.z;
    m.m[8] = -f.x; m.m[9] = -f.y; m.m[10] = -f.z;
    m.m[12] = eye.x; m.m[13] = eye.y; m.m[14] = eye.z;
    return m;
}

hz_mat4_t hz_mat4_perspective(float fov_y, float aspect, float z_near, float z_far)
{
    hz_mat4_t m = { { 0 } };
    float f = 1.0f / hz_tanf(0.5f * fov_y);
    m.m[0] = f / aspect;
    m.m[5] = f;
    m.m[10] = (z_far + z_near) / (z_near - z_far);
    m.m[11] = -1.0f;
    m.m[14] = 2.0f * z_far * z_near / (z_near - z_far);
    return m;
}

hz_status_t hz_mat4_inverse(const hz_mat4_t *a, hz_mat4_t *out)
{
    double m[16], inv[16];
    for (int i = 0; i < 16; i++) {
        if (!hz_isfinitef(a->m[i]))
            return HZ_E_RANGE;
        m[i] = a->m[i];
    }
    /* Cofactor expansion via 2x2 sub-determinants of the two column pairs. */
    double s0 = m[0] * m[5] - m[4] * m[1];
    double s1 = m[0] * m[6] - m[4] * m[2];
    double s2 = m[0] * m[7] - m[4] * m[3];
    double s3 = m[1] * m[6] - m[5] * m[2];
    double s4 = m[1] * m[7] - m[5] * m[3];
    double s5 = m[2] * m[7] - m[6] * m[3];
    double c5 = m[10] * m[15] - m[14] * m[11];
    double c4 = m[9] * m[15] - m[13] * m[11];
    double c3 = m[9] * m[14] - m[13] * m[10];
    double c2 = m[8] * m[15] - m[12] * m[11];
    double c1 = m[8] * m[14] - m[12] * m[10];
    double c0 = m[8] * m[13] - m[12] * m[9];
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    /* Singular relative to Hadamard's bound |det| <= product of column norms: scale-invariant per column, so a
     * scene scaled by 1e-6 is not called singular, while columns dependent to within float precision are. */
    double bound = 1.0;
    for (int col = 0; col < 4; col++) {
        const double *v = &m[col * 4];
        bound *= __builtin_sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
    }
    double adet = det < 0 ? -det : det;
    if (!(bound > 0.0) || !(adet > (double)FLT_EPSILON * bound))
        return HZ_E_RANGE;
    double id = 1.0 / det;
    inv[0] = (m[5] * c5 - m[6] * c4 + m[7] * c3) * id;
    inv[1] = (-m[1] * c5 + m[2] * c4 - m[3] * c3) * id;
    inv[2] = (m[13] * s5 - m[14] * s4 + m[15] * s3) * id;
    inv[3] = (-m[9] * s5 + m[10] * s4 - m[11] * s3) * id;
    inv[4] = (-m[4] * c5 + m[6] * c2 - m[7] * c1) * id;
    inv[5] = (m[0] * c5 - m[2] * c2 + m[3] * c1) * id;
    inv[6] = (-m[12] * s5 + m[14] * s2 - m[15] * s1) * id;
    inv[7] = (m[8] * s5 - m[10] * s2 + m[11] * s1) * id;
    inv[8] = (m[4] * c4 - m[5] * c2 + m[7] * c0) * id;
    inv[9] = (-m[0] * c4 + m[1] * c2 - m[3] * c0) * id;
    inv[10] = (m[12] * s4 - m[13] * s2 + m[15] * s0) * id;
    inv[11] = (-m[8] * s4 + m[9] * s2 - m[11] * s0) * id;
    inv[12] = (-m[4] * c3 + m[5] * c1 - m[6] * c0) * id;
    inv[13] = (m[0] * c3 - m[1] * c1 + m[2] * c0) * id;
    inv[14] = (-m[12] * s3 + m[13] * s1 - m[14] * s0) * id;
    inv[15] = (m[8] * s3 - m[9] * s1 + m[10] * s0) * id;
    for (int i = 0; i < 16; i++) {
        float f = (float)inv[i];
        if (!hz_isfinitef(f))
            return HZ_E_RANGE;
        out->m[i] = f;
    }
    return HZ_OK;
}

hz_vec3_t hz_mat4_mul_point(const hz_mat4_t *a, hz_vec3_t p)
{
    const float *m = a->m;
    return hz_v3(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
                 m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]);
}

hz_vec3_t hz_mat4_mul_dir(const hz_mat4_t *a, hz_vec3_t d)
{
    const float *m = a->m;
    return hz_v3(m[0] * d.x + m[4] * d.y + m[8] * d.z, m[1] * d.x + m[5] * d.y + m[9] * d.z,
                 m[2] * d.x + m[6] * d.y + m[10] * d.z);
}

float hz_mat4_mul_point_h(const hz_mat4_t *a, hz_vec3_t p, hz_vec3_t *out_ndc)
{
    const float *m = a->m;
    hz_vec3_t c = hz_mat4_mul_point(a, p);
    float w = m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15];
    if (out_ndc)
        *out_ndc = w != 0.0f ? hz_v3_scale(c, 1.0f / w) : c;
    return w;
}
