/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* vec3.h - plain floating-point 3-vector helpers and pi, one place for every family.
 * Plain double arithmetic in a fixed order, so a result has the same bits wherever it is
 * computed; they construct output and never decide a topology (predicates.h does). */
#ifndef MFG_VEC3_H
#define MFG_VEC3_H

#include <math.h>

#define MFG_PI 3.14159265358979323846264338327950288
#define MFG_TWO_PI (2.0 * MFG_PI)

/* o = a - b. */
static inline void mfg_sub3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

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

static inline double mfg_norm3(const double a[3])
{
    return sqrt(mfg_dot3(a, a));
}

static inline double mfg_dist3(const double a[3], const double b[3])
{
    double d[3];
    mfg_sub3(a, b, d);
    return mfg_norm3(d);
}

/* Squared distance from p to the box [lo, hi] (0 inside): the bounding-volume trees'
 * pruning bound (medial bvh, side trees, wall-thickness feet). */
static inline double mfg_box_dist2(const double lo[3], const double hi[3], const double p[3])
{
    double s = 0;
    for (int k = 0; k < 3; k++) {
        double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
        s += d * d;
    }
    return s;
}

/* Squared distance from x to the segment ab (to the point a when a == b): the medial
 * elements' distances, the thinning of seams and of sheet boundaries. */
static inline double mfg_seg_dist2(const double x[3], const double a[3], const double b[3])
{
    double ab[3], ax[3], r[3];
    mfg_sub3(b, a, ab);
    mfg_sub3(x, a, ax);
    double l2 = mfg_dot3(ab, ab), t = l2 > 0 ? mfg_dot3(ax, ab) / l2 : 0.0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    for (int k = 0; k < 3; k++)
        r[k] = ax[k] - t * ab[k];
    return mfg_dot3(r, r);
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

#endif
