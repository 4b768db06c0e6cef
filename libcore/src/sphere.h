/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sphere.h - small floating-point vector helpers for the spherical algorithms (only for
 * constructing output; decisions go through predicates.h). */
#ifndef MFG_SPHERE_H
#define MFG_SPHERE_H

#include <math.h>

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

#endif
