/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sphere.h - small floating-point vector helpers for the spherical algorithms (only for
 * constructing output; decisions go through predicates.h).  The one place for each
 * helper that visibility.c and the maxisect_*.c files share. */
#ifndef MFG_SPHERE_H
#define MFG_SPHERE_H

#include <math.h>
#include <stdint.h>

#define MFG_PI 3.14159265358979323846

static inline double mfg_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void mfg_cross3(const double a[3], const double b[3], double out[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

/* out = -a (out may be a). */
static inline void mfg_neg3(const double a[3], double out[3])
{
    out[0] = -a[0];
    out[1] = -a[1];
    out[2] = -a[2];
}

/* out = a / |a|; returns 0 (out set to zero) when a is zero or not finite.  Scales first
 * so tiny or huge inputs do not underflow or overflow in the squares. */
static inline int mfg_unit3(const double a[3], double out[3])
{
    double s = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
    if (!(s > 0.0) || !isfinite(s)) {
        out[0] = out[1] = out[2] = 0.0;
        return 0;
    }
    double x = a[0] / s, y = a[1] / s, z = a[2] / s;
    double r = sqrt(x * x + y * y + z * z);
    out[0] = x / r;
    out[1] = y / r;
    out[2] = z / r;
    return 1;
}

/* Angle between unit vectors a and b in [0, pi]: atan2(|a x b|, a.b) stays accurate for
 * nearly equal and nearly opposite directions, where acos(a.b) loses half the digits. */
static inline double mfg_angle3(const double a[3], const double b[3])
{
    double c[3];
    mfg_cross3(a, b, c);
    return atan2(sqrt(mfg_dot3(c, c)), mfg_dot3(a, b));
}

/* Bearing of y about the axis c, measured counter-clockwise (seen from outside, looking
 * at c) from the half meridian through v, in [0, 2 pi).  c need not be unit. */
static inline double mfg_bearing3(const double c[3], const double v[3], const double y[3])
{
    double p[3], q[3], x[3];
    mfg_cross3(c, v, p);
    mfg_cross3(c, y, q);
    mfg_cross3(p, q, x);
    double t = atan2(mfg_dot3(x, c), mfg_dot3(p, q));
    return t < 0.0 ? t + 2 * MFG_PI : t;
}

/* A fixed stride coprime to m (m >= 1) visits every index of 0..m-1 exactly once, in a
 * scrambled order (i -> i + stride mod m): incremental hulls and Welzl's algorithm then
 * see extreme points early, as with a random permutation, with no memory.  The stride
 * starts near m / golden ratio and moves to the next odd number until gcd(stride, m) = 1
 * (a stride sharing a factor with m would visit only m / gcd of the indices). */
static inline int64_t mfg_scramble_stride(int64_t m)
{
    if (m <= 2)
        return 1;
    int64_t s = (int64_t)((double)m * 0.6180339887498949) | 1;
    for (;;) {
        int64_t x = s, y = m;
        while (y) {
            int64_t r = x % y;
            x = y;
            y = r;
        }
        if (x == 1)
            return s;
        s += 2;
        if (s >= m)
            return 1;
    }
}

/* Smallest cap containing the k >= 1 unit vectors pts (Welzl's algorithm on the sphere,
 * incremental form): centre c and cos(angular radius).  Meaningful for points inside
 * an open hemisphere.  The points are visited in the scrambled order of
 * mfg_scramble_stride, so points listed along a boundary still take linear time.  Each membership test has a slack of
 * MFG_CAP_SLACK in the cosine, so a few vectors may lie that much outside: callers that
 * need every point inside widen the radius by the largest mfg_angle3 afterwards. */
#define MFG_CAP_SLACK 1e-14
void mfg_enclosing_cap(const double *pts, int64_t k, double c[3], double *cosr);

#endif
